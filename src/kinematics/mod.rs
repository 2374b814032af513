//! Kinematics: forward kinematics and Jacobian ([`fk`]), closed-form IK of ortho-parallel arms
//! ([`opw`]), general numeric IK ([`numeric`]), and the front end [`IkSolver`] that picks one,
//! applies joint limits and re-checks every answer by forward kinematics.
//!
//! Frames are in the robot's base frame; lengths in m, angles in rad (degrees only in
//! messages). "Flange" is the `tool_link` frame; "tool" is the nozzle tip, whose +z is the
//! nozzle direction.

pub mod fk;
pub mod numeric;
pub mod opw;

pub use fk::{
    fk, flange_pose, jacobian, jacobian_measures, tool_pose, FastChain, FkFrames, Jacobian,
};
pub use numeric::NumericOptions;
pub use opw::{Branch, Elbow, Shoulder, Wrist};

use crate::math::{Frame, M3, V3};
use crate::robot::{JointKind, RobotModel};
use nalgebra::Vector6;
use std::f64::consts::PI;

/// Largest number of joints the allocation-free routines handle.
pub const MAX_DOF: usize = 8;
// The robot's reach is composed over as many joints as forward kinematics takes.
const _: () = assert!(MAX_DOF == crate::robot::envelope::MAX_CHAIN);

/// `|sin q5|` below which path IK also considers the other wrist variant (dimensionless).
pub(crate) const NEAR_WRIST_SINGULARITY: f64 = 0.2;

/// Path IK's largest step from the previous answer (rad, the largest |Δq| over the joints) of
/// the wrist variant it continues, below which the other wrist variant cannot be nearer, so
/// that it need not be fitted. The flipped variant's joint 4 differs from the unflipped one's
/// by an odd multiple of π (OPW signs ±1; the limit fit adds 2π multiples and moves a value by
/// at most its 1e-9 tolerance), so its step is at least π − d − 3e-9 when the unflipped
/// variant's is d; below (π − 3e-9)/2 ≈ 1.5708 it is larger than d and loses the choice
/// (nearer wins, a tie keeps the unflipped). 1.5 leaves 0.07 rad for rounding.
pub const FLIP_CANNOT_WIN_RAD: f64 = 1.5;

/// Joint vector on the stack (rad for revolute, m for prismatic joints); dereferences to a
/// slice of its `len()` entries.
#[derive(Clone, Copy, PartialEq)]
pub struct JointVec {
    n: usize,
    v: [f64; MAX_DOF],
}

impl JointVec {
    /// `n` zeros (`n` is capped at [`MAX_DOF`]).
    pub fn zeros(n: usize) -> Self {
        JointVec {
            n: n.min(MAX_DOF),
            v: [0.0; MAX_DOF],
        }
    }

    /// Copy of the first ≤ [`MAX_DOF`] entries of `q`.
    pub fn from_slice(q: &[f64]) -> Self {
        let mut j = JointVec::zeros(q.len());
        j.v[..j.n].copy_from_slice(&q[..j.n]);
        j
    }

    /// As a `Vec`.
    pub fn to_vec(&self) -> Vec<f64> {
        self.v[..self.n].to_vec()
    }

    /// All [`MAX_DOF`] slots (rad / m): the entries, then zeros beyond its `len()` entries
    /// (every constructor zeroes them and the slice views never reach them), for fixed-width
    /// loops that vectorise.
    #[inline]
    pub(crate) fn padded(&self) -> &[f64; MAX_DOF] {
        &self.v
    }
}

impl std::ops::Deref for JointVec {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        &self.v[..self.n]
    }
}

impl std::ops::DerefMut for JointVec {
    fn deref_mut(&mut self) -> &mut [f64] {
        &mut self.v[..self.n]
    }
}

impl std::fmt::Debug for JointVec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

/// Why an inverse-kinematics query has no (acceptable) answer.
#[derive(Clone, Debug, PartialEq)]
pub enum IkFailure {
    /// The target is beyond (or inside) what the arm can reach: `what` is measured, in m.
    OutOfReach {
        /// The measured distance, m.
        distance_m: f64,
        /// Smallest reachable value of that distance, m.
        min_reach_m: f64,
        /// Largest reachable value of that distance, m (`inf` = no upper bound).
        max_reach_m: f64,
        /// What the distance is, e.g. "wrist centre from the axis of joint 2".
        what: &'static str,
    },
    /// The solution needs a joint outside its position limits.
    JointLimit {
        /// 0-based joint index.
        joint: usize,
        /// URDF joint name.
        name: String,
        /// The needed value (rad, or m for prismatic joints).
        value: f64,
        /// Lower limit (rad / m).
        lower: f64,
        /// Upper limit (rad / m).
        upper: f64,
        /// Whether the joint is revolute (values shown in degrees).
        revolute: bool,
    },
    /// The closed form is undefined at this pose.
    Singular {
        /// Which singularity.
        what: &'static str,
        /// The singularity measure at the failure (0 = exactly singular).
        measure: f64,
    },
    /// The numeric solver did not converge.
    NoConvergence {
        /// Iterations spent (per seed).
        iterations: usize,
        /// Remaining tool position error, m.
        position_error_m: f64,
        /// Remaining tool orientation error, rad.
        orientation_error_rad: f64,
    },
    /// A solution failed the forward-kinematics re-check (a bug or bad parameters).
    CheckFailed {
        /// Tool position error, m.
        position_error_m: f64,
        /// Tool orientation error, rad.
        orientation_error_rad: f64,
    },
    /// The query itself is not supported (too many joints, wrong length, non-finite target).
    Unsupported(String),
}

impl IkFailure {
    /// How informative a failure is when several branches failed differently.
    fn rank(&self) -> u8 {
        match self {
            IkFailure::OutOfReach { .. } => 1,
            IkFailure::NoConvergence { .. } => 2,
            IkFailure::Singular { .. } => 3,
            IkFailure::JointLimit { .. } => 4,
            IkFailure::CheckFailed { .. } => 5,
            IkFailure::Unsupported(_) => 6,
        }
    }
}

impl std::fmt::Display for IkFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            IkFailure::OutOfReach {
                distance_m,
                min_reach_m,
                max_reach_m,
                what,
            } => {
                write!(f, "out of reach: {what} is {distance_m:.4} m")?;
                if distance_m > max_reach_m {
                    write!(
                        f,
                        ", the arm reaches at most {max_reach_m:.4} m ({:.4} m too far)",
                        distance_m - max_reach_m
                    )
                } else if distance_m < min_reach_m {
                    write!(
                        f,
                        ", it must be at least {min_reach_m:.4} m ({:.4} m too close)",
                        min_reach_m - distance_m
                    )
                } else {
                    write!(f, " (reachable {min_reach_m:.4}–{max_reach_m:.4} m)")
                }
            }
            IkFailure::JointLimit {
                joint,
                name,
                value,
                lower,
                upper,
                revolute,
            } => {
                if *revolute {
                    write!(
                        f,
                        "joint limit: joint {} `{name}` would need {:.2}°, outside its limits [{:.2}°, {:.2}°]",
                        joint + 1,
                        value.to_degrees(),
                        lower.to_degrees(),
                        upper.to_degrees()
                    )
                } else {
                    write!(
                        f,
                        "joint limit: joint {} `{name}` would need {value:.4} m, outside its limits [{lower:.4} m, {upper:.4} m]",
                        joint + 1
                    )
                }
            }
            IkFailure::Singular { what, measure } => {
                write!(f, "singular: {what} (measure {measure:.3e})")
            }
            IkFailure::NoConvergence {
                iterations,
                position_error_m,
                orientation_error_rad,
            } => write!(
                f,
                "no convergence after {iterations} iterations: tool still {position_error_m:.3e} m and {:.3e}° off",
                orientation_error_rad.to_degrees()
            ),
            IkFailure::CheckFailed {
                position_error_m,
                orientation_error_rad,
            } => write!(
                f,
                "IK answer failed the forward-kinematics check: {position_error_m:.3e} m, {orientation_error_rad:.3e} rad"
            ),
            IkFailure::Unsupported(m) => write!(f, "IK not possible: {m}"),
        }
    }
}

impl std::error::Error for IkFailure {}

impl From<IkFailure> for crate::error::Error {
    fn from(e: IkFailure) -> Self {
        crate::error::Error::Unreachable(e.to_string())
    }
}

/// Rotation vector (axis · angle, rad) of `r`, robust near 0 and π.
pub fn rot_log(r: &M3) -> V3 {
    let v = V3::new(
        r[(2, 1)] - r[(1, 2)],
        r[(0, 2)] - r[(2, 0)],
        r[(1, 0)] - r[(0, 1)],
    ) * 0.5;
    let c = (r.trace() - 1.0) * 0.5;
    let s = v.norm();
    let theta = s.atan2(c);
    if c > 0.0 || s > 1e-6 {
        if s < 1e-300 {
            return V3::zeros();
        }
        return v * (theta / s);
    }
    // Near π: sym(R) = cos θ I + (1 − cos θ) u uᵀ.
    let d = [r[(0, 0)], r[(1, 1)], r[(2, 2)]];
    let k = if d[0] >= d[1] && d[0] >= d[2] {
        0
    } else if d[1] >= d[2] {
        1
    } else {
        2
    };
    let mut col: V3 = (r.column(k) + r.row(k).transpose()) * 0.5;
    col[k] -= c;
    let mut u = col / col.norm().max(1e-300);
    if u.dot(&v) < 0.0 {
        u = -u;
    }
    u * theta
}

/// 6-D pose error `[p_t − p; log(R_t Rᵀ)]` of `current` towards `target` (m, rad; base frame).
pub(crate) fn pose_error(target: &Frame, current: &Frame) -> Vector6<f64> {
    let dp = target.pos - current.pos;
    let w = rot_log(&(target.rot * current.rot.transpose()));
    Vector6::new(dp.x, dp.y, dp.z, w.x, w.y, w.z)
}

/// Position (m) and orientation (rad) distance between two poses, accurate to rounding.
pub fn pose_distance(a: &Frame, b: &Frame) -> (f64, f64) {
    (
        (a.pos - b.pos).norm(),
        rot_log(&(a.rot * b.rot.transpose())).norm(),
    )
}

