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
//! local Newton iteration (tolerance [`RETURN_TOL`] `σ_y²` on the yield
//! function), started from a Halley step at `Δλ = 0` built from the trial
//! state's closed-form derivatives; once the evaluated function is within
//! [`RETURN_CLOSE`] `σ_y²`, the last Newton step is taken to first order in
//! its size instead of evaluating again (returned stress: `|σ_vm/σ_y − 1| ≤
//! 5e-10`, measured ≤ 1.3e-10), so that a typical explicit increment needs
//! one evaluation. Swift hardening is
//! evaluated from the point's cached flow stress by a binomial series in
//! `Δε_p / (ε0 + ε_p)` (no `powf` for increments below 2 % of `ε0 + ε_p`).
//! σ_zz = 0 holds by construction; the thickness strain increment is
//! `Δε_zz = −ν/(1−ν)(Δε_xx + Δε_yy − Δε^p_xx − Δε^p_yy) − (Δε^p_xx + Δε^p_yy)`.
//!
//! The return is written once, generic over the number type
//! ([`Real`]: `f64` for one point, lanes for four elements): `trial`,
//! `project` (over a `Curve`: Swift's series, or a table) and `finish`.
//! Four lanes of Swift hardening run it in SIMD; a tabulated curve goes
//! lane by lane. With `f64` each `madd` rounds twice and in lanes once, so a
//! lane equals the one-point run to rounding.

use super::curve::{Curve, Swift, swift_binomial};
use super::{Hardening, Material, PointUpdate, update_points_by_lane, von_mises};
use crate::error::{ShellError, check};
use crate::lanes::{F4, KernelLanes, LaneKernel, Lanes4, Real, run_fastest};

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
    /// ν / (1 − ν).
    nu_ratio: f64,
    /// Swift only: binomial coefficients C(n, k), k = 0..=8, of (1 + x)^n.
    swift_binomial: [f64; 9],
}

/// History of one integration point of [`J2PlaneStress`] (`repr(C)`: the
/// lane kernel moves the two values with one 128-bit load or store).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[repr(C)]
pub struct J2History {
    /// Equivalent plastic strain ε_p (-).
    pub eps_p: f64,
    /// Flow stress at `eps_p` (MPa), cached so that an elastic step costs no hardening evaluation.
    pub sigma_y: f64,
}

