//! Criterion benchmarks of the measurement loop's linearity: `compare` and
//! `diagnose` on simulated torque logs (ABB IRB 4600, 250 Hz, Coulomb friction hidden) at two
//! log lengths, four times apart. Criterion reports throughput in rows per second
//! (`Throughput::Elements`); the loop is linear in the log length when the two lengths give
//! about the same throughput (the ratio of per-row times printed at the end is close to 1).
//! Short on purpose (10 samples each, a few seconds): `cargo bench --bench identify`.
//! The 1,000,000-row figure is measured with the CLI (README, docs/identify.md).

use criterion::{BenchmarkId, Criterion, Throughput};
use printwatt::identify::log::{Log, SignalKind};
use printwatt::identify::{diagnose::diagnose, log::parse_log, metrics, simulate, Model, Prepared};
use std::path::Path;
use std::time::{Duration, Instant};

fn log_of(r: &printwatt::robot::RobotModel, secs: f64) -> Log {
    let mut truth = Model::new(r).unwrap();
    simulate::apply_hidden(&mut truth, &simulate::parse_hidden("coulomb=30").unwrap()).unwrap();
    let tr = simulate::resample(&simulate::excitation(r, secs, 1000.0, 7), 250.0);
    let opt = simulate::SensorOptions {
        kind: SignalKind::Torque,
        noise: 2.0,
        noise_q: 1e-6,
        current_quantum: 0.01,
        seed: 7,
    };
    let text = simulate::simulate_log(&truth, &tr, &opt, &[]).unwrap();
    parse_log(&text, "bench.csv", r.dof(), None).unwrap()
}

fn per_row_seconds(f: &dyn Fn(), rows: usize) -> f64 {
    let t = Instant::now();
    f();
    t.elapsed().as_secs_f64() / rows as f64
}

fn main() {
    let r = printwatt::robot::load(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/abb_irb4600_40_255"),
    )
    .unwrap();
    let mut c = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3))
        .configure_from_args();
    let mut ratios = Vec::new();
    for (what, secs) in [("compare", [20.0, 80.0]), ("diagnose", [10.0, 40.0])] {
        let logs: Vec<Log> = secs.iter().map(|s| log_of(&r, *s)).collect();
        let run = |log: &Log| {
            let mut m = Model::new(&r).unwrap();
            let prep = Prepared::new(&m, log).unwrap();
            if what == "compare" {
                std::hint::black_box(metrics::compare(&prep, &m));
            } else {
                std::hint::black_box(diagnose(&prep, &mut m, 5).unwrap());
            }
        };
        let mut g = c.benchmark_group(what);
        for log in &logs {
            g.throughput(Throughput::Elements(log.len() as u64));
            g.bench_with_input(BenchmarkId::from_parameter(log.len()), log, |b, log| {
                b.iter(|| run(log))
            });
        }
        g.finish();
        // One more timing of each length for the printed ratio (criterion's own estimates
        // are in target/criterion).
        let short = per_row_seconds(&|| run(&logs[0]), logs[0].len());
        let long = per_row_seconds(&|| run(&logs[1]), logs[1].len());
        ratios.push((what, logs[0].len(), logs[1].len(), long / short));
    }
    for (what, a, b, ratio) in ratios {
        println!(
            "{what}: time per row at {b} rows / at {a} rows = {ratio:.2} (1 = linear in the log length)"
        );
    }
    c.final_summary();
}
