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
    Amplitude, Control, Dof, Dofs, NodalLoad, Press, PressStep, ReleaseMethod, Solver,
    SolverSettings, Spring, Springs, StepEnd, Vec3,
};

const K: f64 = 100.0;
const F: f64 = 5.0;

/// Three nodes along x, two springs, node 0 clamped and the others held to
/// the x axis; `free` s of free motion under the end force, then a
/// springback step of tolerance `tol` (at most `max` s) by `method`; with
/// mass-proportional damping `c` (1/s) over the whole run and `before` s
/// of motion before the springback step.
fn chain_by(tol: f64, max: f64, method: ReleaseMethod, c: f64, before: f64) -> Solver {
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
    let settings = SolverSettings {
        damping: c,
        ..SolverSettings::default()
    };
    let mut s = Solver::from_nodes(&nodes, sets, settings).unwrap();
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
            end: StepEnd::Duration(before),
            motions: Vec::new(),
            active_pairs: None,
        },
        PressStep {
            name: "springback".into(),
            end: StepEnd::Settled {
                tolerance: tol,
                max_duration: max,
                method,
            },
            motions: Vec::new(),
            active_pairs: None,
        },
    ];
    s.set_press(Press::new(&[], &[], steps).unwrap()).unwrap();
    s
}

/// The chain released by dynamic relaxation.
fn chain(tol: f64, max: f64) -> Solver {
    chain_by(tol, max, ReleaseMethod::DynamicRelaxation, 0.0, 1e-3)
}

/// Run `s` until its press has finished; the largest energy balance error
/// and the kinetic energy over the external work at each ledger's time.
fn run_to_rest(s: &mut Solver) -> (f64, Vec<(f64, f64)>) {
    let mut balance = 0.0f64;
    let mut kinetic = Vec::new();
    s.run_until(1.001, &mut |sv, r| {
        balance = balance.max(r.energy.balance_error);
        kinetic.push((
            r.energy.time,
            r.energy.kinetic / r.energy.external.max(1e-30),
        ));
        if sv.press().is_some_and(Press::finished) {
            Control::Stop
        } else {
            Control::Continue
        }
    })
    .unwrap();
    (balance, kinetic)
}

/// The same chain released implicitly (`ReleaseMethod::Implicit`): the
/// static solve puts the tip at F/k₁ + F/k₂ to 1e-9 relative (the springs'
/// exact tangent, Newton to its tolerances), the explicit steps after it
/// only confirm the rest (the ten the step takes at least, and not one
/// more), and it agrees with the relaxation within the relaxation's 1e-4.
/// The chain is let go while it still moves (1 ms of motion damped at
/// 1.24e4 1/s, critical for its first mode, ω₁ = 0.618 √(k/m)). The
/// release books the load's work over the jump and the strain energy
/// released exactly, and the kinetic energy left as `½ m v²` of the
/// half-step velocities, which the leapfrog's own measure of it differs
/// from: the energy balance stays within 1e-6 plus the kinetic energy when
/// it was let go (over the external work).
#[test]
fn implicit_release_puts_the_chain_at_its_static_solution() {
    let mut s = chain_by(1e-6, 1.0, ReleaseMethod::Implicit, 1.24e4, 1e-3);
    let (balance, kinetic) = run_to_rest(&mut s);
    let r = s.springback().expect("a springback report").clone();
    let u = s.state().displacement(2).x;
    let exact = 2.0 * F / K;
    let moving = kinetic
        .iter()
        .rfind(|(t, _)| *t < r.t_release)
        .map_or(0.0, |k| k.1);
    let statics = r.implicit.as_ref().expect("a static solve");
    println!(
        "tip {u:.12} mm; {statics}; {} explicit steps, balance {balance:.2e}, kinetic when let go {moving:.2e}",
        r.steps
    );
    assert!(r.settled, "{r:?}");
    assert!(
        (u / exact - 1.0).abs() < 1e-9,
        "tip {u} mm against {exact} mm"
    );
    assert!(statics.iterations() >= 1, "{statics}");
    assert_eq!(r.steps, 10, "{r:?}");
    assert!(moving > 1e-6, "it still moves when let go: {moving}");
    assert!(balance < 1e-6 + moving, "energy balance {balance}");
    let mut dr = chain(1e-6, 1.0);
    run_to_rest(&mut dr);
    let u_dr = dr.state().displacement(2).x;
    assert!((u / u_dr - 1.0).abs() < 1e-4, "{u} against {u_dr}");
}

/// The loaded chain comes to rest at F/k₁ + F/k₂ within 1e-4, settled,
/// with its energy balance closed (module docs).
#[test]
fn relaxation_settles_a_loaded_spring_chain_at_its_static_solution() {
    let mut s = chain(1e-6, 1.0);
    let (balance, _) = run_to_rest(&mut s);
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
