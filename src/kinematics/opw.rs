//! Closed-form inverse kinematics of ortho-parallel arms with a spherical wrist (Brandstötter,
//! Angerer, Hofbaur 2014; the algorithm of `opw_kinematics`), in URDF joint angles (rad).
//!
//! The solver works on the **flange** pose (`tool_link`) in the base frame. It does not apply
//! joint limits; [`super::fit_limits`] (used by [`super::IkSolver`]) does. Angles come back
//! wrapped to (−π, π]; the front end picks the 2π multiple within limits.

use super::IkFailure;
use crate::math::{Frame, M3, V3};
use crate::robot::OpwParams;
use std::f64::consts::PI;

/// Below this `|sin q5|` the wrist is treated as exactly singular: q4 is kept from the
/// reference and q6 takes up the whole rotation about the aligned axes (orientation error of
/// the answer ≤ this value, rad).
pub(crate) const WRIST_SINGULAR_SIN: f64 = 1e-9;

/// Tolerance on the cosine arguments before a pose counts as out of reach (rounding of a
/// fully stretched or folded arm).
const ACOS_SLACK: f64 = 1e-10;

/// Margin (rad) from 0 and π of the closed form's elbow angle `t3` and of `q5` beyond which
/// [`Prepared::branch_of`] of the answer gives the elbow and wrist of the branch it was solved
/// for, without computing it ([`BranchBatch::next_branch`]): `branch_of` reads the signs of
/// `q3 + ψ3 = ±t3` and `q5`, wrapped to (−π, π], recomputed from the URDF angles (a few ulp,
/// ≲ 1e-14 rad, from the conversion); 1e-6 leaves eight orders of magnitude.
const NEXT_BRANCH_MARGIN_RAD: f64 = 1e-6;

/// Margin, relative to the arm's reach `|c2| + κ`, of the distance `ρ` (m) of the wrist
/// centre from the axis of joint 1 beyond which `branch_of`'s shoulder is the branch's:
/// `branch_of` reads the sign of `c2 sin q2 + κ sin(q2 + q3 + ψ3) + a1`, which is `+ρ`
/// (front) or `−ρ` (back) up to the closed form's `acos` clamping (`ACOS_SLACK` = 1e-10:
/// angles off by ≤ √(2e-10) ≈ 1.5e-5 rad each, ≤ 3e-5 of the reach) and rounding; 1e-2
/// leaves a factor of 300.
const NEXT_BRANCH_MARGIN_REL: f64 = 1e-2;

/// Which side of joint 1 the wrist centre is on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shoulder {
    /// Wrist centre in front of the axis of joint 1 (the usual working side).
    Front,
    /// Joint 1 turned by ~π, the arm reaching over backwards.
    Back,
}

/// Sign of the elbow angle (the `acos` branch of joint 3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Elbow {
    /// `q3_opw + ψ3 ∈ [0, π]`: elbow up for the front shoulder (the zero pose of ABB/KUKA arms).
    Up,
    /// `q3_opw + ψ3 ∈ (−π, 0)`.
    Down,
}

/// Sign of joint 5.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Wrist {
    /// `sin q5_opw ≥ 0`.
    NoFlip,
    /// `sin q5_opw < 0` (q4 + π, −q5, q6 + π).
    Flip,
}

impl Wrist {
    /// The other wrist variant.
    pub fn flipped(self) -> Wrist {
        match self {
            Wrist::NoFlip => Wrist::Flip,
            Wrist::Flip => Wrist::NoFlip,
        }
    }
}

/// One of the 8 closed-form solution branches.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Branch {
    /// Shoulder front/back.
    pub shoulder: Shoulder,
    /// Elbow up/down.
    pub elbow: Elbow,
    /// Wrist flip.
    pub wrist: Wrist,
}

impl Branch {
    /// All 8 branches, in the order of [`Branch::index`].
    pub const ALL: [Branch; 8] = [
        Branch::new(Shoulder::Front, Elbow::Up, Wrist::NoFlip),
        Branch::new(Shoulder::Front, Elbow::Down, Wrist::NoFlip),
        Branch::new(Shoulder::Back, Elbow::Up, Wrist::NoFlip),
        Branch::new(Shoulder::Back, Elbow::Down, Wrist::NoFlip),
        Branch::new(Shoulder::Front, Elbow::Up, Wrist::Flip),
        Branch::new(Shoulder::Front, Elbow::Down, Wrist::Flip),
        Branch::new(Shoulder::Back, Elbow::Up, Wrist::Flip),
        Branch::new(Shoulder::Back, Elbow::Down, Wrist::Flip),
    ];

    /// Build a branch.
    pub const fn new(shoulder: Shoulder, elbow: Elbow, wrist: Wrist) -> Self {
        Branch {
            shoulder,
            elbow,
            wrist,
        }
    }

    /// Index 0..8 in the order of `opw_kinematics` (wrist·4 + shoulder·2 + elbow).
    pub fn index(self) -> usize {
        (matches!(self.wrist, Wrist::Flip) as usize) * 4
            + (matches!(self.shoulder, Shoulder::Back) as usize) * 2
            + matches!(self.elbow, Elbow::Down) as usize
    }

