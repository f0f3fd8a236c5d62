//! A bounding-volume hierarchy over boxes (patch spans or facets) with a nearest-first, allocation-free query.

// Numeric kernels index several arrays with one counter.
#![allow(clippy::needless_range_loop)]

use plugins_api::{Aabb, Vec3};

const LEAF_SIZE: usize = 2;
const STACK: usize = 64;

#[derive(Debug, Clone, Copy)]
struct Node {
    min: [f64; 3],
    max: [f64; 3],
    /// Leaf: first primitive in `order`; inner: index of the left child (right = left + 1).
    start: u32,
    /// Leaf: number of primitives; inner: 0.
    count: u32,
}

impl Node {
    #[inline]
    fn dist2(&self, p: &[f64; 3]) -> f64 {
        let mut d2 = 0.0;
        for i in 0..3 {
            let d = (self.min[i] - p[i]).max(p[i] - self.max[i]).max(0.0);
            d2 += d * d;
        }
        d2
    }
}

/// A binary BVH over a fixed list of primitive boxes.
#[derive(Debug, Clone)]
pub struct Bvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
}

impl Bvh {
    /// Build over `boxes` (median split along the longest axis of the centroids).
    pub fn build(boxes: &[Aabb]) -> Self {
        let mut order: Vec<u32> = (0..boxes.len() as u32).collect();
        let mut nodes = vec![Node {
            min: [0.0; 3],
            max: [0.0; 3],
            start: 0,
            count: 0,
        }];
        if !boxes.is_empty() {
            Self::split(boxes, &mut order, &mut nodes, 0, 0, boxes.len());
        }
        Self { nodes, order }
    }

    fn split(
        boxes: &[Aabb],
        order: &mut [u32],
        nodes: &mut Vec<Node>,
        node: usize,
        lo: usize,
        hi: usize,
    ) {
        let mut b = Aabb::empty();
        let mut c = Aabb::empty();
        for &i in &order[lo..hi] {
            let bi = &boxes[i as usize];
            b.grow(&bi.min);
            b.grow(&bi.max);
            c.grow(&((bi.min + bi.max) * 0.5));
        }
        nodes[node].min = [b.min.x, b.min.y, b.min.z];
        nodes[node].max = [b.max.x, b.max.y, b.max.z];
        if hi - lo <= LEAF_SIZE {
            nodes[node].start = lo as u32;
            nodes[node].count = (hi - lo) as u32;
            return;
        }
        let ext = c.max - c.min;
        let axis = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        let mid = (lo + hi) / 2;
        let key = |i: &u32| {
            let bi = &boxes[*i as usize];
            (bi.min[axis] + bi.max[axis], *i)
        };
        order[lo..hi].sort_by(|a, b| {
            key(a)
                .partial_cmp(&key(b))
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        let left = nodes.len();
        nodes.push(nodes[node]);
        nodes.push(nodes[node]);
        nodes[node].start = left as u32;
        nodes[node].count = 0;
        Self::split(boxes, order, nodes, left, lo, mid);
        Self::split(boxes, order, nodes, left + 1, mid, hi);
    }

    /// Visit primitives nearest-box-first, skipping every subtree whose box is
    /// farther than `bound + slack` from `p`. `visit(primitive, box_distance)`
    /// returns the (possibly tightened) bound. Returns the final bound.
    #[inline]
    pub fn nearest(
        &self,
        p: &Vec3,
        mut bound: f64,
        slack: f64,
        mut visit: impl FnMut(usize, f64) -> f64,
    ) -> f64 {
        if self.order.is_empty() {
            return bound;
        }
        let pa = [p.x, p.y, p.z];
        let mut stack = [(0u32, 0.0f64); STACK];
        let mut top = 1;
        stack[0] = (0, self.nodes[0].dist2(&pa));
        while top > 0 {
            top -= 1;
            let (ni, d2) = stack[top];
            let lim = bound + slack;
            if d2 > lim * lim {
                continue;
            }
            let n = &self.nodes[ni as usize];
            if n.count > 0 {
                for k in n.start..n.start + n.count {
                    let prim = self.order[k as usize] as usize;
                    bound = visit(prim, d2.sqrt());
                }
            } else {
                let (a, b) = (n.start, n.start + 1);
                let da = self.nodes[a as usize].dist2(&pa);
                let db = self.nodes[b as usize].dist2(&pa);
                // Push the farther child first so the nearer one is visited first.
                let (first, second) = if da <= db {
                    ((b, db), (a, da))
                } else {
                    ((a, da), (b, db))
                };
                if top + 2 <= STACK {
                    stack[top] = first;
                    stack[top + 1] = second;
                    top += 2;
                }
            }
        }
        bound
    }
}
