//! `J2PlaneStress`: von Mises plasticity under plane stress with isotropic hardening (Simo–Taylor projected return).
//!
//! The return mapping works on the plane-stress subspace directly (Simo &
//! Taylor 1986; Simo & Hughes, *Computational Inelasticity*, §3.4): with
//! `P` the plane-stress deviatoric projector and `C` the plane-stress
//! elasticity, the updated stress is `σ = (C⁻¹ + Δλ P)⁻¹ C⁻¹ σ_trial`, which
//! is diagonal in the basis `p = (σ_xx+σ_yy)/√2`, `q = (σ_xx−σ_yy)/√2`, `σ_xy`:
//!
//! `p = p_tr / (1 + E Δλ / (3(1−ν)))`, `q = q_tr / (1 + 2G Δλ)`,
//! `σ_xy = σ_xy,tr / (1 + 2G Δλ)`.
//!
//! The scalar `Δλ` solves `½ σᵀPσ − ⅓ σ_y²(ε_p + Δλ √(⅔ σᵀPσ)) = 0` by a
//! local Newton iteration (relative tolerance 1e-12 on the yield function).
//! σ_zz = 0 holds by construction; the thickness strain increment is
//! `Δε_zz = −ν/(1−ν)(Δε_xx + Δε_yy − Δε^p_xx − Δε^p_yy) − (Δε^p_xx + Δε^p_yy)`.

use super::{Hardening, Material, PointUpdate, von_mises};
use crate::error::{ShellError, check};

/// Isotropic plane-stress J2 plasticity with a [`Hardening`] curve.
#[derive(Debug, Clone, PartialEq)]
pub struct J2PlaneStress {
    young: f64,
    poisson: f64,
    density: f64,
    hardening: Hardening,
    // Derived constants.
    shear: f64,
    c11: f64,
    c12: f64,
    a_p: f64,
}

/// History of one integration point of [`J2PlaneStress`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct J2History {
    /// Equivalent plastic strain ε_p (-).
    pub eps_p: f64,
    /// Flow stress at `eps_p` (MPa), cached so that an elastic step costs no hardening evaluation.
    pub sigma_y: f64,
}

impl J2PlaneStress {
    /// A validated material: `young` E (MPa) > 0, `poisson` ν in [0, 0.5),
    /// `density` ρ (tonne/mm³) > 0, and a valid hardening curve.
    pub fn new(
        young: f64,
        poisson: f64,
        density: f64,
        hardening: Hardening,
    ) -> Result<Self, ShellError> {
        check("young", young, "MPa", "> 0", young > 0.0)?;
        check(
            "poisson",
            poisson,
            "-",
            "in [0, 0.5)",
            (0.0..0.5).contains(&poisson),
        )?;
        check("density", density, "tonne/mm^3", "> 0", density > 0.0)?;
        hardening.validate()?;
        let c11 = young / (1.0 - poisson * poisson);
        Ok(Self {
            young,
            poisson,
            density,
            hardening,
            shear: young / (2.0 * (1.0 + poisson)),
            c11,
            c12: poisson * c11,
            a_p: young / (3.0 * (1.0 - poisson)),
        })
    }

    /// The hardening curve.
    pub fn hardening(&self) -> &Hardening {
        &self.hardening
    }
}

impl Material for J2PlaneStress {
    type History = J2History;

