//! Stage 1b, the narrow phase: the closest point on the tool of every
//! candidate, warm-started from the point's last answer on this tool. It owns
//! the projection loop (in parallel chunks for many candidates) and what the
//! later stages keep of each projection ([`Near`]).
//!
//! A point whose last projection came with a region of the tool
//! ([`ToolSurface::region`]: a disc of a planar patch on which the closest
//! point is the perpendicular foot, or a patch that is exactly a cylinder or
//! torus, on which it is the radial foot) and whose foot still lies in that
//! region is answered in closed form (a dot product on a plane, a square
//! root or two on a cylinder or torus), its warm start kept; any other point
//! is projected, and the tool is asked for the region around its new answer.

use plugins_api::{Projection, ProjectionHint, ToolRegion, ToolSurface, Vec3};
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
    /// Whether the tool projected the point (else the region answered); its
    /// new region is then in [`Candidates::regions`].
    pub projected: bool,
    /// Whether a curved region answered.
    pub curved: bool,
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
        projected: false,
        curved: false,
    };

    /// What the step keeps of `pr`; the tool's region around it goes to
    /// `region`.
    fn of(pr: &Projection, tool: &dyn ToolSurface, region: &mut Option<ToolRegion>) -> Self {
        let hint = pr.hint();
        *region = tool.region(&hint);
        Self {
            normal: pr.normal,
            distance: pr.distance,
            hint,
            projected: true,
            curved: false,
        }
    }

    /// The answer for `x` from the last projection's region `region` (warm
    /// start `hint` kept), if its foot is still in the region.
    #[inline]
    fn from_region(
        at: &ToolStep,
        x: &Vec3,
        region: &ToolRegion,
        hint: ProjectionHint,
    ) -> Option<Self> {
        let (distance, normal) = region.project_local(&at.local(x))?;
        Some(Self {
            normal: at.to_global * normal,
            distance,
            hint,
            projected: false,
            curved: matches!(region, ToolRegion::Curved(_)),
        })
    }
}

/// Project the nodes of `cand.points` (blank node `nodes[k]` at `x`, warm
/// start `hint[k]`, region `region[k]`) on `tool` (placed as `at`) into
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
    (hint, region): (&[Option<ProjectionHint>], &[Option<ToolRegion>]),
    cand: &mut Candidates,
    pair: &str,
) -> Result<(), ContactError> {
    let (ks, near, regions) = (&cand.points, &mut cand.near, &mut cand.regions[..]);
    near.clear();
    let one = |k: u32, new_region: &mut Option<ToolRegion>| {
        let (k, xk) = (k as usize, &x[nodes[k as usize] as usize]);
        if let (Some(r), Some(h)) = (&region[k], hint[k])
            && let Some(n) = Near::from_region(at, xk, r, h)
        {
            return Ok(n);
        }
        tool.project(xk, hint[k])
            .map(|pr| Near::of(&pr, tool, new_region))
    };
    if parallel(ks.len()) {
        near.resize(ks.len(), Near::NONE);
        let done: Result<(), ()> = near
            .par_chunks_mut(PARALLEL_CHUNK)
            .zip(regions.par_chunks_mut(PARALLEL_CHUNK))
            .zip(ks.par_chunks(PARALLEL_CHUNK))
            .try_for_each(|((out, regions), ks)| {
                for ((o, r), &k) in out.iter_mut().zip(regions).zip(ks) {
                    *o = one(k, r).map_err(|_| ())?;
                }
                Ok(())
            });
        if done.is_ok() {
            return Ok(());
        }
    }
    // One thread (or a failure to report in candidate order): in order,
    // into the slots' kept capacity.
    near.clear();
    for (&k, r) in ks.iter().zip(regions.iter_mut()) {
        near.push(one(k, r).map_err(|source| ContactError::Tool {
            pair: pair.to_string(),
            node: nodes[k as usize] as usize,
            source: Box::new(source),
        })?);
    }
    Ok(())
}
