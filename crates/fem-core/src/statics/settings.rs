//! `NewtonSettings`: tolerances, load stepping, line search, pivot test.

use crate::FemError;

/// Settings of the static Newton solver; [`Default`] gives the documented defaults.
///
/// # Convergence
///
/// An increment has converged when, at the current state `u_k`, all three hold:
///
/// - **force**: `‖R_k‖ ≤ force_tolerance · max(F_ref, force_floor)`, with
///   `R` the residual on the free DOFs and `F_ref = max(‖λ F_ext‖, ‖F_int‖)`
///   (`F_int` over all DOFs, so the reactions count). Translations (N) and
///   rotations (N·mm) are checked separately, each against its own
///   reference. Default `1e-8`: eight digits of equilibrium, far below the
///   1e-3–1e-4 that a springback result carries, yet two or more orders
///   above round-off for the forces of a well-conditioned model.
/// - **displacement**: the last correction `‖α δu‖ ≤ displacement_tolerance
///   · max(‖Δu‖, displacement_floor)`, with `Δu` the increment's
///   displacement so far; translations (mm) and rotations (rad) separately.
///   Default `1e-8`, for the same reasons; near the solution Newton's
///   correction is the error of the previous iterate, so this bounds the
///   error of the displacement.
/// - **energy**: `|α δu · R_{k−1}| ≤ energy_tolerance · |δu_0 · R_0|` (the
///   work of the last correction against the residual it removed, relative
///   to the first iteration's). Default `1e-12`: the energy is quadratic in
///   the error, so this is a relative error of about `1e-6` in the energy
///   norm — a safety net that catches a small residual with a large
///   correction in a soft direction, not the criterion that usually binds.
///
/// Every increment takes at least one Newton iteration, so all three are
/// measured on an actual correction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonSettings {
    /// Relative force tolerance (-), `> 0`. Default `1e-8`.
    pub force_tolerance: f64,
    /// Relative displacement tolerance (-), `> 0`. Default `1e-8`.
    pub displacement_tolerance: f64,
    /// Relative energy tolerance (-), `> 0`. Default `1e-12`.
    pub energy_tolerance: f64,
    /// Lower bound of the force reference (N, or N·mm for moments), `>= 0`,
    /// for a model carrying no force at all. Default `1e-9`.
    pub force_floor: f64,
    /// Lower bound of the displacement reference (mm, or rad), `>= 0`, for
    /// an increment that does not move. Default `1e-12`.
    pub displacement_floor: f64,
    /// Newton iterations per increment attempt before it counts as
    /// diverged, `>= 1`. Default `25`.
    pub max_iterations: usize,
    /// First load increment `Δλ`, in `(0, 1]`. Default `0.1`.
    pub initial_increment: f64,
    /// Smallest load increment; a cut-back below it stops the solve.
    /// In `(0, initial_increment]`. Default `1e-5`.
    pub min_increment: f64,
    /// Largest load increment, in `[initial_increment, 1]`. Default `1`.
    pub max_increment: f64,
    /// Cut-backs (halvings of `Δλ`) allowed in a row on one increment
    /// before the solve stops. Default `12`.
    pub max_cutbacks: usize,
    /// Factor (`>= 1`) the increment grows by after an increment converged
    /// within `easy_iterations`. Default `1.5`.
    pub growth_factor: f64,
    /// Iterations within which an increment counts as easy. Default `5`.
    pub easy_iterations: usize,
    /// Backtracking steps of the line search per iteration (0: full Newton
    /// steps). Default `10`.
    pub line_search_steps: usize,
    /// Keep the factorised tangent while it contracts the residual well
    /// (modified Newton): after an iteration whose `‖R‖` fell to at most
    /// this fraction of the previous one, the next iteration (in this
    /// increment or the next) solves with the same factor and assembles
    /// forces only; after one that did not, it assembles and factorises
    /// the tangent anew. `0` factorises every iteration (full Newton,
    /// quadratic near the solution). In `[0, 1)`. Default `0`.
    pub reuse_contraction: f64,
    /// Factorise the symmetric part `½ (K + Kᵀ)` of an unsymmetric
    /// tangent, by Cholesky (`LLᵀ`, or `LDLᵀ` when it is not positive
    /// definite), in place of LU of `K`: each factorisation is cheaper,
    /// and Newton converges linearly rather than quadratically. The
    /// residual, and so the solution, is the same. Far from the tangent
    /// (a strongly unsymmetric one) that iteration need not contract at
    /// any increment: an increment that the symmetric part still fails
    /// after the last cut-back allowed is tried again, from its first
    /// size, with the exact tangent by LU, which then serves to the end
    /// of the solve (`SolveReport::exact_fallback`). Default `false`.
    pub symmetrize: bool,
    /// An iteration whose residual norm exceeds this multiple of the
    /// increment's first residual norm diverged, `> 1`. Default `1e6`.
    pub divergence_ratio: f64,
    /// A pivot `p_j` of the factorised tangent with `|p_j| <=
    /// pivot_tolerance · |K_jj|` marks DOF `j` as free (a singular tangent),
    /// in `(0, 1)`. Default `1e-12`: a rigid-body mode leaves a pivot at
    /// round-off, about `1e-16` of its diagonal; a stiff model that loses
    /// twelve digits of a DOF's stiffness would give meaningless results anyway.
    pub pivot_tolerance: f64,
}

