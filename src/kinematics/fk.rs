//! Forward kinematics and the geometric Jacobian of the tool point, allocation-free.
//!
//! Everything is in the robot's base frame; positions in m, angles in rad (prismatic joint
//! positions in m).

use super::MAX_DOF;
use crate::math::{Frame, V3};
use crate::robot::{JointKind, RobotModel};
use crate::simd::{F64s, Level, LANES};

/// Every frame of the chain at one joint vector, base frame, m / rad.
#[derive(Clone, Copy, Debug)]
pub struct FkFrames {
    /// Number of valid entries in `joints`.
    pub n: usize,
    /// Frame of joint `i` (= its child link) in the base frame; entries `n..` are identity.
    pub joints: [Frame; MAX_DOF],
    /// Flange (`tool_link`) frame in the base frame.
    pub flange: Frame,
    /// Nozzle tip (tool centre point) in the base frame; the nozzle points along its +z.
    pub tool: Frame,
}

impl FkFrames {
    /// The joint frames actually used, base frame.
    pub fn joint_frames(&self) -> &[Frame] {
        &self.joints[..self.n]
    }
}

/// All joint frames, the flange and the tool pose for `q` (rad / m). Joints beyond
/// `q.len()` are taken at 0; only the first [`MAX_DOF`] joints are used (the front end
/// [`super::IkSolver`] refuses longer chains).
pub fn fk(model: &RobotModel, q: &[f64]) -> FkFrames {
    let mut joints = [Frame::identity(); MAX_DOF];
    let mut f = Frame::identity();
    let n = model.joints.len().min(MAX_DOF);
    for (i, j) in model.joints.iter().take(n).enumerate() {
        f = f.compose(&j.transform(q.get(i).copied().unwrap_or(0.0)));
        joints[i] = f;
    }
    let flange = f.compose(&model.flange);
    let tool = flange.compose(&model.tool);
    FkFrames {
        n,
        joints,
        flange,
        tool,
    }
}

/// Flange pose in the base frame for `q` (rad / m): the fast path (no joint frames kept).
#[inline]
pub fn flange_pose(model: &RobotModel, q: &[f64]) -> Frame {
    let mut f = Frame::identity();
    for (i, j) in model.joints.iter().enumerate() {
        f = f.compose(&j.transform(q.get(i).copied().unwrap_or(0.0)));
    }
    f.compose(&model.flange)
}

/// Nozzle-tip (tool) pose in the base frame for `q` (rad / m).
#[inline]
pub fn tool_pose(model: &RobotModel, q: &[f64]) -> Frame {
    flange_pose(model, q).compose(&model.tool)
}

/// Geometric Jacobian of the tool point, 6 × n, base frame.
///
/// Column `i` maps `q̇_i` to the tool twist: rows 0–2 the linear velocity of the nozzle tip
/// (m/s per rad/s, or per m/s for prismatic joints), rows 3–5 the angular velocity (rad/s per
/// rad/s; 0 for prismatic joints).
#[derive(Clone, Copy, Debug)]
pub struct Jacobian {
    /// Number of valid columns.
    pub n: usize,
    /// Columns `[vx, vy, vz, wx, wy, wz]`; entries `n..` are zero.
    pub cols: [[f64; 6]; MAX_DOF],
}

impl Jacobian {
    /// Entry at `row` (0..6) and `col` (0..n).
    #[inline]
    pub fn get(&self, row: usize, col: usize) -> f64 {
        self.cols[col][row]
    }

    /// `J · J^T`, 6 × 6 (mixed units: m² in the linear block, 1 in the angular block).
    pub(crate) fn jjt(&self) -> nalgebra::Matrix6<f64> {
        let mut m = nalgebra::Matrix6::zeros();
        for c in &self.cols[..self.n] {
            for r in 0..6 {
                for s in 0..6 {
                    m[(r, s)] += c[r] * c[s];
                }
            }
        }
        m
    }
}

/// Geometric Jacobian of the tool point at `q` (rad / m), together with the frames it used.
pub(crate) fn jacobian_with_frames(model: &RobotModel, q: &[f64]) -> (Jacobian, FkFrames) {
    let frames = fk(model, q);
    (jacobian_of_frames(model, &frames), frames)
}

/// Geometric Jacobian of the tool point at `q` (rad / m); see [`Jacobian`].
pub fn jacobian(model: &RobotModel, q: &[f64]) -> Jacobian {
    jacobian_with_frames(model, q).0
}

