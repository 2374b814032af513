//! Feasibility of a placement beyond what timing checks (reach with one configuration, joint
//! position/velocity/acceleration/jerk limits): a margin from the wrist, elbow and shoulder
//! singularities, and no collision of the arm's links with the print bed, the part being
//! printed, or the arm itself.
//!
//! # Collision model (documented estimate, not CAD)
//! Each link is a capsule around the segment between consecutive points of the chain
//! `base origin → joint-frame origins (FK) → flange → nozzle tip`. Segments shorter than
//! 1 mm are dropped. Radii are fractions of the robot's reach `R` (from the robot's info, else
//! the straight-line length of the chain at q = 0), see [`LinkRadii`]: e.g. on the
//! IRB 6700 (R = 2.6 m) base column 0.18 m, arm 0.117 m, wrist 0.065 m, nozzle 0.039 m.
//! - **Bed**: a box in the part frame covering the path's xy bounding box grown by
//!   [`FeasibilityOptions::bed_margin_m`], from the lowest path point down by
//!   [`FeasibilityOptions::bed_depth_m`]. The nozzle segment (flange → tip) is exempt: the
//!   tip prints on the bed.
//! - **Part**: a box over the xy bounding box of the print moves, from the bed up to the highest
//!   point printed so far. The nozzle segment is exempt.
//! - **Self**: capsule–capsule distance (exact segment–segment distance) between links at least
//!   three apart along the chain and separated by more than the sum of their radii of chain
//!   length (e.g. the wrist or nozzle against the base column; the base column against the
//!   upper arm is left to the joint limits, since the capsule estimate would flag it falsely).
//!
//! Capsule–box tests are "segment meets the box grown by r on every side", which is exact on
//! faces and conservative by at most `r(√3 − 1)` at edges and corners.
//!
//! Checks run on every `check_every`-th sample plus the last one (at 4 ms and 150 mm/s, every
//! 10th sample is every 6 mm of path): a brief graze between checked samples can be missed.
//!
//! Singularity margins use the closed-form (OPW) measures and are skipped for robots without
//! OPW parameters (documented limitation).

use crate::kinematics::fk::fk;
use crate::kinematics::opw;
use crate::math::{Frame, V3};
use crate::robot::RobotModel;
use serde::Serialize;

/// Thresholds of the feasibility checks.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FeasibilityOptions {
    /// `|sin q5|` below which a sample counts as near the wrist singularity (dimensionless;
    /// 0.05 ≈ 2.9°). Near it, joints 4 and 6 may use at most [`Self::wrist_rate_max`] of their
    /// velocity and acceleration limits (see [`super::margins`]).
    pub wrist_min: f64,
    /// Largest share of joint 4/6 velocity or acceleration limit accepted near the wrist
    /// singularity (dimensionless, 0.5 = half the limit).
    pub wrist_rate_max: f64,
    /// Position margin from each joint's limits, rad (per joint; the drive file's
    /// `limit_margin_rad` takes precedence).
    pub joint_margin_rad: [f64; crate::kinematics::MAX_DOF],
    /// Smallest accepted elbow measure `|sin(q3 + ψ3)|` (dimensionless; 0 = stretched out).
    pub elbow_min: f64,
    /// Smallest accepted distance of the wrist centre from the axis of joint 1, m.
    pub shoulder_min_m: f64,
    /// Check collisions at all.
    pub collisions: bool,
    /// Check singularities and collisions at every k-th sample (plus the last), ≥ 1.
    pub check_every: usize,
    /// Link capsule radii as fractions of the reach.
    pub radii: LinkRadii,
    /// Bed extends this far beyond the path's xy bounding box, m.
    pub bed_margin_m: f64,
    /// Bed (table) thickness below the lowest path point, m.
    pub bed_depth_m: f64,
}

impl Default for FeasibilityOptions {
    fn default() -> Self {
        FeasibilityOptions {
            wrist_min: 0.05,
            wrist_rate_max: super::margins::DEFAULT_WRIST_RATE_MAX,
            joint_margin_rad: [super::margins::DEFAULT_JOINT_MARGIN_DEG.to_radians();
                crate::kinematics::MAX_DOF],
            elbow_min: 0.05,
            shoulder_min_m: 0.10,
            collisions: true,
            check_every: 10,
            radii: LinkRadii::default(),
            bed_margin_m: 0.10,
            bed_depth_m: 0.50,
        }
    }
}

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

