//! Take the answer to the robot: the chosen placement as an ABB RAPID `wobjdata` (the part
//! frame as the work object's user frame, in mm and a unit quaternion `[q1, q2, q3, q4]` =
//! `[w, x, y, z]`, robot base = world assumed), and as a JSON frame in the COMPAS `Frame`
//! layout (`point`, `xaxis`, `yaxis`; m) for COMPAS / Grasshopper users. A RAPID or G-code path
//! written in the part frame then runs where the placement says when programmed in this work
//! object. The path itself is also written re-expressed point by point in the robot base
//! frame, as G-code ([`gcode_base`]) and as an ABB RAPID module of `MoveL`s in `wobj0`
//! ([`rapid_base`]), for controllers and slicers that take the path in base coordinates.
//!
//! The hand-off a controller runs as is ([`hand_off`]): the nozzle's `tooldata` with the
//! drive file's payload and its inertia, a start `jointtarget` at the planned first sample,
//! every robtarget's configuration `[cf1, cf4, cf6, cfx]` from the planned branch
//! ([`abb_conf`]) with `ConfL \On`, `SingArea \Wrist` where the wrist may pass through its
//! singularity (a wrist margin of 0; `\Off` otherwise), a part-frame module that prints in
//! `wobjPrint` ([`rapid_part`]), comments inside the modules. Every module reads back with
//! printwatt's own RAPID reader ([`crate::toolpath::rapid`]) into the exported path. A
//! Universal Robots arm gets a URScript program instead of the RAPID modules
//! ([`urscript`]), read back the same way.

pub mod urscript;

use crate::frame::Placement;
use crate::math::V3;
use crate::robot::RobotModel;
use crate::timing::{Move, Prim};

/// Largest chord of an arc (or any curved move) in the exported base-frame path, m (5 mm: a
/// chordal error of 0.03 mm on a 0.1 m radius).
pub(crate) const EXPORT_CHORD_M: f64 = 0.005;

/// One point of the path in the robot base frame: the end of a (piece of a) programmed move.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BasePoint {
    /// Nozzle tip, robot base frame, m.
    pub p: V3,
    /// Commanded TCP speed of the move ending here, m/s.
    pub speed: f64,
    /// Corner zone at the end of the move, m (0 = fine point); 0 inside a subdivided arc's
    /// last chord only when the move itself stops.
    pub zone: f64,
    /// The move ending here extrudes.
    pub print: bool,
    /// Source line of the programmed move.
    pub line: usize,
}

/// The programmed path (part frame) placed at `at`: the start point, then the end of every
/// move, curved moves subdivided into chords of at most [`EXPORT_CHORD_M`].
pub fn base_frame_path(moves: &[Move], at: &Placement) -> Vec<BasePoint> {
    let f = at.frame();
    let mut out = Vec::new();
    if let Some(m0) = moves.first() {
        out.push(BasePoint {
            p: f.apply(&m0.prim.point(0.0)),
            speed: m0.speed,
            zone: 0.0,
            print: false,
            line: m0.line,
        });
    }
    for m in moves {
        let len = m.prim.length();
        let n = match m.prim {
            Prim::Line { .. } => 1,
            _ => ((len / EXPORT_CHORD_M).ceil() as usize).max(1),
        };
        for i in 1..=n {
            let s = len * i as f64 / n as f64;
            out.push(BasePoint {
                p: f.apply(&m.prim.point(s)),
                speed: m.speed,
                zone: if i == n { m.zone } else { m.zone.max(0.0005) },
                print: m.print,
                line: m.line,
            });
        }
    }
    out
}

fn header(at: &Placement, robot: &str, comment: &str) -> String {
    format!(
        "{comment} printwatt: path re-expressed in the robot base frame of {robot} (mm)\n{comment} placement: x = {:.4} m, y = {:.4} m, z = {:.4} m, part yaw = {:.4} deg, nozzle spin = {:.4} deg\n{comment} nozzle vertical (tool z = -Z of the base), turned by yaw + spin = {:.4} deg about it\n",
        at.x,
        at.y,
        at.z,
        at.yaw.to_degrees(),
        at.nozzle_spin.to_degrees(),
        at.nozzle_yaw().to_degrees()
    )
}

