//! `--method surrogate` (docs/identification.md, "Surrogate"): a Latin
//! hypercube sweep of the fitted values over their bounds, run as one
//! parallel batch; a Gaussian process ([`super::gp`]) of every measured
//! quantity over the sweep; the objective minimised on the processes
//! (their predictive variance added for `wls`), from the best sweep
//! points; then
//! the check run at the optimum, its Jacobian and the roughness probes as
//! one batch (the uncertainty the other methods take at their end).

use super::evaluate::{Evaluation, Evaluator};
use super::gp::Gp;
use super::lhs::latin_hypercube;
use super::objective::{Objective, scale};
use super::uncertainty::Uncertainty;
use super::{IdentifyError, Options, ROUGHNESS_PROBES, at_optimum, best};
use argmin::core::{CostFunction, Executor};
use argmin::solver::neldermead::NelderMead;
use serde::Serialize;
use std::time::Instant;

/// Largest `--samples`: each quantity's fit costs `O(N³)`, and a sweep
/// this large costs more runs than any direct method.
pub const MAX_SAMPLES: usize = 1000;

/// Sweep points that start the surrogate's minimisation (the best ones).
pub const STARTS: usize = 5;

/// Nelder–Mead's first simplex on the surrogate: each value moved by this
/// fraction of its range, inwards.
pub const SIMPLEX_STEP: f64 = 0.05;

/// Nelder–Mead's iterations on the surrogate, per start.
pub const SURROGATE_ITERATIONS: u64 = 2000;

/// The default sweep for `n` fitted values: `10 n` points, the rule of
/// Loeppky, Sacks and Welch (Technometrics 51) for a Gaussian
/// process of a computer model.
pub fn default_samples(n: usize) -> usize {
    10 * n
}

/// The fewest sweep points for `n` fitted values: more than the `2n + 2`
/// values each process's likelihood fits (`n` length scales, the linear
/// mean's `n + 1` coefficients and the variance).
pub fn min_samples(n: usize) -> usize {
    2 * n + 3
}

/// The evaluations the surrogate asks for: the sweep, then the check, the
/// Jacobian's `n` points and the roughness probes.
pub fn evaluations(options: &Options) -> usize {
    let n = options.params.len();
    options.samples.unwrap_or_else(|| default_samples(n)) + 1 + n + ROUGHNESS_PROBES
}

/// Check `--samples` for `n` fitted values.
///
/// # Errors
/// Below [`min_samples`] or above [`MAX_SAMPLES`].
pub fn check_samples(samples: usize, n: usize) -> Result<(), IdentifyError> {
    if samples < min_samples(n) || samples > MAX_SAMPLES {
        return Err(IdentifyError::Option(format!(
            "--samples {samples}: must be from {} (for {n} fitted value{}) to {MAX_SAMPLES} sweep points",
            min_samples(n),
            if n == 1 { "" } else { "s" }
        )));
    }
    Ok(())
}

/// The surrogate's figures in the report.
#[derive(Debug, Clone, Serialize)]
pub struct SurrogateFigures {
    /// Sweep points asked for (`--samples`).
    pub samples: usize,
    /// Sweep points whose runs all succeeded (the processes' training points).
    pub samples_used: usize,
    /// Gaussian processes fitted (one per measured value).
    pub quantities: usize,
    /// Starts of the minimisation on the surrogate.
    pub starts: usize,
    /// The best sweep point's objective (full runs).
    pub objective_best_sample: f64,
    /// The surrogate's objective at its optimum (with its variance).
    pub objective_surrogate: f64,
    /// The check run's objective at the surrogate's optimum.
    pub objective_check: Option<f64>,
    /// Largest `|surrogate mean − check run|` over the measured values, as
    /// a fraction of each value's scale (`|measured|`).
    pub check_max_relative_error: Option<f64>,
    /// Largest `|surrogate mean − check run| / σ_gp` over the measured values.
    pub check_max_error_in_sigma: Option<f64>,
    /// Largest surrogate `σ_gp` at the optimum, as a fraction of each value's scale.
    pub sigma_max_relative: f64,
    /// Runs made by this call for the sweep.
    pub sweep_runs: usize,
    /// Runs made by this call at the optimum (check run, Jacobian and probes).
    pub optimum_runs: usize,
    /// Points of the batch at the optimum: the check, `n` Jacobian points
    /// and the roughness probes.
    pub optimum_points: usize,
    /// Wall seconds of the sweep.
    pub sweep_wall_s: f64,
    /// Wall seconds of the processes' fits and the minimisation on them.
    pub surrogate_wall_s: f64,
    /// Wall seconds of the batch at the optimum.
    pub optimum_wall_s: f64,
}

