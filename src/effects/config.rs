//! The drive file's optional `[effects]` table, parsed once (in [`crate::robot::load`]) and
//! carried by [`crate::robot::RobotModel::effects`], so that identification
//! ([`crate::identify::Model`]) and the energy model ([`crate::energy::EnergyModel`]) read the
//! same switches and parameters.
//!
//! Keys (all optional, SI, unknown keys are errors naming the key):
//! `enabled = [...]` (catalogue names; replaces [`DEFAULT_EFFECTS`]), `stribeck_nm` (one
//! `f_s` per joint, N·m), `stribeck_velocity_rad_s` (`v_s`), `payload_mass_error_kg` (`Δm`),
//! `balancer_preload_n` (`F0`), `balancer_stiffness_n_per_m` (`k`),
//! `regeneration_recovered_fraction` (`ρ`); balancer geometry `balancer_joint` (1-based, default
//! 2), `balancer_lever_m` (`a`), `balancer_base_m` (`b`), `balancer_upright_rad` (`q_up`): a
//! drive file that gives `a` and `b` declares that the robot has a balancer; `[effects.values]`
//! (effect name → parameter values in the effect's order, for robots whose file has no other
//! key for them). Values are checked against the effects' bounds
//! ([`super::ParamSpec`]).

use super::{
    Balancer, Effect, Regeneration as RegenEffect, Stribeck, BALANCER_A_M, BALANCER_B_M,
    BALANCER_UPRIGHT_RAD, CATALOGUE, STRIBECK_VELOCITY_RAD_S,
};
use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// Effects switched on by default when the robot has drive data (those the drive file's
/// `[[joints]]` and `[cabinet]` keys carry). Without drive data nothing is switched on.
pub const DEFAULT_EFFECTS: [&str; 7] = [
    "viscous",
    "coulomb",
    "armature",
    "copper",
    "gear_efficiency",
    "regeneration",
    "standby",
];

/// Index of a catalogue name, or an error listing the names.
pub fn catalogue_index(name: &str) -> Result<usize> {
    CATALOGUE.iter().position(|c| *c == name).ok_or_else(|| {
        Error::Invalid(format!(
            "unknown effect `{name}`; the catalogue: {}",
            CATALOGUE.join(", ")
        ))
    })
}

/// The `[effects]` table as written (strict: unknown keys are errors).
#[derive(Deserialize, Serialize, Debug, Default, Clone)]
#[serde(deny_unknown_fields)]
pub(crate) struct EffectsTable {
    pub enabled: Option<Vec<String>>,
    pub stribeck_nm: Option<Vec<f64>>,
    pub stribeck_velocity_rad_s: Option<f64>,
    pub payload_mass_error_kg: Option<f64>,
    pub balancer_preload_n: Option<f64>,
    pub balancer_stiffness_n_per_m: Option<f64>,
    pub balancer_joint: Option<usize>,
    pub balancer_lever_m: Option<f64>,
    pub balancer_base_m: Option<f64>,
    pub balancer_upright_rad: Option<f64>,
    pub regeneration_recovered_fraction: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub values: Option<std::collections::BTreeMap<String, Vec<f64>>>,
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
    /// Validation RMSE before and after the round (signal unit).
    pub validation_rmse_before: f64,
    /// Validation RMSE after the round (signal unit).
    pub validation_rmse_after: f64,
}

