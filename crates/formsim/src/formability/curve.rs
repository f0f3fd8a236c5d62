//! Forming limit curves: the largest major strain a sheet takes at each
//! minor strain before it necks, either Keeler–Brazier's curve from the
//! sheet's hardening exponent and thickness or a table the user measured.

use serde::{Deserialize, Serialize};

/// The strain measure a curve is defined in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Measure {
    /// Engineering strain `e = ΔL / L0` (what circle-grid analysis reads).
    Engineering,
    /// True (logarithmic) strain `ε = ln(L / L0)`.
    True,
}

impl Measure {
    /// The name as written in a scene.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Engineering => "engineering",
            Self::True => "true",
        }
    }

    /// A true strain in this measure.
    pub fn from_true(self, eps: f64) -> f64 {
        match self {
            Self::Engineering => eps.exp_m1(),
            Self::True => eps,
        }
    }
}

/// Keeler–Brazier's hardening exponent cap: the correlation was fitted to
/// steels up to `n = 0.21`, and a larger `n` counts as 0.21.
pub const KEELER_BRAZIER_N_MAX: f64 = 0.21;

/// Slope of Keeler–Brazier's right-hand branch in engineering strain.
pub const KEELER_BRAZIER_RIGHT_SLOPE: f64 = 0.6;

/// A forming limit curve `major = FLC(minor)` in its own measure.
#[derive(Debug, Clone, PartialEq)]
pub enum FormingLimitCurve {
    /// Keeler–Brazier: the plane-strain limit `FLD0` (engineering, as a
    /// fraction), the left branch at constant true thickness strain through
    /// it, the right branch rising with slope 0.6 in engineering strain.
    KeelerBrazier {
        /// Plane-strain limit, engineering major strain (-).
        fld0: f64,
        /// The hardening exponent the formula used (capped, -).
        n: f64,
        /// Sheet thickness (mm).
        thickness: f64,
    },
    /// A measured curve, piecewise linear between its points, constant
    /// beyond its first and last minor strain.
    Table {
        /// `(minor, major)`, minor strictly increasing.
        points: Vec<(f64, f64)>,
        /// The measure its strains are in.
        measure: Measure,
    },
}

impl FormingLimitCurve {
    /// Keeler–Brazier's curve of a sheet `thickness` mm thick with hardening
    /// exponent `n`: `FLD0 (%) = (23.3 + 14.13 t) · min(n, 0.21) / 0.21`.
    ///
    /// # Errors
    /// A thickness or exponent that is not finite and positive.
    pub fn keeler_brazier(thickness: f64, n: f64) -> Result<Self, String> {
        if !(thickness.is_finite() && thickness > 0.0) {
            return Err(format!("thickness {thickness} mm: must be finite and > 0"));
        }
        if !(n.is_finite() && n > 0.0) {
            return Err(format!(
                "hardening exponent n = {n}: must be finite and > 0"
            ));
        }
        let n = n.min(KEELER_BRAZIER_N_MAX);
        let fld0_percent = (23.3 + 14.13 * thickness) * n / KEELER_BRAZIER_N_MAX;
        Ok(Self::KeelerBrazier {
            fld0: fld0_percent / 100.0,
            n,
            thickness,
        })
    }

    /// A measured curve through `points` `(minor, major)` in `measure`.
    ///
    /// # Errors
    /// Fewer than two points, a value that is not finite, minor strains not
    /// strictly increasing, or a major strain not above zero.
    pub fn table(points: Vec<(f64, f64)>, measure: Measure) -> Result<Self, String> {
        if points.len() < 2 {
            return Err(format!(
                "{} point(s): a curve needs at least 2 (minor, major) rows",
                points.len()
            ));
        }
        for (i, &(minor, major)) in points.iter().enumerate() {
            if !(minor.is_finite() && major.is_finite()) {
                return Err(format!("row {}: ({minor}, {major}) is not finite", i + 1));
            }
            if major <= 0.0 {
                return Err(format!(
                    "row {}: major strain {major} must be > 0 (a forming limit is a stretch)",
                    i + 1
                ));
            }
            if i > 0 && minor <= points[i - 1].0 {
                return Err(format!(
                    "row {}: minor strain {minor} must be larger than the row before's {}",
                    i + 1,
                    points[i - 1].0
                ));
            }
        }
        Ok(Self::Table { points, measure })
    }

    /// The measure the curve's strains are in.
    pub fn measure(&self) -> Measure {
        match self {
            Self::KeelerBrazier { .. } => Measure::Engineering,
            Self::Table { measure, .. } => *measure,
        }
    }

