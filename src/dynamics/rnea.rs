//! Model, workspace and algorithms. See the module docs in `dynamics/mod.rs`.

use crate::error::{Error, Result};
use crate::math::{rot_axis, M3, V3};
use crate::robot::{JointKind, RobotModel};

/// Largest number of joints a [`DynModel`] supports (workspace arrays are this size).
pub const MAX_DOF: usize = 8;

/// What to include in a [`DynModel`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DynOptions {
    /// Merge the robot's payload (mass, CoM, inertia at the flange) into the last link.
    pub payload: bool,
    /// Add the reflected rotor inertia `G²·J_m` (kg·m², joint side) of each drive as a diagonal
    /// term `G²J_m q̈` (the `armature` effect). Needs drive data; a robot without a drive gets
    /// zero armature and [`DynModel::has_armature`] reports `false`.
    pub armature: bool,
}

/// Precomputed per-link parameters in the re-oriented joint frame (axis = local +z).
#[derive(Clone, Copy, Debug)]
pub(super) struct Link {
    /// Constant part of the rotation child → parent: `R(q) = c · Rz(q)` (revolute) or `c`.
    pub(super) c: M3,
    /// Joint origin in the parent frame at q = 0, m.
    pub(super) p: V3,
    /// Prismatic joint (translation along local z).
    pub(super) prismatic: bool,
    /// Mass, kg.
    pub(super) mass: f64,
    /// First moment of mass `m·c` about the joint origin, kg·m.
    pub(super) h: V3,
    /// Inertia about the joint origin, kg·m².
    pub(super) io: M3,
    /// Reflected rotor inertia G²J_m, kg·m² (revolute) or kg (prismatic).
    pub(super) armature: f64,
    /// `c` as an index into [`super::batch::PERMS`] when it is a signed permutation (the
    /// lockstep kernel then applies it by relabelling), else `None`.
    pub(super) perm: Option<u8>,
}

impl Default for Link {
    fn default() -> Self {
        Link {
            c: M3::identity(),
            p: V3::zeros(),
            prismatic: false,
            mass: 0.0,
            h: V3::zeros(),
            io: M3::zeros(),
            armature: 0.0,
            perm: super::batch::perm_of(&M3::identity()),
        }
    }
}

/// Entries of a fixed rotation within this of 0 or ±1, all of them, make it the signed
/// permutation they round to (`cos(π/2)` of a URDF's `rpy` or of the re-orientation is
/// 6.1e-17, not 0).
const SNAP_TO_PERMUTATION: f64 = 1e-14;

/// `c` rounded onto the signed permutation it is within [`SNAP_TO_PERMUTATION`] of, entry
/// by entry; else `c` unchanged.
fn snap_to_permutation(c: &M3) -> M3 {
    let r = c.map(|x| {
        if x.abs() <= SNAP_TO_PERMUTATION {
            0.0
        } else if (x - 1.0).abs() <= SNAP_TO_PERMUTATION {
            1.0
        } else if (x + 1.0).abs() <= SNAP_TO_PERMUTATION {
            -1.0
        } else {
            x
        }
    });
    if super::batch::perm_of(&r).is_some() {
        r
    } else {
        *c
    }
}

/// Immutable rigid-body model of a fixed-base serial chain, built once from a [`RobotModel`].
/// Cheap to share between threads (`Send + Sync`, no interior mutability).
#[derive(Clone, Debug)]
pub struct DynModel {
    pub(super) n: usize,
    pub(super) links: [Link; MAX_DOF],
    /// Base acceleration that models gravity: `a_0 = −g`, m/s², base frame.
    pub(super) a0: V3,
    /// `C_0ᵀ a_0` (m/s²): the base acceleration in link 0's frame at `q_0 = 0`, as the
    /// lockstep kernel's first link reads it.
    pub(super) a0_local: V3,
    gravity: V3,
    has_armature: bool,
    options: DynOptions,
}

/// Rotation `A` with `A e_z = axis` (unit axis).
fn z_to_axis(axis: &V3) -> M3 {
    let a = axis.normalize();
    let ez = V3::z();
    let k = ez.cross(&a);
    let s = k.norm();
    if s < 1e-12 {
        if a.z > 0.0 {
            M3::identity()
        } else {
            M3::new(1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0)
        }
    } else {
        rot_axis(&(k / s), s.atan2(a.z))
    }
}

