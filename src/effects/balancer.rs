//! `balancer`: the gravity balancer of axis 2 of large arms, a spring (or gas/hydraulic-spring)
//! cylinder between link 1 and link 2 that takes part of the arm's weight off the axis-2 motor.
//!
//! Geometry (per robot, from the drive file's `[effects]` table): the cylinder's fixed end sits
//! on link 1 at distance `b` from the axis-2 pivot, its moving end on link 2 at distance `a`;
//! the two ends are aligned (cylinder shortest, `L_min = |b − a|`) when the joint is at
//! `q_up`, the pose where the arm stands upright and its own weight has no lever. Length
//! `L(q) = √(a² + b² − 2ab cos(q − q_up))`, `dL/dq = a b sin(q − q_up) / L`.
//!
//! Force: a tension `F = F0 + k (L − L_min)` (preload `F0` N at the shortest length, of
//! either sign: negative for a cylinder that pushes near its shortest length;
//! stiffness `k ≥ 0` N/m), pulling the arm back towards upright. Its potential `V(L)` has its
//! minimum at `q_up`, where gravity's potential has its maximum, so it relieves gravity on both
//! sides of upright. The torque the motor must add to hold it is
//! `τ = dV/dq = (F0 + k (L − L_min)) dL/dq`: zero at upright, opposite to the gravity torque
//! when the arm leans out, and linear in (`F0`, `k`) (regressor
//! `[dL/dq, (L − L_min) dL/dq]`, m and m²).

use super::plausible::{self, PLAUSIBILITY_SIGMAS};
use super::{
    check_values, BuildContext, DrawPhase, Drawing, Effect, EnergyClass, ParamSpec, Uncertainty,
};
use crate::error::Result;

/// Default lever of the moving end on link 2, m (ESTIMATE used when a drive file names no
/// geometry; see docs/effects.md).
pub const BALANCER_A_M: f64 = 0.2;
/// Default distance of the fixed end on link 1 from the axis-2 pivot, m (ESTIMATE).
pub const BALANCER_B_M: f64 = 0.6;
/// Default upright angle `q_up` of axis 2 (ABB and Stäubli zero: lower arm vertical), rad.
pub const BALANCER_UPRIGHT_RAD: f64 = 0.0;

/// Axis-2 balancer with fixed geometry and identifiable preload and stiffness.
#[derive(Clone, Debug, PartialEq)]
pub struct Balancer {
    /// Index (0-based) of the joint it acts on (1 = axis 2).
    pub joint: usize,
    /// Lever of the moving end on the joint's child link, m (> 0).
    pub a: f64,
    /// Distance of the fixed end on the parent link from the pivot, m (> 0, ≠ a).
    pub b: f64,
    /// Joint angle at which the cylinder is shortest (arm upright), rad.
    pub upright: f64,
    /// Preload (tension at the shortest length) `F0`, N (either sign: negative pushes).
    pub preload: f64,
    /// Stiffness `k`, N/m (≥ 0).
    pub stiffness: f64,
    /// Whether the robot's drive file declares a balancer (gives `balancer_lever_m` and
    /// `balancer_base_m`); a drive file that declares none makes the effect implausible.
    pub declared: bool,
    /// Whether the geometry is an assumed prior: a robot without drive data (a bare URDF)
    /// says nothing about a balancer, so the effect is a candidate with the default geometry
    /// ([`BALANCER_A_M`], [`BALANCER_B_M`], [`BALANCER_UPRIGHT_RAD`]), and a drive file with
    /// `balancer_lever_m` and `balancer_base_m` gives the real one.
    pub assumed_geometry: bool,
}

