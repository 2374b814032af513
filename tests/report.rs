//! The run report: a sweep rendered to `report.html` is well-formed XML (XHTML) with the
//! expected figures; `summary.json` and `placements.csv` parse. The `compare` report of the
//! identification commands is drawn by the same chart module and checked the same way.
//! The top view and the infeasible summary are checked against what a designer was shown
//! before. Rendering in a browser: tests/browser.rs.

mod common;

use printwatt::evaluate::{Evaluator, FeasibilityOptions, Objective};
use printwatt::report::placement::{Detail, RunReport};
use printwatt::report::site::SiteGeometry;
use printwatt::search::optimise::{self, OptimiseOptions};
use printwatt::search::Grid;

/// A report over a small grid with two bed heights (some cells infeasible), optimised, with
/// the site geometry; built once for the tests of this file.
fn report() -> &'static RunReport {
    static R: std::sync::OnceLock<RunReport> = std::sync::OnceLock::new();
    R.get_or_init(build_report)
}

fn build_report() -> RunReport {
    let model = common::robot("abb_irb6700_200_260");
    let tp = common::path("default.gcode");
    let job = common::default_job(&model, &tp);
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    let grid = Grid {
        xs: vec![1.2, 1.3, 1.4, 1.5],
        ys: vec![-0.1, 0.0, 0.1],
        zs: vec![0.25, 0.5],
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
            charts: None,
        });
    }
    let baseline = optimise::feasible_centre(&rows).unwrap().clone();
    let site = SiteGeometry::new(
        &model,
        &job,
        opt.best.placement.z,
        std::path::Path::new("paths/default.gcode"),
        None,
    );
    RunReport {
        title: "test <report> & co".into(),
        meta: vec![("robot".into(), model.name().into())],
        rows,
        names: None,
        grid: Some(grid),
        optimise: Some(opt),
        baseline: Some(("centre".into(), baseline)),
        details,
        electrical: model.drive.is_some(),
        site: Some(site),
    }
}