/// Why a placement is infeasible.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Reason {
    /// A path point has no IK solution.
    Unreachable,
    /// One arm configuration cannot be held along the path.
    ConfigurationChange,
    /// Joint velocity/acceleration/jerk limits not met after re-planning.
    JointLimits,
    /// A joint comes closer to a position limit than its margin.
    JointLimitMargin,
    /// Near the wrist singularity, joint 4 or 6 moves too fast.
    WristSingularity,
    /// Too close to the elbow singularity (arm stretched).
    ElbowSingularity,
    /// Wrist centre too close to the axis of joint 1.
    ShoulderSingularity,
    /// A link hits the print bed.
    CollisionBed,
    /// A link hits the part being printed.
    CollisionPart,
    /// Two links of the arm collide.
    SelfCollision,
    /// The model failed (e.g. dynamics error); should not happen with a valid robot.
    ModelError,
}

impl Reason {
    /// Stable snake_case name (as in JSON/CSV).
    pub fn name(self) -> &'static str {
        match self {
            Reason::Unreachable => "unreachable",
            Reason::ConfigurationChange => "configuration_change",
            Reason::JointLimits => "joint_limits",
            Reason::JointLimitMargin => "joint_limit_margin",
            Reason::WristSingularity => "wrist_singularity",
            Reason::ElbowSingularity => "elbow_singularity",
            Reason::ShoulderSingularity => "shoulder_singularity",
            Reason::CollisionBed => "collision_bed",
            Reason::CollisionPart => "collision_part",
            Reason::SelfCollision => "self_collision",
            Reason::ModelError => "model_error",
        }
    }
}

/// An infeasible placement: why, and where along the path.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Infeasible {
    /// The reason.
    pub reason: Reason,
    /// Path sample index (at the interpolation period), when known.
    pub sample: Option<usize>,
    /// Time along the path, s, when known.
    pub t_s: Option<f64>,
    /// Source line of the programmed move, when known.
    pub line: Option<usize>,
    /// Nozzle tip in the robot base frame, m, when known.
    pub point_m: Option<[f64; 3]>,
    /// Human-readable detail (values and thresholds).
    pub detail: String,
}

impl std::fmt::Display for Infeasible {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.reason.name())?;
        if let Some(s) = self.sample {
            write!(f, " at sample {s}")?;
        }
        if let Some(t) = self.t_s {
            write!(f, " (t = {t:.3} s")?;
            if let Some(l) = self.line {
                write!(f, ", line {l}")?;
            }
            write!(f, ")")?;
        }
        if let Some(p) = self.point_m {
            write!(f, " at ({:.3}, {:.3}, {:.3}) m", p[0], p[1], p[2])?;
        }
        write!(f, ": {}", self.detail)
    }
}

impl Infeasible {
    /// From a timing failure.
    pub fn from_timing(e: &crate::timing::TimingFailure) -> Self {
        use crate::timing::TimingFailure as T;
        let detail = e.to_string();
        match e {
            T::Unreachable {
                sample,
                t,
                point,
                line,
                ..
            } => Infeasible {
                reason: Reason::Unreachable,
                sample: Some(*sample),
                t_s: Some(*t),
                line: Some(*line),
                point_m: Some([point.x, point.y, point.z]),
                detail,
            },
            T::ConfigurationChange {
                sample,
                t,
                point,
                line,
                ..
            } => Infeasible {
                reason: Reason::ConfigurationChange,
                sample: Some(*sample),
                t_s: Some(*t),
                line: Some(*line),
                point_m: Some([point.x, point.y, point.z]),
                detail,
            },
            T::LimitsNotMet { t, .. } => Infeasible {
                reason: Reason::JointLimits,
                sample: None,
                t_s: Some(*t),
                line: None,
                point_m: None,
                detail,
            },
        }
    }
}

/// Smallest margins met along the checked samples (for reports).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Margins {
    /// Smallest `|sin q5|` (dimensionless); `None` without OPW parameters.
    pub wrist: Option<f64>,
    /// Largest share of joint 4/6 velocity or acceleration limit used near the wrist
    /// singularity (dimensionless); `None` if the path never comes near it.
    pub wrist_rate: Option<f64>,
    /// Closest approach to a position limit: (joint, 1-based; distance, rad), every sample.
    pub joint_limit_rad: Option<(usize, f64)>,
    /// Smallest elbow measure (dimensionless).
    pub elbow: Option<f64>,
    /// Smallest wrist-centre distance from the axis of joint 1, m.
    pub shoulder_m: Option<f64>,
    /// Smallest clearance between a link capsule and the bed, m: distance of the segment's
    /// ends and middle to the bed box minus the radius (an upper bound of the true clearance;
    /// the collision test itself is the exact slab test against the grown box).
    pub bed_clearance_m: Option<f64>,
}

