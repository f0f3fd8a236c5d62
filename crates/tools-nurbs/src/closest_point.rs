//! Closest point on one patch: bound-constrained Newton on `(u, v)` with a line search.
//!
//! Minimises `f(u, v) = ½ |S(u, v) - x|²` over the patch's parameter box. The
//! Hessian is the exact one (`S_a·S_b + (S - x)·S_ab`) while it is positive
//! definite and the Gauss–Newton one (`S_a·S_b`) otherwise. A variable sitting
//! on its bound with the step pushing outwards is frozen and the other one is
//! solved alone (1-D Newton along the edge); other steps are projected onto the
//! box; a halving line search keeps `f` from increasing. The iteration stops
//! when the physical step `|S_u δu + S_v δv|` falls below [`STEP_TOL`], and
//! returns the last evaluated point with its derivatives (so the caller has the
//! second derivatives for the curvature without another evaluation).
//!
//! On an affine piece (flat, linear parametrisation: `S_ab = 0`) Newton's step
//! is exact, so a step that stays inside the piece ends the iteration at once,
//! its point and derivatives taken from the step rather than a new evaluation
//! (a plane or a straight wall costs one evaluation). The current and trial
//! evaluations alternate between two slots, so accepting a step copies nothing.

use crate::surface::{Derivs, NurbsSurface};
use plugins_api::Vec3;

/// Newton stops when the physical step is below this length (mm).
pub const STEP_TOL: f64 = 1e-11;
const MAX_ITER: usize = 40;

/// A tangential residual above this (relative to `1 + distance`, mm) at an
/// interior answer means Newton stalled rather than converged.
pub const STALL_TOL: f64 = 1e-7;

/// A local closest point on one patch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PatchHit {
    /// Parameter u.
    pub u: f64,
    /// Parameter v.
    pub v: f64,
    /// Surface derivatives at `(u, v)`.
    pub d: Derivs,
    /// Squared distance (mm²) from the query point.
    pub dist2: f64,
    /// Whether the answer sits on the patch boundary with the distance still
    /// decreasing outwards (the true closest point may be on a neighbour), or
    /// Newton stalled inside the patch where the distance still decreases
    /// along the surface (on a knot where the parametrisation is only C⁰,
    /// whose kink the line search cannot step over): either way the answer
    /// is not a verified closest point and a search should follow.
    pub on_edge: bool,
}

/// Parameter box of a patch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamBox {
    /// `[u_min, u_max]`.
    pub u: [f64; 2],
    /// `[v_min, v_max]`.
    pub v: [f64; 2],
}

/// Whether a step `step` from `t` leaves the interval `b` at once: `t` sits on
/// a bound (within `eps`, see [`bound_eps`]) and the step points outwards.
#[inline]
fn pushes_out(t: f64, step: f64, b: [f64; 2], eps: f64) -> bool {
    (t <= b[0] + eps && step < 0.0) || (t >= b[1] - eps && step > 0.0)
}

/// A parameter a rounding error inside a bound counts as on it (a hint
/// saved from an edge answer comes back as 1e-17 inside).
#[inline]
fn bound_eps(b: [f64; 2]) -> f64 {
    1e-12 * (b[1] - b[0])
}

/// Local closest point of `surf` to `x` starting from `(u0, v0)`.
#[inline]
pub fn newton(surf: &NurbsSurface, dom: &ParamBox, x: &Vec3, u0: f64, v0: f64) -> PatchHit {
    let (mut d0, mut d1) = (Derivs::ZERO, Derivs::ZERO);
    let end = newton_in(surf, dom, x, u0, v0, [&mut d0, &mut d1]);
    PatchHit {
        u: end.u,
        v: end.v,
        d: if end.slot == 0 { d0 } else { d1 },
        dist2: end.dist2,
        on_edge: end.on_edge,
    }
}

/// Where [`newton_in`] stopped; the derivatives there are `ds[slot]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct NewtonEnd {
    /// Parameter u.
    pub u: f64,
    /// Parameter v.
    pub v: f64,
    /// Squared distance (mm²), as [`PatchHit::dist2`].
    pub dist2: f64,
    /// As [`PatchHit::on_edge`].
    pub on_edge: bool,
    /// Which slot (0 or 1) holds the derivatives at `(u, v)`.
    pub slot: usize,
}

