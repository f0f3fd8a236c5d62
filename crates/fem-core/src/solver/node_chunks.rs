//! Stage 1's free update of every node, in fixed chunks of nodes.
//!
//! The nodes are cut into chunks of [`NODE_CHUNK`] whatever the number of
//! threads; each chunk sums its own energy terms, and the chunks' sums are
//! added in chunk order. The result is therefore the same bits on one
//! thread or many: only how the chunks are shared among the threads
//! changes. From [`PARALLEL_MIN_NODES`] nodes on, with more than one rayon
//! thread, the chunks run on rayon's pool; below, one after the other on
//! the calling thread (a small model pays no hand-over). A model of at most
//! one chunk sums exactly as one running sum over its nodes.

use super::{FreeSums, StepConstants};
use crate::{Forces, NodalState, Vec3};
use rayon::prelude::*;

/// Nodes per chunk: the unit of the sums' order (a few microseconds of work).
pub(crate) const NODE_CHUNK: usize = 512;

/// From this many nodes on (and with more than one thread) the chunks run
/// in parallel; below, the hand-over to the pool costs more than it saves.
pub(crate) const PARALLEL_MIN_NODES: usize = 4 * NODE_CHUNK;

/// Whether `n` nodes are worked on in parallel chunks (large enough, and
/// more than one rayon thread).
pub(crate) fn parallel(n: usize) -> bool {
    n >= PARALLEL_MIN_NODES && rayon::current_num_threads() > 1
}

/// How many chunks `n` nodes make.
pub(super) fn chunks(n: usize) -> usize {
    n.div_ceil(NODE_CHUNK)
}

/// What every chunk reads: masses, constraint bits, forces, the step.
struct Shared<'a> {
    m: &'a [f64],
    j: &'a [f64],
    constrained: &'a [u8],
    f: &'a [Vec3],
    mt: &'a [Vec3],
    k: &'a StepConstants,
}

/// The slices of one chunk that it writes.
struct ChunkMut<'a> {
    x: &'a mut [Vec3],
    v: &'a mut [Vec3],
    w: &'a mut [Vec3],
    v_old: &'a mut [Vec3],
    w_old: &'a mut [Vec3],
}

impl Shared<'_> {
    /// The free update of the chunk of nodes starting at `start`: old
    /// velocities kept, new ones from the forces, and the positions of the
    /// nodes without constraints (the constrained ones move after their
    /// constraints); returns the chunk's sums.
    #[inline(always)]
    fn chunk(&self, start: usize, c: ChunkMut<'_>) -> FreeSums {
        let len = c.x.len();
        let r = start..start + len;
        let (ms, js, cm) = (
            &self.m[r.clone()],
            &self.j[r.clone()],
            &self.constrained[r.clone()],
        );
        let (fs, mts) = (&self.f[r.clone()], &self.mt[r]);
        let (vs, ws) = (&mut c.v[..len], &mut c.w[..len]);
        let (vos, wos) = (&mut c.v_old[..len], &mut c.w_old[..len]);
        let k = self.k;
        let mut free = FreeSums::default();
        for i in 0..len {
            let m = ms[i];
            let vo = vs[i];
            vos[i] = vo;
            if m > 0.0 {
                free.update(0, m, &mut vs[i], vo, &fs[i], k);
            }
            let j = js[i];
            let wo = ws[i];
            wos[i] = wo;
            if j > 0.0 {
                free.update(1, j, &mut ws[i], wo, &mts[i], k);
            }
            if cm[i] == 0 {
                let v = vs[i];
                let x = &mut c.x[i];
                x.x += v.x * k.dt;
                x.y += v.y * k.dt;
                x.z += v.z * k.dt;
            }
        }
        free
    }
}

