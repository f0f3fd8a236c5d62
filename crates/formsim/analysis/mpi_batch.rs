//! Throughput and overhead of the MPI executor (docs/scale-out.md), under
//! `mpirun` (cargo feature `mpi`):
//!
//! - `mpi_batch cup N OUT`: N runs of the coarse square cup
//!   (`scenes/square-cup.toml`, 10 × 10 elements, one thread each) into
//!   `OUT/run-K`, spread over the ranks (rank 0 works too); prints the
//!   batch's wall seconds and runs per hour.
//! - `mpi_batch empty N`: N jobs that do nothing, handed to one worker
//!   (rank 0 only dispatches); prints the hand-out, serialisation and
//!   return time per job.
//! - `mpi_batch wait block|poll`: rank 1 sends one message after 3 s; rank 0
//!   waits for it in a blocking receive (`block`) or polling with
//!   [`formsim::batch::mpi::POLL`] sleeps (`poll`, as the executor does);
//!   prints rank 0's CPU seconds while it waited.
//!
//! Run from the repository's root, e.g.
//! `mpirun -n 2 target/release/examples/mpi_batch cup 8 /tmp/cups`.

use formsim::batch::mpi::world;
use formsim::batch::{Executor, JobSpec, Record};
use formsim::run::{Progress, RunOptions, run};
use std::path::PathBuf;
use std::time::Instant;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage =
        "usage: mpi_batch cup N OUT | mpi_batch empty N | mpi_batch wait block|poll (under mpirun)";
    if let [m, how] = args.as_slice()
        && m == "wait"
    {
        return wait(how == "poll");
    }
    let (mode, n) = match args.as_slice() {
        [m, n, ..] => (
            m.as_str(),
            n.parse::<usize>().map_err(|e| format!("N: {n}: {e}"))?,
        ),
        _ => return Err(usage.into()),
    };
    let out = PathBuf::from(args.get(2).map_or("/tmp/mpi_batch", String::as_str));
    let w = world()
        .map_err(|e| e.to_string())?
        .ok_or("not under mpirun")?;
    let cup = |_: usize, s: &JobSpec| -> Record {
        let wall = Instant::now();
        let outcome = formsim::scene::load("scenes/square-cup.toml".as_ref(), &s.sets)
            .map_err(|e| e.to_string())
            .and_then(|loaded| {
                let options = RunOptions {
                    out: s.out.clone(),
                    progress: Progress::Hidden,
                };
                run(&loaded, &options).map_err(|e| e.to_string())
            })
            .map(|r| serde_json::json!(r.summary.increments));
        record(s, outcome, wall.elapsed().as_secs_f64())
    };
    let empty = |_: usize, s: &JobSpec| record(s, Ok(serde_json::Value::Null), 0.0);
    let work: &formsim::batch::Work<'_> = if mode == "cup" { &cup } else { &empty };
    if w.rank() > 0 {
        return w.serve(1, work).map_err(|e| e.to_string());
    }
    let jobs: Vec<JobSpec> = (0..n)
        .map(|k| JobSpec {
            label: format!("run-{k}"),
            sets: vec!["blank.mesh.divisions=10".into()],
            out: out.join(format!("run-{k}")),
            estimate: 1.0,
        })
        .collect();
    let exec = w.executor(1, mode == "cup");
    let t = Instant::now();
    let mut failed = 0;
    exec.run(&jobs, work, &mut |_, r| {
        failed += usize::from(r.outcome.is_err())
    })
    .map_err(|e| e.to_string())?;
    let wall = t.elapsed().as_secs_f64();
    match mode {
        "cup" => println!(
            "{n} runs on {} rank(s): {wall:.2} s, {:.0} runs per hour, {failed} failed",
            w.size(),
            n as f64 * 3600.0 / wall
        ),
        _ => println!(
            "{n} empty jobs to {} worker(s): {:.3} ms per job",
            w.size() - 1,
            1e3 * wall / n as f64
        ),
    }
    Ok(())
}

/// Rank 0's CPU seconds while it waits 3 s for rank 1's message.
fn wait(poll: bool) -> Result<(), String> {
    use mpi::point_to_point::{Destination, MatchedReceiveVec, Source};
    use mpi::topology::{Communicator, SimpleCommunicator};
    let w = world()
        .map_err(|e| e.to_string())?
        .ok_or("not under mpirun")?;
    let comm = SimpleCommunicator::world();
    if w.rank() == 1 {
        std::thread::sleep(std::time::Duration::from_secs(3));
        comm.process_at_rank(0).send(&[1u8][..]);
        return Ok(());
    }
    if w.rank() > 1 {
        return Ok(());
    }
    let cpu = cpu_time::ProcessTime::now();
    let wall = Instant::now();
    let from = comm.process_at_rank(1);
    if poll {
        loop {
            if let Some(m) = from.immediate_matched_probe() {
                m.matched_receive_vec::<u8>();
                break;
            }
            std::thread::sleep(formsim::batch::mpi::POLL);
        }
    } else {
        from.receive_vec::<u8>();
    }
    println!(
        "{}: rank 0 waited {:.2} s wall, {:.2} s CPU",
        if poll { "polling" } else { "blocking receive" },
        wall.elapsed().as_secs_f64(),
        cpu.elapsed().as_secs_f64()
    );
    Ok(())
}

fn record(s: &JobSpec, outcome: Result<serde_json::Value, String>, wall_s: f64) -> Record {
    Record {
        label: s.label.clone(),
        outcome,
        cpu_s: 0.0,
        wall_s,
        started_s: 0.0,
    }
}
