//! `Real`: the number type the element kernels are written in — `f64` for one element, [`F4`] for four elements in the lanes of one SIMD register.
//!
//! A kernel written once over `T: Real` runs on one element (`T = f64`) or
//! on four at a time (`T = F4`). `F4` does every operation lane by lane in
//! IEEE arithmetic, in the order the kernel writes (no reassociation), and
//! branches become masks ([`Real::select`]). The one difference from the
//! one-element run is [`Real::madd`]: `F4` fuses its product and sum (one
//! rounding, `f64::mul_add`), `f64` rounds twice; so lane `l` of a
//! four-element run is the one-element run of element `l` to rounding
//! (`tests/lanes_match_scalar.rs`), and the same bits on every processor (a
//! fused multiply–add is exactly specified). Compiled inside a function with
//! the `avx2` and `fma` target features the lane loops become 256-bit
//! instructions and `madd` one `vfmadd`; elsewhere (a processor without FMA)
//! `mul_add` is the C library's exact `fma`, slower but the same bits.
//!
//! A four-element kernel is written once as a `LaneKernel`, generic over
//! [`Lanes4`], and `run_fastest` runs it: on a processor with AVX2 and FMA
//! in a private AVX register type (`avx.rs`, every operation one AVX
//! instruction with `F4`'s bits), compiled with those target features;
//! elsewhere in `F4`. The AVX type cannot be named outside `avx.rs`, and the
//! only way to run a kernel on it takes an `Avx2Fma`, the proof of the
//! run-time check: the types, not a comment, keep its instructions off a
//! processor that lacks them.

use crate::block_nodes::{BlockNodes, Lanes3};
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

/// `[e(0), e(1), e(2), e(3)]` for a lane expression `e(l)`, written out so
/// that it inlines whatever the size of the kernel around it.
macro_rules! lanes {
    (|$l:ident| $e:expr) => {
        [
            {
                let $l = 0;
                $e
            },
            {
                let $l = 1;
                $e
            },
            {
                let $l = 2;
                $e
            },
            {
                let $l = 3;
                $e
            },
        ]
    };
}

