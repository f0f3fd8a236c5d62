//! # Step 2: a block on a plane, through the explicit engine
//!
//! **What it shows.** How a model is put together from the engine crates and
//! run, on the smallest model that has contact with friction: a stiff block
//! (four nodes joined by six springs) pressed onto a rigid plane by a normal
//! force `N` and pulled along `x` by a slowly ramped tangential force `T`.
//! Step 1 drove one friction point by hand; here the explicit solver
//! (`fem_core::Solver`, central differences) moves the nodes and the contact
//! effect (`contact::ContactEffect`) finds the touching nodes, computes their
//! penalty pressure and slip increment every step and hands them to the same
//! kind of `PointIntegrator`. The stages, in the order the code below builds
//! them:
//!
//! 1. **nodes and sets**: positions, and named node sets that loads and
//!    masses refer to;
//! 2. **the solver** over those nodes (default settings: the time step is
//!    90 % of the smallest stable step any effect reports);
//! 3. **masses**: lumped point masses (the block has no elements to carry a
//!    density);
//! 4. **springs** (`fem_core::Springs`, an effect): the block's stiffness;
//! 5. **the tool**: an exact NURBS plane (`tools_nurbs::builders::primitives::plane`);
//! 6. **the contact pair** (`contact::ContactPair`: tool × blank nodes × friction
//!    law) inside a `ContactEffect`, which owns the tools, an optional press
//!    (none here: the plane does not move) and the blank's nodal geometry
//!    (`BlankGeometry`: the quad gives each node its tributary area);
//! 7. **loads and amplitudes**: `N` rises smoothly, then `T` ramps linearly;
//! 8. **`run_until` with a callback** that watches the contact points' status
//!    after every step;
//! 9. **the energy ledger**: where the work of the loads went.
//!
//! **The physics.** Amontons–Coulomb friction (`μ = 0.144`) holds the block
//! as long as `T < μ N`; it starts to slide at `T = μ N` (with `N = 1000 N`:
//! 144 N). The pull ramps to `2 μ N` over 0.1 s, slowly against the block's
//! own dynamics (on its contact springs it rings at about 1 kHz normal to
//! the plane and 8 kHz along it), so the onset of slip is quasi-static and
//! happens where the static balance says. Reference:
//! docs/benchmarks.md §3 ("Block on a plane"), tolerance 1 %, the one
//! `crates/contact/tests/block_on_plane.rs` uses.
//!
//! **Run:** `cargo run --release -p formsim-examples --example step2_block_on_plane`
//!
//! **Output.** The set-up (time step, what limits it), a history every
//! 10 ms (applied `T`, the friction and normal forces the block exerts on
//! the plane, the points' status, the block's travel), the force at which
//! all four points first slip against `μ N`, and the energy ledger at the
//! end, e.g.
//!
//! ```text
//!   t (s)    T (N)   F_t (N)   F_n (N)  stick/slip   u_x (mm)
//! ...
//!  0.0600   115.25    115.16   1000.42    4/0        0.00001
//!  0.0700   144.00    144.02   1000.16    0/4        0.00001
//!  0.0800   172.86    143.94    999.56    0/4        0.12072
//! ...
//! slip starts at T = 144.00 N; mu N = 144.00 N (rel. error 0.00 %, tolerance 1 %)
//! energy (mJ) at t = 0.120 s: loads 3775.092 = kinetic 1615.472 + springs 0.000 + contact 4.158 +
//! friction 2155.464; balance error 1.1e-8
//! ```
//!
//! Once sliding, the friction force stays at `μ N` while the pull keeps
//! growing: the difference accelerates the block (its kinetic energy).

use contact::{BlankGeometry, ContactEffect, ContactPair, PairSpec, PointStatus};
use fem_core::{Amplitude, Control, Dof, NodalLoad, Solver, SolverSettings, Spring, Springs, Vec3};
use friction_laws::builtin;
use plugins_api::{Params, TangentMode, ToolSurface};
use std::collections::BTreeMap;
use tools_nurbs::builders::primitives::plane;
use tools_nurbs::builders::{Facing, Placement};

/// Coulomb coefficient (the square cup's, docs/friction-math.md §7).
const MU: f64 = 0.144;
/// Normal force on the block (N).
const N: f64 = 1000.0;
/// The pull ramps linearly from 0 at `T0` to `2 μ N` at `T1` (s).
const T0: f64 = 0.02;
/// End of the ramp (s).
const T1: f64 = 0.12;

/// Block thickness (mm).
const THICKNESS: f64 = 1.0;