    /// Classify URDF joint angles `q` (rad; missing entries count as 0) into their branch. Invariant under
    /// 2π shifts of any joint.
    pub fn of(p: &OpwParams, q: &[f64]) -> Branch {
        let o = opw_angles(p, q);
        let psi3 = p.a2.atan2(p.c3);
        let k = (p.a2 * p.a2 + p.c3 * p.c3).sqrt();
        let cx1 = p.c2 * o[1].sin() + k * (o[1] + o[2] + psi3).sin() + p.a1;
        Branch {
            shoulder: if cx1 >= 0.0 {
                Shoulder::Front
            } else {
                Shoulder::Back
            },
            elbow: if (o[2] + psi3).sin() >= 0.0 {
                Elbow::Up
            } else {
                Elbow::Down
            },
            wrist: if o[4].sin() >= 0.0 {
                Wrist::NoFlip
            } else {
                Wrist::Flip
            },
        }
    }
}

impl std::fmt::Display for Branch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "shoulder {}, elbow {}, wrist {}",
            match self.shoulder {
                Shoulder::Front => "front",
                Shoulder::Back => "back",
            },
            match self.elbow {
                Elbow::Up => "up",
                Elbow::Down => "down",
            },
            match self.wrist {
                Wrist::NoFlip => "no flip",
                Wrist::Flip => "flip",
            }
        )
    }
}

/// Constants of the closed form that depend only on the OPW parameters, computed once (by
/// [`super::IkSolver::new`]) instead of per query: `κ = √(a2² + c3²)` (m), `κ²`, `c2²` (m²) and
/// `ψ3 = atan2(a2, c3)` (rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Prepared {
    kappa: f64,
    kappa2: f64,
    c22: f64,
    psi3: f64,
}

impl Prepared {
    /// The constants of `p`.
    pub fn new(p: &OpwParams) -> Self {
        let kappa2 = p.a2 * p.a2 + p.c3 * p.c3;
        Prepared {
            kappa: kappa2.sqrt(),
            kappa2,
            c22: p.c2 * p.c2,
            psi3: p.a2.atan2(p.c3),
        }
    }

    /// `ψ3 = atan2(a2, c3)`, rad.
    pub fn psi3(&self) -> f64 {
        self.psi3
    }

    /// [`Branch::of`] with the constants precomputed; the elbow and wrist signs come from
    /// wrapped angles instead of sines (same answer up to rounding at the boundaries).
    #[inline]
    pub fn branch_of(&self, p: &OpwParams, q: &[f64]) -> Branch {
        let o = opw_angles(p, q);
        let e = o[2] + self.psi3;
        let cx1 =
            p.c2 * crate::fastmath::sin(o[1]) + self.kappa * crate::fastmath::sin(o[1] + e) + p.a1;
        Branch {
            shoulder: if cx1 >= 0.0 {
                Shoulder::Front
            } else {
                Shoulder::Back
            },
            elbow: if wrap_pi(e) >= 0.0 {
                Elbow::Up
            } else {
                Elbow::Down
            },
            wrist: if wrap_pi(o[4]) >= 0.0 {
                Wrist::NoFlip
            } else {
                Wrist::Flip
            },
        }
    }
}

/// OPW angles of `q` (URDF, rad); missing entries are taken as 0.
#[inline]
fn opw_angles(p: &OpwParams, q: &[f64]) -> [f64; 6] {
    let mut a = [0.0; 6];
    for (d, s) in a.iter_mut().zip(q) {
        *d = *s;
    }
    p.to_opw(&a)
}

/// Wrap an angle to (−π, π].
#[inline]
pub fn wrap_pi(a: f64) -> f64 {
    let w = a - (2.0 * PI) * ((a + PI) / (2.0 * PI)).floor();
    // w in [−π, π); move −π to π.
    if w <= -PI {
        w + 2.0 * PI
    } else {
        w
    }
}

#[inline]
fn checked_acos(x: f64) -> Option<f64> {
    if x.is_nan() || x.abs() > 1.0 + ACOS_SLACK {
        None
    } else {
        Some(crate::fastmath::acos(x.clamp(-1.0, 1.0)))
    }
}

/// Can the arm (joints 1–3) of the `shoulder` branch put the wrist centre at `c` (base frame,
/// m)? Exactly the reach conditions of the closed form (the same expressions, in the same
/// order, as the arm part of [`solve_branch_prepared`], without its trigonometry): `Ok` if and
/// only if both elbow variants of that shoulder have an arm solution. Used to reject a path
/// that leaves the reachable set before any tracking (a necessary condition for every branch).
/// `slack` (dimensionless, ≥ 0) widens every condition: with `slack` = 1e-9 a wrist centre
/// computed with rounding differences of ~1e-15 m is never rejected where the closed form
/// would accept it.
#[inline]
pub(crate) fn arm_reaches(
    p: &OpwParams,
    k: &Prepared,
    c: &V3,
    shoulder: Shoulder,
    slack: f64,
) -> Result<(), IkFailure> {
    let rho2 = c.x * c.x + c.y * c.y - p.b * p.b;
    if rho2.is_nan() || rho2 < -slack {
        return Err(IkFailure::OutOfReach {
            distance_m: (c.x * c.x + c.y * c.y).sqrt(),
            min_reach_m: p.b.abs(),
            max_reach_m: f64::INFINITY,
            what: "wrist centre from the axis of joint 1",
        });
    }
    let rho = rho2.max(0.0).sqrt();
    let nx1 = rho - p.a1;
    let dz = c.z - p.c1;
    let x = match shoulder {
        Shoulder::Front => nx1,
        Shoulder::Back => nx1 + 2.0 * p.a1,
    };
    let s2 = x * x + dz * dz;
    let s = s2.sqrt();
    if s == 0.0 && slack == 0.0 {
        return Err(IkFailure::Singular {
            what: "wrist centre on the axis of joint 2",
            measure: 0.0,
        });
    }
    let ok = |v: f64| !(v.is_nan() || v.abs() > 1.0 + ACOS_SLACK + slack);
    if ok((s2 + k.c22 - k.kappa2) / (2.0 * s * p.c2))
        && ok((s2 - k.c22 - k.kappa2) / (2.0 * p.c2 * k.kappa))
    {
        Ok(())
    } else {
        Err(IkFailure::OutOfReach {
            distance_m: s,
            min_reach_m: (p.c2 - k.kappa).abs(),
            max_reach_m: p.c2 + k.kappa,
            what: "wrist centre from the axis of joint 2",
        })
    }
}

