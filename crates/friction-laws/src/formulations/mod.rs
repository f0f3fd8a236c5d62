//! The built-in kinematic formulations of friction-math §4: how the history
//! traction is carried into the new frame, and which slip direction is used.
//!
//! Per step `n → n+1`, `t*` is a formulation's transported history (projected
//! onto the tangent plane of `n_{n+1}` by the return mapping), `t_tr = t* - k_T
//! Δu_T` the trial and `t_end = τ_c(ω_n) φ_tr` the radial-return traction. The
//! rate-based slip directions are the forward estimate `d = φ_n + Δt φ̇_n`
//! evaluated in the frame of `n+1` from `t*` and `t_end`
//! ([`plugins_api::kinematics::forward_direction`]): objective by construction,
//! and accurate whatever the ratio of slip to elastic slip per step. The shared
//! return mapping normalises `d` and falls back to `φ_tr` when it is `None`.
//!
//! | name | transport `t*` | slip direction `d` |
//! |---|---|---|
//! | [`Convective`] | minimal rotation `R_tool n_n → n_{n+1}` applied to `R_tool t_n` | `φ_tr` (backward Euler) |
//! | [`Jaumann`] | `R_surf R_W t_n`, `R_W = cay(Δt W)` | `φ* + Δt φ̇`: Jaumann rate |
//! | [`Lagrangian`] | `(I - n⊗n) F_{n+1} F_n⁻¹ t_n` | `φ* + Δt φ̇`: convected rate |
//! | [`UpdatedLagrangian`] | `(I - n⊗n) cay(Δt L) t_n` | `φ* + Δt φ̇`: convected rate, `Ḟ = L` |

pub mod convective;
pub mod jaumann;
pub mod lagrangian;
pub mod updated_lagrangian;

pub use convective::Convective;
pub use jaumann::Jaumann;
pub use lagrangian::Lagrangian;
pub use updated_lagrangian::UpdatedLagrangian;

use plugins_api::{Mat3, Vec3};

/// A vector whose components are all NaN: what a transport returns when the
/// blank's deformation data cannot carry the history (singular or inverted
/// deformation gradient), so that the return mapping reports an error instead
/// of silently keeping the old traction.
#[inline]
pub(crate) fn not_transportable() -> Vec3 {
    Vec3::repeat(f64::NAN)
}

/// `det(m) > 0` and finite: an admissible (orientation-preserving) deformation gradient.
#[inline]
pub(crate) fn admissible(m: &Mat3) -> bool {
    let det = m.determinant();
    det.is_finite() && det > 0.0
}
