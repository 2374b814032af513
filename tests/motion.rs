//! Motion a controller can run and geometry a site can trust: the wrist-singularity margin,
//! the print head against the part printed so far, and exported programs that parse back into
//! the planned path and arm configuration.

mod common;

use printwatt::evaluate::feasibility::{FeasibilityOptions, Reason};
use printwatt::evaluate::{Evaluated, Evaluator, Objective};
use printwatt::frame::Placement;

fn one(ev: &Evaluator, at: Placement) -> Evaluated {
    let mut sc = ev.scratch().unwrap();
    ev.evaluate(&mut sc, &at)
}

/// The default job's answer without a wrist margin (x, y, z, yaw): q5 passes through 0 there.
fn through_the_wrist() -> Placement {
    Placement::new(1.440301, 0.121159, 0.000130, 93.142f64.to_radians())
}

#[test]
fn the_wrist_margin_rejects_a_placement_whose_wrist_passes_through_the_singularity_and_margin_0_lets_it_pass(
) {
    let model = common::robot("abb_irb6700_200_260");
    let tp = common::path("default.gcode");
    let job = common::default_job(&model, &tp);
    let at = through_the_wrist();
    // Default: 5° from q5 = 0, checked on every sample, named with the sample and the angle.
    let o = FeasibilityOptions::default();
    assert!((o.wrist_margin_rad.to_degrees() - 5.0).abs() < 1e-12);
    let ev = Evaluator::new(&job, o, Objective::Supply);
    let e = one(&ev, at).outcome.unwrap_err();
    assert_eq!(e.reason, Reason::WristSingularity, "{e}");
    assert!(e.sample.is_some() && e.line.is_some(), "{e}");
    assert!(
        e.detail
            .contains("from the wrist singularity (wrist margin 5.00°"),
        "{e}"
    );
    // Passing through allowed: feasible, and the closest approach over every sample is stated.
    let free = FeasibilityOptions {
        wrist_margin_rad: 0.0,
        ..Default::default()
    };
    let ev = Evaluator::new(&job, free, Objective::Supply);
    let f = one(&ev, at).outcome.unwrap_or_else(|e| panic!("{e}"));
    let d = f.margins.wrist_deg().expect("an OPW arm");
    assert!(d < 0.1, "q5 comes within {d}° of 0");
    // Every sample, not only the checked ones: never above the checked samples' minimum.
    assert!(f.margins.wrist_every.unwrap() <= f.margins.wrist.unwrap());
    let s = printwatt::evaluate::feasibility::margins::wrist_statement(&free, &f.margins).unwrap();
    assert!(s.contains("SingArea \\Wrist"), "{s}");
    // A margin just below the closest approach keeps the placement; just above rejects it.
    for (deg, ok) in [(d * 0.5, true), (d * 2.0 + 0.01, false)] {
        let o = FeasibilityOptions {
            wrist_margin_rad: deg.to_radians(),
            ..Default::default()
        };
        let ev = Evaluator::new(&job, o, Objective::Supply);
        let r = one(&ev, at).outcome;
        assert_eq!(r.is_ok(), ok, "margin {deg}°: {:?}", r.err());
    }
}

/// A 0.3 m straight wall of `layers` 20 mm layers along x at y = 0, then a travel over it
/// (10 mm above its top) to y = `beside_mm`, down to the first layer and a bead along x.
fn wall_then_bead(layers: usize, beside_mm: f64) -> printwatt::toolpath::Toolpath {
    let mut t = String::from("G21\nG90\nM82\n");
    let mut e = 0.0;
    t += "G0 F12000 X-150 Y0 Z20\n";
    for k in 0..layers {
        let z = 20.0 * (k + 1) as f64;
        let x = if k % 2 == 0 { 150.0 } else { -150.0 };
        if k > 0 {
            t += &format!("G0 Z{z:.3}\n");
        }
        e += 15.0;
        t += &format!("G1 F9000 X{x:.3} Y0 Z{z:.3} E{e:.3}\n");
    }
    let top = 20.0 * layers as f64 + 10.0;
    let x_end = if layers % 2 == 1 { 150.0 } else { -150.0 };
    t += &format!("G0 F12000 Z{top:.3}\nG0 X{x_end:.3} Y{beside_mm:.3}\nG0 Z20\n");
    e += 15.0;
    t += &format!("G1 F9000 X{:.3} Y{beside_mm:.3} E{e:.3}\n", -x_end);
    printwatt::toolpath::parse_gcode(
        &t,
        "wall_then_bead.gcode",
        &printwatt::toolpath::ReadOptions::default(),
    )
    .unwrap()
}

