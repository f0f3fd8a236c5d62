//! `Hill48PlaneStress`: Hill's 1948 quadratic anisotropic plasticity under
//! plane stress, from the r-values, with isotropic hardening (fully implicit
//! closest-point return).
//!
//! ## Criterion
//! In the orthotropy axes (1 = rolling direction RD, 2 = transverse TD),
//! Hill (1948, Proc. R. Soc. A 193, 281–297) in plane stress reads
//! `σ̄² = (G+H) σ11² − 2H σ11 σ22 + (H+F) σ22² + 2N σ12²`, and with the
//! normalisation `G + H = 1` (σ̄ is the uniaxial yield stress along RD) the
//! coefficients follow from the r-values (Banabic, *Sheet Metal Forming
//! Processes*, Springer 2010, §2.2; see [`HillCoefficients::from_r_values`]):
//! `G = 1/(1+r0)`, `H = r0/(1+r0)`, `F = r0/(r90 (1+r0))`,
//! `N = (r0+r90)(1+2 r45) / (2 r90 (1+r0))`.
//! Written as `σ̄² = σᵀ P σ` with `σ = [σ11, σ22, σ12]` (tensor shear), the
//! flow is associated: `Δε^p = Δλ P σ` (engineering shear), the plastic work
//! is `σ·Δε^p = Δλ σ̄²`, so the work-conjugate equivalent plastic strain is
//! `Δε̄ = Δλ σ̄`, and hardening is the [`Hardening`] curve on it.
//!
//! ## Frame (the choice and its limits)
//! The shells hand the material stresses and strain increments in their
//! co-rotational frame (`e1` bisects sides 1→2 and 4→3, `e3` is normal to both
//! diagonals; `geometry.rs`), which spins with the element, and stresses are
//! stored in it without further rotation. Axes fixed in that frame therefore
//! convect with the element, as material axes should. The material keeps one
//! angle `θ` from `e1` to RD ([`Hill48PlaneStress::with_rolling_angle`]) and
//! rotates the criterion once into the element frame, `P_e = Tᵀ P T`
//! (`T` the stress rotation by θ); the return then works in the element frame
//! with no per-point rotation. Limits: (1) θ is one constant per material, so
//! every element of a set must share it (the scene builder computes θ of each
//! element from global x projected onto its plane and refuses a blank whose
//! elements disagree — a flat, consistently numbered structured blank
//! shares it; a per-element angle would need a per-element history
//! initialisation in `ShellSet`); (2) the axes follow the frame's spin (the
//! mean rotation of the element's sides), not the RD material fibre itself,
//! which differ under large in-plane shear of the element; (3) elasticity is
//! isotropic.
//!
//! ## Return mapping
//! With `C` the isotropic plane-stress elasticity, the closest-point
//! projection gives `(I + Δλ C P) σ = σ_trial`, diagonal in the basis of
//! `C P`'s eigenvectors (computed once per material, `Spectral`: Simo &
//! Taylor's projected return generalised from von Mises' `P`), and `Δλ ≥ 0`
//! solves `g(Δλ) = σ̄(σ(Δλ)) − σ_y(ε̄_n + Δλ σ̄) = 0` by Newton with its
//! exact derivative, safeguarded by bisection inside a bracket, converged
//! to [`HILL_RETURN_TOL`] relative.
//! σ_zz = 0 by construction; the thickness strain increment is that of
//! J2: `Δε_zz = −ν/(1−ν)(Δε_xx + Δε_yy − tr Δε^p) − tr Δε^p`, `tr Δε^p` the
//! in-plane trace (plastic incompressibility). Dissipation `σ_y Δε̄`.
//!
//! ## Four elements in lanes
//! With Swift hardening, [`Material::update_points_x4`] runs the same
//! return for four elements at once in SIMD lanes (`swift_x4`; a tabulated
//! curve goes lane by lane through the scalar `update`, as J2's does). The
//! criterion and its spectral basis are the material's (one rolling angle
//! per material, above), so the four lanes share `V`, `V⁻¹` and `λ_i` and
//! differ only in their stresses and histories. The trial stress and the
//! elastic test are the scalar update's operations in the same order, so an
//! elastic lane is the scalar result bit for bit. A plastic lane solves the
//! same equation on the squared form `F(Δλ) = ½(σ̄² − σ_y²)` with Halley
//! steps (value, slope and curvature in closed form, one division each; the
//! first from `Δλ = 0` in closed form, sharing its division with the
//! evaluation at its end), safeguarded by
//! bisection inside the same bracket, converged lanes masked; a lane whose
//! `|F| ≤ LANE_CLOSE σ_y²` takes its last Halley step to second order in
//! its size without evaluating again (Halley's error is cubic, about
//! `(LANE_CLOSE)³`), and Swift's curve is read by its binomial series from
//! the cached flow stress (`curve.rs`), so that a typical explicit increment
//! costs one evaluation (a division, a square root and the series) instead
//! of the scalar update's three and a `powf`. Each lane ends on the
//! scalar update's root to rounding: the lane test in `hill48_tests.rs`
//! bounds the difference by 1e-12 of each quantity's scale (measured: a
//! few 1e-15).

use super::curve::{Curve, Swift, swift_binomial};
use super::{Hardening, Material, PointUpdate, update_points_by_lane};
use crate::error::{ShellError, check};
use crate::lanes::Lanes4;

