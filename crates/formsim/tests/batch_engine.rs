//! The batch engine under `compare`, `study` and `identify`.
//!
//! - Their outputs are those of the commands before the engine, timings
//!   apart: the gold files in `tests/batch_gold/` were written by formsim
//!   at the commit before the engine (bac3d08) with the very commands below,
//!   and every figure that is not a timing must match them byte for byte.
//! - A second call with the same arguments reads every run from the
//!   journal and writes the same outputs; a run missing from the journal is
//!   run again, alone; `--fresh` starts over.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Output;

mod batch_support;
use batch_support::untimed;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn formsim(args: &[&str]) -> Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_formsim"))
        .current_dir(root())
        .args(args)
        .output()
        .unwrap()
}

fn ok(o: &Output) -> String {
    let stderr = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(o.status.success(), "{stderr}");
    stderr
}

fn gold(name: &str) -> String {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/batch_gold")
        .join(name);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The text of a JSON file with its timings masked.
fn untimed_json(text: &str) -> String {
    serde_json::to_string_pretty(&untimed(serde_json::from_str(text).unwrap())).unwrap()
}

/// `compare.csv` without its wall-time columns.
fn untimed_csv(text: &str) -> String {
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let timed: Vec<usize> = (0..header.len())
        .filter(|&i| header[i] == "wall_time_s" || header[i] == "wall_rel")
        .collect();
    assert_eq!(timed.len(), 2, "{text}");
    let keep = |line: &str| -> String {
        let cells: Vec<&str> = line.split(',').collect();
        (0..cells.len())
            .filter(|i| !timed.contains(i))
            .map(|i| cells[i])
            .collect::<Vec<_>>()
            .join(",")
    };
    std::iter::once(keep(&header.join(",")))
        .chain(lines.map(keep))
        .collect::<Vec<_>>()
        .join("\n")
}

/// `compare.md` with the cells of its wall-time columns (`wall time (s)`
/// and the `rel.` after it) emptied.
fn untimed_md(text: &str) -> String {
    let mut timed: Vec<usize> = Vec::new();
    text.lines()
        .map(|line| {
            if !line.starts_with('|') {
                return line.to_string();
            }
            let cells: Vec<&str> = line.split('|').collect();
            if let Some(w) = cells.iter().position(|c| c.trim() == "wall time (s)") {
                timed = vec![w, w + 1];
            }
            (0..cells.len())
                .map(|i| if timed.contains(&i) { "" } else { cells[i] })
                .collect::<Vec<_>>()
                .join("|")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

const COMPARE: &[&str] = &[
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
];

fn with_out<'a>(args: &[&'a str], out: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut all = args.to_vec();
    all.extend(["--out", out]);
    all.extend(extra);
    all
}

/// `compare` on the block (2 × 2 cases of 4 and 16 elements): the gold
/// table; called again, every row comes from the journal and the table is
/// the same; with one row's journal entry removed, only that row runs; with
/// `--fresh`, all run.
#[test]
fn compare_on_the_engine_gives_the_tables_of_before_and_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cmp");
    let o = out.to_str().unwrap();
    let first = ok(&formsim(&with_out(COMPARE, o, &[])));
    assert_eq!(first.matches("(from the journal)").count(), 0, "{first}");
    let csv = read(&out.join("compare.csv"));
    let md = read(&out.join("compare.md"));
    assert_eq!(untimed_csv(&csv), untimed_csv(&gold("compare.csv")));
    assert_eq!(untimed_md(&md), untimed_md(&gold("compare.md")));

    let again = ok(&formsim(&with_out(COMPARE, o, &[])));
    assert_eq!(again.matches("(from the journal)").count(), 4, "{again}");
    assert_eq!(
        read(&out.join("compare.csv")),
        csv,
        "journalled rows give the same table"
    );
    assert_eq!(read(&out.join("compare.md")), md);

    std::fs::remove_file(out.join("journal/runs/d4-ac-jaumann.json")).unwrap();
    let one = ok(&formsim(&with_out(COMPARE, o, &[])));
    assert_eq!(one.matches("(from the journal)").count(), 3, "{one}");
    assert!(
        one.contains("done d4-ac-jaumann: 10025 increments"),
        "{one}"
    );
    assert_eq!(
        untimed_csv(&read(&out.join("compare.csv"))),
        untimed_csv(&csv)
    );

    let fresh = ok(&formsim(&with_out(COMPARE, o, &["--fresh"])));
    assert_eq!(fresh.matches("(from the journal)").count(), 0, "{fresh}");
    assert_eq!(fresh.matches("done ").count(), 4, "{fresh}");

    // Other arguments on the same folder: refused, in one line, pointing at --fresh.
    let mut other = COMPARE.to_vec();
    other[7] = "d5:blank.mesh.divisions=5";
    let o2 = formsim(&with_out(&other, o, &[]));
    let err = String::from_utf8_lossy(&o2.stderr);
    assert!(!o2.status.success(), "{err}");
    assert!(
        err.contains("holds the results of another batch") && err.contains("--fresh"),
        "{err}"
    );
    assert_eq!(err.trim().lines().count(), 1, "{err}");
}

const STUDY: &[&str] = &[
    "--threads",
    "1",
    "study",
    "scenes/square-cup.toml",
    "--set",
    "blank.mesh.divisions=4",
    "--set",
    "output.frames=0",
    "--set",
    "output.plots=false",
    "--vary",
    "contact.law=ac,wvs,wh",
    "--quantities",
    "draw_in.DX,OD:major",
];

/// `study` of three laws on the 4 × 4 cup: the gold `study.json` (timings
/// and the recommendation they decide masked); called again, every run
/// comes from the journal and `study.json` is the same file.
#[test]
fn study_on_the_engine_gives_the_study_of_before_and_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    let o = out.to_str().unwrap();
    ok(&formsim(&with_out(STUDY, o, &["--quiet"])));
    let json = read(&out.join("study.json"));
    assert_eq!(untimed_json(&json), untimed_json(&gold("study.json")));
    let again = ok(&formsim(&with_out(STUDY, o, &[])));
    assert!(
        again.contains("4 runs in the journal of an earlier call"),
        "{again}"
    );
    assert_eq!(
        read(&out.join("study.json")),
        json,
        "the same file, timings too"
    );
}

