//! Feasibility of a placement beyond what timing checks (reach with one configuration, joint
//! position/velocity/acceleration/jerk limits): a margin from the wrist, elbow and shoulder
//! singularities, and no collision of the arm's links with the print bed, the part being
//! printed, or the arm itself.
//!
//! # Collision model
//! See [`crate::evaluate::feasibility::collision`]: parry3d shapes from the URDF's `<collision>` elements (capsules
//! sized by [`LinkRadii`] where a link has none), the print head and hose from the drive file,
//! the bed as a cuboid, and the printed part as bead capsules in a BVH.
//!
//! Checks run on every `check_every`-th sample plus the last one (at 4 ms and 150 mm/s, every
//! 10th sample is every 6 mm of path): a brief graze between checked samples can be missed.
//!
//! Singularity margins use the closed-form (OPW) measures and are skipped for robots without
//! OPW parameters (documented limitation).

pub mod collision;
pub mod margins;

use self::collision::{Beads, Bed, RobotShapes};
use crate::kinematics::opw;
use crate::math::{Frame, V3};
use crate::robot::RobotModel;
pub use crate::robot::{reach_m, LinkRadii};
use parry3d_f64::math::Isometry;
use serde::{Deserialize, Serialize};

/// Thresholds of the feasibility checks.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FeasibilityOptions {
    /// `|sin q5|` below which a sample counts as near the wrist singularity (dimensionless;
    /// 0.05 ≈ 2.9°). Near it, joints 4 and 6 may use at most [`Self::wrist_rate_max`] of their
    /// velocity and acceleration limits (see [`crate::evaluate::feasibility::margins`]).
    pub wrist_min: f64,
    /// Largest share of joint 4/6 velocity or acceleration limit accepted near the wrist
    /// singularity (dimensionless, 0.5 = half the limit).
    pub wrist_rate_max: f64,
    /// Distance kept from the wrist singularity, rad: on every sample the OPW `q5` stays at
    /// least this far from 0 and ±180° (`|sin q5| ≥ sin margin`), as the joint-limit margins
    /// are kept (see [`crate::evaluate::feasibility::margins`]). 0 lets the wrist pass through
    /// the singularity (a round nozzle whose `q6` is free; the exported program then carries
    /// `SingArea \Wrist`), leaving only the rate rule of [`Self::wrist_min`].
    pub wrist_margin_rad: f64,
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
    /// Clearance above the nozzle tip from which up the print head is checked against the
    /// part printed so far, m (every sample; [`collision::HeadOverPart`]). Below it the nozzle
    /// lays the bead of the layer being printed.
    pub head_clearance_m: f64,
}

impl Default for FeasibilityOptions {
    fn default() -> Self {
        FeasibilityOptions {
            wrist_min: 0.05,
            wrist_rate_max: crate::evaluate::feasibility::margins::DEFAULT_WRIST_RATE_MAX,
            wrist_margin_rad: crate::evaluate::feasibility::margins::DEFAULT_WRIST_MARGIN_DEG
                .to_radians(),
            joint_margin_rad: [crate::evaluate::feasibility::margins::DEFAULT_JOINT_MARGIN_DEG
                .to_radians(); crate::kinematics::MAX_DOF],
            elbow_min: 0.05,
            shoulder_min_m: 0.10,
            collisions: true,
            check_every: 10,
            radii: LinkRadii::default(),
            bed_margin_m: 0.10,
            bed_depth_m: 0.50,
            head_clearance_m: collision::HEAD_CLEARANCE_M,
        }
    }
}

impl FeasibilityOptions {
    /// Refuse options no check could use (named as settings, not as a front end's options).
    pub fn check(&self) -> crate::error::Result<()> {
        // In degrees, as the margin is given (90° converted to radians and back is 90° within
        // rounding).
        let m = self.wrist_margin_rad;
        if !(m.is_finite() && m >= 0.0 && m.to_degrees() <= 90.0 + 1e-9) {
            return Err(crate::error::Error::Invalid(format!(
                "wrist margin {}°: expected a margin in [0, 90]° (0 lets the wrist pass through the singularity)",
                m.to_degrees()
            )));
        }
        if self.check_every == 0 {
            return Err(crate::error::Error::Invalid(
                "the collision check interval must be at least 1 sample".into(),
            ));
        }
        Ok(())
    }
}

