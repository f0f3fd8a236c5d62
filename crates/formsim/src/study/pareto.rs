//! `pareto.png`: each variant's largest error against its CPU time, log
//! axes, one marker and colour per knob, the Pareto front (no other variant
//! both cheaper and more accurate) drawn through its points, the tolerance
//! as a horizontal line and the reference's time as a vertical one. With a
//! converged answer the reference has an error too and stands on the
//! chart, with the refinement sequence's levels. Models (`--model`) are not
//! drawn: their differences are not errors.

use super::{Outcome, Results};
use crate::plot::{PlotError, ensure_font};
use plotters::prelude::*;
use std::path::Path;

/// Errors below this are drawn at it (a log axis has no zero).
const ERROR_FLOOR: f64 = 1e-6;

/// The variants on the chart (not the reference, unless the study has a
/// converged answer) on the Pareto front of (CPU time, worst error),
/// cheapest first: each is more accurate than every cheaper one.
pub fn front(r: &Results) -> Vec<&Outcome> {
    let mut sorted: Vec<&Outcome> = r
        .outcomes
        .iter()
        .filter(|o| group(r, o).is_some())
        .collect();
    sorted.sort_by(|a, b| {
        a.cost_s
            .total_cmp(&b.cost_s)
            .then(a.worst.total_cmp(&b.worst))
    });
    let mut best = f64::INFINITY;
    sorted
        .into_iter()
        .filter(|o| {
            let keep = o.worst < best;
            best = best.min(o.worst);
            keep
        })
        .collect()
}

/// Which marker group a variant belongs to: its changed knob's index; the
/// number of knobs `n` for a combination, `n + 1` for a level of the
/// refinement sequence, `n + 2` for the reference when the study has a
/// converged answer (`None` without one).
fn group(r: &Results, o: &Outcome) -> Option<usize> {
    let n = r.spec.knobs.len();
    if o.level.is_some() {
        return Some(n + 1);
    }
    match o.changed.as_slice() {
        [] => r.converged.as_ref().map(|_| n + 2),
        [key] => r.spec.knobs.iter().position(|k| k.key == *key && !k.model),
        _ => Some(r.spec.knobs.len()),
    }
}

/// Draw `pareto.png` into `out`.
///
/// # Errors
/// No font, or the image cannot be written; the message names the file.
pub fn draw(out: &Path, r: &Results) -> Result<(), PlotError> {
    ensure_font()?;
    let path = out.join("pareto.png");
    let fail = PlotError::drawing(&path);
    let y = |o: &Outcome| o.worst.max(ERROR_FLOOR);
    let xs = r.outcomes.iter().map(|o| o.cost_s);
    let (x0, x1) = xs.fold((f64::INFINITY, 0.0_f64), |(a, b), x| (a.min(x), b.max(x)));
    let (y0, y1) = r
        .outcomes
        .iter()
        .filter(|o| group(r, o).is_some())
        .map(y)
        .chain([r.spec.tolerance])
        .fold((f64::INFINITY, 0.0_f64), |(a, b), v| (a.min(v), b.max(v)));
    let root = BitMapBackend::new(&path, (1000, 650)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| fail(&e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("{}: largest error against time", r.scene),
            ("sans-serif", 22),
        )
        .margin(14)
        .x_label_area_size(45)
        .y_label_area_size(80)
        // Room on the right (a factor 4 of time) for the legend.
        .build_cartesian_2d(
            (x0 / 1.3..x1 * 4.0).log_scale(),
            (y0 / 2.0..y1 * 2.0).log_scale(),
        )
        .map_err(|e| fail(&e))?;
    chart
        .configure_mesh()
        .x_desc("CPU time per run at the reference's pace (s)")
        .y_desc("largest relative error over the quantities")
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .x_label_formatter(&|v| {
            if *v >= 10.0 {
                format!("{v:.0}")
            } else {
                format!("{v:.1}")
            }
        })
        .label_style(("sans-serif", 15))
        .draw()
        .map_err(|e| fail(&e))?;
    let tol = r.spec.tolerance;
    chart
        .draw_series(LineSeries::new(
            [(x0 / 1.3, tol), (x1 * 4.0, tol)],
            RED.mix(0.6).stroke_width(1),
        ))
        .map_err(|e| fail(&e))?
        .label(format!("tolerance {}", super::report::percent(tol)))
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], RED.mix(0.6)));
    let t_ref = r.outcomes[0].cpu_s.median;
    chart
        .draw_series(LineSeries::new(
            [(t_ref, y0 / 2.0), (t_ref, y1 * 2.0)],
            BLACK.mix(0.4).stroke_width(1),
        ))
        .map_err(|e| fail(&e))?
        .label("reference's time")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK.mix(0.4)));
    let f: Vec<(f64, f64)> = front(r).into_iter().map(|o| (o.cost_s, y(o))).collect();
    chart
        .draw_series(LineSeries::new(f, BLACK.stroke_width(2)))
        .map_err(|e| fail(&e))?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK.stroke_width(2)));
    let names: Vec<String> = r
        .spec
        .knobs
        .iter()
        .map(|k| k.key.clone())
        .chain(["combined", "refinement levels", "reference"].map(String::from))
        .collect();
    for (g, name) in names.iter().enumerate() {
        let points: Vec<(f64, f64, String)> = r
            .outcomes
            .iter()
            .filter(|o| group(r, o) == Some(g))
            .map(|o| (o.cost_s, y(o), short_value(r, o)))
            .collect();
        if points.is_empty() {
            continue;
        }
        let color = Palette99::pick(g).to_rgba();
        chart
            .draw_series(points.iter().map(|(x, v, text)| {
                EmptyElement::at((*x, *v))
                    + marker(g, color)
                    + Text::new(text.clone(), (7, -16), ("sans-serif", 13))
            }))
            .map_err(|e| fail(&e))?
            .label(name.as_str())
            .legend(move |(x, y)| EmptyElement::at((x + 9, y)) + marker(g, color));
    }
    crate::plot::legend(&mut chart, SeriesLabelPosition::UpperRight, 14).map_err(|e| fail(&e))?;
    root.present().map_err(|e| fail(&e))
}

/// A marker shape per knob: circle, triangle, square, cross, in turn.
fn marker<DB: DrawingBackend>(g: usize, color: RGBAColor) -> DynElement<'static, DB, (i32, i32)> {
    let style = color.filled();
    match g % 4 {
        0 => Circle::new((0, 0), 6, style).into_dyn(),
        1 => TriangleMarker::new((0, 0), 7, style).into_dyn(),
        2 => Rectangle::new([(-5, -5), (5, 5)], style).into_dyn(),
        _ => Cross::new((0, 0), 6, color.stroke_width(3)).into_dyn(),
    }
}

/// The value a variant gives its knob (its label for a combination).
fn short_value(r: &Results, o: &Outcome) -> String {
    match group(r, o) {
        Some(g) if g < r.spec.knobs.len() => o.settings[g].1.clone(),
        _ => o.label.clone(),
    }
}
