//! Nothing lost, nothing crashes, under scripted faults: a closed pipe and a full disk on
//! standard output, two runs writing one output at once, a replacement killed half way, a lock
//! left by a killed run, and a merge asked to write into its own shards. One test per guard,
//! named after it.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_printwatt"));
    for k in [
        "PRINTWATT_TEST_WRITE_DELAY_MS",
        "PRINTWATT_TEST_REPLACE_DELAY_MS",
        "PRINTWATT_TEST_COMMIT_DELAY_MS",
        "SLURM_ARRAY_TASK_ID",
        "JOB_COMPLETION_INDEX",
    ] {
        c.env_remove(k);
    }
    c
}

fn scratch(name: &str) -> PathBuf {
    let d = common::scratch("faults", name);
    std::fs::copy(
        common::root().join("paths/default.gcode"),
        d.join("wall.gcode"),
    )
    .unwrap();
    std::fs::write(d.join("p.gcode"), SHORT).unwrap();
    d
}

/// A short printing G-code (100 mm at 150 mm/s).
const SHORT: &str = "G21\nG90\nG0 X0 Y0 Z20 F6000\nG1 X100 E1 F9000\n";

/// A small sweep over the default robot.
const GRID: [&str; 9] = [
    "sweep",
    "--x",
    "1.5:1.7:0.1",
    "--y",
    "0",
    "--yaw",
    "90",
    "--path",
    "wall.gcode",
];

const ENERGY: [&str; 7] = [
    "energy",
    "--robot",
    "abb_irb4600_40_255",
    "--path",
    "p.gcode",
    "--at",
    "1.5,0,0.3,0",
];

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Every command that prints, as a user would run it (text and `--json`).
fn printing_commands() -> Vec<Vec<&'static str>> {
    let mut v: Vec<Vec<&str>> = vec![vec!["robots"], vec!["robots", "--json"]];
    let mut e = ENERGY.to_vec();
    e.push("--no-csv");
    v.push(e.clone());
    e.push("--json");
    v.push(e);
    v.push(GRID.to_vec());
    let mut g = GRID.to_vec();
    g.push("--json");
    v.push(g);
    // `optimise` text output.
    v.push(vec![
        "optimise",
        "--path",
        "p.gcode",
        "--max-evals",
        "5",
        "--x",
        "1.5",
        "--y",
        "0",
        "--yaw",
        "90",
        "--no-report",
    ]);
    v
}

#[test]
fn a_closed_pipe_on_stdout_ends_every_command_quietly() {
    let d = scratch("pipe");
    for args in printing_commands() {
        let (r, w) = std::io::pipe().unwrap();
        drop(r); // the reader is gone before the first line is written
        let o = bin()
            .args(&args)
            .current_dir(&d)
            .stdout(w)
            .stderr(Stdio::piped())
            .output()
            .unwrap();
        let e = stderr(&o);
        assert!(!e.contains("panicked"), "{args:?}: {e}");
        assert!(
            !e.contains("error"),
            "{args:?}: a closed pipe is not an error to tell: {e}"
        );
        assert_eq!(
            o.status.code(),
            Some(141),
            "{args:?}: status {:?}: {e}",
            o.status
        );
    }
}

#[test]
fn a_full_disk_on_stdout_is_a_one_line_error_in_every_command() {
    let d = scratch("full");
    for args in printing_commands() {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let o = bin()
            .args(&args)
            .current_dir(&d)
            .stdout(full)
            .stderr(Stdio::piped())
            .output()
            .unwrap();
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {e}");
        assert!(!e.contains("panicked"), "{args:?}: {e}");
        let last = e.lines().last().unwrap_or_default();
        assert!(
            last.starts_with("error: writing to standard output:") && last.contains("No space"),
            "{args:?}: {e}"
        );
        assert_eq!(
            e.lines().filter(|l| l.starts_with("error")).count(),
            1,
            "{e}"
        );
    }
}