/// Registry entry: geometry, preload and stiffness from the `[effects]` keys
/// (`balancer_joint`, `balancer_lever_m`, `balancer_base_m`, `balancer_upright_rad`,
/// `balancer_preload_n`, `balancer_stiffness_n_per_m`; errors name the key).
pub(crate) fn build(ctx: &BuildContext) -> Result<Box<dyn Effect>> {
    let t = ctx.table;
    let dof = ctx.dof();
    let mut b = Balancer::zero();
    if let Some(j) = t.balancer_joint {
        if j == 0 || j > dof {
            return Err(ctx.bad(
                "balancer_joint",
                format!("must be a joint number 1..={dof}, got {j}"),
            ));
        }
        b.joint = j - 1;
    }
    for (key, v) in [
        ("balancer_lever_m", t.balancer_lever_m),
        ("balancer_base_m", t.balancer_base_m),
    ] {
        if let Some(x) = v {
            // A spring balancer's lever and base are parts of the arm: a few tenths of a
            // metre, never more than the arm (10 m bounds every robot printwatt models).
            if !(x.is_finite() && x > 0.0 && x <= 10.0) {
                return Err(ctx.bad(key, format!("must be finite and in (0, 10] m, got {x}")));
            }
        }
    }
    if let Some(x) = t.balancer_lever_m {
        b.a = x;
    }
    if let Some(x) = t.balancer_base_m {
        b.b = x;
    }
    if (b.a - b.b).abs() < 1e-6 {
        return Err(ctx.bad(
            "balancer_lever_m",
            format!(
                "lever {} m equals the base distance {} m: the cylinder would reach zero length",
                b.a, b.b
            ),
        ));
    }
    if let Some(x) = t.balancer_upright_rad {
        if !x.is_finite() {
            return Err(ctx.bad("balancer_upright_rad", format!("must be finite, got {x}")));
        }
        b.upright = x;
    }
    b.declared = t.balancer_lever_m.is_some() && t.balancer_base_m.is_some();
    b.assumed_geometry = !b.declared && ctx.robot.drive.is_none();
    for (key, v, idx) in [
        ("balancer_preload_n", t.balancer_preload_n, 0),
        (
            "balancer_stiffness_n_per_m",
            t.balancer_stiffness_n_per_m,
            1,
        ),
    ] {
        if let Some(x) = v {
            let mut vals = b.values();
            vals[idx] = x;
            b.set_values(&vals)
                .map_err(|e| ctx.bad(key, e.to_string()))?;
        }
    }
    Ok(Box::new(b))
}

impl Balancer {
    /// A balancer on axis 2 with the default geometry and no force.
    pub fn zero() -> Self {
        Balancer {
            joint: 1,
            a: BALANCER_A_M,
            b: BALANCER_B_M,
            upright: BALANCER_UPRIGHT_RAD,
            preload: 0.0,
            stiffness: 0.0,
            declared: false,
            assumed_geometry: false,
        }
    }
    /// Cylinder length `L(q)`, m, at joint angle `q` rad.
    pub fn length(&self, q: f64) -> f64 {
        self.length_at_cos(crate::fastmath::cos(q - self.upright))
    }
    /// [`Balancer::length`] from `cos(q − q_up)`.
    #[inline]
    fn length_at_cos(&self, c: f64) -> f64 {
        (self.a * self.a + self.b * self.b - 2.0 * self.a * self.b * c)
            .max(1e-12)
            .sqrt()
    }
    /// Shortest length `L_min = |b − a|`, m.
    pub(crate) fn min_length(&self) -> f64 {
        (self.b - self.a).abs()
    }
    /// The two regressor entries `[dL/dq, (L − L_min) dL/dq]` (m, m²) at joint angle `q` rad.
    pub fn shape(&self, q: f64) -> [f64; 2] {
        let (s, c) = crate::fastmath::sin_cos(q - self.upright);
        let l = self.length_at_cos(c);
        let dl = self.a * self.b * s / l;
        let stretch = (l - self.min_length()).max(0.0);
        [dl, stretch * dl]
    }
    /// Torque the motor of joint [`Balancer::joint`] adds at its angle `q` rad, N·m:
    /// `(F0 + k ΔL) dL/dq` (opposite to gravity's when the arm leans out of upright).
    #[inline]
    pub fn joint_torque(&self, q: f64) -> f64 {
        let s = self.shape(q);
        s[0] * self.preload + s[1] * self.stiffness
    }

    /// [`Balancer::joint_torque`] at [`crate::simd::LANES`] angles at once (rad → N·m), lane by
    /// lane bit-identical (the same operations; the sines by
    /// [`crate::fastmath::sin_cos_lanes`]). Inlined into the caller, so it runs on the caller's
    /// instruction set ([`crate::simd`]).
    #[inline(always)]
    pub(crate) fn joint_torque_lanes(
        &self,
        q: &[f64; crate::simd::LANES],
    ) -> [f64; crate::simd::LANES] {
        use crate::simd::LANES;
        let mut x = [0.0; LANES];
        for l in 0..LANES {
            x[l] = q[l] - self.upright;
        }
        let (s, c) = crate::fastmath::sin_cos_lanes(&x);
        let mut t = [0.0; LANES];
        for l in 0..LANES {
            let len = self.length_at_cos(c[l]);
            let dl = self.a * self.b * s[l] / len;
            let stretch = (len - self.min_length()).max(0.0);
            t[l] = dl * self.preload + (stretch * dl) * self.stiffness;
        }
        t
    }
}

