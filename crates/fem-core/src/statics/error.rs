//! Errors of the static solver; every message is one line naming the node,
//! DOF, field or load factor.

use crate::{Dof, FemError};
use thiserror::Error;

/// Everything that can stop a static solve.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum StaticsError {
    /// Bad input, or an effect's hard error at set-up.
    #[error(transparent)]
    Setup(#[from] FemError),
    /// The tangent is singular: a free rigid-body mode or a DOF nothing holds.
    #[error(
        "singular tangent at λ = {lambda}: node {node} {} is free (pivot {pivot:.3e} against \
         its diagonal {diagonal:.3e}); a rigid-body mode or an unsupported DOF: fix it or stiffen it",
        .dof.name()
    )]
    Singular {
        /// Load factor of the state whose tangent is singular.
        lambda: f64,
        /// The node of the free DOF.
        node: usize,
        /// The free DOF.
        dof: Dof,
        /// Its pivot in the factorisation (N/mm or N·mm/rad; 0 when unknown).
        pivot: f64,
        /// Its diagonal entry of the tangent.
        diagonal: f64,
    },
    /// A load on DOFs that no effect stiffens: nothing can carry it.
    #[error(
        "node {node} {} carries a load of {value} but no effect stiffens it ({count} such DOFs): \
         fix it or add an effect that holds it",
        .dof.name()
    )]
    UnheldLoad {
        /// The first such node.
        node: usize,
        /// Its DOF.
        dof: Dof,
        /// The load at `λ = 1` (N or N·mm).
        value: f64,
        /// How many loaded DOFs no effect stiffens.
        count: usize,
    },
    /// An effect broke the assembly contract (a node out of range, a
    /// tangent pattern that changed).
    #[error("`{effect}`: {message}")]
    Assembly {
        /// The effect.
        effect: String,
        /// What it did.
        message: String,
    },
    /// The sparse factorisation failed for a reason of its own (out of memory).
    #[error("sparse factorisation failed: {0}")]
    Factorisation(String),
    /// The last cut-back failed too: the state stays at `lambda_converged`.
    #[error(
        "no convergence toward λ = {lambda_target} (Δλ = {increment:.3e}): {reason}; stopped \
         after {cutbacks} cut-backs ({stop}); the state stays at λ = {lambda_converged}; \
         |R| of the last attempt: {}",
        residual_list(.residuals)
    )]
    NotConverged {
        /// Load factor of the last converged increment, where the state stays.
        lambda_converged: f64,
        /// Load factor of the last attempt.
        lambda_target: f64,
        /// Its load increment.
        increment: f64,
        /// Cut-backs made in this solve.
        cutbacks: usize,
        /// Why the last attempt failed.
        reason: String,
        /// Why it was the last: too many cut-backs in a row, or the
        /// increment would fall below `min_increment`.
        stop: String,
        /// Residual norms `‖R‖₂` of the last attempt, one per iteration.
        residuals: Vec<f64>,
    },
}

fn residual_list(r: &[f64]) -> String {
    let list: Vec<String> = r.iter().map(|x| format!("{x:.3e}")).collect();
    format!("[{}]", list.join(", "))
}
