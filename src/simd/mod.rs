//! Runtime choice of the instruction set, and the one register abstraction, for the kernels
//! that run several samples in lockstep: the IK's closed form and FK re-check while
//! tracking, the limit fit's lane verdicts, the collision lanes, RNEA and the balancer in the
//! energy pass. Structure-of-arrays batches of [`LANES`] samples, each kernel written once,
//! compiled for the baseline x86-64 (SSE2), AVX2 + FMA and AVX-512F, and chosen at run time
//! by [`level`].
//!
//! # The abstraction
//!
//! [`F64s`] is "some lanes of `f64` in a register": `W` lanes with the operations the kernels
//! take (load, store, splat, `+ − ·`, `√`, `|x|`, the selects nalgebra and parry use for
//! minima and maxima, `f64::max`, comparisons to lane bit masks, one 8 × 12 transpose). It
//! has five register types:
//!
//! | type (private)      | lanes | instruction set                         |
//! |---------------------|-------|-----------------------------------------|
//! | `f64`               | 1     | any (the scalar reference)              |
//! | `Reg<__m128d>`      | 2     | SSE2, x86-64's baseline                 |
//! | `Reg<__m256d>`      | 4     | AVX2 + FMA                              |
//! | `Reg<__m512d>`      | 8     | AVX-512F                                |
//!
//! The intrinsics live in one place, [`V`] (`reg.rs`): one implementation per register type,
//! each method `unsafe` (the CPU must have the type's instruction set). `Reg<T>` wraps a
//! `T: V` and makes its methods safe: the type is private to this module and only
//! [`dispatch`] instantiates kernels with it, after checking the CPU, inside a function
//! compiled for the instruction set. So `unsafe` and `std::arch` stay in `src/simd/`; a kernel
//! is plain safe Rust generic over `R: F64s`.
//!
//! # Writing a kernel
//!
//! Write the body once, generic over the registers, `#[inline(always)]`:
//!
//! ```ignore
//! #[inline(always)]
//! fn axpy<R: F64s>(a: f64, x: &[f64; LANES], y: &mut [f64; LANES]) {
//!     for h in (0..LANES).step_by(R::W) {
//!         R::splat(a).mul(R::load(&x[h..])).add(R::load(&y[h..])).store(&mut y[h..]);
//!     }
//! }
//! ```
//!
//! and give it a [`Kernel`] (its inputs as fields, `run::<R>` calling the body), run by
//! [`dispatch`]`(level, kernel)`. With `R = f64` the same body is the scalar reference, one
//! sample wide (as `dynamics::batch::rnea_lanes` with `W = 1` serves the per-sample RNEA).
//!
//! A kernel that needs no register type (fixed-length `[f64; W]` loops that the compiler
//! vectorises by itself, as RNEA's and the tool FK's) runs through [`run`]`(level,
//! #[inline(always)] || body)`, which compiles the closure for the level's instruction set
//! the same way. [`with_rounding`] does it for SSE4.1 (`floor`, `ceil`, `round` as
//! instructions: the limit fit).
//!
//! # How dispatch works
//!
//! [`dispatch`] and [`run`] match on the [`Level`] and call a generic wrapper marked
//! `#[target_feature(enable = "avx512f")]` (or `"avx2,fma"`), monomorphised per kernel; the
//! kernel's `#[inline(always)]` body is inlined into it and compiled for that instruction
//! set. The CPU check (`is_x86_feature_detected!`, a cached bit test) is made per call, next to
//! the only `unsafe` calls of the wrappers. The baseline (SSE2, and [`Level::Scalar`] for the
//! kernels that have no per-sample form of their own) needs no wrapper.
//!
//! # Why hand-written, not a crate
//!
//! The kernels need few operations (no gathers, no shuffles beyond one transpose), but
//! specific ones: the selects must be the IEEE ones nalgebra and parry run, `f64::max`'s NaN
//! rule, comparisons straight to bit masks. `wide` fixes the lane width at compile time (no
//! runtime dispatch). `multiversion` dispatches one function by CPU features, but it clones a
//! function per target rather than handing the body a register type, so the lane width would
//! still be one fixed array length, and the register-carried kernels (the FK re-check, the
//! collision lanes) need the register type. `pulp` does hand one over, with its own
//! operation set and a dependency; the ~300 lines of `reg.rs` and `dispatch.rs` are the
//! whole of it here, and keep the exact IEEE semantics in view.
//!
//! # Same results on every path
//!
//! Rust never contracts `a * b + c` into a fused multiply-add on its own, and every kernel
//! performs, lane by lane, exactly the operations of the scalar code in the same order, so
//! the batched results are **bit-identical** to the scalar path's on every level (tested:
//! `tests/simd.rs`); the stated tolerance of the SIMD paths against the scalar one is 0.
//! Results are therefore also the same for any thread count and any machine.
//!
//! # Forcing a path
//!
//! The environment variable `PRINTWATT_SIMD` (read once, at the first use) chooses the level:
//! `scalar` (the per-sample code, no batching), `sse2`, `avx2`, `avx512`, or `auto` (the
//! default: the best the CPU has). A level the CPU lacks, or an unknown value, means `auto`.
//! [`set_level`] does the same from code (benchmarks and tests use it to measure and compare
//! the paths in one process).

