//! What the command-line tests share: the `formsim` binary run with
//! arguments, its two output streams as one text, and plugin crates of the
//! workspace built as shared libraries.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Run the `formsim` binary with `args`.
pub fn formsim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_formsim"))
        .args(args)
        .output()
        .expect("formsim runs")
}

/// Standard output then standard error, as text.
pub fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

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
