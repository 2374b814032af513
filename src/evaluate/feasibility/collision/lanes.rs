//! [`check_bodies`](crate::evaluate::feasibility::collision::check_bodies) of [`LANES`] samples in lockstep, for the case that
//! dominates a placement evaluation: an arm whose joints turn about coordinate axes and whose
//! shapes (the print head aside) are capsules.
//!
//! The bodies' frames, each capsule's axis at its pose, its box, its gap from the bed's box,
//! whether its box meets the root of the beads' hierarchy, and the self pairs' boxes are
//! computed lane by lane with the operations [`RobotShapes::body_frames_into`] and
//! `check_with` run on one sample, in the same order (plain IEEE arithmetic, minima and
//! comparisons as nalgebra and parry take them): every number is the per-sample one, bit for
//! bit. [`CollisionLanes::replay`] then takes one lane through `check_with`'s steps (the bed
//! clearance in shape order from the running one, the closed-form clearance
//! [`Bed::axis_above`] from the kept axis ends where a shape's gap reaches it); a lane that
//! needs anything more (a GJK distance, a contact, a box meeting the part's or another
//! shape's box, a NaN) is handed back to the caller, who runs the per-sample check on it. So
//! the verdict, message and bed clearance are those of the per-sample check, by construction.
//!
//! The lanes are computed a register's width at a time (`C` lanes: 8 on AVX-512, 4 on AVX2,
//! 2 otherwise), the frames carried from joint to joint as register values, each body's
//! shapes placed as its frame is made (no spills of the frames, no loop over
//! every shape at every body, no lane-by-lane bit packing; the numbers are the same).

use crate::evaluate::feasibility::collision::{
    on_floor_check, Beads, Bed, Floor, RobotShapes, Role, Turn, SPHERE_MARGIN_M,
};
use crate::kinematics::fk::Axis;
use crate::kinematics::MAX_DOF;
use crate::math::Frame;
use crate::simd::LANES;

/// Shapes the lockstep check takes (more go the per-sample way).
pub(crate) const MAX_SHAPES: usize = 16;

/// One value per lane.
type L = [f64; LANES];

/// The results of [`CollisionLanes::compute`] for up to [`LANES`] samples.
#[derive(Clone)]
pub(crate) struct CollisionLanes {
    /// Per shape: the gap of its box from the bed's box, m.
    gap: [L; MAX_SHAPES],
    /// Per shape: its capsule axis's ends at its pose (x, y, z of the first end, then of the
    /// second; part frame, m).
    ends: [[L; 6]; MAX_SHAPES],
    /// Per shape: its capsule's radius, m.
    rad: [f64; MAX_SHAPES],
    /// Per lane: the smallest gap (m) of the shapes in `order` (`+∞` without any).
    low: L,
    /// Bit `l`: some self pair's boxes meet in lane `l`, some shape's box meets the beads'
    /// root, or lane `l` holds a NaN (the per-sample way).
    exact: u32,
    /// The bed's box (part frame, m).
    bed_lo: [f64; 3],
    bed_hi: [f64; 3],
    /// The shapes checked against the bed and the part (all but the print head), in order.
    order: [u8; MAX_SHAPES],
    count: usize,
    /// The floor ([`Bed::floor`]) and the shapes checked against it (bit `i`: shape `i`).
    floor: Option<Floor>,
    on_floor: u32,
    /// Scratch: every shape's box (corners, m) per lane.
    lo: [[L; 3]; MAX_SHAPES],
    hi: [[L; 3]; MAX_SHAPES],
}

impl Default for CollisionLanes {
    fn default() -> Self {
        CollisionLanes {
            gap: [[0.0; LANES]; MAX_SHAPES],
            ends: [[[0.0; LANES]; 6]; MAX_SHAPES],
            rad: [0.0; MAX_SHAPES],
            low: [f64::INFINITY; LANES],
            exact: 0,
            bed_lo: [0.0; 3],
            bed_hi: [0.0; 3],
            order: [0; MAX_SHAPES],
            count: 0,
            floor: None,
            on_floor: 0,
            lo: [[[0.0; LANES]; 3]; MAX_SHAPES],
            hi: [[[0.0; LANES]; 3]; MAX_SHAPES],
        }
    }
}

impl RobotShapes {
    /// Whether [`CollisionLanes::compute`] takes this arm: at most [`MAX_DOF`] revolute joints
    /// about coordinate axes, at most [`MAX_SHAPES`] shapes, every shape other than the print
    /// head a capsule.
    pub fn lockstep(&self) -> bool {
        self.chain.joints.len() <= MAX_DOF
            && self
                .chain
                .joints
                .iter()
                .all(|j| matches!(j.turn, Turn::Revolute(Axis::X(_) | Axis::Y(_) | Axis::Z(_))))
            && self.shapes.len() <= MAX_SHAPES
            && self
                .shapes
                .iter()
                .all(|s| s.role == Role::Head || s.axis_body.is_some())
    }
}