/// Orientation distance (rad) of two rotation matrices from their Frobenius difference:
/// `‖Ra − Rb‖_F = 2√2 sin(θ/2)`. Accurate to rounding for small angles (no product of the
/// matrices, no `atan2`); loses precision only near θ = π. Used by the FK re-check.
#[inline]
pub(crate) fn rotation_distance_fast(a: &M3, b: &M3) -> f64 {
    let f2: f64 = a.iter().zip(b.iter()).map(|(x, y)| (x - y) * (x - y)).sum();
    let h = (f2.sqrt() * (0.125f64).sqrt()).min(1.0);
    // asin h = h (1 + h²/6 + …): below 1e-8 the correction is under half an ulp.
    if h < 1e-8 {
        2.0 * h
    } else {
        2.0 * h.asin()
    }
}

/// Put each revolute joint on the 2π multiple that is within limits and closest to `q_ref`
/// (or to 0 without a reference), then check every joint against its limits (1e-9 slack,
/// clamped). Prismatic joints are only checked.
pub fn fit_limits(
    model: &RobotModel,
    q: &mut [f64],
    q_ref: Option<&[f64]>,
) -> Result<(), IkFailure> {
    // `floor`, `ceil` and `round` are exact, so every build gives the same answer; with SSE4.1
    // they are instructions instead of libm calls (a wide-range joint continuing past ±π takes
    // them on every sample).
    crate::simd::with_rounding(
        #[inline(always)]
        || fit_limits_body(model, q, q_ref),
    )
}

#[inline(always)]
fn fit_limits_body(
    model: &RobotModel,
    q: &mut [f64],
    q_ref: Option<&[f64]>,
) -> Result<(), IkFailure> {
    const TOL: f64 = 1e-9;
    const TAU: f64 = 2.0 * PI;
    for (i, j) in model.joints.iter().enumerate().take(q.len()) {
        let fail = |value: f64| IkFailure::JointLimit {
            joint: i,
            name: j.name.clone(),
            value,
            lower: j.lower,
            upper: j.upper,
            revolute: j.kind == JointKind::Revolute,
        };
        let v = q[i];
        match j.kind {
            JointKind::Revolute => {
                let center = q_ref.and_then(|r| r.get(i).copied()).unwrap_or(0.0);
                // Fast path: within limits and less than π from the centre, so already on the
                // closest 2π multiple.
                if v >= j.lower && v <= j.upper && (v - center).abs() < PI {
                    continue;
                }
                // A NaN or infinite angle is no angle: no 2π multiple puts it within the
                // limits (before, NaN made `clamp` panic and ±∞ came out as NaN).
                if !v.is_finite() {
                    return Err(fail(v));
                }
                let kmin = ((j.lower - TOL - v) / TAU).ceil();
                let kmax = ((j.upper + TOL - v) / TAU).floor();
                // Not `kmin > kmax`: NaN limits fail too (`clamp` below panics on NaN).
                #[allow(clippy::neg_cmp_op_on_partial_ord)]
                if !(kmin <= kmax) {
                    let w = opw::wrap_pi(v - center) + center;
                    return Err(fail(w));
                }
                let k = ((center - v) / TAU).round().clamp(kmin, kmax);
                q[i] = (v + k * TAU).clamp(j.lower, j.upper);
            }
            JointKind::Prismatic => {
                if !j.within_limits(v, TOL) {
                    return Err(fail(v));
                }
                q[i] = v.clamp(j.lower, j.upper);
            }
        }
    }
    Ok(())
}

/// The joint limits [`fit_limits`] reads, gathered once per solver (a robot's joints are
/// large records; the per-sample fit of path IK reads six of their numbers): per joint the
/// limits, the limits widened by the fit's tolerance (`lower − 1e-9`, `upper + 1e-9`, the
/// same sums `fit_limits` forms per call) and the kind.
/// [`LimitTable::fit`] is [`fit_limits`], bit for bit.
#[derive(Clone, Debug)]
pub struct LimitTable {
    n: usize,
    lower: [f64; MAX_DOF],
    upper: [f64; MAX_DOF],
    lower_tol: [f64; MAX_DOF],
    upper_tol: [f64; MAX_DOF],
    revolute: [bool; MAX_DOF],
}

/// Tolerance of [`fit_limits`]' limit checks, rad (m).
const FIT_TOL: f64 = 1e-9;

impl LimitTable {
    /// The table of `model`'s first [`MAX_DOF`] joints.
    pub fn new(model: &RobotModel) -> LimitTable {
        let mut t = LimitTable {
            n: model.joints.len().min(MAX_DOF),
            lower: [0.0; MAX_DOF],
            upper: [0.0; MAX_DOF],
            lower_tol: [0.0; MAX_DOF],
            upper_tol: [0.0; MAX_DOF],
            revolute: [false; MAX_DOF],
        };
        for (i, j) in model.joints.iter().take(MAX_DOF).enumerate() {
            t.lower[i] = j.lower;
            t.upper[i] = j.upper;
            t.lower_tol[i] = j.lower - FIT_TOL;
            t.upper_tol[i] = j.upper + FIT_TOL;
            t.revolute[i] = j.kind == JointKind::Revolute;
        }
        t
    }

    /// [`fit_limits`]`(model, q, q_ref)` from the table (`model` the table's robot, for the
    /// error's joint name only): the same answer, the same error, bit for bit.
    #[inline]
    pub fn fit(
        &self,
        model: &RobotModel,
        q: &mut [f64],
        q_ref: Option<&[f64]>,
    ) -> Result<(), IkFailure> {
        if model.joints.len() > MAX_DOF {
            return fit_limits(model, q, q_ref);
        }
        let m = q.len().min(self.n);
        let (q_m, lower, upper) = (&q[..m], &self.lower[..m], &self.upper[..m]);
        // fit_limits' fast path at every joint (revolute, within the limits, less than π from
        // the centre: its reference, else 0) leaves `q` as it is.
        let mut inside = true;
        match q_ref {
            Some(r) if r.len() >= m => {
                for i in 0..m {
                    inside &= self.revolute[i]
                        & (q_m[i] >= lower[i])
                        & (q_m[i] <= upper[i])
                        & ((q_m[i] - r[i]).abs() < PI);
                }
            }
            None => {
                for i in 0..m {
                    inside &= self.revolute[i]
                        & (q_m[i] >= lower[i])
                        & (q_m[i] <= upper[i])
                        & ((q_m[i] - 0.0).abs() < PI);
                }
            }
            Some(_) => inside = false,
        }
        if inside {
            return Ok(());
        }
        crate::simd::with_rounding(
            #[inline(always)]
            || self.fit_joints(model, q, q_ref),
        )
    }

    /// [`LimitTable::fit`] of joint `j` (revolute) over [`crate::simd::LANES`] values `v` (rad)
    /// with the centres `centre` (rad), in lockstep: per lane the fitted value, bit for bit
    /// `fit`'s, and whether `fit` accepts it (1, else 0; 0 for a prismatic joint: not
    /// handled).
    #[allow(clippy::needless_range_loop)] // lanes of parallel fixed arrays
    #[inline(always)]
    pub(crate) fn fit_lanes(
        &self,
        j: usize,
        v: &[f64; crate::simd::LANES],
        centre: &[f64; crate::simd::LANES],
    ) -> ([f64; crate::simd::LANES], [u64; crate::simd::LANES]) {
        use crate::simd::LANES;
        const TAU: f64 = 2.0 * PI;
        let (lo, hi) = (self.lower[j], self.upper[j]);
        let (lo_tol, hi_tol) = (self.lower_tol[j], self.upper_tol[j]);
        let rev = u64::from(self.revolute[j]);
        let mut out = [0.0; LANES];
        let mut ok = [0u64; LANES];
        for l in 0..LANES {
            let (x, c) = (v[l], centre[l]);
            let fast = (x >= lo) & (x <= hi) & ((x - c).abs() < PI);
            let kmin = ((lo_tol - x) / TAU).ceil();
            let kmax = ((hi_tol - x) / TAU).floor();
            // f64::clamp as selects (the same comparisons; no panic on NaN lanes).
            let r = ((c - x) / TAU).round();
            let k = if r < kmin { kmin } else { r };
            let k = if k > kmax { kmax } else { k };
            let w = x + k * TAU;
            let w = if w < lo { lo } else { w };
            let w = if w > hi { hi } else { w };
            out[l] = if fast { x } else { w };
            ok[l] = rev & u64::from(fast | (x.is_finite() & (kmin <= kmax)));
        }
        (out, ok)
    }

    /// Per lane (bit `l`) whether [`LimitTable::fit`] without a reference accepts the
    /// 6-joint vectors `qj[j][lane]` (rad), decided in lockstep on `level` by
    /// [`LimitTable::fit_lanes`] about 0 (the same comparisons and roundings); levels without
    /// SSE4.1 rounding (scalar, SSE2) test only fit's fast path (revolute, within the
    /// limits, less than π from 0), a subset. Only for a table of 6 joints.
    pub(crate) fn accepts_lanes(
        &self,
        qj: &[[f64; crate::simd::LANES]; 6],
        level: crate::simd::Level,
    ) -> u32 {
        use crate::simd::{Level, LANES};
        match level {
            Level::Avx512 | Level::Avx2 if level.available() => crate::simd::run(
                level,
                #[inline(always)]
                || self.accepts_lanes_body(qj),
            ),
            _ => {
                let mut all = [1u64; LANES];
                for (j, v) in qj.iter().enumerate() {
                    let (lo, hi) = (self.lower[j], self.upper[j]);
                    let rev = u64::from(self.revolute[j]);
                    for (a, &x) in all.iter_mut().zip(v) {
                        *a &= rev & u64::from((x >= lo) & (x <= hi) & ((x - 0.0).abs() < PI));
                    }
                }
                let mut mask = 0u32;
                for (l, a) in all.iter().enumerate() {
                    mask |= u32::from(*a != 0) << l;
                }
                mask
            }
        }
    }

