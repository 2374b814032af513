//! The lockstep (SIMD) batches against the per-sample scalar path: the
//! batched RNEA and energy of every instruction-set level this CPU runs give the scalar
//! results bit for bit (the stated tolerance is 0: same operations, same order, no fused
//! multiply-add), and a sweep forced onto the scalar path ranks the placements the same.

mod common;

use printwatt::dynamics::{rnea_batch, rnea_with_sincos, DynData, DynModel, StateBatch};
use printwatt::energy::{self, EnergyModel, SamplePower};
use printwatt::fastmath;
use printwatt::simd::{self, Level, LANES};
use std::sync::Mutex;

/// The level is process-wide: the tests of this file that set it take turns.
static LEVEL_LOCK: Mutex<()> = Mutex::new(());

/// A deterministic stream of pseudo-random numbers in [-1, 1) (seeded).
fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut u = common::xorshift(seed);
    move || 2.0 * u() - 1.0
}

/// `count` random joint states of an `n`-joint arm: (q, sincos, qd, qdd).
fn states(seed: u64, n: usize, count: usize) -> Vec<State> {
    let mut u = uniform(seed);
    (0..count)
        .map(|_| {
            let q: Vec<f64> = (0..n).map(|_| 3.0 * u()).collect();
            let mut sc = vec![0.0; 2 * n];
            for j in 0..n {
                (sc[j], sc[n + j]) = fastmath::sin_cos(q[j]);
            }
            let qd = (0..n).map(|_| 2.0 * u()).collect();
            let qdd = (0..n).map(|_| 10.0 * u()).collect();
            (q, sc, qd, qdd)
        })
        .collect()
}

fn levels() -> Vec<Level> {
    Level::ALL.into_iter().filter(|l| l.available()).collect()
}

/// One joint state: (q, sincos, qd, qdd) as [`states`] makes them.
type State = (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>);

/// The lockstep RNEA of one batch of at most `LANES` states, on every level this CPU runs,
/// equals the scalar `rnea_with_sincos` bit for bit, lane by lane and joint by joint.
fn assert_batched_rnea_is_scalar_rnea(
    dm: &DynModel,
    data: &mut printwatt::dynamics::DynData,
    chunk: &[State],
    label: &str,
) {
    let n = dm.dof();
    let mut b = StateBatch::default();
    for (l, (_, sc, qd, qdd)) in chunk.iter().enumerate() {
        b.set(l, n, sc, qd, qdd);
    }
    let mut want = vec![0.0; n];
    for level in levels() {
        let mut tau = [[f64::NAN; LANES]; printwatt::dynamics::MAX_DOF];
        rnea_batch(dm, &b, &mut tau, level);
        for (l, (q, sc, qd, qdd)) in chunk.iter().enumerate() {
            rnea_with_sincos(dm, data, q, sc, qd, qdd, &mut want).unwrap();
            for j in 0..n {
                assert_eq!(
                    tau[j][l].to_bits(),
                    want[j].to_bits(),
                    "{label}, {level:?}, lane {l}, joint {j}: {} vs {}",
                    tau[j][l],
                    want[j]
                );
            }
        }
    }
}

/// The energy of one batch of at most `LANES` states on `level`, by both lockstep passes
/// (`eval_lanes_with_sincos`, and the sweep's row-major `eval_rows` with its inputs `x`
/// carried over from the batch before), equals the per-sample path's `want`, field by field
/// and lane by lane.
fn assert_energy_lanes_are_per_sample(
    em: &EnergyModel,
    data: &mut printwatt::dynamics::DynData,
    chunk: &[State],
    want: &[SamplePower],
    x: &mut energy::LaneInputs,
    level: Level,
    label: &str,
) {
    let mut out = energy::PowerLanes::default();
    energy::eval_lanes_with_sincos(
        em,
        data,
        chunk.len(),
        |l| &chunk[l].0,
        |l| &chunk[l].1,
        |l| &chunk[l].2,
        |l| &chunk[l].3,
        &mut out,
        level,
    )
    .unwrap();
    for (l, w) in want.iter().enumerate() {
        assert_eq!(
            format!("{:?}", out.sample(l)),
            format!("{w:?}"),
            "{label}, {level:?}, lane {l}"
        );
    }
    let (mut q, mut sc, mut qd, mut qdd) = (vec![], vec![], vec![], vec![]);
    for (a, b, c, d) in chunk {
        q.extend_from_slice(a);
        sc.extend_from_slice(b);
        qd.extend_from_slice(c);
        qdd.extend_from_slice(d);
    }
    let rows = energy::Rows {
        q: &q,
        sincos: Some(&sc),
        qd: &qd,
        qdd: &qdd,
    };
    let mut out = energy::PowerLanes::default();
    energy::eval_rows(em, data, chunk.len(), &rows, x, &mut out, level).unwrap();
    for (l, w) in want.iter().enumerate() {
        assert_eq!(
            format!("{:?}", out.sample(l)),
            format!("{w:?}"),
            "rows: {label}, {level:?}, lane {l}"
        );
    }
}

#[test]
fn batched_rnea_equals_scalar_rnea_bit_for_bit_on_every_level() {
    for name in ["abb_irb6700_200_260", "ur10e", "staubli_tx200"] {
        let model = common::robot(name);
        for armature in [false, true] {
            let dm = common::dyn_model(&model, armature);
            assert!(dm.batchable(), "{name}: every joint is revolute");
            let n = dm.dof();
            let mut data = dm.data();
            let st = states(7, n, 5 * LANES + 3);
            for chunk in st.chunks(LANES) {
                assert_batched_rnea_is_scalar_rnea(
                    &dm,
                    &mut data,
                    chunk,
                    &format!("{name}, armature {armature}"),
                );
            }
        }
    }
}

/// Fixed rotations that are not signed permutations (tilted joint frames) take the kernel's
/// dense products: still bit for bit the scalar reference on every level, and `τ(q, q̇, q̈) =
/// M(q) q̈ + τ(q, q̇, 0)` with the mass matrix of the composite-rigid-body algorithm (an
/// independent code path) to 1e-11 relative.
#[test]
fn batched_rnea_with_tilted_joint_frames_equals_scalar_rnea_and_the_mass_matrix_identity() {
    use printwatt::dynamics::mass_matrix;
    use printwatt::math::rot_axis;
    use printwatt::nalgebra::Vector3;
    let mut model = common::robot("abb_irb6700_200_260");
    for (i, j) in model.joints.iter_mut().enumerate() {
        let axis = Vector3::new(0.3, -0.5 + 0.1 * i as f64, 0.8).normalize();
        j.origin.rot *= rot_axis(&axis, 0.2 + 0.15 * i as f64);
    }
    let dm = common::dyn_model(&model, true);
    let n = dm.dof();
    let mut data = dm.data();
    let st = states(11, n, 3 * LANES + 5);
    let (mut want, mut t0, mut mm) = (vec![0.0; n], vec![0.0; n], vec![0.0; n * n]);
    let zero = vec![0.0; n];
    for chunk in st.chunks(LANES) {
        assert_batched_rnea_is_scalar_rnea(&dm, &mut data, chunk, "tilted frames");
        for (q, sc, qd, qdd) in chunk {
            rnea_with_sincos(&dm, &mut data, q, sc, qd, qdd, &mut want).unwrap();
            rnea_with_sincos(&dm, &mut data, q, sc, qd, &zero, &mut t0).unwrap();
            mass_matrix(&dm, &mut data, q, &mut mm).unwrap();
            for j in 0..n {
                let m_qdd: f64 = (0..n).map(|k| mm[j * n + k] * qdd[k]).sum();
                let e = (want[j] - (m_qdd + t0[j])).abs() / want[j].abs().max(1.0);
                assert!(e <= 1e-11, "joint {j}: {} vs {}", want[j], m_qdd + t0[j]);
            }
        }
    }
}

#[test]
fn simd_and_scalar_energy_agree_within_the_stated_tolerance() {
    // The stated tolerance is 0: every field of every sample equal, bit for bit.
    for name in ["abb_irb6700_200_260", "abb_irb4600_40_255", "ur10e"] {
        let model = common::robot(name);
        let em = EnergyModel::new(&model).unwrap();
        let n = em.dof();
        let mut data = em.data();
        let st = states(11, n, 3 * LANES + 5);
        for chunk in st.chunks(LANES) {
            let mut want = vec![SamplePower::default(); chunk.len()];
            for ((q, sc, qd, qdd), w) in chunk.iter().zip(want.iter_mut()) {
                energy::eval_sample_with_sincos(&em, &mut data, q, sc, qd, qdd, w).unwrap();
            }
            for level in levels() {
                let mut out = [SamplePower::default(); LANES];
                energy::eval_batch_with_sincos(
                    &em,
                    &mut data,
                    chunk.len(),
                    |l| &chunk[l].0,
                    |l| &chunk[l].1,
                    |l| &chunk[l].2,
                    |l| &chunk[l].3,
                    &mut out,
                    level,
                )
                .unwrap();
                for (l, w) in want.iter().enumerate() {
                    // Debug prints every f64 exactly (shortest round-trip form).
                    assert_eq!(
                        format!("{:?}", out[l]),
                        format!("{w:?}"),
                        "{name}, {level:?}, lane {l}"
                    );
                }
            }
        }
    }
}

#[test]
fn a_batch_with_a_wrong_slice_length_is_an_error_not_a_panic() {
    let model = common::robot("abb_irb6700_200_260");
    let em = EnergyModel::new(&model).unwrap();
    let mut data = em.data();
    let (q, sc, v) = (vec![0.0; 6], vec![0.0; 11], vec![0.0; 6]);
    let mut out = [SamplePower::default(); LANES];
    let r = energy::eval_batch_with_sincos(
        &em,
        &mut data,
        2,
        |_| &q,
        |_| &sc,
        |_| &v,
        |_| &v,
        &mut out,
        simd::detected(),
    );
    assert!(r.is_err());
}

#[test]
fn forcing_the_scalar_path_gives_the_same_placement_ranking() {
    use printwatt::evaluate::feasibility::FeasibilityOptions;
    use printwatt::evaluate::{Evaluator, Objective};
    use printwatt::frame::Placement;
    let model = common::robot("abb_irb6700_200_260");
    let job = common::default_job(&model, &common::path("seed000_test_path.gcode"));
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let ps: Vec<Placement> = [1.5, 1.7, 1.9]
        .iter()
        .flat_map(|&x| {
            [-0.3, 0.0, 0.3].map(|y| Placement {
                x,
                y,
                z: 0.2,
                yaw: 90f64.to_radians(),
                nozzle_spin: 0.0,
            })
        })
        .collect();
    let _g = LEVEL_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let run = |level: Level| {
        assert!(simd::set_level(level));
        assert_eq!(simd::level(), level);
        ev.sweep(&ps, &|_, _| {}).unwrap()
    };
    let scalar = run(Level::Scalar);
    assert!(
        scalar.iter().filter(|e| e.cost().is_finite()).count() >= 3,
        "too few feasible placements to rank"
    );
    let rank = |r: &[printwatt::evaluate::Evaluated]| {
        let mut ix: Vec<usize> = (0..r.len()).collect();
        ix.sort_by(|&a, &b| r[a].cost().total_cmp(&r[b].cost()));
        ix
    };
    for level in levels() {
        let batched = run(level);
        assert_eq!(rank(&batched), rank(&scalar), "{level:?}");
        for (a, b) in batched.iter().zip(&scalar) {
            assert_eq!(a.feasible(), b.feasible(), "{level:?} at {:?}", a.placement);
        }
    }
    simd::set_level(simd::detected());
}

#[test]
fn the_level_names_round_trip_and_the_detected_level_is_available() {
    for l in Level::ALL {
        assert_eq!(Level::from_name(l.name()), Some(l));
    }
    assert_eq!(Level::from_name("avx1024"), None);
    assert!(simd::detected().available());
    assert_ne!(simd::detected(), Level::Scalar);
}

