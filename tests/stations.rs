//! Multi-station plans: where the path is split, one station for a path within
//! reach with the energy of the single placement, several stations for a long path with every
//! segment feasible from its own (re-evaluated here), relocation cost and station count, the
//! error for a path no station covers, thread-count determinism, and the command's output
//! policy.

mod common;
use common::{bin, root};

use printwatt::energy::EnergyOptions;
use printwatt::evaluate::{Evaluator, FeasibilityOptions, Objective, PathJob};
use printwatt::robot::RobotModel;
use printwatt::stations::{self, split_units, Candidates, Headings, Plan, StationsProblem};
use printwatt::timing::{JointStageOptions, ProfileOptions};
use printwatt::toolpath::{self, ReadOptions, Toolpath};

/// The feasibility checks of these tests: the default ones with a wrist margin of 0. Printing a
/// straight wall from a track beside it, part origin below the base, takes `q5` through 0 near
/// the station's foot; the plans here are about stations, not about that margin
/// (tests/motion.rs is).
fn feasibility() -> FeasibilityOptions {
    FeasibilityOptions {
        wrist_margin_rad: 0.0,
        ..FeasibilityOptions::default()
    }
}

fn robot() -> RobotModel {
    common::robot("abb_irb6700_200_260")
}

fn gcode(text: &str) -> Toolpath {
    toolpath::parse_gcode(text, "test.gcode", &ReadOptions::default()).unwrap()
}

/// A straight wall along x at y = 0, `pieces` pieces of `len_mm` printed one after the
/// other with a lifted travel between them (one layer, z = 20 mm), 150 mm/s.
fn wall_text(pieces: usize, len_mm: f64) -> String {
    let mut t = String::from("G21\nG90\nG0 X0 Y0 Z20 F12000\n");
    for k in 0..pieces {
        let (a, b) = (k as f64 * len_mm, (k + 1) as f64 * len_mm);
        if k > 0 {
            t += &format!("M5\nG0 Z70\nG0 X{a} Y0\nG0 Z20\n");
        }
        t += &format!("M3\nG1 X{b} Y0 F9000\n");
    }
    t += "M5\n";
    t
}

/// Stations along a track 1.2 m beside the wall (the side of negative y).
fn problem<'a>(
    model: &'a RobotModel,
    path: &'a Toolpath,
    relocation_j: f64,
) -> StationsProblem<'a> {
    let (lo, hi) = path.bounding_box().unwrap();
    StationsProblem {
        robot: model,
        path,
        energy: EnergyOptions::default(),
        profile: ProfileOptions::default(),
        joint: JointStageOptions::default(),
        feasibility: feasibility(),
        objective: Objective::Supply,
        candidates: Candidates {
            positions: stations::track_positions([lo.x - 0.5, -1.2], [hi.x + 0.5, -1.2], 0.5)
                .unwrap(),
            headings: Headings::Auto,
            description: "test track".into(),
            track: None,
        },
        z_m: -0.5,
        spin_rad: 0.0,
        relocation_j,
        relocation_j_per_m: 0.0,
        footprint_m: stations::default_footprint_m(model),
    }
}

