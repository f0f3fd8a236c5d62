//! `kind = "plane"`: a flat rectangle `length × width` (mm) centred on the
//! origin, normal +z (or −z facing down).

use super::{Request, ToolKey, ToolKind};
use crate::builders::{Facing, primitives};
use crate::error::NurbsError;
use crate::spec::Tool;

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Keys {
    length: f64,
    width: f64,
}

fn build(r: Request<'_>) -> Result<Tool, NurbsError> {
    let (name, place) = (r.name, r.place);
    let k: Keys = r.params()?;
    Ok(Tool::Nurbs(primitives::plane(
        name, k.length, k.width, &place,
    )?))
}

inventory::submit! {
    ToolKind {
        name: "plane",
        summary: "a flat rectangle centred on the origin",
        keys: &[
            ToolKey::required("length", "mm", "> 0", "size along x"),
            ToolKey::required("width", "mm", "> 0", "size along y"),
        ],
        default_facing: Facing::Up,
        build,
    }
}
