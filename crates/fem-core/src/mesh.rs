//! The quad-shell mesh: nodes, 4-node elements, node and element sets; the structured rectangle generator and the validator.

use crate::{FemError, Vec3};
use std::collections::{BTreeMap, HashMap};

/// A quad-shell mesh. Indices are 0-based; quads list their nodes
/// counter-clockwise about the element normal `(x3 - x1) × (x4 - x2)`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mesh {
    /// Node coordinates (mm).
    pub nodes: Vec<Vec3>,
    /// Element connectivity (node indices).
    pub quads: Vec<[u32; 4]>,
    /// Named node sets (node indices).
    pub node_sets: BTreeMap<String, Vec<u32>>,
    /// Named element sets (element indices).
    pub element_sets: BTreeMap<String, Vec<u32>>,
}

/// Thresholds of [`Mesh::validate_with`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshQuality {
    /// Smallest admissible corner angle (degrees); below it a quad is badly distorted.
    pub min_corner_angle_deg: f64,
    /// Largest admissible corner angle (degrees); above it a quad is badly distorted.
    pub max_corner_angle_deg: f64,
    /// Largest admissible warp angle (degrees): the larger, over the two
    /// diagonal splits, of the angle between the normals of the two triangles.
    pub max_warp_deg: f64,
    /// Area below which a quad counts as zero-area, relative to the square of
    /// its longest edge (-).
    pub min_relative_area: f64,
}

impl Default for MeshQuality {
    fn default() -> Self {
        Self {
            min_corner_angle_deg: 5.0,
            max_corner_angle_deg: 175.0,
            max_warp_deg: 30.0,
            min_relative_area: 1e-10,
        }
    }
}

