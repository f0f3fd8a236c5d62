//! What the static solver refuses, in one line naming the node and DOF: a
//! free rigid-body mode, a DOF nothing holds, a load nothing carries, bad
//! settings and inputs.

use fem_core::statics::{NewtonSettings, StaticProblem, StaticSolver, StaticsError};
use fem_core::{Dof, Dofs, FemError, Spring, Springs, Vec3};

/// A chain of `n` springs (100 N/mm, 10 mm) along x; nodes `0..=n`.
fn chain(n: usize) -> StaticProblem {
    chain_with(n, |_| 100.0)
}

/// A chain of `n` springs of stiffness `k(i)` (N/mm), 10 mm, along x.
fn chain_with(n: usize, k: impl Fn(u32) -> f64) -> StaticProblem {
    let nodes: Vec<Vec3> = (0..=n)
        .map(|i| Vec3::new(10.0 * i as f64, 0.0, 0.0))
        .collect();
    let springs = (0..n as u32)
        .map(|i| Spring {
            a: i,
            b: i + 1,
            k: k(i),
            length0: 10.0,
        })
        .collect();
    let mut p = StaticProblem::new(&nodes).unwrap();
    p.add_effect(Springs::new("chain", n + 1, springs).unwrap());
    p
}

fn all_nodes(n: usize) -> Vec<u32> {
    (0..=n as u32).collect()
}

/// Asserts a one-line singular-tangent error naming `dof` of some node,
/// and that the solver still holds the finite start state.
fn assert_singular(solver: &StaticSolver, err: &StaticsError, dofs: &[Dof]) {
    let text = err.to_string();
    println!("{text}");
    assert!(!text.contains('\n'), "one line: {text}");
    match err {
        StaticsError::Singular {
            node, dof, lambda, ..
        } => {
            assert!(*node < solver.positions().len());
            assert!(dofs.contains(dof), "{dof:?}");
            assert!(text.contains(&format!("node {node} {}", dof.name())));
            assert!(lambda.is_finite());
        }
        other => panic!("expected a singular tangent, got {other}"),
    }
    assert_eq!(solver.lambda(), 0.0);
    assert!(
        solver
            .positions()
            .iter()
            .all(|p| p.iter().all(|c| c.is_finite()))
    );
}

/// A spring chain guided along x (uy, uz fixed) with nothing fixing x: the
/// rigid translation along x is free. Loaded or not, with round stiffnesses
/// (an exactly zero pivot) or irregular ones (a pivot at round-off), the
/// first tangent is singular and the solve stops at once
/// with the one-line error naming a node's `ux`; no panic, no NaN.
/// Reference: the chain's stiffness matrix is `k` times a path graph's
/// Laplacian, whose null space is the uniform translation.
#[test]
fn spring_chain_with_nothing_fixed_names_a_free_node() {
    let irregular = |i: u32| 100.0 / 3.0 * (1.0 + 0.37 * f64::from(i)).sqrt();
    for (load, round) in [(10.0, true), (0.0, true), (10.0, false)] {
        let mut p = chain_with(4, |i| if round { 100.0 } else { irregular(i) });
        p.fix(&all_nodes(4), Dofs::of(&[Dof::Uy, Dof::Uz])).unwrap();
        p.add_load(&[4], Dof::Ux, load).unwrap();
        let mut solver = StaticSolver::new(p, NewtonSettings::default()).unwrap();
        let err = solver.solve().unwrap_err();
        assert_singular(&solver, &err, &[Dof::Ux]);
    }
}

/// A spring chain clamped at node 0 and loaded along its axis, its other
/// nodes free in y and z: with no tension yet, nothing holds them sideways
/// (zero diagonal), and the error names one of those DOFs. Reference: the
/// lateral stiffness of an axial spring is `T / L`, zero at `T = 0`.
#[test]
fn unstressed_spring_chain_free_sideways_names_a_lateral_dof() {
    let mut p = chain(3);
    p.fix(&[0], Dofs::ALL).unwrap();
    p.add_load(&[3], Dof::Ux, 10.0).unwrap();
    let mut solver = StaticSolver::new(p, NewtonSettings::default()).unwrap();
    let err = solver.solve().unwrap_err();
    assert_singular(&solver, &err, &[Dof::Uy, Dof::Uz]);
}

