//! Electrical and supply effects (seed 001, eqs. 2–4): they act after the joint torque is
//! known, so they implement [`Effect`] (name and bounded parameters) but not
//! [`super::TorqueEffect`]. Their contribution is evaluated by the motor model in
//! [`crate::energy`] and, with identifiable parameters, in [`crate::identify`]:
//! motor torque `τ_m = τ/(G η)` when driving and `τ η / G` when back-driven, current
//! `i = τ_m / K_t`, electrical power `P = τ_m G q̇ + R i²`.

use super::{check_values, per_joint, Effect, ParamSpec};
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
}
