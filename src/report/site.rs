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
pub(crate) const SEED000_EC_J: [(&str, Option<f64>); 5] = [
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
    /// The robot base's footprint seen from above (base frame x, y, m): the outline (convex,
    /// counter-clockwise) of the fixed base's collision geometry; empty when the robot file
    /// gives none.
    pub base_footprint_m: Vec<(f64, f64)>,
    /// The pedestal under the base, `(height, radius)`, m, when the drive file states one.
    pub pedestal_m: Option<(f64, f64)>,
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
            base_footprint_m: base_footprint(model),
            pedestal_m: (model.info.pedestal_height_m > 0.0 && model.info.pedestal_radius_m > 0.0)
                .then_some((model.info.pedestal_height_m, model.info.pedestal_radius_m)),
            reference,
        }
    }
}

/// The outline seen from above (x, y, m, base frame; convex, counter-clockwise) of the fixed
/// base's collision geometry: mesh pieces by their vertices, boxes by their corners, cylinders
/// and spheres by 24 points around them. Empty when the model has none.
pub fn base_footprint(model: &RobotModel) -> Vec<(f64, f64)> {
    use crate::robot::GeomShape;
    let mut pts: Vec<(f64, f64)> = Vec::new();
    for g in &model.base_collision {
        let local: Vec<V3> = match &g.shape {
            GeomShape::Hull { points, .. } => points.clone(),
            GeomShape::Box { size_m } => {
                let h = V3::from(*size_m) * 0.5;
                (0..8)
                    .map(|i| {
                        let s = |b: usize| if i & b == 0 { -1.0 } else { 1.0 };
                        V3::new(s(1) * h.x, s(2) * h.y, s(4) * h.z)
                    })
                    .collect()
            }
            GeomShape::Cylinder { radius_m, length_m } => {
                ring(*radius_m, &[-0.5 * length_m, 0.5 * length_m])
            }
            GeomShape::Sphere { radius_m } => ring(*radius_m, &[0.0])
                .into_iter()
                .chain([V3::new(0.0, 0.0, *radius_m), V3::new(0.0, 0.0, -radius_m)])
                .collect(),
        };
        pts.extend(local.iter().map(|p| {
            let w = g.origin.apply(p);
            (w.x, w.y)
        }));
    }
    convex_hull_2d(pts)
}

/// Points around a z-axis circle of radius `r` at the heights `zs`.
fn ring(r: f64, zs: &[f64]) -> Vec<V3> {
    zs.iter()
        .flat_map(|&z| {
            (0..24).map(move |i| {
                let a = std::f64::consts::TAU * i as f64 / 24.0;
                V3::new(r * a.cos(), r * a.sin(), z)
            })
        })
        .collect()
}

/// Convex hull of 2-D points (Andrew's monotone chain), counter-clockwise, no repeated point.
pub(crate) fn convex_hull_2d(mut p: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    p.retain(|(x, y)| x.is_finite() && y.is_finite());
    p.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut h: Vec<(f64, f64)> = Vec::with_capacity(2 * p.len());
    for pass in 0..2 {
        let start = h.len();
        let it: Box<dyn Iterator<Item = &(f64, f64)>> = if pass == 0 {
            Box::new(p.iter())
        } else {
            Box::new(p.iter().rev())
        };
        for &q in it {
            while h.len() >= start + 2 && cross(h[h.len() - 2], h[h.len() - 1], q) <= 0.0 {
                h.pop();
            }
            h.push(q);
        }
        h.pop();
    }
    h
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
