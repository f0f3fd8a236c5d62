//! One increment's Newton iterations: consistent tangent, Dirichlet
//! constraints by elimination, backtracking line search on `‖R‖`, and the
//! force, displacement and energy criteria.

use super::StaticSolver;
use super::StaticsError;
use super::dof_map::split_norms;
use super::evaluate::{Eval, Failure};
use super::factor::FactorFault;

/// Armijo constant of the line search: a step `α` is accepted when
/// `‖R(α)‖² <= (1 − 2 c α) ‖R(0)‖²` (sufficient decrease of `½‖R‖²`,
/// whose slope along the Newton direction is `−‖R(0)‖²`).
const ARMIJO: f64 = 1e-4;

/// Where the line search stopped.
#[derive(Debug, Clone, Copy, PartialEq)]
struct LineStep {
    /// Step length `α` along the Newton correction.
    alpha: f64,
    /// The evaluation at the new state.
    eval: Eval,
    /// Whether that evaluation holds the tangent.
    fresh: bool,
    /// Backtracking steps taken.
    backtracks: usize,
    /// Whether `‖R‖` decreased enough (else the last, shortest step was taken).
    descent: bool,
}

/// Line searches in a row without enough decrease after which the attempt
/// fails: the residual has stalled at a minimum of `‖R‖` that is no
/// equilibrium (past a limit load, say).
const STALLS: usize = 2;

/// What a converged increment attempt took.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Converged {
    pub iterations: usize,
    pub backtracks: usize,
    pub force_reference: f64,
}

impl StaticSolver {
    /// Iterate from the committed state to equilibrium at `lambda`; the
    /// residual norms go to `history` (cleared first, never reallocated
    /// beyond `max_iterations + 1` values).
    pub(super) fn attempt_increment(
        &mut self,
        lambda: f64,
        history: &mut Vec<f64>,
    ) -> Result<Converged, Failure> {
        history.clear();
        self.lambda_trial = lambda;
        self.apply_prescribed();
        let mut eval = self.evaluate(!self.keep_factor)?;
        history.push(eval.merit);
        if self.in_balance(&eval) {
            // Already in equilibrium at the new load factor (a release with
            // nothing left to let go): a Newton step would only stir
            // round-off, and the energy criterion cannot hold against it.
            // The first tangent is still factorised: a free rigid-body mode
            // is an error even where nothing loads it.
            if !self.factored_once {
                self.newton_direction()?;
            }
            return Ok(Converged {
                iterations: 0,
                backtracks: 0,
                force_reference: eval.ref_t,
            });
        }
        let (r0, mut e0, mut backtracks, mut stalls) = (eval.merit, None, 0, 0);
        for iteration in 1..=self.settings.max_iterations {
            self.newton_direction()?;
            let energy = dot(&self.du, &self.r).abs();
            let e0 = *e0.get_or_insert(energy);
            let step = self.line_search(eval.merit)?;
            let alpha = step.alpha;
            backtracks += step.backtracks;
            history.push(step.eval.merit);
            let contraction = self.settings.reuse_contraction;
            self.keep_factor = step.eval.merit <= contraction * eval.merit;
            eval = step.eval;
            if self.converged(&eval, alpha, alpha * energy, e0) {
                return Ok(Converged {
                    iterations: iteration,
                    backtracks,
                    force_reference: eval.ref_t,
                });
            }
            if eval.merit > self.settings.divergence_ratio * r0 {
                return Err(Failure::Soft(format!(
                    "the residual grew to {:.3e}, {:.1e} times the first",
                    eval.merit,
                    eval.merit / r0
                )));
            }
            // A stall is a line search that found no descent; with full
            // steps (no line search) the residual may rise for an iteration
            // or two on a yield surface's kink before Newton takes hold, and
            // only divergence and the iteration limit end the attempt.
            stalls = if step.descent || self.settings.line_search_steps == 0 {
                0
            } else {
                stalls + 1
            };
            if stalls == STALLS {
                return Err(Failure::Soft(format!(
                    "the residual stalled at |R| = {:.3e} ({STALLS} line searches without descent): \
                     no equilibrium nearby",
                    eval.merit
                )));
            }
            if !step.fresh && !self.keep_factor {
                eval = self.evaluate(true)?;
            }
        }
        Err(Failure::Soft(format!(
            "{} iterations without convergence",
            self.settings.max_iterations
        )))
    }

    /// Set every constrained DOF to its value at `lambda_trial`.
    fn apply_prescribed(&mut self) {
        let dl = self.lambda_trial - self.lambda;
        for &(g, value) in &self.constraints {
            let (node, d) = (g as usize / 6, g as usize % 6);
            if d < 3 {
                self.x[node][d] = self.x_start[node][d] + self.lambda_trial * value;
            } else {
                self.dtheta[node][d - 3] = dl * value;
            }
        }
    }

