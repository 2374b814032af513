//! Per-sample checks that need the joint motion, run on every sample of a timed path:
//!
//! - **Joint-limit margin**: every revolute joint keeps at least its margin (rad) from both
//!   position limits, so that a base placement error or a calibration offset of a few degrees
//!   does not stop the print at a limit. The margin comes, per joint, from the drive file
//!   (`limit_margin_rad` in `[[joints]]`), else from [`FeasibilityOptions::joint_margin_rad`]
//!   (default [`DEFAULT_JOINT_MARGIN_DEG`] on every joint; `--joint-margin` on the command line).
//! - **Wrist singularity, as a vertical nozzle sees it**: near `q5 = 0` (|sin q5| below
//!   [`FeasibilityOptions::wrist_min`]) what hurts is joints 4 and 6 spinning fast to keep the
//!   tool orientation, not the pose itself. A sample near the singularity is rejected only when
//!   joint 4 or 6 uses more than [`FeasibilityOptions::wrist_rate_max`] of its velocity or
//!   acceleration limit there. A `q5` passing 0 while `q4` stays still is harmless and
//!   accepted.
//! - **Wrist margin**: on every sample the OPW `q5` keeps at least
//!   [`FeasibilityOptions::wrist_margin_rad`] (default [`DEFAULT_WRIST_MARGIN_DEG`]) from 0 and
//!   ±180°, i.e. `|sin q5| ≥ sin margin`: at the singularity axes 4 and 6 align and a real
//!   controller may stop or flip the wrist however slowly joint 4 moves. A margin of 0 lets
//!   the wrist pass through (the rate rule above still applies; the export then asks the
//!   controller for `SingArea \Wrist`).

use crate::evaluate::feasibility::{FeasibilityOptions, Margins, Reason};
use crate::kinematics::opw;
use crate::robot::{JointKind, RobotModel};

/// Default joint-limit margin on every joint, degrees.
pub(crate) const DEFAULT_JOINT_MARGIN_DEG: f64 = 3.0;

/// Default largest share of joint 4/6 velocity or acceleration limit accepted near the wrist
/// singularity (dimensionless).
pub const DEFAULT_WRIST_RATE_MAX: f64 = 0.5;

/// Default distance kept from the wrist singularity (`q5` from 0 and ±180°), degrees.
pub const DEFAULT_WRIST_MARGIN_DEG: f64 = 5.0;

/// The smallest `|sin q5|` the wrist margin accepts: `sin` of the margin (0 for a margin of
/// 0; the margin is taken in [0°, 90°]).
#[inline]
pub(crate) fn wrist_floor(o: &FeasibilityOptions) -> f64 {
    let m = o.wrist_margin_rad;
    if m > 0.0 {
        m.min(std::f64::consts::FRAC_PI_2).sin()
    } else {
        0.0
    }
}

/// Lower the running minimum `m` by `v` (the first value taken as it is).
#[inline(always)]
fn lower(m: &mut Option<f64>, v: f64) {
    *m = Some(m.map_or(v, |x: f64| x.min(v)));
}

/// The position margin of joint `j`, rad: the drive file's per-joint value, else the option's.
pub fn joint_margin(model: &RobotModel, o: &FeasibilityOptions, j: usize) -> f64 {
    model
        .info
        .limit_margins_rad
        .get(j)
        .copied()
        .flatten()
        .unwrap_or_else(|| o.joint_margin_rad.get(j).copied().unwrap_or(0.0))
}

/// Check one sample (`q` rad, `qd` rad/s, `qdd` rad/s²) against the joint-limit margins and
/// the wrist-rate rule; updates `margins`. Returns the reason and a detail on failure.
pub fn check_joint_sample(
    model: &RobotModel,
    o: &FeasibilityOptions,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    margins: &mut Margins,
) -> Option<(Reason, String)> {
    check_joint_sample_with(model, o, q, None, qd, qdd, margins)
}

