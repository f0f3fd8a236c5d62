//! `formsim study` on a coarse square cup (the reduced study that runs in
//! CI): the variants are real runs of their knob values, each error is the
//! one recomputed here from the runs' own `summary.json`, costs are spreads
//! over the repeats, and a bad value stops the study before anything runs.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn formsim(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_formsim"))
        .current_dir(root())
        .args(args)
        .output()
        .unwrap()
}

fn json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The draw-in DX (mm) of the variant `label`'s run, from its summary.json.
fn draw_in_dx(out: &Path, label: &str) -> f64 {
    json(&out.join(label).join("summary.json"))["draw_in"]["DX"]
        .as_f64()
        .unwrap()
}

/// Reference: 10 × 10 elements, AC, no frames. Variants: 8 × 8 elements,
/// WVS, and two VTK frames (which must not move any result: error 0).
#[test]
fn study_of_the_coarse_cup_gives_each_variant_its_errors_and_costs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    let o = formsim(&[
        "--threads",
        "1",
        "study",
        "scenes/square-cup.toml",
        "--vary",
        "blank.mesh.divisions=10,8",
        "--vary",
        "contact.law=ac,wvs",
        "--vary",
        "output.frames=0,2",
        "--quantities",
        "draw_in.DX,punch_force_max,OD:major",
        "--repeat",
        "2",
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    let s = json(&out.join("study.json"));
    assert_eq!(s["threads"], 1);
    let variants = s["variants"].as_array().unwrap();
    let labels: Vec<&str> = variants
        .iter()
        .map(|v| v["label"].as_str().unwrap())
        .collect();
    assert_eq!(
        labels[..4],
        ["reference", "divisions-8", "law-wvs", "frames-2"]
    );

    // Errors of the scalars, from the runs' own summaries.
    let dx = |label: &str| draw_in_dx(&out, label);
    let d_ref = dx("reference");
    for v in &variants[1..4] {
        let label = v["label"].as_str().unwrap();
        let expected = ((dx(label) - d_ref) / d_ref).abs();
        let got = v["errors"][0]["error"].as_f64().unwrap();
        assert_eq!(got, expected, "{label}");
        let worst = v["errors"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| e["error"].as_f64().unwrap())
            .fold(0.0, f64::max);
        assert_eq!(v["worst"].as_f64().unwrap(), worst, "{label}");
    }
    // A coarser mesh and another law move the results; frames do not.
    assert!(variants[1]["worst"].as_f64().unwrap() > 1e-3);
    assert!(variants[2]["worst"].as_f64().unwrap() > 1e-4);
    assert_eq!(variants[3]["worst"].as_f64().unwrap(), 0.0);
    assert!(
        variants[0]["errors"]
            .as_array()
            .unwrap()
            .iter()
            .all(Value::is_null)
    );

    // Costs: two rounds; the reference at both ends of each (three
    // variants, fewer than the reference's period), the others once per
    // round; spreads ordered; speed-ups per run against the reference.
    let reference = &variants[0];
    assert_eq!(reference["runs"], 4);
    let ref_median = reference["cpu_s"]["median"].as_f64().unwrap();
    for v in variants {
        let c = &v["cpu_s"];
        let (lo, mid, hi) = (
            c["min"].as_f64().unwrap(),
            c["median"].as_f64().unwrap(),
            c["max"].as_f64().unwrap(),
        );
        assert!(0.0 < lo && lo <= mid && mid <= hi, "{v}");
        assert!(v["increments"].as_u64().unwrap() > 0);
        let s = &v["speed_up"];
        let (lo, mid, hi) = (
            s["min"].as_f64().unwrap(),
            s["median"].as_f64().unwrap(),
            s["max"].as_f64().unwrap(),
        );
        assert!(0.0 < lo && lo <= mid && mid <= hi, "{v}");
        assert_eq!(v["cost_s"].as_f64().unwrap(), ref_median / mid);
        if v["label"] != "reference" {
            assert_eq!(v["runs"], 2, "{v}");
        }
    }
    assert_eq!(reference["speed_up"]["min"], 1.0);
    // The coarser mesh is cheaper beyond any drift of the machine.
    assert!(variants[1]["speed_up"]["min"].as_f64().unwrap() > 1.2);
    // Each variant is the run of its values.
    let summary = json(&out.join("divisions-8/summary.json"));
    assert_eq!(summary["elements"], 64);
    assert_eq!(json(&out.join("law-wvs/summary.json"))["law"], "wvs");

    // The recommendation, if any, is within the tolerance.
    if let Some(label) = s["recommendation"].as_str() {
        let v = variants.iter().find(|v| v["label"] == label).unwrap();
        assert!(v["worst"].as_f64().unwrap() <= 0.02);
    }
    let md = std::fs::read_to_string(out.join("study.md")).unwrap();
    for heading in [
        "## `blank.mesh.divisions`",
        "## `contact.law`",
        "## `output.frames`",
        "## Warnings",
        "## Recommendation",
    ] {
        assert!(md.contains(heading), "{heading}\n{md}");
    }
    // The coarse meshes' warning, listed per variant as summary.json has it.
    assert!(md.contains("- `divisions-8`: blank.mesh:"), "{md}");
    for png in ["pareto.png", "times.png"] {
        assert!(
            std::fs::metadata(out.join(png)).unwrap().len() > 1000,
            "{png}"
        );
    }

    // The same folder again needs --force.
    let again = formsim(&[
        "study",
        "scenes/square-cup.toml",
        "--vary",
        "contact.law=ac,wvs",
        "--quantities",
        "draw_in.DX",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!again.status.success());
    assert!(String::from_utf8_lossy(&again.stderr).contains("--force"));
}

/// A study with a refinement sequence (`--converge`, 4 → 8 → 16 divisions
/// of the coarse cup's quarter) and a model (`--model contact.law`): the
/// converged answer of `draw_in.DX` is recomputed here from the levels' own
/// `summary.json` (Richardson with the observed order, or the finest level
/// where the levels are not asymptotic), every variant's error, the
/// reference's too, is against it, and the model is reported apart and
/// never recommended.
#[test]
fn a_refinement_sequence_gives_the_converged_answer_every_error_is_against() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    let o = formsim(&[
        "--threads",
        "1",
        "study",
        "scenes/square-cup.toml",
        "--set",
        "blank.mesh.divisions=8",
        "--set",
        "output.frames=0",
        "--vary",
        "blank.integration_points=5,3",
        "--model",
        "contact.law=ac,wvs",
        "--converge",
        "blank.mesh.divisions=4,8,16",
        "--quantities",
        "draw_in.DX,OD:major",
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    let s = json(&out.join("study.json"));
    let labels: Vec<&str> = s["variants"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v["label"].as_str().unwrap())
        .collect();
    assert_eq!(
        labels,
        [
            "reference",
            "integration_points-3",
            "law-wvs",
            "level-1",
            "level-2",
            "level-3"
        ]
    );
    assert_eq!(s["knobs"][1]["model"], true);
    let c = &s["converged"];
    assert_eq!(c["ratio"], 2.0);
    assert_eq!(c["levels"].as_array().unwrap().len(), 3);
    assert_eq!(
        json(&out.join("level-3/summary.json"))["elements"],
        256,
        "the finest level is 16 × 16"
    );

    // The converged draw-in, recomputed from the levels' summaries.
    let dx = |label: &str| draw_in_dx(&out, label);
    let (f1, f2, f3) = (dx("level-1"), dx("level-2"), dx("level-3"));
    let q = &c["quantities"][0];
    let estimate = q["estimate"]["value"].as_f64().unwrap();
    let (d21, d32) = (f1 - f2, f2 - f3);
    let p = (d21 / d32).ln() / 2f64.ln();
    if d21 * d32 > 0.0 && (0.5..=4.0).contains(&p) {
        let expected = f3 + (f3 - f2) / (2f64.powf(p) - 1.0);
        assert!((estimate - expected).abs() <= 1e-12 * expected.abs(), "{q}");
        assert!(q["not_asymptotic"].is_null(), "{q}");
    } else {
        assert_eq!(estimate, f3, "{q}");
        assert!(q["not_asymptotic"].is_string(), "{q}");
    }
    // The level at the reference's settings is the reference's run.
    assert_eq!(dx("level-2"), dx("reference"));

    // Every error, the reference's too, is against the converged answer.
    for v in s["variants"].as_array().unwrap() {
        let label = v["label"].as_str().unwrap();
        let expected = ((dx(label) - estimate) / estimate).abs();
        assert_eq!(
            v["errors"][0]["error"].as_f64().unwrap(),
            expected,
            "{label}"
        );
        assert!(v["errors"][1]["error"].as_f64().unwrap() >= 0.0, "{label}");
    }
    assert_ne!(s["recommendation"], "law-wvs");
    let md = std::fs::read_to_string(out.join("study.md")).unwrap();
    for needle in [
        "## The converged answer",
        "relative to the converged answer",
        "A model, not an accuracy knob",
    ] {
        assert!(md.contains(needle), "{needle}\n{md}");
    }
}

/// An unknown law in the second variant is found while planning: one line
/// naming the variant, and no run (no output folder).
#[test]
fn a_bad_value_stops_the_study_before_any_run() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    let o = formsim(&[
        "study",
        "scenes/square-cup.toml",
        "--vary",
        "contact.law=ac,nope",
        "--quantities",
        "draw_in.DX",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("law-nope") && stderr.contains("nope"),
        "{stderr}"
    );
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(!out.exists());
}

/// Command-line mistakes are one-line errors naming the option.
#[test]
fn bad_study_options_are_named() {
    let cases: [(&[&str], &str); 7] = [
        (&["--vary", "contact.law"], "--vary"),
        (&["--vary", "contact.law=ac,ac"], "twice"),
        (
            &[
                "--vary",
                "contact.law=ac,wvs",
                "--reference",
                "blank.mesh.divisions=5",
            ],
            "--reference",
        ),
        (
            &["--vary", "contact.law=ac,wvs", "--repeat", "0"],
            "--repeat",
        ),
        (
            &["--vary", "contact.law=ac,wvs", "--tolerance=-1"],
            "--tolerance",
        ),
        (
            &[
                "--vary",
                "contact.law=ac,wvs",
                "--converge",
                "blank.mesh.divisions=4,8",
            ],
            "three or more",
        ),
        (
            &[
                "--vary",
                "contact.law=ac,wvs",
                "--converge",
                "blank.mesh.divisions=4,8,12",
            ],
            "one ratio",
        ),
    ];
    for (args, word) in cases {
        let mut all = vec!["study", "scenes/square-cup.toml", "--out", "/nonexistent/x"];
        all.extend_from_slice(args);
        all.extend_from_slice(&["--quantities", "draw_in.DX"]);
        let o = formsim(&all);
        assert!(!o.status.success(), "{args:?}");
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(stderr.contains(word), "{args:?}: {stderr}");
    }
}

/// A quantity the scene does not report (a misspelt key, a section or
/// report stroke it does not have) is refused while planning, naming it and
/// what the scene reports, and nothing runs (no output folder).
#[test]
fn a_quantity_the_scene_does_not_report_stops_the_study_before_any_run() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    for (q, needle) in [
        ("draw_in.DQ", "`draw_in.DQ`"),
        ("punch_forse_max", "`punch_forse_max`"),
        ("states.17.draw_in.DX", "`states.17.draw_in.DX`"),
        ("OQ:major", "section `OQ`"),
        ("OD@17:major", "at stroke 17 mm"),
    ] {
        let o = formsim(&[
            "study",
            "scenes/square-cup.toml",
            "--vary",
            "contact.law=ac,wvs",
            "--quantities",
            q,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(!o.status.success(), "{q}");
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(stderr.contains(needle), "{q}: {stderr}");
        assert!(stderr.contains("draw_in: DD, DX, DY"), "{q}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
        assert!(!out.exists(), "{q}");
    }
}

/// The punch force at a stroke (`punch_force@STROKE`) is the run's
/// `punch_force.csv` interpolated linearly at that stroke, recomputed
/// here from the file; a quantity the scene does not report
/// (`OD@33:major`, no report stroke at 33 mm) is refused before any run.
#[test]
fn the_punch_force_at_a_stroke_is_the_runs_force_history_interpolated() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    let o = formsim(&[
        "study",
        "scenes/square-cup.toml",
        "--set",
        "blank.mesh.divisions=4",
        "--set",
        "output.frames=0",
        "--set",
        "output.plots=false",
        "--vary",
        "contact.law=ac,wh",
        "--quantities",
        "punch_force@20",
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = json(&out.join("study.json"));
    let got = s["variants"][0]["values"][0].as_f64().unwrap();
    let csv = std::fs::read_to_string(out.join("reference/punch_force.csv")).unwrap();
    let rows: Vec<(f64, f64)> = csv
        .lines()
        .skip(1)
        .map(|l| {
            let c: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            (c[1], c[2])
        })
        .collect();
    let k = rows.iter().position(|r| r.0 >= 20.0).unwrap();
    let ((s0, f0), (s1, f1)) = (rows[k - 1], rows[k]);
    let expected = f0 + (f1 - f0) * (20.0 - s0) / (s1 - s0);
    assert!(
        (got - expected).abs() <= 1e-9 * expected.abs(),
        "{got} against {expected} from punch_force.csv"
    );
    assert!(got > 1000.0, "{got} N: the punch pushes at 20 mm");

    let bad = formsim(&[
        "study",
        "scenes/square-cup.toml",
        "--vary",
        "contact.law=ac,wh",
        "--quantities",
        "OD@33:major",
        "--out",
        dir.path().join("bad").to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(!bad.status.success());
    assert!(err.contains("OD") && err.contains("33"), "{err}");
    assert!(!dir.path().join("bad").exists(), "{err}");
}
