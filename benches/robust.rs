//! The decision under uncertainty on the main job: `printwatt optimise --uncertainty 50`
//! (shipped IRB 6700, `paths/default.gcode`, the default grid and search) through the library
//! (`search::run`, one evaluator reused for every draw: each candidate is timed once, only its
//! energy is recomputed per draw, and each draw's own optimum is refined on the same
//! evaluator), against the same job without the study, alternated in the same run.
//!
//! Printed: the wall time of each (median of interleaved rounds), their ratio, the study's
//! evaluations, the CPU model and the load average. The time must stay practical on 2 cores:
//! the bench fails when a draw costs more than one plain optimise (each draw refines its own
//! optimum, a reduced search; its candidates' energies reuse the timed motion).
//!
//! Run: `cargo bench --bench robust` (plain main, no criterion).

#[path = "../tests/common/mod.rs"]
mod common;

use printwatt::search::job::OptimiseConfig;
use printwatt::search::run::Silent;
use std::time::Instant;

fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .unwrap_or_default()
        .lines()
        .find(|l| l.starts_with("model name"))
        .and_then(|l| l.split(':').nth(1))
        .map_or("unknown CPU".into(), |s| s.trim().to_string())
}

fn main() {
    let draws = 50;
    let path_file = common::root().join("paths/default.gcode");
    let plain = OptimiseConfig::new(
        common::robot("abb_irb6700_200_260"),
        common::path("default.gcode"),
        &path_file,
    );
    let mut robust = plain.clone();
    robust.settings.uncertainty = Some(draws);
    let rounds = 2;
    let (mut t_plain, mut t_robust) = (Vec::new(), Vec::new());
    let mut last = None;
    for _ in 0..rounds {
        let t = Instant::now();
        let p = printwatt::search::run(&plain, &Silent).unwrap();
        t_plain.push(t.elapsed().as_secs_f64());
        std::hint::black_box(p);
        let t = Instant::now();
        let r = printwatt::search::run(&robust, &Silent).unwrap();
        t_robust.push(t.elapsed().as_secs_f64());
        last = Some(r);
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (tp, tr) = (median(&mut t_plain), median(&mut t_robust));
    let out = last.unwrap();
    let rb = out
        .report
        .optimise
        .as_ref()
        .and_then(|o| o.decision.as_ref())
        .and_then(|d| d.robust.as_ref())
        .expect("a robust choice with --uncertainty");
    let rec = rb.recommendation();
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "printwatt robust bench: the main job with {draws} draws on {} threads, {}",
        rayon::current_num_threads(),
        cpu_model()
    );
    println!("  load average (1, 5, 15 min) at the end: {}", load.trim());
    println!(
        "  optimise: {tp:.2} s wall; with --uncertainty {draws}: {tr:.2} s wall ({:.1}x; median of {rounds} alternated rounds); robust study: {} evaluations, {} candidates",
        tr / tp,
        rb.evaluations,
        rb.candidates.len()
    );
    println!(
        "  recommendation: expected regret {:.1} J (nominal answer {:.1} J), within 1 % of the drives' energy in {:.0} % of the draws",
        rec.expected_regret_j,
        rb.nominal().expected_regret_j,
        100.0 * rec.p_within_1pct
    );
    println!(
        "  per draw: {:.2} s wall = {:.2}x one plain optimise",
        (tr - tp) / draws as f64,
        (tr - tp) / draws as f64 / tp
    );
    assert!(
        tr - tp < draws as f64 * tp,
        "a draw of the study costs more than a plain optimise: {:.1}x for {draws} draws",
        tr / tp
    );
}
