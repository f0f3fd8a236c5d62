//! Time amplitudes that scale prescribed motions and loads: constant, linear ramp, C² smooth step, table.

use crate::FemError;

/// A dimensionless time function `A(t)` that multiplies a load or a prescribed motion.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Amplitude {
    /// `A(t) = 1`.
    #[default]
    Constant,
    /// 0 before `t0`, linear from 0 at `t0` to 1 at `t1`, 1 after.
    Linear {
        /// Start time (s).
        t0: f64,
        /// End time (s), `> t0`.
        t1: f64,
    },
    /// 0 before `t0`, `6ξ⁵ − 15ξ⁴ + 10ξ³` with `ξ = (t − t0)/(t1 − t0)`, 1
    /// after `t1`: C² (zero velocity and acceleration at both ends).
    SmoothStep {
        /// Start time (s).
        t0: f64,
        /// End time (s), `> t0`.
        t1: f64,
    },
    /// 0 before `t0`, `21ξ⁵ − 35ξ⁶ + 15ξ⁷` with `ξ = (t − t0)/(t1 − t0)`, 1
    /// after `t1`: the integral of the speed profile `∝ ξ⁴(1 − ξ)²`. It starts
    /// more gently than the smooth step (speed `∝ ξ⁴`, not `ξ²`) and peaks
    /// later (at ξ = 2/3), so that a punch is slow while the blank's internal
    /// energy is still small; at rest with zero acceleration at both ends.
    SlowStart {
        /// Start time (s).
        t0: f64,
        /// End time (s), `> t0`.
        t1: f64,
    },
    /// Piecewise linear through `(t, A)` points with strictly increasing `t`;
    /// held constant outside the table.
    Table(Vec<(f64, f64)>),
}

impl Amplitude {
    /// Check the parameters (finite times, `t1 > t0`, a non-empty strictly increasing table).
    pub fn validate(&self) -> Result<(), FemError> {
        let bad = |field: &str, value: f64, range: &'static str| FemError::InvalidParameter {
            field: field.to_string(),
            value,
            unit: "s",
            range,
        };
        match self {
            Amplitude::Constant => Ok(()),
            Amplitude::Linear { t0, t1 }
            | Amplitude::SmoothStep { t0, t1 }
            | Amplitude::SlowStart { t0, t1 } => {
                if !t0.is_finite() {
                    return Err(bad("amplitude.t0", *t0, "finite"));
                }
                if !(t1.is_finite() && t1 > t0) {
                    return Err(bad("amplitude.t1", *t1, "finite and > t0"));
                }
                Ok(())
            }
            Amplitude::Table(points) => {
                if points.is_empty() {
                    return Err(FemError::InvalidSetup(
                        "amplitude table is empty: give at least one (t, A) point".into(),
                    ));
                }
                for (k, &(t, a)) in points.iter().enumerate() {
                    if !t.is_finite() {
                        return Err(bad(&format!("amplitude.table[{k}].t"), t, "finite"));
                    }
                    if !a.is_finite() {
                        return Err(FemError::InvalidParameter {
                            field: format!("amplitude.table[{k}].A"),
                            value: a,
                            unit: "-",
                            range: "finite",
                        });
                    }
                    if k > 0 && t <= points[k - 1].0 {
                        return Err(bad(
                            &format!("amplitude.table[{k}].t"),
                            t,
                            "strictly greater than the previous time",
                        ));
                    }
                }
                Ok(())
            }
        }
    }

    /// `A(t)`.
    pub fn value(&self, t: f64) -> f64 {
        match self {
            Amplitude::Constant => 1.0,
            Amplitude::Linear { t0, t1 } => ((t - t0) / (t1 - t0)).clamp(0.0, 1.0),
            Amplitude::SmoothStep { t0, t1 } => {
                let s = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
                s * s * s * (s * (6.0 * s - 15.0) + 10.0)
            }
            Amplitude::SlowStart { t0, t1 } => {
                let s = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
                let s5 = s * s * s * s * s;
                s5 * (21.0 + s * (-35.0 + 15.0 * s))
            }
            Amplitude::Table(p) => table_value(p, t),
        }
    }

    /// `dA/dt` (1/s); for a table, the slope of the segment holding `t`.
    pub fn rate(&self, t: f64) -> f64 {
        match self {
            Amplitude::Constant => 0.0,
            Amplitude::Linear { t0, t1 } => {
                if t >= *t0 && t <= *t1 {
                    1.0 / (t1 - t0)
                } else {
                    0.0
                }
            }
            Amplitude::SmoothStep { t0, t1 } => {
                let s = (t - t0) / (t1 - t0);
                if !(0.0..=1.0).contains(&s) {
                    return 0.0;
                }
                30.0 * s * s * (s - 1.0) * (s - 1.0) / (t1 - t0)
            }
            Amplitude::SlowStart { t0, t1 } => {
                let s = (t - t0) / (t1 - t0);
                if !(0.0..=1.0).contains(&s) {
                    return 0.0;
                }
                105.0 * s * s * s * s * (1.0 - s) * (1.0 - s) / (t1 - t0)
            }
            Amplitude::Table(p) => {
                if p.len() < 2 || t < p[0].0 || t >= p[p.len() - 1].0 {
                    return 0.0;
                }
                let k = p.partition_point(|q| q.0 <= t);
                let (a, b) = (p[k - 1], p[k]);
                (b.1 - a.1) / (b.0 - a.0)
            }
        }
    }
}

/// The piecewise-linear function through `points` (strictly increasing
/// abscissae) at `x`, held constant beyond the ends; 0 for no points, NaN
/// for a NaN `x`. Amplitude tables and force curves
/// ([`crate::ForceLaw::Compression`]) both read it.
pub(crate) fn table_value(points: &[(f64, f64)], x: f64) -> f64 {
    let Some(first) = points.first() else {
        return 0.0;
    };
    if x.is_nan() {
        return f64::NAN;
    }
    if x <= first.0 {
        return first.1;
    }
    let last = points[points.len() - 1];
    if x >= last.0 {
        return last.1;
    }
    // First point with abscissa > x (exists, since x < last.0).
    let k = points.partition_point(|q| q.0 <= x);
    let (a, b) = (points[k - 1], points[k]);
    a.1 + (b.1 - a.1) * (x - a.0) / (b.0 - a.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slow_start_goes_from_0_to_1_and_its_rate_is_its_derivative() {
        // A(ξ) = 21ξ⁵ − 35ξ⁶ + 15ξ⁷ is the normalised integral of ξ⁴(1 − ξ)²
        // (∫₀¹ ξ⁴(1 − ξ)² dξ = 1/105): A(0) = 0, A(1) = 1, A' = 105 ξ⁴(1 − ξ)².
        let a = Amplitude::SlowStart { t0: 1.0, t1: 3.0 };
        assert_eq!(a.value(0.5), 0.0);
        assert!((a.value(3.0) - 1.0).abs() < 1e-15);
        assert_eq!(a.value(4.0), 1.0);
        for k in 1..20 {
            let t = 1.0 + 0.1 * k as f64;
            let h = 1e-6;
            let fd = (a.value(t + h) - a.value(t - h)) / (2.0 * h);
            assert!(
                (fd - a.rate(t)).abs() < 1e-8,
                "t = {t}: {fd} vs {}",
                a.rate(t)
            );
        }
        // Slower than the smooth step early on.
        let s = Amplitude::SmoothStep { t0: 1.0, t1: 3.0 };
        assert!(a.value(1.4) < 0.5 * s.value(1.4));
    }
}
