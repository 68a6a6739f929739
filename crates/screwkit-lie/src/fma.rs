//! Multiply-add policies for kernels compiled twice: once portable, once for CPUs with fused
//! multiply-add (selected at run time by the caller).
//!
//! `a.mul_add(b, c)` is one instruction where the CPU has FMA and the function is compiled with
//! that target feature, but a C library call otherwise, so hot kernels are written against
//! [`MulAdd`] and instantiated with [`Plain`] (portable) and [`Fused`] (inside
//! `#[target_feature(enable = "avx2,fma")]` functions only). The two differ in the last bit
//! (fused rounds once), never more.

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

/// Fused `a·b + c` (one rounding): only for code compiled with the `fma` target feature.
#[derive(Debug, Clone, Copy)]
pub struct Fused;

impl MulAdd for Fused {
    #[inline(always)]
    fn madd(a: f64, b: f64, c: f64) -> f64 {
        a.mul_add(b, c)
    }
}

/// True when this CPU runs the `avx2,fma` clones of the hot kernels (x86-64 with AVX2 and FMA;
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
