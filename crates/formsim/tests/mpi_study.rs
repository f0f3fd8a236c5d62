//! `formsim study` under `mpirun -n 3` gives the same study as with the
//! local executor: study.json is the same text, bit for bit, once the
//! timings (CPU and wall seconds, speed-ups, costs, and the recommendation
//! that follows from them) are masked. The coarse square cup as in
//! `tests/study.rs`: 10 × 10 and 8 × 8 elements, AC and WVS.
#![cfg(feature = "mpi")]

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod batch_support;
use batch_support::untimed;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The study's arguments into `out`: one knob and one model, so that no
/// `combined` variant (which follows from the timings) can appear.
fn args(out: &Path) -> Vec<String> {
    [
        "--threads",
        "1",
        "study",
        "scenes/square-cup.toml",
        "--vary",
        "blank.mesh.divisions=10,8",
        "--model",
        "contact.law=ac,wvs",
        "--quantities",
        "draw_in.DX,punch_force_max,OD:major",
        "--out",
        out.to_str().unwrap(),
    ]
    .map(String::from)
    .to_vec()
}

fn check(o: &Output) {
    assert!(
        o.status.success(),
        "{}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// study.json with every timing replaced by null.
fn masked(out: &Path) -> Value {
    masked_file(&out.join("study.json"))
}

/// The JSON file `path` with every timing replaced by null.
fn masked_file(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).unwrap();
    untimed(serde_json::from_str(&text).unwrap())
}

#[test]
fn a_study_under_mpirun_is_the_local_study_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let (local, mpi) = (dir.path().join("local"), dir.path().join("mpi"));
    let exe = env!("CARGO_BIN_EXE_formsim");
    let o = Command::new(exe)
        .current_dir(root())
        .args(args(&local))
        .output()
        .unwrap();
    check(&o);
    let o = Command::new("mpirun")
        .current_dir(root())
        .args(["-n", "3", "--oversubscribe", exe])
        .args(args(&mpi))
        .output()
        .expect("mpirun (Open MPI) on the PATH");
    check(&o);
    // One study (rank 0's), its runs three at a time (two workers and rank 0).
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(stderr.matches("study: ").count(), 1, "{stderr}");
    assert!(
        stderr.contains("3 at a time on 1 thread(s) each"),
        "{stderr}"
    );
    let (a, b) = (masked(&local), masked(&mpi));
    assert_eq!(a["variants"].as_array().unwrap().len(), 3, "{a}");
    // Same text: every number the same bits (shortest round-trip form).
    assert_eq!(
        serde_json::to_string_pretty(&a).unwrap(),
        serde_json::to_string_pretty(&b).unwrap()
    );
    // Every variant's folder has its run's summary.
    for v in a["variants"].as_array().unwrap() {
        let label = v["label"].as_str().unwrap();
        assert!(mpi.join(label).join("summary.json").is_file(), "{label}");
    }
}

/// `formsim compare` under `mpirun -n 3` writes the local comparison's
/// table: compare.csv the same text once its wall-time columns are left
/// out; every row's run is in its folder.
#[test]
fn a_comparison_under_mpirun_is_the_local_one_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let exe = env!("CARGO_BIN_EXE_formsim");
    let args = |out: &Path| -> Vec<String> {
        [
            "--threads",
            "1",
            "compare",
            "scenes/block-on-plane.toml",
            "--case",
            "d2:blank.mesh.divisions=2",
            "--case",
            "d4:blank.mesh.divisions=4",
            "--formulations",
            "convective,jaumann",
            "--set",
            "output.frames=0",
            "--out",
            out.to_str().unwrap(),
        ]
        .map(String::from)
        .to_vec()
    };
    let (local, mpi) = (dir.path().join("local"), dir.path().join("mpi"));
    check(
        &Command::new(exe)
            .current_dir(root())
            .args(args(&local))
            .output()
            .unwrap(),
    );
    check(
        &Command::new("mpirun")
            .current_dir(root())
            .args(["-n", "3", "--oversubscribe", exe])
            .args(args(&mpi))
            .output()
            .expect("mpirun (Open MPI) on the PATH"),
    );
    let untimed = |out: &Path| -> Vec<String> {
        let text = std::fs::read_to_string(out.join("compare.csv")).unwrap();
        let header: Vec<String> = text
            .lines()
            .next()
            .unwrap()
            .split(',')
            .map(String::from)
            .collect();
        text.lines()
            .map(|l| {
                (l.split(',').zip(&header))
                    .filter(|(_, h)| *h != "wall_time_s" && *h != "wall_rel")
                    .map(|(c, _)| c)
                    .collect::<Vec<_>>()
                    .join(",")
            })
            .collect()
    };
    let (a, b) = (untimed(&local), untimed(&mpi));
    assert_eq!(a.len(), 5, "{a:?}");
    assert_eq!(a, b);
    for label in [
        "d2-ac-convective",
        "d2-ac-jaumann",
        "d4-ac-convective",
        "d4-ac-jaumann",
    ] {
        assert!(mpi.join(label).join("summary.json").is_file(), "{label}");
    }
}

/// `formsim identify` under `mpirun -n 3` writes the identification of the
/// local engine (the gold file of `tests/batch_engine.rs`, timings masked),
/// and so does a second call with `--fresh` into the same folder, whose
/// journal only rank 0 removes.
#[test]
fn an_identification_under_mpirun_is_the_gold_one_fresh_or_not() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("id");
    let exe = env!("CARGO_BIN_EXE_formsim");
    let gold = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/batch_gold/identification.json");
    for fresh in [false, true] {
        let o = Command::new("mpirun")
            .current_dir(root())
            .args(["-n", "3", "--oversubscribe", exe])
            .args(["--threads", "1", "identify", "scenes/square-cup-al.toml"])
            .args(["--measurements", "data/numisheet93-al-drawin-40mm.csv"])
            .args(["--fit", "contact.params.ac.mu=0.02..0.3"])
            .args(["--max-evaluations", "4", "-q"])
            .args([
                "--set",
                "blank.mesh.divisions=6",
                "--set",
                "output.frames=0",
            ])
            .args([
                "--set",
                "output.plots=false",
                "--out",
                out.to_str().unwrap(),
            ])
            .args(fresh.then_some("--fresh"))
            .output()
            .expect("mpirun (Open MPI) on the PATH");
        check(&o);
        assert_eq!(
            masked_file(&out.join("identification.json")),
            masked_file(&gold),
            "fresh: {fresh}"
        );
    }
}