/// Why a placement is infeasible.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
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
    /// A link (or the hose) reaches below the floor the robot or its pedestal stands on.
    CollisionFloor,
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
            Reason::CollisionFloor => "collision_floor",
            Reason::CollisionPart => "collision_part",
            Reason::SelfCollision => "self_collision",
            Reason::ModelError => "model_error",
        }
    }
}

/// An infeasible placement: why, and where along the path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
    /// The energy model failed at sample `k` of a path sampled every `dt` s.
    pub(crate) fn model_error(k: usize, dt: f64, e: &crate::error::Error) -> Self {
        Infeasible {
            reason: Reason::ModelError,
            sample: Some(k),
            t_s: Some(k as f64 * dt),
            line: None,
            point_m: None,
            detail: e.to_string(),
        }
    }

    /// From a timing failure.
    pub(crate) fn from_timing(e: &crate::timing::TimingFailure) -> Self {
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
            T::LimitsNotMet {
                t, sample, line, ..
            } => Infeasible {
                reason: Reason::JointLimits,
                sample: Some(*sample),
                t_s: Some(*t),
                line: Some(*line),
                point_m: None,
                detail,
            },
        }
    }
}

/// Smallest margins met along the checked samples (for reports).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Margins {
    /// Smallest `|sin q5|` (dimensionless); `None` without OPW parameters.
    pub wrist: Option<f64>,
    /// Largest share of joint 4/6 velocity or acceleration limit used near the wrist
    /// singularity (dimensionless); `None` if the path never comes near it.
    pub wrist_rate: Option<f64>,
    /// Closest approach to a position limit: (joint, 1-based; distance, rad), every sample.
    pub joint_limit_rad: Option<(usize, f64)>,
    /// Smallest `|sin q5|` over every sample (dimensionless; the wrist margin's measure, see
    /// [`Margins::wrist_deg`]); `None` without OPW parameters. [`Margins::wrist`] is the same
    /// measure on the checked samples only.
    #[serde(default)]
    pub wrist_every: Option<f64>,
    /// Smallest elbow measure (dimensionless).
    pub elbow: Option<f64>,
    /// Smallest wrist-centre distance from the axis of joint 1, m.
    pub shoulder_m: Option<f64>,
    /// Smallest distance between an arm shape (not the print head) and the bed, m (parry's
    /// exact distance, evaluated where the AABB broad phase says it could be the smallest).
    pub bed_clearance_m: Option<f64>,
}

impl Margins {
    /// The closest approach of `q5` to the wrist singularity (0 or ±180°) over every sample,
    /// degrees.
    pub fn wrist_deg(&self) -> Option<f64> {
        self.wrist_every
            .map(|w| w.clamp(0.0, 1.0).asin().to_degrees())
    }
}

/// The static world of one placement: the bed in the part frame.
#[derive(Clone, Copy)]
pub struct World {
    /// Base → part transform.
    pub base_to_part: Frame,
    /// The robot base pose in the part frame (parry isometry of `base_to_part`).
    pub base_iso: Isometry<f64>,
    /// Bed box, part frame, m.
    pub bed_lo: V3,
    /// Bed box, part frame, m.
    pub bed_hi: V3,
    /// The bed as a parry cuboid.
    pub bed: Bed,
}

impl World {
    /// Build from the path's bounding box over every move (part frame, m).
    pub fn new(at: &Frame, all: (V3, V3), o: &FeasibilityOptions) -> Self {
        let ztop = all.0.z;
        let bed_lo = V3::new(
            all.0.x - o.bed_margin_m,
            all.0.y - o.bed_margin_m,
            ztop - o.bed_depth_m,
        );
        let bed_hi = V3::new(all.1.x + o.bed_margin_m, all.1.y + o.bed_margin_m, ztop);
        let base_to_part = at.inverse();
        World {
            base_to_part,
            base_iso: collision::iso(&base_to_part),
            bed_lo,
            bed_hi,
            bed: Bed::new(&bed_lo, &bed_hi),
        }
    }

    /// This world with the floor under the arm of `shapes` (see [`collision::Floor`]): the
    /// links and the hose must stay above it.
    pub fn with_floor(mut self, shapes: &RobotShapes) -> Self {
        self.bed.floor = Some(collision::Floor::of(shapes, &self.base_to_part, &self.bed));
        self
    }
}

/// What the arm can collide with at one placement, and its own shapes: borrowed for
/// [`check_sample`].
#[derive(Clone, Copy)]
pub struct Scene<'a> {
    /// The bed and the part frame at this placement.
    pub world: &'a World,
    /// The arm's collision shapes.
    pub shapes: &'a RobotShapes,
    /// The beads of the path (part frame).
    pub beads: &'a Beads,
}

