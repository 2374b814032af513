//! Energy of a timed joint trajectory: torques → power → energy, per joint and per effect.
//!
//! Per sample (all joint-side quantities unless marked):
//! - rigid-body torque `τ_rb = rne(q, q̇, q̈)` (seed 000, eq. 5) with the payload, and the
//!   armature `G²J_m q̈` when the robot has a drive;
//! - friction `τ_f = f_v q̇ + f_c tanh(q̇/ε) + f_s exp(−(q̇/v_s)²) tanh(q̇/ε)` (seed 000, eq. 2,
//!   smoothed, plus the Stribeck term; [`crate::effects`]);
//! - the axis-2 balancer's torque `τ_b` ([`crate::effects::Balancer`]);
//! - joint torque `τ = τ_rb + τ_f + τ_b`, mechanical power `P_j = τ_j q̇_j` (seed 000, eq. 6);
//! - motor model (seed 001, eqs. 2–4): motor torque `τ_m = τ/(G η)` when driving
//!   (`τ q̇ ≥ 0`) and `τ η / G` when back-driven, current `i = τ_m / K_t`, motor speed
//!   `ω_m = G q̇`, voltage `u = R i + K_t ω_m` (K_v = K_t in SI), electrical power `P_el = u i`
//!   `= τ q̇ + (gear loss) + R i²`;
//! - supply by the regeneration policy: `none`/`per_axis` Σ max(P_el,j, 0); `dc_bus`
//!   max(Σ P_el,j, 0); `grid` Σ P_el,j; of the power the policy burns, the fraction `ρ`
//!   (`regeneration` effect) is recovered: `P_drives − ρ (P_drives − Σ P_el)`; plus the
//!   cabinet's standby power.
//!
//! Which effects are in, and their parameters, come from the one effect registry
//! ([`crate::effects::EffectSet::of_robot`]: drive data, the drive file's `[effects]` table
//! and `[effects.values]`), the same set [`crate::identify::Model`] walks; the torque and
//! power formulas are the same code ([`motor`], [`supply_power`], the effects'
//! `add_torque`), so energy torques equal identification's predictions. Effects that are
//! errors of the robot's own inertial parameters (`payload`, `rigid_body`) are folded into the
//! rigid body once ([`crate::effects::Effect::fold_into`]); every other enabled torque effect
//! is added per sample and booked to friction, balancer or rigid body by its
//! [`crate::effects::EnergyClass`].
//!
//! Energies are trapezoidal integrals `E = ∫ P dt` (seed 000, eq. 7). The breakdown closes:
//! `E_supply = E_rigid_body + E_balancer + E_friction + E_gear + E_copper
//! + E_regeneration_lost + E_standby`.
//!
//! Without drive data the model is the rigid body only (payload, no armature, no friction):
//! electrical power is taken equal to mechanical power, negative power is lost per axis
//! (policy `none`), and [`EnergyReport::model`] says so.
//!
//! For placement sweeps, [`eval_sample`] evaluates one sample without allocating.

mod lanes;
mod report;

pub use lanes::{
    eval_lanes_with_sincos, eval_rows, eval_rows_summed, EnergySums, LaneInputs, PowerLanes, Rows,
};
pub use report::{EffectEnergy, EnergyReport, JointEnergy, SampleSeries, TotalEnergy};

use crate::dynamics::{rnea, rnea_with_sincos, DynData, DynModel, DynOptions, MAX_DOF};
use crate::effects::{
    Effect, EffectSet, EnergyClass, MotorTerm, Stage, SupplyTerm, COULOMB_VELOCITY_SCALE_RAD_S,
};
use crate::error::{Error, Result};
use crate::robot::{Regeneration, RobotModel};
use crate::simd::{Level, LANES};
use crate::trajectory::{JointTrajectory, RateBlocks};
use std::sync::Arc;

/// Choices for [`EnergyModel::with_options`] (they live beside the effects they switch).
pub use crate::effects::EnergyOptions;

/// Motor and gearbox constants of one axis, copied into fixed arrays for the hot loop.
#[derive(Clone, Copy, Debug, Default)]
struct Axis {
    gear: f64,
    kt: f64,
    r: f64,
    eta: f64,
}

/// Immutable energy model of a robot: rigid body + torque effects + motor model + cabinet.
#[derive(Clone, Debug)]
pub struct EnergyModel {
    dynamics: DynModel,
    n: usize,
    has_drive: bool,
    axes: [Axis; MAX_DOF],
    /// Enabled, non-null torque effects added per sample, with their energy class.
    torque: Vec<(Arc<dyn Effect>, EnergyClass)>,
    /// The same effects in the form the lockstep pass evaluates ([`lanes`]).
    lane_effects: Vec<(lanes::LaneEffect, EnergyClass)>,
    /// The joints whose angles (not only their sines) the lockstep effects read.
    lane_angles: [bool; MAX_DOF],
    /// Names of the effects in the model (folded or per sample), for the description.
    in_model: Vec<String>,
    /// Every effect acting in the model and where its energy is booked, in catalogue order.
    booked: Vec<(String, Booked)>,
    calibration: Option<String>,
    regeneration: Regeneration,
    recovered_fraction: f64,
    standby_w: f64,
    joint_names: Vec<String>,
    robot_name: String,
    options: EnergyOptions,
}

