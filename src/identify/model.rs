//! The model the measurements are compared with: the rigid body (nominal payload) plus the
//! catalogue's effects, each switched on or off and carrying its own parameters, and the
//! motor model that turns joint torque into the logged signal (seed 001, eqs. 2–4).
//!
//! Prediction per sample: `τ = τ_rb + Σ_enabled τ_effect` (joint side, N·m); then
//! `τ_m = τ/(G η)` when driving (`τ q̇ ≥ 0`) else `τ η/G`, `i = τ_m/K_t`, `P = τ_m G q̇ + R i²`
//! per axis, and `P_supply = P_drives − ρ (P_drives − Σ P) + P_0` with `P_drives` from the
//! drive's regeneration policy. Effects switched off contribute nothing: no friction, `η = 1`,
//! `R = 0`, `ρ = 0`, `P_0 = 0`.

use crate::dynamics::{rnea, DynModel, DynOptions, MAX_DOF};
pub use crate::effects::{catalogue_index, DEFAULT_EFFECTS};
use crate::effects::{
    Armature, Balancer, Copper, Coulomb, Effect, GearEfficiency, ParamSpec, Payload,
    Regeneration as RegenEffect, Standby, Stribeck, TorqueEffect, Viscous, CATALOGUE,
    COULOMB_VELOCITY_SCALE_RAD_S,
};
use crate::error::{Error, Result};
use crate::identify::log::{Log, SignalKind};
use crate::robot::{Regeneration, RobotModel};
use std::path::{Path, PathBuf};

/// The comparison model: every catalogue effect with its parameters and an on/off switch.
#[derive(Debug)]
pub struct Model {
    /// Number of joints.
    pub n: usize,
    /// Robot name.
    pub robot_name: String,
    /// Gear ratios (motor turns per joint turn).
    pub gear: Vec<f64>,
    /// Torque constants K_t, N·m/A (motor side).
    pub kt: Vec<f64>,
    /// Drive regeneration policy.
    pub policy: Regeneration,
    /// Whether drive data exist (needed for current and power logs).
    pub has_drive: bool,
    /// `viscous`.
    pub viscous: Viscous,
    /// `coulomb`.
    pub coulomb: Coulomb,
    /// `stribeck`.
    pub stribeck: Stribeck,
    /// `armature`.
    pub armature: Armature,
    /// `payload` (mass error).
    pub payload: Payload,
    /// `balancer`.
    pub balancer: Balancer,
    /// `copper`.
    pub copper: Copper,
    /// `gear_efficiency`.
    pub gear_efficiency: GearEfficiency,
    /// `regeneration`.
    pub regeneration: RegenEffect,
    /// `standby`.
    pub standby: Standby,
    /// Switch per catalogue entry (order of [`CATALOGUE`]).
    pub enabled: [bool; 10],
    /// Whether the robot declares a balancer (drive file geometry): without one, a `balancer`
    /// candidate is not physically plausible.
    pub balancer_declared: bool,
    dynamics: DynModel,
}

/// Parse a comma-separated effect list.
pub fn parse_effect_list(s: &str) -> Result<Vec<&'static str>> {
    let mut out = Vec::new();
    for w in s.split(',').map(str::trim).filter(|w| !w.is_empty()) {
        let i = catalogue_index(w)?;
        if !out.contains(&CATALOGUE[i]) {
            out.push(CATALOGUE[i]);
        }
    }
    Ok(out)
}

/// The drive file a `--robot` argument refers to (directory → `drive.toml`, a `.toml` file →
/// itself), if any.
pub fn drive_file_of(robot_arg: &Path) -> Option<PathBuf> {
    if robot_arg.is_dir() {
        let p = robot_arg.join("drive.toml");
        p.is_file().then_some(p)
    } else if robot_arg.extension().is_some_and(|e| e == "toml") {
        Some(robot_arg.to_path_buf())
    } else {
        None
    }
}

