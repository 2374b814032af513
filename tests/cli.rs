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

#[test]
fn robots_lists_the_shipped_robots() {
    let o = printwatt(&["robots", "--json"], &root());
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
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
            "t.csv",
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
            "--out",
            "p.csv",
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
    let csv = std::fs::read_to_string(d.join("t.csv")).unwrap();
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
            "t2.csv",
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
    // The output may not overwrite an input.
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
        &["refusing to write"],
    );
    assert_eq!(std::fs::read(&good).unwrap(), before);
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

    // A link without inertial, asked for dynamics: names the link; kinematics still load.
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
    fails_with(
        &["energy", "--robot", "r2", "--trajectory", traj],
        &d,
        &["link_3", "inertial"],
    );
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
