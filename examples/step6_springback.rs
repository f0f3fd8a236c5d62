//! # Step 6: springback with the static solver
//!
//! **What it shows.** Steps 2 to 4 ran the explicit engine: time steps,
//! masses, a press. Springback asks a static question instead: once the
//! tools are gone, where does the part come to rest? This example answers
//! it for a strip with `fem_core::statics`, the Newton solver the
//! springback step's implicit method uses:
//!
//! - `StaticShells::new` makes Belytschko–Tsay shells an effect of the
//!   static solver, with their exact tangent (dual numbers through the
//!   explicit element's own kernel, the material entering through
//!   `Material::consistent_tangent`);
//! - a `StaticProblem` holds the nodes, the effects, the fixed DOFs and the
//!   loads; a `StaticSolver` solves it by load increments, Newton's method
//!   with the consistent tangent and faer's sparse factorisations, and
//!   reports each increment's residual history;
//! - the bent shells (stresses and plastic histories) are handed to a
//!   second problem, a *stress release* (`release_start_forces`): the
//!   internal forces the moment held are let go increment by increment, as
//!   the springback step lets go of what the tools held.
//!
//! **The physics.** A strip of NUMISHEET'93 mild steel (Swift hardening,
//! `σ = 565.32 (0.007117 + ε_p)^0.2589` MPa), 4 mm long and 1 mm thick,
//! in plane strain (ν → ½), clamped at one end, is bent by an end moment
//! to the curvature `κ ≈ 1/25 mm⁻¹` (its outer fibres well past yield) and
//! released. The moment is uniform, so the curvature is the tip rotation
//! over the length. Unloading is elastic: taking off the applied moment
//! `M` (per unit width) lowers the curvature by `Δκ = 12 M / (E′ t³)`,
//! `E′ = E / (1 − ν²)`, and the
//! springback ratio `κ_f / κ` follows from the moment–curvature relation
//! integrated through the thickness (`shell_elements::bending`, Hill's
//! plane-strain bending). Reference and tolerance: the springback ratio
//! within 2 % and `Δκ` within 0.5 % (docs/springback.md, "Verification").
//!
//! **Run it:** `cargo run --release -p formsim-examples --example
//! step6_springback` (about 0.1 s). It prints the solver's report of each
//! solve (increments, iterations, the residual falling quadratically) and
//! the two comparisons.

use fem_core::statics::{NewtonSettings, StaticProblem, StaticSolver};
use fem_core::{Dof, Dofs, Mesh, Vec3};
use shell_elements::bending::PlaneStrainStrip;
use shell_elements::{BelytschkoTsay, Hardening, J2PlaneStress, RuleKind, Section, StaticShells};

/// Young's modulus (MPa) and Poisson's ratio (plane strain: ν → ½).
const E: f64 = 200_000.0;
const NU: f64 = 0.4999;
/// Thickness, length and width of the strip (mm).
const T: f64 = 1.0;
const LENGTH: f64 = 4.0;
const WIDTH: f64 = 1.0;

/// The strip's problem at `nodes`: clamped at x = 0, held in plane strain
/// (no `uy`, no rotation about x or z), and `moment` (N·mm, whole width)
/// on its tip, shared by the tip's nodes.
fn problem(
    nodes: &[Vec3],
    mesh: &Mesh,
    shells: StaticShells<J2PlaneStress>,
    moment: f64,
) -> StaticProblem {
    let mut p = StaticProblem::new(nodes).expect("finite nodes");
    p.add_effect(shells);
    p.fix(&mesh.node_sets["x0"], Dofs::ALL)
        .expect("nodes in range");
    let plane_strain = Dofs::of(&[Dof::Uy, Dof::Rx, Dof::Rz]);
    p.fix(&mesh.node_sets["all"], plane_strain)
        .expect("nodes in range");
    if moment != 0.0 {
        let tip = &mesh.node_sets["x1"];
        p.add_load(tip, Dof::Ry, moment / tip.len() as f64)
            .expect("a finite load");
    }
    p
}

/// The rotation of `r` about y (rad).
fn about_y(r: &fem_core::Mat3) -> f64 {
    r[(0, 2)].atan2(r[(0, 0)])
}

fn run() {
    let swift = Hardening::swift(565.32, 0.007117, 0.2589).expect("valid Swift law");
    let strip = PlaneStrainStrip::new(E, NU, T, swift.clone()).expect("valid strip");
    let mesh = fem_core::rectangle(LENGTH, WIDTH, 4, 1).expect("a 4 × 1 mesh");
    let material = J2PlaneStress::new(E, NU, 7.85e-9, swift).expect("valid material");
    // 15 Lobatto points through the thickness: the plastic zone's edge is
    // sharp, and the rule must see it.
    let section = Section::new(T)
        .and_then(|s| s.with_rule(RuleKind::Lobatto, 15))
        .expect("valid section");
    let shells = StaticShells::new(
        "strip",
        &mesh.nodes,
        &mesh.quads,
        section,
        BelytschkoTsay::default(),
        material,
    )
    .expect("valid shells");
    // Full Newton steps (the springback step takes them too), small load
    // increments, and a force floor of the strip's scale (1 N).
    let settings = NewtonSettings {
        force_floor: 1.0,
        line_search_steps: 0,
        max_increment: 0.1,
        ..NewtonSettings::default()
    };

    // 1. Bend: the moment of the curvature 1/25 mm⁻¹, applied over increments.
    let moment = strip.moment(1.0 / 25.0) * WIDTH;
    let mut bend = StaticSolver::new(problem(&mesh.nodes, &mesh, shells, moment), settings)
        .expect("a well-posed bend");
    let bent_report = bend.solve().expect("the bend converges");
    let tip = mesh.node_sets["x1"][0] as usize;
    let kappa = about_y(&bend.rotation(tip)) / LENGTH;
    println!("bend to M = {moment:.2} N·mm:\n{bent_report}");

    // 2. Release: the bent shells, their stresses and histories kept, on the
    // bent nodes; the forces the moment held let go with λ.
    let bent = bend
        .effect::<StaticShells<J2PlaneStress>>(0)
        .expect("the shells are effect 0")
        .clone();
    let mut released = problem(bend.positions(), &mesh, bent, 0.0);
    released.release_start_forces();
    let mut release = StaticSolver::new(released, settings).expect("a well-posed release");
    let release_report = release.solve().expect("the release converges");
    let kappa_f = kappa + about_y(&release.rotation(tip)) / LENGTH;
    println!("release:\n{release_report}");

    // 3. Compare with the closed forms at the curvature reached.
    let dk = kappa - kappa_f;
    // Unloading takes off the moment applied (per unit width).
    let dk_ref = 12.0 * (moment / WIDTH) / (strip.plane_strain_modulus() * T.powi(3));
    let ratio = kappa_f / kappa;
    let ratio_ref = strip.springback(kappa).expect("a plastic bend").ratio;
    println!(
        "bent to κ = {kappa:.6} 1/mm; springback Δκ = {dk:.6} 1/mm (12 M/E′t³ = {dk_ref:.6}, {:+.3} %); \
         κ_f/κ = {ratio:.5} (closed form {ratio_ref:.5}, {:+.3} %)",
        100.0 * (dk / dk_ref - 1.0),
        100.0 * (ratio / ratio_ref - 1.0)
    );
    assert!(
        (dk / dk_ref - 1.0).abs() < 0.005,
        "Δκ off by more than 0.5 %"
    );
    assert!(
        (ratio / ratio_ref - 1.0).abs() < 0.02,
        "κ_f/κ off by more than 2 %"
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
