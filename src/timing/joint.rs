//! From the Cartesian motion to the joint trajectory: inverse kinematics per sample with one
//! arm configuration held along the path, joint velocities, accelerations and jerks by
//! central differences, and the controller's answer to a joint limit: the path speed is
//! reduced where the limit binds (and, where the demand comes from a ramp, the acceleration
//! over that stretch only), then the motion is planned again ([`Slowing`]). Every reduction
//! is local and reported with where and by how much.

use super::geometry::Piece;
use super::profile::{nodes, plan_at_speeds, CartesianMotion, Nodes, ProfileOptions};
use crate::frame::Placement;
use crate::kinematics::{nozzle_target, IkFailure, IkSolver, JointVec};
use crate::math::{Frame, V3};
use crate::robot::RobotModel;
use crate::trajectory::JointTrajectory;
use serde::Serialize;
use std::sync::Arc;

/// Which limit bound.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LimitKind {
    /// Joint velocity limit (rad/s).
    Velocity,
    /// Joint acceleration limit (rad/s²).
    Acceleration,
    /// Joint jerk limit (rad/s³).
    Jerk,
}

/// A place where a joint limit made the controller slow down.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Slowdown {
    /// 0-based joint index.
    pub joint: usize,
    /// Which limit.
    pub kind: LimitKind,
    /// Time of the worst sample in the first plan that violated it, s.
    pub t: f64,
    /// Path position (arc length) there, m.
    pub s: f64,
    /// Programmed move index (0-based) there.
    pub move_index: usize,
    /// Demand over limit before the slow-down (> 1).
    pub ratio: f64,
    /// Path speed there after the slow-downs, as a share of the unslowed plan's (≤ 1; 1 when
    /// only the acceleration was lowered).
    pub speed_factor: f64,
    /// Ramp acceleration (and jerk) there after the slow-downs, as a share of the profile's
    /// (≤ 1; 1 when only the speed was capped): lowered where the demand came from a ramp,
    /// over that stretch of path only.
    pub accel_factor: f64,
}

/// Hard cap on the planning rounds, as a multiple of [`JointStageOptions::max_iterations`]
/// (see [`replan_again`]).
pub(crate) const EXTRA_ROUNDS_FACTOR: usize = 4;

/// Whether the controller plans again after round `round` (1-based) left `count` samples
/// over a joint limit, `fewest` being the fewest any earlier round left (`usize::MAX` after
/// the first). Within `max_rounds` rounds it always does. Past them it goes on while it makes
/// progress, no round leaving more than 16 times as many samples over a limit as the fewest
/// before it (the count wanders as excesses move on), up to
/// [`EXTRA_ROUNDS_FACTOR`] × `max_rounds` rounds: on dense paths (many short moves) each
/// round's local slow-downs shift a few ramps, which may bind again a little further on, so
/// the excesses die out over more rounds than a path of long moves needs; from round
/// `max_rounds` on the rule also aims further below the limits ([`round_margin`]).
/// With `max_rounds` = 1 no round is added.
pub(crate) fn replan_again(round: usize, max_rounds: usize, count: usize, fewest: usize) -> bool {
    round < max_rounds
        || (max_rounds > 1
            && count <= fewest.saturating_mul(16)
            && round < EXTRA_ROUNDS_FACTOR * max_rounds)
}

/// The margin the slow-down rule aims at in round `round` (1-based) of `max_rounds`: `margin`
/// in the allowed rounds, then `margin²`, `margin³`, … each further `max_rounds` rounds, so
/// that excesses that keep appearing on a dense path are pushed further below the limit.
pub(crate) fn round_margin(margin: f64, round: usize, max_rounds: usize) -> f64 {
    let extra = round / max_rounds.max(1);
    margin.powi(1 + i32::try_from(extra).unwrap_or(i32::MAX).min(8))
}

/// Sample stride of the first, coarse pass of the reach prune (see
/// [`JointStageOptions::prune_stride`]).
const PRUNE_COARSE_STRIDE: usize = 64;

/// Chunks of [`crate::simd::LANES`] samples the reach prune maps to the base frame at a time.
const PRUNE_BLOCK: usize = 8;

/// Options of the joint stage.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct JointStageOptions {
    /// Re-planning rounds before giving up.
    pub max_iterations: usize,
    /// Target fraction of a limit after a slow-down (e.g. 0.95).
    pub margin: f64,
    /// Check jerk limits too.
    pub check_jerk: bool,
    /// Prune before tracking (0 = off): reject a placement at once when a path sample's
    /// wrist centre is out of the arm's reach ([`IkSolver::reachable`], every sample), and skip
    /// an arm configuration when its shoulder/elbow branch cannot reach every
    /// `prune_stride`-th sample within joint limits ([`IkSolver::branch_admits`]). Both are
    /// necessary conditions of tracking, so the outcome (timed path, or infeasible) is the
    /// same as without pruning; only which sample an infeasible placement is reported at
    /// may differ.
    pub prune_stride: usize,
}

impl Default for JointStageOptions {
    fn default() -> Self {
        JointStageOptions {
            max_iterations: 12,
            margin: 0.95,
            check_jerk: true,
            prune_stride: 8,
        }
    }
}

/// Why a path could not be timed at a placement. Each names the sample and where it is.
#[derive(Clone, Debug, PartialEq)]
pub enum TimingFailure {
    /// No IK solution at a sample.
    Unreachable {
        /// Sample index.
        sample: usize,
        /// Time, s.
        t: f64,
        /// TCP in the base frame, m.
        point: V3,
        /// Source line of the move.
        line: usize,
        /// The IK's reason.
        reason: IkFailure,
        /// Source file of the path (empty when unknown).
        file: std::sync::Arc<String>,
    },
    /// Holding one configuration needs a jump (wrist flip or branch change) between samples.
    ConfigurationChange {
        /// Sample index where the jump happens.
        sample: usize,
        /// Time, s.
        t: f64,
        /// TCP in the base frame, m.
        point: V3,
        /// Source line of the move.
        line: usize,
        /// Joint that jumps (0-based) and by how much, rad.
        joint: usize,
        /// The jump, rad.
        jump: f64,
        /// Source file of the path (empty when unknown).
        file: std::sync::Arc<String>,
    },
    /// Joint limits still exceeded after the allowed re-planning rounds.
    LimitsNotMet {
        /// Joint (0-based).
        joint: usize,
        /// Which limit.
        kind: LimitKind,
        /// Demand over limit.
        ratio: f64,
        /// Time, s.
        t: f64,
        /// Sample index of the last plan where the worst excess is.
        sample: usize,
        /// Source line of the move there.
        line: usize,
        /// Re-planning rounds run.
        rounds: usize,
        /// Source file of the path (empty when unknown).
        file: std::sync::Arc<String>,
    },
}

/// `line 12 of wall.gcode`, or `line 12` when the file is unknown.
fn line_in(line: usize, file: &str) -> String {
    if file.is_empty() {
        format!("line {line}")
    } else {
        format!("line {line} of {file}")
    }
}

impl TimingFailure {
    /// The failure with the path's source file named (kept when one is named already).
    pub(crate) fn in_file(mut self, source: &str) -> TimingFailure {
        let (TimingFailure::Unreachable { file, .. }
        | TimingFailure::ConfigurationChange { file, .. }
        | TimingFailure::LimitsNotMet { file, .. }) = &mut self;
        if file.is_empty() {
            *file = std::sync::Arc::new(source.to_string());
        }
        self
    }

    /// Source line of the move where timing failed.
    pub fn line(&self) -> usize {
        match self {
            TimingFailure::Unreachable { line, .. }
            | TimingFailure::ConfigurationChange { line, .. }
            | TimingFailure::LimitsNotMet { line, .. } => *line,
        }
    }
}

impl std::fmt::Display for TimingFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TimingFailure::Unreachable { sample, t, point, line, reason, file, .. } => write!(
                f,
                "path sample {sample} (t = {t:.3} s, move on {}) at ({:.4}, {:.4}, {:.4}) m is unreachable: {reason}",
                line_in(*line, file), point.x, point.y, point.z
            ),
            TimingFailure::ConfigurationChange { sample, t, point, line, joint, jump, file } => write!(
                f,
                "holding one arm configuration fails at path sample {sample} (t = {t:.3} s, move on {}, ({:.4}, {:.4}, {:.4}) m): joint {} would jump {:.1} deg (wrist flip or branch change)",
                line_in(*line, file), point.x, point.y, point.z, joint + 1, jump.to_degrees()
            ),
            TimingFailure::LimitsNotMet { joint, kind, ratio, t, sample, line, rounds, file } => write!(
                f,
                "joint {} {kind:?} limit still exceeded ({ratio:.2}x) at path sample {sample} (t = {t:.3} s, move on {}) after re-planning {rounds} times",
                joint + 1, line_in(*line, file)
            ),
        }
    }
}

/// A path timed at a placement.
#[derive(Clone, Debug)]
pub struct TimedPath {
    /// The joint trajectory (t, q, q̇, q̈) at the interpolation period.
    pub traj: JointTrajectory,
    /// The Cartesian motion in the part frame it follows (shared with the job's [`Plan`] when
    /// no joint limit made the controller slow down).
    pub motion: Arc<CartesianMotion>,
    /// TCP in the base frame per sample, m.
    pub tcp: Vec<V3>,
    /// Where joint limits slowed the path.
    pub slowdowns: Vec<Slowdown>,
    /// Planning rounds used (1 = no limit bound).
    pub rounds: usize,
    /// Lowest acceleration factor applied anywhere along the path (1 = none). The
    /// acceleration is lowered only over the stretches where a ramp made a limit bind (see
    /// [`Slowing`]); elsewhere the profile's acceleration holds.
    pub accel_factor: f64,
}

/// IK along the motion (part frame) at the placement `at`, continuing from `q0` (rad / m);
/// fills `buf.qs` (row-major joint positions), `buf.sincos` (their sines and cosines, from
/// the IK's FK re-check) and `buf.tcp` (base frame, m).
pub fn track(
    solver: &IkSolver,
    pieces: &[Piece],
    moves_line: &dyn Fn(usize) -> usize,
    motion: &CartesianMotion,
    at: &Placement,
    q0: &[f64],
    buf: &mut Buffers,
) -> Result<(), TimingFailure> {
    track_with(solver, pieces, moves_line, motion, at, q0, buf, None)
}

/// [`track`], with the base-frame tips of `motion` at `at` already computed lane-wise when
/// `pre` is given ([`TipMap::lanes_of`] of every [`crate::simd::LANES`] samples in order, chunk `c`
/// holding samples `c · LANES ..`; the same values bit for bit, so the same result).
#[allow(clippy::too_many_arguments)]
pub(crate) fn track_with(
    solver: &IkSolver,
    pieces: &[Piece],
    moves_line: &dyn Fn(usize) -> usize,
    motion: &CartesianMotion,
    at: &Placement,
    q0: &[f64],
    buf: &mut Buffers,
    pre: Option<&[TipLanes]>,
) -> Result<(), TimingFailure> {
    let model = solver.model;
    let part_to_base = at.frame();
    // A step larger than this cannot be a continuous motion of one configuration.
    let mut max_step = [f64::INFINITY; crate::kinematics::MAX_DOF];
    for (m, j) in max_step.iter_mut().zip(&model.joints) {
        *m = if j.velocity_limit.is_finite() {
            (j.velocity_limit * motion.dt * 4.0).max(0.05)
        } else {
            0.5
        };
    }
    // The nozzle's orientation is the same at every sample: its sine and cosine once.
    let rot = nozzle_target(&V3::zeros(), at.nozzle_yaw()).rot;
    // With SIMD (crate::simd) the IK's FK re-check runs deferred, in lockstep batches of
    // LANES samples: the same verdicts and sines bit for bit, and a failing check is reported
    // at its sample ahead of any later failure, exactly as the per-sample check would.
    let level = crate::simd::level();
    let mut tr = Tracking {
        solver,
        pieces,
        moves_line,
        motion,
        n: model.dof(),
        rot,
        path_target: solver.path_target(&rot),
        max_step,
        level,
        batched: level != crate::simd::Level::Scalar && solver.batch_checkable(),
        transient: buf.transient_sincos,
        sc: [0.0; 2 * crate::kinematics::MAX_DOF],
        qs: std::mem::take(&mut buf.qs),
        tcp: std::mem::take(&mut buf.tcp),
        sincos: std::mem::take(&mut buf.sincos),
        base: 0,
        prev: JointVec::from_slice(q0),
    };
    tr.qs.clear();
    tr.tcp.clear();
    tr.sincos.clear();
    let res = if tr.batched {
        tr.run_batched(&part_to_base, pre)
    } else {
        tr.run_per_sample(&part_to_base)
    };
    buf.qs = tr.qs;
    buf.tcp = tr.tcp;
    buf.sincos = tr.sincos;
    res
}

/// The state of [`track_with`] along one path: what holds for every sample, and the buffers
/// being filled.
struct Tracking<'t, 's> {
    solver: &'t IkSolver<'s>,
    pieces: &'t [Piece],
    moves_line: &'t dyn Fn(usize) -> usize,
    motion: &'t CartesianMotion,
    /// Joints of the arm.
    n: usize,
    /// The nozzle's orientation in the base frame (the same at every sample).
    rot: crate::math::M3,
    path_target: crate::kinematics::PathTarget,
    /// Largest step per sample of a continuous motion of one configuration, per joint.
    max_step: [f64; crate::kinematics::MAX_DOF],
    level: crate::simd::Level,
    /// Whether the IK runs in lockstep batches with its FK re-check deferred.
    batched: bool,
    /// Keep no sines and cosines past the batch whose FK re-check needs them.
    transient: bool,
    /// The sines and cosines of one sample's answer (per-sample path).
    sc: [f64; 2 * crate::kinematics::MAX_DOF],
    /// Joint positions, row-major.
    qs: Vec<f64>,
    /// Tips in the base frame, m.
    tcp: Vec<V3>,
    /// The sines and cosines of the samples checked from `base` on.
    sincos: Vec<f64>,
    /// The sample `sincos` starts at (every sample before it checked and its sines dropped,
    /// with `transient`).
    base: usize,
    /// The last sample's answer.
    prev: JointVec,
}

/// Lane `l`'s tip of the batch tips `tp` (the same bits as the placement's frame applied).
#[inline]
fn lane_tip(tp: &TipLanes, l: usize) -> V3 {
    V3::new(tp[0][l], tp[1][l], tp[2][l])
}

/// The base-frame tips of `count` samples of `motion` from `k0`, lane by lane into `out`
/// (lanes from `count` on left as they were).
#[inline]
fn tips_into(
    motion: &CartesianMotion,
    part_to_base: &Frame,
    k0: usize,
    count: usize,
    out: &mut TipLanes,
) {
    for (l, pk) in motion.p[k0..k0 + count].iter().enumerate() {
        let t = part_to_base.apply(pk);
        (out[0][l], out[1][l], out[2][l]) = (t.x, t.y, t.z);
    }
}

