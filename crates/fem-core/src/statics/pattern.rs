//! `Pattern`: the tangent's sparsity pattern over the free equations
//! (compressed sparse columns, both triangles and the whole diagonal) and
//! each recorded entry's value slot, fixed at the first assembly.

use super::DofMap;
use super::assembly::NO_SLOT;
use faer::sparse::SymbolicSparseColMat;
use std::ops::Range;

/// The recorded entries and where their values go.
pub(crate) struct Pattern {
    /// Global (row, column) of every recorded entry, effects one after the other.
    pub keys: Vec<(u32, u32)>,
    /// Per effect: its range in `keys` and `slots`.
    pub segments: Vec<Range<usize>>,
    /// Per entry: its index in the matrix's values, or [`NO_SLOT`] when it
    /// couples a constrained or dropped DOF.
    pub slots: Vec<u32>,
    /// The matrix's structure: `n × n`, columns sorted, structurally symmetric.
    pub matrix: SymbolicSparseColMat<usize>,
    /// Per equation: the value index of its diagonal entry.
    pub diagonal: Vec<usize>,
    /// Per value index `(i, j)`: the value index of `(j, i)`.
    pub transpose: Vec<u32>,
}

impl Pattern {
    /// The pattern of `entries` (segment `segments[e]` from effect `e`)
    /// over the equations of `dofs`.
    pub fn new(entries: &[(u32, u32, f64)], segments: Vec<Range<usize>>, dofs: &DofMap) -> Self {
        let n = dofs.len();
        let eq = |g: u32| dofs.eq[g as usize];
        // (column, row) pairs of both triangles and the diagonal.
        let mut pairs: Vec<(u32, u32)> = Vec::with_capacity(2 * entries.len() + n);
        for &(r, c, _) in entries {
            let (i, j) = (eq(r), eq(c));
            if i != NO_SLOT && j != NO_SLOT {
                pairs.push((j, i));
                pairs.push((i, j));
            }
        }
        pairs.extend((0..n as u32).map(|i| (i, i)));
        pairs.sort_unstable();
        pairs.dedup();
        let mut col_ptr = vec![0usize; n + 1];
        for &(j, _) in &pairs {
            col_ptr[j as usize + 1] += 1;
        }
        for j in 0..n {
            col_ptr[j + 1] += col_ptr[j];
        }
        let row_idx: Vec<usize> = pairs.iter().map(|&(_, i)| i as usize).collect();
        let slot = |i: u32, j: u32| -> usize {
            let col = col_ptr[j as usize]..col_ptr[j as usize + 1];
            let at = row_idx[col.clone()].binary_search(&(i as usize));
            col.start + at.expect("every entry is in the pattern")
        };
        let slots = entries
            .iter()
            .map(|&(r, c, _)| match (eq(r), eq(c)) {
                (i, j) if i != NO_SLOT && j != NO_SLOT => slot(i, j) as u32,
                _ => NO_SLOT,
            })
            .collect();
        let diagonal = (0..n as u32).map(|i| slot(i, i)).collect();
        let transpose = (0..n)
            .flat_map(|j| (col_ptr[j]..col_ptr[j + 1]).map(move |p| (j, p)))
            .map(|(j, p)| slot(j as u32, row_idx[p] as u32) as u32)
            .collect();
        let keys = entries.iter().map(|&(r, c, _)| (r, c)).collect();
        let matrix = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        Self {
            keys,
            segments,
            slots,
            matrix,
            diagonal,
            transpose,
        }
    }

    /// Replace `values` by the symmetric part `½ (K + Kᵀ)` of the matrix
    /// they hold.
    pub fn symmetrize(&self, values: &mut [f64]) {
        for (p, &q) in self.transpose.iter().enumerate() {
            let q = q as usize;
            if q > p {
                let mean = 0.5 * (values[p] + values[q]);
                values[p] = mean;
                values[q] = mean;
            }
        }
    }

    /// Number of stored entries of the matrix.
    pub fn nnz(&self) -> usize {
        self.matrix.row_idx().len()
    }
}
