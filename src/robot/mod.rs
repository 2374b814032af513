//! Robot models: URDF (kinematics and inertials) plus an optional drive file (TOML).
//!
//! A robot is given as a directory holding `robot.urdf` and, optionally, `drive.toml`
//! (the shipped robots in `robots/`), as a `.urdf` file (rigid body only), or as a drive file
//! whose `[robot] urdf = "..."` names the URDF (relative to the drive file).

pub mod drive;
pub(crate) mod envelope;
pub mod inertia;
pub mod mesh;
pub(crate) mod model;
pub(crate) mod opw;
pub mod shipped;
pub mod template;
pub mod urdf;
pub(crate) mod validate;

pub use drive::{
    CalibratedParam, Calibration, CalibrationRound, Drive, EffectsData, EffectsTable, JointDrive,
    Regeneration,
};
pub use envelope::{reach_m, LinkRadii};
pub use model::{
    CollisionGeom, GeomShape, Inertial, Joint, JointKind, RobotInfo, RobotModel, ToolGeometry,
    VisualGeom, VisualShape, Visuals,
};
pub use opw::OpwParams;

use crate::error::{read_text, Error, Result};
use crate::math::{rotation_distance, Frame, M3, V3};
use std::path::{Path, PathBuf};

/// Keys of the drive data proper: the drive train of each joint and the cabinet's standby.
const DRIVE_DATA_KEYS: [&str; 8] = [
    "gear_ratio",
    "torque_constant_nm_per_a",
    "winding_resistance_ohm",
    "rotor_inertia_kg_m2",
    "viscous_nm_s_per_rad",
    "coulomb_nm",
    "gear_efficiency",
    "standby_power_w",
];

/// `(estimated, given)`: the drive-data values of a drive file's text ([`DRIVE_DATA_KEYS`] in
/// `[[joints]]` and `[cabinet]`), and how many of them carry `ESTIMATE` in their comment or in
/// their table's header comment.
fn drive_estimate_count(text: &str) -> (usize, usize) {
    let (mut est, mut given) = (0, 0);
    let mut in_drive = false;
    let mut table_estimate = false;
    for line in text.lines() {
        let l = line.trim();
        if l.starts_with('[') {
            let head = l.split('#').next().unwrap_or("").trim();
            in_drive = head == "[[joints]]" || head == "[cabinet]";
            table_estimate = l.contains("ESTIMATE");
            continue;
        }
        if !in_drive || l.starts_with('#') {
            continue;
        }
        let Some((key, rest)) = l.split_once('=') else {
            continue;
        };
        if DRIVE_DATA_KEYS.contains(&key.trim()) {
            given += 1;
            let comment = rest.split_once('#').map_or("", |c| c.1);
            if table_estimate || comment.contains("ESTIMATE") {
                est += 1;
            }
        }
    }
    (est, given)
}

/// The status of the robot's drive data in one line, for every report: estimated (how many
/// values of the drive file are marked ESTIMATE), given, or absent (mechanical energy only).
pub(crate) fn drive_data_status(model: &RobotModel) -> String {
    if model.drive.is_none() {
        return "none: no drive train, so the energies are the joints' mechanical work, not a supply's draw".into();
    }
    let calibrated = model.effects.calibration_summary();
    if let (Some(c), Some((0, n))) = (&calibrated, model.info.drive_estimates) {
        // A calibrated robot's file carries no ESTIMATE marks of its own.
        return format!(
            "calibrated: {c}; the {n} drive-train and cabinet values not identified from a log are those of the robot it started from (ESTIMATE where its drive file says so)"
        );
    }
    match model.info.drive_estimates {
        Some((e, n)) if e > 0 => format!(
            "ESTIMATE: {e} of the drive file's {n} drive-train and cabinet values are marked ESTIMATE (not published, not measured){}: the energies rank placements and paths, they are not calibrated predictions",
            calibrated.map_or_else(String::new, |c| format!("; calibrated since: {c}"))
        ),
        Some((_, n)) => format!(
            "given: none of the drive file's {n} drive-train and cabinet values is marked ESTIMATE"
        ),
        None => "given".into(),
    }
}