/// `[p]×ᵀ[p]× = (p·p) 1 − p pᵀ`: the parallel-axis term per unit mass.
fn pax(p: &V3) -> M3 {
    M3::identity() * p.dot(p) - p * p.transpose()
}

impl DynModel {
    /// Precompute the per-link parameters of `robot` (joint frames, mass, first moment
    /// `m c`, inertia about each joint origin, armature `G²J_m`).
    ///
    /// Errors: [`Error::MissingInertial`] naming the first link without `<inertial>`;
    /// [`Error::Invalid`] for more than [`MAX_DOF`] joints or a zero joint axis.
    pub fn new(robot: &RobotModel, options: DynOptions) -> Result<Self> {
        let n = robot.dof();
        if n > MAX_DOF {
            return Err(Error::Invalid(format!(
                "robot `{}` has {n} joints; dynamics support at most {MAX_DOF}",
                robot.name()
            )));
        }
        let inertials = robot.dynamic_links(options.payload)?;
        let mut links = [Link::default(); MAX_DOF];
        let mut a_prev = M3::identity();
        let arm: Vec<f64> = match (&robot.drive, options.armature) {
            (Some(d), true) if d.joints.len() == n => {
                d.joints.iter().map(|j| j.armature()).collect()
            }
            _ => vec![0.0; n],
        };
        let has_armature =
            options.armature && robot.drive.as_ref().is_some_and(|d| d.joints.len() == n);
        for (i, (j, inert)) in robot.joints.iter().zip(inertials.iter()).enumerate() {
            if j.axis.norm().partial_cmp(&1e-9) != Some(std::cmp::Ordering::Greater) {
                return Err(Error::Invalid(format!(
                    "joint `{}` of robot `{}` has a zero axis",
                    j.name,
                    robot.name()
                )));
            }
            let a = z_to_axis(&j.axis);
            let c = snap_to_permutation(&(a_prev.transpose() * j.origin.rot * a));
            let p = a_prev.transpose() * j.origin.pos;
            // Inertial in the re-oriented frame: com' = Aᵀ com, I' = Aᵀ I A.
            let com = a.transpose() * inert.com;
            let ic = a.transpose() * inert.inertia * a;
            links[i] = Link {
                c,
                p,
                prismatic: j.kind == JointKind::Prismatic,
                mass: inert.mass,
                h: com * inert.mass,
                io: ic + pax(&com) * inert.mass,
                armature: arm[i],
                perm: super::batch::perm_of(&c),
            };
            a_prev = a;
        }
        let a0 = -robot.gravity;
        let c0 = &links[0].c;
        let col = |k: usize| (c0[(0, k)] * a0.x + c0[(1, k)] * a0.y) + c0[(2, k)] * a0.z;
        Ok(DynModel {
            n,
            links,
            a0,
            a0_local: V3::new(col(0), col(1), col(2)),
            gravity: robot.gravity,
            has_armature,
            options,
        })
    }

    /// Whether [`super::rnea_batch`] applies: every joint revolute.
    pub fn batchable(&self) -> bool {
        self.links[..self.n].iter().all(|l| !l.prismatic)
    }

    /// Number of joints.
    pub fn dof(&self) -> usize {
        self.n
    }

    /// Whether joint `i` (0-based) is prismatic (`false` beyond the last joint).
    pub(crate) fn is_prismatic(&self, i: usize) -> bool {
        i < self.n && self.links[i].prismatic
    }

    /// Whether the armature `G²J_m` term is active (requested and drive data present).
    pub fn has_armature(&self) -> bool {
        self.has_armature
    }

    /// Options the model was built with.
    pub fn options(&self) -> DynOptions {
        self.options
    }

    /// Reflected rotor inertia of joint `i`, kg·m² (0 when inactive or out of range).
    pub fn armature(&self, i: usize) -> f64 {
        if i < self.n {
            self.links[i].armature
        } else {
            0.0
        }
    }

    /// Gravity in the base frame, m/s².
    pub fn gravity(&self) -> V3 {
        self.gravity
    }