/// What a shape's box is tested against ([`CollisionLanes::place`]).
struct Around {
    /// The bed's box corners (m).
    bed: ([f64; 3], [f64; 3]),
    /// The corners of the beads' root box (m).
    root: ([f64; 3], [f64; 3]),
    /// Bit `l`: some bead is laid at lane `l`'s sample.
    laid: u32,
}

/// The register types' raw operations ([`crate::simd::V`]), public for the tests that compare
/// each register type with the scalar operations; the kernels here take [`F64s`].
pub mod reg {
    pub use crate::simd::V;
}

use crate::simd::F64s;

/// `m · v` per lane, in nalgebra's order (`(m₀ v₀ + m₁ v₁) + m₂ v₂` per row), plus `p`.
#[inline(always)]
fn mul_add<T: F64s>(rot: &[T; 9], v: &crate::math::V3, p: &[T; 3]) -> [T; 3] {
    let (x, y, z) = (T::splat(v.x), T::splat(v.y), T::splat(v.z));
    let row = |r: usize| {
        rot[3 * r]
            .mul(x)
            .add(rot[3 * r + 1].mul(y))
            .add(rot[3 * r + 2].mul(z))
            .add(p[r])
    };
    [row(0), row(1), row(2)]
}

/// `rot · m` per lane (each entry `(r₀ m₀ + r₁ m₁) + r₂ m₂`, as nalgebra multiplies).
#[inline(always)]
fn mul_rot<T: F64s>(rot: &[T; 9], m: &crate::math::M3) -> [T; 9] {
    let mut out = *rot;
    for row in 0..3 {
        for col in 0..3 {
            out[3 * row + col] = rot[3 * row]
                .mul(T::splat(m[(0, col)]))
                .add(rot[3 * row + 1].mul(T::splat(m[(1, col)])))
                .add(rot[3 * row + 2].mul(T::splat(m[(2, col)])));
        }
    }
    out
}

/// Turn columns `A` and `B` of `r` by the angle with sine `sg · s` and cosine `c` per lane
/// ([`Axis::rotate`]'s operations; the columns as constants, so the frame stays in registers).
#[inline(always)]
fn rot_cols<T: F64s, const A: usize, const B: usize>(r: &mut [T; 9], s: T, c: T, sg: f64) {
    let s = T::splat(sg).mul(s);
    for row in 0..3 {
        let (ra, rb) = (r[3 * row + A], r[3 * row + B]);
        r[3 * row + A] = ra.mul(c).add(rb.mul(s));
        r[3 * row + B] = rb.mul(c).sub(ra.mul(s));
    }
}

impl CollisionLanes {
    /// Every lane's numbers (see the module docs), a register of `T` at a time (every `T`
    /// gives the same numbers). `sincos[j]` / `sincos[n + j]`: joint `j`'s sine / cosine per
    /// lane; `world`: the robot base in the part frame; `laid`: the beads laid at each lane's
    /// sample. For an arm [`RobotShapes::lockstep`] takes.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // parallel fixed arrays indexed by lane
    pub(crate) fn compute<T: F64s>(
        &mut self,
        rs: &RobotShapes,
        sincos: &[L],
        world: &Frame,
        bed: &Bed,
        beads: &Beads,
        laid: &[usize; LANES],
    ) {
        let n = rs.chain.joints.len();
        // NaN lanes go the per-sample way.
        let mut nan = [0u64; LANES];
        for v in &sincos[..2 * n] {
            for l in 0..LANES {
                nan[l] |= v[l].is_nan() as u64;
            }
        }
        let mut exact = 0u32;
        for l in 0..LANES {
            exact |= ((nan[l] != 0) as u32) << l;
        }
        // Beads::root_meets: some bead laid and the root's box meets the shape's.
        let mut at = Around {
            bed: (bed.aabb.mins.coords.into(), bed.aabb.maxs.coords.into()),
            root: ([0.0; 3], [0.0; 3]),
            laid: 0,
        };
        if let Some(r) = beads.nodes.first() {
            at.root = (r.aabb.mins.coords.into(), r.aabb.maxs.coords.into());
            for (l, &n) in laid.iter().enumerate() {
                at.laid |= u32::from(n > 0 && (r.start as usize) < n) << l;
            }
        }
        (self.bed_lo, self.bed_hi) = at.bed;
        // Each body's shapes; the order of the bed and part checks.
        let last = n + 1;
        let mut on_body = [0u32; MAX_DOF + 2];
        self.count = 0;
        self.floor = bed.floor;
        self.on_floor = 0;
        for (i, s) in rs.shapes.iter().enumerate().take(MAX_SHAPES) {
            self.on_floor |= u32::from(on_floor_check(s)) << i;
            on_body[s.body.min(last)] |= 1 << i;
            self.rad[i] = s.axis_body.map_or(0.0, |a| a.2);
            if s.role != Role::Head {
                self.order[self.count] = i as u8;
                self.count += 1;
            }
        }
        for off in (0..LANES).step_by(T::W) {
            exact |= self.chunk::<T>(rs, off, sincos, world, &at, &on_body) << off;
        }
        self.exact = exact;
    }

