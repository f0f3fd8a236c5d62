//! formsim's modules depend one way: a scene is read and built (`scene/`),
//! then run (`run/`); the rows a run records (`records.rs`) depend on
//! neither. A `use` of `run` inside `scene/` would close a circle again.

use std::path::Path;

/// The `.rs` files under `dir` (recursively).
fn sources(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(sources(&p));
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
    out
}

/// Code lines (not comments) of `path` that name `module`.
fn uses(path: &Path, module: &str) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .filter(|l| l.contains(&format!("crate::{module}")))
        .map(|l| format!("{}: {}", path.display(), l.trim()))
        .collect()
}

#[test]
fn scene_does_not_import_run() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut bad = Vec::new();
    for f in sources(&src.join("scene")) {
        bad.extend(uses(&f, "run"));
    }
    for module in ["run", "scene"] {
        bad.extend(uses(&src.join("records.rs"), module));
    }
    assert!(
        bad.is_empty(),
        "imports against the direction scene → run:\n{}",
        bad.join("\n")
    );
}