    fn name(&self) -> &'static str {
        "j2-plane-stress"
    }
    fn density(&self) -> f64 {
        self.density
    }
    fn young(&self) -> f64 {
        self.young
    }
    fn poisson(&self) -> f64 {
        self.poisson
    }
    fn shear_modulus(&self) -> f64 {
        self.shear
    }
    fn initial_history(&self) -> J2History {
        J2History {
            eps_p: 0.0,
            sigma_y: self.hardening.eval(0.0).0,
        }
    }
    fn plastic_strain(&self, h: &J2History) -> f64 {
        h.eps_p
    }
    fn flow_stress(&self, h: &J2History) -> f64 {
        h.sigma_y
    }

    #[inline]
    fn update(&self, s: &mut [f64; 3], h: &mut J2History, de: [f64; 3]) -> PointUpdate {
        let nu = self.poisson;
        let g = self.shear;
        // Elastic trial.
        let t0 = s[0] + self.c11 * de[0] + self.c12 * de[1];
        let t1 = s[1] + self.c12 * de[0] + self.c11 * de[1];
        let t2 = s[2] + g * de[2];
        let vm2 = t0 * t0 + t1 * t1 - t0 * t1 + 3.0 * t2 * t2;
        let sy0 = h.sigma_y;
        if vm2 <= sy0 * sy0 {
            *s = [t0, t1, t2];
            return PointUpdate {
                deps_zz: -nu / (1.0 - nu) * (de[0] + de[1]),
                dissipation: 0.0,
            };
        }
        // Projected return: Newton on Δλ.
        let sum = t0 + t1;
        let dif = t0 - t1;
        let a1 = sum * sum / 6.0; // p_tr² / 3
        let a2 = 0.5 * dif * dif + 2.0 * t2 * t2; // q_tr² + 2 σ_xy²
        let ap = self.a_p;
        let g2 = 2.0 * g;
        let r23 = (2.0f64 / 3.0).sqrt();
        let mut dl = 0.0f64;
        let mut sy = sy0;
        let mut eps = h.eps_p;
        let tol = 1e-12 * sy0 * sy0;
        for _ in 0..60 {
            let f1 = 1.0 / (1.0 + ap * dl);
            let f2 = 1.0 / (1.0 + g2 * dl);
            let phi2 = a1 * f1 * f1 + a2 * f2 * f2;
            let phi = phi2.sqrt();
            let d = dl * r23 * phi;
            eps = h.eps_p + d;
            let (y, hm) = self.hardening.eval_from(h.eps_p, sy0, d);
            sy = y;
            let f = 0.5 * phi2 - y * y / 3.0;
            if f.abs() <= tol {
                break;
            }
            let dphi2 = -2.0 * ap * a1 * f1 * f1 * f1 - 2.0 * g2 * a2 * f2 * f2 * f2;
            let deps = r23 * (phi + dl * 0.5 * dphi2 / phi);
            let df = 0.5 * dphi2 - (2.0 / 3.0) * y * hm * deps;
            let next = dl - f / df;
            dl = if next > 0.0 { next } else { 0.5 * dl };
        }
        let f1 = 1.0 / (1.0 + ap * dl);
        let f2 = 1.0 / (1.0 + g2 * dl);
        let ps = 0.5 * sum * f1;
        let qs = 0.5 * dif * f2;
        *s = [ps + qs, ps - qs, t2 * f2];
        let deps_p = eps - h.eps_p;
        h.eps_p = eps;
        h.sigma_y = sy;
        // Δε^p = Δλ P σ: its in-plane trace is Δλ (σ_xx + σ_yy) / 3.
        let tr_p = dl * (s[0] + s[1]) / 3.0;
        PointUpdate {
            deps_zz: -nu / (1.0 - nu) * (de[0] + de[1] - tr_p) - tr_p,
            dissipation: sy * deps_p,
        }
    }

    fn equivalent_stress(&self, s: &[f64; 3]) -> f64 {
        von_mises(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn steel() -> J2PlaneStress {
        J2PlaneStress::new(
            206_000.0,
            0.3,
            7.85e-9,
            Hardening::swift(565.32, 0.007117, 0.2589).unwrap(),
        )
        .unwrap()
    }

    #[test]
    fn parameters_out_of_range_name_the_field() {
        let h = Hardening::swift(500.0, 0.01, 0.2).unwrap();
        let e = J2PlaneStress::new(206e3, 0.5, 7.85e-9, h.clone()).unwrap_err();
        assert!(e.to_string().contains("`poisson` = 0.5"), "{e}");
        let e = J2PlaneStress::new(-1.0, 0.3, 7.85e-9, h.clone()).unwrap_err();
        assert!(e.to_string().contains("young") && e.to_string().contains("MPa"));
        assert!(J2PlaneStress::new(206e3, 0.3, 0.0, h).is_err());
    }

    /// After a plastic step the stress lies on the yield surface (|σ_vm − σ_y| ≤ 1e-9 σ_y)
    /// and the plastic dissipation equals σ:Δε^p (consistency of the return, Simo & Hughes §3.4).
    #[test]
    fn return_mapping_lands_on_the_yield_surface_for_large_increments() {
        let m = steel();
        for de in [
            [0.01, 0.0, 0.0],
            [0.02, -0.005, 0.01],
            [-0.01, -0.01, 0.0],
            [0.0, 0.0, 0.05],
        ] {
            let mut s = [0.0; 3];
            let mut h = m.initial_history();
            let u = m.update(&mut s, &mut h, de);
            let vm = von_mises(&s);
            assert!(
                (vm - h.sigma_y).abs() <= 1e-9 * h.sigma_y,
                "{de:?}: {vm} vs {}",
                h.sigma_y
            );
            assert!(h.eps_p > 0.0 && u.dissipation > 0.0);
            // Total in-plane + normal strain: the plastic part is isochoric.
            let e = m.young;
            let nu = m.poisson;
            let ee = [
                (s[0] - nu * s[1]) / e,
                (s[1] - nu * s[0]) / e,
                -nu / e * (s[0] + s[1]),
            ];
            let plastic_trace = (de[0] - ee[0]) + (de[1] - ee[1]) + (u.deps_zz - ee[2]);
            assert!(plastic_trace.abs() < 1e-12, "{plastic_trace}");
        }
    }

    /// Consistent with finite differences: the return is a function of the
    /// strain increment alone, so splitting a proportional increment into
    /// many small ones converges to the single-step answer for radial paths
    /// (radial return is exact for proportional loading, Simo & Hughes §3.4).
    #[test]
    fn proportional_path_is_step_size_independent() {
        let m = steel();
        let de = [0.02, -0.01, 0.0];
        let (mut s1, mut h1) = ([0.0; 3], m.initial_history());
        m.update(&mut s1, &mut h1, de);
        let (mut s2, mut h2) = ([0.0; 3], m.initial_history());
        for _ in 0..1000 {
            m.update(&mut s2, &mut h2, [de[0] / 1000.0, de[1] / 1000.0, 0.0]);
        }
        // Not exactly radial (the trial direction rotates in the elastic range): 1 %.
        assert!(
            (h1.eps_p - h2.eps_p).abs() < 0.01 * h2.eps_p,
            "{} {}",
            h1.eps_p,
            h2.eps_p
        );
    }
}
