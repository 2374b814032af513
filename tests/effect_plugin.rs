//! An effect defined outside the library, in this one file, plus one registration: a constant
//! pull per joint (a hanging hose or cable), `τ_j = c_j`. Once registered it is read from a
//! drive file's `[effects]` table, adds exactly its torque to the energy model, leaves the
//! energy with the payload option it states, is fitted by identification, judged by its own
//! plausibility rule and written to the calibrated robot, and draws its own range in the
//! placement's uncertainty study. A second one supplies a motor term (`spare_winding`, the
//! winding resistance) and enters the motor model by that role.

#![allow(clippy::needless_range_loop)]

mod common;
use common::{close, root, scratch, Sines};
use printwatt::effects::{
    check_values, register, BuildContext, DrawPhase, Drawing, Effect, EffectSet, MotorTerm,
    ParamSpec, Registration, Stage, Uncertainty,
};
use printwatt::energy::{eval_sample, evaluate, EnergyModel, EnergyOptions, SamplePower};
use printwatt::error::Result;
use printwatt::robot::{load, RobotModel};
use printwatt::search::uncertainty::{drawn_robot, Ranges};
use std::path::{Path, PathBuf};

// ---- the effect: this file and one registration ---------------------------------------------

/// Half-width of the uniform range of each joint's pull in the uncertainty study, ± fraction.
const HOSE_PULL_REL: f64 = 0.1;

/// The largest pull a hose exerts on a joint, N·m: a fitted pull beyond it is no hose's.
const HOSE_PULL_MAX_NM: f64 = 500.0;

/// `hose_pull`: a constant torque per joint, N·m.
#[derive(Clone, Debug, PartialEq)]
struct HosePull {
    c: Vec<f64>,
}

/// Built from the robot: no pull unless the drive file's `[effects.values] hose_pull` says.
fn build(ctx: &BuildContext) -> Result<Box<dyn Effect>> {
    Ok(Box::new(HosePull {
        c: vec![0.0; ctx.dof()],
    }))
}

impl Effect for HosePull {
    fn name(&self) -> &'static str {
        "hose_pull"
    }
    fn params(&self) -> Vec<ParamSpec> {
        (0..self.c.len())
            .map(|j| ParamSpec {
                name: format!("c[{}]", j + 1),
                unit: "N·m",
                lower: -1e4,
                upper: 1e4,
            })
            .collect()
    }
    fn values(&self) -> Vec<f64> {
        self.c.clone()
    }
    fn set_values(&mut self, values: &[f64]) -> Result<()> {
        check_values(self.name(), &self.params(), values)?;
        self.c.copy_from_slice(values);
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn is_null(&self) -> bool {
        self.c.iter().all(|c| *c == 0.0)
    }
    /// The hose is part of the print head's equipment: it leaves the energy with the payload.
    fn in_energy_model(&self, options: &EnergyOptions, _has_drive: bool) -> bool {
        options.payload
    }
    /// A hose weighs a few kilograms: a pull beyond [`HOSE_PULL_MAX_NM`] is no hose's.
    fn implausible_fit(&self, _std_errors: &[Option<f64>]) -> Option<String> {
        let why: Vec<String> = self
            .c
            .iter()
            .enumerate()
            .filter(|(_, c)| c.abs() > HOSE_PULL_MAX_NM)
            .map(|(j, c)| {
                format!(
                    "c[{}] = {c} N·m: no hose pulls more than {HOSE_PULL_MAX_NM} N·m",
                    j + 1
                )
            })
            .collect();
        (!why.is_empty()).then(|| why.join("; "))
    }
    fn add_torque(&self, _q: &[f64], _qd: &[f64], _qdd: &[f64], tau: &mut [f64]) {
        for (t, c) in tau.iter_mut().zip(&self.c) {
            *t += c;
        }
    }
    fn regressor(&self, _q: &[f64], _qd: &[f64], _qdd: &[f64], y: &mut [f64]) -> bool {
        let p = self.c.len();
        y.iter_mut().for_each(|v| *v = 0.0);
        for j in 0..p {
            y[j * p + j] = 1.0;
        }
        true
    }
    fn uncertainty(&self) -> Option<Uncertainty> {
        Some(Uncertainty {
            phase: DrawPhase::Effects,
            rank: 100,
            draws_identified: false,
        })
    }
    fn draw(&self, d: &mut Drawing<'_>, _joint: Option<usize>) {
        let mut c = self.c.clone();
        for (j, c) in c.iter_mut().enumerate() {
            let f = 1.0 + HOSE_PULL_REL * d.uniform();
            *c *= f;
            d.record(format!("hose pull joint {}", j + 1), f);
        }
        d.robot
            .effects
            .table
            .values
            .get_or_insert_with(Default::default)
            .insert("hose_pull".into(), c);
    }
}