    /// The body of [`LimitTable::accepts_lanes`] with rounding instructions.
    #[inline(always)]
    fn accepts_lanes_body(&self, qj: &[[f64; crate::simd::LANES]; 6]) -> u32 {
        use crate::simd::LANES;
        let mut all = [1u64; LANES];
        for (j, v) in qj.iter().enumerate() {
            let (_, ok) = self.fit_lanes(j, v, &[0.0; LANES]);
            for (a, o) in all.iter_mut().zip(ok) {
                *a &= o;
            }
        }
        let mut mask = 0u32;
        for (l, a) in all.iter().enumerate() {
            mask |= u32::from(*a != 0) << l;
        }
        mask
    }

    /// fit_limits_body with the table's numbers: the same operations in the same order.
    #[allow(clippy::needless_range_loop)] // joint i of q and of the table's arrays
    #[inline(always)]
    fn fit_joints(
        &self,
        model: &RobotModel,
        q: &mut [f64],
        q_ref: Option<&[f64]>,
    ) -> Result<(), IkFailure> {
        const TAU: f64 = 2.0 * PI;
        let m = q.len().min(self.n);
        for i in 0..m {
            let fail = |value: f64| {
                let j = &model.joints[i];
                IkFailure::JointLimit {
                    joint: i,
                    name: j.name.clone(),
                    value,
                    lower: j.lower,
                    upper: j.upper,
                    revolute: j.kind == JointKind::Revolute,
                }
            };
            let (lower, upper) = (self.lower[i], self.upper[i]);
            let v = q[i];
            if self.revolute[i] {
                let center = q_ref.and_then(|r| r.get(i).copied()).unwrap_or(0.0);
                if v >= lower && v <= upper && (v - center).abs() < PI {
                    continue;
                }
                // A NaN or infinite angle is no angle: no 2π multiple puts it within the
                // limits (before, NaN made `clamp` panic and ±∞ came out as NaN).
                if !v.is_finite() {
                    return Err(fail(v));
                }
                let kmin = ((self.lower_tol[i] - v) / TAU).ceil();
                let kmax = ((self.upper_tol[i] - v) / TAU).floor();
                // Not `kmin > kmax`: NaN limits fail too (`clamp` below panics on NaN).
                #[allow(clippy::neg_cmp_op_on_partial_ord)]
                if !(kmin <= kmax) {
                    let w = opw::wrap_pi(v - center) + center;
                    return Err(fail(w));
                }
                let k = ((center - v) / TAU).round().clamp(kmin, kmax);
                q[i] = (v + k * TAU).clamp(lower, upper);
            } else {
                if !(v >= self.lower_tol[i] && v <= self.upper_tol[i]) {
                    return Err(fail(v));
                }
                q[i] = v.clamp(lower, upper);
            }
        }
        Ok(())
    }
}

/// What the lockstep path IK computes once per tool orientation ([`IkSolver::path_target`]):
/// the orientation (base frame), the flange's (`rot · tool⁻¹`), the offset from the tool tip
/// to the flange origin (m), and the rotation the FK re-check compares against
/// ([`fk::FastChain::check_rotation`]).
#[derive(Clone, Copy, Debug)]
pub struct PathTarget {
    rot: M3,
    frot: M3,
    off: V3,
    check_rot: M3,
}

/// Where [`IkSolver::check_lanes`]' sines and cosines go: into a slice, or appended.
enum Out<'a> {
    Slice(&'a mut [f64]),
    Push(&'a mut Vec<f64>),
}

/// [`IkSolver::continuing_lanes`]' answer.
#[derive(Clone, Copy, Debug)]
pub struct Continuing {
    /// How many leading lanes are taken.
    pub taken: usize,
    /// Their answers joint by joint (rad): `q[j][lane]` for the 6 joints (the rows beyond
    /// stay 0: the layout [`IkSolver::check_lanes`] reads).
    pub q: [[f64; crate::simd::LANES]; MAX_DOF],
    /// [`opw::Prepared::branch_of`] of the last taken answer, bit for bit (the batch's
    /// branch when none is taken).
    pub branch_after: Branch,
}

impl Continuing {
    /// None taken yet.
    pub fn new() -> Continuing {
        Continuing {
            taken: 0,
            q: [[0.0; crate::simd::LANES]; MAX_DOF],
            branch_after: Branch::ALL[0],
        }
    }
}

impl Default for Continuing {
    fn default() -> Self {
        Continuing::new()
    }
}

/// One inverse-kinematics answer, already checked by forward kinematics and within limits.
#[derive(Clone, Copy, Debug)]
pub struct Solution {
    /// Joint vector (rad / m).
    pub q: JointVec,
    /// The closed-form branch, for OPW arms.
    pub branch: Option<Branch>,
    /// Tool position error of the FK re-check, m.
    pub position_error_m: f64,
    /// Tool orientation error of the FK re-check, rad.
    pub orientation_error_rad: f64,
}

/// Inverse-kinematics front end: closed form when the model has OPW parameters, numeric
/// otherwise. Targets are **tool** (nozzle-tip) poses in the base frame.
#[derive(Clone, Debug)]
pub struct IkSolver<'a> {
    /// The robot.
    pub model: &'a RobotModel,
    tool_inv: Frame,
    chain: fk::FastChain,
    opw_k: Option<opw::Prepared>,
    limits: LimitTable,
    /// Whether [`FLIP_CANNOT_WIN_RAD`]'s bound holds for this arm (OPW sign of joint 4 ±1,
    /// offset small enough that its rounding is far below the bound's margin).
    flip_bound: bool,
    /// Settings of the numeric solver.
    pub numeric: NumericOptions,
    /// Accepted tool position error of the FK re-check, m.
    pub check_position_m: f64,
    /// Accepted tool orientation error of the FK re-check, rad.
    pub check_orientation_rad: f64,
    /// Upper bound of the distance tool point ↔ origin of joint 1 (sum of link lengths), m.
    pub reach_bound_m: f64,
}

impl<'a> IkSolver<'a> {
    /// A solver for `model` (at most [`MAX_DOF`] joints).
    pub fn new(model: &'a RobotModel) -> Result<Self, IkFailure> {
        if model.dof() == 0 || model.dof() > MAX_DOF {
            return Err(IkFailure::Unsupported(format!(
                "robot `{}` has {} joints; the kinematics handle 1..={MAX_DOF}",
                model.name(),
                model.dof()
            )));
        }
        let reach_bound_m = model
            .joints
            .iter()
            .skip(1)
            .map(|j| {
                j.origin.pos.norm()
                    + match j.kind {
                        JointKind::Prismatic => j.upper.abs().max(j.lower.abs()),
                        JointKind::Revolute => 0.0,
                    }
            })
            .sum::<f64>()
            + model.flange.pos.norm()
            + model.tool.pos.norm();
        Ok(IkSolver {
            model,
            tool_inv: model.tool.inverse(),
            chain: fk::FastChain::new(model),
            opw_k: model.opw.as_ref().map(opw::Prepared::new),
            limits: LimitTable::new(model),
            flip_bound: model
                .opw
                .as_ref()
                .is_some_and(|p| p.signs[3].abs() == 1.0 && p.offsets[3].abs() <= 100.0),
            numeric: NumericOptions::default(),
            check_position_m: 1e-6,
            check_orientation_rad: 1e-6,
            reach_bound_m,
        })
    }

    /// The flange pose that puts the tool at `tool_target` (`target ∘ tool⁻¹`).
    #[inline]
    pub fn flange_target(&self, tool_target: &Frame) -> Frame {
        tool_target.compose(&self.tool_inv)
    }

    /// Re-check `q` by forward kinematics against the tool target; returns (m, rad) errors.
    #[inline]
    pub fn check(&self, tool_target: &Frame, q: &[f64]) -> Result<(f64, f64), IkFailure> {
        self.check_pose(tool_target, &self.chain.tool(q))
    }

    /// [`IkSolver::check`] that also writes the sines and cosines of `q` it computed into
    /// `sincos` (see [`fk::FastChain::tool_with_sincos`]).
    #[inline]
    pub fn check_with_sincos(
        &self,
        tool_target: &Frame,
        q: &[f64],
        sincos: &mut [f64],
    ) -> Result<(f64, f64), IkFailure> {
        self.check_pose(tool_target, &self.chain.tool_with_sincos(q, sincos))
    }

    #[inline]
    fn check_pose(&self, tool_target: &Frame, f: &Frame) -> Result<(f64, f64), IkFailure> {
        let dp = (f.pos - tool_target.pos).norm();
        let dr = rotation_distance_fast(&f.rot, &tool_target.rot);
        if dp < self.check_position_m && dr < self.check_orientation_rad {
            Ok((dp, dr))
        } else {
            // The precise distances for the message.
            let (dp, dr) = pose_distance(f, tool_target);
            Err(IkFailure::CheckFailed {
                position_error_m: dp,
                orientation_error_rad: dr,
            })
        }
    }

    fn precheck(&self, tool_target: &Frame) -> Result<(), IkFailure> {
        let finite = tool_target.pos.iter().all(|v| v.is_finite())
            && tool_target.rot.iter().all(|v| v.is_finite());
        if !finite {
            return Err(IkFailure::Unsupported("non-finite target pose".into()));
        }
        let d = (tool_target.pos - self.model.joints[0].origin.pos).norm();
        // OPW arms report the more precise wrist-centre distance from the closed form.
        if self.model.opw.is_none() && d > self.reach_bound_m {
            return Err(IkFailure::OutOfReach {
                distance_m: d,
                min_reach_m: 0.0,
                max_reach_m: self.reach_bound_m,
                what: "nozzle tip from the base of joint 1",
            });
        }
        Ok(())
    }