/// Number type of the element kernels: `f64` or [`F4`].
pub trait Real:
    Copy
    + Default
    + std::fmt::Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
    + AddAssign
    + SubAssign
    + Send
    + Sync
    + 'static
{
    /// Comparison result: `bool` for `f64`, [`M4`] for `F4`.
    type Mask: Copy;
    /// Every lane equal to `x`.
    fn splat(x: f64) -> Self;
    /// `self · a + b`: rounded once in [`F4`]'s lanes (fused multiply–add),
    /// twice for `f64` (`self * a + b`, so that one-element kernels keep
    /// their bits where no FMA unit is compiled in).
    fn madd(self, a: Self, b: Self) -> Self;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Maximum with `f64::max`'s NaN rule (a NaN operand loses).
    fn max(self, o: Self) -> Self;
    /// `self > o`, lane by lane (false where either is NaN).
    fn gt(self, o: Self) -> Self::Mask;
    /// Finite (neither NaN nor infinite), lane by lane.
    fn is_finite(self) -> Self::Mask;
    /// `a` where `m`, else `b`.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// Whether any lane of `m` is set.
    fn any(m: Self::Mask) -> bool;
    /// `self <= o`, lane by lane (false where either is NaN).
    fn le(self, o: Self) -> Self::Mask;
    /// `self < o`, lane by lane (false where either is NaN).
    fn lt(self, o: Self) -> Self::Mask;
    /// Absolute value.
    fn abs(self) -> Self;
    /// Lanes set in both.
    fn mask_and(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    /// Lanes set in `a` and clear in `b`.
    fn mask_and_not(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    /// Lanes set in either.
    fn mask_or(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    /// Lanes clear in `a`.
    fn mask_not(a: Self::Mask) -> Self::Mask;
    /// `f(self, o)` lane by lane in the lanes of `m`, `self` in the others:
    /// for a rare scalar function (a `powf`) beside lane arithmetic; in
    /// lanes it runs out of line, so that the code around it stays in
    /// registers.
    fn map_where(self, o: Self, m: Self::Mask, f: impl Fn(f64, f64) -> f64) -> Self;
}

impl Real for f64 {
    type Mask = bool;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn madd(self, a: Self, b: Self) -> Self {
        self * a + b
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        f64::max(self, o)
    }
    #[inline(always)]
    fn gt(self, o: Self) -> bool {
        self > o
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        f64::is_finite(self)
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
        self <= o
    }
    #[inline(always)]
    fn lt(self, o: Self) -> bool {
        self < o
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f64::abs(self)
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
    #[inline(always)]
    fn map_where(self, o: Self, m: bool, f: impl Fn(f64, f64) -> f64) -> Self {
        if m { f(self, o) } else { self }
    }
}

/// [`Real::map_where`] of four lanes, out of line.
#[cold]
#[inline(never)]
fn map_where4(a: [f64; 4], b: [f64; 4], m: [bool; 4], f: impl Fn(f64, f64) -> f64) -> [f64; 4] {
    std::array::from_fn(|l| if m[l] { f(a[l], b[l]) } else { a[l] })
}

/// Four `f64` lanes (one per element of a block of four).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(32))]
pub struct F4(pub [f64; 4]);

/// A lane mask of [`F4`]: all bits set (true) or clear (false) per lane.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(C, align(32))]
pub struct M4(pub [u64; 4]);

impl M4 {
    /// Mask from one `bool` per lane.
    #[inline(always)]
    pub fn from_bools(b: [bool; 4]) -> Self {
        M4(lanes!(|l| (b[l] as u64).wrapping_neg()))
    }
    /// Lane `l` as a `bool`.
    #[inline(always)]
    pub fn lane(self, l: usize) -> bool {
        self.0[l] != 0
    }
    /// Lanes set in both.
    #[inline(always)]
    pub fn and(self, o: Self) -> Self {
        M4(lanes!(|l| self.0[l] & o.0[l]))
    }
    /// Lanes set in either.
    #[inline(always)]
    pub fn or(self, o: Self) -> Self {
        M4(lanes!(|l| self.0[l] | o.0[l]))
    }
    /// Lanes set in `self` and clear in `o`.
    #[inline(always)]
    pub fn and_not(self, o: Self) -> Self {
        M4(lanes!(|l| self.0[l] & !o.0[l]))
    }
    /// Whether every lane is set.
    #[inline(always)]
    pub fn all(self) -> bool {
        self.0.iter().all(|&x| x != 0)
    }
}

impl F4 {
    /// Lane `l` of each of four values gathered into one.
    #[inline(always)]
    pub fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        F4([f(0), f(1), f(2), f(3)])
    }
    /// `self <= o`, lane by lane.
    #[inline(always)]
    pub fn le(self, o: Self) -> M4 {
        M4(lanes!(|l| ((self.0[l] <= o.0[l]) as u64).wrapping_neg()))
    }
    /// `self < o`, lane by lane.
    #[inline(always)]
    pub fn lt(self, o: Self) -> M4 {
        M4(lanes!(|l| ((self.0[l] < o.0[l]) as u64).wrapping_neg()))
    }
    /// Absolute value.
    #[inline(always)]
    pub fn abs(self) -> Self {
        F4(lanes!(|l| self.0[l].abs()))
    }
}

macro_rules! lane_op {
    ($tr:ident, $f:ident, $tra:ident, $fa:ident) => {
        impl $tr for F4 {
            type Output = F4;
            #[inline(always)]
            fn $f(self, o: F4) -> F4 {
                F4(lanes!(|l| self.0[l].$f(o.0[l])))
            }
        }
        impl $tr<f64> for F4 {
            type Output = F4;
            #[inline(always)]
            fn $f(self, o: f64) -> F4 {
                F4(lanes!(|l| self.0[l].$f(o)))
            }
        }
        impl $tr<F4> for f64 {
            type Output = F4;
            #[inline(always)]
            fn $f(self, o: F4) -> F4 {
                F4(lanes!(|l| self.$f(o.0[l])))
            }
        }
        impl $tra for F4 {
            #[inline(always)]
            fn $fa(&mut self, o: F4) {
                *self = $tr::$f(*self, o);
            }
        }
    };
}
use std::ops::{DivAssign, MulAssign};
lane_op!(Add, add, AddAssign, add_assign);
lane_op!(Sub, sub, SubAssign, sub_assign);
lane_op!(Mul, mul, MulAssign, mul_assign);
lane_op!(Div, div, DivAssign, div_assign);

impl Neg for F4 {
    type Output = F4;
    #[inline(always)]
    fn neg(self) -> F4 {
        F4(lanes!(|l| -self.0[l]))
    }
}

impl Real for F4 {
    type Mask = M4;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        F4([x; 4])
    }
    #[inline(always)]
    fn madd(self, a: Self, b: Self) -> Self {
        F4(lanes!(|l| self.0[l].mul_add(a.0[l], b.0[l])))
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        F4(lanes!(|l| self.0[l].sqrt()))
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        F4(lanes!(|l| self.0[l].max(o.0[l])))
    }
    #[inline(always)]
    fn gt(self, o: Self) -> M4 {
        M4(lanes!(|l| ((self.0[l] > o.0[l]) as u64).wrapping_neg()))
    }
    #[inline(always)]
    fn is_finite(self) -> M4 {
        M4(lanes!(|l| (self.0[l].is_finite() as u64).wrapping_neg()))
    }
    #[inline(always)]
    fn select(m: M4, a: Self, b: Self) -> Self {
        F4(lanes!(|l| f64::from_bits(
            (a.0[l].to_bits() & m.0[l]) | (b.0[l].to_bits() & !m.0[l])
        )))
    }
    #[inline(always)]
    fn any(m: M4) -> bool {
        m.0.iter().any(|&x| x != 0)
    }
    #[inline(always)]
    fn le(self, o: Self) -> M4 {
        F4::le(self, o)
    }
    #[inline(always)]
    fn lt(self, o: Self) -> M4 {
        F4::lt(self, o)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        F4::abs(self)
    }
    #[inline(always)]
    fn mask_and(a: M4, b: M4) -> M4 {
        a.and(b)
    }
    #[inline(always)]
    fn mask_and_not(a: M4, b: M4) -> M4 {
        a.and_not(b)
    }
    #[inline(always)]
    fn mask_or(a: M4, b: M4) -> M4 {
        a.or(b)
    }
    #[inline(always)]
    fn mask_not(a: M4) -> M4 {
        M4::from_bools([true; 4]).and_not(a)
    }
    #[inline(always)]
    fn map_where(self, o: Self, m: M4, f: impl Fn(f64, f64) -> f64) -> Self {
        let lanes = [m.lane(0), m.lane(1), m.lane(2), m.lane(3)];
        F4(map_where4(self.0, o.0, lanes, f))
    }
}

/// A four-lane number type of the element kernels: [`F4`] (portable) or the
/// AVX2 register type the AVX2 kernels run on (crate-private), the same bits
/// lane by lane.
pub trait Lanes4: Real {
    /// The four lanes of `a`.
    fn from_array(a: [f64; 4]) -> Self;
    /// The four lanes.
    fn to_array(self) -> [f64; 4];
    /// Whether every lane is set.
    fn mask_all(a: Self::Mask) -> bool;
    /// Lane `l` as a `bool`.
    fn mask_lane(a: Self::Mask, l: usize) -> bool;
}

impl Lanes4 for F4 {
    #[inline(always)]
    fn from_array(a: [f64; 4]) -> Self {
        F4(a)
    }
    #[inline(always)]
    fn to_array(self) -> [f64; 4] {
        self.0
    }
    #[inline(always)]
    fn mask_all(a: M4) -> bool {
        a.all()
    }
    #[inline(always)]
    fn mask_lane(a: M4, l: usize) -> bool {
        a.lane(l)
    }
}

/// The first and the second values of four pairs, each in lanes (pair `l`
/// in lane `l`): one 128-bit load per pair and two unpacks per two lanes, in
/// registers.
#[inline(always)]
pub fn unzip4(p: [&[f64; 2]; 4]) -> (F4, F4) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{__m128d, _mm_unpackhi_pd, _mm_unpacklo_pd};
        let v: [__m128d; 4] = p.map(|q| bytemuck::cast(*q));
        // SAFETY: SSE2 is part of every x86_64 processor (this is compiled
        // for x86_64 only).
        let (a, b): ([__m128d; 2], [__m128d; 2]) = unsafe {
            (
                [_mm_unpacklo_pd(v[0], v[1]), _mm_unpacklo_pd(v[2], v[3])],
                [_mm_unpackhi_pd(v[0], v[1]), _mm_unpackhi_pd(v[2], v[3])],
            )
        };
        (F4(bytemuck::cast(a)), F4(bytemuck::cast(b)))
    }
    #[cfg(not(target_arch = "x86_64"))]
    (F4(lanes!(|l| p[l][0])), F4(lanes!(|l| p[l][1])))
}

