//! Shell sections: thickness, through-thickness integration rule (Gauss or Lobatto), shear correction, hourglass coefficient.

use crate::error::{ShellError, check};

/// Largest number of through-thickness points a section may have.
pub const MAX_THICKNESS_POINTS: usize = 32;

/// Family of the through-thickness quadrature.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RuleKind {
    /// Gauss–Legendre (exact for polynomials of degree 2n−1; no point on the surfaces).
    #[default]
    Gauss,
    /// Gauss–Lobatto (points on both surfaces; exact to degree 2n−3), n ≥ 2.
    Lobatto,
}

/// Through-thickness points `ζ ∈ [−1, 1]` (ζ = 2z/t) and weights summing to 2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThroughThickness {
    /// Number of points.
    pub n: usize,
    /// Positions ζ_k, increasing (bottom to top).
    pub zeta: [f64; MAX_THICKNESS_POINTS],
    /// Weights w_k (sum 2).
    pub weight: [f64; MAX_THICKNESS_POINTS],
}

/// Legendre polynomial P_n and its derivative at x.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let k = k as f64;
        let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    let nf = n as f64;
    let dp = if (1.0 - x * x).abs() < 1e-300 {
        0.0
    } else {
        nf * (p0 - x * p1) / (1.0 - x * x)
    };
    (p1, dp)
}

impl ThroughThickness {
    /// An `n`-point rule of the given kind (Gauss: 1..=32, Lobatto: 2..=32).
    pub fn new(kind: RuleKind, n: usize) -> Result<Self, ShellError> {
        let lo = if kind == RuleKind::Lobatto { 2.0 } else { 1.0 };
        check(
            "thickness_points",
            n as f64,
            "-",
            "an integer in [1, 32] (Gauss) or [2, 32] (Lobatto)",
            (lo..=MAX_THICKNESS_POINTS as f64).contains(&(n as f64)),
        )?;
        let mut zeta = [0.0; MAX_THICKNESS_POINTS];
        let mut weight = [0.0; MAX_THICKNESS_POINTS];
        let nf = n as f64;
        match kind {
            RuleKind::Gauss => {
                for i in 0..n {
                    let mut x = -(std::f64::consts::PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
                    for _ in 0..100 {
                        let (p, dp) = legendre(n, x);
                        let dx = p / dp;
                        x -= dx;
                        if dx.abs() < 1e-16 {
                            break;
                        }
                    }
                    let (_, dp) = legendre(n, x);
                    zeta[i] = x;
                    weight[i] = 2.0 / ((1.0 - x * x) * dp * dp);
                }
            }
            RuleKind::Lobatto => {
                zeta[0] = -1.0;
                zeta[n - 1] = 1.0;
                let end = 2.0 / (nf * (nf - 1.0));
                weight[0] = end;
                weight[n - 1] = end;
                // Interior points: roots of P'_{n-1}; Newton on P'_{n-1} using
                // (1-x²) P'' = 2x P' - m(m+1) P.
                let m = n - 1;
                let mf = m as f64;
                for i in 1..n - 1 {
                    let mut x = -(std::f64::consts::PI * i as f64 / mf).cos();
                    for _ in 0..100 {
                        let (p, dp) = legendre(m, x);
                        let ddp = (2.0 * x * dp - mf * (mf + 1.0) * p) / (1.0 - x * x);
                        let dx = dp / ddp;
                        x -= dx;
                        if dx.abs() < 1e-16 {
                            break;
                        }
                    }
                    let (p, _) = legendre(m, x);
                    zeta[i] = x;
                    weight[i] = 2.0 / (mf * (mf + 1.0) * p * p);
                }
            }
        }
        Ok(Self { n, zeta, weight })
    }

    /// Points and weights as slices of length `n`.
    pub fn points(&self) -> (&[f64], &[f64]) {
        (&self.zeta[..self.n], &self.weight[..self.n])
    }
}

/// Section and control parameters common to every element of a shell set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    /// Initial thickness t0 (mm), > 0.
    pub thickness: f64,
    /// Through-thickness rule (default: 5 Gauss points).
    pub rule: ThroughThickness,
    /// Transverse shear correction factor κ (-), default 5/6.
    pub shear_factor: f64,
    /// Hourglass coefficient r (-) of the stiffness-based control (Belytschko–Tsay only), default 0.05.
    pub hourglass: f64,
}

impl Section {
    /// A section of thickness `t0` (mm) with the defaults: 5 Gauss points, κ = 5/6, r_hg = 0.05.
    pub fn new(thickness: f64) -> Result<Self, ShellError> {
        check("thickness", thickness, "mm", "> 0", thickness > 0.0)?;
        Ok(Self {
            thickness,
            rule: ThroughThickness::new(RuleKind::Gauss, 5)?,
            shear_factor: 5.0 / 6.0,
            hourglass: 0.05,
        })
    }

    /// Replace the through-thickness rule.
    pub fn with_rule(mut self, kind: RuleKind, n: usize) -> Result<Self, ShellError> {
        self.rule = ThroughThickness::new(kind, n)?;
        Ok(self)
    }

    /// Replace the hourglass coefficient (in [0, 1]).
    pub fn with_hourglass(mut self, r: f64) -> Result<Self, ShellError> {
        check("hourglass", r, "-", "in [0, 1]", (0.0..=1.0).contains(&r))?;
        self.hourglass = r;
        Ok(self)
    }

    /// Replace the shear correction factor (in (0, 1]).
    pub fn with_shear_factor(mut self, k: f64) -> Result<Self, ShellError> {
        check("shear_factor", k, "-", "in (0, 1]", k > 0.0 && k <= 1.0)?;
        self.shear_factor = k;
        Ok(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Gauss n integrates ζ^(2n−1)-degree polynomials exactly, Lobatto 2n−3 (Abramowitz & Stegun 25.4.29/25.4.32); 1e-13.
    #[test]
    fn rules_integrate_polynomials_to_their_degree() {
        for n in 1usize..=10 {
            for (kind, deg) in [
                (RuleKind::Gauss, 2 * n - 1),
                (RuleKind::Lobatto, (2 * n).saturating_sub(3)),
            ] {
                if kind == RuleKind::Lobatto && n < 2 {
                    continue;
                }
                let r = ThroughThickness::new(kind, n).unwrap();
                let (z, w) = r.points();
                for p in 0..=deg {
                    let q: f64 = z.iter().zip(w).map(|(z, w)| w * z.powi(p as i32)).sum();
                    let exact = if p % 2 == 1 {
                        0.0
                    } else {
                        2.0 / (p as f64 + 1.0)
                    };
                    assert!((q - exact).abs() < 1e-13, "{kind:?} n={n} p={p}: {q}");
                }
            }
        }
        assert!(ThroughThickness::new(RuleKind::Gauss, 0).is_err());
        assert!(ThroughThickness::new(RuleKind::Lobatto, 1).is_err());
        assert!(
            Section::new(0.0)
                .unwrap_err()
                .to_string()
                .contains("thickness")
        );
    }
}