/// [`newton`] on a caller's pair of evaluation slots: the current point's
/// derivatives and the trial point's alternate between `ds[0]` and `ds[1]`,
/// so an accepted step moves no data. (Two separate slots rather than one
/// array: each is small enough to be cleared inline.)
#[inline(always)]
pub(crate) fn newton_in(
    surf: &NurbsSurface,
    dom: &ParamBox,
    x: &Vec3,
    u0: f64,
    v0: f64,
    ds: [&mut Derivs; 2],
) -> NewtonEnd {
    let mut u = u0.clamp(dom.u[0], dom.u[1]);
    let mut v = v0.clamp(dom.v[0], dom.v[1]);
    let (eu, ev) = (bound_eps(dom.u), bound_eps(dom.v));
    let mut k = 0;
    let mut flat = surf.eval_into(u, v, &mut *ds[0]);
    let mut r = ds[0].s - x;
    let mut f = r.norm_squared();
    let mut on_edge = false;
    for _ in 0..MAX_ITER {
        let d = &*ds[k];
        let g = Gradient::at(d, &r);
        let Some((su, sv, edge)) = boxed_step(d, &r, &g, (u, v), dom, (eu, ev)) else {
            on_edge = true;
            break;
        };
        let (gu, gv, uu, uv, vv) = (g.gu, g.gv, g.uu, g.uv, g.vv);
        on_edge = edge;
        let un = (u + su).clamp(dom.u[0], dom.u[1]);
        let vn = (v + sv).clamp(dom.v[0], dom.v[1]);
        // The box cut the step: the minimum lies beyond an edge of this patch
        // (e.g. a hint a rounding error inside an edge, pushed out by Newton).
        let cut = un != u + su || vn != v + sv;
        let (su, sv) = (un - u, vn - v);
        // |S_u δu + S_v δv| from the first fundamental form already at hand.
        let step = (su * su * uu + 2.0 * su * sv * uv + sv * sv * vv)
            .max(0.0)
            .sqrt();
        if step < STEP_TOL * (1.0 + f.sqrt()) || !step.is_finite() {
            on_edge |= cut;
            break;
        }
        // On an affine piece Newton's step is exact: when it stays strictly
        // inside the piece, the new point and its (unchanged) derivatives
        // follow without an evaluation, and no further step is needed.
        if let Some(piece) = flat.filter(|_| !cut) {
            let b = surf.piece_bounds(piece);
            if un > b[0] && un < b[1] && vn > b[2] && vn < b[3] {
                let (s, dsu, dsv) = (d.s + d.su * su + d.sv * sv, d.su, d.sv);
                *ds[1 - k] = Derivs {
                    s,
                    su: dsu,
                    sv: dsv,
                    ..Derivs::ZERO
                };
                (u, v, k) = (un, vn, 1 - k);
                r = s - x;
                f = r.norm_squared();
                break;
            }
        }
        // Near the minimum f no longer resolves the tangential error (it
        // changes by less than its rounding), so a step that keeps f within
        // rounding and reduces the tangential residual is accepted too.
        let mut t = 1.0;
        let mut accepted = false;
        let mut flat_t = None;
        for _ in 0..12 {
            let ut = u + t * su;
            let vt = v + t * sv;
            flat_t = surf.eval_into(ut, vt, &mut *ds[1 - k]);
            let dt = &*ds[1 - k];
            let rt = dt.s - x;
            let ft = rt.norm_squared();
            let ok = ft <= f || {
                let gtu = rt.dot(&dt.su);
                let gtv = rt.dot(&dt.sv);
                ft <= f * (1.0 + 1e-12) + 1e-300
                    && gtu * gtu / dt.su.norm_squared() + gtv * gtv / dt.sv.norm_squared()
                        < gu * gu / uu + gv * gv / vv
            };
            if ok {
                (u, v, r, f) = (ut, vt, rt, ft);
                k = 1 - k;
                accepted = true;
                break;
            }
            t *= 0.5;
        }
        // A full, uncut step within one affine piece reached the exact
        // minimum: the next step would vanish to rounding, so skip it.
        if accepted && t == 1.0 && !cut && flat.is_some() && flat == flat_t {
            break;
        }
        flat = flat_t;
        if !accepted || step * t < STEP_TOL {
            on_edge |= cut;
            break;
        }
    }
    if !on_edge {
        on_edge = ends_on_edge(&*ds[k], &r, f, (u, v), dom, (eu, ev));
    }
    NewtonEnd {
        u,
        v,
        dist2: f,
        on_edge,
        slot: k,
    }
}

