//! The one list of effects. Each line registers an effect by its stable name, the stage it
//! acts in, the drive-file keys it reads (`[effects] <key>`) and the function that builds it
//! from a robot (drive data, its keys, `[effects.values]`); the order is the catalogue order
//! used in reports. Energy, identify, diagnose, compare and the calibrated drive file all walk
//! the registry through [`super::EffectSet`]: a new effect is its own file plus one line here
//! ([`REGISTRY`]), or, outside the crate, one [`EffectRegistry::with`].

use super::config::BuildContext;
use super::{Effect, Stage};
use crate::error::{Error, Result};

/// One registered effect.
#[derive(Clone, Copy)]
pub struct Registration {
    /// Stable name (command line, drive files, reports; architecture.md).
    pub name: &'static str,
    /// The stage it acts in; the built effect must report the same ([`Effect::stage`]).
    pub stage: Stage,
    /// The `[effects]` keys of the drive file it reads (each owned by one effect; any other
    /// key is an error naming the file and the key). Its `[effects.values]` entry is its own
    /// name and is not listed.
    pub keys: &'static [&'static str],
    /// Builds the effect for a robot, reading and validating its own drive-file keys.
    pub build: fn(&BuildContext) -> Result<Box<dyn Effect>>,
}

impl std::fmt::Debug for Registration {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Registration({}, {:?})", self.name, self.stage)
    }
}

use super::{MotorTerm as M, SupplyTerm as S};

/// The catalogue, in report order. One line per effect.
#[rustfmt::skip]
pub static REGISTRY: &[Registration] = &[
    Registration { name: "viscous", stage: Stage::Torque, keys: &[], build: super::viscous::build },
    Registration { name: "coulomb", stage: Stage::Torque, keys: &[], build: super::coulomb::build },
    Registration { name: "stribeck", stage: Stage::Torque, keys: super::stribeck::KEYS, build: super::stribeck::build },
    Registration { name: "armature", stage: Stage::Torque, keys: &[], build: super::armature::build },
    Registration { name: "payload", stage: Stage::Torque, keys: super::payload::KEYS, build: super::payload::build },
    Registration { name: "balancer", stage: Stage::Torque, keys: super::balancer::KEYS, build: super::balancer::build },
    Registration { name: "offset", stage: Stage::Torque, keys: &[], build: super::offset::build },
    Registration { name: "rigid_body", stage: Stage::Torque, keys: &[], build: super::rigid_body::build },
    Registration { name: "copper", stage: Stage::Motor(M::WindingResistance), keys: &[], build: super::electrical::build_copper },
    Registration { name: "gear_efficiency", stage: Stage::Motor(M::GearEfficiency), keys: &[], build: super::electrical::build_gear_efficiency },
    Registration { name: "regeneration", stage: Stage::Supply(S::RecoveredFraction), keys: super::electrical::REGENERATION_KEYS, build: super::electrical::build_regeneration },
    Registration { name: "standby", stage: Stage::Supply(S::ConstantPower), keys: &[], build: super::electrical::build_standby },
];

/// The registry installed for the process ([`EffectRegistry::install`]).
static INSTALLED: std::sync::RwLock<Option<std::sync::Arc<EffectRegistry>>> =
    std::sync::RwLock::new(None);

/// Keys of the `[effects]` table that belong to no effect (the switches and the values).
const TABLE_KEYS: [&str; 2] = ["enabled", "values"];

/// A registry of effects: the catalogue ([`REGISTRY`]) plus effects registered from outside
/// the crate ([`EffectRegistry::with`]), checked when registered: names and drive-file keys
/// unique, and at most one effect per single-valued stage ([`Stage::is_single`]: the motor
/// model's winding resistance and gear efficiency, the supply's recovered fraction).
#[derive(Clone, Debug)]
pub struct EffectRegistry {
    entries: Vec<Registration>,
}

impl Default for EffectRegistry {
    fn default() -> Self {
        Self::builtin()
    }
}

impl EffectRegistry {
    /// The catalogue, [`REGISTRY`].
    pub fn builtin() -> Self {
        EffectRegistry {
            entries: REGISTRY.to_vec(),
        }
    }

