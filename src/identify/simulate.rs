//! Simulated logs from a "true" robot that differs from the nominal model by hidden effects
//! and parameter errors, with sensor noise, current quantisation and a controller's sample
//! rate; seeded (ChaCha8). The output follows docs/measurement-logs.md (`t`, `q1..qN`, signal).

use crate::effects::catalogue;
use crate::error::{Error, Result};
use crate::identify::log::SignalKind;
use crate::identify::model::{catalogue_index, Model};
use crate::robot::RobotModel;
use crate::trajectory::JointTrajectory;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// One hidden effect. For an effect with per-joint parameters, `effect=v` adds `v` to every
/// per-joint parameter, `effect[j]=v` only to joint `j` (1-based); `effect=v1:v2` adds `v1`
/// to the first per-joint kind and `v2` to the second (coulomb `f_c+:f_c−`, N·m); values
/// beyond the per-joint kinds *set* the effect's scalar parameters (stribeck `f_s:v_s`,
/// coulomb `f_c+:f_c−:ε`, rad/s). For an effect without per-joint parameters the values are
/// added in order (balancer `F0:k` N and N/m; payload `Δm:Δh_x:Δh_y:Δh_z` kg and kg·m).
#[derive(Clone, Debug, PartialEq)]
pub struct Hidden {
    /// Catalogue name.
    pub effect: &'static str,
    /// 1-based joint, or all.
    pub joint: Option<usize>,
    /// Values.
    pub values: Vec<f64>,
}

/// Split `effect[j]` into the effect's name and the 1-based joint `j` (`None` without
/// brackets): the one parser of per-joint effect names (`simulate`'s hidden effects,
/// `identify`'s per-joint subsets). Error: a joint that is not a whole number ≥ 1, or a
/// bracket left open.
pub(crate) fn split_joint(s: &str) -> Result<(&str, Option<usize>)> {
    let s = s.trim();
    match s.split_once('[') {
        Some((n, j)) => {
            let k = j
                .strip_suffix(']')
                .and_then(|j| j.trim().parse::<usize>().ok())
                .filter(|&k| k >= 1)
                .ok_or_else(|| {
                    Error::Invalid(format!(
                        "`{s}`: expected effect[j] with a joint j from 1 (e.g. viscous[2])"
                    ))
                })?;
            Ok((n.trim(), Some(k)))
        }
        None => Ok((s, None)),
    }
}

/// Parse `coulomb=40,balancer=8000:20000,payload=+15,viscous[2]=30`.
pub fn parse_hidden(s: &str) -> Result<Vec<Hidden>> {
    let mut out = Vec::new();
    for item in s.split(',').map(str::trim).filter(|x| !x.is_empty()) {
        let (lhs, rhs) = item.split_once('=').ok_or_else(|| {
            Error::Invalid(format!("hidden effect `{item}`: expected effect=value"))
        })?;
        let (name, joint) = split_joint(lhs)
            .map_err(|_| Error::Invalid(format!("hidden effect `{item}`: bad joint index")))?;
        let i = catalogue_index(name)?;
        let values = rhs
            .split(':')
            .map(|v| {
                v.trim().parse::<f64>().map_err(|_| {
                    Error::Invalid(format!("hidden effect `{item}`: `{v}` is not a number"))
                })
            })
            .collect::<Result<Vec<f64>>>()?;
        out.push(Hidden {
            effect: catalogue()[i],
            joint,
            values,
        });
    }
    Ok(out)
}