/// Hill'48 plane-stress coefficients `F, G, H, N` with `G + H = 1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HillCoefficients {
    /// F (-).
    pub f: f64,
    /// G (-).
    pub g: f64,
    /// H (-).
    pub h: f64,
    /// N (-).
    pub n: f64,
}

impl HillCoefficients {
    /// From the r-values `[r0, r45, r90]` (Banabic 2010, §2.2), each finite
    /// and > 0 (the error names `r0`, `r45` or `r90` and its value).
    pub fn from_r_values(r: [f64; 3]) -> Result<Self, ShellError> {
        for (name, v) in [("r0", r[0]), ("r45", r[1]), ("r90", r[2])] {
            check(name, v, "-", "> 0 (finite)", v > 0.0)?;
        }
        let [r0, r45, r90] = r;
        Ok(Self {
            f: r0 / (r90 * (1.0 + r0)),
            g: 1.0 / (1.0 + r0),
            h: r0 / (1.0 + r0),
            n: (r0 + r90) * (1.0 + 2.0 * r45) / (2.0 * r90 * (1.0 + r0)),
        })
    }

    /// `P` in the orthotropy axes: `σ̄² = σᵀ P σ`, `σ = [σ11, σ22, σ12]`.
    pub fn matrix(&self) -> [[f64; 3]; 3] {
        let Self { f, g, h, n } = *self;
        [[g + h, -h, 0.0], [-h, f + h, 0.0], [0.0, 0.0, 2.0 * n]]
    }

    /// Uniaxial yield stress at `angle` (rad) from RD relative to RD's:
    /// `1 / √(uᵀ P u)`, `u = [cos²α, sin²α, sin α cos α]`.
    pub fn yield_ratio(&self, angle: f64) -> f64 {
        let (s, c) = angle.sin_cos();
        let u = [c * c, s * s, s * c];
        1.0 / quad(&self.matrix(), &u).sqrt()
    }

    /// r-value (width over thickness plastic strain rate) in uniaxial tension
    /// at `angle` (rad) from RD:
    /// `r_α = (H + (2N − F − G − 4H) sin²α cos²α) / (F sin²α + G cos²α)`.
    pub fn r_value(&self, angle: f64) -> f64 {
        let Self { f, g, h, n } = *self;
        let (s, c) = angle.sin_cos();
        let (s2, c2) = (s * s, c * c);
        (h + (2.0 * n - f - g - 4.0 * h) * s2 * c2) / (f * s2 + g * c2)
    }
}

/// `σ_m = T σ_e`: stress `[σxx, σyy, σxy]` from the element frame into axes
/// turned by `theta` (rad) about the normal.
pub fn stress_rotation(theta: f64) -> [[f64; 3]; 3] {
    let (s, c) = theta.sin_cos();
    [
        [c * c, s * s, 2.0 * s * c],
        [s * s, c * c, -2.0 * s * c],
        [-s * c, s * c, c * c - s * s],
    ]
}

/// Convergence tolerance of the return: `|g| ≤ HILL_RETURN_TOL σ_y` on
/// `g = σ̄ − σ_y`, or a Newton step below it relative to Δλ. The iteration
/// reads Swift's curve by [`Hardening::eval_from`] (1e-12 relative), so the
/// returned stress lies on the curve's surface to about 1e-12.
pub const HILL_RETURN_TOL: f64 = 1e-14;

/// Residual `|σ̄ − σ_y| / σ_y` below which the return takes its last
/// Newton step without evaluating again: the step's error is of order
/// `(HILL_RETURN_CLOSE)² ≈ 1e-14` relative (times the curvature of `g`,
/// of order one), so that a typical explicit increment needs three
/// evaluations of `g` instead of four (`plastic_steps_end_on_the_yield_surface…`
/// prints the largest miss measured: 1.2e-14).
pub const HILL_RETURN_CLOSE: f64 = 1e-7;

/// Anisotropic (Hill'48) plane-stress plasticity with a [`Hardening`] curve.
#[derive(Debug, Clone, PartialEq)]
pub struct Hill48PlaneStress {
    young: f64,
    poisson: f64,
    density: f64,
    hardening: Hardening,
    r_values: [f64; 3],
    /// Angle θ (rad) from the element's `e1` to the rolling direction.
    angle: f64,
    // Derived constants.
    shear: f64,
    c11: f64,
    c12: f64,
    nu_ratio: f64,
    /// `P` in the element frame (`Tᵀ P T`).
    p: [[f64; 3]; 3],
    /// The return's spectral basis (see [`Spectral`]).
    spec: Spectral,
    /// Swift only: binomial coefficients C(n, k), k = 0..=8, of (1 + x)^n.
    swift_binomial: [f64; 9],
}

/// `C P = V Λ V⁻¹` with `V = C^½ Q`, `Q Λ Qᵀ = C^½ P C^½` (symmetric,
/// eigenvalues λ_i ≥ 0), so that `VᵀPV = Λ`: with `y = V⁻¹ σ_trial`, the
/// returned stress is `σ(Δλ) = V (y_i / (1 + Δλ λ_i))` and
/// `σ̄² = Σ λ_i y_i² / (1 + Δλ λ_i)²` — J2's closed form (Simo & Taylor's
/// `p`, `q` basis) for any `P`, computed once per material.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Spectral {
    v: [[f64; 3]; 3],
    v_inv: [[f64; 3]; 3],
    lam: [f64; 3],
    /// `λ_max⁻¹⁰`: makes the four-lane return's first Halley step, a ratio
    /// of two terms of tenth degree in stress, dimensionless (and so of
    /// the same size in MPa and in Pa) before their product of four is
    /// divided once.
    start_scale: f64,
}

