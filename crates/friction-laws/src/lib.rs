//! # friction-laws: formsim's built-in friction laws and kinematic formulations
//!
//! Place in the pipeline: stage 5 of an explicit step (contact) calls a
//! [`plugins_api::PointIntegrator`] per batch of contact points; this crate
//! supplies the built-in ones. It owns the four isotropic laws of
//! docs/friction-math.md §3 ([`laws`]: `ac`, `wvs`, `wh`, `levanov`), the four
//! kinematic formulations of §4 ([`formulations`]: `convective`, `jaumann`,
//! `lagrangian`, `updated-lagrangian`), their registration in the
//! `plugins-api` registry, and [`builtin`]: monomorphised pairings of any
//! built-in law with any formulation (enum dispatch, no virtual call per point).
//!
//! It must not know about meshes, tools or scenes; the return mapping it relies
//! on is the shared one in `plugins_api::return_mapping`.

pub mod builtin;
pub mod formulations;
pub mod laws;
mod registration;

/// Keep this crate's registrations alive: the linker drops the `inventory`
/// submissions of a crate nothing references. Call once before using the
/// registry (formsim's CLI does).
pub fn ensure_linked() {
    std::hint::black_box(registration::keep());
}
