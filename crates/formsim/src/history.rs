//! Reading a prescribed contact-point history (`formsim friction-point --history IN.csv`).
//!
//! Format: comma-separated, one header line naming the columns (any order),
//! `#` comment lines and blank lines ignored, read by the `csv` crate (a field
//! may be quoted, a line may end in `\r\n`, blanks around a field are
//! dropped). Units: mm, N, MPa, s.
//!
//! | column | required | meaning |
//! |---|---|---|
//! | `t` | yes | time at the end of the step (s), strictly increasing, first `> 0` (the history starts at rest at `t = 0`) |
//! | `p` | yes | contact pressure at the end of the step (MPa), `≥ 0`; `0` = open contact |
//! | `du_x,du_y,du_z` | yes | slip increment of the step `Δu_T` (mm), blank relative to tool |
//! | `n_x,n_y,n_z` | yes | unit tool normal at the end of the step (normalised if within 1e-3 of unit length) |
//! | `w_x,w_y,w_z` | no | blank spin as an axial vector (rad/s): `L = [w]×` unless `l_ij` are given |
//! | `l_11` … `l_33` | no | blank velocity gradient at mid-step (1/s), all nine |
//! | `f_11` … `f_33` | no | blank total deformation gradient at the end of the step, all nine; otherwise accumulated as `F_{n+1} = cay(Δt L) F_n` |
//! | `r_x,r_y,r_z` | no | tool rotation over the step as a rotation vector (rad) |
//! | `sigma_y` | no | blank flow stress (MPa); required by laws that need it (`levanov`) |
//! | `temperature` | no | temperature (K); required by laws that need it |

use std::collections::HashMap;
use std::path::Path;

use plugins_api::kinematics::{cayley, skew};
use plugins_api::{Mat3, StepInput, StepKinematics, Vec3};

/// A parsed history: one [`StepInput`] per data row, with its time and source line.
#[derive(Clone, Debug)]
pub struct History {
    /// Time at the end of each step (s).
    pub times: Vec<f64>,
    /// Line number (1-based) of each step in the file.
    pub lines: Vec<usize>,
    /// Step inputs, in order.
    pub steps: Vec<StepInput>,
    /// Which optional column groups were present.
    pub present: Present,
}

/// Optional column groups found in the header.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Present {
    /// `w_x,w_y,w_z`.
    pub spin: bool,
    /// `l_11..l_33`.
    pub vel_grad: bool,
    /// `f_11..f_33`.
    pub def_grad: bool,
    /// `r_x,r_y,r_z`.
    pub tool_rotation: bool,
    /// `sigma_y`.
    pub flow_stress: bool,
    /// `temperature`.
    pub temperature: bool,
}

