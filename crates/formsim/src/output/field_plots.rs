//! PNG colour maps of a per-element scalar on the blank in plan view (e.g. the
//! thinning map): each quadrilateral is filled with its value's colour on a
//! perceptual (viridis) scale, axes in mm with equal aspect ratio, a colour
//! bar labelled with the minimum and maximum.
//!
//! Text uses the font found by [`crate::plot`] (DejaVu Sans or Liberation
//! Sans, `FORMSIM_FONT` overrides).

use std::ops::Range;
use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::error::{OutputError, create_parent_dir};

/// Image width (px).
const WIDTH: u32 = 800;
/// Image height (px).
const HEIGHT: u32 = 700;
/// Width of the colour-bar column on the right (px).
const BAR_COLUMN: u32 = 150;
/// Above this many elements the element edges are not drawn (they would hide the colours).
const MAX_OUTLINED_ELEMENTS: usize = 2500;
/// Colour steps drawn in the colour bar.
const BAR_STEPS: usize = 128;

/// Viridis (matplotlib's default map, public domain) sampled at eleven equally
/// spaced points; intermediate values are interpolated linearly.
const VIRIDIS: [[u8; 3]; 11] = [
    [0x44, 0x01, 0x54],
    [0x48, 0x24, 0x75],
    [0x41, 0x44, 0x87],
    [0x35, 0x5f, 0x8d],
    [0x2a, 0x78, 0x8e],
    [0x21, 0x91, 0x8c],
    [0x22, 0xa8, 0x84],
    [0x44, 0xbf, 0x70],
    [0x7a, 0xd1, 0x51],
    [0xbd, 0xdf, 0x26],
    [0xfd, 0xe7, 0x25],
];

/// Colour of `t` in `[0, 1]` (clamped) on the viridis scale.
fn viridis(t: f64) -> RGBColor {
    let s = t.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f64;
    let i = (s.floor() as usize).min(VIRIDIS.len() - 2);
    let f = s - i as f64;
    let mix = |k: usize| {
        let (a, b) = (f64::from(VIRIDIS[i][k]), f64::from(VIRIDIS[i + 1][k]));
        (a + f * (b - a)).round() as u8
    };
    RGBColor(mix(0), mix(1), mix(2))
}

/// A value as a short label: four significant digits, exponent form when very
/// large or small.
fn label(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".to_string()
    } else if (1e-3..1e5).contains(&a) {
        let decimals = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.3e}")
    }
}

/// Check lengths, node numbers and finiteness; return the value range.
fn validate(
    path: &Path,
    quads: &[[u32; 4]],
    xy: &[[f64; 2]],
    values: &[f64],
) -> Result<(f64, f64), OutputError> {
    if quads.is_empty() {
        return Err(OutputError::invalid(path, "no elements to plot"));
    }
    if values.len() != quads.len() {
        return Err(OutputError::invalid(
            path,
            format!(
                "{} element values for {} elements",
                values.len(),
                quads.len()
            ),
        ));
    }
    if let Some((n, p)) = xy
        .iter()
        .enumerate()
        .find(|(_, p)| !(p[0].is_finite() && p[1].is_finite()))
    {
        return Err(OutputError::invalid(
            path,
            format!(
                "node {n} has coordinates ({}, {}) mm; they must be finite",
                p[0], p[1]
            ),
        ));
    }
    for (e, quad) in quads.iter().enumerate() {
        if let Some(&n) = quad.iter().find(|&&n| n as usize >= xy.len()) {
            return Err(OutputError::invalid(
                path,
                format!(
                    "element {e} refers to node {n} but there are {} nodes",
                    xy.len()
                ),
            ));
        }
    }
    if let Some((e, v)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(OutputError::invalid(
            path,
            format!("element value at element {e} is {v}; values must be finite"),
        ));
    }
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    Ok((lo, hi))
}

