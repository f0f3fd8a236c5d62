//! Tool builders with exact rational geometry: square-cup punch, die and blankholder, S-rail set, plane, cylinder.
//!
//! Every builder states its orientation (which way the blank-side normal
//! points) and bakes its placement (`origin`, `facing`) into the geometry, so
//! the tool's rigid pose starts at the identity and the press scheduler moves
//! it from there. The rule shared by all: **the normal points out of the
//! tool's material**, towards where the blank can be.

pub mod primitives;
pub mod s_rail;
pub mod square_cup;
pub mod sweep;

use crate::error::NurbsError;
use crate::nurbs_tool::{NurbsTool, OrientedPatch};
use crate::surface::NurbsSurface;
use plugins_api::Vec3;
use sweep::{Part, mapped};

/// Which way a tool's working face (punch nose, die face, holder face) points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Facing {
    /// Towards +z.
    #[default]
    Up,
    /// Towards -z (the tool is mirrored through its local z = 0 plane).
    Down,
}

/// Quarter model (the quadrant x ≥ 0, y ≥ 0, for two symmetry planes) or full model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Model {
    /// Quadrant x ≥ 0, y ≥ 0 only.
    #[default]
    Quarter,
    /// The whole tool (four mirrored quadrants).
    Full,
}

/// Where a built tool goes: origin (mm) of its local frame and the way its working face points.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Placement {
    /// Position (mm) of the tool's local origin (the centre of its working face).
    pub origin: Vec3,
    /// Working face up or down.
    pub facing: Facing,
}

/// Mirror quadrant parts into the full model when asked.
pub(crate) fn symmetric(parts: Vec<Part>, model: Model) -> Vec<Part> {
    match model {
        Model::Quarter => parts,
        Model::Full => {
            let mut all = Vec::with_capacity(parts.len() * 4);
            for m in [
                [1.0, 1.0, 1.0],
                [-1.0, 1.0, 1.0],
                [-1.0, -1.0, 1.0],
                [1.0, -1.0, 1.0],
            ] {
                all.extend(parts.iter().map(|p| mapped(p, m, Vec3::zeros())));
            }
            all
        }
    }
}

/// Place the parts, validate them and orient each patch so that its normal
/// agrees with the part's reference direction at the patch centre.
pub(crate) fn assemble(
    name: &str,
    parts: &[Part],
    place: &Placement,
) -> Result<NurbsTool, NurbsError> {
    let mz = match place.facing {
        Facing::Up => 1.0,
        Facing::Down => -1.0,
    };
    let mut patches = Vec::with_capacity(parts.len());
    for (i, part) in parts.iter().enumerate() {
        let p = mapped(part, [1.0, 1.0, mz], place.origin);
        let surface = NurbsSurface::new(i, &p.def)?;
        let (du, dv) = surface.domain();
        let d = surface.eval(0.5 * (du[0] + du[1]), 0.5 * (dv[0] + dv[1]));
        let sign = if d.su.cross(&d.sv).dot(&p.reference) >= 0.0 {
            1.0
        } else {
            -1.0
        };
        patches.push(OrientedPatch { surface, sign });
    }
    NurbsTool::new(name, patches)
}

/// Check that a builder parameter is finite and positive.
pub(crate) fn positive(tool: &str, key: &str, value: f64) -> Result<f64, NurbsError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(NurbsError::Param {
            tool: tool.to_string(),
            key: key.to_string(),
            value,
            unit: "mm",
            reason: "must be finite and > 0".into(),
        })
    }
}

/// Refuse `value` unless `ok`, with `reason`.
pub(crate) fn require(
    ok: bool,
    tool: &str,
    key: &str,
    value: f64,
    reason: String,
) -> Result<(), NurbsError> {
    if ok {
        Ok(())
    } else {
        Err(NurbsError::Param {
            tool: tool.to_string(),
            key: key.to_string(),
            value,
            unit: "mm",
            reason,
        })
    }
}
