//! The drive file (TOML): what a URDF does not say. Joint acceleration and jerk limits, gear
//! ratios, motor constants, friction, gearbox efficiency, the cabinet's standby power and
//! regeneration policy, the default payload and the tool (nozzle) transform, plus the
//! closed-form kinematic parameters. Every key carries its unit in its name; values are SI.
//! The schema is documented in `docs/drive-file.md`.

use crate::error::{Error, Result};
use crate::robot::opw::OpwParams;
use serde::{Deserialize, Serialize};

/// What happens to power that a joint returns (negative electrical power).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Regeneration {
    /// Negative power is lost: each axis draws `max(P, 0)`.
    None,
    /// Burnt per axis in its brake resistor: each axis draws `max(P, 0)` (same energy as `none`,
    /// named separately because the heat goes to a resistor).
    PerAxis,
    /// Axes share a DC bus: the bus draws `max(Σ P, 0)`; the remainder is burnt.
    DcBus,
    /// Regenerative supply: the cabinet draws the net `Σ P`, negative returned to the grid.
    Grid,
}

impl Regeneration {
    /// Stable name as used in drive files and on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            Regeneration::None => "none",
            Regeneration::PerAxis => "per_axis",
            Regeneration::DcBus => "dc_bus",
            Regeneration::Grid => "grid",
        }
    }

    /// Parse a command-line or file name.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "none" => Some(Regeneration::None),
            "per_axis" => Some(Regeneration::PerAxis),
            "dc_bus" => Some(Regeneration::DcBus),
            "grid" => Some(Regeneration::Grid),
            _ => None,
        }
    }
}

impl std::str::FromStr for Regeneration {
    type Err = crate::error::Error;
    fn from_str(s: &str) -> crate::error::Result<Self> {
        Regeneration::parse(s).ok_or_else(|| {
            crate::error::Error::Invalid(format!(
                "regeneration policy `{s}`: expected none, per_axis, dc_bus or grid"
            ))
        })
    }
}

impl std::fmt::Display for Regeneration {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Drive train of one joint. Motor-side quantities are marked; the rest are joint side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointDrive {
    /// Motor turns per joint turn (> 0).
    pub gear_ratio: f64,
    /// Motor torque constant K_t, N·m/A (motor side). The SI back-EMF constant K_v equals it.
    pub torque_constant: f64,
    /// Winding resistance R, Ω.
    pub winding_resistance: f64,
    /// Rotor inertia J_m, kg·m² (motor side). Reflected to the joint as G²·J_m.
    pub rotor_inertia: f64,
    /// Viscous friction f_v, N·m·s/rad (joint side).
    pub viscous: f64,
    /// Coulomb friction f_c, N·m (joint side).
    pub coulomb: f64,
    /// Gearbox efficiency η in (0, 1].
    pub gear_efficiency: f64,
}

impl JointDrive {
    /// The value of the drive file's per-joint key `key` (SI, as in `[[joints]]`), or `None`
    /// for a key the drive train does not have.
    pub fn key(&self, key: &str) -> Option<f64> {
        Some(match key {
            "gear_ratio" => self.gear_ratio,
            "torque_constant_nm_per_a" => self.torque_constant,
            "winding_resistance_ohm" => self.winding_resistance,
            "rotor_inertia_kg_m2" => self.rotor_inertia,
            "viscous_nm_s_per_rad" => self.viscous,
            "coulomb_nm" => self.coulomb,
            "gear_efficiency" => self.gear_efficiency,
            _ => return None,
        })
    }