/// Bounding box of the nodes used by the elements, as `(x range, y range)` in mm.
fn bounding_box(quads: &[[u32; 4]], xy: &[[f64; 2]]) -> (Range<f64>, Range<f64>) {
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &n in quads.iter().flatten() {
        let [x, y] = xy[n as usize];
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    (x0..x1, y0..y1)
}

/// Grow the data box so that one millimetre spans the same number of pixels
/// along x and y in a plotting area of `(w, h)` pixels, with a 3 % border.
fn equal_aspect(x: Range<f64>, y: Range<f64>, (w, h): (u32, u32)) -> (Range<f64>, Range<f64>) {
    let span = (x.end - x.start).max(y.end - y.start).max(1e-9);
    let dx = (x.end - x.start).max(1e-3 * span) * 1.06;
    let dy = (y.end - y.start).max(1e-3 * span) * 1.06;
    let (w, h) = (f64::from(w.max(1)), f64::from(h.max(1)));
    let mm_per_px = (dx / w).max(dy / h);
    let (cx, cy) = (0.5 * (x.start + x.end), 0.5 * (y.start + y.end));
    let (hx, hy) = (0.5 * mm_per_px * w, 0.5 * mm_per_px * h);
    (cx - hx..cx + hx, cy - hy..cy + hy)
}

/// The error of a failed drawing step on `path`.
fn plot_error<E: std::fmt::Display>(path: &Path) -> impl Fn(E) -> OutputError + '_ {
    move |e| OutputError::Plot {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// The colour scale of a map: the range the colours span (`lo..hi`) and the
/// data's own minimum and maximum, written at the ends of the colour bar.
struct ColourScale {
    /// Value at the dark-blue end.
    lo: f64,
    /// Value at the yellow end.
    hi: f64,
    /// The data's minimum.
    vmin: f64,
    /// The data's maximum.
    vmax: f64,
}

impl ColourScale {
    /// The scale of values from `vmin` to `vmax`. A constant field still gets
    /// a non-empty scale (all elements mid-colour).
    fn new(vmin: f64, vmax: f64) -> Self {
        let (lo, hi) = if vmax > vmin {
            (vmin, vmax)
        } else {
            let d = (vmin.abs() * 1e-3).max(1e-12);
            (vmin - d, vmax + d)
        };
        Self { lo, hi, vmin, vmax }
    }

    /// The colour of `v` on the viridis scale.
    fn colour(&self, v: f64) -> RGBColor {
        viridis((v - self.lo) / (self.hi - self.lo))
    }
}

/// The image's drawing area.
type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;
/// A chart with f64 axes on the image.
type Chart<'a, 'b> =
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Draw a plan-view (x, y) colour map of one scalar per element into a PNG of
/// 800 × 700 px: every quadrilateral filled with its value's colour on the
/// viridis scale from the minimum (dark blue) to the maximum (yellow), axes in
/// mm with equal aspect ratio, and a colour bar labelled `colorbar_label`
/// whose end ticks are the minimum and the maximum. `xy` are node coordinates
/// (mm), `quads` four zero-based node numbers per element, `values` one number
/// per element. Missing parent directories are created.
///
/// # Errors
/// [`OutputError::Invalid`] when there is no element, the value count differs
/// from the element count, an element refers to a missing node, or a
/// coordinate or value is NaN or infinite (the message names the index);
/// [`OutputError::Plot`] when no font is found or drawing fails;
/// [`OutputError::Io`] when the directory cannot be created.
pub fn element_map_png(
    path: &Path,
    title: &str,
    colorbar_label: &str,
    quads: &[[u32; 4]],
    xy: &[[f64; 2]],
    values: &[f64],
) -> Result<(), OutputError> {
    let (vmin, vmax) = validate(path, quads, xy, values)?;
    crate::plot::ensure_font().map_err(plot_error(path))?;
    create_parent_dir(path)?;
    let scale = ColourScale::new(vmin, vmax);

    let root = BitMapBackend::new(path, (WIDTH, HEIGHT)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_error(path))?;
    let body = root
        .titled(title, ("sans-serif", 22))
        .map_err(plot_error(path))?;
    let (map_area, bar_area) = body.split_horizontally(WIDTH - BAR_COLUMN);
    draw_map(path, &map_area, quads, xy, values, &scale)?;
    draw_colour_bar(path, &root, &bar_area, colorbar_label, &scale)?;
    root.present().map_err(plot_error(path))
}

/// The map's chart on `map_area`: built once to learn the plotting area's
/// size, then with equal-aspect ranges around the elements, axes drawn.
fn map_chart<'a, 'b>(
    path: &Path,
    map_area: &'a Area<'b>,
    quads: &[[u32; 4]],
    xy: &[[f64; 2]],
) -> Result<Chart<'a, 'b>, OutputError> {
    let (bx, by) = bounding_box(quads, xy);
    let builder = || {
        let mut b = ChartBuilder::on(map_area);
        b.margin(15).x_label_area_size(45).y_label_area_size(65);
        b
    };
    let probe = builder()
        .build_cartesian_2d(bx.clone(), by.clone())
        .map_err(plot_error(path))?;
    let (rx, ry) = equal_aspect(bx, by, probe.plotting_area().dim_in_pixel());
    drop(probe);
    let mut chart = builder()
        .build_cartesian_2d(rx, ry)
        .map_err(plot_error(path))?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("x (mm)")
        .y_desc("y (mm)")
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()
        .map_err(plot_error(path))?;
    Ok(chart)
}

/// The closed outline of element `q` (its four corners, then the first again).
fn ring(q: &[u32; 4], xy: &[[f64; 2]]) -> Vec<(f64, f64)> {
    q.iter()
        .chain(&q[..1])
        .map(|&n| {
            let [x, y] = xy[n as usize];
            (x, y)
        })
        .collect()
}

/// The map on `map_area`: axes, every element filled with its value's
/// colour, then the element edges.
fn draw_map(
    path: &Path,
    map_area: &Area<'_>,
    quads: &[[u32; 4]],
    xy: &[[f64; 2]],
    values: &[f64],
    scale: &ColourScale,
) -> Result<(), OutputError> {
    let mut chart = map_chart(path, map_area, quads, xy)?;
    chart
        .draw_series(
            quads
                .iter()
                .zip(values)
                .map(|(q, &v)| Polygon::new(ring(q, xy), scale.colour(v).filled())),
        )
        .map_err(plot_error(path))?;
    // Edges: dark lines on coarse meshes; on fine meshes each element's own
    // colour, which closes the hairline gaps the rasteriser leaves between
    // neighbouring polygons.
    let outlined = quads.len() <= MAX_OUTLINED_ELEMENTS;
    chart
        .draw_series(quads.iter().zip(values).map(|(q, &v)| {
            let edge = if outlined {
                BLACK.mix(0.35).stroke_width(1)
            } else {
                scale.colour(v).stroke_width(1)
            };
            PathElement::new(ring(q, xy), edge)
        }))
        .map_err(plot_error(path))?;
    Ok(())
}

/// The colour bar on `bar_area`: same vertical margins as the map so both
/// line up; nice ticks on the right, the exact minimum and maximum written
/// at its ends (on `root`).
fn draw_colour_bar(
    path: &Path,
    root: &Area<'_>,
    bar_area: &Area<'_>,
    colorbar_label: &str,
    scale: &ColourScale,
) -> Result<(), OutputError> {
    let (lo, hi) = (scale.lo, scale.hi);
    let mut bar = ChartBuilder::on(bar_area)
        .margin(15)
        .margin_left(5)
        .x_label_area_size(45)
        .right_y_label_area_size(95)
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(plot_error(path))?;
    bar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(6)
        .set_tick_mark_size(LabelAreaPosition::Right, 6)
        .y_desc(colorbar_label)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()
        .map_err(plot_error(path))?;
    let dv = (hi - lo) / BAR_STEPS as f64;
    bar.draw_series((0..BAR_STEPS).map(|i| {
        let v0 = lo + dv * i as f64;
        Rectangle::new(
            [(0.0, v0), (1.0, v0 + dv)],
            scale.colour(v0 + 0.5 * dv).filled(),
        )
    }))
    .map_err(plot_error(path))?;
    bar.draw_series(std::iter::once(Rectangle::new(
        [(0.0, lo), (1.0, hi)],
        BLACK.stroke_width(1),
    )))
    .map_err(plot_error(path))?;
    let (top, bottom) = (bar.backend_coord(&(0.0, hi)), bar.backend_coord(&(0.0, lo)));
    draw_end_labels(path, root, top, bottom, scale)
}

/// The data's maximum above the colour bar's `top` and its minimum below its
/// `bottom` (pixel positions on `root`).
fn draw_end_labels(
    path: &Path,
    root: &Area<'_>,
    top: (i32, i32),
    bottom: (i32, i32),
    scale: &ColourScale,
) -> Result<(), OutputError> {
    let end_label = |name: &str, v: f64, at: (i32, i32)| {
        Text::new(
            format!("{name} {}", label(v)),
            at,
            ("sans-serif", 14)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Left, VPos::Center)),
        )
    };
    root.draw(&end_label("max", scale.vmax, (top.0, top.1 - 12)))
        .map_err(plot_error(path))?;
    root.draw(&end_label("min", scale.vmin, (bottom.0, bottom.1 + 13)))
        .map_err(plot_error(path))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends_are_the_table_ends_and_clamp() {
        // Source: the table itself; exact (integer colours).
        assert_eq!(viridis(0.0), RGBColor(0x44, 0x01, 0x54));
        assert_eq!(viridis(1.0), RGBColor(0xfd, 0xe7, 0x25));
        assert_eq!(viridis(-3.0), viridis(0.0));
        assert_eq!(viridis(7.0), viridis(1.0));
        assert_eq!(viridis(0.5), RGBColor(0x21, 0x91, 0x8c));
    }

    #[test]
    fn equal_aspect_gives_same_mm_per_pixel_on_both_axes() {
        let (x, y) = equal_aspect(0.0..200.0, 0.0..50.0, (400, 600));
        let sx = (x.end - x.start) / 400.0;
        let sy = (y.end - y.start) / 600.0;
        assert!((sx - sy).abs() <= 1e-12 * sx, "{sx} vs {sy}");
        assert!(x.start < 0.0 && x.end > 200.0 && y.start < 0.0 && y.end > 50.0);
    }

    #[test]
    fn labels_keep_four_significant_digits() {
        assert_eq!(label(0.0), "0");
        assert_eq!(label(0.123456), "0.1235");
        assert_eq!(label(-12.3456), "-12.35");
        assert_eq!(label(1.5e-5), "1.500e-5");
    }
}