/// Check one joint vector `q` (rad) against singularity margins and collisions; `laid` is the
/// number of beads of `scene.beads` printed so far. Updates `margins`. Returns the reason
/// and a detail on failure. `poses`: scratch. As [`check_sample_with`] without shared sines.
pub(crate) fn check_sample(
    model: &RobotModel,
    o: &FeasibilityOptions,
    scene: Scene<'_>,
    q: &[f64],
    laid: usize,
    poses: &mut Vec<Isometry<f64>>,
    margins: &mut Margins,
) -> Option<(Reason, String)> {
    check_sample_with(model, o, scene, q, None, laid, poses, margins)
}

/// [`check_sample`] with, when known, the sines and cosines of `q` (`2 n` values, the sines
/// then the cosines, as the IK's FK re-check leaves them; see
/// [`RobotShapes::body_frames`]): the links' frames are composed from them in the part frame
/// ([`RobotShapes::body_frames`] from [`World::base_to_part`]) and checked by
/// [`collision::check_bodies`]. Without them the sines are computed with
/// [`crate::fastmath::sin_cos`], which gives the same numbers, so the answer does not depend
/// on whether they are given.
///
/// The singularity measures are [`opw::wrist_singularity`], [`opw::elbow_singularity`] and
/// [`opw::shoulder_singularity`] to the bit (their robot-only terms made once,
/// [`RobotShapes::elbow_terms`]). The collision verdict, reason and message, and the bed
/// clearance, are those of the reference [`check_sample_by_fk`] except through the shape
/// poses' rounding ([`collision::POSE_BOUND`]).
#[allow(clippy::too_many_arguments)]
pub fn check_sample_with(
    model: &RobotModel,
    o: &FeasibilityOptions,
    scene: Scene<'_>,
    q: &[f64],
    sincos: Option<&[f64]>,
    laid: usize,
    poses: &mut Vec<Isometry<f64>>,
    margins: &mut Margins,
) -> Option<(Reason, String)> {
    if let Some(p) = model.opw.as_ref().filter(|_| q.len() >= 6) {
        // opw::{wrist,elbow,shoulder}_singularity's operations, the OPW angles once.
        let (psi3, k) = scene.shapes.elbow_terms(p);
        let mut a = [0.0; 6];
        a.copy_from_slice(&q[..6]);
        let oa = p.to_opw(&a);
        let sin = crate::fastmath::sin;
        // sin(q·σ − 0) = σ·sin q to the bit for σ = ±1 on the fast path (odd kernels, a
        // symmetric reduction): the shared sine where it is that one.
        let shared =
            sincos.filter(|sc| sc.len() == 2 * q.len() && !crate::fastmath::libm_selected());
        let sin_o = |j: usize| match shared {
            Some(sc)
                if p.offsets[j] == 0.0
                    && p.signs[j].abs() == 1.0
                    && q[j].abs() <= crate::fastmath::SIN_COS_MAX =>
            {
                p.signs[j] * sc[j]
            }
            _ => sin(oa[j]),
        };
        let w = sin_o(4).abs();
        let e = sin(oa[2] + psi3).abs();
        let s = (p.c2 * sin_o(1) + k * sin(oa[1] + oa[2] + psi3) + p.a1).abs();
        if let Some(f) = singular(o, margins, w, e, s) {
            return Some(f);
        }
    }
    if !o.collisions {
        return None;
    }
    collisions_with(scene, q, sincos, laid, poses, margins)
}

/// The collision part of [`check_sample_with`] (with `o.collisions` set).
#[inline]
fn collisions_with(
    scene: Scene<'_>,
    q: &[f64],
    sincos: Option<&[f64]>,
    laid: usize,
    poses: &mut Vec<Isometry<f64>>,
    margins: &mut Margins,
) -> Option<(Reason, String)> {
    let Scene {
        world,
        shapes,
        beads,
    } = scene;
    let mut bodies = collision::BodyFrames::default();
    shapes.body_frames_into(q, sincos, &world.base_to_part, &mut bodies);
    collision::check_bodies(
        shapes,
        &bodies,
        &world.bed,
        beads,
        laid,
        &mut margins.bed_clearance_m,
        poses,
    )
}

/// One value per lane.
type Lanes = [f64; crate::simd::LANES];

