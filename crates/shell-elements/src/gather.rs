//! The element results gathered onto the nodes: forces, moments and the
//! nodal frames (area, normal), one node at a time.
//!
//! Each node adds the contributions of its elements in increasing element
//! order, starting from what the node already holds: the same sequence of
//! additions as a serial scatter over the elements in order, so the same
//! bits, whether the nodes run one after the other or in parallel.

use fem_core::{Forces, Vec3};
use rayon::prelude::*;

use crate::formulation::ElementResult;
use crate::lanes::F4;

/// Nodes per parallel task.
const CHUNK: usize = 256;

/// Per node, its element corners `4 e + k` in increasing element order
/// (compressed rows).
#[derive(Debug, Clone, Default)]
pub(crate) struct NodeCorners {
    offsets: Vec<u32>,
    corners: Vec<u32>,
}

impl NodeCorners {
    /// The corners of `quads` around each of `nodes` nodes.
    pub fn new(nodes: usize, quads: &[[u32; 4]]) -> Self {
        let mut offsets = vec![0u32; nodes + 1];
        for &n in quads.iter().flatten() {
            offsets[n as usize + 1] += 1;
        }
        for i in 0..nodes {
            offsets[i + 1] += offsets[i];
        }
        let mut next = offsets.clone();
        let mut corners = vec![0u32; quads.len() * 4];
        for (e, q) in quads.iter().enumerate() {
            for (k, &n) in q.iter().enumerate() {
                let slot = &mut next[n as usize];
                corners[*slot as usize] = (4 * e + k) as u32;
                *slot += 1;
            }
        }
        Self { offsets, corners }
    }

    /// Number of nodes.
    fn nodes(&self) -> usize {
        self.offsets.len() - 1
    }

    /// The corners around node `i`.
    #[inline]
    fn of(&self, i: usize) -> &[u32] {
        &self.corners[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }
}

/// The step's element results: blocks of four in lanes, then the rest.
#[derive(Clone, Copy)]
pub(crate) struct Results<'a> {
    pub blocks: &'a [ElementResult<F4>],
    pub rest: &'a [ElementResult],
}

impl Results<'_> {
    /// Force and moment of element `e` at its corner `k` (N, N·mm).
    #[inline(always)]
    fn corner(&self, e: usize, k: usize) -> ([f64; 3], [f64; 3]) {
        let nb4 = 4 * self.blocks.len();
        if e < nb4 {
            let (r, l) = (&self.blocks[e / 4], e % 4);
            let f = &r.f[k];
            let m = &r.m[k];
            (
                [f[0].0[l], f[1].0[l], f[2].0[l]],
                [m[0].0[l], m[1].0[l], m[2].0[l]],
            )
        } else {
            let r = &self.rest[e - nb4];
            (r.f[k], r.m[k])
        }
    }

    /// Projected area (mm²) and unit normal of element `e`.
    #[inline(always)]
    fn frame(&self, e: usize) -> (f64, [f64; 3]) {
        let nb4 = 4 * self.blocks.len();
        if e < nb4 {
            let (r, l) = (&self.blocks[e / 4], e % 4);
            (
                r.area.0[l],
                [r.normal[0].0[l], r.normal[1].0[l], r.normal[2].0[l]],
            )
        } else {
            let r = &self.rest[e - nb4];
            (r.area, r.normal)
        }
    }
}

/// Add every element's corner forces and moments to its nodes' `forces`;
/// in parallel chunks of nodes when `parallel`.
pub(crate) fn forces(
    corners: &NodeCorners,
    results: Results<'_>,
    forces: &mut Forces,
    parallel: bool,
) {
    let node = |i: usize, f: &mut Vec3, m: &mut Vec3| {
        for &c in corners.of(i) {
            let (fe, me) = results.corner(c as usize / 4, c as usize % 4);
            f.x += fe[0];
            f.y += fe[1];
            f.z += fe[2];
            m.x += me[0];
            m.y += me[1];
            m.z += me[2];
        }
    };
    let n = corners.nodes().min(forces.f.len()).min(forces.m.len());
    let (f, m) = (&mut forces.f[..n], &mut forces.m[..n]);
    if parallel {
        f.par_iter_mut()
            .zip(m.par_iter_mut())
            .enumerate()
            .with_min_len(CHUNK)
            .for_each(|(i, (f, m))| node(i, f, m));
    } else {
        f.iter_mut()
            .zip(m.iter_mut())
            .enumerate()
            .for_each(|(i, (f, m))| node(i, f, m));
    }
}

