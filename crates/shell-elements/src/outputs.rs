//! Per-element outputs: logarithmic membrane strain (from the deformation gradient), thickness, plastic strain, stresses.

use crate::geometry::{Frame, V3};

/// Logarithmic (Hencky) membrane strain of an element's mid-surface.
///
/// Computed from the in-plane deformation gradient `F` at the element centre
/// between the reference (`x0`) and current (`x`) configurations, each
/// expressed in its own co-rotational frame: `ε = ½ ln(F Fᵀ)` (Eulerian),
/// so it is exact for any path and rigid rotation (no accumulation of
/// increments).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LogStrain {
    /// `[ε_xx, ε_yy, ε_xy]` (tensor shear) in the current co-rotational frame (-).
    pub tensor: [f64; 3],
    /// Major principal strain (-).
    pub major: f64,
    /// Minor principal strain (-).
    pub minor: f64,
    /// Direction of the major strain, unit vector in the global frame.
    pub major_direction: V3,
}

/// Eigen-decomposition of a symmetric 2×2 `[a, b; b, c]`: (λ1 ≥ λ2, angle of λ1's vector).
fn sym2_eigen(a: f64, b: f64, c: f64) -> (f64, f64, f64) {
    let m = 0.5 * (a + c);
    let r = (0.25 * (a - c) * (a - c) + b * b).sqrt();
    let angle = 0.5 * (2.0 * b).atan2(a - c);
    (m + r, m - r, angle)
}

pub(crate) fn log_membrane_strain(x0: &[V3; 4], x: &[V3; 4]) -> LogStrain {
    let f0 = Frame::new(x0);
    let f1 = Frame::new(x);
    let (b1, b2, _) = crate::geometry::b_matrix(&f0, 0.0, 0.0);
    // F[a][b] = Σ x̂_a,I ∂N_I/∂X_b.
    let mut f = [[0.0; 2]; 2];
    for i in 0..4 {
        f[0][0] += f1.x[i] * b1[i];
        f[0][1] += f1.x[i] * b2[i];
        f[1][0] += f1.y[i] * b1[i];
        f[1][1] += f1.y[i] * b2[i];
    }
    // b = F Fᵀ.
    let bxx = f[0][0] * f[0][0] + f[0][1] * f[0][1];
    let byy = f[1][0] * f[1][0] + f[1][1] * f[1][1];
    let bxy = f[0][0] * f[1][0] + f[0][1] * f[1][1];
    let (l1, l2, ang) = sym2_eigen(bxx, bxy, byy);
    let (e1, e2) = (0.5 * l1.ln(), 0.5 * l2.ln());
    let (c, s) = (ang.cos(), ang.sin());
    let tensor = [
        e1 * c * c + e2 * s * s,
        e1 * s * s + e2 * c * c,
        (e1 - e2) * c * s,
    ];
    LogStrain {
        tensor,
        major: e1,
        minor: e2,
        major_direction: f1.global([c, s, 0.0]),
    }
}

/// Everything a post-processor reads from one element.
#[derive(Debug, Clone, PartialEq)]
pub struct ShellElementOutput {
    /// Logarithmic membrane strain and its principal values.
    pub strain: LogStrain,
    /// Current thickness (mm).
    pub thickness: f64,
    /// Logarithmic thickness strain ln(t/t0) (-).
    pub thickness_strain: f64,
    /// Equivalent plastic strain, mean over the element's points (-).
    pub plastic_strain_mean: f64,
    /// Equivalent plastic strain, largest over the element's points (-).
    pub plastic_strain_max: f64,
    /// Von Mises stress at every point (MPa), in-plane point major, bottom to top.
    pub von_mises: Vec<f64>,
    /// Flow stress at the outer fibres `[bottom, top]` (MPa).
    pub outer_flow_stress: [f64; 2],
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rigidly rotated, biaxially stretched square: ε = (ln 1.2, ln 0.9), exact to 1e-12.
    #[test]
    fn log_strain_of_stretched_and_rotated_square_is_exact() {
        let x0 = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let (a, b) = (0.7f64, 0.4f64);
        let rot = |p: V3| {
            // stretch, then rotate about z by a and about x by b
            let q = [1.2 * p[0], 0.9 * p[1], 0.0];
            let r = [
                q[0] * a.cos() - q[1] * a.sin(),
                q[0] * a.sin() + q[1] * a.cos(),
                0.0,
            ];
            [r[0], r[1] * b.cos(), r[1] * b.sin()]
        };
        let x = x0.map(rot);
        let s = log_membrane_strain(&x0, &x);
        assert!((s.major - 1.2f64.ln()).abs() < 1e-12);
        assert!((s.minor - 0.9f64.ln()).abs() < 1e-12);
        let d = s.major_direction;
        assert!((d[0] - a.cos()).abs() < 1e-12 && (d[1] - a.sin() * b.cos()).abs() < 1e-12);
    }
}
