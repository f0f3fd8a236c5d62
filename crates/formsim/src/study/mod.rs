//! `formsim study`: what accuracy costs in time, on the user's own scene.
//!
//! A study varies *knobs* (any scene key, `--vary KEY=V1,V2,…`) around a
//! *reference* (one value per knob: the first listed, or `--reference`; list
//! the most accurate value first). It runs the reference and every
//! one-knob-at-a-time variant (or, with `cross`, every combination), one
//! run after the other on the same worker threads, and gives each variant
//! its error on the chosen [quantities](quantity) against the reference and
//! its cost: increments, CPU seconds and wall seconds.
//!
//! Timing on a shared machine: each run is timed whole (set-up, steps,
//! output), CPU time being the process's over the run (every thread). With
//! `repeat` > 1 the rounds visit the variants in alternate order
//! (forward, backward, …), so that a slow spell of the machine falls on
//! different variants, and each variant reports the median with the fastest
//! and slowest. Costs are compared on the median CPU time. A repeat must give
//! the same bits as the first run of its variant; a difference stops the study.
//!
//! After a one-at-a-time study, when two knobs or more each have a value
//! within the tolerance that is cheaper than the reference, the study also
//! runs that combination (`combined`), since errors do not simply add. The
//! recommendation is the cheapest completed variant whose every quantity is
//! within the tolerance and that is [`cheaper`] than the reference beyond
//! the noise (its slowest run faster than the reference's fastest). [`report`] writes `study.json` and `study.md`,
//! [`pareto`] the error-against-time plot `pareto.png`, [`bars`] the
//! relative CPU times `times.png`.

pub mod bars;
pub mod converged;
pub mod pareto;
pub mod quantity;
pub mod report;
pub mod richardson;
pub mod schedule;

use crate::batch::{BatchError, Engine};
use crate::run::RunError;
use crate::scene::{self, SceneError};
use quantity::{MeasureError, Measured, Quantity, QuantityError};
pub use schedule::VariantRun;
use schedule::{Runs, run_rounds};
use std::path::{Path, PathBuf};

/// What can go wrong in a study: its options, a variant's scene, a run, the
/// reports.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// `--vary` without `=`.
    #[error("--vary `{text}`: expected KEY=V1,V2,…")]
    VaryFormat {
        /// The argument.
        text: String,
    },
    /// `--vary` with nothing before `=`.
    #[error("--vary `{text}`: no key before `=`")]
    VaryNoKey {
        /// The argument.
        text: String,
    },
    /// `--vary` with an empty value.
    #[error("--vary `{text}`: an empty value")]
    VaryEmptyValue {
        /// The argument.
        text: String,
    },
    /// `--vary` with a value listed twice.
    #[error("--vary `{text}`: the value `{value}` is listed twice")]
    VaryRepeatedValue {
        /// The argument.
        text: String,
        /// The value.
        value: String,
    },
    /// A `--reference` part without `=`.
    #[error("--reference: `{part}` is not KEY=VALUE")]
    ReferenceFormat {
        /// The part.
        part: String,
    },
    /// A `--reference` key that is not varied.
    #[error("--reference: `{key}` is not one of the --vary keys")]
    ReferenceNotVaried {
        /// The key.
        key: String,
    },
    /// No `--vary`.
    #[error("a study needs at least one --vary KEY=V1,V2,…")]
    NoKnob,
    /// No quantity.
    #[error("a study needs at least one quantity (--quantities)")]
    NoQuantity,
    /// A key varied twice.
    #[error("--vary: the key `{key}` is varied twice")]
    KnobTwice {
        /// The key.
        key: String,
    },
    /// `--repeat 0`.
    #[error("--repeat: 0: must be at least 1")]
    RepeatZero,
    /// A tolerance that is not a positive fraction.
    #[error("--tolerance: {tolerance}: must be a positive fraction (0.02 = 2 %)")]
    Tolerance {
        /// The tolerance given.
        tolerance: f64,
    },
    /// A quantity cannot be parsed.
    #[error(transparent)]
    Quantity(#[from] MeasureError),
    /// Two variants would have the same label.
    #[error("two variants would share the folder `{label}`")]
    SharedFolder {
        /// The label.
        label: String,
    },
    /// A quantity the variant's scene does not report.
    #[error("--quantities: {label}: {message}")]
    QuantityNotReported {
        /// The variant's label.
        label: String,
        /// The quantity and what the scene reports.
        message: String,
    },
    /// A variant's scene does not load or build.
    #[error("{label}: {source}")]
    Variant {
        /// The variant's label.
        label: String,
        /// The scene's error.
        source: SceneError,
    },
    /// The output directory or a report cannot be written.
    #[error("{path}: {source}")]
    Io {
        /// The directory or file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The reference run failed.
    #[error("the reference run failed: {message}")]
    ReferenceFailed {
        /// Why (`no result` when nothing says).
        message: String,
    },
    /// A variant's quantity cannot be compared with the reference's.
    #[error("{quantity}: {source}")]
    Compare {
        /// The quantity's name.
        quantity: String,
        /// Why.
        source: MeasureError,
    },
    /// A repeated run gave other values than the first.
    #[error(
        "{label}: a repeated run gave other values than the first (the runs must be the same bits)"
    )]
    NotTheSameBits {
        /// The variant's label.
        label: String,
    },
    /// The batch engine failed (journal, executor).
    #[error(transparent)]
    Batch(#[from] BatchError),
    /// A run failed.
    #[error(transparent)]
    Run(#[from] RunError),
    /// A refinement sequence with fewer than three levels, or keys with
    /// different numbers of levels.
    #[error("--converge `{key}`: {levels} levels; a refinement sequence needs {expected}")]
    ConvergeLevels {
        /// The key.
        key: String,
        /// Its levels.
        levels: usize,
        /// What it needs (at least three, as many as the first key).
        expected: String,
    },
    /// A refinement sequence that is not geometric.
    #[error(
        "--converge `{key}`: the values must be positive numbers refined by one ratio, coarse to fine (25,50,100 or 1e-6,5e-7,2.5e-7)"
    )]
    ConvergeRatio {
        /// The key.
        key: String,
    },
    /// Two refined keys with different ratios.
    #[error(
        "--converge `{key}`: ratio {ratio}, but the first key's is {first}: every key refines by one ratio"
    )]
    ConvergeRatiosDiffer {
        /// The key.
        key: String,
        /// Its ratio.
        ratio: f64,
        /// The first key's.
        first: f64,
    },
    /// A level of the refinement sequence failed: no converged answer.
    #[error("the refinement sequence's {label} failed, so there is no converged answer: {message}")]
    LevelFailed {
        /// The level's label.
        label: String,
        /// Why.
        message: String,
    },
    /// The levels' quantities cannot be extrapolated together.
    #[error("the converged answer: {0}")]
    Converge(String),
    /// `study.json` cannot be made.
    #[error(transparent)]
    Json(#[from] serde_json::Error),
}

