//! `kind = "cylinder"`: a cylinder about the y axis, `radius` and `length`
//! (mm), swept from `start_deg` to `end_deg` (from +x towards +z; default
//! the full turn).

use super::{Request, ToolKey, ToolKind};
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
        summary: "a cylinder about the y axis, swept from start_deg to end_deg",
        keys: &[
            ToolKey::required("radius", "mm", "> 0", "radius"),
            ToolKey::required("length", "mm", "> 0", "length along y, centred on the origin"),
            ToolKey::optional("start_deg", "degrees", "0", "any",  "where the sweep starts, from +x towards +z"),
            ToolKey::optional("end_deg", "degrees", "360", "(start_deg, start_deg + 360]", "where the sweep ends"),
        ],
        default_facing: Facing::Up,
        build,
    }
}
