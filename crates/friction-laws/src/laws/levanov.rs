//! Levanov friction, `τ_c = m (σ_y/√3)(1 - exp(-c p/σ_y))`, reading the blank
//! flow stress `σ_y` (friction-math §3, thesis ch. 1).

use plugins_api::law::LawDescription;
use plugins_api::{CriticalShear, FrictionError, FrictionLaw, ParamSpec, PointNeeds, ShearInputs};

use super::STICK_STIFFNESS;
use plugins_api::params::check_values;

/// `1/√3`.
const INV_SQRT_3: f64 = 0.577_350_269_189_625_8;

/// Levanov friction: `Φ = |t| - m (σ_y/√3)(1 - exp(-c p/σ_y))`.
///
/// `σ_y` is the current flow stress of the blank at the contact point
/// ([`ShearInputs::flow_stress`]); the law declares [`PointNeeds::FLOW_STRESS`]
/// so that the engine computes it only when needed. For `p ≪ σ_y` it tends to
/// Coulomb friction with `μ = c m/√3`; for `p ≫ σ_y` to the shear-friction
/// (Siebel/Tresca) limit `m σ_y/√3`, smoothly and monotonically in `p`.
/// `1 - exp(-x)` is evaluated as `-expm1(-x)`, accurate for small `x`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Levanov {
    m: f64,
    c: f64,
    k_t: f64,
}

impl Levanov {
    /// Name as typed in scenes.
    pub const NAME: &'static str = "levanov";

    /// Default shape constant `c` (-).
    pub const DEFAULT_C: f64 = 1.25;

    /// Parameter schema, in the order `from_values` receives the values.
    pub const PARAMS: &'static [ParamSpec] = &[
        ParamSpec::required(
            "m",
            "-",
            0.0,
            1.0,
            "friction factor m of the shear limit m σ_y/√3 (-)",
        )
        .exclusive_min(),
        ParamSpec::optional(
            "c",
            "-",
            Self::DEFAULT_C,
            0.0,
            f64::INFINITY,
            "shape constant c of 1 - exp(-c p/σ_y) (-); small-p Coulomb μ = c m/√3",
        )
        .exclusive_min(),
        STICK_STIFFNESS,
    ];

    /// Name, one-line summary and parameter schema.
    pub const DESCRIPTION: LawDescription = LawDescription {
        name: Self::NAME,
        summary: "Levanov: τ_c = m (σ_y/√3)(1 - exp(-c p/σ_y)), σ_y = blank flow stress \
                  (docs/friction-math.md §3)",
        params: Self::PARAMS,
    };

    /// Build from values in [`Self::PARAMS`] order (`m`, `c`, `k_t`).
    ///
    /// # Errors
    /// A value count other than 3, or a value out of range or not finite,
    /// naming the parameter.
    pub fn from_values(values: &[f64]) -> Result<Self, FrictionError> {
        check_values(Self::NAME, Self::PARAMS, values)?;
        Ok(Self {
            m: values[0],
            c: values[1],
            k_t: values[2],
        })
    }

    /// Build as a boxed [`FrictionLaw`] (the registry's builder).
    ///
    /// # Errors
    /// As [`Self::from_values`].
    pub fn build(values: &[f64]) -> Result<Box<dyn FrictionLaw>, FrictionError> {
        Ok(Box::new(Self::from_values(values)?))
    }

    /// Levanov with friction factor `m` (-), shape constant `c` (-) and stick
    /// stiffness `k_t` (MPa/mm).
    ///
    /// # Errors
    /// As [`Self::from_values`].
    pub fn new(m: f64, c: f64, k_t: f64) -> Result<Self, FrictionError> {
        Self::from_values(&[m, c, k_t])
    }

    /// Friction factor `m` (-).
    #[must_use]
    pub fn m(&self) -> f64 {
        self.m
    }

    /// Shape constant `c` (-).
    #[must_use]
    pub fn c(&self) -> f64 {
        self.c
    }
}

impl FrictionLaw for Levanov {
    fn name(&self) -> &str {
        Self::NAME
    }

    fn stick_stiffness(&self) -> f64 {
        self.k_t
    }

    fn needs(&self) -> PointNeeds {
        PointNeeds::FLOW_STRESS
    }

