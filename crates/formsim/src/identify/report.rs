//! The report of an identification (`DIR/identification.json`,
//! `DIR/identification.md`, `DIR/objective.png`, `DIR/fit.png`) and of a
//! sensitivity table (`DIR/sensitivity.json`, `DIR/sensitivity.md`).

use super::evaluate::{Evaluation, Evaluator};
use super::measurements::{Measurements, Quantity};
use super::plots::{MarkPanel, draw};
use super::sensitivity::Table;
use super::uncertainty::Uncertainty;
use super::{IdentifyError, Options, SensitivityOptions};
use crate::plot::{Panel, Series, draw_panels};
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

/// A fitted value from start to end.
#[derive(Debug, Clone, Serialize)]
pub struct ParamReport {
    /// Scene key.
    pub key: String,
    /// Bounds.
    pub bounds: [f64; 2],
    /// Start value.
    pub start: f64,
    /// Identified value.
    pub end: f64,
    /// Change, % of the start (`None` at a zero start).
    pub change_percent: Option<f64>,
}

/// One evaluation on the optimiser's path.
#[derive(Debug, Clone, Serialize)]
pub struct PathStep {
    /// Journal number.
    pub index: usize,
    /// The values.
    pub values: Vec<f64>,
    /// The objective (`None`: a run failed).
    pub objective: Option<f64>,
    /// Read from the journal rather than run by this call.
    pub from_journal: bool,
    /// Wall seconds of its runs (when it was run).
    pub wall_s: f64,
}

/// A measured value and its simulation at start and end.
#[derive(Debug, Clone, Serialize)]
pub struct PredictionRow {
    /// Data set.
    pub set: String,
    /// Quantity.
    pub quantity: String,
    /// Line in the measurements file.
    pub line: usize,
    /// Measured value.
    pub measured: f64,
    /// Its standard error.
    pub se: Option<f64>,
    /// Simulated at the start.
    pub start: Option<f64>,
    /// Simulated at the end.
    pub end: Option<f64>,
}

/// `identification.json`.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// Scene file.
    pub scene: String,
    /// Overrides of every run (the command's).
    pub overrides: Vec<String>,
    /// Measurements file.
    pub measurements: String,
    /// Objective name.
    pub objective: String,
    /// Optimiser name.
    pub method: String,
    /// Why it stopped.
    pub stop: String,
    /// The fitted values.
    pub params: Vec<ParamReport>,
    /// The objective at the start.
    pub objective_start: Option<f64>,
    /// The objective at the end.
    pub objective_end: f64,
    /// Its change, % of the start.
    pub objective_change_percent: Option<f64>,
    /// Every evaluation asked for, in order (the Jacobian's last).
    pub path: Vec<PathStep>,
    /// Evaluations asked for (an optimiser may ask for a point twice).
    pub evaluations: usize,
    /// Distinct points evaluated.
    pub distinct: usize,
    /// Runs made by this call.
    pub runs_made: usize,
    /// Distinct points an earlier call had made (read from the journal).
    pub from_journal: usize,
    /// Wall seconds of this call.
    pub wall_s: f64,
    /// The uncertainty at the end.
    pub uncertainty: Option<Uncertainty>,
    /// Why there is no uncertainty.
    pub uncertainty_error: Option<String>,
    /// Every measured value against its simulation.
    pub predictions: Vec<PredictionRow>,
    /// `summary.json`'s `states` of each data set's run at the end: what the
    /// identified model predicts at every report stroke.
    pub end_states: BTreeMap<String, serde_json::Value>,
}

fn finite(v: f64) -> Option<f64> {
    v.is_finite().then_some(v)
}

fn percent(from: f64, to: f64) -> Option<f64> {
    (from != 0.0 && from.is_finite() && to.is_finite()).then(|| 100.0 * (to - from) / from.abs())
}