/// One knob: a scene key and the values it takes.
#[derive(Debug, Clone, PartialEq)]
pub struct Knob {
    /// Scene key, as for `--set` (e.g. `blank.mesh.divisions`).
    pub key: String,
    /// Values, as written after `=` (the first is the default reference);
    /// [`DEFAULT`] removes the key.
    pub values: Vec<String>,
    /// A model (`--model`: the friction law, the formulation) rather than
    /// an accuracy knob: its values are other models, not approximations
    /// of one answer, so its variants are reported apart and take no part
    /// in the combination, the recommendation or the Pareto front.
    pub model: bool,
}

impl Knob {
    /// Parse `KEY=V1,V2,…`.
    ///
    /// # Errors
    /// No `=`, an empty key, no value or an empty or repeated one.
    pub fn parse(text: &str) -> Result<Self, StudyError> {
        let (key, list) = text
            .split_once('=')
            .ok_or_else(|| StudyError::VaryFormat { text: text.into() })?;
        let key = key.trim();
        if key.is_empty() {
            return Err(StudyError::VaryNoKey { text: text.into() });
        }
        let values: Vec<String> = list.split(',').map(|v| v.trim().to_string()).collect();
        if values.iter().any(String::is_empty) {
            return Err(StudyError::VaryEmptyValue { text: text.into() });
        }
        for (i, v) in values.iter().enumerate() {
            if values[..i].contains(v) {
                return Err(StudyError::VaryRepeatedValue {
                    text: text.into(),
                    value: v.clone(),
                });
            }
        }
        Ok(Self {
            key: key.into(),
            values,
            model: false,
        })
    }
}

/// Parse `--reference "KEY=V;KEY=V"` into `(key, value)` pairs (empty
/// parts skipped).
///
/// # Errors
/// A part without `=`.
pub fn parse_reference(text: &str) -> Result<Vec<(String, String)>, StudyError> {
    text.split(';')
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .map(|part| {
            let (k, v) = part
                .split_once('=')
                .ok_or_else(|| StudyError::ReferenceFormat { part: part.into() })?;
            Ok((k.trim().to_string(), v.trim().to_string()))
        })
        .collect()
}

