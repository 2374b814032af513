//! Collision geometry (parry3d-f64): distances against closed-form ones, a user's URDF
//! `<collision>` elements used (boxes, cylinders, meshes), the print head and hose, the bed,
//! and the growing part.

mod common;

use parry3d_f64::math::{Isometry, Point, Vector};
use parry3d_f64::query;
use parry3d_f64::shape::{Ball, Capsule, Cuboid, Cylinder, SharedShape};
use printwatt::evaluate::feasibility::collision::{self, Beads, Bed, RobotShapes, Role};
use printwatt::evaluate::feasibility::{LinkRadii, Reason};
use printwatt::math::{Frame, V3};
use printwatt::robot::load;
use std::path::Path;
use std::sync::Mutex;

/// Held by every test here that sets the process-wide SIMD level: without it, one test's
/// `set_level(Scalar)` lands in the middle of another's lockstep run (the libtest threads share
/// the level), and that run's count of lockstep answers depends on the interleaving.
static LEVEL_LOCK: Mutex<()> = Mutex::new(());

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

/// A round wall of bead centres about the part frame's z axis: `layers` layers 20 mm apart
/// (the first at z = 0.02 m), 100 points a layer on a circle of `radius_m` (m).
fn round_wall(radius_m: f64, layers: usize) -> Vec<V3> {
    let mut p = Vec::with_capacity(100 * layers);
    for layer in 0..layers {
        for k in 0..100 {
            let a = std::f64::consts::TAU * k as f64 / 100.0;
            p.push(V3::new(
                radius_m * a.cos(),
                radius_m * a.sin(),
                0.02 * (layer + 1) as f64,
            ));
        }
    }
    p
}

/// Joint angles (rad) at fractions `u` ∈ [0, 1] of each joint's range, clipped to ±3.2 rad.
fn q_in_limits(model: &printwatt::robot::RobotModel, u: &[f64]) -> Vec<f64> {
    model
        .joints
        .iter()
        .zip(u)
        .map(|(j, u)| {
            let (lo, hi) = (j.lower.max(-3.2), j.upper.min(3.2));
            lo + u * (hi - lo)
        })
        .collect()
}

