//! Tool kinds by registration: each `kind` a scene's `[tools.NAME]` table
//! may name is a [`ToolKind`] submitted to the registry (`inventory`) from
//! its own file in this folder. A new kind is one file here, with its keys
//! and its `inventory::submit!`; nothing else names it ([`crate::spec`]
//! looks every kind up here, `formsim tools kinds` lists them).
//!
//! Every table takes `kind`, `origin = [x, y, z]` (mm) and `facing`; the
//! rest of its keys go to the kind's builder as [`Request::table`].

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

/// A registered tool kind.
#[derive(Debug)]
pub struct ToolKind {
    /// The name a scene gives as `kind`.
    pub name: &'static str,
    /// One line: what it builds and its keys (units).
    pub summary: &'static str,
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
}
