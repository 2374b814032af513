//! Placement: margins, tolerance, objectives, spins, run names, advice.

mod common;
use common::bin;

use printwatt::evaluate::{Evaluator, FeasibilityOptions, Objective};
use printwatt::search::optimise::{OptimiseOptions, Savings};
use printwatt::search::refine::{self, Bounds, SearchOptions};
use printwatt::search::tolerance::{self, Tolerance};
use printwatt::search::Grid;
use printwatt::toolpath::{self, ReadOptions};

const YAW90: f64 = std::f64::consts::FRAC_PI_2;

#[test]
fn optimum_respects_joint_margins_and_holds_its_tolerance() {
    // The default example: joint 3 used to end 0.03° from its stop. The optimum now keeps the
    // 3° margin on every joint and every tolerance corner (±20 mm, ±1°) is feasible.
    let model = common::robot("abb_irb6700_200_260");
    let tp = common::path("default.gcode");
    let job = common::default_job(&model, &tp);
    let feas = FeasibilityOptions::default();
    let ev = Evaluator::new(&job, feas, Objective::Supply);
    let g = Grid {
        xs: vec![1.4, 1.5, 1.6],
        ys: vec![-0.1, 0.1],
        zs: vec![0.4, 0.6],
        yaws: vec![YAW90],
        spins: vec![0.0],
    };
    let ps = g.placements();
    let grid = ev.sweep(&ps, &|_, _| {}).unwrap();
    let tol = Tolerance::default();
    let so = SearchOptions {
        bounds: Bounds {
            x: [1.4, 1.6],
            y: [-0.1, 0.1],
            z: [0.4, 0.6],
        },
        tolerance: tol,
        step_z_m: 0.05,
        z: true,
        max_start_cells: 5,
    };
    let opts = OptimiseOptions {
        max_evals: 16,
        ..Default::default()
    };
    let (res, info) =
        refine::refine(&ev, &grid, &opts, &so, std::sync::Arc::new(|_, _, _| {})).unwrap();
    assert!(res.evals <= 16);
    assert!(info.tolerance.holds, "{:?}", info.tolerance);
    let f = res.best.feasible().unwrap();
    let (j, d) = f.margins.joint_limit_rad.unwrap();
    assert!(
        d >= 3f64.to_radians() - 1e-9,
        "joint {j} {d} rad from a limit"
    );
    // Re-evaluate at the corners independently.
    let corners = ev
        .sweep(&tol.corners(&res.best.placement), &|_, _| {})
        .unwrap();
    assert_eq!(corners.len(), 16);
    for c in &corners {
        let cf = c.feasible().unwrap_or_else(|| panic!("{:?}", c.outcome));
        assert!(cf.margins.joint_limit_rad.unwrap().1 >= 3f64.to_radians() - 1e-9);
    }
    let chk = tolerance::check(&ev, &res.best.placement, &tol).unwrap();
    assert!(chk.holds && chk.corners == 16);
    // Savings are stated for supply and drives; supply = standby + drives.
    let base = &grid[0];
    if let Some(s) = Savings::of(&res.best, base) {
        assert!((s.supply.0 - (s.drives.0 + s.standby.0)).abs() < 1e-6);
    }
    assert!((f.supply_j - (f.standby_j + f.drives_j)).abs() < 1e-6 * f.supply_j);
}

#[test]
fn joint_margin_rejects_a_placement_that_ends_at_a_stop() {
    // x = 1.4 m, z = 0.5 m, yaw 90°: joint 3 reaches 67° against its 70° stop.
    let model = common::robot("abb_irb6700_200_260");
    let tp = common::path("default.gcode");
    let job = common::default_job(&model, &tp);
    let at = printwatt::toolpath::Placement::new(1.4, 0.0, 0.5, YAW90);
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let e = ev.sweep(&[at], &|_, _| {}).unwrap().remove(0);
    let err = e.outcome.unwrap_err();
    assert_eq!(err.reason, printwatt::evaluate::Reason::JointLimitMargin);
    assert!(err.detail.contains("joint 3"), "{err}");
    let none = FeasibilityOptions {
        joint_margin_rad: [0.0; 8],
        ..Default::default()
    };
    let ev = Evaluator::new(&job, none, Objective::Supply);
    let f = ev.sweep(&[at], &|_, _| {}).unwrap().remove(0);
    let (j, d) = f.feasible().unwrap().margins.joint_limit_rad.unwrap();
    assert_eq!(j, 3);
    assert!(d < 3f64.to_radians());
}

