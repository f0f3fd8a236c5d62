//! `formsim run`: one forming simulation of a scene, from set-up to the files
//! of `DIR` (`summary.json`, `sections/*.csv`, `energy.csv`,
//! `punch_force.csv`, `vtk/*.vtu` + `blank.pvd`, PNG plots).
//!
//! The time-step loop calls [`fem_core::Solver::step`] (the shells hand their
//! thickness, and flow stress when a law reads it, to contact inside the
//! step, through the solver's shared fields) and samples histories on a
//! fixed schedule; everything that allocates (snapshots,
//! frames) happens only at the scheduled times.
//!
//! A run ends [`Status::Completed`], [`Status::Failed`] (the solver stopped,
//! a value became NaN or infinite, a frame could not be written) or
//! [`Status::Interrupted`] ([`interrupt`], at the next step boundary). A run
//! that stops early still writes `summary.json` with its status and cause and
//! the histories up to the last finite sample.

pub mod finite;
pub mod out_dir;
pub mod post;
pub mod probe;
pub mod profile;
mod recorder;
pub mod reference_checks;
pub mod springback;
pub mod summary;
mod summary_text;
pub mod timing;
pub mod tools_report;
pub mod warnings;
pub mod write;

pub use crate::records::{HistoryRow, ToolRow, ToolState};

use crate::output::OutputError;
use crate::scene::blank_mesh::FileIds;
use crate::scene::{LoadedScene, Model, SceneError};
use post::Snapshot;
use recorder::Recorder;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Set by [`interrupt`]; the step loop reads it at every step boundary.
static INTERRUPT: AtomicBool = AtomicBool::new(false);

/// Ask the runs of this process to stop at their next step boundary, as
/// [`Status::Interrupted`] (what a SIGINT handler calls). Returns whether a
/// stop had already been asked for.
pub fn interrupt() -> bool {
    INTERRUPT.swap(true, Ordering::Relaxed)
}

/// How a run ended: `summary.json`'s `status`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// The run reached its end time.
    Completed,
    /// The run stopped early: the solver stopped, a value became NaN or
    /// infinite, or a file could not be written during the run.
    Failed,
    /// The run was interrupted ([`interrupt`], Ctrl-C).
    Interrupted,
}

/// Why a run stopped before its end.
#[derive(Debug, Clone, PartialEq)]
pub struct Stop {
    /// [`Status::Failed`] or [`Status::Interrupted`].
    pub status: Status,
    /// What stopped it, one line (`summary.json`'s `cause`).
    pub cause: String,
}

impl Stop {
    fn failed(cause: impl std::fmt::Display) -> Self {
        Self {
            status: Status::Failed,
            cause: cause.to_string(),
        }
    }
}

/// How to run.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// Output directory (created). Files of an earlier run there are
    /// overwritten, not removed: clean it first with [`out_dir::prepare`].
    pub out: PathBuf,
    /// Progress display.
    pub progress: Progress,
}

/// How a run shows its progress.
#[derive(Debug, Clone, Default)]
pub enum Progress {
    /// Nothing.
    #[default]
    Hidden,
    /// Its own bar on the terminal (stderr), cleared at the end.
    Terminal,
    /// A bar the caller made (one line of a `MultiProgress`, say); it is left
    /// finished, with `done` or `stopped` as its message.
    Bar(indicatif::ProgressBar),
}

/// Errors of a run.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The scene is invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The run failed: the solver stopped, a value became NaN or infinite,
    /// or a frame could not be written (what was computed so far has been
    /// written, `summary.json` with `"status": "failed"`).
    #[error("run stopped at t = {time:.6e} s: {message} (results so far in {out})")]
    Failed {
        /// Time reached (s).
        time: f64,
        /// The cause (`summary.json`'s `cause`).
        message: String,
        /// Output directory.
        out: String,
    },
    /// The run was interrupted (what was computed so far has been written,
    /// `summary.json` with `"status": "interrupted"`).
    #[error(
        "run interrupted at step {step} (t = {time:.6e} s, stroke {stroke:.3} mm); results so far in {out}"
    )]
    Interrupted {
        /// Steps taken.
        step: u64,
        /// Time reached (s).
        time: f64,
        /// Stroke reached (mm).
        stroke: f64,
        /// Output directory.
        out: String,
    },
    /// Writing an output failed.
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// Everything a run produced, in memory.
#[derive(Debug, Clone)]
pub struct RunResult {
    /// `summary.json`'s content.
    pub summary: summary::Summary,
    /// Histories.
    pub history: Vec<HistoryRow>,
    /// The tools' history (`tools.csv`), sampled with `history`.
    pub tool_history: Vec<ToolRow>,
    /// Final snapshot.
    pub last: Snapshot,
    /// Snapshots at the report strokes.
    pub states: Vec<(f64, Snapshot)>,
    /// Seconds spent writing the files after `summary.json` was assembled
    /// (`summary.json`, sections, CSVs, plots): not in its `timing`.
    pub write_s: f64,
}

