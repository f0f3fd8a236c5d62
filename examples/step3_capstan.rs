//! # Step 3: the capstan, from a scene file
//!
//! **What it shows.** Step 2 assembled a model by hand. A forming run is
//! usually described by a *scene* instead: a TOML file naming the blank
//! mesh, its material and shells, the tools, the contact law, the loads and
//! the press programme (docs/scene-format.md). This example loads
//! `scenes/capstan.toml` through the library, the way `formsim run` does:
//!
//! - `formsim::scene::load(path, overrides)` reads the file, applies
//!   `--set`-style overrides (`KEY=VALUE` strings; none here, step 4 uses
//!   them) and validates it into a typed `Scene`, whose fields the example
//!   reads (the friction coefficient, and the `[output.capstan]` table,
//!   resolved against the keys the capstan check declares);
//! - `formsim::scene::build(&loaded)` turns it into a `Model`: a
//!   `fem_core::Solver` holding the shells, the contact effect with its tools
//!   and pairs, boundary conditions and loads, plus what the outputs need
//!   (mesh, tool names, end time);
//! - the example then steps `model.solver` itself with `run_until` and a
//!   callback, reading the reaction at the pulled end, instead of calling
//!   `formsim::run::run`, which would also write result files;
//! - at the end it reads the shells' stress resultants through the model's
//!   shell handle (`model.shells.get`, as their concrete type) to show the
//!   tension along the wrap.
//!
//! **The physics.** A thin elastic strip (0.1 mm thick, 4 mm wide,
//! Belytschko–Tsay shells) is wrapped through `θ = 90°` over a fixed rigid
//! drum of radius 20 mm. One end hangs from a constant force
//! `T_in = 200 N`; the other is drawn at 1 m/s. In steady sliding the belt
//! friction (capstan) equation of Euler and Eytelwein gives
//!
//! ```text
//! T_out / T_in = exp(μ θ)
//! ```
//!
//! independent of the drum radius; the strip's bending stiffness adds a small
//! excess that shrinks with `t/R`. With `μ = 0.144`, `exp(μ π/2) = 1.2538`.
//! Reference and tolerance: docs/benchmarks.md §3 ("Capstan"), 2 %, as in
//! `crates/contact/tests/capstan.rs`. Locally the same law reads
//! `T(φ) = T_in exp(μ φ)` at the angle `φ` from where the strip leaves the
//! drum on the held side; the example prints the strip's membrane force
//! along the wrap beside it. That table is an illustration, not a check:
//! it is one instant of a dynamic run, and stress waves in the strip move
//! it by a percent or two.
//!
//! The run takes about 78,000 explicit steps (0.1 mm shells of 1 mm: a
//! time step of 0.15 µs), a few seconds in release. To try another
//! formulation from the command line:
//! `cargo run --release -p formsim -- run scenes/capstan.toml --set contact.formulation=jaumann --out DIR`.
//!
//! **Run:** `cargo run --release -p formsim-examples --example step3_capstan`
//!
//! **Output.** What the scene built; the pulled-end force averaged over
//! steady sliding and the ratio against `exp(μ θ)`; the energy ledger; the
//! tension along the wrap, e.g.
//!
//! ```text
//! scene `capstan`: 144 shells, 219 nodes, tools [drum], law ac x convective, end time 0.012 s
//! T_in = 200 N on set `hold`; set `pull` drawn along ux; mu = 0.144, theta = 90°; averaging from 0.008 s
//!
//! T_out = 249.11 N (mean over 26056 of 78157 steps, 3.9 s), T_out/T_in = 1.2456,
//! exp(mu theta) = 1.2538 (rel. error 0.66 %, tolerance 2 %)
//! energy (mJ): external work 465.3 = kinetic 0.2 + internal 25.3 + contact -4.3 + friction 443.0; ...
//!
//! tension along the wrap (last step; phi from where the strip leaves on the held side):
//!   phi (deg)   T (N)   T_in exp(mu phi) (N)
//!        80.3   246.1        244.7
//! ...
//!         0.9   199.1        200.5
//! ```

use fem_core::{Control, Solver, Vec3};
use formsim::scene::schema::MeshSpec;
use formsim::scene::{self, LoadedScene, Model, Scene};
use shell_elements::{BelytschkoTsay, J2PlaneStress, ShellSet};
use std::path::Path;
use std::time::Instant;

