//! Building the effects of a robot from its drive file, and the set of effects with their
//! switches that energy and identification share.
//!
//! The drive file's `[effects]` table holds `enabled = [...]` (catalogue names; replaces
//! [`DEFAULT_EFFECTS`]), `[effects.values]` (effect name → parameter values in the effect's
//! order; wins over the other keys; this is where `identify` writes what no other key holds),
//! and the effects' own keys: each registered effect names the keys it reads
//! ([`super::Registration::keys`]) and reads and validates them in its `build` function
//! ([`BuildContext::number`] and friends: errors name the file and `effects.<key>`, values
//! are checked against the effects' bounds, [`super::ParamSpec`]). A key no registered effect
//! reads is an error naming it. docs/effects.md.

use super::registry::{EffectId, EffectRegistry};
use super::{Effect, EnergyClass, Stage};
use crate::error::{Error, Result};
use crate::robot::{EffectsTable, RobotModel};

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

/// What an effect's `build` function reads: the robot, its `[effects]` table and file.
#[derive(Debug)]
pub struct BuildContext<'a> {
    /// The robot (dof, inertials, payload, drive data).
    pub robot: &'a RobotModel,
    /// The `[effects]` table (default when there is none).
    pub table: &'a EffectsTable,
    /// The drive file's name, for error messages.
    pub file: &'a str,
}

impl BuildContext<'_> {
    /// Number of joints.
    pub fn dof(&self) -> usize {
        self.robot.dof()
    }
    /// An error naming the file and `effects.<key>`.
    pub fn bad(&self, key: &str, msg: impl Into<String>) -> Error {
        Error::Field {
            file: self.file.to_string(),
            field: format!("effects.{key}"),
            msg: msg.into(),
        }
    }
    /// The number under `[effects] <key>` (`None` when absent; error naming the key when it
    /// is not a number).
    pub fn number(&self, key: &str) -> Result<Option<f64>> {
        self.table.number(key).map_err(|m| self.bad(key, m))
    }
    /// The list of numbers under `[effects] <key>`.
    pub fn numbers(&self, key: &str) -> Result<Option<Vec<f64>>> {
        self.table.numbers(key).map_err(|m| self.bad(key, m))
    }
    /// The non-negative integer under `[effects] <key>`.
    pub fn integer(&self, key: &str) -> Result<Option<usize>> {
        self.table.integer(key).map_err(|m| self.bad(key, m))
    }
    /// Per-joint values from the drive's `[[joints]]` (`dflt` per joint without drive data).
    pub fn per_joint(&self, f: impl Fn(&crate::robot::JointDrive) -> f64, dflt: f64) -> Vec<f64> {
        match &self.robot.drive {
            Some(d) => d.joints.iter().map(f).collect(),
            None => vec![dflt; self.dof()],
        }
    }
    /// Apply `[effects.values].<name>` to `e` if the table has it (error naming the key).
    pub fn apply_values(&self, e: &mut dyn Effect) -> Result<()> {
        if let Some(v) = self.table.values.as_ref().and_then(|m| m.get(e.name())) {
            e.set_values(v)
                .map_err(|err| self.bad(&format!("values.{}", e.name()), err.to_string()))?;
        }
        Ok(())
    }
}

/// Every registered effect of a robot with its switch, in catalogue order.
#[derive(Debug, Clone, Default)]
pub struct EffectSet {
    effects: Vec<Box<dyn Effect>>,
    enabled: Vec<bool>,
    /// The `[effects]` keys each effect reads (empty for hand-pushed effects).
    keys: Vec<&'static [&'static str]>,
}

impl EffectSet {
    /// An empty set (for hand-built sets; see [`EffectSet::push`]).
    pub fn new() -> Self {
        Self::default()
    }

    /// The friction effects of a drive: `viscous` and `coulomb` (velocity scale
    /// [`super::COULOMB_VELOCITY_SCALE_RAD_S`]), both switched on.
    pub fn friction_of(drive: &crate::robot::Drive) -> Self {
        let mut s = Self::new();
        s.push(Box::new(super::Viscous::from_drive(drive)));
        s.push(Box::new(super::Coulomb::from_drive(
            drive,
            super::COULOMB_VELOCITY_SCALE_RAD_S,
        )));
        s
    }

    /// Every effect of the process's registry ([`EffectRegistry::current`]: the catalogue,
    /// [`super::REGISTRY`], unless a program installed its own) for `robot`:
    /// [`EffectSet::of_robot_with`].
    pub fn of_robot(robot: &RobotModel) -> Result<Self> {
        Self::of_robot_with(robot, &EffectRegistry::current())
    }

