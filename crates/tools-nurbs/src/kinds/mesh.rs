//! `kind = "mesh"`: a faceted tool from a triangle file (STL or OBJ,
//! `file` relative to the scene), moved to the origin, mirrored in z when
//! facing down; `flip_normals` turns its facets over.

use super::{Request, ToolKey, ToolKind};
use crate::builders::Facing;
use crate::error::NurbsError;
use crate::faceted::FacetedTool;
use crate::mesh_io::read_mesh;
use crate::spec::Tool;
use plugins_api::Vec3;

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Keys {
    file: String,
    #[serde(default)]
    flip_normals: bool,
}

fn build(r: Request<'_>) -> Result<Tool, NurbsError> {
    let (name, base, place) = (r.name, r.base, r.place);
    let k: Keys = r.params()?;
    let mut mesh = read_mesh(&base.join(&k.file))?;
    let mz = if place.facing == Facing::Down {
        -1.0
    } else {
        1.0
    };
    for v in &mut mesh.vertices {
        *v = Vec3::new(v.x, v.y, mz * v.z) + place.origin;
    }
    // Mirroring reverses the winding.
    Ok(Tool::Faceted(FacetedTool::new(
        name,
        &mesh,
        k.flip_normals ^ (mz < 0.0),
    )?))
}

inventory::submit! {
    ToolKind {
        name: "mesh",
        summary: "a faceted tool from an STL or OBJ file",
        keys: &[
            ToolKey::required("file", "path", "an .stl or .obj file", "the triangles, relative to the scene"),
            ToolKey::optional("flip_normals", "-", "false", "true | false", "turn the facets over"),
        ],
        default_facing: Facing::Up,
        build,
    }
}
