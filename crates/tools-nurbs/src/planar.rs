//! Planar patches: a warm projection at the price of one evaluation.
//!
//! A patch whose control points all lie in one plane lies in that plane (the
//! convex hull of a net with positive weights). For such a patch the closest
//! point of a query point `x` is the foot of the perpendicular from `x` on the
//! plane whenever that foot is inside the patch, so the point, the normal and
//! the signed distance of the answer follow from the plane exactly, whatever
//! the parametrisation (the die face and the blankholder of the square cup are
//! planar patches with rational quadratic parametrisations along the
//! opening's rounded outline, which Newton needs two or three rational
//! evaluations to invert).
//!
//! Only the parameters `(u, v)` of the foot need the parametrisation: they
//! serve as the next warm start and decide whether the foot lies inside the
//! patch. From the hint `(u₀, v₀)` (the last answer of the same point) one
//! evaluation gives `S` and its first and second derivatives; one
//! Gauss–Newton step of `S(u, v) = foot` gives the step `δ`, and the
//! second-order term it leaves, `½ S''(δ, δ)`, mapped back to the parameters,
//! gives a correction `ε`: `(u, v) = (u₀, v₀) + δ − ε`, off by `O(|δ|³)`.
//! A node moves a fraction of an element per explicit step, so `δ` is tiny
//! and the parameters are as good as Newton's; the error does not
//! accumulate, because the next projection evaluates the surface at the
//! updated parameters. With `δ` and `ε` in units of the parameter widths of
//! the hint's Bézier piece (the parametrisation may be only C⁰ across the
//! knots between pieces, so the expansion holds within one), the foot is
//! accepted only when
//! - `|δ| ≤` [`MAX_STEP`] and `|ε| ≤` [`MAX_CORRECTION`]` |δ|` (the expansion
//!   converges: a parametrisation that curves strongly over the step, like
//!   the ruled die face near the opening's small corner radius, is left to
//!   Newton), and
//! - the corrected `(u, v)` lie inside the piece's parameter box by more
//!   than `2 |ε|` plus [`EDGE_MARGIN`],
//!
//! so that the true parameters are inside the piece, and so the patch,
//! too; otherwise the caller runs the
//! bound-constrained Newton as for any patch.

use crate::closest_point::ParamBox;
use crate::nurbs_tool::OrientedPatch;
use crate::surface::{Derivs, NurbsSurface};
use plugins_api::{FlatRegion, Vec3};

/// Control points within this fraction of the net's bounding-box diagonal of
/// one plane make a planar patch.
pub const PLANAR_TOL: f64 = 1e-12;

/// Largest parameter step (in units of the piece's parameter widths) taken
/// by the planar warm projection; a larger move falls back on Newton.
pub const MAX_STEP: f64 = 1e-2;

/// Largest second-order correction, as a fraction of the step, for which
/// the corrected parameters are trusted (the expansion in the step converges
/// fast); a parametrisation curving more over the step falls back on Newton.
pub const MAX_CORRECTION: f64 = 0.1;

/// Normalised distance from the piece's parameter bounds under which the
/// planar warm projection falls back on Newton (which settles edges).
pub const EDGE_MARGIN: f64 = 1e-9;

/// The plane of a planar patch in the tool's local frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    /// Unit normal towards the blank side (the patch's orientation).
    pub normal: Vec3,
    /// `normal · p` for the points `p` of the plane (mm).
    pub offset: f64,
}

