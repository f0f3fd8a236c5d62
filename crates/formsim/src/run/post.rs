//! Post-processing of a model state: strains along sections, draw-in,
//! thinning, punch force. Called at report strokes and at the end (it
//! allocates; it is not part of the time-step loop).

use super::tools_report::{self, ToolSummary};
use crate::formability::FormabilityState;
use crate::scene::schema::{DrawIn, SectionLine};
use crate::scene::{LoadedScene, Model, SceneError};
use fem_core::Mesh;
use serde::Serialize;
use std::collections::BTreeMap;

/// The elements of one section, ordered by initial distance from its start.
#[derive(Debug, Clone)]
pub struct SectionIndex {
    /// Section name (`OD`, `OX`).
    pub name: String,
    /// `(element, initial distance from the start along the section (mm))`.
    pub elements: Vec<(usize, f64)>,
}

/// Elements whose initial centroid lies within half an element size of the
/// segment, with the centroid's distance along it.
pub fn section_index(mesh: &Mesh, line: &SectionLine) -> SectionIndex {
    let (ax, ay) = (line.from[0], line.from[1]);
    let (dx, dy) = (line.to[0] - ax, line.to[1] - ay);
    let len = dx.hypot(dy);
    let (ux, uy) = (dx / len, dy / len);
    let mut elements = Vec::new();
    for (e, q) in mesh.quads.iter().enumerate() {
        let p = q.map(|n| mesh.nodes[n as usize]);
        let cx = 0.25 * p.iter().map(|v| v.x).sum::<f64>();
        let cy = 0.25 * p.iter().map(|v| v.y).sum::<f64>();
        let area = 0.5 * ((p[2] - p[0]).cross(&(p[3] - p[1]))).norm();
        let half = 0.5 * area.sqrt() * (1.0 + 1e-6);
        let s = (cx - ax) * ux + (cy - ay) * uy;
        let off = ((cx - ax) * uy - (cy - ay) * ux).abs();
        if off <= half && s >= -half && s <= len + half {
            elements.push((e, s));
        }
    }
    elements.sort_by(|a, b| a.1.total_cmp(&b.1));
    SectionIndex {
        name: line.name.clone(),
        elements,
    }
}

/// Every `[[output.sections]]` line crosses an element of the blank and
/// every `[[output.profiles]]` line has the seven nodes its fits need
/// (two in the web, three in the wall, two in the flange): a line that
/// misses the blank is one line at its key, not a NaN or an empty curve at
/// the end of the run.
///
/// # Errors
/// The first line that misses, at its key.
pub fn check_lines(loaded: &LoadedScene, mesh: &Mesh) -> Result<(), SceneError> {
    let o = &loaded.scene.output;
    for (i, line) in o.sections.iter().enumerate() {
        if section_index(mesh, line).elements.is_empty() {
            return Err(loaded.key_error(
                &format!("output.sections[{i}]"),
                format!(
                    "no element of the blank lies on the line from {:?} to {:?} (within half an element)",
                    line.from, line.to
                ),
            ));
        }
    }
    for (i, line) in o.profiles.iter().enumerate() {
        let n = super::profile::profile_index(mesh, line).nodes.len();
        if n < 7 {
            return Err(loaded.key_error(
                &format!("output.profiles[{i}]"),
                format!(
                    "{n} nodes of the blank lie on the line from {:?} to {:?} (within half an element); its fits need 7",
                    line.from, line.to
                ),
            ));
        }
    }
    Ok(())
}

/// One point of a section curve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
pub struct SectionRow {
    /// Initial distance from the section's start (mm).
    pub distance: f64,
    /// Major logarithmic membrane strain (-).
    pub major: f64,
    /// Minor logarithmic membrane strain (-).
    pub minor: f64,
    /// Thickness strain `ln(t/t0)` (-).
    pub thickness_strain: f64,
    /// Thinning `(t0 − t)/t0` (-).
    pub thinning: f64,
}

