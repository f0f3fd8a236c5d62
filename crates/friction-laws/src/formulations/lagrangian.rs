//! The `lagrangian` formulation: total-Lagrangian push-forward of the history with the blank's deformation (friction-math §4, thesis eqs. 2.57–2.60).

use plugins_api::kinematics::{forward_direction, tangent_part};
use plugins_api::{DirectionInputs, KinematicFormulation, PointNeeds, StepKinematics, Vec3};

use super::{admissible, not_transportable};

/// Name as typed in scenes.
pub const NAME: &str = "lagrangian";

/// CPU time of a run with this formulation relative to the same run with
/// `convective` (1.40–1.47 on the fine S-rail, one per law: docs/s-rail.md); orders a batch's runs, largest
/// first.
pub const RELATIVE_COST: f64 = 1.44;

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
/// (b) Slip direction: the forward estimate `d = φ* + Δt φ̇` in the frame of
/// step `n+1` ([`plugins_api::kinematics::forward_direction`]; see the
/// [module docs](super) for why that frame).
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

    #[inline(always)]
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

#[cfg(test)]
mod tests {
    use super::*;
    use plugins_api::kinematics::{cayley, skew};
    use plugins_api::return_mapping::{PointState, StepInput, TangentMode, step};
    use plugins_api::{CriticalShear, FrictionError, FrictionLaw, Mat3, ShearInputs};

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

    /// Orthonormal tangent basis `(e1, e2)` of the unit normal `n`.
    fn tangent_basis(n: &Vec3) -> (Vec3, Vec3) {
        let v = Vec3::new(1.0, 0.3, -0.2);
        let e1 = (v - n * n.dot(&v)).normalize();
        (e1, n.cross(&e1))
    }

    /// Direction inputs with the given transported history and end traction;
    /// the other fields are arbitrary (the direction must not read them).
    fn inputs(k: &StepKinematics, t_star: Vec3, t_end: Vec3) -> DirectionInputs<'_> {
        DirectionInputs {
            kin: k,
            t_old: tangent_history(k),
            p_old: 10.0,
            t_star,
            t_trial: t_end * 3.0,
            t_end,
            p_new: 12.0,
        }
    }

    /// friction-math §4 (lagrangian row, (b)): no transported history (`|t*| = 0`)
    /// gives `None` (backward Euler); so does the NaN `t*` of a singular `F`
    /// (the return mapping errors before asking, but the direction must not be NaN).
    #[test]
    fn slip_direction_is_none_without_transported_history() {
        let mut k = kin();
        let (e1, _) = tangent_basis(&k.n_new);
        assert_eq!(
            Lagrangian.slip_direction(&inputs(&k, Vec3::zeros(), e1)),
            None
        );
        k.f_new = Mat3::zeros();
        let t_star = Lagrangian.transport(&tangent_history(&k), &k);
        assert!(t_star.iter().all(|v| v.is_nan()));
        assert_eq!(Lagrangian.slip_direction(&inputs(&k, t_star, e1)), None);
        assert_eq!(Lagrangian.needs(), PointNeeds::DEFORMATION_GRADIENT);
        assert_eq!(Lagrangian.name(), NAME);
    }

    /// `forward_direction`: an end traction parallel to `t*` (any magnitude or
    /// sense) gives `d = φ*` (tolerance 2e-16 absolute); a general one gives
    /// `d = e1 + (c/a) e2` for `t* = a e1`, `t_end = b e1 + c e2` (1e-15 relative).
    #[test]
    fn slip_direction_follows_the_closed_form() {
        let k = kin();
        let (e1, e2) = tangent_basis(&k.n_new);
        let t_star = 7.0 * e1 - 3.0 * e2;
        let phi_star = t_star / t_star.norm();
        for scale in [0.3, 1.0, 2.5, -1.0] {
            let d = Lagrangian
                .slip_direction(&inputs(&k, t_star, scale * t_star))
                .unwrap();
            assert!(
                (d - phi_star).norm() <= 2e-16,
                "scale {scale}: {d} vs {phi_star}"
            );
        }
        let (a, b, c) = (11.0, 10.5, 0.8);
        let d = Lagrangian
            .slip_direction(&inputs(&k, a * e1, b * e1 + c * e2))
            .unwrap();
        let expected = e1 + (c / a) * e2;
        assert!(
            (d - expected).norm() <= 1e-15 * expected.norm(),
            "{d} vs {expected}"
        );
    }

    /// The deformation enters the direction only through `t* = P ΔF t_n`: with the
    /// same `t*` and `t_end`, different `F_n`, `F_{n+1}` (and `t_n`, pressures,
    /// trial) give the bit-identical direction.
    #[test]
    fn slip_direction_reads_only_transported_and_end_tractions() {
        let k = kin();
        let (e1, e2) = tangent_basis(&k.n_new);
        let (t_star, t_end) = (9.0 * e1 + 2.0 * e2, 8.0 * e1 + 4.5 * e2);
        let d = Lagrangian.slip_direction(&inputs(&k, t_star, t_end));
        let mut other = k;
        other.f_old = Mat3::identity();
        other.f_new = Mat3::new(1.3, 0.4, 0.0, 0.0, 0.8, 0.1, 0.2, 0.0, 1.1);
        other.n_old = Vec3::new(-0.4, 0.3, 1.0).normalize();
        let x = DirectionInputs {
            kin: &other,
            t_old: Vec3::new(-1.0, 5.0, 0.0),
            p_old: 99.0,
            t_star,
            t_trial: -t_end,
            t_end,
            p_new: 1.0,
        };
        assert!(d.is_some());
        assert_eq!(Lagrangian.slip_direction(&x), d);
    }

    /// friction-math §4, "Objectivity": with `F' = Q F` (both steps), `n' = Q n`,
    /// the transported history is `Q t*` and the direction `Q d`. Tolerance 1e-14
    /// relative on both.
    #[test]
    fn transport_and_slip_direction_are_objective() {
        let k = kin();
        let q = cayley(&skew(&Vec3::new(0.9, -1.7, 0.4)));
        let mut kq = k;
        kq.n_old = q * k.n_old;
        kq.n_new = q * k.n_new;
        kq.f_old = q * k.f_old;
        kq.f_new = q * k.f_new;
        let t = tangent_history(&k);
        let t_star = Lagrangian.transport(&t, &k);
        let t_star_q = Lagrangian.transport(&(q * t), &kq);
        assert!((t_star_q - q * t_star).norm() <= 1e-14 * t_star.norm());
        let (e1, e2) = tangent_basis(&k.n_new);
        let t_end = 0.9 * t_star.norm() * (0.95 * e1 + 0.3 * e2);
        let d = Lagrangian
            .slip_direction(&inputs(&k, t_star, t_end))
            .unwrap();
        let dq = Lagrangian
            .slip_direction(&inputs(&kq, t_star_q, q * t_end))
            .unwrap();
        assert!((dq - q * d).norm() <= 1e-14 * d.norm(), "{dq} vs {}", q * d);
    }
}
