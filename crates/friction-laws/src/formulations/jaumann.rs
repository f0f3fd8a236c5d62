//! The `jaumann` formulation: co-rotational (Eulerian) transport with the blank spin (friction-math §4, thesis eqs. 2.42–2.43, 2.67).

use plugins_api::kinematics::{cayley, forward_direction, rotate_minimal};
use plugins_api::{DirectionInputs, KinematicFormulation, PointNeeds, StepKinematics, Vec3};

/// Name as typed in scenes.
pub const NAME: &str = "jaumann";

/// One-line summary for registries and the CLI.
pub const SUMMARY: &str = "co-rotational: history rotated by the blank spin (Hughes-Winget) then onto the new tangent plane; d = phi_n + dt (phi_dot - W phi) in the spun frame";

/// The co-rotational (Jaumann, Eulerian) formulation of friction-math §4, the
/// thesis's new model.
///
/// (a) Transport, with `W = (L - Lᵀ)/2` the blank spin at mid-step:
///
/// ```text
/// R_W = (I - ½ΔtW)⁻¹ (I + ½ΔtW)          (Hughes–Winget, an exact rotation)
/// t*  = R_surf R_W t_n,   R_surf = R_min(R_W n_n → n_{n+1})
/// ```
///
/// so the history first spins with the material and is then carried, by the
/// minimal rotation, onto the tangent plane of the new normal. With `W = 0`
/// it is bit-for-bit the transport of [`Convective`](super::Convective) on a
/// fixed tool.
///
/// (b) Slip direction: the forward estimate `d = φ_n + Δt φ̇_n` of §4,
/// evaluated in the frame of step `n+1` where this formulation's transported
/// history `t*` lives (so that it uses objective quantities only and is exactly
/// objective): `d = φ* + (I - φ*⊗φ*)(t_end - t*)/|t*|`
/// ([`forward_direction`](plugins_api::kinematics::forward_direction): the
/// closed-form `φ̇` with `ṅ = 0` in the co-moving frame and `Δt Ṫ = t_end - t*`,
/// `t_end = τ_c(ω_n) φ_tr` the radial-return traction, the `Δ²γ` term dropped).
/// The spin enters through `t*`: advancing the direction by the Jaumann rate
/// `φ̇ - Wφ` is advancing the spun direction `R_W φ_n` by the material rate.
/// `None` (backward Euler) when `|t*| = 0`.
///
/// Needs [`PointNeeds::SPIN`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Jaumann;

impl KinematicFormulation for Jaumann {
    fn name(&self) -> &str {
        NAME
    }

    fn needs(&self) -> PointNeeds {
        PointNeeds::SPIN
    }

    #[inline]
    fn transport(&self, t_old: &Vec3, kin: &StepKinematics) -> Vec3 {
        let r_w = cayley(&(kin.dt * kin.spin()));
        rotate_minimal(&(r_w * kin.n_old), &kin.n_new, &(r_w * t_old))
    }

    #[inline]
    fn slip_direction(&self, x: &DirectionInputs<'_>) -> Option<Vec3> {
        forward_direction(&x.t_star, &x.t_end, &x.kin.n_new)
    }
}

/// Build the formulation (registry factory).
#[must_use]
pub fn build() -> Box<dyn KinematicFormulation> {
    Box::new(Jaumann)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formulations::Convective;
    use plugins_api::Mat3;
    use plugins_api::kinematics::skew;

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

    /// friction-math §4 (jaumann row): the transported traction is tangent to
    /// `n_{n+1}` and keeps its length (two rotations). Tolerance 1e-14 relative.
    #[test]
    fn transported_traction_is_tangent_and_keeps_length() {
        let k = kin();
        let t = tangent_history(&k);
        let s = Jaumann.transport(&t, &k);
        assert!(
            s.dot(&k.n_new).abs() <= 1e-14 * t.norm(),
            "normal part {}",
            s.dot(&k.n_new)
        );
        assert!((s.norm() - t.norm()).abs() <= 1e-14 * t.norm());
    }

    /// Zero history stays zero (exactly).
    #[test]
    fn zero_history_stays_zero() {
        assert_eq!(Jaumann.transport(&Vec3::zeros(), &kin()), Vec3::zeros());
    }

    /// friction-math §4: `jaumann` equals `convective` exactly whenever `W = 0`
    /// (fixed tool); a symmetric `L` has no spin. Bit-for-bit.
    #[test]
    fn equals_convective_bitwise_without_spin() {
        let mut k = kin();
        k.vel_grad = 0.5 * (k.vel_grad + k.vel_grad.transpose());
        let t = tangent_history(&k);
        assert_eq!(Jaumann.transport(&t, &k), Convective.transport(&t, &k));
    }

    /// A blank spinning rigidly with the tool normal (`n_{n+1} = R_W n_n`) carries
    /// the history rigidly: `t* = R_W t_n` (tolerance 1e-14).
    #[test]
    fn rigid_spin_is_carried_rigidly() {
        let mut k = kin();
        k.vel_grad = skew(&Vec3::new(0.4, -1.0, 0.7));
        let r_w = cayley(&(k.dt * k.spin()));
        k.n_new = r_w * k.n_old;
        let t = tangent_history(&k);
        assert!((Jaumann.transport(&t, &k) - r_w * t).norm() <= 1e-14 * t.norm());
    }

    /// With no history the slip direction falls back to backward Euler; with a
    /// history and `W = 0`, unchanged normals and a trial along `t_n`, `d = φ_n`.
    #[test]
    fn slip_direction_edge_cases() {
        let k = kin();
        let x = DirectionInputs {
            kin: &k,
            t_old: Vec3::zeros(),
            p_old: 10.0,
            t_trial: Vec3::x(),
            p_new: 10.0,
        };
        assert_eq!(Jaumann.slip_direction(&x), None);
        let n = Vec3::z();
        let k = StepKinematics::simple(1e-3, n, n);
        let t = Vec3::new(3.0, 4.0, 0.0);
        let x = DirectionInputs {
            kin: &k,
            t_old: t,
            p_old: 10.0,
            t_trial: 2.0 * t,
            p_new: 12.0,
        };
        let d = Jaumann.slip_direction(&x).unwrap();
        assert!((d - t / 5.0).norm() <= 1e-15);
        assert_eq!(Jaumann.needs(), PointNeeds::SPIN);
        assert_eq!(build().name(), NAME);
    }
}