#[test]
fn sin_cos_of_eight_lanes_equals_sin_cos_bit_for_bit_including_special_values() {
    let mut u = uniform(3);
    let mut xs: Vec<f64> = (0..800).map(|_| 70.0 * u()).collect();
    xs.extend([
        0.0,
        -0.0,
        1e-300,
        -3e-9,
        7.450_580_596_923_828e-9,
        f64::NAN,
        64.0,
        -64.000001,
        1e6,
        f64::INFINITY,
        std::f64::consts::FRAC_PI_2,
        -std::f64::consts::PI,
        2.356194490192345,
        -5.497787143782138,
    ]);
    for chunk in xs.chunks(LANES) {
        let mut x = [0.25; LANES];
        x[..chunk.len()].copy_from_slice(chunk);
        let (s, c) = fastmath::sin_cos_lanes(&x);
        for l in 0..LANES {
            let (ws, wc) = fastmath::sin_cos(x[l]);
            assert_eq!(
                (s[l].to_bits(), c[l].to_bits()),
                (ws.to_bits(), wc.to_bits()),
                "x = {:e}",
                x[l]
            );
        }
    }
}

#[test]
fn batched_tool_poses_equal_the_scalar_fk_recheck_bit_for_bit_on_every_level() {
    use printwatt::kinematics::fk::FastChain;
    for name in [
        "abb_irb6700_200_260",
        "abb_irb4600_40_255",
        "staubli_tx200",
        "ur10e",
    ] {
        let model = common::robot(name);
        let chain = FastChain::new(&model);
        if !chain.batchable() {
            continue;
        }
        let n = model.dof();
        let st = states(5, n, 4 * LANES);
        for chunk in st.chunks(LANES) {
            let mut qb = [[0.0; LANES]; printwatt::dynamics::MAX_DOF];
            for (l, (q, ..)) in chunk.iter().enumerate() {
                for j in 0..n {
                    qb[j][l] = q[j];
                }
            }
            for level in levels() {
                let tb = chain.tool_batch(&qb, level);
                for (l, (q, ..)) in chunk.iter().enumerate() {
                    let mut sc = vec![0.0; 2 * n];
                    let want = chain.tool_with_sincos(q, &mut sc);
                    let got = tb.frame(l);
                    assert_eq!(format!("{got:?}"), format!("{want:?}"), "{name} {level:?}");
                    for j in 0..n {
                        assert_eq!(tb.s[j][l].to_bits(), sc[j].to_bits());
                        assert_eq!(tb.c[j][l].to_bits(), sc[n + j].to_bits());
                    }
                }
            }
        }
    }
}

#[test]
fn a_failing_fk_recheck_is_reported_at_the_same_sample_when_the_checks_run_in_batches() {
    use printwatt::frame::Placement;
    use printwatt::kinematics::{nozzle_target, IkSolver};
    use printwatt::timing::{self, blend_path, JointStageOptions, ProfileOptions};
    let _g = LEVEL_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let model = common::robot("abb_irb6700_200_260");
    let tp = common::path("default.gcode");
    let moves = timing::moves_from_toolpath(&tp);
    let pieces = blend_path(&moves);
    let lines: Vec<usize> = moves.iter().map(|m| m.line).collect();
    let at = Placement::new(1.7, 0.0, 0.0, std::f64::consts::FRAC_PI_2);
    let time = |solver: &IkSolver, level: Level| {
        assert!(simd::set_level(level));
        timing::time_at(
            solver,
            &pieces,
            &|i| lines[i],
            &at,
            &ProfileOptions::default(),
            &JointStageOptions::default(),
        )
    };
    let mut solver = IkSolver::new(&model).unwrap();
    assert!(
        solver.batch_checkable(),
        "the deferred, batched re-check applies"
    );
    let t = time(&solver, Level::Scalar).expect("the default path at the default placement");
    // The re-check's position error of every sample; a threshold at the largest one fails
    // the path exactly where it is reached first.
    let rot = nozzle_target(&nalgebra::Vector3::zeros(), at.nozzle_yaw()).rot;
    let n = model.dof();
    let mut sc = vec![0.0; 2 * n];
    let dp: Vec<f64> = (0..t.traj.len())
        .map(|k| {
            let target = printwatt::math::Frame { rot, pos: t.tcp[k] };
            solver
                .check_with_sincos(&target, t.traj.q(k), &mut sc)
                .unwrap()
                .0
        })
        .collect();
    let worst = dp.iter().copied().fold(0.0, f64::max);
    let first = dp.iter().position(|&d| d == worst).unwrap();
    assert!(
        first > LANES,
        "the worst sample is {first}: pick another path"
    );
    solver.check_position_m = worst;
    let want = time(&solver, Level::Scalar).expect_err("a check fails");
    assert!(
        matches!(want, timing::TimingFailure::Unreachable { sample, .. } if sample == first),
        "{want:?}"
    );
    for level in levels() {
        let got = time(&solver, level).expect_err("a check fails");
        assert_eq!(got, want, "{level:?}");
    }
    simd::set_level(simd::detected());
}

#[test]
fn atan2_and_acos_of_eight_lanes_equal_the_scalar_functions_bit_for_bit() {
    let mut u = uniform(17);
    let mut pairs: Vec<(f64, f64)> = (0..4000)
        .map(|i| {
            let scale = [1e-3, 1.0, 30.0, 1e5][i % 4];
            (scale * u(), scale * u())
        })
        .collect();
    let specials = [
        0.0,
        -0.0,
        1.0,
        -1.0,
        1e-310,
        1e301,
        f64::NAN,
        f64::INFINITY,
        -2.5,
    ];
    for &y in &specials {
        for &x in &specials {
            pairs.push((y, x));
        }
    }
    // The reduction boundaries of atan: t = 7/16 and 11/16 and their neighbours.
    for t in [0.4375f64, 0.6875, 1.0] {
        for d in [-1e-16, 0.0, 1e-16] {
            pairs.push((t + d, 1.0));
            pairs.push((1.0, t + d));
        }
    }
    for chunk in pairs.chunks(LANES) {
        let (mut y, mut x) = ([0.5; LANES], [0.5; LANES]);
        for (l, &(a, b)) in chunk.iter().enumerate() {
            (y[l], x[l]) = (a, b);
        }
        let got = fastmath::atan2_lanes(&y, &x);
        let ac = fastmath::acos_lanes(&x);
        for l in 0..LANES {
            let want = fastmath::atan2(y[l], x[l]);
            assert!(
                got[l].to_bits() == want.to_bits() || (got[l].is_nan() && want.is_nan()),
                "atan2({:e}, {:e}): {} vs {}",
                y[l],
                x[l],
                got[l],
                want
            );
            let want = fastmath::acos(x[l]);
            assert!(
                ac[l].to_bits() == want.to_bits() || (ac[l].is_nan() && want.is_nan()),
                "acos({:e})",
                x[l]
            );
        }
    }
}

#[test]
fn the_closed_form_of_eight_samples_equals_the_per_sample_closed_form_on_every_branch() {
    use printwatt::kinematics::nozzle_target;
    use printwatt::kinematics::opw::{solve_branch_batch, solve_branch_prepared, Branch, Prepared};
    let mut checked = 0;
    for name in ["abb_irb6700_200_260", "abb_irb4600_40_255", "staubli_tx200"] {
        let model = common::robot(name);
        let Some(p) = model.opw else {
            continue;
        };
        let k = Prepared::new(&p);
        let mut u = uniform(23);
        let reach = printwatt::evaluate::feasibility::reach_m(&model);
        for spin in [0.0, 0.7, -2.0] {
            // Flange poses with one orientation, tips spread over the workspace.
            let rot = nozzle_target(&nalgebra::Vector3::zeros(), spin).rot;
            for _ in 0..6 {
                let tips: Vec<nalgebra::Vector3<f64>> = (0..LANES)
                    .map(|_| {
                        nalgebra::Vector3::new(
                            reach * (0.6 + 0.3 * u()),
                            reach * 0.5 * u(),
                            reach * 0.4 * u(),
                        )
                    })
                    .collect();
                let mut pos = [[0.0; LANES]; 3];
                for (l, t) in tips.iter().enumerate() {
                    (pos[0][l], pos[1][l], pos[2][l]) = (t.x, t.y, t.z);
                }
                for branch in Branch::ALL {
                    for level in levels().into_iter().filter(|l| *l != Level::Scalar) {
                        let b = solve_branch_batch(&p, &k, &rot, &pos, branch, level);
                        for (l, t) in tips.iter().enumerate() {
                            let flange = printwatt::math::Frame { rot, pos: *t };
                            let want = solve_branch_prepared(&p, &k, &flange, branch, None);
                            if b.ok[l] {
                                let (q, s5) = want.expect("an ok lane has an answer");
                                for (got, want) in b.q(l).iter().zip(&q) {
                                    assert_eq!(got.to_bits(), want.to_bits(), "{name}");
                                }
                                assert_eq!(b.s5[l].to_bits(), s5.to_bits());
                                // The other wrist variant from the same lane.
                                let flip = Branch {
                                    wrist: branch.wrist.flipped(),
                                    ..branch
                                };
                                let (qf, _) =
                                    solve_branch_prepared(&p, &k, &flange, flip, None).unwrap();
                                let got = b.variant(&p, l, flip.wrist);
                                for (g, w) in got.iter().zip(&qf) {
                                    assert_eq!(g.to_bits(), w.to_bits(), "{name} flipped");
                                }
                                checked += 1;
                            } else if let Ok((_, s5)) = want {
                                assert!(s5 < 1e-9, "{name}: a lane with an answer not ok");
                            }
                        }
                    }
                }
            }
        }
    }
    assert!(checked > 500, "only {checked} lanes with an answer");
}

#[test]
fn energy_of_a_timed_path_is_the_same_on_the_scalar_and_every_simd_path() {
    // energy_of (the uncertainty draws' re-evaluation) computes the sines itself.
    use printwatt::evaluate::feasibility::FeasibilityOptions;
    use printwatt::evaluate::{Evaluator, Objective};
    use printwatt::frame::Placement;
    let _g = LEVEL_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let model = common::robot("abb_irb6700_200_260");
    let job = common::default_job(&model, &common::path("seed000_test_path.gcode"));
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let mut sc = ev.scratch().unwrap();
    let at = Placement::new(1.8, 0.0, 0.2, 90f64.to_radians());
    let timed = ev.timed(&mut sc, &at).expect("a feasible placement");
    let margins = Default::default();
    let mut energy = |level: Level| {
        assert!(simd::set_level(level));
        ev.energy_of(&mut sc, &timed, margins).unwrap()
    };
    let want = energy(Level::Scalar);
    for level in levels() {
        assert_eq!(energy(level), want, "{level:?}");
    }
    simd::set_level(simd::detected());
}

