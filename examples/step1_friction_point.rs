//! # Step 1: one contact point through a friction law
//!
//! **What it shows.** The smallest use of formsim's friction machinery: no
//! mesh, no tool, no solver. One contact point is pressed at a constant
//! pressure `p` and dragged along `x` by a prescribed history of slip
//! increments `Δu_T`, and a `PointIntegrator` (a friction law paired with a
//! kinematic formulation, built by `friction_laws::builtin::integrator`)
//! returns the friction traction `t` of each step. This is exactly what the
//! contact stage of an explicit step does at every touching node, and what
//! `formsim friction-point` does along a history read from a file
//! (`crates/formsim/src/point_driver.rs`).
//!
//! **The physics.** The return mapping of docs/friction-math.md §2 splits the
//! slip into an elastic ("stick") part, carried by a tangential spring of
//! stiffness `k_T`, and a true slip part:
//!
//! - trial traction `t_tr = t_n - k_T Δu_T`;
//! - **stick** while `|t_tr| ≤ τ_c`: `t = t_tr`, so from rest `|t| = k_T U`
//!   with `U = Σ |Δu_T|` the distance travelled;
//! - **slip** otherwise: `t = τ_c t_tr/|t_tr|`, slip multiplier
//!   `Δγ = (|t_tr| - τ_c)/k_T`, dissipation `ΔD = τ_c Δγ`.
//!
//! For Amontons–Coulomb (`ac`, eq. 2.13 of Colville's thesis), `τ_c = μ p`,
//! so in steady sliding `|t| = μ p` and the accumulated dissipation per unit
//! area is `D = μ p × Σ Δγ` (the slip length), with `Σ Δγ = U - μ p/k_T`: the
//! stick spring keeps the last `μ p/k_T` of the travel as elastic
//! displacement. Here `μ = 0.144` and `p = 10 MPa`, the NUMISHEET'93 square
//! cup's value (docs/friction-math.md §7), and `k_T = 1e4 MPa/mm`, the
//! default: the stick phase lasts only `μ p/k_T = 144 nm` of travel, which is
//! why the history below moves in nanometres.
//!
//! The same history is then run through the Wriggers–van der Ven–Stein law
//! (`wvs`, `τ_c = β p + α p^ν`, eqs. 2.15–2.16) with the square cup's
//! benchmark parameters `α = 0.03`, `β = 0.144`, `ν = 0.8`: its effective
//! coefficient `μ(p) = β + α p^(ν-1)` is higher than Coulomb's at 10 MPa.
//!
//! **Run:** `cargo run --release -p formsim-examples --example step1_friction_point`
//!
//! **Output.** A table of the history (step, travel `U` in nm, `|t|`,
//! `k_T U`, stick or slip), then the Coulomb checks (slip stress against
//! `μ p`, slip length against `U - μ p/k_T`, dissipation against
//! `μ p × slip length`) and the WVS effective
//! coefficient against eq. 2.16, each with its relative error, e.g.
//!
//! ```text
//! step  U (nm)   |t| (MPa)  k_T U (MPa)  state
//!    5    3.000     0.0300       0.0300  stick
//! ...
//!   35  126.000     1.2600       1.2600  stick
//!   38  148.200     1.4400       1.4820  slip
//! ...
//! 37 steps in stick, 23 in slip; total travel U = 366.000 nm
//! sliding: |t| = 1.440000 MPa, mu p = 1.440000 MPa (rel. error 0.0e0)
//! slip length: sum dgamma = 222.000000 nm, U - mu p/k_T = 222.000000 nm (rel. error 0.0e0)
//! dissipation: D = 3.196800e-4 N/mm, mu p (U - mu p/k_T) = 3.196800e-4 N/mm (rel. error 0.0e0)
//!
//! wvs (alpha = 0.03, beta = 0.144, nu = 0.8): 39 stick steps, effective mu = |t|/p = 0.162929,
//! beta + alpha p^(nu-1) = 0.162929 (rel. error 1.7e-16)
//! ```
//!
//! In slip the column `k_T U` is what the stick spring alone would carry:
//! the return mapping caps it at `τ_c` and books the rest as slip.
//!
//! The checks use a relative tolerance of 1e-12 for quantities the return
//! mapping computes in closed form (`|t|` in stick and slip, `μ_eff`) and
//! 1e-9 for sums over the history (dissipation, slip length), which collect
//! round-off from every step.

