//! Real slicer G-code from Cura and Bambu Studio (a one-layer plate and a printed 50-layer
//! cube) beside the PrusaSlicer files: each reads, its layers are the slicer's own markers
//! (`;LAYER:n`, `;LAYER_CHANGE`, `; CHANGE_LAYER`), and its energy at a placement is finite
//! and plausible. The files and how they were made:
//! `tests/data/slicer/README.md`.

use std::path::PathBuf;
use std::process::Command;

use printwatt::toolpath::{load, parse_gcode, ReadOptions, Toolpath};

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/slicer")
        .join(name)
}

fn read(name: &str) -> (Toolpath, String) {
    let f = data(name);
    let tp = load(&f, &ReadOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}"));
    (tp, std::fs::read_to_string(&f).unwrap())
}

/// Lines that are exactly the marker (after trimming), or start with it for Cura's `;LAYER:n`.
fn markers(text: &str, marker: &str) -> usize {
    text.lines()
        .filter(|l| {
            let l = l.trim();
            if marker == ";LAYER:" {
                l.strip_prefix(marker)
                    .is_some_and(|n| n.parse::<i64>().is_ok())
            } else {
                l == marker
            }
        })
        .count()
}

/// `printwatt energy` at a placement: (time s, supply energy J).
fn energy(name: &str, extra: &[&str]) -> (f64, f64) {
    let out = Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .arg("energy")
        .arg("--path")
        .arg(data(name))
        .args(extra)
        .arg("--no-csv")
        .output()
        .expect("run printwatt");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(text.contains("feasible (the checks"), "{name}: {text}");
    let num = |prefix: &str| -> f64 {
        let l = text
            .lines()
            .find(|l| l.starts_with(prefix))
            .unwrap_or_else(|| panic!("no `{prefix}` in {text}"));
        l[prefix.len()..]
            .split_whitespace()
            .next()
            .and_then(|w| w.parse().ok())
            .unwrap_or_else(|| panic!("no number in `{l}`"))
    };
    (num("time"), num("supply energy"))
}

#[test]
fn a_cura_file_reads_with_one_layer_per_layer_marker() {
    let (tp, text) = read("cura_box_20mm.gcode");
    // Cura writes ;LAYER_COUNT:67 and ;LAYER:0 … ;LAYER:66.
    assert!(text.contains(";LAYER_COUNT:67"));
    assert_eq!(markers(&text, ";LAYER:"), 67);
    assert_eq!(tp.layer_starts.len(), 67);
    assert_eq!(tp.layers(), 67);
    // Every print move lies in its marked layer: layer k at z = 0.3 (k + 1) mm.
    let mut checked = 0;
    for (i, m) in tp.moves.iter().enumerate() {
        let layer = tp.layer_of(i);
        if i > 0 {
            assert!(layer >= tp.layer_of(i - 1), "move {i}");
        }
        if let (true, Some(k)) = (m.print, layer) {
            let z = 0.3e-3 * (k + 1) as f64;
            assert!(
                (m.end.z - z).abs() < 1e-7,
                "line {}: z {} in layer {k}",
                m.line,
                m.end.z
            );
            checked += 1;
        }
    }
    assert!(checked > 2000, "{checked}");
    // The start code makes no move (Cura's prime is E only): the first move opens layer 0.
    assert_eq!(tp.layer_starts[0], 0);
    assert_eq!(tp.layer_of(0), Some(0));
    // Cura's ;TYPE: features are kept as boundaries.
    let names: Vec<&str> = tp.features.iter().map(|f| f.name.as_str()).collect();
    for n in ["WALL-OUTER", "WALL-INNER", "SKIN", "FILL"] {
        assert!(names.contains(&n), "{n}: {names:?}");
    }
    assert!(tp
        .features
        .windows(2)
        .all(|w| w[0].first_move <= w[1].first_move));
}

#[test]
fn a_bambu_studio_file_reads_with_its_change_layer_marker_and_text_m_codes() {
    let (tp, text) = read("bambustudio_plate_1layer.gcode");
    assert!(text.contains("; BambuStudio 02.04.00.70"));
    assert!(text.contains("M1002 gcode_claim_action : 2"));
    assert!(text.contains("G380 S2 Z30 F1200"));
    assert_eq!(markers(&text, "; CHANGE_LAYER"), 1);
    assert_eq!(tp.layer_starts.len(), 1);
    assert_eq!(tp.layers(), 1);
    let names: Vec<&str> = tp.features.iter().map(|f| f.name.as_str()).collect();
    assert!(names.contains(&"Outer wall"), "{names:?}");
    assert!(names.contains(&"Bottom surface"), "{names:?}");
    // Bambu's probing move G380 and bed levelling G29.x are not path points.
    let w = tp.warnings.join("\n");
    assert!(w.contains("G380") && w.contains("G29.1"), "{w}");
}

