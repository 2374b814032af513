//! Take the answer to the robot: the chosen placement as an ABB RAPID `wobjdata` (the part
//! frame as the work object's user frame, in mm and a unit quaternion `[q1, q2, q3, q4]` =
//! `[w, x, y, z]`, robot base = world assumed), and as a JSON frame in the COMPAS `Frame`
//! layout (`point`, `xaxis`, `yaxis`; m) for COMPAS / Grasshopper users. A RAPID or G-code path
//! written in the part frame then runs where the placement says when programmed in this work
//! object. (The path re-expressed point by point in the base frame is not written yet.)

use crate::toolpath::Placement;

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
