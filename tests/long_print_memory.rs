//! A long print is optimised without per-sample series: a placement reported in detail has its
//! energy integrated sample by sample into the report's figures and charts (the charts keep
//! their decimated points only), and `--json` answers are written straight from the typed
//! result, numbers rounded as they are written, without a JSON value tree in between. Both
//! give the same bytes as before.
//!
//! The memory is measured in this process by a counting global allocator (the peak of bytes
//! allocated and not yet freed); the tests take a lock so that one measures at a time.

mod common;
#[path = "common/wall.rs"]
mod wall;

use printwatt::evaluate::feasibility::FeasibilityOptions;
use printwatt::evaluate::{Evaluator, Objective};
use printwatt::frame::Placement;
use printwatt::report::placement::{Detail, RunReport};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let p = System.alloc(l);
        if !p.is_null() {
            let now = LIVE.fetch_add(l.size(), Ordering::Relaxed) + l.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        System.dealloc(p, l);
        LIVE.fetch_sub(l.size(), Ordering::Relaxed);
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

/// `f`'s result and the peak of bytes it held beyond what was live when it started.
fn peak_of<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let base = LIVE.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let r = f();
    (r, PEAK.load(Ordering::Relaxed).saturating_sub(base))
}

fn report(details: Vec<Detail>, rows: Vec<printwatt::evaluate::Evaluated>) -> RunReport {
    RunReport {
        title: "wall".into(),
        meta: Vec::new(),
        rows,
        names: None,
        grid: None,
        optimise: None,
        baseline: None,
        details,
        electrical: true,
        site: None,
    }
}

#[test]
fn optimising_a_long_print_holds_no_per_sample_series() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner());
    let model = common::robot("abb_irb6700_200_260");
    let text = wall::wall_gcode(1800.0, 600.0, 4.0, 8);
    let tp = printwatt::toolpath::parse_gcode(
        &text,
        "wall8.gcode",
        &printwatt::toolpath::ReadOptions::default(),
    )
    .unwrap();
    let job = common::default_job(&model, &tp);
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    // The first feasible placement of a few in front of the robot.
    let mut sc = ev.scratch().unwrap();
    let e = [
        (0.9, 0.15, 1.3),
        (1.2, 0.0, 1.0),
        (1.6, 0.0, 0.0),
        (1.4, 0.0, 0.5),
    ]
    .iter()
    .map(|&(x, y, z)| ev.evaluate(&mut sc, &Placement::new(x, y, z, 94f64.to_radians())))
    .find(|e| e.feasible().is_some())
    .expect("the wall is feasible in front of the robot");
    let at = e.placement;
    let samples = e.feasible().unwrap().samples;
    // The detail as the optimisation and the sweep report it, and as it was made before:
    // the whole per-sample series kept.
    let (d, streamed) = peak_of(|| {
        printwatt::search::run::detail(&job, "best", &e)
            .unwrap()
            .unwrap()
    });
    let (full, whole) = peak_of(|| job.evaluate(&at).unwrap().unwrap());
    let per = |b: usize| b as f64 / samples as f64;
    eprintln!(
        "{samples} samples: the detail peaks at {:.0} bytes a sample (timed path included), the whole series at {:.0}",
        per(streamed),
        per(whole)
    );
    assert!(d.energy.series.t.is_empty() && d.charts.is_some());
    // The same figures, bit for bit, and the same report, byte for byte.
    assert_eq!(d.energy.joints, full.energy.joints);
    assert_eq!(d.energy.total, full.energy.total);
    let old = Detail {
        label: "best".into(),
        eval: e.clone(),
        energy: full.energy,
        charts: None,
    };
    assert_eq!(
        report(vec![d], vec![e.clone()]).html(),
        report(vec![old], vec![e]).html(),
        "the charts drawn from the streamed series differ from those of the whole series"
    );
    // Timing sets the detail's peak; keeping the series (26 numbers, 208 bytes a sample) on
    // top of the timed path raises the peak by more than 50 bytes a sample.
    assert!(
        per(whole) - per(streamed) >= 50.0,
        "the detail holds {:.0} bytes a sample, the whole series {:.0}",
        per(streamed),
        per(whole)
    );
}

/// Rows shaped as a sweep's: floats at every scale, nested objects, arrays, options, enums.
#[derive(serde::Serialize)]
struct Row {
    status: &'static str,
    x_m: f64,
    energy_j: f64,
    small: f64,
    samples: usize,
    joints: Vec<f64>,
    reason: Option<Kind>,
    losses: std::collections::BTreeMap<String, f64>,
}

#[derive(serde::Serialize)]
#[serde(rename_all = "snake_case")]
enum Kind {
    Reach,
    Margins { joint: usize, left_deg: f64 },
}