/// The whole example, stage by stage (the numbers of the header).
fn run() {
    // --- 1. Nodes and sets ---------------------------------------------------
    let (nodes, sets) = block_nodes_and_sets();

    // --- 2. The solver --------------------------------------------------------
    let mut solver = Solver::from_nodes(&nodes, sets, SolverSettings::default())
        .expect("finite coordinates and in-range sets");

    // --- 3. Masses ------------------------------------------------------------
    // 1 kg (1e-3 tonne) per node; no rotational inertia (the nodes only
    // translate: nothing applies a moment).
    solver
        .add_point_mass("block", 1e-3, 0.0)
        .expect("the set exists and the mass is positive");

    // --- 4. Springs -----------------------------------------------------------
    add_block_springs(&mut solver, &nodes);

    // --- 5. The tool ----------------------------------------------------------
    let tools = plane_tool();

    // --- 6. The contact pair ----------------------------------------------------
    let contact_id = add_contact(&mut solver, &nodes, tools);

    // --- 7. Loads and amplitudes ------------------------------------------------
    let (t_max, ramp) = add_loads(&mut solver);

    // Set-up: masses gathered, effects ordered, the first stable step found.
    initialize_and_print_setup(&mut solver, t_max);

    // --- 8. Run, watching the contact points ----------------------------------
    let slip_at = run_watching_contact(&mut solver, contact_id, t_max, &ramp);
    check_slip_onset(slip_at, t_max, &ramp);

    // --- 9. The energy ledger ----------------------------------------------------
    check_energy_ledger(&solver);
}

/// Stage 1: the block's four nodes and the node set `block` that holds them.
fn block_nodes_and_sets() -> (Vec<Vec3>, BTreeMap<String, Vec<u32>>) {
    // A 10 × 10 mm block, 1 mm thick. Contact measures the gap of the
    // blank's *face* (the nodes are its mid-surface, offset by half the
    // thickness towards the tool), so nodes at z = t/2 put the face exactly
    // on the plane z = 0.
    let side = 10.0;
    let z = 0.5 * THICKNESS;
    let nodes = vec![
        Vec3::new(0.0, 0.0, z),
        Vec3::new(side, 0.0, z),
        Vec3::new(side, side, z),
        Vec3::new(0.0, side, z),
    ];
    let sets = BTreeMap::from([("block".to_string(), vec![0, 1, 2, 3])]);
    (nodes, sets)
}

/// Stage 4: the block's stiffness, six springs (an effect) between its nodes.
fn add_block_springs(solver: &mut Solver, nodes: &[Vec3]) {
    // Four edges and two diagonals, 1e5 N/mm each: stiff enough that the
    // block deforms by micrometres, so it moves as one body.
    let springs = [(0, 1), (1, 2), (2, 3), (3, 0), (0, 2), (1, 3)]
        .into_iter()
        .map(|(a, b): (u32, u32)| Spring {
            a,
            b,
            k: 1e5,
            length0: (nodes[a as usize] - nodes[b as usize]).norm(),
        })
        .collect();
    solver.add_effect(
        Springs::new("block springs", nodes.len(), springs).expect("valid node indices and k > 0"),
    );
}

/// Stage 5: the tool, an exact NURBS plane, as the list of tools contact owns.
fn plane_tool() -> Vec<Box<dyn ToolSurface>> {
    // A 100 × 100 mm plane through the origin, its normal (the side the blank
    // may be on) pointing up. Tools are rigid: a press could move them, and
    // contact only sees them through the `ToolSurface` trait.
    let tool = plane(
        "plane",
        100.0,
        100.0,
        &Placement {
            origin: Vec3::zeros(),
            facing: Facing::Up,
        },
    )
    .expect("positive length and width");
    vec![Box::new(tool)]
}

/// Stage 6: the contact pair (the plane against every node, AC friction)
/// inside a `ContactEffect`; returns the effect's id, to read the contact
/// state back during the run.
fn add_contact(
    solver: &mut Solver,
    nodes: &[Vec3],
    tools: Vec<Box<dyn ToolSurface>>,
) -> fem_core::EffectId {
    // The blank's geometry: one quad over the four nodes gives each node a
    // quarter of the 100 mm² face as its area (pressure = normal force / area).
    let quads = [[0u32, 1, 2, 3]];
    let geometry = BlankGeometry::new(nodes.len(), &quads).expect("valid quad");
    // The friction model: a law paired with a formulation, as in step 1.
    let friction = builtin::integrator(
        "ac",
        &Params::new().with("mu", MU),
        "convective",
        TangentMode::None,
    )
    .expect("ac and convective are built in");
    // The pair: tool 0 against every node. The penalty stiffness of each node
    // follows the blank's bulk modulus (steel's E/(3(1 - 2ν)) here, in MPa)
    // and the pair's penalty scale (default 0.1; docs/contact.md).
    let spec = PairSpec::new("plane-block", 0, 1.7e5);
    let pair = ContactPair::new(&spec, friction, &geometry, nodes).expect("valid pair settings");
    // No press: the plane stays where it was built.
    let contact = ContactEffect::new(tools, vec![pair], geometry, vec![THICKNESS; 4])
        .expect("the pair's tool exists and there is one thickness per node");
    solver.add_effect(contact)
}