    /// Every effect of `registry` for `robot`, built from its drive data and drive-file
    /// tables, with the switches of `[effects] enabled` ([`DEFAULT_EFFECTS`] when the robot
    /// has drive data and the table names none, plus a declared balancer with a force;
    /// nothing without drive data). Errors ([`Error::Field`]) name the file and
    /// `effects.<key>`: a key no effect reads, a bad value, an unknown effect name; an effect
    /// whose stage is not the one it was registered with.
    pub fn of_robot_with(robot: &RobotModel, registry: &EffectRegistry) -> Result<Self> {
        let table = &robot.effects.table;
        let file = robot
            .effects
            .file
            .clone()
            .unwrap_or_else(|| robot.name().to_string());
        let ctx = BuildContext {
            robot,
            table,
            file: &file,
        };
        for key in table.keys.keys() {
            registry
                .owner_of_key(key)
                .map_err(|e| ctx.bad(key, e.to_string()))?;
        }
        if let Some(v) = &table.values {
            for name in v.keys() {
                registry
                    .index(name)
                    .map_err(|e| ctx.bad("values", e.to_string()))?;
            }
        }
        let entries = registry.entries();
        let mut effects = Vec::with_capacity(entries.len());
        for r in entries {
            let mut e = (r.build)(&ctx)?;
            let torque_line = matches!(e.energy_class(), EnergyClass::Line(_));
            if torque_line == (e.stage() == Stage::Torque) {
                return Err(Error::Invalid(format!(
                    "effect `{}`: a torque effect is booked to rigid_body, friction or balancer, \
                     a motor or supply effect to a line of its own ({:?})",
                    r.name,
                    e.energy_class()
                )));
            }
            if e.name() != r.name || e.stage() != r.stage {
                return Err(Error::Invalid(format!(
                    "effect registered as `{}` ({:?}) builds `{}` ({:?})",
                    r.name,
                    r.stage,
                    e.name(),
                    e.stage()
                )));
            }
            ctx.apply_values(e.as_mut())?;
            effects.push(e);
        }
        let has_drive = robot.drive.is_some();
        let enabled = match &table.enabled {
            Some(list) => {
                let mut m = vec![false; entries.len()];
                for s in list {
                    let i = registry
                        .index(s)
                        .map_err(|e| ctx.bad("enabled", e.to_string()))?;
                    m[i] = true;
                }
                m
            }
            None => effects.iter().map(|e| e.on_by_default(has_drive)).collect(),
        };
        Ok(EffectSet {
            effects,
            enabled,
            keys: entries.iter().map(|r| r.keys).collect(),
        })
    }

    /// Add an effect, switched on.
    pub fn push(&mut self, effect: Box<dyn Effect>) {
        self.effects.push(effect);
        self.enabled.push(true);
        self.keys.push(&[]);
    }

    /// The `[effects]` keys the effect called `name` reads (empty when unknown).
    pub fn keys_of(&self, name: &str) -> &'static [&'static str] {
        self.position(name).map_or(&[], |i| self.keys[i])
    }

    /// The position of the effect called `name` in this set.
    fn position(&self, name: &str) -> Option<usize> {
        self.effects.iter().position(|e| e.name() == name)
    }

    /// The effect called `name`. Error: unknown name (listing the catalogue).
    pub fn get(&self, name: &str) -> Result<&dyn Effect> {
        match self.position(name) {
            Some(i) => Ok(self.effects[i].as_ref()),
            None => Err(EffectId::of(name)
                .err()
                .unwrap_or_else(|| Error::Invalid(format!("effect `{name}` is not in this set")))),
        }
    }

    /// The effect called `name` as its concrete type `T` (e.g. [`super::Balancer`] for its
    /// geometry), or `None` when absent or of another type.
    pub fn typed<T: 'static>(&self, name: &str) -> Option<&T> {
        self.get(name).ok()?.as_any().downcast_ref::<T>()
    }

    /// The effect called `name`, mutable.
    pub fn get_mut(&mut self, name: &str) -> Result<&mut dyn Effect> {
        match self.position(name) {
            Some(i) => Ok(self.effects[i].as_mut()),
            None => Err(EffectId::of(name)
                .err()
                .unwrap_or_else(|| Error::Invalid(format!("effect `{name}` is not in this set")))),
        }
    }

    /// Switch the effect called `name` on or off; `false` if there is none.
    pub fn set_enabled(&mut self, name: &str, on: bool) -> bool {
        match self.position(name) {
            Some(i) => {
                self.enabled[i] = on;
                true
            }
            None => false,
        }
    }

    /// Switch every effect off.
    pub fn disable_all(&mut self) {
        self.enabled.iter_mut().for_each(|e| *e = false);
    }

    /// Whether the effect called `name` is switched on (false for unknown names).
    pub fn is_enabled(&self, name: &str) -> bool {
        self.position(name).is_some_and(|i| self.enabled[i])
    }

    /// Names of the effects, with their switches.
    pub fn names(&self) -> Vec<(&'static str, bool)> {
        self.effects
            .iter()
            .zip(&self.enabled)
            .map(|(e, on)| (e.name(), *on))
            .collect()
    }

    /// Names of the effects switched on, in catalogue order.
    pub fn enabled_names(&self) -> Vec<&'static str> {
        self.names()
            .into_iter()
            .filter(|(_, on)| *on)
            .map(|(n, _)| n)
            .collect()
    }

    /// The effects with their switches, in order.
    pub fn iter(&self) -> impl Iterator<Item = (&dyn Effect, bool)> {
        self.effects
            .iter()
            .zip(&self.enabled)
            .map(|(e, on)| (e.as_ref(), *on))
    }

    /// The torque effects with their switches, in order.
    pub fn torque_effects(&self) -> impl Iterator<Item = (&dyn Effect, bool)> {
        self.iter().filter(|(e, _)| e.stage() == Stage::Torque)
    }

    /// Values of an enabled effect, or `None` when it is off or absent.
    pub fn enabled_values(&self, name: &str) -> Option<Vec<f64>> {
        self.position(name)
            .filter(|&i| self.enabled[i])
            .map(|i| self.effects[i].values())
    }

    /// Sum of the enabled torque effects' torques added to `tau` (N·m).
    pub fn add_torque(&self, q: &[f64], qd: &[f64], qdd: &[f64], tau: &mut [f64]) {
        for (e, on) in self.torque_effects() {
            if on {
                e.add_torque(q, qd, qdd, tau);
            }
        }
    }
}

