//! A drive-file template for a URDF: the `drive.toml` a team fills in for its own arm.
//!
//! [`drive_template`] reads the URDF (as a robot given by its `.urdf` alone: link inertias it
//! lacks are estimated, [`super::inertia`]) and writes a drive file with one `[[joints]]`
//! table per actuated joint of its chain, every key explained in a comment beside it. Values
//! nobody can read off the URDF are placeholders marked `ESTIMATE` (with how they were made);
//! keys without a sensible placeholder (the drive train, the rated payload, the cabinet) are
//! written commented out, with what to put there. The template loads as it is: the rigid body
//! with the placeholder tool and joint limits (energy = the mechanical power until the drive
//! train is filled in). [`write_drive_template`] writes it through [`crate::output`], never over
//! an existing file.

use super::model::{Joint, JointKind, RobotModel};
use crate::error::{Error, Result};
use crate::output::{self, Existing, Inputs};
use std::fmt::Write as _;
use std::path::{Component, Path, PathBuf};

/// Seconds in which a main axis (joints 1–3) reaches its velocity limit, for the placeholder
/// acceleration limits (a typical industrial arm: 0.3–0.7 s).
pub(crate) const RAMP_MAIN_S: f64 = 0.5;
/// The same for the wrist axes (joints 4 and up).
pub(crate) const RAMP_WRIST_S: f64 = 0.35;
/// Seconds in which the acceleration limit builds up, for the placeholder jerk limits.
pub(crate) const JERK_RAMP_S: f64 = 0.1;
/// Placeholder nozzle tip below the flange, m (a 3DCP print head).
pub(crate) const TOOL_LENGTH_M: f64 = 0.3;

/// What [`write_drive_template`] wrote.
#[derive(Clone, Debug)]
pub struct Template {
    /// The drive file written.
    pub path: PathBuf,
    /// The `[robot] urdf` value: the URDF relative to the drive file.
    pub urdf_relative: String,
    /// The robot's name (the URDF's).
    pub robot: String,
    /// The actuated joints, one `[[joints]]` table each.
    pub joints: Vec<String>,
    /// Moving links whose inertia the URDF does not give (estimated; a commented
    /// `[links.<name>]` table each in the template).
    pub estimated_links: Vec<String>,
    /// The URDF reader's warnings (estimated inertias among them).
    pub warnings: Vec<String>,
    /// The template's text.
    pub text: String,
}

/// `to` relative to the directory `from_dir`, both made absolute first (`..` where they part);
/// `/` separated, as a drive file writes paths.
pub(crate) fn relative_path(to: &Path, from_dir: &Path) -> String {
    let to = output::resolve_lenient(to);
    let from = output::resolve_lenient(from_dir);
    let a: Vec<Component> = to.components().collect();
    let b: Vec<Component> = from.components().collect();
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut parts: Vec<String> = Vec::new();
    for _ in common..b.len() {
        parts.push("..".into());
    }
    for c in &a[common..] {
        parts.push(c.as_os_str().to_string_lossy().into_owned());
    }
    if parts.is_empty() {
        ".".into()
    } else {
        parts.join("/")
    }
}

/// A TOML basic string.
fn quoted(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}

/// A float as TOML writes it, rounded to 4 significant digits (placeholders claim no more).
fn num(x: f64) -> String {
    let r = output::round_significant(x, 4);
    let s = format!("{r}");
    if s.contains('.') || s.contains('e') || s.contains("inf") || s.contains("NaN") {
        s
    } else {
        format!("{s}.0")
    }
}

/// A float with every digit kept (values read from the URDF).
fn exact(x: f64) -> String {
    let s = format!("{x:?}");
    if s.contains('.') || s.contains('e') {
        s
    } else {
        format!("{s}.0")
    }
}

/// The template for the URDF `urdf`, to be written at `out` (its `[robot] urdf` is relative to
/// `out`'s directory). Errors name the URDF and its line as loading it does.
pub(crate) fn drive_template(urdf: &Path, out: &Path) -> Result<Template> {
    if !urdf.is_file() {
        return Err(Error::Invalid(format!(
            "{}: no such URDF file",
            urdf.display()
        )));
    }
    let model = super::load(urdf)?;
    let out_dir = out
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let rel = relative_path(urdf, out_dir);
    let text = template_text(&model, urdf, &rel);
    let estimated_links = model
        .info
        .inertia_sources
        .iter()
        .zip(&model.link_names)
        .filter(|(s, _)| s.is_estimate())
        .map(|(_, n)| n.clone())
        .collect();
    Ok(Template {
        path: out.to_path_buf(),
        urdf_relative: rel,
        robot: model.name().to_string(),
        joints: model.joints.iter().map(|j| j.name.clone()).collect(),
        estimated_links,
        warnings: model.warnings.clone(),
        text,
    })
}

