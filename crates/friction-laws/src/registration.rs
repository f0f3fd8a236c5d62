//! Registration of the built-in laws and formulations in the `plugins-api`
//! registry, in one place with the function that keeps it linked.

use plugins_api::registry::{FormulationEntry, LawEntry};

use crate::formulations::{convective, jaumann, lagrangian, updated_lagrangian};
use crate::laws::{Ac, Levanov, Wh, Wvs};

inventory::submit! { LawEntry { description: Ac::DESCRIPTION, build: Ac::build } }
inventory::submit! { LawEntry { description: Wvs::DESCRIPTION, build: Wvs::build } }
inventory::submit! { LawEntry { description: Wh::DESCRIPTION, build: Wh::build } }
inventory::submit! { LawEntry { description: Levanov::DESCRIPTION, build: Levanov::build } }

inventory::submit! { FormulationEntry { name: convective::NAME, summary: convective::SUMMARY, build: convective::build } }
inventory::submit! { FormulationEntry { name: jaumann::NAME, summary: jaumann::SUMMARY, build: jaumann::build } }
inventory::submit! { FormulationEntry { name: lagrangian::NAME, summary: lagrangian::SUMMARY, build: lagrangian::build } }
inventory::submit! {
    FormulationEntry { name: updated_lagrangian::NAME, summary: updated_lagrangian::SUMMARY, build: updated_lagrangian::build }
}

/// Referenced by [`crate::ensure_linked`] so that this object file, and with it
/// the submissions above, is linked into every binary that uses the crate.
#[inline(never)]
pub(crate) fn keep() -> usize {
    std::hint::black_box(4)
}
