//! The benches' clocks: this thread's CPU time and the core clock, shared by
//! `benches/placement.rs`, `benches/energy_pass.rs` and `benches/optimise.rs`.
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

/// The core clock, GHz: a chain of `iters` dependent integer adds, one cycle each on x86-64,
/// timed on this thread's CPU clock.
pub fn clock_ghz(iters: u64) -> f64 {
    let t0 = thread_ns();
    let mut x: u64 = black_box(1);
    #[cfg(target_arch = "x86_64")]
    for _ in 0..iters / 8 {
        // SAFETY: register-only arithmetic.
        unsafe {
            std::arch::asm!(
                "add {0}, 1", "add {0}, 1", "add {0}, 1", "add {0}, 1",
                "add {0}, 1", "add {0}, 1", "add {0}, 1", "add {0}, 1",
                inout(reg) x,
                options(nomem, nostack, pure)
            );
        }
    }
    black_box(x);
    iters as f64 / (thread_ns() - t0)
}