/// The default robot with every torque effect the lockstep pass knows (viscous, Coulomb,
/// Stribeck, armature, offset, balancer) and one it calls per lane (rigid_body), and `count`
/// states (rad, sines and cosines, rad/s, rad/s²) whose velocities sit around zero where the
/// smoothed Coulomb sign is not saturated, mixed with saturated ones, exact zeros and −0.
#[allow(clippy::type_complexity)]
fn every_effect_robot_and_states(
    count: usize,
) -> (
    printwatt::robot::RobotModel,
    Vec<(Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>)>,
) {
    let mut model = common::robot("abb_irb6700_200_260");
    let n = model.dof();
    let t = &mut model.effects.table;
    t.enabled = Some(
        [
            "viscous",
            "coulomb",
            "stribeck",
            "armature",
            "payload",
            "balancer",
            "offset",
            "rigid_body",
            "copper",
            "gear_efficiency",
            "regeneration",
            "standby",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect(),
    );
    t.stribeck_nm = Some(
        (0..n)
            .map(|j| if j == 2 { 0.0 } else { 5.0 + j as f64 })
            .collect(),
    );
    let mut values = t.values.clone().unwrap_or_default();
    values.insert(
        "offset".into(),
        (0..n).map(|j| 0.5 - 0.3 * j as f64).collect(),
    );
    t.values = Some(values.clone());
    // A small rigid-body error: an effect the lockstep pass calls per lane.
    let k = printwatt::effects::EffectSet::of_robot(&model)
        .unwrap()
        .get_mut("rigid_body")
        .unwrap()
        .params()
        .len();
    values.insert(
        "rigid_body".into(),
        (0..k).map(|i| 1e-3 * (1.0 + (i % 7) as f64)).collect(),
    );
    model.effects.table.values = Some(values);
    let mut u = uniform(23);
    let st = (0..count)
        .map(|k| {
            let q: Vec<f64> = (0..n).map(|_| 3.0 * u()).collect();
            let mut sc = vec![0.0; 2 * n];
            for j in 0..n {
                (sc[j], sc[n + j]) = fastmath::sin_cos(q[j]);
            }
            let qd = (0..n)
                .map(|j| match (k + j) % 5 {
                    0 => 0.03 * u(),  // |q̇/ε| < 30: some lanes below 20
                    1 => 0.005 * u(), // well inside the transition
                    2 => 2.0 * u(),   // saturated
                    3 => 0.0,
                    _ => -0.0,
                })
                .collect();
            let qdd = (0..n).map(|_| 10.0 * u()).collect();
            (q, sc, qd, qdd)
        })
        .collect();
    (model, st)
}

#[test]
fn lockstep_friction_motor_and_supply_stages_equal_the_per_sample_path_near_velocity_reversals() {
    // Every torque effect the lockstep pass knows (viscous, Coulomb, Stribeck, armature,
    // offset, balancer) and one it calls per lane (rigid_body), on every regeneration policy,
    // at velocities around zero where the smoothed Coulomb sign is not saturated (libm's tanh
    // per lane) mixed with saturated ones, exact zeros and −0 included: every field of every
    // sample bit for bit.
    use printwatt::robot::Regeneration;
    let (model, st) = every_effect_robot_and_states(6 * LANES + 3);
    for regeneration in [
        Regeneration::None,
        Regeneration::PerAxis,
        Regeneration::DcBus,
        Regeneration::Grid,
    ] {
        let em = EnergyModel::with_options(
            &model,
            energy::EnergyOptions {
                regeneration: Some(regeneration),
                ..Default::default()
            },
        )
        .unwrap();
        let desc = em.description();
        for e in [
            "stribeck",
            "offset",
            "balancer",
            "coulomb",
            "viscous",
            "rigid_body",
        ] {
            assert!(desc.contains(e), "{e} is in the model: {desc}");
        }
        let mut data = em.data();
        let mut inputs = vec![energy::LaneInputs::default(); 4];
        for chunk in st.chunks(LANES) {
            let mut want = vec![SamplePower::default(); chunk.len()];
            for ((q, sc, qd, qdd), w) in chunk.iter().zip(want.iter_mut()) {
                energy::eval_sample_with_sincos(&em, &mut data, q, sc, qd, qdd, w).unwrap();
            }
            for level in levels() {
                // The row-major pass' inputs are carried over from the chunk before (a short
                // last chunk keeps stale lanes).
                let x = &mut inputs[level as usize];
                let label = format!("{regeneration:?}");
                assert_energy_lanes_are_per_sample(&em, &mut data, chunk, &want, x, level, &label);
            }
        }
    }
}

/// What [`summed_pass`] runs after every batch: `(data, k0, count, rows)`.
type BatchHook<'h> = dyn FnMut(&mut DynData, usize, usize, &energy::Rows) + 'h;

/// The sums of the summed pass (energy::eval_rows_summed) over the row-major trajectory
/// `[q, sincos, qd, qdd]` (`n` joints a sample; the sines then the cosines, `2 n` a sample)
/// in batches of LANES samples from the first (the last batch short), with the weights
/// `weight(k)` (s), the sines given or computed, on `level`. `each(data, k0, count, rows)`,
/// where given, runs after every batch (its `count` samples from `k0`) on the same `data`.
#[allow(clippy::too_many_arguments)]
fn summed_pass(
    em: &EnergyModel,
    data: &mut DynData,
    n: usize,
    [q, sc, qd, qdd]: [&[f64]; 4],
    given: bool,
    weight: &dyn Fn(usize) -> f64,
    level: Level,
    mut each: Option<&mut BatchHook>,
) -> energy::EnergySums {
    let m = q.len() / n;
    let mut x = energy::LaneInputs::default();
    let mut out = energy::PowerLanes::default();
    let mut sums = energy::EnergySums::default();
    for k0 in (0..m).step_by(LANES) {
        let count = LANES.min(m - k0);
        let rows = energy::Rows {
            q: &q[k0 * n..],
            sincos: given.then(|| &sc[k0 * 2 * n..]),
            qd: &qd[k0 * n..],
            qdd: &qdd[k0 * n..],
        };
        let mut w = [0.0; LANES];
        for (l, w) in w.iter_mut().enumerate().take(count) {
            *w = weight(k0 + l);
        }
        energy::eval_rows_summed(
            em, data, count, &rows, &mut x, &mut out, &mut sums, &w, level,
        )
        .unwrap();
        if let Some(each) = each.as_mut() {
            each(data, k0, count, &rows);
        }
    }
    sums
}

#[test]
fn the_row_major_lockstep_pass_carries_its_inputs_across_batches_and_its_sums_equal_the_per_sample_path_bit_for_bit(
) {
    // energy::eval_rows (the sweep's energy pass: rows of the trajectory transposed into lanes,
    // RNEA and the tail compiled together per level, inputs and RNEA intermediates kept from
    // batch to batch, nothing cleared) against the per-sample path, with the sines given and
    // computed, over batches of 8, 8 and 3 samples, and the energy sums it adds in the same
    // pass (eval_rows_summed) equal the per-sample path's; short slices are an error, not a
    // panic.
    let model = common::robot("abb_irb6700_200_260");
    let n = model.dof();
    let em = EnergyModel::new(&model).unwrap();
    let mut data = em.data();
    let mut u = uniform(31);
    let m = 2 * LANES + 3;
    let q: Vec<f64> = (0..m * n).map(|_| 6.0 * u() - 3.0).collect();
    let qd: Vec<f64> = (0..m * n)
        .map(|i| {
            if i % 4 == 0 {
                0.01 * u()
            } else {
                2.0 * u() - 1.0
            }
        })
        .collect();
    let qdd: Vec<f64> = (0..m * n).map(|_| 20.0 * u() - 10.0).collect();
    let mut sc = vec![0.0; m * 2 * n];
    for k in 0..m {
        for j in 0..n {
            (sc[k * 2 * n + j], sc[k * 2 * n + n + j]) = fastmath::sin_cos(q[k * n + j]);
        }
    }
    let mut want = vec![SamplePower::default(); m];
    for (k, w) in want.iter_mut().enumerate() {
        let r = |a: &[f64]| a[k * n..(k + 1) * n].to_vec();
        energy::eval_sample(&em, &mut data, &r(&q), &r(&qd), &r(&qdd), w).unwrap();
    }
    // The sums of the per-sample path (energy::EnergySums::add_sample, trapezoid weights).
    let weight = |k: usize| printwatt::numerics::trapezoid_weight(k, m, 0.004);
    let mut want_sums = energy::EnergySums::default();
    for (k, w) in want.iter().enumerate() {
        want_sums.add_sample(k, w, weight(k), n);
    }
    let traj = [&q[..], &sc, &qd, &qdd];
    for level in levels() {
        for given in [true, false] {
            let mut x = energy::LaneInputs::default();
            let mut out = energy::PowerLanes::default();
            // eval_rows on the same data after every summed batch: neither disturbs the other.
            let mut rows_pass =
                |data: &mut DynData, k0: usize, count: usize, rows: &energy::Rows| {
                    energy::eval_rows(&em, data, count, rows, &mut x, &mut out, level).unwrap();
                    for l in 0..count {
                        assert_eq!(
                            format!("{:?}", out.sample(l)),
                            format!("{:?}", want[k0 + l]),
                            "{level:?}, sines given {given}, sample {}",
                            k0 + l
                        );
                    }
                };
            let sums = summed_pass(
                &em,
                &mut data,
                n,
                traj,
                given,
                &weight,
                level,
                Some(&mut rows_pass),
            );
            assert_eq!(
                format!("{sums:?}"),
                format!("{want_sums:?}"),
                "summed in the pass: {level:?}, sines given {given}"
            );
            let short = energy::Rows {
                q: &q[..n],
                sincos: None,
                qd: &qd,
                qdd: &qdd,
            };
            assert!(
                energy::eval_rows(&em, &mut data, 2, &short, &mut x, &mut out, level).is_err(),
                "{level:?}"
            );
        }
    }
}

#[test]
fn the_branch_a_closed_form_batch_hands_on_equals_branch_of_its_answers_bit_for_bit() {
    // take_near continues lane l from lane l − 1's answer without computing its branch when
    // the batch knows it (BranchBatch::known_branch): next_branch must be exactly
    // Prepared::branch_of of each lane's answer, also at the branch boundaries (q3 + ψ3 and
    // q5 on 0 and ±π, where only the sign of a wrapped angle decides).
    use printwatt::kinematics::nozzle_target;
    use printwatt::kinematics::opw::{solve_branch_batch, Branch, Prepared};
    use std::f64::consts::PI;
    for name in ["abb_irb6700_200_260", "abb_irb4600_40_255", "staubli_tx200"] {
        let model = common::robot(name);
        let Some(p) = model.opw else {
            continue;
        };
        let k = Prepared::new(&p);
        let mut u = uniform(29);
        let reach = printwatt::evaluate::feasibility::reach_m(&model);
        let rot = nozzle_target(&nalgebra::Vector3::zeros(), 0.3).rot;
        let mut pos = [[0.0; LANES]; 3];
        for (i, scale) in [(0.6, 0.3), (0.0, 0.5), (0.0, 0.4)].into_iter().enumerate() {
            for v in pos[i].iter_mut() {
                *v = reach * (scale.0 + scale.1 * u());
            }
        }
        for branch in Branch::ALL {
            for level in levels().into_iter().filter(|l| *l != Level::Scalar) {
                let mut b = solve_branch_batch(&p, &k, &rot, &pos, branch, level);
                for l in 0..LANES {
                    // The lane's vector is the joint-by-joint answer continuing_lanes reads.
                    for (qj, v) in b.qj.iter().zip(b.q(l)) {
                        assert_eq!(qj[l].to_bits(), v.to_bits(), "{name}");
                    }
                }
                for l in 0..LANES {
                    assert_eq!(
                        b.next_branch[l],
                        k.branch_of(&p, &b.q(l)),
                        "{name} lane {l}"
                    );
                }
                // Boundary joint vectors (the lockstep branch_of on its own): q3 + ψ3, q5
                // and q2 on 0, −0, ±π and just off them.
                let psi3 = k.psi3();
                for (i, edge) in [0.0, -0.0, PI, -PI, 1e-17, PI - 1e-15]
                    .into_iter()
                    .enumerate()
                {
                    let mut q = [[0.0; 6]; LANES];
                    for (l, ql) in q.iter_mut().enumerate() {
                        *ql = [u(), u(), u(), u(), u(), u()];
                        let o = match (l + i) % 3 {
                            0 => 4,
                            1 => 2,
                            _ => 1,
                        };
                        let v = if o == 2 { edge - psi3 } else { edge };
                        ql[o] = (v + p.offsets[o]) * p.signs[o];
                    }
                    let got = printwatt::kinematics::opw::branch_of_batch(&p, &k, &q);
                    for (l, ql) in q.iter().enumerate() {
                        assert_eq!(got[l], k.branch_of(&p, ql), "{name} edge {edge} lane {l}");
                    }
                }
                // A joint vector other than the previous lane's answer is not known.
                let mut other = b.q(2);
                other[0] += 1e-12;
                assert_eq!(b.known_branch(3, &other), None);
                assert_eq!(b.known_branch(0, &other), None, "prev not set: NaN");
                b.prev = other;
                assert_eq!(b.known_branch(0, &other), Some(b.branch));
            }
        }
    }
}

#[test]
fn fk_recheck_verdicts_in_lockstep_equal_the_per_sample_check_around_the_tolerance() {
    // check_batch decides the lanes that pass with room to spare in lockstep and hands every
    // other lane to the per-sample check: the verdicts equal check_with_sincos's for targets
    // moved by 0 to 2 tolerances in position or orientation.
    use printwatt::kinematics::{nozzle_target, IkSolver};
    let model = common::robot("abb_irb6700_200_260");
    let solver = IkSolver::new(&model).unwrap();
    assert!(solver.batch_checkable());
    let n = model.dof();
    let st = states(31, n, 6 * LANES);
    let chain = printwatt::kinematics::fk::FastChain::new(&model);
    let mut u = uniform(37);
    let mut seen = [0usize; 2];
    for (c, chunk) in st.chunks(LANES).enumerate() {
        let targets: Vec<printwatt::math::Frame> = chunk
            .iter()
            .enumerate()
            .map(|(l, (q, ..))| {
                let mut sc = vec![0.0; 2 * n];
                let mut f = chain.tool_with_sincos(q, &mut sc);
                let r = (c * LANES + l) % 4;
                let x = 2.0 * u().abs();
                match r {
                    0 => f.pos.x += x * solver.check_position_m,
                    1 => f.pos.z -= 0.5 * x * solver.check_position_m,
                    2 => {
                        let spin = nozzle_target(&nalgebra::Vector3::zeros(), x * 1e-6).rot;
                        f.rot *= spin;
                    }
                    _ => {}
                }
                f
            })
            .collect();
        let want: Vec<bool> = chunk
            .iter()
            .zip(&targets)
            .map(|((q, ..), t)| {
                let mut sc = vec![0.0; 2 * n];
                solver.check_with_sincos(t, q, &mut sc).is_ok()
            })
            .collect();
        for v in &want {
            seen[*v as usize] += 1;
        }
        for level in levels().into_iter().filter(|l| *l != Level::Scalar) {
            // The first failing lane is reported; the lanes before it pass.
            let mut out = vec![vec![0.0; 2 * n]; LANES];
            let mut it = out.iter_mut();
            let r = solver.check_batch(
                chunk.len(),
                |l| targets[l],
                |l| &chunk[l].0,
                |_| it.next().unwrap(),
                level,
            );
            let first_fail = want.iter().position(|ok| !ok);
            match (r, first_fail) {
                (Ok(()), None) => {}
                (Err((l, _)), Some(f)) => assert_eq!(l, f, "{level:?}"),
                (r, f) => panic!("{level:?}: {r:?} vs first failing lane {f:?}"),
            }
        }
    }
    assert!(seen[0] > 3 && seen[1] > 3, "both verdicts occur: {seen:?}");
}

#[test]
fn precomputed_joint_checks_equal_the_per_sample_joint_check_and_leave_the_same_margins() {
    use printwatt::evaluate::feasibility::margins::{check_joint_sample_with, JointChecks};
    use printwatt::evaluate::feasibility::{FeasibilityOptions, Margins};
    for name in ["abb_irb6700_200_260", "ur10e", "staubli_tx200"] {
        let model = common::robot(name);
        let n = model.dof();
        let o = FeasibilityOptions::default();
        let checks = JointChecks::new(&model, &o);
        let mut u = uniform(41);
        let (mut a, mut b) = (Margins::default(), Margins::default());
        let mut fails = 0;
        for k in 0..3000 {
            // Joint vectors across the limits (some within the margin or beyond), some with
            // joint 5 near 0 (the wrist rule) and fast wrist joints.
            let q: Vec<f64> = model
                .joints
                .iter()
                .enumerate()
                .map(|(j, jt)| {
                    let (lo, hi) = (jt.lower.max(-4.0), jt.upper.min(4.0));
                    let v = 0.5 * (lo + hi) + 0.52 * (hi - lo) * u();
                    if j == 4 && k % 3 == 0 {
                        1e-3 * u()
                    } else {
                        v
                    }
                })
                .collect();
            let mut sc = vec![0.0; 2 * n];
            for j in 0..n {
                (sc[j], sc[n + j]) = fastmath::sin_cos(q[j]);
            }
            let qd: Vec<f64> = (0..n).map(|_| 3.0 * u()).collect();
            let qdd: Vec<f64> = (0..n).map(|_| 20.0 * u()).collect();
            let sincos = (k % 5 != 0).then_some(&sc[..]);
            let want = check_joint_sample_with(&model, &o, &q, sincos, &qd, &qdd, &mut a);
            let got = checks.check(&model, &o, &q, sincos, &qd, &qdd, &mut b);
            assert_eq!(got, want, "{name} sample {k}");
            assert_eq!(format!("{b:?}"), format!("{a:?}"), "{name} sample {k}");
            fails += want.is_some() as usize;
        }
        assert!(
            fails > 100 && fails < 2900,
            "{name}: {fails} failing samples"
        );
    }
}

#[test]
fn timing_a_path_gives_the_same_trajectory_slowdowns_and_failures_on_every_level() {
    // The joint stage's derivatives (row stencils) and limit checks (screened in lockstep)
    // against the per-sample path: robots with and without a closed form, two paths, the
    // drives' limits as shipped and lowered so that the controller slows down (and, lowered
    // far, fails): the same joint trajectory to the bit, the same slow-downs and rounds, the
    // same failure.
    use printwatt::kinematics::IkSolver;
    use printwatt::timing::{self, blend_path, JointStageOptions, ProfileOptions};
    use printwatt::toolpath::Placement;
    let _g = LEVEL_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let (mut slowed, mut failed, mut plain) = (0, 0, 0);
    let cases = [
        (
            "abb_irb6700_200_260",
            Placement::new(1.7, 0.0, 0.0, 90f64.to_radians()),
        ),
        (
            "abb_irb4600_40_255",
            Placement::new(1.4, 0.0, 0.3, 90f64.to_radians()),
        ),
        (
            "staubli_tx200",
            Placement::new(1.2, 0.0, 0.3, 90f64.to_radians()),
        ),
        ("ur10e", Placement::new(0.7, 0.0, 0.2, 90f64.to_radians())),
    ];
    for (name, at) in cases {
        for path in ["seed000_test_path.gcode", "default.gcode"] {
            let tp = common::path(path);
            let moves = timing::moves_from_toolpath(&tp);
            let pieces = blend_path(&moves);
            for scale in [1.0, 0.5, 0.2, 0.02] {
                let mut model = common::robot(name);
                for j in &mut model.joints {
                    j.velocity_limit *= scale;
                    j.acceleration_limit *= scale;
                    j.jerk_limit *= scale;
                }
                let solver = IkSolver::new(&model).unwrap();
                let run = |level: Level| {
                    assert!(simd::set_level(level));
                    timing::time_at(
                        &solver,
                        &pieces,
                        &|i| moves[i].line,
                        &at,
                        &ProfileOptions::default(),
                        &JointStageOptions::default(),
                    )
                };
                let want = run(Level::Scalar);
                match &want {
                    Ok(t) if t.rounds > 1 => slowed += 1,
                    Ok(_) => plain += 1,
                    Err(_) => failed += 1,
                }
                for level in levels() {
                    let got = run(level);
                    let what = format!("{name} {path} limits x{scale} {level:?}");
                    match (&got, &want) {
                        (Ok(g), Ok(w)) => {
                            assert_eq!(bits(&g.traj.q), bits(&w.traj.q), "{what}");
                            assert_eq!(bits(&g.traj.qd), bits(&w.traj.qd), "{what}");
                            assert_eq!(bits(&g.traj.qdd), bits(&w.traj.qdd), "{what}");
                            assert_eq!(g.slowdowns, w.slowdowns, "{what}");
                            assert_eq!(g.rounds, w.rounds, "{what}");
                            assert_eq!(g.accel_factor.to_bits(), w.accel_factor.to_bits());
                        }
                        (Err(g), Err(w)) => {
                            assert_eq!(format!("{g:?}"), format!("{w:?}"), "{what}")
                        }
                        _ => panic!("{what}: {got:?} vs {want:?}"),
                    }
                }
            }
        }
    }
    simd::set_level(simd::detected());
    assert!(
        slowed >= 2 && failed >= 1 && plain >= 2,
        "{slowed} slowed, {failed} failed, {plain} plain"
    );
}

#[test]
fn a_limit_table_fits_joint_vectors_exactly_as_fit_limits_does() {
    // LimitTable::fit (path IK's per-sample fit, limits gathered once) against fit_limits on
    // every shipped robot: joint vectors inside, at and beyond the limits (by the tolerance
    // and by whole turns), wide-range joints past ±π from their reference, infinite and NaN
    // entries, no reference, a short reference, a short vector: the same fitted vector to the
    // bit and the same error.
    use printwatt::kinematics::{fit_limits, LimitTable};
    let mut u = uniform(11);
    let mut fitted = 0;
    for name in [
        "abb_irb6700_200_260",
        "abb_irb4600_40_255",
        "staubli_tx200",
        "ur10e",
        "puma560",
    ] {
        let model = common::robot(name);
        let n = model.dof();
        let table = LimitTable::new(&model);
        for case in 0..4000 {
            let mut q: Vec<f64> = model
                .joints
                .iter()
                .map(|j| {
                    let (lo, hi) = (j.lower.max(-10.0), j.upper.min(10.0));
                    let mid = 0.5 * (lo + hi);
                    let half = 0.5 * (hi - lo);
                    match case % 7 {
                        0 => mid + 0.99 * half * u(),
                        1 => mid + 1.3 * half * u(),
                        2 => {
                            if u() > 0.0 {
                                hi + 2e-9 * u()
                            } else {
                                lo + 2e-9 * u()
                            }
                        }
                        3 => mid + 0.9 * half * u() + std::f64::consts::TAU * (3.0 * u()).round(),
                        4 => std::f64::consts::PI * u() * 1.2,
                        5 => {
                            [f64::NEG_INFINITY, f64::INFINITY, f64::NAN, 0.5, -0.5][(case / 7) % 5]
                        }
                        _ => 20.0 * u(),
                    }
                })
                .collect();
            let r: Vec<f64> = q.iter().map(|v| v + 4.0 * u()).collect();
            if case % 11 == 0 {
                q.truncate(n - 1);
            }
            let refs: [Option<&[f64]>; 3] = [None, Some(&r), Some(&r[..n / 2])];
            for q_ref in refs {
                let (mut a, mut b) = (q.clone(), q.clone());
                let want = fit_limits(&model, &mut a, q_ref);
                let got = table.fit(&model, &mut b, q_ref);
                assert_eq!(
                    format!("{got:?}"),
                    format!("{want:?}"),
                    "{name} {q:?} {q_ref:?}"
                );
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&b), bits(&a), "{name} {q:?} {q_ref:?}");
                fitted += want.is_ok() as usize;
            }
        }
    }
    assert!(fitted > 10_000, "only {fitted} fitted");
}

