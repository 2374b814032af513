//! Named regression tests for the physical checks of loaded models (`robot::validate`, the URDF
//! reader) and two reader behaviours that had none. Each edits one value of a copy
//! of a shipped robot and asserts the error (or warning) that names the file and the field; each
//! fails if its check is removed (the load would then succeed or the message would be missing).

mod common;
use common::root;

use std::path::{Path, PathBuf};

/// A copy of the ABB IRB 4600 in a fresh directory, with `edit_urdf` / `edit_drive` applied.
fn robot_with(
    name: &str,
    edit_urdf: &dyn Fn(&str) -> String,
    edit_drive: &dyn Fn(&str) -> String,
) -> PathBuf {
    let d = common::scratch("chk", name).join("rob");
    std::fs::create_dir_all(&d).unwrap();
    let src = root().join("robots/abb_irb4600_40_255");
    let u = std::fs::read_to_string(src.join("robot.urdf")).unwrap();
    let t = std::fs::read_to_string(src.join("drive.toml")).unwrap();
    let (u2, t2) = (edit_urdf(&u), edit_drive(&t));
    std::fs::write(d.join("robot.urdf"), u2).unwrap();
    std::fs::write(d.join("drive.toml"), t2).unwrap();
    d
}

fn same(s: &str) -> String {
    s.to_string()
}

/// Replace the first occurrence of `from` (which must exist).
fn once(s: &str, from: &str, to: &str) -> String {
    assert!(s.contains(from), "seed has no `{from}`");
    s.replacen(from, to, 1)
}

/// Replace the line starting with `key =` in the first `[[joints]]` table (or anywhere when
/// `first_joint` is false) by `key = value`.
fn set_key(s: &str, key: &str, value: &str, first_joint: bool) -> String {
    let start = if first_joint {
        s.find("[[joints]]").unwrap()
    } else {
        0
    };
    let i = start + s[start..].find(&format!("\n{key} =")).expect(key) + 1;
    let j = i + s[i..].find('\n').unwrap();
    format!("{}{key} = {value}{}", &s[..i], &s[j..])
}

fn load_err(d: &Path) -> String {
    printwatt::robot::load(d)
        .expect_err("the edited robot must be refused")
        .to_string()
}

#[test]
fn payload_inertia_with_nan_is_refused_naming_the_field() {
    let d = robot_with("pl-nan", &same, &|t| {
        set_key(
            t,
            "inertia_kg_m2",
            "[nan, 0.333, 0.216, 0.0, 0.0, 0.0]",
            false,
        )
    });
    let e = load_err(&d);
    assert!(
        e.contains("drive.toml") && e.contains("payload.inertia_kg_m2"),
        "{e}"
    );
}

#[test]
fn payload_com_with_nan_is_refused_naming_the_field() {
    let d = robot_with("pl-com-nan", &same, &|t| {
        set_key(t, "com_m", "[0.0, nan, 0.15]", false)
    });
    let e = load_err(&d);
    assert!(
        e.contains("drive.toml") && e.contains("payload.com_m"),
        "{e}"
    );
}

#[test]
fn payload_inertia_violating_the_triangle_inequality_is_refused() {
    // Positive definite, but Ixx + Iyy < Izz: no rigid body has it.
    let d = robot_with("pl-tri", &same, &|t| {
        set_key(t, "inertia_kg_m2", "[0.1, 0.1, 1.0, 0.0, 0.0, 0.0]", false)
    });
    let e = load_err(&d);
    assert!(
        e.contains("payload.inertia_kg_m2") && e.contains("triangle inequality"),
        "{e}"
    );
}

#[test]
fn gear_efficiency_of_1e_minus_300_is_refused_naming_the_joint() {
    let d = robot_with("eff", &same, &|t| {
        set_key(t, "gear_efficiency", "1e-300", true)
    });
    let e = load_err(&d);
    assert!(
        e.contains("drive.toml") && e.contains("joints[0]") && e.contains("gear_efficiency"),
        "{e}"
    );
}

#[test]
fn huge_viscous_coefficient_is_refused_naming_the_joint() {
    let d = robot_with("visc", &same, &|t| {
        set_key(t, "viscous_nm_s_per_rad", "1e300", true)
    });
    let e = load_err(&d);
    assert!(
        e.contains("joints[0]") && e.contains("viscous_nm_s_per_rad"),
        "{e}"
    );
}

#[test]
fn huge_link_inertia_is_refused_naming_the_link() {
    let d = robot_with(
        "inertia",
        &|u| once(u, "ixx=\"4.415859778951\"", "ixx=\"1e300\""),
        &same,
    );
    let e = load_err(&d);
    assert!(
        e.contains("robot.urdf") && e.contains("inertia") && e.contains("link `"),
        "{e}"
    );
}

