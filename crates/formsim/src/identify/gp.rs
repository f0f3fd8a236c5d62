//! A Gaussian-process regression of one scalar on points of the unit box,
//! wrapping `egobox-gp` (docs/identification.md, "Surrogate"): constant
//! mean, Matérn 5/2 correlation with one length scale per input, the
//! hyperparameters by maximum likelihood (egobox's multistart with a fixed
//! seed, so a fit is repeatable).
//!
//! The outputs are standardised here (mean 0, standard deviation 1) before
//! the fit and the predictions brought back to their units; an output that
//! does not vary over the points is a constant with no variance.

use egobox_gp::correlation_models::Matern52Corr;
use egobox_gp::mean_models::LinearMean;
use egobox_gp::{GaussianProcess, GpError};
use linfa::Dataset;
use linfa::traits::Fit;
use ndarray::{Array1, Array2};

/// Outputs whose standard deviation over the points is below this fraction
/// of their largest magnitude (or 1) are treated as constant.
pub const CONSTANT_SPREAD: f64 = 1e-12;

/// Restarts of the likelihood's maximisation (egobox seeds them itself).
pub const LIKELIHOOD_STARTS: usize = 10;

/// A fitted Gaussian process of one output.
#[derive(Debug)]
pub struct Gp {
    model: Model,
    mean: f64,
    sd: f64,
    dims: usize,
}

#[derive(Debug)]
enum Model {
    Fitted(Box<GaussianProcess<f64, LinearMean, Matern52Corr>>),
    Constant,
}

impl Gp {
    /// Fit on `inputs` (points of the unit box, one `Vec` each, all of one
    /// length) and their `outputs`.
    ///
    /// # Errors
    /// Fewer than two points, points of different lengths, a non-finite
    /// value, or egobox's fit fails (its message).
    pub fn fit(inputs: &[Vec<f64>], outputs: &[f64]) -> Result<Self, String> {
        let n = inputs.len();
        let dims = inputs.first().map_or(0, Vec::len);
        if n < 2 || outputs.len() != n || dims == 0 {
            return Err(format!(
                "a surrogate needs at least two points with one output each; got {n} points and {} outputs",
                outputs.len()
            ));
        }
        if inputs.iter().any(|x| x.len() != dims) {
            return Err("the surrogate's points do not all have the same dimension".into());
        }
        if inputs
            .iter()
            .flatten()
            .chain(outputs)
            .any(|v| !v.is_finite())
        {
            return Err("a surrogate's point or output is not a finite number".into());
        }
        let mean = outputs.iter().sum::<f64>() / n as f64;
        let sd = (outputs.iter().map(|y| (y - mean).powi(2)).sum::<f64>() / n as f64).sqrt();
        let magnitude = outputs.iter().fold(1.0_f64, |m, y| m.max(y.abs()));
        if sd <= CONSTANT_SPREAD * magnitude {
            return Ok(Self {
                model: Model::Constant,
                mean,
                sd: 0.0,
                dims,
            });
        }
        let x = Array2::from_shape_fn((n, dims), |(i, j)| inputs[i][j]);
        let y = Array1::from_iter(outputs.iter().map(|v| (v - mean) / sd));
        let model = GaussianProcess::<f64, LinearMean, Matern52Corr>::params(
            LinearMean::default(),
            Matern52Corr::default(),
        )
        .n_start(LIKELIHOOD_STARTS)
        .fit(&Dataset::new(x, y))
        .map_err(|e: GpError| format!("the surrogate's fit failed: {e}"))?;
        Ok(Self {
            model: Model::Fitted(Box::new(model)),
            mean,
            sd,
            dims,
        })
    }

    /// The predictive mean and variance (in the output's units, squared for
    /// the variance) at `u`, a point of the unit box. A prediction that
    /// fails or is not finite gives `(NaN, +∞)`, which every objective
    /// turns into `+∞`.
    pub fn predict(&self, u: &[f64]) -> (f64, f64) {
        let model = match &self.model {
            Model::Constant => return (self.mean, 0.0),
            Model::Fitted(m) => m,
        };
        if u.len() != self.dims {
            return (f64::NAN, f64::INFINITY);
        }
        let x = Array2::from_shape_fn((1, self.dims), |(_, j)| u[j]);
        match model.predict_valvar(&x) {
            Ok((m, v)) if m[0].is_finite() && v[0].is_finite() => (
                self.mean + self.sd * m[0],
                self.sd * self.sd * v[0].max(0.0),
            ),
            _ => (f64::NAN, f64::INFINITY),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A smooth analytic function on [0, 1]: `sin(3u) + u²/2`, range about 1.
    fn f(u: f64) -> f64 {
        (3.0 * u).sin() + 0.5 * u * u
    }

    /// Ten points at the centres of ten equal strata (a 1-D Latin
    /// hypercube, 0.05 to 0.95): between its outer points the Gaussian
    /// process reproduces `f` on a 181-point grid within 1e-3 (0.1 % of its
    /// range); beyond them, where it extrapolates by half a stratum, its
    /// error is within three of its own predictive standard deviations; at
    /// the points it was trained on it predicts a variance below 1e-8 (of an
    /// output variance near 0.1).
    #[test]
    fn gp_recovers_a_smooth_1d_function_from_ten_points() {
        let u: Vec<f64> = (0..10).map(|i| (i as f64 + 0.5) / 10.0).collect();
        let inputs: Vec<Vec<f64>> = u.iter().map(|&v| vec![v]).collect();
        let outputs: Vec<f64> = u.iter().map(|&v| f(v)).collect();
        let gp = Gp::fit(&inputs, &outputs).unwrap();
        let error = |v: f64| (gp.predict(&[v]).0 - f(v)).abs();
        let inside = (10..=190)
            .map(|k| error(k as f64 / 200.0))
            .fold(0.0, f64::max);
        assert!(
            inside < 1e-3,
            "largest error between the outer points {inside:e}"
        );
        for k in (0..10).chain(191..=200) {
            let v = k as f64 / 200.0;
            let sigma = gp.predict(&[v]).1.sqrt();
            assert!(
                error(v) <= 3.0 * sigma,
                "at {v}: error {:e}, σ {sigma:e}",
                error(v)
            );
        }
        for x in &inputs {
            let (m, var) = gp.predict(x);
            assert!((m - f(x[0])).abs() < 1e-6, "at {x:?}: {m} vs {}", f(x[0]));
            assert!(var < 1e-8, "variance {var:e} at training point {x:?}");
        }
        // Between two points the variance is larger than at them.
        let (between, at) = (gp.predict(&[0.5]).1, gp.predict(&[0.55]).1);
        assert!(
            between > at,
            "variance {between:e} between, {at:e} at a point"
        );
    }

    /// A constant output is a constant with no variance; bad input is an
    /// error, not a panic.
    #[test]
    fn gp_handles_a_constant_output_and_refuses_bad_input() {
        let inputs = vec![vec![0.1], vec![0.5], vec![0.9]];
        let gp = Gp::fit(&inputs, &[2.0, 2.0, 2.0]).unwrap();
        assert_eq!(gp.predict(&[0.3]), (2.0, 0.0));
        assert!(Gp::fit(&inputs[..1], &[1.0]).is_err());
        assert!(Gp::fit(&inputs, &[1.0, f64::NAN, 2.0]).is_err());
        assert!(Gp::fit(&[vec![0.1], vec![0.2, 0.3]], &[1.0, 2.0]).is_err());
    }
}
