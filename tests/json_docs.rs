//! Stable JSON: the `--json` output of `simulate`, `compare`, `diagnose` and
//! `identify` against the field lists of docs/json.md (the ```` ```fields <command> ```` blocks),
//! both ways, so that the documentation and the output cannot drift apart: every field the
//! output has is documented, and every documented field is present wherever its parent is
//! non-null and non-empty. Arrays are written `name[]`, nested fields `a.b`.

mod common;
use common::root;

use serde_json::Value;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn run(dir: &Path, args: &[&str]) -> String {
    String::from_utf8(common::run_ok(args, dir).stdout).unwrap()
}

/// The documented field paths of `command` (docs/json.md, block ```` ```fields command ````).
fn documented(command: &str) -> BTreeSet<String> {
    let text = std::fs::read_to_string(root().join("docs/json.md")).unwrap();
    let open = format!("```fields {command}");
    let start = text
        .lines()
        .position(|l| l.trim() == open)
        .unwrap_or_else(|| panic!("docs/json.md has no `{open}` block"));
    text.lines()
        .skip(start + 1)
        .take_while(|l| l.trim() != "```")
        .map(|l| l.trim().to_string())
        .filter(|l| !l.is_empty())
        .collect()
}

/// Every field path of a JSON value, and the paths that have children (non-null objects,
/// arrays with object elements).
fn paths(v: &Value, pre: &str, out: &mut BTreeSet<String>, parents: &mut BTreeSet<String>) {
    match v {
        Value::Object(m) => {
            if !m.is_empty() {
                parents.insert(pre.to_string());
            }
            for (k, x) in m {
                let p = if pre.is_empty() {
                    k.clone()
                } else {
                    format!("{pre}.{k}")
                };
                out.insert(p.clone());
                paths(x, &p, out, parents);
            }
        }
        Value::Array(a) => {
            let p = format!("{pre}[]");
            for x in a {
                if x.is_object() || x.is_array() {
                    paths(x, &p, out, parents);
                }
            }
        }
        _ => {}
    }
}

fn parent_of(p: &str) -> String {
    match p.rfind('.') {
        Some(i) => p[..i].to_string(),
        None => String::new(),
    }
}

/// Check one command's output against docs/json.md.
fn check(command: &str, outputs: &[&str]) {
    let doc = documented(command);
    let (mut seen, mut parents) = (BTreeSet::new(), BTreeSet::new());
    for o in outputs {
        let v: Value = serde_json::from_str(o).unwrap();
        assert_eq!(
            v["schema_version"].as_u64(),
            Some(printwatt::identify::JSON_SCHEMA_VERSION as u64),
            "{command}: schema_version"
        );
        paths(&v, "", &mut seen, &mut parents);
    }
    let undocumented: Vec<&String> = seen.difference(&doc).collect();
    assert!(
        undocumented.is_empty(),
        "{command}: fields in the output that docs/json.md does not list: {undocumented:?}"
    );
    // A documented field must be there wherever its parent (or its array element) is.
    let missing: Vec<&String> = doc
        .iter()
        .filter(|d| {
            let par = parent_of(d);
            parents.contains(&par) && !seen.contains(*d)
        })
        .collect();
    assert!(
        missing.is_empty(),
        "{command}: fields docs/json.md lists that the output lacks: {missing:?}"
    );
}

/// A short simulated torque log (IRB 4600, Coulomb friction hidden) in `dir/log.csv`.
fn log_in(dir: &Path) -> PathBuf {
    let robot = root().join("robots/abb_irb4600_40_255");
    run(
        dir,
        &[
            "simulate",
            "--robot",
            robot.to_str().unwrap(),
            "--excite",
            "4",
            "--hidden",
            "coulomb=20",
            "--signal",
            "tau",
            "--noise",
            "2",
            "--rate",
            "100",
            "--seed",
            "3",
            "--out",
            dir.to_str().unwrap(),
        ],
    );
    dir.join("log.csv")
}

fn robot_arg() -> String {
    root()
        .join("robots/abb_irb4600_40_255")
        .to_string_lossy()
        .into_owned()
}

#[test]
fn json_output_of_simulate_matches_docs_json_md() {
    let d = common::scratch("json", "simulate");
    let r = robot_arg();
    let base = [
        "simulate", "--robot", &r, "--excite", "1", "--signal", "tau", "--rate", "50", "--seed",
        "1", "--json",
    ];
    let rows = run(&d, &base);
    let mut with_out: Vec<&str> = base.to_vec();
    let out = d.join("o");
    let out_s = out.to_string_lossy().into_owned();
    with_out.extend(["--out", &out_s]);
    let file = run(&d, &with_out);
    check("simulate", &[&rows, &file]);
}

#[test]
fn json_output_of_compare_matches_docs_json_md() {
    let d = common::scratch("json", "compare");
    let log = log_in(&d);
    let out = run(
        &d,
        &[
            "compare",
            "--robot",
            &robot_arg(),
            "--log",
            log.to_str().unwrap(),
            "--json",
        ],
    );
    check("compare", &[&out]);
}

