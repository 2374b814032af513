//! `payload`: an error in the payload at the flange (extruder, hose and material): its mass
//! `Δm` and its first moment of mass `Δh = Δ(m c)` (flange frame), so that both the mass and
//! the centre of mass of a load are identified. RNEA is linear in the inertial parameters
//! (mass, first moment, inertia), so the torque is
//! `τ = Δm · U(c₀) + Σᵢ Δhᵢ · ∂U/∂cᵢ(c₀)`, where `U(c)` is the inverse dynamics (gravity and
//! inertial) of a 1 kg point mass at `c` in the flange frame and `c₀` the nominal payload's
//! centre of mass (the flange origin when the robot has no payload). The derivative is the
//! central difference `(U(c₀ + s eᵢ) − U(c₀ − s eᵢ)) / 2s`, exact for the gravity and
//! first-moment terms (the point mass's inertia about the flange is even in `s`). Regressor
//! `[U(c₀), ∂U/∂c]` (N·m/kg, N·m/(kg·m)).
//!
//! The identified payload is `m = m₀ + Δm`, `c = c₀ + Δh / m` (its inertia about its
//! centre of mass is kept); [`Effect::fold_into`] writes it into the robot for the energy
//! model, and `identify` into the calibrated robot's `[payload]` table.

use super::{check_values, BuildContext, Effect, ParamSpec};
use crate::dynamics::{rnea, DynData, DynModel, DynOptions, MAX_DOF};
use crate::error::Result;
use crate::math::V3;
use crate::robot::{Inertial, RobotModel};
use std::sync::{Arc, Mutex};

/// Step `s` of the central difference in the CoM, m (the result does not depend on it up to
/// rounding).
const COM_STEP_M: f64 = 0.1;
/// Bound on each component of the first-moment error `|Δh|`, kg·m.
pub const PAYLOAD_MOMENT_MAX_KG_M: f64 = 1e3;

/// Payload error at the flange: mass and first moment.
#[derive(Debug, Clone)]
pub struct Payload {
    /// Mass error `Δm`, kg (≥ −nominal mass).
    pub dm: f64,
    /// First-moment error `Δh = Δ(m c)`, kg·m, flange frame.
    pub dh: [f64; 3],
    /// Nominal payload mass, kg (lower bound of `Δm` is its negative).
    pub nominal_mass: f64,
    /// Nominal payload centre of mass `c₀`, m, flange frame.
    pub nominal_com: [f64; 3],
    /// Unit point-mass models at `c₀`, `c₀ ± s eᵢ` (index 0, then `1 + 2i` and `2 + 2i`).
    units: Arc<Vec<DynModel>>,
    data: Arc<Mutex<DynData>>,
}

/// Registry entry: `Δm` from `[effects] payload_mass_error_kg` (0 by default, ≥ −nominal mass).
pub(crate) fn build(ctx: &BuildContext) -> Result<Box<dyn Effect>> {
    let mut p = Payload::new(ctx.robot)?;
    if let Some(dm) = ctx.table.payload_mass_error_kg {
        if !(dm.is_finite() && dm >= -p.nominal_mass) {
            return Err(ctx.bad(
                "payload_mass_error_kg",
                format!(
                    "must be finite and >= -{} (the nominal payload), got {dm}",
                    p.nominal_mass
                ),
            ));
        }
        p.dm = dm;
    }
    Ok(Box::new(p))
}

impl Payload {
    /// The effect for `robot` with no error. Error: the robot lacks inertials (as
    /// [`DynModel::new`]).
    pub fn new(robot: &RobotModel) -> Result<Self> {
        let mut r = robot.clone();
        for l in r.links.iter_mut() {
            *l = Some(Inertial::zero());
        }
        let com = robot.payload.map(|p| p.com).unwrap_or_else(V3::zeros);
        let mut units = Vec::with_capacity(7);
        let mut deltas = vec![V3::zeros()];
        for i in 0..3 {
            let mut d = V3::zeros();
            d[i] = COM_STEP_M;
            deltas.push(d);
            deltas.push(-d);
        }
        for d in deltas {
            let mut unit = Inertial::zero();
            unit.mass = 1.0;
            unit.com = com + d;
            r.payload = Some(unit);
            units.push(DynModel::new(
                &r,
                DynOptions {
                    payload: true,
                    armature: false,
                },
            )?);
        }
        let data = units[0].data();
        Ok(Payload {
            dm: 0.0,
            dh: [0.0; 3],
            nominal_mass: robot.payload.map_or(0.0, |p| p.mass),
            nominal_com: [com.x, com.y, com.z],
            units: Arc::new(units),
            data: Arc::new(Mutex::new(data)),
        })
    }

