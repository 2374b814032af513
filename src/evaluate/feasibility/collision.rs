//! Collision geometry with `parry3d-f64`: the arm's links, the print head and hose, the bed,
//! and the printed part as it grows.
//!
//! - **Links**: each link's URDF `<collision>` elements (boxes, cylinders, spheres, meshes as
//!   convex hulls), fixed children merged. A link without any (every shipped robot today) gets
//!   a capsule around the segment from its joint origin to the next joint origin (or the
//!   flange), radius a fraction of the reach ([`LinkRadii`], a documented estimate: on the
//!   IRB 6700, R = 2.6 m, base column 0.18 m, arm 0.117 m, wrist 0.065 m). The fixed base gets
//!   its URDF geometry or a capsule from the base origin to joint 1.
//! - **Print head and hose**: from the drive file's `[tool.geometry]` table (flange frame):
//!   a cylinder of `head_radius_m` around the flange → nozzle-tip axis, and a straight capsule
//!   of `hose_radius_m` from `hose_from_m` to `hose_to_m`. Without the table the head is a
//!   capsule of radius `nozzle × R` from the flange to the tip and there is no hose. The head
//!   prints on the bed and the part, so the head shape is exempt from the bed and part checks
//!   of [`check`]; instead [`HeadOverPart`] checks the head above a stated clearance over the
//!   nozzle tip ([`FeasibilityOptions::head_clearance_m`](crate::evaluate::feasibility::FeasibilityOptions::head_clearance_m))
//!   against the beads laid so far, on every sample.
//! - **Bed**: a cuboid under the path (see [`crate::evaluate::feasibility::World`]).
//! - **Part**: the beads laid so far, capsules of [`BEAD_RADIUS_M`] around the nozzle-tip path
//!   (centre one bead radius below the tip) between checked print samples, in a bounding-volume
//!   hierarchy over the order they are laid in ([`Beads`]), built once per job (and again for a
//!   placement whose timing re-planned the motion); a query at sample `k` takes only the beads
//!   finished at or before `k`, and skips whole subtrees laid later.
//! - **Self**: shape pairs on bodies at least three apart along the chain (base = 0, link i =
//!   i + 1, tool = n + 1) that do not already touch at q = 0 (an allowed-collision matrix made
//!   at the home pose, as SRDF generators do).
//!
//! Every test has an AABB broad phase before the exact parry query.

use crate::evaluate::feasibility::{LinkRadii, Reason};
use crate::kinematics::fk::{fk, Axis};
use crate::math::{Frame, V3};
use crate::robot::{GeomShape, RobotModel};
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::{Isometry, Point, Translation, Vector};
use parry3d_f64::na::{Matrix3, Rotation3, UnitQuaternion};
use parry3d_f64::query;
use parry3d_f64::shape::{Capsule, Cuboid, Cylinder, Segment, SharedShape};

pub mod lanes;

/// Bead radius of the printed part, m (ESTIMATE: a 40 mm wide concrete bead, typical of 3DCP).
pub const BEAD_RADIUS_M: f64 = 0.02;

/// Default clearance above the nozzle tip from which up the print head is checked against the
/// printed part, m (ESTIMATE: the free nozzle length of a 3DCP head, about two 15 mm layers;
/// the head body above it must not meet any bead laid so far).
pub(crate) const HEAD_CLEARANCE_M: f64 = 0.03;

/// The print head above the layer being printed, against the printed part: the head's
/// cylinder (or the fallback nozzle capsule's radius) from `clearance` above the nozzle tip
/// up to the flange, checked on every sample against the beads laid so far (parry, as the
/// links). The nozzle itself, below the clearance, lays the bead and is not checked.
///
/// The nozzle is vertical and its spin relative to the part is fixed along a path, so the
/// head's pose in the part frame at a sample is the nozzle-tip point with one rotation
/// (that of [`crate::kinematics::nozzle_target`] at the nozzle spin): whether the head meets
/// the part depends on the path, the head and the spin, not on where the robot stands.
#[derive(Clone)]
pub(crate) struct HeadOverPart {
    /// The head above the clearance, in the nozzle-tip frame.
    local: Isometry<f64>,
    shape: SharedShape,
    /// Clearance above the nozzle tip, m.
    pub clearance_m: f64,
    /// The head is a cylinder about the nozzle axis (a tool along its flange's axis): turning
    /// the nozzle about that axis moves no point of it, so where it meets the part does not
    /// depend on the spin.
    spin_free: bool,
}

/// Where the print head meets the printed part: the sample, the bead and the words.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct HeadHit {
    /// Sample index of the motion checked.
    pub sample: usize,
    /// Index of the bead met (in the order laid).
    pub bead: usize,
    /// What happened, in words.
    pub detail: String,
}

impl HeadOverPart {
    /// The head of `model` above `clearance_m` (m) over the nozzle tip; `None` when nothing
    /// of the head is left above it (or the tool has no length).
    pub fn new(
        model: &RobotModel,
        reach: f64,
        radii: &LinkRadii,
        clearance_m: f64,
    ) -> Option<Self> {
        let tip = model.tool.pos;
        let len = tip.norm();
        let radius = match &model.tool_geometry {
            Some(g) => g.head_radius_m,
            None => radii.nozzle * reach,
        };
        if clearance_m.is_nan()
            || clearance_m < 0.0
            || len - clearance_m < 1e-3
            || radius.is_nan()
            || radius <= 0.0
        {
            return None;
        }
        // In the flange frame: from the flange to `clearance` short of the tip.
        let low = tip * ((len - clearance_m) / len);
        let (l, shape) = cylinder_between(&V3::zeros(), &low, radius)?;
        // Flange frame → tip frame.
        let to_tip = iso(&model.tool.inverse());
        let local = to_tip * l;
        // The cylinder's axis (parry: its local y) in the tip frame, on the nozzle axis (z)?
        let half = shape.as_cylinder().map_or(0.0, |c| c.half_height);
        let on_axis = |y: f64| {
            let p = local * Point::new(0.0, y, 0.0);
            p.x.abs() <= 1e-12 * len && p.y.abs() <= 1e-12 * len
        };
        Some(HeadOverPart {
            local,
            shape,
            clearance_m,
            spin_free: on_axis(half) && on_axis(-half),
        })
    }

    /// The spin at which [`HeadOverPart::first_hit`] is found for a nozzle spun by `spin`
    /// (rad): 0 when the head is a cylinder about the nozzle axis (where it meets the part is
    /// the same at every spin, so it is found once), else `spin`.
    pub(crate) fn spin_checked(&self, spin: f64) -> f64 {
        if self.spin_free {
            0.0
        } else {
            spin
        }
    }

    /// The head's pose and box (part frame) with the nozzle tip at a point, the nozzle spun by
    /// `spin` (rad). The head turns the same way at every point: its rotation and its box
    /// turned (parry's support-map box: each face a support point, rotation · local support +
    /// translation) are found once, and at a point the box is that turned box moved by the
    /// pose's translation: the same values, bit for bit, as `compute_aabb` at the pose
    /// (tested), without its six support-point searches a sample.
    fn placed(&self, spin: f64) -> impl Fn(&V3) -> (Isometry<f64>, Aabb) + '_ {
        let rot = crate::kinematics::nozzle_target(&V3::zeros(), spin).rot;
        let turn = iso(&Frame {
            rot,
            pos: V3::zeros(),
        })
        .rotation;
        let turned = {
            let r = (Isometry::from_parts(Translation::identity(), turn) * self.local).rotation;
            self.shape
                .compute_aabb(&Isometry::from_parts(Translation::identity(), r))
        };
        move |tip: &V3| {
            let pose = Isometry::from_parts(Translation::from(*tip), turn) * self.local;
            let t = pose.translation.vector;
            (pose, Aabb::new(turned.mins + t, turned.maxs + t))
        }
    }

    /// The first sample of the nozzle-tip points `p` (part frame, m) at which the head, the
    /// nozzle spun by `spin` (rad) relative to the part, comes within the bead radius of a
    /// bead of `beads` laid by then: every sample is checked.
    pub(crate) fn first_hit(&self, beads: &Beads, p: &[V3], spin: f64) -> Option<HeadHit> {
        if beads.is_empty() {
            return None;
        }
        let placed = self.placed(spin);
        let bound = PieceBound::of_aabb(&self.shape.compute_local_aabb());
        let mut laid = 0;
        for (k, tip) in p.iter().enumerate() {
            laid = beads.laid_at_from(k, laid);
            if laid == 0 {
                continue;
            }
            let (pose, aabb) = placed(tip);
            if let Some(b) = beads.hit_placed(&pose, &self.shape, &aabb, None, Some(&bound), laid) {
                return Some(HeadHit {
                    sample: k,
                    bead: b,
                    detail: format!(
                        "print head ({:.0} mm and more above the nozzle tip) comes within {:.3} m of printed bead {b}",
                        self.clearance_m * 1000.0,
                        beads.radius_m
                    ),
                });
            }
        }
        None
    }
}

/// What a shape stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// A link (or the fixed base).
    Link,
    /// The print head (exempt from bed and part checks).
    Head,
    /// The material hose.
    Hose,
}

/// One shape rigidly attached to a body of the arm.
#[derive(Clone)]
pub struct BodyShape {
    /// 0 = fixed base, `i + 1` = link of joint `i`, `n + 1` = tool (flange frame).
    pub body: usize,
    /// Pose of the shape in its body frame.
    pub local: Isometry<f64>,
    /// The shape.
    pub shape: SharedShape,
    /// What it stands for.
    pub role: Role,
    /// For messages: "link `name` (URDF box)", "capsule of link 3", "print head", ...
    pub label: String,
    /// A sphere that holds the shape, in the shape's own frame (centre, m; radius, m): the
    /// self pairs' broad phase (see [`check`]).
    pub bound: (Point<f64>, f64),
    /// `local` is the identity (the shape's pose is its body's).
    pub at_origin: bool,
    /// The shape when it is a capsule (its axis in the shape's frame, m).
    pub capsule: Option<Capsule>,
    /// `local` as a rotation matrix and a translation (m).
    local_frame: Frame,
    /// A capsule's axis ends in the body frame (`local` applied, m) and its radius, m.
    axis_body: Option<(V3, V3, f64)>,
    /// The bounding sphere's centre in the body frame (`local` applied, m).
    centre_body: V3,
    /// A mesh piece's box in its own frame (centre, half extents, m): its world box at a pose
    /// is that box turned (a box that holds the piece's AABB, in O(1) instead of one transform
    /// per vertex: the broad phase of a piece with a few hundred vertices).
    local_box: Option<(Vector<f64>, Vector<f64>)>,
    /// A mesh piece's bounds in its own frame (the prefilter of its exact distance to a bead).
    local_bound: Option<PieceBound>,
}