#[test]
fn json_output_of_diagnose_matches_docs_json_md() {
    let d = common::scratch("json", "diagnose");
    let log = log_in(&d);
    let out = run(
        &d,
        &[
            "diagnose",
            "--robot",
            &robot_arg(),
            "--log",
            log.to_str().unwrap(),
            "--json",
        ],
    );
    check("diagnose", &[&out]);
}

#[test]
fn json_output_of_identify_matches_docs_json_md() {
    let d = common::scratch("json", "identify");
    let log = log_in(&d);
    let out = run(
        &d,
        &[
            "identify",
            "--robot",
            &robot_arg(),
            "--log",
            log.to_str().unwrap(),
            "--effects",
            "coulomb",
            "--out",
            d.join("id").to_str().unwrap(),
            "--json",
        ],
    );
    check("identify", &[&out]);
}

/// The documented fields of one object against the object itself, both ways.
fn check_object(block: &str, v: &Value) {
    let doc = documented(block);
    let (mut seen, mut parents) = (BTreeSet::new(), BTreeSet::new());
    assert!(v.is_object(), "{block}: not an object: {v}");
    paths(v, "", &mut seen, &mut parents);
    let undocumented: Vec<&String> = seen.difference(&doc).collect();
    assert!(
        undocumented.is_empty(),
        "{block}: fields in the output that docs/json.md does not list: {undocumented:?}"
    );
    let missing: Vec<&String> = doc.difference(&seen).collect();
    assert!(
        missing.is_empty(),
        "{block}: fields docs/json.md lists that the output lacks: {missing:?}"
    );
}

#[test]
fn json_path_reduction_of_optimise_matches_docs_json_md() {
    let d = common::scratch("json", "reduction");
    // Five layers of the shipped wall's outline (1200 x 40 mm), 15 mm apart, seams alternating.
    let mut g = String::from("G21\nG90\nM83\n");
    for k in 0..5 {
        let z = 15.0 * (k + 1) as f64;
        let c = if k % 2 == 0 {
            [
                "X-600 Y-20",
                "X600 Y-20",
                "X600 Y20",
                "X-600 Y20",
                "X-600 Y-20",
            ]
        } else {
            [
                "X600 Y20",
                "X-600 Y20",
                "X-600 Y-20",
                "X600 Y-20",
                "X600 Y20",
            ]
        };
        g += &format!("G0 F12000 Z{}\nG0 {}\nG0 Z{z}\n", z + 10.0, c[0]);
        for p in &c[1..] {
            g += &format!("G1 F9000 {p} E1\n");
        }
    }
    std::fs::write(d.join("wall5.gcode"), g).unwrap();
    let out = run(
        &d,
        &[
            "optimise",
            "--robot",
            root().join("robots/abb_irb6700_200_260").to_str().unwrap(),
            "--path",
            "wall5.gcode",
            "--at",
            "1.8,0,0,0",
            "--max-evals",
            "0",
            "--tolerance",
            "0,0",
            "--evaluation",
            "reduced",
            "--wrist-margin",
            "0",
            "--json",
        ],
    );
    let v: Value = serde_json::from_str(&out).unwrap();
    check_object("optimise.path_reduction", &v["optimise"]["path_reduction"]);
    check_object(
        "outcome.path_reduction",
        &v["optimise"]["best_grid"]["outcome"]["path_reduction"],
    );
}

#[test]
fn json_output_of_stations_matches_docs_json_md() {
    let d = common::scratch("json", "stations");
    // Two 1.5 m wall pieces with a travel between them, stations along a track beside them.
    std::fs::write(
        d.join("wall.gcode"),
        "G21\nG90\nG0 X0 Y0 Z20 F12000\nM3\nG1 X1500 Y0 F9000\nM5\nG0 Z70\nG0 X1500\nG0 Z20\nM3\nG1 X3000\nM5\n",
    )
    .unwrap();
    let out = run(
        &d,
        &[
            "stations",
            "--path",
            "wall.gcode",
            "--relocation-cost",
            "5000",
            "--track",
            "-0.5,-1.2:3.5,-1.2",
            "--wrist-margin",
            "0",
            "--json",
        ],
    );
    check("stations", &[&out]);
}

#[test]
fn json_output_of_inspect_matches_docs_json_md() {
    let d = common::scratch("json", "inspect");
    std::fs::write(
        d.join("p.csv"),
        "x,y,z,print\n0,0,20,1\n500,0,20,1\n500,0,40,0\n",
    )
    .unwrap();
    let g = root().join("paths/default.gcode");
    let a = run(&d, &["inspect", g.to_str().unwrap(), "--json"]);
    let b = run(&d, &["inspect", "p.csv", "--json"]);
    let r = root().join("tests/data/rapid/two_workobjects.mod");
    let c = run(
        &d,
        &[
            "inspect",
            r.to_str().unwrap(),
            "--proc",
            "path_plano",
            "--json",
        ],
    );
    check("inspect", &[&a, &b, &c]);
    let _ = std::fs::remove_dir_all(&d);
}
