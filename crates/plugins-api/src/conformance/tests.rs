//! Tests of the conformance suite with laws and formulations defined here (no built-ins).
//!
//! Source of every property: docs/friction-math.md §2 (return mapping), §4
//! (formulations, objectivity) and §5 (the suite). The good laws must pass every
//! check under both test formulations; each broken law must fail the checks that
//! its defect concerns, with a readable detail, and the suite must never panic.

use std::time::Instant;

use super::*;
use crate::kinematics::rotate_minimal;
use crate::{CriticalShear, DirectionInputs, ShearInputs, StepKinematics, Vec3};

/// What a test law computes.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    /// Amontons–Coulomb `τ_c = μ p` (friction-math §3, eq. 2.13).
    Coulomb,
    /// Work softening `τ_c = max(a0 + a1 ω, 0) p` (§3 WH with `μ_min = 0`).
    Softening,
    /// Coulomb with a wrong `∂τ_c/∂p` (1.5 μ).
    WrongDtauDp,
    /// Coulomb that returns NaN above 300 MPa.
    NanAbove300,
    /// Work softening without the clamp: `τ_c` goes negative.
    Unclamped,
    /// Coulomb that panics above 400 MPa.
    PanicAbove400,
}

/// A test law: one struct, its behaviour chosen by [`Kind`].
struct TestLaw {
    kind: Kind,
    a0: f64,
    a1: f64,
    k_t: f64,
}

impl FrictionLaw for TestLaw {
    fn name(&self) -> &str {
        "test-law"
    }
    fn stick_stiffness(&self) -> f64 {
        self.k_t
    }
    fn work_dependent(&self) -> bool {
        matches!(self.kind, Kind::Softening | Kind::Unclamped)
    }
    fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
        let p = x.p;
        let mu = self.a0;
        match self.kind {
            Kind::Coulomb => CriticalShear {
                tau: mu * p,
                dtau_dp: mu,
                ..Default::default()
            },
            Kind::WrongDtauDp => CriticalShear {
                tau: mu * p,
                dtau_dp: 1.5 * mu,
                ..Default::default()
            },
            Kind::NanAbove300 => {
                let tau = if p > 300.0 { f64::NAN } else { mu * p };
                CriticalShear {
                    tau,
                    dtau_dp: mu,
                    ..Default::default()
                }
            }
            Kind::PanicAbove400 => {
                assert!(p <= 400.0, "test law exploded at p = {p} MPa");
                CriticalShear {
                    tau: mu * p,
                    dtau_dp: mu,
                    ..Default::default()
                }
            }
            Kind::Softening => {
                let m = self.a0 + self.a1 * x.omega;
                if m > 0.0 {
                    CriticalShear {
                        tau: m * p,
                        dtau_dp: m,
                        dtau_domega: self.a1 * p,
                        ..Default::default()
                    }
                } else {
                    CriticalShear {
                        clamped: true,
                        ..Default::default()
                    }
                }
            }
            Kind::Unclamped => {
                let m = self.a0 + self.a1 * x.omega;
                CriticalShear {
                    tau: m * p,
                    dtau_dp: m,
                    dtau_domega: self.a1 * p,
                    ..Default::default()
                }
            }
        }
    }
}

/// Schema of the Coulomb-type test laws.
const COULOMB_SPECS: [ParamSpec; 2] = [
    ParamSpec::optional("mu", "-", 0.12, 0.0, 10.0, "friction coefficient"),
    ParamSpec::optional("k_t", "MPa/mm", 1e5, 0.0, f64::INFINITY, "stick stiffness")
        .exclusive_min(),
];

/// Schema of the work-softening test laws.
const SOFTENING_SPECS: [ParamSpec; 3] = [
    ParamSpec::optional(
        "a0",
        "-",
        0.15,
        0.0,
        10.0,
        "friction coefficient at zero work",
    ),
    ParamSpec::optional(
        "a1",
        "mm/N",
        -2e-3,
        -1.0,
        1.0,
        "slope of μ in the frictional work",
    ),
    ParamSpec::optional("k_t", "MPa/mm", 1e5, 0.0, f64::INFINITY, "stick stiffness")
        .exclusive_min(),
];

