//! `Assembly`: where an effect adds its internal forces and tangent entries,
//! keyed by (node, DOF) with 6 DOFs per node (global index `6 · node + dof`).

use crate::{Dof, Mat3, Vec3};

/// No value slot: the entry couples a constrained or dropped DOF.
pub(crate) const NO_SLOT: u32 = u32::MAX;

/// The three DOFs of a node that a 3-vector or a 3×3 block addresses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DofGroup {
    /// `ux`, `uy`, `uz` (force in N, stiffness in N/mm).
    Translation,
    /// `rx`, `ry`, `rz` (moment in N·mm, stiffness in N·mm/rad).
    Rotation,
}

impl DofGroup {
    fn offset(self) -> usize {
        match self {
            DofGroup::Translation => 0,
            DofGroup::Rotation => 3,
        }
    }
}

/// Where the tangent entries go.
pub(crate) enum Sink<'a> {
    /// Forces only.
    Off,
    /// First assembly: record every entry (row, column, value).
    Record(&'a mut Vec<(u32, u32, f64)>),
    /// Later assemblies: check each entry against the recorded pattern and
    /// add it to its value slot (or drop it).
    Scatter {
        keys: &'a [(u32, u32)],
        slots: &'a [u32],
        values: &'a mut [f64],
        next: usize,
    },
    /// A dense row-major matrix of `6 n × 6 n` (for verifying tangents).
    Dense(&'a mut [f64]),
}

/// The accumulator an effect adds its internal forces and tangent to.
///
/// Every tangent entry given at set-up, zero or not, puts its row's and
/// column's DOFs in the system (a zero geometric stiffness at the start
/// may grow later); a DOF that no entry names is dropped. So give only the
/// entries the effect can ever make nonzero.
///
/// Out-of-range nodes and a tangent whose entries differ from those of the
/// first assembly are recorded (the first one) and reported by the solver
/// as an error naming the effect; the offending entry is skipped.
pub struct Assembly<'a> {
    n_dofs: usize,
    f: &'a mut [f64],
    sink: Sink<'a>,
    fault: Option<String>,
}

impl<'a> Assembly<'a> {
    /// An assembly over `f.len() / 6` nodes.
    pub(crate) fn new(f: &'a mut [f64], sink: Sink<'a>) -> Self {
        Self {
            n_dofs: f.len(),
            f,
            sink,
            fault: None,
        }
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.n_dofs / 6
    }

    /// Whether the solver wants the tangent in this call (else forces only).
    pub fn wants_tangent(&self) -> bool {
        !matches!(self.sink, Sink::Off)
    }

    /// Add `value` (N or N·mm) to the internal force of `dof` at `node`.
    pub fn add_force(&mut self, node: u32, dof: Dof, value: f64) {
        if let Some(g) = self.index(node, dof.index()) {
            self.f[g] += value;
        }
    }

    /// Add a force (N) or moment (N·mm) vector at `node`.
    pub fn add_force3(&mut self, node: u32, group: DofGroup, value: &Vec3) {
        if let Some(g) = self.index(node, group.offset()) {
            for (f, v) in self.f[g..g + 3].iter_mut().zip(value.iter()) {
                *f += v;
            }
        }
    }

    /// Add `value` to the tangent entry `∂F_int(row) / ∂u(col)`.
    pub fn add_stiffness(&mut self, row: (u32, Dof), col: (u32, Dof), value: f64) {
        let (Some(r), Some(c)) = (
            self.index(row.0, row.1.index()),
            self.index(col.0, col.1.index()),
        ) else {
            return;
        };
        self.push(r, c, value);
    }

    /// Add a 3×3 block to the tangent: rows the `row` group of `row.0`,
    /// columns the `col` group of `col.0` (entries in row-major order).
    pub fn add_block3(&mut self, row: (u32, DofGroup), col: (u32, DofGroup), block: &Mat3) {
        let (Some(r), Some(c)) = (
            self.index(row.0, row.1.offset()),
            self.index(col.0, col.1.offset()),
        ) else {
            return;
        };
        for i in 0..3 {
            for j in 0..3 {
                self.push(r + i, c + j, block[(i, j)]);
            }
        }
    }

    /// The first fault, and for a scatter whether the effect gave as many
    /// entries as at the first assembly.
    pub(crate) fn finish(mut self) -> Result<(), String> {
        if let Sink::Scatter { keys, next, .. } = &self.sink
            && self.fault.is_none()
            && *next != keys.len()
        {
            self.fault = Some(format!(
                "the tangent has {next} entries, {} at the first assembly (the pattern must not change)",
                keys.len()
            ));
        }
        self.fault.map_or(Ok(()), Err)
    }

    fn index(&mut self, node: u32, dof: usize) -> Option<usize> {
        let g = 6 * node as usize + dof;
        if g < self.n_dofs {
            return Some(g);
        }
        if self.fault.is_none() {
            self.fault = Some(format!(
                "node {node} is out of range (the model has {} nodes)",
                self.n_dofs / 6
            ));
        }
        None
    }

    fn push(&mut self, r: usize, c: usize, value: f64) {
        match &mut self.sink {
            Sink::Off => {}
            Sink::Record(entries) => entries.push((r as u32, c as u32, value)),
            Sink::Dense(k) => k[r * self.n_dofs + c] += value,
            Sink::Scatter {
                keys,
                slots,
                values,
                next,
            } => {
                let key = (r as u32, c as u32);
                match keys.get(*next) {
                    Some(&k) if k == key => {
                        let slot = slots[*next];
                        if slot != NO_SLOT {
                            values[slot as usize] += value;
                        }
                    }
                    expected => {
                        if self.fault.is_none() {
                            self.fault = Some(pattern_fault(*next, key, expected.copied()));
                        }
                    }
                }
                *next += 1;
            }
        }
    }
}

fn pattern_fault(at: usize, got: (u32, u32), expected: Option<(u32, u32)>) -> String {
    let name = |(r, c): (u32, u32)| {
        format!(
            "(node {} {}, node {} {})",
            r / 6,
            Dof::ALL[r as usize % 6].name(),
            c / 6,
            Dof::ALL[c as usize % 6].name()
        )
    };
    match expected {
        Some(e) => format!(
            "tangent entry {at} is {} but was {} at the first assembly (the pattern must not change)",
            name(got),
            name(e)
        ),
        None => format!(
            "tangent entry {at} {} is beyond the {at} entries of the first assembly (the pattern must not change)",
            name(got)
        ),
    }
}
