//! # exp-decay: an example formsim friction plugin (static → kinetic Coulomb law)
//!
//! The friction coefficient decays exponentially with the sliding speed from its
//! static value `μ_s` to its kinetic value `μ_k`:
//!
//! ```text
//! μ(v) = μ_k + (μ_s - μ_k) exp(-d |v|),      τ_c = μ(v) p
//! ∂τ_c/∂p = μ(v),   ∂τ_c/∂|v| = -d (μ_s - μ_k) exp(-d |v|) p,   ∂τ_c/∂ω = 0
//! ```
//!
//! `μ_k > μ_s` is allowed (velocity *strengthening*, e.g. lubricated contact);
//! since `μ` stays between `μ_s` and `μ_k`, `τ_c ≥ 0` whenever both are `≥ 0`.
//! `d = 0` gives Amontons–Coulomb with `μ = μ_s`.
//!
//! The law only depends on `plugins-api`; `export_friction_law!` turns it into
//! a shared library formsim loads at run time (see `plugins/README.md`).

use plugins_api::abi::PluginLaw;
use plugins_api::{CriticalShear, FrictionLaw, ParamSpec, PointNeeds, ShearInputs};

/// The exponential-decay static/kinetic law; parameters as in [`ExpDecay::PARAMS`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExpDecay {
    /// Static friction coefficient `μ_s` (-), at `v = 0`.
    pub mu_s: f64,
    /// Kinetic friction coefficient `μ_k` (-), as `v → ∞`.
    pub mu_k: f64,
    /// Decay coefficient `d` (s/mm).
    pub d: f64,
    /// Stick stiffness `k_T` (MPa/mm).
    pub k_t: f64,
}

impl FrictionLaw for ExpDecay {
    fn name(&self) -> &str {
        Self::NAME
    }
    fn stick_stiffness(&self) -> f64 {
        self.k_t
    }
    fn needs(&self) -> PointNeeds {
        Self::NEEDS
    }
    fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
        // `d = 0` must not meet `v = ∞` in `0 · ∞ = NaN`.
        let decay = if self.d == 0.0 {
            1.0
        } else {
            (-self.d * x.sliding_speed.abs()).exp()
        };
        let mu = self.mu_k + (self.mu_s - self.mu_k) * decay;
        CriticalShear {
            tau: mu * x.p,
            dtau_dp: mu,
            dtau_domega: 0.0,
            dtau_dspeed: -self.d * (self.mu_s - self.mu_k) * decay * x.p,
            clamped: false,
        }
    }
}

impl PluginLaw for ExpDecay {
    const NAME: &'static str = "exp-decay";
    const SUMMARY: &'static str =
        "tau_c = (mu_k + (mu_s - mu_k) exp(-d |v|)) p: static-to-kinetic Coulomb friction";
    const PARAMS: &'static [ParamSpec] = &[
        ParamSpec::required(
            "mu_s",
            "-",
            0.0,
            f64::INFINITY,
            "static friction coefficient (v = 0)",
        ),
        ParamSpec::required(
            "mu_k",
            "-",
            0.0,
            f64::INFINITY,
            "kinetic friction coefficient (v -> infinity)",
        ),
        ParamSpec::optional(
            "d",
            "s/mm",
            0.0,
            0.0,
            f64::INFINITY,
            "decay coefficient of mu with the sliding speed",
        ),
        ParamSpec::optional(
            "k_t",
            "MPa/mm",
            1e5,
            0.0,
            f64::INFINITY,
            "stick stiffness (regularisation)",
        )
        .exclusive_min(),
    ];
    const NEEDS: PointNeeds = PointNeeds::SLIDING_VELOCITY;

    fn from_values(v: &[f64]) -> Result<Self, String> {
        // The host has checked count and ranges against PARAMS.
        Ok(Self {
            mu_s: v[0],
            mu_k: v[1],
            d: v[2],
            k_t: v[3],
        })
    }
}

plugins_api::export_friction_law!(ExpDecay);

#[cfg(test)]
mod tests {
    use super::*;

