//! # Step 4: the NUMISHEET'93 square cup, assembled in code
//!
//! **What it shows.** Everything a forming run is made of, built directly
//! from the engine crates instead of from a scene file: the blank mesh, the
//! shells with their section and material, the rigid NURBS tools, the
//! double-action press programme, the contact pairs with their friction law,
//! the symmetry planes. It is what `formsim::scene::build`
//! (`crates/formsim/src/scene/build.rs`) does for `scenes/square-cup.toml`,
//! written out by hand, so that you can see which API each scene key ends up
//! in and start from here when a model needs something a scene cannot say.
//!
//! **The model** (docs/benchmarks.md §1; Colville's thesis §4.2; NUMISHEET'93):
//! a quarter of a 150 × 150 × 0.78 mm mild-steel blank (Swift hardening
//! `σ_y = 565.32 (0.007117 + ε_p)^0.2589` MPa, E = 206 GPa, ν = 0.3) on a die
//! with a 74 × 74 mm opening, held by a blankholder at 19.6 kN (4.9 kN on the
//! quarter) and drawn by a 70 × 70 mm punch; Amontons–Coulomb friction
//! `μ = 0.144`, convective formulation, on all three tools. To run in under a
//! second it is coarse (10 × 10 shells of 7.5 mm instead of 50 × 50) and the
//! draw is short (10 mm of punch travel in 3.5 ms instead of 40 mm in 14 ms,
//! the same mean speed).
//!
//! **The check.** The same cup is then built from `scenes/square-cup.toml`
//! with the matching overrides (the `--set` strings of the command line:
//! `blank.mesh.divisions=10`, `steps[2].duration=0.0035`,
//! `steps[2].motions[1].distance=10`), and both models are stepped to the end
//! of the press programme. They must agree **to the last bit**: every node's
//! position and velocity, the punch force and every energy. This is possible
//! because the engine is deterministic (no dependence on thread count,
//! docs/architecture.md §3) and both paths make the very same calls with the
//! very same numbers, in the same order. Order matters: the scene builder
//! adds the tools in its table's key order (alphabetical: blankholder, die,
//! punch), contact pairs follow the tools, and the pairs' forces are summed
//! in pair order. Floating-point addition is not associative, so listing the
//! tools as punch, die, blankholder changes the last bits of the first
//! contact forces, and in a dynamic run such differences grow: after the
//! draw the nodes then differ by a few micrometres (3.5 µm when tried). That
//! is round-off, not physics, but it is not the same bits; the example
//! asserts the scene builder's tool order too.
//!
//! As a physical check it also requires the energy books to close (balance
//! error below 1 %, the ledger of `crates/fem-core/src/energy.rs`) and the
//! force-controlled blankholder to deliver its prescribed 4.9 kN during the
//! draw (mean reaction within 2 %).
//!
//! **Run:** `cargo run --release -p formsim-examples --example step4_square_cup_in_code`
//!
//! **Output.** The model's size and time step, a history of the draw
//! (stroke, punch force, holder force, energies), the final
//! energy ledger, then the comparison with the scene-built model, e.g.
//!
//! ```text
//!  stroke (mm)  punch (kN)  holder (kN)  internal (J)  friction (J)  kinetic/internal
//! ...
//!         9.91       28.27         4.65       23.6777        4.3152             0.000
//!
//! after 9201 steps (0.4 s): stroke 10.01 mm, punch force 28.91 kN (max 29.26 kN), full cup
//! energy (J, quarter): external 29.3307 = internal 24.2805 (plastic 23.6677) + ... ; balance error 1.3e-6
//! holder: mean force during the draw 4895.0 N, prescribed 4900 N (rel. error 0.10 %, tolerance 2 %)
//! ...
//! scene-built model after 9201 steps (0.3 s): same steps true, positions true, velocities true,
//! forces true, energies true (identical to the bit); largest position difference 0.0e0 mm
//! ```
//!
//! The punch force is that of the full cup (four quarters); the holder
//! force and the energies are those of the quarter model.

