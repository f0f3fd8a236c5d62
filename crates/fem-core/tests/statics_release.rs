//! A stress release (`StaticProblem::release_start_forces`), the static
//! form of springback: a chain of springs held stretched at its start state
//! (the tools' forces) is let go and comes to rest at its free lengths, or
//! in balance with a dead load that stays on.

use fem_core::statics::{NewtonSettings, StaticProblem, StaticSolver};
use fem_core::{Dof, Dofs, Spring, Springs, Vec3};

/// Three nodes on the x axis, 0–1–2, 10 mm apart, springs of 100 and
/// 200 N/mm whose free lengths are 8 and 9 mm: at the start both springs
/// pull (200 N each), in balance only if something holds node 1 and 2.
fn stretched_chain(load: f64) -> StaticSolver {
    let x: Vec<Vec3> = (0..3)
        .map(|i| Vec3::new(10.0 * f64::from(i), 0.0, 0.0))
        .collect();
    let springs = vec![
        Spring {
            a: 0,
            b: 1,
            k: 100.0,
            length0: 8.0,
        },
        Spring {
            a: 1,
            b: 2,
            k: 200.0,
            length0: 9.0,
        },
    ];
    let mut p = StaticProblem::new(&x).unwrap();
    p.add_effect(Springs::new("chain", 3, springs).unwrap());
    p.fix(&[0], Dofs::ALL).unwrap();
    p.fix(&[1, 2], Dofs::of(&[Dof::Uy, Dof::Uz])).unwrap();
    p.release_start_forces();
    if load != 0.0 {
        p.add_load(&[2], Dof::Ux, load).unwrap();
    }
    StaticSolver::new(p, NewtonSettings::default()).unwrap()
}

/// Let go with no load: each spring returns to its free length exactly
/// (statics; tolerance 1e-9 mm) and the fixed end reacts nothing. The
/// start state is the solve's λ = 0 balance: the first increment starts
/// from the residual `Δλ × 200 N`, the force the tools held at node 2
/// (node 1's two springs pull 200 N each way).
#[test]
fn stretched_chain_released_returns_to_its_free_lengths() {
    let mut s = stretched_chain(0.0);
    let report = s.solve().unwrap();
    let first = &report.increments[0];
    println!("{report:?}");
    assert!(
        (first.residuals[0] - first.increment * 200.0).abs() < 1e-9,
        "{first:?}"
    );
    let x = s.positions();
    assert!((x[1].x - 8.0).abs() < 1e-9, "{x:?}");
    assert!((x[2].x - 17.0).abs() < 1e-9, "{x:?}");
    assert!(s.reaction(0, Dof::Ux).abs() < 1e-6, "nothing left to react");
}

/// Let go under a 50 N dead load at the free end: the chain ends in
/// balance with it, each spring 50 N longer than free (0.5 and 0.25 mm;
/// tolerance 1e-9 mm), the fixed end reacting −50 N.
#[test]
fn stretched_chain_released_under_a_load_balances_it() {
    let mut s = stretched_chain(50.0);
    s.solve().unwrap();
    let x = s.positions();
    assert!((x[1].x - 8.5).abs() < 1e-9, "{x:?}");
    assert!((x[2].x - 17.75).abs() < 1e-9, "{x:?}");
    assert!((s.reaction(0, Dof::Ux) + 50.0).abs() < 1e-6);
}
