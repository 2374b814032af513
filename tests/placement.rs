//! Placement planner: feasibility with reasons, sweeps, determinism, optimiser, CLI.

mod common;
use common::{bin, root};

use printwatt::evaluate::{Evaluator, FeasibilityOptions, Objective};
use printwatt::robot;
use printwatt::toolpath::{self, Placement, ReadOptions};

fn load(robot_id: &str, path: &str) -> (robot::RobotModel, toolpath::Toolpath) {
    let model = robot::load(&root().join("robots").join(robot_id)).unwrap();
    let tp = toolpath::load(&root().join("paths").join(path), &ReadOptions::default()).unwrap();
    (model, tp)
}

#[test]
fn fast_evaluation_matches_full_evaluation() {
    let (model, tp) = load("abb_irb6700_200_260", "default.gcode");
    let job = common::default_job(&model, &tp);
    // The wrist checks off (this placement passes near the wrist singularity).
    let feas = FeasibilityOptions {
        wrist_min: 0.0,
        wrist_margin_rad: 0.0,
        ..Default::default()
    };
    let ev = Evaluator::new(&job, feas, Objective::Supply);
    let at = Placement::new(1.7, 0.0, 0.0, std::f64::consts::FRAC_PI_2);
    let mut sc = ev.scratch().unwrap();
    let t0 = std::time::Instant::now();
    let fast = ev.evaluate(&mut sc, &at);
    let dt_fast = t0.elapsed();
    let t0 = std::time::Instant::now();
    let full = job.evaluate(&at).unwrap().unwrap();
    let dt_full = t0.elapsed();
    eprintln!(
        "fast {dt_fast:?} full {dt_full:?} samples {}",
        full.timed.traj.len()
    );
    let f = fast.outcome.as_ref().unwrap_or_else(|e| panic!("{e}"));
    let rel = (f.supply_j - full.energy.total.supply_j).abs() / full.energy.total.supply_j;
    assert!(
        rel < 1e-9,
        "{} vs {}",
        f.supply_j,
        full.energy.total.supply_j
    );
    assert_eq!(f.samples, full.timed.traj.len());
}

use printwatt::evaluate::{Evaluated, Reason};
use printwatt::search::optimise::{self, OptimiseOptions};

const YAW90: f64 = std::f64::consts::FRAC_PI_2;

fn one(ev: &Evaluator, at: Placement) -> Evaluated {
    let mut sc = ev.scratch().unwrap();
    ev.evaluate(&mut sc, &at)
}

#[test]
fn unreachable_placement_names_the_sample_line_and_point() {
    let (model, tp) = load("abb_irb6700_200_260", "default.gcode");
    let job = common::default_job(&model, &tp);
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    // The far end of the 2 m path is out of reach at x = 2.0 m, yaw 0.
    let r = one(&ev, Placement::new(2.0, 0.0, 0.0, 0.0));
    assert_eq!(r.cost(), f64::INFINITY);
    let e = r.outcome.unwrap_err();
    assert_eq!(e.reason, Reason::Unreachable);
    assert!(e.sample.unwrap() > 0, "{e}");
    assert!(e.line.is_some() && e.point_m.is_some() && e.t_s.is_some());
    assert!(e.to_string().contains("sample"), "{e}");
}

#[test]
fn wrist_passing_through_zero_with_joint_4_still_is_feasible() {
    let (model, tp) = load("abb_irb6700_200_260", "default.gcode");
    let job = common::default_job(&model, &tp);
    let at = Placement::new(1.7, 0.0, 0.0, YAW90);
    // Reachable and timed (see tests/timing.rs); passes within 2.9° of the wrist singularity
    // (|sin q5| < 0.05) with joints 4 and 6 slow: accepted by the rate rule where passing
    // through is allowed (wrist margin 0; the default margin keeps 5° from it).
    let through = FeasibilityOptions {
        wrist_margin_rad: 0.0,
        ..Default::default()
    };
    let ev = Evaluator::new(&job, through, Objective::Supply);
    let f = one(&ev, at).outcome.unwrap_or_else(|e| panic!("{e}"));
    assert!(f.margins.wrist.unwrap() < 0.05, "{:?}", f.margins);
    let rate = f
        .margins
        .wrist_rate
        .expect("the path comes near the singularity");
    assert!(rate < 0.5, "joint 4/6 use {rate} of their limits");
    // The rule still rejects a wrist that moves fast there: with a strict share the same
    // placement fails as a wrist singularity, naming the joint and where.
    let strict = FeasibilityOptions {
        wrist_rate_max: rate / 2.0,
        ..through
    };
    let ev = Evaluator::new(&job, strict, Objective::Supply);
    let e = one(&ev, at).outcome.unwrap_err();
    assert_eq!(e.reason, Reason::WristSingularity, "{e}");
    assert!(e.sample.is_some() && e.line.is_some());
    assert!(e.detail.contains("joint"), "{e}");
}

