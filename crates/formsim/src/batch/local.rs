//! The local executor: `--jobs N` runs at a time in this process, each on
//! its own rayon pool of `--threads T` threads.

use super::{BatchError, Executor, JobSpec, Record, Work};
use std::collections::VecDeque;
use std::sync::Mutex;

/// Runs jobs in this process, [`Local::jobs`] at a time, the largest
/// [`JobSpec::estimate`] first (equal estimates in the batch's order).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Local {
    /// Runs at a time (≥ 1).
    pub jobs: usize,
    /// Threads of each run (≥ 1).
    pub threads: usize,
}

impl Local {
    /// `jobs` and `threads` as asked; what is not asked fills the machine's
    /// `cores` (`N × T = cores`, at least 1 each); neither asked: one run
    /// per core up to the batch's `runs`, the cores shared among them.
    pub fn sized(jobs: Option<usize>, threads: Option<usize>, cores: usize, runs: usize) -> Self {
        let cores = cores.max(1);
        let (jobs, threads) = match (jobs, threads) {
            (Some(n), Some(t)) => (n, t),
            (Some(n), None) => (n, cores / n.max(1)),
            (None, Some(t)) => (cores / t.max(1), t),
            (None, None) => {
                let n = runs.clamp(1, cores);
                (n, cores / n)
            }
        };
        Self {
            jobs: jobs.max(1),
            threads: threads.max(1),
        }
    }
}

/// A rayon pool of `threads` threads for the runs of one worker.
pub(crate) fn pool(threads: usize) -> Result<rayon::ThreadPool, BatchError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| BatchError::Executor(format!("a pool of {threads} threads: {e}")))
}

impl Executor for Local {
    fn run(
        &self,
        jobs: &[JobSpec],
        work: &Work<'_>,
        done: &mut dyn FnMut(usize, Record),
    ) -> Result<(), BatchError> {
        let queue: Mutex<VecDeque<usize>> = Mutex::new(super::largest_first(jobs).into());
        let next = || {
            queue
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .pop_front()
        };
        let workers = self.jobs.min(jobs.len());
        let mut pools = Vec::with_capacity(workers);
        for _ in 0..workers {
            pools.push(pool(self.threads)?);
        }
        let (tx, rx) = std::sync::mpsc::channel::<(usize, Record)>();
        std::thread::scope(|s| {
            for pool in &pools {
                let tx = tx.clone();
                let next = &next;
                s.spawn(move || {
                    while let Some(i) = next() {
                        let record = pool.install(|| work(i, &jobs[i]));
                        if tx.send((i, record)).is_err() {
                            break;
                        }
                    }
                });
            }
            drop(tx);
            for (i, record) in rx {
                done(i, record);
            }
        });
        Ok(())
    }

    fn threads(&self) -> usize {
        self.threads
    }
}

/// A [`Local`] sized for each batch by [`Local::sized`]: a batch of one
/// run gets every core, a batch of many runs one core each (what
/// `identify`'s evaluations run on).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PerBatch {
    /// Runs at a time, if asked (`--jobs`).
    pub jobs: Option<usize>,
    /// Threads of each run, if asked (`--threads`).
    pub threads: Option<usize>,
    /// The machine's cores.
    pub cores: usize,
}

impl PerBatch {
    /// The local executor for a batch of `runs`.
    pub fn for_runs(&self, runs: usize) -> Local {
        Local::sized(self.jobs, self.threads, self.cores, runs)
    }
}

impl Executor for PerBatch {
    fn run(
        &self,
        jobs: &[JobSpec],
        work: &Work<'_>,
        done: &mut dyn FnMut(usize, Record),
    ) -> Result<(), BatchError> {
        self.for_runs(jobs.len()).run(jobs, work, done)
    }

    fn threads(&self) -> usize {
        self.threads.unwrap_or(self.cores)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(label: &str) -> JobSpec {
        JobSpec {
            label: label.into(),
            sets: Vec::new(),
            out: label.into(),
            estimate: 1.0,
        }
    }

    #[test]
    fn sizes_fill_the_cores() {
        assert_eq!(
            Local::sized(None, None, 8, 1),
            Local {
                jobs: 1,
                threads: 8
            }
        );
        assert_eq!(
            Local::sized(None, None, 8, 99),
            Local {
                jobs: 8,
                threads: 1
            }
        );
        assert_eq!(
            Local::sized(Some(2), None, 8, 1),
            Local {
                jobs: 2,
                threads: 4
            }
        );
        assert_eq!(
            Local::sized(None, Some(4), 8, 1),
            Local {
                jobs: 2,
                threads: 4
            }
        );
        assert_eq!(
            Local::sized(Some(3), Some(3), 2, 1),
            Local {
                jobs: 3,
                threads: 3
            }
        );
        assert_eq!(
            Local::sized(Some(4), None, 2, 1),
            Local {
                jobs: 4,
                threads: 1
            }
        );
    }

    #[test]
    fn one_at_a_time_the_largest_estimate_runs_first() {
        let jobs: Vec<JobSpec> = [1.0, 3.0, 2.0, 3.0]
            .iter()
            .enumerate()
            .map(|(i, &e)| JobSpec {
                estimate: e,
                ..spec(&format!("j{i}"))
            })
            .collect();
        let exec = Local {
            jobs: 1,
            threads: 1,
        };
        let work = |_: usize, s: &JobSpec| Record::failed(s, "nothing to do");
        let mut order = Vec::new();
        exec.run(&jobs, &work, &mut |i, _| order.push(i)).unwrap();
        assert_eq!(order, [1, 3, 2, 0], "largest first, ties in order");
    }

    #[test]
    fn every_job_runs_once_on_a_pool_of_its_size() {
        let jobs: Vec<JobSpec> = (0..7).map(|i| spec(&format!("j{i}"))).collect();
        let exec = Local {
            jobs: 3,
            threads: 2,
        };
        let work = |i: usize, s: &JobSpec| Record {
            label: s.label.clone(),
            outcome: Ok(serde_json::json!([i, rayon::current_num_threads()])),
            cpu_s: 0.0,
            wall_s: 0.0,
            started_s: 0.0,
        };
        let mut seen = Vec::new();
        exec.run(&jobs, &work, &mut |i, r| seen.push((i, r)))
            .unwrap();
        seen.sort_by_key(|s| s.0);
        assert_eq!(seen.len(), 7);
        for (i, r) in &seen {
            assert_eq!(r.label, format!("j{i}"));
            assert_eq!(r.outcome, Ok(serde_json::json!([i, 2])));
        }
    }
}