impl super::HistoryWords for J2History {
    const WORDS: usize = 2;
    fn write_words(&self, out: &mut Vec<f64>) {
        out.extend([self.eps_p, self.sigma_y]);
    }
    fn read_words(words: &[f64]) -> Self {
        Self {
            eps_p: words[0],
            sigma_y: words[1],
        }
    }
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
        let swift_binomial = match hardening {
            Hardening::Swift { n, .. } => swift_binomial(n),
            Hardening::Table { .. } => [0.0; 9],
        };
        Ok(Self {
            young,
            poisson,
            density,
            hardening,
            shear: young / (2.0 * (1.0 + poisson)),
            c11,
            c12: poisson * c11,
            a_p: young / (3.0 * (1.0 - poisson)),
            nu_ratio: poisson / (1.0 - poisson),
            swift_binomial,
        })
    }

    /// The hardening curve.
    pub fn hardening(&self) -> &Hardening {
        &self.hardening
    }

    /// Elastic trial stress and whether it lies inside the yield surface
    /// (one point, or the lanes of four).
    #[inline(always)]
    fn trial<T: Real>(&self, s: &[T; 3], sy0: T, d: [T; 3]) -> ([T; 3], T::Mask) {
        let (c11, c12, g) = (T::splat(self.c11), T::splat(self.c12), T::splat(self.shear));
        let t0 = d[1].madd(c12, d[0].madd(c11, s[0]));
        let t1 = d[1].madd(c11, d[0].madd(c12, s[1]));
        let t2 = d[2].madd(g, s[2]);
        let vm2 = (t2 * 3.0).madd(t2, (-t0).madd(t1, t1.madd(t1, t0 * t0)));
        ([t0, t1, t2], T::le(vm2, sy0 * sy0))
    }

    /// The projected return of one point, or of the lanes of four, whose
    /// trial stress `t` lies outside the yield surface in the lanes of
    /// `plastic` (the other lanes are computed and not used). `sy0`: the
    /// flow stress at the start; `hm0`, `dhm0`: the curve's first and second
    /// derivatives there.
    ///
    /// A Halley step from Δλ = 0, built from the closed-form value and first
    /// two derivatives of the yield function at the trial state (its error
    /// cubic in the increment), then Newton steps until `|f| ≤ RETURN_TOL
    /// σ_y,0²` in every plastic lane; a lane within `RETURN_CLOSE σ_y,0²`
    /// takes its last step to first order in its size δ instead of
    /// evaluating again. Lanes that have converged are masked.
    #[inline(always)]
    fn project<T: Real, C: Curve<T>>(
        &self,
        t: [T; 3],
        plastic: T::Mask,
        sy0: T,
        hm0: T,
        dhm0: T,
        curve: &C,
    ) -> Projected<T> {
        let (ap, g2) = (self.a_p, 2.0 * self.shear);
        let (z, one) = (T::splat(0.0), T::splat(1.0));
        let [t0, t1, t2] = t;
        let sum = t0 + t1;
        let dif = t0 - t1;
        let a1 = sum * sum * (1.0 / 6.0); // p_tr² / 3
        let a2 = (t2 * 2.0).madd(t2, dif * 0.5 * dif); // q_tr² + 2 σ_xy²
        // f(Δλ) = ½ φ² − ⅓ σ_y(ε_p + √⅔ Δλ φ)², with φ² = a1 f1² + a2 f2².
        let phi2_0 = a1 + a2;
        let phi0 = phi2_0.sqrt();
        let f0 = (-(sy0 * sy0)).madd(T::splat(1.0 / 3.0), phi2_0 * 0.5);
        let dphi2_0 = a2.madd(T::splat(g2), a1 * ap) * -2.0;
        let ddphi2_0 = a2.madd(T::splat(g2 * g2), a1 * (ap * ap)) * 6.0;
        // Δε_p = √⅔ Δλ φ: its first derivative is √⅔ φ0, its second
        // √⅔ φ²′/φ0. The Halley step Δλ = −f f′ / (f′² − ½ f f″) is taken
        // with numerator and denominator times φ0 (> 0), so that the
        // division by φ0 in f″ folds into the step's one division.
        let dd_0 = phi0 * R23;
        let dy_0 = hm0 * dd_0;
        let df0 = (-(sy0 * (2.0 / 3.0))).madd(dy_0, dphi2_0 * 0.5);
        // φ0 f″ = ½ φ0 φ²″ − ⅔ (φ0 σ_y′² + σ_y (φ0 h′ (Δε_p′)² + h √⅔ φ²′)),
        // (Δε_p′)² = ⅔ φ0².
        let ddy_0_phi = (dhm0 * (2.0 / 3.0) * phi2_0).madd(phi0, hm0 * R23 * dphi2_0);
        let ddf0_phi = (-(dy_0 * dy_0).madd(phi0, sy0 * ddy_0_phi))
            .madd(T::splat(2.0 / 3.0), ddphi2_0 * 0.5 * phi0);
        let df0sq = df0 * df0 * phi0;
        let den = (-(f0 * 0.5)).madd(ddf0_phi, df0sq);
        // Δλ0 = num / den0 (num clamped at 0; Newton, −f/f′, when the
        // correction is not small), and the first evaluation's
        // f1 = 1 / (1 + a_p Δλ0) = den0 / b1, f2 = den0 / b2 with
        // b1 = den0 + a_p num, b2 = den0 + 2G num: all three from one
        // division by den0 b1 b2.
        let num = -f0 * df0 * phi0;
        let num = T::select(num.gt(z), num, z);
        // A lane with no stress (not plastic, df0 = 0) takes den0 = 1 and so
        // Δλ0 = 0, not 0/0 (a select beside `den`, off the chain).
        let den0 = T::select(den.gt(df0sq * 0.5), den, T::select(df0sq.gt(z), df0sq, one));
        let b1 = num.madd(T::splat(ap), den0);
        let b2 = num.madd(T::splat(g2), den0);
        let b12 = b1 * b2;
        let inv0 = one / (den0 * b12);
        let den0sq = den0 * den0;
        // φ² = a1 f1² + a2 f2² = S w² with S = a1 b2² + a2 b1², w = den0 /
        // (b1 b2) = den0² inv0: the square root of S runs beside the division.
        let big_s = (a2 * b1).madd(b1, a1 * b2 * b2);
        let w = den0sq * inv0;
        let root_s = big_s.sqrt();
        let mut first = Some((w * b2, w * b1, big_s * w * w, root_s * w));
        let mut r = Projected {
            dl: num * b12 * inv0,
            f1: one,
            f2: one,
            d: z,
            sy: sy0,
        };
        let tol = sy0 * RETURN_TOL * sy0;
        let close = sy0 * RETURN_CLOSE * sy0;
        let mut active = plastic;
        for _ in 0..60 {
            let dl = r.dl;
            let (f1, f2, phi2, phi) = match first.take() {
                Some(f) => f,
                None => {
                    let den1 = dl.madd(T::splat(ap), one);
                    let den2 = dl.madd(T::splat(g2), one);
                    let inv = one / (den1 * den2);
                    let (f1, f2) = (den2 * inv, den1 * inv);
                    let phi2 = (a2 * f2).madd(f2, a1 * f1 * f1);
                    (f1, f2, phi2, phi2.sqrt())
                }
            };
            let d = dl * R23 * phi;
            let sy = curve.flow(d, active);
            r.f1 = T::select(active, f1, r.f1);
            r.f2 = T::select(active, f2, r.f2);
            r.d = T::select(active, d, r.d);
            r.sy = T::select(active, sy, r.sy);
            let f = (-(sy * sy)).madd(T::splat(1.0 / 3.0), phi2 * 0.5);
            let open = T::mask_and_not(active, T::le(T::abs(f), tol));
            if !T::any(open) {
                break;
            }
            // f′ = ½ φ²′ − ⅔ σ_y h √⅔ (φ² + ½ Δλ φ²′) / φ with h = hn / hd;
            // the Newton step δ = −f / f′ with f′ scaled by hd φ takes a
            // single division, q = −f / (hd φ f′), δ = q hd φ.
            let (hn, hd) = curve.slope(d, sy);
            let dphi2 = (a2 * g2 * f2 * f2).madd(f2, a1 * ap * f1 * f1 * f1) * -2.0;
            let g = (dl * 0.5).madd(dphi2, phi2);
            let df_scaled = (-(sy * ((2.0 / 3.0) * R23) * hn)).madd(g, dphi2 * 0.5 * hd * phi);
            let q = -f / df_scaled;
            let delta = q * hd * phi;
            let next = dl + delta;
            // Lanes within RETURN_CLOSE: the last step, to first order in δ
            // (f1′ = −a_p f1², f2′ = −2G f2², d′ = u hd / δ); σ_y at the new
            // ε_p from the curve, so that the cached flow stress stays the
            // curve's.
            let last = T::mask_and(T::mask_and(open, T::le(T::abs(f), close)), next.gt(z));
            let u = g * R23 * q;
            let d_last = u.madd(hd, d);
            r.f1 = T::select(last, (-(f1 * ap * f1)).madd(delta, f1), r.f1);
            r.f2 = T::select(last, (-(f2 * g2 * f2)).madd(delta, f2), r.f2);
            r.d = T::select(last, d_last, r.d);
            r.sy = T::select(last, curve.step(sy, u, d_last, last), r.sy);
            // In the lanes of `last`, next > 0: the step is `next`.
            let step = T::select(next.gt(z), next, dl * 0.5);
            r.dl = T::select(open, step, dl);
            active = T::mask_and_not(open, last);
            if !T::any(active) {
                break;
            }
        }
        r
    }

    /// Stress and thickness strain after a return: `Δε_zz = −ν/(1−ν)(Δε_xx +
    /// Δε_yy − Δε^p_xx − Δε^p_yy) − (Δε^p_xx + Δε^p_yy)`, the in-plane trace
    /// of `Δε^p = Δλ P σ` being `Δλ (σ_xx + σ_yy) / 3`.
    #[inline(always)]
    fn finish<T: Real>(&self, t: [T; 3], de: [T; 3], r: &Projected<T>) -> ([T; 3], T) {
        let [t0, t1, t2] = t;
        let ps = (t0 + t1) * 0.5 * r.f1;
        let qs = (t0 - t1) * 0.5 * r.f2;
        let sn = [ps + qs, ps - qs, t2 * r.f2];
        let tr_p = r.dl * (sn[0] + sn[1]) * (1.0 / 3.0);
        let deps_zz = (de[0] + de[1] - tr_p).madd(T::splat(-self.nu_ratio), -tr_p);
        (sn, deps_zz)
    }
}

