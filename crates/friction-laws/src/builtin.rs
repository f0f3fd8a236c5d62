//! Monomorphised pairings of the built-in laws and formulations (enum dispatch).
//!
//! [`integrator`] turns names into a `Box<dyn PointIntegrator>` whose inside is
//! a [`PairedIntegrator`] over the *concrete* law and formulation types: one
//! virtual call per batch of points, none per floating-point operation. A law
//! that is not built in (a statically linked plugin found in the registry, or a
//! dynamically loaded one passed to [`with_law`]) is paired as a trait object
//! with a concrete formulation; a formulation that is not built in (registered
//! by a linked crate) is paired as a trait object too.
//!
//! The built-in laws and formulations are listed once, in `builtins!`: the
//! names ([`LAW_NAMES`], [`FORMULATION_NAMES`]), the enum
//! [`BuiltinFormulation`], every pairing and the registrations
//! (`registration.rs`) are generated from that list. A new built-in law or
//! formulation is its file plus one entry there.

use plugins_api::{
    DirectionInputs, FrictionError, FrictionLaw, KinematicFormulation, PairedIntegrator, Params,
    PointIntegrator, PointNeeds, StepKinematics, TangentMode, Vec3, registry,
};

use crate::formulations::{
    Convective, Jaumann, Lagrangian, UpdatedLagrangian, convective, jaumann, lagrangian,
    updated_lagrangian,
};
use crate::laws::{Ac, Levanov, Wh, Wvs};

/// The one list of built-in components: calls `$generate!` with the laws
/// (types with `NAME`, `PARAMS`, `DESCRIPTION`, `from_values`, `build`) and
/// the formulations (`Type in module`, the module holding `NAME` and
/// `SUMMARY`), in the thesis's order.
macro_rules! builtins {
    ($generate:ident) => {
        $generate! {
            laws: [Ac, Wvs, Wh, Levanov],
            formulations: [
                Convective in convective,
                Jaumann in jaumann,
                Lagrangian in lagrangian,
                UpdatedLagrangian in updated_lagrangian,
            ]
        }
    };
}
pub(crate) use builtins;

/// The number of its arguments, as a `usize` constant.
macro_rules! count {
    () => { 0usize };
    ($head:tt $($tail:tt)*) => { 1usize + count!($($tail)*) };
}

/// Names, the formulation enum and its dispatch, and the pairings.
macro_rules! pairings {
    (laws: [$($law:ident),+], formulations: [$($form:ident in $module:ident),+ $(,)?]) => {
        /// Names of the built-in laws, in the thesis's order.
        pub const LAW_NAMES: [&str; count!($($law)+)] = [$($law::NAME),+];
        /// Names of the built-in formulations, in the thesis's order.
        pub const FORMULATION_NAMES: [&str; count!($($form)+)] = [$($module::NAME),+];

        /// Any built-in formulation, dispatched by `match`.
        #[derive(Clone, Copy, Debug)]
        pub enum BuiltinFormulation {
            $(
                #[doc = concat!("`", stringify!($module), "`.")]
                $form($form),
            )+
        }

        impl BuiltinFormulation {
            /// The built-in formulation called `name`, if there is one.
            fn built_in(name: &str) -> Option<Self> {
                $(if name == $module::NAME {
                    return Some(Self::$form($form));
                })+
                None
            }
        }

        impl KinematicFormulation for BuiltinFormulation {
            fn name(&self) -> &str {
                match self { $(Self::$form(f) => f.name(),)+ }
            }
            fn needs(&self) -> PointNeeds {
                match self { $(Self::$form(f) => f.needs(),)+ }
            }
            #[inline]
            fn transport(&self, t_old: &Vec3, kin: &StepKinematics) -> Vec3 {
                match self { $(Self::$form(f) => f.transport(t_old, kin),)+ }
            }
            #[inline]
            fn slip_direction(&self, x: &DirectionInputs<'_>) -> Option<Vec3> {
                match self { $(Self::$form(f) => f.slip_direction(x),)+ }
            }
            fn backward_euler(&self) -> bool {
                match self { $(Self::$form(f) => f.backward_euler(),)+ }
            }
        }

        /// `law` paired with `formulation`, monomorphised over both types
        /// when the formulation is built in.
        fn pair<L: FrictionLaw + 'static>(
            law: L,
            formulation: Formulation,
            tangent: TangentMode,
        ) -> Box<dyn PointIntegrator> {
            match formulation {
                $(Formulation::Builtin(BuiltinFormulation::$form(f)) => Box::new(PairedIntegrator {
                    law,
                    formulation: f,
                    tangent,
                }),)+
                Formulation::Registered(f) => Box::new(PairedIntegrator {
                    law,
                    formulation: f,
                    tangent,
                }),
            }
        }

        /// The built-in law `law` with `params` paired with `formulation`;
        /// the formulation back when `law` is not built in.
        fn built_in_law(
            law: &str,
            params: &Params,
            formulation: Formulation,
            tangent: TangentMode,
        ) -> Result<Result<Box<dyn PointIntegrator>, FrictionError>, Formulation> {
            $(if law == $law::NAME {
                let built = params
                    .resolve(law, $law::PARAMS)
                    .and_then(|v| $law::from_values(&v));
                return Ok(built.map(|l| pair(l, formulation, tangent)));
            })+
            Err(formulation)
        }
    };
}

