//! What a static solve reports: increments, iterations, residual histories,
//! where the time went, the size of the factor.

use std::fmt;

/// One converged load increment.
#[derive(Debug, Clone, PartialEq)]
pub struct IncrementReport {
    /// Load factor reached (-).
    pub lambda: f64,
    /// Load increment `Δλ` of this increment (-).
    pub increment: f64,
    /// Newton iterations (tangent solves) it took.
    pub iterations: usize,
    /// Residual norm `‖R‖₂` over the free DOFs (N and N·mm together) at
    /// the start and after every iteration: `iterations + 1` values.
    pub residuals: Vec<f64>,
    /// The force reference at convergence, `max(‖(1 − λ) F_start + λ F_ext‖, ‖F_int‖)`
    /// over translations (N): divide `residuals` by it for relative norms.
    pub force_reference: f64,
    /// Line-search backtracking steps taken, summed over the iterations.
    pub backtracks: usize,
    /// Negative pivots of the last factorised tangent when it was `LDLᵀ`
    /// (the number of negative eigenvalues: 0 on a stable branch), else 0.
    pub negative_pivots: usize,
}

/// Wall-clock seconds of a solve, by task.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StaticTiming {
    /// Internal forces and tangents of the effects, residuals, norms (s).
    pub assembly: f64,
    /// Symbolic analyses: ordering and elimination tree, once per solver (s).
    pub symbolic: f64,
    /// Numeric factorisations (s).
    pub numeric: f64,
    /// Triangular solves (s).
    pub solve: f64,
    /// The whole solve, set-up included (s).
    pub total: f64,
}

/// The linear systems of a solve.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SystemStats {
    /// Equations: free DOFs that some effect stiffens.
    pub equations: usize,
    /// Constrained DOFs (fixed or prescribed).
    pub constrained: usize,
    /// DOFs no effect stiffens, dropped from the system.
    pub dropped: usize,
    /// Stored entries of the tangent (both triangles).
    pub matrix_nnz: usize,
    /// Stored values of the Cholesky factor `L` (after fill-in).
    pub factor_nnz: usize,
    /// Bytes of the Cholesky factor: values and indices. (An LU of an
    /// unsymmetric tangent holds more; faer does not give its size.)
    pub factor_bytes: usize,
    /// Numeric `LLᵀ` factorisations.
    pub llt: usize,
    /// Numeric `LDLᵀ` factorisations (the tangent was not positive definite).
    pub ldlt: usize,
    /// Numeric LU factorisations (unsymmetric tangent, or `LDLᵀ` inaccurate).
    pub lu: usize,
}

/// What a static solve did.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SolveReport {
    /// The converged increments, in order.
    pub increments: Vec<IncrementReport>,
    /// Increment attempts that failed and were cut back.
    pub cutbacks: usize,
    /// Whether the solve went over to the exact tangent: with
    /// [`super::NewtonSettings::symmetrize`], an increment that the
    /// symmetric part failed after the last cut-back allowed is tried
    /// again with the exact tangent, which then serves to the end.
    pub exact_fallback: bool,
    /// Why each failed attempt failed (`λ = …: reason`), in order: the
    /// cut-backs and the fall-back to the exact tangent.
    pub cutback_reasons: Vec<String>,
    /// Where the time went.
    pub timing: StaticTiming,
    /// Sizes of the linear systems and factorisations made.
    pub system: SystemStats,
    /// The settings the solve ran with.
    pub settings: super::NewtonSettings,
}

impl SolveReport {
    /// Newton iterations over all converged increments.
    pub fn iterations(&self) -> usize {
        self.increments.iter().map(|i| i.iterations).sum()
    }
}

impl fmt::Display for SolveReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (s, t) = (&self.system, &self.timing);
        writeln!(
            f,
            "{} increments, {} iterations, {} cut-backs{}; {} equations ({} constrained, {} dropped), \
             K nnz {}, L nnz {} ({:.2} MiB); factorisations LLt {}, LDLt {}, LU {}",
            self.increments.len(),
            self.iterations(),
            self.cutbacks,
            if self.exact_fallback {
                ", then the exact tangent"
            } else {
                ""
            },
            s.equations,
            s.constrained,
            s.dropped,
            s.matrix_nnz,
            s.factor_nnz,
            s.factor_bytes as f64 / (1024.0 * 1024.0),
            s.llt,
            s.ldlt,
            s.lu
        )?;
        writeln!(
            f,
            "time {:.4} s: assembly {:.4}, symbolic {:.4}, numeric {:.4}, solves {:.4}",
            t.total, t.assembly, t.symbolic, t.numeric, t.solve
        )?;
        for (k, inc) in self.increments.iter().enumerate() {
            write!(
                f,
                "increment {k}: λ = {:.6} (Δλ {:.3e}), {} iterations, |R|:",
                inc.lambda, inc.increment, inc.iterations
            )?;
            for r in &inc.residuals {
                write!(f, " {r:.3e}")?;
            }
            writeln!(f)?;
        }
        for reason in &self.cutback_reasons {
            writeln!(f, "failed: {reason}")?;
        }
        Ok(())
    }
}
