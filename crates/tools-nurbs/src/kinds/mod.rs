//! Tool kinds by registration: each `kind` a scene's `[tools.NAME]` table
//! may name is a [`ToolKind`] submitted to the registry (`inventory`) from
//! its own file in this folder. A new kind is one file here, with its
//! declared keys ([`ToolKey`]: name, unit, default, range, doc), its builder
//! and its `inventory::submit!`; nothing else names it ([`crate::spec`]
//! looks every kind up here, `formsim tools kinds` lists them).
//!
//! Every table takes `kind`, `origin = [x, y, z]` (mm) and `facing`; the
//! rest of its keys go to the kind's builder as [`Request::table`], checked
//! against its declaration first: a key it does not declare, or a required
//! one missing, is an error naming the tool, the key and the declared keys.

mod cylinder;
mod mesh;
mod plane;
mod s_rail;
mod square_cup;

use crate::builders::{Facing, Placement};
use crate::error::NurbsError;
use crate::spec::Tool;
use serde::de::DeserializeOwned;
use std::path::Path;

/// What a kind's builder receives.
#[derive(Debug)]
pub struct Request<'a> {
    /// The tool's name (`NAME` of `[tools.NAME]`).
    pub name: &'a str,
    /// The kind asked for.
    pub kind: &'a str,
    /// The table's keys but `kind`, `origin` and `facing`.
    pub table: toml::Table,
    /// Directory against which relative file paths resolve.
    pub base: &'a Path,
    /// Origin and facing.
    pub place: Placement,
    /// The kind's declared keys ([`ToolKind::keys`]).
    pub keys: &'static [ToolKey],
}

impl Request<'_> {
    /// Remove and read `key`, if present.
    ///
    /// # Errors
    /// The value does not have the expected type.
    pub fn take<T: DeserializeOwned>(&mut self, key: &str) -> Result<Option<T>, NurbsError> {
        crate::spec::take(self.name, &mut self.table, key)
    }

    /// Read the remaining keys as the kind's parameters (unknown keys are
    /// errors when `T` denies them).
    ///
    /// # Errors
    /// A missing, unknown or mistyped key, naming the tool and the kind.
    pub fn params<T: DeserializeOwned>(self) -> Result<T, NurbsError> {
        crate::spec::params(self.name, self.kind, self.table)
    }
}

/// A key a tool kind reads from its table.
#[derive(Debug, Clone, Copy)]
pub struct ToolKey {
    /// The key (`radius`).
    pub name: &'static str,
    /// Its unit (`mm`, `degrees`, `-`; `path` or `text` for words).
    pub unit: &'static str,
    /// Its default as written in a scene; `None` makes the key required.
    pub default: Option<&'static str>,
    /// The values the builder accepts (`> 0`, `quarter | full`).
    pub range: &'static str,
    /// One line: what it sets.
    pub doc: &'static str,
}

impl ToolKey {
    /// A required key.
    #[must_use]
    pub const fn required(
        name: &'static str,
        unit: &'static str,
        range: &'static str,
        doc: &'static str,
    ) -> Self {
        Self {
            name,
            unit,
            default: None,
            range,
            doc,
        }
    }

    /// A key with a default.
    #[must_use]
    pub const fn optional(
        name: &'static str,
        unit: &'static str,
        default: &'static str,
        range: &'static str,
        doc: &'static str,
    ) -> Self {
        Self {
            name,
            unit,
            default: Some(default),
            range,
            doc,
        }
    }
}

/// `a [mm], b [mm]` for messages.
pub fn key_list(keys: &[ToolKey]) -> String {
    keys.iter()
        .map(|k| format!("{} [{}]", k.name, k.unit))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A registered tool kind.
#[derive(Debug)]
pub struct ToolKind {
    /// The name a scene gives as `kind`.
    pub name: &'static str,
    /// One line: what it builds.
    pub summary: &'static str,
    /// The keys of its table but `kind`, `origin` and `facing`.
    pub keys: &'static [ToolKey],
    /// `facing` when the table does not say.
    pub default_facing: Facing,
    /// Build the tool.
    pub build: fn(Request<'_>) -> Result<Tool, NurbsError>,
}

inventory::collect!(ToolKind);

/// Every registered kind, sorted by name.
pub fn all() -> Vec<&'static ToolKind> {
    let mut v: Vec<&'static ToolKind> = inventory::iter::<ToolKind>.into_iter().collect();
    v.sort_by_key(|k| k.name);
    v
}

/// The kind named `name`.
pub fn find(name: &str) -> Option<&'static ToolKind> {
    inventory::iter::<ToolKind>
        .into_iter()
        .find(|k| k.name == name)
}

/// The registered names, sorted, for messages.
pub fn names() -> String {
    all().iter().map(|k| k.name).collect::<Vec<_>>().join(", ")
}

