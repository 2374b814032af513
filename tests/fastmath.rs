//! The fast elementary functions (`printwatt::fastmath`) against libm, densely over the
//! ranges the hot loop meets them (joint angles up to ±4π, every quadrant of `atan2`, the
//! whole domain of `acos`), at the bounds the module docs state; and the joint sines computed
//! once per sample (by the IK's FK re-check) giving what computing them afresh gives.

mod common;

use printwatt::fastmath;
use std::sync::Mutex;

/// The libm switch is process-wide: the tests of this file take turns.
static SWITCH: Mutex<()> = Mutex::new(());

/// Spacing of doubles at |y| (1 ulp), the smallest normal spacing for y = 0.
fn ulp(y: f64) -> f64 {
    let a = y.abs().max(f64::MIN_POSITIVE);
    f64::from_bits(a.to_bits() + 1) - a
}

/// Largest error of `fast` against `exact` in ulp of the exact value, ignoring an absolute
/// error up to `abs_floor`.
fn worst(
    xs: impl Iterator<Item = f64>,
    fast: impl Fn(f64) -> f64,
    exact: impl Fn(f64) -> f64,
    abs_floor: f64,
) -> (f64, f64) {
    let mut w = (0.0, 0.0);
    for x in xs {
        let (f, e) = (fast(x), exact(x));
        assert!(f.is_finite() == e.is_finite(), "finiteness differs at {x}");
        let err = (f - e).abs();
        let u = if err <= abs_floor { 0.0 } else { err / ulp(e) };
        if u > w.0 {
            w = (u, x);
        }
    }
    w
}

/// `n` deterministic pseudo-random numbers in [0, 1) (seeded).
fn uniform(seed: u64, n: usize) -> impl Iterator<Item = f64> {
    let mut u = common::xorshift(seed);
    (0..n).map(move |_| u())
}

/// Dense grid over [-a, a], random points, and points next to every multiple of π/4
/// (quadrant boundaries of the reduction and zeros of sin/cos).
fn angles(a: f64) -> Vec<f64> {
    let n = 400_000;
    let mut v: Vec<f64> = (0..=n)
        .map(|i| -a + 2.0 * a * i as f64 / n as f64)
        .collect();
    v.extend(uniform(7, 400_000).map(|u| -a + 2.0 * a * u));
    let quarter = std::f64::consts::FRAC_PI_4;
    let k_max = (a / quarter) as i64;
    for k in -k_max..=k_max {
        let c = k as f64 * quarter;
        let mut lo = c;
        let mut hi = c;
        for _ in 0..64 {
            lo = f64::from_bits(lo.to_bits().wrapping_sub(1)).min(lo - 1e-300);
            hi = f64::from_bits(hi.to_bits().wrapping_add(1)).max(hi + 1e-300);
            v.push(lo);
            v.push(hi);
        }
        for e in 1..12 {
            v.push(c + 10f64.powi(-e));
            v.push(c - 10f64.powi(-e));
        }
    }
    v
}

#[test]
fn fast_sin_cos_stay_within_the_stated_bound_over_the_joint_ranges() {
    let _g = SWITCH.lock().unwrap_or_else(|e| e.into_inner());
    fastmath::set_libm(false);
    let xs = angles(4.0 * std::f64::consts::PI);
    let (ws, xs_at) = worst(xs.iter().copied(), fastmath::sin, f64::sin, 1e-24);
    let (wc, xc_at) = worst(xs.iter().copied(), fastmath::cos, f64::cos, 1e-24);
    println!("sin: worst {ws:.2} ulp at {xs_at}; cos: worst {wc:.2} ulp at {xc_at}");
    assert!(ws <= 2.0, "sin: {ws} ulp at {xs_at}");
    assert!(wc <= 2.0, "cos: {wc} ulp at {xc_at}");
    // The whole fast domain, sparser.
    let m = fastmath::SIN_COS_MAX;
    let (ws, at) = worst(
        uniform(11, 200_000).map(|u| -m + 2.0 * m * u),
        fastmath::sin,
        f64::sin,
        1e-24,
    );
    assert!(ws <= 2.0, "sin: {ws} ulp at {at}");
    // sin_cos is the pair.
    for &x in xs.iter().step_by(97) {
        assert_eq!(fastmath::sin_cos(x), (fastmath::sin(x), fastmath::cos(x)));
    }
}