/// The file a robot was loaded from (its drive file, else its URDF), relative to the working
/// directory when it lies under it (so that a report is the same on every machine).
pub(crate) fn robot_file_display(model: &RobotModel) -> String {
    let f = model.info.drive_file.as_deref().unwrap_or(&model.source);
    // A shipped robot is named the same from every working directory (`robots/<name>/…`), so
    // that one job gives one report wherever it runs; another file as it was given.
    let canon = |p: &Path| std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf());
    let file = canon(f);
    for dir in [
        shipped::robots_dir(),
        Path::new(env!("CARGO_MANIFEST_DIR")).join("robots"),
    ] {
        if let Ok(rel) = file.strip_prefix(canon(&dir)) {
            return Path::new("robots").join(rel).display().to_string();
        }
    }
    std::env::current_dir()
        .ok()
        .and_then(|d| f.strip_prefix(d).ok().map(|p| p.display().to_string()))
        .unwrap_or_else(|| f.display().to_string())
}

/// Tolerances for the load-time check of closed-form parameters against the URDF chain.
const OPW_CHECK_POSITION_M: f64 = 1e-6;
const OPW_CHECK_ANGLE_RAD: f64 = 1e-6;

/// Load a robot from a directory, a `.urdf` file or a drive `.toml` file.
pub fn load(path: &Path) -> Result<RobotModel> {
    let (urdf_path, drive_path) = resolve(path)?;
    let drive_text = match &drive_path {
        Some(p) => Some(read_text(p)?),
        None => None,
    };
    let drive_name = drive_path
        .as_ref()
        .map(|p| p.display().to_string())
        .unwrap_or_default();
    let drive_file = match &drive_text {
        Some(t) => Some(drive::parse_drive_file(t, &drive_name)?),
        None => None,
    };
    let urdf_text = read_text(&urdf_path)?;
    let urdf_name = urdf_path.display().to_string();
    let tool_link = drive_file.as_ref().and_then(|d| d.robot.tool_link.clone());
    let mut model = urdf::parse_urdf(&urdf_text, &urdf_name, tool_link.as_deref())?;
    model.source = urdf_path.clone();
    if let Some(d) = drive_file {
        apply_drive(&mut model, d, &drive_name)?;
    }
    model.info.drive_file = drive_path.clone();
    model.info.drive_estimates = drive_text.as_deref().map(drive_estimate_count);
    inertia::complete(&mut model);
    validate::validate(
        &mut model,
        &validate::Sources {
            urdf: (&urdf_name, &urdf_text),
            drive: drive_text.as_deref().map(|t| (drive_name.as_str(), t)),
        },
    )?;
    if let Some(dir) = path.is_dir().then_some(path) {
        if model.info.name.is_empty() {
            model.info.name = dir
                .file_name()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
        }
    }
    Ok(model)
}

/// Find the URDF and the drive file for a user-given path.
fn resolve(path: &Path) -> Result<(PathBuf, Option<PathBuf>)> {
    if path.is_dir() {
        let urdf = path.join("robot.urdf");
        let drive = path.join("drive.toml");
        let urdf = if urdf.is_file() {
            urdf
        } else {
            let mut found: Vec<PathBuf> = std::fs::read_dir(path)
                .map_err(|e| Error::io(path, e))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "urdf"))
                .collect();
            found.sort();
            match found.len() {
                1 => found.remove(0),
                0 => {
                    return Err(Error::Invalid(format!(
                        "{}: no robot.urdf (or other .urdf) in this directory",
                        path.display()
                    )))
                }
                _ => {
                    return Err(Error::Invalid(format!(
                        "{}: several .urdf files and no robot.urdf: name one",
                        path.display()
                    )))
                }
            }
        };
        return Ok((urdf, drive.is_file().then_some(drive)));
    }
    if !path.exists() {
        return Err(Error::Invalid(format!(
            "{}: no such robot file or directory",
            path.display()
        )));
    }
    match path.extension().and_then(|e| e.to_str()) {
        Some("urdf") | Some("xml") => Ok((path.to_path_buf(), None)),
        Some("toml") => {
            let text = read_text(path)?;
            let d = drive::parse_drive_file(&text, &path.display().to_string())?;
            let rel = d.robot.urdf.ok_or_else(|| Error::Field {
                file: path.display().to_string(),
                field: "robot.urdf".into(),
                msg: "a drive file given on its own must name its URDF".into(),
            })?;
            let base = path.parent().unwrap_or(Path::new("."));
            Ok((base.join(rel), Some(path.to_path_buf())))
        }
        _ => Err(Error::Invalid(format!(
            "{}: expected a robot directory, a .urdf file or a drive .toml file",
            path.display()
        ))),
    }
}

fn finite_pos(file: &str, field: &str, v: f64) -> Result<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(Error::Field {
            file: file.into(),
            field: field.into(),
            msg: format!("must be finite and > 0, got {v}"),
        })
    }
}