/// Referenced by [`crate::ensure_linked`], so that a binary that names no
/// item of this module still links its registrations.
#[inline(never)]
pub(crate) fn anchor() -> usize {
    all().len()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_registry_holds_every_built_in_kind_once() {
        let names: Vec<&str> = all().iter().map(|k| k.name).collect();
        assert_eq!(
            names,
            [
                "blankholder",
                "cylinder",
                "die",
                "mesh",
                "plane",
                "punch",
                "s-rail-blankholder",
                "s-rail-die",
                "s-rail-punch"
            ]
        );
        assert!(all().iter().all(|k| !k.summary.is_empty()));
        assert_eq!(
            find("blankholder").map(|k| k.default_facing),
            Some(Facing::Down)
        );
        assert!(find("nope").is_none());
    }

    /// A table of every declared key at its default (`required` gives the
    /// keys without one).
    fn declared_table(kind: &ToolKind, required: &[(&str, toml::Value)]) -> toml::Table {
        let mut t = toml::Table::new();
        for k in kind.keys {
            let value = match k.default {
                Some(d) => d.parse::<toml::Value>().unwrap_or_else(|e| {
                    panic!("{}: default of `{}` is not TOML: {e}", kind.name, k.name)
                }),
                None => required
                    .iter()
                    .find(|(n, _)| *n == k.name)
                    .unwrap_or_else(|| panic!("{}: no sample for `{}`", kind.name, k.name))
                    .1
                    .clone(),
            };
            t.insert(k.name.to_string(), value);
        }
        t
    }

    /// Every kind's declaration is complete, each key once, and a table of
    /// every declared key (defaults as declared) builds: the builder reads
    /// every key the kind declares.
    #[test]
    fn every_declared_key_is_read_by_its_kind() {
        let samples = [
            ("radius", toml::Value::Float(10.0)),
            ("length", toml::Value::Float(20.0)),
            ("width", toml::Value::Float(20.0)),
            ("file", toml::Value::String("two.obj".into())),
        ];
        let dir = std::env::temp_dir().join(format!("tool-keys-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("two.obj"),
            "v 0 0 0\nv 10 0 0\nv 10 10 0\nv 0 10 0\nf 1 2 3\nf 1 3 4\n",
        )
        .unwrap();
        for kind in all() {
            let mut names: Vec<_> = kind.keys.iter().map(|k| k.name).collect();
            names.sort_unstable();
            names.dedup();
            assert_eq!(names.len(), kind.keys.len(), "{}: a key twice", kind.name);
            for k in kind.keys {
                assert!(
                    !k.unit.is_empty() && !k.range.is_empty() && !k.doc.is_empty(),
                    "{}: `{}` incomplete",
                    kind.name,
                    k.name
                );
            }
            let mut t = declared_table(kind, &samples);
            t.insert("kind".into(), kind.name.into());
            crate::spec::build_tool("t", &t, &dir)
                .unwrap_or_else(|e| panic!("{} with its declared keys: {e}", kind.name));
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// The declared defaults are the builders' defaults.
    #[test]
    fn declared_defaults_are_the_builders_defaults() {
        use crate::builders::s_rail::SRailParams;
        use crate::builders::square_cup::{DieParams, HolderParams, PunchParams};
        fn parsed<T: DeserializeOwned>(kind: &str) -> T {
            let mut t = declared_table(find(kind).unwrap(), &[]);
            t.remove("model");
            toml::Value::Table(t).try_into().unwrap()
        }
        assert_eq!(parsed::<PunchParams>("punch"), PunchParams::default());
        assert_eq!(parsed::<DieParams>("die"), DieParams::default());
        assert_eq!(
            parsed::<HolderParams>("blankholder"),
            HolderParams::default()
        );
        for kind in ["s-rail-punch", "s-rail-die", "s-rail-blankholder"] {
            assert_eq!(parsed::<SRailParams>(kind), SRailParams::default());
        }
        let model = find("punch")
            .unwrap()
            .keys
            .iter()
            .find(|k| k.name == "model");
        let model: crate::builders::Model = model
            .unwrap()
            .default
            .unwrap()
            .parse::<toml::Value>()
            .unwrap()
            .try_into()
            .unwrap();
        assert_eq!(model, crate::builders::Model::default());
    }

    /// A key the kind does not declare, and a required key missing, are
    /// one-line errors naming the tool, the key and the declared keys.
    #[test]
    fn undeclared_and_missing_keys_name_the_key() {
        let table = |text: &str| text.parse::<toml::Table>().unwrap();
        let e = crate::spec::build_tool(
            "roll",
            &table("kind = \"cylinder\"\nradius = 5.0\nlength = 9.0\nradus = 4.0"),
            Path::new("."),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("tool `roll`")
                && e.contains("unknown key `radus`")
                && e.contains("radius [mm]"),
            "{e}"
        );
        let e = crate::spec::build_tool(
            "roll",
            &table("kind = \"cylinder\"\nlength = 9.0"),
            Path::new("."),
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("missing key `radius` (mm, > 0: radius)"), "{e}");
    }
}
