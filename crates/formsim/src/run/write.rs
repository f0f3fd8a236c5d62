//! Writing a run's files: `summary.json`, `sections/*.csv`, `energy.csv`,
//! `punch_force.csv`, `tools.csv`, VTK frames and the `.pvd` series, PNG plots.

use super::post::{SectionRow, Snapshot};
use super::summary::stroke_key;
use super::{RunResult, Status};
use crate::formability::FormabilityState;
use crate::output::OutputError;
use crate::output::csv_text::CsvText;
use crate::output::vtk::{BlankFrame, FieldData, write_pvd, write_vtu};
use crate::plot::{Panel, Series, draw_panels};
use crate::scene::Model;
use std::path::Path;

fn write_text(path: &Path, text: &str) -> Result<(), OutputError> {
    std::fs::write(path, text).map_err(|source| OutputError::Io {
        path: path.to_path_buf(),
        source,
    })
}

fn finite(path: &Path, what: &str, v: f64) -> Result<f64, OutputError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(OutputError::Invalid {
            what: format!("{}: {what} is {v}", path.display()),
        })
    }
}

/// One VTK frame of the blank: current shape, displacement, contact pressure
/// and friction traction per node (largest over the pairs), and per element
/// thickness, thinning, major/minor/thickness strain, von Mises, plastic strain.
///
/// # Errors
/// Non-finite values, I/O.
pub fn frame(path: &Path, model: &Model, time: f64, stroke: f64) -> Result<(), OutputError> {
    let state = model.solver.state();
    let n = state.x.len();
    let x: Vec<[f64; 3]> = state.x.iter().map(|p| [p.x, p.y, p.z]).collect();
    let u: Vec<[f64; 3]> = state
        .x
        .iter()
        .zip(&state.x0)
        .map(|(a, b)| [a.x - b.x, a.y - b.y, a.z - b.z])
        .collect();
    let mut pressure = vec![0.0; n];
    let mut traction = vec![[0.0; 3]; n];
    if let Some(c) = model.contact() {
        for pair in c.pairs() {
            for (k, &node) in pair.nodes().iter().enumerate() {
                let node = node as usize;
                if pair.pressure[k] > pressure[node] {
                    pressure[node] = pair.pressure[k];
                    let t = pair.traction[k];
                    traction[node] = [t.x, t.y, t.z];
                }
            }
        }
    }
    let shells = model.shells();
    let ne = shells.len();
    let t0 = model.thickness0;
    let mut thickness = Vec::with_capacity(ne);
    let mut thinning = Vec::with_capacity(ne);
    let mut major = Vec::with_capacity(ne);
    let mut minor = Vec::with_capacity(ne);
    let mut eps3 = Vec::with_capacity(ne);
    let mut mises = Vec::with_capacity(ne);
    let mut peeq = Vec::with_capacity(ne);
    for e in 0..ne {
        let t = shells.thickness(e);
        let s = shells.membrane_strain(e, state);
        thickness.push(t);
        thinning.push((t0 - t) / t0);
        major.push(s.major);
        minor.push(s.minor);
        eps3.push((t / t0).ln());
        mises.push(shells.von_mises_max(e));
        peeq.push(shells.plastic_strain_max(e));
    }
    // In a springback step: the springback displacement since the tools
    // let go, less its best fit by the free rigid-body modes.
    let springback: Option<Vec<[f64; 3]>> = model.solver.springback().map(|r| {
        r.displacement(&state.x)
            .iter()
            .map(|d| [d.x, d.y, d.z])
            .collect()
    });
    let mut point_fields = vec![
        ("contact_pressure", FieldData::Scalar(&pressure)),
        ("friction_traction", FieldData::Vector(&traction)),
    ];
    if let Some(d) = &springback {
        point_fields.push(("springback_displacement", FieldData::Vector(d)));
    }
    let (mut zone, mut margin) = (Vec::new(), Vec::new());
    if let Some(f) = &model.formability {
        for p in f.evaluate(model).points {
            zone.push(f64::from(p.zone.code()));
            margin.push(p.margin);
        }
    }
    let mut cell_fields = vec![
        ("thickness", FieldData::Scalar(&thickness)),
        ("thinning", FieldData::Scalar(&thinning)),
        ("major_strain", FieldData::Scalar(&major)),
        ("minor_strain", FieldData::Scalar(&minor)),
        ("thickness_strain", FieldData::Scalar(&eps3)),
        ("von_mises_max", FieldData::Scalar(&mises)),
        ("plastic_strain_max", FieldData::Scalar(&peeq)),
    ];
    if model.formability.is_some() {
        cell_fields.push(("fld_zone", FieldData::Scalar(&zone)));
        cell_fields.push(("fld_margin", FieldData::Scalar(&margin)));
    }
    write_vtu(
        path,
        &BlankFrame {
            time,
            stroke,
            quads: &model.mesh.quads,
            x: &x,
            displacement: &u,
            point_fields: &point_fields,
            cell_fields: &cell_fields,
        },
    )
}

