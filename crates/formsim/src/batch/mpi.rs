//! The MPI executor: a batch spread over the ranks of an MPI job (cargo
//! feature `mpi`; docs/scale-out.md).
//!
//! Every rank starts the same `formsim` command. [`world`] initialises MPI
//! only when a launcher started the process. Rank 0 plans the batch, keeps
//! its journal and reports, and runs [`MpiExecutor`]; every other rank calls
//! [`World::serve`], which runs the job specs rank 0 sends until rank 0
//! says stop (when its [`World`] is dropped).
//!
//! Rank 0 works too: a thread of its own takes jobs from the same queue
//! (largest [`JobSpec::estimate`] first) as the ranks that ask for work,
//! while the main thread (the only one that calls MPI: threading level
//! `Funneled`) hands specs out and takes records in. It polls with a
//! [`POLL`] sleep between empty looks, since Open MPI's blocking receive
//! spins on its core and would take it from the local runs.
//!
//! Messages are serde_json bytes: a job `(index, spec)` to a worker, a
//! record `(index, record)` back, and while a job runs, a sign of life
//! every [`ALIVE_EVERY`]. A panic in a run is caught on the rank that runs
//! it and comes back as a failed record. A rank that dies: under a plain
//! `mpirun`, Open MPI ends the whole job (the journal keeps every record
//! that arrived, so the same command resumes what is missing). Under
//! `mpirun --enable-recovery` the others go on; rank 0 then counts a
//! worker silent for [`MpiExecutor::silence_limit`] as lost, records its
//! run as failed, gives it no more work and finishes the batch on the
//! others.
//!
//! How a command uses it (`main.rs`, for `study`; `compare` and `identify`
//! alike, with their own quantities): every rank parses and plans (bad
//! input fails on every rank alike, before MPI starts), then
//!
//! ```ignore
//! let world = formsim::batch::mpi::world()?; // None outside a launcher
//! if let Some(w) = &world && w.rank() > 0 {
//!     // A worker: no folder, journal or report; the runs only.
//!     let clock = std::time::Instant::now();
//!     let extract = |r: &RunResult| {
//!         let v = study::VariantRun::of(r, &quantities)?;
//!         serde_json::to_value(v).map_err(|e| e.to_string())
//!     };
//!     w.serve(threads, &|_, spec| {
//!         batch::run_job(Scene::File(&args.scene), spec, Progress::Hidden, clock, &extract)
//!     })?;
//!     return Ok(ExitCode::SUCCESS);
//! }
//! let mpi = world.as_ref().map(|w| w.executor(threads, true));
//! let executor: &dyn Executor = match &mpi { Some(m) => m, None => &local };
//! // … the engine on `executor`, as without MPI; `world` is dropped last
//! // (rank 0 then tells the workers to stop), on errors too.
//! ```
//!
//! A command that does not share its runs so (and every command of a build
//! without the feature) calls [`super::launcher::single_copy`] instead,
//! which refuses to run as one of several copies.

use super::local::pool;
use super::{BatchError, Executor, JobSpec, Record, Work, largest_first, panic_message};
use mpi::Threading;
use mpi::environment::Universe;
use mpi::point_to_point::{Destination, MatchedReceiveVec, Source};
use mpi::topology::{Communicator, SimpleCommunicator};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError, mpsc};
use std::time::{Duration, Instant};

/// Rank 0 → worker: `(index, spec)`.
const TAG_JOB: i32 = 1;
/// Rank 0 → worker: no more work, return from [`World::serve`].
const TAG_STOP: i32 = 2;
/// Worker → rank 0: `(index, record)`.
const TAG_RECORD: i32 = 3;
/// Worker → rank 0: the job still runs.
const TAG_ALIVE: i32 = 4;

/// Sleep between two looks that found no message.
pub const POLL: Duration = Duration::from_millis(2);
/// How often a worker says that its job still runs.
pub const ALIVE_EVERY: Duration = Duration::from_secs(1);
/// Default of [`MpiExecutor::silence_limit`].
pub const SILENCE_LIMIT: Duration = Duration::from_secs(30);