impl Effect for Balancer {
    fn name(&self) -> &'static str {
        "balancer"
    }
    /// Its force; the geometry keys stay.
    fn effects_keys(&self) -> &'static [&'static str] {
        &["balancer_preload_n", "balancer_stiffness_n_per_m"]
    }
    fn uncertainty(&self) -> Option<Uncertainty> {
        Some(Uncertainty {
            phase: DrawPhase::Effects,
            rank: 0,
            draws_identified: true,
        })
    }
    /// A robot with a balancer (declared, or with a force): absent with probability
    /// `balancer_absent_probability`, else its preload and stiffness scaled by one factor
    /// (± `balancer_force_rel`). An identified balancer is there: its `F0` and `k` are drawn
    /// with their standard errors.
    fn draw(&self, d: &mut Drawing<'_>, _joint: Option<usize>) {
        let t = &d.robot.effects.table;
        let declared = t.balancer_lever_m.is_some() && t.balancer_base_m.is_some();
        // A calibrated robot keeps the balancer in `[effects.values]` (which wins over the keys).
        let (p0, k0) = match t.values.as_ref().and_then(|v| v.get("balancer")) {
            Some(b) if b.len() >= 2 => (b[0], b[1]),
            _ => (
                t.balancer_preload_n.unwrap_or(0.0),
                t.balancer_stiffness_n_per_m.unwrap_or(0.0),
            ),
        };
        if !(declared || p0 != 0.0 || k0 != 0.0) {
            return;
        }
        let identified = d.identified("F0").is_some() && d.identified("k").is_some();
        let present = d.unit() >= d.ranges.balancer_absent_probability || identified;
        let (f0, k) = match (d.identified("F0"), d.identified("k")) {
            (Some((f, df)), Some((k, dk))) => (f + df, (k + dk).max(0.0)),
            _ => {
                let f = 1.0 + d.ranges.balancer_force_rel * d.uniform();
                (p0 * f, k0 * f)
            }
        };
        let (f0, k) = if present { (f0, k) } else { (0.0, 0.0) };
        let t = &mut d.robot.effects.table;
        t.balancer_preload_n = Some(f0);
        t.balancer_stiffness_n_per_m = Some(k);
        // A calibrated robot keeps the balancer in `[effects.values]`, which wins.
        if let Some(b) = t.values.as_mut().and_then(|v| v.get_mut("balancer")) {
            if b.len() >= 2 {
                b[0] = f0;
                b[1] = k;
            }
        }
        d.record("balancer present", if present { 1.0 } else { 0.0 });
    }
    fn params(&self) -> Vec<ParamSpec> {
        vec![
            ParamSpec {
                name: "F0".into(),
                unit: "N",
                lower: f64::NEG_INFINITY,
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
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn energy_class(&self) -> EnergyClass {
        EnergyClass::Balancer
    }
    fn is_null(&self) -> bool {
        self.preload == 0.0 && self.stiffness == 0.0
    }
    fn implausible(&self) -> Option<String> {
        (!self.declared && !self.assumed_geometry).then(|| {
            "the robot declares no balancer (drive file [effects] balancer_lever_m, balancer_base_m): \
a gravity error here is a link or payload error"
                .to_string()
        })
    }
    /// Implausible as [`Effect::implausible`] says, else when its geometry is not physical
    /// (levers > 0 and different) or its stiffness is below zero by more than
    /// [`PLAUSIBILITY_SIGMAS`] standard errors; the preload may have either sign (a cylinder
    /// pushing at its shortest length).
    fn implausible_fit(&self, std_errors: &[Option<f64>]) -> Option<String> {
        if let Some(w) = self.implausible() {
            return Some(w);
        }
        let mut why = Vec::new();
        if !(self.a > 0.0 && self.b > 0.0 && (self.a - self.b).abs() > 1e-6) {
            why.push(format!(
                "its geometry is not physical (levers {} m and {} m must be > 0 and differ)",
                self.a, self.b
            ));
        }
        if self.stiffness < -PLAUSIBILITY_SIGMAS * plausible::se(std_errors, 1) {
            why.push(format!("its stiffness {:.1} N/m is < 0", self.stiffness));
        }
        plausible::reasons(why)
    }
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