/// Every node's free update (stage 1 but the constraints), chunk by chunk,
/// each chunk's sums into `chunk_sums` (room for [`chunks`]`(n)`); returns
/// their total, added in chunk order. The positions of constrained nodes
/// are left to the caller.
pub(super) fn free_update(
    st: &mut NodalState,
    forces: &Forces,
    (v_old, w_old): (&mut [Vec3], &mut [Vec3]),
    constrained: &[u8],
    chunk_sums: &mut [FreeSums],
    k: &StepConstants,
) -> FreeSums {
    let n = st.x.len();
    let NodalState {
        x,
        v,
        w,
        mass,
        inertia,
        ..
    } = st;
    let shared = Shared {
        m: &mass[..n],
        j: &inertia[..n],
        constrained: &constrained[..n],
        f: &forces.f[..n],
        mt: &forces.m[..n],
        k,
    };
    let sums = &mut chunk_sums[..chunks(n)];
    let (x, v, w) = (&mut x[..n], &mut v[..n], &mut w[..n]);
    let (v_old, w_old) = (&mut v_old[..n], &mut w_old[..n]);
    let one = |(c, ((((x, v), w), v_old), w_old), s): ChunkItem<'_>| {
        *s = shared.chunk(
            c * NODE_CHUNK,
            ChunkMut {
                x,
                v,
                w,
                v_old,
                w_old,
            },
        );
    };
    if parallel(n) {
        x.par_chunks_mut(NODE_CHUNK)
            .zip(v.par_chunks_mut(NODE_CHUNK))
            .zip(w.par_chunks_mut(NODE_CHUNK))
            .zip(v_old.par_chunks_mut(NODE_CHUNK))
            .zip(w_old.par_chunks_mut(NODE_CHUNK))
            .zip(sums.par_iter_mut())
            .enumerate()
            .map(|(c, (a, s))| (c, a, s))
            .for_each(one);
    } else {
        x.chunks_mut(NODE_CHUNK)
            .zip(v.chunks_mut(NODE_CHUNK))
            .zip(w.chunks_mut(NODE_CHUNK))
            .zip(v_old.chunks_mut(NODE_CHUNK))
            .zip(w_old.chunks_mut(NODE_CHUNK))
            .zip(sums.iter_mut())
            .enumerate()
            .map(|(c, (a, s))| (c, a, s))
            .for_each(one);
    }
    let mut total = FreeSums::default();
    for s in sums.iter() {
        total.merge(s);
    }
    total
}

/// Zero every force and moment (stage 4's start), in parallel chunks on
/// large models.
pub(super) fn zero_forces(forces: &mut Forces) {
    if parallel(forces.f.len()) {
        let zero = |c: &mut [Vec3]| c.iter_mut().for_each(|v| *v = Vec3::zeros());
        forces.f.par_chunks_mut(NODE_CHUNK).for_each(zero);
        forces.m.par_chunks_mut(NODE_CHUNK).for_each(zero);
    } else {
        forces.clear();
    }
}

/// Whether every force and moment is finite (a sum per chunk, which is
/// finite when all its terms are and, but for an overflow, not otherwise;
/// the caller searches the culprit when it is not).
pub(super) fn forces_finite(forces: &Forces) -> bool {
    let sum = |(f, m): (&[Vec3], &[Vec3])| -> f64 {
        f.iter()
            .zip(m)
            .map(|(f, m)| f.x + f.y + f.z + m.x + m.y + m.z)
            .sum()
    };
    let (f, m) = (&forces.f[..], &forces.m[..forces.f.len()]);
    if parallel(f.len()) {
        f.par_chunks(NODE_CHUNK)
            .zip(m.par_chunks(NODE_CHUNK))
            .all(|c| sum(c).is_finite())
    } else {
        sum((f, m)).is_finite()
    }
}

/// One chunk's written slices.
type Rows<'a> = &'a mut [Vec3];

/// One chunk's index, its written slices `((((x, v), w), v_old), w_old)`
/// and its sums.
type ChunkItem<'a> = (
    usize,
    ((((Rows<'a>, Rows<'a>), Rows<'a>), Rows<'a>), Rows<'a>),
    &'a mut FreeSums,
);
