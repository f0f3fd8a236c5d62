//! Newton's residual falls quadratically near the solution with the
//! static BT shells' tangent: the tip-loaded cantilever (`PL²/EI = 5`,
//! 40 × 1 shells) in 5 increments.
//!
//! Source: Newton's method with the exact Jacobian of a smooth residual
//! converges quadratically, `r_{k+1} ≤ C r_k²` near the root (Dennis &
//! Schnabel 1983, Thm 5.2.1); an inexact tangent gives only linear
//! convergence, `r_{k+1} / r_k` bounded away from 0.
//! Check: with the relative residuals `r = ‖R‖ / ‖R_0‖` of each increment,
//! every iteration that starts close to the solution (`r_k ≤ 1e-3`) and
//! ends above the rounding floor (`‖R_{k+1}‖ > 1e-6 N`, where the force
//! criterion stops) satisfies `r_{k+1} ≤ C r_k²` with `C = 300` (measured
//! at most 145), so that each such step multiplies the residual by at
//! most `0.3` at `r_k = 1e-3` and by `3e-3` at `r_k = 1e-5`; and there are
//! at least three such iterations in the solve. Linear convergence would
//! make `r_{k+1} / r_k²` grow as `r_k` falls. The residual histories are
//! printed; docs/springback.md has them.

mod static_common;

use fem_core::Dof;
use fem_core::statics::StaticSolver;
use static_common::{EI, L, clamped_strip, fixed_steps};

#[test]
fn residual_falls_quadratically() {
    let (mut problem, tip) = clamped_strip(40, 1);
    let p = 5.0 * EI / (L * L);
    problem
        .add_load(&tip, Dof::Uz, -p / tip.len() as f64)
        .unwrap();
    let mut solver = StaticSolver::new(problem, fixed_steps(0.2)).unwrap();
    let report = solver.solve().unwrap();
    print!("{report}");
    let floor = 1e-6;
    let (mut worst, mut steps): (f64, usize) = (0.0, 0);
    for inc in &report.increments {
        let r = &inc.residuals;
        for k in 0..r.len() - 1 {
            let (a, b) = (r[k] / r[0], r[k + 1] / r[0]);
            if a <= 1e-3 && r[k + 1] > floor {
                let c = b / (a * a);
                println!(
                    "λ = {:.1}: r_k = {a:.3e}, r_k+1 = {b:.3e}, r_k+1 / r_k² = {c:.3e}",
                    inc.lambda
                );
                worst = worst.max(c);
                steps += 1;
            }
        }
    }
    println!("{steps} iterations near the solution, largest r_k+1 / r_k² = {worst:.3e}");
    assert!(steps >= 3, "only {steps} iterations near the solution");
    assert!(worst < 300.0);
}
