//! What a study's quantities ([`crate::quantity`]: a number of
//! `summary.json`, a section curve, the punch force at a stroke) measure in
//! a run, and the error of a variant against the reference.
//!
//! Errors are relative. A number's is `|v − v_ref| / |v_ref|`. A curve's is
//! measured at the reference's points (the variant's curve interpolated
//! linearly there, so meshes may differ): the root mean square of the
//! difference over the points the two curves share (L2) and its largest
//! magnitude (max), both divided by the reference curve's largest magnitude.
//! The L2 figure is the one held against the tolerance.

use crate::identify::observe::{interpolate, lookup};
pub use crate::quantity::Quantity;
use crate::run::RunResult;

/// Why a quantity cannot be parsed, measured or compared.
#[derive(Debug, thiserror::Error)]
pub enum MeasureError {
    /// A name of `--quantities` does not parse.
    #[error("--quantities `{text}`: {source}")]
    Parse {
        /// The quantity as given.
        text: String,
        /// What is wrong.
        source: crate::quantity::ParseError,
    },
    /// The run's summary could not be turned into JSON.
    #[error(transparent)]
    Summary(#[from] serde_json::Error),
    /// `summary.json` has no number at the key.
    #[error("{name}: summary.json has no number at this key")]
    NoNumber {
        /// The quantity's name.
        name: String,
    },
    /// The run did not report the section curve.
    #[error(
        "{name}: the run reported no such section curve (output.sections, output.report_strokes)"
    )]
    NoCurve {
        /// The quantity's name.
        name: String,
    },
    /// The run gave a value that is not finite.
    #[error("{name}: the run gave a value that is not finite")]
    NotFinite {
        /// The quantity's name.
        name: String,
    },
    /// The reference's number is 0.
    #[error("the reference value is 0: no relative error")]
    ZeroReference,
    /// A number against a curve.
    #[error("a number compared with a curve")]
    Mixed,
    /// The reference curve is 0 everywhere.
    #[error("the reference curve is zero everywhere: no relative error")]
    ZeroCurve,
    /// The variant's curve covers less than half of the reference's points.
    #[error(
        "the curve covers {covered} of the reference's {points} points: the sections do not match"
    )]
    Coverage {
        /// Reference points the curve covers.
        covered: usize,
        /// The reference's points.
        points: usize,
    },
}

/// What a run gave for a quantity.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Measured {
    /// A number.
    Scalar(f64),
    /// A curve: `(initial distance (mm), value)`.
    Curve(Vec<(f64, f64)>),
}

/// A variant's error on one quantity, relative to the reference.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct QuantityError {
    /// The error held against the tolerance (a number's relative error, a
    /// curve's relative L2 norm).
    pub error: f64,
    /// A curve's relative max norm (a number: its relative error again).
    pub max: f64,
}

/// Parse a name of `--quantities` ([`Quantity::parse`]).
///
/// # Errors
/// The name does not parse: one line naming it.
pub fn parse(text: &str) -> Result<Quantity, MeasureError> {
    Quantity::parse(text).map_err(|source| MeasureError::Parse {
        text: text.trim().into(),
        source,
    })
}

/// What a study reads of a run.
pub trait Measure {
    /// What `result` gave for this quantity; `summary` is its summary as
    /// JSON ([`measure_all`] makes it once for every quantity).
    ///
    /// # Errors
    /// A key `summary.json` does not have, a section or report stroke the
    /// run did not report, a stroke the punch did not reach, a value that
    /// is not finite.
    fn measure(
        &self,
        result: &RunResult,
        summary: &serde_json::Value,
    ) -> Result<Measured, MeasureError>;
}

impl Measure for Quantity {
    fn measure(
        &self,
        result: &RunResult,
        summary: &serde_json::Value,
    ) -> Result<Measured, MeasureError> {
        let name = self.name();
        let measured = match self {
            Quantity::Scalar { key } => {
                let parts: Vec<&str> = key.split('.').collect();
                let v = lookup(summary, &parts)
                    .and_then(serde_json::Value::as_f64)
                    .ok_or_else(|| MeasureError::NoNumber { name: name.clone() })?;
                Measured::Scalar(v)
            }
            Quantity::Curve {
                section,
                stroke,
                column,
            } => {
                let snapshot = match stroke {
                    None => Some(&result.last),
                    Some(s) => result
                        .states
                        .iter()
                        .find(|(k, _)| (k - s).abs() <= 1e-9 * s.abs().max(1.0))
                        .map(|(_, snap)| snap),
                };
                let rows = snapshot
                    .and_then(|snap| snap.curves.get(section))
                    .ok_or_else(|| MeasureError::NoCurve { name: name.clone() })?;
                Measured::Curve(rows.iter().map(|r| (r.distance, column.of(r))).collect())
            }
            Quantity::Force { stroke } => {
                let points: Vec<(f64, f64)> = (result.history.iter())
                    .map(|h| (h.stroke, h.punch_force))
                    .collect();
                let f = interpolate(&points, *stroke)
                    .ok_or_else(|| MeasureError::NoNumber { name: name.clone() })?;
                Measured::Scalar(f)
            }
        };
        let finite = match &measured {
            Measured::Scalar(v) => v.is_finite(),
            Measured::Curve(p) => p.iter().all(|(x, y)| x.is_finite() && y.is_finite()),
        };
        if finite {
            Ok(measured)
        } else {
            Err(MeasureError::NotFinite { name })
        }
    }
}

