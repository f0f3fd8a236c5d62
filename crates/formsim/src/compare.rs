//! `formsim compare`: the thesis's law × formulation matrix on one scene, and
//! any other set of variants of it (mesh convergence, element choice, …).
//!
//! Each row runs as `formsim run` would, with its overrides, into
//! `DIR/LABEL/`; the runs share the machine's cores (rayon). A row is a
//! *case* (a name and its own `--set` overrides, for example
//! `bt-100:blank.mesh.divisions=100;solver.mass_scaling_dt=2.5e-7`) crossed
//! with a law and a formulation. Without cases the rows are `laws ×
//! formulations`; with cases and no `--laws`/`--formulations`, each case
//! keeps the scene's own law and formulation. The table (`DIR/compare.md`,
//! `DIR/compare.csv`) gives, per run, the extreme strains along each section,
//! the largest thinning and the frictional energy share, each also as % of the
//! reference run (the first row), and wall time and increments relative to
//! it. `DIR/plots/` overlays the strain curves.

use crate::plot::{Panel, Series, draw_panels};
use crate::run::{Progress, RunOptions, RunResult, run};
use crate::scene;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A named variant of the scene: its own `KEY=VALUE` overrides.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    /// Name: the row's label and output folder (letters, digits, `-`, `_`, `.`).
    pub name: String,
    /// Overrides, applied after the command's `--set` values.
    pub sets: Vec<String>,
}

impl Case {
    /// Parse `NAME` or `NAME:KEY=VALUE[;KEY=VALUE…]`.
    ///
    /// # Errors
    /// An empty name, a name with other characters than letters, digits,
    /// `-`, `_`, `.`, or an override without `=`.
    pub fn parse(text: &str) -> Result<Self, String> {
        let (name, rest) = text.split_once(':').unwrap_or((text, ""));
        let name = name.trim();
        if name.is_empty()
            || !name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'))
        {
            return Err(format!(
                "--case `{text}`: the name before `:` must be letters, digits, `-`, `_` or `.` \
                 (e.g. `bt-25:blank.mesh.divisions=25`)"
            ));
        }
        let mut sets = Vec::new();
        for part in rest.split(';').map(str::trim).filter(|p| !p.is_empty()) {
            if !part.contains('=') {
                return Err(format!(
                    "--case `{text}`: override `{part}` is not KEY=VALUE"
                ));
            }
            sets.push(part.to_string());
        }
        Ok(Self {
            name: name.to_string(),
            sets,
        })
    }
}

/// What to run: the cases, laws and formulations crossed, and overrides for every run.
#[derive(Debug, Clone, Default)]
pub struct Matrix {
    /// Cases (empty: one case, the scene as it is).
    pub cases: Vec<Case>,
    /// Laws (empty: the scene's own).
    pub laws: Vec<String>,
    /// Formulations (empty: the scene's own).
    pub formulations: Vec<String>,
    /// Overrides for every run, applied first.
    pub sets: Vec<String>,
}

/// One finished (or failed) run of the matrix.
#[derive(Debug)]
pub struct Entry {
    /// The row's label (also its folder under `DIR`).
    pub label: String,
    /// The case's name, if the matrix has cases.
    pub case: Option<String>,
    /// Law name.
    pub law: String,
    /// Formulation name.
    pub formulation: String,
    /// The result, or the error message.
    pub result: Result<RunResult, String>,
}

