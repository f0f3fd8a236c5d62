//! Reference checks by registration: each scene `kind` that compares a run
//! with an analytic reference is a [`ReferenceCheck`] submitted to the
//! registry (`inventory`) from its own file in this folder. A new check is
//! one file here (and its reference in [`ensure_linked`]); nothing else
//! names it: the scene's `kind` is resolved through the registry
//! ([`crate::scene::kind::resolve`]), the recorder samples what the check
//! asks for, and `summary.json` and `formsim run`'s output take its figures.
//!
//! A check's file declares:
//!
//! - `name`, the scene's `kind`, and a one-line `summary`;
//! - `key`: its object in `summary.json` (and its table `[output.KEY]`,
//!   declared with the scene's keys in `crates/formsim/src/scene/schema.rs`
//!   `Output`, since the scene's tables deny unknown keys);
//! - `needs`: what it needs from the scene, checked when the scene is
//!   loaded, a one-line error naming the key;
//! - `start`: its [`Sampler`], what it samples during the run (a pulled
//!   end's reaction, [`PullMean`], and whatever else it reads);
//! - [`Sampler::figures`]: its value against the analytic reference, with μ
//!   the Coulomb coefficient of the scene's law ([`coulomb_mu`]; a law that
//!   has none gives no figures and a warning), and further figures of its
//!   own;
//! - `line`: the line `formsim run` prints (value, reference, deviation).
//!
//! `generic` and `square-cup` are not checks
//! ([`crate::scene::kind::PRESETS`]).

mod block;
mod capstan;
mod mu;
mod strip;

pub use crate::scene::kind::{Figures, ReferenceCheck, Sampler, reference_checks};
pub use mu::{ReferenceError, coulomb_mu};

use crate::scene::schema::PulledEnd;
use crate::scene::validate::dof_from_name;
use crate::scene::{LoadedScene, Model, SceneError};
use serde::ser::{Serialize, SerializeMap, Serializer};

/// Keep the registrations of this folder in the final binary (the linker
/// drops the `inventory` submissions of an object file nothing references).
/// Called by `formsim`'s `main` and by [`crate::run::run`]; a program that
/// loads scenes without running them calls it once first.
pub fn ensure_linked() -> usize {
    std::hint::black_box(block::anchor() + capstan::anchor() + strip::anchor())
}

/// A reference check's result in `summary.json`: `"KEY": {VALUE_KEY,
/// analytic, …}`.
#[derive(Debug, Clone)]
pub struct Reference {
    /// The check.
    pub check: &'static ReferenceCheck,
    /// Its figures.
    pub figures: Figures,
}

impl Reference {
    /// The line `formsim run` prints (without indent).
    pub fn line(&self) -> String {
        (self.check.line)(&self.figures)
    }
}

impl Serialize for Reference {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(1))?;
        map.serialize_entry(self.check.key, &FiguresJson(self))?;
        map.end()
    }
}

/// The figures' object: `{VALUE_KEY, analytic, …}`.
struct FiguresJson<'a>(&'a Reference);

impl Serialize for FiguresJson<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let f = &self.0.figures;
        let mut map = serializer.serialize_map(Some(2 + f.more.len()))?;
        map.serialize_entry(self.0.check.value_key, &f.value)?;
        map.serialize_entry("analytic", &f.analytic)?;
        for (name, v) in &f.more {
            map.serialize_entry(name, v)?;
        }
        map.end()
    }
}

/// The mean reaction of a pulled end along its DOF (N, absolute value),
/// over the samples from its `average_from` on.
#[derive(Debug, Clone)]
pub struct PullMean {
    set: String,
    axis: usize,
    from: f64,
    sum: f64,
    n: usize,
}

impl PullMean {
    /// Averaging the reaction of `end`.
    pub fn new(end: &PulledEnd<'_>) -> Self {
        Self {
            set: end.pull_set.to_string(),
            axis: dof_from_name(end.pull_dof).map_or(0, |d| d.axis()),
            from: end.average_from,
            sum: 0.0,
            n: 0,
        }
    }

    /// Add the reaction now if averaging has started; whether it has.
    ///
    /// # Errors
    /// The solver does not know the node set.
    pub fn sample(&mut self, loaded: &LoadedScene, model: &Model) -> Result<bool, SceneError> {
        if model.solver.time() < self.from {
            return Ok(false);
        }
        let (f, _) = model
            .solver
            .reaction(&self.set)
            .map_err(|e| loaded.key_error("output", e.to_string()))?;
        self.sum += f[self.axis].abs();
        self.n += 1;
        Ok(true)
    }

    /// Samples taken.
    pub fn samples(&self) -> usize {
        self.n
    }

    /// The mean (0 before the first sample).
    pub fn mean(&self) -> f64 {
        if self.n > 0 {
            self.sum / self.n as f64
        } else {
            0.0
        }
    }
}

