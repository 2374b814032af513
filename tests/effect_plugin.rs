//! An effect added from outside the crate: one file (this one) plus one registration. The
//! effect `nozzle_heater` (the print head's heater, a constant draw on the cabinet's supply)
//! reads its own drive-file key, acts in the supply stage, is reported under its own name in
//! the energy breakdown, writes itself into a calibrated drive file and declares the range the
//! uncertainty study draws it from.

mod common;
use common::root;

use printwatt::effects::{
    BuildContext, Effect, EffectRegistry, EffectSet, EnergyClass, ParamSpec, Registration, Stage,
    SupplyTerm, UncertaintyRange,
};
use printwatt::energy::{evaluate, EnergyModel};
use printwatt::error::{Error, Result};

/// The heater's constant draw `P_h`, W.
#[derive(Clone, Debug)]
struct NozzleHeater {
    power: f64,
}

impl Effect for NozzleHeater {
    fn name(&self) -> &'static str {
        "nozzle_heater"
    }
    fn params(&self) -> Vec<ParamSpec> {
        vec![ParamSpec {
            name: "P_h".into(),
            unit: "W",
            lower: 0.0,
            upper: 1e4,
        }]
    }
    fn values(&self) -> Vec<f64> {
        vec![self.power]
    }
    fn set_values(&mut self, v: &[f64]) -> Result<()> {
        match v {
            [p] if (0.0..=1e4).contains(p) => {
                self.power = *p;
                Ok(())
            }
            _ => Err(Error::Invalid(format!(
                "nozzle_heater: P_h {v:?} outside [0, 1e4] W"
            ))),
        }
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn stage(&self) -> Stage {
        Stage::Supply(SupplyTerm::ConstantPower)
    }
    fn energy_class(&self) -> EnergyClass {
        EnergyClass::Line("nozzle_heater")
    }
    fn is_null(&self) -> bool {
        self.power == 0.0
    }
    fn on_by_default(&self, has_drive: bool) -> bool {
        has_drive && !self.is_null()
    }
    fn uncertainty(&self) -> Vec<UncertaintyRange> {
        vec![UncertaintyRange {
            key: "nozzle_heater_rel",
            default: 0.25,
            params: vec![0],
        }]
    }
}

/// Its build function: reads and validates `[effects] nozzle_heater_w`.
fn build(ctx: &BuildContext) -> Result<Box<dyn Effect>> {
    let mut e = NozzleHeater { power: 0.0 };
    if let Some(p) = ctx.number("nozzle_heater_w")? {
        e.set_values(&[p])
            .map_err(|err| ctx.bad("nozzle_heater_w", err.to_string()))?;
    }
    Ok(Box::new(e))
}

/// The one registration.
fn registry() -> EffectRegistry {
    EffectRegistry::builtin()
        .with(Registration {
            name: "nozzle_heater",
            stage: Stage::Supply(SupplyTerm::ConstantPower),
            keys: &["nozzle_heater_w"],
            build,
        })
        .unwrap()
}

/// A copy of the shipped IRB 4600 whose drive file's `[effects]` gets `extra` lines; its
/// directory.
fn robot_with(dir_name: &str, extra: &str) -> std::path::PathBuf {
    let src = root().join("robots/abb_irb4600_40_255");
    let dir = std::env::temp_dir().join(format!(
        "printwatt_plugin_{}_{dir_name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for f in ["robot.urdf", "README.md"] {
        std::fs::copy(src.join(f), dir.join(f)).unwrap();
    }
    let drive = std::fs::read_to_string(src.join("drive.toml")).unwrap();
    assert!(drive.contains("\n[effects]"));
    let drive = drive.replacen("\n[effects]", &format!("\n[effects]\n{extra}"), 1);
    std::fs::write(dir.join("drive.toml"), drive).unwrap();
    dir
}

#[test]
fn registration_is_checked() {
    // A second effect for a single-valued stage, a taken name or key, are refused.
    let dup = Registration {
        name: "heater2",
        stage: Stage::Supply(SupplyTerm::RecoveredFraction),
        keys: &[],
        build,
    };
    assert!(EffectRegistry::builtin().with(dup).is_err());
    let taken_key = Registration {
        name: "heater3",
        stage: Stage::Supply(SupplyTerm::ConstantPower),
        keys: &["balancer_lever_m"],
        build,
    };
    let e = EffectRegistry::builtin()
        .with(taken_key)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("balancer_lever_m") && e.contains("balancer"),
        "{e}"
    );
    assert!(registry()
        .with(Registration {
            name: "nozzle_heater",
            stage: Stage::Supply(SupplyTerm::ConstantPower),
            keys: &[],
            build,
        })
        .is_err());
}