impl BodyShape {
    fn new(
        body: usize,
        local: Isometry<f64>,
        shape: SharedShape,
        role: Role,
        label: String,
    ) -> Self {
        let b = shape.compute_local_bounding_sphere();
        let capsule = shape.as_capsule().copied();
        let local_bound = shape
            .as_convex_polyhedron()
            .map(|h| PieceBound::of_points(h.local_aabb(), h.points()));
        let local_box = local_bound
            .as_ref()
            .map(|b| (b.aabb.center().coords, b.aabb.half_extents()));
        let at_origin = local == Isometry::identity();
        let local_frame = Frame {
            rot: *local.rotation.to_rotation_matrix().matrix(),
            pos: local.translation.vector,
        };
        let in_body = |p: &Point<f64>| {
            if at_origin {
                p.coords
            } else {
                (local * p).coords
            }
        };
        BodyShape {
            body,
            local,
            shape,
            role,
            label,
            bound: (b.center, b.radius),
            at_origin,
            capsule,
            local_frame,
            axis_body: capsule.map(|c| (in_body(&c.segment.a), in_body(&c.segment.b), c.radius)),
            centre_body: in_body(&b.center),
            local_box,
            local_bound,
        }
    }
}

/// The arm's collision shapes and the pairs checked against each other.
#[derive(Clone)]
pub struct RobotShapes {
    /// All shapes.
    pub shapes: Vec<BodyShape>,
    /// Index pairs (into `shapes`) checked for self-collision.
    pub pairs: Vec<(usize, usize)>,
    /// Number of links whose URDF collision geometry is used (the rest are capsules).
    pub links_with_urdf_geometry: usize,
    /// Depth of the floor below the base frame's origin, m (the pedestal's height; 0 = the
    /// base stands on the floor): see [`Floor`].
    pub floor_below_base_m: f64,
    /// The chain of the model given to [`RobotShapes::new`], for [`RobotShapes::body_frames`].
    chain: Chain,
}

/// How a joint of [`Chain`] moves its child frame.
#[derive(Clone, Copy, Debug)]
enum Turn {
    /// Revolute about the unit axis (specialised as FK's [`Axis`]).
    Revolute(Axis),
    /// Prismatic along the unit axis.
    Slide(V3),
}

/// One joint of [`Chain`]: its origin (translation, m; rotation unless the identity) and turn.
#[derive(Clone, Copy, Debug)]
struct ChainJoint {
    pos: V3,
    rot: Option<crate::math::M3>,
    turn: Turn,
}

/// The model's chain pre-processed for [`RobotShapes::body_frames`] (as
/// [`crate::kinematics::fk::FastChain`] does for the tool pose): identity origin rotations
/// skipped, a turn about a coordinate axis applied to two columns. At most
/// [`crate::kinematics::MAX_DOF`] joints.
#[derive(Clone, Debug, Default)]
struct Chain {
    joints: Vec<ChainJoint>,
    /// Flange in the last joint's frame.
    flange: Frame,
    /// The OPW elbow's `(a2, c3)` (m) and from them `ψ3 = atan2(a2, c3)` (rad) and
    /// `√(a2² + c3²)` (m), for the singularity measures ([`RobotShapes::elbow_terms`]).
    elbow: Option<[f64; 4]>,
}

impl Chain {
    fn new(model: &RobotModel) -> Self {
        use crate::robot::JointKind;
        let n = model.joints.len().min(crate::kinematics::MAX_DOF);
        let joints = model.joints[..n]
            .iter()
            .map(|j| {
                let turn = if j.kind == JointKind::Prismatic {
                    Turn::Slide(j.axis)
                } else {
                    Turn::Revolute(Axis::of(&j.axis))
                };
                ChainJoint {
                    pos: j.origin.pos,
                    rot: (j.origin.rot != crate::math::M3::identity()).then_some(j.origin.rot),
                    turn,
                }
            })
            .collect();
        Chain {
            joints,
            flange: model.flange,
            elbow: model.opw.as_ref().map(|p| {
                let (psi3, k) = elbow_terms(p);
                [p.a2, p.c3, psi3, k]
            }),
        }
    }
}

/// `(atan2(a2, c3), √(a2² + c3²))` of `p` (rad, m), as [`crate::kinematics::opw`]'s singularity
/// measures compute them.
fn elbow_terms(p: &crate::robot::OpwParams) -> (f64, f64) {
    (
        crate::fastmath::atan2(p.a2, p.c3),
        (p.a2 * p.a2 + p.c3 * p.c3).sqrt(),
    )
}

/// The frames of the arm's bodies at one joint vector, in the frame the chain was started in
/// (the part frame in a placement evaluation): body 0 the robot base, body `i + 1` the link
/// of joint `i`, body `n + 1` the flange (see [`RobotShapes::body_frames`]).
#[derive(Clone, Copy, Debug)]
pub struct BodyFrames {
    /// Number of joints.
    n: usize,
    frames: [Frame; crate::kinematics::MAX_DOF + 2],
}

impl BodyFrames {
    /// The frame of body `b` (0 = base, `i + 1` = link of joint `i`, beyond: the flange).
    #[inline]
    pub fn body(&self, b: usize) -> &Frame {
        &self.frames[b.min(self.n + 1)]
    }

    /// The pose of shape `s` (its body's frame composed with its own pose), as a parry
    /// isometry (m).
    pub(crate) fn shape_pose(&self, s: &BodyShape) -> Isometry<f64> {
        let f = self.body(s.body);
        if s.at_origin {
            iso(f)
        } else {
            iso(&f.compose(&s.local_frame))
        }
    }
}

/// Largest difference between a shape pose of [`RobotShapes::body_frames`] and
/// [`RobotShapes::poses_by_fk`]'s at the same joint vector, stated (tested: translation, m, and
/// rotation angle, rad, on random configurations of every shipped robot and a URDF arm with
/// general shapes, world poses up to 3 m from the origin): the two differ only by rounding,
/// the sines (the shared polynomial ones, [`crate::fastmath::sin_cos`], within 2 ulp of
/// libm's) and the order of the products (matrices instead of quaternions).
pub const POSE_BOUND: f64 = 1e-13;

/// Largest difference between the bed clearance of [`check_bodies`] (poses from
/// [`RobotShapes::body_frames`]) and [`check_unfiltered`]'s on [`RobotShapes::poses_by_fk`]'s
/// poses, m, stated for a clearance in closed form (every capsule's axis above the bed's top
/// face: tested on random and near-contact configurations). Where parry's GJK distance gives
/// a clearance (a shape other than a capsule, or a capsule reaching beyond the bed's top
/// face) the GJK's own error dominates: on a hose 5.5e-6 m from the bed's corner, parry said
/// 5.3e-4 m for one of two poses that differ in their last bits and 5.5e-6 m for the other.
pub const CLEARANCE_BOUND: f64 = 1e-12;

/// Convert a frame (rotation matrix + position) to a parry isometry.
pub fn iso(f: &Frame) -> Isometry<f64> {
    let r = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(f.rot));
    Isometry::from_parts(Translation::from(f.pos), r)
}

/// A cylinder (parry: along y) along the segment `a → b`, in the frame of `a` and `b`.
fn cylinder_between(a: &V3, b: &V3, r: f64) -> Option<(Isometry<f64>, SharedShape)> {
    let d = b - a;
    let len = d.norm();
    if len < 1e-6 || r <= 0.0 {
        return None;
    }
    let rot = UnitQuaternion::rotation_between(&Vector::y(), &d).unwrap_or_else(|| {
        // d is along −y.
        UnitQuaternion::from_axis_angle(&Vector::x_axis(), std::f64::consts::PI)
    });
    let c = (a + b) * 0.5;
    Some((
        Isometry::from_parts(Translation::from(c), rot),
        SharedShape::new(Cylinder::new(0.5 * len, r)),
    ))
}

fn capsule(a: &V3, b: &V3, r: f64) -> Option<SharedShape> {
    ((b - a).norm() > 1e-3 && r > 0.0)
        .then(|| SharedShape::new(Capsule::new(Point::from(*a), Point::from(*b), r)))
}

fn urdf_shape(s: &GeomShape) -> Option<(Isometry<f64>, SharedShape)> {
    let id = Isometry::identity();
    Some(match s {
        GeomShape::Box { size_m } => (
            id,
            SharedShape::new(Cuboid::new(Vector::from(*size_m) * 0.5)),
        ),
        // URDF cylinders run along z, parry's along y: turn y onto z.
        GeomShape::Cylinder { radius_m, length_m } => (
            Isometry::rotation(Vector::x() * std::f64::consts::FRAC_PI_2),
            SharedShape::new(Cylinder::new(0.5 * length_m, *radius_m)),
        ),
        GeomShape::Sphere { radius_m } => (id, SharedShape::ball(*radius_m)),
        GeomShape::Hull { points, .. } => {
            let pts: Vec<Point<f64>> = points.iter().map(|p| Point::from(*p)).collect();
            (id, SharedShape::convex_hull(&pts)?)
        }
    })
}

/// The URDF collision geometry `geoms` of body `body` (link `name`) added to `shapes`; whether
/// there was any.
fn add_urdf(
    shapes: &mut Vec<BodyShape>,
    body: usize,
    name: &str,
    geoms: &[crate::robot::CollisionGeom],
) -> bool {
    let mut any = false;
    for g in geoms {
        if let Some((l, s)) = urdf_shape(&g.shape) {
            let kind = match &g.shape {
                GeomShape::Box { .. } => "box",
                GeomShape::Cylinder { .. } => "cylinder",
                GeomShape::Sphere { .. } => "sphere",
                GeomShape::Hull { .. } => "mesh hull",
            };
            shapes.push(BodyShape::new(
                body,
                iso(&g.origin) * l,
                s,
                Role::Link,
                format!("link `{name}` (URDF {kind})"),
            ));
            any = true;
        }
    }
    any
}

