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

use super::{Hardening, Material, PointUpdate};
use crate::error::{ShellError, check};

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
        Self {
            v: mat_mul(&half, &q),
            v_inv: mat_mul(&qt, &inv_half),
            lam: std::array::from_fn(|i| eig.eigenvalues[i].max(0.0)),
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
            hardening,
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
        let Spectral { v, v_inv, lam } = &self.spec;
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
        let Spectral { v, v_inv, lam } = &self.spec;
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