/// The scene, found from this package's directory so that the example runs
/// from any working directory.
const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/capstan.toml");

/// The whole example: load and build the scene, run it, check the capstan
/// ratio and the energy books, print the tension along the wrap.
fn run() {
    println!("Step 3: capstan (belt friction) from scenes/capstan.toml\n");
    let loaded: LoadedScene =
        scene::load(Path::new(SCENE), &[]).expect("scenes/capstan.toml is a valid scene");
    let s = &loaded.scene;
    let (capstan, mu, theta) = capstan_reference(s);

    // The model: solver, shells, contact (drum, pair, law), loads and
    // boundary conditions, all from the scene.
    let mut model = scene::build(&loaded).expect("the scene builds");
    print_model(s, &model, &capstan, mu);

    let pull = run_averaging_pull(&mut model, &capstan);
    check_capstan_ratio(&pull, &capstan, mu, theta);
    check_energy_ledger(&model);
    print_tension_along_wrap(s, &model, &capstan, mu);
}

/// The keys of `[output.capstan]` the example reads.
struct Capstan<'a> {
    /// The node set pulled: its reaction is `T_out`.
    pull_set: &'a str,
    /// The DOF it is pulled along.
    pull_dof: &'a str,
    /// `T_in` (N).
    hold_force: f64,
    /// `θ` (degrees).
    angle_deg: f64,
    /// Start of the mean (s).
    average_from: f64,
}

/// What the scene says about its own analytic reference (its
/// `[output.capstan]` table, with the defaults filled in) and the Coulomb
/// coefficient of its law: the table, `μ` and the wrap angle `θ` (rad).
fn capstan_reference(s: &Scene) -> (Capstan<'_>, f64, f64) {
    let table = s
        .output
        .checks
        .get("capstan")
        .expect("scenes/capstan.toml has an [output.capstan] table");
    let number = |key| table.number(key).expect("a key the capstan check declares");
    let name = |key| table.name(key).expect("a key the capstan check declares");
    let capstan = Capstan {
        pull_set: name("pull_set"),
        pull_dof: name("pull_dof"),
        hold_force: number("hold_force"),
        angle_deg: number("angle_deg"),
        average_from: number("average_from"),
    };
    assert_eq!(
        s.contact.law, "ac",
        "the reference below needs tau_c = mu p"
    );
    let mu = s.contact.params["ac"]["mu"];
    let theta = capstan.angle_deg.to_radians();
    (capstan, mu, theta)
}

/// Print what the scene built and what the run will measure.
fn print_model(s: &Scene, model: &Model, capstan: &Capstan<'_>, mu: f64) {
    println!(
        "scene `{}`: {} shells, {} nodes, tools [{}], law {} x {}, end time {} s",
        s.scene.name,
        model.mesh.quads.len(),
        model.mesh.nodes.len(),
        model.tool_names.join(", "),
        model.law,
        model.formulation,
        model.end_time
    );
    println!(
        "T_in = {} N on set `hold`; set `{}` drawn along {}; mu = {mu}, theta = {}°; averaging \
         from {} s\n",
        capstan.hold_force,
        capstan.pull_set,
        capstan.pull_dof,
        capstan.angle_deg,
        capstan.average_from
    );
}

/// The pulled end's force averaged over steady sliding.
struct PullForce {
    /// Mean force (N): `T_out`.
    mean: f64,
    /// Steps averaged.
    samples: u32,
    /// Steps run.
    steps: u64,
    /// Wall time of the run (s).
    seconds: f64,
}

/// Step the solver to the end, averaging the reaction of the pulled end
/// (the force its prescribed motion needs, i.e. T_out) once sliding is steady.
fn run_averaging_pull(model: &mut Model, capstan: &Capstan<'_>) -> PullForce {
    let axis = match capstan.pull_dof {
        "uy" => 1,
        "uz" => 2,
        _ => 0,
    };
    let (mut sum, mut samples) = (0.0, 0u32);
    let started = Instant::now();
    let end = model.end_time;
    let summary = model
        .solver
        .run_until(end, &mut |solver: &Solver, report| {
            if report.time >= capstan.average_from {
                let (force, _moment) = solver
                    .reaction(capstan.pull_set)
                    .expect("the pull set exists: the scene validated it");
                sum += force[axis].abs();
                samples += 1;
            }
            Control::Continue
        })
        .expect("the capstan runs to its end time");
    assert!(samples > 0, "no step after average_from");
    PullForce {
        mean: sum / f64::from(samples),
        samples,
        steps: summary.steps,
        seconds: started.elapsed().as_secs_f64(),
    }
}