/// What the surrogate method hands to the report.
#[derive(Debug)]
pub struct Outcome {
    /// The best sweep point (the start of the inversion).
    pub first: Evaluation,
    /// The check run at the surrogate's optimum (or the best run, if it failed).
    pub end: Evaluation,
    /// What happened, in a sentence.
    pub stop: String,
    /// The uncertainty at the optimum.
    pub uncertainty: Result<Uncertainty, IdentifyError>,
    /// The figures.
    pub figures: SurrogateFigures,
}

/// One process per measured value, in data-set and point order.
struct Surrogate<'a> {
    ev: &'a Evaluator<'a>,
    gps: Vec<Vec<Gp>>,
}

impl Surrogate<'_> {
    /// The objective on the surrogate at `x` (the fitted values): `wls`
    /// with the variance `se² + σ_gp²`; `mae` on the processes' means
    /// (docs/identification.md, "Surrogate", says why not the absolute
    /// error's expectation over the predictive distribution).
    fn cost(&self, x: &[f64]) -> f64 {
        let u: Vec<f64> = self
            .ev
            .params()
            .iter()
            .zip(x)
            .map(|(p, v)| p.to_unit(*v))
            .collect();
        let data = self.ev.data();
        let mut total = 0.0;
        let mut sets_used = 0usize;
        for (set, gps) in data.sets.iter().zip(&self.gps) {
            if set.points.is_empty() {
                continue;
            }
            let mut sum = 0.0;
            for (point, gp) in set.points.iter().zip(gps) {
                let (mean, var) = gp.predict(&u);
                let d = mean - point.value;
                sum += match self.ev.objective() {
                    Objective::Wls => {
                        let se = point.se.unwrap_or(f64::NAN);
                        d * d / (se * se + var)
                    }
                    Objective::Mae => d.abs() / scale(point),
                };
            }
            match self.ev.objective() {
                Objective::Wls => total += sum,
                Objective::Mae => {
                    total += sum / set.points.len() as f64;
                    sets_used += 1;
                }
            }
        }
        let value = match self.ev.objective() {
            Objective::Mae => total / sets_used.max(1) as f64,
            Objective::Wls => total,
        };
        if value.is_finite() {
            value
        } else {
            f64::INFINITY
        }
    }
}

/// Nelder–Mead on the surrogate, in free variables (bounded as
/// [`super::params::FitParam::from_free`]).
struct OnSurrogate<'s, 'a> {
    surrogate: &'s Surrogate<'a>,
}

impl CostFunction for OnSurrogate<'_, '_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, z: &Vec<f64>) -> Result<f64, argmin::core::Error> {
        let x: Vec<f64> = self
            .surrogate
            .ev
            .params()
            .iter()
            .zip(z)
            .map(|(p, z)| p.from_free(*z))
            .collect();
        Ok(self.surrogate.cost(&x))
    }
}

/// Fit one process per measured value on the successful sweep points.
fn fit(ev: &Evaluator<'_>, sweep: &[&Evaluation]) -> Result<Vec<Vec<Gp>>, IdentifyError> {
    let inputs: Vec<Vec<f64>> = sweep
        .iter()
        .map(|e| {
            ev.params()
                .iter()
                .zip(&e.values)
                .map(|(p, v)| p.to_unit(*v))
                .collect()
        })
        .collect();
    let mut gps = Vec::new();
    for (s, set) in ev.data().sets.iter().enumerate() {
        let mut of_set = Vec::new();
        for (i, point) in set.points.iter().enumerate() {
            let outputs: Vec<f64> = sweep
                .iter()
                .map(|e| e.predictions[s].as_ref().map_or(f64::NAN, |p| p[i]))
                .collect();
            let gp = Gp::fit(&inputs, &outputs).map_err(|why| {
                IdentifyError::Evaluation(format!(
                    "set {}: {} (line {}): {why}",
                    set.name,
                    point.label(),
                    point.line
                ))
            })?;
            of_set.push(gp);
        }
        gps.push(of_set);
    }
    Ok(gps)
}

