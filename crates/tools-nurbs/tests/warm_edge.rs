//! Regression: a warm start whose hint lies a rounding error inside a patch edge
//! (as a hint saved from an edge answer comes back) must still leave the patch
//! when the closest point lies beyond that edge. Contact's die-shoulder seam
//! test's case: a blank node walking off the die face onto the shoulder must not keep
//! the face's edge point (distance 0.3955 instead of 0.385) and lose contact.

use plugins_api::{ToolSurface, Vec3};
use tools_nurbs::builders::square_cup::benchmark_quarter_die;

/// Walk a point along the die face to the shoulder seam with warm starts, then
/// step onto the shoulder: the warm answer equals the cold one (1e-12 mm).
#[test]
fn warm_start_from_an_edge_hint_crosses_the_seam() {
    let die = benchmark_quarter_die().unwrap();
    let mut hint = None;
    for i in 0..=80 {
        let q = Vec3::new(50.0 - 0.1 * f64::from(i), 10.0, 0.385);
        hint = Some(die.project(&q, hint).unwrap().hint());
    }
    for a_deg in [0.5_f64, 1.0, 5.0] {
        let a = a_deg.to_radians();
        // A point 0.385 mm off the shoulder (axis x = 42, z = -5, radius 5).
        let x = Vec3::new(42.0 - 5.385 * a.sin(), 10.0, -5.0 + 5.385 * a.cos());
        let warm = die.project(&x, hint).unwrap();
        let cold = die.project(&x, None).unwrap();
        assert!(
            (warm.distance - cold.distance).abs() < 1e-12 && (warm.distance - 0.385).abs() < 1e-9,
            "{a_deg}°: warm {} (patch {}), cold {} (patch {})",
            warm.distance,
            warm.patch,
            cold.distance,
            cold.patch
        );
    }
}

/// Regression: a warm Newton whose path crosses a knot where the
/// parametrisation is only C⁰ (the punch bottom's pieces meet along the
/// corner diagonals with a jump in `S_u`) must not stop on the knot short
/// of the closest point. The flat-region test's case: from a far hint the
/// line search must not shrink the step to nothing at the kink, leaving
/// Newton at a point 0.17 mm farther than the foot. Points over the punch bottom (a
/// plane), warm-started from hints anywhere on that patch, with the planar
/// shortcut off: the answer is the perpendicular foot (1e-9 mm).
#[test]
fn warm_newton_does_not_stop_on_a_c0_knot() {
    use tools_nurbs::builders::square_cup::{PunchParams, punch};
    use tools_nurbs::builders::{Facing, Model, Placement};
    let mut tool = punch(
        "punch",
        &PunchParams::default(),
        Model::Full,
        &Placement {
            origin: Vec3::zeros(),
            facing: Facing::Up,
        },
    )
    .unwrap();
    tool.set_planar_path(false);
    // The quadrant of the punch bottom (a planar patch at z = 0) holding
    // the point (-19.616, 20.620, 0) at (u, v) = (2.626, 0.540).
    let bottom = (0..tool.patches().len())
        .find(|&i| {
            let p = tool.patches()[i]
                .surface
                .point(2.626214797742098, 0.5397982184521956);
            tool.is_planar(i)
                && (p - Vec3::new(-19.61599542200186, 20.620380503668827, 0.0)).norm() < 1e-9
        })
        .expect("the punch bottom's quadrant");
    let patch = &tool.patches()[bottom];
    let (du, dv) = patch.surface.domain();
    let mut checked = 0;
    for a in 0..12 {
        for b in 0..12 {
            let (u, v) = (
                du[0] + (du[1] - du[0]) * (a as f64 + 0.5) / 12.0,
                dv[0] + (dv[1] - dv[0]) * (b as f64 + 0.5) / 12.0,
            );
            let target = patch.surface.point(u, v);
            for (c, d) in [
                (0.1, 0.9),
                (0.9, 0.1),
                (0.5, 0.5),
                (0.05, 0.05),
                (0.77, 0.31),
                (0.33, 0.6),
                (0.6, 0.95),
                (0.98, 0.5),
            ] {
                let hint = plugins_api::ProjectionHint {
                    patch: bottom as u32,
                    u: du[0] + (du[1] - du[0]) * c,
                    v: dv[0] + (dv[1] - dv[0]) * d,
                };
                let x = target - Vec3::z() * 1.2;
                let w = tool.project(&x, Some(hint)).unwrap();
                assert!(
                    (w.point - target).norm() < 1e-9 && (w.distance + 1.2).abs() < 1e-9,
                    "x {x:?} from hint {hint:?}: {w:?}"
                );
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 1152);
    // The case the flat-region test found: from (2.626, 0.540) to a foot at
    // u = 3.009 across the knot u = 3.
    let hint = plugins_api::ProjectionHint {
        patch: bottom as u32,
        u: 2.626214797742098,
        v: 0.5397982184521956,
    };
    let x = Vec3::new(-20.130145604490266, 21.940038598937925, -1.2323307755285704);
    let w = tool.project(&x, Some(hint)).unwrap();
    let foot = Vec3::new(x.x, x.y, 0.0);
    assert!(
        (w.point - foot).norm() < 1e-9 && (w.distance - x.z).abs() < 1e-9,
        "{w:?}"
    );
}
