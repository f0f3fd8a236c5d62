//! Measurements: what an identification fits the simulation to
//! (docs/identification.md, "The measurements file").
//!
//! Two forms are read:
//! - **TOML**, any number of data sets (`[[set]]`), each with its own scene
//!   overrides, scalar quantities named by their `summary.json` key, curves
//!   along a section at a report stroke, and the punch force against stroke,
//!   every value with an optional standard error;
//! - **CSV** `stroke_mm,quantity,value_mm[,se_mm]` with `#` comments: one data
//!   set of draw-in values, `quantity` a draw-in point of the scene, each row
//!   the scalar `states.<stroke>.draw_in.<quantity>`.
//!
//! Every error names the file and the line.

use super::IdentifyError;
use crate::csv_records::{LineError, error_line, start_line};
use crate::run::summary::stroke_key;
use serde::Deserialize;
use std::path::{Path, PathBuf};
use toml::Spanned;

/// The measurements of one identification.
#[derive(Debug, Clone)]
pub struct Measurements {
    /// The file they came from.
    pub path: PathBuf,
    /// The data sets (the thesis's `m` sets), each simulated by its own run.
    pub sets: Vec<DataSet>,
}

/// One data set: one experiment, simulated by one run of the scene with the
/// set's overrides.
#[derive(Debug, Clone)]
pub struct DataSet {
    /// Name (letters, digits, `-`, `_`, `.`): the folder of its runs.
    pub name: String,
    /// Scene overrides of this experiment (`KEY=VALUE`), after the command's.
    pub overrides: Vec<String>,
    /// The measured values, in the order the objective reads them.
    pub points: Vec<Point>,
}

pub use crate::quantity::{CurveColumn, Quantity};

/// One measured value.
#[derive(Debug, Clone)]
pub struct Point {
    /// What it measures (a curve's at a report stroke).
    pub quantity: Quantity,
    /// For a curve: the initial distance from the section's start (mm) at
    /// which the curve is read.
    pub distance: Option<f64>,
    /// The measured value (in the scene's units).
    pub value: f64,
    /// Its standard error, if given.
    pub se: Option<f64>,
    /// The scale its error is divided by in the mean-absolute-error
    /// objective: `|value|` for a scalar, the largest `|value|` of its curve
    /// for a curve or force point.
    pub scale: f64,
    /// Which group of the data set it belongs to (a scalar: its own; a curve:
    /// the curve's), for plots.
    pub group: String,
    /// 1-based line in the file.
    pub line: usize,
}

impl Point {
    /// A short label: the key, `OD@40 major at 12.5 mm`, `force at 20 mm`.
    pub fn label(&self) -> String {
        match &self.quantity {
            Quantity::Scalar { key } => key.clone(),
            Quantity::Curve {
                section,
                stroke,
                column,
            } => format!(
                "{section}@{} {} at {} mm",
                stroke.map_or_else(|| "end".into(), stroke_key),
                column.name(),
                self.distance.unwrap_or(f64::NAN)
            ),
            Quantity::Force { stroke } => format!("punch force at {stroke} mm"),
        }
    }
}

impl Measurements {
    /// Read a measurements file (CSV by its `.csv` extension, else TOML).
    ///
    /// # Errors
    /// The file cannot be read, or a line is malformed: `FILE:LINE: what`.
    pub fn read(path: &Path) -> Result<Self, IdentifyError> {
        let text = plugins_api::input_file::read_text(path, plugins_api::input_file::TEXT_LIMIT)
            .map_err(|e| IdentifyError::Measurements {
                path: path.to_path_buf(),
                line: 0,
                message: e.to_string(),
            })?;
        let is_csv = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
        let sets = if is_csv {
            read_csv(&text)
        } else {
            read_toml(&text)
        }
        .map_err(|(line, message)| IdentifyError::Measurements {
            path: path.to_path_buf(),
            line,
            message,
        })?;
        if sets.iter().all(|s| s.points.is_empty()) {
            return Err(IdentifyError::Measurements {
                path: path.to_path_buf(),
                line: 0,
                message: "no measured values".into(),
            });
        }
        Ok(Self {
            path: path.to_path_buf(),
            sets,
        })
    }

    /// Every report stroke the measurements read (states and curves), sorted.
    pub fn strokes(&self) -> Vec<f64> {
        let mut out: Vec<f64> = Vec::new();
        for p in self.sets.iter().flat_map(|s| &s.points) {
            if let Some(s) = p.quantity.report_stroke()
                && !out.iter().any(|o| stroke_key(*o) == stroke_key(s))
            {
                out.push(s);
            }
        }
        out.sort_by(f64::total_cmp);
        out
    }