/// The squared-distance function's gradient `(r·S_u, r·S_v)` at a point and
/// the first fundamental form `(S_u·S_u, S_u·S_v, S_v·S_v)`.
struct Gradient {
    gu: f64,
    gv: f64,
    uu: f64,
    uv: f64,
    vv: f64,
}

impl Gradient {
    #[inline(always)]
    fn at(d: &Derivs, r: &Vec3) -> Self {
        Self {
            gu: r.dot(&d.su),
            gv: r.dot(&d.sv),
            uu: d.su.norm_squared(),
            uv: d.su.dot(&d.sv),
            vv: d.sv.norm_squared(),
        }
    }
}

/// Newton's step `(δu, δv)` from `(u, v)` for the residual `r = S − x`
/// (the Hessian, or the first fundamental form where the Hessian is not
/// positive definite), with a parameter that the step would push out of the
/// box held at its bound and the step taken along the other one only
/// (`true`: on an edge). `None`: both would push out, or the one left would.
#[inline(always)]
fn boxed_step(
    d: &Derivs,
    r: &Vec3,
    g: &Gradient,
    (u, v): (f64, f64),
    dom: &ParamBox,
    (eu, ev): (f64, f64),
) -> Option<(f64, f64, bool)> {
    let Gradient { gu, gv, uu, uv, vv } = *g;
    let (mut huu, mut huv, mut hvv) = (uu + r.dot(&d.suu), uv + r.dot(&d.suv), vv + r.dot(&d.svv));
    if !(huu > 0.0 && hvv > 0.0 && huu * hvv - huv * huv > 1e-12 * uu * vv) {
        (huu, huv, hvv) = (uu, uv, vv);
    }
    let idet = 1.0 / (huu * hvv - huv * huv);
    let su = -(hvv * gu - huv * gv) * idet;
    let sv = -(huu * gv - huv * gu) * idet;
    let fix_u = pushes_out(u, su, dom.u, eu);
    let fix_v = pushes_out(v, sv, dom.v, ev);
    if fix_u && fix_v {
        None
    } else if fix_u {
        let sv = -gv / hvv;
        (!pushes_out(v, sv, dom.v, ev)).then_some((0.0, sv, true))
    } else if fix_v {
        let su = -gu / huu;
        (!pushes_out(u, su, dom.u, eu)).then_some((su, 0.0, true))
    } else {
        Some((su, sv, false))
    }
}

/// Whether a Newton run that ended at `(u, v)` (derivatives `d`, residual
/// `r`, `f = |r|²`) without reaching an edge is really on one: strictly
/// inside, a stall whose tangential residual `|r·S_a|/|S_a|` (mm) is above
/// rounding (a kink); on a bound, a gradient pointing out of the box.
#[inline(always)]
fn ends_on_edge(
    d: &Derivs,
    r: &Vec3,
    f: f64,
    (u, v): (f64, f64),
    dom: &ParamBox,
    (eu, ev): (f64, f64),
) -> bool {
    let gu = r.dot(&d.su) / d.su.norm();
    let gv = r.dot(&d.sv) / d.sv.norm();
    let at_bound = u <= dom.u[0] || u >= dom.u[1] || v <= dom.v[0] || v >= dom.v[1];
    if !at_bound {
        // Newton stopped at a step of STEP_TOL: a converged answer's
        // tangential residual is at rounding level; on a kink it is a
        // fraction of the distance.
        let tol = STALL_TOL * (1.0 + f.sqrt());
        return gu.abs() > tol || gv.abs() > tol;
    }
    let eps = 1e-12 * (1.0 + f.sqrt());
    let gu = if gu.abs() <= eps { 0.0 } else { gu };
    let gv = if gv.abs() <= eps { 0.0 } else { gv };
    pushes_out(u, -gu, dom.u, eu) || pushes_out(v, -gv, dom.v, ev)
}