    /// [`CollisionLanes::compute`] of lanes `off..off + T::W`: the bodies' frames
    /// ([`RobotShapes::body_frames_into`]'s operations), each body's shapes placed as its
    /// frame is made, then the self pairs' boxes. Returns bit `l`: lane `off + l` goes the
    /// per-sample way (a self pair's boxes or a shape's box and the beads' root meet).
    #[inline(always)]
    fn chunk<T: F64s>(
        &mut self,
        rs: &RobotShapes,
        off: usize,
        sincos: &[L],
        world: &Frame,
        at: &Around,
        on_body: &[u32; MAX_DOF + 2],
    ) -> u32 {
        let n = rs.chain.joints.len();
        let mut r = [T::splat(0.0); 9];
        for (i, e) in r.iter_mut().enumerate() {
            *e = T::splat(world.rot[(i / 3, i % 3)]);
        }
        let mut p = [T::splat(0.0); 3];
        for (i, e) in p.iter_mut().enumerate() {
            *e = T::splat(world.pos[i]);
        }
        let mut low = T::splat(f64::INFINITY);
        let laid = at.laid >> off;
        let mut exact = self.place::<T>(rs, on_body[0], off, &r, &p, at, laid, &mut low);
        for (i, j) in rs.chain.joints.iter().enumerate() {
            p = mul_add(&r, &j.pos, &p);
            if let Some(o) = &j.rot {
                r = mul_rot(&r, o);
            }
            let (s, c) = (T::load(&sincos[i][off..]), T::load(&sincos[n + i][off..]));
            match j.turn {
                Turn::Revolute(Axis::X(sg)) => rot_cols::<T, 1, 2>(&mut r, s, c, sg),
                Turn::Revolute(Axis::Y(sg)) => rot_cols::<T, 2, 0>(&mut r, s, c, sg),
                Turn::Revolute(Axis::Z(sg)) => rot_cols::<T, 0, 1>(&mut r, s, c, sg),
                // RobotShapes::lockstep refuses every other joint.
                _ => rot_cols::<T, 0, 1>(&mut r, s, c, f64::NAN),
            }
            exact |= self.place::<T>(rs, on_body[i + 1], off, &r, &p, at, laid, &mut low);
        }
        let fl = &rs.chain.flange;
        let fp = mul_add(&r, &fl.pos, &p);
        let fr = mul_rot(&r, &fl.rot);
        exact |= self.place::<T>(rs, on_body[n + 1], off, &fr, &fp, at, laid, &mut low);
        low.store(&mut self.low[off..]);
        // Self pairs' boxes.
        let (lo, hi) = (&self.lo, &self.hi);
        for &(i, j) in &rs.pairs {
            let mut hit = u32::MAX;
            for k in 0..3 {
                hit &= T::le_ge(
                    T::load(&lo[i][k][off..]),
                    T::load(&hi[j][k][off..]),
                    T::load(&hi[i][k][off..]),
                    T::load(&lo[j][k][off..]),
                );
            }
            exact |= hit;
        }
        exact & (u32::MAX >> (32 - T::W))
    }

