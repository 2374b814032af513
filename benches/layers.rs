//! A building-scale print: `printwatt optimise` with the path reduction
//! (src/placement/reduce.rs) on a 300-layer wall of more than 3·10⁶ samples at the default
//! 4 ms period, on 2 threads, against one full evaluation measured in the same run.
//!
//! The wall is generated in code (tests/common/wall.rs, not committed): a 1.8 m × 0.6 m
//! rectangular outline (4.8 m per layer at 150 mm/s, seams alternating between two corners,
//! retract, 10 mm z hop and travel between layers), 300 layers of 4 mm (1.2 m tall). The
//! optimisation is the CLI's: the default grid (1536 placements), Nelder–Mead refinement
//! (120 evaluations) with the default 20 mm / 1° tolerance, then the answer re-evaluated in
//! full ([`printwatt::evaluate::reduce::confirm`]).
//!
//! Prints: samples, the wall time of the optimisation on 2 threads (grid, refinement, full
//! re-evaluation), the time of one full and one reduced evaluation of the chosen placement on
//! 1 thread, their ratio, how the evaluations went (estimates, rejected by the reduced
//! evaluation, evaluated in full, layers re-planned), and the estimate against the full
//! energy at the chosen placement.
//!
//! Run: `cargo bench --bench layers` (plain main, no criterion). `PRINTWATT_LAYERS=N` sets
//! the number of layers (default 300); `PRINTWATT_LAYERS_BREAKDOWN=K` times every K-th grid
//! cell on one thread instead and sorts the time by how each cell was evaluated.

#[path = "common/pinocchio.rs"]
mod pinocchio;
#[path = "../tests/common/wall.rs"]
mod wall;

#[path = "../tests/common/mod.rs"]
mod common;

use printwatt::evaluate::feasibility::{reach_m, FeasibilityOptions};
use printwatt::evaluate::reduce::{self, ReduceOptions, Reduction};
use printwatt::evaluate::{Evaluator, Objective};
use printwatt::search::optimise::{default_grid, OptimiseOptions};
use printwatt::search::refine::{self, Bounds, SearchOptions};
use printwatt::search::tolerance::Tolerance;
use printwatt::toolpath::{self, ReadOptions};
use std::time::Instant;

