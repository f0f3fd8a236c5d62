//! `formsim identify` and `formsim sensitivity` on the command line: bad input
//! gives one line naming what is wrong, before any run; the shipped data
//! files read.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn formsim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_formsim"))
        .args(args)
        .output()
        .expect("formsim runs")
}

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

#[test]
fn identify_bad_input_gives_one_line_before_any_run() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("id");
    let out = out.to_str().unwrap();
    let scene = repo("scenes/square-cup-al.toml");
    let scene = scene.to_str().unwrap();
    let csv = repo("data/numisheet93-al-drawin-40mm.csv");
    let csv = csv.to_str().unwrap();
    let bad_csv = dir.path().join("bad.csv");
    std::fs::write(
        &bad_csv,
        "stroke_mm,quantity,value_mm\n40,DX,28.5\n40,DY,\n",
    )
    .unwrap();
    let bad_csv = bad_csv.to_str().unwrap();
    let cases: Vec<(Vec<&str>, Vec<&str>)> = vec![
        (
            vec!["--fit", "contact.params.ac.mu=0.3..0.1"],
            vec!["--fit", "LO = 0.3 must be below HI = 0.1"],
        ),
        (vec!["--fit", "contact.params.ac.mu"], vec!["KEY=LO..HI"]),
        (
            vec!["--fit", "contact.params.ac.mu=0..1:2"],
            vec!["START = 2 is outside"],
        ),
        (
            vec![
                "--fit",
                "contact.params.ac.mu=0.02..0.3",
                "--objective",
                "wls",
            ],
            vec!["needs a standard error", "states.40.draw_in.DX (line 11)"],
        ),
        (
            vec![
                "--fit",
                "contact.params.ac.mu=0.02..0.3",
                "--method",
                "bfgs",
            ],
            vec!["--method bfgs"],
        ),
        (
            vec![
                "--fit",
                "contact.params.ac.mu=0.02..0.3",
                "--fit",
                "contact.params.ac.mu=0.1..0.2",
            ],
            vec!["fitted twice"],
        ),
        (
            vec!["--fit", "contact.params.ac.muu=0.02..0.3"],
            vec!["muu"],
        ),
        (
            vec!["--fit", "contact.params.ac.mu=0.02..0.3", "--fd-step", "0"],
            vec!["--fd-step 0"],
        ),
        (
            vec![
                "--fit",
                "contact.params.ac.mu=0.02..0.3",
                "--method",
                "surrogate",
                "--samples",
                "4",
            ],
            vec!["--samples 4", "from 5"],
        ),
        (
            vec!["--fit", "contact.params.ac.mu=0.02..0.3", "--samples", "10"],
            vec!["--samples 10", "only --method surrogate"],
        ),
    ];
    for (extra, needles) in cases {
        let mut args = vec!["identify", scene, "--measurements", csv, "--out", out];
        args.extend(&extra);
        let o = formsim(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{extra:?} should fail");
        assert_eq!(err.trim().lines().count(), 1, "{extra:?}: {err}");
        for n in needles {
            assert!(err.contains(n), "{extra:?}: `{n}` not in `{err}`");
        }
    }
    let o = formsim(&[
        "identify",
        scene,
        "--measurements",
        bad_csv,
        "--fit",
        "contact.params.ac.mu=0.02..0.3",
        "--out",
        out,
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("bad.csv:3:") && err.contains("value_mm"),
        "{err}"
    );
    // Nothing ran: no journal entry was written.
    let journal = Path::new(out).join("journal");
    let entries = std::fs::read_dir(&journal).map(|d| d.count()).unwrap_or(0);
    assert!(entries <= 1, "{} entries in {}", entries, journal.display());
}

#[test]
fn sensitivity_rejects_a_bad_step() {
    let dir = tempfile::tempdir().unwrap();
    let o = formsim(&[
        "sensitivity",
        repo("scenes/square-cup-al.toml").to_str().unwrap(),
        "--measurements",
        repo("data/numisheet93-al-drawin-40mm.csv")
            .to_str()
            .unwrap(),
        "--param",
        "contact.params.ac.mu=0.02..0.3",
        "--step",
        "1.5",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("--step 1.5"), "{err}");
}

#[test]
fn shipped_measurement_files_read() {
    use formsim::identify::measurements::Measurements;
    for name in [
        "data/numisheet93-al-drawin-40mm.csv",
        "data/twin-al-cup.toml",
    ] {
        let m = Measurements::read(&repo(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(!m.is_empty(), "{name}");
    }
}

/// The smallest budget `identify` accepts for one fitted value (3) runs to
/// its limit and reports what it found: argmin's Nelder–Mead asks for the
/// first simplex again and unwraps the answer, so a point already evaluated
/// is read whatever the limit.
#[test]
fn identify_at_the_smallest_evaluation_budget_reports_instead_of_panicking() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("id");
    let csv = repo("data/numisheet93-al-drawin-40mm.csv");
    let o = identify_al_mu(
        &csv,
        &out,
        &[
            "--max-evaluations",
            "3",
            "-q",
            "--set",
            "blank.mesh.divisions=6",
            "--set",
            "output.frames=0",
            "--set",
            "output.plots=false",
        ],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        stdout.contains("stopped at the limit of 3 evaluations"),
        "{stdout}"
    );
}

/// A measured quantity the scene does not report (a draw-in point it does
/// not have) is refused before any run, naming the line.
#[test]
fn identify_refuses_a_quantity_the_scene_does_not_report() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("m.csv");
    std::fs::write(
        &csv,
        "stroke_mm,quantity,value_mm\n40,DX,28.5\n40,DQ,28.5\n",
    )
    .unwrap();
    let out = dir.path().join("id");
    let o = identify_al_mu(&csv, &out, &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(err.contains("states.40.draw_in.DQ (line 3)"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(!out.join("runs").exists(), "{err}");
}

/// `formsim identify` of AC's μ on the aluminium cup against `csv` into
/// `out`, with `extra` arguments.
fn identify_al_mu(csv: &Path, out: &Path, extra: &[&str]) -> Output {
    let scene = repo("scenes/square-cup-al.toml");
    let mut args = vec![
        "identify",
        scene.to_str().unwrap(),
        "--measurements",
        csv.to_str().unwrap(),
        "--fit",
        "contact.params.ac.mu=0.05..0.3",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    formsim(&args)
}