/// Arm part (joints 1–3, OPW angles) of one shoulder/elbow branch, or why it has none.
#[inline]
fn arm(
    p: &OpwParams,
    k: &Prepared,
    c: &V3,
    shoulder: Shoulder,
    elbow: Elbow,
) -> Result<([f64; 3], (f64, f64)), IkFailure> {
    let rho2 = c.x * c.x + c.y * c.y - p.b * p.b;
    if rho2.is_nan() || rho2 < 0.0 {
        return Err(IkFailure::OutOfReach {
            distance_m: (c.x * c.x + c.y * c.y).sqrt(),
            min_reach_m: p.b.abs(),
            max_reach_m: f64::INFINITY,
            what: "wrist centre from the axis of joint 1",
        });
    }
    let rho = rho2.sqrt();
    let nx1 = rho - p.a1;
    let dz = c.z - p.c1;
    let (kappa2, kappa, c22, psi3) = (k.kappa2, k.kappa, k.c22, k.psi3);
    let x = match shoulder {
        Shoulder::Front => nx1,
        Shoulder::Back => nx1 + 2.0 * p.a1,
    };
    // q1 = φ − β (front) or φ + β − π (back) with φ = atan2(c_y, c_x), β = atan2(b, ρ). From
    // cos φ = c_x/r, sin φ = c_y/r, cos β = ρ/r, sin β = b/r (r² = c_x² + c_y²) one atan2
    // gives q1 (equal modulo 2π), and its sine and cosine are left for the wrist.
    let r2 = c.x * c.x + c.y * c.y;
    let (q1, sc1) = if r2 > 1e-200 {
        let (s1, c1) = match shoulder {
            Shoulder::Front => ((c.y * rho - c.x * p.b) / r2, (c.x * rho + c.y * p.b) / r2),
            Shoulder::Back => (-(c.y * rho + c.x * p.b) / r2, -(c.x * rho - c.y * p.b) / r2),
        };
        (crate::fastmath::atan2(s1, c1), (s1, c1))
    } else {
        // Wrist centre on the axis of joint 1 (b = 0): φ undefined, take 0 as atan2 does.
        let q1 = match shoulder {
            Shoulder::Front => -p.b.atan2(rho),
            Shoulder::Back => p.b.atan2(rho) - PI,
        };
        (q1, q1.sin_cos())
    };
    let s2 = x * x + dz * dz;
    let s = s2.sqrt();
    let out = || IkFailure::OutOfReach {
        distance_m: s,
        min_reach_m: (p.c2 - kappa).abs(),
        max_reach_m: p.c2 + kappa,
        what: "wrist centre from the axis of joint 2",
    };
    if s == 0.0 {
        return Err(IkFailure::Singular {
            what: "wrist centre on the axis of joint 2",
            measure: 0.0,
        });
    }
    let t2 = checked_acos((s2 + c22 - kappa2) / (2.0 * s * p.c2)).ok_or_else(out)?;
    let t3 = checked_acos((s2 - c22 - kappa2) / (2.0 * p.c2 * kappa)).ok_or_else(out)?;
    let (q2, q3) = match shoulder {
        Shoulder::Front => {
            let a = crate::fastmath::atan2(x, dz);
            match elbow {
                Elbow::Up => (a - t2, t3 - psi3),
                Elbow::Down => (a + t2, -t3 - psi3),
            }
        }
        Shoulder::Back => {
            let a = crate::fastmath::atan2(x, dz);
            match elbow {
                Elbow::Up => (-t2 - a, t3 - psi3),
                Elbow::Down => (t2 - a, -t3 - psi3),
            }
        }
    };
    Ok(([q1, q2, q3], sc1))
}

/// Wrist part (OPW q4, q5, q6) given the arm and `(sin q1, cos q1)`; `q4_ref` (OPW angle, rad) is used at the
/// singularity.
#[inline]
fn wrist(r: &M3, arm: &[f64; 3], sc1: (f64, f64), w: Wrist, q4_ref: f64) -> ([f64; 3], f64) {
    let (s1, c1) = sc1;
    let (s23, c23) = crate::fastmath::sin_cos(arm[1] + arm[2]);
    // Columns of R_0c.
    let x = V3::new(c1 * c23, s1 * c23, -s23);
    let y = V3::new(-s1, c1, 0.0);
    let z = V3::new(c1 * s23, s1 * s23, c23);
    let rz = r.column(2);
    // R_ce = R_0c^T R, only the entries needed.
    let r02 = x.dot(&rz);
    let r12 = y.dot(&rz);
    let r22 = z.dot(&rz);
    let s5 = (r02 * r02 + r12 * r12).sqrt();
    if s5 < WRIST_SINGULAR_SIN {
        let rx = r.column(0);
        let r00 = x.dot(&rx);
        let r10 = y.dot(&rx);
        if r22 >= 0.0 {
            // R_ce ≈ Rz(q4 + q6).
            let sum = crate::fastmath::atan2(r10, r00);
            ([q4_ref, 0.0, sum - q4_ref], s5)
        } else {
            // R_ce ≈ Ry(π) Rz(q6 − q4).
            let r11 = y.dot(&r.column(1));
            let diff = crate::fastmath::atan2(r10, r11);
            ([q4_ref, PI, diff + q4_ref], s5)
        }
    } else {
        let r20 = z.dot(&r.column(0));
        let r21 = z.dot(&r.column(1));
        let q4 = crate::fastmath::atan2(r12, r02);
        let q5 = crate::fastmath::atan2(s5, r22);
        let q6 = crate::fastmath::atan2(r21, -r20);
        let a = match w {
            Wrist::NoFlip => [q4, q5, q6],
            Wrist::Flip => [q4 + PI, -q5, q6 + PI],
        };
        (a, s5)
    }
}

