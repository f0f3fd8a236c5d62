//! Curved patches with a closed-form projection: exact circular cylinders
//! and tori, recognised from their control nets when the tool is built.
//!
//! The die and punch radii of the forming tools are circular arcs swept
//! along straight lines (cylinders) and about plan corners (tori), and their
//! corner walls are straight lines swept about an arc (cylinders). A patch
//! is recognised as one of them only when its net proves it, to round-off
//! ([`CURVED_TOL`] of the net's diagonal, and of the weight ratios), as one
//! Bézier piece each way:
//!
//! - **circular arc**: a rational quadratic with equal end weights, equal
//!   legs `L` and middle weight ratio `w₁/w₀ = cos h`, `2h` the angle the
//!   legs turn (the chord is `2 L cos h`): exactly the arc of radius
//!   `L / tan h` tangent to both legs, over the angle `2h`;
//! - **extrusion**: every row of the second direction is the first row
//!   translated by `(j/q) D` with the same weights, so `S(u, v) = C(u) + v D`;
//!   an arc `C` in the plane normal to `D` makes a right circular cylinder;
//! - **revolution**: every row of the second direction is a circular arc
//!   about one axis, with the same angles and weight ratios, starting in one
//!   meridian half-plane; then `S(u, v) = Rot(α(v)) C(u)` with `C` the first
//!   column (each row's homogeneous sum rotates its start about the axis by
//!   the same `α(v)`). A circular-arc `C` in the meridian plane makes a
//!   torus (its centre on the spine circle), a straight `C` parallel to the
//!   axis a cylinder.
//!
//! Such a patch gets a [`CurvedRegion`] (the closed form is in plugins-api):
//! the whole patch less a margin of [`CURVED_EDGE_MARGIN`] of its angles and
//! lengths, so that a foot the closed form puts inside is inside for Newton
//! too. A torus is accepted only when its tube does not cross the axis over
//! the patch (every point at distance `radius` from the spine circle, which
//! the closed form's proof needs). As a guard against a wrong recognition,
//! a grid of points of the patch must lie on the recognised tube to 1e-9 of
//! its size, with the patch's normal along the tube's.

use crate::closest_point::ParamBox;
use crate::nurbs_tool::OrientedPatch;
use plugins_api::{CurvedRegion, CurvedShape, Vec3};

/// Positions within this fraction of the net's diagonal, and weight ratios
/// within this, count as equal.
pub const CURVED_TOL: f64 = 1e-11;

/// The part of a curved patch's angles and lengths left out at each of its
/// edges: a foot nearer an edge is left to Newton (which settles edges).
pub const CURVED_EDGE_MARGIN: f64 = 1e-6;

/// A circular arc recognised from a rational quadratic.
#[derive(Debug, Clone, Copy)]
struct Arc {
    centre: Vec3,
    /// Unit normal of the arc's plane.
    normal: Vec3,
    radius: f64,
    /// Half the angle the arc turns (rad).
    half: f64,
    /// Unit direction from the centre to the arc's middle.
    mid: Vec3,
}

/// The circular arc of the rational quadratic `p`, `w`, if it is one.
fn arc(p: [Vec3; 3], w: [f64; 3], tol: f64) -> Option<Arc> {
    let (l0, l2) = ((p[1] - p[0]).norm(), (p[2] - p[1]).norm());
    let l = 0.5 * (l0 + l2);
    let cos_h = (p[2] - p[0]).norm() / (2.0 * l);
    let same = (w[0] - w[2]).abs() <= CURVED_TOL * w[0]
        && (l0 - l2).abs() <= tol
        && l > tol
        && cos_h > 0.0
        && cos_h < 1.0 - 1e-9
        && (w[1] / w[0] - cos_h).abs() <= CURVED_TOL;
    if !same {
        return None;
    }
    let sin_h = (1.0 - cos_h * cos_h).sqrt();
    let to_chord = 0.5 * (p[0] + p[2]) - p[1];
    let towards = to_chord / to_chord.norm();
    Some(Arc {
        centre: p[1] + towards * (l / sin_h),
        normal: (p[1] - p[0]).cross(&(p[2] - p[1])).normalize(),
        radius: l * cos_h / sin_h,
        half: cos_h.acos(),
        mid: -towards,
    })
}

