//! The rigid-tool contract: closest-point projection with curvature, pose and velocity.
//!
//! Contact (stage 5 of an explicit step) asks a tool, for each candidate blank
//! point, where the closest point of the tool surface is, on which side the
//! point lies, and how the surface curves there (the formulations of
//! friction-math §4 read the normal's rotation). The tool's geometry is fixed
//! in its own reference frame; the press scheduler moves it rigidly with a
//! [`RigidPose`] and a [`RigidVelocity`].
//!
//! Implementations (exact NURBS tools, faceted tools) live in `tools-nurbs`;
//! the contact code knows tools only through [`ToolSurface`].

use crate::{CurvedRegion, Mat3, ToolRegion, Vec3};
use thiserror::Error;

/// A query a tool cannot answer.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ToolError {
    /// The query point is NaN or infinite.
    #[error("tool `{tool}`: query point ({x}, {y}, {z}) mm is not finite")]
    NonFinitePoint {
        /// Tool name.
        tool: String,
        /// x coordinate (mm).
        x: f64,
        /// y coordinate (mm).
        y: f64,
        /// z coordinate (mm).
        z: f64,
    },
    /// Anything else an implementation must report (names the patch and the field).
    #[error("tool `{tool}`: {message}")]
    Other {
        /// Tool name.
        tool: String,
        /// What went wrong.
        message: String,
    },
}

/// An axis-aligned bounding box in the global frame (mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Aabb {
    /// The empty box (contains nothing; grows with [`Aabb::grow`]).
    pub fn empty() -> Self {
        Self {
            min: Vec3::repeat(f64::INFINITY),
            max: Vec3::repeat(f64::NEG_INFINITY),
        }
    }

    /// Enlarge the box to contain `p`.
    pub fn grow(&mut self, p: &Vec3) {
        self.min = self.min.inf(p);
        self.max = self.max.sup(p);
    }

    /// The box enlarged by `margin` (mm) on every side.
    pub fn inflated(&self, margin: f64) -> Self {
        Self {
            min: self.min - Vec3::repeat(margin),
            max: self.max + Vec3::repeat(margin),
        }
    }

    /// Whether `p` lies inside or on the box.
    pub fn contains(&self, p: &Vec3) -> bool {
        (0..3).all(|i| p[i] >= self.min[i] && p[i] <= self.max[i])
    }

    /// Distance (mm) from `p` to the box; 0 inside.
    pub fn distance(&self, p: &Vec3) -> f64 {
        let d = (self.min - p).sup(&(p - self.max)).sup(&Vec3::zeros());
        d.norm()
    }
}

/// A rigid placement of a tool: `x_global = rotation · x_local + translation` (mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidPose {
    /// Translation of the tool's local origin (mm).
    pub translation: Vec3,
    /// Rotation from the tool's local frame to the global frame (proper orthogonal).
    pub rotation: Mat3,
}

impl Default for RigidPose {
    fn default() -> Self {
        Self {
            translation: Vec3::zeros(),
            rotation: Mat3::identity(),
        }
    }
}

impl RigidPose {
    /// Map a point from the tool's local frame to the global frame.
    pub fn to_global(&self, x_local: &Vec3) -> Vec3 {
        self.rotation * x_local + self.translation
    }

    /// Map a point from the global frame to the tool's local frame.
    pub fn to_local(&self, x_global: &Vec3) -> Vec3 {
        self.rotation.transpose() * (x_global - self.translation)
    }
}

/// The rigid velocity of a tool: `v(x) = linear + angular × (x - pose.translation)`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RigidVelocity {
    /// Velocity of the tool's local origin (mm/s).
    pub linear: Vec3,
    /// Angular velocity (rad/s), global frame.
    pub angular: Vec3,
}

/// Where the previous projection of the same point landed, to warm-start the next.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProjectionHint {
    /// Patch (or facet) index of the previous answer.
    pub patch: u32,
    /// Surface parameter `u` of the previous answer.
    pub u: f64,
    /// Surface parameter `v` of the previous answer.
    pub v: f64,
}

/// The closest point of a tool surface to a query point, in the global frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    /// Closest point on the surface (mm).
    pub point: Vec3,
    /// Unit normal at the closest point, oriented towards the blank side.
    pub normal: Vec3,
    /// Signed distance (mm): positive on the blank side of the surface,
    /// negative when the query point has penetrated.
    pub distance: f64,
    /// Curvature tensor `K = ∇_s n` (Weingarten map, 1/mm) as a symmetric
    /// 3×3 tensor in the tangent plane (`K n = 0`), global frame. Positive
    /// eigenvalues: the surface curves away from the blank side (convex
    /// towards the blank, like a punch nose).
    pub curvature: Mat3,
    /// Principal curvatures `k1 ≥ k2` (1/mm), eigenvalues of `curvature` in the tangent plane.
    pub k1: f64,
    /// Second principal curvature (1/mm).
    pub k2: f64,
    /// Patch (or facet) index: pass back as a [`ProjectionHint`].
    pub patch: u32,
    /// Surface parameter `u` on that patch.
    pub u: f64,
    /// Surface parameter `v` on that patch.
    pub v: f64,
}

impl Projection {
    /// The hint that warm-starts the next projection of the same point.
    pub fn hint(&self) -> ProjectionHint {
        ProjectionHint {
            patch: self.patch,
            u: self.u,
            v: self.v,
        }
    }
}

