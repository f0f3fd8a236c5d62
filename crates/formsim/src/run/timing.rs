//! `summary.json`'s `timing`: where the wall time of a run went, per stage
//! (docs/contact.md, "Where a step goes").

use crate::scene::Model;
use serde::Serialize;

/// Contact's seconds: the whole effect and its stages.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct ContactSeconds {
    /// The contact effect's whole `add_forces`, as the solver timed it (s).
    pub total: f64,
    /// Moving the tools (the press) (s).
    pub press: f64,
    /// The blank's nodal geometry update (s).
    pub geometry: f64,
    /// Candidate selection of the pairs (step 1a) (s).
    pub broad_phase: f64,
    /// Projection of the candidates on the tools (step 1b) (s).
    pub projection: f64,
    /// Gap, penalty and gathering of the touching points (step 1c) (s).
    pub normal: f64,
    /// The friction laws' batch return mapping (step 2) (s).
    pub friction: f64,
    /// Forces, reactions and energies (step 3) (s).
    pub scatter: f64,
}

/// Seconds spent over the run, per stage (wall clock).
///
/// `elements + contact.total + engine + output` is the time-step loop,
/// `wall_time_s` (to the clock readings between the stages); `final_output`
/// comes after the loop.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct Timing {
    /// The shells' `add_forces` (every effect but contact) (s).
    pub elements: f64,
    /// Contact (s).
    pub contact: ContactSeconds,
    /// The rest of `Solver::step`: integration, constraints, energy ledger,
    /// force assembly, stable time step and mass scaling (s).
    pub engine: f64,
    /// The loop's time outside `Solver::step`: sampling the histories,
    /// snapshots at the report strokes, VTK frames, progress (s).
    pub output: f64,
    /// After the loop: the final snapshot and `blank.pvd` (s). The files
    /// written after `summary.json` is assembled (`summary.json` itself,
    /// sections, CSVs, plots) are not in it; `formsim run` prints their time.
    pub final_output: f64,
}

impl Timing {
    /// Assemble from the solver's and contact's sums, the loop's `output`
    /// seconds and the `final_output` seconds.
    pub fn new(model: &Model, output: f64, final_output: f64) -> Self {
        let t = model.solver.timing();
        let contact_index = model.contact.map(|id| id.0);
        let effect = |k: usize| t.effects.get(k).copied().unwrap_or(0.0);
        let elements = (0..t.effects.len())
            .filter(|&k| Some(k) != contact_index)
            .map(effect)
            .sum();
        let contact = match (contact_index, model.contact()) {
            (Some(k), Some(c)) => {
                let s = c.timing();
                ContactSeconds {
                    total: effect(k),
                    press: s.press,
                    geometry: s.geometry,
                    broad_phase: s.broad_phase,
                    projection: s.projection,
                    normal: s.normal,
                    friction: s.friction,
                    scatter: s.scatter,
                }
            }
            _ => ContactSeconds::default(),
        };
        Self {
            elements,
            contact,
            engine: t.engine(),
            output,
            final_output,
        }
    }

    /// The loop's stages summed: `elements + contact.total + engine + output` (s).
    pub fn loop_sum(&self) -> f64 {
        self.elements + self.contact.total + self.engine + self.output
    }

    /// One line for the terminal, in seconds and % of the loop's `wall` time,
    /// e.g. `elements 8.1 s (25 %), contact 20.3 s (63 %: projection 11.0,
    /// …), engine 2.0 s (6 %), output 1.2 s (4 %)`.
    pub fn line(&self, wall: f64) -> String {
        let pct = |s: f64| {
            if wall > 0.0 { 100.0 * s / wall } else { 0.0 }
        };
        let c = &self.contact;
        format!(
            "elements {:.2} s ({:.0} %), contact {:.2} s ({:.0} %: press {:.2}, geometry {:.2}, \
             broad phase {:.2}, projection {:.2}, normal {:.2}, friction {:.2}, scatter {:.2}), \
             engine {:.2} s ({:.0} %), output {:.2} s ({:.0} %)",
            self.elements,
            pct(self.elements),
            c.total,
            pct(c.total),
            c.press,
            c.geometry,
            c.broad_phase,
            c.projection,
            c.normal,
            c.friction,
            c.scatter,
            self.engine,
            pct(self.engine),
            self.output,
            pct(self.output),
        )
    }
}