/// The ParaView collection of the frames.
///
/// # Errors
/// I/O.
pub fn pvd(path: &Path, frames: &[(f64, String)]) -> Result<(), OutputError> {
    write_pvd(path, frames)
}

fn section_csv(path: &Path, rows: &[SectionRow]) -> Result<(), OutputError> {
    let io = |e| OutputError::io(path, e);
    let mut csv = CsvText::new();
    csv.record(["distance", "major", "minor", "thickness_strain", "thinning"])
        .map_err(io)?;
    for r in rows {
        for (what, v) in [
            ("major", r.major),
            ("minor", r.minor),
            ("thickness_strain", r.thickness_strain),
        ] {
            finite(path, what, v)?;
        }
        csv.record(
            [r.distance, r.major, r.minor, r.thickness_strain, r.thinning].map(|v| v.to_string()),
        )
        .map_err(io)?;
    }
    csv.write_to(path).map_err(io)
}

/// Every file of the run, the small ones first so that they are the most
/// likely to land on a full disk: the histories (`energy.csv`,
/// `punch_force.csv`, `tools.csv`), the sections, `summary.json`, then the
/// frames' `blank.pvd` (when the run wrote `frames`) and the plots.
///
/// A run that did not complete writes what is finite: a section file with
/// a non-finite value is left out (listed in `summary.json`'s
/// `not_written`), a non-finite figure of `summary.json` too (listed in
/// `not_finite`), and a plot or `blank.pvd` that cannot be written is
/// skipped (logged).
///
/// # Errors
/// Non-finite values, I/O, plotting (of a completed run; of a stopped run,
/// I/O of the histories and `summary.json`).
pub fn all(
    out: &Path,
    result: &RunResult,
    model: &Model,
    plots: bool,
    frames: &[(f64, String)],
) -> Result<(), OutputError> {
    let stopped = result.summary.status != Status::Completed;

    // Histories.
    energy_csv(&out.join("energy.csv"), result)?;
    punch_force_csv(&out.join("punch_force.csv"), result)?;
    tools_csv(&out.join("tools.csv"), result, model)?;

    // Sections, at the end and at each report stroke.
    let mut not_written = Vec::new();
    let dir = out.join("sections");
    if !result.last.curves.is_empty() {
        std::fs::create_dir_all(&dir).map_err(|source| OutputError::Io {
            path: dir.clone(),
            source,
        })?;
        let mut each = |snap: &Snapshot, suffix: &str| -> Result<(), OutputError> {
            for (name, rows) in &snap.curves {
                match section_csv(&dir.join(format!("{name}{suffix}.csv")), rows) {
                    Err(OutputError::Invalid { what }) if stopped => {
                        // Named relative to the output directory.
                        let prefix = format!("{}/", out.display());
                        not_written.push(what.strip_prefix(&prefix).unwrap_or(&what).to_string());
                    }
                    other => other?,
                }
            }
            Ok(())
        };
        each(&result.last, "")?;
        for (r, snap) in &result.states {
            each(snap, &format!("_stroke{}", stroke_key(*r)))?;
        }
    }

    // The forming limit diagram at the end and at each report stroke.
    let fld_states = std::iter::once((String::new(), &result.last)).chain(
        result
            .states
            .iter()
            .map(|(r, snap)| (format!("_stroke{}", stroke_key(*r)), snap)),
    );
    for (suffix, snap) in fld_states {
        if let Some(fld) = &snap.formability {
            let name = format!("fld{suffix}.csv");
            match fld_csv(&out.join(&name), fld) {
                Err(OutputError::Invalid { .. }) if stopped => not_written.push(name),
                other => other?,
            }
        }
    }

    // summary.json
    let path = out.join("summary.json");
    let invalid = |e: serde_json::Error| OutputError::Invalid {
        what: format!("{}: {e}", path.display()),
    };
    let mut value = serde_json::to_value(&result.summary).map_err(invalid)?;
    if stopped {
        let mut not_finite = Vec::new();
        drop_nulls(&mut value, String::new(), &mut not_finite);
        if let serde_json::Value::Object(m) = &mut value {
            for (key, list) in [("not_finite", not_finite), ("not_written", not_written)] {
                if !list.is_empty() {
                    m.insert(key.into(), list.into());
                }
            }
        }
    } else if let Some(key) = first_null(&value, String::new()) {
        return Err(OutputError::Invalid {
            what: format!(
                "{}: `{key}` is not finite (NaN or infinity); the run is not trustworthy",
                path.display()
            ),
        });
    }
    let json = serde_json::to_string_pretty(&value).map_err(invalid)?;
    write_text(&path, &(json + "\n"))?;

    // The large files.
    let large = || -> Result<(), OutputError> {
        if !frames.is_empty() {
            pvd(&out.join("blank.pvd"), frames)?;
        }
        if plots {
            plots_png(out, result, model)?;
        }
        Ok(())
    };
    match large() {
        Err(e) if stopped => {
            tracing::info!("the stopped run's remaining files are not written: {e}");
            Ok(())
        }
        other => other,
    }
}

