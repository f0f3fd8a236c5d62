//! Profile of one explicit step of the NUMISHEET'93 quarter square cup on a
//! 50×50 BT blank (2,601 nodes; three pairs: punch, die, blankholder), set up
//! by hand, as the former cup smoke test did, with fixed-step mass scaling at 1e-6 s.
//! Runs 2 ms of simulated time (1 ms clamp, 1 ms draw) and prints the wall time
//! per step, the time spent in the contact effect per step and the number of
//! tool projections per step. As the machine may be shared, it also prints
//! the fastest 100-step window (wall and contact time per step).
//!
//! ```text
//! RAYON_NUM_THREADS=1 cargo run --release -p contact --example cup_step_profile
//! RAYON_NUM_THREADS=2 cargo run --release -p contact --example cup_step_profile -- --no-skip
//! ```
//!
//! Options: `--no-skip` projects every candidate node every step
//! (`PairSpec::skip_far = false`); `--n N` blank divisions (default 50);
//! `--t-end T` simulated time (s, default 2e-3).

use std::path::Path;
use std::time::{Duration, Instant};

use contact::{BlankGeometry, ContactEffect, ContactPair, PairSpec};
use fem_core::{
    Control, Effect, EnergyTally, FemError, FieldAccess, Forces, NodalField, NodalState, Press,
    PressStep, Solver, SolverSettings, StableDt, StepContext, StepEnd, ToolMotion, Vec3, rectangle,
};
use friction_laws::builtin;
use plugins_api::{Params, RigidPose, TangentMode, ToolSurface};
use shell_elements::{BelytschkoTsay, Hardening, J2PlaneStress, Section, ShellSet};

/// The contact effect with a stopwatch around `add_forces`.
struct Timed {
    inner: ContactEffect,
    spent: Duration,
}

impl Effect for Timed {
    fn name(&self) -> &str {
        self.inner.name()
    }
    fn add_lumped_mass(&self, state: &NodalState, mass: &mut [f64], inertia: &mut [f64]) {
        self.inner.add_lumped_mass(state, mass, inertia);
    }
    fn stable_dt(&self, state: &NodalState) -> Option<StableDt> {
        self.inner.stable_dt(state)
    }
    fn scale_mass(
        &mut self,
        state: &NodalState,
        target_dt: f64,
        mass: &mut [f64],
        inertia: &mut [f64],
    ) -> f64 {
        self.inner.scale_mass(state, target_dt, mass, inertia)
    }
    fn add_forces(
        &mut self,
        ctx: &StepContext,
        state: &NodalState,
        forces: &mut Forces,
        fields: &mut FieldAccess<'_>,
    ) -> Result<(), FemError> {
        let t = Instant::now();
        let r = self.inner.add_forces(ctx, state, forces, fields);
        self.spent += t.elapsed();
        r
    }
    fn energies(&self) -> EnergyTally {
        self.inner.energies()
    }
    fn reads(&self) -> &[NodalField] {
        self.inner.reads()
    }
}

