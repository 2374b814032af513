//! Tool presets (`--tool`): seed 001's machining spindle replaces the TX200's tool and payload,
//! and its offset centre of mass loads the wrist as the closed-form static torque says.

mod common;

use printwatt::dynamics::gravity_torque;
use printwatt::kinematics::fk::fk;
use printwatt::math::V3;
use printwatt::robot::apply_tool_preset;

fn wrist_gravity_torque(model: &printwatt::robot::RobotModel, q: &[f64]) -> f64 {
    let dm = common::dyn_model(model, false);
    let mut data = dm.data();
    let mut tau = vec![0.0; model.dof()];
    gravity_torque(&dm, &mut data, q, &mut tau).unwrap();
    tau[4]
}

#[test]
fn seed001_spindle_preset_offsets_the_payload_and_loads_the_wrist() {
    let mut spindle = common::robot("staubli_tx200");
    apply_tool_preset(
        &mut spindle,
        &common::root().join("presets/seed001_spindle.toml"),
    )
    .expect("preset loads");
    let p = spindle.payload.unwrap();
    assert_eq!(p.mass, 40.0);
    assert!((spindle.tool.pos - V3::new(0.20, 0.0, 0.35)).norm() < 1e-12);
    assert!(spindle.warnings.iter().any(|w| w.contains("seed 001")));
    // At a pose with the wrist bent, the spindle's share of the joint-5 holding torque equals
    // axis5 · ((c − o5) × m g) with c its centre of mass (a hand computation from FK).
    let q = [0.0, 0.3, 1.2, 0.0, 0.9, 0.4];
    let mut bare = spindle.clone();
    bare.payload = None;
    let d_tau = wrist_gravity_torque(&spindle, &q) - wrist_gravity_torque(&bare, &q);
    let f = fk(&spindle, &q);
    let j5 = &f.joints[4];
    let axis = j5.rot * spindle.joints[4].axis;
    let c = f.flange.apply(&p.com);
    let weight = V3::new(0.0, 0.0, -9.81 * p.mass);
    // Holding torque = −(torque of gravity about the axis).
    let want = -axis.dot(&(c - j5.pos).cross(&weight));
    assert!(
        (d_tau - want).abs() < 1e-6 * want.abs().max(1.0),
        "spindle's joint-5 torque {d_tau} N·m, hand computation {want} N·m"
    );
    // A real load (tens of N·m) for the estimated 40 kg at 0.20 m.
    assert!(d_tau.abs() > 20.0, "{d_tau}");
}

#[test]
fn a_bad_tool_preset_is_a_clear_error() {
    let dir = std::env::temp_dir().join(format!("pw-preset-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("bad.toml");
    std::fs::write(
        &f,
        "[preset]\nname = \"x\"\n[tool]\nxyz_m = [0.0, 0.0, 0.1]\n[payload]\nmass_kg = -3.0\n",
    )
    .unwrap();
    let mut m = common::robot("staubli_tx200");
    let e = apply_tool_preset(&mut m, &f).unwrap_err().to_string();
    assert!(e.contains("payload.mass_kg"), "{e}");
    std::fs::write(&f, "[tool]\nxyz_m = [0.0, 0.0, 0.1]\n").unwrap();
    let e = apply_tool_preset(&mut m, &f).unwrap_err().to_string();
    assert!(e.contains("bad.toml") && e.contains("preset"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