impl Spectral {
    fn new(c11: f64, c12: f64, shear: f64, p: &[[f64; 3]; 3]) -> Self {
        // C^{±½}: the 2×2 block has eigenvectors (1, ±1)/√2.
        let root = |e: f64| {
            let (a, b) = ((c11 + c12).powf(e), (c11 - c12).powf(e));
            let (d, o) = (0.5 * (a + b), 0.5 * (a - b));
            [[d, o, 0.0], [o, d, 0.0], [0.0, 0.0, shear.powf(e)]]
        };
        let (half, inv_half) = (root(0.5), root(-0.5));
        let sm = mat_mul(&mat_mul(&half, p), &half);
        let eig = nalgebra::SymmetricEigen::new(nalgebra::Matrix3::from_fn(|i, j| {
            0.5 * (sm[i][j] + sm[j][i])
        }));
        let q: [[f64; 3]; 3] =
            std::array::from_fn(|i| std::array::from_fn(|j| eig.eigenvectors[(i, j)]));
        let qt: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| q[j][i]));
        let lam: [f64; 3] = std::array::from_fn(|i| eig.eigenvalues[i].max(0.0));
        Self {
            v: mat_mul(&half, &q),
            v_inv: mat_mul(&qt, &inv_half),
            lam,
            start_scale: lam[0].max(lam[1]).max(lam[2]).powi(-10),
        }
    }
}

/// History of one integration point of [`Hill48PlaneStress`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Hill48History {
    /// Equivalent plastic strain ε̄ (-), work-conjugate to the Hill stress.
    pub eps_p: f64,
    /// Flow stress at `eps_p` (MPa).
    pub sigma_y: f64,
}

impl super::HistoryWords for Hill48History {
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

impl Hill48PlaneStress {
    /// A validated material with RD along the element's `e1`: `young` E
    /// (MPa, positive), `poisson` ν in [0, 0.5), `density` ρ (tonne/mm³,
    /// positive), a valid hardening curve (flow stress along RD) and
    /// `r_values = [r0, r45, r90]`, each finite and positive.
    pub fn new(
        young: f64,
        poisson: f64,
        density: f64,
        hardening: Hardening,
        r_values: [f64; 3],
    ) -> Result<Self, ShellError> {
        check("young", young, "MPa", "> 0", young > 0.0)?;
        let nu_ok = (0.0..0.5).contains(&poisson);
        check("poisson", poisson, "-", "in [0, 0.5)", nu_ok)?;
        check("density", density, "tonne/mm^3", "> 0", density > 0.0)?;
        hardening.validate()?;
        let coeffs = HillCoefficients::from_r_values(r_values)?;
        let c11 = young / (1.0 - poisson * poisson);
        Ok(Self {
            young,
            poisson,
            density,
            r_values,
            angle: 0.0,
            shear: young / (2.0 * (1.0 + poisson)),
            c11,
            c12: poisson * c11,
            nu_ratio: poisson / (1.0 - poisson),
            p: coeffs.matrix(),
            spec: Spectral::new(
                c11,
                poisson * c11,
                young / (2.0 * (1.0 + poisson)),
                &coeffs.matrix(),
            ),
            swift_binomial: match hardening {
                Hardening::Swift { n, .. } => swift_binomial(n),
                Hardening::Table { .. } => [0.0; 9],
            },
            hardening,
        })
    }

