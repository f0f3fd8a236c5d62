//! Reading a user's file safely: only a regular file (not a device, a FIFO
//! or a directory, which can block or never end), and at most a stated
//! number of bytes, checked before anything is read and again while
//! reading (a file that grows, a `/proc` file that reports no size).
//! Every crate that reads a file a user names (scenes, meshes, tool specs,
//! histories, measurements, plugins) goes through here.

use std::io::Read;
use std::path::Path;

/// Largest text file read as a scene, tool spec, history or measurements
/// (bytes): 64 MiB, some hundred times the largest shipped.
pub const TEXT_LIMIT: u64 = 64 << 20;
/// Largest mesh file (`.inp`, `.msh`, `.stl`, `.obj`) read (bytes): 1 GiB,
/// about ten million nodes in text.
pub const MESH_LIMIT: u64 = 1 << 30;

/// Why a file was not read.
#[derive(Debug, thiserror::Error)]
pub enum InputFileError {
    /// The path does not exist.
    #[error("file not found")]
    NotFound,
    /// Not a regular file.
    #[error("is {0}, not a regular file")]
    NotRegular(&'static str),
    /// Larger than the limit.
    #[error("{size} bytes, more than the {limit} bytes a file of this kind may have")]
    TooLarge {
        /// Size found (bytes; at least `limit + 1` for a file read past it).
        size: u64,
        /// The limit (bytes).
        limit: u64,
    },
    /// Not UTF-8 text.
    #[error("is not UTF-8 text")]
    NotText,
    /// Any other error of the system.
    #[error("cannot read the file: {0}")]
    Io(#[from] std::io::Error),
}

/// Check that `path` names a regular file (following links) of at most
/// `limit` bytes, without opening it.
///
/// # Errors
/// [`InputFileError`]: not found, not a regular file, too large, or the
/// system's error.
pub fn check(path: &Path, limit: u64) -> Result<(), InputFileError> {
    let meta = std::fs::metadata(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => InputFileError::NotFound,
        _ => InputFileError::Io(e),
    })?;
    if !meta.is_file() {
        return Err(InputFileError::NotRegular(kind_of(&meta)));
    }
    if meta.len() > limit {
        return Err(InputFileError::TooLarge {
            size: meta.len(),
            limit,
        });
    }
    Ok(())
}

/// Read at most `limit` bytes of the regular file `path`.
///
/// # Errors
/// As [`check`], and a file that grows past `limit` while it is read.
pub fn read_bytes(path: &Path, limit: u64) -> Result<Vec<u8>, InputFileError> {
    check(path, limit)?;
    let file = std::fs::File::open(path)?;
    let mut bytes = Vec::new();
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(InputFileError::TooLarge {
            size: bytes.len() as u64,
            limit,
        });
    }
    Ok(bytes)
}

/// Read the regular file `path` as UTF-8 text of at most `limit` bytes.
///
/// # Errors
/// As [`read_bytes`], and text that is not UTF-8.
pub fn read_text(path: &Path, limit: u64) -> Result<String, InputFileError> {
    String::from_utf8(read_bytes(path, limit)?).map_err(|_| InputFileError::NotText)
}

/// What a file that is not regular is, for the message.
fn kind_of(meta: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = meta.file_type();
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if meta.is_dir() {
        "a directory"
    } else {
        "not a regular file"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Devices and directories are refused before they are opened (reading
    /// /dev/zero never ends); a file over the limit is refused by its size;
    /// a regular file within it reads.
    #[test]
    fn only_regular_files_within_the_limit_are_read() {
        let e = read_text(Path::new("/dev/zero"), TEXT_LIMIT).unwrap_err();
        assert_eq!(e.to_string(), "is a character device, not a regular file");
        let e = read_text(Path::new("/"), TEXT_LIMIT).unwrap_err();
        assert_eq!(e.to_string(), "is a directory, not a regular file");
        let e = read_text(Path::new("/no/such/file"), TEXT_LIMIT).unwrap_err();
        assert_eq!(e.to_string(), "file not found");
        let dir = std::env::temp_dir().join(format!("input-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.txt");
        std::fs::write(&p, "0123456789").unwrap();
        assert_eq!(read_text(&p, 10).unwrap(), "0123456789");
        let e = read_text(&p, 9).unwrap_err();
        assert!(
            e.to_string().starts_with("10 bytes, more than the 9"),
            "{e}"
        );
        std::fs::write(&p, [0xff, 0xfe]).unwrap();
        assert!(matches!(read_text(&p, 10), Err(InputFileError::NotText)));
        std::fs::remove_dir_all(&dir).ok();
    }
}