/// A moment on a node of a spring chain: springs do not stiffen rotations,
/// so the rotations are dropped and the load can be carried by nothing;
/// set-up refuses it naming the node and DOF.
#[test]
fn load_on_a_rotation_no_effect_stiffens_is_refused() {
    let mut p = chain(2);
    p.fix(&[0], Dofs::ALL).unwrap();
    p.add_load(&[2], Dof::Rz, 5.0).unwrap();
    let Err(err) = StaticSolver::new(p, NewtonSettings::default()) else {
        panic!("accepted a load on a dropped DOF");
    };
    println!("{err}");
    assert!(matches!(
        err,
        StaticsError::UnheldLoad {
            node: 2,
            dof: Dof::Rz,
            ..
        }
    ));
    assert!(err.to_string().contains("node 2 rz"));
}

/// Settings out of range are refused, naming the field and the value.
#[test]
fn newton_settings_out_of_range_are_refused_by_name() {
    let cases = [
        NewtonSettings {
            force_tolerance: -1e-8,
            ..Default::default()
        },
        NewtonSettings {
            energy_tolerance: f64::NAN,
            ..Default::default()
        },
        NewtonSettings {
            max_iterations: 0,
            ..Default::default()
        },
        NewtonSettings {
            min_increment: 0.5,
            initial_increment: 0.1,
            ..Default::default()
        },
        NewtonSettings {
            growth_factor: 0.5,
            ..Default::default()
        },
        NewtonSettings {
            pivot_tolerance: 1.0,
            ..Default::default()
        },
        NewtonSettings {
            reuse_contraction: 1.0,
            ..Default::default()
        },
    ];
    let fields = [
        "force_tolerance",
        "energy_tolerance",
        "max_iterations",
        "min_increment",
        "growth_factor",
        "pivot_tolerance",
        "reuse_contraction",
    ];
    for (s, field) in cases.iter().zip(fields) {
        let err = s.validate().unwrap_err();
        println!("{err}");
        assert!(
            matches!(&err, FemError::InvalidParameter { field: f, .. } if f == &format!("newton.{field}"))
        );
        let Err(StaticsError::Setup(_)) = StaticSolver::new(chain(1), *s) else {
            panic!("the solver accepted {field}");
        };
    }
}

/// Inputs out of range are refused by name: a node past the end, a
/// non-finite value, a DOF constrained to two values, a non-finite
/// coordinate.
#[test]
fn static_problem_inputs_out_of_range_are_refused() {
    let mut p = chain(2);
    let e = p.fix(&[3], Dofs::ALL).unwrap_err().to_string();
    assert!(e.contains("node 3 is out of range"), "{e}");
    let e = p
        .add_load(&[1], Dof::Ux, f64::INFINITY)
        .unwrap_err()
        .to_string();
    assert!(e.contains("load ux"), "{e}");
    let e = p
        .prescribe(&[1], Dof::Uy, f64::NAN)
        .unwrap_err()
        .to_string();
    assert!(e.contains("prescribed uy"), "{e}");
    p.prescribe(&[1], Dof::Ux, 1.0).unwrap();
    let e = p.fix(&[1], Dofs::of(&[Dof::Ux])).unwrap_err().to_string();
    assert!(e.contains("node 1: ux is constrained twice"), "{e}");
    let bad = [Vec3::new(0.0, f64::NAN, 0.0)];
    let Err(e) = StaticProblem::new(&bad) else {
        panic!("accepted a NaN coordinate");
    };
    assert!(e.to_string().contains("node 0: coordinate y"), "{e}");
}
