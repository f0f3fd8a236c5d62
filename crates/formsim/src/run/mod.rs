//! `formsim run`: one forming simulation of a scene, from set-up to the files
//! of `DIR` (`summary.json`, `sections/*.csv`, `energy.csv`,
//! `punch_force.csv`, `vtk/*.vtu` + `blank.pvd`, PNG plots).
//!
//! The time-step loop calls [`fem_core::Solver::step`] (the shells hand their
//! thickness, and flow stress when a law reads it, to contact inside the
//! step, through the solver's shared fields) and samples histories on a
//! fixed schedule; everything that allocates (snapshots,
//! frames) happens only at the scheduled times.

pub mod out_dir;
pub mod post;
pub mod reference;
pub mod summary;
pub mod timing;
pub mod tools_report;
pub mod warnings;
pub mod write;

use crate::output::OutputError;
use crate::scene::validate::dof_from_name;
use crate::scene::{LoadedScene, Model, SceneError};
use post::{Post, Snapshot};
use std::path::PathBuf;
use std::time::Instant;

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
    /// The solver stopped (what was computed so far has been written).
    #[error("run stopped at t = {time:.6e} s: {message} (results so far in {out})")]
    Solver {
        /// Time reached (s).
        time: f64,
        /// The solver's message.
        message: String,
        /// Output directory.
        out: String,
    },
    /// Writing an output failed.
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// One row of the histories (`energy.csv`, `punch_force.csv`).
#[derive(Debug, Clone, Copy, Default)]
pub struct HistoryRow {
    /// Time (s).
    pub time: f64,
    /// Stroke (mm).
    pub stroke: f64,
    /// Punch force, full-model equivalent (N).
    pub punch_force: f64,
    /// Energies at this time.
    pub energy: fem_core::EnergyLedger,
    /// Time step (s).
    pub dt: f64,
}