#[test]
fn report_is_well_formed_with_expected_figures() {
    let rep = report();
    let dir = std::env::temp_dir().join(format!("pw-report-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    rep.write(&dir).unwrap();
    let html = std::fs::read_to_string(dir.join("report.html")).unwrap();
    let doc = common::parse_xhtml(&html);
    let ids = common::figure_ids(&doc);
    for want in ["heatmap", "bars", "joints", "power-0", "power-1"] {
        assert!(ids.contains(&want), "figure {want} in {ids:?}");
    }
    let svgs = doc.descendants().filter(|n| n.has_tag_name("svg")).count();
    // top view, z slice, bars, supply, joints, power and cumulative energy at best and worst.
    assert_eq!(svgs, 9, "{ids:?}");
    // Infeasible cells are marked by reason and the optimum is marked.
    let classes: Vec<&str> = doc
        .descendants()
        .filter_map(|n| n.attribute("class"))
        .collect();
    assert!(classes.contains(&"mark-optimum"), "{classes:?}");
    assert!(classes.contains(&"mark-best-cell"), "{classes:?}");
    assert!(classes
        .iter()
        .any(|c| c.starts_with("mark-") && *c != "mark-optimum"));
    assert!(!html.contains("NaN") && !html.contains("\"inf\"") && !html.contains(">inf<"));
    assert!(html.contains("test &lt;report&gt; &amp; co"));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["placements"], 24);
    assert!(s["saving_pct"].as_f64().is_some());
    assert_eq!(s["details"][0]["joints"].as_array().unwrap().len(), 6);
    let csv = std::fs::read_to_string(dir.join("placements.csv")).unwrap();
    assert_eq!(csv.lines().count(), 25);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn compare_report_has_every_chart_and_stays_small() {
    let dir = std::env::temp_dir().join(format!("pw-compare-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    common::ok(
        common::bin()
            .args([
                "compare",
                "--robot",
                "robots/abb_irb4600_40_255",
                "--log",
                "results/identify_example/log.csv",
                "--out",
            ])
            .arg(&dir),
    );
    let html = std::fs::read_to_string(dir.join("report.html")).unwrap();
    // 5000 samples × 6 joints: decimated lines and thinned scatters keep it well under 1 MB.
    assert!(
        html.len() < 1_000_000,
        "report.html is {} bytes",
        html.len()
    );
    let doc = common::parse_xhtml(&html);
    let ids = common::figure_ids(&doc);
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
    // 5 charts per joint plus its binned residual against velocity, position and time
    // (where the model fails).
    for j in 1..=6 {
        for what in ["velocity", "position", "time"] {
            let want = format!("joint_{j}-profile-{what}-q{j}");
            assert!(ids.contains(&want.as_str()), "figure {want} in {ids:?}");
        }
    }
    assert_eq!(svgs.len(), 48);
    // Every chart has drawn data (a non-empty path), axis labels with units, and the
    // measured-vs-model charts a legend naming both.
    for s in &svgs {
        assert!(s
            .descendants()
            .any(|n| n.has_tag_name("path") && n.attribute("d").is_some_and(|d| d.len() > 100)));
        assert!(s.descendants().any(|n| n.text() == Some("residual [N·m]")
            || n.text() == Some("mean residual [N·m]")
            || n.text() == Some("torque τ [N·m]")));
    }
    assert!(html.contains(">measured<") && html.contains(">model<"));
    assert!(html.contains("joint 2 acceleration q̈ [rad/s²]"));
    assert!(!html.contains("NaN"));
    // The metrics table (six joints and the total) and the table of where the model fails
    // (the 15 largest of 6 joints × 5 structures).
    let rows = doc.descendants().filter(|n| n.has_tag_name("tr")).count();
    assert_eq!(rows, 1 + 7 + 1 + 15);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The top-view SVG of the shared report, parsed.
fn top_view_svg() -> String {
    report().heatmap_svg().expect("top view")
}

/// Attributes of every element with tag `tag` in `svg` (as (name, value) lists).
fn elements<'a>(doc: &'a roxmltree::Document, tag: &str) -> Vec<roxmltree::Node<'a, 'a>> {
    doc.descendants().filter(|n| n.has_tag_name(tag)).collect()
}

fn attr(n: &roxmltree::Node, a: &str) -> f64 {
    n.attribute(a)
        .and_then(|v| v.parse().ok())
        .unwrap_or(f64::NAN)
}

#[test]
fn heatmap_is_drawn_to_scale_with_robot_base_reach_and_part_outline() {
    let svg = top_view_svg();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    // Cells: 0.1 m × 0.1 m on the grid, so their drawn width and height must match (equal axis
    // scales; the old heatmap stretched x and y independently).
    let cells: Vec<_> = elements(&doc, "rect")
        .into_iter()
        .filter(|r| r.children().any(|c| c.has_tag_name("title")))
        .collect();
    assert_eq!(cells.len(), 4 * 3);
    for c in &cells {
        let (w, h) = (attr(c, "width"), attr(c, "height"));
        assert!((w - h).abs() < 0.05, "cell {w} × {h} px for 0.1 × 0.1 m");
    }
    let classes: Vec<&str> = doc
        .descendants()
        .filter_map(|n| n.attribute("class"))
        .collect();
    for want in ["base", "reach", "part at the optimum"] {
        assert!(classes.contains(&want), "{want} in {classes:?}");
    }
    // The reach circle's radius equals the annulus' outer radius at the same scale as the cells.
    let site = report().site.as_ref().unwrap();
    let (_, outer) = site.annulus_m.expect("annulus");
    // (cells are drawn 0.3 px wider than their share so neighbours do not show seams)
    let px_per_m = (attr(&cells[0], "width") - 0.3) / 0.1;
    let reach = elements(&doc, "circle")
        .into_iter()
        .find(|c| c.attribute("class") == Some("reach"))
        .unwrap();
    assert!(
        (attr(&reach, "r") - outer * px_per_m).abs() < 0.2 + 0.003 * px_per_m,
        "reach circle r = {} px, want {} px",
        attr(&reach, "r"),
        outer * px_per_m
    );
}

#[test]
fn heatmap_is_a_slice_at_the_best_bed_height_and_yaw_not_a_minimum() {
    let rep = report();
    let best_grid = &rep.optimise.as_ref().unwrap().best_grid;
    let svg = top_view_svg();
    let z = printwatt::report::svg::fmt_num(best_grid.placement.z);
    assert!(
        svg.contains(&format!("energy at bed z = {z} m")),
        "title names the slice"
    );
    // Every coloured cell shows the energy of the row at that bed height (and the grid's one
    // yaw and spin), not the minimum over both heights.
    let doc = roxmltree::Document::parse(&svg).unwrap();
    for c in elements(&doc, "rect") {
        let Some(t) = c.children().find(|n| n.has_tag_name("title")) else {
            continue;
        };
        let t = t.text().unwrap_or("");
        let Some((xy, v)) = t.split_once(": ") else {
            continue;
        };
        let Ok(v) = v.parse::<f64>() else { continue };
        let xy: Vec<f64> = xy
            .trim_matches(|c| c == '(' || c == ')')
            .split(", ")
            .map(|s| s.parse().unwrap())
            .collect();
        let row = rep
            .rows
            .iter()
            .find(|r| {
                (r.placement.x - xy[0]).abs() < 1e-9
                    && (r.placement.y - xy[1]).abs() < 1e-9
                    && (r.placement.z - best_grid.placement.z).abs() < 1e-9
            })
            .unwrap();
        let want = printwatt::report::svg::fmt_num(row.cost());
        assert_eq!(printwatt::report::svg::fmt_num(v), want, "cell {xy:?}");
    }
}

#[test]
fn colour_bar_covers_the_optimum() {
    let rep = report();
    let opt = rep.best().unwrap().cost();
    let svg = top_view_svg();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let bar = doc
        .descendants()
        .find(|n| n.attribute("class") == Some("cbar"))
        .unwrap();
    let (lo, hi) = (attr(&bar, "data-lo"), attr(&bar, "data-hi"));
    assert!(
        lo <= opt && opt <= hi,
        "optimum {opt} J outside the colour bar {lo}–{hi} J"
    );
}

#[test]
fn optimum_marker_sits_in_a_feasible_cell() {
    let rep = report();
    let svg = top_view_svg();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    // The ring marks the best grid cell; that cell must be coloured (feasible), not crossed.
    let ring = doc
        .descendants()
        .find(|n| n.attribute("class") == Some("mark-best-cell"))
        .expect("best-cell ring");
    let c = ring.children().find(|n| n.has_tag_name("circle")).unwrap();
    let (cx, cy) = (attr(&c, "cx"), attr(&c, "cy"));
    let cell = elements(&doc, "rect")
        .into_iter()
        .find(|r| {
            r.children().any(|t| t.has_tag_name("title"))
                && attr(r, "x") <= cx
                && cx <= attr(r, "x") + attr(r, "width")
                && attr(r, "y") <= cy
                && cy <= attr(r, "y") + attr(r, "height")
        })
        .expect("a cell under the ring");
    assert_ne!(
        cell.attribute("fill"),
        Some("#f2f2f2"),
        "ring on a grey cell"
    );
    let crossed = doc
        .descendants()
        .filter(|n| {
            n.attribute("class").is_some_and(|c| {
                c.starts_with("mark-") && c != "mark-best-cell" && c != "mark-optimum"
            })
        })
        .any(|g| {
            let l = g.children().find(|n| n.has_tag_name("line")).unwrap();
            let (x1, x2) = (attr(&l, "x1"), attr(&l, "x2"));
            let (y1, y2) = (attr(&l, "y1"), attr(&l, "y2"));
            (x1.min(x2)..=x1.max(x2)).contains(&cx) && (y1.min(y2)..=y1.max(y2)).contains(&cy)
        });
    assert!(!crossed, "the ring sits on a crossed cell");
    assert!(rep.optimise.as_ref().unwrap().best_grid.cost().is_finite());
}

#[test]
fn infeasible_cells_are_summarised_by_reason_with_details_collapsed() {
    let rep = report();
    let html = rep.html();
    let n_inf = rep.rows.iter().filter(|r| r.outcome.is_err()).count();
    assert!(n_inf > 0);
    let doc = common::parse_xhtml(&html);
    // The count table: one row per reason, counts adding up to the infeasible placements.
    let h2 = doc
        .descendants()
        .find(|n| n.has_tag_name("h2") && n.text() == Some("Infeasible placements by reason"))
        .expect("summary heading");
    let table = h2
        .next_siblings()
        .find(|n| n.has_tag_name("table"))
        .unwrap();
    let counts: usize = table
        .descendants()
        .filter(|n| n.has_tag_name("tr"))
        .skip(1)
        .map(|tr| {
            tr.children()
                .filter(|n| n.has_tag_name("td"))
                .nth(1)
                .and_then(|td| td.text())
                .unwrap()
                .parse::<usize>()
                .unwrap()
        })
        .sum();
    assert_eq!(counts, n_inf);
    // The per-placement rows live only inside a collapsed <details>.
    let details = doc
        .descendants()
        .find(|n| n.has_tag_name("details"))
        .expect("details");
    assert!(details.attribute("open").is_none());
    let rows_in_details = details
        .descendants()
        .filter(|n| n.has_tag_name("tr"))
        .count();
    assert_eq!(rows_in_details, n_inf + 1);
}

#[test]
fn the_report_files_made_at_once_are_those_made_one_by_one() {
    // RunReport::write_into makes summary.json, placements.csv and report.html at once where
    // the pool has threads free: each file is byte for byte what its own method makes, on 1
    // and 2 threads.
    let rep = report();
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let dir = std::env::temp_dir().join(format!(
            "pw-report-at-once-{}-{threads}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        pool.install(|| rep.write(&dir)).unwrap();
        let read = |f: &str| std::fs::read_to_string(dir.join(f)).unwrap();
        assert_eq!(
            read("summary.json"),
            rep.summary_json(true).unwrap(),
            "{threads}"
        );
        assert_eq!(read("placements.csv"), rep.placements_csv(), "{threads}");
        assert_eq!(read("report.html"), rep.html(), "{threads}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// The figure `id` of a page and its SVG (as text).
fn figure_svg(html: &str, id: &str) -> Option<String> {
    let i = html.find(&format!("<figure id=\"{id}\">"))?;
    let rest = &html[i..];
    let a = rest.find("<svg")?;
    let b = rest.find("</svg>")?;
    Some(rest[a..b + 6].to_string())
}

#[test]
fn energy_bars_start_above_zero_when_the_standby_dominates() {
    let rep = report();
    // The standby (cabinet × print time) is most of the supply here.
    let f = rep.best().unwrap().feasible().unwrap();
    assert!(
        f.standby_j > f.drives_j,
        "{} vs {}",
        f.standby_j,
        f.drives_j
    );
    let html = rep.html();
    let svg = figure_svg(&html, "bars").expect("bars figure");
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let from = elements(&doc, "text")
        .into_iter()
        .find(|t| t.attribute("class") == Some("axis-from"))
        .expect("the chart says where its bars start");
    let base = attr(&from, "data-baseline");
    // Not zero, below every bar, and within the standby every placement draws.
    let lowest = rep
        .rows
        .iter()
        .map(|r| r.cost())
        .filter(|c| c.is_finite())
        .fold(f64::INFINITY, f64::min);
    let standby = rep
        .rows
        .iter()
        .filter_map(|r| r.feasible())
        .map(|f| f.standby_j)
        .fold(f64::INFINITY, f64::min);
    assert!(
        base > 0.5 * standby && base <= standby && base < lowest,
        "{base} {standby} {lowest}"
    );
    // The lowest y tick is not 0 either: the axis starts at the standby.
    let ticks: Vec<f64> = elements(&doc, "text")
        .iter()
        .filter(|t| t.attribute("text-anchor") == Some("end"))
        .filter_map(|t| t.text()?.parse().ok())
        .collect();
    assert!(ticks.iter().all(|t| *t >= base), "{ticks:?} from {base}");
    let caption = &html[html.find("<figure id=\"bars\">").unwrap()..];
    let caption =
        &caption[caption.find("<figcaption>").unwrap()..caption.find("</figcaption>").unwrap()];
    assert!(caption.contains("standby"), "{caption}");
}

#[test]
fn a_sweep_report_caption_describes_only_what_its_top_view_draws() {
    let mut rep = report().clone();
    rep.optimise = None;
    rep.baseline = None;
    let html = rep.html();
    let svg = figure_svg(&html, "heatmap").unwrap();
    assert!(
        !svg.contains("mark-optimum"),
        "a sweep has no refined optimum"
    );
    let i = html.find("<figure id=\"heatmap\">").unwrap();
    let cap = &html[i..];
    let cap = &cap[cap.find("<figcaption>").unwrap()..cap.find("</figcaption>").unwrap()];
    assert!(!cap.contains("refined optimum"), "{cap}");
    assert!(!cap.contains("optimum"), "{cap}");
    assert!(
        cap.contains("the ring marks the best placement of the sweep"),
        "{cap}"
    );
    // No answer card without an optimisation; the optimise report has one.
    assert!(!html.contains("id=\"answer\""));
    assert!(report().html().contains("<section id=\"answer\""));
}

#[test]
fn a_yaw_slice_with_one_feasible_point_is_said_in_words_not_drawn() {
    // The report's 24 rows read as a grid of 4 × 3 × 1 bed heights × 2 yaws, every row of the
    // second yaw made infeasible.
    let mut rep = report().clone();
    let g = Grid {
        xs: vec![1.2, 1.3, 1.4, 1.5],
        ys: vec![-0.1, 0.0, 0.1],
        zs: vec![0.5],
        yaws: vec![std::f64::consts::FRAC_PI_2, std::f64::consts::PI],
        spins: vec![0.0],
    };
    let bad = rep
        .rows
        .iter()
        .find(|r| r.outcome.is_err())
        .unwrap()
        .outcome
        .clone();
    for ix in 0..4 {
        for iy in 0..3 {
            rep.rows[g.index(ix, iy, 0, 1, 0)].outcome = bad.clone();
        }
    }
    rep.grid = Some(g);
    let html = rep.html();
    assert!(figure_svg(&html, "slice-yaw").is_none());
    assert!(
        html.contains(
            "Energy against yaw through the best grid cell: only 1 of the 2 yaws is feasible, 90°:"
        ),
        "no words for the lone point"
    );
}

#[test]
fn top_view_stacks_labels_at_one_spot_and_draws_infeasible_points_with_their_own_symbol() {
    use printwatt::report::svg::{self, MapPoint, TopView};
    let p = |label: &str, value: f64| MapPoint {
        x: 1.5,
        y: 0.0,
        label: label.into(),
        value,
        class: "named".into(),
    };
    let v = TopView {
        points: vec![p("P1@0°", 100.0), p("P1@45°", 110.0), p("P1@90°", f64::NAN)],
        circles: vec![
            (0.0, 0.0, 2.6, "reach".into(), "reach 0.8–2.6 m".into()),
            (0.0, 0.0, 0.8, "reach-inner".into(), "inner reach".into()),
        ],
        value_label: "energy [J]".into(),
        ..Default::default()
    };
    let s = svg::top_view(&svg::Frame::new("t", "x", "y").size(900.0, 640.0), &v);
    let doc = roxmltree::Document::parse(&s).unwrap();
    let labels: Vec<(String, f64)> = elements(&doc, "text")
        .iter()
        .filter(|t| t.text().is_some_and(|x| x.starts_with("P1@")))
        .map(|t| (t.text().unwrap().to_string(), attr(t, "y")))
        .collect();
    assert_eq!(labels.len(), 3);
    for i in 0..3 {
        for j in 0..i {
            assert!(
                (labels[i].1 - labels[j].1).abs() >= 11.0,
                "overprinted: {labels:?}"
            );
        }
    }
    // The infeasible one: a cross (no circle, unlike the inner reach's hollow circle), and the
    // legend names it.
    let g = doc
        .descendants()
        .find(|n| n.attribute("data-infeasible") == Some("1"))
        .expect("an infeasible mark");
    assert!(g.descendants().all(|n| !n.has_tag_name("circle")));
    assert!(g.descendants().any(|n| n.has_tag_name("path")));
    assert!(s.contains(">infeasible placement</text>"));
}

#[test]
fn the_answer_card_states_the_energy_the_cli_prints_and_the_uncertainty_is_drawn() {
    let d = std::env::temp_dir().join(format!("pw-answer-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    let o = common::ok(
        common::bin()
            .args([
                "optimise",
                "--x",
                "1.3,1.5,3",
                "--y",
                "-0.1,0.1,3",
                "--z",
                "0.5",
                "--yaw",
                "90",
                "--max-evals",
                "10",
                "--uncertainty",
                "6",
                "--out",
            ])
            .arg(&d),
    );
    let out = String::from_utf8_lossy(&o.stdout);
    let energy = out
        .lines()
        .find_map(|l| l.strip_prefix("energy "))
        .and_then(|l| l.split(" J").next())
        .unwrap_or_else(|| panic!("no energy line in {out}"))
        .to_string();
    let html = std::fs::read_to_string(d.join("report.html")).unwrap();
    let doc = common::parse_xhtml(&html);
    let card = doc
        .descendants()
        .find(|n| n.attribute("id") == Some("answer"))
        .expect("an answer card");
    // First on the page, after the title.
    let first = doc
        .descendants()
        .find(|n| n.has_tag_name("body"))
        .unwrap()
        .children()
        .filter(|n| n.is_element())
        .nth(1)
        .unwrap();
    assert_eq!(first.attribute("id"), Some("answer"));
    let text: String = card
        .descendants()
        .filter_map(|n| n.text())
        .collect::<Vec<_>>()
        .join(" ");
    assert!(
        text.contains(&format!("energy {energy} J")),
        "{energy} not in {text}"
    );
    for want in [
        "drives ",
        "standby ",
        "against the baseline",
        "placement tolerance: holds",
        "over 6 robots drawn",
        "expected regret",
        "robot file: robots/abb_irb6700_200_260/drive.toml",
        "drive data: ESTIMATE: ",
        "margins: joint-limit margin",
        "path: paths/default.gcode",
        "print speed: 150 mm/s",
    ] {
        assert!(text.contains(want), "{want} not in {text}");
    }
    // The uncertainty study as a chart: one bar per band of regret, the draws counted.
    let svg = figure_svg(&html, "uncertainty").expect("uncertainty chart");
    let u = roxmltree::Document::parse(&svg).unwrap();
    let counted: f64 = elements(&u, "rect")
        .iter()
        .filter_map(|r| r.children().find(|c| c.has_tag_name("title")))
        .filter_map(|t| t.text()?.rsplit(": ").next()?.parse::<f64>().ok())
        .sum();
    assert_eq!(counted, 6.0, "{svg}");
    let _ = std::fs::remove_dir_all(&d);
}