/// [`check_joint_sample`] with, when known, the sines and cosines of `q` (the sines then the
/// cosines, `2 dof` values; see [`crate::kinematics::IkSolver::solve_near_with_sincos`]),
/// from which the wrist measure is taken ([`opw::wrist_singularity_sincos`]).
pub fn check_joint_sample_with(
    model: &RobotModel,
    o: &FeasibilityOptions,
    q: &[f64],
    sincos: Option<&[f64]>,
    qd: &[f64],
    qdd: &[f64],
    margins: &mut Margins,
) -> Option<(Reason, String)> {
    let fail = joint_limits_check(model, o, q, margins);
    if fail.is_some() {
        return fail;
    }
    let p = model.opw.as_ref().filter(|_| q.len() >= 6)?;
    let w = match sincos {
        Some(sc) if sc.len() == 2 * q.len() => {
            let (s, c) = sc.split_at(q.len());
            opw::wrist_singularity_sincos(p, s[4], c[4])
        }
        _ => opw::wrist_singularity(p, q),
    };
    lower(&mut margins.wrist_every, w);
    let floor = wrist_floor(o);
    if w < floor {
        return Some((
            Reason::WristSingularity,
            format!(
                "q5 at {:.2}° is {:.2}° from the wrist singularity (wrist margin {:.2}°; a wrist margin of 0 lets the wrist pass through)",
                q[4].to_degrees(),
                w.clamp(0.0, 1.0).asin().to_degrees(),
                o.wrist_margin_rad.to_degrees()
            ),
        ));
    }
    if w >= o.wrist_min {
        return None;
    }
    wrist_rate_check(model, o, w, qd, qdd, margins)
}

/// The joint position limits with their margins at `q`, lowering the smallest distance to a
/// limit in `margins`: the first joint too near its limit, if any.
#[inline]
fn joint_limits_check(
    model: &RobotModel,
    o: &FeasibilityOptions,
    q: &[f64],
    margins: &mut Margins,
) -> Option<(Reason, String)> {
    let mut fail: Option<(Reason, String)> = None;
    for (j, jt) in model.joints.iter().enumerate().take(q.len()) {
        if jt.kind != JointKind::Revolute || !(jt.lower.is_finite() && jt.upper.is_finite()) {
            continue;
        }
        let d = (q[j] - jt.lower).min(jt.upper - q[j]);
        if margins.joint_limit_rad.is_none_or(|(_, m)| d < m) {
            margins.joint_limit_rad = Some((j + 1, d));
        }
        let m = joint_margin(model, o, j);
        if fail.is_none() && d < m {
            let lim = if q[j] - jt.lower < jt.upper - q[j] {
                jt.lower
            } else {
                jt.upper
            };
            fail = Some((
                Reason::JointLimitMargin,
                format!(
                    "joint {} at {:.2}° is {:.2}° from its limit {:.2}° (margin {:.2}°)",
                    j + 1,
                    q[j].to_degrees(),
                    d.to_degrees(),
                    lim.to_degrees(),
                    m.to_degrees()
                ),
            ));
        }
    }
    fail
}

/// Near the wrist singularity (wrist measure `w`), joints 4 and 6 within the allowed share of
/// their velocity and acceleration limits (`qd`, `qdd`), the largest share noted in `margins`.
#[inline]
fn wrist_rate_check(
    model: &RobotModel,
    o: &FeasibilityOptions,
    w: f64,
    qd: &[f64],
    qdd: &[f64],
    margins: &mut Margins,
) -> Option<(Reason, String)> {
    let mut worst = (0.0f64, 0usize, "");
    for j in [3usize, 5] {
        let jt = &model.joints[j];
        for (v, lim, what) in [
            (qd[j], jt.velocity_limit, "velocity"),
            (qdd[j], jt.acceleration_limit, "acceleration"),
        ] {
            if lim.is_finite() && lim > 0.0 {
                let r = v.abs() / lim;
                if r > worst.0 {
                    worst = (r, j + 1, what);
                }
            }
        }
    }
    if margins.wrist_rate.is_none_or(|r| worst.0 > r) {
        margins.wrist_rate = Some(worst.0);
    }
    (worst.0 > o.wrist_rate_max).then(|| {
        (
            Reason::WristSingularity,
            format!(
                "near the wrist singularity (|sin q5| = {w:.4} < {:.4}) joint {} uses {:.0} % of its {} limit (> {:.0} %)",
                o.wrist_min,
                worst.1,
                worst.0 * 100.0,
                worst.2,
                o.wrist_rate_max * 100.0
            ),
        )
    })
}