impl Default for NewtonSettings {
    fn default() -> Self {
        Self {
            force_tolerance: 1e-8,
            displacement_tolerance: 1e-8,
            energy_tolerance: 1e-12,
            force_floor: 1e-9,
            displacement_floor: 1e-12,
            max_iterations: 25,
            initial_increment: 0.1,
            min_increment: 1e-5,
            max_increment: 1.0,
            max_cutbacks: 12,
            growth_factor: 1.5,
            easy_iterations: 5,
            line_search_steps: 10,
            reuse_contraction: 0.0,
            symmetrize: false,
            divergence_ratio: 1e6,
            pivot_tolerance: 1e-12,
        }
    }
}

impl NewtonSettings {
    /// Check every field; the error names the field, its value and range.
    pub fn validate(&self) -> Result<(), FemError> {
        let s = self;
        let open01 = |v: f64| v > 0.0 && v < 1.0;
        let checks: [(&str, f64, &'static str, &'static str, bool); 14] = [
            (
                "force_tolerance",
                s.force_tolerance,
                "-",
                "in (0, 1)",
                open01(s.force_tolerance),
            ),
            (
                "displacement_tolerance",
                s.displacement_tolerance,
                "-",
                "in (0, 1)",
                open01(s.displacement_tolerance),
            ),
            (
                "energy_tolerance",
                s.energy_tolerance,
                "-",
                "in (0, 1)",
                open01(s.energy_tolerance),
            ),
            (
                "force_floor",
                s.force_floor,
                "N",
                "finite and >= 0",
                s.force_floor >= 0.0 && s.force_floor.is_finite(),
            ),
            (
                "displacement_floor",
                s.displacement_floor,
                "mm",
                "finite and >= 0",
                s.displacement_floor >= 0.0 && s.displacement_floor.is_finite(),
            ),
            (
                "max_iterations",
                s.max_iterations as f64,
                "-",
                ">= 1",
                s.max_iterations >= 1,
            ),
            (
                "initial_increment",
                s.initial_increment,
                "-",
                "in (0, 1]",
                s.initial_increment > 0.0 && s.initial_increment <= 1.0,
            ),
            (
                "min_increment",
                s.min_increment,
                "-",
                "in (0, initial_increment]",
                s.min_increment > 0.0 && s.min_increment <= s.initial_increment,
            ),
            (
                "max_increment",
                s.max_increment,
                "-",
                "in [initial_increment, 1]",
                s.max_increment >= s.initial_increment && s.max_increment <= 1.0,
            ),
            (
                "growth_factor",
                s.growth_factor,
                "-",
                "finite and >= 1",
                s.growth_factor >= 1.0 && s.growth_factor.is_finite(),
            ),
            (
                "easy_iterations",
                s.easy_iterations as f64,
                "-",
                "<= max_iterations",
                s.easy_iterations <= s.max_iterations,
            ),
            (
                "reuse_contraction",
                s.reuse_contraction,
                "-",
                "in [0, 1)",
                s.reuse_contraction >= 0.0 && s.reuse_contraction < 1.0,
            ),
            (
                "divergence_ratio",
                s.divergence_ratio,
                "-",
                "> 1",
                s.divergence_ratio > 1.0,
            ),
            (
                "pivot_tolerance",
                s.pivot_tolerance,
                "-",
                "in (0, 1)",
                open01(s.pivot_tolerance),
            ),
        ];
        for (field, value, unit, range, ok) in checks {
            if !ok {
                return Err(FemError::InvalidParameter {
                    field: format!("newton.{field}"),
                    value,
                    unit,
                    range,
                });
            }
        }
        Ok(())
    }
}
