//! The immutable robot model: a serial chain of actuated joints with the inertia of each link,
//! the flange and tool frames, the payload and the optional drive data.
//!
//! Conventions (the URDF's): the frame of joint `i` is the frame of its child link. At `q_i = 0`
//! it sits at `joints[i].origin` in the frame of joint `i-1` (the base frame for `i = 0`); the
//! joint then rotates (revolute, rad) or slides (prismatic, m) about/along `joints[i].axis`,
//! given in its own frame. Link `i` is the rigid body carried by joint `i`, with every fixed
//! descendant merged in.

use crate::math::{rot_axis, Frame, M3, V3};
use crate::robot::drive::Drive;
use crate::robot::opw::OpwParams;
use std::path::PathBuf;

/// Revolute (angle in rad) or prismatic (displacement in m).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointKind {
    /// Rotation about the axis, q in rad.
    Revolute,
    /// Translation along the axis, q in m.
    Prismatic,
}

/// One actuated joint of the chain.
#[derive(Clone, Debug)]
pub struct Joint {
    /// URDF joint name.
    pub name: String,
    /// Revolute or prismatic.
    pub kind: JointKind,
    /// Frame of this joint at q = 0 in the frame of the previous joint (base frame for joint 0).
    pub origin: Frame,
    /// Unit axis in this joint's frame.
    pub axis: V3,
    /// Lower position limit, rad (m for prismatic); `-inf` for continuous joints.
    pub lower: f64,
    /// Upper position limit, rad (m for prismatic); `+inf` for continuous joints.
    pub upper: f64,
    /// Velocity limit, rad/s (m/s); `+inf` when unknown.
    pub velocity_limit: f64,
    /// Acceleration limit, rad/s² (m/s²); `+inf` when unknown (from the drive file).
    pub acceleration_limit: f64,
    /// Jerk limit, rad/s³ (m/s³); `+inf` when unknown (from the drive file).
    pub jerk_limit: f64,
    /// Effort limit, N·m (N); `None` when the URDF gives 0 or nothing.
    pub effort_limit: Option<f64>,
}

impl Joint {
    /// Transform of this joint's frame in the previous joint's frame at position `q`.
    #[inline]
    pub(crate) fn transform(&self, q: f64) -> Frame {
        match self.kind {
            JointKind::Revolute => Frame {
                rot: self.origin.rot * rot_axis(&self.axis, q),
                pos: self.origin.pos,
            },
            JointKind::Prismatic => Frame {
                rot: self.origin.rot,
                pos: self.origin.pos + self.origin.rot * (self.axis * q),
            },
        }
    }

    /// Whether `q` lies within the position limits (inclusive, with `tol`).
    pub fn within_limits(&self, q: f64, tol: f64) -> bool {
        q >= self.lower - tol && q <= self.upper + tol
    }
}

/// Mass properties of a rigid body, expressed in some frame F.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inertial {
    /// Mass, kg.
    pub mass: f64,
    /// Centre of mass in F, m.
    pub com: V3,
    /// Inertia tensor about the centre of mass, axes of F, kg·m².
    pub inertia: M3,
}

impl Inertial {
    /// A body of zero mass.
    pub fn zero() -> Self {
        Inertial {
            mass: 0.0,
            com: V3::zeros(),
            inertia: M3::zeros(),
        }
    }

    /// The same body expressed in the parent frame of `f` (`f` maps F to the parent).
    pub(crate) fn transformed(&self, f: &Frame) -> Inertial {
        Inertial {
            mass: self.mass,
            com: f.apply(&self.com),
            inertia: f.rot * self.inertia * f.rot.transpose(),
        }
    }

    /// Inertia tensor about the frame origin, kg·m² (parallel-axis theorem).
    pub(crate) fn inertia_about_origin(&self) -> M3 {
        let c = self.com;
        self.inertia + self.mass * (M3::identity() * c.dot(&c) - c * c.transpose())
    }

    /// Two rigid bodies in the same frame merged into one.
    pub fn merged(&self, other: &Inertial) -> Inertial {
        let m = self.mass + other.mass;
        if m <= 0.0 {
            // Massless bodies may still carry rotational inertia (published PUMA data do).
            return Inertial {
                mass: 0.0,
                com: V3::zeros(),
                inertia: self.inertia_about_origin() + other.inertia_about_origin(),
            };
        }
        let com = (self.com * self.mass + other.com * other.mass) / m;
        let about_origin = self.inertia_about_origin() + other.inertia_about_origin();
        let shifted = about_origin - m * (M3::identity() * com.dot(&com) - com * com.transpose());
        Inertial {
            mass: m,
            com,
            inertia: shifted,
        }
    }
}