/// Error while reading a history: the file, the line and what is wrong.
#[derive(Debug, thiserror::Error)]
#[error("{file}:{line}: {message}")]
pub struct HistoryError {
    /// File name as given.
    pub file: String,
    /// 1-based line number (0 for the file as a whole).
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

const REQUIRED: [&str; 8] = ["t", "p", "du_x", "du_y", "du_z", "n_x", "n_y", "n_z"];
const MATRIX: [&str; 9] = ["11", "12", "13", "21", "22", "23", "31", "32", "33"];

fn known_columns() -> Vec<String> {
    let mut v: Vec<String> = REQUIRED.iter().map(|s| (*s).to_string()).collect();
    v.extend(
        [
            "w_x",
            "w_y",
            "w_z",
            "r_x",
            "r_y",
            "r_z",
            "sigma_y",
            "temperature",
        ]
        .map(String::from),
    );
    for prefix in ["l_", "f_"] {
        v.extend(MATRIX.iter().map(|ij| format!("{prefix}{ij}")));
    }
    v
}

/// Rotation matrix of a rotation vector (Rodrigues).
fn rotation_from_vector(r: &Vec3) -> Mat3 {
    let angle = r.norm();
    if angle == 0.0 {
        return Mat3::identity();
    }
    let k = skew(&(r / angle));
    Mat3::identity() + k * angle.sin() + k * k * (1.0 - angle.cos())
}

/// Read and validate a history file.
///
/// # Errors
/// Unreadable file, missing header or column, unknown column, malformed or
/// non-finite number, non-increasing time, non-unit normal: each with the line.
pub fn read(path: &Path) -> Result<History, HistoryError> {
    let file = path.display().to_string();
    let text = plugins_api::input_file::read_text(path, plugins_api::input_file::TEXT_LIMIT)
        .map_err(|e| HistoryError {
            file: file.clone(),
            line: 0,
            message: format!("cannot read: {e}"),
        })?;
    parse(&text, &file)
}

/// Parse history text (see the module docs for the format).
///
/// # Errors
/// As [`read`].
pub fn parse(text: &str, file: &str) -> Result<History, HistoryError> {
    let mut rows =
        crate::csv_records::records(text, true).map(|r| r.map_err(|(line, e)| at(file, line, e)));
    let (header_line, header) = rows
        .next()
        .transpose()?
        .ok_or_else(|| at(file, 0, "empty file: no header line".into()))?;
    let cols = Columns::of(&header, header_line, file)?;
    let mut out = History {
        times: Vec::new(),
        lines: Vec::new(),
        steps: Vec::new(),
        present: cols.present,
    };
    let mut prev = Previous {
        t: 0.0,
        n: None,
        f: Mat3::identity(),
    };
    for row in rows {
        let (line, fields) = row?;
        if fields.len() != cols.count {
            return Err(at(
                file,
                line,
                format!("{} fields, the header has {}", fields.len(), cols.count),
            ));
        }
        let row = Row {
            fields: &fields,
            cols: &cols,
            line,
            file,
        };
        let (t, step) = row.step(&mut prev)?;
        out.times.push(t);
        out.lines.push(line);
        out.steps.push(step);
    }
    if out.steps.is_empty() {
        return Err(at(
            file,
            header_line,
            "no data rows after the header".into(),
        ));
    }
    Ok(out)
}

/// The error at `line` of `file`.
fn at(file: &str, line: usize, message: String) -> HistoryError {
    HistoryError {
        file: file.to_string(),
        line,
        message,
    }
}

/// The header: each column's index and which optional groups are present.
struct Columns<'a> {
    count: usize,
    index: HashMap<&'a str, usize>,
    present: Present,
}

impl<'a> Columns<'a> {
    /// Read and check the header record (`line` of `file`).
    fn of(header: &'a csv::StringRecord, line: usize, file: &str) -> Result<Self, HistoryError> {
        let known = known_columns();
        let mut index: HashMap<&str, usize> = HashMap::new();
        for (i, name) in header.iter().enumerate() {
            if !known.iter().any(|k| k == name) {
                return Err(at(
                    file,
                    line,
                    format!("unknown column `{name}`; known: {}", known.join(",")),
                ));
            }
            if index.insert(name, i).is_some() {
                return Err(at(file, line, format!("column `{name}` appears twice")));
            }
        }
        for col in REQUIRED {
            if !index.contains_key(col) {
                return Err(at(
                    file,
                    line,
                    format!(
                        "missing required column `{col}` (required: {})",
                        REQUIRED.join(",")
                    ),
                ));
            }
        }
        let group = |cols: &[String]| -> Result<bool, HistoryError> {
            let n = cols
                .iter()
                .filter(|c| index.contains_key(c.as_str()))
                .count();
            if n != 0 && n != cols.len() {
                return Err(at(
                    file,
                    line,
                    format!("columns {} must be given together", cols.join(",")),
                ));
            }
            Ok(n == cols.len())
        };
        let vec_cols = |p: &str| ["x", "y", "z"].map(|a| format!("{p}_{a}")).to_vec();
        let mat_cols = |p: &str| {
            MATRIX
                .iter()
                .map(|ij| format!("{p}_{ij}"))
                .collect::<Vec<_>>()
        };
        let present = Present {
            spin: group(&vec_cols("w"))?,
            vel_grad: group(&mat_cols("l"))?,
            def_grad: group(&mat_cols("f"))?,
            tool_rotation: group(&vec_cols("r"))?,
            flow_stress: index.contains_key("sigma_y"),
            temperature: index.contains_key("temperature"),
        };
        Ok(Self {
            count: header.len(),
            index,
            present,
        })
    }
}

/// What a row carries over to the next: time, normal, deformation gradient.
struct Previous {
    t: f64,
    n: Option<Vec3>,
    f: Mat3,
}

