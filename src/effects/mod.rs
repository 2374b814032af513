//! Physical effects beyond the rigid body, one file per effect, one trait, one registry
//! (architecture.md, rule 3 and "Physical effects: the catalogue").
//!
//! Every effect has a stable [`Effect::name`] (used on the command line, in drive files and in
//! reports), named parameters with unit and bounds ([`ParamSpec`]) and its current values. A
//! joint-side torque effect ([`Stage::Torque`]) adds [`Effect::add_torque`] and, where the
//! torque is linear in the parameters, a regressor `Y(q, q̇, q̈)` with `τ_effect = Y · θ`
//! ([`Effect::regressor`], the shape identification builds on; cf. pinocchio
//! `algorithm/regressor.hpp`). The electrical and supply effects ([`Stage::Motor`],
//! [`Stage::Supply`]) act after the torque is known and are evaluated by the motor model
//! (seed 001, eqs. 2–4) from their values.
//!
//! **Adding an effect** = one file here implementing [`Effect`] with a `build` function, plus
//! one line in [`registry::REGISTRY`] (an effect defined outside the crate: one call of
//! [`register`]). The file also states the drive-file keys it reads ([`BuildContext`]) and
//! writes when `identify` writes a calibrated robot ([`Effect::write_drive_keys`],
//! [`Effect::effects_keys`]), and what it draws in the placement's uncertainty study
//! ([`Effect::uncertainty`], [`Effect::draw`]). [`EffectSet::of_robot`] builds every registered effect
//! from the robot's drive file (`[[joints]]`, `[effects]`, `[effects.values]`); energy
//! ([`crate::energy`]), identification, diagnosis and comparison ([`crate::identify`]) all walk
//! that set, so they see the same effects with the same parameters. The robot description
//! ([`crate::robot`]) carries the drive file's tables as data and does not know the effects.

mod armature;
mod balancer;
mod config;
mod coulomb;
mod electrical;
mod offset;
mod payload;
pub(crate) mod plausible;
pub(crate) mod registry;
mod rigid_body;
mod stribeck;
mod uncertain;
mod viscous;

pub use armature::Armature;
pub use balancer::{Balancer, BALANCER_A_M, BALANCER_B_M, BALANCER_UPRIGHT_RAD};
pub(crate) use config::MotorTerms;
pub use config::{BuildContext, EffectSet, EnergyOptions, DEFAULT_EFFECTS};
pub use coulomb::{Coulomb, COULOMB_VELOCITY_SCALE_RAD_S};
pub use electrical::{Copper, GearEfficiency, Regeneration, Standby};
pub use offset::Offset;
pub use payload::Payload;
pub use registry::{
    catalogue, catalogue_index, register, registrations, EffectId, Registration, REGISTRY,
};
pub use rigid_body::RigidBody;
pub use stribeck::{Stribeck, STRIBECK_VELOCITY_RAD_S};
pub use uncertain::{DrawPhase, Drawing, Uncertainty};
pub use viscous::Viscous;

pub use crate::robot::drive::{
    CalibratedParam, Calibration, CalibrationRound, DriveKept, DriveKeysMut,
};

/// The same trait as [`Effect`] under its former name (torque effects implement
/// [`Effect::add_torque`] and [`Effect::regressor`]).
use crate::error::{Error, Result};
use crate::robot::RobotModel;

/// Where in the chain an effect acts. A motor or supply effect names the term of the motor
/// model it supplies, so the energy model takes each by its role, never by its name: a new
/// motor or supply term is a new variant the compiler makes every stage handle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Joint-side torque added to the rigid body (`τ = τ_rb + Σ τ_effect`).
    Torque,
    /// A term of each axis's motor model.
    Motor(MotorTerm),
    /// A term of the supply side.
    Supply(SupplyTerm),
}

impl Stage {
    /// The term a motor or supply stage supplies, in words ("the winding resistance").
    pub fn term(self) -> &'static str {
        match self {
            Stage::Torque => "a joint torque",
            Stage::Motor(MotorTerm::WindingResistance) => "the winding resistance",
            Stage::Motor(MotorTerm::GearEfficiency) => "the gear efficiency",
            Stage::Supply(SupplyTerm::Regeneration) => "the regeneration",
            Stage::Supply(SupplyTerm::Standby) => "the standby power",
        }
    }
}

