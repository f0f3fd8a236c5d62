//! Engine verification with spring models: central-difference accuracy, energy balance,
//! time step, mass scaling, boundary conditions, loads, dynamic relaxation, collapse errors.

use fem_core::{
    Amplitude, Control, Dof, Dofs, Effect, EffectId, EnergyTally, FemError, Forces, History,
    MotionKind, NodalLoad, NodalState, Solver, SolverSettings, Spring, Springs, StableDt,
    StepContext, Vec3,
};
use std::collections::BTreeMap;
use std::f64::consts::PI;

const M: f64 = 1e-3; // tonne (1 kg)
const K: f64 = 100.0; // N/mm

/// A chain of `n` springs along x (length 10 mm each), node 0 fixed, point
/// mass `m` on nodes 1..=n. Sets: base, tip, free, all.
fn chain(n: usize, k: f64, m: f64, settings: SolverSettings) -> (Solver, EffectId) {
    let nodes: Vec<Vec3> = (0..=n)
        .map(|i| Vec3::new(10.0 * i as f64, 0.0, 0.0))
        .collect();
    let mut sets = BTreeMap::new();
    sets.insert("base".to_string(), vec![0]);
    sets.insert("tip".to_string(), vec![n as u32]);
    sets.insert("free".to_string(), (1..=n as u32).collect());
    sets.insert("all".to_string(), (0..=n as u32).collect());
    let springs = (0..n)
        .map(|i| Spring {
            a: i as u32,
            b: i as u32 + 1,
            k,
            length0: 10.0,
        })
        .collect();
    let mut s = Solver::from_nodes(&nodes, sets, settings).unwrap();
    let id = s.add_effect(Springs::new("chain", n + 1, springs).unwrap());
    s.add_point_mass("free", m, 0.0).unwrap();
    s.fix("base", Dofs::ALL).unwrap();
    (s, id)
}

/// Downward zero crossings of `u(t)`, linearly interpolated.
fn crossings(samples: &[(f64, f64)]) -> Vec<f64> {
    samples
        .windows(2)
        .filter(|w| w[0].1 > 0.0 && w[1].1 <= 0.0)
        .map(|w| w[0].0 + (w[1].0 - w[0].0) * w[0].1 / (w[0].1 - w[1].1))
        .collect()
}

/// Period and peak |u| of a single oscillator released from `u0`, with `steps_per_period`.
fn oscillator(steps_per_period: f64) -> (f64, f64, f64) {
    let omega = (K / M).sqrt();
    let period = 2.0 * PI / omega;
    let settings = SolverSettings {
        safety_factor: 1.0,
        dt_max: Some(period / steps_per_period),
        ..Default::default()
    };
    let (mut s, _) = chain(1, K, M, settings);
    let u0 = 0.5;
    s.state_mut().x[1].x += u0;
    let mut samples = vec![(0.0, u0)];
    let mut peak: f64 = 0.0;
    s.run_until(10.5 * period, &mut |s, r| {
        let u = s.state().displacement(1).x;
        samples.push((r.time, u));
        peak = peak.max(u.abs());
        Control::Continue
    })
    .unwrap();
    let c = crossings(&samples);
    let measured = (c[c.len() - 1] - c[0]) / (c.len() - 1) as f64;
    (measured, period, peak / u0)
}

// Central difference on u'' = -ω² u: the discrete solution is u_n = u0 cos(ω_d n Δt)
// with sin(ω_d Δt / 2) = ω Δt / 2 (Belytschko, Liu & Moran, Nonlinear Finite Elements,
// §6.3), so the period error is ≈ (ωΔt)²/24: second order, amplitude exact.
// Tolerances: period vs ω_d within 1e-6 (interpolation of crossings); ratio of errors
// at 50 and 100 steps/period in [3.8, 4.2]; peak amplitude within 0.2 % of u0, never above.
#[test]
fn mass_spring_oscillator_period_and_amplitude_match_analytic() {
    let omega = (K / M).sqrt();
    let mut errors = Vec::new();
    for n in [50.0, 100.0, 200.0] {
        let (t_meas, t_exact, peak) = oscillator(n);
        let dt = t_exact / n;
        let omega_d = 2.0 / dt * (omega * dt / 2.0).asin();
        let t_discrete = 2.0 * PI / omega_d;
        let err = (t_meas - t_exact) / t_exact;
        println!(
            "steps/period {n}: period {t_meas:.9e} s, exact {t_exact:.9e}, rel err {err:.3e}, \
             vs discrete theory {:.2e}, peak/u0 {peak:.6}",
            (t_meas - t_discrete) / t_discrete
        );
        assert!(((t_meas - t_discrete) / t_discrete).abs() < 1e-6);
        assert!(peak <= 1.0 + 1e-12 && peak > 0.998, "peak/u0 = {peak}");
        errors.push(err);
    }
    // ω_d > ω: the discrete period is shorter.
    assert!(errors[0] < 0.0 && errors[0] > -1e-3, "{errors:?}");
    for w in errors.windows(2) {
        let order = w[0] / w[1];
        assert!((3.8..4.2).contains(&order), "error ratio {order}, want ≈ 4");
    }
}

