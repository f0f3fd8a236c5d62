//! Exact rational building blocks: arcs and lines as rational quadratics, profiles swept along plan spines, ruled rings.
//!
//! A circular arc of opening `2h ≤ 90°` is one rational quadratic span with
//! control points on the end tangents and middle weight `cos h` (for a quarter
//! circle: weights `1, √2/2, 1`); lines are degree-2 spans with the middle
//! point at the midpoint. A profile in `(ρ, z)` swept along a straight spine
//! piece is an extrusion; swept around a spine arc it is a surface of
//! revolution (the tensor product of two rational arcs), both exact.

use crate::surface::PatchDef;
use plugins_api::Vec3;

/// A planar curve piece: a line or a circular arc (sweep at most 90°).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Piece {
    /// Straight segment from `a` to `b`.
    Line {
        /// Start.
        a: [f64; 2],
        /// End.
        b: [f64; 2],
    },
    /// Arc of radius `r` about `c` from angle `a0` to `a1` (rad).
    Arc {
        /// Centre.
        c: [f64; 2],
        /// Radius.
        r: f64,
        /// Start angle (rad).
        a0: f64,
        /// End angle (rad).
        a1: f64,
    },
}

impl Piece {
    /// The three control points and weights of the rational quadratic.
    pub fn control(&self) -> ([[f64; 2]; 3], [f64; 3]) {
        match *self {
            Piece::Line { a, b } => (
                [a, [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])], b],
                [1.0, 1.0, 1.0],
            ),
            Piece::Arc { c, r, a0, a1 } => {
                let h = 0.5 * (a1 - a0);
                let m = 0.5 * (a0 + a1);
                let rm = r / h.cos();
                (
                    [
                        [c[0] + r * a0.cos(), c[1] + r * a0.sin()],
                        [c[0] + rm * m.cos(), c[1] + rm * m.sin()],
                        [c[0] + r * a1.cos(), c[1] + r * a1.sin()],
                    ],
                    [1.0, h.cos(), 1.0],
                )
            }
        }
    }

    /// Unit tangent at the middle of the piece, in the direction of travel.
    pub fn mid_tangent(&self) -> [f64; 2] {
        match *self {
            Piece::Line { a, b } => {
                let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                let l = (dx * dx + dy * dy).sqrt();
                [dx / l, dy / l]
            }
            Piece::Arc { a0, a1, .. } => {
                let m = 0.5 * (a0 + a1);
                let s = (a1 - a0).signum();
                [-s * m.sin(), s * m.cos()]
            }
        }
    }

    /// Length of the piece.
    pub fn length(&self) -> f64 {
        match *self {
            Piece::Line { a, b } => ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt(),
            Piece::Arc { r, a0, a1, .. } => r * (a1 - a0).abs(),
        }
    }
}

/// Which side of the profile (looking along its direction of travel) the tool's material lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Material {
    /// Material on the left: the blank-side normal is the tangent turned clockwise.
    Left,
    /// Material on the right: the blank-side normal is the tangent turned counter-clockwise.
    Right,
}

/// A plan-view spine piece along which a `(ρ, z)` profile is swept; `ρ` is
/// the offset from the spine along its outward direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Spine {
    /// Straight: from `p` along unit `dir` for `len`; `out` is the unit offset direction.
    Line {
        /// Start point (x, y).
        p: [f64; 2],
        /// Unit direction.
        dir: [f64; 2],
        /// Length (mm).
        len: f64,
        /// Unit offset direction (perpendicular to `dir`).
        out: [f64; 2],
    },
    /// Arc about `c` of radius `r0` from `a0` to `a1` (rad); the offset `ρ`
    /// moves away from the centre when `sigma = 1`, towards it when `-1`.
    Arc {
        /// Centre.
        c: [f64; 2],
        /// Spine radius (mm; 0 for a plan corner swept about its centre).
        r0: f64,
        /// Start angle (rad).
        a0: f64,
        /// End angle (rad).
        a1: f64,
        /// `+1` or `-1`.
        sigma: f64,
    },
}

/// A patch definition with the direction its blank-side normal must have at its parameter centre.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    /// The patch.
    pub def: PatchDef,
    /// Blank-side reference direction at the patch centre.
    pub reference: Vec3,
}

fn knots(n_spans: usize) -> Vec<f64> {
    let mut k = vec![0.0; 3];
    for s in 1..n_spans {
        k.push(s as f64);
        k.push(s as f64);
    }
    k.extend([n_spans as f64; 3]);
    k
}