/// [`check_joint_sample_with`] with what depends only on the robot and the options worked
/// out once (which joints have finite revolute limits, each one's margin), for the per-sample
/// loop of a placement evaluation. [`JointChecks::check`] gives exactly
/// [`check_joint_sample_with`]'s answer and leaves `margins` exactly as it does: a sample that
/// fails, or comes near the wrist singularity, is handed to [`check_joint_sample_with`] itself.
#[derive(Clone, Debug)]
pub struct JointChecks {
    /// Per checked joint: index, lower and upper limit (rad), margin (rad).
    limits: Vec<(usize, f64, f64, f64)>,
    /// OPW joint-5 sign and offset when the robot has OPW parameters (the wrist measure).
    wrist: Option<(f64, f64)>,
    /// [`JointChecks::screen`]'s tables over a block of [`crate::simd::LANES`] samples,
    /// row-major as the trajectory (entry `k n + j`): lower and upper limits and margins
    /// (rad); a joint without finite revolute limits has `−∞`, `+∞`, `−∞` (it always passes).
    /// `None` for an arm of other than [`SCREEN_DOF`] joints.
    table: Option<Box<ScreenTable>>,
    /// Velocity (rad/s) and acceleration (rad/s²) limits of joints 4 and 6 (the wrist rule),
    /// for robots with 6 joints or more.
    wrist_limits: Option<[(f64, f64); 2]>,
    /// The instruction-set level [`JointChecks::screen`] runs on (the level in force when
    /// made, where the CPU has it; every level gives the same answer).
    level: crate::simd::Level,
}

/// Joints of the arms [`JointChecks::screen`] takes in lockstep (every shipped arm).
const SCREEN_DOF: usize = 6;

/// Entries of one [`JointChecks::screen`] block.
const SCREEN_ENTRIES: usize = crate::simd::LANES * SCREEN_DOF;

/// See [`JointChecks::table`].
#[derive(Clone, Debug)]
struct ScreenTable {
    lower: [f64; SCREEN_ENTRIES],
    upper: [f64; SCREEN_ENTRIES],
    margin: [f64; SCREEN_ENTRIES],
}

/// The lockstep pass of [`JointChecks::screen`] over a block's entries (see
/// [`screen_entries`]).
struct ScreenKernel<'a> {
    t: &'a ScreenTable,
    q: &'a [f64; SCREEN_ENTRIES],
    running: Option<Option<f64>>,
}

impl crate::simd::Kernel for ScreenKernel<'_> {
    type Out = (bool, Option<usize>);
    #[inline(always)]
    fn run<R: crate::simd::F64s>(self) -> Self::Out {
        screen_entries::<R>(self.t, self.q, self.running)
    }
}

impl JointChecks {
    /// The checks of `model` under `o`.
    pub fn new(model: &RobotModel, o: &FeasibilityOptions) -> Self {
        let limits = model
            .joints
            .iter()
            .enumerate()
            .filter(|(_, jt)| {
                jt.kind == JointKind::Revolute && jt.lower.is_finite() && jt.upper.is_finite()
            })
            .map(|(j, jt)| (j, jt.lower, jt.upper, joint_margin(model, o, j)))
            .collect::<Vec<_>>();
        let n = model.joints.len();
        let table = (n == SCREEN_DOF).then(|| {
            let mut t = Box::new(ScreenTable {
                lower: [f64::NEG_INFINITY; SCREEN_ENTRIES],
                upper: [f64::INFINITY; SCREEN_ENTRIES],
                margin: [f64::NEG_INFINITY; SCREEN_ENTRIES],
            });
            for k in 0..crate::simd::LANES {
                for &(j, lower, upper, m) in &limits {
                    let i = k * n + j;
                    (t.lower[i], t.upper[i], t.margin[i]) = (lower, upper, m);
                }
            }
            t
        });
        let lim = |j: usize| {
            let jt = &model.joints[j];
            (jt.velocity_limit, jt.acceleration_limit)
        };
        JointChecks {
            limits,
            wrist: model.opw.as_ref().map(|p| (p.signs[4], p.offsets[4])),
            table,
            wrist_limits: (n >= 6).then(|| [lim(3), lim(5)]),
            level: Some(crate::simd::level())
                .filter(|l| l.available())
                .unwrap_or(crate::simd::Level::Scalar),
        }
    }

