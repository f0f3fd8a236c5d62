//! An end moment rolls a clamped elastic strip into a circle: the static
//! BT shells against the exact solution of pure bending.
//!
//! Source: Euler–Bernoulli pure bending, `κ = M / EI` uniform, so the
//! strip bends into an arc of radius `R = EI / M` and the tip turns by
//! `θ = M L / EI` (the classic check of large-rotation shells, e.g.
//! Sze, Liu & Lo 2004, "Popular benchmark problems for geometric
//! nonlinear analysis of shells", FEA&D 40). With the moment about +y
//! the tip sits at `x = R sin θ`, `z = −R (1 − cos θ)`.
//! `M = 2π EI/L` closes a full circle (tip back at the root), `M = π EI/L`
//! makes a half circle (tip at `z = −2L/π`).
//! Strip: L = 100 mm, b = 10 mm, t = 1 mm, E = 200 GPa, ν = 0, 40 × 1
//! shells (and 40 × 2 for the half circle); the moment is shared by the
//! tip nodes as a uniform edge moment (trapezoid weights), a dead moment
//! about +y (it stays normal to the plane of bending).
//! Tolerances: tip position within 0.5 % of L, tip rotation within 0.5 %
//! of `θ` (measured figures printed; docs/springback.md). The error is
//! the midpoint configuration's (module docs of `shell_elements::statics`):
//! an element turning by `α` in one increment reads its curvature
//! increment over its midpoint length, `cos(α/2)` short, so under a given
//! moment it bends by about `α²/8` too little, and the tip rotation falls
//! short by the mean over the strip, `Δθ_tip²/24` with
//! `Δθ_tip` the tip's rotation per increment; the third test checks that
//! halving the increment quarters it (ratio in [3.5, 4.5]).

mod static_common;

use fem_core::Dof;
use fem_core::statics::StaticSolver;
use static_common::{EI, L, add_edge_load, angle_about_y, clamped_strip, fixed_steps, mean};

/// Roll the strip of `40 × across` shells with `M = factor · EI / L` in
/// increments of `dl`; the tip's position error over L and rotation error
/// over θ.
fn roll(factor: f64, dl: f64, across: usize) -> (f64, f64) {
    let (mut problem, tip) = clamped_strip(40, across);
    let m = factor * EI / L;
    add_edge_load(&mut problem, &tip, Dof::Ry, m);
    let mut solver = StaticSolver::new(problem, fixed_steps(dl)).unwrap();
    // The tip's rotation, unwrapped increment by increment.
    let (mut theta, mut last) = (0.0, 0.0);
    let report = solver
        .solve_observed(&mut |s| {
            let a = angle_about_y(&s.rotation(tip[0] as usize));
            let mut d = a - last;
            d -= (d / std::f64::consts::TAU).round() * std::f64::consts::TAU;
            theta += d;
            last = a;
        })
        .unwrap();
    let exact_theta = m * L / EI;
    let r = EI / m;
    let exact = fem_core::Vec3::new(r * exact_theta.sin(), 0.0, -r * (1.0 - exact_theta.cos()));
    let x = mean(&tip, |k| solver.positions()[k]);
    let tip_y = fem_core::Vec3::new(0.0, static_common::B / 2.0, 0.0);
    let pos_err = (x - tip_y - exact).norm() / L;
    let rot_err = (theta - exact_theta).abs() / exact_theta;
    println!(
        "40 × {across} shells, M = {factor:.4} EI/L, Δλ = {dl}: {} increments, {} iterations; tip at \
         ({:.4}, {:.4}, {:.4}) mm, exact ({:.4}, 0, {:.4}); |Δx|/L = {pos_err:.3e}; \
         θ = {theta:.5} rad, exact {exact_theta:.5}, error {rot_err:.3e}",
        report.increments.len(),
        report.iterations(),
        x.x,
        x.y - tip_y.y,
        x.z,
        exact.x,
        exact.z,
    );
    (pos_err, rot_err)
}

#[test]
fn end_moment_closes_the_strip_into_a_full_circle() {
    let (pos, rot) = roll(std::f64::consts::TAU, 0.025, 1);
    assert!(pos < 5e-3, "tip position error {pos:.3e} L");
    assert!(rot < 5e-3, "tip rotation error {rot:.3e}");
}

#[test]
fn half_the_moment_makes_a_half_circle() {
    let (pos, rot) = roll(std::f64::consts::PI, 0.05, 1);
    assert!(pos < 5e-3, "tip position error {pos:.3e} L");
    assert!(rot < 5e-3, "tip rotation error {rot:.3e}");
}

#[test]
fn two_shells_across_make_the_same_half_circle() {
    let (pos, rot) = roll(std::f64::consts::PI, 0.05, 2);
    assert!(pos < 5e-3, "tip position error {pos:.3e} L");
    assert!(rot < 5e-3, "tip rotation error {rot:.3e}");
}

#[test]
fn increment_error_is_second_order() {
    let (_, coarse) = roll(std::f64::consts::TAU, 0.025, 1);
    let (_, fine) = roll(std::f64::consts::TAU, 0.0125, 1);
    let predicted = (std::f64::consts::TAU * 0.025).powi(2) / 24.0;
    println!(
        "rotation error {coarse:.3e} (Δθ_tip²/24 = {predicted:.3e}) → {fine:.3e}, ratio {:.3}",
        coarse / fine
    );
    assert!((3.5..=4.5).contains(&(coarse / fine)));
}
