//! An inlinable sine/cosine pair for the hot paths.
//!
//! `f64::sin_cos` calls the C library twice (or once, as `sincos`): an opaque call the CPU
//! cannot overlap with the neighbouring joints' work. [`sin_cos`] is the classic fdlibm
//! algorithm written inline and lean: Cody–Waite reduction x = n·π/2 + y with π/2 split in two
//! parts (33 + 53 bits, exact products for |n| < 2²⁰), then fdlibm's minimax polynomials for
//! sin and cos on |y| ≤ π/4 sharing y² and y⁴ (Estrin's scheme: a short dependency chain for
//! single calls; about 30 vector operations per 4 angles, a third fewer than before), then the quadrant without
//! a branch. Outside |x| < 2¹⁹·π/2 or for non-finite x it falls back to the standard library.
//!
//! Accuracy, against the C library's `sin`/`cos` (tested in `tests/trig.rs` over millions of
//! arguments with |x| ≤ 1e5, every path): at most **1 ulp** of the result wherever |result| ≥
//! 1e-3, and an absolute error ≤ 2⁻⁵³ (half an ulp of 1) everywhere — near a zero of sin or
//! cos at large |x| the two-part reduction's last bits make that up to a few ulps of the tiny
//! result (9 measured at |x| ≤ 1e5), harmless for rotation entries of magnitude up to 1.

// The constants are fdlibm's, written with the digits it publishes.
#![allow(clippy::excessive_precision)]

use crate::fma::{MulAdd, Plain};
use crate::lanes::{Lanes, MAX_WIDTH};

/// 1.5·2⁵²: adding and subtracting it rounds to the nearest integer.
const SHIFTER: f64 = 6_755_399_441_055_744.0;
/// 2/π.
const INV_PIO2: f64 = std::f64::consts::FRAC_2_PI;
/// First 33 bits of π/2.
const PIO2_1: f64 = 1.570_796_326_734_125_614_17;
/// π/2 − PIO2_1.
const PIO2_1T: f64 = 6.077_100_506_506_192_249_32e-11;

const S1: f64 = -1.666_666_666_666_663_243_48e-1;
const S2: f64 = 8.333_333_333_322_489_461_24e-3;
const S3: f64 = -1.984_126_982_985_794_931_34e-4;
const S4: f64 = 2.755_731_370_707_006_767_89e-6;
const S5: f64 = -2.505_076_025_340_686_341_95e-8;
const S6: f64 = 1.589_690_995_211_550_102_21e-10;

const C1: f64 = 4.166_666_666_666_660_190_37e-2;
const C2: f64 = -1.388_888_888_887_410_957_49e-3;
const C3: f64 = 2.480_158_728_947_672_941_78e-5;
const C4: f64 = -2.755_731_435_139_066_330_35e-7;
const C5: f64 = 2.087_572_321_298_174_827_90e-9;
const C6: f64 = -1.135_964_755_778_819_482_65e-11;

/// (sin y, cos y) for |y| ≤ π/4 + ε, sharing z = y² and z²:
/// sin y = y + y·z·(S1 + z·P(z)) (fdlibm's `__kernel_sin` form) and
/// cos y = 1 + z·(−½ + z·Q(z)), with fdlibm's minimax coefficients, P and Q evaluated in
/// Estrin's scheme (pairs in z, combined in z²) to shorten the dependency chain that a single
/// call waits for. Without `__kernel_cos`'s compensated 1 − z/2: 17 operations for the pair
/// instead of 25, and the error stays ≤ 1 ulp of the result (see the module documentation).
#[inline(always)]
fn kernels<A: MulAdd>(y: f64) -> (f64, f64) {
    let z = y * y;
    let z2 = z * z;
    let v = z * y;
    // P(z) = S2 + S3 z + S4 z² + S5 z³ + S6 z⁴.
    let p = A::madd(z2, A::madd(z2, S6, A::madd(z, S5, S4)), A::madd(z, S3, S2));
    let s = A::madd(v, A::madd(z, p, S1), y);
    // Q(z) = C1 + C2 z + ⋯ + C6 z⁵.
    let q = A::madd(
        z2,
        A::madd(z2, A::madd(z, C6, C5), A::madd(z, C4, C3)),
        A::madd(z, C2, C1),
    );
    let c = A::madd(z, A::madd(z, q, -0.5), 1.0);
    (s, c)
}

