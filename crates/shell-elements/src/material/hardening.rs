//! Isotropic hardening curves: Swift's power law and a tabulated (piecewise linear) curve.

use crate::error::{ShellError, check};

/// Flow stress as a function of the equivalent plastic strain.
#[derive(Debug, Clone, PartialEq)]
pub enum Hardening {
    /// Swift: `σ_y = K (ε0 + ε_p)^n`.
    Swift {
        /// Strength coefficient K (MPa), > 0.
        k: f64,
        /// Pre-strain ε0 (-), > 0.
        eps0: f64,
        /// Hardening exponent n (-), in [0, 1); n = 0 is perfect plasticity at σ_y = K.
        n: f64,
    },
    /// Piecewise linear through `(ε_p, σ_y)` rows; the last segment's slope
    /// continues beyond the last row (constant if there is a single row).
    Table {
        /// Plastic strains (-), starting at 0, strictly increasing.
        eps_p: Vec<f64>,
        /// Flow stresses (MPa), > 0 and non-decreasing.
        sigma_y: Vec<f64>,
    },
}

impl Hardening {
    /// Swift's law, validated.
    pub fn swift(k: f64, eps0: f64, n: f64) -> Result<Self, ShellError> {
        let h = Hardening::Swift { k, eps0, n };
        h.validate()?;
        Ok(h)
    }

    /// A tabulated curve from `(ε_p, σ_y)` rows, validated.
    pub fn table(rows: &[(f64, f64)]) -> Result<Self, ShellError> {
        let h = Hardening::Table {
            eps_p: rows.iter().map(|r| r.0).collect(),
            sigma_y: rows.iter().map(|r| r.1).collect(),
        };
        h.validate()?;
        Ok(h)
    }

    /// Check the parameters; the error names the field, its value and unit.
    pub fn validate(&self) -> Result<(), ShellError> {
        match self {
            Hardening::Swift { k, eps0, n } => {
                check("swift.k", *k, "MPa", "> 0", *k > 0.0)?;
                check("swift.eps0", *eps0, "-", "> 0", *eps0 > 0.0)?;
                check("swift.n", *n, "-", "in [0, 1)", (0.0..1.0).contains(n))
            }
            Hardening::Table { eps_p, sigma_y } => {
                let bad = |row: usize, reason| ShellError::BadTable {
                    row,
                    reason,
                    eps_p: eps_p.get(row).copied().unwrap_or(f64::NAN),
                    sigma_y: sigma_y.get(row).copied().unwrap_or(f64::NAN),
                };
                if eps_p.is_empty() || eps_p.len() != sigma_y.len() {
                    return Err(bad(
                        0,
                        "the table needs at least one row of (eps_p, sigma_y)",
                    ));
                }
                if eps_p[0] != 0.0 {
                    return Err(bad(0, "the first row must be at eps_p = 0"));
                }
                for i in 0..eps_p.len() {
                    if !eps_p[i].is_finite() || !sigma_y[i].is_finite() || sigma_y[i] <= 0.0 {
                        return Err(bad(i, "values must be finite and sigma_y > 0"));
                    }
                    if i > 0 && eps_p[i] <= eps_p[i - 1] {
                        return Err(bad(i, "eps_p must increase strictly"));
                    }
                    if i > 0 && sigma_y[i] < sigma_y[i - 1] {
                        return Err(bad(
                            i,
                            "sigma_y must not decrease (softening is not supported)",
                        ));
                    }
                }
                Ok(())
            }
        }
    }

