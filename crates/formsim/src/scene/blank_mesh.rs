//! The blank's mesh: generated from `[blank.mesh]` or read from its file,
//! then checked before anything is built on it. A file without shells, an
//! element of zero area or with a repeated node, a non-finite coordinate or
//! a distorted element is refused with the file and the element named by
//! the file's own numbers (a generated mesh names them by 0-based index).

use super::estimate::{self, MeshSize};
use super::schema::MeshSpec;
use super::{LoadedScene, SceneError};
use fem_core::{FemError, Mesh, MeshFile, MeshQuality, Vec3};

/// The file's own numbers of a blank mesh read from a file.
#[derive(Debug, Clone, Default)]
pub struct FileIds {
    /// The file's id of each node, by index.
    pub nodes: Vec<i64>,
    /// The file's id of each element, by index.
    pub elements: Vec<i64>,
}

impl FileIds {
    /// How a message names node `n`: its file id, else its 0-based index.
    pub fn node(ids: Option<&Self>, n: usize) -> i64 {
        ids.and_then(|f| f.nodes.get(n).copied())
            .unwrap_or(n as i64)
    }

    /// How a message names element `e`: its file id, else its 0-based index.
    pub fn element(ids: Option<&Self>, e: usize) -> i64 {
        ids.and_then(|f| f.elements.get(e).copied())
            .unwrap_or(e as i64)
    }

    /// `message` from the engine, which numbers nodes and elements from 0,
    /// with every `node N` and `element N` (and `nodes N, M, …`) renamed to
    /// the file's numbers.
    pub fn rename(ids: Option<&Self>, message: &str) -> String {
        let Some(f) = ids else {
            return message.to_string();
        };
        let mut out = String::with_capacity(message.len());
        let mut rest = message;
        while let Some((at, word, table)) = next_number_word(rest, f) {
            let after = at + word.len();
            out.push_str(&rest[..after]);
            rest = &rest[after..];
            // The list after the word: digits, separated by ", ".
            loop {
                let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
                if digits == 0 {
                    break;
                }
                let n: Option<usize> = rest[..digits].parse().ok();
                match n.and_then(|n| table.get(n)) {
                    Some(id) => out.push_str(&id.to_string()),
                    None => out.push_str(&rest[..digits]),
                }
                rest = &rest[digits..];
                if rest.starts_with(", ") && rest[2..].starts_with(|c: char| c.is_ascii_digit()) {
                    out.push_str(", ");
                    rest = &rest[2..];
                } else {
                    break;
                }
            }
        }
        out.push_str(rest);
        out
    }
}

/// The first `node `, `nodes `, `element ` or `elements ` in `text` that a
/// digit follows: its position, the word and the id table it names.
fn next_number_word<'a>(text: &str, f: &'a FileIds) -> Option<(usize, &'static str, &'a [i64])> {
    let words: [(&'static str, &'a [i64]); 4] = [
        ("nodes ", &f.nodes),
        ("node ", &f.nodes),
        ("elements ", &f.elements),
        ("element ", &f.elements),
    ];
    words
        .iter()
        .filter_map(|(w, t)| {
            text.match_indices(w)
                .find(|(i, _)| text[i + w.len()..].starts_with(|c: char| c.is_ascii_digit()))
                .map(|(i, _)| (i, *w, *t))
        })
        .min_by_key(|(i, w, _)| (*i, std::cmp::Reverse(w.len())))
}