#[test]
fn bed_collision_is_reported_with_where() {
    let (model, tp) = load("abb_irb6700_200_260", "default.gcode");
    let job = common::default_job(&model, &tp);
    let at = Placement::new(1.4, 0.0, 0.5, YAW90);
    // Joint 3 comes within 3° of its stop here: no joint-limit margin in this test.
    let no_margin = FeasibilityOptions {
        joint_margin_rad: [0.0; 8],
        ..Default::default()
    };
    let ev = Evaluator::new(&job, no_margin, Objective::Supply);
    assert!(
        one(&ev, at).outcome.is_ok(),
        "feasible with the default bed"
    );
    // A print table reaching 1.5 m beyond the path passes under the robot: its top, 0.52 m
    // above the base-frame origin, cuts the base column.
    let big_bed = FeasibilityOptions {
        bed_margin_m: 1.5,
        ..no_margin
    };
    let ev = Evaluator::new(&job, big_bed, Objective::Supply);
    let e = one(&ev, at).outcome.unwrap_err();
    assert_eq!(e.reason, Reason::CollisionBed, "{e}");
    assert_eq!(e.sample, Some(0));
    // Lower the bed (z too low for that table: 0.52 m → below the base) and the column clears.
    let e2 = one(&ev, Placement::new(1.4, 0.0, -0.3, YAW90)).outcome;
    assert!(
        !matches!(&e2, Err(x) if x.reason == Reason::CollisionBed),
        "{e2:?}"
    );
}

fn small_grid() -> printwatt::search::Grid {
    printwatt::search::Grid {
        xs: vec![1.4, 1.5, 1.6],
        ys: vec![-0.1, 0.0, 0.1],
        zs: vec![0.5],
        yaws: vec![YAW90],
        spins: vec![0.0],
    }
}

#[test]
fn sweep_is_bit_identical_with_one_and_two_threads_and_survives_failures() {
    let (model, tp) = load("abb_irb6700_200_260", "default.gcode");
    let job = common::default_job(&model, &tp);
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let mut ps = small_grid().placements();
    ps.insert(3, Placement::new(5.0, 0.0, 0.0, 0.0)); // unreachable, in the middle
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| ev.sweep(&ps, &|_, _| {})).unwrap()
    };
    let a = run(1);
    let b = run(2);
    assert_eq!(a.len(), ps.len());
    assert!(a[3].outcome.is_err(), "the far placement fails");
    assert!(a.iter().filter(|r| r.outcome.is_ok()).count() >= 4);
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(x.cost().to_bits(), y.cost().to_bits());
        assert_eq!(format!("{x:?}"), format!("{y:?}"));
    }
}

#[test]
fn optimiser_beats_the_grid_is_deterministic_and_reports_sensitivity() {
    let (model, tp) = load("abb_irb6700_200_260", "default.gcode");
    let job = common::default_job(&model, &tp);
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let grid = ev.sweep(&small_grid().placements(), &|_, _| {}).unwrap();
    let best_grid = optimise::best_of(&grid).unwrap().cost();
    let opts = OptimiseOptions {
        max_evals: 40,
        ..Default::default()
    };
    let pool = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let a = pool(1).install(|| optimise::optimise(&ev, &grid, &opts).unwrap());
    let b = pool(2).install(|| optimise::optimise(&ev, &grid, &opts).unwrap());
    assert!(a.best.cost() <= best_grid);
    assert_eq!(a.best.cost().to_bits(), b.best.cost().to_bits());
    assert_eq!(a.best.placement, b.best.placement);
    assert_eq!(a.history_j, b.history_j);
    let s = &a.sensitivity;
    assert_eq!(s.h_m, 0.05);
    assert!(s.e0_j.is_finite());
    for k in 0..4 {
        assert!(
            s.e_j[k].is_some() != s.reasons[k].is_some(),
            "energy or reason at {k}"
        );
    }
    assert!(s.e_j.iter().any(|e| e.is_some()));
}

