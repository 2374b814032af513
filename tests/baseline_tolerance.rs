//! `printwatt optimise` checks its baseline against the placement tolerance the answer must
//! hold: a negative "saving vs baseline" against a baseline a site could not rely
//! on is reported as such, in the terminal, `--json` / `summary.json` and the HTML report.
//!
//! The case: the IRB 4600-40/2.55 on the default path over a 182-cell grid, seed 7. The
//! default baseline (the centre of the feasible grid region, x = 1.25 m, y = 0, yaw 90°) is
//! cheaper than the answer (−21.3 J) but 8 of the 16 corners of its ±20 mm, ±1° box come
//! within joint 3's 3° margin; the answer holds the tolerance.

mod common;
use common::root;

use serde_json::Value;
use std::path::{Path, PathBuf};

const CASE: [&str; 13] = [
    "optimise",
    "--robot",
    "abb_irb4600_40_255",
    "--path",
    "paths/default.gcode",
    "--x",
    "0.75:2.25:0.25",
    "--y",
    "-1.5:1.5:0.25",
    "--yaw",
    "0,90",
    "--seed",
    "7",
];

/// Run `printwatt` on the case (with `extra` arguments) from the repository root; stdout.
fn run(extra: &[&str]) -> String {
    let o = common::run_ok(&[&CASE[..], extra].concat(), &root());
    String::from_utf8(o.stdout).unwrap()
}

fn json(extra: &[&str]) -> Value {
    let mut a = vec!["--json"];
    a.extend_from_slice(extra);
    serde_json::from_str(&run(&a)).unwrap()
}

fn line<'a>(out: &'a str, start: &str) -> Option<&'a str> {
    out.lines().find(|l| l.starts_with(start))
}

fn tmp(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("printwatt_basetol_{tag}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn read(d: &Path, f: &str) -> String {
    std::fs::read_to_string(d.join(f)).unwrap()
}

#[test]
fn a_baseline_that_does_not_hold_the_tolerance_is_reported_so() {
    let dir = tmp("fails");
    let out = run(&["--out", dir.to_str().unwrap()]);
    assert!(
        line(
            &out,
            "baseline (centre of the feasible grid region): x = 1.250 m, y = 0.000 m"
        )
        .is_some(),
        "{out}"
    );
    let t = line(&out, "baseline tolerance: ").unwrap_or_else(|| panic!("{out}"));
    assert!(
        t.starts_with("baseline tolerance: does NOT hold ±20 mm in x and y, ±20 mm in z, ±1.0° in yaw: 8 of the 16 corners infeasible (first: joint_limit_margin"),
        "{t}"
    );
    let s = line(&out, "saving vs baseline: ").unwrap_or_else(|| panic!("{out}"));
    assert!(s.contains("supply -21.3 J"), "{s}");
    assert!(
        s.contains("measured against a baseline that does NOT hold the placement tolerance"),
        "{s}"
    );
    // The answer holds it.
    assert!(
        line(&out, "tolerance: holds").is_some(),
        "the answer should hold the tolerance: {out}"
    );

    // summary.json and the HTML report say the same.
    let v: Value = serde_json::from_str(&read(&dir, "summary.json")).unwrap();
    let b = &v["optimise"]["baseline_tolerance"];
    assert_eq!(b["holds"], Value::Bool(false), "{b}");
    assert_eq!(b["corners"], 16, "{b}");
    assert_eq!(b["failures"].as_array().map(Vec::len), Some(8), "{b}");
    // Counted with the other tolerance evaluations.
    let ev = v["meta"]["evaluations"].as_str().unwrap_or_default();
    assert!(ev.contains("the baseline 16)"), "{ev}");
    let html = read(&dir, "report.html");
    assert!(html.contains("baseline tolerance"), "report.html");
    assert!(html.contains("does NOT hold ±20 mm"), "report.html");
    assert!(
        html.contains("measured against a baseline that does NOT hold the placement tolerance"),
        "report.html"
    );
    let _ = std::fs::remove_dir_all(&dir);

    // `--json` carries the same check, whatever the thread count.
    let one = json(&["--threads", "1"]);
    let two = json(&["--threads", "2"]);
    assert_eq!(
        one["optimise"]["baseline_tolerance"],
        v["optimise"]["baseline_tolerance"]
    );
    assert_eq!(
        one["optimise"]["baseline_tolerance"],
        two["optimise"]["baseline_tolerance"]
    );
}

#[test]
fn a_baseline_that_holds_the_tolerance_is_reported_so() {
    let out = run(&["--no-report", "--baseline", "1.3,0,0,92"]);
    let t = line(&out, "baseline tolerance: ").unwrap_or_else(|| panic!("{out}"));
    assert!(
        t.starts_with("baseline tolerance: holds ±20 mm in x and y, ±20 mm in z, ±1.0° in yaw: all 16 corners feasible, energy "),
        "{t}"
    );
    let s = line(&out, "saving vs baseline: ").unwrap_or_else(|| panic!("{out}"));
    assert!(!s.contains("does NOT hold"), "{s}");
    let v = json(&["--baseline", "1.3,0,0,92"]);
    let b = &v["optimise"]["baseline_tolerance"];
    assert_eq!(b["holds"], Value::Bool(true), "{b}");
    assert_eq!(b["corners"], 16, "{b}");
    assert_eq!(b["failures"].as_array().map(Vec::len), Some(0), "{b}");
}

#[test]
fn a_zero_tolerance_does_not_check_the_baseline() {
    let out = run(&["--no-report", "--tolerance", "0,0"]);
    assert!(line(&out, "baseline (").is_some(), "{out}");
    assert!(line(&out, "baseline tolerance").is_none(), "{out}");
    let v = json(&["--tolerance", "0,0"]);
    assert_eq!(v["optimise"]["baseline_tolerance"], Value::Null);
}
