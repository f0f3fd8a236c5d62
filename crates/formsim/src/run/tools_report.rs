//! What each tool and contact pair did in a run, for `summary.json`: per tool
//! and press step the force it exerted on the blank (mean, min, max; along its
//! direction of motion and in total), the force prescribed to a
//! force-controlled tool, its travel and work; per pair the frictional
//! dissipation, and the contact area and mean pressure at the end. Forces are
//! those on the model (a quarter model carries a quarter of the press force).

use crate::records::{ToolRow, ToolState};
use crate::scene::Model;
use contact::{Sampled, ToolStepLog};
use fem_core::{Amplitude, ForceLaw, ToolMotion};
use serde::Serialize;
use std::collections::BTreeMap;

/// Mean, smallest and largest value of a force over a press step (N).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct ForceStats {
    /// Time mean.
    pub mean: f64,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
}

impl ForceStats {
    fn of(s: &Sampled, duration: f64) -> Self {
        let (mean, min, max) = s.mean_min_max(duration);
        Self { mean, min, max }
    }
}

/// What one tool did over one press step.
#[derive(Debug, Clone, Serialize)]
pub struct ToolStepSummary {
    /// Index of the press step (0-based, in programme order).
    pub index: usize,
    /// Time spent in the step (s).
    pub duration_s: f64,
    /// Unit direction the forces are resolved along (the tool's direction of
    /// motion, else its first direction in the programme, else −z).
    pub direction: [f64; 3],
    /// Force the tool exerted on the blank along `direction` (N).
    pub force_along: ForceStats,
    /// Magnitude of the force the tool exerted on the blank (N).
    pub force_total: ForceStats,
    /// Force prescribed to a force-controlled tool (N).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub force_prescribed: Option<ForceStats>,
    /// `force_along.mean / force_prescribed.mean − 1` (-), force control only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub delivered_error: Option<f64>,
    /// The mean force that went into a force-controlled tool's own
    /// acceleration over the step, `m Δv / duration` along `direction` (N):
    /// the tool's momentum change, which the blank does not feel.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub force_inertia: Option<f64>,
    /// `delivered_error` with the tool's own acceleration taken out,
    /// `(force_along.mean + force_inertia) / force_prescribed.mean − 1` (-):
    /// the share lost to the tool's dashpot or kept by a transient; the
    /// delivered-force warning reads this.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub held_error: Option<f64>,
    /// Travel along `direction` over the step (mm).
    pub travel: f64,
    /// The prescribed force followed a gas-spring curve at full amplitude
    /// over the step: it varies, but the tool must deliver it all along.
    #[serde(skip)]
    pub follows_curve: bool,
    /// Work the tool did on the blank through contact (mJ = N·mm).
    pub work: f64,
}

/// What one tool did over the run.
#[derive(Debug, Clone, Serialize)]
pub struct ToolSummary {
    /// Travel along the tool's press axis at the end, from its initial pose (mm).
    pub travel: f64,
    /// Work the tool did on the blank through contact over the run (mJ).
    pub work: f64,
    /// Per press step, keyed by the step's name.
    pub steps: BTreeMap<String, ToolStepSummary>,
}

/// What one contact pair did.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct PairSummary {
    /// Frictional dissipation over the run (mJ).
    pub friction_dissipation: f64,
    /// Contact area at the end (mm²): nodal areas of the touching points.
    pub contact_area: f64,
    /// Area-weighted mean contact pressure at the end (MPa).
    pub mean_pressure: f64,
}

/// What one drawbead did (docs/drawbeads.md).
#[derive(Debug, Clone, Serialize)]
pub struct BeadSummary {
    /// The tool it is fixed to.
    pub tool: String,
    /// Its length (mm).
    pub length: f64,
    /// Stick stiffness per unit length, `max F_t / elastic_slip` (N/mm²).
    pub stiffness: f64,
    /// Restraining force on the blank at the end (N).
    pub restraining_force: f64,
    /// Largest restraining force of the run (N).
    pub restraining_force_max: f64,
    /// Clamping force on the blank at the end (N).
    pub normal_force: f64,
    /// Length over clamped blank at the end (mm).
    pub length_engaged: f64,
    /// Largest length over clamped blank of the run (mm).
    pub length_engaged_max: f64,
    /// Dissipation of its restraint over the run (mJ).
    pub dissipation: f64,
    /// Work its tool did through it (mJ).
    pub tool_work: f64,
}

/// The tools' block of `summary.json`.
pub fn tools(model: &Model) -> BTreeMap<String, ToolSummary> {
    let Some(c) = model.contact() else {
        return BTreeMap::new();
    };
    let step_names: Vec<String> = model.press().map_or_else(Vec::new, |p| {
        p.steps().iter().map(|s| s.name.clone()).collect()
    });
    let axes = press_axes(model);
    let follows_curve = |step: usize, tool: usize| {
        model.press().is_some_and(|p| {
            p.steps().get(step).is_some_and(|s| {
                s.motions.iter().any(|(t, m)| {
                    *t == tool
                        && matches!(
                            m,
                            ToolMotion::Force {
                                force: ForceLaw::Compression(_),
                                amplitude: None | Some(Amplitude::Constant),
                                ..
                            }
                        )
                })
            })
        })
    };
    c.tool_log()
        .iter()
        .zip(&model.tool_names)
        .enumerate()
        .map(|(i, (log, name))| {
            let travel = model
                .press()
                .map_or(0.0, |p| p.displacement(i).dot(&axes[i]));
            (
                name.clone(),
                tool_summary(log, &step_names, travel, |step| follows_curve(step, i)),
            )
        })
        .collect()
}