/// What a study runs and how it judges the variants.
#[derive(Debug, Clone)]
pub struct Spec {
    /// The knobs (at least one).
    pub knobs: Vec<Knob>,
    /// Reference values `(key, value)` replacing a knob's first value.
    pub reference: Vec<(String, String)>,
    /// The quantities compared (at least one).
    pub quantities: Vec<Quantity>,
    /// Every combination of the knobs' values instead of one knob at a time.
    pub cross: bool,
    /// Runs per variant (≥ 1), in alternating rounds.
    pub repeat: usize,
    /// Largest relative error a recommended variant may have on any quantity.
    pub tolerance: f64,
    /// Overrides for every run, applied before the knobs.
    pub sets: Vec<String>,
    /// The refinement sequence (`--converge KEY=V1,V2,V3`, coarse to fine,
    /// every key with the same levels and ratio): when given, the study
    /// runs each level with every refined key at that level's value, the
    /// knobs at their reference, extrapolates the converged answer
    /// ([`converged`]) and measures every variant, the reference too,
    /// against it.
    pub converge: Vec<Knob>,
}

/// One variant: a value for every knob.
#[derive(Debug)]
pub struct Variant {
    /// Label and output folder.
    pub label: String,
    /// `(key, value)` for every knob, in the knobs' order.
    pub settings: Vec<(String, String)>,
    /// Which knobs differ from the reference.
    pub changed: Vec<usize>,
    /// The level (0 = coarsest) when the variant is one of the refinement
    /// sequence's.
    pub level: Option<usize>,
    /// The scene's overrides (the study's, then the variant's).
    pub sets: Vec<String>,
    loaded: scene::LoadedScene,
}

/// The variants of a study, each scene loaded and built once (a bad value
/// stops the study before anything runs). Made by [`plan`].
#[derive(Debug)]
pub struct Plan {
    /// The spec it was made from.
    pub spec: Spec,
    /// Reference first.
    pub variants: Vec<Variant>,
    scene_path: std::path::PathBuf,
}

impl Plan {
    /// The variants' labels (their folders under the output directory), the
    /// possible `combined` one last.
    pub fn labels(&self) -> Vec<String> {
        let mut l: Vec<String> = self.variants.iter().map(|v| v.label.clone()).collect();
        if !self.spec.cross {
            l.push(COMBINED.into());
        }
        l
    }
}

/// A knob value that removes the key from the scene, so that its default
/// applies (`--vary solver.mass_scaling_dt=5e-7,default`: with and without
/// mass scaling).
pub const DEFAULT: &str = "default";

/// Label of the combination of each knob's cheapest value within tolerance.
pub const COMBINED: &str = "combined";

/// Cost of a variant over its runs.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Spread {
    /// Fastest run.
    pub min: f64,
    /// Median over the runs.
    pub median: f64,
    /// Slowest run.
    pub max: f64,
}

impl Spread {
    fn of(samples: &[f64]) -> Self {
        let mut s = samples.to_vec();
        s.sort_by(f64::total_cmp);
        let n = s.len();
        let median = if n % 2 == 1 {
            s[n / 2]
        } else {
            0.5 * (s[n / 2 - 1] + s[n / 2])
        };
        Self {
            min: s[0],
            median,
            max: s[n - 1],
        }
    }
}

/// A finished variant.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Outcome {
    /// Label (folder).
    pub label: String,
    /// `(key, value)` for every knob.
    pub settings: Vec<(String, String)>,
    /// Keys of the knobs that differ from the reference (for a level of
    /// the refinement sequence: the refined keys).
    pub changed: Vec<String>,
    /// The level of the refinement sequence (0 = coarsest), if it is one.
    pub level: Option<usize>,
    /// Increments of the run.
    pub increments: u64,
    /// Timed runs (the reference runs several times per round).
    pub runs: usize,
    /// Process CPU seconds per run.
    pub cpu_s: Spread,
    /// Wall seconds per run.
    pub wall_s: Spread,
    /// Energy balance error of the run (relative).
    pub balance_error: f64,
    /// Largest kinetic/internal energy ratio of the run (after forming starts).
    pub kinetic_to_internal_max: f64,
    /// Largest kinetic energy / external work of the run (after forming
    /// starts): whether a mass-scaled or fast variant stayed quasi-static.
    pub kinetic_to_work_max: f64,
    /// The run's warnings (`summary.json`'s `warnings`).
    pub warnings: Vec<String>,
    /// Each quantity's value (numbers) or `None` (curves).
    pub values: Vec<Option<f64>>,
    /// Each quantity's error against the converged answer when the study
    /// has one, else against the reference (`None` for the reference).
    pub errors: Vec<Option<QuantityError>>,
    /// The largest error over the quantities (0 for the reference without
    /// a converged answer).
    pub worst: f64,
    /// Speed-up over the reference, run by run: the reference's CPU time
    /// at the moment of the run (interpolated between its runs) over the
    /// run's; 1 for the reference.
    pub speed_up: Spread,
    /// The variant's CPU time at the reference's pace: the reference's
    /// median CPU seconds over the median speed-up (what plots and the
    /// recommendation compare).
    pub cost_s: f64,
}

