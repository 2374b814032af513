//! Every HTML report rendered in a real browser (headless Chromium): the committed reports under
//! `results/` and freshly written optimise, P1–P5 sweep and compare reports. A page fails when
//! it renders blank, logs a script error, or holds an SVG chart without data (`data-n` = 0).
//!
//! `.ci/run` installs Debian's `chromium` when it is missing. Locally: `apt-get install
//! chromium`, or point `PRINTWATT_CHROMIUM` at a Chromium/Chrome binary. Without one the test
//! fails and says so (set `PRINTWATT_SKIP_BROWSER=1` to skip it knowingly).

mod common;

use common::root;
use std::path::{Path, PathBuf};
use std::process::Command;

fn chromium() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("PRINTWATT_CHROMIUM") {
        return Some(PathBuf::from(p));
    }
    let path = std::env::var_os("PATH")?;
    for dir in std::env::split_paths(&path) {
        for name in ["chromium", "chromium-browser", "google-chrome"] {
            let p = dir.join(name);
            if p.is_file() {
                return Some(p);
            }
        }
    }
    None
}

/// Render `page` headless; returns (DOM after load, browser log).
fn render(bin: &Path, page: &Path) -> (String, String) {
    static N: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let k = N.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let profile = std::env::temp_dir().join(format!("pw-chromium-{}-{k}", std::process::id()));
    let _ = std::fs::remove_dir_all(&profile);
    let out = Command::new(bin)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--enable-logging=stderr",
            "--v=0",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg("--dump-dom")
        .arg(format!(
            "file://{}",
            page.canonicalize().expect("report exists").display()
        ))
        .output()
        .expect("chromium runs");
    let _ = std::fs::remove_dir_all(&profile);
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// What is wrong with a rendered page (empty = nothing).
fn problems(dom: &str, log: &str) -> Vec<String> {
    let mut p = Vec::new();
    // Blank: no body text beyond markup.
    let mut body = dom.split("<body").nth(1).unwrap_or("").to_string();
    for tag in ["script", "style"] {
        while let Some(a) = body.find(&format!("<{tag}")) {
            let close = format!("</{tag}>");
            let b = body[a..]
                .find(&close)
                .map_or(body.len(), |b| a + b + close.len());
            body.replace_range(a..b, "");
        }
    }
    let text: String = {
        let mut t = String::new();
        let mut in_tag = false;
        for c in body.chars() {
            match c {
                '<' => in_tag = true,
                '>' => in_tag = false,
                c if !in_tag && !c.is_whitespace() => t.push(c),
                _ => {}
            }
        }
        t
    };
    if text.chars().count() < 20 {
        p.push(format!("blank page ({} characters of text)", text.len()));
    }
    for line in log.lines().filter(|l| l.contains(":CONSOLE")) {
        if line.contains("Uncaught") || line.contains("Error") {
            p.push(format!("script error: {line}"));
        }
    }
    for (i, svg) in dom.split("<svg").skip(1).enumerate() {
        let tag = svg.split('>').next().unwrap_or("");
        let n = tag
            .split("data-n=\"")
            .nth(1)
            .and_then(|r| r.split('"').next())
            .and_then(|v| v.parse::<usize>().ok());
        // Charts say how many data items they draw; a page written before that attribute
        // existed is judged by its drawing: a path with points, a marker or a bar.
        let body = svg.split("</svg>").next().unwrap_or("");
        let drawn = body.matches("<path").count()
            + body.matches("<circle").count()
            + body.matches("<rect").count().saturating_sub(1);
        match n {
            Some(0) => p.push(format!("SVG #{i} has no data")),
            None if drawn == 0 => p.push(format!("SVG #{i} draws nothing")),
            _ => {}
        }
    }
    p
}

fn run(args: &[&str]) {
    let out = Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .current_dir(root())
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "printwatt {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn reports_under(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        // Local scratch runs (git-ignored) are not committed reports.
        if p.is_dir() && !p.ends_with("results/runs") && !p.ends_with("results/tmp") {
            reports_under(&p, out);
        } else if p.file_name().is_some_and(|n| n == "report.html") {
            out.push(p);
        }
    }
}