#[test]
fn the_print_head_over_a_tall_wall_beside_a_new_bead_is_infeasible_with_the_reason_and_the_sample()
{
    let model = common::robot("abb_irb6700_200_260");
    // 29 layers: a 0.58 m wall.
    let far = wall_then_bead(29, 400.0);
    let far_job = common::default_job(&model, &far);
    let ev = Evaluator::new(&far_job, FeasibilityOptions::default(), Objective::Supply);
    // A placement where the wall and a bead 0.4 m away are feasible.
    let candidates = [
        Placement::new(1.5, 0.0, 0.0, 0.0),
        Placement::new(1.5, 0.0, 0.0, std::f64::consts::FRAC_PI_2),
        Placement::new(1.3, 0.3, 0.2, 0.0),
        Placement::new(1.7, -0.3, -0.2, 0.0),
        Placement::new(1.2, 0.0, 0.4, 0.0),
    ];
    let at = candidates
        .iter()
        .copied()
        .find(|at| one(&ev, *at).outcome.is_ok())
        .expect("a placement where the wall and a far bead are feasible");
    let wall_samples = {
        let wall = wall_then_bead(29, 400.0);
        let j = common::default_job(&model, &wall);
        // The wall ends where the travel towards the bead leaves its top.
        let m = &j.plan.motion;
        (0..m.p.len())
            .rev()
            .find(|&k| m.print[k] && m.p[k].y.abs() < 1e-9)
            .unwrap()
    };
    for beside in [120.0, -120.0] {
        let tp = wall_then_bead(29, beside);
        let job = common::default_job(&model, &tp);
        let ev = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
        let e = one(&ev, at).outcome.unwrap_err();
        assert_eq!(e.reason, Reason::CollisionPart, "beside {beside} mm: {e}");
        assert!(e.detail.contains("print head"), "{e}");
        let k = e.sample.expect("the sample");
        assert!(
            k > wall_samples,
            "{e}: after the wall (sample {wall_samples})"
        );
        let p = e.point_m.unwrap();
        // Below the wall's top, beside it.
        let part = at.frame().inverse().apply(&printwatt::math::V3::from(p));
        assert!(
            part.z < 0.58 && (part.y - beside / 1000.0).abs() < 1e-6,
            "{part:?}"
        );
        assert!(e.to_string().contains("sample"), "{e}");
    }
}

#[test]
fn every_exported_module_reads_back_into_the_exported_path_to_1_um_and_the_planned_configuration() {
    use printwatt::export;
    use printwatt::toolpath::{parse_rapid, read_program};
    let model = common::robot("abb_irb6700_200_260");
    let tp = common::path("default.gcode");
    let job = common::default_job(&model, &tp);
    let at = through_the_wrist().with_spin(10f64.to_radians());
    for margin_deg in [0.0, 5.0] {
        let o = FeasibilityOptions {
            wrist_margin_rad: f64::to_radians(margin_deg),
            ..Default::default()
        };
        let ev = Evaluator::new(&job, o, Objective::Supply);
        let files = export::hand_off(&ev, &at, "").unwrap();
        let points = export::base_frame_path(&job.moves, &at);
        let plan = export::joint_plan(&ev, &points, &at).unwrap();
        let mut sc = ev.scratch().unwrap();
        let timed = ev.timed(&mut sc, &at).unwrap();
        let mut modules = 0;
        for (name, text) in &files {
            if !name.ends_with(".mod") {
                continue;
            }
            modules += 1;
            // Parses as a path and as a program; no comment before MODULE, one module.
            let opts = printwatt::toolpath::ReadOptions::default();
            let path = parse_rapid(text, name, &opts).unwrap_or_else(|e| panic!("{name}: {e}"));
            let prog = read_program(text, name).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(prog.comments_before_module, 0, "{name}");
            assert_eq!(prog.modules.len(), 1, "{name}");
            if name == "wobj_print.mod" {
                assert!(text.contains("PERS wobjdata wobjPrint"), "{text}");
                continue;
            }
            let part = name == "path_part.mod";
            // The tool load with the drive file's inertia (0.7875, 0.7875, 0.675 kg m²).
            assert!(
                text.contains("[1.000000000, 0.000000000, 0.000000000, 0.000000000], 0.7875, 0.7875, 0.6750]]"),
                "{name}: {}",
                text.lines().find(|l| l.contains("tooldata")).unwrap()
            );
            // The path to 1 µm, in the base frame (the part-frame module through the placement).
            assert_eq!(prog.targets.len(), points.len(), "{name}");
            let frame = at.frame();
            for (t, b) in prog.targets.iter().zip(&points) {
                let p = printwatt::math::V3::from(t.pos_mm) / 1000.0;
                let base = if part { frame.apply(&p) } else { p };
                assert!(
                    (base - b.p).norm() < 1e-6,
                    "{name} line {}: {base:?} vs {:?}",
                    t.line,
                    b.p
                );
                assert_eq!(t.wobj, if part { "wobjPrint" } else { "wobj0" });
            }
            let ends: Vec<_> = std::iter::once(path.start)
                .chain(path.moves.iter().map(|m| m.end))
                .collect();
            let mut k = 0;
            for b in &points {
                let want = if part {
                    frame.inverse().apply(&b.p)
                } else {
                    b.p
                };
                if (ends[k] - want).norm() > 1e-6 {
                    k += 1;
                }
                assert!((ends[k] - want).norm() < 1e-6, "{name}: point {k}");
            }
            assert_eq!(k + 1, ends.len(), "{name}");
            // The configuration: the plan's at every point, and the timed path's at the
            // nearest planned sample wherever no joint sits on a quadrant boundary.
            assert_eq!(prog.conf_l, Some(true), "{name}");
            let sing = if margin_deg == 0.0 { "wrist" } else { "off" };
            assert_eq!(prog.sing_area.as_deref(), Some(sing), "{name}");
            assert_eq!(prog.abs_moves, vec!["jstart".to_string()]);
            let (_, axes) = &prog.jointtargets[0];
            for (a, q) in axes.iter().zip(timed.traj.q(0)) {
                assert!((a - q.to_degrees()).abs() < 1e-4, "{axes:?}");
            }
            let mut compared = 0;
            for (i, t) in prog.targets.iter().enumerate() {
                assert_eq!(t.conf, export::abb_conf(&model, &plan.points[i]), "{name}");
                let b = points[i].p;
                let k = (0..timed.tcp.len())
                    .min_by(|&x, &y| {
                        (timed.tcp[x] - b)
                            .norm()
                            .total_cmp(&(timed.tcp[y] - b).norm())
                    })
                    .unwrap();
                if (timed.tcp[k] - b).norm() > 1e-3 {
                    continue;
                }
                // Entry by entry, where the joint does not sit on a quadrant boundary (q4 and
                // q6 of a vertical nozzle often stay at 0) or q5 at 0 (cfx's sign bit).
                let q = timed.traj.q(k);
                let want = export::abb_conf(&model, q);
                let on_edge = |v: f64| {
                    let r = v.to_degrees() / 90.0;
                    (r - r.round()).abs() * 90.0 < 0.5
                };
                let skip = [
                    on_edge(q[0]),
                    on_edge(q[3]),
                    on_edge(q[5]),
                    q[4].abs() < 1e-3,
                ];
                for i in 0..4 {
                    if !skip[i] {
                        assert_eq!(t.conf[i], want[i], "{name} line {} entry {i}", t.line);
                        compared += 1;
                    }
                }
            }
            assert!(compared > prog.targets.len(), "{name}: {compared} compared");
        }
        assert_eq!(modules, 3);
    }
}