// Same oscillator, with the time step varying by ±30 % (averaged-Δt velocity update):
// still second order. Tolerance: error < 1e-3 at ≈ 50 steps/period, ratio of errors
// between 50 and 100 steps/period > 3 (a first-order scheme would give 2).
#[test]
fn variable_time_step_keeps_second_order_accuracy() {
    let e50 = oscillator_variable(50.0);
    let e100 = oscillator_variable(100.0);
    println!("variable dt: rel period error {e50:.3e} (50/period), {e100:.3e} (100/period)");
    assert!(e50.abs() < 1e-3);
    assert!(e50 / e100 > 3.0, "ratio {}", e50 / e100);
}

/// A force-free effect whose stable dt oscillates ±30 % with simulated time.
struct Wobble {
    base: f64,
    time: f64,
    omega: f64,
}

impl Effect for Wobble {
    fn name(&self) -> &str {
        "wobble"
    }
    fn stable_dt(&self, _s: &NodalState) -> Option<StableDt> {
        Some(StableDt {
            dt: self.base * (1.0 + 0.3 * (self.omega * self.time).sin()),
            element: 0,
            what: "test schedule",
        })
    }
    fn add_forces(
        &mut self,
        c: &StepContext,
        _s: &NodalState,
        _f: &mut Forces,
        _fields: &mut fem_core::FieldAccess<'_>,
    ) -> Result<(), FemError> {
        self.time = c.time;
        Ok(())
    }
}

// A step that varies by ±30 % every few steps: the spring chain's energy
// still balances to round-off, because the ledger's integration term holds
// the exact difference between the springs' trapezoidal work and central
// difference's kinetic-energy update at a step change
// (fem_core::energy). Tolerance 1e-11 relative: round-off over 20,000 steps.
#[test]
fn energy_balances_at_a_varying_step() {
    let (mut s, period) = wobbling_chain(3, 40.0);
    s.state_mut().x[3].x += 0.5;
    s.state_mut().x[1].x -= 0.2;
    let mut worst = 0.0f64;
    let mut dts = (f64::INFINITY, 0.0f64);
    s.run_until(200.0 * period, &mut |_, r| {
        worst = worst.max(r.energy.balance_error);
        dts = (dts.0.min(r.dt), dts.1.max(r.dt));
        Control::Continue
    })
    .unwrap();
    assert!(dts.1 > 1.5 * dts.0, "the step varied: {dts:?}");
    assert!(worst < 1e-11, "worst balance error {worst:e}");
}

/// A chain of `n` springs whose step `Wobble` varies by ±30 % around
/// `period / steps_per_period` (`period` of one mass on one spring, returned).
fn wobbling_chain(n: usize, steps_per_period: f64) -> (Solver, f64) {
    let omega = (K / M).sqrt();
    let period = 2.0 * PI / omega;
    let settings = SolverSettings {
        safety_factor: 1.0,
        ..Default::default()
    };
    let (mut s, _) = chain(n, K, M, settings);
    s.add_effect(Wobble {
        base: period / steps_per_period,
        time: 0.0,
        omega: 2.0 * PI / (0.37 * period),
    });
    (s, period)
}

fn oscillator_variable(steps_per_period: f64) -> f64 {
    let (mut s, period) = wobbling_chain(1, steps_per_period);
    let u0 = 0.5;
    s.state_mut().x[1].x += u0;
    let mut samples = vec![(0.0, u0)];
    let mut dts = (f64::INFINITY, 0.0f64);
    s.run_until(10.5 * period, &mut |s, r| {
        samples.push((r.time, s.state().displacement(1).x));
        dts = (dts.0.min(r.dt), dts.1.max(r.dt));
        Control::Continue
    })
    .unwrap();
    assert!(dts.1 / dts.0 > 1.7, "dt range {dts:?}");
    let c = crossings(&samples);
    let measured = (c[c.len() - 1] - c[0]) / (c.len() - 1) as f64;
    (measured - period) / period
}

// An undamped linear spring chain (no loads): central difference conserves
// ½ v_{n-1/2}·M v_{n+1/2} + ½ xᵀK x exactly at constant Δt (Hughes, The Finite Element
// Method, §9.3); the ledger uses that kinetic form, so the balance error is round-off.
// Tolerance: balance error < 1e-6 relative over 5000 steps.
#[test]
fn undamped_spring_chain_conserves_energy() {
    let (mut s, _) = chain(10, K, M, SolverSettings::default());
    for i in 1..=10 {
        s.state_mut().x[i].x += 0.3 * ((i * 7 % 5) as f64 - 2.0) / 2.0;
    }
    s.state_mut().v[4].x = 50.0;
    let mut worst: f64 = 0.0;
    let mut e0 = None;
    for _ in 0..5000 {
        let r = s.step().unwrap();
        worst = worst.max(r.energy.balance_error);
        e0.get_or_insert(r.energy.total());
    }
    let l = s.ledger();
    println!(
        "5000 steps: worst balance error {worst:.2e}; E_kin {:.6} mJ, E_int {:.6} mJ, E0 {:.6} mJ",
        l.kinetic,
        l.internal,
        e0.unwrap()
    );
    assert!(worst < 1e-6, "worst balance error {worst}");
    assert!(l.internal > 0.0 && l.kinetic > 0.0);
}

