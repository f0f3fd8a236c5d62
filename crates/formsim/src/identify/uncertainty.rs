//! The uncertainty of identified values (docs/identification.md,
//! "Uncertainty"): the linearised covariance from the Jacobian at the
//! optimum, 95 % intervals, correlations, and warnings when the data do not
//! determine a value.
//!
//! With a standard error on every measured value the residuals are weighted
//! by them and their variance is known: `C = (JᵀJ)⁻¹`, intervals `± 1.96 σ`.
//! Without, every scaled error is taken to have one unknown variance,
//! estimated from the residuals: `s² = Σ r² / (N − n)`, `C = s² (JᵀJ)⁻¹`,
//! intervals `± t(0.975, N − n) σ` (Student). The covariance is taken from
//! the singular values of `J`, so a direction the data do not see shows as
//! an unbounded interval and a warning instead of a failed inverse.
//!
//! **Roughness.** An explicit forming run answers a change of 1e-6 of a
//! friction coefficient with a slightly different objective (contact
//! decisions flip): the objective is rough at a level `σ_f`, measured by
//! probe runs at the optimum moved by 1e-6 of each range. The optimum of a
//! rough objective is only known within `Δχ² ≈ 2 σ_f` (in units of the
//! residual variance), on top of the `Δχ² = 1` of the data: the covariance is
//! multiplied by `1 + 2 σ_f / s²` (reported as `inflation`).

use super::params::FitParam;
use nalgebra::DMatrix;
use serde::Serialize;
use statrs::distribution::{ContinuousCDF, Normal, StudentsT};

/// Correlation above which two values are reported as not separately identifiable.
pub const CORRELATION_LIMIT: f64 = 0.95;
/// A 95 % half-interval above this fraction of the value (or of its range,
/// for a value at zero) is reported as not identifiable.
pub const RELATIVE_HALF_WIDTH_LIMIT: f64 = 0.5;

/// A direction whose singular value is below this fraction of the largest is
/// reported as not seen by the data (whether or not an interval exists).
pub const WEAK_DIRECTION: f64 = 1e-2;

/// A value within this fraction of its range from a bound is reported as at the bound.
pub const AT_BOUND: f64 = 1e-3;

/// What the data say about the identified values.
#[derive(Debug, Clone, Serialize)]
pub struct Uncertainty {
    /// How the variance was obtained.
    pub basis: String,
    /// Measured values `N` and fitted values `n`.
    pub data_points: usize,
    /// The quantile the intervals use (1.96, or Student's for `N − n`).
    pub quantile: f64,
    /// The residual variance used (1 with standard errors given).
    pub variance_scale: f64,
    /// Standard deviation of the sum of squared residuals over the probe
    /// runs at the optimum (the objective's roughness), if measured.
    pub roughness_sd: Option<f64>,
    /// Factor on the covariance for the roughness: `1 + 2 σ_f / s²`.
    pub inflation: f64,
    /// Standard deviation of each value (`None`: the data do not bound it).
    pub sigma: Vec<Option<f64>>,
    /// 95 % interval of each value.
    pub interval95: Vec<Option<[f64; 2]>>,
    /// Correlation matrix (`None` where a σ is unbounded).
    pub correlation: Vec<Vec<Option<f64>>>,
    /// Singular values of the Jacobian with each column scaled by its
    /// value's range (how strongly the data see each direction).
    pub singular_values: Vec<f64>,
    /// Warnings: values the data do not determine.
    pub warnings: Vec<String>,
}

