//! Plane-strain bending of a sheet and its elastic springback: the closed
//! forms and the through-thickness integrals that springback tests compare
//! with.
//!
//! A strip bent in plane strain (no strain across its width) to a uniform
//! curvature `κ` has the fibre strain `ε = κ z` at a distance `z` from its
//! mid-surface. For an incompressible J2 material (ν = ½, the idealisation of
//! Hill's plane-strain solution) the fibre stress is `σ = (2/√3) σ̄` with the
//! equivalent plastic strain `ε̄_p = (2/√3) ε_p`: elastic `σ = E′ ε`
//! (`E′ = E/(1 − ν²)`) up to the plane-strain yield stress
//! `S = (2/√3) σ_y(0)`, then on the hardening curve. The moment per unit
//! width is `M(κ) = 2 ∫₀^{t/2} σ(κ z) z dz`. Released, the strip unloads
//! elastically by `Δκ = M / (E′ I)` (`I = t³/12` per unit width), so its
//! curvature falls to `κ_f = κ − 12 M / (E′ t³)`.
//!
//! For an elastic–perfectly plastic sheet this is Gardiner's formula
//! (F. J. Gardiner, "The springback of metals", Trans. ASME 79, 1957,
//! pp. 1–9): with `x = S R / (E′ t)` and `R = 1/κ`,
//! `R / R_f = κ_f / κ = 1 − 3x + 4x³` ([`gardiner_ratio`]), valid while the
//! section has yielded (`x ≤ ½`). [`PlaneStrainStrip`] integrates any
//! [`Hardening`] curve (Swift, tabulated) the same way.

use crate::{Hardening, ShellError};

/// `2/√3`: the plane-strain factor on the yield stress and strain.
const PLANE_STRAIN: f64 = 1.154_700_538_379_251_5;

/// Gardiner's springback ratio `R/R_f = κ_f/κ = 1 − 3x + 4x³` of an
/// elastic–perfectly plastic sheet bent to the mid-surface radius `R`, with
/// `x = S R / (E′ t)` (`S` the plane-strain yield stress, `E′` the
/// plane-strain modulus, `t` the thickness). For `x ≥ ½` the section stayed
/// elastic and springs back flat (ratio 0).
#[must_use]
pub fn gardiner_ratio(x: f64) -> f64 {
    if x >= 0.5 {
        0.0
    } else {
        1.0 - 3.0 * x + 4.0 * x.powi(3)
    }
}

/// A strip of one material and thickness bent in plane strain.
#[derive(Debug, Clone)]
pub struct PlaneStrainStrip {
    /// Plane-strain modulus `E′ = E/(1 − ν²)` (MPa).
    e_ps: f64,
    /// Thickness (mm).
    thickness: f64,
    /// The hardening curve `σ_y(ε̄_p)`.
    hardening: Hardening,
}

/// A bend and its springback.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Springback {
    /// Moment per unit width at the bend (N·mm/mm).
    pub moment: f64,
    /// Curvature after release (1/mm).
    pub kappa_final: f64,
    /// `κ_f / κ = R / R_f`.
    pub ratio: f64,
}

impl PlaneStrainStrip {
    /// A strip of `young` (MPa), `poisson`, `thickness` (mm) and `hardening`.
    ///
    /// # Errors
    /// A modulus, Poisson's ratio or thickness out of range, naming it.
    pub fn new(
        young: f64,
        poisson: f64,
        thickness: f64,
        hardening: Hardening,
    ) -> Result<Self, ShellError> {
        let bad = |what: &str, v: f64, range: &str| {
            Err(ShellError::InvalidInput(format!(
                "plane-strain strip: {what} = {v} must be {range}"
            )))
        };
        if !(young.is_finite() && young > 0.0) {
            return bad("young (MPa)", young, "finite and > 0");
        }
        if !(poisson.is_finite() && (0.0..0.5).contains(&poisson)) {
            return bad("poisson", poisson, "in [0, 0.5)");
        }
        if !(thickness.is_finite() && thickness > 0.0) {
            return bad("thickness (mm)", thickness, "finite and > 0");
        }
        hardening.validate()?;
        Ok(Self {
            e_ps: young / (1.0 - poisson * poisson),
            thickness,
            hardening,
        })
    }