/// The motor-model term a [`Stage::Motor`] effect supplies (one value per joint).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotorTerm {
    /// Winding resistance `R` (Ω): copper loss `R i²` with `i = τ_m / k_t`.
    WindingResistance,
    /// Gear efficiency `η` (1): loss in the gear, in the direction of the power flow.
    GearEfficiency,
}

/// The supply term a [`Stage::Supply`] effect supplies (one value).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SupplyTerm {
    /// Share `ρ` of braking power recovered.
    Regeneration,
    /// Standby power `P0` (W) drawn while the arm is on.
    Standby,
}

/// Which part of the energy breakdown a torque effect's power `τ_effect q̇` is booked to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnergyClass {
    /// Rigid body (inertial errors, armature, offset torques).
    RigidBody,
    /// Friction (dissipative).
    Friction,
    /// Balancer (a spring: stored and released).
    Balancer,
}

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

/// Access to the concrete type behind a `dyn Effect` (implemented for every type).
pub trait AsAny {
    /// `self` as [`std::any::Any`], for [`EffectSet::typed`].
    fn as_any(&self) -> &dyn std::any::Any;
}

impl<T: std::any::Any> AsAny for T {
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// What every effect has: a stable name and named, bounded parameters; torque effects also
/// their torque and (when linear) its regressor.
pub trait Effect: AsAny + Send + Sync + std::fmt::Debug {
    /// Stable short name from the catalogue ([`registry::REGISTRY`]).
    fn name(&self) -> &'static str;
    /// The parameters, in the order of [`Effect::values`] and of the regressor's columns.
    fn params(&self) -> Vec<ParamSpec>;
    /// Current parameter values (SI, units as in [`Effect::params`]).
    fn values(&self) -> Vec<f64>;
    /// Replace all parameter values. Error: wrong count, or a value outside its bounds.
    fn set_values(&mut self, values: &[f64]) -> Result<()>;
    /// A boxed copy.
    fn clone_box(&self) -> Box<dyn Effect>;

