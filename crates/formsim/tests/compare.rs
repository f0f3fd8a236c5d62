//! `formsim compare` on the block-on-plane scene: the rows are the cases
//! crossed with the laws and formulations, each row is a real run of its own
//! overrides, and the table carries every row.

use formsim::compare::{Case, Matrix, compare};
use std::path::{Path, PathBuf};

fn scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/block-on-plane.toml")
}

fn strings(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

#[test]
fn case_parses_name_and_overrides() {
    let c = Case::parse("bt-100:blank.mesh.divisions=100; solver.mass_scaling_dt=2.5e-7").unwrap();
    assert_eq!(c.name, "bt-100");
    assert_eq!(
        c.sets,
        strings(&["blank.mesh.divisions=100", "solver.mass_scaling_dt=2.5e-7"])
    );
    let c = Case::parse("as-is").unwrap();
    assert!(c.sets.is_empty());
    for bad in ["", ":a=1", "two words:a=1", "x:novalue", "a/b:a=1"] {
        let e = Case::parse(bad).unwrap_err().to_string();
        assert!(e.starts_with("--case"), "{bad}: {e}");
    }
}

/// Two mesh cases × two formulations: four runs, labelled `CASE-LAW-FORMULATION`,
/// whose element counts are those of each case's mesh, and a table row each.
#[test]
fn compare_crosses_cases_with_formulations() {
    let dir = tempfile::tempdir().unwrap();
    let matrix = Matrix {
        cases: vec![
            Case::parse("d2:blank.mesh.divisions=2").unwrap(),
            Case::parse("d4:blank.mesh.divisions=4").unwrap(),
        ],
        laws: Vec::new(),
        formulations: strings(&["convective", "jaumann"]),
        sets: Vec::new(),
    };
    let entries = compare(&scene(), &matrix, dir.path(), false, &mut |_| {}).unwrap();
    let labels: Vec<&str> = entries.iter().map(|e| e.label.as_str()).collect();
    assert_eq!(
        labels,
        [
            "d2-ac-convective",
            "d2-ac-jaumann",
            "d4-ac-convective",
            "d4-ac-jaumann"
        ]
    );
    for e in &entries {
        let r = e.result.as_ref().unwrap();
        let n = if e.label.starts_with("d2") { 4 } else { 16 };
        assert_eq!(r.elements, n, "{}", e.label);
        assert_eq!(r.formulation, e.formulation);
        assert!(dir.path().join(&e.label).join("summary.json").is_file());
    }
    let md = std::fs::read_to_string(dir.path().join("compare.md")).unwrap();
    assert!(md.contains("| case | law | formulation |"), "{md}");
    assert!(!md.contains("NaN"), "{md}");
    assert!(!md.contains("## Warnings"), "{md}");
    let csv = std::fs::read_to_string(dir.path().join("compare.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows.len(), 5, "{csv}");
    assert!(rows[1].starts_with("d2,ac,convective,"));
    assert!(rows[4].starts_with("d4,ac,jaumann,"));
}

/// A case whose override is invalid stops the comparison before any run,
/// naming the case and the key.
#[test]
fn compare_rejects_a_bad_case_before_running() {
    let dir = tempfile::tempdir().unwrap();
    let matrix = Matrix {
        cases: vec![
            Case::parse("ok").unwrap(),
            Case::parse("bad:blank.thickness=-1").unwrap(),
        ],
        ..Default::default()
    };
    let e = compare(&scene(), &matrix, dir.path(), false, &mut |_| {})
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("case bad:") && e.contains("blank.thickness"),
        "{e}"
    );
    assert!(!dir.path().join("ok").exists());
    let twice = Matrix {
        cases: vec![Case::parse("a").unwrap(), Case::parse("a").unwrap()],
        ..Default::default()
    };
    let e = compare(&scene(), &twice, dir.path(), false, &mut |_| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("used twice"), "{e}");
}

/// An unknown law among valid ones stops the comparison before any row runs:
/// the error names the row and the law, and nothing is written.
#[test]
fn compare_rejects_an_unknown_law_before_running_any_row() {
    let dir = tempfile::tempdir().unwrap();
    let matrix = Matrix {
        laws: strings(&["ac", "nosuch"]),
        formulations: strings(&["convective"]),
        sets: strings(&["blank.mesh.divisions=2"]),
        ..Default::default()
    };
    let e = compare(&scene(), &matrix, dir.path(), false, &mut |_| {})
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("law nosuch, formulation convective: ") && e.contains("unknown law `nosuch`"),
        "{e}"
    );
    assert_eq!(e.lines().count(), 1, "{e}");
    let written: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert!(written.is_empty(), "nothing may be written: {written:?}");
}

/// An override that loads but cannot be built (a parameter out of range for
/// the law) is found before running, naming the case, law and formulation.
#[test]
fn compare_rejects_a_case_that_does_not_build_before_running() {
    let dir = tempfile::tempdir().unwrap();
    let matrix = Matrix {
        cases: vec![
            Case::parse("ok:blank.mesh.divisions=2").unwrap(),
            Case::parse("bad-mu:blank.mesh.divisions=2;contact.params.ac.mu=-1").unwrap(),
        ],
        ..Default::default()
    };
    let e = compare(&scene(), &matrix, dir.path(), false, &mut |_| {})
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("case bad-mu, law ac, formulation convective: ") && e.contains("mu"),
        "{e}"
    );
    assert!(std::fs::read_dir(dir.path()).unwrap().next().is_none());
}

/// The same law twice would make two rows write into one folder.
#[test]
fn compare_rejects_a_row_listed_twice() {
    let dir = tempfile::tempdir().unwrap();
    let matrix = Matrix {
        laws: strings(&["ac", "ac"]),
        ..Default::default()
    };
    let e = compare(&scene(), &matrix, dir.path(), false, &mut |_| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("`ac-convective` appears twice"), "{e}");
}

/// Each row's warnings (`summary.json`'s `warnings`) are listed under the
/// table of `compare.md`: the block under WVS has no closed form to check.
#[test]
fn compare_lists_each_rows_warnings() {
    let dir = tempfile::tempdir().unwrap();
    let matrix = Matrix {
        cases: vec![
            Case::parse("coulomb").unwrap(),
            Case::parse(
                "pressure:contact.law=wvs;contact.params.wvs.alpha=0.03;contact.params.wvs.beta=0.2;contact.params.wvs.nu=0.8",
            )
            .unwrap(),
        ],
        laws: Vec::new(),
        formulations: Vec::new(),
        sets: strings(&["output.plots=false", "output.frames=0"]),
    };
    let entries = compare(&scene(), &matrix, dir.path(), false, &mut |_| {}).unwrap();
    let warned: Vec<&String> = entries
        .iter()
        .flat_map(|e| &e.result.as_ref().unwrap().warnings)
        .collect();
    assert_eq!(warned.len(), 1, "{warned:?}");
    assert!(warned[0].contains("no analytic reference"), "{warned:?}");
    let md = std::fs::read_to_string(dir.path().join("compare.md")).unwrap();
    let label = &entries[1].label;
    assert!(md.contains("## Warnings"), "{md}");
    assert!(
        md.contains(&format!("- `{label}`: no analytic reference")),
        "{md}"
    );
}