/// The end points of the curve `p`, `w` (degree 1 or 2) if it is a straight
/// segment with a linear parametrisation (equal weights, evenly spaced points).
fn segment(p: &[Vec3], w: &[f64], tol: f64) -> Option<(Vec3, Vec3)> {
    let n = p.len() - 1;
    let (a, b) = (p[0], p[n]);
    let even = (0..=n).all(|k| {
        (w[k] - w[0]).abs() <= CURVED_TOL * w[0]
            && (p[k] - (a + (b - a) * (k as f64 / n as f64))).norm() <= tol
    });
    (even && (b - a).norm() > tol).then_some((a, b))
}

/// Unit vectors equal to round-off.
fn parallel(a: &Vec3, b: &Vec3) -> bool {
    (a - b).norm() <= 1e3 * CURVED_TOL
}

/// The cosine of an angular half-range `half` less the margin.
fn shrunk_cos(half: f64) -> f64 {
    (half * (1.0 - 2.0 * CURVED_EDGE_MARGIN)).cos()
}

/// The control net of one Bézier piece, read along `(i, j)` with `i` the
/// first parametric direction unless transposed.
struct Net {
    points: Vec<Vec3>,
    weights: Vec<f64>,
    count_v: usize,
    transposed: bool,
    /// Degrees along `i` and `j`.
    deg: [usize; 2],
}

impl Net {
    fn at(&self, i: usize, j: usize) -> (Vec3, f64) {
        let k = if self.transposed {
            j * self.count_v + i
        } else {
            i * self.count_v + j
        };
        (self.points[k], self.weights[k])
    }

    /// The curve along `i` at `j`.
    fn column(&self, j: usize) -> (Vec<Vec3>, Vec<f64>) {
        (0..=self.deg[0]).map(|i| self.at(i, j)).unzip()
    }

    /// The curve along `j` at `i`, if quadratic.
    fn row3(&self, i: usize) -> Option<([Vec3; 3], [f64; 3])> {
        (self.deg[1] == 2).then(|| {
            let (a, b, c) = (self.at(i, 0), self.at(i, 1), self.at(i, 2));
            ([a.0, b.0, c.0], [a.1, b.1, c.1])
        })
    }
}

/// A cylinder swept along `j`: every row a translate of the first column.
fn extrusion(net: &Net, tol: f64) -> Option<CurvedRegion> {
    let (p, w) = net.column(0);
    let c = arc(p.clone().try_into().ok()?, w.clone().try_into().ok()?, tol)?;
    let q = net.deg[1];
    let d = net.at(0, q).0 - net.at(0, 0).0;
    let len = d.norm();
    let axis = d / len;
    let swept = (0..=net.deg[0]).all(|i| {
        (0..=q).all(|j| {
            let (pj, wj) = net.at(i, j);
            (pj - p[i] - d * (j as f64 / q as f64)).norm() <= tol
                && (wj - w[i]).abs() <= CURVED_TOL * w[i]
        })
    });
    (swept && len > tol && (parallel(&axis, &c.normal) || parallel(&axis, &-c.normal))).then(|| {
        let m = CURVED_EDGE_MARGIN * len;
        CurvedRegion {
            origin: c.centre,
            axis,
            radius: c.radius,
            side: 1.0,
            mid: c.mid,
            cos_half: shrunk_cos(c.half),
            shape: CurvedShape::Cylinder {
                along: [m, len - m],
            },
        }
    })
}

