//! Geometric helpers shared by formulations: minimal rotations, Cayley maps,
//! and the closed-form rate of the traction direction `φ̇` (friction-math §4).

use crate::{Mat3, Vec3};

/// Projector onto the tangent plane of the unit normal `n`: `I - n⊗n`.
#[inline]
#[must_use]
pub fn tangent_projector(n: &Vec3) -> Mat3 {
    Mat3::identity() - n * n.transpose()
}

/// `v - n (n·v)`: the part of `v` in the tangent plane of the unit normal `n`.
#[inline]
#[must_use]
pub fn tangent_part(n: &Vec3, v: &Vec3) -> Vec3 {
    v - n * n.dot(v)
}

/// Skew matrix `[w]×` with `[w]× v = w × v`.
#[inline]
#[must_use]
pub fn skew(w: &Vec3) -> Mat3 {
    Mat3::new(0.0, -w.z, w.y, w.z, 0.0, -w.x, -w.y, w.x, 0.0)
}

/// Axial vector of the skew part of `m`.
#[inline]
#[must_use]
pub fn axial(m: &Mat3) -> Vec3 {
    0.5 * Vec3::new(
        m[(2, 1)] - m[(1, 2)],
        m[(0, 2)] - m[(2, 0)],
        m[(1, 0)] - m[(0, 1)],
    )
}

/// Whether `m` is exactly the identity, bit for bit (an OR tree over the
/// entries' bit patterns, no chain of floating-point compares). Cheap enough to
/// pick, per point, the fast path of a fixed tool (`tool_rotation = I`).
#[inline(always)]
#[must_use]
pub fn is_identity(m: &Mat3) -> bool {
    let one = 1f64.to_bits();
    let [a, b, c] = m.data.0;
    ((a[0].to_bits() ^ one)
        | a[1].to_bits()
        | a[2].to_bits()
        | b[0].to_bits()
        | (b[1].to_bits() ^ one)
        | b[2].to_bits()
        | c[0].to_bits()
        | c[1].to_bits()
        | (c[2].to_bits() ^ one))
        == 0
}

/// Apply the minimal rotation that takes unit vector `a` to unit vector `b`
/// (rotation about `a × b`) to `v`. Exact for all `a ≠ -b`; for antiparallel
/// normals (no unique minimal rotation) `v` is returned unchanged.
#[inline]
#[must_use]
pub fn rotate_minimal(a: &Vec3, b: &Vec3, v: &Vec3) -> Vec3 {
    let c = a.dot(b);
    if c <= -1.0 + 1e-14 {
        return *v;
    }
    let k = a.cross(b);
    // Rodrigues with sinθ = |k|, cosθ = c, axis k/|k|:
    // R v = v c + (k × v) + k (k·v) / (1 + c).
    v * c + k.cross(v) + k * (k.dot(v) / (1.0 + c))
}

/// Cayley map `(I - ½A)⁻¹(I + ½A)` (Hughes–Winget): an exact rotation when `A`
/// is skew; for a mid-step displacement gradient `A = Δt L` it reproduces the
/// step deformation gradient exactly. Returns the identity if `I - ½A` is singular.
#[inline]
#[must_use]
pub fn cayley(a: &Mat3) -> Mat3 {
    let half = 0.5 * a;
    let lhs = Mat3::identity() - half;
    match lhs.try_inverse() {
        Some(inv) => inv * (Mat3::identity() + half),
        None => Mat3::identity(),
    }
}

/// `cay([a]×) v` for the skew matrix of `a`, i.e. the Hughes–Winget rotation
/// `(I - ½Δt W)⁻¹(I + ½Δt W) v` with `a = ½Δt w` (`w` the axial vector of `W`),
/// in closed form (Gibbs–Rodrigues parameters): `v + 2 (a × v + a × (a × v))/(1 + a·a)`.
/// Equal to [`cayley`] of the skew matrix, without a matrix inverse.
#[inline]
#[must_use]
pub fn cayley_rotate(a: &Vec3, v: &Vec3) -> Vec3 {
    let av = a.cross(v);
    v + (av + a.cross(&av)) * (2.0 / (1.0 + a.norm_squared()))
}

/// Closed-form material rate of the traction direction `φ = t/|t|`, `t = (I - n⊗n) T`
/// (friction-math §4): `ṫ = (I - n⊗n) Ṫ - (ṅ⊗n + n⊗ṅ) T`,
/// `φ̇ = (I - φ⊗φ) ṫ / |t|`. Returns `None` when `|t| = 0` (no direction).
#[inline]
#[must_use]
pub fn direction_rate(
    traction: &Vec3,
    traction_rate: &Vec3,
    n: &Vec3,
    n_rate: &Vec3,
) -> Option<Vec3> {
    let t = tangent_part(n, traction);
    let norm = t.norm();
    if norm == 0.0 || !norm.is_finite() {
        return None;
    }
    let phi = t / norm;
    let t_rate =
        tangent_part(n, traction_rate) - (n_rate * n.dot(traction) + n * n_rate.dot(traction));
    Some((t_rate - phi * phi.dot(&t_rate)) / norm)
}