/// Everything computed for one sample. Arrays have [`MAX_DOF`] entries; the first `dof` are
/// meaningful. Units: N·m for torques, W for powers, A for current, V for voltage.
#[derive(Clone, Copy, Debug, Default)]
pub struct SamplePower {
    /// Rigid-body torque incl. payload, armature and the other rigid-body-class effects
    /// (`offset`, `rigid_body`), N·m.
    pub tau_rb: [f64; MAX_DOF],
    /// Friction torque (the friction-class effects: viscous, Coulomb, Stribeck), N·m.
    pub tau_friction: [f64; MAX_DOF],
    /// Balancer torque (0 when the `balancer` effect is off), N·m.
    pub tau_balancer: [f64; MAX_DOF],
    /// Joint torque `τ_rb + τ_f + τ_b`, N·m.
    pub tau: [f64; MAX_DOF],
    /// Mechanical power at the joint `τ q̇` (seed 000, eq. 6), W.
    pub p_mech: [f64; MAX_DOF],
    /// Rigid-body part `τ_rb q̇`, W.
    pub p_rigid_body: [f64; MAX_DOF],
    /// Balancer power `τ_b q̇` (stored in / released by the spring), W.
    pub p_balancer: [f64; MAX_DOF],
    /// Friction loss `τ_f q̇` (≥ 0), W.
    pub p_friction: [f64; MAX_DOF],
    /// Gearbox loss `τ_m ω_m − τ q̇` (≥ 0), W.
    pub p_gear: [f64; MAX_DOF],
    /// Copper loss `R i²`, W.
    pub p_copper: [f64; MAX_DOF],
    /// Electrical power `u i` (seed 001, eq. 4), W; negative when regenerating.
    pub p_el: [f64; MAX_DOF],
    /// Motor current `i = τ_m/K_t`, A (0 without drive).
    pub current: [f64; MAX_DOF],
    /// Motor voltage `u = R i + K_t ω_m`, V (0 without drive).
    pub voltage: [f64; MAX_DOF],
    /// Power drawn by the drives after the regeneration policy, W.
    pub p_drives: f64,
    /// Power returned by the axes but burnt (`p_drives − Σ p_el` ≥ 0, after the recovered
    /// fraction ρ), W.
    pub p_regeneration_lost: f64,
    /// Supply power: `p_drives + standby`, W.
    pub p_supply: f64,
}

impl EnergyModel {
    /// The model with default options (payload, armature, friction when a drive exists).
    pub fn new(robot: &RobotModel) -> Result<Self> {
        Self::with_options(robot, EnergyOptions::default())
    }

    /// The model with explicit options. Errors: as [`DynModel::new`]; an invalid Coulomb
    /// velocity scale; a drive whose joint count differs from the robot's.
    pub fn with_options(robot: &RobotModel, options: EnergyOptions) -> Result<Self> {
        Self::with_effects(robot, options, EffectSet::of_robot(robot)?)
    }

    /// The model with explicit options and effects (the robot's own are
    /// [`EffectSet::of_robot`]): each enabled effect acts at its [`Stage`], a motor or supply
    /// effect by the term it names, so an effect defined outside printwatt enters like a
    /// registered one. Errors: as [`EnergyModel::with_options`].
    pub fn with_effects(
        robot: &RobotModel,
        options: EnergyOptions,
        mut set: EffectSet,
    ) -> Result<Self> {
        let n = robot.dof();
        let has_drive = robot.drive.is_some();
        set_coulomb_scale(&options, &mut set)?;
        let mut dyn_robot = robot.clone();
        if !options.payload {
            dyn_robot.payload = None;
        }
        let staged = Staged::of(&set, &options, has_drive, &mut dyn_robot)?;
        let dynamics = DynModel::new(
            &dyn_robot,
            DynOptions {
                payload: options.payload,
                armature: false,
            },
        )?;
        let (axes, mut regeneration, standby_w) = drive_axes(robot, &staged)?;
        if let Some(r) = options.regeneration {
            regeneration = r;
        }
        let torque = staged.torque;
        let lane_effects: Vec<_> = torque
            .iter()
            .map(|(e, c)| (lanes::LaneEffect::of(e, n), *c))
            .collect();
        let lane_angles = lanes::angles_read(&lane_effects, n);
        Ok(EnergyModel {
            dynamics,
            n,
            has_drive,
            axes,
            torque,
            lane_effects,
            lane_angles,
            in_model: staged.in_model,
            booked: staged.booked,
            regeneration,
            recovered_fraction: if has_drive { staged.rho } else { 0.0 },
            standby_w,
            joint_names: robot.joints.iter().map(|j| j.name.clone()).collect(),
            robot_name: robot.name().to_string(),
            calibration: robot.effects.calibration_summary(),
            options,
        })
    }

    /// Number of joints.
    pub fn dof(&self) -> usize {
        self.n
    }

    /// Whether drive data (motor model, friction, cabinet) are present.
    pub fn has_drive(&self) -> bool {
        self.has_drive
    }

    /// The rigid-body model used.
    pub fn dynamics(&self) -> &DynModel {
        &self.dynamics
    }

    /// Regeneration policy in force.
    pub fn regeneration(&self) -> Regeneration {
        self.regeneration
    }

