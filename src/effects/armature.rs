//! `armature`: reflected rotor inertia `τ = G² J_m q̈` (joint side; the rotor's kinetic energy
//! `½ J_m (G q̇)²`).

use super::uncertain::at;
use super::EnergyOptions;
use super::{
    check_values, diagonal_regressor, per_joint, BuildContext, DrawPhase, Drawing, DriveKept,
    DriveKeysMut, Effect, ParamSpec, Uncertainty,
};
use crate::error::Result;

/// Reflected rotor inertia per joint `I_a = G² J_m`, kg·m².
#[derive(Clone, Debug, PartialEq)]
pub struct Armature {
    /// `G² J_m` per joint, kg·m².
    pub ia: Vec<f64>,
}

/// Registry entry: `G² J_m` from the drive file (zeros without drive data).
pub(crate) fn build(ctx: &BuildContext) -> Result<Box<dyn Effect>> {
    Ok(Box::new(Armature {
        ia: ctx.per_joint(|j| j.armature(), 0.0),
    }))
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
    /// Implausible when a fitted value is below zero.
    fn implausible_fit(&self, std_errors: &[Option<f64>]) -> Option<String> {
        super::plausible::implausible_if_negative(self, std_errors)
    }
    /// `[[joints]] rotor_inertia_kg_m2` (= `G² J_m / G²`).
    fn write_drive_keys(&self, keys: &mut DriveKeysMut<'_>) -> Result<DriveKept> {
        let jm: Vec<f64> = self
            .ia
            .iter()
            .zip(keys.gear_ratios())
            .map(|(ia, g)| ia / (g * g))
            .collect();
        keys.set_joints("rotor_inertia_kg_m2", &jm)?;
        Ok(DriveKept::Keys)
    }
    fn uncertainty(&self) -> Option<Uncertainty> {
        at(DrawPhase::Joint, 1)
    }
    /// Only an identified armature is drawn (normal with its standard error, as the rotor
    /// inertia); a nominal one has no range.
    fn draw(&self, d: &mut Drawing<'_>, joint: Option<usize>) {
        let Some(j) = joint else { return };
        if let Some(f) = d.identified_factor(&format!("G2Jm[{}]", j + 1)) {
            if let Some(jd) = d.joint(j) {
                jd.rotor_inertia *= f;
            }
            d.record(format!("armature joint {}", j + 1), f);
        }
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
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    /// Kept with [`EnergyOptions::armature`] for a robot with drive data (the rotor inertia
    /// is drive data).
    fn in_energy_model(&self, options: &EnergyOptions, has_drive: bool) -> bool {
        options.armature && has_drive
    }
    fn needs_joint_motion(&self) -> bool {
        true
    }
    fn is_null(&self) -> bool {
        self.ia.iter().all(|f| *f == 0.0)
    }
    fn driven_by_motion(&self) -> bool {
        true
    }
    fn add_torque(&self, _q: &[f64], _qd: &[f64], qdd: &[f64], tau: &mut [f64]) {
        for ((t, a), i) in tau.iter_mut().zip(qdd).zip(&self.ia) {
            *t += i * a;
        }
    }
    fn regressor(&self, _q: &[f64], _qd: &[f64], qdd: &[f64], y: &mut [f64]) -> bool {
        diagonal_regressor(self.ia.len(), y, |j| qdd.get(j).copied().unwrap_or(0.0));
        true
    }
}