/// The sampler of a check that reads only a pulled end: its value is the
/// mean reaction over `divisor`, its reference `analytic(μ)`.
pub(crate) struct PullOnly {
    pull: PullMean,
    divisor: f64,
    analytic: Box<dyn Fn(f64) -> f64>,
}

impl PullOnly {
    /// Averaging the reaction of `end`, divided by `divisor`, against `analytic(μ)`.
    pub(crate) fn boxed(
        end: &PulledEnd<'_>,
        divisor: f64,
        analytic: impl Fn(f64) -> f64 + 'static,
    ) -> Box<dyn Sampler> {
        Box::new(Self {
            pull: PullMean::new(end),
            divisor,
            analytic: Box::new(analytic),
        })
    }
}

impl Sampler for PullOnly {
    fn sample(&mut self, loaded: &LoadedScene, model: &Model) -> Result<(), SceneError> {
        self.pull.sample(loaded, model).map(|_| ())
    }

    fn sampled(&self) -> bool {
        self.pull.samples() > 0
    }

    fn figures(&self, mu: f64) -> Option<Figures> {
        Some(Figures {
            value: self.pull.mean() / self.divisor,
            analytic: (self.analytic)(mu),
            more: Vec::new(),
        })
    }
}

/// `Ok` when the scene has the check's table `[output.KEY]` (`present`),
/// else the one-line error at `output.KEY`.
pub(crate) fn needs_table(
    loaded: &LoadedScene,
    present: bool,
    kind: &str,
    key: &str,
) -> Result<(), SceneError> {
    if present {
        Ok(())
    } else {
        Err(loaded.key_error(
            &format!("output.{key}"),
            format!("a {kind} scene needs [output.{key}]"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::kind;

    /// The registry holds the three built-in checks, each name and key
    /// once, each with its one-line summary, and resolves them.
    #[test]
    fn the_registry_holds_the_three_checks() {
        ensure_linked();
        let names: Vec<&str> = reference_checks().iter().map(|c| c.name).collect();
        assert_eq!(names, ["block-on-plane", "capstan", "strip-draw"]);
        let keys: Vec<&str> = reference_checks().iter().map(|c| c.key).collect();
        assert_eq!(keys, ["block", "capstan", "strip"]);
        assert!(
            reference_checks()
                .iter()
                .all(|c| !c.summary.is_empty() && !c.summary.contains('\n'))
        );
        assert_eq!(
            kind::resolve("capstan").unwrap().map(|c| c.value_key),
            Some("tension_ratio")
        );
        assert!(kind::resolve("generic").unwrap().is_none());
        assert!(kind::resolve("square-cup").unwrap().is_none());
    }

    /// An unknown kind is refused when the scene is loaded, in one line
    /// naming the key and every kind there is.
    #[test]
    fn an_unknown_kind_is_refused_naming_the_registered_ones() {
        ensure_linked();
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenes/block-on-plane.toml");
        let e = crate::scene::load(&path, &["scene.kind=\"capstain\"".into()])
            .unwrap_err()
            .to_string();
        assert!(!e.contains('\n'), "{e}");
        assert!(
            e.contains("scene.kind") && e.contains("\"capstain\""),
            "{e}"
        );
        for name in [
            "generic",
            "square-cup",
            "block-on-plane",
            "capstan",
            "strip-draw",
        ] {
            assert!(e.contains(name), "{name} not in: {e}");
        }
    }

    /// Each check refuses a scene without its `[output.KEY]`, naming it.
    #[test]
    fn each_check_names_the_table_it_needs() {
        ensure_linked();
        let scenes = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
        for (scene, kind, key) in [
            ("block-on-plane", "capstan", "output.capstan"),
            ("block-on-plane", "strip-draw", "output.strip"),
            ("capstan", "block-on-plane", "output.block"),
        ] {
            let path = scenes.join(format!("{scene}.toml"));
            crate::scene::load(&path, &[]).unwrap();
            let e = crate::scene::load(&path, &[format!("scene.kind=\"{kind}\"")])
                .unwrap_err()
                .to_string();
            assert!(!e.contains('\n') && e.contains(key), "{kind}: {e}");
        }
    }

    /// A check's figures in `summary.json`: its value under its own name,
    /// the reference as `analytic`, then its further figures in order; the
    /// deviation is the printed line's.
    #[test]
    fn figures_serialise_under_the_check_key() {
        ensure_linked();
        let check = kind::reference_check("strip-draw").unwrap();
        let r = Reference {
            check,
            figures: Figures {
                value: 303.0,
                analytic: 300.0,
                more: vec![("holder_force", 999.5), ("mu", 0.15)],
            },
        };
        assert_eq!(
            serde_json::to_string(&r).unwrap(),
            r#"{"strip":{"draw_force":303.0,"analytic":300.0,"holder_force":999.5,"mu":0.15}}"#
        );
        assert!((r.figures.deviation_percent() - 1.0).abs() < 1e-12);
        assert_eq!(r.figures.get("mu"), Some(0.15));
        assert_eq!(r.figures.get("nope"), None);
    }
}