    /// Standby power, W.
    pub fn standby_power(&self) -> f64 {
        self.standby_w
    }

    /// Options the model was built with.
    pub fn options(&self) -> EnergyOptions {
        self.options
    }

    /// A fresh workspace.
    pub fn data(&self) -> DynData {
        self.dynamics.data()
    }

    /// One line describing what the model contains.
    pub fn description(&self) -> String {
        let effects = if self.in_model.is_empty() {
            String::new()
        } else {
            format!(" + effects: {}", self.in_model.join(", "))
        };
        let desc = if self.has_drive {
            let regen = if self.recovered_fraction != 0.0 {
                format!(
                    "`{}` (recovered fraction {})",
                    self.regeneration.name(),
                    self.recovered_fraction
                )
            } else {
                format!("`{}`", self.regeneration.name())
            };
            let motor = match (
                self.axes[..self.n].iter().any(|a| a.r != 0.0),
                self.axes[..self.n].iter().any(|a| a.eta != 1.0),
            ) {
                (true, true) => "copper, gear efficiency",
                (true, false) => "copper",
                (false, true) => "gear efficiency",
                (false, false) => "lossless",
            };
            format!(
                "rigid body{}{effects} + motor model ({motor}) + regeneration {regen} + standby {} W",
                if self.options.payload { " + payload" } else { "" },
                self.standby_w
            )
        } else {
            format!(
                "rigid body only{}{effects} (no drive data): electrical power = mechanical power, \
                 negative power lost per axis; no copper or standby",
                if self.options.payload {
                    " + payload"
                } else {
                    ""
                }
            )
        };
        match &self.calibration {
            Some(c) => format!("{desc}; {c}"),
            None => desc,
        }
    }
}

/// The Coulomb velocity scale of `options` into the Coulomb effect of `set` (when enabled and
/// not the default). Errors: a scale that is not a positive number.
fn set_coulomb_scale(options: &EnergyOptions, set: &mut EffectSet) -> Result<()> {
    if !(options.coulomb_velocity_scale.is_finite() && options.coulomb_velocity_scale > 0.0) {
        return Err(Error::Invalid(format!(
            "coulomb velocity scale must be > 0 rad/s, got {}",
            options.coulomb_velocity_scale
        )));
    }
    if options.coulomb_velocity_scale != COULOMB_VELOCITY_SCALE_RAD_S && set.is_enabled("coulomb") {
        let c = set.get_mut("coulomb")?;
        let mut v = c.values();
        if let Some(last) = v.last_mut() {
            *last = options.coulomb_velocity_scale;
        }
        c.set_values(&v)?;
    }
    Ok(())
}

/// Where the energy of an effect acting in the model is booked.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Booked {
    /// A joint torque evaluated per sample: its index in [`EnergyModel`]'s torque effects and
    /// its class.
    Torque(usize, EnergyClass),
    /// A joint torque folded into the rigid-body model (the payload).
    Folded,
    /// A motor or supply term.
    Term(Stage),
}

impl Booked {
    /// The part of [`TotalEnergy`] the energy is booked to (the field's name without `_j`).
    fn part(self) -> &'static str {
        match self {
            Booked::Torque(_, EnergyClass::RigidBody) | Booked::Folded => "rigid_body",
            Booked::Torque(_, EnergyClass::Friction) => "friction",
            Booked::Torque(_, EnergyClass::Balancer) => "balancer",
            Booked::Term(Stage::Motor(MotorTerm::WindingResistance)) => "copper",
            Booked::Term(Stage::Motor(MotorTerm::GearEfficiency)) => "gear",
            Booked::Term(Stage::Supply(SupplyTerm::Regeneration)) => "regeneration_lost",
            Booked::Term(Stage::Supply(SupplyTerm::Standby)) => "standby",
            Booked::Term(Stage::Torque) => unreachable!("a torque effect is booked by class"),
        }
    }
}

/// The enabled effects sorted by the stage they act at.
struct Staged {
    /// Torque effects that do not fold into the rigid body, with their energy class.
    torque: Vec<(Arc<dyn Effect>, EnergyClass)>,
    /// Names of the torque effects in the model.
    in_model: Vec<String>,
    /// Every effect acting in the model and where its energy is booked.
    booked: Vec<(String, Booked)>,
    /// Motor terms: winding resistance and gear efficiency per joint.
    motor: [Option<Vec<f64>>; 2],
    /// Recovered fraction of regenerated power.
    rho: f64,
    /// Standby power, W.
    p0: f64,
}

impl Staged {
    /// The enabled effects of `set` that `options` keeps, by stage; torque effects that fold
    /// into the rigid body go into `dyn_robot`. Error: two enabled effects supply the same
    /// motor or supply term.
    fn of(
        set: &EffectSet,
        options: &EnergyOptions,
        has_drive: bool,
        dyn_robot: &mut RobotModel,
    ) -> Result<Staged> {
        let mut staged = Staged {
            torque: Vec::new(),
            in_model: Vec::new(),
            booked: Vec::new(),
            motor: [None, None],
            rho: 0.0,
            p0: 0.0,
        };
        let terms = set.motor_terms()?;
        staged.motor = [terms.winding_resistance, terms.gear_efficiency];
        staged.rho = terms.regeneration.unwrap_or(0.0);
        staged.p0 = terms.standby_w.unwrap_or(0.0);
        for (e, on) in set.iter() {
            if !on {
                continue;
            }
            let stage = e.stage();
            if stage != Stage::Torque {
                if has_drive {
                    staged
                        .booked
                        .push((e.name().to_string(), Booked::Term(stage)));
                }
                continue;
            }
            let class = e.energy_class();
            if e.is_null() || !e.in_energy_model(options, has_drive) {
                continue;
            }
            staged.in_model.push(e.name().to_string());
            let booked = if e.fold_into(dyn_robot) {
                Booked::Folded
            } else {
                staged.torque.push((Arc::from(e.clone_box()), class));
                Booked::Torque(staged.torque.len() - 1, class)
            };
            staged.booked.push((e.name().to_string(), booked));
        }
        Ok(staged)
    }
}