/// Capsules where the URDF gives nothing (`base_has`: the base has geometry; `has[i]`: link
/// `i` has): base → joint 1, joint i → joint i+1 (or flange), radii scaled by `reach`.
fn add_capsules(
    shapes: &mut Vec<BodyShape>,
    model: &RobotModel,
    reach: f64,
    radii: &LinkRadii,
    base_has: bool,
    has: &[bool],
) {
    let radius = |end: usize| {
        reach
            * if end <= 1 {
                radii.base
            } else if end <= 3 {
                radii.arm
            } else {
                radii.wrist
            }
    };
    if !base_has {
        if let Some(j0) = model.joints.first() {
            if let Some(s) = capsule(&V3::zeros(), &j0.origin.pos, radius(0)) {
                shapes.push(BodyShape::new(
                    0,
                    Isometry::identity(),
                    s,
                    Role::Link,
                    "capsule of the base".into(),
                ));
            }
        }
    }
    for (i, h) in has.iter().enumerate() {
        if *h {
            continue;
        }
        let end = model
            .joints
            .get(i + 1)
            .map_or(model.flange.pos, |j| j.origin.pos);
        if let Some(s) = capsule(&V3::zeros(), &end, radius(i + 1)) {
            shapes.push(BodyShape::new(
                i + 1,
                Isometry::identity(),
                s,
                Role::Link,
                format!(
                    "capsule of link `{}`",
                    model.link_names.get(i).map_or("?", String::as_str)
                ),
            ));
        }
    }
}

/// The print head and hose (flange frame) added to `shapes`: the tool geometry's, or a
/// nozzle capsule scaled by `reach`.
fn add_head(shapes: &mut Vec<BodyShape>, model: &RobotModel, reach: f64, radii: &LinkRadii) {
    let n = model.joints.len();
    let tip = model.tool.pos;
    match &model.tool_geometry {
        Some(g) => {
            if let Some((l, s)) = cylinder_between(&V3::zeros(), &tip, g.head_radius_m) {
                shapes.push(BodyShape::new(n + 1, l, s, Role::Head, "print head".into()));
            }
            let (a, b) = (V3::from(g.hose_from_m), V3::from(g.hose_to_m));
            if let Some(s) = capsule(&a, &b, g.hose_radius_m) {
                shapes.push(BodyShape::new(
                    n + 1,
                    Isometry::identity(),
                    s,
                    Role::Hose,
                    "hose".into(),
                ));
            }
        }
        None => {
            if let Some(s) = capsule(&V3::zeros(), &tip, radii.nozzle * reach) {
                shapes.push(BodyShape::new(
                    n + 1,
                    Isometry::identity(),
                    s,
                    Role::Head,
                    "nozzle (capsule)".into(),
                ));
            }
        }
    }
}

impl RobotShapes {
    /// Build the shapes of `model`; `reach` scales the fallback capsules and the default head.
    pub fn new(model: &RobotModel, reach: f64, radii: &LinkRadii) -> Self {
        let n = model.joints.len();
        let mut shapes = Vec::new();
        let mut with_urdf = 0;
        let base_name = "base".to_string();
        let base_has = add_urdf(&mut shapes, 0, &base_name, &model.base_collision);
        let mut has = vec![false; n];
        for (i, h) in has.iter_mut().enumerate() {
            let name = model.link_names.get(i).map_or("?", String::as_str);
            if let Some(g) = model.link_collision.get(i) {
                *h = add_urdf(&mut shapes, i + 1, name, g);
                if *h {
                    with_urdf += 1;
                }
            }
        }
        add_capsules(&mut shapes, model, reach, radii, base_has, &has);
        add_head(&mut shapes, model, reach, radii);
        // The pedestal: a fixed body under the base, a cylinder about the base's z axis from
        // the floor up to the base frame's origin.
        let (ph, pr) = (model.info.pedestal_height_m, model.info.pedestal_radius_m);
        if ph > 0.0 && pr > 0.0 {
            if let Some((l, s)) = cylinder_between(&V3::new(0.0, 0.0, -ph), &V3::zeros(), pr) {
                shapes.push(BodyShape::new(
                    0,
                    l,
                    s,
                    Role::Link,
                    format!("pedestal ({ph} m high, radius {pr} m)"),
                ));
            }
        }
        let mut rs = RobotShapes {
            shapes,
            pairs: Vec::new(),
            links_with_urdf_geometry: with_urdf,
            floor_below_base_m: ph.max(0.0),
            chain: Chain::new(model),
        };
        rs.allow_home_contacts(model);
        rs
    }

    /// The allowed-collision matrix at the home pose: the pairs of shapes checked are those
    /// of bodies at least three apart that do not touch at home.
    fn allow_home_contacts(&mut self, model: &RobotModel) {
        let n = model.joints.len();
        let home = self.poses(model, &vec![0.0; n], &Isometry::identity());
        for i in 0..self.shapes.len() {
            for j in i + 1..self.shapes.len() {
                let (a, b) = (&self.shapes[i], &self.shapes[j]);
                if a.body.abs_diff(b.body) < 3 {
                    continue;
                }
                let touching = query::intersection_test(
                    &home[i],
                    a.shape.as_ref(),
                    &home[j],
                    b.shape.as_ref(),
                )
                .unwrap_or(true);
                if !touching {
                    self.pairs.push((i, j));
                }
            }
        }
    }

    /// World poses of every shape at `q` (rad), with `world` the pose of the robot base.
    pub fn poses(
        &self,
        model: &RobotModel,
        q: &[f64],
        world: &Isometry<f64>,
    ) -> Vec<Isometry<f64>> {
        let mut out = Vec::with_capacity(self.shapes.len());
        self.poses_into(model, q, world, &mut out);
        out
    }

    /// As [`Self::poses`], into `out` (cleared first).
    ///
    /// The same numbers as [`Self::poses_by_fk`] (the chain by [`fk`], each frame turned into
    /// an isometry and composed with `world` and the shape's own pose), with the work that
    /// cannot change a value left out: a joint frame whose origin has no rotation and whose
    /// axis is a coordinate axis takes the product with the joint's rotation from its two
    /// turning columns (the other products are by exact zeros), no tool frame is made, and a
    /// shape placed at its body's origin takes the body's pose without a product with the
    /// identity. Zeros may differ in sign; every number is equal (tested on random
    /// configurations of every shipped robot).
    pub fn poses_into(
        &self,
        model: &RobotModel,
        q: &[f64],
        world: &Isometry<f64>,
        out: &mut Vec<Isometry<f64>>,
    ) {
        out.clear();
        let n = model.joints.len().min(crate::kinematics::MAX_DOF);
        let mut bodies = [Isometry::identity(); crate::kinematics::MAX_DOF + 2];
        bodies[0] = *world;
        let mut f = Frame::identity();
        for (i, j) in model.joints.iter().take(n).enumerate() {
            let qi = q.get(i).copied().unwrap_or(0.0);
            f = next_frame(&f, j, qi);
            bodies[i + 1] = world * iso(&f);
        }
        bodies[n + 1] = world * iso(&f.compose(&model.flange));
        for s in &self.shapes {
            let b = &bodies[s.body.min(n + 1)];
            out.push(if s.at_origin { *b } else { b * s.local });
        }
    }

    /// The bodies' frames at `q` (rad / m) in the frame in which the robot base stands at
    /// `world` (for a placement, the part frame: [`crate::evaluate::feasibility::World::base_to_part`]),
    /// as rotation matrices composed along the chain from `world` on: no quaternion, no
    /// product with the world pose per body. `sincos`, when given (`2 n` values: the sines of
    /// `q`, then the cosines, as the IK's FK re-check leaves them in
    /// [`crate::timing::joint::Buffers::sincos`]), supplies the revolute joints' sines and
    /// cosines; otherwise they are computed here with [`crate::fastmath::sin_cos`], which gives
    /// the same numbers. For the chain of the model given to [`RobotShapes::new`]; joints
    /// missing from `q` are at 0.
    ///
    /// Each shape's pose ([`BodyFrames::shape_pose`]) agrees with [`Self::poses_by_fk`]'s
    /// within [`POSE_BOUND`] (not to the bit: the sines are the shared polynomial ones and
    /// the products are in another order).
    pub fn body_frames(&self, q: &[f64], sincos: Option<&[f64]>, world: &Frame) -> BodyFrames {
        let mut out = BodyFrames {
            n: 0,
            frames: [Frame::identity(); crate::kinematics::MAX_DOF + 2],
        };
        self.body_frames_into(q, sincos, world, &mut out);
        out
    }

    /// [`Self::body_frames`] into `out` (overwritten).
    #[inline]
    pub fn body_frames_into(
        &self,
        q: &[f64],
        sincos: Option<&[f64]>,
        world: &Frame,
        out: &mut BodyFrames,
    ) {
        let n = self.chain.joints.len();
        out.n = n;
        let sc = sincos.filter(|sc| sc.len() == 2 * q.len() && q.len() == n);
        let (mut r, mut p) = (world.rot, world.pos);
        out.frames[0] = *world;
        for (i, j) in self.chain.joints.iter().enumerate() {
            let qi = q.get(i).copied().unwrap_or(0.0);
            p += r * j.pos;
            if let Some(o) = &j.rot {
                r *= o;
            }
            match j.turn {
                Turn::Slide(a) => p += r * (a * qi),
                Turn::Revolute(axis) => {
                    let (s, c) = match sc {
                        Some(sc) => (sc[i], sc[n + i]),
                        None => crate::fastmath::sin_cos(qi),
                    };
                    axis.rotate(&mut r, s, c);
                }
            }
            out.frames[i + 1] = Frame { rot: r, pos: p };
        }
        let fl = &self.chain.flange;
        out.frames[n + 1] = Frame {
            rot: r * fl.rot,
            pos: r * fl.pos + p,
        };
    }

    /// `(ψ3, k) = (atan2(a2, c3), √(a2² + c3²))` of `p` (rad, m): the terms of the elbow and
    /// shoulder singularity measures that depend on the robot only, made once by
    /// [`RobotShapes::new`] (again here for parameters other than its model's). The same
    /// numbers as computing them anew.
    #[inline]
    pub(crate) fn elbow_terms(&self, p: &crate::robot::OpwParams) -> (f64, f64) {
        match self.chain.elbow {
            Some([a2, c3, psi3, k])
                if a2 == p.a2 && c3 == p.c3 && !crate::fastmath::libm_selected() =>
            {
                (psi3, k)
            }
            _ => elbow_terms(p),
        }
    }

    /// Every shape's pose from `bodies` ([`BodyFrames::shape_pose`]; for tests and
    /// comparisons, the check itself makes only those it needs).
    pub fn poses_of(&self, bodies: &BodyFrames) -> Vec<Isometry<f64>> {
        self.shapes.iter().map(|s| bodies.shape_pose(s)).collect()
    }

    /// [`Self::poses_into`] the plain way: [`fk`] for every frame, each shape's pose the
    /// product of its body's and its own. The reference that `poses_into` is tested against.
    #[doc(hidden)]
    pub fn poses_by_fk(
        &self,
        model: &RobotModel,
        q: &[f64],
        world: &Isometry<f64>,
    ) -> Vec<Isometry<f64>> {
        let f = fk(model, q);
        let n = f.n;
        let mut bodies = Vec::with_capacity(n + 2);
        bodies.push(*world);
        for fr in f.joint_frames() {
            bodies.push(world * iso(fr));
        }
        bodies.push(world * iso(&f.flange));
        self.shapes
            .iter()
            .map(|s| bodies[s.body.min(n + 1)] * s.local)
            .collect()
    }
}

