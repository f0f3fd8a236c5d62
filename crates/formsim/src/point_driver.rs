//! Integrating one contact point along a prescribed history (`formsim friction-point`).

use std::io::Write;
use std::path::Path;

use plugins_api::{FrictionError, PointIntegrator, PointState, StepOutput};

use crate::history::History;

/// One output row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Record {
    /// Time (s).
    pub t: f64,
    /// Pressure (MPa).
    pub p: f64,
    /// The step's result.
    pub out: StepOutput,
    /// Cumulative dissipation per unit area (N/mm).
    pub dissipation: f64,
    /// Frictional work density `ω` after the step (N/mm).
    pub omega: f64,
}

impl Record {
    /// Effective friction coefficient `|t|/p` (0 for open contact).
    #[must_use]
    pub fn mu_eff(&self) -> f64 {
        if self.p > 0.0 {
            self.out.t.norm() / self.p
        } else {
            0.0
        }
    }
}

/// What a run did, for the one-paragraph report.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunSummary {
    /// Steps integrated.
    pub steps: usize,
    /// Steps in stick.
    pub stick: usize,
    /// Steps in slip.
    pub slip: usize,
    /// Steps with open contact.
    pub open: usize,
    /// Steps where a clamp of the law was active, and the first time it was.
    pub clamped: usize,
    /// First time a clamp was active (s).
    pub first_clamp_t: Option<f64>,
    /// Final frictional work density (N/mm).
    pub omega: f64,
    /// Largest `|t|/τ_c - 1` over slipping steps (should be ≤ 1e-12).
    pub max_excess: f64,
}

/// Integrate the history with `integrator`, from a virgin point.
///
/// # Errors
/// The first step that fails, with the history file's line number.
pub fn run(
    integrator: &dyn PointIntegrator,
    history: &History,
    file: &str,
) -> Result<(Vec<Record>, RunSummary), String> {
    let mut state = PointState::default();
    let mut records = Vec::with_capacity(history.steps.len());
    let mut summary = RunSummary::default();
    let mut dissipation = 0.0;
    for ((input, &t), &line) in history.steps.iter().zip(&history.times).zip(&history.lines) {
        let out = integrator
            .step(&mut state, input)
            .map_err(|e: FrictionError| format!("{file}:{line}: {e}"))?;
        let finite = out
            .t
            .iter()
            .chain([out.dgamma, out.dissipation, state.omega].iter())
            .all(|v| v.is_finite());
        if !finite {
            return Err(format!(
                "{file}:{line}: {} produced a non-finite result",
                integrator.law_name()
            ));
        }
        dissipation += out.dissipation;
        summary.steps += 1;
        if out.open {
            summary.open += 1;
        } else if out.stick {
            summary.stick += 1;
        } else {
            summary.slip += 1;
            if out.tau_c > 0.0 {
                summary.max_excess = summary.max_excess.max(out.t.norm() / out.tau_c - 1.0);
            }
        }
        if out.clamped {
            summary.clamped += 1;
            summary.first_clamp_t.get_or_insert(t);
        }
        records.push(Record {
            t,
            p: input.p,
            out,
            dissipation,
            omega: state.omega,
        });
    }
    summary.omega = state.omega;
    Ok((records, summary))
}

/// Write the records as `t,t_x,t_y,t_z,stick,dgamma,dissipation,omega,mu_eff`.
///
/// # Errors
/// I/O errors, naming the file.
pub fn write_csv(path: &Path, records: &[Record]) -> Result<(), String> {
    let io = |e: std::io::Error| format!("{}: {e}", path.display());
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(io)?;
    }
    let mut w = std::io::BufWriter::new(std::fs::File::create(path).map_err(io)?);
    writeln!(w, "t,t_x,t_y,t_z,stick,dgamma,dissipation,omega,mu_eff").map_err(io)?;
    for r in records {
        writeln!(
            w,
            "{:e},{:e},{:e},{:e},{},{:e},{:e},{:e},{:e}",
            r.t,
            r.out.t.x,
            r.out.t.y,
            r.out.t.z,
            u8::from(r.out.stick),
            r.out.dgamma,
            r.dissipation,
            r.omega,
            r.mu_eff()
        )
        .map_err(io)?;
    }
    w.flush().map_err(io)
}
