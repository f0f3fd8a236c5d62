//! The journal of an identification: every finished evaluation is a file
//! `DIR/journal/eval-NNNN.json` (written whole, then renamed into place), and
//! `DIR/journal/context.json` says what they are evaluations of. A second call
//! with the same scene, overrides, data-set overrides and fitted keys reads
//! them back and never repeats a finished run; a call with other arguments is
//! refused rather than mixing results.

use super::IdentifyError;
use super::observe::Observables;
use crate::batch::journal::{Basis, basis_difference};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// What the evaluations of a journal depend on.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Context {
    /// formsim's version.
    pub version: String,
    /// A fingerprint of the running executable ([`build_fingerprint`]): a
    /// rebuilt formsim may compute other results under the same version
    /// (empty in journals that do not record it).
    #[serde(default)]
    pub build: String,
    /// The scene file's text.
    pub scene_text: String,
    /// Overrides of every run (the command's `--set` and identify's own).
    pub overrides: Vec<String>,
    /// Each data set's name and overrides.
    pub sets: Vec<(String, Vec<String>)>,
    /// The fitted keys, in order.
    pub keys: Vec<String>,
}

/// One finished evaluation: the runs of every data set at one parameter point.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Entry {
    /// Its number (the order in which it was started).
    pub index: usize,
    /// The fitted values, in the order of the context's keys.
    pub values: Vec<f64>,
    /// Wall seconds of its runs (added over data sets).
    pub wall_s: f64,
    /// Each data set's observables, or the run's error.
    pub sets: BTreeMap<String, Result<Observables, String>>,
}

/// The journal on disk and in memory.
#[derive(Debug)]
pub struct Journal {
    dir: PathBuf,
    state: Mutex<State>,
}

#[derive(Debug, Default)]
struct State {
    by_values: HashMap<Vec<u64>, Entry>,
    next: usize,
}

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|v| v.to_bits()).collect()
}

fn io_error(path: &Path, e: impl std::fmt::Display) -> IdentifyError {
    IdentifyError::Journal(format!("{}: {e}", path.display()))
}

impl Journal {
    /// Open (or start) the journal in `dir/journal` for `context`.
    ///
    /// # Errors
    /// The directory cannot be made or read; it holds a journal of another
    /// context; an entry does not parse.
    pub fn open(dir: &Path, context: &Context) -> Result<Self, IdentifyError> {
        let dir = dir.join("journal");
        std::fs::create_dir_all(&dir).map_err(|e| io_error(&dir, e))?;
        let context_path = dir.join("context.json");
        if context_path.exists() {
            let text =
                std::fs::read_to_string(&context_path).map_err(|e| io_error(&context_path, e))?;
            let old: Context =
                serde_json::from_str(&text).map_err(|e| io_error(&context_path, e))?;
            if &old != context {
                return Err(IdentifyError::Journal(format!(
                    "{} holds the runs of another identification ({}): choose another --out or remove it",
                    dir.display(),
                    difference(&old, context)
                )));
            }
        } else {
            write_atomic(
                &context_path,
                &serde_json::to_string_pretty(context).unwrap_or_default(),
            )?;
        }
        let mut state = State::default();
        let mut names: Vec<PathBuf> = std::fs::read_dir(&dir)
            .map_err(|e| io_error(&dir, e))?
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| {
                p.file_name()
                    .and_then(|n| n.to_str())
                    .is_some_and(|n| n.starts_with("eval-") && n.ends_with(".json"))
            })
            .collect();
        names.sort();
        for path in names {
            let text = std::fs::read_to_string(&path).map_err(|e| io_error(&path, e))?;
            let entry: Entry = serde_json::from_str(&text).map_err(|e| io_error(&path, e))?;
            state.next = state.next.max(entry.index + 1);
            state.by_values.insert(bits(&entry.values), entry);
        }
        Ok(Self {
            dir,
            state: Mutex::new(state),
        })
    }

    /// The finished evaluation at exactly `values`, if any.
    pub fn get(&self, values: &[f64]) -> Option<Entry> {
        self.lock().by_values.get(&bits(values)).cloned()
    }

    /// The number of finished evaluations.
    pub fn len(&self) -> usize {
        self.lock().by_values.len()
    }

    /// Whether nothing has been evaluated.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The number the next new evaluation will get.
    pub fn next(&self) -> usize {
        self.lock().next
    }

    /// A number for a new evaluation.
    pub fn next_index(&self) -> usize {
        let mut s = self.lock();
        s.next += 1;
        s.next - 1
    }

    /// Record a finished evaluation (file first, then memory).
    ///
    /// # Errors
    /// The file cannot be written.
    pub fn record(&self, entry: Entry) -> Result<(), IdentifyError> {
        let path = self.dir.join(format!("eval-{:04}.json", entry.index));
        let text = serde_json::to_string(&entry).map_err(|e| io_error(&path, e))?;
        write_atomic(&path, &text)?;
        self.lock().by_values.insert(bits(&entry.values), entry);
        Ok(())
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        // A panic in another evaluation leaves the map consistent (inserts are whole).
        self.state
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}