/// Apply hidden effects to a model (switching them on). Values leaving the bounds are clamped.
pub fn apply_hidden(model: &mut Model, hidden: &[Hidden]) -> Result<()> {
    let n = model.n;
    for h in hidden {
        model.set_enabled(h.effect, true)?;
        let specs = model.params(h.effect)?;
        let mut v = model.values(h.effect)?;
        // Per-joint kinds (`f_c+[..]`, `f_c-[..]`) in order, and the scalar parameters.
        let mut kinds: Vec<String> = Vec::new();
        for sp in &specs {
            if let Some((k, _)) = sp.name.split_once('[') {
                if !kinds.iter().any(|x| x == k) {
                    kinds.push(k.to_string());
                }
            }
        }
        if kinds.is_empty() {
            for (x, a) in v.iter_mut().zip(&h.values) {
                *x += a;
            }
        } else {
            let mut scalar = h.values.iter().skip(kinds.len());
            for (i, sp) in specs.iter().enumerate() {
                match sp.name.split_once('[') {
                    Some((k, jt)) => {
                        let kind = kinds.iter().position(|x| x == k).unwrap_or(0);
                        let add = if h.values.len() == 1 {
                            h.values[0]
                        } else {
                            h.values.get(kind).copied().unwrap_or(0.0)
                        };
                        let j = jt.trim_end_matches(']').parse::<usize>().unwrap_or(0);
                        if j <= n && h.joint.is_none_or(|k| k == j) {
                            v[i] += add;
                        }
                    }
                    None => {
                        if let Some(x) = scalar.next() {
                            v[i] = *x;
                        }
                    }
                }
            }
        }
        for (x, s) in v.iter_mut().zip(&specs) {
            *x = x.clamp(s.lower, s.upper);
        }
        if h.effect == "payload" && h.values.len() <= 4 {
            // A hidden load (mass and first moment) keeps its inertia about its own centre of
            // mass, as identify's payload does.
            v.truncate(4);
        }
        model.set_values(h.effect, &v)?;
    }
    Ok(())
}

/// A smooth exciting trajectory: per joint a sum of three sines within position, velocity
/// and acceleration limits (a third of each), about the middle of the joint range, sampled at
/// `rate_hz` for `duration_s`. Analytic `q̇`, `q̈`.
pub fn excitation(robot: &RobotModel, duration_s: f64, rate_hz: f64, seed: u64) -> JointTrajectory {
    let n = robot.dof();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let w = [0.6, 0.3, 0.1];
    let mut spec = Vec::new();
    for (j, jt) in robot.joints.iter().enumerate() {
        let (lo, hi) = if jt.upper > jt.lower {
            (jt.lower, jt.upper)
        } else {
            (-3.0, 3.0)
        };
        let centre = 0.5 * (lo + hi);
        let f0 = 0.15 + 0.035 * j as f64 + 0.02 * rng.gen::<f64>();
        let f = [f0, 2.3 * f0, 3.7 * f0];
        let tw = std::f64::consts::TAU;
        let sv: f64 = (0..3).map(|k| w[k] * tw * f[k]).sum();
        let sa: f64 = (0..3).map(|k| w[k] * (tw * f[k]).powi(2)).sum();
        let vl = if jt.velocity_limit > 0.0 {
            jt.velocity_limit
        } else {
            2.0
        };
        let al = if jt.acceleration_limit > 0.0 {
            jt.acceleration_limit
        } else {
            5.0
        };
        let amp = (0.3 * 0.5 * (hi - lo))
            .min(0.35 * vl / sv)
            .min(0.35 * al / sa);
        let ph: Vec<f64> = (0..3).map(|_| rng.gen::<f64>() * tw).collect();
        spec.push((centre, amp, f, ph));
    }
    let mut tr = JointTrajectory::new(n);
    let len = (duration_s * rate_hz).round().max(2.0) as usize;
    let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for k in 0..len {
        let t = k as f64 / rate_hz;
        for (j, (c, a, f, ph)) in spec.iter().enumerate() {
            q[j] = *c;
            qd[j] = 0.0;
            qdd[j] = 0.0;
            for i in 0..3 {
                let om = std::f64::consts::TAU * f[i];
                let x = om * t + ph[i];
                q[j] += a * w[i] * x.sin();
                qd[j] += a * w[i] * om * x.cos();
                qdd[j] -= a * w[i] * om * om * x.sin();
            }
        }
        tr.push(t, &q, &qd, &qdd);
    }
    tr
}

