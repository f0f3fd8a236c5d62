//! Time of one `ContactPair::step` of a 50×50 quarter blank (2,601 nodes) on
//! the exact NURBS square-cup die: the flange presses 0.01 mm into the die
//! face, the part over the opening hangs clear, and every node jiggles a
//! little each step (so that warm starts do real work).
//!
//! Two reports, each in a rayon pool of 1 and of 2 threads:
//!
//! - **whole step**: geometry update plus pair step, with `skip_far` on and
//!   off, the fastest of several batches of steps (the machine may be shared);
//! - **stages**: with `skip_far` on (the default), the time of each stage of
//!   the pair step (`stages::{broad_phase, narrow_phase, normal, friction,
//!   scatter}`, read from the pair's own `timing` around every step) and of
//!   the whole pair step, fastest and median over all steps, with the size of
//!   the per-point friction input the normal stage gathers.
//!
//! ```text
//! cargo bench -p contact --bench pair_step
//! ```

use std::time::Instant;

use contact::{BlankGeometry, BlankView, ContactPair, ContactTiming, PairSpec};
use friction_laws::builtin;
use plugins_api::{Params, StepInput, TangentMode, ToolSurface, Vec3};
use tools_nurbs::builders::square_cup::benchmark_quarter_die;

const N: usize = 50;
const T0: f64 = 0.78;
const DT: f64 = 1e-6;
const BATCH: usize = 200;
const BATCHES: usize = 10;

/// The blank's positions at step `k`: flat, 0.01 mm into the die, jiggled.
fn blank_at(base: &[Vec3], k: usize) -> Vec<Vec3> {
    let s = k as f64;
    base.iter()
        .enumerate()
        .map(|(i, p)| {
            let j = 1e-4 * (0.37 * s + 0.11 * i as f64).sin();
            Vec3::new(p.x + j, p.y - j, 0.5 * T0 - 0.01 + j)
        })
        .collect()
}

/// The die, the blank and the positions and velocities of a batch of steps.
struct Setup {
    tool: Box<dyn ToolSurface>,
    x0: Vec<Vec3>,
    geometry: BlankGeometry,
    mass: Vec<f64>,
    thickness: Vec<f64>,
    positions: Vec<Vec<Vec3>>,
    velocities: Vec<Vec<Vec3>>,
}

impl Setup {
    fn new() -> Self {
        let mesh = fem_core::rectangle(75.0, 75.0, N, N).unwrap();
        let base = mesh.nodes.clone();
        let nn = base.len();
        let positions: Vec<Vec<Vec3>> = (0..=BATCH).map(|k| blank_at(&base, k)).collect();
        let velocities = (1..=BATCH)
            .map(|k| {
                positions[k]
                    .iter()
                    .zip(&positions[k - 1])
                    .map(|(a, b)| (a - b) / DT)
                    .collect()
            })
            .collect();
        Self {
            tool: Box::new(benchmark_quarter_die().unwrap()),
            x0: positions[0].clone(),
            geometry: BlankGeometry::new(nn, &mesh.quads).unwrap(),
            mass: vec![1e-6; nn],
            thickness: vec![T0; nn],
            positions,
            velocities,
        }
    }

    /// An AC (μ = 0.144) convective pair on the die.
    fn pair(&self, skip_far: bool) -> ContactPair {
        let integ = builtin::integrator(
            "ac",
            &Params::new().with("mu", 0.144),
            "convective",
            TangentMode::None,
        )
        .unwrap();
        let spec = PairSpec {
            skip_far,
            ..PairSpec::new("die-blank", 0, 1.7e5)
        };
        ContactPair::new(&spec, integ, &self.geometry, &self.x0).unwrap()
    }

    /// The blank at step `k` of the batch (`1..=BATCH`).
    fn view(&self, k: usize) -> BlankView<'_> {
        BlankView {
            x0: &self.x0,
            x: &self.positions[k],
            v: &self.velocities[k - 1],
            mass: &self.mass,
            thickness: &self.thickness,
            flow_stress: None,
        }
    }
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
}