// The engine takes safety × the smallest stable dt over the effects and over
// the nodes they share (their stiffnesses summed per node, fem_core::nodal_limit),
// names the limiting node and the effects on it; dt_max caps it.
// Springs' bound: Δt = √(2 m / Σk). Tolerance: 1e-12 relative.
#[test]
fn stable_time_step_is_respected() {
    let settings = SolverSettings::default();
    let (mut s, _) = chain(3, K, M, settings);
    // A stiffer spring 2–3 (node 3 is the tip: Σk = 5K there, 6K at node 2).
    let stiff = Springs::new(
        "stiff",
        4,
        vec![Spring {
            a: 2,
            b: 3,
            k: 4.0 * K,
            length0: 10.0,
        }],
    )
    .unwrap();
    s.add_effect(stiff);
    let setup = s.initialize().unwrap();
    // Per effect: chain √(2m/2K) at nodes 1, 2; stiff √(2m/4K) at nodes 2, 3.
    // Together at node 2: Σk = 2K + 4K, √(2m/6K): the combined limit rules.
    let expect = 0.9 * (2.0 * M / (6.0 * K)).sqrt();
    assert!((setup.dt_initial - expect).abs() < 1e-12 * expect);
    let lim = setup.limit.unwrap();
    assert!(lim.combined);
    assert_eq!(lim.stable.element, 2);
    assert_eq!(s.effect_name(lim.effect), "stiff");
    let r = s.step().unwrap();
    assert!((r.dt - expect).abs() < 1e-12 * expect && (r.dt_next - expect).abs() < 1e-12 * expect);

    let capped = SolverSettings {
        dt_max: Some(1e-5),
        ..Default::default()
    };
    let (mut s, _) = chain(3, K, M, capped);
    let r = s.step().unwrap();
    assert_eq!((r.dt, r.limit), (1e-5, None));
}

// Fixed-time-step mass scaling: the springs add mass so that √(2 m_i / Σk_i) ≥ target/safety,
// i.e. m_i ≥ Σk_i (target/safety)² / 2. Predicted added mass computed here by hand;
// tolerance 1e-12 relative; the run then uses exactly the target step.
#[test]
fn mass_scaling_adds_the_predicted_mass() {
    let n = 5;
    let target = 2.0 * (M / K).sqrt(); // twice the interior nodes' stable dt
    let settings = SolverSettings {
        mass_scaling_dt: Some(target),
        ..Default::default()
    };
    let (mut s, _) = chain(n, K, M, settings);
    let setup = s.initialize().unwrap();
    let goal = target / 0.9;
    // Node 0 (fixed, no point mass): Σk = K; nodes 1..n-1: 2K; tip: K.
    let need = |ksum: f64| 0.5 * ksum * goal * goal;
    let predicted = need(K) + (n - 1) as f64 * (need(2.0 * K) - M) + (need(K) - M).max(0.0);
    let physical = n as f64 * M;
    println!(
        "added {:.6e} t (predicted {predicted:.6e}), {:.2} % of {physical:.1e} t",
        setup.added_mass, setup.added_mass_percent
    );
    assert!((setup.added_mass - predicted).abs() < 1e-12 * predicted);
    assert!((setup.added_mass_percent - 100.0 * predicted / physical).abs() < 1e-9);
    assert!((setup.dt_initial - target).abs() < 1e-15);
    let r = s.step().unwrap();
    assert!((r.dt_next - target).abs() < 1e-15);
    assert_eq!(s.added_mass().0, setup.added_mass);
}

/// A square of 4 nodes with 6 springs (edges + diagonals) in the plane z = 0, side 10.
fn square(settings: SolverSettings) -> Solver {
    let nodes = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(10.0, 0.0, 0.0),
        Vec3::new(10.0, 10.0, 0.0),
        Vec3::new(0.0, 10.0, 0.0),
    ];
    let mut sets = BTreeMap::new();
    sets.insert("x0".to_string(), vec![0, 3]);
    sets.insert("x1".to_string(), vec![1, 2]);
    sets.insert("n0".to_string(), vec![0]);
    sets.insert("n2".to_string(), vec![2]);
    sets.insert("all".to_string(), vec![0, 1, 2, 3]);
    let pairs = [(0, 1), (1, 2), (2, 3), (3, 0), (0, 2), (1, 3)];
    let springs = pairs
        .iter()
        .map(|&(a, b)| Spring {
            a,
            b,
            k: K,
            length0: if (a + b) % 2 == 0 {
                200f64.sqrt()
            } else {
                10.0
            },
        })
        .collect();
    let mut s = Solver::from_nodes(&nodes, sets, settings).unwrap();
    s.add_effect(Springs::new("square", 4, springs).unwrap());
    s.add_point_mass("all", M, 1e-2).unwrap();
    s
}

