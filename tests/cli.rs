//! The CLI as a user sees it: each documented command end to end on the shipped robots and
//! paths, and bad input that must give a clear error, a non-zero exit and no partial output.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn printwatt(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("run printwatt")
}

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("printwatt-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Simulates 8 s of exciting motion of the IRB 4600 at 100 Hz (noise 1 N·m, seed 3) with the
/// `hidden` effect into `d`, and returns the log's path.
fn irb4600_log(d: &Path, hidden: &str, extra: &[&str]) -> String {
    let ds = d.display().to_string();
    let mut args = vec![
        "simulate",
        "--robot",
        "abb_irb4600_40_255",
        "--excite",
        "8",
        "--hidden",
        hidden,
        "--rate",
        "100",
        "--noise",
        "1",
        "--seed",
        "3",
        "--out",
        &ds,
    ];
    args.extend_from_slice(extra);
    let o = printwatt(&args, &root());
    assert!(o.status.success(), "{}", stderr(&o));
    d.join("log.csv").display().to_string()
}

#[test]
fn robots_lists_the_shipped_robots() {
    let o = printwatt(&["robots", "--json"], &root());
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["schema_version"], 1);
    let v = &v["robots"];
    let ids: Vec<&str> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["id"].as_str().unwrap())
        .collect();
    for id in [
        "abb_irb4600_40_255",
        "abb_irb6700_200_260",
        "puma560",
        "staubli_tx200",
        "ur10e",
    ] {
        assert!(ids.contains(&id), "{ids:?}");
    }
    for r in v.as_array().unwrap() {
        assert_eq!(r["joints"], 6);
        assert!(r["reach_m"].as_f64().unwrap() > 0.5);
        assert!(!r["provenance"].as_str().unwrap().is_empty());
    }
}

