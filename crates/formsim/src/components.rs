//! Resolving user-named components (built-in law, linked plugin, plugin file,
//! formulation) into point integrators and conformance subjects.

use std::path::PathBuf;

use friction_laws::builtin::{self, BuiltinFormulation, FORMULATION_NAMES, Formulation};
use plugins_api::loader::PluginLibrary;
use plugins_api::{FrictionError, ParamSpec, Params, PointIntegrator, TangentMode};

/// Where a friction law comes from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LawSource {
    /// A law in the registry (built-in or statically linked plugin), by name.
    Named(String),
    /// A dynamic plugin, by the path of its shared library.
    Plugin(PathBuf),
}

/// A point integrator for `source` with `params`, paired with the
/// formulation `formulation` (built in or registered) with
/// `formulation_params`.
///
/// # Errors
/// Unknown law/formulation, parameter errors, plugin loading errors.
pub fn point_integrator(
    source: &LawSource,
    params: &Params,
    formulation: &str,
    formulation_params: &Params,
    tangent: TangentMode,
) -> Result<Box<dyn PointIntegrator>, FrictionError> {
    // The formulation first, so that a typo there is reported even when the
    // law is also wrong.
    let formulation = Formulation::resolve(formulation, formulation_params)?;
    match source {
        LawSource::Named(name) => builtin::integrator_with(name, params, formulation, tangent),
        LawSource::Plugin(path) => {
            let library = PluginLibrary::open(path)?;
            Ok(builtin::with_law_in(
                library.build(params)?,
                formulation,
                tangent,
            ))
        }
    }
}

/// The built-in formulations, in the thesis's order.
#[must_use]
pub fn all_formulations() -> Vec<BuiltinFormulation> {
    FORMULATION_NAMES
        .iter()
        .map(|n| BuiltinFormulation::from_name(n).expect("built-in formulation names are valid"))
        .collect()
}

/// A base parameter set for the conformance suite: the user's values, then the
/// benchmark values of a built-in law, then for any remaining required
/// parameter a value inside its range (reported by the caller).
#[must_use]
pub fn suite_params(law: &str, specs: &[ParamSpec], given: &Params) -> (Params, Vec<String>) {
    let mut params = builtin::benchmark_params(law);
    for (k, v) in &given.0 {
        params.set(k, *v);
    }
    let mut chosen = Vec::new();
    for spec in specs {
        if spec.default.is_none() && !params.0.contains_key(spec.name) {
            let lo = if spec.min.is_finite() { spec.min } else { 0.0 };
            let hi = spec.max.min(lo + 0.2);
            let value = if hi > lo { lo + 0.5 * (hi - lo) } else { lo };
            params.set(spec.name, value);
            chosen.push(format!("{}={}", spec.name, value));
        }
    }
    (params, chosen)
}