/// Tolerance of the return on the yield function `f = (σ_vm² − σ_y²)/3`,
/// relative to `σ_y²` at the start of the step: an evaluation within it
/// ends the return as it is (`|σ_vm/σ_y − 1| ≤ 1.5e-10`); one within
/// [`RETURN_CLOSE`] ends it after a linearised Newton step.
pub const RETURN_TOL: f64 = 1e-10;

/// Residual of the yield function, relative to `σ_y²` at the start of the
/// step, below which the return takes one last Newton step to first order in
/// its size δ instead of evaluating the yield function again (`f1`, `f2` and
/// Δε_p to first order, σ_y from the curve at the new ε_p): Newton's error
/// is then `≈ 3 (f/σ_y²)²` and the linearisation's of the same order, so
/// that the returned stress meets `|σ_vm/σ_y − 1| ≤ 5e-10` (checked by
/// `linearised_last_step_lands_on_the_yield_surface`: at most 1.3e-10
/// measured), and a typical explicit increment, whose Halley start leaves
/// `f/σ_y² ~ 1e-6`, needs one evaluation of the yield function instead of
/// two (its square root, division and series).
pub const RETURN_CLOSE: f64 = 1e-5;

/// √(2/3).
const R23: f64 = 0.816_496_580_927_726;

/// Where a projected return ends (one point, or the lanes of four).
#[derive(Debug, Clone, Copy, Default)]
struct Projected<T> {
    /// Plastic multiplier Δλ.
    dl: T,
    /// `1 / (1 + a_p Δλ)`, `1 / (1 + 2G Δλ)`.
    f1: T,
    f2: T,
    /// Plastic strain increment Δε_p.
    d: T,
    /// Flow stress at `ε_p + Δε_p`.
    sy: T,
}

/// A tabulated curve for one point at plastic strain `eps_p` (four lanes go
/// one by one through it: [`update_points_by_lane`]).
struct Table<'a> {
    hard: &'a Hardening,
    eps_p: f64,
}

