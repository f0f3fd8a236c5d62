//! The `updated-lagrangian` formulation: push-forward with the step deformation gradient `cay(Δt L)` (friction-math §4, thesis eqs. 2.61–2.65).

use plugins_api::kinematics::forward_direction;
use plugins_api::{DirectionInputs, KinematicFormulation, Mat3, PointNeeds, StepKinematics, Vec3};

use super::{admissible, not_transportable, tangent_part};

/// Name as typed in scenes.
pub const NAME: &str = "updated-lagrangian";

/// One-line summary for registries and the CLI.
pub const SUMMARY: &str = "updated Lagrangian: F = I at step n, history pushed forward by cay(dt L) and projected; d = phi_n + dt phi_dot with F_dot = L (convected rate)";

/// The updated-Lagrangian formulation of friction-math §4: the reference is the
/// configuration at step `n` (`F = I`, `J = 1`, `Λ = 1`, eq. 2.61).
///
/// (a) Transport, with `L` the blank velocity gradient at mid-step:
///
/// ```text
/// ΔF = (I - ½ΔtL)⁻¹ (I + ½ΔtL)            (exact step gradient for a mid-step L)
/// t* = (I - n_{n+1}⊗n_{n+1}) ΔF t_n
/// ```
///
/// If `I - ½ΔtL` is singular or `det ΔF ≤ 0` (a step far too large for the
/// deformation rate) the transport returns NaN, which the return mapping
/// reports as an error.
///
/// (b) Slip direction: the forward estimate `d = φ_n + Δt φ̇_n` of §4,
/// evaluated in the frame of step `n+1` where this formulation's transported
/// history `t*` lives (so that it uses objective quantities only and is exactly
/// objective): `d = φ* + (I - φ*⊗φ*)(t_end - t*)/|t*|`
/// ([`forward_direction`](plugins_api::kinematics::forward_direction): the
/// closed-form `φ̇` with `ṅ = 0` in the co-moving frame and `Δt Ṫ = t_end - t*`,
/// `t_end = τ_c(ω_n) φ_tr` the radial-return traction, the `Δ²γ` term dropped).
/// The deformation enters through `t* = P cay(Δt L) t_n` (`Ḟ = L`, eqs.
/// 2.62–2.65). With `L` the exact mid-step gradient of the motion that also
/// gives `F`, `cay(Δt L) = F_{n+1} F_n⁻¹` and this formulation coincides with
/// [`Lagrangian`](super::Lagrangian) step by step; they differ when `F` and
/// `L` come from different sources (e.g. total `F` from reference geometry,
/// `L` from nodal velocities), and then agree to `O(Δt)`. `None` when `|t*| = 0`.
///
/// Needs [`PointNeeds::VELOCITY_GRADIENT`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct UpdatedLagrangian;

impl KinematicFormulation for UpdatedLagrangian {
    fn name(&self) -> &str {
        NAME
    }

    fn needs(&self) -> PointNeeds {
        PointNeeds::VELOCITY_GRADIENT
    }

    #[inline]
    fn transport(&self, t_old: &Vec3, kin: &StepKinematics) -> Vec3 {
        let half = (0.5 * kin.dt) * kin.vel_grad;
        match (Mat3::identity() - half).try_inverse() {
            Some(inv) => {
                let df = inv * (Mat3::identity() + half);
                if admissible(&df) {
                    tangent_part(&kin.n_new, &(df * t_old))
                } else {
                    not_transportable()
                }
            }
            None => not_transportable(),
        }
    }

    #[inline]
    fn slip_direction(&self, x: &DirectionInputs<'_>) -> Option<Vec3> {
        forward_direction(&x.t_star, &x.t_end, &x.kin.n_new)
    }
}

/// Build the formulation (registry factory).
#[must_use]
pub fn build() -> Box<dyn KinematicFormulation> {
    Box::new(UpdatedLagrangian)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formulations::Lagrangian;
    use plugins_api::kinematics::cayley;

    fn kin() -> StepKinematics {
        let mut k = StepKinematics::simple(
            1e-2,
            Vec3::new(0.1, -0.2, 1.0).normalize(),
            Vec3::new(0.25, 0.05, 1.0).normalize(),
        );
        k.vel_grad = Mat3::new(0.3, 1.2, -0.4, -0.7, 0.1, 0.9, 0.5, -1.1, -0.2);
        k
    }

    fn tangent_history(k: &StepKinematics) -> Vec3 {
        let v = Vec3::new(3.0, -7.0, 2.0);
        v - k.n_old * k.n_old.dot(&v)
    }

    /// friction-math §4 (updated-lagrangian row): the transported traction is
    /// tangent to `n_{n+1}` (tolerance 1e-14 relative).
    #[test]
    fn transported_traction_is_tangent() {
        let k = kin();
        let t = tangent_history(&k);
        assert!(UpdatedLagrangian.transport(&t, &k).dot(&k.n_new).abs() <= 1e-14 * t.norm());
    }

    /// Zero history stays zero (exactly).
    #[test]
    fn zero_history_stays_zero() {
        assert_eq!(
            UpdatedLagrangian.transport(&Vec3::zeros(), &kin()),
            Vec3::zeros()
        );
    }

    /// friction-math §4: with `F_{n+1} F_n⁻¹ = cay(Δt L)` the updated and total
    /// Lagrangian transports coincide (tolerance 1e-13 relative).
    #[test]
    fn shares_the_transport_of_lagrangian() {
        let mut k = kin();
        k.f_old = Mat3::new(1.1, 0.2, 0.0, -0.1, 0.95, 0.05, 0.0, 0.1, 1.0);
        k.f_new = cayley(&(k.dt * k.vel_grad)) * k.f_old;
        let t = tangent_history(&k);
        let ul = UpdatedLagrangian.transport(&t, &k);
        let tl = Lagrangian.transport(&t, &k);
        assert!((ul - tl).norm() <= 1e-13 * t.norm(), "{ul} vs {tl}");
    }

    /// A step with `Δt λ ≥ 2` for a real eigenvalue `λ` of `L` has no admissible
    /// step gradient: the transport is NaN (so the return mapping errors) and the
    /// slip direction falls back to backward Euler.
    #[test]
    fn inadmissible_step_gradient_is_not_transported() {
        let mut k = kin();
        k.vel_grad = Mat3::from_diagonal(&Vec3::new(200.0, 0.0, 0.0));
        let t = tangent_history(&k);
        assert!(
            UpdatedLagrangian
                .transport(&t, &k)
                .iter()
                .all(|v| v.is_nan())
        );
        k.vel_grad = Mat3::from_diagonal(&Vec3::new(300.0, 0.0, 0.0));
        assert!(
            UpdatedLagrangian
                .transport(&t, &k)
                .iter()
                .all(|v| v.is_nan())
        );
        let x = DirectionInputs {
            kin: &k,
            t_old: t,
            p_old: 10.0,
            t_trial: Vec3::x(),
            p_new: 10.0,
        };
        assert_eq!(UpdatedLagrangian.slip_direction(&x), None);
        assert_eq!(UpdatedLagrangian.needs(), PointNeeds::VELOCITY_GRADIENT);
        assert_eq!(build().name(), NAME);
    }
}