/// The plane of `patch` when all its control points lie in one (to
/// [`PLANAR_TOL`] of the net's diagonal), oriented like the patch.
pub fn plane_of(patch: &OrientedPatch, dom: &ParamBox) -> Option<Plane> {
    let s = &patch.surface;
    let d = s.eval(0.5 * (dom.u[0] + dom.u[1]), 0.5 * (dom.v[0] + dom.v[1]));
    let c = d.su.cross(&d.sv);
    let normal = c * (patch.sign / c.norm());
    let (mut lo, mut hi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
    for p in s.control_points() {
        lo = lo.inf(&p);
        hi = hi.sup(&p);
    }
    let tol = PLANAR_TOL * (hi - lo).norm();
    let flat = normal.iter().all(|c| c.is_finite())
        && s.control_points()
            .all(|p| (p - d.s).dot(&normal).abs() <= tol);
    flat.then_some(Plane {
        normal,
        offset: normal.dot(&d.s),
    })
}

/// A planar warm answer: the foot's parameters and its unsigned distance;
/// `Derivs::s` of the slot written is the foot, `su` and `sv` the tangents
/// at the hint, the second derivatives zero.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanarHit {
    /// Parameter `u` of the foot (first-order update of the hint).
    pub u: f64,
    /// Parameter `v` of the foot.
    pub v: f64,
    /// Unsigned distance from the query point to the plane (mm).
    pub dist: f64,
    /// The second-order correction applied to `(u, v)`, in units of the
    /// piece's parameter widths: the estimate of the first-order update's error; the
    /// corrected parameters are off by a small fraction of it.
    pub error: f64,
}

/// The closest point of the planar patch `surf` (plane `plane`, parameter
/// box `dom`) to `x` (local frame), warm-started at `(u0, v0)`, written into
/// `out`; `None` when the foot is not provably inside the patch (see the
/// module docs), and the caller must run Newton.
#[inline]
pub fn warm(
    surf: &NurbsSurface,
    dom: &ParamBox,
    plane: &Plane,
    x: &Vec3,
    u0: f64,
    v0: f64,
    out: &mut Derivs,
) -> Option<PlanarHit> {
    let u0 = u0.clamp(dom.u[0], dom.u[1]);
    let v0 = v0.clamp(dom.v[0], dom.v[1]);
    // The expansion holds within the hint's Bézier piece (the
    // parametrisation may be only C⁰ across the knots between pieces).
    let [pu0, pu1, pv0, pv1] = surf.eval_boxed(u0, v0, out);
    // The height from the plane's own offset, not from the evaluated point:
    // the answer does not depend on the hint it was warm-started from.
    let height = x.dot(&plane.normal) - plane.offset;
    let foot = x - plane.normal * height;
    let delta = foot - out.s;
    let (uu, uv, vv) = (
        out.su.norm_squared(),
        out.su.dot(&out.sv),
        out.sv.norm_squared(),
    );
    let (gu, gv) = (out.su.dot(&delta), out.sv.dot(&delta));
    let idet = 1.0 / (uu * vv - uv * uv);
    let du = (vv * gu - uv * gv) * idet;
    let dv = (uu * gv - uv * gu) * idet;
    // The second-order term the Gauss–Newton step leaves, ½ S''(δ, δ), and
    // the parameter correction it asks for (in the tangent plane).
    let r2 = (out.suu * (du * du) + out.suv * (2.0 * du * dv) + out.svv * (dv * dv)) * 0.5;
    let (hu, hv) = (out.su.dot(&r2), out.sv.dot(&r2));
    let eu = (vv * hu - uv * hv) * idet;
    let ev = (uu * hv - uv * hu) * idet;
    let (wu, wv) = (pu1 - pu0, pv1 - pv0);
    let step = (du / wu).abs().max((dv / wv).abs());
    let error = (eu / wu).abs().max((ev / wv).abs());
    // `!(… <= …)` also refuses a NaN.
    if !(step <= MAX_STEP && error <= MAX_CORRECTION * step) {
        return None;
    }
    let (u, v) = (u0 + du - eu, v0 + dv - ev);
    let margin = 2.0 * error + EDGE_MARGIN;
    let inside = (u - pu0) / wu > margin
        && (pu1 - u) / wu > margin
        && (v - pv0) / wv > margin
        && (pv1 - v) / wv > margin;
    if !inside {
        return None;
    }
    out.s = foot;
    out.suu = Vec3::zeros();
    out.suv = Vec3::zeros();
    out.svv = Vec3::zeros();
    Some(PlanarHit {
        u,
        v,
        dist: height.abs(),
        error,
    })
}

/// Segments per knot span along each edge of a planar patch's [`Outline`].
pub const OUTLINE_SEGMENTS: usize = 16;

/// A flat region ([`FlatRegion`]) is offered only around parameters at least
/// this fraction of the patch's parameter widths from its edges (closer, a
/// node would leave a small disc within a few steps, and the warm projection
/// is cheaper than finding a new one every time).
pub const REGION_PARAM_MARGIN: f64 = 0.01;