    /// This registry plus `r` (appended to the catalogue order). Errors: a name already
    /// registered, a drive-file key another effect (or the table itself) owns, a
    /// single-valued stage another effect already fills.
    pub fn with(mut self, r: Registration) -> Result<Self> {
        let bad = |msg: String| Error::Invalid(format!("registering effect `{}`: {msg}", r.name));
        if r.name.is_empty()
            || !r
                .name
                .chars()
                .all(|c| c.is_ascii_lowercase() || c == '_' || c.is_ascii_digit())
        {
            return Err(bad("a name is lower-case letters, digits and `_`".into()));
        }
        if self.entries.iter().any(|e| e.name == r.name) {
            return Err(bad("the name is already registered".into()));
        }
        for k in r.keys {
            if TABLE_KEYS.contains(k) {
                return Err(bad(format!("`{k}` is a key of the [effects] table itself")));
            }
            if let Some(o) = self.entries.iter().find(|e| e.keys.contains(k)) {
                return Err(bad(format!(
                    "drive-file key `{k}` belongs to effect `{}`",
                    o.name
                )));
            }
        }
        if r.stage.is_single() {
            if let Some(o) = self.entries.iter().find(|e| e.stage == r.stage) {
                return Err(bad(format!(
                    "stage {:?} takes one effect and `{}` has it",
                    r.stage, o.name
                )));
            }
        }
        self.entries.push(r);
        Ok(self)
    }

    /// Make this registry the one every model of the process builds its effects from
    /// ([`super::EffectSet::of_robot`], [`crate::energy::EnergyModel::new`], identification,
    /// the calibrated drive file, the uncertainty study): how a program registers its own
    /// effects once, at start-up.
    pub fn install(self) {
        let mut g = INSTALLED.write().unwrap_or_else(|e| e.into_inner());
        *g = Some(std::sync::Arc::new(self));
    }

    /// The installed registry ([`EffectRegistry::install`]), else the catalogue.
    pub fn current() -> std::sync::Arc<EffectRegistry> {
        let g = INSTALLED.read().unwrap_or_else(|e| e.into_inner());
        match g.as_ref() {
            Some(r) => std::sync::Arc::clone(r),
            None => std::sync::Arc::new(Self::builtin()),
        }
    }

    /// The registrations, in catalogue order.
    pub fn entries(&self) -> &[Registration] {
        &self.entries
    }

    /// The stable names, in catalogue order.
    pub fn names(&self) -> Vec<&'static str> {
        self.entries.iter().map(|r| r.name).collect()
    }

    /// Position of the effect called `name`. Error: unknown name, listing the catalogue.
    pub fn index(&self, name: &str) -> Result<usize> {
        self.entries
            .iter()
            .position(|r| r.name == name)
            .ok_or_else(|| {
                Error::Invalid(format!(
                    "unknown effect `{name}`; the catalogue: {}",
                    self.names().join(", ")
                ))
            })
    }

    /// The effect owning the `[effects]` key `key` (`None` for the table's own keys).
    /// Error: a key no effect reads, listing the keys.
    pub fn owner_of_key(&self, key: &str) -> Result<Option<&Registration>> {
        if TABLE_KEYS.contains(&key) {
            return Ok(None);
        }
        match self.entries.iter().find(|r| r.keys.contains(&key)) {
            Some(r) => Ok(Some(r)),
            None => {
                let mut all: Vec<&str> = TABLE_KEYS.to_vec();
                all.extend(self.entries.iter().flat_map(|r| r.keys.iter().copied()));
                Err(Error::Invalid(format!(
                    "unknown key `{key}`; the keys: {}",
                    all.join(", ")
                )))
            }
        }
    }
}

/// Identity of a registered effect: its position in [`REGISTRY`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct EffectId(pub(crate) usize);

impl EffectId {
    /// The effect called `name`. Error: unknown name, listing the catalogue.
    pub fn of(name: &str) -> Result<EffectId> {
        REGISTRY
            .iter()
            .position(|r| r.name == name)
            .map(EffectId)
            .ok_or_else(|| {
                Error::Invalid(format!(
                    "unknown effect `{name}`; the catalogue: {}",
                    catalogue().join(", ")
                ))
            })
    }
    /// Its stable name.
    pub fn name(self) -> &'static str {
        REGISTRY[self.0].name
    }
    /// Its position in the catalogue (0-based).
    pub fn index(self) -> usize {
        self.0
    }
    /// Every registered effect, in catalogue order.
    pub fn all() -> impl Iterator<Item = EffectId> {
        (0..REGISTRY.len()).map(EffectId)
    }
}

/// The stable names of the catalogue, in order.
pub fn catalogue() -> Vec<&'static str> {
    REGISTRY.iter().map(|r| r.name).collect()
}

/// Index of a catalogue name, or an error listing the names.
pub fn catalogue_index(name: &str) -> Result<usize> {
    EffectId::of(name).map(EffectId::index)
}