#[test]
fn fast_atan2_stays_within_two_ulp_in_every_quadrant() {
    let _g = SWITCH.lock().unwrap_or_else(|e| e.into_inner());
    fastmath::set_libm(false);
    let mut pts: Vec<(f64, f64)> = Vec::new();
    // Every direction on circles of several radii, densely.
    for &r in &[1e-9, 1e-3, 0.7, 1.0, 2.6, 1e4] {
        let n = 200_000;
        for i in 0..n {
            let a = -std::f64::consts::PI + 2.0 * std::f64::consts::PI * i as f64 / n as f64;
            pts.push((r * a.sin(), r * a.cos()));
        }
    }
    // Random pairs over wide magnitudes, and the interval edges of the reduction.
    let u: Vec<f64> = uniform(3, 600_000).collect();
    for c in u.chunks(3) {
        let s = 10f64.powf(-6.0 + 12.0 * c[2]);
        pts.push(((c[0] - 0.5) * s, c[1] - 0.5));
    }
    for &t in &[0.4375f64, 0.6875, 1.0] {
        for d in -50i64..=50 {
            let n = f64::from_bits(t.to_bits().wrapping_add(d as u64));
            for (sy, sx) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                pts.push((sy * n, sx * 1.0));
                pts.push((sy * 1.0, sx * n));
            }
        }
    }
    let mut w = (0.0, (0.0, 0.0));
    for &(y, x) in &pts {
        let (f, e) = (fastmath::atan2(y, x), y.atan2(x));
        let u = (f - e).abs() / ulp(e);
        if u > w.0 {
            w = (u, (y, x));
        }
    }
    println!("atan2: worst {:.2} ulp at {:?}", w.0, w.1);
    assert!(w.0 <= 2.0, "atan2: {} ulp at {:?}", w.0, w.1);
}

#[test]
fn fast_acos_stays_within_three_ulp_over_its_domain() {
    let _g = SWITCH.lock().unwrap_or_else(|e| e.into_inner());
    fastmath::set_libm(false);
    let n = 400_000;
    let mut xs: Vec<f64> = (0..=n).map(|i| -1.0 + 2.0 * i as f64 / n as f64).collect();
    xs.extend(uniform(5, 200_000).map(|u| 2.0 * u - 1.0));
    for e in 1..16 {
        let d = 10f64.powi(-e);
        xs.extend([1.0 - d, -1.0 + d, d, -d]);
    }
    let (w, at) = worst(xs.into_iter(), fastmath::acos, f64::acos, 0.0);
    println!("acos: worst {w:.2} ulp at {at}");
    assert!(w <= 3.0, "acos: {w} ulp at {at}");
}

#[test]
fn fast_functions_give_libms_answer_outside_their_domain_and_on_special_values() {
    let _g = SWITCH.lock().unwrap_or_else(|e| e.into_inner());
    fastmath::set_libm(false);
    let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
    for x in [
        65.0,
        -1e6,
        1e300,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
    ] {
        let (s, c) = fastmath::sin_cos(x);
        assert!(same(s, x.sin()) && same(c, x.cos()), "sin_cos({x})");
    }
    for (y, x) in [
        (0.0, 0.0),
        (-0.0, 0.0),
        (0.0, -0.0),
        (-0.0, -0.0),
        (1.0, f64::INFINITY),
        (f64::INFINITY, -1.0),
        (f64::NAN, 1.0),
        (1e305, 1.0),
    ] {
        assert!(same(fastmath::atan2(y, x), y.atan2(x)), "atan2({y}, {x})");
    }
    for x in [1.5, -1.0000001, f64::NAN] {
        assert!(same(fastmath::acos(x), x.acos()), "acos({x})");
    }
    // tanh: ±1 where libm rounds to ±1 (and beyond), ±0 and NaN as libm's.
    for x in [
        -1e3,
        -20.0,
        20.0,
        1e300,
        f64::INFINITY,
        f64::NEG_INFINITY,
        0.0,
        -0.0,
        f64::NAN,
    ] {
        assert!(same(fastmath::tanh(x), x.tanh()), "tanh({x})");
    }
}

