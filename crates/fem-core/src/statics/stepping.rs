//! Load stepping: increments of `λ` from the converged state to 1, cut back
//! (halved) on failure and grown after easy convergence; commit and revert.

use super::evaluate::Failure;
use super::{IncrementReport, NewtonSettings, SolveReport, StaticSolver, StaticsError};
use plugins_api::nalgebra::Rotation3;
use std::time::Instant;

/// A target within this of 1 is taken as 1 (no sliver of an increment).
const LAMBDA_SNAP: f64 = 1e-12;

impl StaticSolver {
    /// Solve from the converged load factor to `λ = 1`.
    ///
    /// # Errors
    /// [`StaticsError::Singular`] when the first tangent is singular;
    /// [`StaticsError::NotConverged`] when an increment still fails after
    /// the last cut-back (or below `min_increment`); an assembly fault. The
    /// solver then holds the last converged increment.
    pub fn solve(&mut self) -> Result<SolveReport, StaticsError> {
        self.solve_observed(&mut |_| {})
    }

    /// [`StaticSolver::solve`], calling `observer` after every converged
    /// increment (to record a load–deflection curve, say).
    pub fn solve_observed(
        &mut self,
        observer: &mut dyn FnMut(&StaticSolver),
    ) -> Result<SolveReport, StaticsError> {
        let t = Instant::now();
        let total0 = self.timing.total;
        let result = self.step_to_one(observer);
        self.timing.total = total0 + t.elapsed().as_secs_f64();
        let mut report = result?;
        report.timing = self.timing;
        report.system = self.system();
        report.settings = self.settings;
        Ok(report)
    }

    fn step_to_one(
        &mut self,
        observer: &mut dyn FnMut(&StaticSolver),
    ) -> Result<SolveReport, StaticsError> {
        let s = self.settings;
        let mut report = SolveReport::default();
        let mut history = Vec::with_capacity(s.max_iterations + 1);
        // Cut-backs in a row on the current increment, and its size when
        // the first of them failed.
        let (mut dl, mut in_a_row, mut first_failed) = (s.initial_increment, 0, 0.0);
        while self.lambda < 1.0 {
            let mut target = (self.lambda + dl).min(1.0);
            if 1.0 - target < LAMBDA_SNAP {
                target = 1.0;
            }
            let step = target - self.lambda;
            match self.attempt_increment(target, &mut history) {
                Ok(c) => {
                    self.commit();
                    report.increments.push(IncrementReport {
                        lambda: target,
                        increment: step,
                        iterations: c.iterations,
                        residuals: history.clone(),
                        force_reference: c.force_reference,
                        backtracks: c.backtracks,
                        negative_pivots: self.factor.as_ref().map_or(0, |f| f.negative_pivots),
                    });
                    observer(self);
                    if c.iterations <= s.easy_iterations {
                        dl = (dl * s.growth_factor).min(s.max_increment);
                    }
                    in_a_row = 0;
                }
                Err(Failure::Hard(e)) => {
                    self.revert();
                    return Err(e);
                }
                Err(Failure::Soft(reason)) => {
                    self.revert();
                    if in_a_row == 0 {
                        first_failed = step;
                    }
                    let Some(stop) = stop_reason(&s, in_a_row, step) else {
                        in_a_row += 1;
                        report.cutbacks += 1;
                        report
                            .cutback_reasons
                            .push(format!("λ = {target}: {reason}"));
                        dl = 0.5 * step;
                        continue;
                    };
                    if s.symmetrize && !self.symmetric && !self.exact_tangent {
                        // The symmetric part is not the tangent: far from
                        // it, its Newton iteration need not contract at
                        // any increment. Before giving up, the solve goes
                        // on with the exact tangent (LU), from the
                        // increment that first failed.
                        self.exact_tangent = true;
                        report.exact_fallback = true;
                        report.cutback_reasons.push(format!(
                            "λ = {target}: {reason}; {stop}: the exact tangent from here on"
                        ));
                        (dl, in_a_row) = (first_failed, 0);
                        continue;
                    }
                    return Err(StaticsError::NotConverged {
                        lambda_converged: self.lambda,
                        lambda_target: target,
                        increment: step,
                        cutbacks: report.cutbacks,
                        reason,
                        stop,
                        residuals: history.clone(),
                    });
                }
            }
        }
        Ok(report)
    }

    /// Accept the trial state: the effects commit, the rotations compose,
    /// the increment's rotation vectors restart from zero.
    fn commit(&mut self) {
        let state = super::TrialState {
            x_start: &self.x_start,
            x_committed: &self.x_committed,
            x: &self.x,
            rotation_committed: &self.rotation_committed,
            dtheta: &self.dtheta,
            lambda: self.lambda_trial,
        };
        for effect in &mut self.effects {
            effect.commit(&state);
        }
        for (r, d) in self.rotation_committed.iter_mut().zip(&mut self.dtheta) {
            if *d != crate::Vec3::zeros() {
                *r = Rotation3::new(*d).into_inner() * *r;
                *d = crate::Vec3::zeros();
            }
        }
        self.x_committed.copy_from_slice(&self.x);
        self.f_committed.copy_from_slice(&self.f_int);
        self.lambda = self.lambda_trial;
    }

    /// Back to the committed state.
    fn revert(&mut self) {
        self.keep_factor = false;
        for effect in &mut self.effects {
            effect.revert();
        }
        self.x.copy_from_slice(&self.x_committed);
        self.dtheta
            .iter_mut()
            .for_each(|d| *d = crate::Vec3::zeros());
        self.lambda_trial = self.lambda;
    }
}

/// Why a failed attempt of increment `step` after `in_a_row` cut-backs in
/// a row is the last, if it is.
fn stop_reason(s: &NewtonSettings, in_a_row: usize, step: f64) -> Option<String> {
    if in_a_row == s.max_cutbacks {
        Some(format!("{in_a_row} in a row, the most allowed"))
    } else if 0.5 * step < s.min_increment {
        Some(format!(
            "half of Δλ = {step:.3e} is below min_increment = {:e}",
            s.min_increment
        ))
    } else {
        None
    }
}