/// Run `loaded` and write its outputs to `options.out`.
///
/// # Errors
/// Scene/model errors before the run; [`RunError::Failed`] or
/// [`RunError::Interrupted`] for a run that stopped early (after writing what
/// was computed so far); output errors.
pub fn run(loaded: &LoadedScene, options: &RunOptions) -> Result<RunResult, RunError> {
    run_staged(loaded, options, None)
}

/// [`run`], and with `save_state` the blank's whole state written there
/// when the run completes (`formsim run --save-state`, docs/stages.md);
/// `summary.json` records it under `saved_state`.
///
/// # Errors
/// As [`run`]; a state that cannot be written is an output error.
pub fn run_staged(
    loaded: &LoadedScene,
    options: &RunOptions,
    save_state: Option<&std::path::Path>,
) -> Result<RunResult, RunError> {
    reference_checks::ensure_linked();
    let scene = &loaded.scene;
    let out = &options.out;
    std::fs::create_dir_all(out).map_err(|e| OutputError::Io {
        path: out.clone(),
        source: e,
    })?;
    let mut model = crate::scene::build(loaded)?;
    post::check_lines(loaded, &model.mesh)?;
    tracing::info!(
        scene = %scene.scene.name,
        nodes = model.mesh.nodes.len(),
        threads = rayon::current_num_threads(),
        out = %out.display(),
        "run"
    );
    let (setup, notes) = model.set_up().map_err(|e| {
        let message = FileIds::rename(model.file_ids.as_ref(), &e.to_string());
        let key = match model.initial_state {
            Some(_) => "blank.initial_state",
            None => "solver",
        };
        loaded.key_error(key, message)
    })?;
    if let Some(st) = &model.initial_state {
        tracing::info!(
            path = %st.path.display(),
            checksum = %st.checksum,
            "the blank starts from its saved state"
        );
    }
    for n in &notes {
        tracing::info!("initial state: {n}");
    }
    tracing::info!(
        dt_initial = setup.dt_initial,
        added_mass_percent = setup.added_mass_percent,
        "set-up done"
    );
    let setup_warnings = setup_warnings(loaded, &setup);
    for w in &setup_warnings {
        tracing::warn!("{w}");
    }
    let mut rec = Recorder::new(loaded, &model, out);
    let bar = match &options.progress {
        Progress::Hidden => None,
        Progress::Terminal => progress_bar(),
        Progress::Bar(b) => Some(b.clone()),
    };
    let started = Instant::now();
    let stop = step_loop(&mut model, &mut rec, bar.as_ref());
    match (&options.progress, &bar) {
        (Progress::Bar(b), _) => {
            b.finish_with_message(if stop.is_some() { "stopped" } else { "done" })
        }
        (_, Some(b)) => b.finish_and_clear(),
        _ => {}
    }
    let wall = started.elapsed().as_secs_f64();
    let saved = match (save_state, &stop) {
        (Some(path), None) => Some(save(loaded, &model, path)?),
        _ => None,
    };
    finish(
        loaded,
        &model,
        Setup {
            report: &setup,
            warnings: setup_warnings,
        },
        rec,
        out,
        wall,
        Ending { stop, saved },
    )
}

/// How the step loop ended: why it stopped early (if it did), and the
/// state it saved (`--save-state`, a completed run only).
struct Ending {
    stop: Option<Stop>,
    saved: Option<summary::StateRecord>,
}

/// Write the blank's whole state to `path` (docs/stages.md); its record
/// for `summary.json`.
fn save(
    loaded: &LoadedScene,
    model: &Model,
    path: &std::path::Path,
) -> Result<summary::StateRecord, RunError> {
    let state = crate::state_file::StateFile {
        element: loaded.scene.blank.element.clone(),
        material: crate::scene::schema::material_model(&loaded.scene),
        quads: model.mesh.quads.clone(),
        resume: model.solver.save_resume(),
    };
    let checksum = crate::state_file::write(path, &state)
        .map_err(|e| OutputError::io(path, std::io::Error::other(e)))?;
    tracing::info!(path = %path.display(), "state saved");
    Ok(summary::StateRecord {
        path: path.display().to_string(),
        checksum,
    })
}