impl Tracking<'_, '_> {
    /// The tip `tip` at sample `k` is out of reach: the failure, naming the move's line.
    fn unreachable(&self, k: usize, tip: V3, reason: IkFailure) -> TimingFailure {
        unreachable_sample(self.pieces, self.moves_line, self.motion, k, tip, reason)
    }

    /// Check the samples not yet checked, below `upto`, in lockstep batches.
    #[inline]
    fn check_pending(&mut self, upto: usize) -> Result<(), TimingFailure> {
        use crate::simd::LANES;
        let n = self.n;
        let base = self.base;
        let mut k0 = base + self.sincos.len() / (2 * n);
        while k0 < upto {
            let count = LANES.min(upto - k0);
            let mut qb = [[0.0; LANES]; crate::kinematics::MAX_DOF];
            for l in 0..count {
                for (lanes, v) in qb.iter_mut().zip(&self.qs[(k0 + l) * n..(k0 + l + 1) * n]) {
                    lanes[l] = *v;
                }
            }
            self.sincos.resize((k0 + count - base) * 2 * n, 0.0);
            if let Err((l, reason)) = self.solver.check_lanes(
                count,
                &qb,
                &self.path_target,
                &self.tcp[k0..k0 + count],
                &mut self.sincos[(k0 - base) * 2 * n..],
                self.level,
            ) {
                self.sincos.truncate((k0 - base) * 2 * n);
                return Err(self.unreachable(k0 + l, self.tcp[k0 + l], reason));
            }
            k0 += count;
        }
        Ok(())
    }

    /// One sample's answer by IkSolver::take_near from the batch `chunk` (batched) or solved
    /// with its check (per sample), its step checked; appended to the buffers.
    #[inline]
    fn sample(
        &mut self,
        k: usize,
        tip: V3,
        chunk: Option<&crate::kinematics::opw::BranchBatch>,
    ) -> Result<(), TimingFailure> {
        let n = self.n;
        let target = Frame {
            rot: self.rot,
            pos: tip,
        };
        let solved = if self.batched {
            match chunk {
                Some(b) => self
                    .solver
                    .take_near(b, k % crate::simd::LANES, &target, &self.prev),
                None => self.solver.solve_near_unchecked(&target, &self.prev),
            }
        } else {
            self.solver
                .solve_near_with_sincos(&target, &self.prev, &mut self.sc[..2 * n])
        };
        let q = match solved {
            Ok(q) => q,
            Err(reason) => {
                if self.batched {
                    self.check_pending(k)?;
                }
                return Err(self.unreachable(k, tip, reason));
            }
        };
        self.check_step(k, &target, &q)?;
        self.qs.extend_from_slice(&q[..n]);
        self.tcp.push(tip);
        self.prev = q;
        if !self.batched && !self.transient {
            self.sincos.extend_from_slice(&self.sc[..2 * n]);
        }
        Ok(())
    }

    /// The step from the last answer to `q` at sample `k` (tool target `target`): a joint
    /// that moves more than its largest step is a configuration change.
    #[inline]
    fn check_step(&mut self, k: usize, target: &Frame, q: &JointVec) -> Result<(), TimingFailure> {
        let n = self.n;
        let tip = target.pos;
        // The first joint whose step is too large (none: the common case, found in one
        // pass over the joints).
        // All MAX_DOF slots at once: beyond the robot's joints both vectors hold zeros and
        // the step limit is +inf.
        let jump = k > 0 && {
            let (a, b) = (q.padded(), self.prev.padded());
            let mut any = 0u8;
            for j in 0..crate::kinematics::MAX_DOF {
                any |= u8::from((a[j] - b[j]).abs() > self.max_step[j]);
            }
            any != 0
        };
        if !jump {
            return Ok(());
        }
        for j in 0..n {
            let d = (q[j] - self.prev[j]).abs();
            if d > self.max_step[j] {
                if self.batched {
                    // The per-sample path checked this sample's answer before its step.
                    self.check_pending(k)?;
                    self.solver
                        .check_with_sincos(target, q, &mut self.sc[..2 * n])
                        .map_err(|reason| self.unreachable(k, tip, reason))?;
                }
                let mi = self.pieces[self.motion.piece[k]].move_index;
                return Err(TimingFailure::ConfigurationChange {
                    sample: k,
                    t: k as f64 * self.motion.dt,
                    point: tip,
                    line: (self.moves_line)(mi),
                    file: std::sync::Arc::default(),
                    joint: j,
                    jump: d,
                });
            }
        }
        Ok(())
    }

    /// Every sample solved with its check, one by one.
    fn run_per_sample(&mut self, part_to_base: &Frame) -> Result<(), TimingFailure> {
        for (k, p) in self.motion.p.iter().enumerate() {
            self.sample(k, part_to_base.apply(p), None)?;
        }
        Ok(())
    }

    /// Batched: the closed form of the next LANES samples in lockstep; the leading lanes that
    /// provably continue one another unchanged (IkSolver::continuing_lanes: what take_near
    /// would return, within the step limits) are taken at once, the rest one by one with
    /// take_near exactly as solve_near would answer. Every sample of the batch is FK-checked
    /// before the next batch (in lockstep; straight from the lanes when all were taken at
    /// once), so a failing check is reported at its sample ahead of any later failure.
    fn run_batched(
        &mut self,
        part_to_base: &Frame,
        pre: Option<&[TipLanes]>,
    ) -> Result<(), TimingFailure> {
        use crate::simd::LANES;
        let n = self.n;
        let len = self.motion.p.len();
        // Exactly: a re-planned, longer path's buffers would otherwise double.
        self.qs.reserve_exact(len * n);
        self.tcp.reserve_exact(len);
        if !self.transient {
            self.sincos.reserve_exact(len * 2 * n);
        }
        // The batch's tips lane by lane when computed here (lanes from count on: stale,
        // ignored).
        let mut tp_now = [[0.0; LANES]; 3];
        let mut k0 = 0;
        let mut bt = Batches::new(self.level);
        // The tips computed before, when they cover the whole path (k0 is a multiple of LANES).
        let pre = pre.filter(|t| t.len() * LANES >= len);
        while k0 < len {
            let count = LANES.min(len - k0);
            // The tips lane by lane: the ones computed before (borrowed, not copied), or now.
            let tp: &TipLanes = match pre {
                Some(pre) => &pre[k0 / LANES],
                None => {
                    tips_into(self.motion, part_to_base, k0, count, &mut tp_now);
                    &tp_now
                }
            };
            let solved = bt.solve(self, part_to_base, pre, tp, k0, count);
            let chunk = solved.then_some(&bt.batches[bt.cur]);
            bt.cont.taken = 0;
            if let Some(b) = chunk {
                self.solver.continuing_lanes(
                    b,
                    count,
                    &self.prev,
                    &self.max_step,
                    k0 > 0,
                    self.level,
                    &mut bt.cont,
                );
            }
            let taken = bt.cont.taken;
            if taken > 0 && self.take_continuing(&bt.cont, tp, k0, count)? {
                bt.known = Some(bt.cont.branch_after);
                k0 += count;
                if self.transient {
                    self.sincos.clear();
                    self.base = k0;
                }
                continue;
            }
            for l in taken..count {
                self.sample(k0 + l, lane_tip(tp, l), chunk)?;
            }
            let upto = self.tcp.len();
            self.check_pending(upto)?;
            k0 += count;
            if self.transient {
                // Every sample so far checked: its sines are not kept.
                self.sincos.clear();
                self.base = k0;
            }
        }
        Ok(())
    }

    /// The leading lanes `c` of the batch of `count` samples from `k0` (tips `tp`) that
    /// continue one another, appended; when they are the whole batch and every earlier sample
    /// is checked, checked in lockstep straight from the lanes (and this says so).
    fn take_continuing(
        &mut self,
        c: &crate::kinematics::Continuing,
        tp: &TipLanes,
        k0: usize,
        count: usize,
    ) -> Result<bool, TimingFailure> {
        let n = self.n;
        let taken = c.taken;
        // The taken answers row by row (6 joints: continuing_lanes takes lanes of 6-axis
        // arms only).
        push_rows6(&mut self.qs, &c.q, taken);
        self.tcp.extend((0..taken).map(|l| lane_tip(tp, l)));
        let mut last = JointVec::zeros(n);
        for (j, v) in last.iter_mut().enumerate() {
            *v = c.q[j][taken - 1];
        }
        self.prev = last;
        if taken != count || self.sincos.len() != (k0 - self.base) * 2 * n {
            return Ok(false);
        }
        let base = self.base;
        self.solver
            .check_lanes_push(
                count,
                &c.q,
                &self.path_target,
                // This batch's tips, just appended (every earlier sample taken).
                &self.tcp[k0..k0 + count],
                tp,
                &mut self.sincos,
                self.level,
            )
            .map_err(|(l, reason)| {
                self.sincos.truncate((k0 - base) * 2 * n);
                self.unreachable(k0 + l, lane_tip(tp, l), reason)
            })?;
        Ok(true)
    }
}

/// The closed-form batches of the batched [`track_with`], overwritten batch by batch (not
/// moved): the current one is `batches[cur]`; on AVX-512 two are solved in one lockstep pass
/// (cheaper than two, opw::solve_branch_pair_into), the second ahead with the first's branch,
/// and taken by IkSolver::presolved_or_solve (exactly the batch solved then) when its turn
/// comes. Not on AVX2: 16 lanes are 4 registers of 16 per value there, and the spills cost
/// more than the overlap gains (placement bench: 140-144 -> 147-149 ns/sample).
struct Batches {
    batches: [crate::kinematics::opw::BranchBatch; 2],
    /// Whether two batches are solved in one pass.
    pairs: bool,
    /// Whether `batches[1 - cur]` holds the next batch, solved ahead.
    ahead: bool,
    cur: usize,
    /// The next batch's tips lane by lane when computed here.
    tp_next: TipLanes,
    /// The branch of the last answer, when the last batch's lanes all continued one another.
    known: Option<crate::kinematics::Branch>,
    /// The leading lanes of the current batch that continue one another.
    cont: crate::kinematics::Continuing,
}

impl Batches {
    /// None solved yet, at SIMD level `level`.
    fn new(level: crate::simd::Level) -> Self {
        Batches {
            batches: [crate::kinematics::opw::BranchBatch::default(); 2],
            pairs: level == crate::simd::Level::Avx512,
            ahead: false,
            cur: 0,
            tp_next: [[0.0; crate::simd::LANES]; 3],
            known: None,
            cont: crate::kinematics::Continuing::new(),
        }
    }

    /// Solve the batch of `count` samples from `k0` (tips `tp`) into `batches[cur]`: taken
    /// from the pass that solved it ahead, or solved now (with the next one on AVX-512).
    /// Whether the closed form holds for the batch.
    fn solve(
        &mut self,
        tr: &Tracking<'_, '_>,
        part_to_base: &Frame,
        pre: Option<&[TipLanes]>,
        tp: &TipLanes,
        k0: usize,
        count: usize,
    ) -> bool {
        use crate::simd::LANES;
        let len = tr.motion.p.len();
        if self.ahead {
            self.ahead = false;
            self.cur = 1 - self.cur;
            return tr.solver.presolved_or_solve(
                &tr.path_target,
                tp,
                count,
                &tr.prev,
                self.known.take(),
                tr.level,
                &mut self.batches[self.cur],
            );
        }
        if !(self.pairs && k0 + LANES < len) {
            return tr.solver.solve_near_batch_lanes(
                &tr.path_target,
                tp,
                count,
                &tr.prev,
                self.known.take(),
                tr.level,
                &mut self.batches[self.cur],
            );
        }
        let count_next = LANES.min(len - k0 - LANES);
        let tp_b: &TipLanes = match pre {
            Some(pre) => &pre[k0 / LANES + 1],
            None => {
                tips_into(
                    tr.motion,
                    part_to_base,
                    k0 + LANES,
                    count_next,
                    &mut self.tp_next,
                );
                &self.tp_next
            }
        };
        let (b0, b1) = self.batches.split_at_mut(1);
        let pair = if self.cur == 0 {
            [&mut b0[0], &mut b1[0]]
        } else {
            [&mut b1[0], &mut b0[0]]
        };
        self.ahead = tr.solver.solve_near_batch_pair_lanes(
            &tr.path_target,
            [tp, tp_b],
            [count, count_next],
            &tr.prev,
            self.known.take(),
            tr.level,
            pair,
        );
        self.ahead
    }
}

/// Append the joint vectors of the first `taken` lanes of `q` (`q[j][lane]`, 6 joints, rad)
/// to `qs` row by row (`taken · 6` values): the same values, moved
/// ([`crate::simd::push_transposed`]).
fn push_rows6(
    qs: &mut Vec<f64>,
    q: &[[f64; crate::simd::LANES]; crate::kinematics::MAX_DOF],
    taken: usize,
) {
    let rows = [&q[0], &q[1], &q[2], &q[3], &q[4], &q[5]];
    crate::simd::push_transposed::<f64>(qs, &rows, taken)
}

/// IK along `len` tool tips (`tip(i)`, base frame, m) with the nozzle orientation `rot`,
/// continuing from `q0` (rad / m), with no step check: the joint vectors go to `qs` (cleared;
/// row-major), exactly as the per-sample loop
/// `q = solver.solve_near(&Frame { rot, pos: tip(i) }, &prev)?; prev = q` appends them.
/// The error names the first sample where that loop stops, `(i, its tip, the reason)`, bit
/// for bit; `qs` then holds no meaningful values.
///
/// With SIMD ([`crate::simd::level`] not scalar) and a [`IkSolver::batch_checkable`] solver,
/// the closed form runs in lockstep batches of [`crate::simd::LANES`] samples
/// ([`IkSolver::solve_near_batch_lanes`]); the leading lanes that provably continue one
/// another ([`IkSolver::continuing_lanes`]) are taken at once, the rest with
/// [`IkSolver::take_near`], and the FK re-check of each batch runs in lockstep
/// ([`IkSolver::check_lanes`]) before the next batch: a failing check is reported at its
/// sample ahead of any later failure, as the per-sample check reports it.
pub fn track_near(
    solver: &IkSolver,
    rot: &crate::math::M3,
    len: usize,
    tip: impl Fn(usize) -> V3,
    q0: &[f64],
    qs: &mut Vec<f64>,
) -> Result<(), (usize, V3, IkFailure)> {
    let n = solver.model.dof();
    qs.clear();
    let level = crate::simd::level();
    if level == crate::simd::Level::Scalar || !solver.batch_checkable() || q0.len() != n {
        let mut prev = JointVec::from_slice(q0);
        for i in 0..len {
            let t = tip(i);
            let q = solver
                .solve_near(&Frame { rot: *rot, pos: t }, &prev)
                .map_err(|r| (i, t, r))?;
            qs.extend_from_slice(&q[..n]);
            prev = q;
        }
        return Ok(());
    }
    qs.reserve(len * n);
    let mut tr = NearTracker {
        solver,
        rot: *rot,
        target: solver.path_target(rot),
        level,
        n,
        prev: JointVec::from_slice(q0),
        no_step: [f64::INFINITY; crate::kinematics::MAX_DOF],
        batch: crate::kinematics::opw::BranchBatch::default(),
        cont: crate::kinematics::Continuing::new(),
        known: None,
        sincos: [0.0; crate::simd::LANES * 2 * crate::kinematics::MAX_DOF],
    };
    let mut k0 = 0;
    while k0 < len {
        let count = crate::simd::LANES.min(len - k0);
        let mut lanes = NearLanes {
            tips: [V3::zeros(); crate::simd::LANES],
            tp: [[0.0; crate::simd::LANES]; 3],
            qb: [[0.0; crate::simd::LANES]; crate::kinematics::MAX_DOF],
        };
        for l in 0..count {
            let t = tip(k0 + l);
            lanes.tips[l] = t;
            (lanes.tp[0][l], lanes.tp[1][l], lanes.tp[2][l]) = (t.x, t.y, t.z);
        }
        tr.solve_batch(&mut lanes, k0, count)?;
        if n == 6 {
            push_rows6(qs, &lanes.qb, count);
        } else {
            for l in 0..count {
                qs.extend(lanes.qb.iter().take(n).map(|row| row[l]));
            }
        }
        k0 += count;
    }
    Ok(())
}

