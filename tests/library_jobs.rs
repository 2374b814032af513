//! The library runs the jobs: `search::run` on an `OptimiseConfig` gives the command line's
//! answer bit for bit (the binary only parses its arguments into the config and prints the
//! outcome), and progress reaches the observer.

use printwatt::robot;
use printwatt::search::job::{OptimiseConfig, PlacementSet};
use printwatt::search::run::{Observer, Progress, Silent, Stage};
use printwatt::search::{self, Grid};
use printwatt::toolpath::{self, ReadOptions};
use std::path::PathBuf;
use std::process::Command;
use std::sync::Mutex;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `printwatt ARGS` (with `--json` among them) run in the temporary directory: its JSON.
fn cli_json(args: &[&str]) -> serde_json::Value {
    let out = Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .args(args)
        .current_dir(std::env::temp_dir())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The small job of the `optimise_small` transcript (18 grid placements) with every other
/// setting at its default.
fn small_job() -> OptimiseConfig {
    let path_file = root().join("paths/default.gcode");
    let model = robot::load(&root().join("robots/abb_irb6700_200_260")).unwrap();
    let tp = toolpath::load(&path_file, &ReadOptions::default()).unwrap();
    let mut cfg = OptimiseConfig::new(model, tp, &path_file);
    cfg.placements = Some(PlacementSet::grid(Grid {
        xs: search::parse_range("x", "1.4:1.8:0.2").unwrap(),
        ys: search::parse_range("y", "-0.2:0.2:0.2").unwrap(),
        zs: vec![0.2],
        yaws: vec![0.0, 90f64.to_radians()],
        spins: vec![0.0],
    }));
    cfg
}

#[test]
fn library_optimise_matches_cli() {
    let cfg = small_job();
    let out = search::run(&cfg, &Silent).unwrap();
    let lib: serde_json::Value =
        serde_json::from_str(&out.report.summary_json(false).unwrap()).unwrap();
    let mut cli = cli_json(&[
        "optimise",
        "--path",
        &cfg.path_file.display().to_string(),
        "--x",
        "1.4:1.8:0.2",
        "--y",
        "-0.2:0.2:0.2",
        "--z",
        "0.2",
        "--yaw",
        "0,90",
        "--json",
    ]);
    // The reader's warnings are the front end's notes (stderr and `warnings`), not the answer.
    if let Some(o) = cli.as_object_mut() {
        o.remove("warnings");
    }
    let differ: Vec<&String> = cli
        .as_object()
        .unwrap()
        .iter()
        .filter(|(k, v)| lib.get(k.as_str()) != Some(v))
        .map(|(k, _)| k)
        .collect();
    assert!(
        differ.is_empty(),
        "the library's answer differs in {differ:?}"
    );
    assert_eq!(lib, cli, "the library's answer is not the command line's");
}

#[derive(Default)]
struct Seen(Mutex<Vec<(Stage, usize)>>);

impl Observer for Seen {
    fn progress(&self, p: Progress) {
        self.0.lock().unwrap().push((p.stage, p.done));
    }
}

#[test]
fn progress_reaches_the_observer_and_does_not_change_the_answer() {
    let mut cfg = small_job();
    cfg.settings.max_evals = 10;
    cfg.settings.tolerance = "0,0".parse().unwrap();
    let seen = Seen::default();
    let a = search::run(&cfg, &seen).unwrap();
    let b = search::run(&cfg, &Silent).unwrap();
    assert_eq!(
        a.report.summary_json(false).unwrap(),
        b.report.summary_json(false).unwrap()
    );
    let seen = seen.0.into_inner().unwrap();
    assert!(seen.iter().any(|(s, _)| *s == Stage::Grid));
    assert!(seen.iter().any(|(s, _)| *s == Stage::Refinement));
}

#[test]
fn bad_settings_are_refused_before_any_work() {
    let mut cfg = small_job();
    cfg.settings.uncertainty = Some(0);
    let e = search::run(&cfg, &Silent).err().unwrap().to_string();
    assert!(e.contains("expected 1 to 100000 draws"), "{e}");
}

#[test]
fn a_search_stopped_by_its_budget_reports_the_iterations_it_made() {
    let mut cfg = small_job();
    cfg.settings.max_evals = 20;
    let out = search::run(&cfg, &Silent).unwrap();
    let o = out.report.optimise.as_ref().unwrap();
    let si = o.search.as_ref().unwrap();
    assert!(si.budget_spent.is_some(), "20 evaluations do not converge");
    assert!(
        o.iterations > 0 && o.iterations <= o.evals,
        "{} iterations, {} evaluations",
        o.iterations,
        o.evals
    );
}

/// `stations::run` on a `StationsJob` gives `printwatt stations --json`'s plan bit for bit, and
/// the facts it states about the job are the command's (the binary only parses its arguments
/// into the job and prints the outcome).
#[test]
fn library_stations_matches_cli() {
    use printwatt::report::stations::StationsReport;
    use printwatt::stations::{self, Sites, StationsJob};
    let path_file = root().join("paths/floor_four_rooms.gcode");
    let model = robot::load(&root().join("robots/abb_irb6700_200_260")).unwrap();
    let tp = toolpath::load(&path_file, &ReadOptions::default()).unwrap();
    let mut job = StationsJob::new(&model, &tp, 20000.0);
    job.sites = Sites::Track {
        from: [-1.0, 1.5],
        to: [13.0, 1.5],
        step_m: 0.5,
    };
    job.feasibility.wrist_margin_rad = 0.0;
    let out = stations::run(&job, &|_, _| {}).unwrap();
    let facts = out.facts(&job);
    let rep = StationsReport {
        title: String::new(),
        meta: facts.clone(),
        plan: &out.plan,
        path: &tp,
        relocation_cost_j: job.relocation_j,
        relocation_cost_per_m_j: job.relocation_j_per_m,
    };
    let mut lib: serde_json::Value = serde_json::from_str(&rep.summary_json().unwrap()).unwrap();
    let mut cli = cli_json(&[
        "stations",
        "--path",
        path_file.to_str().unwrap(),
        "--relocation-cost",
        "20000",
        "--track",
        "-1,1.5:13,1.5",
        "--wrist-margin",
        "0",
        "--json",
    ]);
    let cli_meta = cli["meta"].clone();
    for (k, v) in &facts {
        assert_eq!(cli_meta[k.as_str()], v.as_str(), "{k}");
    }
    for d in [&mut lib, &mut cli] {
        let o = d.as_object_mut().unwrap();
        for k in ["title", "meta", "schema_version", "warnings"] {
            o.remove(k);
        }
    }
    assert_eq!(lib, cli);
    assert_eq!(out.plan.segments.len(), 5);
}
