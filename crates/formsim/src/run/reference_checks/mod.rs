//! Reference checks by registration: each scene `kind` that compares a run
//! with an analytic reference is a [`ReferenceCheck`] submitted to the
//! registry (`inventory`) from its own file in this folder. A new check is
//! one file here (and its reference in [`ensure_linked`]); nothing else
//! names it: the scene's `kind` is resolved through the registry
//! ([`crate::scene::kind::resolve`]), its table `[output.KEY]` is resolved
//! against the keys it declares ([`crate::scene::check_table`]), the
//! recorder samples what the check asks for, and `summary.json` and
//! `formsim run`'s output take its figures.
//!
//! A check's file declares:
//!
//! - `name`, the scene's `kind`, and a one-line `summary`;
//! - `key`: its table `[output.KEY]` and its object in `summary.json`;
//! - `keys`: its table's keys ([`TableKey`]: a number with its unit,
//!   default, range and doc, or a name of a node set, tool or DOF); the
//!   pulled end's are here ([`PULL_SET`], [`PULL_DOF`], [`AVERAGE_FROM`]);
//! - `needs`: what else it needs from a scene of its kind, given its
//!   resolved table, checked when the scene is loaded, a one-line error
//!   naming the key ([`crate::scene::kind::needs_nothing_else`] when the
//!   keys say it all);
//! - `start`: its [`Sampler`], what it samples during the run (a pulled
//!   end's reaction, [`PullMean`], and whatever else it reads), made from
//!   its resolved table ([`CheckTable`]);
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

pub use crate::scene::check_table::{CheckTable, NameSpec, TableKey};
pub use crate::scene::kind::{Figures, ReferenceCheck, Sampler, reference_checks};
pub use mu::{ReferenceError, coulomb_mu};

use crate::scene::validate::dof_from_name;
use crate::scene::{LoadedScene, Model, SceneError};
use plugins_api::ParamSpec;
use serde::ser::{Serialize, SerializeMap, Serializer};

/// The node set pulled: `pull_set` of a check's table.
pub const PULL_SET: TableKey = TableKey::Name(NameSpec::required(
    "pull_set",
    "node set",
    "the node set pulled (a prescribed motion): its mean reaction along pull_dof is the measured force",
));

/// The DOF it is pulled along: `pull_dof` of a check's table (required;
/// `TableKey::Name(PULL_DOF_SPEC.or("ux"))` gives it a default).
pub const PULL_DOF: TableKey = TableKey::Name(PULL_DOF_SPEC);

/// [`PULL_DOF`]'s spec.
pub const PULL_DOF_SPEC: NameSpec =
    NameSpec::required("pull_dof", "DOF", "the DOF along which pull_set is pulled")
        .one_of(&["ux", "uy", "uz"]);

/// The start of the mean: `average_from` of a check's table.
pub const AVERAGE_FROM: TableKey = TableKey::Number(ParamSpec::required(
    "average_from",
    "s",
    0.0,
    f64::INFINITY,
    "the reaction is averaged from this time on (steady sliding)",
));

/// The pulled end of a check's table: [`PULL_SET`], [`PULL_DOF`] and
/// [`AVERAGE_FROM`].
#[derive(Debug, Clone, Copy)]
pub struct PulledEnd<'a> {
    /// The node set pulled.
    pub pull_set: &'a str,
    /// The DOF it is pulled along (`ux`, `uy`, `uz`).
    pub pull_dof: &'a str,
    /// Averaging starts at this time (s).
    pub average_from: f64,
}

