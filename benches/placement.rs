//! Placement throughput on the default path (`paths/default.gcode`) and the shipped default
//! robot: placements per second, per-sample cost of the full placement evaluation
//! (time-parameterisation + IK + feasibility + RNEA + power) on one thread, as a ratio to a
//! bare RNEA call measured in the same run, and the projected time of the target:
//! a 50 × 50 grid on a 5,000-sample path (12.5 M path samples) on this machine's cores.
//!
//! It also measures, in the same run, the default grid with and without the prune before
//! tracking (`JointStageOptions::prune_stride`), per feasible and per infeasible placement.
//!
//! Run: `cargo bench --bench placement` (plain main, no criterion: prints a small table).

use printwatt::dynamics::rnea;
use printwatt::energy::EnergyOptions;
use printwatt::placement::feasibility::FeasibilityOptions;
use printwatt::placement::optimise::default_grid;
use printwatt::placement::{Evaluator, Objective, PathJob};
use printwatt::robot;
use printwatt::timing::{JointStageOptions, ProfileOptions};
use printwatt::toolpath::{self, Placement, ReadOptions};
use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let model = robot::load(&root.join("robots/abb_irb6700_200_260")).unwrap();
    let tp = toolpath::load(&root.join("paths/default.gcode"), &ReadOptions::default()).unwrap();
    let job = PathJob::new(
        &model,
        &tp,
        EnergyOptions::default(),
        ProfileOptions::default(),
        JointStageOptions::default(),
    )
    .unwrap();
    let n = model.dof();
    // Reference: bare RNEA on the samples of a real trajectory.
    // A feasible placement: the centre of the default grid's feasible region.
    let grid0 = {
        let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
        let ps = default_grid(printwatt::placement::feasibility::reach_m(&model)).placements();
        ev.sweep(&ps, &|_, _| {}).unwrap()
    };
    let at = printwatt::placement::optimise::feasible_centre(&grid0)
        .expect("a feasible grid cell")
        .placement;
    let full = job.evaluate(&at).unwrap().unwrap();
    let tr = &full.timed.traj;
    let m = tr.len();
    let mut data = job.energy.data();
    let mut tau = vec![0.0; n];
    let reps = 20;
    let t0 = Instant::now();
    for _ in 0..reps {
        for k in 0..m {
            rnea(
                job.energy.dynamics(),
                &mut data,
                tr.q(k),
                tr.qd(k),
                tr.qdd(k),
                &mut tau,
            )
            .unwrap();
            black_box(&tau);
        }
    }
    let rnea_ns = t0.elapsed().as_secs_f64() * 1e9 / (reps * m) as f64;

    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    let all = rayon::ThreadPoolBuilder::new()
        .num_threads(cores)
        .build()
        .unwrap();
    let per_sample = |feas: FeasibilityOptions| {
        let ev = Evaluator::new(&job, feas, Objective::Supply);
        let mut sc = ev.scratch().unwrap();
        let r = ev.evaluate(&mut sc, &at);
        let samples = r.feasible().expect("feasible").samples;
        let reps = 10;
        let t0 = Instant::now();
        for _ in 0..reps {
            black_box(ev.evaluate(&mut sc, &at));
        }
        (
            t0.elapsed().as_secs_f64() * 1e9 / (reps * samples) as f64,
            samples,
        )
    };
    let (full_ns, samples) = per_sample(FeasibilityOptions::default());
    let (nocoll_ns, _) = per_sample(FeasibilityOptions {
        collisions: false,
        ..Default::default()
    });
    // The unoptimised path for comparison: timing::time_at (plans per candidate) + evaluate
    // (series stored).
    let reps = 5;
    let t0 = Instant::now();
    for _ in 0..reps {
        black_box(job.evaluate(&at).unwrap().unwrap());
    }
    let slow_ns = t0.elapsed().as_secs_f64() * 1e9 / (reps * samples) as f64;

    // Throughput on the default workspace grid (mixed feasible / infeasible placements).
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let ps = default_grid(printwatt::placement::feasibility::reach_m(&model)).placements();
    let rate = |pool: &rayon::ThreadPool| {
        let t0 = Instant::now();
        let r = pool.install(|| ev.sweep(&ps, &|_, _| {})).unwrap();
        let s = t0.elapsed().as_secs_f64();
        (
            ps.len() as f64 / s,
            r.iter().filter(|e| e.cost().is_finite()).count(),
        )
    };
    let (rate1, feasible) = rate(&one);
    let (rate_all, _) = rate(&all);
    // Feasible-only throughput (every sample evaluated).
    let feas_ps: Vec<Placement> = grid0
        .iter()
        .filter(|e| e.cost().is_finite())
        .map(|e| e.placement)
        .take(16)
        .collect();
    let t0 = Instant::now();
    let _ = all.install(|| ev.sweep(&feas_ps, &|_, _| {})).unwrap();
    let feas_rate_all = feas_ps.len() as f64 / t0.elapsed().as_secs_f64();

    // Prune before tracking (issue 12 item 1): the same grid with and without pruning, one
    // thread, each placement timed alone and booked as feasible or infeasible.
    let job_unpruned = PathJob::new(
        &model,
        &tp,
        EnergyOptions::default(),
        ProfileOptions::default(),
        JointStageOptions {
            prune_stride: 0,
            ..Default::default()
        },
    )
    .unwrap();
    let per_kind = |ev: &Evaluator| {
        let mut sc = ev.scratch().unwrap();
        let (mut tf, mut nf, mut ti, mut ni) = (0.0, 0usize, 0.0, 0usize);
        for p in &ps {
            let t0 = Instant::now();
            let r = black_box(ev.evaluate(&mut sc, p));
            let s = t0.elapsed().as_secs_f64();
            if r.cost().is_finite() {
                tf += s;
                nf += 1;
            } else {
                ti += s;
                ni += 1;
            }
        }
        (tf, nf, ti, ni)
    };
    let ev_u = Evaluator::new(
        &job_unpruned,
        FeasibilityOptions::default(),
        Objective::Supply,
    );
    let (pf, pnf, pi, pni) = per_kind(&ev);
    let (uf, unf, ui, uni) = per_kind(&ev_u);
    assert_eq!((pnf, pni), (unf, uni), "pruning changed a verdict");

    let target = 50.0 * 50.0 * 5000.0;
    println!("printwatt placement bench ({} cores)", cores);
    println!("  path samples (feasible placement)       {samples}");
    println!("  bare RNEA (reference)                   {rnea_ns:9.1} ns/sample   1.00x");
    println!(
        "  full placement eval, 1 thread           {full_ns:9.1} ns/sample  {:5.2}x RNEA",
        full_ns / rnea_ns
    );
    println!(
        "    of which without collision checks     {nocoll_ns:9.1} ns/sample  {:5.2}x RNEA",
        nocoll_ns / rnea_ns
    );
    println!(
        "  time_at + energy::evaluate (unoptimised){slow_ns:9.1} ns/sample  {:5.2}x RNEA ({:.2}x the fast path)",
        slow_ns / rnea_ns,
        slow_ns / full_ns
    );
    println!(
        "  default grid ({} placements, {feasible} feasible): {rate1:.0} placements/s on 1 thread, {rate_all:.0} on {cores}",
        ps.len()
    );
    println!("  feasible placements only: {feas_rate_all:.1} placements/s on {cores} threads");
    println!(
        "  prune before tracking, default grid on 1 thread ({pnf} feasible, {pni} infeasible):"
    );
    println!(
        "    pruned:   grid {:.3} s; feasible {:.2} ms each, infeasible {:.3} ms each ({:.1} % of a feasible one); infeasible share of grid time {:.0} %",
        pf + pi,
        pf / pnf.max(1) as f64 * 1e3,
        pi / pni.max(1) as f64 * 1e3,
        (pi / pni.max(1) as f64) / (pf / pnf.max(1) as f64) * 100.0,
        pi / (pf + pi) * 100.0
    );
    println!(
        "    unpruned: grid {:.3} s; feasible {:.2} ms each, infeasible {:.3} ms each ({:.1} % of a feasible one); infeasible share of grid time {:.0} %",
        uf + ui,
        uf / unf.max(1) as f64 * 1e3,
        ui / uni.max(1) as f64 * 1e3,
        (ui / uni.max(1) as f64) / (uf / unf.max(1) as f64) * 100.0,
        ui / (uf + ui) * 100.0
    );
    println!(
        "    pruned / unpruned grid time: {:.3} ({:.2}x faster); infeasible placements {:.1}x faster",
        (pf + pi) / (uf + ui),
        (uf + ui) / (pf + pi),
        ui / pi
    );
    println!(
        "  projected 50x50 grid x 5000 samples (12.5 M samples, all feasible): {:.1} s on 1 thread, {:.1} s on {cores} (ideal scaling); target 10 s",
        target * full_ns * 1e-9,
        target * full_ns * 1e-9 / cores as f64
    );
}
