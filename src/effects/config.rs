//! Building the effects of a robot from its drive file, and the set of effects with their
//! switches that energy and identification share.
//!
//! Keys of the drive file's `[effects]` table (all optional, SI; unknown keys are errors
//! naming the key, values are checked against the effects' bounds ([`super::ParamSpec`])):
//! `enabled = [...]` (catalogue names; replaces [`DEFAULT_EFFECTS`]), `stribeck_nm`,
//! `stribeck_velocity_rad_s`, `payload_mass_error_kg`, `balancer_preload_n`,
//! `balancer_stiffness_n_per_m`, balancer geometry `balancer_joint` (1-based),
//! `balancer_lever_m`, `balancer_base_m`, `balancer_upright_rad` (a drive file that gives the
//! lever and the base declares that the robot has a balancer), `regeneration_recovered_fraction`,
//! and `[effects.values]`: effect name → parameter values in the effect's order (wins over
//! the other keys; this is where `identify` writes what no other key holds). docs/effects.md.

use super::registry::{registrations, EffectId};
use super::{Effect, MotorTerm, Stage, SupplyTerm, COULOMB_VELOCITY_SCALE_RAD_S};
use crate::error::{Error, Result};
use crate::robot::{EffectsTable, Regeneration, RobotModel};

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
    /// Per-joint values from the drive's `[[joints]]` (`dflt` per joint without drive data).
    pub fn per_joint(&self, f: impl Fn(&crate::robot::JointDrive) -> f64, dflt: f64) -> Vec<f64> {
        match &self.robot.drive {
            Some(d) => d.joints.iter().map(f).collect(),
            None => vec![dflt; self.dof()],
        }
    }
    /// Per-joint values of the drive file's `[[joints]]` key `key` (`dflt` per joint without
    /// drive data). Error: a key the drive train does not have.
    pub(crate) fn joint_key(&self, key: &str, dflt: f64) -> Result<Vec<f64>> {
        match &self.robot.drive {
            Some(d) => d
                .joints
                .iter()
                .map(|j| {
                    j.key(key).ok_or_else(|| Error::Field {
                        file: self.file.to_string(),
                        field: format!("joints.{key}"),
                        msg: "not a drive key of the joint tables".into(),
                    })
                })
                .collect(),
            None => Ok(vec![dflt; self.dof()]),
        }
    }
    /// Apply `[effects.values].<name>` to `e` if the table has it (error naming the key).
    pub(crate) fn apply_values(&self, e: &mut dyn Effect) -> Result<()> {
        if let Some(v) = self.table.values.as_ref().and_then(|m| m.get(e.name())) {
            e.set_values(v)
                .map_err(|err| self.bad(&format!("values.{}", e.name()), err.to_string()))?;
        }
        Ok(())
    }
}

/// The motor and supply terms of an effect set ([`EffectSet::motor_terms`]); `None` where no
/// switched-on effect supplies the term.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct MotorTerms {
    /// Winding resistance per joint, Ω.
    pub winding_resistance: Option<Vec<f64>>,
    /// Gear efficiency per joint (1).
    pub gear_efficiency: Option<Vec<f64>>,
    /// Share of braking power recovered (1).
    pub regeneration: Option<f64>,
    /// Standby power, W.
    pub standby_w: Option<f64>,
}

/// Every registered effect of a robot with its switch, indexed by [`EffectId`].
#[derive(Debug, Clone, Default)]
pub struct EffectSet {
    effects: Vec<Box<dyn Effect>>,
    enabled: Vec<bool>,
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

