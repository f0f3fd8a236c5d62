//! What the cup benches share: the square cup drawn to mid-draw, and one
//! criterion bench that steps it on and keeps each step's duration.

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion};
use formsim::scene::{self, Model};
use std::path::Path;
use std::time::{Duration, Instant};

/// Punch stroke at which the benches start (mm).
pub const START: f64 = 13.0;

/// The punch's stroke (mm).
pub fn stroke(model: &Model) -> f64 {
    let s = model.stroke.expect("the cup has a stroke tool");
    model
        .press()
        .map_or(0.0, |p| p.displacement(s.index).dot(&s.direction))
}

/// `scenes/square-cup.toml` with `sets`, built and drawn to [`START`];
/// `label` names it in the set-up line.
pub fn cup_at_mid_draw(label: &str, sets: &[&str]) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/square-cup.toml");
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let loaded = scene::load(&path, &sets).expect("scene");
    let mut model = scene::build(&loaded).expect("model");
    model.solver.initialize().expect("set-up");
    let t = Instant::now();
    while stroke(&model) < START {
        model.solver.step().expect("step");
    }
    eprintln!(
        "set-up {label}: {} steps to {:.2} mm of stroke in {:.1} s ({} rayon threads)",
        model.solver.steps(),
        stroke(&model),
        t.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    );
    model
}

/// Bench `id` in `group`: every iteration one more step of `model`; the
/// duration of each step lands in `steps` while it has room (allocated by
/// the caller, so nothing allocates while timing).
pub fn bench_steps(
    group: &mut BenchmarkGroup<'_, WallTime>,
    id: &str,
    model: &mut Model,
    steps: &mut Vec<Duration>,
) {
    group.bench_function(id, |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                let t = Instant::now();
                model.solver.step().expect("step");
                let d = t.elapsed();
                total += d;
                if steps.len() < steps.capacity() {
                    steps.push(d);
                }
            }
            total
        })
    });
}

/// Criterion held to its minimum (10 samples, 0.3 s of warm-up, 1 s of
/// measurement): every iteration moves the draw on, so a bench should cover
/// a short stretch of it.
pub fn few_short_samples() -> Criterion {
    Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1))
}