/// A builder that validates through `Params::resolve` (as the registry does).
fn builder(kind: Kind) -> impl Fn(&Params) -> Result<Box<dyn FrictionLaw>, FrictionError> {
    move |params: &Params| {
        let law: Box<dyn FrictionLaw> = match kind {
            Kind::Softening | Kind::Unclamped => {
                let v = params.resolve("test-law", &SOFTENING_SPECS)?;
                Box::new(TestLaw {
                    kind,
                    a0: v[0],
                    a1: v[1],
                    k_t: v[2],
                })
            }
            _ => {
                let v = params.resolve("test-law", &COULOMB_SPECS)?;
                Box::new(TestLaw {
                    kind,
                    a0: v[0],
                    a1: 0.0,
                    k_t: v[1],
                })
            }
        };
        Ok(law)
    }
}

/// Identity transport (`t* = t_n`, re-projected by the return mapping),
/// backward-Euler slip direction. Not objective: see `objectivity` below.
struct Identity;

impl KinematicFormulation for Identity {
    fn name(&self) -> &str {
        "identity"
    }
    fn needs(&self) -> PointNeeds {
        PointNeeds::NONE
    }
    fn transport(&self, t_old: &Vec3, _kin: &StepKinematics) -> Vec3 {
        *t_old
    }
    fn slip_direction(&self, _x: &DirectionInputs<'_>) -> Option<Vec3> {
        None
    }
}

/// Convective-like transport with a forward slip direction: `d` is the
/// transported old direction `φ_n` (objective, and different from `φ_tr`, so the
/// `c = φ_tr·d < 1` path of the return mapping is exercised).
struct ConvectiveForward;

impl KinematicFormulation for ConvectiveForward {
    fn name(&self) -> &str {
        "convective-forward"
    }
    fn needs(&self) -> PointNeeds {
        PointNeeds::TOOL_ROTATION
    }
    fn transport(&self, t_old: &Vec3, kin: &StepKinematics) -> Vec3 {
        ConvectiveLike.transport(t_old, kin)
    }
    fn slip_direction(&self, x: &DirectionInputs<'_>) -> Option<Vec3> {
        let norm = x.t_old.norm();
        (norm > 0.0).then(|| ConvectiveLike.transport(&(x.t_old / norm), x.kin))
    }
}

/// Convective-like transport (friction-math §4): rotate with the tool, then by
/// the minimal rotation taking the rotated old normal to the new one.
struct ConvectiveLike;

impl KinematicFormulation for ConvectiveLike {
    fn name(&self) -> &str {
        "convective-like"
    }
    fn needs(&self) -> PointNeeds {
        PointNeeds::TOOL_ROTATION
    }
    fn transport(&self, t_old: &Vec3, kin: &StepKinematics) -> Vec3 {
        let r = kin.tool_rotation;
        rotate_minimal(&(r * kin.n_old).normalize(), &kin.n_new, &(r * t_old))
    }
    fn slip_direction(&self, _x: &DirectionInputs<'_>) -> Option<Vec3> {
        None
    }
}

use crate::PointNeeds;

const FORMULATIONS: [&dyn KinematicFormulation; 2] = [&ConvectiveForward, &ConvectiveLike];

/// Run the suite on a law of `kind` with schema `specs` and base `base`,
/// printing the report and the time per formulation.
fn run(kind: Kind, specs: &[ParamSpec], base: Params) -> Report {
    let build = builder(kind);
    let subject = Subject {
        name: format!("{kind:?}"),
        params: specs,
        build: &build,
        base,
    };
    let start = Instant::now();
    let report = check_law(&subject, &FORMULATIONS, &Options::default());
    let per_pair = start.elapsed().as_secs_f64() / FORMULATIONS.len() as f64;
    println!("{report}\n[{kind:?}: {per_pair:.3} s per law × formulation]");
    report
}

/// Names of the failed checks (sorted, deduplicated).
fn failed_checks(report: &Report) -> Vec<&'static str> {
    let mut v: Vec<_> = report.failures().map(|r| r.check).collect();
    v.sort_unstable();
    v.dedup();
    v
}