impl Curve<f64> for Table<'_> {
    #[inline(always)]
    fn flow(&self, d: f64, _: bool) -> f64 {
        self.hard.eval(self.eps_p + d).0
    }
    #[inline(always)]
    fn slope(&self, d: f64, _: f64) -> (f64, f64) {
        (self.hard.eval(self.eps_p + d).1, 1.0)
    }
    #[inline(always)]
    fn step(&self, _: f64, _: f64, d_last: f64, _: bool) -> f64 {
        self.hard.eval(self.eps_p + d_last).0
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

    #[inline(always)]
    fn update(&self, s: &mut [f64; 3], h: &mut J2History, de: [f64; 3]) -> PointUpdate {
        let [u] = self.update_points::<1>(std::array::from_mut(s), std::array::from_mut(h), &[de]);
        u
    }

    /// The `N` points of a section: with Swift hardening four at a time in
    /// lanes (the same kernel as four elements', so a one-element run is
    /// lane `l` of a four-element run bit for bit); a tabulated curve point
    /// by point.
    #[inline(always)]
    fn update_points<const N: usize>(
        &self,
        s: &mut [[f64; 3]; N],
        h: &mut [J2History; N],
        de: &[[f64; 3]; N],
    ) -> [PointUpdate; N] {
        match &self.hardening {
            Hardening::Swift { k, eps0, n } => self.swift_points(*k, *eps0, *n, s, h, de),
            hard @ Hardening::Table { .. } => {
                std::array::from_fn(|p| self.table_point(hard, &mut s[p], &mut h[p], de[p]))
            }
        }
    }

    /// Four elements' sections in lanes: the same projected return, each
    /// branch a lane mask (Swift hardening; a tabulated curve goes lane by
    /// lane).
    #[inline(always)]
    fn update_points_x4<L: Lanes4, const N: usize>(
        &self,
        s: &mut [[L; 3]; N],
        h: &mut [[J2History; N]; 4],
        de: &[[L; 3]; N],
    ) -> [PointUpdate<L>; N] {
        match self.hardening {
            Hardening::Swift { k, eps0, n } => self.swift_x4(k, eps0, n, s, h, de),
            Hardening::Table { .. } => update_points_by_lane(self, s, h, de),
        }
    }

    fn equivalent_stress(&self, s: &[f64; 3]) -> f64 {
        von_mises(s)
    }

    /// The closed-form algorithmic tangent of the projected return: the
    /// plane-stress elasticity `C` if the trial stress lies inside the
    /// yield surface, else the derivative of the converged return (Simo &
    /// Taylor 1986), `Ξ − a n nᵀ / (a σᵀPn + b)` with `Ξ = (C⁻¹ + Δλ P)⁻¹`,
    /// `n = Ξ P σ`, `a = 1 − k Δλ/φ`, `b = k φ`, `k = (⅔)^{3/2} σ_y H`,
    /// `φ = √(σᵀPσ)`, at the returned σ, Δλ, σ_y and the curve's slope H
    /// at the new ε_p (`a σᵀPn + b` is `−f′(Δλ)` of the return's yield
    /// function).
    /// The return is run again here, with `f64` arithmetic (the lane
    /// kernel's fused multiply-adds aside, the update's own iteration);
    /// no allocation.
    fn consistent_tangent(&self, s: &[f64; 3], h: &J2History, de: [f64; 3]) -> [[f64; 3]; 3] {
        match self.converged_return(s, h, de) {
            None => [
                [self.c11, self.c12, 0.0],
                [self.c12, self.c11, 0.0],
                [0.0, 0.0, self.shear],
            ],
            Some((sn, r, slope)) => self.plastic_tangent(&sn, &r, slope),
        }
    }
}

impl J2PlaneStress {
    /// The return of one point from the committed `(s, h)` for `de`, in
    /// `f64`: the returned stress, the converged [`Projected`] state and the
    /// curve's slope `dσ_y/dε_p` at the new plastic strain; `None` for an
    /// elastic step.
    fn converged_return(
        &self,
        s: &[f64; 3],
        h: &J2History,
        de: [f64; 3],
    ) -> Option<([f64; 3], Projected<f64>, f64)> {
        let (t, elastic) = self.trial(s, h.sigma_y, de);
        if elastic {
            return None;
        }
        let J2History {
            eps_p,
            sigma_y: sy0,
        } = *h;
        let (r, slope) = match &self.hardening {
            Hardening::Swift { k, eps0, n } => {
                let (curve, hm0, dhm0) = self.swift_curve(*k, *eps0, *n, eps_p, sy0);
                let r = self.project(t, true, sy0, hm0, dhm0, &curve);
                (r, n * r.sy / (eps0 + eps_p + r.d))
            }
            hard @ Hardening::Table { .. } => {
                let curve = Table { hard, eps_p };
                let r = self.project(t, true, sy0, hard.eval(eps_p).1, 0.0, &curve);
                (r, hard.eval(eps_p + r.d).1)
            }
        };
        Some((self.finish(t, de, &r).0, r, slope))
    }

    /// `∂σ/∂Δε` of a converged return at the returned stress `sn`.
    ///
    /// Differentiating `σ = Ξ(Δλ) C⁻¹ σ_trial` gives `dσ = Ξ dΔε − n dΔλ`
    /// (`dΞ/dΔλ = −Ξ P Ξ`); the yield function `½ φ² − ⅓ σ_y(ε_p + Δε_p)²`
    /// with `Δε_p = √⅔ Δλ φ` stays zero, so `a (nᵀdΔε − σᵀPn dΔλ) = b dΔλ`.
    /// `Ξ` is diagonal in the basis `(σxx+σyy)/√2`, `(σxx−σyy)/√2`, `σxy`:
    /// `(c11 + c12) f1`, `2G f2`, `G f2` with the return's `f1`, `f2`.
    fn plastic_tangent(&self, sn: &[f64; 3], r: &Projected<f64>, slope: f64) -> [[f64; 3]; 3] {
        let xi_p = (self.c11 + self.c12) * r.f1;
        let xi_q = 2.0 * self.shear * r.f2;
        let xi = [
            [0.5 * (xi_p + xi_q), 0.5 * (xi_p - xi_q), 0.0],
            [0.5 * (xi_p - xi_q), 0.5 * (xi_p + xi_q), 0.0],
            [0.0, 0.0, self.shear * r.f2],
        ];
        // P σ with P = ⅓ [[2, −1, 0], [−1, 2, 0], [0, 0, 6]].
        let ps = [
            (2.0 * sn[0] - sn[1]) * (1.0 / 3.0),
            (2.0 * sn[1] - sn[0]) * (1.0 / 3.0),
            2.0 * sn[2],
        ];
        let n: [f64; 3] =
            std::array::from_fn(|i| xi[i][0] * ps[0] + xi[i][1] * ps[1] + xi[i][2] * ps[2]);
        let s_pn = ps[0] * n[0] + ps[1] * n[1] + ps[2] * n[2];
        let phi = (sn[0] * ps[0] + sn[1] * ps[1] + sn[2] * ps[2]).sqrt();
        let k = (2.0 / 3.0) * R23 * r.sy * slope;
        let (a, b) = (1.0 - k * r.dl / phi, k * phi);
        let c = a / (a * s_pn + b);
        std::array::from_fn(|i| std::array::from_fn(|j| xi[i][j] - c * n[i] * n[j]))
    }
}

