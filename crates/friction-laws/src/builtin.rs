//! Monomorphised pairings of the built-in laws and formulations (enum dispatch).
//!
//! [`integrator`] turns names into a `Box<dyn PointIntegrator>` whose inside is
//! a [`PairedIntegrator`] over the *concrete* law and formulation types: one
//! virtual call per batch of points, none per floating-point operation. A law
//! that is not built in (a statically linked plugin found in the registry, or a
//! dynamically loaded one passed to [`with_law`]) is paired as a trait object
//! with a concrete formulation.

use plugins_api::{
    DirectionInputs, FrictionError, FrictionLaw, KinematicFormulation, PairedIntegrator, Params,
    PointIntegrator, PointNeeds, StepKinematics, TangentMode, Vec3, registry,
};

use crate::formulations::{
    Convective, Jaumann, Lagrangian, UpdatedLagrangian, convective, jaumann, lagrangian,
    updated_lagrangian,
};
use crate::laws::{Ac, Levanov, Wh, Wvs};

/// Names of the built-in laws, in the thesis's order.
pub const LAW_NAMES: [&str; 4] = [Ac::NAME, Wvs::NAME, Wh::NAME, Levanov::NAME];
/// Names of the built-in formulations, in the thesis's order.
pub const FORMULATION_NAMES: [&str; 4] = [
    convective::NAME,
    jaumann::NAME,
    lagrangian::NAME,
    updated_lagrangian::NAME,
];

/// Any built-in formulation, dispatched by `match`.
#[derive(Clone, Copy, Debug)]
pub enum BuiltinFormulation {
    /// `convective`.
    Convective(Convective),
    /// `jaumann`.
    Jaumann(Jaumann),
    /// `lagrangian`.
    Lagrangian(Lagrangian),
    /// `updated-lagrangian`.
    UpdatedLagrangian(UpdatedLagrangian),
}

impl BuiltinFormulation {
    /// The built-in formulation called `name`.
    ///
    /// # Errors
    /// [`FrictionError::UnknownComponent`] listing the built-in names.
    pub fn from_name(name: &str) -> Result<Self, FrictionError> {
        Ok(match name {
            "convective" => Self::Convective(Convective),
            "jaumann" => Self::Jaumann(Jaumann),
            "lagrangian" => Self::Lagrangian(Lagrangian),
            "updated-lagrangian" => Self::UpdatedLagrangian(UpdatedLagrangian),
            _ => {
                return Err(FrictionError::UnknownComponent {
                    kind: "formulation",
                    name: name.to_string(),
                    known: FORMULATION_NAMES.join(", "),
                });
            }
        })
    }
}

macro_rules! dispatch_formulation {
    ($self:ident, $f:ident => $body:expr) => {
        match $self {
            BuiltinFormulation::Convective($f) => $body,
            BuiltinFormulation::Jaumann($f) => $body,
            BuiltinFormulation::Lagrangian($f) => $body,
            BuiltinFormulation::UpdatedLagrangian($f) => $body,
        }
    };
}

impl KinematicFormulation for BuiltinFormulation {
    fn name(&self) -> &str {
        dispatch_formulation!(self, f => f.name())
    }
    fn needs(&self) -> PointNeeds {
        dispatch_formulation!(self, f => f.needs())
    }
    #[inline]
    fn transport(&self, t_old: &Vec3, kin: &StepKinematics) -> Vec3 {
        dispatch_formulation!(self, f => f.transport(t_old, kin))
    }
    #[inline]
    fn slip_direction(&self, x: &DirectionInputs<'_>) -> Option<Vec3> {
        dispatch_formulation!(self, f => f.slip_direction(x))
    }
    fn backward_euler(&self) -> bool {
        dispatch_formulation!(self, f => f.backward_euler())
    }
}

fn pair<L: FrictionLaw + 'static>(
    law: L,
    formulation: &str,
    tangent: TangentMode,
) -> Result<Box<dyn PointIntegrator>, FrictionError> {
    let boxed: Box<dyn PointIntegrator> = match BuiltinFormulation::from_name(formulation)? {
        BuiltinFormulation::Convective(f) => Box::new(PairedIntegrator {
            law,
            formulation: f,
            tangent,
        }),
        BuiltinFormulation::Jaumann(f) => Box::new(PairedIntegrator {
            law,
            formulation: f,
            tangent,
        }),
        BuiltinFormulation::Lagrangian(f) => Box::new(PairedIntegrator {
            law,
            formulation: f,
            tangent,
        }),
        BuiltinFormulation::UpdatedLagrangian(f) => Box::new(PairedIntegrator {
            law,
            formulation: f,
            tangent,
        }),
    };
    Ok(boxed)
}

/// A point integrator for the law `law` (built-in, or registered by a linked
/// plugin) with `params`, paired with the built-in formulation `formulation`.
///
/// # Errors
/// Unknown law or formulation (listing the known ones); parameter errors.
pub fn integrator(
    law: &str,
    params: &Params,
    formulation: &str,
    tangent: TangentMode,
) -> Result<Box<dyn PointIntegrator>, FrictionError> {
    // Validate the formulation first so that a typo there is reported even when
    // the law is also wrong.
    BuiltinFormulation::from_name(formulation)?;
    match law {
        "ac" => pair(
            Ac::from_values(&params.resolve(law, Ac::PARAMS)?)?,
            formulation,
            tangent,
        ),
        "wvs" => pair(
            Wvs::from_values(&params.resolve(law, Wvs::PARAMS)?)?,
            formulation,
            tangent,
        ),
        "wh" => pair(
            Wh::from_values(&params.resolve(law, Wh::PARAMS)?)?,
            formulation,
            tangent,
        ),
        "levanov" => pair(
            Levanov::from_values(&params.resolve(law, Levanov::PARAMS)?)?,
            formulation,
            tangent,
        ),
        other => with_law(registry::build_law(other, params)?, formulation, tangent),
    }
}

/// A point integrator for an already built law (e.g. a dynamically loaded
/// plugin), paired with the built-in formulation `formulation`.
///
/// # Errors
/// Unknown formulation.
pub fn with_law(
    law: Box<dyn FrictionLaw>,
    formulation: &str,
    tangent: TangentMode,
) -> Result<Box<dyn PointIntegrator>, FrictionError> {
    pair(law, formulation, tangent)
}

/// Parameters of the NUMISHEET'93 square-cup benchmark for each built-in law
/// (friction-math §7; WH's α converted from mm/kN to mm/N; Levanov's friction
/// factor chosen so that its small-pressure limit `c m/√3` equals AC's 0.144).
#[must_use]
pub fn benchmark_params(law: &str) -> Params {
    match law {
        "ac" => Params::new().with("mu", 0.144),
        "wvs" => Params::new()
            .with("alpha", 0.03)
            .with("beta", 0.144)
            .with("nu", 0.8),
        "wh" => Params::new().with("a0", 0.1448).with("a1", -8.757e-5),
        "levanov" => Params::new().with("m", 0.144 * 3f64.sqrt() / 1.25),
        _ => Params::new(),
    }
}