/// Everything a run produced, in memory.
#[derive(Debug, Clone)]
pub struct RunResult {
    /// `summary.json`'s content.
    pub summary: summary::Summary,
    /// Histories.
    pub history: Vec<HistoryRow>,
    /// The tools' history (`tools.csv`), sampled with `history`.
    pub tool_history: Vec<tools_report::ToolRow>,
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
/// Scene/model errors before the run; a solver error during the run (after
/// writing what was computed so far); output errors.
pub fn run(loaded: &LoadedScene, options: &RunOptions) -> Result<RunResult, RunError> {
    let scene = &loaded.scene;
    let out = &options.out;
    std::fs::create_dir_all(out).map_err(|e| OutputError::Io {
        path: out.clone(),
        source: e,
    })?;
    let mut model = crate::scene::build(loaded)?;
    let post = Post::new(
        &model.mesh,
        &scene.output.sections,
        &scene.output.draw_in,
        scene.output.punch_edge_distance,
    );
    tracing::info!(
        scene = %scene.scene.name,
        nodes = model.mesh.nodes.len(),
        threads = rayon::current_num_threads(),
        out = %out.display(),
        "run"
    );
    let setup = model
        .solver
        .initialize()
        .map_err(|e| loaded.key_error("solver", e.to_string()))?;
    tracing::info!(
        dt_initial = setup.dt_initial,
        added_mass_percent = setup.added_mass_percent,
        "set-up done"
    );
    let mut press_log = PressLog::default();
    let end = model.end_time;
    let o = &scene.output;
    let sample_every = end / (o.history_points as f64 - 1.0);
    let frame_every = if o.frames > 0 {
        end / o.frames as f64
    } else {
        f64::INFINITY
    };
    let mut next_sample = 0.0;
    let mut next_frame = 0.0;
    let mut history = Vec::with_capacity(o.history_points + 2);
    let mut tool_history = Vec::with_capacity(o.history_points + 2);
    let axes = tools_report::press_axes(&model);
    let mut frames: Vec<(f64, String)> = Vec::new();
    let mut strokes: Vec<f64> = o.report_strokes.clone();
    strokes.sort_by(f64::total_cmp);
    let mut states: Vec<(f64, Snapshot)> = Vec::new();
    let mut ki_max: f64 = 0.0;
    let mut hg_max: f64 = 0.0;
    let mut force_max: f64 = 0.0;
    let mut pull_sum = (0.0, 0usize);
    // The strip's holder: force delivered and prescribed, summed while drawing.
    let strip_holder = strip_holder(loaded, &model);
    let mut holder_sum = (0.0, 0.0);
    let mut clamp_seen = false;
    let bar = match &options.progress {
        Progress::Hidden => None,
        Progress::Terminal => progress_bar(),
        Progress::Bar(b) => Some(b.clone()),
    };
    let started = Instant::now();
    let mut stop: Option<String> = None;
    let vtk_dir = out.join("vtk");
    if o.frames > 0 {
        std::fs::create_dir_all(&vtk_dir).map_err(|e| OutputError::Io {
            path: vtk_dir.clone(),
            source: e,
        })?;
    }
    let pull = pulled_set(loaded);
    let dt0 = setup.dt_initial;
    // The loop's time outside `Solver::step` (sampling, snapshots, frames,
    // progress): from `mark` to each step, and after the last.
    let mut output_s = 0.0;
    let mut mark = Instant::now();
    loop {
        let time = model.solver.time();
        let (stroke, force) = stroke_and_force(&model, o.symmetry_factor);
        force_max = force_max.max(force);
        let e = *model.solver.ledger();
        let forming = match model.stroke {
            Some(_) => stroke >= o.forming_starts_at,
            None => time >= 0.1 * end,
        };
        if forming && e.internal > 0.0 {
            ki_max = ki_max.max(e.kinetic / e.internal);
            hg_max = hg_max.max(e.hourglass / e.internal);
        }
        if let Some(c) = model.contact() {
            clamp_seen |= c.pairs().iter().any(|p| p.clamped);
        }
        if let Some((set, dof, from)) = &pull
            && time >= *from
        {
            let (f, _) = model
                .solver
                .reaction(set)
                .map_err(|e| loaded.key_error("output", e.to_string()))?;
            pull_sum.0 += f[*dof].abs();
            pull_sum.1 += 1;
            if let (Some(i), Some(c)) = (strip_holder, model.contact()) {
                holder_sum.0 -= c.reactions()[i].dot(&axes[i]);
                holder_sum.1 += c.press().and_then(|p| p.applied_force(i)).unwrap_or(0.0);
            }
        }
        if time >= next_sample || time >= end {
            history.push(HistoryRow {
                time,
                stroke,
                punch_force: force,
                energy: e,
                dt: model.solver.dt_next(),
            });
            tool_history.push(tools_report::sample(&model, &axes, time, stroke));
            next_sample += sample_every;
        }
        while let Some(&r) = strokes.first() {
            if stroke >= r - 1e-4 {
                states.push((r, post.snapshot(&model, time, stroke, force)));
                strokes.remove(0);
            } else {
                break;
            }
        }
        if o.frames > 0 && (time >= next_frame || time >= end) {
            let name = format!("blank_{:04}.vtu", frames.len());
            write::frame(&vtk_dir.join(&name), &model, time, stroke)?;
            // Relative to blank.pvd, which sits beside vtk/.
            frames.push((time, format!("vtk/{name}")));
            next_frame += frame_every;
        }
        if time >= end {
            break;
        }
        // The steps `Solver::run_until(end, …)` takes, landing on `end`.
        output_s += mark.elapsed().as_secs_f64();
        let stepped = model.solver.step_toward(end);
        mark = Instant::now();
        if let Err(err) = stepped {
            // The caller reports the stop; at -vv it shows where the log stood.
            tracing::debug!(time = model.solver.time(), "run stopped: {err}");
            stop = Some(err.to_string());
            break;
        }
        press_log.update(&model, stroke);
        if model.solver.steps() % 64 == 0
            && let Some(b) = &bar
        {
            b.set_position((1000.0 * model.solver.time() / end) as u64);
            b.set_message(format!(
                "stroke {stroke:6.2} mm  force {:8.0} N  K/I {:5.3}  balance {:.1e}",
                force,
                if e.internal > 0.0 {
                    e.kinetic / e.internal
                } else {
                    0.0
                },
                e.balance_error
            ));
        }
    }
    match (&options.progress, &bar) {
        (Progress::Bar(b), _) => {
            b.finish_with_message(if stop.is_some() { "stopped" } else { "done" })
        }
        (_, Some(b)) => b.finish_and_clear(),
        _ => {}
    }
    output_s += mark.elapsed().as_secs_f64();
    let wall = started.elapsed().as_secs_f64();
    let finish = Instant::now();
    let time = model.solver.time();
    let (stroke, force) = stroke_and_force(&model, o.symmetry_factor);
    let last = post.snapshot(&model, time, stroke, force);
    if o.frames > 0 {
        write::pvd(&out.join("blank.pvd"), &frames)?;
    }
    let timing = timing::Timing::new(&model, output_s, finish.elapsed().as_secs_f64());
    let summary = summary::Summary::new(summary::Inputs {
        loaded,
        model: &model,
        setup: &setup,
        wall,
        last: &last,
        states: &states,
        force_max,
        ki_max,
        hg_max,
        capstan: (pull_sum.1 > 0).then(|| pull_sum.0 / pull_sum.1 as f64),
        holder: (pull_sum.1 > 0 && strip_holder.is_some()).then(|| {
            let n = pull_sum.1 as f64;
            (holder_sum.0 / n, holder_sum.1 / n)
        }),
        clamp_seen,
        stopped: stop.clone(),
        dt0,
        timing,
    });
    let mut result = RunResult {
        summary,
        history,
        tool_history,
        last,
        states,
        write_s: 0.0,
    };
    let writing = Instant::now();
    write::all(out, &result, &model, o.plots)?;
    result.write_s = writing.elapsed().as_secs_f64();
    if let Some(message) = stop {
        return Err(RunError::Solver {
            time,
            message,
            out: out.display().to_string(),
        });
    }
    Ok(result)
}

/// Stroke (mm) and punch force (full-model N) of the stroke tool.
fn stroke_and_force(model: &Model, symmetry: f64) -> (f64, f64) {
    match (model.stroke, model.contact()) {
        (Some(s), Some(c)) => {
            let stroke = c
                .press()
                .map_or(0.0, |p| p.displacement(s.index).dot(&s.direction));
            let force = -c.reactions()[s.index].dot(&s.direction) * symmetry;
            (stroke, force)
        }
        _ => (0.0, 0.0),
    }
}

/// The node set, DOF axis and averaging start of the pulled end of a
/// capstan, block or strip scene.
fn pulled_set(loaded: &LoadedScene) -> Option<(String, usize, f64)> {
    let kind = loaded.scene.scene.kind;
    loaded
        .scene
        .output
        .pulled_ends()
        .find(|e| e.kind == kind)
        .map(|e| {
            (
                e.pull_set.to_string(),
                dof_from_name(e.pull_dof).map_or(0, |d| d.axis()),
                e.average_from,
            )
        })
}

/// The index of a strip-draw scene's holder.
fn strip_holder(loaded: &LoadedScene, model: &Model) -> Option<usize> {
    let strip = loaded.scene.output.strip.as_ref()?;
    model.tool_names.iter().position(|n| *n == strip.holder)
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
        let Some(press) = model.contact().and_then(|c| c.press()) else {
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