impl Report {
    /// Assemble the report.
    pub fn new(
        options: &Options,
        ev: &Evaluator<'_>,
        first: &Evaluation,
        end: &Evaluation,
        stop: String,
        uncertainty: Result<Uncertainty, IdentifyError>,
    ) -> Self {
        let log = ev.log();
        let data = ev.data();
        let mut predictions = Vec::new();
        for (s, set) in data.sets.iter().enumerate() {
            let at = |e: &Evaluation, i: usize| e.predictions[s].as_ref().ok().map(|p| p[i]);
            for (i, p) in set.points.iter().enumerate() {
                predictions.push(PredictionRow {
                    set: set.name.clone(),
                    quantity: p.label(),
                    line: p.line,
                    measured: p.value,
                    se: p.se,
                    start: at(first, i),
                    end: at(end, i),
                });
            }
        }
        let end_states = ev
            .entry(&end.values)
            .map(|entry| {
                entry
                    .sets
                    .into_iter()
                    .filter_map(|(name, obs)| {
                        Some((name, obs.ok()?.summary.get("states")?.clone()))
                    })
                    .collect()
            })
            .unwrap_or_default();
        let (uncertainty, uncertainty_error) = match uncertainty {
            Ok(u) => (Some(u), None),
            Err(e) => (None, Some(e.to_string())),
        };
        Self {
            scene: options.scene.display().to_string(),
            overrides: options.sets.clone(),
            measurements: data.path.display().to_string(),
            objective: options.objective.name().into(),
            method: options.method.name().into(),
            stop,
            params: options
                .params
                .iter()
                .enumerate()
                .map(|(j, p)| ParamReport {
                    key: p.key.clone(),
                    bounds: [p.lo, p.hi],
                    start: first.values[j],
                    end: end.values[j],
                    change_percent: percent(first.values[j], end.values[j]),
                })
                .collect(),
            objective_start: finite(first.cost),
            objective_end: end.cost,
            objective_change_percent: percent(first.cost, end.cost),
            path: log
                .iter()
                .map(|e| PathStep {
                    index: e.index,
                    values: e.values.clone(),
                    objective: finite(e.cost),
                    from_journal: e.from_journal,
                    wall_s: e.wall_s,
                })
                .collect(),
            evaluations: log.len(),
            distinct: ev.distinct().0,
            runs_made: ev.runs_made(),
            from_journal: ev.distinct().1,
            wall_s: ev.elapsed_s(),
            uncertainty,
            uncertainty_error,
            predictions,
            end_states,
        }
    }

    /// Write `identification.json`, `identification.md` and the plots to `out`.
    ///
    /// # Errors
    /// A file cannot be written.
    pub fn write(&self, out: &Path, data: &Measurements) -> Result<(), IdentifyError> {
        let json =
            serde_json::to_string_pretty(self).map_err(|e| IdentifyError::Report(e.to_string()))?;
        write(&out.join("identification.json"), &json)?;
        write(&out.join("identification.md"), &self.markdown())?;
        self.plot_objective(out)?;
        self.plot_fit(out, data)
    }

