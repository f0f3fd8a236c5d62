//! The MPI executor under a real `mpirun` (Open MPI), on jobs that sleep
//! instead of forming: every job runs once, the largest start first, rank 0
//! works too, a panic is a failed record, and a worker killed mid-run.
//!
//! Each test starts `mpirun -n 3 --oversubscribe` on this very test binary
//! with `--ignored --exact mpi_child`: the ignored test `mpi_child` is the
//! MPI program (its case in FORMSIM_MPI_CASE); rank 0 appends each record,
//! as it arrives, to the file FORMSIM_MPI_JOURNAL (as the batch journal
//! does), one JSON line each.
#![cfg(feature = "mpi")]

use formsim::batch::mpi::world;
use formsim::batch::{Executor, JobSpec, Record};
use serde_json::{Value, json};
use std::io::Write;
use std::path::Path;
use std::process::{Command, Output};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

/// Seconds since the epoch: start times comparable across the ranks of
/// one machine.
fn now_s() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}

/// Eight jobs of 0.3 s to 1.0 s, estimates in scrambled order; in the case
/// `panic` the job `j3` panics, in the case `kill` the first job of rank 1
/// writes its pid and label to FORMSIM_MPI_PID and sleeps until killed.
fn jobs() -> Vec<JobSpec> {
    [4.0, 2.0, 7.0, 1.0, 5.0, 8.0, 3.0, 6.0]
        .iter()
        .enumerate()
        .map(|(i, &e)| JobSpec {
            label: format!("j{i}"),
            sets: Vec::new(),
            out: format!("j{i}").into(),
            estimate: e,
        })
        .collect()
}

fn work(case: &str, spec: &JobSpec) -> Record {
    let started = now_s();
    let pid = std::process::id();
    if case == "panic" && spec.label == "j3" {
        panic!("boom in {}", spec.label);
    }
    let path = std::env::var("FORMSIM_MPI_PID").unwrap();
    let rank = std::env::var("OMPI_COMM_WORLD_RANK").unwrap();
    if case == "kill" && rank == "1" && !Path::new(&path).exists() {
        std::fs::write(&path, format!("{pid} {}", spec.label)).unwrap();
        std::thread::sleep(Duration::from_secs(120));
    }
    std::thread::sleep(Duration::from_secs_f64(0.1 * spec.estimate + 0.2));
    Record {
        label: spec.label.clone(),
        outcome: Ok(json!({"pid": pid, "started": started, "estimate": spec.estimate})),
        cpu_s: 0.0,
        wall_s: 0.0,
        started_s: 0.0,
    }
}

/// The MPI program (run by `mpirun`, never on its own).
#[test]
#[ignore = "the MPI program of the other tests, run by mpirun"]
fn mpi_child() {
    let case = std::env::var("FORMSIM_MPI_CASE").unwrap();
    let w = world().unwrap().expect("started by mpirun");
    let work = |_: usize, s: &JobSpec| work(&case, s);
    if w.rank() > 0 {
        w.serve(1, &work).unwrap();
        return;
    }
    let mut exec = w.executor(1, true);
    exec.silence_limit = Duration::from_secs(3);
    let path = std::env::var("FORMSIM_MPI_JOURNAL").unwrap();
    let mut journal = std::fs::File::create(path).unwrap();
    let jobs = jobs();
    exec.run(&jobs, &work, &mut |i, r| {
        let line = json!({"index": i, "record": r, "rank0_pid": std::process::id()});
        writeln!(journal, "{line}").unwrap();
        journal.flush().unwrap();
    })
    .unwrap();
}

/// `mpirun -n 3` (`extra` options first) on `mpi_child` with `case`;
/// returns its output and the journal's lines.
fn mpirun(case: &str, extra: &[&str], dir: &Path, during: impl FnOnce()) -> (Output, Vec<Value>) {
    let journal = dir.join("journal.jsonl");
    let child = Command::new("mpirun")
        .args(extra)
        .args(["-n", "3", "--oversubscribe"])
        .arg(std::env::current_exe().unwrap())
        .args(["--ignored", "--exact", "mpi_child", "--test-threads", "1"])
        .env("FORMSIM_MPI_CASE", case)
        .env("FORMSIM_MPI_JOURNAL", &journal)
        .env("FORMSIM_MPI_PID", dir.join("pid"))
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("mpirun (Open MPI) on the PATH");
    during();
    let output = child.wait_with_output().unwrap();
    let lines = std::fs::read_to_string(&journal)
        .unwrap_or_default()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    (output, lines)
}

fn ok_outcome(line: &Value) -> Option<&Value> {
    line["record"]["outcome"].get("Ok")
}

