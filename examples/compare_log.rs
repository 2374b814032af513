//! Check the model against a measured log: here a log simulated from a "true" robot with a
//! hidden Coulomb friction, compared with the nominal model (RMSE and energy error per joint).
//!
//! `cargo run --release --example compare_log`

use printwatt::identify::{self, metrics, simulate, Model, Prepared, SignalKind};
use std::path::Path;

pub fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let robot = printwatt::load_robot(&root.join("robots/abb_irb4600_40_255"))?;
    // The log a real robot would give: the nominal robot plus 30 N·m of Coulomb friction,
    // 8 s of exciting motion sampled at 250 Hz with 2 N·m of torque noise.
    let mut truth = Model::new(&robot)?;
    simulate::apply_hidden(&mut truth, &simulate::parse_hidden("coulomb=30")?)?;
    let motion = simulate::resample(&simulate::excitation(&robot, 8.0, 1000.0, 7), 250.0);
    let sensor = simulate::SensorOptions {
        kind: SignalKind::Torque,
        noise: 2.0,
        noise_q: 1e-6,
        current_quantum: 0.0,
        seed: 7,
    };
    let text = simulate::simulate_log(&truth, &motion, &sensor, &[])?;
    let file = std::env::temp_dir().join(format!("printwatt-example-{}.csv", std::process::id()));
    std::fs::write(&file, text)?;

    // Read it back as any log (docs/measurement-logs.md) and compare the nominal model.
    let log = identify::read_log(&file, robot.dof(), None)?;
    let model = Model::new(&robot)?;
    let (cmp, _prediction) = metrics::compare(&Prepared::new(&model, &log)?, &model);
    println!(
        "log {} ({} samples), unit {}",
        cmp.log, cmp.samples, cmp.unit
    );
    for c in cmp.channels.iter().chain([&cmp.total]) {
        println!(
            "{:<8} rmse {:>8.2}  energy measured {:>9.1} J, model {:>9.1} J ({:+.1} %)",
            c.name, c.rmse, c.energy_measured_j, c.energy_model_j, c.energy_error_pct
        );
    }
    std::fs::remove_file(&file)?;
    Ok(())
}
