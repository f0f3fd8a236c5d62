//! The static shells' tangent against central finite differences of their
//! internal forces, on one element moved through finite translations and
//! rotations (shared by the Belytschko–Tsay and fully integrated tests).

use super::Trial;
use fem_core::Vec3;
use fem_core::statics::{StaticTangent, dense_tangent};

/// A 10 mm × 8 mm quad, slightly skewed; `warp` lifts nodes 0 and 2 by
/// `+warp` and 1 and 3 by `−warp` (mm).
pub fn quad(warp: f64) -> Vec<Vec3> {
    vec![
        Vec3::new(0.0, 0.0, warp),
        Vec3::new(10.0, 0.5, -warp),
        Vec3::new(10.8, 8.3, warp),
        Vec3::new(0.4, 8.0, -warp),
    ]
}

/// A smooth deterministic "random" number in [−1, 1] for index `k`.
pub fn wiggle(k: usize) -> f64 {
    ((k as f64 + 1.0) * 12.9898).sin() * 0.999
}

/// Move `trial` to: a rigid rotation `angle` about a skew axis through
/// the centre, a membrane stretch `stretch` along x, and perturbations of
/// `du` (mm) and `dth` (rad) on every DOF.
pub fn deform(t: &mut Trial, angle: f64, stretch: f64, du: f64, dth: f64, salt: usize) {
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

/// `max |K − K_fd| / max |K|` of `shells` (one element) at `t`, and
/// `max |K|`; central differences with `h = 1e-5` (mm or rad).
pub fn tangent_error<S: StaticTangent + Clone>(shells: &mut S, t: &Trial) -> (f64, f64) {
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