fn solve(p: &StationsProblem) -> Plan {
    stations::solve(p, &|_, _| {}).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn units_are_cut_at_travel_moves_and_layer_changes() {
    // Three pieces with travel between them: three units.
    let w = gcode(&wall_text(3, 1000.0));
    let u = split_units(&w).unwrap();
    assert_eq!(u.len(), 3);
    assert!(u.iter().all(|u| (u.print_length_m - 1.0).abs() < 1e-9));
    // Seed 000's path: three layers printed continuously (the nozzle rises while extruding):
    // one unit per layer, the rising move opening the layer it rises to.
    let s = toolpath::load(
        &root().join("paths/seed000_test_path.gcode"),
        &ReadOptions::default(),
    )
    .unwrap();
    let u = split_units(&s).unwrap();
    assert_eq!(u.len(), 3, "{u:?}");
    assert!(u.windows(2).all(|w| w[1].z_m > w[0].z_m));
    let rise = &s.moves[u[1].first_move];
    assert!(rise.print && (rise.end.z - u[1].z_m).abs() < 1e-12);
    // A path that never extrudes cannot be split.
    let e = split_units(&gcode("G21\nG0 X0 Y0\nG0 X100\n")).unwrap_err();
    assert!(e.to_string().contains("no extruding moves"), "{e}");
}

#[test]
fn a_path_within_one_reach_gets_one_station_and_the_energy_of_that_placement() {
    let model = robot();
    let path = toolpath::load(
        &root().join("paths/seed000_test_path.gcode"),
        &ReadOptions::default(),
    )
    .unwrap();
    let mut p = problem(&model, &path, 1.0e6);
    p.candidates.positions = stations::grid_positions(&path, 0.5, 2.0).unwrap();
    let plan = solve(&p);
    assert_eq!(plan.segments.len(), 1, "{:?}", plan.segments);
    assert_eq!(plan.relocations, 0);
    let seg = &plan.segments[0];
    assert_eq!(seg.moves, [0, path.moves.len() - 1]);
    // The whole path evaluated at that station's placement, as `optimise` evaluates it.
    let job = PathJob::new(
        &model,
        &path,
        EnergyOptions::default(),
        ProfileOptions::default(),
        JointStageOptions::default(),
    )
    .unwrap();
    let ev = Evaluator::new(&job, feasibility(), Objective::Supply);
    let whole = ev.sweep(&[seg.station.placement], &|_, _| {}).unwrap();
    let e = whole[0].cost();
    assert!(
        (e - plan.energy_j).abs() <= 1e-9 * e,
        "plan {} J vs placement {e} J",
        plan.energy_j
    );
    assert_eq!(plan.total_j, plan.energy_j);
}

/// The sub-path of moves `first..=last`, built here from the path's moves (not with the
/// library's splitter), so that a segment is checked independently.
fn moves_of(path: &Toolpath, first: usize, last: usize) -> Toolpath {
    Toolpath {
        source: "segment".into(),
        start: if first == 0 {
            path.start
        } else {
            path.moves[first - 1].end
        },
        moves: path.moves[first..=last].to_vec(),
        ..Default::default()
    }
}

#[test]
fn a_long_path_gets_several_stations_and_every_segment_is_feasible_from_its_own() {
    let model = robot();
    let path = gcode(&wall_text(4, 2000.0));
    let p = problem(&model, &path, 1000.0);
    let plan = solve(&p);
    assert!(plan.segments.len() >= 2, "{:?}", plan.segments);
    assert_eq!(plan.relocations, plan.segments.len() - 1);
    // Contiguous, in order, covering every unit.
    assert_eq!(plan.segments[0].units[0], 0);
    assert_eq!(plan.segments.last().unwrap().units[1], plan.units.len() - 1);
    for w in plan.segments.windows(2) {
        assert_eq!(w[1].units[0], w[0].units[1] + 1);
        assert_ne!(
            (w[0].station.x_m, w[0].station.y_m),
            (w[1].station.x_m, w[1].station.y_m)
        );
    }
    let mut sum = 0.0;
    for s in &plan.segments {
        // The station's placement puts the robot base where the station says.
        let base = s
            .station
            .placement
            .frame()
            .inverse()
            .apply(&Default::default());
        assert!((base.x - s.station.x_m).abs() < 1e-9 && (base.y - s.station.y_m).abs() < 1e-9);
        let sub = moves_of(&path, s.moves[0], s.moves[1]);
        let job = PathJob::new(
            &model,
            &sub,
            EnergyOptions::default(),
            ProfileOptions::default(),
            JointStageOptions::default(),
        )
        .unwrap();
        let ev = Evaluator::new(&job, feasibility(), Objective::Supply);
        let r = ev.sweep(&[s.station.placement], &|_, _| {}).unwrap();
        let f = r[0]
            .feasible()
            .unwrap_or_else(|| panic!("segment {:?} infeasible: {:?}", s.units, r[0].outcome));
        assert!((f.energy_j - s.eval.energy_j).abs() <= 1e-9 * f.energy_j);
        sum += f.energy_j;
    }
    assert!((plan.energy_j - sum).abs() <= 1e-9 * sum);
    assert!((plan.total_j - (sum + 1000.0 * plan.relocations as f64)).abs() <= 1e-9 * plan.total_j);
}

#[test]
fn raising_the_relocation_cost_never_increases_the_number_of_stations() {
    let model = robot();
    let path = gcode(&wall_text(4, 1500.0));
    let mut last: Option<(usize, f64)> = None;
    let mut counts = Vec::new();
    for cost in [0.0, 300.0, 3000.0, 3.0e4, 3.0e6] {
        let plan = solve(&problem(&model, &path, cost));
        let n = plan.segments.len();
        counts.push(n);
        if let Some((n0, t0)) = last {
            assert!(
                n <= n0,
                "cost {cost} J: {n} stations after {n0}: {counts:?}"
            );
            assert!(plan.total_j >= t0, "cost {cost} J: total fell");
        }
        last = Some((n, plan.total_j));
    }
    // Free relocations use more stations than costly ones on this path (not a vacuous test).
    assert!(counts[0] > *counts.last().unwrap(), "{counts:?}");
}

#[test]
fn a_path_no_station_covers_is_refused_naming_the_first_unit_out_of_reach() {
    let model = robot();
    // A 2 m piece, then a 9 m straight piece no station reaches end to end (lines 5-6).
    let text =
        "G21\nG90\nG0 X0 Y0 Z20 F12000\nM3\nG1 X2000 Y0 F9000\nM5\nG0 X3000\nM3\nG1 X12000\nM5\n";
    let path = gcode(text);
    let e = stations::solve(&problem(&model, &path, 1000.0), &|_, _| {}).unwrap_err();
    let m = e.to_string();
    assert!(m.contains("unit 1 "), "{m}");
    assert!(m.contains("lines 9–9"), "{m}");
    assert!(m.contains("within the arm's reach"), "{m}");
}

#[test]
fn one_and_two_threads_give_the_same_plan() {
    let model = robot();
    let path = gcode(&wall_text(4, 1500.0));
    let p = problem(&model, &path, 2000.0);
    let run = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| solve(&p))
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn bad_relocation_costs_and_steps_are_refused() {
    let model = robot();
    let path = gcode(&wall_text(2, 1000.0));
    let mut p = problem(&model, &path, -1.0);
    let e = stations::solve(&p, &|_, _| {}).unwrap_err();
    assert!(e.to_string().contains("relocation cost"), "{e}");
    p.relocation_j = f64::NAN;
    assert!(stations::solve(&p, &|_, _| {}).is_err());
    assert!(stations::grid_positions(&path, 0.0, 1.0).is_err());
    assert!(stations::grid_positions(&path, 1e-4, 3.0).is_err()); // too many positions
    assert!(stations::track_positions([0.0, 0.0], [1.0, 0.0], -1.0).is_err());
}

#[test]
fn stations_refuses_to_overwrite_an_existing_run_without_force() {
    let d = std::env::temp_dir().join(format!("printwatt_stations_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let path = d.join("wall.gcode");
    std::fs::write(&path, wall_text(2, 1500.0)).unwrap();
    let out = d.join("run");
    let args = |force: bool| {
        let mut v = vec![
            "stations".to_string(),
            "--path".into(),
            path.display().to_string(),
            "--relocation-cost".into(),
            "5000".into(),
            "--track".into(),
            "-0.5,-1.2:3.5,-1.2".into(),
            "--wrist-margin".into(),
            "0".into(),
            "--out".into(),
            out.display().to_string(),
        ];
        if force {
            v.push("--force".into());
        }
        v
    };
    let o = bin().args(args(false)).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in ["summary.json", "stations.csv", "report.html", "run.json"] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let before = std::fs::read(out.join("summary.json")).unwrap();
    let o = bin().args(args(false)).output().unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--force"), "{err}");
    assert_eq!(std::fs::read(out.join("summary.json")).unwrap(), before);
    let o = bin().args(args(true)).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // Grid options of sweep/optimise do not apply.
    let o = bin()
        .args(["stations", "--relocation-cost", "1", "--x", "1:2:1"])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("chooses its own stations"));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn fixed_headings_along_a_track_are_kept_and_stations_stay_on_the_track() {
    let model = robot();
    let path = gcode(&wall_text(3, 1500.0));
    let mut p = problem(&model, &path, 2000.0);
    let h = 90f64.to_radians();
    p.candidates.headings = Headings::Fixed(vec![h]);
    let plan = solve(&p);
    for s in &plan.segments {
        assert_eq!(s.station.heading_rad, h);
        assert!(
            (s.station.y_m + 1.2).abs() < 1e-12,
            "off the track: {:?}",
            s.station
        );
        // The placement's yaw is the heading turned back.
        assert!((s.station.placement.yaw + h).abs() < 1e-12);
    }
}

#[test]
fn walls_printed_before_a_segment_are_in_its_collision_scene() {
    use printwatt::evaluate::Reason;
    use printwatt::frame::Placement;
    let model = robot();
    let path =
        toolpath::load(&root().join("paths/default.gcode"), &ReadOptions::default()).unwrap();
    let job = PathJob::new(
        &model,
        &path,
        EnergyOptions::default(),
        ProfileOptions::default(),
        JointStageOptions::default(),
    )
    .unwrap();
    let at = Placement::new(1.7, 0.0, 0.0, std::f64::consts::FRAC_PI_2);
    let free = Evaluator::new(&job, feasibility(), Objective::Supply);
    let e = free.sweep(&[at], &|_, _| {}).unwrap();
    assert!(e[0].cost().is_finite(), "{:?}", e[0].outcome);
    // A 3 m column printed earlier halfway between the robot base and the part origin: the
    // arm reaches over it.
    let base = at.frame().inverse().apply(&Default::default());
    let mid = base * 0.5;
    let column = vec![(
        printwatt::math::V3::new(mid.x, mid.y, 0.0),
        printwatt::math::V3::new(mid.x, mid.y, 3.0),
    )];
    let walled = Evaluator::new(&job, feasibility(), Objective::Supply).with_prior_walls(column);
    let e = walled.sweep(&[at], &|_, _| {}).unwrap();
    let why = e[0].outcome.as_ref().expect_err("the column is in the way");
    assert_eq!(why.reason, Reason::CollisionPart, "{why}");
    // Bead 0 is the column: walls printed earlier are indexed before the path's own beads and
    // stand from sample 0 on (where the arm first meets it depends on the links' shapes).
    assert!(why.detail.contains("printed bead 0"), "the column: {why}");
}

/// One layer (z = 20 mm) of straight wall pieces (mm, part frame) printed one after the
/// other with a lifted travel between them, 150 mm/s.
fn pieces_text(pieces: &[[f64; 4]]) -> String {
    let mut t = format!(
        "G21\nG90\nG0 X{} Y{} Z20 F12000\n",
        pieces[0][0], pieces[0][1]
    );
    for (k, p) in pieces.iter().enumerate() {
        if k > 0 {
            t += &format!("M5\nG0 Z70\nG0 X{} Y{}\nG0 Z20\n", p[0], p[1]);
        }
        t += &format!("M3\nG1 X{} Y{} F9000\n", p[2], p[3]);
    }
    t + "M5\n"
}

/// Points every 10 mm along the walls of moves `..=last` (plan view, m).
fn wall_points(path: &Toolpath, last: usize) -> Vec<[f64; 2]> {
    let mut v = Vec::new();
    for (start, m) in path.segments().take(last + 1) {
        if m.print {
            let n = ((m.length(&start) / 0.01).ceil() as usize).max(1);
            for k in 0..=n {
                let q = m.point_at(&start, k as f64 / n as f64);
                v.push([q.x, q.y]);
            }
        }
    }
    v
}

/// Distance from `p` to the segment `a–b` (plan view, m).
fn to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy)
}

fn grid_problem<'a>(model: &'a RobotModel, path: &'a Toolpath, step: f64) -> StationsProblem<'a> {
    let reach = printwatt::evaluate::feasibility::reach_m(model);
    let mut p = problem(model, path, 20_000.0);
    p.candidates = Candidates::grid(path, step, reach, Headings::Auto).unwrap();
    p
}

/// The example floor plan (four rooms with doors).
fn floor_path() -> Toolpath {
    toolpath::load(
        &root().join("paths/floor_four_rooms.gcode"),
        &ReadOptions::default(),
    )
    .unwrap()
}

#[test]
fn a_station_plan_never_stands_on_or_drives_across_a_printed_wall() {
    // The example floor (four rooms with doors): a plan stood stations inside rooms whose
    // walls were printed before, reached across them, on a crawler that cannot cross them.
    let model = robot();
    let path = floor_path();
    let p = grid_problem(&model, &path, 0.75);
    let plan = solve(&p);
    assert!(plan.segments.len() > 1);
    // The checks bound: positions on walls were refused, and ways across walls were refused
    // or went around them.
    assert!(plan.stats.footprint_on_wall > 0);
    assert!(plan.stats.way_blocked + plan.stats.detoured > 0);
    assert_clear_of_walls(&plan, &path, p.footprint_m);
}

/// No station of `plan` stands on a wall printed before or by its segment, and no way between
/// stations comes closer to a wall printed before the move than the floor disc (radius
/// `footprint` m) allows: checked on wall points every 10 mm, independently of the planner.
fn assert_clear_of_walls(plan: &Plan, path: &Toolpath, footprint: f64) {
    assert_eq!(plan.ways.len(), plan.segments.len() - 1);
    let clear = footprint + printwatt::evaluate::feasibility::collision::BEAD_RADIUS_M;
    let tol = 0.006;
    for (k, s) in plan.segments.iter().enumerate() {
        let at = [s.station.x_m, s.station.y_m];
        for w in wall_points(path, s.moves[1]) {
            let d = (w[0] - at[0]).hypot(w[1] - at[1]);
            assert!(
                d + tol >= clear,
                "station {} stands on a wall: {d} m from ({}, {})",
                k + 1,
                w[0],
                w[1]
            );
        }
        if let Some(next) = plan.segments.get(k + 1) {
            let to = [next.station.x_m, next.station.y_m];
            let way = &plan.ways[k];
            assert_eq!(way.points.first(), Some(&at));
            assert_eq!(way.points.last(), Some(&to));
            assert!(way.length_m + 1e-12 >= (to[0] - at[0]).hypot(to[1] - at[1]));
            for w in wall_points(path, s.moves[1]) {
                for leg in way.points.windows(2) {
                    let d = to_segment(w, leg[0], leg[1]);
                    assert!(
                        d + tol >= clear,
                        "the way from station {} crosses the wall at ({}, {}): {d} m",
                        k + 1,
                        w[0],
                        w[1]
                    );
                }
            }
        }
    }
}

#[test]
fn a_room_closed_around_the_arm_is_refused_and_one_closed_from_outside_or_through_a_door_is_not() {
    // Room A (0..3 m) printed whole, then room B (3..6 m) against its right wall: from inside
    // A nothing reaches B's far wall, and the way out of A crosses A's walls.
    let model = robot();
    let mut a: Vec<[f64; 4]> = vec![
        [0.0, 0.0, 3000.0, 0.0],
        [3000.0, 0.0, 3000.0, 3000.0],
        [3000.0, 3000.0, 0.0, 3000.0],
        [0.0, 3000.0, 0.0, 0.0],
    ];
    let b = [
        [3000.0, 0.0, 6000.0, 0.0],
        [6000.0, 0.0, 6000.0, 3000.0],
        [6000.0, 3000.0, 3000.0, 3000.0],
    ];
    // Stations only inside the rooms: the arm that closes A stands in it and is shut in.
    let inside = |p: &mut StationsProblem| {
        p.candidates
            .positions
            .retain(|q| q[1] > 0.0 && q[1] < 3.0 && q[0] > 0.0 && q[0] < 6.0 && q[0] != 3.0);
    };
    let closed = gcode(&pieces_text(&[a.clone(), b.to_vec()].concat()));
    let mut p = grid_problem(&model, &closed, 0.75);
    inside(&mut p);
    let e = stations::solve(&p, &|_, _| {}).expect_err("room A closes the arm in");
    let msg = e.to_string();
    assert!(
        msg.contains("no plan of stations prints the path") && msg.contains("wall"),
        "{msg}"
    );
    // Stations anywhere: A is closed from a station outside it, and the crawler goes around
    // A to B, clear of every wall.
    let p = grid_problem(&model, &closed, 0.75);
    let plan = solve(&p);
    assert!(plan.stats.detoured > 0);
    assert!(
        plan.ways.iter().any(|w| w.points.len() > 2),
        "{:?}",
        plan.ways
    );
    assert_clear_of_walls(&plan, &closed, p.footprint_m);
    // The same rooms with a 1.5 m door in the shared wall, stations inside: through the door.
    a[1] = [3000.0, 0.0, 3000.0, 750.0];
    a.insert(2, [3000.0, 2250.0, 3000.0, 3000.0]);
    let door = gcode(&pieces_text(&[a, b.to_vec()].concat()));
    let mut p = grid_problem(&model, &door, 0.75);
    inside(&mut p);
    let plan = solve(&p);
    assert!(plan.segments.len() > 1);
    assert_clear_of_walls(&plan, &door, p.footprint_m);
}

#[test]
fn a_track_under_a_wall_is_refused_naming_the_wall_line() {
    let model = robot();
    let path = floor_path();
    let mut p = problem(&model, &path, 20_000.0);
    // Along y = 0.5 m: under the cross walls (their doors are at 0.75…2.25 m).
    p.candidates = Candidates::track([-1.0, 0.5], [13.0, 0.5], 0.5, Headings::Auto).unwrap();
    let e = stations::solve(&p, &|_, _| {}).expect_err("the rail lies under walls");
    let msg = e.to_string();
    assert!(msg.contains("lies under the wall printed by line"), "{msg}");
}

#[test]
fn a_crawler_goes_around_a_printed_wall_through_its_door_and_never_through_a_narrow_gap() {
    // A 10 × 5 m room whose wall along y = 0 has a door at x = 1…3 m; the disc (0.5 m, plus
    // the bead's half-width) goes from (−1, −2) m inside to (−1, 2) m outside. The straight way
    // crosses the wall; the way found goes through the door, every leg clear of the wall (checked on wall points every
    // 10 mm, independently of the router). With a 0.8 m gap, narrower than the disc, and with
    // no gap, there is no way.
    use printwatt::stations::floor::{wall_chords, Floor, Router};
    let r = 0.5;
    let clear = r + printwatt::evaluate::feasibility::collision::BEAD_RADIUS_M;
    let (a, b) = ([-1.0, -2.0], [-1.0, 2.0]);
    let wall = |gap: Option<(f64, f64)>| {
        let mut pieces: Vec<[f64; 4]> = vec![
            [-5000.0, -5000.0, 5000.0, -5000.0],
            [5000.0, -5000.0, 5000.0, 0.0],
        ];
        match gap {
            Some((g0, g1)) => pieces.extend([[5000.0, 0.0, g1, 0.0], [g0, 0.0, -5000.0, 0.0]]),
            None => pieces.push([5000.0, 0.0, -5000.0, 0.0]),
        }
        pieces.push([-5000.0, 0.0, -5000.0, -5000.0]);
        gcode(&pieces_text(&pieces))
    };
    let door = wall(Some((1000.0, 3000.0)));
    let floor = Floor::from_chords(&wall_chords(&door));
    let last = door.moves.len() - 1;
    assert!(floor.first_blocking(a, b, r, last).is_some());
    let way = Router::new(&floor, r)
        .way(a, b, last)
        .expect("a way through the door");
    assert_eq!(way.points.first(), Some(&a));
    assert_eq!(way.points.last(), Some(&b));
    let len: f64 = way
        .points
        .windows(2)
        .map(|l| (l[1][0] - l[0][0]).hypot(l[1][1] - l[0][1]))
        .sum();
    assert!((len - way.length_m).abs() < 1e-12);
    // Through the door: from (−1, −2) to (1.525, 0) (the nearest the disc passes the jamb)
    // and on to (−1, 2); the octagons make it at most a few per cent longer.
    let through_door = 2.0 * (2.0 + clear).hypot(2.0);
    assert!(
        way.length_m >= through_door - 1e-9 && way.length_m < 1.06 * through_door,
        "{way:?}"
    );
    let crossing = way
        .points
        .windows(2)
        .find(|l| (l[0][1] < 0.0) != (l[1][1] < 0.0))
        .expect("the way crosses y = 0");
    let t = -crossing[0][1] / (crossing[1][1] - crossing[0][1]);
    let x = crossing[0][0] + t * (crossing[1][0] - crossing[0][0]);
    assert!(
        (1.0 + clear - 1e-6..=3.0 - clear + 1e-6).contains(&x),
        "{x}"
    );
    for w in wall_points(&door, last) {
        for leg in way.points.windows(2) {
            assert!(
                to_segment(w, leg[0], leg[1]) + 0.006 >= clear,
                "{w:?} {leg:?}"
            );
        }
    }
    for closed in [wall(Some((1000.0, 1800.0))), wall(None)] {
        let floor = Floor::from_chords(&wall_chords(&closed));
        let last = closed.moves.len() - 1;
        assert_eq!(Router::new(&floor, r).way(a, b, last), None);
    }
}