    /// The plane-strain modulus `E′` (MPa).
    #[must_use]
    pub fn plane_strain_modulus(&self) -> f64 {
        self.e_ps
    }

    /// The plane-strain yield stress `S = (2/√3) σ_y(0)` (MPa).
    #[must_use]
    pub fn plane_strain_yield(&self) -> f64 {
        PLANE_STRAIN * self.hardening.eval(0.0).0
    }

    /// The curvature at which the outer fibres yield, `2S/(E′ t)` (1/mm).
    #[must_use]
    pub fn first_yield_curvature(&self) -> f64 {
        2.0 * self.plane_strain_yield() / (self.e_ps * self.thickness)
    }

    /// The fibre stress (MPa) at the fibre strain `strain` of a monotonic
    /// bend: `E′ ε` below yield, else the root of
    /// `σ = (2/√3) σ_y((2/√3)(ε − σ/E′))`, odd in `ε`.
    #[must_use]
    pub fn fibre_stress(&self, strain: f64) -> f64 {
        let e = strain.abs();
        let s0 = self.plane_strain_yield();
        if self.e_ps * e <= s0 {
            return self.e_ps * strain;
        }
        // g(σ) = σ − (2/√3) σ_y(ε̄_p(σ)) rises with σ; its root lies in [s0, E′ε].
        let g =
            |s: f64| s - PLANE_STRAIN * self.hardening.eval(PLANE_STRAIN * (e - s / self.e_ps)).0;
        let (mut lo, mut hi) = (s0.min(self.e_ps * e), self.e_ps * e);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if g(mid) > 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
            if hi - lo <= 1e-14 * hi {
                break;
            }
        }
        (0.5 * (lo + hi)).copysign(strain)
    }

    /// The moment per unit width (N·mm/mm) at the curvature `kappa`:
    /// `2 ∫₀^{t/2} σ(κ z) z dz`, by composite Simpson on the elastic core and
    /// the plastic zone apart (the stress has a kink where they meet).
    #[must_use]
    pub fn moment(&self, kappa: f64) -> f64 {
        let h = 0.5 * self.thickness;
        let k = kappa.abs();
        let z_e = if k > 0.0 {
            (self.plane_strain_yield() / (self.e_ps * k)).min(h)
        } else {
            h
        };
        let f = |z: f64| self.fibre_stress(k * z) * z;
        let m = 2.0 * (simpson(&f, 0.0, z_e) + simpson(&f, z_e, h));
        m.copysign(kappa)
    }

    /// The springback of a bend to `kappa` (1/mm): elastic unloading by the
    /// moment.
    ///
    /// # Errors
    /// Unloading that yields the outer fibres in reverse (the residual stress
    /// there exceeds the flow stress they reached), where the elastic
    /// unloading assumed here no longer holds.
    pub fn springback(&self, kappa: f64) -> Result<Springback, ShellError> {
        let moment = self.moment(kappa);
        let dk = 12.0 * moment / (self.e_ps * self.thickness.powi(3));
        let h = 0.5 * self.thickness;
        let outer = self.fibre_stress(kappa * h);
        let residual = outer - self.e_ps * dk * h;
        if residual.abs() > outer.abs() * (1.0 + 1e-12) {
            return Err(ShellError::InvalidInput(format!(
                "plane-strain strip: unloading from κ = {kappa} 1/mm yields the outer fibres in reverse \
                 (residual {residual:.1} MPa against flow stress {outer:.1} MPa)"
            )));
        }
        Ok(Springback {
            moment,
            kappa_final: kappa - dk,
            ratio: (kappa - dk) / kappa,
        })
    }
}

/// `∫_a^b f` by composite Simpson on 2000 intervals (exact for cubics; the
/// stress is smooth on each part [`PlaneStrainStrip::moment`] gives it).
fn simpson(f: &impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    const N: usize = 2000;
    if b <= a {
        return 0.0;
    }
    let h = (b - a) / N as f64;
    let inner: f64 = (1..N)
        .map(|i| f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 })
        .sum();
    (f(a) + inner + f(b)) * h / 3.0
}