    /// The standard inertial parameters of link `i` (0-based moving link) in its joint frame
    /// (re-oriented so the joint axis is +z), the vector RNEA is linear in:
    /// `[m, h_x, h_y, h_z, I_xx, I_yy, I_zz, I_xy, I_xz, I_yz]` with `h = m c` (kg·m) and `I`
    /// about the joint origin (kg·m²). Zeros out of range.
    pub fn link_params(&self, i: usize) -> [f64; 10] {
        if i >= self.n {
            return [0.0; 10];
        }
        let l = &self.links[i];
        [
            l.mass,
            l.h.x,
            l.h.y,
            l.h.z,
            l.io[(0, 0)],
            l.io[(1, 1)],
            l.io[(2, 2)],
            l.io[(0, 1)],
            l.io[(0, 2)],
            l.io[(1, 2)],
        ]
    }

    /// A copy whose links have the standard parameters `params` (one
    /// [`DynModel::link_params`] vector per moving link; missing links get zeros), without
    /// armature. Since RNEA is linear in these, `rnea(with_link_params(a + b)) =
    /// rnea(with_link_params(a)) + rnea(with_link_params(b))` up to the gravity/velocity terms
    /// being shared: exactly linear. Parameters need not be physical (a difference of two
    /// models is fine).
    pub(crate) fn with_link_params(&self, params: &[[f64; 10]]) -> DynModel {
        let mut m = self.clone();
        m.has_armature = false;
        for i in 0..m.n {
            let p = params.get(i).copied().unwrap_or([0.0; 10]);
            let l = &mut m.links[i];
            l.mass = p[0];
            l.h = V3::new(p[1], p[2], p[3]);
            l.io = M3::new(p[4], p[7], p[8], p[7], p[5], p[9], p[8], p[9], p[6]);
            l.armature = 0.0;
        }
        m
    }

    /// A fresh workspace for this model.
    pub fn data(&self) -> DynData {
        DynData::default()
    }

    fn check(&self, what: &str, len: usize) -> Result<()> {
        if len != self.n {
            return Err(Error::SizeMismatch {
                what: what.to_string(),
                got: len,
                expected: self.n,
            });
        }
        Ok(())
    }
}

/// Per-thread workspace for the algorithms of this module: fixed-size arrays, no heap.
/// Holds intermediate joint transforms, link forces and composite inertias (RNEA of a
/// revolute model runs the lockstep kernel on one lane and leaves it untouched).
#[derive(Clone, Debug)]
pub struct DynData {
    r: [M3; MAX_DOF],
    p: [V3; MAX_DOF],
    f: [V3; MAX_DOF],
    nn: [V3; MAX_DOF],
    ic_m: [f64; MAX_DOF],
    ic_h: [V3; MAX_DOF],
    ic_i: [M3; MAX_DOF],
}

impl Default for DynData {
    fn default() -> Self {
        DynData {
            r: [M3::identity(); MAX_DOF],
            p: [V3::zeros(); MAX_DOF],
            f: [V3::zeros(); MAX_DOF],
            nn: [V3::zeros(); MAX_DOF],
            ic_m: [0.0; MAX_DOF],
            ic_h: [V3::zeros(); MAX_DOF],
            ic_i: [M3::zeros(); MAX_DOF],
        }
    }
}

/// Joint transforms (child → parent) of every joint at `q`, into `d.r`, `d.p`.
#[inline(always)]
fn kinematics(m: &DynModel, d: &mut DynData, q: &[f64]) {
    kinematics_with(m, d, q, |i| crate::fastmath::sin_cos(q[i]))
}

/// [`kinematics`] with the revolute joints' `(sin q_i, cos q_i)` from `sin_cos(i)`.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // parallel fixed arrays indexed by joint
fn kinematics_with(
    m: &DynModel,
    d: &mut DynData,
    q: &[f64],
    sin_cos: impl Fn(usize) -> (f64, f64),
) {
    for i in 0..m.n {
        let l = &m.links[i];
        if l.prismatic {
            d.r[i] = l.c;
            d.p[i] = l.p + l.c.column(2) * q[i];
        } else {
            let (s, c) = sin_cos(i);
            let c0 = l.c.column(0);
            let c1 = l.c.column(1);
            d.r[i] = M3::from_columns(&[c0 * c + c1 * s, c1 * c - c0 * s, l.c.column(2).into()]);
            d.p[i] = l.p;
        }
    }
}

