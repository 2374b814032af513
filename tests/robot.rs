//! Loading users' URDFs: meshes ignored, fixed joints merged (checked through the dynamics),
//! passive/mimic side branches frozen and merged, continuous joints, and clear errors.

use printwatt::dynamics::{rnea, DynModel, DynOptions};
use printwatt::robot::urdf::parse_urdf;

/// A two-joint arm. `tip` is either one link with the mass of two bodies merged by hand, or a
/// link with a fixed child carrying the second body; `extra` is appended inside <robot>.
fn arm(tip: &str, extra: &str) -> String {
    format!(
        r#"<?xml version="1.0"?>
<robot name="two">
  <link name="world"/>
  <link name="base"><visual><geometry><mesh filename="package://nowhere/base.stl"/></geometry></visual></link>
  <joint name="to_base" type="fixed"><parent link="world"/><child link="base"/><origin xyz="0 0 0.5"/></joint>
  <link name="l1">
    <inertial><origin xyz="0.2 0 0" rpy="0 0 0"/><mass value="3"/><inertia ixx="0.01" iyy="0.05" izz="0.05" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="2" effort="100"/></joint>
  <joint name="j2" type="continuous"><parent link="l1"/><child link="l2"/><origin xyz="0.4 0 0" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/></joint>
  {tip}
  {extra}
</robot>"#
    )
}

const SPLIT: &str = r#"
  <link name="l2"><inertial><origin xyz="0.1 0 0"/><mass value="2"/><inertia ixx="0.002" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="fix" type="fixed"><parent link="l2"/><child link="tool"/><origin xyz="0.3 0 0" rpy="0 0.5 0"/></joint>
  <link name="tool"><inertial><origin xyz="0 0 0.05" rpy="0.3 0 0"/><mass value="1"/><inertia ixx="0.001" iyy="0.002" izz="0.003" ixy="0" ixz="0" iyz="0"/></inertial><collision><geometry><mesh filename="tool.dae"/></geometry></collision></link>
"#;

#[test]
fn fixed_children_are_merged_exactly() {
    let split = parse_urdf(&arm(SPLIT, ""), "split.urdf", None).unwrap();
    assert_eq!(split.dof(), 2);
    assert_eq!(split.flange_link, "tool");
    assert!(
        split.warnings.iter().any(|w| w.contains("mesh")),
        "{:?}",
        split.warnings
    );
    assert!(
        split.joints[1].upper.is_infinite(),
        "continuous joint has no limits"
    );
    // Merged mass and centre of mass, by hand: body A 2 kg at (0.1,0,0); body B 1 kg at
    // (0.3,0,0) + Ry(0.5)·(0,0,0.05).
    let l2 = split.links[1].unwrap();
    assert!((l2.mass - 3.0).abs() < 1e-15);
    let b = nalgebra::Vector3::new(0.3 + 0.05 * 0.5f64.sin(), 0.0, 0.05 * 0.5f64.cos());
    let com = (nalgebra::Vector3::new(0.1, 0.0, 0.0) * 2.0 + b) / 3.0;
    assert!((l2.com - com).norm() < 1e-15);
    // Through the dynamics: the same torques as a robot whose l2 carries the merged inertial
    // written out by hand.
    let i = l2.inertia;
    let merged = format!(
        r#"<link name="l2"><inertial><origin xyz="{} {} {}"/><mass value="3"/><inertia ixx="{}" iyy="{}" izz="{}" ixy="{}" ixz="{}" iyz="{}"/></inertial></link>"#,
        com.x,
        com.y,
        com.z,
        i[(0, 0)],
        i[(1, 1)],
        i[(2, 2)],
        i[(0, 1)],
        i[(0, 2)],
        i[(1, 2)]
    );
    let one = parse_urdf(&arm(&merged, ""), "one.urdf", None).unwrap();
    let opts = DynOptions {
        payload: false,
        armature: false,
    };
    let (ma, mb) = (
        DynModel::new(&split, opts).unwrap(),
        DynModel::new(&one, opts).unwrap(),
    );
    let (mut da, mut db) = (ma.data(), mb.data());
    let (mut ta, mut tb) = ([0.0; 2], [0.0; 2]);
    for k in 0..20 {
        let x = k as f64 * 0.37;
        let (q, qd, qdd) = ([x.sin(), x.cos()], [0.3 * x.cos(), -0.2], [0.5, x.sin()]);
        rnea(&ma, &mut da, &q, &qd, &qdd, &mut ta).unwrap();
        rnea(&mb, &mut db, &q, &qd, &qdd, &mut tb).unwrap();
        for j in 0..2 {
            assert!(
                (ta[j] - tb[j]).abs() < 1e-12 * (1.0 + ta[j].abs()),
                "{ta:?} vs {tb:?}"
            );
        }
    }
}

#[test]
fn passive_mimic_branches_are_frozen_and_merged_with_a_warning() {
    let massless = r#"
  <joint name="cyl" type="revolute"><parent link="l1"/><child link="cylinder"/><origin xyz="0.1 0 0"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" velocity="1" effort="0"/><mimic joint="j2" multiplier="-0.25"/></joint>
  <link name="cylinder"/>"#;
    let m = parse_urdf(&arm(SPLIT, massless), "m.urdf", None).unwrap();
    assert_eq!(m.dof(), 2);
    assert!(
        m.warnings
            .iter()
            .any(|w| w.contains("cyl") && w.contains("massless")),
        "{:?}",
        m.warnings
    );
    let heavy = r#"
  <joint name="cyl" type="revolute"><parent link="l1"/><child link="cylinder"/><origin xyz="0.1 0 0"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" velocity="1" effort="0"/><mimic joint="j2" multiplier="-0.25"/></joint>
  <link name="cylinder"><inertial><mass value="5"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>"#;
    let h = parse_urdf(&arm(SPLIT, heavy), "h.urdf", None).unwrap();
    assert!(
        (h.links[0].unwrap().mass - 8.0).abs() < 1e-12,
        "5 kg merged into l1"
    );
    assert!(
        h.warnings.iter().any(|w| w.contains("carry mass")),
        "{:?}",
        h.warnings
    );
}

#[test]
fn malformed_urdfs_name_the_line() {
    let bad_number = arm(SPLIT, "").replace(r#"<mass value="2"/>"#, r#"<mass value="two"/>"#);
    let e = parse_urdf(&bad_number, "b.urdf", None)
        .unwrap_err()
        .to_string();
    let line = bad_number
        .lines()
        .position(|l| l.contains("value=\"two\""))
        .unwrap()
        + 1;
    assert!(
        e.starts_with(&format!("b.urdf:{line}:")) && e.contains("`two`"),
        "{e}"
    );
    let no_limit = arm(SPLIT, "").replace(
        r#"<limit lower="-3" upper="3" velocity="2" effort="100"/>"#,
        "",
    );
    let e = parse_urdf(&no_limit, "c.urdf", None)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("c.urdf:") && e.contains("j1") && e.contains("<limit>"),
        "{e}"
    );
    let floating = arm(SPLIT, "").replace(r#"type="continuous""#, r#"type="floating""#);
    let e = parse_urdf(&floating, "d.urdf", None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("floating") && e.contains("not supported"), "{e}");
    let e = parse_urdf(&arm(SPLIT, ""), "e.urdf", Some("nope"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("tool_link `nope`"), "{e}");
    let e = parse_urdf("<robot><link name='a'/>", "f.urdf", None)
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("f.urdf:1:"), "{e}");
}