    /// Reflected rotor inertia G²·J_m, kg·m² (joint side).
    pub fn armature(&self) -> f64 {
        self.gear_ratio * self.gear_ratio * self.rotor_inertia
    }
}

/// The drive train of the whole robot and its cabinet.
#[derive(Clone, Debug, PartialEq)]
pub struct Drive {
    /// One per actuated joint, in chain order.
    pub joints: Vec<JointDrive>,
    /// Cabinet's constant draw (controller, fans, released brakes), W.
    pub standby_power: f64,
    /// Policy for negative power.
    pub regeneration: Regeneration,
}

// ---- the file as written -----------------------------------------------------------------------

/// The drive file as written: one schema, read and written with serde (`identify` writes a
/// calibrated robot with it, [`DriveFile::to_toml`]).
#[derive(Deserialize, Serialize, Debug, Default, Clone)]
#[serde(deny_unknown_fields)]
pub(crate) struct DriveFile {
    #[serde(default)]
    pub robot: RobotTable,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kinematics: Option<KinematicsTable>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tool: Option<ToolTable>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub payload: Option<PayloadTable>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cabinet: Option<CabinetTable>,
    /// Optional `[effects]` table (switches and identified parameters of effects the rest of
    /// the file has no keys for), validated by the effects themselves when a model is built (`crate::effects::EffectSet::of_robot`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub effects: Option<EffectsTable>,
    /// Optional `[calibration]` table: where the identified values of a calibrated robot came
    /// from (written by `identify`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibration: Option<Calibration>,
    /// Optional `[uncertainty]` table: ranges of the estimated numbers, read by the
    /// placement's uncertainty study (`crate::search::uncertainty::Ranges`), kept as written.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uncertainty: Option<toml::Value>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joints: Vec<JointTable>,
    /// Optional `[links.<name>]` tables: inertias of moving links, replacing the URDF's (or
    /// its missing ones), keyed by URDF link name.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub links: std::collections::BTreeMap<String, LinkTable>,
}

/// A drive file's `[links.<name>]` table: the link's rigid body in its URDF link frame.
#[derive(Deserialize, Serialize, Debug, Clone, PartialEq)]
#[serde(deny_unknown_fields)]
pub(crate) struct LinkTable {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Centre of mass in the link frame, m.
    pub com_m: [f64; 3],
    /// Inertia about the centre of mass, link frame axes, kg·m²: `[ixx, iyy, izz, ixy, ixz,
    /// iyz]`.
    pub inertia_kg_m2: [f64; 6],
}

/// The drive file's `[effects]` table as written (strict: unknown keys are errors). The robot
/// description carries it as data ([`crate::robot::RobotModel::effects`]); the effects
/// themselves read and validate their keys when a model is built (the robot does not know the
/// effects). Keys: docs/effects.md.
#[derive(Deserialize, Serialize, Debug, Default, Clone, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct EffectsTable {
    /// Catalogue names switched on (replaces the default switches).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub enabled: Option<Vec<String>>,
    /// `stribeck`: `f_s` per joint, N·m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stribeck_nm: Option<Vec<f64>>,
    /// `stribeck`: `v_s`, rad/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stribeck_velocity_rad_s: Option<f64>,
    /// `payload`: mass error `Δm`, kg.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub payload_mass_error_kg: Option<f64>,
    /// `balancer`: preload `F0`, N.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub balancer_preload_n: Option<f64>,
    /// `balancer`: stiffness `k`, N/m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub balancer_stiffness_n_per_m: Option<f64>,
    /// `balancer`: joint it acts on (1-based).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub balancer_joint: Option<usize>,
    /// `balancer`: lever `a` on the moving link, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub balancer_lever_m: Option<f64>,
    /// `balancer`: distance `b` of the fixed end, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub balancer_base_m: Option<f64>,
    /// `balancer`: upright angle `q_up`, rad.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub balancer_upright_rad: Option<f64>,
    /// `regeneration`: recovered fraction `ρ`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub regeneration_recovered_fraction: Option<f64>,
    /// Effect name → parameter values in the order of the effect's parameters (SI).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub values: Option<std::collections::BTreeMap<String, Vec<f64>>>,
}

/// What a robot's drive file says about the effects, kept as data: the file, its `[effects]`
/// table and its `[calibration]` table. The effects read and validate it
/// (`crate::effects::EffectSet::of_robot`); the robot description does not know them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EffectsData {
    /// The drive file the tables came from (`None`: no drive file, or no table in it).
    pub file: Option<String>,
    /// The `[effects]` table (default when there is none).
    pub table: EffectsTable,
    /// The `[calibration]` table when the robot is a calibrated one.
    pub calibration: Option<Calibration>,
}

