//! `armature`: reflected rotor inertia `τ = G² J_m q̈` (joint side; the rotor's kinetic energy
//! `½ J_m (G q̇)²`). [`crate::dynamics::DynModel`] includes the same term when built with
//! `armature: true`; this effect is its parameterised form for identification.

use super::{check_values, per_joint, Effect, ParamSpec, TorqueEffect};
use crate::error::Result;

/// Reflected rotor inertia per joint `I_a = G² J_m`, kg·m².
#[derive(Clone, Debug, PartialEq)]
pub struct Armature {
    /// `G² J_m` per joint, kg·m².
    pub ia: Vec<f64>,
}

impl Armature {
    /// From the drive's gear ratios and rotor inertias ([`crate::robot::JointDrive::armature`]).
    pub fn from_drive(drive: &crate::robot::Drive) -> Self {
        Armature {
            ia: drive.joints.iter().map(|j| j.armature()).collect(),
        }
    }
}

impl Effect for Armature {
    fn name(&self) -> &'static str {
        "armature"
    }
    fn params(&self) -> Vec<ParamSpec> {
        per_joint("G2Jm", "kg·m²", self.ia.len())
    }
    fn values(&self) -> Vec<f64> {
        self.ia.clone()
    }
    fn set_values(&mut self, values: &[f64]) -> Result<()> {
        check_values(self.name(), &self.params(), values)?;
        self.ia.copy_from_slice(values);
        Ok(())
    }
}

impl TorqueEffect for Armature {
    fn add_torque(&self, _q: &[f64], _qd: &[f64], qdd: &[f64], tau: &mut [f64]) {
        for ((t, a), i) in tau.iter_mut().zip(qdd).zip(&self.ia) {
            *t += i * a;
        }
    }
    fn regressor(&self, _q: &[f64], _qd: &[f64], qdd: &[f64], y: &mut [f64]) -> bool {
        let p = self.ia.len();
        y.iter_mut().for_each(|v| *v = 0.0);
        for (j, a) in qdd.iter().enumerate().take(p) {
            if let Some(c) = y.get_mut(j * p + j) {
                *c = *a;
            }
        }
        true
    }
}
