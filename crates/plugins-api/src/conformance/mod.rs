//! The conformance suite of friction-math §5: every law × every formulation, at point level.
//!
//! [`check_law`] builds a law from its parameter set ([`Subject`]) and drives it
//! through the shared return mapping [`crate::return_mapping::step`] (with
//! [`TangentMode::Consistent`](crate::TangentMode::Consistent)) under each
//! formulation given, along designed and random point histories. No mesh and
//! no tool are involved: the histories prescribe pressure, slip increment,
//! normals and, where a component declares it needs them (§6), flow stress,
//! temperature, velocity gradient, deformation gradient and tool rotation.
//! Quantities nobody declared are left at the neutral values the engine uses
//! (`NaN` for flow stress and temperature, `L = 0`, `F = I`, no tool rotation),
//! so a law that reads data it did not declare fails.
//!
//! The checks, in report order (see [`CHECKS`]):
//!
//! 1. `stick`: from a zero history, a slip increment well below the limit sticks, `t = -k_T Δu_T`.
//! 2. `traction-bound`: `|t| ≤ τ_c(p, ω_{n+1}, ctx)(1 + 1e-12)` after every step.
//! 3. `consistency`: `Φ = |t| - τ_c = 0` (relative 1e-10) in every slipping step.
//! 4. `tangent`: `∂t/∂Δu_T` and `∂t/∂p` against central differences of the step.
//! 5. `dissipation`: `ΔD ≥ 0` in every step.
//! 6. `monotone-work`: `ω` never decreases.
//! 7. `objectivity`: a superposed rigid rotation rotates the tractions (§4).
//! 8. `edge-cases`: the edge cases of §2 give finite, documented answers.
//! 9. `random-histories`: property-based histories with a fixed seed; checks 2, 3, 5, 6 along them.
//! 10. `non-finite-input`: NaN/inf input is an `InvalidInput` error and leaves the state unchanged.
//! 11. `determinism`: the same history twice gives bitwise identical outputs.
//! 12. `parameter-validation`: values just outside a parameter's range (and NaN) are refused
//!     with an error naming the parameter.
//!
//! Checks 2, 3, 5 and 6 are evaluated along the designed reference history and
//! along the random histories together. A panic inside the law (or a
//! formulation) is caught and reported as a failure of the check that was
//! running, with the panic message; the suite itself does not panic. (The
//! process's panic hook still prints the message to stderr.)

mod checks;
mod driver;
mod histories;
#[cfg(test)]
mod tests;

use std::fmt;

use crate::{FrictionError, FrictionLaw, KinematicFormulation, ParamSpec, Params};

/// Names of the checks, in the order of friction-math §5 and of the report.
/// The first eleven run once per formulation; `parameter-validation` once per law.
pub const CHECKS: [&str; 12] = [
    "stick",
    "traction-bound",
    "consistency",
    "tangent",
    "dissipation",
    "monotone-work",
    "objectivity",
    "edge-cases",
    "random-histories",
    "non-finite-input",
    "determinism",
    "parameter-validation",
];

/// A law factory from parameter values, as the suite calls it.
pub type BuildLaw<'a> = dyn Fn(&Params) -> Result<Box<dyn FrictionLaw>, FrictionError> + 'a;

/// The law under test: how to build it, and from which parameters.
pub struct Subject<'a> {
    /// Name for the report, e.g. `wvs` or `plugin exp-decay (libexp_decay.so)`.
    pub name: String,
    /// Parameter schema of the law.
    pub params: &'a [ParamSpec],
    /// Builds the law from user parameter values (defaults fill the rest);
    /// must validate them against [`Subject::params`].
    #[allow(
        clippy::type_complexity,
        reason = "the builder signature of the registry, spelled out for plugin authors"
    )]
    pub build: &'a BuildLaw<'a>,
    /// A valid parameter set for the run (defaults fill the rest).
    pub base: Params,
}

/// Settings of a run of the suite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Seed of the random histories (`rand_chacha::ChaCha8Rng::seed_from_u64`).
    pub seed: u64,
    /// Number of random histories per formulation.
    pub random_histories: usize,
    /// Number of steps of each random history.
    pub steps_per_history: usize,
    /// Relative tolerance of the tangents against central finite differences.
    pub tangent_rel_tol: f64,
}

