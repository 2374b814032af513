//! General inverse kinematics for arms without a closed form (e.g. UR10e): damped least squares
//! with Levenberg–Marquardt damping on the full 6-D pose error of the tool, with joint limits.
//!
//! Targets are **tool** (nozzle tip) poses in the base frame, m / rad.

use super::fk::{fk, jacobian_of_frames, FkFrames};
use super::{pose_error, IkFailure, JointVec, MAX_DOF};
use crate::math::Frame;
use crate::robot::RobotModel;
use nalgebra::{Matrix6, Vector6};

/// Settings of the Levenberg–Marquardt iteration.
#[derive(Clone, Copy, Debug)]
pub struct NumericOptions {
    /// Maximum iterations per seed.
    pub max_iterations: usize,
    /// Position tolerance of the tool point, m.
    pub tol_position_m: f64,
    /// Orientation tolerance, rad.
    pub tol_orientation_rad: f64,
    /// Initial damping λ (same mixed units as the Jacobian: m for position rows).
    pub initial_damping: f64,
    /// Largest joint step per iteration, rad (m for prismatic joints).
    pub max_step: f64,
    /// Number of deterministic seeds used by [`solve_all`].
    pub seeds: usize,
    /// Restarts of [`solve_from`] when the first attempt stalls: from the seeds of
    /// [`seeds`]`(model, restart_pool)` nearest to the given seed, nearest first.
    pub restarts: usize,
    /// Number of deterministic seeds the restarts are chosen from.
    pub restart_pool: usize,
}

impl Default for NumericOptions {
    fn default() -> Self {
        NumericOptions {
            max_iterations: 200,
            tol_position_m: 1e-11,
            tol_orientation_rad: 1e-11,
            initial_damping: 1e-2,
            max_step: 0.5,
            seeds: 32,
            restarts: RESTARTS,
            restart_pool: 64,
        }
    }
}

#[inline]
fn clamp_limits(model: &RobotModel, q: &mut JointVec) {
    for (i, j) in model.joints.iter().enumerate().take(q.len()) {
        q[i] = q[i].clamp(j.lower, j.upper);
    }
}

#[inline]
fn err_of(target: &Frame, f: &FkFrames) -> (Vector6<f64>, f64) {
    let e = pose_error(target, &f.tool);
    let n = e.norm_squared();
    (e, n)
}

/// Default of [`NumericOptions::restarts`].
pub(crate) const RESTARTS: usize = 8;

/// Solve from one seed (rad / m, clamped into the limits first). When that attempt stalls in a
/// local minimum, restart from up to [`NumericOptions::restarts`] deterministic seeds, nearest
/// to `seed` first (distance modulo 2π, so the answer stays close to the seed where possible).
/// Returns the converged joint vector (within limits) or [`IkFailure::NoConvergence`] with the
/// errors of the first attempt.
pub fn solve_from(
    model: &RobotModel,
    tool_target: &Frame,
    seed: &[f64],
    opts: &NumericOptions,
) -> Result<JointVec, IkFailure> {
    let n = model.dof();
    if n > MAX_DOF || seed.len() < n {
        return Err(IkFailure::Unsupported(format!(
            "numeric IK needs a seed of {n} joints (≤ {MAX_DOF}), got {}",
            seed.len()
        )));
    }
    let first = match solve_once(model, tool_target, &seed[..n], opts) {
        Ok(q) => return Ok(q),
        Err(e) => e,
    };
    if opts.restarts == 0 {
        return Err(first);
    }
    let dist = |q: &[f64]| -> f64 {
        model
            .joints
            .iter()
            .zip(q.iter().zip(seed))
            .map(|(j, (a, b))| match j.kind {
                crate::robot::JointKind::Revolute => super::opw::wrap_pi(a - b).powi(2),
                crate::robot::JointKind::Prismatic => (a - b).powi(2),
            })
            .sum()
    };
    let mut pool: Vec<(f64, JointVec)> = seeds(model, opts.restart_pool.max(opts.restarts))
        .into_iter()
        .map(|s| (dist(&s), s))
        .collect();
    pool.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (_, s) in pool.iter().take(opts.restarts) {
        if let Ok(q) = solve_once(model, tool_target, s, opts) {
            return Ok(q);
        }
    }
    Err(first)
}

