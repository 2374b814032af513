//! `payload`: an error in the payload at the flange (extruder, hose and material): its mass
//! `Δm` (at the nominal centre of mass `c₀`), its first moment of mass `Δh` and its inertia
//! about the flange origin `ΔI_o` (flange frame), so that the mass, the centre of mass and the
//! rotational inertia of a load are identified. RNEA is linear in a body's standard inertial
//! parameters `(m, h = m c, I_o)` (mass, first moment, inertia about the frame origin), so the
//! torque is exactly
//! `τ = Δm · U(c₀) + Σᵢ Δhᵢ · ∂U/∂cᵢ(c₀) + Σ_k ΔI_k · J_k`,
//! where `U(c)` is the inverse dynamics (gravity and inertial) of a 1 kg point mass at `c` in
//! the flange frame, `∂U/∂cᵢ` its central difference `(U(c₀ + s eᵢ) − U(c₀ − s eᵢ)) / 2s`
//! (exact: `U` is quadratic in `c`) and `J_k` the torque of a massless body whose inertia about
//! the flange origin is the `k`-th basis tensor (`xx, yy, zz, xy, xz, yz`). Regressor
//! `[U(c₀), ∂U/∂c, J]` (N·m/kg, N·m/(kg·m), N·m/(kg·m²)). Moving first moment `Δh` carries the
//! point-mass inertia with it to first order; when only the mass and the centre of mass are
//! fitted, `ΔI_o` follows them as `P(Δh)/m` ([`Payload::held_inertia_error`]), so the load keeps
//! its own inertia about its centre of mass exactly.
//!
//! With `P(c) = |c|² 1 − c cᵀ` (a unit point mass's inertia about the origin), the identified
//! payload has `m = m₀ + Δm`, `h = (m₀ + Δm) c₀ + Δh`,
//! `I_o = I_c,0 + (m₀ + Δm) P(c₀) + 2 (c₀·Δh) 1 − (Δh c₀ᵀ + c₀ Δhᵀ) + ΔI_o`; its centre of mass
//! is `c = h / m` and its inertia about that centre `I_c = I_o − m P(c)`. [`Effect::fold_into`] writes
//! exactly that body into the robot, so the energy model, `compare` and the calibrated robot
//! `identify` writes evaluate the same torque the fit scored (to rounding).

use super::plausible::{
    self, se, PAYLOAD_INERTIA_TOL_KG_M2, PAYLOAD_MAX_COM_M, PAYLOAD_MOVING_MASS_SHARE,
    PAYLOAD_RATED_FACTOR, PLAUSIBILITY_SIGMAS,
};
use super::uncertain::at;
use super::{
    check_values, BuildContext, DrawPhase, Drawing, DriveKept, DriveKeysMut, Effect, ParamSpec,
    Uncertainty,
};
use crate::dynamics::{rnea, DynData, DynModel, DynOptions, MAX_DOF};
use crate::error::Result;
use crate::math::{M3, V3};
use crate::robot::{Inertial, RobotModel};
use std::sync::{Arc, Mutex};

/// The drive file's `[effects]` key holding `Δm` (kg), read here.
const MASS_ERROR_KEY: &str = "payload_mass_error_kg";
/// Step `s` of the central difference of the first moment, m (the result does not depend on
/// it up to rounding).
const COM_STEP_M: f64 = 0.1;
/// Bound on each component of the first-moment error `|Δh|`, kg·m.
pub(crate) const PAYLOAD_MOMENT_MAX_KG_M: f64 = 1e3;
/// Bound on each component of the inertia error `|ΔI_o|`, kg·m².
pub(crate) const PAYLOAD_INERTIA_MAX_KG_M2: f64 = 1e3;
/// Number of parameters: `Δm`, `Δh` (3), `ΔI_o` (6).
pub(crate) const PAYLOAD_PARAMS: usize = 10;
/// Names of the inertia components, in parameter order.
pub(crate) const PAYLOAD_INERTIA_NAMES: [&str; 6] = ["xx", "yy", "zz", "xy", "xz", "yz"];

