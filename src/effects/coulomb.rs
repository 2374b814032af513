//! `coulomb`: joint-side Coulomb friction with a value per direction and an identified
//! transition width (seed 000, eq. 2, second term; direction-dependent as in Corke &
//! Armstrong-Hélouvry 1994):
//! `τ = f_c+ · max(s, 0) + f_c− · min(s, 0)`, `s = tanh(q̇ / ε)`,
//! so `τ → +f_c+` when moving forward, `τ → −f_c−` when moving back, and the sign changes
//! smoothly over `|q̇| ≲ 3ε`. Linear in `f_c±` for a fixed `ε`; with `ε` a parameter the effect
//! is fitted by the bounded nonlinear fit ([`Effect::regressor`] returns `false`).

use super::uncertain::at;
use super::{
    check_values, per_joint, BuildContext, DrawPhase, Drawing, DriveKept, DriveKeysMut, Effect,
    EnergyClass, ParamSpec, Uncertainty,
};
use crate::error::Result;

/// The drive file's `[[joints]]` key holding `f_c` (N·m, both directions), read and written
/// here.
const DRIVE_KEY: &str = "coulomb_nm";

/// Default transition width ε of the smoothed sign, rad/s: at |q̇| = 3ε the friction reaches
/// 99.5 % of `f_c`. Small against path speeds (≥ 0.01 rad/s in printing), large enough to keep
/// the torque continuous across velocity reversals of sampled paths.
pub const COULOMB_VELOCITY_SCALE_RAD_S: f64 = 1e-3;
/// Bounds of the identified transition width ε, rad/s.
pub(crate) const COULOMB_WIDTH_BOUNDS_RAD_S: (f64, f64) = (1e-4, 0.2);

/// Coulomb friction per joint and direction, N·m (joint side), sign smoothed with `tanh(q̇/ε)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Coulomb {
    /// `f_c+` per joint (moving forward, `q̇ > 0`), N·m (≥ 0).
    pub fc_pos: Vec<f64>,
    /// `f_c−` per joint (moving back, `q̇ < 0`), N·m (≥ 0).
    pub fc_neg: Vec<f64>,
    /// Transition width ε of the smoothed sign, rad/s (in [`COULOMB_WIDTH_BOUNDS_RAD_S`]).
    pub velocity_scale: f64,
}

/// Registry entry: `f_c+ = f_c− = coulomb_nm` from the drive file (zeros without drive
/// data), ε = [`COULOMB_VELOCITY_SCALE_RAD_S`].
pub(crate) fn build(ctx: &BuildContext) -> Result<Box<dyn Effect>> {
    let fc = ctx.joint_key(DRIVE_KEY, 0.0)?;
    Ok(Box::new(Coulomb::symmetric(
        fc,
        COULOMB_VELOCITY_SCALE_RAD_S,
    )))
}

impl Coulomb {
    /// The same `f_c` in both directions (N·m per joint), width `eps` rad/s.
    pub fn symmetric(fc: Vec<f64>, eps: f64) -> Self {
        Coulomb {
            fc_neg: fc.clone(),
            fc_pos: fc,
            velocity_scale: eps,
        }
    }

    /// From the drive file's `coulomb_nm`, with velocity scale `eps` rad/s (non-positive or
    /// non-finite values fall back to [`COULOMB_VELOCITY_SCALE_RAD_S`]).
    pub fn from_drive(drive: &crate::robot::Drive, eps: f64) -> Self {
        Coulomb::symmetric(
            drive.joints.iter().map(|j| j.coulomb).collect(),
            if eps.is_finite() && eps > 0.0 {
                eps
            } else {
                COULOMB_VELOCITY_SCALE_RAD_S
            },
        )
    }

    /// Smoothed sign `tanh(q̇/ε)` (dimensionless).
    #[inline]
    pub fn smooth_sign(&self, qd: f64) -> f64 {
        crate::fastmath::tanh(qd / self.velocity_scale)
    }

    /// Torque of joint `j` at velocity `qd` rad/s, N·m.
    #[inline]
    pub fn joint_torque(&self, j: usize, qd: f64) -> f64 {
        let (Some(&p), Some(&n)) = (self.fc_pos.get(j), self.fc_neg.get(j)) else {
            return 0.0;
        };
        if p == 0.0 && n == 0.0 {
            return 0.0;
        }
        let s = self.smooth_sign(qd);
        if s >= 0.0 {
            p * s
        } else {
            n * s
        }
    }
}

impl Effect for Coulomb {
    fn name(&self) -> &'static str {
        "coulomb"
    }
    /// Implausible when a fitted value is below zero.
    fn implausible_fit(&self, std_errors: &[Option<f64>]) -> Option<String> {
        super::plausible::implausible_if_negative(self, std_errors)
    }
    /// `[[joints]] coulomb_nm` holds one value per joint: the mean of both directions; the
    /// values per direction and the transition width go to `[effects.values]` too (which
    /// wins).
    fn write_drive_keys(&self, keys: &mut DriveKeysMut<'_>) -> Result<DriveKept> {
        let fc: Vec<f64> = self
            .fc_pos
            .iter()
            .zip(&self.fc_neg)
            .map(|(p, n)| 0.5 * (p + n))
            .collect();
        keys.set_joints(DRIVE_KEY, &fc)?;
        Ok(DriveKept::KeysAndValues)
    }
    fn uncertainty(&self) -> Option<Uncertainty> {
        at(DrawPhase::Joint, 3)
    }
    /// `coulomb_nm` of the joint: ± `coulomb_rel` (an identified `f_c±` lives in
    /// `[effects.values]` and is drawn there).
    fn draw(&self, d: &mut Drawing<'_>, joint: Option<usize>) {
        let Some(j) = joint else { return };
        let rel = d.ranges.coulomb_rel;
        let label = format!("Coulomb friction joint {}", j + 1);
        let fc = d.factor(&format!("f_c[{}]", j + 1), rel, label);
        if let Some(jd) = d.joint(j) {
            jd.coulomb *= fc;
        }
    }
    fn params(&self) -> Vec<ParamSpec> {
        let n = self.fc_pos.len();
        let mut p = per_joint("f_c+", "N·m", n);
        p.extend(per_joint("f_c-", "N·m", n));
        p.push(ParamSpec {
            name: "eps".into(),
            unit: "rad/s",
            lower: COULOMB_WIDTH_BOUNDS_RAD_S.0,
            upper: COULOMB_WIDTH_BOUNDS_RAD_S.1,
        });
        p
    }
    fn values(&self) -> Vec<f64> {
        let mut v = self.fc_pos.clone();
        v.extend_from_slice(&self.fc_neg);
        v.push(self.velocity_scale);
        v
    }
    /// Accepts `2n + 1` values (`f_c+`, `f_c−`, ε), `2n` (ε kept) or `n` (the same `f_c` in
    /// both directions, as older calibrated files wrote).
    fn set_values(&mut self, values: &[f64]) -> Result<()> {
        let n = self.fc_pos.len();
        let mut full = self.values();
        if values.len() == n {
            full[..n].copy_from_slice(values);
            full[n..2 * n].copy_from_slice(values);
        } else if values.len() == 2 * n {
            full[..2 * n].copy_from_slice(values);
        } else {
            full = values.to_vec();
        }
        check_values(self.name(), &self.params(), &full)?;
        self.fc_pos.copy_from_slice(&full[..n]);
        self.fc_neg.copy_from_slice(&full[n..2 * n]);
        self.velocity_scale = full[2 * n];
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
        self.fc_pos.iter().chain(&self.fc_neg).all(|f| *f == 0.0)
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