/// One value per lane ([`crate::simd::LANES`]).
type Lanes = [f64; crate::simd::LANES];

/// Closed-form answers of [`crate::simd::LANES`] flange poses sharing one orientation, in
/// lockstep; see [`solve_branch_batch`]. Joint-major only (a lane's vector is
/// [`BranchBatch::q`]): the lockstep callers read the answers joint by joint.
#[derive(Clone, Copy, Debug)]
pub struct BranchBatch {
    /// The branch every lane was solved for.
    pub branch: Branch,
    /// URDF angles (rad, not wrapped) joint by joint, as [`solve_branch_prepared`] gives
    /// them: `qj[j][lane]`.
    pub qj: [Lanes; 6],
    /// OPW angles joint by joint before the wrist variant is applied (`q1 … q6` with the
    /// wrist's `atan2` results), for [`BranchBatch::variant`]: `oj[j][lane]`.
    pub oj: [Lanes; 6],
    /// `|sin q5|` per lane (the same for both wrist variants).
    pub s5: Lanes,
    /// Whether the lane holds [`solve_branch_prepared`]'s answer; `false` where it errs or
    /// the lane needs `q_ref` (the wrist singularity) or a degenerate case (wrist centre on
    /// the axis of joint 1): such lanes are to be solved one by one.
    pub ok: [bool; crate::simd::LANES],
    /// Per lane, [`Prepared::branch_of`] of the lane's answer [`BranchBatch::q`], exactly:
    /// the batch's own branch where every lane is provably far from the branch boundaries
    /// (`NEXT_BRANCH_MARGIN_RAD`, `NEXT_BRANCH_MARGIN_REL`), else the same operations in
    /// lockstep. The branch the next sample continues when it continues from that answer
    /// unchanged ([`BranchBatch::known_branch`]).
    pub next_branch: [Branch; crate::simd::LANES],
    /// The joint vector the batch's branch was taken from (rad; [`Prepared::branch_of`] of it
    /// is `branch`), when the caller set it; NaN otherwise.
    pub prev: [f64; 6],
}

impl Default for BranchBatch {
    /// A batch of no answers (every lane not `ok`), to be filled by [`solve_branch_batch_into`].
    fn default() -> Self {
        BranchBatch {
            branch: Branch::ALL[0],
            qj: [[0.0; crate::simd::LANES]; 6],
            oj: [[0.0; crate::simd::LANES]; 6],
            s5: [0.0; crate::simd::LANES],
            ok: [false; crate::simd::LANES],
            next_branch: [Branch::ALL[0]; crate::simd::LANES],
            prev: [f64::NAN; 6],
        }
    }
}

/// The body of [`solve_branch_batch`]: [`solve_branch_prepared`]'s operations per lane, in
/// the same order.
#[inline(always)]
fn solve_branch_lanes(
    p: &OpwParams,
    k: &Prepared,
    rot: &M3,
    pos: &[Lanes; 3],
    branch: Branch,
    out: &mut BranchBatch,
) {
    solve_branch_lanes_n::<{ crate::simd::LANES }, 1>(p, k, rot, pos, branch, [out])
}