use contact::{BlankGeometry, ContactEffect, ContactPair, PairSpec, PenaltySettings};
use fem_core::{
    Amplitude, Control, EnergyLedger, ForceLaw, Mesh, Press, PressStep, Solver, SolverSettings,
    StepEnd, ToolMotion, Vec3,
};
use formsim::scene::{self, Model};
use friction_laws::builtin;
use plugins_api::{Params, TangentMode, ToolSurface};
use shell_elements::{BelytschkoTsay, Hardening, J2PlaneStress, RuleKind, Section, ShellSet};
use std::path::Path;
use std::time::Instant;
use tools_nurbs::builders::square_cup::{self, DieParams, HolderParams, PunchParams};
use tools_nurbs::builders::{Facing, Model as Symmetry, Placement};

/// The scene the check builds, found from this package's directory.
const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/square-cup.toml");

/// Shells along each side of the quarter blank (the scene's 50, coarsened).
const DIVISIONS: usize = 10;
/// Punch travel of the draw step (mm) and its duration (s): the scene's
/// 39.99 mm in 14 ms, shortened at the same mean speed.
const DRAW: f64 = 10.0;
/// See [`DRAW`].
const DRAW_TIME: f64 = 3.5e-3;
/// Blank thickness (mm).
const T0: f64 = 0.78;
/// Quarter of the 19.6 kN blankholder force (N).
const HOLDER_FORCE: f64 = 4900.0;
/// Full cup / quarter model.
const SYMMETRY: f64 = 4.0;

/// Tool indices: the scene's order (its `[tools]` table's keys, sorted).
const HOLDER: usize = 0;
/// See [`HOLDER`].
const DIE: usize = 1;
/// See [`HOLDER`].
const PUNCH: usize = 2;
/// Tool names, in index order.
const TOOLS: [&str; 3] = ["blankholder", "die", "punch"];

/// The cup built by hand: the solver and where to find its parts.
struct Cup {
    solver: Solver,
    contact: fem_core::EffectId,
    end_time: f64,
}

/// Build the cup from the engine crates, as `formsim::scene::build` would
/// from `scenes/square-cup.toml` with the overrides of [`scene_overrides`].
fn build_in_code() -> Cup {
    // --- Mesh -------------------------------------------------------------------
    let mesh = blank_mesh();

    // --- Solver -----------------------------------------------------------------
    let mut solver = mass_scaled_solver(&mesh);

    // --- Shells: section, material, element -------------------------------------
    solver.add_effect(blank_shells(&mesh));

    // --- Tools --------------------------------------------------------------------
    let tools = cup_tools();

    // --- Press programme ------------------------------------------------------------
    let press = press_programme(&tools);
    let end_time = press.nominal_duration();

    // --- Contact ----------------------------------------------------------------------
    // The press is a stage of the solver's step: it moves the tools before
    // the effects' forces, and contact reads where it put them.
    solver.set_press(press).expect("before set-up");
    let contact = solver.add_effect(contact_effect(&mesh, tools));

    // --- Boundary conditions ----------------------------------------------------------
    // Symmetry planes x = 0 and y = 0: normal translation and in-plane
    // rotations fixed.
    solver.symmetry("x0", 0).expect("set x0 exists");
    solver.symmetry("y0", 1).expect("set y0 exists");

    Cup {
        solver,
        contact,
        end_time,
    }
}

/// The blank's mesh: a structured 10 × 10 quad mesh of the quarter blank
/// [0, 75]², lifted so that its mid-surface lies t0/2 above the die face
/// z = 0. `rectangle` also names the edge node sets x0, x1, y0, y1 and `all`.
fn blank_mesh() -> Mesh {
    let mut mesh = fem_core::rectangle(75.0, 75.0, DIVISIONS, DIVISIONS)
        .expect("positive sizes and divisions");
    for p in &mut mesh.nodes {
        *p += Vec3::new(0.0, 0.0, 0.5 * T0);
    }
    mesh
}

