//! The NUMISHEET'93 square cup's tools, `kind = "punch" | "die" |
//! "blankholder"`, with their dimensions (mm; docs/tools.md) and `model =
//! "quarter" | "full"`.

use super::{Request, ToolKind};
use crate::builders::square_cup::{self, DieParams, HolderParams, PunchParams};
use crate::builders::{Facing, Model};
use crate::error::NurbsError;
use crate::spec::Tool;

/// The table's `model` (default a quarter) and the request without it.
fn model(mut r: Request<'_>) -> Result<(Model, Request<'_>), NurbsError> {
    let m = r.take("model")?.unwrap_or_default();
    Ok((m, r))
}

fn punch(r: Request<'_>) -> Result<Tool, NurbsError> {
    let (m, r) = model(r)?;
    let (name, place) = (r.name, r.place);
    let p: PunchParams = r.params()?;
    Ok(Tool::Nurbs(square_cup::punch(name, &p, m, &place)?))
}

fn die(r: Request<'_>) -> Result<Tool, NurbsError> {
    let (m, r) = model(r)?;
    let (name, place) = (r.name, r.place);
    let p: DieParams = r.params()?;
    Ok(Tool::Nurbs(square_cup::die(name, &p, m, &place)?))
}

fn blankholder(r: Request<'_>) -> Result<Tool, NurbsError> {
    let (m, r) = model(r)?;
    let (name, place) = (r.name, r.place);
    let p: HolderParams = r.params()?;
    Ok(Tool::Nurbs(square_cup::blankholder(name, &p, m, &place)?))
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
