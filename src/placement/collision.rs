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
//!   capsule of radius `nozzle × R` from the flange to the tip and there is no hose. The head is
//!   exempt from the bed and part checks (it prints on them).
//! - **Bed**: a cuboid under the path (see [`super::feasibility::World`]).
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

use super::feasibility::{LinkRadii, Reason};
use crate::kinematics::fk::fk;
use crate::math::{Frame, V3};
use crate::robot::{GeomShape, RobotModel};
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::{Isometry, Point, Translation, Vector};
use parry3d_f64::na::{Rotation3, UnitQuaternion};
use parry3d_f64::query;
use parry3d_f64::shape::{Capsule, Cuboid, Cylinder, Segment, SharedShape};

/// Bead radius of the printed part, m (ESTIMATE: a 40 mm wide concrete bead, typical of 3DCP).
pub const BEAD_RADIUS_M: f64 = 0.02;

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
        BodyShape {
            body,
            local,
            shape,
            role,
            label,
            bound: (b.center, b.radius),
            at_origin: local == Isometry::identity(),
            capsule,
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
}

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

impl RobotShapes {
    /// Build the shapes of `model`; `reach` scales the fallback capsules and the default head.
    pub fn new(model: &RobotModel, reach: f64, radii: &LinkRadii) -> Self {
        let n = model.joints.len();
        let mut shapes = Vec::new();
        let mut with_urdf = 0;
        let mut add_urdf = |body: usize, name: &str, geoms: &[crate::robot::CollisionGeom]| {
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
        };
        let base_name = "base".to_string();
        let base_has = add_urdf(0, &base_name, &model.base_collision);
        let mut has = vec![false; n];
        for (i, h) in has.iter_mut().enumerate() {
            let name = model.link_names.get(i).map_or("?", String::as_str);
            if let Some(g) = model.link_collision.get(i) {
                *h = add_urdf(i + 1, name, g);
                if *h {
                    with_urdf += 1;
                }
            }
        }
        // Capsules where the URDF gives nothing: base → joint 1, joint i → joint i+1 (or flange).
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
        // Print head and hose (flange frame).
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
        // Allowed-collision matrix at the home pose.
        let mut rs = RobotShapes {
            shapes,
            pairs: Vec::new(),
            links_with_urdf_geometry: with_urdf,
        };
        let home = rs.poses(model, &vec![0.0; n], &Isometry::identity());
        for i in 0..rs.shapes.len() {
            for j in i + 1..rs.shapes.len() {
                let (a, b) = (&rs.shapes[i], &rs.shapes[j]);
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
                    rs.pairs.push((i, j));
                }
            }
        }
        rs
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
    pub fn with_prior(
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

    /// Number of beads finished at or before sample `k`.
    pub fn laid_at(&self, k: usize) -> usize {
        self.done_at.partition_point(|&d| d <= k)
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
    pub fn hit_within(
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
        self.hit_placed(pose, shape, aabb, cap, laid)
    }

    /// [`Beads::hit_within`] with, for a capsule, its axis's ends at `pose` and its radius
    /// already known (`cap`: `pose * a`, `pose * b`, part frame, m; radius, m).
    fn hit_placed(
        &self,
        pose: &Isometry<f64>,
        shape: &SharedShape,
        aabb: &Aabb,
        cap: Option<(Point<f64>, Point<f64>, f64)>,
        laid: usize,
    ) -> Option<usize> {
        if laid == 0 || self.nodes.is_empty() {
            return None;
        }
        let aabb = *aabb;
        let cap_id = Isometry::identity();
        // A capsule (every link without URDF geometry) against a bead segment in closed form
        // (segment–segment closest points, Ericson's method as parry implements it) instead of
        // parry's general GJK dispatch: same distance, a fraction of the cost.
        let touches = |i: usize| {
            let seg = &self.segs[i];
            let d = match &cap {
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
                    query::distance(pose, shape.as_ref(), &cap_id, seg).unwrap_or(f64::INFINITY)
                }
            };
            d < self.radius_m
        };
        // The root first: most shapes (the base, the upper arm) miss the part's box.
        let root = &self.nodes[0];
        if root.start as usize >= laid || !root.aabb.intersects(&aabb) {
            return None;
        }
        // Depth-first, lower indices first: the first bead found is the first laid.
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let nd = &self.nodes[stack[top] as usize];
            if nd.start as usize >= laid || !nd.aabb.intersects(&aabb) {
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
    const ON_STACK: usize = 16;
    let n = rs.shapes.len().min(poses.len());
    let none = Aabb::new_invalid();
    if n <= ON_STACK {
        let (mut boxes, mut exact) = ([none; ON_STACK], [false; ON_STACK]);
        check_with(
            rs,
            poses,
            bed,
            beads,
            laid,
            clearance,
            &mut boxes[..n],
            &mut exact[..n],
        )
    } else {
        let (mut boxes, mut exact) = (vec![none; n], vec![false; n]);
        check_with(
            rs, poses, bed, beads, laid, clearance, &mut boxes, &mut exact,
        )
    }
}

/// Margin added to a bounding sphere's radius before its box stands in for a shape's AABB, m
/// (against rounding in the sphere's centre; a larger box only makes the test looser).
pub const SPHERE_MARGIN_M: f64 = 1e-6;

/// [`check`] with `boxes` and `exact` (one per shape) as scratch for the shapes' boxes: the
/// AABB (`exact`), or a box that holds it.
#[allow(clippy::too_many_arguments)]
fn check_with(
    rs: &RobotShapes,
    poses: &[Isometry<f64>],
    bed: &Bed,
    beads: &Beads,
    laid: usize,
    clearance: &mut Option<f64>,
    boxes: &mut [Aabb],
    exact: &mut [bool],
) -> Option<(Reason, String)> {
    for (i, (s, p)) in rs.shapes.iter().zip(poses).enumerate() {
        if s.role == Role::Head {
            let (c, r) = s.bound;
            let (c, r) = (p * c, r + SPHERE_MARGIN_M);
            boxes[i] = Aabb::new(c - Vector::repeat(r), c + Vector::repeat(r));
            exact[i] = false;
            continue;
        }
        // A capsule's axis at its pose, once for its AABB (as parry makes it), the bed and the
        // beads.
        let cap = s
            .capsule
            .map(|c| (p * c.segment.a, p * c.segment.b, c.radius));
        let a = match &cap {
            Some((ea, eb, r)) => Capsule::new(*ea, *eb, *r).local_aabb(),
            None => s.shape.compute_aabb(p),
        };
        (boxes[i], exact[i]) = (a, true);
        // Bed: broad phase on the AABB gap, exact distance only when it could lower the margin.
        let gap = aabb_gap(&a, &bed.aabb);
        if gap <= clearance.unwrap_or(f64::INFINITY) {
            let above = match &cap {
                Some((ea, eb, r)) => bed.axis_above(ea, eb, *r),
                None => None,
            };
            let d = match above {
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
        if let Some(b) = beads.hit_placed(p, &s.shape, &a, cap, laid) {
            return Some((
                Reason::CollisionPart,
                format!(
                    "{} (shape {i}) comes within {:.3} m of printed bead {b}",
                    s.label, beads.radius_m
                ),
            ));
        }
    }
    // Self pairs: boxes first, then the exact test. The print head's box is that of its
    // bounding sphere (it holds the AABB: when it misses the other shape's box, so would the
    // AABB); only when it meets one is the AABB computed.
    for &(i, j) in &rs.pairs {
        if !boxes[i].intersects(&boxes[j]) {
            continue;
        }
        for k in [i, j] {
            if !exact[k] {
                boxes[k] = rs.shapes[k].shape.compute_aabb(&poses[k]);
                exact[k] = true;
            }
        }
        if !boxes[i].intersects(&boxes[j]) {
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
}
