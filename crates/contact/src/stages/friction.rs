//! Stage 2, friction: the pair's law × formulation over the gathered
//! touching points, through [`PointIntegrator::step_batch`] (one batch, or
//! independent chunks in parallel for many points). It owns the batch's
//! states and outputs and the naming of the first point a model refuses.
//! A frictionless pair runs [`no_friction`] instead.

use plugins_api::{PointIntegrator, PointState, StepOutput};
use rayon::prelude::*;

use super::{Batch, FRICTION_CHUNK, parallel};
use crate::ContactError;

/// Run `integrator` over `batch`: its states start from `history[k]` for
/// each gathered point `k` and hold the states after the step; its outputs
/// are overwritten. Each point lands in its own slot, so the results do not
/// depend on the threads.
///
/// # Errors
/// The friction model refusing a point: the first refused point in batch
/// order with its own error, naming `pair` and the blank node (`nodes[k]`).
pub(crate) fn friction(
    integrator: &dyn PointIntegrator,
    history: &[PointState],
    nodes: &[u32],
    batch: &mut Batch,
    pair: &str,
) -> Result<(), ContactError> {
    let Batch {
        points,
        inputs,
        states,
        outputs,
        ..
    } = batch;
    states.clear();
    states.extend(points.iter().map(|&k| history[k as usize]));
    outputs.clear();
    outputs.resize(points.len(), StepOutput::default());
    let done = if parallel(points.len()) {
        states
            .par_chunks_mut(FRICTION_CHUNK)
            .zip(inputs.par_chunks(FRICTION_CHUNK))
            .zip(outputs.par_chunks_mut(FRICTION_CHUNK))
            .try_for_each(|((s, i), o)| integrator.step_batch(s, i, o))
    } else {
        integrator.step_batch(states, inputs, outputs)
    };
    let Err(batch_error) = done else {
        return Ok(());
    };
    // Name the first point refused, with its own error: re-run point by point.
    let mut first = (0, batch_error);
    for (&k, input) in points.iter().zip(inputs.iter()) {
        let mut s = history[k as usize];
        if let Err(e) = integrator.step(&mut s, input) {
            first = (nodes[k as usize] as usize, e);
            break;
        }
    }
    Err(ContactError::Friction {
        pair: pair.to_string(),
        node: first.0,
        source: Box::new(first.1),
    })
}

/// A frictionless pair's stage: every gathered point gets a zero traction,
/// no slip, no dissipation and an empty history, without any law.
pub(crate) fn no_friction(batch: &mut Batch) {
    let n = batch.points.len();
    batch.states.clear();
    batch.states.resize(n, PointState::default());
    batch.outputs.clear();
    batch.outputs.resize(n, StepOutput::default());
}
