//! The assembled tangent as a `faer` matrix, for benchmarks and for
//! inspecting the linear algebra outside the Newton loop.

use super::evaluate::Failure;
use super::{StaticSolver, StaticsError};
use crate::{Dof, FemError, Vec3};
use faer::sparse::SparseColMat;

impl StaticSolver {
    /// The tangent `K = ∂F_int/∂u` at the converged state (the start state
    /// before the first increment), over the equations, as the Newton
    /// iterations factorise it: `n × n` compressed sparse columns, both
    /// triangles and the whole diagonal stored (structurally symmetric;
    /// the values are not when an effect's tangent is not), row indices
    /// sorted. Equation `i` is the DOF [`StaticSolver::equation_dof`]`(i)`:
    /// the free DOFs that some effect stiffens, in increasing global index
    /// `6 · node + dof`.
    ///
    /// It assembles the effects at the converged state (the trial state of
    /// a zero increment) and then reverts them, so the solve can go on
    /// after it; its assembly time counts in [`StaticSolver::timing`]. The
    /// solve itself does not need it: it is there to measure and compare
    /// factorisations on a real tangent.
    ///
    /// # Errors
    /// An effect failing at the converged state, or breaking the assembly
    /// contract.
    pub fn tangent_matrix(&mut self) -> Result<SparseColMat<usize, f64>, StaticsError> {
        self.x.copy_from_slice(&self.x_committed);
        self.dtheta.iter_mut().for_each(|d| *d = Vec3::zeros());
        self.lambda_trial = self.lambda;
        let eval = self.evaluate(true);
        for effect in &mut self.effects {
            effect.revert();
        }
        match eval {
            Ok(_) => Ok(SparseColMat::new(
                self.pattern.matrix.clone(),
                self.values.clone(),
            )),
            Err(Failure::Hard(e)) => Err(e),
            Err(Failure::Soft(message)) => {
                Err(StaticsError::Setup(FemError::InvalidSetup(format!(
                    "the tangent at the converged state (λ = {}): {message}",
                    self.lambda
                ))))
            }
        }
    }

    /// The (node, DOF) of equation `i` of [`StaticSolver::tangent_matrix`];
    /// `None` when `i` is not below the number of equations.
    pub fn equation_dof(&self, i: usize) -> Option<(usize, Dof)> {
        (i < self.dofs.len()).then(|| self.dofs.node_dof(i))
    }
}
