//! The material itself: [`J2Voce`] and its [`UserMaterial`] impl (the
//! formulas are in the crate docs). Kept apart from the export so that the
//! test fixture `plugins/test-broken-material` can compile the same file.

use plugins_api::ParamSpec;
use plugins_api::material::{Elastic, PointResult, UserMaterial};

/// The material's parameters (see [`J2Voce::PARAMS`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct J2Voce {
    /// Elastic constants and density.
    pub elastic: Elastic,
    /// Initial yield stress σ_0 (MPa).
    pub sigma0: f64,
    /// Voce saturation stress Q (MPa).
    pub q: f64,
    /// Voce rate b (-).
    pub b: f64,
    /// Linear hardening modulus H (MPa).
    pub h: f64,
}

impl J2Voce {
    /// Flow stress σ_y(ε_p) (MPa) and its slope dσ_y/dε_p (MPa).
    #[must_use]
    pub fn hardening(&self, eps_p: f64) -> (f64, f64) {
        let decay = (-self.b * eps_p).exp();
        (
            self.sigma0 + self.q * (1.0 - decay) + self.h * eps_p,
            self.q * self.b * decay + self.h,
        )
    }

    /// The plastic multiplier Δγ ≥ 0 that puts the trial state (sum² `a1`,
    /// difference-and-shear² `a2`, as in the crate docs) on the yield
    /// surface from plastic strain `eps_p`.
    fn multiplier(&self, a1: f64, a2: f64, eps_p: f64) -> f64 {
        let Elastic { young, poisson, .. } = self.elastic;
        let (c1, c2) = (young / (3.0 * (1.0 - poisson)), young / (1.0 + poisson));
        // g(Δγ) = ½ f̄² - ⅓ σ_y², decreasing from g(0) > 0.
        let g = |dg: f64| {
            let (d1, d2) = (1.0 + c1 * dg, 1.0 + c2 * dg);
            let f2 = a1 / (d1 * d1) + a2 / (d2 * d2);
            let df2 = -2.0 * c1 * a1 / (d1 * d1 * d1) - 2.0 * c2 * a2 / (d2 * d2 * d2);
            let f = f2.sqrt();
            let kappa = eps_p + (2.0f64 / 3.0).sqrt() * dg * f;
            let dkappa = (2.0f64 / 3.0).sqrt() * (f + dg * df2 / (2.0 * f));
            let (sy, hy) = self.hardening(kappa);
            (
                0.5 * f2 - sy * sy / 3.0,
                0.5 * df2 - 2.0 / 3.0 * sy * hy * dkappa,
            )
        };
        // Newton from Δγ = 0, kept inside the bracket [lo, hi] that the
        // signs of g give (bisection, or doubling while there is no upper
        // end, when a Newton step leaves it). Converged when |g| is below
        // 1e-13 of σ_y²/3 at the start (|σ_vm/σ_y - 1| ~ 1e-13).
        let tol = 1e-13 * self.hardening(eps_p).0.powi(2) / 3.0;
        let (mut lo, mut hi, mut x) = (0.0, f64::INFINITY, 0.0);
        for _ in 0..200 {
            let (v, dv) = g(x);
            if v.abs() <= tol {
                return x;
            }
            if v > 0.0 {
                lo = x;
            } else {
                hi = x;
            }
            let newton = x - v / dv;
            x = if newton > lo && newton < hi {
                newton
            } else if hi.is_finite() {
                0.5 * (lo + hi)
            } else {
                2.0 * lo.max(1e-6 / c2)
            };
        }
        x
    }
}

