//! Plugin crates of the workspace built as shared libraries for the tests.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Build the workspace crate `name` (a plugin `cdylib`) in this test
/// binary's profile and return its shared library.
///
/// # Panics
/// If cargo fails: a test that needs the plugin cannot proceed.
pub fn plugin(name: &str) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let release = !cfg!(debug_assertions);
    let mut cmd = Command::new(cargo);
    cmd.current_dir(&root).args(["build", "-q", "-p", name]);
    if release {
        cmd.arg("--release");
    }
    assert!(cmd.status().unwrap().success(), "cargo build -p {name}");
    let target =
        std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| root.join("target"), PathBuf::from);
    target
        .join(if release { "release" } else { "debug" })
        .join(format!(
            "{}{}{}",
            std::env::consts::DLL_PREFIX,
            name.replace('-', "_"),
            std::env::consts::DLL_SUFFIX
        ))
}
