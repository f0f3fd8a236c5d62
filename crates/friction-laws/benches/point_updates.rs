//! Point updates per second per core for every built-in law × formulation
//! (issue: aim AC + convective ≥ 20 M/s, no pairing below 5 M/s).
//!
//! Each iteration integrates one explicit step at a batch of contact points
//! through `PointIntegrator::step_batch` (one virtual call per batch,
//! monomorphised inside), with a random mix of stick and slip, curved-tool
//! normals, blank spin and deformation, and no tangent (explicit dynamics needs
//! none). Two batch sizes: 4096 points, whose inputs (~1.5 MB) stream from L3,
//! and 512 points, whose inputs stay in L2 — as when an engine updates friction
//! on a chunk of contact points right after computing their gaps.
//! Run: `cargo bench -p friction-laws --bench point_updates`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use friction_laws::builtin::{self, FORMULATION_NAMES, LAW_NAMES};
use plugins_api::kinematics::cayley;
use plugins_api::{Mat3, PointState, StepInput, StepKinematics, StepOutput, TangentMode, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn inputs(points: usize) -> Vec<StepInput> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    (0..points)
        .map(|_| {
            let tilt = Vec3::new(
                rng.random_range(-0.3..0.3),
                rng.random_range(-0.3..0.3),
                1.0,
            )
            .normalize();
            let n_old = tilt;
            let n_new = (tilt
                + Vec3::new(
                    rng.random_range(-1e-3..1e-3),
                    rng.random_range(-1e-3..1e-3),
                    0.0,
                ))
            .normalize();
            let dir = Vec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            );
            let tangential = dir - n_new * n_new.dot(&dir);
            // Slip increments from 1e-6 to 1e-3 mm: small ones stick, large ones slip.
            let du = tangential.normalize() * 10f64.powf(rng.random_range(-6.0..-3.0));
            let dt = 1e-6;
            let l = Mat3::from_fn(|_, _| rng.random_range(-50.0..50.0));
            let f_old = Mat3::identity() + Mat3::from_fn(|_, _| rng.random_range(-0.05..0.05));
            let kin = StepKinematics {
                dt,
                n_old,
                n_new,
                tool_rotation: Mat3::identity(),
                vel_grad: l,
                f_old,
                f_new: cayley(&(l * dt)) * f_old,
            };
            let mut input = StepInput::new(rng.random_range(1.0..100.0), du, kin);
            input.flow_stress = rng.random_range(250.0..450.0);
            input
        })
        .collect()
}

fn point_updates(c: &mut Criterion) {
    for (group_name, points) in [("point_updates", 4096), ("point_updates_in_cache", 512)] {
        let inputs = inputs(points);
        let mut group = c.benchmark_group(group_name);
        group.throughput(Throughput::Elements(points as u64));
        for law in LAW_NAMES {
            for formulation in FORMULATION_NAMES {
                let integrator = builtin::integrator(
                    law,
                    &builtin::benchmark_params(law),
                    formulation,
                    TangentMode::None,
                )
                .expect("benchmark parameters are valid");
                let mut states = vec![PointState::default(); points];
                let mut outputs = vec![StepOutput::default(); points];
                group.bench_function(format!("{law}/{formulation}"), |b| {
                    b.iter(|| {
                        integrator
                            .step_batch(&mut states, std::hint::black_box(&inputs), &mut outputs)
                            .expect("benchmark inputs are valid");
                    });
                });
            }
        }
        group.finish();
    }
}

criterion_group!(benches, point_updates);
criterion_main!(benches);