    /// Every solution for the tool pose: all 8 closed-form branches that are within limits
    /// (joints on the 2π multiple closest to 0), or the distinct numeric solutions from
    /// deterministic seeds. Each is FK-checked. Errors when there is none, with the most
    /// informative reason.
    pub fn solve_all(&self, tool_target: &Frame) -> Result<Vec<Solution>, IkFailure> {
        self.precheck(tool_target)?;
        let mut out: Vec<Solution> = Vec::new();
        let mut why: Option<IkFailure> = None;
        let note = |e: IkFailure, why: &mut Option<IkFailure>| {
            if why.as_ref().is_none_or(|w| e.rank() > w.rank()) {
                *why = Some(e);
            }
        };
        match &self.model.opw {
            Some(p) => {
                let flange = self.flange_target(tool_target);
                for b in Branch::ALL {
                    let r = opw::solve_branch(p, &flange, b).and_then(|q| {
                        let mut q = JointVec::from_slice(&q);
                        self.limits.fit(self.model, &mut q, None)?;
                        let (dp, dr) = self.check(tool_target, &q)?;
                        Ok(Solution {
                            q,
                            branch: Some(b),
                            position_error_m: dp,
                            orientation_error_rad: dr,
                        })
                    });
                    match r {
                        Ok(s) => {
                            if !out
                                .iter()
                                .any(|o| numeric::same_modulo_2pi(self.model, &o.q, &s.q, 1e-9))
                            {
                                out.push(s)
                            }
                        }
                        Err(e) => note(e, &mut why),
                    }
                }
            }
            None => match numeric::solve_all(self.model, tool_target, &self.numeric) {
                Ok(qs) => {
                    for mut q in qs {
                        let r = self
                            .limits
                            .fit(self.model, &mut q, None)
                            .and_then(|_| self.check(tool_target, &q));
                        match r {
                            Ok((dp, dr)) => out.push(Solution {
                                q,
                                branch: None,
                                position_error_m: dp,
                                orientation_error_rad: dr,
                            }),
                            Err(e) => note(e, &mut why),
                        }
                    }
                }
                Err(e) => note(e, &mut why),
            },
        }
        if out.is_empty() {
            return Err(why.unwrap_or(IkFailure::Unsupported("no solution".into())));
        }
        Ok(out)
    }

    /// A necessary condition for any IK answer at `tool_target` (base frame, m), far cheaper
    /// than solving: for OPW arms, the wrist centre within reach of the arm for at least one
    /// shoulder (the closed form's own reach conditions, [`opw::arm_reaches`]); otherwise the
    /// tool within the sum of link lengths of joint 1. An `Err` here means that
    /// [`IkSolver::solve_near`] fails for every previous joint vector and
    /// [`IkSolver::solve_all`] finds nothing, so a path containing this target cannot be
    /// tracked. `Ok` proves nothing.
    #[inline]
    pub fn reachable(&self, tool_target: &Frame) -> Result<(), IkFailure> {
        match (&self.model.opw, &self.opw_k) {
            (Some(p), Some(_)) => {
                let flange = self.flange_target(tool_target);
                self.wrist_centre_reachable(&(flange.pos - flange.rot.column(2) * p.c4), 0.0)
            }
            _ => self.precheck(tool_target),
        }
    }

    /// For a tool orientation `rot` (base frame), the constant offset from the tool point to
    /// the wrist centre, m (OPW arms; `None` otherwise): wrist centre = tip + offset.
    pub(crate) fn wrist_offset(&self, rot: &M3) -> Option<V3> {
        let p = self.model.opw.as_ref()?;
        let flange = self.flange_target(&Frame {
            rot: *rot,
            pos: V3::zeros(),
        });
        Some(flange.pos - flange.rot.column(2) * p.c4)
    }

    /// [`IkSolver::reachable`] on a wrist centre `c` (base frame, m) of an OPW arm, with the
    /// conditions widened by `slack` (see [`opw::arm_reaches`]; use 1e-9 for a wrist centre
    /// from [`IkSolver::wrist_offset`], whose rounding differs from the solver's). `Ok` for
    /// arms without OPW parameters.
    #[inline]
    pub(crate) fn wrist_centre_reachable(&self, c: &V3, slack: f64) -> Result<(), IkFailure> {
        let (Some(p), Some(k)) = (&self.model.opw, &self.opw_k) else {
            return Ok(());
        };
        match opw::arm_reaches(p, k, c, Shoulder::Front, slack) {
            Ok(()) => Ok(()),
            Err(e) => opw::arm_reaches(p, k, c, Shoulder::Back, slack).map_err(|_| e),
        }
    }

    /// The closed-form branch [`IkSolver::solve_near`] continues from `q` (OPW arms), else `None`.
    pub fn branch_of(&self, q: &[f64]) -> Option<Branch> {
        match (&self.model.opw, &self.opw_k) {
            (Some(p), Some(k)) if q.len() >= 6 => Some(k.branch_of(p, q)),
            _ => None,
        }
    }

    /// A necessary condition for [`IkSolver::solve_near`] to continue a path in the
    /// shoulder/elbow branch `(shoulder, elbow)` at `tool_target`: one of the branch's two
    /// wrist variants reaches the target with every joint within its limits. At an exactly
    /// singular wrist (`|sin q5|` < 1e-6), where `solve_near` splits the rotation between
    /// joints 4 and 6 according to the previous sample, joints 4 and 6 are not judged. No
    /// forward-kinematics re-check (it can only reject more). OPW arms only (`Ok` otherwise).
    pub fn branch_admits(
        &self,
        tool_target: &Frame,
        shoulder: Shoulder,
        elbow: Elbow,
    ) -> Result<(), IkFailure> {
        let (Some(p), Some(k)) = (&self.model.opw, &self.opw_k) else {
            return Ok(());
        };
        let flange = self.flange_target(tool_target);
        let mut first: Option<IkFailure> = None;
        for wrist in [Wrist::NoFlip, Wrist::Flip] {
            let r = opw::solve_branch_prepared(
                p,
                k,
                &flange,
                Branch::new(shoulder, elbow, wrist),
                None,
            )
            .and_then(|(q, s5)| {
                let mut q = JointVec::from_slice(&q);
                if s5 < 1e-6 {
                    for j in [3, 5] {
                        if let (Some(v), Some(jt)) = (q.get_mut(j), self.model.joints.get(j)) {
                            if jt.lower <= jt.upper {
                                *v = 0.0f64.clamp(jt.lower, jt.upper);
                            }
                        }
                    }
                }
                self.limits.fit(self.model, &mut q, None)
            });
            match r {
                Ok(()) => return Ok(()),
                Err(e) => {
                    first.get_or_insert(e);
                }
            }
        }
        Err(first.unwrap_or(IkFailure::Unsupported("no wrist variant".into())))
    }

    /// [`IkSolver::branch_admits`] of up to [`crate::simd::LANES`] tool targets with the
    /// common orientation `rot` and the tips `tips` (base frame, m), the closed form in
    /// lockstep on `level` ([`opw::solve_branch_batch`]; both wrist variants come from each
    /// lane, as [`IkSolver::take_near`] takes them): the first target it rejects, with
    /// exactly the error `branch_admits` gives, or `None`. Lanes the batch does not hold
    /// (unreachable, near the wrist singularity) go through `branch_admits` itself.
    pub fn branch_admits_batch(
        &self,
        rot: &M3,
        tips: &[V3],
        shoulder: Shoulder,
        elbow: Elbow,
        level: crate::simd::Level,
    ) -> Option<(usize, IkFailure)> {
        use crate::simd::LANES;
        let (Some(p), Some(k)) = (&self.model.opw, &self.opw_k) else {
            return None;
        };
        let tips = &tips[..tips.len().min(LANES)];
        // flange_target of each tip, as solve_near_batch forms it.
        let frot = rot * self.tool_inv.rot;
        let off = rot * self.tool_inv.pos;
        let mut pos = [[0.0; LANES]; 3];
        for (l, t) in tips.iter().enumerate() {
            pos[0][l] = off.x + t.x;
            pos[1][l] = off.y + t.y;
            pos[2][l] = off.z + t.z;
        }
        let b = opw::solve_branch_batch(
            p,
            k,
            &frot,
            &pos,
            Branch::new(shoulder, elbow, Wrist::NoFlip),
            level,
        );
        // LimitTable::fit's verdict in lockstep on the no-flip answers (qj, the batch being
        // solved without flip: BranchBatch::variant(NoFlip) bit for bit), about fit's centre
        // without a reference (0): the lanes it accepts need no per-lane fit; the rest are
        // fitted per lane (both variants, the error).
        let mut inside = [false; LANES];
        if self.model.joints.len() == 6 && self.limits.n == 6 {
            let mask = self.limits.accepts_lanes(&b.qj, level);
            for (l, i) in inside.iter_mut().enumerate() {
                *i = mask >> l & 1 != 0;
            }
        }
        for (l, tip) in tips.iter().enumerate() {
            // branch_admits zeroes q4 and q6 below |sin q5| = 1e-6: per sample there.
            let r = if b.ok[l] && b.s5[l] >= 1e-6 && inside[l] {
                Ok(())
            } else if b.ok[l] && b.s5[l] >= 1e-6 {
                let fit = |w: Wrist| {
                    let mut q = JointVec::from_slice(&b.variant(p, l, w));
                    self.limits.fit(self.model, &mut q, None)
                };
                fit(Wrist::NoFlip).or_else(|e| fit(Wrist::Flip).map_err(|_| e))
            } else {
                self.branch_admits(
                    &Frame {
                        rot: *rot,
                        pos: *tip,
                    },
                    shoulder,
                    elbow,
                )
            };
            if let Err(e) = r {
                return Some((l, e));
            }
        }
        None
    }

    /// The solution that continues `q_prev` (rad / m; the previous path sample): the same
    /// closed-form branch with wide-range joints on the 2π multiple closest to `q_prev` and q4
    /// kept at the wrist singularity, or the numeric solution seeded at `q_prev`. FK-checked.
    #[inline]
    pub fn solve_near(&self, tool_target: &Frame, q_prev: &[f64]) -> Result<JointVec, IkFailure> {
        let mut sincos = [0.0; 2 * MAX_DOF];
        self.solve_near_with_sincos(tool_target, q_prev, &mut sincos)
    }

    /// [`IkSolver::solve_near`] that also writes the sines and cosines of the answer, computed
    /// once by its FK re-check, into `sincos` (length ≥ 2 × dof: the sines, then the cosines;
    /// see [`fk::FastChain::tool_with_sincos`]), for RNEA and the feasibility checks of the
    /// same sample.
    #[inline]
    pub fn solve_near_with_sincos(
        &self,
        tool_target: &Frame,
        q_prev: &[f64],
        sincos: &mut [f64],
    ) -> Result<JointVec, IkFailure> {
        if q_prev.len() != self.model.dof() {
            return Err(IkFailure::Unsupported(format!(
                "previous joint vector has {} entries, the robot {}",
                q_prev.len(),
                self.model.dof()
            )));
        }
        match (&self.model.opw, &self.opw_k) {
            (Some(p), Some(k)) => {
                let q = self.solve_near_opw(p, k, tool_target, q_prev)?;
                self.check_with_sincos(tool_target, &q, sincos)?;
                Ok(q)
            }
            _ => {
                self.precheck(tool_target)?;
                let mut q = numeric::solve_from(self.model, tool_target, q_prev, &self.numeric)?;
                self.limits.fit(self.model, &mut q, Some(q_prev))?;
                self.check_with_sincos(tool_target, &q, sincos)?;
                Ok(q)
            }
        }
    }