/// Stage 7: the normal force `N` (a smooth step over 10 ms) and the pull `T`
/// (a linear ramp to `2 μ N` from `T0` to `T1`). Returns `2 μ N` and the
/// pull's ramp.
fn add_loads(solver: &mut Solver) -> (f64, Amplitude) {
    // A load is a force per node times a time function A(t). N rises over
    // 10 ms with a C² smooth step (no jerk to set the block ringing) ...
    solver
        .add_load(&NodalLoad {
            set: "block".into(),
            dof: Dof::Uz,
            value: -N / 4.0,
            amplitude: Amplitude::SmoothStep { t0: 0.0, t1: 0.01 },
        })
        .expect("valid load");
    // ... then T ramps linearly from 0 at T0 to 2 μ N at T1.
    let t_max = 2.0 * MU * N;
    let ramp = Amplitude::Linear { t0: T0, t1: T1 };
    solver
        .add_load(&NodalLoad {
            set: "block".into(),
            dof: Dof::Ux,
            value: t_max / 4.0,
            amplitude: ramp.clone(),
        })
        .expect("valid load");
    (t_max, ramp)
}

/// Set-up: masses gathered, effects ordered, the first stable step found;
/// print the problem and the time step.
fn initialize_and_print_setup(solver: &mut Solver, t_max: f64) {
    let setup = solver.initialize().expect("a valid model");
    println!(
        "Step 2: block on a plane, N = {N} N, AC mu = {MU}; T ramps to 2 mu N = {t_max} N over \
         {T0}-{T1} s"
    );
    println!(
        "time step {:.3e} s, limited by {}\n",
        setup.dt_initial,
        setup
            .limit
            .as_ref()
            .map_or("dt_max", |l| solver.effect_name(l.effect))
    );
}

/// Stage 8: run to `T1`, printing a history every 10 ms; returns the time
/// of the first step at which all four points slipped.
fn run_watching_contact(
    solver: &mut Solver,
    contact_id: fem_core::EffectId,
    t_max: f64,
    ramp: &Amplitude,
) -> Option<f64> {
    // The callback runs after every step with the solver (read-only) and the
    // step's report; it could also stop the run (`Control::Stop`).
    let mut slip_at: Option<f64> = None;
    let mut next_print = 0.01;
    println!("  t (s)    T (N)   F_t (N)   F_n (N)  stick/slip   u_x (mm)");
    solver
        .run_until(T1, &mut |s: &Solver, report| {
            let c: &ContactEffect = s
                .effect(contact_id)
                .expect("the id was returned for a ContactEffect");
            let pair = &c.pairs()[0];
            let slipping = pair
                .status
                .iter()
                .filter(|st| **st == PointStatus::Slip)
                .count();
            let sticking = pair
                .status
                .iter()
                .filter(|st| **st == PointStatus::Stick)
                .count();
            if slipping == 4 && slip_at.is_none() {
                slip_at = Some(report.time);
            }
            if report.time >= next_print {
                next_print += 0.01;
                // The reaction is what the block does to the plane: friction
                // along x, the normal force along -z.
                let r = pair.reaction.force;
                println!(
                    "{:7.4} {:8.2} {:9.2} {:9.2}    {sticking}/{slipping}   {:12.5}",
                    report.time,
                    t_max * ramp.value(report.time),
                    r.x,
                    -r.z,
                    s.state().displacement(0).x
                );
            }
            Control::Continue
        })
        .expect("the run completes");
    slip_at
}

/// The pull at the first step where every point slipped, against μ N
/// (docs/benchmarks.md §3; tolerance 1 %).
fn check_slip_onset(slip_at: Option<f64>, t_max: f64, ramp: &Amplitude) {
    assert!(slip_at.is_some(), "the block never slid: T reached 2 mu N");
    let t_slip = t_max * ramp.value(slip_at.unwrap_or_default());
    let mu_n = MU * N;
    let err = (t_slip - mu_n).abs() / mu_n;
    println!(
        "\nslip starts at T = {t_slip:.2} N; mu N = {mu_n:.2} N (rel. error {:.2} %, tolerance 1 %)",
        100.0 * err
    );
    assert!(err < 0.01, "T_slip = {t_slip} N vs mu N = {mu_n} N");
}

/// Stage 9: print the energy ledger and check that friction dissipated
/// energy and that the books close.
fn check_energy_ledger(solver: &Solver) {
    // Work of the loads = kinetic + springs (internal) + stored contact
    // (penalty and stick springs) + frictional dissipation, up to the
    // balance error (fem-core's energy module documents each term).
    let e = solver.ledger();
    println!(
        "energy (mJ) at t = {:.3} s: loads {:.3} = kinetic {:.3} + springs {:.3} + contact {:.3} + \
         friction {:.3}; balance error {:.1e}",
        e.time, e.external_loads, e.kinetic, e.internal, e.contact, e.friction, e.balance_error
    );
    // After sliding, friction has dissipated energy, and the books close to
    // 1 % (the tolerance of crates/contact/tests/block_on_plane.rs).
    assert!(e.friction > 0.0, "no frictional dissipation after sliding");
    assert!(
        e.balance_error < 0.01,
        "energy balance error {}",
        e.balance_error
    );
}

#[cfg_attr(test, allow(dead_code))]
fn main() {
    run();
}

#[test]
fn runs_as_documented() {
    run();
}
