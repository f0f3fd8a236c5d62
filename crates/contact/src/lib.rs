//! # contact: blank nodes against rigid tools, with friction
//!
//! Place in the pipeline: stage 5 of an explicit step (docs/architecture.md §3). For every
//! contact pair (a rigid [`ToolSurface`](plugins_api::ToolSurface) against the
//! blank), this crate projects the blank nodes on the tool (warm-started from the
//! previous step), measures the gap of the blank face on the tool's side (the
//! mid-surface node offset by half the current thickness, docs/friction-math.md §1),
//! turns penetration into a penalty pressure ([`penalty`]), the relative motion
//! of blank and tool into a slip increment, and hands both to the pair's friction
//! model through [`PointIntegrator`](plugins_api::PointIntegrator) (any law ×
//! any formulation, built-in or plugin). It adds the nodal forces, sums the
//! reactions on each tool and keeps the pair's energies (frictional dissipation,
//! stored penalty energy, the work the tools do).
//!
//! A pair's step is a pipeline of five stages, each in its own module under
//! `stages/` (broad phase, narrow phase, normal, friction, scatter; the
//! module's documentation says what each reads and writes).
//!
//! It owns the per-point contact state, laid out per pair as arrays over the
//! pair's nodes, and the nodal geometry that the formulations read
//! ([`BlankGeometry`]: areas, normals, velocity and deformation gradients),
//! computed only when an active law or formulation declares it (docs/friction-math.md §6).
//!
//! It must not know about tool geometry (only the `ToolSurface` trait), about
//! particular friction laws (only the plugins-api traits), about the shell
//! elements (it reads the nodal thickness and flow stress as `fem-core` shared
//! fields, [`fem_core::NodalField`], written by whichever effect owns the
//! shells) or about scenes.
//!
//! Drawbeads ([`Drawbead`], docs/drawbeads.md) ride on the effect: each is a
//! line force fixed to a tool, acting where the blank touches that tool.

mod blank;
mod drawbead;
mod effect;
mod error;
mod friction_record;
mod pair;
pub mod penalty;
mod stages;
mod timing;
mod tool_log;

pub use blank::{BlankGeometry, BlankView};
pub use drawbead::{BeadEnergy, Drawbead, DrawbeadSpec};
pub use effect::ContactEffect;
pub use error::ContactError;
pub use friction_record::{FrictionRecord, RECORD_NEEDS};
pub use pair::{ContactEnergy, ContactPair, FRICTIONLESS, PairSpec, PointStatus, Reaction};
pub use penalty::PenaltySettings;
pub use timing::ContactTiming;
pub use tool_log::{Sampled, ToolStepLog};
