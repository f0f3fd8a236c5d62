//! The built-in friction laws of friction-math §3: `ac`, `wvs`, `wh`, `levanov`.
//!
//! Each law is a plain struct holding its validated parameters and implementing
//! [`plugins_api::FrictionLaw`]; the return mapping is the shared one in
//! `plugins_api::return_mapping`. Every law exposes the same building blocks so
//! that registration happens in one place: `NAME`, `PARAMS` (schema in builder
//! order), `DESCRIPTION`, `from_values` (values in `PARAMS` order, all
//! validation), `build` (boxed) and a typed `new`.

use plugins_api::ParamSpec;
use plugins_api::law::LawDescription;

mod ac;
mod levanov;
mod wh;
mod wvs;

pub use ac::Ac;
pub use levanov::Levanov;
pub use wh::Wh;
pub use wvs::Wvs;

/// Descriptions (name, summary, parameter schema) of the four built-in laws,
/// in the order of [`crate::builtin::LAW_NAMES`].
pub const DESCRIPTIONS: &[LawDescription] = &[
    Ac::DESCRIPTION,
    Wvs::DESCRIPTION,
    Wh::DESCRIPTION,
    Levanov::DESCRIPTION,
];

/// Default stick stiffness `k_T` (MPa/mm). At 1e4 MPa/mm the elastic slip
/// before sliding, `τ_c / k_T`, stays below 1e-3 mm for friction stresses up
/// to 10 MPa: far below the element sizes (1–5 mm) and slip distances (mm)
/// of forming. The thesis's "100 GPa" read as 1e5 MPa/mm gives no more
/// accuracy, and on contact nodes its spring sets the mass that fixed-step
/// mass scaling adds (docs/friction-math.md, "The stick stiffness").
pub const DEFAULT_STICK_STIFFNESS: f64 = 1e4;

/// Schema of the stick stiffness `k_T`, shared by every law (last in each `PARAMS`).
pub const STICK_STIFFNESS: ParamSpec = ParamSpec::optional(
    "k_t",
    "MPa/mm",
    DEFAULT_STICK_STIFFNESS,
    0.0,
    f64::INFINITY,
    "tangential stiffness in stick k_T (MPa/mm), a penalty-like regularisation",
)
.exclusive_min();

/// Helpers shared by the laws' unit tests.
#[cfg(test)]
pub(crate) mod test_support {
    use plugins_api::{
        DirectionInputs, FrictionLaw, KinematicFormulation, PointNeeds, ShearInputs,
        StepKinematics, Vec3,
    };

    /// A trivial formulation for point histories on a fixed flat tool:
    /// transport = identity, backward-Euler slip direction, needs nothing.
    pub(crate) struct Identity;

    impl KinematicFormulation for Identity {
        fn name(&self) -> &str {
            "test-identity"
        }
        fn needs(&self) -> PointNeeds {
            PointNeeds::NONE
        }
        fn transport(&self, t_old: &Vec3, _kin: &StepKinematics) -> Vec3 {
            *t_old
        }
        fn slip_direction(&self, _x: &DirectionInputs<'_>) -> Option<Vec3> {
            None
        }
    }

    /// Kinematics of a step over a fixed flat tool with normal `+z`.
    pub(crate) fn flat_kinematics() -> StepKinematics {
        let n = Vec3::new(0.0, 0.0, 1.0);
        StepKinematics::simple(1e-3, n, n)
    }

    /// Shear inputs at `(p, ω)` with flow stress `sigma_y`; other fields NaN
    /// (not computed), as the engine leaves them.
    pub(crate) fn inputs(p: f64, omega: f64, sigma_y: f64) -> ShearInputs {
        ShearInputs {
            p,
            omega,
            sliding_speed: f64::NAN,
            flow_stress: sigma_y,
            temperature: f64::NAN,
        }
    }

    /// Relative difference `|a - b| / |b|` (absolute if `b = 0`).
    pub(crate) fn rel(a: f64, b: f64) -> f64 {
        if b == 0.0 {
            (a - b).abs()
        } else {
            ((a - b) / b).abs()
        }
    }

    /// Central finite differences of `τ_c` with respect to `p` (step `h`) and
    /// `ω` (step `k`) at `x`.
    pub(crate) fn central_differences<L: FrictionLaw>(
        law: &L,
        x: &ShearInputs,
        h: f64,
        k: f64,
    ) -> (f64, f64) {
        let tau = |p: f64, omega: f64| law.critical_shear(&ShearInputs { p, omega, ..*x }).tau;
        let d_p = (tau(x.p + h, x.omega) - tau(x.p - h, x.omega)) / (2.0 * h);
        let d_omega = (tau(x.p, x.omega + k) - tau(x.p, x.omega - k)) / (2.0 * k);
        (d_p, d_omega)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The registry lists exactly the four laws of friction-math §3, each with
    /// `k_t` last in its schema and the same `k_t` spec.
    #[test]
    fn registered_names_match_descriptions_and_share_stick_stiffness() {
        assert_eq!(crate::builtin::LAW_NAMES, ["ac", "wvs", "wh", "levanov"]);
        for (name, d) in crate::builtin::LAW_NAMES.iter().zip(DESCRIPTIONS) {
            assert_eq!(*name, d.name);
            assert_eq!(d.params.last(), Some(&STICK_STIFFNESS), "{name}");
            assert!(!d.summary.is_empty());
        }
    }

    /// Wrong number of values: a clear error listing the expected parameters.
    #[test]
    fn wrong_value_count_is_rejected_with_parameter_list() {
        let e = Ac::from_values(&[0.1]).unwrap_err().to_string();
        assert!(
            e.contains("expected 2 parameter values (mu, k_t), got 1"),
            "{e}"
        );
    }
}