/// The state of [`track_near`]'s lockstep batches along one path.
struct NearTracker<'t, 's> {
    solver: &'t IkSolver<'s>,
    /// The nozzle's orientation in the base frame.
    rot: crate::math::M3,
    target: crate::kinematics::PathTarget,
    level: crate::simd::Level,
    /// Joints of the arm.
    n: usize,
    /// The last sample's answer.
    prev: JointVec,
    /// No step limit: every lane's step is within it.
    no_step: [f64; crate::kinematics::MAX_DOF],
    batch: crate::kinematics::opw::BranchBatch,
    cont: crate::kinematics::Continuing,
    /// The branch of prev, when the last batch's lanes all continued one another.
    known: Option<crate::kinematics::Branch>,
    /// Scratch for the re-check's sines and cosines (not kept).
    sincos: [f64; crate::simd::LANES * 2 * crate::kinematics::MAX_DOF],
}

/// One batch of [`track_near`]: its tips (as points and lane by lane) and its answers joint
/// by joint (rows beyond the robot's joints: 0).
struct NearLanes {
    tips: [V3; crate::simd::LANES],
    tp: TipLanes,
    qb: [[f64; crate::simd::LANES]; crate::kinematics::MAX_DOF],
}

/// The first `taken` lanes of `cont`, which continue one another, into `qb` (`n` joints):
/// the last of them, the answer to continue from.
fn take_continuing(
    cont: &crate::kinematics::Continuing,
    n: usize,
    qb: &mut [[f64; crate::simd::LANES]; crate::kinematics::MAX_DOF],
    taken: usize,
) -> JointVec {
    // continuing_lanes takes lanes of 6-axis arms only.
    for (row, c) in qb.iter_mut().zip(&cont.q).take(6) {
        row[..taken].copy_from_slice(&c[..taken]);
    }
    let mut last = JointVec::zeros(n);
    for (j, v) in last.iter_mut().enumerate() {
        *v = qb[j][taken - 1];
    }
    last
}

impl NearTracker<'_, '_> {
    /// Solve the batch of `count` samples from `k0` into `lanes.qb`: the leading lanes that
    /// continue one another at once, the rest one by one, then the FK re-check in lockstep.
    /// The error names the first sample where the per-sample loop stops.
    fn solve_batch(
        &mut self,
        lanes: &mut NearLanes,
        k0: usize,
        count: usize,
    ) -> Result<(), (usize, V3, IkFailure)> {
        let (n, level) = (self.n, self.level);
        let solver = self.solver;
        let solved = solver.solve_near_batch_lanes(
            &self.target,
            &lanes.tp,
            count,
            &self.prev,
            self.known.take(),
            level,
            &mut self.batch,
        );
        let chunk = solved.then_some(&self.batch);
        self.cont.taken = 0;
        if let Some(b) = chunk {
            solver.continuing_lanes(
                b,
                count,
                &self.prev,
                &self.no_step,
                false,
                level,
                &mut self.cont,
            );
        }
        let taken = self.cont.taken;
        let (tips, qb) = (&lanes.tips, &mut lanes.qb);
        if taken > 0 {
            self.prev = take_continuing(&self.cont, self.n, qb, taken);
        }
        for l in taken..count {
            let t = Frame {
                rot: self.rot,
                pos: tips[l],
            };
            let solved = match chunk {
                Some(b) => solver.take_near(b, l, &t, &self.prev),
                None => solver.solve_near_unchecked(&t, &self.prev),
            };
            match solved {
                Ok(q) => {
                    for j in 0..n {
                        qb[j][l] = q[j];
                    }
                    self.prev = q;
                }
                Err(reason) => {
                    // The samples before it first: a failing check there stops the
                    // per-sample loop earlier.
                    if l > 0 {
                        solver
                            .check_lanes(l, qb, &self.target, &tips[..l], &mut self.sincos, level)
                            .map_err(|(f, r)| (k0 + f, tips[f], r))?;
                    }
                    return Err((k0 + l, tips[l], reason));
                }
            }
        }
        solver
            .check_lanes(
                count,
                qb,
                &self.target,
                &tips[..count],
                &mut self.sincos,
                level,
            )
            .map_err(|(f, r)| (k0 + f, tips[f], r))?;
        if taken == count {
            self.known = Some(self.cont.branch_after);
        }
        Ok(())
    }
}

/// Tool-tip points of [`crate::simd::LANES`] path samples in the base frame, lane by lane
/// (`t[i][l]`: coordinate `i` (x, y, z) of lane `l`, m).
pub(crate) type TipLanes = [[f64; crate::simd::LANES]; 3];

/// A [`Frame`] (part to base) as [`TipMap::lanes_of`] applies it to points given lane by
/// lane: rotation row-major, translation.
#[derive(Clone, Copy)]
pub(crate) struct TipMap {
    r: [[f64; 3]; 3],
    t: [f64; 3],
}

impl TipMap {
    pub(crate) fn new(frame: &Frame) -> TipMap {
        let mut r = [[0.0; 3]; 3];
        for (i, row) in r.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = frame.rot[(i, j)];
            }
        }
        TipMap {
            r,
            t: [frame.pos.x, frame.pos.y, frame.pos.z],
        }
    }

    /// [`Frame::apply`] of the points `x` (part frame, m; chunks of [`point_lanes`]) in
    /// lockstep, chunk by chunk into `out` (as long as `x`; lanes past the path's end:
    /// `frame.pos`), vectorised for `level`: each coordinate as
    /// `((r_i0 x + r_i1 y) + r_i2 z) + t_i`, the operations and order of nalgebra's
    /// matrix-vector product and sum in [`Frame::apply`] (no fused multiply-add), so every
    /// lane is that point's [`Frame::apply`] bit for bit (tested).
    #[inline]
    pub(crate) fn lanes_of(&self, x: &[TipLanes], out: &mut [TipLanes], level: crate::simd::Level) {
        crate::simd::run(
            level,
            #[inline(always)]
            || tip_lanes_of_body(self, x, out),
        )
    }
}

/// The body of [`TipMap::lanes_of`].
#[inline(always)]
fn tip_lanes_of_body(m: &TipMap, x: &[TipLanes], out: &mut [TipLanes]) {
    let (r, t) = (&m.r, &m.t);
    for (x, out) in x.iter().zip(out.iter_mut()) {
        for (i, o) in out.iter_mut().enumerate() {
            for (l, v) in o.iter_mut().enumerate() {
                *v = ((r[i][0] * x[0][l] + r[i][1] * x[1][l]) + r[i][2] * x[2][l]) + t[i];
            }
        }
    }
}

/// Derivatives of uniformly sampled positions (row-major `len × n`, rad or m, `dt` s apart):
/// (q̇, q̈, q⃛) from [`crate::numerics::differentiate`] and
/// [`crate::numerics::third_derivative_uniform`].
pub fn differentiate(q: &[f64], n: usize, dt: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let len = q.len().checked_div(n).unwrap_or(0);
    let grid = crate::numerics::Grid::Uniform { dt, len };
    let (qd, qdd) = crate::numerics::differentiate(grid, &q[..len * n], n)
        .unwrap_or_else(|_| (vec![0.0; len * n], vec![0.0; len * n]));
    (qd, qdd, crate::numerics::third_derivative_uniform(q, n, dt))
}

struct Violation {
    joint: usize,
    kind: LimitKind,
    sample: usize,
    ratio: f64,
    /// The joint's velocity and acceleration at that sample (rad/s, rad/s²).
    rate: (f64, f64),
}

/// Every (sample, joint, limit) over its limit, from the positions `q` (for the jerk,
/// [`crate::numerics::third_derivative_uniform_at`], computed where needed rather than
/// stored) and the derivatives `qd`, `qdd` (row-major, `dt` s apart), in the order sample,
/// joint, kind. On a SIMD level ([`crate::simd::Level`]) the interior samples are screened
/// first in lockstep ([`screen_rows`]: the same values and comparisons, no list); only the
/// samples of a block that has an excess go through the per-sample checks, so the list is the
/// per-sample path's ([`crate::simd::Level::Scalar`]) exactly.
fn violations(
    model: &RobotModel,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    dt: f64,
    check_jerk: bool,
    level: crate::simd::Level,
) -> Vec<Violation> {
    let n = model.dof();
    let mut out = Vec::new();
    let m = qd.len() / n;
    let row = |k: usize, out: &mut Vec<Violation>| {
        row_violations(model, q, qd, qdd, dt, check_jerk, k, out)
    };
    if level == crate::simd::Level::Scalar || !check_jerk || m < 5 {
        for k in 0..m {
            row(k, &mut out);
        }
        return out;
    }
    // Rows 0, 1 and m − 2, m − 1 (the jerk clamped to the interior) per sample; rows
    // 2 ..= m − 3 screened in blocks of SCREEN_BLOCK entries, each row of a block with an
    // excess checked per sample once.
    let limits = |f: fn(&crate::robot::Joint) -> f64| -> Vec<f64> {
        // A limit the per-sample check skips (not finite) never binds: +∞.
        let lim: Vec<f64> = model
            .joints
            .iter()
            .map(|j| {
                let l = f(j);
                if l.is_finite() {
                    l
                } else {
                    f64::INFINITY
                }
            })
            .collect();
        (0..n + SCREEN_BLOCK).map(|t| lim[t % n]).collect()
    };
    let lims = [
        limits(|j| j.velocity_limit),
        limits(|j| j.acceleration_limit),
        limits(|j| j.jerk_limit),
    ];
    row(0, &mut out);
    row(1, &mut out);
    let (first, end) = (2 * n, (m - 2) * n);
    let mut next_row = 2;
    let mut i0 = first;
    while i0 + SCREEN_BLOCK <= end {
        let o = i0 % n;
        let lim = [
            &lims[0][o..o + SCREEN_BLOCK],
            &lims[1][o..o + SCREEN_BLOCK],
            &lims[2][o..o + SCREEN_BLOCK],
        ];
        if screen_rows(q, qd, qdd, n, dt, i0, lim, level) {
            let last = (i0 + SCREEN_BLOCK - 1) / n;
            for k in next_row.max(i0 / n)..=last {
                row(k, &mut out);
            }
            next_row = last + 1;
        }
        i0 += SCREEN_BLOCK;
    }
    // The rows of the rest, then the last two.
    for k in next_row.max(i0 / n)..m {
        row(k, &mut out);
    }
    out
}

/// Limits per entry of a block of [`derivatives_and_violations`] (period `n`, the joints):
/// velocity, acceleration, and the jerk's as a bound on its numerator (jerk_screen_bound,
/// `den = 2 dt³`); +∞ where the per-sample check skips one (not finite).
fn block_limits(model: &RobotModel, den: f64) -> [Vec<f64>; 3] {
    let n = model.dof();
    let limits = |f: fn(&crate::robot::Joint) -> f64, bound: &dyn Fn(f64) -> f64| {
        let lim: Vec<f64> = model
            .joints
            .iter()
            .map(|j| {
                let l = f(j);
                if l.is_finite() {
                    bound(l)
                } else {
                    f64::INFINITY
                }
            })
            .collect();
        (0..n + SCREEN_BLOCK)
            .map(|t| lim[t % n])
            .collect::<Vec<f64>>()
    };
    [
        limits(|j| j.velocity_limit, &|l| l),
        limits(|j| j.acceleration_limit, &|l| l),
        limits(|j| j.jerk_limit, &|l| jerk_screen_bound(l, den)),
    ]
}

/// The joint velocities and accelerations of the positions `q` (row-major, `dt` s apart)
/// into `qd`, `qdd` (reused buffers, as [`crate::numerics::differentiate_uniform_into_on`]
/// writes them) and the list of [`violations`] of them, in one pass over the samples on a
/// SIMD level: each block of [`SCREEN_BLOCK`] interior entries is differentiated and screened
/// together ([`derive_screen`]), the rows of a block with a possible excess checked per
/// sample after the pass. The same derivatives and the same list (order, ratios) bit for bit
/// as the two passes ([`crate::simd::Level::Scalar`], and every level: tested).
fn derivatives_and_violations(
    model: &RobotModel,
    q: &[f64],
    dt: f64,
    check_jerk: bool,
    qd: &mut Vec<f64>,
    qdd: &mut Vec<f64>,
    level: crate::simd::Level,
) -> Vec<Violation> {
    let n = model.dof();
    let m = q.len().checked_div(n).unwrap_or(0);
    // The screen needs the jerk's rows 2 ..= m − 3 and a step the stencil takes.
    let den = 2.0 * dt * dt * dt;
    if level == crate::simd::Level::Scalar || !check_jerk || m < 5 || !(dt > 0.0 && dt.is_finite())
    {
        crate::numerics::differentiate_uniform_into_on(q, n, dt, qd, qdd, level);
        return violations(model, q, qd, qdd, dt, check_jerk, level);
    }
    // Every entry is written below (m ≥ 5, a valid step): a reused buffer is not zeroed.
    crate::numerics::resize_exact(qd, m * n);
    crate::numerics::resize_exact(qdd, m * n);
    let w = crate::numerics::uniform_weights(dt);
    crate::numerics::uniform_end_rows(q, n, &w, qd, qdd);
    // Row 1: derivatives only (its jerk is clamped, it is checked per sample).
    crate::numerics::uniform_stencil_entries_on(q, n, w[1], n..2 * n, qd, qdd, level);
    let lims = block_limits(model, den);
    let (first, end) = (2 * n, (m - 2) * n);
    // Blocks with a possible excess (their first entries), in order.
    let mut flagged: Vec<usize> = Vec::new();
    let mut i0 = first;
    while i0 + SCREEN_BLOCK <= end {
        let o = i0 % n;
        let lim = [
            &lims[0][o..o + SCREEN_BLOCK],
            &lims[1][o..o + SCREEN_BLOCK],
            &lims[2][o..o + SCREEN_BLOCK],
        ];
        if derive_screen_rows(q, qd, qdd, n, w[1], i0, lim, level) {
            flagged.push(i0);
        }
        i0 += SCREEN_BLOCK;
    }
    // The rest of the interior (up to row m − 2): derivatives only, checked per sample.
    crate::numerics::uniform_stencil_entries_on(q, n, w[1], i0..(m - 1) * n, qd, qdd, level);
    let mut out = Vec::new();
    let mut row = |k: usize| row_violations(model, q, qd, qdd, dt, check_jerk, k, &mut out);
    row(0);
    row(1);
    let mut next_row = 2;
    for b0 in flagged {
        let last = (b0 + SCREEN_BLOCK - 1) / n;
        for k in next_row.max(b0 / n)..=last {
            row(k);
        }
        next_row = last + 1;
    }
    for k in next_row.max(i0 / n)..m {
        row(k);
    }
    out
}

