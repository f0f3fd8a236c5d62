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

use fem_core::Vec3;
use fem_core::statics::{StaticTangent, dense_tangent};
use shell_elements::{BelytschkoTsay, J2PlaneStress, Material, StaticShells};
use static_common::{Trial, elastic, section, steel};

/// A 10 mm × 8 mm quad, slightly skewed; `warp` lifts nodes 0 and 2 by
/// `+warp` and 1 and 3 by `−warp` (mm).
fn quad(warp: f64) -> Vec<Vec3> {
    vec![
        Vec3::new(0.0, 0.0, warp),
        Vec3::new(10.0, 0.5, -warp),
        Vec3::new(10.8, 8.3, warp),
        Vec3::new(0.4, 8.0, -warp),
    ]
}

/// A smooth deterministic "random" number in [−1, 1] for index `k`.
fn wiggle(k: usize) -> f64 {
    ((k as f64 + 1.0) * 12.9898).sin() * 0.999
}

/// Move `trial` to: a rigid rotation `angle` about a skew axis through
/// the centre, a membrane stretch `stretch` along x, and perturbations of
/// `du` (mm) and `dth` (rad) on every DOF.
fn deform(t: &mut Trial, angle: f64, stretch: f64, du: f64, dth: f64, salt: usize) {
    let axis = Vec3::new(0.3, -0.5, 0.8).normalize();
    let r = nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle);
    let c: Vec3 = t.x_committed.iter().sum::<Vec3>() / 4.0;
    for n in 0..4 {
        let p = t.x_committed[n] - c;
        let s = Vec3::new(p.x * (1.0 + stretch), p.y, p.z);
        let w = Vec3::from_fn(|i, _| wiggle(salt + 6 * n + i));
        t.x[n] = c + r * s + du * w;
        t.dtheta[n] = axis * angle + dth * Vec3::from_fn(|i, _| wiggle(salt + 6 * n + 3 + i));
    }
}

/// `max |K − K_fd| / max |K|` of `shells` at `t`, and `max |K|`.
fn tangent_error(shells: &mut StaticShells<J2PlaneStress>, t: &Trial) -> (f64, f64) {
    let k = dense_tangent(shells, &t.state(), true).unwrap();
    let h = 1e-5;
    let mut worst: f64 = 0.0;
    let kmax = k.stiffness.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for j in 0..24 {
        let (n, d) = (j / 6, j % 6);
        let at = |sign: f64| {
            let mut p = Trial {
                x_start: t.x_start.clone(),
                x_committed: t.x_committed.clone(),
                x: t.x.clone(),
                rotations: t.rotations.clone(),
                dtheta: t.dtheta.clone(),
            };
            if d < 3 {
                p.x[n][d] += sign * h;
            } else {
                p.dtheta[n][d - 3] += sign * h;
            }
            let mut s = shells.clone();
            dense_tangent(&mut s, &p.state(), false).unwrap().forces
        };
        let (fp, fm) = (at(1.0), at(-1.0));
        for i in 0..24 {
            let fd = (fp[i] - fm[i]) / (2.0 * h);
            worst = worst.max((k.k(i, j) - fd).abs());
        }
    }
    (worst / kmax, kmax)
}

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
