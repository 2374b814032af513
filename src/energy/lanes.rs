//! The energy pass of [`LANES`] samples in lockstep, structure of arrays:
//! RNEA ([`crate::dynamics::rnea_batch`]), then the torque effects, the motor model and the
//! supply lane by lane in plain `[f64; LANES]` loops compiled for the level in force
//! ([`crate::simd`]), so that they vectorise like RNEA does.
//!
//! Every lane performs the operations of [`super::eval_sample_with_sincos`] in the same order
//! (branches become selects: both sides computed, one kept), so each lane is **bit-identical**
//! to the per-sample path (tested: `tests/simd.rs`). The smoothed Coulomb sign is
//! [`crate::fastmath::tanh_lanes`]: ±1 by select for `|q̇/ε| ≥ 20`, and where a lane is
//! slower than that (20 ε, 0.02 rad/s by default: reversals and standstills) the polynomial
//! [`crate::fastmath::tanh`] of every lane in lockstep, bit for bit the per-sample path's.
//! The Stribeck term's `exp` is libm's per lane. An effect the pass does not know ([`LaneEffect::Other`]) is called per lane
//! through [`Effect::add_torque`].

use super::{EnergyModel, SamplePower};
use crate::dynamics::{rnea_batch, Lanes, StateBatch, MAX_DOF};
use crate::effects::{
    Armature, Balancer, Coulomb, Effect, EnergyClass, Offset, Stribeck, Viscous,
    COULOMB_VELOCITY_SCALE_RAD_S,
};
use crate::error::{Error, Result};
use crate::robot::Regeneration;
use crate::simd::{Level, LANES};
use std::sync::Arc;

/// The per-sample quantities of [`LANES`] samples, joint-major (`x[j][lane]`): the fields of
/// [`SamplePower`] with the same units (N·m, W, A, V). Lanes beyond the samples in use hold
/// values not meant to be read.
#[derive(Clone, Copy, Debug)]
pub struct PowerLanes {
    /// See [`SamplePower::tau_rb`], N·m.
    pub tau_rb: [Lanes; MAX_DOF],
    /// See [`SamplePower::tau_friction`], N·m.
    pub tau_friction: [Lanes; MAX_DOF],
    /// See [`SamplePower::tau_balancer`], N·m.
    pub tau_balancer: [Lanes; MAX_DOF],
    /// See [`SamplePower::tau`], N·m.
    pub tau: [Lanes; MAX_DOF],
    /// See [`SamplePower::p_mech`], W.
    pub p_mech: [Lanes; MAX_DOF],
    /// See [`SamplePower::p_rigid_body`], W.
    pub p_rigid_body: [Lanes; MAX_DOF],
    /// See [`SamplePower::p_balancer`], W.
    pub p_balancer: [Lanes; MAX_DOF],
    /// See [`SamplePower::p_friction`], W.
    pub p_friction: [Lanes; MAX_DOF],
    /// See [`SamplePower::p_gear`], W.
    pub p_gear: [Lanes; MAX_DOF],
    /// See [`SamplePower::p_copper`], W.
    pub p_copper: [Lanes; MAX_DOF],
    /// See [`SamplePower::p_el`], W.
    pub p_el: [Lanes; MAX_DOF],
    /// See [`SamplePower::current`], A.
    pub current: [Lanes; MAX_DOF],
    /// See [`SamplePower::voltage`], V.
    pub voltage: [Lanes; MAX_DOF],
    /// See [`SamplePower::p_drives`], W.
    pub p_drives: Lanes,
    /// See [`SamplePower::p_regeneration_lost`], W.
    pub p_regeneration_lost: Lanes,
    /// See [`SamplePower::p_supply`], W.
    pub p_supply: Lanes,
}

impl Default for PowerLanes {
    fn default() -> Self {
        let z = [[0.0; LANES]; MAX_DOF];
        PowerLanes {
            tau_rb: z,
            tau_friction: z,
            tau_balancer: z,
            tau: z,
            p_mech: z,
            p_rigid_body: z,
            p_balancer: z,
            p_friction: z,
            p_gear: z,
            p_copper: z,
            p_el: z,
            current: z,
            voltage: z,
            p_drives: [0.0; LANES],
            p_regeneration_lost: [0.0; LANES],
            p_supply: [0.0; LANES],
        }
    }
}

impl PowerLanes {
    /// Lane `lane` as a [`SamplePower`].
    pub fn sample(&self, lane: usize) -> SamplePower {
        let col = |a: &[Lanes; MAX_DOF]| {
            let mut r = [0.0; MAX_DOF];
            for (v, l) in r.iter_mut().zip(a) {
                *v = l[lane];
            }
            r
        };
        SamplePower {
            tau_rb: col(&self.tau_rb),
            tau_friction: col(&self.tau_friction),
            tau_balancer: col(&self.tau_balancer),
            tau: col(&self.tau),
            p_mech: col(&self.p_mech),
            p_rigid_body: col(&self.p_rigid_body),
            p_balancer: col(&self.p_balancer),
            p_friction: col(&self.p_friction),
            p_gear: col(&self.p_gear),
            p_copper: col(&self.p_copper),
            p_el: col(&self.p_el),
            current: col(&self.current),
            voltage: col(&self.voltage),
            p_drives: self.p_drives[lane],
            p_regeneration_lost: self.p_regeneration_lost[lane],
            p_supply: self.p_supply[lane],
        }
    }

    /// Put `s` into lane `lane`.
    fn set_sample(&mut self, lane: usize, s: &SamplePower) {
        let put = |a: &mut [Lanes; MAX_DOF], v: &[f64; MAX_DOF]| {
            for (l, x) in a.iter_mut().zip(v) {
                l[lane] = *x;
            }
        };
        put(&mut self.tau_rb, &s.tau_rb);
        put(&mut self.tau_friction, &s.tau_friction);
        put(&mut self.tau_balancer, &s.tau_balancer);
        put(&mut self.tau, &s.tau);
        put(&mut self.p_mech, &s.p_mech);
        put(&mut self.p_rigid_body, &s.p_rigid_body);
        put(&mut self.p_balancer, &s.p_balancer);
        put(&mut self.p_friction, &s.p_friction);
        put(&mut self.p_gear, &s.p_gear);
        put(&mut self.p_copper, &s.p_copper);
        put(&mut self.p_el, &s.p_el);
        put(&mut self.current, &s.current);
        put(&mut self.voltage, &s.voltage);
        self.p_drives[lane] = s.p_drives;
        self.p_regeneration_lost[lane] = s.p_regeneration_lost;
        self.p_supply[lane] = s.p_supply;
    }
}

