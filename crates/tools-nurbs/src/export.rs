//! Export of tools for viewing: tessellation into quads/triangles, ASCII VTU (ParaView) and OBJ writers.
//!
//! The VTU file is written by hand (ASCII `UnstructuredGrid`, one piece) with
//! point data `normal` (blank side), `k1`, `k2` (1/mm) and cell data `patch`;
//! tests read it back with vtkio's XML reader.

use crate::error::NurbsError;
use crate::faceted::FacetedTool;
use crate::nurbs_tool::NurbsTool;
use crate::spec::Tool;
use plugins_api::{ToolSurface, Vec3};
use std::fmt::Write as _;
use std::path::Path;

/// A tool surface as polygons in the global frame (at the tool's current pose).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Tessellation {
    /// Vertex positions (mm).
    pub points: Vec<Vec3>,
    /// Blank-side unit normals at the vertices.
    pub normals: Vec<Vec3>,
    /// Principal curvatures at the vertices (1/mm).
    pub k: Vec<[f64; 2]>,
    /// Polygons (3 or 4 vertex indices).
    pub cells: Vec<Vec<u32>>,
    /// Patch (or facet) index of each polygon.
    pub patch: Vec<u32>,
}

/// Quads per knot span along each direction in a NURBS tessellation.
pub const SPAN_DIVISIONS: usize = 8;

/// Tessellate a NURBS tool: every knot span into a grid of quads.
pub fn tessellate_nurbs(tool: &NurbsTool) -> Tessellation {
    let mut t = Tessellation::default();
    let pose = tool.pose();
    for (pi, p) in tool.patches().iter().enumerate() {
        for &(u0, u1) in &p.surface.spans_u() {
            for &(v0, v1) in &p.surface.spans_v() {
                let base = t.points.len() as u32;
                let m = SPAN_DIVISIONS;
                for a in 0..=m {
                    for b in 0..=m {
                        let u = u0 + (u1 - u0) * a as f64 / m as f64;
                        let v = v0 + (v1 - v0) * b as f64 / m as f64;
                        let d = p.surface.eval(u, v);
                        let g = crate::differential::local_geometry(&d, p.sign);
                        t.points.push(pose.to_global(&d.s));
                        t.normals.push(pose.rotation * g.normal);
                        t.k.push([g.k1, g.k2]);
                    }
                }
                let id = |a: usize, b: usize| base + (a * (m + 1) + b) as u32;
                for a in 0..m {
                    for b in 0..m {
                        // Counter-clockwise seen from the blank side.
                        let mut q = vec![id(a, b), id(a + 1, b), id(a + 1, b + 1), id(a, b + 1)];
                        if p.sign < 0.0 {
                            q.reverse();
                        }
                        t.cells.push(q);
                        t.patch.push(pi as u32);
                    }
                }
            }
        }
    }
    t
}

/// A faceted tool's own triangles with its smoothed vertex normals (curvature columns zero).
pub fn tessellate_faceted(tool: &FacetedTool) -> Tessellation {
    let pose = tool.pose();
    let (v, tri) = tool.mesh();
    Tessellation {
        points: v.iter().map(|p| pose.to_global(p)).collect(),
        normals: tool
            .vertex_normals()
            .iter()
            .map(|n| pose.rotation * n)
            .collect(),
        k: vec![[0.0, 0.0]; v.len()],
        cells: tri.iter().map(|t| t.to_vec()).collect(),
        patch: (0..tri.len() as u32).collect(),
    }
}

/// Tessellate any tool of a spec.
pub fn tessellate(tool: &Tool) -> Tessellation {
    match tool {
        Tool::Nurbs(t) => tessellate_nurbs(t),
        Tool::Faceted(t) => tessellate_faceted(t),
    }
}

fn io(path: &Path, e: std::io::Error) -> NurbsError {
    NurbsError::Write {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// Write a tessellation as an ASCII VTU file.
pub fn write_vtu(path: &Path, t: &Tessellation) -> Result<(), NurbsError> {
    let mut s = String::new();
    let _ = writeln!(s, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        s,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">"
    );
    let _ = writeln!(s, "  <UnstructuredGrid>");
    let _ = writeln!(
        s,
        "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        t.points.len(),
        t.cells.len()
    );
    let vec3 = |s: &mut String, name: &str, v: &[Vec3]| {
        let _ = writeln!(
            s,
            "        <DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"3\" format=\"ascii\">"
        );
        for p in v {
            let _ = writeln!(s, "          {:e} {:e} {:e}", p.x, p.y, p.z);
        }
        let _ = writeln!(s, "        </DataArray>");
    };
    let _ = writeln!(s, "      <PointData Normals=\"normal\">");
    vec3(&mut s, "normal", &t.normals);
    for (k, name) in ["k1", "k2"].iter().enumerate() {
        let _ = writeln!(
            s,
            "        <DataArray type=\"Float64\" Name=\"{name}\" format=\"ascii\">"
        );
        for v in &t.k {
            let _ = writeln!(s, "          {:e}", v[k]);
        }
        let _ = writeln!(s, "        </DataArray>");
    }
    let _ = writeln!(s, "      </PointData>");
    let _ = writeln!(s, "      <CellData Scalars=\"patch\">");
    let _ = writeln!(
        s,
        "        <DataArray type=\"Int32\" Name=\"patch\" format=\"ascii\">"
    );
    for p in &t.patch {
        let _ = writeln!(s, "          {p}");
    }
    let _ = writeln!(s, "        </DataArray>");
    let _ = writeln!(s, "      </CellData>");
    let _ = writeln!(s, "      <Points>");
    vec3(&mut s, "Points", &t.points);
    let _ = writeln!(s, "      </Points>");
    let _ = writeln!(s, "      <Cells>");
    let _ = writeln!(
        s,
        "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">"
    );
    for c in &t.cells {
        let ids: Vec<String> = c.iter().map(|i| i.to_string()).collect();
        let _ = writeln!(s, "          {}", ids.join(" "));
    }
    let _ = writeln!(s, "        </DataArray>");
    let _ = writeln!(
        s,
        "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">"
    );
    let mut off = 0;
    for c in &t.cells {
        off += c.len();
        let _ = writeln!(s, "          {off}");
    }
    let _ = writeln!(s, "        </DataArray>");
    let _ = writeln!(
        s,
        "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">"
    );
    for c in &t.cells {
        let _ = writeln!(s, "          {}", if c.len() == 4 { 9 } else { 5 });
    }
    let _ = writeln!(s, "        </DataArray>");
    let _ = writeln!(s, "      </Cells>");
    let _ = writeln!(s, "    </Piece>");
    let _ = writeln!(s, "  </UnstructuredGrid>");
    let _ = writeln!(s, "</VTKFile>");
    std::fs::write(path, s).map_err(|e| io(path, e))
}

/// Write a tessellation as a Wavefront OBJ file (positions, normals, polygons).
pub fn write_obj(path: &Path, t: &Tessellation, name: &str) -> Result<(), NurbsError> {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# formsim tool `{name}` (mm); normals towards the blank side"
    );
    let _ = writeln!(s, "o {name}");
    for p in &t.points {
        let _ = writeln!(s, "v {:e} {:e} {:e}", p.x, p.y, p.z);
    }
    for n in &t.normals {
        let _ = writeln!(s, "vn {:e} {:e} {:e}", n.x, n.y, n.z);
    }
    for c in &t.cells {
        let ids: Vec<String> = c.iter().map(|i| format!("{0}//{0}", i + 1)).collect();
        let _ = writeln!(s, "f {}", ids.join(" "));
    }
    std::fs::write(path, s).map_err(|e| io(path, e))
}
