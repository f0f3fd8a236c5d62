//! A study's reports: `study.json` (every figure) and `study.md` (one table
//! per knob, the recommendation).

use super::{Outcome, Results, StudyError, recommendation};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;

/// `study.json`'s content.
#[derive(Serialize)]
struct Json<'a> {
    scene: &'a str,
    threads: usize,
    repeat: usize,
    tolerance: f64,
    cross: bool,
    sets: &'a [String],
    knobs: Vec<JsonKnob<'a>>,
    quantities: Vec<String>,
    variants: &'a [Outcome],
    failed: &'a [super::Failed],
    recommendation: Option<&'a str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    converged: Option<&'a super::converged::Converged>,
}

#[derive(Serialize)]
struct JsonKnob<'a> {
    key: &'a str,
    values: &'a [String],
    reference: &'a str,
    model: bool,
}

/// Write `study.json` and `study.md` into `out`.
///
/// # Errors
/// A file cannot be written.
pub fn write(out: &Path, results: &Results) -> Result<(), StudyError> {
    let write = |name: &str, text: &str| {
        let path = out.join(name);
        std::fs::write(&path, text).map_err(|source| StudyError::Io { path, source })
    };
    let json = to_json(results)?;
    write("study.json", &json)?;
    write("study.md", &markdown(results))
}

fn to_json(r: &Results) -> Result<String, StudyError> {
    let reference = &r.outcomes[0];
    let doc = Json {
        scene: &r.scene,
        threads: r.threads,
        repeat: r.spec.repeat,
        tolerance: r.spec.tolerance,
        cross: r.spec.cross,
        sets: &r.spec.sets,
        knobs: r
            .spec
            .knobs
            .iter()
            .zip(&reference.settings)
            .map(|(k, (_, v))| JsonKnob {
                key: &k.key,
                values: &k.values,
                reference: v,
                model: k.model,
            })
            .collect(),
        quantities: r.spec.quantities.iter().map(|q| q.name()).collect(),
        variants: &r.outcomes,
        failed: &r.failed,
        recommendation: recommendation(r).map(|o| o.label.as_str()),
        converged: r.converged.as_ref(),
    };
    Ok(serde_json::to_string_pretty(&doc)?)
}

/// A relative error as a percentage with two or three significant digits.
pub fn percent(x: f64) -> String {
    let v = 100.0 * x;
    if v == 0.0 {
        "0 %".into()
    } else if v >= 10.0 {
        format!("{v:.0} %")
    } else if v >= 1.0 {
        format!("{v:.1} %")
    } else if v >= 0.01 {
        format!("{v:.2} %")
    } else {
        format!("{v:.1e} %")
    }
}