/// The blank mesh of the scene, with its `all` sets, checked, and the
/// file's numbers when it was read from a file.
///
/// # Errors
/// Generator parameters (`blank.mesh`), unreadable or inconsistent files
/// and too large a file mesh (`blank.mesh.path`, with the file and line),
/// bad elements (naming the element and its nodes).
pub fn build_mesh(loaded: &LoadedScene) -> Result<(Mesh, Option<FileIds>), SceneError> {
    let mut ids = None;
    let mut mesh = match &loaded.scene.blank.mesh {
        MeshSpec::File { path, translate } => {
            let file = read_file(loaded, path)?;
            check(&file.mesh, Some(&file))
                .map_err(|m| loaded.key_error("blank.mesh.path", format!("{path}: {m}")))?;
            let est = estimate::estimate(&loaded.scene, MeshSize::of_mesh(&file.mesh));
            estimate::check_size(loaded, &est)?;
            let mut m = file.mesh;
            ids = Some(FileIds {
                nodes: file.node_ids,
                elements: file.element_ids,
            });
            for p in &mut m.nodes {
                *p += Vec3::new(translate[0], translate[1], translate[2]);
            }
            m
        }
        spec => {
            let m = generate(loaded, spec)
                .map_err(|e| loaded.key_error("blank.mesh", e.to_string()))?;
            let what = match spec {
                MeshSpec::Rectangle { .. } => "rectangle",
                _ => "wrapped strip",
            };
            check(&m, None).map_err(|e| loaded.key_error("blank.mesh", format!("{what}: {e}")))?;
            m
        }
    };
    mesh.add_all_sets();
    Ok((mesh, ids))
}

/// Read the `.inp` or `.msh` file `path` (relative to the scene).
fn read_file(loaded: &LoadedScene, path: &str) -> Result<MeshFile, SceneError> {
    let full = loaded.base_dir().join(path);
    let ext = full
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let read = match ext.as_str() {
        "inp" => fem_core::read_inp_numbered(&full),
        "msh" => fem_core::read_msh_numbered(&full),
        _ => {
            return Err(loaded.key_error(
                "blank.mesh.path",
                format!("\"{path}\": expected a .inp or .msh file"),
            ));
        }
    };
    read.map_err(|e| loaded.key_error("blank.mesh.path", e.to_string()))
}

/// The rectangle or wrapped strip of `spec`.
fn generate(loaded: &LoadedScene, spec: &MeshSpec) -> Result<Mesh, FemError> {
    match spec {
        MeshSpec::Rectangle {
            size,
            divisions,
            origin,
        } => {
            let (nx, ny) = divisions.pair();
            let mut m = fem_core::rectangle(size[0], size[1], nx as usize, ny as usize)?;
            for p in &mut m.nodes {
                *p += Vec3::new(origin[0], origin[1], origin[2]);
            }
            Ok(m)
        }
        MeshSpec::WrappedStrip {
            radius,
            width,
            tail,
            angle_deg,
            element_size,
        } => fem_core::wrapped_strip(
            *radius + 0.5 * loaded.scene.blank.thickness,
            *width,
            *tail,
            angle_deg.to_radians(),
            *element_size,
        ),
        MeshSpec::File { .. } => unreachable!("files are read, not generated"),
    }
}

/// How nodes and elements are named in messages: the file's ids, else
/// 0-based indices.
struct Names<'a>(Option<&'a MeshFile>);

impl Names<'_> {
    fn node(&self, n: u32) -> i64 {
        self.0
            .and_then(|f| f.node_ids.get(n as usize).copied())
            .unwrap_or(n as i64)
    }
    fn element(&self, e: usize) -> i64 {
        self.0
            .and_then(|f| f.element_ids.get(e).copied())
            .unwrap_or(e as i64)
    }
    fn nodes_of(&self, q: &[u32; 4]) -> String {
        let ids: Vec<String> = q.iter().map(|&n| self.node(n).to_string()).collect();
        format!("nodes {}", ids.join(", "))
    }
}

