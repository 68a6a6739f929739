//! An inlinable sine/cosine pair for the hot paths.
//!
//! `f64::sin_cos` calls the C library twice (or once, as `sincos`): an opaque call the CPU
//! cannot overlap with the neighbouring joints' work. [`sin_cos`] is the classic fdlibm
//! algorithm written inline: Cody–Waite reduction x = n·π/2 + y with π/2 split in two parts
//! (33 + 53 bits, exact products for |n| < 2²⁰), then the fdlibm minimax kernels for sin and
//! cos on |y| ≤ π/4 (errors < 1 ulp of 1), then the quadrant. Outside |x| < 2¹⁹·π/2 or for
//! non-finite x it falls back to the standard library. Absolute error ≤ 2.3e-16 against
//! `f64::sin_cos` (tested over millions of arguments in `tests/trig.rs`).

// The constants are fdlibm's, written with the digits it publishes.
#![allow(clippy::excessive_precision)]

use crate::fma::{MulAdd, Plain};

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

/// sin y for |y| ≤ π/4 (fdlibm `__kernel_sin` with a zero tail).
#[inline(always)]
fn kernel_sin<A: MulAdd>(y: f64) -> f64 {
    let z = y * y;
    let v = z * y;
    let r = A::madd(z, A::madd(z, A::madd(z, A::madd(z, S6, S5), S4), S3), S2);
    A::madd(v, A::madd(z, r, S1), y)
}

/// cos y for |y| ≤ π/4 (fdlibm `__kernel_cos` with a zero tail).
#[inline(always)]
fn kernel_cos<A: MulAdd>(y: f64) -> f64 {
    let z = y * y;
    let w2 = z * z;
    let r = A::madd(
        w2 * w2,
        A::madd(z, A::madd(z, C6, C5), C4),
        z * A::madd(z, A::madd(z, C3, C2), C1),
    );
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    w + A::madd(z, r, (1.0 - w) - hz)
}

/// Above this |x| (≈ 2¹⁹·π/2) the two-part Cody–Waite reduction is no longer exact enough.
const REDUCTION_LIMIT: f64 = 823_549.6;

/// (sin x, cos x) for finite |x| < [`REDUCTION_LIMIT`]: reduction, kernels, quadrant; no branch.
#[inline(always)]
fn sin_cos_reduced<A: MulAdd>(x: f64) -> (f64, f64) {
    // Round to nearest with the 1.5·2⁵² trick (f64::round is a libm call on baseline x86-64);
    // the low mantissa bits of `k` then hold n mod 4.
    let k = A::madd(x, INV_PIO2, SHIFTER);
    let quadrant = k.to_bits() & 3;
    let n = k - SHIFTER;
    // n·PIO2_1 is exact (33-bit constant, |n| < 2²⁰), so fused or not gives the same y.
    let y = A::madd(-n, PIO2_1T, A::madd(-n, PIO2_1, x));
    let (s, c) = (kernel_sin::<A>(y), kernel_cos::<A>(y));
    // Branch-free quadrant: odd quadrants swap sin and cos; signs from the quadrant bits.
    let odd = quadrant & 1 == 1;
    let (s, c) = if odd { (c, s) } else { (s, c) };
    let sin_sign = (quadrant & 2) << 62;
    let cos_sign = ((quadrant + 1) & 2) << 62;
    (
        f64::from_bits(s.to_bits() ^ sin_sign),
        f64::from_bits(c.to_bits() ^ cos_sign),
    )
}

/// (sin x, cos x), inlined; see the module documentation for the method and accuracy.
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if !x.is_finite() || x.abs() >= REDUCTION_LIMIT {
        return x.sin_cos();
    }
    sin_cos_reduced::<Plain>(x)
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
    // NaN fails the comparison, so it takes the scalar path too.
    if !x.iter().all(|v| v.abs() < REDUCTION_LIMIT) {
        for i in 0..LANES {
            (s[i], c[i]) = sin_cos(x[i]);
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
