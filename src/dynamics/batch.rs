//! RNEA of [`LANES`] samples in lockstep, structure of arrays (issue 12 item 3).
//!
//! Each sample of a batch is computed with exactly the scalar [`super::rnea_with_sincos`]'s
//! operations in the same order (nalgebra's `M3 * V3` is `(m₀₀x + m₀₁y) + m₀₂z` row by row,
//! `M3ᵀ * V3` the same by columns, `a × b` the textbook formula), without fused
//! multiply-adds, so the torques are bit-identical to the scalar path's on every
//! [`crate::simd::Level`]; the lanes only change how many samples one instruction serves.
//! The rotation `R_i = C_i Rz(q_i)` keeps its constant third column as a scalar.
//!
//! Limitations: revolute joints only ([`DynModel::batchable`]); a model with a prismatic
//! joint is evaluated sample by sample by the callers.

use super::rnea::DynModel;
use super::MAX_DOF;
use crate::math::{M3, V3};
use crate::simd::{Level, LANES};

/// One value per lane.
pub type Lanes = [f64; LANES];

/// Joint states of [`LANES`] samples, joint-major (`s[j][lane]`): `sin q_j`, `cos q_j`
/// (dimensionless), `q̇_j` rad/s, `q̈_j` rad/s². Lanes beyond the samples in use may hold
/// anything finite; their results are not meant to be read.
#[derive(Clone, Copy, Debug)]
pub struct StateBatch {
    /// `sin q_j`.
    pub s: [Lanes; MAX_DOF],
    /// `cos q_j`.
    pub c: [Lanes; MAX_DOF],
    /// `q̇_j`, rad/s.
    pub qd: [Lanes; MAX_DOF],
    /// `q̈_j`, rad/s².
    pub qdd: [Lanes; MAX_DOF],
}

impl Default for StateBatch {
    fn default() -> Self {
        StateBatch {
            s: [[0.0; LANES]; MAX_DOF],
            c: [[1.0; LANES]; MAX_DOF],
            qd: [[0.0; LANES]; MAX_DOF],
            qdd: [[0.0; LANES]; MAX_DOF],
        }
    }
}

impl StateBatch {
    /// Put one sample into `lane`: `sincos` as [`super::rnea_with_sincos`] takes it (the
    /// sines then the cosines of the `n` joints), `qd`, `qdd` of length `n`.
    #[inline]
    pub fn set(&mut self, lane: usize, n: usize, sincos: &[f64], qd: &[f64], qdd: &[f64]) {
        for j in 0..n {
            self.s[j][lane] = sincos[j];
            self.c[j][lane] = sincos[n + j];
            self.qd[j][lane] = qd[j];
            self.qdd[j][lane] = qdd[j];
        }
    }
}

macro_rules! lanes {
    ($l:ident => $e:expr) => {{
        let mut r = [0.0f64; LANES];
        for $l in 0..LANES {
            r[$l] = $e;
        }
        r
    }};
}

/// A 3-vector per lane.
#[derive(Clone, Copy)]
struct VL {
    x: Lanes,
    y: Lanes,
    z: Lanes,
}

impl VL {
    #[inline(always)]
    fn splat(v: &V3) -> VL {
        VL {
            x: [v.x; LANES],
            y: [v.y; LANES],
            z: [v.z; LANES],
        }
    }
    #[inline(always)]
    fn add(&self, o: &VL) -> VL {
        VL {
            x: lanes!(l => self.x[l] + o.x[l]),
            y: lanes!(l => self.y[l] + o.y[l]),
            z: lanes!(l => self.z[l] + o.z[l]),
        }
    }
    #[inline(always)]
    fn scale(&self, s: f64) -> VL {
        VL {
            x: lanes!(l => self.x[l] * s),
            y: lanes!(l => self.y[l] * s),
            z: lanes!(l => self.z[l] * s),
        }
    }
    /// `self × b`, `b` the same in every lane.
    #[inline(always)]
    fn cross_c(&self, b: &V3) -> VL {
        VL {
            x: lanes!(l => self.y[l] * b.z - self.z[l] * b.y),
            y: lanes!(l => self.z[l] * b.x - self.x[l] * b.z),
            z: lanes!(l => self.x[l] * b.y - self.y[l] * b.x),
        }
    }
    /// `a × self`, `a` the same in every lane.
    #[inline(always)]
    fn c_cross(a: &V3, b: &VL) -> VL {
        VL {
            x: lanes!(l => a.y * b.z[l] - a.z * b.y[l]),
            y: lanes!(l => a.z * b.x[l] - a.x * b.z[l]),
            z: lanes!(l => a.x * b.y[l] - a.y * b.x[l]),
        }
    }
    #[inline(always)]
    fn cross(&self, b: &VL) -> VL {
        VL {
            x: lanes!(l => self.y[l] * b.z[l] - self.z[l] * b.y[l]),
            y: lanes!(l => self.z[l] * b.x[l] - self.x[l] * b.z[l]),
            z: lanes!(l => self.x[l] * b.y[l] - self.y[l] * b.x[l]),
        }
    }
    /// `M v` with a constant `M` (nalgebra's order: `(m₀ x + m₁ y) + m₂ z` per row).
    #[inline(always)]
    fn c_mul(m: &M3, v: &VL) -> VL {
        let row = |r: usize| {
            let (a, b, c) = (m[(r, 0)], m[(r, 1)], m[(r, 2)]);
            lanes!(l => (a * v.x[l] + b * v.y[l]) + c * v.z[l])
        };
        VL {
            x: row(0),
            y: row(1),
            z: row(2),
        }
    }
}