    #[inline]
    fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
        let sigma_y = x.flow_stress;
        let e = -self.c * x.p / sigma_y;
        let limit = self.m * sigma_y * INV_SQRT_3;
        CriticalShear {
            tau: -limit * e.exp_m1(),
            dtau_dp: self.m * self.c * INV_SQRT_3 * e.exp(),
            ..CriticalShear::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::laws::test_support::{Identity, central_differences, flat_kinematics, inputs, rel};
    use plugins_api::return_mapping::step;
    use plugins_api::{FrictionError, Params, PointState, StepInput, TangentMode, Vec3};

    /// friction-math §3: `∂τ_c/∂p = (c m/√3) exp(-c p/σ_y)` against central
    /// differences (step 1e-4 p) for p/σ_y from 1e-8 to 8 (c p/σ_y ≤ 10), `∂τ_c/∂ω = 0`.
    /// Tolerance: relative 1e-6.
    #[test]
    fn levanov_derivatives_match_central_differences() {
        for law in [
            Levanov::new(0.3, 1.25, 1e5).unwrap(),
            Levanov::new(1.0, 3.0, 1e5).unwrap(),
        ] {
            for &sigma_y in &[150.0, 400.0] {
                // Beyond c p/σ_y ≈ 10 the slope is below round-off of τ_c itself.
                for &ratio in [1e-8, 1e-4, 1e-2, 0.1, 0.5, 1.0, 2.0, 4.0, 8.0]
                    .iter()
                    .filter(|&&r| law.c * r <= 10.0)
                {
                    let x = inputs(ratio * sigma_y, 5.0, sigma_y);
                    let cs = law.critical_shear(&x);
                    let (fd_p, fd_w) = central_differences(&law, &x, 1e-4 * x.p, 1e-3);
                    assert!(
                        rel(fd_p, cs.dtau_dp) <= 1e-6,
                        "p/σ_y = {ratio}: {fd_p} vs {}",
                        cs.dtau_dp
                    );
                    assert_eq!((cs.dtau_domega, fd_w), (0.0, 0.0));
                }
            }
        }
    }

    /// friction-math §3 limits: p/σ_y = 1e-8 gives Coulomb μ = c m/√3 (relative
    /// 1e-6; the exact relative deviation is c p/(2σ_y) ≈ 6e-9); p/σ_y = 40 gives
    /// m σ_y/√3 (relative 1e-15; exp(-50) ≈ 2e-22). τ_c(0) = 0.
    #[test]
    fn levanov_limits_coulomb_and_shear_friction() {
        let (m, c, sigma_y) = (0.4, 1.25, 300.0);
        let law = Levanov::new(m, c, 1e5).unwrap();
        let p = 1e-8 * sigma_y;
        let mu = c * m / 3.0_f64.sqrt();
        let small = law.critical_shear(&inputs(p, 0.0, sigma_y));
        assert!(rel(small.tau / p, mu) <= 1e-6, "{} vs {mu}", small.tau / p);
        assert!(rel(small.dtau_dp, mu) <= 1e-6);
        let large = law.critical_shear(&inputs(40.0 * sigma_y, 0.0, sigma_y));
        assert!(rel(large.tau, m * sigma_y / 3.0_f64.sqrt()) <= 1e-15);
        assert_eq!(law.critical_shear(&inputs(0.0, 0.0, sigma_y)).tau, 0.0);
        eprintln!(
            "levanov: τ/p at p/σ_y = 1e-8 deviates from c m/√3 by {:.2e} (relative)",
            rel(small.tau / p, mu)
        );
    }

    /// friction-math §3: τ_c is monotone (non-decreasing, with ∂τ_c/∂p > 0) in p
    /// over p/σ_y ∈ [0, 20], and bounded by the shear limit.
    #[test]
    fn levanov_monotone_in_pressure() {
        let law = Levanov::new(0.7, 1.25, 1e5).unwrap();
        let sigma_y = 250.0;
        let limit = 0.7 * sigma_y / 3.0_f64.sqrt();
        let mut last = 0.0;
        for i in 0..=20_000 {
            let p = f64::from(i) * 1e-3 * sigma_y;
            let cs = law.critical_shear(&inputs(p, 0.0, sigma_y));
            assert!(
                cs.tau >= last && cs.dtau_dp > 0.0 && cs.tau <= limit,
                "p = {p}"
            );
            last = cs.tau;
        }
    }

    /// friction-math §6: the law declares the flow stress and the shared return
    /// mapping refuses a step without it; with it, slip gives |t| = τ_c(p, σ_y)
    /// (relative 1e-14).
    #[test]
    fn levanov_needs_flow_stress() {
        let law = Levanov::new(0.5, 1.25, 1e5).unwrap();
        assert_eq!(law.needs(), PointNeeds::FLOW_STRESS);
        let mut state = PointState::default();
        let mut input = StepInput::new(50.0, Vec3::new(0.01, 0.0, 0.0), flat_kinematics());
        let e = step(&law, &Identity, TangentMode::None, &mut state, &input).unwrap_err();
        assert!(
            matches!(
                e,
                FrictionError::InvalidInput {
                    field: "sigma_y",
                    ..
                }
            ),
            "{e}"
        );
        input.flow_stress = 300.0;
        let out = step(&law, &Identity, TangentMode::None, &mut state, &input).unwrap();
        let expected = 0.5 * 300.0 / 3.0_f64.sqrt() * (1.0 - (-1.25 * 50.0 / 300.0_f64).exp());
        assert!(!out.stick && rel(out.t.norm(), expected) <= 1e-14);
    }

    /// friction-math §5 validation: m > 1, m ≤ 0, c ≤ 0, k_T ≤ 0, NaN: errors
    /// naming the parameter.
    #[test]
    fn levanov_validation_names_the_parameter() {
        for (values, name) in [
            ([1.2, 1.25, 1e5], "`m`"),
            ([0.0, 1.25, 1e5], "`m`"),
            ([f64::NAN, 1.25, 1e5], "`m`"),
            ([0.5, 0.0, 1e5], "`c`"),
            ([0.5, 1.25, 0.0], "`k_t`"),
            ([0.5, 1.25, f64::NAN], "`k_t`"),
        ] {
            let e = Levanov::from_values(&values).unwrap_err().to_string();
            assert!(e.contains(name), "{values:?}: {e}");
        }
        let e = Params::new()
            .with("m", 1.5)
            .resolve("levanov", Levanov::PARAMS)
            .unwrap_err()
            .to_string();
        assert!(e.contains("`m`") && e.contains("<= 1"), "{e}");
        let v = Params::new()
            .with("m", 1.0)
            .resolve("levanov", Levanov::PARAMS)
            .unwrap();
        assert_eq!(v, vec![1.0, 1.25, crate::laws::DEFAULT_STICK_STIFFNESS]);
        assert_eq!(Levanov::build(&v).unwrap().needs(), PointNeeds::FLOW_STRESS);
    }
}