/// A cylinder or torus swept about an axis along `j`.
fn revolution(net: &Net, tol: f64) -> Option<CurvedRegion> {
    let rows: Vec<Arc> = (0..=net.deg[0])
        .map(|i| net.row3(i).and_then(|(p, w)| arc(p, w, tol)))
        .collect::<Option<_>>()?;
    let r0 = rows[0];
    let (axis, start) = (r0.normal, (net.at(0, 0).0 - r0.centre).normalize());
    let coaxial = rows.iter().enumerate().all(|(i, a)| {
        parallel(&a.normal, &axis)
            && (a.half - r0.half).abs() <= CURVED_TOL
            && (a.centre - r0.centre).cross(&axis).norm() <= tol
            && parallel(&(net.at(i, 0).0 - a.centre).normalize(), &start)
    });
    if !coaxial {
        return None;
    }
    let (p, w) = net.column(0);
    let cos_half = shrunk_cos(r0.half);
    if let Some((a, b)) = segment(&p, &w, tol) {
        // A straight profile parallel to the axis: a cylinder about it.
        let (za, zb) = ((a - r0.centre).dot(&axis), (b - r0.centre).dot(&axis));
        let radius = (a - r0.centre - axis * za).norm();
        let rb = (b - r0.centre - axis * zb).norm();
        let (lo, hi) = (za.min(zb), za.max(zb));
        let m = CURVED_EDGE_MARGIN * (hi - lo);
        let straight =
            parallel(&(b - a).normalize(), &axis) || parallel(&(a - b).normalize(), &axis);
        return (straight && (radius - rb).abs() <= tol).then_some(CurvedRegion {
            origin: r0.centre,
            axis,
            radius,
            side: 1.0,
            mid: r0.mid,
            cos_half,
            shape: CurvedShape::Cylinder {
                along: [lo + m, hi - m],
            },
        });
    }
    let tube = arc(p.try_into().ok()?, w.try_into().ok()?, tol)?;
    // The profile's plane is the meridian plane of `start`.
    if !parallel(&tube.normal, &start.cross(&axis)) && !parallel(&tube.normal, &-start.cross(&axis))
    {
        return None;
    }
    let origin = r0.centre + axis * (tube.centre - r0.centre).dot(&axis);
    let off = tube.centre - origin;
    let spine = off.norm();
    if spine > tol && off.dot(&start) < 0.0 {
        return None;
    }
    let spine = if spine > tol { spine } else { 0.0 };
    let tube_mid = [tube.mid.dot(&start), tube.mid.dot(&axis)];
    // The tube must not cross the axis over the patch: the distance off the
    // axis, spine + radius cos θ, is smallest at an end or at θ = π.
    let ends = [net.at(0, 0).0, net.at(net.deg[0], 0).0];
    let crosses = ends.iter().any(|e| (e - origin).dot(&start) < -tol)
        || (-tube_mid[0] >= tube.half.cos() && spine < tube.radius);
    (!crosses).then_some(CurvedRegion {
        origin,
        axis,
        radius: tube.radius,
        side: 1.0,
        mid: r0.mid,
        cos_half,
        shape: CurvedShape::Torus {
            spine,
            tube_mid,
            tube_cos: shrunk_cos(tube.half),
        },
    })
}

/// The outward tube direction at the point `s` of the tube of `r`, and how
/// far `s` lies from the tube (mm).
fn tube_direction(r: &CurvedRegion, s: &Vec3) -> (Vec3, f64) {
    let w = s - r.origin;
    let z = w.dot(&r.axis);
    let radial = w - r.axis * z;
    let q = match r.shape {
        CurvedShape::Cylinder { .. } => radial,
        CurvedShape::Torus { spine, .. } => {
            let rho = radial.norm();
            let e = if rho > 0.0 { radial / rho } else { r.mid };
            w - e * spine
        }
    };
    let n = q.norm();
    (q / n, (n - r.radius).abs())
}

/// The curved region of `patch` (parameter box `dom`) if it is exactly a
/// circular cylinder or torus (see the module docs), oriented like the
/// patch.
pub fn curved_of(patch: &OrientedPatch, dom: &ParamBox) -> Option<CurvedRegion> {
    let s = &patch.surface;
    let (p, q) = s.degrees();
    if s.spans_u().len() != 1 || s.spans_v().len() != 1 || s.net_size() != (p + 1, q + 1) {
        return None;
    }
    let points: Vec<Vec3> = s.control_points().collect();
    let weights: Vec<f64> = s.weights().collect();
    let (mut lo, mut hi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
    for c in &points {
        lo = lo.inf(c);
        hi = hi.sup(c);
    }
    let size = (hi - lo).norm();
    let tol = CURVED_TOL * size;
    let found = [false, true].into_iter().find_map(|transposed| {
        let net = Net {
            points: points.clone(),
            weights: weights.clone(),
            count_v: q + 1,
            transposed,
            deg: if transposed { [q, p] } else { [p, q] },
        };
        if net.deg[0] != 2 {
            return None;
        }
        extrusion(&net, tol).or_else(|| revolution(&net, tol))
    })?;
    // Orientation, and the guard: a grid of the patch on the tube, with
    // the patch's normal along the tube's direction.
    const GRID: usize = 5;
    let mut side = 0.0;
    for a in 0..GRID {
        for b in 0..GRID {
            let f = |k: usize, r: [f64; 2]| r[0] + (r[1] - r[0]) * k as f64 / (GRID - 1) as f64;
            let d = s.eval(f(a, dom.u), f(b, dom.v));
            let n = d.su.cross(&d.sv).normalize() * patch.sign;
            let (t, off) = tube_direction(&found, &d.s);
            let along = n.dot(&t);
            if !(off <= 1e-9 * size && along.abs() > 1.0 - 1e-9) {
                return None;
            }
            if side == 0.0 {
                side = along.signum();
            } else if side != along.signum() {
                return None;
            }
        }
    }
    Some(CurvedRegion { side, ..found })
}
