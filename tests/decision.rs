//! A placement a site can act on: the robust choice over plausible robots, the value of
//! measuring each uncertain parameter, the excitation experiment designed for the decision,
//! and the measurement loop closed on a hidden balancer.

mod common;
use common::root;

use printwatt::evaluate::{Evaluator, FeasibilityOptions, Objective};
use printwatt::frame::Placement;
use printwatt::identify::excite::{self, ExciteOptions};
use printwatt::search::job::RobustObjective;
use printwatt::search::optimise::OptimiseOptions;
use printwatt::search::refine::{self, Bounds, SearchOptions};
use printwatt::search::robust::{self, RobustOptions};
use printwatt::search::tolerance::Tolerance;
use printwatt::search::uncertainty::Ranges;
use printwatt::search::value_of_information;

fn quiet() -> refine::Progress {
    std::sync::Arc::new(|_, _, _| {})
}

fn at(x: f64, y: f64, z: f64) -> Placement {
    Placement {
        x,
        y,
        z,
        yaw: 0.0,
        nozzle_spin: 0.0,
    }
}

#[test]
fn robust_choice_beats_the_nominal_answers_expected_energy_and_states_within_1pct_of_the_drives_energy(
) {
    // The IRB 6700 on the short test path, the "answer" a feasible cell off the nominal
    // optimum, the balancer uncertain (present or not, ±50 %) and standby ±50 %: the robust
    // choice is another candidate with a lower expected energy, and "within 1 %" is counted
    // against each draw's best drives' energy, never the supply (standby excluded).
    let model = common::robot("abb_irb6700_200_260");
    let tp = common::path("seed000_test_path.gcode");
    let job = common::default_job(&model, &tp);
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let ps = [at(1.6, -0.3, 0.0), at(2.2, 0.3, 0.4)];
    let start = ev
        .sweep(&[at(1.9, 0.0, 0.2)], &|_, _| {})
        .unwrap()
        .remove(0);
    assert!(
        start.cost().is_finite(),
        "{:?}",
        start.outcome.as_ref().err()
    );
    let so = SearchOptions::new(Bounds::over(&ps, None).unwrap(), Tolerance::default());
    let ranges = Ranges {
        balancer_absent_probability: 0.3,
        balancer_force_rel: 0.5,
        standby_power_rel: 0.5,
        ..common::zero_ranges()
    };
    let o = RobustOptions {
        draws: 12,
        seed: 3,
        ranges: Some(ranges),
        draw_optima: false,
        ..Default::default()
    };
    let r = robust::robust(&ev, &start, &OptimiseOptions::default(), &so, &o).unwrap();
    let (rec, nom) = (r.recommendation(), r.nominal());
    assert_ne!(r.recommended, 0, "{:#?}", r.candidates);
    assert!(
        rec.expected_j < nom.expected_j,
        "robust {} J, nominal {} J",
        rec.expected_j,
        nom.expected_j
    );
    assert!(rec.expected_regret_j <= nom.expected_regret_j);
    // Within 1 %: recounted from the energies and each draw's best drives' energy.
    for (c, cand) in r.candidates.iter().enumerate() {
        let within = (0..r.draws)
            .filter(|&d| {
                let best = r.energy_j[d].iter().copied().fold(f64::INFINITY, f64::min);
                r.energy_j[d][c] - best <= 0.01 * r.best_drives_j[d]
            })
            .count();
        assert_eq!(cand.p_within_1pct, within as f64 / r.draws as f64, "{c}");
    }
    // The drives' energy is what a placement changes; the standby is a large share of the
    // supply and is reported apart.
    assert!(r.drives_j > 0.0 && r.standby_j > 0.0);
    assert!(r
        .best_drives_j
        .iter()
        .zip(&r.energy_j)
        .all(|(d, e)| *d < e.iter().copied().fold(f64::INFINITY, f64::min)));
    // The worst-case criterion picks a candidate whose largest regret is the smallest.
    let w = robust::robust(
        &ev,
        &start,
        &OptimiseOptions::default(),
        &so,
        &RobustOptions {
            criterion: RobustObjective::Regret,
            ..o
        },
    )
    .unwrap();
    let min_max = w
        .candidates
        .iter()
        .map(|c| c.max_regret_j)
        .fold(f64::INFINITY, f64::min);
    assert!(w.recommendation().max_regret_j <= min_max + 1e-9 || w.tolerance_checked > 1);
    // Knowing one parameter is worth no more than knowing every one.
    assert!(r
        .value_of_information
        .iter()
        .all(|v| v.value_j >= 0.0 && v.value_j <= r.value_of_everything_j + 1e-9));
    assert!(!robust::lines(&r).is_empty());
}