/// Samples whose velocities and accelerations [`lean_violations`] derives at a time.
const LEAN_BLOCK: usize = 4096;

/// The [`violations`] of the positions `q` (row-major, `dt` s apart, at least 5 samples, a
/// finite `dt` > 0) without keeping their velocities and accelerations: derived
/// [`LEAN_BLOCK`] samples at a time ([`crate::numerics::uniform_rates_rows`], the values
/// of [`derivatives_and_violations`] bit for bit) and checked sample by sample, so the list
/// is the same (order, ratios).
fn lean_violations(
    model: &RobotModel,
    q: &[f64],
    dt: f64,
    check_jerk: bool,
    level: crate::simd::Level,
) -> Vec<Violation> {
    let n = model.dof();
    let m = q.len() / n;
    let mut out = Vec::new();
    let (mut qd, mut qdd) = (vec![0.0; LEAN_BLOCK * n], vec![0.0; LEAN_BLOCK * n]);
    let w = crate::numerics::uniform_weights(dt);
    for k0 in (0..m).step_by(LEAN_BLOCK) {
        let count = LEAN_BLOCK.min(m - k0);
        crate::numerics::uniform_rates_rows(q, n, &w, k0, count, &mut qd, &mut qdd, level);
        for r in 0..count {
            let row = r * n..(r + 1) * n;
            row_violations_of(
                model,
                q,
                (&qd[row.clone()], &qdd[row]),
                (dt, check_jerk, m),
                k0 + r,
                &mut out,
            );
        }
    }
    out
}

/// A bound `b` on the jerk's numerator such that `|num| / den > limit` (the per-sample jerk
/// check, `den = 2 dt³` s³ > 0, a finite `limit` rad/s³) implies `|num| > b`: the screen's
/// test without a division. `limit · den`, lowered by a few ulps for its rounding; where that
/// product is not a normal positive number (a limit ≤ 0, an underflow) the screen tests
/// everything (−∞, or 0 when only the product underflowed); an overflow (+∞) tests nothing,
/// rightly (|num| ≤ f64::MAX < limit · den).
fn jerk_screen_bound(limit: f64, den: f64) -> f64 {
    if !(den.is_normal() && den.is_sign_positive() && limit > 0.0) {
        return f64::NEG_INFINITY;
    }
    let t = limit * den;
    if t.is_infinite() {
        f64::INFINITY
    } else if t.is_normal() {
        t * (1.0 - 4.0 * f64::EPSILON)
    } else {
        0.0
    }
}

/// [`screen_rows`] fused with the derivatives: the interior stencil (weights `(d1, d2)`,
/// [`crate::numerics::uniform_weights`]) of the [`SCREEN_BLOCK`] entries from `i0` (rows
/// 2 ..= m − 3) written to `qd`, `qdd`, and whether any of them may be over its limit
/// (`lim`: velocity and acceleration limits, and [`jerk_screen_bound`]s), vectorised for
/// `level`.
#[allow(clippy::too_many_arguments)]
#[inline]
fn derive_screen_rows(
    q: &[f64],
    qd: &mut [f64],
    qdd: &mut [f64],
    n: usize,
    w: ([f64; 3], [f64; 3]),
    i0: usize,
    lim: [&[f64]; 3],
    level: crate::simd::Level,
) -> bool {
    let b = SCREEN_BLOCK;
    let qs = [
        &q[i0 - 2 * n..][..b],
        &q[i0 - n..][..b],
        &q[i0..][..b],
        &q[i0 + n..][..b],
        &q[i0 + 2 * n..][..b],
    ];
    let (v, a) = (&mut qd[i0..i0 + b], &mut qdd[i0..i0 + b]);
    crate::simd::run(
        level,
        #[inline(always)]
        || derive_screen(qs, w, v, a, lim),
    )
}

/// The body of [`derive_screen_rows`]: `qs` the positions 2 rows before, 1 before, the
/// entries', 1 after and 2 after; the stencil of numerics (`w0·a + w1·b + w2·c` left to
/// right) and the jerk's numerator of
/// [`crate::numerics::third_derivative_uniform_at`], the same operations in the same order.
#[inline(always)]
fn derive_screen(
    qs: [&[f64]; 5],
    (d1, d2): ([f64; 3], [f64; 3]),
    v: &mut [f64],
    a: &mut [f64],
    lim: [&[f64]; 3],
) -> bool {
    fn block(x: &[f64]) -> &[f64; SCREEN_BLOCK] {
        x[..SCREEN_BLOCK].try_into().expect("a block")
    }
    let (qm2, qm1, q0, qp1, qp2) = (
        block(qs[0]),
        block(qs[1]),
        block(qs[2]),
        block(qs[3]),
        block(qs[4]),
    );
    let v: &mut [f64; SCREEN_BLOCK] = (&mut v[..SCREEN_BLOCK]).try_into().expect("a block");
    let a: &mut [f64; SCREEN_BLOCK] = (&mut a[..SCREEN_BLOCK]).try_into().expect("a block");
    let (lv, la, lj) = (block(lim[0]), block(lim[1]), block(lim[2]));
    // 1 where an entry may be over its limit, or-ed (an integer reduction, so that it
    // vectorises).
    let mut over = 0u64;
    for i in 0..SCREEN_BLOCK {
        let (f0, f1, f2) = (qm1[i], q0[i], qp1[i]);
        let vi = d1[0] * f0 + d1[1] * f1 + d1[2] * f2;
        let ai = d2[0] * f0 + d2[1] * f1 + d2[2] * f2;
        v[i] = vi;
        a[i] = ai;
        let num = qp2[i] - 2.0 * qp1[i] + 2.0 * qm1[i] - qm2[i];
        let x = (vi.abs() > lv[i]) | (ai.abs() > la[i]) | (num.abs() > lj[i]);
        over |= x as u64;
    }
    over != 0
}

/// Entries screened at once by [`screen_rows`] and [`derive_screen_rows`] (128: the calls'
/// overhead halved against 64, a block with an excess still only ~21 rows of 6 joints).
const SCREEN_BLOCK: usize = 128;

/// The per-sample checks of sample `k` ([`violations`]), appended to `out`.
#[allow(clippy::too_many_arguments)]
#[inline]
fn row_violations(
    model: &RobotModel,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    dt: f64,
    check_jerk: bool,
    k: usize,
    out: &mut Vec<Violation>,
) {
    let n = model.dof();
    let m = qd.len() / n;
    let row = k * n..(k + 1) * n;
    row_violations_of(
        model,
        q,
        (&qd[row.clone()], &qdd[row]),
        (dt, check_jerk, m),
        k,
        out,
    );
}

/// [`row_violations`] with sample `k`'s velocities and accelerations given (`rates`, one
/// row each), of a path of `m` samples.
#[inline]
fn row_violations_of(
    model: &RobotModel,
    q: &[f64],
    (qd, qdd): (&[f64], &[f64]),
    (dt, check_jerk, m): (f64, bool, usize),
    k: usize,
    out: &mut Vec<Violation>,
) {
    let n = model.dof();
    let jerk = |k: usize, j: usize| {
        if check_jerk && m >= 5 {
            crate::numerics::third_derivative_uniform_at(q, n, dt, k, j)
        } else {
            0.0
        }
    };
    for (j, jt) in model.joints.iter().enumerate() {
        let checks = [
            (LimitKind::Velocity, qd[j], jt.velocity_limit),
            (LimitKind::Acceleration, qdd[j], jt.acceleration_limit),
            (
                LimitKind::Jerk,
                if jt.jerk_limit.is_finite() {
                    jerk(k, j)
                } else {
                    0.0
                },
                jt.jerk_limit,
            ),
        ];
        for (kind, v, lim) in checks {
            if lim.is_finite() && v.abs() > lim {
                out.push(Violation {
                    joint: j,
                    kind,
                    sample: k,
                    ratio: v.abs() / lim,
                    rate: (qd[j], qdd[j]),
                });
            }
        }
    }
}

/// Whether any of the [`SCREEN_BLOCK`] row-major entries from `i0` (all in rows
/// 2 ..= m − 3) is over its limit (`lim`: velocity, acceleration and jerk limits of those
/// entries, +∞ where none applies): `|q̇| > lim`, `|q̈| > lim`, and the jerk of
/// [`crate::numerics::third_derivative_uniform_at`] (the same operations in the same order,
/// entry `i`'s neighbours `± n`, `± 2n` entries away), vectorised for `level`.
#[allow(clippy::too_many_arguments)]
#[inline]
fn screen_rows(
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    n: usize,
    dt: f64,
    i0: usize,
    lim: [&[f64]; 3],
    level: crate::simd::Level,
) -> bool {
    let b = SCREEN_BLOCK;
    let qs = [
        &q[i0 - 2 * n..][..b],
        &q[i0 - n..][..b],
        &q[i0 + n..][..b],
        &q[i0 + 2 * n..][..b],
    ];
    let (v, a) = (&qd[i0..i0 + b], &qdd[i0..i0 + b]);
    crate::simd::run(
        level,
        #[inline(always)]
        || screen(qs, v, a, dt, lim),
    )
}

/// The body of [`screen_rows`]: `qs` the positions 2 rows before, 1 before, 1 after and 2
/// after each entry; `v`, `a` its velocity and acceleration.
#[inline(always)]
fn screen(qs: [&[f64]; 4], v: &[f64], a: &[f64], dt: f64, lim: [&[f64]; 3]) -> bool {
    fn block(x: &[f64]) -> &[f64; SCREEN_BLOCK] {
        x[..SCREEN_BLOCK].try_into().expect("a block")
    }
    let (qm2, qm1, qp1, qp2) = (block(qs[0]), block(qs[1]), block(qs[2]), block(qs[3]));
    let (v, a) = (block(v), block(a));
    let (lv, la, lj) = (block(lim[0]), block(lim[1]), block(lim[2]));
    let den = 2.0 * dt * dt * dt;
    // 1 where an entry is over its limit, or-ed (an integer reduction, so that it
    // vectorises).
    let mut over = 0u64;
    for i in 0..SCREEN_BLOCK {
        let jerk = (qp2[i] - 2.0 * qp1[i] + 2.0 * qm1[i] - qm2[i]) / den;
        let x = (v[i].abs() > lv[i]) | (a[i].abs() > la[i]) | (jerk.abs() > lj[i]);
        over |= x as u64;
    }
    over != 0
}

/// Rates of the (filtered) arc length `s` (m, `dt` s apart) at sample `k`: (ṡ m/s, s̈ m/s²,
/// s⃛ m/s³), central differences (shifted inwards at the ends).
pub(crate) fn path_rates(s: &[f64], dt: f64, k: usize) -> (f64, f64, f64) {
    let m = s.len();
    if m < 5 {
        return (0.0, 0.0, 0.0);
    }
    let c = k.clamp(2, m - 3);
    let v = (s[c + 1] - s[c - 1]) / (2.0 * dt);
    let a = (s[c + 1] - 2.0 * s[c] + s[c - 1]) / (dt * dt);
    let j = (s[c + 2] - 2.0 * s[c + 1] + 2.0 * s[c - 1] - s[c - 2]) / (2.0 * dt * dt * dt);
    (v, a, j)
}

/// The share (dimensionless) of a joint's acceleration or jerk demand that comes from the
/// path's ramp (its tangential acceleration s̈ and jerk s⃛) rather than from its speed and
/// curvature, from the joint's rates `qd`, `qdd`, `qddd` (rad/s, rad/s², rad/s³) and the path
/// rates `(ṡ, s̈, s⃛)` at the sample: with q̇ = q′ṡ, q̈ = q′s̈ + q″ṡ², q⃛ = q′s⃛ + 3q″ṡs̈ +
/// q‴ṡ³, the ramp part is q′s̈ (acceleration) or q′s⃛ + 3q″ṡs̈ (jerk). Lowering the speed
/// scales the rest; lowering the acceleration (and with it the jerk) scales the ramp part.
/// Velocity: 0. At rest (ṡ ≈ 0): 1.
pub(crate) fn ramp_share(
    kind: LimitKind,
    qd: f64,
    qdd: f64,
    qddd: f64,
    rates: (f64, f64, f64),
) -> f64 {
    let (sd, sdd, sddd) = rates;
    if kind == LimitKind::Velocity {
        return 0.0;
    }
    if sd.abs() < 1e-6 {
        return 1.0;
    }
    let q1 = qd / sd;
    let (ramp, total) = match kind {
        LimitKind::Acceleration => (q1 * sdd, qdd),
        _ => {
            let q2 = (qdd - q1 * sdd) / (sd * sd);
            (q1 * sddd + 3.0 * q2 * sd * sdd, qddd)
        }
    };
    if total.abs() < 1e-300 || !(ramp / total).is_finite() {
        return 0.0;
    }
    ramp / total
}

/// One sample over a joint limit, as the slow-down rule needs it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Excess {
    /// Sample index of the plan.
    pub sample: usize,
    /// 0-based joint index.
    pub joint: usize,
    /// Which limit.
    pub kind: LimitKind,
    /// Demand over limit (> 1).
    pub ratio: f64,
    /// Share of the demand from the path's ramp ([`ramp_share`]).
    pub ramp_share: f64,
}

/// Where a demand counts as coming from a ramp ([`ramp_share`] at least this): the
/// acceleration is lowered there instead of the speed.
pub(crate) const RAMP_SHARE: f64 = 0.5;

/// Lowest factor the ramp acceleration is lowered by in one round (dimensionless).
const MIN_ACCEL_STEP: f64 = 0.1;

/// What one round of the slow-down rule did at one excess: the factor applied to the path
/// speed or to the ramp acceleration there, relative to the plan it was found in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Lever {
    /// Path speed capped at this share of the current speed (around the sample).
    Speed(f64),
    /// Ramp acceleration lowered to this share of the current one (over the ramp around the
    /// sample).
    Accel(f64),
}