/// `f.compose(&j.transform(q))` (rad / m), with the same numbers: for a revolute joint whose
/// origin has no rotation and whose axis is exactly a coordinate axis, the rotation
/// [`crate::math::rot_axis`] makes has exact zeros off the turning plane, so each column of
/// the product is one or two of its terms (in the order the full product adds them; a zero
/// term only ever changes the sign of a zero sum).
#[inline]
fn next_frame(f: &Frame, j: &crate::robot::Joint, q: f64) -> Frame {
    use crate::robot::JointKind;
    let (x, y, z) = (j.axis.x, j.axis.y, j.axis.z);
    let unit = |a: f64, b: f64, c: f64| a.abs() == 1.0 && b == 0.0 && c == 0.0;
    if j.kind != JointKind::Revolute
        || j.origin.rot != crate::math::M3::identity()
        || !(unit(x, y, z) || unit(y, z, x) || unit(z, x, y))
    {
        return f.compose(&j.transform(q));
    }
    let (s, c) = q.sin_cos();
    let t = 1.0 - c;
    let r = &f.rot;
    let col = |k: usize| V3::new(r[(0, k)], r[(1, k)], r[(2, k)]);
    // rot_axis about axis k (sign σ): the diagonal entry of k is t·σ·σ + c = t + c; in the
    // plane (a, b) after k: R[a][a] = R[b][b] = c, R[b][a] = σ s, R[a][b] = −σ s.
    let (k, a, b, sg) = if x != 0.0 {
        (0, 1, 2, x)
    } else if y != 0.0 {
        (1, 2, 0, y)
    } else {
        (2, 0, 1, z)
    };
    // rot_axis's entries: R[b][a] = t·(..)·0 + s·σ, R[a][b] = t·(..)·0 − s·σ.
    let (sba, sab) = (s * sg, -(s * sg));
    let (ca, cb, ck) = (col(a), col(b), col(k));
    // Column a of f·R: f[:, a]·R[a][a] + f[:, b]·R[b][a]; column b: f[:, a]·R[a][b] +
    // f[:, b]·R[b][b], each added in index order (a < b, or b < a when the axis is y).
    let (na, nb) = if a < b {
        (ca * c + cb * sba, ca * sab + cb * c)
    } else {
        (cb * sba + ca * c, cb * c + ca * sab)
    };
    let nk = ck * (t + c);
    let mut rot = crate::math::M3::zeros();
    rot.set_column(a, &na);
    rot.set_column(b, &nb);
    rot.set_column(k, &nk);
    Frame {
        rot,
        pos: f.rot * j.origin.pos + f.pos,
    }
}

/// The printed part: bead capsules in a bounding-volume hierarchy, in the part frame.
///
/// The hierarchy is built over the beads in the order they are laid (each node holds a
/// contiguous range of bead indices, split in halves), not over space: a path lays its beads
/// along a continuous curve, so index ranges are compact in space, and a query at sample `k`
/// skips every node whose first bead is laid after `k` without looking at its children. On a
/// tall wall (300 layers, 3·10⁵ beads) a spatial BVH handed every bead of the layers *above*
/// the current one that a link's box overlaps to the `laid` filter, one by one; here they
/// cost one test per subtree. The beads found are the same; the one named is the first laid.
pub struct Beads {
    segs: Vec<Segment>,
    /// Each bead's box, loosened by the bead radius.
    boxes: Vec<Aabb>,
    /// Sample index at which bead `i` is finished (non-decreasing).
    done_at: Vec<usize>,
    /// The hierarchy over index ranges, root first (see [`BeadNode`]).
    nodes: Vec<BeadNode>,
    /// Bead radius, m.
    pub radius_m: f64,
}

/// Beads per leaf of [`Beads`]' hierarchy.
const BEAD_LEAF: usize = 8;

/// A node of [`Beads`]' hierarchy: the box of beads `start..end` and its children `left` and
/// `right` (indices into the node list; 0 for a leaf: the root is never a child).
#[derive(Clone, Copy, Debug)]
struct BeadNode {
    aabb: Aabb,
    start: u32,
    end: u32,
    left: u32,
    right: u32,
}

/// Build the hierarchy over `boxes[r]` into `nodes`; returns the node's index.
fn build_bead_nodes(boxes: &[Aabb], r: std::ops::Range<usize>, nodes: &mut Vec<BeadNode>) -> u32 {
    let mut aabb = boxes[r.start];
    for b in &boxes[r.start + 1..r.end] {
        aabb.merge(b);
    }
    let me = nodes.len();
    nodes.push(BeadNode {
        aabb,
        start: r.start as u32,
        end: r.end as u32,
        left: 0,
        right: 0,
    });
    if r.len() > BEAD_LEAF {
        let mid = r.start + r.len() / 2;
        let l = build_bead_nodes(boxes, r.start..mid, nodes);
        let rr = build_bead_nodes(boxes, mid..r.end, nodes);
        nodes[me].left = l;
        nodes[me].right = rr;
    }
    me as u32
}

impl Beads {
    /// Beads along the nozzle-tip points `p` (part frame, m) where `print` is set, one bead
    /// capsule per run of up to `every` print samples.
    pub fn new(p: &[V3], print: &[bool], every: usize, radius_m: f64) -> Self {
        Beads::with_prior(&[], p, print, every, radius_m)
    }

    /// [`Beads::new`] with walls printed before this path starts: `prior` nozzle-tip segments
    /// (part frame, m), laid from sample 0 on and indexed before the path's own beads (a
    /// multi-station plan's earlier segments).
    pub(crate) fn with_prior(
        prior: &[(V3, V3)],
        p: &[V3],
        print: &[bool],
        every: usize,
        radius_m: f64,
    ) -> Self {
        let every = every.max(1);
        let down = V3::new(0.0, 0.0, radius_m);
        let mut segs = Vec::new();
        let mut done_at = Vec::new();
        for (a, b) in prior {
            segs.push(Segment::new(Point::from(a - down), Point::from(b - down)));
            done_at.push(0);
        }
        let mut start: Option<usize> = None;
        for k in 0..p.len() {
            if !print.get(k).copied().unwrap_or(false) {
                start = None;
                continue;
            }
            let s = *start.get_or_insert(k);
            let next_prints = print.get(k + 1).copied().unwrap_or(false);
            if k > s && (k - s >= every || !next_prints) {
                segs.push(Segment::new(
                    Point::from(p[s] - down),
                    Point::from(p[k] - down),
                ));
                done_at.push(k);
                start = Some(k);
            }
        }
        let boxes: Vec<Aabb> = segs
            .iter()
            .map(|s| Aabb::from_points([s.a, s.b]).loosened(radius_m))
            .collect();
        let mut nodes = Vec::with_capacity(2 * boxes.len().div_ceil(BEAD_LEAF));
        if !boxes.is_empty() {
            build_bead_nodes(&boxes, 0..boxes.len(), &mut nodes);
        }
        Beads {
            segs,
            boxes,
            done_at,
            nodes,
            radius_m,
        }
    }

    /// Whether [`Beads::hit_placed`] with `aabb` and `laid` goes past the hierarchy's root
    /// (some bead laid and the root's box meets `aabb`): when not, it finds nothing.
    #[inline(always)]
    fn root_meets(&self, aabb: &Aabb, laid: usize) -> bool {
        laid > 0
            && self
                .nodes
                .first()
                .is_some_and(|r| (r.start as usize) < laid && r.aabb.intersects(aabb))
    }

    /// Number of beads finished at or before sample `k`.
    pub fn laid_at(&self, k: usize) -> usize {
        self.done_at.partition_point(|&d| d <= k)
    }

    /// [`Beads::laid_at`]`(k)` given `from`, the count at an earlier sample (or any number
    /// not above it): a few steps forward from `from` (the checked samples of a batch lay a
    /// bead or so each), a binary search beyond. The same number as `laid_at(k)`.
    #[inline]
    pub fn laid_at_from(&self, k: usize, from: usize) -> usize {
        let d = &self.done_at;
        let mut i = from.min(d.len());
        for _ in 0..4 {
            if i == d.len() || d[i] > k {
                return i;
            }
            i += 1;
        }
        i + d[i..].partition_point(|&x| x <= k)
    }

    /// Number of beads.
    pub fn len(&self) -> usize {
        self.segs.len()
    }

    /// No bead at all (a path without print moves).
    pub fn is_empty(&self) -> bool {
        self.segs.is_empty()
    }

    /// Does `shape` at `pose` (part frame) come within the bead radius of one of the first
    /// `laid` beads? Returns the bead index.
    pub fn hit(&self, pose: &Isometry<f64>, shape: &SharedShape, laid: usize) -> Option<usize> {
        if laid == 0 || self.nodes.is_empty() {
            return None;
        }
        self.hit_within(pose, shape, &shape.compute_aabb(pose), laid)
    }

    /// [`Beads::hit`] with the shape's AABB at `pose` already known (`aabb`, part frame, m:
    /// `shape.compute_aabb(pose)`).
    pub(crate) fn hit_within(
        &self,
        pose: &Isometry<f64>,
        shape: &SharedShape,
        aabb: &Aabb,
        laid: usize,
    ) -> Option<usize> {
        if laid == 0 || self.nodes.is_empty() {
            return None;
        }
        let cap = shape
            .as_capsule()
            .map(|c| (pose * c.segment.a, pose * c.segment.b, c.radius));
        let local = if shape.as_convex_polyhedron().is_some() {
            None
        } else {
            Some(PieceBound::of_aabb(&shape.compute_local_aabb()))
        };
        self.hit_placed(pose, shape, aabb, cap, local.as_ref(), laid)
    }

