//! Margins as a trade: the answer of the default job found again with joint-limit margins of
//! 3°, 5° and 8° and wrist margins of 0°, 5° and 8°, so a site chooses its margins knowing
//! what each costs; and no stricter setting is cheaper than the answer (it would keep the
//! configured margins too).

mod common;

use printwatt::search::job::OptimiseConfig;
use printwatt::search::run::Silent;
use printwatt::search::{self, margins};

fn default_config() -> OptimiseConfig {
    let path_file = common::root().join("paths/default.gcode");
    let model = common::robot("abb_irb6700_200_260");
    let tp = common::path("default.gcode");
    OptimiseConfig::new(model, tp, &path_file)
}

#[test]
fn the_answer_states_its_energy_at_each_traded_joint_and_wrist_margin() {
    let cfg = default_config();
    let out = search::run(&cfg, &Silent).unwrap();
    let res = out.report.optimise.as_ref().unwrap();
    let best = res.best.feasible().unwrap();
    let trade = res
        .decision
        .as_ref()
        .and_then(|d| d.margins.as_ref())
        .expect("the margin trade is on by default");
    let settings: Vec<(f64, f64)> = trade
        .points
        .iter()
        .map(|p| (p.joint_margin_deg, p.wrist_margin_deg))
        .collect();
    assert_eq!(
        settings,
        vec![(3.0, 0.0), (3.0, 5.0), (3.0, 8.0), (5.0, 5.0), (8.0, 5.0)]
    );
    let configured: Vec<_> = trade.points.iter().filter(|p| p.configured).collect();
    assert_eq!(configured.len(), 1);
    assert_eq!(configured[0].energy_j, Some(best.energy_j));
    assert_eq!(configured[0].placement, Some(res.best.placement));
    for p in &trade.points {
        let e = p
            .energy_j
            .expect("every traded setting has an answer on the default job");
        assert_eq!(p.delta_j, Some(e - best.energy_j));
    }
    // The text says each setting with its difference.
    let lines = margins::lines(trade);
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("margins joint 8°, wrist 5°: ") && l.contains(" J (+")),
        "{lines:#?}"
    );
}

#[test]
fn no_stricter_margin_setting_is_cheaper_than_the_answer() {
    let cfg = default_config();
    let out = search::run(&cfg, &Silent).unwrap();
    let res = out.report.optimise.as_ref().unwrap();
    let e0 = res.best.feasible().unwrap().energy_j;
    let trade = res.decision.as_ref().unwrap().margins.as_ref().unwrap();
    for p in trade
        .points
        .iter()
        .filter(|p| p.joint_margin_deg >= 3.0 && p.wrist_margin_deg >= 5.0 && !p.configured)
    {
        if let Some(e) = p.energy_j {
            assert!(
                e >= e0 - 1e-9,
                "joint {}°, wrist {}°: {e} J below the answer's {e0} J",
                p.joint_margin_deg,
                p.wrist_margin_deg
            );
        }
    }
    assert!(trade.cheaper_stricter().is_none());
}

#[test]
fn the_wrist_margin_costs_energy_and_its_answer_without_it_passes_near_the_singularity() {
    let cfg = default_config();
    let out = search::run(&cfg, &Silent).unwrap();
    let res = out.report.optimise.as_ref().unwrap();
    let e0 = res.best.feasible().unwrap().energy_j;
    let trade = res.decision.as_ref().unwrap().margins.as_ref().unwrap();
    let free = trade
        .points
        .iter()
        .find(|p| p.wrist_margin_deg == 0.0)
        .unwrap();
    let e_free = free.energy_j.unwrap();
    assert!(
        e_free < e0,
        "without the wrist margin {e_free} J, with it {e0} J"
    );
    // The answer without the margin is one the margin forbids: evaluated under the default
    // options it is infeasible for the wrist.
    let job = common::default_job(&cfg.robot, &cfg.path);
    let ev =
        printwatt::evaluate::Evaluator::new(&job, cfg.settings.feasibility, cfg.settings.objective);
    let e = ev
        .sweep(&[free.placement.unwrap()], &|_, _| {})
        .unwrap()
        .remove(0);
    let why = e.outcome.as_ref().expect_err("infeasible with the margin");
    assert!(why.to_string().contains("wrist"), "{why}");
}

/// `printwatt optimise` on a small grid with `extra`: its standard output.
fn small_optimise(extra: &[&str]) -> String {
    let o = common::bin()
        .args([
            "optimise",
            "--x",
            "1.4:1.8:0.2",
            "--y",
            "-0.2:0.2:0.2",
            "--z",
            "0.2,0.5",
            "--yaw",
            "0,90",
            "--no-report",
        ])
        .args(extra)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", common::stderr_of(&o));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn optimise_without_the_margin_trade_prints_no_trade() {
    assert!(small_optimise(&[]).contains("margins joint 3°, wrist 5° (the answer's)"));
    assert!(!small_optimise(&["--no-margin-trade"]).contains("margins joint"));
}
