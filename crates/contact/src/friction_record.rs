//! An opt-in record of what the friction stage saw at every touching point
//! of a pair in its last step: the history it started from, the return
//! mapping's input (pressure, slip increment, kinematics) and its output.
//!
//! It is a diagnostic (docs/s-rail.md, "Why the formulations agree"): with
//! the record, a caller can apply every kinematic formulation's transport to
//! the very history and kinematics the run's own formulation saw, and
//! compare the spin and frame-rotation terms with the slip increment's. A
//! recording pair computes every kinematic quantity a formulation may read
//! ([`RECORD_NEEDS`]), whatever its own formulation declares; its own law and
//! formulation read only what they declared, so the run is the same bits
//! (tested). Off (the default) the pair keeps no record and pays one branch
//! per step.

use plugins_api::{PointNeeds, PointState, StepInput, StepOutput};

use crate::stages::Batch;

/// The point data a recording pair computes on top of its own needs: the
/// velocity gradient (jaumann's spin, updated-lagrangian's `L`), the
/// deformation gradients at `n` and `n+1` (lagrangian) and the tool's
/// rotation over the step (convective).
pub const RECORD_NEEDS: PointNeeds = PointNeeds::VELOCITY_GRADIENT
    .union(PointNeeds::DEFORMATION_GRADIENT)
    .union(PointNeeds::TOOL_ROTATION);

/// The friction stage of a pair's last step, per touching point (all four
/// vectors in the same order, the pair-point order).
#[derive(Clone, Debug, Default)]
pub struct FrictionRecord {
    /// Pair point of each touching point (index into `ContactPair::nodes`).
    pub points: Vec<u32>,
    /// The friction history the step started from (`t_n`, `p_n`, `ω_n`).
    pub history: Vec<PointState>,
    /// The return mapping's input (pressure, slip increment `Δu_T`, step
    /// kinematics with every field of [`RECORD_NEEDS`] filled).
    pub inputs: Vec<StepInput>,
    /// The return mapping's output (traction, `τ_c`, stick or slip, `Δγ`, …).
    pub outputs: Vec<StepOutput>,
}

impl FrictionRecord {
    /// Copy the batch of a step whose friction stage has run, with the
    /// pair's history before the step (`history[k]` for pair point `k`).
    pub(crate) fn capture(&mut self, batch: &Batch, history: &[PointState]) {
        let n = batch.points.len();
        self.points.clear();
        self.points.extend_from_slice(&batch.points);
        self.history.clear();
        self.history
            .extend(batch.points.iter().map(|&k| history[k as usize]));
        self.inputs.clear();
        self.inputs.extend_from_slice(&batch.inputs[..n]);
        self.outputs.clear();
        self.outputs.extend_from_slice(&batch.outputs[..n]);
    }
}
