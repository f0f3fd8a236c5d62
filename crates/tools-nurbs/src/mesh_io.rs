//! Reading triangle meshes: STL (ASCII and binary) through `stl_io`, OBJ through
//! `tobj` (polygons fan-triangulated); both checked here for what the crates
//! let through (non-finite coordinates, faces of fewer than three vertices).

use crate::error::NurbsError;
use plugins_api::Vec3;
use std::borrow::Cow;
use std::io::{BufRead, Read};
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
    let bytes = plugins_api::input_file::read_bytes(path, plugins_api::input_file::MESH_LIMIT)
        .map_err(|e| file_err(path, format!("cannot read: {e}")))?;
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

/// The bytes of a binary STL: 80 header bytes, a little-endian triangle
/// count, 50 bytes per triangle.
const STL_HEADER: usize = 84;
const STL_TRIANGLE: usize = 50;

/// Parse STL bytes: binary when the size matches the binary layout (the
/// header's triangle count times 50 bytes after 84), ASCII when the text starts
/// with `solid`. The triangles are kept as a soup (three vertices each, in
/// file order); binary coordinates must be finite (ASCII ones are checked by
/// `stl_io`). ASCII values are read as `f32`, the precision of the format.
pub fn parse_stl(bytes: &[u8]) -> Result<TriMesh, String> {
    let (input, binary) = stl_input(bytes)?;
    let mut cursor = std::io::Cursor::new(input.as_ref());
    let reader = stl_io::create_stl_reader(&mut cursor).map_err(|e| format!("STL: {e}"))?;
    let mut m = TriMesh::default();
    for (t, tri) in reader.enumerate() {
        let tri = tri.map_err(|e| {
            let what = if binary {
                "binary STL, triangle"
            } else {
                "ASCII STL, facet"
            };
            format!("{what} {}: {e}", t + 1)
        })?;
        for v in tri.vertices {
            let v = [v[0] as f64, v[1] as f64, v[2] as f64];
            m.vertices.push(finite(v, &format!("triangle {}", t + 1))?);
        }
        let i = 3 * t as u32;
        m.triangles.push([i, i + 1, i + 2]);
    }
    Ok(m)
}

/// The bytes to hand `stl_io`, and whether they are binary STL. `stl_io`
/// takes a file for ASCII when its first line starts with `solid ` and for
/// binary otherwise, whatever its size; here the size decides first, and a
/// bare `solid` line (valid ASCII STL) is accepted too.
fn stl_input(bytes: &[u8]) -> Result<(Cow<'_, [u8]>, bool), String> {
    if bytes.is_empty() {
        return Err("empty file".into());
    }
    let count = (bytes.len() >= STL_HEADER)
        .then(|| u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64);
    let size = count.map(|n| n * STL_TRIANGLE as u64 + STL_HEADER as u64);
    if size == Some(bytes.len() as u64) {
        // Some exporters write `solid` into the binary header too: the header
        // carries nothing, so blank it for stl_io's test.
        let mut b = bytes.to_vec();
        b[..80].fill(b' ');
        return Ok((Cow::Owned(b), true));
    }
    if let Some(rest) = bytes.strip_prefix(b"solid") {
        return match rest.first() {
            Some(b' ') => Ok((Cow::Borrowed(bytes), false)),
            Some(b'\r' | b'\n' | b'\t') | None => {
                Ok((Cow::Owned([b"solid ", rest].concat()), false))
            }
            Some(_) => Err("ASCII STL: the first line is not `solid [name]`".into()),
        };
    }
    Err(match (count, size) {
        (Some(n), Some(size)) => format!(
            "neither ASCII STL (no `solid` line first) nor binary STL: the header counts {n} triangles, \
             {size} bytes, the file has {} (truncated or padded)",
            bytes.len()
        ),
        _ => format!(
            "neither ASCII STL (no `solid` line first) nor binary STL ({} bytes, less than the 84-byte header)",
            bytes.len()
        ),
    })
}