#[test]
fn the_prunes_branch_check_in_lockstep_rejects_the_same_first_sample_with_the_same_error() {
    // IkSolver::branch_admits_batch (the prune before tracking, 8 thinned samples at once)
    // against branch_admits sample by sample: tips inside and beyond the reach, every
    // shoulder/elbow branch, several nozzle spins, and targets at and near the wrist
    // singularity (from joint vectors with q5 = 0 .. 1e-3): the same first rejected sample
    // with the same error, for every start within the batch, on every level.
    use printwatt::kinematics::fk::tool_pose;
    use printwatt::kinematics::opw::{Elbow, Shoulder};
    use printwatt::kinematics::{nozzle_target, IkSolver};
    use printwatt::math::{Frame, V3};
    let _g = LEVEL_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let (mut rejected, mut admitted) = (0, 0);
    let robots = ["abb_irb6700_200_260", "abb_irb4600_40_255", "staubli_tx200"];
    for (name, narrow) in robots.iter().flat_map(|r| [(*r, false), (*r, true)]) {
        let mut model = common::robot(name);
        assert!(model.opw.is_some(), "{name}");
        if narrow {
            // Wrist joints 4 and 6 within ±0.3 rad: at the singularity only the zeroed
            // q4, q6 of branch_admits fit.
            for j in [3, 5] {
                (model.joints[j].lower, model.joints[j].upper) = (-0.3, 0.3);
            }
        }
        let solver = IkSolver::new(&model).unwrap();
        let reach = printwatt::evaluate::feasibility::reach_m(&model);
        let mut u = uniform(31);
        let mut batches: Vec<(nalgebra::Matrix3<f64>, Vec<V3>)> = Vec::new();
        for spin in [0.0, 0.7, -2.0, 3.1] {
            let rot = nozzle_target(&V3::zeros(), spin).rot;
            for _ in 0..12 {
                let tips = (0..LANES)
                    .map(|_| {
                        V3::new(
                            reach * (0.55 + 0.45 * u()),
                            reach * 0.6 * u(),
                            reach * 0.5 * u(),
                        )
                    })
                    .collect();
                batches.push((rot, tips));
            }
        }
        for q5 in [0.0, 1e-9, 1e-7, 3e-7, 2e-6, 1e-3] {
            for _ in 0..6 {
                let mut q: Vec<f64> = (0..6).map(|_| 1.2 * u()).collect();
                q[4] = q5;
                let t: Frame = tool_pose(&model, &q);
                let tips = (0..LANES)
                    .map(|l| t.pos + V3::new(1e-8 * l as f64 * u(), 0.0, 1e-8 * l as f64 * u()))
                    .collect();
                batches.push((t.rot, tips));
            }
        }
        for (rot, tips) in &batches {
            for (shoulder, elbow) in [
                (Shoulder::Front, Elbow::Up),
                (Shoulder::Front, Elbow::Down),
                (Shoulder::Back, Elbow::Up),
                (Shoulder::Back, Elbow::Down),
            ] {
                for start in 0..LANES {
                    let tips = &tips[start..];
                    let want = tips.iter().enumerate().find_map(|(l, tip)| {
                        let target = Frame {
                            rot: *rot,
                            pos: *tip,
                        };
                        solver
                            .branch_admits(&target, shoulder, elbow)
                            .err()
                            .map(|e| (l, e))
                    });
                    match &want {
                        Some(_) => rejected += 1,
                        None => admitted += 1,
                    }
                    for level in levels() {
                        let got = solver.branch_admits_batch(rot, tips, shoulder, elbow, level);
                        assert_eq!(
                            format!("{got:?}"),
                            format!("{want:?}"),
                            "{name} narrow {narrow} {shoulder:?} {elbow:?} from {start} {level:?}"
                        );
                    }
                }
            }
        }
    }
    assert!(
        rejected > 300 && admitted > 300,
        "{rejected} rejected, {admitted} admitted"
    );
}

