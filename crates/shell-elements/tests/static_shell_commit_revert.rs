//! Commit and revert of the static shells' point states.
//!
//! Source: the contract of `fem_core::statics::StaticTangent` — the
//! forces are a function of the trial state and the committed history
//! only; `commit` keeps the last trial state, `revert` forgets it.
//! Checks, on one warped element of J2–Swift steel:
//! - revert: after a plastic trial evaluation and `revert`, the forces at
//!   any state are what they were before (bit for bit: same inputs, same
//!   operations), and so are the committed stresses;
//! - commit: with ν = 0 and an elastic material (no thickness change), the
//!   forces at the committed configuration with no increment equal the
//!   trial forces that were committed, to `1e-10` of their largest
//!   (measured: identical, the same operations on the same values),
//!   including hourglass and drilling forces;
//! - repeated evaluation: two calls at one state give the same forces
//!   (the trial calls leave no trace).

mod static_common;

use fem_core::Vec3;
use fem_core::statics::{StaticTangent, dense_tangent};
use shell_elements::{BelytschkoTsay, J2PlaneStress, StaticShells};
use static_common::{Trial, elastic, section, steel};

fn quad() -> Vec<Vec3> {
    vec![
        Vec3::new(0.0, 0.0, 0.3),
        Vec3::new(10.0, 0.5, -0.3),
        Vec3::new(10.8, 8.3, 0.3),
        Vec3::new(0.4, 8.0, -0.3),
    ]
}

fn shells(mat: J2PlaneStress) -> StaticShells<J2PlaneStress> {
    StaticShells::new(
        "shell",
        &quad(),
        &[[0, 1, 2, 3]],
        section(1.0, 5),
        BelytschkoTsay::default(),
        mat,
    )
    .unwrap()
}

/// Move the trial state: stretch along x by `s`, a shear-like warp `w`
/// (mm) on node 2, rotations `r` (rad) about several axes.
fn moved(t: &Trial, s: f64, w: f64, r: f64) -> Trial {
    let mut m = Trial::at(&t.x_committed);
    m.x_start.clone_from(&t.x_start);
    for n in 0..4 {
        m.x[n].x *= 1.0 + s;
        m.dtheta[n] = Vec3::new(r, -0.5 * r * n as f64, 0.2 * r);
    }
    m.x[2] += Vec3::new(w, -w, 2.0 * w);
    m
}

fn forces(s: &mut StaticShells<J2PlaneStress>, t: &Trial) -> Vec<f64> {
    dense_tangent(s, &t.state(), false).unwrap().forces
}

#[test]
fn revert_forgets_the_trial_state() {
    let mut s = shells(steel());
    let t0 = Trial::at(&quad());
    let t1 = moved(&t0, 0.01, 0.05, 0.01);
    let before = forces(&mut s, &t1);
    let sigma = s.stress(0, 4);
    // A plastic trial state, then revert.
    let plastic = moved(&t0, 0.08, 0.3, 0.1);
    let _ = dense_tangent(&mut s, &plastic.state(), true).unwrap();
    s.revert();
    assert_eq!(s.stress(0, 4), sigma);
    assert_eq!(forces(&mut s, &t1), before);
    // Without revert too: the trial calls leave the committed state alone.
    let _ = forces(&mut s, &plastic);
    assert_eq!(forces(&mut s, &t1), before);
}

#[test]
fn commit_keeps_the_trial_state() {
    let mut s = shells(elastic(200_000.0, 0.0));
    let t0 = Trial::at(&quad());
    let mut t1 = moved(&t0, 0.002, 0.05, 0.02);
    let trial = forces(&mut s, &t1);
    s.commit(&t1.state());
    t1.commit();
    let after = forces(&mut s, &t1);
    let scale = trial.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = trial
        .iter()
        .zip(&after)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    println!(
        "max |F| = {scale:.4e}, committed vs trial forces: {diff:.3e} ({:.2e}); \
         hourglass {:?}, drilling {:?}",
        diff / scale,
        s.hourglass_forces(0),
        s.drilling_moments(0)
    );
    assert!(s.hourglass_forces(0).iter().any(|&q| q != 0.0));
    assert!(s.drilling_moments(0).iter().any(|&q| q != 0.0));
    assert!(diff <= 1e-10 * scale);
}