/// Facts about the robot from the drive file's `[robot]` table.
#[derive(Clone, Debug, Default)]
pub struct RobotInfo {
    /// Display name, e.g. "ABB IRB 6700-200/2.60".
    pub name: String,
    /// Datasheet reach, m.
    pub reach_m: Option<f64>,
    /// Rated payload, kg.
    pub rated_payload_kg: Option<f64>,
    /// The robot's mass as its datasheet states it (base and arm, without payload), kg; the
    /// link masses estimated from geometry are scaled to it
    /// ([`crate::robot::inertia::complete`]).
    pub mass_kg: Option<f64>,
    /// One line on where the numbers come from.
    pub provenance: String,
    /// What the default payload is (extruder, hose, material), from the drive file.
    pub payload_description: Option<String>,
    /// Per-joint position margin from the limits for placement searches, rad (drive file
    /// `limit_margin_rad`; `None` = the command's default).
    pub limit_margins_rad: Vec<Option<f64>>,
    /// Height of the pedestal (plinth) the base stands on, m (drive file
    /// `pedestal_height_m`; 0 = the base stands on the floor). The floor is this far below the
    /// base frame's origin.
    pub pedestal_height_m: f64,
    /// Radius of the pedestal, a cylinder about the base frame's z axis, m (drive file
    /// `pedestal_radius_m`).
    pub pedestal_radius_m: f64,
    /// Where each moving link's inertia comes from (chain order; filled when the robot is
    /// loaded, [`crate::robot::inertia::complete`]).
    pub inertia_sources: Vec<crate::robot::inertia::InertiaSource>,
    /// The drive file the robot was loaded with, if any.
    pub drive_file: Option<std::path::PathBuf>,
    /// How many of the drive file's drive-train and cabinet values (`[[joints]]` gear ratio,
    /// torque constant, winding resistance, rotor inertia, friction, gear efficiency;
    /// `[cabinet]` standby power) are marked `ESTIMATE` in their comments, of how many given:
    /// `(estimated, given)`.
    pub drive_estimates: Option<(usize, usize)>,
}

/// The immutable robot model. Build it with [`crate::robot::load`].
#[derive(Clone, Debug)]
pub struct RobotModel {
    /// Name, provenance, reach, rated payload.
    pub info: RobotInfo,
    /// Where the model was loaded from (the URDF, or the robot directory).
    pub source: PathBuf,
    /// Actuated joints in chain order.
    pub joints: Vec<Joint>,
    /// Name of the link carried by each joint (the first link, fixed children merged into it).
    pub link_names: Vec<String>,
    /// Mass properties of link `i` in the frame of joint `i`; `None` where the URDF has no
    /// `<inertial>` for the link or any link merged into it.
    pub links: Vec<Option<Inertial>>,
    /// The flange (`tool_link`) frame in the last joint's frame.
    pub flange: Frame,
    /// Name of the flange link.
    pub flange_link: String,
    /// The nozzle tip (tool centre point) in the flange frame; the nozzle points along its +z.
    pub tool: Frame,
    /// Payload at the flange (extruder, hose, material) in the flange frame, if any.
    pub payload: Option<Inertial>,
    /// Gravity in the base frame, m/s².
    pub gravity: V3,
    /// Drive data (gear ratios, motors, friction, cabinet); `None` = rigid body only.
    pub drive: Option<Drive>,
    /// The drive file's `[effects]` and `[calibration]` tables as data; the effects read them
    /// (one registry for [`crate::identify`] and [`crate::energy`]); default when there are none.
    pub effects: crate::robot::drive::EffectsData,
    /// Closed-form (OPW) kinematic parameters, when the arm is ortho-parallel with a spherical
    /// wrist and the drive file names them. Checked against the URDF chain on load.
    pub opw: Option<OpwParams>,
    /// Collision geometry of the fixed base (the root link and links fixed to it), base frame;
    /// empty when the URDF gives none.
    pub base_collision: Vec<CollisionGeom>,
    /// Collision geometry of link `i` (fixed children merged) in the frame of joint `i`; an
    /// empty entry means the URDF gives none for that link (a capsule stands in for it).
    pub link_collision: Vec<Vec<CollisionGeom>>,
    /// Visual geometry of each moving link that has neither an inertial nor collision geometry
    /// in the URDF (link frame; empty otherwise): what its inertia is estimated from then.
    pub link_visual: Vec<Vec<CollisionGeom>>,
    /// What the URDF's `<visual>` elements draw, for the view (the planner never uses them).
    pub visuals: Visuals,
    /// Print head and hose from the drive file's `[tool.geometry]`, if given.
    pub tool_geometry: Option<ToolGeometry>,
    /// Things the loader noticed and accepted (ignored meshes, merged passive joints, ...).
    pub warnings: Vec<String>,
}

/// One `<collision>` element of a URDF link.
#[derive(Clone, Debug, PartialEq)]
pub struct CollisionGeom {
    /// Pose of the shape in its link (or joint) frame.
    pub origin: Frame,
    /// The shape.
    pub shape: GeomShape,
}

