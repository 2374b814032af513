//! Run time of the multi-station planner (`printwatt stations`) on the shipped example
//! `paths/floor_four_rooms.gcode` (12 × 3 m, four rooms, 26 units) with the IRB 6700 on the
//! default candidate grid (every 0.5 m over the footprint ± the reach), as a ratio to one
//! single-placement evaluation measured in the same run: the plan's first segment (one room,
//! 18 m of wall) evaluated at its station, on one thread.
//!
//! Run: `cargo bench --bench stations` (plain main, no criterion: prints a small table; the
//! planner takes seconds, so each figure is the best of 2 runs, the reference the best of 5).

#[path = "../tests/common/mod.rs"]
mod common;

use printwatt::energy::EnergyOptions;
use printwatt::evaluate::{Evaluator, FeasibilityOptions, Objective};
use printwatt::stations::{self, Candidates, Headings, StationsProblem};
use printwatt::timing::{JointStageOptions, ProfileOptions};
use printwatt::toolpath::{self, ReadOptions};
use std::path::Path;
use std::time::Instant;

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let model = common::robot("abb_irb6700_200_260");
    let path = toolpath::load(
        &root.join("paths/floor_four_rooms.gcode"),
        &ReadOptions::default(),
    )
    .unwrap();
    let reach = printwatt::evaluate::feasibility::reach_m(&model);
    let problem = StationsProblem {
        robot: &model,
        path: &path,
        energy: EnergyOptions::default(),
        profile: ProfileOptions::default(),
        joint: JointStageOptions::default(),
        // A wrist margin of 0, as README.md runs this plan: its stations pass q5 through 0.
        feasibility: FeasibilityOptions {
            wrist_margin_rad: 0.0,
            ..FeasibilityOptions::default()
        },
        objective: Objective::Supply,
        candidates: Candidates {
            positions: stations::grid_positions(&path, 0.5, reach).unwrap(),
            headings: Headings::Auto,
            description: "grid every 0.5 m".into(),
            track: None,
        },
        z_m: -0.5,
        spin_rad: 0.0,
        relocation_j: 20_000.0,
        relocation_j_per_m: 0.0,
        footprint_m: stations::default_footprint_m(&model),
    };
    let pool = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    let time_plan = |n: usize| {
        let p = pool(n);
        let mut best = f64::INFINITY;
        let mut plan = None;
        for _ in 0..2 {
            let t0 = Instant::now();
            let r = p.install(|| stations::solve(&problem, &|_, _| {}).unwrap());
            best = best.min(t0.elapsed().as_secs_f64());
            plan = Some(r);
        }
        (best, plan.unwrap())
    };
    let (t1, plan) = time_plan(1);
    let (tn, plan_n) = time_plan(cores);
    assert_eq!(plan, plan_n, "the plan depends on the thread count");
    // Reference: one single-placement evaluation, the plan's first segment at its station.
    let s0 = &plan.segments[0];
    let sub = stations::sub_path(&path, s0.moves[0], s0.moves[1]);
    let job = common::default_job(&model, &sub);
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let mut sc = ev.scratch().unwrap();
    let mut t_ref = f64::INFINITY;
    for _ in 0..5 {
        let t0 = Instant::now();
        let e = ev.evaluate(&mut sc, &s0.station.placement);
        t_ref = t_ref.min(t0.elapsed().as_secs_f64());
        assert!(e.cost().is_finite());
    }
    let st = &plan.stats;
    println!(
        "floor_four_rooms.gcode, IRB 6700, grid 0.5 m: {} units, {} positions, {} runs, {} evaluations ({} feasible); plan: {} stations, total {:.1} J",
        st.units,
        st.positions,
        st.runs,
        st.evaluations,
        st.feasible,
        plan.segments.len(),
        plan.total_j
    );
    println!(
        "one evaluation of segment 1 at its station ({} samples, 1 thread): {:.1} ms",
        s0.eval.samples,
        t_ref * 1e3
    );
    println!(
        "planner, 1 thread: {:.2} s = {:.0} x one evaluation",
        t1,
        t1 / t_ref
    );
    println!(
        "planner, {cores} threads: {:.2} s = {:.0} x one evaluation (speed-up {:.2})",
        tn,
        tn / t_ref,
        t1 / tn
    );
}
