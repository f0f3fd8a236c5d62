//! Work-hardening (or softening) friction of de Souza Neto et al.,
//! `τ_c = max(μ(ω), μ_min) p` with a polynomial `μ(ω)` of degree ≤ 5 in the
//! frictional work density `ω` (friction-math §3, thesis eqs. 2.17–2.19, 4.1).

use plugins_api::law::LawDescription;
use plugins_api::{CriticalShear, FrictionError, FrictionLaw, ParamSpec, ShearInputs};

use super::STICK_STIFFNESS;
use plugins_api::params::check_values;

/// Work-dependent friction: `Φ = |t| - max(μ(ω), μ_min) p`,
/// `μ(ω) = Σ_{i=0}^{5} a_i ω^i` (evaluated by Horner's rule).
///
/// `ω` is the frictional work per unit area (N/mm), the running sum of the
/// step dissipations `ΔD`; it grows only while slipping, and the shared return
/// mapping integrates it by backward Euler ([`FrictionLaw::work_dependent`]).
///
/// **Units.** `a_0` is dimensionless and `a_i` is in `(mm/N)^i`. The thesis
/// quotes the linear fit `μ = β + α ω` with `α` in mm/kN and `ω` in kN/mm;
/// in N–mm units `α[mm/N] = 1e-3 · α[mm/kN]` (generally
/// `a_i[(mm/N)^i] = 1e-3^i · a_i[(mm/kN)^i]`). The square-cup benchmark
/// (friction-math §7), `α = -8.757e-2 mm/kN, β = 0.1448`, is therefore
/// `a0 = 0.1448, a1 = -8.757e-5`.
///
/// **Clamp.** The benchmark fits are work *softening* (`a_1 < 0`), so `μ(ω)`
/// eventually falls below any floor. When `μ(ω) < μ_min` the law uses
/// `μ_min` (≥ 0), sets [`CriticalShear::clamped`] (reported to the user) and
/// returns `∂τ_c/∂ω = 0`. For the linear fit the clamp starts at
/// `ω* = (a_0 - μ_min)/(-a_1)`. `μ(0) = a_0 < μ_min` is allowed: the clamp is
/// then active from the start.
///
/// A polynomial that overflows at very large `ω` gives a non-finite `τ_c`,
/// which the return mapping reports as an error rather than propagating.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wh {
    a: [f64; 6],
    /// Index of the highest non-zero coefficient: Horner starts there, so the
    /// benchmarks' linear fit costs one step instead of five.
    degree: usize,
    mu_min: f64,
    k_t: f64,
}

impl Wh {
    /// Name as typed in scenes.
    pub const NAME: &'static str = "wh";