/// `spare_winding`: the winding resistance per axis `R`, Ω, supplied to the motor model as
/// `copper` supplies it.
#[derive(Clone, Debug, PartialEq)]
struct SpareWinding {
    r: Vec<f64>,
}

/// Built from the robot: zero unless the drive file's `[effects.values] spare_winding` says.
fn build_spare_winding(ctx: &BuildContext) -> Result<Box<dyn Effect>> {
    Ok(Box::new(SpareWinding {
        r: vec![0.0; ctx.dof()],
    }))
}

impl Effect for SpareWinding {
    fn name(&self) -> &'static str {
        "spare_winding"
    }
    fn params(&self) -> Vec<ParamSpec> {
        (0..self.r.len())
            .map(|j| ParamSpec {
                name: format!("R[{}]", j + 1),
                unit: "Ω",
                lower: 0.0,
                upper: f64::INFINITY,
            })
            .collect()
    }
    fn values(&self) -> Vec<f64> {
        self.r.clone()
    }
    fn set_values(&mut self, values: &[f64]) -> Result<()> {
        check_values(self.name(), &self.params(), values)?;
        self.r.copy_from_slice(values);
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn stage(&self) -> Stage {
        Stage::Motor(MotorTerm::WindingResistance)
    }
}

/// The registration lines (`spare_winding` first: `hose_pull` ends the catalogue).
fn registered() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        register(Registration {
            name: "spare_winding",
            build: build_spare_winding,
        })
        .expect("spare_winding registers");
        register(Registration {
            name: "hose_pull",
            build,
        })
        .expect("hose_pull registers");
    });
}

// ---- the checks ------------------------------------------------------------------------------

const PULL: [f64; 6] = [0.0, 180.0, -60.0, 12.0, 0.0, 3.0];

/// The shipped IRB 6700's drive file, naming its URDF, with `hose_pull` switched on (`pull`)
/// or not, written to `dir`.
fn drive_file(dir: &Path, pull: Option<[f64; 6]>) -> PathBuf {
    let src = root().join("robots/abb_irb6700_200_260");
    let text = std::fs::read_to_string(src.join("drive.toml")).unwrap();
    let urdf = src.join("robot.urdf");
    let mut out = String::new();
    for line in text.lines() {
        out.push_str(line);
        out.push('\n');
        if line == "[robot]" {
            out.push_str(&format!("urdf = {:?}\n", urdf.display().to_string()));
        }
        if line.starts_with("[effects]") {
            let mut on = vec![
                "viscous",
                "coulomb",
                "armature",
                "balancer",
                "copper",
                "gear_efficiency",
                "regeneration",
                "standby",
            ];
            if pull.is_some() {
                on.push("hose_pull");
            }
            out.push_str(&format!("enabled = {on:?}\n"));
        }
    }
    if let Some(c) = pull {
        out.push_str(&format!("\n[effects.values]\nhose_pull = {c:?}\n"));
    }
    let path = dir.join(if pull.is_some() {
        "pull.toml"
    } else {
        "plain.toml"
    });
    std::fs::write(&path, out).unwrap();
    path
}

fn robots(name: &str) -> (RobotModel, RobotModel, PathBuf) {
    registered();
    let dir = scratch("effect-plugin", name);
    let with = drive_file(&dir, Some(PULL));
    (
        load(&with).unwrap(),
        load(&drive_file(&dir, None)).unwrap(),
        with,
    )
}

