//! `BlockNodes`: the nodal positions and velocities a block of four elements reads, gathered into SIMD lanes.
//!
//! A block kernel wants node `i`'s component `c` of its four elements in one
//! vector (`[[F4; 3]; 4]`, element `l` in lane `l`), while the nodal state
//! stores each node's `x, y, z` side by side. [`BlockNodes::gather`] builds
//! the lanes; `BlockNodes::gather_avx2` does the same with two 128-bit
//! loads, one broadcast pair and two unpacks per node and array, in
//! registers, so that the kernel does not load vectors from lanes stored one
//! by one (a load that spans four separate stores cannot be forwarded and
//! waits for them to reach the cache). Both give the same bits.

use crate::geometry::V3;
use crate::lanes::F4;
use fem_core::Vec3;

/// Three nodal arrays (positions, velocities, angular velocities) and the
/// connectivity of a block of four elements (`q[l]`: element `l`'s nodes),
/// every index checked against the arrays.
#[derive(Clone, Copy, Debug)]
pub struct BlockNodes<'a> {
    x: &'a [Vec3],
    v: &'a [Vec3],
    w: &'a [Vec3],
    q: &'a [[u32; 4]; 4],
}

/// Node `i`, component `c`, element `l` in lane `l`: positions, velocities,
/// angular velocities.
pub type Lanes3 = [[[F4; 3]; 4]; 3];

impl<'a> BlockNodes<'a> {
    /// The block's nodes, or `None` when an index of `q` is out of range of
    /// any of the three arrays.
    pub fn new(x: &'a [Vec3], v: &'a [Vec3], w: &'a [Vec3], q: &'a [[u32; 4]; 4]) -> Option<Self> {
        let len = x.len().min(v.len()).min(w.len());
        q.iter()
            .flatten()
            .all(|&n| (n as usize) < len)
            .then_some(Self { x, v, w, q })
    }

    /// The block's nodes without the index check.
    ///
    /// # Safety
    /// Every index of `q` must be below the length of each array.
    #[inline(always)]
    pub(crate) unsafe fn new_unchecked(
        x: &'a [Vec3],
        v: &'a [Vec3],
        w: &'a [Vec3],
        q: &'a [[u32; 4]; 4],
    ) -> Self {
        Self { x, v, w, q }
    }

    /// Element `l`'s corners: positions, velocities, angular velocities.
    #[inline(always)]
    pub fn element(&self, l: usize) -> ([V3; 4], [V3; 4], [V3; 4]) {
        let q = &self.q[l];
        let at = |a: &[Vec3], i: usize| {
            let p = &a[q[i] as usize];
            [p.x, p.y, p.z]
        };
        (
            std::array::from_fn(|i| at(self.x, i)),
            std::array::from_fn(|i| at(self.v, i)),
            std::array::from_fn(|i| at(self.w, i)),
        )
    }

    /// The three arrays in lanes (portable code).
    #[inline(always)]
    pub fn gather(&self) -> Lanes3 {
        let one = |a: &[Vec3]| -> [[F4; 3]; 4] {
            let mut o = [[F4::default(); 3]; 4];
            for i in 0..4 {
                for l in 0..4 {
                    // SAFETY: `new` or `new_unchecked`'s caller checked the
                    // indices against the arrays' lengths.
                    let p = unsafe { a.get_unchecked(self.q[l][i] as usize) };
                    (o[i][0].0[l], o[i][1].0[l], o[i][2].0[l]) = (p.x, p.y, p.z);
                }
            }
            o
        };
        [one(self.x), one(self.v), one(self.w)]
    }

