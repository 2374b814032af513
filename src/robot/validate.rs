//! Physical validation of a loaded robot model: every number finite and in its physical range,
//! checked once after the URDF and the drive file are read, so that no NaN, infinity or
//! impossible value reaches the kinematics, the dynamics or an output.
//!
//! Checked (errors name the file, the line where the text shows it, and the field):
//! - joints: position limits finite with lower <= upper (revolute, prismatic); velocity,
//!   acceleration and jerk limits > 0 and not implausibly small (below [`MIN_LIMIT`]: a typo
//!   that would make timing ask for terabytes);
//! - link inertials and the payload: mass finite, >= 0 and at most [`MAX_MASS_KG`]; centre of
//!   mass finite; inertia finite, symmetric and positive semi-definite; the payload's inertia
//!   also satisfies the triangle inequality (a link's violation is a warning: the published
//!   PUMA 560 data violate it); a moving link with zero mass and zero inertia is an error;
//! - drive: gear ratio in (0, [`MAX_DRIVE_VALUE`]], torque constant in [[`MIN_TORQUE_CONSTANT`], [`MAX_DRIVE_VALUE`]]; resistance, rotor inertia, viscous and
//!   Coulomb friction finite, >= 0 and below [`MAX_DRIVE_VALUE`]; gear efficiency in
//!   [[`MIN_EFFICIENCY`], 1]; standby power finite >= 0;
//! - tool transform and OPW parameters finite, lengths below [`MAX_LENGTH_M`].

use super::drive::Drive;
use super::model::{Inertial, JointKind, RobotModel};
use crate::error::{Error, Result};
use crate::math::M3;

/// Smallest velocity (rad/s or m/s), acceleration or jerk limit accepted: 1e-3. Below it a
/// limit is a unit or typing error (a URDF `velocity="1e-9"`).
pub(crate) const MIN_LIMIT: f64 = 1e-3;
/// Largest link or payload mass accepted, kg.
pub(crate) const MAX_MASS_KG: f64 = 1e5;
/// Largest length accepted for a tool offset, centre of mass or OPW parameter, m.
pub(crate) const MAX_LENGTH_M: f64 = 100.0;
/// Largest inertia entry accepted, kg·m².
pub(crate) const MAX_INERTIA: f64 = 1e6;
/// Largest drive value accepted (gear ratio, K_t, R, rotor inertia, friction), SI.
pub(crate) const MAX_DRIVE_VALUE: f64 = 1e7;

/// Smallest motor torque constant accepted, N·m/A: servo motors of robot arms have 0.05 to a
/// few N·m/A; a value far below turns any torque into an unbounded current.
pub(crate) const MIN_TORQUE_CONSTANT: f64 = 1e-3;
/// Smallest gear efficiency accepted (a gearbox below 1 % does not move an arm).
pub(crate) const MIN_EFFICIENCY: f64 = 0.01;

/// Where the model came from, for messages: file names and texts (to find lines).
pub(crate) struct Sources<'a> {
    /// URDF file name and text.
    pub urdf: (&'a str, &'a str),
    /// Drive file name and text, when there is one.
    pub drive: Option<(&'a str, &'a str)>,
}

/// 1-based line of the first occurrence of `needle` in `text` at or after the line of
/// `after` (when given), or `None`.
fn line_of(text: &str, needle: &str, after: Option<&str>) -> Option<usize> {
    let start = match after {
        Some(a) => text.find(a)?,
        None => 0,
    };
    let i = text[start..].find(needle)? + start;
    Some(text[..i].matches('\n').count() + 1)
}

/// Line of `key` inside the `idx`-th `[[joints]]` table of a drive file.
fn joint_key_line(text: &str, idx: usize, key: &str) -> Option<usize> {
    let mut pos = 0;
    for _ in 0..=idx {
        pos += text[pos..].find("[[joints]]")? + 1;
    }
    let rest = &text[pos..];
    let end = rest.find("\n[").unwrap_or(rest.len());
    let k = rest[..end].find(key)?;
    Some(text[..pos + k].matches('\n').count() + 1)
}