#[test]
fn merge_refuses_an_output_equal_to_or_inside_a_shard_with_or_without_force() {
    let d = scratch("merge");
    for k in 0..2 {
        let mut a = GRID.to_vec();
        let spec = format!("{k}/2");
        a.extend(["--shard", &spec, "--out", "sh"]);
        let o = bin().args(&a).current_dir(&d).output().unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let snapshot = |d: &Path| -> Vec<(PathBuf, Vec<u8>)> {
        let mut v = Vec::new();
        for s in ["sh/shard-0-of-2", "sh/shard-1-of-2"] {
            for e in std::fs::read_dir(d.join(s)).unwrap().flatten() {
                v.push((e.path(), std::fs::read(e.path()).unwrap()));
            }
        }
        v.sort();
        v
    };
    let before = snapshot(&d);
    for out in [
        "sh/shard-0-of-2",
        "sh/shard-0-of-2/merged",
        "sh",
        "./sh/../sh/shard-1-of-2",
    ] {
        for force in [false, true] {
            let mut a = vec!["merge", "sh", "--out", out];
            if force {
                a.push("--force");
            }
            let o = bin().args(&a).current_dir(&d).output().unwrap();
            let e = stderr(&o);
            assert!(
                !o.status.success(),
                "merge --out {out} (force {force}) must fail"
            );
            assert!(
                e.contains("refusing to write") && e.contains("input"),
                "{e}"
            );
        }
    }
    assert_eq!(snapshot(&d), before, "the shards are untouched");
    // The same merge elsewhere still works.
    let o = bin()
        .args(["merge", "sh", "--out", "merged"])
        .current_dir(&d)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn two_runs_writing_one_new_file_at_once_fail_the_second() {
    let d = scratch("race");
    let spawn = || {
        let mut a = ENERGY.to_vec();
        a.extend(["--out", "o"]);
        bin()
            .args(&a)
            .current_dir(&d)
            .env("PRINTWATT_TEST_WRITE_DELAY_MS", "1500")
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let a = spawn();
    let b = spawn();
    let (oa, ob) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
    let wins = [&oa, &ob].iter().filter(|o| o.status.success()).count();
    assert_eq!(
        wins,
        1,
        "exactly one writes: {} / {}",
        stderr(&oa),
        stderr(&ob)
    );
    let loser = if oa.status.success() { &ob } else { &oa };
    assert!(stderr(loser).contains("exists"), "{}", stderr(loser));
    // No temporary file is left.
    let left: Vec<_> = std::fs::read_dir(d.join("o"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name())
        .collect();
    assert_eq!(left.len(), 1, "{left:?}");
}

fn wait_for(what: &str, mut f: impl FnMut() -> bool) {
    let t = Instant::now();
    while !f() {
        assert!(
            t.elapsed() < Duration::from_secs(120),
            "waited too long for {what}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn run_files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| {
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect();
    v.sort();
    v
}

#[test]
fn a_killed_force_replacement_is_restored_on_the_next_run() {
    let d = scratch("killed");
    let mut a = GRID.to_vec();
    a.extend(["--out", "run"]);
    let o = bin().args(&a).current_dir(&d).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let before = run_files(&d.join("run"));
    // Replace it, and kill the replacement between moving the old run aside and moving the
    // new one in.
    let mut f = a.clone();
    f.extend(["--force", "--objective", "mechanical"]);
    let mut child = bin()
        .args(&f)
        .current_dir(&d)
        .env("PRINTWATT_TEST_REPLACE_DELAY_MS", "30000")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let old = d.join(format!(".run.printwatt-old-{}", child.id()));
    wait_for("the old run moved aside", || old.exists());
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(!d.join("run").exists(), "killed between the two renames");
    // The next run without --force puts the old run back (and so refuses to replace it).
    let o = bin().args(&a).current_dir(&d).output().unwrap();
    assert!(!o.status.success());
    assert!(stderr(&o).contains("exists"), "{}", stderr(&o));
    assert_eq!(
        run_files(&d.join("run")),
        before,
        "the earlier run is back, unchanged"
    );
    assert!(!old.exists());
}

#[test]
fn a_lock_left_by_a_killed_run_or_naming_a_reused_pid_does_not_block() {
    let d = scratch("lock");
    // A lock file naming PID 1 (running, but not printwatt: a reused PID) and no flock.
    std::fs::write(d.join(".run.printwatt-lock"), "1\n").unwrap();
    let mut a = GRID.to_vec();
    a.extend(["--out", "run"]);
    let o = bin().args(&a).current_dir(&d).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!d.join(".run.printwatt-lock").exists());
    // A run killed while it holds the lock: the lock goes with it.
    let mut f = a.clone();
    f.push("--force");
    let mut child = bin()
        .args(&f)
        .current_dir(&d)
        .env("PRINTWATT_TEST_COMMIT_DELAY_MS", "30000")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let staging = d.join(format!(".run.printwatt-tmp-{}", child.id()));
    wait_for("the run to write", || staging.exists());
    // While it runs, a second run into the same directory is refused, naming the first.
    let o = bin().args(&f).current_dir(&d).output().unwrap();
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("being written by another printwatt run") && e.contains(&child.id().to_string()),
        "{e}"
    );
    child.kill().unwrap();
    child.wait().unwrap();
    let o = bin().args(&f).current_dir(&d).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        !staging.exists(),
        "the killed run's staging directory is removed"
    );
}

#[test]
fn an_input_without_end_stops_at_the_stated_size_naming_the_file() {
    let d = scratch("urandom");
    let t = Instant::now();
    let o = bin()
        .args([
            "compare",
            "--robot",
            "abb_irb4600_40_255",
            "--log",
            "/dev/urandom",
        ])
        .current_dir(&d)
        .env("PRINTWATT_MAX_INPUT_BYTES", "10000000")
        .output()
        .unwrap();
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("/dev/urandom") && e.contains("longer than 10000000 bytes"),
        "{e}"
    );
    assert!(t.elapsed() < Duration::from_secs(60));
    // Path and study readers too (a file name with the reader's extension, without end).
    std::os::unix::fs::symlink("/dev/zero", d.join("zero.gcode")).unwrap();
    std::os::unix::fs::symlink("/dev/zero", d.join("zero.toml")).unwrap();
    for args in [
        vec![
            "energy",
            "--robot",
            "abb_irb4600_40_255",
            "--path",
            "zero.gcode",
            "--at",
            "1.5,0,0.3,0",
        ],
        vec!["study", "zero.toml"],
    ] {
        let o = bin()
            .args(&args)
            .current_dir(&d)
            .env("PRINTWATT_MAX_INPUT_BYTES", "1000000")
            .output()
            .unwrap();
        assert!(!o.status.success());
        let e = stderr(&o);
        assert!(
            e.contains("zero.") && e.contains("longer than 1000000 bytes"),
            "{args:?}: {e}"
        );
    }
}
