//! `times.png`: each variant's CPU time relative to the reference's at the
//! moment of each run (1 / speed-up, [`super::schedule`]), one horizontal
//! bar per variant (the median), a whisker from its fastest to its slowest
//! run, and a line at 1 (the thesis's Fig. 4.16 when the knobs
//! are the law and the formulation).

use super::Results;
use crate::plot::{PlotError, ensure_font};
use plotters::prelude::*;
use std::path::Path;

/// Draw `times.png` into `out`.
///
/// # Errors
/// No font, or the image cannot be written; the message names the file.
pub fn draw(out: &Path, r: &Results) -> Result<(), PlotError> {
    ensure_font()?;
    let path = out.join("times.png");
    let fail = PlotError::drawing(&path);
    let t_ref = r.outcomes[0].cpu_s.median;
    // Relative time = 1 / speed-up, run by run against the reference.
    let rows: Vec<(String, f64, f64, f64)> = r
        .outcomes
        .iter()
        .map(|o| {
            (
                o.label.clone(),
                1.0 / o.speed_up.max,
                1.0 / o.speed_up.median,
                1.0 / o.speed_up.min,
            )
        })
        .collect();
    let n = rows.len();
    let x1 = rows.iter().map(|r| r.3).fold(1.0, f64::max) * 1.1;
    let height = 120 + 34 * u32::try_from(n).unwrap_or(u32::MAX / 64);
    let root = BitMapBackend::new(&path, (1000, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| fail(&e))?;
    let labels: Vec<String> = rows.iter().map(|r| r.0.clone()).collect();
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!(
                "{}: CPU time relative to the reference (median {:.2} s)",
                r.scene, t_ref
            ),
            ("sans-serif", 20),
        )
        .margin(14)
        .x_label_area_size(40)
        .y_label_area_size(260)
        .build_cartesian_2d(0.0..x1, -0.5..(n as f64 - 0.5))
        .map_err(|e| fail(&e))?;
    chart
        .configure_mesh()
        .disable_y_mesh()
        .y_labels(n)
        .y_label_formatter(&|y| {
            let i = y.round();
            if (y - i).abs() < 1e-6 && i >= 0.0 {
                labels.get(n - 1 - i as usize).cloned().unwrap_or_default()
            } else {
                String::new()
            }
        })
        .x_desc("CPU time / the reference's at the same moment (median over the runs; whisker: fastest to slowest)")
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(|e| fail(&e))?;
    // The first row at the top.
    let y = |i: usize| (n - 1 - i) as f64;
    chart
        .draw_series(rows.iter().enumerate().map(|(i, row)| {
            let color = if i == 0 {
                BLACK.mix(0.5)
            } else {
                BLUE.mix(0.6)
            };
            Rectangle::new([(0.0, y(i) - 0.32), (row.2, y(i) + 0.32)], color.filled())
        }))
        .map_err(|e| fail(&e))?;
    chart
        .draw_series(rows.iter().enumerate().map(|(i, row)| {
            PathElement::new(vec![(row.1, y(i)), (row.3, y(i))], BLACK.stroke_width(2))
        }))
        .map_err(|e| fail(&e))?;
    chart
        .draw_series(std::iter::once(PathElement::new(
            vec![(1.0, -0.5), (1.0, n as f64 - 0.5)],
            RED.mix(0.7).stroke_width(1),
        )))
        .map_err(|e| fail(&e))?;
    chart
        .draw_series(rows.iter().enumerate().map(|(i, row)| {
            Text::new(
                format!("{:.2}", row.2),
                (row.3.max(row.2) + 0.01 * x1, y(i) + 0.1),
                ("sans-serif", 13),
            )
        }))
        .map_err(|e| fail(&e))?;
    root.present().map_err(|e| fail(&e))
}