/// Jacobian from already computed frames.
pub(crate) fn jacobian_of_frames(model: &RobotModel, frames: &FkFrames) -> Jacobian {
    let mut cols = [[0.0; 6]; MAX_DOF];
    let p = frames.tool.pos;
    for (i, j) in model.joints.iter().take(frames.n).enumerate() {
        let f = &frames.joints[i];
        let z: V3 = f.rot * j.axis;
        match j.kind {
            JointKind::Revolute => {
                let v = z.cross(&(p - f.pos));
                cols[i] = [v.x, v.y, v.z, z.x, z.y, z.z];
            }
            JointKind::Prismatic => cols[i] = [z.x, z.y, z.z, 0.0, 0.0, 0.0],
        }
    }
    Jacobian { n: frames.n, cols }
}

/// Smallest singular value of the tool Jacobian and the manipulability `sqrt(det(J Jᵀ))`.
///
/// Units are mixed (linear rows in m/rad, angular rows in rad/rad); compare values of the same
/// robot and tool only. Both are 0 at a singularity. For arms with fewer than 6 joints both
/// are 0 by definition.
pub fn jacobian_measures(model: &RobotModel, q: &[f64]) -> (f64, f64) {
    let j = jacobian(model, q);
    let m = j.jjt();
    let eig = nalgebra::SymmetricEigen::new(m);
    let min = eig
        .eigenvalues
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    let det: f64 = eig.eigenvalues.iter().product();
    (min.max(0.0).sqrt(), det.max(0.0).sqrt())
}

/// A revolute joint's unit axis (in its joint frame), specialised when it is a coordinate
/// axis exactly: `X(±1)`, `Y(±1)`, `Z(±1)` hold the sign.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Axis {
    X(f64),
    Y(f64),
    Z(f64),
    General(V3),
}

impl Axis {
    /// The specialised form of the unit axis `a`.
    pub(crate) fn of(a: &V3) -> Axis {
        let exact = |a: f64, b: f64, c: f64| a.abs() == 1.0 && b == 0.0 && c == 0.0;
        let (x, y, z) = (a.x, a.y, a.z);
        if exact(x, y, z) {
            Axis::X(x)
        } else if exact(y, x, z) {
            Axis::Y(y)
        } else if exact(z, x, y) {
            Axis::Z(z)
        } else {
            Axis::General(*a)
        }
    }

    /// `r ← r · R(axis, q)` for the joint angle `q` given by its sine `s` and cosine `c`.
    #[inline(always)]
    pub(crate) fn rotate(self, r: &mut crate::math::M3, s: f64, c: f64) {
        match self {
            Axis::X(sg) => rot_cols(r, 1, 2, sg * s, c),
            Axis::Y(sg) => rot_cols(r, 2, 0, sg * s, c),
            Axis::Z(sg) => rot_cols(r, 0, 1, sg * s, c),
            Axis::General(a) => *r *= crate::math::rot_axis_sc(&a, s, c),
        }
    }
}

#[derive(Clone, Copy, Debug)]
struct FastJoint {
    /// `None` when the origin rotation is the identity.
    rot: Option<crate::math::M3>,
    pos: V3,
    axis: Axis,
    axis_vec: V3,
    prismatic: bool,
}

/// A pre-processed copy of the chain for the fastest flange/tool pose (identity origin
/// rotations skipped, rotations about coordinate axes applied to two columns only). Same
/// result as [`flange_pose`] / [`tool_pose`] to rounding. At most [`MAX_DOF`] joints.
#[derive(Clone, Copy, Debug)]
pub struct FastChain {
    n: usize,
    joints: [FastJoint; MAX_DOF],
    flange: Frame,
    /// `flange ∘ tool`, so that the tool pose costs one composition.
    tail: Frame,
}

/// Rotate columns `a` and `b` of `r` by the angle with sine `s` and cosine `c` (post-multiply
/// by a rotation about the third coordinate axis).
#[inline(always)]
fn rot_cols(r: &mut crate::math::M3, a: usize, b: usize, s: f64, c: f64) {
    for i in 0..3 {
        let ra = r[(i, a)];
        let rb = r[(i, b)];
        r[(i, a)] = ra * c + rb * s;
        r[(i, b)] = rb * c - ra * s;
    }
}

