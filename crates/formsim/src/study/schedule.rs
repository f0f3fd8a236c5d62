//! The order in which a study runs its variants, and the timing of each run.
//!
//! A shared machine drifts in speed over minutes (by half, within hours, on
//! the machines this was measured on). A round therefore runs the
//! reference first, again after every [`REFERENCE_EVERY`] variants, and
//! last. Each variant's run is then compared with the reference's CPU time
//! interpolated at the middle of that run ([`reference_at`]): a slow spell
//! slows both. Rounds alternate direction (forward, backward, …).

use super::quantity::{Measured, Quantity, measure_all};
use super::{StudyError, Variant};
use crate::run::{Progress, RunOptions, RunResult, run};
use std::path::Path;
use std::time::Instant;

/// The reference runs again after this many variants in a round.
pub const REFERENCE_EVERY: usize = 4;

/// A variant's runs so far.
#[derive(Default)]
pub(crate) struct Runs {
    /// The first completed run.
    pub first: Option<RunResult>,
    /// The quantities of the first run.
    pub values: Vec<Measured>,
    /// Process CPU seconds per run.
    pub cpu: Vec<f64>,
    /// Wall seconds per run.
    pub wall: Vec<f64>,
    /// Middle of each run, seconds since the study started.
    pub at: Vec<f64>,
    /// Why the variant failed.
    pub failure: Option<String>,
}

impl Runs {
    /// Add `other`'s runs (the same variant, run later); they must give the
    /// same bits.
    pub fn merge(&mut self, other: Runs, label: &str) -> Result<(), StudyError> {
        if self.first.is_some() && other.first.is_some() && self.values != other.values {
            return Err(not_the_same_bits(label));
        }
        if self.first.is_none() {
            self.first = other.first;
            self.values = other.values;
        }
        self.cpu.extend(other.cpu);
        self.wall.extend(other.wall);
        self.at.extend(other.at);
        self.failure = self.failure.take().or(other.failure);
        Ok(())
    }
}

fn not_the_same_bits(label: &str) -> StudyError {
    StudyError::NotTheSameBits {
        label: label.to_string(),
    }
}

/// The order of one round over `n` variants (0 the reference): the
/// reference, then the others (forward in even rounds, backward in odd
/// ones) with the reference after every [`REFERENCE_EVERY`] and at the end.
pub fn round_order(n: usize, round: usize) -> Vec<usize> {
    let mut others: Vec<usize> = (1..n).collect();
    if round % 2 == 1 {
        others.reverse();
    }
    let mut order = vec![0];
    for (j, &i) in others.iter().enumerate() {
        order.push(i);
        if (j + 1) % REFERENCE_EVERY == 0 || j + 1 == others.len() {
            order.push(0);
        }
    }
    order
}

/// The reference's CPU time at `t` (s since the study started): linear
/// between the reference runs around `t`, the nearest one outside them.
/// `runs` are `(at, cpu)` in time order, at least one.
pub fn reference_at(runs: &[(f64, f64)], t: f64) -> f64 {
    match runs.iter().position(|r| r.0 >= t) {
        Some(0) => runs[0].1,
        None => runs[runs.len() - 1].1,
        Some(k) => {
            let ((t0, c0), (t1, c1)) = (runs[k - 1], runs[k]);
            if t1 > t0 {
                c0 + (c1 - c0) * (t - t0) / (t1 - t0)
            } else {
                c1
            }
        }
    }
}

/// `repeat` rounds over `variants` (the first is the reference) in the
/// order of [`round_order`]; `clock` is the study's start.
pub(crate) fn run_rounds(
    variants: &[&Variant],
    quantities: &[Quantity],
    repeat: usize,
    out: &Path,
    clock: Instant,
    bar: Option<&indicatif::ProgressBar>,
    on_run: &dyn Fn(&str, Result<&RunResult, &str>),
) -> Result<Vec<Runs>, StudyError> {
    let mut runs: Vec<Runs> = variants.iter().map(|_| Runs::default()).collect();
    for round in 0..repeat {
        for i in round_order(variants.len(), round) {
            let (v, r) = (variants[i], &mut runs[i]);
            if r.failure.is_some() {
                continue;
            }
            if let Some(b) = bar {
                b.set_message(format!("round {}/{repeat}: {}", round + 1, v.label));
            }
            let start = clock.elapsed().as_secs_f64();
            match run_once(v, out, bar) {
                Err(e) => {
                    let m = e.to_string();
                    on_run(&v.label, Err(&m));
                    r.failure = Some(m);
                }
                Ok(t) => {
                    on_run(&v.label, Ok(&t.result));
                    let middle = start + 0.5 * t.wall_s;
                    record(v, r, t, middle, quantities)?;
                }
            }
        }
    }
    Ok(runs)
}

/// One timed run's figures.
struct Timed {
    result: RunResult,
    cpu_s: f64,
    wall_s: f64,
}

/// Run a variant once into `out/LABEL`, timed.
fn run_once(
    v: &Variant,
    out: &Path,
    bar: Option<&indicatif::ProgressBar>,
) -> Result<Timed, StudyError> {
    if let Some(b) = bar {
        b.reset();
    }
    let cpu = cpu_time::ProcessTime::try_now().map_err(StudyError::CpuTime)?;
    let wall = Instant::now();
    let result = run(
        &v.loaded,
        &RunOptions {
            out: out.join(&v.label),
            progress: bar.map_or(Progress::Hidden, |b| Progress::Bar(b.clone())),
        },
    )?;
    let cpu_s = cpu
        .try_elapsed()
        .map_err(StudyError::CpuTime)?
        .as_secs_f64();
    Ok(Timed {
        result,
        cpu_s,
        wall_s: wall.elapsed().as_secs_f64(),
    })
}

/// Keep a run's figures; a repeat must give the first run's bits.
fn record(
    v: &Variant,
    r: &mut Runs,
    t: Timed,
    at: f64,
    quantities: &[Quantity],
) -> Result<(), StudyError> {
    let values = match measure_all(quantities, &t.result) {
        Ok(values) => values,
        Err(e) => {
            r.failure = Some(e.to_string());
            return Ok(());
        }
    };
    if r.first.is_none() {
        r.values = values;
        r.first = Some(t.result);
    } else if values != r.values {
        return Err(not_the_same_bits(&v.label));
    }
    r.cpu.push(t.cpu_s);
    r.wall.push(t.wall_s);
    r.at.push(at);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounds_bracket_every_few_variants_with_the_reference() {
        assert_eq!(round_order(1, 0), [0]);
        assert_eq!(round_order(3, 0), [0, 1, 2, 0]);
        assert_eq!(
            round_order(7, 0),
            [0, 1, 2, 3, 4, 0, 5, 6, 0],
            "every {REFERENCE_EVERY}"
        );
        assert_eq!(round_order(7, 1), [0, 6, 5, 4, 3, 0, 2, 1, 0]);
    }

    #[test]
    fn the_reference_is_interpolated_between_its_runs() {
        let r = [(10.0, 30.0), (20.0, 40.0), (40.0, 20.0)];
        assert_eq!(reference_at(&r, 5.0), 30.0);
        assert_eq!(reference_at(&r, 15.0), 35.0);
        assert_eq!(reference_at(&r, 30.0), 30.0);
        assert_eq!(reference_at(&r, 50.0), 20.0);
    }
}