fn detail<'r>(report: &'r Report, check: &str) -> Vec<&'r str> {
    report
        .results
        .iter()
        .filter(|r| r.check == check)
        .map(|r| r.detail.as_str())
        .collect()
}

/// friction-math §5: a correct Coulomb law passes every check under both test
/// formulations (tolerances are the suite's own: 1e-12 bound, 1e-10
/// consistency and objectivity, 1e-5 tangents).
#[test]
fn coulomb_passes_every_check_with_both_formulations() {
    let report = run(
        Kind::Coulomb,
        &COULOMB_SPECS,
        Params::new().with("mu", 0.144),
    );
    assert!(report.passed(), "{report}");
    assert_eq!(report.results.len(), 11 * 2 + 1);
    let text = report.to_string();
    assert!(text.ends_with("23 passed, 0 failed"), "{text}");
    // The tangent check really checked points in stick and in slip.
    for d in detail(&report, "tangent") {
        assert!(
            d.starts_with("checked ") && !d.contains("checked 0 "),
            "{d}"
        );
    }
}

/// friction-math §3 (WH, `μ_min = 0`) and §5: a correct work-softening law
/// passes every check. (With `a1 = -2e-3` mm/N the random histories drive `ω`
/// to ~75 N/mm, i.e. `μ` close to 0; backward Euler approaches the clamp
/// asymptotically and never overshoots it.)
///
/// History: this failed while the shared return mapping solved for `Δγ`.
/// `solve_work_dependent` iterates on `Δγ` and stops at `|f| ≤ 1e-15 |t_tr|`;
/// `τ = |t_tr| - k_T Δγ` then carries an absolute error of order
/// `1e-15 |t_tr|`, so `|t| ≤ τ_c(ω_{n+1})(1 + 1e-12)` breaks once
/// `|t_tr|/τ_c ≳ 1e3–1e4` (measured: 1.07e-12 relative at p = 427 MPa,
/// |Δu_T| = 0.82 mm; 5e-10 at p = 1e-12 MPa, |Δu_T| = 1e6 mm; at p = 1e6 MPa,
/// |Δu_T| = 1e6 mm, |t| = 7.4e4 MPa while τ_c(ω_{n+1}) = 0). Solving for `τ`
/// instead of `Δγ` removes the cancellation. Un-ignore when fixed.
#[test]
fn work_softening_passes_every_check_with_both_formulations() {
    let report = run(Kind::Softening, &SOFTENING_SPECS, Params::new());
    assert!(report.passed(), "{report}");
}

/// A milder softening (`a1 = -2e-4` mm/N, `|t_tr|/τ_c` never large enough to
/// expose the solver's tolerance along the histories) passes every check
/// except, possibly, the extreme edge cases.
#[test]
fn mild_work_softening_passes_the_history_checks() {
    let report = run(
        Kind::Softening,
        &SOFTENING_SPECS,
        Params::new().with("a1", -2e-4),
    );
    let failed = failed_checks(&report);
    assert!(failed.iter().all(|c| *c == "edge-cases"), "{report}");
}

/// friction-math §2 consistent tangent `∂t/∂p = (∂τ_c/∂p) φ_tr`: a law with a
/// wrong `∂τ_c/∂p` fails `tangent` under both formulations, and nothing else
/// (`∂τ_c/∂p` enters nothing but the tangent).
#[test]
fn wrong_dtau_dp_fails_only_the_tangent_check() {
    let report = run(Kind::WrongDtauDp, &COULOMB_SPECS, Params::new());
    assert_eq!(failed_checks(&report), vec!["tangent"], "{report}");
    assert_eq!(report.failures().count(), 2, "{report}");
    for d in detail(&report, "tangent") {
        assert!(d.contains("∂t/∂p") && d.contains("slip"), "{d}");
    }
}

