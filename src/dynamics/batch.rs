//! RNEA of [`LANES`] samples in lockstep, structure of arrays.
//!
//! One kernel, [`rnea_lanes`], generic over the number of lanes `W`: the lockstep levels run
//! it with `W =` [`LANES`], and the scalar reference ([`super::rnea_with_sincos`], [`super::rnea`]
//! of a revolute model) runs the very same code with `W = 1`. Every lane therefore performs
//! the same operations in the same order (no fused multiply-adds: Rust never contracts), so
//! the torques are bit-identical on every [`crate::simd::Level`]; the lanes only change how
//! many samples one instruction serves.
//!
//! # Formulation
//!
//! The joint rotation is `R_i = C_i Rz(q_i)` with a constant `C_i` ([`super::DynModel`]).
//! `Rᵢᵀ v` is taken as `Rz(q)ᵀ (Cᵀ v)` and `R v` as `C (Rz(q) v)`: `Rz` costs four products
//! and two sums, and when `C_i` is a signed permutation (every joint of an arm whose axes and
//! fixed rotations are along the coordinate axes, as in the shipped robots; `DynModel::new`
//! snaps `C_i` onto one when it is within 1e-14 of it) `Cᵀ v` and `C v` are a compile-time
//! relabelling with sign changes, no arithmetic: the kernel is instantiated per link for the
//! 24 rotations among them ([`PERMS`]), a general `C` takes the dense 3×3 products. No
//! rotation matrix is built or stored. The base link starts from rest (`ω₀ = ω̇₀ = 0`,
//! gravity as the base acceleration), so link 0 needs only `nz₀` (its force is never
//! propagated) and link 1's parent velocities lie along its parent's z axis: those two are
//! written out with the zero terms left out. With an exact signed permutation these are the
//! textbook formulas' operations minus products with exact zeros, so the values equal the
//! dense formulation's except for the sign of a zero result (`x + (±0) = x` for `x ≠ 0`).
//!
//! Limitations: revolute joints only ([`DynModel::batchable`]); a model with a prismatic
//! joint is evaluated sample by sample by the callers with the dense formulation.

use super::rnea::{DynModel, Link};
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

/// A whole-lane expression over the `W` lanes in scope.
macro_rules! lanes {
    ($l:ident => $e:expr) => {{
        let mut r = [0.0f64; W];
        for $l in 0..W {
            r[$l] = $e;
        }
        r
    }};
}

/// A 3-vector per lane.
#[derive(Clone, Copy)]
pub(crate) struct VL<const W: usize> {
    x: [f64; W],
    y: [f64; W],
    z: [f64; W],
}

