//! `Dual`: a forward-mode dual number carrying the derivatives with respect
//! to one element's 24 DOFs, so that the element kernel written over
//! [`Real`] gives its exact tangent.
//!
//! `a = re + Σ_j d_j ε_j` with `ε_i ε_j = 0`: sums, products, quotients and
//! square roots propagate the first derivatives exactly (the chain rule);
//! comparisons and selections act on the value, so a kernel branches as
//! its `f64` version does. The value of every operation is the `f64`
//! operation on the values (same rounding: [`Real::madd`] is `a · b + c`
//! unfused for both), so the dual kernel's values equal the `f64` kernel's
//! bit for bit.

use crate::lanes::Real;
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

/// Number of derivatives a [`Dual`] carries: 4 nodes × 6 DOFs.
pub(crate) const N_DERIV: usize = 24;

/// A value and its derivatives with respect to an element's 24 DOFs.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Dual {
    /// The value.
    pub re: f64,
    /// `∂/∂q_j` for the element's DOFs `q_j`, `j = 6 · node + dof`.
    pub d: [f64; N_DERIV],
}

impl Dual {
    /// A constant (no derivative).
    #[inline(always)]
    pub fn constant(re: f64) -> Self {
        Self {
            re,
            d: [0.0; N_DERIV],
        }
    }

    /// The independent variable `q_j` at value `re`.
    #[inline(always)]
    pub fn variable(re: f64, j: usize) -> Self {
        let mut a = Self::constant(re);
        a.d[j] = 1.0;
        a
    }

    /// `f(re)` with derivative `f'(re) = slope`.
    #[inline(always)]
    fn chain(self, value: f64, slope: f64) -> Self {
        let mut d = self.d;
        d.iter_mut().for_each(|x| *x *= slope);
        Self { re: value, d }
    }
}

impl Add for Dual {
    type Output = Self;
    #[inline(always)]
    fn add(mut self, o: Self) -> Self {
        self.re += o.re;
        self.d.iter_mut().zip(&o.d).for_each(|(a, b)| *a += b);
        self
    }
}

impl Sub for Dual {
    type Output = Self;
    #[inline(always)]
    fn sub(mut self, o: Self) -> Self {
        self.re -= o.re;
        self.d.iter_mut().zip(&o.d).for_each(|(a, b)| *a -= b);
        self
    }
}

impl Mul for Dual {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        let mut d = [0.0; N_DERIV];
        for ((x, a), b) in d.iter_mut().zip(&self.d).zip(&o.d) {
            *x = a * o.re + self.re * b;
        }
        Self {
            re: self.re * o.re,
            d,
        }
    }
}

impl Div for Dual {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        let re = self.re / o.re;
        let inv = 1.0 / o.re;
        let mut d = [0.0; N_DERIV];
        for ((x, a), b) in d.iter_mut().zip(&self.d).zip(&o.d) {
            *x = (a - re * b) * inv;
        }
        Self { re, d }
    }
}

impl Neg for Dual {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.chain(-self.re, -1.0)
    }
}

impl Add<f64> for Dual {
    type Output = Self;
    #[inline(always)]
    fn add(mut self, o: f64) -> Self {
        self.re += o;
        self
    }
}

impl Sub<f64> for Dual {
    type Output = Self;
    #[inline(always)]
    fn sub(mut self, o: f64) -> Self {
        self.re -= o;
        self
    }
}

impl Mul<f64> for Dual {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: f64) -> Self {
        self.chain(self.re * o, o)
    }
}

impl Div<f64> for Dual {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: f64) -> Self {
        self.chain(self.re / o, 1.0 / o)
    }
}

impl AddAssign for Dual {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl SubAssign for Dual {
    #[inline(always)]
    fn sub_assign(&mut self, o: Self) {
        *self = *self - o;
    }
}

impl Real for Dual {
    type Mask = bool;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        Self::constant(x)
    }
    #[inline(always)]
    fn madd(self, a: Self, b: Self) -> Self {
        self * a + b
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        let r = self.re.sqrt();
        self.chain(r, 0.5 / r)
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        // f64::max's rule: a NaN operand loses.
        if self.re.max(o.re) == self.re && !self.re.is_nan() {
            self
        } else {
            o
        }
    }
    #[inline(always)]
    fn gt(self, o: Self) -> bool {
        self.re > o.re
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        self.re.is_finite()
    }
    #[inline(always)]
    fn select(m: bool, a: Self, b: Self) -> Self {
        if m { a } else { b }
    }
    #[inline(always)]
    fn any(m: bool) -> bool {
        m
    }
    #[inline(always)]
    fn le(self, o: Self) -> bool {
        self.re <= o.re
    }
    #[inline(always)]
    fn lt(self, o: Self) -> bool {
        self.re < o.re
    }
    #[inline(always)]
    fn abs(self) -> Self {
        if self.re < 0.0 { -self } else { self }
    }
    #[inline(always)]
    fn mask_and(a: bool, b: bool) -> bool {
        a && b
    }
    #[inline(always)]
    fn mask_and_not(a: bool, b: bool) -> bool {
        a && !b
    }
    #[inline(always)]
    fn mask_or(a: bool, b: bool) -> bool {
        a || b
    }
    #[inline(always)]
    fn mask_not(a: bool) -> bool {
        !a
    }
    /// The value `f(re, o.re)` where `m`; its derivatives by central
    /// differences of `f` in both arguments (relative step `1e-7`). The
    /// element kinematics never call it (only materials' lane kernels do).
    fn map_where(self, o: Self, m: bool, f: impl Fn(f64, f64) -> f64) -> Self {
        if !m {
            return self;
        }
        let (a, b) = (self.re, o.re);
        let (ha, hb) = (1e-7 * a.abs().max(1.0), 1e-7 * b.abs().max(1.0));
        let fa = (f(a + ha, b) - f(a - ha, b)) / (2.0 * ha);
        let fb = (f(a, b + hb) - f(a, b - hb)) / (2.0 * hb);
        let mut d = [0.0; N_DERIV];
        for ((x, da), db) in d.iter_mut().zip(&self.d).zip(&o.d) {
            *x = fa * da + fb * db;
        }
        Self { re: f(a, b), d }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `f(x, y) = sqrt(x² + y) / (x − 3y) · 2 + x`: the dual derivatives
    /// equal the closed-form partials (hand-derived) to 1e-14 relative.
    #[test]
    fn dual_derivatives_match_closed_form() {
        let (x0, y0) = (1.7, 0.4);
        let (x, y) = (Dual::variable(x0, 0), Dual::variable(y0, 5));
        let f = (x * x + y).sqrt() / (x - y * 3.0) * 2.0 + x;
        let r = (x0 * x0 + y0).sqrt();
        let q = x0 - 3.0 * y0;
        let fx = 2.0 * (x0 / r / q - r / (q * q)) + 1.0;
        let fy = 2.0 * (0.5 / r / q + 3.0 * r / (q * q));
        assert!((f.re - (2.0 * r / q + x0)).abs() < 1e-14);
        assert!((f.d[0] - fx).abs() < 1e-14 * fx.abs());
        assert!((f.d[5] - fy).abs() < 1e-14 * fy.abs());
        assert!(
            f.d.iter()
                .enumerate()
                .all(|(j, &v)| j == 0 || j == 5 || v == 0.0)
        );
    }
}