/// Forward estimate of the slip direction in the frame of step `n+1`
/// (friction-math §4 (b), `d = φ_n + Δt φ̇_n`), evaluated from objective
/// quantities only: the transported history `t*` and the end-of-step traction
/// `t_end`, both tangent to `n_new`. In that co-moving frame the normal is at
/// rest, so the closed-form rate is [`direction_rate`] with `ṅ = 0` and
/// `Δt Ṫ = t_end - t*`:
///
/// `d = φ* + (I - φ*⊗φ*) (t_end - t*) / |t*|`.
///
/// The spin, convection or surface rotation of each formulation enters through
/// its own `t*`. Returns `None` when `|t*| = 0`.
#[inline]
#[must_use]
pub fn forward_direction(t_star: &Vec3, t_end: &Vec3, n_new: &Vec3) -> Option<Vec3> {
    // Both vectors are tangent to `n_new`, so `direction_rate` with `ṅ = 0`
    // reduces to `φ̇ Δt = (I - φ*⊗φ*)(t_end - t*)/|t*|`; the projection onto the
    // plane of `n_new` is kept for inputs that are not exactly tangent.
    let t = tangent_part(n_new, t_star);
    let norm = t.norm();
    if norm == 0.0 || !norm.is_finite() {
        return None;
    }
    let inv = norm.recip();
    let phi = t * inv;
    let dt_rate = tangent_part(n_new, t_end) - t;
    Some(phi + (dt_rate - phi * phi.dot(&dt_rate)) * inv)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn minimal_rotation_maps_a_to_b_and_preserves_length() {
        let a = Vec3::new(0.0, 0.0, 1.0);
        let b = Vec3::new(0.3, -0.2, 0.9).normalize();
        let r = rotate_minimal(&a, &b, &a);
        assert!((r - b).norm() < 1e-15);
        let v = Vec3::new(1.0, 2.0, 0.0);
        assert!((rotate_minimal(&a, &b, &v).norm() - v.norm()).abs() < 1e-14);
        // Tangent vectors stay tangent.
        assert!(rotate_minimal(&a, &b, &v).dot(&b).abs() < 1e-14);
    }

    #[test]
    fn cayley_of_skew_is_a_rotation() {
        let r = cayley(&skew(&Vec3::new(0.1, -0.4, 0.2)));
        assert!((r.transpose() * r - Mat3::identity()).norm() < 1e-14);
        assert!((r.determinant() - 1.0).abs() < 1e-14);
    }

    #[test]
    fn closed_form_cayley_rotation_equals_the_matrix_cayley_map() {
        for w in [
            Vec3::new(0.1, -0.4, 0.2),
            Vec3::new(3.0, 1.0, -2.0),
            Vec3::zeros(),
        ] {
            let v = Vec3::new(0.7, -1.3, 2.1);
            let matrix = cayley(&skew(&w)) * v;
            let closed = cayley_rotate(&(0.5 * w), &v);
            assert!(
                (matrix - closed).norm() <= 1e-14 * v.norm(),
                "{matrix} vs {closed}"
            );
        }
    }

    #[test]
    fn forward_direction_is_the_closed_form_rate_in_the_co_moving_frame() {
        let n = Vec3::new(0.1, -0.2, 1.0).normalize();
        let t_star = Vec3::new(3.0, 1.0, 0.0) - n * n.dot(&Vec3::new(3.0, 1.0, 0.0));
        let t_end = Vec3::new(2.0, 2.5, 0.0) - n * n.dot(&Vec3::new(2.0, 2.5, 0.0));
        let via_rate = t_star / t_star.norm()
            + direction_rate(&t_star, &(t_end - t_star), &n, &Vec3::zeros()).unwrap();
        let direct = forward_direction(&t_star, &t_end, &n).unwrap();
        assert!((via_rate - direct).norm() < 1e-15, "{via_rate} vs {direct}");
        assert_eq!(forward_direction(&Vec3::zeros(), &t_end, &n), None);
    }

    /// friction-math §4: the closed-form `φ̇` must agree with central finite
    /// differences of `φ(t)` along a smooth history to 1e-6 relative.
    #[test]
    fn direction_rate_matches_central_differences_along_smooth_history() {
        let traction = |s: f64| {
            Vec3::new(
                3.0 * s.cos() + 0.5,
                2.0 * (1.3 * s).sin() - 0.7,
                -40.0 + 5.0 * s,
            )
        };
        let traction_rate = |s: f64| Vec3::new(-3.0 * s.sin(), 2.6 * (1.3 * s).cos(), 5.0);
        let normal = |s: f64| Vec3::new(0.2 * s.sin(), 0.3 * (0.7 * s).cos(), 1.0).normalize();
        let phi = |s: f64| {
            let n = normal(s);
            let t = traction(s) - n * n.dot(&traction(s));
            t / t.norm()
        };
        for i in 0..20 {
            let s = -1.0 + 0.1 * f64::from(i);
            let h = 1e-5;
            let n_rate = (normal(s + h) - normal(s - h)) / (2.0 * h);
            let fd = (phi(s + h) - phi(s - h)) / (2.0 * h);
            let exact =
                direction_rate(&traction(s), &traction_rate(s), &normal(s), &n_rate).unwrap();
            assert!(
                (fd - exact).norm() <= 1e-6 * exact.norm().max(1e-3),
                "s = {s}: {fd} vs {exact}"
            );
        }
    }
}