impl<const W: usize> VL<W> {
    #[inline(always)]
    fn zero() -> VL<W> {
        VL {
            x: [0.0; W],
            y: [0.0; W],
            z: [0.0; W],
        }
    }
    /// Component `i` (0, 1, 2).
    #[inline(always)]
    fn comp(&self, i: usize) -> [f64; W] {
        match i {
            0 => self.x,
            1 => self.y,
            _ => self.z,
        }
    }
    #[inline(always)]
    fn add(&self, o: &VL<W>) -> VL<W> {
        VL {
            x: lanes!(l => self.x[l] + o.x[l]),
            y: lanes!(l => self.y[l] + o.y[l]),
            z: lanes!(l => self.z[l] + o.z[l]),
        }
    }
    #[inline(always)]
    fn scale(&self, s: f64) -> VL<W> {
        VL {
            x: lanes!(l => self.x[l] * s),
            y: lanes!(l => self.y[l] * s),
            z: lanes!(l => self.z[l] * s),
        }
    }
    /// `self × b`, `b` the same in every lane.
    #[inline(always)]
    fn cross_c(&self, b: &V3) -> VL<W> {
        VL {
            x: lanes!(l => self.y[l] * b.z - self.z[l] * b.y),
            y: lanes!(l => self.z[l] * b.x - self.x[l] * b.z),
            z: lanes!(l => self.x[l] * b.y - self.y[l] * b.x),
        }
    }
    /// `a × self`, `a` the same in every lane.
    #[inline(always)]
    fn c_cross(a: &V3, b: &VL<W>) -> VL<W> {
        VL {
            x: lanes!(l => a.y * b.z[l] - a.z * b.y[l]),
            y: lanes!(l => a.z * b.x[l] - a.x * b.z[l]),
            z: lanes!(l => a.x * b.y[l] - a.y * b.x[l]),
        }
    }
    #[inline(always)]
    fn cross(&self, b: &VL<W>) -> VL<W> {
        VL {
            x: lanes!(l => self.y[l] * b.z[l] - self.z[l] * b.y[l]),
            y: lanes!(l => self.z[l] * b.x[l] - self.x[l] * b.z[l]),
            z: lanes!(l => self.x[l] * b.y[l] - self.y[l] * b.x[l]),
        }
    }
    /// `(a x + b y) + c z` per lane.
    #[inline(always)]
    fn dot_c(&self, a: f64, b: f64, c: f64) -> [f64; W] {
        lanes!(l => (a * self.x[l] + b * self.y[l]) + c * self.z[l])
    }
    /// `M v` with a constant `M` (nalgebra's order: `(m₀ x + m₁ y) + m₂ z` per row).
    #[inline(always)]
    fn c_mul(m: &M3, v: &VL<W>) -> VL<W> {
        VL {
            x: v.dot_c(m[(0, 0)], m[(0, 1)], m[(0, 2)]),
            y: v.dot_c(m[(1, 0)], m[(1, 1)], m[(1, 2)]),
            z: v.dot_c(m[(2, 0)], m[(2, 1)], m[(2, 2)]),
        }
    }
    /// `Mᵀ v` with a constant `M` (column `k` dotted with `v`, `(m₀ₖ x + m₁ₖ y) + m₂ₖ z`).
    #[inline(always)]
    fn c_tr_mul(m: &M3, v: &VL<W>) -> VL<W> {
        VL {
            x: v.dot_c(m[(0, 0)], m[(1, 0)], m[(2, 0)]),
            y: v.dot_c(m[(0, 1)], m[(1, 1)], m[(2, 1)]),
            z: v.dot_c(m[(0, 2)], m[(1, 2)], m[(2, 2)]),
        }
    }
}

/// `Rz(q)ᵀ u` per lane from `sin q`, `cos q`: `(c uₓ + s u_y, c u_y − s uₓ, u_z)`.
#[inline(always)]
fn rz_t<const W: usize>(s: &[f64; W], c: &[f64; W], u: &VL<W>) -> VL<W> {
    VL {
        x: lanes!(l => c[l] * u.x[l] + s[l] * u.y[l]),
        y: lanes!(l => c[l] * u.y[l] - s[l] * u.x[l]),
        z: u.z,
    }
}

/// `Rz(q) v` per lane: `(c vₓ − s v_y, s vₓ + c v_y, v_z)`.
#[inline(always)]
fn rz<const W: usize>(s: &[f64; W], c: &[f64; W], v: &VL<W>) -> VL<W> {
    VL {
        x: lanes!(l => c[l] * v.x[l] - s[l] * v.y[l]),
        y: lanes!(l => s[l] * v.x[l] + c[l] * v.y[l]),
        z: v.z,
    }
}

/// The constant rotation `C` of a joint, as the kernel applies it.
trait Fixed<const W: usize> {
    /// `Cᵀ v`.
    fn ct(&self, v: &VL<W>) -> VL<W>;
    /// `C v`.
    fn c(&self, v: &VL<W>) -> VL<W>;
}

/// A general `C`: dense 3×3 products.
struct Dense<'a>(&'a M3);

