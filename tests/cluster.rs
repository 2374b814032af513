//! Sharded sweeps (`sweep --shard`, `merge`): the merged files are the single run's files bit
//! for bit, whatever the shard count and thread count; merge refuses what is not one run.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn printwatt(args: &[&str], cwd: &Path, env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_printwatt"));
    c.args(args).current_dir(cwd);
    for k in [
        "SLURM_ARRAY_TASK_ID",
        "SLURM_ARRAY_TASK_MIN",
        "SLURM_ARRAY_TASK_MAX",
        "SLURM_ARRAY_TASK_COUNT",
        "JOB_COMPLETION_INDEX",
    ] {
        c.env_remove(k);
    }
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("running printwatt")
}

fn ok(o: &Output) -> String {
    assert!(
        o.status.success(),
        "failed: {}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn err(o: &Output) -> String {
    assert!(
        !o.status.success(),
        "should have failed: {}",
        String::from_utf8_lossy(&o.stdout)
    );
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A fresh scratch directory holding a copy of the shipped default path (so that a test may
/// change it) and the shipped robots reachable by name.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("printwatt-cluster-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    std::fs::copy(root.join("paths/default.gcode"), d.join("wall.gcode")).unwrap();
    d
}

/// A small grid over the default robot with feasible and infeasible cells.
const GRID: [&str; 8] = [
    "--x",
    "1.5:1.9:0.1",
    "--y",
    "-0.5:0.5:0.25",
    "--yaw",
    "90,80",
    "--path",
    "wall.gcode",
];

fn sweep(extra: &[&str], cwd: &Path, env: &[(&str, &str)]) -> Output {
    let mut a = vec!["sweep"];
    a.extend(GRID);
    a.extend(extra);
    printwatt(&a, cwd, env)
}

#[test]
fn merged_shards_give_the_single_run_files_bit_for_bit() {
    let d = scratch("bits");
    let single = ok(&sweep(&["--out", "single", "--threads", "2"], &d, &[]));
    // Three shards, computed with different thread counts, in a different order.
    for (k, threads) in [(2, "2"), (0, "1"), (1, "2")] {
        let spec = format!("{k}/3");
        let o = ok(&sweep(
            &["--shard", &spec, "--out", "parts", "--threads", threads],
            &d,
            &[],
        ));
        assert!(o.contains(&format!("shard {k} of 3")), "{o}");
    }
    // Merged from another working directory: the job's relative paths are the shards'.
    let elsewhere = d.join("elsewhere");
    std::fs::create_dir_all(&elsewhere).unwrap();
    let merged = ok(&printwatt(
        &["merge", "../parts", "--out", "../merged"],
        &elsewhere,
        &[],
    ));
    assert_eq!(single, merged, "the terminal answers differ");
    let mut feasible = 0;
    for f in ["summary.json", "placements.csv", "report.html"] {
        let a = std::fs::read(d.join("single").join(f)).unwrap();
        let b = std::fs::read(d.join("merged").join(f)).unwrap();
        assert!(a == b, "{f} differs between the single run and the merge");
        if f == "placements.csv" {
            feasible = String::from_utf8(a)
                .unwrap()
                .lines()
                .filter(|l| l.contains(",true,"))
                .count();
        }
    }
    assert!(
        (15..50).contains(&feasible),
        "the grid should hold feasible cells: {feasible}"
    );
    let run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("merged/run.json")).unwrap()).unwrap();
    assert_eq!(run["shards"], 3);
    assert_eq!(run["placements"], 50);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn merge_refuses_a_missing_shard_a_duplicate_and_shards_of_another_job() {
    let d = scratch("refuse");
    for k in 0..3 {
        ok(&sweep(
            &["--shard", &format!("{k}/3"), "--out", "a"],
            &d,
            &[],
        ));
    }
    // Another job: a different objective.
    ok(&sweep(
        &["--shard", "1/3", "--out", "b", "--objective", "mechanical"],
        &d,
        &[],
    ));
    let e = err(&printwatt(
        &["merge", "a/shard-0-of-3", "a/shard-2-of-3", "--out", "m"],
        &d,
        &[],
    ));
    assert!(e.contains("1 of 3 shards missing (0-based: 1)"), "{e}");
    let e = err(&printwatt(
        &[
            "merge",
            "a/shard-0-of-3",
            "a/shard-1-of-3",
            "a/shard-2-of-3",
            "b/shard-1-of-3",
            "--out",
            "m",
        ],
        &d,
        &[],
    ));
    assert!(
        e.contains("not a shard of the same run") && e.contains("--objective"),
        "{e}"
    );
    // The same shard copied under another name.
    copy_dir(&d.join("a/shard-1-of-3"), &d.join("copy"));
    let e = err(&printwatt(&["merge", "a", "copy", "--out", "m"], &d, &[]));
    assert!(e.contains("shard 1 of 3 is given twice"), "{e}");
    // A damaged rows file.
    let rows = d.join("a/shard-2-of-3/rows.postcard");
    let mut b = std::fs::read(&rows).unwrap();
    let n = b.len();
    b[n / 2] ^= 0x40;
    std::fs::write(&rows, b).unwrap();
    let e = err(&printwatt(&["merge", "a", "--out", "m"], &d, &[]));
    assert!(e.contains("damaged or replaced"), "{e}");
    assert!(!d.join("m").exists(), "a refused merge wrote its output");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn merge_refuses_shards_whose_input_file_changed_since_they_ran() {
    let d = scratch("changed");
    for k in 0..2 {
        ok(&sweep(
            &["--shard", &format!("{k}/2"), "--out", "a"],
            &d,
            &[],
        ));
    }
    let p = d.join("wall.gcode");
    let mut text = std::fs::read_to_string(&p).unwrap();
    text.push_str("; edited after the shards ran\n");
    std::fs::write(&p, text).unwrap();
    let e = err(&printwatt(&["merge", "a", "--out", "m"], &d, &[]));
    assert!(e.contains("wall.gcode changed since the shards ran"), "{e}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn shard_auto_reads_the_slurm_array_and_the_kubernetes_index() {
    let d = scratch("auto");
    let slurm = [
        ("SLURM_ARRAY_TASK_ID", "2"),
        ("SLURM_ARRAY_TASK_MIN", "1"),
        ("SLURM_ARRAY_TASK_MAX", "2"),
        ("SLURM_ARRAY_TASK_COUNT", "2"),
    ];
    let o = ok(&sweep(&["--shard", "auto", "--out", "s"], &d, &slurm));
    assert!(o.contains("shard 1 of 2 (from the Slurm job array)"), "{o}");
    assert!(d.join("s/shard-1-of-2/shard.json").is_file());
    let o = ok(&sweep(
        &["--shard", "auto/2", "--out", "s"],
        &d,
        &[("JOB_COMPLETION_INDEX", "0")],
    ));
    assert!(
        o.contains("shard 0 of 2 (from the Kubernetes Indexed Job)"),
        "{o}"
    );
    ok(&printwatt(&["merge", "s", "--out", "m"], &d, &[]));
    let e = err(&sweep(&["--shard", "auto", "--out", "s"], &d, &[]));
    assert!(e.contains("SLURM_ARRAY_TASK_ID"), "{e}");
    // Never replaced without --force.
    let e = err(&sweep(&["--shard", "0/2", "--out", "s"], &d, &[]));
    assert!(e.contains("shard-0-of-2"), "{e}");
    ok(&sweep(
        &["--shard", "0/2", "--out", "s", "--force"],
        &d,
        &[],
    ));
    // A shard needs a place to go.
    let e = err(&sweep(&["--shard", "0/2"], &d, &[]));
    assert!(e.contains("--out"), "{e}");
    let _ = std::fs::remove_dir_all(&d);
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
}

#[test]
fn uncertainty_study_shards_merge_to_the_single_run_files_bit_for_bit() {
    // `optimise --uncertainty N` split over its draws.
    let d = scratch("study");
    let job = [
        "optimise",
        "--x",
        "1.5:1.9:0.1",
        "--y",
        "-0.5:0.5:0.25",
        "--yaw",
        "90",
        "--path",
        "wall.gcode",
        "--max-evals",
        "12",
        "--uncertainty",
        "5",
        "--seed",
        "3",
    ];
    let run = |extra: &[&str]| {
        let mut a: Vec<&str> = job.to_vec();
        a.extend(extra);
        printwatt(&a, &d, &[])
    };
    let single = ok(&run(&["--out", "single", "--threads", "2"]));
    assert!(single.contains("uncertainty"), "{single}");
    for (k, threads) in [(1, "2"), (0, "1")] {
        let o = ok(&run(&[
            "--shard",
            &format!("{k}/2"),
            "--out",
            "parts",
            "--threads",
            threads,
        ]));
        assert!(o.contains(&format!("shard {k} of 2")), "{o}");
        assert!(
            !d.join("parts/summary.json").exists(),
            "a shard writes no run"
        );
    }
    let merged = ok(&printwatt(&["merge", "parts", "--out", "merged"], &d, &[]));
    // The answer, line for line, but the run's time and where its report went.
    let answer = |s: &str| -> Vec<String> {
        s.lines()
            .filter(|l| !l.starts_with("grid ") && !l.starts_with("report:"))
            .map(str::to_string)
            .collect()
    };
    assert_eq!(
        answer(&single),
        answer(&merged),
        "the terminal answers differ"
    );
    assert!(single.contains("saving against the baseline"), "{single}");
    for f in ["summary.json", "placements.csv", "report.html"] {
        let a = std::fs::read(d.join("single").join(f)).unwrap();
        let b = std::fs::read(d.join("merged").join(f)).unwrap();
        assert!(a == b, "{f} differs between the single run and the merge");
    }
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("merged/summary.json")).unwrap())
            .unwrap();
    let u = &s["optimise"]["uncertainty"];
    assert_eq!(u["draws"], 5, "{u}");
    assert_eq!(u["per_draw_j"].as_array().map(Vec::len), Some(5));
    let facts: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("merged/run.json")).unwrap()).unwrap();
    assert_eq!(facts["draws"], 5);
    // Half the shards are not a study; a shard without --uncertainty is refused by the parser.
    let e = err(&printwatt(
        &["merge", "parts/shard-0-of-2", "--out", "m2"],
        &d,
        &[],
    ));
    assert!(e.contains("missing"), "{e}");
    let mut a: Vec<&str> = job[..job.len() - 4].to_vec();
    a.extend(["--shard", "0/2", "--out", "p2"]);
    let e = err(&printwatt(&a, &d, &[]));
    assert!(e.contains("--uncertainty"), "{e}");
    let _ = std::fs::remove_dir_all(&d);
}