/// A tool preset file (`tools/*.toml`): the drive file's `[tool]` (with its optional
/// `[tool.geometry]`) and `[payload]` tables, and a `[preset]` table naming it and its source.
#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct ToolPreset {
    preset: PresetInfo,
    tool: drive::ToolTable,
    payload: drive::PayloadTable,
}

#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct PresetInfo {
    name: String,
    #[serde(default)]
    provenance: String,
}

/// Replace the robot's tool (TCP, head geometry) and payload by a tool preset file, e.g. seed
/// 001's machining spindle (`tools/seed001_spindle.toml`). Errors name the file and the field;
/// the preset's name and provenance are recorded in the model's warnings (shown in reports).
pub fn apply_tool_preset(model: &mut RobotModel, path: &Path) -> Result<()> {
    let text = read_text(path)?;
    let file = path.display().to_string();
    let p: ToolPreset = toml::from_str(&text).map_err(|e| Error::Field {
        file: file.clone(),
        field: "tool preset".into(),
        msg: e.to_string(),
    })?;
    model.tool_geometry = None;
    apply_tool_and_payload(model, Some(p.tool), Some(p.payload), &file)?;
    model.warnings.push(format!(
        "tool preset `{}` from {file}: {}",
        p.preset.name, p.preset.provenance
    ));
    Ok(())
}

/// The drive file's (or a tool preset's) `[tool]` and `[payload]` tables applied to `model`.
fn apply_tool_and_payload(
    model: &mut RobotModel,
    tool: Option<drive::ToolTable>,
    payload: Option<drive::PayloadTable>,
    file: &str,
) -> Result<()> {
    if let Some(t) = tool {
        model.tool = Frame::from_xyz_rpy(t.xyz_m, t.rpy_rad);
        if let Some(g) = t.geometry {
            let ok = |v: f64| v.is_finite() && v >= 0.0;
            if !(ok(g.head_radius_m) && ok(g.hose_radius_m)) {
                return Err(Error::Field {
                    file: file.into(),
                    field: "tool.geometry".into(),
                    msg: format!(
                        "radii must be >= 0, got head {} m, hose {} m",
                        g.head_radius_m, g.hose_radius_m
                    ),
                });
            }
            model.tool_geometry = Some(crate::robot::ToolGeometry {
                head_radius_m: g.head_radius_m,
                hose_radius_m: g.hose_radius_m,
                hose_from_m: g.hose_from_m,
                hose_to_m: g.hose_to_m,
            });
        }
    }
    if let Some(p) = payload {
        if !(p.mass_kg.is_finite() && p.mass_kg >= 0.0) {
            return Err(Error::Field {
                file: file.into(),
                field: "payload.mass_kg".into(),
                msg: format!("must be >= 0, got {}", p.mass_kg),
            });
        }
        model.info.payload_description = p.description.clone();
        let [ixx, iyy, izz, ixy, ixz, iyz] = p.inertia_kg_m2;
        model.payload = Some(Inertial {
            mass: p.mass_kg,
            com: V3::from(p.com_m),
            inertia: M3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz),
        });
    }
    Ok(())
}

/// The drive file's `[links.<name>]` tables: each replaces the inertial of the moving link of
/// that URDF name (mass kg, centre of mass m and inertia about it kg·m², link frame).
fn apply_links(
    model: &mut RobotModel,
    links: &std::collections::BTreeMap<String, drive::LinkTable>,
    file: &str,
) -> Result<()> {
    let n = model.dof();
    model
        .info
        .inertia_sources
        .resize(n, inertia::InertiaSource::Urdf);
    for (name, t) in links {
        let field = |k: &str| format!("links.{name}.{k}");
        let Some(i) = model.link_names.iter().position(|l| l == name) else {
            return Err(Error::Field {
                file: file.into(),
                field: format!("links.{name}"),
                msg: format!(
                    "`{name}` is not a moving link of the URDF chain (moving links: {})",
                    model.link_names.join(", ")
                ),
            });
        };
        if !(t.mass_kg.is_finite() && t.mass_kg > 0.0) {
            return Err(Error::Field {
                file: file.into(),
                field: field("mass_kg"),
                msg: format!("must be finite and > 0, got {}", t.mass_kg),
            });
        }
        if t.com_m.iter().any(|v| !v.is_finite()) {
            return Err(Error::Field {
                file: file.into(),
                field: field("com_m"),
                msg: format!("must be finite, got {:?}", t.com_m),
            });
        }
        let [ixx, iyy, izz, ixy, ixz, iyz] = t.inertia_kg_m2;
        if t.inertia_kg_m2.iter().any(|v| !v.is_finite())
            || ixx < 0.0
            || iyy < 0.0
            || izz < 0.0
            || ixx + iyy < izz - 1e-12
            || ixx + izz < iyy - 1e-12
            || iyy + izz < ixx - 1e-12
        {
            return Err(Error::Field {
                file: file.into(),
                field: field("inertia_kg_m2"),
                msg: format!(
                    "[ixx, iyy, izz, ixy, ixz, iyz] = {:?}: expected finite moments >= 0 that \
                     meet the triangle inequality (ixx + iyy >= izz, …)",
                    t.inertia_kg_m2
                ),
            });
        }
        model.links[i] = Some(Inertial {
            mass: t.mass_kg,
            com: V3::from(t.com_m),
            inertia: M3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz),
        });
        model.info.inertia_sources[i] = inertia::InertiaSource::DriveFile;
    }
    Ok(())
}