// Fixed DOFs keep their value exactly; a symmetry plane x = const fixes ux, ry, rz
// (and leaves uy, uz, rx free). Pulling node 2 in +x and +y: nodes 0, 3 (on the plane
// x = 0) slide along y only. Exact (tolerance 0).
#[test]
fn fixed_dofs_and_symmetry_plane_hold() {
    assert_eq!(Dofs::symmetry(0), Dofs::of(&[Dof::Ux, Dof::Ry, Dof::Rz]));
    assert_eq!(Dofs::symmetry(1), Dofs::of(&[Dof::Uy, Dof::Rx, Dof::Rz]));
    assert_eq!(Dofs::symmetry(2), Dofs::of(&[Dof::Uz, Dof::Rx, Dof::Ry]));
    let mut s = square(SolverSettings::default());
    s.symmetry("x0", 0).unwrap();
    s.fix("n0", Dofs::of(&[Dof::Uy])).unwrap();
    s.fix("all", Dofs::of(&[Dof::Uz])).unwrap();
    for (dof, value) in [
        (Dof::Ux, 50.0),
        (Dof::Uy, 80.0),
        (Dof::Rx, 1.0),
        (Dof::Rz, 1.0),
    ] {
        s.add_load(&NodalLoad {
            set: "all".into(),
            dof,
            value,
            amplitude: Amplitude::Constant,
        })
        .unwrap();
    }
    s.run_until(5e-3, &mut |_, _| Control::Continue).unwrap();
    let st = s.state();
    assert_eq!(st.x[0], st.x0[0]);
    assert_eq!(st.x[3].x, 0.0);
    assert!(st.x[3].y - st.x0[3].y > 0.1, "node 3 slides along y");
    assert!(st.x[2].x > 10.1);
    for i in 0..4 {
        assert_eq!(st.x[i].z, 0.0);
    }
    for i in [0, 3] {
        assert_eq!((st.w[i].y, st.w[i].z), (0.0, 0.0));
        assert!(st.w[i].x > 0.0, "rx is free on the plane");
    }
    assert!(st.w[1].z > 0.0);
}

// Prescribed displacement with a C² smooth step (6ξ⁵−15ξ⁴+10ξ³) reaches the target
// exactly at t1 (tolerance 1e-12 mm) and the prescribed node is at rest afterwards
// (exactly zero velocity); the reaction work balances kinetic + spring energy
// (linear system: balance error < 1e-9).
#[test]
fn prescribed_smooth_step_reaches_target_with_zero_end_velocity() {
    // Constant Δt dividing t1 (the energy identity is exact at constant Δt).
    let t1 = 0.2;
    let settings = SolverSettings {
        dt_max: Some(t1 / 100.0),
        ..Default::default()
    };
    let (mut s, _) = chain(2, K, M, settings);
    let target = 2.0;
    s.prescribe(
        "tip",
        Dof::Ux,
        MotionKind::Displacement,
        target,
        Amplitude::SmoothStep { t0: 0.0, t1 },
    )
    .unwrap();
    let mut worst: f64 = 0.0;
    let r = s
        .run_until(t1, &mut |_, r| {
            worst = worst.max(r.energy.balance_error);
            Control::Continue
        })
        .unwrap();
    assert_eq!(s.time(), t1);
    let u = s.state().displacement(2).x;
    let v = s.state().v[2].x;
    println!(
        "at t1: u = {u:.15} mm, v_(n+1/2) = {v:.3e} mm/s, steps {}",
        r.steps
    );
    assert!((u - target).abs() < 1e-12);
    // v_{n-1/2} over the last step is O(Δt²) because A'(t1) = 0.
    assert!(v.abs() < 1e-2 * target / t1);
    s.run_until(1.5 * t1, &mut |_, r| {
        worst = worst.max(r.energy.balance_error);
        Control::Continue
    })
    .unwrap();
    assert!((s.state().displacement(2).x - target).abs() < 1e-12);
    assert_eq!(s.state().v[2].x, 0.0);
    let l = s.ledger();
    println!(
        "W_prescribed {:.6} mJ = E_kin {:.6} + E_int {:.6}; worst balance error {worst:.2e}",
        l.external_prescribed, l.kinetic, l.internal
    );
    assert!(l.external_prescribed > 0.0);
    assert!(worst < 1e-9, "{worst}");

    // Prescribed velocity: x = x0 + v t exactly (linear amplitude held at 1).
    let (mut s, _) = chain(2, K, M, SolverSettings::default());
    s.prescribe(
        "tip",
        Dof::Uy,
        MotionKind::Velocity,
        100.0,
        Amplitude::Constant,
    )
    .unwrap();
    s.run_until(2e-3, &mut |_, _| Control::Continue).unwrap();
    assert!((s.state().displacement(2).y - 0.2).abs() < 1e-12);
}

// A suddenly applied constant load on an undamped single oscillator: peak deflection
// twice the static one, P/k (dynamic amplification 2, Clough & Penzien, Dynamics of
// Structures, §4-4). Discrete sampling at 100 steps/period: within 0.1 %. The load's
// work balances the energies: balance error < 1e-9 (linear system).
#[test]
fn suddenly_applied_load_doubles_static_deflection() {
    let period = 2.0 * PI * (M / K).sqrt();
    let settings = SolverSettings {
        dt_max: Some(period / 100.0),
        ..Default::default()
    };
    let (mut s, _) = chain(1, K, M, settings);
    let p = 30.0;
    s.add_load(&NodalLoad {
        set: "tip".into(),
        dof: Dof::Ux,
        value: p,
        amplitude: Amplitude::Constant,
    })
    .unwrap();
    let mut peak: f64 = 0.0;
    let mut worst: f64 = 0.0;
    s.run_until(3.0 * period, &mut |s, r| {
        peak = peak.max(s.state().displacement(1).x);
        worst = worst.max(r.energy.balance_error);
        Control::Continue
    })
    .unwrap();
    let l = s.ledger();
    println!(
        "peak {peak:.6} mm (2P/k = {:.6}); W_loads {:.6} mJ; worst balance error {worst:.2e}",
        2.0 * p / K,
        l.external_loads
    );
    assert!((peak / (2.0 * p / K) - 1.0).abs() < 1e-3);
    assert!(worst < 1e-9);
}

