//! `DofMap`: which global DOFs (`6 · node + dof`) enter the system — the
//! free ones that some effect stiffens — and their equation numbers.

use super::assembly::NO_SLOT;
use crate::Dof;

/// The equation numbering of the free DOFs.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DofMap {
    /// Per global DOF: its equation, or [`NO_SLOT`] (constrained or dropped).
    pub eq: Vec<u32>,
    /// Per equation: its global DOF.
    pub global: Vec<u32>,
    /// Per global DOF: whether some effect's tangent has an entry in its row.
    pub stiffened: Vec<bool>,
    /// Per equation: whether it is a rotation.
    pub is_rotation: Vec<bool>,
}

impl DofMap {
    /// Number the DOFs that appear in `entries` (row or column) and are not
    /// constrained, in global order.
    pub fn new(n_dofs: usize, entries: &[(u32, u32, f64)], constrained: &[bool]) -> Self {
        let mut stiffened = vec![false; n_dofs];
        for &(r, c, _) in entries {
            stiffened[r as usize] = true;
            stiffened[c as usize] = true;
        }
        let mut eq = vec![NO_SLOT; n_dofs];
        let mut global = Vec::new();
        for g in 0..n_dofs {
            if stiffened[g] && !constrained[g] {
                eq[g] = global.len() as u32;
                global.push(g as u32);
            }
        }
        let is_rotation = global.iter().map(|&g| g % 6 >= 3).collect();
        Self {
            eq,
            global,
            stiffened,
            is_rotation,
        }
    }

    /// Number of equations.
    pub fn len(&self) -> usize {
        self.global.len()
    }

    /// (node, DOF) of equation `i`.
    pub fn node_dof(&self, i: usize) -> (usize, Dof) {
        let g = self.global[i] as usize;
        (g / 6, Dof::ALL[g % 6])
    }
}

/// `(‖v_translations‖, ‖v_rotations‖)` over the equations.
pub(crate) fn split_norms(v: &[f64], is_rotation: &[bool]) -> (f64, f64) {
    let (mut t, mut r) = (0.0, 0.0);
    for (x, &rot) in v.iter().zip(is_rotation) {
        if rot {
            r += x * x;
        } else {
            t += x * x;
        }
    }
    (t.sqrt(), r.sqrt())
}