/// [`check_sample_with`] of a path's checked samples (every `every`-th sample and the last),
/// [`crate::simd::LANES`] of them computed at once: when sample `k` is asked for and is not
/// in the batch in hand, the batch becomes `k` and the next checked samples after it, and
/// their singularity measures (the same sines as lane arithmetic, [`crate::fastmath::
/// sin_cos_lanes`]) and collision geometry ([`collision::lanes::CollisionLanes`]) are
/// computed in lockstep. Each sample is then answered in turn: the measures are the
/// per-sample ones bit for bit and go through the same rule; the collision verdict comes
/// from the lanes only where they show that the per-sample check finds nothing (then the
/// bed clearance is updated as it does), and every other sample (a GJK distance, a box
/// meeting another shape's or the part's, an angle off the fast sines' domain, a NaN) goes
/// through [`check_sample_with`] itself. So every answer, message and margin is
/// [`check_sample_with`]'s, and asking in order gives the same first failure; computing a
/// batch has no effect on `margins`, so a batch cut short by a failure changes nothing.
pub struct CheckedLanes {
    /// The samples of the batch in hand (`len` of them) and the next lane to answer.
    ks: [usize; crate::simd::LANES],
    len: usize,
    next: usize,
    /// Per lane: the wrist, elbow and shoulder measures (see [`check_sample_with`]).
    w: Lanes,
    e: Lanes,
    s: Lanes,
    /// Bit `l`: lane `l` goes through [`check_sample_with`].
    special: u32,
    /// The arm has OPW parameters (the singularity measures are checked).
    opw: bool,
    /// The collision geometry is taken in lockstep ([`RobotShapes::lockstep`]).
    collide: bool,
    coll: collision::lanes::CollisionLanes,
    /// Samples answered from the lanes alone, and of them those whose bed clearance the
    /// lanes lowered (for tests).
    answered: usize,
    lowered: usize,
}

impl CheckedLanes {
    /// For `model` and `shapes` under `o`: `None` where the lockstep answer is not taken
    /// (the scalar level, libm's sines, an arm of more than [`crate::kinematics::MAX_DOF`]
    /// joints, OPW signs other than ±1 or offsets other than 0 on joints 2 and 5).
    pub fn new(model: &RobotModel, o: &FeasibilityOptions, shapes: &RobotShapes) -> Option<Self> {
        let n = model.dof();
        if crate::simd::level() == crate::simd::Level::Scalar
            || crate::fastmath::libm_selected()
            || n > crate::kinematics::MAX_DOF
        {
            return None;
        }
        let opw = match model.opw.as_ref().filter(|_| n >= 6) {
            Some(p) => {
                let unit = |j: usize| p.offsets[j] == 0.0 && p.signs[j].abs() == 1.0;
                if !(unit(1) && unit(4)) {
                    return None;
                }
                true
            }
            None => false,
        };
        Some(CheckedLanes {
            ks: [0; crate::simd::LANES],
            len: 0,
            next: 0,
            w: [0.0; crate::simd::LANES],
            e: [0.0; crate::simd::LANES],
            s: [0.0; crate::simd::LANES],
            special: 0,
            opw,
            collide: o.collisions && shapes.lockstep(),
            coll: Default::default(),
            answered: 0,
            lowered: 0,
        })
    }

    /// How many samples [`CheckedLanes::check`] answered from the lanes alone, without
    /// [`check_sample_with`]'s collision check (for tests).
    #[doc(hidden)]
    pub fn answered(&self) -> usize {
        self.answered
    }

    /// How many of [`CheckedLanes::answered`]'s samples lowered the bed clearance (the lanes'
    /// closed-form clearance taken; for tests).
    #[doc(hidden)]
    pub fn answered_lowering(&self) -> usize {
        self.lowered
    }

