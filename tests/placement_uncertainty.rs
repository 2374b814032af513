//! How much to trust the answer (`optimise --uncertainty N`).

mod common;
use common::root;

use printwatt::evaluate::{Evaluator, FeasibilityOptions, Objective};
use printwatt::robot;
use printwatt::search::uncertainty::{self, Ranges};
use printwatt::search::Grid;

/// Run the CLI from the repository root; its stdout. Panics (with stderr) on failure.
fn run_cli(args: &[&str]) -> String {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .args(args)
        .current_dir(root())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The loop on the IRB 4600 in `dir` (made afresh): a simulated 20 s exciting log of `signal`
/// at 100 Hz with `hidden` effects and `noise`, identified with `effects`. The calibrated
/// robot's file and the log's path.
fn calibrate(
    dir: &std::path::Path,
    signal: &str,
    hidden: &str,
    noise: &str,
    effects: &str,
) -> (std::path::PathBuf, String) {
    let _ = std::fs::remove_dir_all(dir);
    std::fs::create_dir_all(dir).unwrap();
    let ds = dir.display().to_string();
    run_cli(&[
        "simulate",
        "--robot",
        "abb_irb4600_40_255",
        "--excite",
        "20",
        "--signal",
        signal,
        "--hidden",
        hidden,
        "--noise",
        noise,
        "--rate",
        "100",
        "--seed",
        "5",
        "--out",
        &ds,
    ]);
    let log = dir.join("log.csv").display().to_string();
    let id = dir.join("id").display().to_string();
    run_cli(&[
        "identify",
        "--robot",
        "abb_irb4600_40_255",
        "--log",
        &log,
        "--effects",
        effects,
        "--out",
        &id,
    ]);
    (dir.join("id/abb_irb4600_40_255.calibrated.toml"), log)
}

fn pool(n: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .unwrap()
}

#[test]
fn uncertainty_study_is_deterministic_for_a_seed_and_thread_count() {
    let model = common::robot("abb_irb4600_40_255");
    let tp = common::path("seed000_test_path.gcode");
    let job = common::default_job(&model, &tp);
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let g = Grid {
        xs: vec![1.0, 1.2, 1.4],
        ys: vec![-0.3, 0.0, 0.3],
        zs: vec![0.0],
        yaws: vec![0.0],
        spins: vec![0.0],
    };
    let rows = ev.sweep(&g.placements(), &|_, _| {}).unwrap();
    let feasible: Vec<_> = rows
        .iter()
        .filter(|r| r.cost().is_finite())
        .cloned()
        .collect();
    assert!(feasible.len() >= 4, "{} feasible", feasible.len());
    let base = feasible.last().unwrap().clone();
    let run = |threads: usize, seed: u64| {
        pool(threads)
            .install(|| uncertainty::study(&job, &ev, &feasible, Some(&base), 8, seed).unwrap())
    };
    let a = run(1, 7);
    let b = run(2, 7);
    // Bitwise identical for 1 and 2 threads.
    assert_eq!(
        serde_json::to_string(&a).unwrap(),
        serde_json::to_string(&b).unwrap()
    );
    for (x, y) in a.per_draw_j.iter().zip(&b.per_draw_j) {
        assert_eq!(x[0].to_bits(), y[0].to_bits());
    }
    // The shipped [uncertainty] table is used, and a different seed draws other robots.
    assert!(matches!(a.source, uncertainty::Source::DriveFile(ref f) if f.ends_with("drive.toml")));
    let c = run(2, 8);
    assert_ne!(a.per_draw_j, c.per_draw_j);
    assert!(a.p_within_1pct >= 0.0 && a.p_within_1pct <= 1.0);
    assert!(a.rank_correlation[1] <= a.rank_correlation[0]);
    assert!(!a.depends_on.is_empty());
    // With every range zero, each draw is the nominal robot: the candidates' energies are
    // exactly the nominal ones and the best candidate is the best in every draw.
    let zero = common::zero_ranges();
    let mut ranked = feasible.clone();
    ranked.sort_by(|x, y| x.cost().total_cmp(&y.cost()));
    let z = uncertainty::study_with(&job, &ev, &ranked, Some(&base), 3, 1, Some(zero)).unwrap();
    assert_eq!(z.p_best, 1.0);
    assert_eq!(z.p_within_1pct, 1.0);
    assert_eq!(z.rank_correlation, [1.0, 1.0]);
    for d in &z.per_draw_j {
        assert_eq!(d[0].to_bits(), ranked[0].cost().to_bits());
    }
}

#[test]
fn every_shipped_drive_file_gives_ranges_for_its_estimates() {
    for r in [
        "abb_irb6700_200_260",
        "abb_irb4600_40_255",
        "staubli_tx200",
        "ur10e",
        "puma560",
    ] {
        let model = robot::load(&root().join("robots").join(r)).unwrap();
        let (ranges, file) = Ranges::of_robot(&model)
            .unwrap()
            .unwrap_or_else(|| panic!("{r}: no [uncertainty] table"));
        assert!(file.ends_with("drive.toml"));
        assert!(
            ranges.link_mass_rel > 0.0 && ranges.torque_constant_rel > 0.0,
            "{r}"
        );
        if model.effects.table.balancer_lever_m.is_some() {
            assert!(ranges.balancer_absent_probability > 0.0, "{r}");
        }
    }
}

#[test]
fn uncertainty_draws_computed_in_interleaved_shards_reduce_to_the_single_run_study() {
    // A study's draws split as shards split them (draw d on shard d mod 3),
    // serialised and read back as a merge reads them, give the single run's study bit for bit.
    let model = common::robot("abb_irb4600_40_255");
    let tp = common::path("seed000_test_path.gcode");
    let job = common::default_job(&model, &tp);
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let g = Grid {
        xs: vec![1.0, 1.2, 1.4],
        ys: vec![-0.3, 0.0],
        zs: vec![0.0],
        yaws: vec![0.0],
        spins: vec![0.0],
    };
    let rows = ev.sweep(&g.placements(), &|_, _| {}).unwrap();
    let feasible: Vec<_> = rows
        .iter()
        .filter(|r| r.cost().is_finite())
        .cloned()
        .collect();
    assert!(feasible.len() >= 3, "{} feasible", feasible.len());
    let base = feasible.last().unwrap().clone();
    let n = 7;
    let single = uncertainty::study(&job, &ev, &feasible, Some(&base), n, 11).unwrap();
    let setup = uncertainty::StudySetup::new(&ev, &feasible, Some(&base), n, 11, None).unwrap();
    let mut per: Vec<Option<uncertainty::Draw>> = vec![None; n];
    for k in 0..3 {
        let mine: Vec<usize> = (0..n).filter(|d| d % 3 == k).collect();
        // postcard, as shard rows are stored: every bit of an f64 kept.
        let bytes = postcard::to_stdvec(&setup.draws(&mine).unwrap()).unwrap();
        let back: Vec<uncertainty::Draw> = postcard::from_bytes(&bytes).unwrap();
        for (d, x) in mine.into_iter().zip(back) {
            per[d] = Some(x);
        }
    }
    let per: Vec<_> = per.into_iter().map(Option::unwrap).collect();
    let merged = setup.reduce(&per).unwrap();
    assert_eq!(
        serde_json::to_string(&merged).unwrap(),
        serde_json::to_string(&single).unwrap()
    );
    // A missing draw or a draw of other candidates is refused, not reduced.
    assert!(setup.reduce(&per[..n - 1]).is_err());
    let mut wrong = per.clone();
    wrong[2].energies_j.pop();
    assert!(setup.reduce(&wrong).is_err());
    assert!(setup.draw(n).is_err());
}

#[test]
fn a_calibrated_robots_uncertainty_draws_vary_the_parameters_it_identified() {
    // A calibrated robot keeps per-direction Coulomb friction in `[effects.values]`, which wins
    // over the drive keys: the draws must vary it there (they varied the drive key, to no
    // effect, so every draw was the nominal robot), and the calibrated file must keep it (it
    // kept the mean of both directions only).
    let d = std::env::temp_dir().join(format!("printwatt-unc-cal-{}", std::process::id()));
    let (cal, log) = calibrate(&d, "tau", "coulomb=60:20", "1", "coulomb_directional");
    // The calibrated robot reproduces the log as well as the fit did (noise 1 N·m).
    let cmp: serde_json::Value = serde_json::from_str(&run_cli(&[
        "compare",
        "--robot",
        &cal.display().to_string(),
        "--log",
        &log,
        "--json",
    ]))
    .unwrap();
    let rmse = cmp["total"]["rmse"].as_f64().unwrap();
    assert!(
        rmse < 1.5,
        "calibrated robot's RMSE {rmse} N·m: the identified friction was lost"
    );
    // With every range zero, only the identified parameters vary between draws.
    let model = robot::load(&cal).unwrap();
    let tp = common::path("seed000_test_path.gcode");
    let job = common::default_job(&model, &tp);
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let g = Grid {
        xs: vec![1.2, 1.4],
        ys: vec![0.0],
        zs: vec![0.0],
        yaws: vec![0.0],
        spins: vec![0.0],
    };
    let rows = ev.sweep(&g.placements(), &|_, _| {}).unwrap();
    let feasible: Vec<_> = rows
        .iter()
        .filter(|r| r.cost().is_finite())
        .cloned()
        .collect();
    assert!(!feasible.is_empty());
    let zero = common::zero_ranges();
    let st = uncertainty::study_with(&job, &ev, &feasible, None, 4, 3, Some(zero)).unwrap();
    let e0 = feasible[0].cost();
    assert!(
        st.per_draw_j.iter().any(|d| d[0] != e0),
        "every draw gave the nominal energy {e0} J: the identified parameters were not varied"
    );
    assert!(
        st.per_draw_j
            .iter()
            .all(|d| ((d[0] - e0) / e0).abs() < 0.01),
        "standard errors of ~0.05 N·m move the energy by far less than 1 %: {:?}",
        st.per_draw_j
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_calibrated_robots_identified_armature_copper_gear_efficiency_and_payload_are_drawn_from_their_standard_errors(
) {
    // These live in the drive keys of a calibrated robot. They were drawn from the (wide)
    // ranges, not their standard errors, while the study listed them as calibrated; the
    // armature was not drawn at all, and the torque constant was drawn on top of a winding
    // resistance identified with it held (the log determines R/k_t² only). An identified
    // payload (written as the robot's payload) was drawn from the payload mass range.
    let d = std::env::temp_dir().join(format!("printwatt-unc-drive-{}", std::process::id()));
    let (cal, _) = calibrate(
        &d,
        "p",
        "coulomb=30,payload=+15",
        "5",
        "coulomb,armature,copper,gear_efficiency,payload",
    );
    let model = robot::load(&cal).unwrap();
    let se = |name: &str| {
        let p = model
            .effects
            .calibration
            .as_ref()
            .unwrap()
            .params
            .iter()
            .find(|p| p.name == name);
        let p = p.unwrap_or_else(|| panic!("{name} not identified"));
        (p.value, p.std_error.unwrap())
    };
    let tp = common::path("seed000_test_path.gcode");
    let job = common::default_job(&model, &tp);
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let g = Grid {
        xs: vec![1.3],
        ys: vec![0.0],
        zs: vec![0.0],
        yaws: vec![0.0],
        spins: vec![0.0],
    };
    let rows = ev.sweep(&g.placements(), &|_, _| {}).unwrap();
    assert!(rows[0].cost().is_finite());
    // Wide ranges: a draw from them would spread far more than the standard errors.
    let ranges = Ranges {
        torque_constant_rel: 0.3,
        winding_resistance_rel: 0.5,
        gear_efficiency_abs: 0.2,
        payload_mass_rel: 0.3,
        ..common::zero_ranges()
    };
    let n = 60;
    let setup = uncertainty::StudySetup::new(&ev, &rows, None, n, 7, Some(ranges)).unwrap();
    let draws = setup.draws(&(0..n).collect::<Vec<_>>()).unwrap();
    let values = |name: &str| -> Vec<f64> {
        draws
            .iter()
            .map(|d| {
                d.drawn
                    .iter()
                    .find(|x| x.0 == name)
                    .unwrap_or_else(|| panic!("{name} not drawn"))
                    .1
            })
            .collect()
    };
    let sd = |v: &[f64]| {
        let m = v.iter().sum::<f64>() / v.len() as f64;
        (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (v.len() - 1) as f64).sqrt()
    };
    for j in [2, 3] {
        for (drawn, param) in [("winding resistance", "R"), ("armature", "G2Jm")] {
            let (v, s) = se(&format!("{param}[{j}]"));
            // Multipliers: spread s / v.
            let ratio = sd(&values(&format!("{drawn} joint {j}"))) / (s / v);
            assert!(
                (0.6..1.5).contains(&ratio),
                "{drawn} joint {j}: spread {ratio} × its standard error"
            );
        }
        let (_, s) = se(&format!("eta[{j}]"));
        let ratio = sd(&values(&format!("gear efficiency joint {j}"))) / s;
        assert!(
            (0.6..1.5).contains(&ratio),
            "gear efficiency joint {j}: spread {ratio} × its standard error"
        );
        assert!(
            draws[0]
                .drawn
                .iter()
                .all(|x| x.0 != format!("torque constant joint {j}")),
            "the torque constant is drawn on top of an identified winding resistance"
        );
    }
    let (_, s) = se("dm");
    let m = model.payload.as_ref().unwrap().mass;
    let ratio = sd(&values("payload mass")) / (s / m);
    assert!(
        (0.6..1.5).contains(&ratio),
        "payload mass: spread {ratio} × its standard error"
    );
    let st = setup.reduce(&draws).unwrap();
    for name in ["R[2]", "G2Jm[2]", "eta[2]", "dm", "dh_z"] {
        assert!(
            st.calibrated.iter().any(|c| c == name),
            "{name} missing from {:?}",
            st.calibrated
        );
    }
    let _ = std::fs::remove_dir_all(&d);
}
