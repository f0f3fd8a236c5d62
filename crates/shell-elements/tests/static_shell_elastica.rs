//! A tip-loaded cantilever against the elastica: the static BT shells
//! under a dead transverse tip load `P` at `PL²/EI = 1, 2, 5`.
//!
//! Source: the inextensible Euler–Bernoulli elastica of a cantilever with
//! a vertical dead tip load. With `θ(s)` the slope, `EI θ'' = −P cos θ`,
//! `θ(0) = 0`, `θ'(L) = 0`, the tip slope `θ₀` solves
//! `√(2k) = ∫₀^θ₀ dθ / √(sin θ₀ − sin θ)` (`k = PL²/EI`), and the tip's
//! deflection and horizontal displacement are
//! `w/L = ∫₀^θ₀ sin θ dθ / √(sin θ₀ − sin θ) / √(2k)`,
//! `u/L = 1 − √(2 sin θ₀ / k)`. The test computes them (substitution
//! `θ = θ₀ (1 − τ²)`, which removes the end singularity, composite
//! 3-point Gauss over 400 intervals, bisection for `θ₀`); they reproduce
//! Mattiasson's table (1981, IJNME 17: `w/L` = 0.30172, 0.49346, 0.71379,
//! `u/L` = 0.05643, 0.16064, 0.38763) to the five digits printed there.
//! Strip: L = 100 mm, b = 10 mm, t = 1 mm, E = 200 GPa, ν = 0, 40 × 1
//! shells, `P` split over the two tip nodes along −z, 20 increments.
//! Tolerance: tip deflection and shortening within 0.5 % of L, tip
//! rotation within 0.5 % of `θ₀` (measured figures printed;
//! docs/springback.md).

mod static_common;

use fem_core::Dof;
use fem_core::statics::StaticSolver;
use static_common::{EI, L, angle_about_y, clamped_strip, fixed_steps, mean};

/// `∫₀^θ₀ f(θ) dθ / √(sin θ₀ − sin θ)` with `θ = θ₀ (1 − τ²)`.
fn elastica_integral(theta0: f64, f: impl Fn(f64) -> f64) -> f64 {
    let gauss = [
        (-(0.6f64).sqrt(), 5.0 / 9.0),
        (0.0, 8.0 / 9.0),
        ((0.6f64).sqrt(), 5.0 / 9.0),
    ];
    let n = 400;
    let h = 1.0 / n as f64;
    let mut sum = 0.0;
    for i in 0..n {
        for (x, w) in gauss {
            let tau = (i as f64 + 0.5 + 0.5 * x) * h;
            let th = theta0 * (1.0 - tau * tau);
            sum += w * 0.5 * h * f(th) * 2.0 * theta0 * tau / (theta0.sin() - th.sin()).sqrt();
        }
    }
    sum
}

/// Tip slope, deflection over L and horizontal displacement over L of
/// the elastica at `k = PL²/EI`.
fn elastica(k: f64) -> (f64, f64, f64) {
    let target = (2.0 * k).sqrt();
    let (mut a, mut b) = (1e-9, std::f64::consts::FRAC_PI_2 - 1e-9);
    for _ in 0..100 {
        let m = 0.5 * (a + b);
        if elastica_integral(m, |_| 1.0) < target {
            a = m;
        } else {
            b = m;
        }
    }
    let theta0 = 0.5 * (a + b);
    let w = elastica_integral(theta0, f64::sin) / target;
    let u = 1.0 - (2.0 * theta0.sin() / k).sqrt();
    (theta0, w, u)
}

/// The elastica's own check against Mattiasson's table (five digits).
#[test]
fn elastica_reference_reproduces_mattiasson() {
    for (k, w, u) in [
        (1.0, 0.30172, 0.05643),
        (2.0, 0.49346, 0.16064),
        (5.0, 0.71379, 0.38763),
    ] {
        let (_, wk, uk) = elastica(k);
        assert!(
            (wk - w).abs() < 6e-6 && (uk - u).abs() < 6e-6,
            "k = {k}: {wk} {uk}"
        );
    }
}

/// The shells at `k`: errors of deflection, shortening (over L) and tip
/// rotation (over θ₀).
fn cantilever(k: f64) -> (f64, f64, f64) {
    let (mut problem, tip) = clamped_strip(40, 1);
    let p = k * EI / (L * L);
    problem
        .add_load(&tip, Dof::Uz, -p / tip.len() as f64)
        .unwrap();
    let mut solver = StaticSolver::new(problem, fixed_steps(0.05)).unwrap();
    let report = solver.solve().unwrap();
    let d = mean(&tip, |n| solver.displacement(n));
    // The load along −z bends the tip down: rotation about +y, positive.
    let theta = angle_about_y(&solver.rotation(tip[0] as usize));
    let (theta0, w, u) = elastica(k);
    let (ew, eu, et) = (
        (-d.z / L - w).abs(),
        (-d.x / L - u).abs(),
        (theta - theta0).abs() / theta0,
    );
    println!(
        "PL²/EI = {k}: {} increments, {} iterations; w/L = {:.5} (elastica {w:.5}, error {ew:.2e}), \
         u/L = {:.5} ({u:.5}, {eu:.2e}), θ = {theta:.5} rad ({theta0:.5}, {et:.2e})",
        report.increments.len(),
        report.iterations(),
        -d.z / L,
        -d.x / L,
    );
    (ew, eu, et)
}

#[test]
fn tip_load_one_matches_the_elastica() {
    let (ew, eu, et) = cantilever(1.0);
    assert!(ew < 5e-3 && eu < 5e-3 && et < 5e-3);
}

#[test]
fn tip_load_two_matches_the_elastica() {
    let (ew, eu, et) = cantilever(2.0);
    assert!(ew < 5e-3 && eu < 5e-3 && et < 5e-3);
}

#[test]
fn tip_load_five_matches_the_elastica() {
    let (ew, eu, et) = cantilever(5.0);
    assert!(ew < 5e-3 && eu < 5e-3 && et < 5e-3);
}