/// The controller's slow-down along a path's nodes, as it re-plans after a joint limit was
/// exceeded: per node, the factor on the speed cap and on the ramp acceleration
/// (1 = none). Each round ([`Slowing::apply`]) acts where a limit is exceeded, relative to
/// the plan in which it was found, so that slow-downs compound:
/// - a velocity limit, or an acceleration or jerk demand mostly from the speed and the
///   path's curvature (ramp share below [`RAMP_SHARE`]), caps the speed at the nodes within
///   the jerk filter's reach (± `taps + 2` samples) of the sample at `margin / ratio` of the
///   current node speed (square root for acceleration, cube root for jerk);
/// - an acceleration or jerk demand mostly from a ramp lowers the ramp acceleration (and,
///   with the filter's length fixed, the jerk) over that window and the rest of the ramp it
///   lies on (the contiguous nodes where the speed is acceleration-limited), by the factor
///   that brings the ramp's share of the demand to `margin` of the limit.
///
/// Elsewhere the speed and the acceleration are the unslowed plan's.
#[derive(Clone, Debug, Default)]
pub(crate) struct Slowing {
    /// Factor on each node's speed cap (1 = none).
    pub scale: Vec<f64>,
    /// Factor on the ramp acceleration at each node (empty: 1 everywhere), see
    /// [`super::profile::speed_at_nodes_local`].
    pub accel_scale: Vec<f64>,
}

impl Slowing {
    /// No slow-down on `nodes` nodes.
    pub fn new(nodes: usize) -> Slowing {
        Slowing {
            scale: vec![1.0; nodes],
            accel_scale: Vec::new(),
        }
    }

    /// Node speeds (m/s) of the plan with these slow-downs.
    pub fn speeds(&self, nodes: &Nodes, accel: f64) -> Vec<f64> {
        super::profile::speed_at_nodes_local(nodes, &self.scale, accel, &self.accel_scale)
    }

    /// Lowest acceleration factor (1 = none).
    pub(crate) fn min_accel_factor(&self) -> f64 {
        self.accel_scale.iter().copied().fold(1.0, f64::min)
    }

    /// One round of the rule (see [`Slowing`]) for the excesses `viol` found in `motion`,
    /// planned on `nodes` at node speeds `v` (m/s). Returns the lever applied at each excess.
    pub fn apply(
        &mut self,
        nodes: &Nodes,
        v: &[f64],
        motion: &CartesianMotion,
        viol: &[Excess],
        margin: f64,
    ) -> Vec<Lever> {
        let nl = nodes.s.len();
        let half = motion.taps + 2;
        let len = motion.s.len();
        let mut out = Vec::with_capacity(viol.len());
        // Acceleration factors of this round, applied after every excess was seen (relative
        // to the plan's, not compounded within a round).
        let mut accel: Vec<(usize, usize, f64)> = Vec::new();
        for e in viol {
            let k0 = e.sample.saturating_sub(half);
            let k1 = (e.sample + half).min(len - 1);
            let (s0, s1) = (motion.s[k0], motion.s[k1]);
            let i0 = nodes.s.partition_point(|&x| x < s0).min(nl - 1);
            let i1 = nodes.s.partition_point(|&x| x <= s1).clamp(i0 + 1, nl);
            let ramp = e.kind != LimitKind::Velocity && e.ramp_share >= RAMP_SHARE;
            if ramp {
                // Bring the ramp part (share r) down so that the whole is `margin` of the
                // limit: r·g + (1 − r) = margin / ratio.
                let r = e.ramp_share;
                let g = ((margin / e.ratio - (1.0 - r)) / r).clamp(MIN_ACCEL_STEP, margin);
                // The ramp the window lies on: the contiguous nodes whose speed is
                // acceleration-limited (below their cap).
                let limited = |i: usize| v[i] < nodes.cap[i] * self.scale[i] * (1.0 - 1e-9);
                let mut a = i0;
                while a > 0 && limited(a - 1) {
                    a -= 1;
                }
                let mut b = i1;
                while b < nl && limited(b) {
                    b += 1;
                }
                accel.push((a.saturating_sub(1), (b + 1).min(nl), g));
                out.push(Lever::Accel(g));
            } else {
                let f = match e.kind {
                    LimitKind::Velocity => margin / e.ratio,
                    LimitKind::Acceleration => (margin / e.ratio).sqrt(),
                    LimitKind::Jerk => (margin / e.ratio).cbrt(),
                };
                let caps = nodes.cap[i0..i1].iter().zip(&v[i0..i1]);
                for (sc, (&cap, &vi)) in self.scale[i0..i1].iter_mut().zip(caps) {
                    if cap > 0.0 {
                        *sc = sc.min(f * vi / cap);
                    }
                }
                out.push(Lever::Speed(f));
            }
        }
        if !accel.is_empty() {
            if self.accel_scale.len() != nl {
                self.accel_scale = vec![1.0; nl];
            }
            // The smallest factor per node of this round, then applied once.
            accel.sort_by_key(|r| r.0);
            let mut round: Vec<(usize, f64)> = Vec::new();
            for &(a, b, g) in &accel {
                for i in a..b {
                    match round.binary_search_by_key(&i, |x| x.0) {
                        Ok(p) => round[p].1 = round[p].1.min(g),
                        Err(p) => round.insert(p, (i, g)),
                    }
                }
            }
            for (i, g) in round {
                self.accel_scale[i] *= g;
            }
        }
        out
    }
}

/// The placement-independent part of timing a path: the speed-limit nodes and the first
/// Cartesian plan (no slow-down). Build it once per path and share it across placements.
#[derive(Clone, Debug)]
pub struct Plan {
    /// Speed-limit nodes along the path.
    pub nodes: Nodes,
    /// The Cartesian motion with no joint-limit slow-down.
    pub motion: Arc<CartesianMotion>,
    /// Its speed at each node, m/s.
    pub v: Vec<f64>,
    /// The motion's points (part frame, m) lane by lane, [`crate::simd::LANES`] samples a
    /// chunk (lanes past the end: 0), with the motion they are of: what the reach prune of
    /// [`time_at_planned`] maps to the base frame ([`TipMap::lanes_of`]) at every placement.
    p_lanes: (Arc<CartesianMotion>, Vec<TipLanes>),
}

impl Plan {
    /// Plan `pieces` with the profile options.
    pub fn new(pieces: &[Piece], popts: &ProfileOptions) -> Plan {
        let nodes = nodes(pieces, popts);
        let v = Slowing::new(nodes.s.len()).speeds(&nodes, popts.accel);
        let motion = Arc::new(plan_at_speeds(pieces, &nodes, &v, popts));
        let lanes = point_lanes(&motion.p);
        Plan {
            nodes,
            p_lanes: (Arc::clone(&motion), lanes),
            motion,
            v,
        }
    }

    /// The motion's points lane by lane, when they are of the current `motion` (a caller may
    /// have replaced it).
    fn point_lanes(&self) -> Option<&[TipLanes]> {
        Arc::ptr_eq(&self.p_lanes.0, &self.motion).then_some(&self.p_lanes.1[..])
    }
}

/// Points `p` lane by lane, [`crate::simd::LANES`] a chunk (lanes past the end: 0).
fn point_lanes(p: &[V3]) -> Vec<TipLanes> {
    p.chunks(crate::simd::LANES)
        .map(|c| {
            let mut x = [[0.0; crate::simd::LANES]; 3];
            for (l, v) in c.iter().enumerate() {
                (x[0][l], x[1][l], x[2][l]) = (v.x, v.y, v.z);
            }
            x
        })
        .collect()
}

/// Buffers reused from one placement to the next (joint positions, their derivatives, TCP
/// points), so that timing a path allocates nothing once they are large enough.
#[derive(Clone, Debug, Default)]
pub struct Buffers {
    /// Joint positions, row-major.
    pub qs: Vec<f64>,
    /// TCP points in the base frame, m.
    pub tcp: Vec<V3>,
    /// Joint velocities, row-major (rad/s).
    pub qd: Vec<f64>,
    /// Joint accelerations, row-major (rad/s²).
    pub qdd: Vec<f64>,
    /// Per sample of the last successfully timed path, the sines then the cosines of its joint
    /// positions (`2 n` values a sample; prismatic joints' entries unused), computed once by the
    /// IK's FK re-check and shared with RNEA and the feasibility checks. Left here by
    /// [`time_path_planned`] (it is not part of the [`TimedPath`]).
    pub sincos: Vec<f64>,
    /// Keep no sines and cosines past the batch whose FK re-check needs them: `sincos` is left
    /// empty (a long path's full evaluation: `2 n` values a sample, 96 bytes for a six-axis
    /// arm, that its consumers compute again with the same function, bit for bit, where they
    /// need them). Off by default.
    pub transient_sincos: bool,
    /// Keep no joint velocities and accelerations: the timed path's `qd` and `qdd` are left
    /// empty, its consumers derive them from the positions a block at a time (the same
    /// values, bit for bit), and a re-planned round lets the previous round's samples go
    /// before planning (a long path's full evaluation: 96 bytes a sample fewer for a
    /// six-axis arm). Applies to paths of at least 5 samples; off by default.
    pub lean_rates: bool,
    /// The base-frame tips of the shared plan's samples at the placement being timed, lane by
    /// lane ([`TipMap::lanes_of`]), computed once by the reach prune of [`time_at_planned`] and used
    /// again by its tracking's first round (scratch; meaningless between calls).
    tips: Vec<TipLanes>,
}

impl Buffers {
    /// Free every vector, keeping the settings (a long path's buffers, hundreds of megabytes,
    /// are not worth keeping for a next placement).
    pub fn release(&mut self) {
        let (transient_sincos, lean_rates) = (self.transient_sincos, self.lean_rates);
        *self = Buffers {
            transient_sincos,
            lean_rates,
            ..Buffers::default()
        };
    }

    /// Free the per-sample vectors of a tracked round (positions, TCP points, rates, sines),
    /// keeping the settings and the tips.
    fn release_samples(&mut self) {
        self.qs = Vec::new();
        self.tcp = Vec::new();
        self.qd = Vec::new();
        self.qdd = Vec::new();
        self.sincos = Vec::new();
    }

    /// Take back the vectors of a timed path for reuse.
    pub fn recycle(&mut self, t: TimedPath) {
        self.qs = t.traj.q;
        self.qd = t.traj.qd;
        self.qdd = t.traj.qdd;
        self.tcp = t.tcp;
    }
}

/// The placement-independent side of timing a path, borrowed from whoever owns it (a
/// [`crate::evaluate::PathJob`], a test): the blended path, its shared first [`Plan`], the
/// source line of each move, and the options. Built once, used for every placement.
#[derive(Clone, Copy)]
pub struct PathTiming<'a> {
    /// The blended path, part frame.
    pub pieces: &'a [Piece],
    /// Its first Cartesian plan (no slow-down), shared by all placements.
    pub plan: &'a Plan,
    /// Source line of timing move `i` (for messages).
    pub moves_line: &'a dyn Fn(usize) -> usize,
    /// Cartesian profile limits (m/s², m/s³) and the interpolation period (s).
    pub profile: &'a ProfileOptions,
    /// Joint-stage options.
    pub joint: &'a JointStageOptions,
    /// Source file of the path, named in every [`TimingFailure`] (empty: unknown).
    pub source: &'a str,
}

/// Time `pieces` at the placement `at`: Cartesian plan, IK with one configuration from `q0`
/// (rad / m), joint-limit checks and slow-downs until every limit holds at every sample.
/// Convenience form of [`time_path_planned`] that plans the path itself.
pub fn time_path(
    solver: &IkSolver,
    pieces: &[Piece],
    moves_line: &dyn Fn(usize) -> usize,
    at: &Placement,
    q0: &[f64],
    popts: &ProfileOptions,
    jopts: &JointStageOptions,
) -> Result<TimedPath, TimingFailure> {
    let plan = Plan::new(pieces, popts);
    let path = PathTiming {
        pieces,
        plan: &plan,
        moves_line,
        profile: popts,
        joint: jopts,
        source: "",
    };
    time_path_planned(solver, &path, at, q0, &mut Buffers::default())
}

/// [`time_path`] with the job's shared [`Plan`] (used as is in the first round) and reusable
/// buffers (moved into the result; hand them back with [`Buffers::recycle`]).
pub fn time_path_planned(
    solver: &IkSolver,
    path: &PathTiming<'_>,
    at: &Placement,
    q0: &[f64],
    buf: &mut Buffers,
) -> Result<TimedPath, TimingFailure> {
    time_path_rounds(solver, path, at, q0, buf, None).map_err(|e| e.in_file(path.source))
}

/// [`time_path_planned`], with the base-frame tips of the shared plan's samples at `at`
/// already computed when `pre` is given (see [`track_with`]; used in the first round only,
/// whose motion is the shared plan's).
fn time_path_rounds(
    solver: &IkSolver,
    path: &PathTiming<'_>,
    at: &Placement,
    q0: &[f64],
    buf: &mut Buffers,
    pre: Option<&[TipLanes]>,
) -> Result<TimedPath, TimingFailure> {
    let model = solver.model;
    let mut rs = Rounds {
        path,
        n: model.dof(),
        slowing: Slowing::new(path.plan.nodes.s.len()),
        v: Vec::new(),
        slowdowns: Vec::new(),
        round: 0,
        fewest: usize::MAX,
        max_rounds: path.joint.max_iterations.max(1),
    };
    let mut tracked = std::mem::take(buf);
    let mut next: Option<Arc<CartesianMotion>> = None;
    loop {
        rs.round += 1;
        let motion = next.take().unwrap_or_else(|| Arc::clone(&path.plan.motion));
        let pre = if rs.round == 1 { pre } else { None };
        if let Err(e) = track_with(
            solver,
            path.pieces,
            path.moves_line,
            &motion,
            at,
            q0,
            &mut tracked,
            pre,
        ) {
            *buf = tracked;
            return Err(e);
        }
        let dt = motion.dt;
        let lean = tracked.lean_rates && tracked.qs.len() >= 5 * rs.n && dt > 0.0 && dt.is_finite();
        let viol = if lean {
            // Positions only: the rates are derived where they are used.
            tracked.qd = Vec::new();
            tracked.qdd = Vec::new();
            let level = crate::simd::level();
            lean_violations(model, &tracked.qs, dt, path.joint.check_jerk, level)
        } else {
            derivatives_and_violations(
                model,
                &tracked.qs,
                dt,
                path.joint.check_jerk,
                &mut tracked.qd,
                &mut tracked.qdd,
                crate::simd::level(),
            )
        };
        if viol.is_empty() {
            return Ok(rs.finish(tracked, buf, motion));
        }
        if let Err(e) = rs.slow_down(&viol, &tracked, &motion) {
            *buf = tracked;
            return Err(e);
        }
        // This round's plan and tracked samples are not needed to plan the next one: a
        // long path's (hundreds of megabytes) are let go first, so that two rounds' worth
        // never coexist.
        drop(motion);
        if lean {
            tracked.release_samples();
        }
        let PathTiming {
            pieces,
            plan,
            profile,
            ..
        } = *path;
        next = Some(Arc::new(plan_at_speeds(
            pieces,
            &plan.nodes,
            &rs.v,
            profile,
        )));
    }
}

