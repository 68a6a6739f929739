//! f64 lanes on the vector unit, and the dispatch of the kernels written on them.
//!
//! The batch kernels compute several configurations at once, one per lane. They are written
//! once against [`Lanes`], the operations on a value of [`Lanes::WIDTH`] lanes, and run through
//! [`dispatch_lanes`], which picks the widest unit this CPU has ([`KernelPath::current`]):
//! - [`Avx512`]: eight lanes, a value is one 512-bit register (32 of them: a pose's twelve
//!   values and the joint's stay in registers along a chain);
//! - [`Avx2`]: four lanes, one 256-bit register (16 of them);
//! - [`Portable`]: four lanes in an array, for the compiler to vectorise as it can.
//!
//! Every operation is the scalar one lane by lane, and the multiply-add rounds as
//! [`Lanes::Scalar`] does: [`Fused`](crate::fma::Fused) on AVX-512 and AVX2, [`Plain`]
//! portably — the policies [`crate::fma::dispatch`] gives the single calls on the same path. So
//! lane l of a kernel that repeats a single call's operations in the same order equals that
//! call on configuration l, bit for bit.
//!
//! The instruction-set types are tokens: only the dispatch creates one, after checking the CPU,
//! so holding one is the proof that its instructions exist.
//!
//! ```
//! use screwkit_lie::lanes::{dispatch_lanes, LaneKernel, Lanes, MAX_WIDTH};
//!
//! /// a·b + c, value by value, [`Lanes::WIDTH`] at a time.
//! struct Madd<'a>(&'a [f64; MAX_WIDTH], &'a [f64; MAX_WIDTH], &'a [f64; MAX_WIDTH]);
//!
//! impl LaneKernel for Madd<'_> {
//!     type Output = [f64; MAX_WIDTH];
//!     #[inline(always)]
//!     fn run<L: Lanes>(self, l: L) -> [f64; MAX_WIDTH] {
//!         let mut out = [0.0; MAX_WIDTH];
//!         for k in (0..MAX_WIDTH).step_by(L::WIDTH) {
//!             let (a, b, c) = (&self.0[k..], &self.1[k..], &self.2[k..]);
//!             l.store(l.madd(l.load(a), l.load(b), l.load(c)), &mut out[k..]);
//!         }
//!         out
//!     }
//! }
//!
//! let x = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0];
//! assert_eq!(dispatch_lanes(Madd(&x, &x, &x))[7], 72.0);
//! ```

use crate::fma::{KernelPath, MulAdd, Plain};

/// The most lanes a value holds (the widest [`Lanes::WIDTH`]); every width divides it.
pub const MAX_WIDTH: usize = 8;

/// Lanes of a portable value.
const PORTABLE_WIDTH: usize = 4;