/// A per-sample torque effect as the lockstep pass evaluates it: the effects it knows with
/// their parameters, anything else called lane by lane.
#[derive(Clone, Debug)]
pub(super) enum LaneEffect {
    /// [`Viscous`]: `τ_j += f_v,j q̇_j` (N·m·s/rad per joint).
    Viscous(Vec<f64>),
    /// [`Armature`]: `τ_j += I_a,j q̈_j` (kg·m² per joint).
    Armature(Vec<f64>),
    /// [`Offset`]: `τ_j += τ_0,j` (N·m per joint).
    Offset(Vec<f64>),
    /// [`Coulomb`].
    Coulomb(Coulomb),
    /// [`Stribeck`].
    Stribeck(Stribeck),
    /// [`Balancer`] (on a joint of the model).
    Balancer(Balancer),
    /// Any other effect, through [`Effect::add_torque`] per lane.
    Other(Arc<dyn Effect>),
}

impl LaneEffect {
    /// The lockstep form of `e` on a model of `n` joints.
    pub(super) fn of(e: &Arc<dyn Effect>, n: usize) -> LaneEffect {
        let a = e.as_any();
        if let Some(v) = a.downcast_ref::<Viscous>() {
            LaneEffect::Viscous(v.fv.clone())
        } else if let Some(v) = a.downcast_ref::<Armature>() {
            LaneEffect::Armature(v.ia.clone())
        } else if let Some(v) = a.downcast_ref::<Offset>() {
            LaneEffect::Offset(v.tau0.clone())
        } else if let Some(c) = a.downcast_ref::<Coulomb>() {
            LaneEffect::Coulomb(c.clone())
        } else if let Some(s) = a.downcast_ref::<Stribeck>() {
            LaneEffect::Stribeck(s.clone())
        } else {
            match a.downcast_ref::<Balancer>() {
                Some(b) if b.joint < n => LaneEffect::Balancer(b.clone()),
                _ => LaneEffect::Other(Arc::clone(e)),
            }
        }
    }
}

/// A whole-lane expression (plain lane arithmetic, which vectorises).
macro_rules! each {
    ($l:ident => $e:expr) => {{
        let mut r = [0.0f64; LANES];
        for $l in 0..LANES {
            r[$l] = $e;
        }
        r
    }};
}

/// The joints whose angles the lockstep effects `e` read (the balancer's joint; every joint
/// for an effect called per lane): only these are transposed into lanes when the sines are
/// given.
pub(super) fn angles_read(e: &[(LaneEffect, EnergyClass)], n: usize) -> [bool; MAX_DOF] {
    let mut read = [false; MAX_DOF];
    for (e, _) in e {
        match e {
            LaneEffect::Balancer(b) if b.joint < MAX_DOF => read[b.joint] = true,
            LaneEffect::Other(_) => read[..n.min(MAX_DOF)].fill(true),
            _ => {}
        }
    }
    read
}

/// The inputs of the lockstep pass: joint angles (rad), their sines and cosines, velocities
/// (rad/s), accelerations (rad/s²), joint-major.
struct Inputs<'b> {
    q: &'b [Lanes; MAX_DOF],
    b: &'b StateBatch,
}

/// The torque effects of [`tail_lanes`], lane by lane: into `tau_rb` (holding RNEA's torques),
/// `tau_friction` and `tau_balancer` (set to zero first) by energy class, N·m.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // parallel fixed arrays indexed by joint and lane
fn effects_lanes(
    model: &EnergyModel,
    x: &Inputs<'_>,
    tau_rb: &mut [Lanes; MAX_DOF],
    tau_friction: &mut [Lanes; MAX_DOF],
    tau_balancer: &mut [Lanes; MAX_DOF],
) {
    let n = model.n;
    let (qd, qdd) = (&x.b.qd, &x.b.qdd);
    for j in 0..MAX_DOF {
        tau_balancer[j] = [0.0; LANES];
        tau_friction[j] = [0.0; LANES];
    }
    for (e, class) in &model.lane_effects {
        let dst = match class {
            EnergyClass::RigidBody => &mut *tau_rb,
            EnergyClass::Friction => &mut *tau_friction,
            EnergyClass::Balancer => &mut *tau_balancer,
        };
        match e {
            LaneEffect::Viscous(fv) => {
                for (j, &f) in fv.iter().enumerate().take(n) {
                    let (d, v) = (dst[j], qd[j]);
                    dst[j] = each!(l => d[l] + f * v[l]);
                }
            }
            LaneEffect::Armature(ia) => {
                for (j, &i) in ia.iter().enumerate().take(n) {
                    let (d, a) = (dst[j], qdd[j]);
                    dst[j] = each!(l => d[l] + i * a[l]);
                }
            }
            LaneEffect::Offset(t0) => {
                for (j, &o) in t0.iter().enumerate().take(n) {
                    let d = dst[j];
                    dst[j] = each!(l => d[l] + o);
                }
            }
            LaneEffect::Coulomb(c) => {
                let threshold = crate::fastmath::ratio_saturation_threshold(c.velocity_scale);
                for j in 0..n {
                    let (Some(&p), Some(&m)) = (c.fc_pos.get(j), c.fc_neg.get(j)) else {
                        for l in 0..LANES {
                            dst[j][l] += 0.0;
                        }
                        continue;
                    };
                    if p == 0.0 && m == 0.0 {
                        for l in 0..LANES {
                            dst[j][l] += 0.0;
                        }
                        continue;
                    }
                    let (d, w) = (dst[j], qd[j]);
                    // tanh(q̇/ε), the division skipped where every lane is saturated.
                    let s =
                        crate::fastmath::tanh_lanes_of_ratio_at(&w, c.velocity_scale, threshold);
                    dst[j] = each!(l => d[l] + if s[l] >= 0.0 { p * s[l] } else { m * s[l] });
                }
            }
            LaneEffect::Stribeck(s) => {
                for j in 0..n {
                    match s.fs.get(j) {
                        Some(&f) if f != 0.0 => {
                            let mut v = [0.0; LANES];
                            for l in 0..LANES {
                                v[l] = qd[j][l] / COULOMB_VELOCITY_SCALE_RAD_S;
                            }
                            let th = crate::fastmath::tanh_lanes(&v);
                            for l in 0..LANES {
                                let e = (-(qd[j][l] / s.vs).powi(2)).exp();
                                dst[j][l] += f * (e * th[l]);
                            }
                        }
                        _ => {
                            for l in 0..LANES {
                                dst[j][l] += 0.0;
                            }
                        }
                    }
                }
            }
            LaneEffect::Balancer(bal) => {
                let j = bal.joint;
                let t = bal.joint_torque_lanes(&x.q[j]);
                for l in 0..LANES {
                    dst[j][l] += t[l];
                }
            }
            LaneEffect::Other(e) => {
                for l in 0..LANES {
                    let (mut a, mut v, mut w, mut t) = (
                        [0.0; MAX_DOF],
                        [0.0; MAX_DOF],
                        [0.0; MAX_DOF],
                        [0.0; MAX_DOF],
                    );
                    for j in 0..n {
                        a[j] = x.q[j][l];
                        v[j] = qd[j][l];
                        w[j] = qdd[j][l];
                        t[j] = dst[j][l];
                    }
                    e.add_torque(&a[..n], &v[..n], &w[..n], &mut t[..n]);
                    for j in 0..n {
                        dst[j][l] = t[j];
                    }
                }
            }
        }
    }
}