/// `T_out/T_in` against Euler–Eytelwein's `exp(μ θ)` (docs/benchmarks.md §3),
/// tolerance 2 %.
fn check_capstan_ratio(pull: &PullForce, capstan: &Capstan<'_>, mu: f64, theta: f64) {
    let t_out = pull.mean;
    let measured = t_out / capstan.hold_force;
    let analytic = (mu * theta).exp();
    let err = (measured - analytic).abs() / analytic;
    println!(
        "T_out = {t_out:.2} N (mean over {} of {} steps, {:.1} s), T_out/T_in = \
         {measured:.4}, exp(mu theta) = {analytic:.4} (rel. error {:.2} %, tolerance 2 %)",
        pull.samples,
        pull.steps,
        pull.seconds,
        100.0 * err
    );
    assert!(
        err < 0.02,
        "T_out/T_in = {measured} vs exp(mu theta) = {analytic}"
    );
}

/// The ledger: nearly all the work of the pull and the hanging load is
/// dissipated by friction.
fn check_energy_ledger(model: &Model) {
    let e = model.solver.ledger();
    println!(
        "energy (mJ): external work {:.1} = kinetic {:.1} + internal {:.1} + contact {:.1} + \
         friction {:.1}; balance error {:.1e}",
        e.external, e.kinetic, e.internal, e.contact, e.friction, e.balance_error
    );
    assert!(e.friction > 0.0 && e.balance_error < 0.01, "{e:?}");
}

/// The tension along the wrap, from the shells' membrane resultants N_xx
/// (N/mm, element frame: x along the strip) times the element width,
/// summed over the two elements across the strip, beside `T_in exp(μ φ)`.
fn print_tension_along_wrap(s: &Scene, model: &Model, capstan: &Capstan<'_>, mu: f64) {
    // The scene chose Belytschko–Tsay shells and an elastic material (J2
    // that never yields): the handle's `get` returns the shells as that
    // `ShellSet` type (`None` for any other element or material).
    let MeshSpec::WrappedStrip { width, .. } = s.blank.mesh else {
        panic!("scenes/capstan.toml meshes a wrapped strip");
    };
    let shells: &ShellSet<BelytschkoTsay, J2PlaneStress> = model
        .shells
        .get(&model.solver)
        .expect("scenes/capstan.toml asks for belytschko-tsay shells and the j2 material");
    let x = &model.solver.state().x;
    let element_width = 0.5 * width; // the generator puts two elements across
    println!(
        "\ntension along the wrap (last step; phi from where the strip leaves on the held side):"
    );
    println!("  phi (deg)   T (N)   T_in exp(mu phi) (N)");
    for row in (0..shells.len() / 2).step_by(4) {
        let pair = [2 * row, 2 * row + 1];
        let centre = pair
            .iter()
            .flat_map(|&e| shells.quads()[e])
            .map(|n| x[n as usize])
            .sum::<Vec3>()
            / 8.0;
        // The drum's axis is y through the origin; the strip leaves it at
        // 180° (on -x), measured from +x towards +z.
        let angle = centre.z.atan2(centre.x).to_degrees();
        if !(90.0..=180.0).contains(&angle) {
            continue; // a tail, not on the drum
        }
        let phi = 180.0 - angle;
        let tension: f64 =
            pair.iter().map(|&e| shells.resultants(e).0[0]).sum::<f64>() * element_width;
        println!(
            "  {phi:9.1} {tension:7.1} {:12.1}",
            capstan.hold_force * (mu * phi.to_radians()).exp()
        );
    }
}

#[cfg_attr(test, allow(dead_code))]
fn main() {
    run();
}

#[test]
fn runs_as_documented() {
    run();
}