impl Model {
    /// The model of a robot: drive values for `viscous`, `coulomb`, `armature`, `copper`,
    /// `gear_efficiency`, `standby`; the robot's `[effects]` configuration
    /// ([`RobotModel::effects`], parsed with the drive file) for the switches
    /// ([`DEFAULT_EFFECTS`] when the robot has drive data and the table gives none, nothing
    /// without drive data) and for `stribeck`, `payload`, `balancer`, `regeneration` (zero when
    /// the table gives nothing). [`crate::energy::EnergyModel`] reads the same configuration.
    /// Error: the robot lacks inertials.
    pub fn new(robot: &RobotModel) -> Result<Self> {
        let n = robot.dof();
        let dynamics = DynModel::new(
            robot,
            DynOptions {
                payload: true,
                armature: false,
            },
        )?;
        let d = robot.drive.as_ref();
        let per = |f: &dyn Fn(&crate::robot::JointDrive) -> f64, dflt: f64| -> Vec<f64> {
            match d {
                Some(d) => d.joints.iter().map(f).collect(),
                None => vec![dflt; n],
            }
        };
        if let Some(d) = d {
            robot.check_len("drive joints", d.joints.len())?;
        }
        let cfg = &robot.effects;
        let mut payload = Payload::new(robot)?;
        payload.set_values(&[cfg.payload_mass_error_kg])?;
        let mut m = Model {
            n,
            robot_name: robot.name().to_string(),
            gear: per(&|j| j.gear_ratio, 1.0),
            kt: per(&|j| j.torque_constant, 1.0),
            policy: d.map_or(Regeneration::None, |d| d.regeneration),
            has_drive: d.is_some(),
            viscous: Viscous {
                fv: per(&|j| j.viscous, 0.0),
            },
            coulomb: Coulomb {
                fc: per(&|j| j.coulomb, 0.0),
                velocity_scale: COULOMB_VELOCITY_SCALE_RAD_S,
            },
            stribeck: cfg.stribeck(n),
            armature: Armature {
                ia: per(&|j| j.armature(), 0.0),
            },
            payload,
            balancer: cfg.balancer(),
            copper: Copper {
                r: per(&|j| j.winding_resistance, 0.0),
            },
            gear_efficiency: GearEfficiency {
                eta: per(&|j| j.gear_efficiency, 1.0),
            },
            regeneration: RegenEffect {
                recovered: cfg.regeneration_recovered_fraction,
            },
            standby: Standby {
                power: d.map_or(0.0, |d| d.standby_power),
            },
            enabled: cfg.enabled_mask(d.is_some()),
            balancer_declared: cfg.balancer_declared,
            dynamics,
        };
        // Identified values the drive file keeps in `[effects.values]` (a calibrated robot
        // without per-joint drive tables) override the defaults above.
        let file = cfg.file.clone().unwrap_or_default();
        for (name, vals) in &cfg.values {
            m.set_values(name, vals).map_err(|e| Error::Field {
                file: file.clone(),
                field: format!("effects.values.{name}"),
                msg: e.to_string(),
            })?;
        }
        Ok(m)
    }

    /// Switch an effect on or off. Error: unknown name.
    pub fn set_enabled(&mut self, name: &str, on: bool) -> Result<()> {
        let i = catalogue_index(name)?;
        self.enabled[i] = on;
        Ok(())
    }

    /// Whether an effect is switched on (false for unknown names).
    pub fn is_enabled(&self, name: &str) -> bool {
        catalogue_index(name).is_ok_and(|i| self.enabled[i])
    }

