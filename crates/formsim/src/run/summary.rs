//! `summary.json`: the figures of one run (scene units).

use super::post::{SectionSummary, Snapshot};
use super::reference_checks::{ReferenceCheck, Sampler};
use super::tools_report::{self, PairSummary, ToolSummary};
use super::warnings::{self, Figures};
use crate::formability::{FormabilityReport, FormabilityState};
use crate::scene::schema::Regime;
use crate::scene::{LoadedScene, Model};
use fem_core::SetupReport;
use serde::Serialize;
use std::collections::BTreeMap;

/// Energies at the end of the run (mJ = N·mm), balance error relative (-).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct EnergySummary {
    /// Internal (elastic + plastic, hourglass excluded).
    pub internal: f64,
    /// Kinetic.
    pub kinetic: f64,
    /// Energy the inertia of selective mass scaling took up (0 without).
    pub kinetic_added: f64,
    /// Hourglass.
    pub hourglass: f64,
    /// Contact (penalty) energy.
    pub contact: f64,
    /// Frictional dissipation.
    pub friction: f64,
    /// Drawbead dissipation (0 without drawbeads).
    pub bead: f64,
    /// Plastic dissipation (part of internal).
    pub plastic: f64,
    /// Work of the tools, loads and prescribed motions (and mass added in the run).
    pub external_work: f64,
    /// `|E_total − E_total(0) − W_ext| / max(...)`, see fem-core's energy ledger.
    pub balance_error_rel: f64,
}

/// The state at one report stroke.
#[derive(Debug, Clone, Serialize)]
pub struct StateSummary {
    /// Section extremes.
    pub sections: BTreeMap<String, SectionSummary>,
    /// Draw-in (mm).
    pub draw_in: BTreeMap<String, f64>,
    /// Largest thinning (-).
    pub thinning_max: f64,
    /// Punch force, full-model equivalent (N).
    pub punch_force: f64,
    /// Stroke reached (mm).
    pub stroke: f64,
    /// `friction / (plastic + friction)` at this state (-).
    pub friction_energy_share: f64,
    /// `friction / internal` at this state (-).
    pub friction_to_internal: f64,
    /// What each tool did up to this state (the current press step so far).
    pub tools: BTreeMap<String, ToolSummary>,
    /// The forming limit diagram at this state (with `[formability]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub formability: Option<FormabilityState>,
}

impl From<&Snapshot> for StateSummary {
    fn from(s: &Snapshot) -> Self {
        Self {
            sections: s.sections.clone(),
            draw_in: s.draw_in.clone(),
            thinning_max: s.thinning_max,
            punch_force: s.punch_force,
            stroke: s.stroke,
            friction_energy_share: friction_energy_share(&s.energy),
            friction_to_internal: friction_to_internal(&s.energy),
            tools: s.tools.clone(),
            formability: s.formability.clone(),
        }
    }
}

/// `friction / (plastic + friction)` (-), 0 before either has grown.
pub fn friction_energy_share(e: &fem_core::EnergyLedger) -> f64 {
    if e.plastic + e.friction > 0.0 {
        e.friction / (e.plastic + e.friction)
    } else {
        0.0
    }
}

/// `friction / internal` (-): the frictional dissipation against the
/// blank's internal energy (elastic + plastic); 0 while internal is 0.
pub fn friction_to_internal(e: &fem_core::EnergyLedger) -> f64 {
    if e.internal > 0.0 {
        e.friction / e.internal
    } else {
        0.0
    }
}

/// A user material in `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct MaterialPlugin {
    /// The plugin material's own name.
    pub name: String,
    /// The library, as the scene gives it (relative to the scene).
    pub path: String,
    /// The parameters the scene sets (the rest are the plugin's defaults or
    /// the sheet's elastic constants).
    pub parameters: std::collections::BTreeMap<String, f64>,
}

/// A state file of forming in stages (docs/stages.md).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StateRecord {
    /// Its path.
    pub path: String,
    /// FNV-1a 64 of its bytes (16 hex digits).
    pub checksum: String,
}

