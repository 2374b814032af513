//! A long measurement log costs memory for the values it compares, not for its text: the log
//! is read line by line into its times, positions and signal; its velocities and
//! accelerations (derived or read) are kept in a temporary file and read a block of rows at
//! a time; the rigid-body torques, the costly effects' regressors and the rates are kept for
//! the rows the fits use; the whole-log prediction and residuals are kept in a temporary file
//! and read a channel at a time. `compare` and `identify` of a 1,000,000-row log stay within
//! a stated margin above the same commands on its first 200,000 rows; `compare` of it within
//! 175 MB, `identify` within 185 MB, `diagnose` within 250 MB.
//!
//! One binary: each child's own peak resident memory is read with `wait4`
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
/// 136–141 bytes for `compare` and `identify` (time, six positions and six signal values,
/// 104 bytes, and the line number, 4; one channel of the residual and one joint's velocity
/// or acceleration column while a channel is analysed). Keeping the velocities and
/// accelerations in memory cost about 220 bytes a row; every row's rigid-body torque and the
/// whole prediction too, about 350; reading the log's text into memory whole, about 1,400.
const MAX_BYTES_PER_FURTHER_ROW: u64 = 170;

/// The most `compare` may hold of the 1,000,000-row log, bytes (measured: about 149 MB; 225 MB
/// with the rates in memory).
const MAX_PEAK_LONG: u64 = 175_000_000;

/// The most `identify --effects coulomb` may hold of it, bytes (measured: about 159 MB; 238 MB
/// with the rates in memory).
const MAX_PEAK_LONG_IDENTIFY: u64 = 185_000_000;

/// The most `diagnose` may hold of it, bytes (measured: 212–218 MB; its fits' share, about
/// 70 MB, does not grow with the log; the fit's `JᵀJ` takes no transposed copy of the
/// Jacobian, 35 MB).
const MAX_PEAK_LONG_DIAGNOSE: u64 = 250_000_000;

/// The simulated 1,000,000-row log and its first 200,000 rows, in a scratch directory.
struct Logs {
    dir: std::path::PathBuf,
    long: std::path::PathBuf,
    short: std::path::PathBuf,
}

impl Logs {
    fn new(tag: &str) -> Self {
        let dir =
            std::env::temp_dir().join(format!("printwatt-log-mem-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let sim = Command::new(env!("CARGO_BIN_EXE_printwatt"))
            .args(["simulate", "--robot", "ur10e", "--excite", "4000"])
            .args(["--hidden", "coulomb=5", "--out"])
            .arg(&dir)
            .output()
            .unwrap();
        assert!(
            sim.status.success(),
            "{}",
            String::from_utf8_lossy(&sim.stderr)
        );
        let long = dir.join("log.csv");
        // The first SHORT_ROWS rows, with the same comments and header.
        let short = dir.join("short.csv");
        long_log::cut(&long, SHORT_ROWS, &short);
        Logs { dir, long, short }
    }

    /// Run `args` on `log` and measure its peak resident memory.
    fn measure(&self, args: &[&str], log: &std::path::Path) -> peak_rss::Run {
        let out = self.dir.join(format!("out-{}", args[0]));
        let _ = std::fs::remove_dir_all(&out);
        let mut c = Command::new(env!("CARGO_BIN_EXE_printwatt"));
        c.args(args)
            .arg("--log")
            .arg(log)
            .args(["--robot", "ur10e"]);
        if args[0] == "identify" {
            c.arg("--out").arg(&out);
        }
        let run = peak_rss::run_measured(&mut c, &self.dir);
        assert!(
            run.status.success(),
            "{args:?} {}: {}",
            log.display(),
            run.stderr
        );
        run
    }
}

impl Drop for Logs {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

#[test]
fn a_long_log_costs_memory_for_its_compared_values_not_its_text() {
    let logs = Logs::new("rows");
    for args in [&["compare"][..], &["identify", "--effects", "coulomb"]] {
        let s = logs.measure(args, &logs.short);
        let l = logs.measure(args, &logs.long);
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
}

#[test]
fn a_million_row_log_is_compared_in_under_175_mb_identified_in_under_185_mb_and_diagnosed_in_under_250_mb(
) {
    let logs = Logs::new("abs");
    for args in [
        &["compare"][..],
        &["identify", "--effects", "coulomb"],
        &["diagnose"],
    ] {
        let run = logs.measure(args, &logs.long);
        let max = match args[0] {
            "diagnose" => MAX_PEAK_LONG_DIAGNOSE,
            "identify" => MAX_PEAK_LONG_IDENTIFY,
            _ => MAX_PEAK_LONG,
        };
        eprintln!(
            "{}: peak {:.0} MB on {LONG_ROWS} rows (under {:.0} MB allowed)",
            args[0],
            run.peak_rss as f64 / 1e6,
            max as f64 / 1e6
        );
        assert!(
            run.peak_rss < max,
            "{}: {} bytes on {LONG_ROWS} rows, not under {max}",
            args[0],
            run.peak_rss
        );
    }
}