/// The robot's collision shapes at the feasibility checks' reach and the default link radii.
fn shapes(model: &printwatt::robot::RobotModel) -> RobotShapes {
    RobotShapes::new(
        model,
        printwatt::evaluate::feasibility::reach_m(model),
        &LinkRadii::default(),
    )
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

/// A four-joint arm written by the test whose links carry URDF boxes, cylinders, spheres and a
/// mesh hull (shapes other than the capsules of the shipped robots), with self pairs between
/// them: base column 0.4 m, joints about z, y, y and a tilted axis, 0.5 m links.
fn mixed_arm(dir: &Path) -> std::path::PathBuf {
    std::fs::write(
        dir.join("l4.stl"),
        stl_box([0.0, -0.06, -0.06], [0.3, 0.06, 0.06]),
    )
    .unwrap();
    let urdf = r#"<robot name="mixed_arm">
  <link name="base"><inertial><mass value="10"/><inertia ixx="1" iyy="1" izz="1"/></inertial>
    <collision><origin xyz="0 0 0.2"/><geometry><box size="0.4 0.4 0.4"/></geometry></collision></link>
  <link name="l1"><inertial><mass value="5"/><inertia ixx="1" iyy="1" izz="1"/></inertial>
    <collision><origin xyz="0 0 0.1"/><geometry><cylinder radius="0.15" length="0.2"/></geometry></collision></link>
  <link name="l2"><inertial><mass value="5"/><inertia ixx="1" iyy="1" izz="1"/></inertial>
    <collision><origin xyz="0.25 0 0" rpy="0 1.5707963267948966 0"/><geometry><cylinder radius="0.08" length="0.5"/></geometry></collision>
    <collision><origin xyz="0.5 0 0"/><geometry><sphere radius="0.12"/></geometry></collision></link>
  <link name="l3"><inertial><mass value="5"/><inertia ixx="1" iyy="1" izz="1"/></inertial>
    <collision><origin xyz="0.25 0 0" rpy="0.3 0 0"/><geometry><box size="0.5 0.1 0.14"/></geometry></collision></link>
  <link name="l4"><inertial><mass value="2"/><inertia ixx="1" iyy="1" izz="1"/></inertial>
    <collision><geometry><mesh filename="l4.stl"/></geometry></collision></link>
  <link name="tool0"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.4"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="2" effort="100"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" velocity="2" effort="100"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/>
    <origin xyz="0.5 0 0"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" velocity="2" effort="100"/></joint>
  <joint name="j4" type="revolute"><parent link="l3"/><child link="l4"/>
    <origin xyz="0.5 0 0"/><axis xyz="0.6 0.8 0"/><limit lower="-3" upper="3" velocity="2" effort="100"/></joint>
  <joint name="flange" type="fixed"><parent link="l4"/><child link="tool0"/><origin xyz="0.3 0 0"/></joint>
</robot>"#;
    let p = dir.join("mixed.urdf");
    std::fs::write(&p, urdf).unwrap();
    p
}

/// The shapes' poses equal to the plain forward kinematics' (every number equal; a zero may
/// differ in sign).
fn same_poses(fast: &[Isometry<f64>], plain: &[Isometry<f64>], q: &[f64]) {
    assert_eq!(fast.len(), plain.len());
    for (a, b) in fast.iter().zip(plain) {
        assert!(
            a.translation.vector == b.translation.vector && a.rotation.coords == b.rotation.coords,
            "q {q:?}: {a:?} vs {b:?}"
        );
    }
}

/// `check` and `check_unfiltered` at `q`: the same verdict, reason and message, and the same
/// running bed clearance to the bit (both continue from `clear`, which takes the new value);
/// the poses they are given equal to the plain forward kinematics' ([`same_poses`]).
#[allow(clippy::too_many_arguments)]
fn same_check(
    model: &printwatt::robot::RobotModel,
    rs: &RobotShapes,
    world: &Isometry<f64>,
    q: &[f64],
    bed: &Bed,
    beads: &Beads,
    laid: usize,
    clear: &mut Option<f64>,
) -> Option<(Reason, String)> {
    let poses = rs.poses(model, q, world);
    same_poses(&poses, &rs.poses_by_fk(model, q, world), q);
    let mut c_fast = *clear;
    let mut c_plain = *clear;
    let fast = collision::check(rs, &poses, bed, beads, laid, &mut c_fast);
    let plain = collision::check_unfiltered(rs, &poses, bed, beads, laid, &mut c_plain);
    assert_eq!(fast, plain, "q {q:?} laid {laid}");
    assert_eq!(
        c_fast.map(f64::to_bits),
        c_plain.map(f64::to_bits),
        "bed clearance at q {q:?}: {c_fast:?} vs {c_plain:?}"
    );
    *clear = c_fast;
    fast
}

#[test]
fn the_prefiltered_collision_check_and_the_shortcut_poses_equal_the_plain_ones_on_random_and_near_contact_configurations(
) {
    use rand::{Rng, SeedableRng};
    let robots = all_robots("mixed");
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(8);
    // A round wall of beads about every robot (part frame = base frame, radius 0.8 m, 0.8 m
    // tall), and a bed under it.
    let p = round_wall(0.8, 40);
    let print = vec![true; p.len()];
    let beads = Beads::new(&p, &print, 5, collision::BEAD_RADIUS_M);
    let (mut outcomes, mut near) = ([0usize; 4], 0usize);
    let tally = |o: &Option<(Reason, String)>, t: &mut [usize; 4]| {
        t[match o.as_ref().map(|h| h.0) {
            None => 0,
            Some(Reason::CollisionBed) => 1,
            Some(Reason::CollisionPart) => 2,
            _ => 3,
        }] += 1;
    };
    for model in &robots {
        let rs = shapes(model);
        let n = model.dof();
        for round in 0..400 {
            // The bed's top anywhere from well below the base to above it.
            let top = rng.gen_range(-0.6..0.3);
            let bed = Bed::new(&V3::new(0.2, -1.5, top - 0.5), &V3::new(2.0, 1.5, top));
            let world = Isometry::translation(0.0, 0.0, rng.gen_range(-0.2..0.2));
            let laid = rng.gen_range(0..=beads.len());
            let mut clear = (round % 2 == 0).then(|| rng.gen_range(0.0..0.5));
            let u: Vec<f64> = (0..n).map(|_| rng.gen::<f64>()).collect();
            let o = same_check(
                model,
                &rs,
                &world,
                &q_in_limits(model, &u),
                &bed,
                &beads,
                laid,
                &mut clear,
            );
            tally(&o, &mut outcomes);
            // Near contact: bisect towards another configuration with the other outcome, and
            // check both sides of the boundary 1e-12 apart in the parameter.
            let v: Vec<f64> = (0..n).map(|_| rng.gen::<f64>()).collect();
            let mid =
                |t: f64| -> Vec<f64> { u.iter().zip(&v).map(|(a, b)| a + t * (b - a)).collect() };
            let other = same_check(
                model,
                &rs,
                &world,
                &q_in_limits(model, &v),
                &bed,
                &beads,
                laid,
                &mut clear.clone(),
            );
            if o.as_ref().map(|h| h.0) == other.as_ref().map(|h| h.0) {
                continue;
            }
            let (mut a, mut b) = (0.0f64, 1.0f64);
            let verdict = |t: f64| {
                let mut c = None;
                same_check(
                    model,
                    &rs,
                    &world,
                    &q_in_limits(model, &mid(t)),
                    &bed,
                    &beads,
                    laid,
                    &mut c,
                )
                .map(|h| h.0)
            };
            let va = verdict(a);
            while b - a > 1e-12 {
                let m = 0.5 * (a + b);
                if verdict(m) == va {
                    a = m
                } else {
                    b = m
                }
            }
            for t in [a, b, a - 1e-9, b + 1e-9] {
                let mut c = clear;
                same_check(
                    model,
                    &rs,
                    &world,
                    &q_in_limits(model, &mid(t.clamp(0.0, 1.0))),
                    &bed,
                    &beads,
                    laid,
                    &mut c,
                );
            }
            near += 1;
        }
    }
    // Every outcome is exercised, and many boundaries between them.
    assert!(outcomes.iter().all(|&c| c > 50), "{outcomes:?}");
    assert!(near > 300, "{near} boundaries");
    eprintln!(
        "largest bed clearance difference: {:e} m",
        f64::from_bits(WORST_CLEARANCE.load(std::sync::atomic::Ordering::Relaxed))
    );
}

#[test]
fn the_prefiltered_collision_check_and_the_shortcut_poses_equal_the_plain_ones_along_real_paths() {
    use printwatt::evaluate::feasibility::{reach_m, FeasibilityOptions, World};
    use printwatt::timing::{JointStageOptions, ProfileOptions};
    use printwatt::toolpath::{self, Placement, ReadOptions};
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let model = load(&root.join("robots/abb_irb6700_200_260")).unwrap();
    let tp = toolpath::load(&root.join("paths/default.gcode"), &ReadOptions::default()).unwrap();
    let job = printwatt::evaluate::PathJob::new(
        &model,
        &tp,
        printwatt::energy::EnergyOptions::default(),
        ProfileOptions::default(),
        JointStageOptions::default(),
    )
    .unwrap();
    let o = FeasibilityOptions::default();
    let rs = RobotShapes::new(&model, reach_m(&model), &o.radii);
    let (mut samples, mut outcomes) = (0, [0usize; 4]);
    for (x, y, z, yaw_deg) in [
        (1.534, -0.121, 0.0, 90.0),
        (1.7, 0.0, 0.0, 90.0),
        (1.3, 0.3, -0.3, 0.0),
    ] {
        let at = Placement::new(x, y, z, f64::to_radians(yaw_deg));
        let Ok(Ok(full)) = job.evaluate(&at) else {
            continue;
        };
        let tr = &full.timed.traj;
        let motion = &*full.timed.motion;
        let (mut lo, mut hi) = (V3::repeat(f64::INFINITY), V3::repeat(f64::NEG_INFINITY));
        for p in &motion.p {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        let world = World::new(&at.frame(), (lo, hi), &o);
        // The bed raised towards the arm (the clearance at the first placement is 0.03 m:
        // just below, at and just above it), and fatter beads raised into the hose and wrist.
        for (dz, every) in [
            (0.0, 1),
            (0.029_999_999, 3),
            (0.03, 3),
            (0.030_000_001, 3),
            (0.06, 7),
            (0.3, 7),
        ] {
            let bed = Bed::new(&world.bed_lo, &(world.bed_hi + V3::new(0.0, 0.0, dz)));
            for (radius, up) in [(collision::BEAD_RADIUS_M, 0.0), (0.06, 0.1), (0.06, 0.25)] {
                let raised: Vec<V3> = motion.p.iter().map(|p| p + V3::new(0.0, 0.0, up)).collect();
                let beads = Beads::new(&raised, &motion.print, o.check_every, radius);
                let mut clear = None;
                for k in (0..tr.len()).step_by(every) {
                    samples += 1;
                    let r = same_check(
                        &model,
                        &rs,
                        &world.base_iso,
                        tr.q(k),
                        &bed,
                        &beads,
                        beads.laid_at(k),
                        &mut clear,
                    );
                    outcomes[match r.map(|h| h.0) {
                        None => 0,
                        Some(Reason::CollisionBed) => 1,
                        Some(Reason::CollisionPart) => 2,
                        _ => 3,
                    }] += 1;
                }
            }
        }
    }
    // Clear samples, the bed and the part met.
    assert!(
        samples > 60_000 && outcomes[0] > 1000 && outcomes[1] > 1000 && outcomes[2] > 1000,
        "{samples} samples, {outcomes:?}"
    );
}

/// Largest entry of `|a − b|` over the translations (m) and over the rotation matrices.
fn pose_gap(a: &Isometry<f64>, b: &Isometry<f64>) -> (f64, f64) {
    let dt = (a.translation.vector - b.translation.vector).abs().max();
    let (ra, rb) = (
        a.rotation.to_rotation_matrix(),
        b.rotation.to_rotation_matrix(),
    );
    let dr = (ra.matrix() - rb.matrix()).abs().max();
    (dt, dr)
}

/// The shipped robots and the test's URDF arm with boxes, cylinders, spheres, a hull and a
/// tilted axis ([`mixed_arm`]).
fn all_robots(tag: &str) -> Vec<printwatt::robot::RobotModel> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tmpdir(tag);
    let mut robots: Vec<printwatt::robot::RobotModel> = [
        "abb_irb6700_200_260",
        "abb_irb4600_40_255",
        "ur10e",
        "staubli_tx200",
        "puma560",
    ]
    .iter()
    .map(|r| load(&root.join("robots").join(r)).unwrap())
    .collect();
    robots.push(load(&mixed_arm(&dir)).unwrap());
    robots
}

/// The joints' sines then cosines of `q`, as the IK's FK re-check leaves them.
fn shared_sines(q: &[f64]) -> Vec<f64> {
    let (s, c): (Vec<f64>, Vec<f64>) = q.iter().map(|&x| printwatt::fastmath::sin_cos(x)).unzip();
    [s, c].concat()
}

#[test]
fn poses_from_the_shared_sines_agree_with_poses_by_fk_within_the_stated_bound() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
    let (mut worst_t, mut worst_r) = (0.0f64, 0.0f64);
    for model in &all_robots("bound") {
        let rs = shapes(model);
        for _ in 0..2000 {
            let q: Vec<f64> = model
                .joints
                .iter()
                .map(|j| rng.gen_range(j.lower.max(-6.0)..j.upper.min(6.0)))
                .collect();
            // The robot base anywhere within 3 m of the part frame's origin, turned any way.
            let world = Frame::from_xyz_rpy(
                [
                    rng.gen_range(-3.0..3.0),
                    rng.gen_range(-3.0..3.0),
                    rng.gen_range(-1.0..1.0),
                ],
                [
                    rng.gen_range(-3.2..3.2),
                    rng.gen_range(-1.5..1.5),
                    rng.gen_range(-3.2..3.2),
                ],
            );
            let sc = shared_sines(&q);
            let shared = rs.body_frames(&q, Some(&sc), &world);
            // Without the shared sines the same numbers (they are computed the same way).
            let own = rs.body_frames(&q, None, &world);
            for b in 0..model.dof() + 2 {
                assert_eq!(shared.body(b), own.body(b), "{q:?} body {b}");
            }
            let plain = rs.poses_by_fk(model, &q, &collision::iso(&world));
            for (a, b) in rs.poses_of(&shared).iter().zip(&plain) {
                let (dt, dr) = pose_gap(a, b);
                worst_t = worst_t.max(dt);
                worst_r = worst_r.max(dr);
                assert!(
                    dt <= collision::POSE_BOUND && dr <= collision::POSE_BOUND,
                    "q {q:?}: {dt:e} m, {dr:e} (bound {:e})",
                    collision::POSE_BOUND
                );
            }
        }
    }
    eprintln!("largest pose difference: {worst_t:e} m, rotation entries {worst_r:e}");
}