/// A calibrated drive file being written (`printwatt identify`'s output, which every command
/// reads back): what an effect's [`Effect::write_calibrated`] may change. Each effect keeps its
/// identified values where it reads them: in its drive keys (`[[joints]]`, `[cabinet]`, the
/// robot's `[payload]`) or in `[effects.values]`, which wins over its `[effects]` keys.
#[derive(Debug)]
pub struct CalibratedDrive<'a> {
    pub(crate) file: &'a mut crate::robot::drive::DriveFile,
    pub(crate) table: &'a mut EffectsTable,
    pub(crate) values: &'a mut std::collections::BTreeMap<String, Vec<f64>>,
    pub(crate) enabled: &'a mut Vec<&'static str>,
    pub(crate) robot: &'a RobotModel,
    /// The `[effects]` keys of the effect being written.
    pub(crate) keys: &'static [&'static str],
}

impl CalibratedDrive<'_> {
    /// The robot as loaded (before identification).
    pub fn robot(&self) -> &RobotModel {
        self.robot
    }
    /// Whether the file has per-joint drive tables (`[[joints]]` with drive keys).
    pub fn has_drive_tables(&self) -> bool {
        self.robot.drive.is_some()
    }
    /// `[effects.values].<name> = v`.
    pub fn set_values(&mut self, name: &str, v: Vec<f64>) {
        self.values.insert(name.to_string(), v);
    }
    /// Remove `[effects.values].<name>`.
    pub fn remove_values(&mut self, name: &str) {
        self.values.remove(name);
    }
    /// Remove the written effect's own `[effects]` keys (its values now live elsewhere).
    pub fn remove_own_keys(&mut self) {
        for k in self.keys {
            self.table.keys.remove(*k);
        }
    }
    /// Set the `[[joints]]` drive key `key` (e.g. `viscous_nm_s_per_rad`) of joint `j` to
    /// `v[j]`, for every joint table. Error: not a drive key of `[[joints]]`.
    pub fn set_joint_key(&mut self, key: &str, v: &[f64]) -> Result<()> {
        for (jt, x) in self.file.joints.iter_mut().zip(v) {
            jt.set_drive_key(key, *x)?;
        }
        Ok(())
    }
    /// Set `[cabinet] standby_power_w` (when the file has a `[cabinet]` table), W.
    pub fn set_standby_power(&mut self, w: f64) {
        if let Some(c) = self.file.cabinet.as_mut() {
            c.standby_power_w = w;
        }
    }
    /// Write the robot's `[payload]`: mass (kg), centre of mass (m, flange frame) and a
    /// description; the inertia as the file had it.
    pub fn set_payload(&mut self, mass: f64, com: [f64; 3], description: String) {
        let inertia = self
            .file
            .payload
            .as_ref()
            .map_or([0.0; 6], |t| t.inertia_kg_m2);
        self.file.payload = Some(crate::robot::drive::PayloadTable {
            mass_kg: mass,
            com_m: com,
            inertia_kg_m2: inertia,
            description: Some(description),
        });
    }
    /// Leave the effect called `name` out of `[effects] enabled` (its values were folded into
    /// the robot).
    pub fn drop_from_enabled(&mut self, name: &str) {
        self.enabled.retain(|e| *e != name);
    }
    /// The default of [`Effect::write_calibrated`]: an enabled effect's values in
    /// `[effects.values]` (its own keys removed), a disabled effect's removed.
    pub fn write_values(&mut self, name: &str, values: Vec<f64>, enabled: bool) {
        if enabled {
            self.set_values(name, values);
            self.remove_own_keys();
        } else {
            self.remove_values(name);
        }
    }
}
