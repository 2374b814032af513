//! Electrical and supply effects (seed 001, eqs. 2–4): they act after the joint torque is
//! known, so they implement [`Effect`] (name and bounded parameters) but not
//! a torque. Their contribution is evaluated by the motor model in
//! [`crate::energy`] and, with identifiable parameters, in [`crate::identify`]:
//! motor torque `τ_m = τ/(G η)` when driving and `τ η / G` when back-driven, current
//! `i = τ_m / K_t`, electrical power `P = τ_m G q̇ + R i²`.

use super::plausible;
use super::uncertain::at;
use super::{
    check_values, per_joint, BuildContext, DrawPhase, Drawing, DriveKept, DriveKeysMut, Effect,
    MotorTerm, ParamSpec, Stage, SupplyTerm, Uncertainty,
};
use crate::error::Result;

/// The drive file's `[[joints]]` key holding `R` (Ω), read and written by `copper`.
const COPPER_DRIVE_KEY: &str = "winding_resistance_ohm";
/// The drive file's `[[joints]]` key holding `η`, read and written by `gear_efficiency`.
const GEAR_EFFICIENCY_DRIVE_KEY: &str = "gear_efficiency";

/// `copper`: winding resistance per axis `R`, Ω; loss `R i²` (W).
#[derive(Clone, Debug, PartialEq)]
pub struct Copper {
    /// `R` per axis, Ω (≥ 0).
    pub r: Vec<f64>,
}

/// `gear_efficiency`: gearbox efficiency per axis `η` in [0.3, 1] (dimensionless).
#[derive(Clone, Debug, PartialEq)]
pub struct GearEfficiency {
    /// `η` per axis.
    pub eta: Vec<f64>,
}

/// `regeneration`: the fraction `ρ` in [0, 1] of the power the drives' regeneration policy
/// burns (brake resistor) that is in fact recovered: supply draw
/// `P_drives − ρ (P_drives − Σ P_el)` (W).
#[derive(Clone, Debug, PartialEq)]
pub struct Regeneration {
    /// Recovered fraction `ρ` (dimensionless).
    pub recovered: f64,
}

/// `standby`: the cabinet's constant draw `P_0`, W (≥ 0).
#[derive(Clone, Debug, PartialEq)]
pub struct Standby {
    /// `P_0`, W.
    pub power: f64,
}

impl Effect for Copper {
    fn name(&self) -> &'static str {
        "copper"
    }
    /// Implausible when a fitted `R` is not positive: no winding has zero resistance.
    fn implausible_fit(&self, std_errors: &[Option<f64>]) -> Option<String> {
        let mut why = Vec::new();
        for (i, (s, x)) in self.params().iter().zip(&self.r).enumerate() {
            if *x <= 0.0 && plausible::fitted(std_errors, i) {
                why.push(format!(
                    "{} = {x:.4} {}: no winding has zero or negative resistance",
                    s.name, s.unit
                ));
            }
        }
        plausible::reasons(why)
    }
    /// `[[joints]] winding_resistance_ohm`.
    fn write_drive_keys(&self, keys: &mut DriveKeysMut<'_>) -> Result<DriveKept> {
        keys.set_joints(COPPER_DRIVE_KEY, &self.r)?;
        Ok(DriveKept::Keys)
    }
    fn uncertainty(&self) -> Option<Uncertainty> {
        at(DrawPhase::Joint, 0)
    }
    /// The joint's torque constant (± `torque_constant_rel`) and winding resistance
    /// (± `winding_resistance_rel`). An identified `R` was fitted with the torque constant
    /// held: what the log determines is `R/k_t²` (the copper loss `R (τ/k_t)²`), drawn with
    /// its standard error; `k_t` is then not drawn again.
    fn draw(&self, d: &mut Drawing<'_>, joint: Option<usize>) {
        let Some(j) = joint else { return };
        let r_cal = d.identified_factor(&format!("R[{}]", j + 1));
        if r_cal.is_none() {
            let kt = 1.0 + d.ranges.torque_constant_rel * d.uniform();
            if let Some(jd) = d.joint(j) {
                jd.torque_constant *= kt;
            }
            d.record(format!("torque constant joint {}", j + 1), kt);
        }
        let rr = match r_cal {
            Some(f) => f,
            None => 1.0 + d.ranges.winding_resistance_rel * d.uniform(),
        };
        if let Some(jd) = d.joint(j) {
            jd.winding_resistance *= rr;
        }
        d.record(format!("winding resistance joint {}", j + 1), rr);
    }
    fn params(&self) -> Vec<ParamSpec> {
        per_joint("R", "Ω", self.r.len())
    }
    fn values(&self) -> Vec<f64> {
        self.r.clone()
    }
    fn set_values(&mut self, values: &[f64]) -> Result<()> {
        check_values(self.name(), &self.params(), values)?;
        self.r.copy_from_slice(values);
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn stage(&self) -> Stage {
        Stage::Motor(MotorTerm::WindingResistance)
    }
}

