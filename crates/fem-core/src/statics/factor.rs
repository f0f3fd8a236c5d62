//! `Factorizer`: the sparse factorisations of the tangent on `faer`'s
//! low-level API — one symbolic analysis (fill-reducing ordering,
//! elimination tree) for the whole solve, numeric factors into reused
//! buffers, `LLᵀ` first, `LDLᵀ` when the tangent is not positive definite,
//! LU when it is not symmetric or `LDLᵀ` (which does not pivot) solved
//! inaccurately.

use super::Pattern;
use super::pivots::{SingularPivot, factor_diagonal, test_pivots};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::SparseColMatRef;
use faer::sparse::linalg::LuError;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LdltRef, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::linalg::lu::{LuRef, NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::{Conj, MatMut, Par, Side};
use std::time::Instant;

/// Largest normwise backward error `‖b − K x‖ / (‖K‖_F ‖x‖ + ‖b‖)` of an
/// `LDLᵀ` solve before the solve is redone with LU (`LDLᵀ` does not pivot,
/// so an indefinite tangent can make it unstable); about `1e6 ε`.
const LDLT_BACKWARD_ERROR: f64 = 1e-10;

/// Which factor the last numeric factorisation made.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Method {
    Llt,
    Ldlt,
    Lu,
}

/// Why a factorisation or solve failed.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum FactorFault {
    /// The tangent is singular at this equation.
    Singular(SingularPivot),
    /// `faer` failed for a reason of its own (out of memory).
    Failed(String),
}

/// Seconds spent, and factorisations made, by method.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct FactorTally {
    pub symbolic: f64,
    pub numeric: f64,
    pub solve: f64,
    pub llt: usize,
    pub ldlt: usize,
    pub lu: usize,
}

/// The factorisations of one pattern, and their reused buffers.
pub(crate) struct Factorizer {
    cholesky: SymbolicCholesky<usize>,
    /// Values of the Cholesky factor (`LLᵀ` or `LDLᵀ`).
    l: Vec<f64>,
    lu: Option<(SymbolicLu<usize>, NumericLu<usize, f64>)>,
    req: StackReq,
    mem: MemBuffer,
    pub method: Method,
    /// Negative pivots of the last `LDLᵀ` (0 for `LLᵀ`; unknown for LU).
    pub negative_pivots: usize,
    pivots: Vec<f64>,
    rhs: Vec<f64>,
    kx: Vec<f64>,
    tolerance: f64,
    pub tally: FactorTally,
}

fn failed(e: impl std::fmt::Debug) -> FactorFault {
    FactorFault::Failed(format!("{e:?}"))
}

fn text(e: impl std::fmt::Debug) -> String {
    format!("{e:?}")
}

