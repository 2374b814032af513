//! `balancer`: the gravity balancer of axis 2 of large arms, a spring or gas cylinder between
//! link 1 and link 2. Simple geometry: the cylinder's fixed end sits at distance `a` from the
//! axis-2 pivot on link 1, its moving end at distance `b` on link 2, the angle between the two
//! lever arms being `q2 + φ0`. Its length is `L(q2) = √(a² + b² − 2ab cos(q2 + φ0))`, its force
//! `F = F0 + k (L − L(0))` (preload `F0`, stiffness `k`), and the joint torque it takes off the
//! motor is `F dL/dq2`, `dL/dq2 = a b sin(q2 + φ0) / L`. The contribution to the required joint
//! torque is therefore `τ2 = −(F0 + k ΔL) dL/dq2`: linear in (`F0`, `k`).

use super::{check_values, Effect, ParamSpec, TorqueEffect};
use crate::error::Result;

/// Default lever on link 1, m.
pub const BALANCER_A_M: f64 = 0.25;
/// Default lever on link 2, m.
pub const BALANCER_B_M: f64 = 0.55;
/// Default angle between the levers at `q2 = 0`, rad.
pub const BALANCER_PHI0_RAD: f64 = std::f64::consts::FRAC_PI_2;

/// Axis-2 balancer with fixed geometry and identifiable preload and stiffness.
#[derive(Clone, Debug, PartialEq)]
pub struct Balancer {
    /// Index (0-based) of the joint it acts on (1 = axis 2).
    pub joint: usize,
    /// Lever on link 1, m.
    pub a: f64,
    /// Lever on link 2, m.
    pub b: f64,
    /// Angle between the levers at `q = 0`, rad.
    pub phi0: f64,
    /// Preload force `F0`, N (≥ 0).
    pub preload: f64,
    /// Stiffness `k`, N/m (≥ 0).
    pub stiffness: f64,
}

impl Balancer {
    /// A balancer on axis 2 with the default geometry and no force.
    pub fn zero() -> Self {
        Balancer {
            joint: 1,
            a: BALANCER_A_M,
            b: BALANCER_B_M,
            phi0: BALANCER_PHI0_RAD,
            preload: 0.0,
            stiffness: 0.0,
        }
    }
    /// Cylinder length `L(q)`, m, at joint angle `q` rad.
    pub fn length(&self, q: f64) -> f64 {
        (self.a * self.a + self.b * self.b - 2.0 * self.a * self.b * (q + self.phi0).cos())
            .max(1e-12)
            .sqrt()
    }
    /// The two regressor entries `[−dL/dq, −ΔL dL/dq]` (m, m²) at joint angle `q` rad.
    pub fn shape(&self, q: f64) -> [f64; 2] {
        let l = self.length(q);
        let dl = self.a * self.b * (q + self.phi0).sin() / l;
        let delta = l - self.length(0.0);
        [-dl, -delta * dl]
    }
    /// Torque on joint [`Balancer::joint`] at its angle `q` rad, N·m: `−(F0 + k ΔL) dL/dq`.
    #[inline]
    pub fn joint_torque(&self, q: f64) -> f64 {
        let s = self.shape(q);
        s[0] * self.preload + s[1] * self.stiffness
    }
}

impl Effect for Balancer {
    fn name(&self) -> &'static str {
        "balancer"
    }
    fn params(&self) -> Vec<ParamSpec> {
        vec![
            ParamSpec {
                name: "F0".into(),
                unit: "N",
                lower: 0.0,
                upper: f64::INFINITY,
            },
            ParamSpec {
                name: "k".into(),
                unit: "N/m",
                lower: 0.0,
                upper: f64::INFINITY,
            },
        ]
    }
    fn values(&self) -> Vec<f64> {
        vec![self.preload, self.stiffness]
    }
    fn set_values(&mut self, values: &[f64]) -> Result<()> {
        check_values(self.name(), &self.params(), values)?;
        self.preload = values[0];
        self.stiffness = values[1];
        Ok(())
    }
}

impl TorqueEffect for Balancer {
    fn add_torque(&self, q: &[f64], _qd: &[f64], _qdd: &[f64], tau: &mut [f64]) {
        if let (Some(q), Some(t)) = (q.get(self.joint), tau.get_mut(self.joint)) {
            *t += self.joint_torque(*q);
        }
    }
    fn regressor(&self, q: &[f64], _qd: &[f64], _qdd: &[f64], y: &mut [f64]) -> bool {
        y.iter_mut().for_each(|v| *v = 0.0);
        if let Some(qj) = q.get(self.joint) {
            let s = self.shape(*qj);
            if y.len() >= 2 * (self.joint + 1) {
                y[2 * self.joint] = s[0];
                y[2 * self.joint + 1] = s[1];
            }
        }
        true
    }
}