/// A variant that failed: its label and the message.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Failed {
    /// Label (folder).
    pub label: String,
    /// Why.
    pub message: String,
}

/// Everything a study found.
#[derive(Debug, Clone)]
pub struct Results {
    /// The spec.
    pub spec: Spec,
    /// Scene name.
    pub scene: String,
    /// Worker threads every run used.
    pub threads: usize,
    /// Completed variants, reference first.
    pub outcomes: Vec<Outcome>,
    /// Failed variants.
    pub failed: Vec<Failed>,
    /// The converged answer, when the study has a refinement sequence.
    pub converged: Option<converged::Converged>,
}

/// Check the spec and build every variant's scene without running any.
///
/// # Errors
/// No knob or no quantity, a knob listed twice, a reference key that is not
/// a knob, `repeat` 0, a tolerance that is not positive, a variant whose
/// scene does not load or build (named by its label).
pub fn plan(scene_path: &Path, spec: Spec) -> Result<Plan, StudyError> {
    check_spec(&spec)?;
    let reference: Vec<String> = spec
        .knobs
        .iter()
        .map(|k| {
            spec.reference
                .iter()
                .rev()
                .find(|(key, _)| *key == k.key)
                .map_or_else(|| k.values[0].clone(), |(_, v)| v.clone())
        })
        .collect();
    let mut picks: Vec<Vec<String>> = vec![reference.clone()];
    if spec.cross {
        for combo in cartesian(&spec.knobs) {
            if combo != reference {
                picks.push(combo);
            }
        }
    } else {
        for (k, knob) in spec.knobs.iter().enumerate() {
            for v in knob.values.iter().filter(|v| **v != reference[k]) {
                let mut p = reference.clone();
                p[k] = v.clone();
                picks.push(p);
            }
        }
    }
    let mut variants = Vec::with_capacity(picks.len());
    for pick in picks {
        let v = variant(scene_path, &spec, &reference, pick, &[])?;
        if variants.iter().any(|w: &Variant| w.label == v.label) {
            return Err(StudyError::SharedFolder { label: v.label });
        }
        variants.push(v);
    }
    let levels = spec.converge.first().map_or(0, |k| k.values.len());
    for l in 0..levels {
        let extra: Vec<(String, String)> = (spec.converge.iter())
            .map(|k| (k.key.clone(), k.values[l].clone()))
            .collect();
        let mut v = variant(scene_path, &spec, &reference, reference.clone(), &extra)?;
        v.label = format!("level-{}", l + 1);
        v.level = Some(l);
        variants.push(v);
    }
    Ok(Plan {
        spec,
        variants,
        scene_path: scene_path.to_path_buf(),
    })
}

fn check_spec(spec: &Spec) -> Result<(), StudyError> {
    if spec.knobs.is_empty() {
        return Err(StudyError::NoKnob);
    }
    if spec.quantities.is_empty() {
        return Err(StudyError::NoQuantity);
    }
    for (i, k) in spec.knobs.iter().enumerate() {
        if spec.knobs[..i].iter().any(|j| j.key == k.key) {
            return Err(StudyError::KnobTwice { key: k.key.clone() });
        }
    }
    for (key, _) in &spec.reference {
        if !spec.knobs.iter().any(|k| k.key == *key) {
            return Err(StudyError::ReferenceNotVaried { key: key.clone() });
        }
    }
    if spec.repeat == 0 {
        return Err(StudyError::RepeatZero);
    }
    if !(spec.tolerance.is_finite() && spec.tolerance > 0.0) {
        return Err(StudyError::Tolerance {
            tolerance: spec.tolerance,
        });
    }
    converge_ratio(&spec.converge).map(|_| ())
}