/// The solver over the mesh, with fixed-step mass scaling at 0.5 µs:
/// elements (and contact springs) whose stable step is shorter get mass
/// added until it is not ([solver] of the scene).
fn mass_scaled_solver(mesh: &Mesh) -> Solver {
    let settings = SolverSettings {
        safety_factor: 0.9,
        mass_scaling_dt: Some(5e-7),
        ..SolverSettings::default()
    };
    Solver::new(mesh, settings).expect("a valid mesh and settings")
}

/// The blank's shells: section, material and element over every quad.
fn blank_shells(mesh: &Mesh) -> ShellSet<BelytschkoTsay, J2PlaneStress> {
    // 5 Gauss points through the thickness, hourglass coefficient 0.05.
    let section = Section::new(T0)
        .and_then(|s| s.with_rule(RuleKind::Gauss, 5))
        .and_then(|s| s.with_hourglass(0.05))
        .expect("valid section");
    // Mild steel: isotropic J2 plasticity, Swift hardening (docs/benchmarks.md §1).
    let hardening = Hardening::swift(565.32, 0.007117, 0.2589).expect("valid Swift curve");
    let material =
        J2PlaneStress::new(206_000.0, 0.30, 7.85e-9, hardening).expect("valid elastic constants");
    // Belytschko–Tsay with its defaults (warping correction on, drilling
    // coefficient 1e-3): what a scene gets when it names no other value.
    ShellSet::new(
        "blank",
        &mesh.nodes,
        &mesh.quads,
        section,
        BelytschkoTsay::default(),
        material,
    )
    .expect("valid shells")
}

/// The three tools, exact NURBS quarter models, in index order (`HOLDER`,
/// `DIE`, `PUNCH`: see the header on why order matters).
fn cup_tools() -> Vec<Box<dyn ToolSurface>> {
    // Each builder bakes its placement into the geometry (the pose starts at
    // the identity; the press moves it from there). Punch and holder start
    // on the blank's top face (z = t0) and face down; the die face is z = 0,
    // facing up.
    let on_top = Placement {
        origin: Vec3::new(0.0, 0.0, T0),
        facing: Facing::Down,
    };
    let on_floor = Placement {
        origin: Vec3::zeros(),
        facing: Facing::Up,
    };
    let holder = square_cup::blankholder(
        TOOLS[HOLDER],
        &HolderParams {
            inner_length: 84.0,
            inner_width: 84.0,
            corner_radius: 12.0,
            outer_length: 170.0,
            outer_width: 170.0,
        },
        Symmetry::Quarter,
        &on_top,
    )
    .expect("valid holder");
    let die = square_cup::die(
        TOOLS[DIE],
        &DieParams {
            opening_length: 74.0,
            opening_width: 74.0,
            corner_radius: 12.0,
            shoulder_radius: 5.0,
            depth: 50.0,
            outer_length: 170.0,
            outer_width: 170.0,
        },
        Symmetry::Quarter,
        &on_floor,
    )
    .expect("valid die");
    let punch = square_cup::punch(
        TOOLS[PUNCH],
        &PunchParams {
            length: 70.0,
            width: 70.0,
            corner_radius: 10.0,
            profile_radius: 8.0,
            height: 50.0,
        },
        Symmetry::Quarter,
        &on_top,
    )
    .expect("valid punch");
    vec![Box::new(holder), Box::new(die), Box::new(punch)]
}