    /// [`check_sample_with`]`(model, o, scene, q, sincos, scene.beads.laid_at(k), poses,
    /// margins)` of sample `k` of a path of `m` samples whose checked samples are every
    /// `every`-th and the last; `qs` and `sincos`: every sample's joint positions (rad, `n`
    /// per sample) and their sines then cosines (`2 n` per sample), row-major. The same
    /// `model`, `o` and shapes as [`CheckedLanes::new`]'s.
    #[allow(clippy::too_many_arguments)]
    pub fn check(
        &mut self,
        model: &RobotModel,
        o: &FeasibilityOptions,
        scene: Scene<'_>,
        k: usize,
        every: usize,
        qs: &[f64],
        sincos: &[f64],
        poses: &mut Vec<Isometry<f64>>,
        margins: &mut Margins,
    ) -> Option<(Reason, String)> {
        let n = model.dof();
        let m = qs.len() / n.max(1);
        let q = &qs[k * n..(k + 1) * n];
        let sc = &sincos[k * 2 * n..(k + 1) * 2 * n];
        if sincos.len() != 2 * qs.len() || k >= m {
            return check_sample_with(
                model,
                o,
                scene,
                q,
                Some(sc),
                scene.beads.laid_at(k),
                poses,
                margins,
            );
        }
        if !(self.next < self.len && self.ks[self.next] == k) {
            self.fill(model, o, scene, k, every.max(1), m, qs, sincos);
        }
        let l = self.next;
        self.next += 1;
        if self.special >> l & 1 != 0 {
            let laid = scene.beads.laid_at(k);
            return check_sample_with(model, o, scene, q, Some(sc), laid, poses, margins);
        }
        if self.opw {
            if let Some(f) = singular(o, margins, self.w[l], self.e[l], self.s[l]) {
                return Some(f);
            }
        }
        let before = margins.bed_clearance_m;
        if !o.collisions || (self.collide && self.coll.replay(l, &mut margins.bed_clearance_m)) {
            self.answered += 1;
            self.lowered += usize::from(margins.bed_clearance_m != before);
            return None;
        }
        let laid = scene.beads.laid_at(k);
        collisions_with(scene, q, Some(sc), laid, poses, margins)
    }

    /// The batch from sample `k` on (see [`CheckedLanes`]).
    #[allow(clippy::too_many_arguments)]
    fn fill(
        &mut self,
        model: &RobotModel,
        o: &FeasibilityOptions,
        scene: Scene<'_>,
        k: usize,
        every: usize,
        m: usize,
        qs: &[f64],
        sincos: &[f64],
    ) {
        const W: usize = crate::simd::LANES;
        let n = model.dof();
        let mut len = 1;
        self.ks[0] = k;
        while len < W && self.ks[len - 1] + 1 < m {
            self.ks[len] = (self.ks[len - 1] + every).min(m - 1);
            len += 1;
        }
        for l in len..W {
            self.ks[l] = self.ks[len - 1];
        }
        (self.len, self.next) = (len, 0);
        // The lanes' inputs: the angles the measures take (joints 2, 3 and 5), sines and
        // cosines joint by joint; beads laid.
        let mut q = [[0.0; W]; crate::kinematics::MAX_DOF];
        let mut sc = [[0.0; W]; 2 * crate::kinematics::MAX_DOF];
        let mut laid = [0usize; W];
        let collide = self.collide && o.collisions;
        for l in 0..W {
            let kl = self.ks[l];
            if self.opw {
                // CheckedLanes::new: `opw` only with 6 joints or more.
                for j in [1, 2, 4] {
                    q[j][l] = qs[kl * n + j];
                }
            }
            for (j, v) in sincos[kl * 2 * n..(kl + 1) * 2 * n].iter().enumerate() {
                sc[j][l] = *v;
            }
            if collide {
                // The samples increase: each lane's count from the previous lane's on.
                laid[l] = if l == 0 {
                    scene.beads.laid_at(kl)
                } else {
                    scene.beads.laid_at_from(kl, laid[l - 1])
                };
            }
        }
        let terms = model
            .opw
            .as_ref()
            .filter(|_| self.opw)
            .map(|p| (p, scene.shapes.elbow_terms(p)));
        let inputs = LaneInputs {
            n,
            q: &q,
            sc: &sc,
            laid: &laid,
            terms,
            scene,
            collide,
        };
        crate::simd::dispatch(
            crate::simd::level(),
            FillKernel {
                c: self,
                x: &inputs,
            },
        )
    }
}

/// The lockstep pass of [`CheckedLanes::fill`] (see [`fill_lanes`]).
struct FillKernel<'a, 'b> {
    c: &'a mut CheckedLanes,
    x: &'a LaneInputs<'b>,
}

impl crate::simd::Kernel for FillKernel<'_, '_> {
    type Out = ();
    #[inline(always)]
    fn run<R: crate::simd::F64s>(self) {
        fill_lanes::<R>(self.c, self.x)
    }
}

