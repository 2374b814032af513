//! A long measurement log costs memory for the values it compares, not for its text: the log
//! is read line by line into its compared columns (time, positions, the signal; velocities and
//! accelerations derived or read), and the costly effects' regressors are kept for the rows
//! the fits use. `compare` and `identify` of a 1,000,000-row log stay within a stated margin
//! above the same commands on its first 200,000 rows.
//!
//! One test in its own binary: each child's own peak resident memory is read with `wait4`
//! (tests/common/peak_rss.rs).

#[path = "common/long_log.rs"]
mod long_log;
#[path = "common/peak_rss.rs"]
mod peak_rss;

use std::process::Command;

/// Rows of the long log (250 Hz: 4,000 s of exciting motion) and of its cut.
const LONG_ROWS: usize = 1_000_000;
const SHORT_ROWS: usize = 200_000;

/// The most a further row of the log may cost, bytes: measured on the release build, about
/// 385 bytes for `compare` (the compared columns, 208 bytes a row with the derived velocities
/// and accelerations; the rigid-body torques, 48; the prediction and its residual, 96) and
/// less for `identify`. Reading the log's text into memory whole, as before, cost about
/// 1,400 bytes a row.
const MAX_BYTES_PER_FURTHER_ROW: u64 = 450;

#[test]
fn a_long_log_costs_memory_for_its_compared_values_not_its_text() {
    let d = std::env::temp_dir().join(format!("printwatt-log-mem-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let bin = env!("CARGO_BIN_EXE_printwatt");
    let sim = Command::new(bin)
        .args(["simulate", "--robot", "ur10e", "--excite", "4000"])
        .args(["--hidden", "coulomb=5", "--out"])
        .arg(&d)
        .output()
        .unwrap();
    assert!(
        sim.status.success(),
        "{}",
        String::from_utf8_lossy(&sim.stderr)
    );
    let long = d.join("log.csv");
    // The first SHORT_ROWS rows, with the same comments and header.
    let short = d.join("short.csv");
    long_log::cut(&long, SHORT_ROWS, &short);
    let measure = |args: &[&str], log: &std::path::Path| {
        let out = d.join(format!("out-{}", args[0]));
        let _ = std::fs::remove_dir_all(&out);
        let mut c = Command::new(bin);
        c.args(args)
            .arg("--log")
            .arg(log)
            .args(["--robot", "ur10e"]);
        if args[0] == "identify" {
            c.arg("--out").arg(&out);
        }
        let run = peak_rss::run_measured(&mut c, &d);
        assert!(
            run.status.success(),
            "{args:?} {}: {}",
            log.display(),
            run.stderr
        );
        run
    };
    for args in [&["compare"][..], &["identify", "--effects", "coulomb"]] {
        let s = measure(args, &short);
        let l = measure(args, &long);
        if args[0] == "compare" {
            for (run, rows) in [(&s, SHORT_ROWS), (&l, LONG_ROWS)] {
                assert!(
                    run.stdout.contains(&format!("({rows} samples")),
                    "{}",
                    run.stdout
                );
            }
        }
        let margin = MAX_BYTES_PER_FURTHER_ROW * (LONG_ROWS - SHORT_ROWS) as u64;
        eprintln!(
            "{}: peak {:.0} MB on {SHORT_ROWS} rows, {:.0} MB on {LONG_ROWS} rows ({:.0} bytes a further row; at most {:.0} MB more allowed)",
            args[0],
            s.peak_rss as f64 / 1e6,
            l.peak_rss as f64 / 1e6,
            l.peak_rss.saturating_sub(s.peak_rss) as f64 / (LONG_ROWS - SHORT_ROWS) as f64,
            margin as f64 / 1e6
        );
        assert!(
            l.peak_rss <= s.peak_rss + margin,
            "{}: {} bytes on {LONG_ROWS} rows, {} on {SHORT_ROWS}: more than {margin} bytes more",
            args[0],
            l.peak_rss,
            s.peak_rss
        );
    }
    let _ = std::fs::remove_dir_all(&d);
}
