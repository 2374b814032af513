//! Nothing lost, nothing crashes: one regression test per defect, named after what
//! it guards. Each runs the binary (or the library) the way a user would and checks the exit,
//! the message (file, line or field, what to do) and that no input was touched.

mod common;
use common::{root, run};

use std::path::{Path, PathBuf};
use std::process::Output;

fn tmp(name: &str) -> PathBuf {
    common::scratch("rob", name)
}

fn err(o: &Output) -> String {
    common::stderr_of(o)
}

/// A copy of a shipped robot in `dir/rob`.
fn robot_copy(dir: &Path) -> PathBuf {
    let r = dir.join("rob");
    std::fs::create_dir_all(&r).unwrap();
    let src = root().join("robots/abb_irb4600_40_255");
    for f in ["robot.urdf", "drive.toml"] {
        std::fs::copy(src.join(f), r.join(f)).unwrap();
    }
    // The collision meshes the URDF names (without them each link warns and a capsule stands in).
    std::fs::create_dir_all(r.join("collision")).unwrap();
    for e in std::fs::read_dir(src.join("collision")).unwrap() {
        let e = e.unwrap().path();
        std::fs::copy(&e, r.join("collision").join(e.file_name().unwrap())).unwrap();
    }
    r
}

/// A short printing G-code (100 mm at 150 mm/s).
const SHORT: &str = "G21\nG90\nG0 X0 Y0 Z20 F6000\nG1 X100 E1 F9000\n";

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn energy_at(dir: &Path, robot: &str, path: &str, extra: &[&str]) -> Output {
    let mut a = vec![
        "energy",
        "--robot",
        robot,
        "--path",
        path,
        "--at",
        "1.5,0,0.3,0",
    ];
    a.extend_from_slice(extra);
    run(&a, dir)
}

// ---- inputs overwritten -------------------------------------------------------------------

#[test]
fn energy_out_refuses_to_replace_the_robot_urdf() {
    let d = tmp("out-urdf");
    robot_copy(&d);
    write(&d, "p.gcode", SHORT);
    for f in ["rob/robot.urdf", "rob/drive.toml"] {
        let before = std::fs::read(d.join(f)).unwrap();
        // --out names a directory: an input file given there is refused, not replaced.
        let o = energy_at(&d, "rob", "p.gcode", &["--out", f]);
        assert!(!o.status.success());
        let e = err(&o);
        assert!(e.contains("not a directory") && e.contains(f), "{e}");
        assert_eq!(std::fs::read(d.join(f)).unwrap(), before, "{f} untouched");
    }
}

#[test]
fn simulate_out_refuses_to_replace_its_own_trajectory_or_path() {
    let d = tmp("sim-out");
    robot_copy(&d);
    let p = write(&d, "p.gcode", SHORT);
    let before = std::fs::read(&p).unwrap();
    let o = run(
        &[
            "simulate",
            "--robot",
            "rob",
            "--path",
            "p.gcode",
            "--at",
            "1.5,0,0.3,0",
            "--out",
            "p.gcode",
        ],
        &d,
    );
    assert!(!o.status.success());
    assert!(err(&o).contains("not a directory"), "{}", err(&o));
    assert_eq!(std::fs::read(&p).unwrap(), before);
    // The log is `<out>/log.csv`: a trajectory of that name is an input, refused.
    let t = write(
        &d,
        "log.csv",
        "t,q1,q2,q3,q4,q5,q6\n0,0,0,0,0,0.5,0\n0.1,0,0,0,0,0.5,0\n0.2,0,0,0,0,0.5,0\n",
    );
    let o = run(
        &[
            "simulate",
            "--robot",
            "rob",
            "--trajectory",
            "log.csv",
            "--force",
        ],
        &d,
    );
    assert!(!o.status.success());
    assert!(err(&o).contains("input of this command"), "{}", err(&o));
    // A hard link to the input is the same file (device + inode), under another name.
    std::fs::create_dir_all(d.join("o")).unwrap();
    std::fs::hard_link(&t, d.join("o/log.csv")).unwrap();
    let o = run(
        &[
            "simulate",
            "--robot",
            "rob",
            "--trajectory",
            "log.csv",
            "--out",
            "o",
            "--force",
        ],
        &d,
    );
    assert!(!o.status.success());
    assert!(err(&o).contains("input of this command"), "{}", err(&o));
}