#[test]
fn sweep_json_is_written_without_a_value_tree() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner());
    let mut r = common::xorshift(3);
    let rows: Vec<Row> = (0..20_000)
        .map(|i| Row {
            status: if i % 3 == 0 { "infeasible" } else { "feasible" },
            x_m: r() * 3.0 - 1.5,
            energy_j: 1e4 + r() * 1e5,
            small: r() * 1e-9,
            samples: i * 17,
            joints: (0..6).map(|_| r() * 1e3 - 500.0).collect(),
            reason: match i % 3 {
                0 => Some(Kind::Margins {
                    joint: i % 6 + 1,
                    left_deg: 0.1 * i as f64,
                }),
                1 => Some(Kind::Reach),
                _ => None,
            },
            losses: [("friction_j", 0.1 + r()), ("copper_j", r() * 3.0)]
                .into_iter()
                .map(|(k, v)| (k.to_string(), v))
                .collect(),
        })
        .collect();
    let warnings = serde_json::json!(["a warning"]);
    let (text, direct) = peak_of(|| {
        #[derive(serde::Serialize)]
        struct Doc<'a> {
            title: &'a str,
            rows: &'a [Row],
        }
        printwatt::output::json_text_with(
            &Doc {
                title: "sweep",
                rows: &rows,
            },
            &[("warnings", warnings.clone())],
        )
        .unwrap()
    });
    // What it replaces: a value tree, rounded, the warnings added, printed.
    let (old, tree) = peak_of(|| {
        let mut v =
            serde_json::json!({ "title": "sweep", "rows": serde_json::to_value(&rows).unwrap() });
        printwatt::output::finish_json(&mut v);
        v["warnings"] = warnings.clone();
        serde_json::to_string_pretty(&v).unwrap()
    });
    assert!(text == old, "the JSON text differs from the value tree's");
    eprintln!(
        "{} bytes of JSON: written directly at a peak of {direct} bytes, through a value tree {tree}",
        text.len()
    );
    // The text, its pieces while an object is put in key order, and the output: within 3.5
    // times the text; a value tree alone is several times the text.
    assert!(
        (direct as f64) < 3.5 * text.len() as f64,
        "{direct} bytes for {} bytes of JSON",
        text.len()
    );
}

#[test]
fn a_long_prints_full_evaluation_holds_its_positions_and_no_per_sample_rates_or_sines() {
    // A wall of more than LEAN_SAMPLES samples evaluated in full (the answer's confirmation,
    // a reduced evaluation's fallback): the timed path's positions, TCP points and times
    // (80 bytes a sample for a six-axis arm, and the tips mapped to the base frame while it
    // is tracked, 24) are what it holds; the velocities and accelerations (96 bytes more) are
    // derived a block at a time where they are used, the sines and cosines of every sample
    // (96 bytes more) are not kept, and the scratch is left without buffers.
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner());
    let model = common::robot("abb_irb6700_200_260");
    let text = wall::wall_gcode(1800.0, 600.0, 4.0, 24);
    let tp = printwatt::toolpath::parse_gcode(
        &text,
        "wall24.gcode",
        &printwatt::toolpath::ReadOptions::default(),
    )
    .unwrap();
    let job = common::default_job(&model, &tp);
    let samples = job.plan.motion.p.len();
    assert!(
        samples >= printwatt::evaluate::evaluator::LEAN_SAMPLES,
        "{samples}"
    );
    let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
    // The first feasible placement of a few in front of the robot, each evaluated with a
    // fresh scratch.
    let (e, peak, kept, sc) = [(1.6, 0.0, 0.0), (1.4, 0.0, 0.5), (1.2, 0.0, 1.0)]
        .iter()
        .map(|&(x, y, z)| {
            let at = Placement::new(x, y, z, 94f64.to_radians());
            let mut sc = ev.scratch().unwrap();
            let before = LIVE.load(Ordering::Relaxed);
            let (e, peak) = peak_of(|| ev.evaluate_full(&mut sc, &at));
            let kept = LIVE.load(Ordering::Relaxed).saturating_sub(before);
            (e, peak, kept, sc)
        })
        .find(|r| r.0.feasible().is_some())
        .expect("the wall is feasible in front of the robot");
    let f = e.feasible().unwrap();
    assert_eq!(f.samples, samples);
    let per = peak as f64 / samples as f64;
    eprintln!("{samples} samples: a full evaluation peaks at {per:.0} bytes a sample");
    assert!(
        per < 130.0,
        "a full evaluation of a long print holds {per:.0} bytes a sample (positions, TCP points, times and tips: about 104)"
    );
    // Nothing is left in the scratch for a next placement (a short path's scratch keeps its
    // buffers: here they would be tens of megabytes).
    assert!(
        kept < 1 << 20,
        "the scratch keeps {kept} bytes after a long print's full evaluation"
    );
    drop(sc);
}
