//! RAPID modules read as the controller runs them: `main` and its procedure calls in order,
//! run-time branches refused unless the entry procedure is named, home positions in `wobj0`
//! left out of the part, declared `wobjdata` frames applied. The real-style module and its
//! origin: `tests/data/rapid/README.md`.

use std::path::{Path, PathBuf};
use std::process::Command;

use printwatt::toolpath::{load, parse_rapid, read_program, read_program_entry, ReadOptions};

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/rapid")
        .join(name)
}

fn entry(name: &str) -> ReadOptions {
    ReadOptions {
        proc: Some(name.to_string()),
        ..Default::default()
    }
}

fn lines(tp: &printwatt::toolpath::Toolpath) -> Vec<usize> {
    tp.moves.iter().map(|m| m.line).collect()
}

/// The end points of the path, mm, rounded to 0.01 mm.
fn points_mm(tp: &printwatt::toolpath::Toolpath) -> Vec<[f64; 3]> {
    std::iter::once(tp.start)
        .chain(tp.moves.iter().map(|m| m.end))
        .map(|p| {
            let r = |v: f64| (v * 1e5).round() / 100.0 + 0.0;
            [r(p.x), r(p.y), r(p.z)]
        })
        .collect()
}

const CALLS: &str = "MODULE Calls
    CONST robtarget p0 := [[0,0,0],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p1 := [[100,0,0],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p2 := [[200,0,0],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p3 := [[300,0,0],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    PROC second()
        MoveL p2, v100, z1, tool0;
        third;
    ENDPROC
    PROC main()
        MoveJ p0, v100, fine, tool0;
        first;
        second;
        MoveL Offs(p0,0,0,50), v100, fine, tool0;
    ENDPROC
    PROC third()
        MoveL p3, v100, z1, tool0;
    ENDPROC
    PROC first()
        MoveL p1, v100, z1, tool0;
    ENDPROC
    PROC unused()
        MoveL Offs(p0,900,0,0), v100, z1, tool0;
    ENDPROC
ENDMODULE
";

#[test]
fn rapid_main_and_its_calls_are_followed_in_order() {
    let tp = parse_rapid(CALLS, "calls.mod", &ReadOptions::default()).unwrap();
    // main's MoveJ (start), first, second, third (called from second), main's last move; the
    // unused procedure's move is not read.
    assert_eq!(lines(&tp), vec![20, 7, 17, 14]);
    assert_eq!(
        points_mm(&tp),
        vec![
            [0.0, 0.0, 0.0],
            [100.0, 0.0, 0.0],
            [200.0, 0.0, 0.0],
            [300.0, 0.0, 0.0],
            [0.0, 0.0, 50.0]
        ]
    );
    assert_eq!(tp.entry.as_deref(), Some("main"));
    let names: Vec<&str> = tp.procedures.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["second", "main", "third", "first", "unused"]);
    // read_program takes the targets in the same order (it reads named and inline
    // robtargets, not Offs).
    let named = CALLS.replace("MoveL Offs(p0,0,0,50)", "MoveL p0");
    let prog = read_program(&named, "calls.mod").unwrap();
    let tl: Vec<usize> = prog.targets.iter().map(|t| t.line).collect();
    assert_eq!(tl, vec![11, 20, 7, 17, 14]);

    // The real-style module from its print procedure: its own moves, then the procedure it
    // calls (lines 64-70), in that order; nothing from path_inclinado (lines 73-87).
    let tp = load(&data("two_workobjects.mod"), &entry("path_plano")).unwrap();
    let l = lines(&tp);
    assert_eq!(l.first(), Some(&49), "{l:?}");
    assert_eq!(l.last(), Some(&70), "{l:?}");
    assert!(l.windows(2).all(|w| w[0] < w[1]), "{l:?}");
    assert!(l.iter().any(|&x| (64..=70).contains(&x)), "{l:?}");
    assert!(l.iter().all(|&x| x < 73), "{l:?}");
}

#[test]
fn rapid_recursive_calls_are_refused_naming_the_chain_and_the_line() {
    let text = "MODULE R
    CONST robtarget p0 := [[0,0,0],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    PROC main()
        MoveJ p0, v100, fine, tool0;
        a;
    ENDPROC
    PROC a()
        MoveL Offs(p0,100,0,0), v100, z1, tool0;
        b;
    ENDPROC
    PROC b()
        a;
    ENDPROC
ENDMODULE
";
    let e = parse_rapid(text, "r.mod", &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("r.mod:12:"), "{e}");
    assert!(e.contains("main → a → b → a"), "{e}");
}

#[test]
fn rapid_without_main_reads_its_one_procedure_and_refuses_several() {
    // One procedure with moves (an exported path): read in file order, as before.
    let one = "MODULE One
    CONST robtarget p0 := [[0,0,0],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    PROC setup()
        SetDO do1, 0;
    ENDPROC
    PROC start()
        MoveJ p0, v100, fine, tool0;
        MoveL Offs(p0,100,0,0), v100, z1, tool0;
    ENDPROC
ENDMODULE
";
    let tp = parse_rapid(one, "one.mod", &ReadOptions::default()).unwrap();
    assert_eq!(lines(&tp), vec![8]);
    assert_eq!(tp.entry.as_deref(), Some("start"));
    // Several procedures with moves and no main: refused, listing them.
    let several = CALLS.replace("PROC main()", "PROC start()");
    let e = parse_rapid(&several, "several.mod", &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("no PROC main"), "{e}");
    for p in [
        "second (line 6, 1 moves)",
        "start (line 10, 2 moves)",
        "third (line 16, 1 moves)",
        "unused (line 22, 1 moves)",
    ] {
        assert!(e.contains(p), "{p}: {e}");
    }
}

#[test]
fn rapid_ambiguous_branches_are_refused_with_the_procedure_list() {
    let f = data("two_workobjects.mod");
    let e = load(&f, &ReadOptions::default()).unwrap_err().to_string();
    let name = f.display().to_string();
    assert!(e.starts_with(&format!("{name}:40:")), "{e}");
    assert!(e.contains("the IF in main"), "{e}");
    assert!(
        e.contains(&format!("path_plano (called at {name}:41)")),
        "{e}"
    );
    assert!(
        e.contains(&format!("path_inclinado (called at {name}:43)")),
        "{e}"
    );
    assert!(e.contains("rectangulo_mesa (line 63, 7 moves)"), "{e}");
    // The library names no flag; the command line adds it.
    assert!(!e.contains("--proc"), "{e}");
    let out = Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .args(["inspect"])
        .arg(&f)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--proc NAME"), "{err}");
    assert!(err.contains(":40:"), "{err}");

    // Branches that reach the same procedures are not a choice; an IF without moves neither.
    let same = "MODULE S
    CONST robtarget p0 := [[0,0,0],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    PROC main()
        IF DI_01 = 1 THEN
            SetDO do1, 1;
        ENDIF
        TEST nMode
        CASE 1, 2:
            path;
        DEFAULT:
            path;
        ENDTEST
    ENDPROC
    PROC path()
        MoveJ p0, v100, fine, tool0;
        MoveL Offs(p0,100,0,0), v100, z1, tool0;
    ENDPROC
ENDMODULE
";
    let tp = parse_rapid(same, "s.mod", &ReadOptions::default()).unwrap();
    assert_eq!(lines(&tp), vec![16]);
    // A TEST whose cases reach different procedures is refused like the IF.
    let test = same.replacen("            path;\n", "            other;\n", 1) + "";
    let test = test.replace(
        "ENDMODULE",
        "    PROC other()\n        MoveJ p0, v100, fine, tool0;\n    ENDPROC\nENDMODULE",
    );
    let e = parse_rapid(&test, "t.mod", &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("t.mod:7:"), "{e}");
    assert!(e.contains("other (called at t.mod:9)"), "{e}");
    assert!(e.contains("path (called at t.mod:11)"), "{e}");
}

#[test]
fn rapid_proc_option_chooses_the_entry() {
    let f = data("two_workobjects.mod");
    let plano = load(&f, &entry("path_plano")).unwrap();
    let inclinado = load(&f, &entry("PATH_INCLINADO")).unwrap();
    assert_eq!(plano.entry.as_deref(), Some("path_plano"));
    assert_eq!(inclinado.entry.as_deref(), Some("path_inclinado"));
    // path_inclinado has no rectangle: 11 moves after its start; path_plano 11 + 7.
    assert_eq!(inclinado.moves.len(), 11);
    assert_eq!(plano.moves.len(), 18);
    assert!(lines(&inclinado).iter().all(|l| (73..=87).contains(l)));
    // read_program from the same entry: every move the controller runs, home ones too.
    let text = std::fs::read_to_string(&f).unwrap();
    let prog = read_program_entry(&text, "f.mod", Some("path_plano")).unwrap();
    assert_eq!(prog.targets.len(), 21);
    assert_eq!(prog.targets[0].wobj, "wobj0");
    // An unknown name is refused listing the procedures; other formats refuse the option.
    let e = load(&f, &entry("path_x")).unwrap_err().to_string();
    assert!(e.contains("no procedure named 'path_x'"), "{e}");
    assert!(e.contains("path_plano (line 46, 14 moves)"), "{e}");
    let g = Path::new(env!("CARGO_MANIFEST_DIR")).join("paths/default.gcode");
    let e = load(&g, &entry("main")).unwrap_err().to_string();
    assert!(e.contains("RAPID modules only"), "{e}");
    // The command line takes it as --proc, for inspect and for the path of every command.
    let out = Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .arg("inspect")
        .arg(&f)
        .args(["--proc", "path_inclinado"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        text.contains("procedures          4 (read from: path_inclinado)"),
        "{text}"
    );
    assert!(
        text.contains("path_inclinado    line 72, 14 moves  <- read"),
        "{text}"
    );
}

#[test]
fn rapid_home_targets_in_wobj0_are_not_part_points() {
    let tp = load(&data("two_workobjects.mod"), &entry("path_plano")).unwrap();
    // The home target lies at (520.5, -0.2, 640.8) mm in wobj0: not on the part, whose
    // highest point is the 70 mm retract.
    let (lo, hi) = tp.bounding_box().unwrap();
    assert!(hi.z < 0.0700001 && lo.z > -1e-9, "{lo:?} {hi:?}");
    assert!(!lines(&tp).contains(&47) && !lines(&tp).contains(&61));
    assert!(
        tp.warnings.iter().any(|w| w.contains(
            "line 47, 61: move(s) in wobj0 while the print uses work object Workobject_plano"
        )),
        "{:?}",
        tp.warnings
    );
    // The tool frame (150 mm) is noted, not applied.
    assert!(
        tp.warnings.iter().any(|w| w.contains(
            ":48: tool Tip (declared on line 2) has a tool frame that is not the identity"
        )),
        "{:?}",
        tp.warnings
    );
    // When the whole print is in wobj0, wobj0 is the part frame: nothing is skipped.
    let wall = Path::new(env!("CARGO_MANIFEST_DIR")).join("paths/wall_rapid.mod");
    let w = load(&wall, &ReadOptions::default()).unwrap();
    assert_eq!(w.moves.len(), 12);
    assert!(!w.warnings.iter().any(|x| x.contains("not part points")));
}

#[test]
fn rapid_wobjdata_frames_are_applied() {
    // The rectangle is written in Workobject_mesa (oframe 400 mm along x and turned 90°
    // about z from the table's frame): in the part frame (Workobject_plano) its corners are
    // (x, y) -> (400 - y, x).
    let tp = load(&data("two_workobjects.mod"), &entry("path_plano")).unwrap();
    let pts = points_mm(&tp);
    let rect = &pts[pts.len() - 7..];
    assert_eq!(
        rect,
        [
            [400.0, 0.0, 70.0],
            [400.0, 0.0, 0.0],
            [400.0, 100.0, 0.0],
            [340.0, 100.0, 0.0],
            [340.0, 0.0, 0.0],
            [400.0, 0.0, 0.0],
            [400.0, 0.0, 70.0]
        ]
    );
    // The D outline stays as written in the part's own work object.
    assert_eq!(pts[0], [0.0, 120.0, 70.0]);
    assert_eq!(pts[2], [0.0, 0.0, 0.0]);
    // The tilted plate's path is read in its own frame (its work object is the part frame):
    // the same outline.
    let inc = load(&data("two_workobjects.mod"), &entry("path_inclinado")).unwrap();
    assert_eq!(points_mm(&inc)[..12], pts[..12]);

    // A uframe rotation and an oframe offset, composed: wobjB = uframe (100, 0, 0) turned
    // 90° about z, oframe (0, 0, 10); the part is wobjA at the origin turned 180° about z.
    let text = "MODULE W
    PERS wobjdata wobjA := [FALSE,TRUE,\"\",[[0,0,0],[0,0,0,1]],[[0,0,0],[1,0,0,0]]];
    PERS wobjdata wobjB := [FALSE,TRUE,\"\",[[100,0,0],[0.707106781,0,0,0.707106781]],[[0,0,10],[1,0,0,0]]];
    CONST robtarget p0 := [[0,0,0],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    PROC main()
        MoveJ p0, v100, fine, tool0 \\WObj:=wobjA;
        MoveL Offs(p0,50,0,0), v100, z1, tool0 \\WObj:=wobjA;
        MoveL Offs(p0,50,0,0), v100, z1, tool0 \\WObj:=wobjA;
        MoveL Offs(p0,20,0,0), v100, z1, tool0 \\WObj:=wobjB;
    ENDPROC
ENDMODULE
";
    let tp = parse_rapid(text, "w.mod", &ReadOptions::default()).unwrap();
    // wobjB's (20, 0, 0): world (100, 20, 10); in wobjA (turned 180°): (-100, -20, 10).
    assert_eq!(points_mm(&tp).last(), Some(&[-100.0, -20.0, 10.0]));
    // A work object used but not declared cannot be put in the part frame: the line is named.
    let bad = text.replacen("wobjB := ", "wobjC := ", 1);
    let e = parse_rapid(&bad, "w.mod", &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("w.mod:9:"), "{e}");
    assert!(e.contains("undefined wobjdata 'wobjB'"), "{e}");
}

#[test]
fn rapid_energy_of_the_real_style_module_is_finite_and_plausible() {
    let out = Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .arg("energy")
        .arg("--path")
        .arg(data("two_workobjects.mod"))
        .args(["--proc", "path_plano", "--at", "1.6,0,0.5,0", "--no-csv"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(text.contains("feasible (the checks"), "{text}");
    let num = |prefix: &str| -> f64 {
        let l = text.lines().find(|l| l.starts_with(prefix)).unwrap();
        l[prefix.len()..]
            .split_whitespace()
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    let t = num("time");
    let e = num("supply energy");
    // 1.4 m of print at 100 mm/s and 0.6 m of travel at 300 mm/s: 15-40 s; on average between
    // the standby (250 W) and 1.5 kW.
    assert!(t > 15.0 && t < 40.0, "{t} s");
    assert!(
        e.is_finite() && e > 250.0 * t && e < 1500.0 * t,
        "{e} J over {t} s"
    );
}
