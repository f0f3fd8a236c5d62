//! The rounded-rectangle punch, the die with a rounded-rectangle opening and the flat blankholder ring (docs/benchmarks.md §1).
//!
//! Built in a local frame with the working face at z = 0 facing +z, the
//! quadrant x ≥ 0, y ≥ 0 first (mirrored for the full model), then placed.
//!
//! - **Punch** (`punch`): flat nose (a rounded rectangle of half sizes
//!   `L/2 - r_p`, `W/2 - r_p`, plan corner `r_c - r_p`), profile fillets of
//!   radius `r_p` (cylinders along the sides, tori at the plan corners: the
//!   profile arc swept about the corner axis), vertical walls down to
//!   `-height` (planes along the sides, cylinders of radius `r_c` at the
//!   corners). Normal: out of the punch (up on the nose, outwards on the walls).
//! - **Die** (`die`): flat face from the outer square to the shoulder, the
//!   shoulder radius `r_s` around the opening (cylinders and tori), vertical
//!   opening walls down to `-depth`. Normal: out of the die material (up on the
//!   face, towards the axis on the opening walls).
//! - **Blankholder** (`blankholder`): flat ring between the outer rectangle
//!   and the inner rounded rectangle (sharp inner edge). Normal: up in the
//!   local frame, so a holder placed with `facing = down` has its normal down.
//!
//! Seams are G1 by construction (every fillet is tangent to its neighbours);
//! curvature jumps where the geometry does: flat → fillet, cylinder → torus,
//! fillet → wall.

use super::sweep::{Material, Part, Piece, Spine, rectangle, ruled, sweep};
use super::{Model, Placement, assemble, positive, require, symmetric};
use crate::error::NurbsError;
use crate::nurbs_tool::NurbsTool;
use std::f64::consts::FRAC_PI_2;

const Q: f64 = FRAC_PI_2;

/// Rounded-rectangle punch parameters (mm).
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PunchParams {
    /// Size along x (mm).
    pub length: f64,
    /// Size along y (mm).
    pub width: f64,
    /// Plan-view corner radius at the walls (mm).
    pub corner_radius: f64,
    /// Profile (nose) radius (mm); must be smaller than `corner_radius`.
    pub profile_radius: f64,
    /// Height of the modelled punch below its nose (mm).
    pub height: f64,
}

impl Default for PunchParams {
    fn default() -> Self {
        Self {
            length: 70.0,
            width: 70.0,
            corner_radius: 10.0,
            profile_radius: 8.0,
            height: 50.0,
        }
    }
}

/// Die parameters (mm).
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DieParams {
    /// Opening size along x at the walls (mm).
    pub opening_length: f64,
    /// Opening size along y (mm).
    pub opening_width: f64,
    /// Plan corner radius of the opening at the walls (mm).
    pub corner_radius: f64,
    /// Shoulder (profile) radius (mm).
    pub shoulder_radius: f64,
    /// Depth of the modelled opening walls below the face (mm).
    pub depth: f64,
    /// Outer size along x (mm).
    pub outer_length: f64,
    /// Outer size along y (mm).
    pub outer_width: f64,
}

impl Default for DieParams {
    fn default() -> Self {
        Self {
            opening_length: 74.0,
            opening_width: 74.0,
            corner_radius: 12.0,
            shoulder_radius: 5.0,
            depth: 50.0,
            outer_length: 170.0,
            outer_width: 170.0,
        }
    }
}

/// Blankholder ring parameters (mm).
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct HolderParams {
    /// Inner size along x (mm).
    pub inner_length: f64,
    /// Inner size along y (mm).
    pub inner_width: f64,
    /// Plan corner radius of the inner edge (mm).
    pub corner_radius: f64,
    /// Outer size along x (mm).
    pub outer_length: f64,
    /// Outer size along y (mm).
    pub outer_width: f64,
}

impl Default for HolderParams {
    fn default() -> Self {
        Self {
            inner_length: 84.0,
            inner_width: 84.0,
            corner_radius: 12.0,
            outer_length: 170.0,
            outer_width: 170.0,
        }
    }
}

