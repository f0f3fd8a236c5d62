//! # Step 5: writing your own friction law
//!
//! **What it shows.** A new friction law in about 40 lines: a struct holding
//! its parameters, a parameter schema, and an implementation of the
//! `plugins_api::FrictionLaw` trait (the critical shear stress `τ_c` and its
//! derivatives). Nothing else is needed: the return mapping
//! (docs/friction-math.md §2) is shared by every law, and any law pairs with
//! any kinematic formulation (§4). The example then
//!
//! 1. pairs the law with each built-in formulation through
//!    `friction_laws::builtin::with_law` (the law as a trait object, the
//!    formulation concrete: how the engine pairs a law that is not built in),
//!    and once as a fully monomorphised `PairedIntegrator<Law, Convective>`
//!    (how `builtin::integrator` pairs the built-in laws), and slides a point
//!    through each;
//! 2. registers the law in the link-time registry (`inventory::submit!`), so
//!    that `builtin::integrator("softening", …)` finds it by name, as a scene's
//!    `contact.law` would in a binary that links it;
//! 3. runs the conformance suite (`plugins_api::conformance`, docs/friction-math.md
//!    §5; what `formsim laws check` and `formsim plugin check` run) on the law
//!    with every formulation, prints the report and requires every check to
//!    pass.
//!
//! To ship the same law as a shared library that formsim loads at run time,
//! wrap it with `plugins_api::export_friction_law!` as `plugins/exp-decay`
//! does (plugins/README.md).
//!
//! **The law.** Pressure-softening Coulomb friction,
//!
//! ```text
//! τ_c = μ0 p / (1 + p/p0),    ∂τ_c/∂p = μ0 / (1 + p/p0)²,    ∂τ_c/∂ω = 0
//! ```
//!
//! Coulomb with coefficient `μ0` at low pressure, an effective coefficient
//! `μ(p) = μ0/(1 + p/p0)` that falls to half at `p = p0`, and a traction that
//! saturates at `μ0 p0` at very high pressure (a crude model of real contact
//! area growing less than proportionally; not a law from the literature).
//! Parameters: `mu0` (-, required), `p0` (MPa, default 100), `k_t` (MPa/mm,
//! default 1e5, the stick stiffness every law has).
//!
//! **Check.** Sliding at `p = 50 MPa` with `μ0 = 0.144`, `p0 = 100 MPa`, the
//! traction under every formulation must be `τ_c = μ0 p/(1 + p/p0) = 4.8 MPa`
//! (relative 1e-12: the radial return gives `τ_c` in closed form), and every
//! check of the conformance suite must pass (its own tolerances, listed in
//! `crates/plugins-api/src/conformance/mod.rs`).
//!
//! **Run:** `cargo run --release -p formsim-examples --example step5_my_friction_law`
//!
//! **Output.** The law's `τ_c` against the formula at a few pressures, one
//! line per formulation with the sliding traction, then the conformance
//! report, e.g.
//!
//! ```text
//! softening x convective          |t| = 4.800000 MPa (mu0 p/(1 + p/p0) = 4.800000, rel. error 0.0e0)
//! ...
//! conformance of `softening` (docs/friction-math.md §5)
//!   PASS  stick                convective          ...
//! 45 passed, 0 failed
//! ```

use friction_laws::builtin::{self, BuiltinFormulation, FORMULATION_NAMES};
use friction_laws::formulations::Convective;
use plugins_api::conformance::{self, Options, Subject};
use plugins_api::law::LawDescription;
use plugins_api::registry::LawEntry;
use plugins_api::{
    CriticalShear, FrictionError, FrictionLaw, KinematicFormulation, PairedIntegrator, ParamSpec,
    Params, PointIntegrator, PointState, ShearInputs, StepInput, StepKinematics, TangentMode, Vec3,
};

// ---------------------------------------------------------------------------
// The law: everything a new law needs (about 40 lines).
// ---------------------------------------------------------------------------

/// Pressure-softening Coulomb friction, `τ_c = μ0 p / (1 + p/p0)`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Softening {
    mu0: f64,
    p0: f64,
    k_t: f64,
}

