//! The journal of a batch: `DIR/journal/batch.json` says what the batch is
//! (formsim's version and build, the command, the scene's text, the
//! arguments that decide its runs), and every finished run is a file
//! `DIR/journal/runs/LABEL.json` (its spec and its [`Record`]), written
//! whole and renamed into place as the run ends. A second call with the
//! same arguments reads them back and runs only what is missing or failed;
//! a call with other arguments is refused rather than mixing results
//! (`--fresh` starts over).

use super::{BatchError, JobSpec, Record};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// What the runs of a journal depend on.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Context {
    /// formsim's version.
    pub version: String,
    /// A fingerprint of the running executable ([`build_fingerprint`]).
    pub build: String,
    /// The command (`compare`, `study`).
    pub command: String,
    /// The scene file's text.
    pub scene_text: String,
    /// The arguments that decide the runs and what is taken from them.
    pub args: Vec<String>,
}

impl Context {
    /// The context of `command` on `scene` with `args`.
    ///
    /// # Errors
    /// The scene cannot be read.
    pub fn new(command: &str, scene: &Path, args: Vec<String>) -> Result<Self, BatchError> {
        let scene_text = std::fs::read_to_string(scene).map_err(|e| io_error(scene, e))?;
        Ok(Self {
            version: env!("CARGO_PKG_VERSION").into(),
            build: build_fingerprint(),
            command: command.into(),
            scene_text,
            args,
        })
    }
}

/// One journalled run.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Entry {
    spec: JobSpec,
    record: Record,
}

/// The journal on disk and in memory.
#[derive(Debug)]
pub struct Journal {
    runs: PathBuf,
    entries: Mutex<BTreeMap<String, Entry>>,
}

/// The journal's folder in an output folder.
pub fn folder(out: &Path) -> PathBuf {
    out.join("journal")
}

/// The folder, under the journal's, of the runs of `out` whose files are
/// not kept (a study's repeated runs): removed with the journal.
pub fn scratch(out: &Path) -> PathBuf {
    folder(out).join("scratch")
}

/// Whether `out` holds a batch journal.
pub fn exists(out: &Path) -> bool {
    folder(out).join("batch.json").is_file()
}

/// Remove the journal of `out` (its context, its runs' files and its
/// [`scratch`] folder; a folder left empty goes too).
///
/// # Errors
/// A file cannot be removed.
pub fn remove(out: &Path) -> Result<(), BatchError> {
    let dir = folder(out);
    let runs = dir.join("runs");
    if runs.is_dir() {
        for item in std::fs::read_dir(&runs).map_err(|e| io_error(&runs, e))? {
            let path = item.map_err(|e| io_error(&runs, e))?.path();
            if path.is_file() && path.extension().is_some_and(|x| x == "json" || x == "tmp") {
                std::fs::remove_file(&path).map_err(|e| io_error(&path, e))?;
            }
        }
        let _ = std::fs::remove_dir(&runs);
    }
    let scratch = scratch(out);
    if scratch.is_dir() {
        std::fs::remove_dir_all(&scratch).map_err(|e| io_error(&scratch, e))?;
    }
    let context = dir.join("batch.json");
    if context.is_file() {
        std::fs::remove_file(&context).map_err(|e| io_error(&context, e))?;
    }
    let _ = std::fs::remove_dir(&dir);
    Ok(())
}

fn io_error(path: &Path, e: impl std::fmt::Display) -> BatchError {
    BatchError::Journal(format!("{}: {e}", path.display()))
}

impl Journal {
    /// Open (or start) the journal of `out` for `context`.
    ///
    /// # Errors
    /// The folder cannot be made or read; it holds the journal of another
    /// batch (the message says what differs); an entry does not parse.
    pub fn open(out: &Path, context: &Context) -> Result<Self, BatchError> {
        let dir = folder(out);
        let runs = dir.join("runs");
        std::fs::create_dir_all(&runs).map_err(|e| io_error(&runs, e))?;
        let context_path = dir.join("batch.json");
        if context_path.exists() {
            let text =
                std::fs::read_to_string(&context_path).map_err(|e| io_error(&context_path, e))?;
            let old: Context =
                serde_json::from_str(&text).map_err(|e| io_error(&context_path, e))?;
            if old != *context {
                return Err(BatchError::Journal(format!(
                    "{} exists and holds the results of another batch ({}); pass --force (or --fresh) to replace them, or use another --out",
                    out.display(),
                    difference(&old, context)
                )));
            }
        } else {
            let text =
                serde_json::to_string_pretty(context).map_err(|e| io_error(&context_path, e))?;
            write_atomic(&context_path, &text)?;
        }
        let mut entries = BTreeMap::new();
        for item in std::fs::read_dir(&runs).map_err(|e| io_error(&runs, e))? {
            let path = item.map_err(|e| io_error(&runs, e))?.path();
            if path.extension().is_none_or(|x| x != "json") {
                continue;
            }
            let text = std::fs::read_to_string(&path).map_err(|e| io_error(&path, e))?;
            let entry: Entry = serde_json::from_str(&text).map_err(|e| io_error(&path, e))?;
            entries.insert(entry.spec.label.clone(), entry);
        }
        Ok(Self {
            runs,
            entries: Mutex::new(entries),
        })
    }

    /// The finished record of `spec` (same label, same overrides, same
    /// folder), if the journal holds one that did not fail.
    pub fn finished(&self, spec: &JobSpec) -> Option<Record> {
        let entries = self.lock();
        let e = entries.get(&spec.label)?;
        (e.spec.sets == spec.sets && e.spec.out == spec.out && e.record.outcome.is_ok())
            .then(|| e.record.clone())
    }