/// [`solve_branch_lanes`] of `N = G ·` [`crate::simd::LANES`] flange positions in lockstep:
/// the same operations per lane, so each group of [`crate::simd::LANES`] lanes `outs[g]`
/// (lanes `g · LANES ..`) is bit for bit what [`solve_branch_lanes`] makes of its
/// positions alone. Wider calls give the vector units independent chains to overlap (the
/// closed form is one long dependency chain of square roots, divisions and polynomials).
#[allow(clippy::needless_range_loop)] // lanes of parallel fixed arrays
#[inline(always)]
fn solve_branch_lanes_n<const N: usize, const G: usize>(
    p: &OpwParams,
    k: &Prepared,
    rot: &M3,
    pos: &[[f64; N]; 3],
    branch: Branch,
    outs: [&mut BranchBatch; G],
) {
    use crate::fastmath::{acos_lanes_n, atan2_lanes_n, sin_cos_lanes_n};
    use crate::simd::LANES;
    const { assert!(N == G * LANES) };
    let mut ok = [true; N];
    let rz = rot.column(2);
    let off = rz * p.c4;
    let (mut cx, mut cy, mut cz) = ([0.0; N], [0.0; N], [0.0; N]);
    for l in 0..N {
        cx[l] = pos[0][l] - off.x;
        cy[l] = pos[1][l] - off.y;
        cz[l] = pos[2][l] - off.z;
    }
    let (kappa2, kappa, c22, psi3) = (k.kappa2, k.kappa, k.c22, k.psi3);
    let (mut s1, mut c1, mut x, mut dz) = ([0.0; N], [0.0; N], [0.0; N], [0.0; N]);
    let (mut a2, mut a3) = ([0.0; N], [0.0; N]);
    let (mut s2v, mut sv) = ([0.0; N], [0.0; N]);
    let mut rhov = [0.0; N];
    let two_a1 = 2.0 * p.a1;
    let den3 = 2.0 * p.c2 * kappa;
    for l in 0..N {
        let rho2 = cx[l] * cx[l] + cy[l] * cy[l] - p.b * p.b;
        ok[l] &= !(rho2.is_nan() || rho2 < 0.0);
        let rho = rho2.sqrt();
        rhov[l] = rho;
        let nx1 = rho - p.a1;
        dz[l] = cz[l] - p.c1;
        x[l] = match branch.shoulder {
            Shoulder::Front => nx1,
            Shoulder::Back => nx1 + two_a1,
        };
        let r2 = cx[l] * cx[l] + cy[l] * cy[l];
        ok[l] &= r2 > 1e-200;
        (s1[l], c1[l]) = match branch.shoulder {
            Shoulder::Front => (
                (cy[l] * rho - cx[l] * p.b) / r2,
                (cx[l] * rho + cy[l] * p.b) / r2,
            ),
            Shoulder::Back => (
                -(cy[l] * rho + cx[l] * p.b) / r2,
                -(cx[l] * rho - cy[l] * p.b) / r2,
            ),
        };
        let s2 = x[l] * x[l] + dz[l] * dz[l];
        let s = s2.sqrt();
        ok[l] &= s != 0.0;
        let u2 = (s2 + c22 - kappa2) / (2.0 * s * p.c2);
        let u3 = (s2 - c22 - kappa2) / den3;
        ok[l] &= !(u2.is_nan() || u2.abs() > 1.0 + ACOS_SLACK);
        ok[l] &= !(u3.is_nan() || u3.abs() > 1.0 + ACOS_SLACK);
        a2[l] = u2.clamp(-1.0, 1.0);
        a3[l] = u3.clamp(-1.0, 1.0);
        // Keep NaN lanes finite for the vector kernels (they are not ok anyway).
        if !ok[l] {
            a2[l] = 0.0;
            a3[l] = 0.0;
        }
        s2v[l] = s2;
        sv[l] = s;
    }
    let q1 = atan2_lanes_n(&s1, &c1);
    let t2 = acos_lanes_n(&a2);
    let t3 = acos_lanes_n(&a3);
    let a = atan2_lanes_n(&x, &dz);
    let (mut q2, mut q3, mut sum23) = ([0.0; N], [0.0; N], [0.0; N]);
    for l in 0..N {
        (q2[l], q3[l]) = match (branch.shoulder, branch.elbow) {
            (Shoulder::Front, Elbow::Up) => (a[l] - t2[l], t3[l] - psi3),
            (Shoulder::Front, Elbow::Down) => (a[l] + t2[l], -t3[l] - psi3),
            (Shoulder::Back, Elbow::Up) => (-t2[l] - a[l], t3[l] - psi3),
            (Shoulder::Back, Elbow::Down) => (t2[l] - a[l], -t3[l] - psi3),
        };
        sum23[l] = q2[l] + q3[l];
    }
    // wrist()
    let (s23, c23) = sin_cos_lanes_n(&sum23);
    let (rx, ry) = (rot.column(0), rot.column(1));
    let (mut r12, mut r02, mut s5, mut r22) = ([0.0; N], [0.0; N], [0.0; N], [0.0; N]);
    let (mut r21, mut mr20) = ([0.0; N], [0.0; N]);
    for l in 0..N {
        let xv = [c1[l] * c23[l], s1[l] * c23[l], -s23[l]];
        let yv = [-s1[l], c1[l], 0.0];
        let zv = [c1[l] * s23[l], s1[l] * s23[l], c23[l]];
        r02[l] = xv[0] * rz.x + xv[1] * rz.y + xv[2] * rz.z;
        r12[l] = yv[0] * rz.x + yv[1] * rz.y + yv[2] * rz.z;
        r22[l] = zv[0] * rz.x + zv[1] * rz.y + zv[2] * rz.z;
        s5[l] = (r02[l] * r02[l] + r12[l] * r12[l]).sqrt();
        ok[l] &= s5[l].is_nan() || s5[l] >= WRIST_SINGULAR_SIN;
        let r20 = zv[0] * rx.x + zv[1] * rx.y + zv[2] * rx.z;
        r21[l] = zv[0] * ry.x + zv[1] * ry.y + zv[2] * ry.z;
        mr20[l] = -r20;
    }
    let q4 = atan2_lanes_n(&r12, &r02);
    let q5 = atan2_lanes_n(&s5, &r22);
    let q6 = atan2_lanes_n(&r21, &mr20);
    // variant() joint by joint: the wrist variant, then (o + offset) · sign.
    // (w + offset) · sign of the wrist variant's angle w: o as it is, o + π, or −o.
    #[inline(always)]
    fn urdf<const N: usize>(
        o: &[f64; N],
        wr: impl Fn(f64) -> f64,
        off: f64,
        sign: f64,
    ) -> [f64; N] {
        let mut r = [0.0; N];
        for (r, o) in r.iter_mut().zip(o) {
            *r = (wr(*o) + off) * sign;
        }
        r
    }
    let (off, sg) = (&p.offsets, &p.signs);
    let mut qj = [[0.0; N]; 6];
    qj[0] = urdf(&q1, |o| o, off[0], sg[0]);
    qj[1] = urdf(&q2, |o| o, off[1], sg[1]);
    qj[2] = urdf(&q3, |o| o, off[2], sg[2]);
    match branch.wrist {
        Wrist::NoFlip => {
            qj[3] = urdf(&q4, |o| o, off[3], sg[3]);
            qj[4] = urdf(&q5, |o| o, off[4], sg[4]);
            qj[5] = urdf(&q6, |o| o, off[5], sg[5]);
        }
        Wrist::Flip => {
            qj[3] = urdf(&q4, |o| o + PI, off[3], sg[3]);
            qj[4] = urdf(&q5, |o| -o, off[4], sg[4]);
            qj[5] = urdf(&q6, |o| o + PI, off[5], sg[5]);
        }
    }
    for l in 0..N {
        ok[l] &= qj[0][l].is_finite()
            & qj[1][l].is_finite()
            & qj[2][l].is_finite()
            & qj[3][l].is_finite()
            & qj[4][l].is_finite()
            & qj[5][l].is_finite();
    }
    // Prepared::branch_of of each answer is the batch's branch where the answer is far from
    // the branch boundaries (see NEXT_BRANCH_MARGIN_RAD): every lane ok, the wrist centre
    // off the axis of joint 1 (ρ), the elbow angle t3 and q5 inside (0, π) with margin.
    // Otherwise it is computed (branch_of_joints, bit for bit branch_of).
    let m = NEXT_BRANCH_MARGIN_RAD;
    let rho_min = NEXT_BRANCH_MARGIN_REL * (p.c2.abs() + kappa);
    let mut certain = [true; N];
    for l in 0..N {
        certain[l] = ok[l]
            & (rhov[l] > rho_min)
            & (t3[l] > m)
            & (t3[l] < PI - m)
            & (q5[l] > m)
            & (q5[l] < PI - m);
    }
    let oj = [q1, q2, q3, q4, q5, q6];
    // Each group of LANES lanes into its batch, row by row (a whole-array move is a kilobyte
    // memcpy).
    for (g, out) in outs.into_iter().enumerate() {
        let r = g * LANES..(g + 1) * LANES;
        for j in 0..6 {
            out.oj[j].copy_from_slice(&oj[j][r.clone()]);
            out.qj[j].copy_from_slice(&qj[j][r.clone()]);
        }
        out.next_branch = if certain[r.clone()].iter().all(|c| *c) {
            [branch; LANES]
        } else {
            branch_of_joints(p, k, &out.qj)
        };
        out.branch = branch;
        out.s5.copy_from_slice(&s5[r.clone()]);
        out.ok.copy_from_slice(&ok[r]);
        out.prev = [f64::NAN; 6];
    }
}

