//! Effects on demand, measured: the cost of one whole
//! explicit step of the square cup in mid-draw for each effect a scene may
//! ask for, as a ratio to the scene as it is (AC + convective,
//! Belytschko–Tsay, 5 points), all measured in the same run.
//!
//! Every variant is the cup of `scenes/square-cup.toml` with one set of
//! `--set` overrides, built and drawn to 13 mm of punch stroke as
//! `cup_step` does; all are drawn first, then benched one after the other
//! (about 1.5 s each), so that the ratios come from the same half-minute of
//! the machine. Each step is timed on its own: the table gives the fastest
//! and the median step per variant and their ratios to the baseline's.
//! "no contact" is the baseline's step without its contact effect: the
//! baseline's median times the share of the step outside contact, from
//! `Solver::timing` over the same steps.
//!
//! ```text
//! RAYON_NUM_THREADS=1 cargo bench -p formsim --bench effects
//! ```
//! prints the table (markdown) at the end; `docs/accuracy-cost.md` keeps one.

mod common;

use common::{START, bench_steps, cup_at_mid_draw};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use formsim::scene::Model;
use std::time::Duration;

/// Room for the duration of every step a variant takes (no allocation while timing).
const MAX_STEPS: usize = 50_000;

/// The variants: label and overrides. The first is the baseline.
const VARIANTS: [(&str, &[&str]); 11] = [
    ("AC, convective (the scene)", &[]),
    ("frictionless", &["contact.law=frictionless"]),
    ("WVS, convective", &["contact.law=wvs"]),
    ("WH, convective", &["contact.law=wh"]),
    ("Levanov, convective", &["contact.law=levanov"]),
    ("AC, jaumann", &["contact.formulation=jaumann"]),
    ("AC, lagrangian", &["contact.formulation=lagrangian"]),
    (
        "AC, updated-lagrangian",
        &["contact.formulation=updated-lagrangian"],
    ),
    (
        "fully integrated shell",
        &["blank.element=fully-integrated"],
    ),
    ("3 points", &["blank.integration_points=3"]),
    ("7 points", &["blank.integration_points=7"]),
];

/// A variant's measured steps.
struct Timed {
    label: &'static str,
    steps: Vec<Duration>,
    /// Seconds in the contact effect and in the whole step, over the benched steps.
    contact_s: f64,
    total_s: f64,
}

fn effects(c: &mut Criterion) {
    let mut models: Vec<(&'static str, Model)> = VARIANTS
        .iter()
        .map(|(label, sets)| (*label, cup_at_mid_draw(label, sets)))
        .collect();
    let elements = models[0].1.mesh.quads.len();
    let mut g = c.benchmark_group("effects");
    g.throughput(Throughput::Elements(elements as u64));
    let mut timed = Vec::new();
    for (label, model) in &mut models {
        let k = model.contact.expect("contact").0;
        let (c0, t0) = (
            model.solver.timing().effects[k],
            model.solver.timing().total,
        );
        let mut steps: Vec<Duration> = Vec::with_capacity(MAX_STEPS);
        bench_steps(&mut g, label, model, &mut steps);
        let t = model.solver.timing();
        timed.push(Timed {
            label,
            steps,
            contact_s: t.effects[k] - c0,
            total_s: t.total - t0,
        });
    }
    g.finish();
    print_table(&mut timed, elements);
}

/// Fastest and median step of each variant (µs) and their ratios to the first.
fn print_table(timed: &mut [Timed], elements: usize) {
    let stats: Vec<(f64, f64)> = timed
        .iter_mut()
        .map(|t| {
            t.steps.sort_unstable();
            let us = |d: &Duration| 1e6 * d.as_secs_f64();
            (
                t.steps.first().map_or(0.0, us),
                t.steps.get(t.steps.len() / 2).map_or(0.0, us),
            )
        })
        .collect();
    let (f0, m0) = stats[0];
    println!(
        "\n{elements} elements, {} rayon threads, from {START} mm of stroke\n",
        rayon::current_num_threads()
    );
    println!("| variant | fastest step (µs) | ratio | median step (µs) | ratio | steps timed |");
    println!("|---|---:|---:|---:|---:|---:|");
    let base = &timed[0];
    let outside = 1.0 - base.contact_s / base.total_s;
    println!(
        "| no contact (the baseline's step outside contact) | – | – | {:.1} | {:.2} | – |",
        m0 * outside,
        outside
    );
    for (t, (f, m)) in timed.iter().zip(&stats) {
        println!(
            "| {} | {f:.1} | {:.2} | {m:.1} | {:.2} | {} |",
            t.label,
            f / f0,
            m / m0,
            t.steps.len()
        );
    }
}

criterion_group! {
    name = benches;
    config = common::few_short_samples();
    targets = effects
}
criterion_main!(benches);