/// Extremes of one section.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
pub struct SectionSummary {
    /// Largest major strain (-).
    pub major_max: f64,
    /// Smallest minor strain (-).
    pub minor_min: f64,
    /// Largest thinning `(t0 − t)/t0` along the section (-).
    pub thinning_max: f64,
    /// Minor strain at `output.punch_edge_distance` (linear interpolation), when asked.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub minor_at_punch_edge: Option<f64>,
}

/// The state reported at one stroke (or at the end).
#[derive(Debug, Clone, Serialize)]
pub struct Snapshot {
    /// Time (s).
    pub time: f64,
    /// Stroke (mm).
    pub stroke: f64,
    /// Punch force, full-model equivalent (N).
    pub punch_force: f64,
    /// Largest thinning `(t0 − t)/t0` over the blank (-).
    pub thinning_max: f64,
    /// Energies at this state (mJ).
    #[serde(skip)]
    pub energy: fem_core::EnergyLedger,
    /// What each tool did up to this state (forces on the model, per press step).
    #[serde(skip)]
    pub tools: BTreeMap<String, ToolSummary>,
    /// Section extremes.
    pub sections: BTreeMap<String, SectionSummary>,
    /// Draw-in (mm).
    pub draw_in: BTreeMap<String, f64>,
    /// Section curves (written as CSV, not into the summary).
    #[serde(skip)]
    pub curves: BTreeMap<String, Vec<SectionRow>>,
    /// The forming limit diagram, when the scene has `[formability]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub formability: Option<FormabilityState>,
}

/// What post-processing needs, prepared once.
#[derive(Debug, Clone)]
pub struct Post {
    /// Sections.
    pub sections: Vec<SectionIndex>,
    /// `(name, node, inward unit [x, y])`.
    pub draw_in: Vec<(String, usize, [f64; 2])>,
    /// See `SectionSummary::minor_at_punch_edge`.
    pub punch_edge: Option<f64>,
}

impl Post {
    /// Index sections and draw-in points on the initial mesh.
    pub fn new(
        mesh: &Mesh,
        sections: &[SectionLine],
        draw_in: &[DrawIn],
        punch_edge: Option<f64>,
    ) -> Self {
        let draw_in = draw_in
            .iter()
            .map(|d| {
                let node = mesh
                    .nodes
                    .iter()
                    .enumerate()
                    .min_by(|a, b| {
                        let da = (a.1.x - d.at[0]).hypot(a.1.y - d.at[1]);
                        let db = (b.1.x - d.at[0]).hypot(b.1.y - d.at[1]);
                        da.total_cmp(&db)
                    })
                    .map_or(0, |(i, _)| i);
                let n = d.inward[0].hypot(d.inward[1]);
                (d.name.clone(), node, [d.inward[0] / n, d.inward[1] / n])
            })
            .collect();
        Self {
            sections: sections.iter().map(|l| section_index(mesh, l)).collect(),
            draw_in,
            punch_edge,
        }
    }

    /// The snapshot of the model's current state.
    pub fn snapshot(&self, model: &Model, time: f64, stroke: f64, punch_force: f64) -> Snapshot {
        let shells = model.shells();
        let state = model.solver.state();
        let t0 = model.thickness0;
        let thinning_max = (0..shells.len())
            .map(|e| (t0 - shells.thickness(e)) / t0)
            .fold(f64::NEG_INFINITY, f64::max);
        let mut sections = BTreeMap::new();
        let mut curves = BTreeMap::new();
        for sec in &self.sections {
            let rows: Vec<SectionRow> = sec
                .elements
                .iter()
                .map(|&(e, distance)| {
                    let strain = shells.membrane_strain(e, state);
                    let t = shells.thickness(e);
                    SectionRow {
                        distance,
                        major: strain.major,
                        minor: strain.minor,
                        thickness_strain: (t / t0).ln(),
                        thinning: (t0 - t) / t0,
                    }
                })
                .collect();
            sections.insert(sec.name.clone(), extremes(&rows, self.punch_edge));
            curves.insert(sec.name.clone(), rows);
        }
        let draw_in = self
            .draw_in
            .iter()
            .map(|(name, node, dir)| {
                let u = state.x[*node] - state.x0[*node];
                (name.clone(), u.x * dir[0] + u.y * dir[1])
            })
            .collect();
        Snapshot {
            time,
            stroke,
            punch_force,
            thinning_max,
            energy: *model.solver.ledger(),
            tools: tools_report::tools(model),
            sections,
            draw_in,
            curves,
            formability: model.formability.as_ref().map(|f| f.evaluate(model)),
        }
    }
}