/// Everything after RNEA, lane by lane (see the module docs); `out.tau_rb` holds the
/// rigid-body torques.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // parallel fixed arrays indexed by joint and lane
/// With `ALL` false only what the integration reads is written (`tau_rb`, `tau_friction`,
/// `tau_balancer`, `p_mech`, `p_friction`, `p_gear`, `p_copper`, `p_el` and the supply lanes);
/// `tau`, `p_rigid_body`, `p_balancer`, `current` and `voltage` are left as they were.
fn tail_lanes<const ALL: bool>(model: &EnergyModel, x: &Inputs<'_>, out: &mut PowerLanes) {
    let n = model.n;
    let qd = &x.b.qd;
    effects_lanes(
        model,
        x,
        &mut out.tau_rb,
        &mut out.tau_friction,
        &mut out.tau_balancer,
    );
    // super::power_sample, lane by lane: whole-lane expressions (which vectorise), the
    // per-sample formulas' operations in their order.
    for j in 0..n {
        let ax = model.axes[j];
        let v = qd[j];
        let (tf, tb, trb) = (out.tau_friction[j], out.tau_balancer[j], out.tau_rb[j]);
        let tau = each!(l => trb[l] + tf[l] + tb[l]);
        let pm = each!(l => tau[l] * v[l]);
        if ALL {
            out.tau[j] = tau;
        }
        out.p_mech[j] = pm;
        if ALL {
            out.p_rigid_body[j] = each!(l => trb[l] * v[l]);
        }
        out.p_friction[j] = each!(l => tf[l] * v[l]);
        if ALL {
            out.p_balancer[j] = each!(l => tb[l] * v[l]);
        }
        if model.has_drive {
            // super::motor, the branch as a select of the dividend and the divisor: one
            // division (`τ / (G η)` driving, `(τ η) / G` regenerating), the same bits.
            let ge = ax.gear * ax.eta;
            let tm = each!(l => {
                let drive = tau[l] * v[l] >= 0.0;
                let num = if drive { tau[l] } else { tau[l] * ax.eta };
                let den = if drive { ge } else { ax.gear };
                num / den
            });
            let wm = each!(l => ax.gear * v[l]);
            let i = each!(l => tm[l] / ax.kt);
            let shaft = each!(l => tm[l] * wm[l]);
            let copper = each!(l => ax.r * i[l] * i[l]);
            if ALL {
                out.current[j] = i;
                out.voltage[j] = each!(l => ax.r * i[l] + ax.kt * wm[l]);
            }
            out.p_copper[j] = copper;
            out.p_gear[j] = each!(l => shaft[l] - pm[l]);
            out.p_el[j] = each!(l => shaft[l] + copper[l]);
        } else {
            if ALL {
                out.current[j] = [0.0; LANES];
                out.voltage[j] = [0.0; LANES];
            }
            out.p_copper[j] = [0.0; LANES];
            out.p_gear[j] = [0.0; LANES];
            out.p_el[j] = pm;
        }
    }
    // Joint by joint over all lanes (each lane's sums still in joint order).
    let zero: f64 = std::iter::empty::<f64>().sum();
    let (rho, p0) = (model.recovered_fraction, model.standby_w);
    let mut sum = [zero; LANES];
    let mut pos = [zero; LANES];
    for j in 0..n {
        for l in 0..LANES {
            sum[l] += out.p_el[j][l];
            pos[l] += out.p_el[j][l].max(0.0);
        }
    }
    let regeneration = model.regeneration;
    for l in 0..LANES {
        let (sum, pos) = (sum[l], pos[l]);
        let draw = match regeneration {
            Regeneration::None | Regeneration::PerAxis => pos,
            Regeneration::DcBus => sum.max(0.0),
            Regeneration::Grid => sum,
        };
        let drives = draw - rho * (draw - sum);
        out.p_drives[l] = drives;
        out.p_regeneration_lost[l] = drives - sum;
        out.p_supply[l] = drives + p0;
    }
}