/// Run the rows of `matrix` on `scene_path` and write the table and plots to
/// `out`; with `progress`, one bar per row on the terminal.
///
/// # Errors
/// The scene does not load with some row's overrides; two cases share a
/// name; no run succeeds; the output cannot be written.
pub fn compare(
    scene_path: &Path,
    matrix: &Matrix,
    out: &Path,
    progress: bool,
    on_done: &(dyn Fn(&Entry) + Sync),
) -> Result<Vec<Entry>, String> {
    for (i, c) in matrix.cases.iter().enumerate() {
        if matrix.cases[..i].iter().any(|d| d.name == c.name) {
            return Err(format!("--case: the name `{}` is used twice", c.name));
        }
    }
    let cases: Vec<Option<&Case>> = if matrix.cases.is_empty() {
        vec![None]
    } else {
        matrix.cases.iter().map(Some).collect()
    };
    let laws: Vec<Option<&String>> = if matrix.laws.is_empty() {
        vec![None]
    } else {
        matrix.laws.iter().map(Some).collect()
    };
    let forms: Vec<Option<&String>> = if matrix.formulations.is_empty() {
        vec![None]
    } else {
        matrix.formulations.iter().map(Some).collect()
    };
    let label_combo = matrix.cases.is_empty() || laws.len() * forms.len() > 1;
    // Check the scene once per row, before running anything.
    let mut jobs = Vec::new();
    for case in &cases {
        for law in &laws {
            for f in &forms {
                let mut sets = matrix.sets.clone();
                if let Some(c) = case {
                    sets.extend(c.sets.iter().cloned());
                }
                if let Some(l) = law {
                    sets.push(format!("contact.law={l}"));
                }
                if let Some(f) = f {
                    sets.push(format!("contact.formulation={f}"));
                }
                let loaded = scene::load(scene_path, &sets).map_err(|e| match case {
                    Some(c) => format!("case {}: {e}", c.name),
                    None => e.to_string(),
                })?;
                let law = loaded.scene.contact.law.clone();
                let formulation = loaded.scene.contact.formulation.clone();
                let combo = format!("{law}-{formulation}");
                let label = match case {
                    Some(c) if label_combo => format!("{}-{combo}", c.name),
                    Some(c) => c.name.clone(),
                    None => combo,
                };
                let entry = (label, case.map(|c| c.name.clone()), law, formulation);
                jobs.push((entry, loaded));
            }
        }
    }
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let bars = progress_bars(progress, jobs.iter().map(|(row, _)| row.0.as_str()));
    let entries: Vec<Entry> = jobs
        .into_par_iter()
        .zip(bars)
        .map(|(((label, case, law, formulation), loaded), bar)| {
            let dir: PathBuf = out.join(&label);
            let result = run(
                &loaded,
                &RunOptions {
                    out: dir,
                    progress: bar.map_or(Progress::Hidden, Progress::Bar),
                },
            )
            .map_err(|e| e.to_string());
            let entry = Entry {
                label,
                case,
                law,
                formulation,
                result,
            };
            on_done(&entry);
            entry
        })
        .collect();
    if entries.iter().all(|e| e.result.is_err()) {
        return Err("every run failed (see the messages above)".into());
    }
    write_table(out, &entries)?;
    write_plots(out, &entries)?;
    Ok(entries)
}

/// One bar per row, labelled, in a `MultiProgress` (or none at all).
fn progress_bars<'a>(
    show: bool,
    labels: impl ExactSizeIterator<Item = &'a str>,
) -> Vec<Option<indicatif::ProgressBar>> {
    let style = indicatif::ProgressStyle::with_template(
        "{prefix:>24} {elapsed_precise} [{bar:30}] {percent:>3}% eta {eta}  {msg}",
    )
    .map(|s| s.progress_chars("=> "));
    let (true, Ok(style)) = (show, style) else {
        return labels.map(|_| None).collect();
    };
    let multi = indicatif::MultiProgress::new();
    labels
        .map(|label| {
            let bar = multi.add(indicatif::ProgressBar::new(1000));
            bar.set_style(style.clone());
            bar.set_prefix(label.to_string());
            Some(bar)
        })
        .collect()
}

/// A column of the table: name and value of a run.
type Column = (String, Box<dyn Fn(&RunResult) -> Option<f64>>);

fn columns(reference: &RunResult) -> Vec<Column> {
    let mut cols: Vec<Column> = Vec::new();
    for name in reference.summary.sections.keys() {
        let n = name.clone();
        cols.push((
            format!("{name} major max"),
            Box::new(move |r: &RunResult| r.summary.sections.get(&n).map(|s| s.major_max)),
        ));
        let n = name.clone();
        cols.push((
            format!("{name} minor min"),
            Box::new(move |r: &RunResult| r.summary.sections.get(&n).map(|s| s.minor_min)),
        ));
        if reference.summary.sections[name]
            .minor_at_punch_edge
            .is_some()
        {
            let n = name.clone();
            cols.push((
                format!("{name} minor at punch edge"),
                Box::new(move |r: &RunResult| {
                    r.summary
                        .sections
                        .get(&n)
                        .and_then(|s| s.minor_at_punch_edge)
                }),
            ));
        }
    }
    cols.push((
        "thinning max".into(),
        Box::new(|r: &RunResult| Some(r.summary.thinning_max)),
    ));
    cols.push((
        "friction share".into(),
        Box::new(|r: &RunResult| Some(r.summary.friction_energy_share)),
    ));
    cols.push((
        "punch force max (kN)".into(),
        Box::new(|r: &RunResult| Some(1e-3 * r.summary.punch_force_max)),
    ));
    cols.push((
        "kinetic/internal max".into(),
        Box::new(|r: &RunResult| Some(r.summary.kinetic_to_internal_max)),
    ));
    cols
}