    /// Parameter schema, in the order `from_values` receives the values.
    pub const PARAMS: &'static [ParamSpec] = &[
        ParamSpec::required(
            "a0",
            "-",
            0.0,
            f64::INFINITY,
            "μ(0) = a0, friction coefficient of fresh contact (-)",
        ),
        ParamSpec::optional(
            "a1",
            "mm/N",
            0.0,
            f64::NEG_INFINITY,
            f64::INFINITY,
            "coefficient of ω in μ(ω) (mm/N; = 1e-3 × the thesis's α in mm/kN)",
        ),
        ParamSpec::optional(
            "a2",
            "(mm/N)^2",
            0.0,
            f64::NEG_INFINITY,
            f64::INFINITY,
            "coefficient of ω² in μ(ω) ((mm/N)^2)",
        ),
        ParamSpec::optional(
            "a3",
            "(mm/N)^3",
            0.0,
            f64::NEG_INFINITY,
            f64::INFINITY,
            "coefficient of ω³ in μ(ω) ((mm/N)^3)",
        ),
        ParamSpec::optional(
            "a4",
            "(mm/N)^4",
            0.0,
            f64::NEG_INFINITY,
            f64::INFINITY,
            "coefficient of ω⁴ in μ(ω) ((mm/N)^4)",
        ),
        ParamSpec::optional(
            "a5",
            "(mm/N)^5",
            0.0,
            f64::NEG_INFINITY,
            f64::INFINITY,
            "coefficient of ω⁵ in μ(ω) ((mm/N)^5)",
        ),
        ParamSpec::optional(
            "mu_min",
            "-",
            0.0,
            0.0,
            f64::INFINITY,
            "lower clamp μ_min of μ(ω) (-); reported when active",
        ),
        STICK_STIFFNESS,
    ];

    /// Name, one-line summary and parameter schema.
    pub const DESCRIPTION: LawDescription = LawDescription {
        name: Self::NAME,
        summary: "work hardening/softening: τ_c = max(Σ a_i ω^i, μ_min) p, ω = frictional work (N/mm) \
                  (docs/friction-math.md §3, eqs. 2.17-2.19)",
        params: Self::PARAMS,
    };

    /// Build from values in [`Self::PARAMS`] order (`a0` … `a5`, `mu_min`, `k_t`).
    ///
    /// # Errors
    /// A value count other than 8, or a value out of range or not finite,
    /// naming the parameter.
    pub fn from_values(values: &[f64]) -> Result<Self, FrictionError> {
        check_values(Self::NAME, Self::PARAMS, values)?;
        let mut a = [0.0; 6];
        a.copy_from_slice(&values[..6]);
        let degree = a.iter().rposition(|&ai| ai != 0.0).unwrap_or(0);
        Ok(Self {
            a,
            degree,
            mu_min: values[6],
            k_t: values[7],
        })
    }

    /// Build as a boxed [`FrictionLaw`] (the registry's builder).
    ///
    /// # Errors
    /// As [`Self::from_values`].
    pub fn build(values: &[f64]) -> Result<Box<dyn FrictionLaw>, FrictionError> {
        Ok(Box::new(Self::from_values(values)?))
    }

    /// WH with coefficients `a` (`a[i]` in `(mm/N)^i`), clamp `mu_min` (-) and
    /// stick stiffness `k_t` (MPa/mm).
    ///
    /// # Errors
    /// As [`Self::from_values`].
    pub fn new(a: [f64; 6], mu_min: f64, k_t: f64) -> Result<Self, FrictionError> {
        Self::from_values(&[a[0], a[1], a[2], a[3], a[4], a[5], mu_min, k_t])
    }

    /// The linear fit of the benchmarks, `μ = beta + alpha ω`, with `alpha`
    /// already in mm/N (`1e-3 ×` the thesis's value in mm/kN).
    ///
    /// # Errors
    /// As [`Self::from_values`].
    pub fn linear(beta: f64, alpha: f64, mu_min: f64, k_t: f64) -> Result<Self, FrictionError> {
        Self::new([beta, alpha, 0.0, 0.0, 0.0, 0.0], mu_min, k_t)
    }

    /// Coefficients `a_i` of `μ(ω)` (`(mm/N)^i`).
    #[must_use]
    pub fn coefficients(&self) -> [f64; 6] {
        self.a
    }

    /// Lower clamp `μ_min` (-).
    #[must_use]
    pub fn mu_min(&self) -> f64 {
        self.mu_min
    }

    /// Unclamped `μ(ω)` and `μ'(ω)` (1/(N/mm)) by Horner's rule.
    #[inline]
    #[must_use]
    pub fn mu(&self, omega: f64) -> (f64, f64) {
        let mut mu = self.a[self.degree];
        let mut dmu = 0.0;
        for &ai in self.a[..self.degree].iter().rev() {
            dmu = dmu * omega + mu;
            mu = mu * omega + ai;
        }
        (mu, dmu)
    }
}

impl FrictionLaw for Wh {
    fn name(&self) -> &str {
        Self::NAME
    }

    fn stick_stiffness(&self) -> f64 {
        self.k_t
    }

    fn work_dependent(&self) -> bool {
        true
    }

