//! Load control past the limit load: the solver cuts back, then stops with
//! an error carrying the residual history and the last converged load
//! factor, the state left there.

mod statics_common;

use fem_core::statics::{NewtonSettings, StaticsError};
use statics_common::{APEX, deflection, limit, load, truss_under_load};

/// The von Mises truss under a downward apex load of 1.5 times its limit
/// load `P_lim` (closed form in `statics_common::limit`): no equilibrium
/// near the stable branch past `λ = 1/1.5`, so the increments are cut back
/// toward the limit point until `min_increment`, and the solve stops with
/// `NotConverged`. The last converged `λ` must lie within
/// `[0.99, 1] / 1.5` (below the limit and close to it), the error must
/// carry the last attempt's residual history, and the state must be that
/// of the last converged increment: `P(w) = λ 1.5 P_lim` to 1e-8 of
/// `P_lim` and `w` the closed form's root to 1e-6 relative (the root is
/// ill-conditioned right at the limit point, where `dP/dw → 0`).
#[test]
fn von_mises_truss_loaded_past_its_limit_cuts_back_then_stops_with_history() {
    let (w_lim, p_lim) = limit();
    let p = 1.5 * p_lim;
    let settings = NewtonSettings {
        force_tolerance: 1e-12,
        min_increment: 1e-6,
        max_cutbacks: 30,
        ..Default::default()
    };
    let mut solver = truss_under_load(p, settings);
    let err = solver.solve().unwrap_err();
    let text = err.to_string();
    println!("{text}");
    assert!(!text.contains('\n'), "one line");
    let StaticsError::NotConverged {
        lambda_converged,
        lambda_target,
        cutbacks,
        residuals,
        ..
    } = err
    else {
        panic!("expected NotConverged, got {text}");
    };
    let lambda_limit = p_lim / p;
    println!(
        "λ limit {lambda_limit:.9}, last converged {lambda_converged:.9}, last tried \
         {lambda_target:.9}, {cutbacks} cut-backs, {} residuals",
        residuals.len()
    );
    assert!(lambda_converged < lambda_limit && lambda_converged > 0.99 * lambda_limit);
    assert!(lambda_target > lambda_converged);
    assert!(cutbacks >= 1 && !residuals.is_empty());
    assert!(residuals.iter().all(|r| r.is_finite()));
    assert_eq!(solver.lambda(), lambda_converged);
    let w = -solver.displacement(APEX).z;
    let w_exact = deflection(lambda_converged * p);
    println!("w = {w:.9} mm (limit {w_lim:.9}), closed form {w_exact:.9}");
    assert!((load(w) - lambda_converged * p).abs() < 1e-8 * p_lim);
    assert!((w - w_exact).abs() < 1e-6 * w_exact);
}