/// `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// Scene name.
    pub scene: String,
    /// Scene description (`[scene] description`).
    pub description: String,
    /// Friction law (of the first pair).
    pub law: String,
    /// Kinematic formulation (of the first pair).
    pub formulation: String,
    /// Shell element.
    pub element: String,
    /// Material model (`blank.material.model`, resolved).
    pub material: String,
    /// The user material of the `plugin` model: its name, library and parameters.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub material_plugin: Option<MaterialPlugin>,
    /// Number of shells.
    pub elements: usize,
    /// Number of nodes.
    pub nodes: usize,
    /// Explicit steps taken.
    pub increments: u64,
    /// Wall time of the time-step loop (s).
    pub wall_time_s: f64,
    /// Where the wall time went, per stage (s).
    pub timing: super::timing::Timing,
    /// `elements × increments / wall_time_s`.
    pub element_cycles_per_s: f64,
    /// Threads of the rayon pool.
    pub threads: usize,
    /// Simulated time (s).
    pub simulated_time_s: f64,
    /// First time step (s).
    pub dt_initial_s: f64,
    /// Mass added by mass scaling, % of the physical mass (at the end).
    pub added_mass_percent: f64,
    /// Energies at the end.
    pub energy: EnergySummary,
    /// `friction / (plastic + friction)` (-).
    pub friction_energy_share: f64,
    /// `friction / internal` (-).
    pub friction_to_internal: f64,
    /// Largest kinetic/internal ratio once forming has started, over the
    /// samples whose internal energy is at least 1 % of the external work
    /// (0 when none is) (-).
    pub kinetic_to_internal_max: f64,
    /// Largest kinetic energy / external work once forming has started (-):
    /// the quasi-static measure the warning reads.
    pub kinetic_to_work_max: f64,
    /// `"quasi-static"` (the kinetic-energy check applies) or `"dynamic"`
    /// (`scene.regime`).
    pub regime: String,
    /// Largest hourglass/internal ratio once forming has started, over the
    /// same samples as `kinetic_to_internal_max` (-).
    pub hourglass_to_internal_max: f64,
    /// Largest thinning at the end (-).
    pub thinning_max: f64,
    /// Largest punch force over the run, full-model equivalent (N).
    pub punch_force_max: f64,
    /// Final stroke (mm).
    pub stroke: f64,
    /// Section extremes at the end.
    pub sections: BTreeMap<String, SectionSummary>,
    /// Draw-in at the end (mm).
    pub draw_in: BTreeMap<String, f64>,
    /// States at the report strokes (keys: the stroke in mm).
    pub states: BTreeMap<String, StateSummary>,
    /// The figures of the scene's reference check (`capstan`, `block`,
    /// `strip`: [`super::reference_checks`]), as `"KEY": {…}`.
    #[serde(flatten)]
    pub reference: Option<super::reference_checks::Reference>,
    /// What each tool did (forces on the model, per press step).
    pub tools: BTreeMap<String, ToolSummary>,
    /// What each contact pair did.
    pub pairs: BTreeMap<String, PairSummary>,
    /// What each drawbead did (absent without drawbeads).
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub beads: BTreeMap<String, super::tools_report::BeadSummary>,
    /// Whether a law's clamp (WH's `μ_min`) was active at some step.
    pub friction_clamp_active: bool,
    /// Bounds the run exceeded (docs/scene-format.md, "Warnings"), one line each.
    pub warnings: Vec<String>,
    /// Every setting of the run as resolved (defaults filled in, overrides
    /// applied): the scene as formsim read it.
    pub settings: serde_json::Value,
    /// `--set` overrides applied.
    pub overrides: Vec<String>,
    /// The state the blank started from (`blank.initial_state`), when given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub initial_state: Option<StateRecord>,
    /// The state this run saved (`--save-state`), when asked.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub saved_state: Option<StateRecord>,
    /// What the springback step did, when the scene has one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub springback: Option<super::springback::SpringbackSummary>,
    /// What selective mass scaling did, when the run scales so.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub selective_mass: Option<SelectiveSummary>,
    /// The shape measures of each `[[output.profiles]]` line.
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub profiles: BTreeMap<String, super::profile::ProfileSummary>,
    /// The forming limit diagram at the end (with `[formability]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub formability: Option<FormabilityReport>,
    /// How the run ended: `completed`, `failed` or `interrupted`.
    pub status: super::Status,
    /// Why a run that did not complete stopped, one line (the first
    /// non-finite value with its quantity, node or element, step and time;
    /// the solver's message; the file that could not be written; where an
    /// interrupt stopped it). Absent for a completed run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cause: Option<String>,
}