/// Four pairs out of two lanes' values (the inverse of [`unzip4`]), stored
/// with one 128-bit store each.
#[inline(always)]
pub fn zip4(a: F4, b: F4, p: [&mut [f64; 2]; 4]) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{__m128d, _mm_unpackhi_pd, _mm_unpacklo_pd};
        let [a01, a23]: [__m128d; 2] = bytemuck::cast(a.0);
        let [b01, b23]: [__m128d; 2] = bytemuck::cast(b.0);
        // SAFETY: SSE2 is part of every x86_64 processor (this is compiled
        // for x86_64 only).
        let q = unsafe {
            [
                _mm_unpacklo_pd(a01, b01),
                _mm_unpackhi_pd(a01, b01),
                _mm_unpacklo_pd(a23, b23),
                _mm_unpackhi_pd(a23, b23),
            ]
        };
        for (p, q) in p.into_iter().zip(q) {
            *p = bytemuck::cast(q);
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    for (l, q) in p.into_iter().enumerate() {
        *q = [a.0[l], b.0[l]];
    }
}

/// Proof that this processor has AVX2 and FMA: made only by
/// [`Avx2Fma::detect`] (its field is private to this module), so a value of
/// it is the run-time check having passed.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx2Fma(());

impl Avx2Fma {
    /// The proof, if this processor has AVX2 and FMA (checked once, cached
    /// by the standard library).
    #[inline(always)]
    pub(crate) fn detect() -> Option<Self> {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        {
            return Some(Avx2Fma(()));
        }
        None
    }
}