#[test]
fn cli_sweep_json_and_optimise_end_to_end() {
    // A 3 × 3 grid the default robot reaches on the default path.
    let grid = [
        "--x",
        "1.4:1.6:0.1",
        "--y",
        "-0.1:0.1:0.1",
        "--z",
        "0.5",
        "--yaw",
        "90",
    ];
    let out = common::ok(bin().arg("sweep").args(grid).arg("--json"));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["placements"], 9);
    assert!(v["feasible"].as_u64().unwrap() >= 4);
    assert_eq!(v["rows"].as_array().unwrap().len(), 9);

    let dir = std::env::temp_dir().join(format!("pw-place-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = common::ok(
        bin()
            .arg("optimise")
            .args(grid)
            .args(["--max-evals", "20", "--run", "t", "--results-dir"])
            .arg(&dir),
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("best placement") && stdout.contains("saving"),
        "{stdout}"
    );
    for f in ["summary.json", "placements.csv", "report.html"] {
        assert!(dir.join("t").join(f).is_file(), "{f}");
    }
    // An existing run is not replaced without --force.
    let again = |force: bool| {
        let mut c = bin();
        c.args(common::ONE_CELL_OPTIMISE)
            .args(["--run", "t", "--results-dir"])
            .arg(&dir);
        if force {
            c.arg("--force");
        }
        c.output().unwrap()
    };
    let out = again(false);
    assert!(!out.status.success());
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("--force"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = again(true);
    common::assert_ok(&out);
    // A run directory holding a foreign file is refused, not overwritten, even with --force.
    std::fs::write(dir.join("t").join("notes.txt"), "mine").unwrap();
    let out = again(true);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("notes.txt"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn cli_bad_input_fails_clearly() {
    let out = bin()
        .args(["sweep", "--x", "1:abc:0.1", "--y", "0"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(e.contains("--x") && e.contains("abc"), "{e}");
    let out = bin()
        .args(["sweep", "--robot", "no_such_robot", "--x", "1", "--y", "0"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(e.contains("no_such_robot"), "{e}");
}

#[test]
fn parse_range_values_and_errors() {
    use printwatt::search::parse_range;
    assert_eq!(parse_range("x", "1:1.2:0.1").unwrap().len(), 3);
    assert_eq!(parse_range("x", "0.5").unwrap(), vec![0.5]);
    assert_eq!(parse_range("x", "1,2,3").unwrap(), vec![1.0, 2.0, 3.0]);
    assert!(parse_range("x", "1:0:0.1").is_err());
    assert!(parse_range("x", "1:2:0").is_err());
    assert!(parse_range("x", "1:2").is_err());
}

/// A difference of two nearly equal energies is rounded to the digits the energies carry: the
/// same placement's energy summed in another order (2e-11 J apart out of ~1.3e4 J) saves
/// "no difference", in the library's savings, their JSON and the text, while a real saving
/// keeps its digits.
#[test]
fn savings_between_equal_placements_are_no_difference_not_float_noise() {
    let (model, tp) = load("abb_irb6700_200_260", "default.gcode");
    let job = common::default_job(&model, &tp);
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let at = Placement::new(1.6, 0.0, 0.2, std::f64::consts::FRAC_PI_2);
    let base = one(&ev, at);
    let mut same = base.clone();
    if let Ok(f) = &mut same.outcome {
        f.energy_j += 2e-11;
        f.supply_j += 2e-11;
        f.drives_j -= 3e-12;
    }
    assert_ne!(
        base.feasible().unwrap().supply_j - same.feasible().unwrap().supply_j,
        0.0
    );
    let s = optimise::Savings::of(&same, &base).unwrap();
    for (what, (j, pct)) in [
        ("objective", s.objective),
        ("supply", s.supply),
        ("drives", s.drives),
        ("standby", s.standby),
    ] {
        assert_eq!(
            (j.to_bits(), pct.to_bits()),
            (0, 0),
            "{what}: {j} J {pct} %"
        );
    }
    let json = printwatt::output::json_text(&s).unwrap();
    assert!(!json.contains("e-1"), "{json}");
    assert_eq!(
        printwatt::report::placement::saving_text(s.supply.0, s.supply.1),
        "no difference"
    );
    // A real saving is kept (other placement, other energy).
    let other = one(
        &ev,
        Placement::new(1.5, 0.0, 0.2, std::f64::consts::FRAC_PI_2),
    );
    let s = optimise::Savings::of(&other, &base).unwrap();
    let raw = base.feasible().unwrap().supply_j - other.feasible().unwrap().supply_j;
    assert!(raw.abs() > 1.0, "{raw}");
    assert!((s.supply.0 - raw).abs() <= 1e-4, "{} vs {raw}", s.supply.0);
    assert!(printwatt::report::placement::saving_text(s.supply.0, s.supply.1).ends_with("%)"));
}