fn touching(pair: &ContactPair) -> usize {
    pair.status
        .iter()
        .filter(|s| **s != contact::PointStatus::Open)
        .count()
}

/// Geometry update plus pair step, fastest batch.
fn whole_step(setup: &Setup, skip_far: bool, threads: usize) {
    let mut pair = setup.pair(skip_far);
    let mut g = setup.geometry.clone();
    let mut f = vec![Vec3::zeros(); setup.x0.len()];
    let pool = pool(threads);
    let mut best = f64::INFINITY;
    for _ in 0..BATCHES {
        let t = pool.install(|| {
            let t = Instant::now();
            for k in 1..=BATCH {
                let view = setup.view(k);
                g.update(&view, DT, pair.needs());
                pair.step(setup.tool.as_ref(), &g, &view, DT, &mut f)
                    .unwrap();
            }
            t.elapsed().as_secs_f64()
        });
        best = best.min(t);
    }
    println!(
        "skip_far {skip_far:5}, {threads} thread(s): {:.3} ms/step (geometry + pair step; \
         {} of {} nodes touch, {:.0} projections/step)",
        best * 1e3 / BATCH as f64,
        touching(&pair),
        setup.x0.len(),
        pair.projections as f64 / (BATCH * BATCHES) as f64
    );
}

/// Stage names as in `ContactTiming`, and the whole pair step.
const STAGES: [&str; 6] = [
    "broad_phase",
    "projection",
    "normal",
    "friction",
    "scatter",
    "pair step",
];

/// The pair's stage seconds of one step: `after − before`, then the whole step.
fn stage_seconds(before: &ContactTiming, after: &ContactTiming, whole: f64) -> [f64; 6] {
    [
        after.broad_phase - before.broad_phase,
        after.projection - before.projection,
        after.normal - before.normal,
        after.friction - before.friction,
        after.scatter - before.scatter,
        whole,
    ]
}

/// Each stage's time per step (skip_far on), fastest and median over all steps.
fn stages(setup: &Setup, threads: usize) {
    let mut pair = setup.pair(true);
    let mut g = setup.geometry.clone();
    let mut f = vec![Vec3::zeros(); setup.x0.len()];
    let pool = pool(threads);
    let mut samples: [Vec<f64>; 6] = Default::default();
    for batch in 0..=BATCHES {
        pool.install(|| {
            for k in 1..=BATCH {
                let view = setup.view(k);
                g.update(&view, DT, pair.needs());
                let before = pair.timing;
                let t = Instant::now();
                pair.step(setup.tool.as_ref(), &g, &view, DT, &mut f)
                    .unwrap();
                let whole = t.elapsed().as_secs_f64();
                // The first batch warms up (first projections, caches).
                if batch > 0 {
                    let s = stage_seconds(&before, &pair.timing, whole);
                    for (all, x) in samples.iter_mut().zip(s) {
                        all.push(x);
                    }
                }
            }
        });
    }
    println!(
        "stages, skip_far true, {threads} thread(s), {} steps ({} of {} nodes touch; \
         StepInput {} bytes per touching point):",
        BATCH * BATCHES,
        touching(&pair),
        setup.x0.len(),
        std::mem::size_of::<StepInput>()
    );
    for (name, mut all) in STAGES.into_iter().zip(samples) {
        all.sort_by(f64::total_cmp);
        println!(
            "  {name:12} fastest {:8.1} µs   median {:8.1} µs",
            all[0] * 1e6,
            all[all.len() / 2] * 1e6
        );
    }
}

fn main() {
    let setup = Setup::new();
    for skip_far in [false, true] {
        for threads in [1, 2] {
            whole_step(&setup, skip_far, threads);
        }
    }
    for threads in [1, 2] {
        stages(&setup, threads);
    }
}