#[test]
fn a_printed_bambu_studio_cube_reads_as_fifty_layers_of_extruded_moves_and_arcs() {
    let (tp, text) = read("bambustudio_a1mini_cube_50layers.gcode");
    assert!(text.contains("; BambuStudio 02.01.01.52"));
    assert!(text.contains("; enable_arc_fitting = 1"));
    assert_eq!(markers(&text, "; CHANGE_LAYER"), 50);
    assert_eq!(tp.layer_starts.len(), 50);
    assert_eq!(tp.layers(), 50);
    // Relative extrusion (M83) with real E words: the part's moves are print moves, layer k
    // printed at z = 0.2 (k + 1) mm, in layer order.
    let mut printed = vec![0usize; 50];
    for (i, m) in tp.moves.iter().enumerate() {
        let Some(k) = tp.layer_of(i) else { continue };
        if i > 0 && tp.layer_of(i - 1).is_some() {
            assert!(k >= tp.layer_of(i - 1).unwrap(), "move {i}");
        }
        if m.print {
            let z = 0.2e-3 * (k + 1) as f64;
            assert!(
                (m.end.z - z).abs() < 1e-6,
                "line {}: z {} in layer {k}",
                m.line,
                m.end.z
            );
            printed[k] += 1;
        }
    }
    assert!(printed.iter().all(|&n| n > 0), "{printed:?}");
    assert!(printed.iter().sum::<usize>() > 1500, "{printed:?}");
    // Arc fitting is on: the G2/G3 moves are read as arcs, not chords.
    let arcs = tp
        .moves
        .iter()
        .filter(|m| matches!(m.kind, printwatt::toolpath::MoveKind::Arc { .. }))
        .count();
    let g23 = text
        .lines()
        .filter(|l| l.starts_with("G2 ") || l.starts_with("G3 "))
        .count();
    assert!(
        g23 > 400 && arcs == g23,
        "{arcs} arcs read of {g23} G2/G3 lines"
    );
    let names: Vec<&str> = tp.features.iter().map(|f| f.name.as_str()).collect();
    for n in [
        "Outer wall",
        "Inner wall",
        "Sparse infill",
        "Bridge",
        "Top surface",
    ] {
        assert!(names.contains(&n), "{n}: {names:?}");
    }
}

#[test]
fn a_printed_bambu_studio_cube_has_a_plausible_energy_at_its_scale_and_scaled_to_a_metre() {
    let name = "bambustudio_a1mini_cube_50layers.gcode";
    let (t, e) = energy(name, &["--at", "1.7,0,0.5,0"]);
    // Every move at its commanded speed takes 448 s (`printwatt inspect`); the arm's
    // acceleration and jerk limits add to it.
    assert!(t > 448.0 && t < 1000.0, "{t} s");
    assert!(e > 250.0 * t && e < 1000.0 * t, "{e} J over {t} s");
    // Scaled by 5 (a 1 m plate, 1 mm layers) at the speeds as written: longer, still feasible.
    let (t5, e5) = energy(name, &["--scale", "5", "--at", "1.2,-0.5,0.3,0"]);
    assert!(t5 > 3.0 * t && t5 < 6.0 * t, "{t5} s vs {t} s");
    assert!(e5 > 250.0 * t5 && e5 < 1000.0 * t5, "{e5} J over {t5} s");
}

#[test]
fn bambu_m201_accelerations_are_not_read_as_coordinates() {
    // The real file sets `M201 X20000 Y20000 Z1500 E5000` in its start code (line 508).
    let (tp, text) = read("bambustudio_plate_1layer.gcode");
    assert_eq!(
        text.lines().nth(507),
        Some("M201 X20000 Y20000 Z1500 E5000")
    );
    let (_, hi) = tp.bounding_box().unwrap();
    assert!(hi.x < 0.3 && hi.y < 0.3 && hi.z < 0.2, "{hi:?}");
    // And on its own, before any move: no move, no extrusion.
    let t = parse_gcode(
        "M201 X1000 Y1000 Z500 E5000\nG1 X0 Y0 Z0.2 F600\nG1 X10 E1\n",
        "m.gcode",
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(t.moves.len(), 1);
    assert!((t.start.x).abs() < 1e-12 && (t.moves[0].end.x - 0.01).abs() < 1e-12);
}

#[test]
fn prusaslicer_layer_change_markers_are_the_layers() {
    for (name, n) in [
        ("prusaslicer_box_20mm.gcode", 66),
        ("prusaslicer_ring_20mm.gcode", 4),
    ] {
        let (tp, text) = read(name);
        assert_eq!(markers(&text, ";LAYER_CHANGE"), n, "{name}");
        assert_eq!(tp.layer_starts.len(), n, "{name}");
    }
}

#[test]
fn layer_markers_win_over_z_levels_and_only_the_first_kind_counts() {
    // Bambu Studio's layer change block, three layers, the second with a z-hopped print move
    // (two z levels in one marked layer), and a PrusaSlicer-style marker that does not count
    // once Bambu's kind was met.
    let text = "M83\nG1 X0 Y0 Z0.2 F600\n\
        ; CHANGE_LAYER\n; Z_HEIGHT: 0.2\nG1 X10 E1\nG1 X10 Y10 E1\n\
        ; CHANGE_LAYER\n; Z_HEIGHT: 0.4\n;LAYER_CHANGE\nG1 Z0.4\nG1 X0 E1\nG1 Z0.45 Y0 E1\n\
        ; CHANGE_LAYER\n; Z_HEIGHT: 0.6\nG1 Z0.6\n; FEATURE: Outer wall\nG1 X10 E1\n";
    let tp = parse_gcode(text, "b.gcode", &ReadOptions::default()).unwrap();
    assert_eq!(tp.layer_starts, vec![0, 2, 5]);
    assert_eq!(tp.layers(), 3);
    assert_eq!(tp.layer_count(), 4);
    let per_move: Vec<Option<usize>> = (0..tp.moves.len()).map(|i| tp.layer_of(i)).collect();
    assert_eq!(
        per_move,
        vec![
            Some(0),
            Some(0),
            Some(1),
            Some(1),
            Some(1),
            Some(2),
            Some(2)
        ]
    );
    assert_eq!(tp.features.len(), 1);
    assert_eq!(tp.features[0].first_move, 6);
    // A file without markers counts z levels, as before.
    let plain = parse_gcode(
        "G1 X0 Y0 Z0.2\nG1 X10 E1\nG1 Z0.4\nG1 X0 E2\n",
        "p.gcode",
        &ReadOptions::default(),
    )
    .unwrap();
    assert!(plain.layer_starts.is_empty());
    assert_eq!(plain.layers(), 2);
}

#[test]
fn inspect_counts_layers_from_the_slicer_markers() {
    let out = Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .arg("inspect")
        .arg(data("cura_box_20mm.gcode"))
        .arg("--json")
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["layers"], 67);
    assert_eq!(v["layers_from"], "markers");
    assert_eq!(v["features"][0], "WALL-INNER");
}

