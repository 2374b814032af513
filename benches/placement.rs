//! Placement throughput on the default path (`paths/default.gcode`) and the shipped default
//! robot: placements per second, per-sample cost of the full placement evaluation
//! (time-parameterisation + IK + feasibility + RNEA + power) on one thread, as a ratio to a
//! bare RNEA call measured in the same run, and the projected time of the target:
//! a 50 × 50 grid on a 5,000-sample path (12.5 M path samples) on this machine's cores.
//!
//! It also measures, in the same run, the default grid with and without the prune before
//! tracking (`JointStageOptions::prune_stride`), per feasible and per infeasible placement.
//!
//! Before/after of the fast elementary functions (`printwatt::fastmath`) in
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

#[path = "common/pinocchio.rs"]
mod pinocchio;

#[path = "common/clock.rs"]
mod clock;
#[path = "../tests/common/mod.rs"]
mod common;

use clock::{clock_ghz, fma_rate, thread_ns};

use printwatt::dynamics::{rnea, rnea_batch, rnea_with_sincos, StateBatch, MAX_DOF};
use printwatt::energy::{self, EnergyOptions, SamplePower};
use printwatt::evaluate::feasibility::FeasibilityOptions;
use printwatt::evaluate::{Evaluator, Objective, PathJob};
use printwatt::search::optimise::default_grid;
use printwatt::simd::{self, Level, LANES};
use printwatt::timing::{JointStageOptions, ProfileOptions};
use printwatt::toolpath::Placement;
use std::hint::black_box;
use std::time::Instant;

/// Flops (one add, subtract or multiply each; no FMA) of one revolute link in the batched
/// RNEA kernel (`src/dynamics/batch.rs`), counted from its code: joint rotation 18, origin
/// acceleration 33, angular velocity 16 and acceleration 23, link acceleration 15, `I ω` 15,
/// force 36, moment 39, torque 2, backward propagation to the parent 48.
const RNEA_FLOPS_PER_LINK: f64 = 18.0 + 33.0 + 16.0 + 23.0 + 15.0 + 15.0 + 36.0 + 39.0 + 2.0 + 48.0;
/// Of which the backward propagation to the parent, which the first link does not do.
const RNEA_BACKWARD_FLOPS: f64 = 48.0;
/// The earlier estimate's other terms (README): IK closed form and FK
/// re-check, energy terms, timing, per-sample checks, flops per sample.
const FLOPS_IK: f64 = 650.0;
/// See [`FLOPS_IK`].
const FLOPS_ENERGY: f64 = 150.0;
/// See [`FLOPS_IK`].
const FLOPS_TIMING: f64 = 100.0;
/// See [`FLOPS_IK`].
const FLOPS_CHECKS: f64 = 50.0;