/// Write the template for `urdf` to `out`: refused when `out` exists (nothing is ever
/// overwritten) or is the URDF itself.
pub fn write_drive_template(urdf: &Path, out: &Path) -> Result<Template> {
    let mut inputs = Inputs::new();
    inputs.add(urdf);
    output::check_file(out, &inputs, Existing::Force(false))?;
    let t = drive_template(urdf, out)?;
    output::write_file(out, t.text.as_bytes(), &inputs, Existing::Force(false))?;
    Ok(t)
}

fn template_text(m: &RobotModel, urdf: &Path, rel: &str) -> String {
    let file_name = urdf
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut s = String::new();
    write_header(&mut s, m, &file_name);
    write_robot(&mut s, m, rel, &file_name);
    write_tool(&mut s);
    write_payload_and_cabinet(&mut s);
    write_estimated_links(&mut s, m);
    let n = m.dof();
    for (i, j) in m.joints.iter().enumerate() {
        write_joint(&mut s, i, n, j);
    }
    s
}

/// The template's opening comment: what the file is and how to fill it in.
fn write_header(w: &mut String, m: &RobotModel, file_name: &str) {
    let _ = writeln!(
        w,
        "# drive.toml of {} -- a template written by printwatt from {file_name}",
        m.name()
    );
    let _ = writeln!(
        w,
        "# printwatt drive file (docs/drive-file.md): what the URDF does not say. SI units, the unit in\n\
         # every key's name. Values marked ESTIMATE are placeholders: replace them with the robot's\n\
         # numbers (datasheet, controller configuration, a measurement) and say where each came from\n\
         # in its comment. Keys written commented out (`# key = ...`) have no sensible placeholder:\n\
         # fill them in and remove the `#`. As written, this file loads: the rigid body with the\n\
         # placeholder tool and joint limits (energy = the mechanical power of the joints until the\n\
         # drive train of every joint is filled in)."
    );
    let _ = writeln!(w);
}

/// The `[robot]` table: the URDF, name, tool link, reach and provenance.
fn write_robot(w: &mut String, m: &RobotModel, rel: &str, file_name: &str) {
    let reach = super::reach_m(m);
    let _ = writeln!(w, "[robot]");
    let _ = writeln!(
        w,
        "urdf = {}  # the URDF, relative to this file (read when this file itself is given as the robot)",
        quoted(rel)
    );
    let _ = writeln!(
        w,
        "name = {}  # name in reports (the URDF's robot name)",
        quoted(m.name())
    );
    let _ = writeln!(
        w,
        "tool_link = {}  # the URDF link ending the arm chain: the flange frame, z out of the flange",
        quoted(&m.flange_link)
    );
    let _ = writeln!(
        w,
        "reach_m = {}  # ESTIMATE: the sum of the link lengths at the zero pose; the datasheet's reach sizes the default placement grid, the link capsules and the stations' footprint",
        num(reach)
    );
    let _ = writeln!(
        w,
        "# rated_payload_kg = 0.0  # the rated payload from the datasheet, kg: listed with the robots, and the link masses are checked against it"
    );
    let _ = writeln!(
        w,
        "# mass_kg = 0.0  # the robot's mass from the datasheet (base and arm, no payload), kg: link masses estimated from geometry are scaled to it"
    );
    let _ = writeln!(
        w,
        "provenance = \"kinematics, position and velocity limits from {file_name}; tool, acceleration and jerk limits ESTIMATE (template)\"  # where the numbers come from, shown with the robots"
    );
    let _ = writeln!(w);
}