fn markdown(r: &Results) -> String {
    let reference = &r.outcomes[0];
    let settings: Vec<String> = reference
        .settings
        .iter()
        .map(|(k, v)| format!("`{k}={v}`"))
        .collect();
    let mut md = format!(
        "# Study of {}: what accuracy costs in time\n\n\
         Reference: {}. Every run on {} worker thread(s), {} round(s) in alternating \
         order, the reference at the start of each round, after every {} variants and at \
         the end. CPU s: process CPU seconds of the whole run (set-up, steps, output; \
         every thread), median over the runs with the fastest and slowest in brackets. \
         Speed-up: per run, the reference's CPU time at that moment (interpolated between \
         its runs, so that a slow spell of the machine slows both) over the run's; median \
         (smallest–largest). A variant is cheaper only when every run was. Errors are \
         relative to {against}: a number's `|v − v_ref| / |v_ref|`, a curve's RMS \
         difference at the reference's points over the reference curve's largest \
         magnitude (the max norm is in `study.json`). K/W max: the largest kinetic energy \
         over the external work of the run (quasi-static below 0.05). Tolerance: {}.\n\n",
        r.scene,
        settings.join(", "),
        r.threads,
        r.spec.repeat,
        super::schedule::REFERENCE_EVERY,
        percent(r.spec.tolerance),
        against = if r.converged.is_some() {
            "the converged answer (below; the reference's own error too)"
        } else {
            "the reference"
        },
    );
    if !r.spec.sets.is_empty() {
        let _ = writeln!(
            md,
            "Every run also with `--set {}`.\n",
            r.spec.sets.join("` `--set ")
        );
    }
    md.push_str("## The reference\n\n| quantity | value |\n|---|---|\n");
    for (q, v) in r.spec.quantities.iter().zip(&reference.values) {
        let shown = v.map_or_else(|| "(curve)".into(), |x| format!("{x:.6}"));
        let _ = writeln!(md, "| `{}` | {shown} |", q.name());
    }
    let _ = writeln!(
        md,
        "\n{} increments, {:.2} CPU s ({:.2}–{:.2}), {:.2} wall s, energy balance error {:.1e}.\n",
        reference.increments,
        reference.cpu_s.median,
        reference.cpu_s.min,
        reference.cpu_s.max,
        reference.wall_s.median,
        reference.balance_error
    );
    if let Some(c) = &r.converged {
        converged_section(&mut md, r, c);
    }
    if r.spec.cross {
        md.push_str("## Every combination\n\n");
        table(&mut md, r, None, |_| true);
    } else {
        for (k, knob) in r.spec.knobs.iter().enumerate() {
            let _ = writeln!(md, "## `{}`\n", knob.key);
            if knob.model {
                md.push_str(
                    "A model, not an accuracy knob: its \"errors\" are the differences \
                     between models. It takes no part in the combination, the recommendation \
                     or the Pareto front.\n\n",
                );
            }
            table(&mut md, r, Some(k), |o| {
                o.level.is_none()
                    && (o.changed.is_empty() || (o.changed.len() == 1 && o.changed[0] == knob.key))
            });
        }
        if r.outcomes.iter().any(|o| o.label == super::COMBINED) {
            md.push_str(
                "## Combined\n\nEach knob at its cheapest value within the tolerance, run together \
                 (errors do not simply add).\n\n",
            );
            table(&mut md, r, None, |o| {
                o.changed.is_empty() || o.label == super::COMBINED
            });
        }
    }
    if !r.failed.is_empty() {
        md.push_str("## Failed\n\n");
        for f in &r.failed {
            let _ = writeln!(md, "- `{}`: {}", f.label, f.message);
        }
        md.push('\n');
    }
    let warned: Vec<&Outcome> = r
        .outcomes
        .iter()
        .filter(|o| !o.warnings.is_empty())
        .collect();
    let sequence = r
        .converged
        .as_ref()
        .map(|c| c.warnings(r.spec.tolerance))
        .unwrap_or_default();
    if !warned.is_empty() || !sequence.is_empty() {
        md.push_str("## Warnings\n\n");
        for w in &sequence {
            let _ = writeln!(md, "- the converged answer: {w}");
        }
        for o in warned {
            for w in &o.warnings {
                let _ = writeln!(md, "- `{}`: {w}", o.label);
            }
        }
        md.push('\n');
    }
    md.push_str("## Recommendation\n\n");
    md.push_str(&recommend(r));
    md
}

/// One table: rows are the outcomes `keep` selects; with `knob`, the first
/// column is that knob's value, otherwise the variant's label.
fn table(md: &mut String, r: &Results, knob: Option<usize>, keep: impl Fn(&Outcome) -> bool) {
    md.push_str(if knob.is_some() {
        "| value |"
    } else {
        "| variant |"
    });
    for q in &r.spec.quantities {
        let _ = write!(md, " `{}` |", q.name());
    }
    md.push_str(" worst | increments | CPU s | wall s | speed-up | K/W max | balance |\n|");
    for _ in 0..r.spec.quantities.len() + 8 {
        md.push_str("---|");
    }
    md.push('\n');
    for o in r.outcomes.iter().filter(|o| keep(o)) {
        let name = match knob {
            Some(k) => o.settings[k].1.clone(),
            None => o.label.clone(),
        };
        let is_ref = o.changed.is_empty();
        let name = if is_ref {
            format!("**{name}** (ref.)")
        } else {
            name
        };
        let _ = write!(md, "| {name} |");
        for e in &o.errors {
            let _ = write!(
                md,
                " {} |",
                e.map_or_else(|| "–".into(), |e| percent(e.error))
            );
        }
        let within = if is_ref && r.converged.is_none() {
            String::from("–")
        } else if o.worst <= r.spec.tolerance {
            percent(o.worst)
        } else {
            format!("**{}**", percent(o.worst))
        };
        let _ = writeln!(
            md,
            " {within} | {} | {:.2} ({:.2}–{:.2}) | {:.2} | {:.2} ({:.2}–{:.2}) | {:.3} | {:.1e} |",
            o.increments,
            o.cpu_s.median,
            o.cpu_s.min,
            o.cpu_s.max,
            o.wall_s.median,
            o.speed_up.median,
            o.speed_up.min,
            o.speed_up.max,
            o.kinetic_to_work_max,
            o.balance_error
        );
    }
    md.push('\n');
}

