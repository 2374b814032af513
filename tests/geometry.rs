//! The shipped arms' published collision hulls, the pedestal under the base and the floor.

mod common;

use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::{Isometry, Point};
use parry3d_f64::query;
use parry3d_f64::shape::Ball;
use printwatt::evaluate::feasibility::collision::{self, Beads, RobotShapes};
use printwatt::evaluate::feasibility::{reach_m, LinkRadii, Reason, World};
use printwatt::math::{Frame, V3};
use printwatt::robot::RobotModel;

fn shapes(model: &RobotModel) -> RobotShapes {
    RobotShapes::new(model, reach_m(model), &LinkRadii::default())
}

/// The base's shapes' box at the home pose (base frame, m).
fn base_box(rs: &RobotShapes) -> Aabb {
    let mut b = Aabb::new_invalid();
    for s in rs.shapes.iter().filter(|s| s.body == 0) {
        b.merge(&s.shape.compute_aabb(&s.local));
    }
    b
}

#[test]
fn the_shipped_arms_collide_with_their_published_hulls() {
    for name in ["abb_irb6700_200_260", "abb_irb4600_40_255", "ur10e"] {
        let model = common::robot(name);
        let rs = shapes(&model);
        // Every link and the base: URDF geometry, no capsule stands in.
        assert_eq!(rs.links_with_urdf_geometry, model.dof(), "{name}");
        assert!(
            rs.shapes
                .iter()
                .filter(|s| s.role == collision::Role::Link)
                .all(|s| s.label.contains("URDF mesh hull")),
            "{name}: {:?}",
            rs.shapes.iter().map(|s| &s.label).collect::<Vec<_>>()
        );
        // The hulls are small: at most 64 vertices for a link in one piece, a few hundred for
        // a piece of a decomposed link.
        for s in &rs.shapes {
            if let Some(h) = s.shape.as_convex_polyhedron() {
                let whole = rs
                    .shapes
                    .iter()
                    .filter(|t| t.body == s.body && t.role == s.role)
                    .count()
                    == 1;
                let most = if whole { 64 } else { 400 };
                assert!(h.points().len() <= most, "{name} {}", s.label);
            }
        }
        // At home, with nothing around, the arm meets nothing (no self-collision).
        let q = vec![0.0; model.dof()];
        let world = World::new(
            &Frame::identity(),
            (V3::new(-9.0, -0.5, 0.0), V3::new(-8.0, 0.5, 0.1)),
            &Default::default(),
        )
        .with_floor(&rs);
        let poses = rs.poses(&model, &q, &world.base_iso);
        let beads = Beads::new(&[], &[], 1, 0.02);
        assert_eq!(
            collision::check(&rs, &poses, &world.bed, &beads, 0, &mut None),
            None,
            "{name}"
        );
    }
    // The IRB 6700's foot: the published base reaches 0.6 m behind the axis of joint 1 and
    // 0.36 m to each side, far beyond the 0.18 m capsule that stood in for it; a ball 0.3 m
    // behind the axis, 0.2 m up, meets the base.
    let model = common::robot("abb_irb6700_200_260");
    let rs = shapes(&model);
    let b = base_box(&rs);
    assert!(
        b.mins.x < -0.6 && b.maxs.y > 0.35 && b.mins.y < -0.35,
        "{b:?}"
    );
    assert!(-b.mins.x > 0.18 + 0.4, "{b:?}");
    let base = rs.shapes.iter().find(|s| s.body == 0).unwrap();
    let ball = Ball::new(0.05);
    assert!(query::intersection_test(
        &base.local,
        base.shape.as_ref(),
        &Isometry::translation(-0.3, 0.0, 0.2),
        &ball
    )
    .unwrap());
}

/// The IRB 6700 with the upper arm tilted 85° forward and the forearm level with it: the
/// wrist reaches about 0.26 m below the base frame's origin.
const DIVE: [f64; 6] = [0.0, 1.48, 0.0, 0.0, 0.0, 0.0];