    /// The same material with RD at `theta` (rad, finite) from the element's
    /// `e1`, counter-clockwise about `e3`.
    pub fn with_rolling_angle(mut self, theta: f64) -> Result<Self, ShellError> {
        check("rolling_angle", theta, "rad", "finite", true)?;
        let t = stress_rotation(theta);
        let pm = self.coefficients().matrix();
        self.p = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                (0..3)
                    .map(|a| (0..3).map(|b| t[a][i] * pm[a][b] * t[b][j]).sum::<f64>())
                    .sum()
            })
        });
        self.angle = theta;
        self.spec = Spectral::new(self.c11, self.c12, self.shear, &self.p);
        Ok(self)
    }

    /// The hardening curve (flow stress along RD).
    pub fn hardening(&self) -> &Hardening {
        &self.hardening
    }
    /// `[r0, r45, r90]`.
    pub fn r_values(&self) -> [f64; 3] {
        self.r_values
    }
    /// Angle θ (rad) from the element's `e1` to RD.
    pub fn rolling_angle(&self) -> f64 {
        self.angle
    }
    /// Hill coefficients of the r-values.
    pub fn coefficients(&self) -> HillCoefficients {
        HillCoefficients::from_r_values(self.r_values).expect("validated in new")
    }
    /// `P` in the element frame: `σ̄² = σᵀ P σ`.
    pub fn criterion_matrix(&self) -> [[f64; 3]; 3] {
        self.p
    }

    /// Elastic stress increment `C Δε` (engineering shear in, tensor shear out).
    fn elastic(&self, de: [f64; 3]) -> [f64; 3] {
        [
            self.c11 * de[0] + self.c12 * de[1],
            self.c12 * de[0] + self.c11 * de[1],
            self.shear * de[2],
        ]
    }

    /// Solve the return for a yielding trial stress `t` from history `h`:
    /// `(σ, Δλ, ε̄ increment, σ_y at the new ε̄)`.
    fn return_map(&self, t: [f64; 3], h: &Hill48History) -> ([f64; 3], f64, f64, f64) {
        let Spectral { v, v_inv, lam, .. } = &self.spec;
        let y = mat_vec(v_inv, &t);
        let a: [f64; 3] = std::array::from_fn(|i| lam[i] * y[i] * y[i]);
        // σ̄ and dσ̄/dΔλ at Δλ (one division for the three factors).
        let at = |dl: f64| {
            let b = [1.0 + dl * lam[0], 1.0 + dl * lam[1], 1.0 + dl * lam[2]];
            let inv = 1.0 / (b[0] * b[1] * b[2]);
            let f = [b[1] * b[2] * inv, b[0] * b[2] * inv, b[0] * b[1] * inv];
            let phi2 = (0..3).map(|i| a[i] * f[i] * f[i]).sum::<f64>();
            let dphi2 = (0..3)
                .map(|i| -2.0 * a[i] * lam[i] * f[i] * f[i] * f[i])
                .sum::<f64>();
            let phi = phi2.sqrt();
            (phi, 0.5 * dphi2 / phi)
        };
        let stress = |dl: f64| mat_vec(v, &std::array::from_fn(|i| y[i] / (1.0 + dl * lam[i])));
        let sy0 = h.sigma_y;
        let (mut lo, mut hi) = (0.0, f64::INFINITY);
        let mut dl = 0.0;
        for _ in 0..200 {
            let (phi, dphi) = at(dl);
            let d = dl * phi;
            // From the cached flow stress (Swift: no `powf` for small
            // increments, 1e-12 relative); the curve itself at the end.
            let (sy, hm) = self.hardening.eval_from(h.eps_p, sy0, d);
            let g = phi - sy;
            if g.abs() <= HILL_RETURN_TOL * sy0 {
                break;
            }
            if g > 0.0 {
                lo = dl;
            } else {
                hi = dl;
            }
            let dg = dphi - hm * (phi + dl * dphi);
            let mut next = dl - g / dg;
            let newton = next > lo && next < hi && next.is_finite();
            if !newton {
                next = if hi.is_finite() {
                    0.5 * (lo + hi)
                } else {
                    2.0 * lo.max(1e-3 / sy0)
                };
            }
            let small_step = (next - dl).abs() <= HILL_RETURN_TOL * next;
            dl = next;
            // Newton's error after this step is of order (g/σ_y)²: within
            // HILL_RETURN_CLOSE the step ends the return unevaluated.
            if small_step || (newton && g.abs() <= HILL_RETURN_CLOSE * sy0) {
                break;
            }
        }
        let d = dl * at(dl).0;
        (stress(dl), dl, d, self.hardening.eval(h.eps_p + d).0)
    }
}

impl Material for Hill48PlaneStress {
    type History = Hill48History;

    fn name(&self) -> &'static str {
        "hill48-plane-stress"
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
    fn initial_history(&self) -> Hill48History {
        Hill48History {
            eps_p: 0.0,
            sigma_y: self.hardening.eval(0.0).0,
        }
    }
    fn plastic_strain(&self, h: &Hill48History) -> f64 {
        h.eps_p
    }
    fn flow_stress(&self, h: &Hill48History) -> f64 {
        h.sigma_y
    }
    /// Hill's equivalent stress `√(σᵀ P σ)` (MPa), in the element frame.
    fn equivalent_stress(&self, s: &[f64; 3]) -> f64 {
        quad(&self.p, s).sqrt()
    }

    fn update(&self, s: &mut [f64; 3], h: &mut Hill48History, de: [f64; 3]) -> PointUpdate {
        let (t, elastic) = self.trial(s, h, de);
        if elastic {
            *s = t;
            return PointUpdate {
                deps_zz: -self.nu_ratio * (de[0] + de[1]),
                dissipation: 0.0,
            };
        }
        let (sn, dl, d, sy) = self.return_map(t, h);
        *s = sn;
        h.eps_p += d;
        h.sigma_y = sy;
        let ps = mat_vec(&self.p, &sn);
        let tr_p = dl * (ps[0] + ps[1]);
        PointUpdate {
            deps_zz: -self.nu_ratio * (de[0] + de[1] - tr_p) - tr_p,
            dissipation: sy * d,
        }
    }

    /// Four elements' sections in lanes: with Swift hardening the lane
    /// return (module documentation, "Four elements in lanes"), each branch
    /// a lane mask; a tabulated curve lane by lane through [`update`](Self::update).
    #[inline(always)]
    fn update_points_x4<L: Lanes4, const N: usize>(
        &self,
        s: &mut [[L; 3]; N],
        h: &mut [[Hill48History; N]; 4],
        de: &[[L; 3]; N],
    ) -> [PointUpdate<L>; N] {
        match self.hardening {
            Hardening::Swift { k, eps0, n } => self.swift_x4(k, eps0, n, s, h, de),
            Hardening::Table { .. } => update_points_by_lane(self, s, h, de),
        }
    }