impl UserMaterial for J2Voce {
    const NAME: &'static str = "j2-voce";
    const SUMMARY: &'static str = "plane-stress J2 plasticity, Voce hardening sigma_y = sigma0 + q (1 - exp(-b eps_p)) + h eps_p; state: eps_p";
    // Defaults: a mild steel (E, ν, ρ) yielding at 200 MPa without
    // hardening; in a scene, youngs_modulus, poissons_ratio and density come
    // from [blank.material] unless `parameters` sets them.
    const PARAMS: &'static [ParamSpec] = &[
        ParamSpec::optional(
            "youngs_modulus",
            "MPa",
            210_000.0,
            0.0,
            f64::INFINITY,
            "Young's modulus E",
        )
        .exclusive_min(),
        ParamSpec::optional("poissons_ratio", "-", 0.3, -1.0, 0.5, "Poisson's ratio nu")
            .exclusive_min(),
        ParamSpec::optional(
            "density",
            "tonne/mm^3",
            7.85e-9,
            0.0,
            f64::INFINITY,
            "mass density",
        )
        .exclusive_min(),
        ParamSpec::optional(
            "sigma0",
            "MPa",
            200.0,
            0.0,
            f64::INFINITY,
            "initial yield stress",
        )
        .exclusive_min(),
        ParamSpec::optional(
            "q",
            "MPa",
            0.0,
            0.0,
            f64::INFINITY,
            "Voce saturation stress Q",
        ),
        ParamSpec::optional("b", "-", 0.0, 0.0, f64::INFINITY, "Voce rate b"),
        ParamSpec::optional(
            "h",
            "MPa",
            0.0,
            0.0,
            f64::INFINITY,
            "linear hardening modulus H",
        ),
    ];
    const N_STATE: usize = 1;
    const ISOTROPIC: bool = true;

    fn from_values(v: &[f64]) -> Result<Self, String> {
        let elastic = Elastic {
            young: v[0],
            poisson: v[1],
            density: v[2],
        };
        if v[1] >= 0.5 {
            return Err(format!("poissons_ratio = {} must be < 0.5", v[1]));
        }
        Ok(Self {
            elastic,
            sigma0: v[3],
            q: v[4],
            b: v[5],
            h: v[6],
        })
    }

    fn elastic(&self) -> Elastic {
        self.elastic
    }

    fn initial_state(&self, state: &mut [f64]) -> f64 {
        state[0] = 0.0;
        self.sigma0
    }

    fn update(
        &self,
        deps: [f64; 3],
        stress: &mut [f64; 3],
        state: &mut [f64],
    ) -> Result<PointResult, String> {
        let Elastic { young, poisson, .. } = self.elastic;
        let c = young / (1.0 - poisson * poisson);
        let g2 = young / (1.0 + poisson);
        let old = *stress;
        // Elastic predictor (engineering shear in, tensor shear out).
        let t = [
            old[0] + c * (deps[0] + poisson * deps[1]),
            old[1] + c * (deps[1] + poisson * deps[0]),
            old[2] + 0.5 * g2 * deps[2],
        ];
        let eps_p = state[0];
        let (sy, _) = self.hardening(eps_p);
        let (sum, diff) = (t[0] + t[1], t[1] - t[0]);
        let (a1, a2) = (sum * sum / 6.0, diff * diff / 2.0 + 2.0 * t[2] * t[2]);
        let elastic_dzz = |s: &[f64; 3]| -poisson / young * (s[0] + s[1] - old[0] - old[1]);
        if 0.5 * (a1 + a2) - sy * sy / 3.0 <= 0.0 {
            *stress = t;
            return Ok(PointResult {
                deps_zz: elastic_dzz(&t),
                dissipation: 0.0,
                plastic_strain: eps_p,
                flow_stress: sy,
            });
        }
        let dg = self.multiplier(a1, a2, eps_p);
        let d1 = 1.0 + young / (3.0 * (1.0 - poisson)) * dg;
        let d2 = 1.0 + g2 * dg;
        let (s_sum, s_diff) = (sum / d1, diff / d2);
        let s = [0.5 * (s_sum - s_diff), 0.5 * (s_sum + s_diff), t[2] / d2];
        let f = (a1 / (d1 * d1) + a2 / (d2 * d2)).sqrt();
        let deps_p = (2.0f64 / 3.0).sqrt() * dg * f;
        let (sy_new, _) = self.hardening(eps_p + deps_p);
        *stress = s;
        state[0] = eps_p + deps_p;
        Ok(PointResult {
            deps_zz: elastic_dzz(&s) - dg * (s[0] + s[1]) / 3.0,
            dissipation: sy_new * deps_p,
            plastic_strain: eps_p + deps_p,
            flow_stress: sy_new,
        })
    }
}
