//! Placement throughput on the default path (`paths/default.gcode`) and the shipped default
//! robot: placements per second, per-sample cost of the full placement evaluation
//! (time-parameterisation + IK + feasibility + RNEA + power) on one thread, as a ratio to a
//! bare RNEA call measured in the same run, and the projected time of the target:
//! a 50 × 50 grid on a 5,000-sample path (12.5 M path samples) on this machine's cores.
//!
//! It also measures, in the same run, the default grid with and without the prune before
//! tracking (`JointStageOptions::prune_stride`), per feasible and per infeasible placement.
//!
//! Before/after of the fast elementary functions (`printwatt::fastmath`, issue 12 item 2) in
//! the same run: every per-sample figure is measured with libm's functions
//! (`fastmath::set_libm(true)`; the sines computed once per sample and the reused buffers
//! apply to both) and with the fast path, interleaved round by round so that a load
//! spike hits both alike, and reported as the median of the rounds, each as a ratio to the
//! bare RNEA **with libm** measured in the same rounds (the reference the earlier figures
//! used). The projection of the target (50 × 50 placements × 5,000 samples) is made
//! from a measured sweep of feasible placements on all cores, for both paths.
//!
//! Single-thread figures are this thread's on-CPU time (`CLOCK_THREAD_CPUTIME_ID`), so
//! that other processes sharing the cores do not inflate them; the sweep on all cores is
//! wall-clock time and is only meaningful on an otherwise idle machine.
//!
//! Run: `cargo bench --bench placement` (plain main, no criterion: prints a small table).
//! The load average is printed: figures from a loaded machine are not idle figures, but the
//! ratios of one run survive load.

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

/// This thread's time on a CPU, ns (`clock_gettime(CLOCK_THREAD_CPUTIME_ID)`), so that the
/// single-thread figures do not count the time other processes hold the CPU (the scheduler's
/// `/proc/thread-self/schedstat` is only updated at ticks: too coarse for a few ms).
fn thread_ns() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the clock id is a constant the call accepts.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed");
    ts.tv_sec as f64 * 1e9 + ts.tv_nsec as f64
}

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
    let mut rnea_pass = || {
        let reps = 5;
        let t0 = thread_ns();
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
        (thread_ns() - t0) / (reps * m) as f64
    };

    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    let all = rayon::ThreadPoolBuilder::new()
        .num_threads(cores)
        .build()
        .unwrap();
    let ev_full = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let ev_nocoll = Evaluator::new(
        &job,
        FeasibilityOptions {
            collisions: false,
            ..Default::default()
        },
        Objective::Supply,
    );
    let samples = ev_full
        .evaluate(&mut ev_full.scratch().unwrap(), &at)
        .feasible()
        .expect("feasible")
        .samples;
    let per_sample = |ev: &Evaluator| {
        let mut sc = ev.scratch().unwrap();
        black_box(ev.evaluate(&mut sc, &at));
        let reps = 3;
        let t0 = thread_ns();
        for _ in 0..reps {
            black_box(ev.evaluate(&mut sc, &at));
        }
        (thread_ns() - t0) / (reps * samples) as f64
    };
    // Feasible placements of the default grid (every sample evaluated), swept on all cores.
    let feas_ps: Vec<Placement> = grid0
        .iter()
        .filter(|e| e.cost().is_finite())
        .map(|e| e.placement)
        .take(16)
        .collect();
    let sweep_ns = |ev: &Evaluator| {
        let t0 = Instant::now();
        let r = all.install(|| ev.sweep(&feas_ps, &|_, _| {})).unwrap();
        let s: usize = r
            .iter()
            .filter_map(|e| e.feasible())
            .map(|f| f.samples)
            .sum();
        t0.elapsed().as_secs_f64() * 1e9 / s as f64
    };
    // Before (libm) and after (fast), interleaved; the answers must agree to the stated
    // tolerance of the fast functions (a few ulp, amplified by the integration: 1e-9 relative).
    let (mut e_libm, mut e_fast) = (0.0, 0.0);
    for (libm, e) in [(true, &mut e_libm), (false, &mut e_fast)] {
        printwatt::fastmath::set_libm(libm);
        *e = ev_full
            .evaluate(&mut ev_full.scratch().unwrap(), &at)
            .cost();
    }
    assert!(
        ((e_fast - e_libm) / e_libm).abs() < 1e-9,
        "fast and libm energies differ: {e_fast} vs {e_libm} J"
    );
    let rounds = 7;
    let mut t: [[Vec<f64>; 2]; 4] = Default::default();
    for _ in 0..rounds {
        for (i, libm) in [true, false].into_iter().enumerate() {
            printwatt::fastmath::set_libm(libm);
            t[0][i].push(rnea_pass());
            t[1][i].push(per_sample(&ev_full));
            t[2][i].push(per_sample(&ev_nocoll));
            t[3][i].push(sweep_ns(&ev_full));
        }
    }
    printwatt::fastmath::set_libm(false);
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let mut med = [[0.0; 2]; 4];
    for (row, ts) in med.iter_mut().zip(t.iter_mut()) {
        for (cell, v) in row.iter_mut().zip(ts.iter_mut()) {
            *cell = median(v);
        }
    }
    let rnea_ns = med[0][0];
    let full_ns = med[1][1];

    // The unoptimised path for comparison: timing::time_at (plans per candidate) + evaluate
    // (series stored).
    let reps = 5;
    let t0 = thread_ns();
    for _ in 0..reps {
        black_box(job.evaluate(&at).unwrap().unwrap());
    }
    let slow_ns = (thread_ns() - t0) / (reps * samples) as f64;

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
            let t0 = thread_ns();
            let r = black_box(ev.evaluate(&mut sc, p));
            let s = (thread_ns() - t0) * 1e-9;
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
    let load = || std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!("printwatt placement bench ({} cores)", cores);
    println!(
        "  load average (1, 5, 15 min) at the end: {}",
        load().trim()
    );
    println!("  path samples (feasible placement)       {samples}");
    println!(
        "  before (libm) and after (fastmath), median of {rounds} interleaved rounds, on-CPU time; ratios to bare RNEA with libm:"
    );
    println!("                                              libm                      fast      fast/libm");
    let names = [
        "bare RNEA",
        "full placement eval, 1 thread",
        "  without collision checks",
        &format!("feasible sweep, {cores} threads, wall/sample"),
    ];
    for (name, [l, f]) in names.iter().zip(med) {
        println!(
            "  {name:<38} {l:8.1} ns {:5.2}x    {f:8.1} ns {:5.2}x    {:5.3}",
            l / rnea_ns,
            f / rnea_ns,
            f / l
        );
    }
    println!(
        "  projected 50x50 grid x 5000 samples (12.5 M samples, all feasible) on {cores} threads, from the measured sweep (wall): libm {:.2} s, fast {:.2} s ({:.2}x faster); target 1 s",
        target * med[3][0] * 1e-9,
        target * med[3][1] * 1e-9,
        med[3][0] / med[3][1]
    );
    println!(
        "    from 1 thread's on-CPU time x ideal scaling: libm {:.2} s, fast {:.2} s",
        target * med[1][0] * 1e-9 / cores as f64,
        target * full_ns * 1e-9 / cores as f64
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
    println!(
        "  prune before tracking, default grid on 1 thread, on-CPU time ({pnf} feasible, {pni} infeasible):"
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
}
