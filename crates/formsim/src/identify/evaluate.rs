//! Evaluations: the runs of every data set at a parameter point, their
//! simulated values and the objective, taken from the journal when they are
//! there and run in parallel when they are not.
//!
//! A batch of points is one batch of the engine ([`crate::batch`]) over its
//! (point, data set) runs: on the local executor a batch of one run gets
//! every thread for its own parallel loops, a batch of several runs shares
//! them (results are the same bits either way).

use super::IdentifyError;
use super::journal::{Context, Entry, Journal};
use super::measurements::Measurements;
use super::objective::Objective;
use super::observe::{Observables, ObserveError};
use super::params::{FitParam, assignment};
use crate::batch::{self, Executor, JobSpec, Record};
use crate::run::summary::stroke_key;
use crate::run::{Progress, RunResult};
use crate::scene;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

/// Why a data set has no predictions at an evaluated point: `set NAME: …`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("set {set}: {reason}")]
pub struct PredictionError {
    /// The data set's name.
    pub set: String,
    /// What failed.
    pub reason: PredictionFailure,
}

/// What failed for a [`PredictionError`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PredictionFailure {
    /// The run failed (its message, as the journal keeps it).
    #[error("{0}")]
    Run(String),
    /// A measured point has no simulated value.
    #[error(transparent)]
    Observe(#[from] ObserveError),
    /// The journal entry has no run of the data set.
    #[error("not in the journal entry")]
    NotJournalled,
}

/// One data set's run at a point: its observables (or the run's error)
/// and its wall seconds.
type PairRun = (Result<Observables, String>, f64);

/// One evaluated point.
#[derive(Debug, Clone)]
pub struct Evaluation {
    /// Its journal number.
    pub index: usize,
    /// The fitted values.
    pub values: Vec<f64>,
    /// The simulated value of every measured point, per data set (`Err`: the
    /// run or a lookup failed).
    pub predictions: Vec<Result<Vec<f64>, PredictionError>>,
    /// The objective (`+∞` when a prediction failed).
    pub cost: f64,
    /// Wall seconds of its runs.
    pub wall_s: f64,
    /// Whether an earlier call made it (read from the journal on resuming).
    pub from_journal: bool,
}

impl Evaluation {
    /// The first failure, if any.
    pub fn failure(&self) -> Option<&PredictionError> {
        self.predictions.iter().find_map(|p| p.as_ref().err())
    }
}

/// Runs the scene at parameter points (the objective's only way to the
/// simulation).
pub struct Evaluator<'a> {
    scene_path: PathBuf,
    overrides: Vec<String>,
    data: &'a Measurements,
    params: &'a [FitParam],
    objective: Objective,
    journal: Journal,
    executor: &'a dyn Executor,
    runs_dir: PathBuf,
    /// Every evaluation asked for, in order (repeats included).
    log: Mutex<Vec<Evaluation>>,
    bar: Option<indicatif::ProgressBar>,
    started: Instant,
    /// Journal numbers below this were made by an earlier call.
    first_new: usize,
}

impl std::fmt::Debug for Evaluator<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Evaluator")
            .field("scene", &self.scene_path)
            .field("journal", &self.journal)
            .finish_non_exhaustive()
    }
}

/// The overrides identify adds to every run: no VTK frames or plots (they
/// change no figure), and a report state at every stroke the measurements read.
pub fn run_overrides(data: &Measurements, scene_strokes: &[f64]) -> Vec<String> {
    let mut strokes: Vec<f64> = scene_strokes.to_vec();
    for s in data.strokes() {
        if !strokes.iter().any(|t| stroke_key(*t) == stroke_key(s)) {
            strokes.push(s);
        }
    }
    strokes.sort_by(f64::total_cmp);
    let list: Vec<String> = strokes.iter().map(|s| format!("{s:?}")).collect();
    vec![
        "output.frames=0".into(),
        "output.plots=false".into(),
        format!("output.report_strokes=[{}]", list.join(", ")),
    ]
}

