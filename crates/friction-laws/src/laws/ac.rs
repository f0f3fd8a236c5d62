//! Amontons–Coulomb friction, `τ_c = μ p` (friction-math §3, thesis eq. 2.13).

use plugins_api::law::LawDescription;
use plugins_api::{CriticalShear, FrictionError, FrictionLaw, ParamSpec, ShearInputs};

use super::STICK_STIFFNESS;
use plugins_api::params::check_values;

/// Amontons–Coulomb friction: `Φ = |t| - μ p` (eq. 2.13).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ac {
    mu: f64,
    k_t: f64,
}

impl Ac {
    /// Name as typed in scenes.
    pub const NAME: &'static str = "ac";

    /// Parameter schema, in the order `from_values` receives the values.
    pub const PARAMS: &'static [ParamSpec] = &[
        ParamSpec::required("mu", "-", 0.0, f64::INFINITY, "friction coefficient μ (-)"),
        STICK_STIFFNESS,
    ];

    /// Name, one-line summary and parameter schema.
    pub const DESCRIPTION: LawDescription = LawDescription {
        name: Self::NAME,
        summary: "Amontons-Coulomb: τ_c = μ p (docs/friction-math.md §3, eq. 2.13)",
        params: Self::PARAMS,
    };

    /// Build from values in [`Self::PARAMS`] order (`mu`, `k_t`).
    ///
    /// # Errors
    /// A value count other than 2, or a value out of range or not finite,
    /// naming the parameter.
    pub fn from_values(values: &[f64]) -> Result<Self, FrictionError> {
        check_values(Self::NAME, Self::PARAMS, values)?;
        Ok(Self {
            mu: values[0],
            k_t: values[1],
        })
    }

    /// Build as a boxed [`FrictionLaw`] (the registry's builder).
    ///
    /// # Errors
    /// As [`Self::from_values`].
    pub fn build(values: &[f64]) -> Result<Box<dyn FrictionLaw>, FrictionError> {
        Ok(Box::new(Self::from_values(values)?))
    }

    /// Coulomb friction with coefficient `mu` (-) and stick stiffness `k_t` (MPa/mm).
    ///
    /// # Errors
    /// As [`Self::from_values`].
    pub fn new(mu: f64, k_t: f64) -> Result<Self, FrictionError> {
        Self::from_values(&[mu, k_t])
    }

    /// Friction coefficient `μ` (-).
    #[must_use]
    pub fn mu(&self) -> f64 {
        self.mu
    }
}

impl FrictionLaw for Ac {
    fn name(&self) -> &str {
        Self::NAME
    }

    fn stick_stiffness(&self) -> f64 {
        self.k_t
    }

    #[inline]
    fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
        CriticalShear {
            tau: self.mu * x.p,
            dtau_dp: self.mu,
            ..CriticalShear::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::laws::test_support::{central_differences, inputs, rel};
    use plugins_api::Params;

    /// friction-math §3 (eq. 2.13): `∂τ_c/∂p = μ`, `∂τ_c/∂ω = 0` against central
    /// differences over a grid of p and ω; relative 1e-6.
    #[test]
    fn ac_derivatives_match_central_differences() {
        let law = Ac::new(0.144, 1e5).unwrap();
        for &p in &[1e-6, 1e-3, 0.1, 1.0, 10.0, 1e3] {
            for &omega in &[0.0, 1.0, 1e3] {
                let x = inputs(p, omega, f64::NAN);
                let cs = law.critical_shear(&x);
                let (fd_p, fd_w) = central_differences(&law, &x, 1e-4 * p, 1e-3);
                assert!(
                    rel(fd_p, cs.dtau_dp) <= 1e-6,
                    "p = {p}: {fd_p} vs {}",
                    cs.dtau_dp
                );
                assert_eq!(cs.dtau_domega, 0.0);
                assert_eq!(fd_w, 0.0);
                assert!(!cs.clamped);
            }
        }
    }

    /// Eq. 2.13 at the square-cup value μ = 0.144 (friction-math §7); relative 1e-15.
    #[test]
    fn ac_square_cup_value() {
        let law = Ac::new(0.144, 1e5).unwrap();
        assert!(rel(law.critical_shear(&inputs(12.5, 0.0, f64::NAN)).tau, 1.8) <= 1e-15);
        assert_eq!(law.critical_shear(&inputs(0.0, 0.0, f64::NAN)).tau, 0.0);
    }

    /// friction-math §5 validation: negative μ, k_T ≤ 0, NaN: errors naming the parameter.
    #[test]
    fn ac_validation_names_the_parameter() {
        let e = Ac::new(-0.1, 1e5).unwrap_err().to_string();
        assert!(e.contains("`mu`") && e.contains(">= 0"), "{e}");
        let e = Ac::new(0.1, 0.0).unwrap_err().to_string();
        assert!(
            e.contains("`k_t`") && e.contains("MPa/mm") && e.contains("> 0"),
            "{e}"
        );
        let e = Ac::new(0.1, -1.0).unwrap_err().to_string();
        assert!(e.contains("`k_t`"), "{e}");
        let e = Ac::new(f64::NAN, 1e5).unwrap_err().to_string();
        assert!(e.contains("`mu`") && e.contains("NaN"), "{e}");
        let e = Params::new()
            .with("mu", -0.2)
            .resolve("ac", Ac::PARAMS)
            .unwrap_err()
            .to_string();
        assert!(e.contains("`mu`"), "{e}");
        let e = Params::new()
            .resolve("ac", Ac::PARAMS)
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing parameter `mu`"), "{e}");
        // The default k_T applies.
        let v = Params::new()
            .with("mu", 0.11)
            .resolve("ac", Ac::PARAMS)
            .unwrap();
        assert_eq!(
            Ac::build(&v).unwrap().stick_stiffness(),
            crate::laws::DEFAULT_STICK_STIFFNESS
        );
    }
}