/// The extremes of one section's rows; `punch_edge`: the initial distance
/// where the minor strain is read (see [`SectionSummary::minor_at_punch_edge`]).
pub fn extremes(rows: &[SectionRow], punch_edge: Option<f64>) -> SectionSummary {
    let max = |f: fn(&SectionRow) -> f64| rows.iter().map(f).fold(f64::NEG_INFINITY, f64::max);
    SectionSummary {
        major_max: max(|r| r.major),
        minor_min: rows.iter().map(|r| r.minor).fold(f64::INFINITY, f64::min),
        thinning_max: max(|r| r.thinning),
        minor_at_punch_edge: punch_edge.and_then(|d| interpolate(rows, d)),
    }
}

/// Minor strain at initial distance `d` along the rows (linear interpolation).
fn interpolate(rows: &[SectionRow], d: f64) -> Option<f64> {
    let first = rows.first()?;
    if d <= first.distance {
        return Some(first.minor);
    }
    for w in rows.windows(2) {
        if d <= w[1].distance {
            let span = w[1].distance - w[0].distance;
            let a = if span > 0.0 {
                (d - w[0].distance) / span
            } else {
                0.0
            };
            return Some(w[0].minor + a * (w[1].minor - w[0].minor));
        }
    }
    rows.last().map(|r| r.minor)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A section's extremes: largest major strain and thinning, smallest
    /// minor strain, each from its own row.
    #[test]
    fn extremes_take_each_figure_from_its_own_row() {
        let row = |distance: f64, major: f64, minor: f64, thinning: f64| SectionRow {
            distance,
            major,
            minor,
            thickness_strain: -thinning,
            thinning,
        };
        let rows = [
            row(0.0, 0.10, -0.02, 0.01),
            row(1.0, 0.30, -0.01, 0.02),
            row(2.0, 0.20, -0.05, 0.07),
        ];
        let s = extremes(&rows, Some(0.5));
        assert_eq!(s.major_max, 0.30);
        assert_eq!(s.minor_min, -0.05);
        assert_eq!(s.thinning_max, 0.07);
        assert!((s.minor_at_punch_edge.unwrap() + 0.015).abs() < 1e-15);
        assert!(extremes(&rows, None).minor_at_punch_edge.is_none());
    }

    #[test]
    fn diagonal_and_edge_sections_pick_one_element_per_division() {
        let mesh = fem_core::rectangle(75.0, 75.0, 10, 10).unwrap();
        let od = section_index(
            &mesh,
            &SectionLine {
                name: "OD".into(),
                from: [0.0, 0.0],
                to: [75.0, 75.0],
            },
        );
        let ox = section_index(
            &mesh,
            &SectionLine {
                name: "OX".into(),
                from: [0.0, 0.0],
                to: [75.0, 0.0],
            },
        );
        assert_eq!(od.elements.len(), 10);
        assert_eq!(ox.elements.len(), 10);
        // Diagonal elements (i, i): index 11 i; distances (i + 1/2) h √2.
        for (i, &(e, s)) in od.elements.iter().enumerate() {
            assert_eq!(e, 11 * i);
            assert!((s - (i as f64 + 0.5) * 7.5 * 2f64.sqrt()).abs() < 1e-9);
        }
        for (i, &(e, _)) in ox.elements.iter().enumerate() {
            assert_eq!(e, i);
        }
    }
}
