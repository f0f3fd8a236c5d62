//! Point updates per second per core for every built-in law × formulation
//! (issue: aim AC + convective ≥ 20 M/s, no pairing below 5 M/s).
//!
//! Each iteration integrates one explicit step at 4096 contact points through
//! `PointIntegrator::step_batch` (one virtual call per batch, monomorphised
//! inside), with a mix of stick and slip, curved-tool normals, blank spin and
//! deformation, and no tangent (explicit dynamics needs none).
//! Run: `cargo bench -p friction-laws --bench point_updates`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use friction_laws::builtin::{self, FORMULATION_NAMES, LAW_NAMES};
use plugins_api::kinematics::cayley;
use plugins_api::{Mat3, PointState, StepInput, StepKinematics, StepOutput, TangentMode, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const POINTS: usize = 4096;

fn inputs() -> Vec<StepInput> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    (0..POINTS)
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
    let inputs = inputs();
    let mut group = c.benchmark_group("point_updates");
    group.throughput(Throughput::Elements(POINTS as u64));
    for law in LAW_NAMES {
        for formulation in FORMULATION_NAMES {
            let integrator = builtin::integrator(
                law,
                &builtin::benchmark_params(law),
                formulation,
                TangentMode::None,
            )
            .expect("benchmark parameters are valid");
            let mut states = vec![PointState::default(); POINTS];
            let mut outputs = vec![StepOutput::default(); POINTS];
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

criterion_group!(benches, point_updates);
criterion_main!(benches);