/// The planning rounds of [`time_path_rounds`]: the slow-down so far and what it reports.
struct Rounds<'p, 'a> {
    path: &'p PathTiming<'a>,
    /// Joints of the arm.
    n: usize,
    slowing: Slowing,
    /// Node speeds of the current round's plan (from the second round on; the first is the
    /// shared plan's).
    v: Vec<f64>,
    slowdowns: Vec<Slowdown>,
    /// Rounds planned so far.
    round: usize,
    /// Fewest samples over a limit left by a round so far.
    fewest: usize,
    max_rounds: usize,
}

impl Rounds<'_, '_> {
    /// The timed path of the round whose tracked samples `tracked` keep every limit (its
    /// sines and cosines left in `buf`).
    fn finish(
        self,
        tracked: Buffers,
        buf: &mut Buffers,
        motion: Arc<CartesianMotion>,
    ) -> TimedPath {
        let mut traj = JointTrajectory::new(self.n);
        let len = motion.p.len();
        traj.t = match i32::try_from(len) {
            // The same values (k < 2³¹ converts exactly either way), converted in vectors.
            Ok(len) => (0..len).map(|k| f64::from(k) * motion.dt).collect(),
            Err(_) => (0..len).map(|k| k as f64 * motion.dt).collect(),
        };
        traj.q = tracked.qs;
        traj.qd = tracked.qd;
        traj.qdd = tracked.qdd;
        buf.sincos = tracked.sincos;
        buf.transient_sincos = tracked.transient_sincos;
        buf.lean_rates = tracked.lean_rates;
        TimedPath {
            traj,
            motion,
            tcp: tracked.tcp,
            slowdowns: self.slowdowns,
            rounds: self.round,
            accel_factor: self.slowing.min_accel_factor(),
        }
    }

    /// The limits not met: the worst of `viol` (samples of `motion`).
    fn worst(&self, viol: &[Violation], motion: &CartesianMotion) -> TimingFailure {
        let w = viol
            .iter()
            .max_by(|a, b| a.ratio.total_cmp(&b.ratio))
            .expect("non-empty");
        TimingFailure::LimitsNotMet {
            joint: w.joint,
            kind: w.kind,
            ratio: w.ratio,
            t: w.sample as f64 * motion.dt,
            sample: w.sample,
            line: (self.path.moves_line)(self.path.pieces[motion.piece[w.sample]].move_index),
            rounds: self.round,
            file: std::sync::Arc::default(),
        }
    }

    /// After a round whose plan `motion` (tracked: `tracked`) has the violations `viol`: slow
    /// down around every violating sample (see [`Slowing`]), report the worst per (joint,
    /// kind, move), and set the next round's node speeds (`v`); the limits not met when no
    /// round may follow.
    fn slow_down(
        &mut self,
        viol: &[Violation],
        tracked: &Buffers,
        motion: &CartesianMotion,
    ) -> Result<(), TimingFailure> {
        let PathTiming {
            pieces,
            plan: shared,
            profile: popts,
            joint: jopts,
            ..
        } = *self.path;
        let nodes = &shared.nodes;
        let again = replan_again(self.round, self.max_rounds, viol.len(), self.fewest);
        self.fewest = self.fewest.min(viol.len());
        if !again {
            return Err(self.worst(viol, motion));
        }
        let excess = excesses_of(viol, tracked, motion, self.n);
        let margin = round_margin(jopts.margin, self.round, self.max_rounds);
        let v_now: &[f64] = if self.round == 1 { &shared.v } else { &self.v };
        let levers = self.slowing.apply(nodes, v_now, motion, &excess, margin);
        for (w, lever) in viol.iter().zip(&levers) {
            let i = nodes
                .s
                .partition_point(|&x| x < motion.s[w.sample])
                .min(nodes.s.len() - 1);
            let factors = match *lever {
                Lever::Speed(f) => {
                    // The new speed there against the unslowed plan's.
                    let v0 = shared.v[i];
                    (
                        if v0 > 0.0 {
                            (f * v_now[i] / v0).min(f)
                        } else {
                            f
                        },
                        1.0,
                    )
                }
                Lever::Accel(g) => (1.0, self.slowing.accel_scale.get(i).copied().unwrap_or(g)),
            };
            let mi = pieces[motion.piece[w.sample]].move_index;
            record_slowdown(&mut self.slowdowns, w, factors, motion, mi, self.round);
        }
        // The next round's node speeds, once: for its plan, and first for the budget: a
        // slow-down so deep that the re-planned motion would exceed the sample budget (a joint
        // limit of 1e-9 rad/s) is a failure to meet the limits, not an allocation of
        // terabytes.
        self.v = self.slowing.speeds(nodes, popts.accel);
        if over_budget(&self.v, nodes, popts) {
            return Err(self.worst(viol, motion));
        }
        Ok(())
    }
}

/// The violations `viol` of the round tracked in `tracked` (plan `motion`, `n` joints) as
/// excesses, with the share of each that comes from a ramp.
fn excesses_of(
    viol: &[Violation],
    tracked: &Buffers,
    motion: &CartesianMotion,
    n: usize,
) -> Vec<Excess> {
    let dt = motion.dt;
    viol.iter()
        .map(|w| {
            let (k, j) = (w.sample, w.joint);
            let jerk = if w.kind == LimitKind::Jerk {
                crate::numerics::third_derivative_uniform_at(&tracked.qs, n, dt, k, j)
            } else {
                0.0
            };
            Excess {
                sample: k,
                joint: j,
                kind: w.kind,
                ratio: w.ratio,
                ramp_share: ramp_share(
                    w.kind,
                    w.rate.0,
                    w.rate.1,
                    jerk,
                    path_rates(&motion.s, dt, k),
                ),
            }
        })
        .collect()
}

/// Violation `w` (a sample of `motion`, on move `mi`) slowed down by the speed and
/// acceleration `factors` in round `round`, recorded: the worst per (joint, kind, move).
fn record_slowdown(
    slowdowns: &mut Vec<Slowdown>,
    w: &Violation,
    factors: (f64, f64),
    motion: &CartesianMotion,
    mi: usize,
    round: usize,
) {
    let (speed, accel) = factors;
    match slowdowns
        .iter_mut()
        .find(|s| s.joint == w.joint && s.kind == w.kind && s.move_index == mi)
    {
        Some(s) => {
            if w.ratio > s.ratio && round == 1 {
                s.ratio = w.ratio;
                s.t = w.sample as f64 * motion.dt;
                s.s = motion.s[w.sample];
            }
            s.speed_factor = s.speed_factor.min(speed);
            s.accel_factor = s.accel_factor.min(accel);
        }
        None => slowdowns.push(Slowdown {
            joint: w.joint,
            kind: w.kind,
            t: w.sample as f64 * motion.dt,
            s: motion.s[w.sample],
            move_index: mi,
            ratio: w.ratio,
            speed_factor: speed,
            accel_factor: accel,
        }),
    }
}

/// Whether a plan at node speeds `v` over `nodes` would exceed the sample budget (its
/// duration estimated from the speeds, the dwells and the jerk filter).
fn over_budget(v: &[f64], nodes: &Nodes, popts: &ProfileOptions) -> bool {
    let t_est: f64 = (1..v.len())
        .map(|i| {
            let vs = v[i] + v[i - 1];
            if vs > 0.0 {
                2.0 * (nodes.s[i] - nodes.s[i - 1]) / vs
            } else {
                0.0
            }
        })
        .sum::<f64>()
        + nodes.dwell_total();
    let samples = t_est / popts.dt + popts.accel / popts.jerk / popts.dt;
    samples.is_nan() || samples > super::budget::max_samples() as f64
}

/// Time a blended path at a placement, choosing the arm configuration: every IK solution at
/// the first sample is tried, widest joint-limit margin first, and the first that carries the
/// whole path with one configuration wins. When none does, the failure of the candidate that
/// got furthest along the path is returned. Convenience form of [`time_at_planned`].
pub fn time_at(
    solver: &IkSolver,
    pieces: &[Piece],
    moves_line: &dyn Fn(usize) -> usize,
    at: &Placement,
    popts: &ProfileOptions,
    jopts: &JointStageOptions,
) -> Result<TimedPath, TimingFailure> {
    let plan = Plan::new(pieces, popts);
    let path = PathTiming {
        pieces,
        plan: &plan,
        moves_line,
        profile: popts,
        joint: jopts,
        source: "",
    };
    time_at_planned(solver, &path, at, &mut Buffers::default())
}

/// [`time_at`] with the job's shared [`Plan`] and reusable [`Buffers`]: what a placement
/// sweep calls in its hot loop.
pub fn time_at_planned(
    solver: &IkSolver,
    path: &PathTiming<'_>,
    at: &Placement,
    buf: &mut Buffers,
) -> Result<TimedPath, TimingFailure> {
    let mut tips = std::mem::take(&mut buf.tips);
    tips.clear();
    let r = time_at_with(solver, path, at, buf, &mut tips);
    buf.tips = tips;
    r.map_err(|e| e.in_file(path.source))
}

/// The body of [`time_at_planned`]; `tips` (empty) receives the base-frame tips of the
/// shared plan's samples lane by lane when the reach prune computes them all.
fn time_at_with(
    solver: &IkSolver,
    path: &PathTiming<'_>,
    at: &Placement,
    buf: &mut Buffers,
    tips_all: &mut Vec<TipLanes>,
) -> Result<TimedPath, TimingFailure> {
    let PathTiming {
        pieces,
        plan,
        moves_line,
        joint: jopts,
        ..
    } = *path;
    let part_to_base = at.frame();
    let first = pieces
        .first()
        .map(|p| p.prim.point(0.0))
        .unwrap_or_else(V3::zeros);
    let tip = part_to_base.apply(&first);
    let unreachable_at_start = |reason| TimingFailure::Unreachable {
        sample: 0,
        t: 0.0,
        point: tip,
        line: moves_line(0),
        reason,
        file: std::sync::Arc::default(),
    };
    let stride = jopts.prune_stride;
    let pl = Pruning {
        solver,
        pieces,
        moves_line,
        motion0: &plan.motion,
        part_to_base,
        rot: nozzle_target(&V3::zeros(), at.nozzle_yaw()).rot,
    };
    if stride > 0 {
        pl.reach(plan, tips_all)?;
    }
    let mut cands = solver
        .solve_all(&nozzle_target(&tip, at.nozzle_yaw()))
        .map_err(unreachable_at_start)?;
    let model = solver.model;
    cands.sort_by(|a, b| {
        crate::kinematics::limit_margin(model, &b.q)
            .total_cmp(&crate::kinematics::limit_margin(model, &a.q))
    });
    // The tips of every sample, when the prune computed them (the same values as
    // part_to_base.apply).
    let tips_all: Option<&[TipLanes]> =
        (tips_all.len() * crate::simd::LANES >= pl.motion0.p.len()).then_some(&tips_all[..]);
    let mut best_err: Option<TimingFailure> = None;
    let level = crate::simd::level();
    for c in &cands {
        if stride > 0 && !pl.motion0.p.is_empty() {
            if let Err(e) = pl.thinned(&c.q, stride, tips_all, level) {
                keep_furthest(&mut best_err, e);
                continue;
            }
        }
        match time_path_rounds(solver, path, at, &c.q, buf, tips_all) {
            Ok(t) => return Ok(t),
            Err(e) => keep_furthest(&mut best_err, e),
        }
    }
    Err(best_err.unwrap_or_else(|| {
        unreachable_at_start(IkFailure::Unsupported(
            "no IK solution at the first sample".into(),
        ))
    }))
}

/// Keep `e` in `best` when it got further along the path than the failure kept there.
fn keep_furthest(best: &mut Option<TimingFailure>, e: TimingFailure) {
    let progress = |e: &TimingFailure| match e {
        TimingFailure::Unreachable { sample, .. }
        | TimingFailure::ConfigurationChange { sample, .. } => *sample,
        TimingFailure::LimitsNotMet { .. } => usize::MAX,
    };
    if best.as_ref().is_none_or(|b| progress(&e) > progress(b)) {
        *best = Some(e);
    }
}

/// The tip `tip` (base frame, m) at sample `k` of `motion` is out of reach (`reason`): the
/// failure, naming the move's line.
fn unreachable_sample(
    pieces: &[Piece],
    moves_line: &dyn Fn(usize) -> usize,
    motion: &CartesianMotion,
    k: usize,
    tip: V3,
    reason: IkFailure,
) -> TimingFailure {
    let mi = pieces[motion.piece[k]].move_index;
    TimingFailure::Unreachable {
        sample: k,
        t: k as f64 * motion.dt,
        point: tip,
        line: moves_line(mi),
        reason,
        file: std::sync::Arc::default(),
    }
}

/// The cheap tests of [`time_at_with`] at one placement before any configuration is tracked
/// along the shared plan: every sample within reach, every stride-th sample within a
/// configuration's branch.
struct Pruning<'p, 's> {
    solver: &'p IkSolver<'s>,
    pieces: &'p [Piece],
    moves_line: &'p dyn Fn(usize) -> usize,
    /// The shared plan's motion.
    motion0: &'p CartesianMotion,
    part_to_base: Frame,
    /// The nozzle's orientation in the base frame (the same at every sample).
    rot: crate::math::M3,
}

impl Pruning<'_, '_> {
    /// Sample `k`'s tip out of reach: the failure.
    fn fail_at(&self, k: usize, tip: V3, reason: IkFailure) -> TimingFailure {
        unreachable_sample(self.pieces, self.moves_line, self.motion0, k, tip, reason)
    }

    /// The tool target at sample `k`, and its tip (base frame).
    fn target_at(&self, k: usize) -> (Frame, V3) {
        let tip = self.part_to_base.apply(&self.motion0.p[k]);
        (
            Frame {
                rot: self.rot,
                pos: tip,
            },
            tip,
        )
    }

    /// Prune 1: every sample's wrist centre within reach (no trigonometry), coarse to fine
    /// so that a path leaving the reachable set is found after a few samples. With SIMD, the
    /// tips of every sample lane by lane go to `tips_all`.
    fn reach(&self, plan: &Plan, tips_all: &mut Vec<TipLanes>) -> Result<(), TimingFailure> {
        let (solver, motion0) = (self.solver, self.motion0);
        let m = motion0.p.len();
        let coarse = (0..m).step_by(PRUNE_COARSE_STRIDE);
        match solver.wrist_offset(&self.rot) {
            Some(d) if crate::simd::level() != crate::simd::Level::Scalar => {
                for k in coarse {
                    let tip = self.part_to_base.apply(&motion0.p[k]);
                    if let Err(reason) = solver.wrist_centre_reachable(&(tip + d), 1e-9) {
                        return Err(self.fail_at(k, tip, reason));
                    }
                }
                self.reach_lanes(plan, d, tips_all)
            }
            Some(d) => {
                for k in coarse.chain(0..m) {
                    let tip = self.part_to_base.apply(&motion0.p[k]);
                    if let Err(reason) = solver.wrist_centre_reachable(&(tip + d), 1e-9) {
                        return Err(self.fail_at(k, tip, reason));
                    }
                }
                Ok(())
            }
            None => {
                for k in coarse.chain(0..m) {
                    let (target, tip) = self.target_at(k);
                    if let Err(reason) = solver.reachable(&target) {
                        return Err(self.fail_at(k, tip, reason));
                    }
                }
                Ok(())
            }
        }
    }

