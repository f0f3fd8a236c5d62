//! PNG plots (plotters, bitmap backend): line charts of histories and sections.
//!
//! Text is drawn with a TrueType font found on the system (DejaVu Sans or
//! Liberation Sans, the common Debian fonts; `FORMSIM_FONT` overrides); without
//! one, plotting fails with a message saying which package to install.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::prelude::*;

const FONT_CANDIDATES: [&str; 5] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    "/Library/Fonts/Arial.ttf",
];

/// Why a plot cannot be drawn.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// No TrueType font for the labels.
    #[error(
        "no TrueType font found for plot labels: install the Debian package fonts-dejavu-core or set FORMSIM_FONT=/path/to/font.ttf"
    )]
    NoFont,
    /// The plotting library failed, or the image's directory cannot be made.
    #[error("{path}: cannot draw plot: {message}")]
    Draw {
        /// The image being written.
        path: PathBuf,
        /// The library's (or the system's) message.
        message: String,
    },
}

impl PlotError {
    /// A [`PlotError::Draw`] for `path` from any error's message.
    pub(crate) fn drawing(path: &Path) -> impl Fn(&dyn std::fmt::Display) -> Self + '_ {
        move |e| Self::Draw {
            path: path.to_path_buf(),
            message: e.to_string(),
        }
    }
}

/// Register a sans-serif font once per process.
pub(crate) fn ensure_font() -> Result<(), PlotError> {
    static FONT: OnceLock<bool> = OnceLock::new();
    let found = *FONT.get_or_init(|| {
        let from_env = std::env::var("FORMSIM_FONT").ok();
        let candidates = from_env.iter().map(String::as_str).chain(FONT_CANDIDATES);
        for path in candidates {
            if let Ok(bytes) = std::fs::read(path) {
                // The font must live for the whole process (plotters keeps a reference).
                let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
                if plotters::style::register_font("sans-serif", FontStyle::Normal, bytes).is_ok() {
                    return true;
                }
            }
        }
        false
    });
    if found {
        Ok(())
    } else {
        Err(PlotError::NoFont)
    }
}

/// One curve of a chart.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Points `(x, y)`.
    pub points: Vec<(f64, f64)>,
}

/// One panel: a title, axis labels and curves.
#[derive(Clone, Debug)]
pub struct Panel {
    /// Panel title.
    pub title: String,
    /// x-axis label with unit.
    pub x_label: String,
    /// y-axis label with unit.
    pub y_label: String,
    /// Curves.
    pub series: Vec<Series>,
}

fn bounds(panel: &Panel) -> ((f64, f64), (f64, f64)) {
    let pts = panel
        .series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|(x, y)| x.is_finite() && y.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in pts {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if x0 > x1 {
        return ((0.0, 1.0), (0.0, 1.0));
    }
    let pad = |a: f64, b: f64| {
        let span = if b > a { b - a } else { a.abs().max(1.0) };
        (a - 0.05 * span, b + 0.05 * span)
    };
    (if x1 > x0 { (x0, x1) } else { pad(x0, x1) }, pad(y0, y1))
}

/// A chart on a bitmap with f64 axes.
pub(crate) type Chart<'a, 'b> = ChartContext<
    'a,
    BitMapBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;
/// A drawing error of the bitmap backend.
pub(crate) type DrawError<'b> =
    DrawingAreaErrorKind<<BitMapBackend<'b> as DrawingBackend>::ErrorType>;

/// A chart on `area` with its caption and labelled axes over `ranges`
/// (`caption` in points; the axis labels two points smaller).
///
/// # Errors
/// The drawing backend fails.
pub(crate) fn axes<'a, 'b>(
    area: &'a DrawingArea<BitMapBackend<'b>, plotters::coord::Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    ((x0, x1), (y0, y1)): ((f64, f64), (f64, f64)),
    caption: u32,
) -> Result<Chart<'a, 'b>, DrawError<'b>> {
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", caption))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .label_style(("sans-serif", caption - 6))
        .draw()?;
    Ok(chart)
}

/// The legend every chart of formsim draws: a white box with a black
/// border at `position`, labels in `font`-point sans-serif.
///
/// # Errors
/// The drawing backend fails.
pub(crate) fn legend<'a, DB: DrawingBackend + 'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
    font: u32,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", font))
        .draw()
}

/// Draw panels stacked vertically into a PNG of `width × (height_per_panel · n)` pixels.
///
/// # Errors
/// No font, or the image cannot be written; the message names the file.
pub fn draw_panels(
    path: &Path,
    panels: &[Panel],
    width: u32,
    height_per_panel: u32,
) -> Result<(), PlotError> {
    ensure_font()?;
    let fail = PlotError::drawing(path);
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| fail(&e))?;
    }
    let rows = u32::try_from(panels.len().max(1)).unwrap_or(1);
    let root = BitMapBackend::new(path, (width, height_per_panel * rows)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| fail(&e))?;
    let areas = root.split_evenly((panels.len().max(1), 1));
    for (panel, area) in panels.iter().zip(areas.iter()) {
        let mut chart = axes(
            area,
            &panel.title,
            &panel.x_label,
            &panel.y_label,
            bounds(panel),
            20,
        )
        .map_err(|e| fail(&e))?;
        for (i, s) in panel.series.iter().enumerate() {
            let color = Palette99::pick(i).to_rgba();
            chart
                .draw_series(LineSeries::new(
                    s.points.iter().copied(),
                    color.stroke_width(2),
                ))
                .map_err(|e| fail(&e))?
                .label(s.label.as_str())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
                });
        }
        legend(&mut chart, SeriesLabelPosition::MiddleRight, 14).map_err(|e| fail(&e))?;
    }
    root.present().map_err(|e| fail(&e))
}