/// Each axis's gear, torque constant and motor terms, the regeneration and the standby power
/// of the robot's drive (none without one). Errors: a drive whose joint count differs from
/// the robot's.
fn drive_axes(robot: &RobotModel, staged: &Staged) -> Result<([Axis; MAX_DOF], Regeneration, f64)> {
    let motor = &staged.motor;
    let mut axes = [Axis::default(); MAX_DOF];
    let mut regeneration = Regeneration::None;
    let mut standby_w = 0.0;
    if let Some(d) = &robot.drive {
        robot.check_len("drive joints", d.joints.len())?;
        for (j, (a, jd)) in axes.iter_mut().zip(&d.joints).enumerate() {
            *a = Axis {
                gear: jd.gear_ratio,
                kt: jd.torque_constant,
                r: motor[0].as_ref().map_or(0.0, |v| v[j]),
                eta: motor[1].as_ref().map_or(1.0, |v| v[j]),
            };
        }
        regeneration = d.regeneration;
        standby_w = staged.p0;
    }
    Ok((axes, regeneration, standby_w))
}

/// One axis of the motor model at joint torque `tau` (N·m) and velocity `v` (rad/s), see
/// [`motor`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MotorPoint {
    /// Motor torque `τ_m`, N·m (motor side).
    pub torque: f64,
    /// Current `i = τ_m/K_t`, A.
    pub current: f64,
    /// Voltage `u = R i + K_t G q̇`, V.
    pub voltage: f64,
    /// Shaft power `τ_m G q̇`, W.
    pub shaft: f64,
    /// Copper loss `R i²`, W.
    pub copper: f64,
    /// Electrical power `shaft + copper` (`= u i`), W.
    pub p_el: f64,
}

/// The motor model of one axis (seed 001, eqs. 2–4): `τ_m = τ/(G η)` when driving
/// (`τ q̇ ≥ 0`) else `τ η/G`; `i = τ_m/K_t`; `P_el = τ_m G q̇ + R i²`. Shared by
/// [`eval_sample`] and [`crate::identify::Model::signal_from_torque`].
#[inline]
pub fn motor(tau: f64, v: f64, gear: f64, eta: f64, kt: f64, r: f64) -> MotorPoint {
    let tm = if tau * v >= 0.0 {
        tau / (gear * eta)
    } else {
        tau * eta / gear
    };
    let wm = gear * v;
    let i = tm / kt;
    let shaft = tm * wm;
    let copper = r * i * i;
    MotorPoint {
        torque: tm,
        current: i,
        voltage: r * i + kt * wm,
        shaft,
        copper,
        p_el: shaft + copper,
    }
}

/// Supply-side powers of one sample, W; see [`supply_power`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct SupplyPoint {
    /// Drawn by the drives after the policy and the recovered fraction.
    pub drives: f64,
    /// Returned by the axes and burnt (`drives − Σ P_el`).
    pub lost: f64,
    /// `drives + P_0`.
    pub supply: f64,
}

/// Supply power from per-axis electrical powers `p_el` (W): the policy's draw
/// ([`drives_power`]) less the recovered fraction `rho` of what it burns, plus standby `p0`:
/// `P_drives − ρ (P_drives − Σ P_el) + P_0`. Shared by [`eval_sample`] and
/// [`crate::identify::Model::signal_from_torque`].
#[inline]
pub(crate) fn supply_power(policy: Regeneration, p_el: &[f64], rho: f64, p0: f64) -> SupplyPoint {
    let sum: f64 = p_el.iter().sum();
    let policy_draw = drives_power(policy, p_el);
    let drives = policy_draw - rho * (policy_draw - sum);
    SupplyPoint {
        drives,
        lost: drives - sum,
        supply: drives + p0,
    }
}

/// Supply power of the drives under a regeneration policy, W, from per-axis electrical powers.
#[inline]
pub(crate) fn drives_power(policy: Regeneration, p_el: &[f64]) -> f64 {
    match policy {
        Regeneration::None | Regeneration::PerAxis => p_el.iter().map(|p| p.max(0.0)).sum(),
        Regeneration::DcBus => p_el.iter().sum::<f64>().max(0.0),
        Regeneration::Grid => p_el.iter().sum(),
    }
}

/// Evaluate one sample (`q` rad, `qd` rad/s, `qdd` rad/s², each of length `dof`) into `out`,
/// returning the supply power in W. No allocation; meant for placement sweeps' hot loops.
/// Equations: module docs. Error: [`Error::SizeMismatch`] on a wrong slice length.
pub fn eval_sample(
    model: &EnergyModel,
    data: &mut DynData,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    out: &mut SamplePower,
) -> Result<f64> {
    eval_sample_inner(model, data, q, None, qd, qdd, out)
}