/// OBJ statements dropped before `tobj` reads the text (the line becomes
/// empty, so line numbers stay): `l` polylines, which `tobj` would read as
/// faces; texture and normal data, which a rigid tool does not use and whose
/// relative indices overflow in `tobj`'s index arithmetic; materials.
const OBJ_UNUSED: [&str; 6] = ["l", "vt", "vn", "vp", "mtllib", "usemtl"];

/// A reader over text that counts the lines it hands out, to place the
/// errors of `tobj`, which name no line.
struct LineCounter<'a> {
    rest: &'a [u8],
    /// `\n` handed out so far.
    newlines: usize,
    /// Whether the last byte handed out ended a line.
    at_line_start: bool,
}

impl LineCounter<'_> {
    /// 1-based number of the line read last.
    fn line(&self) -> usize {
        self.newlines + usize::from(!self.at_line_start)
    }
}

impl Read for LineCounter<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = buf.len().min(self.rest.len());
        buf[..n].copy_from_slice(&self.rest[..n]);
        self.consume(n);
        Ok(n)
    }
}

impl BufRead for LineCounter<'_> {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        Ok(self.rest)
    }

    fn consume(&mut self, n: usize) {
        let (done, rest) = self.rest.split_at(n);
        self.newlines += done.iter().filter(|&&c| c == b'\n').count();
        if let Some(&last) = done.last() {
            self.at_line_start = last == b'\n';
        }
        self.rest = rest;
    }
}

/// Parse OBJ text with `tobj`: `v x y z [w]` and `f a b c …` (indices `a`,
/// `a/t`, `a/t/n`, `a//n`, negative = relative), polygons fan-triangulated
/// (`a b c`, `a c d`, …, the winding kept). Groups and objects are joined into
/// one mesh; vertices no face uses are left out.
pub fn parse_obj(text: &str) -> Result<TriMesh, String> {
    let mut kept = String::with_capacity(text.len());
    for line in text.split_inclusive('\n') {
        let first = line.split_whitespace().next().unwrap_or("");
        if OBJ_UNUSED.contains(&first) {
            kept.push_str(if line.ends_with('\n') { "\n" } else { "" });
        } else {
            kept.push_str(line);
        }
    }
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        // Kept, to be refused below: a face of one or two vertices.
        ignore_points: false,
        ignore_lines: false,
    };
    let mut reader = LineCounter {
        rest: kept.as_bytes(),
        newlines: 0,
        at_line_start: true,
    };
    let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| obj_error(e, reader.line(), text))?;
    let mut m = TriMesh::default();
    for model in models {
        let offset = m.vertices.len() as u32;
        for p in model.mesh.positions.chunks_exact(3) {
            m.vertices
                .push(finite([p[0], p[1], p[2]], "a face's vertex")?);
        }
        for t in model.mesh.indices.chunks_exact(3) {
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                return Err(format!(
                    "triangle {} (faces fan-triangulated in file order) repeats a vertex: \
                     a face needs three different vertices",
                    m.triangles.len() + 1
                ));
            }
            m.triangles
                .push([t[0] + offset, t[1] + offset, t[2] + offset]);
        }
    }
    Ok(m)
}

