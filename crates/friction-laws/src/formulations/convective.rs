//! The `convective` formulation: parallel transport of the history with the tool surface (friction-math §4).

use plugins_api::kinematics::{is_identity, rotate_minimal};
use plugins_api::{DirectionInputs, KinematicFormulation, PointNeeds, StepKinematics, Vec3};

/// Name as typed in scenes.
pub const NAME: &str = "convective";

/// CPU time of a run with this formulation relative to the same run with
/// `convective`: 1, the others' costs are relative to it (docs/s-rail.md).
pub const RELATIVE_COST: f64 = 1.0;

/// One-line summary for registries and the CLI.
pub const SUMMARY: &str = "standard: history carried by the tool's rigid rotation and the minimal rotation n_n -> n_{n+1}; d = phi_tr (backward Euler)";

/// The standard (convective) formulation of friction-math §4.
///
/// (a) Transport: with `R_tool` the rigid rotation of the tool over the step
/// ([`StepKinematics::tool_rotation`], the identity for a fixed tool),
///
/// ```text
/// t* = R_min(R_tool n_n → n_{n+1}) · R_tool t_n
/// ```
///
/// where `R_min(a → b)` is the minimal rotation about `a × b`
/// ([`rotate_minimal`]). It depends only on the normals, never on a surface
/// parametrisation, so nothing jumps at patch seams; it preserves `|t_n|` and
/// maps the tangent plane of `n_n` onto that of `n_{n+1}`.
///
/// (b) Slip direction: `None`, i.e. backward Euler `d = φ_tr`.
///
/// Needs [`PointNeeds::TOOL_ROTATION`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Convective;

impl KinematicFormulation for Convective {
    fn name(&self) -> &str {
        NAME
    }

    fn needs(&self) -> PointNeeds {
        PointNeeds::TOOL_ROTATION
    }

    #[inline(always)]
    fn transport(&self, t_old: &Vec3, kin: &StepKinematics) -> Vec3 {
        if is_identity(&kin.tool_rotation) {
            // A fixed tool (the common case): skip two matrix-vector products.
            rotate_minimal(&kin.n_old, &kin.n_new, t_old)
        } else {
            rotating_tool(t_old, kin)
        }
    }

    #[inline]
    fn slip_direction(&self, _x: &DirectionInputs<'_>) -> Option<Vec3> {
        None
    }

    #[inline]
    fn backward_euler(&self) -> bool {
        true
    }
}

/// [`Convective::transport`] for a tool that rotates over the step (kept out
/// of line: the fixed tool is the hot case).
#[inline(never)]
fn rotating_tool(t_old: &Vec3, kin: &StepKinematics) -> Vec3 {
    let r = &kin.tool_rotation;
    rotate_minimal(&(r * kin.n_old), &kin.n_new, &(r * t_old))
}

#[cfg(test)]
mod tests {
    use super::*;
    use plugins_api::Mat3;
    use plugins_api::kinematics::{cayley, skew};

    fn kin() -> StepKinematics {
        let mut k = StepKinematics::simple(
            1e-3,
            Vec3::new(0.1, -0.2, 1.0).normalize(),
            Vec3::new(0.25, 0.05, 1.0).normalize(),
        );
        k.tool_rotation = cayley(&skew(&Vec3::new(0.02, -0.05, 0.03)));
        k
    }

    fn tangent_history(k: &StepKinematics) -> Vec3 {
        let v = Vec3::new(3.0, -7.0, 2.0);
        v - k.n_old * k.n_old.dot(&v)
    }

    /// friction-math §4 (convective row): the transported traction is tangent to
    /// `n_{n+1}` and keeps its length (a rotation). Tolerance 1e-14 relative.
    #[test]
    fn transported_traction_is_tangent_and_keeps_length() {
        let k = kin();
        let t = tangent_history(&k);
        let s = Convective.transport(&t, &k);
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
        assert_eq!(Convective.transport(&Vec3::zeros(), &kin()), Vec3::zeros());
    }

    /// A fixed tool with `n_{n+1} = n_n` leaves the history bit-for-bit unchanged.
    #[test]
    fn fixed_flat_tool_leaves_history_unchanged() {
        let n = Vec3::z();
        let k = StepKinematics::simple(1e-3, n, n);
        let t = Vec3::new(1.5, -2.5, 0.0);
        assert_eq!(k.tool_rotation, Mat3::identity());
        assert_eq!(Convective.transport(&t, &k), t);
    }

    /// A pure rigid tool rotation carries the traction rigidly: `t* = R t_n` when
    /// `n_{n+1} = R n_n` (tolerance 1e-14).
    #[test]
    fn rigid_tool_rotation_is_carried_rigidly() {
        let mut k = kin();
        k.n_new = k.tool_rotation * k.n_old;
        let t = tangent_history(&k);
        let s = Convective.transport(&t, &k);
        assert!((s - k.tool_rotation * t).norm() <= 1e-14 * t.norm());
    }

    /// friction-math §4 (convective row): `d = φ_tr` (backward Euler), i.e. no
    /// direction of its own, whatever the history, trial and end tractions.
    #[test]
    fn needs_tool_rotation_and_uses_backward_euler() {
        assert_eq!(Convective.needs(), PointNeeds::TOOL_ROTATION);
        assert_eq!(Convective.name(), NAME);
        let k = kin();
        let t_old = tangent_history(&k);
        let t_star = Convective.transport(&t_old, &k);
        let t_trial = t_star - 1e5 * Vec3::new(1e-4, -2e-4, 0.0);
        let x = DirectionInputs {
            kin: &k,
            t_old,
            p_old: 10.0,
            t_star,
            t_trial,
            t_end: 1.44 * t_trial / t_trial.norm(),
            p_new: 10.0,
        };
        assert_eq!(Convective.slip_direction(&x), None);
    }
}