/// A check's answer: why a sample fails, and the message.
type Verdict = Option<(Reason, String)>;

/// The largest difference of bed clearances [`both_checks`] saw (bits of a positive f64, m).
static WORST_CLEARANCE: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// The check from the bodies' frames (shared sines) and the plain one (libm's sines,
/// `poses_by_fk`, `check_unfiltered`) at `q`: their verdicts and messages, and both running bed
/// clearances (both continue from `clear`; the first's is kept).
#[allow(clippy::too_many_arguments)]
fn both_checks(
    model: &printwatt::robot::RobotModel,
    rs: &RobotShapes,
    world: &Frame,
    q: &[f64],
    bed: &Bed,
    beads: &Beads,
    laid: usize,
    clear: &mut Option<f64>,
) -> (Verdict, Verdict) {
    let bodies = rs.body_frames(q, Some(&shared_sines(q)), world);
    let (mut c_new, mut c_plain) = (*clear, *clear);
    let mut isos = Vec::new();
    let new = collision::check_bodies(rs, &bodies, bed, beads, laid, &mut c_new, &mut isos);
    let plain = rs.poses_by_fk(model, q, &collision::iso(world));
    let old = collision::check_unfiltered(rs, &plain, bed, beads, laid, &mut c_plain);
    // The clearances within the bound whenever both checks reached the same shapes and every
    // shape's clearance is the closed form (a capsule above the bed); where parry's GJK gives
    // it, its own error dominates (see collision::CLEARANCE_BOUND).
    let closed = rs
        .shapes
        .iter()
        .zip(&plain)
        .all(|(s, p)| s.role == Role::Head || bed.capsule_above(p, &s.shape).is_some());
    if closed && new.as_ref().map(|h| h.0) == old.as_ref().map(|h| h.0) {
        match (c_new, c_plain) {
            (Some(a), Some(b)) => {
                let d = (a - b).abs();
                WORST_CLEARANCE.fetch_max(d.to_bits(), std::sync::atomic::Ordering::Relaxed);
                assert!(
                    d <= collision::CLEARANCE_BOUND,
                    "{} q {q:?}: clearance {a} vs {b}",
                    model.name(),
                )
            }
            (a, b) => assert_eq!(a, b, "q {q:?}"),
        }
    }
    *clear = c_new;
    (new, old)
}

