//! Levenberg–Marquardt on finite-difference Jacobians, projected on the
//! bounds: the derivative-based alternative to Nelder–Mead.
//!
//! It minimises the sum of squared residuals ([`super::objective::residuals`])
//! in the values scaled to their ranges. Each iteration runs the trial point
//! and its `n` Jacobian points as one parallel batch (the Jacobian is taken
//! speculatively, as if the trial were accepted, so that the runs of one
//! iteration share the cores); a rejected trial costs its batch and raises
//! the damping.

use super::IdentifyError;
use super::evaluate::Evaluator;
use super::jacobian::{Jacobian, from_stencil, stencil};
use nalgebra::{DMatrix, DVector};

/// Rejected steps in a row after which the iteration stops: with a rough
/// objective (docs/identification.md, "Roughness") smaller and smaller steps
/// would only sample its noise.
pub const MAX_REJECTED: usize = 3;

/// Levenberg–Marquardt's settings.
#[derive(Debug, Clone, Copy)]
pub struct Settings {
    /// Finite-difference step, as a fraction of each range.
    pub fd_step: f64,
    /// Stop when a step moves no value by more than this fraction of its range.
    pub x_tolerance: f64,
    /// Stop when the sum of squares falls by less than this fraction.
    pub f_tolerance: f64,
    /// Stop before an iteration that would pass this many evaluations.
    pub max_evaluations: usize,
}

fn sum_squares(j: &Jacobian) -> f64 {
    j.residuals.iter().map(|r| r * r).sum()
}

fn batch(ev: &Evaluator<'_>, x: &[f64], fd_step: f64) -> Result<Option<Jacobian>, IdentifyError> {
    let (points, steps) = stencil(ev, x, fd_step);
    let evaluations = ev.evaluate_batch(&points)?;
    if evaluations[0].failure().is_some() {
        return Ok(None);
    }
    from_stencil(ev, &evaluations, &steps).map(Some)
}

/// The damped Gauss–Newton step in range-scaled values.
fn step(j: &Jacobian, widths: &[f64], lambda: f64) -> Option<Vec<f64>> {
    let n = widths.len();
    let js = DMatrix::from_fn(j.matrix.nrows(), n, |i, k| j.matrix[(i, k)] * widths[k]);
    let r = DVector::from_column_slice(&j.residuals);
    let mut a = js.transpose() * &js;
    let g = js.transpose() * r;
    let floor = a.diagonal().iter().copied().fold(0.0, f64::max) * 1e-12;
    for k in 0..n {
        a[(k, k)] += lambda * a[(k, k)].max(floor);
    }
    let du = a.cholesky()?.solve(&(-g));
    Some(du.iter().zip(widths).map(|(d, w)| d * w).collect())
}

/// Minimise the sum of squared residuals from `start`; returns why it stopped.
///
/// # Errors
/// A run of a Jacobian (other than a trial point) failed; the journal cannot be written.
pub fn minimise(
    ev: &Evaluator<'_>,
    start: &[f64],
    settings: Settings,
) -> Result<String, IdentifyError> {
    let params = ev.params();
    let widths: Vec<f64> = params.iter().map(|p| p.width()).collect();
    let n = params.len();
    let mut current = batch(ev, start, settings.fd_step)?.ok_or_else(|| {
        IdentifyError::Evaluation(format!("the run at the start {start:?} failed"))
    })?;
    let mut lambda = 1e-3;
    let mut rejected = 0;
    loop {
        if ev.log().len() + n + 1 > settings.max_evaluations {
            return Ok(format!(
                "stopped at the limit of {} evaluations",
                settings.max_evaluations
            ));
        }
        let Some(dx) = step(&current, &widths, lambda) else {
            return Ok(
                "the normal equations are singular: the data do not determine the values".into(),
            );
        };
        let x = &current.at.values;
        let trial: Vec<f64> = x
            .iter()
            .zip(&dx)
            .zip(params)
            .map(|((x, d), p)| (x + d).clamp(p.lo, p.hi))
            .collect();
        let moved = trial
            .iter()
            .zip(x)
            .zip(&widths)
            .map(|((t, x), w)| ((t - x) / w).abs())
            .fold(0.0, f64::max);
        if moved < settings.x_tolerance {
            return Ok(format!(
                "converged: the step moves no value by more than {:.0e} of its range",
                settings.x_tolerance
            ));
        }
        match batch(ev, &trial, settings.fd_step)? {
            Some(next) if sum_squares(&next) < sum_squares(&current) => {
                let fall = 1.0 - sum_squares(&next) / sum_squares(&current);
                current = next;
                rejected = 0;
                lambda = (lambda / 3.0).max(1e-9);
                if fall < settings.f_tolerance {
                    return Ok(format!(
                        "converged: the sum of squares fell by less than {:.0e}",
                        settings.f_tolerance
                    ));
                }
            }
            _ => {
                lambda *= 4.0;
                rejected += 1;
                if rejected >= MAX_REJECTED {
                    return Ok(format!(
                        "{MAX_REJECTED} steps in a row did not lower the sum of squares: the objective's roughness dominates (see the roughness in the report)"
                    ));
                }
                if lambda > 1e8 {
                    return Ok("no step lowers the sum of squares (damping above 1e8)".into());
                }
            }
        }
    }
}
