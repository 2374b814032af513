//! Criterion benchmarks of the dynamics and the per-sample energy evaluation, with a ratio
//! against Pinocchio 4.1's C++ RNEA when the harness `../shared/bench/pinocchio-rnea/run.sh` is present
//! (run once per robot on the same URDF; see its README); the lockstep RNEA (8 samples per
//! call on the CPU's best SIMD level) per sample in the same run, as a ratio to it too.

#![allow(clippy::needless_range_loop)] // index-parallel arrays read more clearly in tests

#[path = "common/pinocchio.rs"]
mod pinocchio;

use criterion::{black_box, Criterion};
use printwatt::dynamics::{
    gravity_torque, mass_matrix, rnea, rnea_batch, DynModel, DynOptions, StateBatch,
};
use printwatt::energy::{eval_sample, EnergyModel, SamplePower};
use printwatt::simd::LANES;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::time::Instant;

const N_STATES: usize = 1000;

fn robot_dir(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("robots")
        .join(name)
}

/// Random states like the Pinocchio harness: q ∈ [−π, π], qd, qdd ∈ [−1, 1].
fn states(n: usize) -> Vec<[Vec<f64>; 3]> {
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    (0..N_STATES)
        .map(|_| {
            [
                (0..n).map(|_| rng.gen_range(-PI..PI)).collect(),
                (0..n).map(|_| rng.gen_range(-1.0..1.0)).collect(),
                (0..n).map(|_| rng.gen_range(-1.0..1.0)).collect(),
            ]
        })
        .collect()
}

/// Median over batches of the mean ns per RNEA call (same protocol as the Pinocchio harness).
fn our_rnea_ns(model: &DynModel, st: &[[Vec<f64>; 3]]) -> f64 {
    let mut d = model.data();
    let mut tau = vec![0.0; model.dof()];
    let mut batch = |d: &mut printwatt::dynamics::DynData| {
        let t0 = Instant::now();
        for s in st {
            let _ = rnea(model, d, &s[0], &s[1], &s[2], &mut tau);
            black_box(&tau);
        }
        t0.elapsed().as_nanos() as f64 / st.len() as f64
    };
    for _ in 0..100 {
        batch(&mut d);
    }
    let mut v: Vec<f64> = (0..1000).map(|_| batch(&mut d)).collect();
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// The same for the lockstep RNEA ([`rnea_batch`] on the CPU's best SIMD level): ns per
/// sample, the sines of each batch computed inside the timed loop
/// ([`printwatt::fastmath::sin_cos_lanes`]) as RNEA computes them.
fn our_rnea_batch_ns(model: &DynModel, st: &[[Vec<f64>; 3]]) -> f64 {
    let n = model.dof();
    let level = printwatt::simd::detected();
    let mut tau = [[0.0; LANES]; printwatt::dynamics::MAX_DOF];
    let mut batch = || {
        let t0 = Instant::now();
        for chunk in st.chunks(LANES) {
            let mut b = StateBatch::default();
            for j in 0..n {
                let mut x = [0.0; LANES];
                for (l, s) in chunk.iter().enumerate() {
                    x[l] = s[0][j];
                    b.qd[j][l] = s[1][j];
                    b.qdd[j][l] = s[2][j];
                }
                (b.s[j], b.c[j]) = printwatt::fastmath::sin_cos_lanes(&x);
            }
            rnea_batch(model, &b, &mut tau, level);
            black_box(&tau);
        }
        t0.elapsed().as_nanos() as f64 / st.len() as f64
    };
    for _ in 0..100 {
        batch();
    }
    let mut v: Vec<f64> = (0..1000).map(|_| batch()).collect();
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let mut ratios = Vec::new();
    for name in ["abb_irb6700_200_260", "ur10e"] {
        let robot = match printwatt::robot::load(&robot_dir(name)) {
            Ok(r) => r,
            Err(e) => {
                eprintln!("{name}: {e}");
                continue;
            }
        };
        let n = robot.dof();
        let Ok(full) = DynModel::new(
            &robot,
            DynOptions {
                payload: true,
                armature: true,
            },
        ) else {
            continue;
        };
        let Ok(bare) = DynModel::new(&robot, DynOptions::default()) else {
            continue;
        };
        let Ok(em) = EnergyModel::new(&robot) else {
            continue;
        };
        let st = states(n);
        let mut d = full.data();
        let mut tau = vec![0.0; n];
        let mut m = vec![0.0; n * n];
        let mut sp = SamplePower::default();
        let mut k = 0usize;
        let mut next = || {
            k = (k + 1) % N_STATES;
            &st[k]
        };
        c.bench_function(&format!("rnea/{name}"), |b| {
            b.iter(|| {
                let s = next();
                let _ = rnea(&full, &mut d, &s[0], &s[1], &s[2], &mut tau);
                black_box(&tau);
            })
        });
        c.bench_function(&format!("gravity/{name}"), |b| {
            b.iter(|| {
                let s = next();
                let _ = gravity_torque(&full, &mut d, &s[0], &mut tau);
                black_box(&tau);
            })
        });
        c.bench_function(&format!("mass_matrix/{name}"), |b| {
            b.iter(|| {
                let s = next();
                let _ = mass_matrix(&full, &mut d, &s[0], &mut m);
                black_box(&m);
            })
        });
        c.bench_function(&format!("energy_sample/{name}"), |b| {
            b.iter(|| {
                let s = next();
                black_box(eval_sample(&em, &mut d, &s[0], &s[1], &s[2], &mut sp).ok());
            })
        });
        if std::env::args().all(|a| a != "--test" && a != "--list") {
            let ours = our_rnea_ns(&bare, &st);
            let lockstep = our_rnea_batch_ns(&bare, &st);
            let level = printwatt::simd::detected().name();
            match pinocchio::rnea_ns(&robot_dir(name).join("robot.urdf")) {
                Ok((pin, nv)) => ratios.push(format!(
                    "{name}: ours {ours:.1} ns / pinocchio {pin:.1} ns (nv = {nv}) = {:.3}; lockstep ({level}, 8 samples) {lockstep:.1} ns per sample = {:.3}",
                    ours / pin,
                    lockstep / pin
                )),
                Err(e) => ratios.push(format!(
                    "{name}: ours {ours:.1} ns, lockstep ({level}) {lockstep:.1} ns per sample; pinocchio reference unavailable ({e})"
                )),
            }
        }
    }
    c.final_summary();
    for r in ratios {
        println!("rnea ratio  {r}");
    }
}