/// The nodal areas (a quarter of each element's projected area, mm²) and the
/// area-weighted sums of the element normals (mm²), written whole; in
/// parallel chunks of nodes when `parallel`.
pub(crate) fn frames(
    corners: &NodeCorners,
    results: Results<'_>,
    area: &mut [f64],
    normal: [&mut [f64]; 3],
    parallel: bool,
) {
    let node = |i: usize, a: &mut f64, x: &mut f64, y: &mut f64, z: &mut f64| {
        let (mut sa, mut s) = (0.0, [0.0; 3]);
        for &c in corners.of(i) {
            let (ae, ne) = results.frame(c as usize / 4);
            sa += 0.25 * ae;
            for d in 0..3 {
                s[d] += ne[d] * ae;
            }
        }
        (*a, *x, *y, *z) = (sa, s[0], s[1], s[2]);
    };
    let [nx, ny, nz] = normal;
    let n = corners.nodes().min(area.len());
    for rest in [&mut area[n..], &mut nx[n..], &mut ny[n..], &mut nz[n..]] {
        rest.fill(0.0);
    }
    if parallel {
        area[..n]
            .par_iter_mut()
            .zip(nx[..n].par_iter_mut())
            .zip(ny[..n].par_iter_mut())
            .zip(nz[..n].par_iter_mut())
            .enumerate()
            .with_min_len(CHUNK)
            .for_each(|(i, (((a, x), y), z))| node(i, a, x, y, z));
    } else {
        for i in 0..n {
            let (a, x, y, z) = (&mut area[i], &mut nx[i], &mut ny[i], &mut nz[i]);
            node(i, a, x, y, z);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 9 × 7 grid of quads (63: 15 blocks of four and 3 left over) with
    /// made-up results, gathered serially and in parallel on two threads:
    /// the same bits as adding the corners element by element in order.
    #[test]
    fn gathering_by_node_equals_the_serial_scatter_bit_for_bit() {
        let (nx, ny) = (9usize, 7usize);
        let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
        let quads: Vec<[u32; 4]> = (0..ny)
            .flat_map(|j| {
                (0..nx).map(move |i| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)])
            })
            .collect();
        let nodes = (nx + 1) * (ny + 1);
        let value = |e: usize, k: usize, c: usize| ((e * 31 + k * 7 + c) as f64 * 0.37).sin() * 1e3;
        let one = |e: usize| {
            let mut r = ElementResult::<f64>::default();
            for k in 0..4 {
                for c in 0..3 {
                    r.f[k][c] = value(e, k, c);
                    r.m[k][c] = value(e, k, c + 3);
                }
            }
            r.area = 1.0 + value(e, 0, 9).abs() * 1e-3;
            r.normal = [value(e, 1, 9), value(e, 2, 9), 1.0];
            r
        };
        let nb = quads.len() / 4;
        let mut blocks = vec![ElementResult::<F4>::default(); nb];
        for (b, block) in blocks.iter_mut().enumerate() {
            for l in 0..4 {
                block.set_lane(l, &one(4 * b + l));
            }
        }
        let rest: Vec<ElementResult> = (4 * nb..quads.len()).map(one).collect();
        // The reference: element by element, in order, onto non-zero forces.
        let start = |i: usize| Vec3::new(i as f64, -(i as f64), 0.5);
        let mut expect = Forces::zeros(nodes);
        expect
            .f
            .iter_mut()
            .enumerate()
            .for_each(|(i, f)| *f = start(i));
        let (mut ea, mut en) = (
            vec![0.0; nodes],
            [vec![0.0; nodes], vec![0.0; nodes], vec![0.0; nodes]],
        );
        for (e, q) in quads.iter().enumerate() {
            let r = one(e);
            for (k, &n) in q.iter().enumerate() {
                let n = n as usize;
                expect.f[n] += Vec3::from(r.f[k]);
                expect.m[n] += Vec3::from(r.m[k]);
                ea[n] += 0.25 * r.area;
                for d in 0..3 {
                    en[d][n] += r.normal[d] * r.area;
                }
            }
        }
        let corners = NodeCorners::new(nodes, &quads);
        let results = Results {
            blocks: &blocks,
            rest: &rest,
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        for parallel in [false, true] {
            let mut got = Forces::zeros(nodes);
            got.f
                .iter_mut()
                .enumerate()
                .for_each(|(i, f)| *f = start(i));
            let (mut a, mut x, mut y, mut z) = (
                vec![9.0; nodes],
                vec![9.0; nodes],
                vec![9.0; nodes],
                vec![9.0; nodes],
            );
            pool.install(|| {
                forces(&corners, results, &mut got, parallel);
                frames(
                    &corners,
                    results,
                    &mut a,
                    [&mut x, &mut y, &mut z],
                    parallel,
                );
            });
            assert_eq!(got.f, expect.f, "parallel {parallel}");
            assert_eq!(got.m, expect.m, "parallel {parallel}");
            assert_eq!(
                (a, [x, y, z]),
                (ea.clone(), en.clone()),
                "parallel {parallel}"
            );
        }
    }
}