#[test]
fn the_libm_switch_returns_libms_results() {
    let _g = SWITCH.lock().unwrap_or_else(|e| e.into_inner());
    fastmath::set_libm(true);
    let mut differs_fast = false;
    for x in angles(2.0).into_iter().step_by(13) {
        assert_eq!(fastmath::sin_cos(x), x.sin_cos());
        assert_eq!(fastmath::atan2(x, 0.3), x.atan2(0.3));
        let c = (x / 2.0).clamp(-1.0, 1.0);
        assert_eq!(fastmath::acos(c).to_bits(), c.acos().to_bits());
    }
    fastmath::set_libm(false);
    assert!(!fastmath::libm_selected());
    for x in angles(2.0).into_iter().step_by(13) {
        differs_fast |=
            fastmath::sin_cos(x) != x.sin_cos() || fastmath::atan2(x, 0.3) != x.atan2(0.3);
    }
    assert!(
        differs_fast,
        "the fast path never differs from libm: is it in use?"
    );
}

#[test]
fn the_ik_records_the_sines_of_its_answer_and_rnea_from_them_equals_rnea() {
    let _g = SWITCH.lock().unwrap_or_else(|e| e.into_inner());
    fastmath::set_libm(false);
    use printwatt::dynamics::{rnea, rnea_with_sincos};
    use printwatt::kinematics::{nozzle_target, IkSolver};
    let model = common::robot("abb_irb6700_200_260");
    let solver = IkSolver::new(&model).unwrap();
    let dm = common::dyn_model(&model, true);
    let (mut d1, mut d2) = (dm.data(), dm.data());
    let n = model.dof();
    let mut checked = 0;
    for (i, u) in uniform(9, 200).enumerate() {
        let tip = nalgebra::Vector3::new(1.2 + 0.8 * u, -0.6 + 0.006 * i as f64, 0.3);
        let target = nozzle_target(&tip, 0.3 * u);
        let Ok(sols) = solver.solve_all(&target) else {
            continue;
        };
        let mut sincos = vec![f64::NAN; 2 * n];
        let q = solver
            .solve_near_with_sincos(&target, &sols[0].q, &mut sincos)
            .expect("continuing a solution of the same target");
        for j in 0..n {
            let (s, c) = fastmath::sin_cos(q[j]);
            assert_eq!((sincos[j], sincos[n + j]), (s, c), "joint {j}");
        }
        let qd: Vec<f64> = (0..n).map(|j| 0.3 - 0.1 * j as f64).collect();
        let qdd: Vec<f64> = (0..n).map(|j| -0.5 + 0.2 * j as f64).collect();
        let (mut t1, mut t2) = (vec![0.0; n], vec![0.0; n]);
        rnea(&dm, &mut d1, &q, &qd, &qdd, &mut t1).unwrap();
        rnea_with_sincos(&dm, &mut d2, &q, &sincos, &qd, &qdd, &mut t2).unwrap();
        assert_eq!(t1, t2, "torques from the shared sines differ");
        checked += 1;
    }
    assert!(checked > 100, "only {checked} reachable targets");
    let mut tau = vec![0.0; n];
    assert!(
        rnea_with_sincos(&dm, &mut d1, &[0.0; 6], &[0.0; 11], &[0.0; 6], &[0.0; 6], &mut tau)
            .is_err()
    );
}

#[test]
fn a_placement_evaluated_with_shared_sines_equals_its_energy_computed_afresh() {
    let _g = SWITCH.lock().unwrap_or_else(|e| e.into_inner());
    fastmath::set_libm(false);
    use printwatt::evaluate::feasibility::FeasibilityOptions;
    use printwatt::evaluate::{Evaluator, Objective};
    use printwatt::frame::Placement;
    let model = common::robot("abb_irb6700_200_260");
    let job = common::default_job(&model, &common::path("seed000_test_path.gcode"));
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let mut sc = ev.scratch().unwrap();
    let at = Placement::new(1.8, 0.0, 0.2, 90f64.to_radians());
    // evaluate: the sines of the IK's FK re-check, shared by the checks and RNEA.
    let shared = ev.evaluate(&mut sc, &at);
    let f = shared.feasible().expect("a feasible placement");
    // energy_of: the same trajectory, its sines computed again per sample.
    let timed = ev.timed(&mut sc, &at).unwrap();
    let afresh = ev.energy_of(&mut sc, &timed, f.margins).unwrap();
    assert_eq!(f, &afresh);
}

