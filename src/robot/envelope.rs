//! The arm's size for estimates and the collision model: its reach and the radii of its links
//! as fractions of the reach. The robot reader estimates missing link inertias from them; the
//! feasibility checks build the arm's capsules from them.

use super::RobotModel;
use crate::math::{Frame, V3};
use serde::Serialize;

/// The most joints a chain is composed over, as forward kinematics takes them (its `MAX_DOF`,
/// which a compile-time check in the kinematics holds equal to this).
pub(crate) const MAX_CHAIN: usize = 8;

/// Capsule radii as fractions of the reach `R` (dimensionless). The chain segment that ends at
/// the origin of joint `i` (0-based) is "base" for i ≤ 1, "arm" for i ≤ 3, "wrist" beyond;
/// the flange → tip segment is "nozzle".
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LinkRadii {
    /// Base column and shoulder (× R).
    pub base: f64,
    /// Upper arm and forearm (× R).
    pub arm: f64,
    /// Wrist and flange (× R).
    pub wrist: f64,
    /// Nozzle / extruder (× R).
    pub nozzle: f64,
}

impl Default for LinkRadii {
    fn default() -> Self {
        LinkRadii {
            base: 0.07,
            arm: 0.045,
            wrist: 0.025,
            nozzle: 0.015,
        }
    }
}

/// Reach used to scale the link radii, m: the robot's stated reach, else the length of its
/// chain at zero joint values (joint origins, flange and tool), at least 0.1 m. The chain is
/// composed as forward kinematics composes it, so the figure is the same to the last bit.
pub fn reach_m(model: &RobotModel) -> f64 {
    if let Some(r) = model.info.reach_m.filter(|r| *r > 0.0) {
        return r;
    }
    let mut f = Frame::identity();
    let mut prev = V3::zeros();
    let mut s = 0.0;
    for j in model.joints.iter().take(MAX_CHAIN) {
        f = f.compose(&j.transform(0.0));
        s += (f.pos - prev).norm();
        prev = f.pos;
    }
    let tool = f.compose(&model.flange).compose(&model.tool);
    (s + (tool.pos - prev).norm()).max(0.1)
}