/// The rotation `R = C Rz(q)` per lane: columns 0 and 1 vary, column 2 is `C`'s.
#[derive(Clone, Copy)]
struct RL {
    c0: VL,
    c1: VL,
    c2: V3,
}

impl RL {
    /// `Rᵀ v` (nalgebra's `tr_mul`: column `j` dotted with `v`, `(r₀ x + r₁ y) + r₂ z`).
    #[inline(always)]
    fn tr_mul(&self, v: &VL) -> VL {
        let (c0, c1, c2) = (&self.c0, &self.c1, &self.c2);
        VL {
            x: lanes!(l => (c0.x[l] * v.x[l] + c0.y[l] * v.y[l]) + c0.z[l] * v.z[l]),
            y: lanes!(l => (c1.x[l] * v.x[l] + c1.y[l] * v.y[l]) + c1.z[l] * v.z[l]),
            z: lanes!(l => (c2.x * v.x[l] + c2.y * v.y[l]) + c2.z * v.z[l]),
        }
    }
    /// `R v` (row by row, `(r₀ x + r₁ y) + r₂ z`).
    #[inline(always)]
    fn mul(&self, v: &VL) -> VL {
        let (c0, c1, c2) = (&self.c0, &self.c1, &self.c2);
        VL {
            x: lanes!(l => (c0.x[l] * v.x[l] + c1.x[l] * v.y[l]) + c2.x * v.z[l]),
            y: lanes!(l => (c0.y[l] * v.x[l] + c1.y[l] * v.y[l]) + c2.y * v.z[l]),
            z: lanes!(l => (c0.z[l] * v.x[l] + c1.z[l] * v.y[l]) + c2.z * v.z[l]),
        }
    }
}

/// The kernel's per-link intermediates (rotations, forces, moments), kept from batch to batch
/// by a caller that runs many: each is written before it is read, so nothing is cleared per
/// batch (callgrind counted their zeroing at up to ~3,500 instructions a batch in `memset`s).
#[derive(Clone, Copy)]
pub(crate) struct RneaScratch {
    rot: [RL; MAX_DOF],
    f: [VL; MAX_DOF],
    nn: [VL; MAX_DOF],
}

impl Default for RneaScratch {
    fn default() -> Self {
        let zero = VL::splat(&V3::zeros());
        RneaScratch {
            rot: [RL {
                c0: zero,
                c1: zero,
                c2: V3::zeros(),
            }; MAX_DOF],
            f: [zero; MAX_DOF],
            nn: [zero; MAX_DOF],
        }
    }
}

impl std::fmt::Debug for RneaScratch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("RneaScratch")
    }
}

