//! The drive file's optional `[effects]` table, parsed once (in [`crate::robot::load`]) and
//! carried by [`crate::robot::RobotModel::effects`], so that identification
//! ([`crate::identify::Model`]) and the energy model ([`crate::energy::EnergyModel`]) read the
//! same switches and parameters.
//!
//! Keys (all optional, SI, unknown keys are errors naming the key):
//! `enabled = [...]` (catalogue names; replaces [`DEFAULT_EFFECTS`]), `stribeck_nm` (one
//! `f_s` per joint, N·m), `stribeck_velocity_rad_s` (`v_s`), `payload_mass_error_kg` (`Δm`),
//! `balancer_preload_n` (`F0`), `balancer_stiffness_n_per_m` (`k`),
//! `regeneration_recovered_fraction` (`ρ`). Values are checked against the effects' bounds
//! ([`super::ParamSpec`]).

use super::{
    Balancer, Effect, Regeneration as RegenEffect, Stribeck, CATALOGUE, STRIBECK_VELOCITY_RAD_S,
};
use crate::error::{Error, Result};
use serde::Deserialize;

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
#[derive(Deserialize, Debug, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct EffectsTable {
    pub enabled: Option<Vec<String>>,
    pub stribeck_nm: Option<Vec<f64>>,
    pub stribeck_velocity_rad_s: Option<f64>,
    pub payload_mass_error_kg: Option<f64>,
    pub balancer_preload_n: Option<f64>,
    pub balancer_stiffness_n_per_m: Option<f64>,
    pub regeneration_recovered_fraction: Option<f64>,
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
        }
    }
}

impl EffectsConfig {
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
        Ok(c)
    }

    /// The switches by catalogue index for a robot with (`has_drive`) or without drive data.
    pub fn enabled_mask(&self, has_drive: bool) -> [bool; 10] {
        match self.enabled {
            Some(m) => m,
            None if has_drive => {
                let mut m = [false; 10];
                for e in DEFAULT_EFFECTS {
                    if let Ok(i) = catalogue_index(e) {
                        m[i] = true;
                    }
                }
                m
            }
            None => [false; 10],
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

    /// The `balancer` effect (default geometry) with the configured preload and stiffness.
    pub fn balancer(&self) -> Balancer {
        Balancer {
            preload: self.balancer_preload_n,
            stiffness: self.balancer_stiffness_n_per_m,
            ..Balancer::zero()
        }
    }
}