    /// Whether bead `i` comes within the bead radius of `shape` at `pose` (`cap`, `local`: as
    /// in [`Beads::hit_placed`]). A capsule (every link without URDF geometry) against a bead
    /// segment in closed form (segment–segment closest points, Ericson's method as parry
    /// implements it) instead of parry's general GJK dispatch: same distance, a fraction of the
    /// cost.
    #[inline]
    fn touches(
        &self,
        i: usize,
        pose: &Isometry<f64>,
        shape: &SharedShape,
        cap: &Option<(Point<f64>, Point<f64>, f64)>,
        local: Option<&PieceBound>,
    ) -> bool {
        let cap_id = Isometry::identity();
        let seg = &self.segs[i];
        let d = match cap {
            Some((a, b, r)) => {
                let (la, lb) = query::details::closest_points_segment_segment_with_locations_nD(
                    (a, b),
                    (&seg.a, &seg.b),
                );
                let pa = Segment::new(*a, *b).point_at(&la);
                let pb = seg.point_at(&lb);
                ((pa - pb).norm() - r).max(0.0)
            }
            None => {
                if let Some(l) = local {
                    let (a, b) = (
                        pose.inverse_transform_point(&seg.a),
                        pose.inverse_transform_point(&seg.b),
                    );
                    let sb = Aabb::new(a.inf(&b), a.sup(&b));
                    if aabb_gap(&sb, &l.aabb) >= self.radius_m || l.apart(&a, &b, self.radius_m) {
                        return false;
                    }
                }
                query::distance(pose, shape.as_ref(), &cap_id, seg).unwrap_or(f64::INFINITY)
            }
        };
        d < self.radius_m
    }

    /// [`Beads::hit_within`] with, for a capsule, its axis's ends at `pose` and its radius
    /// already known (`cap`: `pose * a`, `pose * b`, part frame, m; radius, m), and for another
    /// shape its AABB in its own frame where known (`local`: a bead whose segment's box in that
    /// frame lies a bead radius or more from it cannot touch, and skips the exact distance).
    fn hit_placed(
        &self,
        pose: &Isometry<f64>,
        shape: &SharedShape,
        aabb: &Aabb,
        cap: Option<(Point<f64>, Point<f64>, f64)>,
        local: Option<&PieceBound>,
        laid: usize,
    ) -> Option<usize> {
        if laid == 0 || self.nodes.is_empty() {
            return None;
        }
        let aabb = *aabb;
        let touches = |i: usize| self.touches(i, pose, shape, &cap, local);
        // The root first: most shapes (the base, the upper arm) miss the part's box.
        let root = &self.nodes[0];
        if root.start as usize >= laid || !root.aabb.intersects(&aabb) {
            return None;
        }
        // A shape with a box of its own (a mesh piece) is held by that box turned to `pose`;
        // a node whose box lies apart from it along one of its axes holds no bead within
        // reach (the node's box holds every point within the bead radius of its beads).
        let turned = local
            .filter(|_| cap.is_none())
            .map(|l| Turned::new(pose, &l.aabb));
        // Depth-first, lower indices first: the first bead found is the first laid.
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let nd = &self.nodes[stack[top] as usize];
            if nd.start as usize >= laid
                || !nd.aabb.intersects(&aabb)
                || turned.as_ref().is_some_and(|t| t.apart(&nd.aabb))
            {
                continue;
            }
            if nd.left == 0 {
                let end = (nd.end as usize).min(laid);
                if let Some(i) = (nd.start as usize..end)
                    .find(|&i| self.boxes[i].intersects(&aabb) && touches(i))
                {
                    return Some(i);
                }
            } else {
                // Right pushed first so that the left (earlier) half is searched first; the
                // depth is at most log2 of the bead count, far below the stack's 64.
                stack[top] = nd.right;
                stack[top + 1] = nd.left;
                top += 2;
            }
        }
        None
    }
}

/// The bed as a parry cuboid (part frame).
#[derive(Clone, Copy)]
pub struct Bed {
    /// Pose of the cuboid's centre.
    pub pose: Isometry<f64>,
    /// The cuboid.
    pub cuboid: Cuboid,
    /// Its AABB.
    pub aabb: Aabb,
    /// The floor, when checked ([`crate::evaluate::feasibility::World::with_floor`]).
    pub floor: Option<Floor>,
}

/// The floor: the plane the robot (or its pedestal) stands on, `normal · x = height` in the
/// part frame with `normal` the base frame's z axis. It lies [`RobotShapes::floor_below_base_m`]
/// below the base frame's origin, or at the bed's top where the path lies lower (a part in a
/// pit, or an arm on a raised track: the floor is then taken down to the bed's top). The
/// links and the hose must stay above it; the fixed base and pedestal stand on it and the
/// print head, which prints on the bed, is exempt as it is from the bed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Floor {
    /// Upward unit normal (the base's z axis in the part frame).
    pub normal: V3,
    /// `normal · x` on the floor, m.
    pub height: f64,
}

impl Floor {
    /// The floor of `rs` with the base at `base` (part frame) over the bed `bed`.
    pub fn of(rs: &RobotShapes, base: &Frame, bed: &Bed) -> Floor {
        let normal = base.rot.column(2).into_owned();
        let under_base = normal.dot(&base.pos) - rs.floor_below_base_m;
        let bed_top = normal.dot(&V3::new(
            bed.aabb.center().x,
            bed.aabb.center().y,
            bed.aabb.maxs.z,
        ));
        Floor {
            normal,
            height: under_base.min(bed_top),
        }
    }

    /// Height of the lowest point of `shape` at `pose` above the floor, m (negative: below).
    pub fn clearance(&self, pose: &Isometry<f64>, shape: &SharedShape) -> Option<f64> {
        let down = -Vector::from(self.normal);
        let p = shape.as_support_map()?.support_point(pose, &down);
        Some(self.normal.dot(&p.coords) - self.height)
    }

    /// Height of the lowest corner of `b` (part frame, m) above the floor, m: at most the
    /// [`Floor::clearance`] of any shape inside it.
    pub(crate) fn box_clearance(&self, b: &Aabb) -> f64 {
        let (c, h) = (b.center().coords, b.half_extents());
        self.normal.dot(&c) - self.normal.abs().dot(&h) - self.height
    }

    /// [`Floor::clearance`] of the capsule around `a`–`b` (part frame, m) of radius `r`, m.
    pub(crate) fn axis_clearance(&self, a: &Point<f64>, b: &Point<f64>, r: f64) -> f64 {
        self.normal.dot(&a.coords).min(self.normal.dot(&b.coords)) - r - self.height
    }
}

/// Whether shape `s` is checked against the floor (the links and the hose, not the fixed
/// base and pedestal nor the print head).
#[inline(always)]
pub(crate) fn on_floor_check(s: &BodyShape) -> bool {
    s.body > 0 && s.role != Role::Head
}

fn floor_message(s: &BodyShape, i: usize, c: f64) -> (Reason, String) {
    (
        Reason::CollisionFloor,
        format!(
            "{} (shape {i}) reaches {:.3} m below the floor",
            s.label,
            (-c).max(0.0)
        ),
    )
}

impl Bed {
    /// Exact distance of a capsule `shape` at `pose` (part frame) from the bed when the
    /// capsule's axis lies wholly above the bed's top face and within its footprint (the usual
    /// case: a link above the table): then the nearest point of the bed to every point of the
    /// axis is straight below it, and the distance is the axis's lowest height over the top
    /// minus the radius (0 when it touches). `None` in every other case (use parry's GJK).
    pub fn capsule_above(&self, pose: &Isometry<f64>, shape: &SharedShape) -> Option<f64> {
        let c = shape.as_capsule()?;
        self.axis_above(&(pose * c.segment.a), &(pose * c.segment.b), c.radius)
    }

    /// [`Bed::capsule_above`] of the capsule around the axis `a`–`b` (part frame, m) of
    /// radius `radius`, m.
    fn axis_above(&self, a: &Point<f64>, b: &Point<f64>, radius: f64) -> Option<f64> {
        let (lo, hi) = (&self.aabb.mins, &self.aabb.maxs);
        let inside = |p: &Point<f64>| {
            p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= hi.z
        };
        (inside(a) && inside(b)).then(|| (a.z.min(b.z) - hi.z - radius).max(0.0))
    }

    /// From the box corners `lo`, `hi` (part frame, m).
    pub fn new(lo: &V3, hi: &V3) -> Self {
        let c = (lo + hi) * 0.5;
        Bed {
            pose: Isometry::translation(c.x, c.y, c.z),
            cuboid: Cuboid::new((hi - lo) * 0.5),
            aabb: Aabb::new(Point::from(*lo), Point::from(*hi)),
            floor: None,
        }
    }
}

/// Collision check of one sample: the shapes at `poses` (part frame) against the bed, the
/// first `laid` beads and each other. Updates the smallest bed clearance `clearance` (m).
///
/// Broad phases, each conservative (a pair it drops is one the exact query would find apart):
/// every shape's AABB against the bed and the beads' hierarchy (computed once a shape and
/// shared by both); for the self pairs the AABBs, where the print head, which meets neither
/// bed nor beads, first stands in with the box of its bounding sphere (its own AABB, costly
/// for a cylinder, is computed only when that box meets the other shape's). The verdict, the
/// reason, its message and the clearance are those of the same tests without these
/// shortcuts ([`check_unfiltered`]; tested on random, near-contact and real configurations).
pub fn check(
    rs: &RobotShapes,
    poses: &[Isometry<f64>],
    bed: &Bed,
    beads: &Beads,
    laid: usize,
    clearance: &mut Option<f64>,
) -> Option<(Reason, String)> {
    let n = rs.shapes.len().min(poses.len());
    with_boxes(n, |boxes, exact| {
        check_with(
            rs,
            &mut Isos(poses),
            n,
            bed,
            beads,
            laid,
            clearance,
            boxes,
            exact,
        )
    })
}

/// [`check`] of the shapes placed by `bodies` ([`RobotShapes::body_frames`]): the same tests,
/// with each capsule's axis and the print head's bounding sphere placed straight from its
/// body's frame, and a shape's parry isometry ([`BodyFrames::shape_pose`]) made only for the
/// queries that need one (a shape other than a capsule, a capsule not wholly above the bed,
/// a self pair whose boxes meet). `isos`: scratch for those isometries (resized here).
///
/// Its answer is [`check_unfiltered`]'s on the poses of [`BodyFrames::shape_pose`]; against
/// [`RobotShapes::poses_by_fk`]'s poses it differs only through the poses' rounding
/// ([`POSE_BOUND`]): the bed clearance by at most about as much, the verdict only for a
/// configuration that close to a boundary between outcomes.
pub fn check_bodies(
    rs: &RobotShapes,
    bodies: &BodyFrames,
    bed: &Bed,
    beads: &Beads,
    laid: usize,
    clearance: &mut Option<f64>,
    isos: &mut Vec<Isometry<f64>>,
) -> Option<(Reason, String)> {
    let n = rs.shapes.len();
    if isos.len() < n {
        isos.resize(n, Isometry::identity());
    }
    with_boxes(n, |boxes, exact| {
        check_with(
            rs,
            &mut Placed {
                bodies,
                isos,
                made: 0,
            },
            n,
            bed,
            beads,
            laid,
            clearance,
            boxes,
            exact,
        )
    })
}