impl<const W: usize> Fixed<W> for Dense<'_> {
    #[inline(always)]
    fn ct(&self, v: &VL<W>) -> VL<W> {
        VL::c_tr_mul(self.0, v)
    }
    #[inline(always)]
    fn c(&self, v: &VL<W>) -> VL<W> {
        VL::c_mul(self.0, v)
    }
}

/// The 24 rotations that are signed permutations: `(p, s)` means column `k` of `C` is
/// `s[k] e_{p[k]}`.
pub(super) const PERMS: [([usize; 3], [i8; 3]); 24] = perms();

const fn perms() -> [([usize; 3], [i8; 3]); 24] {
    // The first three permutations are even, the last three odd.
    let ps = [
        [0, 1, 2],
        [1, 2, 0],
        [2, 0, 1],
        [0, 2, 1],
        [2, 1, 0],
        [1, 0, 2],
    ];
    let mut out = [([0usize; 3], [1i8; 3]); 24];
    let (mut k, mut i) = (0, 0);
    while i < 6 {
        let parity: i8 = if i < 3 { 1 } else { -1 };
        let mut m = 0;
        while m < 8 {
            let s: [i8; 3] = [
                if m & 1 == 0 { 1 } else { -1 },
                if m & 2 == 0 { 1 } else { -1 },
                if m & 4 == 0 { 1 } else { -1 },
            ];
            if parity * s[0] * s[1] * s[2] == 1 {
                out[k] = (ps[i], s);
                k += 1;
            }
            m += 1;
        }
        i += 1;
    }
    out
}

/// The index into [`PERMS`] of `c` when it is exactly a signed permutation.
pub(super) fn perm_of(c: &M3) -> Option<u8> {
    PERMS
        .iter()
        .position(|(p, s)| {
            (0..3).all(|k| {
                (0..3).all(|r| {
                    let want = if r == p[k] { f64::from(s[k]) } else { 0.0 };
                    c[(r, k)] == want
                })
            })
        })
        .map(|i| i as u8)
}

/// `C =` [`PERMS`]`[ID]`: relabelling with sign changes, resolved at compile time.
struct SignedPerm<const ID: usize>;

impl<const ID: usize> SignedPerm<ID> {
    const P: [usize; 3] = PERMS[ID].0;
    const S: [i8; 3] = PERMS[ID].1;
    /// The inverse permutation: `P[INV[r]] = r`.
    const INV: [usize; 3] = {
        let p = PERMS[ID].0;
        let mut q = [0usize; 3];
        let mut k = 0;
        while k < 3 {
            q[p[k]] = k;
            k += 1;
        }
        q
    };
}

/// `a` or `−a` by the constant sign `s`.
#[inline(always)]
fn signed<const W: usize>(s: i8, a: [f64; W]) -> [f64; W] {
    if s < 0 {
        lanes!(l => -a[l])
    } else {
        a
    }
}

impl<const ID: usize, const W: usize> Fixed<W> for SignedPerm<ID> {
    #[inline(always)]
    fn ct(&self, v: &VL<W>) -> VL<W> {
        // (Cᵀ v)_k = s_k v_{p_k}.
        let (p, s) = (Self::P, Self::S);
        VL {
            x: signed(s[0], v.comp(p[0])),
            y: signed(s[1], v.comp(p[1])),
            z: signed(s[2], v.comp(p[2])),
        }
    }
    #[inline(always)]
    fn c(&self, v: &VL<W>) -> VL<W> {
        // (C v)_{p_k} = s_k v_k: row r takes k = p⁻¹(r).
        let (q, s) = (Self::INV, Self::S);
        VL {
            x: signed(s[q[0]], v.comp(q[0])),
            y: signed(s[q[1]], v.comp(q[1])),
            z: signed(s[q[2]], v.comp(q[2])),
        }
    }
}