/// This process's place in an MPI job: its rank, the job's size, and MPI
/// itself (finalised when the `World` is dropped, after rank 0 has told
/// every worker to stop).
pub struct World {
    rank: usize,
    size: usize,
    /// Workers rank 0 still counts on (index: rank).
    alive: Mutex<Vec<bool>>,
    /// Dropped last: `MPI_Finalize`.
    universe: Option<Universe>,
}

impl std::fmt::Debug for World {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("World")
            .field("rank", &self.rank)
            .field("size", &self.size)
            .finish_non_exhaustive()
    }
}

/// MPI's world when a launcher (`mpirun`, `mpiexec`, `srun`) started this
/// process, `Ok(None)` otherwise (and MPI is not touched).
///
/// # Errors
/// MPI cannot be initialised with the threading level `Funneled`; the
/// launcher started several processes that MPI does not see as one job
/// (e.g. `srun` without `--mpi=pmix`).
pub fn world() -> Result<Option<World>, BatchError> {
    let Some(expected) = super::launcher::launched() else {
        return Ok(None);
    };
    let err = |m: String| Err(BatchError::Executor(m));
    if let Some(n) = super::launcher::srun_without_mpi(&|v| std::env::var(v).ok()) {
        return err(format!(
            "srun started {n} tasks with no MPI plugin, so MPI cannot join them: pass \
             --mpi=pmix (or set MpiDefault=pmix in slurm.conf)"
        ));
    }
    let Some((universe, threading)) = mpi::initialize_with_threading(Threading::Funneled) else {
        return err("MPI is already initialised".into());
    };
    if threading < Threading::Funneled {
        return err(format!(
            "MPI offers the threading level {threading:?}; formsim needs Funneled"
        ));
    }
    let comm = universe.world();
    let (rank, size) = (comm.rank() as usize, comm.size() as usize);
    if let Some(n) = expected
        && n != size
    {
        return err(format!(
            "the launcher started {n} processes but MPI sees {size} (srun: pass --mpi=pmix)"
        ));
    }
    Ok(Some(World {
        rank,
        size,
        alive: Mutex::new(vec![true; size]),
        universe: Some(universe),
    }))
}

impl World {
    /// This process's rank (0: the one that plans and reports).
    pub fn rank(&self) -> usize {
        self.rank
    }

    /// MPI's world communicator.
    fn comm(&self) -> SimpleCommunicator {
        SimpleCommunicator::world()
    }

    /// Which workers rank 0 still counts on (index: rank).
    fn alive(&self) -> std::sync::MutexGuard<'_, Vec<bool>> {
        self.alive.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Processes in the job.
    pub fn size(&self) -> usize {
        self.size
    }

    /// The executor of rank 0: runs of `threads` threads each, one per rank
    /// at a time, and with `local` one more on rank 0 itself.
    pub fn executor(&self, threads: usize, local: bool) -> MpiExecutor<'_> {
        MpiExecutor {
            world: self,
            threads: threads.max(1),
            local,
            silence_limit: SILENCE_LIMIT,
            clock: Instant::now(),
        }
    }

    /// A worker's loop (ranks > 0): run each job rank 0 sends through
    /// `work` on a pool of `threads` threads and send the record back, until
    /// rank 0 says stop. A panic in `work` is the run's failed record.
    ///
    /// # Errors
    /// The thread pool cannot be made; a message cannot be read.
    pub fn serve(&self, threads: usize, work: &Work<'_>) -> Result<(), BatchError> {
        let pool = pool(threads)?;
        let comm = self.comm();
        let root = comm.process_at_rank(0);
        loop {
            let (bytes, status) = loop {
                match root.immediate_matched_probe() {
                    Some(m) => break m.matched_receive_vec::<u8>(),
                    None => std::thread::sleep(POLL),
                }
            };
            if status.tag() == TAG_STOP {
                return Ok(());
            }
            let (index, spec): (usize, JobSpec) = decode(&bytes, "a job spec from rank 0")?;
            let record = std::thread::scope(|s| {
                let run = s.spawn(|| pool.install(|| guarded(work, index, &spec)));
                let mut said = Instant::now();
                while !run.is_finished() {
                    std::thread::sleep(POLL);
                    if said.elapsed() >= ALIVE_EVERY {
                        root.send_with_tag(&[0u8][..], TAG_ALIVE);
                        said = Instant::now();
                    }
                }
                run.join()
                    .unwrap_or_else(|p| Record::failed(&spec, &panic_message(p.as_ref())))
            });
            root.send_with_tag(&encode(&(index, record))[..], TAG_RECORD);
        }
    }

    /// Tell every worker rank 0 counts on to stop (rank 0; once).
    fn stop_workers(&self) {
        let mut alive = self.alive();
        let comm = self.comm();
        for r in 1..self.size {
            if alive[r] {
                comm.process_at_rank(r as i32)
                    .send_with_tag(&[0u8][..], TAG_STOP);
                alive[r] = false;
            }
        }
    }
}