/// G-code of the path in the robot base frame: `G21 G90`, then `G0` (travel) / `G1` (print)
/// with `X Y Z` in mm and `F` in mm/min; printwatt reads it back as the same path with the
/// placement at the origin.
pub fn gcode_base(points: &[BasePoint], at: &Placement, robot: &str) -> String {
    let mut s = header(at, robot, ";");
    s.push_str("G21\nG90\n");
    for (i, b) in points.iter().enumerate() {
        let g = if i == 0 || !b.print { "G0" } else { "G1" };
        s.push_str(&format!(
            "{g} X{:.4} Y{:.4} Z{:.4} F{:.1} ; line {}\n",
            b.p.x * 1000.0,
            b.p.y * 1000.0,
            b.p.z * 1000.0,
            b.speed * 60_000.0,
            b.line
        ));
    }
    s
}

/// Unit quaternion `[q1, q2, q3, q4]` = `[w, x, y, z]` of a rotation matrix.
fn quat(r: &crate::math::M3) -> [f64; 4] {
    let q = nalgebra::UnitQuaternion::from_rotation_matrix(
        &nalgebra::Rotation3::from_matrix_unchecked(*r),
    );
    [q.w, q.i, q.j, q.k]
}

/// The arm configuration the plan holds along an exported path: the joint vector (rad) at the
/// planned first sample (the program's start `jointtarget`) and at every exported point
/// (inverse kinematics continued from the previous point, so on the planned branch), and
/// whether the wrist may pass through its singularity (a wrist margin of 0: the program then
/// sets `SingArea \Wrist`).
#[derive(Clone, Debug, PartialEq)]
pub struct JointPlan {
    /// Joint positions at the planned first sample, rad.
    pub start: Vec<f64>,
    /// Joint positions at each exported point, rad (one per point).
    pub points: Vec<Vec<f64>>,
    /// The wrist may pass through its singularity (`SingArea \Wrist`); else `SingArea \Off`.
    pub wrist_through: bool,
}

/// The [`JointPlan`] of `points` (from [`base_frame_path`] at `at`) under `ev`'s job and
/// feasibility options: the placement is timed as the evaluation times it, and the joints at
/// each point continue the planned first sample's configuration.
pub fn joint_plan(
    ev: &crate::evaluate::Evaluator<'_, '_>,
    points: &[BasePoint],
    at: &Placement,
) -> crate::error::Result<JointPlan> {
    let mut sc = ev.scratch()?;
    let timed = ev
        .timed(&mut sc, at)
        .map_err(|e| crate::error::Error::Invalid(format!("the placement does not time: {e}")))?;
    let start = timed.traj.q(0).to_vec();
    let solver = crate::kinematics::IkSolver::new(ev.job.robot)
        .map_err(|e| crate::error::Error::Invalid(format!("inverse kinematics: {e}")))?;
    let mut prev = start.clone();
    let mut out = Vec::with_capacity(points.len());
    for b in points {
        let target = crate::kinematics::nozzle_target(&b.p, at.nozzle_yaw());
        let q = solver.solve_near(&target, &prev).map_err(|e| {
            crate::error::Error::Invalid(format!(
                "exported point of line {} ({:.1}, {:.1}, {:.1}) mm: {e}",
                b.line,
                b.p.x * 1000.0,
                b.p.y * 1000.0,
                b.p.z * 1000.0
            ))
        })?;
        prev = q.to_vec();
        out.push(prev.clone());
    }
    Ok(JointPlan {
        start,
        points: out,
        wrist_through: crate::evaluate::feasibility::margins::wrist_floor(&ev.feasibility) == 0.0,
    })
}