/// `f(boxes, exact)` with `n` scratch boxes and flags (on the stack for up to 32 shapes: an arm
/// with a link in several convex pieces has more than 16).
#[inline(always)]
fn with_boxes<R>(n: usize, f: impl FnOnce(&mut [Aabb], &mut [bool]) -> R) -> R {
    const ON_STACK: usize = 32;
    let none = Aabb::new_invalid();
    if n <= ON_STACK {
        let (mut boxes, mut exact) = ([none; ON_STACK], [false; ON_STACK]);
        f(&mut boxes[..n], &mut exact[..n])
    } else {
        let (mut boxes, mut exact) = (vec![none; n], vec![false; n]);
        f(&mut boxes, &mut exact)
    }
}

impl Default for BodyFrames {
    fn default() -> Self {
        BodyFrames {
            n: 0,
            frames: [Frame::identity(); crate::kinematics::MAX_DOF + 2],
        }
    }
}

/// Where [`check_with`] takes the shapes' placement from.
trait ShapePoses {
    /// A capsule's axis ends at its pose (m) and its radius (m); `None` for other shapes.
    fn axis(&self, i: usize, s: &BodyShape) -> Option<(Point<f64>, Point<f64>, f64)>;
    /// The centre of the shape's bounding sphere at its pose (m).
    fn centre(&self, i: usize, s: &BodyShape) -> Point<f64>;
    /// The shape's pose.
    fn iso(&mut self, i: usize, s: &BodyShape) -> Isometry<f64>;
}

/// Poses given as isometries ([`check`]).
struct Isos<'a>(&'a [Isometry<f64>]);

impl ShapePoses for Isos<'_> {
    #[inline(always)]
    fn axis(&self, i: usize, s: &BodyShape) -> Option<(Point<f64>, Point<f64>, f64)> {
        let p = &self.0[i];
        s.capsule
            .map(|c| (p * c.segment.a, p * c.segment.b, c.radius))
    }
    #[inline(always)]
    fn centre(&self, i: usize, s: &BodyShape) -> Point<f64> {
        self.0[i] * s.bound.0
    }
    #[inline(always)]
    fn iso(&mut self, i: usize, _: &BodyShape) -> Isometry<f64> {
        self.0[i]
    }
}

/// Poses from the bodies' frames, isometries made on demand ([`check_bodies`]).
struct Placed<'a> {
    bodies: &'a BodyFrames,
    isos: &'a mut [Isometry<f64>],
    /// Bit `i`: `isos[i]` made (shapes beyond 64 are made at every use).
    made: u64,
}

impl ShapePoses for Placed<'_> {
    #[inline(always)]
    fn axis(&self, _: usize, s: &BodyShape) -> Option<(Point<f64>, Point<f64>, f64)> {
        let f = self.bodies.body(s.body);
        s.axis_body.map(|(a, b, r)| {
            // The fallback capsules start at their body's origin.
            let pa = if a == V3::zeros() {
                f.pos
            } else {
                f.rot * a + f.pos
            };
            (Point::from(pa), Point::from(f.rot * b + f.pos), r)
        })
    }
    #[inline(always)]
    fn centre(&self, _: usize, s: &BodyShape) -> Point<f64> {
        let f = self.bodies.body(s.body);
        Point::from(f.rot * s.centre_body + f.pos)
    }
    #[inline]
    fn iso(&mut self, i: usize, s: &BodyShape) -> Isometry<f64> {
        if i < 64 && self.made & (1 << i) != 0 {
            return self.isos[i];
        }
        let p = self.bodies.shape_pose(s);
        if i < 64 {
            self.isos[i] = p;
            self.made |= 1 << i;
        }
        p
    }
}

/// Margin added to a bounding sphere's radius before its box stands in for a shape's AABB, m
/// (against rounding in the sphere's centre; a larger box only makes the test looser).
pub(crate) const SPHERE_MARGIN_M: f64 = 1e-6;

/// [`check`] of the first `n` shapes placed by `at`, with `boxes` and `exact` (one per shape)
/// as scratch for the shapes' boxes: the AABB (`exact`), or a box that holds it.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn check_with(
    rs: &RobotShapes,
    at: &mut impl ShapePoses,
    n: usize,
    bed: &Bed,
    beads: &Beads,
    laid: usize,
    clearance: &mut Option<f64>,
    boxes: &mut [Aabb],
    exact: &mut [bool],
) -> Option<(Reason, String)> {
    let env = Against { bed, beads, laid };
    for (i, s) in rs.shapes.iter().enumerate().take(n) {
        if s.role == Role::Head {
            let (c, r) = (at.centre(i, s), s.bound.1 + SPHERE_MARGIN_M);
            boxes[i] = Aabb::new(c - Vector::repeat(r), c + Vector::repeat(r));
            exact[i] = false;
            continue;
        }
        // A capsule's axis at its pose, once for its AABB (as parry makes it), the bed and the
        // beads.
        let cap = at.axis(i, s);
        let (a, ex) = shape_box(at, i, s, &cap);
        (boxes[i], exact[i]) = (a, ex);
        if let Some(hit) = env.shape_meets(at, i, s, cap, &a, clearance) {
            return Some(hit);
        }
    }
    self_pairs(rs, at, n, boxes, exact)
}

/// What a robot's shapes are checked against in [`check_with`]: the bed (and the floor), and
/// the first `laid` beads.
struct Against<'c> {
    bed: &'c Bed,
    beads: &'c Beads,
    laid: usize,
}

/// Shape `i` (`s`, a capsule with axis `cap` at its pose, if it is one) placed by `at`: its
/// box, and whether that is its AABB (else a box that holds it).
#[inline(always)]
fn shape_box(
    at: &mut impl ShapePoses,
    i: usize,
    s: &BodyShape,
    cap: &Option<(Point<f64>, Point<f64>, f64)>,
) -> (Aabb, bool) {
    match (cap, &s.local_box) {
        (Some((ea, eb, r)), _) => (Capsule::new(*ea, *eb, *r).local_aabb(), true),
        // A mesh piece: its own box turned (holds the AABB; the self pairs make the exact
        // AABB only where these boxes meet).
        (None, Some((c, h))) => {
            let p = at.iso(i, s);
            let rot = p.rotation.to_rotation_matrix();
            let m = rot.matrix();
            let half = m.abs() * h;
            let centre = p * Point::from(*c);
            (Aabb::new(centre - half, centre + half), false)
        }
        (None, None) => (s.shape.compute_aabb(&at.iso(i, s)), true),
    }
}

impl Against<'_> {
    /// Shape `i` (`s`, placed by `at`; `cap`: its axis when a capsule, `a`: its box) against
    /// the floor, the bed (lowering `clearance`) and the beads: what it meets first, if
    /// anything.
    #[inline(always)]
    fn shape_meets(
        &self,
        at: &mut impl ShapePoses,
        i: usize,
        s: &BodyShape,
        cap: Option<(Point<f64>, Point<f64>, f64)>,
        a: &Aabb,
        clearance: &mut Option<f64>,
    ) -> Option<(Reason, String)> {
        let (bed, beads, laid) = (self.bed, self.beads, self.laid);
        // Floor: the links and the hose stay above it.
        if let Some(f) = bed.floor.as_ref().filter(|_| on_floor_check(s)) {
            let c = match &cap {
                Some((ea, eb, r)) => Some(f.axis_clearance(ea, eb, *r)),
                // The box first: most samples keep it above the floor.
                None => Some(f.box_clearance(a))
                    .filter(|c| *c >= 0.0)
                    .or_else(|| f.clearance(&at.iso(i, s), &s.shape)),
            };
            if let Some(c) = c.filter(|c| *c < 0.0) {
                return Some(floor_message(s, i, c));
            }
        }
        // Bed: broad phase on the AABB gap, exact distance only when it could lower the margin.
        let gap = aabb_gap(a, &bed.aabb);
        if gap <= clearance.unwrap_or(f64::INFINITY) {
            let above = match &cap {
                Some((ea, eb, r)) => bed.axis_above(ea, eb, *r),
                None => None,
            };
            let d = match above {
                Some(d) => d,
                None => query::distance(&at.iso(i, s), s.shape.as_ref(), &bed.pose, &bed.cuboid)
                    .unwrap_or(gap),
            };
            *clearance = Some(clearance.map_or(d, |c| c.min(d)));
            if d <= 0.0 {
                return Some((
                    Reason::CollisionBed,
                    format!("{} (shape {i}) meets the bed", s.label),
                ));
            }
        }
        // The hierarchy's root first, here (most shapes miss the part's box); the pose only
        // for a shape other than a capsule (a capsule goes by its axis).
        if !beads.root_meets(a, laid) {
            return None;
        }
        let p = if cap.is_some() {
            Isometry::identity()
        } else {
            at.iso(i, s)
        };
        let b = beads.hit_placed(&p, &s.shape, a, cap, s.local_bound.as_ref(), laid)?;
        Some((
            Reason::CollisionPart,
            format!(
                "{} (shape {i}) comes within {:.3} m of printed bead {b}",
                s.label, beads.radius_m
            ),
        ))
    }
}

/// The self pairs of [`check_with`] among the first `n` shapes: boxes first, then the exact
/// test. The print head's box is that of its bounding sphere (it holds the AABB: when it
/// misses the other shape's box, so would the AABB); only when it meets one is the AABB
/// computed.
#[inline(always)]
fn self_pairs(
    rs: &RobotShapes,
    at: &mut impl ShapePoses,
    n: usize,
    boxes: &mut [Aabb],
    exact: &mut [bool],
) -> Option<(Reason, String)> {
    for &(i, j) in &rs.pairs {
        if i >= n || j >= n || !boxes[i].intersects(&boxes[j]) {
            continue;
        }
        // Mesh pieces: their own boxes turned (a separating-axis test), not their AABBs (one
        // transform per vertex).
        if rs.shapes[i].local_box.is_some() || rs.shapes[j].local_box.is_some() {
            let ob = |k: usize, at: &mut dyn ShapePoses| match rs.shapes[k].local_box {
                Some((c, h)) => {
                    let p = at.iso(k, &rs.shapes[k]);
                    let m = *p.rotation.to_rotation_matrix().matrix();
                    ((p * Point::from(c)).coords, m, h)
                }
                None => (
                    boxes[k].center().coords,
                    Matrix3::identity(),
                    boxes[k].half_extents(),
                ),
            };
            if obb_separated(&ob(i, at), &ob(j, at)) {
                continue;
            }
        }
        for k in [i, j] {
            if !exact[k] && rs.shapes[k].local_box.is_none() {
                let s = &rs.shapes[k];
                boxes[k] = s.shape.compute_aabb(&at.iso(k, s));
                exact[k] = true;
            }
        }
        if !boxes[i].intersects(&boxes[j]) {
            continue;
        }
        let (a, b) = (&rs.shapes[i], &rs.shapes[j]);
        let (pi, pj) = (at.iso(i, a), at.iso(j, b));
        if query::intersection_test(&pi, a.shape.as_ref(), &pj, b.shape.as_ref()).unwrap_or(false) {
            return Some((
                Reason::SelfCollision,
                format!("{} and {} collide", a.label, b.label),
            ));
        }
    }
    None
}