#[test]
fn identify_drive_out_refuses_to_replace_the_measurement_log_even_with_force() {
    let d = tmp("id-log");
    robot_copy(&d);
    let o = run(
        &[
            "simulate", "--robot", "rob", "--excite", "4", "--rate", "100", "--out", ".",
        ],
        &d,
    );
    assert!(o.status.success(), "{}", err(&o));
    std::fs::copy(d.join("log.csv"), d.join("val.csv")).unwrap();
    for target in ["log.csv", "val.csv", "rob/robot.urdf"] {
        let before = std::fs::read(d.join(target)).unwrap();
        let o = run(
            &[
                "identify",
                "--robot",
                "rob",
                "--log",
                "log.csv",
                "--validate-log",
                "val.csv",
                "--effects",
                "coulomb",
                "--drive-out",
                target,
                "--force",
            ],
            &d,
        );
        assert!(!o.status.success(), "{target}");
        assert!(err(&o).contains("input of this command"), "{}", err(&o));
        assert_eq!(std::fs::read(d.join(target)).unwrap(), before, "{target}");
    }
}

#[test]
fn sweep_run_refuses_to_replace_the_set_it_reads() {
    let d = tmp("sweep-set");
    std::fs::create_dir_all(d.join("sets")).unwrap();
    let set = write(
        &d,
        "sets/placements.csv",
        "name,x[mm],y[mm],z[mm],yaw[deg]\nP1,1600,0,200,0\n",
    );
    let before = std::fs::read(&set).unwrap();
    let path = root().join("paths/seed000_test_path.gcode");
    let o = run(
        &[
            "sweep",
            "--path",
            path.to_str().unwrap(),
            "--set",
            "sets/placements.csv",
            "--results-dir",
            ".",
            "--run",
            "sets",
        ],
        &d,
    );
    assert!(!o.status.success());
    assert!(err(&o).contains("input of this command"), "{}", err(&o));
    assert_eq!(std::fs::read(&set).unwrap(), before);
}

#[test]
fn a_users_own_summary_json_in_a_run_directory_is_never_replaced() {
    use printwatt::output::{Existing, Inputs, RunDir};
    let d = tmp("own-summary");
    std::fs::create_dir_all(d.join("mine")).unwrap();
    // The user's own file, with printwatt's file name but not printwatt's content.
    let own = write(&d, "mine/summary.json", "{\"my\": \"notes\"}");
    let e = RunDir::begin(&d, "mine", &Inputs::new(), Existing::Replace).unwrap_err();
    assert!(e.to_string().contains("summary.json"), "{e}");
    assert_eq!(
        std::fs::read_to_string(&own).unwrap(),
        "{\"my\": \"notes\"}"
    );
    // A printwatt run is replaced; once the user edits one of its files, it is not.
    let mut rd = RunDir::begin(&d, "ours", &Inputs::new(), Existing::Replace).unwrap();
    rd.write("summary.json", b"{}").unwrap();
    rd.commit().unwrap();
    let rd = RunDir::begin(&d, "ours", &Inputs::new(), Existing::Replace).unwrap();
    drop(rd);
    std::fs::write(d.join("ours/summary.json"), "{\"edited\": 1}").unwrap();
    let e = RunDir::begin(&d, "ours", &Inputs::new(), Existing::Replace).unwrap_err();
    assert!(
        e.to_string().contains("changed after printwatt wrote it"),
        "{e}"
    );
}

// ---- interrupted or concurrent runs -------------------------------------------------------

/// A PID no process has (above Linux's largest pid_max).
const DEAD_PID: u32 = 999_999_999;

#[test]
fn stale_temp_files_of_a_killed_run_do_not_block_later_runs() {
    use printwatt::output::{Existing, Inputs, RunDir};
    let d = tmp("stale");
    let mut rd = RunDir::begin(&d, "r", &Inputs::new(), Existing::Replace).unwrap();
    rd.write("summary.json", b"{}").unwrap();
    rd.commit().unwrap();
    // What a SIGKILL leaves: a temp file in the run, a staging directory, an old directory and
    // the lock, all of a dead process.
    std::fs::write(d.join(format!("r/summary.json.tmp-{DEAD_PID}")), "x").unwrap();
    std::fs::create_dir_all(d.join(format!(".r.printwatt-tmp-{DEAD_PID}"))).unwrap();
    std::fs::create_dir_all(d.join(format!(".r.printwatt-old-{DEAD_PID}"))).unwrap();
    std::fs::write(d.join(".r.printwatt-lock"), format!("{DEAD_PID}\n")).unwrap();
    let mut rd = RunDir::begin(&d, "r", &Inputs::new(), Existing::Replace).unwrap();
    rd.write("summary.json", b"{\"new\": 1}").unwrap();
    rd.commit().unwrap();
    let left: Vec<String> = std::fs::read_dir(&d)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(left, vec!["r".to_string()], "stale files cleaned");
    assert!(!d.join(format!("r/summary.json.tmp-{DEAD_PID}")).exists());
    // The same for a single file written atomically.
    let f = d.join("out.csv");
    std::fs::write(d.join(format!("out.csv.tmp-{DEAD_PID}")), "x").unwrap();
    printwatt::output::write_atomic(&f, b"a").unwrap();
    assert!(!d.join(format!("out.csv.tmp-{DEAD_PID}")).exists());
}