/// ABB configuration data `[cf1, cf4, cf6, cfx]` of the joint vector `q` (rad; the URDF's
/// joint angles taken as the controller's): `cf1`, `cf4`, `cf6` the quadrant of axes 1, 4 and 6
/// (`floor(q / 90°)`: 0 for [0°, 90°), −1 for [−90°, 0°), …), `cfx` from ABB's table (RAPID
/// reference, `confdata`): 4 × (wrist centre behind axis 1) + 2 × (wrist centre backward of
/// the lower arm) + (axis 5 negative). The wrist centre is the flange less `c4` along its
/// axis (OPW arms; the origin of joint 5 otherwise).
pub fn abb_conf(model: &RobotModel, q: &[f64]) -> [i32; 4] {
    let quadrant = |v: f64| (v / std::f64::consts::FRAC_PI_2).floor() as i32;
    let at = |j: usize| q.get(j).copied().unwrap_or(0.0);
    let f = crate::kinematics::fk::fk(model, q);
    let joints = f.joint_frames();
    let wc = match &model.opw {
        Some(p) => f.flange.pos - f.flange.rot.column(2) * p.c4,
        None => joints.get(4).map_or(f.flange.pos, |j| j.pos),
    };
    // The arm plane: axis 1 along base z through the origin; (r, z) after turning by −q1.
    let (s1, c1) = at(0).sin_cos();
    let plane = |p: &V3| (c1 * p.x + s1 * p.y, p.z);
    let (wr, wz) = plane(&wc);
    let behind = wr < 0.0;
    let backward = match (joints.get(1), joints.get(2)) {
        (Some(a2), Some(a3)) => {
            let (r2, z2) = plane(&a2.pos);
            let (r3, z3) = plane(&a3.pos);
            let (ur, uz) = (r3 - r2, z3 - z2);
            let (vr, vz) = (wr - r2, wz - z2);
            ur * vz - uz * vr > 0.0
        }
        _ => false,
    };
    let negative5 = at(4) < 0.0;
    [
        quadrant(at(0)),
        quadrant(at(3)),
        quadrant(at(5)),
        4 * i32::from(behind) + 2 * i32::from(backward) + i32::from(negative5),
    ]
}

/// The `tooldata` of the nozzle: tool frame of the robot, load from the drive file's payload
/// (mass, centre of mass, principal axes and moments of inertia, kg·m²).
fn tooldata(model: &RobotModel) -> String {
    let tq = quat(&model.tool.rot);
    let (mass, cog, aom, moments) = match model.payload {
        Some(p) if p.mass > 0.0 => {
            let e = nalgebra::SymmetricEigen::new(p.inertia);
            let mut axes = e.eigenvectors;
            if axes.determinant() < 0.0 {
                axes.set_column(2, &(-axes.column(2)));
            }
            // Principal axes along the tool axes where the tensor is diagonal already.
            let diagonal = (0..3).all(|i| (0..3).all(|j| i == j || p.inertia[(i, j)] == 0.0));
            if diagonal {
                (
                    p.mass,
                    p.com,
                    [1.0, 0.0, 0.0, 0.0],
                    [p.inertia[(0, 0)], p.inertia[(1, 1)], p.inertia[(2, 2)]],
                )
            } else {
                (
                    p.mass,
                    p.com,
                    quat(&axes),
                    [e.eigenvalues[0], e.eigenvalues[1], e.eigenvalues[2]],
                )
            }
        }
        _ => (0.001, V3::zeros(), [1.0, 0.0, 0.0, 0.0], [0.0; 3]),
    };
    format!(
        "  PERS tooldata tNozzle := [TRUE, [[{:.3}, {:.3}, {:.3}], [{:.9}, {:.9}, {:.9}, {:.9}]], [{:.3}, [{:.3}, {:.3}, {:.3}], [{:.9}, {:.9}, {:.9}, {:.9}], {:.4}, {:.4}, {:.4}]];\n",
        model.tool.pos.x * 1000.0,
        model.tool.pos.y * 1000.0,
        model.tool.pos.z * 1000.0,
        tq[0],
        tq[1],
        tq[2],
        tq[3],
        mass,
        cog.x * 1000.0,
        cog.y * 1000.0,
        cog.z * 1000.0,
        aom[0],
        aom[1],
        aom[2],
        aom[3],
        moments[0],
        moments[1],
        moments[2]
    )
}