/// Sweep one profile piece (in `(ρ, z)`) along one spine piece.
pub fn sweep(profile: &Piece, material: Material, spine: &Spine) -> Part {
    let (pc, pw) = profile.control();
    let t = profile.mid_tangent();
    let nrz = match material {
        Material::Left => [t[1], -t[0]],
        Material::Right => [-t[1], t[0]],
    };
    let mut points = Vec::new();
    let mut weights = Vec::new();
    let (degree_v, knots_v, count_v, out_mid) = match *spine {
        Spine::Line { p, dir, len, out } => {
            for i in 0..3 {
                for j in 0..2 {
                    let s = j as f64 * len;
                    let (rho, z) = (pc[i][0], pc[i][1]);
                    points.push(Vec3::new(
                        p[0] + s * dir[0] + rho * out[0],
                        p[1] + s * dir[1] + rho * out[1],
                        z,
                    ));
                    weights.push(pw[i]);
                }
            }
            (1, vec![0.0, 0.0, 1.0, 1.0], 2, out)
        }
        Spine::Arc {
            c,
            r0,
            a0,
            a1,
            sigma,
        } => {
            let h = 0.5 * (a1 - a0);
            let m = 0.5 * (a0 + a1);
            let k = [
                [a0.cos(), a0.sin()],
                [m.cos() / h.cos(), m.sin() / h.cos()],
                [a1.cos(), a1.sin()],
            ];
            let om = [1.0, h.cos(), 1.0];
            for i in 0..3 {
                let rr = r0 + sigma * pc[i][0];
                for j in 0..3 {
                    points.push(Vec3::new(
                        c[0] + rr * k[j][0],
                        c[1] + rr * k[j][1],
                        pc[i][1],
                    ));
                    weights.push(pw[i] * om[j]);
                }
            }
            (2, knots(1), 3, [sigma * m.cos(), sigma * m.sin()])
        }
    };
    Part {
        def: PatchDef {
            degree_u: 2,
            degree_v,
            knots_u: knots(1),
            knots_v,
            count_v,
            points,
            weights,
        },
        reference: Vec3::new(nrz[0] * out_mid[0], nrz[0] * out_mid[1], nrz[1]),
    }
}

/// A planar patch at height `z` ruled between two plan curves of the same
/// number of pieces (piece `k` of `inner` faces piece `k` of `outer`). The
/// blank-side normal is `+z` when `up`.
pub fn ruled(inner: &[Piece], outer: &[Piece], z: f64, up: bool) -> Part {
    let n = inner.len();
    let mut points = Vec::new();
    let mut weights = Vec::new();
    for k in 0..n {
        let (ic, iw) = inner[k].control();
        let (oc, ow) = outer[k].control();
        let first = if k == 0 { 0 } else { 1 };
        for i in first..3 {
            points.push(Vec3::new(ic[i][0], ic[i][1], z));
            weights.push(iw[i]);
            points.push(Vec3::new(oc[i][0], oc[i][1], z));
            weights.push(ow[i]);
        }
    }
    Part {
        def: PatchDef {
            degree_u: 2,
            degree_v: 1,
            knots_u: knots(n),
            knots_v: vec![0.0, 0.0, 1.0, 1.0],
            count_v: 2,
            points,
            weights,
        },
        reference: Vec3::new(0.0, 0.0, if up { 1.0 } else { -1.0 }),
    }
}

/// A flat bilinear rectangle `[x0, x1] × [y0, y1]` at height `z`.
pub fn rectangle(x: [f64; 2], y: [f64; 2], z: f64, up: bool) -> Part {
    let mut points = Vec::new();
    for xi in x {
        for yi in y {
            points.push(Vec3::new(xi, yi, z));
        }
    }
    Part {
        def: PatchDef {
            degree_u: 1,
            degree_v: 1,
            knots_u: vec![0.0, 0.0, 1.0, 1.0],
            knots_v: vec![0.0, 0.0, 1.0, 1.0],
            count_v: 2,
            points,
            weights: vec![1.0; 4],
        },
        reference: Vec3::new(0.0, 0.0, if up { 1.0 } else { -1.0 }),
    }
}

/// Apply `x ↦ diag(m) x + t` to a part (a reflection when an entry of `m` is -1).
pub fn mapped(part: &Part, m: [f64; 3], t: Vec3) -> Part {
    let mut p = part.clone();
    for q in &mut p.def.points {
        *q = Vec3::new(m[0] * q.x, m[1] * q.y, m[2] * q.z) + t;
    }
    let r = &part.reference;
    p.reference = Vec3::new(m[0] * r.x, m[1] * r.y, m[2] * r.z);
    p
}