fn apply_drive(model: &mut RobotModel, d: drive::DriveFile, file: &str) -> Result<()> {
    apply_robot_table(model, d.robot, file)?;
    apply_tool_and_payload(model, d.tool, d.payload, file)?;
    apply_links(model, &d.links, file)?;
    let drives = apply_joint_tables(model, &d.joints, file)?;
    apply_drive_trains(model, drives, d.cabinet.as_ref(), file)?;
    if d.effects.is_some() || d.calibration.is_some() {
        model.effects = drive::EffectsData {
            file: Some(file.to_string()),
            table: d.effects.unwrap_or_default(),
            calibration: d.calibration,
        };
    }
    if let Some(k) = d.kinematics {
        if model.dof() != 6 {
            return Err(Error::Field {
                file: file.into(),
                field: "kinematics".into(),
                msg: format!(
                    "OPW parameters need a 6-axis arm, the URDF has {} joints",
                    model.dof()
                ),
            });
        }
        let p = k.to_params(file)?;
        check_opw(model, &p, file)?;
        model.opw = Some(p);
    }
    Ok(())
}

/// The `[robot]` table: name, reach, pedestal, rated payload, mass and provenance.
fn apply_robot_table(model: &mut RobotModel, robot: drive::RobotTable, file: &str) -> Result<()> {
    if let Some(n) = robot.name {
        model.info.name = n;
    }
    model.info.reach_m = robot.reach_m;
    for (key, v) in [
        ("pedestal_height_m", robot.pedestal_height_m),
        ("pedestal_radius_m", robot.pedestal_radius_m),
    ] {
        if let Some(v) = v.filter(|v| !(v.is_finite() && *v >= 0.0)) {
            return Err(Error::Field {
                file: file.into(),
                field: format!("robot.{key}"),
                msg: format!("{v}: expected a length ≥ 0 m"),
            });
        }
    }
    model.info.pedestal_height_m = robot.pedestal_height_m.unwrap_or(0.0);
    model.info.pedestal_radius_m = robot.pedestal_radius_m.unwrap_or(0.0);
    if model.info.pedestal_height_m > 0.0 && model.info.pedestal_radius_m == 0.0 {
        return Err(Error::Field {
            file: file.into(),
            field: "robot.pedestal_radius_m".into(),
            msg: format!(
                "a pedestal of height {} m needs its radius (the footprint, m)",
                model.info.pedestal_height_m
            ),
        });
    }
    model.info.rated_payload_kg = robot.rated_payload_kg;
    if let Some(m) = robot.mass_kg {
        if !(m.is_finite() && m > 0.0) {
            return Err(Error::Field {
                file: file.into(),
                field: "robot.mass_kg".into(),
                msg: format!("must be finite and > 0, got {m}"),
            });
        }
    }
    model.info.mass_kg = robot.mass_kg;
    model.info.provenance = robot.provenance.unwrap_or_default();
    Ok(())
}