/// The refinement ratio of the sequence (1 without one), after checking
/// it: three levels or more, as many for every key, one ratio.
pub fn converge_ratio(converge: &[Knob]) -> Result<f64, StudyError> {
    let Some(first) = converge.first() else {
        return Ok(1.0);
    };
    let n = first.values.len();
    let mut ratio = None;
    for k in converge {
        let m = k.values.len();
        if m < 3 || m != n {
            return Err(StudyError::ConvergeLevels {
                key: k.key.clone(),
                levels: m,
                expected: if m < 3 {
                    "three or more".into()
                } else {
                    format!("{n}, as many as `{}`", first.key)
                },
            });
        }
        let r = richardson::ratio_of(&k.values)
            .ok_or_else(|| StudyError::ConvergeRatio { key: k.key.clone() })?;
        let first = *ratio.get_or_insert(r);
        if (r / first - 1.0).abs() > 1e-6 {
            return Err(StudyError::ConvergeRatiosDiffer {
                key: k.key.clone(),
                ratio: r,
                first,
            });
        }
    }
    Ok(ratio.unwrap_or(1.0))
}

/// Every combination of the knobs' values, the first knob varying slowest.
fn cartesian(knobs: &[Knob]) -> Vec<Vec<String>> {
    let mut out: Vec<Vec<String>> = vec![Vec::new()];
    for k in knobs {
        out = out
            .into_iter()
            .flat_map(|p| {
                k.values.iter().map(move |v| {
                    let mut q = p.clone();
                    q.push(v.clone());
                    q
                })
            })
            .collect();
    }
    out
}

/// Load and build the scene of one pick of values.
fn variant(
    scene_path: &Path,
    spec: &Spec,
    reference: &[String],
    pick: Vec<String>,
    extra: &[(String, String)],
) -> Result<Variant, StudyError> {
    let changed: Vec<usize> = (0..pick.len())
        .filter(|&k| pick[k] != reference[k])
        .collect();
    let label = label_of(&spec.knobs, &pick, &changed);
    let settings: Vec<(String, String)> = spec
        .knobs
        .iter()
        .zip(&pick)
        .map(|(k, v)| (k.key.clone(), v.clone()))
        .collect();
    let mut sets = spec.sets.clone();
    sets.extend(settings.iter().chain(extra).map(|(k, v)| {
        if v == DEFAULT {
            format!("{k}=")
        } else {
            format!("{k}={v}")
        }
    }));
    let in_variant = |source| StudyError::Variant {
        label: label.clone(),
        source,
    };
    let loaded = scene::load(scene_path, &sets).map_err(in_variant)?;
    let probe = crate::run::probe::probe(&loaded).map_err(|e| match e {
        RunError::Scene(source) => in_variant(source),
        other => StudyError::QuantityNotReported {
            label: label.clone(),
            message: other.to_string(),
        },
    })?;
    for q in &spec.quantities {
        q.check(&probe)
            .map_err(|message| StudyError::QuantityNotReported {
                label: label.clone(),
                message,
            })?;
    }
    Ok(Variant {
        label,
        settings,
        changed,
        level: None,
        sets,
        loaded,
    })
}

/// `reference`, or the changed knobs as `LASTKEY-VALUE` joined by `+`, with
/// characters other than letters, digits, `-`, `_`, `.` replaced by `_`.
fn label_of(knobs: &[Knob], pick: &[String], changed: &[usize]) -> String {
    if changed.is_empty() {
        return "reference".into();
    }
    changed
        .iter()
        .map(|&k| {
            let key = knobs[k].key.rsplit('.').next().unwrap_or(&knobs[k].key);
            let raw = format!("{key}-{}", pick[k]);
            raw.chars()
                .map(|c| {
                    if c.is_ascii_alphanumeric() || "-_.".contains(c) {
                        c
                    } else {
                        '_'
                    }
                })
                .collect::<String>()
        })
        .collect::<Vec<_>>()
        .join("+")
}

