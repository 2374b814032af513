//! Issue 9 item 4: how much to trust the answer (`optimise --uncertainty N`).

mod common;
use common::root;

use printwatt::placement::uncertainty::{self, Ranges};
use printwatt::placement::{Evaluator, FeasibilityOptions, Grid, Objective};
use printwatt::robot;

/// Every range zero: a draw is the nominal robot but for what a calibrated robot identified.
fn zero_ranges() -> Ranges {
    Ranges {
        link_mass_rel: 0.0,
        link_com_m: 0.0,
        link_inertia_rel: 0.0,
        payload_mass_rel: 0.0,
        torque_constant_rel: 0.0,
        winding_resistance_rel: 0.0,
        viscous_rel: 0.0,
        coulomb_rel: 0.0,
        gear_efficiency_abs: 0.0,
        standby_power_rel: 0.0,
        balancer_absent_probability: 0.0,
        balancer_force_rel: 0.0,
    }
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
    let zero = zero_ranges();
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
    // Issue 12 item 6: a study's draws split as shards split them (draw d on shard d mod 3),
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
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let run = |args: &[&str]| {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_printwatt"))
            .args(args)
            .current_dir(root())
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let ds = d.display().to_string();
    run(&[
        "simulate",
        "--robot",
        "abb_irb4600_40_255",
        "--excite",
        "20",
        "--hidden",
        "coulomb=60:20",
        "--noise",
        "1",
        "--rate",
        "100",
        "--seed",
        "5",
        "--out",
        &ds,
    ]);
    let log = d.join("log.csv").display().to_string();
    let id = d.join("id").display().to_string();
    run(&[
        "identify",
        "--robot",
        "abb_irb4600_40_255",
        "--log",
        &log,
        "--effects",
        "coulomb",
        "--out",
        &id,
    ]);
    let cal = d.join("id/abb_irb4600_40_255.calibrated.toml");
    // The calibrated robot reproduces the log as well as the fit did (noise 1 N·m).
    let cmp: serde_json::Value = serde_json::from_str(&run(&[
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
    let zero = zero_ranges();
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
