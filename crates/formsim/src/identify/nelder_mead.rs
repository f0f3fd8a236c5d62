//! Nelder–Mead (argmin's) on the free variables of the bounded values
//! ([`FitParam::from_free`]): every proposed point is inside the bounds.
//!
//! The first simplex is the start and, for each value, the start moved by
//! 10 % of its range towards the inside; its `n + 1` points run as one
//! parallel batch before argmin asks for them one by one (it then reads them
//! from the journal). The iterations are sequential: each run gets every
//! thread.

use super::IdentifyError;
use super::evaluate::Evaluator;
use super::params::FitParam;
use argmin::core::{CostFunction, Executor};
use argmin::solver::neldermead::NelderMead;
use std::sync::Mutex;

/// Nelder–Mead's settings.
#[derive(Debug, Clone, Copy)]
pub struct Settings {
    /// Stop when the standard deviation of the objective over the simplex is below this.
    pub sd_tolerance: f64,
    /// Stop after this many iterations.
    pub max_iters: u64,
    /// Stop before an evaluation past this many.
    pub max_evaluations: usize,
}

struct Problem<'e, 'a> {
    ev: &'e Evaluator<'a>,
    error: Mutex<Option<IdentifyError>>,
    limit: usize,
}

/// The values of free variables `z`.
fn values(params: &[FitParam], z: &[f64]) -> Vec<f64> {
    params.iter().zip(z).map(|(p, z)| p.from_free(*z)).collect()
}

impl CostFunction for Problem<'_, '_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, z: &Vec<f64>) -> Result<f64, argmin::core::Error> {
        let x = values(self.ev.params(), z);
        // A point already evaluated is read, whatever the limit: argmin's
        // Nelder–Mead asks for every vertex of the first simplex again in
        // its `init` and unwraps the answer (the limit of 3 panicked there).
        if self.ev.entry(&x).is_none() && self.ev.log().len() >= self.limit {
            return Err(argmin::core::Error::msg("the evaluation limit is reached"));
        }
        match self.ev.evaluate(&x) {
            Ok(e) => Ok(e.cost),
            Err(e) => {
                let message = e.to_string();
                if let Ok(mut slot) = self.error.lock() {
                    slot.get_or_insert(e);
                }
                Err(argmin::core::Error::msg(message))
            }
        }
    }
}

/// The first simplex, as free variables.
fn simplex(params: &[FitParam], start: &[f64]) -> Vec<Vec<f64>> {
    let z0: Vec<f64> = params
        .iter()
        .zip(start)
        .map(|(p, x)| p.to_free(*x))
        .collect();
    let mut out = vec![z0.clone()];
    for (j, p) in params.iter().enumerate() {
        let u = p.to_unit(start[j]);
        let moved = if u + 0.1 <= 1.0 { u + 0.1 } else { u - 0.1 };
        let mut z = z0.clone();
        z[j] = p.to_free(p.from_unit(moved));
        out.push(z);
    }
    out
}

/// Minimise the objective from `start`. The result is read from the
/// evaluator's log (the best evaluation), so the reason argmin stopped (its
/// tolerance, the iteration or evaluation limit) needs no handling here.
///
/// # Errors
/// The journal could not be written.
pub fn minimise(
    ev: &Evaluator<'_>,
    start: &[f64],
    settings: Settings,
) -> Result<String, IdentifyError> {
    let params = ev.params();
    let simplex = simplex(params, start);
    let first: Vec<Vec<f64>> = simplex.iter().map(|z| values(params, z)).collect();
    ev.evaluate_batch(&first)?;
    let problem = Problem {
        ev,
        error: Mutex::new(None),
        limit: settings.max_evaluations,
    };
    let solver = NelderMead::new(simplex)
        .with_sd_tolerance(settings.sd_tolerance)
        .map_err(|e| IdentifyError::Option(format!("Nelder–Mead: {e}")))?;
    let outcome = Executor::new(problem, solver)
        .configure(|state| state.max_iters(settings.max_iters))
        .run();
    match outcome {
        Ok(result) => {
            let reason = result.state().termination_status.to_string();
            Ok(reason)
        }
        Err(e) => {
            // The problem is gone with the executor; a journal error was
            // stored in it before argmin saw the message.
            let message = e.to_string();
            if message.contains("evaluation limit") {
                Ok(format!(
                    "stopped at the limit of {} evaluations",
                    settings.max_evaluations
                ))
            } else {
                Err(IdentifyError::Evaluation(message))
            }
        }
    }
}