/// A four-lane type a block kernel runs on: [`F4`] or the AVX register
/// type, each with its way of gathering a block's nodes.
pub(crate) trait KernelLanes: Lanes4 {
    /// The block's positions, velocities and angular velocities, node `i`,
    /// component `c`, element `l` in lane `l` (to be loaded into `Self`).
    fn gather(nodes: &BlockNodes<'_>) -> Lanes3;
}

impl KernelLanes for F4 {
    #[inline(always)]
    fn gather(nodes: &BlockNodes<'_>) -> Lanes3 {
        nodes.gather()
    }
}

/// A computation written once over a four-lane type, run by
/// [`run_fastest`] on the fastest lanes this processor has.
pub(crate) trait LaneKernel {
    /// What the computation gives.
    type Output;
    /// The computation in lanes of `L`. Written `#[inline(always)]`, so that
    /// it compiles inside the caller's target features.
    fn run<L: KernelLanes>(self) -> Self::Output;
}

/// `k` in AVX registers (compiled with AVX2 and FMA) where the processor has
/// them, else in [`F4`] (baseline SSE2, where `madd` is the C library's
/// exact `fma`): the same bits either way.
#[inline(always)]
pub(crate) fn run_fastest<K: LaneKernel>(k: K) -> K::Output {
    #[cfg(target_arch = "x86_64")]
    if let Some(avx) = Avx2Fma::detect() {
        return avx::run(avx, k);
    }
    k.run::<F4>()
}

#[cfg(target_arch = "x86_64")]
mod avx;

#[cfg(test)]
mod tests {
    use super::*;

    /// Lane arithmetic is the scalar arithmetic, bit for bit, including NaN
    /// and signed-zero cases of `max` and `select`.
    #[test]
    fn lanes_match_scalar_bit_for_bit() {
        let a = F4([1.5, -0.0, f64::NAN, 3e-300]);
        let b = F4([2.0f64.sqrt(), 0.0, 1.0, f64::INFINITY]);
        for l in 0..4 {
            let (x, y) = (a.0[l], b.0[l]);
            assert_eq!((a + b).0[l].to_bits(), (x + y).to_bits());
            assert_eq!((a * b - a / b).0[l].to_bits(), (x * y - x / y).to_bits());
            assert_eq!(a.sqrt().0[l].to_bits(), x.sqrt().to_bits());
            assert_eq!(Real::max(a, b).0[l].to_bits(), x.max(y).to_bits());
            assert_eq!(Real::gt(a, b).lane(l), x > y);
            let m = Real::gt(a, b);
            assert_eq!(
                F4::select(m, a, b).0[l].to_bits(),
                f64::select(x > y, x, y).to_bits()
            );
        }
        assert!(F4::any(Real::is_finite(a)) && !Real::is_finite(a).all());
    }

    /// `unzip4` and `zip4` move each pair's values to their lanes and back.
    #[test]
    fn pairs_unzip_to_lanes_and_zip_back() {
        let mut p = [[1.0, -1.0], [2.0, -2.0], [3.0, -3.0], [4.0, -4.0]];
        let [p0, p1, p2, p3] = &p;
        let (a, b) = unzip4([p0, p1, p2, p3]);
        assert_eq!(
            (a, b),
            (F4([1.0, 2.0, 3.0, 4.0]), F4([-1.0, -2.0, -3.0, -4.0]))
        );
        let [q0, q1, q2, q3] = &mut p;
        zip4(b, a, [q0, q1, q2, q3]);
        assert_eq!(p, [[-1.0, 1.0], [-2.0, 2.0], [-3.0, 3.0], [-4.0, 4.0]]);
    }

    /// `madd` rounds once in lanes (the exact `f64::mul_add`) and twice for
    /// `f64`: with `x = 1 + 2⁻²⁷`, `x·x − 1 = 2⁻²⁶ + 2⁻⁵⁴` exactly, which the
    /// fused form keeps and the two-rounding form loses. Tolerance: none.
    #[test]
    fn madd_is_fused_in_lanes_and_not_in_f64() {
        let x = 1.0 + 2f64.powi(-27);
        let fused = F4::splat(x).madd(F4::splat(x), F4::splat(-1.0));
        let plain = Real::madd(x, x, -1.0);
        for l in 0..4 {
            assert_eq!(fused.0[l], 2f64.powi(-26) + 2f64.powi(-54));
        }
        assert_eq!(plain, 2f64.powi(-26));
    }
}