    /// Names of the effects switched on, in catalogue order.
    pub fn enabled_names(&self) -> Vec<&'static str> {
        CATALOGUE
            .iter()
            .zip(self.enabled)
            .filter(|(_, on)| *on)
            .map(|(n, _)| *n)
            .collect()
    }

    /// The effect called `name`.
    pub fn effect(&self, name: &str) -> Result<&dyn Effect> {
        Ok(match catalogue_index(name)? {
            0 => &self.viscous,
            1 => &self.coulomb,
            2 => &self.stribeck,
            3 => &self.armature,
            4 => &self.payload,
            5 => &self.balancer,
            6 => &self.copper,
            7 => &self.gear_efficiency,
            8 => &self.regeneration,
            _ => &self.standby,
        })
    }

    fn effect_mut(&mut self, name: &str) -> Result<&mut dyn Effect> {
        Ok(match catalogue_index(name)? {
            0 => &mut self.viscous,
            1 => &mut self.coulomb,
            2 => &mut self.stribeck,
            3 => &mut self.armature,
            4 => &mut self.payload,
            5 => &mut self.balancer,
            6 => &mut self.copper,
            7 => &mut self.gear_efficiency,
            8 => &mut self.regeneration,
            _ => &mut self.standby,
        })
    }

    /// Parameter specs of an effect.
    pub fn params(&self, name: &str) -> Result<Vec<ParamSpec>> {
        Ok(self.effect(name)?.params())
    }

    /// Parameter values of an effect (SI).
    pub fn values(&self, name: &str) -> Result<Vec<f64>> {
        Ok(self.effect(name)?.values())
    }

    /// Set the parameter values of an effect (checked against the bounds).
    pub fn set_values(&mut self, name: &str, values: &[f64]) -> Result<()> {
        self.effect_mut(name)?.set_values(values)
    }

    /// Whether an effect can be seen in a log of this signal: torque-side effects in every
    /// log; `copper` and `gear_efficiency` in power logs (`gear_efficiency` also in current
    /// logs); `regeneration` and `standby` only in `p_total` logs.
    pub fn observable(name: &str, kind: SignalKind) -> bool {
        match name {
            "copper" => matches!(kind, SignalKind::AxisPower | SignalKind::TotalPower),
            "gear_efficiency" => kind != SignalKind::Torque,
            "regeneration" | "standby" => kind == SignalKind::TotalPower,
            _ => true,
        }
    }

    fn torque_effects(&self) -> [(&dyn TorqueEffect, bool); 6] {
        [
            (&self.viscous, self.enabled[0]),
            (&self.coulomb, self.enabled[1]),
            (&self.stribeck, self.enabled[2]),
            (&self.armature, self.enabled[3]),
            (&self.payload, self.enabled[4]),
            (&self.balancer, self.enabled[5]),
        ]
    }

    /// Joint torque of the model at one state (N·m), into `tau` (length `n`).
    pub fn torque(&self, q: &[f64], qd: &[f64], qdd: &[f64], tau: &mut [f64]) -> Result<()> {
        let mut data = self.dynamics.data();
        rnea(&self.dynamics, &mut data, q, qd, qdd, tau)?;
        for (e, on) in self.torque_effects() {
            if on {
                e.add_torque(q, qd, qdd, tau);
            }
        }
        Ok(())
    }

    /// Signal of kind `kind` from joint torques `tau` (N·m) at velocities `qd` (rad/s), into
    /// `out` (`kind.channels(n)` values).
    pub fn signal_from_torque(&self, kind: SignalKind, tau: &[f64], qd: &[f64], out: &mut [f64]) {
        let n = self.n;
        if kind == SignalKind::Torque {
            out[..n].copy_from_slice(&tau[..n]);
            return;
        }
        let mut p = [0.0; MAX_DOF];
        for j in 0..n {
            let eta = if self.enabled[7] {
                self.gear_efficiency.eta[j]
            } else {
                1.0
            };
            let r = if self.enabled[6] {
                self.copper.r[j]
            } else {
                0.0
            };
            let m = crate::energy::motor(tau[j], qd[j], self.gear[j], eta, self.kt[j], r);
            p[j] = m.p_el;
            match kind {
                SignalKind::Current => out[j] = m.current,
                SignalKind::AxisPower => out[j] = p[j],
                _ => {}
            }
        }
        if kind == SignalKind::TotalPower {
            let rho = if self.enabled[8] {
                self.regeneration.recovered
            } else {
                0.0
            };
            let p0 = if self.enabled[9] {
                self.standby.power
            } else {
                0.0
            };
            out[0] = crate::energy::supply_power(self.policy, &p[..n], rho, p0).supply;
        }
    }

    /// The rigid-body model (nominal payload, no armature: that is the `armature` effect).
    pub fn dynamics(&self) -> &DynModel {
        &self.dynamics
    }
}

/// A log prepared for repeated prediction: rigid-body torques and the regressors of the
/// linear torque effects computed once.
#[derive(Debug)]
pub struct Prepared<'a> {
    /// The log.
    pub log: &'a Log,
    /// Rigid-body torque per sample, row-major `len × n`, N·m.
    pub tau_rb: Vec<f64>,
    /// Regressors of the linear torque effects by catalogue index (0 viscous, 1 coulomb,
    /// 3 armature, 4 payload, 5 balancer): `len × n × P` each.
    regs: Vec<Option<Vec<f64>>>,
}