// A nodal moment on a node with only rotational inertia: w = M t / I; the rotational
// kinetic energy equals the moment's work. Tolerances 1e-12 relative (constant
// acceleration is integrated exactly), energy balance < 1e-9.
#[test]
fn nodal_moment_spins_up_rotational_inertia() {
    let nodes = vec![Vec3::zeros()];
    let mut sets = BTreeMap::new();
    sets.insert("n".to_string(), vec![0]);
    let settings = SolverSettings {
        dt_max: Some(1e-4),
        ..Default::default()
    };
    let mut s = Solver::from_nodes(&nodes, sets, settings).unwrap();
    let inertia = 2e-3;
    s.add_point_mass("n", M, inertia).unwrap();
    let moment = 5.0;
    s.add_load(&NodalLoad {
        set: "n".into(),
        dof: Dof::Rz,
        value: moment,
        amplitude: Amplitude::Constant,
    })
    .unwrap();
    s.run_until(1e-2, &mut |_, _| Control::Continue).unwrap();
    // w is at t − Δt/2.
    let t_half = s.time() - 0.5e-4;
    let w = s.state().w[0].z;
    assert!((w - moment * t_half / inertia).abs() < 1e-12 * w);
    let l = s.ledger();
    assert!(l.kinetic_rotational > 0.0 && (l.kinetic - l.kinetic_rotational).abs() < 1e-15);
    assert!(l.balance_error < 1e-9, "{}", l.balance_error);
}

// Dynamic relaxation (mass-proportional damping c = 2 ω₁, ω₁ the chain's lowest
// frequency) of a chain of 10 springs under a tip load reaches the static answer
// u_i = i P / k. Tolerance: 1e-6 relative at the tip; energy balance with the
// damping term < 1e-8.
#[test]
fn dynamic_relaxation_converges_to_static_spring_chain() {
    let n = 10;
    let w1 = 2.0 * (K / M).sqrt() * (PI / (2.0 * (2 * n + 1) as f64)).sin();
    let settings = SolverSettings {
        damping: 2.0 * w1,
        ..Default::default()
    };
    let (mut s, _) = chain(n, K, M, settings);
    let p = 20.0;
    s.add_load(&NodalLoad {
        set: "tip".into(),
        dof: Dof::Ux,
        value: p,
        amplitude: Amplitude::Constant,
    })
    .unwrap();
    let mut worst: f64 = 0.0;
    let summary = s
        .run_until(1.0, &mut |s, r| {
            worst = worst.max(r.energy.balance_error);
            if r.step > 100 && r.energy.kinetic < 1e-16 * r.energy.internal {
                return Control::Stop;
            }
            let _ = s;
            Control::Continue
        })
        .unwrap();
    let tip = s.state().displacement(n).x;
    let exact = n as f64 * p / K;
    let l = s.ledger();
    println!(
        "DR: {} steps, tip {tip:.10} mm (static {exact}), E_int {:.6}, E_damp {:.6}, W {:.6}, \
         worst balance error {worst:.2e}",
        summary.steps, l.internal, l.damping, l.external
    );
    assert!(summary.stopped_by_callback);
    assert!((tip / exact - 1.0).abs() < 1e-6);
    for i in 1..n {
        assert!((s.state().displacement(i).x - i as f64 * p / K).abs() < 1e-6 * exact);
    }
    assert!(l.damping > 0.0);
    assert!(worst < 1e-8, "{worst}");
}

/// An effect whose stable time step shrinks exponentially (a collapsing element 42).
struct Shrinking {
    time: f64,
}

impl Effect for Shrinking {
    fn name(&self) -> &str {
        "shrinking"
    }
    fn stable_dt(&self, _s: &NodalState) -> Option<StableDt> {
        Some(StableDt {
            dt: 1e-5 * (-self.time / 5e-5).exp(),
            element: 42,
            what: "element length / wave speed",
        })
    }
    fn add_forces(
        &mut self,
        c: &StepContext,
        _s: &NodalState,
        _f: &mut Forces,
        _fields: &mut fem_core::FieldAccess<'_>,
    ) -> Result<(), FemError> {
        self.time = c.time;
        Ok(())
    }
    fn energies(&self) -> EnergyTally {
        EnergyTally::default()
    }
}

