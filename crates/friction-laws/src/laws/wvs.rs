//! Wriggers–van der Ven–Stein pressure-dependent friction, `τ_c = β p + α p^ν`
//! (friction-math §3, thesis eqs. 2.15–2.16), with the C¹ quadratic
//! regularisation below `p_0` for `ν < 1`.

use plugins_api::law::LawDescription;
use plugins_api::{CriticalShear, FrictionError, FrictionLaw, ParamSpec, ShearInputs};

use super::STICK_STIFFNESS;
use plugins_api::params::check_values;

/// Wriggers–van der Ven–Stein friction: `Φ = |t| - α p^ν - β p` (eq. 2.15; the
/// thesis's eq. 3.19, `|t| - α p^ν + β p`, is a typo), i.e. a pressure-dependent
/// coefficient `μ(p) = β + α p^(ν-1)` (eq. 2.16).
///
/// **Regularisation (ν < 1).** `∂τ_c/∂p = β + α ν p^(ν-1)` is unbounded as
/// `p → 0`. Below `p_0` the law uses `τ_c = a p + b p²` with
/// `b = α(ν-1) p_0^(ν-2)`, `a = β + α(2-ν) p_0^(ν-1)`, which matches `τ_c` and
/// `∂τ_c/∂p` at `p_0` (C¹) and vanishes at `p = 0`. It is non-negative and
/// non-decreasing on `[0, p_0]` for every admissible parameter set: `b ≤ 0`, so
/// `a + b p ≥ a + b p_0 = β + α p_0^(ν-1) ≥ 0` and
/// `a + 2 b p ≥ a + 2 b p_0 = β + α ν p_0^(ν-1) ≥ 0`; the tangent is bounded by `a`.
/// It lies below the power law (by at most about `0.05 α p_0^ν` for `ν = 0.8`),
/// and only for `p < p_0`.
///
/// **No regularisation for ν ≥ 1.** Then `p^(ν-1)` is bounded on any bounded
/// pressure range (it equals 1 for `ν = 1` and tends to 0 as `p → 0` for
/// `ν > 1`), so `∂τ_c/∂p` stays finite, tending to `β + α` (ν = 1) or `β`
/// (ν > 1) at `p = 0`; the power law is used for every `p` and `p_0` is ignored.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wvs {
    alpha: f64,
    beta: f64,
    nu: f64,
    p0: f64,
    k_t: f64,
    /// Linear coefficient of the regularisation (-); unused for `ν ≥ 1`.
    a: f64,
    /// Quadratic coefficient of the regularisation (1/MPa); unused for `ν ≥ 1`.
    b: f64,
}

impl Wvs {
    /// Name as typed in scenes.
    pub const NAME: &'static str = "wvs";

    /// Default regularisation pressure `p_0` (MPa).
    pub const DEFAULT_P0: f64 = 1e-3;

