//! `kind = "cylinder"`: a cylinder about the x axis, `radius` and `length`
//! (mm), swept from `start_deg` to `end_deg` (default the full turn).

use super::{Request, ToolKind};
use crate::builders::{Facing, primitives};
use crate::error::NurbsError;
use crate::spec::Tool;

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Keys {
    radius: f64,
    length: f64,
    #[serde(default)]
    start_deg: f64,
    #[serde(default = "full_turn")]
    end_deg: f64,
}

fn full_turn() -> f64 {
    360.0
}

fn build(r: Request<'_>) -> Result<Tool, NurbsError> {
    let (name, place) = (r.name, r.place);
    let k: Keys = r.params()?;
    Ok(Tool::Nurbs(primitives::cylinder(
        name,
        k.radius,
        k.length,
        k.start_deg,
        k.end_deg,
        &place,
    )?))
}

inventory::submit! {
    ToolKind {
        name: "cylinder",
        summary: "cylinder: radius, length (mm), start_deg and end_deg (default 0 and 360)",
        default_facing: Facing::Up,
        build,
    }
}