    /// Every sample, LANES at a time: the front shoulder's reach in lockstep, conservatively
    /// (reach::FrontReach: a lane it passes, the exact test passes); a lane it does not pass
    /// is asked per sample (the exact test, the back shoulder, and the error), in order: the
    /// exact test's outcome. `d`: the wrist centre's offset from the tip.
    fn reach_lanes(
        &self,
        plan: &Plan,
        d: V3,
        tips_all: &mut Vec<TipLanes>,
    ) -> Result<(), TimingFailure> {
        const LANES: usize = crate::simd::LANES;
        let solver = self.solver;
        let m = self.motion0.p.len();
        let level = crate::simd::level();
        let front_reach = solver.model.opw.as_ref().map(super::reach::FrontReach::new);
        // The block's masks (chunk front_at + i at i).
        let (mut front, mut front_at) = ([0u32; PRUNE_BLOCK], 0);
        let mut k0 = 0;
        // The tips lane by lane (TipMap::lanes_of, bit for bit part_to_base.apply), kept for
        // the second prune and the first round of tracking.
        let chunks = m.div_ceil(LANES);
        tips_all.reserve(chunks);
        let map = TipMap::new(&self.part_to_base);
        // The points lane by lane (the plan's, or now), PRUNE_BLOCK chunks mapped at a time.
        let own;
        let x = match plan.point_lanes() {
            Some(x) if x.len() == chunks => x,
            _ => {
                own = point_lanes(&self.motion0.p);
                &own[..]
            }
        };
        while k0 < m {
            let count = LANES.min(m - k0);
            let c0 = k0 / LANES;
            if c0 == tips_all.len() {
                let b = PRUNE_BLOCK.min(chunks - c0);
                tips_all.resize(c0 + b, [[0.0; LANES]; 3]);
                map.lanes_of(&x[c0..c0 + b], &mut tips_all[c0..c0 + b], level);
                // The wrist centres tip + d of the block (V3's sum per coordinate) the screen
                // passes.
                front_at = c0;
                match &front_reach {
                    Some(r) => r.masks(
                        &tips_all[c0..c0 + b],
                        [d.x, d.y, d.z],
                        1e-9,
                        &mut front[..b],
                        level,
                    ),
                    None => front.fill(0),
                }
            }
            let t = &tips_all[c0];
            // The lanes it does not pass, in order.
            let mut missed = !front[c0 - front_at] & ((1u32 << count) - 1);
            while missed != 0 {
                let l = missed.trailing_zeros() as usize;
                missed &= missed - 1;
                let tip = V3::new(t[0][l], t[1][l], t[2][l]);
                if let Err(reason) = solver.wrist_centre_reachable(&(tip + d), 1e-9) {
                    return Err(self.fail_at(k0 + l, tip, reason));
                }
            }
            k0 += count;
        }
        Ok(())
    }

    /// Sample `k`'s tip: from the tips computed lane by lane (`tips_all`), or now.
    #[inline]
    fn tip_at(&self, tips_all: Option<&[TipLanes]>, k: usize) -> V3 {
        const LANES: usize = crate::simd::LANES;
        match tips_all {
            Some(t) => {
                let c = &t[k / LANES];
                V3::new(c[0][k % LANES], c[1][k % LANES], c[2][k % LANES])
            }
            None => self.part_to_base.apply(&self.motion0.p[k]),
        }
    }