impl FastChain {
    /// Pre-process `model` (joints beyond [`MAX_DOF`] are ignored; check `model.dof()`).
    pub fn new(model: &RobotModel) -> Self {
        let blank = FastJoint {
            rot: None,
            pos: V3::zeros(),
            axis: Axis::Z(1.0),
            axis_vec: V3::z(),
            prismatic: false,
        };
        let mut joints = [blank; MAX_DOF];
        let n = model.dof().min(MAX_DOF);
        for (i, j) in model.joints.iter().take(n).enumerate() {
            let axis = Axis::of(&j.axis);
            let is_id = j.origin.rot == crate::math::M3::identity();
            joints[i] = FastJoint {
                rot: (!is_id).then_some(j.origin.rot),
                pos: j.origin.pos,
                axis,
                axis_vec: j.axis,
                prismatic: j.kind == JointKind::Prismatic,
            };
        }
        FastChain {
            n,
            joints,
            flange: model.flange,
            tail: model.flange.compose(&model.tool),
        }
    }

    /// Frame of the last joint in the base frame for `q` (rad / m; missing entries taken as 0).
    #[inline]
    fn last_joint(&self, q: &[f64]) -> Frame {
        self.last_joint_with(q, |_, _, _| {})
    }

    /// [`FastChain::last_joint`], handing each revolute joint's `(i, sin q_i, cos q_i)` to
    /// `record` as it is computed.
    #[inline(always)]
    fn last_joint_with(&self, q: &[f64], mut record: impl FnMut(usize, f64, f64)) -> Frame {
        let mut r = crate::math::M3::identity();
        let mut p = V3::zeros();
        for (i, j) in self.joints[..self.n].iter().enumerate() {
            let qi = q.get(i).copied().unwrap_or(0.0);
            p += r * j.pos;
            if let Some(o) = &j.rot {
                r *= o;
            }
            if j.prismatic {
                p += r * (j.axis_vec * qi);
                continue;
            }
            let (s, c) = crate::fastmath::sin_cos(qi);
            record(i, s, c);
            j.axis.rotate(&mut r, s, c);
        }
        Frame { rot: r, pos: p }
    }

    /// [`FastChain::tool`] that also writes the joints' sines and cosines it computed into
    /// `sincos` (length ≥ 2 × joints: `sin q_0 … sin q_{n−1}`, then `cos q_0 … cos q_{n−1}`;
    /// prismatic joints' entries are left untouched), for the callers that need them again
    /// for the same `q` (RNEA, feasibility): computed once per sample.
    #[inline]
    pub fn tool_with_sincos(&self, q: &[f64], sincos: &mut [f64]) -> Frame {
        let n = self.n;
        let (s_out, c_out) = sincos.split_at_mut(n);
        self.last_joint_with(q, |i, s, c| {
            s_out[i] = s;
            c_out[i] = c;
        })
        .compose(&self.tail)
    }

    /// Flange pose in the base frame for `q` (rad / m; missing entries taken as 0).
    #[inline]
    pub fn flange(&self, q: &[f64]) -> Frame {
        self.last_joint(q).compose(&self.flange)
    }

    /// Tool (nozzle-tip) pose in the base frame for `q` (rad / m).
    #[inline]
    pub fn tool(&self, q: &[f64]) -> Frame {
        self.last_joint(q).compose(&self.tail)
    }
}

/// Tool poses of [`LANES`] joint vectors at once (structure of arrays; base frame): the
/// rotation `rot[i][j][lane]`, the position `pos[i][lane]` (m), and the revolute joints'
/// sines `s[j][lane]` and cosines `c[j][lane]`.
#[derive(Clone, Copy, Debug)]
pub struct ToolBatch {
    /// Rotation, row `i`, column `j`.
    pub rot: [[Lanes; 3]; 3],
    /// Position, m.
    pub pos: [Lanes; 3],
    /// `sin q_j`.
    pub s: [Lanes; MAX_DOF],
    /// `cos q_j`.
    pub c: [Lanes; MAX_DOF],
}

impl ToolBatch {
    /// The tool pose of one lane.
    pub fn frame(&self, lane: usize) -> Frame {
        let r = &self.rot;
        Frame {
            rot: crate::math::M3::new(
                r[0][0][lane],
                r[0][1][lane],
                r[0][2][lane],
                r[1][0][lane],
                r[1][1][lane],
                r[1][2][lane],
                r[2][0][lane],
                r[2][1][lane],
                r[2][2][lane],
            ),
            pos: V3::new(self.pos[0][lane], self.pos[1][lane], self.pos[2][lane]),
        }
    }
}

