//! The converged answer of a study: Richardson extrapolation over a
//! refinement sequence, with its uncertainty.
//!
//! A sequence refines every accuracy knob that converges (mesh size, time
//! step, punch speed) together by one ratio `r > 1` per level, coarse to
//! fine. For a quantity `f` on the last three levels `f₁` (coarse), `f₂`,
//! `f₃` (fine), the observed order is
//! `p = ln((f₁ − f₂) / (f₂ − f₃)) / ln r`, the extrapolated value
//! `f∞ = f₃ + (f₃ − f₂) / (r^p − 1)` and its uncertainty the fine-level
//! grid convergence index `GCI = F_s |f₃ − f₂| / (r^p − 1)` with the
//! safety factor `F_s = 1.25` (Roache, *Verification and Validation in
//! Computational Science and Engineering*, 1998; the procedure of Celik
//! et al., J. Fluids Eng. 130 (2008) 078001).
//!
//! The extrapolation holds only in the asymptotic range, where the error
//! falls as `h^p`. It is refused, and the finest level is taken with the
//! whole spread of the last three levels as its uncertainty (`F_s = 3`
//! on `|f₃ − f₁|`, Roache's factor for an unproven order), when the
//! differences change sign (oscillating convergence), when `p` lies
//! outside [`ORDER_RANGE`], or, with four levels or more, when the order of
//! the three coarser levels differs from the finer ones' by more than
//! [`ORDER_AGREEMENT`]. Each refusal says why.

use serde::Serialize;

/// The orders of convergence an extrapolation accepts: first order (an
/// explicit step's rate effects, a penalty) to fourth.
pub const ORDER_RANGE: (f64, f64) = (0.5, 4.0);

/// Largest relative difference between the orders of two consecutive
/// triples of levels for the sequence to count as asymptotic.
pub const ORDER_AGREEMENT: f64 = 0.25;

/// Safety factor of the grid convergence index with an observed order.
pub const SAFETY: f64 = 1.25;

/// Safety factor when the order is not proven (no extrapolation).
pub const SAFETY_UNPROVEN: f64 = 3.0;

/// The converged answer of one number.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Estimate {
    /// The estimate: extrapolated, or the finest level's value.
    pub value: f64,
    /// Its uncertainty (same unit, one-sided bound `F_s × …`).
    pub uncertainty: f64,
    /// The observed order `p` of the last three levels, when they converge
    /// monotonically.
    pub order: Option<f64>,
    /// Whether the extrapolation was made (the sequence is asymptotic).
    pub extrapolated: bool,
}

/// Why a sequence is not in its asymptotic range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NotAsymptotic {
    /// The last three levels' differences change sign.
    Oscillating,
    /// The observed order lies outside [`ORDER_RANGE`].
    Order(f64),
    /// The coarser triple's order differs from the finer one's.
    Disagree {
        /// Order of the three coarser levels.
        coarse: f64,
        /// Order of the three finest.
        fine: f64,
    },
    /// The last two levels are the same bits (nothing to extrapolate;
    /// the estimate is exact for this sequence).
    Converged,
}

impl std::fmt::Display for NotAsymptotic {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Oscillating => write!(f, "the levels oscillate"),
            Self::Order(p) => write!(
                f,
                "observed order {p:.2} is outside [{}, {}]",
                ORDER_RANGE.0, ORDER_RANGE.1
            ),
            Self::Disagree { coarse, fine } => write!(
                f,
                "observed orders {coarse:.2} (coarser levels) and {fine:.2} (finer) differ by more than {:.0} %",
                100.0 * ORDER_AGREEMENT
            ),
            Self::Converged => write!(f, "the two finest levels agree to the bit"),
        }
    }
}

/// The observed order of three levels `f₁, f₂, f₃` refined by `r`, when
/// they converge monotonically (the differences keep their sign and
/// neither is zero).
pub fn observed_order(f: [f64; 3], r: f64) -> Option<f64> {
    let (d21, d32) = (f[0] - f[1], f[1] - f[2]);
    (d21 * d32 > 0.0).then(|| (d21 / d32).ln() / r.ln())
}

/// The converged estimate of `levels` (coarse to fine, at least three)
/// refined by `r > 1`, and why it is not extrapolated when it is not.
pub fn extrapolate(levels: &[f64], r: f64) -> (Estimate, Option<NotAsymptotic>) {
    let n = levels.len();
    assert!(n >= 3 && r > 1.0, "three levels and r > 1");
    let f = [levels[n - 3], levels[n - 2], levels[n - 1]];
    let unproven = |order, why| {
        let spread = (f[2] - f[0]).abs().max((f[2] - f[1]).abs());
        let e = Estimate {
            value: f[2],
            uncertainty: SAFETY_UNPROVEN * spread,
            order,
            extrapolated: false,
        };
        (e, Some(why))
    };
    if f[1] == f[2] {
        return unproven(None, NotAsymptotic::Converged);
    }
    let Some(p) = observed_order(f, r) else {
        return unproven(None, NotAsymptotic::Oscillating);
    };
    if !(ORDER_RANGE.0..=ORDER_RANGE.1).contains(&p) {
        return unproven(Some(p), NotAsymptotic::Order(p));
    }
    if n >= 4 {
        let coarse = [levels[n - 4], levels[n - 3], levels[n - 2]];
        match observed_order(coarse, r) {
            Some(q) if ((q - p) / p).abs() <= ORDER_AGREEMENT => {}
            Some(q) => return unproven(Some(p), NotAsymptotic::Disagree { coarse: q, fine: p }),
            None => return unproven(Some(p), NotAsymptotic::Oscillating),
        }
    }
    let denominator = r.powf(p) - 1.0;
    let estimate = Estimate {
        value: f[2] + (f[2] - f[1]) / denominator,
        uncertainty: SAFETY * (f[2] - f[1]).abs() / denominator,
        order: Some(p),
        extrapolated: true,
    };
    (estimate, None)
}

