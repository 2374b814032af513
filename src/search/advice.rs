//! When no placement is feasible: how many failed for each reason, and what to try.

use crate::evaluate::evaluator::Evaluated;
use crate::evaluate::feasibility::Reason;
use crate::robot::RobotModel;
use std::collections::BTreeMap;

/// Infeasible placements per reason (reasons in their declared order).
pub(crate) fn counts_by_reason(rows: &[Evaluated]) -> BTreeMap<Reason, usize> {
    let mut m = BTreeMap::new();
    for r in rows {
        if let Err(e) = &r.outcome {
            *m.entry(e.reason).or_insert(0) += 1;
        }
    }
    m
}

/// True when the robot has no tool offset: the nozzle tip is the flange itself.
pub(crate) fn no_tool_offset(robot: &RobotModel) -> bool {
    robot.tool.pos.norm() < 1e-9
}

/// A setting of a sweep that advice asks to change. The library names it in words
/// ([`Knob::words`]); a front end names it its own way (the command line by its option).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Knob {
    /// The grid's x values (m).
    X,
    /// The grid's y values (m).
    Y,
    /// The bed height z (m).
    Z,
    /// The part yaws (deg).
    Yaw,
    /// The nozzle spins (deg).
    Spin,
    /// The margin kept from every joint's position limits (deg).
    JointMargin,
    /// The share of the joint 4/6 rate limits allowed near the wrist singularity.
    WristRateMax,
    /// The distance kept from the wrist singularity (deg).
    WristMargin,
    /// The smallest elbow measure accepted (dimensionless).
    ElbowMin,
    /// The smallest wrist-centre distance from axis 1 accepted (m).
    ShoulderMin,
}

impl Knob {
    /// The library's words for the setting.
    pub fn words(self) -> &'static str {
        match self {
            Knob::X => "x",
            Knob::Y => "y",
            Knob::Z => "z",
            Knob::Yaw => "yaw",
            Knob::Spin => "spin",
            Knob::JointMargin => "the joint-limit margin",
            Knob::WristRateMax => "the wrist rate share",
            Knob::WristMargin => "the wrist margin",
            Knob::ElbowMin => "the elbow minimum",
            Knob::ShoulderMin => "the shoulder minimum",
        }
    }
}

/// One sentence of advice with the settings it names: `template` holds one `{}` per knob, in
/// order. [`Advice::render`] names them; `Display` uses [`Knob::words`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Advice {
    /// The sentence, a `{}` where each knob goes.
    pub template: &'static str,
    /// The settings named, in order.
    pub knobs: &'static [Knob],
}

impl Advice {
    /// The sentence with each knob named by `name`.
    pub fn render(&self, name: &dyn Fn(Knob) -> String) -> String {
        let mut out = String::new();
        let mut parts = self.template.split("{}");
        out.push_str(parts.next().unwrap_or(""));
        for (k, rest) in self.knobs.iter().zip(parts) {
            out.push_str(&name(*k));
            out.push_str(rest);
        }
        out
    }
}

impl std::fmt::Display for Advice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.render(&|k| k.words().to_string()))
    }
}

/// What to try for the placements that failed for `reason` (one sentence).
pub fn what_to_try(reason: Reason) -> Advice {
    use Knob::*;
    let (template, knobs): (&'static str, &'static [Knob]) = match reason {
        Reason::Unreachable => (
            "move the grid toward the robot ({}, {}), change the bed height ({}), or check the path's units and origin",
            &[X, Y, Z],
        ),
        Reason::ConfigurationChange => (
            "try other part yaws ({} 0,90,180,270) or nozzle spins ({} 0,90,180)",
            &[Yaw, Spin],
        ),
        Reason::JointLimits => (
            "lower the print speed in the path or place the part farther from the base",
            &[],
        ),
        Reason::JointLimitMargin => (
            "try other yaws or spins, or lower {} (deg) if the robot's limits are known precisely",
            &[JointMargin],
        ),
        Reason::WristSingularity => (
            "try other nozzle spins ({} 0,45,90) or yaws; {} raises the accepted joint 4/6 speed; {} 0 lets the wrist pass through the singularity",
            &[Spin, WristRateMax, WristMargin],
        ),
        Reason::ElbowSingularity => (
            "bring the grid nearer the robot ({}) or lower {}",
            &[X, ElbowMin],
        ),
        Reason::ShoulderSingularity => (
            "move the grid away from axis 1 ({}) or lower {}",
            &[X, ShoulderMin],
        ),
        Reason::CollisionBed | Reason::CollisionPart => (
            "raise the bed ({}), move the part outward ({}), or check the nozzle length in the drive file's [tool]",
            &[Z, X],
        ),
        Reason::CollisionFloor => (
            "raise the bed ({}), move the part outward ({}), or stand the robot on a pedestal (the drive file's [robot] pedestal_height_m)",
            &[Z, X],
        ),
        Reason::SelfCollision => ("move the part outward ({}) or try other yaws", &[X]),
        Reason::ModelError => (
            "check the robot files (a model error is not a placement problem)",
            &[],
        ),
    };
    Advice { template, knobs }
}

/// The message printed when no placement of `rows` is feasible: counts per reason, what to
/// try for each (its settings named by `name`: a front end's own names, e.g. the command
/// line's options, or the library's words, [`Knob::words`]), and the tool-offset hint for a
/// robot whose flange is its nozzle.
pub fn nothing_feasible_named(
    rows: &[Evaluated],
    robot: &RobotModel,
    name: &dyn Fn(Knob) -> String,
) -> String {
    let mut s = format!("no feasible placement among {} evaluated:\n", rows.len());
    for (r, n) in counts_by_reason(rows) {
        s.push_str(&format!(
            "  {n:>6} {}: {}\n",
            r.name(),
            what_to_try(r).render(name)
        ));
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
