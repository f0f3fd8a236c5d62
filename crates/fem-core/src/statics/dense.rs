//! Dense evaluation of one effect's internal forces and tangent, for
//! verifying a tangent (against finite differences, say) on small models.

use super::assembly::Sink;
use super::{Assembly, StaticTangent, TrialState};
use crate::FemError;

/// Internal forces and tangent of an effect as dense arrays over all
/// `6 n` DOFs (index `6 · node + dof`).
#[derive(Debug, Clone, PartialEq)]
pub struct DenseTangent {
    /// Number of DOFs, `6 n`.
    pub n_dofs: usize,
    /// Internal forces (N, N·mm), `n_dofs` values.
    pub forces: Vec<f64>,
    /// Tangent `∂F_int/∂u`, row-major, `n_dofs²` values (empty when only
    /// the forces were asked for).
    pub stiffness: Vec<f64>,
}

impl DenseTangent {
    /// Tangent entry (`row`, `col`) (global DOF indices).
    pub fn k(&self, row: usize, col: usize) -> f64 {
        self.stiffness[row * self.n_dofs + col]
    }
}

/// Evaluate `effect` at `state` into dense arrays; the tangent too when
/// `with_tangent`. It allocates `(6 n)²` values: small models only.
///
/// # Errors
/// The effect's own error, or an assembly fault (a node out of range) as
/// [`FemError::Effect`].
pub fn dense_tangent<E: StaticTangent + ?Sized>(
    effect: &mut E,
    state: &TrialState<'_>,
    with_tangent: bool,
) -> Result<DenseTangent, FemError> {
    let n_dofs = 6 * state.len();
    let mut forces = vec![0.0; n_dofs];
    let mut stiffness = vec![0.0; if with_tangent { n_dofs * n_dofs } else { 0 }];
    let sink = if with_tangent {
        Sink::Dense(&mut stiffness)
    } else {
        Sink::Off
    };
    let mut out = Assembly::new(&mut forces, sink);
    effect.internal_forces(state, &mut out)?;
    out.finish().map_err(|message| FemError::Effect {
        effect: effect.name().to_string(),
        message,
    })?;
    Ok(DenseTangent {
        n_dofs,
        forces,
        stiffness,
    })
}
