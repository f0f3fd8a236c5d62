//! # j2-voce: an example formsim user-material plugin
//!
//! Plane-stress J2 (von Mises) plasticity with isotropic Voce hardening,
//!
//! ```text
//! σ_y(ε_p) = σ_0 + Q (1 - exp(-b ε_p)) + H ε_p
//! ```
//!
//! integrated by the plane-stress return mapping of Simo & Taylor (1986;
//! Simo & Hughes, *Computational Inelasticity*, 1998, §3.4). In the frame of
//! the element, with the trial stress `σ*` (elastic predictor) and the plastic
//! multiplier `Δγ`,
//!
//! ```text
//! σ_xx + σ_yy = (σ*_xx + σ*_yy) / (1 + E Δγ / (3(1-ν)))
//! σ_yy - σ_xx = (σ*_yy - σ*_xx) / (1 + 2G Δγ),   σ_xy = σ*_xy / (1 + 2G Δγ)
//! f̄²(Δγ) = σᵀPσ = (2/3) σ_vm²,   Δε_p = Δγ √(2/3) f̄
//! ½ f̄²(Δγ) - ⅓ σ_y²(ε_p + Δε_p) = 0        (solved for Δγ: Newton, bracketed)
//! ```
//!
//! The state is one variable, the equivalent plastic strain `ε_p`. The
//! dissipation is the plastic work `σ_y Δε_p`; the thickness strain
//! `Δε_zz = -(ν/E)(Δσ_xx+Δσ_yy) - Δγ (σ_xx+σ_yy)/3` (elastic plus plastic,
//! the plastic flow being isochoric).
//!
//! The crate depends on `plugins-api` alone; `export_material!` turns it into
//! a shared library that formsim loads at run time (`plugins/README.md`).

mod material;

pub use material::J2Voce;

plugins_api::export_material!(J2Voce);

#[cfg(test)]
mod tests {
    use super::*;
    use plugins_api::Params;
    use plugins_api::material::conformance::check_material;
    use plugins_api::material::loader::MaterialLibrary;
    use plugins_api::material::{PointResult, UserMaterial};

    /// A mild steel-like set (MPa, tonne/mm³).
    fn params() -> Params {
        Params::new()
            .with("youngs_modulus", 206_000.0)
            .with("density", 7.85e-9)
            .with("sigma0", 170.0)
            .with("q", 250.0)
            .with("b", 9.0)
            .with("h", 100.0)
    }

    /// The material passes every check of the suite through its own table.
    #[test]
    fn j2_voce_passes_the_material_conformance_suite() {
        let lib = MaterialLibrary::linked::<J2Voce>().expect("table");
        let m = lib.build(&params()).expect("material");
        let report = check_material(&m);
        assert!(report.passed(), "{report}");
    }

    /// Uniaxial tension to ε_p: σ_xx follows σ_y(ε_p) of the Voce law (the
    /// closed form) to 1e-9, driven through the table with σ_yy = 0 held by
    /// the increment's lateral strain.
    #[test]
    fn uniaxial_tension_follows_the_voce_curve() {
        let lib = MaterialLibrary::linked::<J2Voce>().expect("table");
        let m = lib.build(&params()).expect("material");
        let law = J2Voce::from_values(&[206_000.0, 0.3, 7.85e-9, 170.0, 250.0, 9.0, 100.0])
            .expect("values");
        let (mut s, mut st) = ([0.0; 3], [0.0]);
        m.initial_state(&mut st).expect("state");
        for _ in 0..200 {
            // Lateral strain by secant so that σ_yy = 0.
            let dx = 2e-4;
            let try_it = |dy: f64| {
                let (mut s2, mut st2, mut r) = ([s], st, [PointResult::default()]);
                m.update(&[[dx, dy, 0.0]], &mut s2, &mut st2, &mut r)
                    .expect("update");
                (s2[0], st2, r[0])
            };
            let (mut a, mut b) = (-0.3 * dx, -0.5 * dx);
            for _ in 0..50 {
                let (fa, fb) = (try_it(a).0[1], try_it(b).0[1]);
                if fb.abs() < 1e-11 || fa == fb {
                    break;
                }
                (a, b) = (b, b - fb * (b - a) / (fb - fa));
            }
            let (s2, st2, r) = try_it(b);
            (s, st) = (s2, st2);
            let (sy, _) = law.hardening(st[0]);
            if st[0] == 0.0 {
                assert!(s[0] < sy, "elastic above yield: {} vs {sy}", s[0]);
                continue;
            }
            assert!((s[0] - sy).abs() <= 1e-9 * sy, "{} vs {sy}", s[0]);
            assert!((r.flow_stress - sy).abs() <= 1e-12 * sy);
        }
        assert!(st[0] > 0.035, "plastic strain {}", st[0]);
    }
}