mod dispatch;
mod reg;
mod transpose;

pub(crate) use dispatch::{dispatch, run, with_rounding, Kernel};
pub(crate) use reg::F64s;
pub use reg::V;
pub(crate) use transpose::push_transposed;

use std::sync::atomic::{AtomicU8, Ordering};

/// Samples per batch: one AVX-512 register of `f64`, two AVX2 registers, four SSE2 ones.
pub const LANES: usize = 8;

/// An instruction-set level of the batched kernels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Level {
    /// No batching: the per-sample scalar code (the reference).
    Scalar,
    /// Batches of [`LANES`] samples in baseline x86-64 (SSE2) or the target's baseline.
    Sse2,
    /// Batches compiled for AVX2 + FMA (x86-64 only; FMA is not used for contraction).
    Avx2,
    /// Batches compiled for AVX-512F (x86-64 only).
    Avx512,
}

impl Level {
    /// Every level, from the reference up.
    pub const ALL: [Level; 4] = [Level::Scalar, Level::Sse2, Level::Avx2, Level::Avx512];

    /// The name `PRINTWATT_SIMD` accepts.
    pub fn name(self) -> &'static str {
        match self {
            Level::Scalar => "scalar",
            Level::Sse2 => "sse2",
            Level::Avx2 => "avx2",
            Level::Avx512 => "avx512",
        }
    }

    /// The level of a name (`scalar`, `sse2`, `avx2`, `avx512`), `None` for anything else.
    pub fn from_name(s: &str) -> Option<Level> {
        Level::ALL.into_iter().find(|l| l.name() == s)
    }

    fn code(self) -> u8 {
        match self {
            Level::Scalar => 1,
            Level::Sse2 => 2,
            Level::Avx2 => 3,
            Level::Avx512 => 4,
        }
    }

    fn of_code(c: u8) -> Level {
        match c {
            1 => Level::Scalar,
            2 => Level::Sse2,
            3 => Level::Avx2,
            _ => Level::Avx512,
        }
    }

    /// Whether this CPU can run the level. Inlined: the dispatches ask it once per batch, and
    /// as a call it cost about 20 instructions each time (about 5 per sample on AVX2).
    #[inline]
    pub fn available(self) -> bool {
        match self {
            Level::Scalar | Level::Sse2 => true,
            #[cfg(target_arch = "x86_64")]
            Level::Avx2 => is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma"),
            #[cfg(target_arch = "x86_64")]
            Level::Avx512 => is_x86_feature_detected!("avx512f"),
            #[cfg(not(target_arch = "x86_64"))]
            Level::Avx2 | Level::Avx512 => false,
        }
    }
}

/// 0: not chosen yet; else [`Level::code`].
static LEVEL: AtomicU8 = AtomicU8::new(0);

/// The best level this CPU runs.
pub fn detected() -> Level {
    [Level::Avx512, Level::Avx2]
        .into_iter()
        .find(|l| l.available())
        .unwrap_or(Level::Sse2)
}

/// The level in force (process-wide): [`set_level`]'s, else `PRINTWATT_SIMD`'s, else
/// [`detected`].
#[inline]
pub fn level() -> Level {
    match LEVEL.load(Ordering::Relaxed) {
        0 => {
            let l = std::env::var("PRINTWATT_SIMD")
                .ok()
                .and_then(|s| Level::from_name(s.trim()))
                .filter(|l| l.available())
                .unwrap_or_else(detected);
            LEVEL.store(l.code(), Ordering::Relaxed);
            l
        }
        c => Level::of_code(c),
    }
}

/// Choose the level process-wide (benchmarks, A/B tests). A level this CPU lacks is refused:
/// the level in force is kept and `false` returned.
pub fn set_level(l: Level) -> bool {
    if !l.available() {
        return false;
    }
    LEVEL.store(l.code(), Ordering::Relaxed);
    true
}