/// The first collision of `model` at `q` with a bed far behind the arm (its top at z = 0, the
/// part frame the base frame), the floor under the base: by [`collision::check`] on the poses
/// and by [`collision::check_bodies`] on the bodies' frames.
fn verdicts(model: &RobotModel, q: &[f64]) -> [Option<(Reason, String)>; 2] {
    let rs = shapes(model);
    let world = World::new(
        &Frame::identity(),
        (V3::new(-9.0, -0.5, 0.0), V3::new(-8.0, 0.5, 0.1)),
        &Default::default(),
    )
    .with_floor(&rs);
    let beads = Beads::new(&[], &[], 1, 0.02);
    let poses = rs.poses(model, q, &world.base_iso);
    let a = collision::check(&rs, &poses, &world.bed, &beads, 0, &mut None);
    let bodies = rs.body_frames(q, None, &world.base_to_part);
    let mut isos = Vec::new();
    let b = collision::check_bodies(&rs, &bodies, &world.bed, &beads, 0, &mut None, &mut isos);
    [a, b]
}

#[test]
fn a_link_below_the_floor_is_infeasible_with_the_reason() {
    let model = common::robot("abb_irb6700_200_260");
    for v in verdicts(&model, &DIVE) {
        let (reason, detail) = v.expect("the wrist dives below the floor");
        assert_eq!(reason, Reason::CollisionFloor, "{detail}");
        assert_eq!(reason.name(), "collision_floor");
        assert!(detail.contains("below the floor"), "{detail}");
        assert!(detail.contains("link_"), "{detail}");
    }
    // Raised (upper arm 40° forward) it stays above the floor.
    let up = [0.0, 0.7, 0.0, 0.0, 0.0, 0.0];
    assert_eq!(verdicts(&model, &up), [None, None]);
    // The capsule arms (no published meshes) as well: the PUMA 560's forearm down.
    let puma = common::robot("puma560");
    let q = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    let [a, b] = verdicts(&puma, &q);
    assert_eq!(a, b);
}

/// A copy of the shipped IRB 6700 in a scratch directory, and a function giving its drive
/// file with `keys` added to the `[robot]` table.
fn irb6700_copy(name: &str) -> (std::path::PathBuf, impl Fn(&str) -> String) {
    let dir = common::scratch("geometry", name);
    std::fs::create_dir_all(dir.join("collision")).unwrap();
    let src = common::root().join("robots/abb_irb6700_200_260");
    for f in ["robot.urdf", "README.md"] {
        std::fs::copy(src.join(f), dir.join(f)).unwrap();
    }
    for e in std::fs::read_dir(src.join("collision")).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), dir.join("collision").join(e.file_name())).unwrap();
    }
    let drive = std::fs::read_to_string(src.join("drive.toml")).unwrap();
    let with = move |keys: &str| drive.replacen("[robot]\n", &format!("[robot]\n{keys}\n"), 1);
    (dir, with)
}

