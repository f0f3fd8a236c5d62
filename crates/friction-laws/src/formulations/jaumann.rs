//! The `jaumann` formulation: co-rotational (Eulerian) transport with the blank spin (friction-math §4, thesis eqs. 2.42–2.43, 2.67).

use plugins_api::kinematics::{axial, cayley_rotate, forward_direction, rotate_minimal};
use plugins_api::{DirectionInputs, KinematicFormulation, PointNeeds, StepKinematics, Vec3};

/// Name as typed in scenes.
pub const NAME: &str = "jaumann";

/// CPU time of a run with this formulation relative to the same run with
/// `convective` (1.29–1.36 on the fine S-rail, one per law: docs/s-rail.md); orders a batch's runs, largest
/// first.
pub const RELATIVE_COST: f64 = 1.32;

/// One-line summary for registries and the CLI.
pub const SUMMARY: &str = "co-rotational: history rotated by the blank spin (Hughes-Winget) then onto the new tangent plane; d = phi* + dt phi_dot in the spun frame (Jaumann rate)";

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
/// (b) Slip direction: the forward estimate `d = φ* + Δt φ̇` in the frame of
/// step `n+1` ([`plugins_api::kinematics::forward_direction`]; see the
/// [module docs](super) for why that frame).
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

    #[inline(always)]
    fn transport(&self, t_old: &Vec3, kin: &StepKinematics) -> Vec3 {
        // R_W = cay(Δt W) applied in closed form: a = ½Δt w, w = axial(W).
        let a = (0.5 * kin.dt) * axial(&kin.vel_grad);
        let n_spun = cayley_rotate(&a, &kin.n_old);
        rotate_minimal(&n_spun, &kin.n_new, &cayley_rotate(&a, t_old))
    }

    #[inline]
    fn slip_direction(&self, x: &DirectionInputs<'_>) -> Option<Vec3> {
        forward_direction(&x.t_star, &x.t_end, &x.kin.n_new)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formulations::Convective;
    use plugins_api::Mat3;
    use plugins_api::kinematics::{cayley, skew};

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

    /// friction-math §4 (jaumann row, (b)): with no transported history
    /// (`|t*| = 0`) there is no rate to advance, so `None` (backward Euler); a
    /// non-finite `t*` likewise gives `None`, never a NaN direction.
    #[test]
    fn slip_direction_is_none_without_transported_history() {
        let k = kin();
        let (e1, _) = tangent_basis(&k.n_new);
        assert_eq!(Jaumann.slip_direction(&inputs(&k, Vec3::zeros(), e1)), None);
        let nan = Vec3::repeat(f64::NAN);
        assert_eq!(Jaumann.slip_direction(&inputs(&k, nan, e1)), None);
    }

    /// `forward_direction`: when the end traction is parallel to `t*` (any
    /// magnitude, either sense) the direction rate vanishes and `d = φ*`
    /// (tolerance 2e-16 absolute). For the opposite sense (a reversal within the
    /// step) `d = φ*` is 180° from `φ_tr`; the return mapping then uses `φ_tr`.
    #[test]
    fn slip_direction_is_phi_star_when_end_traction_is_parallel() {
        let k = kin();
        let (e1, e2) = tangent_basis(&k.n_new);
        let t_star = 7.0 * e1 - 3.0 * e2;
        let phi_star = t_star / t_star.norm();
        for scale in [0.3, 1.0, 2.5, -1.0] {
            let d = Jaumann
                .slip_direction(&inputs(&k, t_star, scale * t_star))
                .unwrap();
            assert!(
                (d - phi_star).norm() <= 2e-16,
                "scale {scale}: {d} vs {phi_star}"
            );
        }
    }

    /// friction-math §4 (b): `d = φ* + (I - φ*⊗φ*)(t_end - t*)/|t*|`, checked in
    /// an explicit tangent basis of `n_{n+1}`: `t* = a e1`, `t_end = b e1 + c e2`
    /// gives `d = e1 + (c/a) e2` (tangent, not normalised). Tolerance 1e-15 relative.
    #[test]
    fn slip_direction_matches_closed_form_in_tangent_basis() {
        let k = kin();
        let (e1, e2) = tangent_basis(&k.n_new);
        let (a, b, c) = (11.0, 10.5, 0.8);
        let d = Jaumann
            .slip_direction(&inputs(&k, a * e1, b * e1 + c * e2))
            .unwrap();
        let expected = e1 + (c / a) * e2;
        assert!(
            (d - expected).norm() <= 1e-15 * expected.norm(),
            "{d} vs {expected}"
        );
        assert!(d.dot(&k.n_new).abs() <= 1e-15);
    }

    /// The direction reads only `t*`, `t_end` and `n_{n+1}` (objective data): the
    /// spin enters through `t*`. Changing `t_n`, the pressures, the trial, `L`,
    /// `n_n` or `Δt` leaves it bit-for-bit unchanged.
    #[test]
    fn slip_direction_reads_only_transported_and_end_tractions() {
        let k = kin();
        let (e1, e2) = tangent_basis(&k.n_new);
        let (t_star, t_end) = (9.0 * e1 + 2.0 * e2, 8.0 * e1 + 4.5 * e2);
        let d = Jaumann.slip_direction(&inputs(&k, t_star, t_end));
        let mut other = k;
        other.vel_grad = skew(&Vec3::new(-3.0, 2.0, 5.0));
        other.n_old = Vec3::new(-0.4, 0.3, 1.0).normalize();
        other.dt = 0.37;
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
        assert_eq!(Jaumann.slip_direction(&x), d);
    }

    /// friction-math §4, "Objectivity": an observer rotated by `Q` sees `n' = Q n`,
    /// `t*' = Q t*`, `t_end' = Q t_end` and must get `d' = Q d`. Tolerance 1e-14 relative.
    #[test]
    fn slip_direction_is_objective() {
        let k = kin();
        let (e1, e2) = tangent_basis(&k.n_new);
        let (t_star, t_end) = (9.0 * e1 + 2.0 * e2, 8.0 * e1 + 4.5 * e2);
        let d = Jaumann.slip_direction(&inputs(&k, t_star, t_end)).unwrap();
        let q = cayley(&skew(&Vec3::new(0.9, -1.7, 0.4)));
        let mut kq = k;
        kq.n_old = q * k.n_old;
        kq.n_new = q * k.n_new;
        let dq = Jaumann
            .slip_direction(&inputs(&kq, q * t_star, q * t_end))
            .unwrap();
        assert!((dq - q * d).norm() <= 1e-14 * d.norm(), "{dq} vs {}", q * d);
    }

    /// Accuracy of the forward estimate, independent of the slip per step: when the
    /// traction turns by `α` at constant magnitude (`|t_end| = |t*|`), `d = φ* +
    /// sin α e⊥` lies `α - atan(sin α) = α³/2 + O(α⁵)` from the end direction
    /// (derived from the closed form). Checked at α = 1e-2, 2e-2: `err/α³ = 0.5`
    /// within 1e-3.
    #[test]
    fn slip_direction_error_is_third_order_in_the_turn_angle() {
        let k = kin();
        let (e1, e2) = tangent_basis(&k.n_new);
        let t_star = 12.0 * e1;
        for alpha in [1e-2_f64, 2e-2] {
            let t_end = 12.0 * (alpha.cos() * e1 + alpha.sin() * e2);
            let d = Jaumann.slip_direction(&inputs(&k, t_star, t_end)).unwrap();
            let err = alpha - d.dot(&e2).atan2(d.dot(&e1));
            assert!(
                (err / alpha.powi(3) - 0.5).abs() <= 1e-3,
                "α = {alpha}: err {err:e}"
            );
        }
        assert_eq!(Jaumann.needs(), PointNeeds::SPIN);
        assert_eq!(Jaumann.name(), NAME);
    }
}