#[test]
fn energy_of_a_trajectory_agrees_with_the_same_path_timed_by_printwatt() {
    let d = tmpdir("energy");
    let traj = root().join("tests/data/traj/irb6700_default_25hz.csv");
    let o = printwatt(
        &[
            "energy",
            "--robot",
            "abb_irb6700_200_260",
            "--trajectory",
            traj.to_str().unwrap(),
            "--json",
            "--out",
            "t",
        ],
        &d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let a: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let o = printwatt(
        &[
            "energy",
            "--robot",
            "abb_irb6700_200_260",
            "--path",
            root().join("paths/default.gcode").to_str().unwrap(),
            "--at",
            "1.7,0,0,90",
            "--json",
            "--no-csv",
        ],
        &d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let b: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let ea = a["energy"]["total"]["supply_j"].as_f64().unwrap();
    let eb = b["energy"]["total"]["supply_j"].as_f64().unwrap();
    // The trajectory file is the same motion at 25 Hz instead of 250 Hz (derivatives by central
    // differences): the energies agree to a fraction of a percent.
    assert!(ea > 1000.0 && ((ea - eb) / eb).abs() < 0.01, "{ea} vs {eb}");
    assert_eq!(a["energy"]["joints"].as_array().unwrap().len(), 6);
    let csv = std::fs::read_to_string(d.join("t/irb6700_default_25hz.energy.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(
        header.starts_with("t[s],q1[rad]")
            && header.contains("tau6[Nm]")
            && header.ends_with("p_supply[W]")
    );
    assert_eq!(
        csv.lines().count(),
        1 + a["energy"]["samples"].as_u64().unwrap() as usize
    );
    // The human-readable summary names every joint and the total.
    let o = printwatt(
        &[
            "energy",
            "--robot",
            "abb_irb6700_200_260",
            "--trajectory",
            traj.to_str().unwrap(),
            "--out",
            "t2",
        ],
        &d,
    );
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("joint_6") && text.contains("supply energy"),
        "{text}"
    );
}

fn write(d: &Path, name: &str, text: &str) -> PathBuf {
    let p = d.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn fails_with(args: &[&str], cwd: &Path, needles: &[&str]) {
    let o = printwatt(args, cwd);
    let e = stderr(&o);
    assert!(!o.status.success(), "expected failure for {args:?}");
    assert!(!e.contains("panicked"), "panic: {e}");
    for n in needles {
        assert!(e.contains(n), "`{n}` not in: {e}");
    }
}

#[test]
fn bad_trajectories_name_file_line_and_column() {
    let d = tmpdir("badtraj");
    let ok_rows = "0,0,0,0,0,0,0\n0.1,0,0,0,0,0,0\n0.2,0,0,0,0,0,0\n";
    let nan = write(
        &d,
        "nan.csv",
        &format!("t,q1,q2,q3,q4,q5,q6\n{ok_rows}0.3,0,0,NaN,0,0,0\n"),
    );
    fails_with(
        &[
            "energy",
            "--robot",
            "abb_irb6700_200_260",
            "--trajectory",
            "nan.csv",
            "--out",
            "o.csv",
        ],
        &d,
        &["nan.csv:5:9", "q3"],
    );
    assert!(!d.join("o.csv").exists(), "no partial output");
    let _ = nan;
    write(
        &d,
        "back.csv",
        &format!("t,q1,q2,q3,q4,q5,q6\n{ok_rows}0.15,0,0,0,0,0,0\n"),
    );
    fails_with(
        &[
            "energy",
            "--robot",
            "abb_irb6700_200_260",
            "--trajectory",
            "back.csv",
        ],
        &d,
        &["back.csv:5", "not after"],
    );
    write(
        &d,
        "five.csv",
        "t,q1,q2,q3,q4,q5\n0,0,0,0,0,0\n0.1,0,0,0,0,0\n0.2,0,0,0,0,0\n",
    );
    fails_with(
        &[
            "energy",
            "--robot",
            "abb_irb6700_200_260",
            "--trajectory",
            "five.csv",
        ],
        &d,
        &["five.csv", "got 5, expected 6"],
    );
    write(
        &d,
        "unit.csv",
        &format!("t[fortnight],q1,q2,q3,q4,q5,q6\n{ok_rows}"),
    );
    fails_with(
        &[
            "energy",
            "--robot",
            "abb_irb6700_200_260",
            "--trajectory",
            "unit.csv",
        ],
        &d,
        &["unit.csv:1:1", "fortnight"],
    );
    // The output may not overwrite an input: --out names a directory, and a file there is
    // not taken for one.
    let good = write(&d, "good.csv", &format!("t,q1,q2,q3,q4,q5,q6\n{ok_rows}"));
    let before = std::fs::read(&good).unwrap();
    fails_with(
        &[
            "energy",
            "--robot",
            "abb_irb6700_200_260",
            "--trajectory",
            "good.csv",
            "--out",
            "good.csv",
        ],
        &d,
        &["--out good.csv", "not a directory"],
    );
    assert_eq!(std::fs::read(&good).unwrap(), before);
    // A second run does not replace the first one's CSV without --force.
    let args = [
        "energy",
        "--robot",
        "abb_irb6700_200_260",
        "--trajectory",
        "good.csv",
    ];
    assert!(printwatt(&args, &d).status.success());
    fails_with(&args, &d, &["good.energy.csv exists already", "--force"]);
    let mut forced = args.to_vec();
    forced.push("--force");
    assert!(printwatt(&forced, &d).status.success());
}

#[test]
fn bad_robots_name_file_and_line_or_field() {
    let d = tmpdir("badrobot");
    let src = root().join("robots/abb_irb6700_200_260");
    let urdf = std::fs::read_to_string(src.join("robot.urdf")).unwrap();
    let drive = std::fs::read_to_string(src.join("drive.toml")).unwrap();
    let traj = root().join("tests/data/traj/irb6700_default_25hz.csv");
    let traj = traj.to_str().unwrap();

    // Malformed XML.
    let r1 = d.join("r1");
    std::fs::create_dir_all(&r1).unwrap();
    write(&r1, "robot.urdf", &urdf.replacen("</link>", "</lnk>", 1));
    fails_with(
        &["energy", "--robot", "r1", "--trajectory", traj],
        &d,
        &["r1/robot.urdf:", "XML"],
    );

    // A link without inertial, asked for dynamics: estimated, and the warning names the link.
    let r2 = d.join("r2");
    std::fs::create_dir_all(&r2).unwrap();
    let start = urdf.find("<link name=\"link_3\"").unwrap();
    let i0 = start + urdf[start..].find("<inertial>").unwrap();
    let i1 = i0 + urdf[i0..].find("</inertial>").unwrap() + "</inertial>".len();
    write(
        &r2,
        "robot.urdf",
        &format!("{}{}", &urdf[..i0], &urdf[i1..]),
    );
    write(&r2, "drive.toml", &drive);
    let o = printwatt(
        &["energy", "--robot", "r2", "--trajectory", traj, "--no-csv"],
        &d,
    );
    let e = stderr(&o);
    assert!(o.status.success(), "{e}");
    assert!(e.contains("ESTIMATE") && e.contains("`link_3`"), "{e}");
    assert!(printwatt::robot::load(&r2).is_ok());

    // A drive file with a wrong field value names the field.
    let r3 = d.join("r3");
    std::fs::create_dir_all(&r3).unwrap();
    write(&r3, "robot.urdf", &urdf);
    let bad = drive.replacen("gear_efficiency = ", "gear_efficiency = 7.0 #", 1);
    write(&r3, "drive.toml", &bad);
    fails_with(
        &["energy", "--robot", "r3", "--trajectory", traj],
        &d,
        &["drive.toml", "gear_efficiency", "(0, 1]"],
    );

    // A drive-file syntax error names line and column.
    let r4 = d.join("r4");
    std::fs::create_dir_all(&r4).unwrap();
    write(&r4, "robot.urdf", &urdf);
    write(&r4, "drive.toml", &format!("{drive}\n[cabinet\n"));
    fails_with(
        &["energy", "--robot", "r4", "--trajectory", traj],
        &d,
        &["drive.toml:"],
    );

    // Unknown robot.
    fails_with(
        &["energy", "--robot", "no_such_robot", "--trajectory", traj],
        &d,
        &["no_such_robot"],
    );
}

#[test]
fn an_infeasible_placement_says_why() {
    let d = tmpdir("infeasible");
    let p = root().join("paths/default.gcode");
    fails_with(
        &[
            "energy",
            "--robot",
            "abb_irb6700_200_260",
            "--path",
            p.to_str().unwrap(),
            "--at",
            "2.5,0,0,0",
        ],
        &d,
        &["infeasible", "path sample", "unreachable"],
    );
    fails_with(
        &[
            "energy",
            "--robot",
            "abb_irb6700_200_260",
            "--path",
            p.to_str().unwrap(),
            "--at",
            "2.5,0,0",
        ],
        &d,
        &["--at `2.5,0,0`", "expected x,y,z,yaw"],
    );
}

#[test]
fn version_names_the_commit() {
    let o = printwatt(&["--version"], &root());
    assert!(o.status.success(), "{}", stderr(&o));
    let v = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        v.starts_with(&format!("printwatt {} (commit ", env!("CARGO_PKG_VERSION"))),
        "{v}"
    );
    let head = Command::new("git")
        .args(["rev-parse", "--short", "HEAD"])
        .current_dir(root())
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string());
    match head {
        Some(h) if std::env::var_os("PRINTWATT_COMMIT").is_none() => {
            assert!(v.contains(&format!("(commit {h})")), "{v} vs HEAD {h}")
        }
        Some(_) => {}
        None => assert!(v.contains("not built from a git checkout"), "{v}"),
    }
}

fn help(cmd: &str) -> String {
    let o = printwatt(&[cmd, "--help"], &root());
    assert!(o.status.success(), "{cmd}: {}", stderr(&o));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The help text of `--opt` with its value name, whitespace normalised (clap puts the text
/// beside the option or, when the lines are long, on the following indented lines).
fn option_line(help: &str, opt: &str) -> Option<String> {
    let lines: Vec<&str> = help.lines().collect();
    let i = lines.iter().position(|l| {
        let t = l.trim_start();
        t.starts_with(&format!("{opt} ")) || t == opt
    })?;
    let mut text = lines[i].trim().to_string();
    for l in &lines[i + 1..] {
        let t = l.trim_start();
        if t.is_empty() || t.starts_with('-') {
            break;
        }
        text.push(' ');
        text.push_str(t);
    }
    Some(text.split_whitespace().collect::<Vec<_>>().join(" "))
}

const COMMANDS: [&str; 7] = [
    "energy", "sweep", "optimise", "simulate", "compare", "diagnose", "identify",
];

#[test]
fn shared_options_read_the_same_in_every_command() {
    let helps: Vec<(&str, String)> = COMMANDS.iter().map(|c| (*c, help(c))).collect();
    // --robot, --tool and the output options: present everywhere, one text, one default.
    for opt in ["--robot", "--tool", "--out", "--json", "--force"] {
        let lines: Vec<_> = helps
            .iter()
            .map(|(c, h)| {
                (
                    c,
                    option_line(h, opt).unwrap_or_else(|| panic!("{c}: no {opt}")),
                )
            })
            .collect();
        for (c, l) in &lines {
            assert_eq!(l, &lines[0].1, "{opt} differs in {c}");
        }
    }
    assert!(option_line(&helps[0].1, "--robot")
        .unwrap()
        .contains("[default: abb_irb6700_200_260]"));
    // Timing options: on every command that times a path, with the same unit and default.
    for opt in [
        "--zone",
        "--period",
        "--accel",
        "--jerk",
        "--at",
        "--spin",
        "--path",
        "--path-units",
        "--scale",
    ] {
        let lines: Vec<_> = ["energy", "sweep", "optimise", "simulate"]
            .iter()
            .map(|c| {
                let h = &helps.iter().find(|(n, _)| n == c).unwrap().1;
                option_line(h, opt).unwrap_or_else(|| panic!("{c}: no {opt}"))
            })
            .collect();
        assert!(lines.iter().all(|l| l == &lines[0]), "{opt}: {lines:#?}");
    }
    // Feasibility checks: the same in `energy --at` as in `sweep` and `optimise`.
    for opt in [
        "--no-collisions",
        "--check-every",
        "--wrist-min",
        "--wrist-rate-max",
        "--wrist-margin",
        "--joint-margin",
        "--elbow-min",
        "--shoulder-min",
    ] {
        let lines: Vec<_> = ["energy", "sweep", "optimise"]
            .iter()
            .map(|c| {
                let h = &helps.iter().find(|(n, _)| n == c).unwrap().1;
                option_line(h, opt).unwrap_or_else(|| panic!("{c}: no {opt}"))
            })
            .collect();
        assert!(lines.iter().all(|l| l == &lines[0]), "{opt}: {lines:#?}");
    }
    // Energy options on every command that computes the energy of a timed path.
    for opt in ["--regeneration", "--no-payload", "--no-friction"] {
        for c in ["energy", "sweep", "optimise"] {
            let h = &helps.iter().find(|(n, _)| n == &c).unwrap().1;
            assert!(option_line(h, opt).is_some(), "{c}: no {opt}");
        }
    }
}

#[test]
fn numeric_options_state_their_unit_and_default() {
    let cases: [(&str, &str, &[&str]); 14] = [
        ("energy", "--zone", &["mm", "[default: 5]"]),
        ("energy", "--period", &["ms", "[default: 4]"]),
        ("energy", "--accel", &["m/s²", "[default: 1]"]),
        ("energy", "--jerk", &["m/s³", "[default: 10]"]),
        ("energy", "--spin", &["deg", "[default: 0]"]),
        ("energy", "--at", &["m, m, m, deg"]),
        ("sweep", "--x", &[", m", "default"]),
        ("sweep", "--yaw", &["deg", "[default: 0]"]),
        (
            "sweep",
            "--elbow-min",
            &["dimensionless", "[default: 0.05]"],
        ),
        ("sweep", "--shoulder-min", &[", m", "[default: 0.1]"]),
        ("sweep", "--joint-margin", &["deg", "[default: 3]"]),
        ("simulate", "--rate", &["Hz", "[default: 250]"]),
        ("simulate", "--noise-q", &["rad", "[default: 0.000001]"]),
        ("simulate", "--excite", &["SECONDS"]),
    ];
    for (c, opt, needles) in cases {
        let l = option_line(&help(c), opt).unwrap_or_else(|| panic!("{c}: no {opt}"));
        for n in needles {
            assert!(l.contains(n), "{c} {opt}: `{n}` not in `{l}`");
        }
    }
}

#[test]
fn near_miss_robot_names_get_did_you_mean_and_the_list() {
    let d = tmpdir("nearmiss");
    for (cmd, typed, meant) in [
        ("energy", "abb_irb6700", "abb_irb6700_200_260"),
        ("sweep", "ur10", "ur10e"),
        ("compare", "staubli_tx2000", "staubli_tx200"),
    ] {
        let mut args = vec![cmd, "--robot", typed];
        if cmd == "compare" {
            args.extend(["--log", "log.csv"]);
        } else {
            args.extend(["--at", "1.7,0,0,90"]);
        }
        fails_with(
            &args,
            &d,
            &[
                &format!("robot `{typed}`"),
                &format!("did you mean `{meant}`"),
                "Shipped robots: abb_irb4600_40_255, abb_irb6700_200_260, puma560, staubli_tx200, ur10e",
            ],
        );
    }
    // Nothing near: the list alone.
    fails_with(
        &["energy", "--robot", "zzz", "--at", "1.7,0,0,90"],
        &d,
        &["robot `zzz`", "Shipped robots:"],
    );
    assert!(!stderr(&printwatt(
        &["energy", "--robot", "zzz", "--at", "1.7,0,0,90"],
        &d
    ))
    .contains("did you mean"));
}

#[test]
fn a_placement_in_millimetres_gets_a_hint() {
    let d = tmpdir("mm");
    fails_with(
        &["energy", "--at", "1700,0,0,90"],
        &d,
        &["--at `1700,0,0,90`", "x = 1700 m", "did you mean 1.7 m"],
    );
    fails_with(
        &["sweep", "--at", "1.7,0,0,90;1700,0,200,0"],
        &d,
        &["x = 1700 m", "did you mean 1.7 m"],
    );
    fails_with(
        &["sweep", "--x", "1200:1800:100", "--y", "0"],
        &d,
        &["x = 1200 m", "did you mean 1.2 m"],
    );
}

#[test]
fn energy_json_writes_nothing_but_the_json() {
    let d = tmpdir("jsononly");
    let o = printwatt(&["energy", "--at", "1.7,0,0,90", "--json"], &d);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v["output_csv"].is_null(), "{v}");
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 0, "files written");
    // --out makes it write the CSV too; --no-csv never.
    let o = printwatt(
        &["energy", "--at", "1.7,0,0,90", "--json", "--out", "o"],
        &d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(d.join("o/default.energy.csv").is_file());
    let o = printwatt(&["energy", "--at", "1.7,0,0,90", "--no-csv"], &d);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!d.join("default.energy.csv").exists());
}

#[test]
fn sweep_runs_at_the_timing_energy_was_checked_at() {
    let d = tmpdir("timing");
    // The bed 0.3 m up: at z = 0 this placement takes the wrist through q5 = 0, which the default
    // wrist margin rejects.
    let args = [
        "--at",
        "1.7,0,0.3,90",
        "--period",
        "8",
        "--accel",
        "0.5",
        "--json",
    ];
    let mut e = vec!["energy"];
    e.extend(args);
    let o = printwatt(&e, &d);
    assert!(o.status.success(), "{}", stderr(&o));
    let e: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let mut s = vec!["sweep"];
    s.extend(args);
    let o = printwatt(&s, &d);
    assert!(o.status.success(), "{}", stderr(&o));
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let t_e = e["print_time_s"].as_f64().unwrap();
    assert_eq!(s["best"]["outcome"]["status"], "feasible", "{s}");
    let t_s = s["best"]["outcome"]["duration_s"].as_f64().unwrap();
    assert_eq!(t_e, t_s);
    // 8 ms samples: the path takes the same time as at 4 ms, with half the samples.
    let o = printwatt(&["energy", "--at", "1.7,0,0.3,90", "--json"], &d);
    let e4: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let n8 = e["energy"]["samples"].as_u64().unwrap();
    let n4 = e4["energy"]["samples"].as_u64().unwrap();
    assert!((n4 as f64 / n8 as f64 - 2.0).abs() < 0.01, "{n4} vs {n8}");
}

/// Every number of a JSON value has at most 9 significant digits; no `Ok`/`Err` key anywhere.
fn check_json_shape(cmd: &str, v: &serde_json::Value, path: &str) {
    match v {
        serde_json::Value::Number(n) => {
            let x = n.as_f64().unwrap();
            let r: f64 = format!("{x:.8e}").parse().unwrap();
            assert_eq!(x, r, "{cmd}: {path} = {x} has float noise");
        }
        serde_json::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                check_json_shape(cmd, x, &format!("{path}[{i}]"));
            }
        }
        serde_json::Value::Object(o) => {
            for (k, x) in o {
                assert!(k != "Ok" && k != "Err", "{cmd}: Rust wrapper at {path}.{k}");
                check_json_shape(cmd, x, &format!("{path}.{k}"));
            }
        }
        _ => {}
    }
}