/// The kernel: every operation of `rnea_core` (revolute joints) per lane, same order (inlined
/// into its caller, so it runs on the caller's instruction set; [`rnea_batch`] dispatches).
#[inline(always)]
pub(crate) fn rnea_lanes(
    m: &DynModel,
    b: &StateBatch,
    tau: &mut [Lanes; MAX_DOF],
    sc: &mut RneaScratch,
) {
    let n = m.n;
    let zero = VL::splat(&V3::zeros());
    let RneaScratch { rot, f, nn } = sc;
    let mut wp = zero;
    let mut wdp = zero;
    let mut ap = VL::splat(&m.a0);
    for i in 0..n {
        let lk = &m.links[i];
        let (s, c) = (&b.s[i], &b.c[i]);
        let (k0, k1) = (lk.c.column(0), lk.c.column(1));
        // Columns of C Rz(q): c0 c + c1 s and c1 c − c0 s.
        let r = RL {
            c0: VL {
                x: lanes!(l => k0.x * c[l] + k1.x * s[l]),
                y: lanes!(l => k0.y * c[l] + k1.y * s[l]),
                z: lanes!(l => k0.z * c[l] + k1.z * s[l]),
            },
            c1: VL {
                x: lanes!(l => k1.x * c[l] - k0.x * s[l]),
                y: lanes!(l => k1.y * c[l] - k0.y * s[l]),
                z: lanes!(l => k1.z * c[l] - k0.z * s[l]),
            },
            c2: lk.c.column(2).into_owned(),
        };
        let (qd, qdd) = (&b.qd[i], &b.qdd[i]);
        // link_motion, revolute.
        let a_origin = ap
            .add(&wdp.cross_c(&lk.p))
            .add(&wp.cross(&wp.cross_c(&lk.p)));
        let wpl = r.tr_mul(&wp);
        let mut w = wpl;
        w.z = lanes!(l => w.z[l] + qd[l]);
        let wdt = r.tr_mul(&wdp);
        let wd = VL {
            x: lanes!(l => wdt.x[l] + wpl.y[l] * qd[l]),
            y: lanes!(l => wdt.y[l] + (-wpl.x[l]) * qd[l]),
            z: lanes!(l => (wdt.z[l] + 0.0 * qd[l]) + qdd[l]),
        };
        let a = r.tr_mul(&a_origin);
        let iw = VL::c_mul(&lk.io, &w);
        f[i] = a
            .scale(lk.mass)
            .add(&wd.cross_c(&lk.h))
            .add(&w.cross(&w.cross_c(&lk.h)));
        nn[i] = VL::c_mul(&lk.io, &wd)
            .add(&w.cross(&iw))
            .add(&VL::c_cross(&lk.h, &a));
        wp = w;
        wdp = wd;
        ap = a;
        rot[i] = r;
    }
    for i in (0..n).rev() {
        let lk = &m.links[i];
        let arm = lk.armature;
        let (t, qdd) = (&nn[i].z, &b.qdd[i]);
        tau[i] = lanes!(l => t[l] + arm * qdd[l]);
        if i > 0 {
            let r = &rot[i];
            let fp = r.mul(&f[i]);
            let np = r.mul(&nn[i]).add(&VL::c_cross(&lk.p, &fp));
            f[i - 1] = f[i - 1].add(&fp);
            nn[i - 1] = nn[i - 1].add(&np);
        }
    }
}

fn rnea_sse2(m: &DynModel, b: &StateBatch, tau: &mut [Lanes; MAX_DOF]) {
    rnea_lanes(m, b, tau, &mut RneaScratch::default())
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn rnea_avx2(m: &DynModel, b: &StateBatch, tau: &mut [Lanes; MAX_DOF]) {
    rnea_lanes(m, b, tau, &mut RneaScratch::default())
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn rnea_avx512(m: &DynModel, b: &StateBatch, tau: &mut [Lanes; MAX_DOF]) {
    rnea_lanes(m, b, tau, &mut RneaScratch::default())
}

/// Joint torques `tau[j][lane]` (N·m) of the [`LANES`] samples of `b` by RNEA
/// (`τ = M(q) q̈ + C(q, q̇) q̇ + G(q)`, plus the armature when the model has it), with the
/// instruction set `level` ([`Level::Scalar`] runs the baseline build of the same kernel).
/// Bit-identical, lane by lane, to [`super::rnea_with_sincos`] of each sample. A `level`
/// this CPU lacks runs the baseline build. Only for a [`DynModel::batchable`] model
/// (revolute joints); for others the result is unspecified.
pub fn rnea_batch(m: &DynModel, b: &StateBatch, tau: &mut [Lanes; MAX_DOF], level: Level) {
    match level {
        #[cfg(target_arch = "x86_64")]
        Level::Avx512 if Level::Avx512.available() => {
            // SAFETY: the CPU has AVX-512F (checked just above).
            unsafe { rnea_avx512(m, b, tau) }
        }
        #[cfg(target_arch = "x86_64")]
        Level::Avx2 if Level::Avx2.available() => {
            // SAFETY: the CPU has AVX2 and FMA (checked just above).
            unsafe { rnea_avx2(m, b, tau) }
        }
        _ => rnea_sse2(m, b, tau),
    }
}