    /// [`check_joint_sample_with`]`(model, o, q, sincos, qd, qdd, margins)` (the same `model`
    /// and `o` as [`JointChecks::new`]'s), bit for bit.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub fn check(
        &self,
        model: &RobotModel,
        o: &FeasibilityOptions,
        q: &[f64],
        sincos: Option<&[f64]>,
        qd: &[f64],
        qdd: &[f64],
        margins: &mut Margins,
    ) -> Option<(Reason, String)> {
        let before = margins.joint_limit_rad;
        let mut fails = false;
        for &(j, lower, upper, m) in &self.limits {
            let Some(&v) = q.get(j) else { break };
            let d = (v - lower).min(upper - v);
            if margins.joint_limit_rad.is_none_or(|(_, x)| d < x) {
                margins.joint_limit_rad = Some((j + 1, d));
            }
            fails |= d < m;
        }
        // The wrist measure as check_joint_sample_with takes it, for the common case (shared
        // sines, joint 5's OPW offset 0); anything else goes the long way.
        let clear_of_wrist = match (self.wrist, sincos) {
            (None, _) => Some(None),
            _ if q.len() < 6 => Some(None),
            (Some((sign, off)), Some(sc)) if off == 0.0 && sc.len() == 2 * q.len() => {
                let w = (sign * sc[4]).abs();
                (w >= o.wrist_min && w >= wrist_floor(o)).then_some(Some(w))
            }
            _ => None,
        };
        match clear_of_wrist {
            Some(w) if !fails => {
                if let Some(w) = w {
                    lower(&mut margins.wrist_every, w);
                }
                None
            }
            _ => {
                margins.joint_limit_rad = before;
                check_joint_sample_with(model, o, q, sincos, qd, qdd, margins)
            }
        }
    }
}

