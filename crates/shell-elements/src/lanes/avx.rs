//! `F4x`: four `f64` lanes in one AVX register, for the kernels that
//! [`run_fastest`](super::run_fastest) compiles with the `avx2` and `fma`
//! target features. Every operation is one AVX instruction with the IEEE
//! result of [`F4`](super::F4)'s lane-by-lane code, so the same bits.
//!
//! # Why the intrinsics are sound
//! An AVX instruction may run only on a processor that has AVX2 and FMA.
//! The types guarantee it: `F4x` and `M4x` are private to this module, so
//! code elsewhere cannot name them, and the only place that instantiates a
//! kernel with them is [`run`], which takes an [`Avx2Fma`] — a proof that
//! only [`Avx2Fma::detect`] makes, after the run-time check. Any `F4x`
//! value therefore exists in a process whose processor passed that check,
//! which is the one requirement of every `unsafe` block below.

use super::{Avx2Fma, KernelLanes, LaneKernel, Lanes4, Real};
use crate::block_nodes::{BlockNodes, Lanes3};
use std::arch::x86_64::*;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

/// Four `f64` lanes in one AVX register (see the module documentation).
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
struct F4x(__m256d);

/// A lane mask of [`F4x`]: all bits set (true) or clear (false) per lane.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
struct M4x(__m256d);

/// `k` in [`F4x`] lanes, compiled with AVX2 and FMA.
#[inline(always)]
pub(super) fn run<K: LaneKernel>(avx: Avx2Fma, k: K) -> K::Output {
    // SAFETY: `avx` proves the processor has AVX2 and FMA.
    unsafe { run_avx2(avx, k) }
}

/// [`run`]'s body, compiled with the AVX2 and FMA target features.
#[target_feature(enable = "avx2,fma")]
unsafe fn run_avx2<K: LaneKernel>(_avx: Avx2Fma, k: K) -> K::Output {
    k.run::<F4x>()
}

impl F4x {
    /// Every lane `x` (a data move: no AVX instruction needed).
    #[inline(always)]
    fn splat_data(x: f64) -> Self {
        // SAFETY: see the module documentation.
        F4x(unsafe { _mm256_set1_pd(x) })
    }
}

macro_rules! avx_op {
    ($tr:ident, $f:ident, $tra:ident, $fa:ident, $intr:ident) => {
        impl $tr for F4x {
            type Output = F4x;
            #[inline(always)]
            fn $f(self, o: F4x) -> F4x {
                // SAFETY: see the module documentation.
                F4x(unsafe { $intr(self.0, o.0) })
            }
        }
        impl $tr<f64> for F4x {
            type Output = F4x;
            #[inline(always)]
            fn $f(self, o: f64) -> F4x {
                $tr::$f(self, F4x::splat_data(o))
            }
        }
        impl $tr<F4x> for f64 {
            type Output = F4x;
            #[inline(always)]
            fn $f(self, o: F4x) -> F4x {
                $tr::$f(F4x::splat_data(self), o)
            }
        }
        impl $tra for F4x {
            #[inline(always)]
            fn $fa(&mut self, o: F4x) {
                *self = $tr::$f(*self, o);
            }
        }
    };
}
avx_op!(Add, add, AddAssign, add_assign, _mm256_add_pd);
avx_op!(Sub, sub, SubAssign, sub_assign, _mm256_sub_pd);
avx_op!(Mul, mul, MulAssign, mul_assign, _mm256_mul_pd);
avx_op!(Div, div, DivAssign, div_assign, _mm256_div_pd);

impl Neg for F4x {
    type Output = F4x;
    #[inline(always)]
    fn neg(self) -> F4x {
        // SAFETY: see the module documentation.
        F4x(unsafe { _mm256_xor_pd(self.0, F4x::splat_data(-0.0).0) })
    }
}

impl Default for F4x {
    #[inline(always)]
    fn default() -> Self {
        // SAFETY: see the module documentation.
        F4x(unsafe { _mm256_setzero_pd() })
    }
}