/// §2: a law returning NaN (above 300 MPa) fails, with the error text, and the
/// suite does not panic; checks that never reach 300 MPa still pass.
#[test]
fn nan_law_fails_without_panicking() {
    let report = run(Kind::NanAbove300, &COULOMB_SPECS, Params::new());
    let failed = failed_checks(&report);
    for check in ["traction-bound", "random-histories", "edge-cases"] {
        assert!(failed.contains(&check), "{check} should fail: {report}");
    }
    for check in ["stick", "tangent", "objectivity", "parameter-validation"] {
        assert!(!failed.contains(&check), "{check} should pass: {report}");
    }
    assert!(
        report.failures().all(|r| r.detail.contains("non-finite")),
        "{report}"
    );
}

/// §3 (`τ_c ≥ 0`): work softening without the clamp goes negative once the
/// frictional work exceeds `a0/|a1|`. The backward-Euler solve never visits
/// such a work along the histories (the traction falls to zero first), so the
/// suite probes the law's contract directly in `edge-cases`, which fails and
/// names the negative `τ_c`.
#[test]
fn negative_critical_shear_fails() {
    let report = run(Kind::Unclamped, &SOFTENING_SPECS, Params::new());
    let failed = failed_checks(&report);
    assert!(
        !report.passed() && failed.contains(&"edge-cases"),
        "{report}"
    );
    assert!(
        report
            .failures()
            .any(|r| r.detail.contains("negative critical shear stress")),
        "{report}"
    );
    assert!(
        !failed.contains(&"stick") && !failed.contains(&"tangent"),
        "{report}"
    );
}

/// A panic inside the law is caught and reported as a failure of the check
/// that was running, with the panic message.
#[test]
fn panicking_law_fails_with_the_panic_message() {
    let report = run(Kind::PanicAbove400, &COULOMB_SPECS, Params::new());
    let failed = failed_checks(&report);
    assert!(
        failed.contains(&"random-histories") && failed.contains(&"edge-cases"),
        "{report}"
    );
    for r in report.failures() {
        assert!(
            r.detail.contains("panicked: test law exploded at p ="),
            "{}: {}",
            r.check,
            r.detail
        );
    }
    assert!(!failed.contains(&"stick"), "{report}");
}

/// §5 parameter validation: a builder that ignores the schema (reads the values
/// without `resolve`) accepts `μ < 0`, `μ > 10`, `k_T = 0` and NaN: the check
/// fails and names each parameter; all the other checks pass.
#[test]
fn parameter_validation_catches_a_builder_that_ignores_the_schema() {
    let lax = |params: &Params| -> Result<Box<dyn FrictionLaw>, FrictionError> {
        let get = |k: &str, d: f64| params.0.get(k).copied().unwrap_or(d);
        Ok(Box::new(TestLaw {
            kind: Kind::Coulomb,
            a0: get("mu", 0.12),
            a1: 0.0,
            k_t: get("k_t", 1e5),
        }))
    };
    let subject = Subject {
        name: "lax".into(),
        params: &COULOMB_SPECS,
        build: &lax,
        base: Params::new(),
    };
    let report = check_law(&subject, &FORMULATIONS, &Options::default());
    assert_eq!(
        failed_checks(&report),
        vec!["parameter-validation"],
        "{report}"
    );
    let d = &report.failures().next().unwrap().detail;
    // mu: NaN, below 0, above 10; k_t: NaN, = 0 (exclusive bound).
    assert!(d.starts_with("5 of 5 probes failed"), "{d}");
    assert!(
        d.contains("`mu` = -0.000001") && d.contains("`mu` = 10.00001") && d.contains("`k_t` = 0 "),
        "{d}"
    );
}

/// A builder that refuses bad values but with a message that does not name the
/// parameter fails too; one whose message names it passes.
#[test]
fn parameter_validation_requires_the_parameter_name_in_the_error() {
    let vague = |params: &Params| -> Result<Box<dyn FrictionLaw>, FrictionError> {
        params.resolve("test-law", &COULOMB_SPECS).map_err(|_| {
            FrictionError::InvalidParameters {
                component: "test-law".into(),
                reason: "bad value".into(),
            }
        })?;
        builder(Kind::Coulomb)(params)
    };
    let subject = Subject {
        name: "vague".into(),
        params: &COULOMB_SPECS,
        build: &vague,
        base: Params::new(),
    };
    let result = super::checks::parameter_validation(&subject);
    assert!(
        !result.passed && result.detail.contains("does not name the parameter"),
        "{}",
        result.detail
    );
    let good = builder(Kind::Coulomb);
    let subject = Subject {
        name: "good".into(),
        params: &COULOMB_SPECS,
        build: &good,
        base: Params::new(),
    };
    let result = super::checks::parameter_validation(&subject);
    assert!(result.passed, "{}", result.detail);
}

