//! Registration of the built-in laws and formulations in the `plugins-api`
//! registry, generated from the one list of built-ins
//! ([`crate::builtin`]'s `builtins!`), with the function that keeps it linked.

use plugins_api::registry::{FormulationEntry, LawEntry};
use plugins_api::{FrictionError, KinematicFormulation};

use crate::builtin::builtins;
use crate::formulations::{
    Convective, Jaumann, Lagrangian, UpdatedLagrangian, convective, jaumann, lagrangian,
    updated_lagrangian,
};
use crate::laws::{Ac, Levanov, Wh, Wvs};

/// The registry's builder of a built-in formulation (they take no parameters).
fn build_formulation<F: KinematicFormulation + Default + 'static>(
    _values: &[f64],
) -> Result<Box<dyn KinematicFormulation>, FrictionError> {
    Ok(Box::new(F::default()))
}

/// One registry entry per built-in law and formulation.
macro_rules! registrations {
    (laws: [$($law:ident),+], formulations: [$($form:ident in $module:ident),+ $(,)?]) => {
        $(inventory::submit! { LawEntry { description: $law::DESCRIPTION, build: $law::build } })+
        $(inventory::submit! {
            FormulationEntry {
                name: $module::NAME,
                summary: $module::SUMMARY,
                params: &[],
                relative_cost: $module::RELATIVE_COST,
                build: build_formulation::<$form>,
            }
        })+
    };
}

builtins!(registrations);

/// Referenced by [`crate::ensure_linked`] so that this object file, and with it
/// the submissions above, is linked into every binary that uses the crate.
#[inline(never)]
pub(crate) fn keep() -> usize {
    std::hint::black_box(4)
}