    /// Whether the FK re-check can be deferred and run in lockstep batches
    /// ([`IkSolver::solve_near_unchecked`] + [`IkSolver::check_batch`]): a closed-form (OPW)
    /// arm whose chain [`fk::FastChain::batchable`] is.
    pub fn batch_checkable(&self) -> bool {
        self.model.opw.is_some() && self.opw_k.is_some() && self.chain.batchable()
    }

    /// [`IkSolver::solve_near`] without its FK re-check (the closed form, fitted to the
    /// limits), for callers that check the answers later with [`IkSolver::check_batch`]
    /// before using them. For a robot that is not [`IkSolver::batch_checkable`], the checked
    /// [`IkSolver::solve_near`].
    #[inline]
    pub fn solve_near_unchecked(
        &self,
        tool_target: &Frame,
        q_prev: &[f64],
    ) -> Result<JointVec, IkFailure> {
        match (&self.model.opw, &self.opw_k) {
            (Some(p), Some(k)) if q_prev.len() == self.model.dof() => {
                self.solve_near_opw(p, k, tool_target, q_prev)
            }
            _ => self.solve_near(tool_target, q_prev),
        }
    }

    /// The closed form of up to [`crate::simd::LANES`] tool targets with the common
    /// orientation `rot` and the tips `tips` (base frame, m), in lockstep on `level`, for the
    /// branch that continues `q_prev` (rad). `None` for a robot without closed form (or a
    /// `q_prev` of the wrong length). Each sample's answer is then taken with
    /// [`IkSolver::take_near`].
    pub fn solve_near_batch(
        &self,
        rot: &M3,
        tips: &[V3],
        q_prev: &[f64],
        level: crate::simd::Level,
    ) -> Option<opw::BranchBatch> {
        use crate::simd::LANES;
        let mut tp = [[0.0; LANES]; 3];
        let count = tips.len().min(LANES);
        for (l, t) in tips.iter().take(LANES).enumerate() {
            (tp[0][l], tp[1][l], tp[2][l]) = (t.x, t.y, t.z);
        }
        let mut b = opw::BranchBatch::default();
        let target = self.path_target(rot);
        self.solve_near_batch_lanes(&target, &tp, count, q_prev, None, level, &mut b)
            .then_some(b)
    }

    /// What the lockstep path IK ([`IkSolver::solve_near_batch_lanes`],
    /// [`IkSolver::check_lanes`]) computes once per tool orientation `rot` (base frame).
    pub fn path_target(&self, rot: &M3) -> PathTarget {
        PathTarget {
            rot: *rot,
            frot: rot * self.tool_inv.rot,
            off: rot * self.tool_inv.pos,
            check_rot: self.chain.check_rotation(rot),
        }
    }

    /// The closed form's parameters for the lockstep path IK continuing `q_prev` (rad);
    /// `None` for a robot without closed form or a `q_prev` of the wrong length.
    #[inline]
    fn opw_continuing(&self, q_prev: &[f64]) -> Option<(&crate::robot::OpwParams, &opw::Prepared)> {
        match (&self.model.opw, &self.opw_k) {
            (Some(p), Some(k)) if q_prev.len() == self.model.dof() => Some((p, k)),
            _ => None,
        }
    }

    /// The flange positions of one batch's tips `tp[i][lane]` (base frame, m) into the block
    /// of [`crate::simd::LANES`] lanes of `pos` from lane `at`: `off + tip` (`off`: the
    /// target's `rot · tool_inv.pos`, m; the `flange_target` of each tip), and 0 in the
    /// block's lanes from `count` on (no tip).
    #[inline(always)]
    fn flange_block<const W: usize>(
        pos: &mut [[f64; W]; 3],
        at: usize,
        off: &V3,
        tp: &[[f64; crate::simd::LANES]; 3],
        count: usize,
    ) {
        use crate::simd::LANES;
        let off = [off.x, off.y, off.z];
        for i in 0..3 {
            let row = &mut pos[i][at..at + LANES];
            for l in 0..LANES {
                row[l] = off[i] + tp[i][l];
            }
            // Then the lanes without a tip (the last batch's only), in one go rather than a
            // select per lane.
            if count < LANES {
                row[count..].fill(0.0);
            }
        }
    }

    /// The closed form of the `count` tips given lane by lane (`tp[i][lane]`, base frame, m;
    /// lanes from `count` on are ignored) with the orientation of `target`
    /// ([`IkSolver::path_target`]), in lockstep on `level`, into `batch` (overwritten), for
    /// the branch that continues `q_prev` (rad): `branch` when the caller knows it (exactly
    /// [`opw::Prepared::branch_of`]`(q_prev)`, e.g. [`Continuing::branch_after`]), else
    /// computed. `false` (and `batch` untouched) for a robot without closed form or a
    /// `q_prev` of the wrong length. Each sample's answer is then taken with
    /// [`IkSolver::take_near`]. [`IkSolver::solve_near_batch`] is the same for tips given
    /// sample by sample.
    #[allow(clippy::too_many_arguments)]
    pub fn solve_near_batch_lanes(
        &self,
        target: &PathTarget,
        tp: &[[f64; crate::simd::LANES]; 3],
        count: usize,
        q_prev: &[f64],
        branch: Option<Branch>,
        level: crate::simd::Level,
        batch: &mut opw::BranchBatch,
    ) -> bool {
        let Some((p, k)) = self.opw_continuing(q_prev) else {
            return false;
        };
        let mut pos = [[0.0; crate::simd::LANES]; 3];
        Self::flange_block(&mut pos, 0, &target.off, tp, count);
        let branch = branch.unwrap_or_else(|| k.branch_of(p, q_prev));
        opw::solve_branch_batch_into(p, k, &target.frot, &pos, branch, level, batch);
        if q_prev.len() == 6 {
            batch.prev.copy_from_slice(q_prev);
        }
        true
    }

    /// [`IkSolver::solve_near_batch_lanes`] of two consecutive batches at once
    /// ([`opw::solve_branch_pair_into`]): `batches[0]` for the tips `tp[0]` (its first
    /// `counts[0]` lanes) exactly as `solve_near_batch_lanes(target, tp[0], counts[0], q_prev,
    /// branch, level, ..)` makes it, and `batches[1]` solved ahead for the tips `tp[1]` (first
    /// `counts[1]` lanes) with the same branch, for [`IkSolver::presolved_or_solve`] to take
    /// once its `q_prev` is known. `false` (batches untouched) where `solve_near_batch_lanes`
    /// gives `false`.
    #[allow(clippy::too_many_arguments)]
    pub fn solve_near_batch_pair_lanes(
        &self,
        target: &PathTarget,
        tp: [&[[f64; crate::simd::LANES]; 3]; 2],
        counts: [usize; 2],
        q_prev: &[f64],
        branch: Option<Branch>,
        level: crate::simd::Level,
        batches: [&mut opw::BranchBatch; 2],
    ) -> bool {
        let Some((p, k)) = self.opw_continuing(q_prev) else {
            return false;
        };
        // As solve_near_batch_lanes, batch by batch.
        let mut pos = [[0.0; opw::PAIR_LANES]; 3];
        for (g, (tp, &count)) in tp.iter().zip(&counts).enumerate() {
            Self::flange_block(&mut pos, g * crate::simd::LANES, &target.off, tp, count);
        }
        let branch = branch.unwrap_or_else(|| k.branch_of(p, q_prev));
        let [b0, b1] = batches;
        opw::solve_branch_pair_into(p, k, &target.frot, &pos, branch, level, [&mut *b0, b1]);
        if q_prev.len() == 6 {
            b0.prev.copy_from_slice(q_prev);
        }
        true
    }

    /// [`IkSolver::solve_near_batch_lanes`]`(target, tp, count, q_prev, branch, level, batch)`
    /// for a `batch` that [`IkSolver::solve_near_batch_pair_lanes`] solved ahead (as its second
    /// batch) for these tips: where the branch `solve_near_batch_lanes` would take (`branch`,
    /// else [`opw::Prepared::branch_of`]`(q_prev)`) is the one it was solved for, the batch is
    /// that answer already, bit for bit (no lane depends on `q_prev`), and only its
    /// [`opw::BranchBatch::prev`] is set; otherwise it is solved afresh for that branch.
    #[allow(clippy::too_many_arguments)]
    pub fn presolved_or_solve(
        &self,
        target: &PathTarget,
        tp: &[[f64; crate::simd::LANES]; 3],
        count: usize,
        q_prev: &[f64],
        branch: Option<Branch>,
        level: crate::simd::Level,
        batch: &mut opw::BranchBatch,
    ) -> bool {
        let Some((p, k)) = self.opw_continuing(q_prev) else {
            return false;
        };
        let branch = branch.unwrap_or_else(|| k.branch_of(p, q_prev));
        if batch.branch != branch {
            return self.solve_near_batch_lanes(
                target,
                tp,
                count,
                q_prev,
                Some(branch),
                level,
                batch,
            );
        }
        batch.prev = [f64::NAN; 6];
        if q_prev.len() == 6 {
            batch.prev.copy_from_slice(q_prev);
        }
        true
    }

