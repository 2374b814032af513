//! `coulomb`: joint-side Coulomb friction `τ = f_c sign(q̇)` (seed 000, eq. 2, second term),
//! smoothed near zero speed as `f_c tanh(q̇ / ε)`.

use super::{check_values, per_joint, Effect, ParamSpec, TorqueEffect};
use crate::error::{Error, Result};

/// Default velocity scale ε of the smoothed sign, rad/s: at |q̇| = 3ε the friction reaches
/// 99.5 % of `f_c`. Small against path speeds (≥ 0.01 rad/s in printing), large enough to keep
/// the torque continuous across velocity reversals of sampled paths.
pub const COULOMB_VELOCITY_SCALE_RAD_S: f64 = 1e-3;

/// Coulomb friction per joint, `f_c` in N·m (joint side), sign smoothed with `tanh(q̇/ε)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Coulomb {
    /// `f_c` per joint, N·m.
    pub fc: Vec<f64>,
    /// Velocity scale ε of the smoothed sign, rad/s (> 0).
    pub velocity_scale: f64,
}

impl Coulomb {
    /// From the drive file's `coulomb_nm`, with velocity scale `eps` rad/s (non-positive or
    /// non-finite values fall back to [`COULOMB_VELOCITY_SCALE_RAD_S`]).
    pub fn from_drive(drive: &crate::robot::Drive, eps: f64) -> Self {
        Coulomb {
            fc: drive.joints.iter().map(|j| j.coulomb).collect(),
            velocity_scale: if eps.is_finite() && eps > 0.0 {
                eps
            } else {
                COULOMB_VELOCITY_SCALE_RAD_S
            },
        }
    }

    /// Smoothed sign `tanh(q̇/ε)` (dimensionless).
    #[inline]
    pub fn smooth_sign(&self, qd: f64) -> f64 {
        (qd / self.velocity_scale).tanh()
    }

    /// Torque of joint `j` at velocity `qd` rad/s, N·m.
    #[inline]
    pub fn joint_torque(&self, j: usize, qd: f64) -> f64 {
        match self.fc.get(j) {
            Some(&f) if f != 0.0 => f * self.smooth_sign(qd),
            _ => 0.0,
        }
    }

    /// Change the velocity scale ε (rad/s, > 0).
    pub fn set_velocity_scale(&mut self, eps: f64) -> Result<()> {
        if !(eps.is_finite() && eps > 0.0) {
            return Err(Error::Invalid(format!(
                "coulomb velocity scale must be > 0 rad/s, got {eps}"
            )));
        }
        self.velocity_scale = eps;
        Ok(())
    }
}

impl Effect for Coulomb {
    fn name(&self) -> &'static str {
        "coulomb"
    }
    fn params(&self) -> Vec<ParamSpec> {
        per_joint("f_c", "N·m", self.fc.len())
    }
    fn values(&self) -> Vec<f64> {
        self.fc.clone()
    }
    fn set_values(&mut self, values: &[f64]) -> Result<()> {
        check_values(self.name(), &self.params(), values)?;
        self.fc.copy_from_slice(values);
        Ok(())
    }
}

impl TorqueEffect for Coulomb {
    fn add_torque(&self, _q: &[f64], qd: &[f64], _qdd: &[f64], tau: &mut [f64]) {
        for (j, (t, v)) in tau.iter_mut().zip(qd).enumerate() {
            *t += self.joint_torque(j, *v);
        }
    }
    fn regressor(&self, _q: &[f64], qd: &[f64], _qdd: &[f64], y: &mut [f64]) -> bool {
        let p = self.fc.len();
        y.iter_mut().for_each(|v| *v = 0.0);
        for (j, v) in qd.iter().enumerate().take(p) {
            if let Some(c) = y.get_mut(j * p + j) {
                *c = self.smooth_sign(*v);
            }
        }
        true
    }
}