impl<'a> PulledEnd<'a> {
    /// The pulled end of `table` (`None` when its check does not declare
    /// the three keys).
    pub fn of(table: &'a CheckTable) -> Option<Self> {
        Some(Self {
            pull_set: table.name(PULL_SET.key())?,
            pull_dof: table.name(PULL_DOF.key())?,
            average_from: table.number(AVERAGE_FROM.key())?,
        })
    }
}

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::kind;
    use crate::scene::schema::Output;

    fn scenes() -> std::path::PathBuf {
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
    }

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

    /// Each check declares its table's keys, each once, with a unit and one
    /// line of doc; no table is one of `[output]`'s own keys.
    #[test]
    fn each_check_declares_its_keys() {
        ensure_linked();
        for c in reference_checks() {
            assert!(!c.keys.is_empty(), "{}", c.name);
            assert!(!Output::OWN_KEYS.contains(&c.key), "{}", c.name);
            for (i, k) in c.keys.iter().enumerate() {
                assert!(
                    !k.unit().is_empty() && !k.doc().is_empty() && !k.doc().contains('\n'),
                    "{}.{}",
                    c.key,
                    k.key()
                );
                assert!(
                    c.keys[..i].iter().all(|e| e.key() != k.key()),
                    "{}.{} twice",
                    c.key,
                    k.key()
                );
            }
        }
        let capstan: Vec<&str> = kind::reference_check("capstan")
            .unwrap()
            .keys
            .iter()
            .map(|k| k.key())
            .collect();
        assert_eq!(
            capstan,
            [
                "pull_set",
                "pull_dof",
                "hold_force",
                "angle_deg",
                "average_from"
            ]
        );
    }

    /// A table in `[output]` that no check reads is refused in one line
    /// naming it and the tables of the registered checks.
    #[test]
    fn a_table_no_check_reads_is_refused() {
        ensure_linked();
        let path = scenes().join("block-on-plane.toml");
        let e = crate::scene::load(&path, &["output.blok.pull_set=\"all\"".into()])
            .unwrap_err()
            .to_string();
        assert!(!e.contains('\n'), "{e}");
        assert!(
            e.contains("output.blok: no registered reference check reads [output.blok]"),
            "{e}"
        );
        for table in [
            "[output.block] of block-on-plane",
            "[output.capstan] of capstan",
            "[output.strip] of strip-draw",
        ] {
            assert!(e.contains(table), "{table} not in: {e}");
        }
        // A check's key that is not a table is named as such.
        let e = crate::scene::load(&path, &["output.capstan=3".into()])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("output.capstan: 3 (an integer): expected a table { pull_set,"),
            "{e}"
        );
    }

    /// A check's table is resolved against its keys when the scene is read:
    /// an unknown key names the table and the key, at its line in the file;
    /// a mistyped value names the key and the unit; a value out of range
    /// names the value and the range; defaults fill in.
    #[test]
    fn a_check_table_is_resolved_against_its_keys() {
        ensure_linked();
        let path = scenes().join("block-on-plane.toml");
        let text = std::fs::read_to_string(&path).unwrap();
        let line = 1 + text
            .lines()
            .position(|l| l.starts_with("block = {"))
            .unwrap();
        let typo = text.replace("normal_force = 100.0", "normal_forse = 100.0");
        assert_ne!(typo, text, "the block's table changed");
        let e = crate::scene::parse(&typo, &path, &[])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&format!(
                ":{line}: output.block.normal_forse: unknown key in [output.block] (its keys: pull_set, pull_dof, normal_force, average_from)"
            )),
            "{e}"
        );
        for (set, says) in [
            (
                "output.block.normal_force=\"heavy\"",
                "output.block.normal_force: \"heavy\" (a string): expected a number in N",
            ),
            (
                "output.block.normal_force=-5",
                "output.block.normal_force: -5 N: must be finite and > 0",
            ),
            (
                "output.block.pull_set=3",
                "output.block.pull_set: 3 (an integer): expected a string, the node set's name",
            ),
            (
                "output.block.pull_dof=\"rz\"",
                "output.block.pull_dof: \"rz\": must be ux, uy or uz",
            ),
            (
                "output.block.pull_dof=",
                "output.block.pull_dof: missing from [output.block]: pull_dof (DOF)",
            ),
            (
                "output.block.average_from=-1e-3",
                "output.block.average_from: -0.001 s: must be finite and >= 0",
            ),
        ] {
            let e = crate::scene::load(&path, &[set.to_string()])
                .unwrap_err()
                .to_string();
            assert!(e.contains(says) && !e.contains('\n'), "{set}: {e}");
        }
        let loaded = crate::scene::load(
            &scenes().join("capstan.toml"),
            &["output.capstan.pull_dof=".into()],
        )
        .unwrap();
        let table = &loaded.scene.output.checks["capstan"];
        assert_eq!(table.name("pull_dof"), Some("ux"));
        assert_eq!(table.number("hold_force"), Some(200.0));
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