use friction_laws::builtin;
use plugins_api::{
    Params, PointIntegrator, PointState, StepInput, StepKinematics, TangentMode, Vec3,
};

/// Contact pressure (MPa): the square cup's order of magnitude.
const P: f64 = 10.0;
/// Coulomb coefficient of the NUMISHEET'93 steel cup (docs/friction-math.md §7).
const MU: f64 = 0.144;
/// Steps of the history.
const STEPS: u32 = 60;
/// Slip increment growth per step (mm): step `n` moves `n × DELTA`, a linear
/// ramp of the sliding speed from rest.
const DELTA: f64 = 2e-7;
/// Time step (s). Coulomb does not read it; it only has to be positive.
const DT: f64 = 1e-4;

/// Relative difference `|a - b| / |b|`.
fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// What one run of the history produced.
struct Outcome {
    /// Traction magnitude after the last step (MPa).
    t_last: f64,
    /// Σ ΔD over the history (N/mm).
    dissipation: f64,
    /// Σ Δγ over the history (mm).
    slip_length: f64,
    /// Total travel U = Σ |Δu_T| (mm).
    travel: f64,
    /// Number of steps that stuck (all before the first slip).
    stick_steps: u32,
}

/// Drive `integrator` along the ramp history at pressure `P`; print the table
/// when `print` is set; check the stick phase on the way (`|t| = k_T U`).
fn run_history(integrator: &dyn PointIntegrator, print: bool) -> Outcome {
    // A fixed, flat tool: the normal is +z at both ends of every step, and no
    // deformation data are given (`simple` fills neutral values: F = I, L = 0).
    let n = Vec3::z();
    let kin = StepKinematics::simple(DT, n, n);
    let k_t = integrator.stick_stiffness();
    // The per-point history the engine keeps between steps: traction, pressure, ω.
    let mut state = PointState::default();
    let mut out = Outcome {
        t_last: 0.0,
        dissipation: 0.0,
        slip_length: 0.0,
        travel: 0.0,
        stick_steps: 0,
    };
    let mut slipped = false;
    if print {
        println!("step  U (nm)   |t| (MPa)  k_T U (MPa)  state");
    }
    for step in 1..=STEPS {
        let du = Vec3::new(f64::from(step) * DELTA, 0.0, 0.0);
        out.travel += du.x;
        let input = StepInput::new(P, du, kin);
        let result = integrator
            .step(&mut state, &input)
            .expect("finite input with p > 0, dt > 0 and a unit normal is valid");
        let t = result.t.norm();
        out.dissipation += result.dissipation;
        out.slip_length += result.dgamma;
        out.t_last = t;
        if result.stick {
            // Stick after a slip would mean the traction dropped below τ_c:
            // impossible under a monotone drag.
            assert!(
                !slipped,
                "step {step}: stick after slip under a monotone drag"
            );
            out.stick_steps += 1;
            // Stick: the traction is the stick spring's, k_T × travel
            // (closed form, relative 1e-12).
            let elastic = k_t * out.travel;
            assert!(
                rel(t, elastic) <= 1e-12,
                "step {step}: stick traction {t} MPa vs k_T U = {elastic} MPa"
            );
        } else {
            slipped = true;
        }
        // Print every fifth step, and the first slipping step.
        let first_slip = !result.stick && out.stick_steps + 1 == step;
        if print && (step % 5 == 0 || first_slip) {
            println!(
                "{step:4} {:8.3} {t:10.4} {:12.4}  {}",
                out.travel * 1e6,
                k_t * out.travel,
                if result.stick { "stick" } else { "slip" }
            );
        }
    }
    out
}