#[test]
fn tracking_in_lockstep_batches_gives_the_per_sample_answers_and_sines_through_the_wrist_singularity(
) {
    // timing::joint::track takes the leading lanes of each closed-form batch at once when
    // they provably continue one another (IkSolver::continuing_lanes: the limit fit in
    // lockstep, 2π shifts included; the flipped wrist variant not fitted where it cannot be
    // nearer) and checks them straight from the lanes. Against the per-sample path
    // (Level::Scalar: solve_near with both wrist variants fitted near the singularity), on
    // paths that pass the wrist singularity, from every first-sample configuration, with the
    // shipped limits, joint 4/6 ranges shifted by 2π and narrowed: the same answers, TCP
    // points and sines bit for bit, or the same failure.
    use printwatt::kinematics::{opw, IkSolver};
    use printwatt::timing::{self, blend_path, Buffers, Plan, ProfileOptions};
    use printwatt::toolpath::Placement;
    use std::f64::consts::PI;
    let _g = LEVEL_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let (mut ok_cases, mut failed, mut near_singular) = (0, 0, 0);
    let cases = [
        (
            "abb_irb6700_200_260",
            Placement::new(1.534, -0.121, 0.0, 90f64.to_radians()),
        ),
        (
            "abb_irb6700_200_260",
            Placement::new(1.7, 0.0, 0.0, 90f64.to_radians()),
        ),
        (
            "abb_irb6700_200_260",
            Placement::new(1.534, -0.121, 0.0, 0.0).with_spin(1.0),
        ),
        (
            "abb_irb4600_40_255",
            Placement::new(1.4, 0.0, 0.3, 90f64.to_radians()),
        ),
        (
            "staubli_tx200",
            Placement::new(1.2, 0.0, 0.3, 90f64.to_radians()),
        ),
        ("ur10e", Placement::new(0.7, 0.0, 0.2, 90f64.to_radians())),
    ];
    let popts = ProfileOptions::default();
    for (name, at) in cases {
        for path in ["default.gcode", "seed000_test_path.gcode"] {
            let tp = common::path(path);
            let moves = timing::moves_from_toolpath(&tp);
            let pieces = blend_path(&moves);
            let plan = Plan::new(&pieces, &popts);
            for limits in 0..3 {
                let mut model = common::robot(name);
                for j in [3, 5] {
                    let jt = &mut model.joints[j];
                    match limits {
                        // Shifted by 2π: every answer is fitted onto another turn.
                        1 => (jt.lower, jt.upper) = (0.0, 2.0 * PI + 1.0),
                        // Narrowed: the fit fails, or the other wrist variant is taken.
                        2 => (jt.lower, jt.upper) = (-2.0, 2.0),
                        _ => {}
                    }
                }
                let solver = IkSolver::new(&model).unwrap();
                let first = at.frame().apply(&plan.motion.p[0]);
                let Ok(starts) = solver.solve_all(&at.nozzle_target(&first)) else {
                    continue;
                };
                for s in starts {
                    let run = |level: Level| {
                        assert!(simd::set_level(level));
                        let mut buf = Buffers::default();
                        let r = timing::joint::track(
                            &solver,
                            &pieces,
                            &|i| moves[i].line,
                            &plan.motion,
                            &at,
                            &s.q,
                            &mut buf,
                        );
                        (r, buf)
                    };
                    let (want, wb) = run(Level::Scalar);
                    match &want {
                        Ok(()) => {
                            ok_cases += 1;
                            if let Some(p) = &model.opw {
                                near_singular += wb
                                    .qs
                                    .chunks(6)
                                    .filter(|q| opw::wrist_singularity(p, q) < 0.05)
                                    .count();
                            }
                        }
                        Err(_) => failed += 1,
                    }
                    for level in levels() {
                        let (got, gb) = run(level);
                        let what = format!("{name} {path} limits {limits} {level:?}");
                        assert_eq!(format!("{got:?}"), format!("{want:?}"), "{what}");
                        if want.is_ok() {
                            assert_eq!(bits(&gb.qs), bits(&wb.qs), "{what}");
                            assert_eq!(bits(&gb.sincos), bits(&wb.sincos), "{what}");
                            let tcp = |b: &Buffers| {
                                b.tcp
                                    .iter()
                                    .flat_map(|p| p.iter().map(|v| v.to_bits()))
                                    .collect::<Vec<_>>()
                            };
                            assert_eq!(tcp(&gb), tcp(&wb), "{what}");
                        }
                    }
                }
            }
        }
    }
    simd::set_level(simd::detected());
    assert!(
        ok_cases >= 4 && failed >= 4 && near_singular >= 100,
        "cases: {ok_cases} tracked ({near_singular} samples near the wrist singularity), {failed} failed"
    );
}

#[test]
fn skipping_the_flipped_wrist_fit_where_it_cannot_be_nearer_gives_solve_nears_answer() {
    // take_near returns the unflipped variant without fitting the flipped one when its step
    // from q_prev is at most FLIP_CANNOT_WIN_RAD. Against solve_near_unchecked (both fitted)
    // near the wrist singularity, with q_prev stepped away from the answer by up to 3 rad in
    // joints 4 and 6 (either side of the bound) and narrowed limits.
    use printwatt::kinematics::IkSolver;
    use printwatt::math::Frame;
    use std::f64::consts::PI;
    let _g = LEVEL_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let mut u = uniform(41);
    let (mut compared, mut near, mut far) = (0, 0, 0);
    for name in ["abb_irb6700_200_260", "abb_irb4600_40_255", "staubli_tx200"] {
        for narrow in [false, true] {
            let mut model = common::robot(name);
            if narrow {
                for j in [3, 5] {
                    (model.joints[j].lower, model.joints[j].upper) = (-2.5, 2.5);
                }
            }
            let solver = IkSolver::new(&model).unwrap();
            for _ in 0..300 {
                // A configuration near the wrist singularity, its tool pose the target.
                let mut q0 = [0.0; 6];
                for (j, v) in q0.iter_mut().enumerate() {
                    *v = if j == 4 { 0.15 * u() } else { 1.2 * u() };
                }
                let f = printwatt::kinematics::tool_pose(&model, &q0);
                let mut tips = [f.pos; LANES];
                for (l, t) in tips.iter_mut().enumerate() {
                    t.x += 1e-4 * l as f64;
                }
                let mut q_prev = q0;
                q_prev[3] += 3.0 * u();
                q_prev[5] += 3.0 * u();
                q_prev[0] += 0.01 * u();
                for level in levels().into_iter().filter(|l| *l != Level::Scalar) {
                    let Some(b) = solver.solve_near_batch(&f.rot, &tips, &q_prev, level) else {
                        continue;
                    };
                    for (l, tip) in tips.iter().enumerate() {
                        let target = Frame {
                            rot: f.rot,
                            pos: *tip,
                        };
                        let got = solver.take_near(&b, l, &target, &q_prev);
                        let want = solver.solve_near_unchecked(&target, &q_prev);
                        match (&got, &want) {
                            (Ok(g), Ok(w)) => {
                                assert_eq!(bits(g), bits(w), "{name} lane {l} {level:?}");
                                let d = g
                                    .iter()
                                    .zip(&q_prev)
                                    .map(|(a, b)| (a - b).abs())
                                    .fold(0.0, f64::max);
                                compared += 1;
                                near += usize::from(d <= 1.5);
                                far += usize::from(d > 1.5 && d < PI);
                            }
                            _ => assert_eq!(format!("{got:?}"), format!("{want:?}"), "{name}"),
                        }
                    }
                }
            }
        }
    }
    assert!(
        compared > 1000 && near > 50 && far > 50,
        "{compared} compared, {near} within the bound, {far} beyond it"
    );

    fn bits(v: &[f64]) -> Vec<u64> {
        v.iter().map(|x| x.to_bits()).collect()
    }
}