/// What [`Summary::new`] reads.
pub struct Inputs<'a> {
    /// The scene.
    pub loaded: &'a LoadedScene,
    /// The model after the run.
    pub model: &'a Model,
    /// Set-up report.
    pub setup: &'a SetupReport,
    /// Wall time of the loop (s).
    pub wall: f64,
    /// Final snapshot.
    pub last: &'a Snapshot,
    /// Report-stroke snapshots.
    pub states: &'a [(f64, Snapshot)],
    /// Largest punch force (N).
    pub force_max: f64,
    /// Largest K/I while forming.
    pub ki_max: f64,
    /// Largest kinetic energy / external work while forming.
    pub kw_max: f64,
    /// Warnings of the set-up (mesh resolution, mass added at set-up).
    pub setup_warnings: Vec<String>,
    /// Largest hourglass/internal while forming.
    pub hg_max: f64,
    /// The scene's reference check and what it sampled.
    pub reference: Option<(&'static ReferenceCheck, &'a dyn Sampler)>,
    /// Whether a clamp was active.
    pub clamp_seen: bool,
    /// Why the run stopped early.
    pub stop: Option<&'a super::Stop>,
    /// First time step (s).
    pub dt0: f64,
    /// Seconds per stage.
    pub timing: super::timing::Timing,
    /// What the springback step did, when the scene has one.
    pub springback: Option<super::springback::SpringbackSummary>,
    /// The `[[output.profiles]]` lines, measured.
    pub profiles: &'a [super::profile::Measured],
}

/// The stroke as a key: `15` for 15.0, `12.5` for 12.5.
pub fn stroke_key(r: f64) -> String {
    if (r - r.round()).abs() < 1e-9 {
        format!("{}", r.round() as i64)
    } else {
        format!("{r}")
    }
}

impl Summary {
    /// Assemble the summary.
    pub fn new(i: Inputs<'_>) -> Self {
        let scene = &i.loaded.scene;
        let e = i.model.solver.ledger();
        let elements = i.model.mesh.quads.len();
        let increments = i.model.solver.steps();
        let (_, added_percent) = i.model.solver.added_mass();
        let mut notes = Vec::new();
        // μ is read from the law once the check has sampled something; a
        // law without a Coulomb coefficient gives no figures, and a note.
        let reference = i
            .reference
            .filter(|(_, sampler)| sampler.sampled())
            .and_then(|(check, sampler)| {
                let mu = super::reference_checks::coulomb_mu(i.loaded)
                    .map_err(|why| notes.push(format!("no analytic reference: {why}")))
                    .ok()?;
                let figures = sampler.figures(mu)?;
                Some(super::reference_checks::Reference { check, figures })
            });
        let tools = tools_report::tools(i.model);
        let mut warnings = i.setup_warnings.clone();
        warnings.extend(warnings::check(
            &Figures {
                added_mass_percent: added_percent,
                kinetic_to_work_max: i.kw_max,
                dynamic: scene.scene.regime == Regime::Dynamic,
                hourglass_to_internal_max: i.hg_max,
                balance_error: e.balance_error,
            },
            &tools,
        ));
        warnings.append(&mut notes);
        let selective_mass = i
            .model
            .solver
            .selective_stats()
            .map(|s| SelectiveSummary::new(&s, i.setup.physical_mass));
        if let Some(s) = selective_mass.as_ref().filter(|s| s.unconverged > 0) {
            warnings.push(format!(
                "selective mass scaling: {} of {} mass solves stopped at {} iterations above \
                 solver.mass_scaling_tolerance: raise the tolerance or lower solver.mass_scaling_dt",
                s.unconverged,
                s.solves,
                fem_core::solver::SELECTIVE_MAX_ITERATIONS
            ));
        }
        let springback = i.springback;
        if let Some(b) = springback.as_ref().filter(|b| !b.settled) {
            warnings.push(format!(
                "springback: not at rest after {:.2e} s (residual {:.2e} N, {:.1e} of the {:.2e} N when the tools let go, tolerance {:.0e}): the shape is not the springback shape; give the step a longer duration",
                b.duration_s,
                b.residual_n,
                b.residual_n / b.residual_start_n.max(f64::MIN_POSITIVE),
                b.residual_start_n,
                b.tolerance
            ));
        }
        for m in i.profiles {
            if let Err(why) = &m.segments {
                warnings.push(format!(
                    "profile {}: no shape measures: {why}; move output.profiles' web_to, flange_from or shoulder_clear",
                    m.name
                ));
            }
        }
        let profiles = i
            .profiles
            .iter()
            .filter_map(|m| Some((m.name.clone(), m.summary()?)))
            .collect();
        Summary {
            scene: scene.scene.name.clone(),
            description: scene.scene.description.clone(),
            law: i.model.law.clone(),
            formulation: i.model.formulation.clone(),
            element: scene.blank.element.clone(),
            material: i.model.shells.material.to_string(),
            material_plugin: i.model.shells.plugin.map(|name| MaterialPlugin {
                name: name.to_string(),
                path: scene.blank.material.plugin.clone().unwrap_or_default(),
                parameters: scene.blank.material.parameters.clone(),
            }),
            elements,
            nodes: i.model.mesh.nodes.len(),
            increments,
            wall_time_s: i.wall,
            timing: i.timing,
            element_cycles_per_s: if i.wall > 0.0 {
                elements as f64 * increments as f64 / i.wall
            } else {
                0.0
            },
            threads: rayon::current_num_threads(),
            simulated_time_s: i.model.solver.time(),
            dt_initial_s: i.dt0,
            added_mass_percent: added_percent,
            energy: EnergySummary {
                internal: e.internal,
                kinetic: e.kinetic,
                kinetic_added: e.kinetic_added,
                hourglass: e.hourglass,
                contact: e.contact,
                friction: e.friction,
                bead: e.bead,
                plastic: e.plastic,
                external_work: e.external,
                balance_error_rel: e.balance_error,
            },
            friction_energy_share: friction_energy_share(e),
            friction_to_internal: friction_to_internal(e),
            kinetic_to_internal_max: i.ki_max,
            kinetic_to_work_max: i.kw_max,
            regime: scene.scene.regime.as_str().to_string(),
            hourglass_to_internal_max: i.hg_max,
            thinning_max: i.last.thinning_max,
            punch_force_max: i.force_max,
            stroke: i.last.stroke,
            sections: i.last.sections.clone(),
            draw_in: i.last.draw_in.clone(),
            states: i
                .states
                .iter()
                .map(|(r, s)| (stroke_key(*r), StateSummary::from(s)))
                .collect(),
            reference,
            tools,
            pairs: tools_report::pairs(i.model),
            beads: tools_report::beads(i.model),
            friction_clamp_active: i.clamp_seen,
            warnings,
            settings: settings(scene),
            overrides: i.loaded.overrides.clone(),
            initial_state: None,
            saved_state: None,
            springback,
            selective_mass,
            profiles,
            formability: i
                .model
                .formability
                .as_ref()
                .zip(i.last.formability.as_ref())
                .map(|(f, end)| FormabilityReport {
                    curve: f.summary(),
                    end: end.clone(),
                }),
            status: i.stop.map_or(super::Status::Completed, |s| s.status),
            cause: i.stop.map(|s| s.cause.clone()),
        }
    }
}

