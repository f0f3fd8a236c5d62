//! The static-assembly interface: what an effect gives the static solver
//! (internal forces and consistent tangent at a trial state) and the
//! commit/revert protocol of path-dependent effects.

use super::Assembly;
use crate::{Effect, FemError, Mat3, Vec3};

/// A trial configuration of the static solver, as an effect sees it.
///
/// Translations are total: `x` holds the trial positions. Rotations are
/// incremental: node `i`'s trial rotation from the start of the solve is
/// `exp([dtheta[i]]×) · rotation_committed[i]`, with `dtheta[i]` the rotation
/// vector (rad, global frame) since the last committed increment. The
/// solver updates `dtheta` additively (`dtheta += δθ`), so a tangent's
/// rotational columns are derivatives with respect to `dtheta`.
#[derive(Debug, Clone, Copy)]
pub struct TrialState<'a> {
    /// Positions at the start of the static solve (mm); the reference of
    /// the prescribed displacements.
    pub x_start: &'a [Vec3],
    /// Positions at the last committed (converged) increment (mm).
    pub x_committed: &'a [Vec3],
    /// Trial positions (mm).
    pub x: &'a [Vec3],
    /// Nodal rotations from the start of the solve to the last committed
    /// increment (rotation matrices).
    pub rotation_committed: &'a [Mat3],
    /// Trial rotation vectors since the last committed increment (rad).
    pub dtheta: &'a [Vec3],
    /// Load factor of the trial state (0 at the start, 1 at the end).
    pub lambda: f64,
}

impl TrialState<'_> {
    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether there are no nodes.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }
}

/// An effect that the static solver can drive: it gives its internal nodal
/// forces and their consistent tangent at a trial state.
///
/// # Contract
///
/// - [`StaticTangent::internal_forces`] adds `F_int = ∂W/∂u` (for an
///   elastic effect; the force the effect's material resists with, the
///   negative of what [`Effect::add_forces`] adds) and, when
///   [`Assembly::wants_tangent`], the consistent tangent `∂F_int/∂u`,
///   both in the global frame, 6 DOFs per node.
/// - The result is a function of the trial state and of the committed
///   history only: the solver calls it many times per increment (Newton
///   iterations, line-search trials) and in any order.
/// - The tangent's entries come in the same order, at the same (row,
///   column) positions, at every call that wants it: the sparsity pattern
///   is recorded at the first call and reused (an entry whose value happens
///   to be zero is still given). Give both triangles of a symmetric tangent.
/// - [`StaticTangent::commit`] accepts the trial state of the last call as
///   the new committed state (a plastic shell updates its history there);
///   [`StaticTangent::revert`] forgets whatever the trial calls left since
///   the last commit (the solver cuts the increment back).
pub trait StaticTangent: Effect {
    /// Add the internal forces (and the tangent when `out` wants it) at `state`.
    ///
    /// # Errors
    /// A trial state the effect cannot evaluate (a spring of zero length, an
    /// inverted element): the solver backtracks or cuts the increment back.
    fn internal_forces(
        &mut self,
        state: &TrialState<'_>,
        out: &mut Assembly<'_>,
    ) -> Result<(), FemError>;

    /// Accept `state` (the last evaluated trial state) as converged.
    fn commit(&mut self, state: &TrialState<'_>) {
        let _ = state;
    }

    /// Drop everything the trial calls did since the last commit.
    fn revert(&mut self) {}

    /// Whether the tangent is symmetric (the solver then uses a symmetric
    /// factorisation; otherwise LU).
    fn symmetric_tangent(&self) -> bool {
        true
    }
}
