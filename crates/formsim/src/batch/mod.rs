//! The batch engine: what `compare`, `study` and `identify` share when they
//! run many scenes.
//!
//! A strategy (one of the three commands) turns its arguments into
//! [`JobSpec`]s (a label, the scene's overrides, the run's folder), checks
//! every one of them before anything runs, and hands them to an
//! [`Executor`]: [`local::Local`] runs them in this process, `--jobs N`
//! at a time on `--threads T` each; the MPI executor (cargo feature `mpi`)
//! spreads them over the ranks of an MPI job. Each run ends as a [`Record`]:
//! the strategy's quantities, extracted from the run by the strategy's own
//! [`Extract`] (small, serialisable: it crosses ranks and goes to the
//! [`journal::Journal`]), or the one-line reason it failed, with its CPU
//! and wall seconds. The journal records each record as it arrives, so a
//! batch that is interrupted and called again with the same arguments runs
//! only what is missing.

pub mod cpu;
pub mod journal;
pub mod launcher;
pub mod local;
#[cfg(feature = "mpi")]
pub mod mpi;

use crate::run::{Progress, RunOptions, RunResult};
use crate::scene::{self, LoadedScene};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// One run to make: the scene's overrides and where its files go.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JobSpec {
    /// The run's label: its folder's name and its key in the journal.
    pub label: String,
    /// Overrides of the scene (`KEY=VALUE`), in order.
    pub sets: Vec<String>,
    /// The run's output folder.
    pub out: PathBuf,
    /// Relative cost of the run (e.g. its element count times its
    /// increments): executors that choose an order start the largest first.
    pub estimate: f64,
}

/// What a finished run reports back: small, so that it crosses ranks and
/// fits the journal.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Record {
    /// The job's label.
    pub label: String,
    /// The strategy's quantities of the run, or why it failed (one line).
    pub outcome: Result<serde_json::Value, String>,
    /// CPU seconds of the threads that ran it.
    pub cpu_s: f64,
    /// Wall seconds.
    pub wall_s: f64,
    /// When it started, seconds since the batch's clock started.
    pub started_s: f64,
}

impl Record {
    /// An untimed failed record of `spec`: `why` it has no result.
    pub fn failed(spec: &JobSpec, why: &str) -> Self {
        Self {
            label: spec.label.clone(),
            outcome: Err(why.to_string()),
            cpu_s: 0.0,
            wall_s: 0.0,
            started_s: 0.0,
        }
    }
}

/// What goes wrong with a batch itself (a run's failure is a [`Record`]).
#[derive(Debug, thiserror::Error)]
pub enum BatchError {
    /// The journal cannot be read or written, or belongs to another batch.
    #[error("journal: {0}")]
    Journal(String),
    /// The executor cannot run the batch (no thread pool, MPI failure).
    #[error("executor: {0}")]
    Executor(String),
    /// The output folder cannot be made ready.
    #[error(transparent)]
    OutDir(#[from] crate::run::out_dir::OutDirError),
}

/// Takes a strategy's quantities from a finished run.
pub type Extract<'a> = dyn Fn(&RunResult) -> Result<serde_json::Value, String> + Sync + 'a;

/// Runs one job in this process: `(index in the batch, spec) → record`.
pub type Work<'a> = dyn Fn(usize, &JobSpec) -> Record + Sync + 'a;

/// Runs a batch of jobs.
pub trait Executor: Sync {
    /// Run `jobs` through `work` (in this process or elsewhere); `done` is
    /// called on the calling thread as each record arrives, in completion
    /// order, with the job's index in `jobs`.
    ///
    /// # Errors
    /// The executor cannot run (a thread pool cannot be made, MPI fails).
    fn run(
        &self,
        jobs: &[JobSpec],
        work: &Work<'_>,
        done: &mut dyn FnMut(usize, Record),
    ) -> Result<(), BatchError>;

    /// Worker threads of each run.
    fn threads(&self) -> usize;
}

/// A job's scene: the one the plan loaded and checked, or (on another rank,
/// which has no plan) the scene file loaded with the spec's overrides.
pub enum Scene<'a> {
    /// Loaded and checked by the plan.
    Planned(&'a LoadedScene),
    /// To load from this file.
    File(&'a Path),
}

/// Run one job here: load its scene unless the plan did, run it into its
/// folder and take the strategy's quantities. A panic inside is caught and
/// recorded as the run's failure; CPU time is that of the threads of the
/// rayon pool the job runs on ([`cpu::pool_seconds`]).
pub fn run_job(
    scene: Scene<'_>,
    spec: &JobSpec,
    progress: Progress,
    clock: Instant,
    extract: &Extract<'_>,
) -> Record {
    let started_s = clock.elapsed().as_secs_f64();
    let cpu0 = cpu::pool_seconds();
    let wall = Instant::now();
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let owned;
        let loaded = match scene {
            Scene::Planned(l) => l,
            Scene::File(path) => {
                owned = scene::load(path, &spec.sets).map_err(|e| e.to_string())?;
                &owned
            }
        };
        let options = RunOptions {
            out: spec.out.clone(),
            progress,
        };
        let result = crate::run::run(loaded, &options).map_err(|e| e.to_string())?;
        extract(&result)
    }))
    .unwrap_or_else(|panic| Err(format!("the run panicked: {}", panic_message(&panic))));
    Record {
        label: spec.label.clone(),
        outcome,
        cpu_s: (cpu::pool_seconds() - cpu0).max(0.0),
        wall_s: wall.elapsed().as_secs_f64(),
        started_s,
    }
}