/// The uncertainty at `x` from the Jacobian `j` of the residuals `r`
/// (weighted by standard errors when `weighted`).
pub fn uncertainty(
    params: &[FitParam],
    x: &[f64],
    j: &DMatrix<f64>,
    r: &[f64],
    weighted: bool,
    roughness_sd: Option<f64>,
) -> Uncertainty {
    let (rows, n) = j.shape();
    let dof = rows.saturating_sub(n);
    let rss: f64 = r.iter().map(|v| v * v).sum();
    let (basis, scale2, quantile) = if weighted {
        let q = Normal::new(0.0, 1.0).map_or(1.959_963_984_540_054, |d| d.inverse_cdf(0.975));
        (
            "standard errors given: known variances, intervals ± 1.96 σ".to_string(),
            1.0,
            Some(q),
        )
    } else if dof > 0 {
        let q = StudentsT::new(0.0, 1.0, dof as f64)
            .ok()
            .map(|d| d.inverse_cdf(0.975));
        (
            format!(
                "no standard errors: one variance for every scaled error, estimated from the residuals (s² = {:.3e} over {dof} degrees of freedom), intervals ± t(0.975, {dof}) σ",
                rss / dof as f64
            ),
            rss / dof as f64,
            q,
        )
    } else {
        (
            format!(
                "no standard errors and no more measured values ({rows}) than fitted ones ({n}): no interval"
            ),
            f64::NAN,
            None,
        )
    };
    // Scale columns by the ranges so that the singular values compare directions.
    let widths: Vec<f64> = params.iter().map(FitParam::width).collect();
    let scaled = DMatrix::from_fn(rows, n, |i, k| j[(i, k)] * widths[k]);
    let svd = scaled.svd(false, true);
    let s = svd.singular_values.clone();
    let largest = s.iter().copied().fold(0.0, f64::max);
    let mut cov = DMatrix::<f64>::zeros(n, n);
    let mut unbounded = vec![false; n];
    if let Some(vt) = &svd.v_t {
        for (k, &sk) in s.iter().enumerate() {
            if sk <= 1e-10 * largest || sk == 0.0 {
                for (c, u) in unbounded.iter_mut().enumerate() {
                    *u |= vt[(k, c)].abs() > 1e-6;
                }
                continue;
            }
            for a in 0..n {
                for b in 0..n {
                    cov[(a, b)] += vt[(k, a)] * vt[(k, b)] / (sk * sk) * widths[a] * widths[b];
                }
            }
        }
    }
    let inflation = match roughness_sd {
        Some(sd) if scale2 > 0.0 && scale2.is_finite() => 1.0 + 2.0 * sd / scale2,
        _ => 1.0,
    };
    let ok = |a: usize| !unbounded[a] && scale2.is_finite() && quantile.is_some();
    let sigma: Vec<Option<f64>> = (0..n)
        .map(|a| ok(a).then(|| (inflation * scale2 * cov[(a, a)]).sqrt()))
        .collect();
    let q = quantile.unwrap_or(f64::NAN);
    let interval95 = (0..n)
        .map(|a| sigma[a].map(|sd| [x[a] - q * sd, x[a] + q * sd]))
        .collect();
    let correlation = (0..n)
        .map(|a| {
            (0..n)
                .map(|b| {
                    (ok(a) && ok(b) && cov[(a, a)] > 0.0 && cov[(b, b)] > 0.0)
                        .then(|| cov[(a, b)] / (cov[(a, a)] * cov[(b, b)]).sqrt())
                })
                .collect()
        })
        .collect();
    let mut u = Uncertainty {
        basis,
        data_points: rows,
        quantile: q,
        variance_scale: scale2,
        roughness_sd,
        inflation,
        sigma,
        interval95,
        correlation,
        singular_values: s.iter().copied().collect(),
        warnings: Vec::new(),
    };
    u.warnings = warnings(params, x, &u, &unbounded);
    u
}