impl Drop for World {
    fn drop(&mut self) {
        if self.rank == 0 {
            self.stop_workers();
        }
        drop(self.universe.take());
    }
}

/// Rank 0's executor: hands jobs to the ranks as they become free, largest
/// first, and runs jobs itself on a thread of its own (`local`).
pub struct MpiExecutor<'w> {
    world: &'w World,
    threads: usize,
    local: bool,
    /// A worker whose job has not said it still runs for this long is
    /// counted lost (its run failed; no more work for it).
    pub silence_limit: Duration,
    /// Records run on other ranks start when they were handed out, on this
    /// clock (started when the executor was made).
    clock: Instant,
}

impl std::fmt::Debug for MpiExecutor<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MpiExecutor")
            .field("ranks", &self.world.size)
            .field("threads", &self.threads)
            .field("local", &self.local)
            .field("silence_limit", &self.silence_limit)
            .finish_non_exhaustive()
    }
}

/// What rank 0 knows of one worker during a batch.
#[derive(Clone, Copy)]
enum Worker {
    /// Waiting for a job.
    Idle,
    /// Running job `index` since `handed`; last heard of at `heard`.
    Busy {
        index: usize,
        handed: Instant,
        heard: Instant,
    },
    /// Lost, or not a worker (rank 0).
    Out,
}

impl Executor for MpiExecutor<'_> {
    fn run(
        &self,
        jobs: &[JobSpec],
        work: &Work<'_>,
        done: &mut dyn FnMut(usize, Record),
    ) -> Result<(), BatchError> {
        if self.world.rank != 0 {
            return Err(BatchError::Executor(format!(
                "the MPI executor runs on rank 0, not on rank {}",
                self.world.rank
            )));
        }
        let order = largest_first(jobs);
        let next = AtomicUsize::new(0);
        let stop = AtomicBool::new(false);
        let take = || {
            if stop.load(Ordering::Relaxed) {
                return None;
            }
            order.get(next.fetch_add(1, Ordering::Relaxed)).copied()
        };
        let pool = if self.local {
            Some(pool(self.threads)?)
        } else {
            None
        };
        let (tx, rx) = mpsc::channel::<(usize, Record)>();
        std::thread::scope(|s| {
            if let Some(pool) = &pool {
                let (take, tx) = (&take, tx);
                s.spawn(move || {
                    while let Some(i) = take() {
                        let record = pool.install(|| guarded(work, i, &jobs[i]));
                        if tx.send((i, record)).is_err() {
                            break;
                        }
                    }
                });
            } else {
                drop(tx);
            }
            let result = self.dispatch(jobs, &take, &rx, done);
            if result.is_err() {
                stop.store(true, Ordering::Relaxed);
            }
            result
        })
    }

    fn threads(&self) -> usize {
        self.threads
    }
}