    const LAW: ExpDecay = ExpDecay {
        mu_s: 0.2,
        mu_k: 0.1,
        d: 0.05,
        k_t: 1e5,
    };

    fn at(p: f64, v: f64) -> ShearInputs {
        ShearInputs {
            p,
            omega: 0.0,
            sliding_speed: v,
            flow_stress: f64::NAN,
            temperature: f64::NAN,
        }
    }

    /// Closed form of the module docs; derivatives against central differences
    /// (step 1e-6 relative; tolerance 1e-7 relative, the truncation + round-off
    /// level of a central difference of a smooth function).
    #[test]
    fn derivatives_match_central_differences() {
        for law in [
            LAW,
            ExpDecay {
                mu_s: 0.1,
                mu_k: 0.3,
                ..LAW
            },
        ] {
            for &p in &[0.5, 10.0, 250.0] {
                for &v in &[0.0, 1.0, 20.0, 300.0] {
                    let cs = law.critical_shear(&at(p, v));
                    let hp = 1e-6 * p;
                    let fd_p = (law.critical_shear(&at(p + hp, v)).tau
                        - law.critical_shear(&at(p - hp, v)).tau)
                        / (2.0 * hp);
                    assert!(
                        (fd_p - cs.dtau_dp).abs() <= 1e-7 * cs.dtau_dp.abs(),
                        "p={p} v={v}: {fd_p} vs {}",
                        cs.dtau_dp
                    );
                    // One-sided at v = 0, where |v| has a kink: the law's slope is the right derivative.
                    let hv = 1e-6 * v.max(1.0);
                    let fd_v = if v == 0.0 {
                        (law.critical_shear(&at(p, hv)).tau - cs.tau) / hv
                    } else {
                        (law.critical_shear(&at(p, v + hv)).tau
                            - law.critical_shear(&at(p, v - hv)).tau)
                            / (2.0 * hv)
                    };
                    let tol = if v == 0.0 { 1e-5 } else { 1e-7 };
                    let scale = (law.d * (law.mu_s - law.mu_k) * p).abs();
                    assert!(
                        (fd_v - cs.dtau_dspeed).abs() <= tol * scale,
                        "p={p} v={v}: {fd_v} vs {}",
                        cs.dtau_dspeed
                    );
                    assert_eq!(cs.dtau_domega, 0.0);
                }
            }
        }
    }

    /// Limits of the closed form: `μ(0) = μ_s`, `μ(∞) = μ_k`, `d = 0` is
    /// Coulomb with `μ_s`; all finite, `τ_c ≥ 0` (exact comparisons: the formula
    /// reduces to one product in each case).
    #[test]
    fn limits_static_kinetic_and_coulomb() {
        assert_eq!(LAW.critical_shear(&at(10.0, 0.0)).tau, 0.2 * 10.0);
        let fast = LAW.critical_shear(&at(10.0, f64::INFINITY));
        assert_eq!((fast.tau, fast.dtau_dspeed), (0.1 * 10.0, 0.0));
        let coulomb = ExpDecay { d: 0.0, ..LAW }.critical_shear(&at(10.0, f64::INFINITY));
        assert_eq!((coulomb.tau, coulomb.dtau_dspeed), (0.2 * 10.0, 0.0));
        assert_eq!(LAW.critical_shear(&at(0.0, 5.0)).tau, 0.0);
    }

    /// The exported table describes the law: the macro's output as the host sees it.
    #[test]
    fn exported_table_describes_the_law() {
        let table = formsim_friction_plugin_v1();
        assert!(!table.is_null());
        // SAFETY: the entry returns a leaked 'static table.
        let t = unsafe { &*table };
        assert_eq!(t.abi_version, plugins_api::ABI_VERSION);
        assert_eq!(t.needs, PointNeeds::SLIDING_VELOCITY.0);
        assert_eq!(t.n_params, 4);
        // SAFETY: leaked NUL-terminated string.
        assert_eq!(
            unsafe { std::ffi::CStr::from_ptr(t.name) }.to_str(),
            Ok("exp-decay")
        );
    }
}
