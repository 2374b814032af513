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
//! one line in [`registry::REGISTRY`]. [`EffectSet::of_robot`] builds every registered effect
//! from the robot's drive file (`[[joints]]`, `[effects]`, `[effects.values]`); energy
//! ([`crate::energy`]), identification, diagnosis and comparison ([`crate::identify`]) all walk
//! that set, so they see the same effects with the same parameters. The robot description
//! ([`crate::robot`]) carries the drive file's tables as data and does not know the effects.

mod armature;
mod balancer;
mod config;
mod coulomb;
mod electrical;
pub mod lanes;
mod offset;
mod payload;
pub mod registry;
mod rigid_body;
mod stribeck;
mod viscous;

pub use armature::Armature;
pub use balancer::{
    declared_in as balancer_declared_in, Balancer, BALANCER_A_M, BALANCER_B_M, BALANCER_UPRIGHT_RAD,
};
pub use config::{BuildContext, CalibratedDrive, EffectSet, DEFAULT_EFFECTS};
pub use coulomb::{Coulomb, COULOMB_VELOCITY_SCALE_RAD_S};
pub use electrical::{Copper, GearEfficiency, Regeneration, Standby};
pub use lanes::{on_level, LaneState, Lanes};
pub use offset::Offset;
pub use payload::Payload;
pub use registry::{catalogue, catalogue_index, EffectId, EffectRegistry, Registration, REGISTRY};
pub use rigid_body::RigidBody;
pub use stribeck::{Stribeck, STRIBECK_VELOCITY_RAD_S};
pub use viscous::Viscous;

pub use crate::robot::drive::{CalibratedParam, Calibration, CalibrationRound};

/// The same trait as [`Effect`] under its former name (torque effects implement
/// [`Effect::add_torque`] and [`Effect::regressor`]).
pub use self::Effect as TorqueEffect;

use crate::error::{Error, Result};
use crate::robot::RobotModel;

/// Where in the chain an effect acts, and what it sets there.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stage {
    /// Joint-side torque added to the rigid body (`τ = τ_rb + Σ τ_effect`).
    Torque,
    /// A term of each axis's motor model (values: one per axis).
    Motor(MotorTerm),
    /// A term of the supply (values: one).
    Supply(SupplyTerm),
}

/// The terms of the motor model an effect of [`Stage::Motor`] sets (one effect each).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MotorTerm {
    /// Winding resistance `R` per axis, Ω: copper loss `R i²` (`copper`).
    WindingResistance,
    /// Gearbox efficiency `η` per axis (`gear_efficiency`).
    GearEfficiency,
}

/// The terms of the supply an effect of [`Stage::Supply`] sets.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SupplyTerm {
    /// The recovered fraction `ρ` of what the regeneration policy burns (`regeneration`;
    /// one effect).
    RecoveredFraction,
    /// A constant draw `P`, W, added to the supply (`standby`; any number of effects, each
    /// its own line `<line>_j = P × duration` of the energy breakdown).
    ConstantPower,
}

impl Stage {
    /// Whether at most one effect may act in this stage (a term of the motor model, the
    /// recovered fraction); torque effects and constant draws add up.
    pub fn is_single(self) -> bool {
        !matches!(
            self,
            Stage::Torque | Stage::Supply(SupplyTerm::ConstantPower)
        )
    }
}

/// How an effect's energy is reported: which line of the energy breakdown
/// ([`crate::energy::EnergyReport`]) it is booked to, `<line>_j` in the JSON.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnergyClass {
    /// A torque effect's power `τ_effect q̇` booked with the rigid body (`rigid_body`:
    /// inertial errors, armature, offset torques).
    RigidBody,
    /// A torque effect's power booked as friction (`friction`, dissipative).
    Friction,
    /// A torque effect's power booked to the balancer (`balancer`: a spring, stored and
    /// released).
    Balancer,
    /// A motor or supply effect's own line of the breakdown, named here (`copper`, `gear`,
    /// `regeneration_lost`, `standby`, or a new effect's name).
    Line(&'static str),
}

