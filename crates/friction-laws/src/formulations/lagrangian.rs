//! The `lagrangian` formulation: total-Lagrangian push-forward of the history with the blank's deformation (friction-math §4, thesis eqs. 2.57–2.60).

use plugins_api::kinematics::forward_direction;
use plugins_api::{DirectionInputs, KinematicFormulation, PointNeeds, StepKinematics, Vec3};

use super::{admissible, not_transportable, tangent_part};

/// Name as typed in scenes.
pub const NAME: &str = "lagrangian";

/// One-line summary for registries and the CLI.
pub const SUMMARY: &str = "total Lagrangian: history pushed forward by F_{n+1} F_n^-1 and projected; d = phi_n + dt phi_dot (convected rate)";

/// The total-Lagrangian formulation of friction-math §4.
///
/// (a) Transport, with `ΔF = F_{n+1} F_n⁻¹` from the total deformation gradients:
///
/// ```text
/// t* = (I - n_{n+1}⊗n_{n+1}) ΔF t_n
/// ```
///
/// If `F_n` or `F_{n+1}` is not admissible (`det F ≤ 0` or not finite) the
/// history cannot be carried: the transport returns NaN, which the shared
/// return mapping reports as a `NonFiniteResult` error of this formulation
/// (never a silent fallback to the old traction).
///
/// (b) Slip direction: the forward estimate `d = φ_n + Δt φ̇_n` of §4,
/// evaluated in the frame of step `n+1` where this formulation's transported
/// history `t*` lives (so that it uses objective quantities only and is exactly
/// objective): `d = φ* + (I - φ*⊗φ*)(t_end - t*)/|t*|`
/// ([`forward_direction`](plugins_api::kinematics::forward_direction): the
/// closed-form `φ̇` with `ṅ = 0` in the co-moving frame and `Δt Ṫ = t_end - t*`,
/// `t_end = τ_c(ω_n) φ_tr` the radial-return traction, the `Δ²γ` term dropped).
/// The deformation enters through `t* = P ΔF t_n`: the direction is advanced
/// by the convected (push-forward) rate, eqs. 2.57–2.60. `None` when `|t*| = 0`.
///
/// Needs [`PointNeeds::DEFORMATION_GRADIENT`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Lagrangian;

impl KinematicFormulation for Lagrangian {
    fn name(&self) -> &str {
        NAME
    }

    fn needs(&self) -> PointNeeds {
        PointNeeds::DEFORMATION_GRADIENT
    }

    #[inline]
    fn transport(&self, t_old: &Vec3, kin: &StepKinematics) -> Vec3 {
        if !(admissible(&kin.f_old) && admissible(&kin.f_new)) {
            return not_transportable();
        }
        match kin.f_old.try_inverse() {
            Some(f_old_inv) => tangent_part(&kin.n_new, &(kin.f_new * (f_old_inv * t_old))),
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
    Box::new(Lagrangian)
}

#[cfg(test)]
mod tests {
    use super::*;
    use plugins_api::return_mapping::{PointState, StepInput, TangentMode, step};
    use plugins_api::{CriticalShear, FrictionError, FrictionLaw, ShearInputs};

    struct Coulomb;
    impl FrictionLaw for Coulomb {
        fn name(&self) -> &str {
            "test-coulomb"
        }
        fn stick_stiffness(&self) -> f64 {
            1e5
        }
        fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
            CriticalShear {
                tau: 0.1 * x.p,
                dtau_dp: 0.1,
                ..CriticalShear::default()
            }
        }
    }

    fn kin() -> StepKinematics {
        let mut k = StepKinematics::simple(
            1e-2,
            Vec3::new(0.1, -0.2, 1.0).normalize(),
            Vec3::new(0.25, 0.05, 1.0).normalize(),
        );
        k.f_old = Mat3::new(1.1, 0.2, 0.0, -0.1, 0.95, 0.05, 0.0, 0.1, 1.0);
        k.f_new = Mat3::new(1.12, 0.25, 0.01, -0.12, 0.93, 0.06, 0.01, 0.1, 1.01);
        k
    }

    fn tangent_history(k: &StepKinematics) -> Vec3 {
        let v = Vec3::new(3.0, -7.0, 2.0);
        v - k.n_old * k.n_old.dot(&v)
    }

    /// friction-math §4 (lagrangian row): after the push-forward the traction is
    /// re-projected, so it is tangent to `n_{n+1}` (tolerance 1e-14 relative).
    #[test]
    fn transported_traction_is_tangent() {
        let k = kin();
        let t = tangent_history(&k);
        let s = Lagrangian.transport(&t, &k);
        assert!(s.dot(&k.n_new).abs() <= 1e-14 * t.norm());
        let expected = tangent_part(&k.n_new, &(k.f_new * k.f_old.try_inverse().unwrap() * t));
        assert!((s - expected).norm() <= 1e-14 * t.norm());
    }

    /// Zero history stays zero (exactly).
    #[test]
    fn zero_history_stays_zero() {
        assert_eq!(Lagrangian.transport(&Vec3::zeros(), &kin()), Vec3::zeros());
    }

    /// Without deformation (`F_{n+1} = F_n`) on a flat fixed tool the history is unchanged.
    #[test]
    fn no_deformation_leaves_history_unchanged() {
        let mut k = kin();
        k.n_new = k.n_old;
        k.f_new = k.f_old;
        let t = tangent_history(&k);
        assert!((Lagrangian.transport(&t, &k) - t).norm() <= 1e-14 * t.norm());
    }

    /// A singular deformation gradient must not be swallowed: the transport is
    /// non-finite and the shared return mapping reports an error naming the formulation.
    #[test]
    fn singular_deformation_gradient_is_an_error() {
        let mut k = kin();
        k.f_old = Mat3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0);
        let t = tangent_history(&k);
        assert!(Lagrangian.transport(&t, &k).iter().all(|v| v.is_nan()));
        let mut state = PointState {
            t,
            p: 50.0,
            omega: 0.0,
        };
        let before = state;
        let input = StepInput::new(50.0, Vec3::new(1e-4, 0.0, 0.0), k);
        let err = step(&Coulomb, &Lagrangian, TangentMode::None, &mut state, &input).unwrap_err();
        assert!(
            matches!(err, FrictionError::NonFiniteResult { ref component, .. } if component == NAME),
            "{err}"
        );
        assert_eq!(state, before, "state must be left unchanged on error");
        // An inverted one (det < 0) likewise.
        k.f_old = Mat3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0);
        assert!(Lagrangian.transport(&t, &k).iter().all(|v| v.is_nan()));
    }

    /// With no history, or a singular `F`, the slip direction falls back to backward Euler.
    #[test]
    fn slip_direction_edge_cases() {
        let mut k = kin();
        let x = DirectionInputs {
            kin: &k,
            t_old: Vec3::zeros(),
            p_old: 10.0,
            t_trial: Vec3::x(),
            p_new: 10.0,
        };
        assert_eq!(Lagrangian.slip_direction(&x), None);
        k.f_new = Mat3::zeros();
        let x = DirectionInputs {
            kin: &k,
            t_old: tangent_history(&k),
            p_old: 10.0,
            t_trial: Vec3::x(),
            p_new: 10.0,
        };
        assert_eq!(Lagrangian.slip_direction(&x), None);
        assert_eq!(Lagrangian.needs(), PointNeeds::DEFORMATION_GRADIENT);
        assert_eq!(build().name(), NAME);
    }
}
