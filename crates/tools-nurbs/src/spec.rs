//! The tools section of a scene file (TOML): `[tools.NAME]` tables naming a builder (`kind`) and its keys.
//!
//! Keys, units and defaults are documented in `docs/tools.md`. Every tool
//! table takes `kind`, `origin = [x, y, z]` (mm, default `[0, 0, 0]`) and
//! `facing = "up" | "down"` (default: the kind's); the kind, registered in
//! [`crate::kinds`], reads the rest. Unknown keys are errors naming the tool
//! and the key.

use crate::builders::{Facing, Placement};
use crate::error::NurbsError;
use crate::faceted::FacetedTool;
use crate::kinds;
use crate::nurbs_tool::NurbsTool;
use plugins_api::{
    Aabb, CurvedRegion, FlatRegion, Projection, ProjectionHint, RigidPose, RigidVelocity,
    ToolError, ToolSurface, Vec3,
};
use serde::de::DeserializeOwned;
use std::path::Path;

/// A tool of a spec: exact NURBS or faceted (enum dispatch, no virtual call per query).
#[derive(Debug, Clone)]
pub enum Tool {
    /// Exact NURBS tool.
    Nurbs(NurbsTool),
    /// Triangle-mesh tool.
    Faceted(FacetedTool),
}

macro_rules! each {
    ($self:ident, $t:ident => $e:expr) => {
        match $self {
            Tool::Nurbs($t) => $e,
            Tool::Faceted($t) => $e,
        }
    };
}

impl ToolSurface for Tool {
    fn name(&self) -> &str {
        each!(self, t => t.name())
    }
    fn pose(&self) -> RigidPose {
        each!(self, t => t.pose())
    }
    fn set_pose(&mut self, pose: RigidPose, velocity: RigidVelocity) {
        each!(self, t => t.set_pose(pose, velocity))
    }
    fn velocity(&self) -> RigidVelocity {
        each!(self, t => t.velocity())
    }
    fn bounding_box(&self) -> Aabb {
        each!(self, t => t.bounding_box())
    }
    fn project(&self, x: &Vec3, hint: Option<ProjectionHint>) -> Result<Projection, ToolError> {
        each!(self, t => t.project(x, hint))
    }
    fn project_batch(
        &self,
        points: &[Vec3],
        hints: &[Option<ProjectionHint>],
        out: &mut [Projection],
    ) -> Result<(), ToolError> {
        each!(self, t => t.project_batch(points, hints, out))
    }
    fn flat_region(&self, hint: &ProjectionHint) -> Option<FlatRegion> {
        each!(self, t => t.flat_region(hint))
    }
    fn curved_region(&self, hint: &ProjectionHint) -> Option<CurvedRegion> {
        each!(self, t => t.curved_region(hint))
    }
}

/// A spec error on one line (TOML's own messages span several).
fn spec_err(message: String) -> NurbsError {
    let message = message
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join(" ");
    NurbsError::Spec { message }
}

/// Remove and read `key` of the tool `name`'s table, if present.
pub(crate) fn take<T: DeserializeOwned>(
    name: &str,
    table: &mut toml::Table,
    key: &str,
) -> Result<Option<T>, NurbsError> {
    match table.remove(key) {
        None => Ok(None),
        Some(v) => v
            .try_into()
            .map(Some)
            .map_err(|e| spec_err(format!("tool `{name}`: key `{key}`: {e}"))),
    }
}

/// Read a tool's remaining keys as its kind's parameters.
pub(crate) fn params<T: DeserializeOwned>(
    name: &str,
    kind: &str,
    table: toml::Table,
) -> Result<T, NurbsError> {
    toml::Value::Table(table).try_into().map_err(|e| {
        spec_err(format!(
            "tool `{name}` (kind `{kind}`): {}",
            e.to_string().trim()
        ))
    })
}

/// Build one tool from its table; `base` resolves relative mesh paths.
/// The kind is looked up in the registry ([`crate::kinds`]).
pub fn build_tool(name: &str, table: &toml::Table, base: &Path) -> Result<Tool, NurbsError> {
    let mut t = table.clone();
    let kind: String = take(name, &mut t, "kind")?.ok_or_else(|| {
        spec_err(format!(
            "tool `{name}`: missing key `kind` (one of {})",
            kinds::names()
        ))
    })?;
    let Some(registered) = kinds::find(&kind) else {
        return Err(spec_err(format!(
            "tool `{name}`: unknown kind `{kind}` (one of {})",
            kinds::names()
        )));
    };
    let origin: [f64; 3] = take(name, &mut t, "origin")?.unwrap_or([0.0; 3]);
    if origin.iter().any(|v| !v.is_finite()) {
        return Err(spec_err(format!(
            "tool `{name}`: origin {origin:?} mm is not finite"
        )));
    }
    let facing: Facing = take(name, &mut t, "facing")?.unwrap_or(registered.default_facing);
    check_keys(name, registered, &t)?;
    (registered.build)(kinds::Request {
        name,
        kind: &kind,
        table: t,
        keys: registered.keys,
        base,
        place: Placement {
            origin: Vec3::from(origin),
            facing,
        },
    })
}

/// The table's keys against the kind's declaration: none undeclared, every
/// required one given.
fn check_keys(name: &str, kind: &kinds::ToolKind, table: &toml::Table) -> Result<(), NurbsError> {
    let declared = || {
        if kind.keys.is_empty() {
            "none".to_string()
        } else {
            kinds::key_list(kind.keys)
        }
    };
    if let Some(key) = table
        .keys()
        .find(|k| !kind.keys.iter().any(|d| d.name == *k))
    {
        return Err(spec_err(format!(
            "tool `{name}` (kind `{}`): unknown key `{key}` (its keys: {}; and kind, origin, facing)",
            kind.name,
            declared()
        )));
    }
    if let Some(k) = kind
        .keys
        .iter()
        .find(|k| k.default.is_none() && !table.contains_key(k.name))
    {
        return Err(spec_err(format!(
            "tool `{name}` (kind `{}`): missing key `{}` ({}, {}: {})",
            kind.name, k.name, k.unit, k.range, k.doc
        )));
    }
    Ok(())
}

/// Build every tool of a spec text (`[tools.NAME]` tables; other sections ignored), sorted by name.
pub fn parse(text: &str, base: &Path) -> Result<Vec<Tool>, NurbsError> {
    let doc: toml::Table = text
        .parse()
        .map_err(|e: toml::de::Error| spec_err(e.to_string().trim().to_string()))?;
    let tools = doc
        .get("tools")
        .and_then(|v| v.as_table())
        .ok_or_else(|| spec_err("no [tools] section".into()))?;
    let mut out = Vec::new();
    for (name, v) in tools {
        let table = v
            .as_table()
            .ok_or_else(|| spec_err(format!("tools.{name} is not a table")))?;
        out.push(build_tool(name, table, base)?);
    }
    if out.is_empty() {
        return Err(spec_err("the [tools] section defines no tool".into()));
    }
    Ok(out)
}

/// Read and build a spec file (relative mesh paths resolve against its directory).
pub fn load(path: &Path) -> Result<Vec<Tool>, NurbsError> {
    let text = plugins_api::input_file::read_text(path, plugins_api::input_file::TEXT_LIMIT)
        .map_err(|e| NurbsError::File {
            path: path.display().to_string(),
            message: format!("cannot read: {e}"),
        })?;
    let base = path.parent().unwrap_or(Path::new("."));
    parse(&text, base).map_err(|e| match e {
        NurbsError::Spec { message } => NurbsError::File {
            path: path.display().to_string(),
            message,
        },
        other => other,
    })
}
