//! Formability: will the part split? A forming limit curve per scene
//! ([`curve`]), every element's major and minor strain placed on the
//! forming limit diagram with its zone and safety margin ([`zones`]), the
//! counts per zone and the smallest margin for `summary.json`, and the
//! diagram itself ([`plot`]). Evaluated at the report strokes and at the
//! end; never in the time-step loop.

pub mod curve;
pub mod plot;
pub mod settings;
pub mod zones;

use crate::scene::schema::HardeningSpec;
use crate::scene::{LoadedScene, Model, SceneError};
use curve::FormingLimitCurve;
use serde::Serialize;
use settings::CurveKind;
use std::collections::BTreeMap;
use zones::{FldPoint, Thresholds, Zone, classify};

/// A scene's forming limit curve and thresholds, ready to evaluate.
#[derive(Debug, Clone, PartialEq)]
pub struct Formability {
    /// The curve.
    pub curve: FormingLimitCurve,
    /// The zones' thresholds.
    pub thresholds: Thresholds,
    /// The table's file as the scene names it.
    pub file: Option<String>,
}

/// The curve as `summary.json` reports it.
#[derive(Debug, Clone, Serialize)]
pub struct CurveSummary {
    /// `keeler-brazier` or `table`.
    pub kind: &'static str,
    /// `engineering` or `true`.
    pub measure: &'static str,
    /// The limit at plane strain, in the measure (-).
    pub plane_strain_limit: f64,
    /// Keeler–Brazier's exponent as used (capped at 0.21).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub n: Option<f64>,
    /// Keeler–Brazier's thickness (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub thickness: Option<f64>,
    /// The table's file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// Width of the marginal band (-).
    pub margin: f64,
    /// Least major true strain of a stretched sheet (-).
    pub insufficient_stretch: f64,
}

/// Where the smallest margin is.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Worst {
    /// Element index (0-based, in the blank's order).
    pub element: usize,
    /// Its initial centroid (mm).
    pub at: [f64; 3],
    /// Its major and minor strain, in the curve's measure (-).
    pub major: f64,
    /// See `major`.
    pub minor: f64,
    /// Its zone.
    pub zone: Zone,
}

/// The diagram of one state, as `summary.json` reports it.
#[derive(Debug, Clone, Serialize)]
pub struct FormabilityState {
    /// Elements per zone (every zone listed).
    pub zones: BTreeMap<&'static str, usize>,
    /// The smallest safety margin over the blank (-; negative beyond the curve).
    pub margin_min: f64,
    /// The element with the smallest margin.
    pub worst: Worst,
    /// Every element's point (written to `fld.csv` and the plot).
    #[serde(skip)]
    pub points: Vec<FldPoint>,
}

/// `summary.json` `formability`: the curve, and the diagram at the end.
#[derive(Debug, Clone, Serialize)]
pub struct FormabilityReport {
    /// The curve and thresholds.
    pub curve: CurveSummary,
    /// Counts, smallest margin and where, at the end.
    #[serde(flatten)]
    pub end: FormabilityState,
}

impl Formability {
    /// The scene's `[formability]`, built: `None` without the table.
    ///
    /// # Errors
    /// A key out of range, a Keeler–Brazier curve without a hardening
    /// exponent, a table file that cannot be read or is not a curve.
    pub fn from_scene(loaded: &LoadedScene) -> Result<Option<Self>, SceneError> {
        let Some(f) = &loaded.scene.formability else {
            return Ok(None);
        };
        let key = |k: &str, m: String| loaded.key_error(&format!("formability.{k}"), m);
        for (k, v) in [
            ("margin", f.margin),
            ("insufficient_stretch", f.insufficient_stretch),
        ] {
            if !(v.is_finite() && (0.0..1.0).contains(&v)) {
                return Err(key(k, format!("{v}: must be a strain in [0, 1)")));
            }
        }
        let curve = match f.curve {
            CurveKind::KeelerBrazier => {
                for k in ["file", "measure"] {
                    let given = if k == "file" {
                        f.file.is_some()
                    } else {
                        f.measure.is_some()
                    };
                    if given {
                        return Err(key(k, "only with curve = \"table\"".into()));
                    }
                }
                let n = match (f.n, &loaded.scene.blank.material.hardening) {
                    (Some(n), _) => n,
                    (None, Some(HardeningSpec::Swift { n, .. })) => *n,
                    _ => {
                        return Err(key(
                            "n",
                            "required: Keeler–Brazier needs the sheet's hardening exponent, and blank.material.hardening is not Swift (give formability.n, or curve = \"table\")".into(),
                        ));
                    }
                };
                FormingLimitCurve::keeler_brazier(loaded.scene.blank.thickness, n)
                    .map_err(|m| key("n", m))?
            }
            CurveKind::Table => {
                if f.n.is_some() {
                    return Err(key("n", "only with curve = \"keeler-brazier\"".into()));
                }
                let Some(file) = &f.file else {
                    return Err(key("file", "required with curve = \"table\"".into()));
                };
                let Some(measure) = f.measure else {
                    return Err(key(
                        "measure",
                        "required with curve = \"table\": \"engineering\" or \"true\"".into(),
                    ));
                };
                let path = loaded.base_dir().join(file);
                let text = std::fs::read_to_string(&path)
                    .map_err(|e| key("file", format!("{}: {e}", path.display())))?;
                let points = table_points(&text)
                    .map_err(|m| key("file", format!("{}: {m}", path.display())))?;
                FormingLimitCurve::table(points, measure)
                    .map_err(|m| key("file", format!("{}: {m}", path.display())))?
            }
        };
        Ok(Some(Self {
            curve,
            thresholds: Thresholds {
                margin: f.margin,
                stretch: f.insufficient_stretch,
            },
            file: f.file.clone(),
        }))
    }

