//! Take the answer to the robot: the chosen placement as an ABB RAPID `wobjdata` (the part
//! frame as the work object's user frame, in mm and a unit quaternion `[q1, q2, q3, q4]` =
//! `[w, x, y, z]`, robot base = world assumed), and as a JSON frame in the COMPAS `Frame`
//! layout (`point`, `xaxis`, `yaxis`; m) for COMPAS / Grasshopper users. A RAPID or G-code path
//! written in the part frame then runs where the placement says when programmed in this work
//! object. The path itself is also written re-expressed point by point in the robot base
//! frame, as G-code ([`gcode_base`]) and as an ABB RAPID module of `MoveL`s in `wobj0`
//! ([`rapid_base`]), for controllers and slicers that take the path in base coordinates.

use crate::frame::Placement;
use crate::math::V3;
use crate::robot::RobotModel;
use crate::timing::{Move, Prim};

/// Largest chord of an arc (or any curved move) in the exported base-frame path, m (5 mm: a
/// chordal error of 0.03 mm on a 0.1 m radius).
pub const EXPORT_CHORD_M: f64 = 0.005;

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

/// An ABB RAPID module of the path in the robot base frame: a `tooldata` for the nozzle (tool
/// frame and payload of the robot), then one `MoveL` per point in `wobj0` (mm, the nozzle's
/// orientation as a quaternion, `ConfL \Off`), speed `[v_tcp, 500, 5000, 1000]` mm/s and the
/// move's zone (`fine` at fine points).
pub fn rapid_base(points: &[BasePoint], at: &Placement, model: &RobotModel) -> String {
    let mut s = header(at, model.name(), "!");
    let tq = quat(&model.tool.rot);
    let (mass, cog) = model
        .payload
        .map_or((0.001, V3::zeros()), |p| (p.mass.max(0.001), p.com));
    s.push_str("MODULE printwatt_path_base\n");
    s.push_str(&format!(
        "  PERS tooldata tNozzle := [TRUE, [[{:.3}, {:.3}, {:.3}], [{:.9}, {:.9}, {:.9}, {:.9}]], [{:.3}, [{:.3}, {:.3}, {:.3}], [1, 0, 0, 0], 0, 0, 0]];\n",
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
        cog.z * 1000.0
    ));
    let q = quat(&at.nozzle_target(&V3::zeros()).rot);
    s.push_str("  PROC print_path()\n    ConfL \\Off;\n");
    for b in points {
        let zone = if b.zone <= 0.0 {
            "fine".to_string()
        } else {
            format!(
                "[FALSE, {0:.1}, {0:.1}, {0:.1}, {1:.1}, {0:.1}, {1:.1}]",
                b.zone * 1000.0,
                b.zone * 100.0
            )
        };
        s.push_str(&format!(
            "    MoveL [[{:.3}, {:.3}, {:.3}], [{:.9}, {:.9}, {:.9}, {:.9}], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]], [{:.1}, 500, 5000, 1000], {zone}, tNozzle \\WObj:=wobj0; ! line {}\n",
            b.p.x * 1000.0,
            b.p.y * 1000.0,
            b.p.z * 1000.0,
            q[0],
            q[1],
            q[2],
            q[3],
            b.speed * 1000.0,
            b.line
        ));
    }
    s.push_str("  ENDPROC\nENDMODULE\n");
    s
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
