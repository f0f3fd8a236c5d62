//! The sharp-edge rule beyond a tool's free edge (`tools_nurbs::free_edges`):
//! a point beyond an open sheet's boundary is at `|x − p|` from the edge,
//! positive, along `(x − p)/|x − p|`; inside the sheet and across seams the
//! answer is the face's. The expected values are closed forms of a flat
//! rectangle and a cylinder; tolerances are round-off (1e-12 mm on
//! 10-mm-sized tools).

use plugins_api::{Mat3, RigidPose, RigidVelocity, ToolSurface, Vec3};
use std::path::Path;
use tools_nurbs::NurbsTool;
use tools_nurbs::builders::primitives::{cylinder, plane};
use tools_nurbs::builders::{Facing, Placement};
use tools_nurbs::spec::{Tool, parse};

/// A 20 × 10 rectangle (x ∈ [−10, 10], y ∈ [−5, 5]) at z = 0, facing up.
fn sheet() -> NurbsTool {
    let place = Placement {
        origin: Vec3::zeros(),
        facing: Facing::Up,
    };
    plane("sheet", 20.0, 10.0, &place).unwrap()
}

fn close(a: &Vec3, b: &Vec3) -> bool {
    (a - b).norm() < 1e-12
}

/// A point beyond the edge x = 10 and below the plane is outside the tool,
/// at its distance from the edge line (without the sharp-edge rule it would
/// read as penetrated by its height below the plane's normal side: −0.5 here).
#[test]
fn beyond_the_edge_below_the_plane_is_outside_at_the_edge_distance() {
    for hint in [
        None,
        Some(plugins_api::ProjectionHint {
            patch: 0,
            u: 0.9,
            v: 0.5,
        }),
    ] {
        let p = sheet().project(&Vec3::new(10.3, 1.0, -0.4), hint).unwrap();
        assert!(close(&p.point, &Vec3::new(10.0, 1.0, 0.0)), "{p:?}");
        assert!((p.distance - 0.5).abs() < 1e-12, "{p:?}");
        assert!(close(&p.normal, &Vec3::new(0.6, 0.0, -0.8)), "{p:?}");
        assert_eq!(p.curvature, Mat3::zeros());
    }
}

/// Wrapping over the edge (beyond it, above the plane) the normal points from
/// the edge to the point; on the edge's normal line it is the face's normal,
/// so the normal turns continuously from the face round the edge.
#[test]
fn over_the_edge_the_normal_points_from_the_edge() {
    let tool = sheet();
    let p = tool.project(&Vec3::new(10.2, -2.0, 0.3), None).unwrap();
    let r = Vec3::new(0.2, 0.0, 0.3);
    assert!((p.distance - r.norm()).abs() < 1e-12, "{p:?}");
    assert!(close(&p.normal, &(r / r.norm())), "{p:?}");
    let p = tool.project(&Vec3::new(10.0, -2.0, 0.3), None).unwrap();
    assert!(
        (p.distance - 0.3).abs() < 1e-12 && close(&p.normal, &Vec3::z()),
        "{p:?}"
    );
    // Beyond a corner: from the corner point.
    let p = tool.project(&Vec3::new(10.3, 5.4, 0.0), None).unwrap();
    assert!((p.distance - 0.5).abs() < 1e-12, "{p:?}");
    assert!(close(&p.normal, &Vec3::new(0.6, 0.8, 0.0)), "{p:?}");
}

/// Inside the sheet the answer is unchanged: signed height, face normal,
/// penetrated below.
#[test]
fn inside_the_sheet_the_answer_is_the_face() {
    let p = sheet().project(&Vec3::new(9.9, 1.0, -0.4), None).unwrap();
    assert!(
        (p.distance + 0.4).abs() < 1e-12 && close(&p.normal, &Vec3::z()),
        "{p:?}"
    );
}

/// The rule follows the tool's pose: the sheet turned by 90° about x (its
/// normal along −y) answers the rotated point with the rotated direction.
#[test]
fn beyond_the_edge_of_a_rotated_sheet() {
    let mut tool = sheet();
    let q = Mat3::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0);
    let t = Vec3::new(1.0, 2.0, 3.0);
    tool.set_pose(
        RigidPose {
            translation: t,
            rotation: q,
        },
        RigidVelocity::default(),
    );
    let p = tool
        .project(&(q * Vec3::new(10.3, 1.0, -0.4) + t), None)
        .unwrap();
    assert!((p.distance - 0.5).abs() < 1e-12, "{p:?}");
    assert!(close(&p.normal, &(q * Vec3::new(0.6, 0.0, -0.8))), "{p:?}");
}

