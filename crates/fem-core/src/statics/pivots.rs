//! Reading the pivots of a sparse Cholesky factor (`L_jj²` of `LLᵀ`, `D_jj`
//! of `LDLᵀ`) and testing them for a singular tangent.

use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};

/// Write into `out[j]` the diagonal entry of column `j` of the factor whose
/// values are `l` (columns in the factorisation's permuted order). Both
/// `LLᵀ` and `LDLᵀ` factors keep it on the factor's diagonal (`L_jj`,
/// resp. `D_jj`).
pub(crate) fn factor_diagonal(symbolic: &SymbolicCholesky<usize>, l: &[f64], out: &mut [f64]) {
    match symbolic.raw() {
        SymbolicCholeskyRaw::Simplicial(s) => {
            let factor = s.factor();
            let (col_ptr, row_idx) = (factor.col_ptr(), factor.row_idx());
            for (j, d) in out.iter_mut().enumerate() {
                *d = (col_ptr[j]..col_ptr[j + 1])
                    .find(|&p| row_idx[p] == j)
                    .map_or(0.0, |p| l[p]);
            }
        }
        SymbolicCholeskyRaw::Supernodal(s) => {
            let factor = SupernodalLltRef::new(s, l);
            for k in 0..s.n_supernodes() {
                let node = factor.supernode(k);
                let block = node.val();
                for j in 0..block.ncols() {
                    out[node.start() + j] = block[(j, j)];
                }
            }
        }
    }
}

/// The equation whose pivot is smallest against its diagonal, when that
/// ratio is at or below `tolerance`: a singular tangent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SingularPivot {
    /// The equation (original numbering).
    pub equation: usize,
    /// Its pivot (N/mm or N·mm/rad).
    pub pivot: f64,
    /// Its diagonal entry of the tangent.
    pub diagonal: f64,
}

/// Test the pivots `pivots[j]` (permuted order; `fwd[j]` the original
/// equation, identity when `None`) against the tangent's diagonal `diag`
/// (original order). Returns the number of negative pivots, or the most
/// singular equation when a pivot `|p_j| <= tolerance · |K_jj|` (a zero
/// diagonal is measured against round-off of the largest one).
pub(crate) fn test_pivots(
    pivots: &[f64],
    fwd: Option<&[usize]>,
    diag: impl Fn(usize) -> f64,
    tolerance: f64,
) -> Result<usize, SingularPivot> {
    let orig = |j: usize| fwd.map_or(j, |f| f[j]);
    let max_diag = (0..pivots.len()).map(|i| diag(i).abs()).fold(0.0, f64::max);
    let floor = max_diag * f64::EPSILON;
    let mut worst: Option<(f64, SingularPivot)> = None;
    let mut negative = 0;
    for (j, &p) in pivots.iter().enumerate() {
        let i = orig(j);
        let d = diag(i);
        // A NaN pivot counts as zero.
        let ratio = match p.abs() / d.abs().max(floor).max(f64::MIN_POSITIVE) {
            r if r.is_nan() => 0.0,
            r => r,
        };
        negative += usize::from(p < 0.0);
        if ratio <= tolerance && worst.is_none_or(|(r, _)| ratio < r) {
            let at = SingularPivot {
                equation: i,
                pivot: if p.is_finite() { p } else { 0.0 },
                diagonal: d,
            };
            worst = Some((ratio, at));
        }
    }
    worst.map_or(Ok(negative), |(_, at)| Err(at))
}