type Lanes = [f64; LANES];
type ML = [[Lanes; 3]; 3];

/// `m v` per lane with a constant `v` (nalgebra's order: `(m₀ x + m₁ y) + m₂ z` per row).
#[inline(always)]
fn ml_mul_v(m: &ML, v: &V3) -> [Lanes; 3] {
    // Plain loops, not std::array::from_fn: its closure is not always inlined, and whether it
    // is changed with unrelated code elsewhere in the crate (callgrind: ±3.6 M instructions of
    // 5 evaluations in FastChain::tool_batch).
    let mut out = [[0.0; LANES]; 3];
    for (i, r) in out.iter_mut().enumerate() {
        for l in 0..LANES {
            r[l] = (m[i][0][l] * v.x + m[i][1][l] * v.y) + m[i][2][l] * v.z;
        }
    }
    out
}

/// `m o` per lane with a constant `o` (nalgebra's gemm: column by column, the same order).
#[inline(always)]
fn ml_mul_m(m: &ML, o: &crate::math::M3) -> ML {
    let mut out = [[[0.0; LANES]; 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, r) in row.iter_mut().enumerate() {
            for l in 0..LANES {
                r[l] = (m[i][0][l] * o[(0, j)] + m[i][1][l] * o[(1, j)]) + m[i][2][l] * o[(2, j)];
            }
        }
    }
    out
}

impl FastChain {
    /// Whether [`FastChain::tool_batch`] applies: every joint revolute about a coordinate
    /// axis of its frame.
    pub fn batchable(&self) -> bool {
        self.joints[..self.n]
            .iter()
            .all(|j| !j.prismatic && !matches!(j.axis, Axis::General(_)))
    }

    /// The body of [`FastChain::tool_batch`]: [`FastChain::tool_with_sincos`]'s operations
    /// per lane, in the same order.
    #[inline(always)]
    fn tool_lanes(&self, q: &[Lanes; MAX_DOF]) -> ToolBatch {
        let (one, zero) = ([1.0; LANES], [0.0; LANES]);
        let mut r: ML = [[one, zero, zero], [zero, one, zero], [zero, zero, one]];
        let mut p = [zero; 3];
        let mut s_out = [zero; MAX_DOF];
        let mut c_out = [one; MAX_DOF];
        for (i, j) in self.joints[..self.n].iter().enumerate() {
            let d = ml_mul_v(&r, &j.pos);
            for (pk, dk) in p.iter_mut().zip(&d) {
                for l in 0..LANES {
                    pk[l] += dk[l];
                }
            }
            if let Some(o) = &j.rot {
                r = ml_mul_m(&r, o);
            }
            let (s, c) = crate::fastmath::sin_cos_lanes(&q[i]);
            s_out[i] = s;
            c_out[i] = c;
            let (a, b, sg) = match j.axis {
                Axis::X(sg) => (1, 2, sg),
                Axis::Y(sg) => (2, 0, sg),
                Axis::Z(sg) => (0, 1, sg),
                Axis::General(_) => unreachable!("FastChain::batchable excludes general axes"),
            };
            for row in r.iter_mut() {
                for l in 0..LANES {
                    let ss = sg * s[l];
                    let (ra, rb) = (row[a][l], row[b][l]);
                    row[a][l] = ra * c[l] + rb * ss;
                    row[b][l] = rb * c[l] - ra * ss;
                }
            }
        }
        // compose(tail): rot = r · tail.rot, pos = r · tail.pos + p.
        let rot = ml_mul_m(&r, &self.tail.rot);
        let tp = ml_mul_v(&r, &self.tail.pos);
        let mut pos = [[0.0; LANES]; 3];
        for (i, v) in pos.iter_mut().enumerate() {
            for l in 0..LANES {
                v[l] = tp[i][l] + p[i][l];
            }
        }
        ToolBatch {
            rot,
            pos,
            s: s_out,
            c: c_out,
        }
    }

