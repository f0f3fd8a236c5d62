//! Scenes: the TOML file that describes one forming simulation
//! (`docs/scene-format.md`), its command-line overrides, its checks and the
//! model built from it.
//!
//! Reading a scene goes: text → TOML table (syntax errors carry the line) →
//! `--set` overrides → typed [`Scene`] (unknown or mistyped keys name the key
//! and its line), with the reference checks' `[output.KEY]` tables resolved
//! against the keys each check declares ([`check_table`]) → [`validate`] (ranges, names, units) → [`build()`] (the
//! solver with its effects).

pub mod blank_mesh;
pub mod build;
pub mod check_table;
pub mod drawbeads;
pub mod error;
pub mod estimate;
pub mod kind;
pub mod locate;
pub mod material;
pub mod overrides;
pub mod resolved;
pub mod schema;
pub mod validate;

pub use build::{Model, build};
pub use error::SceneError;
pub use schema::Scene;

use std::path::{Path, PathBuf};

/// A scene read from a file, with the overrides applied and checked.
#[derive(Debug, Clone)]
pub struct LoadedScene {
    /// The typed scene.
    pub scene: Scene,
    /// The file it came from.
    pub path: PathBuf,
    /// Its text (for locating keys in later errors).
    pub text: String,
    /// The overrides applied (`KEY=VALUE` as given).
    pub overrides: Vec<String>,
}

impl LoadedScene {
    /// Directory that relative paths in the scene are resolved against.
    pub fn base_dir(&self) -> &Path {
        self.path.parent().unwrap_or(Path::new("."))
    }

    /// An error about `key` (dotted path), located in the file when it is there.
    pub fn key_error(&self, key: &str, message: impl Into<String>) -> SceneError {
        key_error(&self.path, &self.text, &self.overrides, key, message.into())
    }
}

fn key_error(
    path: &Path,
    text: &str,
    overrides: &[String],
    key: &str,
    message: String,
) -> SceneError {
    let from_set = overrides.iter().any(|a| {
        a.split_once('=')
            .is_some_and(|(k, _)| key.starts_with(k.trim()) || k.trim().starts_with(key))
    });
    let line = if from_set {
        None
    } else {
        locate::line_of(text, key)
    };
    SceneError::Key {
        path: path.to_path_buf(),
        line,
        from_set,
        key: key.to_string(),
        message,
    }
}

/// Read `path`, apply `overrides` (`KEY=VALUE`), type-check and validate.
///
/// # Errors
/// I/O, TOML syntax, unknown/missing/mistyped keys, values out of range: each
/// names the file, the line (when the key is in the file) and the key.
pub fn load(path: &Path, overrides: &[String]) -> Result<LoadedScene, SceneError> {
    let text = plugins_api::input_file::read_text(path, plugins_api::input_file::TEXT_LIMIT)
        .map_err(|source| SceneError::Io {
            path: path.to_path_buf(),
            source,
        })?;
    parse(&text, path, overrides)
}

/// [`load`] from text (`path` names the file in messages and anchors relative paths).
///
/// # Errors
/// As [`load`].
pub fn parse(text: &str, path: &Path, overrides: &[String]) -> Result<LoadedScene, SceneError> {
    let mut table: toml::Table = toml::from_str(text).map_err(|e| SceneError::Syntax {
        path: path.to_path_buf(),
        line: e.span().map_or(1, |s| locate::line_at(text, s.start)),
        message: e.message().trim().to_string(),
    })?;
    for assignment in overrides {
        let (key, value) = overrides::parse_assignment(assignment)?;
        overrides::apply(&mut table, &key, value, assignment)?;
    }
    // The reference checks' tables, apart from `[output]`'s own keys.
    let checks = kind::reference_checks();
    let tables = check_table::take_tables(&mut table, &checks);
    let mut scene: Scene =
        serde_path_to_error::deserialize(toml::Value::Table(table)).map_err(|e| {
            let key = e.path().to_string();
            let message = e.inner().message().trim().to_string();
            key_error(path, text, overrides, &key, message)
        })?;
    scene.output.checks = check_table::resolve_all(&tables, &checks)
        .map_err(|e| key_error(path, text, overrides, &e.key, e.message))?;
    let loaded = LoadedScene {
        scene,
        path: path.to_path_buf(),
        text: text.to_string(),
        overrides: overrides.to_vec(),
    };
    validate::validate(&loaded)?;
    Ok(loaded)
}