#[test]
fn the_base_footprint_for_the_report_is_the_base_collision_geometry_from_above() {
    // The base's footprint is its collision geometry seen from above: the IRB 6700's foot
    // reaches 0.63 m behind axis 1 and 0.36 m to each side.
    let model = common::robot("abb_irb6700_200_260");
    let f = printwatt::report::site::base_footprint(&model);
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in &f {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    assert!(f.len() >= 3, "{f:?}");
    assert!(
        x0 < -0.6 && x0 > -0.7 && x1 > 0.35 && y1 > 0.35 && y0 < -0.35,
        "{f:?}"
    );
    // A capsule arm has none (the report marks axis 1 instead).
    assert!(printwatt::report::site::base_footprint(&common::robot("puma560")).is_empty());
}

#[test]
fn the_pedestal_raises_the_robot_and_is_a_fixed_body() {
    // From the drive file's [robot] table.
    let (dir, with) = irb6700_copy("pedestal");
    std::fs::write(
        dir.join("drive.toml"),
        with("pedestal_height_m = 0.8\npedestal_radius_m = 0.5"),
    )
    .unwrap();
    let model = printwatt::robot::load(&dir).unwrap();
    assert_eq!(model.info.pedestal_height_m, 0.8);
    assert_eq!(model.info.pedestal_radius_m, 0.5);
    let rs = shapes(&model);
    assert_eq!(rs.floor_below_base_m, 0.8);
    // The pedestal: a fixed body (body 0, as the base) from the floor to the base, 0.5 m round.
    let ped: Vec<_> = rs
        .shapes
        .iter()
        .enumerate()
        .filter(|(_, s)| s.label.starts_with("pedestal"))
        .collect();
    assert_eq!(ped.len(), 1);
    let (pi, p) = ped[0];
    assert_eq!(p.body, 0);
    let b = p.shape.compute_aabb(&p.local);
    assert!(
        (b.mins.z + 0.8).abs() < 1e-9 && b.maxs.z.abs() < 1e-9,
        "{b:?}"
    );
    assert!(
        (b.maxs.x - 0.5).abs() < 1e-9 && (b.mins.y + 0.5).abs() < 1e-9,
        "{b:?}"
    );
    // It is checked against the links far enough along the chain (as the base is).
    assert!(rs.pairs.iter().any(|&(i, j)| i == pi || j == pi));
    // Standing on it, the arm's dive stays 0.5 m above the floor.
    assert_eq!(verdicts(&model, &DIVE), [None, None]);
    // A pedestal of a negative height or without its radius is refused, naming the key.
    for (keys, key) in [
        (
            "pedestal_height_m = -1.0\npedestal_radius_m = 0.5",
            "pedestal_height_m",
        ),
        ("pedestal_height_m = 0.5", "pedestal_radius_m"),
    ] {
        std::fs::write(dir.join("drive.toml"), with(keys)).unwrap();
        let e = printwatt::robot::load(&dir).unwrap_err().to_string();
        assert!(e.contains(key) && e.contains("drive.toml"), "{e}");
    }
}

#[test]
fn every_shipped_collision_hull_is_convex_and_holds_its_vertices() {
    // The committed pieces are decimated, conservative hulls (their containment of the
    // source meshes is checked by `tools/robots/collision_hulls.py --check` against the
    // sources): each file's vertices are its own convex hull's (nothing lost in reading), at
    // most 64 of them for a link in one piece and 400 for a piece of a decomposed link, in
    // metres (within 1.5 m of the link origin).
    for name in ["abb_irb6700_200_260", "abb_irb4600_40_255", "ur10e"] {
        let dir = common::root().join("robots").join(name).join("collision");
        let mut n = 0;
        for e in std::fs::read_dir(&dir).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_none_or(|x| x != "obj") {
                continue;
            }
            n += 1;
            let v = printwatt::robot::mesh::read_vertices(&p).unwrap();
            let stem = p.file_stem().unwrap().to_string_lossy().into_owned();
            let link = stem.rsplit_once('-').unwrap().0.to_string();
            let whole = !dir.join(format!("{link}-2.obj")).exists();
            let most = if whole { 64 } else { 400 };
            assert!(v.len() <= most && v.len() >= 4, "{}", p.display());
            let pts: Vec<Point<f64>> = v.iter().map(|p| Point::from(*p)).collect();
            let hull = parry3d_f64::shape::ConvexPolyhedron::from_convex_hull(&pts).unwrap();
            // A decomposed link's piece (a halfspace intersection) may hold a vertex within
            // rounding of a face, which the hull drops.
            let kept = hull.points().len();
            assert!(
                kept == v.len() || (!whole && kept + 4 >= v.len()),
                "{}: {kept} of {}",
                p.display(),
                v.len()
            );
            assert!(v.iter().all(|p| p.norm() < 1.5), "{}", p.display());
        }
        assert!(n >= 7, "{name}: base and six links, a piece or more each");
        // Every link and the base have a piece, named `<link>-<k>.obj` with k from 1.
        for link in [
            "base_link",
            "link_1",
            "link_2",
            "link_3",
            "link_4",
            "link_5",
            "link_6",
        ] {
            assert!(dir.join(format!("{link}-1.obj")).exists(), "{name} {link}");
        }
    }
}

/// The convex pieces of link `link` (0-based joint index + 1 = body) of `rs`, in the link frame.
fn pieces(rs: &RobotShapes, body: usize) -> Vec<&collision::BodyShape> {
    rs.shapes
        .iter()
        .filter(|s| s.body == body && s.role == collision::Role::Link)
        .collect()
}

