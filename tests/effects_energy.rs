//! The drive file's `[effects]` table in the energy model: the energy model's torques equal
//! identification's predictions on the worked example's identified drive file; the balancer
//! adds exactly its own torque; the breakdown still closes; unknown keys are errors naming
//! file and key; `printwatt energy` on the identified drive file differs from the nominal robot.

#![allow(clippy::needless_range_loop)]

mod common;
use common::{close, root, Sines};
use printwatt::effects::{Balancer, Effect, EffectSet};
use printwatt::energy::{eval_sample, evaluate, EnergyModel, SamplePower};
use printwatt::identify::log::SignalKind;
use printwatt::identify::Model;
use printwatt::robot::{load, RobotModel};
use printwatt::trajectory::JointTrajectory;
use std::path::{Path, PathBuf};

/// Deterministic smooth motion: per joint 0.4 sin(0.7t+φ) + 0.15 sin(2.1t+φ') + 0.05 sin(4.3t+φ'').
fn sines(n: usize, t_end: f64, steps: usize) -> JointTrajectory {
    let terms = (0..n)
        .map(|j| {
            [(0.4, 0.7), (0.15, 2.1), (0.05, 4.3)]
                .iter()
                .enumerate()
                .map(|(i, &(a, w))| (a, w, 0.3 * (j + 1) as f64 + 1.1 * i as f64))
                .collect()
        })
        .collect();
    Sines { terms }.trajectory(t_end, steps)
}
use std::process::Command;

fn identified_file() -> PathBuf {
    root().join("results/identify_example/identify/robot.calibrated.toml")
}

/// Switch effect `name` on or off in the robot's `[effects]` table (the others keep their
/// switches).
fn set_enabled(r: &mut RobotModel, name: &str, on: bool) {
    let mut list: Vec<String> = EffectSet::of_robot(r)
        .unwrap()
        .enabled_names()
        .iter()
        .map(|s| s.to_string())
        .collect();
    list.retain(|n| n != name);
    if on {
        list.push(name.to_string());
    }
    r.effects.table.enabled = Some(list);
}

/// Set effect `name`'s values in the robot's `[effects.values]`.
fn set_values(r: &mut RobotModel, name: &str, v: Vec<f64>) {
    r.effects
        .table
        .values
        .get_or_insert_with(Default::default)
        .insert(name.to_string(), v);
}

fn set(r: &RobotModel) -> EffectSet {
    EffectSet::of_robot(r).unwrap()
}

fn balancer(r: &RobotModel) -> Balancer {
    set(r).typed::<Balancer>("balancer").unwrap().clone()
}

fn identified() -> RobotModel {
    load(&identified_file()).unwrap()
}

#[test]
fn identified_drive_file_carries_its_effects() {
    let r = identified();
    let e = set(&r);
    assert!(e.is_enabled("balancer") && !e.is_enabled("stribeck"));
    // The values in force are the ones the calibration record lists, with standard errors.
    let cal = r.effects.calibration.as_ref().expect("a calibrated robot");
    assert_eq!(cal.rounds.len(), 2, "round 1 carried over, round 2 added");
    let param = |name: &str| {
        cal.params
            .iter()
            .find(|p| p.effect == "balancer" && p.name == name)
            .unwrap()
    };
    let b = balancer(&r);
    assert!(close(b.preload, param("F0").value, 1e-15));
    assert!(close(b.stiffness, param("k").value, 1e-15));
    // Round 2 re-fits round 1's balancer jointly with Coulomb, so F0 carries round 2.
    assert!(param("F0").std_error.is_some_and(|s| s > 0.0) && param("F0").round == 2);
    // The nominal robot declares its sized balancer; the calibrated one moved it.
    let nominal = load(&root().join("robots/abb_irb4600_40_255")).unwrap();
    assert!(balancer(&nominal).declared);
    assert!(set(&nominal).is_enabled("balancer"));
    assert!(set(&nominal).is_enabled("viscous"));
    assert!(nominal.effects.calibration.is_none());
    assert!((balancer(&nominal).preload - b.preload).abs() > 1000.0);
}

