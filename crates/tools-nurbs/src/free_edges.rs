//! Free edges of an open tool and the sharp-edge rule for points beyond them.
//!
//! A side of a patch (`u = u_min`, `u = u_max`, `v = v_min`, `v = v_max`) is
//! **free** when the tool has no surface along it: no other patch (a seam, or
//! an overlapping patch such as the S-rail's apron under the swept flange's
//! outer edge) and not the same patch's opposite side (a closed cylinder).
//! The sides are classified once, when the tool is built, by sampling
//! [`SAMPLES`] points along each side and asking whether every one of them
//! lies on some other part of the tool within [`ON_SURFACE_TOL`].
//!
//! **The rule.** When the closest point `p` of a query point `x` lies on a
//! free side and `x` is beyond it (`r = x − p` has a positive component along
//! the side's outward tangent: the distance still decreases out of the
//! patch), the tool there is a bare edge, a line with nothing behind it. The
//! answer is then the distance to that line, `|r|`, **positive** (nothing is
//! inside a bare edge), with the direction `r / |r|` as the normal and zero
//! curvature. A blank node that has slid off the end of an open tool sheet
//! therefore feels the edge only while it is within its own half thickness of
//! it (wrapping round it, pushed radially away), and nothing once it is
//! farther, above or below the sheet's plane; on the normal line itself
//! (`r ∥ n`) the rule gives the face's own answer, so the normal turns
//! continuously from the face round the edge. Inside the patch, and on
//! sides that are not free, nothing changes.

use crate::closest_point::ParamBox;
use crate::nurbs_tool::OrientedPatch;
use crate::surface::Derivs;
use plugins_api::Vec3;

/// Points sampled along each side to classify it.
pub const SAMPLES: usize = 9;

/// A side point closer than this (mm) to another part of the tool is covered.
pub const ON_SURFACE_TOL: f64 = 1e-6;

/// Which sides of one patch are free, in the order `u_min`, `u_max`,
/// `v_min`, `v_max`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FreeSides(pub [bool; 4]);

impl FreeSides {
    /// Whether any side is free.
    #[inline]
    pub fn any(&self) -> bool {
        self.0.iter().any(|&f| f)
    }

    /// Whether the point `x` (local frame) whose closest point on the patch
    /// is `d.s` at `(u, v)` lies beyond a free side of the patch (box `dom`):
    /// `(u, v)` on that side (within a rounding error of the bound) and
    /// `x − S` pointing out of the patch across it.
    #[inline]
    pub fn beyond(&self, dom: &ParamBox, u: f64, v: f64, d: &Derivs, x: &Vec3) -> bool {
        let [umin, umax, vmin, vmax] = self.0;
        let (eu, ev) = (1e-12 * (dom.u[1] - dom.u[0]), 1e-12 * (dom.v[1] - dom.v[0]));
        let r = x - d.s;
        // Outward along the side: −S_u on u_min, +S_u on u_max, likewise v.
        let tol = 1e-12 * r.norm();
        (umin && u <= dom.u[0] + eu && -r.dot(&d.su) > tol * d.su.norm())
            || (umax && u >= dom.u[1] - eu && r.dot(&d.su) > tol * d.su.norm())
            || (vmin && v <= dom.v[0] + ev && -r.dot(&d.sv) > tol * d.sv.norm())
            || (vmax && v >= dom.v[1] - ev && r.dot(&d.sv) > tol * d.sv.norm())
    }
}

/// The point of side `side` (0: `u_min`, 1: `u_max`, 2: `v_min`, 3:
/// `v_max`) at the fraction `f` of its length, and the parameters of the
/// opposite side's point with the same other parameter.
fn side_params(dom: &ParamBox, side: usize, f: f64) -> ((f64, f64), (f64, f64)) {
    let along = |b: [f64; 2]| b[0] + (b[1] - b[0]) * f;
    match side {
        0 => ((dom.u[0], along(dom.v)), (dom.u[1], along(dom.v))),
        1 => ((dom.u[1], along(dom.v)), (dom.u[0], along(dom.v))),
        2 => ((along(dom.u), dom.v[0]), (along(dom.u), dom.v[1])),
        _ => ((along(dom.u), dom.v[1]), (along(dom.u), dom.v[0])),
    }
}

/// Classify the sides of every patch (see the module docs). `boxes[i]` is
/// patch `i`'s bounding box (local frame), used to skip far patches, and
/// `distance(k, q)` the distance (mm) from `q` to patch `k` (its closest
/// point, local frame).
pub fn classify(
    patches: &[OrientedPatch],
    domains: &[ParamBox],
    boxes: &[plugins_api::Aabb],
    distance: impl Fn(usize, &Vec3) -> f64,
) -> Vec<FreeSides> {
    let mut out = Vec::with_capacity(patches.len());
    for (i, (p, dom)) in patches.iter().zip(domains).enumerate() {
        let mut free = [false; 4];
        for (side, f_side) in free.iter_mut().enumerate() {
            *f_side = (0..SAMPLES).any(|j| {
                let f = (j as f64 + 0.5) / SAMPLES as f64;
                let ((u, v), (uo, vo)) = side_params(dom, side, f);
                let q = p.surface.point(u, v);
                let closed = (p.surface.point(uo, vo) - q).norm() <= ON_SURFACE_TOL;
                let covered = closed
                    || (0..patches.len()).any(|k| {
                        k != i
                            && boxes[k].inflated(ON_SURFACE_TOL).contains(&q)
                            && distance(k, &q) <= ON_SURFACE_TOL
                    });
                !covered
            });
        }
        out.push(FreeSides(free));
    }
    out
}