    /// Where it acts (default: joint-side torque).
    fn stage(&self) -> Stage {
        Stage::Torque
    }
    /// The energy-breakdown class of its torque (default: rigid body).
    fn energy_class(&self) -> EnergyClass {
        EnergyClass::RigidBody
    }
    /// Whether the energy model with `options` keeps this (enabled, not null) torque effect,
    /// for a robot with drive data (`has_drive`) or without: the energy option that switches
    /// it, and whether it needs drive data. Default: a friction effect
    /// ([`EnergyClass::Friction`]) follows [`EnergyOptions::friction`], any
    /// other is kept.
    fn in_energy_model(&self, options: &EnergyOptions, _has_drive: bool) -> bool {
        self.energy_class() != EnergyClass::Friction || options.friction
    }
    /// Add this effect's joint torque (N·m, N for prismatic joints) at state
    /// (`q` rad, `qd` rad/s, `qdd` rad/s², each of length `dof`) to `tau`. Default: nothing
    /// (effects after the torque).
    fn add_torque(&self, _q: &[f64], _qd: &[f64], _qdd: &[f64], _tau: &mut [f64]) {}
    /// Fill the regressor `Y` (row-major, `dof × params().len()`) with
    /// `τ_effect = Y · values()`, and return `true`; return `false` (leaving `y` untouched)
    /// if the effect is not linear in its parameters (default).
    fn regressor(&self, _q: &[f64], _qd: &[f64], _qdd: &[f64], _y: &mut [f64]) -> bool {
        false
    }
    /// Whether evaluating it costs inverse-dynamics passes (`payload`, `rigid_body`):
    /// identification then caches its regressor once per log. Default `false`.
    fn costly(&self) -> bool {
        false
    }
    /// Whether its per-joint parameters (named `…[j]`) act only while joint `j` moves
    /// (friction, armature): a log in which that joint stands still leaves them unidentified,
    /// and identification holds them at their values. Default `false`.
    fn needs_joint_motion(&self) -> bool {
        false
    }
    /// Whether it contributes nothing with its current values (skipped by the energy model).
    fn is_null(&self) -> bool {
        false
    }
    /// For effects that are errors of the robot's own inertial parameters (`payload`,
    /// `rigid_body`): apply them to `robot` (exactly, RNEA is linear in the inertial
    /// parameters) and return `true`; the energy model then evaluates the corrected rigid
    /// body instead of calling [`Effect::add_torque`] per sample. Default `false`.
    fn fold_into(&self, _robot: &mut RobotModel) -> bool {
        false
    }
    /// Why this effect is not physically plausible for the robot it was built for (e.g. a
    /// `balancer` on a robot whose drive file declares none), or `None`.
    fn implausible(&self) -> Option<String> {
        None
    }
    /// Why the effect's *current (fitted) values* are not physically plausible for the robot
    /// (e.g. a `rigid_body` fit that gives a link a negative mass), given the standard error
    /// of each value (`None`: not identifiable); `None` when plausible. Default: the same as
    /// [`Effect::implausible`] (the robot, not the values, decides).
    fn implausible_fit(&self, _std_errors: &[Option<f64>]) -> Option<String> {
        self.implausible()
    }
    /// Whether a velocity- or acceleration-driven per-joint parameter (which a joint that does
    /// not move cannot excite); default `false`.
    fn driven_by_motion(&self) -> bool {
        false
    }
    /// What it draws in the placement's uncertainty study, or `None` (default: nothing).
    fn uncertainty(&self) -> Option<Uncertainty> {
        None
    }
    /// Draw its numbers of the robot in `d` (`joint`: the joint, 0-based, in
    /// [`DrawPhase::Joint`]; `None` in the other phases), recording each drawn value. Default:
    /// nothing.
    fn draw(&self, _d: &mut Drawing<'_>, _joint: Option<usize>) {}
    /// Write its current values into the drive keys it owns (`identify` writing a calibrated
    /// drive file with per-joint drive tables) and say where the file then keeps them.
    /// Default: no drive key, the values go to `[effects.values]`.
    fn write_drive_keys(&self, _keys: &mut DriveKeysMut<'_>) -> Result<DriveKept> {
        Ok(DriveKept::Values)
    }
    /// The `[effects]` keys it is built from that its values in `[effects.values]` replace
    /// (cleared when `identify` writes them there). Default: none.
    fn effects_keys(&self) -> &'static [&'static str] {
        &[]
    }
}

impl Clone for Box<dyn Effect> {
    fn clone(&self) -> Self {
        self.clone_box()
    }
}

/// Check a new parameter vector of effect `effect` against its specs (count and bounds), for
/// [`Effect::set_values`].
pub fn check_values(effect: &str, specs: &[ParamSpec], values: &[f64]) -> Result<()> {
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

/// Per-joint parameter specs `prefix[1..=n]`, bounds `[0, ∞)`.
pub(crate) fn per_joint(prefix: &str, unit: &'static str, n: usize) -> Vec<ParamSpec> {
    per_joint_bounded(prefix, unit, n, 0.0, f64::INFINITY)
}

/// Per-joint parameter specs `prefix[1..=n]` with bounds.
pub(crate) fn per_joint_bounded(
    prefix: &str,
    unit: &'static str,
    n: usize,
    lower: f64,
    upper: f64,
) -> Vec<ParamSpec> {
    (0..n)
        .map(|j| ParamSpec {
            name: format!("{prefix}[{}]", j + 1),
            unit,
            lower,
            upper,
        })
        .collect()
}

/// Diagonal per-joint regressor: `y[j, j] = f(j)`, zeros elsewhere (`dof × p`, `p` columns).
pub(crate) fn diagonal_regressor(p: usize, y: &mut [f64], f: impl Fn(usize) -> f64) {
    y.iter_mut().for_each(|v| *v = 0.0);
    for j in 0..p {
        if let Some(c) = y.get_mut(j * p + j) {
            *c = f(j);
        }
    }
}