/// Whether a ball of radius `r` at `p` (link frame of `body`, m) meets one of its pieces.
fn meets(rs: &RobotShapes, body: usize, p: V3, r: f64) -> bool {
    let ball = Ball::new(r);
    pieces(rs, body).iter().any(|s| {
        query::intersection_test(
            &s.local,
            s.shape.as_ref(),
            &Isometry::translation(p.x, p.y, p.z),
            &ball,
        )
        .unwrap()
    })
}

#[test]
fn the_forearm_fork_is_open_in_the_collision_geometry() {
    // The ABB forearms (link_4) end in a fork around the wrist: the collision geometry is
    // several convex pieces, the tube and the two prongs, with the wrist's axis (joint 5's
    // origin) between the prongs free; the tube is solid. One convex hull of all the pieces
    // would close the fork (as the published collision mesh, a convex hull, does).
    for name in ["abb_irb6700_200_260", "abb_irb4600_40_255"] {
        let model = common::robot(name);
        let rs = shapes(&model);
        let body = 4; // link_4
        let ps = pieces(&rs, body);
        assert!(ps.len() >= 3, "{name}: {} pieces", ps.len());
        let wrist = model.joints[4].origin.pos; // joint 5 in the link_4 frame
        assert!(
            wrist.x > 1.0 && wrist.y == 0.0 && wrist.z == 0.0,
            "{name} {wrist:?}"
        );
        // Between the prongs, on the wrist's axis: free (a 10 mm ball, and one a little
        // above and below the axis).
        for dz in [-0.03, 0.0, 0.03] {
            let p = wrist + V3::new(0.0, 0.0, dz);
            assert!(
                !meets(&rs, body, p, 0.01),
                "{name}: the fork is closed at {p:?}"
            );
        }
        // In the tube, half way to the wrist: solid.
        assert!(
            meets(&rs, body, wrist * 0.4, 0.01),
            "{name}: the tube is open"
        );
        // The prongs: either side of the wrist, beyond its housing.
        let side = |y: f64| meets(&rs, body, wrist + V3::new(0.0, y, 0.0), 0.005);
        assert!(
            (0..40).any(|k| side(0.06 + 0.005 * k as f64))
                && (0..40).any(|k| side(-0.06 - 0.005 * k as f64)),
            "{name}: no prong beside the wrist"
        );
        // One hull of all the pieces would hold the wrist's axis.
        let mut all: Vec<Point<f64>> = Vec::new();
        for s in &ps {
            let h = s.shape.as_convex_polyhedron().unwrap();
            all.extend(h.points().iter().map(|p| s.local * p));
        }
        let one = parry3d_f64::shape::ConvexPolyhedron::from_convex_hull(&all).unwrap();
        assert!(query::intersection_test(
            &Isometry::identity(),
            &one,
            &Isometry::translation(wrist.x, wrist.y, wrist.z),
            &Ball::new(0.01)
        )
        .unwrap());
    }
}

#[test]
fn a_capsule_through_the_fork_meets_only_the_tube() {
    // A 10 mm rod along the wrist's axis of bending (y, joint 5's axis) at the wrist, 60 mm
    // long: it lies in the fork's opening and meets no piece of the forearm; the same rod
    // through the tube meets it. (The hose of [tool.geometry] passes there when the wrist
    // bends.)
    use parry3d_f64::shape::Capsule;
    let model = common::robot("abb_irb6700_200_260");
    let rs = shapes(&model);
    let wrist = model.joints[4].origin.pos;
    let rod = |x: f64, z: f64| Capsule::new(Point::new(x, -0.03, z), Point::new(x, 0.03, z), 0.01);
    let hits = |c: &Capsule| {
        pieces(&rs, 4).iter().any(|s| {
            query::intersection_test(&s.local, s.shape.as_ref(), &Isometry::identity(), c).unwrap()
        })
    };
    assert!(!hits(&rod(wrist.x, 0.0)), "the rod at the wrist's axis");
    assert!(hits(&rod(0.3, 0.0)), "the rod through the tube");
}
