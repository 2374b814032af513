//! The lockstep energy pass alone (`energy::eval_rows_summed`: transposition, RNEA, the torque
//! effects, the motor model, the supply and the trapezoid sums, 8 samples per call) on the
//! trajectory of the placement bench's feasible placement (the default robot and path, the
//! centre of the default grid's feasible region), per level the CPU has: ns per sample and,
//! with the core clock measured in the same run, cycles per sample. The sines are the ones
//! the IK shares (computed here by `fastmath::sin_cos`, bit for bit the same).
//!
//! Times are this thread's on-CPU time (`CLOCK_THREAD_CPUTIME_ID`); the levels are
//! interleaved round by round and the median of the rounds is printed, with the load
//! average. To compare two builds, run their binaries alternately at a quiet moment.
//!
//! For scale, the lockstep RNEA alone (`dynamics::rnea_batch` of the same full batches, their
//! states transposed beforehand) is timed in the same rounds.
//!
//! Run: `cargo bench --bench energy_pass` (plain main, no criterion: prints a small table).

#[path = "common/clock.rs"]
mod clock;
#[path = "../tests/common/mod.rs"]
mod common;

use clock::{clock_ghz, thread_ns};

use printwatt::dynamics::{rnea_batch, StateBatch, MAX_DOF};
use printwatt::energy::{self, EnergySums, LaneInputs, PowerLanes, Rows};
use printwatt::evaluate::feasibility::FeasibilityOptions;
use printwatt::evaluate::{Evaluator, Objective};
use printwatt::search::optimise::{default_grid, feasible_centre};
use printwatt::simd::{Level, LANES};
use std::hint::black_box;

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let model = common::robot("abb_irb6700_200_260");
    let tp = common::path("default.gcode");
    let job = common::default_job(&model, &tp);
    let n = model.dof();
    let at = match std::env::var("PRINTWATT_PLACEMENT") {
        Ok(s) => printwatt::toolpath::Placement::parse(&s).expect("x,y,z,yaw"),
        Err(_) => {
            let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
            let ps = default_grid(printwatt::evaluate::feasibility::reach_m(&model)).placements();
            let grid = ev.sweep(&ps, &|_, _| {}).unwrap();
            feasible_centre(&grid)
                .expect("a feasible grid cell")
                .placement
        }
    };
    let full = job.evaluate(&at).unwrap().unwrap();
    let tr = &full.timed.traj;
    let m = tr.len();
    let dt = full.timed.motion.dt;
    let mut sincos = vec![0.0; m * 2 * n];
    for k in 0..m {
        for j in 0..n {
            let (s, c) = printwatt::fastmath::sin_cos(tr.q[k * n + j]);
            sincos[k * 2 * n + j] = s;
            sincos[k * 2 * n + n + j] = c;
        }
    }
    let mut data = job.energy.data();
    let levels: Vec<Level> = [Level::Avx512, Level::Avx2]
        .into_iter()
        .filter(|l| l.available())
        .collect();
    // One pass over the whole trajectory on `level`: ns per sample, and the supply energy.
    let mut pass = |level: Level| -> (f64, f64) {
        let mut sums = EnergySums::default();
        let mut pl = PowerLanes::default();
        let mut inputs = LaneInputs::default();
        let t0 = thread_ns();
        for k0 in (0..m).step_by(LANES) {
            let count = LANES.min(m - k0);
            let r = Rows {
                q: &tr.q[k0 * n..],
                sincos: Some(&sincos[k0 * 2 * n..]),
                qd: &tr.qd[k0 * n..],
                qdd: &tr.qdd[k0 * n..],
            };
            let w = [dt; LANES];
            energy::eval_rows_summed(
                &job.energy,
                &mut data,
                count,
                black_box(&r),
                &mut inputs,
                &mut pl,
                &mut sums,
                &w,
                level,
            )
            .unwrap();
        }
        let ns = (thread_ns() - t0) / m as f64;
        (ns, EnergySums::lanes_total(black_box(&sums.supply)))
    };
    // The same samples' full batches as StateBatches, for RNEA alone.
    let batches: Vec<StateBatch> = (0..m / LANES)
        .map(|b| {
            let mut sb = StateBatch::default();
            for l in 0..LANES {
                let k = b * LANES + l;
                sb.set(
                    l,
                    n,
                    &sincos[k * 2 * n..(k + 1) * 2 * n],
                    &tr.qd[k * n..(k + 1) * n],
                    &tr.qdd[k * n..(k + 1) * n],
                );
            }
            sb
        })
        .collect();
    let rnea_only = |level: Level| -> f64 {
        let mut tau = [[0.0; LANES]; MAX_DOF];
        let t0 = thread_ns();
        for b in &batches {
            rnea_batch(job.energy.dynamics(), black_box(b), &mut tau, level);
            black_box(&tau);
        }
        (thread_ns() - t0) / (batches.len() * LANES) as f64
    };
    for &l in &levels {
        for _ in 0..20 {
            pass(l);
            rnea_only(l);
        }
    }
    let rounds = 60;
    let mut per: Vec<Vec<f64>> = vec![Vec::new(); levels.len()];
    let mut per_rnea: Vec<Vec<f64>> = vec![Vec::new(); levels.len()];
    let mut supply = vec![0.0; levels.len()];
    let mut ghz = Vec::new();
    for r in 0..rounds {
        if r % 10 == 0 {
            ghz.push(clock_ghz(100_000_000));
        }
        for (i, &l) in levels.iter().enumerate() {
            let mut best = f64::INFINITY;
            for _ in 0..5 {
                let (ns, e) = pass(l);
                best = best.min(ns);
                supply[i] = e;
            }
            per[i].push(best);
            let mut best = f64::INFINITY;
            for _ in 0..5 {
                best = best.min(rnea_only(l));
            }
            per_rnea[i].push(best);
        }
    }
    let ghz = median(&mut ghz);
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "energy pass, {m} samples at ({}, {}, {}) m, yaw {} rad; clock {ghz:.2} GHz; load {}",
        at.x,
        at.y,
        at.z,
        at.yaw,
        load.split_whitespace()
            .take(3)
            .collect::<Vec<_>>()
            .join(" ")
    );
    for (i, l) in levels.iter().enumerate() {
        let ns = median(&mut per[i]);
        let r = median(&mut per_rnea[i]);
        println!(
            "  {:<7} {ns:7.2} ns/sample  {:7.1} cycles/sample  (supply {:.6e} J); RNEA alone {r:6.2} ns, {:6.1} cycles",
            format!("{l:?}"),
            ns * ghz,
            supply[i],
            r * ghz
        );
    }
}