impl Mesh {
    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.nodes.len()
    }

    /// Number of quads.
    pub fn n_elements(&self) -> usize {
        self.quads.len()
    }

    /// The node set `name`, or an error listing the known sets.
    pub fn node_set(&self, name: &str) -> Result<&[u32], FemError> {
        self.node_sets
            .get(name)
            .map(Vec::as_slice)
            .ok_or_else(|| FemError::UnknownSet {
                kind: "node set",
                name: name.to_string(),
                known: join_keys(&self.node_sets),
            })
    }

    /// The element set `name`, or an error listing the known sets.
    pub fn element_set(&self, name: &str) -> Result<&[u32], FemError> {
        self.element_sets
            .get(name)
            .map(Vec::as_slice)
            .ok_or_else(|| FemError::UnknownSet {
                kind: "element set",
                name: name.to_string(),
                known: join_keys(&self.element_sets),
            })
    }

    /// Check the mesh with the default [`MeshQuality`] thresholds.
    ///
    /// Errors (the first one found, naming the node or element): non-finite
    /// coordinates, node index out of range, a node repeated in a quad, set
    /// indices out of range, zero area, inverted or non-convex corners
    /// (a corner whose Jacobian is not positive about the element normal),
    /// corner angles outside `[5°, 175°]`, warp angle above 30°, and neighbours
    /// with opposite orientation (a shared edge traversed in the same
    /// direction by both).
    pub fn validate(&self) -> Result<(), FemError> {
        self.validate_with(&MeshQuality::default())
    }

    /// [`Mesh::validate`] with explicit thresholds.
    pub fn validate_with(&self, q: &MeshQuality) -> Result<(), FemError> {
        for (i, p) in self.nodes.iter().enumerate() {
            for (axis, value) in ["x", "y", "z"].into_iter().zip(p.iter()) {
                if !value.is_finite() {
                    return Err(FemError::NonFiniteCoordinate {
                        node: i,
                        axis,
                        value: *value,
                    });
                }
            }
        }
        let n = self.nodes.len();
        for (e, quad) in self.quads.iter().enumerate() {
            for (k, &a) in quad.iter().enumerate() {
                if a as usize >= n {
                    return Err(FemError::NodeOutOfRange {
                        element: e,
                        node: a as u64,
                        n_nodes: n,
                    });
                }
                if quad[..k].contains(&a) {
                    return Err(FemError::DuplicateNode {
                        element: e,
                        node: a,
                    });
                }
            }
            self.check_shape(e, quad, q)?;
        }
        for (name, set) in &self.node_sets {
            check_set("node set", name, set, n)?;
        }
        for (name, set) in &self.element_sets {
            check_set("element set", name, set, self.quads.len())?;
        }
        self.check_orientation()
    }

    fn check_shape(&self, e: usize, quad: &[u32; 4], q: &MeshQuality) -> Result<(), FemError> {
        let p: [Vec3; 4] = quad.map(|a| self.nodes[a as usize]);
        let normal = (p[2] - p[0]).cross(&(p[3] - p[1]));
        let area = 0.5 * normal.norm();
        let longest = (0..4)
            .map(|k| (p[(k + 1) % 4] - p[k]).norm())
            .fold(0.0, f64::max);
        if area.is_nan() || area <= q.min_relative_area * longest * longest || longest == 0.0 {
            return Err(FemError::BadElement {
                element: e,
                reason: "zero area".into(),
                measure: "area (mm²)",
                value: area,
            });
        }
        let nhat = normal / normal.norm();
        for k in 0..4 {
            let a = p[(k + 1) % 4] - p[k];
            let b = p[(k + 3) % 4] - p[k];
            let (la, lb) = (a.norm(), b.norm());
            let sin = a.cross(&b).dot(&nhat) / (la * lb);
            let cos = a.dot(&b) / (la * lb);
            let angle = sin.atan2(cos).to_degrees();
            if sin <= 0.0 {
                return Err(FemError::BadElement {
                    element: e,
                    reason: format!("inverted or non-convex at node {}", quad[k]),
                    measure: "corner angle (degrees)",
                    value: angle,
                });
            }
            if angle < q.min_corner_angle_deg || angle > q.max_corner_angle_deg {
                return Err(FemError::BadElement {
                    element: e,
                    reason: format!("badly distorted at node {}", quad[k]),
                    measure: "corner angle (degrees)",
                    value: angle,
                });
            }
        }
        let tri = |i: usize, j: usize, k: usize| (p[j] - p[i]).cross(&(p[k] - p[i]));
        let angle = |a: Vec3, b: Vec3| a.cross(&b).norm().atan2(a.dot(&b)).to_degrees();
        let warp = angle(tri(0, 1, 2), tri(0, 2, 3)).max(angle(tri(1, 2, 3), tri(1, 3, 0)));
        if warp > q.max_warp_deg {
            return Err(FemError::BadElement {
                element: e,
                reason: "badly warped".into(),
                measure: "warp angle (degrees)",
                value: warp,
            });
        }
        Ok(())
    }

    fn check_orientation(&self) -> Result<(), FemError> {
        // Directed edge (a, b) -> element that traverses it.
        let mut seen: HashMap<(u32, u32), usize> = HashMap::with_capacity(4 * self.quads.len());
        for (e, quad) in self.quads.iter().enumerate() {
            for k in 0..4 {
                let edge = (quad[k], quad[(k + 1) % 4]);
                if let Some(&other) = seen.get(&edge) {
                    return Err(FemError::BadElement {
                        element: e,
                        reason: format!(
                            "inverted relative to its neighbour {other} (edge {}-{} traversed in \
                             the same direction by both)",
                            edge.0, edge.1
                        ),
                        measure: "neighbour element",
                        value: other as f64,
                    });
                }
                seen.insert(edge, e);
            }
        }
        Ok(())
    }

    /// Add (or replace) the node set `"all"` and the element set `"all"`.
    pub fn add_all_sets(&mut self) {
        self.node_sets
            .insert("all".into(), (0..self.nodes.len() as u32).collect());
        self.element_sets
            .insert("all".into(), (0..self.quads.len() as u32).collect());
    }
}

fn join_keys(m: &BTreeMap<String, Vec<u32>>) -> String {
    m.keys().cloned().collect::<Vec<_>>().join(", ")
}

fn check_set(kind: &'static str, name: &str, set: &[u32], len: usize) -> Result<(), FemError> {
    match set.iter().find(|&&i| i as usize >= len) {
        Some(&i) => Err(FemError::SetOutOfRange {
            kind,
            name: name.to_string(),
            index: i as u64,
            len,
        }),
        None => Ok(()),
    }
}

