//! The benches' clocks: this thread's CPU time, the core clock and the core's vector FMA
//! rate, shared by `benches/placement.rs`, `benches/energy_pass.rs` and
//! `benches/optimise.rs`.
#![allow(dead_code)] // each bench uses a subset

use std::hint::black_box;

/// This thread's time on a CPU, ns (`clock_gettime(CLOCK_THREAD_CPUTIME_ID)`), so that the
/// single-thread figures do not count the time other processes hold the CPU (the scheduler's
/// `/proc/thread-self/schedstat` is only updated at ticks: too coarse for a few ms).
pub fn thread_ns() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the clock id is a constant the call accepts.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed");
    ts.tv_sec as f64 * 1e9 + ts.tv_nsec as f64
}

/// This thread's time on a CPU, s ([`thread_ns`]).
pub fn thread_s() -> f64 {
    thread_ns() * 1e-9
}

/// Latency of a 64-bit `imul r64, r64`, cycles: 3 on current x86-64 cores (Intel's and
/// AMD's Zen family; Agner Fog's tables, uops.info). A chain of `add reg, 1`, which this
/// clock used before, is not one cycle per add everywhere: some recent cores run several
/// such dependent adds of an immediate per cycle (an Intel Xeon timed it at 20.9 "GHz").
/// A dependent multiply is not shortcut that way.
const IMUL_LATENCY_CYCLES: f64 = 3.0;

/// The core clock, GHz: a chain of `iters` dependent integer multiplies
/// ([`IMUL_LATENCY_CYCLES`] each), timed on this thread's CPU clock; the best of three runs
/// (a run interrupted by another process only looks slower).
pub fn clock_ghz(iters: u64) -> f64 {
    (0..3).map(|_| clock_once(iters)).fold(0.0, f64::max)
}

fn clock_once(iters: u64) -> f64 {
    let t0 = thread_ns();
    let mut x: u64 = black_box(3);
    #[cfg(target_arch = "x86_64")]
    for _ in 0..iters / 8 {
        // SAFETY: register-only arithmetic.
        unsafe {
            std::arch::asm!(
                "imul {0}, {0}", "imul {0}, {0}", "imul {0}, {0}", "imul {0}, {0}",
                "imul {0}, {0}", "imul {0}, {0}", "imul {0}, {0}", "imul {0}, {0}",
                inout(reg) x,
                options(nomem, nostack, pure)
            );
        }
    }
    black_box(x);
    (iters / 8 * 8) as f64 * IMUL_LATENCY_CYCLES / (thread_ns() - t0)
}

/// The vector FMA rate of one core, measured: 12 independent chains of `vfmadd231pd` (more
/// than latency × pipes on current cores, so the pipes, not the chains, limit it) on the
/// widest `f64` registers the CPU has, timed on this thread's CPU clock and turned into
/// cycles by `ghz` ([`clock_ghz`]). `None` without AVX2 + FMA.
#[derive(Clone, Copy, Debug)]
pub struct FmaRate {
    /// `f64` lanes per register (8: AVX-512, 4: AVX2).
    pub lanes: usize,
    /// Vector FMAs issued per cycle (2 on cores with two FMA pipes).
    pub per_cycle: f64,
}

impl FmaRate {
    /// Flops per cycle at this rate, an FMA counted as two (a multiply and an add): also the
    /// rate of separate multiplies and adds on cores whose adders match their FMA pipes.
    pub fn flops_per_cycle(&self) -> f64 {
        2.0 * self.lanes as f64 * self.per_cycle
    }
}

/// [`FmaRate`] of this core at the clock `ghz`, the best of three runs of `iters` loop
/// passes (12 FMAs each).
pub fn fma_rate(iters: u64, ghz: f64) -> Option<FmaRate> {
    #[cfg(target_arch = "x86_64")]
    {
        let (lanes, run): (usize, fn(u64)) = if std::is_x86_feature_detected!("avx512f") {
            // SAFETY (of the call below): the CPU has AVX-512F (checked here).
            (8, |n| unsafe { fma_chains_512(n) })
        } else if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
            // SAFETY (of the call below): the CPU has AVX and FMA (checked here).
            (4, |n| unsafe { fma_chains_256(n) })
        } else {
            return None;
        };
        let best_ns = (0..3)
            .map(|_| {
                let t0 = thread_ns();
                run(black_box(iters));
                thread_ns() - t0
            })
            .fold(f64::INFINITY, f64::min);
        let cycles = best_ns * ghz;
        Some(FmaRate {
            lanes,
            per_cycle: (iters * 12) as f64 / cycles,
        })
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (iters, ghz);
        None
    }
}

