//! A multi-patch rigid NURBS tool: oriented patches, a BVH over their knot spans, warm and cold projection.
//!
//! Projection (local frame; the pose maps in and out):
//! - **warm**: Newton on the hinted patch from the hinted `(u, v)`; an
//!   interior answer is returned at once (the explicit-step fast path, no
//!   allocation). An answer clamped on the patch boundary, or an invalid hint,
//!   continues with the cold search, bounded by the warm answer's distance.
//! - **cold**: nearest-box-first traversal of the BVH over knot spans (boxes
//!   of the spans' control points, conservative by the convex-hull property of
//!   positive weights); for each span not farther than the best distance so
//!   far, Newton from the nearest of a precomputed 5 × 5 seed grid of that
//!   span. Answers on edges and corners come out of the bound-constrained
//!   Newton (1-D Newton along the edge, or the corner itself).
//! - **ties**: candidates within [`TIE_TOL`] of the best distance are resolved
//!   to the lowest patch index, so a point equidistant from two patches always
//!   gets the same one.

use crate::bvh::Bvh;
use crate::closest_point::{ParamBox, PatchHit, newton, newton_in};
use crate::curved;
use crate::differential::local_geometry_rotated;
use crate::error::NurbsError;
use crate::free_edges::{self, FreeSides};
use crate::planar::{self, Outline, Plane};
use crate::surface::{Derivs, NurbsSurface, PatchDef};
use plugins_api::{
    Aabb, CurvedRegion, FlatRegion, Mat3, Projection, ProjectionHint, RigidPose, RigidVelocity,
    ToolError, ToolSurface, Vec3,
};
use rayon::prelude::*;

/// Distances (mm) closer than this are ties, broken by the lowest patch index.
pub const TIE_TOL: f64 = 1e-9;
const SEED_N: usize = 5;
const SEEDS: usize = SEED_N * SEED_N;

/// One patch of a tool with its orientation.
#[derive(Debug, Clone, PartialEq)]
pub struct OrientedPatch {
    /// The surface.
    pub surface: NurbsSurface,
    /// `+1` when `S_u × S_v` points towards the blank, `-1` when it points away.
    pub sign: f64,
}

#[derive(Debug, Clone, Copy)]
struct Element {
    patch: u32,
    bbox: Aabb,
}

#[derive(Debug, Clone, Copy)]
struct Seed {
    p: Vec3,
    u: f64,
    v: f64,
}

/// A rigid tool made of NURBS patches (see the module docs for the projection).
#[derive(Debug, Clone)]
pub struct NurbsTool {
    name: String,
    patches: Vec<OrientedPatch>,
    domains: Vec<ParamBox>,
    /// The plane of each planar patch (see [`crate::planar`]).
    planes: Vec<Option<Plane>>,
    /// The outline of each planar patch, for its flat regions.
    outlines: Vec<Option<Outline>>,
    /// The curved region of each patch that is exactly a circular cylinder
    /// or torus ([`crate::curved`]).
    curved: Vec<Option<CurvedRegion>>,
    /// Whether the tool offers its curved regions; `true` unless switched
    /// off for comparison.
    curved_path: bool,
    /// The free sides of each patch ([`crate::free_edges`]): a point beyond
    /// one is answered by the sharp-edge rule.
    free: Vec<FreeSides>,
    /// Whether warm projections on planar patches take the plane's closed
    /// form ([`crate::planar`]); `true` unless switched off for comparison.
    planar_path: bool,
    elements: Vec<Element>,
    seeds: Vec<Seed>,
    bvh: Bvh,
    local_box: Aabb,
    pose: RigidPose,
    /// Whether `pose.rotation` differs from the identity (else the pose is a
    /// translation and the frames map without matrix products).
    rotated: bool,
    velocity: RigidVelocity,
}

/// The local closest point an answer is built from (its derivatives are kept apart).
#[derive(Debug, Clone, Copy)]
struct Found {
    patch: usize,
    u: f64,
    v: f64,
    dist: f64,
    /// Which of the caller's two derivative slots holds the answer's.
    slot: usize,
    /// Whether the answer is the foot on a planar patch's plane
    /// ([`crate::planar`]): normal and curvature come from the plane.
    planar: bool,
}

impl Found {
    /// A search result, its derivatives copied into `ds[0]`.
    fn from_best(b: &Best, ds: [&mut Derivs; 2]) -> Self {
        *ds[0] = b.hit.d;
        Self {
            patch: b.patch,
            u: b.hit.u,
            v: b.hit.v,
            dist: b.dist,
            slot: 0,
            planar: false,
        }
    }
}