impl Real for F4x {
    type Mask = M4x;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        F4x::splat_data(x)
    }
    #[inline(always)]
    fn madd(self, a: Self, b: Self) -> Self {
        // SAFETY: see the module documentation.
        F4x(unsafe { _mm256_fmadd_pd(self.0, a.0, b.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: see the module documentation.
        F4x(unsafe { _mm256_sqrt_pd(self.0) })
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        // f64::max as compiled for x86: `max_pd(o, self)` (which gives
        // its second operand, `self`, when `o` is NaN or the two are
        // equal, as ±0), and `o` where `self` is NaN.
        // SAFETY: see the module documentation.
        unsafe {
            let m = _mm256_max_pd(o.0, self.0);
            let self_nan = _mm256_cmp_pd::<_CMP_UNORD_Q>(self.0, self.0);
            F4x(_mm256_blendv_pd(m, o.0, self_nan))
        }
    }
    #[inline(always)]
    fn gt(self, o: Self) -> M4x {
        // SAFETY: see the module documentation.
        M4x(unsafe { _mm256_cmp_pd::<_CMP_GT_OQ>(self.0, o.0) })
    }
    #[inline(always)]
    fn is_finite(self) -> M4x {
        // x − x is 0 exactly for finite x and NaN otherwise.
        // SAFETY: see the module documentation.
        unsafe {
            let d = _mm256_sub_pd(self.0, self.0);
            M4x(_mm256_cmp_pd::<_CMP_EQ_OQ>(d, F4x::default().0))
        }
    }
    #[inline(always)]
    fn select(m: M4x, a: Self, b: Self) -> Self {
        // SAFETY: see the module documentation.
        F4x(unsafe { _mm256_blendv_pd(b.0, a.0, m.0) })
    }
    #[inline(always)]
    fn any(m: M4x) -> bool {
        mask_bits(m) != 0
    }
    #[inline(always)]
    fn le(self, o: Self) -> M4x {
        // SAFETY: see the module documentation.
        M4x(unsafe { _mm256_cmp_pd::<_CMP_LE_OQ>(self.0, o.0) })
    }
    #[inline(always)]
    fn lt(self, o: Self) -> M4x {
        // SAFETY: see the module documentation.
        M4x(unsafe { _mm256_cmp_pd::<_CMP_LT_OQ>(self.0, o.0) })
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // SAFETY: see the module documentation.
        F4x(unsafe { _mm256_andnot_pd(F4x::splat_data(-0.0).0, self.0) })
    }
    #[inline(always)]
    fn mask_and(a: M4x, b: M4x) -> M4x {
        // SAFETY: see the module documentation.
        M4x(unsafe { _mm256_and_pd(a.0, b.0) })
    }
    #[inline(always)]
    fn mask_and_not(a: M4x, b: M4x) -> M4x {
        // SAFETY: see the module documentation.
        M4x(unsafe { _mm256_andnot_pd(b.0, a.0) })
    }
    #[inline(always)]
    fn mask_or(a: M4x, b: M4x) -> M4x {
        // SAFETY: see the module documentation.
        M4x(unsafe { _mm256_or_pd(a.0, b.0) })
    }
    #[inline(always)]
    fn mask_not(a: M4x) -> M4x {
        // SAFETY: see the module documentation.
        M4x(unsafe { _mm256_xor_pd(a.0, _mm256_castsi256_pd(_mm256_set1_epi64x(-1))) })
    }
    #[inline(always)]
    fn map_where(self, o: Self, m: M4x, f: impl Fn(f64, f64) -> f64) -> Self {
        let lanes = [
            F4x::mask_lane(m, 0),
            F4x::mask_lane(m, 1),
            F4x::mask_lane(m, 2),
            F4x::mask_lane(m, 3),
        ];
        F4x::from_array(super::map_where4(self.to_array(), o.to_array(), lanes, f))
    }
}

/// The sign bits of `m`'s lanes, lane `l` in bit `l`.
#[inline(always)]
fn mask_bits(m: M4x) -> i32 {
    // SAFETY: see the module documentation.
    unsafe { _mm256_movemask_pd(m.0) }
}

impl KernelLanes for F4x {
    #[inline(always)]
    fn gather(nodes: &BlockNodes<'_>) -> Lanes3 {
        // An `F4x` exists only after the check (see the module
        // documentation): the proof can be restated here.
        nodes.gather_avx2(Avx2Fma(()))
    }
}

impl Lanes4 for F4x {
    #[inline(always)]
    fn from_array(a: [f64; 4]) -> Self {
        // SAFETY: see the module documentation; the load reads `a`.
        F4x(unsafe { _mm256_loadu_pd(a.as_ptr()) })
    }
    #[inline(always)]
    fn to_array(self) -> [f64; 4] {
        let mut a = [0.0; 4];
        // SAFETY: see the module documentation; the store writes `a`.
        unsafe { _mm256_storeu_pd(a.as_mut_ptr(), self.0) };
        a
    }
    #[inline(always)]
    fn mask_all(a: M4x) -> bool {
        mask_bits(a) == 0b1111
    }
    #[inline(always)]
    fn mask_lane(a: M4x, l: usize) -> bool {
        (mask_bits(a) >> l) & 1 != 0
    }
}

#[cfg(test)]
mod tests {
    use super::super::{F4, KernelLanes, LaneKernel, Lanes4, Real};
    use super::Avx2Fma;

    /// The operations of `F4x`, checked against `F4`'s inside one kernel
    /// run with the AVX lanes (the only way to make `F4x` values).
    struct Check;

    impl LaneKernel for Check {
        type Output = ();
        #[inline(always)]
        fn run<L: KernelLanes>(self) {
            check_ops::<L>();
        }
    }

    /// `run` hands the kernel the AVX lanes when the processor has them.
    #[test]
    fn run_fastest_runs_the_avx_lanes_where_the_processor_has_them() {
        struct Name;
        impl LaneKernel for Name {
            type Output = &'static str;
            fn run<L: KernelLanes>(self) -> &'static str {
                std::any::type_name::<L>()
            }
        }
        let name = super::super::run_fastest(Name);
        assert_eq!(Avx2Fma::detect().is_some(), name.ends_with("F4x"), "{name}");
    }

    /// The AVX register type gives `F4`'s bits for every operation,
    /// including NaN, infinities and signed zeros in `max` (but for the
    /// unspecified max of +0 and −0), comparisons, `is_finite`, `select`,
    /// `abs`, negation and the fused `madd`; and its masks read as `F4`'s.
    /// Skipped (passes) without AVX2 and FMA. Tolerance: none.
    #[test]
    fn avx_lanes_match_portable_lanes_bit_for_bit() {
        if let Some(avx) = Avx2Fma::detect() {
            super::run(avx, Check);
        }
    }

    #[inline(always)]
    fn check_ops<L: Lanes4>() {
        let vals = [
            1.5,
            -0.0,
            0.0,
            f64::NAN,
            3e-300,
            -2.25,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        let bits = |x: [f64; 4]| x.map(f64::to_bits);
        for i in 0..vals.len() {
            for j in 0..vals.len() {
                let a4 = [vals[i], vals[j], vals[(i + j) % 8], vals[(i + 3) % 8]];
                let b4 = [vals[j], vals[(i + 5) % 8], vals[i], vals[(j + 1) % 8]];
                let c4 = [vals[(j + 2) % 8], vals[i], vals[j], vals[(i + j + 1) % 8]];
                let (a, b, c) = (F4(a4), F4(b4), F4(c4));
                let (x, y, z) = (L::from_array(a4), L::from_array(b4), L::from_array(c4));
                assert_eq!(bits((x + y).to_array()), bits((a + b).0));
                assert_eq!(bits((x - y * 2.0).to_array()), bits((a - b * 2.0).0));
                assert_eq!(bits((x / y).to_array()), bits((a / b).0));
                assert_eq!(bits((-x).to_array()), bits((-a).0));
                assert_eq!(bits(x.madd(y, z).to_array()), bits(a.madd(b, c).0));
                assert_eq!(bits(x.sqrt().to_array()), bits(a.sqrt().0));
                assert_eq!(bits(L::splat(a4[0]).to_array()), bits(F4::splat(a4[0]).0));
                assert_eq!(bits(L::default().to_array()), bits(F4::default().0));
                // (`f64::max` of +0 and −0 may give either, and does differ
                // between compilations; the kernel's `max` reads sums of
                // squares, never −0.)
                let (mx, ma) = (Real::max(x, y).to_array(), Real::max(a, b).0);
                for l in 0..4 {
                    if !(a4[l] == 0.0 && b4[l] == 0.0) {
                        assert_eq!(mx[l].to_bits(), ma[l].to_bits());
                    }
                }
                assert_eq!(bits(Real::abs(x).to_array()), bits(F4::abs(a).0));
                let masks = [
                    (Real::gt(x, y), Real::gt(a, b)),
                    (Real::le(x, y), F4::le(a, b)),
                    (Real::lt(x, y), F4::lt(a, b)),
                    (Real::is_finite(x), Real::is_finite(a)),
                ];
                for (mx, ma) in masks {
                    for l in 0..4 {
                        assert_eq!(L::mask_lane(mx, l), ma.lane(l));
                    }
                    assert_eq!(L::any(mx), F4::any(ma));
                    assert_eq!(L::mask_all(mx), ma.all());
                    let sel = L::select(mx, x, y).to_array();
                    assert_eq!(bits(sel), bits(F4::select(ma, a, b).0));
                    let not = L::mask_not(mx);
                    for l in 0..4 {
                        assert_eq!(L::mask_lane(not, l), !ma.lane(l));
                    }
                    let both = L::mask_and(mx, not);
                    assert!(!L::any(both));
                    let rest = L::mask_and_not(mx, not);
                    assert_eq!(L::mask_all(rest), ma.all());
                }
            }
        }
        // It ran on F4x (a kernel run by `run` gets the AVX lanes).
        assert!(std::any::type_name::<L>().ends_with("F4x"));
    }
}