    /// Parameter schema, in the order `from_values` receives the values.
    pub const PARAMS: &'static [ParamSpec] = &[
        ParamSpec::required(
            "alpha",
            "MPa^(1-nu)",
            0.0,
            f64::INFINITY,
            "coefficient α of the power term α p^ν (MPa^(1-ν))",
        ),
        ParamSpec::required(
            "beta",
            "-",
            0.0,
            f64::INFINITY,
            "Coulomb part β of τ_c = β p + α p^ν (-)",
        ),
        ParamSpec::required(
            "nu",
            "-",
            0.0,
            f64::INFINITY,
            "pressure exponent ν of the power term (-)",
        )
        .exclusive_min(),
        ParamSpec::optional(
            "p0",
            "MPa",
            Self::DEFAULT_P0,
            0.0,
            f64::INFINITY,
            "regularisation pressure p_0 (MPa): quadratic τ_c below it when ν < 1",
        )
        .exclusive_min(),
        STICK_STIFFNESS,
    ];

    /// Name, one-line summary and parameter schema.
    pub const DESCRIPTION: LawDescription = LawDescription {
        name: Self::NAME,
        summary: "Wriggers-van der Ven-Stein: τ_c = β p + α p^ν, C¹ quadratic below p0 when ν < 1 \
                  (docs/friction-math.md §3, eqs. 2.15-2.16)",
        params: Self::PARAMS,
    };

    /// Build from values in [`Self::PARAMS`] order (`alpha`, `beta`, `nu`, `p0`, `k_t`).
    ///
    /// # Errors
    /// A value count other than 5, a value out of range or not finite (naming
    /// the parameter), or a `p_0` so small for the given `ν < 1` that the
    /// regularisation coefficients overflow.
    pub fn from_values(values: &[f64]) -> Result<Self, FrictionError> {
        check_values(Self::NAME, Self::PARAMS, values)?;
        let (alpha, beta, nu, p0, k_t) = (values[0], values[1], values[2], values[3], values[4]);
        let (a, b) = if nu < 1.0 {
            let b = alpha * (nu - 1.0) * p0.powf(nu - 2.0);
            let a = beta + alpha * (2.0 - nu) * p0.powf(nu - 1.0);
            if !(a.is_finite() && b.is_finite()) {
                return Err(FrictionError::InvalidParameters {
                    component: Self::NAME.to_string(),
                    reason: format!(
                        "`p0` = {p0} MPa is too small for `nu` = {nu}: the regularisation \
                         coefficients a = {a}, b = {b} 1/MPa are not finite; choose a larger p0"
                    ),
                });
            }
            (a, b)
        } else {
            (beta + alpha, 0.0)
        };
        Ok(Self {
            alpha,
            beta,
            nu,
            p0,
            k_t,
            a,
            b,
        })
    }

    /// Build as a boxed [`FrictionLaw`] (the registry's builder).
    ///
    /// # Errors
    /// As [`Self::from_values`].
    pub fn build(values: &[f64]) -> Result<Box<dyn FrictionLaw>, FrictionError> {
        Ok(Box::new(Self::from_values(values)?))
    }

    /// WVS with `alpha` (MPa^(1-ν)), `beta` (-), `nu` (-), regularisation
    /// pressure `p0` (MPa) and stick stiffness `k_t` (MPa/mm).
    ///
    /// # Errors
    /// As [`Self::from_values`].
    pub fn new(alpha: f64, beta: f64, nu: f64, p0: f64, k_t: f64) -> Result<Self, FrictionError> {
        Self::from_values(&[alpha, beta, nu, p0, k_t])
    }

    /// `α` (MPa^(1-ν)).
    #[must_use]
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// `β` (-).
    #[must_use]
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// `ν` (-).
    #[must_use]
    pub fn nu(&self) -> f64 {
        self.nu
    }

    /// Regularisation pressure `p_0` (MPa); inactive when `ν ≥ 1`.
    #[must_use]
    pub fn p0(&self) -> f64 {
        self.p0
    }

    /// Whether the quadratic regularisation is used below `p_0` (`ν < 1`).
    #[must_use]
    pub fn is_regularised(&self) -> bool {
        self.nu < 1.0
    }

    /// The power law `β p + α p^ν` and its slope (one `powf`).
    #[inline]
    fn power(&self, p: f64) -> (f64, f64) {
        let q = p.powf(self.nu - 1.0);
        (
            p * (self.beta + self.alpha * q),
            self.beta + self.alpha * self.nu * q,
        )
    }

    /// The regularising quadratic `a p + b p²` and its slope.
    #[inline]
    fn quadratic(&self, p: f64) -> (f64, f64) {
        (p * (self.a + self.b * p), self.a + 2.0 * self.b * p)
    }
}

impl FrictionLaw for Wvs {
    fn name(&self) -> &str {
        Self::NAME
    }

    fn stick_stiffness(&self) -> f64 {
        self.k_t
    }

