//! `plots/fld.png`: every element's point on the forming limit diagram,
//! coloured by zone, with the curve and the margin line.

use super::Formability;
use super::zones::{FldPoint, Zone};
use crate::plot::{PlotError, axes, ensure_font};
use plotters::prelude::*;
use std::path::Path;

fn colour(zone: Zone) -> RGBColor {
    match zone {
        Zone::Failure => RGBColor(215, 25, 28),
        Zone::Marginal => RGBColor(253, 174, 17),
        Zone::Safe => RGBColor(26, 150, 65),
        Zone::InsufficientStretch => RGBColor(150, 150, 150),
        Zone::Compression => RGBColor(43, 131, 186),
        Zone::WrinklingTendency => RGBColor(120, 40, 170),
    }
}

/// The diagram's axis ranges: every point, the curve's plane-strain limit
/// and some room around it.
fn ranges(f: &Formability, points: &[FldPoint]) -> ((f64, f64), (f64, f64)) {
    let (mut x0, mut x1) = (-0.1_f64, 0.1_f64);
    let (mut y0, mut y1) = (0.0_f64, 1.2 * f.curve.plane_strain_limit());
    for p in points {
        x0 = x0.min(p.minor);
        x1 = x1.max(p.minor);
        y0 = y0.min(p.major);
        y1 = y1.max(p.major);
    }
    let (dx, dy) = (0.05 * (x1 - x0), 0.05 * (y1 - y0));
    ((x0 - dx, x1 + dx), (y0 - dy, y1 + dy))
}

/// Draw the diagram of `points` into `path` (900 × 700 pixels).
///
/// # Errors
/// No font, or the image cannot be written; the message names the file.
pub fn draw(
    path: &Path,
    f: &Formability,
    points: &[FldPoint],
    title: &str,
) -> Result<(), PlotError> {
    ensure_font()?;
    let fail = PlotError::drawing(path);
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| fail(&e))?;
    }
    let root = BitMapBackend::new(path, (900, 700)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| fail(&e))?;
    let measure = f.curve.measure().as_str();
    let ((x0, x1), y) = ranges(f, points);
    let mut chart = axes(
        &root,
        title,
        &format!("minor strain ({measure}, -)"),
        &format!("major strain ({measure}, -)"),
        ((x0, x1), y),
        20,
    )
    .map_err(|e| fail(&e))?;
    for zone in Zone::ALL {
        let c = colour(zone);
        let mine: Vec<(f64, f64)> = points
            .iter()
            .filter(|p| p.zone == zone)
            .map(|p| (p.minor, p.major))
            .collect();
        let label = format!("{} ({})", zone.label(), mine.len());
        chart
            .draw_series(
                mine.iter()
                    .map(|&(x, y)| Circle::new((x, y), 2, c.filled())),
            )
            .map_err(|e| fail(&e))?
            .label(label)
            .legend(move |(x, y)| Circle::new((x + 9, y), 4, c.filled()));
    }
    let line = |shift: f64| -> Vec<(f64, f64)> {
        (0..=200)
            .map(|i| x0 + (x1 - x0) * f64::from(i) / 200.0)
            .map(|x| (x, f.curve.limit(x) - shift))
            .collect()
    };
    chart
        .draw_series(LineSeries::new(line(0.0), BLACK.stroke_width(2)))
        .map_err(|e| fail(&e))?
        .label("forming limit curve")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK.stroke_width(2)));
    let m = f.thresholds.margin;
    let orange = RGBColor(230, 120, 0);
    chart
        .draw_series(LineSeries::new(line(m), orange.stroke_width(1)))
        .map_err(|e| fail(&e))?
        .label(format!("margin line ({m})"))
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], orange.stroke_width(1)));
    crate::plot::legend(&mut chart, SeriesLabelPosition::UpperRight, 14).map_err(|e| fail(&e))?;
    root.present().map_err(|e| fail(&e))
}
