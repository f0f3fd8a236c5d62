//! Warnings of a finished run: the figures that say a result may not be
//! trustworthy, each against a documented bound (docs/scene-format.md,
//! "Warnings"). They go to the console and to `summary.json`'s `warnings`.

use super::tools_report::ToolSummary;
use std::collections::BTreeMap;

/// Mass added by mass scaling above which a run is flagged (% of the
/// physical mass): the bound `scene check` applies at set-up, applied to the
/// mass at the end of the run (contact adds mass as nodes touch: the shipped
/// square cup has 296 % at set-up and 456 % at the end).
pub use crate::scene::estimate::ADDED_MASS_WARNING_PERCENT as ADDED_MASS_PERCENT_MAX;
/// Largest kinetic/internal energy ratio while forming for a quasi-static run.
pub const KINETIC_TO_INTERNAL_MAX: f64 = 0.05;
/// Largest hourglass/internal energy ratio while forming (the usual 10 %
/// guideline for reduced-integration shells).
pub const HOURGLASS_TO_INTERNAL_MAX: f64 = 0.10;
/// Largest relative energy balance error at the end of a run.
pub const BALANCE_ERROR_MAX: f64 = 0.01;
/// Largest relative difference between the mean force a force-controlled tool
/// delivered over a press step and the one prescribed, checked in the steps
/// whose prescribed force is steady (its smallest value at least
/// [`STEADY_FORCE_MIN_RATIO`] of its largest): while a force ramps up, the
/// tool's momentum and the damper take their share, as they should.
pub const DELIVERED_FORCE_ERROR_MAX: f64 = 0.01;
/// A press step's prescribed force counts as steady when its smallest value
/// is at least this fraction of its largest.
pub const STEADY_FORCE_MIN_RATIO: f64 = 0.9;

/// The figures the warnings read.
#[derive(Debug, Clone, Copy)]
pub struct Figures {
    /// Added mass at the end (% of the physical mass).
    pub added_mass_percent: f64,
    /// Largest kinetic/internal while forming.
    pub kinetic_to_internal_max: f64,
    /// Largest hourglass/internal while forming.
    pub hourglass_to_internal_max: f64,
    /// Energy balance error at the end (relative).
    pub balance_error: f64,
}

/// Every bound a run exceeded, one line each, naming the figure, its value,
/// the bound and what to look at.
pub fn check(f: &Figures, tools: &BTreeMap<String, ToolSummary>) -> Vec<String> {
    let mut w = Vec::new();
    if f.added_mass_percent > ADDED_MASS_PERCENT_MAX {
        w.push(format!(
            "mass scaling added {:.0} % of the physical mass (bound {ADDED_MASS_PERCENT_MAX:.0} %): \
             check kinetic/internal, or lower solver.mass_scaling_dt",
            f.added_mass_percent
        ));
    }
    if f.kinetic_to_internal_max > KINETIC_TO_INTERNAL_MAX {
        w.push(format!(
            "kinetic/internal energy reached {:.3} while forming (bound {KINETIC_TO_INTERNAL_MAX}): \
             the run is not quasi-static; slow the tools or lower solver.mass_scaling_dt",
            f.kinetic_to_internal_max
        ));
    }
    if f.hourglass_to_internal_max > HOURGLASS_TO_INTERNAL_MAX {
        w.push(format!(
            "hourglass/internal energy reached {:.3} while forming (bound {HOURGLASS_TO_INTERNAL_MAX}): \
             refine the mesh or use blank.element = \"fully-integrated\"",
            f.hourglass_to_internal_max
        ));
    }
    if f.balance_error > BALANCE_ERROR_MAX {
        w.push(format!(
            "energy balance error {:.2e} (bound {BALANCE_ERROR_MAX}): energy is created or lost \
             unaccounted; check the time step and the contact penalty",
            f.balance_error
        ));
    }
    for (name, t) in tools {
        for (step, s) in &t.steps {
            let steady = s
                .force_prescribed
                .is_some_and(|p| p.min >= STEADY_FORCE_MIN_RATIO * p.max);
            if let Some(e) = s.delivered_error
                && steady
                && e.abs() > DELIVERED_FORCE_ERROR_MAX
            {
                w.push(format!(
                    "{name} delivered {:+.2} % of its prescribed force in step \"{step}\" \
                     (bound {:.0} %): a dashpot or a tool still accelerating",
                    100.0 * e,
                    100.0 * DELIVERED_FORCE_ERROR_MAX
                ));
            }
        }
    }
    w
}