/// `$body` with `$f` the [`Fixed`] of link `$lk` (a [`SignedPerm`] instance per rotation,
/// else [`Dense`]).
macro_rules! with_fixed {
    ($lk:expr, |$f:ident| $body:expr) => {
        match $lk.perm {
            Some(0) => {
                let $f = SignedPerm::<0>;
                $body
            }
            Some(1) => {
                let $f = SignedPerm::<1>;
                $body
            }
            Some(2) => {
                let $f = SignedPerm::<2>;
                $body
            }
            Some(3) => {
                let $f = SignedPerm::<3>;
                $body
            }
            Some(4) => {
                let $f = SignedPerm::<4>;
                $body
            }
            Some(5) => {
                let $f = SignedPerm::<5>;
                $body
            }
            Some(6) => {
                let $f = SignedPerm::<6>;
                $body
            }
            Some(7) => {
                let $f = SignedPerm::<7>;
                $body
            }
            Some(8) => {
                let $f = SignedPerm::<8>;
                $body
            }
            Some(9) => {
                let $f = SignedPerm::<9>;
                $body
            }
            Some(10) => {
                let $f = SignedPerm::<10>;
                $body
            }
            Some(11) => {
                let $f = SignedPerm::<11>;
                $body
            }
            Some(12) => {
                let $f = SignedPerm::<12>;
                $body
            }
            Some(13) => {
                let $f = SignedPerm::<13>;
                $body
            }
            Some(14) => {
                let $f = SignedPerm::<14>;
                $body
            }
            Some(15) => {
                let $f = SignedPerm::<15>;
                $body
            }
            Some(16) => {
                let $f = SignedPerm::<16>;
                $body
            }
            Some(17) => {
                let $f = SignedPerm::<17>;
                $body
            }
            Some(18) => {
                let $f = SignedPerm::<18>;
                $body
            }
            Some(19) => {
                let $f = SignedPerm::<19>;
                $body
            }
            Some(20) => {
                let $f = SignedPerm::<20>;
                $body
            }
            Some(21) => {
                let $f = SignedPerm::<21>;
                $body
            }
            Some(22) => {
                let $f = SignedPerm::<22>;
                $body
            }
            Some(23) => {
                let $f = SignedPerm::<23>;
                $body
            }
            _ => {
                let $f = Dense(&$lk.c);
                $body
            }
        }
    };
}

/// The kernel's per-link forces and moments (links `1..n`), kept from batch to batch by a
/// caller that runs many: each is written before it is read, so nothing is cleared per batch
/// (callgrind counted their zeroing at up to ~3,500 instructions a batch in `memset`s).
#[derive(Clone, Copy)]
pub(crate) struct RneaScratch<const W: usize = LANES> {
    f: [VL<W>; MAX_DOF],
    nn: [VL<W>; MAX_DOF],
}

impl<const W: usize> Default for RneaScratch<W> {
    fn default() -> Self {
        RneaScratch {
            f: [VL::zero(); MAX_DOF],
            nn: [VL::zero(); MAX_DOF],
        }
    }
}

impl<const W: usize> std::fmt::Debug for RneaScratch<W> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("RneaScratch")
    }
}

/// One moving link `i ≥ 1` of the forward pass: its angular velocity, angular acceleration
/// and origin acceleration (rad/s, rad/s², m/s²) in its own frame from its parent's
/// (`wp`, `wdp`, and `a_origin`: the parent's acceleration carried to this joint's origin),
/// and its force and moment (N, N·m) about the joint origin.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn link_forward<const W: usize, F: Fixed<W>>(
    fx: &F,
    lk: &Link,
    s: &[f64; W],
    c: &[f64; W],
    qd: &[f64; W],
    qdd: &[f64; W],
    wp: &VL<W>,
    wdp: &VL<W>,
    a_origin: &VL<W>,
) -> (VL<W>, VL<W>, VL<W>, VL<W>, VL<W>) {
    let wpl = rz_t(s, c, &fx.ct(wp));
    let mut w = wpl;
    w.z = lanes!(l => w.z[l] + qd[l]);
    let wdt = rz_t(s, c, &fx.ct(wdp));
    let wd = VL {
        x: lanes!(l => wdt.x[l] + wpl.y[l] * qd[l]),
        y: lanes!(l => wdt.y[l] + (-wpl.x[l]) * qd[l]),
        z: lanes!(l => wdt.z[l] + qdd[l]),
    };
    let a = rz_t(s, c, &fx.ct(a_origin));
    let iw = VL::c_mul(&lk.io, &w);
    let f = a
        .scale(lk.mass)
        .add(&wd.cross_c(&lk.h))
        .add(&w.cross(&w.cross_c(&lk.h)));
    let nn = VL::c_mul(&lk.io, &wd)
        .add(&w.cross(&iw))
        .add(&VL::c_cross(&lk.h, &a));
    (w, wd, a, f, nn)
}

