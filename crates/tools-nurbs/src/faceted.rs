//! Faceted tools: triangle meshes behind the same `ToolSurface`, with Phong-smoothed normals and a curvature estimate.
//!
//! Vertices are welded (coincident within 1e-9 of the mesh size), vertex
//! normals are angle-weighted face normals, and at a closest point with
//! barycentric coordinates `b` the normal is the interpolated (Phong) normal
//! `n = N/|N|`, `N = Σ b_i n_i`. The curvature estimate is the gradient of
//! that field over the facet, `K ≈ sym(P (Σ n_i ⊗ ∇b_i) P)/|N|` with
//! `P = I - n⊗n`: exact in the limit of fine meshes of smooth surfaces, zero on
//! flat regions. Patch id = triangle index, `(u, v) = (b_1, b_2)`. The closest
//! point itself lies on the flat facets; the signed distance takes its sign
//! from the Phong normal, except beyond an open edge of the mesh, where the
//! sharp-edge rule answers ([`crate::faceted_edges`]). Winding defines the blank side (counter-clockwise
//! seen from the blank); `flip_normals` reverses it.

use crate::bvh::Bvh;
use crate::error::NurbsError;
use crate::faceted_edges::Boundary;
use crate::mesh_io::TriMesh;
use crate::nurbs_tool::{TIE_TOL, batch, posed_box};
use plugins_api::{
    Aabb, Mat3, Projection, ProjectionHint, RigidPose, RigidVelocity, ToolError, ToolSurface, Vec3,
};
use std::collections::HashMap;

/// A rigid tool given as a triangle mesh.
#[derive(Debug, Clone)]
pub struct FacetedTool {
    name: String,
    vertices: Vec<Vec3>,
    normals: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    /// Gradients of the barycentric coordinates over each facet.
    grads: Vec<[Vec3; 3]>,
    /// The open boundary (edges of one triangle), for the sharp-edge rule.
    boundary: Boundary,
    bvh: Bvh,
    local_box: Aabb,
    pose: RigidPose,
    velocity: RigidVelocity,
}

/// Closest point of triangle `(a, b, c)` to `p` and its barycentric coordinates
/// (Ericson, *Real-Time Collision Detection*, §5.1.5).
fn closest_on_triangle(p: &Vec3, a: &Vec3, b: &Vec3, c: &Vec3) -> (Vec3, [f64; 3]) {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(&ap);
    let d2 = ac.dot(&ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (*a, [1.0, 0.0, 0.0]);
    }
    let bp = p - b;
    let d3 = ab.dot(&bp);
    let d4 = ac.dot(&bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (*b, [0.0, 1.0, 0.0]);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (a + ab * v, [1.0 - v, v, 0.0]);
    }
    let cp = p - c;
    let d5 = ab.dot(&cp);
    let d6 = ac.dot(&cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (*c, [0.0, 0.0, 1.0]);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (a + ac * w, [1.0 - w, 0.0, w]);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + (c - b) * w, [0.0, 1.0 - w, w]);
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    (a + ab * v + ac * w, [1.0 - v - w, v, w])
}