/// One link capsule in the base frame.
#[derive(Clone, Copy, Debug)]
pub struct Capsule {
    /// Segment start, m.
    pub a: V3,
    /// Segment end, m.
    pub b: V3,
    /// Radius, m.
    pub r: f64,
    /// True for the nozzle (flange → tip), exempt from bed and part checks.
    pub nozzle: bool,
    /// Chain length from the base to `a`, m (to skip neighbours in self-collision checks).
    pub chain_s: f64,
}

/// Reach used to scale the link radii, m.
pub fn reach_m(model: &RobotModel) -> f64 {
    if let Some(r) = model.info.reach_m.filter(|r| *r > 0.0) {
        return r;
    }
    let f = fk(model, &vec![0.0; model.dof()]);
    let mut prev = V3::zeros();
    let mut s = 0.0;
    for fr in f.joint_frames() {
        s += (fr.pos - prev).norm();
        prev = fr.pos;
    }
    (s + (f.tool.pos - prev).norm()).max(0.1)
}

/// The link capsules at `q` (rad), base frame. At most `MAX_DOF + 3` capsules, written into
/// `out` (cleared first).
pub fn capsules(
    model: &RobotModel,
    reach: f64,
    radii: &LinkRadii,
    q: &[f64],
    out: &mut Vec<Capsule>,
) {
    out.clear();
    let f = fk(model, q);
    let mut prev = V3::zeros();
    let mut s = 0.0;
    let n = f.n;
    let mut push = |a: V3, b: V3, r: f64, nozzle: bool, s: &mut f64| {
        let len = (b - a).norm();
        if len > 1e-3 {
            out.push(Capsule {
                a,
                b,
                r: r * reach,
                nozzle,
                chain_s: *s,
            });
        }
        *s += len;
    };
    for (i, fr) in f.joints[..n].iter().enumerate() {
        let r = if i <= 1 {
            radii.base
        } else if i <= 3 {
            radii.arm
        } else {
            radii.wrist
        };
        push(prev, fr.pos, r, false, &mut s);
        prev = fr.pos;
    }
    push(prev, f.flange.pos, radii.wrist, false, &mut s);
    push(f.flange.pos, f.tool.pos, radii.nozzle, true, &mut s);
}

/// Distance between segments `[p1, q1]` and `[p2, q2]`, m (exact; Ericson, Real-Time
/// Collision Detection §5.1.9).
pub fn segment_distance(p1: &V3, q1: &V3, p2: &V3, q2: &V3) -> f64 {
    let d1 = q1 - p1;
    let d2 = q2 - p2;
    let r = p1 - p2;
    let a = d1.dot(&d1);
    let e = d2.dot(&d2);
    let f = d2.dot(&r);
    let eps = 1e-18;
    let (s, t);
    if a <= eps && e <= eps {
        return r.norm();
    }
    if a <= eps {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(&r);
        if e <= eps {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(&d2);
            let denom = a * e - b * b;
            let mut s0 = if denom > eps {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t0 = 0.0;
                s0 = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t0 = 1.0;
                s0 = ((b - c) / a).clamp(0.0, 1.0);
            }
            s = s0;
            t = t0;
        }
    }
    ((p1 + d1 * s) - (p2 + d2 * t)).norm()
}

/// Does segment `[a, b]` meet the axis-aligned box `[lo, hi]` (slab test)? Exact.
pub fn segment_hits_box(a: &V3, b: &V3, lo: &V3, hi: &V3) -> bool {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for i in 0..3 {
        if d[i].abs() < 1e-15 {
            if a[i] < lo[i] || a[i] > hi[i] {
                return false;
            }
        } else {
            let inv = 1.0 / d[i];
            let (mut ta, mut tb) = ((lo[i] - a[i]) * inv, (hi[i] - a[i]) * inv);
            if ta > tb {
                std::mem::swap(&mut ta, &mut tb);
            }
            t0 = t0.max(ta);
            t1 = t1.min(tb);
            if t0 > t1 {
                return false;
            }
        }
    }
    true
}