impl<'a> Evaluator<'a> {
    /// Set up the evaluations of `params` against `data` on the scene at
    /// `scene_path` (with `sets`), journalled in `out`, run on `executor`.
    ///
    /// # Errors
    /// The scene does not load; the journal belongs to other arguments.
    pub fn new(
        scene_path: &Path,
        sets: &[String],
        data: &'a Measurements,
        params: &'a [FitParam],
        objective: Objective,
        out: &Path,
        executor: &'a dyn Executor,
    ) -> Result<Self, IdentifyError> {
        let loaded =
            scene::load(scene_path, sets).map_err(|e| IdentifyError::Scene(e.to_string()))?;
        let mut overrides = sets.to_vec();
        overrides.extend(run_overrides(data, &loaded.scene.output.report_strokes));
        let context = Context {
            version: env!("CARGO_PKG_VERSION").into(),
            build: super::journal::build_fingerprint(),
            scene_text: loaded.text.clone(),
            overrides: overrides.clone(),
            sets: data
                .sets
                .iter()
                .map(|s| (s.name.clone(), s.overrides.clone()))
                .collect(),
            keys: params.iter().map(|p| p.key.clone()).collect(),
        };
        let journal = Journal::open(out, &context)?;
        let first_new = journal.next();
        Ok(Self {
            scene_path: scene_path.to_path_buf(),
            overrides,
            data,
            params,
            objective,
            journal,
            executor,
            runs_dir: out.join("runs"),
            log: Mutex::new(Vec::new()),
            bar: None,
            started: Instant::now(),
            first_new,
        })
    }

    /// Show a progress bar of `limit` runs with the best objective so far.
    pub fn with_progress(mut self, limit: usize) -> Self {
        let style = indicatif::ProgressStyle::with_template(
            "{elapsed_precise} [{bar:30}] {pos}/{len} evaluations  {msg}",
        )
        .map(|s| s.progress_chars("=> "));
        if let Ok(style) = style {
            let bar = indicatif::ProgressBar::new(limit as u64);
            bar.set_style(style);
            self.bar = Some(bar);
        }
        self
    }

    /// The scene overrides of every run, for a data set's run at `values`.
    pub fn overrides_at(&self, set: usize, values: &[f64]) -> Vec<String> {
        let mut all = self.overrides.clone();
        all.extend(self.data.sets[set].overrides.iter().cloned());
        all.extend(
            self.params
                .iter()
                .zip(values)
                .map(|(p, v)| assignment(p, *v)),
        );
        all
    }

    /// The measurements.
    pub fn data(&self) -> &Measurements {
        self.data
    }

    /// The fitted parameters.
    pub fn params(&self) -> &[FitParam] {
        self.params
    }

    /// The objective.
    pub fn objective(&self) -> Objective {
        self.objective
    }

    /// The journal entry (observables of every data set) at exactly `values`.
    pub fn entry(&self, values: &[f64]) -> Option<Entry> {
        self.journal.get(values)
    }

    /// Every evaluation asked for so far, in order.
    pub fn log(&self) -> Vec<Evaluation> {
        self.log.lock().map(|l| l.clone()).unwrap_or_default()
    }

    /// The number of runs made by this call (each distinct point it ran,
    /// times the data sets).
    pub fn runs_made(&self) -> usize {
        (self.journal.next() - self.first_new) * self.data.sets.len()
    }

    /// The number of distinct points evaluated in this call, and how many of
    /// them an earlier call had made.
    pub fn distinct(&self) -> (usize, usize) {
        let log = self.log();
        let mut seen: Vec<usize> = log.iter().map(|e| e.index).collect();
        seen.sort_unstable();
        seen.dedup();
        let earlier = seen.iter().filter(|i| **i < self.first_new).count();
        (seen.len(), earlier)
    }