    /// The answer of lane `lane` of `batch` for `tool_target` (its tip and orientation must be
    /// the ones [`IkSolver::solve_near_batch`] was given), continuing `q_prev`: exactly
    /// [`IkSolver::solve_near_unchecked`]`(tool_target, q_prev)`. The lane's closed form (both
    /// wrist variants come from it) is used when `q_prev` continues the batch's branch and the
    /// lane has an answer within limits; otherwise the sample is solved afresh.
    #[inline]
    pub fn take_near(
        &self,
        batch: &opw::BranchBatch,
        lane: usize,
        tool_target: &Frame,
        q_prev: &[f64],
    ) -> Result<JointVec, IkFailure> {
        if let (Some(p), Some(k)) = (&self.model.opw, &self.opw_k) {
            if batch.ok[lane]
                && q_prev.len() == self.model.dof()
                && batch
                    .known_branch(lane, q_prev)
                    .unwrap_or_else(|| k.branch_of(p, q_prev))
                    == batch.branch
            {
                // solve_near_opw's choice between the two wrist variants, from the lane.
                let b = batch.branch;
                let fit = |w: Wrist| {
                    let mut q = JointVec::from_slice(&batch.variant(p, lane, w));
                    self.limits.fit(self.model, &mut q, Some(q_prev)).map(|_| q)
                };
                let first = fit(b.wrist);
                let dist = |q: &JointVec| {
                    q.iter()
                        .zip(q_prev)
                        .map(|(a, b)| (a - b).abs())
                        .fold(0.0, f64::max)
                };
                if let Ok(q) = &first {
                    if batch.s5[lane] > NEAR_WRIST_SINGULARITY {
                        return Ok(*q);
                    }
                    // The flipped variant cannot be nearer (see FLIP_CANNOT_WIN_RAD): skip
                    // its fit.
                    if self.flip_bound && dist(q) <= FLIP_CANNOT_WIN_RAD {
                        return Ok(*q);
                    }
                }
                match (first, fit(b.wrist.flipped())) {
                    (Ok(q1), Ok(q2)) => return Ok(if dist(&q2) < dist(&q1) { q2 } else { q1 }),
                    (Ok(q), Err(_)) | (Err(_), Ok(q)) => return Ok(q),
                    // Both fail: the per-sample path gives the error it reports.
                    (Err(_), Err(_)) => {}
                }
            }
        }
        self.solve_near_unchecked(tool_target, q_prev)
    }

    /// How many leading lanes (of the first `count`) of `batch` (from
    /// [`IkSolver::solve_near_batch`] with `q_prev`) path tracking can take at once, decided in
    /// lockstep, with their answers, into `out`: lane `l` continues lane `l − 1`'s answer (lane 0
    /// `q_prev`), and for each taken lane the answer is provably [`IkSolver::take_near`]'s,
    /// bit for bit, and its step from the previous answer is within `max_step` (rad per
    /// joint; not checked at lane 0 unless `step_at_first`). The conditions: the lane is
    /// `ok`; its branch is the batch's (lane 0: `q_prev` is the batch's own; later lanes:
    /// [`opw::BranchBatch::next_branch`], or `branch_of` of the previous fitted answer in
    /// lockstep where the fit moved a joint it reads); the limit fit of the lane's wrist
    /// variant ([`LimitTable::fit`], in lockstep, its 2π shifts included) accepts it; and
    /// either `|sin q5| >` [`NEAR_WRIST_SINGULARITY`] or the flipped variant cannot be nearer
    /// ([`FLIP_CANNOT_WIN_RAD`]), so `take_near` returns this one. Every lane from the first
    /// that fails a condition is for `take_near`.
    #[allow(clippy::too_many_arguments)]
    pub fn continuing_lanes(
        &self,
        batch: &opw::BranchBatch,
        count: usize,
        q_prev: &[f64],
        max_step: &[f64; MAX_DOF],
        step_at_first: bool,
        level: crate::simd::Level,
        out: &mut Continuing,
    ) {
        use crate::simd::LANES;
        out.taken = 0;
        out.branch_after = batch.branch;
        if self.model.dof() != 6 || self.limits.n != 6 || q_prev.len() != 6 {
            return;
        }
        // Lane 0 continues q_prev only if the batch was solved from it (bit for bit).
        if batch.known_branch(0, q_prev) != Some(batch.branch) {
            return;
        }
        let count = count.min(LANES);
        struct K<'a, 's> {
            solver: &'a IkSolver<'s>,
            batch: &'a opw::BranchBatch,
            count: usize,
            q_prev: &'a [f64],
            max_step: &'a [f64; MAX_DOF],
            step_at_first: bool,
            out: &'a mut Continuing,
        }
        impl crate::simd::Kernel for K<'_, '_> {
            type Out = ();
            #[inline(always)]
            fn run<R: crate::simd::F64s>(self) {
                self.solver.continuing_body::<R>(
                    self.batch,
                    self.count,
                    self.q_prev,
                    self.max_step,
                    self.step_at_first,
                    self.out,
                )
            }
        }
        crate::simd::dispatch(
            level,
            K {
                solver: self,
                batch,
                count,
                q_prev,
                max_step,
                step_at_first,
                out,
            },
        )
    }

    /// The per-lane verdicts of [`IkSolver::continuing_lanes`] (6 joints), the answers joint
    /// by joint, and the branch of each lane's answer, in lockstep.
    #[allow(clippy::needless_range_loop)] // lanes of parallel fixed arrays
    #[inline(always)]
    fn continuing_body<R: crate::simd::F64s>(
        &self,
        batch: &opw::BranchBatch,
        count: usize,
        q_prev: &[f64],
        max_step: &[f64; MAX_DOF],
        step_at_first: bool,
        out: &mut Continuing,
    ) {
        use crate::simd::LANES;
        // Per-lane verdicts as bit masks (bit l: lane l), combined in scalar registers.
        const ALL: u32 = (1 << LANES) - 1;
        let fitted: &mut [[f64; LANES]; 6] =
            (&mut out.q[..6]).try_into().expect("6 of MAX_DOF rows");
        let t = &self.limits;
        let mut ok = 0u32;
        for l in 0..LANES {
            ok |= u32::from(batch.ok[l]) << l;
        }
        // Lanes with a step over max_step (as track's jump test: NaN is none).
        let mut over = 0u32;
        let mut dist = [0.0f64; LANES];
        let mut shifted = false;
        for j in 0..6 {
            let v = &batch.qj[j];
            // Each lane's fit is centred on the previous lane's fitted answer (lane 0:
            // q_prev). Where every lane takes the fit's fast path (the common case) that is
            // the previous lane's value as it is.
            let mut centre = [0.0; LANES];
            centre[0] = q_prev[j];
            centre[1..].copy_from_slice(&v[..LANES - 1]);
            let inside = lane_ops::inside::<R>(v, &centre, t.lower[j], t.upper[j]);
            let fb = if t.revolute[j] && inside == ALL {
                *v
            } else {
                // Guess the centres by fitting every lane about q_prev (a), fit again about
                // the guesses (b): where the two agree bit for bit along the lanes, (b) is
                // the chained fit.
                let (fa, oka) = t.fit_lanes(j, v, &[q_prev[j]; LANES]);
                centre[1..].copy_from_slice(&fa[..LANES - 1]);
                let (fb, okb) = t.fit_lanes(j, v, &centre);
                let mut agree = 0u32;
                let mut moved = 0u32;
                for l in 0..LANES {
                    let same = fa[l].to_bits() == fb[l].to_bits();
                    agree |= u32::from((oka[l] & okb[l] != 0) & same) << l;
                    moved |= u32::from(fb[l].to_bits() != v[l].to_bits()) << l;
                }
                ok &= agree;
                // branch_of reads joints 2, 3 and 5 only (OPW q2, q3, q5).
                shifted |= matches!(j, 1 | 2 | 4) && moved != 0;
                fb
            };
            over |= lane_ops::step::<R>(&fb, &centre, max_step[j], &mut dist);
            fitted[j] = fb;
        }
        let mut step = !over;
        if !step_at_first {
            step |= 1;
        }
        // The branch of each lane's answer: the batch's of the unfitted answers (the same
        // bits where the fit moved none of the joints branch_of reads), or again of the
        // fitted ones.
        let next = match (&self.model.opw, &self.opw_k) {
            (Some(p), Some(k)) if shifted => opw::branch_of_joints(p, k, fitted),
            _ => batch.next_branch,
        };
        let wrist_ok = lane_ops::wrist_ok::<R>(&batch.s5, &dist, self.flip_bound);
        let mut branch_ok = 1u32;
        for l in 1..LANES {
            branch_ok |= u32::from(next[l - 1] == batch.branch) << l;
        }
        let taken = ok & step & wrist_ok & branch_ok;
        // The leading taken lanes, at most count.
        let t = ((!taken).trailing_zeros() as usize).min(count);
        out.taken = t;
        if t > 0 {
            out.branch_after = next[t - 1];
        }
    }

    /// The FK re-check of `count ≤` [`crate::simd::LANES`] answers in lockstep, all for tool
    /// poses of `target`'s orientation ([`IkSolver::path_target`]): lane `l` is the joint
    /// vector `q[j][l]` (rad) for the tip `tips[l]` (m); the sines then the cosines of each
    /// answer go to `sincos[l · 2 dof ..]` (as [`IkSolver::solve_near_with_sincos`] writes
    /// them). The verdicts, errors and sines are [`IkSolver::check_with_sincos`]'s, bit for
    /// bit. Errors with the first failing lane. Only for a [`IkSolver::batch_checkable`]
    /// solver.
    pub fn check_lanes(
        &self,
        count: usize,
        q: &[[f64; crate::simd::LANES]; MAX_DOF],
        target: &PathTarget,
        tips: &[V3],
        sincos: &mut [f64],
        level: crate::simd::Level,
    ) -> Result<(), (usize, IkFailure)> {
        assert!(
            self.chain.batchable(),
            "check_lanes on a chain it does not apply to"
        );
        self.check_lanes_dispatch(count, q, target, tips, None, Out::Slice(sincos), level)
    }

    /// [`IkSolver::check_lanes`] that appends the sines and cosines of the `count` answers
    /// to `sincos` (`count · 2 dof` values, the same as `check_lanes` writes) when all pass,
    /// and leaves it as it was on an error: no zero fill ahead of the values. `tp` holds the
    /// tips lane by lane (`tp[i][lane] == tips[lane][i]`, m).
    #[allow(clippy::too_many_arguments)]
    pub fn check_lanes_push(
        &self,
        count: usize,
        q: &[[f64; crate::simd::LANES]; MAX_DOF],
        target: &PathTarget,
        tips: &[V3],
        tp: &[[f64; crate::simd::LANES]; 3],
        sincos: &mut Vec<f64>,
        level: crate::simd::Level,
    ) -> Result<(), (usize, IkFailure)> {
        assert!(
            self.chain.batchable(),
            "check_lanes on a chain it does not apply to"
        );
        self.check_lanes_dispatch(count, q, target, tips, Some(tp), Out::Push(sincos), level)
    }