/// The `[tool]` table and the commented `[tool.geometry]` one.
fn write_tool(w: &mut String) {
    let _ = writeln!(
        w,
        "[tool]  # the nozzle tip relative to tool_link, URDF xyz/rpy convention; the nozzle points along the tool frame's +z"
    );
    let _ = writeln!(
        w,
        "xyz_m = [0.0, 0.0, {}]  # ESTIMATE: a 3DCP nozzle tip {TOOL_LENGTH_M} m out of the flange along its z; measure the real head",
        num(TOOL_LENGTH_M)
    );
    let _ = writeln!(
        w,
        "rpy_rad = [0.0, 0.0, 0.0]  # roll, pitch, yaw of the tool frame in the flange frame, rad"
    );
    let _ = writeln!(w);
    let _ = writeln!(
        w,
        "# [tool.geometry]  # the print head and hose for the collision checks, flange frame; without it the head is a capsule from the flange to the tip"
    );
    let _ = writeln!(
        w,
        "# head_radius_m = 0.1  # the head: a cylinder of this radius around the flange-to-tip axis, m"
    );
    let _ = writeln!(
        w,
        "# hose_radius_m = 0.03  # the material hose: a straight capsule of this radius, m (0: no hose)"
    );
    let _ = writeln!(
        w,
        "# hose_from_m = [0.15, 0.0, 0.25]  # one end of the hose's axis, flange frame, m"
    );
    let _ = writeln!(w, "# hose_to_m = [0.15, 0.0, -0.05]  # the other end, m");
    let _ = writeln!(w);
}

/// The commented `[payload]` and `[cabinet]` tables.
fn write_payload_and_cabinet(w: &mut String) {
    let _ = writeln!(
        w,
        "# [payload]  # extruder, hose and material rigidly attached to tool_link, carried by the dynamics"
    );
    let _ = writeln!(
        w,
        "# mass_kg = 0.0  # the print head's mass with its share of hose and material, kg"
    );
    let _ = writeln!(
        w,
        "# com_m = [0.0, 0.0, 0.15]  # its centre of mass in the flange frame, m"
    );
    let _ = writeln!(
        w,
        "# inertia_kg_m2 = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]  # [ixx, iyy, izz, ixy, ixz, iyz] about the centre of mass, flange axes, kg m^2"
    );
    let _ = writeln!(w, "# description = \"3DCP print head\"  # shown in reports");
    let _ = writeln!(w);
    let _ = writeln!(
        w,
        "# [cabinet]  # read once every joint has its drive train (below)"
    );
    let _ = writeln!(
        w,
        "# standby_power_w = 0.0  # the cabinet's constant draw (controller, fans, released brakes), W"
    );
    let _ = writeln!(
        w,
        "# regeneration = \"none\"  # braking energy: \"none\" (lost), \"per_axis\" (burnt per axis), \"dc_bus\" (shared on a DC bus), \"grid\" (returned)"
    );
}

/// Commented `[links.<name>]` tables with the estimates for links whose inertia the URDF lacks.
fn write_estimated_links(w: &mut String, m: &RobotModel) {
    // Links whose inertia the URDF lacks: the estimate, as a table to confirm or replace.
    let estimated: Vec<usize> = (0..m.dof())
        .filter(|&i| {
            m.info
                .inertia_sources
                .get(i)
                .is_some_and(|s| s.is_estimate())
        })
        .collect();
    if !estimated.is_empty() {
        let _ = writeln!(w);
        let _ = writeln!(
            w,
            "# Moving links without an <inertial> in the URDF: printwatt estimates them (the values below,\n\
             # ESTIMATE, uncertain by tens of percent). Give the real mass, centre of mass (link frame, m)\n\
             # and inertia about it ([ixx, iyy, izz, ixy, ixz, iyz], link axes, kg m^2) and remove the `#`."
        );
        for i in estimated {
            let name = &m.link_names[i];
            let how = m.info.inertia_sources[i].words();
            let _ = writeln!(w, "# [links.{name}]  # {how}");
            if let Some(l) = m.links[i] {
                let _ = writeln!(w, "# mass_kg = {}", num(l.mass));
                let _ = writeln!(
                    w,
                    "# com_m = [{}, {}, {}]",
                    num(l.com.x),
                    num(l.com.y),
                    num(l.com.z)
                );
                let t = l.inertia;
                let _ = writeln!(
                    w,
                    "# inertia_kg_m2 = [{}, {}, {}, {}, {}, {}]",
                    num(t[(0, 0)]),
                    num(t[(1, 1)]),
                    num(t[(2, 2)]),
                    num(t[(0, 1)]),
                    num(t[(0, 2)]),
                    num(t[(1, 2)])
                );
            }
        }
    }
}