#[test]
fn a_run_directory_is_replaced_whole_or_not_at_all() {
    use printwatt::output::{Existing, Inputs, RunDir};
    let d = tmp("whole");
    let mut rd = RunDir::begin(&d, "r", &Inputs::new(), Existing::Replace).unwrap();
    rd.write("summary.json", b"old summary").unwrap();
    rd.write("placements.csv", b"old placements").unwrap();
    rd.commit().unwrap();
    // A run that fails half-way (dropped without commit): the old run is intact, nothing new.
    let mut rd = RunDir::begin(&d, "r", &Inputs::new(), Existing::Replace).unwrap();
    rd.write("summary.json", b"new summary").unwrap();
    drop(rd);
    assert_eq!(
        std::fs::read(d.join("r/summary.json")).unwrap(),
        b"old summary"
    );
    assert_eq!(
        std::fs::read(d.join("r/placements.csv")).unwrap(),
        b"old placements"
    );
    // A completed run replaces all of it: no old file survives beside a new one.
    let mut rd = RunDir::begin(&d, "r", &Inputs::new(), Existing::Replace).unwrap();
    rd.write("summary.json", b"new summary").unwrap();
    rd.commit().unwrap();
    assert_eq!(
        std::fs::read(d.join("r/summary.json")).unwrap(),
        b"new summary"
    );
    assert!(!d.join("r/placements.csv").exists());
}

#[test]
fn a_run_directorys_files_are_complete_when_it_is_committed_while_their_syncs_overlap() {
    // RunDir::write syncs each file on a thread of its own; commit waits for every sync before
    // the rename. Several files written back to back, one large: all complete after commit,
    // and the manifest records each file's content.
    use printwatt::output::{Existing, Inputs, RunDir};
    let d = tmp("overlap");
    let big: Vec<u8> = (0..4_000_000u32).map(|i| (i % 251) as u8).collect();
    let mut rd = RunDir::begin(&d, "r", &Inputs::new(), Existing::Replace).unwrap();
    rd.write("report.html", &big).unwrap();
    for k in 0..6 {
        rd.write(&format!("f{k}.txt"), format!("file {k}").as_bytes())
            .unwrap();
    }
    rd.commit().unwrap();
    assert_eq!(std::fs::read(d.join("r/report.html")).unwrap(), big);
    for k in 0..6 {
        assert_eq!(
            std::fs::read_to_string(d.join(format!("r/f{k}.txt"))).unwrap(),
            format!("file {k}")
        );
    }
    let manifest = std::fs::read_dir(d.join("r"))
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().starts_with('.'))
        .map(|e| std::fs::read_to_string(e.path()).unwrap())
        .next()
        .expect("a manifest");
    for k in 0..6 {
        assert!(manifest.contains(&format!("f{k}.txt")), "{manifest}");
    }
    // No staging directory is left beside the run.
    let left: Vec<String> = std::fs::read_dir(&d)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains("printwatt-tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

#[test]
fn a_second_run_into_a_locked_run_directory_fails_clearly() {
    use printwatt::output::{Existing, Inputs, RunDir};
    let d = tmp("lock");
    let first = RunDir::begin(&d, "r", &Inputs::new(), Existing::Replace).unwrap();
    let e = RunDir::begin(&d, "r", &Inputs::new(), Existing::Replace)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("being written by another printwatt run") && e.contains("PID"),
        "{e}"
    );
    drop(first);
    RunDir::begin(&d, "r", &Inputs::new(), Existing::Replace).unwrap();
}

#[test]
fn run_outside_results_dir_is_refused() {
    let d = tmp("escape");
    for bad in ["../../x", "/tmp/x", "a/../../b", "."] {
        let o = run(
            &[
                "sweep",
                "--at",
                "1.6,0,0,0",
                "--run",
                bad,
                "--results-dir",
                "res",
            ],
            &d,
        );
        assert!(!o.status.success(), "{bad}");
        assert!(
            err(&o).contains("must stay inside the results directory")
                && err(&o).contains("--results-dir"),
            "{bad}: {}",
            err(&o)
        );
    }
    assert!(!d.parent().unwrap().join("x").exists());
}

// ---- crashes ------------------------------------------------------------------------------

#[test]
fn deep_xml_is_an_error_not_a_stack_overflow() {
    let d = tmp("deep");
    let xml = format!(
        "<robot name=\"x\">{}{}</robot>",
        "<a>".repeat(20_000),
        "</a>".repeat(20_000)
    );
    write(&d, "deep.urdf", &xml);
    write(&d, "p.gcode", SHORT);
    let o = energy_at(&d, "deep.urdf", "p.gcode", &[]);
    assert_eq!(o.status.code(), Some(1), "{}", err(&o));
    assert!(
        err(&o).contains("deep.urdf:1:1: XML nested deeper than"),
        "{}",
        err(&o)
    );
}