impl FacetedTool {
    /// Weld, orient and index a mesh. Degenerate (zero-area) facets are an error naming the facet.
    pub fn new(name: &str, mesh: &TriMesh, flip_normals: bool) -> Result<Self, NurbsError> {
        if mesh.triangles.is_empty() {
            return Err(NurbsError::Empty {
                tool: name.to_string(),
            });
        }
        let mut bbox = Aabb::empty();
        for v in &mesh.vertices {
            bbox.grow(v);
        }
        let size = (bbox.max - bbox.min).norm().max(1e-300);
        let q = 1e-9 * size;
        let mut map: HashMap<[i64; 3], u32> = HashMap::new();
        let mut vertices = Vec::new();
        let mut remap = Vec::with_capacity(mesh.vertices.len());
        for v in &mesh.vertices {
            let key = [
                (v.x / q).round() as i64,
                (v.y / q).round() as i64,
                (v.z / q).round() as i64,
            ];
            let id = *map.entry(key).or_insert_with(|| {
                vertices.push(*v);
                (vertices.len() - 1) as u32
            });
            remap.push(id);
        }
        let mut triangles = Vec::with_capacity(mesh.triangles.len());
        let mut normals = vec![Vec3::zeros(); vertices.len()];
        let mut grads = Vec::with_capacity(mesh.triangles.len());
        let mut boxes = Vec::with_capacity(mesh.triangles.len());
        for (ti, t) in mesh.triangles.iter().enumerate() {
            let mut t = [
                remap[t[0] as usize],
                remap[t[1] as usize],
                remap[t[2] as usize],
            ];
            if flip_normals {
                t.swap(1, 2);
            }
            let p = [
                vertices[t[0] as usize],
                vertices[t[1] as usize],
                vertices[t[2] as usize],
            ];
            let cr = (p[1] - p[0]).cross(&(p[2] - p[0]));
            let area2 = cr.norm();
            if area2.is_nan() || area2 <= 1e-12 * size * size {
                return Err(NurbsError::Param {
                    tool: name.to_string(),
                    key: format!("facet {ti} area"),
                    value: 0.5 * area2,
                    unit: "mm²",
                    reason: "is zero: degenerate triangle".into(),
                });
            }
            let fn_ = cr / area2;
            let mut g = [Vec3::zeros(); 3];
            for k in 0..3 {
                let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
                let e1 = b - a;
                let e2 = c - a;
                let ang = e1.angle(&e2);
                normals[t[k] as usize] += fn_ * ang;
                // ∇b_k: perpendicular to the opposite edge, towards vertex k, |∇b_k| = 1/height.
                let opp = c - b;
                g[k] = fn_.cross(&opp) / area2;
            }
            let mut b = Aabb::empty();
            for v in &p {
                b.grow(v);
            }
            boxes.push(b);
            grads.push(g);
            triangles.push(t);
        }
        for n in &mut normals {
            let l = n.norm();
            if l > 0.0 {
                *n /= l;
            }
        }
        let boundary = Boundary::of(&triangles, &grads);
        Ok(Self {
            name: name.to_string(),
            boundary,
            bvh: Bvh::build(&boxes),
            local_box: bbox,
            vertices,
            normals,
            triangles,
            grads,
            pose: RigidPose::default(),
            velocity: RigidVelocity::default(),
        })
    }

    /// Number of facets.
    pub fn facet_count(&self) -> usize {
        self.triangles.len()
    }

    /// Welded vertices (local frame) and triangles.
    pub fn mesh(&self) -> (&[Vec3], &[[u32; 3]]) {
        (&self.vertices, &self.triangles)
    }

    /// Whether the mesh has open (free) edges, answered by the sharp-edge
    /// rule ([`crate::faceted_edges`]).
    pub fn is_open(&self) -> bool {
        self.boundary.is_open()
    }

    /// Vertex normals (angle-weighted, unit).
    pub fn vertex_normals(&self) -> &[Vec3] {
        &self.normals
    }

    #[inline]
    fn facet(&self, ti: usize, x: &Vec3) -> (Vec3, [f64; 3], f64) {
        let t = &self.triangles[ti];
        let (p, b) = closest_on_triangle(
            x,
            &self.vertices[t[0] as usize],
            &self.vertices[t[1] as usize],
            &self.vertices[t[2] as usize],
        );
        (p, b, (p - x).norm())
    }

