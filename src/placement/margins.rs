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

use super::feasibility::{FeasibilityOptions, Margins, Reason};
use crate::kinematics::opw;
use crate::robot::{JointKind, RobotModel};

/// Default joint-limit margin on every joint, degrees.
pub const DEFAULT_JOINT_MARGIN_DEG: f64 = 3.0;

/// Default largest share of joint 4/6 velocity or acceleration limit accepted near the wrist
/// singularity (dimensionless).
pub const DEFAULT_WRIST_RATE_MAX: f64 = 0.5;

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
    if w >= o.wrist_min {
        return None;
    }
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
            .collect();
        JointChecks {
            limits,
            wrist: model.opw.as_ref().map(|p| (p.signs[4], p.offsets[4])),
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
            (None, _) => true,
            _ if q.len() < 6 => true,
            (Some((sign, off)), Some(sc)) if off == 0.0 && sc.len() == 2 * q.len() => {
                (sign * sc[4]).abs() >= o.wrist_min
            }
            _ => false,
        };
        if fails || !clear_of_wrist {
            margins.joint_limit_rad = before;
            return check_joint_sample_with(model, o, q, sincos, qd, qdd, margins);
        }
        None
    }
}

/// How close to its joint-limit margin a placement's closest joint comes: the margin is met
/// "on" the margin when the joint's smallest distance from a limit is within this of it, rad
/// (0.01°): the answer then sits on the margin the way an optimum can sit on a search bound.
pub const ON_MARGIN_RAD: f64 = 1.7453292519943295e-4;

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
