//! The static Newton solver: equilibrium `F_int(u) = λ F_ext` by load
//! increments, the first brick of springback.
//!
//! # The assembly interface
//!
//! An effect gives its internal forces and consistent tangent at a trial
//! state through an [`Assembly`], keyed by (node, DOF) with 6 DOFs per
//! node (translations `ux uy uz`, rotations `rx ry rz`). Path-dependent
//! effects keep trial and committed state apart: [`StaticTangent::commit`]
//! on convergence, [`StaticTangent::revert`] on a cut-back.
//! [`Springs`](crate::Springs) implement it with the exact tangent of the
//! geometrically nonlinear axial spring; [`dense_tangent`] evaluates any
//! effect densely, to check its tangent against finite differences.

mod assembly;
mod dense;
mod springs;
mod tangent;

pub use assembly::{Assembly, DofGroup};
pub use dense::{DenseTangent, dense_tangent};
pub use tangent::{StaticTangent, TrialState};