    /// [`IkSolver::check_lanes_with`] at the register width of `level`: the one kernel behind
    /// [`IkSolver::check_lanes`] and [`IkSolver::check_lanes_push`].
    #[allow(clippy::too_many_arguments)]
    fn check_lanes_dispatch(
        &self,
        count: usize,
        q: &[[f64; crate::simd::LANES]; MAX_DOF],
        target: &PathTarget,
        tips: &[V3],
        tp: Option<&[[f64; crate::simd::LANES]; 3]>,
        out: Out<'_>,
        level: crate::simd::Level,
    ) -> Result<(), (usize, IkFailure)> {
        struct K<'a, 's, 'o> {
            solver: &'a IkSolver<'s>,
            count: usize,
            q: &'a [[f64; crate::simd::LANES]; MAX_DOF],
            target: &'a PathTarget,
            tips: &'a [V3],
            tp: Option<&'a [[f64; crate::simd::LANES]; 3]>,
            out: Out<'o>,
        }
        impl crate::simd::Kernel for K<'_, '_, '_> {
            type Out = Result<(), (usize, IkFailure)>;
            #[inline(always)]
            fn run<R: crate::simd::F64s>(self) -> Self::Out {
                self.solver.check_lanes_with::<R>(
                    self.count,
                    self.q,
                    self.target,
                    self.tips,
                    self.tp,
                    self.out,
                )
            }
        }
        crate::simd::dispatch(
            level,
            K {
                solver: self,
                count,
                q,
                target,
                tips,
                tp,
                out,
            },
        )
    }

    /// The body of [`IkSolver::check_lanes`] on the registers `R` (inlined into the dispatch,
    /// so compiled for their instruction set).
    #[allow(clippy::needless_range_loop)] // lanes of parallel fixed arrays
    #[inline(always)]
    fn check_lanes_with<R: crate::simd::F64s>(
        &self,
        count: usize,
        q: &[[f64; crate::simd::LANES]; MAX_DOF],
        target: &PathTarget,
        tips: &[V3],
        tp_in: Option<&[[f64; crate::simd::LANES]; 3]>,
        sincos: Out<'_>,
    ) -> Result<(), (usize, IkFailure)> {
        use crate::simd::LANES;
        let n = self.model.dof();
        let count = count.min(LANES).min(tips.len());
        // The lanes that pass with room to spare are decided in lockstep on a pose within
        // fk::CHECK_POSE_BOUND of the exact one: position error below tol/2 − that bound,
        // orientation measure of rotation_distance_fast below min(1e-8, tol/2)/2 − the
        // bound (its small-angle branch), where the exact pose passes check_pose for sure.
        // Every other lane (and NaN) goes through the per-sample check itself, on the exact
        // pose: the same verdicts and errors as check_with_sincos.
        let mut built = [[0.0; LANES]; 3];
        let tp = match tp_in {
            Some(tp) => tp,
            None => {
                for (l, t) in tips.iter().take(count).enumerate() {
                    for i in 0..3 {
                        built[i][l] = t[i];
                    }
                }
                &built
            }
        };
        let bound = fk::CHECK_POSE_BOUND;
        let dp_max = 0.5 * self.check_position_m - bound;
        let dp2_max = dp_max * dp_max;
        let h_max = 0.5 * (1e-8f64).min(0.5 * self.check_orientation_rad) - bound;
        let f2_max = 8.0 * h_max * h_max;
        let room = dp_max > 0.0 && h_max > 0.0;
        let judge = |cl: &fk::CheckLanes| {
            let mut clear = [0u64; LANES];
            for l in 0..LANES {
                clear[l] = u64::from((cl.dp2[l] < dp2_max) & (cl.f2[l] < f2_max));
            }
            for l in 0..count {
                if !(room && clear[l] != 0) {
                    let mut ql = [0.0; MAX_DOF];
                    for (j, v) in ql.iter_mut().enumerate().take(n) {
                        *v = q[j][l];
                    }
                    let mut sc = [0.0; 2 * MAX_DOF];
                    self.check_with_sincos(
                        &Frame {
                            rot: target.rot,
                            pos: tips[l],
                        },
                        &ql[..n],
                        &mut sc[..2 * n],
                    )
                    .map_err(|e| (l, e))?;
                }
            }
            match sincos {
                Out::Slice(sincos) => {
                    for (l, out) in sincos.chunks_exact_mut(2 * n).take(count).enumerate() {
                        let (so, co) = out.split_at_mut(n);
                        for j in 0..n {
                            so[j] = cl.s[j][l];
                            co[j] = cl.c[j][l];
                        }
                    }
                }
                Out::Push(sincos) => {
                    // Appended sample by sample: the sines, then the cosines.
                    let mut rows = [&cl.s[0]; 2 * MAX_DOF];
                    for j in 0..n {
                        (rows[j], rows[n + j]) = (&cl.s[j], &cl.c[j]);
                    }
                    crate::simd::push_transposed::<R>(sincos, &rows[..2 * n], count);
                }
            }
            Ok(())
        };
        self.chain
            .measure_then::<R, _>(q, &target.check_rot, tp, judge)
    }

    /// The FK re-check of `count ≤` [`crate::simd::LANES`] answers in lockstep: lane `l` is the
    /// joint vector `q(l)` (rad) for the tool pose `target(l)`; the sines and cosines of
    /// each answer go to `sincos(l)` (length `2 dof`, as
    /// [`IkSolver::solve_near_with_sincos`] writes them). The verdicts and the sines are
    /// those of [`IkSolver::check_with_sincos`], bit for bit (the same operations per lane).
    /// Errors with the first failing lane and its [`IkFailure::CheckFailed`]. Only for a
    /// [`IkSolver::batch_checkable`] solver.
    #[allow(clippy::needless_range_loop)] // lanes of parallel fixed arrays
    pub fn check_batch<'q>(
        &self,
        count: usize,
        target: impl Fn(usize) -> Frame,
        q: impl Fn(usize) -> &'q [f64],
        mut sincos: impl FnMut(usize) -> &'q mut [f64],
        level: crate::simd::Level,
    ) -> Result<(), (usize, IkFailure)> {
        use crate::simd::LANES;
        let n = self.model.dof();
        let count = count.min(LANES);
        let mut qb = [[0.0; LANES]; MAX_DOF];
        for l in 0..count {
            for (lanes, v) in qb.iter_mut().zip(q(l).iter().take(n)) {
                lanes[l] = *v;
            }
        }
        let tb = self.chain.tool_batch(&qb, level);
        // The verdicts of the lanes that pass with room to spare, in lockstep: the squared
        // position error below (tol/2)² and the orientation measure of
        // rotation_distance_fast below min(1e-8, tol/2)/2 (its small-angle branch), where no
        // rounding difference can change check_pose's verdict. Every other lane (and NaN)
        // goes through check_pose itself.
        let (mut tp, mut tr) = ([[0.0; LANES]; 3], [[0.0; LANES]; 9]);
        for l in 0..count {
            let t = target(l);
            for i in 0..3 {
                tp[i][l] = t.pos[i];
            }
            for (i, v) in t.rot.iter().enumerate() {
                tr[i][l] = *v;
            }
        }
        let dp_max = 0.5 * self.check_position_m;
        let dp2_max = dp_max * dp_max;
        let h_max = 0.5 * (1e-8f64).min(0.5 * self.check_orientation_rad);
        let f2_max = 8.0 * h_max * h_max;
        let mut clear = [false; LANES];
        for (l, c) in clear.iter_mut().enumerate() {
            let mut dp2 = 0.0;
            for i in 0..3 {
                let d = tb.pos[i][l] - tp[i][l];
                dp2 += d * d;
            }
            let mut f2 = 0.0;
            for i in 0..9 {
                // Column-major, as M3::iter.
                let d = tb.rot[i % 3][i / 3][l] - tr[i][l];
                f2 += d * d;
            }
            *c = dp_max > 0.0 && h_max > 0.0 && dp2 < dp2_max && f2 < f2_max;
        }
        for l in 0..count {
            if !clear[l] {
                self.check_pose(&target(l), &tb.frame(l))
                    .map_err(|e| (l, e))?;
            }
            let out = sincos(l);
            for j in 0..n {
                out[j] = tb.s[j][l];
                out[n + j] = tb.c[j][l];
            }
        }
        Ok(())
    }

    /// The closed-form part of [`IkSolver::solve_near`]: joints fitted to the limits, not yet
    /// FK-checked.
    #[inline]
    fn solve_near_opw(
        &self,
        p: &crate::robot::OpwParams,
        k: &opw::Prepared,
        tool_target: &Frame,
        q_prev: &[f64],
    ) -> Result<JointVec, IkFailure> {
        let flange = self.flange_target(tool_target);
        // Keep the shoulder and elbow of q_prev; of the two wrist variants take the one nearer
        // to q_prev, so that a smooth passage through q5 = 0 stays smooth.
        let b = k.branch_of(p, q_prev);
        let solve = |br: Branch| -> Result<(JointVec, f64), IkFailure> {
            let (q, s5) = opw::solve_branch_prepared(p, k, &flange, br, Some(q_prev))?;
            let mut q = JointVec::from_slice(&q);
            self.limits.fit(self.model, &mut q, Some(q_prev))?;
            Ok((q, s5))
        };
        let dist = |q: &JointVec| {
            q.iter()
                .zip(q_prev)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
        };
        let first = solve(b);
        if let Ok((q, s5)) = &first {
            // Far from the wrist singularity the flipped variant differs by about π in q4 and
            // q6 and cannot be nearer: skip it (the fast path).
            if *s5 > NEAR_WRIST_SINGULARITY {
                return Ok(*q);
            }
        }
        let flip = Branch {
            wrist: b.wrist.flipped(),
            ..b
        };
        let second = solve(flip);
        match (first, second) {
            (Ok((q1, _)), Ok((q2, _))) => Ok(if dist(&q2) < dist(&q1) { q2 } else { q1 }),
            (Ok((q, _)), Err(_)) | (Err(_), Ok((q, _))) => Ok(q),
            (Err(e1), Err(e2)) => {
                // Both variants violate limits: report the unflipped one. Otherwise the first
                // failure that is not a joint limit, after the general reachability check.
                let e = match (&e1, &e2) {
                    (IkFailure::JointLimit { .. }, IkFailure::JointLimit { .. }) => e1,
                    (IkFailure::JointLimit { .. }, _) => e2,
                    _ => e1,
                };
                if !matches!(e, IkFailure::JointLimit { .. }) {
                    self.precheck(tool_target)?;
                }
                Err(e)
            }
        }
    }

    /// The spin (rad, about the vertical nozzle axis) on an `n_grid` grid over (−π, π] whose
    /// solution maximises `score(q)`: with `q_prev` the solution continuing it, otherwise every
    /// solution of [`IkSolver::solve_all`]. `None` when no spin is reachable.
    pub fn best_spin<F: Fn(&[f64]) -> f64>(
        &self,
        tip: &V3,
        q_prev: Option<&[f64]>,
        n_grid: usize,
        score: F,
    ) -> Option<SpinChoice> {
        let mut best: Option<SpinChoice> = None;
        let mut consider = |spin: f64, q: JointVec| {
            let s = score(&q);
            if s.is_finite() && best.as_ref().is_none_or(|b| s > b.score) {
                best = Some(SpinChoice { spin, q, score: s });
            }
        };
        for k in 0..n_grid.max(1) {
            let spin = -PI + 2.0 * PI * (k as f64 + 1.0) / n_grid.max(1) as f64;
            let t = nozzle_target(tip, spin);
            match q_prev {
                Some(qp) => {
                    if let Ok(q) = self.solve_near(&t, qp) {
                        consider(spin, q);
                    }
                }
                None => {
                    if let Ok(sols) = self.solve_all(&t) {
                        for s in sols {
                            consider(spin, s.q);
                        }
                    }
                }
            }
        }
        best
    }
}