fn err(file: &str, line: Option<usize>, field: &str, msg: String) -> Error {
    match line {
        Some(line) => Error::Parse {
            file: file.into(),
            line,
            column: 1,
            msg: format!("{field}: {msg}"),
        },
        None => Error::Field {
            file: file.into(),
            field: field.into(),
            msg,
        },
    }
}

/// Check an inertia matrix (kg·m²): finite, symmetric, positive semi-definite; returns whether
/// it satisfies the triangle inequality of its principal moments.
fn check_inertia(i: &M3) -> std::result::Result<bool, String> {
    if i.iter().any(|v| !v.is_finite()) {
        return Err(format!(
            "inertia has a non-finite entry: {:?}",
            i.as_slice()
        ));
    }
    if i.iter().any(|v| v.abs() > MAX_INERTIA) {
        return Err(format!(
            "inertia entry above {MAX_INERTIA} kg·m² (a unit error?): {:?}",
            i.as_slice()
        ));
    }
    let scale = i.iter().fold(0.0_f64, |m, v| m.max(v.abs())).max(1e-300);
    if (i - i.transpose()).abs().max() > 1e-9 * scale {
        return Err("inertia is not symmetric".into());
    }
    let e = nalgebra::SymmetricEigen::new(*i).eigenvalues;
    let tol = 1e-9 * scale;
    if e.iter().any(|&l| l < -tol) {
        return Err(format!(
            "inertia is not positive semi-definite (principal moments {:.6e}, {:.6e}, {:.6e} kg·m²)",
            e[0], e[1], e[2]
        ));
    }
    let (a, b, c) = (e[0], e[1], e[2]);
    Ok(a + b >= c - tol && a + c >= b - tol && b + c >= a - tol)
}

fn check_inertial(
    what: &str,
    inertial: &Inertial,
) -> std::result::Result<Option<String>, (String, String)> {
    let m = inertial.mass;
    if !(m.is_finite() && m >= 0.0) {
        return Err((
            "mass".into(),
            format!("{what}: mass must be finite and >= 0, got {m} kg"),
        ));
    }
    if m > MAX_MASS_KG {
        return Err((
            "mass".into(),
            format!("{what}: mass {m} kg is above {MAX_MASS_KG} kg (a unit error?)"),
        ));
    }
    if inertial
        .com
        .iter()
        .any(|v| !v.is_finite() || v.abs() > MAX_LENGTH_M)
    {
        return Err((
            "com".into(),
            format!(
                "{what}: centre of mass must be finite and within {MAX_LENGTH_M} m, got {:?}",
                inertial.com.as_slice()
            ),
        ));
    }
    match check_inertia(&inertial.inertia) {
        Err(e) => Err(("inertia".into(), format!("{what}: {e}"))),
        Ok(true) => Ok(None),
        Ok(false) => Ok(Some(format!(
            "{what}: inertia violates the triangle inequality (kept as given)"
        ))),
    }
}

/// Validate a loaded model (see the module docs). Warnings are appended to `model.warnings`.
pub fn validate(model: &mut RobotModel, src: &Sources) -> Result<()> {
    let (ufile, utext) = src.urdf;
    check_joint_limits(model, src)?;
    let warnings: Vec<String> = Vec::new();
    check_links(model, ufile, utext)?;
    // Payload, tool, OPW, drive: from the drive file.
    let (dfile, dtext) = src.drive.unwrap_or((ufile, ""));
    check_payload_and_tool(model, dfile, dtext)?;
    check_opw(model, dfile, dtext)?;
    check_drive(model, dfile, dtext)?;
    if model.gravity.iter().any(|v| !v.is_finite()) {
        return Err(err(ufile, None, "gravity", "must be finite".into()));
    }
    model.warnings.extend(warnings);
    Ok(())
}