/// What `result` gave for each of `quantities`, in order.
///
/// # Errors
/// As [`Quantity::measure`], for the first quantity that fails.
pub fn measure_all(
    quantities: &[Quantity],
    result: &RunResult,
) -> Result<Vec<Measured>, MeasureError> {
    let summary = serde_json::to_value(&result.summary)?;
    quantities
        .iter()
        .map(|q| q.measure(result, &summary))
        .collect()
}

/// The relative error of `value` against `reference`.
///
/// # Errors
/// A number against a curve; a reference that is zero everywhere; curves
/// that share fewer than half of the reference's points.
pub fn error(value: &Measured, reference: &Measured) -> Result<QuantityError, MeasureError> {
    match (value, reference) {
        (Measured::Scalar(v), Measured::Scalar(r)) => {
            if *r == 0.0 {
                return Err(MeasureError::ZeroReference);
            }
            let e = ((v - r) / r).abs();
            Ok(QuantityError { error: e, max: e })
        }
        (Measured::Curve(v), Measured::Curve(r)) => curve_error(v, r),
        _ => Err(MeasureError::Mixed),
    }
}

fn curve_error(
    curve: &[(f64, f64)],
    reference: &[(f64, f64)],
) -> Result<QuantityError, MeasureError> {
    let scale = reference.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    if scale == 0.0 {
        return Err(MeasureError::ZeroCurve);
    }
    let diffs: Vec<f64> = reference
        .iter()
        .filter_map(|&(x, r)| interpolate(curve, x).map(|v| v - r))
        .collect();
    if 2 * diffs.len() < reference.len() {
        return Err(MeasureError::Coverage {
            covered: diffs.len(),
            points: reference.len(),
        });
    }
    let mean_square = diffs.iter().map(|d| d * d).sum::<f64>() / diffs.len() as f64;
    let max = diffs.iter().map(|d| d.abs()).fold(0.0, f64::max);
    Ok(QuantityError {
        error: mean_square.sqrt() / scale,
        max: max / scale,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bad_name_is_refused_in_one_line_naming_it() {
        for (text, what) in [
            ("OD:strain", "column"),
            ("OD@x:major", "stroke"),
            (":major", "section"),
            (" ", "empty"),
        ] {
            let e = parse(text).unwrap_err().to_string();
            assert!(
                e.starts_with(&format!("--quantities `{}`", text.trim())),
                "{e}"
            );
            assert!(e.contains(what) && e.lines().count() == 1, "{e}");
        }
        assert_eq!(parse("punch_force@20").unwrap().name(), "punch_force@20");
    }

    #[test]
    fn scalar_error_is_relative() {
        let e = error(&Measured::Scalar(10.5), &Measured::Scalar(10.0)).unwrap();
        assert!((e.error - 0.05).abs() < 1e-15);
        assert!(error(&Measured::Scalar(1.0), &Measured::Scalar(0.0)).is_err());
    }

    /// A curve shifted by a constant 0.01 on a coarser mesh, against a
    /// reference peaking at 0.5: L2 = max = 0.01 / 0.5 wherever the coarse
    /// curve interpolates the line exactly.
    #[test]
    fn curve_error_interpolates_the_variant_at_the_reference_points() {
        let reference: Vec<(f64, f64)> = (0..=10).map(|i| (i as f64, 0.05 * i as f64)).collect();
        let coarse: Vec<(f64, f64)> = (0..=5)
            .map(|i| (2.0 * i as f64, 0.1 * i as f64 + 0.01))
            .collect();
        let e = error(
            &Measured::Curve(coarse),
            &Measured::Curve(reference.clone()),
        )
        .unwrap();
        assert!((e.error - 0.02).abs() < 1e-12, "{e:?}");
        assert!((e.max - 0.02).abs() < 1e-12, "{e:?}");
        let short: Vec<(f64, f64)> = reference[..4].to_vec();
        assert!(
            error(&Measured::Curve(short), &Measured::Curve(reference))
                .unwrap_err()
                .to_string()
                .contains("do not match")
        );
    }
}
