//! Finite-difference Jacobians of the least-squares residuals
//! ([`super::objective::residuals`]) with respect to the fitted values.

use super::IdentifyError;
use super::evaluate::{Evaluation, Evaluator};
use super::objective::residuals;
use nalgebra::DMatrix;

/// A Jacobian and the evaluation it was taken at.
#[derive(Debug, Clone)]
pub struct Jacobian {
    /// The evaluation at the point.
    pub at: Evaluation,
    /// The step of each value (signed: towards the inside of its range).
    pub steps: Vec<f64>,
    /// `∂r_i/∂x_j`, residuals by rows, values by columns (per unit of each value).
    pub matrix: DMatrix<f64>,
    /// The residuals at the point.
    pub residuals: Vec<f64>,
}

/// The points of a forward-difference Jacobian at `x`: `x` itself, then `x`
/// moved by `fraction` of each range, towards the inside.
pub fn stencil(ev: &Evaluator<'_>, x: &[f64], fraction: f64) -> (Vec<Vec<f64>>, Vec<f64>) {
    let mut points = vec![x.to_vec()];
    let mut steps = Vec::new();
    for (j, p) in ev.params().iter().enumerate() {
        let mut h = fraction * p.width();
        if x[j] + h > p.hi {
            h = -h;
        }
        let mut q = x.to_vec();
        q[j] += h;
        steps.push(q[j] - x[j]);
        points.push(q);
    }
    (points, steps)
}

/// Assemble the Jacobian from the evaluations of [`stencil`]'s points.
///
/// # Errors
/// A run of the stencil failed.
pub fn from_stencil(
    ev: &Evaluator<'_>,
    evaluations: &[Evaluation],
    steps: &[f64],
) -> Result<Jacobian, IdentifyError> {
    let predictions = |e: &Evaluation| -> Result<Vec<Vec<f64>>, IdentifyError> {
        e.predictions
            .iter()
            .map(|p| {
                p.clone().map_err(|m| {
                    IdentifyError::Evaluation(format!(
                        "evaluation {} at {:?}: {m}",
                        e.index, e.values
                    ))
                })
            })
            .collect()
    };
    let base = residuals(ev.data(), &predictions(&evaluations[0])?);
    let mut matrix = DMatrix::zeros(base.len(), steps.len());
    for (j, h) in steps.iter().enumerate() {
        let r = residuals(ev.data(), &predictions(&evaluations[j + 1])?);
        for i in 0..base.len() {
            matrix[(i, j)] = (r[i] - base[i]) / h;
        }
    }
    Ok(Jacobian {
        at: evaluations[0].clone(),
        steps: steps.to_vec(),
        matrix,
        residuals: base,
    })
}

/// The forward-difference Jacobian at `x` with steps of `fraction` of each
/// range, its `n + 1` runs as one parallel batch.
///
/// # Errors
/// A run failed; the journal cannot be written.
pub fn jacobian(ev: &Evaluator<'_>, x: &[f64], fraction: f64) -> Result<Jacobian, IdentifyError> {
    let (points, steps) = stencil(ev, x, fraction);
    let evaluations = ev.evaluate_batch(&points)?;
    from_stencil(ev, &evaluations, &steps)
}
