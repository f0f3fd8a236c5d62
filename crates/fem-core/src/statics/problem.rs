//! `StaticProblem`: the model a static solve works on — start positions,
//! effects, fixed and prescribed DOFs, nodal loads.

use super::StaticTangent;
use crate::{Dof, Dofs, FemError, Vec3};

/// The model of a static solve: nodes at their start positions, the
/// effects that stiffen them, constraints and loads.
///
/// At load factor `λ` the solve seeks `F_int(u) = λ F_ext` on the free
/// DOFs, with every prescribed DOF at `λ ū` from its start value (a fixed
/// DOF is a prescribed one with `ū = 0`). Loads are dead loads (fixed
/// global direction). A load on a constrained DOF goes to its reaction.
///
/// A stress release ([`StaticProblem::release_start_forces`]) starts out of
/// balance: the internal forces at the start state were held by something
/// now gone (the tools of a springback), and the solve seeks
/// `F_int(u) = (1 − λ) F_int(x_start) + λ F_ext`, so that `λ = 0` is the
/// start state itself and the held forces are let go increment by
/// increment.
pub struct StaticProblem {
    pub(super) x_start: Vec<Vec3>,
    pub(super) effects: Vec<Box<dyn StaticTangent>>,
    /// Per global DOF `6 · node + dof`: the prescribed value `ū` (mm or rad).
    pub(super) prescribed: Vec<Option<f64>>,
    /// Per global DOF: the external load at `λ = 1` (N or N·mm).
    pub(super) loads: Vec<f64>,
    /// Whether the start state's internal forces are let go over the
    /// increments (a stress release).
    pub(super) release: bool,
}

impl StaticProblem {
    /// A problem over nodes at `x_start` (mm), with no effect, constraint or load.
    ///
    /// # Errors
    /// No node, or a coordinate that is not finite.
    pub fn new(x_start: &[Vec3]) -> Result<Self, FemError> {
        if x_start.is_empty() {
            return Err(FemError::InvalidSetup(
                "a static problem needs at least one node".to_string(),
            ));
        }
        for (node, p) in x_start.iter().enumerate() {
            for (axis, &value) in ["x", "y", "z"].into_iter().zip(p.iter()) {
                if !value.is_finite() {
                    return Err(FemError::NonFiniteCoordinate { node, axis, value });
                }
            }
        }
        let n = 6 * x_start.len();
        Ok(Self {
            x_start: x_start.to_vec(),
            effects: Vec::new(),
            prescribed: vec![None; n],
            loads: vec![0.0; n],
            release: false,
        })
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.x_start.len()
    }

    /// Add an effect; returns its index (for [`super::StaticSolver::effect`]).
    pub fn add_effect<E: StaticTangent>(&mut self, effect: E) -> usize {
        self.add_boxed_effect(Box::new(effect))
    }

    /// Add a boxed effect; returns its index.
    pub fn add_boxed_effect(&mut self, effect: Box<dyn StaticTangent>) -> usize {
        self.effects.push(effect);
        self.effects.len() - 1
    }

    /// Make the solve a stress release: the internal forces of the start
    /// state are in balance at `λ = 0` and let go by `λ = 1` (see the type's
    /// documentation). A springback from a formed state is one.
    pub fn release_start_forces(&mut self) {
        self.release = true;
    }

    /// Fix `dofs` of every node in `nodes` (zero displacement from the start).
    ///
    /// # Errors
    /// A node out of range, or a DOF already prescribed to a nonzero value.
    pub fn fix(&mut self, nodes: &[u32], dofs: Dofs) -> Result<(), FemError> {
        for dof in Dof::ALL.into_iter().filter(|d| dofs.contains(*d)) {
            for &node in nodes {
                self.constrain(node, dof, 0.0)?;
            }
        }
        Ok(())
    }

    /// Prescribe the displacement (mm) or rotation (rad) `value` at `λ = 1`
    /// of `dof` of every node in `nodes`, reached as `λ · value`. A
    /// prescribed rotation is applied increment by increment as the
    /// rotation vector `Δλ · value` about the global axis.
    ///
    /// # Errors
    /// A node out of range, a value not finite, or a DOF already
    /// constrained to another value.
    pub fn prescribe(&mut self, nodes: &[u32], dof: Dof, value: f64) -> Result<(), FemError> {
        if !value.is_finite() {
            return Err(FemError::InvalidParameter {
                field: format!("prescribed {}", dof.name()),
                value,
                unit: if dof.is_rotation() { "rad" } else { "mm" },
                range: "finite",
            });
        }
        nodes
            .iter()
            .try_for_each(|&node| self.constrain(node, dof, value))
    }

    /// Add the load `value` at `λ = 1` (N on a translation, N·mm on a
    /// rotation) on `dof` of every node in `nodes`.
    ///
    /// # Errors
    /// A node out of range or a value not finite.
    pub fn add_load(&mut self, nodes: &[u32], dof: Dof, value: f64) -> Result<(), FemError> {
        if !value.is_finite() {
            return Err(FemError::InvalidParameter {
                field: format!("load {}", dof.name()),
                value,
                unit: if dof.is_rotation() { "N·mm" } else { "N" },
                range: "finite",
            });
        }
        for &node in nodes {
            let g = self.global(node, dof, "load")?;
            self.loads[g] += value;
        }
        Ok(())
    }

    fn constrain(&mut self, node: u32, dof: Dof, value: f64) -> Result<(), FemError> {
        let g = self.global(node, dof, "constraint")?;
        match self.prescribed[g] {
            Some(old) if old != value => Err(FemError::InvalidSetup(format!(
                "node {node}: {} is constrained twice, to {old} and to {value} {}",
                dof.name(),
                if dof.is_rotation() { "rad" } else { "mm" }
            ))),
            _ => {
                self.prescribed[g] = Some(value);
                Ok(())
            }
        }
    }

    fn global(&self, node: u32, dof: Dof, what: &str) -> Result<usize, FemError> {
        if node as usize >= self.n_nodes() {
            return Err(FemError::InvalidSetup(format!(
                "{what} on {}: node {node} is out of range (the problem has {} nodes)",
                dof.name(),
                self.n_nodes()
            )));
        }
        Ok(6 * node as usize + dof.index())
    }
}