/// The refinement ratio of one knob's numeric values `v₁, v₂, …` (coarse
/// to fine): the constant ratio between consecutive values, taken above 1
/// (a mesh's divisions grow, a time step shrinks). `None` when a value is
/// not a positive number or the ratio is not constant within 1e-6.
pub fn ratio_of(values: &[String]) -> Option<f64> {
    let v: Vec<f64> = values
        .iter()
        .map(|s| s.parse::<f64>().ok().filter(|x| x.is_finite() && *x > 0.0))
        .collect::<Option<_>>()?;
    let ratios: Vec<f64> = v
        .windows(2)
        .map(|w| (w[1] / w[0]).max(w[0] / w[1]))
        .collect();
    let r = *ratios.first()?;
    (r > 1.0 && ratios.iter().all(|q| (q / r - 1.0).abs() <= 1e-6)).then_some(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `f(h) = 2 + 0.3 h²` at `h = 4, 2, 1`: order 2 exactly, extrapolated
    /// to 2 within round-off; the uncertainty is 1.25 |f₃ − f₂| / 3.
    #[test]
    fn second_order_sequence_extrapolates_to_its_limit() {
        let f = |h: f64| 2.0 + 0.3 * h * h;
        let (e, why) = extrapolate(&[f(4.0), f(2.0), f(1.0)], 2.0);
        assert_eq!(why, None);
        assert!((e.order.unwrap() - 2.0).abs() < 1e-12, "{e:?}");
        assert!((e.value - 2.0).abs() < 1e-12, "{e:?}");
        assert!((e.uncertainty - 1.25 * 0.9 / 3.0).abs() < 1e-12, "{e:?}");
        assert!(e.extrapolated);
    }

    /// With a higher-order term the four-level check compares the two
    /// triples' orders: `2 + h² + 0.05 h³` at `h = 8, 4, 2, 1` keeps them
    /// within 25 %, and the estimate's error lies within its uncertainty.
    #[test]
    fn four_levels_check_the_order_and_bound_the_error() {
        let f = |h: f64| 2.0 + h * h + 0.05 * h.powi(3);
        let levels = [f(8.0), f(4.0), f(2.0), f(1.0)];
        let (e, why) = extrapolate(&levels, 2.0);
        assert_eq!(why, None, "{e:?}");
        assert!((e.value - 2.0).abs() <= e.uncertainty, "{e:?}");
    }

    #[test]
    fn oscillating_or_odd_orders_are_not_extrapolated() {
        let (e, why) = extrapolate(&[1.0, 1.2, 1.1], 2.0);
        assert_eq!(why, Some(NotAsymptotic::Oscillating));
        assert_eq!(e.value, 1.1);
        assert!((e.uncertainty - 3.0 * 0.1).abs() < 1e-12);
        let (_, why) = extrapolate(&[1.0, 1.5, 1.51], 2.0);
        assert!(matches!(why, Some(NotAsymptotic::Order(p)) if p > 4.0));
        let (_, why) = extrapolate(&[1.0, 2.0, 1.5, 1.25], 2.0);
        assert_eq!(why, Some(NotAsymptotic::Oscillating));
        let levels = [1.0, 1.5, 1.75, 1.8];
        let (_, why) = extrapolate(&levels, 2.0);
        assert!(
            matches!(why, Some(NotAsymptotic::Disagree { .. })),
            "{why:?}"
        );
        let (e, why) = extrapolate(&[1.0, 2.0, 2.0], 2.0);
        assert_eq!(why, Some(NotAsymptotic::Converged));
        assert_eq!(e.value, 2.0);
    }

    #[test]
    fn ratios_are_constant_and_above_one() {
        let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
        assert_eq!(ratio_of(&s(&["25", "50", "100"])), Some(2.0));
        assert_eq!(ratio_of(&s(&["1e-6", "5e-7", "2.5e-7"])), Some(2.0));
        assert_eq!(ratio_of(&s(&["25", "50", "75"])), None);
        assert_eq!(ratio_of(&s(&["25", "default"])), None);
        assert_eq!(ratio_of(&s(&["1", "1"])), None);
    }
}
