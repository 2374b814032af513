//! Path reduction for long repetitive prints (src/placement/reduce.rs,
//! src/toolpath/repeat.rs): the estimate against the full evaluation, feasibility across z,
//! the fallback for paths that do not repeat, and optimise's report of both figures.

mod common;
#[path = "common/wall.rs"]
mod wall;

use printwatt::evaluate::reduce::{NotReduced, ReduceOptions, Reduction};
use printwatt::evaluate::{Evaluator, FeasibilityOptions, Objective};
use printwatt::frame::Placement;
use printwatt::toolpath::repeat;
use printwatt::toolpath::{self, ReadOptions, Toolpath};

fn wall_path(layers: usize) -> Toolpath {
    toolpath::parse_gcode(
        &wall::wall_gcode(800.0, 200.0, 20.0, layers),
        "wall.gcode",
        &ReadOptions::default(),
    )
    .unwrap()
}

/// A 12-layer wall, each layer 10 mm shorter than the one below: nothing repeats.
fn taper_path() -> Toolpath {
    let mut taper = String::new();
    for (k, layer) in (0..12).map(|k| {
        (
            k,
            wall::wall_gcode(800.0 - 10.0 * k as f64, 200.0, 20.0, k + 1),
        )
    }) {
        // The last layer of a k+1-layer wall is layer k of the taper.
        let body: Vec<&str> = layer.lines().collect();
        let start = body
            .iter()
            .rposition(|l| l.starts_with("G0 X"))
            .unwrap_or(4);
        let start = if k == 0 { 4 } else { start - 2 };
        for l in &body[start..body.len() - 2] {
            taper += l;
            taper += "\n";
        }
    }
    toolpath::parse_gcode(&taper, "taper.gcode", &ReadOptions::default()).unwrap()
}

fn forced() -> ReduceOptions {
    ReduceOptions {
        min_samples: 0,
        ..Default::default()
    }
}

fn evaluators<'j, 'a>(
    job: &'j printwatt::evaluate::PathJob<'a>,
    tp: &Toolpath,
    o: ReduceOptions,
) -> (Evaluator<'j, 'a>, Evaluator<'j, 'a>) {
    let red = Reduction::plan(job, tp, o).unwrap();
    (
        Evaluator::new(job, FeasibilityOptions::default(), Objective::Supply).with_reduction(red),
        Evaluator::new(job, FeasibilityOptions::default(), Objective::Supply),
    )
}

#[test]
fn shipped_wall_repeats_with_alternating_seams() {
    let tp = common::path("wall_multilayer.gcode");
    let rep = repeat::repetition(&tp, repeat::REPEAT_TOLERANCE_M).unwrap();
    assert_eq!(rep.units.len(), 10);
    assert_eq!(rep.period, 2, "the seam alternates between two corners");
    // Layer 0 comes from the home position; layers 1..9 repeat.
    assert_eq!(rep.run, 1..10);
    assert!((rep.units[3].z_m - 0.060).abs() < 1e-12);
}

#[test]
fn float_noise_below_the_tolerance_still_repeats_and_a_taper_does_not() {
    // 0.3 µm of noise in every coordinate (G-code written to 4 decimals of a mm).
    let noisy: String = wall::wall_gcode(800.0, 200.0, 20.0, 12)
        .lines()
        .enumerate()
        .map(|(i, l)| {
            let l = if l.starts_with("G1") && i % 2 == 1 {
                l.replace(".0000 Y", ".0003 Y")
            } else {
                l.to_string()
            };
            format!("{l}\n")
        })
        .collect();
    assert_ne!(noisy, wall::wall_gcode(800.0, 200.0, 20.0, 12));
    let tp = toolpath::parse_gcode(&noisy, "noisy.gcode", &ReadOptions::default()).unwrap();
    let rep = repeat::repetition(&tp, repeat::REPEAT_TOLERANCE_M).unwrap();
    assert_eq!((rep.period, rep.run.len()), (2, 11));
    let tp = taper_path();
    assert_eq!(repeat::layers(&tp, repeat::REPEAT_TOLERANCE_M).len(), 12);
    assert!(repeat::repetition(&tp, repeat::REPEAT_TOLERANCE_M).is_none());
}

