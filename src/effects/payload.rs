//! `payload`: an error `Δm` in the payload mass at the flange (extruder, hose and material).
//! Its torque is `Δm · τ_unit(q, q̇, q̈)`, where `τ_unit` is the inverse dynamics (gravity and
//! inertial, RNEA) of a 1 kg point mass at the nominal payload's centre of mass (flange origin
//! when the robot has no payload): linear in `Δm`, so the regressor is `τ_unit`.

use super::{check_values, Effect, ParamSpec, TorqueEffect};
use crate::dynamics::{rnea, DynData, DynModel, DynOptions};
use crate::error::Result;
use crate::robot::{Inertial, RobotModel};
use std::sync::Mutex;

/// Payload mass error at the flange.
#[derive(Debug)]
pub struct Payload {
    /// Mass error `Δm`, kg (≥ −nominal mass).
    pub dm: f64,
    /// Nominal payload mass, kg (lower bound of `Δm` is its negative).
    pub nominal_mass: f64,
    unit: DynModel,
    data: Mutex<DynData>,
}

impl Payload {
    /// The effect for `robot` with `Δm = 0`. Error: the robot lacks inertials (as
    /// [`DynModel::new`]).
    pub fn new(robot: &RobotModel) -> Result<Self> {
        let mut r = robot.clone();
        for l in r.links.iter_mut() {
            *l = Some(Inertial::zero());
        }
        let com = robot
            .payload
            .map(|p| p.com)
            .unwrap_or_else(crate::math::V3::zeros);
        let mut unit = Inertial::zero();
        unit.mass = 1.0;
        unit.com = com;
        r.payload = Some(unit);
        let model = DynModel::new(
            &r,
            DynOptions {
                payload: true,
                armature: false,
            },
        )?;
        let data = model.data();
        Ok(Payload {
            dm: 0.0,
            nominal_mass: robot.payload.map_or(0.0, |p| p.mass),
            unit: model,
            data: Mutex::new(data),
        })
    }

    /// Torque of a 1 kg point mass at the payload CoM (N·m per kg) into `out`.
    pub fn unit_torque(&self, q: &[f64], qd: &[f64], qdd: &[f64], out: &mut [f64]) {
        out.iter_mut().for_each(|v| *v = 0.0);
        if let Ok(mut d) = self.data.lock() {
            let _ = rnea(&self.unit, &mut d, q, qd, qdd, out);
        }
    }
}

impl Effect for Payload {
    fn name(&self) -> &'static str {
        "payload"
    }
    fn params(&self) -> Vec<ParamSpec> {
        vec![ParamSpec {
            name: "dm".into(),
            unit: "kg",
            lower: -self.nominal_mass,
            upper: f64::INFINITY,
        }]
    }
    fn values(&self) -> Vec<f64> {
        vec![self.dm]
    }
    fn set_values(&mut self, values: &[f64]) -> Result<()> {
        check_values(self.name(), &self.params(), values)?;
        self.dm = values[0];
        Ok(())
    }
}

impl TorqueEffect for Payload {
    fn add_torque(&self, q: &[f64], qd: &[f64], qdd: &[f64], tau: &mut [f64]) {
        if self.dm == 0.0 {
            return;
        }
        let mut u = [0.0; crate::dynamics::MAX_DOF];
        let n = tau.len().min(u.len());
        self.unit_torque(q, qd, qdd, &mut u[..n]);
        for (t, v) in tau.iter_mut().zip(&u[..n]) {
            *t += self.dm * v;
        }
    }
    fn regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64], y: &mut [f64]) -> bool {
        self.unit_torque(q, qd, qdd, y);
        true
    }
}
