//! `formsim identify` and `formsim sensitivity`: friction parameters (or any
//! scene values) from measurements, their sensitivities and their
//! uncertainty (docs/identification.md).
//!
//! - [`measurements`]: the measured values (TOML data sets or the draw-in CSV).
//! - [`params`]: the fitted values, `--fit KEY=LO..HI[:START]`.
//! - [`evaluate`]: runs of the scene at parameter points, journalled
//!   ([`journal`]) so that a second call resumes without repeating a run,
//!   parallel where the optimiser asks for several points at once.
//! - [`objective`]: the thesis's mean absolute error, or weighted least squares.
//! - [`nelder_mead`] (argmin) and [`levenberg`] (Levenberg–Marquardt on
//!   finite-difference Jacobians, [`jacobian`]).
//! - [`uncertainty`]: the linearised covariance, intervals, correlations.
//! - [`mod@sensitivity`]: the normalised sensitivity table ([`sensitivity()`] writes it).
//! - [`report`]: `identification.json`, `identification.md` and the plots.

pub mod evaluate;
pub mod jacobian;
pub mod journal;
pub mod levenberg;
pub mod measurements;
pub mod nelder_mead;
pub mod objective;
pub mod observe;
pub mod params;
pub mod plots;
pub mod report;
pub mod sensitivity;
pub mod uncertainty;

use evaluate::{Evaluation, Evaluator};
use measurements::Measurements;
use objective::Objective;
use params::FitParam;
use std::path::{Path, PathBuf};

/// What can go wrong in an identification.
#[derive(Debug, thiserror::Error)]
pub enum IdentifyError {
    /// A `--fit` value is malformed.
    #[error("--fit `{text}`: {message}")]
    Fit {
        /// The argument.
        text: String,
        /// What is wrong.
        message: String,
    },
    /// The measurements file is malformed.
    #[error("{}:{line}: {message}", path.display())]
    Measurements {
        /// The file.
        path: PathBuf,
        /// 1-based line (0: the whole file).
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// Another option is wrong.
    #[error("{0}")]
    Option(String),
    /// The scene does not load with the identification's overrides.
    #[error("{0}")]
    Scene(String),
    /// The journal cannot be read or written, or belongs to other arguments.
    #[error("journal: {0}")]
    Journal(String),
    /// A run needed for a derivative failed.
    #[error("{0}")]
    Evaluation(String),
    /// A report file cannot be written.
    #[error("{0}")]
    Report(String),
    /// The batch engine cannot run the evaluations.
    #[error(transparent)]
    Batch(#[from] crate::batch::BatchError),
}

/// The local executor identify runs on when none is given: a batch of one
/// run on every thread of the global pool, a batch of several one thread
/// each.
pub fn default_executor() -> crate::batch::local::PerBatch {
    crate::batch::local::PerBatch {
        jobs: None,
        threads: None,
        cores: rayon::current_num_threads(),
    }
}

/// The optimiser.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Nelder–Mead (argmin), bounds by a sine transform.
    NelderMead,
    /// Levenberg–Marquardt on finite-difference Jacobians, projected on the bounds.
    LevenbergMarquardt,
}

impl Method {
    /// Parse `nelder-mead` or `lm`.
    ///
    /// # Errors
    /// Another name.
    pub fn parse(name: &str) -> Result<Self, IdentifyError> {
        match name {
            "nelder-mead" | "nm" => Ok(Self::NelderMead),
            "lm" | "levenberg-marquardt" => Ok(Self::LevenbergMarquardt),
            other => Err(IdentifyError::Option(format!(
                "--method {other}: expected nelder-mead or lm"
            ))),
        }
    }

    /// The name.
    pub fn name(self) -> &'static str {
        match self {
            Self::NelderMead => "nelder-mead",
            Self::LevenbergMarquardt => "lm",
        }
    }
}

/// Everything `identify` needs.
#[derive(Debug, Clone)]
pub struct Options {
    /// Scene file.
    pub scene: PathBuf,
    /// Overrides of every run.
    pub sets: Vec<String>,
    /// The fitted values.
    pub params: Vec<FitParam>,
    /// The objective.
    pub objective: Objective,
    /// The optimiser.
    pub method: Method,
    /// Stop after this many evaluations.
    pub max_evaluations: usize,
    /// Nelder–Mead's tolerance on the objective's spread over the simplex.
    pub tolerance: f64,
    /// Finite-difference step of the Jacobians (fraction of each range).
    pub fd_step: f64,
    /// Output directory (journal, runs, report).
    pub out: PathBuf,
    /// Progress bar.
    pub progress: bool,
}

/// The start of each value: its START, else the scene's own value when it is
/// a number inside the range, else the middle of the range.
///
/// # Errors
/// The scene does not load.
pub fn start_values(
    scene: &Path,
    sets: &[String],
    params: &[FitParam],
) -> Result<Vec<f64>, IdentifyError> {
    let loaded =
        crate::scene::load(scene, sets).map_err(|e| IdentifyError::Scene(e.to_string()))?;
    let table: toml::Table = toml::from_str(&loaded.text).unwrap_or_default();
    Ok(params
        .iter()
        .map(|p| {
            p.start.unwrap_or_else(|| {
                scene_value(&table, &p.key, sets)
                    .filter(|v| (p.lo..=p.hi).contains(v))
                    .unwrap_or(0.5 * (p.lo + p.hi))
            })
        })
        .collect())
}