    /// Whether every value has a standard error.
    pub fn all_have_se(&self) -> bool {
        self.sets
            .iter()
            .flat_map(|s| &s.points)
            .all(|p| p.se.is_some())
    }

    /// The number of measured values.
    pub fn len(&self) -> usize {
        self.sets.iter().map(|s| s.points.len()).sum()
    }

    /// Whether there is no measured value.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// 1-based line of byte offset `at` in `text`.
fn line_of(text: &str, at: usize) -> usize {
    text[..at.min(text.len())].matches('\n').count() + 1
}

// ---- CSV ------------------------------------------------------------------

/// The CSV form: one data set `measured` of draw-in scalars.
fn read_csv(text: &str) -> Result<Vec<DataSet>, LineError> {
    let mut reader = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let headers = reader
        .headers()
        .map_err(|e| (error_line(&e), e.to_string()))?
        .clone();
    let column = |name: &str| headers.iter().position(|h| h == name);
    let (Some(stroke_c), Some(q_c), Some(v_c)) =
        (column("stroke_mm"), column("quantity"), column("value_mm"))
    else {
        return Err((
            start_line(text, headers.position(), true),
            format!(
                "the header must name stroke_mm, quantity, value_mm (and optionally se_mm); found `{}`",
                headers.iter().collect::<Vec<_>>().join(",")
            ),
        ));
    };
    let se_c = column("se_mm");
    let mut points = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| (error_line(&e), e.to_string()))?;
        let line = start_line(text, record.position(), true);
        let field = |c: usize| record.get(c).unwrap_or("");
        let number = |c: usize, what: &str| -> Result<f64, LineError> {
            field(c)
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    (
                        line,
                        format!("{what} `{}` is not a finite number", field(c)),
                    )
                })
        };
        let stroke = number(stroke_c, "stroke_mm")?;
        if stroke <= 0.0 {
            return Err((line, format!("stroke_mm {stroke} must be positive (mm)")));
        }
        let quantity = field(q_c);
        if !crate::scene::validate::is_plain_name(quantity) {
            return Err((
                line,
                format!("quantity `{quantity}` must be a draw-in point's name (e.g. DX)"),
            ));
        }
        let value = number(v_c, "value_mm")?;
        let se = match se_c {
            Some(c) if !field(c).is_empty() => Some(positive_se(number(c, "se_mm")?, line)?),
            _ => None,
        };
        let key = format!("states.{}.draw_in.{quantity}", stroke_key(stroke));
        points.push(Point {
            quantity: Quantity::Scalar { key: key.clone() },
            distance: None,
            value,
            se,
            scale: value.abs(),
            group: key,
            line,
        });
    }
    Ok(vec![DataSet {
        name: "measured".into(),
        overrides: Vec::new(),
        points,
    }])
}

fn positive_se(se: f64, line: usize) -> Result<f64, LineError> {
    if se > 0.0 && se.is_finite() {
        Ok(se)
    } else {
        Err((line, format!("standard error {se} must be positive")))
    }
}