/// A RAPID module `name` of `MoveL`s to `points` (mm in the work object `wobj`, the nozzle's
/// orientation `q` there), `header` (comment lines, `!`) inside the module, `decls` after
/// the tool. With a `plan`: a start `jointtarget` at the planned first sample reached by
/// `MoveAbsJ`, each robtarget's configuration from the plan, `ConfL \On` and `SingArea`;
/// without: configuration `[0, 0, 0, 0]` and `ConfL \Off`.
#[allow(clippy::too_many_arguments)]
fn rapid_module(
    name: &str,
    header: &str,
    decls: &str,
    points: &[(V3, &BasePoint)],
    q: [f64; 4],
    wobj: &str,
    model: &RobotModel,
    plan: Option<&JointPlan>,
) -> String {
    let mut s = format!("MODULE {name}\n");
    for l in header.lines() {
        s.push_str(&format!("  {l}\n"));
    }
    s.push_str(&tooldata(model));
    s.push_str(decls);
    if let Some(p) = plan {
        let mut j = [0.0; 6];
        for (v, q) in j.iter_mut().zip(&p.start) {
            *v = q.to_degrees();
        }
        s.push_str(&format!(
            "  CONST jointtarget jStart := [[{:.4}, {:.4}, {:.4}, {:.4}, {:.4}, {:.4}], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]];\n",
            j[0], j[1], j[2], j[3], j[4], j[5]
        ));
    }
    s.push_str("  PROC print_path()\n");
    match plan {
        Some(p) => {
            s.push_str("    ConfL \\On;\n");
            s.push_str(if p.wrist_through {
                "    SingArea \\Wrist;\n"
            } else {
                "    SingArea \\Off;\n"
            });
            s.push_str(&format!(
                "    MoveAbsJ jStart, v100, fine, tNozzle \\WObj:={wobj};\n"
            ));
        }
        None => s.push_str("    ConfL \\Off;\n"),
    }
    for (i, (p, b)) in points.iter().enumerate() {
        let zone = if b.zone <= 0.0 {
            "fine".to_string()
        } else {
            format!(
                "[FALSE, {0:.1}, {0:.1}, {0:.1}, {1:.1}, {0:.1}, {1:.1}]",
                b.zone * 1000.0,
                b.zone * 100.0
            )
        };
        let cf = plan
            .and_then(|pl| pl.points.get(i))
            .map_or([0; 4], |qj| abb_conf(model, qj));
        s.push_str(&format!(
            "    MoveL [[{:.3}, {:.3}, {:.3}], [{:.9}, {:.9}, {:.9}, {:.9}], [{}, {}, {}, {}], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]], [{:.1}, 500, 5000, 1000], {zone}, tNozzle \\WObj:={wobj}; ! line {}\n",
            p.x * 1000.0,
            p.y * 1000.0,
            p.z * 1000.0,
            q[0],
            q[1],
            q[2],
            q[3],
            cf[0],
            cf[1],
            cf[2],
            cf[3],
            b.speed * 1000.0,
            b.line
        ));
    }
    s.push_str("  ENDPROC\nENDMODULE\n");
    s
}

/// An ABB RAPID module of the path in the robot base frame: a `tooldata` for the nozzle (tool
/// frame and payload of the robot, with its inertia), then one `MoveL` per point in `wobj0`
/// (mm, the nozzle's orientation as a quaternion, configuration `[0, 0, 0, 0]`,
/// `ConfL \Off`), speed `[v_tcp, 500, 5000, 1000]` mm/s and the move's zone (`fine` at fine
/// points). [`rapid_base_planned`] hands the planned arm configuration over as well.
pub fn rapid_base(points: &[BasePoint], at: &Placement, model: &RobotModel) -> String {
    rapid_base_with(points, at, model, None)
}