    #[inline]
    fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
        let (mu, dmu) = self.mu(x.omega);
        // `mu < mu_min` is false for NaN, which then reaches the caller's check.
        if mu < self.mu_min {
            CriticalShear {
                tau: self.mu_min * x.p,
                dtau_dp: self.mu_min,
                clamped: true,
                ..CriticalShear::default()
            }
        } else {
            CriticalShear {
                tau: mu * x.p,
                dtau_dp: mu,
                dtau_domega: dmu * x.p,
                ..CriticalShear::default()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::laws::test_support::{Identity, central_differences, flat_kinematics, inputs, rel};
    use plugins_api::return_mapping::step;
    use plugins_api::{Params, PointState, StepInput, TangentMode, Vec3};

    /// friction-math §7, square cup: `α = -8.757e-2 mm/kN = -8.757e-5 mm/N`, `β = 0.1448`.
    const A0: f64 = 0.1448;
    const A1: f64 = -8.757e-5;

    /// A degree-5 polynomial scaled to ω ~ 1e3 N/mm, positive on [0, 2000].
    fn quintic() -> Wh {
        let l: f64 = 1e-3;
        Wh::new(
            [
                0.12,
                0.05 * l,
                -0.03 * l.powi(2),
                0.01 * l.powi(3),
                0.004 * l.powi(4),
                -0.001 * l.powi(5),
            ],
            0.0,
            1e5,
        )
        .unwrap()
    }

    /// friction-math §3: Horner's rule equals the direct sums `Σ a_i ω^i` and
    /// `Σ i a_i ω^(i-1)`. Tolerance: 1e-14 × the sum of the absolute terms.
    #[test]
    fn wh_mu_horner_matches_direct_sum() {
        for law in [
            quintic(),
            Wh::new([0.3, -1.0, 2.0, -3.0, 4.0, -5.0], 0.0, 1e5).unwrap(),
        ] {
            let a = law.coefficients();
            for &omega in &[0.0, 1e-3, 0.7, 1.0, 3.3, 10.0, 250.0, 1e3, 1.9e3] {
                let (mu, dmu) = law.mu(omega);
                let (mut s, mut sabs, mut d, mut dabs) = (0.0, 0.0, 0.0, 0.0);
                for (i, &ai) in a.iter().enumerate() {
                    let e = i32::try_from(i).unwrap();
                    s += ai * omega.powi(e);
                    sabs += (ai * omega.powi(e)).abs();
                    if i > 0 {
                        d += f64::from(e) * ai * omega.powi(e - 1);
                        dabs += (f64::from(e) * ai * omega.powi(e - 1)).abs();
                    }
                }
                assert!((mu - s).abs() <= 1e-14 * sabs, "ω = {omega}: {mu} vs {s}");
                assert!(
                    (dmu - d).abs() <= 1e-14 * dabs.max(f64::MIN_POSITIVE),
                    "ω = {omega}: {dmu} vs {d}"
                );
            }
        }
    }

    /// friction-math §3: `∂τ_c/∂p = μ`, `∂τ_c/∂ω = μ'(ω) p` against central
    /// differences (steps 1e-4 p, 1e-4 max(ω, 1)) over grids of p and ω, for the
    /// quintic and for the square-cup fit on both sides of the clamp (where the
    /// ω-derivative is 0). Tolerance: relative 1e-6.
    #[test]
    fn wh_derivatives_match_central_differences() {
        let cup = Wh::linear(A0, A1, 0.05, 1e5).unwrap();
        for law in [quintic(), cup] {
            for &p in &[1e-3, 0.1, 1.0, 30.0, 500.0] {
                for &omega in &[0.0, 1.0, 50.0, 400.0, 900.0, 1500.0, 1900.0] {
                    let x = inputs(p, omega, f64::NAN);
                    let cs = law.critical_shear(&x);
                    let (fd_p, fd_w) =
                        central_differences(&law, &x, 1e-4 * p, 1e-4 * omega.max(1.0));
                    assert!(
                        rel(fd_p, cs.dtau_dp) <= 1e-6,
                        "p = {p}, ω = {omega}: {fd_p} vs {}",
                        cs.dtau_dp
                    );
                    assert!(
                        rel(fd_w, cs.dtau_domega) <= 1e-6,
                        "p = {p}, ω = {omega}: {fd_w} vs {}",
                        cs.dtau_domega
                    );
                }
            }
        }
    }

    /// friction-math §3 clamp with the square-cup fit: active exactly beyond
    /// `ω* = (a0 - μ_min)/(-a1)` (checked at ω*(1 ∓ 1e-9)), flag set, ∂τ_c/∂ω = 0,
    /// τ_c = μ_min p, no NaN even at ω = 1e12 N/mm.
    #[test]
    fn wh_clamp_activates_at_omega_star() {
        let p = 20.0;
        for mu_min in [0.0, 0.05] {
            let law = Wh::linear(A0, A1, mu_min, 1e5).unwrap();
            let star = (A0 - mu_min) / -A1;
            let before = law.critical_shear(&inputs(p, star * (1.0 - 1e-9), f64::NAN));
            let after = law.critical_shear(&inputs(p, star * (1.0 + 1e-9), f64::NAN));
            assert!(!before.clamped && rel(before.dtau_domega, A1 * p) <= 1e-15);
            assert!(after.clamped && after.dtau_domega == 0.0);
            assert!(rel(after.tau, mu_min * p) <= 1e-15 && after.dtau_dp == mu_min);
            let far = law.critical_shear(&inputs(p, 1e12, f64::NAN));
            assert!(far.clamped && far.tau == mu_min * p && far.tau >= 0.0);
            assert!(
                [far.tau, far.dtau_dp, far.dtau_domega]
                    .iter()
                    .all(|v| v.is_finite())
            );
            eprintln!("wh square cup, μ_min = {mu_min}: ω* = {star:.4} N/mm");
        }
    }

    /// friction-math §3 backward Euler for WH, through the shared return mapping:
    /// a slipping history (square-cup fit, μ_min = 0.05, p = 100 MPa, Δu = 0.5 mm
    /// per step, every 7th step at rest) crosses the clamp. ω is non-decreasing;
    /// each slipping step satisfies |t| = τ_c(ω_{n+1}) and the discrete equation
    /// `|t_tr| - k_T Δγ - μ(ω_n + τ Δγ) p = 0`, with `ω_{n+1} = ω_n + τ Δγ`;
    /// the clamp flag turns on exactly when ω_{n+1} > ω*. Tolerance: relative 1e-12,
    /// plus 4 ulp of |t_tr| where `|t_tr| - k_T Δγ` cancels and 4 ulp of ω for its
    /// increment (round-off of the data, not of the solver).
    #[test]
    fn wh_slipping_history_satisfies_backward_euler() {
        let (p, k_t, mu_min) = (100.0, 1e5, 0.05);
        let law = Wh::linear(A0, A1, mu_min, k_t).unwrap();
        let star = (A0 - mu_min) / -A1;
        let mut state = PointState::default();
        let kin = flat_kinematics();
        let (mut first_clamp, mut slips, mut rest_slip) = (None, 0, 0.0_f64);
        for n in 0..300 {
            let du = if n % 7 == 6 {
                Vec3::zeros()
            } else {
                Vec3::new(0.5, 0.0, 0.0)
            };
            let t_tr = state.t - k_t * du;
            let omega_n = state.omega;
            let out = step(
                &law,
                &Identity,
                TangentMode::Consistent,
                &mut state,
                &StepInput::new(p, du, kin),
            )
            .unwrap();
            assert!(state.omega >= omega_n, "ω decreased at step {n}");
            assert!(
                out.t
                    .iter()
                    .chain(out.tangent.iter())
                    .chain(out.dt_dp.iter())
                    .all(|v| v.is_finite())
            );
            if out.stick {
                assert_eq!(state.omega, omega_n);
                continue;
            }
            slips += 1;
            let tau = out.t.norm();
            let cs_end = law.critical_shear(&inputs(p, state.omega, f64::NAN));
            assert!(
                rel(tau, cs_end.tau) <= 1e-12,
                "step {n}: |t| = {tau} vs τ_c(ω_n+1) = {}",
                cs_end.tau
            );
            // `|t_tr| - k_T Δγ` cancels (|t_tr| ≈ 5e4 MPa, τ ≈ 10 MPa here): allow
            // 4 ulp of |t_tr| on top of the relative 1e-12.
            let slack = 1e-12 * tau + 4.0 * f64::EPSILON * t_tr.norm();
            assert!(
                (t_tr.norm() - k_t * out.dgamma - tau).abs() <= slack,
                "step {n}: radial return"
            );
            // ω is a running sum: its increment is resolved only to a few ulp of ω.
            let d_omega = state.omega - omega_n;
            assert!(
                (d_omega - tau * out.dgamma).abs()
                    <= 1e-12 * tau * out.dgamma + 4.0 * f64::EPSILON * state.omega,
                "step {n}: ΔD {d_omega} vs τ Δγ = {}",
                tau * out.dgamma
            );
            if du == Vec3::zeros() {
                // At rest |t_tr| = |t_n| = τ_c(ω_n) to the 1e-12 checked above, so any
                // slip is bounded by 1e-12 τ / k_T.
                rest_slip = rest_slip.max(out.dgamma);
                assert!(
                    out.dgamma <= 1e-12 * tau / k_t,
                    "step {n}: Δγ = {}",
                    out.dgamma
                );
            }
            let residual = t_tr.norm()
                - k_t * out.dgamma
                - law
                    .critical_shear(&inputs(p, omega_n + tau * out.dgamma, f64::NAN))
                    .tau;
            assert!(
                residual.abs() <= slack,
                "step {n}: backward-Euler residual {residual}"
            );
            assert_eq!(
                out.clamped,
                state.omega > star,
                "step {n}: ω = {}",
                state.omega
            );
            if out.clamped && first_clamp.is_none() {
                first_clamp = Some((n, omega_n, state.omega));
            }
        }
        let (n, before, after) = first_clamp.expect("the clamp never activated");
        assert!(before <= star && after > star);
        assert!(rel(state.t.norm(), mu_min * p) <= 1e-12);
        eprintln!(
            "wh history: {slips} slipping steps, clamp first active at step {n} \
             (ω {before:.3} -> {after:.3} N/mm, ω* = {star:.3}), final ω = {:.3}; \
             largest round-off Δγ at rest {rest_slip:.1e} mm",
            state.omega
        );
    }

    /// friction-math §5 validation: negative a0 or μ_min, k_T ≤ 0, NaN or infinite
    /// coefficients, unknown keys: errors naming the parameter.
    #[test]
    fn wh_validation_names_the_parameter() {
        let e = Wh::linear(-0.1, A1, 0.0, 1e5).unwrap_err().to_string();
        assert!(e.contains("`a0`"), "{e}");
        let e = Wh::linear(A0, f64::NAN, 0.0, 1e5).unwrap_err().to_string();
        assert!(e.contains("`a1`") && e.contains("any finite value"), "{e}");
        let e = Wh::new([A0, 0.0, 0.0, 0.0, 0.0, f64::INFINITY], 0.0, 1e5)
            .unwrap_err()
            .to_string();
        assert!(e.contains("`a5`"), "{e}");
        let e = Wh::linear(A0, A1, -0.01, 1e5).unwrap_err().to_string();
        assert!(e.contains("`mu_min`"), "{e}");
        let e = Wh::linear(A0, A1, 0.0, 0.0).unwrap_err().to_string();
        assert!(e.contains("`k_t`"), "{e}");
        let e = Params::new()
            .with("a0", 0.1)
            .with("a6", 1.0)
            .resolve("wh", Wh::PARAMS)
            .unwrap_err()
            .to_string();
        assert!(e.contains("a6") && e.contains("known: a0, a1"), "{e}");
        let v = Params::new()
            .with("a0", A0)
            .with("a1", A1)
            .resolve("wh", Wh::PARAMS)
            .unwrap();
        assert_eq!(
            v,
            vec![
                A0,
                A1,
                0.0,
                0.0,
                0.0,
                0.0,
                0.0,
                crate::laws::DEFAULT_STICK_STIFFNESS
            ]
        );
        let law = Wh::build(&v).unwrap();
        assert!(law.work_dependent() && law.name() == "wh");
    }
}