#[test]
fn the_collision_check_from_shared_sines_gives_the_plain_checks_verdicts_messages_and_clearance_off_the_boundaries(
) {
    use rand::{Rng, SeedableRng};
    let robots = all_robots("verdicts");
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(10);
    let p = round_wall(0.8, 40);
    let beads = Beads::new(&p, &vec![true; p.len()], 5, collision::BEAD_RADIUS_M);
    let (mut outcomes, mut near) = ([0usize; 4], 0usize);
    for model in &robots {
        let rs = shapes(model);
        let n = model.dof();
        for round in 0..400 {
            let top = rng.gen_range(-0.6..0.3);
            let bed = Bed::new(&V3::new(0.2, -1.5, top - 0.5), &V3::new(2.0, 1.5, top));
            let world = Frame::from_xyz_rpy(
                [0.0, 0.0, rng.gen_range(-0.2..0.2)],
                [0.0, 0.0, rng.gen_range(-0.3..0.3)],
            );
            let laid = rng.gen_range(0..=beads.len());
            let mut clear = (round % 2 == 0).then(|| rng.gen_range(0.0..0.5));
            let u: Vec<f64> = (0..n).map(|_| rng.gen::<f64>()).collect();
            let (o, old) = both_checks(
                model,
                &rs,
                &world,
                &q_in_limits(model, &u),
                &bed,
                &beads,
                laid,
                &mut clear,
            );
            // A random configuration is not within 1e-13 m of a boundary: the same answer.
            assert_eq!(o, old, "{} at {:?}", model.name(), q_in_limits(model, &u));
            outcomes[match o.as_ref().map(|h| h.0) {
                None => 0,
                Some(Reason::CollisionBed) => 1,
                Some(Reason::CollisionPart) => 2,
                _ => 3,
            }] += 1;
            // Near contact: bisect towards a configuration with another outcome; 1e-4 of the
            // way on either side of the boundary the answers agree. (Closer they may not: a
            // link that grazes the bed tangentially is within t² of it, and parry's GJK
            // decides a touch within its own tolerance, where the last bits of a pose can flip
            // its answer.)
            let v: Vec<f64> = (0..n).map(|_| rng.gen::<f64>()).collect();
            let mid =
                |t: f64| -> Vec<f64> { u.iter().zip(&v).map(|(a, b)| a + t * (b - a)).collect() };
            let verdict = |t: f64| {
                let mut c = None;
                both_checks(
                    model,
                    &rs,
                    &world,
                    &q_in_limits(model, &mid(t)),
                    &bed,
                    &beads,
                    laid,
                    &mut c,
                )
                .0
                .map(|h| h.0)
            };
            let va = verdict(0.0);
            if va == verdict(1.0) {
                continue;
            }
            let (mut a, mut b) = (0.0f64, 1.0f64);
            while b - a > 1e-12 {
                let m = 0.5 * (a + b);
                if verdict(m) == va {
                    a = m
                } else {
                    b = m
                }
            }
            for t in [a - 1e-4, b + 1e-4] {
                let mut c = clear;
                let q = q_in_limits(model, &mid(t.clamp(0.0, 1.0)));
                let (o, old) = both_checks(model, &rs, &world, &q, &bed, &beads, laid, &mut c);
                assert_eq!(o, old, "{} at {q:?}", model.name());
            }
            near += 1;
        }
    }
    assert!(outcomes.iter().all(|&c| c > 50), "{outcomes:?}");
    assert!(near > 300, "{near} boundaries");
    eprintln!(
        "largest bed clearance difference: {:e} m",
        f64::from_bits(WORST_CLEARANCE.load(std::sync::atomic::Ordering::Relaxed))
    );
}

