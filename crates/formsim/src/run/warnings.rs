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
/// Largest share of the external work that is kinetic energy while forming,
/// for a quasi-static run: the usual 5 % guideline, written against the
/// work the tools and loads put into the blank rather than its internal
/// energy, so that it also measures runs whose work goes into friction
/// (a strip drawn between flat tools stores almost none of it).
pub const KINETIC_TO_WORK_MAX: f64 = 0.05;
/// Largest hourglass/internal energy ratio while forming (the usual 10 %
/// guideline for reduced-integration shells).
pub const HOURGLASS_TO_INTERNAL_MAX: f64 = 0.10;
/// The hourglass/internal and kinetic/internal ratios are sampled only while the internal energy is
/// at least this share of the external work: below it the blank's
/// deformation is not what the run is about (a plate sliding on a plane) and
/// a ratio over it is not a measure.
pub const INTERNAL_SHARE_MIN: f64 = 0.01;
/// Largest relative energy balance error at the end of a run.
pub const BALANCE_ERROR_MAX: f64 = 0.01;
/// Largest relative difference between the mean force a force-controlled tool
/// delivered over a press step and the one prescribed, less the force that
/// went into the tool's own acceleration (its momentum change over the step:
/// a holder carried up by a rising die delivers more while it speeds up, as
/// a real one does), checked in the steps
/// whose prescribed force is steady (its smallest value at least
/// [`STEADY_FORCE_MIN_RATIO`] of its largest) or follows a gas-spring curve
/// at full amplitude (it varies with the tool's travel, and the tool must
/// deliver it all along): while a force ramps up in time, the tool's
/// momentum and the damper take their share, as they should.
pub const DELIVERED_FORCE_ERROR_MAX: f64 = 0.01;
/// A press step's prescribed force counts as steady when its smallest value
/// is at least this fraction of its largest.
pub const STEADY_FORCE_MIN_RATIO: f64 = 0.9;

/// The kinetic energy's share of the external work, the quasi-static
/// measure of [`KINETIC_TO_WORK_MAX`] (0 before any work is done); with
/// selective mass scaling the added inertia's energy counts as kinetic.
pub fn kinetic_to_work(e: &fem_core::EnergyLedger) -> f64 {
    if e.external > 0.0 {
        (e.kinetic + e.kinetic_added) / e.external
    } else {
        0.0
    }
}