    /// The closed-form algorithmic tangent of the closest-point return: the
    /// plane-stress elasticity `C` if the trial stress lies inside the yield
    /// surface, else the derivative of the converged return,
    /// `Ξ − a n nᵀ / (a σᵀPn + H φ²)` with `Ξ = (C⁻¹ + Δλ P)⁻¹`,
    /// `n = Ξ P σ`, `a = 1 − H Δλ`, `φ = √(σᵀPσ)` and `H` the curve's slope
    /// at the new ε̄ (`(a σᵀPn + H φ²)/φ` is `−g′(Δλ)` of the return's
    /// `g = σ̄ − σ_y`). The return is run again here; no allocation.
    fn consistent_tangent(&self, s: &[f64; 3], h: &Hill48History, de: [f64; 3]) -> [[f64; 3]; 3] {
        let (t, elastic) = self.trial(s, h, de);
        if elastic {
            return [
                [self.c11, self.c12, 0.0],
                [self.c12, self.c11, 0.0],
                [0.0, 0.0, self.shear],
            ];
        }
        let (_, dl, d, _) = self.return_map(t, h);
        self.plastic_tangent(&t, dl, self.hardening.eval(h.eps_p + d).1)
    }
}

impl Hill48PlaneStress {
    /// The elastic trial stress `σ + C Δε` and whether it lies inside (or
    /// on) the yield surface of the point's flow stress.
    fn trial(&self, s: &[f64; 3], h: &Hill48History, de: [f64; 3]) -> ([f64; 3], bool) {
        let dse = self.elastic(de);
        let t = [s[0] + dse[0], s[1] + dse[1], s[2] + dse[2]];
        let elastic = quad(&self.p, &t) <= h.sigma_y * h.sigma_y;
        (t, elastic)
    }

    /// `∂σ/∂Δε` of the converged return from the trial stress `t` with
    /// multiplier `dl` and hardening slope `slope` at the new ε̄.
    ///
    /// Differentiating `σ = Ξ(Δλ) C⁻¹ σ_trial` gives `dσ = Ξ dΔε − n dΔλ`
    /// (`dΞ/dΔλ = −Ξ P Ξ`), and `g = φ − σ_y(ε̄_n + Δλ φ) = 0` gives
    /// `a (nᵀdΔε − σᵀPn dΔλ) = H φ² dΔλ`. In the spectral basis
    /// (`Spectral`), with `D = diag(1/(1 + Δλ λ_i))` and `z = D V⁻¹ σ_trial`
    /// (so `σ = V z`): `Ξ = V D Vᵀ`, `n = V D Λ z`, `σᵀPn = Σ λ_i² D_i z_i²`
    /// and `φ² = Σ λ_i z_i²`.
    fn plastic_tangent(&self, t: &[f64; 3], dl: f64, slope: f64) -> [[f64; 3]; 3] {
        let Spectral { v, v_inv, lam, .. } = &self.spec;
        let y = mat_vec(v_inv, t);
        let dk: [f64; 3] = std::array::from_fn(|k| 1.0 / (1.0 + dl * lam[k]));
        let z: [f64; 3] = std::array::from_fn(|k| y[k] * dk[k]);
        let w: [f64; 3] = std::array::from_fn(|k| lam[k] * dk[k] * z[k]);
        let s_pn = (0..3).map(|k| lam[k] * z[k] * w[k]).sum::<f64>();
        let phi2 = (0..3).map(|k| lam[k] * z[k] * z[k]).sum::<f64>();
        let a = 1.0 - slope * dl;
        let c = a / (a * s_pn + slope * phi2);
        let n = mat_vec(v, &w);
        std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let xi = (0..3).map(|k| v[i][k] * dk[k] * v[j][k]).sum::<f64>();
                xi - c * n[i] * n[j]
            })
        })
    }
}

/// Residual `|F| = |σ̄² − σ_y²| / 2`, relative to `σ_y²` at the start of
/// the step, below which a lane of the four-lane return takes its last
/// Halley step to second order in its size δ instead of evaluating again.
/// Halley's error is then of order `(LANE_CLOSE)³ ≈ 1e-15` relative, the
/// second-order updates' (`f_i`, `Δε̄`, σ_y) of order `(λ_i δ)³`, smaller
/// still; a typical explicit increment, whose Halley start from `Δλ = 0`
/// leaves `|F|/σ_y² ~ 1e-6`, thus needs one evaluation.
const LANE_CLOSE: f64 = 1e-5;

/// Iterations of the four-lane return before a lane is taken as it is (a
/// bisection from the largest bracket halves it fifty times within this).
const LANE_ITERATIONS: usize = 100;

/// Where a lane return ends (four lanes).
#[derive(Debug, Clone, Copy)]
struct LaneReturn<L> {
    /// Plastic multiplier Δλ.
    dl: L,
    /// `1 / (1 + Δλ λ_i)`, i = 0, 1, 2.
    f: [L; 3],
    /// Equivalent plastic strain increment Δε̄.
    d: L,
    /// Flow stress at `ε̄ + Δε̄`.
    sy: L,
}