/// `fld.csv`: every element's point on the forming limit diagram.
fn fld_csv(path: &Path, fld: &FormabilityState) -> Result<(), OutputError> {
    let io = |e| OutputError::io(path, e);
    let mut csv = CsvText::new();
    csv.record(["element", "major", "minor", "zone", "margin"])
        .map_err(io)?;
    for (e, p) in fld.points.iter().enumerate() {
        for (what, v) in [("major", p.major), ("minor", p.minor), ("margin", p.margin)] {
            finite(path, &format!("element {e}'s {what}"), v)?;
        }
        csv.record([
            e.to_string(),
            p.major.to_string(),
            p.minor.to_string(),
            p.zone.name().to_string(),
            p.margin.to_string(),
        ])
        .map_err(io)?;
    }
    csv.write_to(path).map_err(io)
}

/// `at.k`, or `k` at the top.
fn dotted(at: &str, k: &str) -> String {
    if at.is_empty() {
        k.to_string()
    } else {
        format!("{at}.{k}")
    }
}

/// Remove the nulls (non-finite numbers serialised) of `v`, pushing the
/// dotted key of each to `keys`.
fn drop_nulls(v: &mut serde_json::Value, at: String, keys: &mut Vec<String>) {
    let join = |k: &str| dotted(&at, k);
    match v {
        serde_json::Value::Object(m) => {
            m.retain(|k, v| {
                if v.is_null() {
                    keys.push(join(k));
                    false
                } else {
                    true
                }
            });
            for (k, v) in m.iter_mut() {
                drop_nulls(v, join(k), keys);
            }
        }
        serde_json::Value::Array(a) => {
            for (k, v) in a.iter_mut().enumerate() {
                if v.is_null() {
                    keys.push(join(&k.to_string()));
                }
                drop_nulls(v, join(&k.to_string()), keys);
            }
            a.retain(|v| !v.is_null());
        }
        _ => {}
    }
}