#[test]
fn the_browser_check_catches_blank_pages_script_errors_and_empty_charts() {
    let Some(bin) = chromium() else {
        assert!(
            std::env::var_os("PRINTWATT_SKIP_BROWSER").is_some(),
            "no Chromium found: `apt-get install chromium` (.ci/run does), set PRINTWATT_CHROMIUM, or PRINTWATT_SKIP_BROWSER=1"
        );
        return;
    };
    let dir = std::env::temp_dir().join(format!("pw-browser-neg-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.html");
    std::fs::write(
        &bad,
        r#"<!DOCTYPE html><html><body><svg xmlns="http://www.w3.org/2000/svg" data-n="0"></svg><script>undefinedFunction();</script></body></html>"#,
    )
    .unwrap();
    let (dom, log) = render(&bin, &bad);
    let p = problems(&dom, &log);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(p.iter().any(|x| x.starts_with("blank page")), "{p:?}");
    assert!(
        p.iter().any(|x| x.starts_with("script error")),
        "{p:?}\n{log}"
    );
    assert!(p.iter().any(|x| x.contains("has no data")), "{p:?}");
}

#[test]
fn every_report_renders_in_a_browser_with_data_in_every_chart() {
    let Some(bin) = chromium() else {
        assert!(
            std::env::var_os("PRINTWATT_SKIP_BROWSER").is_some(),
            "no Chromium found: `apt-get install chromium` (.ci/run does), set PRINTWATT_CHROMIUM, or PRINTWATT_SKIP_BROWSER=1"
        );
        return;
    };
    let tmp = std::env::temp_dir().join(format!("pw-browser-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    let t = tmp.to_str().unwrap();
    // Fresh reports of each kind: optimise on a small grid, the seed-000 P1–P5 sweep (map with
    // the paper's values), a compare report and a stations plan.
    run(&[
        "optimise",
        "--x",
        "1.2:1.5:0.1",
        "--y",
        "-0.1:0.1:0.1",
        "--z",
        "0.25,0.5",
        "--yaw",
        "90",
        "--max-evals",
        "10",
        "--results-dir",
        t,
        "--run",
        "opt",
    ]);
    run(&[
        "sweep",
        "--path",
        "paths/seed000_test_path.gcode",
        "--set",
        "paths/placements/p1-p5.csv",
        "--z",
        "0.2",
        "--objective",
        "mechanical_abs",
        "--results-dir",
        t,
        "--run",
        "p15",
    ]);
    run(&[
        "compare",
        "--robot",
        "robots/abb_irb4600_40_255",
        "--log",
        "results/identify_example/log.csv",
        "--out",
        &format!("{t}/compare"),
    ]);
    run(&[
        "stations",
        "--path",
        "paths/floor_four_rooms.gcode",
        "--relocation-cost",
        "20000",
        "--track",
        "-1,1.5:13,1.5",
        "--wrist-margin",
        "0",
        "--out",
        &format!("{t}/stations"),
    ]);
    let mut pages = Vec::new();
    reports_under(&tmp, &mut pages);
    assert_eq!(pages.len(), 4, "{pages:?}");
    let p15 = std::fs::read_to_string(tmp.join("p15/report.html")).unwrap();
    assert!(p15.contains("Ours beside the paper") && p15.contains("2497.6"));
    reports_under(&root().join("results"), &mut pages);
    // Two browsers at a time (2 cores).
    let failures: Vec<String> = std::thread::scope(|s| {
        let chunks: Vec<Vec<PathBuf>> = vec![
            pages.iter().step_by(2).cloned().collect(),
            pages.iter().skip(1).step_by(2).cloned().collect(),
        ];
        let hs: Vec<_> = chunks
            .into_iter()
            .map(|c| {
                let bin = bin.clone();
                s.spawn(move || {
                    c.iter()
                        .flat_map(|p| {
                            let (dom, log) = render(&bin, p);
                            problems(&dom, &log)
                                .into_iter()
                                .map(|e| format!("{}: {e}", p.display()))
                                .collect::<Vec<_>>()
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        hs.into_iter().flat_map(|h| h.join().unwrap()).collect()
    });
    let _ = std::fs::remove_dir_all(&tmp);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