/// One Levenberg–Marquardt attempt from `seed` (clamped into the limits first), no restarts.
pub fn solve_once(
    model: &RobotModel,
    tool_target: &Frame,
    seed: &[f64],
    opts: &NumericOptions,
) -> Result<JointVec, IkFailure> {
    let n = model.dof().min(seed.len()).min(MAX_DOF);
    let mut q = JointVec::from_slice(&seed[..n]);
    clamp_limits(model, &mut q);
    let mut frames = fk(model, &q);
    let (mut e, mut err) = err_of(tool_target, &frames);
    let mut lambda = opts.initial_damping;
    let tol2 = |e: &Vector6<f64>| {
        e.fixed_rows::<3>(0).norm() < opts.tol_position_m
            && e.fixed_rows::<3>(3).norm() < opts.tol_orientation_rad
    };
    let mut iterations = 0;
    for it in 0..opts.max_iterations {
        iterations = it + 1;
        if tol2(&e) {
            return Ok(q);
        }
        let jac = jacobian_of_frames(model, &frames);
        let mut a: Matrix6<f64> = jac.jjt();
        for d in 0..6 {
            a[(d, d)] += lambda * lambda;
        }
        let Some(ch) = a.cholesky() else {
            lambda *= 10.0;
            continue;
        };
        let y = ch.solve(&e);
        let mut dq = [0.0; MAX_DOF];
        let mut big: f64 = 0.0;
        for (i, c) in jac.cols[..n].iter().enumerate() {
            dq[i] = (0..6).map(|r| c[r] * y[r]).sum();
            big = big.max(dq[i].abs());
        }
        let scale = if big > opts.max_step {
            opts.max_step / big
        } else {
            1.0
        };
        let mut qn = q;
        for i in 0..n {
            qn[i] += dq[i] * scale;
        }
        clamp_limits(model, &mut qn);
        let fnew = fk(model, &qn);
        let (en, errn) = err_of(tool_target, &fnew);
        if errn < err {
            q = qn;
            frames = fnew;
            e = en;
            err = errn;
            lambda = (lambda * 0.3).max(1e-9);
        } else {
            lambda = (lambda * 4.0).min(1e4);
            if lambda >= 1e4 {
                break;
            }
        }
    }
    if tol2(&e) {
        return Ok(q);
    }
    Err(IkFailure::NoConvergence {
        iterations,
        position_error_m: e.fixed_rows::<3>(0).norm(),
        orientation_error_rad: e.fixed_rows::<3>(3).norm(),
    })
}

/// Van der Corput radical inverse in base `b` (deterministic low-discrepancy seeds).
fn radical_inverse(mut i: usize, b: usize) -> f64 {
    let mut f = 1.0;
    let mut r = 0.0;
    while i > 0 {
        f /= b as f64;
        r += f * (i % b) as f64;
        i /= b;
    }
    r
}

const PRIMES: [usize; MAX_DOF] = [2, 3, 5, 7, 11, 13, 17, 19];

/// The deterministic seeds used by [`solve_all`]: the zero pose, then a Halton sequence over
/// the joint ranges (clipped to ±π), rad / m.
pub fn seeds(model: &RobotModel, count: usize) -> Vec<JointVec> {
    let n = model.dof().min(MAX_DOF);
    let mut out = Vec::with_capacity(count);
    let mut z = JointVec::zeros(n);
    clamp_limits(model, &mut z);
    out.push(z);
    for k in 1..count {
        let mut q = JointVec::zeros(n);
        for (i, j) in model.joints.iter().take(n).enumerate() {
            let lo = j.lower.max(-std::f64::consts::PI);
            let hi = j.upper.min(std::f64::consts::PI);
            q[i] = lo + (hi - lo) * radical_inverse(k, PRIMES[i]);
        }
        out.push(q);
    }
    out
}

/// All distinct solutions found from [`NumericOptions::seeds`] deterministic seeds (not
/// guaranteed complete). Two solutions are the same when every joint agrees within 1e-6
/// (modulo 2π for revolute joints). On no solution, the failure of the best attempt.
pub fn solve_all(
    model: &RobotModel,
    tool_target: &Frame,
    opts: &NumericOptions,
) -> Result<Vec<JointVec>, IkFailure> {
    let mut sols: Vec<JointVec> = Vec::new();
    let mut last = None;
    for s in seeds(model, opts.seeds) {
        match solve_once(model, tool_target, &s, opts) {
            Ok(q) => {
                if !sols.iter().any(|p| same_modulo_2pi(model, p, &q, 1e-6)) {
                    sols.push(q);
                }
            }
            Err(e) => last = Some(e),
        }
    }
    if sols.is_empty() {
        return Err(last.unwrap_or(IkFailure::Unsupported("no seeds".into())));
    }
    Ok(sols)
}

/// Whether two joint vectors agree within `tol` (rad / m), revolute joints modulo 2π.
pub(crate) fn same_modulo_2pi(model: &RobotModel, a: &[f64], b: &[f64], tol: f64) -> bool {
    model.joints.iter().enumerate().all(|(i, j)| {
        let d = a[i] - b[i];
        match j.kind {
            crate::robot::JointKind::Revolute => super::opw::wrap_pi(d).abs() < tol,
            crate::robot::JointKind::Prismatic => d.abs() < tol,
        }
    })
}