#[test]
fn optimum_on_a_search_bound_is_flagged_with_the_bound_named() {
    let b = Bounds {
        x: [1.0, 2.0],
        y: [-0.5, 0.5],
        z: [0.0, 0.5],
    };
    let p = printwatt::toolpath::Placement::new(1.5, 0.0, 0.5, 0.0);
    assert_eq!(b.on_bounds(&p, 0.005), vec!["z max = 0.500 m".to_string()]);
    let inside = printwatt::toolpath::Placement::new(1.5, 0.0, 0.25, 0.0);
    assert!(b.on_bounds(&inside, 0.005).is_empty());
}

#[test]
fn objectives_drives_and_mechanical_positive_are_offered_and_old_names_still_parse() {
    for (n, o) in Objective::ALL {
        assert_eq!(n.parse::<Objective>().unwrap(), o);
        assert_eq!(o.name(), n);
    }
    assert_eq!(
        "mechanical-abs".parse::<Objective>().unwrap(),
        Objective::MechanicalAbs
    );
    let e = "power".parse::<Objective>().unwrap_err().to_string();
    assert!(
        e.contains("mechanical_positive") && e.contains("drives"),
        "{e}"
    );
    assert!(Objective::MechanicalAbs.describe().contains("|τq̇|"));
    assert!(Objective::MechanicalPositive
        .describe()
        .contains("max(τq̇, 0)"));
}

#[test]
fn sweep_set_with_several_spins_evaluates_every_spin() {
    let out = common::ok(bin().args([
        "sweep",
        "--path",
        "paths/seed000_test_path.gcode",
        "--set",
        "paths/placements/p1-p5.csv",
        "--z",
        "0.2",
        "--spin",
        "0,45,90",
        "--json",
    ]));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["placements"], 15);
    let spins: std::collections::BTreeSet<i64> = v["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["placement"]["spin_deg"].as_f64().unwrap().round() as i64)
        .collect();
    assert_eq!(spins.into_iter().collect::<Vec<_>>(), vec![0, 45, 90]);
}