    /// [`gather`](Self::gather) with AVX instructions, in registers, on a
    /// processor that has them (`_avx` is the proof).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(crate) fn gather_avx2(&self, _avx: crate::lanes::Avx2Fma) -> Lanes3 {
        // SAFETY: `_avx` proves the processor has AVX2.
        unsafe { self.gather_avx2_unchecked() }
    }

    /// [`gather_avx2`](Self::gather_avx2)'s body.
    ///
    /// # Safety
    /// The processor must have AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn gather_avx2_unchecked(&self) -> Lanes3 {
        use std::arch::x86_64::{
            _mm_load_sd, _mm_loadh_pd, _mm_loadu_pd, _mm256_castpd128_pd256, _mm256_insertf128_pd,
            _mm256_storeu_pd, _mm256_unpackhi_pd, _mm256_unpacklo_pd,
        };
        let one = |a: &[Vec3]| -> [[F4; 3]; 4] {
            let base = a.as_ptr().cast::<f64>();
            let mut o = [[F4::default(); 3]; 4];
            for i in 0..4 {
                // SAFETY: the indices are in range (see `gather`) and a
                // `Vec3` is three contiguous `f64`; the loads read x, y (16
                // bytes) and z (8 bytes) of the node and nothing beyond.
                unsafe {
                    let p = self.q.map(|e| base.add(3 * e[i] as usize));
                    let xy02 = _mm256_insertf128_pd::<1>(
                        _mm256_castpd128_pd256(_mm_loadu_pd(p[0])),
                        _mm_loadu_pd(p[2]),
                    );
                    let xy13 = _mm256_insertf128_pd::<1>(
                        _mm256_castpd128_pd256(_mm_loadu_pd(p[1])),
                        _mm_loadu_pd(p[3]),
                    );
                    let z01 = _mm_loadh_pd(_mm_load_sd(p[0].add(2)), p[1].add(2));
                    let z23 = _mm_loadh_pd(_mm_load_sd(p[2].add(2)), p[3].add(2));
                    let z = _mm256_insertf128_pd::<1>(_mm256_castpd128_pd256(z01), z23);
                    _mm256_storeu_pd(o[i][0].0.as_mut_ptr(), _mm256_unpacklo_pd(xy02, xy13));
                    _mm256_storeu_pd(o[i][1].0.as_mut_ptr(), _mm256_unpackhi_pd(xy02, xy13));
                    _mm256_storeu_pd(o[i][2].0.as_mut_ptr(), z);
                }
            }
            o
        };
        [one(self.x), one(self.v), one(self.w)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arrays(n: usize) -> [Vec<Vec3>; 3] {
        std::array::from_fn(|a| {
            (0..n)
                .map(|k| {
                    let f = (100 * a + 3 * k) as f64;
                    Vec3::new(f + 0.25, f + 1.5, -f - 2.75)
                })
                .collect()
        })
    }

    /// An index at or beyond the shortest array is refused.
    #[test]
    fn block_nodes_refuse_out_of_range_indices() {
        let [x, v, w] = arrays(5);
        let ok = [[0, 1, 2, 3], [1, 2, 3, 4], [4, 3, 2, 1], [0, 0, 4, 4]];
        assert!(BlockNodes::new(&x, &v, &w, &ok).is_some());
        let bad = [[0, 1, 2, 3], [1, 2, 3, 5], [4, 3, 2, 1], [0, 0, 4, 4]];
        assert!(BlockNodes::new(&x, &v, &w, &bad).is_none());
        assert!(BlockNodes::new(&x, &v[..4], &w, &ok).is_none());
    }

    /// The AVX gather and the portable one put every node's component in
    /// the right lane, including the arrays' last node (no read beyond it).
    /// Tolerance: none.
    #[test]
    fn avx2_gather_matches_portable_gather() {
        let [x, v, w] = arrays(7);
        let q = [[6, 0, 3, 2], [5, 6, 1, 0], [2, 4, 6, 3], [1, 1, 5, 6]];
        let b = BlockNodes::new(&x, &v, &w, &q).unwrap();
        let g = b.gather();
        for (a, arr) in [&x, &v, &w].into_iter().enumerate() {
            for i in 0..4 {
                for l in 0..4 {
                    let p = arr[q[l][i] as usize];
                    assert_eq!(
                        [g[a][i][0].0[l], g[a][i][1].0[l], g[a][i][2].0[l]],
                        [p.x, p.y, p.z]
                    );
                }
            }
        }
        for l in 0..4 {
            let (ex, ev, ew) = b.element(l);
            for i in 0..4 {
                assert_eq!(ex[i], [g[0][i][0].0[l], g[0][i][1].0[l], g[0][i][2].0[l]]);
                assert_eq!(ev[i][2], g[1][i][2].0[l]);
                assert_eq!(ew[i][1], g[2][i][1].0[l]);
            }
        }
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = crate::lanes::Avx2Fma::detect() {
            assert_eq!(b.gather_avx2(avx), g);
        }
    }
}
