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
//! is compiled inside the AVX2 + FMA clone). Call it through [`dispatch`], which holds the
//! `unsafe` call and the `#[target_feature]` twin of the single calls (the batch kernels have
//! the other dispatch, [`crate::lanes::dispatch_lanes`]; both ask [`KernelPath::current`], the
//! one place that checks the CPU):
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
        // by `KernelPath::current`, which never reports a path the CPU lacks).
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

/// True when this CPU runs the fused clones of the kernels (x86-64 with AVX2 and FMA, unless
/// [`KernelPath::current`] was told otherwise). Always false on other architectures.
#[inline(always)]
pub fn fused_available() -> bool {
    KernelPath::current() != KernelPath::Portable
}

/// The instruction sets the kernels run on, narrowest first: what [`dispatch`] and
/// [`crate::lanes::dispatch_lanes`] choose from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum KernelPath {
    /// Baseline code, two roundings per multiply-add ([`Plain`]).
    Portable,
    /// AVX2 + FMA: fused multiply-adds ([`Fused`]); the lane kernels on 256-bit registers.
    Avx2Fma,
    /// AVX-512 (F, VL, DQ) besides AVX2 + FMA: the lane kernels on 512-bit registers, the
    /// single calls as on [`KernelPath::Avx2Fma`].
    Avx512,
}

/// The environment variable that narrows the kernel path for a measurement: `portable`,
/// `avx2` or `avx512` (a path wider than the CPU has falls back to the widest it has; any
/// other value is ignored). Read once, at the first kernel call.
pub const KERNELS_VAR: &str = "SCREWKIT_KERNELS";

impl KernelPath {
    /// Every path, narrowest first.
    pub const ALL: [KernelPath; 3] = [
        KernelPath::Portable,
        KernelPath::Avx2Fma,
        KernelPath::Avx512,
    ];

    /// The widest path this CPU has (detected once and cached by the standard library).
    pub fn detected() -> KernelPath {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::is_x86_feature_detected as has;
            if has!("avx2") && has!("fma") {
                if has!("avx512f") && has!("avx512vl") && has!("avx512dq") {
                    return KernelPath::Avx512;
                }
                return KernelPath::Avx2Fma;
            }
        }
        KernelPath::Portable
    }

    /// The path the kernels take: [`KernelPath::detected`], narrowed by [`KERNELS_VAR`] when
    /// set (decided once per process).
    #[inline(always)]
    pub fn current() -> KernelPath {
        static CURRENT: std::sync::OnceLock<KernelPath> = std::sync::OnceLock::new();
        *CURRENT.get_or_init(|| {
            KernelPath::detected().narrowed_by(std::env::var(KERNELS_VAR).ok().as_deref())
        })
    }

    /// This path narrowed by [`KERNELS_VAR`]'s value `asked`: the path it names when that is
    /// no wider; unset, an unknown word or a wider path leave it (a typo shows in the benches'
    /// `host` line, which names the path taken).
    pub fn narrowed_by(self, asked: Option<&str>) -> KernelPath {
        asked
            .and_then(|v| KernelPath::from_name(v.trim()))
            .map_or(self, |a| a.min(self))
    }

    /// Whether this CPU can run the path.
    pub fn available(self) -> bool {
        self <= KernelPath::detected()
    }

    /// The path's name: `portable`, `avx2+fma` or `avx512`.
    pub fn name(self) -> &'static str {
        match self {
            KernelPath::Portable => "portable",
            KernelPath::Avx2Fma => "avx2+fma",
            KernelPath::Avx512 => "avx512",
        }
    }

    /// The path named `portable`, `avx2` (or `avx2+fma`) or `avx512`.
    pub fn from_name(name: &str) -> Option<KernelPath> {
        match name {
            "portable" => Some(KernelPath::Portable),
            "avx2" | "avx2+fma" => Some(KernelPath::Avx2Fma),
            "avx512" => Some(KernelPath::Avx512),
            _ => None,
        }
    }
}

/// The kernel path this process runs ([`KernelPath::current`]'s name: `"avx512"`, `"avx2+fma"`
/// or `"portable"`), for benchmarks to say where they ran.
pub fn kernel_path() -> &'static str {
    KernelPath::current().name()
}

#[cfg(test)]
mod tests {
    use super::KernelPath;

    /// The override's words, and that it only ever narrows (never asks for instructions the
    /// CPU lacks), whatever it holds.
    #[test]
    fn the_override_narrows_only() {
        use KernelPath::{Avx2Fma, Avx512, Portable};
        for path in KernelPath::ALL {
            assert_eq!(KernelPath::from_name(path.name()), Some(path));
            assert_eq!(path.narrowed_by(None), path);
            for junk in [
                "",
                "AVX512",
                "avx-512",
                "sse",
                "avx2 fma",
                "\0",
                "portable!",
            ] {
                assert_eq!(path.narrowed_by(Some(junk)), path, "{junk:?}");
            }
        }
        assert_eq!(Avx512.narrowed_by(Some("avx2")), Avx2Fma);
        assert_eq!(Avx512.narrowed_by(Some(" portable\n")), Portable);
        assert_eq!(Avx2Fma.narrowed_by(Some("avx512")), Avx2Fma);
        assert_eq!(Portable.narrowed_by(Some("avx512")), Portable);
        assert_eq!(Portable.narrowed_by(Some("avx2+fma")), Portable);
        assert!(KernelPath::current().available() && KernelPath::Portable.available());
    }
}
