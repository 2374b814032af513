//! Peak memory and wall time of the measurement loop on long logs: `compare`, `diagnose` and
//! `identify --effects coulomb` of a simulated torque log (UR10e, 250 Hz, `simulate --excite
//! 4000 --hidden coulomb=5`: 1,000,000 rows) and of its first 200,000 rows. Each command runs
//! as its own process, measured on its own (`wait4`: its peak resident memory and its wall
//! time); the load average before and after is printed, since the wall times depend on what
//! else runs. `cargo bench --bench log_memory` (about two minutes on 2 cores);
//! `PRINTWATT_LOG_MEMORY_ROWS=200000,1000000` sets the lengths, `PRINTWATT_LOG_MEMORY_COMMANDS=
//! compare,identify` the commands.

#[path = "../tests/common/long_log.rs"]
mod long_log;
#[path = "../tests/common/peak_rss.rs"]
mod peak_rss;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// Peak resident memory (bytes) and wall time (s) of one command run to its end.
fn measured(args: &[&str], log: &Path, scratch: &Path) -> (u64, f64) {
    let out = scratch.join(format!("out-{}", args[0]));
    let _ = std::fs::remove_dir_all(&out);
    let mut c = Command::new(env!("CARGO_BIN_EXE_printwatt"));
    c.args(args)
        .arg("--log")
        .arg(log)
        .args(["--robot", "ur10e"]);
    if args[0] == "identify" {
        c.arg("--out").arg(&out);
    }
    let t = Instant::now();
    let run = peak_rss::run_measured(&mut c, scratch);
    let wall = t.elapsed().as_secs_f64();
    assert!(
        run.status.success(),
        "{args:?} on {} failed: {}",
        log.display(),
        run.stderr
    );
    (run.peak_rss, wall)
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

fn main() {
    let rows: Vec<usize> = std::env::var("PRINTWATT_LOG_MEMORY_ROWS")
        .ok()
        .map(|v| v.split(',').filter_map(|x| x.trim().parse().ok()).collect())
        .unwrap_or_else(|| vec![200_000, 1_000_000]);
    let commands: Vec<String> = std::env::var("PRINTWATT_LOG_MEMORY_COMMANDS")
        .map(|v| v.split(',').map(|x| x.trim().to_string()).collect())
        .unwrap_or_else(|_| vec!["compare".into(), "diagnose".into(), "identify".into()]);
    let longest = rows.iter().copied().max().unwrap_or(1_000_000);
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/bench-log-memory");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    let secs = (longest as f64 / 250.0).ceil().to_string();
    let sim = Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .args(["simulate", "--robot", "ur10e", "--excite", &secs])
        .args(["--hidden", "coulomb=5", "--out"])
        .arg(&dir)
        .output()
        .expect("simulate");
    assert!(
        sim.status.success(),
        "{}",
        String::from_utf8_lossy(&sim.stderr)
    );
    let full = dir.join("log.csv");
    println!("load average before: {}", load_average());
    println!(
        "{:<10} {:>10} {:>14} {:>10}",
        "command", "rows", "peak memory", "wall"
    );
    for cmd in &commands {
        let args: Vec<&str> = match cmd.as_str() {
            "identify" => vec!["identify", "--effects", "coulomb"],
            c => vec![c],
        };
        for &n in &rows {
            let log = dir.join(format!("log{n}.csv"));
            if !log.exists() {
                long_log::cut(&full, n, &log);
            }
            let (peak, wall) = measured(&args, &log, &dir);
            println!(
                "{:<10} {:>10} {:>11.0} MB {:>8.2} s",
                cmd,
                n,
                peak as f64 / 1e6,
                wall
            );
        }
    }
    println!("load average after: {}", load_average());
    let _ = std::fs::remove_dir_all(&dir);
}