// ---- TOML -----------------------------------------------------------------

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    #[serde(rename = "set", default)]
    sets: Vec<Spanned<RawSet>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSet {
    name: String,
    #[serde(default)]
    overrides: Vec<String>,
    #[serde(default)]
    scalar: Vec<Spanned<RawScalar>>,
    #[serde(default)]
    curve: Vec<Spanned<RawCurve>>,
    #[serde(default)]
    force: Option<Spanned<RawForce>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScalar {
    key: String,
    value: f64,
    se: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCurve {
    section: String,
    stroke: f64,
    quantity: String,
    /// `[distance, value]` or `[distance, value, se]`.
    points: Vec<Vec<f64>>,
    se: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawForce {
    /// `[stroke, force]` or `[stroke, force, se]`.
    points: Vec<Vec<f64>>,
    se: Option<f64>,
}

fn read_toml(text: &str) -> Result<Vec<DataSet>, LineError> {
    let raw: RawFile = toml::from_str(text).map_err(|e| {
        let line = e.span().map_or(0, |s| line_of(text, s.start));
        (line, e.message().trim().replace('\n', "; "))
    })?;
    let mut sets: Vec<DataSet> = Vec::new();
    for set in raw.sets {
        let line = line_of(text, set.span().start);
        let set = set.into_inner();
        if !crate::scene::validate::is_plain_name(&set.name) {
            return Err((
                line,
                format!(
                    "set name `{}` must be letters, digits, `-`, `_` or `.`",
                    set.name
                ),
            ));
        }
        if sets.iter().any(|s| s.name == set.name) {
            return Err((line, format!("set name `{}` is used twice", set.name)));
        }
        for o in &set.overrides {
            crate::scene::overrides::parse_assignment(o).map_err(|e| (line, e.to_string()))?;
        }
        let mut points = Vec::new();
        for s in set.scalar {
            let line = line_of(text, s.span().start);
            points.push(scalar(s.into_inner(), line)?);
        }
        for c in set.curve {
            let line = line_of(text, c.span().start);
            points.extend(curve(c.into_inner(), line)?);
        }
        if let Some(f) = set.force {
            let line = line_of(text, f.span().start);
            points.extend(force(f.into_inner(), line)?);
        }
        sets.push(DataSet {
            name: set.name,
            overrides: set.overrides,
            points,
        });
    }
    if sets.is_empty() {
        return Err((1, "no [[set]] table".into()));
    }
    Ok(sets)
}

fn finite(v: f64, what: &str, line: usize) -> Result<f64, LineError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err((line, format!("{what} {v} is not finite")))
    }
}

fn scalar(s: RawScalar, line: usize) -> Result<Point, LineError> {
    if s.key.split('.').any(str::is_empty) {
        return Err((
            line,
            format!("key `{}` is not a dotted summary.json key", s.key),
        ));
    }
    let value = finite(s.value, "value", line)?;
    Ok(Point {
        quantity: Quantity::Scalar { key: s.key.clone() },
        distance: None,
        value,
        se: s.se.map(|se| positive_se(se, line)).transpose()?,
        scale: value.abs(),
        group: s.key,
        line,
    })
}

/// `[x, value]` or `[x, value, se]` rows, checked.
fn rows(
    points: &[Vec<f64>],
    default_se: Option<f64>,
    line: usize,
) -> Result<Vec<(f64, f64, Option<f64>)>, LineError> {
    if points.is_empty() {
        return Err((line, "points is empty".into()));
    }
    let default_se = default_se.map(|se| positive_se(se, line)).transpose()?;
    points
        .iter()
        .map(|p| match p.as_slice() {
            [x, v] => Ok((
                finite(*x, "point", line)?,
                finite(*v, "point", line)?,
                default_se,
            )),
            [x, v, se] => Ok((
                finite(*x, "point", line)?,
                finite(*v, "point", line)?,
                Some(positive_se(*se, line)?),
            )),
            _ => Err((
                line,
                format!(
                    "a point must be [x, value] or [x, value, se], not {} numbers",
                    p.len()
                ),
            )),
        })
        .collect()
}

fn curve(c: RawCurve, line: usize) -> Result<Vec<Point>, LineError> {
    let column = CurveColumn::parse(&c.quantity).ok_or_else(|| {
        (
            line,
            format!(
                "quantity `{}`: expected major, minor, thickness_strain or thinning",
                c.quantity
            ),
        )
    })?;
    let stroke = finite(c.stroke, "stroke", line)?;
    if stroke <= 0.0 {
        return Err((line, format!("stroke {stroke} must be positive (mm)")));
    }
    let rows = rows(&c.points, c.se, line)?;
    let scale = rows.iter().map(|r| r.1.abs()).fold(0.0, f64::max);
    let group = format!("{}@{} {}", c.section, stroke_key(stroke), column.name());
    Ok(rows
        .into_iter()
        .map(|(distance, value, se)| Point {
            quantity: Quantity::Curve {
                section: c.section.clone(),
                stroke: Some(stroke),
                column,
            },
            distance: Some(distance),
            value,
            se,
            scale,
            group: group.clone(),
            line,
        })
        .collect())
}

fn force(f: RawForce, line: usize) -> Result<Vec<Point>, LineError> {
    let rows = rows(&f.points, f.se, line)?;
    let scale = rows.iter().map(|r| r.1.abs()).fold(0.0, f64::max);
    Ok(rows
        .into_iter()
        .map(|(stroke, value, se)| Point {
            quantity: Quantity::Force { stroke },
            distance: None,
            value,
            se,
            scale,
            group: "punch force".into(),
            line,
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, text: &str) -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        (dir, path)
    }

    #[test]
    fn shared_drawin_csv_is_read_as_it_is() {
        let text =
            "# comment\n# more\nstroke_mm,quantity,value_mm\n40,DX,28.5\n40,DY,28.5\n40,DD,15.0\n";
        let (_d, path) = write("m.csv", text);
        let m = Measurements::read(&path).unwrap();
        assert_eq!(m.sets.len(), 1);
        let keys: Vec<String> = m.sets[0].points.iter().map(Point::label).collect();
        assert_eq!(
            keys,
            [
                "states.40.draw_in.DX",
                "states.40.draw_in.DY",
                "states.40.draw_in.DD"
            ]
        );
        assert_eq!(m.sets[0].points[2].value, 15.0);
        assert_eq!(m.sets[0].points[2].line, 6);
        assert_eq!(m.strokes(), vec![40.0]);
        assert!(!m.all_have_se());
    }

    #[test]
    fn bad_csv_names_the_line() {
        let (_d, path) = write(
            "m.csv",
            "stroke_mm,quantity,value_mm\n40,DX,28.5\n40,DY,abc\n",
        );
        let e = Measurements::read(&path).unwrap_err().to_string();
        assert!(
            e.contains("m.csv:3:") && e.contains("abc") && !e.contains('\n'),
            "{e}"
        );
        let (_d, path) = write("m.csv", "stroke,q,v\n40,DX,28.5\n");
        let e = Measurements::read(&path).unwrap_err().to_string();
        assert!(e.contains("m.csv:1:") && e.contains("stroke_mm"), "{e}");
    }

    /// A row after comment or blank lines is named by its own line (the `csv`
    /// crate's record position is where its reader began to look, before the
    /// lines it skipped: this read line 5, and the header's error line 1).
    #[test]
    fn a_row_after_comments_and_blank_lines_names_its_own_line() {
        let text = "# c\n\nstroke_mm,quantity,value_mm\n40,DX,28.5\n# note\n\n40,DY,abc\n";
        let (_d, path) = write("m.csv", text);
        let e = Measurements::read(&path).unwrap_err().to_string();
        assert!(e.contains("m.csv:7:") && e.contains("abc"), "{e}");
        let text = "# c\n\nstroke,q,v\n40,DX,28.5\n";
        let (_d, path) = write("m.csv", text);
        let e = Measurements::read(&path).unwrap_err().to_string();
        assert!(e.contains("m.csv:3:") && e.contains("stroke_mm"), "{e}");
    }

    #[test]
    fn toml_sets_curves_and_force() {
        let text = r#"
[[set]]
name = "m1"
overrides = ["tools.blankholder.force=4900.0"]
scalar = [{ key = "states.12.5.draw_in.DX", value = 4.0, se = 0.2 }]
[[set.curve]]
section = "OD"
stroke = 40
quantity = "major"
points = [[10.0, 0.05], [20.0, -0.1, 0.02]]
se = 0.01
[set.force]
points = [[10.0, 30000.0]]
se = 500.0
"#;
        let (_d, path) = write("m.toml", text);
        let m = Measurements::read(&path).unwrap();
        let p = &m.sets[0].points;
        assert_eq!(p.len(), 4);
        assert_eq!(p[1].se, Some(0.01));
        assert_eq!(p[2].se, Some(0.02));
        assert_eq!(p[2].scale, 0.1);
        assert_eq!(p[3].quantity, Quantity::Force { stroke: 10.0 });
        assert_eq!(m.strokes(), vec![12.5, 40.0]);
        assert!(m.all_have_se());
    }

    #[test]
    fn bad_toml_names_the_line() {
        let cases = [
            (
                "[[set]]\nname = \"a\"\n[[set.curve]]\nsection = \"OD\"\nstroke = 40\nquantity = \"majr\"\npoints = [[1.0, 2.0]]\n",
                ":3:",
                "majr",
            ),
            (
                "[[set]]\nname = \"a\"\nscalar = [{ key = \"x\", value = 1.0, se = -1.0 }]\n",
                ":3:",
                "standard error",
            ),
            ("[[set]]\nname = \"a\"\nbogus = 1\n", ":", "bogus"),
            (
                "[[set]]\nname = \"a\"\n[[set]]\nname = \"a\"\n",
                ":3:",
                "twice",
            ),
            ("[[set]\n", ":1:", ""),
        ];
        for (text, line, word) in cases {
            let (_d, path) = write("m.toml", text);
            let e = Measurements::read(&path).unwrap_err().to_string();
            assert!(
                e.contains(line) && e.contains(word) && !e.contains('\n'),
                "{text}: {e}"
            );
        }
    }
}