/// The local closest point found by a search.
#[derive(Debug, Clone, Copy)]
struct Best {
    patch: usize,
    hit: PatchHit,
    dist: f64,
}

impl NurbsTool {
    /// A tool from validated, oriented patches (identity pose, at rest).
    pub fn new(name: &str, patches: Vec<OrientedPatch>) -> Result<Self, NurbsError> {
        if patches.is_empty() {
            return Err(NurbsError::Empty {
                tool: name.to_string(),
            });
        }
        let mut domains = Vec::with_capacity(patches.len());
        let mut elements = Vec::new();
        let mut seeds = Vec::new();
        let mut local_box = Aabb::empty();
        for (pi, p) in patches.iter().enumerate() {
            let (du, dv) = p.surface.domain();
            domains.push(ParamBox { u: du, v: dv });
            for &(u0, u1) in &p.surface.spans_u() {
                for &(v0, v1) in &p.surface.spans_v() {
                    let mut bbox = Aabb::empty();
                    let (um, vm) = (0.5 * (u0 + u1), 0.5 * (v0 + v1));
                    for c in p.surface.span_control_points(um, vm) {
                        bbox.grow(&c);
                        local_box.grow(&c);
                    }
                    elements.push(Element {
                        patch: pi as u32,
                        bbox,
                    });
                    for a in 0..SEED_N {
                        for b in 0..SEED_N {
                            let u = u0 + (u1 - u0) * a as f64 / (SEED_N - 1) as f64;
                            let v = v0 + (v1 - v0) * b as f64 / (SEED_N - 1) as f64;
                            seeds.push(Seed {
                                p: p.surface.point(u, v),
                                u,
                                v,
                            });
                        }
                    }
                }
            }
        }
        let boxes: Vec<Aabb> = elements.iter().map(|e| e.bbox).collect();
        let planes: Vec<Option<Plane>> = patches
            .iter()
            .zip(&domains)
            .map(|(p, d)| planar::plane_of(p, d))
            .collect();
        let outlines = patches
            .iter()
            .zip(&domains)
            .zip(&planes)
            .map(|((p, d), plane)| plane.map(|_| Outline::of(&p.surface, d)))
            .collect();
        let curved = patches
            .iter()
            .zip(&domains)
            .zip(&planes)
            .map(|((p, d), plane)| plane.is_none().then(|| curved::curved_of(p, d)).flatten())
            .collect();
        let mut tool = Self {
            name: name.to_string(),
            bvh: Bvh::build(&boxes),
            patches,
            domains,
            planes,
            outlines,
            curved,
            curved_path: true,
            free: Vec::new(),
            planar_path: true,
            elements,
            seeds,
            local_box,
            pose: RigidPose::default(),
            rotated: false,
            velocity: RigidVelocity::default(),
        };
        let mut patch_boxes = vec![Aabb::empty(); tool.patches.len()];
        for e in &tool.elements {
            let b = &mut patch_boxes[e.patch as usize];
            b.grow(&e.bbox.min);
            b.grow(&e.bbox.max);
        }
        tool.free = free_edges::classify(&tool.patches, &tool.domains, &patch_boxes, |k, q| {
            tool.best_on_patch(k, q).map_or(f64::INFINITY, |b| b.dist)
        });
        Ok(tool)
    }

    /// Which sides of patch `i` are free edges of the tool
    /// ([`crate::free_edges`]), in the order `u_min`, `u_max`, `v_min`, `v_max`.
    pub fn free_sides(&self, i: usize) -> [bool; 4] {
        self.free.get(i).map_or([false; 4], |f| f.0)
    }

    /// Validate patch definitions (errors name the patch index and field) and
    /// build a tool; `signs[i] = ±1` orients patch `i` (see [`OrientedPatch`]).
    pub fn from_defs(name: &str, defs: &[PatchDef], signs: &[f64]) -> Result<Self, NurbsError> {
        let mut patches = Vec::with_capacity(defs.len());
        for (i, d) in defs.iter().enumerate() {
            patches.push(OrientedPatch {
                surface: NurbsSurface::new(i, d)?,
                sign: signs.get(i).copied().unwrap_or(1.0).signum(),
            });
        }
        Self::new(name, patches)
    }

    /// The oriented patches (local frame).
    pub fn patches(&self) -> &[OrientedPatch] {
        &self.patches
    }