#[test]
fn value_of_measuring_a_parameter_that_does_not_move_the_decision_is_about_zero() {
    // Two candidates: A is cheaper when the balancer is strong, B when it is weak; standby
    // shifts both alike. Knowing the balancer is worth the regret it removes; knowing the
    // standby is worth ~0.
    let n = 400;
    let mut r = common::xorshift(9);
    let (mut drawn, mut energy) = (Vec::new(), Vec::new());
    for _ in 0..n {
        let bal = 0.5 + r(); // 0.5 … 1.5
        let sb = 0.7 + 0.6 * r();
        let base = 10_000.0 * sb;
        // A: 12 000 − 1000·(bal − 1); B: 12 000 + 1000·(bal − 1), plus noise.
        let a = base + 12_000.0 - 1000.0 * (bal - 1.0) + 20.0 * (r() - 0.5);
        let b = base + 12_000.0 + 1000.0 * (bal - 1.0) + 20.0 * (r() - 0.5);
        drawn.push(vec![bal, sb]);
        energy.push(vec![a, b]);
    }
    let names = vec!["balancer force".to_string(), "standby power".to_string()];
    // The recommendation by expected energy (they nearly tie in expectation).
    let mean = |c: usize| energy.iter().map(|e| e[c]).sum::<f64>() / n as f64;
    let rec = if mean(0) <= mean(1) { 0 } else { 1 };
    let v = value_of_information::rank(&names, &drawn, &energy, rec, rec, 1000.0);
    let get = |k: &str| v.iter().find(|p| p.name == k).unwrap();
    let (bal, sb) = (get("balancer force"), get("standby power"));
    // With the balancer known: regret 2000·|bal − 1| on the side where the recommendation
    // loses, i.e. 2000·E[(1−bal)+] = 2000 · 0.125 = 250 J (within the sampling error).
    assert!((bal.value_j - 250.0).abs() < 60.0, "{bal:?}");
    assert!(sb.value_j < 0.02 * bal.value_j, "{sb:?}");
    assert_eq!(v[0].name, "balancer force");
    assert!((bal.value_kwh_per_year - bal.value_j * 1000.0 / 3.6e6).abs() < 1e-12);
}