#[test]
fn gcode_f1_5_is_refused_with_a_did_you_mean() {
    let d = tmp("f15");
    robot_copy(&d);
    write(&d, "p.gcode", "G21\nG90\nG0 X0 Y0 Z20\nG1 X1000 E1 F1.5\n");
    let o = energy_at(&d, "rob", "p.gcode", &[]);
    assert_eq!(o.status.code(), Some(1));
    let e = err(&o);
    assert!(
        e.contains("F1.5 mm/min is 0.025 mm/s; did you mean F1500?"),
        "{e}"
    );
    assert!(e.contains("line 4"), "{e}");
}

#[test]
fn gcode_f1_5_on_a_short_move_warns_with_a_did_you_mean() {
    // Short enough to stay within the sample budget (so it is timed), but the user is told.
    let d = tmp("f15short");
    robot_copy(&d);
    write(&d, "p.gcode", "G21\nG90\nG0 X0 Y0 Z20\nG1 X2 E1 F1.5\n");
    let o = energy_at(&d, "rob", "p.gcode", &[]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    let e = err(&o);
    assert!(e.contains("line 4"), "{e}");
    assert!(
        e.contains("F1.5 mm/min is 0.025 mm/s; did you mean F1500?"),
        "{e}"
    );
}

#[test]
fn huge_coordinates_are_an_error_not_a_panic_or_a_hang() {
    let d = tmp("huge");
    robot_copy(&d);
    let n308 = format!("1{}", "0".repeat(307));
    let n309 = format!("1{}", "0".repeat(308));
    for (name, x) in [
        ("a.gcode", n308.as_str()),
        ("b.gcode", n309.as_str()),
        ("c.gcode", "100000000"),
    ] {
        write(
            &d,
            name,
            &format!("G21\nG90\nG0 X0 Y0 Z20\nG1 X{x} E1 F9000\n"),
        );
        let o = energy_at(&d, "rob", name, &[]);
        assert_eq!(o.status.code(), Some(1), "{name}: {}", err(&o));
        let e = err(&o);
        assert!(
            e.contains(&format!("{name}:4")) || e.contains(&format!("{name}: ")),
            "{e}"
        );
        assert!(!e.contains("panicked"), "{e}");
        assert!(e.len() < 2000, "message clipped: {}", e.len());
    }
}

#[test]
fn slow_speeds_tiny_limits_and_short_periods_are_refused_before_allocating() {
    let d = tmp("slow");
    robot_copy(&d);
    // A CSV speed of 0.0001 mm/s.
    write(
        &d,
        "p.csv",
        "x[mm],y[mm],z[mm],speed[mm/s]\n0,0,0,0.0001\n100,0,0,0.0001\n",
    );
    let o = energy_at(&d, "rob", "p.csv", &[]);
    assert!(
        err(&o).contains("0.0001 mm/s is slower than any print"),
        "{}",
        err(&o)
    );
    // RAPID speeddata [0.001, …].
    write(
        &d,
        "p.mod",
        "MODULE M\n CONST speeddata vs := [0.001,500,5000,1000];\n CONST robtarget p0 := [[0,0,0],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n CONST robtarget p1 := [[1000,0,0],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n PROC main()\n  MoveL p0, vs, fine, tool0;\n  MoveL p1, vs, fine, tool0;\n ENDPROC\nENDMODULE\n",
    );
    let o = energy_at(&d, "rob", "p.mod", &[]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        err(&o).contains("0.001 mm/s is slower than any print"),
        "{}",
        err(&o)
    );
    // --period 1e-6 ms.
    write(&d, "p.gcode", SHORT);
    let o = energy_at(&d, "rob", "p.gcode", &["--period", "1e-6"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(err(&o).contains("interpolation period"), "{}", err(&o));
    // A 100 km move.
    write(
        &d,
        "km.gcode",
        "G21\nG90\nG0 X0 Y0 Z20\nG1 X100000000 E1 F9000\n",
    );
    let o = energy_at(&d, "rob", "km.gcode", &[]);
    assert!(
        err(&o).contains("long: check the coordinates"),
        "{}",
        err(&o)
    );
    // A jerk limit of 1e-9 rad/s³ in the drive file; a URDF velocity of 1e-9 rad/s.
    let drive = std::fs::read_to_string(d.join("rob/drive.toml")).unwrap();
    let j = drive
        .find("jerk_limit_rad_s3")
        .expect("drive has jerk limits");
    let eol = drive[j..].find('\n').unwrap() + j;
    let bad = format!("{}jerk_limit_rad_s3 = 1e-9{}", &drive[..j], &drive[eol..]);
    std::fs::create_dir_all(d.join("rj")).unwrap();
    std::fs::write(d.join("rj/drive.toml"), bad).unwrap();
    std::fs::copy(d.join("rob/robot.urdf"), d.join("rj/robot.urdf")).unwrap();
    let o = energy_at(&d, "rj", "p.gcode", &[]);
    let e = err(&o);
    assert!(
        e.contains("implausibly small") && e.contains("rj/drive.toml:"),
        "{e}"
    );
    let urdf = std::fs::read_to_string(d.join("rob/robot.urdf")).unwrap();
    let v = urdf.find("velocity=\"").unwrap() + 10;
    let q = urdf[v..].find('"').unwrap() + v;
    std::fs::write(
        d.join("v.urdf"),
        format!("{}1e-9{}", &urdf[..v], &urdf[q..]),
    )
    .unwrap();
    let o = energy_at(&d, "v.urdf", "p.gcode", &[]);
    assert!(err(&o).contains("implausibly small"), "{}", err(&o));
}

// ---- silent accepts and unclear errors ----------------------------------------------------

#[test]
fn wrist_min_nan_and_empty_list_items_are_refused() {
    let d = tmp("cli-nums");
    let o = run(&["sweep", "--at", "1.6,0,0,0", "--wrist-min", "nan"], &d);
    assert!(!o.status.success());
    assert!(err(&o).contains("--wrist-min NaN"), "{}", err(&o));
    let o = run(&["sweep", "--x", "1,,2", "--y", "0"], &d);
    assert!(!o.status.success());
    assert!(err(&o).contains("item 2 is empty"), "{}", err(&o));
    let o = run(
        &[
            "energy", "--robot", "ur10e", "--path", "x.gcode", "--at", "1,,2,0",
        ],
        &d,
    );
    assert!(!o.status.success());
}

#[test]
fn utf8_bom_and_cr_only_line_endings_are_read() {
    let d = tmp("bom");
    robot_copy(&d);
    let csv = "x[mm],y[mm],z[mm]\n0,0,0\n100,0,0\n";
    std::fs::write(
        d.join("bom.csv"),
        [b"\xEF\xBB\xBF".as_slice(), csv.as_bytes()].concat(),
    )
    .unwrap();
    std::fs::write(d.join("cr.csv"), csv.replace('\n', "\r")).unwrap();
    std::fs::write(
        d.join("bom.gcode"),
        [b"\xEF\xBB\xBF".as_slice(), SHORT.as_bytes()].concat(),
    )
    .unwrap();
    std::fs::write(d.join("cr.gcode"), SHORT.replace('\n', "\r")).unwrap();
    for f in ["bom.csv", "cr.csv", "bom.gcode", "cr.gcode"] {
        let o = energy_at(&d, "rob", f, &["--no-csv"]);
        assert!(o.status.success(), "{f}: {}", err(&o));
    }
}

#[test]
fn invalid_utf8_names_line_and_byte() {
    let d = tmp("utf8");
    robot_copy(&d);
    std::fs::write(
        d.join("bad.csv"),
        b"x[mm],y[mm],z[mm]\n0,0,0\n100,0\xff,0\n",
    )
    .unwrap();
    let o = energy_at(&d, "rob", "bad.csv", &[]);
    let e = err(&o);
    assert!(e.contains("bad.csv:3:6: invalid UTF-8 (byte 0xFF"), "{e}");
}

#[test]
fn a_5_mb_token_is_not_echoed_whole() {
    let d = tmp("token");
    robot_copy(&d);
    let tok = "x".repeat(5_000_000);
    write(&d, "t.gcode", &format!("G21\nG1 X{tok}\n"));
    let o = energy_at(&d, "rob", "t.gcode", &[]);
    assert_eq!(o.status.code(), Some(1));
    assert!(err(&o).len() < 3000, "{} bytes of message", err(&o).len());
    assert!(err(&o).contains("t.gcode:2"), "{}", err(&o));
}

#[test]
fn file_exists_error_names_the_path_and_force_before_anything_is_written() {
    let d = tmp("exists");
    robot_copy(&d);
    let o = run(
        &[
            "simulate", "--robot", "rob", "--excite", "4", "--rate", "100", "--out", ".",
        ],
        &d,
    );
    assert!(o.status.success(), "{}", err(&o));
    // --out naming an existing file: refused before anything is computed or written.
    write(&d, "outfile", "x");
    let identify_into = |out: &str| {
        run(
            &[
                "identify",
                "--robot",
                "rob",
                "--log",
                "log.csv",
                "--effects",
                "coulomb",
                "--out",
                out,
            ],
            &d,
        )
    };
    let o = identify_into("outfile");
    assert!(!o.status.success());
    let e = err(&o);
    assert!(e.contains("outfile exists and is not a directory"), "{e}");
    // An earlier calibrated robot in --out: the message names it and --force.
    std::fs::create_dir_all(d.join("id")).unwrap();
    write(&d, "id/rob.calibrated.toml", "# earlier\n");
    let o = identify_into("id");
    assert!(!o.status.success());
    let e = err(&o);
    assert!(
        e.contains("id/rob.calibrated.toml exists already: pass --force"),
        "{e}"
    );
    assert_eq!(
        std::fs::read_to_string(d.join("id/rob.calibrated.toml")).unwrap(),
        "# earlier\n"
    );
    assert!(!d.join("id/ladder.md").exists(), "nothing half written");
}

// ---- warnings are shown; readers refuse what they cannot read -----------------------------

#[test]
fn reader_warnings_reach_stderr_and_json_with_file_and_line() {
    let d = tmp("warn");
    robot_copy(&d);
    write(
        &d,
        "sp.csv",
        "x[mm],y[mm],z[mm],spede[mm/s]\n0,0,0,100\n100,0,0,100\n",
    );
    let o = energy_at(&d, "rob", "sp.csv", &["--out", "o.csv", "--json"]);
    assert!(o.status.success(), "{}", err(&o));
    assert!(
        err(&o).contains("warning: sp.csv:1: unknown column 'spede'"),
        "{}",
        err(&o)
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let w = &v["warnings"][0];
    assert_eq!(w["file"], "sp.csv");
    assert_eq!(w["line"], 1);
    assert!(w["message"]
        .as_str()
        .unwrap()
        .contains("did you mean 'speed'"));
}

#[test]
fn a_file_with_only_travel_moves_says_so() {
    let d = tmp("g0");
    robot_copy(&d);
    write(&d, "g0.gcode", "G21\nG90\nG0 X0 Y0 Z20\nG0 X100\n");
    let o = energy_at(&d, "rob", "g0.gcode", &["--out", "o.csv"]);
    assert!(err(&o).contains("no print moves"), "{}", err(&o));
}

#[test]
fn gnan_word_is_an_error_not_a_dropped_move() {
    let e = printwatt::toolpath::parse_gcode(
        "G21\nG1 X0 Y0 Z0 F1500\nGnan X5\nG1 X10 E2\n",
        "n.gcode",
        &Default::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.starts_with("n.gcode:3:2: expected a number after 'G'"),
        "{e}"
    );
}

#[test]
fn duplicate_rapid_robtargets_are_reported() {
    let t = "MODULE M\n CONST robtarget p0 := [[0,0,0],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n CONST robtarget p0 := [[1,0,0],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n PROC main()\n  MoveL p0, v100, fine, tool0;\n ENDPROC\nENDMODULE\n";
    let e = printwatt::toolpath::parse_rapid(t, "d.mod", &Default::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("d.mod:3") && e.contains("declared twice (first on line 2)"),
        "{e}"
    );
}

#[test]
fn a_time_gap_in_a_log_is_named() {
    let mut s = String::from("t,q1,q2,q3,q4,q5,q6,tau1,tau2,tau3,tau4,tau5,tau6\n");
    for k in 0..200 {
        let t = if k < 100 {
            k as f64 * 0.004
        } else {
            1000.0 + k as f64 * 0.004
        };
        let q = 0.1 * (k as f64 * 0.05).sin();
        s.push_str(&format!("{t},{q},{q},{q},{q},{q},{q},1,1,1,1,1,1\n"));
    }
    let log = printwatt::identify::log::parse_log(&s, "gap.csv", 6, None).unwrap();
    assert!(
        log.warnings
            .iter()
            .any(|w| w.starts_with("gap.csv:102:") && w.contains("time jumps by 1000")),
        "{:?}",
        log.warnings
    );
}

#[test]
fn q1_mm_on_a_revolute_joint_is_refused() {
    let d = tmp("qmm");
    robot_copy(&d);
    write(
        &d,
        "t.csv",
        "t,q1[mm],q2,q3,q4,q5,q6\n0,0,0,0,0,0.5,0\n0.1,0,0,0,0,0.5,0\n0.2,0,0,0,0,0.5,0\n",
    );
    let o = run(
        &[
            "energy",
            "--robot",
            "rob",
            "--trajectory",
            "t.csv",
            "--out",
            "o.csv",
        ],
        &d,
    );
    assert!(!o.status.success());
    assert!(
        err(&o).contains("t.csv:1:2: column `q1[mm]`: joint 1 is revolute"),
        "{}",
        err(&o)
    );
}

// ---- found by tests/fuzz_mutation.rs --------------------------------------------------------

#[test]
fn toolpath_with_1e308_coordinates_is_refused_naming_the_line() {
    // Parses as a finite number, but every length after it is infinite.
    let d = tmp("huge-coord");
    let p = write(
        &d,
        "p.mod",
        "MODULE M\n  PROC main()\n    MoveL [[0,0,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;\n    MoveL [[1e308,0,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;\n    MoveL [[-1e308,0,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;\n  ENDPROC\nENDMODULE\n",
    );
    let e = printwatt::toolpath::load(&p, &Default::default())
        .expect_err("a 1e308 m move must be refused")
        .to_string();
    assert!(
        e.contains("p.mod:4:") && e.contains("check the units"),
        "{e}"
    );
}

#[test]
fn urdf_with_two_root_links_names_them() {
    let d = tmp("two-roots");
    let r = robot_copy(&d);
    let u = std::fs::read_to_string(r.join("robot.urdf")).unwrap();
    // Cut the first joint's parent link: its child becomes a second root.
    let i = u.find("<joint ").unwrap();
    let j = i + u[i..].find("</joint>").unwrap() + "</joint>".len();
    std::fs::write(r.join("robot.urdf"), format!("{}{}", &u[..i], &u[j..])).unwrap();
    let e = printwatt::robot::load(&r)
        .expect_err("two roots")
        .to_string();
    assert!(
        e.contains("robot.urdf") && e.contains("<link name>") && e.contains("one root link"),
        "{e}"
    );
}

#[test]
fn gcode_dwell_is_timed_as_a_hold_at_the_point() {
    use printwatt::toolpath::Placement;
    let d = tmp("dwell");
    // Two print moves with a fine point (G61) between them, with and without `G4 P2000`.
    let base = "G21\nG90\nG61\nG0 X0 Y0 Z20 F6000\nG1 X100 E1 F6000\n";
    let tail = "G1 X100 Y100 E2\n";
    let plain = write(&d, "plain.gcode", &format!("{base}{tail}"));
    let dwell = write(&d, "dwell.gcode", &format!("{base}G4 P2000\n{tail}"));
    let model = common::robot("abb_irb6700_200_260");
    let at = Placement::new(1.7, 0.0, 0.0, std::f64::consts::FRAC_PI_2);
    let time = |p: &Path| {
        let tp = printwatt::toolpath::load(p, &Default::default()).unwrap();
        assert!(
            !tp.warnings.iter().any(|w| w.contains("G4")),
            "{:?}",
            tp.warnings
        );
        let job = common::default_job(&model, &tp);
        (
            tp.dwells.clone(),
            job.time(&printwatt::kinematics::IkSolver::new(&model).unwrap(), &at)
                .unwrap(),
        )
    };
    let (none, t0) = time(&plain);
    let (dw, t1) = time(&dwell);
    assert!(none.is_empty());
    assert_eq!(dw.len(), 1);
    assert_eq!((dw[0].line, dw[0].seconds), (6, 2.0));
    let m = &t1.motion;
    let grow = m.duration() - t0.motion.duration();
    eprintln!(
        "duration {} s -> {} s: +{grow} s",
        t0.motion.duration(),
        m.duration()
    );
    assert!((grow - 2.0).abs() <= m.dt + 1e-9, "grew by {grow} s");
    // The hold: the longest run of samples at the end of the first move, at rest.
    let end = printwatt::math::V3::new(0.1, 0.0, 0.02);
    let (mut best, mut run, mut best_end) = (0usize, 0usize, 0usize);
    for (k, p) in m.p.iter().enumerate() {
        if (p - end).norm() < 1e-9 {
            run += 1;
            if run > best {
                best = run;
                best_end = k;
            }
        } else {
            run = 0;
        }
    }
    let held = (best.saturating_sub(1)) as f64 * m.dt;
    eprintln!("held at the end of the first move for {held} s ({best} samples)");
    let filter = m.taps as f64 * m.dt;
    assert!(
        held >= 2.0 - filter - m.dt && held <= 2.0 + filter + m.dt,
        "held {held} s"
    );
    for k in best_end + 1 - best..best_end {
        let v = (m.p[k + 1] - m.p[k]).norm() / m.dt;
        assert!(v < 1e-9, "speed {v} m/s at sample {k} during the hold");
    }
    // A `G4` without a duration stays a warning naming its line.
    let p = write(&d, "bare.gcode", &format!("{base}G4\n{tail}"));
    let tp = printwatt::toolpath::load(&p, &Default::default()).unwrap();
    let w = tp.warnings.join("\n");
    assert!(
        tp.dwells.is_empty()
            && w.contains("line 6")
            && w.contains("G4 dwell")
            && w.contains("not timed"),
        "{w}"
    );
}

/// The shared last check before any result leaves printwatt. serde_json writes NaN
/// and infinities as `null`, so the check walks the typed value; the error names the JSON path
/// of the first non-finite number (a time series' index is its sample).
#[test]
fn non_finite_numbers_never_reach_json_outputs() {
    use printwatt::output::check_finite_json;
    use std::collections::BTreeMap;

    #[derive(serde::Serialize)]
    struct Joint {
        name: String,
        rmse: f64,
        samples: Vec<f64>,
        note: Option<f64>,
    }
    #[derive(serde::Serialize)]
    enum Kind {
        Fit { residual: (u32, f32) },
    }
    #[derive(serde::Serialize)]
    struct Report {
        joints: Vec<Joint>,
        kind: Kind,
        extra: BTreeMap<String, f64>,
    }
    let joint = |rmse: f64, s: f64| Joint {
        name: "j".into(),
        rmse,
        samples: vec![1.0, s, 3.0],
        note: None,
    };
    let ok = || Report {
        joints: vec![joint(1.0, 2.0), joint(1.5, 2.5), joint(0.5, 4.0)],
        kind: Kind::Fit {
            residual: (3, 0.25),
        },
        extra: BTreeMap::from([("a".to_string(), 1.0)]),
    };
    assert!(check_finite_json("report", &ok()).is_ok());

    // A NaN deep inside: the error names the quantity's path.
    let mut r = ok();
    r.joints[2].rmse = f64::NAN;
    let e = check_finite_json("report", &r).unwrap_err().to_string();
    assert!(
        e.contains("report") && e.contains("`joints[2].rmse` is NaN"),
        "{e}"
    );

    // In a time series: the first one, naming the sample.
    let mut r = ok();
    r.joints[1].samples[1] = f64::INFINITY;
    r.joints[2].rmse = f64::NAN;
    let e = check_finite_json("report", &r).unwrap_err().to_string();
    assert!(e.contains("`joints[1].samples[1]` is inf"), "{e}");

    // Options, enum variants, tuples, f32 and map keys.
    let mut r = ok();
    r.joints[0].note = Some(f64::NEG_INFINITY);
    let e = check_finite_json("report", &r).unwrap_err().to_string();
    assert!(e.contains("`joints[0].note` is -inf"), "{e}");
    let mut r = ok();
    r.kind = Kind::Fit {
        residual: (3, f32::NAN),
    };
    let e = check_finite_json("report", &r).unwrap_err().to_string();
    assert!(e.contains("`kind.Fit.residual[1]` is NaN"), "{e}");
    let mut r = ok();
    r.extra.insert("power_W".into(), f64::NAN);
    let e = check_finite_json("report", &r).unwrap_err().to_string();
    assert!(e.contains("`extra.power_W` is NaN"), "{e}");

    // A bare number and a flat time series.
    assert!(check_finite_json("x", &f64::NAN)
        .unwrap_err()
        .to_string()
        .contains("NaN"));
    let e = check_finite_json("power", &vec![0.0, 1.0, f64::NAN])
        .unwrap_err()
        .to_string();
    assert!(e.contains("`[2]` is NaN"), "{e}");
}

#[test]
fn length_units_on_a_revolute_joints_angle_and_rate_are_refused_and_deg_is_read() {
    // The units' kind comes from the one unit table (`table::joint_unit_is_linear`): `q2[mm]`
    // and `qd1[mm/s]` on the IRB 6700's revolute joints are lengths, `q2[deg]` an angle.
    let model = common::robot("abb_irb6700_200_260");
    let d = common::scratch("robustness", "joint-units");
    let write = |name: &str, header: &str| {
        let f = d.join(name);
        let row = "0.0,0,0,0,0,0,0\n0.1,0,0,0,0,0,0\n0.2,0,0,0,0,0,0\n";
        std::fs::write(&f, format!("{header}\n{row}")).unwrap();
        f
    };
    let bad = write(
        "mm.csv",
        "t[s],q1[rad],q2[mm],q3[rad],q4[rad],q5[rad],q6[rad]",
    );
    let e = printwatt::trajectory::read_csv_for(&bad, &model)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("q2[mm]") && e.contains("wrong kind of unit"),
        "{e}"
    );
    let rate = write(
        "rate.csv",
        "t[s],q1[rad],q2[deg],q3[rad],q4[rad],q5[rad],q6[rad],qd1[mm/s]",
    );
    let rate_text = std::fs::read_to_string(&rate)
        .unwrap()
        .replace(",0\n", ",0,0\n");
    std::fs::write(&rate, rate_text).unwrap();
    let e = printwatt::trajectory::read_csv_for(&rate, &model)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("qd1[mm/s]") && e.contains("wrong kind of unit"),
        "{e}"
    );
    let good = write(
        "deg.csv",
        "t[s],q1[rad],q2[deg],q3[rad],q4[rad],q5[rad],q6[rad]",
    );
    assert!(printwatt::trajectory::read_csv_for(&good, &model).is_ok());
}