/// `iters` passes of 12 independent `vfmadd231pd` on `zmm0..zmm11` (from zero: no
/// denormals).
///
/// # Safety
/// The CPU has AVX-512F.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn fma_chains_512(iters: u64) {
    if iters == 0 {
        return;
    }
    // SAFETY: register-only arithmetic on registers declared clobbered; AVX-512F (the
    // caller's contract).
    unsafe {
        std::arch::asm!(
            "vxorpd zmm0, zmm0, zmm0", "vxorpd zmm1, zmm1, zmm1", "vxorpd zmm2, zmm2, zmm2",
            "vxorpd zmm3, zmm3, zmm3", "vxorpd zmm4, zmm4, zmm4", "vxorpd zmm5, zmm5, zmm5",
            "vxorpd zmm6, zmm6, zmm6", "vxorpd zmm7, zmm7, zmm7", "vxorpd zmm8, zmm8, zmm8",
            "vxorpd zmm9, zmm9, zmm9", "vxorpd zmm10, zmm10, zmm10", "vxorpd zmm11, zmm11, zmm11",
            "vxorpd zmm12, zmm12, zmm12", "vxorpd zmm13, zmm13, zmm13",
            "2:",
            "vfmadd231pd zmm0, zmm12, zmm13", "vfmadd231pd zmm1, zmm12, zmm13",
            "vfmadd231pd zmm2, zmm12, zmm13", "vfmadd231pd zmm3, zmm12, zmm13",
            "vfmadd231pd zmm4, zmm12, zmm13", "vfmadd231pd zmm5, zmm12, zmm13",
            "vfmadd231pd zmm6, zmm12, zmm13", "vfmadd231pd zmm7, zmm12, zmm13",
            "vfmadd231pd zmm8, zmm12, zmm13", "vfmadd231pd zmm9, zmm12, zmm13",
            "vfmadd231pd zmm10, zmm12, zmm13", "vfmadd231pd zmm11, zmm12, zmm13",
            "dec {n}",
            "jnz 2b",
            n = inout(reg) iters => _,
            out("zmm0") _, out("zmm1") _, out("zmm2") _, out("zmm3") _, out("zmm4") _,
            out("zmm5") _, out("zmm6") _, out("zmm7") _, out("zmm8") _, out("zmm9") _,
            out("zmm10") _, out("zmm11") _, out("zmm12") _, out("zmm13") _,
            options(nomem, nostack),
        );
    }
}

/// As [`fma_chains_512`] on `ymm0..ymm11`.
///
/// # Safety
/// The CPU has AVX and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,fma")]
unsafe fn fma_chains_256(iters: u64) {
    if iters == 0 {
        return;
    }
    // SAFETY: register-only arithmetic on registers declared clobbered; AVX and FMA (the
    // caller's contract).
    unsafe {
        std::arch::asm!(
            "vxorpd ymm0, ymm0, ymm0", "vxorpd ymm1, ymm1, ymm1", "vxorpd ymm2, ymm2, ymm2",
            "vxorpd ymm3, ymm3, ymm3", "vxorpd ymm4, ymm4, ymm4", "vxorpd ymm5, ymm5, ymm5",
            "vxorpd ymm6, ymm6, ymm6", "vxorpd ymm7, ymm7, ymm7", "vxorpd ymm8, ymm8, ymm8",
            "vxorpd ymm9, ymm9, ymm9", "vxorpd ymm10, ymm10, ymm10", "vxorpd ymm11, ymm11, ymm11",
            "vxorpd ymm12, ymm12, ymm12", "vxorpd ymm13, ymm13, ymm13",
            "2:",
            "vfmadd231pd ymm0, ymm12, ymm13", "vfmadd231pd ymm1, ymm12, ymm13",
            "vfmadd231pd ymm2, ymm12, ymm13", "vfmadd231pd ymm3, ymm12, ymm13",
            "vfmadd231pd ymm4, ymm12, ymm13", "vfmadd231pd ymm5, ymm12, ymm13",
            "vfmadd231pd ymm6, ymm12, ymm13", "vfmadd231pd ymm7, ymm12, ymm13",
            "vfmadd231pd ymm8, ymm12, ymm13", "vfmadd231pd ymm9, ymm12, ymm13",
            "vfmadd231pd ymm10, ymm12, ymm13", "vfmadd231pd ymm11, ymm12, ymm13",
            "dec {n}",
            "jnz 2b",
            n = inout(reg) iters => _,
            out("ymm0") _, out("ymm1") _, out("ymm2") _, out("ymm3") _, out("ymm4") _,
            out("ymm5") _, out("ymm6") _, out("ymm7") _, out("ymm8") _, out("ymm9") _,
            out("ymm10") _, out("ymm11") _, out("ymm12") _, out("ymm13") _,
            options(nomem, nostack),
        );
    }
}