/// `summary.json` `selective_mass`: the added inertia and its mass solves.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct SelectiveSummary {
    /// Translational mass the deformation modes carry on top, `Σ 4 β_e m_e`,
    /// as % of the physical mass (at the end).
    pub added_inertia_percent: f64,
    /// Mass solves (one a step).
    pub solves: u64,
    /// Mean conjugate-gradient iterations per solve.
    pub iterations_mean: f64,
    /// The most iterations one solve took.
    pub iterations_max: u32,
    /// Solves stopped at the iteration cap above the tolerance.
    pub unconverged: u64,
    /// Seconds in the solves (part of `timing`'s integration).
    pub seconds: f64,
}

impl SelectiveSummary {
    fn new(s: &fem_core::SelectiveStats, physical_mass: f64) -> Self {
        Self {
            added_inertia_percent: 100.0 * s.added_mass / physical_mass.max(f64::MIN_POSITIVE),
            solves: s.solves,
            iterations_mean: s.iterations as f64 / (s.solves.max(1) as f64),
            iterations_max: s.max_iterations,
            unconverged: s.unconverged,
            seconds: s.seconds,
        }
    }
}

impl Summary {
    /// The figures of the reference check whose `summary.json` key is `key`
    /// (`capstan`, `block`, `strip`), if the run has them.
    pub fn figures(&self, key: &str) -> Option<&super::reference_checks::Figures> {
        self.reference
            .as_ref()
            .filter(|r| r.check.key == key)
            .map(|r| &r.figures)
    }
}

/// The resolved scene as JSON (through TOML, which leaves out unset options).
fn settings(scene: &crate::scene::Scene) -> serde_json::Value {
    crate::scene::resolved::to_toml(scene)
        .map_err(|e| e.to_string())
        .and_then(|v| serde_json::to_value(v).map_err(|e| e.to_string()))
        .unwrap_or_else(|e| serde_json::Value::String(format!("not serialisable: {e}")))
}
