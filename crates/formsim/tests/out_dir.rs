//! `--out DIR` over earlier results: `formsim run` and `formsim compare`
//! refuse a non-empty DIR unless `--force` is given; with it they remove what
//! formsim wrote there (no stale VTK frame survives) and keep other files. The
//! default directory `results/<scene name>` is formsim's own and is replaced.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/block-on-plane.toml")
        .canonicalize()
        .unwrap()
}

/// `formsim ARGS` on the block-on-plane scene at 2 × 2 elements, run in `cwd`.
fn formsim(cwd: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_formsim"))
        .current_dir(cwd)
        .args(args)
        .arg(scene())
        .args(["--quiet", "--set", "blank.mesh.divisions=2"])
        .output()
        .expect("formsim runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Every path under `dir`, relative, sorted.
fn tree(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if p.is_dir() {
            out.extend(tree(&p).into_iter().map(|i| format!("{name}/{i}")));
        }
        out.push(name);
    }
    out.sort();
    out
}

/// A directory with a stale frame of an earlier, longer run and a note of the user's.
fn stale_dir(parent: &Path, name: &str) -> PathBuf {
    let dir = parent.join(name);
    std::fs::create_dir_all(dir.join("vtk")).unwrap();
    std::fs::write(dir.join("vtk/blank_0099.vtu"), "stale").unwrap();
    std::fs::write(dir.join("notes.txt"), "mine").unwrap();
    dir
}

#[test]
fn run_refuses_old_results_and_force_replaces_only_what_it_wrote() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = stale_dir(tmp.path(), "out");
    let before = tree(&dir);
    let out = dir.to_str().unwrap();

    let o = formsim(tmp.path(), &["run", "--out", out]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains(&format!(
            "{out} exists and holds results; pass --force to replace them"
        )),
        "{err}"
    );
    assert_eq!(tree(&dir), before, "a refused run changes nothing");

    for _ in 0..2 {
        let o = formsim(tmp.path(), &["run", "--force", "--out", out]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(!dir.join("vtk/blank_0099.vtu").exists(), "stale frame left");
        assert_eq!(
            std::fs::read_to_string(dir.join("notes.txt")).unwrap(),
            "mine"
        );
        assert!(dir.join("summary.json").is_file());
        // The series and the folder agree: every frame listed is there and no other.
        let pvd = std::fs::read_to_string(dir.join("blank.pvd")).unwrap();
        for frame in std::fs::read_dir(dir.join("vtk")).unwrap() {
            let name = frame.unwrap().file_name().to_string_lossy().into_owned();
            assert!(
                pvd.contains(&format!("vtk/{name}")),
                "{name} not in blank.pvd"
            );
        }
        assert_eq!(pvd.matches("<DataSet").count(), 5, "{pvd}");
    }
}

#[test]
fn run_into_the_default_directory_replaces_its_results() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = stale_dir(&tmp.path().join("results"), "block-on-plane");
    for _ in 0..2 {
        let o = formsim(tmp.path(), &["run"]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(dir.join("summary.json").is_file());
        assert!(!dir.join("vtk/blank_0099.vtu").exists(), "stale frame left");
        assert!(dir.join("notes.txt").is_file());
    }
}

#[test]
fn compare_refuses_old_results_and_force_replaces_its_rows() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("cmp");
    let out = dir.to_str().unwrap();
    let compare = |extra: &[&str], formulation: &str| {
        let mut args = vec!["compare", "--laws", "ac", "--formulations", formulation];
        args.extend(extra);
        args.extend(["--out", out]);
        formsim(tmp.path(), &args)
    };
    let o = compare(&[], "convective");
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::write(dir.join("notes.txt"), "mine").unwrap();
    std::fs::write(dir.join("ac-convective/vtk/blank_0099.vtu"), "stale").unwrap();

    let before = tree(&dir);
    let o = compare(&[], "jaumann");
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    // The folder's journal says which batch its results are of.
    assert!(
        stderr(&o).contains("exists and holds the results of another batch")
            && stderr(&o).contains("pass --force (or --fresh) to replace them"),
        "{}",
        stderr(&o)
    );
    assert_eq!(tree(&dir), before, "a refused comparison changes nothing");

    let o = compare(&["--force"], "jaumann");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!dir.join("ac-convective").exists(), "the old row is gone");
    assert!(dir.join("ac-jaumann/summary.json").is_file());
    assert!(dir.join("notes.txt").is_file());
    let csv = std::fs::read_to_string(dir.join("compare.csv")).unwrap();
    assert_eq!(csv.lines().count(), 2, "{csv}");
}