fn tool_summary(
    log: &[ToolStepLog],
    step_names: &[String],
    travel: f64,
    follows_curve: impl Fn(usize) -> bool,
) -> ToolSummary {
    let mut steps = BTreeMap::new();
    for l in log {
        let mut key = step_names
            .get(l.step)
            .cloned()
            .unwrap_or_else(|| "run".to_string());
        if steps.contains_key(&key) {
            key = format!("{key} #{}", l.step + 1);
        }
        let mut summary = step_summary(l);
        summary.follows_curve = follows_curve(l.step);
        steps.insert(key, summary);
    }
    ToolSummary {
        travel,
        work: log.iter().map(|l| l.work).sum(),
        steps,
    }
}

fn step_summary(l: &ToolStepLog) -> ToolStepSummary {
    let along = ForceStats::of(&l.along, l.duration);
    let prescribed = l.applied.as_ref().map(|a| ForceStats::of(a, l.duration));
    let inertia = l
        .momentum
        .filter(|_| l.duration > 0.0)
        .map(|(first, last)| (last - first) / l.duration);
    let positive = prescribed.filter(|p| p.mean > 0.0);
    ToolStepSummary {
        index: l.step,
        duration_s: l.duration,
        direction: [l.direction.x, l.direction.y, l.direction.z],
        force_along: along,
        force_total: ForceStats::of(&l.total, l.duration),
        force_prescribed: prescribed,
        delivered_error: positive.map(|p| along.mean / p.mean - 1.0),
        force_inertia: inertia,
        held_error: positive.map(|p| (along.mean + inertia.unwrap_or(0.0)) / p.mean - 1.0),
        travel: l.travel.1 - l.travel.0,
        work: l.work,
        follows_curve: false,
    }
}

/// The pairs' block of `summary.json`.
pub fn pairs(model: &Model) -> BTreeMap<String, PairSummary> {
    let Some(c) = model.contact() else {
        return BTreeMap::new();
    };
    c.pairs()
        .iter()
        .map(|p| {
            let (contact_area, mean_pressure) = p.area_and_mean_pressure(&c.geometry().area);
            (
                p.name().to_string(),
                PairSummary {
                    friction_dissipation: p.energy.friction,
                    contact_area,
                    mean_pressure,
                },
            )
        })
        .collect()
}

/// The drawbeads' block of `summary.json`.
pub fn beads(model: &Model) -> BTreeMap<String, BeadSummary> {
    let Some(c) = model.contact() else {
        return BTreeMap::new();
    };
    c.drawbeads()
        .iter()
        .map(|b| {
            (
                b.name().to_string(),
                BeadSummary {
                    tool: model.tool_names[b.tool()].clone(),
                    length: b.length(),
                    stiffness: b.stiffness(),
                    restraining_force: b.restraining_force,
                    restraining_force_max: b.restraining_force_max,
                    normal_force: b.normal_force,
                    length_engaged: b.length_engaged,
                    length_engaged_max: b.length_engaged_max,
                    dissipation: b.energy.dissipation,
                    tool_work: b.energy.tool_work,
                },
            )
        })
        .collect()
}

/// A tool's own acceleration is shown beside its delivered force when it
/// accounts for more than this share of the prescribed force (the
/// delivered-force warning's bound).
const INERTIA_SHOWN: f64 = super::warnings::DELIVERED_FORCE_ERROR_MAX;

/// One line per force-controlled tool and press step: the force it delivered
/// beside the one prescribed (for the console).
pub fn delivered_lines(tools: &BTreeMap<String, ToolSummary>) -> Vec<String> {
    let mut lines = Vec::new();
    for (name, t) in tools {
        let mut steps: Vec<_> = t.steps.iter().collect();
        steps.sort_by_key(|(_, s)| s.index);
        for (step, s) in steps {
            if let (Some(p), Some(e)) = (s.force_prescribed, s.delivered_error) {
                let mut line = format!(
                    "{name} in \"{step}\": delivered {:.1} N (mean; min {:.1}, max {:.1}), prescribed {:.1} N ({:+.2} %)",
                    s.force_along.mean,
                    s.force_along.min,
                    s.force_along.max,
                    p.mean,
                    100.0 * e
                );
                if let Some(i) = s.force_inertia.filter(|i| i.abs() > INERTIA_SHOWN * p.mean) {
                    line.push_str(&format!(" ({:+.1} N from the tool's own acceleration)", -i));
                }
                lines.push(line);
            }
        }
    }
    lines
}

/// The press axis each tool's history is resolved along: its first direction
/// of motion, else −z.
pub fn press_axes(model: &Model) -> Vec<plugins_api::Vec3> {
    if model.contact().is_none() {
        return Vec::new();
    }
    (0..model.tool_names.len())
        .map(|i| {
            model
                .press()
                .and_then(|p| p.first_direction(i))
                .unwrap_or(-plugins_api::Vec3::z())
        })
        .collect()
}

/// The tools' states now.
pub fn sample(model: &Model, axes: &[plugins_api::Vec3], time: f64, stroke: f64) -> ToolRow {
    let tools = model.contact().map_or_else(Vec::new, |c| {
        axes.iter()
            .enumerate()
            .map(|(i, d)| {
                let f = -c.reactions()[i];
                ToolState {
                    force: f.dot(d),
                    force_total: f.norm(),
                    prescribed: model.press().and_then(|p| p.applied_force(i)),
                    position: model.press().map_or(0.0, |p| p.displacement(i).dot(d)),
                }
            })
            .collect()
    });
    ToolRow {
        time,
        stroke,
        tools,
    }
}