/// The operations on f64 lanes of one instruction set (a token: see the module documentation).
/// Each is the scalar operation lane by lane, exactly rounded as that is, with [`Lanes::madd`]
/// rounded as [`Lanes::Scalar`]'s.
pub trait Lanes: Copy {
    /// [`Lanes::WIDTH`] f64 in this unit's registers.
    type V: Copy;
    /// The scalar multiply-add policy whose results [`Lanes::madd`] equals.
    type Scalar: MulAdd;
    /// The path this is.
    const PATH: KernelPath;
    /// Lanes per value: 8 on AVX-512, 4 on AVX2 (one register either way) and portably; it
    /// divides [`MAX_WIDTH`].
    const WIDTH: usize;
    /// x in every lane.
    fn splat(self, x: f64) -> Self::V;
    /// The first [`Lanes::WIDTH`] values of `x` (panics if shorter).
    fn load(self, x: &[f64]) -> Self::V;
    /// Writes the lanes to the first [`Lanes::WIDTH`] values of `out` (panics if shorter).
    fn store(self, v: Self::V, out: &mut [f64]);
    /// a + b.
    fn add(self, a: Self::V, b: Self::V) -> Self::V;
    /// a − b.
    fn sub(self, a: Self::V, b: Self::V) -> Self::V;
    /// a · b.
    fn mul(self, a: Self::V, b: Self::V) -> Self::V;
    /// a · b + c, rounded as `Self::Scalar::madd`.
    fn madd(self, a: Self::V, b: Self::V, c: Self::V) -> Self::V;
    /// −a (the sign bit flipped, as the scalar `-a`).
    fn neg(self, a: Self::V) -> Self::V;
    /// |a| (the sign bit cleared).
    fn abs(self, a: Self::V) -> Self::V;
    /// Whether a < `limit` in every lane (false where a lane is NaN).
    fn all_below(self, a: Self::V, limit: f64) -> bool;
    /// The lanes' bit patterns plus `k` (wrapping 64-bit integer addition).
    fn bits_add(self, a: Self::V, k: u64) -> Self::V;
    /// Per lane: `a` where the bit pattern of `m` has any of the bits of `bit`, else `b`.
    fn select_bits(self, m: Self::V, bit: u64, a: Self::V, b: Self::V) -> Self::V;
    /// The transpose out: for every lane l and r < `m` (≤ 4),
    /// `out[at + l·stride + r] = v[r][l]`. Panics if that reaches past `out`.
    fn store_transposed(
        self,
        v: &[Self::V; 4],
        m: usize,
        out: &mut [f64],
        at: usize,
        stride: usize,
    );
    /// The transpose in: value r < `m` (≤ 4) holds `src[at + l·stride + r]` in lane l (the
    /// others 0). Panics if that reaches past `src`.
    fn load_transposed(self, src: &[f64], at: usize, stride: usize, m: usize) -> [Self::V; 4];
}

/// A kernel on lanes, written once for every [`Lanes`] and run through [`dispatch_lanes`].
/// `run` and every helper it calls are `#[inline(always)]`, with no closures or iterator
/// adaptors in the hot code (one the inliner leaves out of line is compiled without the
/// dispatch's instruction set), so the whole body is compiled inside the dispatch's clone.
pub trait LaneKernel {
    /// What the kernel returns.
    type Output;
    /// The kernel body on the lanes `l`.
    fn run<L: Lanes>(self, l: L) -> Self::Output;
}

