//! The one list of effects. Each line registers an effect by its stable name and the
//! function that builds it from a robot (drive data, `[effects]` keys, `[effects.values]`);
//! the order is the catalogue order used in reports. Energy, identify, diagnose and compare
//! all walk the registered effects through [`super::EffectSet`]: a new effect is its own file
//! plus one line here. An effect defined outside the crate is its own file plus one call of
//! [`register`] before the first robot is built; it then follows the built-in ones in the
//! catalogue.

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

/// The built-in catalogue, in report order. One line per effect.
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

/// Effects registered with [`register`] (defined outside the crate), after [`REGISTRY`].
static REGISTERED: std::sync::RwLock<Vec<Registration>> = std::sync::RwLock::new(Vec::new());

/// Every registered effect, in catalogue order: [`REGISTRY`], then those added by [`register`].
pub fn registrations() -> Vec<Registration> {
    let extra = REGISTERED.read().unwrap_or_else(|e| e.into_inner());
    REGISTRY.iter().chain(extra.iter()).copied().collect()
}

/// Register an effect defined outside the crate (its own file implementing
/// [`super::Effect`] and a `build` function), after the built-in catalogue; robots built from
/// then on carry it. Registering the same registration again is a no-op. Error: another
/// effect already has the name, or the name is empty or not lowercase letters, digits and
/// `_`.
pub fn register(registration: Registration) -> Result<EffectId> {
    let name = registration.name;
    if name.is_empty()
        || !name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
    {
        return Err(Error::Invalid(format!(
            "effect name `{name}`: expected lowercase letters, digits and `_`"
        )));
    }
    let mut extra = REGISTERED.write().unwrap_or_else(|e| e.into_inner());
    let all: Vec<Registration> = REGISTRY.iter().chain(extra.iter()).copied().collect();
    if let Some(i) = all.iter().position(|r| r.name == name) {
        if i >= REGISTRY.len() && std::ptr::fn_addr_eq(all[i].build, registration.build) {
            return Ok(EffectId(i));
        }
        return Err(Error::Invalid(format!(
            "effect `{name}` is already registered"
        )));
    }
    extra.push(registration);
    Ok(EffectId(all.len()))
}

/// Identity of a registered effect: its position in the catalogue ([`registrations`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct EffectId(pub(crate) usize);

impl EffectId {
    /// The effect called `name`. Error: unknown name, listing the catalogue.
    pub fn of(name: &str) -> Result<EffectId> {
        registrations()
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
        registrations()[self.0].name
    }
    /// Its position in the catalogue (0-based).
    pub fn index(self) -> usize {
        self.0
    }
    /// Every registered effect, in catalogue order.
    pub fn all() -> impl Iterator<Item = EffectId> {
        (0..registrations().len()).map(EffectId)
    }
}

/// The stable names of the catalogue, in order.
pub fn catalogue() -> Vec<&'static str> {
    registrations().iter().map(|r| r.name).collect()
}

/// Index of a catalogue name, or an error listing the names.
pub fn catalogue_index(name: &str) -> Result<usize> {
    EffectId::of(name).map(EffectId::index)
}
