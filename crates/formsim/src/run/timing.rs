//! `summary.json`'s `timing`: where the wall time of a run went, per stage
//! (docs/contact.md, "Where a step goes").

use crate::scene::Model;
use contact::ContactTiming;
use serde::Serialize;

/// Contact's seconds: the whole effect (`total`, as the solver timed it) and
/// its stages (contact's own [`ContactTiming`]), written to `summary.json` as
/// one object: `{total, geometry, broad_phase, projection, normal,
/// friction, scatter}` (s).
#[derive(Debug, Clone, Copy, Default)]
pub struct ContactSeconds {
    /// The contact effect's whole `add_forces` (s).
    pub total: f64,
    /// Its stages (s).
    pub stages: ContactTiming,
}

impl Serialize for ContactSeconds {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let stages = self.stages.stages();
        let mut map = serializer.serialize_map(Some(1 + stages.len()))?;
        map.serialize_entry("total", &self.total)?;
        for (name, seconds) in stages {
            map.serialize_entry(name, &seconds)?;
        }
        map.end()
    }
}

/// Seconds spent over the run, per stage (wall clock).
///
/// `press + elements + contact.total + engine + output` is the time-step loop,
/// `wall_time_s` (to the clock readings between the stages); `final_output`
/// comes after the loop.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct Timing {
    /// The press stage: moving the tools (s).
    pub press: f64,
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
            (Some(k), Some(c)) => ContactSeconds {
                total: effect(k),
                stages: c.timing(),
            },
            _ => ContactSeconds::default(),
        };
        Self {
            press: t.press,
            elements,
            contact,
            engine: t.engine(),
            output,
            final_output,
        }
    }

    /// The loop's stages summed: `press + elements + contact.total + engine
    /// + output` (s).
    pub fn loop_sum(&self) -> f64 {
        self.press + self.elements + self.contact.total + self.engine + self.output
    }

    /// One line for the terminal, in seconds and % of the loop's `wall` time,
    /// e.g. `press 0.01 s (0 %), elements 8.1 s (25 %), contact 20.3 s (63 %: projection 11.0,
    /// …), engine 2.0 s (6 %), output 1.2 s (4 %)`.
    pub fn line(&self, wall: f64) -> String {
        let pct = |s: f64| {
            if wall > 0.0 { 100.0 * s / wall } else { 0.0 }
        };
        let c = &self.contact;
        let stages: Vec<String> = c
            .stages
            .stages()
            .iter()
            .map(|(name, seconds)| format!("{} {seconds:.2}", name.replace('_', " ")))
            .collect();
        format!(
            "press {:.2} s ({:.0} %), elements {:.2} s ({:.0} %), contact {:.2} s ({:.0} %: {}), \
             engine {:.2} s ({:.0} %), output {:.2} s ({:.0} %)",
            self.press,
            pct(self.press),
            self.elements,
            pct(self.elements),
            c.total,
            pct(c.total),
            stages.join(", "),
            self.engine,
            pct(self.engine),
            self.output,
            pct(self.output),
        )
    }
}
