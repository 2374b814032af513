//! The main job from Rust: the energy of a toolpath printed at one placement.
//!
//! `cargo run --release --example energy_at_placement`
//!
//! Loads the default robot (ABB IRB 6700) and the default path, places the path's part frame
//! 1.7 m in front of the robot, on the floor, turned 90°, times it like the controller and
//! prints the print time and the supply energy with its breakdown.

use printwatt::timing::{JointStageOptions, ProfileOptions};
use printwatt::{EnergyOptions, PathJob, Placement, ReadOptions};
use std::path::Path;

pub fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let robot = printwatt::load_robot(&root.join("robots/abb_irb6700_200_260"))?;
    let path = printwatt::load_path(&root.join("paths/default.gcode"), &ReadOptions::default())?;
    // The one text form of a placement: x, y, z in m, yaw in deg (an optional nozzle spin, deg).
    let at = Placement::parse("1.7,0,0,90")?;
    let job = PathJob::new(
        &robot,
        &path,
        EnergyOptions::default(),
        ProfileOptions::default(), // 4 ms period, 1 m/s², 10 m/s³
        JointStageOptions::default(),
    )?;
    match job.evaluate(&at)? {
        Ok(ev) => {
            let t = &ev.energy.total;
            println!("robot       {}", robot.name());
            println!("print time  {:.2} s", ev.energy.duration_s);
            println!(
                "supply      {:.1} J = standby {:.1} J + drives {:.1} J",
                t.supply_j, t.standby_j, t.drives_j
            );
            println!(
                "drives      friction {:.1} J, gear {:.1} J, copper {:.1} J",
                t.friction_j, t.gear_j, t.copper_j
            );
            for j in &ev.energy.joints {
                println!("  {:<8} {:>10.1} J electrical", j.name, j.electrical_j);
            }
        }
        Err(why) => println!("infeasible at {at:?}: {why}"),
    }
    Ok(())
}