/// The double-action press programme that moves `tools` (from their poses).
fn press_programme(tools: &[Box<dyn ToolSurface>]) -> Press {
    // (1) the punch moves 0.01 mm to touch the blank; (2) the holder force
    // rises to 4.9 kN (force control: the holder's travel is integrated from
    // the force and the contact reaction, with a 10 kg mass on its free
    // degree of freedom); (3) the draw, the holder force held, the punch
    // travelling with the slow-start profile (speed ∝ ξ⁴(1 - ξ)², gentle
    // while the blank is still elastic).
    let down = Vec3::new(0.0, 0.0, -1.0);
    let holder_force = |amplitude| ToolMotion::Force {
        direction: down,
        force: ForceLaw::Constant(HOLDER_FORCE),
        amplitude,
        mass: 0.01,
        damping: 0.0,
        relative_damping: 0.0,
    };
    let steps = vec![
        PressStep {
            name: "punch contact".into(),
            end: StepEnd::Duration(1e-4),
            motions: vec![(
                PUNCH,
                ToolMotion::Travel {
                    direction: down,
                    distance: 0.01,
                    amplitude: None, // a C² smooth step over the step
                },
            )],
            active_pairs: None, // every pair, in every step
        },
        PressStep {
            name: "clamp".into(),
            end: StepEnd::Duration(1e-3),
            motions: vec![(
                HOLDER,
                holder_force(Some(Amplitude::SmoothStep { t0: 0.0, t1: 1e-3 })),
            )],
            active_pairs: None,
        },
        PressStep {
            name: "draw".into(),
            end: StepEnd::Duration(DRAW_TIME),
            motions: vec![
                (HOLDER, holder_force(None)),
                (
                    PUNCH,
                    ToolMotion::Travel {
                        direction: down,
                        distance: DRAW,
                        amplitude: Some(Amplitude::SlowStart {
                            t0: 0.0,
                            t1: DRAW_TIME,
                        }),
                    },
                ),
            ],
            active_pairs: None,
        },
    ];
    let names = TOOLS.map(String::from);
    let poses: Vec<_> = tools.iter().map(|t| t.pose()).collect();
    Press::new(&names, &poses, steps).expect("a valid programme")
}

/// The contact effect: one pair per tool against every blank node, the
/// tools (the solver's press moves them) and the blank's nodal geometry.
fn contact_effect(mesh: &Mesh, tools: Vec<Box<dyn ToolSurface>>) -> ContactEffect {
    // Each pair has its own integrator (law × formulation; the pairs keep
    // per-point state). The penalty stiffness follows the blank's bulk
    // modulus and the scene's penalty scale 0.1; nodes farther than 1 mm
    // from a tool's box are not projected.
    let geometry = BlankGeometry::new(mesh.nodes.len(), &mesh.quads).expect("a valid mesh");
    let bulk = 206_000.0 / (3.0 * (1.0 - 2.0 * 0.30));
    let pairs = TOOLS
        .iter()
        .enumerate()
        .map(|(index, name)| {
            let friction = builtin::integrator(
                "ac",
                &Params::new().with("mu", 0.144),
                "convective",
                TangentMode::None,
            )
            .expect("ac and convective are built in");
            let mut spec = PairSpec::new(&format!("{name}-blank"), index, bulk);
            spec.penalty = PenaltySettings {
                scale: 0.1,
                damping: 0.0,
            };
            spec.search_margin = 1.0;
            ContactPair::new(&spec, friction, &geometry, &mesh.nodes).expect("valid pair")
        })
        .collect();
    // The effect starts from the initial thickness and then reads the
    // shells' nodal thickness every step (a shared field).
    ContactEffect::new(tools, pairs, geometry, vec![T0; mesh.nodes.len()]).expect("valid contact")
}

/// The `--set` overrides that make `scenes/square-cup.toml` this cup.
fn scene_overrides() -> Vec<String> {
    vec![
        format!("blank.mesh.divisions={DIVISIONS}"),
        format!("steps[2].duration={DRAW_TIME}"),
        format!("steps[2].motions[1].distance={DRAW}"),
    ]
}

/// Punch stroke (mm), punch force on the full cup (N) and the force the
/// blank exerts on the holder along its axis (N, quarter).
fn forces(solver: &Solver, contact: fem_core::EffectId) -> (f64, f64, f64) {
    let c: &ContactEffect = solver
        .effect(contact)
        .expect("the id was returned for a ContactEffect");
    let press = solver.press().expect("the cup has a press");
    let down = Vec3::new(0.0, 0.0, -1.0);
    let stroke = press.displacement(PUNCH).dot(&down);
    let punch = -c.reactions()[PUNCH].dot(&down) * SYMMETRY;
    let holder = -c.reactions()[HOLDER].dot(&down);
    (stroke, punch, holder)
}

/// Every energy of the ledger, as bits.
fn ledger_bits(e: &EnergyLedger) -> [u64; 8] {
    [
        e.kinetic,
        e.internal,
        e.plastic,
        e.hourglass,
        e.contact,
        e.friction,
        e.external,
        e.balance_abs,
    ]
    .map(f64::to_bits)
}

