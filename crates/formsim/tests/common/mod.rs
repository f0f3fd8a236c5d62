//! Helpers shared by formsim's integration tests: the repository's root,
//! a run of a ready scene with overrides into a fresh temporary directory,
//! and the gold files of the benchmarks' headline figures ([`gold`]).

use formsim::run::{RunOptions, RunResult, run};
use formsim::scene;
use std::path::{Path, PathBuf};

// Each test binary that includes `common` uses a part of the gold checks.
#[allow(dead_code)]
pub mod gold;

/// The repository's root (the shipped scenes are under `scenes/`).
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Run the ready scene `scenes/NAME.toml` with `sets` into a fresh
/// temporary directory (kept alive by the returned handle).
pub fn run_scene(name: &str, sets: &[&str]) -> (tempfile::TempDir, RunResult) {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let loaded = scene::load(&root().join(format!("scenes/{name}.toml")), &sets).unwrap();
    run_loaded(&loaded)
}

/// Run `loaded` into a fresh temporary directory (kept alive by the
/// returned handle).
pub fn run_loaded(loaded: &scene::LoadedScene) -> (tempfile::TempDir, RunResult) {
    let dir = tempfile::tempdir().unwrap();
    let r = run(
        loaded,
        &RunOptions {
            out: dir.path().to_path_buf(),
            progress: Default::default(),
        },
    )
    .unwrap();
    (dir, r)
}
