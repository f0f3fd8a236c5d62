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
//!
//! Before anything runs, [`plan`] loads, validates and builds the scene of
//! every row (with its overrides, law, formulation and parameters): a bad row
//! stops the comparison at once, named `case X, law Y, formulation Z: …`,
//! instead of surfacing after the valid rows have run.

use crate::batch::{self, BatchError, Engine, JobSpec};
use crate::output::csv_text::CsvText;
use crate::plot::{Panel, PlotError, Series, draw_panels};
use crate::run::post::{SectionRow, SectionSummary};
use crate::run::{Progress, RunResult};
use crate::scene::{self, SceneError};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// What can go wrong in a comparison.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    /// A `--case` name with characters other than letters, digits, `-`, `_`, `.`.
    #[error(
        "--case `{text}`: the name before `:` must be letters, digits, `-`, `_` or `.` (not only dots) \
         (e.g. `bt-25:blank.mesh.divisions=25`)"
    )]
    CaseName {
        /// The argument.
        text: String,
    },
    /// A `--case` override without `=`.
    #[error("--case `{text}`: override `{part}` is not KEY=VALUE")]
    CaseOverride {
        /// The argument.
        text: String,
        /// The override.
        part: String,
    },
    /// Two cases have the same name.
    #[error("--case: the name `{name}` is used twice")]
    DuplicateCase {
        /// The name.
        name: String,
    },
    /// Two rows would have the same label (and folder).
    #[error("the row `{label}` appears twice (a law or formulation is listed twice)")]
    DuplicateRow {
        /// The label.
        label: String,
    },
    /// A row's scene does not load, validate or build.
    #[error("{}{source}", row_prefix(row))]
    Row {
        /// The row, as `case X, law Y, formulation Z` (empty for a matrix of
        /// one unnamed row).
        row: String,
        /// The scene's error.
        source: SceneError,
    },
    /// Every run failed.
    #[error("every run failed (see the messages above)")]
    AllFailed,
    /// The output directory or a table cannot be written.
    #[error("{path}: {source}")]
    Io {
        /// The directory or file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// A plot cannot be drawn.
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// The batch engine failed (journal, executor).
    #[error(transparent)]
    Batch(#[from] BatchError),
}

/// `row: `, or nothing for a matrix of one unnamed row.
fn row_prefix(row: &str) -> String {
    if row.is_empty() {
        String::new()
    } else {
        format!("{row}: ")
    }
}

impl CompareError {
    fn io(path: &Path) -> impl FnOnce(std::io::Error) -> Self + '_ {
        |source| Self::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}

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
    pub fn parse(text: &str) -> Result<Self, CompareError> {
        let (name, rest) = text.split_once(':').unwrap_or((text, ""));
        let name = name.trim();
        if !crate::scene::validate::is_plain_name(name) {
            return Err(CompareError::CaseName { text: text.into() });
        }
        let mut sets = Vec::new();
        for part in rest.split(';').map(str::trim).filter(|p| !p.is_empty()) {
            if !part.contains('=') {
                return Err(CompareError::CaseOverride {
                    text: text.into(),
                    part: part.into(),
                });
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
    /// The row's figures, or why the run failed.
    pub result: Result<RowResult, String>,
    /// Whether the result was read from the journal of an earlier call.
    pub from_journal: bool,
}

/// What a comparison takes from a row's run (what its table and plots
/// show, and what its journal keeps).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RowResult {
    /// Scene name.
    pub scene: String,
    /// Law.
    pub law: String,
    /// Formulation.
    pub formulation: String,
    /// Shell elements.
    pub elements: usize,
    /// Increments.
    pub increments: u64,
    /// Wall seconds of the run (`summary.json`'s `wall_time_s`).
    pub wall_time_s: f64,
    /// Relative energy balance error.
    pub balance_error_rel: f64,
    /// Extremes of each section at the end.
    pub sections: BTreeMap<String, SectionSummary>,
    /// Largest thinning (-).
    pub thinning_max: f64,
    /// Frictional share of the external work (-).
    pub friction_energy_share: f64,
    /// Largest punch force (N).
    pub punch_force_max: f64,
    /// Largest kinetic energy over external work after forming starts (-).
    pub kinetic_to_work_max: f64,
    /// The run's warnings.
    pub warnings: Vec<String>,
    /// Each section's curve at the end.
    pub curves: BTreeMap<String, Vec<SectionRow>>,
}

impl RowResult {
    /// A row's figures from its run.
    pub fn of(r: &RunResult) -> Self {
        let s = &r.summary;
        Self {
            scene: s.scene.clone(),
            law: s.law.clone(),
            formulation: s.formulation.clone(),
            elements: s.elements,
            increments: s.increments,
            wall_time_s: s.wall_time_s,
            balance_error_rel: s.energy.balance_error_rel,
            sections: s.sections.clone(),
            thinning_max: s.thinning_max,
            friction_energy_share: s.friction_energy_share,
            punch_force_max: s.punch_force_max,
            kinetic_to_work_max: s.kinetic_to_work_max,
            warnings: s.warnings.clone(),
            curves: r.last.curves.clone(),
        }
    }
}

/// One row of a comparison, checked and ready to run.
#[derive(Debug)]
struct Row {
    /// The row's label (also its folder under the output directory).
    label: String,
    /// The case's name, if the matrix has cases.
    case: Option<String>,
    /// Law name.
    law: String,
    /// Formulation name.
    formulation: String,
    /// The row's overrides (after the command's).
    sets: Vec<String>,
    /// The scene with the row's overrides.
    loaded: scene::LoadedScene,
}

/// The rows of a comparison, each loaded, validated and built once, so that a
/// bad row stops the comparison before anything runs. Made by [`plan`], run by
/// [`execute`].
#[derive(Debug)]
pub struct Plan {
    rows: Vec<Row>,
}

impl Plan {
    /// The rows' labels, in order: the folders that [`execute`] writes under
    /// its output directory.
    pub fn labels(&self) -> impl ExactSizeIterator<Item = &str> {
        self.rows.iter().map(|r| r.label.as_str())
    }
}

/// The one-line name of a row in errors: `case X, law Y, formulation Z`
/// (the parts that are known).
fn row_name(case: Option<&Case>, law: Option<&str>, formulation: Option<&str>) -> String {
    let parts: Vec<String> = [
        case.map(|c| format!("case {}", c.name)),
        law.map(|l| format!("law {l}")),
        formulation.map(|f| format!("formulation {f}")),
    ]
    .into_iter()
    .flatten()
    .collect();
    parts.join(", ")
}

/// A [`CompareError::Row`] for the row `name`.
fn row_error(name: &str) -> impl FnOnce(SceneError) -> CompareError + '_ {
    |source| CompareError::Row {
        row: name.to_string(),
        source,
    }
}

/// Load, validate and build the scene of one row: its case's overrides after
/// `sets`, then its law and formulation.
fn check_row(
    scene_path: &Path,
    sets: &[String],
    case: Option<&Case>,
    law: Option<&String>,
    formulation: Option<&String>,
) -> Result<(scene::LoadedScene, Vec<String>), CompareError> {
    let mut sets = sets.to_vec();
    if let Some(c) = case {
        sets.extend(c.sets.iter().cloned());
    }
    if let Some(l) = law {
        sets.push(format!("contact.law={l}"));
    }
    if let Some(f) = formulation {
        sets.push(format!("contact.formulation={f}"));
    }
    let asked = row_name(
        case,
        law.map(String::as_str),
        formulation.map(String::as_str),
    );
    let loaded = scene::load(scene_path, &sets).map_err(row_error(&asked))?;
    let c = &loaded.scene.contact;
    let name = row_name(case, Some(&c.law), Some(&c.formulation));
    // The whole model (mesh, material, tools, each contact pair's law with its
    // parameters): an unknown law or a bad parameter is found here, not after
    // the rows before it have run. The model is dropped; the run builds its own.
    scene::build(&loaded).map_err(row_error(&name))?;
    Ok((loaded, sets))
}

/// Check every row of `matrix` on `scene_path` (cases × laws × formulations,
/// each with its overrides) without running any.
///
/// # Errors
/// Two cases share a name; two rows share a label; a row's scene does not
/// load, validate or build (unknown law or formulation, bad parameter, bad
/// override): the first such row, named `case X, law Y, formulation Z: …`.
pub fn plan(scene_path: &Path, matrix: &Matrix) -> Result<Plan, CompareError> {
    for (i, c) in matrix.cases.iter().enumerate() {
        if matrix.cases[..i].iter().any(|d| d.name == c.name) {
            return Err(CompareError::DuplicateCase {
                name: c.name.clone(),
            });
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
    let mut rows: Vec<Row> = Vec::new();
    for case in &cases {
        for law in &laws {
            for f in &forms {
                let (loaded, sets) = check_row(scene_path, &matrix.sets, *case, *law, *f)?;
                let law = loaded.scene.contact.law.clone();
                let formulation = loaded.scene.contact.formulation.clone();
                let combo = format!("{law}-{formulation}");
                let label = match case {
                    Some(c) if label_combo => format!("{}-{combo}", c.name),
                    Some(c) => c.name.clone(),
                    None => combo,
                };
                if rows.iter().any(|r| r.label == label) {
                    return Err(CompareError::DuplicateRow { label });
                }
                rows.push(Row {
                    label,
                    case: case.map(|c| c.name.clone()),
                    law,
                    formulation,
                    sets,
                    loaded,
                });
            }
        }
    }
    Ok(Plan { rows })
}

/// Run the rows of `plan` on `engine` (rows its journal holds finished are
/// read back) and write the table and plots to `out`; with `progress`, one
/// bar per row on the terminal. `on_done` is told of each row as it ends.
///
/// # Errors
/// No run succeeds; the engine fails; the output cannot be written.
pub fn execute(
    plan: Plan,
    out: &Path,
    progress: bool,
    engine: &Engine<'_>,
    on_done: &mut dyn FnMut(&Entry),
) -> Result<Vec<Entry>, CompareError> {
    std::fs::create_dir_all(out).map_err(CompareError::io(out))?;
    let bars = progress_bars(progress, plan.labels());
    let jobs: Vec<JobSpec> = plan
        .rows
        .iter()
        .map(|row| JobSpec {
            label: row.label.clone(),
            sets: row.sets.clone(),
            out: out.join(&row.label),
            estimate: batch::estimate_s(&row.loaded),
        })
        .collect();
    let extract = |r: &RunResult| serde_json::to_value(RowResult::of(r)).map_err(|e| e.to_string());
    let work = |i: usize, spec: &JobSpec| {
        let progress = bars[i].clone().map_or(Progress::Hidden, Progress::Bar);
        let scene = batch::Scene::Planned(&plan.rows[i].loaded);
        batch::run_job(scene, spec, progress, engine.clock(), &extract)
    };
    let entry = |i: usize, record: &batch::Record, from_journal: bool| {
        let row = &plan.rows[i];
        Entry {
            label: row.label.clone(),
            case: row.case.clone(),
            law: row.law.clone(),
            formulation: row.formulation.clone(),
            result: record
                .outcome
                .clone()
                .and_then(|v| serde_json::from_value::<RowResult>(v).map_err(|e| e.to_string())),
            from_journal,
        }
    };
    let mut from_journal = vec![false; jobs.len()];
    let records = engine.run(&jobs, &work, &mut |i, record, journalled| {
        from_journal[i] = journalled;
        if journalled && let Some(b) = &bars[i] {
            b.finish_with_message("from the journal");
        }
        on_done(&entry(i, record, journalled));
    })?;
    let entries: Vec<Entry> = records
        .iter()
        .enumerate()
        .map(|(i, r)| entry(i, r, from_journal[i]))
        .collect();
    if entries.iter().all(|e| e.result.is_err()) {
        return Err(CompareError::AllFailed);
    }
    write_table(out, &entries)?;
    write_plots(out, &entries)?;
    Ok(entries)
}

/// [`plan`] then [`execute`] on the local executor without a journal:
/// check every row of `matrix` on `scene_path`, then run them (all at once,
/// one thread each, up to the machine's threads) and write the table and
/// plots to `out`.
///
/// # Errors
/// As [`plan`] (nothing has run then) and [`execute`].
pub fn compare(
    scene_path: &Path,
    matrix: &Matrix,
    out: &Path,
    progress: bool,
    on_done: &mut dyn FnMut(&Entry),
) -> Result<Vec<Entry>, CompareError> {
    let plan = plan(scene_path, matrix)?;
    let cores = rayon::current_num_threads();
    let local = batch::local::Local::sized(None, None, cores, plan.rows.len());
    execute(plan, out, progress, &Engine::new(&local, None), on_done)
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
type Column = (String, Box<dyn Fn(&RowResult) -> Option<f64>>);

fn columns(reference: &RowResult) -> Vec<Column> {
    let mut cols: Vec<Column> = Vec::new();
    for name in reference.sections.keys() {
        let n = name.clone();
        cols.push((
            format!("{name} major max"),
            Box::new(move |r: &RowResult| r.sections.get(&n).map(|s| s.major_max)),
        ));
        let n = name.clone();
        cols.push((
            format!("{name} minor min"),
            Box::new(move |r: &RowResult| r.sections.get(&n).map(|s| s.minor_min)),
        ));
        if reference.sections[name].minor_at_punch_edge.is_some() {
            let n = name.clone();
            cols.push((
                format!("{name} minor at punch edge"),
                Box::new(move |r: &RowResult| {
                    r.sections.get(&n).and_then(|s| s.minor_at_punch_edge)
                }),
            ));
        }
    }
    cols.push((
        "thinning max".into(),
        Box::new(|r: &RowResult| Some(r.thinning_max)),
    ));
    cols.push((
        "friction share".into(),
        Box::new(|r: &RowResult| Some(r.friction_energy_share)),
    ));
    cols.push((
        "punch force max (kN)".into(),
        Box::new(|r: &RowResult| Some(1e-3 * r.punch_force_max)),
    ));
    cols.push((
        "kinetic/work max".into(),
        Box::new(|r: &RowResult| Some(r.kinetic_to_work_max)),
    ));
    cols
}

fn write_table(out: &Path, entries: &[Entry]) -> Result<(), CompareError> {
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
        reference.scene,
        if with_case {
            "cases"
        } else {
            "laws × formulations"
        }
    );
    if with_case {
        md.push_str(" case |");
    }
    md.push_str(" law | formulation |");
    for (name, _) in &cols {
        let _ = write!(md, " {name} |");
    }
    md.push_str(" elements | wall time (s) | rel. | increments | rel. | balance error |\n|");
    for _ in 0..cols.len() + 8 + usize::from(with_case) {
        md.push_str("---|");
    }
    md.push('\n');
    for e in entries {
        md.push('|');
        if with_case {
            let _ = write!(md, " {} |", e.case.as_deref().unwrap_or(""));
        }
        let _ = write!(md, " {} | {} |", e.law, e.formulation);
        match &e.result {
            Ok(r) => {
                for (_, f) in &cols {
                    match (f(r), f(reference)) {
                        (Some(v), Some(v0)) if v0 != 0.0 => {
                            let pct = 100.0 * v / v0;
                            let _ = write!(md, " {v:.4} ({pct:.0} %) |");
                        }
                        // No percentage of a zero reference.
                        (Some(v), Some(_)) => {
                            let _ = write!(md, " {v:.4} (–) |");
                        }
                        _ => md.push_str(" – |"),
                    }
                }
                let s = r;
                let _ = writeln!(
                    md,
                    " {} | {:.1} | {:.2} | {} | {:.2} | {:.1e} |",
                    s.elements,
                    s.wall_time_s,
                    s.wall_time_s / reference.wall_time_s,
                    s.increments,
                    s.increments as f64 / reference.increments as f64,
                    s.balance_error_rel
                );
            }
            Err(msg) => {
                let _ = writeln!(md, " failed: {} |", msg.replace('|', "/"));
            }
        }
    }
    write_warnings(&mut md, entries);
    let p = out.join("compare.md");
    std::fs::write(&p, md).map_err(CompareError::io(&p))?;
    let p = out.join("compare.csv");
    compare_csv(entries, reference, &cols, with_case)
        .and_then(|csv| csv.write_to(&p))
        .map_err(CompareError::io(&p))
}

/// Every run's warnings (`summary.json`'s `warnings`) under the table.
fn write_warnings(md: &mut String, entries: &[Entry]) {
    let mut lines = Vec::new();
    for e in entries {
        if let Ok(r) = &e.result {
            lines.extend(r.warnings.iter().map(|w| format!("- `{}`: {w}", e.label)));
        }
    }
    if !lines.is_empty() {
        md.push_str("\n## Warnings\n\n");
        for l in lines {
            md.push_str(&l);
            md.push('\n');
        }
    }
}

/// `compare.csv`: the table of `compare.md` with full-precision numbers, a
/// column of each value and one of its % of the reference (empty for a
/// reference of zero); a failed run's row ends with `failed`.
fn compare_csv(
    entries: &[Entry],
    reference: &RowResult,
    cols: &[Column],
    with_case: bool,
) -> std::io::Result<CsvText> {
    let mut csv = CsvText::flexible();
    let mut header: Vec<String> = Vec::new();
    if with_case {
        header.push("case".into());
    }
    header.extend(["law".into(), "formulation".into()]);
    for (name, _) in cols {
        let key = name.replace(' ', "_").replace(['(', ')'], "");
        header.extend([key.clone(), format!("{key}_pct")]);
    }
    header.extend(
        [
            "elements",
            "wall_time_s",
            "wall_rel",
            "increments",
            "increments_rel",
            "balance_error_rel",
        ]
        .map(String::from),
    );
    csv.record(&header)?;
    for e in entries {
        let mut row: Vec<String> = Vec::new();
        if with_case {
            row.push(e.case.clone().unwrap_or_default());
        }
        row.extend([e.law.clone(), e.formulation.clone()]);
        let Ok(r) = &e.result else {
            row.push("failed".into());
            csv.record(&row)?;
            continue;
        };
        for (_, f) in cols {
            let (v, pct) = match (f(r), f(reference)) {
                (Some(v), Some(v0)) if v0 != 0.0 => (v.to_string(), (100.0 * v / v0).to_string()),
                // No percentage of a zero reference.
                (Some(v), Some(_)) => (v.to_string(), String::new()),
                _ => (String::new(), String::new()),
            };
            row.extend([v, pct]);
        }
        let s = r;
        row.extend([
            s.elements.to_string(),
            s.wall_time_s.to_string(),
            (s.wall_time_s / reference.wall_time_s).to_string(),
            s.increments.to_string(),
            (s.increments as f64 / reference.increments as f64).to_string(),
            s.balance_error_rel.to_string(),
        ]);
        csv.record(&row)?;
    }
    Ok(csv)
}

fn write_plots(out: &Path, entries: &[Entry]) -> Result<(), CompareError> {
    let ok: Vec<(&Entry, &RowResult)> = entries
        .iter()
        .filter_map(|e| e.result.as_ref().ok().map(|r| (e, r)))
        .collect();
    let Some((_, first)) = ok.first() else {
        return Ok(());
    };
    let dir = out.join("plots");
    std::fs::create_dir_all(&dir).map_err(CompareError::io(&dir))?;
    for name in first.curves.keys() {
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
                    r.curves.get(name).map(|rows| Series {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A failed run's row of `compare.csv` is its case, law and formulation
    /// then `failed`, shorter than the header; the other rows are full.
    #[test]
    fn compare_csv_ends_a_failed_row_with_failed() {
        let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/block-on-plane.toml");
        let dir = tempfile::tempdir().unwrap();
        let matrix = Matrix {
            cases: vec![Case::parse("d2:blank.mesh.divisions=2").unwrap()],
            formulations: vec!["convective".into(), "jaumann".into()],
            ..Default::default()
        };
        let mut entries = compare(
            &scene,
            &matrix,
            &dir.path().join("runs"),
            false,
            &mut |_| {},
        )
        .unwrap();
        entries[1].result = Err("diverged".into());
        write_table(dir.path(), &entries).unwrap();
        let csv = std::fs::read_to_string(dir.path().join("compare.csv")).unwrap();
        let rows: Vec<&str> = csv.lines().collect();
        assert_eq!(rows.len(), 3, "{csv}");
        let width = rows[0].split(',').count();
        assert!(
            rows[0].starts_with("case,law,formulation,") && width > 8,
            "{csv}"
        );
        assert!(rows[1].starts_with("d2,ac,convective,"), "{csv}");
        assert_eq!(rows[1].split(',').count(), width, "{csv}");
        assert_eq!(rows[2], "d2,ac,jaumann,failed");
    }
}