impl EffectsData {
    /// One line naming the calibration (file, rounds, dates, logs), or `None` for a nominal
    /// robot.
    pub fn calibration_summary(&self) -> Option<String> {
        let c = self.calibration.as_ref()?;
        let rounds: Vec<String> = c
            .rounds
            .iter()
            .map(|r| {
                format!(
                    "round {} on {} from {} ({})",
                    r.round,
                    r.date,
                    r.log,
                    r.effects.join(", ")
                )
            })
            .collect();
        Some(format!(
            "calibrated robot {} (from {}; {})",
            self.file.as_deref().unwrap_or("?"),
            c.base_robot,
            rounds.join("; ")
        ))
    }
}

/// The `[calibration]` table of a calibrated robot (written by `printwatt identify`, read
/// back by every command, which then names the calibration it used).
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Calibration {
    /// The robot the first round started from, as given to `identify --robot`.
    pub base_robot: String,
    /// Rounds of identification, oldest first.
    #[serde(default)]
    pub rounds: Vec<CalibrationRound>,
    /// Every identified parameter with its latest value; parameters of earlier rounds that
    /// were not re-fitted are carried over.
    #[serde(default)]
    pub params: Vec<CalibratedParam>,
}

/// One round of `identify`.
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CalibrationRound {
    /// 1-based round number.
    pub round: usize,
    /// UTC date of the run, `YYYY-MM-DD`.
    pub date: String,
    /// The log fitted.
    pub log: String,
    /// Signal of the log (`tau`, `i`, `p`, `p_total`).
    pub signal: String,
    /// Effects fitted in this round.
    pub effects: Vec<String>,
    /// What was validated on.
    pub validation: String,
    /// Validation RMSE before the round (signal unit).
    pub validation_rmse_before: f64,
    /// Validation RMSE after the round (signal unit).
    pub validation_rmse_after: f64,
    /// `effect.param` of the parameters this round fitted with a standard error, in the
    /// order of `correlation`'s rows.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub correlated: Vec<String>,
    /// Their correlation matrix (one row per parameter; with the standard errors of
    /// `[[calibration.params]]` it is the fit's covariance).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub correlation: Vec<Vec<f64>>,
}

/// One identified parameter.
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CalibratedParam {
    /// Catalogue name of the effect.
    pub effect: String,
    /// Parameter name, e.g. `f_c+[2]`.
    pub name: String,
    /// SI unit.
    pub unit: String,
    /// Value in the calibrated robot.
    pub value: f64,
    /// Standard error (same unit); absent when the parameter was held at its prior.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub std_error: Option<f64>,
    /// Value before the round that fitted it.
    pub prior: f64,
    /// Round that fitted it (or held it).
    pub round: usize,
    /// `fitted`, or `held at prior: ...` with the reason.
    pub status: String,
}

impl DriveFile {
    /// The TOML text of this file (SI, unit in every key).
    pub(crate) fn to_toml(&self) -> Result<String> {
        toml::to_string(self).map_err(|e| Error::Invalid(format!("writing a drive file: {e}")))
    }
}

#[derive(Deserialize, Serialize, Debug, Default, Clone)]
#[serde(deny_unknown_fields)]
pub(crate) struct RobotTable {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reach_m: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rated_payload_kg: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mass_kg: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub provenance: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tool_link: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub urdf: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pedestal_height_m: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pedestal_radius_m: Option<f64>,
}

#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub(crate) struct KinematicsTable {
    #[serde(rename = "type")]
    pub kind: String,
    pub a1_m: f64,
    pub a2_m: f64,
    pub b_m: f64,
    pub c1_m: f64,
    pub c2_m: f64,
    pub c3_m: f64,
    pub c4_m: f64,
    pub offsets_rad: [f64; 6],
    pub signs: [f64; 6],
}

#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub(crate) struct ToolTable {
    pub xyz_m: [f64; 3],
    #[serde(default)]
    pub rpy_rad: [f64; 3],
    /// `[tool.geometry]`: print head and hose for collision checks (see
    /// [`crate::robot::ToolGeometry`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub geometry: Option<ToolGeometryTable>,
}

