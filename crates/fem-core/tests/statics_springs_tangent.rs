//! The consistent tangent of `Springs` against central finite differences
//! of its internal forces: stretched, compressed, rotated and zero-free-length
//! springs.

use fem_core::statics::{DenseTangent, TrialState, dense_tangent};
use fem_core::{Mat3, Spring, Springs, Vec3};

/// Central-difference step (mm): truncation error `~ (h/L)²` and round-off
/// `~ ε L/h` are both below 1e-9 relative for `L ≈ 10 mm`.
const H: f64 = 1e-4;

fn trial<'a>(x: &'a [Vec3], rot: &'a [Mat3], dtheta: &'a [Vec3]) -> TrialState<'a> {
    TrialState {
        x_start: x,
        x_committed: x,
        x,
        rotation_committed: rot,
        dtheta,
        lambda: 0.0,
    }
}

/// The dense tangent at `x` and its central-difference estimate, and the
/// largest entry difference relative to the largest tangent entry.
fn tangent_error(springs: &mut Springs, x: &[Vec3]) -> (DenseTangent, f64) {
    let n = x.len();
    let (rot, dtheta) = (vec![Mat3::identity(); n], vec![Vec3::zeros(); n]);
    let k = dense_tangent(springs, &trial(x, &rot, &dtheta), true).unwrap();
    let nd = 6 * n;
    let mut worst: f64 = 0.0;
    for col in 0..nd {
        let (node, d) = (col / 6, col % 6);
        let mut fd = vec![0.0; nd];
        if d < 3 {
            let mut xp = x.to_vec();
            let mut xm = x.to_vec();
            xp[node][d] += H;
            xm[node][d] -= H;
            let fp = dense_tangent(springs, &trial(&xp, &rot, &dtheta), false).unwrap();
            let fm = dense_tangent(springs, &trial(&xm, &rot, &dtheta), false).unwrap();
            for (r, v) in fd.iter_mut().enumerate() {
                *v = (fp.forces[r] - fm.forces[r]) / (2.0 * H);
            }
        }
        // Rotations: springs do not depend on them, so the column is zero.
        for (row, v) in fd.iter().enumerate() {
            worst = worst.max((k.k(row, col) - v).abs());
        }
    }
    let scale = k.stiffness.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    (k, worst / scale)
}

fn spring(a: u32, b: u32, k: f64, length0: f64) -> Spring {
    Spring { a, b, k, length0 }
}

/// A spring stretched 30 % along a skew axis: tension, positive geometric
/// stiffness. Reference: central differences of the internal force;
/// tolerance 1e-6 relative to the largest tangent entry.
#[test]
fn stretched_spring_tangent_matches_central_differences() {
    let x = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(7.0, 6.0, 5.5)];
    let l = x[1].norm();
    let mut s = Springs::new("s", 2, vec![spring(0, 1, 120.0, l / 1.3)]).unwrap();
    let (_, err) = tangent_error(&mut s, &x);
    println!("stretched: relative error {err:.3e}");
    assert!(err < 1e-6, "relative error {err:e}");
}

/// A spring compressed to 60 % of its free length: compression, negative
/// geometric stiffness. Reference: central differences; tolerance 1e-6.
#[test]
fn compressed_spring_tangent_matches_central_differences() {
    let x = [Vec3::new(1.0, -2.0, 0.5), Vec3::new(4.0, 3.0, -1.0)];
    let l = (x[1] - x[0]).norm();
    let mut s = Springs::new("s", 2, vec![spring(0, 1, 80.0, l / 0.6)]).unwrap();
    let (k, err) = tangent_error(&mut s, &x);
    println!("compressed: relative error {err:.3e}");
    assert!(err < 1e-6, "relative error {err:e}");
    // The geometric stiffness is negative: a transverse direction softens.
    let d = (x[1] - x[0]).normalize();
    let t = d.cross(&Vec3::z()).normalize();
    let ktt: f64 = (0..3)
        .flat_map(|i| (0..3).map(move |j| (i, j)))
        .map(|(i, j)| t[i] * k.k(6 + i, 6 + j) * t[j])
        .sum();
    assert!(ktt < 0.0, "transverse stiffness {ktt} should be negative");
}

/// A triangle of springs rotated rigidly by 40° about a skew axis after
/// being stretched, plus a zero-free-length spring: every tangent block
/// is full. Reference: central differences; tolerance 1e-6.
#[test]
fn rotated_spring_network_tangent_matches_central_differences() {
    let base = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(10.0, 0.0, 0.0),
        Vec3::new(4.0, 9.0, 0.0),
        Vec3::new(3.0, 3.0, 6.0),
    ];
    let r = rodrigues(Vec3::new(1.0, 2.0, 0.5).normalize() * 40f64.to_radians());
    let x: Vec<Vec3> = base.iter().map(|p| r * (p * 1.1)).collect();
    let springs = vec![
        spring(0, 1, 100.0, 10.0),
        spring(1, 2, 60.0, 9.0),
        spring(2, 0, 75.0, 11.0),
        spring(0, 3, 50.0, 0.0),
        spring(1, 3, 90.0, 12.0),
    ];
    let mut s = Springs::new("net", 4, springs).unwrap();
    let (_, err) = tangent_error(&mut s, &x);
    println!("rotated network: relative error {err:.3e}");
    assert!(err < 1e-6, "relative error {err:e}");
}

fn rodrigues(axis_angle: Vec3) -> Mat3 {
    let (angle, axis) = (axis_angle.norm(), axis_angle.normalize());
    let k = Mat3::new(
        0.0, -axis.z, axis.y, axis.z, 0.0, -axis.x, -axis.y, axis.x, 0.0,
    );
    Mat3::identity() + k * angle.sin() + k * k * (1.0 - angle.cos())
}