/// The set-up report and its warnings, for [`finish`].
struct Setup<'a> {
    report: &'a fem_core::SetupReport,
    warnings: Vec<String>,
}

/// The warnings known before the first step: a mesh too coarse for a tool
/// radius, and the mass scaling adds at set-up beyond its bound. They go to
/// the log when the run starts and to `summary.json`'s `warnings` with the
/// rest.
fn setup_warnings(loaded: &LoadedScene, setup: &fem_core::SetupReport) -> Vec<String> {
    let mut w = crate::scene::validate::warnings(loaded);
    w.extend(crate::scene::estimate::added_mass_warnings(
        &loaded.scene,
        setup,
    ));
    w
}

/// Record, step, record … until the end (`None`), or why the run stopped:
/// a solver error, the first non-finite value, an output error while
/// recording, an interrupt.
fn step_loop(
    model: &mut Model,
    rec: &mut Recorder<'_>,
    bar: Option<&indicatif::ProgressBar>,
) -> Option<Stop> {
    let end = model.end_time;
    // With `solver.land_on_step_ends`, the press steps' ends to land on.
    let landings = match (model.press(), model.land_on_step_ends) {
        (Some(p), true) => p.step_ends(),
        _ => Vec::new(),
    };
    let mut press_log = PressLog::default();
    let mut mark = Instant::now();
    loop {
        let (stroke, force, e) = match rec.record(model) {
            Ok(v) => v,
            Err(stop) => {
                rec.output_s += mark.elapsed().as_secs_f64();
                return Some(stop);
            }
        };
        if model.solver.time() >= end || rested(model) {
            rec.output_s += mark.elapsed().as_secs_f64();
            return None;
        }
        rec.output_s += mark.elapsed().as_secs_f64();
        if INTERRUPT.load(Ordering::Relaxed) {
            let s = &model.solver;
            return Some(Stop {
                status: Status::Interrupted,
                cause: format!(
                    "interrupted at step {} (t = {:.6e} s, stroke {stroke:.3} mm)",
                    s.steps(),
                    s.time()
                ),
            });
        }
        // The steps `Solver::run_until(end, …)` takes, landing on `end`
        // (and on the press steps' ends, when asked).
        let now = model.solver.time();
        let target = landings
            .iter()
            .find(|&&t| t > now)
            .map_or(end, |&t| t.min(end));
        let stepped = model.solver.step_toward(target);
        mark = Instant::now();
        if let Err(err) = stepped {
            // The caller reports the stop; at -vv it shows where the log stood.
            tracing::debug!(time = model.solver.time(), "run stopped: {err}");
            // The solver's message names what it tripped on; the first
            // non-finite value of the state, if any, is the cause.
            let err = FileIds::rename(model.file_ids.as_ref(), &err.to_string());
            let cause = match finite::scan(model) {
                Some(v) => format!("{v}; the solver stopped on it: {err}"),
                None => err,
            };
            rec.output_s += mark.elapsed().as_secs_f64();
            return Some(Stop::failed(cause));
        }
        if let Some(v) = finite::ledger(model) {
            rec.output_s += mark.elapsed().as_secs_f64();
            return Some(Stop::failed(finite::scan(model).unwrap_or(v)));
        }
        press_log.update(model, stroke);
        if model.solver.steps().is_multiple_of(64)
            && let Some(b) = bar
        {
            b.set_position((1000.0 * model.solver.time() / end) as u64);
            b.set_message(format!(
                "stroke {stroke:6.2} mm  force {:8.0} N  K/W {:5.3}  balance {:.1e}",
                force,
                warnings::kinetic_to_work(&e),
                e.balance_error
            ));
        }
    }
}

