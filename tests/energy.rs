//! Energy model: motor-model identity, regeneration policies, holding torque, standby,
//! an analytic viscous case, the closed breakdown, and the effects' regressors.

#![allow(clippy::needless_range_loop)] // index-parallel arrays read more clearly in tests

mod common;
use common::{close, robot, Sines};
use printwatt::trajectory::JointTrajectory;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Random smooth motion (seeded): amplitudes amp·[0.2, 1) rad, ω in [0.5, 3) rad/s.
fn sines(n: usize, seed: u64, t_end: f64, steps: usize, amp: f64) -> JointTrajectory {
    Sines::random(n, seed, 0.2..1.0, 0.5..3.0)
        .scaled(amp)
        .trajectory(t_end, steps)
}

use printwatt::effects::{Armature, Coulomb, Effect, EffectSet, Viscous};
use printwatt::energy::{eval_sample, evaluate, EnergyModel, EnergyOptions, SamplePower};
use printwatt::robot::Regeneration;

#[test]
fn motor_model_identity_with_unit_gear_efficiency() {
    let mut r = robot("abb_irb6700_200_260");
    if let Some(d) = r.drive.as_mut() {
        d.joints.iter_mut().for_each(|j| j.gear_efficiency = 1.0);
    }
    let drive = r.drive.clone().expect("drive");
    let m = EnergyModel::new(&r).unwrap();
    let mut data = m.data();
    let tr = sines(6, 1, 2.0, 200, 0.5);
    let mut s = SamplePower::default();
    for k in 0..tr.len() {
        eval_sample(&m, &mut data, tr.q(k), tr.qd(k), tr.qdd(k), &mut s).unwrap();
        for j in 0..6 {
            let jd = &drive.joints[j];
            let i = s.tau[j] / (jd.gear_ratio * jd.torque_constant);
            let want = s.tau[j] * tr.qd(k)[j] + jd.winding_resistance * i * i;
            assert!(
                close(s.p_el[j], want, 1e-12),
                "P_el {} vs {want}",
                s.p_el[j]
            );
            assert!(s.p_gear[j].abs() < 1e-9 * s.p_mech[j].abs().max(1.0));
        }
    }
}

#[test]
fn breakdown_closes_and_losses_are_non_negative() {
    for name in ["abb_irb6700_200_260", "staubli_tx200", "ur10e", "puma560"] {
        let r = robot(name);
        let mut opts = EnergyOptions::default();
        for policy in [Regeneration::None, Regeneration::DcBus, Regeneration::Grid] {
            opts.regeneration = Some(policy);
            let m = EnergyModel::with_options(&r, opts).unwrap();
            let rep = evaluate(&m, &sines(6, 2, 3.0, 600, 0.6)).unwrap();
            let t = &rep.total;
            let sum = common::supply_parts(t);
            assert!(
                close(t.supply_j, sum, 1e-9),
                "{name}: {} vs {sum}",
                t.supply_j
            );
            assert!(close(
                t.electrical_j,
                t.rigid_body_j + t.balancer_j + t.friction_j + t.gear_j + t.copper_j,
                1e-9
            ));
            assert!(t.friction_j >= 0.0 && t.gear_j >= -1e-9 && t.copper_j > 0.0);
            assert!(t.regeneration_lost_j >= -1e-9);
            assert!(rep.has_drive && rep.model.contains("motor model"));
            let json = serde_json::to_string(&rep).unwrap();
            assert!(json.contains("\"supply_j\""));
        }
    }
}

#[test]
fn regeneration_policies_are_ordered() {
    let r = robot("abb_irb4600_40_255");
    let tr = sines(6, 3, 4.0, 800, 0.8);
    let e = |p| {
        let m = EnergyModel::with_options(
            &r,
            EnergyOptions {
                regeneration: Some(p),
                ..Default::default()
            },
        )
        .unwrap();
        evaluate(&m, &tr).unwrap().total.supply_j
    };
    let (none, per_axis, dc, grid) = (
        e(Regeneration::None),
        e(Regeneration::PerAxis),
        e(Regeneration::DcBus),
        e(Regeneration::Grid),
    );
    println!("none {none:.3} per_axis {per_axis:.3} dc_bus {dc:.3} grid {grid:.3} J");
    assert_eq!(none, per_axis);
    assert!(grid <= dc && dc <= per_axis);
    assert!(grid < per_axis, "trajectory should regenerate somewhere");
}

#[test]
fn holding_against_gravity_costs_copper_power_only() {
    let r = robot("abb_irb6700_200_260");
    let m = EnergyModel::new(&r).unwrap();
    let mut d = m.data();
    let mut s = SamplePower::default();
    let q = [0.3, 0.5, -0.2, 0.1, 0.4, 0.0];
    let supply = eval_sample(&m, &mut d, &q, &[0.0; 6], &[0.0; 6], &mut s).unwrap();
    assert!(s.tau[1].abs() > 100.0, "joint 2 carries the arm");
    for j in 0..6 {
        assert_eq!(s.p_mech[j], 0.0);
        assert!(close(s.p_el[j], s.p_copper[j], 1e-12));
    }
    assert!(s.p_copper[1] > 0.0);
    assert!(close(
        supply,
        s.p_copper.iter().sum::<f64>() + m.standby_power(),
        1e-12
    ));
}

