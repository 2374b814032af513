//! The hand-off for a Universal Robots arm: `optimise --export` writes one URScript program
//! for the shipped UR10e that reads back (printwatt's URScript reader refuses anything outside
//! the subset it writes) into the exported path to 1 µm, with the nozzle vertical, the
//! planned first sample as the start `movej`, the tool centre point and the payload with its
//! inertia, and the wrist stated.

mod common;

use printwatt::evaluate::feasibility::FeasibilityOptions;
use printwatt::evaluate::{Evaluator, Objective};
use printwatt::export::{self, urscript};
use printwatt::frame::Placement;
use printwatt::kinematics::fk::tool_pose;

/// A feasible placement of the seed test path on the UR10e under `o`: the first of a small
/// grid.
fn feasible(ev: &Evaluator) -> Placement {
    let mut grid = Vec::new();
    for x in [0.6, 0.7, 0.8, 0.5] {
        for y in [0.0, 0.2, -0.2] {
            for z in [0.0, 0.1, -0.1] {
                for yaw in [0.0, 90.0f64] {
                    grid.push(Placement::new(x, y, z, yaw.to_radians()));
                }
            }
        }
    }
    let rows = ev.sweep(&grid, &|_, _| {}).unwrap();
    rows.iter()
        .find(|r| r.feasible().is_some())
        .map(|r| r.placement)
        .expect("a feasible UR10e placement of the seed test path in the grid")
}

#[test]
fn the_ur10e_export_is_a_urscript_program_that_reads_back_into_the_exported_path() {
    let model = common::robot("ur10e");
    assert!(urscript::is_universal_robots(&model));
    let tp = common::path("seed000_test_path.gcode");
    let job = common::default_job(&model, &tp);
    for margin_deg in [5.0, 0.0] {
        let o = FeasibilityOptions {
            wrist_margin_rad: f64::to_radians(margin_deg),
            ..Default::default()
        };
        let ev = Evaluator::new(&job, o, Objective::Supply);
        let at = feasible(&ev);
        let files = export::hand_off(&ev, &at, "").unwrap();
        let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            ["frame.json", "path_base.gcode", "path_base.script"],
            "a UR arm gets URScript, not RAPID"
        );
        let text = &files[2].1;
        let prog = urscript::read_urscript(text, "path_base.script")
            .unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert!(prog.called, "the program runs its function");
        let points = export::base_frame_path(&job.moves, &at);
        let plan = export::joint_plan(&ev, &points, &at).unwrap();
        // The start: the planned first sample's joints, reached in joint space.
        assert_eq!(prog.movej.len(), 1);
        for (a, b) in prog.movej[0].iter().zip(&plan.start) {
            assert!((a - b).abs() < 1e-6, "movej {a} vs plan {b}");
        }
        // The path to 1 µm, nozzle vertical, and the first point where the start joints put
        // the tool.
        assert_eq!(prog.movel.len(), points.len());
        for (m, b) in prog.movel.iter().zip(&points) {
            assert!(
                (m.p_urdf_base() - b.p).norm() < 1e-6,
                "line {}: {:?} vs {:?}",
                m.line,
                m.p_urdf_base(),
                b.p
            );
            let z = m.rot_urdf_base().column(2).into_owned();
            assert!(
                (z - printwatt::math::V3::new(0.0, 0.0, -1.0)).norm() < 1e-5,
                "{z:?}"
            );
            assert!((m.v - b.speed.max(1e-4)).abs() < 1e-6);
            assert!((m.blend - b.zone).abs() < 1e-4);
        }
        let start_tool = tool_pose(&model, &plan.start);
        assert!(
            (start_tool.pos - points[0].p).norm() < 1e-5,
            "the start joints put the nozzle at {:?}, the path starts at {:?}",
            start_tool.pos,
            points[0].p
        );
        // The tool centre point and the payload with its inertia (drive file: 4 kg,
        // 0.0111/0.0111/0.0072 kg m²).
        let tcp = prog.tcp.expect("set_tcp");
        assert!((tcp[2] - model.tool.pos.z).abs() < 1e-6, "{tcp:?}");
        let (m, cog, inertia) = prog.payload.expect("set_target_payload");
        let p = model.payload.unwrap();
        assert!((m - p.mass).abs() < 1e-4);
        assert!((cog[2] - p.com.z).abs() < 1e-6);
        assert!((inertia[0] - 0.0111).abs() < 1e-6 && (inertia[2] - 0.0072).abs() < 1e-6);
        // The wrist, stated as the controller needs it.
        if margin_deg > 0.0 {
            assert!(text.contains("axis 5 stays at least"), "{text}");
        } else {
            assert!(text.contains("protective stop"), "{text}");
        }
    }
}

#[test]
fn an_abb_export_stays_rapid() {
    let model = common::robot("abb_irb6700_200_260");
    assert!(!urscript::is_universal_robots(&model));
}

#[test]
fn a_urscript_program_outside_the_subset_is_refused_with_file_and_line() {
    let e = urscript::read_urscript(
        "def printwatt_path():\n  movel(p[0.1, 0.2, 0.3, 0, 3.14, 0], a=1.0, v=0.1, r=0)\n  while True:\nend\n",
        "cell.script",
    )
    .unwrap_err();
    assert!(e.to_string().starts_with("cell.script:3: "), "{e}");
}