/// Why [`check`] refuses a blank mesh; each message names the node or the
/// element (by the file's numbers when it was read, else 0-based indices)
/// and the element's nodes.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The mesh has no shell elements.
    #[error(
        "no shell elements ({nodes} nodes; need 4-node shells: *ELEMENT, TYPE=S4R in a .inp, quads on a surface in a .msh)"
    )]
    NoShells {
        /// Number of nodes in the mesh.
        nodes: usize,
    },
    /// A node has a coordinate that is not finite.
    #[error("node {node} has a non-finite coordinate ({x}, {y}, {z}) mm")]
    NonFiniteNode {
        /// The node.
        node: i64,
        /// x (mm).
        x: f64,
        /// y (mm).
        y: f64,
        /// z (mm).
        z: f64,
    },
    /// An element refers to a node index past the mesh's nodes.
    #[error("element {element} refers to node index {index}, past the {nodes} nodes")]
    MissingNode {
        /// The element.
        element: i64,
        /// The 0-based node index it refers to.
        index: u32,
        /// Number of nodes in the mesh.
        nodes: usize,
    },
    /// An element lists one node twice.
    #[error("element {element} has zero area: node {node} appears twice ({nodes})")]
    RepeatedNode {
        /// The element.
        element: i64,
        /// The repeated node.
        node: i64,
        /// The element's nodes, as `nodes 1, 2, 3, 4`.
        nodes: String,
    },
    /// An element's area is zero (or below the quality threshold).
    #[error("element {element} has zero area ({area:e} mm²; {nodes})")]
    ZeroArea {
        /// The element.
        element: i64,
        /// Its area (mm²).
        area: f64,
        /// The element's nodes, as `nodes 1, 2, 3, 4`.
        nodes: String,
    },
    /// [`Mesh::validate`] refused an element's shape.
    #[error("element {element}: {reason} ({measure} = {value}; {nodes})")]
    BadElement {
        /// The element.
        element: i64,
        /// What is wrong, the node named by the file's number.
        reason: String,
        /// Name of the measured quantity, with its unit.
        measure: &'static str,
        /// Its value.
        value: f64,
        /// The element's nodes, as `nodes 1, 2, 3, 4`.
        nodes: String,
    },
    /// Any other [`Mesh::validate`] error.
    #[error(transparent)]
    Invalid(FemError),
}

/// Check `mesh` (named by `file`'s numbers when it was read): shells
/// present, finite coordinates, elements on existing and distinct nodes,
/// of non-zero area, then [`Mesh::validate`] (shape, sets, orientation).
///
/// # Errors
/// A [`MeshError`] naming the node or the element and its nodes.
pub fn check(mesh: &Mesh, file: Option<&MeshFile>) -> Result<(), MeshError> {
    let names = Names(file);
    if mesh.quads.is_empty() {
        return Err(MeshError::NoShells {
            nodes: mesh.nodes.len(),
        });
    }
    if let Some(n) = mesh
        .nodes
        .iter()
        .position(|p| !p.iter().all(|v| v.is_finite()))
    {
        let p = mesh.nodes[n];
        return Err(MeshError::NonFiniteNode {
            node: names.node(n as u32),
            x: p.x,
            y: p.y,
            z: p.z,
        });
    }
    for (e, q) in mesh.quads.iter().enumerate() {
        check_element(mesh, e, q, &names)?;
    }
    mesh.validate().map_err(|err| describe(err, mesh, &names))
}

/// Element `e` on nodes `q`: nodes exist, none repeated, area above
/// [`MeshQuality::min_relative_area`] × (longest side)².
fn check_element(mesh: &Mesh, e: usize, q: &[u32; 4], names: &Names) -> Result<(), MeshError> {
    let id = names.element(e);
    if let Some(&n) = q.iter().find(|&&n| n as usize >= mesh.nodes.len()) {
        return Err(MeshError::MissingNode {
            element: id,
            index: n,
            nodes: mesh.nodes.len(),
        });
    }
    if let Some(k) = (1..4).find(|&k| q[..k].contains(&q[k])) {
        return Err(MeshError::RepeatedNode {
            element: id,
            node: names.node(q[k]),
            nodes: names.nodes_of(q),
        });
    }
    let p = q.map(|n| mesh.nodes[n as usize]);
    let area = 0.5 * (p[2] - p[0]).cross(&(p[3] - p[1])).norm();
    let longest = (0..4)
        .map(|k| (p[(k + 1) % 4] - p[k]).norm())
        .fold(0.0, f64::max);
    let min = MeshQuality::default().min_relative_area * longest * longest;
    if area.is_nan() || area <= min || longest == 0.0 {
        return Err(MeshError::ZeroArea {
            element: id,
            area,
            nodes: names.nodes_of(q),
        });
    }
    Ok(())
}

