//! Link-time registry of laws and formulations (`inventory`), looked up by
//! name. Each declares its parameters ([`ParamSpec`]: name, unit, default,
//! range, one line of doc) and is built from values resolved against them.
//!
//! A crate registers a component with `inventory::submit!`. The linker drops an
//! unreferenced crate's registrations, so every crate that registers components
//! exposes an `ensure_linked()` that its users call once (formsim's CLI does).

use crate::law::LawDescription;
use crate::{FrictionError, FrictionLaw, KinematicFormulation, ParamSpec, Params};

/// Builds a law from its parameter values, in the order of its schema.
pub type LawBuilder = fn(&[f64]) -> Result<Box<dyn FrictionLaw>, FrictionError>;

/// A registered friction law.
#[derive(Debug)]
pub struct LawEntry {
    /// Name, summary and parameter schema.
    pub description: LawDescription,
    /// Builder from resolved parameter values.
    pub build: LawBuilder,
}

/// Builds a formulation from its parameter values, in the order of its schema.
pub type FormulationBuilder = fn(&[f64]) -> Result<Box<dyn KinematicFormulation>, FrictionError>;

/// A registered kinematic formulation.
#[derive(Debug)]
pub struct FormulationEntry {
    /// Name as typed in scenes.
    pub name: &'static str,
    /// One-line summary.
    pub summary: &'static str,
    /// Its parameters (a scene's `[contact.params.NAME]`); the built-in
    /// formulations have none.
    pub params: &'static [ParamSpec],
    /// CPU time of a run with it relative to the same run with the
    /// `convective` formulation (1 for a formulation that costs what it
    /// costs): the batch engine starts the costliest runs first.
    pub relative_cost: f64,
    /// Builder from resolved parameter values.
    pub build: FormulationBuilder,
}

impl FormulationEntry {
    /// Resolve `params` against the schema and build the formulation.
    ///
    /// # Errors
    /// Parameter errors naming the parameter, its unit and range; builder errors.
    pub fn instantiate(
        &self,
        params: &Params,
    ) -> Result<Box<dyn KinematicFormulation>, FrictionError> {
        let values = params.resolve(self.name, self.params)?;
        (self.build)(&values)
    }
}

inventory::collect!(LawEntry);
inventory::collect!(FormulationEntry);

impl LawEntry {
    /// Resolve `params` against the schema and build the law.
    ///
    /// # Errors
    /// Parameter errors naming the parameter, its unit and range; builder errors.
    pub fn instantiate(&self, params: &Params) -> Result<Box<dyn FrictionLaw>, FrictionError> {
        let values = params.resolve(self.description.name, self.description.params)?;
        (self.build)(&values)
    }
}

/// All registered laws, sorted by name.
#[must_use]
pub fn laws() -> Vec<&'static LawEntry> {
    let mut v: Vec<_> = inventory::iter::<LawEntry>.into_iter().collect();
    v.sort_by_key(|e| e.description.name);
    v
}

/// All registered formulations, sorted by name.
#[must_use]
pub fn formulations() -> Vec<&'static FormulationEntry> {
    let mut v: Vec<_> = inventory::iter::<FormulationEntry>.into_iter().collect();
    v.sort_by_key(|e| e.name);
    v
}

/// The law registered under `name`.
///
/// # Errors
/// [`FrictionError::UnknownComponent`] listing the known laws.
pub fn law(name: &str) -> Result<&'static LawEntry, FrictionError> {
    laws()
        .into_iter()
        .find(|e| e.description.name == name)
        .ok_or_else(|| FrictionError::UnknownComponent {
            kind: "law",
            name: name.to_string(),
            known: laws()
                .iter()
                .map(|e| e.description.name)
                .collect::<Vec<_>>()
                .join(", "),
        })
}

/// The formulation registered under `name`.
///
/// # Errors
/// [`FrictionError::UnknownComponent`] listing the known formulations.
pub fn formulation(name: &str) -> Result<&'static FormulationEntry, FrictionError> {
    formulations()
        .into_iter()
        .find(|e| e.name == name)
        .ok_or_else(|| FrictionError::UnknownComponent {
            kind: "formulation",
            name: name.to_string(),
            known: formulations()
                .iter()
                .map(|e| e.name)
                .collect::<Vec<_>>()
                .join(", "),
        })
}

/// Build the law `name` with `params` (defaults for the rest).
///
/// # Errors
/// Unknown law; parameter errors.
pub fn build_law(name: &str, params: &Params) -> Result<Box<dyn FrictionLaw>, FrictionError> {
    law(name)?.instantiate(params)
}

/// Build the formulation `name` with `params` (defaults for the rest).
///
/// # Errors
/// Unknown formulation; parameter errors.
pub fn build_formulation(
    name: &str,
    params: &Params,
) -> Result<Box<dyn KinematicFormulation>, FrictionError> {
    formulation(name)?.instantiate(params)
}