impl Factorizer {
    /// The symbolic Cholesky analysis of `pattern` (AMD ordering) and the
    /// buffers of every later factorisation and solve.
    pub fn new(pattern: &Pattern, pivot_tolerance: f64) -> Result<Self, String> {
        let t = Instant::now();
        let n = pattern.matrix.nrows();
        let cholesky = factorize_symbolic_cholesky(
            pattern.matrix.as_ref(),
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .map_err(text)?;
        let req = StackReq::any_of(&[
            cholesky.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            cholesky.factorize_numeric_ldlt_scratch::<f64>(Par::Seq, Default::default()),
            cholesky.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]);
        let mem = MemBuffer::try_new(req).map_err(text)?;
        let l = vec![0.0; cholesky.len_val()];
        let tally = FactorTally {
            symbolic: t.elapsed().as_secs_f64(),
            ..Default::default()
        };
        Ok(Self {
            cholesky,
            l,
            lu: None,
            req,
            mem,
            method: Method::Llt,
            negative_pivots: 0,
            pivots: vec![0.0; n],
            rhs: vec![0.0; n],
            kx: vec![0.0; n],
            tolerance: pivot_tolerance,
            tally,
        })
    }

    /// Values of the Cholesky factor (its nonzeros).
    pub fn factor_nnz(&self) -> usize {
        self.l.len()
    }

    /// Bytes of the Cholesky factor: values and row indices.
    pub fn factor_bytes(&self) -> usize {
        use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw as Raw;
        let indices = match self.cholesky.raw() {
            Raw::Simplicial(s) => s.row_idx().len() + s.col_ptr().len(),
            Raw::Supernodal(s) => s.row_idx().len() + s.col_ptr_for_val().len(),
        };
        self.l.len() * size_of::<f64>() + indices * size_of::<usize>()
    }

    /// Factorise the tangent with values `values` on the pattern.
    pub fn factor(
        &mut self,
        pattern: &Pattern,
        values: &[f64],
        symmetric: bool,
    ) -> Result<(), FactorFault> {
        let t = Instant::now();
        let result = if symmetric {
            self.factor_cholesky(pattern, values)
        } else {
            self.factor_lu(pattern, values)
        };
        self.tally.numeric += t.elapsed().as_secs_f64();
        result
    }

    fn factor_cholesky(&mut self, pattern: &Pattern, values: &[f64]) -> Result<(), FactorFault> {
        let a = SparseColMatRef::new(pattern.matrix.as_ref(), values);
        let stack = MemStack::new(&mut self.mem);
        let llt = self.cholesky.factorize_numeric_llt(
            &mut self.l,
            a,
            Side::Lower,
            LltRegularization::default(),
            Par::Seq,
            stack,
            Default::default(),
        );
        match llt {
            Ok(_) => {
                self.method = Method::Llt;
                self.tally.llt += 1;
                self.test_pivots(pattern, values, |l| l * l)
            }
            // A pivot that is not positive: not positive definite.
            Err(_) => self.factor_ldlt(pattern, values),
        }
    }

    fn factor_ldlt(&mut self, pattern: &Pattern, values: &[f64]) -> Result<(), FactorFault> {
        let a = SparseColMatRef::new(pattern.matrix.as_ref(), values);
        let stack = MemStack::new(&mut self.mem);
        let ldlt = self.cholesky.factorize_numeric_ldlt(
            &mut self.l,
            a,
            Side::Lower,
            LdltRegularization::default(),
            Par::Seq,
            stack,
            Default::default(),
        );
        // A zero pivot (`Err`) shows in the pivot test too, which names its DOF.
        let _ = ldlt;
        self.method = Method::Ldlt;
        self.tally.ldlt += 1;
        self.test_pivots(pattern, values, |d| d)
    }

    fn test_pivots(
        &mut self,
        pattern: &Pattern,
        values: &[f64],
        pivot: impl Fn(f64) -> f64,
    ) -> Result<(), FactorFault> {
        factor_diagonal(&self.cholesky, &self.l, &mut self.pivots);
        self.pivots.iter_mut().for_each(|p| *p = pivot(*p));
        let perm = self.cholesky.perm();
        let fwd = perm.map(|p| p.arrays().0);
        let diag = |i: usize| values[pattern.diagonal[i]];
        self.negative_pivots =
            test_pivots(&self.pivots, fwd, diag, self.tolerance).map_err(FactorFault::Singular)?;
        Ok(())
    }

    fn factor_lu(&mut self, pattern: &Pattern, values: &[f64]) -> Result<(), FactorFault> {
        if self.lu.is_none() {
            let t = Instant::now();
            let symbolic = factorize_symbolic_lu(pattern.matrix.as_ref(), Default::default())
                .map_err(failed)?;
            self.req = StackReq::any_of(&[
                self.req,
                symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()),
                symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
            ]);
            self.mem = MemBuffer::try_new(self.req).map_err(failed)?;
            self.lu = Some((symbolic, NumericLu::new()));
            self.tally.symbolic += t.elapsed().as_secs_f64();
        }
        let Some((symbolic, numeric)) = self.lu.as_mut() else {
            unreachable!("the LU analysis was made above")
        };
        let a = SparseColMatRef::new(pattern.matrix.as_ref(), values);
        let stack = MemStack::new(&mut self.mem);
        self.method = Method::Lu;
        self.tally.lu += 1;
        match symbolic.factorize_numeric_lu(numeric, a, Par::Seq, stack, Default::default()) {
            Ok(_) => Ok(()),
            Err(LuError::SymbolicSingular { index }) => {
                let equation = symbolic.col_perm().arrays().0[index];
                Err(FactorFault::Singular(SingularPivot {
                    equation,
                    pivot: 0.0,
                    diagonal: values[pattern.diagonal[equation]],
                }))
            }
            Err(e) => Err(failed(e)),
        }
    }
}