    /// Torque of unit point-mass model `k` (0: at `c₀`; `1 + 2i`/`2 + 2i`: at `c₀ ± s eᵢ`),
    /// N·m per kg, into `out`.
    fn unit_at(&self, k: usize, q: &[f64], qd: &[f64], qdd: &[f64], out: &mut [f64]) {
        out.iter_mut().for_each(|v| *v = 0.0);
        if let Ok(mut d) = self.data.lock() {
            let _ = rnea(&self.units[k], &mut d, q, qd, qdd, out);
        }
    }

    /// Torque of a 1 kg point mass at the nominal payload CoM (N·m per kg) into `out`.
    pub fn unit_torque(&self, q: &[f64], qd: &[f64], qdd: &[f64], out: &mut [f64]) {
        self.unit_at(0, q, qd, qdd, out);
    }

    /// The identified payload mass `m = m₀ + Δm`, kg, and centre of mass
    /// `c₀ + Δh / m`, m (flange frame; the mass error sits at `c₀`, the first-moment error
    /// moves it; `c₀` when the mass is zero).
    pub fn identified(&self) -> (f64, [f64; 3]) {
        let m = self.nominal_mass + self.dm;
        let mut c = self.nominal_com;
        if m.abs() > 1e-9 {
            for (i, ci) in c.iter_mut().enumerate() {
                *ci = (m * self.nominal_com[i] + self.dh[i]) / m;
            }
        }
        (m, c)
    }
}

impl Effect for Payload {
    fn name(&self) -> &'static str {
        "payload"
    }
    fn params(&self) -> Vec<ParamSpec> {
        let mut p = vec![ParamSpec {
            name: "dm".into(),
            unit: "kg",
            lower: -self.nominal_mass,
            upper: f64::INFINITY,
        }];
        for a in ["x", "y", "z"] {
            p.push(ParamSpec {
                name: format!("dh_{a}"),
                unit: "kg·m",
                lower: -PAYLOAD_MOMENT_MAX_KG_M,
                upper: PAYLOAD_MOMENT_MAX_KG_M,
            });
        }
        p
    }
    fn values(&self) -> Vec<f64> {
        vec![self.dm, self.dh[0], self.dh[1], self.dh[2]]
    }
    /// Accepts 4 values (`Δm`, `Δh`) or 1 (`Δm` only, as older files wrote; `Δh` = 0).
    fn set_values(&mut self, values: &[f64]) -> Result<()> {
        let full = if values.len() == 1 {
            vec![values[0], 0.0, 0.0, 0.0]
        } else {
            values.to_vec()
        };
        check_values(self.name(), &self.params(), &full)?;
        self.dm = full[0];
        self.dh = [full[1], full[2], full[3]];
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(Payload {
            data: Arc::new(Mutex::new(self.units[0].data())),
            ..self.clone()
        })
    }
    fn costly(&self) -> bool {
        true
    }
    fn is_null(&self) -> bool {
        self.dm == 0.0 && self.dh == [0.0; 3]
    }
    fn fold_into(&self, robot: &mut RobotModel) -> bool {
        if self.is_null() {
            return true;
        }
        let (m, c) = self.identified();
        let mut p = robot.payload.unwrap_or_else(Inertial::zero);
        p.mass = m;
        p.com = V3::new(c[0], c[1], c[2]);
        robot.payload = Some(p);
        true
    }
    fn add_torque(&self, q: &[f64], qd: &[f64], qdd: &[f64], tau: &mut [f64]) {
        if self.is_null() {
            return;
        }
        let n = tau.len().min(MAX_DOF);
        let mut y = [0.0; 4 * MAX_DOF];
        self.regressor(q, qd, qdd, &mut y[..4 * n]);
        let v = self.values();
        for (j, t) in tau.iter_mut().enumerate().take(n) {
            *t += (0..4).map(|k| y[j * 4 + k] * v[k]).sum::<f64>();
        }
    }
    fn regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64], y: &mut [f64]) -> bool {
        let n = y.len() / 4;
        let mut u = [0.0; MAX_DOF];
        let mut up = [0.0; MAX_DOF];
        let mut um = [0.0; MAX_DOF];
        self.unit_at(0, q, qd, qdd, &mut u[..n]);
        for j in 0..n {
            y[j * 4] = u[j];
        }
        for i in 0..3 {
            self.unit_at(1 + 2 * i, q, qd, qdd, &mut up[..n]);
            self.unit_at(2 + 2 * i, q, qd, qdd, &mut um[..n]);
            for j in 0..n {
                y[j * 4 + 1 + i] = (up[j] - um[j]) / (2.0 * COM_STEP_M);
            }
        }
        true
    }
}