/// `ω × e_z`.
#[inline(always)]
fn cross_z(w: &V3) -> V3 {
    V3::new(w.y, -w.x, 0.0)
}

/// Gravity-only pass (`q̇ = q̈ = 0`): every link accelerates like the base, `a_i = R_iᵀ a_{i−1}`,
/// so `f = m a`, `n = (m c) × a`.
#[inline(always)]
fn gravity_core(m: &DynModel, d: &mut DynData, q: &[f64], tau: &mut [f64]) {
    kinematics(m, d, q);
    let mut ap = m.a0;
    for i in 0..m.n {
        let l = &m.links[i];
        let a = d.r[i].tr_mul(&ap);
        d.f[i] = a * l.mass;
        d.nn[i] = l.h.cross(&a);
        ap = a;
    }
    backward(m, d, tau, None);
}

/// Backward pass: joint torques from link forces, accumulating children into parents.
#[inline(always)]
fn backward(m: &DynModel, d: &mut DynData, tau: &mut [f64], qdd: Option<&[f64]>) {
    for i in (0..m.n).rev() {
        let l = &m.links[i];
        let t = if l.prismatic { d.f[i].z } else { d.nn[i].z };
        tau[i] = match qdd {
            Some(a) => t + l.armature * a[i],
            None => t,
        };
        if i > 0 {
            let r = &d.r[i];
            let fp = r * d.f[i];
            let np = r * d.nn[i] + d.p[i].cross(&fp);
            d.f[i - 1] += fp;
            d.nn[i - 1] += np;
        }
    }
}

#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn rnea_core(
    m: &DynModel,
    d: &mut DynData,
    q: &[f64],
    sin_cos: impl Fn(usize) -> (f64, f64),
    qd: &[f64],
    qdd: &[f64],
    a0: V3,
    tau: &mut [f64],
) {
    kinematics_with(m, d, q, sin_cos);
    let mut wp = V3::zeros();
    let mut wdp = V3::zeros();
    let mut ap = a0;
    for i in 0..m.n {
        let l = &m.links[i];
        let r = &d.r[i];
        let p = d.p[i];
        let (w, wd, a) = link_motion(l.prismatic, r, &p, &wp, &wdp, &ap, qd[i], qdd[i]);
        let iw = l.io * w;
        d.f[i] = a * l.mass + wd.cross(&l.h) + w.cross(&w.cross(&l.h));
        d.nn[i] = l.io * wd + w.cross(&iw) + l.h.cross(&a);
        wp = w;
        wdp = wd;
        ap = a;
    }
    backward(m, d, tau, Some(qdd));
}

/// One link's motion in its own frame from its parent's (forward pass of RNEA): angular
/// velocity [rad/s], angular acceleration [rad/s²] and linear acceleration of the frame origin
/// [m/s²], given the joint's rotation `r` and offset `p` [m] from the parent frame and the joint
/// rate `qd` and acceleration `qdd` (rad or m). Shared by [`rnea`] and [`rnea_regressor`].
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn link_motion(
    prismatic: bool,
    r: &M3,
    p: &V3,
    wp: &V3,
    wdp: &V3,
    ap: &V3,
    qd: f64,
    qdd: f64,
) -> (V3, V3, V3) {
    let a_origin = ap + wdp.cross(p) + wp.cross(&wp.cross(p));
    let wpl = r.tr_mul(wp);
    if prismatic {
        let w = wpl;
        let wd = r.tr_mul(wdp);
        let mut a = r.tr_mul(&a_origin) + cross_z(&w) * (2.0 * qd);
        a.z += qdd;
        (w, wd, a)
    } else {
        let mut w = wpl;
        w.z += qd;
        let mut wd = r.tr_mul(wdp) + cross_z(&wpl) * qd;
        wd.z += qdd;
        (w, wd, r.tr_mul(&a_origin))
    }
}