impl EnergyClass {
    /// The breakdown line it is booked to (`rigid_body`, `friction`, `balancer` or its own).
    pub fn line(self) -> &'static str {
        match self {
            EnergyClass::RigidBody => "rigid_body",
            EnergyClass::Friction => "friction",
            EnergyClass::Balancer => "balancer",
            EnergyClass::Line(l) => l,
        }
    }
}

/// A range of an effect's estimated parameters, drawn by the placement's uncertainty study
/// ([`crate::search::uncertainty`]): the drive file's `[uncertainty] <key>` (a half-width of a
/// uniform range, relative), else `default`. A draw multiplies each of `params` (indices into
/// [`Effect::params`]) by `1 + r u`, one `u` uniform in [−1, 1] for the range, and the drawn
/// robot carries them in `[effects.values]`.
#[derive(Clone, Debug, PartialEq)]
pub struct UncertaintyRange {
    /// The `[uncertainty]` key, e.g. `nozzle_heater_rel`.
    pub key: &'static str,
    /// Half-width when the drive file gives none (dimensionless).
    pub default: f64,
    /// The parameters it scales.
    pub params: Vec<usize>,
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
    /// How its energy is reported (default: a torque booked with the rigid body).
    fn energy_class(&self) -> EnergyClass {
        EnergyClass::RigidBody
    }
    /// Add this effect's joint torque (N·m, N for prismatic joints) at state
    /// (`q` rad, `qd` rad/s, `qdd` rad/s², each of length `dof`) to `tau`. Default: nothing
    /// (effects after the torque).
    fn add_torque(&self, _q: &[f64], _qd: &[f64], _qdd: &[f64], _tau: &mut [f64]) {}
    /// [`Effect::add_torque`] of [`crate::simd::LANES`] samples at once ([`lanes`]): added to
    /// `tau` (N·m, joint-major `tau[j][lane]`), every lane bit-identical to
    /// [`Effect::add_torque`] of its sample; `level` is the instruction set the caller runs
    /// on (an override compiles its loops for it with [`on_level`]). Default: [`Effect::add_torque`]
    /// sample by sample.
    fn add_torque_lanes(&self, x: &LaneState<'_>, tau: &mut [Lanes], level: crate::simd::Level) {
        let _ = level;
        lanes::add_torque_per_lane(self, x, tau)
    }
    /// Mark in `read` (one flag a joint) the joints whose angles
    /// [`Effect::add_torque_lanes`] reads (only those are put into lanes). Default: every
    /// joint.
    fn angles_read(&self, read: &mut [bool]) {
        read.fill(true)
    }
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
    /// Write its current (identified) values into the calibrated drive file `w`, switched on
    /// or off by `enabled`. Default: [`CalibratedDrive::write_values`] (an enabled effect's
    /// values in `[effects.values]`, which wins over its own keys; a disabled effect's
    /// removed). Effects with drive keys write those.
    fn write_calibrated(&self, enabled: bool, w: &mut CalibratedDrive<'_>) -> Result<()> {
        w.write_values(self.name(), self.values(), enabled);
        Ok(())
    }
    /// Whether it is switched on when the drive file's `[effects]` names no `enabled` list
    /// (`has_drive`: the robot has drive data). Default: the catalogue's [`DEFAULT_EFFECTS`]
    /// when the robot has drive data.
    fn on_by_default(&self, has_drive: bool) -> bool {
        has_drive && DEFAULT_EFFECTS.contains(&self.name())
    }
    /// The ranges the uncertainty study draws its parameters from ([`UncertaintyRange`]).
    /// Default: none. The catalogue's drive-data effects (friction, motor constants, standby,
    /// payload, balancer) are drawn by the study itself on the robot's drive data, in a fixed
    /// order that makes every study's draw stream ([`crate::search::uncertainty::Ranges`]).
    fn uncertainty(&self) -> Vec<UncertaintyRange> {
        Vec::new()
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
}

impl Clone for Box<dyn Effect> {
    fn clone(&self) -> Self {
        self.clone_box()
    }
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
