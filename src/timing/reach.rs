//! The reach prune's lockstep screen: wrist centres that the front shoulder of an OPW arm
//! surely reaches, decided with one square root and no division per wrist centre
//! ([`FrontReach`]). A wrist centre it does not pass is asked the exact way
//! ([`crate::kinematics::IkSolver::wrist_centre_reachable`]), so the prune's outcome, its
//! first unreachable sample and its error are the exact test's.

use crate::robot::opw::OpwParams;
use crate::simd::{F64s, LANES};

use super::joint::TipLanes;

/// How far inside the reach of joints 2 and 3 (the annulus of radii `|c2 − κ|` and
/// `c2 + κ` about the axis of joint 2, `κ = √(a2² + c3²)`) a wrist centre must lie for
/// [`FrontReach`] to pass it, as a share of the outer radius (dimensionless). The exact
/// test's cosines are then at least about `1e-6 · κ / c2` inside ±1 while rounding moves
/// them by less than 1e-14; its tolerance (1 + 1e-10) only widens what it accepts.
pub(crate) const FRONT_REACH_INSET: f64 = 1e-6;

/// A conservative form of [`crate::kinematics::opw::arm_reaches`] with
/// [`crate::kinematics::Shoulder::Front`] for lanes of wrist centres: where it passes a
/// wrist centre, the exact test with any `slack ≥ 0` is `Ok` (the same squared distance
/// `s²` from the axis of joint 2, computed with the same operations, compared with the
/// squared radii of the annulus drawn in by [`FRONT_REACH_INSET`], instead of two cosines
/// from a second square root and two divisions). Where it does not, nothing is decided.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FrontReach {
    /// `b²`, m².
    b2: f64,
    /// `a1`, `c1`, m.
    a1: f64,
    c1: f64,
    /// Bounds on `s²`, m²: `(|c2 − κ| + τ R)²` and `((1 − τ) R)²` with `R = |c2| + κ`,
    /// `τ` = [`FRONT_REACH_INSET`]; `+∞` and `−∞` (nothing passes) for degenerate
    /// parameters.
    lo: f64,
    hi: f64,
}

impl FrontReach {
    /// The screen of the arm `p`.
    pub(crate) fn new(p: &OpwParams) -> FrontReach {
        // The exact test's constants (kinematics::opw::Prepared), from the same operations.
        let kappa = (p.a2 * p.a2 + p.c3 * p.c3).sqrt();
        let c2 = p.c2.abs();
        let r = c2 + kappa;
        let (lo, hi) = if c2 > 0.0 && kappa > 0.0 && r.is_finite() && p.a1.is_finite() {
            let inner = (c2 - kappa).abs() + FRONT_REACH_INSET * r;
            let outer = (1.0 - FRONT_REACH_INSET) * r;
            (inner * inner, outer * outer)
        } else {
            (f64::INFINITY, f64::NEG_INFINITY)
        };
        FrontReach {
            b2: p.b * p.b,
            a1: p.a1,
            c1: p.c1,
            lo,
            hi,
        }
    }

    /// For each chunk of tips `tips[c][i][lane]` (base frame, m), the wrist centres
    /// `tip + d` (m, per coordinate as `V3`'s sum) the screen passes with `slack` (the exact
    /// test's, ≥ 0; [`crate::kinematics::IkSolver::wrist_centre_reachable`]'s with 1e-9 for
    /// the prune), as a bit mask into `masks[c]` (bit `l`: lane `l` surely reached; NaN is
    /// not). `masks` as long as `tips`. The same masks on every level.
    pub(crate) fn masks(
        &self,
        tips: &[TipLanes],
        d: [f64; 3],
        slack: f64,
        masks: &mut [u32],
        level: crate::simd::Level,
    ) {
        struct K<'a> {
            fr: &'a FrontReach,
            tips: &'a [TipLanes],
            d: [f64; 3],
            slack: f64,
            masks: &'a mut [u32],
        }
        impl crate::simd::Kernel for K<'_> {
            type Out = ();
            #[inline(always)]
            fn run<R: F64s>(self) {
                masks_with::<R>(self.fr, self.tips, self.d, self.slack, self.masks)
            }
        }
        crate::simd::dispatch(
            level,
            K {
                fr: self,
                tips,
                d,
                slack,
                masks,
            },
        )
    }
}