#[test]
fn nan_opw_parameter_is_refused_naming_the_field() {
    let d = robot_with("opw-nan", &same, &|t| set_key(t, "c2_m", "nan", false));
    let e = load_err(&d);
    assert!(
        e.contains("drive.toml") && e.contains("kinematics.c2_m"),
        "{e}"
    );
}

#[test]
fn nan_tool_offset_is_refused_naming_the_field() {
    let d = robot_with("tool-nan", &same, &|t| {
        set_key(t, "xyz_m", "[0.0, nan, 0.3]", false)
    });
    let e = load_err(&d);
    assert!(e.contains("drive.toml") && e.contains("tool.xyz_m"), "{e}");
}

#[test]
fn moving_link_with_zero_mass_and_inertia_is_refused() {
    // link_1, the first moving link: the check used to start at the second one.
    let d = robot_with(
        "zero-mass",
        &|u| {
            let u = once(u, "<mass value=\"125.793\"/>", "<mass value=\"0\"/>");
            once(
                &u,
                "<inertia ixx=\"4.415859778951\" ixy=\"0.0\" ixz=\"0.880179449226\" iyy=\"3.793510673438\" iyz=\"0.0\" izz=\"5.038335894486\"/>",
                "<inertia ixx=\"0\" ixy=\"0\" ixz=\"0\" iyy=\"0\" iyz=\"0\" izz=\"0\"/>",
            )
        },
        &same,
    );
    let e = load_err(&d);
    assert!(
        e.contains("robot.urdf") && e.contains("zero mass and zero inertia"),
        "{e}"
    );
}

#[test]
fn urdf_velocity_zero_is_read_as_unknown_with_a_warning_naming_the_joint() {
    // Hand-written and textbook URDFs write velocity="0" for "not given": compare, diagnose
    // and identify never use the limit, so the robot loads, with a warning.
    let d = robot_with(
        "vel0",
        &|u| once(u, "velocity=\"3.0543261909900767\"", "velocity=\"0\""),
        &same,
    );
    let r = printwatt::robot::load(&d).unwrap();
    assert!(
        r.warnings
            .iter()
            .any(|w| w.contains("velocity=\"0\"") && w.contains("joint `")),
        "{:?}",
        r.warnings
    );
    assert!(r.joints.iter().any(|j| j.velocity_limit.is_infinite()));
}

#[test]
fn drive_file_with_five_joint_entries_for_six_joints_is_refused() {
    let d = robot_with("len", &same, &|t| {
        let i = t.rfind("[[joints]]").unwrap();
        t[..i].to_string()
    });
    let e = load_err(&d);
    assert!(
        e.contains("drive.toml")
            && e.contains("5 [[joints]] tables")
            && e.contains("6 actuated joints"),
        "{e}"
    );
}

#[test]
fn log_whose_metadata_names_another_robot_warns() {
    let d = robot_with("log-robot", &same, &same);
    let mut log =
        String::from("# robot: ur10e\nt,q1,q2,q3,q4,q5,q6,tau1,tau2,tau3,tau4,tau5,tau6\n");
    for k in 0..80 {
        log.push_str(&format!("{:.3},0,0,0,0,0,0,1,1,1,1,1,1\n", k as f64 * 0.01));
    }
    let l = d.parent().unwrap().join("l.csv");
    std::fs::write(&l, log).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .args([
            "compare",
            "--robot",
            d.to_str().unwrap(),
            "--log",
            l.to_str().unwrap(),
            "--json",
        ])
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{e}");
    assert!(
        e.contains("names robot `ur10e`") && e.contains("l.csv"),
        "{e}"
    );
}

#[test]
fn semicolon_separated_export_with_decimal_commas_is_read() {
    // A European spreadsheet export: `;` between fields, `,` as the decimal mark.
    let d = common::scratch("chk", "semicolon");
    let p = d.join("p.csv");
    std::fs::write(&p, "x[mm];y[mm];z[mm]\n0;0;0\n10,5;0;0\n10,5;20,25;0\n").unwrap();
    let tp = printwatt::toolpath::load(&p, &Default::default()).expect("a ; export reads");
    assert_eq!(tp.moves.len(), 2);
    assert!(
        (tp.moves[0].end[0] - 0.0105).abs() < 1e-12,
        "{:?}",
        tp.moves[0].end
    );
    assert!(
        (tp.moves[1].end[1] - 0.02025).abs() < 1e-12,
        "{:?}",
        tp.moves[1].end
    );
}
