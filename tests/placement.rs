//! Placement planner: feasibility with reasons, sweeps, determinism, optimiser, CLI.

use printwatt::energy::EnergyOptions;
use printwatt::placement::{Evaluator, FeasibilityOptions, Objective, PathJob};
use printwatt::robot;
use printwatt::timing::{JointStageOptions, ProfileOptions};
use printwatt::toolpath::{self, Placement, ReadOptions};
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn load(robot_id: &str, path: &str) -> (robot::RobotModel, toolpath::Toolpath) {
    let model = robot::load(&root().join("robots").join(robot_id)).unwrap();
    let tp = toolpath::load(&root().join("paths").join(path), &ReadOptions::default()).unwrap();
    (model, tp)
}

#[test]
fn fast_evaluation_matches_full_evaluation() {
    let (model, tp) = load("abb_irb6700_200_260", "default.gcode");
    let job = PathJob::new(
        &model,
        &tp,
        EnergyOptions::default(),
        ProfileOptions::default(),
        JointStageOptions::default(),
    )
    .unwrap();
    let feas = FeasibilityOptions {
        wrist_min: 0.0,
        ..Default::default()
    };
    let ev = Evaluator::new(&job, feas, Objective::Supply);
    let at = Placement::new(1.7, 0.0, 0.0, std::f64::consts::FRAC_PI_2);
    let mut sc = ev.scratch().unwrap();
    let t0 = std::time::Instant::now();
    let fast = ev.evaluate(&mut sc, &at);
    let dt_fast = t0.elapsed();
    let t0 = std::time::Instant::now();
    let full = job.evaluate(&at).unwrap().unwrap();
    let dt_full = t0.elapsed();
    eprintln!(
        "fast {dt_fast:?} full {dt_full:?} samples {}",
        full.timed.traj.len()
    );
    let f = fast.outcome.as_ref().unwrap_or_else(|e| panic!("{e}"));
    eprintln!("{f:?}");
    let rel = (f.supply_j - full.energy.total.supply_j).abs() / full.energy.total.supply_j;
    assert!(
        rel < 1e-9,
        "{} vs {}",
        f.supply_j,
        full.energy.total.supply_j
    );
    assert_eq!(f.samples, full.timed.traj.len());
}