/// [`check`] without its shortcuts (the print head's bounding-sphere box, AABBs shared between
/// the bed and the beads): the plain check that [`check`] is tested against (same arguments, units
/// and result).
#[doc(hidden)]
pub fn check_unfiltered(
    rs: &RobotShapes,
    poses: &[Isometry<f64>],
    bed: &Bed,
    beads: &Beads,
    laid: usize,
    clearance: &mut Option<f64>,
) -> Option<(Reason, String)> {
    let mut aabbs = Vec::with_capacity(poses.len());
    for (s, p) in rs.shapes.iter().zip(poses) {
        aabbs.push(s.shape.compute_aabb(p));
    }
    for (i, (s, p)) in rs.shapes.iter().zip(poses).enumerate() {
        if s.role == Role::Head {
            continue;
        }
        let a = &aabbs[i];
        if let Some(f) = bed.floor.as_ref().filter(|_| on_floor_check(s)) {
            let c = match s.shape.as_capsule() {
                Some(k) => Some(f.axis_clearance(&(p * k.segment.a), &(p * k.segment.b), k.radius)),
                None => f.clearance(p, &s.shape),
            };
            if let Some(c) = c.filter(|c| *c < 0.0) {
                return Some(floor_message(s, i, c));
            }
        }
        // Bed: broad phase on the AABB gap, exact distance only when it could lower the margin.
        let gap = aabb_gap(a, &bed.aabb);
        if gap <= clearance.unwrap_or(f64::INFINITY) {
            let d = match bed.capsule_above(p, &s.shape) {
                Some(d) => d,
                None => query::distance(p, s.shape.as_ref(), &bed.pose, &bed.cuboid).unwrap_or(gap),
            };
            *clearance = Some(clearance.map_or(d, |c| c.min(d)));
            if d <= 0.0 {
                return Some((
                    Reason::CollisionBed,
                    format!("{} (shape {i}) meets the bed", s.label),
                ));
            }
        }
        if let Some(b) = beads.hit(p, &s.shape, laid) {
            return Some((
                Reason::CollisionPart,
                format!(
                    "{} (shape {i}) comes within {:.3} m of printed bead {b}",
                    s.label, beads.radius_m
                ),
            ));
        }
    }
    for &(i, j) in &rs.pairs {
        if !aabbs[i].intersects(&aabbs[j]) {
            continue;
        }
        let (a, b) = (&rs.shapes[i], &rs.shapes[j]);
        if query::intersection_test(&poses[i], a.shape.as_ref(), &poses[j], b.shape.as_ref())
            .unwrap_or(false)
        {
            return Some((
                Reason::SelfCollision,
                format!("{} and {} collide", a.label, b.label),
            ));
        }
    }
    None
}

/// Whether two oriented boxes (centre, axes as the columns of a rotation, half extents; m)
/// are apart, by the separating-axis test over their 15 axes (Gottschalk, Lin and Manocha,
/// "OBBTree", SIGGRAPH 1996), with a small tolerance so that a near touch counts as meeting.
fn obb_separated(
    a: &(Vector<f64>, Matrix3<f64>, Vector<f64>),
    b: &(Vector<f64>, Matrix3<f64>, Vector<f64>),
) -> bool {
    const EPS: f64 = 1e-9;
    let (ca, ra, ha) = a;
    let (cb, rb, hb) = b;
    let r = ra.transpose() * rb;
    let t = ra.transpose() * (cb - ca);
    let ar = r.abs().add_scalar(EPS);
    for i in 0..3 {
        let s = hb[0] * ar[(i, 0)] + hb[1] * ar[(i, 1)] + hb[2] * ar[(i, 2)];
        if t[i].abs() > ha[i] + s + EPS {
            return true;
        }
    }
    for j in 0..3 {
        let s = ha[0] * ar[(0, j)] + ha[1] * ar[(1, j)] + ha[2] * ar[(2, j)];
        let d = t[0] * r[(0, j)] + t[1] * r[(1, j)] + t[2] * r[(2, j)];
        if d.abs() > s + hb[j] + EPS {
            return true;
        }
    }
    for i in 0..3 {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        for j in 0..3 {
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            let sa = ha[i1] * ar[(i2, j)] + ha[i2] * ar[(i1, j)];
            let sb = hb[j1] * ar[(i, j2)] + hb[j2] * ar[(i, j1)];
            let d = t[i2] * r[(i1, j)] - t[i1] * r[(i2, j)];
            if d.abs() > sa + sb + EPS {
                return true;
            }
        }
    }
    false
}

/// The ten directions beside the axes of a 26-sided discrete orientation polytope (k-DOP):
/// the six edge diagonals and the four corner diagonals of a cube, of unit length.
const DOP_DIRS: [[f64; 3]; 10] = {
    const E: f64 = std::f64::consts::FRAC_1_SQRT_2;
    const C: f64 = 0.577_350_269_189_625_8; // 1/√3
    [
        [E, E, 0.0],
        [E, -E, 0.0],
        [E, 0.0, E],
        [E, 0.0, -E],
        [0.0, E, E],
        [0.0, E, -E],
        [C, C, C],
        [C, C, -C],
        [C, -C, C],
        [-C, C, C],
    ]
};

/// Distance beyond the bead radius by which [`PieceBound::apart`] must hold a segment from a
/// piece before the exact distance is skipped, m: far above the rounding of either test, so
/// that a bead the exact distance finds within reach is never skipped.
const DOP_SLACK_M: f64 = 1e-6;

/// A shape's bounds in its own frame: its AABB, and its extent (least and greatest projection)
/// along the ten [`DOP_DIRS`]: with the AABB, a 26-sided polytope that holds the shape. A mesh
/// piece near the print (a wrist, a tool flange) is often a rounded or slanted body that fills
/// the corners of its box poorly; the diagonal planes prove most beads near the box out of
/// reach with 20 dot products, where the exact distance (GJK) takes several scans of the
/// piece's vertices.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PieceBound {
    aabb: Aabb,
    dop: [(f64, f64); 10],
}

impl PieceBound {
    /// The bounds of a convex hull's vertices (`aabb`: their box).
    fn of_points(aabb: Aabb, points: &[Point<f64>]) -> PieceBound {
        let mut dop = [(f64::INFINITY, f64::NEG_INFINITY); 10];
        for p in points {
            for (d, u) in dop.iter_mut().zip(&DOP_DIRS) {
                let s = u[0] * p.x + u[1] * p.y + u[2] * p.z;
                *d = (d.0.min(s), d.1.max(s));
            }
        }
        PieceBound { aabb, dop }
    }

    /// The bounds of a box (its corners: the polytope holds whatever the box holds).
    fn of_aabb(aabb: &Aabb) -> PieceBound {
        PieceBound {
            dop: PieceBound::of_points(*aabb, &aabb.vertices()).dop,
            aabb: *aabb,
        }
    }

    /// The segment `a`–`b` (the shape's frame, m) lies `r` + [`DOP_SLACK_M`] or more beyond
    /// one of the diagonal planes: no point of it comes within `r` of the shape.
    #[inline(always)]
    fn apart(&self, a: &Point<f64>, b: &Point<f64>, r: f64) -> bool {
        let reach = r + DOP_SLACK_M;
        self.dop.iter().zip(&DOP_DIRS).any(|(&(lo, hi), u)| {
            let sa = u[0] * a.x + u[1] * a.y + u[2] * a.z;
            let sb = u[0] * b.x + u[1] * b.y + u[2] * b.z;
            sa.min(sb) - hi >= reach || lo - sa.max(sb) >= reach
        })
    }
}

/// A box of a shape's own frame turned to a pose (part frame): centre, axes and half extents.
struct Turned {
    centre: Vector<f64>,
    axes: [Vector<f64>; 3],
    half: Vector<f64>,
}

impl Turned {
    fn new(pose: &Isometry<f64>, local: &Aabb) -> Self {
        let r = pose.rotation.to_rotation_matrix();
        let m = r.matrix();
        Turned {
            centre: (pose * local.center()).coords,
            axes: [
                m.column(0).into_owned(),
                m.column(1).into_owned(),
                m.column(2).into_owned(),
            ],
            half: local.half_extents(),
        }
    }

    /// The turned box and `b` lie apart along one of the turned box's axes (a separating
    /// axis: no point is in both). `false` when they may meet.
    #[inline(always)]
    fn apart(&self, b: &Aabb) -> bool {
        let (c, h) = (b.center().coords, b.half_extents());
        let d = self.centre - c;
        self.axes.iter().zip(self.half.iter()).any(|(u, e)| {
            let reach = h.x * u.x.abs() + h.y * u.y.abs() + h.z * u.z.abs();
            u.dot(&d).abs() > e + reach
        })
    }
}

