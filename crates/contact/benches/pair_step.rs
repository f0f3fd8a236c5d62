//! Time of one `ContactPair::step` of a 50×50 quarter blank (2,601 nodes) on
//! the exact NURBS square-cup die: the flange presses 0.01 mm into the die
//! face, the part over the opening hangs clear, and every node jiggles a
//! little each step (so that warm starts do real work). Runs in a rayon pool
//! of 1 and of 2 threads, with `skip_far` on and off, and prints the fastest
//! of several batches of steps (the machine may be shared).
//!
//! ```text
//! cargo bench -p contact --bench pair_step
//! ```

use std::time::Instant;

use contact::{BlankGeometry, BlankView, ContactPair, PairSpec};
use friction_laws::builtin;
use plugins_api::{Params, TangentMode, Vec3};
use tools_nurbs::builders::square_cup::benchmark_quarter_die;

const N: usize = 50;
const T0: f64 = 0.78;
const DT: f64 = 1e-6;
const BATCH: usize = 200;
const BATCHES: usize = 10;

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

fn main() {
    let tool = benchmark_quarter_die().unwrap();
    let mesh = fem_core::rectangle(75.0, 75.0, N, N).unwrap();
    let base = mesh.nodes.clone();
    let nn = base.len();
    let x0 = blank_at(&base, 0);
    let geometry = BlankGeometry::new(nn, &mesh.quads).unwrap();
    let mass = vec![1e-6; nn];
    let thickness = vec![T0; nn];
    for skip_far in [false, true] {
        for threads in [1, 2] {
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
            let mut pair = ContactPair::new(&spec, integ, &geometry, &x0).unwrap();
            let mut g = geometry.clone();
            let mut f = vec![Vec3::zeros(); nn];
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let positions: Vec<Vec<Vec3>> = (0..=BATCH).map(|k| blank_at(&base, k)).collect();
            let velocities: Vec<Vec<Vec3>> = (1..=BATCH)
                .map(|k| {
                    positions[k]
                        .iter()
                        .zip(&positions[k - 1])
                        .map(|(a, b)| (a - b) / DT)
                        .collect()
                })
                .collect();
            let mut best = f64::INFINITY;
            let mut touching = 0;
            for _ in 0..BATCHES {
                let t = pool.install(|| {
                    let t = Instant::now();
                    for k in 1..=BATCH {
                        let view = BlankView {
                            x0: &x0,
                            x: &positions[k],
                            v: &velocities[k - 1],
                            mass: &mass,
                            thickness: &thickness,
                            flow_stress: None,
                        };
                        g.update(&view, DT, pair.needs());
                        pair.step(&tool, &g, &view, DT, &mut f).unwrap();
                    }
                    t.elapsed().as_secs_f64()
                });
                best = best.min(t);
                touching = pair
                    .status
                    .iter()
                    .filter(|s| **s != contact::PointStatus::Open)
                    .count();
            }
            println!(
                "skip_far {skip_far:5}, {threads} thread(s): {:.3} ms/step (geometry + pair step; \
                 {touching} of {nn} nodes touch, {:.0} projections/step)",
                best * 1e3 / BATCH as f64,
                pair.projections as f64 / (BATCH * BATCHES) as f64
            );
        }
    }
}
