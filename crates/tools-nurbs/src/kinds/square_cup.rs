//! The NUMISHEET'93 square cup's tools, `kind = "punch" | "die" |
//! "blankholder"`, with their dimensions (mm; docs/tools.md) and `model =
//! "quarter" | "full"`.

use super::{Request, ToolKind};
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
        summary: "square-cup punch: length, width, corner_radius, profile_radius, height (mm), model",
        default_facing: Facing::Up,
        build: punch,
    }
}

inventory::submit! {
    ToolKind {
        name: "die",
        summary: "square-cup die: opening_length, opening_width, corner_radius, shoulder_radius, depth, outer_length, outer_width (mm), model",
        default_facing: Facing::Up,
        build: die,
    }
}

inventory::submit! {
    ToolKind {
        name: "blankholder",
        summary: "square-cup blankholder ring: inner_length, inner_width, corner_radius, outer_length, outer_width (mm), model",
        default_facing: Facing::Down,
        build: blankholder,
    }
}