/// A base set that does not build fails every check with the reason, without panicking.
#[test]
fn unbuildable_base_set_fails_every_check() {
    let report = run(
        Kind::Coulomb,
        &COULOMB_SPECS,
        Params::new().with("mu", -1.0),
    );
    assert_eq!(report.failures().count(), report.results.len(), "{report}");
    assert!(
        report
            .results
            .iter()
            .all(|r| r.detail.contains("`mu` = -1")),
        "{report}"
    );
}

/// §4 objectivity: the identity transport is not objective; the suite fails it
/// and says whether the law itself is objective (checked with the formulation
/// conjugated by `Q`); the convective-like one is objective to round-off.
#[test]
fn objectivity_separates_formulation_from_law() {
    let build = builder(Kind::Coulomb);
    let subject = Subject {
        name: "coulomb".into(),
        params: &COULOMB_SPECS,
        build: &build,
        base: Params::new(),
    };
    let forms: [&dyn KinematicFormulation; 2] = [&Identity, &ConvectiveLike];
    let report = check_law(&subject, &forms, &Options::default());
    let by_form = |f: &str| {
        report
            .results
            .iter()
            .find(|r| r.check == "objectivity" && r.formulation.as_deref() == Some(f))
            .unwrap()
    };
    let id = by_form("identity");
    assert!(
        !id.passed
            && id
                .detail
                .starts_with("formulation `identity` is not objective")
            && id.detail.contains("the law itself is"),
        "{}",
        id.detail
    );
    let conv = by_form("convective-like");
    assert!(
        conv.passed && !conv.detail.contains("not applicable"),
        "{}",
        conv.detail
    );
}

/// A law that reads the flow stress without declaring it gets NaN (as from the
/// engine) and fails; declaring it makes it pass (§6).
#[test]
fn undeclared_point_data_is_not_supplied() {
    struct ReadsFlowStress(PointNeeds);
    impl FrictionLaw for ReadsFlowStress {
        fn name(&self) -> &str {
            "reads-flow-stress"
        }
        fn stick_stiffness(&self) -> f64 {
            1e5
        }
        fn needs(&self) -> PointNeeds {
            self.0
        }
        fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
            // Levanov-like (§3) with m = 0.3, c = 1.25.
            let k = 0.3 * x.flow_stress / 3f64.sqrt();
            let e = (-1.25 * x.p / x.flow_stress).exp();
            CriticalShear {
                tau: k * (1.0 - e),
                dtau_dp: k * 1.25 / x.flow_stress * e,
                ..Default::default()
            }
        }
    }
    for (needs, ok) in [(PointNeeds::NONE, false), (PointNeeds::FLOW_STRESS, true)] {
        let build = move |_: &Params| -> Result<Box<dyn FrictionLaw>, FrictionError> {
            Ok(Box::new(ReadsFlowStress(needs)))
        };
        let subject = Subject {
            name: "levanov-like".into(),
            params: &[],
            build: &build,
            base: Params::new(),
        };
        let report = check_law(&subject, &FORMULATIONS, &Options::default());
        assert_eq!(report.passed(), ok, "{report}");
    }
}

/// The report reads as specified: one line per check × formulation and a summary.
#[test]
fn report_display_lists_every_result_and_a_summary() {
    let report = run(Kind::WrongDtauDp, &COULOMB_SPECS, Params::new());
    let text = report.to_string();
    assert_eq!(text.lines().count(), 1 + report.results.len() + 1, "{text}");
    assert!(
        text.lines()
            .any(|l| l.starts_with("  FAIL  tangent") && l.contains("convective-forward")),
        "{text}"
    );
    assert!(text.ends_with("21 passed, 2 failed"), "{text}");
}