#[test]
fn an_effect_defined_in_one_file_outside_the_crate_is_read_from_the_drive_file_and_adds_its_torque_to_the_energy(
) {
    let (with, without, _) = robots("energy");
    assert_eq!(printwatt::effects::catalogue().last(), Some(&"hose_pull"));
    let set = EffectSet::of_robot(&with).unwrap();
    assert!(set.is_enabled("hose_pull"));
    assert_eq!(set.get("hose_pull").unwrap().values(), PULL.to_vec());
    assert!(!EffectSet::of_robot(&without)
        .unwrap()
        .is_enabled("hose_pull"));

    // Per sample the torque grows by exactly the pull; nothing else changes.
    let (m_on, m_off) = (
        EnergyModel::new(&with).unwrap(),
        EnergyModel::new(&without).unwrap(),
    );
    let tr = Sines {
        terms: (0..6)
            .map(|j| vec![(0.3, 0.9, 0.4 * j as f64), (0.1, 2.3, 1.0)])
            .collect(),
    }
    .trajectory(4.0, 400);
    let (mut d_on, mut d_off) = (m_on.data(), m_off.data());
    let (mut s_on, mut s_off) = (SamplePower::default(), SamplePower::default());
    for k in 0..tr.len() {
        let (q, qd, qdd) = (tr.q(k), tr.qd(k), tr.qdd(k));
        eval_sample(&m_on, &mut d_on, q, qd, qdd, &mut s_on).unwrap();
        eval_sample(&m_off, &mut d_off, q, qd, qdd, &mut s_off).unwrap();
        for j in 0..6 {
            let d = s_on.tau[j] - s_off.tau[j];
            assert!(
                (d - PULL[j]).abs() <= 1e-9 * s_on.tau[j].abs().max(1.0),
                "sample {k} joint {}: {d} N·m vs {}",
                j + 1,
                PULL[j]
            );
        }
    }
    // The energy: the same as the built-in constant torque (`offset`) with the same values,
    // and not the energy without it.
    let mut offset = without.clone();
    let t = &mut offset.effects.table;
    t.enabled.as_mut().unwrap().push("offset".into());
    t.values
        .get_or_insert_with(Default::default)
        .insert("offset".into(), PULL.to_vec());
    let e_on = evaluate(&m_on, &tr).unwrap().total.supply_j;
    let e_off = evaluate(&m_off, &tr).unwrap().total.supply_j;
    let e_ref = evaluate(&EnergyModel::new(&offset).unwrap(), &tr)
        .unwrap()
        .total
        .supply_j;
    assert!(close(e_on, e_ref, 1e-12), "{e_on} J vs offset {e_ref} J");
    assert!((e_on - e_off).abs() > 1e-3 * e_off, "{e_on} J vs {e_off} J");
}

#[test]
fn an_effect_defined_in_one_file_outside_the_crate_is_drawn_in_the_uncertainty_study() {
    let (with, _, _) = robots("uncertainty");
    let ranges = Ranges::default();
    let (m, drawn) = drawn_robot(&with, &ranges, 11, 3);
    let (m2, drawn2) = drawn_robot(&with, &ranges, 11, 3);
    assert_eq!(drawn, drawn2, "the same seed and draw give the same robot");
    assert_eq!(
        EffectSet::of_robot(&m2)
            .unwrap()
            .get("hose_pull")
            .unwrap()
            .values(),
        EffectSet::of_robot(&m)
            .unwrap()
            .get("hose_pull")
            .unwrap()
            .values()
    );
    // Its draws come last (after the built-in effects', whose order a seed keeps).
    let pulls: Vec<&(String, f64)> = drawn
        .iter()
        .filter(|(n, _)| n.starts_with("hose pull"))
        .collect();
    assert_eq!(pulls.len(), 6);
    assert_eq!(drawn[drawn.len() - 6..].iter().collect::<Vec<_>>(), pulls);
    let got = EffectSet::of_robot(&m)
        .unwrap()
        .get("hose_pull")
        .unwrap()
        .values();
    let mut moved = false;
    for j in 0..6 {
        let f = pulls[j].1;
        assert!(
            (1.0 - HOSE_PULL_REL..=1.0 + HOSE_PULL_REL).contains(&f),
            "{f}"
        );
        assert_eq!(got[j], PULL[j] * f, "joint {}", j + 1);
        moved |= PULL[j] != 0.0 && f != 1.0;
    }
    assert!(moved, "the draw changes the pull");
    // Another draw draws other values.
    let (_, other) = drawn_robot(&with, &ranges, 11, 4);
    assert_ne!(other[other.len() - 6..], drawn[drawn.len() - 6..]);
}

