//! `formsim tools`: export a tools spec to VTU/OBJ, project a CSV of points on one tool.

use crate::output::csv_text::CsvText;
use plugins_api::{ToolError, ToolSurface, Vec3};
use std::path::{Path, PathBuf};
use tools_nurbs::NurbsError;
use tools_nurbs::export::{tessellate, write_obj, write_vtu};
use tools_nurbs::spec::{Tool, load};

/// What can go wrong in `formsim tools`; each message names the file.
#[derive(Debug, thiserror::Error)]
pub enum ToolsError {
    /// The tools spec does not load, or an export file cannot be written.
    #[error(transparent)]
    Spec(#[from] NurbsError),
    /// The output directory cannot be created.
    #[error("{path}: cannot create: {source}")]
    CreateDir {
        /// The directory.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The points file cannot be read.
    #[error("{path}: cannot read: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// Why it was not read.
        source: plugins_api::input_file::InputFileError,
    },
    /// The points file has no header.
    #[error("{path}: empty file (expected a header x,y,z)")]
    EmptyFile {
        /// The file.
        path: PathBuf,
    },
    /// The points file is not readable as CSV (a quoted field runs over a
    /// line end).
    #[error("{path} line {line}: {message}")]
    Csv {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// The header lacks a coordinate column.
    #[error("{path}: missing column `{column}` (header: {header})")]
    MissingColumn {
        /// The file.
        path: PathBuf,
        /// `x`, `y` or `z`.
        column: &'static str,
        /// The header's names, trimmed, comma-separated.
        header: String,
    },
    /// A line lacks a coordinate.
    #[error("{path} line {line}: missing value for `{column}`")]
    MissingValue {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// `x`, `y` or `z`.
        column: &'static str,
    },
    /// A coordinate is not a number.
    #[error("{path} line {line}: {column} = `{raw}` is not a number")]
    NotANumber {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// `x`, `y` or `z`.
        column: &'static str,
        /// The text found.
        raw: String,
    },
    /// A coordinate is infinite or NaN.
    #[error("{path} line {line}: {column} = {value} mm is not finite")]
    NotFinite {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// `x`, `y` or `z`.
        column: &'static str,
        /// The value (mm).
        value: f64,
    },
    /// No tool of that name in the spec.
    #[error("unknown tool `{name}` in {spec}; tools: {known}")]
    UnknownTool {
        /// The name asked for.
        name: String,
        /// The tools spec.
        spec: PathBuf,
        /// The spec's tool names, comma-separated.
        known: String,
    },
    /// A point cannot be projected on the tool.
    #[error(transparent)]
    Projection(#[from] ToolError),
    /// The output CSV cannot be written.
    #[error("{path}: cannot write: {source}")]
    Write {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
}

/// Build every tool of `spec` and write `DIR/NAME.vtu` and `DIR/NAME.obj`; returns the files written.
///
/// # Errors
/// The spec does not load, or a file cannot be written.
pub fn export(spec: &Path, out: &Path) -> Result<Vec<String>, ToolsError> {
    let tools = load(spec)?;
    std::fs::create_dir_all(out).map_err(|source| ToolsError::CreateDir {
        path: out.to_path_buf(),
        source,
    })?;
    let mut written = Vec::new();
    for tool in &tools {
        let t = tessellate(tool);
        let vtu = out.join(format!("{}.vtu", tool.name()));
        let obj = out.join(format!("{}.obj", tool.name()));
        write_vtu(&vtu, &t)?;
        write_obj(&obj, &t, tool.name())?;
        written.push(vtu.display().to_string());
        written.push(obj.display().to_string());
    }
    Ok(written)
}

/// Read `x,y,z` columns (any order; other columns ignored) from a CSV file
/// (read by the `csv` crate: fields may be quoted, blank lines are skipped).
///
/// # Errors
/// The file cannot be read, has no header or a coordinate column missing,
/// or a coordinate is missing, not a number or not finite.
pub fn read_points(path: &Path) -> Result<Vec<Vec3>, ToolsError> {
    let file = || path.to_path_buf();
    let text = plugins_api::input_file::read_text(path, plugins_api::input_file::TEXT_LIMIT)
        .map_err(|source| ToolsError::Read {
            path: file(),
            source,
        })?;
    let mut records = crate::csv_records::records(&text, false).map(|r| {
        r.map_err(|(line, message)| ToolsError::Csv {
            path: file(),
            line,
            message,
        })
    });
    let (_, header) = records
        .next()
        .transpose()?
        .ok_or_else(|| ToolsError::EmptyFile { path: file() })?;
    let column = |name: &'static str| {
        header
            .iter()
            .position(|c| c == name)
            .ok_or_else(|| ToolsError::MissingColumn {
                path: file(),
                column: name,
                header: header.iter().collect::<Vec<_>>().join(","),
            })
    };
    let idx = [column("x")?, column("y")?, column("z")?];
    let mut points = Vec::new();
    for record in records {
        let (line, vals) = record?;
        let mut p = [0.0; 3];
        for (k, name) in ["x", "y", "z"].into_iter().enumerate() {
            let raw = vals.get(idx[k]).ok_or_else(|| ToolsError::MissingValue {
                path: file(),
                line,
                column: name,
            })?;
            let v: f64 = raw.parse().map_err(|_| ToolsError::NotANumber {
                path: file(),
                line,
                column: name,
                raw: raw.to_string(),
            })?;
            if !v.is_finite() {
                return Err(ToolsError::NotFinite {
                    path: file(),
                    line,
                    column: name,
                    value: v,
                });
            }
            p[k] = v;
        }
        points.push(Vec3::from(p));
    }
    Ok(points)
}

/// Project the points of `points_csv` on tool `name` of `spec` and write `out_csv`
/// (`px,py,pz,nx,ny,nz,distance,k1,k2,patch,u,v`); returns the number of points.
///
/// # Errors
/// The spec does not load or has no tool `name`, the points cannot be read
/// ([`read_points`]) or projected, or `out_csv` cannot be written.
pub fn project(
    spec: &Path,
    name: &str,
    points_csv: &Path,
    out_csv: &Path,
) -> Result<usize, ToolsError> {
    let tools = load(spec)?;
    let tool: &Tool = tools.iter().find(|t| t.name() == name).ok_or_else(|| {
        let known: Vec<&str> = tools.iter().map(|t| t.name()).collect();
        ToolsError::UnknownTool {
            name: name.to_string(),
            spec: spec.to_path_buf(),
            known: known.join(", "),
        }
    })?;
    let points = read_points(points_csv)?;
    let mut out = Vec::with_capacity(points.len());
    for x in &points {
        out.push(tool.project(x, None)?);
    }
    let write = |source| ToolsError::Write {
        path: out_csv.to_path_buf(),
        source,
    };
    let mut csv = CsvText::new();
    csv.record([
        "px", "py", "pz", "nx", "ny", "nz", "distance", "k1", "k2", "patch", "u", "v",
    ])
    .map_err(write)?;
    for p in &out {
        let mut row = [
            p.point.x, p.point.y, p.point.z, p.normal.x, p.normal.y, p.normal.z, p.distance, p.k1,
            p.k2,
        ]
        .map(|v| v.to_string())
        .to_vec();
        row.extend([p.patch.to_string(), p.u.to_string(), p.v.to_string()]);
        csv.record(&row).map_err(write)?;
    }
    csv.write_to(out_csv).map_err(write)?;
    Ok(out.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn points(text: &str) -> Result<Vec<Vec3>, ToolsError> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.csv");
        std::fs::write(&path, text).unwrap();
        read_points(&path)
    }

    /// A quoted coordinate reads as its number (`"2"` as 2), also in a
    /// `\r\n` file.
    #[test]
    fn quoted_coordinates_read_as_numbers() {
        let p = points("id,\"x\",y,z\r\n\"a, b\",1,\"2\",3\r\n").unwrap();
        assert_eq!(p, vec![Vec3::new(1.0, 2.0, 3.0)]);
    }

    /// Blank lines are skipped and counted: an error names the line of the
    /// bad value; a missing column shows the header's names.
    #[test]
    fn errors_name_the_line_across_blank_lines() {
        let e = points("\n x , y ,z\n\n  \n1,2,3\n4,,6\n").unwrap_err();
        assert!(
            e.to_string()
                .ends_with("p.csv line 6: y = `` is not a number"),
            "{e}"
        );
        let e = points("x, y\n1,2\n").unwrap_err();
        assert!(
            e.to_string().ends_with("missing column `z` (header: x,y)"),
            "{e}"
        );
        let e = points("x,y,z\n1,2\n").unwrap_err();
        assert!(
            e.to_string()
                .ends_with("p.csv line 2: missing value for `z`"),
            "{e}"
        );
        let e = points("x,y,z\n1,2,3\n1,\"2,3\n4,5,6\n").unwrap_err();
        assert!(
            e.to_string().contains("p.csv line 3: a quoted field"),
            "{e}"
        );
    }
}