/// One data row, split into fields.
struct Row<'a> {
    fields: &'a csv::StringRecord,
    cols: &'a Columns<'a>,
    line: usize,
    file: &'a str,
}

impl Row<'_> {
    fn err(&self, message: String) -> HistoryError {
        at(self.file, self.line, message)
    }

    fn get(&self, col: &str) -> Result<f64, HistoryError> {
        let raw = &self.fields[self.cols.index[col]];
        let v: f64 = raw
            .parse()
            .map_err(|_| self.err(format!("column `{col}`: `{raw}` is not a number")))?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.err(format!("column `{col}`: {v} is not finite")))
        }
    }

    fn get_vec(&self, p: &str) -> Result<Vec3, HistoryError> {
        Ok(Vec3::new(
            self.get(&format!("{p}_x"))?,
            self.get(&format!("{p}_y"))?,
            self.get(&format!("{p}_z"))?,
        ))
    }

    fn get_mat(&self, p: &str) -> Result<Mat3, HistoryError> {
        let mut m = Mat3::zeros();
        for (k, ij) in MATRIX.iter().enumerate() {
            m[(k / 3, k % 3)] = self.get(&format!("{p}_{ij}"))?;
        }
        Ok(m)
    }

    /// The row's time and step, checked against the previous row (updated).
    fn step(&self, prev: &mut Previous) -> Result<(f64, StepInput), HistoryError> {
        let present = &self.cols.present;
        let t = self.get("t")?;
        if t <= prev.t {
            return Err(self.err(format!(
                "column `t`: time {t} s must exceed the previous {} s (strictly increasing, first > 0)",
                prev.t
            )));
        }
        let dt = t - prev.t;
        let p = self.get("p")?;
        if p < 0.0 {
            return Err(self.err(format!(
                "column `p`: pressure {p} MPa must be >= 0 (0 = open contact)"
            )));
        }
        let du = self.get_vec("du")?;
        let n = self.normal()?;
        let vel_grad = if present.vel_grad {
            self.get_mat("l")?
        } else if present.spin {
            skew(&self.get_vec("w")?)
        } else {
            Mat3::zeros()
        };
        let f_new = if present.def_grad {
            let f = self.get_mat("f")?;
            if f.determinant() <= 0.0 {
                return Err(self.err(format!(
                    "columns f_11..f_33: det F = {} must be > 0",
                    f.determinant()
                )));
            }
            f
        } else {
            cayley(&(vel_grad * dt)) * prev.f
        };
        let tool_rotation = if present.tool_rotation {
            rotation_from_vector(&self.get_vec("r")?)
        } else {
            Mat3::identity()
        };
        let kin = StepKinematics {
            dt,
            n_old: prev.n.unwrap_or(n),
            n_new: n,
            tool_rotation,
            vel_grad,
            f_old: prev.f,
            f_new,
        };
        let mut step = StepInput::new(p, du, kin);
        if present.flow_stress {
            step.flow_stress = self.get("sigma_y")?;
        }
        if present.temperature {
            step.temperature = self.get("temperature")?;
        }
        *prev = Previous {
            t,
            n: Some(n),
            f: f_new,
        };
        Ok((t, step))
    }

    /// The unit normal of the row (within 1e-3 of unit length, normalised).
    fn normal(&self) -> Result<Vec3, HistoryError> {
        let n_raw = self.get_vec("n")?;
        let len = n_raw.norm();
        if (len - 1.0).abs() > 1e-3 {
            return Err(self.err(format!(
                "columns n_x,n_y,n_z: |n| = {len} is not a unit normal"
            )));
        }
        Ok(n_raw / len)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = "# a comment\nt,p,du_x,du_y,du_z,n_x,n_y,n_z\n0.1,10,0.001,0,0,0,0,1\n0.2,10,0.001,0,0,0,0,1.0000001\n";

    #[test]
    fn reads_required_columns() {
        let h = parse(GOOD, "h.csv").unwrap();
        assert_eq!(h.steps.len(), 2);
        assert_eq!(h.lines, vec![3, 4]);
        assert!((h.steps[1].kin.dt - 0.1).abs() < 1e-15);
        assert!((h.steps[1].kin.n_new.norm() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn errors_carry_file_line_and_column() {
        let e = parse("t,p,du_x,du_y,du_z,n_x,n_y\n", "h.csv")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("h.csv:1:") && e.contains("`n_z`"), "{e}");
        let e = parse(
            "t,p,du_x,du_y,du_z,n_x,n_y,n_z\n0.1,NaN,0,0,0,0,0,1\n",
            "h.csv",
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("h.csv:2:") && e.contains("`p`") && e.contains("NaN"),
            "{e}"
        );
        let e = parse(
            "t,p,du_x,du_y,du_z,n_x,n_y,n_z\n0.1,1,0,0,0,0,0,1\n0.1,1,0,0,0,0,0,1\n",
            "h.csv",
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("h.csv:3:") && e.contains("strictly increasing"),
            "{e}"
        );
        let e = parse(
            "t,p,du_x,du_y,du_z,n_x,n_y,n_z\n0.1,1,0,0,x,0,0,1\n",
            "h.csv",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("`du_z`: `x` is not a number"), "{e}");
        let e = parse("t,p,du_x,du_y,du_z,n_x,n_y,n_z,w_x\n", "h.csv")
            .unwrap_err()
            .to_string();
        assert!(e.contains("must be given together"), "{e}");
        let e = parse(
            "t,p,du_x,du_y,du_z,n_x,n_y,n_z\n0.1,1,0,0,0,0,0,2\n",
            "h.csv",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("unit normal"), "{e}");
    }

    /// Blank lines (also of spaces) and comments (also indented) are skipped
    /// and the lines counted across them;
    /// blanks around fields and names are dropped.
    #[test]
    fn blank_and_comment_lines_are_skipped_and_counted() {
        let text = "\n  \n # indented, comment\n t , p,du_x,du_y,du_z,n_x,n_y,n_z \n\n# c\n 0.1 ,10,0,0,0,0,0,1\n   \n0.2,10,0,0,0,0,0,1";
        let h = parse(text, "h.csv").unwrap();
        assert_eq!(h.lines, vec![7, 9]);
        let e = parse("# only a comment\n  \n", "h.csv").unwrap_err();
        assert_eq!(e.to_string(), "h.csv:0: empty file: no header line");
        let e = parse(
            "t,p,du_x,du_y,du_z,n_x,n_y,n_z\n\n0.1,1,0,0,0,0,1\n",
            "h.csv",
        )
        .unwrap_err();
        assert_eq!(e.to_string(), "h.csv:3: 7 fields, the header has 8");
    }

    /// A file with `\r\n` line ends reads as with `\n`, lines counted alike.
    #[test]
    fn crlf_line_ends_read_as_lf() {
        let h = parse(&GOOD.replace('\n', "\r\n"), "h.csv").unwrap();
        assert_eq!(h.lines, vec![3, 4]);
        assert_eq!(h.times, parse(GOOD, "h.csv").unwrap().times);
    }

    /// A quoted field reads as its text (`"0.1"` as the number 0.1); a
    /// quoted comma stays in its field.
    #[test]
    fn quoted_fields_read_as_their_text() {
        let text = "\"t\",p,du_x,du_y,du_z,n_x,n_y,n_z\n\"0.1\",10,0,0,0,0,0,1\n";
        assert_eq!(parse(text, "h.csv").unwrap().times, vec![0.1]);
        let text = "t,p,du_x,du_y,du_z,n_x,n_y,n_z\n0.1,\"1,5\",0,0,0,0,0,1\n";
        let e = parse(text, "h.csv").unwrap_err().to_string();
        assert_eq!(e, "h.csv:2: column `p`: `1,5` is not a number");
    }

    #[test]
    fn spin_column_gives_skew_velocity_gradient_and_accumulated_f() {
        let text = "t,p,du_x,du_y,du_z,n_x,n_y,n_z,w_x,w_y,w_z\n0.5,1,0,0,0,0,0,1,0,0,2\n";
        let h = parse(text, "h.csv").unwrap();
        let k = &h.steps[0].kin;
        assert_eq!(k.vel_grad, skew(&Vec3::new(0.0, 0.0, 2.0)));
        // F accumulated by the Cayley map of a spin is a rotation.
        assert!((k.f_new.transpose() * k.f_new - Mat3::identity()).norm() < 1e-14);
    }
}