#[test]
fn optimise_without_run_writes_a_new_named_run_and_never_replaces_one() {
    let dir = std::env::temp_dir().join(format!("pw-runs-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let go = || {
        common::ok(
            bin()
                .args(common::ONE_CELL_OPTIMISE)
                .args(["--tolerance", "0,0", "--results-dir"])
                .arg(&dir),
        );
    };
    go();
    go();
    let names: Vec<String> = std::fs::read_dir(dir.join("runs"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
    for n in &names {
        assert!(
            n.starts_with("optimise-abb_irb6700_200_260-default-"),
            "{n}"
        );
    }
    assert_ne!(names[0], names[1]);
    assert!(!dir.join("optimise-default").exists());
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(
        printwatt::output::utc_stamp(1_795_000_000),
        "20261118T110640Z"
    );
}

#[test]
fn urdf_without_nozzle_gets_counts_per_reason_and_the_no_tool_offset_hint() {
    let out = bin()
        .args([
            "optimise",
            "--robot",
            "robots/abb_irb6700_200_260/robot.urdf",
            "--x",
            "5,6",
            "--y",
            "0",
            "--no-report",
        ])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(e.contains("no feasible placement among 2"), "{e}");
    assert!(e.contains("2 unreachable"), "{e}");
    assert!(
        e.contains("no tool offset: the flange is the nozzle"),
        "{e}"
    );
}

/// The robot and path the export tests export.
fn export_case() -> (printwatt::robot::RobotModel, printwatt::toolpath::Toolpath) {
    (
        common::robot("abb_irb6700_200_260"),
        common::path("default.gcode"),
    )
}

/// The placement the export tests put the nozzle at: off the axes, with yaw and nozzle spin.
fn export_at() -> printwatt::toolpath::Placement {
    printwatt::toolpath::Placement::new(1.55, 0.05, 0.45, 100f64.to_radians())
        .with_spin(10f64.to_radians())
}

#[test]
fn exported_wobjdata_and_frame_put_the_nozzle_where_the_placement_says() {
    use printwatt::export;
    let (model, tp) = export_case();
    let job = common::default_job(&model, &tp);
    let at = export_at();
    let pe = job.evaluate(&at).unwrap().unwrap();
    // Read the numbers back from the RAPID text: [[x, y, z], [q1, q2, q3, q4]] in mm.
    let w = export::wobjdata("wobjPrint", &at);
    let inner = &w[w.find("[[").unwrap() + 2..];
    let nums: Vec<f64> = inner[..inner.find("]]").unwrap()]
        .split([',', '[', ']'])
        .filter_map(|t| t.trim().parse().ok())
        .collect();
    assert_eq!(nums.len(), 7, "{w}");
    let t = nalgebra::Vector3::new(nums[0], nums[1], nums[2]) / 1000.0;
    let q = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
        nums[3], nums[4], nums[5], nums[6],
    ));
    // The COMPAS frame says the same.
    let f = export::compas_frame(&at);
    let xa = &f["data"]["xaxis"];
    let xaxis = nalgebra::Vector3::new(
        xa[0].as_f64().unwrap(),
        xa[1].as_f64().unwrap(),
        xa[2].as_f64().unwrap(),
    );
    assert!((q * nalgebra::Vector3::x() - xaxis).norm() < 1e-9);
    // FK of the timed joint trajectory puts the nozzle tip at wobj ∘ part-frame point.
    let traj = &pe.timed.traj;
    let motion = &pe.timed.motion;
    let mut worst: f64 = 0.0;
    for k in (0..traj.len()).step_by(50) {
        let tip = printwatt::kinematics::fk::tool_pose(&model, traj.q(k)).pos;
        let want = q * motion.p[k] + t;
        worst = worst.max((tip - want).norm());
    }
    assert!(
        worst < 1e-3,
        "nozzle {worst} m from where the wobjdata puts it"
    );
}

#[test]
fn an_optimum_on_the_joint_limit_margin_is_flagged_and_the_margin_stated() {
    use printwatt::evaluate::feasibility::margins::margin_statement;
    use printwatt::evaluate::feasibility::Margins;
    let model = common::robot("abb_irb6700_200_260");
    let o = FeasibilityOptions::default();
    let margin = 3f64.to_radians();
    // Joint 3 exactly on its 3° margin (67.00° against its 70° stop): flagged.
    let on = Margins {
        joint_limit_rad: Some((3, margin)),
        ..Default::default()
    };
    let (text, flagged) = margin_statement(&model, &o, &on).unwrap();
    assert!(flagged, "{text}");
    assert!(
        text.contains("joint 3 keeps 3.00°") && text.contains("margin 3.00°"),
        "{text}"
    );
    // 1° further away: stated, not flagged.
    let off = Margins {
        joint_limit_rad: Some((3, margin + 1f64.to_radians())),
        ..Default::default()
    };
    let (text, flagged) = margin_statement(&model, &o, &off).unwrap();
    assert!(!flagged && text.contains("4.00°"), "{text}");
}

#[test]
fn exported_base_frame_path_puts_the_nozzle_where_the_placement_says() {
    use printwatt::export;
    use printwatt::kinematics::{nozzle_target, IkSolver};
    let (model, tp) = export_case();
    let job = common::default_job(&model, &tp);
    let at = export_at();
    let pts = export::base_frame_path(&job.moves, &at);
    assert!(pts.len() > job.moves.len());
    // Read the coordinates back from both files (mm).
    let nums = |line: &str, open: &str, close: &str| -> Vec<f64> {
        let i = line.find(open).unwrap() + open.len();
        line[i..i + line[i..].find(close).unwrap()]
            .split([',', '[', ']'])
            .filter_map(|t| t.trim().parse().ok())
            .collect()
    };
    let g = export::gcode_base(&pts, &at, model.name());
    let from_g: Vec<[f64; 3]> = g
        .lines()
        .filter(|l| l.starts_with("G0 ") || l.starts_with("G1 "))
        .map(|l| {
            let w: Vec<f64> = l
                .split_whitespace()
                .filter(|t| t.starts_with(['X', 'Y', 'Z']))
                .map(|t| t[1..].parse::<f64>().unwrap() / 1000.0)
                .collect();
            [w[0], w[1], w[2]]
        })
        .collect();
    let r = export::rapid_base(&pts, &at, &model);
    let from_r: Vec<Vec<f64>> = r
        .lines()
        .filter(|l| l.trim_start().starts_with("MoveL"))
        .map(|l| nums(l, "[[", "]]"))
        .collect();
    assert_eq!(from_g.len(), pts.len());
    assert_eq!(from_r.len(), pts.len());
    // FK of the IK solution at the placement: the nozzle is at the exported point, pointing
    // where the RAPID quaternion says.
    let solver = IkSolver::new(&model).unwrap();
    let frame = at.frame();
    let mut checked = 0;
    let mut k = 0;
    for m in &job.moves {
        let n = 3;
        for i in 0..n {
            let s = m.prim.length() * i as f64 / n as f64;
            let want = frame.apply(&m.prim.point(s));
            let target = nozzle_target(&want, at.nozzle_yaw());
            let Ok(sols) = solver.solve_all(&target) else {
                continue;
            };
            for sol in sols {
                let t = printwatt::kinematics::fk::tool_pose(&model, &sol.q);
                assert!((t.pos - want).norm() < 1e-6);
                checked += 1;
            }
        }
        k += 1;
    }
    assert!(
        checked > 50 && k == job.moves.len(),
        "{checked} IK solutions checked"
    );
    // Every exported point is FK of an IK solution at that point, to the file's rounding.
    let q_rapid = {
        let v = &from_r[0];
        nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(v[3], v[4], v[5], v[6]))
    };
    for (i, b) in pts.iter().enumerate().step_by(5) {
        let target = nozzle_target(&b.p, at.nozzle_yaw());
        let sol = &solver.solve_all(&target).unwrap()[0];
        let t = printwatt::kinematics::fk::tool_pose(&model, &sol.q);
        let g = nalgebra::Vector3::new(from_g[i][0], from_g[i][1], from_g[i][2]);
        let rp = nalgebra::Vector3::new(from_r[i][0], from_r[i][1], from_r[i][2]) / 1000.0;
        assert!((t.pos - g).norm() < 1e-6, "G-code point {i}");
        assert!((t.pos - rp).norm() < 1e-6, "RAPID point {i}");
        let rot = nalgebra::UnitQuaternion::from_rotation_matrix(
            &nalgebra::Rotation3::from_matrix_unchecked(t.rot),
        );
        assert!(rot.angle_to(&q_rapid) < 1e-6, "RAPID orientation at {i}");
    }
    // The G-code reads back as the same path.
    let dir = std::env::temp_dir().join(format!("pw_export_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("path_base.gcode");
    std::fs::write(&f, &g).unwrap();
    let back = toolpath::load(&f, &ReadOptions::default()).unwrap();
    let ends: Vec<_> = back.moves.iter().map(|m| m.end).collect();
    assert_eq!(ends.len() + 1, pts.len());
    for (e, b) in ends.iter().zip(&pts[1..]) {
        assert!((e - b.p).norm() < 1e-6);
    }
    std::fs::remove_dir_all(&dir).ok();
}
