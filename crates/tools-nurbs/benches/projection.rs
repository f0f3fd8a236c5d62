//! Projections per second per core on the square-cup punch (quarter model), warm-started and cold.
//!
//! Warm: each point's hint is the answer for the same node one explicit step
//! earlier, 0.01 mm away (what contact passes every step). Cold: no hint.
//! Points lie within 5 mm of the quarter punch surface (the contact search
//! band), in the quadrant x, y ≥ 0 that the quarter model covers.
//! Run: `cargo bench -p tools-nurbs --bench projection`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use plugins_api::{ProjectionHint, ToolSurface, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use tools_nurbs::builders::square_cup::{PunchParams, punch};
use tools_nurbs::builders::{Model, Placement};

fn bench(c: &mut Criterion) {
    let tool = punch(
        "punch",
        &PunchParams::default(),
        Model::Quarter,
        &Placement::default(),
    )
    .unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let n = 4096;
    let mut points = Vec::with_capacity(n);
    let mut hints: Vec<ProjectionHint> = Vec::with_capacity(n);
    while points.len() < n {
        // A random point of the quarter punch surface, lifted 0–5 mm along its normal.
        let q = Vec3::new(
            rng.random_range(0.0..40.0),
            rng.random_range(0.0..40.0),
            rng.random_range(-50.0..5.0),
        );
        let p = tool.project(&q, None).unwrap();
        let x = p.point + p.normal * rng.random_range(0.0..5.0);
        let step = Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        )
        .normalize()
            * 0.01;
        hints.push(tool.project(&(x - step), None).unwrap().hint());
        points.push(x);
    }
    let mut g = c.benchmark_group("square_cup_punch_projection");
    g.throughput(Throughput::Elements(n as u64));
    g.bench_function("warm", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for (x, h) in points.iter().zip(&hints) {
                acc += tool.project(black_box(x), Some(*h)).unwrap().distance;
            }
            acc
        })
    });
    g.bench_function("cold", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for x in &points {
                acc += tool.project(black_box(x), None).unwrap().distance;
            }
            acc
        })
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(3));
    targets = bench
}
criterion_main!(benches);
