//! Helpers shared by the workspace-level integration tests (building the example plugin).

use std::path::PathBuf;
use std::process::Command;

/// Build `plugins/exp-decay` in the current profile's target directory and return the
/// path of its shared library.
///
/// # Panics
/// If cargo fails: the test that needs the plugin cannot proceed.
#[must_use]
pub fn build_example_plugin() -> PathBuf {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let release = !cfg!(debug_assertions);
    let mut cmd = Command::new(cargo);
    cmd.current_dir(&root)
        .args(["build", "-q", "-p", "exp-decay"]);
    if release {
        cmd.arg("--release");
    }
    let status = cmd.status().expect("cargo runs");
    assert!(status.success(), "building the example plugin failed");
    let target =
        std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| root.join("target"), PathBuf::from);
    let lib = format!(
        "{}exp_decay{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    );
    target
        .join(if release { "release" } else { "debug" })
        .join(lib)
}
