//! Multi-station plans (issue 12 item 5): where the path is split, one station for a path within
//! reach with the energy of the single placement, several stations for a long path with every
//! segment feasible from its own (re-evaluated here), relocation cost and station count, the
//! error for a path no station covers, thread-count determinism, and the command's output
//! policy.

mod common;
use common::{bin, root};

use printwatt::energy::EnergyOptions;
use printwatt::placement::stations::{
    self, split_units, Candidates, Headings, Plan, StationsProblem,
};
use printwatt::placement::{Evaluator, FeasibilityOptions, Objective, PathJob};
use printwatt::robot::RobotModel;
use printwatt::timing::{JointStageOptions, ProfileOptions};
use printwatt::toolpath::{self, ReadOptions, Toolpath};

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
        feasibility: FeasibilityOptions::default(),
        objective: Objective::Supply,
        candidates: Candidates {
            positions: stations::track_positions([lo.x - 0.5, -1.2], [hi.x + 0.5, -1.2], 0.5)
                .unwrap(),
            headings: Headings::Auto,
            description: "test track".into(),
        },
        z_m: -0.5,
        spin_rad: 0.0,
        relocation_j,
        relocation_j_per_m: 0.0,
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
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
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
        let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
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