/// The figures the warnings read.
#[derive(Debug, Clone, Copy)]
pub struct Figures {
    /// Added mass at the end (% of the physical mass).
    pub added_mass_percent: f64,
    /// Largest kinetic energy / external work while forming.
    pub kinetic_to_work_max: f64,
    /// Whether the scene is dynamic by design (`scene.regime = "dynamic"`):
    /// the quasi-static check does not apply.
    pub dynamic: bool,
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
    if !f.dynamic && f.kinetic_to_work_max > KINETIC_TO_WORK_MAX {
        w.push(format!(
            "kinetic energy reached {:.3} of the external work while forming (bound {KINETIC_TO_WORK_MAX}): \
             the run is not quasi-static; slow the tools or lower solver.mass_scaling_dt \
             (or declare scene.regime = \"dynamic\" if it is dynamic by design)",
            f.kinetic_to_work_max
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
            let steady = s.follows_curve
                || s.force_prescribed
                    .is_some_and(|p| p.min >= STEADY_FORCE_MIN_RATIO * p.max);
            if let (Some(e), Some(held)) = (s.delivered_error, s.held_error)
                && steady
                && held.abs() > DELIVERED_FORCE_ERROR_MAX
            {
                w.push(format!(
                    "{name} delivered {:+.2} % of its prescribed force in step \"{step}\", \
                     {:+.2} % with its own acceleration taken out (bound {:.0} %): \
                     its dashpot takes a share, or it has not settled",
                    100.0 * e,
                    100.0 * held,
                    100.0 * DELIVERED_FORCE_ERROR_MAX
                ));
            }
        }
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    fn figures(kinetic_to_work_max: f64, dynamic: bool) -> Figures {
        Figures {
            added_mass_percent: 0.0,
            kinetic_to_work_max,
            dynamic,
            hourglass_to_internal_max: 0.0,
            balance_error: 0.0,
        }
    }

    /// The quasi-static check fires above 5 % of the work, names the
    /// figure and the key that exempts a dynamic scene, and does not apply
    /// to one.
    #[test]
    fn kinetic_share_of_the_work_warns_unless_the_scene_is_dynamic() {
        let none = BTreeMap::new();
        assert!(check(&figures(0.049, false), &none).is_empty());
        let w = check(&figures(0.051, false), &none);
        assert_eq!(w.len(), 1);
        assert!(w[0].contains("0.051 of the external work"), "{}", w[0]);
        assert!(w[0].contains("scene.regime"), "{}", w[0]);
        assert!(check(&figures(0.9, true), &none).is_empty());
    }

    /// The share is of the external work; no work, no ratio.
    #[test]
    fn kinetic_to_work_reads_the_ledger() {
        let mut e = fem_core::EnergyLedger::default();
        assert_eq!(kinetic_to_work(&e), 0.0);
        e.kinetic = 1.0;
        e.external = 40.0;
        assert_eq!(kinetic_to_work(&e), 0.025);
    }

    /// A steady holder step: delivering 5 % more than prescribed while its
    /// own acceleration accounts for it is no warning; the same 5 % with no
    /// acceleration (a dashpot) is.
    #[test]
    fn delivered_force_warns_on_what_the_tools_acceleration_does_not_explain() {
        use super::super::tools_report::{ForceStats, ToolStepSummary};
        let stats = |v: f64| ForceStats {
            mean: v,
            min: v,
            max: v,
        };
        let tools = |inertia: f64| {
            let step = ToolStepSummary {
                index: 0,
                duration_s: 1e-3,
                direction: [0.0, 0.0, -1.0],
                force_along: stats(1050.0),
                force_total: stats(1050.0),
                force_prescribed: Some(stats(1000.0)),
                delivered_error: Some(0.05),
                force_inertia: Some(inertia),
                held_error: Some((1050.0 + inertia) / 1000.0 - 1.0),
                travel: 0.0,
                work: 0.0,
                follows_curve: false,
            };
            BTreeMap::from([(
                "holder".to_string(),
                ToolSummary {
                    travel: 0.0,
                    work: 0.0,
                    steps: BTreeMap::from([("lift".to_string(), step)]),
                },
            )])
        };
        assert!(check(&figures(0.0, false), &tools(-50.0)).is_empty());
        let w = check(&figures(0.0, false), &tools(0.0));
        assert_eq!(w.len(), 1);
        assert!(w[0].contains("holder delivered +5.00 %"), "{}", w[0]);
    }

    /// A gas-spring step: its prescribed force climbs the curve (from 1000
    /// to 1500 N, not steady), and it is checked all the same; a ramp that
    /// climbs as much is not.
    #[test]
    fn a_gas_spring_step_is_checked_though_its_force_varies() {
        use super::super::tools_report::{ForceStats, ToolStepSummary};
        let tools = |follows_curve: bool, delivered: f64| {
            let step = ToolStepSummary {
                index: 0,
                duration_s: 1e-3,
                direction: [0.0, 0.0, 1.0],
                force_along: ForceStats {
                    mean: delivered,
                    min: 0.9 * delivered,
                    max: 1.1 * delivered,
                },
                force_total: ForceStats {
                    mean: delivered,
                    min: 0.9 * delivered,
                    max: 1.1 * delivered,
                },
                force_prescribed: Some(ForceStats {
                    mean: 1250.0,
                    min: 1000.0,
                    max: 1500.0,
                }),
                delivered_error: Some(delivered / 1250.0 - 1.0),
                force_inertia: Some(0.0),
                held_error: Some(delivered / 1250.0 - 1.0),
                travel: -40.0,
                work: 0.0,
                follows_curve,
            };
            BTreeMap::from([(
                "holder".to_string(),
                ToolSummary {
                    travel: -40.0,
                    work: 0.0,
                    steps: BTreeMap::from([("draw".to_string(), step)]),
                },
            )])
        };
        assert!(check(&figures(0.0, false), &tools(true, 1251.0)).is_empty());
        let w = check(&figures(0.0, false), &tools(true, 1200.0));
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].contains("holder delivered -4.00 %"), "{}", w[0]);
        assert!(check(&figures(0.0, false), &tools(false, 1200.0)).is_empty());
    }
}
