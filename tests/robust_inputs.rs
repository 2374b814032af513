//! Inputs that would make a run answer another question than the one asked, or exhaust the
//! machine, are refused where they enter, naming the file and the entry or key at fault: study
//! cells and options, study sizes, `--folds`.

mod common;

use printwatt::campaign::study::{Study, MAX_CASES};
use std::path::Path;
use std::time::Instant;

const HEAD: &str = r#"
[study]
name = "s"

[[robot]]
name = "r"
robot = "abb_irb4600_40_255"

[[path]]
name = "p"
file = "wall.gcode"
"#;

fn parse(extra: &str) -> Result<Study, String> {
    Study::parse(&format!("{HEAD}\n{extra}"), Path::new("dir/study.toml"))
        .map_err(|e| e.to_string())
}

#[test]
fn study_cells_with_values_a_case_would_refuse_fail_the_study_naming_file_and_key() {
    for (cell, key, bad) in [
        (r#"z_bounds = "0.5:0.1""#, "z_bounds", "0.5:0.1"),
        (r#"z_bounds = "foo""#, "z_bounds", "foo"),
        (r#"z_bounds = "nan:1""#, "z_bounds", "nan:1"),
        (r#"baseline = "nan,0,0,0""#, "baseline", "nan,0,0,0"),
        (r#"options = ["--tolerance", "nan,1"]"#, "options", "nan"),
        (r#"options = ["--tolerance=1,inf"]"#, "options", "inf"),
    ] {
        let e =
            parse(&format!("[[cell]]\nname = \"c\"\nx = 1.5\ny = 0\n{cell}\n")).expect_err(cell);
        assert!(
            e.contains("dir/study.toml")
                && e.contains("cell `c`")
                && e.contains(key)
                && e.contains(bad),
            "{cell}: {e}"
        );
    }
    // Study, robot and path options too.
    let e = Study::parse(
        &(HEAD.replace(
            "name = \"s\"",
            "name = \"s\"\noptions = [\"--z-bounds\", \"0:nan\"]",
        ) + "[[cell]]\nname = \"c\"\nx = 1.5\n"),
        Path::new("study.toml"),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("[study] options") && e.contains("nan"), "{e}");
    // Sound values still parse.
    parse("[[cell]]\nname = \"c\"\nx = 1.5\nz_bounds = \"0:0.5\"\nbaseline = \"1.5,0,0,90\"\noptions = [\"--tolerance\", \"20,1\"]\n")
        .unwrap();
}

#[test]
fn a_study_too_large_is_refused_before_its_cases_are_built() {
    // 10⁴ robots × 10⁴ cells × 10⁴ paths: 10¹² cases, refused at once (building them would
    // take terabytes).
    let n = 10_000;
    let mut t = String::from("[study]\nname = \"big\"\n");
    for i in 0..n {
        t.push_str(&format!(
            "[[robot]]\nname = \"r{i}\"\nrobot = \"abb_irb4600_40_255\"\n"
        ));
    }
    for i in 0..n {
        t.push_str(&format!("[[cell]]\nname = \"c{i}\"\nx = 1.5\n"));
    }
    for i in 0..n {
        t.push_str(&format!("[[path]]\nname = \"p{i}\"\nfile = \"w.gcode\"\n"));
    }
    let t0 = Instant::now();
    let e = Study::parse(&t, Path::new("big.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("1000000000000 cases") && e.contains(&MAX_CASES.to_string()),
        "{e}"
    );
    assert!(t0.elapsed().as_secs_f64() < 30.0, "{:?}", t0.elapsed());
}

#[test]
fn explicit_cases_are_checked_for_repeats_in_linear_time() {
    // 100 robots × 100 paths, every combination listed once: MAX_CASES cases.
    let n = 100;
    let mut t = String::from("[study]\nname = \"many\"\n[[cell]]\nname = \"c\"\nx = 1.5\n");
    for i in 0..n {
        t.push_str(&format!(
            "[[robot]]\nname = \"r{i}\"\nrobot = \"abb_irb4600_40_255\"\n"
        ));
        t.push_str(&format!("[[path]]\nname = \"p{i}\"\nfile = \"w.gcode\"\n"));
    }
    let mut cases = String::new();
    for r in 0..n {
        for p in 0..n {
            cases.push_str(&format!(
                "[[case]]\nrobot = \"r{r}\"\ncell = \"c\"\npath = \"p{p}\"\n"
            ));
        }
    }
    let t0 = Instant::now();
    let s = Study::parse(&(t.clone() + &cases), Path::new("many.toml")).unwrap();
    assert_eq!(s.cases.len(), MAX_CASES);
    assert!(t0.elapsed().as_secs_f64() < 10.0, "{:?}", t0.elapsed());
    // A repeat is named, at the end of the list.
    let e = Study::parse(
        &(t.clone()
            + &cases.replace(
                "[[case]]\nrobot = \"r99\"\ncell = \"c\"\npath = \"p99\"\n",
                "[[case]]\nrobot = \"r0\"\ncell = \"c\"\npath = \"p0\"\n",
            )),
        Path::new("many.toml"),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("repeats [[case]] 1"), "{e}");
    // 200,000 listed cases: refused by their number, at once.
    let mut big = t;
    for _ in 0..20 {
        big.push_str(&cases);
    }
    let t0 = Instant::now();
    let e = Study::parse(&big, Path::new("many.toml"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("200000 cases"), "{e}");
    assert!(t0.elapsed().as_secs_f64() < 30.0, "{:?}", t0.elapsed());
}

#[test]
fn diagnose_refuses_folds_outside_two_to_one_hundred() {
    let d = common::scratch("inputs", "folds");
    for f in ["0", "1", "1000000"] {
        let o = common::run(
            &[
                "diagnose",
                "--robot",
                "abb_irb4600_40_255",
                "--log",
                "missing.csv",
                "--folds",
                f,
            ],
            &d,
        );
        assert!(!o.status.success());
        let e = common::stderr_of(&o);
        assert!(
            e.contains("--folds") && e.contains(f) && e.contains("2..=100"),
            "{e}"
        );
    }
}

/// A copy of the default robot in `dir/rob` whose drive file has `from` replaced by `to`.
fn robot_with(dir: &Path, from: &str, to: &str) -> std::path::PathBuf {
    let r = dir.join("rob");
    std::fs::create_dir_all(&r).unwrap();
    let src = common::root().join("robots/abb_irb4600_40_255");
    std::fs::copy(src.join("robot.urdf"), r.join("robot.urdf")).unwrap();
    let d = std::fs::read_to_string(src.join("drive.toml")).unwrap();
    assert!(d.contains(from), "{from}");
    std::fs::write(r.join("drive.toml"), d.replacen(from, to, 1)).unwrap();
    r
}

#[test]
fn drive_values_outside_physical_ranges_are_refused_naming_the_drive_file_and_key() {
    for (name, from, to, key) in [
        (
            "base",
            "balancer_base_m = 0.42",
            "balancer_base_m = 1e308",
            "balancer_base_m",
        ),
        (
            "kt",
            "torque_constant_nm_per_a = 2.0",
            "torque_constant_nm_per_a = 1e-300",
            "torque_constant_nm_per_a",
        ),
    ] {
        let d = common::scratch("inputs", name);
        let r = robot_with(&d, from, to);
        let e = match printwatt::robot::load(&r) {
            Ok(m) => printwatt::effects::EffectSet::of_robot(&m)
                .map(|_| ())
                .map_err(|e| e.to_string()),
            Err(e) => Err(e.to_string()),
        }
        .expect_err(name);
        assert!(e.contains("drive.toml") && e.contains(key), "{name}: {e}");
        // Through the command line: the drive file is blamed, not the trajectory.
        std::fs::write(
            d.join("p.gcode"),
            "G21\nG90\nG0 X0 Y0 Z20 F6000\nG1 X100 E1 F9000\n",
        )
        .unwrap();
        let o = common::run(
            &[
                "energy",
                "--robot",
                "rob",
                "--path",
                "p.gcode",
                "--at",
                "1.5,0,0.3,0",
                "--no-csv",
            ],
            &d,
        );
        assert!(!o.status.success());
        let e = common::stderr_of(&o);
        assert!(e.contains("drive.toml") && e.contains(key), "{name}: {e}");
    }
}

#[test]
fn log_values_outside_physical_ranges_are_refused_naming_the_log_row_and_column() {
    let d = common::scratch("inputs", "log-range");
    // A valid short log of the default robot, then one huge value per case.
    let mut rows = vec!["t,q1,q2,q3,q4,q5,q6,tau1,tau2,tau3,tau4,tau5,tau6".to_string()];
    for k in 0..40 {
        let t = k as f64 * 0.01;
        rows.push(format!(
            "{t},{a},0.5,-0.8,0.1,0.6,0.2,10,-900,-300,2,-20,1",
            a = 0.3 * t
        ));
    }
    for (name, row, col, value, what) in [
        ("tau", 12usize, 8usize, "1e308", "'tau2' = 1e308 N·m"),
        ("q", 20, 3, "-1e308", "'q3' = -1e308 rad"),
        ("t", 30, 0, "1e300", "'t' = 1e300 s"),
    ] {
        let mut r = rows.clone();
        let mut cells: Vec<String> = r[row].split(',').map(String::from).collect();
        cells[col] = value.to_string();
        r[row] = cells.join(",");
        let file = d.join(format!("{name}.csv"));
        std::fs::write(&file, r.join("\n") + "\n").unwrap();
        // The reader refuses it with file, line and column (the header is line 1).
        let e = printwatt::identify::log::read_log(&file, 6, None)
            .map(|_| ())
            .expect_err(name)
            .to_string();
        let at = format!("{name}.csv:{}:", row + 1);
        assert!(
            e.contains(&at) && e.contains(what) && e.contains("outside any physical range"),
            "{name}: {e}"
        );
        // And every command of the measurement loop says so, not "rmse is inf".
        for cmd in ["compare", "diagnose"] {
            let o = common::run(
                &[
                    cmd,
                    "--robot",
                    "abb_irb4600_40_255",
                    "--log",
                    &format!("{name}.csv"),
                ],
                &d,
            );
            assert!(!o.status.success(), "{cmd} {name}");
            let e = common::stderr_of(&o);
            assert!(e.contains(&at) && e.contains(what), "{cmd} {name}: {e}");
            assert!(
                !e.contains("inf") && !e.contains("NaN"),
                "{cmd} {name}: {e}"
            );
        }
    }
}

#[test]
fn huge_numbers_in_messages_are_written_in_scientific_notation() {
    assert_eq!(printwatt::table::show(1e308), "1e308");
    assert_eq!(printwatt::table::show(-2.5e-9), "-2.5e-9");
    assert_eq!(printwatt::table::show(1.25), "1.25");
    assert_eq!(printwatt::table::show(0.0), "0");
}

#[test]
fn an_infinity_or_nan_in_a_drive_file_is_refused_naming_its_key() {
    for (name, from, to, key) in [
        ("reach", "reach_m = 2.55", "reach_m = inf", "robot.reach_m"),
        (
            "kt",
            "torque_constant_nm_per_a = 2.0",
            "torque_constant_nm_per_a = nan",
            "torque_constant_nm_per_a",
        ),
        (
            "big",
            "balancer_base_m = 0.42",
            "balancer_base_m = -inf",
            "balancer_base_m",
        ),
    ] {
        let d = common::scratch("inputs", &format!("drive-{name}"));
        let r = robot_with(&d, from, to);
        let e = printwatt::robot::load(&r)
            .map(|_| ())
            .expect_err(name)
            .to_string();
        assert!(
            e.contains("drive.toml") && e.contains(key) && e.contains("finite"),
            "{name}: {e}"
        );
    }
}

#[test]
fn a_log_without_a_header_row_suggests_naming_its_columns() {
    let d = common::scratch("inputs", "log-no-header");
    let rows: Vec<String> = (0..80)
        .map(|k| {
            let t = k as f64 * 0.01;
            format!("{t},{},0.5,-0.8,0.1,0.6,0.2,10,-900,-300,2,-20,1", 0.3 * t)
        })
        .collect();
    std::fs::write(d.join("raw.csv"), rows.join("\n") + "\n").unwrap();
    let o = common::run(
        &[
            "compare",
            "--robot",
            "abb_irb4600_40_255",
            "--log",
            "raw.csv",
        ],
        &d,
    );
    assert!(!o.status.success());
    let e = common::stderr_of(&o);
    assert!(
        e.contains("raw.csv:1:1") && e.contains("--columns") && e.contains("measurement-logs.md"),
        "{e}"
    );
    // With the columns named, the same file reads.
    let o = common::run(
        &[
            "compare",
            "--robot",
            "abb_irb4600_40_255",
            "--log",
            "raw.csv",
            "--columns",
            "t, q1..q6, tau1..tau6",
        ],
        &d,
    );
    assert!(o.status.success(), "{}", common::stderr_of(&o));
}