    /// The curve for `summary.json`.
    pub fn summary(&self) -> CurveSummary {
        let (kind, n, thickness) = match &self.curve {
            FormingLimitCurve::KeelerBrazier { n, thickness, .. } => {
                ("keeler-brazier", Some(*n), Some(*thickness))
            }
            FormingLimitCurve::Table { .. } => ("table", None, None),
        };
        CurveSummary {
            kind,
            measure: self.curve.measure().as_str(),
            plane_strain_limit: self.curve.plane_strain_limit(),
            n,
            thickness,
            file: self.file.clone(),
            margin: self.thresholds.margin,
            insufficient_stretch: self.thresholds.stretch,
        }
    }

    /// The point of true strains `(eps1, eps2)` on the diagram.
    pub fn point(&self, eps1: f64, eps2: f64) -> FldPoint {
        classify(&self.curve, &self.thresholds, eps1, eps2)
    }

    /// Every element of `model` on the diagram, now.
    pub fn evaluate(&self, model: &Model) -> FormabilityState {
        let shells = model.shells();
        let state = model.solver.state();
        let points: Vec<FldPoint> = (0..shells.len())
            .map(|e| {
                let s = shells.membrane_strain(e, state);
                self.point(s.major, s.minor)
            })
            .collect();
        state_of(points, &model.mesh)
    }
}

/// The counts, the smallest margin and where, of `points` on `mesh`.
pub fn state_of(points: Vec<FldPoint>, mesh: &fem_core::Mesh) -> FormabilityState {
    let mut zones: BTreeMap<&'static str, usize> =
        Zone::ALL.iter().map(|z| (z.name(), 0)).collect();
    let mut worst = 0;
    for (e, p) in points.iter().enumerate() {
        *zones.entry(p.zone.name()).or_default() += 1;
        if p.margin < points[worst].margin {
            worst = e;
        }
    }
    let w = points.get(worst).copied().unwrap_or(FldPoint {
        major: 0.0,
        minor: 0.0,
        zone: Zone::InsufficientStretch,
        margin: f64::INFINITY,
    });
    let at = mesh.quads.get(worst).map_or([0.0; 3], |q| {
        let c = q.iter().fold(nalgebra::Vector3::zeros(), |s, &n| {
            s + mesh.nodes[n as usize]
        }) * 0.25;
        [c.x, c.y, c.z]
    });
    FormabilityState {
        zones,
        margin_min: w.margin,
        worst: Worst {
            element: worst,
            at,
            major: w.major,
            minor: w.minor,
            zone: w.zone,
        },
        points,
    }
}

/// `minor,major` rows of a curve's CSV (a header row of words is skipped,
/// `#` comments too).
fn table_points(text: &str) -> Result<Vec<(f64, f64)>, String> {
    let mut points = Vec::new();
    for (i, record) in crate::csv_records::records(text, true).enumerate() {
        let (line, r) = record.map_err(|(line, m)| format!("line {line}: {m}"))?;
        if r.len() != 2 {
            return Err(format!(
                "line {line}: {} field(s); a row is `minor,major`",
                r.len()
            ));
        }
        let parse = |s: &str| s.parse::<f64>();
        match (parse(&r[0]), parse(&r[1])) {
            (Ok(a), Ok(b)) => points.push((a, b)),
            _ if i == 0 => {} // the header
            _ => {
                return Err(format!(
                    "line {line}: `{},{}` is not two numbers",
                    &r[0], &r[1]
                ));
            }
        }
    }
    Ok(points)
}