/// The `[[joints]]` tables (one per actuated joint, in chain order): their limits and margins
/// applied; their drive trains returned, one per joint.
fn apply_joint_tables(
    model: &mut RobotModel,
    tables: &[drive::JointTable],
    file: &str,
) -> Result<Vec<Option<JointDrive>>> {
    if !tables.is_empty() && tables.len() != model.dof() {
        return Err(Error::Field {
            file: file.into(),
            field: "joints".into(),
            msg: format!(
                "{} [[joints]] tables, but the URDF chain has {} actuated joints ({})",
                tables.len(),
                model.dof(),
                model
                    .joints
                    .iter()
                    .map(|j| j.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        });
    }
    let mut drives = Vec::new();
    for (i, (jt, j)) in tables.iter().zip(model.joints.iter_mut()).enumerate() {
        if jt.name != j.name {
            return Err(Error::Field {
                file: file.into(),
                field: format!("joints[{i}].name"),
                msg: format!(
                    "`{}` does not match URDF joint {} `{}` (tables must follow chain order)",
                    jt.name,
                    i + 1,
                    j.name
                ),
            });
        }
        let f = |k: &str| format!("joints[{i}] (`{}`).{k}", jt.name);
        if let Some(a) = jt.acceleration_limit_rad_s2 {
            j.acceleration_limit = finite_pos(file, &f("acceleration_limit_rad_s2"), a)?;
        }
        if let Some(a) = jt.jerk_limit_rad_s3 {
            j.jerk_limit = finite_pos(file, &f("jerk_limit_rad_s3"), a)?;
        }
        if let Some(a) = jt.velocity_limit_rad_s {
            j.velocity_limit = finite_pos(file, &f("velocity_limit_rad_s"), a)?;
        }
        if let Some(m) = jt.limit_margin_rad {
            if !(m.is_finite() && m >= 0.0) {
                return Err(Error::Field {
                    file: file.into(),
                    field: f("limit_margin_rad"),
                    msg: format!("must be finite and >= 0, got {m}"),
                });
            }
            model.info.limit_margins_rad.resize(i + 1, None);
            model.info.limit_margins_rad[i] = Some(m);
        }
        if let Some(a) = jt.position_min_rad {
            j.lower = a;
        }
        if let Some(a) = jt.position_max_rad {
            j.upper = a;
        }
        if j.lower > j.upper {
            return Err(Error::Field {
                file: file.into(),
                field: f("position_min_rad"),
                msg: format!("lower limit {} > upper limit {}", j.lower, j.upper),
            });
        }
        drives.push(jt.drive(file, i)?);
    }
    Ok(drives)
}

/// The model's drive: every joint's drive train (all or none) and the `[cabinet]` table.
fn apply_drive_trains(
    model: &mut RobotModel,
    drives: Vec<Option<JointDrive>>,
    cabinet: Option<&drive::CabinetTable>,
    file: &str,
) -> Result<()> {
    let any = drives.iter().any(|d| d.is_some());
    if any {
        if let Some(i) = drives.iter().position(|d| d.is_none()) {
            return Err(Error::Field {
                file: file.into(),
                field: format!("joints[{i}]"),
                msg: "drive data given for some joints but not this one: give all or none".into(),
            });
        }
        let cab = cabinet;
        let standby = cab.map_or(0.0, |c| c.standby_power_w);
        if !(standby.is_finite() && standby >= 0.0) {
            return Err(Error::Field {
                file: file.into(),
                field: "cabinet.standby_power_w".into(),
                msg: format!("must be >= 0, got {standby}"),
            });
        }
        model.drive = Some(Drive {
            joints: drives.into_iter().flatten().collect(),
            standby_power: standby,
            regeneration: cab
                .and_then(|c| c.regeneration)
                .unwrap_or(Regeneration::None),
        });
    }
    Ok(())
}

/// Flange pose by the URDF chain at `q` (rad / m).
pub fn chain_flange(model: &RobotModel, q: &[f64]) -> Frame {
    let mut f = Frame::identity();
    for (j, &qi) in model.joints.iter().zip(q) {
        f = f.compose(&j.transform(qi));
    }
    f.compose(&model.flange)
}

/// Check that the closed-form parameters reproduce the URDF chain on deterministic poses.
fn check_opw(model: &RobotModel, p: &OpwParams, file: &str) -> Result<()> {
    let mut worst = (0.0f64, 0.0f64);
    for k in 0..64 {
        let q: Vec<f64> = (0..6)
            .map(|i| {
                let j = &model.joints[i];
                let (lo, hi) = (j.lower.max(-3.0), j.upper.min(3.0));
                let u = ((k * 7 + i * 13) % 64) as f64 / 63.0; // deterministic spread
                lo + (hi - lo) * u
            })
            .collect();
        let a = chain_flange(model, &q);
        let b = p.forward(&q);
        worst.0 = worst.0.max((a.pos - b.pos).norm());
        worst.1 = worst.1.max(rotation_distance(&a.rot, &b.rot));
    }
    if worst.0 > OPW_CHECK_POSITION_M || worst.1 > OPW_CHECK_ANGLE_RAD {
        return Err(Error::Field {
            file: file.into(),
            field: "kinematics".into(),
            msg: format!(
                "the OPW parameters do not reproduce the URDF chain to `{}`: worst position error {:.3e} m, orientation error {:.3e} rad over 64 poses",
                model.flange_link, worst.0, worst.1
            ),
        });
    }
    Ok(())
}