/// What [`fill_lanes`] computes from.
struct LaneInputs<'a> {
    n: usize,
    q: &'a [Lanes; crate::kinematics::MAX_DOF],
    sc: &'a [Lanes; 2 * crate::kinematics::MAX_DOF],
    laid: &'a [usize; crate::simd::LANES],
    /// The OPW parameters and [`RobotShapes::elbow_terms`] when the measures are checked.
    terms: Option<(&'a crate::robot::OpwParams, (f64, f64))>,
    scene: Scene<'a>,
    collide: bool,
}

/// The numbers of [`CheckedLanes::fill`]: [`check_sample_with`]'s singularity measures
/// lane by lane with its operations (`sin` of the OPW angles by
/// [`crate::fastmath::sin_cos_lanes`], bit-identical to [`crate::fastmath::sin`]), and the
/// collision lanes.
/// The collision lanes are taken a register of `T` at a time (every `T` gives the same
/// numbers).
#[inline(always)]
fn fill_lanes<T: crate::simd::F64s>(c: &mut CheckedLanes, x: &LaneInputs<'_>) {
    const W: usize = crate::simd::LANES;
    let mut special = 0u32;
    if let Some((p, (psi3, k))) = x.terms {
        let (q1, q2, q4) = (&x.q[1], &x.q[2], &x.q[4]);
        let (mut ae, mut ash) = ([0.0; W], [0.0; W]);
        for l in 0..W {
            let (o1, o2) = (
                q1[l] * p.signs[1] - p.offsets[1],
                q2[l] * p.signs[2] - p.offsets[2],
            );
            ae[l] = o2 + psi3;
            ash[l] = o1 + o2 + psi3;
        }
        let (se, _) = crate::fastmath::sin_cos_lanes(&ae);
        let (ssh, _) = crate::fastmath::sin_cos_lanes(&ash);
        let (s1, s4) = (&x.sc[1], &x.sc[4]);
        for l in 0..W {
            // check_sample_with's shared sines hold on the fast sines' domain only.
            let off = !(q1[l].abs() <= crate::fastmath::SIN_COS_MAX
                && q4[l].abs() <= crate::fastmath::SIN_COS_MAX);
            special |= u32::from(off) << l;
            c.w[l] = (p.signs[4] * s4[l]).abs();
            c.e[l] = se[l].abs();
            c.s[l] = (p.c2 * (p.signs[1] * s1[l]) + k * ssh[l] + p.a1).abs();
        }
    }
    c.special = special;
    if x.collide {
        let world = x.scene.world;
        c.coll.compute::<T>(
            x.scene.shapes,
            &x.sc[..2 * x.n],
            &world.base_to_part,
            &world.bed,
            x.scene.beads,
            x.laid,
        );
    }
}

/// Record the singularity measures `w`, `e`, `s` in `margins`; the elbow or shoulder failure.
fn singular(
    o: &FeasibilityOptions,
    margins: &mut Margins,
    w: f64,
    e: f64,
    s: f64,
) -> Option<(Reason, String)> {
    let upd = |m: &mut Option<f64>, v: f64| *m = Some(m.map_or(v, |x: f64| x.min(v)));
    upd(&mut margins.wrist, w);
    upd(&mut margins.elbow, e);
    upd(&mut margins.shoulder_m, s);
    // The wrist rule needs joint speeds: see crate::evaluate::feasibility::margins::check_joint_sample.
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
    None
}

/// [`check_sample`] the plain way, as it was before the shared sines: the singularity
/// measures from [`opw`], the shapes' poses by [`RobotShapes::poses_by_fk`] (libm's sines,
/// parry's quaternions) and [`collision::check_unfiltered`]. The reference that
/// [`check_sample_with`] is tested against (same arguments, units and result).
#[doc(hidden)]
pub fn check_sample_by_fk(
    model: &RobotModel,
    o: &FeasibilityOptions,
    scene: Scene<'_>,
    q: &[f64],
    laid: usize,
    margins: &mut Margins,
) -> Option<(Reason, String)> {
    if let Some(p) = model.opw.as_ref().filter(|_| q.len() >= 6) {
        let w = opw::wrist_singularity(p, q);
        let e = opw::elbow_singularity(p, q);
        let s = opw::shoulder_singularity(p, q);
        if let Some(f) = singular(o, margins, w, e, s) {
            return Some(f);
        }
    }
    if !o.collisions {
        return None;
    }
    let Scene {
        world,
        shapes,
        beads,
    } = scene;
    let poses = shapes.poses_by_fk(model, q, &world.base_iso);
    collision::check_unfiltered(
        shapes,
        &poses,
        &world.bed,
        beads,
        laid,
        &mut margins.bed_clearance_m,
    )
}