/// [`eval_sample`] with the joints' sines and cosines already computed for `q` (see
/// [`crate::dynamics::rnea_with_sincos`]: the sines, then the cosines, length `2 dof`).
pub fn eval_sample_with_sincos(
    model: &EnergyModel,
    data: &mut DynData,
    q: &[f64],
    sincos: &[f64],
    qd: &[f64],
    qdd: &[f64],
    out: &mut SamplePower,
) -> Result<f64> {
    eval_sample_inner(model, data, q, Some(sincos), qd, qdd, out)
}

#[inline(always)]
#[allow(clippy::needless_range_loop)] // parallel fixed arrays indexed by joint
fn eval_sample_inner(
    model: &EnergyModel,
    data: &mut DynData,
    q: &[f64],
    sincos: Option<&[f64]>,
    qd: &[f64],
    qdd: &[f64],
    out: &mut SamplePower,
) -> Result<f64> {
    let n = model.n;
    match sincos {
        Some(sc) => rnea_with_sincos(&model.dynamics, data, q, sc, qd, qdd, &mut out.tau_rb[..n])?,
        None => rnea(&model.dynamics, data, q, qd, qdd, &mut out.tau_rb[..n])?,
    }
    Ok(finish_sample(model, q, qd, qdd, out))
}

impl EnergyModel {
    /// Whether [`eval_batch_with_sincos`] evaluates this model in lockstep (every joint
    /// revolute; see [`crate::dynamics::rnea_batch`]).
    pub fn batchable(&self) -> bool {
        self.dynamics.batchable()
    }
}

/// [`eval_sample_with_sincos`] of `count ≤` [`LANES`] samples at once: lane `l` is
/// `q(l)`, `sincos(l)`, `qd(l)`, `qdd(l)` (rad, -, rad/s, rad/s², as
/// [`eval_sample_with_sincos`] takes them) and its result goes to `out[l]` (the supply power,
/// W, in `out[l].p_supply`). The rigid-body torques of the batch run in lockstep on the
/// instruction set `level` ([`crate::dynamics::rnea_batch`]), and so do the torque effects,
/// the motor model and the supply ([`eval_lanes_with_sincos`]). Bit-identical to [`eval_sample_with_sincos`] of each
/// sample. With [`Level::Scalar`] or a model that is not [`EnergyModel::batchable`], each
/// sample goes through [`eval_sample_with_sincos`]. Error: [`Error::SizeMismatch`] on a wrong
/// slice length.
#[allow(clippy::too_many_arguments)]
pub fn eval_batch_with_sincos<'s>(
    model: &EnergyModel,
    data: &mut DynData,
    count: usize,
    q: impl Fn(usize) -> &'s [f64],
    sincos: impl Fn(usize) -> &'s [f64],
    qd: impl Fn(usize) -> &'s [f64],
    qdd: impl Fn(usize) -> &'s [f64],
    out: &mut [SamplePower; LANES],
    level: Level,
) -> Result<()> {
    let count = count.min(LANES);
    if level == Level::Scalar || !model.batchable() {
        for (l, o) in out.iter_mut().enumerate().take(count) {
            eval_sample_with_sincos(model, data, q(l), sincos(l), qd(l), qdd(l), o)?;
        }
        return Ok(());
    }
    let mut p = PowerLanes::default();
    eval_lanes_with_sincos(model, data, count, q, sincos, qd, qdd, &mut p, level)?;
    for (l, o) in out.iter_mut().enumerate().take(count) {
        *o = p.sample(l);
    }
    Ok(())
}

/// The rest of a sample once `out.tau_rb` holds the rigid-body torque: the torque effects,
/// the motor model, the supply. Returns the supply power, W.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // parallel fixed arrays indexed by joint
fn finish_sample(
    model: &EnergyModel,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    out: &mut SamplePower,
) -> f64 {
    let n = model.n;
    out.tau_balancer = [0.0; MAX_DOF];
    out.tau_friction = [0.0; MAX_DOF];
    for (e, class) in &model.torque {
        let dst = match class {
            EnergyClass::RigidBody => &mut out.tau_rb,
            EnergyClass::Friction => &mut out.tau_friction,
            EnergyClass::Balancer => &mut out.tau_balancer,
        };
        e.add_torque(q, qd, qdd, &mut dst[..n]);
    }
    power_sample(model, qd, out)
}