/// One `[[joints]]` table: joint `i` of `n`, its limits and the drive train keys.
fn write_joint(w: &mut String, i: usize, n: usize, j: &Joint) {
    let _ = writeln!(w);
    let _ = writeln!(w, "[[joints]]  # joint {} of {n}", i + 1);
    let _ = writeln!(
        w,
        "name = {}  # the URDF joint, in chain order",
        quoted(&j.name)
    );
    write_joint_limits(w, i, j);
    write_drive_train_keys(w);
}

/// A joint's acceleration, jerk, velocity and position limit keys.
fn write_joint_limits(w: &mut String, i: usize, j: &Joint) {
    let (u, us, us2, us3) = match j.kind {
        JointKind::Revolute => ("rad", "rad/s", "rad/s^2", "rad/s^3"),
        JointKind::Prismatic => ("m", "m/s", "m/s^2", "m/s^3"),
    };
    let ramp = if i < 3 { RAMP_MAIN_S } else { RAMP_WRIST_S };
    if j.velocity_limit.is_finite() {
        let a = j.velocity_limit / ramp;
        let _ = writeln!(
            w,
            "acceleration_limit_rad_s2 = {}  # ESTIMATE: the URDF's velocity limit {} {us} reached in {ramp} s ({us2})",
            num(a),
            num(j.velocity_limit)
        );
        let _ = writeln!(
            w,
            "jerk_limit_rad_s3 = {}  # ESTIMATE: the acceleration limit built up in {JERK_RAMP_S} s ({us3})",
            num(a / JERK_RAMP_S)
        );
    } else {
        let _ = writeln!(
            w,
            "# acceleration_limit_rad_s2 = 0.0  # the joint's acceleration limit, {us2} (the URDF gives no velocity limit to estimate it from)"
        );
        let _ = writeln!(
            w,
            "# jerk_limit_rad_s3 = 0.0  # the joint's jerk limit, {us3}"
        );
    }
    if j.velocity_limit.is_finite() {
        let _ = writeln!(
            w,
            "# velocity_limit_rad_s = {}  # replaces the URDF's velocity limit ({us}; this value is the URDF's)",
            exact(j.velocity_limit)
        );
    } else {
        let _ = writeln!(
            w,
            "# velocity_limit_rad_s = 0.0  # the joint's velocity limit, {us} (the URDF gives none)"
        );
    }
    if j.lower.is_finite() && j.upper.is_finite() {
        let _ = writeln!(
            w,
            "# position_min_rad = {}  # replaces the URDF's lower position limit ({u}; this value is the URDF's)",
            exact(j.lower)
        );
        let _ = writeln!(
            w,
            "# position_max_rad = {}  # replaces the URDF's upper position limit ({u})",
            exact(j.upper)
        );
    }
    let _ = writeln!(
        w,
        "# limit_margin_rad = 0.05  # margin from the position limits that placement searches keep for this joint ({u})"
    );
}

/// The commented drive train keys of a joint, to fill in.
fn write_drive_train_keys(w: &mut String) {
    let _ = writeln!(
        w,
        "# The drive train: all seven keys, for every joint, or none (then energy is mechanical power)."
    );
    let _ = writeln!(w, "# gear_ratio = 100.0  # motor turns per joint turn");
    let _ = writeln!(
        w,
        "# torque_constant_nm_per_a = 1.0  # motor torque constant K_t, N m/A (motor side)"
    );
    let _ = writeln!(
        w,
        "# winding_resistance_ohm = 1.0  # motor winding resistance R, ohm (copper loss R i^2)"
    );
    let _ = writeln!(
        w,
        "# rotor_inertia_kg_m2 = 0.001  # motor rotor inertia J_m, kg m^2 (motor side; the joint sees G^2 J_m)"
    );
    let _ = writeln!(
        w,
        "# viscous_nm_s_per_rad = 0.0  # viscous friction f_v, N m s/rad (joint side)"
    );
    let _ = writeln!(
        w,
        "# coulomb_nm = 0.0  # Coulomb friction f_c, N m (joint side)"
    );
    let _ = writeln!(
        w,
        "# gear_efficiency = 0.9  # gearbox efficiency, 0 < eta <= 1"
    );
}
