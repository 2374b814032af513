//! The run report: a sweep rendered to `report.html` is well-formed XML (XHTML) with the
//! expected figures; `summary.json` and `placements.csv` parse. The `compare` report of the
//! identification commands is drawn by the same chart module and checked the same way.
//! (Screenshots are taken by hand, never by the test suite.)

use printwatt::energy::EnergyOptions;
use printwatt::placement::optimise::{self, OptimiseOptions};
use printwatt::placement::{Evaluator, FeasibilityOptions, Grid, Objective, PathJob};
use printwatt::report::placement::{Detail, RunReport};
use printwatt::robot;
use printwatt::timing::{JointStageOptions, ProfileOptions};
use printwatt::toolpath::{self, ReadOptions};
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn report_is_well_formed_with_expected_figures() {
    let model = robot::load(&root().join("robots/abb_irb6700_200_260")).unwrap();
    let tp = toolpath::load(&root().join("paths/default.gcode"), &ReadOptions::default()).unwrap();
    let job = PathJob::new(
        &model,
        &tp,
        EnergyOptions::default(),
        ProfileOptions::default(),
        JointStageOptions::default(),
    )
    .unwrap();
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let grid = Grid {
        xs: vec![1.2, 1.3, 1.4, 1.5],
        ys: vec![-0.1, 0.0, 0.1],
        zs: vec![0.5],
        yaws: vec![std::f64::consts::FRAC_PI_2],
        spins: vec![0.0],
    };
    let rows = ev.sweep(&grid.placements(), &|_, _| {}).unwrap();
    assert!(
        rows.iter().any(|r| r.outcome.is_err()),
        "some infeasible cells to mark"
    );
    let opt = optimise::optimise(
        &ev,
        &rows,
        &OptimiseOptions {
            max_evals: 10,
            ..Default::default()
        },
    )
    .unwrap();
    let mut details = Vec::new();
    for (label, e) in [
        ("best", &opt.best),
        ("worst", optimise::worst_of(&rows).unwrap()),
    ] {
        let full = job.evaluate(&e.placement).unwrap().unwrap();
        details.push(Detail {
            label: label.into(),
            eval: e.clone(),
            energy: full.energy,
        });
    }
    let baseline = optimise::feasible_centre(&rows).unwrap().clone();
    let rep = RunReport {
        title: "test <report> & co".into(),
        meta: vec![("robot".into(), model.name().into())],
        rows,
        names: None,
        grid: Some(grid),
        optimise: Some(opt),
        baseline: Some(("centre".into(), baseline)),
        details,
        electrical: model.drive.is_some(),
    };
    let dir = std::env::temp_dir().join(format!("pw-report-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    rep.write(&dir).unwrap();
    let html = std::fs::read_to_string(dir.join("report.html")).unwrap();
    let doc = roxmltree::Document::parse_with_options(
        &html,
        roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        },
    )
    .expect("report.html is well-formed XML");
    let ids: Vec<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("figure"))
        .filter_map(|n| n.attribute("id"))
        .collect();
    for want in ["heatmap", "bars", "joints", "power-0", "power-1"] {
        assert!(ids.contains(&want), "figure {want} in {ids:?}");
    }
    let svgs = doc.descendants().filter(|n| n.has_tag_name("svg")).count();
    assert_eq!(svgs, 5);
    // Infeasible cells are marked by reason and the optimum is marked.
    let classes: Vec<&str> = doc
        .descendants()
        .filter_map(|n| n.attribute("class"))
        .collect();
    assert!(classes.contains(&"mark-optimum"), "{classes:?}");
    assert!(classes
        .iter()
        .any(|c| c.starts_with("mark-") && *c != "mark-optimum"));
    assert!(!html.contains("NaN") && !html.contains("\"inf\"") && !html.contains(">inf<"));
    assert!(html.contains("test &lt;report&gt; &amp; co"));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["placements"], 12);
    assert!(s["saving_pct"].as_f64().is_some());
    assert_eq!(s["details"][0]["joints"].as_array().unwrap().len(), 6);
    let csv = std::fs::read_to_string(dir.join("placements.csv")).unwrap();
    assert_eq!(csv.lines().count(), 13);
    let _ = std::fs::remove_dir_all(&dir);
}

fn parse_xhtml(html: &str) -> roxmltree::Document<'_> {
    roxmltree::Document::parse_with_options(
        html,
        roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        },
    )
    .expect("report.html is well-formed XML")
}

#[test]
fn compare_report_has_every_chart_and_stays_small() {
    let dir = std::env::temp_dir().join(format!("pw-compare-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .current_dir(root())
        .args([
            "compare",
            "--robot",
            "robots/abb_irb4600_40_255",
            "--log",
            "results/identify_example/log.csv",
            "--out",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let html = std::fs::read_to_string(dir.join("report.html")).unwrap();
    // 5000 samples × 6 joints: decimated lines and thinned scatters keep it well under 1 MB.
    assert!(
        html.len() < 1_000_000,
        "report.html is {} bytes",
        html.len()
    );
    let doc = parse_xhtml(&html);
    let ids: Vec<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("figure"))
        .filter_map(|n| n.attribute("id"))
        .collect();
    for j in 1..=6 {
        for want in [
            format!("joint_{j}-signal"),
            format!("joint_{j}-residual"),
            format!("joint_{j}-residual-vs-q{j}-velocity"),
            format!("joint_{j}-residual-vs-q{j}-acceleration"),
            format!("joint_{j}-residual-vs-q{j}-position"),
        ] {
            assert!(ids.contains(&want.as_str()), "figure {want} in {ids:?}");
        }
    }
    let svgs: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("svg"))
        .collect();
    assert_eq!(svgs.len(), 30);
    // Every chart has drawn data (a non-empty path), axis labels with units, and the
    // measured-vs-model charts a legend naming both.
    for s in &svgs {
        assert!(s
            .descendants()
            .any(|n| n.has_tag_name("path") && n.attribute("d").is_some_and(|d| d.len() > 100)));
        assert!(s
            .descendants()
            .any(|n| n.text() == Some("residual [N·m]") || n.text() == Some("torque τ [N·m]")));
    }
    assert!(html.contains(">measured<") && html.contains(">model<"));
    assert!(html.contains("joint 2 acceleration q̈ [rad/s²]"));
    assert!(!html.contains("NaN"));
    // The metrics table: six joints and the total.
    let rows = doc.descendants().filter(|n| n.has_tag_name("tr")).count();
    assert_eq!(rows, 1 + 7);
    let _ = std::fs::remove_dir_all(&dir);
}