    /// Whether patch `i` is planar (its warm projections take the plane's
    /// closed form, [`crate::planar`]).
    pub fn is_planar(&self, i: usize) -> bool {
        self.planes.get(i).is_some_and(Option::is_some)
    }

    /// Whether patch `i` is exactly a circular cylinder or torus, with a
    /// curved region ([`crate::curved`]).
    pub fn is_curved(&self, i: usize) -> bool {
        self.curved.get(i).is_some_and(Option::is_some)
    }

    /// Offer the curved regions ([`crate::curved`]) or not (on by default);
    /// off, every point on a curved patch is projected, for comparison.
    pub fn set_curved_regions(&mut self, on: bool) {
        self.curved_path = on;
    }

    /// Switch the planar warm projection ([`crate::planar`]) on or off (on
    /// by default); off, every warm projection runs Newton, for comparison.
    pub fn set_planar_path(&mut self, on: bool) {
        self.planar_path = on;
    }

    /// Bounding box in the tool's local frame (mm).
    pub fn local_box(&self) -> Aabb {
        self.local_box
    }

    /// Number of knot spans (BVH leaves).
    pub fn span_count(&self) -> usize {
        self.elements.len()
    }

    #[inline]
    fn consider(&self, best: &mut Option<Best>, patch: usize, hit: PatchHit) {
        let dist = hit.dist2.sqrt();
        let better = match best {
            None => true,
            Some(b) => dist < b.dist - TIE_TOL || (dist <= b.dist + TIE_TOL && patch < b.patch),
        };
        if better {
            *best = Some(Best { patch, hit, dist });
        }
    }

    /// Cold search over the BVH, starting from an optional bound.
    fn search(&self, x: &Vec3, mut best: Option<Best>) -> Best {
        let bound = best.map_or(f64::INFINITY, |b| b.dist);
        self.bvh.nearest(x, bound, TIE_TOL, |ei, _| {
            let e = &self.elements[ei];
            let cur = best.map_or(f64::INFINITY, |b| b.dist);
            if e.bbox.distance(x) > cur + TIE_TOL {
                return cur;
            }
            let seeds = &self.seeds[ei * SEEDS..(ei + 1) * SEEDS];
            let mut s0 = &seeds[0];
            let mut d0 = f64::INFINITY;
            for s in seeds {
                let d = (s.p - x).norm_squared();
                if d < d0 {
                    d0 = d;
                    s0 = s;
                }
            }
            let pi = e.patch as usize;
            let hit = newton(&self.patches[pi].surface, &self.domains[pi], x, s0.u, s0.v);
            self.consider(&mut best, pi, hit);
            best.map_or(f64::INFINITY, |b| b.dist)
        });
        // The BVH is never empty for a built tool, so a candidate exists.
        best.unwrap_or_else(|| {
            let hit = newton(&self.patches[0].surface, &self.domains[0], x, 0.0, 0.0);
            Best {
                patch: 0,
                dist: hit.dist2.sqrt(),
                hit,
            }
        })
    }

    /// Closest point in the local frame; its derivatives are `ds[slot]` of the answer.
    #[inline]
    fn project_local(&self, x: &Vec3, hint: Option<ProjectionHint>, ds: [&mut Derivs; 2]) -> Found {
        if let Some(h) = hint {
            let pi = h.patch as usize;
            if pi < self.patches.len() && h.u.is_finite() && h.v.is_finite() {
                let [d0, d1] = ds;
                if let Some(plane) = self.planes[pi].as_ref().filter(|_| self.planar_path)
                    && let Some(hit) = planar::warm(
                        &self.patches[pi].surface,
                        &self.domains[pi],
                        plane,
                        x,
                        h.u,
                        h.v,
                        d0,
                    )
                {
                    return Found {
                        patch: pi,
                        u: hit.u,
                        v: hit.v,
                        dist: hit.dist,
                        slot: 0,
                        planar: true,
                    };
                }
                let end = newton_in(
                    &self.patches[pi].surface,
                    &self.domains[pi],
                    x,
                    h.u,
                    h.v,
                    [&mut *d0, &mut *d1],
                );
                let dist = end.dist2.sqrt();
                if !end.on_edge {
                    return Found {
                        patch: pi,
                        u: end.u,
                        v: end.v,
                        dist,
                        slot: end.slot,
                        planar: false,
                    };
                }
                let warm = Best {
                    patch: pi,
                    dist,
                    hit: PatchHit {
                        u: end.u,
                        v: end.v,
                        d: if end.slot == 0 { *d0 } else { *d1 },
                        dist2: end.dist2,
                        on_edge: true,
                    },
                };
                return Found::from_best(&self.search(x, Some(warm)), [d0, d1]);
            }
        }
        Found::from_best(&self.search(x, None), ds)
    }