/// The inertial-parameter regressor of RNEA (Khalil & Dombre 2002, §9.4; cf. pinocchio
/// `computeJointTorqueRegressor`): `τ = Y π` with `π` the [`DynModel::link_params`] of every
/// link stacked (`10 n` values). `y` is row-major `n × 10 n`. One forward pass for the link
/// motions, then for each link parameter the link's force and moment propagated back to the
/// base; the armature is not included. Error: [`Error::SizeMismatch`] on a wrong slice length.
#[allow(clippy::needless_range_loop)] // parallel fixed arrays indexed by joint
pub fn rnea_regressor(
    model: &DynModel,
    data: &mut DynData,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    y: &mut [f64],
) -> Result<()> {
    let n = model.n;
    model.check("rnea_regressor: q", q.len())?;
    model.check("rnea_regressor: qd", qd.len())?;
    model.check("rnea_regressor: qdd", qdd.len())?;
    if y.len() != n * 10 * n {
        return Err(Error::SizeMismatch {
            what: "rnea_regressor: y (n × 10n)".into(),
            got: y.len(),
            expected: n * 10 * n,
        });
    }
    kinematics(model, data, q);
    let mut ws = [V3::zeros(); MAX_DOF];
    let mut wds = [V3::zeros(); MAX_DOF];
    let mut acc = [V3::zeros(); MAX_DOF];
    let mut wp = V3::zeros();
    let mut wdp = V3::zeros();
    let mut ap = model.a0;
    for i in 0..n {
        let l = &model.links[i];
        let r = &data.r[i];
        let p = data.p[i];
        let (w, wd, a) = link_motion(l.prismatic, r, &p, &wp, &wdp, &ap, qd[i], qdd[i]);
        ws[i] = w;
        wds[i] = wd;
        acc[i] = a;
        wp = w;
        wdp = wd;
        ap = a;
    }
    y.iter_mut().for_each(|v| *v = 0.0);
    let cols = 10 * n;
    let e = [V3::x(), V3::y(), V3::z()];
    for i in 0..n {
        let (w, wd, a) = (ws[i], wds[i], acc[i]);
        for c in 0..10 {
            let (f, nn) = match c {
                0 => (a, V3::zeros()),
                1..=3 => {
                    let h = e[c - 1];
                    (wd.cross(&h) + w.cross(&w.cross(&h)), h.cross(&a))
                }
                _ => {
                    let mut io = M3::zeros();
                    match c {
                        4..=6 => io[(c - 4, c - 4)] = 1.0,
                        7 => {
                            io[(0, 1)] = 1.0;
                            io[(1, 0)] = 1.0
                        }
                        8 => {
                            io[(0, 2)] = 1.0;
                            io[(2, 0)] = 1.0
                        }
                        _ => {
                            io[(1, 2)] = 1.0;
                            io[(2, 1)] = 1.0
                        }
                    }
                    (V3::zeros(), io * wd + w.cross(&(io * w)))
                }
            };
            let (mut f, mut nn) = (f, nn);
            let col = 10 * i + c;
            for k in (0..=i).rev() {
                let t = if model.links[k].prismatic { f.z } else { nn.z };
                y[k * cols + col] = t;
                if k > 0 {
                    let r = &data.r[k];
                    let fp = r * f;
                    nn = r * nn + data.p[k].cross(&fp);
                    f = fp;
                }
            }
        }
    }
    Ok(())
}

/// Inverse dynamics by the recursive Newton–Euler algorithm (seed 000, eqs. 1 and 5):
/// `τ = M(q) q̈ + C(q, q̇) q̇ + G(q)` (+ `G²J_m q̈` when the armature is active), fixed base,
/// gravity applied as the base acceleration `−g` (Featherstone 2008, table 5.1).
///
/// `q` rad (m), `qd` rad/s, `qdd` rad/s², all of length `model.dof()`; writes `tau` (N·m or N,
/// length `dof`). No allocation. A model whose joints are all revolute runs the lockstep
/// kernel of [`super::rnea_batch`] on one lane (the same bits as every SIMD level). Error:
/// [`Error::SizeMismatch`] on a wrong slice length.
pub fn rnea(
    model: &DynModel,
    data: &mut DynData,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    tau: &mut [f64],
) -> Result<()> {
    model.check("rnea: q", q.len())?;
    model.check("rnea: qd", qd.len())?;
    model.check("rnea: qdd", qdd.len())?;
    model.check("rnea: tau", tau.len())?;
    if model.batchable() {
        super::batch::rnea_one(model, |i| crate::fastmath::sin_cos(q[i]), qd, qdd, tau);
        return Ok(());
    }
    rnea_core(
        model,
        data,
        q,
        |i| crate::fastmath::sin_cos(q[i]),
        qd,
        qdd,
        model.a0,
        tau,
    );
    Ok(())
}