/// Distance from point `p` to the axis-aligned box `[lo, hi]`, m (0 inside).
pub fn point_box_distance(p: &V3, lo: &V3, hi: &V3) -> f64 {
    let mut s = 0.0;
    for i in 0..3 {
        let d = (lo[i] - p[i]).max(0.0).max(p[i] - hi[i]);
        s += d * d;
    }
    s.sqrt()
}

/// Distance from segment `[a, b]` to the axis-aligned box `[lo, hi]`, m (0 if they meet).
/// Minimised over the segment by golden-section search on the convex distance function.
pub fn segment_box_distance(a: &V3, b: &V3, lo: &V3, hi: &V3) -> f64 {
    if segment_hits_box(a, b, lo, hi) {
        return 0.0;
    }
    let dist = |t: f64| {
        let p = a + (b - a) * t;
        let mut s = 0.0;
        for i in 0..3 {
            let d = (lo[i] - p[i]).max(0.0).max(p[i] - hi[i]);
            s += d * d;
        }
        s.sqrt()
    };
    let g = 0.618_033_988_749_895;
    let (mut l, mut h) = (0.0, 1.0);
    for _ in 0..40 {
        let m1 = h - g * (h - l);
        let m2 = l + g * (h - l);
        if dist(m1) < dist(m2) {
            h = m2;
        } else {
            l = m1;
        }
    }
    dist(0.5 * (l + h)).min(dist(0.0)).min(dist(1.0))
}

/// The static world of one placement: bed and part boxes in the part frame.
#[derive(Clone, Copy, Debug)]
pub struct World {
    /// Base → part transform.
    pub base_to_part: Frame,
    /// Bed box, part frame, m.
    pub bed_lo: V3,
    /// Bed box, part frame, m.
    pub bed_hi: V3,
    /// Part footprint (print moves' xy bounding box), part frame, m; z = bed top.
    pub part_lo: V3,
    /// Part footprint upper corner (x, y), part frame, m.
    pub part_hi_xy: [f64; 2],
}

impl World {
    /// Build from the path's bounding boxes (part frame): `all` over every move, `print` over
    /// print moves.
    pub fn new(at: &Frame, all: (V3, V3), print: (V3, V3), o: &FeasibilityOptions) -> Self {
        let ztop = all.0.z;
        World {
            base_to_part: at.inverse(),
            bed_lo: V3::new(
                all.0.x - o.bed_margin_m,
                all.0.y - o.bed_margin_m,
                ztop - o.bed_depth_m,
            ),
            bed_hi: V3::new(all.1.x + o.bed_margin_m, all.1.y + o.bed_margin_m, ztop),
            part_lo: V3::new(print.0.x, print.0.y, ztop),
            part_hi_xy: [print.1.x, print.1.y],
        }
    }
}