    /// The boxes, bed gaps, axis ends and root tests of the shapes `mask` (bit `i`: shape
    /// `i`) on one body (its frame per lane: `rot`, `pos`) for lanes `off..off + T::W`, as
    /// [`CollisionLanes::compute`] describes; `low` takes the smallest gaps. Returns bit `l`:
    /// lane `off + l`'s box of some shape meets the beads' root where `laid` (bit `l`) says
    /// a bead is laid.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    #[allow(clippy::needless_range_loop)] // parallel fixed arrays indexed by axis
    fn place<T: F64s>(
        &mut self,
        rs: &RobotShapes,
        mask: u32,
        off: usize,
        rot: &[T; 9],
        pos: &[T; 3],
        at: &Around,
        laid: u32,
        low: &mut T,
    ) -> u32 {
        let (blo, bhi) = &at.bed;
        let (rlo, rhi) = &at.root;
        let mut exact = 0;
        let mut m = mask;
        while m != 0 {
            let i = m.trailing_zeros() as usize;
            m &= m - 1;
            let s = &rs.shapes[i];
            if s.role == Role::Head {
                let c = mul_add(rot, &s.centre_body, pos);
                let rad = T::splat(s.bound.1 + SPHERE_MARGIN_M);
                for k in 0..3 {
                    c[k].sub(rad).store(&mut self.lo[i][k][off..]);
                    c[k].add(rad).store(&mut self.hi[i][k][off..]);
                }
                continue;
            }
            let Some((a, b, rad)) = s.axis_body else {
                continue;
            };
            let pa = if a == crate::math::V3::zeros() {
                *pos
            } else {
                mul_add(rot, &a, pos)
            };
            let pb = mul_add(rot, &b, pos);
            let rad = T::splat(rad);
            let zero = T::splat(0.0);
            let mut gap2 = zero;
            let mut meets = u32::MAX;
            for k in 0..3 {
                // Capsule::local_aabb (nalgebra's inf / sup: selects).
                let mn = pa[k].inf(pb[k]).sub(rad);
                let mx = pa[k].sup(pb[k]).add(rad);
                mn.store(&mut self.lo[i][k][off..]);
                mx.store(&mut self.hi[i][k][off..]);
                pa[k].store(&mut self.ends[i][k][off..]);
                pb[k].store(&mut self.ends[i][3 + k][off..]);
                // aabb_gap's terms, added in axis order.
                let d = T::splat(blo[k])
                    .sub(mx)
                    .max(mn.sub(T::splat(bhi[k])))
                    .max(zero);
                gap2 = gap2.add(d.mul(d));
                if laid != 0 {
                    meets &= T::le_ge(mn, T::splat(rhi[k]), mx, T::splat(rlo[k]));
                }
            }
            let g = gap2.sqrt();
            g.store(&mut self.gap[i][off..]);
            *low = g.lt_min(*low);
            if laid != 0 {
                exact |= meets & laid;
            }
        }
        exact
    }

    /// Lane `l` through the per-sample check's steps from the running bed clearance
    /// `clearance` (m): `true` when the per-sample check would find nothing and leave
    /// `clearance` as it is left here; `false` (and `clearance` untouched) when the lane
    /// needs the per-sample check (see the module docs).
    #[inline]
    // `!(low <= c)`: the negated comparison is the NaN rule (as the per-shape test's).
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    pub(crate) fn replay(&self, l: usize, clearance: &mut Option<f64>) -> bool {
        if self.exact >> l & 1 != 0 {
            return false;
        }
        // The floor, as the per-sample check takes it (a shape below it goes that way).
        if let Some(f) = &self.floor {
            for &i in &self.order[..self.count] {
                let i = i as usize;
                if self.on_floor >> i & 1 != 0 {
                    let e = &self.ends[i];
                    let a = parry3d_f64::math::Point::new(e[0][l], e[1][l], e[2][l]);
                    let b = parry3d_f64::math::Point::new(e[3][l], e[4][l], e[5][l]);
                    if !(f.axis_clearance(&a, &b, self.rad[i]) >= 0.0) {
                        return false;
                    }
                }
            }
        }
        // Most samples: no shape's gap reaches the running clearance, which stays as it is.
        if !(self.low[l] <= clearance.unwrap_or(f64::INFINITY)) {
            return true;
        }
        let (lo, hi) = (&self.bed_lo, &self.bed_hi);
        let mut c = *clearance;
        for &i in &self.order[..self.count] {
            let i = i as usize;
            if self.gap[i][l] <= c.unwrap_or(f64::INFINITY) {
                // Bed::axis_above of the capsule's axis.
                let e = &self.ends[i];
                let inside = |x: f64, y: f64, z: f64| {
                    x >= lo[0] && x <= hi[0] && y >= lo[1] && y <= hi[1] && z >= hi[2]
                };
                if !(inside(e[0][l], e[1][l], e[2][l]) && inside(e[3][l], e[4][l], e[5][l])) {
                    return false;
                }
                let d = (e[2][l].min(e[5][l]) - hi[2] - self.rad[i]).max(0.0);
                c = Some(c.map_or(d, |x| x.min(d)));
                if d <= 0.0 {
                    return false;
                }
            }
        }
        *clearance = c;
        true
    }
}