/// [`rapid_base`] with the arm configuration of `plan`: a start `jointtarget` at the planned
/// first sample (`MoveAbsJ`), each robtarget's `[cf1, cf4, cf6, cfx]` ([`abb_conf`]) from the
/// planned branch, `ConfL \On` and `SingArea \Wrist` where the wrist may pass through its
/// singularity (`\Off` otherwise).
pub(crate) fn rapid_base_planned(
    points: &[BasePoint],
    at: &Placement,
    model: &RobotModel,
    plan: &JointPlan,
) -> String {
    rapid_base_with(points, at, model, Some(plan))
}

fn rapid_base_with(
    points: &[BasePoint],
    at: &Placement,
    model: &RobotModel,
    plan: Option<&JointPlan>,
) -> String {
    let q = quat(&at.nozzle_target(&V3::zeros()).rot);
    let pts: Vec<(V3, &BasePoint)> = points.iter().map(|b| (b.p, b)).collect();
    rapid_module(
        "printwatt_path_base",
        &header(at, model.name(), "!"),
        "",
        &pts,
        q,
        "wobj0",
        model,
        plan,
    )
}

/// The path in the part frame as a RAPID module that prints in the work object `wobjPrint`
/// (declared in it, [`wobjdata`]): the same points as [`rapid_base_planned`]'s, each
/// expressed in the part frame (mm), the nozzle's orientation there (its spin relative to the
/// part), with the plan's configuration, start `jointtarget`, `ConfL \On` and `SingArea`.
/// Moving the work object moves the print; the configuration holds near the planned placement.
pub(crate) fn rapid_part(
    points: &[BasePoint],
    at: &Placement,
    model: &RobotModel,
    plan: &JointPlan,
) -> String {
    let to_part = at.frame().inverse();
    let q = quat(&crate::kinematics::nozzle_target(&V3::zeros(), at.nozzle_spin).rot);
    let pts: Vec<(V3, &BasePoint)> = points.iter().map(|b| (to_part.apply(&b.p), b)).collect();
    let head = format!(
        "! printwatt: path in the part frame, printed in the work object wobjPrint (mm)\n{}",
        header(at, model.name(), "!")
    );
    let decl: String = wobjdata("wobjPrint", at)
        .lines()
        .map(|l| format!("  {l}\n"))
        .collect();
    rapid_module(
        "printwatt_path_part",
        &head,
        &decl,
        &pts,
        q,
        "wobjPrint",
        model,
        Some(plan),
    )
}

/// Every file of the hand-off at `at` for `ev`'s job, as (file name, text): the COMPAS frame
/// (`frame.json`) and the base-frame path as G-code (`path_base.gcode`) for every arm; then,
/// for a Universal Robots arm, the URScript program (`path_base.script`, [`urscript`]), and
/// for the others the RAPID work object (`wobj_print.mod`), the base-frame path with the
/// planned configuration (`path_base.mod`) and the part-frame module printing in `wobjPrint`
/// (`path_part.mod`). `prefix` is put before every file name (e.g. `station_1_` for one
/// program per station).
pub fn hand_off(
    ev: &crate::evaluate::Evaluator<'_, '_>,
    at: &Placement,
    prefix: &str,
) -> crate::error::Result<Vec<(String, String)>> {
    let model = ev.job.robot;
    let points = base_frame_path(&ev.job.moves, at);
    let plan = joint_plan(ev, &points, at)?;
    let json = serde_json::to_string_pretty(&compas_frame(at))
        .map_err(|e| crate::error::Error::Invalid(format!("frame.json: {e}")))?;
    let mut out = vec![
        (format!("{prefix}frame.json"), json),
        (
            format!("{prefix}path_base.gcode"),
            gcode_base(&points, at, model.name()),
        ),
    ];
    if urscript::is_universal_robots(model) {
        out.push((
            format!("{prefix}path_base.script"),
            urscript::urscript(&points, at, model, &plan, ev.job.profile.accel),
        ));
        return Ok(out);
    }
    out.insert(
        0,
        (
            format!("{prefix}wobj_print.mod"),
            format!(
                "MODULE printwatt_placement\n{}ENDMODULE\n",
                wobjdata("wobjPrint", at)
                    .lines()
                    .map(|l| format!("  {l}\n"))
                    .collect::<String>()
            ),
        ),
    );
    out.push((
        format!("{prefix}path_base.mod"),
        rapid_base_planned(&points, at, model, &plan),
    ));
    out.push((
        format!("{prefix}path_part.mod"),
        rapid_part(&points, at, model, &plan),
    ));
    Ok(out)
}