#[test]
fn an_effect_defined_in_one_file_outside_the_crate_is_fitted_by_identify_and_written_to_the_calibrated_robot(
) {
    use printwatt::identify::{
        calibrate, ladder, log::parse_log, simulate, train_validation_split, Model, Prepared,
        SignalKind,
    };
    let (_, without, _) = robots("identify");
    let dir = scratch("effect-plugin", "identify-out");
    let plain = drive_file(&dir, None);
    // A torque log of the robot with the pull.
    let mut truth = Model::new(&without).unwrap();
    truth.set_enabled("hose_pull", true).unwrap();
    truth.set_values("hose_pull", &PULL).unwrap();
    let tr = simulate::resample(&simulate::excitation(&without, 8.0, 1000.0, 5), 250.0);
    let opt = simulate::SensorOptions {
        kind: SignalKind::Torque,
        noise: 0.5,
        noise_q: 1e-6,
        current_quantum: 0.01,
        seed: 5,
    };
    let text = simulate::simulate_log(&truth, &tr, &opt, &[]).unwrap();
    let log = parse_log(&text, "pull.csv", 6, None).unwrap();
    // Fitted from the model without it.
    let mut m = Model::new(&without).unwrap();
    m.set_enabled("hose_pull", true).unwrap();
    let prep = Prepared::new(&m, &log).unwrap();
    let (train, val) = train_validation_split(log.traj.len());
    let (train, val): (Vec<usize>, Vec<usize>) = (train.collect(), val.collect());
    let id = ladder::identify(
        &mut m,
        (&prep, &train),
        (&prep, &val),
        &["hose_pull"],
        "held out".into(),
    )
    .unwrap();
    let fitted = m.values("hose_pull").unwrap();
    for j in 0..6 {
        assert!(
            (fitted[j] - PULL[j]).abs() < 1.0,
            "joint {}: {} N·m vs {}",
            j + 1,
            fitted[j],
            PULL[j]
        );
    }
    // Written to the calibrated robot's `[effects.values]`, read back by every command.
    let robot = load(&plain).unwrap();
    let dst = dir.join("pull.calibrated.toml");
    let inp = calibrate::CalibrationInput {
        robot: &robot,
        drive_file: Some(&plain),
        robot_arg: "plain.toml",
        model: &m,
        id: &id,
        log: &log,
        date: "2026-01-01".into(),
    };
    calibrate::write_calibrated(&inp, &dst, None, true).unwrap();
    let back = EffectSet::of_robot(&load(&dst).unwrap()).unwrap();
    assert!(back.is_enabled("hose_pull"));
    assert_eq!(back.get("hose_pull").unwrap().values(), fitted);
}

/// A sampled motion of every joint, `samples` samples over `seconds` s.
fn motion(seconds: f64, samples: usize) -> printwatt::trajectory::JointTrajectory {
    Sines {
        terms: (0..6)
            .map(|j| vec![(0.3, 0.9, 0.4 * j as f64), (0.1, 2.3, 1.0)])
            .collect(),
    }
    .trajectory(seconds, samples)
}

#[test]
fn an_effect_defined_outside_the_crate_leaves_the_energy_with_the_energy_option_it_states() {
    let (with, without, _) = robots("gated");
    let tr = motion(4.0, 400);
    let supply = |robot: &RobotModel, options: EnergyOptions| {
        let m = EnergyModel::with_options(robot, options).unwrap();
        (evaluate(&m, &tr).unwrap().total.supply_j, m.description())
    };
    let off = EnergyOptions {
        payload: false,
        ..Default::default()
    };
    // Its option off: the energy of the robot without it, to the bit, and not named.
    let (e_with, desc) = supply(&with, off);
    let (e_without, _) = supply(&without, off);
    assert_eq!(e_with, e_without);
    assert!(!desc.contains("hose_pull"), "{desc}");
    // Its option on: it is in the energy.
    let (e_with, desc) = supply(&with, EnergyOptions::default());
    let (e_without, _) = supply(&without, EnergyOptions::default());
    assert!(
        (e_with - e_without).abs() > 1e-3 * e_without,
        "{e_with} J vs {e_without} J"
    );
    assert!(desc.contains("hose_pull"), "{desc}");
}

