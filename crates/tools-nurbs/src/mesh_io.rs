//! Reading triangle meshes from STL (ASCII and binary) and OBJ files (polygons fan-triangulated).

use crate::error::NurbsError;
use plugins_api::Vec3;
use std::path::Path;

/// A raw triangle soup or indexed mesh as read (not yet welded).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions (mm).
    pub vertices: Vec<Vec3>,
    /// Triangles as vertex indices, counter-clockwise seen from the normal side.
    pub triangles: Vec<[u32; 3]>,
}

fn file_err(path: &Path, message: String) -> NurbsError {
    NurbsError::File {
        path: path.display().to_string(),
        message,
    }
}

/// Read an `.stl` (ASCII or binary) or `.obj` file, chosen by extension.
pub fn read_mesh(path: &Path) -> Result<TriMesh, NurbsError> {
    let bytes = std::fs::read(path).map_err(|e| file_err(path, format!("cannot read: {e}")))?;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    let mesh = match ext.as_deref() {
        Some("stl") => parse_stl(&bytes).map_err(|m| file_err(path, m))?,
        Some("obj") => {
            let text = std::str::from_utf8(&bytes)
                .map_err(|_| file_err(path, "OBJ file is not UTF-8 text".into()))?;
            parse_obj(text).map_err(|m| file_err(path, m))?
        }
        _ => {
            return Err(file_err(
                path,
                "unknown mesh format (expected .stl or .obj)".into(),
            ));
        }
    };
    if mesh.triangles.is_empty() {
        return Err(file_err(path, "mesh has no triangles".into()));
    }
    Ok(mesh)
}

fn finite(v: [f64; 3], what: &str) -> Result<Vec3, String> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(Vec3::new(v[0], v[1], v[2]))
    } else {
        Err(format!(
            "{what}: vertex ({}, {}, {}) mm is not finite",
            v[0], v[1], v[2]
        ))
    }
}

/// Parse STL bytes (binary when the size matches the binary layout, ASCII otherwise).
pub fn parse_stl(bytes: &[u8]) -> Result<TriMesh, String> {
    if bytes.len() >= 84 {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if bytes.len() == 84 + 50 * n {
            let mut m = TriMesh::default();
            for t in 0..n {
                let base = 84 + 50 * t + 12;
                for k in 0..3 {
                    let mut v = [0.0; 3];
                    for (c, vc) in v.iter_mut().enumerate() {
                        let o = base + 12 * k + 4 * c;
                        *vc = f32::from_le_bytes([
                            bytes[o],
                            bytes[o + 1],
                            bytes[o + 2],
                            bytes[o + 3],
                        ]) as f64;
                    }
                    m.vertices.push(finite(v, &format!("triangle {t}"))?);
                }
                let i = 3 * t as u32;
                m.triangles.push([i, i + 1, i + 2]);
            }
            return Ok(m);
        }
    }
    let text = std::str::from_utf8(bytes)
        .map_err(|_| "neither binary STL (size mismatch) nor ASCII text".to_string())?;
    let mut m = TriMesh::default();
    let mut pending = Vec::new();
    for (ln, line) in text.lines().enumerate() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("vertex") => {
                let mut v = [0.0; 3];
                for c in &mut v {
                    *c = it
                        .next()
                        .and_then(|s| s.parse().ok())
                        .ok_or(format!("line {}: `vertex` needs three numbers", ln + 1))?;
                }
                pending.push(finite(v, &format!("line {}", ln + 1))?);
            }
            Some("endloop") => {
                if pending.len() != 3 {
                    return Err(format!(
                        "line {}: facet with {} vertices (expected 3)",
                        ln + 1,
                        pending.len()
                    ));
                }
                let i = m.vertices.len() as u32;
                m.vertices.append(&mut pending);
                m.triangles.push([i, i + 1, i + 2]);
            }
            _ => {}
        }
    }
    Ok(m)
}

/// Parse OBJ text: `v x y z` and `f a b c …` (indices `a`, `a/t`, `a/t/n`, `a//n`, negative = relative).
pub fn parse_obj(text: &str) -> Result<TriMesh, String> {
    let mut m = TriMesh::default();
    for (ln, line) in text.lines().enumerate() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let mut v = [0.0; 3];
                for c in &mut v {
                    *c = it
                        .next()
                        .and_then(|s| s.parse().ok())
                        .ok_or(format!("line {}: `v` needs three numbers", ln + 1))?;
                }
                m.vertices.push(finite(v, &format!("line {}", ln + 1))?);
            }
            Some("f") => {
                let mut idx = Vec::new();
                for tok in it {
                    let first = tok.split('/').next().unwrap_or("");
                    let k: i64 = first
                        .parse()
                        .map_err(|_| format!("line {}: bad face index `{tok}`", ln + 1))?;
                    let n = m.vertices.len() as i64;
                    let i = if k < 0 { n + k } else { k - 1 };
                    if i < 0 || i >= n {
                        return Err(format!("line {}: face index {k} outside 1..={n}", ln + 1));
                    }
                    idx.push(i as u32);
                }
                if idx.len() < 3 {
                    return Err(format!("line {}: face with {} vertices", ln + 1, idx.len()));
                }
                for k in 1..idx.len() - 1 {
                    m.triangles.push([idx[0], idx[k], idx[k + 1]]);
                }
            }
            _ => {}
        }
    }
    Ok(m)
}