impl Hill48PlaneStress {
    /// [`Material::update_points_x4`] with Swift hardening: every point's
    /// trial first (the scalar update's operations in its order, so that
    /// elastic lanes are its bits), then the return of each point with a
    /// lane outside the yield surface, elastic or converged lanes masked.
    /// Plain loops and no closures, so that all of it compiles inside the
    /// element kernel's target features.
    #[inline(always)]
    fn swift_x4<L: Lanes4, const N: usize>(
        &self,
        k: f64,
        eps0: f64,
        n: f64,
        s: &mut [[L; 3]; N],
        h: &mut [[Hill48History; N]; 4],
        de: &[[L; 3]; N],
    ) -> [PointUpdate<L>; N] {
        let mut out = [PointUpdate::<L>::default(); N];
        let no = L::splat(0.0).gt(L::splat(0.0));
        let mut plastic = [no; N];
        let mut any_plastic = false;
        for p in 0..N {
            let sy0 = L::from_array([
                h[0][p].sigma_y,
                h[1][p].sigma_y,
                h[2][p].sigma_y,
                h[3][p].sigma_y,
            ]);
            let (t, elastic) = self.trial_x4(&s[p], sy0, &de[p]);
            s[p] = t;
            out[p].deps_zz = (de[p][0] + de[p][1]) * -self.nu_ratio;
            plastic[p] = L::mask_not(elastic);
            any_plastic |= L::any(plastic[p]);
        }
        if !any_plastic {
            return out;
        }
        let Spectral { v, v_inv, lam, .. } = self.spec;
        // Row sums of P: the in-plane trace of P σ is `tr · σ`.
        let tr = [
            self.p[0][0] + self.p[1][0],
            self.p[0][1] + self.p[1][1],
            self.p[0][2] + self.p[1][2],
        ];
        for p in 0..N {
            let pl = plastic[p];
            if !L::any(pl) {
                continue;
            }
            let eps_p = L::from_array([h[0][p].eps_p, h[1][p].eps_p, h[2][p].eps_p, h[3][p].eps_p]);
            let sy0 = L::from_array([
                h[0][p].sigma_y,
                h[1][p].sigma_y,
                h[2][p].sigma_y,
                h[3][p].sigma_y,
            ]);
            let [t0, t1, t2] = s[p];
            // y = V⁻¹ σ_trial and a_i = λ_i y_i² (σ̄² = Σ a_i f_i²).
            let mut y = [t0; 3];
            let mut a = [t0; 3];
            for i in 0..3 {
                y[i] = t2.madd(
                    L::splat(v_inv[i][2]),
                    t1.madd(L::splat(v_inv[i][1]), t0 * v_inv[i][0]),
                );
                a[i] = y[i] * y[i] * lam[i];
            }
            let e = eps_p + eps0;
            let curve = Swift {
                c: &self.swift_binomial,
                k,
                n,
                sy0,
                e,
                inv_e: L::splat(1.0) / e,
            };
            let r = self.swift_return_x4(&curve, a, pl);
            // σ = V (y_i f_i); the in-plane trace of Δε^p = Δλ P σ.
            let z = [y[0] * r.f[0], y[1] * r.f[1], y[2] * r.f[2]];
            let mut sn = [t0; 3];
            for c in 0..3 {
                sn[c] = z[2].madd(
                    L::splat(v[c][2]),
                    z[1].madd(L::splat(v[c][1]), z[0] * v[c][0]),
                );
            }
            let tr_p =
                r.dl * sn[2].madd(L::splat(tr[2]), sn[1].madd(L::splat(tr[1]), sn[0] * tr[0]));
            let deps_zz = (de[p][0] + de[p][1] - tr_p).madd(L::splat(-self.nu_ratio), -tr_p);
            for c in 0..3 {
                s[p][c] = L::select(pl, sn[c], s[p][c]);
            }
            out[p].deps_zz = L::select(pl, deps_zz, out[p].deps_zz);
            out[p].dissipation = L::select(pl, r.sy * r.d, L::splat(0.0));
            let eps_new = L::select(pl, eps_p + r.d, eps_p).to_array();
            let sy_new = L::select(pl, r.sy, sy0).to_array();
            for l in 0..4 {
                h[l][p] = Hill48History {
                    eps_p: eps_new[l],
                    sigma_y: sy_new[l],
                };
            }
        }
        out
    }

    /// The trial stress `σ + C Δε` of four lanes and whether each lies
    /// inside (or on) its yield surface: the scalar [`trial`](Self::trial)'s
    /// operations in its order (no fused products), so the same bits.
    #[inline(always)]
    fn trial_x4<L: Lanes4>(&self, s: &[L; 3], sy0: L, de: &[L; 3]) -> ([L; 3], L::Mask) {
        let (c11, c12) = (self.c11, self.c12);
        let t = [
            s[0] + (de[0] * c11 + de[1] * c12),
            s[1] + (de[0] * c12 + de[1] * c11),
            s[2] + de[2] * self.shear,
        ];
        let pm = &self.p;
        let mut pt = [t[0]; 3];
        for i in 0..3 {
            pt[i] = t[0] * pm[i][0] + t[1] * pm[i][1] + t[2] * pm[i][2];
        }
        let quad = t[0] * pt[0] + t[1] * pt[1] + t[2] * pt[2];
        (t, L::le(quad, sy0 * sy0))
    }

