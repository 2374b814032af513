//! `viscous`: joint-side viscous friction `τ = f_v q̇` (seed 000, eq. 2, first term).

use super::uncertain::at;
use super::{
    check_values, diagonal_regressor, per_joint, BuildContext, DrawPhase, Drawing, DriveKept,
    DriveKeysMut, Effect, EnergyClass, ParamSpec, Uncertainty,
};
use crate::error::Result;

/// The drive file's `[[joints]]` key holding `f_v` (N·m·s/rad), read and written here.
const DRIVE_KEY: &str = "viscous_nm_s_per_rad";

/// Viscous friction per joint, `f_v` in N·m·s/rad (joint side).
#[derive(Clone, Debug, PartialEq)]
pub struct Viscous {
    /// `f_v` per joint, N·m·s/rad.
    pub fv: Vec<f64>,
}

/// Registry entry: `f_v` from the drive file's `viscous_nm_s_per_rad` (zeros without drive data).
pub(crate) fn build(ctx: &BuildContext) -> Result<Box<dyn Effect>> {
    Ok(Box::new(Viscous {
        fv: ctx.joint_key(DRIVE_KEY, 0.0)?,
    }))
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
    /// Implausible when a fitted value is below zero.
    fn implausible_fit(&self, std_errors: &[Option<f64>]) -> Option<String> {
        super::plausible::implausible_if_negative(self, std_errors)
    }
    /// `[[joints]] viscous_nm_s_per_rad`.
    fn write_drive_keys(&self, keys: &mut DriveKeysMut<'_>) -> Result<DriveKept> {
        keys.set_joints(DRIVE_KEY, &self.fv)?;
        Ok(DriveKept::Keys)
    }
    fn uncertainty(&self) -> Option<Uncertainty> {
        at(DrawPhase::Joint, 2)
    }
    /// `viscous_nm_s_per_rad` of the joint: identified, normal with its standard error;
    /// else ± `viscous_rel`.
    fn draw(&self, d: &mut Drawing<'_>, joint: Option<usize>) {
        let Some(j) = joint else { return };
        let rel = d.ranges.viscous_rel;
        let label = format!("viscous friction joint {}", j + 1);
        let fv = d.factor(&format!("f_v[{}]", j + 1), rel, label);
        if let Some(jd) = d.joint(j) {
            jd.viscous *= fv;
        }
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
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn needs_joint_motion(&self) -> bool {
        true
    }
    fn energy_class(&self) -> EnergyClass {
        EnergyClass::Friction
    }
    fn is_null(&self) -> bool {
        self.fv.iter().all(|f| *f == 0.0)
    }
    fn driven_by_motion(&self) -> bool {
        true
    }
    fn add_torque(&self, _q: &[f64], qd: &[f64], _qdd: &[f64], tau: &mut [f64]) {
        for ((t, v), f) in tau.iter_mut().zip(qd).zip(&self.fv) {
            *t += f * v;
        }
    }
    fn regressor(&self, _q: &[f64], qd: &[f64], _qdd: &[f64], y: &mut [f64]) -> bool {
        diagonal_regressor(self.fv.len(), y, |j| qd.get(j).copied().unwrap_or(0.0));
        true
    }
}