    /// The markdown report.
    pub fn markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "# Identification\n");
        let _ = writeln!(
            s,
            "Scene `{}`{}, measurements `{}`; objective `{}`, optimiser `{}` ({}).\n",
            self.scene,
            if self.overrides.is_empty() {
                String::new()
            } else {
                format!(" with `{}`", self.overrides.join("`, `"))
            },
            self.measurements,
            self.objective,
            self.method,
            self.stop
        );
        let _ = writeln!(
            s,
            "| value | bounds | start | end | change |\n|---|---|---:|---:|---:|"
        );
        for p in &self.params {
            let _ = writeln!(
                s,
                "| `{}` | {} .. {} | {} | {:.6} | {} |",
                p.key,
                p.bounds[0],
                p.bounds[1],
                p.start,
                p.end,
                p.change_percent
                    .map_or("—".into(), |c| format!("{c:+.1} %"))
            );
        }
        let _ = writeln!(
            s,
            "\nObjective: {} at the start, {:.6} at the end ({}). {} evaluations asked for, {} distinct points: {} runs made by this call, {} points from an earlier call's journal; {:.1} s.\n",
            self.objective_start
                .map_or("—".into(), |v| format!("{v:.6}")),
            self.objective_end,
            self.objective_change_percent
                .map_or("—".into(), |c| format!("{c:+.1} %")),
            self.evaluations,
            self.distinct,
            self.runs_made,
            self.from_journal,
            self.wall_s
        );
        self.markdown_uncertainty(&mut s);
        let _ = writeln!(
            s,
            "\n| set | quantity | measured | se | start | end |\n|---|---|---:|---:|---:|---:|"
        );
        let num = |v: Option<f64>| v.map_or("—".into(), |v| format!("{v:.4}"));
        for p in &self.predictions {
            let _ = writeln!(
                s,
                "| {} | {} | {:.4} | {} | {} | {} |",
                p.set,
                p.quantity,
                p.measured,
                num(p.se),
                num(p.start),
                num(p.end)
            );
        }
        let _ = writeln!(s, "\n![objective](objective.png)\n\n![fit](fit.png)");
        s
    }

    fn markdown_uncertainty(&self, s: &mut String) {
        let Some(u) = &self.uncertainty else {
            let _ = writeln!(
                s,
                "No uncertainty: {}.",
                self.uncertainty_error.as_deref().unwrap_or("unknown")
            );
            return;
        };
        let _ = writeln!(s, "Uncertainty ({}).\n", u.basis);
        if let Some(sd) = u.roughness_sd {
            let _ = writeln!(
                s,
                "Roughness: the sum of squared residuals varies by σ_f = {sd:.3e} over {} probe runs moved by {:.0e} of each range from the end; the covariance is multiplied by 1 + 2 σ_f / s² = {:.3}.\n",
                super::ROUGHNESS_PROBES,
                super::ROUGHNESS_STEP,
                u.inflation
            );
        }
        let _ = writeln!(
            s,
            "| value | end | σ | 95 % interval |\n|---|---:|---:|---|"
        );
        for (j, p) in self.params.iter().enumerate() {
            let _ = writeln!(
                s,
                "| `{}` | {:.6} | {} | {} |",
                p.key,
                p.end,
                u.sigma[j].map_or("unbounded".into(), |v| format!("{v:.3e}")),
                u.interval95[j].map_or("—".into(), |[a, b]| format!("{a:.6} .. {b:.6}"))
            );
        }
        if self.params.len() > 1 {
            let _ = writeln!(s, "\nCorrelations:\n");
            for (a, pa) in self.params.iter().enumerate() {
                for (b, pb) in self.params.iter().enumerate().skip(a + 1) {
                    let _ = writeln!(
                        s,
                        "- `{}` – `{}`: {}",
                        pa.key,
                        pb.key,
                        u.correlation[a][b].map_or("—".into(), |r| format!("{r:.3}"))
                    );
                }
            }
        }
        for w in &u.warnings {
            let _ = writeln!(s, "\n**Warning**: {w}.");
        }
    }

    fn plot_objective(&self, out: &Path) -> Result<(), IdentifyError> {
        let mut best = f64::INFINITY;
        let mut all = Vec::new();
        let mut running = Vec::new();
        for (i, p) in self.path.iter().enumerate() {
            if let Some(v) = p.objective {
                best = best.min(v);
                all.push((i as f64 + 1.0, v));
                running.push((i as f64 + 1.0, best));
            }
        }
        let panel = Panel {
            title: format!(
                "objective ({}) over the evaluations ({})",
                self.objective, self.method
            ),
            x_label: "evaluation".into(),
            y_label: "objective".into(),
            series: vec![
                Series {
                    label: "each evaluation".into(),
                    points: all,
                },
                Series {
                    label: "best so far".into(),
                    points: running,
                },
            ],
        };
        draw_panels(&out.join("objective.png"), &[panel], 900, 380)
            .map_err(|e| IdentifyError::Report(e.to_string()))
    }

    fn plot_fit(&self, out: &Path, data: &Measurements) -> Result<(), IdentifyError> {
        let mut panels: Vec<MarkPanel> = Vec::new();
        let mut k = 0;
        for set in &data.sets {
            let mut groups: Vec<(String, Vec<usize>)> = Vec::new();
            for (i, p) in set.points.iter().enumerate() {
                let group = if matches!(p.quantity, Quantity::Scalar { .. }) {
                    "scalars".to_string()
                } else {
                    p.group.clone()
                };
                match groups.iter_mut().find(|g| g.0 == group) {
                    Some(g) => g.1.push(k + i),
                    None => groups.push((group, vec![k + i])),
                }
            }
            for (group, rows) in groups {
                panels.push(self.fit_panel(&set.name, &group, &rows, data));
            }
            k += set.points.len();
        }
        draw(&out.join("fit.png"), &panels).map_err(|e| IdentifyError::Report(e.to_string()))
    }

    fn fit_panel(&self, set: &str, group: &str, rows: &[usize], data: &Measurements) -> MarkPanel {
        let points: Vec<_> = data.sets.iter().flat_map(|s| &s.points).collect();
        let x_of = |n: usize, row: usize| match &points[row].quantity {
            Quantity::Scalar { .. } => n as f64 + 1.0,
            Quantity::Curve { .. } => points[row].distance.unwrap_or(f64::NAN),
            Quantity::Force { stroke } => *stroke,
        };
        let line = |label: &str, pick: fn(&PredictionRow) -> Option<f64>| Series {
            label: label.into(),
            points: rows
                .iter()
                .enumerate()
                .filter_map(|(n, &r)| pick(&self.predictions[r]).map(|v| (x_of(n, r), v)))
                .collect(),
        };
        let (x_label, title) = if group == "scalars" {
            let names: Vec<&str> = rows
                .iter()
                .map(|&r| self.predictions[r].quantity.as_str())
                .collect();
            (
                "value number".to_string(),
                format!("{set}: {}", names.join(", ")),
            )
        } else if group == "punch force" {
            ("stroke (mm)".into(), format!("{set}: punch force (N)"))
        } else {
            (
                "initial distance along the section (mm)".into(),
                format!("{set}: {group}"),
            )
        };
        MarkPanel {
            title,
            x_label,
            y_label: "value".into(),
            measured: rows
                .iter()
                .enumerate()
                .map(|(n, &r)| {
                    (
                        x_of(n, r),
                        self.predictions[r].measured,
                        self.predictions[r].se,
                    )
                })
                .collect(),
            simulated: vec![
                line("simulated at the start", |p| p.start),
                line("simulated at the end", |p| p.end),
            ],
            lines: group != "scalars",
        }
    }
}