    /// Wall seconds since the evaluator was made.
    pub fn elapsed_s(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    /// Finish the progress bar.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish();
        }
    }

    /// Evaluate one point.
    ///
    /// # Errors
    /// The journal cannot be written.
    pub fn evaluate(&self, values: &[f64]) -> Result<Evaluation, IdentifyError> {
        Ok(self
            .evaluate_batch(&[values.to_vec()])?
            .pop()
            .expect("one evaluation per point"))
    }

    /// Evaluate several points: those in the journal are read, the others
    /// run in parallel and are journalled.
    ///
    /// # Errors
    /// The journal cannot be written.
    pub fn evaluate_batch(&self, points: &[Vec<f64>]) -> Result<Vec<Evaluation>, IdentifyError> {
        let mut entries: Vec<Option<Entry>> = points.iter().map(|p| self.journal.get(p)).collect();
        // Each missing point once, even if the batch repeats it.
        let mut missing: Vec<(usize, Vec<f64>)> = Vec::new();
        for (i, p) in points.iter().enumerate() {
            if entries[i].is_none() && !missing.iter().any(|(_, q)| q == p) {
                missing.push((self.journal.next_index(), p.clone()));
            }
        }
        let pairs: Vec<(usize, usize)> = (0..missing.len())
            .flat_map(|m| (0..self.data.sets.len()).map(move |s| (m, s)))
            .collect();
        let results = self.run_pairs(&missing, &pairs)?;
        for (m, (index, values)) in missing.iter().enumerate() {
            let mut sets = BTreeMap::new();
            let mut wall_s = 0.0;
            for (&(mm, s), (obs, wall)) in pairs.iter().zip(&results) {
                if mm == m {
                    sets.insert(self.data.sets[s].name.clone(), obs.clone());
                    wall_s += wall;
                }
            }
            let entry = Entry {
                index: *index,
                values: values.clone(),
                wall_s,
                sets,
            };
            self.journal.record(entry.clone())?;
            for (i, p) in points.iter().enumerate() {
                if entries[i].is_none() && p == values {
                    entries[i] = Some(entry.clone());
                }
            }
        }
        let evaluations: Vec<Evaluation> = entries
            .into_iter()
            .map(|e| {
                let entry = e.expect("every point evaluated");
                self.score(&entry, entry.index < self.first_new)
            })
            .collect();
        self.note(&evaluations);
        Ok(evaluations)
    }

    /// The runs of the `(point, data set)` pairs of `missing` points on the
    /// executor: each one's observables (or error) and wall seconds.
    fn run_pairs(
        &self,
        missing: &[(usize, Vec<f64>)],
        pairs: &[(usize, usize)],
    ) -> Result<Vec<PairRun>, IdentifyError> {
        let jobs: Vec<JobSpec> = pairs
            .iter()
            .map(|&(m, set)| {
                let (index, values) = (missing[m].0, &missing[m].1);
                let name = &self.data.sets[set].name;
                JobSpec {
                    label: format!("eval-{index:04}/{name}"),
                    sets: self.overrides_at(set, values),
                    out: self.runs_dir.join(format!("eval-{index:04}")).join(name),
                    estimate: 1.0,
                }
            })
            .collect();
        let extract = |r: &RunResult| {
            let o = Observables::from_run(r).map_err(|e| e.to_string())?;
            serde_json::to_value(o).map_err(|e| e.to_string())
        };
        let clock = self.started;
        let work = |_: usize, spec: &JobSpec| {
            let scene = batch::Scene::File(&self.scene_path);
            batch::run_job(scene, spec, Progress::Hidden, clock, &extract)
        };
        let mut records: Vec<Option<Record>> = vec![None; jobs.len()];
        self.executor
            .run(&jobs, &work, &mut |i, r| records[i] = Some(r))?;
        Ok(records
            .into_iter()
            .map(|r| match r {
                Some(r) => {
                    let obs = r.outcome.and_then(|v| {
                        serde_json::from_value::<Observables>(v).map_err(|e| e.to_string())
                    });
                    (obs, r.wall_s)
                }
                None => (Err("the executor lost the run".into()), 0.0),
            })
            .collect())
    }

    /// Predictions and objective of a journal entry.
    fn score(&self, entry: &Entry, from_journal: bool) -> Evaluation {
        let predictions: Vec<Result<Vec<f64>, PredictionError>> = self
            .data
            .sets
            .iter()
            .map(|set| {
                let reason = match entry.sets.get(&set.name) {
                    Some(Ok(obs)) => match obs.predict(set) {
                        Ok(p) => return Ok(p),
                        Err(e) => PredictionFailure::Observe(e),
                    },
                    Some(Err(e)) => PredictionFailure::Run(e.clone()),
                    None => PredictionFailure::NotJournalled,
                };
                Err(PredictionError {
                    set: set.name.clone(),
                    reason,
                })
            })
            .collect();
        let cost = self.objective.cost(self.data, &predictions);
        Evaluation {
            index: entry.index,
            values: entry.values.clone(),
            predictions,
            cost,
            wall_s: entry.wall_s,
            from_journal,
        }
    }

    /// Log evaluations and move the bar.
    fn note(&self, evaluations: &[Evaluation]) {
        let Ok(mut log) = self.log.lock() else {
            return;
        };
        log.extend(evaluations.iter().cloned());
        if let Some(bar) = &self.bar {
            let best = log.iter().map(|e| e.cost).fold(f64::INFINITY, f64::min);
            bar.set_position(log.len() as u64);
            let journal = log
                .iter()
                .filter(|e| e.from_journal)
                .map(|e| e.index)
                .collect::<std::collections::BTreeSet<_>>()
                .len();
            bar.set_message(format!(
                "best {} = {best:.5}{}",
                self.objective.name(),
                if journal > 0 {
                    format!(" ({journal} from an earlier call)")
                } else {
                    String::new()
                }
            ));
        }
    }
}
