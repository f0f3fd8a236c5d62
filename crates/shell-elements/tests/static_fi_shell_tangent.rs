//! The static fully integrated shell's tangent against central finite
//! differences of its internal forces: one element, flat and warped (with
//! and without the warping correction), elastic and plastic (J2, Swift
//! hardening, after a large membrane stretch), at trial states with
//! finite translations and rotations.
//!
//! Source: the tangent is by definition `∂F_int/∂q` over the 24 DOFs
//! (trial positions, rotation increments); each column is compared with
//! `(F(q + h e_j) − F(q − h e_j)) / 2h`, `h = 1e-5` (mm or rad), as for
//! the Belytschko–Tsay shell (`static_shell_tangent.rs`).
//! Tolerance: `max |K − K_fd| ≤ 1e-6 · max |K|` in every case, the
//! Belytschko–Tsay test's (measured figures printed; docs/springback.md).
//! The plastic cases check that every one of the 2×2 Gauss points has
//! yielded in the committed stretch and flows again in the increment.

mod static_common;

use fem_core::statics::StaticTangent;
use shell_elements::{FullyIntegrated, J2PlaneStress, Material, StaticShells};
use static_common::fd::{deform, quad, tangent_error};
use static_common::{Trial, elastic, section, steel};

fn shells(
    warp: f64,
    warping_correction: bool,
    mat: J2PlaneStress,
) -> StaticShells<J2PlaneStress, FullyIntegrated> {
    StaticShells::new(
        "shell",
        &quad(warp),
        &[[0, 1, 2, 3]],
        section(1.0, 5),
        FullyIntegrated {
            warping_correction,
            ..FullyIntegrated::default()
        },
        mat,
    )
    .unwrap()
}

/// Elastic, from the virgin state: a committed 0.2 rad rotation and 0.5 %
/// stretch (stresses, shear and drilling moments), then a 0.4 rad rigid
/// rotation, 1 % stretch, 0.05 mm and 0.03 rad perturbations.
fn elastic_case(warp: f64, warping_correction: bool) -> f64 {
    let mut s = shells(warp, warping_correction, elastic(200_000.0, 0.3));
    let mut t = Trial::at(&quad(warp));
    deform(&mut t, 0.2, 0.005, 0.05, 0.02, 0);
    s.commit(&t.state());
    t.commit();
    assert!((0..4).all(|p| s.transverse_shear_at(0, p) != [0.0; 2]));
    assert!(s.drilling_moments(0).iter().any(|&m| m != 0.0));
    deform(&mut t, 0.4, 0.01, 0.05, 0.03, 100);
    let (err, kmax) = tangent_error(&mut s, &t);
    println!(
        "elastic, warp {warp} mm, warping correction {warping_correction}: \
         max|K| = {kmax:.4e} N/mm, max|K − K_fd|/max|K| = {err:.3e}"
    );
    err
}

/// Plastic: a committed 5 % stretch (plastic at every Gauss point), then a
/// further 2 % stretch with a rotation and perturbations (plastic flow
/// within the increment at every Gauss point).
fn plastic_case(warp: f64) -> f64 {
    let mut s = shells(warp, true, steel());
    let mut t = Trial::at(&quad(warp));
    deform(&mut t, 0.1, 0.05, 0.02, 0.01, 7);
    s.commit(&t.state());
    t.commit();
    let eps_p: [f64; 4] =
        std::array::from_fn(|p| s.material().plastic_strain(s.history_at(0, p, 2)));
    assert!(
        eps_p.iter().all(|&e| e > 0.02),
        "the stretch should be plastic: ε_p = {eps_p:?}"
    );
    deform(&mut t, 0.3, 0.02, 0.02, 0.02, 300);
    let (err, kmax) = tangent_error(&mut s, &t);
    let mut after = s.clone();
    after.commit(&t.state());
    for (p, e) in eps_p.iter().enumerate() {
        let flow = after.material().plastic_strain(after.history_at(0, p, 2)) - e;
        assert!(
            flow > 0.005,
            "the increment should be plastic at Gauss point {p}: Δε_p = {flow}"
        );
    }
    println!(
        "plastic (ε_p = {:.4}…{:.4}), warp {warp} mm: max|K| = {kmax:.4e} N/mm, \
         max|K − K_fd|/max|K| = {err:.3e}",
        eps_p.iter().cloned().fold(f64::INFINITY, f64::min),
        eps_p.iter().cloned().fold(0.0, f64::max),
    );
    err
}

#[test]
fn flat_elastic_fi_tangent_matches_finite_differences() {
    assert!(elastic_case(0.0, true) < 1e-6);
}

#[test]
fn warped_elastic_fi_tangent_matches_finite_differences() {
    assert!(elastic_case(0.4, true) < 1e-6);
}

#[test]
fn warped_elastic_fi_tangent_without_warping_correction_matches_finite_differences() {
    assert!(elastic_case(0.4, false) < 1e-6);
}

#[test]
fn flat_plastic_fi_tangent_matches_finite_differences() {
    assert!(plastic_case(0.0) < 1e-6);
}

#[test]
fn warped_plastic_fi_tangent_matches_finite_differences() {
    assert!(plastic_case(0.4) < 1e-6);
}
