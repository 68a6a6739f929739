//! Multiply-add policies and the one run-time dispatch of the hot kernels.
//!
//! `a.mul_add(b, c)` is one instruction where the CPU has FMA and the function is compiled with
//! that target feature, but a C library call otherwise, so hot kernels are written once against
//! [`MulAdd`] and compiled twice: with [`Plain`] (portable) and with [`Fused`] inside a function
//! compiled for AVX2 + FMA. The two differ in the last bit (fused rounds once), never more.
//!
//! # Adding a kernel
//!
//! A kernel is a value holding its inputs that implements [`Kernel`]: one generic function
//! `run::<A>`, marked `#[inline(always)]` (as must be every helper it calls, so the whole body
//! is compiled inside the AVX2 + FMA clone). Call it through [`dispatch`], which is the only
//! place in the workspace that checks the CPU, holds the `unsafe` call and the
//! `#[target_feature]` twin:
//!
//! ```
//! use screwkit_lie::fma::{dispatch, Kernel, MulAdd, Plain};
//!
//! /// Σ a_i b_i.
//! struct Dot<'a>(&'a [f64], &'a [f64]);
//!
//! impl Kernel for Dot<'_> {
//!     type Output = f64;
//!     #[inline(always)]
//!     fn run<A: MulAdd>(self) -> f64 {
//!         self.0.iter().zip(self.1).fold(0.0, |acc, (a, b)| A::madd(*a, *b, acc))
//!     }
//! }
//!
//! let (a, b) = ([1.0, 2.0, 3.0], [4.0, 5.0, 6.0]);
//! assert_eq!(dispatch(Dot(&a, &b)), 32.0);
//! // Tests call both instantiations directly and require them to agree.
//! assert_eq!(Dot(&a, &b).run::<Plain>(), 32.0);
//! ```

/// `madd(a, b, c) = a·b + c`, rounded the way the implementation says.
pub trait MulAdd {
    /// a·b + c.
    fn madd(a: f64, b: f64, c: f64) -> f64;
}

/// `a·b + c` with two roundings: portable.
#[derive(Debug, Clone, Copy)]
pub struct Plain;

impl MulAdd for Plain {
    #[inline(always)]
    fn madd(a: f64, b: f64, c: f64) -> f64 {
        a * b + c
    }
}

/// Fused `a·b + c` (one rounding). Inside [`dispatch`]'s AVX2 + FMA clone it is one instruction;
/// called elsewhere it is correct but slow (a library call), which the tests that compare both
/// instantiations accept.
#[derive(Debug, Clone, Copy)]
pub struct Fused;

impl MulAdd for Fused {
    #[inline(always)]
    fn madd(a: f64, b: f64, c: f64) -> f64 {
        a.mul_add(b, c)
    }
}

/// A hot kernel written once over the multiply-add policy and run through [`dispatch`].
pub trait Kernel {
    /// What the kernel returns.
    type Output;
    /// The kernel body with the multiply-add policy `A`; `#[inline(always)]` on implementations.
    fn run<A: MulAdd>(self) -> Self::Output;
}

/// Runs `kernel` with fused multiply-adds on CPUs with AVX2 and FMA (see [`fused_available`]),
/// portably elsewhere.
#[inline(always)]
pub fn dispatch<K: Kernel>(kernel: K) -> K::Output {
    #[cfg(target_arch = "x86_64")]
    if fused_available() {
        // SAFETY: the CPU has AVX2 and FMA, the features `run_fused` is compiled for (checked
        // just above).
        return unsafe { run_fused(kernel) };
    }
    kernel.run::<Plain>()
}

/// `kernel.run::<Fused>()` compiled for AVX2 + FMA: the kernel's `#[inline(always)]` body is
/// generated here with those instructions.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn run_fused<K: Kernel>(kernel: K) -> K::Output {
    kernel.run::<Fused>()
}

/// True when this CPU runs the AVX2 + FMA clone of the kernels (x86-64 with AVX2 and FMA;
/// detected once and cached by the standard library). Always false on other architectures.
#[inline(always)]
pub fn fused_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// The kernel path [`dispatch`] takes on this CPU: `"avx2+fma"` (the fused clone) or
/// `"portable"`, for benchmarks to say where they ran.
pub fn kernel_path() -> &'static str {
    if fused_available() {
        "avx2+fma"
    } else {
        "portable"
    }
}