    /// The closest point of patch `patch` to `x` (local frame) from the best
    /// seed of each of its spans.
    fn best_on_patch(&self, patch: usize, x: &Vec3) -> Option<Best> {
        let mut best: Option<Best> = None;
        for (ei, e) in self.elements.iter().enumerate() {
            if e.patch as usize != patch {
                continue;
            }
            let seeds = &self.seeds[ei * SEEDS..(ei + 1) * SEEDS];
            let s0 = seeds.iter().min_by(|a, b| {
                (a.p - x)
                    .norm_squared()
                    .total_cmp(&(b.p - x).norm_squared())
            })?;
            let hit = newton(
                &self.patches[patch].surface,
                &self.domains[patch],
                x,
                s0.u,
                s0.v,
            );
            self.consider(&mut best, patch, hit);
        }
        best
    }

    /// The closest point of one patch only (local frame), from the best seed of
    /// its spans: for checks across seams and for tests.
    pub fn project_on_patch(&self, patch: usize, x: &Vec3) -> Option<Projection> {
        self.best_on_patch(patch, x).map(|b| {
            let (mut d0, mut d1) = (Derivs::ZERO, Derivs::ZERO);
            let f = Found::from_best(&b, [&mut d0, &mut d1]);
            self.finish(x, &f, &d0, &RigidPose::default(), false)
        })
    }

    /// Projection in the tool's local frame (no pose applied).
    pub fn project_local_frame(&self, x: &Vec3, hint: Option<ProjectionHint>) -> Projection {
        let (mut d0, mut d1) = (Derivs::ZERO, Derivs::ZERO);
        let f = self.project_local(x, hint, [&mut d0, &mut d1]);
        let d = if f.slot == 0 { &d0 } else { &d1 };
        self.finish(x, &f, d, &RigidPose::default(), false)
    }

    #[inline(always)]
    fn finish(
        &self,
        x_local: &Vec3,
        b: &Found,
        d: &Derivs,
        pose: &RigidPose,
        rotated: bool,
    ) -> Projection {
        if b.planar
            && let Some(plane) = &self.planes[b.patch]
        {
            return self.finish_planar(x_local, b, d, plane, pose, rotated);
        }
        let free = self.free[b.patch];
        if free.any() && free.beyond(&self.domains[b.patch], b.u, b.v, d, x_local) {
            return Self::finish_beyond_edge(x_local, b, d, pose, rotated);
        }
        let sign = self.patches[b.patch].sign;
        // The signed distance needs the local normal's side only: r · (S_u × S_v).
        let side = (x_local - d.s).dot(&d.su.cross(&d.sv)) * sign;
        let g = local_geometry_rotated(d, sign, rotated.then_some(&pose.rotation));
        let distance = if side < 0.0 { -b.dist } else { b.dist };
        Projection {
            point: if rotated {
                pose.to_global(&d.s)
            } else {
                d.s + pose.translation
            },
            normal: g.normal,
            distance,
            curvature: g.curvature,
            k1: g.k1,
            k2: g.k2,
            patch: b.patch as u32,
            u: b.u,
            v: b.v,
        }
    }

    /// [`Self::finish`] for a point beyond a free edge (the sharp-edge rule
    /// of [`crate::free_edges`]): distance `|x − p|`, positive, normal
    /// `(x − p)/|x − p|`, zero curvature.
    #[cold]
    #[inline(never)]
    fn finish_beyond_edge(
        x_local: &Vec3,
        b: &Found,
        d: &Derivs,
        pose: &RigidPose,
        rotated: bool,
    ) -> Projection {
        let r = x_local - d.s;
        let dist = r.norm();
        let n = r / dist;
        let (point, normal) = if rotated {
            (pose.to_global(&d.s), pose.rotation * n)
        } else {
            (d.s + pose.translation, n)
        };
        Projection {
            point,
            normal,
            distance: dist,
            curvature: Mat3::zeros(),
            k1: 0.0,
            k2: 0.0,
            patch: b.patch as u32,
            u: b.u,
            v: b.v,
        }
    }