impl Factorizer {
    /// Solve `K x = b` in place (`rhs`: `b` in, `x` out) with the last
    /// factor. An `LDLᵀ` solve whose backward error is above
    /// [`LDLT_BACKWARD_ERROR`] is redone with LU (factorised here).
    pub fn solve(
        &mut self,
        pattern: &Pattern,
        values: &[f64],
        rhs: &mut [f64],
    ) -> Result<(), FactorFault> {
        let t = Instant::now();
        let result = self.solve_checked(pattern, values, rhs);
        self.tally.solve += t.elapsed().as_secs_f64();
        result
    }

    fn solve_checked(
        &mut self,
        pattern: &Pattern,
        values: &[f64],
        rhs: &mut [f64],
    ) -> Result<(), FactorFault> {
        if self.method == Method::Ldlt {
            self.rhs.copy_from_slice(rhs);
            self.solve_with_factor(rhs);
            if backward_error(pattern, values, rhs, &self.rhs, &mut self.kx) <= LDLT_BACKWARD_ERROR
            {
                return Ok(());
            }
            let t = Instant::now();
            let lu = self.factor_lu(pattern, values);
            self.tally.numeric += t.elapsed().as_secs_f64();
            lu?;
            rhs.copy_from_slice(&self.rhs);
        }
        self.solve_with_factor(rhs);
        match rhs.iter().position(|x| !x.is_finite()) {
            None => Ok(()),
            Some(equation) => Err(FactorFault::Singular(SingularPivot {
                equation,
                pivot: 0.0,
                diagonal: values[pattern.diagonal[equation]],
            })),
        }
    }

    fn solve_with_factor(&mut self, rhs: &mut [f64]) {
        let n = rhs.len();
        let x = MatMut::from_column_major_slice_mut(rhs, n, 1);
        let stack = MemStack::new(&mut self.mem);
        match self.method {
            Method::Llt => LltRef::new(&self.cholesky, &self.l).solve_in_place_with_conj(
                Conj::No,
                x,
                Par::Seq,
                stack,
            ),
            Method::Ldlt => LdltRef::new(&self.cholesky, &self.l).solve_in_place_with_conj(
                Conj::No,
                x,
                Par::Seq,
                stack,
            ),
            Method::Lu => {
                let Some((symbolic, numeric)) = self.lu.as_ref() else {
                    unreachable!("an LU factor exists when the method is LU")
                };
                LuRef::new_unchecked(symbolic, numeric).solve_in_place_with_conj(
                    Conj::No,
                    x,
                    Par::Seq,
                    stack,
                )
            }
        }
    }
}

/// `‖b − K x‖ / (‖K‖_F ‖x‖ + ‖b‖)`, with `kx` as scratch; infinite when
/// `x` is not finite.
fn backward_error(pattern: &Pattern, values: &[f64], x: &[f64], b: &[f64], kx: &mut [f64]) -> f64 {
    kx.iter_mut().for_each(|v| *v = 0.0);
    let (col_ptr, row_idx) = (pattern.matrix.col_ptr(), pattern.matrix.row_idx());
    let mut k_norm = 0.0;
    for (j, &xj) in x.iter().enumerate() {
        for p in col_ptr[j]..col_ptr[j + 1] {
            kx[row_idx[p]] += values[p] * xj;
            k_norm += values[p] * values[p];
        }
    }
    let norm = |v: &mut dyn Iterator<Item = f64>| v.map(|t| t * t).sum::<f64>().sqrt();
    let r = norm(&mut kx.iter().zip(b).map(|(a, b)| a - b));
    let den = k_norm.sqrt() * norm(&mut x.iter().copied()) + norm(&mut b.iter().copied());
    if !r.is_finite() {
        f64::INFINITY
    } else if den == 0.0 {
        0.0
    } else {
        r / den
    }
}