impl Default for Options {
    /// Seed 20261121, 24 histories of 200 steps, tangent tolerance 1e-5.
    fn default() -> Self {
        Self {
            seed: 20_261_121,
            random_histories: 24,
            steps_per_history: 200,
            tangent_rel_tol: 1e-5,
        }
    }
}

/// The outcome of one check under one formulation.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckResult {
    /// Check name, one of [`CHECKS`].
    pub check: &'static str,
    /// Formulation name; `None` for checks of the law alone (`parameter-validation`).
    pub formulation: Option<String>,
    /// Whether the check passed.
    pub passed: bool,
    /// What was checked and, on failure, the first violation with its values.
    pub detail: String,
}

/// All results of [`check_law`] for one law.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// Name of the law under test ([`Subject::name`]).
    pub subject: String,
    /// One result per check × formulation, in the order of [`CHECKS`].
    pub results: Vec<CheckResult>,
}

impl Report {
    /// Whether every check passed.
    #[must_use]
    pub fn passed(&self) -> bool {
        self.results.iter().all(|r| r.passed)
    }

    /// The failed checks.
    pub fn failures(&self) -> impl Iterator<Item = &CheckResult> {
        self.results.iter().filter(|r| !r.passed)
    }
}

impl fmt::Display for Report {
    /// One line per check × formulation (`PASS`/`FAIL`, check, formulation,
    /// detail), then `N passed, M failed`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let width = self
            .results
            .iter()
            .filter_map(|r| r.formulation.as_ref())
            .map(String::len)
            .max()
            .unwrap_or(0)
            .max(1);
        let rows = self.results.iter().map(|r| {
            let form = r.formulation.as_deref().unwrap_or("-");
            (
                r.passed,
                format!("{:<20} {form:<width$}  {}", r.check, r.detail),
            )
        });
        write_report(
            f,
            &format!(
                "conformance of `{}` (docs/friction-math.md §5)",
                self.subject
            ),
            rows,
        )
    }
}

/// Write a conformance report, of a law or of a material: `title`, one line
/// per result (`PASS`/`FAIL`, then the row's text), then `N passed, M
/// failed`.
pub(crate) fn write_report(
    f: &mut fmt::Formatter<'_>,
    title: &str,
    rows: impl Iterator<Item = (bool, String)>,
) -> fmt::Result {
    writeln!(f, "{title}")?;
    let (mut passed, mut failed) = (0, 0);
    for (ok, row) in rows {
        let status = if ok {
            passed += 1;
            "PASS"
        } else {
            failed += 1;
            "FAIL"
        };
        writeln!(f, "  {status}  {row}")?;
    }
    write!(f, "{passed} passed, {failed} failed")
}

/// Run the conformance suite (friction-math §5) on `subject` under each of
/// `formulations` and return the report. Never panics on a misbehaving law:
/// errors, non-finite results and panics of the law become failed checks.
#[must_use]
pub fn check_law(
    subject: &Subject<'_>,
    formulations: &[&dyn KinematicFormulation],
    options: &Options,
) -> Report {
    let per_law = checks::parameter_validation(subject);
    let per_form: Vec<Vec<CheckResult>> = match checks::LawUnderTest::build(subject) {
        Ok(law) => {
            let suite = checks::Suite::new(&law, options);
            formulations.iter().map(|form| suite.run(*form)).collect()
        }
        Err(reason) => formulations
            .iter()
            .map(|form| {
                CHECKS[..11]
                    .iter()
                    .map(|check| CheckResult {
                        check,
                        formulation: Some(form.name().to_string()),
                        passed: false,
                        detail: format!("not run: {reason}"),
                    })
                    .collect()
            })
            .collect(),
    };
    let mut results = Vec::with_capacity(11 * formulations.len() + 1);
    for i in 0..11 {
        for form_results in &per_form {
            results.push(form_results[i].clone());
        }
    }
    results.push(per_law);
    Report {
        subject: subject.name.clone(),
        results,
    }
}