/// [`rnea`] with the joints' sines and cosines already computed (by the IK's FK re-check of
/// the same sample, [`crate::kinematics::IkSolver::solve_near_with_sincos`]): `sincos` holds
/// `sin q_0 … sin q_{n−1}` then `cos q_0 … cos q_{n−1}` (length `2 dof`; prismatic joints'
/// entries unused). Same result as [`rnea`] when `sincos` is [`crate::fastmath::sin_cos`] of
/// `q`. Error: [`Error::SizeMismatch`] on a wrong slice length.
pub fn rnea_with_sincos(
    model: &DynModel,
    data: &mut DynData,
    q: &[f64],
    sincos: &[f64],
    qd: &[f64],
    qdd: &[f64],
    tau: &mut [f64],
) -> Result<()> {
    let n = model.n;
    model.check("rnea: q", q.len())?;
    model.check("rnea: qd", qd.len())?;
    model.check("rnea: qdd", qdd.len())?;
    model.check("rnea: tau", tau.len())?;
    if sincos.len() != 2 * n {
        return Err(Error::SizeMismatch {
            what: "rnea: sincos (2 dof)".into(),
            got: sincos.len(),
            expected: 2 * n,
        });
    }
    let (s, c) = sincos.split_at(n);
    if model.batchable() {
        super::batch::rnea_one(model, |i| (s[i], c[i]), qd, qdd, tau);
        return Ok(());
    }
    rnea_core(model, data, q, |i| (s[i], c[i]), qd, qdd, model.a0, tau);
    Ok(())
}

/// Gravity torque `G(q)` (seed 000, eq. 1), N·m: the joint torque that holds the arm still
/// at `q` (rad). Writes `tau` (length `dof`).
pub fn gravity_torque(
    model: &DynModel,
    data: &mut DynData,
    q: &[f64],
    tau: &mut [f64],
) -> Result<()> {
    model.check("gravity_torque: q", q.len())?;
    model.check("gravity_torque: tau", tau.len())?;
    gravity_core(model, data, q, tau);
    Ok(())
}

/// Joint-space mass matrix `M(q)` (seed 000, eq. 1), kg·m², by the composite-rigid-body
/// algorithm (Featherstone 2008, §6.2), armature `G²J_m` on the diagonal when active.
/// Writes `mass` row-major, `dof × dof` (both triangles). No allocation.
pub fn mass_matrix(
    model: &DynModel,
    data: &mut DynData,
    q: &[f64],
    mass: &mut [f64],
) -> Result<()> {
    let n = model.n;
    model.check("mass_matrix: q", q.len())?;
    if mass.len() != n * n {
        return Err(Error::SizeMismatch {
            what: "mass_matrix: output (dof²)".into(),
            got: mass.len(),
            expected: n * n,
        });
    }
    let d = data;
    kinematics(model, d, q);
    for i in 0..n {
        let l = &model.links[i];
        d.ic_m[i] = l.mass;
        d.ic_h[i] = l.h;
        d.ic_i[i] = l.io;
    }
    // Composite inertias, tip to base, each about its own joint origin.
    for i in (1..n).rev() {
        let r = d.r[i];
        let p = d.p[i];
        let m = d.ic_m[i];
        let h = r * d.ic_h[i];
        let io = r * d.ic_i[i] * r.transpose();
        let sp = crate::math::skew(&p);
        let sh = crate::math::skew(&h);
        d.ic_m[i - 1] += m;
        d.ic_h[i - 1] += h + p * m;
        d.ic_i[i - 1] += io - sp * sp * m - sp * sh - sh * sp;
    }
    for j in 0..n {
        let lj = &model.links[j];
        // Spatial force F = I^c_j S_j in frame j (about its origin).
        let (mut f, mut nn) = if lj.prismatic {
            (V3::z() * d.ic_m[j], d.ic_h[j].cross(&V3::z()))
        } else {
            (V3::z().cross(&d.ic_h[j]), d.ic_i[j] * V3::z())
        };
        let mut i = j;
        loop {
            let li = &model.links[i];
            let v = if li.prismatic { f.z } else { nn.z };
            mass[i * n + j] = v;
            mass[j * n + i] = v;
            if i == 0 {
                break;
            }
            let fp = d.r[i] * f;
            nn = d.r[i] * nn + d.p[i].cross(&fp);
            f = fp;
            i -= 1;
        }
        mass[j * n + j] += lj.armature;
    }
    Ok(())
}

