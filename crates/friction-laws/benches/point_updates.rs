//! Point updates per second per core for every built-in law × formulation
//! (aim: AC + convective ≥ 20 M/s, no pairing below 5 M/s).
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
use plugins_api::{PointState, StepOutput, TangentMode};

mod support;
use support::inputs;

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