/// The final snapshot, `summary.json` and every file; the stop, if any, as
/// the error (after writing).
fn finish(
    loaded: &LoadedScene,
    model: &Model,
    setup: Setup<'_>,
    mut rec: Recorder<'_>,
    out: &std::path::Path,
    wall: f64,
    ending: Ending,
) -> Result<RunResult, RunError> {
    let Ending { stop, saved } = ending;
    let o = &loaded.scene.output;
    let finish = Instant::now();
    let time = model.solver.time();
    let (stroke, force) = stroke_and_force(model, o.symmetry_factor);
    let last = rec.post.snapshot(model, time, stroke, force);
    if stop.is_some() {
        // The histories up to the last finite sample (the recorder keeps no
        // sample of a state with a non-finite value: this is a guard).
        let n = rec
            .history
            .iter()
            .position(|h| !h.is_finite())
            .unwrap_or(rec.history.len());
        rec.history.truncate(n);
        rec.tool_history.truncate(n);
    }
    let timing = timing::Timing::new(model, rec.output_s, finish.elapsed().as_secs_f64());
    let springback = springback::summary(model, &loaded.scene);
    let profiles = match (model.solver.springback(), &springback) {
        (Some(r), Some((_, d))) => {
            let released: Vec<fem_core::Vec3> =
                r.x_release.iter().zip(d).map(|(x, u)| x + u).collect();
            profile::measure_all(&model.mesh, &o.profiles, &r.x_release, Some(&released))
        }
        _ => profile::measure_all(&model.mesh, &o.profiles, &model.solver.state().x, None),
    };
    let summary = summary::Summary::new(summary::Inputs {
        loaded,
        model,
        setup: setup.report,
        wall,
        last: &last,
        states: &rec.states,
        force_max: rec.force_max,
        ki_max: rec.ki_max,
        kw_max: rec.kw_max,
        setup_warnings: setup.warnings,
        hg_max: rec.hg_max,
        reference: rec
            .reference
            .as_ref()
            .map(|(check, s)| (*check, s.as_ref())),
        clamp_seen: rec.clamp_seen,
        stop: stop.as_ref(),
        dt0: setup.report.dt_initial,
        timing,
        springback: springback.as_ref().map(|(s, _)| s.clone()),
        profiles: &profiles,
    });
    let mut summary = summary;
    summary.initial_state = model.initial_state.as_ref().map(|s| summary::StateRecord {
        path: s.path.display().to_string(),
        checksum: s.checksum.clone(),
    });
    summary.saved_state = saved;
    let mut result = RunResult {
        summary,
        history: rec.history,
        tool_history: rec.tool_history,
        last,
        states: rec.states,
        write_s: 0.0,
    };
    let writing = Instant::now();
    write::all(out, &result, model, o.plots, &rec.frames)?;
    if let Some((_, d)) = &springback {
        let path = out.join("springback.csv");
        springback::csv(&path, model, d).map_err(|e| OutputError::io(&path, e))?;
    }
    profile::write(out, &profiles, o.plots)?;
    result.write_s = writing.elapsed().as_secs_f64();
    let out = out.display().to_string();
    match stop {
        None => Ok(result),
        Some(Stop {
            status: Status::Interrupted,
            ..
        }) => Err(RunError::Interrupted {
            step: model.solver.steps(),
            time,
            stroke,
            out,
        }),
        Some(Stop { cause, .. }) => Err(RunError::Failed {
            time,
            message: cause,
            out,
        }),
    }
}

/// Whether the programme has ended with a springback step that came to
/// rest: the run ends there rather than at the step's longest duration.
pub(crate) fn rested(model: &Model) -> bool {
    model.press().is_some_and(fem_core::Press::finished)
        && model.solver.springback().is_some_and(|s| s.settled)
}

/// Stroke (mm) and punch force (full-model N) of the stroke tool.
fn stroke_and_force(model: &Model, symmetry: f64) -> (f64, f64) {
    match (model.stroke, model.contact()) {
        (Some(s), Some(c)) => {
            let stroke = model
                .press()
                .map_or(0.0, |p| p.displacement(s.index).dot(&s.direction));
            let force = -c.reactions()[s.index].dot(&s.direction) * symmetry;
            (stroke, force)
        }
        _ => (0.0, 0.0),
    }
}

fn progress_bar() -> Option<indicatif::ProgressBar> {
    let bar = indicatif::ProgressBar::new(1000);
    let style = indicatif::ProgressStyle::with_template(
        "{elapsed_precise} [{bar:30}] {percent:>3}% eta {eta}  {msg}",
    )
    .ok()?
    .progress_chars("=> ");
    bar.set_style(style);
    Some(bar)
}

/// The press step the run is in, logged (`-v`) as it changes, with a span
/// that the engine's messages of that step carry.
#[derive(Default)]
struct PressLog {
    step: Option<usize>,
    span: Option<tracing::span::EnteredSpan>,
}

impl PressLog {
    fn update(&mut self, model: &Model, stroke: f64) {
        let Some(press) = model.press() else {
            return;
        };
        let k = press.current_step();
        if self.step == Some(k) {
            return;
        }
        self.step = Some(k);
        self.span = None;
        if let Some(s) = press.steps().get(k) {
            let time = model.solver.time();
            self.span = Some(tracing::info_span!("press step", name = %s.name).entered());
            tracing::info!(time, stroke, "press step {k} `{}` starts", s.name);
        }
    }
}