/// Each joint's position, velocity, acceleration and jerk limits: ordered, positive and
/// plausible.
fn check_joint_limits(model: &RobotModel, src: &Sources) -> Result<()> {
    let (ufile, utext) = src.urdf;
    for j in &model.joints {
        let jline = line_of(utext, &format!("name=\"{}\"", j.name), Some("<joint"));
        let f = |k: &str| format!("joint `{}` {k}", j.name);
        // Continuous joints have infinite limits; NaN or lower > upper never.
        {
            let bad = j.lower.is_nan() || j.upper.is_nan() || j.lower > j.upper;
            if bad {
                return Err(err(
                    ufile,
                    jline,
                    &f("limit"),
                    format!(
                        "position limits must be finite with lower <= upper, got [{}, {}]",
                        j.lower, j.upper
                    ),
                ));
            }
        }
        for (k, v, unit) in [
            ("velocity", j.velocity_limit, "/s"),
            ("acceleration", j.acceleration_limit, "/s²"),
            ("jerk", j.jerk_limit, "/s³"),
        ] {
            let u = if j.kind == JointKind::Prismatic {
                "m"
            } else {
                "rad"
            };
            if v.is_nan() || v <= 0.0 {
                return Err(err(
                    ufile,
                    jline,
                    &f(&format!("{k} limit")),
                    format!("must be > 0, got {v} {u}{unit}"),
                ));
            }
            if v < MIN_LIMIT {
                let (file, line) = match src.drive {
                    Some((df, dt)) if dt.contains(&format!("{k}_limit")) => {
                        let idx = model
                            .joints
                            .iter()
                            .position(|x| x.name == j.name)
                            .unwrap_or(0);
                        (df, joint_key_line(dt, idx, &format!("{k}_limit")))
                    }
                    _ => (ufile, jline),
                };
                return Err(err(
                    file,
                    line,
                    &f(&format!("{k} limit")),
                    format!(
                        "{v} {u}{unit} is implausibly small (below {MIN_LIMIT}): check the unit; timing would take years"
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Each moving link's inertial: finite, plausible, and not all zero.
fn check_links(model: &RobotModel, ufile: &str, utext: &str) -> Result<()> {
    let actuated_children: Vec<usize> = (0..model.links.len()).collect();
    for k in actuated_children {
        let Some(inertial) = &model.links[k] else {
            continue;
        };
        let name = model.link_names.get(k).cloned().unwrap_or_default();
        let line = line_of(utext, &format!("name=\"{name}\""), Some("<link"));
        let what = format!("link `{name}`");
        // A link's triangle-inequality violation is already a warning of the URDF reader
        // (the published PUMA 560 data have one).
        if let Err((field, msg)) = check_inertial(&what, inertial) {
            return Err(err(ufile, line, &format!("{what} {field}"), msg));
        }
        // A moving link (every entry of `model.links`, the first included) with neither mass
        // nor inertia is a link whose data are missing.
        if inertial.mass == 0.0 && inertial.inertia.iter().all(|v| *v == 0.0) {
            return Err(err(
                ufile,
                line,
                &format!("{what} mass"),
                "a moving link with zero mass and zero inertia: give its mass and inertia, or \
                 remove its <inertial> (kinematics only)"
                    .into(),
            ));
        }
    }
    Ok(())
}

/// The payload's inertial and the tool transform of the drive file.
fn check_payload_and_tool(model: &RobotModel, dfile: &str, dtext: &str) -> Result<()> {
    let dline = |needle: &str| line_of(dtext, needle, None);
    if let Some(p) = &model.payload {
        match check_inertial("payload", p) {
            Err((field, msg)) => {
                let key = match field.as_str() {
                    "mass" => "mass_kg",
                    "com" => "com_m",
                    _ => "inertia_kg_m2",
                };
                return Err(err(dfile, dline(key), &format!("payload.{key}"), msg));
            }
            Ok(Some(_)) => {
                return Err(err(
                    dfile,
                    dline("inertia_kg_m2"),
                    "payload.inertia_kg_m2",
                    "the payload's inertia violates the triangle inequality (Ixx + Iyy >= Izz and \
                     permutations): no rigid body has it"
                        .into(),
                ))
            }
            Ok(None) => {}
        }
    }
    let t = &model.tool;
    if t.pos.iter().chain(t.rot.iter()).any(|v| !v.is_finite()) || t.pos.norm() > MAX_LENGTH_M {
        return Err(err(
            dfile,
            dline("xyz_m"),
            "tool.xyz_m / tool.rpy_rad",
            format!(
                "the tool transform must be finite and within {MAX_LENGTH_M} m, got xyz {:?}",
                t.pos.as_slice()
            ),
        ));
    }
    Ok(())
}

/// The OPW kinematic parameters of the drive file: finite lengths and offsets.
fn check_opw(model: &RobotModel, dfile: &str, dtext: &str) -> Result<()> {
    let dline = |needle: &str| line_of(dtext, needle, None);
    if let Some(o) = &model.opw {
        for (k, v) in [
            ("a1_m", o.a1),
            ("a2_m", o.a2),
            ("b_m", o.b),
            ("c1_m", o.c1),
            ("c2_m", o.c2),
            ("c3_m", o.c3),
            ("c4_m", o.c4),
        ] {
            if !(v.is_finite() && v.abs() <= MAX_LENGTH_M) {
                return Err(err(
                    dfile,
                    dline(k),
                    &format!("kinematics.{k}"),
                    format!("must be finite and within {MAX_LENGTH_M} m, got {v}"),
                ));
            }
        }
        if let Some(i) = o.offsets.iter().position(|v| !v.is_finite()) {
            return Err(err(
                dfile,
                dline("offsets_rad"),
                &format!("kinematics.offsets_rad[{i}]"),
                format!("must be finite, got {}", o.offsets[i]),
            ));
        }
    }
    Ok(())
}

/// The drive data: one entry per joint, each in range, and the cabinet's standby power.
fn check_drive(model: &RobotModel, dfile: &str, dtext: &str) -> Result<()> {
    let dline = |needle: &str| line_of(dtext, needle, None);
    if let Some(d) = &model.drive {
        if d.joints.len() != model.joints.len() {
            return Err(err(
                dfile,
                None,
                "joints",
                format!(
                    "{} drive entries for {} joints",
                    d.joints.len(),
                    model.joints.len()
                ),
            ));
        }
        check_drive_joints(model, d, dfile, dtext)?;
        if !(d.standby_power.is_finite() && d.standby_power >= 0.0) {
            return Err(err(
                dfile,
                dline("standby_power_w"),
                "cabinet.standby_power_w",
                format!("must be finite and >= 0, got {}", d.standby_power),
            ));
        }
    }
    Ok(())
}

/// Each joint's drive train values within their ranges.
fn check_drive_joints(model: &RobotModel, d: &Drive, dfile: &str, dtext: &str) -> Result<()> {
    for (i, jd) in d.joints.iter().enumerate() {
        let name = &model.joints[i].name;
        for (key, v, lo, lo_incl, hi) in [
            ("gear_ratio", jd.gear_ratio, 0.0, false, MAX_DRIVE_VALUE),
            (
                "torque_constant_nm_per_a",
                jd.torque_constant,
                MIN_TORQUE_CONSTANT,
                true,
                MAX_DRIVE_VALUE,
            ),
            (
                "winding_resistance_ohm",
                jd.winding_resistance,
                0.0,
                true,
                MAX_DRIVE_VALUE,
            ),
            (
                "rotor_inertia_kg_m2",
                jd.rotor_inertia,
                0.0,
                true,
                MAX_INERTIA,
            ),
            (
                "viscous_nm_s_per_rad",
                jd.viscous,
                0.0,
                true,
                MAX_DRIVE_VALUE,
            ),
            ("coulomb_nm", jd.coulomb, 0.0, true, MAX_DRIVE_VALUE),
            (
                "gear_efficiency",
                jd.gear_efficiency,
                MIN_EFFICIENCY,
                true,
                1.0,
            ),
        ] {
            let ok = v.is_finite() && (v > lo || (lo_incl && v == lo)) && v <= hi;
            if !ok {
                let range = format!("{}{lo}, {hi}]", if lo_incl { "[" } else { "(" });
                return Err(err(
                    dfile,
                    joint_key_line(dtext, i, key),
                    &format!("joints[{i}] (`{name}`).{key}"),
                    format!("must be finite and in {range}, got {v}"),
                ));
            }
        }
    }
    Ok(())
}