// A collapsing time step stops the run with an error naming the effect, the element
// and the cause; the solver keeps the state computed so far.
#[test]
fn time_step_collapse_names_the_element() {
    let (mut s, _) = chain(2, K, M, SolverSettings::default());
    s.add_effect(Shrinking { time: 0.0 });
    let mut seen = 0u64;
    let err = s
        .run_until(1.0, &mut |_, _| {
            seen += 1;
            Control::Continue
        })
        .unwrap_err();
    let msg = err.to_string();
    println!("{msg}");
    match err {
        FemError::TimeStepCollapse {
            element,
            effect,
            dt,
            floor,
            step,
            ..
        } => {
            assert_eq!((element, effect.as_str()), (42, "shrinking"));
            assert!(dt < floor);
            assert_eq!(step, seen + 1);
        }
        other => panic!("unexpected {other:?}"),
    }
    assert!(msg.contains("element 42 of `shrinking` (element length / wave speed)"));
    assert!(s.time() > 2e-4 && s.steps() == seen + 1);
    assert!(s.state().x.iter().all(|x| x.iter().all(|c| c.is_finite())));
}

// Set-up errors name the set, node or field.
#[test]
fn bad_setup_is_reported() {
    let (mut s, _) = chain(2, K, M, SolverSettings::default());
    let e = s.fix("nope", Dofs::ALL).unwrap_err().to_string();
    assert_eq!(e, "unknown node set `nope`; known: all, base, free, tip");
    let e = s
        .prescribe(
            "base",
            Dof::Ux,
            MotionKind::Velocity,
            1.0,
            Amplitude::Constant,
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("node 0: DOF ux is constrained twice"), "{e}");
    let e = s
        .add_load(&NodalLoad {
            set: "tip".into(),
            dof: Dof::Ux,
            value: 1.0,
            amplitude: Amplitude::Linear { t0: 1.0, t1: 1.0 },
        })
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "parameter `amplitude.t1` = 1 s is out of range: must be finite and > t0"
    );
    let bad = SolverSettings {
        safety_factor: 1.5,
        ..Default::default()
    };
    assert!(chain_err(bad).contains("`safety_factor` = 1.5"));
    // No effect imposes a time step and no dt_max.
    let mut sets = BTreeMap::new();
    sets.insert("n".to_string(), vec![0]);
    let mut s = Solver::from_nodes(&[Vec3::zeros()], sets, SolverSettings::default()).unwrap();
    s.add_point_mass("n", M, 0.0).unwrap();
    assert!(s.step().unwrap_err().to_string().contains("set `dt_max`"));
}

fn chain_err(settings: SolverSettings) -> String {
    let nodes = vec![Vec3::zeros()];
    match Solver::from_nodes(&nodes, BTreeMap::new(), settings) {
        Err(e) => e.to_string(),
        Ok(_) => String::new(),
    }
}

/// The chain of `stable_time_step_is_respected` (limit √(2M/6K) at node 2,
/// the two spring effects together) at a fixed step.
fn stiff_chain(fixed: f64) -> Solver {
    let settings = SolverSettings {
        fixed_dt: Some(fixed),
        ..Default::default()
    };
    let (mut s, _) = chain(3, K, M, settings);
    let stiff = vec![Spring {
        a: 2,
        b: 3,
        k: 4.0 * K,
        length0: 10.0,
    }];
    s.add_effect(Springs::new("stiff", 4, stiff).unwrap());
    s.state_mut().x[3].x += 0.1;
    s
}

// A fixed step: at 0.95 of the combined limit every step takes exactly it;
// at 1.05 the solver refuses the first step with one line naming node 2 and
// both effects on it. Exclusive with mass scaling and dt_max.
#[test]
fn fixed_step_is_checked_against_the_combined_limit() {
    let limit = (2.0 * M / (6.0 * K)).sqrt();
    let mut s = stiff_chain(0.95 * limit);
    for _ in 0..100 {
        let r = s.step().unwrap();
        assert_eq!(r.dt, 0.95 * limit);
    }
    let e = stiff_chain(1.05 * limit).initialize().unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, FemError::StepAboveStableLimit { .. }), "{msg}");
    assert!(
        msg.contains("node 2") && msg.contains("chain") && msg.contains("stiff"),
        "{msg}"
    );
    assert!(!msg.contains('\n'));
    for other in [
        SolverSettings {
            fixed_dt: Some(1e-6),
            mass_scaling_dt: Some(1e-6),
            ..Default::default()
        },
        SolverSettings {
            fixed_dt: Some(1e-6),
            dt_max: Some(1e-6),
            ..Default::default()
        },
    ] {
        assert!(chain_err(other).contains("fixed_dt"));
    }
    let bad = SolverSettings {
        fixed_dt: Some(f64::NAN),
        ..Default::default()
    };
    assert!(chain_err(bad).contains("fixed_dt"));
}

// Amplitudes: values and rates at the ends and in between (exact formulas).
#[test]
fn amplitudes_evaluate_their_formulas() {
    let s = Amplitude::SmoothStep { t0: 1.0, t1: 3.0 };
    assert_eq!(
        (s.value(0.0), s.value(1.0), s.value(3.0), s.value(4.0)),
        (0.0, 0.0, 1.0, 1.0)
    );
    assert!((s.value(2.0) - 0.5).abs() < 1e-15);
    assert!((s.rate(2.0) - 30.0 / 16.0 / 2.0).abs() < 1e-15);
    assert_eq!((s.rate(1.0), s.rate(3.0)), (0.0, 0.0));
    let l = Amplitude::Linear { t0: 0.0, t1: 2.0 };
    assert_eq!((l.value(1.0), l.value(5.0), l.rate(1.0)), (0.5, 1.0, 0.5));
    let t = Amplitude::Table(vec![(0.0, 0.0), (1.0, 2.0), (3.0, 1.0)]);
    assert_eq!(
        (t.value(-1.0), t.value(0.5), t.value(2.0), t.value(9.0)),
        (0.0, 1.0, 1.5, 1.0)
    );
    assert_eq!(t.rate(2.0), -0.5);
    let bad = Amplitude::Table(vec![(0.0, 0.0), (0.0, 1.0)]);
    assert!(
        bad.validate()
            .unwrap_err()
            .to_string()
            .contains("amplitude.table[1].t")
    );
}

