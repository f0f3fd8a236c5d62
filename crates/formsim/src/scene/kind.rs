//! The scene's `kind` (`[scene] kind`): one of the built-in [`PRESETS`]
//! (`generic`, `square-cup`) or a [`ReferenceCheck`] from the registry
//! (`inventory`), which compares a run with an analytic reference.
//!
//! This module holds what a reference check is and the registry's look-ups
//! (a check's `[output.KEY]` table is resolved by [`super::check_table`]);
//! the checks themselves are registered from their own files in
//! `crates/formsim/src/run/reference_checks/`, where
//! `run::reference_checks::ensure_linked` keeps them in a binary. [`resolve`]
//! reads the registry as it is linked: a program that loads scenes calls
//! that `ensure_linked` once first (`formsim`'s `main` does, and so does
//! `run::run`).

use super::check_table::{CheckTable, TableKey};
use super::{LoadedScene, Model, SceneError};

/// A kind that is not a reference check.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Preset {
    /// The name a scene gives as `kind`.
    pub name: &'static str,
    /// One line: what the kind means.
    pub summary: &'static str,
}

/// The kinds that are not reference checks. A square cup's sections and
/// draw-in come from `[[output.sections]]` and `[[output.draw_in]]`, which
/// any scene may give.
pub const PRESETS: [Preset; 2] = [
    Preset {
        name: "generic",
        summary: "no benchmark-specific results (the default)",
    },
    Preset {
        name: "square-cup",
        summary: "NUMISHEET'93 square cup: its sections and draw-in come from [[output.sections]] and [[output.draw_in]]",
    },
];

/// A registered reference check: a scene `kind` whose run is compared with
/// an analytic reference. Its file declares its table `[output.KEY]` (the
/// keys, their units, defaults and ranges), what else it needs from the
/// scene, what it samples during the run and how it turns that into its
/// [`Figures`] (`summary.json`'s `KEY{…}` and the line `formsim run`
/// prints).
#[derive(Debug)]
pub struct ReferenceCheck {
    /// The name a scene gives as `kind`.
    pub name: &'static str,
    /// One line: what it measures against what.
    pub summary: &'static str,
    /// Its table, `[output.KEY]`, and its key in `summary.json`.
    pub key: &'static str,
    /// The keys of its table: a scene's table is resolved against them when
    /// it is read (an unknown key, a missing required one, a value of the
    /// wrong type or out of range is one line at that key), and the check
    /// reads the resolved [`CheckTable`].
    pub keys: &'static [TableKey],
    /// The name of [`Figures::value`] in `summary.json` (the reference is
    /// `analytic`).
    pub value_key: &'static str,
    /// What else it needs from a scene of its kind, given its table, before
    /// anything is built: a one-line error naming the key
    /// ([`needs_nothing_else`] when the table's keys say it all).
    pub needs: fn(&LoadedScene, &CheckTable) -> Result<(), SceneError>,
    /// What it samples: its [`Sampler`] for a run of `model`, given its
    /// table (`None` when the model lacks what it reads).
    pub start: fn(&LoadedScene, &CheckTable, &Model) -> Option<Box<dyn Sampler>>,
    /// The line `formsim run` prints of its figures (without indent).
    pub line: fn(&Figures) -> String,
}

impl ReferenceCheck {
    /// Its [`Sampler`] for a run of `model`: [`ReferenceCheck::start`] with
    /// the scene's table (`None` without one).
    pub fn sampler(&self, loaded: &LoadedScene, model: &Model) -> Option<Box<dyn Sampler>> {
        let table = loaded.scene.output.checks.get(self.key)?;
        (self.start)(loaded, table, model)
    }
}

/// [`ReferenceCheck::needs`] of a check whose table's keys say all it needs.
///
/// # Errors
/// None.
pub fn needs_nothing_else(_: &LoadedScene, _: &CheckTable) -> Result<(), SceneError> {
    Ok(())
}

inventory::collect!(ReferenceCheck);

/// What a reference check samples during a run, and the figures it makes of
/// it.
pub trait Sampler {
    /// Sample `model` as it is now (called once before the first step and
    /// after every step).
    ///
    /// # Errors
    /// A quantity the model does not have (a node set the solver does not
    /// know), naming the key.
    fn sample(&mut self, loaded: &LoadedScene, model: &Model) -> Result<(), SceneError>;

    /// Whether anything has been sampled yet (sampling may start late).
    fn sampled(&self) -> bool;

    /// The figures of what was sampled so far, with `mu` the Coulomb
    /// coefficient of the scene's contact law. A mean over no sample is 0:
    /// before the run, the figures have the shape they will have (what
    /// `run::probe` checks quantity names against). `None` when the model
    /// lacks what the check reads.
    fn figures(&self, mu: f64) -> Option<Figures>;
}

/// What a reference check made of a run: its value against the analytic
/// reference, and further figures of its own.
#[derive(Debug, Clone, PartialEq)]
pub struct Figures {
    /// The measured figure (`summary.json`: [`ReferenceCheck::value_key`]).
    pub value: f64,
    /// The analytic reference (`summary.json`: `analytic`).
    pub analytic: f64,
    /// Further figures, in `summary.json` under their names.
    pub more: Vec<(&'static str, f64)>,
}

impl Figures {
    /// `100 (value / analytic − 1)`: the deviation from the reference (%).
    pub fn deviation_percent(&self) -> f64 {
        100.0 * (self.value / self.analytic - 1.0)
    }

    /// The further figure `name`.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.more.iter().find(|(n, _)| *n == name).map(|(_, v)| *v)
    }
}

/// Every registered reference check, sorted by name.
pub fn reference_checks() -> Vec<&'static ReferenceCheck> {
    let mut v: Vec<_> = inventory::iter::<ReferenceCheck>.into_iter().collect();
    v.sort_by_key(|c| c.name);
    v
}

/// The reference check named `name`.
pub fn reference_check(name: &str) -> Option<&'static ReferenceCheck> {
    inventory::iter::<ReferenceCheck>
        .into_iter()
        .find(|c| c.name == name)
}

/// `generic, square-cup; reference checks: a, b, c`, for messages.
pub fn names() -> String {
    let presets: Vec<&str> = PRESETS.iter().map(|p| p.name).collect();
    let checks: Vec<&str> = reference_checks().iter().map(|c| c.name).collect();
    format!(
        "{}; reference checks: {}",
        presets.join(", "),
        if checks.is_empty() {
            "none registered".to_string()
        } else {
            checks.join(", ")
        }
    )
}

/// The scene kind `name`: a preset (`Ok(None)`) or a reference check.
///
/// # Errors
/// Neither: one line naming the kinds there are.
pub fn resolve(name: &str) -> Result<Option<&'static ReferenceCheck>, String> {
    if PRESETS.iter().any(|p| p.name == name) {
        return Ok(None);
    }
    reference_check(name)
        .map(Some)
        .ok_or_else(|| format!("\"{name}\" is not a scene kind (kinds: {})", names()))
}