/// A collision shape in its own frame (URDF conventions: boxes centred, cylinders along z).
#[derive(Clone, Debug, PartialEq)]
pub enum GeomShape {
    /// Box with the given full edge lengths, m.
    Box {
        /// Edge lengths along x, y, z, m.
        size_m: [f64; 3],
    },
    /// Cylinder along z, centred.
    Cylinder {
        /// Radius, m.
        radius_m: f64,
        /// Length along z, m.
        length_m: f64,
    },
    /// Sphere, centred.
    Sphere {
        /// Radius, m.
        radius_m: f64,
    },
    /// Vertices of a mesh (already scaled, m); used as its convex hull.
    Hull {
        /// Vertices, m, in the shape frame.
        points: Vec<V3>,
        /// The mesh file it came from.
        source: String,
    },
}

/// The URDF's `<visual>` elements of the chain's bodies, for drawing only: the fixed base
/// (the root link and links fixed to it, base frame) and each moving link (fixed children
/// merged, frame of its joint). Mesh files are found the way collision meshes are but not read.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Visuals {
    /// Visual elements of the fixed base, base frame.
    pub base: Vec<VisualGeom>,
    /// Visual elements of link `i`, frame of joint `i` (empty: the link has none).
    pub links: Vec<Vec<VisualGeom>>,
    /// Visual elements left out, and why (a mesh not found, a format not drawn, bad sizes).
    pub skipped: Vec<String>,
}

/// One `<visual>` element of a URDF link.
#[derive(Clone, Debug, PartialEq)]
pub struct VisualGeom {
    /// Pose of the geometry in its body frame.
    pub origin: Frame,
    /// The geometry.
    pub shape: VisualShape,
    /// The URDF link it belongs to.
    pub link: String,
}

/// The geometry of a `<visual>` element (URDF conventions: boxes centred, cylinders along z).
#[derive(Clone, Debug, PartialEq)]
pub enum VisualShape {
    /// Box with the given full edge lengths, m.
    Box {
        /// Edge lengths along x, y, z, m.
        size_m: [f64; 3],
    },
    /// Cylinder along z, centred.
    Cylinder {
        /// Radius, m.
        radius_m: f64,
        /// Length along z, m.
        length_m: f64,
    },
    /// Sphere, centred.
    Sphere {
        /// Radius, m.
        radius_m: f64,
    },
    /// A mesh file (STL, COLLADA `.dae` or Wavefront OBJ) found inside the URDF's directory or
    /// inside the ROS package a `package://` name points into.
    Mesh {
        /// The `filename` as the URDF writes it.
        filename: String,
        /// The file, canonical.
        path: PathBuf,
        /// `stl`, `dae` or `obj`.
        format: String,
        /// The URDF's `scale`.
        scale: [f64; 3],
    },
}

/// Print head and hose, from the drive file's `[tool.geometry]` table (flange frame, m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToolGeometry {
    /// Print head: a cylinder around the flange → nozzle-tip axis, radius in m.
    pub head_radius_m: f64,
    /// Hose: capsule radius, m (0 = no hose).
    pub hose_radius_m: f64,
    /// Hose start in the flange frame, m.
    pub hose_from_m: [f64; 3],
    /// Hose end in the flange frame, m (the hose is modelled as a straight capsule to the
    /// point where it is tied to the arm).
    pub hose_to_m: [f64; 3],
}

impl RobotModel {
    /// Number of actuated joints.
    pub fn dof(&self) -> usize {
        self.joints.len()
    }

    /// Display name.
    pub fn name(&self) -> &str {
        &self.info.name
    }

    /// The mass properties of every link in its joint frame, with the payload merged into the
    /// last link when `with_payload`, or the error naming the first link without `<inertial>`.
    pub(crate) fn dynamic_links(&self, with_payload: bool) -> crate::error::Result<Vec<Inertial>> {
        let mut out = Vec::with_capacity(self.links.len());
        for (i, l) in self.links.iter().enumerate() {
            match l {
                Some(l) => out.push(*l),
                None => {
                    return Err(crate::error::Error::MissingInertial {
                        file: self.source.display().to_string(),
                        link: self.link_names[i].clone(),
                    })
                }
            }
        }
        if with_payload {
            if let (Some(p), Some(last)) = (self.payload, out.last_mut()) {
                *last = last.merged(&p.transformed(&self.flange));
            }
        }
        Ok(out)
    }

    /// Total mass of the moving links, kg (links without inertial count as 0).
    pub fn moving_mass(&self) -> f64 {
        self.links.iter().flatten().map(|l| l.mass).sum()
    }

    /// Check a joint vector's length against the robot, naming `what` in the error.
    pub(crate) fn check_len(&self, what: &str, len: usize) -> crate::error::Result<()> {
        if len != self.dof() {
            return Err(crate::error::Error::SizeMismatch {
                what: format!("{what} for robot `{}`", self.name()),
                got: len,
                expected: self.dof(),
            });
        }
        Ok(())
    }
}