/// (a) the energy model's joint torques are identification's predicted torques, and its
/// supply power is identification's predicted `p_total`.
fn energy_matches_identify(r: &RobotModel) {
    let n = r.dof();
    let tr = sines(n, 6.0, 1200);
    let em = EnergyModel::new(r).unwrap();
    let rep = evaluate(&em, &tr).unwrap();
    let im = Model::new(r).unwrap();
    let mut tau = vec![0.0; n];
    let mut p = [0.0];
    for k in 0..tr.len() {
        im.torque(tr.q(k), tr.qd(k), tr.qdd(k), &mut tau).unwrap();
        for j in 0..n {
            let e = rep.series.tau[k * n + j];
            assert!(
                close(e, tau[j], 1e-9),
                "sample {k} joint {}: energy {e} vs identify {}",
                j + 1,
                tau[j]
            );
        }
        im.signal_from_torque(SignalKind::TotalPower, &tau, tr.qd(k), &mut p);
        assert!(
            close(rep.series.p_supply[k], p[0], 1e-9),
            "sample {k}: supply {} vs identify {}",
            rep.series.p_supply[k],
            p[0]
        );
    }
}

#[test]
fn energy_torques_equal_identify_predictions_on_the_identified_drive_file() {
    energy_matches_identify(&identified());
}

#[test]
fn energy_torques_equal_identify_predictions_with_every_effect() {
    let mut r = identified();
    for name in ["stribeck", "payload", "offset", "regeneration"] {
        set_enabled(&mut r, name, true);
    }
    set_enabled(&mut r, "armature", false);
    set_values(
        &mut r,
        "stribeck",
        vec![20.0, 25.0, 10.0, 5.0, 4.0, 3.0, 0.08],
    );
    set_values(&mut r, "payload", vec![4.5, 0.0, 0.0, 0.0]);
    set_values(&mut r, "regeneration", vec![0.4]);
    set_values(&mut r, "offset", vec![3.0, -12.0, 5.0, 0.5, -0.7, 0.2]);
    // Direction-dependent Coulomb friction with a wider transition.
    let mut fc: Vec<f64> = vec![30.0, 45.0, 20.0, 6.0, 5.0, 3.0];
    fc.extend([22.0, 60.0, 14.0, 8.0, 3.0, 4.0, 0.02]);
    set_values(&mut r, "coulomb", fc);
    energy_matches_identify(&r);
}

/// (b) switching the balancer on changes joint 2's torque by exactly the balancer's
/// `add_torque`, and nothing else.
#[test]
fn balancer_adds_exactly_its_own_torque_on_joint_2() {
    let on = identified();
    let mut off = on.clone();
    set_enabled(&mut off, "balancer", false);
    let (m_on, m_off) = (
        EnergyModel::new(&on).unwrap(),
        EnergyModel::new(&off).unwrap(),
    );
    let b = balancer(&on);
    let tr = sines(6, 4.0, 400);
    let (mut d_on, mut d_off) = (m_on.data(), m_off.data());
    let (mut s_on, mut s_off) = (SamplePower::default(), SamplePower::default());
    let mut moved = 0.0f64;
    for k in 0..tr.len() {
        let (q, qd, qdd) = (tr.q(k), tr.qd(k), tr.qdd(k));
        eval_sample(&m_on, &mut d_on, q, qd, qdd, &mut s_on).unwrap();
        eval_sample(&m_off, &mut d_off, q, qd, qdd, &mut s_off).unwrap();
        let mut want = [0.0; 6];
        b.add_torque(q, qd, qdd, &mut want);
        for j in 0..6 {
            assert_eq!(s_on.tau_balancer[j], want[j], "sample {k} joint {}", j + 1);
            assert_eq!(s_on.tau_rb[j], s_off.tau_rb[j]);
            assert_eq!(s_on.tau_friction[j], s_off.tau_friction[j]);
            assert_eq!(s_off.tau_balancer[j], 0.0);
            let d = s_on.tau[j] - s_off.tau[j];
            assert!(
                (d - want[j]).abs() <= 1e-12 * s_on.tau[j].abs().max(1.0),
                "sample {k} joint {}: {d} vs {}",
                j + 1,
                want[j]
            );
        }
        moved = moved.max(want[1].abs());
    }
    assert!(moved > 100.0, "the balancer should matter: {moved} N·m");
}