/// Quadrant of a rounded rectangle of half sizes `(a, b)` and corner radius
/// `c`: line up the x side, two 45° arcs, line along the y side.
fn rounded_quadrant(a: f64, b: f64, c: f64) -> [Piece; 4] {
    let (cx, cy) = (a - c, b - c);
    [
        Piece::Line {
            a: [a, 0.0],
            b: [a, cy],
        },
        Piece::Arc {
            c: [cx, cy],
            r: c,
            a0: 0.0,
            a1: 0.5 * Q,
        },
        Piece::Arc {
            c: [cx, cy],
            r: c,
            a0: 0.5 * Q,
            a1: Q,
        },
        Piece::Line {
            a: [cx, b],
            b: [0.0, b],
        },
    ]
}

/// Quadrant of a sharp rectangle `(a, b)` split to face [`rounded_quadrant`]
/// of `(ra, rb, rc)`: the corner sits at the arcs' 45° joint.
fn sharp_quadrant(a: f64, b: f64, ra: f64, rb: f64, rc: f64) -> [Piece; 4] {
    let y1 = b * (rb - rc) / rb;
    let x1 = a * (ra - rc) / ra;
    [
        Piece::Line {
            a: [a, 0.0],
            b: [a, y1],
        },
        Piece::Line {
            a: [a, y1],
            b: [a, b],
        },
        Piece::Line {
            a: [a, b],
            b: [x1, b],
        },
        Piece::Line {
            a: [x1, b],
            b: [0.0, b],
        },
    ]
}

/// The plan spine of a rounded rectangle quadrant whose corner centre is `(cx, cy)`.
fn corner_spine(cx: f64, cy: f64) -> Vec<Spine> {
    let mut s = Vec::new();
    if cy > 0.0 {
        s.push(Spine::Line {
            p: [cx, 0.0],
            dir: [0.0, 1.0],
            len: cy,
            out: [1.0, 0.0],
        });
    }
    s.push(Spine::Arc {
        c: [cx, cy],
        r0: 0.0,
        a0: 0.0,
        a1: Q,
        sigma: 1.0,
    });
    if cx > 0.0 {
        s.push(Spine::Line {
            p: [cx, cy],
            dir: [-1.0, 0.0],
            len: cx,
            out: [0.0, 1.0],
        });
    }
    s
}

/// The punch quadrant parts (local frame, nose at z = 0 facing +z).
pub fn punch_parts(tool: &str, p: &PunchParams) -> Result<Vec<Part>, NurbsError> {
    let a = 0.5 * positive(tool, "length", p.length)?;
    let b = 0.5 * positive(tool, "width", p.width)?;
    let rc = positive(tool, "corner_radius", p.corner_radius)?;
    let rp = positive(tool, "profile_radius", p.profile_radius)?;
    let h = positive(tool, "height", p.height)?;
    require(
        rp < rc,
        tool,
        "profile_radius",
        rp,
        format!("must be smaller than corner_radius = {rc} mm"),
    )?;
    require(
        rc <= a.min(b),
        tool,
        "corner_radius",
        rc,
        "must not exceed half the punch length and width".into(),
    )?;
    require(
        h > rp,
        tool,
        "height",
        h,
        format!("must exceed profile_radius = {rp} mm"),
    )?;
    let (bx, by, c) = (a - rp, b - rp, rc - rp);
    let (qx, qy) = (0.5 * bx, 0.5 * by);
    let mut parts = vec![
        rectangle([0.0, qx], [0.0, qy], 0.0, true),
        ruled(
            &sharp_quadrant(qx, qy, bx, by, c),
            &rounded_quadrant(bx, by, c),
            0.0,
            true,
        ),
    ];
    let profile = [
        Piece::Arc {
            c: [rc - rp, -rp],
            r: rp,
            a0: Q,
            a1: 0.0,
        },
        Piece::Line {
            a: [rc, -rp],
            b: [rc, -h],
        },
    ];
    for piece in &profile {
        for s in corner_spine(a - rc, b - rc) {
            parts.push(sweep(piece, Material::Right, &s));
        }
    }
    Ok(parts)
}

