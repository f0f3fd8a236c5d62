//! Time of one whole explicit step (`Solver::step`: shells, contact with its
//! three pairs, press, integration, energy ledger) of the NUMISHEET'93 square
//! cup as `scenes/square-cup.toml` defines it (50 × 50 quarter blank, 2,500
//! Belytschko–Tsay shells with 5 points, AC + convective), in mid-draw.
//!
//! Set-up: the scene is loaded and built as `formsim run` does and stepped
//! to 13 mm of punch stroke (about 17,000 steps, 20–25 s). `Solver` is not
//! `Clone` (its effects are boxed trait objects), so the bench steps on from
//! there: every iteration is one more step of the same draw, about 3.2 µm
//! of stroke at this point of the slow-start profile. Criterion is held to
//! its minimum (10 samples, 0.3 s warm-up, 1 s of measurement: 1,000 to
//! 1,500 steps), so the bench covers about 13 to 17 mm, round the 15 mm of
//! mid-draw; the range is printed at the end. Over it the contact area
//! grows and the cost of a step drifts by a few per cent.
//!
//! `step` is criterion's mean (throughput per element). Each step is also
//! timed on its own: the fastest and the median step are printed (the
//! fastest is the robust estimator on a shared machine, interference only
//! ever adding time, as `shell-elements`' `element_loop` argues), with the
//! mean per stage over the same steps, read from `Solver::timing` and
//! `ContactEffect::timing` (the split `summary.json`'s `timing` reports;
//! the stages are not benched one by one).
//!
//! ```text
//! RAYON_NUM_THREADS=1 cargo bench -p formsim --bench cup_step
//! RAYON_NUM_THREADS=2 cargo bench -p formsim --bench cup_step
//! ```

mod common;

use common::{bench_steps, cup_at_mid_draw, stroke};
use contact::ContactTiming;
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use formsim::scene::Model;
use std::time::Duration;

/// Room for the duration of every step the bench takes (no allocation while timing).
const MAX_STEPS: usize = 100_000;

/// What the timers say so far: (step, engine, every effect but contact,
/// contact, contact's stages) in seconds.
fn split(model: &Model) -> (f64, f64, f64, f64, ContactTiming) {
    let t = model.solver.timing();
    let k = model.contact.expect("contact").0;
    let elements = t
        .effects
        .iter()
        .enumerate()
        .filter(|&(i, _)| i != k)
        .map(|(_, s)| s)
        .sum();
    let c = model.contact().expect("contact").timing();
    (t.total, t.engine(), elements, t.effects[k], c)
}

fn cup_step(c: &mut Criterion) {
    let mut model = cup_at_mid_draw("the cup", &[]);
    let elements = model.mesh.quads.len();
    let (steps0, stroke0) = (model.solver.steps(), stroke(&model));
    let before = split(&model);
    let mut g = c.benchmark_group("cup_step");
    g.throughput(Throughput::Elements(elements as u64));
    let mut each: Vec<Duration> = Vec::with_capacity(MAX_STEPS);
    bench_steps(&mut g, "step", &mut model, &mut each);
    g.finish();

    let after = split(&model);
    let n = (model.solver.steps() - steps0) as f64;
    let us = |s: f64| 1e6 * s / n;
    let (c0, c1) = (before.4, after.4);
    eprintln!(
        "benches: {} steps from {:.2} to {:.2} mm of stroke, {} elements, {} rayon threads",
        n,
        stroke0,
        stroke(&model),
        elements,
        rayon::current_num_threads()
    );
    each.sort_unstable();
    let fastest = each.first().map_or(0.0, |d| 1e6 * d.as_secs_f64());
    let median = each
        .get(each.len() / 2)
        .map_or(0.0, |d| 1e6 * d.as_secs_f64());
    let per_element = |t: f64| t / elements as f64;
    eprintln!(
        "step (µs): fastest {fastest:.1} ({:.3} µs per element per cycle), median {median:.1} ({:.3})",
        per_element(fastest),
        per_element(median)
    );
    eprintln!(
        "mean per step (µs): step {:.1} = elements {:.1} + contact {:.1} + engine {:.1}",
        us(after.0 - before.0),
        us(after.2 - before.2),
        us(after.3 - before.3),
        us(after.1 - before.1),
    );
    let stages: Vec<String> = c1
        .stages()
        .iter()
        .zip(c0.stages())
        .map(|((name, s1), (_, s0))| format!("{name} {:.1}", us(s1 - s0)))
        .collect();
    eprintln!("  contact stages (µs): {}", stages.join(", "));
}

criterion_group! {
    name = benches;
    config = common::few_short_samples();
    targets = cup_step
}
criterion_main!(benches);