/// A design study over the scratch directory's wall: two robots, a cell in reach and one out
/// of reach of both (its cases have no answer), the options of every case small.
const STUDY: &str = r#"
[study]
name = "two-arms"
options = ["--max-evals", "12", "--seed", "3"]

[[robot]]
name = "big"
robot = "abb_irb6700_200_260"

[[robot]]
name = "small"
robot = "abb_irb4600_40_255"

[[cell]]
name = "near"
x = "1.3:1.7:0.2"
y = "-0.25:0.25:0.25"
yaw = 90

[[cell]]
name = "far"
x = 4.5
y = 0
yaw = "0,90"

[[path]]
name = "wall"
file = "wall.gcode"
"#;

#[test]
fn design_study_shards_merge_to_the_single_run_files_bit_for_bit() {
    // Design studies split by case, merged into the single run's directory.
    let d = scratch("design");
    std::fs::write(d.join("study.toml"), STUDY).unwrap();
    let single = ok(&printwatt(
        &["study", "study.toml", "--out", "single", "--threads", "2"],
        &d,
        &[],
    ));
    // Shard 1 from a Kubernetes Indexed Job's index, shard 0 from a Slurm array, one thread.
    let o = ok(&printwatt(
        &["study", "study.toml", "--shard", "auto/2", "--out", "parts"],
        &d,
        &[("JOB_COMPLETION_INDEX", "1")],
    ));
    assert!(
        o.contains("shard 1 of 2 (from the Kubernetes Indexed Job)"),
        "{o}"
    );
    let o = ok(&printwatt(
        &[
            "study",
            "study.toml",
            "--shard",
            "auto",
            "--out",
            "parts",
            "--threads",
            "1",
        ],
        &d,
        &[
            ("SLURM_ARRAY_TASK_ID", "0"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_MAX", "1"),
        ],
    ));
    assert!(o.contains("shard 0 of 2 (from the Slurm job array)"), "{o}");
    assert!(o.contains("2 of 4 cases"), "{o}");
    let elsewhere = d.join("elsewhere");
    std::fs::create_dir_all(&elsewhere).unwrap();
    let merged = ok(&printwatt(
        &["merge", "../parts", "--out", "../merged"],
        &elsewhere,
        &[],
    ));
    let answer = |s: &str| -> Vec<String> {
        s.lines()
            .filter(|l| !l.starts_with("report:"))
            .map(str::to_string)
            .collect()
    };
    assert_eq!(
        answer(&single),
        answer(&merged),
        "the terminal answers differ"
    );
    let files = |dir: &str| -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(d.join(dir))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|f| !f.starts_with('.') && f != "run.json")
            .collect();
        v.sort();
        v
    };
    assert_eq!(files("single"), files("merged"));
    // Two answered cases, each with its report page; the far cell's cases have none.
    assert_eq!(
        files("single"),
        [
            "case-0-big-near-wall.html",
            "case-2-small-near-wall.html",
            "report.html",
            "study.csv",
            "summary.json"
        ]
    );
    for f in files("single") {
        let a = std::fs::read(d.join("single").join(&f)).unwrap();
        let b = std::fs::read(d.join("merged").join(&f)).unwrap();
        assert!(a == b, "{f} differs between the single run and the merge");
    }
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("single/summary.json")).unwrap())
            .unwrap();
    let cases = s["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 4);
    assert_eq!(cases[0]["status"], "feasible");
    assert_eq!(cases[1]["status"], "no answer");
    assert!(
        cases[1]["reason"].as_str().unwrap().contains("reach"),
        "{}",
        cases[1]["reason"]
    );
    // The cheaper arm prints the wall; the combinations that print it come first.
    let best = &s["best_per_path"][0];
    let e0 = cases[0]["outcome"]["energy_j"].as_f64().unwrap();
    let e2 = cases[2]["outcome"]["energy_j"].as_f64().unwrap();
    assert_eq!(best["energy_j"].as_f64().unwrap(), e0.min(e2));
    assert_eq!(s["combinations"][0]["feasible"], 1);
    assert_eq!(s["combinations"][3]["feasible"], 0);
    let facts: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("merged/run.json")).unwrap()).unwrap();
    assert_eq!(facts["cases"], 4);
    assert_eq!(facts["shards"], 2);
    // A JSON run without --out writes nothing but the JSON (the same summary).
    let j: serde_json::Value = serde_json::from_str(&ok(&printwatt(
        &["study", "study.toml", "--json", "--threads", "1"],
        &d,
        &[],
    )))
    .unwrap();
    assert_eq!(j["cases"], s["cases"]);
    assert!(!d.join("results").exists(), "a JSON run wrote files");
    // The single run's directory is not replaced without --force.
    let e = err(&printwatt(
        &["study", "study.toml", "--out", "single"],
        &d,
        &[],
    ));
    assert!(e.contains("exists"), "{e}");
    let _ = std::fs::remove_dir_all(&d);
}

