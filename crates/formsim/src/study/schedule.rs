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
use crate::batch::{self, Engine, JobSpec, Record};
use crate::run::{Progress, RunResult};

/// The reference runs again after this many variants in a round.
pub const REFERENCE_EVERY: usize = 4;

/// What a study takes from a run (what its journal keeps).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct VariantRun {
    /// Scene name.
    pub scene: String,
    /// Increments.
    pub increments: u64,
    /// Wall seconds of the run (`summary.json`'s `wall_time_s`).
    pub wall_time_s: f64,
    /// Relative energy balance error.
    pub balance_error_rel: f64,
    /// Largest kinetic/internal energy ratio after forming starts.
    pub kinetic_to_internal_max: f64,
    /// Largest kinetic energy over external work after forming starts.
    pub kinetic_to_work_max: f64,
    /// The run's warnings.
    pub warnings: Vec<String>,
    /// The study's quantities, in order.
    pub values: Vec<Measured>,
}

impl VariantRun {
    /// The figures of `result` and its `quantities`.
    ///
    /// # Errors
    /// A quantity cannot be measured.
    pub fn of(result: &RunResult, quantities: &[Quantity]) -> Result<Self, String> {
        let s = &result.summary;
        Ok(Self {
            scene: s.scene.clone(),
            increments: s.increments,
            wall_time_s: s.wall_time_s,
            balance_error_rel: s.energy.balance_error_rel,
            kinetic_to_internal_max: s.kinetic_to_internal_max,
            kinetic_to_work_max: s.kinetic_to_work_max,
            warnings: s.warnings.clone(),
            values: measure_all(quantities, result).map_err(|e| e.to_string())?,
        })
    }
}

/// A variant's runs so far.
#[derive(Default)]
pub(crate) struct Runs {
    /// The first completed run.
    pub first: Option<VariantRun>,
    /// The quantities of the first run.
    pub values: Vec<Measured>,
    /// CPU seconds per run (of the threads that ran it).
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

/// Where a study's runs go and what it is told of them.
pub(crate) struct Rounds<'a> {
    /// The engine (executor, journal, clock).
    pub engine: &'a Engine<'a>,
    /// The study's output folder.
    pub out: &'a std::path::Path,
    /// The study's bar, if any.
    pub bar: Option<&'a indicatif::ProgressBar>,
    /// Told after each run.
    pub on_run: &'a dyn Fn(&str, Result<&VariantRun, &str>),
    /// Which call of [`run_rounds`] this is (journal labels differ).
    pub call: usize,
}

/// `repeat` rounds over `variants` (the first is the reference) in the
/// order of [`round_order`], each round one batch for the engine: one run
/// at a time, that is the order itself; with several at a time, the runs
/// start in that order as workers become free. A variant's first run in a
/// round writes its folder; its later runs in the same round (the
/// reference's brackets) write a folder of their own in the journal's
/// scratch folder ([`repeat_dir`]), removed as each ends, so that two runs never
/// write one folder at once.
pub(crate) fn run_rounds(
    variants: &[&Variant],
    quantities: &[Quantity],
    repeat: usize,
    r: &Rounds<'_>,
) -> Result<Vec<Runs>, StudyError> {
    let mut runs: Vec<Runs> = variants.iter().map(|_| Runs::default()).collect();
    for round in 0..repeat {
        let (positions, order): (Vec<usize>, Vec<usize>) = round_order(variants.len(), round)
            .into_iter()
            .enumerate()
            .filter(|&(_, i)| runs[i].failure.is_none())
            .unzip();
        let jobs: Vec<JobSpec> = order
            .iter()
            .zip(&positions)
            .enumerate()
            .map(|(k, (&i, j))| {
                // Unique in the study: which call, round and place in it.
                let label = format!("{}/{}.{round}.{j}", variants[i].label, r.call);
                let out = if order[..k].contains(&i) {
                    repeat_dir(r.out, &label)
                } else {
                    r.out.join(&variants[i].label)
                };
                JobSpec {
                    label,
                    sets: variants[i].sets.clone(),
                    out,
                    estimate: 0.0,
                }
            })
            .collect();
        let extract = |result: &RunResult| {
            let v = VariantRun::of(result, quantities)?;
            serde_json::to_value(v).map_err(|e| e.to_string())
        };
        let (bar, clock) = (r.bar, r.engine.clock());
        let work = |k: usize, spec: &JobSpec| {
            let v = variants[order[k]];
            if let Some(b) = bar {
                b.reset();
                b.set_message(format!("round {}/{repeat}: {}", round + 1, v.label));
            }
            let progress = bar.map_or(Progress::Hidden, |b| Progress::Bar(b.clone()));
            let scene = batch::Scene::Planned(&v.loaded);
            batch::run_job(scene, spec, progress, clock, &extract)
        };
        let records = r.engine.run(&jobs, &work, &mut |k, record, _| {
            if jobs[k].out.starts_with(batch::journal::scratch(r.out)) {
                // A repeat's files are the first run's bits: only its
                // timing is kept.
                let _ = std::fs::remove_dir_all(&jobs[k].out);
            }
            let label = &variants[order[k]].label;
            match decode(record) {
                Ok(v) => (r.on_run)(label, Ok(&v)),
                Err(m) => (r.on_run)(label, Err(&m)),
            }
        })?;
        // Left empty by the repeats (or never made).
        let _ = std::fs::remove_dir(batch::journal::scratch(r.out));
        for (k, record) in records.iter().enumerate() {
            let i = order[k];
            keep(variants[i], &mut runs[i], record)?;
        }
    }
    Ok(runs)
}

/// The folder of a repeated run labelled `label` in the study's folder
/// `out`: in the journal's scratch folder, named for the label.
fn repeat_dir(out: &std::path::Path, label: &str) -> std::path::PathBuf {
    batch::journal::scratch(out).join(label.replace('/', "."))
}

/// The study's figures of a record, or why the run failed.
fn decode(record: &Record) -> Result<VariantRun, String> {
    record
        .outcome
        .clone()
        .and_then(|v| serde_json::from_value(v).map_err(|e| e.to_string()))
}

/// Keep a run's figures; a repeat must give the first run's bits.
fn keep(v: &Variant, r: &mut Runs, record: &Record) -> Result<(), StudyError> {
    let run = match decode(record) {
        Ok(run) => run,
        Err(m) => {
            r.failure = Some(m);
            return Ok(());
        }
    };
    if r.first.is_none() {
        r.values = run.values.clone();
        r.first = Some(run);
    } else if run.values != r.values {
        return Err(not_the_same_bits(&v.label));
    }
    r.cpu.push(record.cpu_s);
    r.wall.push(record.wall_s);
    r.at.push(record.started_s + 0.5 * record.wall_s);
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
    fn repeats_write_under_the_journal() {
        let out = std::path::Path::new("/tmp/study");
        assert_eq!(
            repeat_dir(out, "reference/0.1.5"),
            out.join("journal/scratch/reference.0.1.5")
        );
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