#[test]
fn every_command_answers_json_with_schema_version_and_no_rust_wrappers() {
    let d = tmpdir("json-all");
    // simulate --json without --out: the samples in the JSON, no file.
    let o = printwatt(
        &[
            "simulate",
            "--robot",
            "abb_irb4600_40_255",
            "--excite",
            "3",
            "--hidden",
            "coulomb=30",
            "--json",
        ],
        &d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let sim: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(sim["log"].is_null());
    assert_eq!(sim["rows"].as_array().unwrap().len(), 750);
    assert_eq!(sim["columns"][0], "t[s]");
    assert_eq!(
        std::fs::read_dir(&d).unwrap().count(),
        0,
        "simulate --json wrote a file"
    );
    // With --out the log is written and named.
    let o = printwatt(
        &[
            "simulate",
            "--robot",
            "abb_irb4600_40_255",
            "--excite",
            "3",
            "--hidden",
            "coulomb=30",
            "--out",
            ".",
        ],
        &d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(d.join("log.csv").is_file());
    let r = ["--robot", "abb_irb4600_40_255", "--log", "log.csv"];
    let runs: Vec<(&str, Vec<&str>)> = vec![
        ("robots", vec!["robots"]),
        ("energy", vec!["energy", "--at", "1.7,0,0,90"]),
        ("sweep", vec!["sweep", "--at", "1.7,0,0.3,90;3,0,0,0"]),
        (
            "optimise",
            vec![
                "optimise",
                "--x",
                "1.6,1.7",
                "--y",
                "0",
                "--yaw",
                "90",
                "--max-evals",
                "5",
                "--tolerance",
                "0,0",
                // At z = 0 both cells take the wrist through q5 = 0.
                "--wrist-margin",
                "0",
            ],
        ),
        ("compare", [&["compare"][..], &r].concat()),
        ("diagnose", [&["diagnose"][..], &r].concat()),
        (
            "identify",
            [&["identify"][..], &r, &["--effects", "coulomb"]].concat(),
        ),
    ];
    let before: Vec<_> = std::fs::read_dir(&d)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    for (cmd, mut args) in runs {
        args.push("--json");
        let o = printwatt(&args, &d);
        assert!(o.status.success(), "{cmd}: {}", stderr(&o));
        let v: serde_json::Value =
            serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("{cmd}: {e}"));
        assert_eq!(v["schema_version"], 1, "{cmd}");
        assert!(v["warnings"].is_array(), "{cmd}");
        check_json_shape(cmd, &v, "");
        if cmd == "sweep" {
            let rows = v["rows"].as_array().unwrap();
            assert_eq!(rows[0]["outcome"]["status"], "feasible");
            assert!(rows[0]["outcome"]["energy_j"].as_f64().unwrap() > 0.0);
            assert_eq!(rows[1]["outcome"]["status"], "infeasible");
            assert_eq!(rows[1]["outcome"]["reason"], "unreachable");
        }
        // Nothing but the JSON (identify's calibrated robot is its result).
        let now: Vec<_> = std::fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .filter(|f| !before.contains(f))
            .collect();
        if cmd == "identify" {
            assert_eq!(now.len(), 1, "{now:?}");
            assert!(now[0].to_string_lossy().ends_with(".calibrated.toml"));
        } else {
            assert!(now.is_empty(), "{cmd} --json wrote {now:?}");
        }
    }
    assert!(!d.join("results").exists(), "optimise --json wrote a run");
}

/// One meaning of spin: the nozzle's rotation about its own axis relative to the part, deg on
/// the command line, rad in the library. `energy --at x,y,z,yaw,spin`, `sweep --at x,y,z,yaw
/// --spin s` at that single point and the library's `PathJob::evaluate` with
/// `Placement::nozzle_spin` give the same energy; with a tool off the flange axis (seed 001's
/// spindle) the spin matters, so a command reading it as an absolute angle (yaw + spin versus
/// spin) or dropping it would disagree.
#[test]
fn placement_spin_means_the_same_in_every_command() {
    use printwatt::evaluate::PathJob;
    use printwatt::frame::Placement;
    let tool = "presets/seed001_spindle.toml";
    let (x, y, z, yaw, spin) = (1.6, 0.0, 0.2, 90.0_f64, 30.0_f64);
    let at5 = format!("{x},{y},{z},{yaw},{spin}");
    let at4 = format!("{x},{y},{z},{yaw}");
    let json = |args: &[&str]| -> serde_json::Value {
        let o = printwatt(args, &root());
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let e = json(&["energy", "--tool", tool, "--at", &at5, "--json"]);
    let energy_cmd = e["energy"]["total"]["drives_j"].as_f64().unwrap();
    assert_eq!(e["placement"]["nozzle_spin_deg"].as_f64(), Some(spin));
    let s = json(&[
        "sweep", "--tool", tool, "--at", &at4, "--spin", "30", "--json",
    ]);
    assert_eq!(s["placements"], 1);
    assert_eq!(s["best"]["placement"]["spin_deg"].as_f64(), Some(spin));
    let sweep_cmd = s["best"]["outcome"]["drives_j"].as_f64().unwrap();

    let mut model = printwatt::load_robot(&root().join("robots/abb_irb6700_200_260")).unwrap();
    printwatt::robot::apply_tool_preset(&mut model, &root().join(tool)).unwrap();
    let path = printwatt::load_path(
        &root().join("paths/default.gcode"),
        &printwatt::ReadOptions::default(),
    )
    .unwrap();
    let job = PathJob::new(
        &model,
        &path,
        printwatt::EnergyOptions::default(),
        printwatt::timing::ProfileOptions::default(),
        printwatt::timing::JointStageOptions::default(),
    )
    .unwrap();
    let lib = |spin_deg: f64| {
        let at = Placement::new(x, y, z, yaw.to_radians()).with_spin(spin_deg.to_radians());
        // None: infeasible at that spin (a joint limit, say).
        job.evaluate(&at)
            .unwrap()
            .ok()
            .map(|r| r.energy.total.drives_j)
    };
    let library = lib(spin).expect("feasible at the spin asked for");
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-8 * b.abs();
    assert!(
        close(energy_cmd, library) && close(sweep_cmd, library),
        "energy {energy_cmd} J, sweep {sweep_cmd} J, library {library} J"
    );
    // The spin is not a no-op here: the same placement read as an absolute nozzle angle, or
    // without its spin, costs a different energy or is infeasible (so the agreement above is
    // not by accident).
    for other in [0.0, spin + yaw, spin - yaw] {
        if let Some(e) = lib(other) {
            assert!(
                (e - library).abs() > 1e-3 * library,
                "spin {other}°: {e} J against {library} J"
            );
        }
    }
    assert!(
        lib(0.0).is_some(),
        "the spin-free comparison must be feasible"
    );
}

/// `identify --effects "viscous[2]"` fits joint 2's viscous friction only, as `simulate
/// --hidden viscous[2]=…` hides it (one parser of `effect[j]`): the other joints' viscous
/// parameters are held at their prior values and named; a joint beyond the robot is refused.
#[test]
fn compare_takes_per_joint_effect_subsets_as_identify_and_simulate_do() {
    // `--effects viscous[2]` / `--without viscous[2]` mean in `compare` what they mean in
    // `identify` and `simulate --hidden`: that effect on (off) joint 2 only.
    let d = tmpdir("compare-subset");
    let log = irb4600_log(&d, "viscous=40", &[]);
    let rmse = |extra: &[&str]| -> Vec<f64> {
        let mut args = vec![
            "compare",
            "--robot",
            "abb_irb4600_40_255",
            "--log",
            &log,
            "--json",
        ];
        args.extend_from_slice(extra);
        let o = printwatt(&args, &root());
        assert!(o.status.success(), "{extra:?}: {}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        v["channels"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c["rmse"].as_f64().unwrap())
            .collect()
    };
    let all = rmse(&["--effects", "viscous"]);
    let only2 = rmse(&["--effects", "viscous[2]"]);
    let none = rmse(&["--effects", "coulomb", "--without", "coulomb"]);
    assert_eq!(only2[1], all[1], "joint 2 as with viscous on every joint");
    for j in [0, 2, 3, 4, 5] {
        assert_eq!(
            only2[j],
            none[j],
            "joint {}: as with no viscous friction",
            j + 1
        );
        assert!(
            only2[j] > all[j],
            "joint {}: the nominal viscous term helps",
            j + 1
        );
    }
    let nominal = rmse(&[]);
    let without2 = rmse(&["--without", "viscous[2]"]);
    assert!(without2[1] > nominal[1], "joint 2 loses its viscous term");
    for j in [0, 2, 3, 4, 5] {
        assert_eq!(without2[j], nominal[j], "joint {} untouched", j + 1);
    }
    let o = printwatt(
        &[
            "compare",
            "--robot",
            "abb_irb4600_40_255",
            "--log",
            &log,
            "--effects",
            "viscous[9]",
        ],
        &root(),
    );
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("joint 9, but the robot has 6 joints"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn identify_accepts_a_per_joint_effect_subset() {
    let d = tmpdir("subset");
    let log = irb4600_log(&d, "viscous[2]=40", &["--signal", "tau"]);
    let id_dir = d.join("id").display().to_string();
    let o = printwatt(
        &[
            "identify",
            "--robot",
            "abb_irb4600_40_255",
            "--log",
            &log,
            "--effects",
            "viscous[2]",
            "--out",
            &id_dir,
            "--json",
        ],
        &root(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let id = &v["identification"];
    let held: Vec<&str> = id["held_at_prior"]
        .as_array()
        .unwrap()
        .iter()
        .map(|h| h["name"].as_str().unwrap())
        .collect();
    for j in [1, 3, 4, 5, 6] {
        assert!(
            held.contains(&format!("viscous.f_v[{j}]").as_str()),
            "{held:?}"
        );
    }
    assert!(!held.contains(&"viscous.f_v[2]"), "{held:?}");
    let p = |name: &str| {
        id["params"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["effect"] == "viscous" && p["name"] == name)
            .unwrap_or_else(|| panic!("{name} in {}", id["params"]))
            .clone()
    };
    let f2 = p("f_v[2]");
    let (value, nominal) = (
        f2["value"].as_f64().unwrap(),
        f2["nominal"].as_f64().unwrap(),
    );
    assert!(
        (value - nominal - 40.0).abs() < 4.0,
        "f_v[2] {value} from {nominal}: the hidden +40 N·m·s/rad not found"
    );
    for j in [1, 3] {
        let q = p(&format!("f_v[{j}]"));
        assert_eq!(q["value"], q["nominal"], "joint {j} must be held");
    }
    let o = printwatt(
        &[
            "identify",
            "--robot",
            "abb_irb4600_40_255",
            "--log",
            &log,
            "--effects",
            "viscous[9]",
            "--out",
            &id_dir,
            "--force",
        ],
        &root(),
    );
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("joint 9") && stderr(&o).contains("6 joints"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn optimise_does_not_report_a_nozzle_spin_the_energy_does_not_depend_on() {
    // A round nozzle's spin only shifts joint 6 by a constant: the energy is flat in it to
    // ~1e-15, and Nelder–Mead used to report whatever spin rounding noise favoured (16.9°, then
    // 1.9° after a change in the last bits of sin/cos). The start's spin is kept and said.
    let o = printwatt(
        &[
            "optimise",
            "--path",
            "paths/default.gcode",
            "--x",
            "1.4:1.8:0.2",
            "--y",
            "-0.2:0.2:0.2",
            "--z",
            "0.2",
            "--yaw",
            "0,90",
            "--max-evals",
            "10",
            "--tolerance",
            "0,0",
            "--no-report",
            "--json",
        ],
        &root(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let best = &v["optimise"]["best"]["placement"];
    assert_eq!(best["spin_deg"].as_f64(), Some(0.0), "{best}");
    let kept = v["optimise"]["search"]["spin_kept"].as_str().unwrap_or("");
    assert!(
        kept.contains("does not depend on the nozzle spin"),
        "{kept}"
    );
    // The search did move the spin: the note names a spin other than the one kept.
    assert!(
        !kept.starts_with("the energy does not depend on the nozzle spin here (0.0°"),
        "{kept}"
    );
}

#[test]
fn an_unknown_regeneration_policy_is_refused_with_the_four_policies() {
    let d = tmpdir("regen");
    for c in ["energy", "sweep", "optimise"] {
        fails_with(
            &[c, "--regeneration", "foo"],
            &d,
            &["--regeneration", "`foo`", "none, per_axis, dc_bus or grid"],
        );
    }
    // A known policy is accepted.
    let o = printwatt(
        &[
            "energy",
            "--regeneration",
            "grid",
            "--at",
            "1.44,0.12,0,93",
            "--json",
        ],
        &root(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn energy_at_reports_a_placement_sweep_at_calls_infeasible_with_the_same_reason() {
    let d = tmpdir("same-checks");
    let p = root().join("paths/default.gcode");
    let p = p.to_str().unwrap();
    // The part high above the base: the upper arm dips into the bed.
    let at = "1.2,0.5,1.2,90";
    let s = printwatt(&["sweep", "--path", p, "--at", at], &d);
    assert!(s.status.success(), "{}", stderr(&s));
    let out = String::from_utf8_lossy(&s.stdout).into_owned();
    let row = out
        .lines()
        .find(|l| l.trim_start().starts_with("0 "))
        .unwrap_or_else(|| panic!("no row 0 in {out}"));
    let note = row[row.find("collision_bed").unwrap_or_else(|| panic!("{row}"))..].trim_end();
    assert!(note.contains("meets the bed"), "{note}");
    // energy --at: the motion exists, so it is evaluated, and the failure is stated with the
    // sweep's reason word for word, on stdout and as a warning.
    let e = printwatt(&["energy", "--path", p, "--at", at, "--no-csv"], &d);
    assert!(e.status.success(), "{}", stderr(&e));
    let text = String::from_utf8_lossy(&e.stdout).into_owned();
    assert!(
        text.contains(&format!(
            "checks     INFEASIBLE (the checks of `sweep`): {note}"
        )),
        "sweep: {note}\nenergy: {text}"
    );
    assert!(stderr(&e).contains(&format!(
        "placement {at} is INFEASIBLE as `sweep` checks it: {note}"
    )));
    // JSON: `feasibility` as a sweep row's outcome.
    let j = printwatt(&["energy", "--path", p, "--at", at, "--json"], &d);
    assert!(j.status.success(), "{}", stderr(&j));
    let v: serde_json::Value = serde_json::from_slice(&j.stdout).unwrap();
    assert_eq!(v["feasibility"]["status"], "infeasible");
    assert_eq!(v["feasibility"]["reason"], "collision_bed");
    assert!(
        note.contains(v["feasibility"]["detail"].as_str().unwrap()),
        "{v}"
    );
    // Switching the failing check off, as in sweep, makes it feasible.
    let ok = printwatt(
        &[
            "energy",
            "--path",
            p,
            "--at",
            at,
            "--json",
            "--no-collisions",
        ],
        &d,
    );
    let v: serde_json::Value = serde_json::from_slice(&ok.stdout).unwrap();
    assert_eq!(v["feasibility"]["status"], "feasible", "{}", stderr(&ok));
}

#[test]
fn path_units_state_a_unitless_csv_path_and_mm_is_never_assumed_silently() {
    let d = tmpdir("path-units");
    let csv = write(
        &d,
        "square.csv",
        "x,y,z\n0,0,0\n0.6,0,0\n0.6,0.4,0\n0,0.4,0\n0,0,0\n",
    );
    let c = csv.to_str().unwrap();
    let run = |extra: &[&str]| {
        let mut a = vec!["energy", "--path", c, "--at", "1.6,0,0.3,90", "--json"];
        a.extend_from_slice(extra);
        printwatt(&a, &d)
    };
    let m = run(&["--path-units", "m"]);
    assert!(m.status.success(), "{}", stderr(&m));
    assert!(!stderr(&m).contains("assumed"), "{}", stderr(&m));
    let mm = run(&[]);
    assert!(mm.status.success(), "{}", stderr(&mm));
    let e = stderr(&mm);
    assert!(
        e.contains("square.csv:1: x, y, z have no unit; mm assumed"),
        "{e}"
    );
    assert!(
        e.contains("smaller than 50 mm") && e.contains("set the path units to mm or m"),
        "{e}"
    );
    // The notes are in the JSON too.
    let v: serde_json::Value = serde_json::from_slice(&mm.stdout).unwrap();
    let w = v["warnings"].to_string();
    assert!(w.contains("mm assumed"), "{w}");
    // Half size by --scale: a shorter print.
    let t = |o: &Output| {
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()["print_time_s"]
            .as_f64()
            .unwrap()
    };
    let half = run(&["--path-units", "m", "--scale", "0.5"]);
    assert!(half.status.success(), "{}", stderr(&half));
    assert!(t(&half) < 0.6 * t(&m), "{} vs {}", t(&half), t(&m));
    fails_with(
        &["energy", "--path-units", "km", "--at", "1.6,0,0.3,90"],
        &d,
        &["--path-units `km`", "expected mm or m"],
    );
    fails_with(
        &["energy", "--path-units", "m", "--at", "1.6,0,0.3,90"],
        &d,
        &["default.gcode", "CSV paths only"],
    );
}

#[test]
fn energy_runs_on_field_robots_with_missing_or_placeholder_inertias_and_says_so() {
    let d = tmpdir("field-robots");
    let csv = write(
        &d,
        "square.csv",
        "x[m],y[m],z[m]\n0,0,0\n0.6,0,0\n0.6,0.4,0\n0,0.4,0\n0,0,0\n",
    );
    for (urdf, needles) in [
        (
            "abb_irb6640_185_280.urdf",
            &["ESTIMATE", "`link_1`", "[links.<name>]"][..],
        ),
        (
            "kuka_kr120r2500pro.urdf",
            &[
                "same mass, 2 kg",
                "placeholder",
                "less than the rated payload of 120 kg",
            ][..],
        ),
    ] {
        // The URDF as published, with a drive file giving the nozzle and the rated payload.
        let r = d.join(urdf.trim_end_matches(".urdf"));
        std::fs::create_dir_all(&r).unwrap();
        std::fs::copy(
            root().join("tests/data/field_robots").join(urdf),
            r.join("robot.urdf"),
        )
        .unwrap();
        std::fs::write(
            r.join("drive.toml"),
            "[robot]\nrated_payload_kg = 120.0\n\n[tool]\nxyz_m = [0.0, 0.0, 0.3]\nrpy_rad = [0.0, 0.0, 0.0]\n",
        )
        .unwrap();
        let o = printwatt(
            &[
                "energy",
                "--robot",
                r.to_str().unwrap(),
                "--path",
                csv.to_str().unwrap(),
                "--at",
                "1.6,0,0.3,0",
                "--no-csv",
            ],
            &d,
        );
        let e = stderr(&o);
        assert!(o.status.success(), "{urdf}: {e}");
        assert!(!e.contains("has no <inertial>"), "{e}");
        for n in needles {
            assert!(e.contains(n), "{urdf}: `{n}` not in {e}");
        }
        assert!(String::from_utf8_lossy(&o.stdout).contains("supply energy"));
    }
    // `robots` shows where the inertias come from.
    let o = printwatt(&["robots", "--dir", d.to_str().unwrap(), "--json"], &d);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let rows = v["robots"].as_array().unwrap();
    let abb = rows
        .iter()
        .find(|r| r["id"] == "abb_irb6640_185_280")
        .unwrap();
    assert_eq!(abb["inertia_sources"][0], "estimate_from_capsule");
    let kuka = rows
        .iter()
        .find(|r| r["id"] == "kuka_kr120r2500pro")
        .unwrap();
    assert_eq!(kuka["inertia_sources"][0], "urdf");
    let t = printwatt(&["robots", "--dir", d.to_str().unwrap()], &d);
    let out = String::from_utf8_lossy(&t.stdout).into_owned();
    assert!(out.contains("link_1 ESTIMATE (capsule)"), "{out}");
}

/// Every line of a drive-file template that sets a key explains it in a comment.
fn assert_every_key_commented(text: &str) {
    for (i, line) in text.lines().enumerate() {
        let l = line.trim_start_matches("# ").trim();
        if l.contains(" = ") && !line.trim_start().starts_with("# ") {
            assert!(
                line.contains("  # "),
                "line {}: `{line}` has no comment",
                i + 1
            );
        }
    }
}

#[test]
fn robot_init_writes_a_drive_file_that_loads() {
    let d = tmpdir("robot-init");
    // The URDF in one directory, the drive file in another: `[robot] urdf` is relative.
    std::fs::create_dir_all(d.join("urdfs")).unwrap();
    std::fs::copy(
        root().join("robots/abb_irb6700_200_260/robot.urdf"),
        d.join("urdfs/arm.urdf"),
    )
    .unwrap();
    let o = printwatt(
        &[
            "robot",
            "init",
            "urdfs/arm.urdf",
            "--out",
            "cell/drive.toml",
        ],
        &d,
    );
    // The output's directory does not exist yet: it is made, or the refusal says so.
    if !o.status.success() {
        assert!(stderr(&o).contains("cell"), "{}", stderr(&o));
        std::fs::create_dir_all(d.join("cell")).unwrap();
        let o = printwatt(
            &[
                "robot",
                "init",
                "urdfs/arm.urdf",
                "--out",
                "cell/drive.toml",
            ],
            &d,
        );
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let text = std::fs::read_to_string(d.join("cell/drive.toml")).unwrap();
    assert!(text.contains("urdf = \"../urdfs/arm.urdf\""), "{text}");
    assert_eq!(text.matches("[[joints]]").count(), 6, "{text}");
    for j in 1..=6 {
        assert!(text.contains(&format!("name = \"joint_{j}\"")), "{text}");
    }
    assert!(text.contains("ESTIMATE"), "{text}");
    assert!(text.contains("tool_link = \"tool0\""), "{text}");
    assert_every_key_commented(&text);
    // It loads: `energy` on the drive file with the default path.
    let o = printwatt(
        &[
            "energy",
            "--robot",
            "cell/drive.toml",
            "--at",
            "1.7,0,0,90",
            "--no-csv",
        ],
        &d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("supply energy"));

    // A robot directory: robot.urdf + the template as drive.toml.
    let r = d.join("myarm");
    std::fs::create_dir_all(&r).unwrap();
    std::fs::copy(
        root().join("tests/data/field_robots/abb_irb6640_185_280.urdf"),
        r.join("robot.urdf"),
    )
    .unwrap();
    let o = printwatt(
        &[
            "robot",
            "init",
            "myarm/robot.urdf",
            "--out",
            "myarm/drive.toml",
        ],
        &d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(out.contains("link_1"), "{out}");
    let text = std::fs::read_to_string(r.join("drive.toml")).unwrap();
    assert!(text.contains("urdf = \"robot.urdf\""), "{text}");
    // The links the URDF gives no inertia: a commented table each, with the estimate.
    assert!(text.contains("# [links.link_1]"), "{text}");
    assert!(text.contains("# mass_kg = "), "{text}");
    assert_every_key_commented(&text);
    let o = printwatt(
        &[
            "energy",
            "--robot",
            "myarm",
            "--at",
            "1.7,0,0,90",
            "--no-csv",
        ],
        &d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("ESTIMATE"), "{}", stderr(&o));
}

#[test]
fn robot_init_refuses_to_overwrite() {
    let d = tmpdir("robot-init-exists");
    std::fs::copy(root().join("robots/ur10e/robot.urdf"), d.join("robot.urdf")).unwrap();
    std::fs::write(d.join("drive.toml"), "# mine\n").unwrap();
    // The default output, drive.toml here, exists: refused, untouched.
    let o = printwatt(&["robot", "init", "robot.urdf"], &d);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(e.contains("drive.toml") && e.contains("exists"), "{e}");
    assert_eq!(
        std::fs::read_to_string(d.join("drive.toml")).unwrap(),
        "# mine\n"
    );
    // Nor over the URDF itself.
    let o = printwatt(&["robot", "init", "robot.urdf", "--out", "robot.urdf"], &d);
    assert!(!o.status.success());
    assert!(std::fs::read_to_string(d.join("robot.urdf"))
        .unwrap()
        .contains("<robot"));
    // A URDF that is not there: the error names it.
    let o = printwatt(&["robot", "init", "none.urdf", "--out", "new.toml"], &d);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("none.urdf"), "{}", stderr(&o));
    assert!(!d.join("new.toml").exists());
}

#[test]
fn a_urdf_without_inertials_is_estimated_from_its_meshes() {
    // The ABB IRB 6640-185/2.80 as ROS-Industrial publishes it: no <inertial> anywhere, STL
    // collision meshes behind package:// (tests/data/ros_industrial/README.md).
    let urdf =
        root().join("tests/data/ros_industrial/abb_irb6640_support/urdf/irb6640_185_280.urdf");
    let d = tmpdir("ros-i-meshes");
    std::fs::create_dir_all(d.join("cell")).unwrap();
    let o = printwatt(
        &[
            "robot",
            "init",
            urdf.to_str().unwrap(),
            "--out",
            "cell/drive.toml",
        ],
        &d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let energy = |robot: &str| {
        let o = printwatt(
            &[
                "energy",
                "--robot",
                robot,
                "--at",
                "1.7,0,0,90",
                "--no-csv",
                "--json",
            ],
            &d,
        );
        assert!(o.status.success(), "{robot}: {}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        (v, stderr(&o))
    };
    let (v, e) = energy("cell/drive.toml");
    // Every moving link estimated from its mesh hull, labelled, with the stated uncertainty.
    assert!(e.contains("ESTIMATE"), "{e}");
    for l in 1..=6 {
        assert!(
            e.contains(&format!("`link_{l}`")),
            "link_{l} not named in {e}"
        );
    }
    assert!(e.contains("collision shapes at 1200 kg/m³"), "{e}");
    assert!(!e.contains("capsule at"), "a mesh was not read: {e}");
    assert!(e.contains("uncertain by about ±50 %"), "{e}");
    assert!(!e.contains("has no <inertial>"), "{e}");
    // The estimated arm weighs what an arm of its class weighs (the IRB 6640 family weighs
    // 1,310–1,405 kg with its base; the shipped IRB 6700-200/2.60 model moves 793 kg).
    let w: Vec<&str> = e.lines().filter(|l| l.contains("kg in all")).collect();
    assert_eq!(w.len(), 1, "{e}");
    let total: f64 = w[0]
        .split("kg in all")
        .next()
        .and_then(|s| s.rsplit(' ').nth(1))
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no total in {}", w[0]));
    assert!((400.0..1400.0).contains(&total), "{total} kg");
    // Its energy on the default path (rigid body only: the positive mechanical work of each
    // joint) is that of a robot of its size: within a factor of three of the shipped
    // IRB 6700-200/2.60's URDF (its published inertias) at the same placement.
    let supply = |v: &serde_json::Value| v["energy"]["total"]["supply_j"].as_f64().unwrap();
    let ref_urdf = root().join("robots/abb_irb6700_200_260/robot.urdf");
    let (ref_v, _) = energy(ref_urdf.to_str().unwrap());
    assert_eq!(ref_v["energy"]["has_drive"], false);
    let (mine, theirs) = (supply(&v), supply(&ref_v));
    assert!(mine.is_finite() && mine > 0.0, "{v}");
    let ratio = mine / theirs;
    assert!((1.0 / 3.0..3.0).contains(&ratio), "{mine} J vs {theirs} J");
}