/// The dotted key of the first null (a non-finite number serialised) in `v`.
fn first_null(v: &serde_json::Value, at: String) -> Option<String> {
    let join = |k: &str| dotted(&at, k);
    match v {
        serde_json::Value::Null => Some(at),
        serde_json::Value::Object(m) => m.iter().find_map(|(k, v)| first_null(v, join(k))),
        serde_json::Value::Array(a) => a
            .iter()
            .enumerate()
            .find_map(|(k, v)| first_null(v, join(&k.to_string()))),
        _ => None,
    }
}

/// `energy.csv`: time, stroke, time step and the energy ledger of each
/// history row.
fn energy_csv(path: &Path, result: &RunResult) -> Result<(), OutputError> {
    let io = |e| OutputError::io(path, e);
    let mut csv = CsvText::new();
    csv.record([
        "time",
        "stroke",
        "dt",
        "internal",
        "kinetic",
        "hourglass",
        "plastic",
        "contact",
        "friction",
        "bead",
        "external_work",
        "balance_error",
    ])
    .map_err(io)?;
    for h in &result.history {
        csv.record(h.energy_row().map(|v| v.to_string()))
            .map_err(io)?;
    }
    csv.write_to(path).map_err(io)
}

/// `punch_force.csv`: time, stroke and punch force of each history row.
fn punch_force_csv(path: &Path, result: &RunResult) -> Result<(), OutputError> {
    let io = |e| OutputError::io(path, e);
    let mut csv = CsvText::new();
    csv.record(["time", "stroke", "punch_force"]).map_err(io)?;
    for h in &result.history {
        csv.record([h.time, h.stroke, h.punch_force].map(|v| v.to_string()))
            .map_err(io)?;
    }
    csv.write_to(path).map_err(io)
}

/// `tools.csv`: time, stroke, and per tool the force on the blank along its
/// press axis and in total, the prescribed force (empty unless
/// force-controlled) and the position along the axis.
fn tools_csv(path: &Path, result: &RunResult, model: &Model) -> Result<(), OutputError> {
    let io = |e| OutputError::io(path, e);
    let mut csv = CsvText::new();
    let mut header = vec!["time".to_string(), "stroke".to_string()];
    for name in &model.tool_names {
        header.extend(
            ["force", "force_total", "prescribed", "position"].map(|what| format!("{name}_{what}")),
        );
    }
    csv.record(&header).map_err(io)?;
    for row in &result.tool_history {
        let mut fields = vec![row.time.to_string(), row.stroke.to_string()];
        for t in &row.tools {
            finite(path, "a tool force", t.force)?;
            fields.extend([
                t.force.to_string(),
                t.force_total.to_string(),
                t.prescribed.map_or(String::new(), |p| p.to_string()),
                t.position.to_string(),
            ]);
        }
        csv.record(&fields).map_err(io)?;
    }
    csv.write_to(path).map_err(io)
}

/// `plots/tools.png`: each tool's force on the blank along its press axis
/// (and the prescribed force of a force-controlled tool) against time.
fn tools_png(plots: &Path, result: &RunResult, model: &Model) -> Result<(), OutputError> {
    if model.tool_names.is_empty() || result.tool_history.is_empty() {
        return Ok(());
    }
    let h = &result.tool_history;
    let mut series = Vec::new();
    for (i, name) in model.tool_names.iter().enumerate() {
        series.push(Series {
            label: format!("{name}: delivered"),
            points: h
                .iter()
                .map(|r| (r.time * 1e3, 1e-3 * r.tools[i].force))
                .collect(),
        });
        let prescribed: Vec<(f64, f64)> = h
            .iter()
            .filter_map(|r| r.tools[i].prescribed.map(|p| (r.time * 1e3, 1e-3 * p)))
            .collect();
        if !prescribed.is_empty() {
            series.push(Series {
                label: format!("{name}: prescribed"),
                points: prescribed,
            });
        }
    }
    let path = plots.join("tools.png");
    draw_panels(
        &path,
        &[Panel {
            title: titled(
                "Force of each tool on the blank, along its press axis (model)",
                result,
            ),
            x_label: "time (ms)".into(),
            y_label: "force (kN)".into(),
            series,
        }],
        1000,
        500,
    )
    .map_err(plot_err(&path))
}

