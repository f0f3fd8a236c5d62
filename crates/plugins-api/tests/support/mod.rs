//! Fixtures shared by the dynamic-plugin tests: where cargo builds, and
//! building plugin crates of the workspace as shared libraries.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The workspace root.
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .expect("workspace root")
}

/// The target directory cargo builds into: `CARGO_TARGET_DIR` if set (relative
/// to the workspace root, where the build runs), else `<workspace>/target`.
pub fn target_dir() -> PathBuf {
    match std::env::var_os("CARGO_TARGET_DIR") {
        Some(dir) => workspace_root().join(dir),
        None => workspace_root().join("target"),
    }
}

/// The file name of crate `crate_name`'s shared library on this platform.
pub fn dylib_name(crate_name: &str) -> String {
    format!(
        "{}{}{}",
        std::env::consts::DLL_PREFIX,
        crate_name.replace('-', "_"),
        std::env::consts::DLL_SUFFIX
    )
}

/// Build the workspace crates `names` (debug profile, one `cargo build`) and
/// return their shared libraries' paths, in order.
pub fn build_plugins(names: &[&str]) -> Vec<PathBuf> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut cmd = Command::new(cargo);
    cmd.arg("build").current_dir(workspace_root());
    for n in names {
        cmd.args(["-p", n]);
    }
    let out = cmd.output().expect("run cargo build");
    assert!(
        out.status.success(),
        "cargo build of the plugins failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let debug = target_dir().join("debug");
    let paths: Vec<PathBuf> = names.iter().map(|n| debug.join(dylib_name(n))).collect();
    assert!(
        paths.iter().all(|p| p.is_file()),
        "built libraries not found: {paths:?}"
    );
    paths
}