#[cfg(test)]
mod tests {
    use super::*;

    const E: f64 = 200_000.0;
    const NU: f64 = 0.3;
    const T: f64 = 1.0;
    const SY: f64 = 250.0;

    fn perfect() -> PlaneStrainStrip {
        PlaneStrainStrip::new(E, NU, T, Hardening::swift(SY, 1.0, 0.0).unwrap()).unwrap()
    }

    /// The integral reproduces the elastic–perfectly plastic moment in closed
    /// form, `M = (S t²/4)(1 − ⅓(κ_e/κ)²)` (Hill 1950, ch. VII), to 1e-9.
    #[test]
    fn perfectly_plastic_moment_is_hills() {
        let strip = perfect();
        let (s, ke) = (strip.plane_strain_yield(), strip.first_yield_curvature());
        for r in [1.0, 1.5, 3.0, 10.0, 100.0] {
            let m = strip.moment(r * ke);
            let exact = s * T * T / 4.0 * (1.0 - 1.0 / (3.0 * r * r));
            assert!(
                (m / exact - 1.0).abs() < 1e-9,
                "κ = {r} κ_e: {m} vs {exact}"
            );
        }
        let m = strip.moment(0.5 * ke);
        assert!((m / (s * T * T / 6.0 * 0.5) - 1.0).abs() < 1e-12, "{m}");
    }

    /// The integral's springback of a perfectly plastic strip is Gardiner's
    /// formula (Gardiner 1957) to 1e-9, and the ratio falls to 0 at first
    /// yield (`x = ½`).
    #[test]
    fn perfectly_plastic_springback_is_gardiners() {
        let strip = perfect();
        let (s, e) = (strip.plane_strain_yield(), strip.plane_strain_modulus());
        for radius in [10.0, 50.0, 100.0, 200.0] {
            let x = s * radius / (e * T);
            let got = strip.springback(1.0 / radius).unwrap().ratio;
            assert!(
                (got - gardiner_ratio(x)).abs() < 1e-9,
                "R = {radius} mm: {got} vs {}",
                gardiner_ratio(x)
            );
        }
        assert!(gardiner_ratio(0.5).abs() < 1e-15);
        let ke = strip.first_yield_curvature();
        assert!(strip.springback(ke).unwrap().ratio.abs() < 1e-9);
    }

    /// Hardening springs back more than perfect plasticity at the same
    /// curvature (a larger moment), and the fibre stress lies on the flow
    /// curve: `σ = (2/√3) σ_y((2/√3)(ε − σ/E′))` to 1e-10.
    #[test]
    fn swift_hardening_springs_back_more() {
        let swift =
            PlaneStrainStrip::new(E, NU, T, Hardening::swift(565.0, 0.007, 0.26).unwrap()).unwrap();
        let eps = 0.02;
        let s = swift.fibre_stress(eps);
        let flow = PLANE_STRAIN
            * Hardening::swift(565.0, 0.007, 0.26)
                .unwrap()
                .eval(PLANE_STRAIN * (eps - s / swift.plane_strain_modulus()))
                .0;
        assert!((s / flow - 1.0).abs() < 1e-10, "{s} vs {flow}");
        assert!((swift.fibre_stress(-eps) + s).abs() < 1e-9);
        let same_yield = PlaneStrainStrip::new(
            E,
            NU,
            T,
            Hardening::swift(swift.plane_strain_yield() / PLANE_STRAIN, 1.0, 0.0).unwrap(),
        )
        .unwrap();
        let k = 1.0 / 30.0;
        assert!(swift.springback(k).unwrap().ratio < same_yield.springback(k).unwrap().ratio);
    }

    /// Bad inputs name the field.
    #[test]
    fn bad_inputs_name_the_field() {
        let h = Hardening::swift(SY, 1.0, 0.0).unwrap();
        for (e, nu, t, says) in [
            (0.0, 0.3, 1.0, "young"),
            (E, 0.5, 1.0, "poisson"),
            (E, 0.3, f64::NAN, "thickness"),
        ] {
            let m = PlaneStrainStrip::new(e, nu, t, h.clone())
                .unwrap_err()
                .to_string();
            assert!(m.contains(says), "{m}");
        }
    }
}