/// The RAPID declaration `PERS wobjdata <name> := [FALSE, TRUE, "", [[x, y, z], [q1, q2, q3,
/// q4]], [[0, 0, 0], [1, 0, 0, 0]]];` of the part frame (mm, quaternion of the yaw about z).
/// The nozzle spin is a tool rotation, not part of the work object: it is stated in a comment.
pub fn wobjdata(name: &str, p: &Placement) -> String {
    let (s, c) = (0.5 * p.yaw).sin_cos();
    format!(
        "! printwatt placement: x = {:.4} m, y = {:.4} m, z = {:.4} m, yaw = {:.4} deg; nozzle spin {:.4} deg about the tool z\n\
         PERS wobjdata {name} := [FALSE, TRUE, \"\", [[{:.3}, {:.3}, {:.3}], [{:.9}, 0, 0, {:.9}]], [[0, 0, 0], [1, 0, 0, 0]]];\n",
        p.x,
        p.y,
        p.z,
        p.yaw.to_degrees(),
        p.nozzle_spin.to_degrees(),
        p.x * 1000.0,
        p.y * 1000.0,
        p.z * 1000.0,
        c,
        s
    )
}

/// The part frame as a COMPAS `Frame` JSON object (m): `{"point", "xaxis", "yaxis"}`, plus the
/// nozzle spin in degrees.
pub fn compas_frame(p: &Placement) -> serde_json::Value {
    let (s, c) = p.yaw.sin_cos();
    serde_json::json!({
        "dtype": "compas.geometry/Frame",
        "data": {
            "point": [p.x, p.y, p.z],
            "xaxis": [c, s, 0.0],
            "yaxis": [-s, c, 0.0],
        },
        "nozzle_spin_deg": p.nozzle_spin.to_degrees(),
        "units": "m",
    })
}

/// [`hand_off`] for each station of a multi-station plan: one set of files per station,
/// named `station_<k>_…` (k from 1) with module names `printwatt_station_<k>_…`, each the
/// station's sub-path (`moves`: first and last move of `path`, inclusive) at its placement.
#[allow(clippy::too_many_arguments)]
pub fn stations_hand_off(
    robot: &RobotModel,
    path: &crate::toolpath::Toolpath,
    stations: &[([usize; 2], Placement)],
    energy: crate::energy::EnergyOptions,
    profile: crate::timing::ProfileOptions,
    feasibility: crate::evaluate::feasibility::FeasibilityOptions,
    objective: crate::evaluate::Objective,
) -> crate::error::Result<Vec<(String, String)>> {
    let mut out = Vec::new();
    for (k, (moves, at)) in stations.iter().enumerate() {
        let [a, b] = *moves;
        let sub = crate::toolpath::Toolpath {
            source: format!("{} (station {})", path.source, k + 1),
            start: if a == 0 {
                path.start
            } else {
                path.moves[a - 1].end
            },
            moves: path.moves[a..=b.min(path.moves.len().saturating_sub(1))].to_vec(),
            ..Default::default()
        };
        let job = crate::evaluate::PathJob::new(
            robot,
            &sub,
            energy,
            profile,
            crate::timing::JointStageOptions::default(),
        )?;
        let ev = crate::evaluate::Evaluator::new(&job, feasibility, objective);
        let prefix = format!("station_{}_", k + 1);
        for (name, text) in hand_off(&ev, at, &prefix)? {
            let text = text
                .replacen(
                    "MODULE printwatt_",
                    &format!("MODULE printwatt_{prefix}"),
                    1,
                )
                .replace("printwatt_path()", &format!("printwatt_{prefix}path()"));
            out.push((name, text));
        }
    }
    Ok(out)
}