fn write_table(out: &Path, entries: &[Entry]) -> Result<(), String> {
    let Some((ref_entry, reference)) = entries
        .iter()
        .find_map(|e| e.result.as_ref().ok().map(|r| (e, r)))
    else {
        return Ok(());
    };
    let ref_name = &ref_entry.label;
    let with_case = entries.iter().any(|e| e.case.is_some());
    let cols = columns(reference);
    let mut md = format!(
        "# {}: {}\n\nEach value, then in parentheses as % of {ref_name}. \
         Wall time and increments relative to {ref_name}.\n\n|",
        reference.summary.scene,
        if with_case {
            "cases"
        } else {
            "laws × formulations"
        }
    );
    let mut csv = String::new();
    if with_case {
        md.push_str(" case |");
        csv.push_str("case,");
    }
    md.push_str(" law | formulation |");
    csv.push_str("law,formulation");
    for (name, _) in &cols {
        let _ = write!(md, " {name} |");
        let key = name.replace(' ', "_").replace(['(', ')'], "");
        let _ = write!(csv, ",{key},{key}_pct");
    }
    md.push_str(" elements | wall time (s) | rel. | increments | rel. | balance error |\n|");
    csv.push_str(",elements,wall_time_s,wall_rel,increments,increments_rel,balance_error_rel\n");
    for _ in 0..cols.len() + 8 + usize::from(with_case) {
        md.push_str("---|");
    }
    md.push('\n');
    for e in entries {
        md.push('|');
        if with_case {
            let case = e.case.as_deref().unwrap_or("");
            let _ = write!(md, " {case} |");
            let _ = write!(csv, "{case},");
        }
        let _ = write!(md, " {} | {} |", e.law, e.formulation);
        let _ = write!(csv, "{},{}", e.law, e.formulation);
        match &e.result {
            Ok(r) => {
                for (_, f) in &cols {
                    match (f(r), f(reference)) {
                        (Some(v), Some(v0)) if v0 != 0.0 => {
                            let pct = 100.0 * v / v0;
                            let _ = write!(md, " {v:.4} ({pct:.0} %) |");
                            let _ = write!(csv, ",{v},{pct}");
                        }
                        // No percentage of a zero reference.
                        (Some(v), Some(_)) => {
                            let _ = write!(md, " {v:.4} (–) |");
                            let _ = write!(csv, ",{v},");
                        }
                        _ => {
                            md.push_str(" – |");
                            csv.push_str(",,");
                        }
                    }
                }
                let s = &r.summary;
                let wall_rel = s.wall_time_s / reference.summary.wall_time_s;
                let inc_rel = s.increments as f64 / reference.summary.increments as f64;
                let _ = writeln!(
                    md,
                    " {} | {:.1} | {:.2} | {} | {:.2} | {:.1e} |",
                    s.elements,
                    s.wall_time_s,
                    wall_rel,
                    s.increments,
                    inc_rel,
                    s.energy.balance_error_rel
                );
                let _ = writeln!(
                    csv,
                    ",{},{},{},{},{},{}",
                    s.elements,
                    s.wall_time_s,
                    wall_rel,
                    s.increments,
                    inc_rel,
                    s.energy.balance_error_rel
                );
            }
            Err(msg) => {
                let _ = writeln!(md, " failed: {} |", msg.replace('|', "/"));
                let _ = writeln!(csv, ",failed");
            }
        }
    }
    let write = |name: &str, text: &str| {
        let p = out.join(name);
        std::fs::write(&p, text).map_err(|e| format!("{}: {e}", p.display()))
    };
    write("compare.md", &md)?;
    write("compare.csv", &csv)
}

fn write_plots(out: &Path, entries: &[Entry]) -> Result<(), String> {
    let ok: Vec<(&Entry, &RunResult)> = entries
        .iter()
        .filter_map(|e| e.result.as_ref().ok().map(|r| (e, r)))
        .collect();
    let Some((_, first)) = ok.first() else {
        return Ok(());
    };
    let dir = out.join("plots");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for name in first.last.curves.keys() {
        let mut panels = Vec::new();
        for (which, pick) in [
            (
                "major",
                (|r: &crate::run::post::SectionRow| r.major) as fn(&_) -> f64,
            ),
            ("minor", |r: &crate::run::post::SectionRow| r.minor),
        ] {
            let series = ok
                .iter()
                .filter_map(|(e, r)| {
                    r.last.curves.get(name).map(|rows| Series {
                        label: e.label.clone(),
                        points: rows.iter().map(|row| (row.distance, pick(row))).collect(),
                    })
                })
                .collect();
            panels.push(Panel {
                title: format!("{which} strain along {name}"),
                x_label: "initial distance (mm)".into(),
                y_label: format!("{which} strain (-)"),
                series,
            });
        }
        draw_panels(&dir.join(format!("{name}.png")), &panels, 1000, 450)?;
    }
    Ok(())
}