/// Kinetic energy `T = ½ q̇ᵀ M(q) q̇`, J, summed link by link
/// (`½(m v·v + 2 v·(ω × m c) + ωᵀ I_O ω)`, Featherstone 2008 eq. 2.61), plus the rotors'
/// `½ G²J_m q̇²` when the armature is active.
#[allow(clippy::needless_range_loop)] // parallel fixed arrays indexed by joint
pub fn kinetic_energy(model: &DynModel, data: &mut DynData, q: &[f64], qd: &[f64]) -> Result<f64> {
    model.check("kinetic_energy: q", q.len())?;
    model.check("kinetic_energy: qd", qd.len())?;
    kinematics(model, data, q);
    let mut wp = V3::zeros();
    let mut vp = V3::zeros();
    let mut t = 0.0;
    for i in 0..model.n {
        let l = &model.links[i];
        let rt = data.r[i].transpose();
        let mut v = rt * (vp + wp.cross(&data.p[i]));
        let mut w = rt * wp;
        if l.prismatic {
            v.z += qd[i];
        } else {
            w.z += qd[i];
        }
        t += 0.5 * (l.mass * v.dot(&v) + w.dot(&(l.io * w))) + v.dot(&w.cross(&l.h));
        t += 0.5 * l.armature * qd[i] * qd[i];
        wp = w;
        vp = v;
    }
    Ok(t)
}

