//! Test tools shared by the contact tests.

use contact::{BlankGeometry, BlankView, ContactPair};
use plugins_api::{
    Aabb, Mat3, Projection, ProjectionHint, RigidPose, RigidVelocity, ToolError, ToolSurface, Vec3,
};

/// The blank of one contact step: initial positions, positions, velocities
/// (mm, mm/s), nodal masses (tonne) and thicknesses (mm).
pub type Blank<'a> = (&'a [Vec3], &'a [Vec3], &'a [Vec3], &'a [f64], &'a [f64]);

/// One step of `pair` on `tool` for the blank `(x0, x, v, mass, thickness)`:
/// `g` updated for the pair's needs, the nodal contact forces (N) returned.
#[allow(dead_code)] // not every test binary steps a pair
pub fn step_pair(
    pair: &mut ContactPair,
    tool: &dyn ToolSurface,
    g: &mut BlankGeometry,
    (x0, x, v, mass, thickness): Blank<'_>,
    dt: f64,
) -> Vec<Vec3> {
    let view = BlankView {
        x0,
        x,
        v,
        mass,
        thickness,
        flow_stress: None,
    };
    g.update(&view, dt, pair.needs());
    let mut f = vec![Vec3::zeros(); x.len()];
    pair.step(tool, g, &view, dt, &mut f).unwrap();
    f
}

/// The plane `z = pose.translation.z`, normal +z (the blank lies above it).
#[allow(dead_code)] // not every test binary uses the plane
pub struct Plane {
    /// Pose (only the z translation matters).
    pub pose: RigidPose,
    /// Velocity.
    pub vel: RigidVelocity,
}

impl ToolSurface for Plane {
    fn name(&self) -> &str {
        "plane"
    }
    fn pose(&self) -> RigidPose {
        self.pose
    }
    fn set_pose(&mut self, pose: RigidPose, velocity: RigidVelocity) {
        self.pose = pose;
        self.vel = velocity;
    }
    fn velocity(&self) -> RigidVelocity {
        self.vel
    }
    fn bounding_box(&self) -> Aabb {
        let z = self.pose.translation.z;
        Aabb {
            min: Vec3::new(-1e3, -1e3, z),
            max: Vec3::new(1e3, 1e3, z),
        }
    }
    fn project(&self, x: &Vec3, _hint: Option<ProjectionHint>) -> Result<Projection, ToolError> {
        if !x.iter().all(|c| c.is_finite()) {
            return Err(ToolError::NonFinitePoint {
                tool: "plane".into(),
                x: x.x,
                y: x.y,
                z: x.z,
            });
        }
        let z = self.pose.translation.z;
        Ok(Projection {
            point: Vec3::new(x.x, x.y, z),
            normal: Vec3::z(),
            distance: x.z - z,
            curvature: Mat3::zeros(),
            k1: 0.0,
            k2: 0.0,
            patch: 0,
            u: x.x,
            v: x.y,
        })
    }
}
