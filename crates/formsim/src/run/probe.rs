//! What a scene's results will hold, known before any run: the model is
//! built and set up, and `summary.json` is assembled from its initial state
//! with a state at every report stroke. `study` and `identify` check their
//! quantity names, sections and strokes against it before running anything.

use super::RunError;
use super::post::Post;
use super::reference_checks::{Figures, Sampler};
use super::summary::{Inputs, Summary};
use crate::identify::observe::lookup;
use crate::scene::LoadedScene;

/// The shape of a scene's results.
#[derive(Debug, Clone)]
pub struct Probe {
    /// `summary.json` of the initial state, with every report stroke's state.
    summary: serde_json::Value,
    /// Section names (`output.sections`).
    sections: Vec<String>,
    /// Report strokes (mm).
    strokes: Vec<f64>,
}

/// Build and set up `loaded` and assemble its summary without a step.
///
/// # Errors
/// The scene does not build or set up.
pub fn probe(loaded: &LoadedScene) -> Result<Probe, RunError> {
    let mut model = crate::scene::build(loaded)?;
    super::post::check_lines(loaded, &model.mesh)?;
    let setup = model.solver.initialize().map_err(|e| {
        let message =
            crate::scene::blank_mesh::FileIds::rename(model.file_ids.as_ref(), &e.to_string());
        loaded.key_error("solver", message)
    })?;
    let o = &loaded.scene.output;
    let post = Post::new(&model.mesh, &o.sections, &o.draw_in, o.punch_edge_distance);
    let last = post.snapshot(&model, 0.0, 0.0, 0.0);
    let states: Vec<_> = o
        .report_strokes
        .iter()
        .map(|r| (*r, last.clone()))
        .collect();
    // A reference check reports its figures once it has sampled: taken as
    // sampled, with nothing in its means.
    let check = crate::scene::kind::reference_check(&loaded.scene.scene.kind);
    let sampler = check.and_then(|c| c.sampler(loaded, &model));
    let sampled = sampler.as_deref().map(Sampled);
    let summary = Summary::new(Inputs {
        loaded,
        model: &model,
        setup: &setup,
        wall: 0.0,
        last: &last,
        states: &states,
        force_max: 0.0,
        ki_max: 0.0,
        kw_max: 0.0,
        setup_warnings: Vec::new(),
        hg_max: 0.0,
        reference: check.zip(sampled.as_ref().map(|s| s as &dyn Sampler)),
        clamp_seen: false,
        stop: None,
        dt0: setup.dt_initial,
        timing: super::timing::Timing::new(&model, 0.0, 0.0),
        // Before a step there is no springback to report.
        springback: None,
        // Nor a formed shape to measure.
        profiles: &[],
    });
    let summary = serde_json::to_value(&summary)
        .map_err(|e| loaded.key_error("output", format!("summary: {e}")))?;
    Ok(Probe {
        summary,
        sections: o.sections.iter().map(|s| s.name.clone()).collect(),
        strokes: o.report_strokes.clone(),
    })
}

/// A check's sampler taken as having sampled (the probe's).
struct Sampled<'a>(&'a dyn Sampler);

impl Sampler for Sampled<'_> {
    fn sample(
        &mut self,
        _: &LoadedScene,
        _: &crate::scene::Model,
    ) -> Result<(), crate::scene::SceneError> {
        Ok(())
    }

    fn sampled(&self) -> bool {
        true
    }

    fn figures(&self, mu: f64) -> Option<Figures> {
        self.0.figures(mu)
    }
}

impl Probe {
    /// Check that `summary.json` will have a number at the dotted `key`.
    /// Under `tools` and `pairs` (whose steps appear as the run reaches
    /// them) only the tool's or pair's name is checked.
    ///
    /// # Errors
    /// One line: the key and what the scene reports instead.
    pub fn check_key(&self, key: &str) -> Result<(), String> {
        let parts: Vec<&str> = key.split('.').collect();
        let grows = ["tools", "pairs"];
        let checked = match parts.iter().position(|p| grows.contains(p)) {
            Some(i) if parts.len() > i + 1 => lookup(&self.summary, &parts[..i + 2]).is_some(),
            _ => lookup(&self.summary, &parts).is_some_and(serde_json::Value::is_number),
        };
        if checked {
            return Ok(());
        }
        Err(format!(
            "`{key}`: this scene's summary.json has no number there ({})",
            self.what_it_reports()
        ))
    }

    /// Check that the run reports section `section` (at `stroke`, a report
    /// stroke, if given).
    ///
    /// # Errors
    /// One line naming the section or stroke and what the scene reports.
    pub fn check_curve(&self, section: &str, stroke: Option<f64>) -> Result<(), String> {
        let stroke_known = stroke.is_none_or(|s| {
            self.strokes
                .iter()
                .any(|r| (r - s).abs() <= 1e-9 * s.abs().max(1.0))
        });
        if self.sections.iter().any(|s| s == section) && stroke_known {
            return Ok(());
        }
        Err(format!(
            "section `{section}`{}: not reported by this scene ({})",
            stroke.map_or(String::new(), |s| format!(" at stroke {s} mm")),
            self.what_it_reports()
        ))
    }

    /// The sections, draw-in points and report strokes, for messages.
    fn what_it_reports(&self) -> String {
        let names = |key: &str| {
            self.summary[key]
                .as_object()
                .map(|o| o.keys().cloned().collect::<Vec<_>>().join(", "))
                .filter(|s| !s.is_empty())
                .unwrap_or_else(|| "none".into())
        };
        let strokes: Vec<String> = self.strokes.iter().map(|s| format!("{s}")).collect();
        format!(
            "sections: {}; draw_in: {}; report strokes (mm): {}",
            names("sections"),
            names("draw_in"),
            if strokes.is_empty() {
                "none".into()
            } else {
                strokes.join(", ")
            }
        )
    }
}
