//! `viscous`: joint-side viscous friction `τ = f_v q̇` (seed 000, eq. 2, first term).

use super::{check_values, per_joint, Effect, ParamSpec, TorqueEffect};
use crate::error::Result;

/// Viscous friction per joint, `f_v` in N·m·s/rad (joint side).
#[derive(Clone, Debug, PartialEq)]
pub struct Viscous {
    /// `f_v` per joint, N·m·s/rad.
    pub fv: Vec<f64>,
}

impl Viscous {
    /// From the drive file's `viscous_nm_s_per_rad`.
    pub fn from_drive(drive: &crate::robot::Drive) -> Self {
        Viscous {
            fv: drive.joints.iter().map(|j| j.viscous).collect(),
        }
    }

    /// Torque of joint `j` at velocity `qd` rad/s, N·m.
    #[inline]
    pub fn joint_torque(&self, j: usize, qd: f64) -> f64 {
        self.fv.get(j).map_or(0.0, |f| f * qd)
    }
}

impl Effect for Viscous {
    fn name(&self) -> &'static str {
        "viscous"
    }
    fn params(&self) -> Vec<ParamSpec> {
        per_joint("f_v", "N·m·s/rad", self.fv.len())
    }
    fn values(&self) -> Vec<f64> {
        self.fv.clone()
    }
    fn set_values(&mut self, values: &[f64]) -> Result<()> {
        check_values(self.name(), &self.params(), values)?;
        self.fv.copy_from_slice(values);
        Ok(())
    }
}

impl TorqueEffect for Viscous {
    fn add_torque(&self, _q: &[f64], qd: &[f64], _qdd: &[f64], tau: &mut [f64]) {
        for ((t, v), f) in tau.iter_mut().zip(qd).zip(&self.fv) {
            *t += f * v;
        }
    }
    fn regressor(&self, _q: &[f64], qd: &[f64], _qdd: &[f64], y: &mut [f64]) -> bool {
        let p = self.fv.len();
        y.iter_mut().for_each(|v| *v = 0.0);
        for (j, v) in qd.iter().enumerate().take(p) {
            if let Some(c) = y.get_mut(j * p + j) {
                *c = *v;
            }
        }
        true
    }
}
