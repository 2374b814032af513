//! When no placement is feasible: how many failed for each reason, and what to try.

use super::feasibility::Reason;
use super::sweep::Evaluated;
use crate::robot::RobotModel;
use std::collections::BTreeMap;

/// Infeasible placements per reason (reasons in their declared order).
pub fn counts_by_reason(rows: &[Evaluated]) -> BTreeMap<Reason, usize> {
    let mut m = BTreeMap::new();
    for r in rows {
        if let Err(e) = &r.outcome {
            *m.entry(e.reason).or_insert(0) += 1;
        }
    }
    m
}

/// True when the robot has no tool offset: the nozzle tip is the flange itself.
pub fn no_tool_offset(robot: &RobotModel) -> bool {
    robot.tool.pos.norm() < 1e-9
}

/// What to try for the placements that failed for `reason` (one sentence).
pub fn what_to_try(reason: Reason) -> &'static str {
    match reason {
        Reason::Unreachable => {
            "move the grid toward the robot (--x, --y), change the bed height (--z), or check the path's units and origin"
        }
        Reason::ConfigurationChange => {
            "try other part yaws (--yaw 0,90,180,270) or nozzle spins (--spin 0,90,180)"
        }
        Reason::JointLimits => "lower the print speed in the path or place the part farther from the base",
        Reason::JointLimitMargin => {
            "try other yaws or spins, or lower --joint-margin (deg) if the robot's limits are known precisely"
        }
        Reason::WristSingularity => {
            "try other nozzle spins (--spin 0,45,90) or yaws; --wrist-rate-max raises the accepted joint 4/6 speed"
        }
        Reason::ElbowSingularity => "bring the grid nearer the robot (--x) or lower --elbow-min",
        Reason::ShoulderSingularity => "move the grid away from axis 1 (--x) or lower --shoulder-min",
        Reason::CollisionBed | Reason::CollisionPart => {
            "raise the bed (--z), move the part outward (--x), or check the nozzle length in the drive file's [tool]"
        }
        Reason::SelfCollision => "move the part outward (--x) or try other yaws",
        Reason::ModelError => "check the robot files (a model error is not a placement problem)",
    }
}

/// The message printed when no placement of `rows` is feasible: counts per reason, what to
/// try for each, and the tool-offset hint for a robot whose flange is its nozzle.
pub fn nothing_feasible(rows: &[Evaluated], robot: &RobotModel) -> String {
    let mut s = format!("no feasible placement among {} evaluated:\n", rows.len());
    for (r, n) in counts_by_reason(rows) {
        s.push_str(&format!("  {n:>6} {}: {}\n", r.name(), what_to_try(r)));
    }
    if no_tool_offset(robot) {
        s.push_str(
            "  no tool offset: the flange is the nozzle. Give the nozzle tip in a drive file \
             ([tool] xyz_m, e.g. [0, 0, 0.3] for a 0.30 m nozzle along the flange z); with the \
             flange on the bed the wrist meets the bed and the part.\n",
        );
    }
    s
}