/// A disc of a flat piece of a tool, in the tool's local frame, on which
/// the projection has a closed form (see [`ToolSurface::flat_region`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlatRegion {
    /// Unit normal of the plane towards the blank side (local frame).
    pub normal: Vec3,
    /// `normal · p` for the points `p` of the plane (mm).
    pub offset: f64,
    /// Centre of the disc (local frame, mm).
    pub centre: Vec3,
    /// Radius of the disc (mm).
    pub radius: f64,
}

impl FlatRegion {
    /// The answer for the point `x_local` (tool's local frame) when the
    /// foot of its perpendicular on the plane lies in the disc: its signed
    /// distance (mm) and the foot (local frame); `None` outside the disc.
    #[inline]
    pub fn project_local(&self, x_local: &Vec3) -> Option<(f64, Vec3)> {
        let distance = x_local.dot(&self.normal) - self.offset;
        let foot = x_local - self.normal * distance;
        ((foot - self.centre).norm_squared() < self.radius * self.radius)
            .then_some((distance, foot))
    }
}

/// A rigid tool surface that contact can query.
///
/// Implementations must never fail to project a finite point: a point at
/// NaN or infinity is the only error. Equidistant candidates are resolved
/// deterministically: a cold search (no hint) takes the lowest patch index; a
/// warm start keeps its hinted patch when the answer lies inside it, so that a
/// point does not flip between patches from step to step.
pub trait ToolSurface: Send + Sync {
    /// The tool's name as the scene gives it (`punch`, `die`, …).
    fn name(&self) -> &str;

    /// The current rigid pose.
    fn pose(&self) -> RigidPose;

    /// Place the tool (the press scheduler calls this once per step).
    fn set_pose(&mut self, pose: RigidPose, velocity: RigidVelocity);

    /// The current rigid velocity.
    fn velocity(&self) -> RigidVelocity;

    /// Velocity (mm/s) of the tool's material point at global position `x`.
    fn velocity_at(&self, x: &Vec3) -> Vec3 {
        let v = self.velocity();
        v.linear + v.angular.cross(&(x - self.pose().translation))
    }

    /// Bounding box of the surface at its current pose (mm).
    fn bounding_box(&self) -> Aabb;

    /// Closest point of the surface to `x` (global frame), warm-started from
    /// `hint` when given. Errors only for a non-finite `x`.
    fn project(&self, x: &Vec3, hint: Option<ProjectionHint>) -> Result<Projection, ToolError>;

    /// A flat region around the answer that `hint` came from, if the tool
    /// has one there: for every query point `x` whose perpendicular foot on
    /// the region's plane lies inside its disc
    /// ([`FlatRegion::project_local`] of `x` in the local frame), that foot
    /// is the closest point of patch `hint.patch` to `x`, at the signed
    /// distance `normal · x_local − offset`, with the region's normal (mapped
    /// by the pose) and zero curvature: what a warm start from `hint` keeps
    /// (it stays on its hinted patch while the answer lies inside it). A
    /// caller may then skip the projection and keep `hint` for later steps
    /// (its `u`, `v` stay those of the disc's centre). The default, and a
    /// tool with no flat pieces, has none.
    fn flat_region(&self, hint: &ProjectionHint) -> Option<FlatRegion> {
        let _ = hint;
        None
    }

    /// A curved region around the answer that `hint` came from, if its
    /// patch is exactly a circular cylinder or torus
    /// ([`crate::curved_region`]): for every query point `x` that
    /// [`CurvedRegion::project_local`] answers (in the local frame), its
    /// closed-form foot is the closest point of patch `hint.patch` to `x`,
    /// at the signed distance and with the normal (mapped by the pose) it
    /// returns, and lies inside the patch by a margin: what a warm start
    /// from `hint` keeps. A caller may then skip the projection and keep
    /// `hint` for later steps, as with [`ToolSurface::flat_region`]. The
    /// default, and a tool with no such patches, has none.
    fn curved_region(&self, hint: &ProjectionHint) -> Option<CurvedRegion> {
        let _ = hint;
        None
    }

    /// The region around the answer that `hint` came from on which the
    /// closest point has a closed form: the flat region if there is one,
    /// else the curved region.
    fn region(&self, hint: &ProjectionHint) -> Option<ToolRegion> {
        self.flat_region(hint)
            .map(ToolRegion::Flat)
            .or_else(|| self.curved_region(hint).map(ToolRegion::Curved))
    }

    /// Project many points; `hints[i]` is read as the warm start of
    /// `points[i]` and `out[i]` receives its answer. The default loops over
    /// [`ToolSurface::project`]; implementations may parallelise.
    fn project_batch(
        &self,
        points: &[Vec3],
        hints: &[Option<ProjectionHint>],
        out: &mut [Projection],
    ) -> Result<(), ToolError> {
        for ((x, h), o) in points.iter().zip(hints).zip(out.iter_mut()) {
            *o = self.project(x, *h)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pose_round_trip_and_box_distance() {
        let c = std::f64::consts::FRAC_1_SQRT_2;
        let pose = RigidPose {
            translation: Vec3::new(1.0, 2.0, 3.0),
            rotation: Mat3::new(c, -c, 0.0, c, c, 0.0, 0.0, 0.0, 1.0),
        };
        let x = Vec3::new(0.3, -4.0, 7.5);
        assert!((pose.to_local(&pose.to_global(&x)) - x).norm() < 1e-14);
        let mut b = Aabb::empty();
        b.grow(&Vec3::zeros());
        b.grow(&Vec3::new(1.0, 1.0, 1.0));
        assert_eq!(b.distance(&Vec3::new(0.5, 0.5, 0.5)), 0.0);
        assert!((b.distance(&Vec3::new(4.0, 5.0, 0.5)) - 5.0).abs() < 1e-14);
    }
}
