//! `printwatt inspect`: the inspection of a path agrees with the path's own points, and a bad
//! file is an error naming the file and the line.

use std::f64::consts::TAU;
use std::path::{Path, PathBuf};
use std::process::Command;

use printwatt::toolpath::inspect::{inspect, Format};
use printwatt::toolpath::{load, PathUnits, ReadOptions};

fn root(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("printwatt-inspect-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// The default path is a 2000 × 1000 mm rectangle with 100 mm corner arcs, one layer: its
/// box, length and layer count from its own points agree with the inspection.
#[test]
fn inspect_counts_the_default_paths_length_layers_and_box() {
    let file = root("paths/default.gcode");
    let opts = ReadOptions::default();
    let tp = load(&file, &opts).unwrap();
    let ins = inspect(&tp, &file, &opts);
    assert_eq!(ins.format, Format::Gcode);
    assert!(!ins.mm_assumed);
    assert_eq!(ins.moves, tp.moves.len());
    assert_eq!(ins.print_moves + ins.travel_moves, ins.moves);

    // The box of the start and end points (the corner arcs end on the box's sides).
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in std::iter::once(tp.start).chain(tp.moves.iter().map(|m| m.end)) {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let b = ins.bounding_box.expect("a box");
    for k in 0..3 {
        assert!(close(b.min_m[k], lo[k], 1e-9), "min {k}: {b:?} vs {lo:?}");
        assert!(close(b.max_m[k], hi[k], 1e-9), "max {k}: {b:?} vs {hi:?}");
    }
    // 2 m × 1 m, as the file's header says.
    assert!(close(hi[0] - lo[0], 2.0, 1e-9) && close(hi[1] - lo[1], 1.0, 1e-9));

    // Length: the straight sides between the arcs plus one full circle of radius 0.1 m.
    let r = 0.1;
    let (w, h) = (hi[0] - lo[0], hi[1] - lo[1]);
    let expected = 2.0 * (w - 2.0 * r) + 2.0 * (h - 2.0 * r) + TAU * r;
    let total = ins.print_length_m + ins.travel_length_m;
    assert!(close(total, expected, 1e-6), "{total} vs {expected}");

    // Layers: distinct z of the print moves' ends.
    let mut zs: Vec<f64> = tp
        .moves
        .iter()
        .filter(|m| m.print)
        .map(|m| m.end.z)
        .collect();
    zs.sort_by(f64::total_cmp);
    zs.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    assert_eq!(ins.layers, zs.len());
    assert_eq!(ins.layers, 1);

    // Time at the commanded speed: each move's length over its speed.
    let t: f64 = tp.segments().map(|(s, m)| m.length(&s) / m.speed).sum();
    assert!(close(ins.duration_at_commanded_speed_s, t, 1e-9));
    let v: Vec<f64> = tp.moves.iter().map(|m| m.speed).collect();
    let ps = ins.print_speed.expect("print speeds");
    assert_eq!(ps.min_m_s, v.iter().cloned().fold(f64::INFINITY, f64::min));
    assert_eq!(ps.max_m_s, v.iter().cloned().fold(0.0, f64::max));
}

/// A CSV without units: mm assumed and said so; print and travel split by the `print` column.
#[test]
fn inspect_splits_print_and_travel_of_a_csv_and_says_mm_was_assumed() {
    let d = scratch("csv");
    let file = d.join("wall.csv");
    std::fs::write(
        &file,
        "x,y,z,print\n0,0,20,1\n2000,0,20,1\n2000,1000,20,1\n2000,1000,40,0\n0,0,40,1\n",
    )
    .unwrap();
    let opts = ReadOptions::default();
    let tp = load(&file, &opts).unwrap();
    let ins = inspect(&tp, &file, &opts);
    assert_eq!(ins.format, Format::Csv);
    assert!(ins.mm_assumed, "{ins:?}");
    assert_eq!((ins.moves, ins.print_moves, ins.travel_moves), (4, 3, 1));
    let diag = (2.0f64).hypot(1.0);
    assert!(close(ins.print_length_m, 2.0 + 1.0 + diag, 1e-9));
    assert!(close(ins.travel_length_m, 0.02, 1e-9));
    assert_eq!(ins.layers, 2);

    // Stated in metres: nothing assumed, the same geometry.
    let opts_m = ReadOptions {
        path_units: Some(PathUnits::M),
        ..Default::default()
    };
    std::fs::write(
        &file,
        "x,y,z,print\n0,0,0.02,1\n2,0,0.02,1\n2,1,0.02,1\n2,1,0.04,0\n0,0,0.04,1\n",
    )
    .unwrap();
    let tp = load(&file, &opts_m).unwrap();
    let ins_m = inspect(&tp, &file, &opts_m);
    assert!(!ins_m.mm_assumed);
    assert!(close(ins_m.print_length_m, ins.print_length_m, 1e-9));
    let _ = std::fs::remove_dir_all(&d);
}

/// A malformed file: the command fails, naming the file and the line; never a panic.
#[test]
fn inspect_of_a_bad_file_is_an_error_naming_the_file_and_line() {
    let d = scratch("bad");
    let file = d.join("bad.gcode");
    std::fs::write(
        &file,
        "G21\nG90\nG1 X0 Y0 Z0 F6000\nG1 X100 Y0 E1\nG1 X100 Yabc E2\n",
    )
    .unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .arg("inspect")
        .arg(&file)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("bad.gcode") && err.contains(":5"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    // A missing file too.
    let o = Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .arg("inspect")
        .arg(d.join("missing.csv"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("missing.csv"), "{err}");
    let _ = std::fs::remove_dir_all(&d);
}