/// Potential energy in the gravity field, `V = −Σ m_i g·p_com,i`, J, zero at the base origin
/// (seed 000, eq. 1: `G(q) = ∂V/∂q`).
pub fn potential_energy(model: &DynModel, data: &mut DynData, q: &[f64]) -> Result<f64> {
    model.check("potential_energy: q", q.len())?;
    kinematics(model, data, q);
    let mut rw = M3::identity();
    let mut pw = V3::zeros();
    let mut v = 0.0;
    for i in 0..model.n {
        let l = &model.links[i];
        pw += rw * data.p[i];
        rw *= data.r[i];
        v -= model.gravity.dot(&(pw * l.mass + rw * l.h));
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    const ROBOTS: [&str; 5] = [
        "abb_irb6700_200_260",
        "abb_irb4600_40_255",
        "staubli_tx200",
        "ur10e",
        "puma560",
    ];

    fn shipped(name: &str) -> RobotModel {
        let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("robots")
            .join(name);
        crate::robot::load(&p).unwrap()
    }

    /// Deterministic states in wide ranges (rad, rad/s, rad/s²), zeros included.
    fn states(n: usize, count: usize) -> Vec<[Vec<f64>; 3]> {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut u = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            2.0 * ((s >> 11) as f64 / (1u64 << 53) as f64) - 1.0
        };
        (0..count)
            .map(|k| {
                let mut q: Vec<f64> = (0..n).map(|_| 3.5 * u()).collect();
                let mut qd: Vec<f64> = (0..n).map(|_| 3.0 * u()).collect();
                let qdd: Vec<f64> = (0..n).map(|_| 20.0 * u()).collect();
                if k % 7 == 0 {
                    q[k % n] = 0.0;
                    qd[(k + 1) % n] = 0.0;
                }
                [q, qd, qdd]
            })
            .collect()
    }

    fn options() -> [DynOptions; 2] {
        [
            DynOptions::default(),
            DynOptions {
                payload: true,
                armature: true,
            },
        ]
    }

    /// The lockstep kernel's formulation (`Cᵀ` by relabelling, link 0 and 1 without their
    /// zero terms) against the dense one (`rnea_core`: `R = C Rz(q)` built, every product
    /// taken) on the same model: with every fixed rotation a signed permutation the two make
    /// the same roundings, so the torques are equal (`==`: a zero's sign may differ).
    #[test]
    fn the_lean_rnea_equals_the_dense_formulation_when_the_fixed_rotations_are_signed_permutations()
    {
        for name in ROBOTS {
            let r = shipped(name);
            for opts in options() {
                let m = DynModel::new(&r, opts).unwrap();
                let n = m.n;
                assert!(
                    m.links[..n].iter().all(|l| l.perm.is_some()),
                    "{name}: every fixed rotation is a signed permutation"
                );
                let mut d = m.data();
                let (mut lean, mut dense) = (vec![0.0; n], vec![0.0; n]);
                for [q, qd, qdd] in states(n, 300) {
                    rnea(&m, &mut d, &q, &qd, &qdd, &mut lean).unwrap();
                    let sc = |i: usize| crate::fastmath::sin_cos(q[i]);
                    rnea_core(&m, &mut d, &q, sc, &qd, &qdd, m.a0, &mut dense);
                    assert_eq!(lean, dense, "{name} {opts:?} at q {q:?}");
                }
            }
        }
    }

    /// The fixed rotations as computed (`cos(π/2)` = 6.1e-17 where the URDF means 0), not
    /// snapped: the snapped model's torques are within 1e-12 · max(1, |τ|) of these (the
    /// stated bound of the snap: entries move by at most 1e-14, and every product then rounds
    /// differently, on terms up to ~10⁴ N·m for the large arms; measured 2.4e-13).
    #[test]
    fn snapping_the_fixed_rotations_onto_signed_permutations_moves_torques_by_at_most_1e_12_relative(
    ) {
        let mut worst = 0.0f64;
        for name in ROBOTS {
            let r = shipped(name);
            for opts in options() {
                let m = DynModel::new(&r, opts).unwrap();
                let mut raw = m.clone();
                let mut a_prev = M3::identity();
                let mut snapped_any = false;
                for (i, j) in r.joints.iter().enumerate() {
                    let a = z_to_axis(&j.axis);
                    let c = a_prev.transpose() * j.origin.rot * a;
                    snapped_any |= c != m.links[i].c;
                    assert!((c - m.links[i].c).amax() <= SNAP_TO_PERMUTATION);
                    raw.links[i].c = c;
                    raw.links[i].perm = None;
                    a_prev = a;
                }
                assert!(snapped_any, "{name}: some rotation had rounding to snap");
                let n = m.n;
                let mut d = m.data();
                let (mut t, mut t_raw) = (vec![0.0; n], vec![0.0; n]);
                for [q, qd, qdd] in states(n, 300) {
                    rnea(&m, &mut d, &q, &qd, &qdd, &mut t).unwrap();
                    let sc = |i: usize| crate::fastmath::sin_cos(q[i]);
                    rnea_core(&raw, &mut d, &q, sc, &qd, &qdd, raw.a0, &mut t_raw);
                    for j in 0..n {
                        let e = (t[j] - t_raw[j]).abs() / t_raw[j].abs().max(1.0);
                        worst = worst.max(e);
                        assert!(e <= 1e-12, "{name} joint {j}: {} vs {}", t[j], t_raw[j]);
                    }
                }
            }
        }
        println!("snapped vs computed fixed rotations: max relative torque change {worst:.2e}");
    }

    #[test]
    fn a_rotation_near_but_not_within_the_snap_tolerance_of_a_permutation_stays_dense() {
        let exact = rot_axis(&V3::x(), std::f64::consts::FRAC_PI_2);
        assert_ne!(exact[(1, 1)], 0.0, "cos(π/2) rounds to 6.1e-17");
        let s = snap_to_permutation(&exact);
        assert_eq!(s, M3::new(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0));
        assert!(super::super::batch::perm_of(&s).is_some());
        let off = rot_axis(&V3::x(), std::f64::consts::FRAC_PI_2 + 1e-9);
        assert_eq!(snap_to_permutation(&off), off);
        assert!(super::super::batch::perm_of(&off).is_none());
    }
}