#[test]
fn the_first_infeasible_sample_and_its_reason_are_those_of_the_plain_checks_on_colliding_placements(
) {
    use printwatt::evaluate::feasibility::margins::check_joint_sample;
    use printwatt::evaluate::feasibility::{
        check_sample_by_fk, FeasibilityOptions, Margins, Scene, World,
    };
    use printwatt::evaluate::{Evaluator, Objective};
    let model = common::robot("abb_irb6700_200_260");
    let tp = common::path("default.gcode");
    let job = common::default_job(&model, &tp);
    // Fatter links than the default ones, so that the grid meets the bed, the part and itself.
    let mut o = FeasibilityOptions::default();
    o.radii.arm *= 2.0;
    o.radii.wrist *= 3.0;
    let ev = Evaluator::new(&job, o, Objective::Supply);
    let mut sc = ev.scratch().unwrap();
    let rs = RobotShapes::new(
        &model,
        printwatt::evaluate::feasibility::reach_m(&model),
        &o.radii,
    );
    let (mut lo, mut hi) = (V3::repeat(f64::INFINITY), V3::repeat(f64::NEG_INFINITY));
    for p in &job.plan.motion.p {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    let mut seen = std::collections::BTreeMap::new();
    let grid = printwatt::search::optimise::default_grid(
        printwatt::evaluate::feasibility::reach_m(&model),
    )
    .placements();
    for at in grid.iter().step_by(7) {
        let at = *at;
        let got = ev.evaluate(&mut sc, &at).outcome;
        let Ok(timed) = ev.timed(&mut sc, &at) else {
            continue;
        };
        // The plain checks, sample by sample, as the evaluation runs them.
        let world = World::new(&at.frame(), (lo, hi), &o);
        let motion = &*timed.motion;
        let beads = Beads::new(
            &motion.p,
            &motion.print,
            o.check_every,
            collision::BEAD_RADIUS_M,
        );
        let tr = &timed.traj;
        let m = tr.len();
        let mut margins = Margins::default();
        let mut want = None;
        for k in 0..m {
            let jc = check_joint_sample(&model, &o, tr.q(k), tr.qd(k), tr.qdd(k), &mut margins);
            if k % o.check_every == 0 || k + 1 == m || jc.is_some() {
                let scene = Scene {
                    world: &world,
                    shapes: &rs,
                    beads: &beads,
                };
                if let Some(f) = jc.or_else(|| {
                    check_sample_by_fk(&model, &o, scene, tr.q(k), beads.laid_at(k), &mut margins)
                }) {
                    want = Some((k, f));
                    break;
                }
            }
        }
        match (&got, want) {
            (Err(inf), Some((k, (reason, detail)))) => {
                assert_eq!(
                    (inf.sample, inf.reason, &inf.detail),
                    (Some(k), reason, &detail),
                    "at {at:?}"
                );
                *seen.entry(reason.name()).or_insert(0) += 1;
            }
            (Ok(f), None) => {
                let g = &f.margins;
                assert_eq!(
                    (
                        g.wrist,
                        g.elbow,
                        g.shoulder_m,
                        g.joint_limit_rad,
                        g.wrist_rate
                    ),
                    (
                        margins.wrist,
                        margins.elbow,
                        margins.shoulder_m,
                        margins.joint_limit_rad,
                        margins.wrist_rate
                    ),
                    "at {at:?}"
                );
                let (a, b) = (g.bed_clearance_m.unwrap(), margins.bed_clearance_m.unwrap());
                assert!(
                    (a - b).abs() <= collision::CLEARANCE_BOUND,
                    "at {at:?}: {a} vs {b}"
                );
                *seen.entry("feasible").or_insert(0) += 1;
            }
            (got, want) => panic!("at {at:?}: {got:?} vs the plain checks' {want:?}"),
        }
    }
    eprintln!("{seen:?}");
    assert!(seen.get("feasible").is_some_and(|&c| c > 0), "{seen:?}");
    assert!(
        seen.keys()
            .any(|r| r.starts_with("collision") || *r == "self_collision"),
        "{seen:?}"
    );
}

#[test]
fn the_checked_samples_in_lockstep_give_check_sample_with_answers_messages_and_margins_sample_by_sample(
) {
    use printwatt::evaluate::feasibility::{
        check_sample_with, CheckedLanes, FeasibilityOptions, Margins, Scene, World,
    };
    use printwatt::simd::{self, Level};
    use rand::{Rng, SeedableRng};
    let _g = LEVEL_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let robots = all_robots("lockstep");
    // A round wall, 40 layers, printed from the first sample on.
    let wall = round_wall(0.4, 40);
    let (mut outcomes, mut lockstep_robots) = (std::collections::BTreeMap::new(), 0);
    let (mut answered, mut lowering) = (0, 0);
    // The SIMD levels this CPU runs (two lanes, four, eight): each answers its own count.
    let mut levels = Vec::new();
    for level in [Level::Sse2, Level::Avx2, Level::Avx512] {
        if !simd::set_level(level) {
            continue;
        }
        let answered_before = answered;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(12);
        for model in &robots {
            let n = model.dof();
            let o = FeasibilityOptions {
                check_every: rng.gen_range(1..=12),
                ..Default::default()
            };
            let rs = RobotShapes::new(
                model,
                printwatt::evaluate::feasibility::reach_m(model),
                &o.radii,
            );
            let Some(mut lanes) = CheckedLanes::new(model, &o, &rs) else {
                // The scalar level or an arm the lockstep path does not take.
                continue;
            };
            lockstep_robots += usize::from(rs.lockstep());
            for round in 0..12 {
                // The robot base beside the wall, a little above or below the bed's top; every
                // third round on a bed that reaches under the base, above its top (the links
                // wholly above the bed: the bed clearance in closed form, lowered as the arm
                // comes down).
                let wide = round % 3 == 2;
                let base_to_part = Frame::from_xyz_rpy(
                    [
                        rng.gen_range(0.6..1.4),
                        rng.gen_range(-0.4..0.4),
                        if wide {
                            rng.gen_range(0.25..0.5)
                        } else {
                            rng.gen_range(-0.3..0.3)
                        },
                    ],
                    [0.0, 0.0, rng.gen_range(2.5..3.8)],
                );
                let m = 3000;
                let p = &wall[..m.min(wall.len())];
                let half = if wide { 1.6 } else { 0.5 };
                let world = World::new(
                    &base_to_part.inverse(),
                    (V3::new(-half, -half, 0.0), V3::new(half, half, 0.8)),
                    &o,
                );
                let beads = Beads::new(p, &vec![true; p.len()], o.check_every, 0.02);
                let scene = Scene {
                    world: &world,
                    shapes: &rs,
                    beads: &beads,
                };
                // A random walk through the joint space with jumps now and then: the bed, the
                // part, the arm itself, the singularities, parry's GJK, angles beyond the fast
                // sines' domain and NaNs.
                let mut q: Vec<f64> = model
                    .joints
                    .iter()
                    .map(|j| rng.gen_range(j.lower.max(-3.0)..j.upper.min(3.0)))
                    .collect();
                let (mut qs, mut sincos) = (Vec::new(), Vec::new());
                for _ in 0..m {
                    match rng.gen_range(0..400) {
                        0..=3 => {
                            for (v, j) in q.iter_mut().zip(&model.joints) {
                                *v = rng.gen_range(j.lower.max(-3.0)..j.upper.min(3.0));
                            }
                        }
                        4 if round % 3 == 0 => q[rng.gen_range(0..n)] = f64::NAN,
                        5 if round % 4 == 1 => q[rng.gen_range(0..n)] = 70.0,
                        _ => {
                            for (v, j) in q.iter_mut().zip(&model.joints) {
                                if v.is_nan() || v.abs() > 10.0 {
                                    *v = 0.5 * (j.lower.max(-3.0) + j.upper.min(3.0));
                                }
                                *v = (*v + rng.gen_range(-0.03..0.03))
                                    .clamp(j.lower.max(-3.0), j.upper.min(3.0));
                            }
                        }
                    }
                    qs.extend_from_slice(&q);
                    sincos.extend(shared_sines(&q));
                }
                let every = o.check_every;
                let mut want_margins = Margins::default();
                let mut got_margins = Margins::default();
                let mut poses = Vec::new();
                for k in (0..m).filter(|k| k % every == 0 || k + 1 == m) {
                    let (qk, sk) = (&qs[k * n..(k + 1) * n], &sincos[k * 2 * n..(k + 1) * 2 * n]);
                    let want = check_sample_with(
                        model,
                        &o,
                        scene,
                        qk,
                        Some(sk),
                        beads.laid_at(k),
                        &mut poses,
                        &mut want_margins,
                    );
                    let got = lanes.check(
                        model,
                        &o,
                        scene,
                        k,
                        every,
                        &qs,
                        &sincos,
                        &mut poses,
                        &mut got_margins,
                    );
                    assert_eq!(got, want, "{} {level:?} sample {k}", model.name());
                    assert_eq!(
                        format!("{got_margins:?}"),
                        format!("{want_margins:?}"),
                        "{} {level:?} sample {k}",
                        model.name()
                    );
                    let name = want.as_ref().map_or("none", |f| f.0.name());
                    *outcomes.entry(name).or_insert(0usize) += 1;
                }
            }
            answered += lanes.answered();
            lowering += lanes.answered_lowering();
        }
        levels.push((level, answered - answered_before));
    }
    simd::set_level(simd::detected());
    eprintln!(
        "{outcomes:?}, {answered} answered from the lanes alone ({levels:?}), {lowering} of them \
         lowering the bed clearance"
    );
    if lockstep_robots == 0 {
        // The scalar level only: nothing to compare.
        return;
    }
    for r in [
        "none",
        "collision_bed",
        "collision_part",
        "self_collision",
        "elbow_singularity",
        "shoulder_singularity",
    ] {
        assert!(
            outcomes.get(r).is_some_and(|&c| c > 20),
            "{r}: {outcomes:?}"
        );
    }
    // Both ways are taken: passing samples answered by the lanes alone (a placement's usual
    // case for an arm of capsules; an arm with mesh pieces, the shipped ABB arms and the
    // UR10e, goes the per-sample way wherever a piece's box nears something), and the rest
    // (here, with the arm reaching into the wall, most) the per-sample way.
    // The bound is per level taken: a CPU without AVX-512 runs two levels, not three.
    for &(level, count) in levels.iter().filter(|l| l.0 != Level::Scalar) {
        assert!(
            count > 600,
            "{level:?}: {count} answered from the lanes alone ({levels:?})"
        );
    }
    assert!(
        answered < outcomes["none"],
        "{answered} of {} passing samples",
        outcomes["none"]
    );
    // Of those, most leave the bed clearance as it is (no shape's gap reaches it: one test
    // per lane) and a few lower it (a new smallest clearance, the capsules' closed form from
    // the lanes' axis ends, shape by shape; a dozen or so per level on the wide beds).
    assert!(
        lowering > 0 && lowering * 4 < answered,
        "{lowering} of {answered} lowered the clearance"
    );
}

#[test]
fn counting_the_beads_laid_from_an_earlier_count_gives_laid_at() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    for every in [1, 3, 10, 40] {
        let m = 2000;
        let p: Vec<V3> = (0..m)
            .map(|k| V3::new(0.001 * k as f64, 0.0, 0.0))
            .collect();
        // Print moves with travel between them.
        let print: Vec<bool> = (0..m).map(|k| (k / 150) % 3 != 2).collect();
        let beads = Beads::new(&p, &print, every, 0.02);
        for _ in 0..3000 {
            let k = rng.gen_range(0..m + 50);
            let earlier = rng.gen_range(0..=k);
            let want = beads.laid_at(k);
            // From the count at an earlier sample, from 0, and from the count itself.
            for from in [beads.laid_at(earlier), 0, want] {
                assert_eq!(beads.laid_at_from(k, from), want, "every {every}, k {k}");
            }
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[test]
fn the_collision_lanes_registers_give_the_scalar_selects_minima_maxima_and_tests_bit_for_bit() {
    use printwatt::evaluate::feasibility::collision::lanes::reg::V;
    use std::arch::x86_64::{__m128d, __m256d, __m512d};
    let special = [
        0.0,
        -0.0,
        1.0,
        -1.0,
        0.5,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
        -f64::NAN,
        1e-310,
        -2.5,
        2.5,
    ];
    let mut pairs = Vec::new();
    for &a in &special {
        for &b in &special {
            pairs.push((a, b));
        }
    }
    // Every case in every lane position.
    while pairs.len() % 8 != 0 {
        pairs.push((1.0, 2.0));
    }
    /// Lane by lane: the register's answers and the scalar ones.
    unsafe fn check<T: V>(pairs: &[(f64, f64)]) {
        for chunk in pairs.chunks(T::W) {
            let a: Vec<f64> = chunk.iter().map(|p| p.0).collect();
            let b: Vec<f64> = chunk.iter().map(|p| p.1).collect();
            let (x, y) = unsafe { (T::load(&a), T::load(&b)) };
            let mut out = vec![0.0; T::W];
            type Op<T> = (unsafe fn(T, T) -> T, fn(f64, f64) -> f64, &'static str);
            let ops: [Op<T>; 4] = [
                (T::inf, |a, b| if a <= b { a } else { b }, "inf"),
                (T::sup, |a, b| if a >= b { a } else { b }, "sup"),
                (T::lt_min, |a, b| if a < b { a } else { b }, "lt_min"),
                (T::max, f64::max, "max"),
            ];
            for (op, want, name) in ops {
                unsafe { op(x, y).store(&mut out) };
                for l in 0..T::W {
                    let w = want(a[l], b[l]);
                    // f64::max leaves the sign of a zero result and a NaN's bits open: only
                    // the value counts there (its callers square it and compare it).
                    let same = out[l].to_bits() == w.to_bits()
                        || (name == "max" && w == 0.0 && out[l] == 0.0)
                        || (name == "max" && w.is_nan() && out[l].is_nan());
                    assert!(same, "{name}({}, {}) = {} vs {w}", a[l], b[l], out[l]);
                }
            }
            let bits = unsafe { T::le_ge(x, y, y, T::splat(0.5)) };
            for l in 0..T::W {
                let want = a[l] <= b[l] && b[l] >= 0.5;
                assert_eq!(bits >> l & 1 == 1, want, "le_ge {} {}", a[l], b[l]);
            }
            assert_eq!(bits >> T::W, 0);
            for (op, want) in [
                (
                    T::add as unsafe fn(T, T) -> T,
                    (|a, b| a + b) as fn(f64, f64) -> f64,
                ),
                (T::sub, |a, b| a - b),
                (T::mul, |a, b| a * b),
            ] {
                unsafe { op(x, y).store(&mut out) };
                for l in 0..T::W {
                    let w = want(a[l], b[l]);
                    assert!(out[l].to_bits() == w.to_bits() || (w.is_nan() && out[l].is_nan()));
                }
            }
            unsafe { x.sqrt().store(&mut out) };
            for l in 0..T::W {
                let w = a[l].sqrt();
                assert!(out[l].to_bits() == w.to_bits() || (w.is_nan() && out[l].is_nan()));
            }
        }
    }
    unsafe {
        check::<f64>(&pairs);
        check::<__m128d>(&pairs);
    }
    if is_x86_feature_detected!("avx2") {
        #[target_feature(enable = "avx2")]
        unsafe fn avx2(pairs: &[(f64, f64)]) {
            unsafe { check::<__m256d>(pairs) }
        }
        unsafe { avx2(&pairs) };
    }
    if is_x86_feature_detected!("avx512f") {
        #[target_feature(enable = "avx512f")]
        unsafe fn avx512(pairs: &[(f64, f64)]) {
            unsafe { check::<__m512d>(pairs) }
        }
        unsafe { avx512(&pairs) };
    }
}

#[test]
fn evaluations_report_the_same_first_infeasible_sample_and_margins_on_every_level_as_the_scalar_path(
) {
    use printwatt::evaluate::feasibility::FeasibilityOptions;
    use printwatt::evaluate::{Evaluator, Objective};
    use printwatt::simd::{self, Level};
    let _g = LEVEL_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let model = common::robot("abb_irb6700_200_260");
    let tp = common::path("default.gcode");
    let job = common::default_job(&model, &tp);
    // The default links (mostly feasible) and fatter ones (the bed, the part and the arm
    // itself get in the way), every 10th and every 3rd sample checked.
    let mut fat = FeasibilityOptions::default();
    fat.radii.arm *= 2.0;
    fat.radii.wrist *= 3.0;
    let dense = FeasibilityOptions {
        check_every: 3,
        ..fat
    };
    let grid = printwatt::search::optimise::default_grid(
        printwatt::evaluate::feasibility::reach_m(&model),
    )
    .placements();
    let mut seen = std::collections::BTreeMap::new();
    for (o, step) in [(FeasibilityOptions::default(), 11), (fat, 7), (dense, 13)] {
        let ev = Evaluator::new(&job, o, Objective::Supply);
        let mut sc = ev.scratch().unwrap();
        let mut outcome = |level: Level, at| {
            assert!(simd::set_level(level) || level != Level::Scalar);
            match ev.evaluate(&mut sc, at).outcome {
                Ok(f) => format!("feasible {:?}", f.margins),
                Err(e) => format!("{:?} at {:?}: {}", e.reason, e.sample, e.detail),
            }
        };
        for at in grid.iter().step_by(step) {
            let want = outcome(Level::Scalar, at);
            for level in [Level::Sse2, Level::Avx2, Level::Avx512] {
                if level.available() {
                    assert_eq!(outcome(level, at), want, "{level:?} at {at:?}");
                }
            }
            let key = want.split(' ').next().unwrap_or("").to_string();
            *seen.entry(key).or_insert(0) += 1;
        }
    }
    simd::set_level(simd::detected());
    eprintln!("{seen:?}");
    assert!(seen.get("feasible").is_some_and(|&c| c > 2), "{seen:?}");
    assert!(seen.len() >= 4, "{seen:?}");
}