/// Write [`STUDY`] into `d` and run it as `n` shards into `d/parts`.
fn study_shards(d: &Path, n: usize) {
    std::fs::write(d.join("study.toml"), STUDY).unwrap();
    for k in 0..n {
        let spec = format!("{k}/{n}");
        ok(&printwatt(
            &["study", "study.toml", "--shard", &spec, "--out", "parts"],
            d,
            &[],
        ));
    }
}

#[test]
fn merge_refuses_study_shards_whose_study_file_changed_since_they_ran() {
    let d = scratch("design-changed");
    study_shards(&d, 2);
    std::fs::write(d.join("study.toml"), STUDY.replace("\"12\"", "\"13\"")).unwrap();
    let e = err(&printwatt(&["merge", "parts", "--out", "merged"], &d, &[]));
    assert!(e.contains("study.toml changed since the shards ran"), "{e}");
    assert!(!d.join("merged").exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_study_names_the_case_or_entry_at_fault_before_any_work() {
    let d = scratch("design-errors");
    let run = |text: &str| {
        std::fs::write(d.join("s.toml"), text).unwrap();
        err(&printwatt(&["study", "s.toml", "--out", "out"], &d, &[]))
    };
    // A path that is not there: the case is named, nothing is written.
    let e = run(&STUDY.replace("wall.gcode", "wal.gcode"));
    assert!(e.contains("case 0 (big / near / wall)"), "{e}");
    assert!(e.contains("wal.gcode"), "{e}");
    assert!(!d.join("out").exists());
    // Options the study owns, and the objective anywhere but [study].
    let e = run(&STUDY.replace("\"--seed\", \"3\"", "\"--out\", \"x\""));
    assert!(
        e.contains("[study] options: `--out` is not an option of a study case"),
        "{e}"
    );
    let e = run(&STUDY.replace(
        "name = \"small\"",
        "name = \"small\"\noptions = [\"--objective\", \"drives\"]",
    ));
    assert!(
        e.contains("robot `small` options: `--objective` belongs in [study] options"),
        "{e}"
    );
    // An option that does not parse names the case; a TOML error names the line.
    let e = run(&STUDY.replace("\"--seed\", \"3\"", "\"--sed\", \"3\""));
    assert!(
        e.contains("case 0 (big / near / wall): its options do not parse"),
        "{e}"
    );
    let e = run(&STUDY.replace("yaw = 90", "yaw = [90]"));
    assert!(e.contains("s.toml (line "), "{e}");
    assert!(!d.join("out").exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn merge_refuses_a_study_shard_whose_case_page_was_damaged() {
    let d = scratch("design-page");
    study_shards(&d, 2);
    // Case 2 (small / near / wall) is shard 0's second case; its page sits beside the rows.
    let page = d.join("parts/shard-0-of-2/case-2-small-near-wall.html");
    let mut text = std::fs::read_to_string(&page).unwrap();
    text.push_str("<!-- edited -->");
    std::fs::write(&page, text).unwrap();
    let e = err(&printwatt(&["merge", "parts", "--out", "merged"], &d, &[]));
    assert!(
        e.contains("case-2-small-near-wall.html: damaged or replaced"),
        "{e}"
    );
    assert!(!d.join("merged").exists());
    std::fs::remove_file(&page).unwrap();
    let e = err(&printwatt(&["merge", "parts", "--out", "merged"], &d, &[]));
    assert!(
        e.contains("case 2 (small / near / wall): its report page"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&d);
}
