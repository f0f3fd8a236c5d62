//! Warm and cold projections on the square-cup punch, for instruction counting
//! under `valgrind --tool=callgrind` (load-independent, unlike wall time).
//!
//! Run: `cargo build --release -p tools-nurbs --example projection_profile`, then
//! `valgrind --tool=callgrind target/release/examples/projection_profile warm 100000`
//! (or `cold`, or `setup` for the set-up alone, to subtract).

use plugins_api::{ProjectionHint, ToolSurface, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use tools_nurbs::builders::square_cup::{PunchParams, punch};
use tools_nurbs::builders::{Model, Placement};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mode = args.get(1).map_or("warm", |s| s.as_str());
    let reps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(100_000);
    let tool = punch(
        "punch",
        &PunchParams::default(),
        Model::Quarter,
        &Placement::default(),
    )
    .expect("punch builds");
    // The same point set as benches/projection.rs.
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let n = 4096;
    let mut points = Vec::with_capacity(n);
    let mut hints: Vec<ProjectionHint> = Vec::with_capacity(n);
    while points.len() < n {
        let q = Vec3::new(
            rng.random_range(0.0..40.0),
            rng.random_range(0.0..40.0),
            rng.random_range(-50.0..5.0),
        );
        let p = tool.project(&q, None).expect("finite point");
        let x = p.point + p.normal * rng.random_range(0.0..5.0);
        let step = Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        )
        .normalize()
            * 0.01;
        hints.push(
            tool.project(&(x - step), None)
                .expect("finite point")
                .hint(),
        );
        points.push(x);
    }
    let mut acc = 0.0;
    match mode {
        "warm" => {
            for k in 0..reps {
                let i = k % n;
                acc += tool
                    .project(black_box(&points[i]), Some(hints[i]))
                    .expect("finite point")
                    .distance;
            }
        }
        "cold" => {
            for k in 0..reps {
                let i = k % n;
                acc += tool
                    .project(black_box(&points[i]), None)
                    .expect("finite point")
                    .distance;
            }
        }
        _ => {}
    }
    println!("{mode} {reps}: {acc}");
}