/// A flat region's radius, as a fraction of the distance from its centre to
/// the patch's outline: a node moving straight out crosses the disc's edge
/// half way to the patch's, so the next region is half as large, and nodes
/// find a new region a few times on their way to an edge, not every step.
pub const REGION_FRACTION: f64 = 0.5;

/// The edges of a planar patch as a polyline (local frame), with a bound on
/// how far the true edges stray from it.
#[derive(Debug, Clone, PartialEq)]
pub struct Outline {
    segments: Vec<[Vec3; 2]>,
    /// Twice the largest distance of an edge's mid-segment point from its
    /// chord (mm): the chords' sagitta, with a factor two for safety.
    sag: f64,
}

impl Outline {
    /// The outline of `surf` over `dom`: [`OUTLINE_SEGMENTS`] chords per knot
    /// span along each of the four edges.
    pub fn of(surf: &NurbsSurface, dom: &ParamBox) -> Self {
        let mut segments = Vec::new();
        let mut sag = 0.0f64;
        let mut edge = |at: &dyn Fn(f64) -> (f64, f64), spans: &[(f64, f64)]| {
            for &(a, b) in spans {
                for i in 0..OUTLINE_SEGMENTS {
                    let t = |k: f64| a + (b - a) * k / OUTLINE_SEGMENTS as f64;
                    let (t0, t1) = (t(i as f64), t(i as f64 + 1.0));
                    let point = |t: f64| {
                        let (u, v) = at(t);
                        surf.point(u, v)
                    };
                    let (p0, p1) = (point(t0), point(t1));
                    sag = sag.max(segment_distance(&point(0.5 * (t0 + t1)), &[p0, p1]));
                    segments.push([p0, p1]);
                }
            }
        };
        let (su, sv) = (surf.spans_u(), surf.spans_v());
        edge(&|t| (t, dom.v[0]), &su);
        edge(&|t| (t, dom.v[1]), &su);
        edge(&|t| (dom.u[0], t), &sv);
        edge(&|t| (dom.u[1], t), &sv);
        Self {
            segments,
            sag: 2.0 * sag,
        }
    }

    /// A lower bound on the distance (mm) from `p` to the patch's edges.
    pub fn clearance(&self, p: &Vec3) -> f64 {
        let d = self
            .segments
            .iter()
            .map(|s| segment_distance(p, s))
            .fold(f64::INFINITY, f64::min);
        d - self.sag
    }
}

/// Distance (mm) from `p` to the segment `s`.
fn segment_distance(p: &Vec3, s: &[Vec3; 2]) -> f64 {
    let d = s[1] - s[0];
    let len2 = d.norm_squared();
    let t = if len2 > 0.0 {
        ((p - s[0]).dot(&d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (s[0] + d * t - p).norm()
}

/// The flat region around the point `(u, v)` of the planar patch `surf`
/// (plane `plane`, outline `outline`, parameter box `dom`): a disc centred at
/// the point, of radius [`REGION_FRACTION`] of its clearance from the
/// outline; `None` within [`REGION_PARAM_MARGIN`] of an edge.
pub fn region(
    surf: &NurbsSurface,
    dom: &ParamBox,
    plane: &Plane,
    outline: &Outline,
    u: f64,
    v: f64,
) -> Option<FlatRegion> {
    let (wu, wv) = (dom.u[1] - dom.u[0], dom.v[1] - dom.v[0]);
    let margin = ((u - dom.u[0]) / wu)
        .min((dom.u[1] - u) / wu)
        .min((v - dom.v[0]) / wv)
        .min((dom.v[1] - v) / wv);
    if margin.is_nan() || margin < REGION_PARAM_MARGIN {
        return None;
    }
    let s = surf.point(u, v);
    let centre = s - plane.normal * (s.dot(&plane.normal) - plane.offset);
    let radius = REGION_FRACTION * outline.clearance(&centre);
    (radius > 0.0).then_some(FlatRegion {
        normal: plane.normal,
        offset: plane.offset,
        centre,
        radius,
    })
}