impl MpiExecutor<'_> {
    /// Runs at a time: one per worker rank, and one on rank 0 with `local`.
    pub fn ranks(&self) -> usize {
        self.world.size - 1 + usize::from(self.local)
    }

    /// Rank 0's main loop: hand out, take in, count the silent as lost,
    /// until every job has its record.
    fn dispatch(
        &self,
        jobs: &[JobSpec],
        take: &dyn Fn() -> Option<usize>,
        local: &mpsc::Receiver<(usize, Record)>,
        done: &mut dyn FnMut(usize, Record),
    ) -> Result<(), BatchError> {
        let w = self.world;
        let mut workers: Vec<Worker> = {
            let alive = w.alive();
            (0..w.size)
                .map(|r| match r > 0 && alive[r] {
                    true => Worker::Idle,
                    false => Worker::Out,
                })
                .collect()
        };
        let comm = w.comm();
        let mut left = jobs.len();
        while left > 0 {
            let mut busy = self.hand_out(jobs, take, &mut workers);
            while let Ok((i, record)) = local.try_recv() {
                done(i, record);
                left -= 1;
                busy = true;
            }
            while let Some(m) = comm.any_process().immediate_matched_probe() {
                let (bytes, status) = m.matched_receive_vec::<u8>();
                busy = true;
                let r = status.source_rank() as usize;
                if let Some((i, record)) = self.take_in(r, status.tag(), &bytes, &mut workers)? {
                    done(i, record);
                    left -= 1;
                }
            }
            for (i, record) in self.count_the_silent(jobs, &mut workers) {
                done(i, record);
                left -= 1;
            }
            if !self.local && workers.iter().all(|k| matches!(k, Worker::Out)) {
                while let Some(i) = take() {
                    done(i, Record::failed(&jobs[i], "no rank is left to run it"));
                    left -= 1;
                }
            }
            if !busy {
                std::thread::sleep(POLL);
            }
        }
        Ok(())
    }

    /// Give each idle worker the next job; whether any was handed out.
    fn hand_out(
        &self,
        jobs: &[JobSpec],
        take: &dyn Fn() -> Option<usize>,
        workers: &mut [Worker],
    ) -> bool {
        let mut handed = false;
        let comm = self.world.comm();
        for (r, k) in workers.iter_mut().enumerate() {
            if !matches!(k, Worker::Idle) {
                continue;
            }
            let Some(index) = take() else { break };
            let bytes = encode(&(index, &jobs[index]));
            comm.process_at_rank(r as i32)
                .send_with_tag(&bytes[..], TAG_JOB);
            let now = Instant::now();
            *k = Worker::Busy {
                index,
                handed: now,
                heard: now,
            };
            handed = true;
        }
        handed
    }

    /// A message from worker `r`: a record (returned, timed on this
    /// executor's clock) or a sign of life.
    fn take_in(
        &self,
        r: usize,
        tag: i32,
        bytes: &[u8],
        workers: &mut [Worker],
    ) -> Result<Option<(usize, Record)>, BatchError> {
        let Worker::Busy { index, handed, .. } = workers[r] else {
            // A worker counted lost that speaks again: its run is already
            // recorded as failed.
            return Ok(None);
        };
        if tag == TAG_ALIVE {
            workers[r] = Worker::Busy {
                index,
                handed,
                heard: Instant::now(),
            };
            return Ok(None);
        }
        let (i, mut record): (usize, Record) = decode(bytes, &format!("a record from rank {r}"))?;
        if i != index {
            return Err(BatchError::Executor(format!(
                "rank {r} sent the record of job {i} while running job {index}"
            )));
        }
        record.started_s = handed.duration_since(self.clock).as_secs_f64();
        workers[r] = Worker::Idle;
        Ok(Some((i, record)))
    }

    /// Workers silent beyond the limit: lost; their runs' failed records.
    fn count_the_silent(&self, jobs: &[JobSpec], workers: &mut [Worker]) -> Vec<(usize, Record)> {
        let mut lost = Vec::new();
        for (r, k) in workers.iter_mut().enumerate() {
            if let Worker::Busy { index, heard, .. } = *k
                && heard.elapsed() > self.silence_limit
            {
                *k = Worker::Out;
                self.world.alive()[r] = false;
                let why = format!(
                    "rank {r} went silent for {:.0} s while running it (the process died?)",
                    self.silence_limit.as_secs_f64()
                );
                lost.push((index, Record::failed(&jobs[index], &why)));
            }
        }
        lost
    }
}

/// `work` on job `i`, a panic caught as the run's failure.
fn guarded(work: &Work<'_>, i: usize, spec: &JobSpec) -> Record {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| work(i, spec))).unwrap_or_else(|p| {
        Record::failed(
            spec,
            &format!("the run panicked: {}", panic_message(p.as_ref())),
        )
    })
}

fn encode<T: serde::Serialize>(value: &T) -> Vec<u8> {
    // Specs and records are plain data (strings, numbers, JSON values).
    serde_json::to_vec(value).unwrap_or_default()
}

fn decode<T: serde::de::DeserializeOwned>(bytes: &[u8], what: &str) -> Result<T, BatchError> {
    serde_json::from_slice(bytes).map_err(|e| BatchError::Executor(format!("{what}: {e}")))
}
