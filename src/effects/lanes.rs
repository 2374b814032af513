//! Torque effects over lanes of samples: the batched form of [`Effect::add_torque`] that the
//! energy model's lockstep pass calls ([`crate::energy`]), with a one-sample default.
//!
//! [`LANES`] samples sit side by side, joint-major (`q[j][lane]`). An effect that overrides
//! [`Effect::add_torque_lanes`] writes plain `[f64; LANES]` loops performing, lane by lane,
//! exactly the operations of its [`Effect::add_torque`] in the same order (branches become
//! selects), so every lane is bit-identical to the one-sample path ([`on_level`] is the hook
//! for the instruction set the pass runs on, [`crate::simd`]). An effect that does not
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

/// Run an effect's batched loops `f` for the instruction set `level` the energy pass runs on.
/// Today `f` runs as compiled for the baseline (the same bits on every level: no
/// contraction); generic `#[target_feature]` wrappers around the closure made the release
/// build's test binaries fail to link (duplicate symbols of its monomorphised iterators), so
/// the level is the hook for per-level code, not yet used.
#[inline(always)]
pub fn on_level(level: Level, f: impl FnOnce()) {
    let _ = level;
    f()
}
