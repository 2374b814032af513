//! Facts about the cell that the report draws to scale: the reachable annulus of the nozzle at
//! the bed height, the part's outline, and, for the seed-000 reproduction, the paper's P1–P5
//! values to show beside ours.

use crate::evaluate::PathJob;
use crate::kinematics::IkSolver;
use crate::math::{rot_x, Frame, V3};
use crate::robot::RobotModel;
use std::path::Path;

/// Seed 000 (energy consumption model of a robotic arm in 3DCP), §3.2 and Fig. 4: simulated EC
/// per printing position, J. P3 is given only as "comparable to P4" (no number).
pub const SEED000_EC_J: [(&str, Option<f64>); 5] = [
    ("P1", Some(1185.4)),
    ("P2", Some(1151.2)),
    ("P3", None),
    ("P4", Some(2497.6)),
    ("P5", Some(1237.8)),
];

/// A published value by placement name, J (`None`: the source gives no number).
pub type Reference = (String, Option<f64>);

/// What the top view needs besides the sweep rows.
#[derive(Clone, Debug, Default)]
pub struct SiteGeometry {
    /// Bed height the annulus is computed at (z of the part origin in the base frame), m.
    pub z_m: f64,
    /// Smallest and largest horizontal distance from axis 1 at which the nozzle tip, pointing
    /// straight down, has an IK solution at `z_m`, m (sampled every 1 % of the reach, on +x).
    pub annulus_m: Option<(f64, f64)>,
    /// The print moves' nozzle-tip path in the part frame (x, y), m, thinned to ≤ 1500 points.
    pub part_xy_m: Vec<(f64, f64)>,
    /// Published values to show beside ours, by placement name, J (seed 000's P1–P5 when the
    /// run is that reproduction), with where they come from.
    pub reference: Option<(String, Vec<Reference>)>,
}

impl SiteGeometry {
    /// From the job (robot, planned path) at bed height `z_m`; `path_file` and `names` decide
    /// whether the run is the seed-000 reproduction (a `seed000*` path at P1–P5).
    pub fn new(
        model: &RobotModel,
        job: &PathJob,
        z_m: f64,
        path_file: &Path,
        names: Option<&[String]>,
    ) -> Self {
        let motion = &job.plan.motion;
        let print: Vec<(f64, f64)> = motion
            .p
            .iter()
            .zip(&motion.print)
            .filter(|(_, &pr)| pr)
            .map(|(p, _)| (p.x, p.y))
            .collect();
        let step = print.len().div_ceil(1500).max(1);
        let mut part_xy_m: Vec<(f64, f64)> = print.iter().step_by(step).copied().collect();
        if let Some(l) = print.last() {
            part_xy_m.push(*l);
        }
        let seed000 = path_file
            .file_name()
            .is_some_and(|f| f.to_string_lossy().starts_with("seed000"));
        let reference = names.filter(|_| seed000).and_then(|n| {
            let ours: Vec<&str> = n.iter().map(String::as_str).collect();
            let theirs: Vec<&str> = SEED000_EC_J.iter().map(|r| r.0).collect();
            (ours == theirs).then(|| {
                (
                    "seed 000, §3.2 / Fig. 4 (simulated EC; P3 only \"comparable to P4\")".into(),
                    SEED000_EC_J
                        .iter()
                        .map(|(a, b)| (a.to_string(), *b))
                        .collect(),
                )
            })
        });
        SiteGeometry {
            z_m,
            annulus_m: annulus(model, z_m),
            part_xy_m,
            reference,
        }
    }
}

/// Radial reach of a downward nozzle at height `z` (m): smallest and largest reachable distance
/// from axis 1 on the +x axis, sampled every 1 % of the reach up to 120 %.
pub fn annulus(model: &RobotModel, z: f64) -> Option<(f64, f64)> {
    let solver = IkSolver::new(model).ok()?;
    let reach = crate::evaluate::feasibility::reach_m(model);
    let down = rot_x(std::f64::consts::PI);
    let mut lo: Option<f64> = None;
    let mut hi: Option<f64> = None;
    for i in 0..=120 {
        let r = reach * i as f64 / 100.0;
        let target = Frame::new(down, V3::new(r, 0.0, z));
        if solver.solve_all(&target).is_ok_and(|s| !s.is_empty()) {
            lo = Some(lo.map_or(r, |l: f64| l.min(r)));
            hi = Some(hi.map_or(r, |h: f64| h.max(r)));
        }
    }
    lo.zip(hi)
}