impl JointChecks {
    /// [`JointChecks::check`] of `count` consecutive samples at once, for the case that
    /// dominates a feasible placement: `true` when every one of them would pass (no joint
    /// within its margin, none near the wrist singularity), and then `margins` is left
    /// exactly as the per-sample checks leave it. `false` when some sample needs the
    /// per-sample checks (a failure, the wrist rule, a NaN): `margins` is then untouched, and
    /// the caller runs [`JointChecks::check`] on each sample in turn, which reports the first
    /// failure at its own sample as before.
    ///
    /// `qs`, `qds`, `qdds`: the samples' joint positions (rad), velocities (rad/s) and
    /// accelerations (rad/s²), row-major, `n` per sample; `sincos`: their sines then cosines,
    /// `2 n` per sample, when known (see [`JointChecks::check`]). The screen takes the
    /// smallest distance from a limit over the block in lockstep (comparisons and minima
    /// only, exact) and updates `margins.joint_limit_rad` sample by sample, as the per-sample
    /// checks do, only when that smallest distance is below the running one; a sample near
    /// the wrist singularity gets the wrist rule's ratios as [`check_joint_sample_with`]
    /// computes them (`margins.wrist_rate` the same).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn screen(
        &self,
        o: &FeasibilityOptions,
        n: usize,
        count: usize,
        qs: &[f64],
        qds: &[f64],
        qdds: &[f64],
        sincos: Option<&[f64]>,
        margins: &mut Margins,
    ) -> bool {
        const W: usize = crate::simd::LANES;
        // Full blocks of six-joint arms only (the table exists for those); anything else goes
        // the per-sample way, `margins` untouched. With the table the arm has SCREEN_DOF
        // joints, so every checked joint's index is below `n`.
        if n != SCREEN_DOF || count != W {
            return false;
        }
        let Some(t) = self.table.as_deref() else {
            return false;
        };
        let (Some(q), Some(qd), Some(qdd)) = (
            qs.first_chunk::<SCREEN_ENTRIES>(),
            qds.first_chunk::<SCREEN_ENTRIES>(),
            qdds.first_chunk::<SCREEN_ENTRIES>(),
        ) else {
            return false;
        };
        // The wrist measure as `check` takes it: shared sines and joint 5's OPW offset 0.
        let wrist = match (self.wrist, sincos) {
            (None, _) => None,
            (Some((sign, 0.0)), Some(sc)) => match sc.first_chunk::<{ 2 * SCREEN_ENTRIES }>() {
                Some(sc) => Some((sign, sc)),
                None => return false,
            },
            _ => return false,
        };
        // The wrist rule where a sample comes near the singularity, as
        // check_joint_sample_with applies it (its margin kept aside until the block passes).
        let mut wrist_rate = margins.wrist_rate;
        let mut wrist_every = margins.wrist_every;
        if let Some((sign, sc)) = wrist {
            let Some(low) = self.screen_wrist(o, sign, sc, qd, qdd, &mut wrist_rate) else {
                return false;
            };
            lower(&mut wrist_every, low);
        }
        // The entry at the block's smallest distance is sought only where that distance
        // beats the running one (about a quarter of the blocks of a feasible placement, as
        // the arm keeps nearing a limit); never without a checked joint.
        let running = (!self.limits.is_empty()).then_some(margins.joint_limit_rad.map(|m| m.1));
        let (pass, first) = crate::simd::dispatch(self.level, ScreenKernel { t, q, running });
        if !pass {
            return false;
        }
        margins.wrist_rate = wrist_rate;
        margins.wrist_every = wrist_every;
        if let Some(first) = first {
            // The per-sample checks lower the running minimum at each new smallest distance
            // and so end on the first entry (sample by sample, joint by joint) at the block's
            // smallest (no NaN in a passing block), with its distance as they compute it.
            let (v, lower, upper) = (q[first], t.lower[first], t.upper[first]);
            let d = (v - lower).min(upper - v);
            margins.joint_limit_rad = Some((first % SCREEN_DOF + 1, d));
        }
        true
    }

    /// [`JointChecks::screen`]'s wrist measures of a block (`sign`: joint 5's OPW sign; `sc`,
    /// `qd`, `qdd` the block's sines and cosines, velocities and accelerations): the smallest,
    /// with `wrist_rate` lowered by the wrist rule where a sample comes near the singularity;
    /// `None` where a sample goes the per-sample way.
    // `!(w >= wrist_min)`: the negated comparison is the NaN rule (a NaN is near).
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    #[inline]
    fn screen_wrist(
        &self,
        o: &FeasibilityOptions,
        sign: f64,
        sc: &[f64; 2 * SCREEN_ENTRIES],
        qd: &[f64; SCREEN_ENTRIES],
        qdd: &[f64; SCREEN_ENTRIES],
        wrist_rate: &mut Option<f64>,
    ) -> Option<f64> {
        // Most blocks have no sample near it (a NaN counts as near): one test for all. A
        // sample within the wrist margin (or a NaN) goes the per-sample way.
        let floor = wrist_floor(o);
        let mut near = false;
        let mut within = false;
        let mut low = f64::INFINITY;
        for k in 0..crate::simd::LANES {
            let w = (sign * sc[k * 2 * SCREEN_DOF + 4]).abs();
            near |= !(w >= o.wrist_min);
            within |= !(w >= floor);
            low = low.min(w);
        }
        if within {
            return None;
        }
        if near && !self.wrist_rule(o, sign, sc, qd, qdd, wrist_rate) {
            return None;
        }
        Some(low)
    }

    /// [`JointChecks::screen`]'s wrist rule on a block with a sample near the singularity
    /// (`sign`: joint 5's OPW sign; `sc`, `qd`, `qdd` the block's sines and cosines,
    /// velocities and accelerations): `false` where a sample fails it (or the arm has no wrist
    /// limits), else `true` with `wrist_rate` lowered as [`check_joint_sample_with`] lowers
    /// it.
    #[cold]
    #[inline(never)]
    fn wrist_rule(
        &self,
        o: &FeasibilityOptions,
        sign: f64,
        sc: &[f64; 2 * SCREEN_ENTRIES],
        qd: &[f64; SCREEN_ENTRIES],
        qdd: &[f64; SCREEN_ENTRIES],
        wrist_rate: &mut Option<f64>,
    ) -> bool {
        let Some(wl) = self.wrist_limits else {
            return false;
        };
        let n = SCREEN_DOF;
        for k in 0..crate::simd::LANES {
            let w = (sign * sc[k * 2 * n + 4]).abs();
            if w >= o.wrist_min {
                continue;
            }
            let mut worst = 0.0f64;
            for (j, (vl, al)) in [(3usize, wl[0]), (5, wl[1])] {
                for (v, lim) in [(qd[k * n + j], vl), (qdd[k * n + j], al)] {
                    if lim.is_finite() && lim > 0.0 {
                        let r = v.abs() / lim;
                        if r > worst {
                            worst = r;
                        }
                    }
                }
            }
            if wrist_rate.is_none_or(|r| worst > r) {
                *wrist_rate = Some(worst);
            }
            if worst > o.wrist_rate_max {
                return false;
            }
        }
        true
    }
}

