//! `stribeck`: the extra breakaway friction at low speed,
//! `τ = f_s exp(−(q̇/v_s)²) tanh(q̇/ε)` (joint side), on top of Coulomb friction
//! (Olsson et al. 1998, the Stribeck curve). Not linear in `v_s`, so [`Effect::regressor`](super::Effect::regressor)
//! returns `false` and identification uses the bounded nonlinear fit.

use super::{
    check_values, BuildContext, Effect, EnergyClass, ParamSpec, COULOMB_VELOCITY_SCALE_RAD_S,
};
use crate::error::Result;

/// Default Stribeck velocity `v_s`, rad/s.
pub const STRIBECK_VELOCITY_RAD_S: f64 = 0.05;

/// Stribeck friction per joint: peaks `f_s` (N·m) and one Stribeck velocity `v_s` (rad/s).
#[derive(Clone, Debug, PartialEq)]
pub struct Stribeck {
    /// Extra breakaway torque per joint `f_s`, N·m (≥ 0).
    pub fs: Vec<f64>,
    /// Stribeck velocity `v_s`, rad/s, in [0.005, 1].
    pub vs: f64,
}

/// Registry entry: `f_s` from `[effects] stribeck_nm` (one per joint), `v_s` from
/// `stribeck_velocity_rad_s` (errors name the key).
pub(crate) fn build(ctx: &BuildContext) -> Result<Box<dyn Effect>> {
    let n = ctx.dof();
    let t = ctx.table;
    let mut s = Stribeck::zero(n);
    if let Some(fs) = &t.stribeck_nm {
        if fs.len() != n {
            return Err(ctx.bad(
                "stribeck_nm",
                format!("{} values, expected {n} (one per joint)", fs.len()),
            ));
        }
        let mut v = fs.clone();
        v.push(s.vs);
        s.set_values(&v)
            .map_err(|e| ctx.bad("stribeck_nm", e.to_string()))?;
    }
    if let Some(vs) = t.stribeck_velocity_rad_s {
        let mut v = s.values();
        v[n] = vs;
        s.set_values(&v)
            .map_err(|e| ctx.bad("stribeck_velocity_rad_s", e.to_string()))?;
    }
    Ok(Box::new(s))
}

impl Stribeck {
    /// No Stribeck friction on `n` joints (`f_s = 0`, `v_s` = [`STRIBECK_VELOCITY_RAD_S`]).
    pub fn zero(n: usize) -> Self {
        Stribeck {
            fs: vec![0.0; n],
            vs: STRIBECK_VELOCITY_RAD_S,
        }
    }
    /// Shape `exp(−(q̇/v_s)²) tanh(q̇/ε)` (dimensionless) at velocity `qd` rad/s.
    pub fn shape(&self, qd: f64) -> f64 {
        (-(qd / self.vs).powi(2)).exp() * crate::fastmath::tanh(qd / COULOMB_VELOCITY_SCALE_RAD_S)
    }
    /// Torque of joint `j` at velocity `qd` rad/s, N·m (0 where `f_s = 0`). No allocation.
    #[inline]
    pub fn joint_torque(&self, j: usize, qd: f64) -> f64 {
        match self.fs.get(j) {
            Some(&f) if f != 0.0 => f * self.shape(qd),
            _ => 0.0,
        }
    }
}

impl Effect for Stribeck {
    fn name(&self) -> &'static str {
        "stribeck"
    }
    /// Implausible when a fitted value is below zero or the Stribeck velocity is not
    /// positive.
    fn implausible_fit(&self, std_errors: &[Option<f64>]) -> Option<String> {
        let (specs, v) = (self.params(), self.values());
        let mut why = super::plausible::negative_fitted(&specs, &v, std_errors);
        if let Some((s, x)) = specs
            .iter()
            .zip(&v)
            .find(|(s, _)| s.name.starts_with("v_s"))
        {
            if *x <= 0.0 {
                why.push(format!("{} = {x} {} is not > 0", s.name, s.unit));
            }
        }
        super::plausible::reasons(why)
    }
    fn effects_keys(&self) -> &'static [&'static str] {
        &["stribeck_nm", "stribeck_velocity_rad_s"]
    }
    fn params(&self) -> Vec<ParamSpec> {
        let mut p = super::per_joint("f_s", "N·m", self.fs.len());
        p.push(ParamSpec {
            name: "v_s".into(),
            unit: "rad/s",
            lower: 0.005,
            upper: 1.0,
        });
        p
    }
    fn values(&self) -> Vec<f64> {
        let mut v = self.fs.clone();
        v.push(self.vs);
        v
    }
    fn set_values(&mut self, values: &[f64]) -> Result<()> {
        check_values(self.name(), &self.params(), values)?;
        let n = self.fs.len();
        self.fs.copy_from_slice(&values[..n]);
        self.vs = values[n];
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
        self.fs.iter().all(|f| *f == 0.0)
    }
    fn driven_by_motion(&self) -> bool {
        true
    }
    fn add_torque(&self, _q: &[f64], qd: &[f64], _qdd: &[f64], tau: &mut [f64]) {
        for (j, (t, v)) in tau.iter_mut().zip(qd).enumerate() {
            *t += self.joint_torque(j, *v);
        }
    }
}
