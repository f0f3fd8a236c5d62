//! A posed tool answers like its local frame mapped by the pose.

use plugins_api::{Mat3, RigidPose, RigidVelocity, ToolSurface, Vec3};
use tools_nurbs::builders::square_cup::{PunchParams, punch};
use tools_nurbs::builders::{Model, Placement};
use tools_nurbs::closest_point::STEP_TOL;

/// Rigid-body invariance (docs/architecture.md §2: the scheduler moves a tool only through
/// its pose): with a rotation and a translation, every projection equals the
/// local-frame projection of the pulled-back point mapped forward — point
/// `R p + t`, normal `R n`, curvature `R K Rᵀ`, same distance, principal
/// curvatures, patch and `(u, v)`. Tolerance 1e-12 relative (rounding only).
#[test]
fn posed_punch_projection_is_the_rotated_local_projection() {
    let mut tool = punch(
        "punch",
        &PunchParams::default(),
        Model::Full,
        &Placement::default(),
    )
    .unwrap();
    let rotation: Mat3 = nalgebra::Rotation3::from_euler_angles(0.3, -0.7, 1.1).into_inner();
    let pose = RigidPose {
        translation: Vec3::new(12.0, -4.0, 30.0),
        rotation,
    };
    tool.set_pose(pose, RigidVelocity::default());
    let mut checked = 0;
    for i in 0..40 {
        for j in 0..40 {
            let xl = Vec3::new(
                -45.0 + 90.0 * i as f64 / 39.0,
                -45.0 + 90.0 * j as f64 / 39.0,
                -40.0 + 45.0 * ((i * 7 + j * 3) % 11) as f64 / 10.0,
            );
            let x = pose.to_global(&xl);
            let g = tool.project(&x, None).unwrap();
            let l = tool.project_local_frame(&xl, None);
            let tol = 1e-12 * (1.0 + x.norm());
            assert!((g.point - pose.to_global(&l.point)).norm() < tol, "{xl}");
            assert!((g.normal - rotation * l.normal).norm() < 1e-12, "{xl}");
            assert!((g.distance - l.distance).abs() < tol, "{xl}");
            let k = rotation * l.curvature * rotation.transpose();
            assert!((g.curvature - k).norm() < 1e-12 * (1.0 + k.norm()), "{xl}");
            assert!((g.k1 - l.k1).abs() < 1e-12 && (g.k2 - l.k2).abs() < 1e-12);
            assert_eq!(g.patch, l.patch);
            // A warm start from the answer reproduces it, to the tolerance
            // the cold answer was converged to: on a planar patch the warm
            // answer is the exact foot of the perpendicular (its offset is
            // along the normal to rounding), while Newton stops at a step of
            // STEP_TOL (1 + distance).
            let w = tool.project(&x, Some(g.hint())).unwrap();
            let newton = 2.0 * STEP_TOL * (1.0 + g.distance.abs());
            assert!(
                (w.point - g.point).norm() < tol.max(newton),
                "{xl} {g:?} {w:?}"
            );
            if w.k1 == 0.0 && w.k2 == 0.0 {
                assert!((x - w.point).cross(&w.normal).norm() < tol, "{xl} {w:?}");
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 1600);
}
