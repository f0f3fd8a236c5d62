//! Integrating one contact point along a prescribed history (`formsim friction-point`).

use std::path::{Path, PathBuf};

use plugins_api::{FrictionError, PointIntegrator, PointState, StepOutput};

use crate::history::History;
use crate::output::csv_text::CsvText;

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

/// Why a history cannot be integrated or its records written.
#[derive(Debug, thiserror::Error)]
pub enum PointError {
    /// A step of the history failed.
    #[error("{file}:{line}: {source}")]
    Step {
        /// The history file, as given.
        file: String,
        /// 1-based line of the step.
        line: usize,
        /// The integrator's error.
        source: Box<FrictionError>,
    },
    /// A step gave a non-finite traction, slip or work.
    #[error("{file}:{line}: {law} produced a non-finite result")]
    NonFinite {
        /// The history file, as given.
        file: String,
        /// 1-based line of the step.
        line: usize,
        /// The law's name.
        law: String,
    },
    /// The CSV file cannot be written.
    #[error("{path}: {source}")]
    Io {
        /// The file (or its directory).
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
}

/// Integrate the history with `integrator`, from a virgin point.
///
/// # Errors
/// The first step that fails, with the history file's line number.
pub fn run(
    integrator: &dyn PointIntegrator,
    history: &History,
    file: &str,
) -> Result<(Vec<Record>, RunSummary), PointError> {
    let mut state = PointState::default();
    let mut records = Vec::with_capacity(history.steps.len());
    let mut summary = RunSummary::default();
    let mut dissipation = 0.0;
    for ((input, &t), &line) in history.steps.iter().zip(&history.times).zip(&history.lines) {
        let out = integrator
            .step(&mut state, input)
            .map_err(|source| PointError::Step {
                file: file.to_string(),
                line,
                source: Box::new(source),
            })?;
        let finite = out
            .t
            .iter()
            .chain([out.dgamma, out.dissipation, state.omega].iter())
            .all(|v| v.is_finite());
        if !finite {
            return Err(PointError::NonFinite {
                file: file.to_string(),
                line,
                law: integrator.law_name().to_string(),
            });
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

/// Write the records as `t,t_x,t_y,t_z,stick,dgamma,dissipation,omega,mu_eff`
/// (numbers as `{:e}`, `stick` as 0 or 1).
///
/// # Errors
/// I/O errors, naming the file.
pub fn write_csv(path: &Path, records: &[Record]) -> Result<(), PointError> {
    let io = |source: std::io::Error| PointError::Io {
        path: path.to_path_buf(),
        source,
    };
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(io)?;
    }
    let mut csv = CsvText::new();
    csv.record([
        "t",
        "t_x",
        "t_y",
        "t_z",
        "stick",
        "dgamma",
        "dissipation",
        "omega",
        "mu_eff",
    ])
    .map_err(io)?;
    let e = |v: f64| format!("{v:e}");
    for r in records {
        csv.record([
            e(r.t),
            e(r.out.t.x),
            e(r.out.t.y),
            e(r.out.t.z),
            u8::from(r.out.stick).to_string(),
            e(r.out.dgamma),
            e(r.dissipation),
            e(r.omega),
            e(r.mu_eff()),
        ])
        .map_err(io)?;
    }
    csv.write_to(path).map_err(io)
}
