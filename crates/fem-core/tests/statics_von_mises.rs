//! The von Mises (two-bar) truss: load–deflection curve of a shallow
//! symmetric two-spring truss against its closed form, under displacement
//! control through the snap-through and under load control up to just
//! before the limit load.

mod statics_common;

use fem_core::Dof;
use fem_core::statics::{NewtonSettings, StaticSolver};
use statics_common::{APEX, H, deflection, limit, load, truss_under_load, truss_with_midpoints};

/// Tight tolerances: the curve is checked to 1e-8, so equilibrium is
/// iterated to round-off (quadratic convergence makes that one iteration
/// more than the defaults).
fn tight(increment: f64) -> NewtonSettings {
    NewtonSettings {
        force_tolerance: 1e-13,
        displacement_tolerance: 1e-12,
        initial_increment: increment,
        max_increment: increment,
        ..Default::default()
    }
}

/// Displacement control: the apex is pushed down by `2.5 h`, through the
/// limit point, the unstable branch (`P` falls to negative values between
/// `w = h` and `2h`) and onto the inverted branch (tension, `P` rising
/// again). The apex's horizontal DOF and the bars' middle nodes are free
/// (`statics_common::truss_with_midpoints`: compressed, the tangent is
/// indefinite). At each of the 50 increments the reaction on the apex must
/// equal the closed form `P(w) = 2 k (L0 − L) (h − w) / L`
/// (`statics_common::load`, derived there from the apex's vertical
/// equilibrium) within 1e-8 of the limit load, and the apex must stay on
/// the axis of symmetry. At `w = 2h` the bars are back at their free
/// length: no force, so the middle nodes have no lateral stiffness and the
/// tangent is singular at that solution. Newton converges only linearly
/// toward a singular solution, so the increment landing on it runs out of
/// iterations and is cut back once; the halves on either side converge.
#[test]
fn von_mises_truss_under_displacement_control_follows_closed_form_through_snap_through() {
    let mut problem = truss_with_midpoints();
    problem
        .prescribe(&[APEX as u32], Dof::Uz, -2.5 * H)
        .unwrap();
    let mut solver = StaticSolver::new(problem, tight(0.02)).unwrap();
    let (w_lim, p_lim) = limit();
    let mut curve = Vec::new();
    let report = solver
        .solve_observed(&mut |s| {
            let w = -s.displacement(APEX).z;
            // The reaction is the force the constraint applies: up, i.e. −P.
            let p = -s.reaction(APEX, Dof::Uz);
            curve.push((w, p, s.displacement(APEX).x));
        })
        .unwrap();
    let mut worst: f64 = 0.0;
    for &(w, p, ux) in &curve {
        worst = worst.max((p - load(w)).abs() / p_lim);
        assert!(
            ux.abs() < 1e-12 * H,
            "apex off axis: ux = {ux:e} mm at w = {w}"
        );
    }
    println!(
        "{} points, w_limit = {w_lim:.6} mm, P_limit = {p_lim:.6} N; max |P − P_exact| / P_limit = {worst:.3e}",
        curve.len()
    );
    print!("{report}");
    assert!(worst < 1e-8, "max error {worst:e} of P_limit");
    assert!(curve.len() >= 50);
    assert!(report.cutbacks <= 1, "{:?}", report.cutback_reasons);
    // The first hump peaks at the limit point; the curve passes over it.
    let hump = curve.iter().filter(|c| c.0 <= H);
    let p_max = hump.map(|c| c.1).fold(f64::MIN, f64::max);
    let p_min = curve.iter().map(|c| c.1).fold(f64::MAX, f64::min);
    assert!(
        p_max > 0.99 * p_lim && p_max <= p_lim,
        "curve top {p_max} vs limit {p_lim}"
    );
    assert!(
        report.system.ldlt > 0,
        "the compressed truss's tangent is indefinite"
    );
    assert!(p_min < -0.99 * p_lim, "the unstable branch reaches {p_min}");
    assert!((curve.last().unwrap().0 - 2.5 * H).abs() < 1e-12);
}

/// Load control: the apex carries a downward load of 0.99 times the limit
/// load, in increments. At each converged increment the deflection must
/// satisfy the closed form, `|P(w) − λ P| <= 1e-8 P_limit`, and equal the
/// closed form's root on the stable branch (bisection to round-off) within
/// 1e-8 relative.
#[test]
fn von_mises_truss_under_load_control_follows_closed_form_up_to_limit() {
    let (_, p_lim) = limit();
    let p = 0.99 * p_lim;
    let mut solver = truss_under_load(p, tight(0.1));
    let mut curve = Vec::new();
    let report = solver
        .solve_observed(&mut |s| curve.push((s.lambda(), -s.displacement(APEX).z)))
        .unwrap();
    let (mut worst_p, mut worst_w): (f64, f64) = (0.0, 0.0);
    for &(lambda, w) in &curve {
        worst_p = worst_p.max((load(w) - lambda * p).abs() / p_lim);
        let w_exact = deflection(lambda * p);
        worst_w = worst_w.max((w - w_exact).abs() / w_exact);
    }
    println!(
        "{} increments to λ P = {p:.6} N: max |P(w) − λP| / P_limit = {worst_p:.3e}, \
         max |w − w_exact| / w_exact = {worst_w:.3e}",
        curve.len()
    );
    print!("{report}");
    assert!(worst_p < 1e-8, "force error {worst_p:e}");
    assert!(worst_w < 1e-8, "deflection error {worst_w:e}");
    assert_eq!(solver.lambda(), 1.0);
}