#[test]
fn estimate_is_within_its_stated_error_of_the_full_evaluation() {
    let model = common::robot("abb_irb6700_200_260");
    let tp = wall_path(30);
    let job = common::default_job(&model, &tp);
    let (ev, full) = evaluators(&job, &tp, forced());
    let (mut sc, mut sf) = (ev.scratch().unwrap(), full.scratch().unwrap());
    for at in [
        Placement::new(1.8, 0.0, 0.0, 0.0),
        Placement::new(1.6, 0.5, 0.3, 1.5),
        Placement::new(2.0, -0.3, 0.0, 0.5),
    ] {
        let r = ev.evaluate(&mut sc, &at);
        let f = full.evaluate(&mut sf, &at);
        let (r, f) = (r.feasible().unwrap(), f.feasible().unwrap());
        let est = r.path_reduction.as_ref().unwrap();
        assert!(est.fallback.is_none(), "{at:?}: {:?}", est.fallback);
        assert!(est.samples_evaluated < f.samples / 2, "{est:?}");
        let d = (r.energy_j - f.energy_j).abs();
        assert!(
            d <= est.error_j,
            "{at:?}: estimate {} J, full {} J: |difference| {d} J > stated error {} J",
            r.energy_j,
            f.energy_j,
            est.error_j
        );
        assert!(est.error_j < 0.005 * f.energy_j, "{est:?}");
        assert_eq!(r.samples, f.samples);
        for j in 0..6 {
            let (a, b) = (r.joint_electrical_j[j], f.joint_electrical_j[j]);
            assert!(
                (a - b).abs() <= 0.01 * b.abs().max(100.0),
                "joint {j}: {a} vs {b}"
            );
        }
    }
}

#[test]
fn every_layer_evaluated_gives_the_full_evaluation() {
    // 16 layers: classes of 8 and 7 units, all evaluated at 9 nodes when no error is accepted.
    let model = common::robot("abb_irb6700_200_260");
    let tp = wall_path(16);
    let job = common::default_job(&model, &tp);
    let o = ReduceOptions {
        rel_tol: 0.0,
        ..forced()
    };
    let (ev, full) = evaluators(&job, &tp, o);
    let at = Placement::new(1.8, 0.2, 0.1, 0.3);
    let r = ev.evaluate(&mut ev.scratch().unwrap(), &at);
    let f = full.evaluate(&mut full.scratch().unwrap(), &at);
    let (r, f) = (r.feasible().unwrap(), f.feasible().unwrap());
    let est = r.path_reduction.as_ref().unwrap();
    assert_eq!(est.samples_evaluated, f.samples);
    // Only the summation's rounding is stated: positive, and far below 1e-9 of the energy.
    assert!(
        est.error_j > 0.0 && est.error_j <= 1e-9 * f.supply_j,
        "stated error {} J for {} J",
        est.error_j,
        f.supply_j
    );
    for (a, b) in [
        (r.supply_j, f.supply_j),
        (r.drives_j, f.drives_j),
        (r.mechanical_abs_j, f.mechanical_abs_j),
        (r.losses.copper_j, f.losses.copper_j),
    ] {
        assert!((a - b).abs() <= 1e-9 * b.abs(), "{a} vs {b}");
    }
    assert_eq!(r.margins.joint_limit_rad, f.margins.joint_limit_rad);
}

#[test]
fn an_estimate_from_every_layer_is_within_its_stated_error_of_the_full_evaluation() {
    // Every layer evaluated sample by sample: the estimate differs from the full evaluation by
    // the summation order's rounding only (~1e-10 J on 10^4 J), and the stated error must
    // cover it. Before, it stated 0 J and the report read "OUTSIDE the stated error".
    let model = common::robot("abb_irb6700_200_260");
    let tp = wall_path(10);
    let job = common::default_job(&model, &tp);
    // These placements take the wrist through q5 = 0: a wrist margin of 0 keeps them feasible
    // (the estimate's error is the subject here, not the margin).
    let ev = Evaluator::new(
        &job,
        FeasibilityOptions {
            wrist_margin_rad: 0.0,
            ..FeasibilityOptions::default()
        },
        Objective::Supply,
    )
    .with_reduction(Reduction::plan(&job, &tp, forced()).unwrap());
    for at in [
        Placement::new(1.8, 0.2, 0.1, 0.3),
        Placement::new(1.6, -0.1, 0.0, 0.0),
        Placement::new(1.9, 0.3, 0.05, -0.2),
    ] {
        let best = ev.evaluate(&mut ev.scratch().unwrap(), &at);
        let est = best.feasible().unwrap().path_reduction.clone().unwrap();
        assert_eq!(
            est.layers_evaluated, est.layers,
            "{at:?}: every layer evaluated"
        );
        let (_, chk) = printwatt::evaluate::reduce::confirm(&ev, &best)
            .unwrap()
            .expect("an estimate is confirmed");
        assert!(
            chk.within_error,
            "{at:?}: estimate {} J, full {} J, stated error {} J",
            chk.estimate_j, chk.full_j, chk.error_j
        );
        let line = printwatt::report::placement::full_check_line(&chk);
        assert!(line.contains("within the stated error"), "{line}");
    }
}