/// Run the plan's variants (`repeat` rounds, the reference between them:
/// [`schedule`]), then the possible combination (with the reference around
/// it), into `out`; `on_run` is told after each run.
///
/// # Errors
/// The reference fails or does not give a quantity; a repeat differs from
/// its first run; the output folder cannot be made.
pub fn execute(
    plan: Plan,
    out: &Path,
    progress: bool,
    engine: &Engine<'_>,
    on_run: &dyn Fn(&str, Result<&VariantRun, &str>),
) -> Result<Results, StudyError> {
    std::fs::create_dir_all(out).map_err(|source| StudyError::Io {
        path: out.to_path_buf(),
        source,
    })?;
    let Plan {
        spec,
        mut variants,
        scene_path,
    } = plan;
    let bar = progress.then(indicatif::ProgressBar::no_length);
    let rounds = |vs: &[&Variant], call: usize| {
        let r = schedule::Rounds {
            engine,
            out,
            bar: bar.as_ref(),
            on_run,
            call,
        };
        run_rounds(vs, &spec.quantities, spec.repeat, &r)
    };
    let mut runs = rounds(&variants.iter().collect::<Vec<_>>(), 0)?;
    let mut results = tabulate(&spec, &variants, &runs, engine.threads())?;
    if !spec.cross
        && let Some(pick) = combination(&spec, &variants[0].settings, &results)
    {
        let reference: Vec<String> = variants[0].settings.iter().map(|s| s.1.clone()).collect();
        let mut v = variant(&scene_path, &spec, &reference, pick, &[])?;
        v.label = COMBINED.into();
        let mut extra = rounds(&[&variants[0], &v], 1)?.into_iter();
        let (again, combined) = (extra.next(), extra.next());
        if let (Some(again), Some(combined)) = (again, combined) {
            runs[0].merge(again, &variants[0].label)?;
            runs.push(combined);
            variants.push(v);
            results = tabulate(&spec, &variants, &runs, engine.threads())?;
        }
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    Ok(results)
}

/// Errors and costs of every completed variant against the reference (the
/// first): each run's speed-up is the reference's CPU time at that moment
/// ([`schedule::reference_at`]) over the run's.
fn tabulate(
    spec: &Spec,
    variants: &[Variant],
    runs: &[Runs],
    threads: usize,
) -> Result<Results, StudyError> {
    let ref_runs = &runs[0];
    let Some(ref_result) = &ref_runs.first else {
        return Err(StudyError::ReferenceFailed {
            message: ref_runs
                .failure
                .clone()
                .unwrap_or_else(|| "no result".into()),
        });
    };
    let mut timeline: Vec<(f64, f64)> = ref_runs
        .at
        .iter()
        .copied()
        .zip(ref_runs.cpu.iter().copied())
        .collect();
    timeline.sort_by(|a, b| a.0.total_cmp(&b.0));
    let ref_cpu = Spread::of(&ref_runs.cpu).median;
    let converged = converged_answer(spec, variants, runs)?;
    let against = converged.as_ref().map(|c| c.measured.as_slice());
    let mut outcomes = Vec::new();
    let mut failed = Vec::new();
    for (k, (v, r)) in variants.iter().zip(runs).enumerate() {
        let Some(result) = &r.first else {
            failed.push(Failed {
                label: v.label.clone(),
                message: r.failure.clone().unwrap_or_default(),
            });
            continue;
        };
        let mut errors = Vec::new();
        for (i, (q, value)) in spec.quantities.iter().zip(&r.values).enumerate() {
            let ref_value = against.map_or(&ref_runs.values[i], |m| &m[i]);
            errors.push(if k == 0 && against.is_none() {
                None
            } else {
                Some(
                    quantity::error(value, ref_value).map_err(|source| StudyError::Compare {
                        quantity: q.name(),
                        source,
                    })?,
                )
            });
        }
        let worst = errors.iter().flatten().map(|e| e.error).fold(0.0, f64::max);
        let speed_up = if k == 0 {
            Spread {
                min: 1.0,
                median: 1.0,
                max: 1.0,
            }
        } else {
            let ratios: Vec<f64> =
                r.at.iter()
                    .zip(&r.cpu)
                    .map(|(&t, &c)| schedule::reference_at(&timeline, t) / c)
                    .collect();
            Spread::of(&ratios)
        };
        outcomes.push(Outcome {
            label: v.label.clone(),
            settings: v.settings.clone(),
            changed: match v.level {
                Some(_) => spec.converge.iter().map(|k| k.key.clone()).collect(),
                None => v
                    .changed
                    .iter()
                    .map(|&k| spec.knobs[k].key.clone())
                    .collect(),
            },
            level: v.level,
            increments: result.increments,
            runs: r.cpu.len(),
            cpu_s: Spread::of(&r.cpu),
            wall_s: Spread::of(&r.wall),
            balance_error: result.balance_error_rel,
            kinetic_to_internal_max: result.kinetic_to_internal_max,
            kinetic_to_work_max: result.kinetic_to_work_max,
            warnings: result.warnings.clone(),
            values: r
                .values
                .iter()
                .map(|m| match m {
                    Measured::Scalar(x) => Some(*x),
                    Measured::Curve(_) => None,
                })
                .collect(),
            errors,
            worst,
            speed_up,
            cost_s: ref_cpu / speed_up.median,
        });
    }
    Ok(Results {
        spec: spec.clone(),
        scene: ref_result.scene.clone(),
        threads,
        outcomes,
        failed,
        converged,
    })
}

/// The converged answer from the refinement sequence's levels, when the
/// study has one.
fn converged_answer(
    spec: &Spec,
    variants: &[Variant],
    runs: &[Runs],
) -> Result<Option<converged::Converged>, StudyError> {
    if spec.converge.is_empty() {
        return Ok(None);
    }
    let ratio = converge_ratio(&spec.converge)?;
    let (mut labels, mut levels) = (Vec::new(), Vec::new());
    for (v, r) in variants.iter().zip(runs).filter(|(v, _)| v.level.is_some()) {
        if r.first.is_none() {
            return Err(StudyError::LevelFailed {
                label: v.label.clone(),
                message: r.failure.clone().unwrap_or_else(|| "no result".into()),
            });
        }
        labels.push(v.label.clone());
        levels.push(r.values.as_slice());
    }
    converged::Converged::new(
        spec.converge.iter().map(|k| k.key.clone()).collect(),
        ratio,
        labels,
        spec.quantities.iter().map(Quantity::name).collect(),
        &levels,
    )
    .map(Some)
    .map_err(StudyError::Converge)
}

/// For each knob, its cheapest value within the tolerance that is
/// [`cheaper`] than the reference; `Some` when two accuracy knobs or more
/// have one.
fn combination(
    spec: &Spec,
    reference: &[(String, String)],
    results: &Results,
) -> Option<Vec<String>> {
    let mut pick: Vec<String> = reference.iter().map(|s| s.1.clone()).collect();
    let mut moved = 0;
    for (k, knob) in spec.knobs.iter().enumerate().filter(|(_, k)| !k.model) {
        let best = results
            .outcomes
            .iter()
            .filter(|o| o.level.is_none() && o.changed.len() == 1 && o.changed[0] == knob.key)
            .filter(|o| o.worst <= spec.tolerance && cheaper(o))
            .min_by(|a, b| a.cost_s.total_cmp(&b.cost_s));
        if let Some(o) = best {
            pick[k] = o.settings[k].1.clone();
            moved += 1;
        }
    }
    (moved >= 2).then_some(pick)
}

/// Whether `o` changes a model knob ([`Knob::model`]).
pub fn changes_a_model(spec: &Spec, o: &Outcome) -> bool {
    (spec.knobs.iter())
        .filter(|k| k.model)
        .any(|k| o.changed.contains(&k.key))
}

/// Whether `o` is cheaper than the reference beyond the noise of the
/// machine: every one of its runs was faster than the reference at that
/// moment (its smallest speed-up above 1).
pub fn cheaper(o: &Outcome) -> bool {
    o.speed_up.min > 1.0
}

/// The cheapest completed variant within the tolerance on every quantity,
/// when it is [`cheaper`] than the reference (`None`: keep the reference);
/// a variant of a model ([`Knob::model`]) is not a candidate.
pub fn recommendation(results: &Results) -> Option<&Outcome> {
    results
        .outcomes
        .iter()
        .skip(1)
        .filter(|o| !changes_a_model(&results.spec, o))
        .filter(|o| o.worst <= results.spec.tolerance && cheaper(o))
        .min_by(|a, b| a.cost_s.total_cmp(&b.cost_s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn knobs_parse_and_refuse_bad_lists() {
        let k = Knob::parse("blank.mesh.divisions=50, 25,100").unwrap();
        assert_eq!(k.key, "blank.mesh.divisions");
        assert_eq!(k.values, ["50", "25", "100"]);
        let e = |text: &str| Knob::parse(text).unwrap_err().to_string();
        assert!(e("blank.mesh.divisions").contains("KEY=V1"));
        assert!(e("=1,2").contains("no key"));
        assert!(e("a=1,,2").contains("empty value"));
        assert!(e("a=1,2,1").contains("twice"));
    }

    #[test]
    fn cartesian_has_every_combination_once() {
        let knobs = [
            Knob::parse("a=1,2").unwrap(),
            Knob::parse("b=x,y,z").unwrap(),
        ];
        let c = cartesian(&knobs);
        assert_eq!(c.len(), 6);
        assert_eq!(c[0], ["1", "x"]);
        assert_eq!(c[5], ["2", "z"]);
    }

    #[test]
    fn labels_name_the_changed_knobs_in_plain_characters() {
        let knobs = [
            Knob::parse("blank.mesh.divisions=50,25").unwrap(),
            Knob::parse("solver.mass_scaling_dt=5e-7,1e-6").unwrap(),
        ];
        let pick = vec!["25".to_string(), "1e-6".to_string()];
        assert_eq!(label_of(&knobs, &pick, &[]), "reference");
        assert_eq!(label_of(&knobs, &pick, &[0]), "divisions-25");
        assert_eq!(
            label_of(&knobs, &pick, &[0, 1]),
            "divisions-25+mass_scaling_dt-1e-6"
        );
        let odd = vec!["a b/c".to_string(), "x".to_string()];
        assert_eq!(label_of(&knobs, &odd, &[0]), "divisions-a_b_c");
    }

    fn outcome(settings: &[(&str, &str)], changed: &[&str], worst: f64, speed_up: f64) -> Outcome {
        let t = 1.0 / speed_up;
        let one = Spread {
            min: t,
            median: t,
            max: t,
        };
        Outcome {
            label: changed.join("+"),
            settings: settings
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect(),
            changed: changed.iter().map(|c| c.to_string()).collect(),
            level: None,
            increments: 1,
            runs: 1,
            cpu_s: one,
            wall_s: one,
            balance_error: 0.0,
            kinetic_to_internal_max: 0.0,
            kinetic_to_work_max: 0.0,
            warnings: Vec::new(),
            values: Vec::new(),
            errors: Vec::new(),
            worst,
            speed_up: Spread {
                min: speed_up,
                median: speed_up,
                max: speed_up,
            },
            cost_s: t,
        }
    }

    /// Knob a: `2` is within tolerance and faster, `3` faster still but
    /// outside it; knob b: `y` within tolerance and faster; knob c: `q`
    /// within tolerance but slower. The combination takes a=2, b=y, c as in
    /// the reference; the recommendation is the fastest within tolerance.
    #[test]
    fn the_combination_takes_each_knobs_cheapest_value_within_tolerance() {
        let spec = Spec {
            knobs: vec![
                Knob::parse("a=1,2,3").unwrap(),
                Knob::parse("b=x,y").unwrap(),
                Knob::parse("c=p,q").unwrap(),
            ],
            reference: Vec::new(),
            quantities: vec![Quantity::parse("k").unwrap()],
            cross: false,
            repeat: 1,
            tolerance: 0.02,
            sets: Vec::new(),
            converge: Vec::new(),
        };
        let r = [("a", "1"), ("b", "x"), ("c", "p")];
        let results = Results {
            spec: spec.clone(),
            scene: "s".into(),
            threads: 1,
            outcomes: vec![
                outcome(&r, &[], 0.0, 1.0),
                outcome(&[("a", "2"), ("b", "x"), ("c", "p")], &["a"], 0.01, 1.5),
                outcome(&[("a", "3"), ("b", "x"), ("c", "p")], &["a"], 0.05, 3.0),
                outcome(&[("a", "1"), ("b", "y"), ("c", "p")], &["b"], 0.02, 1.2),
                outcome(&[("a", "1"), ("b", "x"), ("c", "q")], &["c"], 0.0, 0.9),
            ],
            failed: Vec::new(),
            converged: None,
        };
        let reference: Vec<(String, String)> = r
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        assert_eq!(
            combination(&spec, &reference, &results).unwrap(),
            ["2", "y", "p"]
        );
        assert_eq!(recommendation(&results).unwrap().label, "a");
        let mut one_knob = results.clone();
        one_knob.outcomes.truncate(3);
        assert_eq!(combination(&spec, &reference, &one_knob), None);
    }

    #[test]
    fn spread_takes_the_median() {
        let s = Spread::of(&[3.0, 1.0, 2.0]);
        assert_eq!((s.min, s.median, s.max), (1.0, 2.0, 3.0));
        assert_eq!(Spread::of(&[4.0, 1.0]).median, 2.5);
    }

    #[test]
    fn refinement_sequences_need_three_levels_and_one_ratio() {
        let k = |t: &str| Knob::parse(t).unwrap();
        let ok = [k("a=25,50,100"), k("b=1e-6,5e-7,2.5e-7")];
        assert_eq!(converge_ratio(&ok).unwrap(), 2.0);
        assert_eq!(converge_ratio(&[]).unwrap(), 1.0);
        let e = |ks: &[Knob]| converge_ratio(ks).unwrap_err().to_string();
        assert!(e(&[k("a=25,50")]).contains("three or more"));
        assert!(e(&[k("a=25,50,100"), k("b=1,2,4,8")]).contains("as many as `a`"));
        assert!(e(&[k("a=25,50,75")]).contains("one ratio"));
        assert!(e(&[k("a=25,50,100"), k("b=1,3,9")]).contains("ratio 3"));
    }
}
