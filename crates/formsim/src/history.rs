//! Reading a prescribed contact-point history (`formsim friction-point --history IN.csv`).
//!
//! Format: comma-separated, one header line naming the columns (any order),
//! `#` comment lines and blank lines ignored. Units: mm, N, MPa, s.
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
    let text = std::fs::read_to_string(path).map_err(|e| HistoryError {
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
    let err = |line: usize, message: String| HistoryError {
        file: file.to_string(),
        line,
        message,
    };
    let mut rows = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let (header_line, header) = rows
        .next()
        .ok_or_else(|| err(0, "empty file: no header line".into()))?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let known = known_columns();
    let mut index: HashMap<&str, usize> = HashMap::new();
    for (i, name) in names.iter().enumerate() {
        if !known.iter().any(|k| k == name) {
            return Err(err(
                header_line,
                format!("unknown column `{name}`; known: {}", known.join(",")),
            ));
        }
        if index.insert(name, i).is_some() {
            return Err(err(header_line, format!("column `{name}` appears twice")));
        }
    }
    for col in REQUIRED {
        if !index.contains_key(col) {
            return Err(err(
                header_line,
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
            return Err(err(
                header_line,
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

    let mut out = History {
        times: Vec::new(),
        lines: Vec::new(),
        steps: Vec::new(),
        present,
    };
    let mut t_prev = 0.0;
    let mut n_prev: Option<Vec3> = None;
    let mut f_prev = Mat3::identity();
    for (line, row) in rows {
        let fields: Vec<&str> = row.split(',').map(str::trim).collect();
        if fields.len() != names.len() {
            return Err(err(
                line,
                format!("{} fields, the header has {}", fields.len(), names.len()),
            ));
        }
        let get = |col: &str| -> Result<f64, HistoryError> {
            let raw = fields[index[col]];
            let v: f64 = raw
                .parse()
                .map_err(|_| err(line, format!("column `{col}`: `{raw}` is not a number")))?;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(err(line, format!("column `{col}`: {v} is not finite")))
            }
        };
        let get_vec = |p: &str| -> Result<Vec3, HistoryError> {
            Ok(Vec3::new(
                get(&format!("{p}_x"))?,
                get(&format!("{p}_y"))?,
                get(&format!("{p}_z"))?,
            ))
        };
        let get_mat = |p: &str| -> Result<Mat3, HistoryError> {
            let mut m = Mat3::zeros();
            for (k, ij) in MATRIX.iter().enumerate() {
                m[(k / 3, k % 3)] = get(&format!("{p}_{ij}"))?;
            }
            Ok(m)
        };
        let t = get("t")?;
        if t <= t_prev {
            return Err(err(
                line,
                format!(
                    "column `t`: time {t} s must exceed the previous {t_prev} s (strictly increasing, first > 0)"
                ),
            ));
        }
        let dt = t - t_prev;
        let p = get("p")?;
        if p < 0.0 {
            return Err(err(
                line,
                format!("column `p`: pressure {p} MPa must be >= 0 (0 = open contact)"),
            ));
        }
        let du = get_vec("du")?;
        let n_raw = get_vec("n")?;
        let len = n_raw.norm();
        if (len - 1.0).abs() > 1e-3 {
            return Err(err(
                line,
                format!("columns n_x,n_y,n_z: |n| = {len} is not a unit normal"),
            ));
        }
        let n = n_raw / len;
        let vel_grad = if present.vel_grad {
            get_mat("l")?
        } else if present.spin {
            skew(&get_vec("w")?)
        } else {
            Mat3::zeros()
        };
        let f_new = if present.def_grad {
            let f = get_mat("f")?;
            if f.determinant() <= 0.0 {
                return Err(err(
                    line,
                    format!(
                        "columns f_11..f_33: det F = {} must be > 0",
                        f.determinant()
                    ),
                ));
            }
            f
        } else {
            cayley(&(vel_grad * dt)) * f_prev
        };
        let tool_rotation = if present.tool_rotation {
            rotation_from_vector(&get_vec("r")?)
        } else {
            Mat3::identity()
        };
        let kin = StepKinematics {
            dt,
            n_old: n_prev.unwrap_or(n),
            n_new: n,
            tool_rotation,
            vel_grad,
            f_old: f_prev,
            f_new,
        };
        let mut step = StepInput::new(p, du, kin);
        if present.flow_stress {
            step.flow_stress = get("sigma_y")?;
        }
        if present.temperature {
            step.temperature = get("temperature")?;
        }
        out.times.push(t);
        out.lines.push(line);
        out.steps.push(step);
        t_prev = t;
        n_prev = Some(n);
        f_prev = f_new;
    }
    if out.steps.is_empty() {
        return Err(err(header_line, "no data rows after the header".into()));
    }
    Ok(out)
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
