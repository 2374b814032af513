//! Torque effects over lanes of samples: the batched form of [`Effect::add_torque`] that the
//! energy model's lockstep pass calls ([`crate::energy`]), with a one-sample default.
//!
//! [`LANES`] samples sit side by side, joint-major (`q[j][lane]`). An effect that overrides
//! [`Effect::add_torque_lanes`] writes plain `[f64; LANES]` loops performing, lane by lane,
//! exactly the operations of its [`Effect::add_torque`] in the same order (branches become
//! selects), so every lane is bit-identical to the one-sample path; [`on_level`] compiles such
//! a body for the instruction set the pass runs on ([`crate::simd`]). An effect that does not
//! override it is called sample by sample (the default), which is bit-identical by
//! construction.

use super::Effect;
use crate::simd::{Level, LANES};

/// One joint quantity of [`LANES`] samples (one value a lane).
pub type Lanes = [f64; LANES];

/// The state of [`LANES`] samples, joint-major: `q[j][lane]` rad, `qd` rad/s, `qdd` rad/s²;
/// the first `n` joints are meaningful. `q` holds only the joints the effects read
/// ([`Effect::angles_read`]); the others are not meant to be read.
#[derive(Clone, Copy, Debug)]
pub struct LaneState<'a> {
    /// Number of joints.
    pub n: usize,
    /// Joint angles, rad.
    pub q: &'a [Lanes],
    /// Joint velocities, rad/s.
    pub qd: &'a [Lanes],
    /// Joint accelerations, rad/s².
    pub qdd: &'a [Lanes],
}

/// The default of [`Effect::add_torque_lanes`]: [`Effect::add_torque`] sample by sample.
#[allow(clippy::needless_range_loop)] // parallel lanes, indexed by joint and lane
pub(crate) fn add_torque_per_lane<E: Effect + ?Sized>(e: &E, x: &LaneState<'_>, tau: &mut [Lanes]) {
    const M: usize = crate::dynamics::MAX_DOF;
    let n = x.n.min(M);
    for l in 0..LANES {
        let (mut a, mut v, mut w, mut t) = ([0.0; M], [0.0; M], [0.0; M], [0.0; M]);
        for j in 0..n {
            a[j] = x.q[j][l];
            v[j] = x.qd[j][l];
            w[j] = x.qdd[j][l];
            t[j] = tau[j][l];
        }
        e.add_torque(&a[..n], &v[..n], &w[..n], &mut t[..n]);
        for j in 0..n {
            tau[j][l] = t[j];
        }
    }
}

/// Run `f` compiled for `level` (AVX2 + FMA, AVX-512F, else the baseline): the batched
/// torque of an effect is called through the trait, out of the pass's own compiled body, and
/// gets its instruction set here. The same bits on every level (no contraction).
#[inline(always)]
pub fn on_level(level: Level, f: impl FnOnce()) {
    match level {
        #[cfg(target_arch = "x86_64")]
        Level::Avx512 if Level::Avx512.available() => {
            // SAFETY: the CPU has AVX-512F (checked just above).
            unsafe { run_avx512(f) }
        }
        #[cfg(target_arch = "x86_64")]
        Level::Avx2 if Level::Avx2.available() => {
            // SAFETY: the CPU has AVX2 and FMA (checked just above).
            unsafe { run_avx2(f) }
        }
        _ => f(),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn run_avx2(f: impl FnOnce()) {
    f()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn run_avx512(f: impl FnOnce()) {
    f()
}