#[test]
fn wall_whose_top_layers_are_out_of_reach_is_not_called_feasible() {
    let model = common::robot("abb_irb6700_200_260");
    let tp = wall_path(30);
    let job = common::default_job(&model, &tp);
    let (ev, full) = evaluators(&job, &tp, forced());
    let one = wall_path(1);
    let job1 = common::default_job(&model, &one);
    let ev1 = Evaluator::new(&job1, FeasibilityOptions::default(), Objective::Supply);
    // x = 1.4: layer 20 of 30 leaves the reach; x = 1.1: the top layers fail too (at 1.0 the
    // upper arm's published housing already meets the bed on the first layer).
    for x in [1.4, 1.1] {
        let at = Placement::new(x, 0.0, 1.6, 0.0);
        assert!(
            ev1.evaluate(&mut ev1.scratch().unwrap(), &at)
                .feasible()
                .is_some(),
            "the first layer alone is feasible at {at:?}"
        );
        let f = full.evaluate(&mut full.scratch().unwrap(), &at);
        let r = ev.evaluate(&mut ev.scratch().unwrap(), &at);
        let (fi, ri) = (f.outcome.unwrap_err(), r.outcome.unwrap_err());
        assert_eq!(ri.reason, fi.reason, "{ri}");
        assert!(ri.point_m.unwrap()[2] > 1.6 + 0.3, "{ri}");
    }
}

#[test]
fn path_without_repeating_layers_falls_back_to_full_evaluation() {
    let model = common::robot("abb_irb6700_200_260");
    for tp in [common::path("default.gcode"), taper_path()] {
        let job = common::default_job(&model, &tp);
        let why = Reduction::plan(&job, &tp, forced()).unwrap_err();
        assert_eq!(why, NotReduced::NoRepetition, "{}", tp.source);
    }
    // A repeating path shorter than the automatic threshold is evaluated in full too.
    let tp = wall_path(4);
    let job = common::default_job(&model, &tp);
    assert!(matches!(
        Reduction::plan(&job, &tp, ReduceOptions::default()),
        Err(NotReduced::Short(_))
    ));
}