#[test]
fn a_registered_effect_reads_its_key_reports_its_energy_writes_itself_and_is_drawn() {
    registry().install();
    // Its key is read (and, without the registration, unknown: not a key of any effect).
    let dir = robot_with("on", "nozzle_heater_w = 40.0");
    let robot = printwatt::robot::load(&dir).unwrap();
    let set = EffectSet::of_robot(&robot).unwrap();
    assert_eq!(set.get("nozzle_heater").unwrap().values(), vec![40.0]);
    assert!(set.is_enabled("nozzle_heater"));
    let e = EffectSet::of_robot_with(&robot, &EffectRegistry::builtin())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("drive.toml") && e.contains("nozzle_heater_w"),
        "{e}"
    );
    // A bad value is an error naming the file and the key.
    let bad = robot_with("bad", "nozzle_heater_w = -3.0");
    let e = EffectSet::of_robot(&printwatt::robot::load(&bad).unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("drive.toml") && e.contains("nozzle_heater_w"),
        "{e}"
    );

    // Its energy is in the breakdown under its name: P_h × duration, and in the supply.
    let traj = common::Sines::random(robot.dof(), 3, 0.05..0.3, 0.5..2.0).trajectory(2.0, 201);
    let with = evaluate(&EnergyModel::new(&robot).unwrap(), &traj).unwrap();
    let plain = printwatt::robot::load(&robot_with("off", "")).unwrap();
    let without = evaluate(&EnergyModel::new(&plain).unwrap(), &traj).unwrap();
    let line = with.total.line("nozzle_heater").unwrap();
    assert!((line - 40.0 * traj.duration()).abs() < 1e-9, "{line}");
    assert!(without.total.line("nozzle_heater").is_none());
    assert_eq!(with.total.standby_j, without.total.standby_j);
    assert!((with.total.supply_j - without.total.supply_j - line).abs() < 1e-6);
    let json = serde_json::to_value(&with.total).unwrap();
    assert_eq!(json["nozzle_heater_j"].as_f64(), Some(line));
    assert!(serde_json::to_value(&without.total)
        .unwrap()
        .get("nozzle_heater_j")
        .is_none());

    // Written into a calibrated drive file: `[effects.values]` (its key removed), read back.
    let mut cal = set.clone();
    cal.get_mut("nozzle_heater")
        .unwrap()
        .set_values(&[55.0])
        .unwrap();
    let text = printwatt::identify::calibrate::drive_text_with_effects(
        &robot,
        &dir.join("drive.toml"),
        &cal,
    )
    .unwrap();
    assert!(text.contains("nozzle_heater = [55.0]"), "{text}");
    assert!(!text.contains("nozzle_heater_w"), "{text}");
    std::fs::write(dir.join("drive.toml"), &text).unwrap();
    let back = EffectSet::of_robot(&printwatt::robot::load(&dir).unwrap()).unwrap();
    assert_eq!(back.get("nozzle_heater").unwrap().values(), vec![55.0]);
    assert!(back.is_enabled("nozzle_heater"));

    // Its uncertainty range is drawn (the shipped [uncertainty] table names none: its default).
    let tp = common::path("seed000_test_path.gcode");
    let job = common::default_job(&robot, &tp);
    let ev = printwatt::evaluate::Evaluator::new(
        &job,
        printwatt::evaluate::FeasibilityOptions::default(),
        printwatt::evaluate::Objective::Supply,
    );
    let g = printwatt::search::Grid {
        xs: vec![1.2],
        ys: vec![0.0],
        zs: vec![0.0],
        yaws: vec![0.0],
        spins: vec![0.0],
    };
    let rows = ev.sweep(&g.placements(), &|_, _| {}).unwrap();
    let setup =
        printwatt::search::uncertainty::StudySetup::new(&ev, &rows, None, 8, 3, None).unwrap();
    let draws = setup.draws(&(0..8).collect::<Vec<_>>()).unwrap();
    let f: Vec<f64> = draws
        .iter()
        .map(|d| {
            d.drawn
                .iter()
                .find(|(n, _)| n == "nozzle_heater nozzle_heater_rel")
                .expect("drawn")
                .1
        })
        .collect();
    assert!(f.iter().all(|x| (0.75..=1.25).contains(x)), "{f:?}");
    assert!(f.iter().any(|x| *x != f[0]), "{f:?}");
    for d in [dir, bad] {
        let _ = std::fs::remove_dir_all(d);
    }
}
