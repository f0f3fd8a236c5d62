//! What a run leaves for the identification to read (its `summary.json`, its
//! section curves at the report strokes, its punch force against stroke),
//! kept in the journal, and the simulated value of each measured point.

use super::measurements::{CurveColumn, DataSet, Quantity};
use crate::run::RunResult;
use crate::run::summary::stroke_key;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Why a measured point has no simulated value ([`Observables::predict`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ObserveError {
    /// `summary.json` has no number at the key.
    #[error("summary.json has no number at `{key}`")]
    NoNumber {
        /// The dotted key.
        key: String,
    },
    /// The run did not report the section curve.
    #[error(
        "the run reported no section curve `{curve}` (sections or report strokes of the scene)"
    )]
    NoCurve {
        /// The curve, `SECTION@STROKE`.
        curve: String,
    },
    /// The distance lies outside the simulated curve.
    #[error(
        "{curve}: distance {distance} mm is outside the simulated curve ({first:.3}..{last:.3} mm)"
    )]
    OutsideCurve {
        /// The curve, `SECTION@STROKE`.
        curve: String,
        /// The measured point's distance (mm).
        distance: f64,
        /// The curve's first distance (mm; NaN for an empty curve).
        first: f64,
        /// The curve's last distance (mm; NaN for an empty curve).
        last: f64,
    },
    /// The run did not reach the stroke of a force point.
    #[error("punch force: stroke {stroke} mm was not reached")]
    StrokeNotReached {
        /// The stroke (mm).
        stroke: f64,
    },
    /// The simulated value is not finite.
    #[error("{point}: the simulated value is {value}")]
    NotFinite {
        /// The measured point's label.
        point: String,
        /// The simulated value.
        value: f64,
    },
}

/// The observable outputs of one run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Observables {
    /// `summary.json` as written.
    pub summary: serde_json::Value,
    /// Section curves at the report strokes, keyed `SECTION@STROKE`: rows of
    /// `[distance, major, minor, thickness_strain, thinning]`.
    pub curves: BTreeMap<String, Vec<[f64; 5]>>,
    /// Punch force (full part, N) against stroke (mm): `[stroke, force]`.
    pub force: Vec<[f64; 2]>,
}

impl Observables {
    /// Take the observables of a finished run.
    ///
    /// # Errors
    /// The summary does not serialise (cannot happen for finite figures).
    pub fn from_run(result: &RunResult) -> Result<Self, serde_json::Error> {
        let summary = serde_json::to_value(&result.summary)?;
        let mut curves = BTreeMap::new();
        for (stroke, snapshot) in &result.states {
            for (name, rows) in &snapshot.curves {
                curves.insert(
                    format!("{name}@{}", stroke_key(*stroke)),
                    rows.iter()
                        .map(|r| [r.distance, r.major, r.minor, r.thickness_strain, r.thinning])
                        .collect(),
                );
            }
        }
        let force = result
            .history
            .iter()
            .map(|h| [h.stroke, h.punch_force])
            .collect();
        Ok(Self {
            summary,
            curves,
            force,
        })
    }

    /// The simulated value of every point of `set`, in its order.
    ///
    /// # Errors
    /// A key that `summary.json` does not have (or that is not a number), a
    /// curve at a stroke or section the run did not report, a distance or
    /// stroke outside the simulated range, a value that is not finite.
    pub fn predict(&self, set: &DataSet) -> Result<Vec<f64>, ObserveError> {
        set.points
            .iter()
            .map(|p| {
                let v = match &p.quantity {
                    Quantity::Scalar { key } => self.scalar(key),
                    Quantity::Curve {
                        section,
                        stroke,
                        column,
                    } => self.curve(
                        section,
                        stroke.unwrap_or(f64::NAN),
                        *column,
                        p.distance.unwrap_or(f64::NAN),
                    ),
                    Quantity::Force { stroke } => self.force_at(*stroke),
                }?;
                if v.is_finite() {
                    Ok(v)
                } else {
                    Err(ObserveError::NotFinite {
                        point: p.label(),
                        value: v,
                    })
                }
            })
            .collect()
    }