#[test]
fn optimise_on_a_repetitive_path_reports_full_and_estimate_within_half_a_percent() {
    let dir = common::scratch("reduce", "optimise");
    std::fs::write(
        dir.join("wall30.gcode"),
        wall::wall_gcode(800.0, 200.0, 20.0, 30),
    )
    .unwrap();
    let o = common::run(
        &[
            "optimise",
            "--path",
            "wall30.gcode",
            "--x",
            "1.6:2.0:0.2",
            "--y",
            "-0.2:0.2:0.2",
            "--z",
            "0",
            "--yaw",
            "0",
            "--max-evals",
            "12",
            "--tolerance",
            "0,0",
            "--evaluation",
            "reduced",
            "--threads",
            "2",
            "--json",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", common::stderr_of(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let c = &v["optimise"]["path_reduction"];
    let (est, full, err) = (
        c["estimate_j"].as_f64().unwrap(),
        c["full_j"].as_f64().unwrap(),
        c["error_j"].as_f64().unwrap(),
    );
    assert!((est - full).abs() / full < 0.005, "{c}");
    assert_eq!(
        c["within_error"],
        serde_json::json!((est - full).abs() <= err)
    );
    assert_eq!(c["summary"]["layers"], 30);
    // The answer's figures are the full evaluation's (no estimate attached).
    let best = &v["optimise"]["best"]["outcome"];
    assert_eq!(best["energy_j"].as_f64().unwrap(), full);
    assert!(best.get("path_reduction").is_none(), "{best}");
    // Grid cells are estimates, each with its error.
    assert!(v["optimise"]["best_grid"]["outcome"]["path_reduction"]["error_j"].is_number());
    assert!(v["meta"].to_string().contains("reduced: 30 layers"));

    // --evaluation full: no reduction anywhere.
    let o = common::run(
        &[
            "optimise",
            "--path",
            "wall30.gcode",
            "--at",
            "1.8,0,0,0",
            "--max-evals",
            "0",
            "--tolerance",
            "0,0",
            "--evaluation",
            "full",
            "--json",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", common::stderr_of(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v["optimise"].get("path_reduction").is_none());
    assert!(!v.to_string().contains("path_reduction"));
}

#[test]
fn a_joint_speed_limit_binding_on_some_layers_is_replanned_there_and_matches_the_full_evaluation() {
    // Joint speed limits at 12 % of the IRB 6700's: at this placement they bind on a few layers
    // (the controller slows down there; a speed limit never lowers the path's acceleration).
    let mut model = common::robot("abb_irb6700_200_260");
    for j in model.joints.iter_mut() {
        j.velocity_limit *= 0.12;
    }
    let tp = wall_path(30);
    let job = common::default_job(&model, &tp);
    let (ev, full) = evaluators(&job, &tp, forced());
    let at = Placement::new(1.9, 0.4, 0.6, 1.57);
    let r = ev.evaluate(&mut ev.scratch().unwrap(), &at);
    let f = full.evaluate(&mut full.scratch().unwrap(), &at);
    let (r, f) = (r.feasible().unwrap(), f.feasible().unwrap());
    assert!(
        f.rounds > 1,
        "the full evaluation slows down: {} rounds",
        f.rounds
    );
    let est = r.path_reduction.as_ref().unwrap();
    assert_eq!(est.fallback, None);
    assert!(est.layers_replanned >= 1, "{est:?}");
    let counts = ev.reduction().unwrap().counts();
    assert_eq!((counts.full, counts.estimates), (0, 1), "{counts:?}");
    // The slow-down is in the estimate: its samples are the full evaluation's (each re-planned
    // layer's boundary phase aside), more than the unslowed plan's.
    let nominal = ev.nominal_samples();
    assert!(r.samples > nominal && f.samples > nominal);
    assert!(
        r.samples.abs_diff(f.samples) <= est.layers_replanned + 2,
        "{} vs {} samples",
        r.samples,
        f.samples
    );
    let d = (r.energy_j - f.energy_j).abs();
    assert!(
        d <= est.error_j,
        "{} vs {} J: {d} J > stated {} J",
        r.energy_j,
        f.energy_j,
        est.error_j
    );
    assert!(est.error_j < 0.005 * f.energy_j, "{est:?}");
}

#[test]
fn an_infeasible_tall_wall_is_rejected_before_any_full_evaluation() {
    // A 40-layer wall (1.8 × 0.6 m, 4 mm layers: 4e5 samples) on a bed 1.3 m up: link 1 meets
    // the bed at the first sample, and joint 3's jerk limit binds on the evaluated layers. The
    // cheap checks (every sample's reach, every 40th tracked, the evaluated layers' collisions)
    // come before any re-planning or full evaluation.
    let model = common::robot("abb_irb6700_200_260");
    let tp = toolpath::parse_gcode(
        &wall::wall_gcode(1800.0, 600.0, 4.0, 40),
        "wall40.gcode",
        &ReadOptions::default(),
    )
    .unwrap();
    let job = common::default_job(&model, &tp);
    let (ev, full) = evaluators(&job, &tp, ReduceOptions::default());
    let mut sc = ev.scratch().unwrap();
    for at in [
        Placement::new(1.326, -0.121, 1.3, 0.0),
        Placement::new(0.91, 0.849, 1.3, 0.0),
    ] {
        let r = ev.evaluate(&mut sc, &at);
        let f = full.evaluate(&mut full.scratch().unwrap(), &at);
        let (ri, fi) = (r.outcome.unwrap_err(), f.outcome.unwrap_err());
        assert_eq!(
            (ri.reason, ri.sample),
            (fi.reason, fi.sample),
            "{ri} / {fi}"
        );
    }
    let c = ev.reduction().unwrap().counts();
    assert_eq!((c.rejected, c.full, c.estimates), (2, 0, 0), "{c:?}");
}

#[test]
fn an_estimate_whose_stated_error_is_above_the_accepted_one_is_evaluated_in_full_and_says_so() {
    let model = common::robot("abb_irb6700_200_260");
    let tp = wall_path(30);
    let job = common::default_job(&model, &tp);
    let o = ReduceOptions {
        max_nodes: 5,
        max_rel_error: 1e-9,
        ..forced()
    };
    let (ev, full) = evaluators(&job, &tp, o);
    let at = Placement::new(1.8, 0.0, 0.0, 0.0);
    let r = ev.evaluate(&mut ev.scratch().unwrap(), &at);
    let f = full.evaluate(&mut full.scratch().unwrap(), &at);
    let (r, f) = (r.feasible().unwrap(), f.feasible().unwrap());
    let why = r.path_reduction.as_ref().unwrap().fallback.clone().unwrap();
    assert!(
        why.contains("stated error") && why.contains("above the accepted"),
        "{why}"
    );
    assert_eq!(r.energy_j, f.energy_j);
    assert_eq!(ev.reduction().unwrap().counts().full, 1);
}

#[test]
fn a_reduced_sweep_gives_the_same_results_on_1_and_2_threads() {
    // Speed limits at 12 % so that some placements re-plan layers on their own.
    let mut model = common::robot("abb_irb6700_200_260");
    for j in model.joints.iter_mut() {
        j.velocity_limit *= 0.12;
    }
    let tp = wall_path(30);
    let job = common::default_job(&model, &tp);
    let (ev, _) = evaluators(&job, &tp, forced());
    let ps = [
        Placement::new(1.9, 0.4, 0.6, 1.57),
        Placement::new(1.8, 0.0, 0.0, 0.0),
        Placement::new(1.6, 0.5, 0.3, 1.5),
        Placement::new(1.0, 0.0, 1.6, 0.0),
    ];
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| ev.sweep(&ps, &|_, _| {}))
            .unwrap()
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(one, two);
    assert!(one.iter().any(|r| r
        .feasible()
        .and_then(|f| f.path_reduction.as_ref())
        .is_some_and(|e| e.layers_replanned > 0)));
    assert!(one.iter().any(|r| r.feasible().is_none()));
}

#[test]
fn a_ramp_binding_limit_is_replanned_on_its_layers_and_the_estimate_matches_the_full_evaluation_without_a_full_fallback(
) {
    // A 12-layer wall (1.8 × 0.6 m, 4 mm layers, 1.2·10⁵ samples) with the bed 0.65 m up,
    // close to the IRB 6700: joint 3's jerk limit binds at the corners again where the speed
    // is already capped, so the controller lowers the acceleration of those ramps. Until
    // Earlier it lowered the acceleration of the whole path there, which the reduction
    // could not re-plan layer by layer: the placement was evaluated in full. The slow-down is
    // local now, and the layers where it binds are re-planned on their own.
    let model = common::robot("abb_irb6700_200_260");
    let tp = toolpath::parse_gcode(
        &wall::wall_gcode(1800.0, 600.0, 4.0, 12),
        "wall.gcode",
        &ReadOptions::default(),
    )
    .unwrap();
    let job = common::default_job(&model, &tp);
    let (ev, full) = evaluators(&job, &tp, forced());
    let at = Placement::new(1.222, -1.092, 0.65, 0.0);
    // A ramp case: the full evaluation's timing lowers the acceleration somewhere.
    let lines = |i: usize| job.line_of(i);
    let solver = printwatt::kinematics::IkSolver::new(&model).unwrap();
    let timed = printwatt::timing::time_at_planned(
        &solver,
        &job.timing(&lines),
        &at,
        &mut printwatt::timing::Buffers::default(),
    )
    .unwrap();
    assert!(timed.accel_factor < 1.0, "{}", timed.accel_factor);
    let r = ev.evaluate(&mut ev.scratch().unwrap(), &at);
    let f = full.evaluate(&mut full.scratch().unwrap(), &at);
    let (r, f) = (r.feasible().unwrap(), f.feasible().unwrap());
    assert!(f.rounds > 1, "{} rounds", f.rounds);
    let est = r.path_reduction.as_ref().unwrap();
    assert_eq!(est.fallback, None);
    assert!(est.layers_replanned >= 1, "{est:?}");
    let counts = ev.reduction().unwrap().counts();
    assert_eq!((counts.full, counts.estimates), (0, 1), "{counts:?}");
    let nominal = ev.nominal_samples();
    assert!(r.samples > nominal && f.samples > nominal);
    let d = (r.energy_j - f.energy_j).abs();
    assert!(
        d <= est.error_j,
        "{} vs {} J: {d} J > stated {} J",
        r.energy_j,
        f.energy_j,
        est.error_j
    );
    assert!(est.error_j < 0.005 * f.energy_j, "{est:?}");
}

#[test]
fn the_answers_detail_taken_from_its_full_evaluation_is_the_detail_timed_afresh() {
    // The answer of a reduced search is evaluated in full, and its detail (energy report and
    // charts) is worked out from that evaluation's timed path instead of timing the path
    // again: it must be the detail timed afresh, to the bit.
    let model = common::robot("abb_irb6700_200_260");
    let tp = wall_path(30);
    let cfg = reduced_wall_job(&model, &tp);
    let out = printwatt::search::run(&cfg, &printwatt::search::Silent).unwrap();
    let report = &out.report;
    let res = report.optimise.as_ref().unwrap();
    assert!(
        res.path_reduction.is_some(),
        "the answer was confirmed in full"
    );
    let from_full = report.details.iter().find(|d| d.label == "best").unwrap();
    assert_eq!(from_full.eval.placement, res.best.placement);
    let job = common::default_job(&model, &tp);
    let afresh = printwatt::search::run::detail(&job, "best", &res.best)
        .unwrap()
        .unwrap();
    assert_eq!(from_full.energy, afresh.energy);
    assert_eq!(
        format!("{:?}", from_full.charts),
        format!("{:?}", afresh.charts)
    );
    assert!(from_full.energy.total.supply_j.is_finite());
    // The worst and baseline cells, worked out beside the refinement, are reported too.
    let labels: Vec<&str> = report.details.iter().map(|d| d.label.as_str()).collect();
    assert_eq!(labels, ["best", "worst", "baseline"]);
}

/// The 30-layer wall's optimisation job with reduced evaluation (a 3 × 3 grid, 12 Nelder–Mead
/// evaluations, no tolerance, no margin trade).
fn reduced_wall_job(
    model: &printwatt::robot::RobotModel,
    tp: &Toolpath,
) -> printwatt::search::OptimiseConfig {
    use printwatt::search::{self, Grid, PlacementSet};
    let mut cfg = search::OptimiseConfig::new(model.clone(), tp.clone(), "wall30.gcode");
    cfg.placements = Some(PlacementSet::grid(Grid {
        xs: search::parse_range("x", "1.6:2.0:0.2").unwrap(),
        ys: search::parse_range("y", "-0.2:0.2:0.2").unwrap(),
        zs: vec![0.0],
        yaws: vec![0.0],
        spins: vec![0.0],
    }));
    cfg.settings.evaluation = search::EvaluationMode::Reduced;
    cfg.settings.max_evals = 12;
    cfg.settings.margin_trade = false;
    cfg.settings.tolerance = "0,0".parse().unwrap();
    cfg
}

#[test]
fn the_work_beside_the_refinement_gives_the_same_report_on_1_and_2_threads() {
    // The baseline and the worst and baseline details are worked out beside the refinement
    // where a second thread is free, and the answer's detail beside its full evaluation: the
    // summary and the whole report must not depend on the thread count.
    let model = common::robot("abb_irb6700_200_260");
    let tp = wall_path(30);
    let cfg = reduced_wall_job(&model, &tp);
    let run = |n: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap();
        let out = pool
            .install(|| printwatt::search::run(&cfg, &printwatt::search::Silent))
            .unwrap();
        (out.report.summary_json(true).unwrap(), out.report.html())
    };
    let (json1, html1) = run(1);
    let (json2, html2) = run(2);
    assert_eq!(json1, json2);
    assert!(html1 == html2, "the reports differ between 1 and 2 threads");
    assert!(json1.contains("\"baseline\""), "{json1}");
}