/// Sides shared with a neighbour (the 90° pieces of a cylinder, the seam of
/// a closed one) are not free; the cylinder's axial ends and an open arc's
/// ends are. Beyond the open end of a half cylinder the rule applies.
#[test]
fn seams_are_not_free_and_open_ends_are() {
    let place = Placement {
        origin: Vec3::zeros(),
        facing: Facing::Up,
    };
    let full = cylinder("drum", 10.0, 20.0, 0.0, 360.0, &place).unwrap();
    let ends = |t: &NurbsTool, i: usize| {
        let f = t.free_sides(i);
        f.iter().filter(|&&s| s).count()
    };
    for i in 0..full.patches().len() {
        assert_eq!(ends(&full, i), 2, "patch {i}: {:?}", full.free_sides(i));
    }
    let half = cylinder("half", 10.0, 20.0, 0.0, 180.0, &place).unwrap();
    let n = half.patches().len();
    let free: usize = (0..n).map(|i| ends(&half, i)).sum();
    assert_eq!(
        free,
        2 * n + 2,
        "{:?}",
        (0..n).map(|i| half.free_sides(i)).collect::<Vec<_>>()
    );
    // The half drum covers angles 0..180° from +x towards +z: its ends lie
    // on the x axis at x = ±10. A point below the end at x = 10 (z < 0,
    // outside the arc's range) is at its distance from the end line.
    let p = half.project(&Vec3::new(10.3, 0.0, -0.4), None).unwrap();
    assert!((p.distance - 0.5).abs() < 1e-9, "{p:?}");
    assert!(
        close(&p.point, &Vec3::new(10.0, 0.0, 0.0))
            || (p.point - Vec3::new(10.0, 0.0, 0.0)).norm() < 1e-9,
        "{p:?}"
    );
}

/// The S-rail holder's swept flange ends 70 mm from the centre line; the
/// apron lies under that edge, so the edge is not free and a point beyond
/// it, below the face, reads as penetrated (the apron is there). Without the
/// apron the same point is beyond a free edge: outside, at its distance from
/// the edge.
#[test]
fn the_s_rail_apron_covers_the_flange_edge() {
    let spec = |apron: f64| {
        format!("[tools.holder]\nkind = \"s-rail-blankholder\"\nfacing = \"up\"\napron = {apron}\n")
    };
    let holder = |apron: f64| -> Tool { parse(&spec(apron), Path::new(".")).unwrap().remove(0) };
    // Straight 1 runs along +x from the origin: the flange's outer edge at y = 70.
    let x = Vec3::new(20.0, 70.3, -0.4);
    let p = holder(10.0).project(&x, None).unwrap();
    assert!(
        (p.distance + 0.4).abs() < 1e-12 && (p.normal.z - 1.0).abs() < 1e-14,
        "{p:?}"
    );
    let p = holder(0.0).project(&x, None).unwrap();
    assert!((p.distance - 0.5).abs() < 1e-9, "{p:?}");
    assert!(
        (p.normal - Vec3::new(0.0, 0.6, -0.8)).norm() < 1e-9,
        "{p:?}"
    );
}

/// The same 20 × 10 sheet as two facets (counter-clockwise seen from +z).
fn faceted_sheet() -> tools_nurbs::FacetedTool {
    let mesh = tools_nurbs::mesh_io::TriMesh {
        vertices: vec![
            Vec3::new(-10.0, -5.0, 0.0),
            Vec3::new(10.0, -5.0, 0.0),
            Vec3::new(10.0, 5.0, 0.0),
            Vec3::new(-10.0, 5.0, 0.0),
        ],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    };
    tools_nurbs::FacetedTool::new("sheet", &mesh, false).unwrap()
}

/// A faceted sheet answers beyond its open edges as the NURBS one does:
/// below the plane beyond the edge, over it, beyond a corner; inside, the
/// face; the shared diagonal is not an edge of the boundary.
#[test]
fn a_faceted_sheet_follows_the_same_rule() {
    let tool = faceted_sheet();
    assert!(tool.is_open());
    let p = tool.project(&Vec3::new(10.3, 1.0, -0.4), None).unwrap();
    assert!((p.distance - 0.5).abs() < 1e-12, "{p:?}");
    assert!(close(&p.normal, &Vec3::new(0.6, 0.0, -0.8)), "{p:?}");
    assert_eq!(p.curvature, Mat3::zeros());
    let p = tool.project(&Vec3::new(10.2, -2.0, 0.3), None).unwrap();
    let r = Vec3::new(0.2, 0.0, 0.3);
    assert!(
        (p.distance - r.norm()).abs() < 1e-12 && close(&p.normal, &(r / r.norm())),
        "{p:?}"
    );
    let p = tool.project(&Vec3::new(10.3, 5.4, 0.0), None).unwrap();
    assert!(
        (p.distance - 0.5).abs() < 1e-12 && close(&p.normal, &Vec3::new(0.6, 0.8, 0.0)),
        "{p:?}"
    );
    for x in [Vec3::new(9.9, 1.0, -0.4), Vec3::new(0.0, 0.0, -0.4)] {
        let p = tool.project(&x, None).unwrap();
        assert!(
            (p.distance + 0.4).abs() < 1e-12 && close(&p.normal, &Vec3::z()),
            "{x}: {p:?}"
        );
    }
}

/// A closed mesh (a tetrahedron) has no open edge, so the rule never
/// applies to it.
#[test]
fn a_closed_faceted_mesh_has_no_free_edge() {
    let mesh = tools_nurbs::mesh_io::TriMesh {
        vertices: vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(10.0, 0.0, 0.0),
            Vec3::new(0.0, 10.0, 0.0),
            Vec3::new(0.0, 0.0, 10.0),
        ],
        triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    };
    let tool = tools_nurbs::FacetedTool::new("tet", &mesh, false).unwrap();
    assert!(!tool.is_open());
}