/// `[tool.geometry]` (flange frame, m): `head_radius_m` (cylinder around flange → tip),
/// optional `hose_radius_m`, `hose_from_m`, `hose_to_m` (a straight capsule).
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub(crate) struct ToolGeometryTable {
    pub head_radius_m: f64,
    #[serde(default)]
    pub hose_radius_m: f64,
    #[serde(default)]
    pub hose_from_m: [f64; 3],
    #[serde(default)]
    pub hose_to_m: [f64; 3],
}

#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub(crate) struct PayloadTable {
    pub mass_kg: f64,
    #[serde(default)]
    pub com_m: [f64; 3],
    #[serde(default)]
    pub inertia_kg_m2: [f64; 6],
    #[serde(default)]
    pub description: Option<String>,
}

#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub(crate) struct CabinetTable {
    #[serde(default)]
    pub standby_power_w: f64,
    pub regeneration: Option<Regeneration>,
}

#[derive(Deserialize, Serialize, Debug, Clone, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct JointTable {
    pub name: String,
    pub acceleration_limit_rad_s2: Option<f64>,
    pub jerk_limit_rad_s3: Option<f64>,
    pub velocity_limit_rad_s: Option<f64>,
    pub position_min_rad: Option<f64>,
    pub position_max_rad: Option<f64>,
    /// Position margin from the limits kept by placement searches, rad.
    pub limit_margin_rad: Option<f64>,
    pub gear_ratio: Option<f64>,
    pub torque_constant_nm_per_a: Option<f64>,
    pub winding_resistance_ohm: Option<f64>,
    pub rotor_inertia_kg_m2: Option<f64>,
    pub viscous_nm_s_per_rad: Option<f64>,
    pub coulomb_nm: Option<f64>,
    pub gear_efficiency: Option<f64>,
}

/// Parse the TOML text; syntax and schema errors name the file, line and column.
pub(crate) fn parse_drive_file(text: &str, file: &str) -> Result<DriveFile> {
    let df = toml::from_str::<DriveFile>(text).map_err(|e| {
        let (line, column) = e.span().map(|s| line_col(text, s.start)).unwrap_or((0, 0));
        Error::Parse {
            file: file.to_string(),
            line,
            column,
            msg: e.message().to_string(),
        }
    })?;
    // TOML writes `inf` and `nan` (and reads 1e309 as infinity): no number of a robot is
    // either, so the first one is refused naming its key.
    if let Ok(v) = text.parse::<toml::Table>() {
        if let Some(key) = first_non_finite(&toml::Value::Table(v), "") {
            return Err(Error::Field {
                file: file.to_string(),
                field: key,
                msg: "expected a finite number, found an infinity or NaN".into(),
            });
        }
    }
    Ok(df)
}

/// The key path (`tool.geometry.hose_to_m[1]`) of the first non-finite float in `v`.
fn first_non_finite(v: &toml::Value, path: &str) -> Option<String> {
    match v {
        toml::Value::Float(x) if !x.is_finite() => Some(path.to_string()),
        toml::Value::Table(t) => t.iter().find_map(|(k, v)| {
            let p = if path.is_empty() {
                k.clone()
            } else {
                format!("{path}.{k}")
            };
            first_non_finite(v, &p)
        }),
        toml::Value::Array(a) => a
            .iter()
            .enumerate()
            .find_map(|(i, v)| first_non_finite(v, &format!("{path}[{i}]"))),
        _ => None,
    }
}

/// 1-based line and column of a byte offset.
pub(crate) fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

impl KinematicsTable {
    pub(crate) fn to_params(&self, file: &str) -> Result<OpwParams> {
        if self.kind != "opw" {
            return Err(Error::Field {
                file: file.into(),
                field: "kinematics.type".into(),
                msg: format!("unknown kinematics type `{}`, expected `opw`", self.kind),
            });
        }
        for (i, s) in self.signs.iter().enumerate() {
            if *s != 1.0 && *s != -1.0 {
                return Err(Error::Field {
                    file: file.into(),
                    field: format!("kinematics.signs[{i}]"),
                    msg: format!("must be 1 or -1, got {s}"),
                });
            }
        }
        Ok(OpwParams {
            a1: self.a1_m,
            a2: self.a2_m,
            b: self.b_m,
            c1: self.c1_m,
            c2: self.c2_m,
            c3: self.c3_m,
            c4: self.c4_m,
            offsets: self.offsets_rad,
            signs: self.signs,
        })
    }
}

