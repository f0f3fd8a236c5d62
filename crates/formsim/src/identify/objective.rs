//! The objectives (docs/identification.md, "Objectives").
//!
//! - `mae`, the thesis's form (eq. 2.70): the mean over data sets of the mean
//!   over their points of the absolute error, each error divided by its
//!   point's scale (`|measured|` for a scalar, the largest `|measured|` of its
//!   curve for a curve or force point, 1 where that is zero) so that
//!   millimetres, strains and newtons add up. Dimensionless (0.02 = 2 %).
//! - `wls`, weighted least squares: `Σ ((simulated − measured)/se)²` over
//!   every point; needs a standard error on every value.
//!
//! Least-squares residuals (for Levenberg–Marquardt and the covariance):
//! `(simulated − measured)/se` where standard errors are given; otherwise the
//! scaled error divided by `√(m n_j)`, whose sum of squares is the mean over
//! sets of the mean squared scaled error (the least-squares counterpart of
//! `mae`).

use super::IdentifyError;
use super::evaluate::PredictionError;
use super::measurements::{Measurements, Point};

/// Which objective the optimiser minimises.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Objective {
    /// Mean absolute scaled error (the thesis's).
    Mae,
    /// Weighted least squares with the standard errors.
    Wls,
}

impl Objective {
    /// Parse `mae` or `wls`.
    ///
    /// # Errors
    /// Another name.
    pub fn parse(name: &str) -> Result<Self, IdentifyError> {
        match name {
            "mae" => Ok(Self::Mae),
            "wls" => Ok(Self::Wls),
            other => Err(IdentifyError::Option(format!(
                "--objective {other}: expected mae (the thesis's mean absolute error) or wls (weighted least squares)"
            ))),
        }
    }

    /// The name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Mae => "mae",
            Self::Wls => "wls",
        }
    }

    /// The objective of the predictions of every data set (`+∞` if one failed).
    pub fn cost(
        self,
        data: &Measurements,
        predictions: &[Result<Vec<f64>, PredictionError>],
    ) -> f64 {
        let mut sets_used = 0usize;
        let mut total = 0.0;
        for (set, p) in data.sets.iter().zip(predictions) {
            let Ok(p) = p else {
                return f64::INFINITY;
            };
            if set.points.is_empty() {
                continue;
            }
            match self {
                Self::Mae => {
                    let sum: f64 = set
                        .points
                        .iter()
                        .zip(p)
                        .map(|(m, s)| ((s - m.value) / scale(m)).abs())
                        .sum();
                    total += sum / set.points.len() as f64;
                    sets_used += 1;
                }
                Self::Wls => {
                    total += set
                        .points
                        .iter()
                        .zip(p)
                        .map(|(m, s)| ((s - m.value) / m.se.unwrap_or(f64::NAN)).powi(2))
                        .sum::<f64>();
                }
            }
        }
        let value = match self {
            Self::Mae => total / sets_used.max(1) as f64,
            Self::Wls => total,
        };
        if value.is_nan() { f64::INFINITY } else { value }
    }
}

/// A point's error scale in `mae`.
pub fn scale(p: &Point) -> f64 {
    if p.scale > 0.0 { p.scale } else { 1.0 }
}

/// The least-squares residuals of successful predictions of every data set,
/// in data-set and point order: weighted by the standard errors when every
/// value has one, else the scaled errors divided by `√(m n_j)`.
pub fn residuals(data: &Measurements, predictions: &[Vec<f64>]) -> Vec<f64> {
    let weighted = data.all_have_se();
    let m = data
        .sets
        .iter()
        .filter(|s| !s.points.is_empty())
        .count()
        .max(1) as f64;
    data.sets
        .iter()
        .zip(predictions)
        .flat_map(|(set, p)| {
            let n = set.points.len().max(1) as f64;
            set.points
                .iter()
                .zip(p)
                .map(move |(pt, s)| match (weighted, pt.se) {
                    (true, Some(se)) => (s - pt.value) / se,
                    _ => (s - pt.value) / scale(pt) / (m * n).sqrt(),
                })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::measurements::{DataSet, Quantity};
    use super::*;

    fn point(value: f64, se: Option<f64>) -> Point {
        Point {
            quantity: Quantity::Scalar { key: "k".into() },
            distance: None,
            value,
            se,
            scale: value.abs(),
            group: "k".into(),
            line: 1,
        }
    }

    fn data(sets: Vec<Vec<Point>>) -> Measurements {
        Measurements {
            path: "m".into(),
            sets: sets
                .into_iter()
                .enumerate()
                .map(|(i, points)| DataSet {
                    name: format!("m{i}"),
                    overrides: vec![],
                    points,
                })
                .collect(),
        }
    }

    #[test]
    fn mae_is_the_mean_over_sets_of_the_mean_scaled_error() {
        // Set 0: errors 10 % and 30 % -> 0.2; set 1: error 50 % -> 0.5; mean 0.35.
        let d = data(vec![
            vec![point(10.0, None), point(20.0, None)],
            vec![point(2.0, None)],
        ]);
        let p = vec![Ok(vec![11.0, 14.0]), Ok(vec![3.0])];
        assert!((Objective::Mae.cost(&d, &p) - 0.35).abs() < 1e-15);
        let r = residuals(&d, &[vec![11.0, 14.0], vec![3.0]]);
        let ls: f64 = r.iter().map(|x| x * x).sum();
        // Mean over sets of the mean squared scaled error: ((0.01 + 0.09)/2 + 0.25)/2.
        assert!((ls - 0.15).abs() < 1e-15);
        assert_eq!(
            Objective::Mae.cost(
                &d,
                &[
                    Ok(vec![1.0, 1.0]),
                    Err(PredictionError {
                        set: "x".into(),
                        reason: crate::identify::evaluate::PredictionFailure::NotJournalled,
                    })
                ]
            ),
            f64::INFINITY
        );
    }

    #[test]
    fn wls_weights_by_the_standard_errors() {
        let d = data(vec![vec![point(10.0, Some(0.5)), point(20.0, Some(2.0))]]);
        let p = vec![Ok(vec![11.0, 14.0])];
        assert!((Objective::Wls.cost(&d, &p) - (4.0 + 9.0)).abs() < 1e-12);
        assert_eq!(residuals(&d, &[vec![11.0, 14.0]]), vec![2.0, -3.0]);
    }
}