/// The text of a caught panic.
pub fn panic_message(panic: &(dyn std::any::Any + Send)) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| (*s).to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown cause".into())
}

/// Indices of `jobs`, largest [`JobSpec::estimate`] first (stable).
pub fn largest_first(jobs: &[JobSpec]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by(|&a, &b| jobs[b].estimate.total_cmp(&jobs[a].estimate));
    order
}

/// An executor with the batch's journal and clock: what a strategy runs its
/// jobs on.
pub struct Engine<'a> {
    executor: &'a dyn Executor,
    journal: Option<journal::Journal>,
    clock: Instant,
}

impl std::fmt::Debug for Engine<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Engine")
            .field("threads", &self.executor.threads())
            .field("journal", &self.journal)
            .finish_non_exhaustive()
    }
}

impl<'a> Engine<'a> {
    /// An engine on `executor`, journalling into `journal` when given; its
    /// clock starts now.
    pub fn new(executor: &'a dyn Executor, journal: Option<journal::Journal>) -> Self {
        Self {
            executor,
            journal,
            clock: Instant::now(),
        }
    }

    /// When the batch started (records' `started_s` count from it).
    pub fn clock(&self) -> Instant {
        self.clock
    }

    /// Worker threads of each run.
    pub fn threads(&self) -> usize {
        self.executor.threads()
    }

    /// Run `jobs`: those the journal holds finished are read back (`done`
    /// is told with `true`), the others run on the executor and are
    /// journalled as each ends (`done` told with `false`). The records come
    /// back in the order of `jobs`; a job the executor lost is a failed
    /// record.
    ///
    /// # Errors
    /// The executor cannot run; a record cannot be journalled.
    pub fn run(
        &self,
        jobs: &[JobSpec],
        work: &Work<'_>,
        done: &mut dyn FnMut(usize, &Record, bool),
    ) -> Result<Vec<Record>, BatchError> {
        let mut records: Vec<Option<Record>> = vec![None; jobs.len()];
        let mut todo = Vec::new();
        for (i, job) in jobs.iter().enumerate() {
            match self.journal.as_ref().and_then(|j| j.finished(job)) {
                Some(r) => {
                    done(i, &r, true);
                    records[i] = Some(r);
                }
                None => todo.push(i),
            }
        }
        let pending: Vec<JobSpec> = todo.iter().map(|&i| jobs[i].clone()).collect();
        let mut failed_journal = None;
        self.executor.run(
            &pending,
            &|k, spec| work(todo[k], spec),
            &mut |k, record| {
                let i = todo[k];
                if let Some(j) = &self.journal
                    && let Err(e) = j.record(&jobs[i], &record)
                {
                    failed_journal.get_or_insert(e);
                }
                done(i, &record, false);
                records[i] = Some(record);
            },
        )?;
        if let Some(e) = failed_journal {
            return Err(e);
        }
        Ok(records
            .into_iter()
            .zip(jobs)
            .map(|(r, job)| {
                r.unwrap_or_else(|| {
                    Record::failed(job, "the executor lost the run (no record came back)")
                })
            })
            .collect())
    }
}

/// The expected run time of a planned scene (s, [`scene::estimate`]):
/// what [`JobSpec::estimate`] orders by. A scene whose mesh is a file
/// counts as one element.
pub fn estimate_s(loaded: &LoadedScene) -> f64 {
    use crate::scene::estimate::{MeshSize, estimate};
    let size = MeshSize::of_spec(&loaded.scene).unwrap_or(MeshSize::NONE);
    estimate(&loaded.scene, size).run_time_s
}

/// Make `out` ready for a batch of `owner` and open its journal for
/// `context`: a folder whose journal is of this very batch is resumed
/// (nothing is removed); with `fresh` (`--fresh`, or `--force`) what
/// formsim wrote there, the journal too, is removed first; otherwise a
/// folder with results is refused as for one run.
///
/// # Errors
/// As [`crate::run::out_dir::prepare`]; the folder holds the journal of
/// another batch (the message says what differs and to pass `--fresh`).
pub fn prepare(
    out: &Path,
    owner: crate::run::out_dir::Owner<'_>,
    fresh: bool,
    context: &journal::Context,
) -> Result<journal::Journal, BatchError> {
    if fresh || !journal::exists(out) {
        crate::run::out_dir::prepare(out, owner, fresh)?;
        journal::remove(out)?;
    }
    journal::Journal::open(out, context)
}