#[test]
fn standby_power_times_duration_is_added() {
    let mut r = robot("staubli_tx200");
    let tr = sines(6, 4, 2.5, 250, 0.4);
    if let Some(d) = r.drive.as_mut() {
        d.standby_power = 0.0;
    }
    let e0 = evaluate(&EnergyModel::new(&r).unwrap(), &tr).unwrap();
    if let Some(d) = r.drive.as_mut() {
        d.standby_power = 350.0;
    }
    let e1 = evaluate(&EnergyModel::new(&r).unwrap(), &tr).unwrap();
    assert!(close(
        e1.total.supply_j - e0.total.supply_j,
        350.0 * 2.5,
        1e-12
    ));
    assert!(close(e1.total.standby_j, 875.0, 1e-12));
}

#[test]
fn constant_velocity_with_viscous_friction_only_is_analytic() {
    // Joint 1 (vertical axis) turning at constant speed, the others still: M does not depend
    // on q1 and gravity does no work on it, so τ1 = f_v q̇ and E = f_v q̇² T.
    let mut r = robot("abb_irb6700_200_260");
    let fv = r.drive.as_ref().expect("drive").joints[0].viscous;
    assert!(fv > 0.0);
    if let Some(d) = r.drive.as_mut() {
        d.joints.iter_mut().for_each(|j| j.coulomb = 0.0);
    }
    let (w, t_end) = (0.4, 3.0);
    let mut tr = JointTrajectory::new(6);
    for k in 0..=300 {
        let t = t_end * k as f64 / 300.0;
        tr.push(
            t,
            &[w * t, 0.2, -0.3, 0.0, 0.5, 0.0],
            &[w, 0.0, 0.0, 0.0, 0.0, 0.0],
            &[0.0; 6],
        );
    }
    let rep = evaluate(&EnergyModel::new(&r).unwrap(), &tr).unwrap();
    let want = fv * w * w * t_end;
    assert!(
        close(rep.joints[0].mechanical_j, want, 1e-9),
        "{} vs {want}",
        rep.joints[0].mechanical_j
    );
    assert!(close(rep.joints[0].friction_j, want, 1e-12));
    assert!(rep.joints[0].rigid_body_j.abs() < 1e-9 * want);
    assert!(close(rep.total.mechanical_j, want, 1e-9));
}

#[test]
fn without_drive_the_report_is_rigid_body_only() {
    let mut r = robot("ur10e");
    r.drive = None;
    let m = EnergyModel::new(&r).unwrap();
    let tr = sines(6, 5, 2.0, 400, 0.5);
    let rep = evaluate(&m, &tr).unwrap();
    assert!(!rep.has_drive && rep.model.contains("rigid body only"));
    let t = &rep.total;
    assert_eq!(t.copper_j, 0.0);
    assert_eq!(t.friction_j, 0.0);
    assert!(close(t.electrical_j, t.mechanical_j, 1e-12));
    let mut csv = Vec::new();
    rep.series.write_csv(None, &mut csv).unwrap();
    let text = String::from_utf8(csv).unwrap();
    assert_eq!(text.lines().count(), tr.len() + 1);
    assert!(text.starts_with("t[s],tau1[Nm]"));
}

#[test]
fn wrong_trajectory_sizes_are_errors() {
    let r = robot("ur10e");
    let m = EnergyModel::new(&r).unwrap();
    let mut tr = sines(6, 6, 1.0, 10, 0.1);
    tr.qdd.clear();
    assert!(evaluate(&m, &tr).is_err());
    assert!(evaluate(&m, &JointTrajectory::new(5)).is_err());
}

