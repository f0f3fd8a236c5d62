//! # test-panicky: a misbehaving friction plugin, a fixture for the loader's tests
//!
//! Amontons–Coulomb (`τ_c = μ p`) that panics on request, so that
//! `plugins-api/tests/dynamic_plugin.rs` can show that a panic inside a plugin
//! becomes a readable error in the host and never aborts it. Not an example
//! to follow: see `plugins/exp-decay` for that.
//!
//! Test hooks (parameters): `panic_above_p` (MPa): `critical_shear` panics for
//! `p` above it; `create_mode`: 0 builds normally, 1 rejects the values with an
//! error, 2 panics while building.

use plugins_api::abi::PluginLaw;
use plugins_api::{CriticalShear, FrictionLaw, ParamSpec, ShearInputs};

/// Coulomb friction with a panic threshold.
#[derive(Clone, Copy, Debug)]
pub struct Panicky {
    mu: f64,
    panic_above_p: f64,
}

impl FrictionLaw for Panicky {
    fn name(&self) -> &str {
        Self::NAME
    }
    fn stick_stiffness(&self) -> f64 {
        1e5
    }
    fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
        if x.p > self.panic_above_p {
            panic!(
                "test-panicky: deliberate panic at p = {} MPa > panic_above_p = {} MPa",
                x.p, self.panic_above_p
            );
        }
        CriticalShear {
            tau: self.mu * x.p,
            dtau_dp: self.mu,
            ..CriticalShear::default()
        }
    }
}

impl PluginLaw for Panicky {
    const NAME: &'static str = "test-panicky";
    const SUMMARY: &'static str = "tau_c = mu p; panics above panic_above_p (loader test fixture)";
    const PARAMS: &'static [ParamSpec] = &[
        ParamSpec::optional("mu", "-", 0.1, 0.0, f64::INFINITY, "friction coefficient"),
        ParamSpec::optional(
            "panic_above_p",
            "MPa",
            1e300,
            0.0,
            f64::INFINITY,
            "critical_shear panics above this pressure",
        ),
        ParamSpec::optional(
            "create_mode",
            "-",
            0.0,
            0.0,
            2.0,
            "0: build, 1: reject the values, 2: panic while building",
        ),
    ];

    fn from_values(v: &[f64]) -> Result<Self, String> {
        if v[2] == 2.0 {
            panic!("test-panicky: deliberate panic while building");
        }
        if v[2] == 1.0 {
            return Err("test-panicky: create_mode = 1 rejects these values".to_string());
        }
        Ok(Self {
            mu: v[0],
            panic_above_p: v[1],
        })
    }
}

plugins_api::export_friction_law!(Panicky);