impl J2PlaneStress {
    /// Swift's curve at a point's (or four lanes') `ε_p` and cached flow
    /// stress `sy0`, with its first and second derivatives there.
    #[inline(always)]
    fn swift_curve<T: Real>(
        &self,
        k: f64,
        eps0: f64,
        n: f64,
        eps_p: T,
        sy0: T,
    ) -> (Swift<'_, T>, T, T) {
        let e = eps_p + eps0;
        let inv_e = T::splat(1.0) / e;
        let hm0 = sy0 * n * inv_e;
        let dhm0 = hm0 * (n - 1.0) * inv_e;
        let curve = Swift {
            c: &self.swift_binomial,
            k,
            n,
            sy0,
            e,
            inv_e,
        };
        (curve, hm0, dhm0)
    }

    /// [`Material::update_points_x4`] with Swift hardening: every point's
    /// trial first, then the returns of the points with a lane outside the
    /// yield surface, one after the other, each in registers (their
    /// independent division / square-root chains overlap in the processor's
    /// out-of-order window); elastic or converged lanes masked. Plain loops,
    /// no closures: a closure would not be compiled with the AVX2 features
    /// of the kernel that inlines this.
    #[inline(always)]
    fn swift_x4<L: Lanes4, const N: usize>(
        &self,
        k: f64,
        eps0: f64,
        n: f64,
        s: &mut [[L; 3]; N],
        h: &mut [[J2History; N]; 4],
        de: &[[L; 3]; N],
    ) -> [PointUpdate<L>; N] {
        let mut out = [PointUpdate::<L>::default(); N];
        let mut plastic = [L::splat(0.0).gt(L::splat(0.0)); N];
        let mut any_plastic = false;
        for p in 0..N {
            let sy0 = L::from_array([
                h[0][p].sigma_y,
                h[1][p].sigma_y,
                h[2][p].sigma_y,
                h[3][p].sigma_y,
            ]);
            let (t, elastic) = self.trial(&s[p], sy0, de[p]);
            s[p] = t;
            out[p].deps_zz = (de[p][0] + de[p][1]) * -self.nu_ratio;
            plastic[p] = L::mask_not(elastic);
            any_plastic |= L::any(plastic[p]);
        }
        if !any_plastic {
            return out;
        }
        for p in 0..N {
            let pl = plastic[p];
            if !L::any(pl) {
                continue;
            }
            let (eps_p, sy0) = J2History::lanes::<L, N>(h, p);
            let (curve, hm0, dhm0) = self.swift_curve(k, eps0, n, eps_p, sy0);
            let r = self.project(s[p], pl, sy0, hm0, dhm0, &curve);
            let (sn, deps_zz) = self.finish(s[p], de[p], &r);
            for c in 0..3 {
                s[p][c] = L::select(pl, sn[c], s[p][c]);
            }
            out[p].deps_zz = L::select(pl, deps_zz, out[p].deps_zz);
            out[p].dissipation = L::select(pl, r.sy * r.d, L::splat(0.0));
            J2History::set_lanes(
                h,
                p,
                L::select(pl, eps_p + r.d, eps_p),
                L::select(pl, r.sy, sy0),
            );
        }
        out
    }

    /// One element's `N` points with Swift hardening, four at a time in
    /// lanes, through the four-element kernel: on AVX2 registers where
    /// the processor has AVX2 and FMA, else in portable lanes (the same bits).
    #[inline(always)]
    fn swift_points<const N: usize>(
        &self,
        k: f64,
        eps0: f64,
        n: f64,
        s: &mut [[f64; 3]; N],
        h: &mut [J2History; N],
        de: &[[f64; 3]; N],
    ) -> [PointUpdate; N] {
        run_fastest(SwiftPoints {
            mat: self,
            swift: (k, eps0, n),
            s,
            h,
            de,
        })
    }

