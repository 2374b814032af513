//! `offset`: a constant torque per joint, `τ = τ_0` (N·m): a torque-sensor or current offset,
//! or a cable pull that does not change over the motion. Linear: regressor `Y = I`.

use super::{check_values, diagonal_regressor, per_joint_bounded, BuildContext, Effect, ParamSpec};
use crate::error::Result;

/// Bound on `|τ_0|`, N·m: an offset larger than this is not an offset.
pub(crate) const OFFSET_MAX_NM: f64 = 1e4;

/// Constant torque per joint.
#[derive(Clone, Debug, PartialEq)]
pub struct Offset {
    /// `τ_0` per joint, N·m (in [−[`OFFSET_MAX_NM`], +[`OFFSET_MAX_NM`]]).
    pub tau0: Vec<f64>,
}

/// Registry entry: zero on every joint unless `[effects.values] offset` gives values.
pub(crate) fn build(ctx: &BuildContext) -> Result<Box<dyn Effect>> {
    Ok(Box::new(Offset {
        tau0: vec![0.0; ctx.dof()],
    }))
}

impl Effect for Offset {
    fn name(&self) -> &'static str {
        "offset"
    }
    fn params(&self) -> Vec<ParamSpec> {
        per_joint_bounded(
            "tau0",
            "N·m",
            self.tau0.len(),
            -OFFSET_MAX_NM,
            OFFSET_MAX_NM,
        )
    }
    fn values(&self) -> Vec<f64> {
        self.tau0.clone()
    }
    fn set_values(&mut self, values: &[f64]) -> Result<()> {
        check_values(self.name(), &self.params(), values)?;
        self.tau0.copy_from_slice(values);
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn is_null(&self) -> bool {
        self.tau0.iter().all(|f| *f == 0.0)
    }
    fn add_torque(&self, _q: &[f64], _qd: &[f64], _qdd: &[f64], tau: &mut [f64]) {
        for (t, o) in tau.iter_mut().zip(&self.tau0) {
            *t += o;
        }
    }
    fn regressor(&self, _q: &[f64], _qd: &[f64], _qdd: &[f64], y: &mut [f64]) -> bool {
        diagonal_regressor(self.tau0.len(), y, |_| 1.0);
        true
    }
}
