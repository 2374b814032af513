//! Physical effects beyond the rigid body, one file per effect, behind one small trait
//! (architecture.md, rule 3 and "Physical effects: the catalogue").
//!
//! Every effect has a stable [`Effect::name`] (used on the command line, in drive files and in
//! reports), named parameters with unit and bounds ([`ParamSpec`]), its current parameter
//! values, and, for joint-side torque effects, a [`TorqueEffect::add_torque`] contribution and,
//! where the torque is linear in the parameters, a [`TorqueEffect::regressor`] `Y(q, q̇, q̈)`
//! with `τ_effect = Y · θ` (the shape identification builds on; cf. pinocchio
//! `algorithm/regressor.hpp`).
//!
//! Implemented joint-side effects: [`Viscous`] (`viscous`), [`Coulomb`] (`coulomb`),
//! [`Stribeck`] (`stribeck`), [`Armature`] (`armature`), [`Payload`] (`payload`, a payload
//! mass error), [`Balancer`] (`balancer`). The electrical and supply effects [`Copper`],
//! [`GearEfficiency`], [`Regeneration`] and [`Standby`] act after the torque is known; they
//! implement [`Effect`] (name + bounded parameters) and are evaluated by the motor model in
//! [`crate::energy`] and [`crate::identify`] (seed 001, eqs. 2–4).

mod armature;
mod balancer;
mod config;
mod coulomb;
mod electrical;
mod payload;
mod stribeck;
mod viscous;

pub use armature::Armature;
pub use balancer::{Balancer, BALANCER_A_M, BALANCER_B_M, BALANCER_UPRIGHT_RAD};
pub(crate) use config::EffectsTable;
pub use config::{
    catalogue_index, CalibratedParam, Calibration, CalibrationRound, EffectsConfig, DEFAULT_EFFECTS,
};
pub use coulomb::{Coulomb, COULOMB_VELOCITY_SCALE_RAD_S};
pub use electrical::{Copper, GearEfficiency, Regeneration, Standby};
pub use payload::Payload;
pub use stribeck::{Stribeck, STRIBECK_VELOCITY_RAD_S};
pub use viscous::Viscous;

use crate::error::{Error, Result};

/// The stable names of the effect catalogue (architecture.md), implemented or reserved.
pub const CATALOGUE: [&str; 10] = [
    "viscous",
    "coulomb",
    "stribeck",
    "armature",
    "payload",
    "balancer",
    "copper",
    "gear_efficiency",
    "regeneration",
    "standby",
];

/// One named parameter of an effect.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ParamSpec {
    /// Stable name, e.g. `f_v[2]` (joint index 1-based in brackets).
    pub name: String,
    /// SI unit, e.g. `N·m·s/rad`.
    pub unit: &'static str,
    /// Lower bound (inclusive).
    pub lower: f64,
    /// Upper bound (inclusive), `+inf` when unbounded.
    pub upper: f64,
}

/// What every effect has: a stable name and named, bounded parameters.
pub trait Effect: Send + Sync + std::fmt::Debug {
    /// Stable short name from [`CATALOGUE`].
    fn name(&self) -> &'static str;
    /// The parameters, in the order of [`Effect::values`] and of the regressor's columns.
    fn params(&self) -> Vec<ParamSpec>;
    /// Current parameter values (SI, units as in [`Effect::params`]).
    fn values(&self) -> Vec<f64>;
    /// Replace all parameter values. Error: wrong count, or a value outside its bounds.
    fn set_values(&mut self, values: &[f64]) -> Result<()>;
}

/// A joint-side torque effect, added to the rigid-body torque (seed 000, eq. 1: `τ_f`).
pub trait TorqueEffect: Effect {
    /// Add this effect's joint torque (N·m, N for prismatic joints) at state
    /// (`q` rad, `qd` rad/s, `qdd` rad/s², each of length `dof`) to `tau`. No allocation.
    fn add_torque(&self, q: &[f64], qd: &[f64], qdd: &[f64], tau: &mut [f64]);

    /// Fill the regressor `Y` (row-major, `dof × params().len()`) with
    /// `τ_effect = Y · values()`, and return `true`; return `false` (leaving `y` untouched)
    /// if the effect is not linear in its parameters.
    fn regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64], y: &mut [f64]) -> bool;
}

/// Check a new parameter vector against the specs.
pub(crate) fn check_values(effect: &str, specs: &[ParamSpec], values: &[f64]) -> Result<()> {
    if values.len() != specs.len() {
        return Err(Error::SizeMismatch {
            what: format!("parameters of effect `{effect}`"),
            got: values.len(),
            expected: specs.len(),
        });
    }
    for (s, v) in specs.iter().zip(values) {
        if !(v.is_finite() && *v >= s.lower && *v <= s.upper) {
            return Err(Error::Invalid(format!(
                "effect `{effect}`: parameter {} = {v} {} outside [{}, {}]",
                s.name, s.unit, s.lower, s.upper
            )));
        }
    }
    Ok(())
}

/// Per-joint parameter specs `prefix[1..=n]`.
pub(crate) fn per_joint(prefix: &str, unit: &'static str, n: usize) -> Vec<ParamSpec> {
    (0..n)
        .map(|j| ParamSpec {
            name: format!("{prefix}[{}]", j + 1),
            unit,
            lower: 0.0,
            upper: f64::INFINITY,
        })
        .collect()
}

/// A set of torque effects with on/off switches, summed in insertion order.
#[derive(Debug, Default)]
pub struct EffectSet {
    effects: Vec<(Box<dyn TorqueEffect>, bool)>,
}

impl EffectSet {
    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// The friction effects of a drive: `viscous` and `coulomb` (velocity scale
    /// [`COULOMB_VELOCITY_SCALE_RAD_S`]), both switched on.
    pub fn friction_of(drive: &crate::robot::Drive) -> Self {
        let mut s = Self::new();
        s.push(Box::new(Viscous::from_drive(drive)));
        s.push(Box::new(Coulomb::from_drive(
            drive,
            COULOMB_VELOCITY_SCALE_RAD_S,
        )));
        s
    }

    /// Add an effect, switched on.
    pub fn push(&mut self, effect: Box<dyn TorqueEffect>) {
        self.effects.push((effect, true));
    }

    /// Switch the effect called `name` on or off; `false` if there is none.
    pub fn set_enabled(&mut self, name: &str, on: bool) -> bool {
        let mut found = false;
        for (e, en) in &mut self.effects {
            if e.name() == name {
                *en = on;
                found = true;
            }
        }
        found
    }

    /// Names of the effects, with their switches.
    pub fn names(&self) -> Vec<(&'static str, bool)> {
        self.effects.iter().map(|(e, on)| (e.name(), *on)).collect()
    }

    /// Sum of the enabled effects' torques added to `tau` (N·m).
    pub fn add_torque(&self, q: &[f64], qd: &[f64], qdd: &[f64], tau: &mut [f64]) {
        for (e, on) in &self.effects {
            if *on {
                e.add_torque(q, qd, qdd, tau);
            }
        }
    }
}
