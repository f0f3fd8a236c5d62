//! Plots of an identification: measured values with their error bars against
//! the simulated ones at the start and at the end.

use crate::plot::{PlotError, Series, axes, ensure_font};
use plotters::prelude::*;
use std::path::Path;

/// One panel: measured points (with optional standard errors) and simulated lines.
#[derive(Debug, Clone)]
pub struct MarkPanel {
    /// Title.
    pub title: String,
    /// x-axis label with unit.
    pub x_label: String,
    /// y-axis label with unit.
    pub y_label: String,
    /// Measured `(x, value, se)`.
    pub measured: Vec<(f64, f64, Option<f64>)>,
    /// Simulated curves (start, end).
    pub simulated: Vec<Series>,
    /// Join the simulated points by lines (curves); markers only for scalars.
    pub lines: bool,
}

/// Colours of the simulated series: start, end.
const COLOURS: [RGBColor; 2] = [RGBColor(70, 110, 200), RGBColor(210, 50, 40)];

fn range(panel: &MarkPanel) -> ((f64, f64), (f64, f64)) {
    let mut xs: Vec<f64> = panel.measured.iter().map(|m| m.0).collect();
    let mut ys: Vec<f64> = Vec::new();
    for (_, y, se) in &panel.measured {
        let e = se.unwrap_or(0.0);
        ys.extend([y - 1.96 * e, y + 1.96 * e]);
    }
    for s in &panel.simulated {
        xs.extend(s.points.iter().map(|p| p.0));
        ys.extend(s.points.iter().map(|p| p.1));
    }
    let span = |v: &[f64]| {
        let lo = v
            .iter()
            .copied()
            .filter(|x| x.is_finite())
            .fold(f64::MAX, f64::min);
        let hi = v
            .iter()
            .copied()
            .filter(|x| x.is_finite())
            .fold(f64::MIN, f64::max);
        if lo > hi {
            return (0.0, 1.0);
        }
        let pad = if hi > lo {
            0.08 * (hi - lo)
        } else {
            lo.abs().max(1.0) * 0.1
        };
        (lo - pad, hi + pad)
    };
    (span(&xs), span(&ys))
}

/// Draw the panels stacked into a PNG.
///
/// # Errors
/// No font, or the file cannot be written.
pub fn draw(path: &Path, panels: &[MarkPanel]) -> Result<(), PlotError> {
    ensure_font()?;
    let fail = PlotError::drawing(path);
    let rows = u32::try_from(panels.len().max(1)).unwrap_or(1);
    let root = BitMapBackend::new(path, (900, 340 * rows)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| fail(&e))?;
    for (panel, area) in panels
        .iter()
        .zip(root.split_evenly((panels.len().max(1), 1)).iter())
    {
        let mut chart = axes(
            area,
            &panel.title,
            &panel.x_label,
            &panel.y_label,
            range(panel),
            18,
        )
        .map_err(|e| fail(&e))?;
        for (i, s) in panel.simulated.iter().enumerate() {
            let color = COLOURS[i % COLOURS.len()];
            if panel.lines {
                chart
                    .draw_series(LineSeries::new(
                        s.points.iter().copied(),
                        color.stroke_width(2),
                    ))
                    .map_err(|e| fail(&e))?;
            }
            chart
                .draw_series(
                    s.points
                        .iter()
                        .map(|&(x, y)| Circle::new((x, y), 5, color.filled())),
                )
                .map_err(|e| fail(&e))?
                .label(s.label.as_str())
                .legend(move |(x, y)| Circle::new((x + 9, y), 5, color.filled()));
        }
        chart
            .draw_series(panel.measured.iter().filter_map(|&(x, y, se)| {
                se.map(|e| {
                    ErrorBar::new_vertical(
                        x,
                        y - 1.96 * e,
                        y,
                        y + 1.96 * e,
                        BLACK.stroke_width(1),
                        8,
                    )
                })
            }))
            .map_err(|e| fail(&e))?;
        chart
            .draw_series(
                panel
                    .measured
                    .iter()
                    .map(|&(x, y, _)| Cross::new((x, y), 6, BLACK.stroke_width(2))),
            )
            .map_err(|e| fail(&e))?
            .label("measured (95 % bars where se is given)")
            .legend(|(x, y)| Cross::new((x + 9, y), 6, BLACK.stroke_width(2)));
        crate::plot::legend(&mut chart, SeriesLabelPosition::UpperRight, 13)
            .map_err(|e| fail(&e))?;
    }
    root.present().map_err(|e| fail(&e))
}
