//! The static Newton solver: equilibrium `F_int(u) = λ F_ext` by load
//! increments, the first brick of springback.
//!
//! # The problem
//!
//! A [`StaticProblem`] holds nodes at their start positions, effects that
//! implement [`StaticTangent`], fixed and prescribed DOFs and dead loads.
//! With 6 DOFs per node (translations `ux uy uz`, rotations `rx ry rz`),
//! [`StaticSolver`] seeks, for `λ` from 0 to 1,
//!
//! `R(u) = F_int(u) − λ F_ext = 0` on the free DOFs, every prescribed DOF at `λ ū`;
//! a stress release ([`StaticProblem::release_start_forces`], springback)
//! seeks `F_int(u) = (1 − λ) F_int(x_start) + λ F_ext` instead: at `λ = 0`
//! the start state, whose forces the tools held, at `λ = 1` the state
//! without them.
//!
//! Translations are total displacements; rotations are incremental rotation
//! vectors from the last converged increment, composed into the nodal
//! rotations at every commit (see [`TrialState`]).
//!
//! # The assembly interface
//!
//! An effect gives its internal forces and consistent tangent at a trial
//! state through an [`Assembly`], keyed by (node, DOF). The tangent's
//! pattern is recorded at set-up and must not change; the DOFs that no
//! effect stiffens are dropped from the system (a load on one is refused:
//! [`StaticsError::UnheldLoad`]). Path-dependent effects keep trial and
//! committed state apart: [`StaticTangent::commit`] on convergence,
//! [`StaticTangent::revert`] on a cut-back. [`Springs`](crate::Springs)
//! implement it with the exact tangent of the geometrically nonlinear
//! axial spring; [`dense_tangent`] evaluates any effect densely, to check
//! its tangent against finite differences.
//!
//! # The algorithm
//!
//! - **Increments**: `Δλ` starts at [`NewtonSettings::initial_increment`],
//!   grows by `growth_factor` after an increment that took at most
//!   `easy_iterations`, is halved when an attempt fails (too many
//!   iterations, a growing or non-finite residual, an effect refusing every
//!   trial state) and the solve stops with [`StaticsError::NotConverged`],
//!   carrying the last attempt's residual history, after `max_cutbacks`
//!   halvings in a row or below `min_increment`. The state then stays at
//!   the last converged increment.
//! - **Newton iterations**: constrained DOFs are set to their values at the
//!   start of the increment and eliminated (the system holds the free DOFs
//!   only); each iteration solves `K δu = −R` with the consistent tangent,
//!   then a backtracking line search (Armijo on `½‖R‖²`, quadratic
//!   interpolation) picks the step. Convergence needs the force, the
//!   displacement and the energy criteria together ([`NewtonSettings`]
//!   gives them with their defaults).
//! - **Linear algebra** (`faer`): the symbolic factorisation (AMD ordering,
//!   elimination tree, supernodes) is made once, at set-up, and reused by
//!   every iteration of every increment (LU's own analysis, the first time
//!   LU is needed); `LLᵀ` is tried first, `LDLᵀ` on
//!   the same analysis when the tangent is not positive definite (past a
//!   limit point), LU when an effect's tangent is unsymmetric or `LDLᵀ`
//!   solves inaccurately. Two settings trade the quadratic convergence of
//!   the exact tangent for cheaper iterations, with the same convergence
//!   criteria and so the same solution: `symmetrize` factorises the
//!   symmetric part of an unsymmetric tangent by Cholesky in place of LU
//!   (where it fails an increment after every cut-back allowed, the
//!   solve goes on with the exact tangent),
//!   and `reuse_contraction` keeps a factor (modified Newton) while the
//!   iterations it serves contract `‖R‖` enough. A pivot at round-off of
//!   its diagonal names the free DOF: a singular first tangent (a free
//!   rigid-body mode) stops the solve at once with
//!   [`StaticsError::Singular`].
//!   [`StaticSolver::tangent_matrix`] gives the assembled tangent as a
//!   `faer` matrix, to measure factorisations on it
//!   (`crates/shell-elements/benches/static_factor.rs`).
//! - **Cost**: the Newton loop reuses its buffers (residual, correction,
//!   tangent values, factor values, the factorisation's scratch); only
//!   the residual history of a converged increment is copied into its
//!   report. [`SolveReport`] splits the time into assembly, symbolic and
//!   numeric factorisation and solves, and gives the factor's size.
//!
//! # Example
//!
//! ```
//! use fem_core::statics::{NewtonSettings, StaticProblem, StaticSolver};
//! use fem_core::{Dof, Dofs, Spring, Springs, Vec3};
//!
//! // A spring (100 N/mm, free length 10 mm) along x: node 0 clamped,
//! // node 1 guided along x and pulled with 50 N.
//! let nodes = [Vec3::zeros(), Vec3::new(10.0, 0.0, 0.0)];
//! let spring = Spring { a: 0, b: 1, k: 100.0, length0: 10.0 };
//! let mut problem = StaticProblem::new(&nodes)?;
//! problem.add_effect(Springs::new("spring", 2, vec![spring])?);
//! problem.fix(&[0], Dofs::ALL)?;
//! problem.fix(&[1], Dofs::of(&[Dof::Uy, Dof::Uz]))?;
//! problem.add_load(&[1], Dof::Ux, 50.0)?;
//! let mut solver = StaticSolver::new(problem, NewtonSettings::default())?;
//! let report = solver.solve()?;
//! assert!((solver.displacement(1).x - 0.5).abs() < 1e-9);
//! assert!((solver.reaction(0, Dof::Ux) + 50.0).abs() < 1e-6);
//! println!("{report}");
//! # Ok::<(), fem_core::statics::StaticsError>(())
//! ```

mod assembly;
mod dense;
mod dof_map;
mod error;
mod evaluate;
mod factor;
mod matrix;
mod newton;
mod pattern;
mod pivots;
mod problem;
mod report;
mod settings;
mod solver;
mod springs;
mod stepping;
mod tangent;

pub use assembly::{Assembly, DofGroup};
pub use dense::{DenseTangent, dense_tangent};
pub use error::StaticsError;
pub use problem::StaticProblem;
pub use report::{IncrementReport, SolveReport, StaticTiming, SystemStats};
pub use settings::NewtonSettings;
pub use solver::StaticSolver;
pub use tangent::{StaticTangent, TrialState};

pub(crate) use dof_map::DofMap;
pub(crate) use pattern::Pattern;
