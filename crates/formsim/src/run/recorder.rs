//! What the run loop records between steps: histories on their schedule,
//! snapshots at the report strokes, VTK frames, the running maxima
//! `summary.json` needs and what the scene's reference check samples
//! ([`super::reference_checks`]). Before it keeps the state (a history
//! sample, a report stroke, a frame) it checks that every value of the
//! model is finite ([`super::finite::scan`]): a non-finite value stops the
//! run, and no kept sample holds one.

use super::post::{Post, Snapshot};
use super::warnings::INTERNAL_SHARE_MIN;
use super::{HistoryRow, Stop, ToolRow, finite, stroke_and_force, tools_report, write};
use crate::output::OutputError;
use crate::scene::kind::{ReferenceCheck, Sampler};
use crate::scene::{LoadedScene, Model};
use fem_core::EnergyLedger;
use std::path::{Path, PathBuf};

/// The recorder of one run (see the module docs).
pub(super) struct Recorder<'a> {
    loaded: &'a LoadedScene,
    pub post: Post,
    vtk_dir: PathBuf,
    sample_every: f64,
    frame_every: f64,
    next_sample: f64,
    next_frame: f64,
    /// The frame as the tools let go of the blank is written.
    release_framed: bool,
    axes: Vec<plugins_api::Vec3>,
    strokes: Vec<f64>,
    /// The scene's reference check and what it samples.
    pub reference: Option<(&'static ReferenceCheck, Box<dyn Sampler>)>,
    pub history: Vec<HistoryRow>,
    pub tool_history: Vec<ToolRow>,
    pub frames: Vec<(f64, String)>,
    pub states: Vec<(f64, Snapshot)>,
    pub ki_max: f64,
    pub kw_max: f64,
    pub hg_max: f64,
    pub force_max: f64,
    pub clamp_seen: bool,
    /// The loop's seconds outside `Solver::step` (sampling, snapshots,
    /// frames, progress).
    pub output_s: f64,
}

impl<'a> Recorder<'a> {
    /// A recorder for `model`, writing frames under `out/vtk` (created with
    /// the first frame).
    pub fn new(loaded: &'a LoadedScene, model: &Model, out: &Path) -> Self {
        let o = &loaded.scene.output;
        let (start, end) = (model.start_time, model.end_time);
        let span = end - start;
        let vtk_dir = out.join("vtk");
        let mut strokes = o.report_strokes.clone();
        strokes.sort_by(f64::total_cmp);
        Self {
            loaded,
            post: Post::new(&model.mesh, &o.sections, &o.draw_in, o.punch_edge_distance),
            vtk_dir,
            sample_every: span / (o.history_points as f64 - 1.0),
            frame_every: if o.frames > 0 {
                span / o.frames as f64
            } else {
                f64::INFINITY
            },
            next_sample: start,
            next_frame: start,
            release_framed: false,
            axes: tools_report::press_axes(model),
            strokes,
            reference: crate::scene::kind::reference_check(&loaded.scene.scene.kind)
                .and_then(|check| Some((check, check.sampler(loaded, model)?))),
            history: Vec::with_capacity(o.history_points + 2),
            tool_history: Vec::with_capacity(o.history_points + 2),
            frames: Vec::new(),
            states: Vec::new(),
            ki_max: 0.0,
            kw_max: 0.0,
            hg_max: 0.0,
            force_max: 0.0,
            clamp_seen: false,
            output_s: 0.0,
        }
    }

    /// Record the model as it is now; returns its stroke, punch force and
    /// energy ledger (for the progress bar), or why the run must stop: a
    /// non-finite value in a state due to be kept, a frame that could not be
    /// written, a pulled set the solver does not know.
    pub fn record(&mut self, model: &Model) -> Result<(f64, f64, EnergyLedger), Stop> {
        let o = &self.loaded.scene.output;
        let end = model.end_time;
        let time = model.solver.time();
        let (stroke, force) = stroke_and_force(model, o.symmetry_factor);
        self.force_max = self.force_max.max(force);
        let e = *model.solver.ledger();
        let forming = match model.stroke {
            Some(_) => stroke >= o.forming_starts_at,
            None => time - model.start_time >= 0.1 * (end - model.start_time),
        };
        // A springback step's motion is the release itself, not a sign of a
        // forming run too fast to be quasi-static.
        let released = model.solver.springback().is_some();
        let forming = forming && !released;
        if forming {
            self.kw_max = self.kw_max.max(super::warnings::kinetic_to_work(&e));
        }
        // Ratios over the internal energy only where it is a measure.
        if forming && e.internal > 0.0 && e.internal >= INTERNAL_SHARE_MIN * e.external {
            let kinetic = e.kinetic + e.kinetic_added;
            self.ki_max = self.ki_max.max(kinetic / e.internal);
            self.hg_max = self.hg_max.max(e.hourglass / e.internal);
        }
        if let Some(c) = model.contact() {
            self.clamp_seen |= c.pairs().iter().any(|p| p.clamped);
        }
        if let Some((_, sampler)) = &mut self.reference {
            sampler.sample(self.loaded, model).map_err(Stop::failed)?;
        }
        let end_now = time >= end || super::rested(model);
        let sample = time >= self.next_sample || end_now;
        let state_due = self.strokes.first().is_some_and(|&r| stroke >= r - 1e-4);
        // A frame as the tools let go: the shape before springback.
        let let_go = released && !self.release_framed;
        self.release_framed |= released;
        let frame_due = o.frames > 0 && (time >= self.next_frame || end_now || let_go);
        if (sample || state_due || frame_due)
            && let Some(v) = finite::scan(model)
        {
            return Err(Stop::failed(v));
        }
        if sample {
            self.history.push(HistoryRow {
                time,
                stroke,
                punch_force: force,
                energy: e,
                dt: model.solver.dt_next(),
            });
            self.tool_history
                .push(tools_report::sample(model, &self.axes, time, stroke));
            self.next_sample += self.sample_every;
        }
        while let Some(&r) = self.strokes.first() {
            if stroke >= r - 1e-4 {
                self.states
                    .push((r, self.post.snapshot(model, time, stroke, force)));
                self.strokes.remove(0);
            } else {
                break;
            }
        }
        if frame_due {
            if self.frames.is_empty() {
                std::fs::create_dir_all(&self.vtk_dir)
                    .map_err(|e| Stop::failed(OutputError::io(&self.vtk_dir, e)))?;
            }
            let name = format!("blank_{:04}.vtu", self.frames.len());
            write::frame(&self.vtk_dir.join(&name), model, time, stroke).map_err(Stop::failed)?;
            // Relative to blank.pvd, which sits beside vtk/.
            self.frames.push((time, format!("vtk/{name}")));
            self.next_frame += self.frame_every;
        }
        Ok((stroke, force, e))
    }
}