/// The whole example: build and run the cup in code, check it, then check
/// it against the same cup built from the scene file.
fn run() {
    let started = Instant::now();
    let mut cup = build_in_code();
    initialize_and_print_setup(&mut cup);

    // --- Run: history of the draw, mean holder force --------------------------------
    let draw = run_draw(&mut cup);
    let in_code_time = started.elapsed().as_secs_f64();
    check_end_of_draw(&cup, draw.punch_max, in_code_time);
    check_holder_force(&draw);

    // --- The check: the same cup from the scene file ---------------------------------
    check_against_scene(&cup);
}

/// Set-up (masses, effects, first stable step); print the model's size and
/// time step.
fn initialize_and_print_setup(cup: &mut Cup) {
    let setup = cup.solver.initialize().expect("a valid model");
    println!(
        "Step 4: NUMISHEET'93 square cup in code, quarter model, {DIVISIONS} x {DIVISIONS} shells, \
         {DRAW} mm draw"
    );
    println!(
        "{} nodes, time step {:.2e} s (mass scaling added {:.1} % mass), {:.1e} s of press programme\n",
        cup.solver.state().len(),
        setup.dt_initial,
        setup.added_mass_percent,
        cup.end_time
    );
}

/// What the run records along the draw.
struct DrawHistory {
    /// Sum of the holder force over the draw's steps (N).
    holder_sum: f64,
    /// Steps summed in `holder_sum`.
    holder_n: u32,
    /// Largest punch force (N, full cup).
    punch_max: f64,
}

/// Run the press programme to its end, printing a history of the draw every
/// 0.25 ms; record the punch's largest force and the holder force during
/// the draw.
fn run_draw(cup: &mut Cup) -> DrawHistory {
    println!(" stroke (mm)  punch (kN)  holder (kN)  internal (J)  friction (J)  kinetic/internal");
    let draw_starts = 1.1e-3; // after "punch contact" and "clamp"
    let (mut holder_sum, mut holder_n) = (0.0, 0u32);
    let mut punch_max: f64 = 0.0;
    let mut next_print = draw_starts;
    let contact = cup.contact;
    cup.solver
        .run_until(cup.end_time, &mut |s: &Solver, report| {
            let (stroke, punch, holder) = forces(s, contact);
            punch_max = punch_max.max(punch);
            if report.time > draw_starts {
                holder_sum += holder;
                holder_n += 1;
            }
            if report.time >= next_print {
                next_print += 0.25e-3;
                let e = &report.energy;
                println!(
                    "{stroke:12.2} {:11.2} {:12.2} {:13.4} {:13.4} {:17.3}",
                    punch / 1e3,
                    holder / 1e3,
                    e.internal / 1e3,
                    e.friction / 1e3,
                    e.kinetic / e.internal.max(1e-30)
                );
            }
            Control::Continue
        })
        .expect("the cup runs to the end of its programme");
    DrawHistory {
        holder_sum,
        holder_n,
        punch_max,
    }
}

/// Print the stroke, the punch force and the energy ledger after the draw
/// (`in_code_time` s of wall time); check that the books close and that the
/// blank was drawn.
fn check_end_of_draw(cup: &Cup, punch_max: f64, in_code_time: f64) {
    let (stroke, punch, _) = forces(&cup.solver, cup.contact);
    let e = *cup.solver.ledger();
    println!(
        "\nafter {} steps ({in_code_time:.1} s): stroke {stroke:.2} mm, punch force {:.2} kN (max \
         {:.2} kN), full cup",
        cup.solver.steps(),
        punch / 1e3,
        punch_max / 1e3
    );
    println!(
        "energy (J, quarter): external {:.4} = internal {:.4} (plastic {:.4}) + hourglass {:.4} + \
         kinetic {:.4} + contact {:.4} + friction {:.4}; balance error {:.1e}",
        e.external / 1e3,
        e.internal / 1e3,
        e.plastic / 1e3,
        e.hourglass / 1e3,
        e.kinetic / 1e3,
        e.contact / 1e3,
        e.friction / 1e3,
        e.balance_error
    );
    // The books close (fem-core's ledger; 1 %).
    assert!(
        e.balance_error < 0.01,
        "energy balance error {}",
        e.balance_error
    );
    assert!(e.plastic > 0.0 && e.friction > 0.0 && stroke > 0.99 * DRAW);
}