    /// Flow stress and hardening modulus at `eps_p + d`, given the flow stress
    /// `sy` at `eps_p` (the value a point caches). For Swift with
    /// `x = d/(ε0+ε_p) < 1e-3` it avoids `powf`:
    /// `σ_y(ε_p+d) = σ_y(ε_p) exp(n ln(1+x))` with both series to 4th order
    /// (relative error < 1e-12 per call, so no drift of practical size);
    /// otherwise it is [`Hardening::eval`].
    #[inline]
    pub fn eval_from(&self, eps_p: f64, sy: f64, d: f64) -> (f64, f64) {
        if let Hardening::Swift { eps0, n, .. } = self {
            let e = eps0 + eps_p;
            let x = d / e;
            if x.abs() < 1e-3 {
                let l = x * (1.0 - x * (0.5 - x * (1.0 / 3.0 - 0.25 * x)));
                let y = n * l;
                let f = 1.0 + y * (1.0 + y * (0.5 + y * (1.0 / 6.0 + y / 24.0)));
                let s = sy * f;
                return (s, n * s / (e + d));
            }
        }
        self.eval(eps_p + d)
    }

    /// Flow stress σ_y (MPa) and hardening modulus dσ_y/dε_p (MPa) at `eps_p`.
    #[inline]
    pub fn eval(&self, eps_p: f64) -> (f64, f64) {
        match self {
            Hardening::Swift { k, eps0, n } => {
                let e = eps0 + eps_p;
                let s = k * e.powf(*n);
                (s, n * s / e)
            }
            Hardening::Table {
                eps_p: xs,
                sigma_y: ys,
            } => {
                let m = xs.len();
                if m == 1 {
                    return (ys[0], 0.0);
                }
                // Segment i spans [xs[i], xs[i+1]]; the last one extends to infinity.
                let i = xs.partition_point(|&x| x <= eps_p).clamp(1, m - 1) - 1;
                let slope = (ys[i + 1] - ys[i]) / (xs[i + 1] - xs[i]);
                (ys[i] + slope * (eps_p - xs[i]), slope)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn swift_rejects_out_of_range_exponent_naming_the_field() {
        let e = Hardening::swift(565.32, 0.007117, 1.2).unwrap_err();
        assert!(e.to_string().contains("swift.n"), "{e}");
        assert!(Hardening::swift(-1.0, 0.01, 0.2).is_err());
        assert!(Hardening::swift(500.0, 0.0, 0.2).is_err());
    }

    #[test]
    fn table_interpolates_and_extrapolates_and_rejects_softening() {
        let h = Hardening::table(&[(0.0, 200.0), (0.1, 300.0), (0.2, 350.0)]).unwrap();
        let (s, hm) = h.eval(0.05);
        assert!((s - 250.0).abs() < 1e-12 && (hm - 1000.0).abs() < 1e-9);
        let (s, hm) = h.eval(0.3);
        assert!((s - 400.0).abs() < 1e-9 && (hm - 500.0).abs() < 1e-9);
        assert!(Hardening::table(&[(0.0, 200.0), (0.1, 150.0)]).is_err());
        assert!(Hardening::table(&[(0.0, 200.0), (0.0, 250.0)]).is_err());
        assert!(Hardening::table(&[]).is_err());
    }

    /// The powf-free series update agrees with the exact law to 1e-12 relative.
    #[test]
    fn swift_series_update_matches_exact_law() {
        let h = Hardening::swift(565.32, 0.007117, 0.2589).unwrap();
        for &(e, d) in &[(0.0, 7e-6), (0.05, 5e-5), (0.3, 3e-4), (0.01, 0.5)] {
            let sy = h.eval(e).0;
            let (a, ha) = h.eval_from(e, sy, d);
            let (b, hb) = h.eval(e + d);
            assert!(
                (a / b - 1.0).abs() < 1e-12 && (ha / hb - 1.0).abs() < 1e-12,
                "{e} {d}"
            );
        }
    }

    #[test]
    fn swift_slope_matches_finite_difference() {
        let h = Hardening::swift(565.32, 0.007117, 0.2589).unwrap();
        for &e in &[0.0, 0.01, 0.3] {
            let d = 1e-7;
            let fd = (h.eval(e + d).0 - h.eval(e - d.min(e + 0.007)).0) / (d + d.min(e + 0.007));
            assert!((fd - h.eval(e).1).abs() < 1e-4 * h.eval(e).1, "{e}");
        }
    }
}