/// The kernel (revolute joints; see the module docs): joint torques `tau[j][lane]`, N·m, of
/// the states `s`, `c` (sines, cosines), `qd` (rad/s), `qdd` (rad/s²), joint-major. Inlined
/// into its caller, so it runs on the caller's instruction set; [`rnea_batch`] dispatches.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn rnea_lanes<const W: usize>(
    m: &DynModel,
    s: &[[f64; W]; MAX_DOF],
    c: &[[f64; W]; MAX_DOF],
    qd: &[[f64; W]; MAX_DOF],
    qdd: &[[f64; W]; MAX_DOF],
    tau: &mut [[f64; W]; MAX_DOF],
    sc: &mut RneaScratch<W>,
) {
    let n = m.n.min(MAX_DOF);
    if n == 0 {
        return;
    }
    let RneaScratch { f, nn } = sc;
    // Link 0, its parent at rest: ω = q̇₀ e_z, ω̇ = q̈₀ e_z, a = Rz(q₀)ᵀ (C₀ᵀ a₀). Only its
    // moment's z component is ever read: nz = I_zz q̈₀ + (h × a)_z.
    let l0 = &m.links[0];
    let u = m.a0_local;
    let (s0, c0) = (&s[0], &c[0]);
    let a0 = VL {
        x: lanes!(l => c0[l] * u.x + s0[l] * u.y),
        y: lanes!(l => c0[l] * u.y - s0[l] * u.x),
        z: [u.z; W],
    };
    let (izz, h0) = (l0.io[(2, 2)], l0.h);
    let mut nz0 = lanes!(l => izz * qdd[0][l] + (h0.x * a0.y[l] - h0.y * a0.x[l]));
    if n > 1 {
        // Link 1: the parent's ω, ω̇ along its z axis, so the origin's acceleration
        // a + ω̇ × p + ω × (ω × p) has no z terms.
        let (w0, wd0) = (&qd[0], &qdd[0]);
        let lk = &m.links[1];
        let p = lk.p;
        let a_origin = VL {
            x: lanes!(l => (a0.x[l] - wd0[l] * p.y) - w0[l] * (w0[l] * p.x)),
            y: lanes!(l => (a0.y[l] + wd0[l] * p.x) - w0[l] * (w0[l] * p.y)),
            z: a0.z,
        };
        let zero = [0.0; W];
        let wp = VL {
            x: zero,
            y: zero,
            z: *w0,
        };
        let wdp = VL {
            x: zero,
            y: zero,
            z: *wd0,
        };
        let (mut wp, mut wdp, mut ap) = with_fixed!(lk, |fx| {
            let (w, wd, a, fi, ni) =
                link_forward(&fx, lk, &s[1], &c[1], &qd[1], &qdd[1], &wp, &wdp, &a_origin);
            f[1] = fi;
            nn[1] = ni;
            (w, wd, a)
        });
        for i in 2..n {
            let lk = &m.links[i];
            let a_origin = ap
                .add(&wdp.cross_c(&lk.p))
                .add(&wp.cross(&wp.cross_c(&lk.p)));
            (wp, wdp, ap) = with_fixed!(lk, |fx| {
                let (w, wd, a, fi, ni) =
                    link_forward(&fx, lk, &s[i], &c[i], &qd[i], &qdd[i], &wp, &wdp, &a_origin);
                f[i] = fi;
                nn[i] = ni;
                (w, wd, a)
            });
        }
        // Backward: the torque of joint i, then its force and moment into the parent's frame
        // (`R v = C (Rz v)`); into link 0 only the moment's z component. The running force and
        // moment stay in registers: link i − 1's total is its own (from the
        // forward pass) plus its child's, the same addition as accumulating into its slot,
        // without storing it to read it back.
        let (mut fi, mut ni) = (f[n - 1], nn[n - 1]);
        for i in (1..n).rev() {
            let lk = &m.links[i];
            let arm = lk.armature;
            let (t, a) = (&ni.z, &qdd[i]);
            tau[i] = lanes!(l => t[l] + arm * a[l]);
            let (si, ci) = (&s[i], &c[i]);
            let (fp, np) = with_fixed!(lk, |fx| {
                let fp = fx.c(&rz(si, ci, &fi));
                let np = fx.c(&rz(si, ci, &ni)).add(&VL::c_cross(&lk.p, &fp));
                (fp, np)
            });
            if i > 1 {
                fi = f[i - 1].add(&fp);
                ni = nn[i - 1].add(&np);
            } else {
                nz0 = lanes!(l => nz0[l] + np.z[l]);
            }
        }
    }
    let arm = l0.armature;
    tau[0] = lanes!(l => nz0[l] + arm * qdd[0][l]);
}