#[test]
fn every_job_runs_once_largest_first_on_every_rank() {
    let dir = tempfile::tempdir().unwrap();
    let (o, lines) = mpirun("order", &[], dir.path(), || {});
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut indices: Vec<u64> = lines.iter().map(|l| l["index"].as_u64().unwrap()).collect();
    indices.sort_unstable();
    assert_eq!(indices, (0..8).collect::<Vec<u64>>());
    for l in &lines {
        let i = l["index"].as_u64().unwrap();
        assert_eq!(l["record"]["label"], format!("j{i}"));
    }
    // Three ranks ran jobs, rank 0 among them.
    let mut pids: Vec<u64> = lines
        .iter()
        .map(|l| ok_outcome(l).unwrap()["pid"].as_u64().unwrap())
        .collect();
    pids.sort_unstable();
    pids.dedup();
    assert_eq!(pids.len(), 3, "{pids:?}");
    assert!(pids.contains(&lines[0]["rank0_pid"].as_u64().unwrap()));
    // The three largest (8, 7, 6) started first.
    let mut starts: Vec<(f64, f64)> = lines
        .iter()
        .map(|l| {
            let v = ok_outcome(l).unwrap();
            (
                v["started"].as_f64().unwrap(),
                v["estimate"].as_f64().unwrap(),
            )
        })
        .collect();
    starts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut first: Vec<f64> = starts[..3].iter().map(|s| s.1).collect();
    first.sort_by(f64::total_cmp);
    assert_eq!(first, [6.0, 7.0, 8.0]);
}

#[test]
fn a_panic_on_any_rank_is_that_run_s_failed_record() {
    let dir = tempfile::tempdir().unwrap();
    let (o, lines) = mpirun("panic", &[], dir.path(), || {});
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(lines.len(), 8);
    for l in &lines {
        let err = l["record"]["outcome"].get("Err");
        if l["index"] == 3 {
            assert_eq!(err.unwrap(), "the run panicked: boom in j3");
        } else {
            assert!(err.is_none(), "{l}");
        }
    }
}

/// Wait for rank 1's first job to write its pid, then `kill -9` that
/// process; returns the job's label.
fn kill_rank_1(dir: &Path) -> String {
    let path = dir.join("pid");
    let t = Instant::now();
    let text = loop {
        if let Ok(text) = std::fs::read_to_string(&path)
            && text.contains(' ')
        {
            break text;
        }
        assert!(t.elapsed().as_secs() < 60, "rank 1 never started a job");
        std::thread::sleep(Duration::from_millis(20));
    };
    let (pid, label) = text.split_once(' ').unwrap();
    let killed = Command::new("kill").args(["-9", pid]).status().unwrap();
    assert!(killed.success());
    label.to_string()
}

/// A worker rank killed mid-run under a plain `mpirun`: Open MPI ends the
/// job, and the journal holds every record that arrived before.
#[test]
fn a_killed_worker_ends_a_plain_mpirun_and_the_journal_keeps_what_finished() {
    let dir = tempfile::tempdir().unwrap();
    let mut killed = String::new();
    let (o, lines) = mpirun("kill", &[], dir.path(), || killed = kill_rank_1(dir.path()));
    assert!(!o.status.success());
    assert!(lines.len() < 8, "{lines:?}");
    eprintln!(
        "plain mpirun: {:?}, {} records journalled",
        o.status,
        lines.len()
    );
    for l in &lines {
        assert!(ok_outcome(l).is_some(), "{l}");
        assert_ne!(l["record"]["label"], killed.as_str());
    }
}

/// The same under `mpirun --enable-recovery`: rank 0 counts the silent
/// worker lost, records its run as failed, and finishes the others.
#[test]
fn a_killed_worker_under_enable_recovery_fails_only_its_run() {
    let dir = tempfile::tempdir().unwrap();
    let t = Instant::now();
    let mut killed = String::new();
    let (o, lines) = mpirun("kill", &["--enable-recovery"], dir.path(), || {
        killed = kill_rank_1(dir.path())
    });
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(lines.len(), 8, "{stderr}");
    for l in &lines {
        let err = l["record"]["outcome"].get("Err");
        if l["record"]["label"] == killed.as_str() {
            let m = err.unwrap().as_str().unwrap();
            assert!(m.contains("went silent for 3 s"), "{m}");
        } else {
            assert!(err.is_none(), "{l}");
        }
    }
    // Measured with Open MPI 4.1.4: mpirun exits 0 (the lost run is the
    // batch's to report).
    assert!(o.status.success(), "{stderr}");
    eprintln!("--enable-recovery: {:?} after {:?}", o.status, t.elapsed());
}