    /// How many runs the journal holds (finished or failed).
    pub fn len(&self) -> usize {
        self.lock().len()
    }

    /// Whether the journal holds no run.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Record a run as it ends (a failure too: it is run again next time).
    ///
    /// # Errors
    /// The file cannot be written.
    pub fn record(&self, spec: &JobSpec, record: &Record) -> Result<(), BatchError> {
        let entry = Entry {
            spec: spec.clone(),
            record: record.clone(),
        };
        let path = self.runs.join(format!("{}.json", file_name(&spec.label)));
        let text = serde_json::to_string(&entry).map_err(|e| io_error(&path, e))?;
        write_atomic(&path, &text)?;
        self.lock().insert(spec.label.clone(), entry);
        Ok(())
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, BTreeMap<String, Entry>> {
        self.entries
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}

/// A label as a file name: characters other than letters, digits, `-`,
/// `_`, `.` become `_`, and `/` becomes `+`.
fn file_name(label: &str) -> String {
    label
        .chars()
        .map(|c| match c {
            '/' => '+',
            c if c.is_ascii_alphanumeric() || "-_.".contains(c) => c,
            _ => '_',
        })
        .collect()
}

/// A fingerprint of the running executable's bytes (the standard library's
/// default hasher with its fixed keys, hex), or `unknown` when it cannot be
/// read. Only compared between calls on the same machine, so the hash need
/// not be stable across Rust versions.
pub fn build_fingerprint() -> String {
    use std::hash::Hasher;
    static FINGERPRINT: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    FINGERPRINT
        .get_or_init(|| {
            let Some(bytes) = std::env::current_exe()
                .ok()
                .and_then(|p| std::fs::read(p).ok())
            else {
                return "unknown".into();
            };
            let mut h = std::collections::hash_map::DefaultHasher::new();
            h.write(&bytes);
            format!("{:016x}", h.finish())
        })
        .clone()
}

/// Write `text` to `path` through a temporary file and a rename, so that a
/// kill leaves either the whole file or none.
///
/// # Errors
/// The file cannot be written or renamed.
pub fn write_atomic(path: &Path, text: &str) -> Result<(), BatchError> {
    let tmp = path.with_extension("json.tmp");
    std::fs::write(&tmp, text).map_err(|e| io_error(&tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| io_error(path, e))
}

/// What a journal's runs depend on whatever the command: formsim's version,
/// its build and the scene's text.
pub(crate) struct Basis<'a> {
    /// formsim's version.
    pub version: &'a str,
    /// The executable's fingerprint.
    pub build: &'a str,
    /// The scene file's text.
    pub scene_text: &'a str,
}

/// What differs between the bases of two journals, in a few words each.
pub(crate) fn basis_difference(old: &Basis<'_>, new: &Basis<'_>) -> Vec<String> {
    let mut what = Vec::new();
    if old.version != new.version {
        what.push(format!(
            "formsim {} there, {} here",
            old.version, new.version
        ));
    }
    if old.build != new.build {
        what.push("another build of formsim (its runs may differ)".into());
    }
    if old.scene_text != new.scene_text {
        what.push("another scene text".into());
    }
    what
}

impl Context {
    fn basis(&self) -> Basis<'_> {
        Basis {
            version: &self.version,
            build: &self.build,
            scene_text: &self.scene_text,
        }
    }
}

/// What differs between two contexts, in a few words.
fn difference(old: &Context, new: &Context) -> String {
    let mut what = basis_difference(&old.basis(), &new.basis());
    if old.command != new.command {
        what.push(format!("formsim {} there", old.command));
    }
    if old.args != new.args {
        what.push("other arguments".into());
    }
    what.join("; ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn context(args: &[&str]) -> Context {
        Context {
            version: "0".into(),
            build: "b".into(),
            command: "compare".into(),
            scene_text: "x".into(),
            args: args.iter().map(|s| s.to_string()).collect(),
        }
    }

    fn spec(label: &str, set: &str) -> JobSpec {
        JobSpec {
            label: label.into(),
            sets: vec![set.into()],
            out: PathBuf::from("o").join(label),
            estimate: 1.0,
        }
    }

    fn record(label: &str, outcome: Result<f64, &str>) -> Record {
        Record {
            label: label.into(),
            outcome: outcome.map(|v| serde_json::json!(v)).map_err(String::from),
            cpu_s: 1.5,
            wall_s: 2.5,
            started_s: 0.1,
        }
    }

    #[test]
    fn a_journal_reopens_with_its_finished_runs_and_refuses_another_batch() {
        let dir = tempfile::tempdir().unwrap();
        let j = Journal::open(dir.path(), &context(&["--law", "ac"])).unwrap();
        assert!(j.is_empty());
        let (a, b) = (spec("ac-convective", "k=1"), spec("ac/jaumann", "k=2"));
        j.record(&a, &record("ac-convective", Ok(0.1 + 0.2)))
            .unwrap();
        j.record(&b, &record("ac/jaumann", Err("diverged")))
            .unwrap();
        drop(j);
        let j = Journal::open(dir.path(), &context(&["--law", "ac"])).unwrap();
        assert_eq!(j.len(), 2);
        let got = j.finished(&a).unwrap();
        assert_eq!(got, record("ac-convective", Ok(0.1 + 0.2)), "the same bits");
        assert!(j.finished(&b).is_none(), "a failed run runs again");
        assert!(
            j.finished(&spec("ac-convective", "k=3")).is_none(),
            "other overrides"
        );
        let other = Journal::open(dir.path(), &context(&["--law", "wh"])).unwrap_err();
        let message = other.to_string();
        assert!(message.contains("--fresh"), "{message}");
        assert!(message.contains("(other arguments)"), "{message}");
    }
}