fn main() {
    let model = common::robot("abb_irb6700_200_260");
    let tp = common::path("default.gcode");
    let job = common::default_job(&model, &tp);
    let n = model.dof();
    // Reference: bare RNEA on the samples of a real trajectory.
    // A feasible placement: the centre of the default grid's feasible region.
    let grid0 = {
        let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
        let ps = default_grid(printwatt::evaluate::feasibility::reach_m(&model)).placements();
        ev.sweep(&ps, &|_, _| {}).unwrap()
    };
    let at = printwatt::search::optimise::feasible_centre(&grid0)
        .expect("a feasible grid cell")
        .placement;
    let full = job.evaluate(&at).unwrap().unwrap();
    let tr = &full.timed.traj;
    let m = tr.len();
    let mut data = job.energy.data();
    let mut tau = vec![0.0; n];

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
    // In a one-thread pool: an evaluation runs its checks and its energy pass with
    // rayon::join, which would otherwise hand one of them to another thread, whose time this
    // thread's clock does not see.
    let per_sample = |ev: &Evaluator| {
        one.install(|| {
            let mut sc = ev.scratch().unwrap();
            black_box(ev.evaluate(&mut sc, &at));
            let reps = 3;
            let t0 = thread_ns();
            for _ in 0..reps {
                black_box(ev.evaluate(&mut sc, &at));
            }
            (thread_ns() - t0) / (reps * samples) as f64
        })
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
    // Configurations measured in the same run, interleaved round by round: libm's functions
    // on the scalar path (the earlier reference), the fast functions on the scalar path, and
    // the fast functions with the lockstep batches on every SIMD level this CPU runs.
    let levels: Vec<Level> = [Level::Sse2, Level::Avx2, Level::Avx512]
        .into_iter()
        .filter(|l| l.available())
        .collect();
    let mut configs = vec![(true, Level::Scalar), (false, Level::Scalar)];
    configs.extend(levels.iter().map(|&l| (false, l)));
    let set = |(libm, level): (bool, Level)| {
        printwatt::fastmath::set_libm(libm);
        assert!(simd::set_level(level));
    };
    // The answers agree: fast and libm to the fast functions' stated tolerance (a few ulp,
    // amplified by the integration: 1e-9 relative); every SIMD level equals the scalar path
    // bit for bit (its stated tolerance is 0).
    let energies: Vec<f64> = configs
        .iter()
        .map(|&c| {
            set(c);
            ev_full
                .evaluate(&mut ev_full.scratch().unwrap(), &at)
                .cost()
        })
        .collect();
    assert!(
        ((energies[1] - energies[0]) / energies[0]).abs() < 1e-9,
        "fast and libm energies differ: {} vs {} J",
        energies[1],
        energies[0]
    );
    for (e, c) in energies.iter().zip(&configs).skip(2) {
        assert_eq!(
            e.to_bits(),
            energies[1].to_bits(),
            "{c:?} differs from scalar"
        );
    }
    // Bare RNEA and the energy pass (RNEA + effects + motor + supply) of the trajectory's
    // samples, per sample, with the sines given (as the IK gives them).
    let sincos: Vec<f64> = (0..m)
        .flat_map(|k| {
            let q = tr.q(k);
            let (s, c): (Vec<f64>, Vec<f64>) =
                q.iter().map(|&a| printwatt::fastmath::sin_cos(a)).unzip();
            s.into_iter().chain(c)
        })
        .collect();
    let sc = |k: usize| &sincos[k * 2 * n..(k + 1) * 2 * n];
    let mut data2 = job.energy.data();
    let mut rnea_pass = |(libm, level): (bool, Level)| {
        let reps = 5;
        let t0 = thread_ns();
        for _ in 0..reps {
            if level != Level::Scalar {
                let mut t = [[0.0; LANES]; MAX_DOF];
                for k0 in (0..m).step_by(LANES) {
                    let mut b = StateBatch::default();
                    for l in 0..LANES.min(m - k0) {
                        b.set(l, n, sc(k0 + l), tr.qd(k0 + l), tr.qdd(k0 + l));
                    }
                    rnea_batch(job.energy.dynamics(), &b, &mut t, level);
                    black_box(&t);
                }
                continue;
            }
            for k in 0..m {
                if libm {
                    rnea(
                        job.energy.dynamics(),
                        &mut data,
                        tr.q(k),
                        tr.qd(k),
                        tr.qdd(k),
                        &mut tau,
                    )
                } else {
                    rnea_with_sincos(
                        job.energy.dynamics(),
                        &mut data,
                        tr.q(k),
                        sc(k),
                        tr.qd(k),
                        tr.qdd(k),
                        &mut tau,
                    )
                }
                .unwrap();
                black_box(&tau);
            }
        }
        (thread_ns() - t0) / (reps * m) as f64
    };
    let mut energy_pass = |(_, level): (bool, Level)| {
        let reps = 5;
        let mut out = [SamplePower::default(); LANES];
        let mut lanes = energy::PowerLanes::default();
        let mut inputs = energy::LaneInputs::default();
        let t0 = thread_ns();
        for _ in 0..reps {
            for k0 in (0..m).step_by(LANES) {
                if level != Level::Scalar {
                    // What the sweep runs: the structure-of-arrays pass over the trajectory's
                    // rows (without the integration's sums).
                    let rows = energy::Rows {
                        q: &tr.q[k0 * n..],
                        sincos: Some(&sincos[k0 * 2 * n..]),
                        qd: &tr.qd[k0 * n..],
                        qdd: &tr.qdd[k0 * n..],
                    };
                    energy::eval_rows(
                        &job.energy,
                        &mut data2,
                        LANES.min(m - k0),
                        &rows,
                        &mut inputs,
                        &mut lanes,
                        level,
                    )
                    .unwrap();
                    black_box(&lanes);
                    continue;
                }
                energy::eval_batch_with_sincos(
                    &job.energy,
                    &mut data2,
                    LANES.min(m - k0),
                    |l| tr.q(k0 + l),
                    |l| sc(k0 + l),
                    |l| tr.qd(k0 + l),
                    |l| tr.qdd(k0 + l),
                    &mut out,
                    level,
                )
                .unwrap();
                black_box(&out);
            }
        }
        (thread_ns() - t0) / (reps * m) as f64
    };
    let rounds = 7;
    let nc = configs.len();
    let mut t: Vec<Vec<Vec<f64>>> = vec![vec![Vec::new(); nc]; 5];
    for _ in 0..rounds {
        for (i, &c) in configs.iter().enumerate() {
            set(c);
            t[0][i].push(rnea_pass(c));
            t[1][i].push(energy_pass(c));
            t[2][i].push(per_sample(&ev_full));
            t[3][i].push(per_sample(&ev_nocoll));
            t[4][i].push(sweep_ns(&ev_full));
        }
    }
    printwatt::fastmath::set_libm(false);
    simd::set_level(simd::detected());
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let med: Vec<Vec<f64>> = t
        .iter_mut()
        .map(|row| row.iter_mut().map(median).collect())
        .collect();
    let rnea_ns = med[0][0];
    let best = nc - 1; // the best SIMD level this CPU runs
    let full_ns = med[2][best];

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
    let ps = default_grid(printwatt::evaluate::feasibility::reach_m(&model)).placements();
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

    // Prune before tracking: the same grid with and without pruning, one
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
    let names: Vec<String> = configs
        .iter()
        .map(|&(libm, l)| match (libm, l) {
            (true, _) => "libm scalar".to_string(),
            (false, Level::Scalar) => "scalar".to_string(),
            (false, l) => l.name().to_string(),
        })
        .collect();
    println!(
        "  median of {rounds} interleaved rounds, on-CPU time except the sweep; columns: libm's functions on the scalar path, the fast functions on the scalar path, and the lockstep batches of {LANES} samples on each SIMD level (bit-identical to scalar); (x) = time / scalar"
    );
    print!("  {:<44}", "ns per sample");
    for nm in &names {
        print!("{nm:>18}");
    }
    println!();
    let rows = [
        "bare RNEA (sines given; libm: computed)",
        "RNEA + effects + motor + supply",
        "full placement eval, 1 thread",
        "  without collision checks",
        &format!("feasible sweep, {cores} threads, wall"),
    ];
    for (name, row) in rows.iter().zip(&med) {
        print!("  {name:<44}");
        for v in row {
            print!("{:>10.1} ({:4.2})", v, v / row[1]);
        }
        println!();
    }
    println!(
        "  projected 50x50 grid x 5000 samples (12.5 M samples, all feasible) on {cores} threads, from the measured sweep (wall): scalar {:.2} s, {} {:.2} s ({:.2}x faster); target 1 s",
        target * med[4][1] * 1e-9,
        names[best],
        target * med[4][best] * 1e-9,
        med[4][1] / med[4][best]
    );
    println!(
        "    from 1 thread's on-CPU time x ideal scaling: libm scalar {:.2} s, scalar {:.2} s, {} {:.2} s",
        target * med[2][0] * 1e-9 / cores as f64,
        target * med[2][1] * 1e-9 / cores as f64,
        names[best],
        target * full_ns * 1e-9 / cores as f64
    );
    // The SIMD floor: flops per sample over the attainable vector rate, both measured: the
    // clock by a chain of dependent multiplies, the vector rate by independent FMA chains
    // (an FMA counted as two flops: the rate of separate multiplies and adds where the
    // adders match the FMA pipes). The floor takes half of that peak, as the earlier
    // estimate did.
    let ghz = clock_ghz(200_000_000);
    let flops_rnea = RNEA_FLOPS_PER_LINK * n as f64 - RNEA_BACKWARD_FLOPS;
    let flops = flops_rnea + FLOPS_IK + FLOPS_ENERGY + FLOPS_TIMING + FLOPS_CHECKS;
    println!(
        "  clock measured by a chain of dependent integer multiplies (3 cycles each): {ghz:.2} GHz"
    );
    match fma_rate(20_000_000, ghz) {
        Some(fma) => {
            let peak = fma.flops_per_cycle();
            let floor_ns = flops / (0.5 * peak) / ghz;
            println!(
                "  vector FMA rate measured by 12 independent chains: {:.2} FMAs/cycle x {} f64 lanes = {peak:.1} flops/cycle",
                fma.per_cycle, fma.lanes
            );
            println!(
                "  SIMD floor: {flops:.0} flops/sample (RNEA {flops_rnea:.0} counted in the batched kernel, IK {FLOPS_IK:.0}, energy {FLOPS_ENERGY:.0}, timing {FLOPS_TIMING:.0}, checks {FLOPS_CHECKS:.0}) / (half of {peak:.1} flops/cycle x {ghz:.2} GHz) = {floor_ns:.1} ns/sample; 50x50x5000 on {cores} cores at the floor: {:.2} s",
                target * floor_ns * 1e-9 / cores as f64
            );
            println!(
                "  full evaluation ({}) / floor: {:.1}x (target <= 3x); scalar / floor: {:.1}x",
                names[best],
                full_ns / floor_ns,
                med[2][1] / floor_ns
            );
        }
        None => println!("  SIMD floor: not measured (no AVX2 + FMA on this CPU)"),
    }
    println!(
        "  batched RNEA attains {:.1} flops/cycle ({}), scalar RNEA {:.1}",
        flops_rnea / (med[0][best] * ghz),
        names[best],
        flops_rnea / (med[0][1] * ghz)
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
    // The reference: Pinocchio's RNEA on the same robot, timed now.
    let urdf = common::root()
        .join("robots")
        .join("abb_irb6700_200_260")
        .join("robot.urdf");
    println!(
        "{}",
        pinocchio::ratio_line(
            &format!("full placement evaluation, 1 thread, {}", names[best]),
            full_ns,
            &urdf
        )
    );
    println!(
        "{}",
        pinocchio::ratio_line(
            &format!("feasible sweep, {cores} threads, wall, {}", names[best]),
            med[4][best],
            &urdf
        )
    );
}