    /// The return of the lanes of `plastic` (the others are computed and
    /// not used) for `a_i = λ_i y_i²` of their trial stresses, on Swift's
    /// `curve` from each lane's ε̄ and cached flow stress.
    ///
    /// The root of `F(Δλ) = ½(w − σ_y(Δε̄)²)`, `w = σ̄² = Σ a_i f_i²`,
    /// `f_i = 1/(1 + Δλ λ_i)`, `Δε̄ = Δλ √w`, by Halley steps
    /// `δ = −F F′ / (F′² − ½ F F″)`. With `m1 = Σ a_i λ_i f_i³`,
    /// `m2 = Σ a_i λ_i² f_i⁴` (`w′ = −2 m1`, `w″ = 6 m2`), `φ = √w`,
    /// `h = ε0 + ε̄ + Δε̄` (Swift: `σ_y′ = n σ_y / h`), `S = h φ`:
    /// `Δε̄′ = G/φ` with `G = w − Δλ m1`; `Δε̄″ = K/(wφ)` with
    /// `K = −2 w m1 + Δλ (3 w m2 − m1²)`; `F′ = A/S` with
    /// `A = −m1 S − n σ_y² G`; `F″ = B/(w S²)` with
    /// `B = 3 w m2 S² − n (2n − 1) w σ_y² G² − n σ_y² K S`; so
    /// `δ = q w S` with `q = −2 F A / (2 w A² − F B)`, one division (the
    /// first, from Δλ = 0 in closed form, shares its division with the
    /// evaluation at its end, below; Newton's step where Halley's
    /// denominator is below half of Newton's). The last
    /// step (`|F| ≤ LANE_CLOSE σ_y,0²`) updates to second order in δ:
    /// `f_i (1 − ε_i + ε_i²)` with `ε_i = δ λ_i f_i`, and
    /// `Δε̄ + u h` with `u = (Δε̄′ δ + ½ Δε̄″ δ²) / h = q (G w + ½ K δ)`,
    /// σ_y by Swift's series in `u` ([`Curve::step`]). A step outside the
    /// bracket `(lo, hi)` of Δλ (F > 0 at lo, < 0 at hi) is replaced by
    /// bisection (or doubling while no upper end is known), as in the
    /// scalar return; a lane with `|F| ≤ HILL_RETURN_TOL σ_y,0²` ends
    /// where it is.
    #[inline(always)]
    fn swift_return_x4<L: Lanes4>(
        &self,
        curve: &Swift<'_, L>,
        a: [L; 3],
        plastic: L::Mask,
    ) -> LaneReturn<L> {
        let lam = self.spec.lam;
        let n = curve.n;
        let (zero, one) = (L::splat(0.0), L::splat(1.0));
        let sy0 = curve.sy0;
        let sy0sq = sy0 * sy0;
        let tol = sy0sq * HILL_RETURN_TOL;
        let close = sy0sq * LANE_CLOSE;
        // The first Halley step from Δλ = 0, δ0 = N0 / D0, from the closed
        // form there (f_i = 1, Δε̄ = 0, σ_y = σ_y,0; the terms as in the loop
        // below), and the first evaluation at it, with one division: with
        // B_i = D0 + N0 λ_i, `1 + δ0 λ_i = B_i / D0`, so `f_i = D0 / B_i`,
        // and with R = 1 / (D0 B_0 B_1 B_2): δ0 = N0 B_0 B_1 B_2 R,
        // f_i = D0² B_j B_k R, σ̄ = D0² R √(Σ a_i (B_j B_k)²) (the square
        // root beside the division). N0 and D0 are of tenth degree in stress,
        // so they are scaled by λ_max⁻¹⁰ first (`Spectral::start_scale`).
        let w0 = a[0] + a[1] + a[2];
        let s0 = curve.e * w0.sqrt();
        let p = [a[0] * lam[0], a[1] * lam[1], a[2] * lam[2]];
        let m1 = p[0] + p[1] + p[2];
        let m2 = p[2].madd(L::splat(lam[2]), p[1].madd(L::splat(lam[1]), p[0] * lam[0]));
        let nsy2 = sy0sq * n;
        let f0 = (w0 - sy0sq) * 0.5;
        let a0 = (-m1).madd(s0, -(nsy2 * w0));
        let kk0 = w0 * -2.0 * m1;
        let bb0 = (w0 * 3.0 * m2 * s0).madd(
            s0,
            (-(nsy2 * (2.0 * n - 1.0) * w0 * w0)).madd(w0, -(nsy2 * kk0 * s0)),
        );
        let scale = self.spec.start_scale;
        let newton = w0 * 2.0 * a0 * a0 * scale;
        let halley = (w0 * 2.0 * a0).madd(a0, -(f0 * bb0)) * scale;
        // Halley's denominator, or Newton's where Halley's is below half of
        // it (a step far from the root); 1 where there is no stress (a lane
        // that is not plastic: δ0 = 0, not 0/0).
        let den0 = L::select(
            halley.gt(newton * 0.5),
            halley,
            L::select(newton.gt(zero), newton, one),
        );
        let num0 = f0 * a0 * w0 * s0 * (-2.0 * scale);
        let num0 = L::select(num0.gt(zero), num0, zero);
        let bs = [
            num0.madd(L::splat(lam[0]), den0),
            num0.madd(L::splat(lam[1]), den0),
            num0.madd(L::splat(lam[2]), den0),
        ];
        let b01 = bs[0] * bs[1];
        let b012 = b01 * bs[2];
        let rr = one / (den0 * b012);
        let (b12, b02) = (bs[1] * bs[2], bs[0] * bs[2]);
        let sum = (a[2] * b01).madd(b01, (a[1] * b02).madd(b02, a[0] * b12 * b12));
        let root = sum.sqrt();
        let c = den0 * den0 * rr;
        // The state at Δλ: f_i, w = σ̄², φ, Δε̄ and σ_y there.
        let mut dl = num0 * b012 * rr;
        let mut f = [b12 * c, b02 * c, b01 * c];
        let mut w = sum * c * c;
        let mut phi = root * c;
        let mut d = dl * phi;
        let mut sy = curve.flow(d, plastic);
        let mut lo = zero;
        let mut hi = L::splat(f64::INFINITY);
        let mut r = LaneReturn {
            dl: zero,
            f: [one; 3],
            d: zero,
            sy: sy0,
        };
        let mut active = plastic;
        for _ in 0..LANE_ITERATIONS {
            let hd = curve.e + d;
            let big_s = hd * phi;
            let lf = [f[0] * lam[0], f[1] * lam[1], f[2] * lam[2]];
            let p0 = a[0] * f[0] * f[0] * lf[0];
            let p1 = a[1] * f[1] * f[1] * lf[1];
            let p2 = a[2] * f[2] * f[2] * lf[2];
            let m1 = p0 + p1 + p2;
            let m2 = p2.madd(lf[2], p1.madd(lf[1], p0 * lf[0]));
            let g = (-dl).madd(m1, w);
            let kk = (w * 3.0).madd(m2, -(m1 * m1)).madd(dl, w * -2.0 * m1);
            let sy2 = sy * sy;
            let nsy2 = sy2 * n;
            let ff = (w - sy2) * 0.5;
            let aa = (-m1).madd(big_s, -(nsy2 * g));
            let bb = (w * 3.0 * m2 * big_s).madd(
                big_s,
                (-(nsy2 * (2.0 * n - 1.0) * w * g)).madd(g, -(nsy2 * kk * big_s)),
            );
            let den = (w * 2.0 * aa).madd(aa, -(ff * bb));
            let q = ff * aa * -2.0 / den;
            let tiny = L::le(ff.abs(), tol);
            let q = L::select(tiny, zero, q);
            let delta = q * w * big_s;
            let next = dl + delta;
            // The bracket of the root (this lane's F at Δλ).
            lo = L::select(L::mask_and(active, ff.gt(zero)), dl, lo);
            hi = L::select(L::mask_and(active, ff.lt(zero)), dl, hi);
            let inside = L::mask_and(next.gt(lo), next.lt(hi));
            let ok = L::mask_or(tiny, inside);
            let last = L::mask_and(L::mask_and(active, ok), L::le(ff.abs(), close));
            if L::any(last) {
                // Second order in δ (see above).
                let u = q * (g * w).madd(one, kk * delta * 0.5);
                let mut f_last = f;
                for i in 0..3 {
                    let eps = delta * lf[i];
                    f_last[i] = (-(f[i] * eps)).madd(one - eps, f[i]);
                }
                let d_last = u.madd(hd, d);
                let sy_last = curve.step(sy, u, d_last, last);
                r.dl = L::select(last, next, r.dl);
                for i in 0..3 {
                    r.f[i] = L::select(last, f_last[i], r.f[i]);
                }
                r.d = L::select(last, d_last, r.d);
                r.sy = L::select(last, sy_last, r.sy);
            }
            active = L::mask_and_not(active, last);
            if !L::any(active) {
                return r;
            }
            let bad = L::mask_and_not(active, ok);
            let next = if L::any(bad) {
                // Bisection inside the bracket, or doubling beyond 1e-3/σ_y
                // (a strain of 1e-3) while it has no upper end.
                let grow = lo.max(L::splat(1e-3) / sy0) * 2.0;
                let halve = (lo + hi) * 0.5;
                let fallback = L::select(hi.lt(L::splat(f64::INFINITY)), halve, grow);
                L::select(bad, fallback, next)
            } else {
                next
            };
            dl = L::select(active, next, dl);
            // Evaluate at the new Δλ: one division for the three f_i.
            let b = [
                dl.madd(L::splat(lam[0]), one),
                dl.madd(L::splat(lam[1]), one),
                dl.madd(L::splat(lam[2]), one),
            ];
            let b01 = b[0] * b[1];
            let inv = one / (b01 * b[2]);
            f = [b[1] * b[2] * inv, b[0] * b[2] * inv, b01 * inv];
            w = (a[2] * f[2]).madd(f[2], (a[1] * f[1]).madd(f[1], a[0] * f[0] * f[0]));
            phi = w.sqrt();
            d = dl * phi;
            sy = curve.flow(d, active);
        }
        // Lanes still open after the iterations: as they are.
        r.dl = L::select(active, dl, r.dl);
        for i in 0..3 {
            r.f[i] = L::select(active, f[i], r.f[i]);
        }
        r.d = L::select(active, d, r.d);
        r.sy = L::select(active, sy, r.sy);
        r
    }
}

fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn mat_vec(m: &[[f64; 3]; 3], v: &[f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| dot(&m[i], v))
}

fn mat_mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

/// `vᵀ M v`.
fn quad(m: &[[f64; 3]; 3], v: &[f64; 3]) -> f64 {
    dot(v, &mat_vec(m, v))
}

#[cfg(test)]
#[path = "hill48_tests.rs"]
mod tests;
