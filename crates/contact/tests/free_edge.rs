//! Contact beyond an open tool sheet's free edge (the sharp-edge rule of
//! `tools_nurbs::free_edges`, docs/tools.md): a 2 × 2-quad blank (1 mm
//! thick, 1 mm quads, at rest) against a 20 × 10 mm NURBS sheet at z = 0
//! facing up, its free edge the line x = 10.
//!
//! - beyond the edge and below the plane, farther than half the thickness
//!   from the edge line: no contact, no force (without the rule the first
//!   column would read as penetrated by 1 mm and be pushed up);
//! - beyond the edge, above the plane, within half the thickness of the edge
//!   line: the node is pushed along `(x − p)/|x − p|` with the force of the
//!   same gap on the face (same node, same penalty stiffness);
//! - inside the sheet: the answer of an unbounded plane.
//!
//! Tolerances: 1e-12 relative (the same arithmetic on the same numbers up to
//! the projection's round-off).

mod common;

use contact::{BlankGeometry, ContactPair, PairSpec, PointStatus};
use friction_laws::builtin;
use plugins_api::{Params, RigidPose, RigidVelocity, TangentMode, ToolSurface, Vec3};
use tools_nurbs::builders::primitives::plane;
use tools_nurbs::builders::{Facing, Placement};

const T0: f64 = 1.0;
const DT: f64 = 1e-6;

/// One contact step of the blank whose lower-left corner sits at `corner`
/// (at rest) against `tool`: statuses and nodal forces (N).
fn touch(tool: &dyn ToolSurface, corner: Vec3) -> (Vec<PointStatus>, Vec<Vec3>, Vec<Vec3>) {
    let mut mesh = fem_core::rectangle(2.0, 2.0, 2, 2).unwrap();
    mesh.nodes.iter_mut().for_each(|p| *p += corner);
    let x = mesh.nodes.clone();
    let n = x.len();
    let mut geometry = BlankGeometry::new(n, &mesh.quads).unwrap();
    let integ = builtin::integrator(
        "ac",
        &Params::new().with("mu", 0.1),
        "convective",
        TangentMode::None,
    )
    .unwrap();
    let mut pair = ContactPair::new(
        &PairSpec::new("sheet-blank", 0, 1.7e5),
        integ,
        &geometry,
        &x,
    )
    .unwrap();
    let (v, mass, thickness) = (vec![Vec3::zeros(); n], vec![1e-6; n], vec![T0; n]);
    let f = common::step_pair(
        &mut pair,
        tool,
        &mut geometry,
        (&x, &x, &v, &mass, &thickness),
        DT,
    );
    (pair.status.clone(), f, x)
}

fn sheet() -> tools_nurbs::NurbsTool {
    let place = Placement {
        origin: Vec3::zeros(),
        facing: Facing::Up,
    };
    plane("sheet", 20.0, 10.0, &place).unwrap()
}

#[test]
fn beyond_the_edge_below_the_plane_nothing_touches() {
    let (status, f, _) = touch(&sheet(), Vec3::new(10.3, -1.0, -0.4));
    assert!(status.iter().all(|s| *s == PointStatus::Open), "{status:?}");
    assert!(f.iter().all(|f| *f == Vec3::zeros()), "{f:?}");
}

#[test]
fn over_the_edge_within_reach_the_force_points_from_the_edge() {
    let tool = sheet();
    let (status, f, x) = touch(&tool, Vec3::new(10.2, -1.0, 0.3));
    // Reference: the same blank on the face, each node at the edge
    // distance |r| = 0.36 mm above it.
    let r = Vec3::new(0.2, 0.0, 0.3);
    let (_, f_face, _) = touch(&tool, Vec3::new(2.0, -1.0, r.norm()));
    for (i, p) in x.iter().enumerate() {
        if p.x < 10.5 {
            assert_ne!(status[i], PointStatus::Open, "node {i}");
            let dir = f[i] / f[i].norm();
            assert!((dir - r / r.norm()).norm() < 1e-12, "node {i}: {}", f[i]);
            assert!(
                (f[i].norm() - f_face[i].norm()).abs() <= 1e-12 * f_face[i].norm(),
                "node {i}: {} vs {} on the face",
                f[i].norm(),
                f_face[i].norm()
            );
        } else {
            assert_eq!(status[i], PointStatus::Open, "node {i}");
            assert_eq!(f[i], Vec3::zeros(), "node {i}");
        }
    }
}

#[test]
fn inside_the_sheet_the_force_is_the_planes() {
    let corner = Vec3::new(2.0, -1.0, 0.49);
    let (status, f, _) = touch(&sheet(), corner);
    let plane = common::Plane {
        pose: RigidPose::default(),
        vel: RigidVelocity::default(),
    };
    let (status_plane, f_plane, _) = touch(&plane, corner);
    assert_eq!(status, status_plane);
    assert!(status.iter().all(|s| *s != PointStatus::Open));
    for (a, b) in f.iter().zip(&f_plane) {
        assert!((a - b).norm() <= 1e-12 * b.norm(), "{a} vs {b}");
    }
}