/// One identified parameter.
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CalibratedParam {
    /// Catalogue name of the effect.
    pub effect: String,
    /// Parameter name, e.g. `f_c[2]`.
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

/// The validated `[effects]` configuration of a robot. [`Default`] = no table: default
/// switches, every extra parameter zero (`v_s` = [`STRIBECK_VELOCITY_RAD_S`]).
#[derive(Clone, Debug, PartialEq)]
pub struct EffectsConfig {
    /// The drive file the table came from (`None`: no table).
    pub file: Option<String>,
    /// Switches by catalogue index ([`CATALOGUE`]); `None` = [`DEFAULT_EFFECTS`] when the
    /// robot has drive data, nothing otherwise.
    pub enabled: Option<[bool; 10]>,
    /// Stribeck peaks `f_s` per joint, N·m (`None` = zeros).
    pub stribeck_nm: Option<Vec<f64>>,
    /// Stribeck velocity `v_s`, rad/s.
    pub stribeck_velocity_rad_s: f64,
    /// Payload mass error `Δm`, kg.
    pub payload_mass_error_kg: f64,
    /// Balancer preload `F0`, N.
    pub balancer_preload_n: f64,
    /// Balancer stiffness `k`, N/m.
    pub balancer_stiffness_n_per_m: f64,
    /// Recovered fraction `ρ` of the power the regeneration policy burns.
    pub regeneration_recovered_fraction: f64,
    /// Balancer geometry declared by the drive file (`balancer_lever_m`, `balancer_base_m`):
    /// the robot has a balancer. Without it a `balancer` candidate is not plausible.
    pub balancer_declared: bool,
    /// Balancer geometry: joint (0-based), lever `a` on the moving link (m), distance `b` of
    /// the fixed end (m), upright angle (rad).
    pub balancer_geometry: (usize, f64, f64, f64),
    /// Identified parameter values of effects the drive file has no other key for (a robot
    /// without per-joint drive tables): effect name → values in the order of the effect's
    /// parameters (`[effects.values]`, docs/effects.md).
    pub values: std::collections::BTreeMap<String, Vec<f64>>,
    /// The `[calibration]` table when the robot is a calibrated one.
    pub calibration: Option<Calibration>,
}

impl Default for EffectsConfig {
    fn default() -> Self {
        EffectsConfig {
            file: None,
            enabled: None,
            stribeck_nm: None,
            stribeck_velocity_rad_s: STRIBECK_VELOCITY_RAD_S,
            payload_mass_error_kg: 0.0,
            balancer_preload_n: 0.0,
            balancer_stiffness_n_per_m: 0.0,
            regeneration_recovered_fraction: 0.0,
            balancer_declared: false,
            balancer_geometry: (1, BALANCER_A_M, BALANCER_B_M, BALANCER_UPRIGHT_RAD),
            values: Default::default(),
            calibration: None,
        }
    }
}

impl EffectsConfig {
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

    /// Validate a parsed table for a robot of `dof` joints whose nominal payload is
    /// `nominal_payload_kg`. Errors ([`Error::Field`]) name `file` and `effects.<key>`.
    pub(crate) fn from_table(
        t: EffectsTable,
        file: &str,
        dof: usize,
        nominal_payload_kg: f64,
    ) -> Result<Self> {
        let bad = |key: &str, msg: String| Error::Field {
            file: file.to_string(),
            field: format!("effects.{key}"),
            msg,
        };
        let mut c = EffectsConfig {
            file: Some(file.to_string()),
            ..Default::default()
        };
        if let Some(list) = t.enabled {
            let mut mask = [false; 10];
            for s in &list {
                let i = catalogue_index(s).map_err(|e| bad("enabled", e.to_string()))?;
                mask[i] = true;
            }
            c.enabled = Some(mask);
        }
        // Bounds: those of the effects themselves.
        let mut stribeck = Stribeck::zero(dof);
        if let Some(fs) = t.stribeck_nm {
            if fs.len() != dof {
                return Err(bad(
                    "stribeck_nm",
                    format!("{} values, expected {dof} (one per joint)", fs.len()),
                ));
            }
            stribeck.fs = fs;
        }
        if let Some(vs) = t.stribeck_velocity_rad_s {
            stribeck.vs = vs;
        }
        let vals = stribeck.values();
        stribeck.set_values(&vals).map_err(|e| {
            let key = if t
                .stribeck_velocity_rad_s
                .is_some_and(|v| !(0.005..=1.0).contains(&v))
            {
                "stribeck_velocity_rad_s"
            } else {
                "stribeck_nm"
            };
            bad(key, e.to_string())
        })?;
        c.stribeck_nm = Some(stribeck.fs).filter(|fs| fs.iter().any(|f| *f != 0.0));
        c.stribeck_velocity_rad_s = stribeck.vs;
        if let Some(dm) = t.payload_mass_error_kg {
            if !(dm.is_finite() && dm >= -nominal_payload_kg) {
                return Err(bad(
                    "payload_mass_error_kg",
                    format!("must be finite and >= -{nominal_payload_kg} (the nominal payload), got {dm}"),
                ));
            }
            c.payload_mass_error_kg = dm;
        }
        let mut b = Balancer::zero();
        if let Some(j) = t.balancer_joint {
            if j == 0 || j > dof {
                return Err(bad(
                    "balancer_joint",
                    format!("must be a joint number 1..={dof}, got {j}"),
                ));
            }
            b.joint = j - 1;
        }
        for (key, v) in [
            ("balancer_lever_m", t.balancer_lever_m),
            ("balancer_base_m", t.balancer_base_m),
        ] {
            if let Some(x) = v {
                if !(x.is_finite() && x > 0.0) {
                    return Err(bad(key, format!("must be finite and > 0 m, got {x}")));
                }
            }
        }
        if let Some(x) = t.balancer_lever_m {
            b.a = x;
        }
        if let Some(x) = t.balancer_base_m {
            b.b = x;
        }
        if (b.a - b.b).abs() < 1e-6 {
            return Err(bad(
                "balancer_lever_m",
                format!(
                    "lever {} m equals the base distance {} m: the cylinder would reach zero length",
                    b.a, b.b
                ),
            ));
        }
        if let Some(x) = t.balancer_upright_rad {
            if !x.is_finite() {
                return Err(bad(
                    "balancer_upright_rad",
                    format!("must be finite, got {x}"),
                ));
            }
            b.upright = x;
        }
        c.balancer_declared = t.balancer_lever_m.is_some() && t.balancer_base_m.is_some();
        c.balancer_geometry = (b.joint, b.a, b.b, b.upright);
        for (key, v, idx) in [
            ("balancer_preload_n", t.balancer_preload_n, 0),
            (
                "balancer_stiffness_n_per_m",
                t.balancer_stiffness_n_per_m,
                1,
            ),
        ] {
            if let Some(x) = v {
                let mut vals = b.values();
                vals[idx] = x;
                b.set_values(&vals).map_err(|e| bad(key, e.to_string()))?;
            }
        }
        c.balancer_preload_n = b.preload;
        c.balancer_stiffness_n_per_m = b.stiffness;
        if let Some(rho) = t.regeneration_recovered_fraction {
            RegenEffect { recovered: 0.0 }
                .set_values(&[rho])
                .map_err(|e| bad("regeneration_recovered_fraction", e.to_string()))?;
            c.regeneration_recovered_fraction = rho;
        }
        if let Some(v) = t.values {
            for (name, vals) in v {
                catalogue_index(&name).map_err(|e| bad("values", e.to_string()))?;
                if vals.iter().any(|x| !x.is_finite()) {
                    return Err(bad(
                        &format!("values.{name}"),
                        "values must be finite".into(),
                    ));
                }
                c.values.insert(name, vals);
            }
        }
        Ok(c)
    }

    /// The switches by catalogue index for a robot with (`has_drive`) or without drive data.
    pub fn enabled_mask(&self, has_drive: bool) -> [bool; 10] {
        match self.enabled {
            Some(m) => m,
            None => {
                let mut m = [false; 10];
                if has_drive {
                    for e in DEFAULT_EFFECTS {
                        if let Ok(i) = catalogue_index(e) {
                            m[i] = true;
                        }
                    }
                }
                // A declared balancer with a force is part of the robot.
                if self.balancer_declared
                    && (self.balancer_preload_n != 0.0 || self.balancer_stiffness_n_per_m != 0.0)
                {
                    if let Ok(i) = catalogue_index("balancer") {
                        m[i] = true;
                    }
                }
                m
            }
        }
    }

    /// Whether effect `name` is switched on (false for unknown names).
    pub fn is_enabled(&self, name: &str, has_drive: bool) -> bool {
        catalogue_index(name).is_ok_and(|i| self.enabled_mask(has_drive)[i])
    }

    /// Switch effect `name` on or off (the other switches keep their current state for a
    /// robot with or without drive data, `has_drive`). Error: unknown name.
    pub fn set_enabled(&mut self, name: &str, on: bool, has_drive: bool) -> Result<()> {
        let i = catalogue_index(name)?;
        let mut m = self.enabled_mask(has_drive);
        m[i] = on;
        self.enabled = Some(m);
        Ok(())
    }

    /// The `stribeck` effect on `n` joints with the configured parameters.
    pub fn stribeck(&self, n: usize) -> Stribeck {
        let mut s = Stribeck::zero(n);
        if let Some(fs) = &self.stribeck_nm {
            s.fs.iter_mut().zip(fs).for_each(|(a, b)| *a = *b);
        }
        s.vs = self.stribeck_velocity_rad_s;
        s
    }

    /// The `balancer` effect with the configured geometry, preload and stiffness.
    pub fn balancer(&self) -> Balancer {
        let (joint, a, b, upright) = self.balancer_geometry;
        Balancer {
            joint,
            a,
            b,
            upright,
            preload: self.balancer_preload_n,
            stiffness: self.balancer_stiffness_n_per_m,
        }
    }
}