    /// Factorise the tangent (unless the factor in hand is kept) and solve
    /// `K δu = −R` into `du`.
    fn newton_direction(&mut self) -> Result<(), Failure> {
        self.du.copy_from_slice(&self.r);
        let Some(factor) = self.factor.as_mut() else {
            return Ok(());
        };
        let result = if self.keep_factor {
            factor.solve(&self.pattern, &self.values, &mut self.du)
        } else {
            let symmetrize = self.settings.symmetrize && !self.exact_tangent;
            if symmetrize && !self.symmetric {
                self.pattern.symmetrize(&mut self.values);
            }
            let symmetric = self.symmetric || symmetrize;
            factor
                .factor(&self.pattern, &self.values, symmetric)
                .and_then(|()| factor.solve(&self.pattern, &self.values, &mut self.du))
        };
        self.timing.numeric = factor.tally.numeric;
        self.timing.solve = factor.tally.solve;
        self.timing.symbolic = factor.tally.symbolic;
        let first = !self.factored_once;
        self.factored_once = true;
        match result {
            Ok(()) => {
                self.du.iter_mut().for_each(|x| *x = -*x);
                Ok(())
            }
            Err(FactorFault::Failed(message)) => {
                Err(Failure::Hard(StaticsError::Factorisation(message)))
            }
            Err(FactorFault::Singular(p)) => {
                let (node, dof) = self.dofs.node_dof(p.equation);
                let error = StaticsError::Singular {
                    lambda: self.lambda_trial,
                    node,
                    dof,
                    pivot: p.pivot,
                    diagonal: p.diagonal,
                };
                Err(if first {
                    Failure::Hard(error)
                } else {
                    Failure::Soft(error.to_string())
                })
            }
        }
    }

    /// The force criterion alone.
    fn in_balance(&self, eval: &Eval) -> bool {
        let s = &self.settings;
        eval.r_t <= s.force_tolerance * eval.ref_t.max(s.force_floor)
            && eval.r_r <= s.force_tolerance * eval.ref_r.max(s.force_floor)
    }

    /// The three criteria at the state just reached by the correction `α δu`.
    fn converged(&self, eval: &Eval, alpha: f64, energy: f64, e0: f64) -> bool {
        let s = &self.settings;
        let force = self.in_balance(eval);
        let (du_t, du_r) = split_norms(&self.du, &self.dofs.is_rotation);
        let (inc_t, inc_r) = self.increment_norms();
        let floor = s.displacement_floor;
        let displacement = alpha * du_t <= s.displacement_tolerance * inc_t.max(floor)
            && alpha * du_r <= s.displacement_tolerance * inc_r.max(floor);
        let energy = energy <= s.energy_tolerance * e0;
        force && displacement && energy
    }

    /// `(‖x − x_committed‖, ‖dtheta‖)` over all nodes: the increment so far.
    fn increment_norms(&self) -> (f64, f64) {
        let t: f64 = (self.x.iter().zip(&self.x_committed))
            .map(|(a, b)| (a - b).norm_squared())
            .sum();
        let r: f64 = self.dtheta.iter().map(|d| d.norm_squared()).sum();
        (t.sqrt(), r.sqrt())
    }

    /// Backtrack along `du` from the current state until `‖R‖` decreases
    /// enough, or take the shortest step after `line_search_steps`. The
    /// full step is evaluated with the tangent in full Newton (it is
    /// accepted near the solution, so the next iteration needs no second
    /// assembly); shorter ones, and every step when the factor may be
    /// kept, with forces only.
    fn line_search(&mut self, merit0: f64) -> Result<LineStep, Failure> {
        self.x_base.copy_from_slice(&self.x);
        self.dtheta_base.copy_from_slice(&self.dtheta);
        let steps = self.settings.line_search_steps;
        let mut alpha = 1.0;
        for step in 0..=steps {
            self.set_trial(alpha);
            // With factor reuse, the tangent is assembled only when the
            // next iteration needs a new factor (decided on this step's |R|).
            let tangent = step == 0 && self.settings.reuse_contraction == 0.0;
            match self.evaluate(tangent) {
                Ok(eval) if step == steps || sufficient(eval.merit, merit0, alpha) => {
                    return Ok(LineStep {
                        alpha,
                        eval,
                        fresh: tangent,
                        backtracks: step,
                        descent: sufficient(eval.merit, merit0, alpha),
                    });
                }
                Ok(e) => alpha = backtrack(alpha, e.merit, merit0),
                Err(Failure::Soft(reason)) if step == steps => return Err(Failure::Soft(reason)),
                Err(Failure::Soft(_)) => alpha *= 0.5,
                Err(hard) => return Err(hard),
            }
        }
        unreachable!("the last step returns")
    }

    /// Free DOFs at `base + α du`; constrained ones stay where they are.
    fn set_trial(&mut self, alpha: f64) {
        for (&g, &du) in self.dofs.global.iter().zip(&self.du) {
            let (node, d) = (g as usize / 6, g as usize % 6);
            if d < 3 {
                self.x[node][d] = self.x_base[node][d] + alpha * du;
            } else {
                self.dtheta[node][d - 3] = self.dtheta_base[node][d - 3] + alpha * du;
            }
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn sufficient(merit: f64, merit0: f64, alpha: f64) -> bool {
    merit * merit <= (1.0 - 2.0 * ARMIJO * alpha) * merit0 * merit0
}

/// The minimiser of the quadratic through `φ(0) = ½m0²`, `φ'(0) = −m0²`
/// and `φ(α) = ½m²`, kept within `[0.1 α, 0.5 α]`.
fn backtrack(alpha: f64, merit: f64, merit0: f64) -> f64 {
    let m0 = merit0 * merit0;
    let den = merit * merit - m0 + 2.0 * m0 * alpha;
    let next = m0 * alpha * alpha / den;
    if next.is_finite() && den > 0.0 {
        next.clamp(0.1 * alpha, 0.5 * alpha)
    } else {
        0.5 * alpha
    }
}
