//! The sample budget states the memory it measures: the bytes per sample behind the budget's
//! estimate ([`printwatt::timing::budget::bytes_per_sample`]) are those a long print costs
//! `printwatt energy` (the command that keeps the whole per-sample series), and the refusal's
//! message states that estimate before anything is allocated.
//!
//! One test in its own binary: the peak resident memory of the child processes is read with
//! `getrusage(RUSAGE_CHILDREN)`, the maximum over every child waited for so far.

mod common;
#[path = "common/peak_rss.rs"]
mod peak_rss;
#[path = "common/wall.rs"]
mod wall;

use peak_rss::children_max_rss;
use std::process::Command;

#[test]
fn the_sample_budget_states_the_memory_it_measures() {
    let d = std::env::temp_dir().join(format!("printwatt-budget-mem-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let path = d.join("wall40.gcode");
    std::fs::write(&path, wall::wall_gcode(1800.0, 600.0, 4.0, 40)).unwrap();
    let energy = |budget: Option<&str>| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_printwatt"));
        c.arg("energy")
            .arg("--path")
            .arg(&path)
            .args(["--at", "1.6,0,0,90", "--json"]);
        if let Some(b) = budget {
            c.env("PRINTWATT_MAX_SAMPLES", b);
        } else {
            c.env_remove("PRINTWATT_MAX_SAMPLES");
        }
        c.output().unwrap()
    };
    // Refused first (nothing planned: the peak stays that of the refusal), then run.
    let refused = energy(Some("100000"));
    assert!(!refused.status.success());
    let msg = String::from_utf8_lossy(&refused.stderr).to_string();
    let o = energy(None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let samples = v["energy"]["samples"].as_u64().unwrap() as f64;
    let measured = children_max_rss() as f64 / samples;
    let stated = printwatt::timing::budget::bytes_per_sample(6) as f64;
    eprintln!(
        "energy on {samples} samples: {measured:.0} bytes a sample; the budget states {stated:.0}"
    );
    assert!(samples > 3e5, "{samples}");
    // True: not below what a sample costs, and not more than a third above it.
    assert!(
        measured <= stated && stated <= 1.35 * measured,
        "the budget states {stated:.0} bytes a sample, the command used {measured:.0}"
    );
    // The refusal states the estimate: its samples times the bytes a sample (plus the nodes).
    let num = |before: &str| -> f64 {
        let i = msg
            .find(before)
            .unwrap_or_else(|| panic!("`{before}` in: {msg}"));
        let head = &msg[..i];
        let start = head.rfind([' ', '(', '~']).map_or(0, |k| k + 1);
        head[start..].trim().parse().unwrap()
    };
    let est_samples = num(" samples at");
    let gb = num(" GB)");
    assert!(
        (gb - est_samples * stated / 1e9).abs() <= 0.05 + 0.02 * gb,
        "the message states {gb} GB for {est_samples} samples: {msg}"
    );
    assert!(
        est_samples <= samples * 1.01,
        "the estimate is a lower bound"
    );
    let _ = std::fs::remove_dir_all(&d);
}
