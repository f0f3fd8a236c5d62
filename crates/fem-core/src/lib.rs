//! # fem-core: formsim's explicit engine and static solver
//!
//! Place in the pipeline: it runs the explicit step (docs/architecture.md §3)
//! and owns its stages 1–3 and 6 — integration of the nodal state with its
//! boundary conditions, the energy ledger, the press that moves the rigid
//! tools, the stable time step with mass scaling (conventional, or
//! selective: [`selective_mass`]) — and calls the effects for
//! stages 4–5 (element and contact forces); plus the quad-shell [`Mesh`]
//! the blank is built from. It owns the nodal state
//! ([`NodalState`]), the force accumulators ([`Forces`]), the [`Effect`]
//! trait through which element families, contact and anything else add
//! nodal forces, masses, time-step limits and energies, the nodal fields
//! that effects share within a step ([`NodalField`], [`SharedFields`]: the
//! blank's thickness that the shells write and contact reads, say), and the
//! [`Solver`] that drives them, running every field's writer before its
//! readers.
//!
//! It also owns the static solver ([`statics`]), the first brick of
//! springback: a Newton solver of `F_int(u) = λ F_ext` by load increments,
//! with cut-back, line search and sparse `LLᵀ`/`LDLᵀ`/LU factorisations
//! (`faer`), over the effects that implement [`statics::StaticTangent`]
//! (their internal forces and consistent tangent at a trial state, with
//! commit and revert for path-dependent ones). [`Springs`] implement it;
//! shell tangents and the springback step belong to the crates that own
//! shells and the press stage.
//!
//! It must not know about shells, materials, tools, contact or friction:
//! those are effects defined in `shell-elements`, `contact` and friends. The
//! only effects defined here are [`Springs`] (axial springs with point
//! masses), used to verify the engine and for lumped-parameter models, and
//! [`AnchorSprings`] (a node set dragged through a spring, a scene's
//! `[[springs]]`). The press scheduler ([`Press`]) moves the rigid tools:
//! travel, velocity, spin and force control.
//! For springback, [`rigid_modes`] finds the rigid-body modes the blank's
//! constraints leave free, picks a 3-2-1 set of DOFs that removes them and
//! subtracts their best fit from a displacement field.
//!
//! Data layout and cost: the nodal state is a structure of arrays
//! ([`NodalState`]); one step makes one fused pass over the nodes (velocity
//! update, constraints of the node-sorted constraint list, positions, energy
//! sums), one pass to zero the accumulators and one to check them for
//! non-finite values, plus one virtual call per effect. No allocation per
//! step. The engine's own work is about 20–35 ns per node per step on this
//! machine (`cargo run --release -p fem-core --example engine_overhead`),
//! small beside the element work, so the nodal loops are serial: rayon would
//! not pay below ~10⁵ nodes. Effects may assemble in parallel (e.g.
//! per-element force buffers scattered into [`Forces`]).
//!
//! ```
//! use fem_core::{Amplitude, Control, Dof, Dofs, MotionKind, Solver, SolverSettings, Spring, Springs, Vec3};
//! use std::collections::BTreeMap;
//!
//! // Two nodes, one spring (100 N/mm), 1 kg on node 1, node 0 clamped, node 1 pulled 1 mm.
//! let nodes = [Vec3::zeros(), Vec3::new(10.0, 0.0, 0.0)];
//! let sets = BTreeMap::from([("base".to_string(), vec![0]), ("tip".to_string(), vec![1])]);
//! let mut solver = Solver::from_nodes(&nodes, sets, SolverSettings::default())?;
//! let spring = Spring { a: 0, b: 1, k: 100.0, length0: 10.0 };
//! solver.add_effect(Springs::new("spring", 2, vec![spring])?);
//! solver.add_point_mass("tip", 1e-3, 0.0)?;
//! solver.fix("base", Dofs::ALL)?;
//! solver.prescribe("tip", Dof::Ux, MotionKind::Displacement, 1.0,
//!                  Amplitude::SmoothStep { t0: 0.0, t1: 0.1 })?;
//! solver.run_until(0.1, &mut |_, report| {
//!     assert!(report.energy.balance_error < 1e-6);
//!     Control::Continue
//! })?;
//! assert!((solver.state().displacement(1).x - 1.0).abs() < 1e-12);
//! # Ok::<(), fem_core::FemError>(())
//! ```

pub mod amplitude;
pub mod anchor_springs;
pub mod boundary;
pub mod effect;
pub mod energy;
pub mod error;
pub mod fields;
pub mod mesh;
pub mod mesh_io;
pub mod nodal_limit;
pub mod press;
pub mod relaxation;
pub mod resume;
pub mod rigid_modes;
pub mod selective_mass;
pub mod settings;
pub mod solver;
pub mod springs;
pub mod state;
pub mod statics;

pub use amplitude::Amplitude;
pub use anchor_springs::AnchorSprings;
pub use boundary::{BoundaryCondition, Dof, Dofs, MotionKind, NodalLoad};
pub use effect::{Effect, EnergyTally, StableDt, StaticForm};
pub use energy::{EnergyLedger, History, HistoryRow};
pub use error::FemError;
pub use fields::{FieldAccess, NodalField, SharedFields};
pub use mesh::{Mesh, MeshQuality, rectangle, wrapped_strip, wrapped_strip_segments};
pub use mesh_io::{MeshFile, read_inp, read_inp_numbered, read_msh, read_msh_numbered};
pub use press::{
    ForceLaw, Press, PressStep, ReleaseMethod, StepChange, StepEnd, ToolLoad, ToolMotion,
};
pub use relaxation::SpringbackReport;
pub use resume::{SolverResume, StateArrays, ToolResume};
pub use selective_mass::{MassBlocks, SelectiveStats};
pub use settings::{MassScaling, SolverSettings};
pub use solver::{
    Control, DtLimit, EffectId, RunSummary, SetupReport, Solver, StepReport, StepTiming,
};
pub use springs::{Spring, Springs};
pub use state::{Forces, NodalState, StepContext};

/// A 3-vector in the global frame (mm, N, mm/s, … as the quantity requires).
pub type Vec3 = plugins_api::Vec3;

/// A 3×3 matrix in the global frame (a stiffness block in N/mm, a rotation, …).
pub type Mat3 = plugins_api::Mat3;
