//! Regression: a warm start whose hint lies a rounding error inside a patch edge
//! (as a hint saved from an edge answer comes back) must still leave the patch
//! when the closest point lies beyond that edge. Found by contact's die-shoulder
//! seam test: a blank node walking off the die face onto the shoulder kept the
//! face's edge point (distance 0.3955 instead of 0.385) and lost contact.

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
