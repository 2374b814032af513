//! The one list of effects. Each line registers an effect by its stable name and the
//! function that builds it from a robot (drive data, `[effects]` keys, `[effects.values]`);
//! the order is the catalogue order used in reports. Energy, identify, diagnose and compare
//! all walk [`REGISTRY`] through [`super::EffectSet`]: a new effect is its own file plus one
//! line here.

use super::config::BuildContext;
use super::Effect;
use crate::error::{Error, Result};

/// One registered effect.
#[derive(Clone, Copy)]
pub struct Registration {
    /// Stable name (command line, drive files, reports; architecture.md).
    pub name: &'static str,
    /// Builds the effect for a robot, reading and validating its own drive-file keys.
    pub build: fn(&BuildContext) -> Result<Box<dyn Effect>>,
}

impl std::fmt::Debug for Registration {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Registration({})", self.name)
    }
}

/// The catalogue, in report order. One line per effect.
#[rustfmt::skip]
pub static REGISTRY: &[Registration] = &[
    Registration { name: "viscous", build: super::viscous::build },
    Registration { name: "coulomb", build: super::coulomb::build },
    Registration { name: "stribeck", build: super::stribeck::build },
    Registration { name: "armature", build: super::armature::build },
    Registration { name: "payload", build: super::payload::build },
    Registration { name: "balancer", build: super::balancer::build },
    Registration { name: "offset", build: super::offset::build },
    Registration { name: "rigid_body", build: super::rigid_body::build },
    Registration { name: "copper", build: super::electrical::build_copper },
    Registration { name: "gear_efficiency", build: super::electrical::build_gear_efficiency },
    Registration { name: "regeneration", build: super::electrical::build_regeneration },
    Registration { name: "standby", build: super::electrical::build_standby },
];

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
