//! The springback step's dynamic relaxation (`fem_core::relaxation`): a
//! press step ended by `StepEnd::Settled` damps the model to its static
//! solution and removes the rigid-body modes left free.
//!
//! Reference: a chain of two axial springs (k₁ = k₂ = 100 N/mm in series),
//! clamped at one end and loaded by a constant end force F = 5 N, is at rest
//! at the tip displacement F/k₁ + F/k₂ = 0.1 mm (statics). The relaxation
//! starts from a vibrating chain (a first step of free motion) and must end
//! within 1e-4 relative of it with the residual tolerance 1e-6, with the
//! energy balance closed to 1e-6 of the external work (the damping work is
//! booked) and in far fewer steps than the free vibration's decay would take.

use std::collections::BTreeMap;

use fem_core::{
    Amplitude, Control, Dof, Dofs, NodalLoad, Press, PressStep, Solver, SolverSettings, Spring,
    Springs, StepEnd, Vec3,
};

const K: f64 = 100.0;
const F: f64 = 5.0;

/// Three nodes along x, two springs, node 0 clamped and the others held to
/// the x axis; `free` s of free motion under the end force, then a
/// springback step of tolerance `tol` (at most `max` s).
fn chain(tol: f64, max: f64) -> Solver {
    let nodes = [
        Vec3::zeros(),
        Vec3::new(10.0, 0.0, 0.0),
        Vec3::new(20.0, 0.0, 0.0),
    ];
    let sets = BTreeMap::from([
        ("base".to_string(), vec![0]),
        ("inner".to_string(), vec![1, 2]),
        ("tip".to_string(), vec![2]),
    ]);
    let mut s = Solver::from_nodes(&nodes, sets, SolverSettings::default()).unwrap();
    let springs = [(0, 1), (1, 2)].map(|(a, b)| Spring {
        a,
        b,
        k: K,
        length0: 10.0,
    });
    s.add_effect(Springs::new("chain", 3, springs.to_vec()).unwrap());
    s.add_point_mass("inner", 1e-6, 0.0).unwrap();
    s.fix("base", Dofs::ALL).unwrap();
    s.fix(
        "inner",
        Dofs::of(&[Dof::Uy, Dof::Uz, Dof::Rx, Dof::Ry, Dof::Rz]),
    )
    .unwrap();
    s.add_load(&NodalLoad {
        set: "tip".into(),
        dof: Dof::Ux,
        value: F,
        amplitude: Amplitude::Constant,
    })
    .unwrap();
    let steps = vec![
        PressStep {
            name: "vibrate".into(),
            end: StepEnd::Duration(1e-3),
            motions: Vec::new(),
            active_pairs: None,
        },
        PressStep {
            name: "springback".into(),
            end: StepEnd::Settled {
                tolerance: tol,
                max_duration: max,
            },
            motions: Vec::new(),
            active_pairs: None,
        },
    ];
    s.set_press(Press::new(&[], &[], steps).unwrap()).unwrap();
    s
}

/// The loaded chain comes to rest at F/k₁ + F/k₂ within 1e-4, settled,
/// with its energy balance closed (module docs).
#[test]
fn relaxation_settles_a_loaded_spring_chain_at_its_static_solution() {
    let mut s = chain(1e-6, 1.0);
    let mut balance = 0.0f64;
    s.run_until(1.001, &mut |sv, r| {
        balance = balance.max(r.energy.balance_error);
        if sv.press().is_some_and(Press::finished) {
            Control::Stop
        } else {
            Control::Continue
        }
    })
    .unwrap();
    let r = s.springback().expect("a springback report").clone();
    let u = s.state().displacement(2).x;
    let exact = 2.0 * F / K;
    println!(
        "tip {u:.8} mm against {exact} mm; {} relaxation steps, {:.3e} s, residual {:.2e} of {:.2e} N, c = {:.3e} 1/s, balance {balance:.2e}",
        r.steps,
        s.time() - r.t_release,
        r.residual,
        r.residual_start,
        r.damping
    );
    assert!(r.settled, "{r:?}");
    assert!(r.fixed.is_empty() && r.free_modes.is_empty(), "{r:?}");
    assert!(
        (u / exact - 1.0).abs() < 1e-4,
        "tip {u} mm against {exact} mm"
    );
    assert!(balance < 1e-6, "energy balance {balance}");
    // The free chain's period is about 2π √(m/k) ≈ 0.6 ms; critical damping
    // brings it to rest in a few periods, not in the step's 1 s.
    assert!(s.time() - r.t_release < 0.02, "{r:?}");
}

/// A step that cannot settle in its duration ends there, not settled.
#[test]
fn relaxation_that_runs_out_of_time_says_so() {
    let mut s = chain(1e-12, 1e-3);
    s.run_until(2.5e-3, &mut |_, _| Control::Continue).unwrap();
    let r = s.springback().expect("a springback report");
    assert!(!r.settled && r.steps > 5, "{r:?}");
    assert!(s.press().is_some_and(Press::finished));
}
