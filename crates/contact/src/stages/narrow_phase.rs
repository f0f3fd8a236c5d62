//! Stage 1b, the narrow phase: the closest point on the tool of every
//! candidate, warm-started from the point's last answer on this tool. It owns
//! the projection loop (in parallel chunks for many candidates) and what the
//! later stages keep of each projection ([`Near`]).

use plugins_api::{Projection, ProjectionHint, ToolSurface, Vec3};
use rayon::prelude::*;

use super::{Candidates, PARALLEL_CHUNK, parallel};
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
    };

    /// What the step keeps of `pr`.
    fn of(pr: &Projection) -> Self {
        Self {
            normal: pr.normal,
            distance: pr.distance,
            hint: pr.hint(),
        }
    }
}

/// Project the nodes of `cand.points` (blank node `nodes[k]` at `x`, warm
/// start `hint[k]`) on `tool` into `cand.near`, in the same order; in
/// parallel chunks when there are more than
/// [`crate::ContactPair::PARALLEL_MIN_CANDIDATES`]. Each answer lands in its
/// own slot, so the result does not depend on the threads.
///
/// # Errors
/// The tool's error for the first failing node in candidate order (whatever
/// the threads did), naming `pair`.
pub(crate) fn narrow_phase(
    tool: &dyn ToolSurface,
    x: &[Vec3],
    nodes: &[u32],
    hint: &[Option<ProjectionHint>],
    cand: &mut Candidates,
    pair: &str,
) -> Result<(), ContactError> {
    let (ks, near) = (&cand.points, &mut cand.near);
    near.clear();
    near.resize(ks.len(), Near::NONE);
    let one = |k: u32| tool.project(&x[nodes[k as usize] as usize], hint[k as usize]);
    if parallel(ks.len()) {
        let done: Result<(), ()> = near
            .par_chunks_mut(PARALLEL_CHUNK)
            .zip(ks.par_chunks(PARALLEL_CHUNK))
            .try_for_each(|(out, ks)| {
                for (o, &k) in out.iter_mut().zip(ks) {
                    *o = Near::of(&one(k).map_err(|_| ())?);
                }
                Ok(())
            });
        if done.is_ok() {
            return Ok(());
        }
    }
    for (o, &k) in near.iter_mut().zip(ks.iter()) {
        let pr = one(k).map_err(|source| ContactError::Tool {
            pair: pair.to_string(),
            node: nodes[k as usize] as usize,
            source: Box::new(source),
        })?;
        *o = Near::of(&pr);
    }
    Ok(())
}