/// Resample a trajectory (with `qd`, `qdd`) at `rate_hz` by linear interpolation.
pub fn resample(tr: &JointTrajectory, rate_hz: f64) -> JointTrajectory {
    let n = tr.n;
    let mut out = JointTrajectory::new(n);
    if tr.len() < 2 {
        return tr.clone();
    }
    let t0 = tr.t[0];
    let dur = tr.duration();
    let len = (dur * rate_hz).floor() as usize + 1;
    let mut i = 0;
    let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for k in 0..len {
        let t = t0 + k as f64 / rate_hz;
        while i + 2 < tr.len() && tr.t[i + 1] < t {
            i += 1;
        }
        let a = ((t - tr.t[i]) / (tr.t[i + 1] - tr.t[i])).clamp(0.0, 1.0);
        for j in 0..n {
            let lerp = |v: &[f64]| v[i * n + j] * (1.0 - a) + v[(i + 1) * n + j] * a;
            q[j] = lerp(&tr.q);
            qd[j] = lerp(&tr.qd);
            qdd[j] = lerp(&tr.qdd);
        }
        out.push(t - t0, &q, &qd, &qdd);
    }
    out
}

/// Sensor options of a simulated log.
#[derive(Clone, Debug)]
pub struct SensorOptions {
    /// Signal written.
    pub kind: SignalKind,
    /// Standard deviation of the signal noise (signal unit).
    pub noise: f64,
    /// Standard deviation of the position noise, rad.
    pub noise_q: f64,
    /// Current quantisation step, A (current logs; 0 = none).
    pub current_quantum: f64,
    /// Seed.
    pub seed: u64,
}

fn gauss(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = rng.gen::<f64>().max(1e-300);
    let u2: f64 = rng.gen();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// The log text (CSV, contract format) of the true model `truth` along `traj` (`qd`, `qdd`
/// filled). `metadata`: extra `# key: value` lines.
pub fn simulate_log(
    truth: &Model,
    traj: &JointTrajectory,
    opt: &SensorOptions,
    metadata: &[(String, String)],
) -> Result<String> {
    let n = truth.n;
    if opt.kind == SignalKind::Current && !truth.has_drive {
        return Err(Error::Invalid(format!(
            "robot `{}` has no drive data (gear ratio, K_t): a current log cannot be simulated; \
simulate `tau`, `p` or `p_total`",
            truth.robot_name
        )));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(opt.seed);
    let ch = opt.kind.channels(n);
    let mut s = String::new();
    for (k, v) in metadata {
        s.push_str(&format!("# {k}: {v}\n"));
    }
    let mut head = vec!["t[s]".to_string()];
    head.extend((1..=n).map(|j| format!("q{j}[rad]")));
    if opt.kind == SignalKind::TotalPower {
        head.push("p_total[W]".into());
    } else {
        head.extend((1..=n).map(|j| {
            format!(
                "{}{j}[{}]",
                opt.kind.prefix(),
                match opt.kind {
                    SignalKind::Torque => "Nm",
                    SignalKind::Current => "A",
                    _ => "W",
                }
            )
        }));
    }
    s.push_str(&head.join(","));
    s.push('\n');
    let mut tau = vec![0.0; n];
    let mut y = vec![0.0; ch];
    for k in 0..traj.len() {
        truth.torque(traj.q(k), traj.qd(k), traj.qdd(k), &mut tau)?;
        truth.signal_from_torque(opt.kind, &tau, traj.qd(k), &mut y);
        let mut vals = vec![traj.t[k]];
        for j in 0..n {
            vals.push(traj.q(k)[j] + opt.noise_q * gauss(&mut rng));
        }
        for v in &y {
            let mut x = v + opt.noise * gauss(&mut rng);
            if opt.kind == SignalKind::Current && opt.current_quantum > 0.0 {
                x = (x / opt.current_quantum).round() * opt.current_quantum;
            }
            vals.push(x);
        }
        // The last check before the numbers leave: the error names the sample and column.
        crate::output::check_finite_row("simulated log", &head, k, &vals)?;
        let row: Vec<String> = vals
            .iter()
            .enumerate()
            .map(|(i, v)| match i {
                0 => format!("{v:.6}"),
                i if i <= n => format!("{v:.9}"),
                _ => format!("{v:.6}"),
            })
            .collect();
        s.push_str(&row.join(","));
        s.push('\n');
    }
    Ok(s)
}