/// The body of [`FrontReach::masks`] in registers of `R` (`f64`: the scalar reference): per
/// lane the operations of `arm_reaches`' `s²`, so the same masks on every register type.
#[inline(always)]
fn masks_with<R: F64s>(
    fr: &FrontReach,
    tips: &[TipLanes],
    d: [f64; 3],
    slack: f64,
    masks: &mut [u32],
) {
    let (d0, d1, d2) = (R::splat(d[0]), R::splat(d[1]), R::splat(d[2]));
    let (b2, a1, c1) = (R::splat(fr.b2), R::splat(fr.a1), R::splat(fr.c1));
    let (lo, hi, near) = (R::splat(fr.lo), R::splat(fr.hi), R::splat(-slack));
    let zero = R::splat(0.0);
    for (t, mask) in tips.iter().zip(masks.iter_mut()) {
        let mut m = 0u32;
        for h in (0..LANES).step_by(R::W) {
            // The wrist centre and arm_reaches' s², with the same operations.
            let cx = R::load(&t[0][h..]).add(d0);
            let cy = R::load(&t[1][h..]).add(d1);
            let cz = R::load(&t[2][h..]).add(d2);
            let rho2 = cx.mul(cx).add(cy.mul(cy)).sub(b2);
            // `rho2` where positive, else 0 (a NaN stays NaN: its lane fails below anyway).
            let rho = zero.sup(rho2).sqrt();
            let x = rho.sub(a1);
            let dz = cz.sub(c1);
            let s2 = x.mul(x).add(dz.mul(dz));
            // arm_reaches' first test as it is (false for NaN), then the annulus.
            m |= (rho2.ge(near) & s2.ge(lo) & s2.le(hi)) << h;
        }
        *mask = m;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::opw::{arm_reaches, Prepared};
    use crate::kinematics::Shoulder;
    use rand::{Rng, SeedableRng};

    /// The masks of `tips` on every available level, checked equal.
    fn masks_on_every_level(fr: &FrontReach, tips: &[TipLanes], slack: f64) -> Vec<u32> {
        let mut want = vec![0u32; tips.len()];
        masks_with::<f64>(fr, tips, [0.0; 3], slack, &mut want);
        for level in crate::simd::Level::ALL
            .into_iter()
            .filter(|l| l.available())
        {
            let mut got = vec![0u32; tips.len()];
            fr.masks(tips, [0.0; 3], slack, &mut got, level);
            assert_eq!(got, want, "{level:?}");
        }
        want
    }

    #[test]
    #[allow(clippy::needless_range_loop)] // lanes of parallel fixed arrays
    fn the_front_reach_screen_never_passes_a_wrist_centre_the_exact_test_rejects() {
        // FrontReach passes a wrist centre only inside the annulus drawn in by
        // FRONT_REACH_INSET: there arm_reaches (Front) must be Ok, with slack 0 and 1e-9.
        // Wrist centres anywhere about the arm, and mostly right at the inner and outer
        // reach (relative distances 1e-3 down to 1e-13 either side), near the axis of joint
        // 1, NaN and infinite; on the shipped OPW arms and on made-up ones (forearm longer or
        // shorter than the upper arm, about equal, a lateral offset, c2 negative). The
        // screen must also pass most wrist centres the exact test passes.
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("robots");
        let mut arms: Vec<OpwParams> =
            ["abb_irb6700_200_260", "abb_irb4600_40_255", "staubli_tx200"]
                .iter()
                .filter_map(|n| crate::robot::load(&root.join(n)).unwrap().opw)
                .collect();
        assert!(arms.len() >= 3);
        let base = arms[0];
        for (a1, a2, b, c2, c3) in [
            (0.2, 0.1, 0.0, 1.1, 1.4),
            (0.0, 0.0, 0.15, 1.0, 0.4),
            (0.3, 0.3, -0.1, 0.9, 0.9 * 0.9f64.hypot(0.3).recip() * 0.9),
            (0.1, 0.0, 0.0, 0.7, 0.7),
            (0.1, 0.2, 0.05, -0.8, 1.0),
        ] {
            arms.push(OpwParams {
                a1,
                a2,
                b,
                c2,
                c3,
                ..base
            });
        }
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(12);
        let (mut passed, mut exact_ok, mut near_boundary_rejected) = (0usize, 0usize, 0usize);
        for p in &arms {
            let k = Prepared::new(p);
            let fr = FrontReach::new(p);
            let kappa = (p.a2 * p.a2 + p.c3 * p.c3).sqrt();
            let (inner, outer) = ((p.c2.abs() - kappa).abs(), p.c2.abs() + kappa);
            for slack in [0.0, 1e-9] {
                let mut tips: Vec<TipLanes> = Vec::new();
                for case in 0..4000 {
                    let mut t = [[0.0; LANES]; 3];
                    for l in 0..LANES {
                        // s: the distance from the axis of joint 2 in the arm's plane.
                        let s = match case % 4 {
                            0 => rng.gen_range(0.0..1.3) * outer,
                            1 | 2 => {
                                let r = if case % 4 == 1 { inner } else { outer };
                                let e = 10f64.powf(rng.gen_range(-13.0..-3.0));
                                r * (1.0 + if rng.gen() { e } else { -e })
                            }
                            _ => rng.gen_range(0.0..0.05) * outer,
                        };
                        let th = rng.gen_range(-std::f64::consts::PI..std::f64::consts::PI);
                        // rho (≥ 0) and dz with (rho − a1)² + dz² = s².
                        let rho = (p.a1 + s * th.cos()).max(0.0);
                        let dz = s * th.sin();
                        let r = (rho * rho + p.b * p.b).sqrt();
                        let phi = rng.gen_range(-3.2..3.2f64);
                        let mut c = [r * phi.cos(), r * phi.sin(), p.c1 + dz];
                        match rng.gen_range(0..400) {
                            0 => c[rng.gen_range(0..3)] = f64::NAN,
                            1 => c[rng.gen_range(0..3)] = f64::INFINITY,
                            2 => c = [p.b * 0.5, 0.0, p.c1 + dz],
                            _ => {}
                        }
                        for i in 0..3 {
                            t[i][l] = c[i];
                        }
                    }
                    tips.push(t);
                }
                let masks = masks_on_every_level(&fr, &tips, slack);
                for (t, m) in tips.iter().zip(&masks) {
                    for l in 0..LANES {
                        let c = crate::math::V3::new(t[0][l], t[1][l], t[2][l]);
                        let exact = arm_reaches(p, &k, &c, Shoulder::Front, slack).is_ok();
                        let fast = m >> l & 1 != 0;
                        assert!(
                            exact || !fast,
                            "{p:?} slack {slack}: passed {c:?}, which the exact test rejects"
                        );
                        passed += usize::from(fast);
                        exact_ok += usize::from(exact);
                        near_boundary_rejected += usize::from(exact && !fast);
                    }
                }
            }
        }
        // Conservative only within the inset: most of what the exact test passes passes.
        assert!(passed * 10 > exact_ok * 6, "{passed} passed of {exact_ok}");
        assert!(near_boundary_rejected > 1000, "{near_boundary_rejected}");
    }
}