impl Effect for GearEfficiency {
    fn name(&self) -> &'static str {
        "gear_efficiency"
    }
    /// Implausible when an efficiency lies outside (0, 1].
    fn implausible_fit(&self, _std_errors: &[Option<f64>]) -> Option<String> {
        let mut why = Vec::new();
        for (s, x) in self.params().iter().zip(&self.eta) {
            if !(*x > 0.0 && *x <= 1.0) {
                why.push(format!("{} = {x:.4} outside (0, 1]", s.name));
            }
        }
        plausible::reasons(why)
    }
    /// `[[joints]] gear_efficiency`.
    fn write_drive_keys(&self, keys: &mut DriveKeysMut<'_>) -> Result<DriveKept> {
        keys.set_joints(GEAR_EFFICIENCY_DRIVE_KEY, &self.eta)?;
        Ok(DriveKept::Keys)
    }
    fn uncertainty(&self) -> Option<Uncertainty> {
        at(DrawPhase::Joint, 4)
    }
    /// The joint's gear efficiency: identified, normal with its standard error; else
    /// ± `gear_efficiency_abs` (absolute); kept within [0.3, 1].
    fn draw(&self, d: &mut Drawing<'_>, joint: Option<usize>) {
        let Some(j) = joint else { return };
        let Some(eta) = d.joint(j).map(|jd| jd.gear_efficiency) else {
            return;
        };
        let de = match d.identified(&format!("eta[{}]", j + 1)) {
            Some((v, dv)) => (v + dv).clamp(0.3, 1.0) - eta,
            None => d.ranges.gear_efficiency_abs * d.uniform(),
        };
        if let Some(jd) = d.joint(j) {
            jd.gear_efficiency = (jd.gear_efficiency + de).clamp(0.3, 1.0);
        }
        d.record(format!("gear efficiency joint {}", j + 1), de);
    }
    fn params(&self) -> Vec<ParamSpec> {
        per_joint("eta", "1", self.eta.len())
            .into_iter()
            .map(|mut p| {
                p.lower = 0.3;
                p.upper = 1.0;
                p
            })
            .collect()
    }
    fn values(&self) -> Vec<f64> {
        self.eta.clone()
    }
    fn set_values(&mut self, values: &[f64]) -> Result<()> {
        check_values(self.name(), &self.params(), values)?;
        self.eta.copy_from_slice(values);
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn stage(&self) -> Stage {
        Stage::Motor(MotorTerm::GearEfficiency)
    }
}

