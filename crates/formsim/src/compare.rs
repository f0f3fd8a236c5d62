//! `formsim compare`: the thesis's law × formulation matrix on one scene.
//!
//! Each combination runs as `formsim run` would, with `contact.law` and
//! `contact.formulation` overridden, into `DIR/LAW-FORMULATION/`; the runs
//! share the machine's cores (rayon). The table (`DIR/compare.md`,
//! `DIR/compare.csv`) gives, per run, the extreme strains along each section,
//! the largest thinning and the frictional energy share, each also as % of the
//! reference run (the first law with the first formulation), and wall time
//! and increments relative to it. `DIR/plots/` overlays the strain curves.

use crate::plot::{Panel, Series, draw_panels};
use crate::run::{RunOptions, RunResult, run};
use crate::scene;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One finished (or failed) run of the matrix.
#[derive(Debug)]
pub struct Entry {
    /// Law name.
    pub law: String,
    /// Formulation name.
    pub formulation: String,
    /// The result, or the error message.
    pub result: Result<RunResult, String>,
}

/// Run `laws × formulations` on `scene_path` and write the table and plots to `out`.
///
/// # Errors
/// The scene does not load; no run succeeds; the output cannot be written.
pub fn compare(
    scene_path: &Path,
    laws: &[String],
    formulations: &[String],
    overrides: &[String],
    out: &Path,
    on_done: &(dyn Fn(&Entry) + Sync),
) -> Result<Vec<Entry>, String> {
    // Check the scene once, with every combination, before running anything.
    let mut jobs = Vec::new();
    for law in laws {
        for f in formulations {
            let mut sets = overrides.to_vec();
            sets.push(format!("contact.law={law}"));
            sets.push(format!("contact.formulation={f}"));
            let loaded = scene::load(scene_path, &sets).map_err(|e| e.to_string())?;
            jobs.push((law.clone(), f.clone(), loaded));
        }
    }
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let entries: Vec<Entry> = jobs
        .into_par_iter()
        .map(|(law, formulation, loaded)| {
            let dir: PathBuf = out.join(format!("{law}-{formulation}"));
            let result = run(
                &loaded,
                &RunOptions {
                    out: dir,
                    progress: false,
                },
            )
            .map_err(|e| e.to_string());
            let entry = Entry {
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
    cols
}

fn write_table(out: &Path, entries: &[Entry]) -> Result<(), String> {
    let Some(reference) = entries.iter().find_map(|e| e.result.as_ref().ok()) else {
        return Ok(());
    };
    let ref_name = entries
        .iter()
        .find(|e| e.result.is_ok())
        .map(|e| format!("{}-{}", e.law, e.formulation))
        .unwrap_or_default();
    let cols = columns(reference);
    let mut md = format!(
        "# {}: laws × formulations\n\nEach value, then in parentheses as % of {ref_name}. \
         Wall time and increments relative to {ref_name}.\n\n| law | formulation |",
        reference.summary.scene
    );
    let mut csv = String::from("law,formulation");
    for (name, _) in &cols {
        let _ = write!(md, " {name} |");
        let key = name.replace(' ', "_").replace(['(', ')'], "");
        let _ = write!(csv, ",{key},{key}_pct");
    }
    md.push_str(" wall time (s) | rel. | increments | rel. | balance error |\n|---|---|");
    csv.push_str(",wall_time_s,wall_rel,increments,increments_rel,balance_error_rel\n");
    for _ in 0..cols.len() + 5 {
        md.push_str("---|");
    }
    md.push('\n');
    for e in entries {
        let _ = write!(md, "| {} | {} |", e.law, e.formulation);
        let _ = write!(csv, "{},{}", e.law, e.formulation);
        match &e.result {
            Ok(r) => {
                for (_, f) in &cols {
                    match (f(r), f(reference)) {
                        (Some(v), Some(v0)) => {
                            let pct = if v0 != 0.0 { 100.0 * v / v0 } else { f64::NAN };
                            let _ = write!(md, " {v:.4} ({pct:.0} %) |");
                            let _ = write!(csv, ",{v},{pct}");
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
                    " {:.1} | {:.2} | {} | {:.2} | {:.1e} |",
                    s.wall_time_s, wall_rel, s.increments, inc_rel, s.energy.balance_error_rel
                );
                let _ = writeln!(
                    csv,
                    ",{},{},{},{},{}",
                    s.wall_time_s, wall_rel, s.increments, inc_rel, s.energy.balance_error_rel
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
                        label: format!("{}-{}", e.law, e.formulation),
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