/// A plot title followed by the scene's name (`… — s-rail-reconstruction`),
/// so that every figure says which scene it shows.
fn titled(title: &str, result: &RunResult) -> String {
    format!("{title} — {}", result.summary.scene)
}

/// The force-against-stroke plot's title: the stroke tool's force (the
/// punch's in a double-action press, the die's in a single-action one).
fn punch_title(model: &Model) -> String {
    match model.stroke {
        Some(s) => format!(
            "Force of the stroke tool ({}) against its stroke (full-model equivalent)",
            model.tool_names[s.index]
        ),
        None => "Punch force (full-model equivalent)".into(),
    }
}

/// An [`OutputError::Plot`] for `path` around a [`crate::plot::PlotError`]:
/// the file named once (a drawing failure's own text already names it).
pub(crate) fn plot_err(path: &Path) -> impl Fn(crate::plot::PlotError) -> OutputError + '_ {
    move |e| OutputError::Plot {
        path: path.to_path_buf(),
        message: match e {
            crate::plot::PlotError::Draw { message, .. } => message,
            other => other.to_string(),
        },
    }
}

fn plots_png(out: &Path, result: &RunResult, model: &Model) -> Result<(), OutputError> {
    let plots = out.join("plots");
    std::fs::create_dir_all(&plots).map_err(|source| OutputError::Io {
        path: plots.clone(),
        source,
    })?;
    // Strains along each section: one panel per section, final state and report strokes.
    if !result.last.curves.is_empty() {
        let mut panels = Vec::new();
        for (name, rows) in &result.last.curves {
            let mut series = Vec::new();
            let mut add = |label: String, rows: &[SectionRow]| {
                series.push(Series {
                    label: format!("major {label}"),
                    points: rows.iter().map(|r| (r.distance, r.major)).collect(),
                });
                series.push(Series {
                    label: format!("minor {label}"),
                    points: rows.iter().map(|r| (r.distance, r.minor)).collect(),
                });
                series.push(Series {
                    label: format!("thickness {label}"),
                    points: rows
                        .iter()
                        .map(|r| (r.distance, r.thickness_strain))
                        .collect(),
                });
            };
            for (r, snap) in &result.states {
                if let Some(rows) = snap.curves.get(name)
                    && (r - result.last.stroke).abs() > 1e-3
                {
                    add(format!("@{} mm", stroke_key(*r)), rows);
                }
            }
            add(format!("@{:.1} mm", result.last.stroke), rows);
            panels.push(Panel {
                title: titled(&format!("Strains along {name}"), result),
                x_label: "initial distance from the section start (mm)".into(),
                y_label: "logarithmic strain (-)".into(),
                series,
            });
        }
        let path = plots.join("strains.png");
        draw_panels(&path, &panels, 1000, 420).map_err(plot_err(&path))?;
    }
    tools_png(&plots, result, model)?;
    // Energies against time.
    let h = &result.history;
    let series = |label: &str, f: &dyn Fn(&super::HistoryRow) -> f64| Series {
        label: label.into(),
        points: h.iter().map(|r| (r.time * 1e3, f(r))).collect(),
    };
    let path = plots.join("energies.png");
    draw_panels(
        &path,
        &[Panel {
            title: titled("Energies", result),
            x_label: "time (ms)".into(),
            y_label: "energy (mJ)".into(),
            series: vec![
                series("internal", &|r| r.energy.internal),
                series("plastic", &|r| r.energy.plastic),
                series("friction", &|r| r.energy.friction),
                series("kinetic", &|r| r.energy.kinetic),
                series("hourglass", &|r| r.energy.hourglass),
                series("contact", &|r| r.energy.contact),
                series("external work", &|r| r.energy.external),
            ],
        }],
        1000,
        500,
    )
    .map_err(plot_err(&path))?;
    if model.stroke.is_some() {
        let path = plots.join("punch_force.png");
        draw_panels(
            &path,
            &[Panel {
                title: titled(&punch_title(model), result),
                x_label: "stroke (mm)".into(),
                y_label: "force (kN)".into(),
                series: vec![Series {
                    label: "punch force".into(),
                    points: h.iter().map(|r| (r.stroke, 1e-3 * r.punch_force)).collect(),
                }],
            }],
            1000,
            500,
        )
        .map_err(plot_err(&path))?;
    }
    // Thinning map on the formed blank in plan view.
    let state = model.solver.state();
    let xy: Vec<[f64; 2]> = state.x.iter().map(|p| [p.x, p.y]).collect();
    let shells = model.shells();
    let t0 = model.thickness0;
    let thinning: Vec<f64> = (0..shells.len())
        .map(|e| 100.0 * (t0 - shells.thickness(e)) / t0)
        .collect();
    if let (Some(f), Some(fld)) = (&model.formability, &result.last.formability) {
        let path = plots.join("fld.png");
        crate::formability::plot::draw(
            &path,
            f,
            &fld.points,
            &titled(
                &format!(
                    "Forming limit diagram at stroke {:.1} mm",
                    result.last.stroke
                ),
                result,
            ),
        )
        .map_err(plot_err(&path))?;
        let margin: Vec<f64> = fld.points.iter().map(|p| p.margin).collect();
        crate::output::field_plots::element_map_png(
            &plots.join("fld_margin.png"),
            &titled(
                &format!(
                    "Margin to the forming limit at stroke {:.1} mm (plan view)",
                    result.last.stroke
                ),
                result,
            ),
            &format!("margin ({} major strain)", f.curve.measure().as_str()),
            &model.mesh.quads,
            &xy,
            &margin,
        )?;
    }
    crate::output::field_plots::element_map_png(
        &plots.join("thinning.png"),
        &titled(
            &format!(
                "Thinning at stroke {:.1} mm (plan view)",
                result.last.stroke
            ),
            result,
        ),
        "thinning (%)",
        &model.mesh.quads,
        &xy,
        &thinning,
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A section with a non-finite value is refused with the file and the
    /// quantity named, and no file is written (a stopped run then lists it
    /// in `summary.json` `not_written`).
    #[test]
    fn a_section_holding_a_nan_is_not_written() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("OD.csv");
        let row = |t: f64| crate::run::post::SectionRow {
            distance: 1.0,
            major: 0.1,
            minor: -0.1,
            thickness_strain: t,
            thinning: 0.0,
        };
        let e = section_csv(&path, &[row(0.0), row(f64::NAN)]).unwrap_err();
        assert!(matches!(e, OutputError::Invalid { .. }), "{e}");
        assert!(e.to_string().contains("thickness_strain"), "{e}");
        assert!(!path.exists());
        section_csv(&path, &[row(0.0)]).unwrap();
        assert!(path.exists());
    }

    /// A plot that cannot be drawn is reported with its file named once.
    #[test]
    fn a_failed_plot_names_its_file_once() {
        let path = Path::new("out/plots/energy.png");
        let e = plot_err(path)(crate::plot::PlotError::Draw {
            path: path.to_path_buf(),
            message: "disk full".into(),
        });
        assert_eq!(
            e.to_string(),
            "out/plots/energy.png: cannot draw plot: disk full"
        );
    }
}
