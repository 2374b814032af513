//! A fixed workload for instruction-count profiles (valgrind `callgrind`) of one placement
//! evaluation: the bench's feasible placement (`benches/placement.rs`: the default robot and
//! path, the feasible centre of the default grid) evaluated `N` times on one thread.
//!
//! `cargo build --release --example profile_evaluation`, then
//! `valgrind --tool=callgrind target/release/examples/profile_evaluation N` for N = 1 and
//! N = 6: the difference of the two totals over 5 is the cost of one evaluation (the set-up,
//! the grid sweep that finds the placement included, cancels out). valgrind runs the AVX2
//! path (it has no AVX-512). `PRINTWATT_PLACEMENT=x,y,z,yaw` skips the grid sweep.

use printwatt::evaluate::feasibility::FeasibilityOptions;
use printwatt::evaluate::{Evaluator, Objective, PathJob};
use printwatt::search::optimise::{default_grid, feasible_centre};
use printwatt::timing::{JointStageOptions, ProfileOptions};
use printwatt::toolpath::{self, Placement, ReadOptions};
use printwatt::{robot, EnergyOptions};
use std::hint::black_box;
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let reps: usize = std::env::args().nth(1).map_or(Ok(1), |s| s.parse())?;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let model = robot::load(&root.join("robots/abb_irb6700_200_260"))?;
    let tp = toolpath::load(&root.join("paths/default.gcode"), &ReadOptions::default())?;
    let job = PathJob::new(
        &model,
        &tp,
        EnergyOptions::default(),
        ProfileOptions::default(),
        JointStageOptions::default(),
    )?;
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let at = match std::env::var("PRINTWATT_PLACEMENT") {
        Ok(s) => Placement::parse(&s)?,
        Err(_) => {
            let ps = default_grid(printwatt::evaluate::feasibility::reach_m(&model)).placements();
            let grid = ev.sweep(&ps, &|_, _| {})?;
            feasible_centre(&grid)
                .ok_or("no feasible grid cell")?
                .placement
        }
    };
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    one.install(|| -> printwatt::Result<()> {
        let mut sc = ev.scratch()?;
        let mut samples = 0;
        for _ in 0..reps {
            let e = black_box(ev.evaluate(&mut sc, &at));
            samples = e.feasible().map_or(0, |f| f.samples);
        }
        println!(
            "{reps} evaluation(s) at ({}, {}, {}) m, yaw {} rad ({samples} samples each), SIMD {:?}",
            at.x,
            at.y,
            at.z,
            at.yaw,
            printwatt::simd::level()
        );
        Ok(())
    })?;
    Ok(())
}