fn warnings(params: &[FitParam], x: &[f64], u: &Uncertainty, unbounded: &[bool]) -> Vec<String> {
    let mut out = Vec::new();
    for (a, p) in params.iter().enumerate() {
        let u_a = p.to_unit(x[a]);
        if !(AT_BOUND..=1.0 - AT_BOUND).contains(&u_a) {
            out.push(format!(
                "{} ended at its bound {}: the data want a value outside [{}, {}], and the interval (linearised there) says little",
                p.key,
                if u_a < 0.5 { p.lo } else { p.hi },
                p.lo,
                p.hi
            ));
        }
        if unbounded[a] {
            out.push(format!(
                "{} is not identifiable from these data: the measured values do not change along a direction that moves it",
                p.key
            ));
            continue;
        }
        if let Some(sd) = u.sigma[a] {
            let reference = if x[a] != 0.0 { x[a].abs() } else { p.width() };
            if u.quantile * sd > RELATIVE_HALF_WIDTH_LIMIT * reference {
                out.push(format!(
                    "{} is poorly identified: its 95 % interval is ± {:.3e}, more than {:.0} % of {}",
                    p.key,
                    u.quantile * sd,
                    100.0 * RELATIVE_HALF_WIDTH_LIMIT,
                    if x[a] != 0.0 { "its value" } else { "its range" }
                ));
            }
        }
    }
    let largest = u.singular_values.iter().copied().fold(0.0, f64::max);
    let weak = u
        .singular_values
        .iter()
        .filter(|s| **s < WEAK_DIRECTION * largest)
        .count();
    if weak > 0 {
        out.push(format!(
            "the data see only {} of the {} directions in which the values can move: {weak} singular value(s) of the range-scaled Jacobian are below {} of the largest ({})",
            params.len() - weak,
            params.len(),
            WEAK_DIRECTION,
            u.singular_values
                .iter()
                .map(|s| format!("{s:.3e}"))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    for a in 0..params.len() {
        for b in a + 1..params.len() {
            if let Some(rho) = u.correlation[a][b]
                && rho.abs() > CORRELATION_LIMIT
            {
                out.push(format!(
                    "{} and {} are strongly correlated (ρ = {rho:.3}): the data determine a combination of them, not each",
                    params[a].key, params[b].key
                ));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(key: &str) -> FitParam {
        FitParam {
            key: key.into(),
            lo: -10.0,
            hi: 10.0,
            start: None,
        }
    }

    /// Linear regression y = a + b t with known σ = 0.5: the textbook
    /// covariance σ² (XᵀX)⁻¹ (any statistics text, ordinary least squares).
    #[test]
    fn linear_regression_covariance_is_the_textbook_one() {
        let t = [0.0, 1.0, 2.0, 3.0];
        let se = 0.5;
        let j = DMatrix::from_fn(4, 2, |i, k| if k == 0 { 1.0 / se } else { t[i] / se });
        let u = uncertainty(&[p("a"), p("b")], &[5.0, 8.0], &j, &[0.0; 4], true, None);
        // XᵀX = [[4, 6], [6, 14]], det 20: var a = 0.25·14/20, var b = 0.25·4/20.
        assert!((u.sigma[0].unwrap() - (0.25 * 14.0 / 20.0f64).sqrt()).abs() < 1e-12);
        assert!((u.sigma[1].unwrap() - (0.25 * 4.0 / 20.0f64).sqrt()).abs() < 1e-12);
        let rho = -6.0 / (14.0f64 * 4.0).sqrt();
        assert!((u.correlation[0][1].unwrap() - rho).abs() < 1e-12);
        assert!((u.quantile - 1.959_964).abs() < 1e-6);
        assert!(u.warnings.is_empty(), "{:?}", u.warnings);
    }

    #[test]
    fn unknown_variance_uses_student_t_and_the_residuals() {
        let j = DMatrix::from_element(3, 1, 1.0);
        let r = [0.1, -0.1, 0.2];
        let u = uncertainty(&[p("a")], &[5.0], &j, &r, false, None);
        let s2: f64 = (0.01 + 0.01 + 0.04) / 2.0;
        assert!((u.sigma[0].unwrap() - (s2 / 3.0).sqrt()).abs() < 1e-12);
        // t(0.975, 2) = 4.302653 (tables).
        assert!((u.quantile - 4.302_653).abs() < 1e-5);
    }

    #[test]
    fn roughness_inflates_the_covariance() {
        let j = DMatrix::from_element(4, 1, 2.0);
        let smooth = uncertainty(&[p("a")], &[1.0], &j, &[0.0; 4], true, None);
        let rough = uncertainty(&[p("a")], &[1.0], &j, &[0.0; 4], true, Some(0.5));
        assert_eq!(rough.inflation, 2.0);
        assert!((rough.sigma[0].unwrap() / smooth.sigma[0].unwrap() - 2f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn collinear_columns_are_reported_not_inverted() {
        let j = DMatrix::from_fn(3, 2, |i, _| 1.0 + i as f64);
        let u = uncertainty(&[p("a"), p("b")], &[1.0, 1.0], &j, &[0.0; 3], true, None);
        assert!(u.sigma.iter().all(Option::is_none));
        assert_eq!(u.warnings.len(), 3, "{:?}", u.warnings);
        assert!(u.warnings[2].contains("only 1 of the 2 directions"));
        assert!(u.warnings[0].contains("not identifiable"));
    }

    #[test]
    fn strong_correlation_is_warned() {
        let j = DMatrix::from_row_slice(3, 2, &[1.0, 1.0, 1.0, 1.01, 1.0, 0.99]);
        let u = uncertainty(
            &[p("a"), p("b")],
            &[100.0, 100.0],
            &j,
            &[0.0; 3],
            true,
            None,
        );
        assert!(
            u.warnings.iter().any(|w| w.contains("strongly correlated")),
            "{:?}",
            u.warnings
        );
    }
}
