//! Where to print: evaluate a small grid of placements in parallel and take the best.
//!
//! `cargo run --release --example sweep`

use printwatt::evaluate::evaluator::{Evaluator, Objective};
use printwatt::evaluate::feasibility::FeasibilityOptions;
use printwatt::search::Grid;
use printwatt::timing::{JointStageOptions, ProfileOptions};
use printwatt::{EnergyOptions, PathJob, ReadOptions};
use std::path::Path;

pub fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let robot = printwatt::load_robot(&root.join("robots/abb_irb6700_200_260"))?;
    let path = printwatt::load_path(&root.join("paths/default.gcode"), &ReadOptions::default())?;
    let job = PathJob::new(
        &robot,
        &path,
        EnergyOptions::default(),
        ProfileOptions::default(),
        JointStageOptions::default(),
    )?;
    // x, y, z in m; yaws and nozzle spins in rad.
    let grid = Grid {
        xs: vec![1.4, 1.6, 1.8],
        ys: vec![-0.2, 0.0, 0.2],
        zs: vec![0.0, 0.55],
        yaws: vec![90f64.to_radians()],
        spins: vec![0.0],
    };
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let rows = ev.sweep(&grid.placements(), &|_, _| {})?;
    for r in &rows {
        let p = &r.placement;
        match &r.outcome {
            Ok(f) => println!("x {:.1} m, y {:+.1} m: {:.1} J", p.x, p.y, f.energy_j),
            Err(why) => println!("x {:.1} m, y {:+.1} m: {}", p.x, p.y, why.reason.name()),
        }
    }
    let best = printwatt::search::optimise::best_of(&rows).ok_or("no feasible placement")?;
    println!(
        "best: x {:.1} m, y {:+.1} m, {:.1} J supply",
        best.placement.x,
        best.placement.y,
        best.cost()
    );
    Ok(())
}
