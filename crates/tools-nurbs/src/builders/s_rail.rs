//! The S-rail tool set (docs/benchmarks.md §2): a PARAMETRIC RECONSTRUCTION, not the NUMISHEET'96 surfaces.
//!
//! The original tool surfaces are not available; this builds a hat-channel
//! set whose plan-view centre line is straight 1 — arc (left turn) — straight
//! 2 — arc (right turn, same angle, so the end straights are parallel) —
//! straight 3, starting at the origin along +x (straight 1 is prolonged
//! backwards and straight 3 forwards by `end_extension` so that the tools
//! cover the blank). Cross-sections are swept exactly along the centre line
//! (extrusions on straights, surfaces of revolution on arcs).
//!
//! - **Punch** (below the blank, facing up, top at local z = 0): flat top of
//!   width `punch_width - 2 punch_shoulder`, shoulders of `punch_shoulder`,
//!   vertical walls at `±punch_width/2` down to `-draw_depth`. Normal out of the punch.
//! - **Die** (above the blank, face at local z = 0 with normal down): flat
//!   faces out to `±flange_width`, shoulders of `die_shoulder`, cavity walls at
//!   `±(punch_width/2 + clearance)` with `clearance = clearance_factor ×
//!   thickness`, concave roof corners of `punch_shoulder + clearance`, roof at
//!   `draw_depth + thickness`. Normal out of the die (down, into the cavity).
//! - **Blankholder** (facing up at local z = 0): two flat strips from
//!   `±(punch_width/2 + holder_gap)` to `±flange_width`. Normal up.
//! - **Apron** (`apron > 0`, die and blankholder): the swept flange cannot
//!   reach beyond the arc radius (the offset sweep would fold), so a wide
//!   blank overhangs it near the arcs' centres and along the end straights.
//!   Two flat rectangles at the face's height, one either side of the S,
//!   prolong the die face and the holder `apron` mm beyond the flange's
//!   farthest edge along the tools' whole length (like the flat binder of a
//!   real tool set). Each overlaps the swept flange (same plane, same
//!   normal) and stays clear of the channel, which needs the S's lateral
//!   offset plus the channel's half width to stay below `flange_width`.

use super::sweep::{Material, Part, Piece, Spine, rectangle, sweep};
use super::{Facing, Placement, assemble, positive, require};
use crate::error::NurbsError;
use crate::nurbs_tool::NurbsTool;
use std::f64::consts::FRAC_PI_2;

/// S-rail parameters (mm, degrees); defaults from docs/benchmarks.md §2 where given.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SRailParams {
    /// Punch width between the walls (mm).
    pub punch_width: f64,
    /// Draw depth (mm).
    pub draw_depth: f64,
    /// Centre-line arc radius (mm).
    pub arc_radius: f64,
    /// Turning angle of each arc (degrees; reconstruction choice, not in the benchmark data).
    pub arc_angle_deg: f64,
    /// Straight lengths 1, 2, 3 along the centre line (mm).
    pub straight_lengths: [f64; 3],
    /// Prolongation of straights 1 and 3 beyond the S (mm; reconstruction choice).
    pub end_extension: f64,
    /// Punch shoulder radius (mm).
    pub punch_shoulder: f64,
    /// Die shoulder radius (mm).
    pub die_shoulder: f64,
    /// Blank thickness (mm), sets the clearance and the die roof.
    pub thickness: f64,
    /// Die–punch clearance as a multiple of the thickness.
    pub clearance_factor: f64,
    /// Half width of the die face and blankholder from the centre line (mm); < arc_radius.
    pub flange_width: f64,
    /// Gap between punch wall and blankholder inner edge (mm).
    pub holder_gap: f64,
    /// Flat prolongation of the die face and holder beyond the flange's
    /// farthest edge (mm); 0: none (module docs, "Apron").
    pub apron: f64,
}

impl Default for SRailParams {
    fn default() -> Self {
        Self {
            punch_width: 30.0,
            draw_depth: 37.0,
            arc_radius: 80.0,
            arc_angle_deg: 30.0,
            straight_lengths: [60.0, 50.0, 60.0],
            end_extension: 60.0,
            punch_shoulder: 5.0,
            die_shoulder: 5.0,
            thickness: 1.0,
            clearance_factor: 1.1,
            flange_width: 70.0,
            holder_gap: 2.0,
            apron: 0.0,
        }
    }
}

/// Lateral offset (mm) of straight 3's centre line from straight 1's: the
/// two arcs and straight 2 together.
pub fn lateral_offset(p: &SRailParams) -> f64 {
    let th = p.arc_angle_deg.to_radians();
    2.0 * p.arc_radius * (1.0 - th.cos()) + p.straight_lengths[1] * th.sin()
}

/// The x range (mm) of the tools: straight 1's prolonged start to straight 3's prolonged end.
fn x_range(p: &SRailParams) -> [f64; 2] {
    let th = p.arc_angle_deg.to_radians();
    let [l1, l2, l3] = p.straight_lengths;
    let end = l1 + 2.0 * p.arc_radius * th.sin() + l2 * th.cos() + l3 + p.end_extension;
    [-p.end_extension, end]
}

