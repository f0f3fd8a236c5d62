//! The output directory of `formsim run` and `formsim compare`: refuse to
//! write over earlier results, or with `--force` remove exactly what formsim
//! wrote there before (so that no stale file, e.g. a VTK frame of a longer
//! earlier run, survives beside the new ones), keeping every other file.
//!
//! What formsim owns in a run's directory: the files [`RUN_FILES`] and, in
//! the folders of [`RUN_FOLDERS`], the files with that folder's extension; a
//! folder left empty is removed. In a comparison's directory: [`COMPARE_FILES`],
//! `plots/*.png`, and each sub-folder that is one of the comparison's rows or
//! holds a run's results, cleaned as a run's directory. In a study's
//! directory: [`STUDY_FILES`] and its variants' folders, the same way.

use std::path::{Path, PathBuf};

/// Why the output directory cannot be made ready ([`prepare`]); each message
/// is one line naming the path.
#[derive(Debug, thiserror::Error)]
pub enum OutDirError {
    /// The directory or one of its entries cannot be read.
    #[error("{path}: {source}")]
    Io {
        /// The directory.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The path exists and is not a directory.
    #[error("{path} exists and is not a directory")]
    NotDirectory {
        /// The path.
        path: PathBuf,
    },
    /// The directory holds earlier results and `--force` was not given.
    #[error("{path} exists and holds results; pass --force to replace them")]
    HoldsResults {
        /// The directory.
        path: PathBuf,
    },
    /// The directory holds other files and `--force` was not given.
    #[error(
        "{path} exists and holds other files; pass --force to write results into it \
         (those files are kept)"
    )]
    HoldsOtherFiles {
        /// The directory.
        path: PathBuf,
    },
    /// A file or folder cannot be removed.
    #[error("cannot remove {path}: {source}")]
    Remove {
        /// The file or folder.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
}

impl OutDirError {
    fn io(path: &Path) -> impl FnOnce(std::io::Error) -> Self + '_ {
        |source| Self::Io {
            path: path.to_path_buf(),
            source,
        }
    }

    fn remove(path: &Path) -> impl FnOnce(std::io::Error) -> Self + '_ {
        |source| Self::Remove {
            path: path.to_path_buf(),
            source,
        }
    }
}

/// Files a run writes at the top of its directory.
pub const RUN_FILES: &[&str] = &[
    "summary.json",
    "blank.pvd",
    "energy.csv",
    "punch_force.csv",
    "tools.csv",
];

/// Folders a run writes, each with the extension of the files it puts there.
pub const RUN_FOLDERS: &[(&str, &str)] = &[
    ("sections", "csv"),
    ("profiles", "csv"),
    ("vtk", "vtu"),
    ("plots", "png"),
];

/// Files a comparison writes at the top of its directory (besides `plots/`
/// and one folder per row).
pub const COMPARE_FILES: &[&str] = &["compare.md", "compare.csv"];

/// Files a study writes at the top of its directory (besides one folder per variant).
pub const STUDY_FILES: &[&str] = &["study.md", "study.json", "pareto.png", "times.png"];