#[test]
fn an_effect_defined_outside_the_crate_judges_its_own_fitted_values_implausible() {
    use printwatt::identify::{plausible, Model};
    let (with, _, _) = robots("plausible");
    let mut m = Model::new(&with).unwrap();
    let se = [Some(1.0); 6];
    assert_eq!(plausible::implausible_fit(&m, "hose_pull", &se), None);
    let mut bad = PULL;
    bad[2] = -2.0 * HOSE_PULL_MAX_NM;
    m.set_values("hose_pull", &bad).unwrap();
    assert_eq!(
        plausible::implausible_fit(&m, "hose_pull", &se).as_deref(),
        Some("c[3] = -1000 N·m: no hose pulls more than 500 N·m")
    );
}

#[test]
fn an_effect_defined_outside_the_crate_supplies_the_motor_term_it_names() {
    let (with, _, _) = robots("motor-term");
    let tr = motion(4.0, 400);
    let r = EffectSet::of_robot(&with)
        .unwrap()
        .get("copper")
        .unwrap()
        .values();
    assert!(r.iter().all(|r| *r > 0.0), "{r:?}");
    // In place of `copper`, with its values: the same energy, to the bit.
    let mut spare = with.clone();
    let t = &mut spare.effects.table;
    let enabled = t.enabled.as_mut().unwrap();
    enabled.retain(|e| e != "copper");
    enabled.push("spare_winding".into());
    t.values
        .get_or_insert_with(Default::default)
        .insert("spare_winding".into(), r.clone());
    let e_copper = evaluate(&EnergyModel::new(&with).unwrap(), &tr).unwrap();
    let e_spare = evaluate(&EnergyModel::new(&spare).unwrap(), &tr).unwrap();
    assert_eq!(e_copper.total.supply_j, e_spare.total.supply_j);
    assert_eq!(e_copper.total.copper_j, e_spare.total.copper_j);
    assert!(e_spare.total.copper_j > 0.0);
    // Beside `copper`: two effects for one motor term is an error naming both, not one
    // silently replacing the other.
    spare
        .effects
        .table
        .enabled
        .as_mut()
        .unwrap()
        .push("copper".into());
    let err = EnergyModel::new(&spare).unwrap_err().to_string();
    assert!(
        err.contains("`copper`")
            && err.contains("`spare_winding`")
            && err.contains("the winding resistance"),
        "{err}"
    );
    // Identification reads the terms by the same rule: the robot is refused, and switching
    // the second one on in a model is refused and leaves the switch as it was.
    let err = printwatt::identify::Model::new(&spare)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("`copper`") && err.contains("`spare_winding`"),
        "{err}"
    );
    let mut m = printwatt::identify::Model::new(&with).unwrap();
    assert!(m.is_enabled("copper") && !m.is_enabled("spare_winding"));
    let err = m
        .set_enabled("spare_winding", true)
        .unwrap_err()
        .to_string();
    assert!(err.contains("the winding resistance"), "{err}");
    assert!(!m.is_enabled("spare_winding"));
    m.set_enabled("copper", false).unwrap();
    m.set_enabled("spare_winding", true).unwrap();
}

#[test]
fn an_effect_defined_outside_the_crate_is_seen_in_the_logs_its_stage_reaches() {
    use printwatt::identify::{Model, RoundPlan, SignalKind};
    let (with, _, _) = robots("observable");
    let model = Model::new(&with).unwrap();
    // A motor term (winding resistance) is in the power logs only, as `copper` is; a joint
    // torque is in every log.
    for kind in [
        SignalKind::Torque,
        SignalKind::Current,
        SignalKind::AxisPower,
        SignalKind::TotalPower,
    ] {
        assert_eq!(
            model.observable("spare_winding", kind),
            model.observable("copper", kind),
            "{kind:?}"
        );
        assert!(model.observable("hose_pull", kind), "{kind:?}");
    }
    assert!(!model.observable("spare_winding", SignalKind::Torque));
    assert!(model.observable("spare_winding", SignalKind::AxisPower));
    // A round asked to fit it on a torque log is refused, naming it and the log.
    let err = RoundPlan::new(&with, &model, "spare_winding", SignalKind::Torque)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("`spare_winding`") && err.contains("`tau`"),
        "{err}"
    );
    assert!(RoundPlan::new(&with, &model, "spare_winding", SignalKind::AxisPower).is_ok());
}
