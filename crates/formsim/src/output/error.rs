//! The error type of run outputs: one readable line naming the file and the problem.

use std::path::{Path, PathBuf};

/// Why an output file could not be written.
///
/// Every message is one line and names the file concerned, so the CLI can
/// print it as is.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The file or its directory could not be created or written.
    #[error("{}: cannot write: {source}", path.display())]
    Io {
        /// The file (or directory) that failed.
        path: PathBuf,
        /// The operating-system error.
        #[source]
        source: std::io::Error,
    },
    /// The data handed to the writer is inconsistent or not finite; `what`
    /// already names the file, the field, the index and the value.
    #[error("{what}")]
    Invalid {
        /// One-line description, starting with the file path.
        what: String,
    },
    /// The VTK library refused to encode the data set.
    #[error("{}: cannot encode VTK data: {message}", path.display())]
    Vtk {
        /// The file being written.
        path: PathBuf,
        /// The library's message.
        message: String,
    },
    /// The plotting library failed (missing font, drawing or PNG encoding).
    #[error("{}: cannot draw plot: {message}", path.display())]
    Plot {
        /// The image being written.
        path: PathBuf,
        /// The library's message.
        message: String,
    },
}

impl OutputError {
    /// An [`OutputError::Invalid`] whose message starts with `path`.
    pub fn invalid(path: &Path, what: impl std::fmt::Display) -> Self {
        OutputError::Invalid {
            what: format!("{}: {what}", path.display()),
        }
    }

    /// An [`OutputError::Io`] for `path`.
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        OutputError::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}

/// Create the parent directory of `path` if it has one and it is missing.
pub(crate) fn create_parent_dir(path: &Path) -> Result<(), OutputError> {
    match path.parent().filter(|d| !d.as_os_str().is_empty()) {
        Some(dir) => std::fs::create_dir_all(dir).map_err(|e| OutputError::io(dir, e)),
        None => Ok(()),
    }
}