/// Check one joint vector `q` (rad) against singularity margins and collisions; `part_top` is
/// the highest printed point so far (part frame z, m). Updates `margins`. Returns the reason
/// and a detail on failure.
#[allow(clippy::too_many_arguments)]
pub fn check_sample(
    model: &RobotModel,
    reach: f64,
    o: &FeasibilityOptions,
    world: &World,
    q: &[f64],
    part_top: f64,
    caps: &mut Vec<Capsule>,
    margins: &mut Margins,
) -> Option<(Reason, String)> {
    if let Some(p) = model.opw.as_ref().filter(|_| q.len() >= 6) {
        let w = opw::wrist_singularity(p, q);
        let e = opw::elbow_singularity(p, q);
        let s = opw::shoulder_singularity(p, q);
        let upd = |m: &mut Option<f64>, v: f64| *m = Some(m.map_or(v, |x: f64| x.min(v)));
        upd(&mut margins.wrist, w);
        upd(&mut margins.elbow, e);
        upd(&mut margins.shoulder_m, s);
        // The wrist rule needs joint speeds: see super::margins::check_joint_sample.
        if e < o.elbow_min {
            return Some((
                Reason::ElbowSingularity,
                format!("elbow measure {e:.4} < {:.4}", o.elbow_min),
            ));
        }
        if s < o.shoulder_min_m {
            return Some((
                Reason::ShoulderSingularity,
                format!(
                    "wrist centre {s:.3} m from axis 1 < {:.3} m",
                    o.shoulder_min_m
                ),
            ));
        }
    }
    if !o.collisions {
        return None;
    }
    capsules(model, reach, &o.radii, q, caps);
    let tp = &world.base_to_part;
    for (i, c) in caps.iter().enumerate() {
        if c.nozzle {
            continue;
        }
        let (a, b) = (tp.apply(&c.a), tp.apply(&c.b));
        let rv = V3::new(c.r, c.r, c.r);
        // Clearance for reports: distance of the ends and the middle to the box, minus r.
        let d = point_box_distance(&a, &world.bed_lo, &world.bed_hi)
            .min(point_box_distance(&b, &world.bed_lo, &world.bed_hi))
            .min(point_box_distance(
                &((a + b) * 0.5),
                &world.bed_lo,
                &world.bed_hi,
            ))
            - c.r;
        margins.bed_clearance_m = Some(margins.bed_clearance_m.map_or(d, |x| x.min(d)));
        if segment_hits_box(&a, &b, &(world.bed_lo - rv), &(world.bed_hi + rv)) {
            let depth = segment_box_distance(&a, &b, &world.bed_lo, &world.bed_hi);
            return Some((
                Reason::CollisionBed,
                format!(
                    "link capsule {i} (r = {:.3} m) reaches {:.3} m into the bed",
                    c.r,
                    c.r - depth
                ),
            ));
        }
        if part_top > world.part_lo.z + 1e-6 {
            let r = V3::new(c.r, c.r, c.r);
            let hi = V3::new(world.part_hi_xy[0], world.part_hi_xy[1], part_top);
            if segment_hits_box(&a, &b, &(world.part_lo - r), &(hi + r)) {
                return Some((
                    Reason::CollisionPart,
                    format!(
                        "link capsule {i} (r = {:.3} m) meets the part printed up to z = {part_top:.3} m",
                        c.r
                    ),
                ));
            }
        }
    }
    for i in 0..caps.len() {
        for j in i + 3..caps.len() {
            let (ci, cj) = (&caps[i], &caps[j]);
            let gap = cj.chain_s - (ci.chain_s + (ci.b - ci.a).norm());
            if gap <= ci.r + cj.r {
                continue;
            }
            let d = segment_distance(&ci.a, &ci.b, &cj.a, &cj.b);
            if d < ci.r + cj.r {
                return Some((
                    Reason::SelfCollision,
                    format!(
                        "link capsules {i} and {j} are {d:.3} m apart < {:.3} m",
                        ci.r + cj.r
                    ),
                ));
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_distance_cases() {
        let o = V3::zeros();
        let x = V3::new(1.0, 0.0, 0.0);
        // Parallel, offset by 1 in y.
        let d = segment_distance(&o, &x, &V3::new(0.0, 1.0, 0.0), &V3::new(1.0, 1.0, 0.0));
        assert!((d - 1.0).abs() < 1e-12);
        // Crossing skew lines 0.5 apart.
        let d = segment_distance(&o, &x, &V3::new(0.5, -1.0, 0.5), &V3::new(0.5, 1.0, 0.5));
        assert!((d - 0.5).abs() < 1e-12);
        // End-point to end-point.
        let d = segment_distance(&o, &x, &V3::new(2.0, 0.0, 0.0), &V3::new(3.0, 0.0, 0.0));
        assert!((d - 1.0).abs() < 1e-12);
    }

    #[test]
    fn segment_box_cases() {
        let lo = V3::new(0.0, 0.0, -1.0);
        let hi = V3::new(1.0, 1.0, 0.0);
        assert!(segment_hits_box(
            &V3::new(0.5, 0.5, 1.0),
            &V3::new(0.5, 0.5, -0.5),
            &lo,
            &hi
        ));
        assert!(!segment_hits_box(
            &V3::new(2.0, 0.5, 1.0),
            &V3::new(2.0, 0.5, -0.5),
            &lo,
            &hi
        ));
        let d = segment_box_distance(&V3::new(-1.0, 0.5, 0.3), &V3::new(2.0, 0.5, 0.3), &lo, &hi);
        assert!((d - 0.3).abs() < 1e-9, "{d}");
        let d = segment_box_distance(&V3::new(2.0, 2.0, 0.0), &V3::new(3.0, 2.0, 0.0), &lo, &hi);
        assert!((d - 2f64.sqrt()).abs() < 1e-6, "{d}");
    }
}