/// The minimum of the surrogate from `start`: (values, surrogate objective).
fn minimise_from(surrogate: &Surrogate<'_>, start: &[f64]) -> (Vec<f64>, f64) {
    let params = surrogate.ev.params();
    let z0: Vec<f64> = params
        .iter()
        .zip(start)
        .map(|(p, x)| p.to_free(*x))
        .collect();
    let mut simplex = vec![z0.clone()];
    for (j, p) in params.iter().enumerate() {
        let u = p.to_unit(start[j]);
        let moved = if u + SIMPLEX_STEP <= 1.0 {
            u + SIMPLEX_STEP
        } else {
            u - SIMPLEX_STEP
        };
        let mut z = z0.clone();
        z[j] = p.to_free(p.from_unit(moved));
        simplex.push(z);
    }
    let fallback = (start.to_vec(), surrogate.cost(start));
    let Ok(solver) = NelderMead::new(simplex).with_sd_tolerance(1e-12) else {
        return fallback;
    };
    let outcome = Executor::new(OnSurrogate { surrogate }, solver)
        .configure(|state| state.max_iters(SURROGATE_ITERATIONS))
        .run();
    match outcome {
        Ok(result) => {
            let state = result.state();
            match &state.best_param {
                Some(z) if state.best_cost < fallback.1 => (
                    params.iter().zip(z).map(|(p, z)| p.from_free(*z)).collect(),
                    state.best_cost,
                ),
                _ => fallback,
            }
        }
        Err(_) => fallback,
    }
}

/// Identify by the surrogate: sweep, fit, minimise, check.
///
/// # Errors
/// Fewer successful sweep points than [`min_samples`]; a process cannot be
/// fitted; the journal cannot be written.
pub fn identify(options: &Options, ev: &Evaluator<'_>) -> Result<Outcome, IdentifyError> {
    let n = ev.params().len();
    let samples = options.samples.unwrap_or_else(|| default_samples(n));
    check_samples(samples, n)?;
    // The sweep, one batch.
    let started = Instant::now();
    let runs_before = ev.runs_made();
    let points: Vec<Vec<f64>> = latin_hypercube(samples, n)
        .into_iter()
        .map(|u| {
            ev.params()
                .iter()
                .zip(u)
                .map(|(p, u)| p.from_unit(u))
                .collect()
        })
        .collect();
    let sweep = ev.evaluate_batch(&points)?;
    let sweep_runs = ev.runs_made() - runs_before;
    let sweep_wall_s = started.elapsed().as_secs_f64();
    let used: Vec<&Evaluation> = sweep.iter().filter(|e| e.cost.is_finite()).collect();
    if used.len() < min_samples(n) {
        let why = sweep
            .iter()
            .find_map(|e| e.failure())
            .map_or_else(String::new, |f| format!("; the first failure: {f}"));
        return Err(IdentifyError::Evaluation(format!(
            "only {} of {samples} sweep points ran; the surrogate needs {}{why}",
            used.len(),
            min_samples(n)
        )));
    }
    // The processes and the minimisation on them.
    let started = Instant::now();
    let surrogate = Surrogate {
        ev,
        gps: fit(ev, &used)?,
    };
    let mut ranked = used.clone();
    ranked.sort_by(|a, b| a.cost.total_cmp(&b.cost).then(a.index.cmp(&b.index)));
    let starts = ranked.len().min(STARTS);
    let mut optimum = (ranked[0].values.clone(), f64::INFINITY);
    for start in &ranked[..starts] {
        let found = minimise_from(&surrogate, &start.values);
        if found.1 < optimum.1 {
            optimum = found;
        }
    }
    let surrogate_wall_s = started.elapsed().as_secs_f64();
    // The check run, the Jacobian and the probes: one batch.
    let started = Instant::now();
    let runs_before = ev.runs_made();
    let x = optimum.0.clone();
    let uncertainty = at_optimum(ev, &x, options.fd_step, ev.data().all_have_se());
    let check = match ev.log().iter().rev().find(|e| e.values == x).cloned() {
        Some(e) => e,
        None => ev.evaluate(&x)?,
    };
    let optimum_runs = ev.runs_made() - runs_before;
    let optimum_wall_s = started.elapsed().as_secs_f64();
    let figures = figures(
        &surrogate,
        &check,
        Figures {
            samples,
            samples_used: used.len(),
            starts,
            objective_best_sample: ranked[0].cost,
            objective_surrogate: optimum.1,
            sweep_runs,
            optimum_runs,
            optimum_points: 1 + n + ROUGHNESS_PROBES,
            sweep_wall_s,
            surrogate_wall_s,
            optimum_wall_s,
        },
    );
    let first = ranked[0].clone();
    let (end, stop) = if check.cost.is_finite() {
        (
            check,
            format!(
                "surrogate of {} sweep points minimised from {starts} starts; objective {:.6} on the surrogate, {:.6} by the check run",
                used.len(),
                optimum.1,
                figures.objective_check.unwrap_or(f64::NAN)
            ),
        )
    } else {
        let log = ev.log();
        let fallback = best(&log).cloned().unwrap_or_else(|| first.clone());
        (
            fallback,
            format!(
                "the check run at the surrogate's optimum {x:?} failed ({}); the best run is reported",
                check
                    .failure()
                    .map_or_else(|| "unknown".to_string(), ToString::to_string)
            ),
        )
    };
    Ok(Outcome {
        first,
        end,
        stop,
        uncertainty,
        figures,
    })
}