#[test]
fn excitation_stays_within_every_limit_and_improves_the_targeted_condition_number_over_a_sine_sweep(
) {
    let model = common::robot("abb_irb6700_200_260");
    let o = ExciteOptions {
        tries: 40,
        rate_hz: 100.0,
        ..Default::default()
    };
    let e = excite::design(&model, &o).unwrap();
    let lim = &e.limits;
    for j in 0..model.dof() {
        assert!(
            lim.position[j] <= o.limit_share + 1e-9,
            "joint {} position {}",
            j + 1,
            lim.position[j]
        );
        assert!(
            lim.speed[j] <= o.limit_share + 1e-9,
            "joint {} speed {}",
            j + 1,
            lim.speed[j]
        );
        assert!(
            lim.acceleration[j] <= o.limit_share + 1e-9,
            "joint {} acceleration {}",
            j + 1,
            lim.acceleration[j]
        );
        let jt = &model.joints[j];
        for k in 0..e.trajectory.len() {
            let q = e.trajectory.q(k)[j];
            assert!(q >= jt.lower && q <= jt.upper, "joint {} at {q} rad", j + 1);
        }
    }
    assert!(lim.lowest_z_m >= o.floor_z_m - 1e-9, "{}", lim.lowest_z_m);
    // At rest at both ends.
    let last = e.trajectory.len() - 1;
    for k in [0, last] {
        assert!(e.trajectory.qd(k).iter().all(|v| v.abs() < 1e-9));
    }
    // The measured improvement over the naive sine sweep (the README states it).
    let factor = e.naive_condition / e.condition;
    eprintln!(
        "excite: condition {:.3e} vs naive {:.3e} ({factor:.1}×), log-det {:.2} vs {:.2}",
        e.condition, e.naive_condition, e.log_det, e.naive_log_det
    );
    assert!(
        factor >= 2.0,
        "only {factor:.2}× better than the sine sweep"
    );
    assert!(e.log_det > e.naive_log_det);
    // The CSV is the trajectory format `simulate` reads.
    let d = std::env::temp_dir().join(format!("printwatt-excite-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let f = d.join("excite.csv");
    std::fs::write(&f, excite::csv(&e.trajectory)).unwrap();
    let (back, sup) = printwatt::trajectory::read_csv_for(&f, &model).unwrap();
    assert!(sup.velocities && sup.accelerations);
    assert_eq!(back.len(), e.trajectory.len());
    let rapid = excite::rapid(&e.trajectory, model.name(), 25.0, 100.0);
    assert!(
        rapid.starts_with("MODULE")
            && rapid.contains("MoveAbsJ")
            && rapid.trim_end().ends_with("ENDMODULE")
    );
    let ur = excite::urscript(&e.trajectory, model.name(), 25.0, 100.0);
    assert!(ur.contains("servoj(") && ur.contains("def printwatt_excite"));
    let _ = std::fs::remove_dir_all(&d);
}

/// The refinement's answer for `model` on the test path from one grid of cells.
fn answer(model: &printwatt::robot::RobotModel) -> (Placement, f64, f64) {
    let tp = common::path("seed000_test_path.gcode");
    let job = common::default_job(model, &tp);
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let g = printwatt::search::Grid {
        xs: vec![1.6, 1.9, 2.2],
        ys: vec![-0.3, 0.0, 0.3],
        zs: vec![0.0, 0.4],
        yaws: vec![0.0],
        spins: vec![0.0],
    };
    let ps = g.placements();
    let rows = ev.sweep(&ps, &|_, _| {}).unwrap();
    let so = SearchOptions::new(Bounds::over(&ps, None).unwrap(), Tolerance::default());
    let opts = OptimiseOptions {
        max_evals: 80,
        spin: false,
        ..Default::default()
    };
    let (r, _) = refine::refine(&ev, &rows, &opts, &so, quiet()).unwrap();
    let f = r.best.feasible().unwrap();
    (r.best.placement, f.energy_j, f.drives_j)
}

/// Energy of `model` at `p` on the test path, J.
fn energy_at(model: &printwatt::robot::RobotModel, p: &Placement) -> f64 {
    let tp = common::path("seed000_test_path.gcode");
    let job = common::default_job(model, &tp);
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    ev.sweep(&[*p], &|_, _| {}).unwrap()[0].cost()
}

#[test]
fn closed_loop_on_a_hidden_stronger_balancer_recovers_the_true_robots_optimum() {
    // The true robot's balancer is 60 % stronger than the drive file's estimate.
    let nominal = common::robot("abb_irb6700_200_260");
    let mut truth = nominal.clone();
    let t = &mut truth.effects.table;
    let (f0, k0) = (
        t.balancer_preload_n.unwrap(),
        t.balancer_stiffness_n_per_m.unwrap(),
    );
    t.balancer_preload_n = Some(1.6 * f0);
    t.balancer_stiffness_n_per_m = Some(1.6 * k0);
    let (p_true, e_true, drives_true) = answer(&truth);
    let (p_nom, _, _) = answer(&nominal);
    let regret_before = energy_at(&truth, &p_nom) - e_true;
    // The experiment designed for the balancer, simulated on the true robot, identified.
    let e = excite::design(
        &nominal,
        &ExciteOptions {
            tries: 30,
            rate_hz: 100.0,
            ..Default::default()
        },
    )
    .unwrap();
    let mut tm = printwatt::identify::Model::new(&nominal).unwrap();
    let hidden =
        printwatt::identify::simulate::parse_hidden(&format!("balancer={}:{}", 0.6 * f0, 0.6 * k0))
            .unwrap();
    printwatt::identify::simulate::apply_hidden(&mut tm, &hidden).unwrap();
    let log = printwatt::identify::simulate::simulate_log(
        &tm,
        &e.trajectory,
        &printwatt::identify::simulate::SensorOptions {
            kind: printwatt::identify::SignalKind::Torque,
            noise: 2.0,
            noise_q: 0.0,
            current_quantum: 0.0,
            seed: 5,
        },
        &[],
    )
    .unwrap();
    let d = std::env::temp_dir().join(format!("printwatt-loop-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(d.join("log.csv"), log).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .args([
            "identify",
            "--robot",
            "abb_irb6700_200_260",
            "--log",
            &d.join("log.csv").display().to_string(),
            "--effects",
            "balancer",
            "--out",
            &d.join("id").display().to_string(),
        ])
        .current_dir(root())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let cal = printwatt::robot::load(&d.join("id/abb_irb6700_200_260.calibrated.toml")).unwrap();
    // The calibrated robot carries the fit's covariance: F0 and k, fitted together, with
    // their correlation (a symmetric matrix with a unit diagonal).
    let c = cal.effects.calibration.as_ref().unwrap();
    let round = c.rounds.last().unwrap();
    assert_eq!(round.correlated, ["balancer.F0", "balancer.k"]);
    let m = &round.correlation;
    assert!(
        m[0][0] == 1.0 && m[1][1] == 1.0 && m[0][1] == m[1][0],
        "{m:?}"
    );
    assert!(m[0][1].abs() > 0.3, "F0 and k fitted together: {m:?}");
    let (p_cal, _, _) = answer(&cal);
    let regret_after = energy_at(&truth, &p_cal) - e_true;
    eprintln!(
        "closed loop: true optimum {p_true:?} {e_true:.1} J (drives {drives_true:.1} J); nominal answer {p_nom:?} regret {regret_before:.1} J; calibrated answer {p_cal:?} regret {regret_after:.1} J"
    );
    assert!(
        regret_after < 0.01 * drives_true,
        "regret after {regret_after} J"
    );
    assert!(regret_before > regret_after);
    // The decision with the calibrated robot states the regret before the measurement (the
    // robot it was calibrated from, over its estimate ranges) and after it (the identified
    // covariance): the measurement removed most of it.
    let tp_file = root().join("paths/seed000_test_path.gcode");
    let tp = common::path("seed000_test_path.gcode");
    let mut cfg = printwatt::search::job::OptimiseConfig::new(cal.clone(), tp, &tp_file);
    cfg.placements = Some(printwatt::search::job::PlacementSet::grid(
        printwatt::search::Grid {
            xs: vec![1.6, 1.9, 2.2],
            ys: vec![-0.3, 0.0, 0.3],
            zs: vec![0.0, 0.4],
            yaws: vec![0.0],
            spins: vec![0.0],
        },
    ));
    cfg.settings.uncertainty = Some(6);
    cfg.settings.max_evals = 60;
    let out = printwatt::search::run(&cfg, &printwatt::search::run::Silent).unwrap();
    let w = out
        .report
        .optimise
        .as_ref()
        .and_then(|o| o.decision.as_ref())
        .and_then(|d| d.measurement.clone())
        .expect("a calibrated robot's decision states what the measurement did");
    eprintln!("{w}");
    assert_eq!(w.base_robot, "abb_irb6700_200_260");
    // The report states the decision and draws the regret of each candidate.
    let html = out.report.html();
    assert!(html.contains("<h2>Decision</h2>") && html.contains("measurement"));
    let fig = html
        .split("<figure id=\"regret\">")
        .nth(1)
        .expect("the report draws the regret per candidate");
    let n: usize = fig
        .split("data-n=\"")
        .nth(1)
        .and_then(|t| t.split('"').next())
        .and_then(|t| t.parse().ok())
        .unwrap();
    assert!(n >= 2, "regret chart with {n} data items");
    let before = w.before.expect("the base robot is a shipped one");
    assert!(
        w.after.expected_regret_j < 0.5 * before.expected_regret_j,
        "{w}"
    );
    let tol = Tolerance::default();
    assert!(
        (p_cal.x - p_true.x).abs() <= tol.xy_m + 1e-9
            && (p_cal.y - p_true.y).abs() <= tol.xy_m + 1e-9
            && (p_cal.z - p_true.z).abs() <= tol.z_m + 1e-9
            && (p_cal.yaw - p_true.yaw).abs() <= tol.yaw_rad + 1e-9,
        "{p_cal:?} vs {p_true:?}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// Sample correlation of two series.
fn corr(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f64 = a.iter().map(|x| (x - ma).powi(2)).sum();
    let vb: f64 = b.iter().map(|y| (y - mb).powi(2)).sum();
    cov / (va * vb).sqrt()
}

#[test]
fn a_calibrated_robots_draws_follow_the_correlation_its_fit_found() {
    use printwatt::robot::drive::{CalibratedParam, Calibration, CalibrationRound};
    let mut cal = common::robot("abb_irb6700_200_260");
    let f0 = cal.effects.table.balancer_preload_n.unwrap();
    let k = cal.effects.table.balancer_stiffness_n_per_m.unwrap();
    let fv = cal.drive.as_ref().unwrap().joints[1].viscous;
    let param = |effect: &str, name: &str, value: f64, se: f64| CalibratedParam {
        effect: effect.into(),
        name: name.into(),
        unit: String::new(),
        value,
        std_error: Some(se),
        prior: value,
        round: 1,
        status: "fitted".into(),
    };
    let with = |rho: f64| Calibration {
        base_robot: "abb_irb6700_200_260".into(),
        rounds: vec![CalibrationRound {
            round: 1,
            correlated: vec![
                "balancer.F0".into(),
                "balancer.k".into(),
                "viscous.f_v[2]".into(),
            ],
            correlation: vec![
                vec![1.0, 0.0, rho],
                vec![0.0, 1.0, 0.0],
                vec![rho, 0.0, 1.0],
            ],
            ..Default::default()
        }],
        params: vec![
            param("balancer", "F0", f0, 0.05 * f0.abs()),
            param("balancer", "k", k, 0.05 * k.abs()),
            param("viscous", "f_v[2]", fv, 0.05 * fv),
        ],
    };
    for rho in [-0.9, 0.0, 0.8] {
        cal.effects.calibration = Some(with(rho));
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for d in 0..400 {
            let (m, drawn) =
                printwatt::search::uncertainty::drawn_robot(&cal, &Ranges::default(), 7, d);
            a.push(m.effects.table.balancer_preload_n.unwrap());
            b.push(
                drawn
                    .iter()
                    .find(|(n, _)| n == "viscous friction joint 2")
                    .unwrap()
                    .1,
            );
        }
        let r = corr(&a, &b);
        eprintln!("stated correlation {rho}: drawn {r:.3}");
        assert!((r - rho).abs() < 0.1, "stated {rho}, drawn {r}");
    }
}

#[test]
fn a_study_case_run_with_uncertainty_reports_its_robust_choice() {
    let d = std::env::temp_dir().join(format!("printwatt-study-robust-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    std::fs::copy(
        root().join("paths/seed000_test_path.gcode"),
        d.join("part.gcode"),
    )
    .unwrap();
    std::fs::write(
        d.join("study.toml"),
        "[study]\nname = \"robust\"\noptions = [\"--max-evals\", \"30\", \"--uncertainty\", \"4\"]\n\n[[robot]]\nname = \"irb6700\"\nrobot = \"abb_irb6700_200_260\"\n\n[[cell]]\nname = \"front\"\nx = \"1.6:2.2:0.3\"\ny = \"-0.3:0.3:0.3\"\nz = \"0,0.4\"\nyaw = 0\n\n[[path]]\nname = \"part\"\nfile = \"part.gcode\"\n",
    )
    .unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .args(["study", "study.toml", "--out", "run"])
        .current_dir(&d)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(d.join("run/study.csv")).unwrap();
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    // The note (last column) is free text, quoted when it holds a comma.
    let row: Vec<&str> = lines.next().unwrap().splitn(head.len(), ',').collect();
    assert_eq!(head.len(), row.len(), "{csv}");
    let col = |name: &str| {
        let i = head.iter().position(|h| *h == name).unwrap();
        row[i]
            .parse::<f64>()
            .unwrap_or_else(|_| panic!("{name}: {csv}"))
    };
    let (rec, nom) = (
        col("robust_expected_regret_j"),
        col("nominal_expected_regret_j"),
    );
    assert!(rec >= 0.0 && rec <= nom + 1e-9, "{rec} vs {nom}");
    assert!((0.0..=1.0).contains(&col("robust_p_within_1pct")));
    let x = col("robust_x_m");
    assert!((1.0..=2.5).contains(&x), "{x}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("run/summary.json")).unwrap())
            .unwrap();
    let r = &s["cases"][0]["robust"];
    // summary.json rounds to 9 significant digits.
    let j = r["expected_regret_j"]
        .as_f64()
        .expect("robust fields in summary.json");
    assert!((j - rec).abs() <= 1e-6 * rec.abs().max(1.0), "{j} vs {rec}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn pareto_option_times_the_answer_at_each_acceleration_and_marks_the_front() {
    let tp_file = root().join("paths/seed000_test_path.gcode");
    let mut cfg = printwatt::search::job::OptimiseConfig::new(
        common::robot("abb_irb6700_200_260"),
        common::path("seed000_test_path.gcode"),
        &tp_file,
    );
    cfg.placements = Some(printwatt::search::job::PlacementSet::grid(
        printwatt::search::Grid {
            xs: vec![1.6, 1.9],
            ys: vec![-0.3, 0.0, 0.3],
            zs: vec![0.0, 0.4],
            yaws: vec![0.0],
            spins: vec![0.0],
        },
    ));
    cfg.settings.max_evals = 20;
    cfg.settings.pareto = true;
    let out = printwatt::search::run(&cfg, &printwatt::search::run::Silent).unwrap();
    let o = out.report.optimise.as_ref().unwrap();
    let best = out.report.best().unwrap().feasible().unwrap().clone();
    let ps = &o
        .decision
        .as_ref()
        .expect("a decision with --pareto")
        .pareto;
    let scales: Vec<f64> = ps.iter().map(|p| p.scale).collect();
    assert_eq!(scales, printwatt::search::pareto::SCALES);
    for p in ps {
        eprintln!(
            "{}",
            printwatt::search::pareto::lines(std::slice::from_ref(p))[0]
        );
    }
    // The configured timing (×1) is the answer itself.
    let one = ps.iter().find(|p| p.scale == 1.0).unwrap();
    assert!((one.energy_j.unwrap() - best.energy_j).abs() <= 1e-9 * best.energy_j);
    assert!((one.duration_s.unwrap() - best.duration_s).abs() <= 1e-9);
    // Higher limits never make the print slower here, and the front is what no other beats.
    let feas: Vec<_> = ps.iter().filter(|p| p.duration_s.is_some()).collect();
    for w in feas.windows(2) {
        assert!(w[1].duration_s.unwrap() <= w[0].duration_s.unwrap() + 1e-9);
    }
    assert!(feas.iter().any(|p| p.pareto));
    for p in &feas {
        let (t, e) = (p.duration_s.unwrap(), p.energy_j.unwrap());
        let beaten = feas.iter().any(|q| {
            let (tq, eq) = (q.duration_s.unwrap(), q.energy_j.unwrap());
            tq <= t && eq <= e && (tq < t || eq < e)
        });
        assert_eq!(p.pareto, !beaten, "{p:?}");
    }
    let html = out.report.html();
    assert!(html.contains("<figure id=\"pareto\">"));
}