impl Softening {
    /// Name as a scene would type it.
    const NAME: &'static str = "softening";
    /// Parameter schema: name, unit, default (or required), range, one-line doc.
    #[rustfmt::skip]
    const PARAMS: &'static [ParamSpec] = &[
        ParamSpec::required("mu0", "-", 0.0, f64::INFINITY, "coefficient at low pressure μ0"),
        ParamSpec::optional("p0", "MPa", 100.0, 0.0, f64::INFINITY, "pressure where μ halves").exclusive_min(),
        ParamSpec::optional("k_t", "MPa/mm", 1e5, 0.0, f64::INFINITY, "stick stiffness k_T").exclusive_min(),
    ];

    /// Build from values in schema order; `check_values` refuses a wrong
    /// count and any value out of its range, naming the parameter.
    fn from_values(v: &[f64]) -> Result<Self, FrictionError> {
        plugins_api::check_values(Self::NAME, Self::PARAMS, v)?;
        Ok(Self {
            mu0: v[0],
            p0: v[1],
            k_t: v[2],
        })
    }
}

impl FrictionLaw for Softening {
    fn name(&self) -> &str {
        Self::NAME
    }
    fn stick_stiffness(&self) -> f64 {
        self.k_t
    }
    // `needs` keeps its default (nothing beyond p and ω) and `work_dependent`
    // its default (false): τ_c depends on the pressure alone.
    fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
        let s = 1.0 / (1.0 + x.p / self.p0);
        CriticalShear {
            tau: self.mu0 * x.p * s,    // μ0 p/(1 + p/p0)
            dtau_dp: self.mu0 * s * s,  // μ0/(1 + p/p0)²
            ..CriticalShear::default()  // ∂τ_c/∂ω = ∂τ_c/∂|v| = 0, no clamp
        }
    }
}

// ---------------------------------------------------------------------------
// Optional: make the law known by name (the link-time registry).
// ---------------------------------------------------------------------------

/// The registry's builder: values in schema order, boxed law.
fn build_boxed(values: &[f64]) -> Result<Box<dyn FrictionLaw>, FrictionError> {
    Ok(Box::new(Softening::from_values(values)?))
}

inventory::submit! {
    LawEntry {
        description: LawDescription {
            name: Softening::NAME,
            summary: "pressure-softening Coulomb: τ_c = μ0 p / (1 + p/p0)",
            params: Softening::PARAMS,
        },
        build: build_boxed,
    }
}

// ---------------------------------------------------------------------------
// Using it.
// ---------------------------------------------------------------------------

/// Low-pressure coefficient: the square cup's Coulomb value (docs/friction-math.md §7).
const MU0: f64 = 0.144;
/// Softening pressure (MPa).
const P0: f64 = 100.0;
/// Sliding pressure of the check (MPa).
const P: f64 = 50.0;

/// Relative difference `|a - b| / |b|`.
fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Slide one point on a fixed flat tool at pressure `P` far past the stick
/// limit (20 steps of 1 µm against a stick range of τ_c/k_T = 48 nm) and
/// return the final traction magnitude.
fn slide(integrator: &dyn PointIntegrator) -> f64 {
    let n = Vec3::z();
    let input = StepInput::new(
        P,
        Vec3::new(1e-3, 0.0, 0.0),
        StepKinematics::simple(1e-4, n, n),
    );
    let mut state = PointState::default();
    let mut t = 0.0;
    for _ in 0..20 {
        let out = integrator
            .step(&mut state, &input)
            .expect("finite input with p > 0, dt > 0 and a unit normal is valid");
        assert!(!out.stick, "1 µm per step is far beyond the stick range");
        t = out.t.norm();
    }
    t
}