/// [`Prepared::branch_of`] of [`crate::simd::LANES`] joint vectors (URDF angles, rad), lane by
/// lane bit-identical: the lockstep computation [`solve_branch_batch`] makes of
/// [`BranchBatch::next_branch`], on the baseline instruction set.
pub fn branch_of_batch(
    p: &OpwParams,
    k: &Prepared,
    q: &[[f64; 6]; crate::simd::LANES],
) -> [Branch; crate::simd::LANES] {
    branch_of_lanes(p, k, q)
}

/// [`Prepared::branch_of`] of [`crate::simd::LANES`] joint vectors, lane by lane bit-identical
/// (the same operations; the sines by [`crate::fastmath::sin_cos_lanes`], [`wrap_pi`] with
/// its branch as a select).
#[inline(always)]
pub(crate) fn branch_of_lanes(
    p: &OpwParams,
    k: &Prepared,
    q: &[[f64; 6]; crate::simd::LANES],
) -> [Branch; crate::simd::LANES] {
    let mut qj = [[0.0; crate::simd::LANES]; 6];
    for (l, ql) in q.iter().enumerate() {
        for j in 0..6 {
            qj[j][l] = ql[j];
        }
    }
    branch_of_joints(p, k, &qj)
}

/// [`branch_of_lanes`] of joint vectors given joint by joint (`qj[j][lane]`, URDF angles,
/// rad): the same operations on the same values, lane by lane bit-identical to
/// [`Prepared::branch_of`].
#[allow(clippy::needless_range_loop)] // lanes of parallel fixed arrays
#[inline(always)]
pub(crate) fn branch_of_joints(
    p: &OpwParams,
    k: &Prepared,
    qj: &[[f64; crate::simd::LANES]; 6],
) -> [Branch; crate::simd::LANES] {
    use crate::simd::LANES;
    let wrap = |a: f64| {
        let w = a - (2.0 * PI) * ((a + PI) / (2.0 * PI)).floor();
        if w <= -PI {
            w + 2.0 * PI
        } else {
            w
        }
    };
    let (mut o1, mut o1e, mut e, mut o4) = ([0.0; LANES], [0.0; LANES], [0.0; LANES], [0.0; LANES]);
    for l in 0..LANES {
        // OpwParams::to_opw of joints 2, 3 and 5: q · sign − offset.
        let o_1 = qj[1][l] * p.signs[1] - p.offsets[1];
        let o_2 = qj[2][l] * p.signs[2] - p.offsets[2];
        o1[l] = o_1;
        e[l] = o_2 + k.psi3;
        o1e[l] = o_1 + e[l];
        o4[l] = qj[4][l] * p.signs[4] - p.offsets[4];
    }
    let (s1, _) = crate::fastmath::sin_cos_lanes(&o1);
    let (s1e, _) = crate::fastmath::sin_cos_lanes(&o1e);
    let mut front = [false; LANES];
    let mut up = [false; LANES];
    let mut noflip = [false; LANES];
    for l in 0..LANES {
        let cx1 = p.c2 * s1[l] + k.kappa * s1e[l] + p.a1;
        front[l] = cx1 >= 0.0;
        up[l] = wrap(e[l]) >= 0.0;
        noflip[l] = wrap(o4[l]) >= 0.0;
    }
    let mut out = [Branch::ALL[0]; LANES];
    for l in 0..LANES {
        out[l] = Branch {
            shoulder: if front[l] {
                Shoulder::Front
            } else {
                Shoulder::Back
            },
            elbow: if up[l] { Elbow::Up } else { Elbow::Down },
            wrist: if noflip[l] {
                Wrist::NoFlip
            } else {
                Wrist::Flip
            },
        };
    }
    out
}