/// Above this |x| (≈ 2¹⁹·π/2) the two-part Cody–Waite reduction is no longer exact enough.
const REDUCTION_LIMIT: f64 = 823_549.6;

/// (sin x, cos x) for finite |x| < [`REDUCTION_LIMIT`]: reduction, kernels, quadrant; no branch.
#[inline(always)]
fn sin_cos_reduced<A: MulAdd>(x: f64) -> (f64, f64) {
    // Round to nearest with the 1.5·2⁵² trick (f64::round is a libm call on baseline x86-64);
    // the low mantissa bits of `k` then hold n mod 4.
    let k = A::madd(x, INV_PIO2, SHIFTER);
    let quadrant = k.to_bits();
    let n = k - SHIFTER;
    // n·PIO2_1 is exact (33-bit constant, |n| < 2²⁰), so fused or not gives the same y.
    let y = A::madd(-n, PIO2_1T, A::madd(-n, PIO2_1, x));
    let (s, c) = kernels::<A>(y);
    // Branch-free quadrant: odd quadrants swap sin and cos (a select on bit 0, moved to the sign
    // bit so that it is one blend per vector); signs from bit 1 of n and of n + 1.
    let odd = ((quadrant << 63) as i64) < 0;
    let (s, c) = if odd { (c, s) } else { (s, c) };
    let sin_sign = (quadrant & 2) << 62;
    let cos_sign = (quadrant.wrapping_add(1) & 2) << 62;
    (
        f64::from_bits(s.to_bits() ^ sin_sign),
        f64::from_bits(c.to_bits() ^ cos_sign),
    )
}

/// (sin x, cos x), inlined; see the module documentation for the method and accuracy.
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    sin_cos_with::<Plain>(x)
}

/// [`sin_cos`] with the multiply-add policy `A`: the value of one angle whatever the lanes
/// beside it hold (the lane versions fall back to this, angle by angle).
#[inline(always)]
fn sin_cos_with<A: MulAdd>(x: f64) -> (f64, f64) {
    if !x.is_finite() || x.abs() >= REDUCTION_LIMIT {
        return x.sin_cos();
    }
    sin_cos_reduced::<A>(x)
}

/// Sines and cosines of the angles in the lanes of `l` ([`crate::lanes`]): lane by lane the
/// value [`sin_cos_lanes_with`] gives with `l`'s multiply-add policy, bit for bit (the same
/// operations in the same order; a lane holding a non-finite or huge angle sends them all
/// through the scalar path, which gives each angle the same value).
#[inline(always)]
pub fn sin_cos_in<L: Lanes>(l: L, x: L::V) -> (L::V, L::V) {
    // NaN fails the comparison, so it takes the scalar path too.
    if !l.all_below(l.abs(x), REDUCTION_LIMIT) {
        let mut a = [0.0; MAX_WIDTH];
        l.store(x, &mut a);
        let (mut s, mut c) = ([0.0; MAX_WIDTH], [0.0; MAX_WIDTH]);
        for i in 0..L::WIDTH {
            (s[i], c[i]) = sin_cos_with::<L::Scalar>(a[i]);
        }
        return (l.load(&s), l.load(&c));
    }
    let k = l.madd(x, l.splat(INV_PIO2), l.splat(SHIFTER));
    let n = l.sub(k, l.splat(SHIFTER));
    let minus_n = l.neg(n);
    let y = l.madd(
        minus_n,
        l.splat(PIO2_1T),
        l.madd(minus_n, l.splat(PIO2_1), x),
    );
    // `kernels`, operation for operation.
    let z = l.mul(y, y);
    let z2 = l.mul(z, z);
    let v = l.mul(z, y);
    let p = l.madd(
        z2,
        l.madd(z2, l.splat(S6), l.madd(z, l.splat(S5), l.splat(S4))),
        l.madd(z, l.splat(S3), l.splat(S2)),
    );
    let s = l.madd(v, l.madd(z, p, l.splat(S1)), y);
    let q = l.madd(
        z2,
        l.madd(
            z2,
            l.madd(z, l.splat(C6), l.splat(C5)),
            l.madd(z, l.splat(C4), l.splat(C3)),
        ),
        l.madd(z, l.splat(C2), l.splat(C1)),
    );
    let c = l.madd(z, l.madd(z, q, l.splat(-0.5)), l.splat(1.0));
    // The quadrant as in `sin_cos_reduced`: odd n swaps sin and cos; bit 1 of n (of n + 1)
    // flips the sign of sin (of cos).
    let (s, c) = (l.select_bits(k, 1, c, s), l.select_bits(k, 1, s, c));
    let s = l.select_bits(k, 2, l.neg(s), s);
    let c = l.select_bits(l.bits_add(k, 1), 2, l.neg(c), c);
    (s, c)
}