builtins!(pairings);

impl BuiltinFormulation {
    /// The built-in formulation called `name`.
    ///
    /// # Errors
    /// [`FrictionError::UnknownComponent`] listing the built-in names.
    pub fn from_name(name: &str) -> Result<Self, FrictionError> {
        Self::built_in(name).ok_or_else(|| FrictionError::UnknownComponent {
            kind: "formulation",
            name: name.to_string(),
            known: FORMULATION_NAMES.join(", "),
        })
    }
}

/// A formulation resolved by name: a built-in one (monomorphised), or one a
/// linked crate registered (a trait object).
pub enum Formulation {
    /// Built in.
    Builtin(BuiltinFormulation),
    /// Registered in [`plugins_api::registry`] by another crate.
    Registered(Box<dyn KinematicFormulation>),
}

impl std::fmt::Debug for Formulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Builtin(b) => write!(f, "Builtin({b:?})"),
            Self::Registered(r) => write!(f, "Registered({})", r.name()),
        }
    }
}

impl Formulation {
    /// The formulation called `name` with `params` (a built-in one takes none).
    ///
    /// # Errors
    /// [`FrictionError::UnknownComponent`] listing the registered formulations;
    /// parameter errors.
    pub fn resolve(name: &str, params: &Params) -> Result<Self, FrictionError> {
        match BuiltinFormulation::built_in(name) {
            Some(f) => {
                params.resolve(name, &[])?;
                Ok(Self::Builtin(f))
            }
            None => registry::build_formulation(name, params).map(Self::Registered),
        }
    }
}

/// A point integrator for the law `law` (built-in, or registered by a linked
/// plugin) with `params`, paired with the formulation `formulation` (built
/// in, or registered).
///
/// # Errors
/// Unknown law or formulation (listing the known ones); parameter errors.
pub fn integrator(
    law: &str,
    params: &Params,
    formulation: &str,
    tangent: TangentMode,
) -> Result<Box<dyn PointIntegrator>, FrictionError> {
    // Resolve the formulation first so that a typo there is reported even
    // when the law is also wrong.
    let formulation = Formulation::resolve(formulation, &Params::new())?;
    integrator_with(law, params, formulation, tangent)
}

/// [`integrator`] with an already resolved formulation (one with parameters).
///
/// # Errors
/// Unknown law; parameter errors.
pub fn integrator_with(
    law: &str,
    params: &Params,
    formulation: Formulation,
    tangent: TangentMode,
) -> Result<Box<dyn PointIntegrator>, FrictionError> {
    match built_in_law(law, params, formulation, tangent) {
        Ok(built) => built,
        Err(formulation) => Ok(pair(
            registry::build_law(law, params)?,
            formulation,
            tangent,
        )),
    }
}

/// A point integrator for an already built law (e.g. a dynamically loaded
/// plugin), paired with the formulation `formulation` (built in, or
/// registered, without parameters).
///
/// # Errors
/// Unknown formulation.
pub fn with_law(
    law: Box<dyn FrictionLaw>,
    formulation: &str,
    tangent: TangentMode,
) -> Result<Box<dyn PointIntegrator>, FrictionError> {
    Ok(with_law_in(
        law,
        Formulation::resolve(formulation, &Params::new())?,
        tangent,
    ))
}

/// [`with_law`] with an already resolved formulation.
#[must_use]
pub fn with_law_in(
    law: Box<dyn FrictionLaw>,
    formulation: Formulation,
    tangent: TangentMode,
) -> Box<dyn PointIntegrator> {
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