/// The powers of a sample once its torques are in `out` (rigid body, friction, balancer):
/// joint torque, mechanical power, the motor model, the supply. Returns the supply power, W.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // parallel fixed arrays indexed by joint
fn power_sample(model: &EnergyModel, qd: &[f64], out: &mut SamplePower) -> f64 {
    let n = model.n;
    for j in 0..n {
        let v = qd[j];
        let tf = out.tau_friction[j];
        let tb = out.tau_balancer[j];
        let tau = out.tau_rb[j] + tf + tb;
        out.tau_friction[j] = tf;
        out.tau[j] = tau;
        let pm = tau * v;
        out.p_mech[j] = pm;
        out.p_rigid_body[j] = out.tau_rb[j] * v;
        out.p_friction[j] = tf * v;
        out.p_balancer[j] = tb * v;
        if model.has_drive {
            let ax = &model.axes[j];
            let m = motor(tau, v, ax.gear, ax.eta, ax.kt, ax.r);
            out.current[j] = m.current;
            out.voltage[j] = m.voltage;
            out.p_copper[j] = m.copper;
            out.p_gear[j] = m.shaft - pm;
            out.p_el[j] = m.p_el;
        } else {
            out.current[j] = 0.0;
            out.voltage[j] = 0.0;
            out.p_copper[j] = 0.0;
            out.p_gear[j] = 0.0;
            out.p_el[j] = pm;
        }
    }
    let sp = supply_power(
        model.regeneration,
        &out.p_el[..n],
        model.recovered_fraction,
        model.standby_w,
    );
    out.p_drives = sp.drives;
    out.p_regeneration_lost = sp.lost;
    out.p_supply = sp.supply;
    out.p_supply
}

impl EnergyModel {
    /// The names of the joints the model covers, in chain order.
    pub fn joint_names(&self) -> &[String] {
        &self.joint_names
    }
}

/// Evaluate a whole trajectory (velocities and accelerations must be filled; see
/// [`crate::dynamics::fill_derivatives`]) into an [`EnergyReport`] with per-joint and total
/// energies (trapezoidal, seed 000 eq. 7), peaks, RMS torques and the per-sample series.
///
/// Errors: a joint count different from the model's; a trajectory with missing `qd`/`qdd`
/// or non-increasing times (via [`JointTrajectory::validate`]).
pub fn evaluate(model: &EnergyModel, traj: &JointTrajectory) -> Result<EnergyReport> {
    let n = model.n;
    let len = traj.len();
    let mut series = SampleSeries::with_capacity(n, len.min(traj.q.len() / n.max(1)));
    let mut report = evaluate_streaming(model, traj, &mut |k, s| {
        series.t.push(traj.t[k]);
        series.tau.extend_from_slice(&s.tau[..n]);
        series.p_mech.extend_from_slice(&s.p_mech[..n]);
        series.p_el.extend_from_slice(&s.p_el[..n]);
        series.current.extend_from_slice(&s.current[..n]);
        series.p_supply.push(s.p_supply);
    })?;
    report.series = series;
    Ok(report)
}

/// [`evaluate`] without the per-sample series: every figure of the report integrated sample by
/// sample as the samples are evaluated (the same sums in the same order, so the same bits),
/// each sample's powers handed to `on_sample(k, powers)` and then dropped. The report's
/// `series` is left empty: memory does not grow with the trajectory beyond the trajectory
/// itself. `on_sample` may keep what it needs (a chart's decimated envelope, a CSV row).
pub(crate) fn evaluate_streaming(
    model: &EnergyModel,
    traj: &JointTrajectory,
    on_sample: &mut dyn FnMut(usize, &SamplePower),
) -> Result<EnergyReport> {
    check_trajectory(model, traj, true)?;
    streaming(model, traj, &mut RateBlocks::new(traj, 0.0), on_sample)
}

/// [`evaluate_streaming`] of a timed path sampled every `dt` s that may keep only its
/// positions ([`crate::timing::Buffers::lean_rates`]): its velocities and accelerations are
/// then derived a block at a time, the same values bit for bit, so the same report.
pub(crate) fn evaluate_streaming_timed(
    model: &EnergyModel,
    traj: &JointTrajectory,
    dt: f64,
    on_sample: &mut dyn FnMut(usize, &SamplePower),
) -> Result<EnergyReport> {
    let kept = traj.qd.len() == traj.q.len() && traj.qdd.len() == traj.q.len();
    check_trajectory(model, traj, kept)?;
    if !kept && (traj.len() < 3 || !(dt > 0.0 && dt.is_finite())) {
        return Err(Error::Invalid(
            "trajectory: no velocities and accelerations, and too short or without a period to derive them"
                .into(),
        ));
    }
    streaming(model, traj, &mut RateBlocks::new(traj, dt), on_sample)
}

/// Samples whose rates [`streaming`] takes at a time.
const STREAM_BLOCK: usize = 256;

/// The body of [`evaluate_streaming`]: `traj` checked, its rates from `rates`.
fn streaming(
    model: &EnergyModel,
    traj: &JointTrajectory,
    rates: &mut RateBlocks<'_>,
    on_sample: &mut dyn FnMut(usize, &SamplePower),
) -> Result<EnergyReport> {
    let n = model.n;
    let len = traj.len();
    let mut data = model.data();
    let mut s = SamplePower::default();
    let mut prev = SamplePower::default();
    let mut acc = Streamed::new();
    let mut by_effect = EffectWork::new(model);
    let mut first_tau2 = [0.0; MAX_DOF];
    let t = &traj.t;
    for k0 in (0..len).step_by(STREAM_BLOCK) {
        let count = STREAM_BLOCK.min(len - k0);
        let (qd, qdd) = rates.block(k0, count);
        for (r, k) in (k0..k0 + count).enumerate() {
            let row = r * n..(r + 1) * n;
            let (qd, qdd) = (&qd[row.clone()], &qdd[row]);
            eval_sample(model, &mut data, traj.q(k), qd, qdd, &mut s)?;
            by_effect.add_sample(model, traj.q(k), qd, qdd, (k > 0).then(|| t[k] - t[k - 1]));
            if k > 0 {
                acc.add_interval(n, t[k] - t[k - 1], &prev, &s);
            } else {
                for (f, t) in first_tau2.iter_mut().zip(&s.tau[..n]) {
                    *f = t.powi(2);
                }
            }
            acc.add_peaks(n, &s);
            on_sample(k, &s);
            prev = s;
        }
    }
    let dur = traj.duration();
    let joints = acc.joints(model, dur, len, &first_tau2);
    let total = acc.total(model, &joints, dur, len);
    Ok(EnergyReport {
        robot: model.robot_name.clone(),
        model: model.description(),
        has_drive: model.has_drive,
        regeneration: model.regeneration.name().to_string(),
        standby_power_w: model.standby_w,
        duration_s: dur,
        samples: len,
        by_effect: by_effect.report(model, &total),
        joints,
        total,
        series: SampleSeries {
            n,
            ..Default::default()
        },
    })
}

