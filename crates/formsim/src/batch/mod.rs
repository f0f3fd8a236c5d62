//! The batch engine's contract (what `compare`, `study` and `identify` share
//! when they run many scenes): job specs go to an [`Executor`], records come
//! back. The MPI executor (cargo feature `mpi`) is [`mpi`].

pub mod launcher;
#[cfg(feature = "mpi")]
pub mod mpi;

use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// One run to make: the scene's overrides and where its files go.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JobSpec {
    /// The run's label.
    pub label: String,
    /// Overrides of the scene (`KEY=VALUE`), in order.
    pub sets: Vec<String>,
    /// The run's output folder.
    pub out: PathBuf,
    /// Relative cost of the run: larger runs start first.
    pub estimate: f64,
}

/// What a finished run reports back (small: quantities, not the fields).
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

/// What goes wrong with a batch itself (a run's failure is a [`Record`]).
#[derive(Debug, thiserror::Error)]
pub enum BatchError {
    /// The executor cannot run the batch (no thread pool, MPI failure).
    #[error("executor: {0}")]
    Executor(String),
}

/// Runs one job in this process: `(index in the batch, spec) → record`.
pub type Work<'a> = dyn Fn(usize, &JobSpec) -> Record + Sync + 'a;

/// Runs a batch of jobs.
pub trait Executor: Sync {
    /// Run `jobs` through `work`; `done` is called on the calling thread as
    /// each record arrives, in completion order, with the job's index.
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
