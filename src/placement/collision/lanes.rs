//! [`check_bodies`](super::check_bodies) of [`LANES`] samples in lockstep, for the case that
//! dominates a placement evaluation: an arm whose joints turn about coordinate axes and whose
//! shapes (the print head aside) are capsules.
//!
//! The bodies' frames, each capsule's axis at its pose, its box, its gap from the bed's box,
//! its closed-form bed clearance ([`Bed::axis_above`]), whether its box meets the root of the
//! beads' hierarchy, and the self pairs' boxes are computed lane by lane with the operations
//! [`RobotShapes::body_frames_into`] and `check_with` run on one sample, in the same order
//! (plain IEEE arithmetic, minima and comparisons as nalgebra and parry take them): every
//! number is the per-sample one, bit for bit. [`CollisionLanes::replay`] then takes one lane
//! through `check_with`'s steps (the bed clearance in shape order from the running one); a
//! lane that needs anything more (a GJK distance, a contact, a box meeting the part's or
//! another shape's box, a NaN) is handed back to the caller, who runs the per-sample check
//! on it. So the verdict, message and bed clearance are those of the per-sample check, by
//! construction.

use super::{Beads, Bed, RobotShapes, Role, Turn, SPHERE_MARGIN_M};
use crate::kinematics::fk::Axis;
use crate::kinematics::MAX_DOF;
use crate::math::Frame;
use crate::simd::LANES;

/// Shapes the lockstep check takes (more go the per-sample way).
pub const MAX_SHAPES: usize = 16;

/// One value per lane.
type L = [f64; LANES];

/// A frame per lane: the rotation's entries row-major (`rot[3 r + c]`) and the position.
#[derive(Clone, Copy)]
struct FrameLanes {
    rot: [L; 9],
    pos: [L; 3],
}

/// The results of [`CollisionLanes::compute`] for up to [`LANES`] samples.
#[derive(Clone)]
pub struct CollisionLanes {
    /// Per shape: the gap of its box from the bed's box, m.
    gap: [L; MAX_SHAPES],
    /// Per shape: its closed-form bed clearance, m, where `above` is set.
    clear: [L; MAX_SHAPES],
    /// Per shape, bit `l`: lane `l`'s capsule axis lies above the bed's top face.
    above: [u32; MAX_SHAPES],
    /// Per shape, bit `l`: lane `l`'s box meets the root of the beads' hierarchy.
    root: [u32; MAX_SHAPES],
    /// Bit `l`: some self pair's boxes meet in lane `l`, or lane `l` holds a NaN.
    exact: u32,
    /// Scratch: the bodies' frames and every shape's box (corners, m) per lane.
    frames: [FrameLanes; MAX_DOF + 2],
    lo: [[L; 3]; MAX_SHAPES],
    hi: [[L; 3]; MAX_SHAPES],
}