/// [`tail_lanes`]`::<false>` then [`sums_lanes`] of a full batch, fused: the
/// effects into local torques, then joint by joint the motor model, the sums and the
/// supply's running sums with the joint's powers in registers. Nothing is written into
/// [`PowerLanes`] to be read back by the sums (the supply's reads of each joint's `p_el` had
/// been narrower loads of wider stores). Every lane performs the same operations in the same
/// order as there (each sum its own additions), so the bits are the same. `tau_rb` holds
/// RNEA's torques (N·m; the rigid-body effects are added into it), `w` the trapezoid weights
/// (s).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // parallel fixed arrays indexed by joint and lane
fn tail_summed(
    model: &EnergyModel,
    x: &Inputs<'_>,
    tau_rb: &mut [Lanes; MAX_DOF],
    s: &mut EnergySums,
    w: &Lanes,
) {
    let zero: f64 = std::iter::empty::<f64>().sum();
    let mut sum = [zero; LANES];
    let mut pos = [zero; LANES];
    let mut tf = [[0.0; LANES]; MAX_DOF];
    let mut tb = [[0.0; LANES]; MAX_DOF];
    effects_lanes(model, x, tau_rb, &mut tf, &mut tb);
    for j in 0..model.n {
        joint_summed(
            model, j, &x.b.qd[j], &tau_rb[j], &tf[j], &tb[j], s, w, &mut sum, &mut pos,
        );
    }
    supply_summed(model, &sum, &pos, s, w);
}

/// Joint `j`'s powers (its velocity `v` rad/s; torques `trb`, `tf`, `tb` N·m by class) added
/// into the sums `s` with weights `w` (s), and its electrical power into the supply's running
/// `sum` and `pos` (W): [`tail_lanes`]`::<false>`'s and [`sums_lanes`]' operations.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn joint_summed(
    model: &EnergyModel,
    j: usize,
    v: &Lanes,
    trb: &Lanes,
    tf: &Lanes,
    tb: &Lanes,
    s: &mut EnergySums,
    w: &Lanes,
    sum: &mut Lanes,
    pos: &mut Lanes,
) {
    // super::power_sample and the motor model (tail_lanes' operations).
    let ax = model.axes[j];
    let tau = each!(l => trb[l] + tf[l] + tb[l]);
    let pm = each!(l => tau[l] * v[l]);
    let pf = each!(l => tf[l] * v[l]);
    let (pg, pc, pel) = if model.has_drive {
        let ge = ax.gear * ax.eta;
        let tm = each!(l => {
            let drive = tau[l] * v[l] >= 0.0;
            let num = if drive { tau[l] } else { tau[l] * ax.eta };
            let den = if drive { ge } else { ax.gear };
            num / den
        });
        let wm = each!(l => ax.gear * v[l]);
        let i = each!(l => tm[l] / ax.kt);
        let shaft = each!(l => tm[l] * wm[l]);
        let copper = each!(l => ax.r * i[l] * i[l]);
        (
            each!(l => shaft[l] - pm[l]),
            copper,
            each!(l => shaft[l] + copper[l]),
        )
    } else {
        ([0.0; LANES], [0.0; LANES], pm)
    };
    // sums_lanes' additions of this joint, and its share of the supply.
    for l in 0..LANES {
        s.mech[j][l] += w[l] * pm[l];
        s.mech_abs[j][l] += w[l] * pm[l].abs();
        s.mech_pos[j][l] += w[l] * pm[l].max(0.0);
        s.el[j][l] += w[l] * pel[l];
        s.friction[j][l] += w[l] * pf[l];
        s.gear[j][l] += w[l] * pg[l];
        s.copper[j][l] += w[l] * pc[l];
        sum[l] += pel[l];
        pos[l] += pel[l].max(0.0);
    }
}

/// The supply of the batch from the running `sum` and `pos` of the joints' electrical
/// powers (W), added into `s` with weights `w` (s): [`tail_lanes`]' and [`sums_lanes`]'
/// operations.
#[inline(always)]
fn supply_summed(model: &EnergyModel, sum: &Lanes, pos: &Lanes, s: &mut EnergySums, w: &Lanes) {
    let (rho, p0) = (model.recovered_fraction, model.standby_w);
    // The regeneration's choice made once for all lanes (a select per lane would not
    // vectorise).
    let draw = match model.regeneration {
        Regeneration::None | Regeneration::PerAxis => *pos,
        Regeneration::DcBus => each!(l => sum[l].max(0.0)),
        Regeneration::Grid => *sum,
    };
    for l in 0..LANES {
        let drives = draw[l] - rho * (draw[l] - sum[l]);
        s.supply[l] += w[l] * (drives + p0);
        s.drives[l] += w[l] * drives;
        s.regeneration_lost[l] += w[l] * (drives - sum[l]);
    }
}