/// The two apron rectangles of a tool whose flat face starts at half width
/// `inner` (the die shoulder's outer edge, the holder's inner edge), with
/// the blank-side normal up or down. Empty when `apron` is 0.
fn apron_parts(p: &SRailParams, inner: f64, up: bool) -> Vec<Part> {
    apron_rectangles(p, inner)
        .into_iter()
        .map(|(x, y)| rectangle(x, y, 0.0, up))
        .collect()
}

/// The apron's two rectangles in plan, `([x0, x1], [y0, y1])` (mm, local
/// frame), for a tool whose flat face starts at half width `inner` (the die:
/// `punch_width/2 + clearance + die_shoulder`; the holder: `punch_width/2 +
/// holder_gap`). Each reaches from midway between the channel's farthest
/// edge and the flange's nearest outer edge to `apron` beyond the flange's
/// farthest edge. Empty when `apron` is 0.
pub fn apron_rectangles(p: &SRailParams, inner: f64) -> Vec<([f64; 2], [f64; 2])> {
    if p.apron <= 0.0 {
        return Vec::new();
    }
    let (y, f) = (lateral_offset(p), p.flange_width);
    let x = x_range(p);
    vec![
        (x, [0.5 * (y + inner + f), y + f + p.apron]),
        (x, [-f - p.apron, 0.5 * (y - f - inner)]),
    ]
}

/// Half width (mm) at which the die's flat face starts: the die shoulder's outer edge.
pub fn die_face_inner(p: &SRailParams) -> f64 {
    0.5 * p.punch_width + p.clearance_factor * p.thickness + p.die_shoulder
}

/// An apron needs room between the channel and the flange's outer edge.
fn check_apron(name: &str, p: &SRailParams, inner: f64) -> Result<(), NurbsError> {
    require(
        p.apron.is_finite() && p.apron >= 0.0,
        name,
        "apron",
        p.apron,
        "must be finite and >= 0".into(),
    )?;
    let need = lateral_offset(p) + inner;
    require(
        p.apron == 0.0 || need < p.flange_width,
        name,
        "apron",
        p.apron,
        format!(
            "needs flange_width above the S's lateral offset plus the channel half width ({need:.2} mm)"
        ),
    )
}

/// The plan-view centre line as spine pieces (offset ρ positive to the left of travel).
pub fn centre_line(p: &SRailParams) -> Vec<Spine> {
    let th = p.arc_angle_deg.to_radians();
    let r = p.arc_radius;
    let [l1, l2, l3] = p.straight_lengths;
    let e = p.end_extension;
    let line = |start: [f64; 2], a: f64, len: f64| Spine::Line {
        p: start,
        dir: [a.cos(), a.sin()],
        len,
        out: [-a.sin(), a.cos()],
    };
    let c1 = [l1, r];
    let q1 = [c1[0] + r * th.sin(), c1[1] - r * th.cos()];
    let p2 = [q1[0] + l2 * th.cos(), q1[1] + l2 * th.sin()];
    let c2 = [p2[0] + r * th.sin(), p2[1] - r * th.cos()];
    let q2 = [c2[0], c2[1] + r];
    vec![
        line([-e, 0.0], 0.0, l1 + e),
        Spine::Arc {
            c: c1,
            r0: r,
            a0: -FRAC_PI_2,
            a1: -FRAC_PI_2 + th,
            sigma: -1.0,
        },
        line(q1, th, l2),
        Spine::Arc {
            c: c2,
            r0: r,
            a0: FRAC_PI_2 + th,
            a1: FRAC_PI_2,
            sigma: 1.0,
        },
        line(q2, 0.0, l3 + e),
    ]
    .into_iter()
    .filter(|s| !matches!(s, Spine::Line { len, .. } if *len <= 0.0))
    .collect()
}

