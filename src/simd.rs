//! Runtime choice of the instruction set for the per-sample kernels that run several samples
//! in lockstep (issue 12 item 3: the IK's closed form and FK re-check while tracking, RNEA and
//! the balancer in the energy pass): structure-of-arrays batches of [`LANES`] samples, written
//! as plain `[f64; LANES]` loops that LLVM turns into vector instructions, compiled three
//! times (baseline x86-64 SSE2, AVX2 + FMA, AVX-512F) and chosen once per process by
//! [`level`].
//!
//! # Why plain arrays and `#[target_feature]`, not a SIMD crate
//!
//! The kernels are straight-line arithmetic over 8 lanes (no shuffles, no gathers; the
//! transcendentals `sin_cos`, `atan2`, `acos` are fdlibm's kernels per lane with their
//! branches turned into selects, [`crate::fastmath::sin_cos_lanes`] and friends), which LLVM
//! vectorises completely from fixed-length loops; `#[target_feature(enable = …)]` wrappers around one
//! `#[inline(always)]` generic body give the AVX2 and AVX-512 code with runtime dispatch by
//! `is_x86_feature_detected!` and no dependency. `wide` would fix the lane width at compile
//! time (no runtime dispatch), `pulp`/`multiversion` add a dependency for what three
//! ten-line wrappers do here.
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
