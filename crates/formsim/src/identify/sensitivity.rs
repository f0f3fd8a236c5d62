//! Normalised finite-difference sensitivities (the thesis's §4.6.1 table):
//! for each value `x_j` and each measured quantity `q_i` (and the objective
//! `f`), `S = (Δq/q) / (Δx/x)`, the per cent change of `q` for a 1 % change
//! of `x` (for a value at zero, `Δx` is taken relative to its range). Each is
//! computed with two forward steps, `h` and `h/2`, and reported with both, so
//! that the reader sees whether the step is in the linear range.

use super::IdentifyError;
use super::evaluate::Evaluator;
use serde::Serialize;

/// Two sensitivities agree when they differ by at most this fraction of the
/// larger, or both are below [`NEGLIGIBLE`].
pub const AGREEMENT: f64 = 0.1;
/// A sensitivity below this (|%/%|) is negligible.
pub const NEGLIGIBLE: f64 = 0.01;

/// One row: a quantity's sensitivities to every value, at both steps.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    /// Data set.
    pub set: String,
    /// The quantity (`objective` for the objective).
    pub quantity: String,
    /// Its value at the point.
    pub value: f64,
    /// `[S(h), S(h/2)]` for each fitted value.
    pub sensitivity: Vec<[f64; 2]>,
    /// Whether the two steps agree, for each value.
    pub agree: Vec<bool>,
}

/// The sensitivity table at a point.
#[derive(Debug, Clone, Serialize)]
pub struct Table {
    /// The fitted keys.
    pub keys: Vec<String>,
    /// The point.
    pub at: Vec<f64>,
    /// The larger step of each value (the other is half of it).
    pub steps: Vec<f64>,
    /// The relative step asked for.
    pub relative_step: f64,
    /// The objective's row first, then every measured quantity.
    pub rows: Vec<Row>,
    /// Runs made for it (the others came from the journal).
    pub runs: usize,
}

fn agree(a: f64, b: f64) -> bool {
    (a.abs() < NEGLIGIBLE && b.abs() < NEGLIGIBLE)
        || (a - b).abs() <= AGREEMENT * a.abs().max(b.abs())
}

/// The table at `x` with relative step `relative` (`h = relative·|x|`, or
/// `relative·range` at zero; negative where `x + h` would leave the range).
///
/// # Errors
/// A run failed; the journal cannot be written.
pub fn table(ev: &Evaluator<'_>, x: &[f64], relative: f64) -> Result<Table, IdentifyError> {
    let params = ev.params();
    let mut points = vec![x.to_vec()];
    let mut steps = Vec::new();
    let mut norms = Vec::new();
    for (j, p) in params.iter().enumerate() {
        let norm = if x[j] != 0.0 { x[j].abs() } else { p.width() };
        let mut h = relative * norm;
        if x[j] + h > p.hi {
            h = -h;
        }
        steps.push(h);
        norms.push(norm);
        for factor in [1.0, 0.5] {
            let mut q = x.to_vec();
            q[j] += factor * h;
            points.push(q);
        }
    }
    let before = ev.runs_made();
    let evaluations = ev.evaluate_batch(&points)?;
    if let Some(e) = evaluations.iter().find(|e| e.failure().is_some()) {
        return Err(IdentifyError::Evaluation(format!(
            "sensitivity: the run at {:?} failed: {}",
            e.values,
            e.failure().map(ToString::to_string).unwrap_or_default()
        )));
    }
    let flat = |k: usize| -> Vec<f64> {
        let e = &evaluations[k];
        let mut v = vec![e.cost];
        for p in e.predictions.iter().flatten() {
            v.extend(p);
        }
        v
    };
    let base = flat(0);
    let mut labels = vec![("".to_string(), "objective".to_string())];
    for set in &ev.data().sets {
        labels.extend(set.points.iter().map(|p| (set.name.clone(), p.label())));
    }
    let mut rows: Vec<Row> = labels
        .into_iter()
        .zip(&base)
        .map(|((set, quantity), value)| Row {
            set,
            quantity,
            value: *value,
            sensitivity: Vec::new(),
            agree: Vec::new(),
        })
        .collect();
    for j in 0..params.len() {
        let full = flat(1 + 2 * j);
        let half = flat(2 + 2 * j);
        for (i, row) in rows.iter_mut().enumerate() {
            let s = |q: f64, factor: f64| {
                let dq = (q - base[i]) / base[i].abs().max(f64::MIN_POSITIVE);
                100.0 * dq / (100.0 * factor * steps[j] / norms[j])
            };
            let pair = [s(full[i], 1.0), s(half[i], 0.5)];
            row.agree.push(agree(pair[0], pair[1]));
            row.sensitivity.push(pair);
        }
    }
    Ok(Table {
        keys: params.iter().map(|p| p.key.clone()).collect(),
        at: x.to_vec(),
        steps,
        relative_step: relative,
        rows,
        runs: ev.runs_made() - before,
    })
}