/// Remove the journal of `out` (its context and its evaluations), so that
/// the next call starts over (`--fresh`); the runs' folders stay and are
/// written over.
///
/// # Errors
/// A file cannot be removed.
pub fn remove(out: &Path) -> Result<(), IdentifyError> {
    let dir = out.join("journal");
    if !dir.is_dir() {
        return Ok(());
    }
    for item in std::fs::read_dir(&dir).map_err(|e| io_error(&dir, e))? {
        let path = item.map_err(|e| io_error(&dir, e))?.path();
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        let ours = name == "context.json" || (name.starts_with("eval-") && name.contains(".json"));
        if path.is_file() && ours {
            match std::fs::remove_file(&path) {
                // Gone since the listing: what was asked.
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
                r => r.map_err(|e| io_error(&path, e))?,
            }
        }
    }
    let _ = std::fs::remove_dir(&dir);
    Ok(())
}

/// A fingerprint of the running executable (the batch engine's,
/// [`crate::batch::journal::build_fingerprint`]).
pub fn build_fingerprint() -> String {
    crate::batch::journal::build_fingerprint()
}

/// Write `text` to `path` through a temporary file and a rename, so that a
/// kill leaves either the whole file or none.
fn write_atomic(path: &Path, text: &str) -> Result<(), IdentifyError> {
    crate::batch::journal::write_atomic(path, text).map_err(IdentifyError::from)
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
    if old.overrides != new.overrides {
        what.push("other --set overrides or report strokes".into());
    }
    if old.sets != new.sets {
        what.push("other data sets".into());
    }
    if old.keys != new.keys {
        what.push(format!("fitted keys {} there", old.keys.join(", ")));
    }
    what.join("; ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn context(keys: &[&str]) -> Context {
        Context {
            version: "0".into(),
            build: "b".into(),
            scene_text: "x".into(),
            overrides: vec![],
            sets: vec![("m".into(), vec![])],
            keys: keys.iter().map(|k| k.to_string()).collect(),
        }
    }

    #[test]
    fn journal_reopens_with_its_entries_and_refuses_another_context() {
        let dir = tempfile::tempdir().unwrap();
        let c = context(&["mu"]);
        let j = Journal::open(dir.path(), &c).unwrap();
        assert!(j.is_empty());
        let i = j.next_index();
        j.record(Entry {
            index: i,
            values: vec![0.1 + 0.2],
            wall_s: 1.0,
            sets: BTreeMap::from([("m".to_string(), Err("boom".to_string()))]),
        })
        .unwrap();
        drop(j);
        let j = Journal::open(dir.path(), &c).unwrap();
        assert_eq!(j.len(), 1);
        assert!(j.get(&[0.1 + 0.2]).is_some());
        assert!(j.get(&[0.3]).is_none(), "exact bits, not a near value");
        assert_eq!(j.next_index(), 1);
        let e = Journal::open(dir.path(), &context(&["nu"]))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("another identification") && e.contains("mu"),
            "{e}"
        );
    }
}
