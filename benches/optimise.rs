//! `printwatt optimise` on the main job (shipped IRB 6700, `paths/default.gcode`, the default
//! grid, Nelder–Mead with 120 evaluations, ±20 mm / ±1° tolerance) on all cores, split into
//! its phases, with the refinement's tolerance checks made two ways in the same run:
//!
//! - **fast** ([`search::refine`]): a check stops at the first infeasible corner, the corner
//!   that failed last is tried first, as many corners are evaluated at once as there are
//!   threads, nothing is evaluated twice, and the bisection and spin points are evaluated
//!   together with their first corners;
//! - **plain** ([`search::refine_plain`]): the checks as they were before (batches of 4
//!   corners, stopping after a batch with an infeasible one; every placement evaluated each
//!   time it is asked for).
//!
//! Both give the same answer bit for bit (asserted here, tested in
//! `tests/placement_search.rs`). Printed: the grid's wall time, each refinement's wall time
//! (median of interleaved rounds), its evaluations and their ratio; one feasible evaluation
//! on one thread (on-CPU time) as the unit; the load average.
//!
//! Run: `cargo bench --bench optimise` (plain main, no criterion). The end-to-end figure
//! against an older binary is measured with the binaries themselves (README, Performance).

#[path = "common/pinocchio.rs"]
mod pinocchio;

#[path = "common/clock.rs"]
mod clock;
#[path = "../tests/common/mod.rs"]
mod common;

use clock::thread_s;

use printwatt::evaluate::feasibility::{reach_m, FeasibilityOptions};
use printwatt::evaluate::{Evaluator, Objective};
use printwatt::search::optimise::{default_grid, OptimiseOptions};
use printwatt::search::refine::{self, Bounds, SearchOptions};
use printwatt::search::tolerance::Tolerance;
use std::time::Instant;

fn main() {
    let model = common::robot("abb_irb6700_200_260");
    let tp = common::path("default.gcode");
    let job = common::default_job(&model, &tp);
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let g = default_grid(reach_m(&model));
    let ps = g.placements();
    let span = |v: &[f64]| [v[0], v[v.len() - 1]];
    // The CLI's defaults (src/cli/optimise.rs).
    let so = SearchOptions {
        bounds: Bounds {
            x: span(&g.xs),
            y: span(&g.ys),
            z: span(&g.zs),
        },
        tolerance: Tolerance::default(),
        step_z_m: ((g.zs[g.zs.len() - 1] - g.zs[0]) / 4.0).max(0.01),
        z: true,
        max_start_cells: 20,
    };
    let opts = OptimiseOptions {
        step_xy_m: (g.xs[1] - g.xs[0]).min(g.ys[1] - g.ys[0]) / 2.0,
        ..Default::default()
    };
    let quiet = || std::sync::Arc::new(|_, _, _| {}) as refine::Progress;

    // The grid, on all cores.
    let t = Instant::now();
    let grid = ev.sweep(&ps, &|_, _| {}).unwrap();
    let t_grid = t.elapsed().as_secs_f64();
    let feasible: Vec<_> = grid.iter().filter(|e| e.cost().is_finite()).collect();

    // The unit: one feasible evaluation on one thread.
    let at = feasible[0].placement;
    let mut sc = ev.scratch().unwrap();
    ev.evaluate(&mut sc, &at);
    let t0 = thread_s();
    for _ in 0..5 {
        std::hint::black_box(ev.evaluate(&mut sc, &at));
    }
    let t_one = (thread_s() - t0) / 5.0;

    // The refinement both ways, interleaved.
    let rounds = 3;
    let (mut t_fast, mut t_plain) = (Vec::new(), Vec::new());
    let mut fast = None;
    let mut plain = None;
    for _ in 0..rounds {
        let t = Instant::now();
        let r = refine::refine(&ev, &grid, &opts, &so, quiet()).unwrap();
        t_fast.push(t.elapsed().as_secs_f64());
        fast = Some(r);
        let t = Instant::now();
        let r = refine::refine_plain(&ev, &grid, &opts, &so, quiet()).unwrap();
        t_plain.push(t.elapsed().as_secs_f64());
        plain = Some(r);
    }
    let ((fr, fi), (pr, pi)) = (fast.unwrap(), plain.unwrap());
    assert_eq!(fr.best, pr.best, "the same answer");
    assert_eq!(
        fi.tolerance, pi.tolerance,
        "the same tolerance check of the answer"
    );
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (mf, mp) = (median(&mut t_fast), median(&mut t_plain));
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    let threads = rayon::current_num_threads();
    let b = fr.best.placement;
    println!("printwatt optimise bench: the main job on {threads} threads");
    println!("  load average (1, 5, 15 min) at the end: {}", load.trim());
    println!(
        "  answer: x = {:.3} m, y = {:.3} m, z = {:.3} m, yaw = {:.1}°, spin = {:.1}°: {:.1} J",
        b.x,
        b.y,
        b.z,
        b.yaw.to_degrees(),
        b.nozzle_spin.to_degrees(),
        fr.best.cost()
    );
    println!(
        "  one feasible evaluation, 1 thread (on-CPU): {:.2} ms",
        t_one * 1e3
    );
    println!(
        "  grid: {} placements ({} feasible) in {:.3} s wall ({:.0} feasible-evaluation times)",
        ps.len(),
        feasible.len(),
        t_grid,
        t_grid / t_one
    );
    for (name, t, r, i) in [("fast ", mf, &fr, &fi), ("plain", mp, &pr, &pi)] {
        println!(
            "  refinement, {name} checks: {:.3} s wall (median of {rounds}; {:.0} evaluation times): Nelder–Mead {} + tolerance and spin {} evaluations, {} speculative; sensitivity 4",
            t,
            t / t_one,
            r.evals,
            i.tolerance_evals,
            i.speculative_evals
        );
    }
    println!(
        "  fast / plain refinement: {:.3} wall ({:.2}x faster); grid + refinement: {:.3} s against {:.3} s ({:.2}x)",
        mf / mp,
        mp / mf,
        t_grid + mf,
        t_grid + mp,
        (t_grid + mp) / (t_grid + mf)
    );
    println!(
        "{}",
        pinocchio::pass_line(
            "grid + refinement (fast checks)",
            t_grid + mf,
            job.plan.motion.p.len(),
            &common::root()
                .join("robots")
                .join("abb_irb6700_200_260")
                .join("robot.urdf")
        )
    );
}