/// Number of angles [`sin_cos_lanes`] takes at once.
pub const LANES: usize = 8;

/// Sines and cosines of [`LANES`] angles at once: `(s[i], c[i]) = (sin x[i], cos x[i])`.
///
/// The same algorithm as [`sin_cos`], written so the compiler vectorises it across the angles;
/// on x86-64 CPUs with AVX2 and FMA ([`crate::fma::dispatch`]) it runs 4 lanes wide with fused
/// multiply-adds, so results may differ from [`sin_cos`] in the last bit (both stay within
/// 2.3e-16 of the standard library). Blocks holding a non-finite or huge angle take the scalar
/// path.
#[inline]
pub fn sin_cos_lanes(x: &[f64; LANES], s: &mut [f64; LANES], c: &mut [f64; LANES]) {
    crate::fma::dispatch(SinCosLanes { x, s, c });
}

/// The [`sin_cos_lanes`] kernel (see [`crate::fma::Kernel`]).
struct SinCosLanes<'a> {
    x: &'a [f64; LANES],
    s: &'a mut [f64; LANES],
    c: &'a mut [f64; LANES],
}

impl crate::fma::Kernel for SinCosLanes<'_> {
    type Output = ();
    #[inline(always)]
    fn run<A: MulAdd>(self) {
        sin_cos_lanes_with::<A>(self.x, self.s, self.c);
    }
}

/// [`sin_cos_lanes`] with the multiply-add policy `A`, for callers that are themselves compiled
/// twice (see [`crate::fma`]); [`crate::fma::Fused`] only inside `fma` target-feature code.
#[inline(always)]
pub fn sin_cos_lanes_with<A: MulAdd>(x: &[f64; LANES], s: &mut [f64; LANES], c: &mut [f64; LANES]) {
    // NaN fails the comparison, so it takes the scalar path too. A non-short-circuit fold: one
    // vector compare and mask test instead of eight scalar branches.
    let all_small = x
        .iter()
        .fold(true, |ok, v| ok & (v.abs() < REDUCTION_LIMIT));
    if !all_small {
        for i in 0..LANES {
            (s[i], c[i]) = sin_cos_with::<A>(x[i]);
        }
        return;
    }
    for i in 0..LANES {
        (s[i], c[i]) = sin_cos_reduced::<A>(x[i]);
    }
}

/// The portable lanes (no run-time dispatch), public for the accuracy tests.
#[doc(hidden)]
pub fn sin_cos_lanes_portable(x: &[f64; LANES], s: &mut [f64; LANES], c: &mut [f64; LANES]) {
    sin_cos_lanes_with::<Plain>(x, s, c);
}