/// Result of [`IkSolver::best_spin`].
#[derive(Clone, Copy, Debug)]
pub struct SpinChoice {
    /// Rotation about the nozzle axis, rad.
    pub spin: f64,
    /// Joint vector (rad / m).
    pub q: JointVec,
    /// The score of `q`.
    pub score: f64,
}

/// All solutions for a tool pose; see [`IkSolver::solve_all`].
pub fn solve_all(model: &RobotModel, tool_target: &Frame) -> Result<Vec<Solution>, IkFailure> {
    IkSolver::new(model)?.solve_all(tool_target)
}

/// The solution continuing `q_prev`; see [`IkSolver::solve_near`].
pub fn solve_near(
    model: &RobotModel,
    tool_target: &Frame,
    q_prev: &[f64],
) -> Result<JointVec, IkFailure> {
    IkSolver::new(model)?.solve_near(tool_target, q_prev)
}

pub use crate::frame::nozzle_target;

/// Joint-limit margin of `q` (dimensionless): the smallest distance to a limit as a fraction
/// of the joint's range; 0 at a limit, 0.5 at mid-range. Joints without finite limits count
/// as 0.5.
pub fn limit_margin(model: &RobotModel, q: &[f64]) -> f64 {
    model
        .joints
        .iter()
        .zip(q)
        .filter(|(j, _)| j.lower.is_finite() && j.upper.is_finite() && j.upper > j.lower)
        .map(|(j, &v)| (v - j.lower).min(j.upper - v) / (j.upper - j.lower))
        .fold(0.5, f64::min)
}

/// Singularity measures at one joint vector. Every measure is 0 at its singularity.
#[derive(Clone, Copy, Debug)]
pub struct SingularityMeasures {
    /// `|sin q5|` (dimensionless), OPW arms only.
    pub wrist: Option<f64>,
    /// `|sin(q3_opw + ψ3)|` (dimensionless; 0 = stretched out), OPW arms only.
    pub elbow: Option<f64>,
    /// Wrist-centre distance from the axis of joint 1 in the arm plane, m; OPW arms only.
    pub shoulder_m: Option<f64>,
    /// Smallest singular value of the tool Jacobian (mixed units, see [`jacobian_measures`]).
    pub sigma_min: f64,
    /// Manipulability `sqrt(det(J Jᵀ))` (mixed units).
    pub manipulability: f64,
}

/// All singularity measures at `q` (rad / m).
pub fn singularity_measures(model: &RobotModel, q: &[f64]) -> SingularityMeasures {
    let (sigma_min, manipulability) = jacobian_measures(model, q);
    let p = model.opw.as_ref().filter(|_| q.len() >= 6);
    SingularityMeasures {
        wrist: p.map(|p| opw::wrist_singularity(p, q)),
        elbow: p.map(|p| opw::elbow_singularity(p, q)),
        shoulder_m: p.map(|p| opw::shoulder_singularity(p, q)),
        sigma_min,
        manipulability,
    }
}

/// The lane verdicts of [`IkSolver::continuing_lanes`] as bit masks (bit `l`: lane `l`), a
/// register of `R` at a time: compares straight to masks. The same comparisons (ordered,
/// quiet: NaN fails each) on every register type, so the same verdicts on every level.
mod lane_ops {
    use crate::simd::{F64s, LANES};
    use std::f64::consts::PI;

    type Lanes = [f64; LANES];

    /// `(x ≥ lo) ∧ (x ≤ hi) ∧ (|x − c| < π)` per lane (`x` = `v`, `c` = `centre`).
    #[inline(always)]
    pub(super) fn inside<R: F64s>(v: &Lanes, centre: &Lanes, lo: f64, hi: f64) -> u32 {
        let (lo, hi, pi) = (R::splat(lo), R::splat(hi), R::splat(PI));
        let mut m = 0u32;
        for h in (0..LANES).step_by(R::W) {
            let x = R::load(&v[h..]);
            let d = x.sub(R::load(&centre[h..])).abs();
            m |= (x.ge(lo) & x.le(hi) & d.lt(pi)) << h;
        }
        m
    }

    /// `|fb − c| > max` per lane (`c` = `centre`), and `dist ← max(dist, |fb − c|)`
    /// (`f64::max`: a NaN step leaves `dist`).
    #[inline(always)]
    pub(super) fn step<R: F64s>(fb: &Lanes, centre: &Lanes, max: f64, dist: &mut Lanes) -> u32 {
        let max = R::splat(max);
        let mut m = 0u32;
        for h in (0..LANES).step_by(R::W) {
            let d = R::load(&fb[h..]).sub(R::load(&centre[h..])).abs();
            m |= d.gt(max) << h;
            R::load(&dist[h..]).max(d).store(&mut dist[h..]);
        }
        m
    }

    /// `(s5 > NEAR_WRIST_SINGULARITY) ∨ (flip_bound ∧ dist ≤ FLIP_CANNOT_WIN_RAD)`.
    #[inline(always)]
    pub(super) fn wrist_ok<R: F64s>(s5: &Lanes, dist: &Lanes, flip_bound: bool) -> u32 {
        let near = R::splat(super::NEAR_WRIST_SINGULARITY);
        let flip = R::splat(super::FLIP_CANNOT_WIN_RAD);
        let mut m = 0u32;
        for h in (0..LANES).step_by(R::W) {
            let far = R::load(&s5[h..]).gt(near);
            let near_ok = R::load(&dist[h..]).le(flip);
            m |= (far | if flip_bound { near_ok } else { 0 }) << h;
        }
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lane_wise_limit_verdicts_equal_the_per_vector_fit_on_every_level() {
        // LimitTable::accepts_lanes (branch_admits_batch's verdict for 8 lanes at once)
        // against LimitTable::fit without a reference, vector by vector: joint values inside,
        // at and past the limits (by the tolerance and by whole turns), past ±π, infinite and
        // NaN, on robots with wide-range joints. With rounding instructions (AVX2, AVX-512)
        // the same verdict per lane; without (scalar, SSE2) a lane it accepts is one fit
        // accepts.
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut s = 5u64;
        let mut u = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            2.0 * ((s >> 11) as f64 / (1u64 << 53) as f64) - 1.0
        };
        let (mut accepted, mut rejected) = (0, 0);
        for name in ["abb_irb6700_200_260", "staubli_tx200", "ur10e"] {
            let model = crate::robot::load(&root.join("robots").join(name)).unwrap();
            let table = LimitTable::new(&model);
            for case in 0..3000 {
                let mut qj = [[0.0; crate::simd::LANES]; 6];
                for (j, row) in qj.iter_mut().enumerate() {
                    let jt = &model.joints[j];
                    let (lo, hi) = (jt.lower.max(-10.0), jt.upper.min(10.0));
                    let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
                    for v in row.iter_mut() {
                        *v = match (case + j) % 9 {
                            0..=2 => mid + 0.8 * half * u(),
                            3 => mid + 1.3 * half * u(),
                            4 => {
                                if u() > 0.0 {
                                    hi + 2e-9 * u()
                                } else {
                                    lo + 2e-9 * u()
                                }
                            }
                            5 => mid + 0.9 * half * u() + TAU_TEST * (3.0 * u()).round(),
                            6 => std::f64::consts::PI * 1.2 * u(),
                            7 => [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 0.0][case % 4],
                            _ => 0.5 * u(),
                        };
                    }
                }
                for level in crate::simd::Level::ALL
                    .into_iter()
                    .filter(|l| l.available())
                {
                    let mask = table.accepts_lanes(&qj, level);
                    for l in 0..crate::simd::LANES {
                        let mut q = [0.0; 6];
                        for (v, row) in q.iter_mut().zip(&qj) {
                            *v = row[l];
                        }
                        let ok = table.fit(&model, &mut q, None).is_ok();
                        let got = mask >> l & 1 != 0;
                        if matches!(level, crate::simd::Level::Avx2 | crate::simd::Level::Avx512) {
                            assert_eq!(got, ok, "{name} case {case} lane {l} {level:?}");
                        } else {
                            assert!(!got || ok, "{name} case {case} lane {l} {level:?}");
                        }
                        if ok {
                            accepted += 1;
                        } else {
                            rejected += 1;
                        }
                    }
                }
            }
        }
        assert!(
            accepted > 10_000 && rejected > 10_000,
            "{accepted} {rejected}"
        );
    }

    const TAU_TEST: f64 = 2.0 * std::f64::consts::PI;
}