impl JointTable {
    /// The drive data of this joint, or `None` if the table gives no drive numbers at all.
    /// A table that gives some but not all of them is an error naming the missing field.
    pub(crate) fn drive(&self, file: &str, idx: usize) -> Result<Option<JointDrive>> {
        let fields: [(&str, Option<f64>); 7] = [
            ("gear_ratio", self.gear_ratio),
            ("torque_constant_nm_per_a", self.torque_constant_nm_per_a),
            ("winding_resistance_ohm", self.winding_resistance_ohm),
            ("rotor_inertia_kg_m2", self.rotor_inertia_kg_m2),
            ("viscous_nm_s_per_rad", self.viscous_nm_s_per_rad),
            ("coulomb_nm", self.coulomb_nm),
            ("gear_efficiency", self.gear_efficiency),
        ];
        if fields.iter().all(|(_, v)| v.is_none()) {
            return Ok(None);
        }
        let field = |name: &str, msg: String| Error::Field {
            file: file.into(),
            field: format!("joints[{idx}] (`{}`).{name}", self.name),
            msg,
        };
        for (name, v) in fields.iter() {
            match v {
                None => {
                    return Err(field(
                        name,
                        "missing: a joint with drive data needs all seven drive fields".into(),
                    ))
                }
                Some(x) if !x.is_finite() || *x < 0.0 => {
                    return Err(field(name, format!("must be finite and >= 0, got {x}")))
                }
                _ => {}
            }
        }
        let jd = JointDrive {
            gear_ratio: self.gear_ratio.unwrap_or_default(),
            torque_constant: self.torque_constant_nm_per_a.unwrap_or_default(),
            winding_resistance: self.winding_resistance_ohm.unwrap_or_default(),
            rotor_inertia: self.rotor_inertia_kg_m2.unwrap_or_default(),
            viscous: self.viscous_nm_s_per_rad.unwrap_or_default(),
            coulomb: self.coulomb_nm.unwrap_or_default(),
            gear_efficiency: self.gear_efficiency.unwrap_or_default(),
        };
        if jd.gear_ratio <= 0.0 {
            return Err(field(
                "gear_ratio",
                format!("must be > 0, got {}", jd.gear_ratio),
            ));
        }
        if jd.torque_constant <= 0.0 {
            return Err(field(
                "torque_constant_nm_per_a",
                format!("must be > 0, got {}", jd.torque_constant),
            ));
        }
        if jd.gear_efficiency <= 0.0 || jd.gear_efficiency > 1.0 {
            return Err(field(
                "gear_efficiency",
                format!("must be in (0, 1], got {}", jd.gear_efficiency),
            ));
        }
        Ok(Some(jd))
    }
}

// ---- keys effects write ------------------------------------------------------------------------

/// Where a calibrated drive file keeps an effect's identified values (written by `identify`
/// in a drive file with per-joint drive tables, [`crate::effects::Effect::write_drive_keys`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DriveKept {
    /// In `[effects.values]` (the effect has no drive key).
    Values,
    /// In its drive keys, which hold them all (`[effects.values]` does not repeat them).
    Keys,
    /// In its drive keys as far as they go, and in full in `[effects.values]`, which wins
    /// when the robot is loaded.
    KeysAndValues,
    /// As the robot's own body (the payload: `[payload]`), not as an effect: neither
    /// `[effects.values]` nor `[effects] enabled` names it, and its `[effects]` keys
    /// ([`crate::effects::Effect::effects_keys`]) are cleared. With or without per-joint
    /// drive tables.
    Body,
}

/// The drive keys of a calibrated drive file being written, as the effects set them: the
/// per-joint keys of `[[joints]]` and the keys of `[cabinet]` (docs/drive-file.md). Without
/// per-joint drive tables nothing is written: every effect's values then go to
/// `[effects.values]` (or, for [`DriveKept::Body`], into the robot's body).
#[derive(Debug)]
pub struct DriveKeysMut<'a> {
    file: &'a mut DriveFile,
    gear: &'a [f64],
    drive_tables: bool,
}