    /// Tool poses of the [`LANES`] joint vectors `q[j][lane]` (rad) in lockstep on the
    /// instruction set `level` ([`crate::simd`]), lane by lane bit-identical to
    /// [`FastChain::tool_with_sincos`]. Only for a [`FastChain::batchable`] chain (panics
    /// otherwise: a programming error, the callers check).
    pub fn tool_batch(&self, q: &[Lanes; MAX_DOF], level: Level) -> ToolBatch {
        assert!(
            self.batchable(),
            "tool_batch on a chain it does not apply to"
        );
        crate::simd::run(
            level,
            #[inline(always)]
            || self.tool_lanes(q),
        )
    }
}

/// Largest difference (m, and dimensionless for a rotation matrix's entries, in the Frobenius
/// norm) between the pose [`FastChain::check_lanes`] measures against and
/// [`FastChain::tool_with_sincos`]'s, for chains [`FastChain::batchable`] and poses within a
/// few metres of the base: the same sines and cosines, the same products save for terms that
/// are exactly zero, in another order (a few dozen roundings of numbers ≤ 4 in magnitude,
/// ≲ 1e-14), and the tool's rotation moved to the target's side (its orthogonality error,
/// ≲ 1e-15). 1e-12 leaves a hundredfold margin; `tests/simd.rs` measures it.
pub const CHECK_POSE_BOUND: f64 = 1e-12;

/// What [`FastChain::check_lanes`] measures of [`LANES`] tool poses against their targets.
#[derive(Clone, Copy, Debug)]
pub struct CheckLanes {
    /// Squared position error, m² (of a pose within [`CHECK_POSE_BOUND`] of the exact one).
    pub dp2: Lanes,
    /// Squared Frobenius distance of the rotations (of a pose within [`CHECK_POSE_BOUND`]).
    pub f2: Lanes,
    /// `sin q_j`, bit for bit [`FastChain::tool_with_sincos`]'s.
    pub s: [Lanes; MAX_DOF],
    /// `cos q_j`, likewise.
    pub c: [Lanes; MAX_DOF],
}

/// Rotate columns `A` and `B` of `r` by the angle with sine `sg · s` and cosine `c`
/// ([`rot_cols`] in registers).
#[inline(always)]
fn rot_cols_reg<R: F64s, const A: usize, const B: usize>(r: &mut [[R; 3]; 3], s: R, c: R, sg: f64) {
    let ss = R::splat(sg).mul(s);
    for row in r.iter_mut() {
        let (ra, rb) = (row[A], row[B]);
        row[A] = ra.mul(c).add(rb.mul(ss));
        row[B] = rb.mul(c).sub(ra.mul(ss));
    }
}

impl FastChain {
    /// The position and rotation errors of [`FastChain::check_lanes`] in registers of `T`,
    /// chunk by chunk of the lanes.
    #[inline(always)]
    fn check_errors<T: F64s>(
        &self,
        s: &[Lanes; MAX_DOF],
        c: &[Lanes; MAX_DOF],
        m: &crate::math::M3,
        tp: &[Lanes; 3],
        dp2: &mut Lanes,
        f2: &mut Lanes,
    ) {
        for h in (0..LANES).step_by(T::W) {
            let (one, zero) = (T::splat(1.0), T::splat(0.0));
            let mut r = [[one, zero, zero], [zero, one, zero], [zero, zero, one]];
            let mut p = [zero; 3];
            for (i, j) in self.joints[..self.n].iter().enumerate() {
                // p += r · pos, the exactly-zero components of pos skipped.
                for k in 0..3 {
                    let v = j.pos[k];
                    if v != 0.0 {
                        let v = T::splat(v);
                        for (pr, rr) in p.iter_mut().zip(&r) {
                            *pr = pr.add(rr[k].mul(v));
                        }
                    }
                }
                if let Some(o) = &j.rot {
                    let mut out = [[zero; 3]; 3];
                    for (orow, rr) in out.iter_mut().zip(&r) {
                        for (col, oc) in orow.iter_mut().enumerate() {
                            *oc = rr[0]
                                .mul(T::splat(o[(0, col)]))
                                .add(rr[1].mul(T::splat(o[(1, col)])))
                                .add(rr[2].mul(T::splat(o[(2, col)])));
                        }
                    }
                    r = out;
                }
                let (sv, cv) = (T::load(&s[i][h..]), T::load(&c[i][h..]));
                match j.axis {
                    Axis::X(sg) => rot_cols_reg::<T, 1, 2>(&mut r, sv, cv, sg),
                    Axis::Y(sg) => rot_cols_reg::<T, 2, 0>(&mut r, sv, cv, sg),
                    Axis::Z(sg) => rot_cols_reg::<T, 0, 1>(&mut r, sv, cv, sg),
                    Axis::General(_) => unreachable!("FastChain::batchable excludes general axes"),
                }
            }
            // The tool: p + r · tail.pos against tp; r · tail.rot against the target
            // rotation R as r against R · tail.rotᵀ (= m).
            let tpos = self.tail.pos;
            let (tx, ty, tz) = (T::splat(tpos.x), T::splat(tpos.y), T::splat(tpos.z));
            let mut d2 = zero;
            let mut e2 = zero;
            for (row, (pr, rr)) in p.iter().zip(&r).enumerate() {
                let x = pr
                    .add(rr[0].mul(tx).add(rr[1].mul(ty)).add(rr[2].mul(tz)))
                    .sub(T::load(&tp[row][h..]));
                d2 = d2.add(x.mul(x));
                for (col, rc) in rr.iter().enumerate() {
                    let d = rc.sub(T::splat(m[(row, col)]));
                    e2 = e2.add(d.mul(d));
                }
            }
            d2.store(&mut dp2[h..]);
            e2.store(&mut f2[h..]);
        }
    }