    /// Points `g..g+4` of the section in the lanes of `L` as four one-point
    /// elements through [`swift_x4`](Self::swift_x4) (unused lanes zero: no
    /// stress, elastic). Plain loops (see `swift_x4`).
    #[inline(always)]
    fn swift_points_in<L: Lanes4, const N: usize>(
        &self,
        (k, eps0, n): (f64, f64, f64),
        s: &mut [[f64; 3]; N],
        h: &mut [J2History; N],
        de: &[[f64; 3]; N],
    ) -> [PointUpdate; N] {
        let mut out = [PointUpdate::default(); N];
        let mut g = 0;
        while g < N {
            let m = if N - g < 4 { N - g } else { 4 };
            let mut sa = [[0.0; 4]; 3];
            let mut da = [[0.0; 4]; 3];
            let mut hl = [[J2History::default()]; 4];
            for l in 0..m {
                for c in 0..3 {
                    sa[c][l] = s[g + l][c];
                    da[c][l] = de[g + l][c];
                }
                hl[l][0] = h[g + l];
            }
            let mut sl = [[
                L::from_array(sa[0]),
                L::from_array(sa[1]),
                L::from_array(sa[2]),
            ]];
            let dl = [[
                L::from_array(da[0]),
                L::from_array(da[1]),
                L::from_array(da[2]),
            ]];
            let [u] = self.swift_x4::<L, 1>(k, eps0, n, &mut sl, &mut hl, &dl);
            let sn = [
                sl[0][0].to_array(),
                sl[0][1].to_array(),
                sl[0][2].to_array(),
            ];
            let (dz, dd) = (u.deps_zz.to_array(), u.dissipation.to_array());
            for l in 0..m {
                s[g + l] = [sn[0][l], sn[1][l], sn[2][l]];
                out[g + l] = PointUpdate {
                    deps_zz: dz[l],
                    dissipation: dd[l],
                };
                h[g + l] = hl[l][0];
            }
            g += 4;
        }
        out
    }

    /// One point with a tabulated curve: the return with `f64`.
    #[inline(always)]
    fn table_point(
        &self,
        hard: &Hardening,
        s: &mut [f64; 3],
        h: &mut J2History,
        de: [f64; 3],
    ) -> PointUpdate {
        let (t, elastic) = self.trial(s, h.sigma_y, de);
        *s = t;
        let elastic_dzz = (de[0] + de[1]) * -self.nu_ratio;
        if elastic {
            return PointUpdate {
                deps_zz: elastic_dzz,
                dissipation: 0.0,
            };
        }
        let J2History {
            eps_p,
            sigma_y: sy0,
        } = *h;
        let curve = Table { hard, eps_p };
        let r = self.project(t, true, sy0, hard.eval(eps_p).1, 0.0, &curve);
        let (sn, deps_zz) = self.finish(t, de, &r);
        *s = sn;
        *h = J2History {
            eps_p: eps_p + r.d,
            sigma_y: r.sy,
        };
        PointUpdate {
            deps_zz,
            dissipation: r.sy * r.d,
        }
    }
}

impl J2History {
    /// `[ε_p, σ_y]` in memory (the struct is `repr(C)`).
    #[inline(always)]
    fn pair(&self) -> &[f64; 2] {
        // SAFETY: `J2History` is `repr(C)` with two `f64` fields, which is
        // the layout of `[f64; 2]`.
        unsafe { &*(self as *const Self).cast::<[f64; 2]>() }
    }

    /// `[ε_p, σ_y]` in memory, writable.
    #[inline(always)]
    fn pair_mut(&mut self) -> &mut [f64; 2] {
        // SAFETY: as in `pair`.
        unsafe { &mut *(self as *mut Self).cast::<[f64; 2]>() }
    }

    /// Point `p`'s `(ε_p, σ_y)` of four elements in lanes, built in registers.
    #[inline(always)]
    fn lanes<L: Lanes4, const N: usize>(h: &[[J2History; N]; 4], p: usize) -> (L, L) {
        let [h0, h1, h2, h3] = h;
        let (e, s) = crate::lanes::unzip4([h0[p].pair(), h1[p].pair(), h2[p].pair(), h3[p].pair()]);
        (L::from_array(e.0), L::from_array(s.0))
    }

    /// Point `p`'s `(ε_p, σ_y)` of four elements from lanes.
    #[inline(always)]
    fn set_lanes<L: Lanes4, const N: usize>(
        h: &mut [[J2History; N]; 4],
        p: usize,
        eps_p: L,
        sy: L,
    ) {
        let [h0, h1, h2, h3] = h;
        crate::lanes::zip4(
            F4(eps_p.to_array()),
            F4(sy.to_array()),
            [
                h0[p].pair_mut(),
                h1[p].pair_mut(),
                h2[p].pair_mut(),
                h3[p].pair_mut(),
            ],
        );
    }
}

/// One element's `N` points with Swift hardening through
/// [`J2PlaneStress::swift_points_in`], as a [`LaneKernel`].
struct SwiftPoints<'a, const N: usize> {
    mat: &'a J2PlaneStress,
    swift: (f64, f64, f64),
    s: &'a mut [[f64; 3]; N],
    h: &'a mut [J2History; N],
    de: &'a [[f64; 3]; N],
}