impl Default for CollisionLanes {
    fn default() -> Self {
        CollisionLanes {
            gap: [[0.0; LANES]; MAX_SHAPES],
            clear: [[0.0; LANES]; MAX_SHAPES],
            above: [0; MAX_SHAPES],
            root: [0; MAX_SHAPES],
            exact: 0,
            frames: [FrameLanes {
                rot: [[0.0; LANES]; 9],
                pos: [[0.0; LANES]; 3],
            }; MAX_DOF + 2],
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

/// `m · v` per lane, in nalgebra's order (`(m₀ v₀ + m₁ v₁) + m₂ v₂` per row), plus `p`.
#[inline(always)]
fn mul_add(rot: &[L; 9], v: &crate::math::V3, p: &[L; 3]) -> [L; 3] {
    let mut out = [[0.0; LANES]; 3];
    for (r, o) in out.iter_mut().enumerate() {
        for l in 0..LANES {
            let t = rot[3 * r][l] * v.x + rot[3 * r + 1][l] * v.y + rot[3 * r + 2][l] * v.z;
            o[l] = t + p[r][l];
        }
    }
    out
}

impl CollisionLanes {
    /// Every lane's numbers (see the module docs). `sincos[j]` / `sincos[n + j]`: joint `j`'s
    /// sine / cosine per lane; `world`: the robot base in the part frame; `laid`: the beads
    /// laid at each lane's sample. For an arm [`RobotShapes::lockstep`] takes.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // parallel fixed arrays indexed by lane
    pub fn compute(
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
        let mut nan = [false; LANES];
        for v in &sincos[..2 * n] {
            for l in 0..LANES {
                nan[l] |= v[l].is_nan();
            }
        }
        // The bodies' frames (body_frames_into's operations).
        let frames = &mut self.frames;
        let mut r = [[0.0; LANES]; 9];
        for (i, e) in r.iter_mut().enumerate() {
            *e = [world.rot[(i / 3, i % 3)]; LANES];
        }
        let mut p = [[0.0; LANES]; 3];
        for (i, e) in p.iter_mut().enumerate() {
            *e = [world.pos[i]; LANES];
        }
        frames[0] = FrameLanes { rot: r, pos: p };
        for (i, j) in rs.chain.joints.iter().enumerate() {
            p = mul_add(&r, &j.pos, &p);
            if let Some(o) = &j.rot {
                let old = r;
                for row in 0..3 {
                    for col in 0..3 {
                        for l in 0..LANES {
                            r[3 * row + col][l] = old[3 * row][l] * o[(0, col)]
                                + old[3 * row + 1][l] * o[(1, col)]
                                + old[3 * row + 2][l] * o[(2, col)];
                        }
                    }
                }
            }
            let (a, b, sg) = match j.turn {
                Turn::Revolute(Axis::X(sg)) => (1, 2, sg),
                Turn::Revolute(Axis::Y(sg)) => (2, 0, sg),
                Turn::Revolute(Axis::Z(sg)) => (0, 1, sg),
                // RobotShapes::lockstep refuses every other joint.
                _ => (0, 1, f64::NAN),
            };
            let (s, c) = (&sincos[i], &sincos[n + i]);
            for row in 0..3 {
                for l in 0..LANES {
                    let s = sg * s[l];
                    let (ra, rb) = (r[3 * row + a][l], r[3 * row + b][l]);
                    r[3 * row + a][l] = ra * c[l] + rb * s;
                    r[3 * row + b][l] = rb * c[l] - ra * s;
                }
            }
            frames[i + 1] = FrameLanes { rot: r, pos: p };
        }
        let fl = &rs.chain.flange;
        let mut fr = [[0.0; LANES]; 9];
        for row in 0..3 {
            for col in 0..3 {
                for l in 0..LANES {
                    fr[3 * row + col][l] = r[3 * row][l] * fl.rot[(0, col)]
                        + r[3 * row + 1][l] * fl.rot[(1, col)]
                        + r[3 * row + 2][l] * fl.rot[(2, col)];
                }
            }
        }
        frames[n + 1] = FrameLanes {
            rot: fr,
            pos: mul_add(&r, &fl.pos, &p),
        };
        // Each shape's box (a capsule's from its axis, the print head's from its bounding
        // sphere), the bed and the beads' root.
        let (lo, hi) = (&mut self.lo, &mut self.hi);
        let (blo, bhi) = (&bed.aabb.mins, &bed.aabb.maxs);
        // Beads::root_meets: some bead laid and the root's box meets the shape's.
        let (rlo, rhi, laid_any) = match beads.nodes.first() {
            Some(r) => {
                let mut any = 0u32;
                for (l, &n) in laid.iter().enumerate() {
                    any |= u32::from(n > 0 && (r.start as usize) < n) << l;
                }
                (r.aabb.mins, r.aabb.maxs, any)
            }
            None => (Default::default(), Default::default(), 0),
        };
        for (i, s) in rs.shapes.iter().enumerate() {
            let f = &frames[s.body.min(n + 1)];
            if s.role == Role::Head {
                let c = mul_add(&f.rot, &s.centre_body, &f.pos);
                let rad = s.bound.1 + SPHERE_MARGIN_M;
                for k in 0..3 {
                    for l in 0..LANES {
                        lo[i][k][l] = c[k][l] - rad;
                        hi[i][k][l] = c[k][l] + rad;
                    }
                }
                continue;
            }
            let Some((a, b, rad)) = s.axis_body else {
                continue;
            };
            let pa = if a == crate::math::V3::zeros() {
                f.pos
            } else {
                mul_add(&f.rot, &a, &f.pos)
            };
            let pb = mul_add(&f.rot, &b, &f.pos);
            let mut gap2 = [0.0; LANES];
            // All-ones per lane while the test holds (masks vectorise where bools do not).
            let (mut inside, mut meets) = ([!0u64; LANES], [!0u64; LANES]);
            for k in 0..3 {
                let (mut mn, mut mx) = ([0.0; LANES], [0.0; LANES]);
                for l in 0..LANES {
                    // Capsule::local_aabb (nalgebra's inf / sup: selects).
                    let (x, y) = (pa[k][l], pb[k][l]);
                    mn[l] = (if x <= y { x } else { y }) - rad;
                    mx[l] = (if x >= y { x } else { y }) + rad;
                }
                lo[i][k] = mn;
                hi[i][k] = mx;
                for l in 0..LANES {
                    // aabb_gap's terms, added in axis order.
                    let d = (blo[k] - mx[l]).max(mn[l] - bhi[k]).max(0.0);
                    gap2[l] += d * d;
                }
                for l in 0..LANES {
                    let (x, y) = (pa[k][l], pb[k][l]);
                    // Bed::axis_above's footprint test.
                    let t = if k < 2 {
                        (x >= blo[k]) & (x <= bhi[k]) & (y >= blo[k]) & (y <= bhi[k])
                    } else {
                        (x >= bhi[k]) & (y >= bhi[k])
                    };
                    inside[l] &= (t as u64).wrapping_neg();
                    let t = (mn[l] <= rhi[k]) & (mx[l] >= rlo[k]);
                    meets[l] &= (t as u64).wrapping_neg();
                }
            }
            let (mut above, mut at_root) = (0u32, 0u32);
            for l in 0..LANES {
                self.gap[i][l] = gap2[l].sqrt();
                self.clear[i][l] = (pa[2][l].min(pb[2][l]) - bhi[2] - rad).max(0.0);
            }
            for l in 0..LANES {
                above |= ((inside[l] & 1) as u32) << l;
                at_root |= ((meets[l] & 1) as u32) << l;
            }
            (self.above[i], self.root[i]) = (above, at_root & laid_any);
        }
        // Self pairs' boxes.
        let mut exact = 0u32;
        for l in 0..LANES {
            exact |= u32::from(nan[l]) << l;
        }
        let mut hits = [0u64; LANES];
        for &(i, j) in &rs.pairs {
            let mut hit = [!0u64; LANES];
            for k in 0..3 {
                for l in 0..LANES {
                    let t = (lo[i][k][l] <= hi[j][k][l]) & (hi[i][k][l] >= lo[j][k][l]);
                    hit[l] &= (t as u64).wrapping_neg();
                }
            }
            for l in 0..LANES {
                hits[l] |= hit[l];
            }
        }
        for l in 0..LANES {
            exact |= ((hits[l] & 1) as u32) << l;
        }
        self.exact = exact;
    }

    /// Lane `l` through the per-sample check's steps from the running bed clearance
    /// `clearance` (m): `true` when the per-sample check would find nothing and leave
    /// `clearance` as it is left here; `false` (and `clearance` untouched) when the lane
    /// needs the per-sample check (see the module docs).
    pub fn replay(&self, rs: &RobotShapes, l: usize, clearance: &mut Option<f64>) -> bool {
        if self.exact >> l & 1 != 0 {
            return false;
        }
        let mut c = *clearance;
        for (i, s) in rs.shapes.iter().enumerate() {
            if s.role == Role::Head {
                continue;
            }
            if self.gap[i][l] <= c.unwrap_or(f64::INFINITY) {
                if self.above[i] >> l & 1 == 0 {
                    return false;
                }
                let d = self.clear[i][l];
                c = Some(c.map_or(d, |x| x.min(d)));
                if d <= 0.0 {
                    return false;
                }
            }
            if self.root[i] >> l & 1 != 0 {
                return false;
            }
        }
        *clearance = c;
        true
    }
}
