//! Stage 1b, the narrow phase: the closest point on the tool of every
//! candidate, warm-started from the point's last answer on this tool. It owns
//! the projection loop (in parallel chunks for many candidates) and what the
//! later stages keep of each projection ([`Near`]).
//!
//! A point whose last projection came with a flat region of the tool
//! ([`ToolSurface::flat_region`]: a disc of a planar patch on which the
//! closest point is the perpendicular foot) and whose foot still lies in
//! that disc is answered from the plane at the price of a dot product, its
//! warm start kept; any other point is projected, and the tool is asked for
//! the flat region around its new answer.

use plugins_api::{FlatRegion, Projection, ProjectionHint, ToolSurface, Vec3};
use rayon::prelude::*;

use super::{Candidates, PARALLEL_CHUNK, ToolStep, parallel};
use crate::ContactError;

/// What the step keeps of a projection.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Near {
    /// Unit tool normal at the closest point, towards the blank side.
    pub normal: Vec3,
    /// Signed distance of the node from the tool (mm), positive on the blank side.
    pub distance: f64,
    /// Warm start of the next projection.
    pub hint: ProjectionHint,
    /// The flat region the answer lies in, if the tool has one there.
    pub region: Option<FlatRegion>,
    /// Whether the tool projected the point (else the flat region answered).
    pub projected: bool,
}

impl Near {
    /// A placeholder before the projection writes the slot.
    const NONE: Near = Near {
        normal: Vec3::new(0.0, 0.0, 0.0),
        distance: f64::NAN,
        hint: ProjectionHint {
            patch: 0,
            u: f64::NAN,
            v: f64::NAN,
        },
        region: None,
        projected: false,
    };

    /// What the step keeps of `pr`, and the flat region around it.
    fn of(pr: &Projection, tool: &dyn ToolSurface) -> Self {
        let hint = pr.hint();
        Self {
            normal: pr.normal,
            distance: pr.distance,
            hint,
            region: tool.flat_region(&hint),
            projected: true,
        }
    }

    /// The answer for `x` from the last projection's flat region `region`
    /// (warm start `hint` kept), if its foot is still in the region's disc.
    #[inline]
    fn from_region(
        at: &ToolStep,
        x: &Vec3,
        region: &FlatRegion,
        hint: ProjectionHint,
    ) -> Option<Self> {
        let (distance, _) = region.project_local(&at.local(x))?;
        Some(Self {
            normal: at.to_global * region.normal,
            distance,
            hint,
            region: Some(*region),
            projected: false,
        })
    }
}

/// Project the nodes of `cand.points` (blank node `nodes[k]` at `x`, warm
/// start `hint[k]`, flat region `region[k]`) on `tool` (placed as `at`) into
/// `cand.near`, in the same order; in
/// parallel chunks when there are more than
/// [`crate::ContactPair::PARALLEL_MIN_CANDIDATES`]. Each answer lands in its
/// own slot, so the result does not depend on the threads.
///
/// # Errors
/// The tool's error for the first failing node in candidate order (whatever
/// the threads did), naming `pair`.
pub(crate) fn narrow_phase(
    tool: &dyn ToolSurface,
    at: &ToolStep,
    x: &[Vec3],
    nodes: &[u32],
    (hint, region): (&[Option<ProjectionHint>], &[Option<FlatRegion>]),
    cand: &mut Candidates,
    pair: &str,
) -> Result<(), ContactError> {
    let (ks, near) = (&cand.points, &mut cand.near);
    near.clear();
    near.resize(ks.len(), Near::NONE);
    let one = |k: u32| {
        let (k, xk) = (k as usize, &x[nodes[k as usize] as usize]);
        if let (Some(r), Some(h)) = (&region[k], hint[k])
            && let Some(n) = Near::from_region(at, xk, r, h)
        {
            return Ok(n);
        }
        tool.project(xk, hint[k]).map(|pr| Near::of(&pr, tool))
    };
    if parallel(ks.len()) {
        let done: Result<(), ()> = near
            .par_chunks_mut(PARALLEL_CHUNK)
            .zip(ks.par_chunks(PARALLEL_CHUNK))
            .try_for_each(|(out, ks)| {
                for (o, &k) in out.iter_mut().zip(ks) {
                    *o = one(k).map_err(|_| ())?;
                }
                Ok(())
            });
        if done.is_ok() {
            return Ok(());
        }
    }
    for (o, &k) in near.iter_mut().zip(ks.iter()) {
        *o = one(k).map_err(|source| ContactError::Tool {
            pair: pair.to_string(),
            node: nodes[k as usize] as usize,
            source: Box::new(source),
        })?;
    }
    Ok(())
}