/// The identified robot with Stribeck friction, joint offsets and regeneration recovering
/// `rho` of the braking power switched on.
fn with_stribeck_offset_regeneration(rho: f64) -> RobotModel {
    let mut r = identified();
    set_enabled(&mut r, "stribeck", true);
    set_values(
        &mut r,
        "stribeck",
        vec![10.0, 10.0, 10.0, 10.0, 10.0, 10.0, 0.05],
    );
    set_enabled(&mut r, "offset", true);
    set_values(&mut r, "offset", vec![2.0, -8.0, 1.0, 0.0, 0.3, -0.2]);
    set_enabled(&mut r, "regeneration", true);
    set_values(&mut r, "regeneration", vec![rho]);
    r
}

/// (c) the breakdown closes with the balancer, Stribeck friction and partial regeneration.
#[test]
fn breakdown_closes_with_the_identified_effects() {
    for rho in [0.0, 0.5] {
        let r = with_stribeck_offset_regeneration(rho);
        let rep = evaluate(&EnergyModel::new(&r).unwrap(), &sines(6, 5.0, 1000)).unwrap();
        let t = &rep.total;
        let parts = common::supply_parts(t);
        assert!(close(t.supply_j, parts, 1e-9), "{} vs {parts}", t.supply_j);
        assert!(close(
            t.mechanical_j,
            t.rigid_body_j + t.balancer_j + t.friction_j,
            1e-9
        ));
        for je in &rep.joints {
            assert!(close(
                je.mechanical_j,
                je.rigid_body_j + je.balancer_j + je.friction_j,
                1e-9
            ));
        }
        assert!(t.balancer_j != 0.0 && rep.joints[1].balancer_j == t.balancer_j);
        assert!(t.regeneration_lost_j >= -1e-9);
    }
}

