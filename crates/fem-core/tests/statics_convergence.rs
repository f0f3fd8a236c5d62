//! Newton's quadratic convergence with the consistent tangent, on the
//! nonlinear von Mises truss.

mod statics_common;

use fem_core::statics::NewtonSettings;
use statics_common::{limit, truss_under_load};

/// Round-off floor of the relative residual: below it the residual no
/// longer measures the error, so no ratio is taken there.
const FLOOR: f64 = 1e-13;

/// One increment from the unloaded truss to 0.6 times the limit load (so
/// deflection is a quarter of the rise: strongly nonlinear). With the
/// consistent tangent, near the solution `e_{k+1} ≈ C e_k²` for the
/// relative residual `e = ‖R‖ / F_ref`, so `log e_{k+1} / log e_k → 2`.
/// Reference: Newton's method's local quadratic convergence (e.g.
/// Nocedal & Wright, Numerical Optimization, thm. 11.2). The ratio of the
/// last pair above round-off (`e_k < 1e-2`, `e_{k+1} > 1e-13`) must lie in
/// `[1.8, 2.5]`, and the constant `C = e_{k+1} / e_k²` of the last two
/// such pairs must agree within a factor 3; a tangent wrong by a few
/// percent gives linear convergence, a ratio near 1 and a `C` that grows
/// without bound.
#[test]
fn newton_residuals_fall_quadratically_on_the_von_mises_truss() {
    let settings = NewtonSettings {
        force_tolerance: 1e-13,
        displacement_tolerance: 1e-12,
        initial_increment: 1.0,
        line_search_steps: 0,
        ..Default::default()
    };
    let mut solver = truss_under_load(0.6 * limit().1, settings);
    let report = solver.solve().unwrap();
    assert_eq!(report.increments.len(), 1);
    let inc = &report.increments[0];
    let e: Vec<f64> = inc
        .residuals
        .iter()
        .map(|r| r / inc.force_reference)
        .collect();
    println!(
        "relative residuals: {:?}",
        e.iter().map(|x| format!("{x:.3e}")).collect::<Vec<_>>()
    );
    // (log e_{k+1} / log e_k, e_{k+1} / e_k²) for the pairs above round-off.
    let pairs: Vec<(f64, f64)> = e
        .windows(2)
        .filter(|w| w[0] < 1e-2 && w[1] > FLOOR)
        .map(|w| (w[1].ln() / w[0].ln(), w[1] / (w[0] * w[0])))
        .collect();
    for (ratio, c) in &pairs {
        println!("log e_(k+1) / log e_k = {ratio:.3}, C = e_(k+1) / e_k^2 = {c:.3}");
    }
    assert!(
        pairs.len() >= 2,
        "too few iterations above round-off: {e:?}"
    );
    let (ratio, c) = pairs[pairs.len() - 1];
    let (_, c_before) = pairs[pairs.len() - 2];
    assert!((1.8..=2.5).contains(&ratio), "ratio {ratio}");
    assert!(
        (c / c_before).max(c_before / c) < 3.0,
        "C {c_before} then {c}"
    );
}
