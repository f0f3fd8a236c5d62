//! An end moment rolls a clamped elastic strip into a circle: the static
//! fully integrated shells against the exact solution of pure bending.
//!
//! Source: Euler–Bernoulli pure bending, `κ = M / EI` uniform, so the
//! strip bends into an arc of radius `R = EI / M` and the tip turns by
//! `θ = M L / EI` (Sze, Liu & Lo 2004, "Popular benchmark problems for
//! geometric nonlinear analysis of shells", FEA&D 40). With the moment
//! about +y the tip sits at `x = R sin θ`, `z = −R (1 − cos θ)`;
//! `M = 2π EI/L` closes a full circle, `M = π EI/L` makes a half circle.
//! Strip, load and solver settings as the Belytschko–Tsay test
//! (`static_shell_end_moment.rs`): L = 100 mm, b = 10 mm, t = 1 mm,
//! E = 200 GPa, ν = 0, 40 × 1 shells (and 40 × 2 for the half circle), a
//! dead end moment about +y shared by the tip nodes.
//! Tolerances, the Belytschko–Tsay test's: tip position within 0.5 % of
//! L, tip rotation within 0.5 % of `θ` (measured figures printed;
//! docs/springback.md). The error is the midpoint configuration's (module
//! docs of `shell_elements::statics`), the same for both elements: the tip
//! rotation falls short by about `Δθ_tip²/24`; halving the increment
//! quarters it (ratio in [3.5, 4.5]).

mod static_common;

use shell_elements::FullyIntegrated;

/// Roll the strip of `40 × across` fully integrated shells with
/// `M = factor · EI / L` in increments of `dl`; the tip's position error
/// over L and rotation error over θ.
fn roll(factor: f64, dl: f64, across: usize) -> (f64, f64) {
    static_common::roll_strip(FullyIntegrated::default(), factor, dl, across)
}

#[test]
fn fi_end_moment_closes_the_strip_into_a_full_circle() {
    let (pos, rot) = roll(std::f64::consts::TAU, 0.025, 1);
    assert!(pos < 5e-3, "tip position error {pos:.3e} L");
    assert!(rot < 5e-3, "tip rotation error {rot:.3e}");
}

#[test]
fn fi_half_the_moment_makes_a_half_circle() {
    let (pos, rot) = roll(std::f64::consts::PI, 0.05, 1);
    assert!(pos < 5e-3, "tip position error {pos:.3e} L");
    assert!(rot < 5e-3, "tip rotation error {rot:.3e}");
}

#[test]
fn fi_two_shells_across_make_the_same_half_circle() {
    let (pos, rot) = roll(std::f64::consts::PI, 0.05, 2);
    assert!(pos < 5e-3, "tip position error {pos:.3e} L");
    assert!(rot < 5e-3, "tip rotation error {rot:.3e}");
}

#[test]
fn fi_increment_error_is_second_order() {
    let (_, coarse) = roll(std::f64::consts::TAU, 0.025, 1);
    let (_, fine) = roll(std::f64::consts::TAU, 0.0125, 1);
    let predicted = (std::f64::consts::TAU * 0.025).powi(2) / 24.0;
    println!(
        "rotation error {coarse:.3e} (Δθ_tip²/24 = {predicted:.3e}) → {fine:.3e}, ratio {:.3}",
        coarse / fine
    );
    assert!((3.5..=4.5).contains(&(coarse / fine)));
}
