//! Runtime dispatch: a kernel written once, run compiled for the instruction set of a
//! [`Level`] (see the module docs of [`crate::simd`]).

use super::reg::F64s;
use super::Level;

/// A kernel generic over its register type: its inputs are the implementor's fields,
/// [`Kernel::run`] is its body (`#[inline(always)]`, so that it is compiled into the
/// dispatch's instruction set). [`dispatch`] runs it.
pub(crate) trait Kernel {
    /// What the kernel returns.
    type Out;
    /// The body, on registers `R`.
    fn run<R: F64s>(self) -> Self::Out;
}

/// Run `k` compiled for `level`'s instruction set, on its registers: AVX-512F on `__m512d`,
/// AVX2 + FMA on `__m256d`, otherwise ([`Level::Sse2`], [`Level::Scalar`], or a level this
/// CPU lacks) the baseline on `__m128d` (x86-64) or `f64` (elsewhere).
#[inline]
pub(crate) fn dispatch<K: Kernel>(level: Level, k: K) -> K::Out {
    match level {
        #[cfg(target_arch = "x86_64")]
        Level::Avx512 if Level::Avx512.available() => {
            // SAFETY: the CPU has AVX-512F (checked just above).
            unsafe { x86::kernel_avx512(k) }
        }
        #[cfg(target_arch = "x86_64")]
        Level::Avx2 if Level::Avx2.available() => {
            // SAFETY: the CPU has AVX2 and FMA (checked just above).
            unsafe { x86::kernel_avx2(k) }
        }
        #[cfg(target_arch = "x86_64")]
        _ => k.run::<super::reg::Reg<std::arch::x86_64::__m128d>>(),
        #[cfg(not(target_arch = "x86_64"))]
        _ => k.run::<f64>(),
    }
}

/// Run `f` compiled for `level`'s instruction set (as [`dispatch`], for kernels that need no
/// register type: fixed-length lane loops the compiler vectorises). Mark the closure
/// `#[inline(always)]`, so that its body is compiled into the dispatch.
#[inline]
pub(crate) fn run<T>(level: Level, f: impl FnOnce() -> T) -> T {
    match level {
        #[cfg(target_arch = "x86_64")]
        Level::Avx512 if Level::Avx512.available() => {
            // SAFETY: the CPU has AVX-512F (checked just above).
            unsafe { x86::run_avx512(f) }
        }
        #[cfg(target_arch = "x86_64")]
        Level::Avx2 if Level::Avx2.available() => {
            // SAFETY: the CPU has AVX2 and FMA (checked just above).
            unsafe { x86::run_avx2(f) }
        }
        _ => f(),
    }
}

/// Run `f` compiled with SSE4.1 where the CPU has it (`floor`, `ceil` and `round` as
/// instructions rather than libm calls; exact either way, so the same answers), else as it is.
#[inline]
pub(crate) fn with_rounding<T>(f: impl FnOnce() -> T) -> T {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("sse4.1") {
        // SAFETY: the CPU has SSE4.1 (checked just above).
        return unsafe { x86::run_sse41(f) };
    }
    f()
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    use super::super::reg::Reg;
    use super::Kernel;
    use std::arch::x86_64::{__m256d, __m512d};

    #[target_feature(enable = "avx512f")]
    pub(super) fn kernel_avx512<K: Kernel>(k: K) -> K::Out {
        k.run::<Reg<__m512d>>()
    }

    #[target_feature(enable = "avx2,fma")]
    pub(super) fn kernel_avx2<K: Kernel>(k: K) -> K::Out {
        k.run::<Reg<__m256d>>()
    }

    #[target_feature(enable = "avx512f")]
    pub(super) fn run_avx512<T>(f: impl FnOnce() -> T) -> T {
        f()
    }

    #[target_feature(enable = "avx2,fma")]
    pub(super) fn run_avx2<T>(f: impl FnOnce() -> T) -> T {
        f()
    }

    #[target_feature(enable = "sse4.1")]
    pub(super) fn run_sse41<T>(f: impl FnOnce() -> T) -> T {
        f()
    }
}
