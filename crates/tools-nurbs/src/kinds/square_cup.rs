//! The NUMISHEET'93 square cup's tools, `kind = "punch" | "die" |
//! "blankholder"`, with their dimensions (mm; docs/tools.md) and `model =
//! "quarter" | "full"`.

use super::{Request, ToolKey, ToolKind};
use crate::builders::square_cup::{self, DieParams, HolderParams, PunchParams};
use crate::builders::{Facing, Model, Placement};
use crate::error::NurbsError;
use crate::nurbs_tool::NurbsTool;
use crate::spec::Tool;
use serde::de::DeserializeOwned;

/// A square-cup tool: the table's `model` (default a quarter), then its
/// dimensions `P`, handed to `build`.
fn square<P: DeserializeOwned>(
    mut r: Request<'_>,
    build: fn(&str, &P, Model, &Placement) -> Result<NurbsTool, NurbsError>,
) -> Result<Tool, NurbsError> {
    let model = r.take("model")?.unwrap_or_default();
    let (name, place) = (r.name, r.place);
    let p: P = r.params()?;
    Ok(Tool::Nurbs(build(name, &p, model, &place)?))
}

/// `model`, which every square-cup tool reads.
const MODEL: ToolKey = ToolKey::optional(
    "model",
    "text",
    "\"quarter\"",
    "quarter | full",
    "the quadrant x ≥ 0, y ≥ 0 or the whole tool",
);

/// The punch's keys (defaults: the benchmark's, `PunchParams::default`).
const PUNCH: &[ToolKey] = &[
    ToolKey::optional("length", "mm", "70.0", "> 0", "size along x"),
    ToolKey::optional("width", "mm", "70.0", "> 0", "size along y"),
    ToolKey::optional(
        "corner_radius",
        "mm",
        "10.0",
        "(profile_radius, length/2]",
        "plan-view corner radius at the walls",
    ),
    ToolKey::optional(
        "profile_radius",
        "mm",
        "8.0",
        "(0, corner_radius)",
        "profile (nose) radius",
    ),
    ToolKey::optional(
        "height",
        "mm",
        "50.0",
        "> profile_radius",
        "height modelled below the nose",
    ),
    MODEL,
];

/// The die's keys (defaults: `DieParams::default`).
const DIE: &[ToolKey] = &[
    ToolKey::optional(
        "opening_length",
        "mm",
        "74.0",
        "> 0",
        "opening size along x at the walls",
    ),
    ToolKey::optional("opening_width", "mm", "74.0", "> 0", "opening size along y"),
    ToolKey::optional(
        "corner_radius",
        "mm",
        "12.0",
        "(0, opening/2]",
        "plan corner radius of the opening",
    ),
    ToolKey::optional(
        "shoulder_radius",
        "mm",
        "5.0",
        "> 0",
        "shoulder (profile) radius",
    ),
    ToolKey::optional(
        "depth",
        "mm",
        "50.0",
        "> shoulder_radius",
        "depth of the opening's walls below the face",
    ),
    ToolKey::optional(
        "outer_length",
        "mm",
        "170.0",
        "> opening + 2 shoulder",
        "outer size along x",
    ),
    ToolKey::optional(
        "outer_width",
        "mm",
        "170.0",
        "> opening + 2 shoulder",
        "outer size along y",
    ),
    MODEL,
];

/// The blankholder's keys (defaults: `HolderParams::default`).
const HOLDER: &[ToolKey] = &[
    ToolKey::optional("inner_length", "mm", "84.0", "> 0", "inner size along x"),
    ToolKey::optional("inner_width", "mm", "84.0", "> 0", "inner size along y"),
    ToolKey::optional(
        "corner_radius",
        "mm",
        "12.0",
        "(0, inner/2)",
        "plan corner radius of the inner edge",
    ),
    ToolKey::optional(
        "outer_length",
        "mm",
        "170.0",
        "> inner_length",
        "outer size along x",
    ),
    ToolKey::optional(
        "outer_width",
        "mm",
        "170.0",
        "> inner_width",
        "outer size along y",
    ),
    MODEL,
];

fn punch(r: Request<'_>) -> Result<Tool, NurbsError> {
    square::<PunchParams>(r, square_cup::punch)
}

fn die(r: Request<'_>) -> Result<Tool, NurbsError> {
    square::<DieParams>(r, square_cup::die)
}

fn blankholder(r: Request<'_>) -> Result<Tool, NurbsError> {
    square::<HolderParams>(r, square_cup::blankholder)
}

inventory::submit! {
    ToolKind {
        name: "punch",
        summary: "NUMISHEET'93 square-cup punch",
        keys: PUNCH,
        default_facing: Facing::Up,
        build: punch,
    }
}

inventory::submit! {
    ToolKind {
        name: "die",
        summary: "NUMISHEET'93 square-cup die",
        keys: DIE,
        default_facing: Facing::Up,
        build: die,
    }
}

inventory::submit! {
    ToolKind {
        name: "blankholder",
        summary: "NUMISHEET'93 square-cup blankholder ring",
        keys: HOLDER,
        default_facing: Facing::Down,
        build: blankholder,
    }
}
