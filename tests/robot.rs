//! Loading users' URDFs: meshes ignored, fixed joints merged (checked through the dynamics),
//! passive/mimic side branches frozen and merged, continuous joints, and clear errors.

mod common;

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
fn passive_mimic_branches_are_frozen_and_merged_with_a_warning_and_massless_ones_left_quietly() {
    let massless = r#"
  <joint name="cyl" type="revolute"><parent link="l1"/><child link="cylinder"/><origin xyz="0.1 0 0"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" velocity="1" effort="0"/><mimic joint="j2" multiplier="-0.25"/></joint>
  <link name="cylinder"/>"#;
    let m = parse_urdf(&arm(SPLIT, massless), "m.urdf", None).unwrap();
    assert_eq!(m.dof(), 2);
    // A massless passive branch changes no torque: no warning (the shipped IRB 6700's
    // balancer cylinder and piston would otherwise be warned about in every command).
    assert!(
        !m.warnings.iter().any(|w| w.contains("cyl")),
        "{:?}",
        m.warnings
    );
    let shipped =
        printwatt::robot::load(&common::root().join("robots/abb_irb6700_200_260")).unwrap();
    assert!(
        !shipped
            .warnings
            .iter()
            .any(|w| w.contains("cylinder_joint")),
        "{:?}",
        shipped.warnings
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

fn field_robot(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/field_robots")
        .join(name)
}

#[test]
fn a_field_urdf_without_inertials_loads_with_estimated_inertias_labelled_estimate() {
    use printwatt::robot::inertia::InertiaSource;
    let m = printwatt::robot::load(&field_robot("abb_irb6640_185_280.urdf")).unwrap();
    assert_eq!(m.dof(), 6);
    assert_eq!(
        m.info.inertia_sources,
        vec![InertiaSource::EstimateFromCapsule; 6]
    );
    for (i, l) in m.links.iter().enumerate() {
        let l = l.unwrap_or_else(|| panic!("link {i} left without inertia"));
        assert!(l.mass.is_finite() && l.mass > 0.0, "link {i}: {l:?}");
    }
    let w = m.warnings.join("\n");
    assert!(
        w.contains("ESTIMATE") && w.contains("`link_1`") && w.contains("kg/m³"),
        "{w}"
    );
    // The estimate is what dynamics run on: no "has no <inertial>" any more.
    assert!(DynModel::new(&m, DynOptions::default()).is_ok());
}

#[test]
fn placeholder_inertias_are_warned() {
    let m = printwatt::robot::load(&field_robot("kuka_kr120r2500pro.urdf")).unwrap();
    let w = m.warnings.join("\n");
    assert!(
        w.contains("same mass, 2 kg") && w.contains("placeholder"),
        "{w}"
    );
    assert!(!w.contains("ESTIMATE"), "{w}");
    // With the rated payload stated, the total below it is a second warning.
    let d = std::env::temp_dir().join(format!("printwatt-kr120-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    std::fs::copy(field_robot("kuka_kr120r2500pro.urdf"), d.join("robot.urdf")).unwrap();
    std::fs::write(d.join("drive.toml"), "[robot]\nrated_payload_kg = 120.0\n").unwrap();
    let m = printwatt::robot::load(&d).unwrap();
    let w = m.warnings.join("\n");
    assert!(w.contains("less than the rated payload of 120 kg"), "{w}");
}

#[test]
fn drive_file_links_tables_give_missing_inertias_and_name_a_bad_key() {
    use printwatt::robot::inertia::InertiaSource;
    let d = std::env::temp_dir().join(format!("printwatt-irb6640-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    std::fs::copy(
        field_robot("abb_irb6640_185_280.urdf"),
        d.join("robot.urdf"),
    )
    .unwrap();
    std::fs::write(
        d.join("drive.toml"),
        "[links.link_2]\nmass_kg = 250.0\ncom_m = [0.0, 0.0, 0.5]\ninertia_kg_m2 = [40.0, 40.0, 5.0, 0.0, 0.0, 0.0]\n",
    )
    .unwrap();
    let m = printwatt::robot::load(&d).unwrap();
    assert_eq!(m.info.inertia_sources[1], InertiaSource::DriveFile);
    assert_eq!(
        m.info.inertia_sources[0],
        InertiaSource::EstimateFromCapsule
    );
    let l2 = m.links[1].unwrap();
    assert_eq!(l2.mass, 250.0);
    assert_eq!(l2.com, printwatt::math::V3::new(0.0, 0.0, 0.5));
    assert_eq!(l2.inertia[(0, 0)], 40.0);
    assert!(!m.warnings.join("\n").contains("`link_2`"));
    std::fs::write(
        d.join("drive.toml"),
        "[links.link_9]\nmass_kg = 250.0\ncom_m = [0.0, 0.0, 0.5]\ninertia_kg_m2 = [40.0, 40.0, 5.0, 0.0, 0.0, 0.0]\n",
    )
    .unwrap();
    let e = printwatt::robot::load(&d).unwrap_err().to_string();
    assert!(
        e.contains("drive.toml") && e.contains("links.link_9") && e.contains("link_6"),
        "{e}"
    );
    std::fs::write(
        d.join("drive.toml"),
        "[links.link_2]\nmass_kg = 250.0\ncom_m = [0.0, 0.0, 0.5]\ninertia_kg_m2 = [1.0, 1.0, 5.0, 0.0, 0.0, 0.0]\n",
    )
    .unwrap();
    let e = printwatt::robot::load(&d).unwrap_err().to_string();
    assert!(
        e.contains("links.link_2.inertia_kg_m2") && e.contains("triangle"),
        "{e}"
    );
}

#[test]
fn capsule_estimate_of_the_irb6700_is_within_a_quarter_of_its_moving_mass() {
    let mut m = printwatt::load_robot(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/robots/abb_irb6700_200_260"
    )))
    .unwrap();
    let truth: f64 = m.links.iter().flatten().map(|l| l.mass).sum();
    // The shipped arm has published collision hulls: without them, the capsules stand in.
    assert!(m.link_collision.iter().any(|c| !c.is_empty()));
    for c in &mut m.link_collision {
        c.clear();
    }
    for l in &mut m.links {
        *l = None;
    }
    m.info.inertia_sources.clear();
    printwatt::robot::inertia::complete(&mut m);
    let est: f64 = m.links.iter().flatten().map(|l| l.mass).sum();
    eprintln!("IRB 6700 moving mass: {truth:.1} kg, capsule estimate {est:.1} kg");
    assert!((est / truth - 1.0).abs() < 0.25, "{est} vs {truth}");
}

#[test]
fn a_link_without_collision_geometry_is_estimated_from_its_visual_shapes() {
    use printwatt::robot::inertia::{InertiaSource, ESTIMATE_DENSITY_KG_M3};
    let urdf = r#"<robot name="vis">
  <link name="base"/>
  <link name="l1"><visual><geometry><box size="0.2 0.3 0.5"/></geometry></visual></link>
  <link name="l2"><collision><geometry><box size="0.1 0.1 0.4"/></geometry></collision>
    <visual><geometry><box size="1 1 1"/></geometry></visual></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="2"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 0.5"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" velocity="2"/></joint>
</robot>"#;
    let d = std::env::temp_dir().join(format!("printwatt-visual-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(d.join("robot.urdf"), urdf).unwrap();
    let m = printwatt::robot::load(&d.join("robot.urdf")).unwrap();
    assert_eq!(
        m.info.inertia_sources,
        vec![
            InertiaSource::EstimateFromVisual,
            InertiaSource::EstimateFromGeometry
        ]
    );
    // The visual box for l1; l2's collision box wins over its (larger) visual one.
    let mass = |i: usize| m.links[i].unwrap().mass;
    assert!((mass(0) - ESTIMATE_DENSITY_KG_M3 * 0.2 * 0.3 * 0.5).abs() < 1e-9);
    assert!((mass(1) - ESTIMATE_DENSITY_KG_M3 * 0.1 * 0.1 * 0.4).abs() < 1e-9);
    let w = m.warnings.join("\n");
    assert!(w.contains("visual shapes") && w.contains("±50 %"), "{w}");
}

/// The ROS-Industrial IRB 6640-185/2.80 (no `<inertial>`, collision meshes) loaded through a
/// drive file in a temporary directory with the given `[robot]` keys.
fn ros_i_irb6640(tag: &str, robot_keys: &str) -> printwatt::robot::RobotModel {
    let urdf = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/ros_industrial/abb_irb6640_support/urdf/irb6640_185_280.urdf");
    let d = std::env::temp_dir().join(format!("printwatt-mass-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let f = d.join("drive.toml");
    std::fs::write(
        &f,
        format!("[robot]\nurdf = {:?}\n{robot_keys}", urdf.to_str().unwrap()),
    )
    .unwrap();
    let m = printwatt::robot::load(&f).unwrap_or_else(|e| panic!("{e}"));
    let _ = std::fs::remove_dir_all(&d);
    m
}

#[test]
fn estimated_link_masses_are_scaled_to_the_drive_files_robot_mass() {
    // ABB's data sheet of the IRB 6640: 1,310 kg for the 2.55–2.80 m variants (the
    // 185/2.80 among them), 1,405 kg for the 130/3.20.
    let plain = ros_i_irb6640("plain", "");
    let scaled = ros_i_irb6640("scaled", "mass_kg = 1310.0\n");
    let w = scaled.warnings.join("\n");
    assert!(w.contains("[robot] mass_kg = 1310 kg"), "{w}");
    // Without the key the warning says what it would do; with it, no ±50 % on the total.
    assert!(plain.warnings.join("\n").contains("mass_kg"));
    assert!(plain.warnings.join("\n").contains("±50 %"));
    let f: f64 = w
        .split("scaled by ")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no factor in {w}"));
    let base: f64 = w
        .split("estimated the same way (")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no base mass in {w}"));
    // The hulls at 1,200 kg/m³ weigh less than the datasheet's robot: scaled up.
    assert!(f > 1.0 && f < 3.0, "{f}");
    let mut moving = 0.0;
    for i in 0..6 {
        let (a, b) = (plain.links[i].unwrap(), scaled.links[i].unwrap());
        // Every link by the same factor, its inertia with it, its centre of mass kept.
        let k = b.mass / a.mass;
        assert!((k - f).abs() < 0.5e-3 * f, "link {i}: {k} vs {f}");
        assert!((b.inertia[(0, 0)] / a.inertia[(0, 0)] - k).abs() < 1e-9 * k);
        assert!((b.inertia[(1, 2)] - k * a.inertia[(1, 2)]).abs() < 1e-9 * a.inertia.norm());
        assert_eq!(a.com, b.com);
        moving += b.mass;
    }
    // Links and base (scaled alike) weigh the stated mass, to the warning's rounding.
    let total = moving + base * moving / plain.links.iter().flatten().map(|l| l.mass).sum::<f64>();
    assert!((total - 1310.0).abs() < 2.0, "{total} kg");
    // The energy follows the heavier links.
    assert!(scaled.links[1].unwrap().mass > plain.links[1].unwrap().mass);
}

#[test]
fn a_robot_mass_below_the_links_given_is_not_applied_and_a_bad_one_is_refused() {
    let m = ros_i_irb6640(
        "light",
        "mass_kg = 100.0\n\n[links.link_2]\nmass_kg = 250.0\ncom_m = [0.0, 0.0, 0.5]\ninertia_kg_m2 = [40.0, 40.0, 5.0, 0.0, 0.0, 0.0]\n",
    );
    let w = m.warnings.join("\n");
    assert!(
        w.contains("not scaled to the drive file's [robot] mass_kg"),
        "{w}"
    );
    assert!(w.contains("250 kg, not less than the stated 100 kg"), "{w}");
    let urdf = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/ros_industrial/abb_irb6640_support/urdf/irb6640_185_280.urdf");
    let d = std::env::temp_dir().join(format!("printwatt-mass-bad-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let f = d.join("drive.toml");
    std::fs::write(
        &f,
        format!(
            "[robot]\nurdf = {:?}\nmass_kg = -5.0\n",
            urdf.to_str().unwrap()
        ),
    )
    .unwrap();
    let e = printwatt::robot::load(&f).unwrap_err().to_string();
    assert!(
        e.contains("drive.toml") && e.contains("robot.mass_kg"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&d);
}