/// Each per-sample torque effect's own work `Σ_j ∫ τ_e,j q̇_j dt`, integrated as the totals
/// are (the trapezoid in sample order).
struct EffectWork {
    /// Per effect: the work so far, J.
    sum: Vec<f64>,
    /// Per effect: the power at the previous sample, W.
    prev: Vec<f64>,
}

impl EffectWork {
    fn new(model: &EnergyModel) -> EffectWork {
        let zero: f64 = std::iter::empty::<f64>().sum();
        EffectWork {
            sum: vec![zero; model.torque.len()],
            prev: vec![0.0; model.torque.len()],
        }
    }

    /// The sample at `q`, `qd`, `qdd`, `h` s after the previous one (none for the first).
    fn add_sample(
        &mut self,
        model: &EnergyModel,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        h: Option<f64>,
    ) {
        let n = model.n;
        for (i, (e, _)) in model.torque.iter().enumerate() {
            let mut tau = [0.0; MAX_DOF];
            e.add_torque(q, qd, qdd, &mut tau[..n]);
            let p: f64 = tau[..n].iter().zip(qd).map(|(t, v)| t * v).sum();
            if let Some(h) = h {
                self.sum[i] += 0.5 * h * (self.prev[i] + p);
            }
            self.prev[i] = p;
        }
    }

    /// The report's entries: every effect acting in the model, in catalogue order.
    fn report(&self, model: &EnergyModel, total: &TotalEnergy) -> Vec<EffectEnergy> {
        model
            .booked
            .iter()
            .map(|(name, b)| EffectEnergy {
                effect: name.clone(),
                part: b.part(),
                energy_j: match *b {
                    Booked::Torque(i, _) => Some(self.sum[i]),
                    Booked::Folded => None,
                    Booked::Term(Stage::Motor(MotorTerm::WindingResistance)) => {
                        Some(total.copper_j)
                    }
                    Booked::Term(Stage::Motor(MotorTerm::GearEfficiency)) => Some(total.gear_j),
                    Booked::Term(Stage::Supply(SupplyTerm::Regeneration)) => {
                        Some(total.regeneration_lost_j)
                    }
                    Booked::Term(Stage::Supply(SupplyTerm::Standby)) => Some(total.standby_j),
                    Booked::Term(Stage::Torque) => None,
                },
            })
            .collect()
    }
}

/// Errors for a trajectory the model cannot evaluate: another joint count, value arrays of
/// the wrong length (the velocities and accelerations only when `rates` says it keeps
/// them), times that do not increase.
fn check_trajectory(model: &EnergyModel, traj: &JointTrajectory, rates: bool) -> Result<()> {
    let n = model.n;
    if traj.n != n {
        return Err(Error::SizeMismatch {
            what: format!("trajectory joints for robot `{}`", model.robot_name),
            got: traj.n,
            expected: n,
        });
    }
    let len = traj.len();
    let arrays = [("q", &traj.q), ("qd", &traj.qd), ("qdd", &traj.qdd)];
    for (name, v) in &arrays[..if rates { 3 } else { 1 }] {
        if v.len() != len * n {
            return Err(Error::SizeMismatch {
                what: format!(
                    "trajectory {name} values (samples × joints; fill_derivatives fills qd/qdd)"
                ),
                got: v.len(),
                expected: len * n,
            });
        }
    }
    traj.validate("trajectory")
}

/// The running sums and extremes of [`evaluate_streaming`], per joint where indexed.
struct Streamed {
    mech: [f64; MAX_DOF],
    rb: [f64; MAX_DOF],
    bal: [f64; MAX_DOF],
    fr: [f64; MAX_DOF],
    gear: [f64; MAX_DOF],
    cu: [f64; MAX_DOF],
    el: [f64; MAX_DOF],
    el_pos: [f64; MAX_DOF],
    tau2: [f64; MAX_DOF],
    peak_mech: [f64; MAX_DOF],
    peak_el: [f64; MAX_DOF],
    max_abs_tau: [f64; MAX_DOF],
    supply: f64,
    drives: f64,
    lost: f64,
    peak_supply: f64,
}