    /// The limit major strain at `minor`, both in the curve's measure.
    pub fn limit(&self, minor: f64) -> f64 {
        match self {
            Self::KeelerBrazier { fld0, .. } => {
                if minor < 0.0 {
                    // Constant true thickness strain: (1 + e1)(1 + e2) = 1 + FLD0.
                    (1.0 + fld0) / (1.0 + minor) - 1.0
                } else {
                    fld0 + KEELER_BRAZIER_RIGHT_SLOPE * minor
                }
            }
            Self::Table { points, .. } => interpolate(points, minor),
        }
    }

    /// The limit at plane strain (minor strain 0), in the curve's measure.
    pub fn plane_strain_limit(&self) -> f64 {
        self.limit(0.0)
    }
}

/// Piecewise-linear interpolation, constant beyond the ends.
fn interpolate(points: &[(f64, f64)], x: f64) -> f64 {
    let (first, last) = (points[0], points[points.len() - 1]);
    if x <= first.0 {
        return first.1;
    }
    if x >= last.0 {
        return last.1;
    }
    let i = points.partition_point(|p| p.0 <= x);
    let (a, b) = (points[i - 1], points[i]);
    a.1 + (x - a.0) / (b.0 - a.0) * (b.1 - a.1)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Keeler–Brazier's plane-strain limit is the formula's value:
    /// `(23.3 + 14.13 t) n / 0.21` percent, `n` capped at 0.21 (Keeler and
    /// Brazier 1977, as given in the AHSS Application Guidelines, "Forming
    /// Limit Curves"). 1 mm at n = 0.21: 37.43 %; the cup's 0.78 mm steel
    /// (n = 0.2589, capped): 34.3214 %; 0.78 mm at n = 0.15: 24.5153 %.
    #[test]
    fn keeler_brazier_plane_strain_limit_is_the_formula() {
        for (t, n, percent) in [
            (1.0, 0.21, 37.43),
            (0.78, 0.2589, 34.3214),
            (0.78, 0.15, 24.515_285_714_285_7),
            (2.0, 0.105, 25.78),
        ] {
            let c = FormingLimitCurve::keeler_brazier(t, n).unwrap();
            assert!(
                (c.plane_strain_limit() * 100.0 - percent).abs() < 1e-9,
                "t = {t}, n = {n}: {} %",
                c.plane_strain_limit() * 100.0
            );
            assert_eq!(c.measure(), Measure::Engineering);
        }
    }

    /// Left branch: constant true thickness strain, `ε1 + ε2 = ln(1 + FLD0)`;
    /// right branch: slope 0.6 in engineering strain.
    #[test]
    fn keeler_brazier_branches_have_their_published_shape() {
        let c = FormingLimitCurve::keeler_brazier(0.78, 0.2589).unwrap();
        let eps0 = (1.0 + c.plane_strain_limit()).ln();
        for e2 in [-0.4, -0.2, -0.05, -1e-6] {
            let e1 = c.limit(e2);
            assert!(((1.0 + e1).ln() + (1.0 + e2).ln() - eps0).abs() < 1e-12);
        }
        for e2 in [0.0, 0.05, 0.2] {
            let slope = (c.limit(e2 + 0.01) - c.limit(e2)) / 0.01;
            assert!((slope - 0.6).abs() < 1e-9);
        }
    }

    #[test]
    fn a_table_interpolates_and_holds_beyond_its_ends() {
        let c = FormingLimitCurve::table(vec![(-0.2, 0.5), (0.0, 0.3), (0.2, 0.4)], Measure::True)
            .unwrap();
        assert_eq!(c.limit(-0.5), 0.5);
        assert!((c.limit(-0.1) - 0.4).abs() < 1e-15);
        assert!((c.limit(0.1) - 0.35).abs() < 1e-15);
        assert_eq!(c.limit(0.9), 0.4);
    }

    #[test]
    fn bad_curves_are_refused_with_the_row() {
        let e = FormingLimitCurve::table(vec![(0.0, 0.3)], Measure::True).unwrap_err();
        assert!(e.contains("at least 2"), "{e}");
        let e = FormingLimitCurve::table(vec![(0.0, 0.3), (0.0, 0.4)], Measure::True).unwrap_err();
        assert!(e.starts_with("row 2"), "{e}");
        let e =
            FormingLimitCurve::table(vec![(0.0, 0.3), (0.1, f64::NAN)], Measure::True).unwrap_err();
        assert!(e.contains("not finite"), "{e}");
        assert!(FormingLimitCurve::keeler_brazier(0.0, 0.2).is_err());
        assert!(FormingLimitCurve::keeler_brazier(1.0, f64::INFINITY).is_err());
    }
}