/// [`rnea_lanes`] of one sample (the scalar reference of a revolute model): `sin_cos(i)` the
/// joint's `(sin q_i, cos q_i)`, `qd` rad/s, `qdd` rad/s², into `tau` (N·m), all of the
/// model's length.
pub(super) fn rnea_one(
    m: &DynModel,
    sin_cos: impl Fn(usize) -> (f64, f64),
    qd: &[f64],
    qdd: &[f64],
    tau: &mut [f64],
) {
    let n = m.n.min(MAX_DOF);
    let (mut s, mut c, mut v, mut a) = (
        [[0.0; 1]; MAX_DOF],
        [[1.0; 1]; MAX_DOF],
        [[0.0; 1]; MAX_DOF],
        [[0.0; 1]; MAX_DOF],
    );
    for i in 0..n {
        (s[i][0], c[i][0]) = sin_cos(i);
        v[i][0] = qd[i];
        a[i][0] = qdd[i];
    }
    let mut t = [[0.0; 1]; MAX_DOF];
    rnea_lanes::<1>(m, &s, &c, &v, &a, &mut t, &mut RneaScratch::default());
    for (x, t) in tau.iter_mut().zip(&t[..n]) {
        *x = t[0];
    }
}

/// Joint torques `tau[j][lane]` (N·m) of the [`LANES`] samples of `b` by RNEA
/// (`τ = M(q) q̈ + C(q, q̇) q̇ + G(q)`, plus the armature when the model has it), with the
/// instruction set `level` ([`crate::simd::run`]; [`Level::Scalar`] and a level this CPU
/// lacks run the baseline build of the same kernel). Bit-identical, lane by lane, to
/// [`super::rnea_with_sincos`] of each sample. Only for a [`DynModel::batchable`] model
/// (revolute joints); for others the result is unspecified.
pub fn rnea_batch(m: &DynModel, b: &StateBatch, tau: &mut [Lanes; MAX_DOF], level: Level) {
    crate::simd::run(
        level,
        #[inline(always)]
        || {
            rnea_lanes(
                m,
                &b.s,
                &b.c,
                &b.qd,
                &b.qdd,
                tau,
                &mut RneaScratch::default(),
            )
        },
    )
}