    /// [`Self::finish`] for a foot on a planar patch's plane: the plane's
    /// normal, zero curvature, the signed height as the distance (the answer
    /// depends on the query point only, not on the hint it started from).
    #[inline(always)]
    fn finish_planar(
        &self,
        x_local: &Vec3,
        b: &Found,
        d: &Derivs,
        plane: &Plane,
        pose: &RigidPose,
        rotated: bool,
    ) -> Projection {
        let height = x_local.dot(&plane.normal) - plane.offset;
        let (point, normal) = if rotated {
            (pose.to_global(&d.s), pose.rotation * plane.normal)
        } else {
            (d.s + pose.translation, plane.normal)
        };
        Projection {
            point,
            normal,
            distance: height,
            curvature: Mat3::zeros(),
            k1: 0.0,
            k2: 0.0,
            patch: b.patch as u32,
            u: b.u,
            v: b.v,
        }
    }

    #[inline]
    fn check_point(&self, x: &Vec3) -> Result<(), ToolError> {
        if x.x.is_finite() && x.y.is_finite() && x.z.is_finite() {
            Ok(())
        } else {
            Err(ToolError::NonFinitePoint {
                tool: self.name.clone(),
                x: x.x,
                y: x.y,
                z: x.z,
            })
        }
    }
}

/// The bounding box of `local` after the rigid `pose`.
pub fn posed_box(local: &Aabb, pose: &RigidPose) -> Aabb {
    let mut b = Aabb::empty();
    for i in 0..8 {
        let c = Vec3::new(
            if i & 1 == 0 { local.min.x } else { local.max.x },
            if i & 2 == 0 { local.min.y } else { local.max.y },
            if i & 4 == 0 { local.min.z } else { local.max.z },
        );
        b.grow(&pose.to_global(&c));
    }
    b
}

/// Batch projection shared by the tools: length check, then rayon over points.
pub(crate) fn batch<T: ToolSurface + ?Sized>(
    tool: &T,
    points: &[Vec3],
    hints: &[Option<ProjectionHint>],
    out: &mut [Projection],
) -> Result<(), ToolError> {
    if points.len() != out.len() || (hints.len() != points.len()) {
        return Err(ToolError::Other {
            tool: tool.name().to_string(),
            message: format!(
                "project_batch: {} points, {} hints, {} outputs (lengths must match)",
                points.len(),
                hints.len(),
                out.len()
            ),
        });
    }
    out.par_iter_mut()
        .with_min_len(256)
        .zip(points.par_iter().zip(hints.par_iter()))
        .try_for_each(|(o, (x, h))| {
            *o = tool.project(x, *h)?;
            Ok(())
        })
}

impl ToolSurface for NurbsTool {
    fn name(&self) -> &str {
        &self.name
    }

    fn pose(&self) -> RigidPose {
        self.pose
    }

    fn set_pose(&mut self, pose: RigidPose, velocity: RigidVelocity) {
        self.pose = pose;
        self.rotated = pose.rotation != Mat3::identity();
        self.velocity = velocity;
    }

    fn velocity(&self) -> RigidVelocity {
        self.velocity
    }

    fn bounding_box(&self) -> Aabb {
        posed_box(&self.local_box, &self.pose)
    }

    #[inline]
    fn project(&self, x: &Vec3, hint: Option<ProjectionHint>) -> Result<Projection, ToolError> {
        self.check_point(x)?;
        let xl = if self.rotated {
            self.pose.to_local(x)
        } else {
            x - self.pose.translation
        };
        let (mut d0, mut d1) = (Derivs::ZERO, Derivs::ZERO);
        let f = self.project_local(&xl, hint, [&mut d0, &mut d1]);
        let d = if f.slot == 0 { &d0 } else { &d1 };
        Ok(self.finish(&xl, &f, d, &self.pose, self.rotated))
    }

    fn project_batch(
        &self,
        points: &[Vec3],
        hints: &[Option<ProjectionHint>],
        out: &mut [Projection],
    ) -> Result<(), ToolError> {
        batch(self, points, hints, out)
    }

    fn flat_region(&self, hint: &ProjectionHint) -> Option<FlatRegion> {
        let pi = hint.patch as usize;
        if !self.planar_path {
            return None;
        }
        let (plane, outline) = (self.planes.get(pi)?.as_ref()?, self.outlines[pi].as_ref()?);
        planar::region(
            &self.patches[pi].surface,
            &self.domains[pi],
            plane,
            outline,
            hint.u,
            hint.v,
        )
    }

    fn curved_region(&self, hint: &ProjectionHint) -> Option<CurvedRegion> {
        if !self.curved_path {
            return None;
        }
        *self.curved.get(hint.patch as usize)?
    }
}
