//! Scene errors: each names the file, the line when the key is in the file, and the key.

use std::path::PathBuf;

/// What went wrong reading, checking or building a scene.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: plugins_api::input_file::InputFileError,
    },
    /// The file is not valid TOML.
    #[error("{path}:{line}: {message}")]
    Syntax {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// The parser's message.
        message: String,
    },
    /// A key is missing, unknown, of the wrong type or out of range.
    #[error("{}: {key}: {message}", location(path, *line, *from_set))]
    Key {
        /// The file.
        path: PathBuf,
        /// 1-based line of the key (or of its table), when it is in the file.
        line: Option<usize>,
        /// Whether the value came from a `--set` override.
        from_set: bool,
        /// Dotted key path, e.g. `contact.pairs[0].law`.
        key: String,
        /// What is wrong, with the value and the unit.
        message: String,
    },
    /// A `--set KEY=VALUE` argument that cannot be applied.
    #[error("--set {assignment}: {message}")]
    Override {
        /// The argument as given.
        assignment: String,
        /// What is wrong.
        message: String,
    },
}

fn location(path: &std::path::Path, line: Option<usize>, from_set: bool) -> String {
    match (line, from_set) {
        (_, true) => format!("{} (value from --set)", path.display()),
        (Some(l), false) => format!("{}:{l}", path.display()),
        (None, false) => path.display().to_string(),
    }
}