impl<'a> DriveKeysMut<'a> {
    /// The keys of `file`, whose joints have gear ratios `gear`; `drive_tables`: whether the
    /// file has per-joint drive tables (the keys are written only then).
    pub(crate) fn new(file: &'a mut DriveFile, gear: &'a [f64], drive_tables: bool) -> Self {
        DriveKeysMut {
            file,
            gear,
            drive_tables,
        }
    }

    /// Where the file keeps the values of an effect that says `kept`: without per-joint
    /// drive tables in `[effects.values]`, unless it is the robot's body.
    pub(crate) fn kept(&self, kept: DriveKept) -> DriveKept {
        match kept {
            DriveKept::Body => DriveKept::Body,
            k if self.drive_tables => k,
            _ => DriveKept::Values,
        }
    }

    /// Gear ratio of each joint (motor turns per joint turn).
    pub(crate) fn gear_ratios(&self) -> &[f64] {
        self.gear
    }

    /// Set the per-joint key `key` of the first `values.len()` `[[joints]]` tables. Error: a
    /// key the drive file's joint tables do not have.
    pub(crate) fn set_joints(&mut self, key: &str, values: &[f64]) -> Result<()> {
        if !self.drive_tables {
            return Ok(());
        }
        for (jt, v) in self.file.joints.iter_mut().zip(values) {
            *jt.key_mut(key)? = Some(*v);
        }
        if self.file.joints.is_empty() {
            JointTable::check_key(key)?;
        }
        Ok(())
    }

    /// Set `[cabinet] key` when the file has a `[cabinet]` table. Error: a key the table does
    /// not have.
    pub(crate) fn set_cabinet(&mut self, key: &str, value: f64) -> Result<()> {
        if !self.drive_tables {
            return Ok(());
        }
        match key {
            "standby_power_w" => {
                if let Some(c) = self.file.cabinet.as_mut() {
                    c.standby_power_w = value;
                }
                Ok(())
            }
            _ => Err(Error::Invalid(format!(
                "drive file: no key `cabinet.{key}`"
            ))),
        }
    }
}

impl JointTable {
    /// The numeric per-joint drive key `key`.
    fn key_mut(&mut self, key: &str) -> Result<&mut Option<f64>> {
        Ok(match key {
            "gear_ratio" => &mut self.gear_ratio,
            "torque_constant_nm_per_a" => &mut self.torque_constant_nm_per_a,
            "winding_resistance_ohm" => &mut self.winding_resistance_ohm,
            "rotor_inertia_kg_m2" => &mut self.rotor_inertia_kg_m2,
            "viscous_nm_s_per_rad" => &mut self.viscous_nm_s_per_rad,
            "coulomb_nm" => &mut self.coulomb_nm,
            "gear_efficiency" => &mut self.gear_efficiency,
            _ => return Err(Error::Invalid(format!("drive file: no key `joints.{key}`"))),
        })
    }

    /// Whether `key` is a numeric per-joint drive key (error naming it if not).
    fn check_key(key: &str) -> Result<()> {
        JointTable::default().key_mut(key).map(|_| ())
    }
}

impl EffectsTable {
    /// Clear the `[effects]` key `key` (an effect's values now in `[effects.values]`, which
    /// replace it). Error: a key the table does not have.
    pub(crate) fn clear_key(&mut self, key: &str) -> Result<()> {
        match key {
            "stribeck_nm" => self.stribeck_nm = None,
            "stribeck_velocity_rad_s" => self.stribeck_velocity_rad_s = None,
            "payload_mass_error_kg" => self.payload_mass_error_kg = None,
            "balancer_preload_n" => self.balancer_preload_n = None,
            "balancer_stiffness_n_per_m" => self.balancer_stiffness_n_per_m = None,
            "balancer_joint" => self.balancer_joint = None,
            "balancer_lever_m" => self.balancer_lever_m = None,
            "balancer_base_m" => self.balancer_base_m = None,
            "balancer_upright_rad" => self.balancer_upright_rad = None,
            "regeneration_recovered_fraction" => self.regeneration_recovered_fraction = None,
            _ => {
                return Err(Error::Invalid(format!(
                    "drive file: no key `effects.{key}`"
                )))
            }
        }
        Ok(())
    }
}