/// Payload error at the flange: mass, first moment and inertia about the flange origin.
#[derive(Debug, Clone)]
pub struct Payload {
    /// Mass error `Δm`, kg (≥ −nominal mass), placed at the nominal centre of mass `c₀`.
    pub dm: f64,
    /// First-moment error `Δh = Δ(m c)`, kg·m, flange frame.
    pub dh: [f64; 3],
    /// Inertia error about the flange origin `ΔI_o` (`xx, yy, zz, xy, xz, yz`), kg·m², flange
    /// frame.
    pub di: [f64; 6],
    /// Nominal payload mass, kg (lower bound of `Δm` is its negative).
    pub nominal_mass: f64,
    /// Nominal payload centre of mass `c₀`, m, flange frame.
    pub nominal_com: [f64; 3],
    /// Nominal payload inertia about its centre of mass, kg·m², flange axes.
    pub nominal_inertia: M3,
    /// The robot's rated payload, kg (drive file `[robot] rated_payload_kg`), if stated: the
    /// scale of a plausible payload mass.
    rated_payload_kg: Option<f64>,
    /// Total mass of the robot's moving links, kg: the scale of a plausible payload mass
    /// without a rated payload.
    moving_mass_kg: f64,
    /// Unit models: a point mass at `c₀` (index 0), at `c₀ ± s eᵢ` (`1 + 2i`, `2 + 2i`), a massless
    /// body with basis inertia `k` about the origin (`7 + k`).
    units: Arc<Vec<DynModel>>,
    data: Arc<Mutex<DynData>>,
}

/// Symmetric tensor from `xx, yy, zz, xy, xz, yz`.
pub(crate) fn sym_from6(v: &[f64; 6]) -> M3 {
    M3::new(v[0], v[3], v[4], v[3], v[1], v[5], v[4], v[5], v[2])
}

/// `xx, yy, zz, xy, xz, yz` of a symmetric tensor (the inverse of [`sym_from6`]).
fn six_of(m: &M3) -> [f64; 6] {
    [
        m[(0, 0)],
        m[(1, 1)],
        m[(2, 2)],
        m[(0, 1)],
        m[(0, 2)],
        m[(1, 2)],
    ]
}

/// `|c|² 1 − c cᵀ`: the inertia of a unit point mass at `c` about the origin.
fn point_inertia(c: &V3) -> M3 {
    M3::identity() * c.dot(c) - c * c.transpose()
}