/// Runs `kernel` on the widest lanes of [`KernelPath::current`].
#[inline(always)]
pub fn dispatch_lanes<K: LaneKernel>(kernel: K) -> K::Output {
    // The current path is one the CPU has (no second check: this runs once per block).
    match KernelPath::current() {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `KernelPath::current` never reports a path the CPU lacks.
        KernelPath::Avx512 => unsafe { x86::run_avx512(kernel) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as above.
        KernelPath::Avx2Fma => unsafe { x86::run_avx2(kernel) },
        _ => kernel.run(Portable(())),
    }
}

/// Runs `kernel` on the lanes of `path` when this CPU has it (tests run every path the CPU
/// has); gives the kernel back otherwise.
#[inline(always)]
pub fn dispatch_lanes_on<K: LaneKernel>(path: KernelPath, kernel: K) -> Result<K::Output, K> {
    if !path.available() {
        return Err(kernel);
    }
    match path {
        KernelPath::Portable => Ok(kernel.run(Portable(()))),
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the CPU has the path's instructions (`available` above).
        KernelPath::Avx2Fma => Ok(unsafe { x86::run_avx2(kernel) }),
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as above.
        KernelPath::Avx512 => Ok(unsafe { x86::run_avx512(kernel) }),
        #[cfg(not(target_arch = "x86_64"))]
        _ => Err(kernel),
    }
}

/// Portable lanes: four f64 in an array (a pose's twelve rows of them fit baseline x86-64's
/// sixteen 2-lane registers better than eight would), two roundings per multiply-add
/// ([`Plain`]).
#[derive(Debug, Clone, Copy)]
pub struct Portable(());

/// The portable value lane by lane.
macro_rules! each {
    (|$i:ident| $e:expr) => {{
        let mut out = [0.0; PORTABLE_WIDTH];
        for $i in 0..PORTABLE_WIDTH {
            out[$i] = $e;
        }
        out
    }};
}

impl Lanes for Portable {
    type V = [f64; PORTABLE_WIDTH];
    type Scalar = Plain;
    const PATH: KernelPath = KernelPath::Portable;
    const WIDTH: usize = PORTABLE_WIDTH;
    #[inline(always)]
    fn splat(self, x: f64) -> Self::V {
        [x; PORTABLE_WIDTH]
    }
    #[inline(always)]
    fn load(self, x: &[f64]) -> Self::V {
        let mut v = [0.0; PORTABLE_WIDTH];
        v.copy_from_slice(&x[..PORTABLE_WIDTH]);
        v
    }
    #[inline(always)]
    fn store(self, v: Self::V, out: &mut [f64]) {
        out[..PORTABLE_WIDTH].copy_from_slice(&v);
    }
    #[inline(always)]
    fn add(self, a: Self::V, b: Self::V) -> Self::V {
        each!(|i| a[i] + b[i])
    }
    #[inline(always)]
    fn sub(self, a: Self::V, b: Self::V) -> Self::V {
        each!(|i| a[i] - b[i])
    }
    #[inline(always)]
    fn mul(self, a: Self::V, b: Self::V) -> Self::V {
        each!(|i| a[i] * b[i])
    }
    #[inline(always)]
    fn madd(self, a: Self::V, b: Self::V, c: Self::V) -> Self::V {
        each!(|i| Plain::madd(a[i], b[i], c[i]))
    }
    #[inline(always)]
    fn neg(self, a: Self::V) -> Self::V {
        each!(|i| -a[i])
    }
    #[inline(always)]
    fn abs(self, a: Self::V) -> Self::V {
        each!(|i| a[i].abs())
    }
    #[inline(always)]
    fn all_below(self, a: Self::V, limit: f64) -> bool {
        let mut all = true;
        for x in a {
            all &= x < limit;
        }
        all
    }
    #[inline(always)]
    fn bits_add(self, a: Self::V, k: u64) -> Self::V {
        each!(|i| f64::from_bits(a[i].to_bits().wrapping_add(k)))
    }
    #[inline(always)]
    fn select_bits(self, m: Self::V, bit: u64, a: Self::V, b: Self::V) -> Self::V {
        each!(|i| if m[i].to_bits() & bit != 0 {
            a[i]
        } else {
            b[i]
        })
    }
    #[inline(always)]
    fn store_transposed(
        self,
        v: &[Self::V; 4],
        m: usize,
        out: &mut [f64],
        at: usize,
        stride: usize,
    ) {
        for l in 0..PORTABLE_WIDTH {
            let dst = &mut out[at + l * stride..][..m];
            for r in 0..m {
                dst[r] = v[r][l];
            }
        }
    }
    #[inline(always)]
    fn load_transposed(self, src: &[f64], at: usize, stride: usize, m: usize) -> [Self::V; 4] {
        let mut out = [[0.0; PORTABLE_WIDTH]; 4];
        for l in 0..PORTABLE_WIDTH {
            let row = &src[at + l * stride..][..m];
            for r in 0..m {
                out[r][l] = row[r];
            }
        }
        out
    }
}

#[cfg(target_arch = "x86_64")]
pub use x86::{Avx2, Avx512};

// Index loops on purpose in the lane code: an iterator adaptor or closure may stay out of line,
// and then it is compiled without the dispatch's instruction set.
#[cfg(target_arch = "x86_64")]
#[allow(clippy::needless_range_loop)]
mod x86 {
    use super::{KernelPath, LaneKernel, Lanes};
    use crate::fma::Fused;
    use std::arch::x86_64::*;

    /// AVX2 + FMA lanes: four, one 256-bit register per value (sixteen registers: a pose's
    /// twelve values of four configurations stay in them), fused multiply-adds ([`Fused`]).
    #[derive(Debug, Clone, Copy)]
    pub struct Avx2(());

    /// AVX-512 lanes: eight, one 512-bit register per value (32 registers), fused multiply-adds
    /// ([`Fused`]).
    #[derive(Debug, Clone, Copy)]
    pub struct Avx512(());

    /// The kernel compiled for AVX2 + FMA.
    ///
    /// # Safety
    /// The CPU must have AVX2 and FMA.
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn run_avx2<K: LaneKernel>(kernel: K) -> K::Output {
        kernel.run(Avx2(()))
    }

    /// The kernel compiled for AVX-512 (F, VL, DQ) and AVX2 + FMA.
    ///
    /// # Safety
    /// The CPU must have those.
    #[target_feature(enable = "avx2,fma,avx512f,avx512vl,avx512dq")]
    pub(super) unsafe fn run_avx512<K: LaneKernel>(kernel: K) -> K::Output {
        kernel.run(Avx512(()))
    }

    /// The lane mask of the first `m` (≤ 4) of four 64-bit lanes, for the masked moves.
    #[inline(always)]
    unsafe fn first(m: usize) -> __m256i {
        let k = m as i64;
        _mm256_set_epi64x(
            -((k > 3) as i64),
            -((k > 2) as i64),
            -((k > 1) as i64),
            -((k > 0) as i64),
        )
    }

    /// Rows of the 4 × 4 transpose of the columns (a, b, c, d): row r = (a_r, b_r, c_r, d_r).
    #[inline(always)]
    unsafe fn transpose4(a: __m256d, b: __m256d, c: __m256d, d: __m256d) -> [__m256d; 4] {
        let (t0, t1) = (_mm256_unpacklo_pd(a, b), _mm256_unpackhi_pd(a, b));
        let (t2, t3) = (_mm256_unpacklo_pd(c, d), _mm256_unpackhi_pd(c, d));
        [
            _mm256_permute2f128_pd::<0x20>(t0, t2),
            _mm256_permute2f128_pd::<0x20>(t1, t3),
            _mm256_permute2f128_pd::<0x31>(t0, t2),
            _mm256_permute2f128_pd::<0x31>(t1, t3),
        ]
    }

    /// Four lanes of [`Lanes::store_transposed`] (lanes `first_lane..first_lane + 4`): lane
    /// `first_lane + r` gets row r of the transpose of `v` (its first m values).
    #[inline(always)]
    unsafe fn store_four(
        v: [__m256d; 4],
        m: usize,
        out: &mut [f64],
        at: usize,
        stride: usize,
        first_lane: usize,
    ) {
        let rows = transpose4(v[0], v[1], v[2], v[3]);
        let mask = first(m);
        for r in 0..4 {
            let dst = &mut out[at + (first_lane + r) * stride..][..m];
            if m == 4 {
                _mm256_storeu_pd(dst.as_mut_ptr(), rows[r]);
            } else {
                _mm256_maskstore_pd(dst.as_mut_ptr(), mask, rows[r]);
            }
        }
    }

    /// Four lanes of [`Lanes::load_transposed`] (lanes `first_lane..first_lane + 4`).
    #[inline(always)]
    unsafe fn load_four(
        src: &[f64],
        at: usize,
        stride: usize,
        m: usize,
        first_lane: usize,
    ) -> [__m256d; 4] {
        let mask = first(m);
        let mut rows = [_mm256_setzero_pd(); 4];
        for r in 0..4 {
            let s = &src[at + (first_lane + r) * stride..][..m];
            rows[r] = if m == 4 {
                _mm256_loadu_pd(s.as_ptr())
            } else {
                _mm256_maskload_pd(s.as_ptr(), mask)
            };
        }
        transpose4(rows[0], rows[1], rows[2], rows[3])
    }

    /// The sign bit.
    const SIGN: i64 = i64::MIN;

    // SAFETY (every method below): an `Avx2` exists only once the CPU was found to have AVX2
    // and FMA (`dispatch_lanes_on`), the instructions used here.
    impl Lanes for Avx2 {
        type V = __m256d;
        type Scalar = Fused;
        const PATH: KernelPath = KernelPath::Avx2Fma;
        const WIDTH: usize = 4;
        #[inline(always)]
        fn splat(self, x: f64) -> Self::V {
            unsafe { _mm256_set1_pd(x) }
        }
        #[inline(always)]
        fn load(self, x: &[f64]) -> Self::V {
            unsafe { _mm256_loadu_pd(x[..4].as_ptr()) }
        }
        #[inline(always)]
        fn store(self, v: Self::V, out: &mut [f64]) {
            unsafe { _mm256_storeu_pd(out[..4].as_mut_ptr(), v) }
        }
        #[inline(always)]
        fn add(self, a: Self::V, b: Self::V) -> Self::V {
            unsafe { _mm256_add_pd(a, b) }
        }
        #[inline(always)]
        fn sub(self, a: Self::V, b: Self::V) -> Self::V {
            unsafe { _mm256_sub_pd(a, b) }
        }
        #[inline(always)]
        fn mul(self, a: Self::V, b: Self::V) -> Self::V {
            unsafe { _mm256_mul_pd(a, b) }
        }
        #[inline(always)]
        fn madd(self, a: Self::V, b: Self::V, c: Self::V) -> Self::V {
            unsafe { _mm256_fmadd_pd(a, b, c) }
        }
        #[inline(always)]
        fn neg(self, a: Self::V) -> Self::V {
            unsafe { _mm256_xor_pd(a, _mm256_castsi256_pd(_mm256_set1_epi64x(SIGN))) }
        }
        #[inline(always)]
        fn abs(self, a: Self::V) -> Self::V {
            unsafe { _mm256_andnot_pd(_mm256_castsi256_pd(_mm256_set1_epi64x(SIGN)), a) }
        }
        #[inline(always)]
        fn all_below(self, a: Self::V, limit: f64) -> bool {
            unsafe {
                let below = _mm256_cmp_pd::<_CMP_LT_OQ>(a, _mm256_set1_pd(limit));
                _mm256_movemask_pd(below) == 0b1111
            }
        }
        #[inline(always)]
        fn bits_add(self, a: Self::V, k: u64) -> Self::V {
            unsafe {
                _mm256_castsi256_pd(_mm256_add_epi64(
                    _mm256_castpd_si256(a),
                    _mm256_set1_epi64x(k as i64),
                ))
            }
        }
        #[inline(always)]
        fn select_bits(self, m: Self::V, bit: u64, a: Self::V, b: Self::V) -> Self::V {
            unsafe {
                let bits = _mm256_and_si256(_mm256_castpd_si256(m), _mm256_set1_epi64x(bit as i64));
                let none = _mm256_cmpeq_epi64(bits, _mm256_setzero_si256());
                _mm256_blendv_pd(a, b, _mm256_castsi256_pd(none))
            }
        }
        #[inline(always)]
        fn store_transposed(
            self,
            v: &[Self::V; 4],
            m: usize,
            out: &mut [f64],
            at: usize,
            stride: usize,
        ) {
            unsafe { store_four(*v, m, out, at, stride, 0) }
        }
        #[inline(always)]
        fn load_transposed(self, src: &[f64], at: usize, stride: usize, m: usize) -> [Self::V; 4] {
            unsafe { load_four(src, at, stride, m, 0) }
        }
    }

    /// The two 256-bit halves of a 512-bit value.
    #[inline(always)]
    unsafe fn halves(v: __m512d) -> [__m256d; 2] {
        [_mm512_castpd512_pd256(v), _mm512_extractf64x4_pd::<1>(v)]
    }

    /// The 512-bit value of two halves.
    #[inline(always)]
    unsafe fn join(lo: __m256d, hi: __m256d) -> __m512d {
        _mm512_insertf64x4::<1>(_mm512_castpd256_pd512(lo), hi)
    }

    // SAFETY (every method below): an `Avx512` exists only once the CPU was found to have
    // AVX-512 F, VL and DQ besides AVX2 and FMA (`dispatch_lanes_on`).
    impl Lanes for Avx512 {
        type V = __m512d;
        type Scalar = Fused;
        const PATH: KernelPath = KernelPath::Avx512;
        const WIDTH: usize = 8;
        #[inline(always)]
        fn splat(self, x: f64) -> Self::V {
            unsafe { _mm512_set1_pd(x) }
        }
        #[inline(always)]
        fn load(self, x: &[f64]) -> Self::V {
            unsafe { _mm512_loadu_pd(x[..8].as_ptr()) }
        }
        #[inline(always)]
        fn store(self, v: Self::V, out: &mut [f64]) {
            unsafe { _mm512_storeu_pd(out[..8].as_mut_ptr(), v) }
        }
        #[inline(always)]
        fn add(self, a: Self::V, b: Self::V) -> Self::V {
            unsafe { _mm512_add_pd(a, b) }
        }
        #[inline(always)]
        fn sub(self, a: Self::V, b: Self::V) -> Self::V {
            unsafe { _mm512_sub_pd(a, b) }
        }
        #[inline(always)]
        fn mul(self, a: Self::V, b: Self::V) -> Self::V {
            unsafe { _mm512_mul_pd(a, b) }
        }
        #[inline(always)]
        fn madd(self, a: Self::V, b: Self::V, c: Self::V) -> Self::V {
            unsafe { _mm512_fmadd_pd(a, b, c) }
        }
        #[inline(always)]
        fn neg(self, a: Self::V) -> Self::V {
            unsafe { _mm512_xor_pd(a, _mm512_castsi512_pd(_mm512_set1_epi64(SIGN))) }
        }
        #[inline(always)]
        fn abs(self, a: Self::V) -> Self::V {
            unsafe { _mm512_abs_pd(a) }
        }
        #[inline(always)]
        fn all_below(self, a: Self::V, limit: f64) -> bool {
            unsafe { _mm512_cmp_pd_mask::<_CMP_LT_OQ>(a, _mm512_set1_pd(limit)) == 0xff }
        }
        #[inline(always)]
        fn bits_add(self, a: Self::V, k: u64) -> Self::V {
            unsafe {
                _mm512_castsi512_pd(_mm512_add_epi64(
                    _mm512_castpd_si512(a),
                    _mm512_set1_epi64(k as i64),
                ))
            }
        }
        #[inline(always)]
        fn select_bits(self, m: Self::V, bit: u64, a: Self::V, b: Self::V) -> Self::V {
            unsafe {
                let any =
                    _mm512_test_epi64_mask(_mm512_castpd_si512(m), _mm512_set1_epi64(bit as i64));
                _mm512_mask_blend_pd(any, b, a)
            }
        }
        #[inline(always)]
        fn store_transposed(
            self,
            v: &[Self::V; 4],
            m: usize,
            out: &mut [f64],
            at: usize,
            stride: usize,
        ) {
            unsafe {
                let h = [halves(v[0]), halves(v[1]), halves(v[2]), halves(v[3])];
                for k in 0..2 {
                    store_four(
                        [h[0][k], h[1][k], h[2][k], h[3][k]],
                        m,
                        out,
                        at,
                        stride,
                        4 * k,
                    );
                }
            }
        }
        #[inline(always)]
        fn load_transposed(self, src: &[f64], at: usize, stride: usize, m: usize) -> [Self::V; 4] {
            unsafe {
                let (lo, hi) = (
                    load_four(src, at, stride, m, 0),
                    load_four(src, at, stride, m, 4),
                );
                [
                    join(lo[0], hi[0]),
                    join(lo[1], hi[1]),
                    join(lo[2], hi[2]),
                    join(lo[3], hi[3]),
                ]
            }
        }
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)] // as in the kernels
mod tests {
    use super::*;

    /// Every operation on every path this CPU has equals the scalar operation lane by lane,
    /// bit for bit (the multiply-add with the path's scalar policy), and the transposes move
    /// the right values, partial ones touching nothing else.
    struct Check;

    impl LaneKernel for Check {
        type Output = ();
        #[inline(always)]
        fn run<L: Lanes>(self, l: L) {
            let w = L::WIDTH;
            assert!(w > 0 && MAX_WIDTH.is_multiple_of(w));
            let a = [1.5, -0.0, 3.25e-7, -2.0, f64::NAN, 1e300, -7.5, 0.1];
            let b = [0.3, 2.0, -1.0, 0.7, 1.0, 1e10, 3.0, -0.2];
            let c = [-4.0, 1e-20, 0.5, 0.0, 2.0, -1e299, 8.0, 0.3];
            // Every lane of every value meets every special input: all the lane offsets.
            for at in (0..MAX_WIDTH).step_by(w) {
                let (a, b, c) = (&a[at..], &b[at..], &c[at..]);
                let (va, vb, vc) = (l.load(a), l.load(b), l.load(c));
                let out = |v: L::V| {
                    let mut o = [0.0; MAX_WIDTH];
                    l.store(v, &mut o);
                    o
                };
                let same = |got: [f64; MAX_WIDTH], want: &dyn Fn(usize) -> f64, what: &str| {
                    for i in 0..w {
                        assert_eq!(
                            got[i].to_bits(),
                            want(i).to_bits(),
                            "{:?} {what} lane {i}",
                            L::PATH
                        );
                    }
                };
                same(out(l.add(va, vb)), &|i| a[i] + b[i], "add");
                same(out(l.sub(va, vb)), &|i| a[i] - b[i], "sub");
                same(out(l.mul(va, vb)), &|i| a[i] * b[i], "mul");
                same(
                    out(l.madd(va, vb, vc)),
                    &|i| L::Scalar::madd(a[i], b[i], c[i]),
                    "madd",
                );
                same(out(l.neg(va)), &|i| -a[i], "neg");
                same(out(l.abs(va)), &|i| a[i].abs(), "abs");
                same(out(l.splat(0.25)), &|_| 0.25, "splat");
                same(
                    out(l.bits_add(va, 1)),
                    &|i| f64::from_bits(a[i].to_bits().wrapping_add(1)),
                    "bits_add",
                );
                same(
                    out(l.select_bits(va, 2, vb, vc)),
                    &|i| if a[i].to_bits() & 2 != 0 { b[i] } else { c[i] },
                    "select",
                );
                let below = |x: &[f64], limit: f64| x[..w].iter().all(|v| *v < limit);
                assert_eq!(l.all_below(va, 1e301), below(a, 1e301), "NaN is not below");
                assert_eq!(l.all_below(vb, 1e11), below(b, 1e11));
                assert_eq!(l.all_below(vb, 1.5), below(b, 1.5));
            }
            // Transposes, whole and partial, with a stride and an offset.
            let vals: [L::V; 4] = std::array::from_fn(|r| {
                l.load(&std::array::from_fn::<f64, MAX_WIDTH, _>(|k| {
                    (10 * r + k) as f64
                }))
            });
            let out = |v: L::V| {
                let mut o = [0.0; MAX_WIDTH];
                l.store(v, &mut o);
                o
            };
            for m in 1..=4 {
                let len = 3 + (w - 1) * 6 + 4;
                let mut buf = vec![-1.0; len];
                l.store_transposed(&vals, m, &mut buf, 3, 6);
                for (x, got) in buf.iter().enumerate() {
                    let want = match x.checked_sub(3) {
                        Some(y) if y % 6 < m && y / 6 < w => (10 * (y % 6) + y / 6) as f64,
                        _ => -1.0,
                    };
                    assert_eq!(*got, want, "{:?} store m = {m} at {x}", L::PATH);
                }
                let src: Vec<f64> = (0..len).map(|x| x as f64).collect();
                let got = l.load_transposed(&src, 3, 6, m);
                for (r, v) in got.iter().enumerate() {
                    let o = out(*v);
                    for k in 0..w {
                        let want = if r < m { (3 + 6 * k + r) as f64 } else { 0.0 };
                        assert_eq!(o[k], want, "{:?} load m = {m}", L::PATH);
                    }
                }
            }
        }
    }

    #[test]
    fn every_path_equals_the_scalar_operations() {
        let mut ran = 0;
        for path in KernelPath::ALL {
            if dispatch_lanes_on(path, Check).is_ok() {
                ran += 1;
            }
        }
        assert!(ran >= 1 && KernelPath::Portable.available());
        assert_eq!(
            ran,
            KernelPath::ALL.iter().filter(|p| p.available()).count()
        );
    }
}