/// A structured `nx × ny` quad mesh of the rectangle `[0, lx] × [0, ly]` in
/// `z = 0`, counter-clockwise quads (normal `+z`).
///
/// Node `(i, j)` (`i` along x, `j` along y) has index `j (nx + 1) + i`;
/// element `(i, j)` has index `j nx + i`. Node sets: `x0`, `x1` (edges
/// `x = 0`, `x = lx`), `y0`, `y1`, `all`; element set `all`.
pub fn rectangle(lx: f64, ly: f64, nx: usize, ny: usize) -> Result<Mesh, FemError> {
    for (field, value) in [("lx", lx), ("ly", ly)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(FemError::InvalidParameter {
                field: field.into(),
                value,
                unit: "mm",
                range: "finite and > 0",
            });
        }
    }
    for (field, value) in [("nx", nx), ("ny", ny)] {
        if value == 0 || value > 1 << 15 {
            return Err(FemError::InvalidParameter {
                field: field.into(),
                value: value as f64,
                unit: "elements",
                range: "in [1, 32768]",
            });
        }
    }
    let stride = nx + 1;
    let mut nodes = Vec::with_capacity(stride * (ny + 1));
    for j in 0..=ny {
        for i in 0..=nx {
            nodes.push(Vec3::new(
                lx * i as f64 / nx as f64,
                ly * j as f64 / ny as f64,
                0.0,
            ));
        }
    }
    let id = |i: usize, j: usize| (j * stride + i) as u32;
    let mut quads = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mut mesh = Mesh {
        nodes,
        quads,
        ..Default::default()
    };
    let ns = &mut mesh.node_sets;
    ns.insert("x0".into(), (0..=ny).map(|j| id(0, j)).collect());
    ns.insert("x1".into(), (0..=ny).map(|j| id(nx, j)).collect());
    ns.insert("y0".into(), (0..=nx).map(|i| id(i, 0)).collect());
    ns.insert("y1".into(), (0..=nx).map(|i| id(i, ny)).collect());
    mesh.add_all_sets();
    Ok(mesh)
}

/// The segments of [`wrapped_strip`]'s centre line: along each tail
/// (`tail / h` rounded, at least 1) and over the drum (`rm angle / h`
/// rounded up, at least 1), as whole numbers in `f64` so that a size
/// estimate of an absurd input does not overflow.
pub fn wrapped_strip_segments(rm: f64, tail: f64, angle: f64, h: f64) -> (f64, f64) {
    (
        (tail / h).round().max(1.0),
        (rm * angle / h).ceil().max(1.0),
    )
}