// run_until lands exactly on t_end, the callback can stop the run, the history records
// rows and writes CSV, and an effect can be read back as its concrete type.
#[test]
fn run_loop_history_and_effect_access() {
    let (mut s, id) = chain(3, K, M, SolverSettings::default());
    s.state_mut().x[3].x += 0.1;
    let mut h = History::new(10, 0.0);
    let sum = s
        .run_until(0.1234, &mut |_, r| {
            h.record(r);
            Control::Continue
        })
        .unwrap();
    assert_eq!(s.time(), 0.1234);
    h.force_record(&sum.last.unwrap());
    assert!(h.rows.len() >= 2 && h.rows.last().unwrap().time == 0.1234);
    let mut csv = Vec::new();
    h.write_csv(&mut csv).unwrap();
    let csv = String::from_utf8(csv).unwrap();
    assert_eq!(csv.lines().count(), h.rows.len() + 1);
    assert!(csv.starts_with("step,time_s,dt_s,"));
    let stop = s
        .run_until(1.0, &mut |_, r| {
            if r.step >= sum.steps + 3 {
                Control::Stop
            } else {
                Control::Continue
            }
        })
        .unwrap();
    assert!(stop.stopped_by_callback && stop.steps == 3);
    let springs: &Springs = s.effect(id).unwrap();
    assert_eq!(springs.springs().len(), 3);
    assert!(s.effect::<Shrinking>(id).is_none());
}

/// A grounded spring on node 1 whose stiffness grows in time, `k = K (1 + t/τ)`;
/// internal energy by the trapezoidal work of its force (consistent with the engine).
struct Stiffening {
    tau: f64,
    k: f64,
    f_old: f64,
    x_old: f64,
    energy: f64,
}

impl Effect for Stiffening {
    fn name(&self) -> &str {
        "stiffening"
    }
    fn stable_dt(&self, s: &NodalState) -> Option<StableDt> {
        Some(StableDt {
            dt: (2.0 * s.mass[1] / self.k).sqrt(),
            element: 0,
            what: "stiffening spring",
        })
    }
    fn scale_mass(
        &mut self,
        _s: &NodalState,
        target: f64,
        mass: &mut [f64],
        _j: &mut [f64],
    ) -> f64 {
        let need = 0.5 * self.k * target * target;
        let added = (need - mass[1]).max(0.0);
        mass[1] += added;
        added
    }
    fn add_forces(
        &mut self,
        c: &StepContext,
        s: &NodalState,
        f: &mut Forces,
        _fields: &mut fem_core::FieldAccess<'_>,
    ) -> Result<(), FemError> {
        self.k = K * (1.0 + c.time / self.tau);
        let u = s.displacement(1).x;
        let force = -self.k * u;
        self.energy -= 0.5 * (force + self.f_old) * (u - self.x_old);
        self.f_old = force;
        self.x_old = u;
        f.f[1].x += force;
        Ok(())
    }
    fn energies(&self) -> EnergyTally {
        EnergyTally {
            internal: self.energy,
            ..Default::default()
        }
    }
}

// Mass added during the run (fixed-step mass scaling while a stiffening spring
// shrinks the stable step) keeps the step at the target, is reported, and its
// kinetic-energy contribution ½ Δm |v|² is booked so that the balance stays closed.
// Tolerances: dt = target to 1e-15 relative; balance error < 1e-9 (linear, constant Δt);
// while the last steps shrink (≤ 3 %) to land on t_end, < 1e-2 (the scheme has no exact
// energy identity at varying Δt; here ωΔt ≈ 1.1, close to the stability limit 2).
#[test]
fn mass_scaling_during_the_run_keeps_the_step_and_the_balance() {
    let period = 2.0 * PI * (M / K).sqrt();
    let target = 0.5 * 0.9 * (2.0 * M / K).sqrt();
    let settings = SolverSettings {
        mass_scaling_dt: Some(target),
        ..Default::default()
    };
    let nodes = vec![Vec3::zeros(), Vec3::new(10.0, 0.0, 0.0)];
    let mut sets = BTreeMap::new();
    sets.insert("tip".to_string(), vec![1]);
    let mut s = Solver::from_nodes(&nodes, sets, settings).unwrap();
    s.add_point_mass("tip", M, 0.0).unwrap();
    s.add_effect(Stiffening {
        tau: period,
        k: K,
        f_old: 0.0,
        x_old: 0.0,
        energy: 0.0,
    });
    s.state_mut().v[1].x = 100.0;
    let setup = s.initialize().unwrap();
    assert_eq!(setup.added_mass, 0.0);
    let (mut worst, mut worst_landing): (f64, f64) = (0.0, 0.0);
    s.run_until(10.0 * period, &mut |_, r| {
        // Constant Δt = target, except over the last ≤ 32 steps that land on t_end.
        if r.time < 10.0 * period - 33.0 * target {
            assert!((r.dt - target).abs() <= 1e-15 * target);
            worst = worst.max(r.energy.balance_error);
        } else {
            assert!(r.dt <= target && r.dt > 0.96 * target);
            worst_landing = worst_landing.max(r.energy.balance_error);
        }
        Control::Continue
    })
    .unwrap();
    let (added, percent) = s.added_mass();
    let l = s.ledger();
    println!(
        "added {added:.4e} t ({percent:.1} %), W_mass_scaling {:.4} mJ, worst balance error \
         {worst:.2e} at constant Δt, {worst_landing:.2e} while landing on t_end",
        l.external_mass_scaling
    );
    // k grew to 11 K: the node needs ½ 11 K target² of mass.
    let need = 0.5 * K * (1.0 + (10.0 * period - target) / period) * target * target;
    assert!(added > 0.0 && (M + added) >= need * (1.0 - 1e-3));
    assert!(l.external_mass_scaling > 0.0);
    assert!(worst < 1e-9, "{worst}");
    assert!(worst_landing < 1e-2, "{worst_landing}");
}

