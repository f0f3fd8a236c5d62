//! The static Belytschko–Tsay shell's tangent against central finite
//! differences of its internal forces: one element, flat and warped,
//! elastic and plastic (J2, Swift hardening, after a large membrane
//! stretch), at trial states with finite translations and rotations.
//!
//! Source: the tangent is by definition `∂F_int/∂q` over the 24 DOFs
//! (trial positions, rotation increments); each column is compared with
//! `(F(q + h e_j) − F(q − h e_j)) / 2h`, `h = 1e-5` (mm or rad).
//! Tolerance: `max |K − K_fd| ≤ 1e-6 · max |K|` in every case (measured
//! 1e-11 to 3e-11: the differences' rounding). The plastic cases take the
//! material's `consistent_tangent` as it is (for J2 by default the central
//! difference of the return mapping); the bound leaves room for that.

mod static_common;

use fem_core::statics::StaticTangent;
use shell_elements::{BelytschkoTsay, J2PlaneStress, Material, StaticShells};
use static_common::fd::{deform, quad, tangent_error};
use static_common::{Trial, elastic, section, steel};

fn shells(warp: f64, mat: J2PlaneStress) -> StaticShells<J2PlaneStress> {
    StaticShells::new(
        "shell",
        &quad(warp),
        &[[0, 1, 2, 3]],
        section(1.0, 5),
        BelytschkoTsay::default(),
        mat,
    )
    .unwrap()
}

/// Elastic, from the virgin state: a 0.4 rad rigid rotation, 1 % stretch,
/// 0.05 mm and 0.03 rad perturbations.
fn elastic_case(warp: f64) -> f64 {
    let mut s = shells(warp, elastic(200_000.0, 0.3));
    let mut t = Trial::at(&quad(warp));
    // A committed state with stresses, hourglass and drilling forces.
    deform(&mut t, 0.2, 0.005, 0.05, 0.02, 0);
    s.commit(&t.state());
    t.commit();
    deform(&mut t, 0.4, 0.01, 0.05, 0.03, 100);
    let (err, kmax) = tangent_error(&mut s, &t);
    println!("elastic, warp {warp} mm: max|K| = {kmax:.4e} N/mm, max|K − K_fd|/max|K| = {err:.3e}");
    err
}

/// Plastic: a committed 5 % stretch (plastic), then a further 2 % stretch
/// with a rotation and perturbations (plastic flow within the increment).
fn plastic_case(warp: f64) -> f64 {
    let mut s = shells(warp, steel());
    let mut t = Trial::at(&quad(warp));
    deform(&mut t, 0.1, 0.05, 0.02, 0.01, 7);
    s.commit(&t.state());
    t.commit();
    let eps_p = s.material().plastic_strain(s.history(0, 2));
    assert!(eps_p > 0.02, "the stretch should be plastic: ε_p = {eps_p}");
    deform(&mut t, 0.3, 0.02, 0.02, 0.02, 300);
    let (err, kmax) = tangent_error(&mut s, &t);
    // The increment itself flows plastically.
    let mut after = s.clone();
    after.commit(&t.state());
    let flow = after.material().plastic_strain(after.history(0, 2)) - eps_p;
    assert!(
        flow > 0.005,
        "the increment should be plastic: Δε_p = {flow}"
    );
    println!(
        "plastic (ε_p = {eps_p:.4}), warp {warp} mm: max|K| = {kmax:.4e} N/mm, \
         max|K − K_fd|/max|K| = {err:.3e}"
    );
    err
}

#[test]
fn flat_elastic_tangent_matches_finite_differences() {
    assert!(elastic_case(0.0) < 1e-6);
}

#[test]
fn warped_elastic_tangent_matches_finite_differences() {
    assert!(elastic_case(0.4) < 1e-6);
}

#[test]
fn flat_plastic_tangent_matches_finite_differences() {
    assert!(plastic_case(0.0) < 1e-6);
}

#[test]
fn warped_plastic_tangent_matches_finite_differences() {
    assert!(plastic_case(0.4) < 1e-6);
}