#[test]
fn the_lockstep_fk_recheck_measures_within_its_bound_and_gives_the_per_sample_verdicts_written_or_appended(
) {
    // FastChain::check_lanes measures the errors on a pose within fk::CHECK_POSE_BOUND of the
    // exact FK (not the same bits) and gives the joints' sines bit for bit; IkSolver::check_lanes
    // decides only the lanes with room to spare on it and hands every other lane to the
    // per-sample check: the same verdicts, first failing lane and error as check_with_sincos
    // (and its sines when all pass), for lanes moved by 0 to a few tolerances around one
    // target rotation.
    use printwatt::kinematics::fk::{FastChain, CHECK_POSE_BOUND};
    use printwatt::kinematics::IkSolver;
    use printwatt::math::Frame;
    let _g = LEVEL_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let mut u = uniform(43);
    let (mut seen, mut worst) = ([0usize; 2], 0.0f64);
    for name in [
        "abb_irb6700_200_260",
        "abb_irb4600_40_255",
        "staubli_tx200",
        "ur10e",
    ] {
        let model = common::robot(name);
        let solver = IkSolver::new(&model).unwrap();
        let chain = FastChain::new(&model);
        if !solver.batch_checkable() {
            continue;
        }
        let n = model.dof();
        for round in 0..200 {
            let q0: Vec<f64> = model.joints.iter().map(|_| 2.0 * u()).collect();
            let f0 = chain.tool(&q0);
            let mut qb = [[0.0; LANES]; 8];
            let mut tips = [f0.pos; LANES];
            let mut tp = [[0.0; LANES]; 3];
            for l in 0..LANES {
                // Joint and position offsets from none to a few tolerances (1e-6).
                let e = [0.0, 1e-10, 1e-9, 3e-8, 1e-7, 4e-7, 1e-6, 3e-6][(l + round) % LANES];
                for j in 0..n {
                    qb[j][l] = q0[j] + e * u();
                }
                let d = [0.0, 2e-7, 4.99e-7, 5e-7, 9.9e-7, 1e-6, 1.2e-6, 3e-6][(3 * l + round) % 8];
                tips[l].x += d * u();
                tips[l].y += d * u();
                tips[l].z += d * u();
                for i in 0..3 {
                    tp[i][l] = tips[l][i];
                }
            }
            let target = solver.path_target(&f0.rot);
            for level in levels().into_iter().filter(|l| *l != Level::Scalar) {
                // The bound, against the exact pose.
                let cl = chain.check_lanes(&qb, &chain.check_rotation(&f0.rot), &tp, level);
                for l in 0..LANES {
                    let ql: Vec<f64> = (0..n).map(|j| qb[j][l]).collect();
                    let mut sc = vec![0.0; 2 * n];
                    let f = chain.tool_with_sincos(&ql, &mut sc);
                    let dp = (f.pos - tips[l]).norm();
                    let dr = (f.rot - f0.rot).norm();
                    let err = (cl.dp2[l].sqrt() - dp)
                        .abs()
                        .max((cl.f2[l].sqrt() - dr).abs());
                    worst = worst.max(err);
                    assert!(err <= CHECK_POSE_BOUND, "{name} lane {l}: {err:e}");
                    for j in 0..n {
                        assert_eq!(cl.s[j][l].to_bits(), sc[j].to_bits(), "{name}");
                        assert_eq!(cl.c[j][l].to_bits(), sc[n + j].to_bits(), "{name}");
                    }
                }
                // The verdicts, against the per-sample check.
                let mut want = Vec::new();
                for (l, tip) in tips.iter().enumerate() {
                    let ql: Vec<f64> = (0..n).map(|j| qb[j][l]).collect();
                    let mut sc = vec![0.0; 2 * n];
                    let t = Frame {
                        rot: f0.rot,
                        pos: *tip,
                    };
                    want.push((solver.check_with_sincos(&t, &ql, &mut sc), sc));
                }
                let mut out = vec![0.0; LANES * 2 * n];
                let got = solver.check_lanes(LANES, &qb, &target, &tips, &mut out, level);
                // check_lanes_push (track's batches): the same verdict, the same values
                // appended after what the vector held, nothing appended on an error.
                let mut pushed = vec![1.5, -2.5];
                let mut tpl = [[0.0; LANES]; 3];
                for (l, t) in tips.iter().enumerate() {
                    (tpl[0][l], tpl[1][l], tpl[2][l]) = (t.x, t.y, t.z);
                }
                let got_push =
                    solver.check_lanes_push(LANES, &qb, &target, &tips, &tpl, &mut pushed, level);
                assert_eq!(
                    format!("{got_push:?}"),
                    format!("{got:?}"),
                    "{name} {level:?}"
                );
                assert_eq!(bits(&pushed[..2]), bits(&[1.5, -2.5]), "{name}");
                if got.is_ok() {
                    assert_eq!(bits(&pushed[2..]), bits(&out), "{name} {level:?}");
                } else {
                    assert_eq!(pushed.len(), 2, "{name} {level:?}");
                }
                let first = want.iter().position(|(r, _)| r.is_err());
                match (&got, first) {
                    (Ok(()), None) => {}
                    (Err((l, e)), Some(f)) => {
                        assert_eq!(*l, f, "{name} {level:?}");
                        assert_eq!(
                            format!("{:?}", Err::<(), _>(e)),
                            format!("{:?}", want[f].0.as_ref().map(|_| ())),
                            "{name}"
                        );
                    }
                    _ => panic!("{name} {level:?}: {got:?} vs first failing lane {first:?}"),
                }
                // The sines are written when every lane passes.
                for (l, (r, sc)) in want.iter().enumerate().take(first.unwrap_or(LANES)) {
                    seen[usize::from(r.is_ok())] += 1;
                    let o = &out[l * 2 * n..(l + 1) * 2 * n];
                    if got.is_ok() {
                        assert_eq!(bits(o), bits(sc), "{name} lane {l}");
                    }
                }
                if let Some(f) = first {
                    seen[0] += usize::from(f < LANES);
                }
            }
        }
    }
    assert!(
        seen[0] > 50 && seen[1] > 500,
        "verdicts seen: {seen:?}, worst {worst:e}"
    );

    fn bits(v: &[f64]) -> Vec<u64> {
        v.iter().map(|x| x.to_bits()).collect()
    }
}

#[test]
fn the_prunes_reach_test_in_lockstep_rejects_the_same_first_sample_with_the_same_error() {
    // time_at's first prune tests every sample's wrist centre 8 at a time (the front
    // shoulder's reach in lockstep, per sample where it rejects): on placements from well
    // inside to beyond the reach, the same outcome as the per-sample path (Level::Scalar),
    // the same first unreachable sample and error.
    use printwatt::kinematics::IkSolver;
    use printwatt::timing::{self, blend_path, JointStageOptions, ProfileOptions};
    use printwatt::toolpath::Placement;
    let _g = LEVEL_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let (mut unreachable, mut other) = (0, 0);
    let cases = [
        ("abb_irb6700_200_260", (1.534, -0.121, 0.0)),
        ("abb_irb4600_40_255", (1.4, 0.0, 0.3)),
        ("ur10e", (0.7, 0.0, 0.2)),
    ];
    for (name, (x0, y0, z0)) in cases {
        let model = common::robot(name);
        let solver = IkSolver::new(&model).unwrap();
        let tp = common::path("default.gcode");
        let moves = timing::moves_from_toolpath(&tp);
        let pieces = blend_path(&moves);
        for f in [0.5, 0.8, 0.95, 1.0, 1.05, 1.1, 1.2, 1.4, 1.7] {
            let x = x0 * f;
            let at = Placement::new(x, y0, z0, 90f64.to_radians());
            let run = |level: Level| {
                assert!(simd::set_level(level));
                timing::time_at(
                    &solver,
                    &pieces,
                    &|i| moves[i].line,
                    &at,
                    &ProfileOptions::default(),
                    &JointStageOptions::default(),
                )
                .map(|t| t.traj.q.iter().map(|v| v.to_bits()).collect::<Vec<_>>())
            };
            let want = run(Level::Scalar);
            match &want {
                Err(timing::TimingFailure::Unreachable { .. }) => unreachable += 1,
                _ => other += 1,
            }
            for level in levels() {
                let got = run(level);
                assert_eq!(
                    format!("{got:?}"),
                    format!("{want:?}"),
                    "{name} x {x} {level:?}"
                );
            }
        }
    }
    simd::set_level(simd::detected());
    assert!(
        unreachable >= 5 && other >= 5,
        "{unreachable} unreachable, {other} other"
    );
}

#[test]
fn continuing_lanes_verdict_masks_give_the_same_lanes_on_every_level_and_take_nears_answers() {
    // IkSolver::continuing_lanes decides its lanes with vector compares and movemask on AVX2
    // and AVX-512 (lane_ops::Avx2) and with lane loops on the scalar level (lane_ops::Plain).
    // On batches with steps around max_step, 2π-shifted and narrowed wrist limits (the fit's
    // slow path), lanes out of reach or NaN, and poses near the wrist singularity: the same
    // taken count, answers and branch on every level, and each taken lane is take_near's
    // answer continuing the previous one, bit for bit.
    use printwatt::kinematics::{nozzle_target, Continuing, IkSolver, MAX_DOF};
    use std::f64::consts::PI;
    let mut u = uniform(41);
    let (mut taken_total, mut partial, mut slow) = (0usize, 0usize, 0usize);
    for name in ["abb_irb6700_200_260", "abb_irb4600_40_255", "staubli_tx200"] {
        for limits in 0..3 {
            let mut model = common::robot(name);
            for j in [3, 5] {
                let jt = &mut model.joints[j];
                match limits {
                    1 => (jt.lower, jt.upper) = (0.0, 2.0 * PI + 1.0),
                    2 => (jt.lower, jt.upper) = (-2.0, 2.0),
                    _ => {}
                }
            }
            let solver = IkSolver::new(&model).unwrap();
            let reach = printwatt::evaluate::feasibility::reach_m(&model);
            for case in 0..60 {
                // The nozzle points down, or sideways (near the wrist singularity for some
                // tips), spun about its axis.
                let spin = PI * u();
                let mut rot = nozzle_target(&nalgebra::Vector3::zeros(), spin).rot;
                if case % 3 == 1 {
                    rot = nalgebra::Rotation3::from_axis_angle(&nalgebra::Vector3::y_axis(), 1.3)
                        .into_inner()
                        * rot;
                }
                let start = nalgebra::Vector3::new(
                    reach * (0.45 + 0.2 * u()),
                    reach * 0.3 * u(),
                    reach * 0.3 * u(),
                );
                // Steps of 0.1 mm to 20 cm; now and then one far out of reach or NaN.
                let step =
                    nalgebra::Vector3::new(u(), u(), u()) * 10f64.powf(-4.0 + 3.3 * u().abs());
                let mut tips = Vec::new();
                for l in 0..LANES {
                    let mut t = start + step * (l as f64 + 1.0);
                    match (case % 7, l) {
                        (5, 4) => t.x = 10.0 * reach,
                        (6, 6) => t.y = f64::NAN,
                        _ => {}
                    }
                    tips.push(t);
                }
                let target = |t: &nalgebra::Vector3<f64>| printwatt::math::Frame { rot, pos: *t };
                let Ok(starts) = solver.solve_all(&target(&start)) else {
                    continue;
                };
                let max_step = {
                    let mut m = [f64::INFINITY; MAX_DOF];
                    for v in m.iter_mut().take(6) {
                        *v = [0.01, 0.05, 0.3, f64::INFINITY][case % 4];
                    }
                    m
                };
                for s in starts.iter().take(4) {
                    let q_prev = s.q.to_vec();
                    let mut want: Option<(usize, Vec<u64>, _)> = None;
                    for level in levels() {
                        let Some(b) = solver.solve_near_batch(&rot, &tips, &q_prev, level) else {
                            continue;
                        };
                        let mut c = Continuing::new();
                        solver.continuing_lanes(
                            &b,
                            LANES,
                            &q_prev,
                            &max_step,
                            case % 2 == 0,
                            level,
                            &mut c,
                        );
                        let bits: Vec<u64> = (0..c.taken)
                            .flat_map(|l| c.q.iter().map(move |qj| qj[l].to_bits()))
                            .collect();
                        // Each taken lane is take_near's answer from the previous one.
                        let mut prev = q_prev.clone();
                        for (l, tip) in tips.iter().enumerate().take(c.taken) {
                            let q = solver.take_near(&b, l, &target(tip), &prev).unwrap();
                            for (j, v) in q.iter().enumerate() {
                                assert_eq!(
                                    v.to_bits(),
                                    c.q[j][l].to_bits(),
                                    "{name} {level:?} lane {l}"
                                );
                            }
                            prev = q.to_vec();
                        }
                        let got = (c.taken, bits, c.branch_after);
                        match &want {
                            None => want = Some(got),
                            Some(w) => {
                                assert_eq!(&got, w, "{name} limits {limits} case {case} {level:?}")
                            }
                        }
                    }
                    if let Some((t, _, _)) = want {
                        taken_total += t;
                        partial += usize::from(t > 0 && t < LANES);
                        slow += usize::from(limits > 0 && t > 0);
                    }
                }
            }
        }
    }
    assert!(
        taken_total > 1000 && partial > 30 && slow > 30,
        "{taken_total} taken, {partial} partial batches, {slow} through the fit"
    );
}

