//! The `updated-lagrangian` formulation: push-forward with the step deformation gradient `cay(Δt L)` (friction-math §4, thesis eqs. 2.61–2.65).

use plugins_api::kinematics::{forward_direction, tangent_part};
use plugins_api::{DirectionInputs, KinematicFormulation, Mat3, PointNeeds, StepKinematics, Vec3};

use super::not_transportable;

/// Name as typed in scenes.
pub const NAME: &str = "updated-lagrangian";

/// CPU time of a run with this formulation relative to the same run with
/// `convective` (1.31–1.34 on the fine S-rail, one per law: docs/s-rail.md); orders a batch's runs, largest
/// first.
pub const RELATIVE_COST: f64 = 1.32;

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
/// (b) Slip direction: the forward estimate `d = φ* + Δt φ̇` in the frame of
/// step `n+1` ([`plugins_api::kinematics::forward_direction`]; see the
/// [module docs](super) for why that frame).
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

    #[inline(always)]
    fn transport(&self, t_old: &Vec3, kin: &StepKinematics) -> Vec3 {
        // ΔF t = (I - ½ΔtL)⁻¹ (I + ½ΔtL) t, with det ΔF = det(I + ½ΔtL)/det(I - ½ΔtL).
        let half = (0.5 * kin.dt) * kin.vel_grad;
        let minus = Mat3::identity() - half;
        let plus = Mat3::identity() + half;
        let (det_minus, det_plus) = (minus.determinant(), plus.determinant());
        let admissible =
            det_minus.is_finite() && det_plus.is_finite() && det_minus * det_plus > 0.0;
        match minus.try_inverse().filter(|_| admissible) {
            Some(inv) => tangent_part(&kin.n_new, &(inv * (plus * t_old))),
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
    use crate::formulations::Lagrangian;
    use plugins_api::kinematics::{cayley, skew};
    use plugins_api::return_mapping::{PointState, StepInput, TangentMode, step};
    use plugins_api::{CriticalShear, FrictionLaw, ShearInputs};

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
        let t_star = UpdatedLagrangian.transport(&t, &k);
        assert_eq!(
            UpdatedLagrangian.slip_direction(&inputs(&k, t_star, Vec3::x())),
            None
        );
        assert_eq!(UpdatedLagrangian.needs(), PointNeeds::VELOCITY_GRADIENT);
        assert_eq!(UpdatedLagrangian.name(), NAME);
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

    /// friction-math §4 (updated-lagrangian row, (b)): `None` without transported
    /// history; `d = φ*` for an end traction parallel to `t*` (2e-16 absolute);
    /// `d = e1 + (c/a) e2` for `t* = a e1`, `t_end = b e1 + c e2` (1e-15 relative);
    /// and, with the same `t*` and `t_end`, `L` does not enter (bit-identical).
    #[test]
    fn slip_direction_follows_the_closed_form() {
        let k = kin();
        let (e1, e2) = tangent_basis(&k.n_new);
        assert_eq!(
            UpdatedLagrangian.slip_direction(&inputs(&k, Vec3::zeros(), e1)),
            None
        );
        let t_star = 7.0 * e1 - 3.0 * e2;
        let phi_star = t_star / t_star.norm();
        for scale in [0.3, 1.0, 2.5, -1.0] {
            let d = UpdatedLagrangian
                .slip_direction(&inputs(&k, t_star, scale * t_star))
                .unwrap();
            assert!(
                (d - phi_star).norm() <= 2e-16,
                "scale {scale}: {d} vs {phi_star}"
            );
        }
        let (a, b, c) = (11.0, 10.5, 0.8);
        let d = UpdatedLagrangian.slip_direction(&inputs(&k, a * e1, b * e1 + c * e2));
        let expected = e1 + (c / a) * e2;
        assert!((d.unwrap() - expected).norm() <= 1e-15 * expected.norm());
        let mut other = k;
        other.vel_grad = Mat3::from_diagonal(&Vec3::new(-4.0, 1.0, 2.0));
        assert_eq!(
            UpdatedLagrangian.slip_direction(&inputs(&other, a * e1, b * e1 + c * e2)),
            d
        );
    }

    /// friction-math §4, "Objectivity": with `L' = Ω + Q L Qᵀ` (a rotation `Q`
    /// spinning at rate `Ω`, so that `cay(Δt L') = Q_{n+1} cay(Δt L) Q_nᵀ`, built
    /// here directly as the inverse Cayley of that product), `n' = Q n`: the
    /// transported history is `Q_{n+1} t*` and the direction `Q_{n+1} d`.
    /// Tolerance 1e-13 relative (the inverse Cayley map costs a few ulps).
    #[test]
    fn transport_and_slip_direction_are_objective() {
        let k = kin();
        let q0 = cayley(&skew(&Vec3::new(0.9, -1.7, 0.4)));
        let q1 = cayley(&(k.dt * skew(&Vec3::new(2.0, 0.5, -1.0)))) * q0;
        let id = Mat3::identity();
        let df = q1 * cayley(&(k.dt * k.vel_grad)) * q0.transpose();
        let mut kq = k;
        kq.n_old = q0 * k.n_old;
        kq.n_new = q1 * k.n_new;
        kq.vel_grad = (2.0 / k.dt) * (df - id) * (df + id).try_inverse().unwrap();
        let t = tangent_history(&k);
        let t_star = UpdatedLagrangian.transport(&t, &k);
        let t_star_q = UpdatedLagrangian.transport(&(q0 * t), &kq);
        assert!(
            (t_star_q - q1 * t_star).norm() <= 1e-13 * t_star.norm(),
            "{t_star_q} vs {}",
            q1 * t_star
        );
        let (e1, e2) = tangent_basis(&k.n_new);
        let t_end = 0.9 * t_star.norm() * (0.95 * e1 + 0.3 * e2);
        let d = UpdatedLagrangian
            .slip_direction(&inputs(&k, t_star, t_end))
            .unwrap();
        let dq = UpdatedLagrangian
            .slip_direction(&inputs(&kq, t_star_q, q1 * t_end))
            .unwrap();
        assert!(
            (dq - q1 * d).norm() <= 1e-13 * d.norm(),
            "{dq} vs {}",
            q1 * d
        );
    }

    /// friction-math §4: with `L` the exact mid-step gradient of the motion giving
    /// `F` (`F_{n+1} = cay(Δt L) F_n`), `updated-lagrangian` and `lagrangian`
    /// coincide step by step: same `t*`, so same trial, same `d`, same slip and
    /// work. One slipping step of a work-dependent law through the shared return
    /// mapping; traction, `ω` and the consistent tangent agree to 1e-12 relative.
    #[test]
    fn coincides_with_lagrangian_on_consistent_data() {
        struct Work;
        impl FrictionLaw for Work {
            fn name(&self) -> &str {
                "test-work"
            }
            fn stick_stiffness(&self) -> f64 {
                1e5
            }
            fn work_dependent(&self) -> bool {
                true
            }
            fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
                let mu = 0.1448 - 8.757e-5 * x.omega;
                CriticalShear {
                    tau: mu * x.p,
                    dtau_dp: mu,
                    dtau_domega: -8.757e-5 * x.p,
                    ..CriticalShear::default()
                }
            }
        }
        let mut k = kin();
        k.f_old = Mat3::new(1.1, 0.2, 0.0, -0.1, 0.95, 0.05, 0.0, 0.1, 1.0);
        k.f_new = cayley(&(k.dt * k.vel_grad)) * k.f_old;
        let t = 10.0 * tangent_history(&k).normalize();
        let state = PointState {
            t,
            p: 80.0,
            omega: 50.0,
        };
        let (e1, e2) = tangent_basis(&k.n_new);
        let input = StepInput::new(85.0, 2e-3 * e1 - 5e-4 * e2, k);
        let (mut s_tl, mut s_ul) = (state, state);
        let tl = step(
            &Work,
            &Lagrangian,
            TangentMode::Consistent,
            &mut s_tl,
            &input,
        )
        .unwrap();
        let ul = step(
            &Work,
            &UpdatedLagrangian,
            TangentMode::Consistent,
            &mut s_ul,
            &input,
        )
        .unwrap();
        assert!(!tl.stick && tl.dissipation > 0.0);
        assert!(
            (tl.t - ul.t).norm() <= 1e-12 * tl.t.norm(),
            "{} vs {}",
            tl.t,
            ul.t
        );
        assert!((s_tl.omega - s_ul.omega).abs() <= 1e-12 * s_tl.omega);
        assert!((tl.tangent - ul.tangent).norm() <= 1e-12 * tl.tangent.norm());
    }
}