/// URDF angles of the wrist variant `w` of the OPW angles `o` (the wrist's `atan2` results
/// unflipped), as [`solve_branch_prepared`] forms them.
#[inline(always)]
fn variant(p: &OpwParams, o: &[f64; 6], w: Wrist) -> [f64; 6] {
    let wr = match w {
        Wrist::NoFlip => [o[3], o[4], o[5]],
        Wrist::Flip => [o[3] + PI, -o[4], o[5] + PI],
    };
    p.from_opw(&[o[0], o[1], o[2], wr[0], wr[1], wr[2]])
}

impl BranchBatch {
    /// Lane `lane`'s URDF angles (rad, not wrapped): `qj[j][lane]` for the joints `j`.
    #[inline]
    pub fn q(&self, lane: usize) -> [f64; 6] {
        let mut q = [0.0; 6];
        for (v, qj) in q.iter_mut().zip(&self.qj) {
            *v = qj[lane];
        }
        q
    }

    /// Lane `lane`'s URDF angles (rad, not wrapped) for the wrist variant `w` of the batch's
    /// shoulder and elbow: [`solve_branch_prepared`]'s answer for that branch, bit for bit,
    /// when the lane is `ok`.
    pub fn variant(&self, p: &OpwParams, lane: usize, w: Wrist) -> [f64; 6] {
        let mut o = [0.0; 6];
        for (v, oj) in o.iter_mut().zip(&self.oj) {
            *v = oj[lane];
        }
        variant(p, &o, w)
    }

    /// [`Prepared::branch_of`]`(q_prev)` without computing it, when the batch knows it: at
    /// lane 0 for the joint vector the batch was solved from ([`BranchBatch::prev`]), at a
    /// later lane for the previous lane's answer [`BranchBatch::q`]`(lane − 1)` (both
    /// compared bit for bit). `None` otherwise (compute it).
    #[inline]
    pub fn known_branch(&self, lane: usize, q_prev: &[f64]) -> Option<Branch> {
        if q_prev.len() != 6 {
            return None;
        }
        match lane {
            0 => self
                .prev
                .iter()
                .zip(q_prev)
                .all(|(x, y)| x.to_bits() == y.to_bits())
                .then_some(self.branch),
            l if l < crate::simd::LANES => self
                .qj
                .iter()
                .zip(q_prev)
                .all(|(x, y)| x[l - 1].to_bits() == y.to_bits())
                .then_some(self.next_branch[l - 1]),
            _ => None,
        }
    }
}

/// [`solve_branch_prepared`] of [`crate::simd::LANES`] flange poses with the common rotation
/// `rot` and the positions `pos[i][lane]` (base frame, m), in lockstep on the instruction set
/// `level` ([`crate::simd`]). Each `ok` lane holds exactly [`solve_branch_prepared`]'s
/// answer (bit for bit; `q_ref` does not matter away from the wrist singularity, where
/// lanes are not `ok`).
pub fn solve_branch_batch(
    p: &OpwParams,
    k: &Prepared,
    rot: &M3,
    pos: &[Lanes; 3],
    branch: Branch,
    level: crate::simd::Level,
) -> BranchBatch {
    let mut out = BranchBatch::default();
    solve_branch_batch_into(p, k, rot, pos, branch, level, &mut out);
    out
}

/// [`solve_branch_batch`] into `out` (every field written; [`BranchBatch::prev`] NaN): the
/// same answers, bit for bit, without moving the batch.
pub fn solve_branch_batch_into(
    p: &OpwParams,
    k: &Prepared,
    rot: &M3,
    pos: &[Lanes; 3],
    branch: Branch,
    level: crate::simd::Level,
    out: &mut BranchBatch,
) {
    crate::simd::run(
        level,
        #[inline(always)]
        || solve_branch_lanes(p, k, rot, pos, branch, out),
    )
}

/// Lanes of [`solve_branch_pair_into`]: two batches of [`crate::simd::LANES`].
pub const PAIR_LANES: usize = 2 * crate::simd::LANES;

/// [`solve_branch_batch_into`] of two batches at once: the flange positions
/// `pos[i][lane]` (m) of `out[0]` in lanes `0 .. LANES`, of `out[1]` in lanes `LANES ..`, all
/// with the rotation `rot` and for `branch`, in one lockstep pass on `level`. Each batch is bit
/// for bit [`solve_branch_batch_into`]'s of its own positions (the same operations per lane);
/// the pass is cheaper than two: the closed form is one long dependency chain of square
/// roots, divisions and polynomials, and two independent chains per vector operation keep the
/// units busy (measured alone on AVX-512: 67–75 instead of 87–95 cycles per sample; on AVX2,
/// with 16 registers, the spills of 16 lanes cost more than that, and path tracking does not
/// pair there).
pub fn solve_branch_pair_into(
    p: &OpwParams,
    k: &Prepared,
    rot: &M3,
    pos: &[[f64; PAIR_LANES]; 3],
    branch: Branch,
    level: crate::simd::Level,
    out: [&mut BranchBatch; 2],
) {
    crate::simd::run(
        level,
        #[inline(always)]
        || solve_branch_lanes_n(p, k, rot, pos, branch, out),
    )
}