impl Streamed {
    /// Empty sums and extremes. The trapezoid sums as crate::numerics::trapezoid forms them:
    /// Σ_k ½ (t_k − t_{k−1}) (y_{k−1} + y_k), added in sample order from the empty sum.
    fn new() -> Streamed {
        let zero: f64 = std::iter::empty::<f64>().sum();
        Streamed {
            mech: [zero; MAX_DOF],
            rb: [zero; MAX_DOF],
            bal: [zero; MAX_DOF],
            fr: [zero; MAX_DOF],
            gear: [zero; MAX_DOF],
            cu: [zero; MAX_DOF],
            el: [zero; MAX_DOF],
            el_pos: [zero; MAX_DOF],
            tau2: [zero; MAX_DOF],
            peak_mech: [f64::NEG_INFINITY; MAX_DOF],
            peak_el: [f64::NEG_INFINITY; MAX_DOF],
            max_abs_tau: [0.0; MAX_DOF],
            supply: zero,
            drives: zero,
            lost: zero,
            peak_supply: f64::NEG_INFINITY,
        }
    }

    /// The trapezoid of the interval `h` long from sample `prev` to sample `s` added to every
    /// sum.
    #[inline(always)]
    fn add_interval(&mut self, n: usize, h: f64, prev: &SamplePower, s: &SamplePower) {
        let trap = |a: f64, b: f64| 0.5 * h * (a + b);
        for j in 0..n {
            self.mech[j] += trap(prev.p_mech[j], s.p_mech[j]);
            self.rb[j] += trap(prev.p_rigid_body[j], s.p_rigid_body[j]);
            self.bal[j] += trap(prev.p_balancer[j], s.p_balancer[j]);
            self.fr[j] += trap(prev.p_friction[j], s.p_friction[j]);
            self.gear[j] += trap(prev.p_gear[j], s.p_gear[j]);
            self.cu[j] += trap(prev.p_copper[j], s.p_copper[j]);
            self.el[j] += trap(prev.p_el[j], s.p_el[j]);
            self.el_pos[j] += trap(prev.p_el[j].max(0.0), s.p_el[j].max(0.0));
            self.tau2[j] += trap(prev.tau[j].powi(2), s.tau[j].powi(2));
        }
        self.supply += trap(prev.p_supply, s.p_supply);
        self.drives += trap(prev.p_drives, s.p_drives);
        self.lost += trap(prev.p_regeneration_lost, s.p_regeneration_lost);
    }

    /// Sample `s`'s powers and torques taken into the extremes.
    #[inline(always)]
    fn add_peaks(&mut self, n: usize, s: &SamplePower) {
        for j in 0..n {
            self.peak_mech[j] = self.peak_mech[j].max(s.p_mech[j]);
            self.peak_el[j] = self.peak_el[j].max(s.p_el[j]);
            self.max_abs_tau[j] = self.max_abs_tau[j].max(s.tau[j].abs());
        }
        self.peak_supply = self.peak_supply.max(s.p_supply);
    }

    /// Each joint's energies, peaks and torques over `len` samples lasting `dur` s (the RMS
    /// torque of a single sample from its squared torque `first_tau2`).
    fn joints(
        &self,
        model: &EnergyModel,
        dur: f64,
        len: usize,
        first_tau2: &[f64; MAX_DOF],
    ) -> Vec<JointEnergy> {
        (0..model.n)
            .map(|j| {
                let rms = if dur > 0.0 {
                    (self.tau2[j] / dur).sqrt()
                } else if len > 0 {
                    first_tau2[j].sqrt()
                } else {
                    0.0
                };
                JointEnergy {
                    name: model.joint_names[j].clone(),
                    mechanical_j: self.mech[j],
                    rigid_body_j: self.rb[j],
                    balancer_j: self.bal[j],
                    friction_j: self.fr[j],
                    gear_j: self.gear[j],
                    copper_j: self.cu[j],
                    electrical_j: self.el[j],
                    electrical_positive_j: self.el_pos[j],
                    peak_mechanical_power_w: if len > 0 { self.peak_mech[j] } else { 0.0 },
                    peak_electrical_power_w: if len > 0 { self.peak_el[j] } else { 0.0 },
                    rms_torque_nm: rms,
                    max_abs_torque_nm: self.max_abs_tau[j],
                }
            })
            .collect()
    }

    /// The totals: the joints' sums, the drives, the supply and the standby over `duration`.
    fn total(
        &self,
        model: &EnergyModel,
        joints: &[JointEnergy],
        duration: f64,
        len: usize,
    ) -> TotalEnergy {
        let sum = |f: fn(&JointEnergy) -> f64| joints.iter().map(f).sum::<f64>();
        let supply_j = self.supply;
        TotalEnergy {
            mechanical_j: sum(|j| j.mechanical_j),
            rigid_body_j: sum(|j| j.rigid_body_j),
            balancer_j: sum(|j| j.balancer_j),
            friction_j: sum(|j| j.friction_j),
            gear_j: sum(|j| j.gear_j),
            copper_j: sum(|j| j.copper_j),
            electrical_j: sum(|j| j.electrical_j),
            drives_j: self.drives,
            regeneration_lost_j: self.lost,
            standby_j: model.standby_w * duration,
            supply_j,
            peak_supply_power_w: if len > 0 { self.peak_supply } else { 0.0 },
            mean_supply_power_w: if duration > 0.0 {
                supply_j / duration
            } else {
                0.0
            },
        }
    }
}