fn check(name: &str, p: &SRailParams) -> Result<(), NurbsError> {
    positive(name, "punch_width", p.punch_width)?;
    positive(name, "draw_depth", p.draw_depth)?;
    positive(name, "arc_radius", p.arc_radius)?;
    positive(name, "punch_shoulder", p.punch_shoulder)?;
    positive(name, "die_shoulder", p.die_shoulder)?;
    positive(name, "thickness", p.thickness)?;
    positive(name, "flange_width", p.flange_width)?;
    positive(name, "holder_gap", p.holder_gap)?;
    require(
        p.clearance_factor.is_finite() && p.clearance_factor > 0.0,
        name,
        "clearance_factor",
        p.clearance_factor,
        "must be finite and > 0 (a multiple of the thickness)".into(),
    )?;
    require(
        p.arc_angle_deg > 0.0 && p.arc_angle_deg <= 90.0,
        name,
        "arc_angle_deg",
        p.arc_angle_deg,
        "must lie in (0, 90] degrees".into(),
    )?;
    require(
        p.straight_lengths
            .iter()
            .all(|l| l.is_finite() && *l >= 0.0)
            && p.end_extension >= 0.0,
        name,
        "straight_lengths",
        p.straight_lengths[0],
        "and end_extension must be finite and >= 0".into(),
    )?;
    require(
        p.flange_width < p.arc_radius - 1.0,
        name,
        "flange_width",
        p.flange_width,
        format!(
            "must stay below arc_radius - 1 = {} mm (offset sweep must not fold)",
            p.arc_radius - 1.0
        ),
    )?;
    let w = 0.5 * p.punch_width;
    require(
        p.punch_shoulder < w,
        name,
        "punch_shoulder",
        p.punch_shoulder,
        format!("must be below punch_width/2 = {w} mm"),
    )?;
    require(
        p.flange_width > w + p.thickness * p.clearance_factor + p.die_shoulder
            && p.flange_width > w + p.holder_gap,
        name,
        "flange_width",
        p.flange_width,
        "must leave room for the die shoulder and the holder".into(),
    )
}

fn swept(profile: &[Piece], material: Material, spine: &[Spine]) -> Vec<Part> {
    let mut parts = Vec::new();
    for piece in profile {
        for s in spine {
            parts.push(sweep(piece, material, s));
        }
    }
    parts
}

/// The punch (facing up).
pub fn punch(name: &str, p: &SRailParams, place: &Placement) -> Result<NurbsTool, NurbsError> {
    check(name, p)?;
    let (w, r, d) = (0.5 * p.punch_width, p.punch_shoulder, p.draw_depth);
    let q = FRAC_PI_2;
    let profile = [
        Piece::Line {
            a: [w, -d],
            b: [w, -r],
        },
        Piece::Arc {
            c: [w - r, -r],
            r,
            a0: 0.0,
            a1: q,
        },
        Piece::Line {
            a: [w - r, 0.0],
            b: [-(w - r), 0.0],
        },
        Piece::Arc {
            c: [-(w - r), -r],
            r,
            a0: q,
            a1: 2.0 * q,
        },
        Piece::Line {
            a: [-w, -r],
            b: [-w, -d],
        },
    ];
    assemble(
        name,
        &swept(&profile, Material::Left, &centre_line(p)),
        place,
    )
}

/// The die (working face down; `place.facing` is ignored: the die is built facing down).
pub fn die(name: &str, p: &SRailParams, place: &Placement) -> Result<NurbsTool, NurbsError> {
    check(name, p)?;
    let c = p.clearance_factor * p.thickness;
    let (wd, rd, rb) = (
        0.5 * p.punch_width + c,
        p.die_shoulder,
        p.punch_shoulder + c,
    );
    let (h, f) = (p.draw_depth + p.thickness, p.flange_width);
    let q = FRAC_PI_2;
    let profile = [
        Piece::Line {
            a: [f, 0.0],
            b: [wd + rd, 0.0],
        },
        Piece::Arc {
            c: [wd + rd, rd],
            r: rd,
            a0: -q,
            a1: -2.0 * q,
        },
        Piece::Line {
            a: [wd, rd],
            b: [wd, h - rb],
        },
        Piece::Arc {
            c: [wd - rb, h - rb],
            r: rb,
            a0: 0.0,
            a1: q,
        },
        Piece::Line {
            a: [wd - rb, h],
            b: [-(wd - rb), h],
        },
        Piece::Arc {
            c: [-(wd - rb), h - rb],
            r: rb,
            a0: q,
            a1: 2.0 * q,
        },
        Piece::Line {
            a: [-wd, h - rb],
            b: [-wd, rd],
        },
        Piece::Arc {
            c: [-(wd + rd), rd],
            r: rd,
            a0: 0.0,
            a1: -q,
        },
        Piece::Line {
            a: [-(wd + rd), 0.0],
            b: [-f, 0.0],
        },
    ];
    check_apron(name, p, die_face_inner(p))?;
    let place = Placement {
        facing: Facing::Up,
        ..*place
    };
    let mut parts = swept(&profile, Material::Right, &centre_line(p));
    parts.extend(apron_parts(p, die_face_inner(p), false));
    assemble(name, &parts, &place)
}

/// The blankholder (facing up).
pub fn blankholder(
    name: &str,
    p: &SRailParams,
    place: &Placement,
) -> Result<NurbsTool, NurbsError> {
    check(name, p)?;
    let (g, f) = (0.5 * p.punch_width + p.holder_gap, p.flange_width);
    let profile = [
        Piece::Line {
            a: [f, 0.0],
            b: [g, 0.0],
        },
        Piece::Line {
            a: [-g, 0.0],
            b: [-f, 0.0],
        },
    ];
    check_apron(name, p, g)?;
    let mut parts = swept(&profile, Material::Left, &centre_line(p));
    parts.extend(apron_parts(p, g, true));
    assemble(name, &parts, place)
}