/// What is about to be written into the directory.
#[derive(Debug, Clone, Copy)]
pub enum Owner<'a> {
    /// One run (`formsim run`).
    Run,
    /// A comparison (`formsim compare`) whose rows have these labels.
    Compare(&'a [String]),
    /// A study (`formsim study`) whose variants have these labels.
    Study(&'a [String]),
}

/// Make `dir` ready for new results of `owner`.
///
/// A missing or empty directory is ready. Otherwise, without `replace`, it
/// is refused; with `replace`, what formsim owns in it is removed (see the
/// [module docs](self)) and everything else kept.
///
/// # Errors
/// One line: `dir` is not a directory; it holds results or other files and
/// `replace` is false (the message says to pass `--force`); a file cannot be
/// read or removed.
pub fn prepare(dir: &Path, owner: Owner<'_>, replace: bool) -> Result<(), OutDirError> {
    let meta = match std::fs::metadata(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(OutDirError::io(dir)(e)),
        Ok(m) => m,
    };
    let path = dir.to_path_buf();
    if !meta.is_dir() {
        return Err(OutDirError::NotDirectory { path });
    }
    let empty = std::fs::read_dir(dir)
        .map_err(OutDirError::io(dir))?
        .next()
        .is_none();
    if empty {
        return Ok(());
    }
    if !replace {
        return Err(if holds_results(dir, owner)? {
            OutDirError::HoldsResults { path }
        } else {
            OutDirError::HoldsOtherFiles { path }
        });
    }
    match owner {
        Owner::Run => clean_run(dir),
        Owner::Compare(labels) => clean_compare(dir, labels),
        Owner::Study(labels) => clean_batch(dir, STUDY_FILES, labels),
    }
}

/// Whether `dir` holds anything `owner` would write.
fn holds_results(dir: &Path, owner: Owner<'_>) -> Result<bool, OutDirError> {
    Ok(match owner {
        Owner::Run => holds_run(dir),
        Owner::Compare(labels) => {
            COMPARE_FILES.iter().any(|f| dir.join(f).exists())
                || dir.join("plots").exists()
                || !run_folders(dir, labels)?.is_empty()
        }
        Owner::Study(labels) => {
            STUDY_FILES.iter().any(|f| dir.join(f).exists())
                || !run_folders(dir, labels)?.is_empty()
        }
    })
}

/// Whether `dir` holds a file or folder that a run writes.
fn holds_run(dir: &Path) -> bool {
    RUN_FILES
        .iter()
        .chain(RUN_FOLDERS.iter().map(|(f, _)| f))
        .any(|name| dir.join(name).exists())
}

/// The sub-folders of a comparison's `dir` that belong to it: a row's label,
/// or a folder holding a run's `summary.json` (an earlier comparison's row;
/// a folder with only plots or CSV files of the user's own is not one).
fn run_folders(dir: &Path, labels: &[String]) -> Result<Vec<PathBuf>, OutDirError> {
    let mut found = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(OutDirError::io(dir))? {
        let entry = entry.map_err(OutDirError::io(dir))?;
        let path = entry.path();
        let is_dir = entry.file_type().is_ok_and(|t| t.is_dir());
        let is_row = labels.iter().any(|l| entry.file_name() == l.as_str());
        if is_dir && (is_row || path.join("summary.json").is_file()) {
            found.push(path);
        }
    }
    Ok(found)
}

/// Remove the file `path` if it is there.
fn remove_file(path: &Path) -> Result<(), OutDirError> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(OutDirError::remove(path)(e)),
        _ => Ok(()),
    }
}

/// Remove the files of `folder` whose extension is `ext`, then the folder if
/// that left it empty. A symbolic link or a file in its place is left alone.
fn clean_folder(folder: &Path, ext: &str) -> Result<(), OutDirError> {
    if !std::fs::symlink_metadata(folder).is_ok_and(|m| m.is_dir()) {
        return Ok(());
    }
    for entry in std::fs::read_dir(folder).map_err(OutDirError::io(folder))? {
        let path = entry.map_err(OutDirError::io(folder))?.path();
        if path.is_file() && path.extension().is_some_and(|x| x == ext) {
            remove_file(&path)?;
        }
    }
    remove_if_empty(folder)
}

/// Remove `folder` if it is an empty directory.
fn remove_if_empty(folder: &Path) -> Result<(), OutDirError> {
    let empty = std::fs::read_dir(folder)
        .map_err(OutDirError::io(folder))?
        .next()
        .is_none();
    if empty {
        std::fs::remove_dir(folder).map_err(OutDirError::remove(folder))?;
    }
    Ok(())
}

/// Remove a run's files from `dir`.
fn clean_run(dir: &Path) -> Result<(), OutDirError> {
    for name in RUN_FILES {
        remove_file(&dir.join(name))?;
    }
    for (name, ext) in RUN_FOLDERS {
        clean_folder(&dir.join(name), ext)?;
    }
    Ok(())
}

/// Remove a comparison's files from `dir`: its table, its plots and its rows.
fn clean_compare(dir: &Path, labels: &[String]) -> Result<(), OutDirError> {
    clean_folder(&dir.join("plots"), "png")?;
    clean_batch(dir, COMPARE_FILES, labels)
}

