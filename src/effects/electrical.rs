//! Electrical and supply effects (seed 001, eqs. 2–4): they act after the joint torque is
//! known, so they implement [`Effect`] (name and bounded parameters) but not
//! a torque. Their contribution is evaluated by the motor model in
//! [`crate::energy`] and, with identifiable parameters, in [`crate::identify`]:
//! motor torque `τ_m = τ/(G η)` when driving and `τ η / G` when back-driven, current
//! `i = τ_m / K_t`, electrical power `P = τ_m G q̇ + R i²`.

use super::{
    check_values, per_joint, BuildContext, Effect, MotorTerm, ParamSpec, Stage, SupplyTerm,
};
use crate::error::Result;

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
        r: ctx.per_joint(|j| j.winding_resistance, 0.0),
    }))
}

/// Registry entry: `η` from the drive file's `gear_efficiency` (1 without drive data).
pub(crate) fn build_gear_efficiency(ctx: &BuildContext) -> Result<Box<dyn Effect>> {
    Ok(Box::new(GearEfficiency {
        eta: ctx.per_joint(|j| j.gear_efficiency, 1.0),
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
