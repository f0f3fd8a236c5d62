//! Results are never lost: a run that blows up, is
//! interrupted or cannot write a frame still writes `summary.json` with its
//! status and cause, and the histories up to that moment, all finite.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The repository's root (`tests/common` has one too, beside helpers these
/// tests do not use).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The `formsim` binary run with `args`.
fn formsim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_formsim"))
        .args(args)
        .output()
        .expect("formsim runs")
}

/// Standard output then standard error, as text.
fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// The coarse square cup (10 × 10 quarter mesh, 3 ms draw).
const COARSE_CUP: [&str; 4] = [
    "--set",
    "blank.mesh.divisions=10",
    "--set",
    "steps[2].duration=3e-3",
];

fn summary(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json written");
    serde_json::from_str(&text).expect("summary.json is JSON")
}

/// The data rows of a history, every field parsed and finite.
fn finite_rows(path: &Path) -> usize {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let mut rows = 0;
    for line in text.lines().skip(1) {
        for field in line.split(',').filter(|f| !f.is_empty()) {
            let v: f64 = field.parse().unwrap_or_else(|e| panic!("{line}: {e}"));
            assert!(v.is_finite(), "{path:?}: {line}");
        }
        rows += 1;
    }
    rows
}

/// A punch driven 1e9 mm in 3 ms blows the blank up: the run stops at the
/// first non-finite value, names its quantity, element and step on one line
/// of standard error, exits non-zero, and writes `summary.json`
/// (`"status": "failed"` with the cause) and the finite histories so far.
#[test]
fn a_blow_up_is_reported_by_its_first_non_finite_value_and_keeps_the_histories() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let scene = root().join("scenes/square-cup.toml");
    let mut args = vec![
        "-q",
        "run",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend(COARSE_CUP);
    args.extend(["--set", "steps[2].motions[1].distance=1e9"]);
    let o = formsim(&args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    // The coarse mesh draws a set-up warning; the stop is one line.
    let errors: Vec<&str> = err.lines().filter(|l| !l.starts_with("warning:")).collect();
    assert_eq!(errors.len(), 1, "one line: {err}");
    assert!(errors[0].starts_with("error: run stopped at t = "), "{err}");
    assert!(
        err.contains("shell thickness (mm) of element") && err.contains("is NaN at step"),
        "{err}"
    );
    assert!(!err.contains(".csv"), "not a file's complaint: {err}");

    let s = summary(&out);
    assert_eq!(s["status"], "failed");
    let cause = s["cause"].as_str().unwrap();
    let step = s["increments"].as_u64().unwrap();
    assert!(
        cause.starts_with("shell thickness (mm) of element ")
            && cause.contains(&format!("at step {step} ")),
        "{cause}"
    );
    for f in ["energy.csv", "punch_force.csv", "tools.csv"] {
        let rows = finite_rows(&out.join(f));
        assert!(rows > 10, "{f}: {rows} rows");
    }
    // No file holds a NaN: the end state's sections that would are left out
    // and listed. Whether the end state holds one depends on where the
    // blow-up runs away first (the run may stop before the positions turn
    // NaN), so the list may be empty; every file written is checked.
    let not_written = s["not_written"].as_array().cloned().unwrap_or_default();
    for entry in &not_written {
        let name = entry.as_str().unwrap().split(':').next().unwrap();
        assert!(!out.join(name).exists(), "{name}");
    }
    for entry in std::fs::read_dir(out.join("sections")).unwrap() {
        finite_rows(&entry.unwrap().path());
    }
}

/// SIGINT to `formsim run`: the run stops at the next step, writes
/// `summary.json` (`"status": "interrupted"`, where it stopped) and the
/// histories so far, says where it stopped, and exits with 130.
#[cfg(unix)]
#[test]
fn an_interrupted_run_writes_its_results_and_exits_with_130() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let scene = root().join("scenes/square-cup.toml");
    // The full cup: minutes of work, interrupted after its first frame.
    let mut child = Command::new(env!("CARGO_BIN_EXE_formsim"))
        .args(["-q", "run", scene.to_str().unwrap(), "--out"])
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    // The first frame is written in the step loop, after the handler is set.
    while !out.join("vtk/blank_0000.vtu").exists() {
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "no first frame"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(300));
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    // Stopped at the next step: within seconds, not the minutes of the cup.
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > Duration::from_secs(60) {
            child.kill().unwrap();
            panic!("the interrupted run did not stop");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(
        err.contains("run interrupted at step") && err.contains("results so far in"),
        "{err}"
    );

    let s = summary(&out);
    assert_eq!(s["status"], "interrupted");
    let step = s["increments"].as_u64().unwrap();
    assert!(step > 0);
    let cause = s["cause"].as_str().unwrap();
    assert!(
        cause.starts_with(&format!("interrupted at step {step} ")),
        "{cause}"
    );
    for f in ["energy.csv", "punch_force.csv", "tools.csv"] {
        assert!(finite_rows(&out.join(f)) >= 1, "{f}");
    }
    assert!(out.join("blank.pvd").is_file());
}

/// A frame that cannot be written (a folder where `vtk/blank_0001.vtu` must
/// go: refused even to root) stops the run: `summary.json` says
/// `"status": "failed"` and names the file, the histories up to that moment
/// and the frames written so far are kept.
#[test]
fn a_frame_that_cannot_be_written_stops_the_run_and_keeps_the_rest() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path();
    std::fs::create_dir_all(out.join("vtk/blank_0001.vtu")).unwrap();
    let sets: Vec<String> = [
        "blank.mesh.divisions=10",
        "steps[2].duration=3e-3",
        "steps[2].motions[1].distance=4.99",
        "output.frames=3",
    ]
    .map(String::from)
    .to_vec();
    let loaded = formsim::scene::load(&root().join("scenes/square-cup.toml"), &sets).unwrap();
    let r = formsim::run::run(
        &loaded,
        &formsim::run::RunOptions {
            out: out.to_path_buf(),
            progress: Default::default(),
        },
    );
    let Err(formsim::run::RunError::Failed { message, .. }) = r else {
        panic!("the run did not stop: {r:?}");
    };
    assert!(message.contains("blank_0001.vtu"), "{message}");

    let s = summary(out);
    assert_eq!(s["status"], "failed");
    let cause = s["cause"].as_str().unwrap();
    assert!(cause.contains("vtk/blank_0001.vtu"), "{cause}");
    assert!(s["simulated_time_s"].as_f64().unwrap() > 0.0);
    for f in ["energy.csv", "punch_force.csv", "tools.csv"] {
        assert!(finite_rows(&out.join(f)) > 10, "{f}");
    }
    assert!(out.join("vtk/blank_0000.vtu").is_file());
    let pvd = std::fs::read_to_string(out.join("blank.pvd")).unwrap();
    assert!(
        pvd.contains("blank_0000.vtu") && !pvd.contains("blank_0001.vtu"),
        "{pvd}"
    );
}