/// Remove the `files` of a batch of runs (a comparison, a study) from `dir`,
/// and its runs' folders.
fn clean_batch(dir: &Path, files: &[&str], labels: &[String]) -> Result<(), OutDirError> {
    for name in files {
        remove_file(&dir.join(name))?;
    }
    for folder in run_folders(dir, labels)? {
        clean_run(&folder)?;
        remove_if_empty(&folder)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn touch(dir: &Path, name: &str) {
        let path = dir.join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, "x").unwrap();
    }

    #[test]
    fn missing_or_empty_directories_are_ready() {
        let dir = tempfile::tempdir().unwrap();
        prepare(&dir.path().join("new"), Owner::Run, false).unwrap();
        prepare(dir.path(), Owner::Run, false).unwrap();
        prepare(dir.path(), Owner::Compare(&[]), false).unwrap();
    }

    #[test]
    fn a_file_in_place_of_the_directory_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        touch(dir.path(), "f");
        let e = prepare(&dir.path().join("f"), Owner::Run, true)
            .unwrap_err()
            .to_string();
        assert!(e.ends_with("exists and is not a directory"), "{e}");
    }

    #[test]
    fn other_files_alone_are_refused_with_their_own_message() {
        let dir = tempfile::tempdir().unwrap();
        touch(dir.path(), "notes.txt");
        let e = prepare(dir.path(), Owner::Run, false)
            .unwrap_err()
            .to_string();
        assert!(e.contains("holds other files; pass --force"), "{e}");
        prepare(dir.path(), Owner::Run, true).unwrap();
        assert!(dir.path().join("notes.txt").is_file());
    }

    #[test]
    fn replacing_a_run_keeps_files_formsim_did_not_write() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        for f in [
            "summary.json",
            "tools.csv",
            "vtk/blank_0099.vtu",
            "vtk/readme.md",
            "plots/energies.png",
            "sections/OD.csv",
            "notes.txt",
        ] {
            touch(d, f);
        }
        let e = prepare(d, Owner::Run, false).unwrap_err().to_string();
        assert!(e.ends_with("exists and holds results; pass --force to replace them"));
        prepare(d, Owner::Run, true).unwrap();
        let mut left: Vec<String> = walk(d);
        left.sort();
        assert_eq!(left, ["notes.txt", "vtk", "vtk/readme.md"]);
    }

    #[test]
    fn replacing_a_comparison_cleans_its_rows_and_table() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        for f in [
            "compare.md",
            "compare.csv",
            "plots/OD.png",
            "ac-convective/summary.json",
            "ac-convective/vtk/blank_0001.vtu",
            "old-row/summary.json",
            "old-row/energy.csv",
            "mine/notes.txt",
            "docs/plots/figure.png",
            "docs/energy.csv",
        ] {
            touch(d, f);
        }
        std::fs::create_dir(d.join("wh-jaumann")).unwrap();
        let labels = ["wh-jaumann".to_string()];
        let e = prepare(d, Owner::Compare(&labels), false)
            .unwrap_err()
            .to_string();
        assert!(e.contains("holds results"), "{e}");
        prepare(d, Owner::Compare(&labels), true).unwrap();
        // A folder with a run's files but no summary.json is the user's.
        let mut left = walk(d);
        left.sort();
        assert_eq!(
            left,
            [
                "docs",
                "docs/energy.csv",
                "docs/plots",
                "docs/plots/figure.png",
                "mine",
                "mine/notes.txt"
            ]
        );
    }

    #[test]
    fn replacing_a_study_cleans_its_reports_and_variants() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        for f in [
            "study.md",
            "study.json",
            "pareto.png",
            "reference/summary.json",
            "divisions-25/energy.csv",
            "notes.txt",
        ] {
            touch(d, f);
        }
        let labels = ["reference".to_string(), "divisions-25".to_string()];
        let e = prepare(d, Owner::Study(&labels), false)
            .unwrap_err()
            .to_string();
        assert!(e.contains("holds results"), "{e}");
        prepare(d, Owner::Study(&labels), true).unwrap();
        assert_eq!(walk(d), ["notes.txt"]);
    }

    /// Every path under `dir`, relative, sorted.
    fn walk(dir: &Path) -> Vec<String> {
        let mut out = Vec::new();
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            if p.is_dir() {
                let inner = walk(&p);
                out.push(name.clone());
                out.extend(inner.into_iter().map(|i| format!("{name}/{i}")));
            } else {
                out.push(name);
            }
        }
        out.sort();
        out
    }
}