fn write(path: &Path, text: &str) -> Result<(), IdentifyError> {
    std::fs::write(path, text)
        .map_err(|e| IdentifyError::Report(format!("{}: {e}", path.display())))
}

/// Write `DIR/sensitivity.json` and `DIR/sensitivity.md`.
///
/// # Errors
/// A file cannot be written.
pub fn write_sensitivity(
    out: &Path,
    table: &Table,
    options: &SensitivityOptions,
) -> Result<(), IdentifyError> {
    let json =
        serde_json::to_string_pretty(table).map_err(|e| IdentifyError::Report(e.to_string()))?;
    write(&out.join("sensitivity.json"), &json)?;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Sensitivities\n\nScene `{}`{}; objective `{}`. Normalised forward differences `(Δq/q)/(Δx/x)` (% of q per % of x), with the step h = {} × |x| and h/2 (shown as `S(h) / S(h/2)`; `*` where they differ by more than {} %). {} runs.\n",
        options.scene.display(),
        if options.sets.is_empty() {
            String::new()
        } else {
            format!(" with `{}`", options.sets.join("`, `"))
        },
        options.objective.name(),
        table.relative_step,
        100.0 * super::sensitivity::AGREEMENT,
        table.runs
    );
    let _ = write!(s, "| set | quantity | value |");
    for (k, x) in table.keys.iter().zip(&table.at) {
        let _ = write!(s, " `{k}` = {x} |");
    }
    let _ = writeln!(s, "\n|---|---|---:|{}", "---:|".repeat(table.keys.len()));
    for row in &table.rows {
        let _ = write!(s, "| {} | {} | {:.4} |", row.set, row.quantity, row.value);
        for (pair, ok) in row.sensitivity.iter().zip(&row.agree) {
            let _ = write!(
                s,
                " {:.3} / {:.3}{} |",
                pair[0],
                pair[1],
                if *ok { "" } else { " *" }
            );
        }
        let _ = writeln!(s);
    }
    write(&out.join("sensitivity.md"), &s)
}