fn tail_sse2(model: &EnergyModel, x: &Inputs<'_>, out: &mut PowerLanes) {
    tail_lanes::<true>(model, x, out)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn tail_avx2(model: &EnergyModel, x: &Inputs<'_>, out: &mut PowerLanes) {
    tail_lanes::<true>(model, x, out)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn tail_avx512(model: &EnergyModel, x: &Inputs<'_>, out: &mut PowerLanes) {
    tail_lanes::<true>(model, x, out)
}

/// Consecutive samples, row-major (`n` values a sample; the sines then the cosines, `2 n` a
/// sample, for `sincos`), as [`eval_rows`] takes them.
#[derive(Clone, Copy)]
pub struct Rows<'r> {
    /// Joint angles, rad.
    pub q: &'r [f64],
    /// Their sines and cosines, when known (else computed here by
    /// [`crate::fastmath::sin_cos_lanes`], bit for bit [`crate::fastmath::sin_cos`]).
    pub sincos: Option<&'r [f64]>,
    /// Velocities, rad/s.
    pub qd: &'r [f64],
    /// Accelerations, rad/s².
    pub qdd: &'r [f64],
}

/// The lockstep inputs of [`eval_rows`], kept from batch to batch (made once: nothing is
/// cleared per batch; lanes beyond a short batch's samples keep the batch before's values,
/// which are not read).
#[derive(Clone, Copy, Debug, Default)]
pub struct LaneInputs {
    b: StateBatch,
    q: [Lanes; MAX_DOF],
    rnea: crate::dynamics::RneaScratch,
}

/// Rows `0..count` of `r` into the lanes of `x`, and their sines where `r` has none.
#[inline(always)]
fn transpose<const AVX512: bool>(
    n: usize,
    count: usize,
    r: &Rows<'_>,
    angles: &[bool; MAX_DOF],
    x: &mut LaneInputs,
) {
    #[cfg(target_arch = "x86_64")]
    if AVX512 && n == 6 && count == LANES && LANES == 8 {
        // SAFETY: `AVX512` is true only in `pass_avx512`, which runs on a CPU with AVX-512F.
        unsafe {
            transpose_full_avx512(
                r,
                x,
                if r.sincos.is_some() {
                    angles
                } else {
                    &[true; MAX_DOF]
                },
            )
        };
        if r.sincos.is_none() {
            for j in 0..n {
                let (s, c) = crate::fastmath::sin_cos_lanes(&x.q[j]);
                x.b.s[j] = s;
                x.b.c[j] = c;
            }
        }
        return;
    }
    if n == 6 && count == LANES {
        // The six-joint arm, a full batch: fixed sizes (unrolled, no bounds checks per value);
        // the angles only of the joints that need them (all when the sines are computed here).
        let all = [true; MAX_DOF];
        transpose_full::<6>(r, x, if r.sincos.is_some() { angles } else { &all });
    } else {
        transpose_rows(n, count, r, x);
    }
    if r.sincos.is_none() {
        for j in 0..n {
            let (s, c) = crate::fastmath::sin_cos_lanes(&x.q[j]);
            x.b.s[j] = s;
            x.b.c[j] = c;
        }
    }
}

/// [`transpose`] of [`LANES`] rows of `N` joints.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // parallel fixed arrays indexed by joint and lane
fn transpose_full<const N: usize>(r: &Rows<'_>, x: &mut LaneInputs, angles: &[bool; MAX_DOF]) {
    let (q, qd, qdd) = (&r.q[..LANES * N], &r.qd[..LANES * N], &r.qdd[..LANES * N]);
    for l in 0..LANES {
        for j in 0..N {
            x.b.qd[j][l] = qd[l * N + j];
            x.b.qdd[j][l] = qdd[l * N + j];
        }
    }
    for j in 0..N {
        if angles[j] {
            for l in 0..LANES {
                x.q[j][l] = q[l * N + j];
            }
        }
    }
    if let Some(sc) = r.sincos {
        let sc = &sc[..LANES * 2 * N];
        for l in 0..LANES {
            for j in 0..N {
                x.b.s[j][l] = sc[l * 2 * N + j];
                x.b.c[j][l] = sc[l * 2 * N + N + j];
            }
        }
    }
}

/// Eight rows of `N ≤ 8` consecutive values (`src[l · stride + k]`, `k < N`, row `l < 8`)
/// into lanes (`dst[k][l]`) in AVX-512 registers: masked row loads, an 8 × 8 transpose
/// (unpacks of pairs, then 128-bit shuffles, 30 instructions) and whole-vector stores. The
/// same values as the value-by-value copy (moves only); the copy's 8 scalar
/// stores per vector could not be forwarded to the vector loads that read them right after.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
fn rows_to_lanes_avx512<const N: usize>(src: &[f64], stride: usize, dst: &mut [Lanes; MAX_DOF]) {
    use std::arch::x86_64::*;
    assert!(N <= 8 && LANES == 8 && src.len() >= 7 * stride + N);
    let m = ((1u32 << N) - 1) as __mmask8;
    let p = src.as_ptr();
    // SAFETY: each masked load reads elements `l · stride + k`, `k < N`, of `src`, in bounds
    // (asserted above); the masked-off elements are not accessed.
    let (r0, r1, r2, r3, r4, r5, r6, r7) = unsafe {
        (
            _mm512_maskz_loadu_pd(m, p),
            _mm512_maskz_loadu_pd(m, p.add(stride)),
            _mm512_maskz_loadu_pd(m, p.add(2 * stride)),
            _mm512_maskz_loadu_pd(m, p.add(3 * stride)),
            _mm512_maskz_loadu_pd(m, p.add(4 * stride)),
            _mm512_maskz_loadu_pd(m, p.add(5 * stride)),
            _mm512_maskz_loadu_pd(m, p.add(6 * stride)),
            _mm512_maskz_loadu_pd(m, p.add(7 * stride)),
        )
    };
    // Pairs: 128-bit chunk c of t_even holds (r_a[2c], r_b[2c]), of t_odd (r_a[2c+1], r_b[2c+1]).
    // The columns of the row pairs (0,1), (2,3), (4,5), (6,7).
    macro_rules! cols {
        ($a:expr, $b:expr, $c:expr, $d:expr $(,)?) => {{
            let (a, b, c, d) = ($a, $b, $c, $d);
            let v0 = _mm512_shuffle_f64x2::<0x44>(a, b); // a.c0 a.c1 b.c0 b.c1
            let v1 = _mm512_shuffle_f64x2::<0xEE>(a, b); // a.c2 a.c3 b.c2 b.c3
            let w0 = _mm512_shuffle_f64x2::<0x44>(c, d);
            let w1 = _mm512_shuffle_f64x2::<0xEE>(c, d);
            [
                _mm512_shuffle_f64x2::<0x88>(v0, w0), // chunk 0 of each: column 0 (or 1)
                _mm512_shuffle_f64x2::<0xDD>(v0, w0), // chunk 1: column 2 (3)
                _mm512_shuffle_f64x2::<0x88>(v1, w1), // chunk 2: column 4 (5)
                _mm512_shuffle_f64x2::<0xDD>(v1, w1), // chunk 3: column 6 (7)
            ]
        }};
    }
    let even = cols!(
        _mm512_unpacklo_pd(r0, r1),
        _mm512_unpacklo_pd(r2, r3),
        _mm512_unpacklo_pd(r4, r5),
        _mm512_unpacklo_pd(r6, r7),
    );
    let odd = cols!(
        _mm512_unpackhi_pd(r0, r1),
        _mm512_unpackhi_pd(r2, r3),
        _mm512_unpackhi_pd(r4, r5),
        _mm512_unpackhi_pd(r6, r7),
    );
    for k in 0..N {
        let v = if k % 2 == 0 { even[k / 2] } else { odd[k / 2] };
        // SAFETY: `dst[k]` is 8 writable f64 (`LANES == 8`).
        unsafe { _mm512_storeu_pd(dst[k].as_mut_ptr(), v) };
    }
}

/// [`transpose_full`]`::<6>` by [`rows_to_lanes_avx512`]: the same values.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
fn transpose_full_avx512(r: &Rows<'_>, x: &mut LaneInputs, angles: &[bool; MAX_DOF]) {
    const N: usize = 6;
    rows_to_lanes_avx512::<N>(&r.qd[..LANES * N], N, &mut x.b.qd);
    rows_to_lanes_avx512::<N>(&r.qdd[..LANES * N], N, &mut x.b.qdd);
    if angles[..N].iter().any(|&a| a) {
        rows_to_lanes_avx512::<N>(&r.q[..LANES * N], N, &mut x.q);
    }
    if let Some(sc) = r.sincos {
        let sc = &sc[..LANES * 2 * N];
        rows_to_lanes_avx512::<N>(sc, 2 * N, &mut x.b.s);
        rows_to_lanes_avx512::<N>(&sc[N..], 2 * N, &mut x.b.c);
    }
}

/// [`transpose`] of any rows.
#[inline(always)]
fn transpose_rows(n: usize, count: usize, r: &Rows<'_>, x: &mut LaneInputs) {
    for l in 0..count {
        let (q, v, w) = (
            &r.q[l * n..][..n],
            &r.qd[l * n..][..n],
            &r.qdd[l * n..][..n],
        );
        for j in 0..n {
            x.q[j][l] = q[j];
            x.b.qd[j][l] = v[j];
            x.b.qdd[j][l] = w[j];
        }
        if let Some(sc) = r.sincos {
            let sc = &sc[l * 2 * n..][..2 * n];
            for j in 0..n {
                x.b.s[j][l] = sc[j];
                x.b.c[j][l] = sc[n + j];
            }
        }
    }
}

/// The whole lockstep pass of one batch, inlined into one function per level (`AVX512`:
/// the AVX-512 build, which transposes the rows in registers).
#[inline(always)]
fn pass_lanes<const AVX512: bool>(
    model: &EnergyModel,
    count: usize,
    r: &Rows<'_>,
    x: &mut LaneInputs,
    out: &mut PowerLanes,
    sum: Option<(&mut EnergySums, &Lanes)>,
) {
    transpose::<AVX512>(model.n, count, r, &model.lane_angles, x);
    let b = &x.b;
    crate::dynamics::rnea_lanes(
        &model.dynamics,
        &b.s,
        &b.c,
        &b.qd,
        &b.qdd,
        &mut out.tau_rb,
        &mut x.rnea,
    );
    let x = Inputs { q: &x.q, b: &x.b };
    if let Some((s, w)) = sum {
        if count == LANES {
            tail_summed(model, &x, &mut out.tau_rb, s, w);
        } else {
            tail_lanes::<false>(model, &x, out);
            s.add_partial(out, w, count, model.n);
        }
        return;
    }
    tail_lanes::<true>(model, &x, out);
}

fn pass_sse2(
    model: &EnergyModel,
    count: usize,
    r: &Rows<'_>,
    x: &mut LaneInputs,
    out: &mut PowerLanes,
    sum: Option<(&mut EnergySums, &Lanes)>,
) {
    pass_lanes::<false>(model, count, r, x, out, sum)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn pass_avx2(
    model: &EnergyModel,
    count: usize,
    r: &Rows<'_>,
    x: &mut LaneInputs,
    out: &mut PowerLanes,
    sum: Option<(&mut EnergySums, &Lanes)>,
) {
    pass_lanes::<false>(model, count, r, x, out, sum)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn pass_avx512(
    model: &EnergyModel,
    count: usize,
    r: &Rows<'_>,
    x: &mut LaneInputs,
    out: &mut PowerLanes,
    sum: Option<(&mut EnergySums, &Lanes)>,
) {
    pass_lanes::<true>(model, count, r, x, out, sum)
}

/// [`eval_lanes_with_sincos`] of `count ≤` [`LANES`] consecutive samples held row-major in
/// `r` ([`Rows`]: `count · n` angles (rad), velocities (rad/s), accelerations (rad/s²) and,
/// when known, `count · 2n` sines and cosines), into lanes `0..count` of `out` (W, N·m, A,
/// V); `x` carries the lockstep inputs from batch to batch. The same results, lane by lane
/// bit for bit, as [`eval_lanes_with_sincos`] (and so as the per-sample path), with the
/// transposition, RNEA and the rest compiled together for `level`. With [`Level::Scalar`] or
/// a model that is not [`EnergyModel::batchable`] each sample goes through the per-sample
/// path. Error: [`Error::SizeMismatch`] when a slice is shorter than `count` samples.
pub fn eval_rows(
    model: &EnergyModel,
    data: &mut crate::dynamics::DynData,
    count: usize,
    r: &Rows<'_>,
    x: &mut LaneInputs,
    out: &mut PowerLanes,
    level: Level,
) -> Result<()> {
    eval_rows_with(model, data, count, r, x, out, None, level)
}

/// [`eval_rows`], then the batch's powers added into `sums` with trapezoid weights `w` (s per
/// lane; [`EnergySums::add_lanes`]) in the same compiled pass: the sweep's integration step.
/// What `out` holds afterwards is not specified: on the lockstep levels a full batch's powers go
/// straight into the sums (only `tau_rb` is written), a short batch writes what the sums read.
#[allow(clippy::too_many_arguments)]
pub fn eval_rows_summed(
    model: &EnergyModel,
    data: &mut crate::dynamics::DynData,
    count: usize,
    r: &Rows<'_>,
    x: &mut LaneInputs,
    out: &mut PowerLanes,
    sums: &mut EnergySums,
    w: &Lanes,
    level: Level,
) -> Result<()> {
    eval_rows_with(model, data, count, r, x, out, Some((sums, w)), level)
}

#[allow(clippy::too_many_arguments)]
fn eval_rows_with(
    model: &EnergyModel,
    data: &mut crate::dynamics::DynData,
    count: usize,
    r: &Rows<'_>,
    x: &mut LaneInputs,
    out: &mut PowerLanes,
    sum: Option<(&mut EnergySums, &Lanes)>,
    level: Level,
) -> Result<()> {
    let n = model.n;
    let count = count.min(LANES);
    let short = r.q.len() < count * n
        || r.qd.len() < count * n
        || r.qdd.len() < count * n
        || r.sincos.is_some_and(|s| s.len() < count * 2 * n);
    if short {
        return Err(Error::SizeMismatch {
            what: "eval_rows: q, qd, qdd (n a sample), sincos (2 n a sample)".into(),
            got: r.q.len().min(r.qd.len()).min(r.qdd.len()),
            expected: count * n,
        });
    }
    if level == Level::Scalar || !model.batchable() {
        let mut sp = SamplePower::default();
        for l in 0..count {
            let (q, v, w) = (
                &r.q[l * n..][..n],
                &r.qd[l * n..][..n],
                &r.qdd[l * n..][..n],
            );
            match r.sincos {
                Some(sc) => super::eval_sample_with_sincos(
                    model,
                    data,
                    q,
                    &sc[l * 2 * n..][..2 * n],
                    v,
                    w,
                    &mut sp,
                )?,
                None => super::eval_sample(model, data, q, v, w, &mut sp)?,
            };
            out.set_sample(l, &sp);
        }
        if let Some((s, w)) = sum {
            s.add_lanes(out, w, count, n, level);
        }
        return Ok(());
    }
    match level {
        #[cfg(target_arch = "x86_64")]
        Level::Avx512 if Level::Avx512.available() => {
            // SAFETY: the CPU has AVX-512F (checked just above).
            unsafe { pass_avx512(model, count, r, x, out, sum) }
        }
        #[cfg(target_arch = "x86_64")]
        Level::Avx2 if Level::Avx2.available() => {
            // SAFETY: the CPU has AVX2 and FMA (checked just above).
            unsafe { pass_avx2(model, count, r, x, out, sum) }
        }
        _ => pass_sse2(model, count, r, x, out, sum),
    }
    Ok(())
}

/// [`super::eval_sample_with_sincos`] of `count ≤` [`LANES`] samples at once into the lanes
/// of `out` (see [`super::eval_batch_with_sincos`] for the arguments): lane `l` is
/// `q(l)`, `sincos(l)`, `qd(l)`, `qdd(l)` (rad, -, rad/s, rad/s²), and its supply power, W,
/// is `out.p_supply[l]`. RNEA, the torque effects, the motor model and the supply run in
/// lockstep on `level`; each lane is bit-identical to the per-sample path. With
/// [`Level::Scalar`] or a model that is not [`EnergyModel::batchable`] each sample goes
/// through [`super::eval_sample_with_sincos`]. Lanes `count..` are left as they were. Error:
/// [`Error::SizeMismatch`] on a wrong slice length.
#[allow(clippy::too_many_arguments)]
pub fn eval_lanes_with_sincos<'s>(
    model: &EnergyModel,
    data: &mut crate::dynamics::DynData,
    count: usize,
    q: impl Fn(usize) -> &'s [f64],
    sincos: impl Fn(usize) -> &'s [f64],
    qd: impl Fn(usize) -> &'s [f64],
    qdd: impl Fn(usize) -> &'s [f64],
    out: &mut PowerLanes,
    level: Level,
) -> Result<()> {
    let n = model.n;
    let count = count.min(LANES);
    if level == Level::Scalar || !model.batchable() {
        let mut sp = SamplePower::default();
        for l in 0..count {
            super::eval_sample_with_sincos(model, data, q(l), sincos(l), qd(l), qdd(l), &mut sp)?;
            out.set_sample(l, &sp);
        }
        return Ok(());
    }
    let mut b = StateBatch::default();
    let mut qb = [[0.0; LANES]; MAX_DOF];
    for l in 0..count {
        let (a, sc, v, w) = (q(l), sincos(l), qd(l), qdd(l));
        if sc.len() != 2 * n || v.len() != n || w.len() != n || a.len() != n {
            return Err(Error::SizeMismatch {
                what: "eval_batch_with_sincos: q, sincos (2 dof), qd, qdd".into(),
                got: sc.len().min(2 * v.len()).min(2 * w.len()),
                expected: 2 * n,
            });
        }
        b.set(l, n, sc, v, w);
        for (lanes, x) in qb.iter_mut().zip(a) {
            lanes[l] = *x;
        }
    }
    rnea_batch(&model.dynamics, &b, &mut out.tau_rb, level);
    let x = Inputs { q: &qb, b: &b };
    match level {
        #[cfg(target_arch = "x86_64")]
        Level::Avx512 if Level::Avx512.available() => {
            // SAFETY: the CPU has AVX-512F (checked just above).
            unsafe { tail_avx512(model, &x, out) }
        }
        #[cfg(target_arch = "x86_64")]
        Level::Avx2 if Level::Avx2.available() => {
            // SAFETY: the CPU has AVX2 and FMA (checked just above).
            unsafe { tail_avx2(model, &x, out) }
        }
        _ => tail_sse2(model, &x, out),
    }
    Ok(())
}

/// Trapezoid sums (J) of a placement's per-sample powers, kept as [`LANES`] interleaved
/// partial sums: sample `k` goes into lane `k mod LANES` (a lockstep batch starts at a multiple
/// of [`LANES`], so its lane `l` is lane `l` here), joint by joint; the totals add the lanes in
/// order at the end ([`EnergySums::lanes_total`]). The sums of the lockstep pass
/// ([`EnergySums::add_lanes`]) and of the per-sample path ([`EnergySums::add_sample`]) make the
/// same operations in the same order, so they give the same bits. Against one running sum in
/// sample order the result differs by rounding only (each is within the usual recursive
/// summation bound `(m/LANES + LANES + n) ε Σ|w p|` of the exact sum; tested against a
/// compensated sum in `tests/energy.rs`).
#[derive(Clone, Copy, Debug)]
pub struct EnergySums {
    /// `Σ w p_supply`, J.
    pub supply: Lanes,
    /// `Σ w p_drives`, J.
    pub drives: Lanes,
    /// `Σ w p_regeneration_lost`, J.
    pub regeneration_lost: Lanes,
    /// Per joint `Σ w p_mech`, J.
    pub mech: [Lanes; MAX_DOF],
    /// Per joint `Σ w |p_mech|`, J.
    pub mech_abs: [Lanes; MAX_DOF],
    /// Per joint `Σ w max(p_mech, 0)`, J.
    pub mech_pos: [Lanes; MAX_DOF],
    /// Per joint `Σ w p_el`, J.
    pub el: [Lanes; MAX_DOF],
    /// Per joint `Σ w p_friction`, J.
    pub friction: [Lanes; MAX_DOF],
    /// Per joint `Σ w p_gear`, J.
    pub gear: [Lanes; MAX_DOF],
    /// Per joint `Σ w p_copper`, J.
    pub copper: [Lanes; MAX_DOF],
}

impl Default for EnergySums {
    fn default() -> Self {
        let z = [[0.0; LANES]; MAX_DOF];
        EnergySums {
            supply: [0.0; LANES],
            drives: [0.0; LANES],
            regeneration_lost: [0.0; LANES],
            mech: z,
            mech_abs: z,
            mech_pos: z,
            el: z,
            friction: z,
            gear: z,
            copper: z,
        }
    }
}

/// One lane's additions of [`EnergySums`]: `w` s times the powers, W.
macro_rules! add_lane {
    ($s:ident, $l:expr, $w:expr, $n:expr, $supply:expr, $drives:expr, $lost:expr,
     |$j:ident| $pm:expr, $pel:expr, $pf:expr, $pg:expr, $pc:expr) => {{
        let (l, w) = ($l, $w);
        $s.supply[l] += w * $supply;
        $s.drives[l] += w * $drives;
        $s.regeneration_lost[l] += w * $lost;
        for $j in 0..$n {
            let pm = $pm;
            $s.mech[$j][l] += w * pm;
            $s.mech_abs[$j][l] += w * pm.abs();
            $s.mech_pos[$j][l] += w * pm.max(0.0);
            $s.el[$j][l] += w * $pel;
            $s.friction[$j][l] += w * $pf;
            $s.gear[$j][l] += w * $pg;
            $s.copper[$j][l] += w * $pc;
        }
    }};
}

impl EnergySums {
    /// Add sample `k`'s powers `sp` (W) with trapezoid weight `w` (s) into lane `k mod`
    /// [`LANES`], for the first `n` joints.
    #[inline]
    pub fn add_sample(&mut self, k: usize, sp: &SamplePower, w: f64, n: usize) {
        let n = n.min(MAX_DOF);
        add_lane!(
            self,
            k % LANES,
            w,
            n,
            sp.p_supply,
            sp.p_drives,
            sp.p_regeneration_lost,
            |j| sp.p_mech[j],
            sp.p_el[j],
            sp.p_friction[j],
            sp.p_gear[j],
            sp.p_copper[j]
        );
    }

    /// Add the first `count` lanes of `pl` (W; a batch starting at a multiple of [`LANES`])
    /// with trapezoid weights `w` (s) per lane, for the first `n` joints, on `level`:
    /// lane by lane the operations of [`EnergySums::add_sample`].
    pub(crate) fn add_lanes(
        &mut self,
        pl: &PowerLanes,
        w: &Lanes,
        count: usize,
        n: usize,
        level: Level,
    ) {
        let n = n.min(MAX_DOF);
        if count < LANES {
            self.add_partial(pl, w, count, n);
            return;
        }
        match level {
            #[cfg(target_arch = "x86_64")]
            Level::Avx512 if Level::Avx512.available() => {
                // SAFETY: the CPU has AVX-512F (checked just above).
                unsafe { sums_avx512(self, pl, w, n) }
            }
            #[cfg(target_arch = "x86_64")]
            Level::Avx2 if Level::Avx2.available() => {
                // SAFETY: the CPU has AVX2 and FMA (checked just above).
                unsafe { sums_avx2(self, pl, w, n) }
            }
            _ => sums_lanes(self, pl, w, n),
        }
    }

    /// Lanes `0..count` of `pl`, one by one ([`EnergySums::add_sample`]'s operations).
    #[inline(always)]
    fn add_partial(&mut self, pl: &PowerLanes, w: &Lanes, count: usize, n: usize) {
        let n = n.min(MAX_DOF);
        for l in 0..count.min(LANES) {
            add_lane!(
                self,
                l,
                w[l],
                n,
                pl.p_supply[l],
                pl.p_drives[l],
                pl.p_regeneration_lost[l],
                |j| pl.p_mech[j][l],
                pl.p_el[j][l],
                pl.p_friction[j][l],
                pl.p_gear[j][l],
                pl.p_copper[j][l]
            );
        }
    }

    /// The lanes of `a` added in order from +0, J.
    #[inline]
    pub fn lanes_total(a: &Lanes) -> f64 {
        let mut t = 0.0;
        for x in a {
            t += x;
        }
        t
    }
}

/// [`EnergySums::add_lanes`] of a full batch: joint-major, every lane at once.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // parallel fixed arrays indexed by joint and lane
fn sums_lanes(s: &mut EnergySums, pl: &PowerLanes, w: &Lanes, n: usize) {
    for l in 0..LANES {
        s.supply[l] += w[l] * pl.p_supply[l];
        s.drives[l] += w[l] * pl.p_drives[l];
        s.regeneration_lost[l] += w[l] * pl.p_regeneration_lost[l];
    }
    for j in 0..n {
        for l in 0..LANES {
            let pm = pl.p_mech[j][l];
            s.mech[j][l] += w[l] * pm;
            s.mech_abs[j][l] += w[l] * pm.abs();
            s.mech_pos[j][l] += w[l] * pm.max(0.0);
            s.el[j][l] += w[l] * pl.p_el[j][l];
            s.friction[j][l] += w[l] * pl.p_friction[j][l];
            s.gear[j][l] += w[l] * pl.p_gear[j][l];
            s.copper[j][l] += w[l] * pl.p_copper[j][l];
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn sums_avx2(s: &mut EnergySums, pl: &PowerLanes, w: &Lanes, n: usize) {
    sums_lanes(s, pl, w, n)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn sums_avx512(s: &mut EnergySums, pl: &PowerLanes, w: &Lanes, n: usize) {
    sums_lanes(s, pl, w, n)
}
