//! The friction coefficient of the analytic references (capstan `e^{μθ}`,
//! block `μN`, strip `2μF`), read from the scene's active contact law: the
//! law is built with the scene's parameters and probed; it has a Coulomb
//! coefficient when `τ_c = μ p` over pressures and frictional work, and no
//! analytic reference otherwise.

use crate::scene::LoadedScene;
use plugins_api::{FrictionLaw, Params, ShearInputs, registry};

/// Pressures (MPa) and frictional work densities (N/mm) at which the law is
/// probed: from near lift-off to well above the benchmarks' pressures.
const PROBE_PRESSURES: [f64; 4] = [1e-3, 1.0, 30.0, 300.0];
const PROBE_WORK: [f64; 3] = [0.0, 10.0, 1e3];
/// Flow stresses (MPa) at which it is probed (Levanov's `τ_c` depends on it).
const PROBE_FLOW_STRESS: [f64; 2] = [100.0, 400.0];
/// How closely `τ_c / p` must agree over the probes to be one coefficient.
const SAME_MU: f64 = 1e-9;

/// Why the scene's contact law has no Coulomb coefficient ([`coulomb_mu`]).
#[derive(Debug, thiserror::Error)]
pub enum ReferenceError {
    /// The contact law is a dynamic plugin.
    #[error("the contact law is a plugin")]
    Plugin,
    /// Some pairs use another law than the scene's.
    #[error("the pairs use different laws")]
    MixedLaws,
    /// The law does not build with the scene's parameters.
    #[error(transparent)]
    Build(#[from] plugins_api::FrictionError),
    /// `τ_c / p` is not the same, finite and positive at every probe.
    #[error(
        "law `{law}` is not Coulomb (τ_c/p = {first:.6} and {ratio:.6} at p = {p} MPa, \
         ω = {omega} N/mm, σ_y = {flow_stress} MPa)"
    )]
    NotCoulomb {
        /// The law's name.
        law: String,
        /// `τ_c / p` at the first probe.
        first: f64,
        /// `τ_c / p` at this probe.
        ratio: f64,
        /// Pressure of this probe (MPa).
        p: f64,
        /// Frictional work density of this probe (N/mm).
        omega: f64,
        /// Flow stress of this probe (MPa).
        flow_stress: f64,
    },
    /// No probe was made.
    #[error("law `{law}` was not probed")]
    NotProbed {
        /// The law's name.
        law: String,
    },
}

/// The Coulomb coefficient of the scene's active law, or why there is none.
///
/// # Errors
/// A plugin law or per-pair laws (no single named law), a law that is not
/// proportional to the pressure, or one that fails to build; each says so.
pub fn coulomb_mu(loaded: &LoadedScene) -> Result<f64, ReferenceError> {
    let c = &loaded.scene.contact;
    if c.plugin.is_some() {
        return Err(ReferenceError::Plugin);
    }
    if c.pairs
        .iter()
        .any(|p| p.law.as_ref().is_some_and(|l| *l != c.law))
    {
        return Err(ReferenceError::MixedLaws);
    }
    let mut params = Params::new();
    if let Some(table) = c.params.get(&c.law) {
        for (name, v) in table {
            params.set(name, *v);
        }
    }
    let law = registry::build_law(&c.law, &params)?;
    mu_of(law.as_ref())
}

/// `τ_c / p` of `law` if it is the same, finite and positive at every probe.
fn mu_of(law: &dyn FrictionLaw) -> Result<f64, ReferenceError> {
    let mut mu: Option<f64> = None;
    for &p in &PROBE_PRESSURES {
        for &omega in &PROBE_WORK {
            for &flow_stress in &PROBE_FLOW_STRESS {
                let x = ShearInputs {
                    p,
                    omega,
                    sliding_speed: 0.0,
                    flow_stress,
                    temperature: 300.0,
                };
                let m = law.critical_shear(&x).tau / p;
                let m0 = *mu.get_or_insert(m);
                // Written so that a NaN fails the test.
                if !(m.is_finite() && m > 0.0 && (m - m0).abs() <= SAME_MU * m0.abs()) {
                    return Err(ReferenceError::NotCoulomb {
                        law: law.name().to_string(),
                        first: m0,
                        ratio: m,
                        p,
                        omega,
                        flow_stress,
                    });
                }
            }
        }
    }
    mu.ok_or_else(|| ReferenceError::NotProbed {
        law: law.name().to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// AC gives its μ; WVS with ν = 1 is Coulomb with μ = α + β
    /// (friction-math §7); WVS with ν = 0.8, WH with a1 ≠ 0 and Levanov
    /// (saturating in p against the flow stress) are not; μ = 0 gives no
    /// reference.
    #[test]
    fn coulomb_mu_of_the_builtin_laws() {
        friction_laws::ensure_linked();
        let build = |name: &str, kv: &[(&str, f64)]| {
            let mut p = Params::new();
            for (k, v) in kv {
                p.set(k, *v);
            }
            registry::build_law(name, &p).unwrap()
        };
        let ac = build("ac", &[("mu", 0.144)]);
        assert!((mu_of(ac.as_ref()).unwrap() - 0.144).abs() < 1e-15);
        let wvs = build("wvs", &[("alpha", 0.0), ("beta", 0.144), ("nu", 1.0)]);
        assert!((mu_of(wvs.as_ref()).unwrap() - 0.144).abs() < 1e-12);
        let wvs = build("wvs", &[("alpha", 0.03), ("beta", 0.144), ("nu", 0.8)]);
        assert!(mu_of(wvs.as_ref()).is_err());
        let wh = build("wh", &[("a0", 0.1448), ("a1", -8.757e-5)]);
        assert!(mu_of(wh.as_ref()).is_err());
        let wh = build("wh", &[("a0", 0.2), ("a1", 0.0)]);
        assert!((mu_of(wh.as_ref()).unwrap() - 0.2).abs() < 1e-15);
        let levanov = build("levanov", &[("m", 0.2), ("c", 1.25)]);
        assert!(mu_of(levanov.as_ref()).is_err());
        let frictionless = build("ac", &[("mu", 0.0)]);
        assert!(mu_of(frictionless.as_ref()).is_err());
    }
}