/// The same study two runs at a time (`--jobs 2`): its round is one
/// batch, so the reference's second run goes alongside the others into a
/// scratch folder of the journal. `study.json` is the gold one (timings
/// masked), every variant's folder holds its run, and nothing is left in
/// the scratch folder.
#[test]
fn study_two_at_a_time_gives_the_same_study_and_leaves_no_scratch() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    let o = out.to_str().unwrap();
    let said = ok(&formsim(&with_out(STUDY, o, &["--jobs", "2"])));
    assert!(said.contains("2 at a time"), "{said}");
    let json = read(&out.join("study.json"));
    assert_eq!(untimed_json(&json), untimed_json(&gold("study.json")));
    for variant in ["reference", "law-wvs", "law-wh"] {
        assert!(
            out.join(variant).join("summary.json").is_file(),
            "{variant}"
        );
    }
    let journal = out.join("journal");
    assert!(journal.join("runs").is_dir());
    assert!(!journal.join("scratch").exists(), "scratch folder left");
}

/// `identify` (Nelder–Mead, four evaluations, the 6 × 6 aluminium cup):
/// the gold `identification.json`, timings masked.
#[test]
fn identify_on_the_engine_gives_the_identification_of_before() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("id");
    ok(&formsim(&[
        "--threads",
        "1",
        "identify",
        "scenes/square-cup-al.toml",
        "--measurements",
        "data/numisheet93-al-drawin-40mm.csv",
        "--fit",
        "contact.params.ac.mu=0.02..0.3",
        "--max-evaluations",
        "4",
        "--set",
        "blank.mesh.divisions=6",
        "--set",
        "output.frames=0",
        "--set",
        "output.plots=false",
        "--out",
        out.to_str().unwrap(),
        "-q",
    ]));
    let json = read(&out.join("identification.json"));
    assert_eq!(
        untimed_json(&json),
        untimed_json(&gold("identification.json"))
    );
}

/// A row that fails when it runs (a fixed step above the stable limit,
/// found at set-up) is recorded in the journal with its message, the other
/// rows finish, the command exits 1; called again, the finished row comes
/// from the journal and the failed one runs again.
#[test]
fn a_failed_run_is_journalled_and_run_again_while_the_others_are_kept() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cmp");
    let args = [
        "compare",
        "scenes/block-on-plane.toml",
        "--case",
        "ok:blank.mesh.divisions=2",
        "--case",
        "bad:blank.mesh.divisions=2;solver.fixed_dt=1e-5",
        "--set",
        "output.frames=0",
        "--out",
        out.to_str().unwrap(),
    ];
    let o = formsim(&args);
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("failed bad: ") && err.contains("fixed_dt"),
        "{err}"
    );
    let journal: Value = serde_json::from_str(&read(&out.join("journal/runs/bad.json"))).unwrap();
    let message = journal["record"]["outcome"]["Err"].as_str().unwrap();
    assert!(message.contains("fixed time step 1e-5 s"), "{message}");
    assert!(out.join("journal/runs/ok.json").is_file());
    let md = read(&out.join("compare.md"));
    assert!(md.contains("| bad | ac | convective | failed: "), "{md}");

    let again = formsim(&args);
    let err = String::from_utf8_lossy(&again.stderr).to_string();
    assert_eq!(again.status.code(), Some(1), "{err}");
    assert!(
        err.contains("done ok: ") && err.contains("(from the journal)"),
        "{err}"
    );
    assert!(err.contains("failed bad: "), "{err}");
}