#[test]
fn regressor_times_parameters_equals_contribution() {
    let r = robot("puma560");
    let d = r.drive.as_ref().expect("drive");
    // `coulomb` carries its transition width ε as a parameter: not linear, no regressor.
    let c = Coulomb::from_drive(d, 0.01);
    assert!(!c.regressor(&[0.0; 6], &[0.1; 6], &[0.0; 6], &mut [0.0; 6 * 13]));
    let effects: Vec<Box<dyn Effect>> = vec![
        Box::new(Viscous::from_drive(d)),
        Box::new(Armature::from_drive(d)),
    ];
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    for e in &effects {
        let p = e.params();
        let theta = e.values();
        assert_eq!(p.len(), theta.len());
        assert!(p.iter().all(|s| !s.unit.is_empty() && s.lower <= s.upper));
        for _ in 0..20 {
            let x: Vec<f64> = (0..18).map(|_| rng.gen_range(-0.05..0.05)).collect();
            let (q, qd, qdd) = (&x[0..6], &x[6..12], &x[12..18]);
            let mut tau = [0.0; 6];
            e.add_torque(q, qd, qdd, &mut tau);
            let mut y = vec![0.0; 6 * theta.len()];
            assert!(e.regressor(q, qd, qdd, &mut y), "{} is linear", e.name());
            for j in 0..6 {
                let yt: f64 = (0..theta.len())
                    .map(|c| y[j * theta.len() + c] * theta[c])
                    .sum();
                assert!(
                    (yt - tau[j]).abs() <= 1e-12 * tau[j].abs().max(1.0),
                    "{}",
                    e.name()
                );
            }
        }
    }
    let mut v = Viscous::from_drive(d);
    assert!(v.set_values(&[-1.0; 6]).is_err());
    assert!(v.set_values(&[1.0; 5]).is_err());
    let mut set = EffectSet::friction_of(d);
    assert!(set.set_enabled("coulomb", false));
    let mut tau = [0.0; 6];
    set.add_torque(&[0.0; 6], &[1.0; 6], &[0.0; 6], &mut tau);
    for j in 0..6 {
        assert!((tau[j] - d.joints[j].viscous).abs() < 1e-12);
    }
}

#[test]
fn a_placements_energies_summed_in_lane_interleaved_partial_sums_stay_within_rounding_of_a_compensated_sum(
) {
    // The sweep sums sample k into partial sum k mod LANES (energy::EnergySums) on every SIMD
    // level; against an exactly rounded (Neumaier-compensated) sum of the same per-sample
    // powers, each total stays within the recursive summation bound
    // (m/LANES + LANES + n) ε Σ|w p|, and the lockstep and per-sample paths give the same bits.
    use printwatt::evaluate::feasibility::FeasibilityOptions;
    use printwatt::evaluate::{Evaluator, Objective};
    use printwatt::frame::Placement;
    use printwatt::simd::{self, Level, LANES};
    let model = robot("abb_irb6700_200_260");
    let job = common::default_job(&model, &common::path("seed000_test_path.gcode"));
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let mut sc = ev.scratch().unwrap();
    let at = Placement::new(1.8, 0.0, 0.2, 90f64.to_radians());
    let timed = ev.timed(&mut sc, &at).unwrap();
    let f = ev
        .energy_of(&mut sc, &timed, Default::default())
        .expect("feasible");
    let n = model.dof();
    let (m, dt) = (timed.traj.len(), timed.motion.dt);
    // Neumaier sums of w p and of |w p|.
    #[derive(Default)]
    struct Ks {
        s: f64,
        c: f64,
        abs: f64,
    }
    impl Ks {
        fn add(&mut self, x: f64) {
            let t = self.s + x;
            self.c += if self.s.abs() >= x.abs() {
                (self.s - t) + x
            } else {
                (x - t) + self.s
            };
            self.s = t;
            self.abs += x.abs();
        }
        fn value(&self) -> f64 {
            self.s + self.c
        }
    }
    let (mut supply, mut friction, mut mech) = (Ks::default(), Ks::default(), Ks::default());
    let mut data = job.energy.data();
    let mut sp = SamplePower::default();
    for k in 0..m {
        eval_sample(
            &job.energy,
            &mut data,
            timed.traj.q(k),
            timed.traj.qd(k),
            timed.traj.qdd(k),
            &mut sp,
        )
        .unwrap();
        let w = printwatt::numerics::trapezoid_weight(k, m, dt);
        supply.add(w * sp.p_supply);
        for j in 0..n {
            friction.add(w * sp.p_friction[j]);
            mech.add(w * sp.p_mech[j]);
        }
    }
    let bound = |k: &Ks| (m / LANES + LANES + n) as f64 * f64::EPSILON * k.abs;
    for (what, got, k) in [
        ("supply", f.supply_j, &supply),
        ("friction", f.losses.friction_j, &friction),
        ("mechanical", f.mechanical_j, &mech),
    ] {
        let err = (got - k.value()).abs();
        println!(
            "{what}: {got} J, off the compensated sum by {err:.3e} J (bound {:.3e})",
            bound(k)
        );
        assert!(
            err <= bound(k),
            "{what}: {got} vs {} (bound {})",
            k.value(),
            bound(k)
        );
    }
    // The same bits from the per-sample path (scalar) and every lockstep level.
    let want = f.supply_j.to_bits();
    for level in [Level::Scalar, Level::Sse2, Level::Avx2, Level::Avx512] {
        if simd::set_level(level) {
            let g = ev.energy_of(&mut sc, &timed, Default::default()).unwrap();
            assert_eq!(g.supply_j.to_bits(), want, "{level:?}");
            assert_eq!(g, f, "{level:?}");
        }
    }
    simd::set_level(simd::detected());
}