/// Force control: the holder delivers its 4.9 kN through the draw (mean of
/// the contact reaction; 2 %).
fn check_holder_force(draw: &DrawHistory) {
    let holder_mean = draw.holder_sum / f64::from(draw.holder_n.max(1));
    let err = (holder_mean - HOLDER_FORCE).abs() / HOLDER_FORCE;
    println!(
        "holder: mean force during the draw {holder_mean:.1} N, prescribed {HOLDER_FORCE} N \
         (rel. error {:.2} %, tolerance 2 %)",
        100.0 * err
    );
    assert!(err < 0.02, "holder delivered {holder_mean} N");
}

/// Build the same cup from `scenes/square-cup.toml` with the overrides of
/// [`scene_overrides`], run it to the end and compare it with `cup`.
fn check_against_scene(cup: &Cup) {
    let overrides = scene_overrides();
    println!(
        "\nthe same cup from scenes/square-cup.toml --set {}",
        overrides.join(" --set ")
    );
    let loaded =
        scene::load(Path::new(SCENE), &overrides).expect("the scene and overrides are valid");
    let mut model = scene::build(&loaded).expect("the scene builds");
    assert_eq!(model.tool_names, TOOLS, "tool order of the scene builder");
    assert_eq!(
        model.end_time.to_bits(),
        cup.end_time.to_bits(),
        "same press programme"
    );
    let started = Instant::now();
    model
        .solver
        .run_until(model.end_time, &mut |_: &Solver, _| Control::Continue)
        .expect("the scene's cup runs to its end");
    compare_to_the_bit(cup, &model, started);
}

/// The cup built in code against the one built from the scene (run since
/// `started`): time steps, nodal positions and velocities, punch and holder
/// forces and every energy must be identical to the bit.
fn compare_to_the_bit(cup: &Cup, model: &Model, started: Instant) {
    let contact = model.contact.expect("the scene has tools");
    let a = &cup.solver;
    let b = &model.solver;
    let same_steps = a.steps() == b.steps() && a.time().to_bits() == b.time().to_bits();
    let bits = |v: &[Vec3]| -> Vec<u64> {
        v.iter()
            .flat_map(|p| p.iter().map(|c| c.to_bits()))
            .collect()
    };
    let same_x = bits(&a.state().x) == bits(&b.state().x);
    let same_v = bits(&a.state().v) == bits(&b.state().v);
    let (_, punch_a, holder_a) = forces(a, cup.contact);
    let (_, punch_b, holder_b) = forces(b, contact);
    let same_forces =
        punch_a.to_bits() == punch_b.to_bits() && holder_a.to_bits() == holder_b.to_bits();
    let same_energy = ledger_bits(a.ledger()) == ledger_bits(b.ledger());
    let max_dx = a
        .state()
        .x
        .iter()
        .zip(&b.state().x)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max);
    println!(
        "scene-built model after {} steps ({:.1} s): same steps {same_steps}, positions {same_x}, \
         velocities {same_v}, forces {same_forces}, energies {same_energy} (identical to the bit); \
         largest position difference {max_dx:.1e} mm",
        b.steps(),
        started.elapsed().as_secs_f64()
    );
    assert!(
        same_steps,
        "different time stepping: {} vs {} steps",
        a.steps(),
        b.steps()
    );
    assert!(
        same_x && same_v,
        "nodal state differs (max |dx| = {max_dx:e} mm)"
    );
    assert!(
        same_forces,
        "punch {punch_a} vs {punch_b} N, holder {holder_a} vs {holder_b} N"
    );
    assert!(
        same_energy,
        "energies differ: {:?} vs {:?}",
        a.ledger(),
        b.ledger()
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
