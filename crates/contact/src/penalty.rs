//! Normal enforcement: the penalty stiffness of each blank node and optional normal damping.
//!
//! The nodal stiffness follows the blank's own element stiffness, as explicit
//! codes do for shells: `k_i = s · K · A_i / d_i` (N/mm), with `K = E / (3 (1 − 2ν))`
//! the bulk modulus of the blank material, `A_i` the node's tributary area in the
//! initial mesh, `d_i` the longest diagonal of the quads around the node, and `s`
//! the scale factor (`penalty_scale`, default 0.1). With `s ≤ 1` the contact
//! spring is no stiffer than the membrane it presses on, so it does not lower the
//! stable time step noticeably. Normal damping (`damping`, a fraction of critical
//! damping of the node's mass on its contact spring) acts only while the node
//! penetrates and never pulls.

use plugins_api::Vec3;

use crate::{BlankGeometry, ContactError};

/// Settings of the normal enforcement of a contact pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PenaltySettings {
    /// Scale factor `s` of the nodal penalty stiffness (-), `> 0`; default 0.1.
    pub scale: f64,
    /// Normal damping as a fraction of critical (-), in `[0, 1]`; default 0.
    pub damping: f64,
}

impl Default for PenaltySettings {
    fn default() -> Self {
        Self {
            scale: 0.1,
            damping: 0.0,
        }
    }
}

impl PenaltySettings {
    /// Check the ranges, naming the pair.
    ///
    /// # Errors
    /// `scale ≤ 0` or not finite; `damping` outside `[0, 1]`.
    pub fn validate(&self, pair: &str) -> Result<(), ContactError> {
        if !(self.scale > 0.0 && self.scale.is_finite()) {
            return Err(ContactError::OutOfRange {
                pair: pair.into(),
                field: "penalty_scale",
                value: self.scale,
                unit: "-",
                range: "> 0 and finite",
            });
        }
        if !(0.0..=1.0).contains(&self.damping) {
            return Err(ContactError::OutOfRange {
                pair: pair.into(),
                field: "damping",
                value: self.damping,
                unit: "(fraction of critical)",
                range: "in [0, 1]",
            });
        }
        Ok(())
    }
}

/// Nodal penalty stiffness `k_i = s K A_i / d_i` (N/mm) of the initial mesh `x0`.
///
/// # Errors
/// A non-positive or non-finite bulk modulus.
pub fn nodal_stiffness(
    geometry: &BlankGeometry,
    x0: &[Vec3],
    bulk_modulus: f64,
    settings: &PenaltySettings,
    pair: &str,
) -> Result<Vec<f64>, ContactError> {
    if !(bulk_modulus > 0.0 && bulk_modulus.is_finite()) {
        return Err(ContactError::OutOfRange {
            pair: pair.into(),
            field: "bulk_modulus",
            value: bulk_modulus,
            unit: "MPa",
            range: "> 0 (from the blank material: E / (3 (1 - 2 nu)))",
        });
    }
    settings.validate(pair)?;
    let mut g = geometry.clone();
    g.update_areas(x0);
    let quads = g.quads();
    let diag: Vec<f64> = quads
        .iter()
        .map(|q| {
            let d1 = (x0[q[2] as usize] - x0[q[0] as usize]).norm();
            let d2 = (x0[q[3] as usize] - x0[q[1] as usize]).norm();
            d1.max(d2)
        })
        .collect();
    Ok((0..g.node_count())
        .map(|i| {
            let d = g
                .quads_around(i)
                .iter()
                .map(|&e| diag[e as usize])
                .fold(0.0, f64::max);
            if d > 0.0 {
                settings.scale * bulk_modulus * g.area[i] / d
            } else {
                0.0
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_mesh_stiffness_and_bad_settings() {
        // 1 mm squares: interior node area 1, diagonal √2.
        let mut x = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                x.push(Vec3::new(i as f64, j as f64, 0.0));
            }
        }
        let quads = [[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
        let g = BlankGeometry::new(9, &quads).unwrap();
        let k = nodal_stiffness(&g, &x, 1000.0, &PenaltySettings::default(), "p").unwrap();
        assert!((k[4] - 0.1 * 1000.0 / 2f64.sqrt()).abs() < 1e-12);
        assert!((k[0] - 0.1 * 1000.0 * 0.25 / 2f64.sqrt()).abs() < 1e-12);
        let bad = PenaltySettings {
            scale: -1.0,
            damping: 0.0,
        };
        let e = nodal_stiffness(&g, &x, 1000.0, &bad, "punch-blank").unwrap_err();
        assert!(e.to_string().contains("`penalty_scale` = -1"), "{e}");
        let e = nodal_stiffness(&g, &x, f64::NAN, &PenaltySettings::default(), "p").unwrap_err();
        assert!(e.to_string().contains("bulk_modulus"), "{e}");
    }
}