/// Registry entry: `Δm` from `[effects] payload_mass_error_kg` (0 by default, ≥ −nominal mass).
pub(crate) fn build(ctx: &BuildContext) -> Result<Box<dyn Effect>> {
    let mut p = Payload::new(ctx.robot)?;
    if let Some(dm) = ctx.table.payload_mass_error_kg {
        if !(dm.is_finite() && dm >= -p.nominal_mass) {
            return Err(ctx.bad(
                MASS_ERROR_KEY,
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
        let mut bodies = Vec::with_capacity(13);
        let point = |c: V3| {
            let mut u = Inertial::zero();
            u.mass = 1.0;
            u.com = c;
            u
        };
        bodies.push(point(com));
        for i in 0..3 {
            let mut d = V3::zeros();
            d[i] = COM_STEP_M;
            bodies.push(point(com + d));
            bodies.push(point(com - d));
        }
        for k in 0..6 {
            let mut e = [0.0; 6];
            e[k] = 1.0;
            let mut u = Inertial::zero();
            u.inertia = sym_from6(&e);
            bodies.push(u);
        }
        let mut units = Vec::with_capacity(bodies.len());
        for b in bodies {
            r.payload = Some(b);
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
            di: [0.0; 6],
            nominal_mass: robot.payload.map_or(0.0, |p| p.mass),
            nominal_com: [com.x, com.y, com.z],
            nominal_inertia: robot.payload.map_or_else(M3::zeros, |p| p.inertia),
            rated_payload_kg: robot.info.rated_payload_kg,
            moving_mass_kg: robot.moving_mass(),
            units: Arc::new(units),
            data: Arc::new(Mutex::new(data)),
        })
    }

    /// The largest payload mass that is plausible for the robot, kg
    /// ([`plausible::PAYLOAD_RATED_FACTOR`] × the rated payload; without one,
    /// [`plausible::PAYLOAD_MOVING_MASS_SHARE`] of the moving links' mass).
    pub(crate) fn mass_limit(&self) -> f64 {
        match self.rated_payload_kg {
            Some(r) if r > 0.0 => PAYLOAD_RATED_FACTOR * r,
            _ => PAYLOAD_MOVING_MASS_SHARE * self.moving_mass_kg,
        }
    }

    /// Torque of unit model `k` (see the field `units`) into `out`.
    fn unit_at(&self, k: usize, q: &[f64], qd: &[f64], qdd: &[f64], out: &mut [f64]) {
        out.iter_mut().for_each(|v| *v = 0.0);
        if let Ok(mut d) = self.data.lock() {
            let _ = rnea(&self.units[k], &mut d, q, qd, qdd, out);
        }
    }

    /// The identified payload in standard inertial parameters: mass `m` (kg), first moment
    /// `h = m c` (kg·m) and inertia about the flange origin `I_o` (kg·m²), flange frame.
    pub fn standard(&self) -> (f64, V3, M3) {
        let c0 = V3::from(self.nominal_com);
        let m = self.nominal_mass + self.dm;
        let dh = V3::from(self.dh);
        let h = c0 * m + dh;
        let io =
            self.nominal_inertia + point_inertia(&c0) * m + M3::identity() * (2.0 * c0.dot(&dh))
                - (dh * c0.transpose() + c0 * dh.transpose())
                + sym_from6(&self.di);
        (m, h, io)
    }

    /// The inertia error `ΔI_o` that keeps the load's inertia about its own centre of mass at
    /// the nominal one for a mass error `dm` and first-moment error `dh`: `P(Δh) / m`, with
    /// `m = m₀ + Δm` (zero when the mass is zero). With it, [`Payload::body`] writes the
    /// nominal inertia about the centre of mass: what "the payload's inertia is held" means
    /// when only the mass and the centre of mass are fitted.
    pub(crate) fn held_inertia_error(&self, dm: f64, dh: [f64; 3]) -> [f64; 6] {
        let m = self.nominal_mass + dm;
        if m.abs() <= 1e-12 {
            return [0.0; 6];
        }
        six_of(&(point_inertia(&V3::from(dh)) / m))
    }

    /// Derivatives of [`Payload::held_inertia_error`] with respect to `dm` (index 0) and
    /// `dh_x`, `dh_y`, `dh_z` (1–3): `−P(Δh)/m²` and `(2 Δhᵢ 1 − eᵢ Δhᵀ − Δh eᵢᵀ)/m` (the chain
    /// rule of a fit that holds the inertia about the centre of mass). Zeros at zero mass.
    pub(crate) fn held_inertia_derivatives(&self, dm: f64, dh: [f64; 3]) -> [[f64; 6]; 4] {
        let m = self.nominal_mass + dm;
        let mut der = [[0.0; 6]; 4];
        if m.abs() <= 1e-12 {
            return der;
        }
        let d = V3::from(dh);
        der[0] = six_of(&(point_inertia(&d) / (-m * m)));
        for (i, row) in der.iter_mut().skip(1).enumerate() {
            let mut e = V3::zeros();
            e[i] = 1.0;
            let dp = M3::identity() * (2.0 * d[i]) - (e * d.transpose() + d * e.transpose());
            *row = six_of(&(dp / m));
        }
        der
    }

    /// The identified payload mass `m`, kg, and centre of mass `h / m`, m (flange frame; `c₀`
    /// when the mass is zero).
    pub fn identified(&self) -> (f64, [f64; 3]) {
        let b = self.body();
        (b.mass, [b.com.x, b.com.y, b.com.z])
    }

    /// The identified payload as a body: mass, centre of mass and inertia about the centre of
    /// mass (flange frame). A body of zero (or negative) mass keeps its inertia about the
    /// flange origin with the centre of mass at the origin (as [`Inertial::merged`] does).
    pub fn body(&self) -> Inertial {
        let (m, h, io) = self.standard();
        if m.abs() <= 1e-12 {
            return Inertial {
                mass: 0.0,
                com: V3::zeros(),
                inertia: io,
            };
        }
        let c = h / m;
        Inertial {
            mass: m,
            com: c,
            inertia: io - point_inertia(&c) * m,
        }
    }
}

impl Effect for Payload {
    fn name(&self) -> &'static str {
        "payload"
    }
    fn effects_keys(&self) -> &'static [&'static str] {
        &[MASS_ERROR_KEY]
    }
    fn uncertainty(&self) -> Option<Uncertainty> {
        at(DrawPhase::Robot, 1)
    }
    /// The robot's payload mass (inertia scaled with it), ± `payload_mass_rel`. An identified
    /// payload (written as the robot's payload: mass `m`, centre of mass `c`) draws its mass
    /// and first moment `h = m c` with their standard errors.
    fn draw(&self, d: &mut Drawing<'_>, _joint: Option<usize>) {
        if d.robot.payload.is_none() {
            return;
        }
        let f = match d.identified("dm") {
            Some((_, dm)) => {
                let Some(p) = d.robot.payload.as_ref() else {
                    return;
                };
                let (m0, com) = (p.mass, p.com);
                let m1 = (m0 + dm).max(1e-3 * m0.abs().max(1e-3));
                let f = m1 / m0.abs().max(1e-300);
                let mut c = com;
                for (k, a) in ["x", "y", "z"].iter().enumerate() {
                    let h =
                        m0 * com[k] + d.identified(&format!("dh_{a}")).map_or(0.0, |(_, dh)| dh);
                    c[k] = h / m1;
                }
                if let Some(p) = d.robot.payload.as_mut() {
                    p.com = c;
                    p.mass = m1;
                    p.inertia *= f;
                }
                f
            }
            None => {
                let f = 1.0 + d.ranges.payload_mass_rel * d.uniform();
                if let Some(p) = d.robot.payload.as_mut() {
                    p.mass *= f;
                    p.inertia *= f;
                }
                f
            }
        };
        d.record("payload mass", f);
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
        for a in PAYLOAD_INERTIA_NAMES {
            p.push(ParamSpec {
                name: format!("dI_{a}"),
                unit: "kg·m²",
                lower: -PAYLOAD_INERTIA_MAX_KG_M2,
                upper: PAYLOAD_INERTIA_MAX_KG_M2,
            });
        }
        p
    }
    fn values(&self) -> Vec<f64> {
        let mut v = vec![self.dm, self.dh[0], self.dh[1], self.dh[2]];
        v.extend_from_slice(&self.di);
        v
    }
    /// Accepts 10 values (`Δm`, `Δh`, `ΔI_o`), 4 (`Δm`, `Δh`) or 1 (`Δm` only, as older files
    /// wrote; `Δh` = 0). With 4 or 1, `ΔI_o` follows so that the load keeps its inertia about
    /// its own centre of mass ([`Payload::held_inertia_error`]).
    fn set_values(&mut self, values: &[f64]) -> Result<()> {
        let mut full = vec![0.0; PAYLOAD_PARAMS];
        for (f, v) in full.iter_mut().zip(values) {
            *f = *v;
        }
        if ![1, 4, PAYLOAD_PARAMS].contains(&values.len()) {
            full = values.to_vec();
        }
        if [1, 4].contains(&values.len()) {
            // Mass (and first moment) only: the load keeps its inertia about its own centre
            // of mass, as when `identify` fits the mass and the centre of mass.
            let d = self.held_inertia_error(full[0], [full[1], full[2], full[3]]);
            full[4..10].copy_from_slice(&d);
        }
        check_values(self.name(), &self.params(), &full)?;
        self.dm = full[0];
        self.dh = [full[1], full[2], full[3]];
        self.di.copy_from_slice(&full[4..10]);
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
    /// Implausible when its mass is negative or above [`Payload::mass_limit`], its centre of
    /// mass lies more than [`PAYLOAD_MAX_COM_M`] from the flange origin (given the first
    /// moment's standard errors), or its inertia about the centre of mass is no rigid body's
    /// (eigenvalues and triangle inequality, within [`PAYLOAD_INERTIA_TOL_KG_M2`]); each limit
    /// widened by [`PLAUSIBILITY_SIGMAS`] standard errors.
    fn implausible_fit(&self, std_errors: &[Option<f64>]) -> Option<String> {
        let mut why: Vec<String> = Vec::new();
        let (m, h, _) = self.standard();
        let limit = self.mass_limit();
        let sm = PLAUSIBILITY_SIGMAS * se(std_errors, 0);
        if m < -sm {
            why.push(format!("its mass is {m:.3} kg (< 0)"));
        } else if m > limit + sm {
            why.push(format!(
                "its mass {m:.3} kg is above {limit:.1} kg ({})",
                match self.rated_payload_kg {
                    Some(r) if r > 0.0 => {
                        format!("{PAYLOAD_RATED_FACTOR} × the rated payload {r} kg")
                    }
                    _ => format!(
                        "{PAYLOAD_MOVING_MASS_SHARE} × the moving links' {:.1} kg",
                        self.moving_mass_kg
                    ),
                }
            ));
        }
        let sh = (1..4).map(|i| se(std_errors, i)).fold(0.0, f64::max);
        if h.norm() > m.max(0.0) * PAYLOAD_MAX_COM_M + PLAUSIBILITY_SIGMAS * sh * 3f64.sqrt() {
            let b = self.body();
            why.push(format!(
                "its centre of mass lies {:.2} m from the flange origin (first moment {:.3} kg·m for {m:.3} kg; at most {PAYLOAD_MAX_COM_M} m)",
                b.com.norm(),
                h.norm()
            ));
        }
        if m > 0.0 && why.is_empty() {
            let si = (4..10).map(|i| se(std_errors, i)).fold(0.0, f64::max);
            let tol = PAYLOAD_INERTIA_TOL_KG_M2 + PLAUSIBILITY_SIGMAS * si;
            if let Some(w) = plausible::inertia_violation(&self.body(), tol) {
                why.push(w);
            }
        }
        plausible::reasons(why)
    }
    /// The robot's own payload: `identify` writes the identified body as the robot's
    /// `[payload]`, not as an effect.
    fn write_drive_keys(&self, _keys: &mut DriveKeysMut<'_>) -> Result<DriveKept> {
        Ok(DriveKept::Body)
    }
    /// Kept with [`super::EnergyOptions::payload`].
    fn in_energy_model(&self, options: &super::EnergyOptions, _has_drive: bool) -> bool {
        options.payload
    }
    fn is_null(&self) -> bool {
        self.dm == 0.0 && self.dh == [0.0; 3] && self.di == [0.0; 6]
    }
    fn fold_into(&self, robot: &mut RobotModel) -> bool {
        if self.is_null() {
            return true;
        }
        robot.payload = Some(self.body());
        true
    }
    fn add_torque(&self, q: &[f64], qd: &[f64], qdd: &[f64], tau: &mut [f64]) {
        if self.is_null() {
            return;
        }
        let n = tau.len().min(MAX_DOF);
        let mut y = [0.0; PAYLOAD_PARAMS * MAX_DOF];
        self.regressor(q, qd, qdd, &mut y[..PAYLOAD_PARAMS * n]);
        let v = self.values();
        for (j, t) in tau.iter_mut().enumerate().take(n) {
            *t += (0..PAYLOAD_PARAMS)
                .map(|k| y[j * PAYLOAD_PARAMS + k] * v[k])
                .sum::<f64>();
        }
    }
    fn regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64], y: &mut [f64]) -> bool {
        const P: usize = PAYLOAD_PARAMS;
        let n = y.len() / P;
        let mut u = [0.0; MAX_DOF];
        let mut up = [0.0; MAX_DOF];
        let mut um = [0.0; MAX_DOF];
        self.unit_at(0, q, qd, qdd, &mut u[..n]);
        for j in 0..n {
            y[j * P] = u[j];
        }
        for i in 0..3 {
            self.unit_at(1 + 2 * i, q, qd, qdd, &mut up[..n]);
            self.unit_at(2 + 2 * i, q, qd, qdd, &mut um[..n]);
            for j in 0..n {
                y[j * P + 1 + i] = (up[j] - um[j]) / (2.0 * COM_STEP_M);
            }
        }
        for k in 0..6 {
            self.unit_at(7 + k, q, qd, qdd, &mut u[..n]);
            for j in 0..n {
                y[j * P + 4 + k] = u[j];
            }
        }
        true
    }
}