/// A [`Mesh::validate`] error with the file's numbers.
fn describe(err: FemError, mesh: &Mesh, names: &Names) -> MeshError {
    match err {
        FemError::BadElement {
            element,
            reason,
            measure,
            value,
        } => {
            let q = &mesh.quads[element];
            let reason = q
                .iter()
                .find_map(|&n| {
                    let head = reason.strip_suffix(&format!("at node {n}"))?;
                    Some(format!("{head}at node {}", names.node(n)))
                })
                .unwrap_or_else(|| reason.clone());
            MeshError::BadElement {
                element: names.element(element),
                reason,
                measure,
                value,
                nodes: names.nodes_of(q),
            }
        }
        other => MeshError::Invalid(other),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The engine's 0-based numbers become the file's; other numbers stay.
    #[test]
    fn rename_uses_the_files_numbers() {
        let f = FileIds {
            nodes: vec![101, 102, 103],
            elements: vec![7, 8],
        };
        let m = "node 0: mass 2; element 1 (nodes 0, 2, 9) at step 3";
        assert_eq!(
            FileIds::rename(Some(&f), m),
            "node 101: mass 2; element 8 (nodes 101, 103, 9) at step 3"
        );
        assert_eq!(FileIds::rename(None, m), m);
    }

    fn square() -> Mesh {
        fem_core::rectangle(2.0, 1.0, 2, 1).unwrap()
    }

    fn numbered(mesh: Mesh) -> MeshFile {
        MeshFile {
            node_ids: (0..mesh.nodes.len() as i64).map(|i| 100 + i).collect(),
            element_ids: vec![17, 18],
            mesh,
        }
    }

    #[test]
    fn a_good_mesh_passes() {
        check(&square(), None).unwrap();
    }

    #[test]
    fn zero_area_names_the_element_and_its_nodes_by_file_numbers() {
        let mut m = square();
        // Collapse the second element onto a line: nodes 2 and 5 onto 1 and 4.
        m.nodes[2] = Vec3::new(1.0, 0.0, 0.0);
        m.nodes[5] = Vec3::new(1.0, 1.0, 0.0);
        let f = numbered(m);
        let e = check(&f.mesh, Some(&f)).unwrap_err().to_string();
        assert!(
            e.starts_with("element 18 has zero area (") && e.ends_with("nodes 101, 102, 105, 104)"),
            "{e}"
        );
    }

    #[test]
    fn a_repeated_node_is_zero_area() {
        let mut m = square();
        m.quads[0][3] = m.quads[0][2];
        let e = check(&m, None).unwrap_err().to_string();
        assert_eq!(
            e,
            "element 0 has zero area: node 4 appears twice (nodes 0, 1, 4, 4)"
        );
    }

    #[test]
    fn empty_and_non_finite_meshes_are_refused() {
        let e = check(&Mesh::default(), None).unwrap_err().to_string();
        assert!(e.starts_with("no shell elements (0 nodes"), "{e}");
        let mut m = square();
        m.nodes[3].y = f64::NAN;
        let f = numbered(m);
        let e = check(&f.mesh, Some(&f)).unwrap_err().to_string();
        assert!(e.starts_with("node 103 has a non-finite coordinate"), "{e}");
    }

    #[test]
    fn distortion_names_the_file_node() {
        let mut m = square();
        // Push node 4 (top middle) far right: the first element turns non-convex.
        m.nodes[4].x = 2.9;
        let f = numbered(m);
        let e = check(&f.mesh, Some(&f)).unwrap_err().to_string();
        assert!(
            e.starts_with("element 18: inverted or non-convex at node 10"),
            "{e}"
        );
    }
}
