//! Collision geometry (parry3d-f64): distances against closed-form ones, a user's URDF
//! `<collision>` elements used (boxes, cylinders, meshes), the print head and hose, the bed,
//! and the growing part.

mod common;

use parry3d_f64::math::{Isometry, Point, Vector};
use parry3d_f64::query;
use parry3d_f64::shape::{Ball, Capsule, Cuboid, Cylinder, SharedShape};
use printwatt::math::{Frame, V3};
use printwatt::placement::collision::{self, Beads, Bed, RobotShapes, Role};
use printwatt::placement::feasibility::{LinkRadii, Reason};
use printwatt::robot::load;
use std::path::Path;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-6
}

#[test]
fn parry_distances_match_analytic_ones() {
    let id = Isometry::identity();
    // Box (half extents 1, 2, 3) and a sphere of radius 0.5: face, edge and corner regions.
    let bx = Cuboid::new(Vector::new(1.0, 2.0, 3.0));
    let ball = Ball::new(0.5);
    for (c, want) in [
        (V3::new(3.0, 0.0, 0.0), 2.0 - 0.5),         // face: 3 − 1 − r
        (V3::new(2.0, 3.0, 0.0), 2f64.sqrt() - 0.5), // edge: √(1² + 1²) − r
        (V3::new(2.0, 4.0, 5.0), (1.0f64 + 4.0 + 4.0).sqrt() - 0.5), // corner: √(1+4+4) − r
    ] {
        let d = query::distance(&id, &bx, &Isometry::translation(c.x, c.y, c.z), &ball).unwrap();
        assert!(close(d, want), "box–sphere at {c:?}: {d} vs {want}");
    }
    // Capsule–capsule: parallel (offset 1 in y), skew crossing (0.5 apart), end to end.
    let cap = |a: [f64; 3], b: [f64; 3], r: f64| Capsule::new(Point::from(a), Point::from(b), r);
    let c0 = cap([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 0.1);
    for (c1, want) in [
        (cap([0.0, 1.0, 0.0], [1.0, 1.0, 0.0], 0.2), 1.0 - 0.3),
        (cap([0.5, -1.0, 0.5], [0.5, 1.0, 0.5], 0.05), 0.5 - 0.15),
        (cap([2.0, 0.0, 0.0], [3.0, 0.0, 0.0], 0.1), 1.0 - 0.2),
    ] {
        let d = query::distance(&id, &c0, &id, &c1).unwrap();
        assert!(close(d, want), "capsule–capsule: {d} vs {want}");
    }
    // Cylinder (parry: along y, half height 1, radius 0.5) and a sphere beside its mantle and
    // above its cap.
    let cyl = Cylinder::new(1.0, 0.5);
    let d = query::distance(&id, &cyl, &Isometry::translation(2.0, 0.0, 0.0), &ball).unwrap();
    assert!(close(d, 2.0 - 0.5 - 0.5), "cylinder mantle: {d}");
    let d = query::distance(&id, &cyl, &Isometry::translation(0.0, 3.0, 0.0), &ball).unwrap();
    assert!(close(d, 3.0 - 1.0 - 0.5), "cylinder cap: {d}");
    // A convex hull of the unit cube's corners is the cube: same distances as a cuboid.
    let pts: Vec<Point<f64>> = (0..8)
        .map(|i| Point::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
        .collect();
    let hull = SharedShape::convex_hull(&pts).expect("hull");
    let d = query::distance(
        &id,
        hull.as_ref(),
        &Isometry::translation(3.0, 0.5, 0.5),
        &ball,
    )
    .unwrap();
    assert!(close(d, 2.0 - 0.5), "hull face: {d}");
    // The bed cuboid (our wrapper, corners in m) against a sphere above its top.
    let bed = Bed::new(&V3::new(-1.0, -1.0, -0.5), &V3::new(1.0, 1.0, 0.0));
    let d = query::distance(
        &bed.pose,
        &bed.cuboid,
        &Isometry::translation(0.2, 0.3, 0.7),
        &ball,
    )
    .unwrap();
    assert!(close(d, 0.7 - 0.5), "bed–sphere: {d}");
    // Frames convert exactly: a rotated, shifted frame maps points as Frame::apply does.
    let f = Frame::from_xyz_rpy([0.1, -0.2, 0.3], [0.4, -0.5, 0.6]);
    let p = V3::new(0.7, 0.8, -0.9);
    let a = collision::iso(&f) * Point::from(p);
    assert!((a.coords - f.apply(&p)).norm() < 1e-12);
}

/// A two-joint arm written by the test: base column 0.5 m, link 1 turns about z, link 2 about
/// y, flange 0.6 m along link 2's x. `collision` is the XML inside link 2's `<link>`.
fn arm_urdf(dir: &Path, link2_collision: &str) -> std::path::PathBuf {
    let urdf = format!(
        r#"<robot name="test_arm">
  <link name="base"><inertial><mass value="10"/><inertia ixx="1" iyy="1" izz="1"/></inertial></link>
  <link name="l1"><inertial><mass value="5"/><inertia ixx="1" iyy="1" izz="1"/></inertial></link>
  <link name="l2"><inertial><mass value="5"/><inertia ixx="1" iyy="1" izz="1"/></inertial>
    {link2_collision}
  </link>
  <link name="tool0"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.5"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="2" effort="100"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" velocity="2" effort="100"/></joint>
  <joint name="flange" type="fixed"><parent link="l2"/><child link="tool0"/><origin xyz="0.6 0 0"/></joint>
</robot>"#
    );
    let p = dir.join("arm.urdf");
    std::fs::write(&p, urdf).unwrap();
    p
}

fn tmpdir(tag: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("printwatt-collision-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Binary STL of an axis-aligned box `[lo, hi]` (12 triangles).
fn stl_box(lo: [f32; 3], hi: [f32; 3]) -> Vec<u8> {
    let c = |i: usize| {
        [
            if i & 1 == 0 { lo[0] } else { hi[0] },
            if i & 2 == 0 { lo[1] } else { hi[1] },
            if i & 4 == 0 { lo[2] } else { hi[2] },
        ]
    };
    let faces = [
        [0, 1, 3],
        [0, 3, 2],
        [4, 6, 7],
        [4, 7, 5],
        [0, 4, 5],
        [0, 5, 1],
        [2, 3, 7],
        [2, 7, 6],
        [0, 2, 6],
        [0, 6, 4],
        [1, 5, 7],
        [1, 7, 3],
    ];
    let mut b = vec![0u8; 80];
    b.extend_from_slice(&(faces.len() as u32).to_le_bytes());
    for f in faces {
        b.extend_from_slice(&[0u8; 12]);
        for v in f {
            for x in c(v) {
                b.extend_from_slice(&x.to_le_bytes());
            }
        }
        b.extend_from_slice(&[0u8; 2]);
    }
    b
}

#[test]
fn user_urdf_collision_geometry_is_used() {
    let dir = tmpdir("urdf");
    // Link 2 carries a cylinder along its x (URDF cylinders run along z: pitched by 90°), a box
    // and a mesh given relative to the URDF; a missing mesh is a warning, not an error.
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    std::fs::write(
        dir.join("meshes/l2.stl"),
        stl_box([0.0, -0.05, -0.05], [0.6, 0.05, 0.05]),
    )
    .unwrap();
    let xml = r#"<collision><origin xyz="0.3 0 0" rpy="0 1.5707963267948966 0"/>
        <geometry><cylinder radius="0.08" length="0.6"/></geometry></collision>
      <collision><origin xyz="0.3 0 -0.45"/><geometry><box size="0.2 0.2 0.3"/></geometry></collision>
      <collision><geometry><mesh filename="meshes/l2.stl"/></geometry></collision>
      <collision><geometry><mesh filename="meshes/missing.stl"/></geometry></collision>"#;
    let model = load(&arm_urdf(&dir, xml)).expect("load");
    assert!(
        model
            .warnings
            .iter()
            .any(|w| w.contains("meshes/missing.stl") && w.contains("capsule")),
        "{:?}",
        model.warnings
    );
    assert_eq!(
        model.link_collision[1].len(),
        3,
        "cylinder, box and mesh on link 2"
    );
    let rs = RobotShapes::new(&model, 1.0, &LinkRadii::default());
    assert_eq!(rs.links_with_urdf_geometry, 1);
    let on_l2: Vec<&str> = rs
        .shapes
        .iter()
        .filter(|s| s.body == 2)
        .map(|s| s.label.as_str())
        .collect();
    assert_eq!(
        on_l2,
        [
            "link `l2` (URDF cylinder)",
            "link `l2` (URDF box)",
            "link `l2` (URDF mesh hull)"
        ]
    );
    // Link 1 has no geometry: a capsule stands in.
    assert!(rs
        .shapes
        .iter()
        .any(|s| s.body == 1 && s.label == "capsule of link `l1`"));

    // Distances to a bed whose top is at z = 0 (base frame = part frame here): link 2 is
    // horizontal at z = 0.7 at q = 0. Cylinder: 0.7 − 0.08; box: bottom at 0.7 − 0.45 − 0.15;
    // mesh hull: 0.7 − 0.05.
    let bed = Bed::new(&V3::new(-3.0, -3.0, -0.5), &V3::new(3.0, 3.0, 0.0));
    let poses = rs.poses(&model, &[0.0, 0.0], &Isometry::identity());
    let dist = |label: &str| {
        let i = rs.shapes.iter().position(|s| s.label == label).unwrap();
        query::distance(
            &poses[i],
            rs.shapes[i].shape.as_ref(),
            &bed.pose,
            &bed.cuboid,
        )
        .unwrap()
    };
    let d = dist("link `l2` (URDF cylinder)");
    assert!((d - 0.62).abs() < 1e-6, "{d}");
    let d = dist("link `l2` (URDF box)");
    assert!((d - 0.10).abs() < 1e-6, "{d}");
    assert!((dist("link `l2` (URDF mesh hull)") - 0.65).abs() < 1e-6);

    // A bed in front of the base with its top at z = 0.15: the box hanging under link 2 reaches
    // into it, while the capsule that would stand in for link 2 (radius 0.045 of a 1 m reach,
    // at z = 0.7) stays clear: the URDF geometry decides.
    let bed = Bed::new(&V3::new(0.2, -1.0, -0.5), &V3::new(1.5, 1.0, 0.15));
    let q = [0.0, 0.0];
    let poses = rs.poses(&model, &q, &Isometry::identity());
    let beads = Beads::new(&[], &[], 1, 0.02);
    let mut clear = None;
    let hit = collision::check(&rs, &poses, &bed, &beads, 0, &mut clear);
    assert_eq!(
        hit.as_ref().map(|h| h.0),
        Some(Reason::CollisionBed),
        "{hit:?}"
    );
    assert!(hit.unwrap().1.contains("URDF"));
    let bare = load(&arm_urdf(&tmpdir("bare"), "")).unwrap();
    let rs_bare = RobotShapes::new(&bare, 1.0, &LinkRadii::default());
    let poses = rs_bare.poses(&bare, &q, &Isometry::identity());
    assert_eq!(
        collision::check(&rs_bare, &poses, &bed, &beads, 0, &mut None),
        None
    );
}

#[test]
fn printed_beads_block_links_only_once_laid() {
    // A straight bead along x at z = 0.1 (tip), printed over samples 0..=10.
    let p: Vec<V3> = (0..=10)
        .map(|i| V3::new(0.1 * i as f64, 0.0, 0.1))
        .collect();
    let print = vec![true; p.len()];
    let beads = Beads::new(&p, &print, 2, 0.02);
    assert_eq!(beads.len(), 5);
    assert_eq!(beads.laid_at(0), 0);
    assert_eq!(beads.laid_at(4), 2);
    assert_eq!(beads.laid_at(10), 5);
    // A ball of radius 0.05 centred 0.06 m above the bead's centre line (z = 0.08) near its end:
    // 0.06 − 0.05 = 0.01 m < bead radius 0.02 → a hit once that bead is laid, not before.
    let ball = SharedShape::ball(0.05);
    let pose = Isometry::translation(0.95, 0.0, 0.08 + 0.06);
    assert_eq!(beads.hit(&pose, &ball, beads.laid_at(8)), None);
    assert_eq!(beads.hit(&pose, &ball, beads.laid_at(10)), Some(4));
    // 0.08 above: clear.
    let far = Isometry::translation(0.95, 0.0, 0.08 + 0.08);
    assert_eq!(beads.hit(&far, &ball, 5), None);
}

#[test]
fn print_head_and_hose_come_from_the_drive_file() {
    let dir = tmpdir("tool");
    arm_urdf(&dir, "");
    std::fs::write(
        dir.join("drive.toml"),
        r#"[robot]
name = "test arm"
urdf = "arm.urdf"
[tool]
xyz_m = [0.0, 0.0, 0.3]
[tool.geometry]
head_radius_m = 0.12
hose_radius_m = 0.03
hose_from_m = [0.0, 0.0, 0.0]
hose_to_m = [-0.4, 0.0, -0.2]
"#,
    )
    .unwrap();
    let model = load(&dir).expect("load");
    let rs = RobotShapes::new(&model, 1.0, &LinkRadii::default());
    let head = rs.shapes.iter().find(|s| s.role == Role::Head).unwrap();
    let hose = rs.shapes.iter().find(|s| s.role == Role::Hose).unwrap();
    assert_eq!((head.body, hose.body), (3, 3));
    // At q = 0 the flange sits at (0.6, 0, 0.7) with its z along the base z: the head cylinder
    // spans z 0.7..1.0 with radius 0.12; a ball 0.5 m to its side is 0.5 − 0.12 − r away.
    let poses = rs.poses(&model, &[0.0, 0.0], &Isometry::identity());
    let i = rs.shapes.iter().position(|s| s.role == Role::Head).unwrap();
    let d = query::distance(
        &poses[i],
        rs.shapes[i].shape.as_ref(),
        &Isometry::translation(0.6 + 0.5, 0.0, 0.85),
        &Ball::new(0.1),
    )
    .unwrap();
    assert!((d - (0.5 - 0.12 - 0.1)).abs() < 1e-9, "{d}");
    // A negative radius is a clear error.
    let bad = std::fs::read_to_string(dir.join("drive.toml"))
        .unwrap()
        .replace("head_radius_m = 0.12", "head_radius_m = -1");
    std::fs::write(dir.join("drive.toml"), bad).unwrap();
    let e = load(&dir).unwrap_err().to_string();
    assert!(e.contains("tool.geometry"), "{e}");
}

#[test]
fn package_urls_and_obj_meshes_resolve_and_a_missing_package_is_a_warning() {
    // <root>/my_robot_description/meshes/l2.obj referenced as package://my_robot_description/...
    // from a URDF in <root>/my_robot_description/urdf/: found among the URDF's ancestors.
    let root = tmpdir("pkg");
    let pkg = root.join("my_robot_description");
    std::fs::create_dir_all(pkg.join("meshes")).unwrap();
    std::fs::create_dir_all(pkg.join("urdf")).unwrap();
    let mut obj = String::from("# unit cube shifted down 0.5 m\n");
    for i in 0..8 {
        obj += &format!(
            "v {} {} {}\n",
            (i & 1) as f64 * 0.1,
            ((i >> 1) & 1) as f64 * 0.1 - 0.05,
            ((i >> 2) & 1) as f64 * 0.1 - 0.55
        );
    }
    obj += "f 1 2 3\n";
    std::fs::write(pkg.join("meshes/l2.obj"), obj).unwrap();
    let xml = r#"<collision><geometry><mesh filename="package://my_robot_description/meshes/l2.obj" scale="1 1 1"/></geometry></collision>
      <collision><geometry><mesh filename="package://no_such_package/meshes/x.stl"/></geometry></collision>"#;
    let model = load(&arm_urdf(&pkg.join("urdf"), xml)).expect("load");
    assert_eq!(model.link_collision[1].len(), 1, "{:?}", model.warnings);
    assert!(
        model
            .warnings
            .iter()
            .any(|w| w.contains("no_such_package") && w.contains("ROS_PACKAGE_PATH")),
        "{:?}",
        model.warnings
    );
    // The hull's lowest point is 0.7 − 0.55 = 0.15 m above the base plane at q = 0.
    let rs = RobotShapes::new(&model, 1.0, &LinkRadii::default());
    let i = rs
        .shapes
        .iter()
        .position(|s| s.label == "link `l2` (URDF mesh hull)")
        .unwrap();
    let poses = rs.poses(&model, &[0.0, 0.0], &Isometry::identity());
    let bed = Bed::new(&V3::new(-3.0, -3.0, -0.5), &V3::new(3.0, 3.0, 0.0));
    let d = query::distance(
        &poses[i],
        rs.shapes[i].shape.as_ref(),
        &bed.pose,
        &bed.cuboid,
    )
    .unwrap();
    assert!((d - 0.15).abs() < 1e-6, "{d}");
}

#[test]
fn a_degenerate_collision_mesh_is_a_warning_and_a_capsule_stands_in() {
    // Four vertices on one line: no solid, no face.
    let dir = tmpdir("flat");
    std::fs::write(
        dir.join("flat.obj"),
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3\n",
    )
    .unwrap();
    let xml = r#"<collision><geometry><mesh filename="flat.obj"/></geometry></collision>"#;
    let model = load(&arm_urdf(&dir, xml)).expect("load");
    assert!(
        model
            .warnings
            .iter()
            .any(|w| w.contains("flat.obj") && w.contains("no convex hull")),
        "{:?}",
        model.warnings
    );
    let rs = RobotShapes::new(&model, 1.0, &LinkRadii::default());
    assert!(rs
        .shapes
        .iter()
        .any(|s| s.body == 2 && s.label == "capsule of link `l2`"));
}