/// The body of [`JointChecks::screen`]: whether every entry keeps its margin
/// (`min(q − lower, upper − q) ≥ margin`, false for a NaN), and, where the block passes and
/// its smallest such distance is below `running` (`Some(None)`: no running minimum yet;
/// `None`: never), the first entry at the smallest distance (sample by sample, joint by
/// joint). The margin test and the minimum in vertical minima and or-ed failures; the
/// entry, where sought, chunk by chunk by equality with the smallest. Comparisons, selects
/// and minima only, so every level gives the same answer.
// `!(d >= margin)`: the negated comparison is the NaN rule (a NaN fails the screen).
#[inline(always)]
fn screen_entries<R: crate::simd::F64s>(
    t: &ScreenTable,
    q: &[f64; SCREEN_ENTRIES],
    running: Option<Option<f64>>,
) -> (bool, Option<usize>) {
    const _: () = assert!(SCREEN_ENTRIES.is_multiple_of(crate::simd::LANES));
    // Entries c W .. (c + 1) W: `min(q − lower, upper − q)` (`if a < b { a } else { b }`).
    let distance = |c: usize| {
        let x = R::load(&q[c * R::W..]);
        let a = x.sub(R::load(&t.lower[c * R::W..]));
        let b = R::load(&t.upper[c * R::W..]).sub(x);
        a.lt_min(b)
    };
    let all = u32::MAX >> (32 - R::W);
    let mut bad = 0u32;
    let mut low = R::splat(f64::INFINITY);
    for c in 0..SCREEN_ENTRIES / R::W {
        let d = distance(c);
        // !(d >= margin): true for a NaN.
        bad |= !d.ge(R::load(&t.margin[c * R::W..])) & all;
        low = d.lt_min(low);
    }
    if bad != 0 {
        return (false, None);
    }
    // No NaN in a passing block: the order of the minima does not matter.
    let mut lows = [0.0; crate::simd::LANES];
    low.store(&mut lows);
    let mut lowest = f64::INFINITY;
    for &l in &lows[..R::W] {
        lowest = if l < lowest { l } else { lowest };
    }
    match running {
        Some(r) if r.is_none_or(|x| lowest < x) => {
            let l = R::splat(lowest);
            for c in 0..SCREEN_ENTRIES / R::W {
                let d = distance(c);
                // d == lowest (no NaN here).
                let at = d.le(l) & d.ge(l);
                if at != 0 {
                    return (true, Some(c * R::W + at.trailing_zeros() as usize));
                }
            }
            // Not reached: some entry holds the smallest (no NaN in a passing block).
            (true, Some(SCREEN_ENTRIES - 1))
        }
        _ => (true, None),
    }
}

/// How close to its joint-limit margin a placement's closest joint comes: the margin is met
/// "on" the margin when the joint's smallest distance from a limit is within this of it, rad
/// (0.01°): the answer then sits on the margin the way an optimum can sit on a search bound.
pub(crate) const ON_MARGIN_RAD: f64 = 1.7453292519943295e-4;

/// The joint-limit margin a feasible placement keeps, in words, and whether it lies on the
/// margin (see [`ON_MARGIN_RAD`]): e.g. ("joint 3 keeps 4.48° from a limit (margin 3.00°)",
/// false). `None` when no joint has finite limits.
pub fn margin_statement(
    model: &RobotModel,
    o: &FeasibilityOptions,
    m: &Margins,
) -> Option<(String, bool)> {
    let (j, d) = m.joint_limit_rad?;
    let margin = joint_margin(model, o, j.checked_sub(1)?);
    let on = d - margin <= ON_MARGIN_RAD;
    Some((
        format!(
            "joint {j} keeps {:.2}° from a limit (margin {:.2}°)",
            d.to_degrees(),
            margin.to_degrees()
        ),
        on,
    ))
}

