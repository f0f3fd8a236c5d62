//! The open boundary of a faceted tool and the sharp-edge rule beyond it
//! (the faceted counterpart of [`crate::free_edges`]).
//!
//! An edge used by one triangle only is a boundary (free) edge; its
//! outward direction is the in-plane perpendicular pointing away from that
//! triangle. A closest point on a boundary edge, or on a vertex of the
//! boundary, with the query point beyond it (`r = x − p` with a positive
//! component along the outward direction of one of those edges) is answered
//! like a bare line: distance `|r|`, positive, normal `r/|r|`, zero
//! curvature. Closed meshes have no boundary, and their answers do not change.

use plugins_api::Vec3;
use std::collections::HashMap;

/// The boundary of a triangle mesh: per triangle, which of its edges is
/// open (edge `k` is opposite vertex `k`), and per vertex, the outward
/// directions of the open edges that end there.
#[derive(Debug, Clone, Default)]
pub struct Boundary {
    open: Vec<[bool; 3]>,
    vertex_out: HashMap<u32, Vec<Vec3>>,
}

impl Boundary {
    /// The boundary of `triangles`; `grads[t][k]` is the
    /// gradient of triangle `t`'s barycentric coordinate `k` (it points from
    /// edge `k` towards vertex `k`, into the triangle).
    pub fn of(triangles: &[[u32; 3]], grads: &[[Vec3; 3]]) -> Self {
        let key = |a: u32, b: u32| if a < b { (a, b) } else { (b, a) };
        let mut uses: HashMap<(u32, u32), u32> = HashMap::new();
        for t in triangles {
            for k in 0..3 {
                *uses.entry(key(t[(k + 1) % 3], t[(k + 2) % 3])).or_insert(0) += 1;
            }
        }
        let mut open = Vec::with_capacity(triangles.len());
        let mut vertex_out: HashMap<u32, Vec<Vec3>> = HashMap::new();
        for (t, g) in triangles.iter().zip(grads) {
            let mut o = [false; 3];
            for k in 0..3 {
                let (a, b) = (t[(k + 1) % 3], t[(k + 2) % 3]);
                if uses[&key(a, b)] == 1 {
                    o[k] = true;
                    let out = -g[k] / g[k].norm();
                    for v in [a, b] {
                        vertex_out.entry(v).or_default().push(out);
                    }
                }
            }
            open.push(o);
        }
        Self { open, vertex_out }
    }

    /// Whether the mesh has any open edge.
    pub fn is_open(&self) -> bool {
        !self.vertex_out.is_empty()
    }

    /// Whether `x` (local frame), whose closest point on the mesh is `p`
    /// with barycentric coordinates `b` on triangle `ti` (vertices `tri`,
    /// barycentric gradients `g`), lies beyond the mesh's boundary there.
    pub fn beyond(&self, ti: usize, tri: &[u32; 3], g: &[Vec3; 3], b: &[f64; 3], r: &Vec3) -> bool {
        let tol = 1e-12 * r.norm();
        let zero = |v: f64| v.abs() <= 1e-12;
        for k in 0..3 {
            if self.open[ti][k] && zero(b[k]) && -r.dot(&g[k]) > tol * g[k].norm() {
                return true;
            }
        }
        // On a vertex: every open edge that ends there counts.
        (0..3).any(|j| {
            zero(b[(j + 1) % 3])
                && zero(b[(j + 2) % 3])
                && self
                    .vertex_out
                    .get(&tri[j])
                    .is_some_and(|outs| outs.iter().any(|o| r.dot(o) > tol))
        })
    }
}
