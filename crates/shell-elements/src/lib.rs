//! # shell-elements: Belytschko–Tsay family shells and plane-stress J2 plasticity
//!
//! Place in the pipeline: stage 4 of an explicit step (docs/architecture.md §3) — from the
//! nodal velocities to stresses (plane-stress J2 with Swift or tabulated
//! hardening at each through-thickness point), then to nodal forces and
//! moments, hourglass forces, the stable time step and the element energies.
//! It owns the element formulations ([`BelytschkoTsay`], [`FullyIntegrated`]),
//! the [`Material`] trait and [`J2PlaneStress`], through-thickness rules and
//! sections ([`Section`]), per-element outputs ([`ShellElementOutput`]) and
//! [`ShellSet`], which plugs a set of shells into `fem-core`'s solver as an
//! [`Effect`](fem_core::Effect), and the registry of materials and elements
//! by name ([`kinds`]).
//!
//! It must not know about tools, contact, friction or scenes; it sees the
//! engine only through `fem-core`'s `Effect`, `NodalState` and `Forces`.
//! Formulations, equations and verification: `docs/shells.md`.

// Kernels index several fixed-size arrays with one node index.
#![allow(clippy::needless_range_loop)]

pub mod belytschko_tsay;
pub mod bending;
pub mod block_nodes;
pub mod error;
pub mod formulation;
pub mod fully_integrated;
mod geometry;
pub mod kinds;
pub mod lanes;
pub mod material;
pub mod outputs;
pub mod section;
pub mod shell_set;
pub mod statics;
mod view;
#[cfg(test)]
mod warped_tests;

pub use belytschko_tsay::BelytschkoTsay;
pub use block_nodes::BlockNodes;
pub use error::ShellError;
pub use formulation::{ElementBlock, ElementResult, ElementState, ShellFormulation};
pub use fully_integrated::FullyIntegrated;
pub use geometry::{V3, corotational_basis};
pub use lanes::{F4, M4, Real};
pub use material::{
    Hardening, J2History, J2PlaneStress, Material, PluginMaterial, PointUpdate, TANGENT_FD_STEP,
    finite_difference_tangent, plane_stress_elasticity, von_mises,
};
pub use outputs::{LogStrain, ShellElementOutput};
pub use section::{RuleKind, Section, ThroughThickness};
pub use shell_set::ShellSet;
pub use statics::StaticShells;
pub use view::ShellView;