/// A number of the scene at a dotted key, after `sets`.
fn scene_value(table: &toml::Table, key: &str, sets: &[String]) -> Option<f64> {
    let mut table = table.clone();
    for s in sets {
        let (k, v) = crate::scene::overrides::parse_assignment(s).ok()?;
        crate::scene::overrides::apply(&mut table, &k, v, s).ok()?;
    }
    let root = toml::Value::Table(table);
    let mut value = &root;
    for part in key.split('.') {
        value = value.get(part)?;
    }
    value
        .as_float()
        .or_else(|| value.as_integer().map(|i| i as f64))
}

/// The best evaluation of a log (lowest objective, earliest on ties).
pub fn best(log: &[Evaluation]) -> Option<&Evaluation> {
    log.iter()
        .filter(|e| e.cost.is_finite())
        .min_by(|a, b| a.cost.total_cmp(&b.cost).then(a.index.cmp(&b.index)))
}

/// Check the options against the measurements and the scene: one line for
/// the first thing wrong.
///
/// # Errors
/// `wls` without standard errors; no fitted value; a key fitted twice; a
/// fitted key the scene does not accept.
pub fn check(options: &Options, data: &Measurements) -> Result<(), IdentifyError> {
    if options.params.is_empty() {
        return Err(IdentifyError::Option(
            "nothing to fit: give at least one --fit KEY=LO..HI[:START]".into(),
        ));
    }
    for (i, p) in options.params.iter().enumerate() {
        if options.params[..i].iter().any(|q| q.key == p.key) {
            return Err(IdentifyError::Option(format!(
                "--fit {}: the key is fitted twice",
                p.key
            )));
        }
    }
    if options.objective == Objective::Wls && !data.all_have_se() {
        let missing = data
            .sets
            .iter()
            .flat_map(|s| &s.points)
            .find(|p| p.se.is_none())
            .map(|p| format!("{} (line {})", p.label(), p.line))
            .unwrap_or_default();
        return Err(IdentifyError::Option(format!(
            "--objective wls needs a standard error on every measured value; {missing} has none"
        )));
    }
    if options.max_evaluations < options.params.len() + 2 {
        return Err(IdentifyError::Option(format!(
            "--max-evaluations {}: at least {} are needed for {} fitted values",
            options.max_evaluations,
            options.params.len() + 2,
            options.params.len()
        )));
    }
    // Every data set's scene, at the start, loads and builds.
    let start = start_values(&options.scene, &options.sets, &options.params)?;
    for set in &data.sets {
        let mut sets = options.sets.clone();
        sets.extend(set.overrides.iter().cloned());
        sets.extend(
            options
                .params
                .iter()
                .zip(&start)
                .map(|(p, v)| params::assignment(p, *v)),
        );
        let scene_strokes = crate::scene::load(&options.scene, &sets)
            .map_err(|e| IdentifyError::Scene(format!("set {}: {e}", set.name)))?
            .scene
            .output
            .report_strokes;
        // As every evaluation runs it: with a report state at each measured stroke.
        let one = Measurements {
            path: data.path.clone(),
            sets: vec![set.clone()],
        };
        sets.extend(evaluate::run_overrides(&one, &scene_strokes));
        let loaded = crate::scene::load(&options.scene, &sets)
            .map_err(|e| IdentifyError::Scene(format!("set {}: {e}", set.name)))?;
        let probe = crate::run::probe::probe(&loaded)
            .map_err(|e| IdentifyError::Scene(format!("set {}: {e}", set.name)))?;
        for p in &set.points {
            p.quantity.check(&probe).map_err(|why| {
                IdentifyError::Scene(format!(
                    "set {}: {} (line {}): {why}",
                    set.name,
                    p.label(),
                    p.line
                ))
            })?;
        }
    }
    Ok(())
}

/// Run an identification and write its report to `options.out`.
///
/// # Errors
/// Bad options or measurements; the journal belongs to other arguments; a
/// run needed for a derivative failed; the report cannot be written.
pub fn identify(options: &Options, data: &Measurements) -> Result<report::Report, IdentifyError> {
    identify_on(options, data, &default_executor())
}

