//! The hardening curve as the returns see it, for one point (`f64`) or the
//! lanes of four: Swift's law from a point's cached flow stress by binomial
//! series (no `powf` for the small plastic strain increments of explicit
//! steps), shared by [`J2PlaneStress`](super::J2PlaneStress) and
//! [`Hill48PlaneStress`](super::Hill48PlaneStress).

use crate::lanes::Real;

/// Binomial coefficients C(n, k), k = 0..=8, of `(1 + x)^n` (Swift's
/// exponent `n`): the series of [`Swift`]'s curve.
pub(super) fn swift_binomial(n: f64) -> [f64; 9] {
    let mut c = [0.0; 9];
    c[0] = 1.0;
    for k in 1..9 {
        c[k] = c[k - 1] * (n - (k - 1) as f64) / k as f64;
    }
    c
}

/// `Σ c_k x^k`, k = 0..=8, by Estrin's scheme: pairs in x, then in x²,
/// then in x⁴ (a chain of five operations instead of Horner's nine). For
/// `f64` and in lanes alike (`madd` fused in lanes only).
#[inline(always)]
pub(super) fn series8<T: Real>(c: &[f64; 9], x: T) -> T {
    let x2 = x * x;
    let x4 = x2 * x2;
    let p01 = x.madd(T::splat(c[1]), T::splat(c[0]));
    let p23 = x.madd(T::splat(c[3]), T::splat(c[2]));
    let p45 = x.madd(T::splat(c[5]), T::splat(c[4]));
    let p67 = x.madd(T::splat(c[7]), T::splat(c[6]));
    let q0 = x2.madd(p23, p01);
    let q1 = x2.madd(p67, p45);
    x4.madd(x4.madd(T::splat(c[8]), q1), q0)
}

/// `Σ c_k u^k`, k = 0..=4, by Horner's scheme (`f64` and lanes).
#[inline(always)]
pub(super) fn series4<T: Real>(c: &[f64; 9], u: T) -> T {
    let mut acc = u.madd(T::splat(c[4]), T::splat(c[3]));
    for j in (0..3).rev() {
        acc = u.madd(acc, T::splat(c[j]));
    }
    acc
}

/// Relative size `u` of the last Newton step's plastic strain increment
/// below which Swift's flow stress after it is `σ_y (1 + u)^n` to u⁴.
pub(super) const STEP_SERIES: f64 = 1e-3;

/// The hardening curve as the return sees it, for one point (`T = f64`) or
/// the lanes of four.
pub(super) trait Curve<T: Real> {
    /// σ_y at `ε_p + d` in the lanes of `live` (the others: anything).
    fn flow(&self, d: T, live: T::Mask) -> T;
    /// The curve's slope at `ε_p + d`, where σ_y is `sy`, as a fraction
    /// `(hn, hd)` (one division fewer in the Newton step).
    fn slope(&self, d: T, sy: T) -> (T, T);
    /// σ_y after a last Newton step, at `ε_p + d_last` with `d_last = d + u
    /// hd`, from `sy` at `ε_p + d`, in the lanes of `live`.
    fn step(&self, sy: T, u: T, d_last: T, live: T::Mask) -> T;
}

/// Swift's curve for one point or four lanes, from the point's cached flow
/// stress: `σ_y(ε_p + d) = σ_y(ε_p) (1 + x)^n`, `x = d / (ε0 + ε_p)`, by
/// the binomial series to x⁸ (error < |x|⁹ < 6e-16 for |x| < 0.02,
/// `series8`), else `powf` (out of line in lanes).
pub(super) struct Swift<'a, T> {
    /// Binomial coefficients of `(1 + x)^n` ([`swift_binomial`]).
    pub(super) c: &'a [f64; 9],
    /// K (MPa).
    pub(super) k: f64,
    /// n (-).
    pub(super) n: f64,
    /// Flow stress at the start of the step.
    pub(super) sy0: T,
    /// `ε0 + ε_p` and its inverse.
    pub(super) e: T,
    pub(super) inv_e: T,
}

impl<T: Real> Curve<T> for Swift<'_, T> {
    #[inline(always)]
    fn flow(&self, d: T, live: T::Mask) -> T {
        let x = d * self.inv_e;
        let sy = self.sy0 * series8(self.c, x);
        let far = T::mask_and_not(live, T::lt(T::abs(x), T::splat(0.02)));
        if !T::any(far) {
            return sy;
        }
        let (k, n) = (self.k, self.n);
        T::select(
            far,
            self.e.map_where(d, far, |e, d| k * (e + d).powf(n)),
            sy,
        )
    }

    #[inline(always)]
    fn slope(&self, d: T, sy: T) -> (T, T) {
        (sy * self.n, self.e + d)
    }

    /// `sy (1 + u)^n` by the binomial series to u⁴ (error < |C(n, 5)| |u|⁵
    /// < 4e-17 for |u| < [`STEP_SERIES`]; a last step's |u| is at most ~1e-6
    /// in the tests), [`flow`](Curve::flow) at `d_last` beyond it.
    #[inline(always)]
    fn step(&self, sy: T, u: T, d_last: T, live: T::Mask) -> T {
        let y = sy * series4(self.c, u);
        let far = T::mask_and_not(live, T::lt(T::abs(u), T::splat(STEP_SERIES)));
        if !T::any(far) {
            return y;
        }
        T::select(far, self.flow(d_last, far), y)
    }
}
