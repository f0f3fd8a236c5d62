//! `formsim tools`: export a tools spec to VTU/OBJ, project a CSV of points on one tool.

use plugins_api::{ToolSurface, Vec3};
use std::fmt::Write as _;
use std::path::Path;
use tools_nurbs::export::{tessellate, write_obj, write_vtu};
use tools_nurbs::spec::{Tool, load};

/// Build every tool of `spec` and write `DIR/NAME.vtu` and `DIR/NAME.obj`; returns the files written.
pub fn export(spec: &Path, out: &Path) -> Result<Vec<String>, String> {
    let tools = load(spec).map_err(|e| e.to_string())?;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: cannot create: {e}", out.display()))?;
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

/// Read `x,y,z` columns (any order; other columns ignored) from a CSV file.
pub fn read_points(path: &Path) -> Result<Vec<Vec3>, String> {
    let file = path.display();
    let text = std::fs::read_to_string(path).map_err(|e| format!("{file}: cannot read: {e}"))?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let (_, header) = lines
        .next()
        .ok_or(format!("{file}: empty file (expected a header x,y,z)"))?;
    let cols: Vec<&str> = header.split(',').map(str::trim).collect();
    let mut idx = [0usize; 3];
    for (k, name) in ["x", "y", "z"].iter().enumerate() {
        idx[k] = cols.iter().position(|c| c == name).ok_or(format!(
            "{file}: missing column `{name}` (header: {header})"
        ))?;
    }
    let mut points = Vec::new();
    for (ln, line) in lines {
        let vals: Vec<&str> = line.split(',').map(str::trim).collect();
        let mut p = [0.0; 3];
        for (k, name) in ["x", "y", "z"].iter().enumerate() {
            let raw = vals.get(idx[k]).ok_or(format!(
                "{file} line {}: missing value for `{name}`",
                ln + 1
            ))?;
            let v: f64 = raw
                .parse()
                .map_err(|_| format!("{file} line {}: {name} = `{raw}` is not a number", ln + 1))?;
            if !v.is_finite() {
                return Err(format!(
                    "{file} line {}: {name} = {v} mm is not finite",
                    ln + 1
                ));
            }
            p[k] = v;
        }
        points.push(Vec3::from(p));
    }
    Ok(points)
}

/// Project the points of `points_csv` on tool `name` of `spec` and write `out_csv`
/// (`px,py,pz,nx,ny,nz,distance,k1,k2,patch,u,v`); returns the number of points.
pub fn project(
    spec: &Path,
    name: &str,
    points_csv: &Path,
    out_csv: &Path,
) -> Result<usize, String> {
    let tools = load(spec).map_err(|e| e.to_string())?;
    let tool: &Tool = tools.iter().find(|t| t.name() == name).ok_or_else(|| {
        let known: Vec<&str> = tools.iter().map(|t| t.name()).collect();
        format!(
            "unknown tool `{name}` in {}; tools: {}",
            spec.display(),
            known.join(", ")
        )
    })?;
    let points = read_points(points_csv)?;
    let mut out = Vec::with_capacity(points.len());
    for x in &points {
        out.push(tool.project(x, None).map_err(|e| e.to_string())?);
    }
    let mut s = String::from("px,py,pz,nx,ny,nz,distance,k1,k2,patch,u,v\n");
    for p in &out {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{}",
            p.point.x,
            p.point.y,
            p.point.z,
            p.normal.x,
            p.normal.y,
            p.normal.z,
            p.distance,
            p.k1,
            p.k2,
            p.patch,
            p.u,
            p.v
        );
    }
    std::fs::write(out_csv, s).map_err(|e| format!("{}: cannot write: {e}", out_csv.display()))?;
    Ok(out.len())
}