/// [`identify`] with its runs on `executor`.
///
/// # Errors
/// As [`identify`]; the executor cannot run.
pub fn identify_on(
    options: &Options,
    data: &Measurements,
    executor: &dyn crate::batch::Executor,
) -> Result<report::Report, IdentifyError> {
    check(options, data)?;
    let start = start_values(&options.scene, &options.sets, &options.params)?;
    let mut ev = Evaluator::new(
        &options.scene,
        &options.sets,
        data,
        &options.params,
        options.objective,
        &options.out,
        executor,
    )?;
    if options.progress {
        ev = ev.with_progress(options.max_evaluations);
    }
    let stop = match options.method {
        Method::NelderMead => nelder_mead::minimise(
            &ev,
            &start,
            nelder_mead::Settings {
                sd_tolerance: options.tolerance,
                max_iters: options.max_evaluations as u64,
                max_evaluations: options.max_evaluations,
            },
        )?,
        Method::LevenbergMarquardt => levenberg::minimise(
            &ev,
            &start,
            levenberg::Settings {
                fd_step: options.fd_step,
                x_tolerance: 1e-4,
                f_tolerance: 1e-6,
                max_evaluations: options.max_evaluations,
            },
        )?,
    };
    let log = ev.log();
    let first = log
        .first()
        .cloned()
        .ok_or_else(|| IdentifyError::Evaluation("no evaluation was made".into()))?;
    let end = best(&log).cloned().ok_or_else(|| {
        IdentifyError::Evaluation(format!(
            "every run failed; the first: {}",
            first
                .failure()
                .map_or_else(|| "unknown".to_string(), ToString::to_string)
        ))
    })?;
    let uncertainty = at_optimum(&ev, &end.values, options.fd_step, data.all_have_se());
    ev.finish();
    let report = report::Report::new(options, &ev, &first, &end, stop, uncertainty);
    report.write(&options.out, data)?;
    Ok(report)
}

/// Probe runs at the optimum for the objective's roughness.
pub const ROUGHNESS_PROBES: usize = 3;
/// Their distance from the optimum, as a fraction of each range.
pub const ROUGHNESS_STEP: f64 = 1e-6;

/// The Jacobian at `x` and the roughness probes, as one parallel batch, and
/// the uncertainty they give.
fn at_optimum(
    ev: &Evaluator<'_>,
    x: &[f64],
    fd_step: f64,
    weighted: bool,
) -> Result<uncertainty::Uncertainty, IdentifyError> {
    let (mut points, steps) = jacobian::stencil(ev, x, fd_step);
    let n = points.len();
    for k in 0..ROUGHNESS_PROBES {
        let probe = ev
            .params()
            .iter()
            .enumerate()
            .map(|(j, p)| {
                let sign = if (j + k) % 2 == 0 { 1.0 } else { -1.0 };
                let v = x[j] + sign * (k + 1) as f64 * ROUGHNESS_STEP * p.width();
                v.clamp(p.lo, p.hi)
            })
            .collect();
        points.push(probe);
    }
    let evaluations = ev.evaluate_batch(&points)?;
    let jac = jacobian::from_stencil(ev, &evaluations[..n], &steps)?;
    let mut sums = vec![jac.residuals.iter().map(|r| r * r).sum::<f64>()];
    for e in &evaluations[n..] {
        let predictions: Option<Vec<Vec<f64>>> =
            e.predictions.iter().map(|p| p.clone().ok()).collect();
        if let Some(p) = predictions {
            sums.push(
                objective::residuals(ev.data(), &p)
                    .iter()
                    .map(|r| r * r)
                    .sum(),
            );
        }
    }
    let roughness = (sums.len() > 1).then(|| {
        let mean = sums.iter().sum::<f64>() / sums.len() as f64;
        (sums.iter().map(|s| (s - mean).powi(2)).sum::<f64>() / (sums.len() - 1) as f64).sqrt()
    });
    Ok(uncertainty::uncertainty(
        ev.params(),
        x,
        &jac.matrix,
        &jac.residuals,
        weighted,
        roughness,
    ))
}

/// Options of `formsim sensitivity`.
#[derive(Debug, Clone)]
pub struct SensitivityOptions {
    /// Scene file.
    pub scene: PathBuf,
    /// Overrides of every run.
    pub sets: Vec<String>,
    /// The values (bounds keep the steps inside; START is the point).
    pub params: Vec<FitParam>,
    /// The objective of the objective's row.
    pub objective: Objective,
    /// The larger relative step.
    pub step: f64,
    /// Output directory.
    pub out: PathBuf,
}

/// The sensitivity table at the values' starts, written to
/// `out/sensitivity.{json,md}`.
///
/// # Errors
/// As [`identify`].
pub fn sensitivity(
    options: &SensitivityOptions,
    data: &Measurements,
) -> Result<sensitivity::Table, IdentifyError> {
    if !(options.step > 0.0 && options.step < 1.0) {
        return Err(IdentifyError::Option(format!(
            "--step {}: must be in (0, 1) (a fraction of each value)",
            options.step
        )));
    }
    let check_options = Options {
        scene: options.scene.clone(),
        sets: options.sets.clone(),
        params: options.params.clone(),
        objective: options.objective,
        method: Method::NelderMead,
        max_evaluations: usize::MAX,
        tolerance: 0.0,
        fd_step: options.step,
        out: options.out.clone(),
        progress: false,
    };
    check(&check_options, data)?;
    let x = start_values(&options.scene, &options.sets, &options.params)?;
    let executor = default_executor();
    let ev = Evaluator::new(
        &options.scene,
        &options.sets,
        data,
        &options.params,
        options.objective,
        &options.out,
        &executor,
    )?;
    let table = sensitivity::table(&ev, &x, options.step)?;
    report::write_sensitivity(&options.out, &table, options)?;
    Ok(table)
}