/// A one-line message for an error of `tobj`, with the line where `tobj`
/// stopped when the error is about that line.
fn obj_error(e: tobj::LoadError, line: usize, text: &str) -> String {
    use tobj::LoadError as E;
    let n = text
        .lines()
        .filter(|l| l.split_whitespace().next() == Some("v"))
        .count();
    match e {
        E::PositionParseError | E::ScalingByZeroError | E::ColorParseError => {
            format!("line {line}: `v` needs three numbers (and an optional w ≠ 0): {e}")
        }
        E::FaceParseError => format!("line {line}: bad face (`f` needs vertex indices): {e}"),
        E::FaceVertexOutOfBounds => format!(
            "a face index is outside the {n} vertices (1..={n}, or -1 back to the first `v` before the face)"
        ),
        E::InvalidPolygon => "a face `f` has no vertex indices".into(),
        _ => format!("line {line}: {e}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The corners of each triangle, by position.
    fn corners(m: &TriMesh) -> Vec<[[f64; 3]; 3]> {
        let p = |i: u32| {
            let v = m.vertices[i as usize];
            [v.x, v.y, v.z]
        };
        m.triangles
            .iter()
            .map(|t| [p(t[0]), p(t[1]), p(t[2])])
            .collect()
    }

    const POLYGONS: &str = "\
# a quad, a pentagon and a triangle, in four index spellings, over two groups
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0
v 2.5 1 0
vt 0 0
vn 0 0 1
o first
f 1 2 3 4
g second
f 2/1 5/1 6/1/1 3//1 -3
l 1 2 3
f -6 -5 -4
";

    /// tobj's triangulation is the fan `a b c`, `a c d`, … in file order (as
    /// the reader before it), the winding kept; `l` polylines are no faces.
    #[test]
    fn obj_polygons_are_fans_in_file_order() {
        let m = parse_obj(POLYGONS).unwrap();
        let v = |x: f64, y: f64| [x, y, 0.0];
        let (a, b, c, d) = (v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(0.0, 1.0));
        let (e, f) = (v(2.0, 0.0), v(2.5, 1.0));
        let fans = [
            [a, b, c],
            [a, c, d],
            [b, e, f],
            [b, f, c],
            [b, c, d],
            [a, b, c],
        ];
        assert_eq!(corners(&m), fans);
        // Shared corners share an index within a group.
        assert_eq!(m.triangles[0][2], m.triangles[1][1]);
    }

    #[test]
    fn obj_errors_are_one_line_and_name_what_is_wrong() {
        let err = |text: &str| parse_obj(text).unwrap_err();
        let e = err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
        assert!(e.contains("outside the 3 vertices (1..=3"), "{e}");
        let e = err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n");
        assert!(e.contains("outside the 3 vertices"), "{e}");
        let e = err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n");
        assert!(e.contains("outside the 3 vertices"), "{e}");
        let e = err("v 0 0 0\nv 1 x 0\n");
        assert!(e.starts_with("line 2: `v` needs three numbers"), "{e}");
        let e = err("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 a\n");
        assert!(e.starts_with("line 5: bad face"), "{e}");
        let e = err("v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
        assert!(e.contains("vertex (NaN, 1, 0) mm is not finite"), "{e}");
        let e = err("v 0 0 0\nv 1 0 0\nv 1e999 1 0\nf 1 2 3\n");
        assert!(e.contains("vertex (inf, 1, 0) mm is not finite"), "{e}");
        let e = err("v 0 0 0\nv 1 0 0\nf 1 2\n");
        assert!(e.contains("repeats a vertex"), "{e}");
        let e = err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf\n");
        assert!(e.contains("no vertex indices"), "{e}");
        // Relative texture indices far out of range are no overflow (the `vt`
        // data is dropped before tobj reads it).
        let m = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/-9223372036854775808 2/1 3/1\n");
        assert_eq!(m.unwrap().triangles.len(), 1);
        // An unused non-finite vertex is left out with the other unused ones.
        let m = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 0\nf 1 2 3\n").unwrap();
        assert_eq!(m.vertices.len(), 3);
    }

    /// 84-byte header and one 50-byte record per triangle.
    fn binary_stl(header: &[u8], count: u32, tris: &[[f32; 9]]) -> Vec<u8> {
        let mut b = vec![0u8; 80];
        b[..header.len()].copy_from_slice(header);
        b.extend(count.to_le_bytes());
        for t in tris {
            b.extend([0u8; 12]);
            b.extend(t.iter().flat_map(|c| c.to_le_bytes()));
            b.extend([0u8; 2]);
        }
        b
    }

    const TRI: [f32; 9] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];

    #[test]
    fn stl_binary_with_solid_header_and_bare_solid_ascii_read() {
        let b = binary_stl(b"solid exported by some CAD", 2, &[TRI, TRI]);
        let m = parse_stl(&b).unwrap();
        assert_eq!(m.triangles, [[0, 1, 2], [3, 4, 5]]);
        assert_eq!(m.vertices[4], Vec3::new(1.0, 0.0, 0.0));
        let ascii = "solid\r\nfacet normal 0 0 1\r\nouter loop\r\nvertex 0 0 0\r\nvertex 1 0 0\r\n\
                     vertex 0 1 0\r\nendloop\r\nendfacet\r\nendsolid\r\n";
        assert_eq!(parse_stl(ascii.as_bytes()).unwrap(), m_one());
        assert_eq!(
            parse_stl(ascii.replace("solid\r", "solid cup\r").as_bytes()).unwrap(),
            m_one()
        );
    }

    fn m_one() -> TriMesh {
        TriMesh {
            vertices: vec![Vec3::zeros(), Vec3::x(), Vec3::y()],
            triangles: vec![[0, 1, 2]],
        }
    }

    #[test]
    fn stl_errors_are_one_line_and_name_what_is_wrong() {
        assert_eq!(parse_stl(b"").unwrap_err(), "empty file");
        let mut b = binary_stl(b"", 2, &[TRI, TRI]);
        b.truncate(b.len() - 7);
        let e = parse_stl(&b).unwrap_err();
        assert!(
            e.contains("binary STL: the header counts 2 triangles, 184 bytes, the file has 177"),
            "{e}"
        );
        let e = parse_stl(&[7u8; 40]).unwrap_err();
        assert!(e.contains("40 bytes, less than the 84-byte header"), "{e}");
        let mut nan = TRI;
        nan[4] = f32::NAN;
        let e = parse_stl(&binary_stl(b"", 2, &[TRI, nan])).unwrap_err();
        assert_eq!(e, "triangle 2: vertex (1, NaN, 0) mm is not finite");
        let ascii = "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
                     vertex 0 1 0\nendloop\nendfacet\n";
        let e = parse_stl(ascii.as_bytes()).unwrap_err();
        assert!(e.starts_with("ASCII STL, facet 2: EOF"), "{e}");
        let e = parse_stl(ascii.replace("vertex 1 0 0", "vertex 1 nan 0").as_bytes()).unwrap_err();
        assert!(e.starts_with("ASCII STL, facet 1: expected finite"), "{e}");
        let e =
            parse_stl(ascii.replace("endloop", "vertex 2 2 2\nendloop").as_bytes()).unwrap_err();
        assert!(
            e.starts_with("ASCII STL, facet 1: expected [\"endloop\"]"),
            "{e}"
        );
        assert!(!e.contains('\n'), "{e}");
    }

    /// Every prefix of a valid file, and every one-byte change of it, gives a
    /// mesh or an error, never a panic.
    #[test]
    fn truncated_and_garbled_files_never_panic() {
        let stl = binary_stl(b"", 2, &[TRI, TRI]);
        let ascii = b"solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
                     vertex 0 1 0\nendloop\nendfacet\nendsolid s\n";
        for file in [&stl[..], &ascii[..]] {
            for n in 0..file.len() {
                let _ = parse_stl(&file[..n]);
                let mut g = file.to_vec();
                g[n] ^= 0x5a;
                let _ = parse_stl(&g);
            }
        }
        let obj = POLYGONS.as_bytes();
        for n in 0..obj.len() {
            if let Ok(t) = std::str::from_utf8(&obj[..n]) {
                let _ = parse_obj(t);
            }
            let mut g = obj.to_vec();
            g[n] = b"-0/ 9f\n"[n % 7];
            let _ = parse_obj(std::str::from_utf8(&g).unwrap());
        }
    }
}