/// The wrist margin a feasible placement keeps, in words: e.g. "q5 keeps 7.12° from the
/// wrist singularity (wrist margin 5.00°)", or, where the margin is 0, that the wrist may pass
/// through it and the export asks for `SingArea \Wrist`. `None` without OPW parameters.
pub fn wrist_statement(o: &FeasibilityOptions, m: &Margins) -> Option<String> {
    let d = m.wrist_deg()?;
    Some(if wrist_floor(o) > 0.0 {
        format!(
            "q5 keeps {d:.2}° from the wrist singularity (wrist margin {:.2}°)",
            o.wrist_margin_rad.to_degrees()
        )
    } else {
        format!(
            "q5 comes within {d:.2}° of the wrist singularity: passing through it is allowed (wrist margin 0°), the RAPID export sets SingArea \\Wrist"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn screening_a_block_of_joint_checks_passes_only_blocks_the_per_sample_checks_pass_and_leaves_the_same_margins(
    ) {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("robots");
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(31);
        for name in ["abb_irb6700_200_260", "ur10e", "staubli_tx200", "puma560"] {
            let model = crate::robot::load(&root.join(name)).unwrap();
            let n = model.dof();
            let o = FeasibilityOptions::default();
            let checks = JointChecks::new(&model, &o);
            let (mut screened, mut handed_on) = (0, 0);
            let mut running = Margins::default();
            for block in 0..3000 {
                if block % 50 == 0 {
                    // A fresh evaluation: the first block sets the closest approach.
                    running = Margins::default();
                }
                // Mostly full blocks (what the screen takes), now and then a short one (handed
                // on: the last block of a path).
                let count = if block % 8 == 0 {
                    rng.gen_range(1..=crate::simd::LANES)
                } else {
                    crate::simd::LANES
                };
                // Mostly well inside the limits; now and then a joint within its margin, joint
                // 5 near 0 (the wrist rule), a NaN, or a new closest approach to a limit.
                let mut qs = Vec::new();
                for _ in 0..count {
                    for (j, jt) in model.joints.iter().enumerate() {
                        let (lo, hi) = (jt.lower.max(-4.0), jt.upper.min(4.0));
                        let mut v = lo + (hi - lo) * rng.gen_range(0.1..0.9);
                        match rng.gen_range(0..200) {
                            0 => v = lo + rng.gen_range(0.0..0.06),
                            1..=4 if j == 4 => v = rng.gen_range(-0.04..0.04),
                            2 if block % 7 == 0 => v = f64::NAN,
                            5 => v = hi - rng.gen_range(0.052..0.2),
                            _ => {}
                        }
                        qs.push(v);
                    }
                }
                let mut sc = vec![0.0; count * 2 * n];
                for k in 0..count {
                    for j in 0..n {
                        (sc[k * 2 * n + j], sc[k * 2 * n + n + j]) =
                            crate::fastmath::sin_cos(qs[k * n + j]);
                    }
                }
                let sincos = (block % 11 != 0).then_some(&sc[..]);
                // Joint speeds up to 0.8 of the limits: near the wrist singularity the rule
                // passes or fails (and a NaN now and then).
                let mut rate = |lim: f64| {
                    let l = if lim.is_finite() { lim } else { 1.0 };
                    l * rng.gen_range(-0.8..0.8)
                };
                let mut qds = Vec::new();
                let mut qdds = Vec::new();
                for _ in 0..count {
                    for jt in &model.joints {
                        qds.push(rate(jt.velocity_limit));
                        qdds.push(rate(jt.acceleration_limit));
                    }
                }
                if block % 13 == 0 {
                    qds[rng.gen_range(0..count * n)] = f64::NAN;
                }
                // The per-sample checks.
                let mut want = running;
                let mut all_pass = true;
                for k in 0..count {
                    let s = sincos.map(|sc| &sc[k * 2 * n..(k + 1) * 2 * n]);
                    let r = k * n..(k + 1) * n;
                    let (q, qd, qdd) = (&qs[r.clone()], &qds[r.clone()], &qdds[r]);
                    all_pass &= checks.check(&model, &o, q, s, qd, qdd, &mut want).is_none();
                }
                let mut got = running;
                if checks.screen(&o, n, count, &qs, &qds, &qdds, sincos, &mut got) {
                    assert!(all_pass, "{name} block {block}: screened a failing block");
                    assert_eq!(
                        format!("{got:?}"),
                        format!("{want:?}"),
                        "{name} block {block}"
                    );
                    screened += 1;
                } else {
                    assert_eq!(
                        format!("{got:?}"),
                        format!("{running:?}"),
                        "{name} block {block}"
                    );
                    handed_on += 1;
                }
                running = want;
            }
            assert!(
                screened > 1000 && handed_on > 100,
                "{name}: {screened} screened, {handed_on} handed on"
            );
        }
    }

    #[test]
    fn the_screen_names_the_first_sample_and_joint_at_a_tied_smallest_distance_on_every_level() {
        // The screen finds the entry at a block's smallest distance only where that distance
        // beats the running one, by a scan in entry order (sample by sample, joint by joint).
        // Ties are where that order matters: an arm standing still (the same row repeated,
        // the tie then across lanes and chunks of the lockstep kernel), two joints at the
        // same distance in one sample, a running minimum equal to the block's. On every
        // level: the margins of the per-sample checks, bit for bit.
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("robots");
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(12);
        let mut checked = 0;
        for name in ["abb_irb6700_200_260", "staubli_tx200"] {
            let model = crate::robot::load(&root.join(name)).unwrap();
            let n = model.dof();
            assert_eq!(n, SCREEN_DOF);
            let o = FeasibilityOptions::default();
            let base = JointChecks::new(&model, &o);
            let levels = crate::simd::Level::ALL
                .into_iter()
                .filter(|l| l.available());
            for level in levels {
                let checks = JointChecks {
                    level,
                    ..base.clone()
                };
                for block in 0..400 {
                    // Well inside the limits; joint 5 away from 0 (no wrist rule).
                    let row = |rng: &mut rand_chacha::ChaCha8Rng| {
                        let mut r = Vec::new();
                        for (j, jt) in model.joints.iter().enumerate() {
                            let (lo, hi) = (jt.lower.max(-4.0), jt.upper.min(4.0));
                            let v = lo + (hi - lo) * rng.gen_range(0.2..0.8);
                            r.push(if j == 4 && v.abs() < 0.3 { 0.5 } else { v });
                        }
                        r
                    };
                    let mut rows: Vec<Vec<f64>> =
                        (0..crate::simd::LANES).map(|_| row(&mut rng)).collect();
                    match block % 4 {
                        // Standing still: every row the same.
                        0 => {
                            for k in 1..rows.len() {
                                rows[k] = rows[0].clone();
                            }
                        }
                        // Some rows repeated at random places.
                        1 => {
                            for _ in 0..3 {
                                let (a, b) = (rng.gen_range(0..8), rng.gen_range(0..8));
                                rows[b] = rows[a].clone();
                            }
                        }
                        // Joints 1 and 3 of a row at the same distance (the same offset
                        // from both lower limits, where it is exact).
                        2 => {
                            let k = rng.gen_range(0..8);
                            let (l1, l3) = (model.joints[0].lower, model.joints[2].lower);
                            let d = rng.gen_range(0.06..0.3);
                            rows[k][0] = l1 + d;
                            rows[k][2] = l3 + d;
                            if (rows[k][0] - l1).to_bits() != (rows[k][2] - l3).to_bits() {
                                rows[k][2] = rows[k][0] - l1 + l3;
                            }
                        }
                        _ => {}
                    }
                    let qs: Vec<f64> = rows.concat();
                    let mut sc = vec![0.0; crate::simd::LANES * 2 * n];
                    for k in 0..crate::simd::LANES {
                        for j in 0..n {
                            (sc[k * 2 * n + j], sc[k * 2 * n + n + j]) =
                                crate::fastmath::sin_cos(qs[k * n + j]);
                        }
                    }
                    let zeros = vec![0.0; qs.len()];
                    // A fresh evaluation, or a running minimum at, above or below the block's.
                    let mut fresh = Margins::default();
                    let mut first_pass = fresh;
                    for k in 0..crate::simd::LANES {
                        let r = k * n..(k + 1) * n;
                        let s = &sc[k * 2 * n..(k + 1) * 2 * n];
                        checks.check(
                            &model,
                            &o,
                            &qs[r],
                            Some(s),
                            &zeros[..n],
                            &zeros[..n],
                            &mut first_pass,
                        );
                    }
                    let (_, lowest) = first_pass.joint_limit_rad.unwrap();
                    let runs = [
                        None,
                        Some((6, lowest)),
                        Some((2, lowest * (1.0 + 1e-12))),
                        Some((4, lowest * (1.0 - 1e-12))),
                    ];
                    for run in runs {
                        fresh.joint_limit_rad = run;
                        let mut want = fresh;
                        for k in 0..crate::simd::LANES {
                            let r = k * n..(k + 1) * n;
                            let s = &sc[k * 2 * n..(k + 1) * 2 * n];
                            let f = checks.check(
                                &model,
                                &o,
                                &qs[r],
                                Some(s),
                                &zeros[..n],
                                &zeros[..n],
                                &mut want,
                            );
                            assert!(f.is_none(), "{name} block {block}: {f:?}");
                        }
                        let mut got = fresh;
                        assert!(checks.screen(
                            &o,
                            n,
                            crate::simd::LANES,
                            &qs,
                            &zeros,
                            &zeros,
                            Some(&sc),
                            &mut got
                        ));
                        assert_eq!(
                            format!("{got:?}"),
                            format!("{want:?}"),
                            "{name} {level:?} block {block} running {run:?}"
                        );
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked >= 2 * 2 * 400 * 4, "{checked} blocks");
    }
}