fn main() {
    let mut skip = true;
    let mut n = 50usize;
    let mut t_end = 2e-3;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--no-skip" => skip = false,
            "--n" => n = args.next().and_then(|s| s.parse().ok()).expect("--n N"),
            "--t-end" => {
                t_end = args
                    .next()
                    .and_then(|s| s.parse().ok())
                    .expect("--t-end seconds")
            }
            other => panic!("unknown option `{other}` (--no-skip, --n N, --t-end T)"),
        }
    }

    let t0 = 0.78;
    let mut mesh = rectangle(75.0, 75.0, n, n).unwrap();
    for p in &mut mesh.nodes {
        p.z = 0.5 * t0;
    }
    let nodes = mesh.nodes.clone();
    let quads = mesh.quads.clone();
    let nn = nodes.len();
    let settings = SolverSettings {
        mass_scaling_dt: Some(1e-6),
        ..Default::default()
    };
    let mut solver = Solver::new(&mesh, settings).unwrap();
    let steel = J2PlaneStress::new(
        2.06e5,
        0.3,
        7.85e-9,
        Hardening::swift(565.32, 0.007117, 0.2589).unwrap(),
    )
    .unwrap();
    solver.add_effect(
        ShellSet::new(
            "blank",
            &nodes,
            &quads,
            Section::new(t0).unwrap(),
            BelytschkoTsay::default(),
            steel,
        )
        .unwrap(),
    );
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let tools = tools_nurbs::spec::load(&root.join("scenes/tools/square-cup-tools.toml")).unwrap();
    let names: Vec<String> = tools.iter().map(|t| t.name().to_string()).collect();
    let index = |name: &str| names.iter().position(|n| n == name).unwrap();
    let (punch, die, holder) = (index("punch"), index("die"), index("blankholder"));
    let poses: Vec<RigidPose> = tools.iter().map(|t| t.pose()).collect();
    let force_quarter = 4900.0;
    let holder_motion = ToolMotion::Force {
        direction: -Vec3::z(),
        force: fem_core::ForceLaw::Constant(force_quarter),
        amplitude: None,
        mass: 0.01,
        damping: 0.0,
        relative_damping: 0.0,
    };
    let steps = vec![
        PressStep {
            name: "clamp".into(),
            end: StepEnd::Duration(1e-3),
            motions: vec![(holder, holder_motion.clone())],
            active_pairs: None,
        },
        PressStep {
            name: "draw".into(),
            end: StepEnd::Duration(5e-3),
            motions: vec![
                (holder, holder_motion),
                (
                    punch,
                    ToolMotion::Travel {
                        direction: -Vec3::z(),
                        distance: 5.0,
                        amplitude: None,
                    },
                ),
            ],
            active_pairs: None,
        },
    ];
    let press = Press::new(&names, &poses, steps).unwrap();
    let geometry = BlankGeometry::new(nn, &quads).unwrap();
    let bulk = 2.06e5 / (3.0 * (1.0 - 0.6));
    let mut pairs = Vec::new();
    for (tool, name) in [
        (punch, "punch-blank"),
        (die, "die-blank"),
        (holder, "holder-blank"),
    ] {
        let integ = builtin::integrator(
            "ac",
            &Params::new().with("mu", 0.144),
            "convective",
            TangentMode::None,
        )
        .unwrap();
        let spec = PairSpec {
            skip_far: skip,
            ..PairSpec::new(name, tool, bulk)
        };
        pairs.push(ContactPair::new(&spec, integ, &geometry, &nodes).unwrap());
    }
    let boxed: Vec<Box<dyn ToolSurface>> = tools
        .into_iter()
        .map(|t| Box::new(t) as Box<dyn ToolSurface>)
        .collect();
    let contact = ContactEffect::new(boxed, Some(press), pairs, geometry, vec![t0; nn]).unwrap();
    let cid = solver.add_effect(Timed {
        inner: contact,
        spent: Duration::ZERO,
    });
    solver.symmetry("x0", 0).unwrap();
    solver.symmetry("y0", 1).unwrap();
    solver.initialize().unwrap();

    // Per window of WINDOW steps: wall time and time in contact. On a shared
    // machine the fastest window is the least disturbed one.
    const WINDOW: u64 = 100;
    let wall = Instant::now();
    let mut mark = (Instant::now(), Duration::ZERO);
    let mut best = (f64::INFINITY, f64::INFINITY);
    let summary = solver
        .run_until(t_end, &mut |s: &Solver, r| {
            if r.step % WINDOW == 0 {
                let spent = s.effect::<Timed>(cid).map_or(Duration::ZERO, |t| t.spent);
                let w = mark.0.elapsed().as_secs_f64() * 1e3 / WINDOW as f64;
                let c = (spent - mark.1).as_secs_f64() * 1e3 / WINDOW as f64;
                if w < best.0 {
                    best = (w, c);
                }
                mark = (Instant::now(), spent);
            }
            Control::Continue
        })
        .unwrap();
    let wall = wall.elapsed();
    let steps = summary.steps as f64;
    let timed: &Timed = solver.effect(cid).unwrap();
    let c = &timed.inner;
    // Contact does nothing at the initial force computation, so every
    // projection belongs to one of the `steps` steps.
    let per_pair: Vec<(f64, f64, f64)> = c
        .pairs()
        .iter()
        .map(|p| {
            (
                p.projections as f64 / steps,
                p.skipped as f64 / steps,
                p.flat_answers as f64 / steps,
            )
        })
        .collect();
    let total: f64 = per_pair.iter().map(|p| p.0).sum();
    let press = c.press().unwrap();
    let e = solver.ledger();
    let state = solver.state();
    println!(
        "cup {n}x{n} ({nn} nodes), skip_far {skip}, rayon threads {}",
        rayon::current_num_threads()
    );
    println!(
        "steps {}, simulated {:.3e} s, wall {:.3} s: {:.3} ms/step, contact {:.3} ms/step",
        summary.steps,
        solver.time(),
        wall.as_secs_f64(),
        wall.as_secs_f64() * 1e3 / steps,
        timed.spent.as_secs_f64() * 1e3 / steps,
    );
    println!(
        "fastest {WINDOW}-step window: {:.3} ms/step, contact {:.3} ms/step",
        best.0, best.1
    );
    println!(
        "projections/step: {total:.0} ({})",
        c.pairs()
            .iter()
            .zip(&per_pair)
            .map(|(p, (done, skipped, flat))| format!(
                "{} {done:.0}, from flat regions {flat:.0}, skipped {skipped:.0}",
                p.name()
            ))
            .collect::<Vec<_>>()
            .join("; ")
    );
    let touching: Vec<usize> = c
        .pairs()
        .iter()
        .map(|p| {
            p.status
                .iter()
                .filter(|s| **s != contact::PointStatus::Open)
                .count()
        })
        .collect();
    println!(
        "touching at the end: {touching:?}; stroke {:.4} mm; punch force {:.3} N, holder {:.3} N; \
         friction {:.6} mJ, tools' work {:.6} mJ, contact stored {:.6e} mJ; centre z {:.9} mm",
        -press.displacement(punch).z,
        c.reactions()[punch].z,
        c.reactions()[holder].z,
        e.friction,
        e.external_tools,
        c.energy().stored,
        state.x[0].z,
    );
    // Full-precision fingerprints, to compare runs (skip_far, threads) bit for bit.
    let sum_x: f64 = state.x.iter().map(|p| p.x + p.y + p.z).sum();
    println!(
        "fingerprint: sum of coordinates {sum_x:.17e} mm, friction {:.17e} mJ, tools' work {:.17e} mJ",
        e.friction, e.external_tools
    );
}