/// (d) unknown keys and bad values in `[effects]` are errors naming the file and the key.
#[test]
fn bad_effects_tables_name_file_and_key() {
    let src = std::fs::read_to_string(identified_file())
        .unwrap()
        .replace("urdf = \"../robot/robot.urdf\"", "urdf = \"robot.urdf\"");
    let dir = std::env::temp_dir().join(format!("printwatt_fx_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(
        root().join("results/identify_example/robot/robot.urdf"),
        dir.join("robot.urdf"),
    )
    .unwrap();
    // The identified balancer values [F0, k] as written in `[effects.values]`.
    let pre = src
        .lines()
        .find(|l| l.starts_with("balancer = ["))
        .unwrap()
        .to_string();
    let cases = [
        (
            "[effects]\n",
            "[effects]\nbalancer_spring_n = 3.0\n",
            "balancer_spring_n",
        ),
        (
            "enabled = [\"viscous\"",
            "enabled = [\"viscus\"",
            "effects.enabled",
        ),
        (pre.as_str(), "balancer = [1.0]", "balancer"),
        (
            "regeneration = [0.0]",
            "regeneration = [1.5]",
            "regeneration",
        ),
        (
            "balancer_lever_m = 0.15",
            "balancer_lever_m = -0.15",
            "balancer_lever_m",
        ),
        ("balancer_joint = 2", "balancer_joint = 9", "balancer_joint"),
    ];
    for (i, (from, to, key)) in cases.iter().enumerate() {
        assert!(src.contains(from), "{from}");
        let path = dir.join(format!("bad{i}.toml"));
        std::fs::write(&path, src.replacen(from, to, 1)).unwrap();
        let e = load(&path)
            .and_then(|r| EffectSet::of_robot(&r).map(|_| ()))
            .expect_err(to)
            .to_string();
        assert!(
            e.contains(&format!("bad{i}.toml")) && e.contains(key),
            "case {i}: {e}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn energy_cli(robot: &Path, traj: &Path, out: &Path) -> serde_json::Value {
    let o = common::ok(
        Command::new(env!("CARGO_BIN_EXE_printwatt"))
            .args(["energy", "--robot"])
            .arg(robot)
            .arg("--trajectory")
            .arg(traj)
            .arg("--json")
            .arg("--out")
            .arg(out),
    );
    serde_json::from_slice(&o.stdout).unwrap()
}

/// (e) `printwatt energy` reads the identified drive file and its balancer changes the result.
#[test]
fn energy_cli_on_the_identified_drive_file_differs_from_the_nominal_robot() {
    let dir = std::env::temp_dir().join(format!("printwatt_fx_cli_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let tr = sines(6, 4.0, 400);
    let mut csv = String::from("t,q1,q2,q3,q4,q5,q6\n");
    for k in 0..tr.len() {
        csv.push_str(&format!("{}", tr.t[k]));
        for q in tr.q(k) {
            csv.push_str(&format!(",{q}"));
        }
        csv.push('\n');
    }
    let traj = dir.join("traj.csv");
    std::fs::write(&traj, csv).unwrap();
    let a = energy_cli(&identified_file(), &traj, &dir.join("a.csv"));
    let b = energy_cli(
        &root().join("results/identify_example/robot"),
        &traj,
        &dir.join("b.csv"),
    );
    let (ta, tb) = (&a["energy"]["total"], &b["energy"]["total"]);
    let (ea, eb) = (
        ta["supply_j"].as_f64().unwrap(),
        tb["supply_j"].as_f64().unwrap(),
    );
    assert!(
        ea > 0.0 && eb > 0.0 && (ea - eb).abs() > 1e-3 * eb,
        "{ea} vs {eb}"
    );
    // Both carry a balancer (the nominal one sized, the calibrated one identified).
    assert!(ta["balancer_j"].as_f64().unwrap() != tb["balancer_j"].as_f64().unwrap());
    assert!(a["energy"]["model"]
        .as_str()
        .unwrap()
        .contains("calibrated robot"));
    assert!(a["energy"]["model"].as_str().unwrap().contains("balancer"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The shipped default robot (the one `printwatt optimise` uses without --robot).
fn default_robot() -> RobotModel {
    load(&root().join("robots/abb_irb6700_200_260")).unwrap()
}

/// The rigid body's base parameters (a regressor at 100 states, a QR, two SVDs) are found on
/// first use, not when the effect is built: building the effect set, and everything the
/// energy model asks of a null effect (name, stage, class, is it null, a copy), leaves them
/// unfound; an energy model of the robot evaluates as before.
#[test]
fn an_energy_model_does_not_find_the_rigid_body_base() {
    use printwatt::effects::{Effect, RigidBody};
    let r = default_robot();
    let s = set(&r);
    let rb = s.typed::<RigidBody>("rigid_body").unwrap();
    assert!(!rb.base_found(), "building the effect set found the base");
    for (e, _on) in s.iter() {
        let _ = (e.name(), e.stage(), e.energy_class(), e.is_null());
        drop(e.clone_box());
    }
    assert!(rb.is_null());
    assert!(
        !rb.base_found(),
        "the energy model's questions found the base"
    );
    let copy = rb.clone();
    assert!(!copy.base_found());
    // The energy model builds its own set; it still evaluates.
    let m = EnergyModel::new(&r).unwrap();
    let tr = sines(r.dof(), 1.0, 50);
    assert!(evaluate(&m, &tr).unwrap().total.supply_j.is_finite());
}

/// The base found on first use equals the one found at once (as the effect did before it was
/// lazy): parameter names, combinations, nominal values, zero values and the regressor bit
/// for bit, whichever copy asks first; copies share one base; set values read back.
#[test]
fn the_lazy_rigid_body_base_equals_the_eager_one() {
    use printwatt::effects::{Effect, RigidBody};
    for name in ["abb_irb6700_200_260", "ur10e", "puma560"] {
        let r = load(&root().join("robots").join(name)).unwrap();
        // Eager: asked for right after it is built.
        let eager = RigidBody::new(&r).unwrap();
        let p_eager = eager.params();
        assert!(eager.base_found());
        // Lazy: copied first, the copy asks later, after other work.
        let lazy = RigidBody::new(&r).unwrap();
        let copy = lazy.clone();
        assert!(!lazy.base_found() && !copy.base_found());
        let _ = EnergyModel::new(&r).unwrap();
        let v = copy.values();
        assert!(lazy.base_found(), "{name}: copies share one base");
        assert_eq!(
            v,
            vec![0.0; p_eager.len()],
            "{name}: zero errors, one per parameter"
        );
        let names = |ps: &[printwatt::effects::ParamSpec]| {
            ps.iter()
                .map(|p| (p.name.clone(), p.unit, p.lower, p.upper))
                .collect::<Vec<_>>()
        };
        assert_eq!(names(&lazy.params()), names(&p_eager), "{name}");
        assert_eq!(lazy.combination(), eager.combination(), "{name}");
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(
            bits(lazy.nominal_base_values()),
            bits(eager.nominal_base_values()),
            "{name}"
        );
        let n = r.dof();
        let p = p_eager.len();
        let (q, qd, qdd) = (vec![0.3; n], vec![0.5; n], vec![-1.0; n]);
        let (mut ya, mut yb) = (vec![0.0; n * p], vec![0.0; n * p]);
        assert!(eager.regressor(&q, &qd, &qdd, &mut ya));
        assert!(lazy.regressor(&q, &qd, &qdd, &mut yb));
        assert_eq!(bits(&ya), bits(&yb), "{name}");
        // Values set on a lazy effect read back and give the eager effect's torque.
        let vals: Vec<f64> = (0..p).map(|k| 0.05 * ((k as f64) * 0.7).cos()).collect();
        let (mut a, mut b) = (RigidBody::new(&r).unwrap(), eager.clone());
        a.set_values(&vals).unwrap();
        b.set_values(&vals).unwrap();
        assert_eq!(a.values(), vals);
        assert!(!a.is_null());
        let (mut ta, mut tb) = (vec![0.0; n], vec![0.0; n]);
        a.add_torque(&q, &qd, &qdd, &mut ta);
        b.add_torque(&q, &qd, &qdd, &mut tb);
        assert_eq!(bits(&ta), bits(&tb), "{name}");
    }
}

/// A supply effect defined here, outside the library: it names the term it supplies.
#[derive(Clone, Debug)]
struct SiteSupply {
    term: printwatt::effects::SupplyTerm,
    value: f64,
}

impl printwatt::effects::Effect for SiteSupply {
    fn name(&self) -> &'static str {
        "site_supply"
    }
    fn params(&self) -> Vec<printwatt::effects::ParamSpec> {
        vec![printwatt::effects::ParamSpec {
            name: "value".into(),
            unit: "1",
            lower: 0.0,
            upper: f64::INFINITY,
        }]
    }
    fn values(&self) -> Vec<f64> {
        vec![self.value]
    }
    fn set_values(&mut self, v: &[f64]) -> printwatt::error::Result<()> {
        self.value = v[0];
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn printwatt::effects::Effect> {
        Box::new(self.clone())
    }
    fn stage(&self) -> printwatt::effects::Stage {
        printwatt::effects::Stage::Supply(self.term)
    }
}

#[test]
fn a_supply_effect_defined_outside_the_library_acts_by_the_term_it_names() {
    use printwatt::effects::SupplyTerm;
    let r = default_robot();
    let tr = sines(6, 4.0, 800);
    // The same physics through the registered effect and through one defined here: a
    // regeneration term (once taken as the standby power because it was not called
    // "regeneration") and a standby term.
    for (builtin, term, value) in [
        ("regeneration", SupplyTerm::Regeneration, 0.6),
        ("standby", SupplyTerm::Standby, 123.0),
    ] {
        let mut reference = EffectSet::of_robot(&r).unwrap();
        reference.set_enabled(builtin, true);
        reference
            .get_mut(builtin)
            .unwrap()
            .set_values(&[value])
            .unwrap();
        let want = evaluate(
            &EnergyModel::with_effects(&r, Default::default(), reference).unwrap(),
            &tr,
        )
        .unwrap();
        let mut set = EffectSet::of_robot(&r).unwrap();
        set.set_enabled(builtin, false);
        set.push(Box::new(SiteSupply { term, value }));
        let got = evaluate(
            &EnergyModel::with_effects(&r, Default::default(), set).unwrap(),
            &tr,
        )
        .unwrap();
        for (a, b, what) in [
            (got.total.supply_j, want.total.supply_j, "supply"),
            (got.total.standby_j, want.total.standby_j, "standby"),
            (
                got.total.regeneration_lost_j,
                want.total.regeneration_lost_j,
                "regeneration lost",
            ),
        ] {
            assert!(close(a, b, 1e-12), "{builtin}: {what} {a} J vs {b} J");
        }
    }
}

/// The energy report keyed by effect: every effect acting in the model has its line, in
/// catalogue order; a joint-torque effect's energy is what switching it off takes from its
/// part of the breakdown (its work is linear in its torque), the effects of a part add up to
/// that part, a motor or supply term's is its part; the payload, a body of the rigid-body
/// model, has no energy of its own.
#[test]
fn each_effects_energy_is_what_it_adds_to_its_part_of_the_breakdown() {
    let mut r = with_stribeck_offset_regeneration(0.5);
    set_enabled(&mut r, "payload", true);
    set_values(&mut r, "payload", vec![4.5, 0.0, 0.0, 0.0]);
    let tr = sines(6, 5.0, 1000);
    let rep = evaluate(&EnergyModel::new(&r).unwrap(), &tr).unwrap();
    let t = &rep.total;
    let names: Vec<&str> = rep.by_effect.iter().map(|e| e.effect.as_str()).collect();
    let on = set(&r).enabled_names();
    let catalogue_order: Vec<&str> = printwatt::effects::catalogue()
        .into_iter()
        .filter(|c| names.contains(c))
        .collect();
    assert_eq!(names, catalogue_order);
    for want in [
        "viscous",
        "coulomb",
        "stribeck",
        "payload",
        "balancer",
        "offset",
        "copper",
        "gear_efficiency",
        "regeneration",
        "standby",
    ] {
        assert!(names.contains(&want), "{want} missing from {names:?}");
        assert!(on.contains(&want));
    }
    let of = |name: &str| rep.by_effect.iter().find(|e| e.effect == name).unwrap();
    let sum_of = |part: &str| -> f64 {
        rep.by_effect
            .iter()
            .filter(|e| e.part == part)
            .map(|e| e.energy_j.unwrap())
            .sum()
    };
    assert!(close(sum_of("friction"), t.friction_j, 1e-12));
    assert!(close(sum_of("balancer"), t.balancer_j, 1e-12));
    assert!(t.friction_j > 100.0 && t.balancer_j != 0.0);
    for (name, part, total) in [
        ("copper", "copper", t.copper_j),
        ("gear_efficiency", "gear", t.gear_j),
        ("regeneration", "regeneration_lost", t.regeneration_lost_j),
        ("standby", "standby", t.standby_j),
    ] {
        assert_eq!((of(name).part, of(name).energy_j), (part, Some(total)));
    }
    assert_eq!(
        (of("payload").part, of("payload").energy_j),
        ("rigid_body", None)
    );
    // Switched off, a joint-torque effect takes its own energy from its part.
    let part_j = |t: &printwatt::energy::TotalEnergy, part: &str| match part {
        "friction" => t.friction_j,
        "balancer" => t.balancer_j,
        "rigid_body" => t.rigid_body_j,
        p => panic!("{p}"),
    };
    for name in ["viscous", "coulomb", "stribeck", "balancer", "offset"] {
        let e = of(name);
        let mut off = r.clone();
        set_enabled(&mut off, name, false);
        let without = evaluate(&EnergyModel::new(&off).unwrap(), &tr).unwrap();
        assert!(without.by_effect.iter().all(|x| x.effect != name));
        let taken = part_j(t, e.part) - part_j(&without.total, e.part);
        let own = e.energy_j.unwrap();
        assert!(own != 0.0, "{name}");
        assert!(
            (taken - own).abs() <= 1e-9 * (1.0 + own.abs()),
            "{name}: switching it off takes {taken} J from {}, its own energy is {own} J",
            e.part
        );
    }
}