    /// Every registered effect of `robot`, built from its drive data and drive-file tables,
    /// with the switches of `[effects] enabled` ([`DEFAULT_EFFECTS`] when the robot has drive
    /// data and the table names none, plus a declared balancer with a force; nothing without
    /// drive data). Errors ([`Error::Field`]) name the file and `effects.<key>`.
    pub fn of_robot(robot: &RobotModel) -> Result<Self> {
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
        if let Some(v) = &table.values {
            for name in v.keys() {
                EffectId::of(name).map_err(|e| ctx.bad("values", e.to_string()))?;
            }
        }
        let registry = registrations();
        let mut effects = Vec::with_capacity(registry.len());
        for r in &registry {
            let mut e = (r.build)(&ctx)?;
            ctx.apply_values(e.as_mut())?;
            effects.push(e);
        }
        let has_drive = robot.drive.is_some();
        let enabled = match &table.enabled {
            Some(list) => {
                let mut m = vec![false; registry.len()];
                for s in list {
                    let i = EffectId::of(s).map_err(|e| ctx.bad("enabled", e.to_string()))?;
                    m[i.0] = true;
                }
                m
            }
            None => registry
                .iter()
                .zip(&effects)
                .map(|(r, e)| {
                    (has_drive && DEFAULT_EFFECTS.contains(&r.name))
                        || (r.name == "balancer" && e.implausible().is_none() && !e.is_null())
                })
                .collect(),
        };
        Ok(EffectSet { effects, enabled })
    }

    /// Add an effect, switched on.
    pub fn push(&mut self, effect: Box<dyn Effect>) {
        self.effects.push(effect);
        self.enabled.push(true);
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

    /// The motor and supply terms the switched-on effects supply, each read by its
    /// [`Stage`], not by the effect's name. Error: two switched-on effects supply the same
    /// term (one would silently replace the other), naming both.
    pub(crate) fn motor_terms(&self) -> Result<MotorTerms> {
        let mut t = MotorTerms::default();
        let mut supplied: Vec<(Stage, &'static str)> = Vec::new();
        for (e, on) in self.iter() {
            let stage = e.stage();
            if !on || stage == Stage::Torque {
                continue;
            }
            if let Some((_, other)) = supplied.iter().find(|(s, _)| *s == stage) {
                return Err(Error::Invalid(format!(
                    "effects `{other}` and `{}` both supply {}: one effect per motor or supply \
                     term",
                    e.name(),
                    stage.term()
                )));
            }
            supplied.push((stage, e.name()));
            match stage {
                Stage::Torque => {}
                Stage::Motor(MotorTerm::WindingResistance) => {
                    t.winding_resistance = Some(e.values())
                }
                Stage::Motor(MotorTerm::GearEfficiency) => t.gear_efficiency = Some(e.values()),
                Stage::Supply(SupplyTerm::Regeneration) => t.regeneration = Some(e.values()[0]),
                Stage::Supply(SupplyTerm::Standby) => t.standby_w = Some(e.values()[0]),
            }
        }
        Ok(t)
    }

    /// The torque effects with their switches, in order.
    pub(crate) fn torque_effects(&self) -> impl Iterator<Item = (&dyn Effect, bool)> {
        self.iter().filter(|(e, _)| e.stage() == Stage::Torque)
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

/// Which effects the energy model keeps, and overrides of their settings: the choices of
/// [`crate::energy::EnergyModel::with_options`], read by each effect's
/// [`Effect::in_energy_model`](super::Effect::in_energy_model).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyOptions {
    /// Include the payload from the drive file (default `true`).
    pub payload: bool,
    /// Include the friction effects (`viscous`, `coulomb`, `stribeck`), each as switched by the
    /// drive file's `[effects]` table (default `true`).
    pub friction: bool,
    /// Include the armature `G²J_m` when `[effects]` switches it on (default `true`).
    pub armature: bool,
    /// Velocity scale ε of the smoothed Coulomb sign, rad/s; the default
    /// ([`COULOMB_VELOCITY_SCALE_RAD_S`]) keeps the robot's own (identified) ε.
    pub coulomb_velocity_scale: f64,
    /// Override the drive file's regeneration policy.
    pub regeneration: Option<Regeneration>,
}

impl Default for EnergyOptions {
    fn default() -> Self {
        EnergyOptions {
            payload: true,
            friction: true,
            armature: true,
            coulomb_velocity_scale: COULOMB_VELOCITY_SCALE_RAD_S,
            regeneration: None,
        }
    }
}