    /// Closest point in the local frame: `(facet, point, barycentrics, distance)`.
    fn search(&self, x: &Vec3, hint: Option<ProjectionHint>) -> (usize, Vec3, [f64; 3], f64) {
        let mut best = (usize::MAX, Vec3::zeros(), [0.0; 3], f64::INFINITY);
        if let Some(h) = hint
            && (h.patch as usize) < self.triangles.len()
        {
            let ti = h.patch as usize;
            let (p, b, d) = self.facet(ti, x);
            best = (ti, p, b, d);
        }
        self.bvh.nearest(x, best.3, TIE_TOL, |ti, _| {
            let (p, b, d) = self.facet(ti, x);
            if d < best.3 - TIE_TOL || (d <= best.3 + TIE_TOL && ti < best.0) {
                best = (ti, p, b, d);
            }
            best.3
        });
        best
    }

    fn answer(&self, x: &Vec3, ti: usize, p: Vec3, b: [f64; 3], d: f64) -> Projection {
        let t = &self.triangles[ti];
        let r = x - p;
        if self.boundary.is_open() && self.boundary.beyond(ti, t, &self.grads[ti], &b, &r) {
            // The sharp-edge rule (crate::faceted_edges): a bare line.
            let rot = &self.pose.rotation;
            return Projection {
                point: self.pose.to_global(&p),
                normal: rot * (r / d),
                distance: d,
                curvature: Mat3::zeros(),
                k1: 0.0,
                k2: 0.0,
                patch: ti as u32,
                u: b[1],
                v: b[2],
            };
        }
        let big_n: Vec3 = (0..3).map(|k| self.normals[t[k] as usize] * b[k]).sum();
        let ln = big_n.norm();
        let n = big_n / ln;
        let g = &self.grads[ti];
        let grad: Mat3 = (0..3)
            .map(|k| self.normals[t[k] as usize] * g[k].transpose())
            .sum();
        let proj = Mat3::identity() - n * n.transpose();
        let k = proj * grad * proj / ln;
        let k = (k + k.transpose()) * 0.5;
        let e1 = if n.x.abs() < 0.9 {
            Vec3::x()
        } else {
            Vec3::y()
        };
        let e1 = (e1 - n * n.dot(&e1)).normalize();
        let e2 = n.cross(&e1);
        let (a11, a12, a22) = (e1.dot(&(k * e1)), e1.dot(&(k * e2)), e2.dot(&(k * e2)));
        let m = 0.5 * (a11 + a22);
        let r = (0.25 * (a11 - a22).powi(2) + a12 * a12).sqrt();
        let distance = if (x - p).dot(&n) < 0.0 { -d } else { d };
        let rot = &self.pose.rotation;
        Projection {
            point: self.pose.to_global(&p),
            normal: rot * n,
            distance,
            curvature: rot * k * rot.transpose(),
            k1: m + r,
            k2: m - r,
            patch: ti as u32,
            u: b[1],
            v: b[2],
        }
    }
}

impl ToolSurface for FacetedTool {
    fn name(&self) -> &str {
        &self.name
    }

    fn pose(&self) -> RigidPose {
        self.pose
    }

    fn set_pose(&mut self, pose: RigidPose, velocity: RigidVelocity) {
        self.pose = pose;
        self.velocity = velocity;
    }

    fn velocity(&self) -> RigidVelocity {
        self.velocity
    }

    fn bounding_box(&self) -> Aabb {
        posed_box(&self.local_box, &self.pose)
    }

    fn project(&self, x: &Vec3, hint: Option<ProjectionHint>) -> Result<Projection, ToolError> {
        if !(x.x.is_finite() && x.y.is_finite() && x.z.is_finite()) {
            return Err(ToolError::NonFinitePoint {
                tool: self.name.clone(),
                x: x.x,
                y: x.y,
                z: x.z,
            });
        }
        let xl = self.pose.to_local(x);
        let (ti, p, b, d) = self.search(&xl, hint);
        Ok(self.answer(&xl, ti, p, b, d))
    }

    fn project_batch(
        &self,
        points: &[Vec3],
        hints: &[Option<ProjectionHint>],
        out: &mut [Projection],
    ) -> Result<(), ToolError> {
        batch(self, points, hints, out)
    }
}
