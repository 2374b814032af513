//! Cost per path sample of time parameterisation (Cartesian plan + joint-stage differences and
//! limit checks) against the cost of what every sample needs anyway (IK + inverse dynamics +
//! power). The target: timing adds no more than 20 % to IK + dynamics.
//!
//! Criterion times each stage over the whole default path on the IRB 6700; a summary at the end
//! prints the per-sample figures and the ratio, measured in the same run.

use criterion::{criterion_group, Criterion};
use printwatt::dynamics::DynData;
use printwatt::energy::{eval_sample, EnergyModel, SamplePower};
use printwatt::kinematics::IkSolver;
use printwatt::robot::{self, RobotModel};
use printwatt::timing::{self, joint, profile, JointStageOptions, ProfileOptions};
use printwatt::toolpath::{self, Placement, ReadOptions};
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Instant;

struct Setup {
    model: RobotModel,
    moves: Vec<timing::Move>,
    pieces: Vec<timing::Piece>,
    at: Placement,
    opts: ProfileOptions,
}

fn setup() -> Setup {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let model = robot::load(&root.join("robots/abb_irb6700_200_260")).expect("robot");
    let tp =
        toolpath::load(&root.join("paths/default.gcode"), &ReadOptions::default()).expect("path");
    let moves = timing::moves_from_toolpath(&tp);
    let pieces = timing::blend_path(&moves);
    Setup {
        model,
        moves,
        pieces,
        at: Placement::new(1.7, 0.0, 0.0, std::f64::consts::FRAC_PI_2),
        opts: ProfileOptions::default(),
    }
}

/// The default path planned and timed once, for timing its stages separately.
struct Prepared {
    solver_q0: Vec<f64>,
    nodes: profile::Nodes,
    scale: Vec<f64>,
    motion: timing::CartesianMotion,
    traj: printwatt::trajectory::JointTrajectory,
    em: EnergyModel,
}

fn prepare(s: &Setup, solver: &IkSolver) -> Prepared {
    let nodes = profile::nodes(&s.pieces, &s.opts);
    let scale = vec![1.0; nodes.s.len()];
    let motion = profile::plan(&s.pieces, &nodes, &scale, &s.opts);
    let lines = |i: usize| s.moves[i].line;
    let jopts = JointStageOptions::default();
    let t = timing::time_at(solver, &s.pieces, &lines, &s.at, &s.opts, &jopts).expect("timed");
    let em = EnergyModel::new(&s.model).expect("energy model");
    Prepared {
        solver_q0: t.traj.q(0).to_vec(),
        nodes,
        scale,
        motion,
        traj: t.traj,
        em,
    }
}

/// Energy of every sample of `traj`, W summed (the dynamics + power stage).
fn power_pass(em: &EnergyModel, traj: &printwatt::trajectory::JointTrajectory) -> f64 {
    let mut d: DynData = em.data();
    let mut out = SamplePower::default();
    let mut e = 0.0;
    for k in 0..traj.len() {
        e += eval_sample(em, &mut d, traj.q(k), traj.qd(k), traj.qdd(k), &mut out).expect("sample");
    }
    e
}

fn stages(c: &mut Criterion) {
    let s = setup();
    let solver = IkSolver::new(&s.model).expect("solver");
    let p = prepare(&s, &solver);
    let lines = |i: usize| s.moves[i].line;
    let n = s.model.dof();
    let mut g = c.benchmark_group(format!("timing_default_path_{}_samples", p.motion.p.len()));
    g.sample_size(10);
    g.bench_function("cartesian_plan", |b| {
        b.iter(|| black_box(profile::plan(&s.pieces, &p.nodes, &p.scale, &s.opts)))
    });
    let mut bufs = timing::Buffers::default();
    g.bench_function("ik_track", |b| {
        b.iter(|| {
            joint::track(
                &solver,
                &s.pieces,
                &lines,
                &p.motion,
                &s.at,
                &p.solver_q0,
                &mut bufs,
            )
            .expect("track")
        })
    });
    g.bench_function("differences", |b| {
        b.iter(|| black_box(joint::differentiate(&p.traj.q, n, p.motion.dt)))
    });
    g.bench_function("dynamics_power", |b| {
        b.iter(|| black_box(power_pass(&p.em, &p.traj)))
    });
    g.finish();
}

/// Median wall time of `f` over `reps` runs, s.
fn median_time(reps: usize, mut f: impl FnMut()) -> f64 {
    let mut v: Vec<f64> = (0..reps)
        .map(|_| {
            let t0 = Instant::now();
            f();
            t0.elapsed().as_secs_f64()
        })
        .collect();
    v.sort_by(f64::total_cmp);
    v[reps / 2]
}

fn summary() {
    let s = setup();
    let solver = IkSolver::new(&s.model).expect("solver");
    let p = prepare(&s, &solver);
    let lines = |i: usize| s.moves[i].line;
    let n = s.model.dof();
    let m = p.motion.p.len() as f64;
    let reps = 21;
    let plan = median_time(reps, || {
        black_box(profile::plan(&s.pieces, &p.nodes, &p.scale, &s.opts));
    });
    let mut bufs = timing::Buffers::default();
    let ik = median_time(reps, || {
        joint::track(
            &solver,
            &s.pieces,
            &lines,
            &p.motion,
            &s.at,
            &p.solver_q0,
            &mut bufs,
        )
        .expect("track");
    });
    let diff = median_time(reps, || {
        black_box(joint::differentiate(&p.traj.q, n, p.motion.dt));
    });
    let dynp = median_time(reps, || {
        black_box(power_pass(&p.em, &p.traj));
    });
    let ns = |x: f64| x / m * 1e9;
    println!(
        "\n== per path sample ({} samples, IRB 6700, default path, 1 thread) ==",
        p.motion.p.len()
    );
    println!(
        "cartesian plan (blends, speed profile, FIR filter) {:8.1} ns",
        ns(plan)
    );
    println!(
        "joint differences (velocity, acceleration, jerk)  {:8.1} ns",
        ns(diff)
    );
    println!(
        "IK (branch continuing the previous sample)        {:8.1} ns",
        ns(ik)
    );
    println!(
        "RNEA + friction + motor model + power             {:8.1} ns",
        ns(dynp)
    );
    let ratio = (plan + diff) / (ik + dynp);
    println!(
        "timing overhead / (IK + dynamics) = {:.3} (target <= 0.20)",
        ratio
    );
    println!(
        "IK + dynamics + timing per sample = {:.1} ns (target <= 1000 ns for IK + RNEA + power)",
        ns(plan + diff + ik + dynp)
    );
}

criterion_group!(benches, stages);

fn main() {
    benches();
    Criterion::default().configure_from_args().final_summary();
    summary();
}