#[test]
fn the_polynomial_tanh_stays_within_four_ulp_of_libm_below_saturation_and_its_lanes_match_it_bit_for_bit(
) {
    // Stated bound (src/fastmath.rs): |tanh − libm| ≤ 4 ulp over |x| < 20 (the smoothed
    // Coulomb sign q̇/ε of joints slower than 0.02 rad/s), densely and at random, with tiny
    // and subnormal arguments; tanh_lanes gives tanh's bits lane by lane.
    let _g = SWITCH.lock().unwrap_or_else(|e| e.into_inner());
    fastmath::set_libm(false);
    let n = 400_000;
    let mut xs: Vec<f64> = (0..=n)
        .map(|i| -20.0 + 40.0 * i as f64 / n as f64)
        .collect();
    xs.extend(uniform(11, 400_000).map(|u| -20.0 + 40.0 * u));
    xs.extend(uniform(12, 200_000).map(|u| -1.0 + 2.0 * u));
    xs.extend(uniform(13, 100_000).map(|u| 10f64.powf(-320.0 * u)));
    xs.extend([
        19.999_999_999_999_996,
        -19.999_999_999_999_996,
        0.173_286_795_139_986_3, // ln 2 / 4: the reduction's first boundary
        f64::MIN_POSITIVE,
        5e-324,
    ]);
    let (w, at) = worst(xs.iter().copied(), fastmath::tanh, f64::tanh, 0.0);
    println!("tanh: worst {w:.2} ulp at {at}");
    assert!(w <= 4.0, "tanh: {w} ulp at {at}");
    for x in &xs {
        assert_eq!(
            fastmath::tanh(-x).to_bits(),
            (-fastmath::tanh(*x)).to_bits(),
            "odd at {x}"
        );
    }
    use printwatt::simd::LANES;
    for chunk in xs.chunks_exact(LANES).step_by(7) {
        let mut x: [f64; LANES] = chunk.try_into().unwrap();
        // Mix in saturated lanes and NaN.
        x[1] = 25.0;
        x[6] = f64::NAN;
        let t = fastmath::tanh_lanes(&x);
        for l in 0..LANES {
            let s = fastmath::tanh(x[l]);
            assert!(
                t[l].to_bits() == s.to_bits() || (t[l].is_nan() && s.is_nan()),
                "lane {l} at {}",
                x[l]
            );
        }
    }
}