#[test]
fn next_branch_taken_without_branch_of_equals_branch_of_at_the_branch_boundaries() {
    // solve_branch_batch hands on the batch's own branch as next_branch where every lane is
    // ok and far (opw::NEXT_BRANCH_MARGIN_*) from the boundaries branch_of reads: the wrist
    // centre on the axis of joint 1 (ρ), the stretched or folded elbow (t3 at 0 or π) and q5
    // at 0 or π. Poses swept across those boundaries and their margins, every branch, every
    // level: next_branch equals Prepared::branch_of of each lane's answer, ok or not.
    use printwatt::kinematics::opw::{solve_branch_batch, Branch, Prepared};
    use std::f64::consts::PI;
    let mut u = uniform(43);
    let mut lanes = 0usize;
    for name in ["abb_irb6700_200_260", "abb_irb4600_40_255", "staubli_tx200"] {
        let model = common::robot(name);
        let Some(p) = model.opw else {
            continue;
        };
        let k = Prepared::new(&p);
        let psi3 = k.psi3();
        let kappa = (p.a2 * p.a2 + p.c3 * p.c3).sqrt();
        let reach = p.c2.abs() + kappa;
        // q2 (OPW) that puts c2 sin q2 + κ sin(q2 + q3 + ψ3) + a1 (±ρ) at `target`, by
        // bisection on a bracket (None without one).
        let q2_for = |q3: f64, target: f64| {
            let f = |q2: f64| p.c2 * q2.sin() + kappa * (q2 + q3 + psi3).sin() + p.a1 - target;
            let (mut a, mut b) = (-PI, 0.0);
            if f(a).signum() == f(b).signum() {
                (a, b) = (0.0, PI);
                if f(a).signum() == f(b).signum() {
                    return None;
                }
            }
            for _ in 0..200 {
                let m = 0.5 * (a + b);
                if f(m).signum() == f(a).signum() {
                    a = m;
                } else {
                    b = m;
                }
            }
            Some(0.5 * (a + b))
        };
        let eps = [0.0, 1e-12, 1e-9, 1e-7, 1e-6, 2e-6, 1e-5, 1e-3, 0.1];
        for (case, &e) in eps.iter().chain(eps.iter()).enumerate() {
            let sgn = if case < eps.len() { 1.0 } else { -1.0 };
            for anchor in 0..4 {
                // t3 near 0 or π; q5 near 0 or π; ρ near 0 or near its margin.
                let q3 = if anchor % 2 == 0 {
                    -psi3 + sgn * e
                } else {
                    PI - psi3 - sgn * e
                };
                let q5 = if anchor < 2 { sgn * e } else { PI - sgn * e };
                let rho =
                    [sgn * e * reach, 0.01 * reach * (1.0 + sgn * e.min(0.5))][(case + anchor) % 2];
                let q2 = q2_for(q3, rho).unwrap_or(0.3 * u());
                let o = [PI * u(), q2, q3, PI * u(), q5, PI * u()];
                let f = p.forward(&p.from_opw(&o));
                let dir = nalgebra::Vector3::new(u(), u(), u());
                let mut pos = [[0.0; LANES]; 3];
                for l in 0..LANES {
                    let d = [0.0, 1e-12, -1e-9, 1e-7, -1e-5, 1e-4, -1e-3, 1e-2][l];
                    let t = f.pos + dir * d;
                    (pos[0][l], pos[1][l], pos[2][l]) = (t.x, t.y, t.z);
                }
                for branch in Branch::ALL {
                    for level in levels() {
                        let b = solve_branch_batch(&p, &k, &f.rot, &pos, branch, level);
                        for l in 0..LANES {
                            assert_eq!(
                                b.next_branch[l],
                                k.branch_of(&p, &b.q(l)),
                                "{name} case {case} anchor {anchor} {branch:?} {level:?} lane {l}"
                            );
                            lanes += 1;
                        }
                    }
                }
            }
        }
    }
    assert!(lanes > 10_000, "{lanes} lanes");
}

#[test]
fn tracking_with_the_prunes_tips_gives_each_placement_its_own_path_tcp_and_sines_on_every_level() {
    // time_at_planned maps the plan's points to the base frame once, in its reach prune, and
    // hands them to tracking's first round. With one set of buffers reused across placements
    // (feasible ones, a far one the prune rejects, one where no configuration carries the
    // path), on every level: each placement's joint path, TCP points and sines are the
    // per-sample path's (scalar, fresh buffers) to the bit, and each failure is the same.
    // Paths: the default one (9777 samples, not a multiple of 8), a test path, and a short
    // one of two moves.
    use printwatt::kinematics::IkSolver;
    use printwatt::timing::{
        self, blend_path, Buffers, JointStageOptions, PathTiming, Plan, ProfileOptions,
    };
    use printwatt::toolpath::Placement;
    let _g = LEVEL_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let tcp_bits = |v: &[printwatt::math::V3]| {
        v.iter()
            .flat_map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
            .collect::<Vec<_>>()
    };
    let model = common::robot("abb_irb6700_200_260");
    let solver = IkSolver::new(&model).unwrap();
    let placements = [
        Placement::new(1.534, -0.121, 0.0, 90f64.to_radians()),
        Placement::new(1.7, 0.0, 0.0, 90f64.to_radians()),
        Placement::new(6.0, 0.0, 0.0, 0.0),
        Placement::new(0.3, 0.0, 1.5, 0.0),
        Placement::new(1.534, -0.121, 0.0, 90f64.to_radians()),
    ];
    let (popts, jopts) = (ProfileOptions::default(), JointStageOptions::default());
    let (mut ok, mut failed) = (0, 0);
    for (path, keep) in [
        ("default.gcode", usize::MAX),
        ("seed000_test_path.gcode", usize::MAX),
        ("seed000_test_path.gcode", 2),
    ] {
        let tp = common::path(path);
        let mut moves = timing::moves_from_toolpath(&tp);
        moves.truncate(keep);
        let pieces = blend_path(&moves);
        let plan = Plan::new(&pieces, &popts);
        let lines = |i: usize| moves[i].line;
        let job = PathTiming {
            pieces: &pieces,
            plan: &plan,
            moves_line: &lines,
            profile: &popts,
            joint: &jopts,
            source: "",
        };
        let run = |level: Level, buf: &mut Buffers, at: &Placement| {
            assert!(simd::set_level(level));
            let r = timing::time_at_planned(&solver, &job, at, buf);
            r.map(|t| {
                let out = (
                    bits(&t.traj.q),
                    bits(&t.traj.qd),
                    tcp_bits(&t.tcp),
                    bits(&buf.sincos),
                    t.rounds,
                );
                buf.recycle(t);
                out
            })
            .map_err(|e| format!("{e:?}"))
        };
        let want: Vec<_> = placements
            .iter()
            .map(|at| run(Level::Scalar, &mut Buffers::default(), at))
            .collect();
        for level in levels() {
            let mut buf = Buffers::default();
            for (at, w) in placements.iter().zip(&want) {
                let got = run(level, &mut buf, at);
                assert_eq!(&got, w, "{path} (moves {keep}) at {at:?} {level:?}");
                match got {
                    Ok(_) => ok += 1,
                    Err(_) => failed += 1,
                }
            }
        }
    }
    simd::set_level(simd::detected());
    assert!(ok >= 6 && failed >= 4, "{ok} timed, {failed} failed");
}

#[test]
fn saturated_coulomb_batches_and_the_one_division_motor_model_equal_the_per_sample_path_bit_for_bit(
) {
    // The lockstep pass skips the division q̇/ε of a joint whose lanes are all saturated
    // (|q̇| ≥ 20 ε (1 + 2⁻⁵⁰), fastmath::tanh_lanes_of_ratio) and takes the motor torque with
    // one division of a selected dividend and divisor (τ / (G η) driving, (τ η) / G
    // regenerating): on the default robot, with joints whose lanes are all saturated, all at
    // the saturation boundary ±20 ε (a few ulp either side), mixed, zero and −0, in both
    // quadrants of τ q̇, every field of every sample equals the per-sample path's bits on
    // every level, by eval_lanes_with_sincos and by the row-major eval_rows.
    let _g = LEVEL_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let model = common::robot("abb_irb6700_200_260");
    let n = model.dof();
    let em = EnergyModel::new(&model).unwrap();
    assert!(em.description().contains("coulomb"));
    let eps = printwatt::effects::COULOMB_VELOCITY_SCALE_RAD_S;
    let edge = 20.0 * eps;
    let step = |x: f64, k: i64| f64::from_bits((x.to_bits() as i64 + k) as u64);
    let mut u = uniform(31);
    let count = 12 * LANES;
    let mut quadrants = [0usize; 2];
    #[allow(clippy::type_complexity)]
    let st: Vec<(Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>)> = (0..count)
        .map(|k| {
            let (batch, lane) = (k / LANES, (k % LANES) as i64);
            let q: Vec<f64> = (0..n).map(|_| 3.0 * u()).collect();
            let mut sc = vec![0.0; 2 * n];
            for j in 0..n {
                (sc[j], sc[n + j]) = fastmath::sin_cos(q[j]);
            }
            let qd = (0..n)
                .map(|j| {
                    let sign = if u() < 0.0 { -1.0 } else { 1.0 };
                    match (batch + j) % 6 {
                        0 => sign * (0.05 + u().abs()),        // all saturated
                        1 => sign * step(edge, lane - 4),      // at the boundary
                        2 => sign * step(edge, 4 * lane - 16), // around it, wider
                        3 => 0.5 * u(),                        // mixed
                        4 => sign * step(edge * 1.01, -lane),  // just saturated
                        _ => [0.0, -0.0][(lane % 2) as usize],
                    }
                })
                .collect();
            let qdd = (0..n).map(|_| 10.0 * u()).collect();
            (q, sc, qd, qdd)
        })
        .collect();
    let mut data = em.data();
    for chunk in st.chunks(LANES) {
        let mut want = vec![SamplePower::default(); chunk.len()];
        for ((q, sc, qd, qdd), w) in chunk.iter().zip(want.iter_mut()) {
            energy::eval_sample_with_sincos(&em, &mut data, q, sc, qd, qdd, w).unwrap();
            for j in 0..n {
                quadrants[usize::from(w.tau[j] * qd[j] >= 0.0)] += 1;
            }
        }
        for level in levels() {
            let mut x = energy::LaneInputs::default();
            assert_energy_lanes_are_per_sample(&em, &mut data, chunk, &want, &mut x, level, "");
        }
    }
    assert!(
        quadrants[0] > 50 && quadrants[1] > 50,
        "both quadrants met: {quadrants:?}"
    );
}

#[test]
fn the_row_transposition_in_avx512_registers_puts_every_value_in_its_lane() {
    // A full batch of the six-joint arm is transposed from rows into lanes by masked row
    // loads and an 8 × 8 register transpose on AVX-512 (moves only): from slices exactly 8
    // rows long (nothing to read beyond them) starting at every offset of a buffer, with the
    // sines given and computed, every field of every lane equals the per-sample path's bits
    // on every level (the balancer's angle lanes included).
    let model = common::robot("abb_irb6700_200_260");
    let n = model.dof();
    let em = EnergyModel::new(&model).unwrap();
    assert!(em.description().contains("balancer"));
    let mut data = em.data();
    let mut u = uniform(57);
    let m = LANES + 5;
    let q: Vec<f64> = (0..m * n).map(|_| 3.0 * u()).collect();
    let qd: Vec<f64> = (0..m * n)
        .map(|i| (1.0 + (i % 7) as f64) * 0.1 * u())
        .collect();
    let qdd: Vec<f64> = (0..m * n).map(|_| 10.0 * u()).collect();
    let mut sc = vec![0.0; m * 2 * n];
    for k in 0..m {
        for j in 0..n {
            (sc[k * 2 * n + j], sc[k * 2 * n + n + j]) = fastmath::sin_cos(q[k * n + j]);
        }
    }
    let mut want = vec![SamplePower::default(); m];
    for (k, w) in want.iter_mut().enumerate() {
        let r = |a: &[f64]| a[k * n..(k + 1) * n].to_vec();
        energy::eval_sample(&em, &mut data, &r(&q), &r(&qd), &r(&qdd), w).unwrap();
    }
    for level in levels() {
        for given in [true, false] {
            for k0 in 0..=m - LANES {
                let rows = energy::Rows {
                    q: &q[k0 * n..(k0 + LANES) * n],
                    sincos: given.then(|| &sc[k0 * 2 * n..(k0 + LANES) * 2 * n]),
                    qd: &qd[k0 * n..(k0 + LANES) * n],
                    qdd: &qdd[k0 * n..(k0 + LANES) * n],
                };
                let mut x = energy::LaneInputs::default();
                let mut out = energy::PowerLanes::default();
                energy::eval_rows(&em, &mut data, LANES, &rows, &mut x, &mut out, level).unwrap();
                for l in 0..LANES {
                    assert_eq!(
                        format!("{:?}", out.sample(l)),
                        format!("{:?}", want[k0 + l]),
                        "{level:?}, sines given {given}, rows from {k0}, lane {l}"
                    );
                }
            }
        }
    }
}