/// The die quadrant parts (local frame, face at z = 0 facing +z).
pub fn die_parts(tool: &str, p: &DieParams) -> Result<Vec<Part>, NurbsError> {
    let a = 0.5 * positive(tool, "opening_length", p.opening_length)?;
    let b = 0.5 * positive(tool, "opening_width", p.opening_width)?;
    let rc = positive(tool, "corner_radius", p.corner_radius)?;
    let rs = positive(tool, "shoulder_radius", p.shoulder_radius)?;
    let d = positive(tool, "depth", p.depth)?;
    let oa = 0.5 * positive(tool, "outer_length", p.outer_length)?;
    let ob = 0.5 * positive(tool, "outer_width", p.outer_width)?;
    require(
        rc <= a.min(b),
        tool,
        "corner_radius",
        rc,
        "must not exceed half the opening length and width".into(),
    )?;
    require(
        d > rs,
        tool,
        "depth",
        d,
        format!("must exceed shoulder_radius = {rs} mm"),
    )?;
    require(
        oa > a + rs && ob > b + rs,
        tool,
        "outer_length",
        p.outer_length,
        "must leave a flat face beyond the shoulder on every side".into(),
    )?;
    let (ia, ib, ic) = (a + rs, b + rs, rc + rs);
    let mut parts = vec![ruled(
        &rounded_quadrant(ia, ib, ic),
        &sharp_quadrant(oa, ob, ia, ib, ic),
        0.0,
        true,
    )];
    let profile = [
        Piece::Arc {
            c: [rc + rs, -rs],
            r: rs,
            a0: Q,
            a1: 2.0 * Q,
        },
        Piece::Line {
            a: [rc, -rs],
            b: [rc, -d],
        },
    ];
    for piece in &profile {
        for s in corner_spine(a - rc, b - rc) {
            parts.push(sweep(piece, Material::Left, &s));
        }
    }
    Ok(parts)
}

/// The blankholder quadrant part (local frame, face at z = 0 facing +z).
pub fn holder_parts(tool: &str, p: &HolderParams) -> Result<Vec<Part>, NurbsError> {
    let a = 0.5 * positive(tool, "inner_length", p.inner_length)?;
    let b = 0.5 * positive(tool, "inner_width", p.inner_width)?;
    let rc = positive(tool, "corner_radius", p.corner_radius)?;
    let oa = 0.5 * positive(tool, "outer_length", p.outer_length)?;
    let ob = 0.5 * positive(tool, "outer_width", p.outer_width)?;
    require(
        rc < a.min(b),
        tool,
        "corner_radius",
        rc,
        "must be smaller than half the inner length and width".into(),
    )?;
    require(
        oa > a && ob > b,
        tool,
        "outer_length",
        p.outer_length,
        "must exceed the inner size".into(),
    )?;
    Ok(vec![ruled(
        &rounded_quadrant(a, b, rc),
        &sharp_quadrant(oa, ob, a, b, rc),
        0.0,
        true,
    )])
}

/// Build the rounded-rectangle punch.
pub fn punch(
    name: &str,
    p: &PunchParams,
    model: Model,
    place: &Placement,
) -> Result<NurbsTool, NurbsError> {
    assemble(name, &symmetric(punch_parts(name, p)?, model), place)
}

/// Build the die with a rounded-rectangle opening.
pub fn die(
    name: &str,
    p: &DieParams,
    model: Model,
    place: &Placement,
) -> Result<NurbsTool, NurbsError> {
    assemble(name, &symmetric(die_parts(name, p)?, model), place)
}

/// The benchmark's quarter die (docs/benchmarks.md §1, default dimensions) with its
/// face at z = 0 facing up: the fixture of the contact and projection tests.
///
/// # Errors
/// None for the default dimensions; the `Result` is [`die`]'s.
pub fn benchmark_quarter_die() -> Result<NurbsTool, NurbsError> {
    die(
        "die",
        &DieParams::default(),
        Model::Quarter,
        &Placement {
            origin: plugins_api::Vec3::zeros(),
            facing: super::Facing::Up,
        },
    )
}

/// Build the flat blankholder ring.
pub fn blankholder(
    name: &str,
    p: &HolderParams,
    model: Model,
    place: &Placement,
) -> Result<NurbsTool, NurbsError> {
    assemble(name, &symmetric(holder_parts(name, p)?, model), place)
}