/// The refinement sequence's levels and each quantity's converged answer.
fn converged_section(md: &mut String, r: &Results, c: &super::converged::Converged) {
    let _ = write!(
        md,
        "## The converged answer\n\nA refinement sequence of {} levels (`{}`, {}), each \
         refined by {} over the last, the other knobs at the reference. Each quantity is \
         extrapolated from the last three levels (Richardson: observed order `p`, \
         `f∞ = f₃ + (f₃ − f₂)/(r^p − 1)`), its uncertainty the grid convergence index \
         `1.25 |f₃ − f₂|/(r^p − 1)`; where the levels oscillate or `p` is outside [0.5, 4] \
         (or, with four levels, the orders of the coarser and finer triples differ by more \
         than 25 %), the finest level is taken with `3 ×` the levels' spread. Curves are \
         extrapolated point by point at the finest level's points.\n\n\
         | quantity |",
        c.levels.len(),
        c.keys.join("`, `"),
        c.levels.join(", "),
        c.ratio,
    );
    for l in &c.levels {
        let _ = write!(md, " {l} |");
    }
    md.push_str(" p | converged | uncertainty | |\n|");
    for _ in 0..c.levels.len() + 5 {
        md.push_str("---|");
    }
    md.push('\n');
    for q in &c.quantities {
        let _ = write!(md, "| `{}` |", q.name);
        for v in &q.levels {
            let _ = write!(
                md,
                " {} |",
                v.map_or_else(|| "(curve)".into(), |x| format!("{x:.6}"))
            );
        }
        let p = q.estimate.and_then(|e| e.order);
        let note = match (&q.not_asymptotic, q.points_extrapolated) {
            (Some(why), _) => format!("not extrapolated: {why}"),
            (None, Some((done, all))) => format!("{done} of {all} points extrapolated"),
            (None, None) => String::new(),
        };
        let _ = writeln!(
            md,
            " {} | {} | {} | {note} |",
            p.map_or_else(|| "–".into(), |p| format!("{p:.2}")),
            q.estimate
                .map_or_else(|| "(curve)".into(), |e| format!("{:.6}", e.value)),
            percent(q.relative_uncertainty),
        );
    }
    md.push_str("\nThe levels' runs, against the converged answer:\n\n");
    table(md, r, None, |o| o.level.is_some() || o.changed.is_empty());
}

fn recommend(r: &Results) -> String {
    let tol = percent(r.spec.tolerance);
    match recommendation(r) {
        None => format!(
            "No variant within {tol} on every quantity is cheaper than the reference: keep it.\n"
        ),
        Some(o) => {
            let (worst_q, _) = r
                .spec
                .quantities
                .iter()
                .zip(&o.errors)
                .filter_map(|(q, e)| e.map(|e| (q, e.error)))
                .fold(
                    (None, -1.0),
                    |acc, (q, e)| if e > acc.1 { (Some(q), e) } else { acc },
                );
            let changed: Vec<String> = o
                .settings
                .iter()
                .filter(|(k, _)| o.changed.contains(k))
                .map(|(k, v)| format!("`{k}={v}`"))
                .collect();
            format!(
                "The cheapest variant within {tol} on every quantity: **`{}`** ({}), \
                 **{:.2} times faster** than the reference (every run faster: {:.2} to {:.2} \
                 times), its largest error {} (on `{}`).\n",
                o.label,
                changed.join(", "),
                o.speed_up.median,
                o.speed_up.min,
                o.speed_up.max,
                percent(o.worst),
                worst_q.map_or_else(String::new, |q| q.name())
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::percent;

    #[test]
    fn percentages_keep_two_or_three_digits() {
        assert_eq!(percent(0.0), "0 %");
        assert_eq!(percent(0.1234), "12 %");
        assert_eq!(percent(0.01234), "1.2 %");
        assert_eq!(percent(0.001234), "0.12 %");
        assert_eq!(percent(1.234e-6), "1.2e-4 %");
    }
}