/// A strip wrapped over a drum of axis `y` through the origin (the capstan,
/// docs/benchmarks.md §3): a horizontal tail of length `tail` on top of the drum
/// from `x = tail` to the drum's top, an arc of `angle` (rad) in the x–z
/// plane over the drum, a straight tail of length `tail` leaving it
/// tangentially. Mid-surface radius `rm`; three nodes across `width`;
/// element length about `h` along the strip.
///
/// Node sets: `pull` (the free end of the top tail), `hold` (the end of the
/// leaving tail), `centre` (the centre line), `all`; element set `all`.
///
/// # Errors
/// Non-positive or non-finite sizes, an angle outside `(0, π]`.
pub fn wrapped_strip(rm: f64, width: f64, tail: f64, angle: f64, h: f64) -> Result<Mesh, FemError> {
    for (field, value) in [
        ("radius", rm),
        ("width", width),
        ("tail", tail),
        ("element_size", h),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return Err(FemError::InvalidParameter {
                field: field.into(),
                value,
                unit: "mm",
                range: "finite and > 0",
            });
        }
    }
    if !(angle > 0.0 && angle <= std::f64::consts::PI) {
        return Err(FemError::InvalidParameter {
            field: "angle".into(),
            value: angle,
            unit: "rad",
            range: "in (0, pi]",
        });
    }
    let half_pi = std::f64::consts::FRAC_PI_2;
    let (n1, na) = wrapped_strip_segments(rm, tail, angle, h);
    let (n1, na) = (n1 as usize, na as usize);
    let mut centre = Vec::with_capacity(2 * n1 + na + 1);
    for i in 0..=n1 {
        centre.push((tail - i as f64 * tail / n1 as f64, rm));
    }
    for j in 1..=na {
        let a = half_pi + angle * j as f64 / na as f64;
        centre.push((rm * a.cos(), rm * a.sin()));
    }
    let a_end = half_pi + angle;
    let (ex, ez) = (rm * a_end.cos(), rm * a_end.sin());
    let (tx, tz) = (-a_end.sin(), a_end.cos());
    for k in 1..=n1 {
        let s = k as f64 * tail / n1 as f64;
        centre.push((ex + s * tx, ez + s * tz));
    }
    let ys = [-0.5 * width, 0.0, 0.5 * width];
    let mut nodes = Vec::with_capacity(3 * centre.len());
    for &(x, z) in &centre {
        for &y in &ys {
            nodes.push(Vec3::new(x, y, z));
        }
    }
    let m = centre.len();
    let mut quads = Vec::with_capacity(2 * (m - 1));
    for i in 0..m - 1 {
        for j in 0..2 {
            let a = (3 * i + j) as u32;
            quads.push([a, a + 3, a + 4, a + 1]);
        }
    }
    let mut mesh = Mesh {
        nodes,
        quads,
        ..Default::default()
    };
    let last = 3 * (m as u32 - 1);
    let ns = &mut mesh.node_sets;
    ns.insert("pull".into(), vec![0, 1, 2]);
    ns.insert("hold".into(), vec![last, last + 1, last + 2]);
    ns.insert("centre".into(), (0..m as u32).map(|i| 3 * i + 1).collect());
    mesh.add_all_sets();
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrapped_strip_lies_on_the_drum_and_leaves_it_tangentially() {
        let (rm, angle) = (20.05, std::f64::consts::FRAC_PI_2);
        let m = wrapped_strip(rm, 4.0, 20.0, angle, 1.0).unwrap();
        let centre = m.node_set("centre").unwrap();
        // 21 nodes on the top tail, 32 arc nodes (ceil(rm θ / h)), 20 on the leaving tail.
        assert_eq!(centre.len(), 21 + 32 + 20);
        assert_eq!(m.quads.len(), 2 * (centre.len() - 1));
        for &n in &centre[20..=52] {
            let p = m.nodes[n as usize];
            assert!((p.x.hypot(p.z) - rm).abs() < 1e-12, "arc node off the drum");
        }
        // θ = 90°: the leaving tail hangs straight down at x = -rm.
        let end = m.nodes[*centre.last().unwrap() as usize];
        assert!((end.x + rm).abs() < 1e-12 && (end.z + 20.0).abs() < 1e-12);
        assert!(wrapped_strip(rm, 4.0, 20.0, 4.0, 1.0).is_err());
        assert!(wrapped_strip(rm, 0.0, 20.0, angle, 1.0).is_err());
    }

    fn one_quad(p: [[f64; 3]; 4]) -> Mesh {
        Mesh {
            nodes: p.iter().map(|c| Vec3::new(c[0], c[1], c[2])).collect(),
            quads: vec![[0, 1, 2, 3]],
            ..Default::default()
        }
    }

    fn bad_reason(m: &Mesh) -> (usize, String) {
        match m.validate() {
            Err(FemError::BadElement {
                element, reason, ..
            }) => (element, reason),
            other => panic!("expected BadElement, got {other:?}"),
        }
    }

    #[test]
    fn rectangle_has_ccw_quads_and_edge_sets() {
        let m = rectangle(4.0, 2.0, 4, 2).unwrap();
        assert_eq!(m.n_nodes(), 15);
        assert_eq!(m.n_elements(), 8);
        m.validate().unwrap();
        for q in &m.quads {
            let p = q.map(|a| m.nodes[a as usize]);
            let n = (p[2] - p[0]).cross(&(p[3] - p[1]));
            assert!(n.z > 0.0 && (0.5 * n.norm() - 1.0).abs() < 1e-12);
        }
        let check = |set: &str, f: &dyn Fn(&Vec3) -> bool, len: usize| {
            let s = m.node_set(set).unwrap();
            assert_eq!(s.len(), len, "{set}");
            assert!(s.iter().all(|&i| f(&m.nodes[i as usize])), "{set}");
        };
        check("x0", &|p| p.x == 0.0, 3);
        check("x1", &|p| p.x == 4.0, 3);
        check("y0", &|p| p.y == 0.0, 5);
        check("y1", &|p| p.y == 2.0, 5);
        check("all", &|_| true, 15);
        assert_eq!(m.element_set("all").unwrap().len(), 8);
        let e = m.node_set("z0").unwrap_err().to_string();
        assert_eq!(e, "unknown node set `z0`; known: all, x0, x1, y0, y1");
    }

    #[test]
    fn rectangle_rejects_bad_sizes() {
        let e = rectangle(-1.0, 1.0, 2, 2).unwrap_err().to_string();
        assert_eq!(
            e,
            "parameter `lx` = -1 mm is out of range: must be finite and > 0"
        );
        assert!(rectangle(1.0, 1.0, 0, 2).is_err());
        assert!(rectangle(1.0, f64::NAN, 2, 2).is_err());
    }

    #[test]
    fn validate_names_inverted_quad() {
        // Clockwise in a mesh whose neighbour is counter-clockwise.
        let mut m = rectangle(2.0, 1.0, 2, 1).unwrap();
        m.quads[1] = [m.quads[1][0], m.quads[1][3], m.quads[1][2], m.quads[1][1]];
        let (e, reason) = bad_reason(&m);
        assert_eq!(e, 1);
        assert!(
            reason.starts_with("inverted relative to its neighbour 0"),
            "{reason}"
        );
        // A symmetric bow-tie has zero signed area.
        let m = one_quad([[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [1., 1., 0.]]);
        assert_eq!(bad_reason(&m), (0, "zero area".to_string()));
        // An asymmetric bow-tie is inverted at a corner.
        let m = one_quad([[0., 0., 0.], [2., 0., 0.], [0., 1., 0.], [1.5, 2., 0.]]);
        assert_eq!(
            bad_reason(&m),
            (0, "inverted or non-convex at node 2".to_string())
        );
        // A re-entrant (arrow-head) quad.
        let m = one_quad([[0., 0., 0.], [2., 0., 0.], [0.5, 0.5, 0.], [0., 2., 0.]]);
        assert!(
            bad_reason(&m)
                .1
                .starts_with("inverted or non-convex at node 2")
        );
    }

    #[test]
    fn validate_names_zero_area_and_distortion() {
        let m = one_quad([[0., 0., 0.], [1., 0., 0.], [2., 0., 0.], [3., 0., 0.]]);
        assert_eq!(bad_reason(&m), (0, "zero area".to_string()));
        let m = one_quad([[0., 0., 0.], [1., 0., 0.], [1.0, 1e-2, 0.], [0., 1e-2, 0.]]);
        m.validate().unwrap(); // thin is fine
        let m = one_quad([[0., 0., 0.], [10., 0., 0.], [10.2, 0.5, 0.], [0., 0.5, 0.]]);
        m.validate().unwrap();
        let m = one_quad([[0., 0., 0.], [1., 0., 0.], [20., 0.5, 0.], [0., 1., 0.]]);
        let (e, reason) = bad_reason(&m);
        assert_eq!(e, 0);
        // The corner at node 1 is nearly flat (178.5°).
        assert!(reason.starts_with("badly distorted at node 1"), "{reason}");
        let m = one_quad([[0., 0., 0.], [1., 0., 0.], [1., 1., 0.8], [0., 1., 0.]]);
        assert_eq!(bad_reason(&m).1, "badly warped");
    }

    #[test]
    fn validate_names_bad_ids_and_coordinates() {
        let mut m = rectangle(1.0, 1.0, 1, 1).unwrap();
        m.quads[0][2] = 9;
        assert_eq!(
            m.validate().unwrap_err().to_string(),
            "element 0: node index 9 is out of range (mesh has 4 nodes)"
        );
        m.quads[0][2] = 0;
        assert_eq!(
            m.validate().unwrap_err().to_string(),
            "element 0: node 0 appears twice in its connectivity"
        );
        let mut m = rectangle(1.0, 1.0, 1, 1).unwrap();
        m.nodes[3].y = f64::INFINITY;
        assert_eq!(
            m.validate().unwrap_err().to_string(),
            "node 3: coordinate y = inf mm is not finite"
        );
        let mut m = rectangle(1.0, 1.0, 1, 1).unwrap();
        m.node_sets.get_mut("x0").unwrap().push(4);
        assert_eq!(
            m.validate().unwrap_err().to_string(),
            "node set `x0`: index 4 is out of range (mesh has 4)"
        );
    }
}