fn run() {
    // --- Amontons–Coulomb -------------------------------------------------
    // A law by name with its parameters (k_t keeps its default 1e4 MPa/mm),
    // paired with the convective formulation. On a fixed flat tool every
    // formulation transports the traction unchanged, so the choice does not
    // matter here; it does on curved, moving or deforming contact (step 4).
    let ac = builtin::integrator(
        "ac",
        &Params::new().with("mu", MU),
        "convective",
        TangentMode::None,
    )
    .expect("ac with mu = 0.144 and the convective formulation are built in");
    let k_t = ac.stick_stiffness();
    println!(
        "Step 1: one contact point, law `{}` x formulation `{}`",
        ac.law_name(),
        ac.formulation_name()
    );
    println!(
        "p = {P} MPa, mu = {MU}, k_T = {k_t:e} MPa/mm: the point sticks for mu p/k_T = {:.1} nm \
         of travel, then slides at |t| = mu p = {:.3} MPa\n",
        MU * P / k_t * 1e6,
        MU * P
    );
    let coulomb = run_history(ac.as_ref(), true);
    let slip_steps = STEPS - coulomb.stick_steps;
    println!(
        "\n{} steps in stick, {slip_steps} in slip; total travel U = {:.3} nm",
        coulomb.stick_steps,
        coulomb.travel * 1e6
    );
    // The history is long enough to reach sliding, and starts in stick.
    assert!(
        coulomb.stick_steps >= 10 && slip_steps >= 10,
        "the ramp should show both phases: {} stick, {slip_steps} slip steps",
        coulomb.stick_steps
    );

    // Slip: |t| = τ_c = μ p (eq. 2.13; closed-form radial return, relative 1e-12).
    let mu_p = MU * P;
    let err = rel(coulomb.t_last, mu_p);
    println!(
        "sliding: |t| = {:.6} MPa, mu p = {mu_p:.6} MPa (rel. error {err:.1e})",
        coulomb.t_last
    );
    assert!(
        err <= 1e-12,
        "sliding traction {} vs mu p {mu_p}",
        coulomb.t_last
    );

    // The slip length is the travel less the elastic part left in the stick
    // spring: Σ Δγ = U - μ p/k_T (relative 1e-9: a sum over the history).
    let slip_length = coulomb.travel - mu_p / k_t;
    let err = rel(coulomb.slip_length, slip_length);
    println!(
        "slip length: sum dgamma = {:.6} nm, U - mu p/k_T = {:.6} nm (rel. error {err:.1e})",
        coulomb.slip_length * 1e6,
        slip_length * 1e6
    );
    assert!(
        err <= 1e-9,
        "slip length {} vs {slip_length}",
        coulomb.slip_length
    );

    // Dissipation = μ p × slip length (friction-math §2: ΔD = τ_c Δγ summed;
    // relative 1e-9).
    let expected = mu_p * slip_length;
    let err = rel(coulomb.dissipation, expected);
    println!(
        "dissipation: D = {:.6e} N/mm, mu p (U - mu p/k_T) = {expected:.6e} N/mm (rel. error {err:.1e})",
        coulomb.dissipation
    );
    assert!(
        err <= 1e-9,
        "dissipation {} vs {expected}",
        coulomb.dissipation
    );

    // --- Wriggers–van der Ven–Stein -----------------------------------------
    // The same history through another law: only the name and the
    // parameters change. `benchmark_params` holds the square cup's values
    // (alpha = 0.03, beta = 0.144, nu = 0.8; `formsim laws --describe wvs`
    // lists the parameters and their units).
    let params = builtin::benchmark_params("wvs");
    let wvs = builtin::integrator("wvs", &params, "convective", TangentMode::None)
        .expect("wvs with its benchmark parameters is built in");
    let slide = run_history(wvs.as_ref(), false);
    let mu_eff = slide.t_last / P;
    let (alpha, beta, nu) = (params.0["alpha"], params.0["beta"], params.0["nu"]);
    // Eq. 2.16: μ(p) = β + α p^(ν-1) (no regularisation above p0 = 1e-3 MPa).
    let analytic = beta + alpha * P.powf(nu - 1.0);
    let err = rel(mu_eff, analytic);
    println!(
        "\nwvs (alpha = {alpha}, beta = {beta}, nu = {nu}): {} stick steps, effective mu = |t|/p = \
         {mu_eff:.6}, beta + alpha p^(nu-1) = {analytic:.6} (rel. error {err:.1e})",
        slide.stick_steps
    );
    assert!(err <= 1e-12, "wvs mu_eff {mu_eff} vs {analytic}");
    // A higher τ_c sticks longer: the stick phase ends at τ_c/k_T of travel.
    assert!(slide.stick_steps >= coulomb.stick_steps);
}

#[cfg_attr(test, allow(dead_code))]
fn main() {
    run();
}

#[test]
fn runs_as_documented() {
    run();
}