// Reactions: the fixed base of a statically loaded chain carries −P; the reaction
// is the constraint's force on the node (tolerance 1e-6 relative after relaxation).
#[test]
fn reactions_balance_the_applied_load() {
    let n = 4;
    let w1 = 2.0 * (K / M).sqrt() * (PI / (2.0 * (2 * n + 1) as f64)).sin();
    let settings = SolverSettings {
        damping: 2.0 * w1,
        ..Default::default()
    };
    let (mut s, _) = chain(n, K, M, settings);
    let p = 20.0;
    s.add_load(&NodalLoad {
        set: "tip".into(),
        dof: Dof::Ux,
        value: p,
        amplitude: Amplitude::SmoothStep { t0: 0.0, t1: 0.05 },
    })
    .unwrap();
    s.run_until(0.5, &mut |_, _| Control::Continue).unwrap();
    let (f, m) = s.reaction("base").unwrap();
    println!("base reaction {f:?}");
    assert!((f.x + p).abs() < 1e-6 * p, "{f:?}");
    assert_eq!((f.y, f.z, m.norm()), (0.0, 0.0, 0.0));
    let (f, _) = s.reaction("free").unwrap();
    assert_eq!(f, Vec3::zeros());
}

/// Puts a NaN force on node 2 from t > 1 ms.
struct Poison;

impl Effect for Poison {
    fn name(&self) -> &str {
        "poison"
    }
    fn add_forces(
        &mut self,
        c: &StepContext,
        _s: &NodalState,
        f: &mut Forces,
        _fields: &mut fem_core::FieldAccess<'_>,
    ) -> Result<(), FemError> {
        if c.time > 1e-3 {
            f.f[2].y = f64::NAN;
        }
        Ok(())
    }
}

// A non-finite nodal force stops the run with an error naming the node, the quantity
// and the time; an invalid mesh is refused at set-up naming the element.
#[test]
fn non_finite_force_and_bad_mesh_are_named() {
    let (mut s, _) = chain(3, K, M, SolverSettings::default());
    s.add_effect(Poison);
    let e = s.run_until(1.0, &mut |_, _| Control::Continue).unwrap_err();
    match e {
        FemError::NonFiniteState {
            node, field, time, ..
        } => {
            assert_eq!((node, field), (2, "force (N)"));
            assert!(time > 1e-3 && time == s.time());
        }
        other => panic!("unexpected {other:?}"),
    }
    let mut mesh = fem_core::rectangle(2.0, 1.0, 2, 1).unwrap();
    mesh.nodes[4] = Vec3::new(0.5, 0.0, 0.0); // node (1,1) dropped onto the bottom edge
    let e = Solver::new(&mesh, SolverSettings::default())
        .err()
        .unwrap()
        .to_string();
    assert!(e.starts_with("element 0: "), "{e}");
}

/// `step_toward(t_end)` until `t_end` takes the steps of `run_until(t_end)`
/// (same times and states, bit for bit) and lands on `t_end` exactly; a
/// `t_end` already reached is refused.
#[test]
fn step_toward_takes_the_steps_of_run_until() {
    let t_end = 0.0123;
    let (mut a, _) = chain(3, K, M, SolverSettings::default());
    let (mut b, _) = chain(3, K, M, SolverSettings::default());
    for s in [&mut a, &mut b] {
        s.state_mut().x[3].x += 0.5;
    }
    let mut times = Vec::new();
    a.run_until(t_end, &mut |_, r| {
        times.push(r.time);
        Control::Continue
    })
    .unwrap();
    let mut times_b = Vec::new();
    while b.time() < t_end {
        times_b.push(b.step_toward(t_end).unwrap().time);
    }
    assert_eq!(times, times_b);
    assert_eq!(b.time(), t_end);
    assert_eq!(a.state(), b.state());
    let e = b.step_toward(t_end).unwrap_err().to_string();
    assert!(e.contains("t_end"), "{e}");
}
