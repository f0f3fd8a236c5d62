//! friction-math §5: every check of the conformance suite passes for all 4 × 4
//! built-in pairings, and the suite catches a deliberately broken law.

use friction_laws::builtin::{self, BuiltinFormulation, FORMULATION_NAMES, LAW_NAMES};
use plugins_api::conformance::{Options, Subject, check_law};
use plugins_api::law::LawDescription;
use plugins_api::{
    CriticalShear, FrictionError, FrictionLaw, KinematicFormulation, ParamSpec, Params,
    ShearInputs, registry,
};

fn formulations() -> Vec<BuiltinFormulation> {
    FORMULATION_NAMES
        .iter()
        .map(|n| BuiltinFormulation::from_name(n).unwrap())
        .collect()
}

#[test]
fn every_builtin_law_passes_conformance_with_every_formulation() {
    friction_laws::ensure_linked();
    let forms = formulations();
    let refs: Vec<&dyn KinematicFormulation> = forms
        .iter()
        .map(|f| f as &dyn KinematicFormulation)
        .collect();
    let mut failed = Vec::new();
    for law in LAW_NAMES {
        let entry = registry::law(law).unwrap();
        let build = |p: &Params| registry::build_law(law, p);
        let subject = Subject {
            name: law.to_string(),
            params: entry.description.params,
            build: &build,
            base: builtin::benchmark_params(law),
        };
        let report = check_law(&subject, &refs, &Options::default());
        println!("{report}");
        if !report.passed() {
            failed.push(law);
        }
    }
    assert!(failed.is_empty(), "laws failing conformance: {failed:?}");
}

/// Coulomb friction whose `∂τ_c/∂p` is off by 10 %: the suite must fail it.
struct WrongTangent {
    mu: f64,
}

impl FrictionLaw for WrongTangent {
    fn name(&self) -> &str {
        "wrong-tangent"
    }
    fn stick_stiffness(&self) -> f64 {
        1e5
    }
    fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
        CriticalShear {
            tau: self.mu * x.p,
            dtau_dp: 1.1 * self.mu,
            ..CriticalShear::default()
        }
    }
}

const WRONG_PARAMS: &[ParamSpec] = &[ParamSpec::required(
    "mu",
    "-",
    0.0,
    f64::INFINITY,
    "friction coefficient",
)];

#[test]
fn conformance_suite_fails_a_law_with_a_wrong_tangent() {
    let _ = LawDescription {
        name: "wrong-tangent",
        summary: "",
        params: WRONG_PARAMS,
    };
    let build = |p: &Params| -> Result<Box<dyn FrictionLaw>, FrictionError> {
        let v = p.resolve("wrong-tangent", WRONG_PARAMS)?;
        Ok(Box::new(WrongTangent { mu: v[0] }))
    };
    let forms = formulations();
    let refs: Vec<&dyn KinematicFormulation> = forms
        .iter()
        .map(|f| f as &dyn KinematicFormulation)
        .collect();
    let subject = Subject {
        name: "wrong-tangent".into(),
        params: WRONG_PARAMS,
        build: &build,
        base: Params::new().with("mu", 0.144),
    };
    let report = check_law(&subject, &refs, &Options::default());
    println!("{report}");
    assert!(!report.passed());
    assert!(
        report.failures().all(|f| f.check == "tangent"),
        "only the tangent check should fail:\n{report}"
    );
    assert_eq!(
        report.failures().count(),
        refs.len(),
        "the tangent check should fail with every formulation"
    );
}