#[test]
#[allow(clippy::needless_range_loop)] // lanes of parallel fixed arrays
fn sin_cos_lanes_with_tiny_lanes_in_the_kernel_equal_sin_cos_bit_for_bit() {
    use printwatt::simd::LANES;
    // fastmath::sin_cos_lanes_tiny_in_kernel (the FK re-check's sines) runs |x| < 2⁻²⁷ and
    // ±0 through the kernels instead of selecting (x, 1): the same bits as sin_cos and as
    // sin_cos_lanes_with_zeros, on zeros, subnormals, both sides of 2⁻²⁷ and of the fast
    // path's range, non-finite values and joint angles, with the libm switch off and on.
    let _g = SWITCH.lock().unwrap_or_else(|e| e.into_inner());
    let tiny = 7.450_580_596_923_828e-9;
    let mut xs = vec![
        0.0,
        -0.0,
        f64::from_bits(1),
        -f64::from_bits(1),
        f64::MIN_POSITIVE,
        -f64::MIN_POSITIVE,
        1e-300,
        -1e-200,
        1e-20,
        -3e-12,
        tiny,
        -tiny,
        f64::from_bits(tiny.to_bits() - 1),
        -f64::from_bits(tiny.to_bits() - 1),
        f64::from_bits(tiny.to_bits() + 1),
        1e-8,
        fastmath::SIN_COS_MAX,
        -fastmath::SIN_COS_MAX,
        f64::from_bits(fastmath::SIN_COS_MAX.to_bits() + 1),
        1e6,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    xs.extend(uniform(47, 4000).map(|u| 7.0 * u));
    xs.extend(uniform(53, 400).map(|u| tiny * 2.0 * u));
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    for libm in [false, true] {
        fastmath::set_libm(libm);
        for chunk in xs.chunks(LANES) {
            let mut x = [0.5; LANES];
            x[..chunk.len()].copy_from_slice(chunk);
            let (s, c) = fastmath::sin_cos_lanes_tiny_in_kernel(&x);
            let (sz, cz) = fastmath::sin_cos_lanes_with_zeros(&x);
            assert_eq!(bits(&s), bits(&sz), "libm {libm}: {x:?}");
            assert_eq!(bits(&c), bits(&cz), "libm {libm}: {x:?}");
            for l in 0..LANES {
                let (s1, c1) = fastmath::sin_cos(x[l]);
                let (s1, c1) = if x[l].abs() < tiny {
                    (x[l], 1.0)
                } else {
                    (s1, c1)
                };
                assert_eq!(s[l].to_bits(), s1.to_bits(), "libm {libm}: {}", x[l]);
                assert_eq!(c[l].to_bits(), c1.to_bits(), "libm {libm}: {}", x[l]);
            }
        }
    }
    fastmath::set_libm(false);
}

#[test]
#[allow(clippy::needless_range_loop)] // lanes of parallel fixed arrays
fn tanh_of_a_ratio_skips_the_division_only_where_saturated_and_equals_tanh_of_the_quotient() {
    // Also with the threshold made once by the caller (ratio_saturation_threshold, as the
    // pass does per batch) and with a NaN threshold (the kernel on every lane).
    // fastmath::tanh_lanes_of_ratio (the Coulomb sign tanh(q̇/ε) of the lockstep pass) returns
    // ±1 without dividing when every lane has |x| ≥ 20 ε (1 + 2⁻⁵⁰): lane by lane it must give
    // tanh(x / ε)'s bits, at and around the saturation boundary x = ±20 ε (a few ulp either
    // side, where the quotient rounds onto 20 or below it), for widths ε in and outside the
    // identified range, non-positive, subnormal and non-finite ones (which must divide), NaN,
    // ±0 and ±∞ lanes, with libm's switch off and on.
    use printwatt::simd::LANES;
    let _g = SWITCH.lock().unwrap_or_else(|e| e.into_inner());
    let step = |x: f64, k: i64| f64::from_bits((x.to_bits() as i64 + k) as u64);
    for libm in [false, true] {
        fastmath::set_libm(libm);
        for eps in [
            1e-3,
            1e-4,
            0.2,
            3e-3,
            7.3e-5,
            1.0 / 3.0,
            f64::MIN_POSITIVE,
            1e300,
            5e-324,
            0.0,
            -1e-3,
            f64::NAN,
            f64::INFINITY,
        ] {
            let t = 20.0 * eps;
            let mut xs: Vec<f64> = Vec::new();
            if t.is_finite() && t > 0.0 {
                for k in -12..=12 {
                    xs.push(step(t, k));
                }
            }
            xs.extend([2.0 * t, 1e3 * t, 19.0 * eps, 21.0 * eps, 0.02, 2.0, 1e-300]);
            let with_neg: Vec<f64> = xs.iter().flat_map(|&x| [x, -x]).collect();
            let mut batches: Vec<[f64; LANES]> = Vec::new();
            // Every value in all lanes (one sign, and both signs), then sliding windows.
            for &x in &xs {
                batches.push([x; LANES]);
                let mut b = [x; LANES];
                for l in (0..LANES).step_by(2) {
                    b[l] = -x;
                }
                batches.push(b);
            }
            for w in with_neg.windows(LANES) {
                batches.push(w.try_into().unwrap());
            }
            let mut special = [t * 3.0; LANES];
            special[2] = f64::NAN;
            batches.push(special);
            special[2] = f64::INFINITY;
            special[5] = f64::NEG_INFINITY;
            batches.push(special);
            special[3] = 0.0;
            special[4] = -0.0;
            batches.push(special);
            for x in &batches {
                // The threshold made per call, made once (the pass's form), and NaN (every
                // lane through the division and tanh's kernel, saturated ones included).
                let threshold = fastmath::ratio_saturation_threshold(eps);
                for (how, got) in [
                    ("per call", fastmath::tanh_lanes_of_ratio(x, eps)),
                    ("given", fastmath::tanh_lanes_of_ratio_at(x, eps, threshold)),
                    ("NaN", fastmath::tanh_lanes_of_ratio_at(x, eps, f64::NAN)),
                ] {
                    for l in 0..LANES {
                        let want = fastmath::tanh(x[l] / eps);
                        assert!(
                            got[l].to_bits() == want.to_bits()
                                || (got[l].is_nan() && want.is_nan()),
                            "{how}: libm {libm}, eps {eps:e}, lane {l} at {:e}: {} vs {}",
                            x[l],
                            got[l],
                            want
                        );
                    }
                }
            }
        }
    }
    fastmath::set_libm(false);
}