/// Joint angles (URDF convention, rad, wrapped to (−π, π]) of one branch for the flange pose
/// `flange` (base frame, m). Joint limits are not applied. At the wrist singularity q4 = 0.
pub fn solve_branch(p: &OpwParams, flange: &Frame, branch: Branch) -> Result<[f64; 6], IkFailure> {
    solve_branch_near(p, flange, branch, None)
}

/// Like [`solve_branch`], but at the wrist singularity joint 4 keeps its value from `q_ref`
/// (URDF angles, rad; the previous path sample).
#[inline]
pub(crate) fn solve_branch_near(
    p: &OpwParams,
    flange: &Frame,
    branch: Branch,
    q_ref: Option<&[f64]>,
) -> Result<[f64; 6], IkFailure> {
    let (mut q, _) = solve_branch_prepared(p, &Prepared::new(p), flange, branch, q_ref)?;
    for v in &mut q {
        *v = wrap_pi(*v);
    }
    Ok(q)
}

/// The core of [`solve_branch_near`] with precomputed constants: URDF angles (rad) **not**
/// wrapped (within a few π of 0; [`super::fit_limits`] picks the 2π multiple) and `|sin q5|`
/// of the answer (the wrist singularity measure, dimensionless).
#[inline]
pub fn solve_branch_prepared(
    p: &OpwParams,
    k: &Prepared,
    flange: &Frame,
    branch: Branch,
    q_ref: Option<&[f64]>,
) -> Result<([f64; 6], f64), IkFailure> {
    let r = &flange.rot;
    let c = flange.pos - r.column(2) * p.c4;
    let (a, sc1) = arm(p, k, &c, branch.shoulder, branch.elbow)?;
    let q4_ref = match q_ref {
        Some(q) if q.len() > 3 => q[3] * p.signs[3] - p.offsets[3],
        _ => -p.offsets[3],
    };
    let (w, s5) = wrist(r, &a, sc1, branch.wrist, q4_ref);
    let o = [a[0], a[1], a[2], w[0], w[1], w[2]];
    let q = p.from_opw(&o);
    if q.iter().any(|v| !v.is_finite()) {
        return Err(IkFailure::Singular {
            what: "non-finite closed-form solution",
            measure: 0.0,
        });
    }
    Ok((q, s5))
}

/// All 8 branches for the flange pose (base frame, m), indexed by [`Branch::index`]; each
/// entry is the joint vector (URDF, rad, wrapped to (−π, π]) or why that branch has none.
pub fn solve_all(p: &OpwParams, flange: &Frame) -> [Result<[f64; 6], IkFailure>; 8] {
    let k = Prepared::new(p);
    Branch::ALL.map(|b| {
        let (mut q, _) = solve_branch_prepared(p, &k, flange, b, None)?;
        for v in &mut q {
            *v = wrap_pi(*v);
        }
        Ok(q)
    })
}

/// Wrist singularity measure `|sin q5|` (dimensionless, 0 = joints 4 and 6 aligned) for URDF
/// angles `q` (rad).
pub fn wrist_singularity(p: &OpwParams, q: &[f64]) -> f64 {
    crate::fastmath::sin(opw_angles(p, q)[4]).abs()
}

/// [`wrist_singularity`] from `sin q5` and `cos q5` (URDF angle, already computed):
/// `|sin(σ q5 − δ)|` with the OPW sign σ and offset δ of joint 5; equal to
/// [`wrist_singularity`] when δ = 0 (the shipped arms), to rounding otherwise.
#[inline]
pub(crate) fn wrist_singularity_sincos(p: &OpwParams, s5: f64, c5: f64) -> f64 {
    let (sign, off) = (p.signs[4], p.offsets[4]);
    if off == 0.0 {
        (sign * s5).abs()
    } else {
        let (so, co) = crate::fastmath::sin_cos(off);
        (sign * s5 * co - c5 * so).abs()
    }
}

/// Elbow singularity measure `|sin(q3_opw + ψ3)|` (dimensionless): 0 when the arm is stretched
/// out (or folded back), 1 with a right angle between upper arm and forearm line.
pub fn elbow_singularity(p: &OpwParams, q: &[f64]) -> f64 {
    let psi3 = crate::fastmath::atan2(p.a2, p.c3);
    crate::fastmath::sin(opw_angles(p, q)[2] + psi3).abs()
}

/// Shoulder singularity measure, m: distance of the wrist centre from the axis of joint 1
/// within the arm plane (`|c_x1|` of the OPW paper; for `b = 0` the distance to the axis).
pub fn shoulder_singularity(p: &OpwParams, q: &[f64]) -> f64 {
    let o = opw_angles(p, q);
    let psi3 = crate::fastmath::atan2(p.a2, p.c3);
    let k = (p.a2 * p.a2 + p.c3 * p.c3).sqrt();
    (p.c2 * crate::fastmath::sin(o[1]) + k * crate::fastmath::sin(o[1] + o[2] + psi3) + p.a1).abs()
}