fn main() {
    let layers: usize = std::env::var("PRINTWATT_LAYERS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300);
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    let model = common::robot("abb_irb6700_200_260");
    let t = Instant::now();
    let text = wall::wall_gcode(1800.0, 600.0, 4.0, layers);
    let tp = toolpath::parse_gcode(&text, "wall300.gcode", &ReadOptions::default()).unwrap();
    let job = common::default_job(&model, &tp);
    let samples = job.plan.motion.p.len();
    let red = Reduction::plan(&job, &tp, ReduceOptions::default()).unwrap_or_else(|e| {
        panic!("the wall is not reduced ({e:?}): it needs at least 200,000 samples (PRINTWATT_LAYERS >= 25)")
    });
    let t_job = t.elapsed().as_secs_f64();
    println!(
        "wall: {} layers ({} repeating, period {}), {} samples at 4 ms ({:.1} h of printing); reading, planning and the reduction plan {:.2} s",
        red.summary.layers,
        red.summary.repeating_layers,
        red.summary.period,
        samples,
        samples as f64 * 0.004 / 3600.0,
        t_job
    );
    // PRINTWATT_LAYERS_BREAKDOWN=K: where the grid's time goes instead: every K-th grid cell
    // evaluated on one thread, timed and put in a category by how it was evaluated (an
    // estimate, re-planned layers, found infeasible by the reduced evaluation, or evaluated
    // in full and why); one line per cell on stderr, the totals per category on stdout.
    if let Ok(every) = std::env::var("PRINTWATT_LAYERS_BREAKDOWN") {
        let every: usize = every.parse().expect("PRINTWATT_LAYERS_BREAKDOWN: a number");
        let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply)
            .with_reduction(red.clone());
        let grid = default_grid(reach_m(&model));
        let ps = grid.placements();
        let mut sc = ev.scratch().unwrap();
        let mut cats: std::collections::BTreeMap<String, (usize, f64)> = Default::default();
        for (i, p) in ps.iter().enumerate().step_by(every) {
            let c0 = ev.reduction().unwrap().counts();
            let t = Instant::now();
            let r = ev.evaluate(&mut sc, p);
            let dt = t.elapsed().as_secs_f64();
            let c1 = ev.reduction().unwrap().counts();
            let fb = r
                .feasible()
                .and_then(|f| f.path_reduction.as_ref())
                .and_then(|e| e.fallback.clone());
            let rp = c1.replanned_layers - c0.replanned_layers;
            let full = c1.full > c0.full;
            let cat = match (&r.outcome, full) {
                (Ok(_), false) => {
                    format!("feasible reduced{}", if rp > 0 { " replanned" } else { "" })
                }
                (Ok(_), true) => format!(
                    "feasible, evaluated in full ({})",
                    fb.map(|w| if w.contains("lowers the acceleration") {
                        "a ramp: the path's acceleration is lowered".to_string()
                    } else {
                        w.chars().take(40).collect()
                    })
                    .unwrap_or_default()
                ),
                (Err(e), false) => format!("infeasible ({}), reduced evaluation", e.reason.name()),
                (Err(e), true) => {
                    format!("infeasible ({}) after a full evaluation", e.reason.name())
                }
            };
            eprintln!(
                "{i} {:?} {dt:.3} {cat} {}",
                (p.x, p.y, p.z, p.yaw),
                r.outcome
                    .as_ref()
                    .err()
                    .map(|e| e.to_string())
                    .unwrap_or_default()
                    .chars()
                    .take(160)
                    .collect::<String>()
            );
            let e = cats.entry(cat).or_default();
            e.0 += 1;
            e.1 += dt;
        }
        for (k, (n, t)) in &cats {
            println!("{n:5} {t:9.2} s  {k}");
        }
        let total: f64 = cats.values().map(|c| c.1).sum();
        println!(
            "{} of {} grid cells, {total:.1} s on 1 thread; load average at start: {}",
            ps.len().div_ceil(every),
            ps.len(),
            load.trim()
        );
        return;
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let t = Instant::now();
    let ev =
        Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply).with_reduction(red);
    let grid = default_grid(reach_m(&model));
    let ps = grid.placements();
    let rows = pool.install(|| ev.sweep(&ps, &|_, _| {})).unwrap();
    let t_grid = t.elapsed().as_secs_f64();
    let feasible = rows.iter().filter(|r| r.cost().is_finite()).count();
    let span = |f: &dyn Fn(&printwatt::frame::Placement) -> f64| {
        ps.iter()
            .map(f)
            .fold([f64::INFINITY, f64::NEG_INFINITY], |r, v| {
                [r[0].min(v), r[1].max(v)]
            })
    };
    let bounds = Bounds {
        x: span(&|p| p.x),
        y: span(&|p| p.y),
        z: span(&|p| p.z),
    };
    let opts = OptimiseOptions {
        step_xy_m: (grid.xs[1] - grid.xs[0]).min(grid.ys[1] - grid.ys[0]) / 2.0,
        ..Default::default()
    };
    let so = SearchOptions {
        bounds,
        tolerance: Tolerance::default(),
        step_z_m: ((bounds.z[1] - bounds.z[0]) / 4.0).max(0.01),
        z: bounds.z[1] > bounds.z[0],
        max_start_cells: 20,
    };
    let (res, info) = pool
        .install(|| refine::refine(&ev, &rows, &opts, &so, std::sync::Arc::new(|_, _, _| {})))
        .unwrap();
    let t_search = t.elapsed().as_secs_f64();
    let est = res.best.clone();
    let (full, chk) = pool
        .install(|| reduce::confirm(&ev, &est))
        .unwrap()
        .expect("the answer is an estimate");
    let t_total = t.elapsed().as_secs_f64();
    let counts = ev.reduction().map(|r| r.counts()).unwrap_or_default();
    // One full and one reduced evaluation of the chosen placement on one thread, each timed
    // alone.
    let mut sc = ev.scratch().unwrap();
    let t1 = Instant::now();
    let again = ev.evaluate_full(&mut sc, &full.placement);
    let t_full = t1.elapsed().as_secs_f64();
    assert_eq!(again.cost(), full.cost());
    let t1 = Instant::now();
    let reduced = ev.evaluate(&mut sc, &full.placement);
    let t_reduced = t1.elapsed().as_secs_f64();
    assert_eq!(reduced.cost(), est.cost());
    let p = full.placement;
    println!(
        "grid {} placements ({} feasible) {:.1} s; refinement {} evaluations (+{} speculative) and {} tolerance corners {:.1} s; full re-evaluation of the answer {:.1} s",
        ps.len(),
        feasible,
        t_grid,
        res.evals,
        info.speculative_evals,
        info.tolerance_evals,
        t_search - t_grid,
        t_total - t_search
    );
    println!(
        "answer x = {:.3} m, y = {:.3} m, z = {:.3} m, yaw = {:.1}°, spin = {:.1}°",
        p.x,
        p.y,
        p.z,
        p.yaw.to_degrees(),
        p.nozzle_spin.to_degrees()
    );
    println!(
        "energy at the answer: full {:.0} J, estimate {:.0} J ± {:.0} J ({:+.4} %, {} the stated error; {} of {} layers evaluated)",
        chk.full_j,
        chk.estimate_j,
        chk.error_j,
        chk.difference_pct,
        if chk.within_error { "within" } else { "OUTSIDE" },
        chk.layers_evaluated,
        chk.summary.layers
    );
    println!(
        "| optimise, {layers}-layer wall, 2 threads | {:.1} s | one full evaluation, 1 thread, same run: {:.2} s | {:.1} |",
        t_total,
        t_full,
        t_total / t_full
    );
    println!(
        "evaluations: {} estimates, {} found infeasible by the reduced evaluation, {} evaluated in full ({} layers re-planned on their own in the estimates)",
        counts.estimates, counts.rejected, counts.full, counts.replanned_layers
    );
    println!(
        "the answer on 1 thread, same run: full evaluation {t_full:.2} s, reduced {t_reduced:.3} s ({:.1} %)",
        t_reduced / t_full * 100.0
    );
    println!(
        "{}",
        pinocchio::pass_line(
            &format!("optimise, {layers}-layer wall, 2 threads"),
            t_total,
            samples,
            &common::root()
                .join("robots")
                .join("abb_irb6700_200_260")
                .join("robot.urdf")
        )
    );
    println!(
        "load average at start: {}; at the end: {}",
        load.trim(),
        std::fs::read_to_string("/proc/loadavg")
            .unwrap_or_default()
            .trim()
    );
}