    /// Prune 2: a configuration `q` whose branch cannot reach every `stride`-th sample
    /// within limits would fail while tracking; the failure says where.
    fn thinned(
        &self,
        q: &[f64],
        stride: usize,
        tips_all: Option<&[TipLanes]>,
        level: crate::simd::Level,
    ) -> Result<(), TimingFailure> {
        const LANES: usize = crate::simd::LANES;
        let solver = self.solver;
        let Some(b) = solver.branch_of(q) else {
            return Ok(());
        };
        let m = self.motion0.p.len();
        let ks = (stride..m).step_by(stride).chain(std::iter::once(m - 1));
        if level == crate::simd::Level::Scalar {
            for k in ks {
                let (target, tip) = self.target_at(k);
                if let Err(reason) = solver.branch_admits(&target, b.shoulder, b.elbow) {
                    return Err(self.fail_at(k, tip, reason));
                }
            }
            return Ok(());
        }
        // LANES samples at a time, their closed form in lockstep: the same verdicts, and the
        // first sample rejected with the same error.
        let (mut idx, mut tips) = ([0usize; LANES], [V3::zeros(); LANES]);
        let mut count = 0;
        let mut ks = ks.peekable();
        while let Some(k) = ks.next() {
            idx[count] = k;
            tips[count] = self.tip_at(tips_all, k);
            count += 1;
            if count == LANES || ks.peek().is_none() {
                let tips = &tips[..count];
                if let Some((l, reason)) =
                    solver.branch_admits_batch(&self.rot, tips, b.shoulder, b.elbow, level)
                {
                    return Err(self.fail_at(idx[l], tips[l], reason));
                }
                count = 0;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::timing::geometry::{blend_path, Move, Prim};

    /// A 1 m straight line at 0.15 m/s from rest to rest: its nodes and unslowed plan.
    fn line() -> (Vec<Piece>, Plan, ProfileOptions) {
        let moves = [Move {
            prim: Prim::Line {
                a: V3::zeros(),
                b: V3::new(1.0, 0.0, 0.0),
            },
            speed: 0.15,
            zone: 0.0,
            print: true,
            line: 1,
        }];
        let pieces = blend_path(&moves);
        let popts = ProfileOptions::default();
        let plan = Plan::new(&pieces, &popts);
        (pieces, plan, popts)
    }

    /// The sample of `motion` nearest arc length `s`, m.
    fn sample_at(motion: &CartesianMotion, s: f64) -> usize {
        motion.s.partition_point(|&x| x < s)
    }

    /// A deterministic stream in [-1, 1) (xorshift).
    fn uniform(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed.max(1);
        move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            2.0 * ((s >> 11) as f64 / (1u64 << 53) as f64) - 1.0
        }
    }

    fn levels() -> Vec<crate::simd::Level> {
        crate::simd::Level::ALL
            .into_iter()
            .filter(|l| l.available())
            .collect()
    }

    #[test]
    fn fused_and_block_derived_rates_and_their_limit_checks_equal_the_two_passes_bit_for_bit() {
        // The one-pass derivatives and screened limit checks, and the rates derived a block
        // at a time with the lean checks on them (from 5 samples), against the two passes of
        // the per-sample path (differentiate_uniform_into_on, then violations, both scalar):
        // paths of 0 to 40 samples and longer ones (not multiples of 8 or of a block),
        // positions with NaN and infinities here and there, limits at quantiles of the
        // demand (and none, NaN, −∞, 0, negative), steps whose jerk denominator underflows
        // or is huge, into fresh buffers and reused ones holding garbage: the same q̇ and q̈
        // to the bit, and the same excesses (sample, joint, kind, ratio) in the same order.
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let base = crate::robot::load(&root.join("robots/abb_irb6700_200_260")).unwrap();
        let n = base.dof();
        let mut checked = 0;
        let mut with_excess = 0;
        let lens: Vec<usize> = (0..=40).chain([63, 64, 65, 150, 1001]).collect();
        for (t, &m) in lens.iter().enumerate() {
            for dt in [0.004, 1e-110, 0.25, 1e100] {
                let mut u = uniform(100 + t as u64);
                let mut q = vec![0.0; m * n];
                let mut vel = vec![0.0; n];
                for k in 0..m {
                    for j in 0..n {
                        vel[j] += 0.02 * u();
                        q[k * n + j] =
                            if k == 0 { u() } else { q[(k - 1) * n + j] } + vel[j] * 0.004;
                    }
                }
                let mut q_bad = q.clone();
                if m > 12 {
                    q_bad[5 * n + 1] = f64::NAN;
                    q_bad[(m - 4) * n + 3] = f64::INFINITY;
                    q_bad[9 * n] = f64::NEG_INFINITY;
                }
                for q in [&q, &q_bad] {
                    let (mut d0, mut dd0) = (Vec::new(), Vec::new());
                    crate::numerics::differentiate_uniform_into_on(
                        q,
                        n,
                        dt,
                        &mut d0,
                        &mut dd0,
                        crate::simd::Level::Scalar,
                    );
                    let max_abs = |v: &[f64], j: usize| {
                        (0..m)
                            .map(|k| v[k * n + j].abs())
                            .filter(|x| x.is_finite())
                            .fold(0.0, f64::max)
                    };
                    let jerk: Vec<f64> = crate::numerics::third_derivative_uniform(q, n, dt);
                    for (case, scale) in [0.5, 0.97, 1.0, 2.0, 0.0, -1.0].iter().enumerate() {
                        let mut model = base.clone();
                        for (j, jt) in model.joints.iter_mut().enumerate() {
                            jt.velocity_limit = scale * max_abs(&d0, j);
                            jt.acceleration_limit = scale * max_abs(&dd0, j);
                            jt.jerk_limit = scale * max_abs(&jerk, j);
                            match (case + j) % 5 {
                                0 => jt.jerk_limit = f64::INFINITY,
                                1 => jt.velocity_limit = f64::NAN,
                                2 => jt.acceleration_limit = f64::NEG_INFINITY,
                                3 => jt.jerk_limit = f64::MIN_POSITIVE * 0.5,
                                _ => {}
                            }
                        }
                        for check_jerk in [true, false] {
                            let want = violations(
                                &model,
                                q,
                                &d0,
                                &dd0,
                                dt,
                                check_jerk,
                                crate::simd::Level::Scalar,
                            );
                            with_excess += usize::from(!want.is_empty());
                            let key = |v: &Violation| {
                                let r = (v.rate.0.to_bits(), v.rate.1.to_bits());
                                (v.sample, v.joint, v.kind, v.ratio.to_bits(), r)
                            };
                            let bits =
                                |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                            for &level in &levels() {
                                for garbage in [0, m * n / 2, m * n + 7] {
                                    let mut d = vec![f64::NAN; garbage];
                                    let mut dd = vec![-3.0; garbage];
                                    let got = derivatives_and_violations(
                                        &model, q, dt, check_jerk, &mut d, &mut dd, level,
                                    );
                                    let what = format!(
                                        "m={m} dt={dt} scale={scale} jerk={check_jerk} {level:?}"
                                    );
                                    assert_eq!(bits(&d), bits(&d0), "{what}");
                                    assert_eq!(bits(&dd), bits(&dd0), "{what}");
                                    assert_eq!(
                                        got.iter().map(key).collect::<Vec<_>>(),
                                        want.iter().map(key).collect::<Vec<_>>(),
                                        "{what}"
                                    );
                                    checked += 1;
                                }
                                if m < 5 {
                                    continue;
                                }
                                let lean = lean_violations(&model, q, dt, check_jerk, level);
                                assert_eq!(
                                    lean.iter().map(key).collect::<Vec<_>>(),
                                    want.iter().map(key).collect::<Vec<_>>(),
                                    "lean m={m} dt={dt} scale={scale} jerk={check_jerk} {level:?}"
                                );
                                // Blocks of every size from every start, ends included.
                                let w = crate::numerics::uniform_weights(dt);
                                for count in [1, 2, 3, 7, m / 2, m] {
                                    for k0 in (0..m).step_by(count.max(1)) {
                                        let c = count.min(m - k0);
                                        let (mut d, mut dd) = (vec![7.0; c * n], vec![7.0; c * n]);
                                        crate::numerics::uniform_rates_rows(
                                            q, n, &w, k0, c, &mut d, &mut dd, level,
                                        );
                                        let r = k0 * n..(k0 + c) * n;
                                        assert_eq!(
                                            bits(&d),
                                            bits(&d0[r.clone()]),
                                            "m={m} {k0}+{c}"
                                        );
                                        assert_eq!(bits(&dd), bits(&dd0[r]), "m={m} {k0}+{c}");
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
        assert!(
            checked > 1000 && with_excess > 100,
            "{checked} {with_excess}"
        );
    }

    #[test]
    fn a_path_timed_without_keeping_its_rates_is_the_same_path_and_derives_the_same_rates() {
        // A 1.8 × 0.6 m rectangle printed twice by the IRB 6700 with its joint limits lowered
        // so that the controller slows down over several rounds: timed keeping the rates and
        // timed lean (positions only, the previous round let go before each re-plan), the
        // same positions, slow-downs and rounds, and the rates derived a block at a time
        // equal the kept ones, bit for bit.
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut model = crate::robot::load(&root.join("robots/abb_irb6700_200_260")).unwrap();
        for j in &mut model.joints {
            j.velocity_limit *= 0.15;
            j.acceleration_limit *= 0.15;
        }
        let c = [
            (-0.9, -0.3),
            (0.9, -0.3),
            (0.9, 0.3),
            (-0.9, 0.3),
            (-0.9, -0.3),
        ];
        let moves: Vec<Move> = (0..2)
            .flat_map(|layer| {
                let z = 0.004 * (layer + 1) as f64;
                c.windows(2).enumerate().map(move |(i, w)| Move {
                    prim: Prim::Line {
                        a: V3::new(w[0].0, w[0].1, z),
                        b: V3::new(w[1].0, w[1].1, z),
                    },
                    speed: 0.4,
                    zone: 0.01,
                    print: true,
                    line: 4 * layer + i + 1,
                })
            })
            .collect();
        let pieces = blend_path(&moves);
        let solver = crate::kinematics::IkSolver::new(&model).unwrap();
        let at = Placement::new(1.683, 0.128, 0.028, 90.3f64.to_radians());
        let popts = ProfileOptions::default();
        let plan = Plan::new(&pieces, &popts);
        let lines = |i: usize| i + 1;
        let path = PathTiming {
            pieces: &pieces,
            plan: &plan,
            moves_line: &lines,
            profile: &popts,
            joint: &JointStageOptions::default(),
            source: "",
        };
        let kept = time_at_planned(&solver, &path, &at, &mut Buffers::default()).unwrap();
        let mut buf = Buffers {
            lean_rates: true,
            ..Buffers::default()
        };
        let lean = time_at_planned(&solver, &path, &at, &mut buf).unwrap();
        assert!(kept.rounds > 2, "{} rounds", kept.rounds);
        assert!(lean.traj.qd.is_empty() && lean.traj.qdd.is_empty());
        assert!(buf.lean_rates);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&lean.traj.q), bits(&kept.traj.q));
        assert_eq!(bits(&lean.traj.t), bits(&kept.traj.t));
        assert_eq!(lean.slowdowns, kept.slowdowns);
        assert_eq!(lean.rounds, kept.rounds);
        assert_eq!(lean.accel_factor.to_bits(), kept.accel_factor.to_bits());
        let n = model.dof();
        let m = lean.traj.len();
        let mut rates = crate::trajectory::RateBlocks::new(&lean.traj, lean.motion.dt);
        for k0 in (0..m).step_by(1000) {
            let c = 1000.min(m - k0);
            let (qd, qdd) = rates.block(k0, c);
            assert_eq!(bits(qd), bits(&kept.traj.qd[k0 * n..(k0 + c) * n]), "{k0}");
            assert_eq!(
                bits(qdd),
                bits(&kept.traj.qdd[k0 * n..(k0 + c) * n]),
                "{k0}"
            );
        }
    }

    #[test]
    fn the_jerk_screens_bound_never_lets_an_excess_through() {
        // Wherever the per-sample check finds |num| / den > limit, the screen's division-free
        // test |num| > bound holds too: numerators around the limit to the last ulp, limits
        // and steps from tiny to huge (the product under- and overflowing), limits ≤ 0.
        let mut u = uniform(4242);
        let mut found = 0;
        for _ in 0..200_000 {
            let den = 2.0 * 10f64.powf(-120.0 + 240.0 * (0.5 + 0.5 * u())).powi(3);
            let limit = match (u() * 8.0) as i32 {
                0 => 0.0,
                -1 => -1.0,
                1 => f64::MIN_POSITIVE * (0.5 + u().abs()),
                _ => 10f64.powf(300.0 * u()),
            };
            let guess = limit * den;
            let mut num = guess * (1.0 + 1e-15 * u());
            if !num.is_finite() {
                num = f64::MAX * u().abs();
            }
            for k in -3i64..=3 {
                let x = f64::from_bits((num.abs().to_bits() as i64 + k).max(0) as u64);
                if x / den > limit {
                    found += 1;
                    assert!(
                        x > jerk_screen_bound(limit, den),
                        "num {x:e} den {den:e} limit {limit:e}"
                    );
                }
            }
        }
        assert!(found > 100_000, "{found}");
        assert_eq!(jerk_screen_bound(1.0, 0.0), f64::NEG_INFINITY);
        assert_eq!(jerk_screen_bound(f64::MAX, 4.0), f64::INFINITY);
        assert_eq!(jerk_screen_bound(1e-300, 1e-300), 0.0);
    }

    #[test]
    fn tips_mapped_lane_by_lane_equal_frame_apply_bit_for_bit_on_every_level() {
        // Placements with yaws that give exact zeros and signed zeros in the rotation, points
        // with zeros of both signs and of all sizes, paths of 1 to 17 points: every lane of
        // every level is Frame::apply of its point, to the bit (and lanes past the end hold
        // the frame's origin).
        let mut u = uniform(77);
        for yaw in [0.0, 90.0, 180.0, -90.0, 33.3, 271.0] {
            for (x, y, z) in [(1.534, -0.121, 0.0), (0.0, 0.0, 0.0), (-2.0, 1e-9, 0.3)] {
                let at = Placement::new(x, y, z, f64::to_radians(yaw));
                let frame = at.frame();
                let map = TipMap::new(&frame);
                for len in 1..=17 {
                    let p: Vec<V3> = (0..len)
                        .map(|k| match k % 4 {
                            0 => V3::new(0.0, -0.0, 0.0),
                            1 => V3::new(-0.0, 1e-300 * u(), -0.0),
                            _ => V3::new(3.0 * u(), 1e6 * u(), u()),
                        })
                        .collect();
                    let x = point_lanes(&p);
                    for &level in &levels() {
                        let mut out = vec![[[f64::NAN; crate::simd::LANES]; 3]; x.len()];
                        map.lanes_of(&x, &mut out, level);
                        for (k, pk) in p.iter().enumerate() {
                            let want = frame.apply(pk);
                            let c = &out[k / crate::simd::LANES];
                            for i in 0..3 {
                                assert_eq!(
                                    c[i][k % crate::simd::LANES].to_bits(),
                                    want[i].to_bits(),
                                    "yaw {yaw} len {len} sample {k} {level:?}"
                                );
                            }
                        }
                        for k in len..x.len() * crate::simd::LANES {
                            let c = &out[k / crate::simd::LANES];
                            for (i, ci) in c.iter().enumerate() {
                                assert_eq!(ci[k % crate::simd::LANES], frame.pos[i]);
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn a_plan_whose_motion_was_replaced_offers_no_stale_points() {
        // The plan's points lane by lane belong to its own motion: once a caller replaces
        // the motion, they are not used (the prune computes them from the motion it has).
        let (pieces, mut plan, popts) = line();
        let x = plan.point_lanes().expect("the plan's own");
        assert_eq!(x.len(), plan.motion.p.len().div_ceil(crate::simd::LANES));
        assert_eq!(point_lanes(&plan.motion.p), x);
        let other = Plan::new(
            &pieces[..],
            &ProfileOptions {
                dt: popts.dt * 2.0,
                ..popts
            },
        );
        plan.motion = Arc::clone(&other.motion);
        assert!(plan.point_lanes().is_none());
    }

    #[test]
    fn joint_rows_pushed_from_lanes_equal_the_lanes_joint_vectors() {
        // A full batch (the block transposes) and every shorter one, appended after rows
        // already there: row l is lane l's joint vector, the rows before are untouched.
        let mut q = [[0.0; crate::simd::LANES]; crate::kinematics::MAX_DOF];
        let mut u = uniform(9);
        for row in q.iter_mut() {
            for v in row.iter_mut() {
                *v = u();
            }
        }
        for taken in 0..=crate::simd::LANES {
            let mut qs = vec![7.0, -0.0, 1.5];
            push_rows6(&mut qs, &q, taken);
            assert_eq!(qs.len(), 3 + taken * 6);
            assert_eq!(qs[..3], [7.0, -0.0, 1.5]);
            for l in 0..taken {
                for j in 0..6 {
                    assert_eq!(
                        qs[3 + l * 6 + j].to_bits(),
                        q[j][l].to_bits(),
                        "{taken} {l} {j}"
                    );
                }
            }
        }
    }

    #[test]
    fn limit_checks_screened_in_lockstep_list_the_per_sample_checks_excesses_bit_for_bit() {
        // Random smooth-ish joint paths of several lengths on three robots, with limits set so
        // that none, a few and many samples exceed them (and joints without a limit): every
        // SIMD level lists exactly the per-sample path's excesses, in its order, with the same
        // ratios to the bit.
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let dt = 0.004;
        let levels: Vec<_> = crate::simd::Level::ALL
            .into_iter()
            .filter(|l| l.available())
            .collect();
        for (r, name) in ["abb_irb6700_200_260", "ur10e", "puma560"]
            .iter()
            .enumerate()
        {
            let base = crate::robot::load(&root.join("robots").join(name)).unwrap();
            let n = base.dof();
            for (t, &m) in [3usize, 4, 5, 6, 17, 64, 150, 1001].iter().enumerate() {
                let mut u = uniform(1 + (r * 10 + t) as u64);
                let mut q = vec![0.0; m * n];
                let mut vel = vec![0.0; n];
                for k in 0..m {
                    for j in 0..n {
                        vel[j] += 0.02 * u();
                        q[k * n + j] = if k == 0 { u() } else { q[(k - 1) * n + j] } + vel[j] * dt;
                    }
                }
                let (mut qd, mut qdd) = (Vec::new(), Vec::new());
                crate::numerics::differentiate_uniform_into_on(
                    &q,
                    n,
                    dt,
                    &mut qd,
                    &mut qdd,
                    crate::simd::Level::Scalar,
                );
                // Limits: each at a quantile of the demand (0.5, 0.95, 1.0, above all) or none.
                let max_abs = |v: &dyn Fn(usize, usize) -> f64, j: usize| {
                    (0..m).map(|k| v(k, j).abs()).fold(0.0, f64::max)
                };
                let jerk = |k: usize, j: usize| {
                    if m >= 5 {
                        crate::numerics::third_derivative_uniform_at(&q, n, dt, k, j)
                    } else {
                        0.0
                    }
                };
                for (case, scale) in [0.5, 0.97, 1.0, 2.0, f64::INFINITY].iter().enumerate() {
                    let mut model = base.clone();
                    for (j, jt) in model.joints.iter_mut().enumerate() {
                        let pick = (case + j) % 4;
                        jt.velocity_limit = scale * max_abs(&|k, j| qd[k * n + j], j);
                        jt.acceleration_limit = scale * max_abs(&|k, j| qdd[k * n + j], j);
                        jt.jerk_limit = scale * max_abs(&jerk, j);
                        match pick {
                            0 => jt.jerk_limit = f64::INFINITY,
                            1 => jt.velocity_limit = f64::NAN,
                            2 => jt.acceleration_limit = f64::NEG_INFINITY,
                            _ => {}
                        }
                    }
                    for check_jerk in [true, false] {
                        let want = violations(
                            &model,
                            &q,
                            &qd,
                            &qdd,
                            dt,
                            check_jerk,
                            crate::simd::Level::Scalar,
                        );
                        if *scale < 1.0 && m >= 5 && check_jerk {
                            assert!(!want.is_empty(), "{name} m={m} scale={scale}");
                        }
                        for &level in &levels {
                            let got = violations(&model, &q, &qd, &qdd, dt, check_jerk, level);
                            let key =
                                |v: &Violation| (v.sample, v.joint, v.kind, v.ratio.to_bits());
                            assert_eq!(
                                got.iter().map(key).collect::<Vec<_>>(),
                                want.iter().map(key).collect::<Vec<_>>(),
                                "{name} m={m} scale={scale} jerk={check_jerk} {level:?}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn a_limit_that_binds_again_where_the_speed_is_capped_compounds_the_cap() {
        // A velocity demand 1.2× the limit in the middle, then, planned again, 1.05× at the
        // same place: the second cap is relative to the capped speed, not to the programmed
        // one (which the first cap is already below).
        let (pieces, plan, popts) = line();
        let mut sl = Slowing::new(plan.nodes.s.len());
        let k = sample_at(&plan.motion, 0.5);
        let e = |sample, ratio| Excess {
            sample,
            joint: 0,
            kind: LimitKind::Velocity,
            ratio,
            ramp_share: 0.0,
        };
        let lev = sl.apply(&plan.nodes, &plan.v, &plan.motion, &[e(k, 1.2)], 0.95);
        assert_eq!(lev, vec![Lever::Speed(0.95 / 1.2)]);
        let v1 = sl.speeds(&plan.nodes, popts.accel);
        let i = plan.nodes.s.partition_point(|&x| x < 0.5);
        assert!((v1[i] - 0.15 * 0.95 / 1.2).abs() < 1e-12, "{}", v1[i]);
        let m1 = plan_at_speeds(&pieces, &plan.nodes, &v1, &popts);
        let k1 = sample_at(&m1, 0.5);
        sl.apply(&plan.nodes, &v1, &m1, &[e(k1, 1.05)], 0.95);
        let v2 = sl.speeds(&plan.nodes, popts.accel);
        let want = 0.15 * (0.95 / 1.2) * (0.95 / 1.05);
        assert!((v2[i] - want).abs() < 1e-12, "{} vs {want}", v2[i]);
        // Far from the sample the speed is the programmed one.
        let far = plan.nodes.s.partition_point(|&x| x < 0.1);
        assert_eq!(v2[far], 0.15);
        assert!(sl.accel_scale.is_empty());
    }

    #[test]
    fn a_demand_from_a_ramp_lowers_the_acceleration_over_that_ramp_only() {
        // An acceleration demand from the ramp at the start (1.25× the limit, all of it from
        // the ramp): the ramp's acceleration is lowered, to margin / ratio; the speed caps,
        // the cruise and the ramp at the end keep the profile's.
        let (pieces, plan, popts) = line();
        let k = sample_at(&plan.motion, 0.004);
        let rates = path_rates(&plan.motion.s, plan.motion.dt, k);
        assert!(rates.1 > 0.1, "on the ramp: {rates:?}");
        let mut sl = Slowing::new(plan.nodes.s.len());
        let e = Excess {
            sample: k,
            joint: 2,
            kind: LimitKind::Acceleration,
            ratio: 1.25,
            ramp_share: 1.0,
        };
        let lev = sl.apply(&plan.nodes, &plan.v, &plan.motion, &[e], 0.95);
        assert_eq!(lev, vec![Lever::Accel(0.95 / 1.25)]);
        assert!(sl.scale.iter().all(|&c| c == 1.0));
        let node = |s: f64| plan.nodes.s.partition_point(|&x| x < s);
        assert_eq!(sl.accel_scale[node(0.004)], 0.95 / 1.25);
        // The ramp from rest to 0.15 m/s at 1 m/s² is 11 mm long; beyond it (and its
        // neighbouring node), nothing changes.
        assert!(sl.accel_scale[node(0.02)..].iter().all(|&g| g == 1.0));
        let v = sl.speeds(&plan.nodes, popts.accel);
        let slowed = plan_at_speeds(&pieces, &plan.nodes, &v, &popts);
        assert!(slowed.duration() > plan.motion.duration());
        // The ramp at the end, untouched: the last 11 mm are passed exactly as unslowed.
        let (a, b) = (node(0.98), plan.nodes.s.len());
        assert_eq!(&v[a..b], &plan.v[a..b]);
    }

    #[test]
    fn ramp_share_tells_a_ramp_from_speed_and_curvature() {
        // q̇ = q′ṡ, q̈ = q′s̈ + q″ṡ²: with q′ = 2, q″ = 3, ṡ = 0.1, s̈ = 1 the ramp part of q̈ is
        // 2 of 2.03.
        let (q1, q2, q3, sd, sdd, sddd) = (2.0, 3.0, 5.0, 0.1, 1.0, 10.0);
        let qd = q1 * sd;
        let qdd = q1 * sdd + q2 * sd * sd;
        let qddd = q1 * sddd + 3.0 * q2 * sd * sdd + q3 * sd * sd * sd;
        let r = ramp_share(LimitKind::Acceleration, qd, qdd, qddd, (sd, sdd, sddd));
        assert!((r - 2.0 / 2.03).abs() < 1e-12, "{r}");
        let r = ramp_share(LimitKind::Jerk, qd, qdd, qddd, (sd, sdd, sddd));
        assert!((r - 20.9 / 20.905).abs() < 1e-12, "{r}");
        // At constant speed, none; a velocity demand never; at rest, all.
        let r = ramp_share(
            LimitKind::Acceleration,
            qd,
            q2 * sd * sd,
            0.0,
            (sd, 0.0, 0.0),
        );
        assert_eq!(r, 0.0);
        assert_eq!(
            ramp_share(LimitKind::Velocity, qd, qdd, qddd, (sd, sdd, sddd)),
            0.0
        );
        assert_eq!(
            ramp_share(LimitKind::Jerk, 0.0, 1.0, 1.0, (0.0, 1.0, 1.0)),
            1.0
        );
    }
}