impl<const N: usize> LaneKernel for SwiftPoints<'_, N> {
    type Output = [PointUpdate; N];
    #[inline(always)]
    fn run<L: KernelLanes>(self) -> [PointUpdate; N] {
        let SwiftPoints {
            mat,
            swift,
            s,
            h,
            de,
        } = self;
        mat.swift_points_in::<L, N>(swift, s, h, de)
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

    /// The return ends with its last Newton step taken to first order when
    /// the yield function is within `RETURN_CLOSE σ_y²` (see
    /// [`RETURN_CLOSE`]): over increments from 1e-6 to 1e-2 in twelve
    /// directions, at four plastic pre-strains, the stress lies on the yield
    /// surface of the curve's σ_y at the new ε_p within 5e-10 (and the cached
    /// flow stress is the curve's within 1e-13). Bound from the error
    /// estimate `3 (RETURN_CLOSE)²` of the docs, with margin; the largest
    /// measured value is printed.
    #[test]
    fn linearised_last_step_lands_on_the_yield_surface() {
        let m = steel();
        let mut worst = 0.0f64;
        for pre in [0.0, 0.01, 0.1, 0.5] {
            for dir in 0..12 {
                let a = dir as f64 * std::f64::consts::PI / 6.0;
                let u = [a.cos(), (a + 1.0).sin() * 0.7, 0.4 * (2.0 * a).sin()];
                for mag in [1e-6, 1e-5, 1e-4, 1e-3, 1e-2] {
                    // Pre-strain along u, then one increment of size `mag`.
                    let (mut s, mut h) = ([0.0; 3], m.initial_history());
                    let steps = (pre / 1e-3f64).ceil().max(1.0) as usize;
                    let load = (pre + 0.003) / steps as f64;
                    for _ in 0..steps {
                        m.update(&mut s, &mut h, u.map(|c| c * load));
                    }
                    m.update(&mut s, &mut h, u.map(|c| c * mag));
                    let law = m.hardening().eval(h.eps_p).0;
                    assert!((h.sigma_y / law - 1.0).abs() < 1e-13, "{pre} {dir} {mag}");
                    let miss = (von_mises(&s) / law - 1.0).abs();
                    worst = worst.max(miss);
                    assert!(miss <= 5e-10, "pre {pre} dir {dir} Δε {mag}: {miss:e}");
                }
            }
        }
        println!("largest |σ_vm/σ_y − 1|: {worst:.2e}");
    }

    /// Swift's flow stress after a last Newton step, `σ_y (1 + u)^n` from σ_y
    /// at `ε_p + d` (binomial series to u⁴ below `STEP_SERIES`, the curve
    /// beyond), equals `K (ε0 + ε_p + d + u (ε0 + ε_p + d))^n` (`powf`) to
    /// 2e-15 relative (series error < 4e-17 plus rounding), on both sides of
    /// `STEP_SERIES` (beyond it through `Swift::flow`, as in the return) and
    /// for hardening exponents across [0, 1), for one point and in lanes
    /// (fused), up to the ends of the series, |u| < `STEP_SERIES`,
    /// |x| < 0.02, and beyond.
    #[test]
    fn flow_after_last_step_is_the_swift_law() {
        for n in [0.05, 0.2589, 0.5, 0.95] {
            let (k, eps0) = (565.32, 0.007117);
            let m = J2PlaneStress::new(
                206_000.0,
                0.3,
                7.85e-9,
                Hardening::swift(k, eps0, n).unwrap(),
            )
            .unwrap();
            for base in [0.0, 0.01, 0.3] {
                let e = eps0 + base;
                let sy = k * e.powf(n);
                for u in [
                    0.0, 1e-9, -1e-7, 1e-5, -3e-4, 9.9e-4, 1.01e-3, -0.0199, 0.0199, 0.05,
                ] {
                    let law = k * (e + u * e).powf(n);
                    // One point: `step` from σ_y (beyond the series, the
                    // curve from the same point, as the return passes it).
                    let (one, _, _) = m.swift_curve(k, eps0, n, base, sy);
                    let step = one.step(sy, u, u * e, true);
                    let err = (step / law - 1.0).abs();
                    assert!(err <= 2e-15, "n {n} ε_p {base} u {u}: {err:e}");
                    // The lanes: `step` from σ_y, and `flow` at the same
                    // plastic strain from the start (x = u here).
                    let (sc, _, _) = m.swift_curve(k, eps0, n, F4::splat(base), F4::splat(sy));
                    let live = F4::splat(1.0).gt(F4::splat(0.0));
                    let lane_step = sc.step(F4::splat(sy), F4::splat(u), F4::splat(u * e), live);
                    let lane_flow = sc.flow(F4::splat(u * e), live);
                    for (what, got) in [("step", lane_step.0[2]), ("flow", lane_flow.0[1])] {
                        let err = (got / law - 1.0).abs();
                        assert!(
                            err <= 2e-15,
                            "lanes' {what}: n {n} ε_p {base} u {u}: {err:e}"
                        );
                    }
                }
            }
        }
    }

    /// The start's one division (by `den0 b1 b2`, of order `G⁶ σ¹⁵`) stays
    /// within `f64` for stresses in pascals as well as in MPa: the same
    /// strain paths in MPa (one point at a time) and in Pa (E = 2.06e11,
    /// K = 5.6532e8; one point at a time and in four lanes, each lane its own
    /// path) give the same ε_p to 1e-12 and stresses scaled by 1e6 to 1e-12
    /// of σ_vm.
    #[test]
    fn return_is_unit_scale_invariant_from_mpa_to_pascals() {
        let mpa = steel();
        let pa = J2PlaneStress::new(
            206_000.0e6,
            0.3,
            7850.0,
            Hardening::swift(565.32e6, 0.007117, 0.2589).unwrap(),
        )
        .unwrap();
        let path = |lane: usize, i: usize| {
            let a = i as f64 * 0.05 + lane as f64;
            [
                2e-4 * a.cos(),
                -1e-4 + 5e-5 * a.sin(),
                1e-4 * (2.0 * a).sin(),
            ]
        };
        let mut s_mpa = [[0.0; 3]; 4];
        let mut h_mpa = [mpa.initial_history(); 4];
        let mut s_pa = [[0.0; 3]; 4];
        let mut h_pa = [pa.initial_history(); 4];
        let mut s_x4 = [[F4([0.0; 4]); 3]; 1];
        let mut h_x4 = [[pa.initial_history(); 1]; 4];
        for i in 0..200 {
            let mut de_x4 = [[F4([0.0; 4]); 3]; 1];
            for l in 0..4 {
                let de = path(l, i);
                mpa.update(&mut s_mpa[l], &mut h_mpa[l], de);
                pa.update(&mut s_pa[l], &mut h_pa[l], de);
                for c in 0..3 {
                    de_x4[0][c].0[l] = de[c];
                }
            }
            pa.update_points_x4::<F4, 1>(&mut s_x4, &mut h_x4, &de_x4);
            for l in 0..4 {
                let scale = von_mises(&s_mpa[l]) * 1e6;
                let lane = [s_x4[0][0].0[l], s_x4[0][1].0[l], s_x4[0][2].0[l]];
                for (what, s, h) in [("one", s_pa[l], h_pa[l]), ("lanes", lane, h_x4[l][0])] {
                    let ep = h_mpa[l].eps_p;
                    assert!(
                        (ep - h.eps_p).abs() <= 1e-12 * ep.max(1e-3),
                        "{what} {l} step {i}"
                    );
                    for c in 0..3 {
                        let miss = (s_mpa[l][c] * 1e6 - s[c]).abs();
                        assert!(miss <= 1e-12 * scale, "{what} {l} step {i}: {miss:e}");
                    }
                }
            }
        }
        for h in h_mpa {
            assert!(h.eps_p > 0.01, "the paths are plastic: ε_p = {}", h.eps_p);
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

    /// The section-wise update (`update_points`) gives bit for bit what the
    /// point-wise `update` gives, for Swift and tabulated hardening,
    /// with elastic and plastic points mixed; and the cached flow stress after
    /// a small plastic step (binomial series, no `powf`) equals the Swift law
    /// at the new ε_p to 1e-13 relative.
    #[test]
    fn lockstep_section_update_equals_pointwise_update() {
        let table = Hardening::table(&[(0.0, 300.0), (0.05, 400.0), (0.3, 500.0)]).unwrap();
        for m in [
            steel(),
            J2PlaneStress::new(206_000.0, 0.3, 7.85e-9, table).unwrap(),
        ] {
            let mut s5 = [[0.0; 3]; 5];
            let mut h5 = [m.initial_history(); 5];
            let mut s1 = s5;
            let mut h1 = h5;
            for step in 0..400 {
                let a = 2e-5 * (1.0 + 0.3 * (step as f64 * 0.1).sin());
                let de: [[f64; 3]; 5] =
                    std::array::from_fn(|k| [a * (k as f64 - 1.5), -0.4 * a, 0.3 * a * k as f64]);
                let u5 = m.update_points(&mut s5, &mut h5, &de);
                for k in 0..5 {
                    let u1 = m.update(&mut s1[k], &mut h1[k], de[k]);
                    assert_eq!(u1, u5[k], "step {step} point {k}");
                    assert_eq!(s1[k], s5[k], "step {step} point {k}");
                    assert_eq!(h1[k], h5[k], "step {step} point {k}");
                }
            }
            assert!(h5.iter().all(|h| h.eps_p > 0.0), "every point yields");
            for h in &h5 {
                let exact = m.hardening().eval(h.eps_p).0;
                assert!(
                    (h.sigma_y / exact - 1.0).abs() < 1e-13,
                    "{} vs {exact}",
                    h.sigma_y
                );
            }
        }
    }

    /// With Swift hardening one element's points run through the
    /// four-element lane kernel (written once), so a one-element update is
    /// lane `l` of a four-element update bit for bit: 3000 steps of five
    /// points, elastic and plastic, each lane its own path.
    #[test]
    fn one_element_update_is_its_lane_of_the_four_element_update() {
        let m = steel();
        let mut one = [[[0.0; 3]; 5]; 4];
        let mut one_h = [[m.initial_history(); 5]; 4];
        let mut lanes = [[F4::splat(0.0); 3]; 5];
        let mut lanes_h = [[m.initial_history(); 5]; 4];
        let scale = [1.0, 0.5, -1.0, 2.0];
        for step in 0..3000 {
            let a = 4e-4 * (1.0 + 0.9 * (step as f64 * 0.37).sin());
            let de: [[f64; 3]; 5] = std::array::from_fn(|k| {
                let c = (step as f64 * 0.05).cos();
                [a * (k as f64 - 1.5) * c, -0.4 * a, 0.3 * a * k as f64]
            });
            let de_l: [[F4; 3]; 5] =
                std::array::from_fn(|k| std::array::from_fn(|c| F4(scale.map(|f| f * de[k][c]))));
            let u = m.update_points_x4(&mut lanes, &mut lanes_h, &de_l);
            for l in 0..4 {
                let de_one = de.map(|d| d.map(|x| scale[l] * x));
                let v = m.update_points(&mut one[l], &mut one_h[l], &de_one);
                for k in 0..5 {
                    for c in 0..3 {
                        assert_eq!(one[l][k][c].to_bits(), lanes[k][c].0[l].to_bits());
                    }
                    assert_eq!(v[k].deps_zz.to_bits(), u[k].deps_zz.0[l].to_bits());
                    assert_eq!(v[k].dissipation.to_bits(), u[k].dissipation.0[l].to_bits());
                    assert_eq!(one_h[l][k], lanes_h[l][k], "step {step} lane {l} point {k}");
                }
            }
        }
        assert!(
            one_h.iter().flatten().all(|h| h.eps_p > 0.0),
            "every point yields"
        );
    }
}
