//! Long prints do not hold their outputs in memory: `printwatt energy` streams its per-sample
//! CSV to the file as it formats it, and checks the series for non-finite values where they
//! are, so writing the CSV costs (almost) no memory over evaluating the path, and the whole
//! command stays within a stated number of bytes per sample.
//!
//! One test in its own binary: the peak resident memory of the child processes is read with
//! `getrusage(RUSAGE_CHILDREN)`, which is the maximum over every child waited for so far.

mod common;
#[path = "common/peak_rss.rs"]
mod peak_rss;
#[path = "common/wall.rs"]
mod wall;

use peak_rss::children_max_rss;
use std::process::Command;

/// Measured on the release build: about 1.3 KB per sample for the whole `energy` command
/// (trajectory, torques, powers and the timing's own series); the bound leaves room for the
/// allocator, and fails when the CSV (about 0.8 KB per sample as text) or a JSON value of the
/// series is built in memory.
const MAX_BYTES_PER_SAMPLE: f64 = 1600.0;

#[test]
fn energy_streams_its_series_csv_instead_of_holding_it_in_memory() {
    let d = std::env::temp_dir().join(format!("printwatt-out-mem-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let path = d.join("wall40.gcode");
    std::fs::write(&path, wall::wall_gcode(1800.0, 600.0, 4.0, 40)).unwrap();
    let run = |out: Option<&std::path::Path>| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_printwatt"));
        c.arg("energy")
            .arg("--path")
            .arg(&path)
            .args(["--at", "1.6,0,0,90", "--json"]);
        if let Some(o) = out {
            c.arg("--out").arg(o);
        }
        let o = c.output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        (
            v["energy"]["samples"].as_u64().unwrap() as f64,
            children_max_rss(),
        )
    };
    let (samples, without) = run(None);
    let (_, with) = run(Some(&d.join("out")));
    let csv = std::fs::metadata(d.join("out/wall40.energy.csv"))
        .unwrap()
        .len();
    eprintln!(
        "energy on {samples} samples: peak {:.0} MB without the CSV, {:.0} MB writing it ({:.0} MB of CSV): {:.0} bytes per sample",
        without as f64 / 1e6,
        with as f64 / 1e6,
        csv as f64 / 1e6,
        with as f64 / samples
    );
    assert!(samples > 3e5, "{samples}");
    // getrusage gives the maximum over both children: the second raised it by at most a
    // tenth of what the CSV holds.
    assert!(
        (with - without) as f64 <= 0.1 * csv as f64,
        "writing the CSV raised the peak by {} bytes ({} bytes of CSV)",
        with - without,
        csv
    );
    assert!(
        with as f64 / samples <= MAX_BYTES_PER_SAMPLE,
        "{:.0} bytes per sample",
        with as f64 / samples
    );
    let _ = std::fs::remove_dir_all(&d);
}