    /// The rotation [`FastChain::check_lanes`] compares against for tool poses of the
    /// rotation `rot`: `rot · tail.rotᵀ` (the tool's fixed rotation moved to the target's
    /// side).
    pub fn check_rotation(&self, rot: &crate::math::M3) -> crate::math::M3 {
        rot * self.tail.rot.transpose()
    }

    /// For the FK re-check of [`LANES`] joint vectors `q[j][lane]` (rad) against tool poses
    /// of a common rotation `R` (`check_rot` = [`FastChain::check_rotation`]`(R)`) and the
    /// positions `tp[i][lane]` (m), in lockstep on `level`: the squared position and rotation errors of a tool pose within
    /// [`CHECK_POSE_BOUND`] of [`FastChain::tool_with_sincos`]'s (not the same bits: only a
    /// verdict with that much room may rest on them), and the joints' sines and cosines bit
    /// for bit. Only for a [`FastChain::batchable`] chain (panics otherwise: a programming
    /// error, the callers check).
    pub fn check_lanes(
        &self,
        q: &[Lanes; MAX_DOF],
        check_rot: &crate::math::M3,
        tp: &[Lanes; 3],
        level: Level,
    ) -> CheckLanes {
        assert!(
            self.batchable(),
            "check_lanes on a chain it does not apply to"
        );
        struct K<'a> {
            chain: &'a FastChain,
            q: &'a [Lanes; MAX_DOF],
            m: &'a crate::math::M3,
            tp: &'a [Lanes; 3],
        }
        impl crate::simd::Kernel for K<'_> {
            type Out = CheckLanes;
            #[inline(always)]
            fn run<R: F64s>(self) -> CheckLanes {
                self.chain
                    .measure_then::<R, _>(self.q, self.m, self.tp, |c| *c)
            }
        }
        crate::simd::dispatch(
            level,
            K {
                chain: self,
                q,
                m: check_rot,
                tp,
            },
        )
    }

    /// [`FastChain::check_lanes`] on the registers `R`, handed to `then` in place (a
    /// returned [`CheckLanes`] is copied even when inlined: a kilobyte per call). Inlined into
    /// the caller's kernel, so it runs on the caller's instruction set.
    #[inline(always)]
    pub(crate) fn measure_then<R: F64s, T>(
        &self,
        q: &[Lanes; MAX_DOF],
        check_rot: &crate::math::M3,
        tp: &[Lanes; 3],
        then: impl FnOnce(&CheckLanes) -> T,
    ) -> T {
        let mut out = CheckLanes {
            dp2: [0.0; LANES],
            f2: [0.0; LANES],
            s: [[0.0; LANES]; MAX_DOF],
            c: [[1.0; LANES]; MAX_DOF],
        };
        for (i, qi) in q.iter().enumerate().take(self.n) {
            (out.s[i], out.c[i]) = crate::fastmath::sin_cos_lanes_tiny_in_kernel(qi);
        }
        self.check_errors::<R>(&out.s, &out.c, check_rot, tp, &mut out.dp2, &mut out.f2);
        then(&out)
    }
}