    /// A number of `summary.json` by its dotted key.
    fn scalar(&self, key: &str) -> Result<f64, ObserveError> {
        let parts: Vec<&str> = key.split('.').collect();
        lookup(&self.summary, &parts)
            .and_then(serde_json::Value::as_f64)
            .ok_or_else(|| ObserveError::NoNumber { key: key.into() })
    }

    fn curve(
        &self,
        section: &str,
        stroke: f64,
        column: CurveColumn,
        distance: f64,
    ) -> Result<f64, ObserveError> {
        let name = format!("{section}@{}", stroke_key(stroke));
        let rows = self
            .curves
            .get(&name)
            .ok_or_else(|| ObserveError::NoCurve {
                curve: name.clone(),
            })?;
        let c = match column {
            CurveColumn::Major => 1,
            CurveColumn::Minor => 2,
            CurveColumn::ThicknessStrain => 3,
            CurveColumn::Thinning => 4,
        };
        let points: Vec<(f64, f64)> = rows.iter().map(|r| (r[0], r[c])).collect();
        interpolate(&points, distance).ok_or_else(|| ObserveError::OutsideCurve {
            curve: name,
            distance,
            first: points.first().map_or(f64::NAN, |p| p.0),
            last: points.last().map_or(f64::NAN, |p| p.0),
        })
    }

    fn force_at(&self, stroke: f64) -> Result<f64, ObserveError> {
        let points: Vec<(f64, f64)> = self.force.iter().map(|r| (r[0], r[1])).collect();
        interpolate(&points, stroke).ok_or(ObserveError::StrokeNotReached { stroke })
    }
}

/// Follow `parts` through JSON objects; a key may itself contain dots (a
/// stroke such as `12.5`): at each level the shortest join of the next parts
/// that names a key is taken.
pub(crate) fn lookup<'a>(
    value: &'a serde_json::Value,
    parts: &[&str],
) -> Option<&'a serde_json::Value> {
    if parts.is_empty() {
        return Some(value);
    }
    let object = value.as_object()?;
    (1..=parts.len()).find_map(|n| {
        object
            .get(&parts[..n].join("."))
            .and_then(|v| lookup(v, &parts[n..]))
    })
}

/// Linear interpolation at `x` on the first segment of `points` that holds it
/// (`points` in the order they were sampled; a stroke history may start with
/// repeated zeros).
pub(crate) fn interpolate(points: &[(f64, f64)], x: f64) -> Option<f64> {
    points.windows(2).find_map(|w| {
        let ((x0, y0), (x1, y1)) = (w[0], w[1]);
        let (lo, hi) = (x0.min(x1), x0.max(x1));
        if !(lo..=hi).contains(&x) {
            return None;
        }
        // At a sampled point, its own value (the blend below need not give
        // it to the last bit).
        if x == x0 {
            return Some(y0);
        }
        if x == x1 {
            return Some(y1);
        }
        let t = (x - x0) / (x1 - x0);
        Some(y0 + t * (y1 - y0))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lookup_takes_dotted_strokes() {
        let v: serde_json::Value = serde_json::json!({
            "states": {"12.5": {"draw_in": {"DX": 4.0}}, "40": {"draw_in": {"DX": 28.0}}},
            "thinning_max": 0.2
        });
        let get = |k: &str| lookup(&v, &k.split('.').collect::<Vec<_>>()).and_then(|x| x.as_f64());
        assert_eq!(get("states.12.5.draw_in.DX"), Some(4.0));
        assert_eq!(get("states.40.draw_in.DX"), Some(28.0));
        assert_eq!(get("thinning_max"), Some(0.2));
        assert_eq!(get("states.41.draw_in.DX"), None);
    }

    #[test]
    fn interpolation_is_linear_and_bounded() {
        let p = [(0.0, 0.0), (0.0, 0.0), (1.0, 10.0), (3.0, 30.0)];
        assert_eq!(interpolate(&p, 0.5), Some(5.0));
        assert_eq!(interpolate(&p, 2.0), Some(20.0));
        assert_eq!(interpolate(&p, 3.0), Some(30.0));
        assert_eq!(interpolate(&p, 3.5), None);
        // Sampled points come back to the bit.
        let q = [(0.1, 0.3), (0.7, 0.1 + 0.2)];
        assert_eq!(interpolate(&q, 0.7), Some(0.1 + 0.2));
    }
}
