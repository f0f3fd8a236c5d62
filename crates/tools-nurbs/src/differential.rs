//! Differential geometry at a surface point: oriented normal, tangent frame, Weingarten curvature tensor.
//!
//! Sign convention (the one `plugins_api::Projection` documents): `K = ∇_s n`
//! with `n` the *oriented* normal (towards the blank). In the tangent basis
//! `S_u, S_v`, `S_a · K · S_b = S_a · ∂_b n = -S_ab · n = -II_ab`, so
//! `K = -J I⁻¹ II I⁻¹ Jᵀ` with `J = [S_u S_v]`, `I` and `II` the first and
//! second fundamental forms (II taken with the oriented normal). A sphere of
//! radius `R` seen from outside with the outward normal has
//! `K = (1/R)(I - n⊗n)`: positive principal curvatures mean the surface
//! bends away from the blank (a punch nose); a concave surface seen from its
//! inside (a die cavity fillet seen from the blank) has negative ones.

use crate::surface::Derivs;
use plugins_api::{Mat3, Vec3};

/// Oriented normal, tangent frame and curvature at one surface point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalGeometry {
    /// Unit normal towards the blank side.
    pub normal: Vec3,
    /// Unit tangent along `S_u`.
    pub e1: Vec3,
    /// Unit tangent `n × e1` (right-handed frame `e1, e2, n`).
    pub e2: Vec3,
    /// Curvature tensor `K = ∇_s n` (1/mm), symmetric, `K n = 0`.
    pub curvature: Mat3,
    /// Larger principal curvature (1/mm).
    pub k1: f64,
    /// Smaller principal curvature (1/mm).
    pub k2: f64,
}

/// The geometry at `d`; `sign = ±1` orients `S_u × S_v` towards the blank.
#[inline]
pub fn local_geometry(d: &Derivs, sign: f64) -> LocalGeometry {
    local_geometry_rotated(d, sign, None)
}

/// [`local_geometry`] with the frame and the tensor mapped by the rotation
/// `rot` (a tool's pose, local → global) when one is given: the tensor is
/// assembled once, directly in the rotated frame, from the rotated tangents
/// (`R K Rᵀ` without the two matrix products).
#[inline(always)]
pub fn local_geometry_rotated(d: &Derivs, sign: f64, rot: Option<&Mat3>) -> LocalGeometry {
    let cross = d.su.cross(&d.sv);
    // |S_u × S_v|⁻¹ once: it scales the normal and gives b22 below.
    let ic = 1.0 / cross.norm();
    let normal = cross * (sign * ic);
    let lu = d.su.norm();
    let i11 = 1.0 / lu;
    let e1 = d.su * i11;
    let e2 = normal.cross(&e1);
    // J = T B with T = [e1 e2], B upper triangular: b11 = |S_u|,
    // b12 = S_v · e1, b22 = S_v · e2 = n · (S_u × S_v) / |S_u| = sign |S_u × S_v| / |S_u|.
    let b12 = d.sv.dot(&d.su) * i11;
    let l = d.suu.dot(&normal);
    let m = d.suv.dot(&normal);
    let nn = d.svv.dot(&normal);
    let (normal, e1, e2) = match rot {
        Some(rot) => (rot * normal, rot * e1, rot * e2),
        None => (normal, e1, e2),
    };
    if l == 0.0 && m == 0.0 && nn == 0.0 {
        // Flat to rounding (a plane's zero second derivatives): K = 0.
        return LocalGeometry {
            normal,
            e1,
            e2,
            curvature: Mat3::zeros(),
            k1: 0.0,
            k2: 0.0,
        };
    }
    // A = -B⁻ᵀ II B⁻¹, with B⁻¹ = [[1/b11, -b12/(b11 b22)], [0, 1/b22]].
    let i22 = sign * lu * ic;
    let i12 = -b12 * i11 * i22;
    // C = II B⁻¹ (first row and the second column are what A needs).
    let c11 = l * i11;
    let c12 = l * i12 + m * i22;
    let c22 = m * i12 + nn * i22;
    // A = -(B⁻ᵀ C)
    let a11 = -(i11 * c11);
    let a12 = -(i11 * c12);
    let a22 = -(i12 * c12 + i22 * c22);
    let mean = 0.5 * (a11 + a22);
    let r = (0.25 * (a11 - a22) * (a11 - a22) + a12 * a12).sqrt();
    // K = a11 e1⊗e1 + a12 (e1⊗e2 + e2⊗e1) + a22 e2⊗e2 = e1⊗f + e2⊗g with
    // f = a11 e1 + a12 e2, g = a12 e1 + a22 e2; symmetric.
    let f = e1 * a11 + e2 * a12;
    let g = e1 * a12 + e2 * a22;
    let k = |i: usize, j: usize| e1[i] * f[j] + e2[i] * g[j];
    let (k00, k01, k02, k11, k12, k22) = (k(0, 0), k(0, 1), k(0, 2), k(1, 1), k(1, 2), k(2, 2));
    let curvature = Mat3::new(k00, k01, k02, k01, k11, k12, k02, k12, k22);
    LocalGeometry {
        normal,
        e1,
        e2,
        curvature,
        k1: mean + r,
        k2: mean - r,
    }
}
