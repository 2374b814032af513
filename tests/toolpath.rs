//! Toolpath readers: shipped paths, arcs, units, RAPID data, bad input, placements.

use std::f64::consts::{PI, TAU};
use std::path::{Path, PathBuf};

use printwatt::math::V3;
use printwatt::toolpath::{
    load, load_placements, parse_csv, parse_gcode, parse_rapid, MoveKind, Placement, ReadOptions,
    Toolpath, Zone,
};
use printwatt::Error;

fn root(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn shipped(name: &str) -> Toolpath {
    load(&root(&format!("paths/{name}")), &ReadOptions::default())
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn g(text: &str) -> Toolpath {
    parse_gcode(text, "t.gcode", &ReadOptions::default()).unwrap()
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// 90° corner of radius r shortens a path by r (2 − π/2); lengths in m.
fn corner_cut(r_mm: f64) -> f64 {
    r_mm * 1e-3 * (2.0 - PI / 2.0)
}

#[test]
fn seed001_paths_match_hand_lengths() {
    assert!(close(shipped("seed001_x.gcode").length(), 0.140, 1e-12));
    for r in [8.0, 12.0] {
        let p = shipped(&format!("seed001_y2x_r{r}.gcode"));
        assert!(
            close(p.length(), 0.180 - corner_cut(r), 1e-9),
            "{}",
            p.length()
        );
        let p = shipped(&format!("seed001_y2x2y_r{r}.gcode"));
        assert!(close(p.length(), 0.220 - 2.0 * corner_cut(r), 1e-9));
        assert_eq!(
            p.moves
                .iter()
                .filter(|m| matches!(m.kind, MoveKind::Arc { .. }))
                .count(),
            2
        );
        // F3000 mm/min = 0.05 m/s on every move.
        assert!(p
            .moves
            .iter()
            .all(|m| close(m.speed, 0.05, 1e-12) && m.print));
    }
    // Table 1 ratios: 17839.00 J / 101.03 J/mm = 176.57 mm.
    assert!(close(
        shipped("seed001_y2x_r8.gcode").length() * 1e3,
        17839.00 / 101.03,
        0.01
    ));
    assert!(close(
        shipped("seed001_y2x2y_r12.gcode").length() * 1e3,
        21584.76 / 102.93,
        0.01
    ));
}

#[test]
fn seed000_path_marks_and_placements() {
    let p = shipped("seed000_test_path.gcode");
    let loop_len = 2.0 * (0.4 + 0.3) - 8.0 * 0.05 + TAU * 0.05;
    // Print: 3 loops and two 20 mm rises; then a 100 mm travel up (G0).
    assert!(close(p.print_length(), 3.0 * loop_len + 0.04, 1e-9));
    assert!(close(p.length(), p.print_length() + 0.1, 1e-9));
    assert_eq!(p.layer_count(), 3);
    let (ps, pm, pe) = (
        p.mark("Ps").unwrap(),
        p.mark("Pm").unwrap(),
        p.mark("Pe").unwrap(),
    );
    assert!(close(ps.s, 0.0, 1e-12) && (ps.point - V3::new(0.0, -0.15, 0.02)).norm() < 1e-12);
    assert!(close(pm.s, p.print_length() / 2.0, 1e-9));
    assert!((pm.point - V3::new(0.0, 0.15, 0.04)).norm() < 1e-12);
    assert!(close(pe.s, p.print_length(), 1e-9));
    let (lo, hi) = p.bounding_box().unwrap();
    assert!((lo - V3::new(-0.2, -0.15, 0.02)).norm() < 1e-6);
    assert!((hi - V3::new(0.2, 0.15, 0.16)).norm() < 1e-6); // travel up to 160 mm

    let pl = load_placements(&root("paths/placements/p1-p5.csv")).unwrap();
    assert_eq!(pl.len(), 5);
    let want = [
        (1.1, 0.4),
        (1.1, -0.4),
        (1.4, -0.4),
        (1.4, 0.4),
        (1.25, 0.0),
    ];
    for (i, (n, (x, y))) in pl.iter().zip(want).enumerate() {
        assert_eq!(n.name, format!("P{}", i + 1));
        assert!(close(n.placement.x, x, 1e-12) && close(n.placement.y, y, 1e-12));
        assert_eq!((n.placement.z, n.placement.yaw), (0.0, 0.0));
    }
}

#[test]
fn wall_column_rapid_default_load() {
    let w = shipped("wall_multilayer.gcode");
    assert_eq!(w.layer_count(), 10);
    assert!(close(w.print_length(), 10.0 * 2.0 * (1.2 + 0.04), 1e-9));
    assert!(w.moves.iter().any(|m| !m.print), "travel moves flagged");
    assert!(w
        .moves
        .iter()
        .filter(|m| m.print)
        .all(|m| close(m.speed, 0.15, 1e-12)));
    assert!(w
        .warnings
        .iter()
        .any(|s| s.contains("G28") && s.contains("M104")));

    let c = shipped("column_arcs.gcode");
    assert_eq!(c.layer_count(), 5);
    assert!(close(c.print_length(), 5.0 * TAU * 0.15 + 4.0 * 0.02, 1e-9));
    for s in c.sample(0.01) {
        if s.print && s.move_index > 0 && c.moves[s.move_index].kind != MoveKind::Line {
            let r = (s.p.x * s.p.x + s.p.y * s.p.y).sqrt();
            assert!((r - 0.15).abs() < 1e-9, "r = {r}");
        }
    }

    let r = shipped("wall_rapid.mod");
    let layer = 2.4 + TAU * 0.02;
    assert!(
        close(r.print_length(), 2.0 * layer + 0.015, 1e-9),
        "{}",
        r.print_length()
    );
    assert_eq!(r.layer_count(), 2);

    let d = shipped("default.gcode");
    let len = 2.0 * (2.0 + 1.0) - 8.0 * 0.1 + TAU * 0.1;
    assert!(close(d.length(), len, 1e-9) && (5.0..10.0).contains(&len));
    assert!(d
        .moves
        .iter()
        .all(|m| m.print && close(m.speed, 0.15, 1e-12)));
}

#[test]
fn arc_forms_agree_and_points_lie_on_circle() {
    // Quarter circle r = 10 mm, ccw from (10,0) to (0,10).
    let ij = g("G0 X10 Y0 Z0\nG3 X0 Y10 I-10 J0 F600\n");
    let r_form = g("G0 X10 Y0 Z0\nG3 X0 Y10 R10 F600\n");
    let long = g("G0 X10 Y0 Z0\nG3 X0 Y10 R-10 F600\n");
    assert!(close(ij.length(), TAU * 0.01 / 4.0, 1e-12));
    assert!(close(r_form.length(), ij.length(), 1e-12));
    assert!(close(long.length(), 3.0 * TAU * 0.01 / 4.0, 1e-12));
    let (a, b) = (ij.sample(1e-4), r_form.sample(1e-4));
    assert_eq!(a.len(), b.len());
    for (p, q) in a.iter().zip(&b) {
        assert!((p.p - q.p).norm() < 1e-12);
        assert!((p.p.xy().norm() - 0.01).abs() < 1e-9);
    }
    // Mid-point of the short ccw arc is at 45° about (0,0); the long (270°) arc turns about
    // the mirrored centre (10,10) mm, its mid-point at 45° about that.
    let mid = ij.moves[0].point_at(&ij.start, 0.5);
    assert!((mid - V3::new(0.01 / 2f64.sqrt(), 0.01 / 2f64.sqrt(), 0.0)).norm() < 1e-12);
    let mid = long.moves[0].point_at(&long.start, 0.5);
    let a = 0.01 / 2f64.sqrt();
    assert!((mid - V3::new(0.01 + a, 0.01 + a, 0.0)).norm() < 1e-12);
    // G2 full circle, I/J form.
    let full = g("G0 X5 Y0 Z0\nG2 X5 Y0 I-5 J0 F600\n");
    assert!(close(full.length(), TAU * 0.005, 1e-12));
    if let MoveKind::Arc { normal, .. } = full.moves[0].kind {
        assert_eq!(normal, -V3::z());
    }
    // Clockwise: a quarter of the way round, (5,0) → (0,−5).
    let q = full.moves[0].point_at(&full.start, 0.25);
    assert!((q - V3::new(0.0, -0.005, 0.0)).norm() < 1e-12);
}

#[test]
fn relative_inches_feed_and_modes() {
    let abs = g("G21 G90\nG0 X1 Y2 Z3\nG1 X11 Y2 F1200\nG1 X11 Y12\nG2 X21 Y22 I10 J0\n");
    let rel = g("G21 G90\nG0 X1 Y2 Z3\nG91\nG1 X10 F1200\nG1 Y10\nG2 X10 Y10 I10 J0\n");
    assert_eq!(abs.moves.len(), rel.moves.len());
    for (a, r) in abs.moves.iter().zip(&rel.moves) {
        assert!((a.end - r.end).norm() < 1e-15);
        assert!(close(a.length(&V3::zeros()), r.length(&V3::zeros()), 1e-15));
    }
    // F1200 mm/min = 0.02 m/s.
    assert!(close(abs.moves[0].speed, 0.02, 1e-15));
    let inch = g("G20\nG0 X0 Y0 Z0\nG1 X1 F60\n");
    assert!(close(inch.length(), 0.0254, 1e-15));
    assert!(close(inch.moves[0].speed, 0.0254, 1e-15)); // 60 in/min = 1 in/s
                                                        // G92 shifts the coordinates; N and checksums ignored; comments.
    let p = g("N1 G0 X0 Y0 Z0*12\nG92 X100 (now at 100)\nN3 G1 X110 F600 ; comment\n");
    assert!(close(p.moves[0].end.x, 0.010, 1e-15));
    // E-based extrusion: relative E (M83), travel without E.
    let e = g("M83\nG0 X0 Y0 Z0\nG1 X10 E1 F600\nG1 X20\nG1 E-1\nG0 X30\nG1 X40 E2\n");
    let prints: Vec<bool> = e.moves.iter().map(|m| m.print).collect();
    assert_eq!(prints, [true, false, false, true]);
    // M-code extrusion and zones: G61 fine, G64 P2 mm, G9.
    let m = g("G0 X0 Y0 Z0\nM3\nG61\nG1 X10 F600\nG64 P2\nG1 X20\nG1 X30 G9\nM5\nG1 X40\n");
    let z: Vec<Zone> = m.moves.iter().map(|m| m.zone).collect();
    assert_eq!(z[0], Zone::Fine);
    assert!(matches!(z[1], Zone::Blend(r) if close(r, 0.002, 1e-15)));
    assert_eq!(z[2], Zone::Fine);
    assert_eq!(
        m.moves.iter().map(|m| m.print).collect::<Vec<_>>(),
        [true, true, true, false]
    );
    // Unknown codes: one warning listing them.
    let u = g("G0 X0 Y0 Z0\nM106 S255\nG4 P10\nT1\nSET_FAN SPEED=1\nG1 X1\n");
    assert_eq!(
        u.warnings
            .iter()
            .filter(|w| w.contains("ignored codes"))
            .count(),
        1
    );
    assert!(u.warnings[0].contains("M106") && u.warnings[0].contains("SET_FAN"));
}

#[test]
fn csv_units_and_columns() {
    let t = "# a path\nx[m], y[cm], z, speed[mm/min], print\n0,0,0,6000,1\n1,0,0,6000,1\n1,10,0,600,0\n";
    let p = parse_csv(t, "a.csv", &ReadOptions::default()).unwrap();
    assert_eq!(p.moves.len(), 2);
    assert!(close(p.length(), 1.1, 1e-12));
    assert!(close(p.moves[0].speed, 0.1, 1e-12) && close(p.moves[1].speed, 0.01, 1e-12));
    assert!(p.moves[0].print && !p.moves[1].print);
    let q = parse_csv("x,y,z\n0,0,0\n5,0,0\n", "b.csv", &ReadOptions::default()).unwrap();
    assert!(close(q.length(), 0.005, 1e-15) && close(q.moves[0].speed, 0.1, 1e-15));
}

#[test]
fn rapid_speed_zone_and_movec() {
    let text = "MODULE T\n\
        CONST robtarget a := [[0,0,0],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n\
        CONST speeddata s1 := [100,500,5000,1000];\n\
        CONST zonedata zz := [FALSE,7,10,10,1,10,1];\n\
        PROC main()\n\
        MoveJ a, v1000, fine, tool0;\n\
        MoveL [[100,0,0],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, z10, tool0 \\WObj:=wobj0;\n\
        MoveC [[100,100,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], [[0,100,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], s1, zz, tool0;\n\
        MoveL a, v100 \\V:=250, z10 \\Z:=3, tool0;\n\
        movej Offs(a,0,0,100), vmax, z0, tool0;\n\
        ENDPROC\nENDMODULE\n";
    let p = parse_rapid(text, "t.mod", &ReadOptions::default()).unwrap();
    assert_eq!(p.moves.len(), 4);
    let m = &p.moves;
    assert!(close(m[0].speed, 0.1, 1e-15) && m[0].zone == Zone::Blend(0.01) && m[0].print);
    assert!(close(m[1].speed, 0.1, 1e-15) && m[1].zone == Zone::Blend(0.007));
    assert!(close(m[2].speed, 0.25, 1e-15) && m[2].zone == Zone::Blend(0.003));
    assert!(!m[3].print && close(m[3].speed, 7.0, 1e-12) && m[3].zone == Zone::Blend(0.0003));
    // MoveC (100,0) → via (100,100) → (0,100): half circle, centre (50,50), r = 70.71 mm.
    let MoveKind::Arc {
        centre,
        radius,
        sweep,
        ..
    } = m[1].kind
    else {
        panic!()
    };
    assert!((centre - V3::new(0.05, 0.05, 0.0)).norm() < 1e-12);
    assert!(close(radius, 0.05 * 2f64.sqrt(), 1e-12) && close(sweep, PI, 1e-12));
    let via = V3::new(0.1, 0.1, 0.0);
    let closest = p
        .sample(1e-5)
        .iter()
        .filter(|s| s.move_index == 1)
        .map(|s| (s.p - via).norm())
        .fold(f64::INFINITY, f64::min);
    assert!(
        closest < 1e-5,
        "arc passes through the via point: {closest}"
    );
    assert!(close(m[1].point_at(&p.move_start(1), 0.5).y, 0.1, 1e-12));
    // fine
    let f = parse_rapid(
        "MoveL [[0,0,0],[1,0,0,0],[0,0,0,0],[0]], v5, fine, t;\nMoveL [[1,0,0],[1,0,0,0],[0,0,0,0],[0]], v5, fine, t;",
        "f.mod",
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(f.moves[0].zone, Zone::Fine);
    assert_eq!(f.moves[0].zone.radius(), 0.0);
}

fn parse_err(name: &str) -> (String, usize, usize, String) {
    let path = root(&format!("tests/data/toolpath/{name}"));
    match load(&path, &ReadOptions::default()) {
        Err(e @ Error::Parse { .. }) => {
            let s = e.to_string();
            let Error::Parse {
                file,
                line,
                column,
                msg,
            } = e
            else {
                unreachable!()
            };
            assert!(file.ends_with(name) && s.contains(name), "{s}");
            (file, line, column, msg)
        }
        other => panic!("{name}: expected a parse error, got {other:?}"),
    }
}

#[test]
fn bad_input_errors_name_file_line_column() {
    let (_, l, c, m) = parse_err("bad_number.gcode");
    assert_eq!((l, c), (4, 9), "{m}");
    assert!(
        m.contains("expected a number after 'Y'") && m.contains("'abc'"),
        "{m}"
    );
    let (_, l, c, m) = parse_err("arc_no_centre.gcode");
    assert_eq!((l, c), (4, 1), "{m}");
    assert!(m.contains("expected I and J") && m.contains("R"), "{m}");
    let (_, l, c, m) = parse_err("bad_unit.csv");
    assert_eq!((l, c), (2, 7), "{m}");
    assert!(
        m.contains("unknown unit 'furlong'") && m.contains("expected mm"),
        "{m}"
    );
    let (_, l, c, m) = parse_err("nan.csv");
    assert_eq!((l, c), (4, 5), "{m}");
    assert!(
        m.contains("expected a finite number for 'y'") && m.contains("NaN"),
        "{m}"
    );
    let (_, l, c, m) = parse_err("undefined_robtarget.mod");
    assert_eq!((l, c), (5, 15), "{m}");
    assert!(
        m.contains("undefined robtarget 'p99'") && m.contains("expected"),
        "{m}"
    );
    let (_, l, c, m) = parse_err("unterminated_robtarget.mod");
    let text =
        std::fs::read_to_string(root("tests/data/toolpath/unterminated_robtarget.mod")).unwrap();
    let line2 = text.lines().nth(1).unwrap();
    assert_eq!((l, c), (2, line2.find(';').unwrap() + 1), "{m}");
    assert!(
        m.contains("expected ',' or ']'") && m.contains("found ';'"),
        "{m}"
    );
}

#[test]
fn more_gcode_errors() {
    let e = |t: &str| {
        parse_gcode(t, "e.gcode", &ReadOptions::default())
            .unwrap_err()
            .to_string()
    };
    assert!(e("G0 X0 Y0\nG18\n").contains("e.gcode:2:1:"));
    assert!(e("G0 X0 Y0\nG2 X0 Y0 R5\n").contains("full circle"));
    assert!(e("G0 X0 Y0\nG2 X30 Y0 R5\n").contains("chord"));
    assert!(e("G0 X0 Y0\nG2 X30 Y0 I5 J0\n").contains("one circle"));
    assert!(e("X10\n").contains("motion mode"));
    assert!(e("G1 X1 (open\n").contains("expected ')'"));
    assert!(e("G1 X1 F0\n").contains("positive feed"));
}

#[test]
fn placement_transform() {
    let p = Placement::new(1.0, 2.0, 0.5, PI / 2.0);
    let b = p.apply(&V3::new(1.0, 0.0, 0.0));
    assert!(
        (b - V3::new(1.0, 3.0, 0.5)).norm() < 1e-12,
        "part +x → base +y"
    );
    assert!((p.frame().rot * V3::x() - V3::y()).norm() < 1e-15);
}

/// Deterministic pseudo-random junk and mutations of the shipped files: never a panic.
#[test]
fn fuzz_no_panics() {
    let mut seed: u64 = 42;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    let alphabet: Vec<char> = "GMXYZEFIJRNP0123456789.-+ ;()*\n\t[],:=!\\#abcMoveLCvzfine\"\u{e9}"
        .chars()
        .collect();
    let opts = ReadOptions::default();
    let mut corpus: Vec<String> = [
        "wall_multilayer.gcode",
        "column_arcs.gcode",
        "wall_rapid.mod",
    ]
    .iter()
    .map(|f| std::fs::read_to_string(root(&format!("paths/{f}"))).unwrap())
    .collect();
    corpus.push("x[mm],y[mm],z[mm],speed\n0,0,0,1\n1,2,3,4\n".into());
    for i in 0..1500 {
        let text: String = if i % 2 == 0 {
            let n = (rnd() % 200) as usize;
            (0..n)
                .map(|_| alphabet[(rnd() as usize) % alphabet.len()])
                .collect()
        } else {
            let base = &corpus[(rnd() as usize) % corpus.len()];
            let mut c: Vec<char> = base.chars().collect();
            for _ in 0..3 {
                if c.is_empty() {
                    break;
                }
                let k = (rnd() as usize) % c.len();
                match rnd() % 3 {
                    0 => {
                        c.remove(k);
                    }
                    1 => c.insert(k, alphabet[(rnd() as usize) % alphabet.len()]),
                    _ => c[k] = alphabet[(rnd() as usize) % alphabet.len()],
                }
            }
            c.into_iter().collect()
        };
        let results = [
            parse_gcode(&text, "f", &opts),
            parse_csv(&text, "f", &opts),
            parse_rapid(&text, "f", &opts),
        ];
        for p in results.into_iter().flatten() {
            let _ = (
                p.length(),
                p.sample(0.05),
                p.bounding_box(),
                p.layer_count(),
            );
            assert!(p.length().is_finite());
        }
        let _ = printwatt::toolpath::parse_placements(&text, "f");
    }
}

/// `Toolpath::from_points` (the designer's list of points, the Python bindings' path): the same
/// moves as the CSV reader makes of the same points, duplicates dropped, and a clear error for
/// a NaN (naming the row), a speed <= 0, a negative zone, or fewer than two distinct points.
#[test]
fn from_points_builds_the_csv_readers_path_and_names_a_bad_row() {
    let pts = [
        V3::new(0.0, 0.0, 0.0),
        V3::new(0.6, 0.0, 0.0),
        V3::new(0.6, 0.0, 0.0),
        V3::new(0.6, 0.4, 0.01),
    ];
    let opts = ReadOptions::default();
    let tp = Toolpath::from_points(&pts, 0.1, opts.default_zone, "pts").unwrap();
    let csv = parse_csv(
        "x[m],y[m],z[m],speed[m/s]\n0,0,0,0.1\n0.6,0,0,0.1\n0.6,0,0,0.1\n0.6,0.4,0.01,0.1\n",
        "pts.csv",
        &opts,
    )
    .unwrap();
    assert_eq!(tp.moves.len(), 2);
    assert_eq!(tp.start, csv.start);
    for (a, b) in tp.moves.iter().zip(&csv.moves) {
        assert_eq!(
            (a.end, a.speed, a.zone, a.print),
            (b.end, b.speed, b.zone, b.print)
        );
    }
    assert_eq!(tp.moves[1].line, 4, "the point's 1-based row");
    let bad = |pts: &[V3], speed: f64, zone: Zone| {
        Toolpath::from_points(pts, speed, zone, "pts")
            .unwrap_err()
            .to_string()
    };
    let e = bad(&[pts[0], V3::new(1.0, f64::NAN, 0.0)], 0.1, Zone::Fine);
    assert!(
        e.contains("pts: point 2 (row 1)") && e.contains("not a finite"),
        "{e}"
    );
    assert!(bad(&pts, 0.0, Zone::Fine).contains("speed 0 m/s"));
    assert!(bad(&pts, 0.1, Zone::Blend(-0.01)).contains("zone -0.01 m"));
    assert!(bad(&[pts[1], pts[2]], 0.1, Zone::Fine).contains("all at the same place"));
    assert!(bad(&[], 0.1, Zone::Fine).contains("no points"));
}

/// Slicer start code (PrusaSlicer, Cura, Bambu Studio): the letters of an M-code are its
/// parameters (`M201 X1000 Y1000 Z500 E5000` sets accelerations), not coordinates, an
/// extrusion or a feed; the path starts at the first move and prints where E increases.
#[test]
fn slicer_mcode_parameters_are_not_coordinates() {
    let t = g(
        "M201 X1000 Y1000 Z500 E5000 ; sets maximum accelerations, mm/sec^2\n\
               M203 X500 Y500 Z12 E120 ; sets maximum feedrates, mm/sec\n\
               M204 P1000 R1250 T1000\n\
               M205 X8.00 Y8.00 Z0.40 E4.50\n\
               M104 S215\nM140 S60\nM190 S60\nM109 S215\n\
               G21 ; set units to millimeters\nG90\nM82\nG28 W\nG92 E0\n\
               ;LAYER_CHANGE\n;Z:0.2\nG1 Z0.2 F720\nG1 X10 Y10 F3000\n\
               ;TYPE:Perimeter\nG1 X30 Y10 E1.2 F1200\nG1 X30 Y30 E2.4\nM107\n",
    );
    assert_eq!(t.moves.len(), 3, "{:?}", t.moves);
    assert!(close(t.start.z, 0.0002, 1e-12), "start {:?}", t.start);
    assert!(!t.moves[0].print && t.moves[1].print && t.moves[2].print);
    assert!(close(t.moves[2].end.x, 0.030, 1e-12) && close(t.moves[2].end.y, 0.030, 1e-12));
    // F1200 mm/min = 0.02 m/s, modal on the next line.
    assert!(close(t.moves[2].speed, 0.02, 1e-12));
}

#[test]
fn a_placement_set_row_no_arm_reaches_is_named_by_file_row_and_column_with_its_unit() {
    let d = std::env::temp_dir().join(format!("pw_set_far_{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let f = d.join("set.csv");
    std::fs::write(&f, "name,x,y,z,yaw\nA,1500,100,0,0\nB,1500,400000000,0,0\n").unwrap();
    let e = printwatt::toolpath::load_placements(&f)
        .unwrap_err()
        .to_string();
    let want = format!("{}:3:8:", f.display());
    assert!(e.contains(&want), "{e}");
    assert!(e.contains("y = 400000000 reads as 400000 m"), "{e}");
    assert!(e.contains("mm, the default"), "{e}");
    // Metres stated in the header: the same rule, named with the unit.
    std::fs::write(
        &f,
        "name,x[m],y[m],z[m],yaw[deg]\nA,1.5,0.1,0,0\nB,1.5,0.1,60,0\n",
    )
    .unwrap();
    let e = printwatt::toolpath::load_placements(&f)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(":3:") && e.contains("z = 60 reads as 60 m (column unit m)"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_csv_path_without_units_says_mm_was_assumed_and_path_units_state_them() {
    use printwatt::toolpath::PathUnits;
    let text = "x,y,z\n0,0,0\n1.5,0,0\n1.5,1,0\n";
    // No unit anywhere: mm, said once with the header line, and the 1.8 mm part is implausible.
    let p = parse_csv(text, "p.csv", &ReadOptions::default()).unwrap();
    assert!(close(p.length(), 2.5e-3, 1e-15));
    let w = p.warnings.join("\n");
    assert!(
        w.contains("p.csv:1: x, y, z have no unit; mm assumed"),
        "{w}"
    );
    assert!(w.contains("set the path units to mm or m"), "{w}");
    assert!(
        w.contains("smaller than 50 mm") && w.contains("read as mm (assumed"),
        "{w}"
    );
    // Stated by the option: metres, no note, a plausible 1.8 m part.
    let opts = ReadOptions {
        path_units: Some(PathUnits::M),
        ..Default::default()
    };
    let p = parse_csv(text, "p.csv", &opts).unwrap();
    assert!(close(p.length(), 2.5, 1e-12));
    assert!(p.warnings.is_empty(), "{:?}", p.warnings);
    // Unlabelled speeds follow the path unit per second.
    let p = parse_csv("x,y,z,speed\n0,0,0,0.2\n1,0,0,0.2\n", "s.csv", &opts).unwrap();
    assert!(close(p.moves[0].speed, 0.2, 1e-15));
    // Stated in the header: it wins over the option, which is said.
    let p = parse_csv("x[mm],y[mm],z[mm]\n0,0,0\n1500,0,0\n", "h.csv", &opts).unwrap();
    assert!(close(p.length(), 1.5, 1e-12));
    let w = p.warnings.join("\n");
    assert!(w.contains("h.csv:1: the header states [mm]"), "{w}");
    assert!(PathUnits::parse("furlong").is_err());
}

#[test]
fn a_path_of_implausible_extent_is_warned_about_naming_the_unit_read() {
    let d = std::env::temp_dir().join(format!("printwatt-extent-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    // 60 km read from a CSV in metres by its header: too large, the unit named as stated.
    let big = d.join("big.csv");
    std::fs::write(&big, "x[m],y[m],z[m]\n0,0,0\n60,0,0\n").unwrap();
    let p = load(&big, &ReadOptions::default()).unwrap();
    let w = p.warnings.join("\n");
    assert!(
        w.contains("larger than 50 m") && w.contains("read as m (stated in the header)"),
        "{w}"
    );
    assert!(w.contains(&big.display().to_string()), "{w}");
    // A 10 mm G-code part: too small, read as the file's G21 mm.
    let small = d.join("small.gcode");
    std::fs::write(&small, "G21\nG1 X0 Y0 Z0 F600\nG1 X10 Y0 F600\n").unwrap();
    let p = load(&small, &ReadOptions::default()).unwrap();
    let w = p.warnings.join("\n");
    assert!(w.contains("smaller than 50 mm") && w.contains("G21"), "{w}");
    // The shipped 2 m path is plausible: no such warning.
    let p = shipped("default.gcode");
    assert!(!p.warnings.join("\n").contains("implausible"));
}

#[test]
fn path_units_are_refused_for_gcode_and_scale_resizes_the_geometry() {
    use printwatt::toolpath::PathUnits;
    let g = root("paths/default.gcode");
    let e = load(
        &g,
        &ReadOptions {
            path_units: Some(PathUnits::M),
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("default.gcode") && e.contains("CSV paths only"),
        "{e}"
    );
    let full = load(&g, &ReadOptions::default()).unwrap();
    let half = load(
        &g,
        &ReadOptions {
            scale: 0.5,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(close(half.length(), 0.5 * full.length(), 1e-9));
    assert_eq!(half.moves.len(), full.moves.len());
    assert_eq!(half.moves[3].speed, full.moves[3].speed);
    let e = load(
        &g,
        &ReadOptions {
            scale: 0.0,
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("scale"), "{e}");
}