    #[inline]
    fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
        let (tau, dtau_dp) = if self.nu < 1.0 && x.p < self.p0 {
            self.quadratic(x.p)
        } else {
            self.power(x.p)
        };
        CriticalShear {
            tau,
            dtau_dp,
            ..CriticalShear::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::laws::test_support::{Identity, central_differences, flat_kinematics, inputs, rel};
    use plugins_api::return_mapping::step;
    use plugins_api::{Params, PointState, StepInput, TangentMode, Vec3};

    fn square_cup(p0: f64) -> Wvs {
        // friction-math §7, square cup: α = 0.03, β = 0.144, ν = 0.80.
        Wvs::new(0.03, 0.144, 0.8, p0, 1e5).unwrap()
    }

    /// friction-math §3: `∂τ_c/∂p` against central differences (step 1e-4 p) for
    /// p below p_0, around it and ≫ p_0, for ν < 1, ν = 1, ν > 1; `∂τ_c/∂ω = 0`.
    /// Tolerance: relative 1e-6.
    #[test]
    fn wvs_derivatives_match_central_differences() {
        let laws = [
            square_cup(1e-3),
            Wvs::new(0.03, 0.0, 0.5, 1e-3, 1e5).unwrap(),
            Wvs::new(0.2, 0.1, 0.2, 1e-2, 1e5).unwrap(),
            Wvs::new(0.05, 0.1, 1.0, 1e-3, 1e5).unwrap(),
            Wvs::new(0.02, 0.1, 1.5, 1e-3, 1e5).unwrap(),
        ];
        let ps = [
            1e-7, 1e-5, 2e-4, 5e-4, 9e-4, 1.1e-3, 5e-3, 9e-3, 1.2e-2, 0.1, 1.0, 10.0, 100.0, 1e3,
        ];
        for law in &laws {
            for &p in &ps {
                for &omega in &[0.0, 10.0] {
                    let x = inputs(p, omega, f64::NAN);
                    let cs = law.critical_shear(&x);
                    let (fd_p, fd_w) = central_differences(law, &x, 1e-4 * p, 1e-3);
                    assert!(
                        rel(fd_p, cs.dtau_dp) <= 1e-6,
                        "{law:?} p = {p}: fd {fd_p} vs {}",
                        cs.dtau_dp
                    );
                    assert_eq!((cs.dtau_domega, fd_w), (0.0, 0.0));
                }
            }
        }
    }

    /// friction-math §3: the quadratic matches the power law in value and slope at
    /// p_0 (C¹). Tolerance: relative 1e-12 (both are a few roundings from exact).
    #[test]
    fn wvs_regularisation_is_c1_at_p0() {
        for &(alpha, beta, nu, p0) in &[
            (0.03, 0.144, 0.8, 1e-3),
            (0.03, 0.11, 0.8, 1e-4),
            (0.5, 0.0, 0.3, 1e-2),
            (2.0, 0.05, 0.999, 1.0),
            (0.01, 0.2, 0.01, 1e-6),
        ] {
            let law = Wvs::new(alpha, beta, nu, p0, 1e5).unwrap();
            let (tq, dq) = law.quadratic(p0);
            let (tp, dp) = law.power(p0);
            assert!(rel(tq, tp) <= 1e-12, "value at p0: {tq} vs {tp}");
            assert!(rel(dq, dp) <= 1e-12, "slope at p0: {dq} vs {dp}");
            // And through the public entry point, across the switch.
            let below = law.critical_shear(&inputs(p0.next_down(), 0.0, f64::NAN));
            let at = law.critical_shear(&inputs(p0, 0.0, f64::NAN));
            assert!(rel(below.tau, at.tau) <= 1e-12 && rel(below.dtau_dp, at.dtau_dp) <= 1e-12);
        }
    }

    /// friction-math §3: the regularisation is zero at 0, positive and
    /// non-decreasing on (0, p_0], with slope in [0, a]; checked on a grid of
    /// admissible parameters (the doc comment proves it; this guards the code).
    #[test]
    fn wvs_regularisation_positive_monotone_bounded_slope() {
        for &nu in &[0.01, 0.2, 0.5, 0.8, 0.99] {
            for &alpha in &[0.0, 0.03, 5.0] {
                for &beta in &[0.0, 0.144] {
                    for &p0 in &[1e-6, 1e-3, 1.0] {
                        let law = Wvs::new(alpha, beta, nu, p0, 1e5).unwrap();
                        assert_eq!(law.critical_shear(&inputs(0.0, 0.0, f64::NAN)).tau, 0.0);
                        let mut last = 0.0;
                        for i in 1..=1000 {
                            let p = p0 * f64::from(i) / 1000.0;
                            let cs = law.critical_shear(&inputs(p, 0.0, f64::NAN));
                            if alpha + beta > 0.0 {
                                assert!(cs.tau > 0.0, "ν={nu} α={alpha} β={beta} p0={p0} p={p}");
                            }
                            assert!(cs.tau >= last, "not monotone at p = {p}");
                            assert!(cs.dtau_dp >= 0.0 && cs.dtau_dp <= law.a * (1.0 + 1e-15));
                            last = cs.tau;
                        }
                    }
                }
            }
        }
    }

    /// friction-math §3: τ_c(0) = 0 and the tangent stays finite as p → 0 (it tends
    /// to a, relative 1e-12), where the unregularised slope α ν p^(ν-1) is ~1e58.
    #[test]
    fn wvs_tangent_finite_as_pressure_tends_to_zero() {
        let law = square_cup(1e-3);
        for &p in &[0.0, 5e-324, 1e-300, 1e-100, 1e-20] {
            let cs = law.critical_shear(&inputs(p, 0.0, f64::NAN));
            assert!(cs.tau.is_finite() && cs.tau >= 0.0 && cs.dtau_dp.is_finite());
            assert!(
                rel(cs.dtau_dp, law.a) <= 1e-12,
                "p = {p}: {} vs a = {}",
                cs.dtau_dp,
                law.a
            );
        }
        assert_eq!(law.critical_shear(&inputs(0.0, 0.0, f64::NAN)).tau, 0.0);
        let unregularised = 0.03 * 0.8 * 1e-300_f64.powf(-0.2);
        assert!(unregularised > 1e57, "{unregularised}");
    }

    /// friction-math §3: results insensitive to p_0 within a decade (1e-3 vs 1e-4 MPa).
    ///
    /// The two laws differ only for p < 1e-3, by at most
    /// `δ = G α (p_a^ν + p_b^ν)` with `G = max_{s∈[0,1]} |(2-ν)s + (ν-1)s² - s^ν|`
    /// (the deviation of the quadratic from the power law in units of α p_0^ν).
    /// The radial return is a projection onto the disc of radius τ_c, which is
    /// non-expansive and moves by at most |Δτ_c| when the radius changes, so the
    /// tractions of the two runs differ by at most the sum of δ over the
    /// low-pressure steps so far (exactly 0 contribution from steps at p ≥ 1e-3).
    /// The dissipation `ΔD = τ max(T-τ, 0)/k_T` then differs per step by at most
    /// `(T + τ) e_n / k_T`. Tolerance: these bounds (plus 1e-14 MPa round-off).
    #[test]
    fn wvs_results_insensitive_to_p0_within_a_decade() {
        let (alpha, nu) = (0.03, 0.8);
        let g = (0..=100_000)
            .map(|i| {
                let s = f64::from(i) / 100_000.0;
                ((2.0 - nu) * s + (nu - 1.0) * s * s - s.powf(nu)).abs()
            })
            .fold(0.0, f64::max)
            * 1.01;
        let delta = g * alpha * (1e-3_f64.powf(nu) + 1e-4_f64.powf(nu));
        let (law_a, law_b) = (square_cup(1e-3), square_cup(1e-4));
        let k_t = law_a.stick_stiffness();
        let (mut sa, mut sb) = (PointState::default(), PointState::default());
        let kin = flat_kinematics();
        let (mut e, mut d_bound, mut max_dt, mut max_t) = (0.0_f64, 0.0_f64, 0.0_f64, 0.0_f64);
        let (mut low_slips, mut sticks, mut slips) = (0, 0, 0);
        for n in 0..600 {
            let s = f64::from(n);
            let p = match n % 41 {
                5 => 5e-4,
                6 => 2e-4,
                20 => 5e-5,
                _ => 0.5 + 0.45 * (0.07 * s).sin(),
            };
            let du = Vec3::new(3e-7 * (0.2 * s).sin(), 1.5e-7 * (0.13 * s).cos(), 0.0);
            let input = StepInput::new(p, du, kin);
            let oa = step(&law_a, &Identity, TangentMode::None, &mut sa, &input).unwrap();
            let ob = step(&law_b, &Identity, TangentMode::None, &mut sb, &input).unwrap();
            if p < 1e-3 {
                e += delta;
                low_slips += usize::from(!oa.stick);
            }
            if oa.stick {
                sticks += 1
            } else {
                slips += 1
            }
            let diff = (oa.t - ob.t).norm();
            assert!(diff <= e + 1e-14, "step {n}: |Δt| = {diff} > bound {e}");
            let big_t = (oa.t.norm() + k_t * oa.dgamma).max(ob.t.norm() + k_t * ob.dgamma);
            d_bound += (big_t + oa.tau_c.max(ob.tau_c)) * e / k_t;
            let d_diff = (sa.omega - sb.omega).abs();
            assert!(
                d_diff <= d_bound + 1e-14 * sa.omega,
                "step {n}: |Δω| = {d_diff} > {d_bound}"
            );
            max_dt = max_dt.max(diff);
            max_t = max_t.max(oa.t.norm());
        }
        assert!(
            sticks > 50 && slips > 50 && low_slips > 0,
            "{sticks} {slips} {low_slips}"
        );
        eprintln!(
            "wvs p0 1e-3 vs 1e-4: δ = {delta:.3e} MPa per low step, max |Δt| = {max_dt:.3e} MPa \
             (max |t| = {max_t:.3e}), bound {e:.3e}; ω = {:.6e} vs {:.6e} N/mm (bound {d_bound:.3e}); \
             {sticks} stick, {slips} slip, {low_slips} low-p slips",
            sa.omega, sb.omega
        );
    }

    /// friction-math §3 "thesis typo": the implemented slip function is eq. 2.15,
    /// `Φ = |t| - α p^ν - β p`, not eq. 3.19's `|t| - α p^ν + β p`. Checked at
    /// the square-cup values through the law and through a slipping step;
    /// relative 1e-14.
    #[test]
    fn wvs_implements_eq_2_15_not_the_typo_of_eq_3_19() {
        let law = square_cup(1e-3);
        let (alpha, beta, nu) = (0.03, 0.144, 0.8);
        for &p in &[0.05, 1.0, 10.0, 80.0] {
            let eq_2_15 = alpha * (nu * f64::ln(p)).exp() + beta * p;
            let eq_3_19 = alpha * (nu * f64::ln(p)).exp() - beta * p;
            let tau = law.critical_shear(&inputs(p, 0.0, f64::NAN)).tau;
            assert!(rel(tau, eq_2_15) <= 1e-14, "p = {p}: {tau} vs {eq_2_15}");
            assert!(rel(tau, eq_3_19) > 0.1);
            let mut state = PointState::default();
            let input = StepInput::new(p, Vec3::new(1e-3, 0.0, 0.0), flat_kinematics());
            let out = step(&law, &Identity, TangentMode::None, &mut state, &input).unwrap();
            assert!(!out.stick && rel(out.t.norm(), eq_2_15) <= 1e-14);
        }
        // p = 10 MPa: 0.03·10^0.8 + 1.44 = 0.18929 + 1.44 = 1.6293 MPa (hand value, 4 digits).
        assert!((law.critical_shear(&inputs(10.0, 0.0, f64::NAN)).tau - 1.6293).abs() < 5e-5);
    }

    /// friction-math §3: for ν ≥ 1 the power law is used at every p (no
    /// regularisation): ν = 1 is Coulomb with μ = α + β (relative 1e-15), and
    /// for ν = 1.5 the slope at p = 0 is β.
    #[test]
    fn wvs_nu_at_least_one_is_not_regularised() {
        let law = Wvs::new(0.05, 0.1, 1.0, 1e-3, 1e5).unwrap();
        assert!(!law.is_regularised());
        for &p in &[0.0, 1e-300, 1e-4, 1.0] {
            let cs = law.critical_shear(&inputs(p, 0.0, f64::NAN));
            assert!(rel(cs.tau, 0.15 * p) <= 1e-15 && rel(cs.dtau_dp, 0.15) <= 1e-15);
        }
        let law = Wvs::new(0.05, 0.1, 1.5, 1e-3, 1e5).unwrap();
        let cs = law.critical_shear(&inputs(0.0, 0.0, f64::NAN));
        assert_eq!((cs.tau, cs.dtau_dp), (0.0, 0.1));
        let cs = law.critical_shear(&inputs(1e-4, 0.0, f64::NAN));
        assert!(rel(cs.tau, 0.1e-4 + 0.05 * 1e-6) <= 1e-14);
    }

    /// friction-math §5 validation: ν ≤ 0, negative α or β, p_0 ≤ 0, k_T ≤ 0,
    /// NaN, and an overflowing regularisation: errors naming the parameter.
    #[test]
    fn wvs_validation_names_the_parameter() {
        for (values, name) in [
            ([0.03, 0.144, 0.0, 1e-3, 1e5], "`nu`"),
            ([0.03, 0.144, -0.5, 1e-3, 1e5], "`nu`"),
            ([-0.03, 0.144, 0.8, 1e-3, 1e5], "`alpha`"),
            ([0.03, -0.1, 0.8, 1e-3, 1e5], "`beta`"),
            ([0.03, 0.144, 0.8, 0.0, 1e5], "`p0`"),
            ([0.03, 0.144, 0.8, 1e-3, 0.0], "`k_t`"),
            ([0.03, 0.144, 0.8, 1e-3, -1e5], "`k_t`"),
            ([f64::NAN, 0.144, 0.8, 1e-3, 1e5], "`alpha`"),
            ([0.03, 0.144, f64::NAN, 1e-3, 1e5], "`nu`"),
            ([0.03, 0.144, 0.8, f64::INFINITY, 1e5], "`p0`"),
            ([0.03, 0.144, 0.5, 1e-300, 1e5], "`p0`"),
        ] {
            let e = Wvs::from_values(&values).unwrap_err().to_string();
            assert!(e.contains(name), "{values:?}: {e}");
        }
        let e = Params::new()
            .with("alpha", 0.03)
            .with("beta", 0.144)
            .with("nu", 0.0)
            .resolve("wvs", Wvs::PARAMS)
            .unwrap_err()
            .to_string();
        assert!(e.contains("`nu`") && e.contains("> 0"), "{e}");
        let v = Params::new()
            .with("alpha", 0.03)
            .with("beta", 0.144)
            .with("nu", 0.8)
            .resolve("wvs", Wvs::PARAMS)
            .unwrap();
        assert_eq!(
            v,
            vec![0.03, 0.144, 0.8, 1e-3, crate::laws::DEFAULT_STICK_STIFFNESS]
        );
        assert_eq!(Wvs::build(&v).unwrap().name(), "wvs");
    }
}