impl<'a> Prepared<'a> {
    /// Prepare `log` for `model`. Errors: joint count mismatch; a current or power log for a
    /// robot without drive data.
    pub fn new(model: &Model, log: &'a Log) -> Result<Self> {
        let n = model.n;
        if log.traj.n != n {
            return Err(Error::SizeMismatch {
                what: format!(
                    "{}: joints in the log for robot `{}`",
                    log.file, model.robot_name
                ),
                got: log.traj.n,
                expected: n,
            });
        }
        if log.kind == SignalKind::Current && !model.has_drive {
            return Err(Error::Invalid(format!(
                "{}: a current log (`i1..i{n}`) needs each joint's gear ratio and torque constant K_t \
(drive file [[joints]] `gear_ratio`, `torque_constant_nm_per_a`), and robot `{}` has none; \
log joint torque (`tau`), axis power (`p`) or supply power (`p_total`) instead, or give a drive file",
                log.file, model.robot_name
            )));
        }
        let len = log.len();
        let mut data = model.dynamics.data();
        let mut tau_rb = vec![0.0; len * n];
        for k in 0..len {
            rnea(
                &model.dynamics,
                &mut data,
                log.traj.q(k),
                log.traj.qd(k),
                log.traj.qdd(k),
                &mut tau_rb[k * n..(k + 1) * n],
            )?;
        }
        let mut regs: Vec<Option<Vec<f64>>> = vec![None; 6];
        for (i, (e, _)) in model.torque_effects().iter().enumerate() {
            let p = e.params().len();
            let mut all = vec![0.0; len * n * p];
            let mut linear = true;
            for k in 0..len {
                let y = &mut all[k * n * p..(k + 1) * n * p];
                if !e.regressor(log.traj.q(k), log.traj.qd(k), log.traj.qdd(k), y) {
                    linear = false;
                    break;
                }
            }
            if linear {
                regs[i] = Some(all);
            }
        }
        Ok(Prepared { log, tau_rb, regs })
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.log.len()
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.log.is_empty()
    }

    /// Model prediction of the logged signal at the samples `rows`, row-major
    /// `rows.len() × channels`, into `out` (resized).
    pub fn predict(&self, model: &Model, rows: &[usize], out: &mut Vec<f64>) {
        let n = model.n;
        let ch = self.log.channels;
        out.clear();
        out.resize(rows.len() * ch, 0.0);
        let effects = model.torque_effects();
        let vals: Vec<Vec<f64>> = effects.iter().map(|(e, _)| e.values()).collect();
        let mut tau = [0.0; MAX_DOF];
        for (r, &k) in rows.iter().enumerate() {
            tau[..n].copy_from_slice(&self.tau_rb[k * n..(k + 1) * n]);
            let (q, qd, qdd) = (
                self.log.traj.q(k),
                self.log.traj.qd(k),
                self.log.traj.qdd(k),
            );
            for (i, (e, on)) in effects.iter().enumerate() {
                if !*on {
                    continue;
                }
                match &self.regs[i] {
                    Some(y) => {
                        let p = vals[i].len();
                        let yk = &y[k * n * p..(k + 1) * n * p];
                        for (j, t) in tau[..n].iter_mut().enumerate() {
                            let row = &yk[j * p..(j + 1) * p];
                            *t += row.iter().zip(&vals[i]).map(|(a, b)| a * b).sum::<f64>();
                        }
                    }
                    None => e.add_torque(q, qd, qdd, &mut tau[..n]),
                }
            }
            model.signal_from_torque(self.log.kind, &tau[..n], qd, &mut out[r * ch..(r + 1) * ch]);
        }
    }
}

/// A saved copy of a model's switches and parameter values.
#[derive(Clone, Debug)]
pub struct ModelState {
    enabled: [bool; 10],
    values: Vec<Vec<f64>>,
}

impl Model {
    /// Save switches and values.
    pub fn state(&self) -> ModelState {
        ModelState {
            enabled: self.enabled,
            values: CATALOGUE
                .iter()
                .map(|n| self.values(n).unwrap_or_default())
                .collect(),
        }
    }
    /// Restore a saved state.
    pub fn restore(&mut self, s: &ModelState) {
        self.enabled = s.enabled;
        for (n, v) in CATALOGUE.iter().zip(&s.values) {
            let _ = self.set_values(n, v);
        }
    }
}