#[test]
fn abb_configuration_of_the_irb_6700_home_pose_and_its_mirror_images() {
    use printwatt::export::abb_conf;
    let model = common::robot("abb_irb6700_200_260");
    let d = f64::to_radians;
    // Home with the wrist bent down: in front of axis 1, forward of the lower arm, q5 > 0.
    assert_eq!(
        abb_conf(&model, &[0.0, 0.0, 0.0, 0.0, d(30.0), 0.0]),
        [0, 0, 0, 0]
    );
    assert_eq!(
        abb_conf(&model, &[0.0, 0.0, 0.0, 0.0, d(-30.0), 0.0]),
        [0, 0, 0, 1]
    );
    // Quadrants of axes 1, 4 and 6.
    assert_eq!(
        abb_conf(&model, &[d(100.0), 0.0, 0.0, d(-10.0), d(30.0), d(185.0)]),
        [1, -1, 2, 0]
    );
    // The lower arm tilted back 80°: the wrist centre behind axis 1, still forward of the
    // lower arm.
    let back = abb_conf(&model, &[0.0, d(-80.0), 0.0, 0.0, d(30.0), 0.0]);
    assert_eq!(back, [0, 0, 0, 4]);
}

#[test]
fn the_wrist_margin_is_a_checked_library_setting_with_one_default() {
    use printwatt::search::job::OptimiseSettings;
    let d = printwatt::evaluate::feasibility::margins::DEFAULT_WRIST_MARGIN_DEG;
    let o = OptimiseSettings::default();
    assert_eq!(
        o.feasibility.wrist_margin_rad,
        FeasibilityOptions::default().wrist_margin_rad
    );
    assert!((o.feasibility.wrist_margin_rad.to_degrees() - d).abs() < 1e-12);
    assert!(o.check().is_ok());
    for deg in [0.0, 90.0] {
        let f = FeasibilityOptions {
            wrist_margin_rad: f64::to_radians(deg),
            ..Default::default()
        };
        assert!(f.check().is_ok(), "{deg}°");
    }
    for bad in [-1.0, 91.0, f64::NAN] {
        let mut s = OptimiseSettings::default();
        s.feasibility.wrist_margin_rad = f64::to_radians(bad);
        let m = s.check().unwrap_err().to_string();
        // Named as the setting, not as a command-line option.
        assert!(m.starts_with("wrist margin "), "{m}");
        assert!(!m.contains("--"), "{m}");
    }
}