impl Effect for Regeneration {
    fn name(&self) -> &'static str {
        "regeneration"
    }
    /// Implausible when the recovered fraction lies outside [0, 1].
    fn implausible_fit(&self, _std_errors: &[Option<f64>]) -> Option<String> {
        let mut why = Vec::new();
        for (s, x) in self.params().iter().zip(&self.values()) {
            if !(0.0..=1.0).contains(x) {
                why.push(format!("{} = {x:.4} outside [0, 1]", s.name));
            }
        }
        plausible::reasons(why)
    }
    fn effects_keys(&self) -> &'static [&'static str] {
        &["regeneration_recovered_fraction"]
    }
    fn params(&self) -> Vec<ParamSpec> {
        vec![ParamSpec {
            name: "rho".into(),
            unit: "1",
            lower: 0.0,
            upper: 1.0,
        }]
    }
    fn values(&self) -> Vec<f64> {
        vec![self.recovered]
    }
    fn set_values(&mut self, values: &[f64]) -> Result<()> {
        check_values(self.name(), &self.params(), values)?;
        self.recovered = values[0];
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn stage(&self) -> Stage {
        Stage::Supply(SupplyTerm::Regeneration)
    }
}

impl Effect for Standby {
    fn name(&self) -> &'static str {
        "standby"
    }
    /// Implausible when a fitted value is below zero.
    fn implausible_fit(&self, std_errors: &[Option<f64>]) -> Option<String> {
        super::plausible::implausible_if_negative(self, std_errors)
    }
    /// `[cabinet] standby_power_w` (when the file has a `[cabinet]` table).
    fn write_drive_keys(&self, keys: &mut DriveKeysMut<'_>) -> Result<DriveKept> {
        keys.set_cabinet("standby_power_w", self.power)?;
        Ok(DriveKept::Keys)
    }
    fn uncertainty(&self) -> Option<Uncertainty> {
        at(DrawPhase::Cabinet, 0)
    }
    /// The cabinet's standby power: identified, normal with its standard error; else
    /// ± `standby_power_rel`.
    fn draw(&self, d: &mut Drawing<'_>, _joint: Option<usize>) {
        let rel = d.ranges.standby_power_rel;
        let sb = d.factor("P0", rel, "standby power");
        if let Some(dr) = d.robot.drive.as_mut() {
            dr.standby_power *= sb;
        }
    }
    fn params(&self) -> Vec<ParamSpec> {
        vec![ParamSpec {
            name: "P0".into(),
            unit: "W",
            lower: 0.0,
            upper: f64::INFINITY,
        }]
    }
    fn values(&self) -> Vec<f64> {
        vec![self.power]
    }
    fn set_values(&mut self, values: &[f64]) -> Result<()> {
        check_values(self.name(), &self.params(), values)?;
        self.power = values[0];
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn stage(&self) -> Stage {
        Stage::Supply(SupplyTerm::Standby)
    }
}

/// Registry entry: `R` from the drive file's `winding_resistance_ohm` (zeros without drive data).
pub(crate) fn build_copper(ctx: &BuildContext) -> Result<Box<dyn Effect>> {
    Ok(Box::new(Copper {
        r: ctx.joint_key(COPPER_DRIVE_KEY, 0.0)?,
    }))
}

/// Registry entry: `η` from the drive file's `gear_efficiency` (1 without drive data).
pub(crate) fn build_gear_efficiency(ctx: &BuildContext) -> Result<Box<dyn Effect>> {
    Ok(Box::new(GearEfficiency {
        eta: ctx.joint_key(GEAR_EFFICIENCY_DRIVE_KEY, 1.0)?,
    }))
}

/// Registry entry: `ρ` from `[effects] regeneration_recovered_fraction` (0 by default).
pub(crate) fn build_regeneration(ctx: &BuildContext) -> Result<Box<dyn Effect>> {
    let mut r = Regeneration { recovered: 0.0 };
    if let Some(rho) = ctx.table.regeneration_recovered_fraction {
        r.set_values(&[rho])
            .map_err(|e| ctx.bad("regeneration_recovered_fraction", e.to_string()))?;
    }
    Ok(Box::new(r))
}

/// Registry entry: `P_0` from the drive file's `[cabinet] standby_power_w` (0 without drive
/// data).
pub(crate) fn build_standby(ctx: &BuildContext) -> Result<Box<dyn Effect>> {
    Ok(Box::new(Standby {
        power: ctx.robot.drive.as_ref().map_or(0.0, |d| d.standby_power),
    }))
}