/// The figures known before the check.
struct Figures {
    samples: usize,
    samples_used: usize,
    starts: usize,
    objective_best_sample: f64,
    objective_surrogate: f64,
    sweep_runs: usize,
    optimum_runs: usize,
    optimum_points: usize,
    sweep_wall_s: f64,
    surrogate_wall_s: f64,
    optimum_wall_s: f64,
}

/// The surrogate against the check run at its optimum.
fn figures(surrogate: &Surrogate<'_>, check: &Evaluation, f: Figures) -> SurrogateFigures {
    let ev = surrogate.ev;
    let u: Vec<f64> = ev
        .params()
        .iter()
        .zip(&check.values)
        .map(|(p, v)| p.to_unit(*v))
        .collect();
    let mut relative: Option<f64> = Some(0.0);
    let mut in_sigma: Option<f64> = Some(0.0);
    let mut sigma_max_relative = 0.0_f64;
    for (s, set) in ev.data().sets.iter().enumerate() {
        let run = check.predictions[s].as_ref().ok();
        for (i, point) in set.points.iter().enumerate() {
            let (mean, var) = surrogate.gps[s][i].predict(&u);
            let sigma = var.sqrt();
            sigma_max_relative = sigma_max_relative.max(sigma / scale(point));
            match run {
                Some(p) => {
                    let e = (mean - p[i]).abs();
                    relative = relative.map(|r| r.max(e / scale(point)));
                    in_sigma = in_sigma.map(|r| {
                        r.max(if sigma > 0.0 {
                            e / sigma
                        } else if e == 0.0 {
                            0.0
                        } else {
                            f64::INFINITY
                        })
                    });
                }
                None => {
                    relative = None;
                    in_sigma = None;
                }
            }
        }
    }
    SurrogateFigures {
        samples: f.samples,
        samples_used: f.samples_used,
        quantities: surrogate.gps.iter().map(Vec::len).sum(),
        starts: f.starts,
        objective_best_sample: f.objective_best_sample,
        objective_surrogate: f.objective_surrogate,
        objective_check: check.cost.is_finite().then_some(check.cost),
        check_max_relative_error: relative,
        check_max_error_in_sigma: in_sigma.filter(|v| v.is_finite()),
        sigma_max_relative,
        sweep_runs: f.sweep_runs,
        optimum_runs: f.optimum_runs,
        optimum_points: f.optimum_points,
        sweep_wall_s: f.sweep_wall_s,
        surrogate_wall_s: f.surrogate_wall_s,
        optimum_wall_s: f.optimum_wall_s,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_are_checked_with_one_line() {
        assert_eq!(default_samples(1), 10);
        assert!(check_samples(10, 1).is_ok());
        assert_eq!(min_samples(1), 5);
        for (samples, n) in [(4, 1), (8, 3), (1001, 1)] {
            let e = check_samples(samples, n).unwrap_err().to_string();
            assert!(
                e.contains(&format!("--samples {samples}")) && !e.contains('\n'),
                "{e}"
            );
        }
    }
}