#[test]
fn a_cura_box_at_its_own_millimetre_scale_has_a_plausible_energy() {
    let (t, e) = energy("cura_box_20mm.gcode", &["--at", "1.7,0,0.5,0"]);
    // Cura's own estimate is 1071 s at its 30-60 mm/s; the arm's acceleration limits add to it.
    assert!(t > 1000.0 && t < 2500.0, "{t} s");
    // At least the standby (250 W), at most 1 kW on average for a 20 mm part moved slowly.
    assert!(
        e.is_finite() && e > 250.0 * t && e < 1000.0 * t,
        "{e} J over {t} s"
    );
}

#[test]
fn a_bambu_studio_plate_has_a_plausible_energy() {
    let (t, e) = energy("bambustudio_plate_1layer.gcode", &["--at", "1.7,0,0.5,0"]);
    // Mostly the start code's travel (4.9 m, wipes and purges) at up to 700 mm/s.
    assert!(t > 30.0 && t < 600.0, "{t} s");
    assert!(
        e.is_finite() && e > 250.0 * t && e < 1500.0 * t,
        "{e} J over {t} s"
    );
}

#[test]
fn a_concrete_printer_file_from_amworkflow_reads_and_has_a_plausible_energy() {
    // BAM's amworkflow, "Standard: ConcretePrinter": a 150 mm zig-zag cube, 11 mm lines, 3 mm
    // layers, F3465 (57.75 mm/s), absolute extrusion (M82), no G21 (the file's mm).
    let (tp, text) = read("amworkflow_cube_zigzag_150mm.gcode");
    assert!(text.contains("; Standard: ConcretePrinter"));
    assert_eq!(tp.moves.len(), 272);
    assert_eq!(tp.moves.iter().filter(|m| m.print).count(), 256);
    // 16 layers of 3 mm (the file holds the first 16 of the header's 50).
    assert_eq!(tp.layers(), 16);
    for m in tp.moves.iter().filter(|m| m.print) {
        assert!((m.speed - 0.05775).abs() < 1e-9, "{}", m.speed);
        let k = m.end.z / 0.003;
        assert!((k - k.round()).abs() < 1e-9 && (1.0..=16.0).contains(&k.round()));
    }
    assert!(
        (tp.print_length() - 14.4445).abs() < 1e-3,
        "{}",
        tp.print_length()
    );
    // At its own scale: 14.4 m at 57.75 mm/s is 250 s at speed; the supply is at least the
    // standby (250 W) and at most 1 kW on average for a small part moved slowly.
    let (t, e) = energy(
        "amworkflow_cube_zigzag_150mm.gcode",
        &["--at", "1.7,0,0.5,0"],
    );
    assert!(t > 240.0 && t < 300.0, "{t} s");
    assert!(e > 250.0 * t && e < 1000.0 * t, "{e} J over {t} s");
    // Scaled to a 0.7 m element (15 mm layers, the same speed): five times the time, and the
    // energy with it.
    let (t5, e5) = energy(
        "amworkflow_cube_zigzag_150mm.gcode",
        &["--scale", "5", "--at", "1.4,-0.35,0.3,0"],
    );
    assert!(t5 > 4.8 * t && t5 < 5.3 * t, "{t5} s vs {t} s");
    assert!(e5 > 250.0 * t5 && e5 < 1000.0 * t5, "{e5} J over {t5} s");
}