/// Distance between two AABBs, m (0 when they overlap).
fn aabb_gap(a: &Aabb, b: &Aabb) -> f64 {
    let mut s = 0.0;
    for k in 0..3 {
        let d = (b.mins[k] - a.maxs[k]).max(a.mins[k] - b.maxs[k]).max(0.0);
        s += d * d;
    }
    s.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use parry3d_f64::shape::ConvexPolyhedron;
    use rand::{Rng, SeedableRng};

    /// The first laid bead within reach of `shape`, by looking at every bead in turn.
    fn hit_each(
        b: &Beads,
        pose: &Isometry<f64>,
        shape: &SharedShape,
        laid: usize,
    ) -> Option<usize> {
        (0..laid.min(b.len())).find(|&i| {
            query::distance(pose, shape.as_ref(), &Isometry::identity(), &b.segs[i])
                .is_ok_and(|d| d < b.radius_m)
        })
    }

    #[test]
    fn the_bead_hierarchy_finds_the_first_laid_bead_that_checking_every_bead_finds() {
        // A 40-layer rectangular wall (1.0 × 0.4 m, 10 mm layers), beads every 5 samples.
        let mut p = Vec::new();
        let corners = [
            (-0.5, -0.2),
            (0.5, -0.2),
            (0.5, 0.2),
            (-0.5, 0.2),
            (-0.5, -0.2),
        ];
        for layer in 0..40 {
            let z = 0.01 * (layer + 1) as f64;
            for w in corners.windows(2) {
                for k in 0..50 {
                    let t = k as f64 / 50.0;
                    let (x, y) = (
                        w[0].0 + t * (w[1].0 - w[0].0),
                        w[0].1 + t * (w[1].1 - w[0].1),
                    );
                    p.push(V3::new(x, y, z));
                }
            }
        }
        // Travel between layers does not print: every 200th sample.
        let print: Vec<bool> = (0..p.len()).map(|k| k % 200 != 0).collect();
        let beads = Beads::new(&p, &print, 5, BEAD_RADIUS_M);
        assert!(
            beads.len() > 1000 && beads.nodes.len() > 200,
            "{}",
            beads.len()
        );
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(12);
        let shapes = [
            SharedShape::ball(0.05),
            SharedShape::capsule_z(0.3, 0.06),
            SharedShape::cuboid(0.2, 0.05, 0.1),
        ];
        let (mut hits, mut misses) = (0, 0);
        for _ in 0..3000 {
            let s = &shapes[rng.gen_range(0..shapes.len())];
            let pose = Isometry::new(
                Vector::new(
                    rng.gen_range(-0.7..0.7),
                    rng.gen_range(-0.4..0.4),
                    rng.gen_range(-0.1..0.6),
                ),
                Vector::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), 0.0),
            );
            let laid = rng.gen_range(0..=beads.len() + 2);
            let want = hit_each(&beads, &pose, s, laid);
            assert_eq!(beads.hit(&pose, s, laid), want, "{pose:?} laid {laid}");
            if want.is_some() {
                hits += 1
            } else {
                misses += 1
            }
        }
        // Both outcomes are exercised.
        assert!(hits > 300 && misses > 300, "{hits} hits, {misses} misses");
        // No beads at all: nothing to hit, whatever `laid` says.
        let none = Beads::new(&p[..10], &[false; 10], 5, BEAD_RADIUS_M);
        assert_eq!(none.hit(&Isometry::identity(), &shapes[0], 3), None);
    }

    /// The 26-sided bound of a mesh piece never proves a bead out of reach that the exact
    /// distance finds within reach (random convex hulls, random segments near them, many
    /// within a hair of the bead radius), and it does prove most far beads out of reach.
    #[test]
    fn the_piece_bound_never_skips_a_bead_the_exact_distance_finds_within_reach() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(26);
        let r = BEAD_RADIUS_M;
        let (mut near, mut far, mut skipped_far) = (0, 0, 0);
        for _ in 0..400 {
            // A hull of 40 random points in a slanted, elongated cloud (a link piece).
            let (a, b, c) = (
                rng.gen_range(0.02..0.3),
                rng.gen_range(0.02..0.1),
                rng.gen_range(0.02..0.1),
            );
            let rot = UnitQuaternion::from_euler_angles(
                rng.gen_range(-3.2..3.2),
                rng.gen_range(-1.6..1.6),
                rng.gen_range(-3.2..3.2),
            );
            let pts: Vec<Point<f64>> = (0..40)
                .map(|_| {
                    rot * Point::new(
                        rng.gen_range(-a..a),
                        rng.gen_range(-b..b),
                        rng.gen_range(-c..c),
                    )
                })
                .collect();
            let Some(hull) = ConvexPolyhedron::from_convex_hull(&pts) else {
                continue;
            };
            let bound = PieceBound::of_points(hull.local_aabb(), hull.points());
            for _ in 0..100 {
                let mut pt = || {
                    Point::new(
                        rng.gen_range(-0.5..0.5),
                        rng.gen_range(-0.5..0.5),
                        rng.gen_range(-0.5..0.5),
                    )
                };
                let (mut sa, mut sb) = (pt(), pt());
                // Half the segments moved to within a hair of the bead radius of the hull.
                if rng.gen_bool(0.5) {
                    let seg = Segment::new(sa, sb);
                    let id = Isometry::identity();
                    let d = query::distance(&id, &hull, &id, &seg).unwrap();
                    if d > 0.0 {
                        let cp = query::closest_points(&id, &hull, &id, &seg, f64::MAX).unwrap();
                        if let query::ClosestPoints::WithinMargin(p1, p2) = cp {
                            let shift =
                                (p1 - p2).normalize() * (d - r + rng.gen_range(-1e-7..1e-7));
                            sa += shift;
                            sb += shift;
                        }
                    }
                }
                let seg = Segment::new(sa, sb);
                let id = Isometry::identity();
                let d = query::distance(&id, &hull, &id, &seg).unwrap();
                let skipped = bound.apart(&sa, &sb, r);
                assert!(
                    !(skipped && d < r),
                    "a bead at {d} m (radius {r} m) skipped: {sa:?} {sb:?}"
                );
                if d < r {
                    near += 1;
                } else if d > r + 0.05 {
                    far += 1;
                    skipped_far += usize::from(skipped);
                }
            }
        }
        assert!(near > 5000 && far > 5000, "{near} near, {far} far");
        assert!(
            skipped_far * 10 > far * 6,
            "{skipped_far} of {far} beads far out of reach skipped"
        );
    }

    /// The print head's pose and box at a nozzle-tip point, its turned box found once and
    /// moved, are those of the pose made from the tip's frame and parry's `compute_aabb`,
    /// bit for bit, for any spin and any point.
    #[test]
    fn the_heads_moved_box_is_parrys_box_at_its_pose_bit_for_bit() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let model = crate::robot::load(&root.join("robots/abb_irb6700_200_260")).unwrap();
        let head = HeadOverPart::new(&model, 2.6, &LinkRadii::default(), 0.05).unwrap();
        let mut rng = rand::rngs::StdRng::seed_from_u64(5);
        for _ in 0..200 {
            let spin = rng.gen_range(-7.0..7.0);
            let placed = head.placed(spin);
            let rot = crate::kinematics::nozzle_target(&V3::zeros(), spin).rot;
            for _ in 0..50 {
                let tip = V3::new(
                    rng.gen_range(-3.0..3.0),
                    rng.gen_range(-3.0..3.0),
                    rng.gen_range(-0.5..2.5),
                );
                let pose = iso(&Frame { rot, pos: tip }) * head.local;
                let (p, b) = placed(&tip);
                assert_eq!(p, pose);
                let want = head.shape.compute_aabb(&pose);
                for d in 0..3 {
                    assert_eq!(
                        b.mins[d].to_bits(),
                        want.mins[d].to_bits(),
                        "{spin} {tip:?}"
                    );
                    assert_eq!(
                        b.maxs[d].to_bits(),
                        want.maxs[d].to_bits(),
                        "{spin} {tip:?}"
                    );
                }
            }
        }
    }

    /// A head that is a cylinder about the nozzle axis meets the part at the same sample and
    /// bead whatever the spin (so it is checked once, at spin 0); a tool offset from the
    /// flange's axis makes the spin matter.
    #[test]
    fn a_head_about_the_nozzle_axis_meets_the_part_where_it_does_at_every_spin() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut model = crate::robot::load(&root.join("robots/abb_irb6700_200_260")).unwrap();
        let radii = LinkRadii::default();
        let head = HeadOverPart::new(&model, 2.6, &radii, 0.05).unwrap();
        assert!(head.spin_free);
        assert_eq!(head.spin_checked(1.3), 0.0);
        // Layers along x at 20 mm, each next one started lower and lower: the head, 50 mm and
        // more above the tip, comes down onto the beads laid before.
        let mut p = Vec::new();
        for layer in 0..6 {
            let z = 0.3 - 0.03 * layer as f64;
            for k in 0..400 {
                let x = if layer % 2 == 0 { k } else { 399 - k } as f64 * 0.0025;
                p.push(V3::new(x, 0.02 * layer as f64, z));
            }
        }
        let print = vec![true; p.len()];
        let beads = Beads::new(&p, &print, 10, BEAD_RADIUS_M);
        let at0 = head.first_hit(&beads, &p, 0.0);
        assert!(at0.is_some());
        let mut rng = rand::rngs::StdRng::seed_from_u64(3);
        for _ in 0..20 {
            let spin = rng.gen_range(-7.0..7.0);
            let hit = head.first_hit(&beads, &p, spin);
            assert_eq!(
                hit.as_ref().map(|h| (h.sample, h.bead)),
                at0.as_ref().map(|h| (h.sample, h.bead)),
                "{spin}"
            );
        }
        // A nozzle 80 mm to the side of the flange's axis: the spin matters.
        model.tool.pos.x += 0.08;
        let offset = HeadOverPart::new(&model, 2.6, &radii, 0.05).unwrap();
        assert!(!offset.spin_free);
        assert_eq!(offset.spin_checked(1.3), 1.3);
    }

    /// The oriented-box prefilter of the self pairs never calls two meeting boxes apart, and
    /// calls most apart boxes apart: against parry's exact cuboid test on random boxes.
    #[test]
    fn the_oriented_box_test_never_separates_boxes_that_meet() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let (mut apart, mut called_apart) = (0, 0);
        for _ in 0..20_000 {
            let mut obb = || {
                let h = Vector::new(
                    rng.gen_range(0.01..0.5),
                    rng.gen_range(0.01..0.5),
                    rng.gen_range(0.01..0.5),
                );
                let c = Vector::new(
                    rng.gen_range(-0.8..0.8),
                    rng.gen_range(-0.8..0.8),
                    rng.gen_range(-0.8..0.8),
                );
                let r = UnitQuaternion::from_euler_angles(
                    rng.gen_range(-3.2..3.2),
                    rng.gen_range(-1.6..1.6),
                    rng.gen_range(-3.2..3.2),
                );
                (Isometry::from_parts(Translation::from(c), r), h)
            };
            let ((pa, ha), (pb, hb)) = (obb(), obb());
            let boxed = |p: &Isometry<f64>, h: Vector<f64>| {
                (
                    p.translation.vector,
                    *p.rotation.to_rotation_matrix().matrix(),
                    h,
                )
            };
            let sep = obb_separated(&boxed(&pa, ha), &boxed(&pb, hb));
            let meet =
                query::intersection_test(&pa, &Cuboid::new(ha), &pb, &Cuboid::new(hb)).unwrap();
            assert!(
                !(meet && sep),
                "boxes that meet called apart: {pa:?} {ha:?} {pb:?} {hb:?}"
            );
            apart += usize::from(!meet);
            called_apart += usize::from(sep);
        }
        // The 15 axes decide exactly for boxes: every pair apart is found apart.
        assert!(apart > 1000, "{apart}");
        assert_eq!(called_apart, apart);
    }
}