/// Every field of two closed-form batches, bit for bit.
fn assert_same_batch(
    a: &printwatt::kinematics::opw::BranchBatch,
    b: &printwatt::kinematics::opw::BranchBatch,
    what: &str,
) {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<u64>>();
    assert_eq!(a.branch, b.branch, "{what}: branch");
    for j in 0..6 {
        assert_eq!(bits(&a.qj[j]), bits(&b.qj[j]), "{what}: qj[{j}]");
        assert_eq!(bits(&a.oj[j]), bits(&b.oj[j]), "{what}: oj[{j}]");
    }
    assert_eq!(bits(&a.s5), bits(&b.s5), "{what}: s5");
    assert_eq!(a.ok, b.ok, "{what}: ok");
    assert_eq!(a.next_branch, b.next_branch, "{what}: next_branch");
    assert_eq!(bits(&a.prev), bits(&b.prev), "{what}: prev");
}

#[test]
#[allow(clippy::needless_range_loop)] // lanes of parallel fixed arrays
fn two_closed_form_batches_in_one_lockstep_pass_equal_two_single_batches_bit_for_bit_on_every_level(
) {
    // opw::solve_branch_pair_into (16 lanes in one pass, for path tracking) against two
    // solve_branch_batch_into calls: reachable and unreachable tips, a NaN, the wrist centre on
    // the axis of joint 1, lanes without a tip (0), every branch, every level.
    use printwatt::kinematics::nozzle_target;
    use printwatt::kinematics::opw::{
        solve_branch_batch_into, solve_branch_pair_into, Branch, BranchBatch, Prepared, PAIR_LANES,
    };
    let mut u = uniform(71);
    let mut ok_lanes = 0;
    for name in ["abb_irb6700_200_260", "abb_irb4600_40_255", "staubli_tx200"] {
        let model = common::robot(name);
        let Some(p) = model.opw else {
            continue;
        };
        let k = Prepared::new(&p);
        let reach = printwatt::evaluate::feasibility::reach_m(&model);
        for spin in [0.0, 0.7, -2.0] {
            let rot = nozzle_target(&nalgebra::Vector3::zeros(), spin).rot;
            for case in 0..6 {
                let mut pos = [[0.0; PAIR_LANES]; 3];
                for l in 0..PAIR_LANES {
                    let t = match (case, l) {
                        (1, 3) => [f64::NAN, 0.2, 0.3],
                        (2, 5) => [5.0 * reach, 0.0, 0.0],
                        (3, 9) => [0.0, 0.0, 0.5 * reach],
                        (4, l) if l >= 13 => [0.0; 3],
                        _ => [
                            reach * (0.6 + 0.3 * u()),
                            reach * 0.5 * u(),
                            reach * 0.4 * u(),
                        ],
                    };
                    for i in 0..3 {
                        pos[i][l] = t[i];
                    }
                }
                for branch in Branch::ALL {
                    for level in levels() {
                        let mut pair = [BranchBatch::default(); 2];
                        let (a, b) = pair.split_at_mut(1);
                        solve_branch_pair_into(
                            &p,
                            &k,
                            &rot,
                            &pos,
                            branch,
                            level,
                            [&mut a[0], &mut b[0]],
                        );
                        for (g, got) in pair.iter().enumerate() {
                            let mut half = [[0.0; LANES]; 3];
                            for i in 0..3 {
                                half[i].copy_from_slice(&pos[i][g * LANES..(g + 1) * LANES]);
                            }
                            let mut want = BranchBatch::default();
                            solve_branch_batch_into(&p, &k, &rot, &half, branch, level, &mut want);
                            assert_same_batch(
                                got,
                                &want,
                                &format!("{name} spin {spin} case {case} {branch:?} {level:?} {g}"),
                            );
                            ok_lanes += want.ok.iter().filter(|o| **o).count();
                        }
                    }
                }
            }
        }
    }
    assert!(ok_lanes > 1000, "only {ok_lanes} ok lanes");
}

#[test]
#[allow(clippy::needless_range_loop)] // lanes of parallel fixed arrays
fn a_batch_solved_ahead_is_the_batch_solved_then_and_is_solved_afresh_for_another_branch() {
    // IkSolver::solve_near_batch_pair_lanes solves the next batch ahead with the current
    // batch's branch; IkSolver::presolved_or_solve must give exactly
    // solve_near_batch_lanes' batch for that q_prev: taken as it is when branch_of(q_prev)
    // (or the branch given) is the one it was solved for, solved afresh otherwise.
    use printwatt::kinematics::opw::BranchBatch;
    use printwatt::kinematics::{nozzle_target, IkSolver};
    let model = common::robot("abb_irb6700_200_260");
    let solver = IkSolver::new(&model).unwrap();
    let p = model.opw.unwrap();
    let k = printwatt::kinematics::opw::Prepared::new(&p);
    let rot = nozzle_target(&nalgebra::Vector3::zeros(), 0.4).rot;
    let target = solver.path_target(&rot);
    let mut u = uniform(5);
    let mut tips = [[[0.0; LANES]; 3]; 2];
    for g in 0..2 {
        for l in 0..LANES {
            let t = [1.6 + 0.3 * u(), 0.5 * u(), 0.4 + 0.3 * u()];
            for i in 0..3 {
                tips[g][i][l] = t[i];
            }
        }
    }
    // Joint vectors of two branches (the wrist flipped) to continue from.
    let q_front = [0.1, 0.2, 0.1, 0.3, 0.8, -0.2];
    let q_back = [0.1, 0.2, 0.1, 0.3, -0.8, -0.2];
    assert_ne!(k.branch_of(&p, &q_front), k.branch_of(&p, &q_back));
    for level in levels() {
        for counts in [[LANES, LANES], [LANES, 5]] {
            for (q0, q1, given) in [
                (q_front, q_front, None),
                (q_front, q_back, None),
                (q_back, q_front, Some(k.branch_of(&p, &q_front))),
                (q_front, q_front, Some(k.branch_of(&p, &q_back))),
            ] {
                let mut pair = [BranchBatch::default(); 2];
                let (a, b) = pair.split_at_mut(1);
                assert!(solver.solve_near_batch_pair_lanes(
                    &target,
                    [&tips[0], &tips[1]],
                    counts,
                    &q0,
                    None,
                    level,
                    [&mut a[0], &mut b[0]],
                ));
                let mut want0 = BranchBatch::default();
                assert!(solver.solve_near_batch_lanes(
                    &target, &tips[0], counts[0], &q0, None, level, &mut want0
                ));
                assert_same_batch(&pair[0], &want0, &format!("{level:?} first"));
                let mut ahead = pair[1];
                assert!(solver.presolved_or_solve(
                    &target, &tips[1], counts[1], &q1, given, level, &mut ahead
                ));
                let mut want1 = BranchBatch::default();
                assert!(solver.solve_near_batch_lanes(
                    &target, &tips[1], counts[1], &q1, given, level, &mut want1
                ));
                assert_same_batch(&ahead, &want1, &format!("{level:?} second {given:?}"));
            }
        }
    }
}

#[test]
fn sines_and_arctangents_of_any_lane_count_equal_the_scalar_functions_bit_for_bit() {
    // fastmath::{sin_cos, atan2, acos}_lanes_n (the wider calls of the paired closed form)
    // against the scalar functions, special values included.
    let mut u = uniform(9);
    let special = [
        0.0,
        -0.0,
        1e-300,
        -3e-9,
        1.0,
        -1.0,
        f64::NAN,
        1e301,
        f64::INFINITY,
        70.0,
    ];
    let mut xs = [0.0; 24];
    let mut ys = [0.0; 24];
    for round in 0..200 {
        for l in 0..24 {
            xs[l] = if round % 7 == 0 && l < special.len() {
                special[l]
            } else {
                4.0 * u()
            };
            ys[l] = if round % 5 == 0 && l < special.len() {
                special[(l + 3) % special.len()]
            } else {
                4.0 * u()
            };
        }
        let (s, c) = fastmath::sin_cos_lanes_n(&xs);
        let a = fastmath::atan2_lanes_n(&ys, &xs);
        let half: [f64; 16] = std::array::from_fn(|l| 0.5 * xs[l]);
        let ac = fastmath::acos_lanes_n(&half);
        for l in 0..24 {
            let (ws, wc) = fastmath::sin_cos(xs[l]);
            assert_eq!(s[l].to_bits(), ws.to_bits(), "sin {}", xs[l]);
            assert_eq!(c[l].to_bits(), wc.to_bits(), "cos {}", xs[l]);
            assert_eq!(
                a[l].to_bits(),
                fastmath::atan2(ys[l], xs[l]).to_bits(),
                "atan2 {} {}",
                ys[l],
                xs[l]
            );
        }
        for l in 0..16 {
            assert_eq!(
                ac[l].to_bits(),
                fastmath::acos(half[l]).to_bits(),
                "acos {}",
                half[l]
            );
        }
    }
}

#[test]
fn the_fused_summed_pass_adds_the_per_sample_paths_sums_bit_for_bit_with_every_effect_regeneration_and_without_a_drive(
) {
    // eval_rows_summed takes a full batch's powers straight into the sums (the
    // effects into local torques, then joint by joint the motor model, the sums and the
    // supply, nothing written into PowerLanes and read back); a short batch goes through
    // PowerLanes. With every torque effect (rigid_body per lane), on every regeneration policy
    // and without a drive, over full and short batches, the sums equal the per-sample path's
    // (EnergySums::add_sample with trapezoid weights) bit for bit on every level.
    use printwatt::robot::Regeneration;
    let (model, st) = every_effect_robot_and_states(5 * LANES + 3);
    let n = model.dof();
    let mut no_drive = model.clone();
    no_drive.drive = None;
    let m = st.len();
    let weight = |k: usize| printwatt::numerics::trapezoid_weight(k, m, 0.004);
    let (mut q, mut sc, mut qd, mut qdd) = (vec![], vec![], vec![], vec![]);
    for (a, b, c, d) in &st {
        q.extend_from_slice(a);
        sc.extend_from_slice(b);
        qd.extend_from_slice(c);
        qdd.extend_from_slice(d);
    }
    let models = [
        (&model, Regeneration::None),
        (&model, Regeneration::PerAxis),
        (&model, Regeneration::DcBus),
        (&model, Regeneration::Grid),
        (&no_drive, Regeneration::DcBus),
    ];
    for (robot, regeneration) in models {
        let em = EnergyModel::with_options(
            robot,
            energy::EnergyOptions {
                regeneration: Some(regeneration),
                ..Default::default()
            },
        )
        .unwrap();
        assert!(em.description().contains("rigid_body"));
        assert_eq!(em.has_drive(), robot.drive.is_some());
        let mut data = em.data();
        let mut want = energy::EnergySums::default();
        let mut sp = SamplePower::default();
        for (k, (a, b, c, d)) in st.iter().enumerate() {
            energy::eval_sample_with_sincos(&em, &mut data, a, b, c, d, &mut sp).unwrap();
            want.add_sample(k, &sp, weight(k), n);
        }
        let traj = [&q[..], &sc, &qd, &qdd];
        for level in levels() {
            for given in [true, false] {
                let sums = summed_pass(&em, &mut data, n, traj, given, &weight, level, None);
                assert_eq!(
                    format!("{sums:?}"),
                    format!("{want:?}"),
                    "{regeneration:?}, drive {}, {level:?}, sines given {given}",
                    em.has_drive()
                );
            }
        }
    }
}