fn run() {
    let params = Params::new().with("mu0", MU0).with("p0", P0);
    let law = Softening::from_values(
        &params
            .resolve(Softening::NAME, Softening::PARAMS)
            .expect("mu0 = 0.144 and p0 = 100 MPa are in range"),
    )
    .expect("values resolved against the schema are valid");
    let formula = |p: f64| MU0 * p / (1.0 + p / P0);

    println!(
        "Step 5: a new friction law, tau_c = mu0 p / (1 + p/p0), mu0 = {MU0}, p0 = {P0} MPa\n"
    );
    for p in [1.0, 10.0, 100.0, 1000.0] {
        let x = ShearInputs {
            p,
            omega: 0.0,
            sliding_speed: f64::NAN, // not declared in `needs`: left NaN, as the engine does
            flow_stress: f64::NAN,
            temperature: f64::NAN,
        };
        let cs = law.critical_shear(&x);
        println!(
            "p = {p:6} MPa: tau_c = {:8.4} MPa, mu(p) = {:.4}, dtau_c/dp = {:.4}",
            cs.tau,
            cs.tau / p,
            cs.dtau_dp
        );
        assert!(rel(cs.tau, formula(p)) <= 1e-15, "tau_c at p = {p}");
    }

    // 1. Pair with every built-in formulation. `with_law` takes a boxed law
    //    (a trait object: one virtual call per τ_c evaluation) and a
    //    formulation by name (concrete, matched once).
    println!("\nsliding at p = {P} MPa under each formulation:");
    let expected = formula(P);
    for name in FORMULATION_NAMES {
        let integrator = builtin::with_law(Box::new(law), name, TangentMode::None)
            .expect("the names in FORMULATION_NAMES are built in");
        let t = slide(integrator.as_ref());
        let err = rel(t, expected);
        println!(
            "  {} x {name:<20} |t| = {t:.6} MPa (mu0 p/(1 + p/p0) = {expected:.6}, rel. error {err:.1e})",
            integrator.law_name()
        );
        assert!(err <= 1e-12, "{name}: |t| = {t} vs {expected}");
    }
    // The monomorphised pairing: law and formulation as concrete types, no
    // virtual call inside the step (what `builtin::integrator` builds for the
    // built-in laws). It gives the same bits as the trait-object pairing.
    let concrete = PairedIntegrator::new(law, Convective);
    let dynamic = builtin::with_law(Box::new(law), "convective", TangentMode::None)
        .expect("convective is built in");
    let (a, b) = (slide(&concrete), slide(dynamic.as_ref()));
    println!(
        "  PairedIntegrator<Softening, Convective>: |t| = {a:.6} MPa, same bits as with_law: {}",
        a.to_bits() == b.to_bits()
    );
    assert_eq!(
        a.to_bits(),
        b.to_bits(),
        "monomorphised vs trait-object pairing"
    );

    // 2. By name, through the registry (the `inventory::submit!` above).
    let by_name = builtin::integrator(Softening::NAME, &params, "jaumann", TangentMode::None)
        .expect("the law is registered under its name");
    let t = slide(by_name.as_ref());
    println!(
        "  by name: builtin::integrator(\"{}\", …, \"jaumann\"): |t| = {t:.6} MPa",
        by_name.law_name()
    );
    assert!(
        rel(t, expected) <= 1e-12,
        "registered law: {t} vs {expected}"
    );

    // 3. The conformance suite, with every built-in formulation. `build` must
    //    validate user values against the schema (`Params::resolve`): the
    //    suite's parameter-validation check feeds it out-of-range values.
    let build = |p: &Params| -> Result<Box<dyn FrictionLaw>, FrictionError> {
        build_boxed(&p.resolve(Softening::NAME, Softening::PARAMS)?)
    };
    let subject = Subject {
        name: Softening::NAME.to_string(),
        params: Softening::PARAMS,
        build: &build,
        base: params.clone(),
    };
    let formulations: Vec<BuiltinFormulation> = FORMULATION_NAMES
        .iter()
        .map(|n| BuiltinFormulation::from_name(n).expect("built-in names are valid"))
        .collect();
    let refs: Vec<&dyn KinematicFormulation> = formulations
        .iter()
        .map(|f| f as &dyn KinematicFormulation)
        .collect();
    let report = conformance::check_law(&subject, &refs, &Options::default());
    println!("\n{report}");
    // 11 checks per formulation plus the parameter validation, all passed.
    assert_eq!(report.results.len(), 11 * refs.len() + 1);
    assert!(
        report.passed(),
        "conformance failures: {:?}",
        report.failures().collect::<Vec<_>>()
    );
}

#[cfg_attr(test, allow(dead_code))]
fn main() {
    run();
}

#[test]
fn runs_as_documented() {
    run();
}
