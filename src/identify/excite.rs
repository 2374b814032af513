//! An excitation experiment designed for the decision: periodic (Fourier) joint motion
//! within the joints' position, speed and acceleration limits, kept above a floor plane and
//! out of a keep-out box (the bed and the part), chosen so that the parameters the placement
//! decision depends on (the *targets*, e.g. the axis-2 balancer) are identifiable from a log
//! of it while the *nuisance* parameters (e.g. friction) are fitted alongside.
//!
//! Joint `j` moves as `q_j(t) = c_j + w(t) Σ_l (a_jl sin(l ω t) + b_jl cos(l ω t))` (`L`
//! harmonics of the base frequency `ω = 2π/T`), with a quintic fade-in and fade-out `w` over
//! the first and last `fade_s` so that the motion starts and ends at rest at the centre pose.
//! Each joint's coefficients are scaled so that its position excursion on either side of the
//! centre, its speed and its acceleration reach at most `limit_share` of the joint's limits
//! (the room to the limit on that side, so an asymmetric range is used in full; checked on the
//! samples).
//!
//! The information matrix is that of the identification's regressors: the derivative of the
//! joint torques with respect to each parameter (the identify model's effects, relative to
//! the parameter's magnitude), stacked over the samples and joints. The targets'
//! information given the nuisance parameters is the Schur complement `I_tt − I_tn I_nn⁻¹ I_nt`;
//! the design minimises its condition number (then maximises its log-determinant) among the
//! designs at least as informative as the sine sweep (log-determinant not below it), by a
//! seeded random search with local refinement that starts from the sine sweep,
//! and reports its condition number beside that of a naive sine sweep (one sine of period `T`
//! per joint at the same limits).

use crate::error::{Error, Result};
use crate::identify::model::Model;
use crate::robot::RobotModel;
use crate::trajectory::JointTrajectory;
use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;
use std::f64::consts::TAU;

/// Options of [`design`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ExciteOptions {
    /// Period of the Fourier motion, s.
    pub period_s: f64,
    /// Harmonics per joint.
    pub harmonics: usize,
    /// Periods in the experiment.
    pub periods: usize,
    /// Fade-in and fade-out, s.
    pub fade_s: f64,
    /// Sample rate of the written trajectory (the rate the controller logs at), Hz.
    pub rate_hz: f64,
    /// Share of each joint's position range on either side of the centre, speed and
    /// acceleration limit used (0–1).
    pub limit_share: f64,
    /// Effects whose parameters the decision depends on (identify's names).
    pub targets: Vec<String>,
    /// Effects fitted alongside (identify's names).
    pub nuisance: Vec<String>,
    /// Random designs tried, then as many local refinements.
    pub tries: usize,
    /// Seed of the search.
    pub seed: u64,
    /// Lowest height of every joint origin from joint 3 on and of the flange above the base
    /// frame's origin, m.
    pub floor_z_m: f64,
    /// A box (base frame, m: min and max corners) the elbow, wrist and flange stay out of:
    /// the bed and the part.
    pub keep_out: Option<([f64; 3], [f64; 3])>,
}

impl Default for ExciteOptions {
    /// 10 s period, 5 harmonics, 2 periods with 1 s fades, 250 Hz, 80 % of the limits, the
    /// balancer targeted with viscous and Coulomb friction as nuisance, 150 tries, seed 1,
    /// floor at 0.3 m, no keep-out box.
    fn default() -> Self {
        ExciteOptions {
            period_s: 10.0,
            harmonics: 5,
            periods: 2,
            fade_s: 1.0,
            rate_hz: 250.0,
            limit_share: 0.8,
            targets: vec!["balancer".into()],
            nuisance: vec!["viscous".into(), "coulomb".into()],
            tries: 150,
            seed: 1,
            floor_z_m: 0.3,
            keep_out: None,
        }
    }
}

/// How close the trajectory comes to each limit, as the largest share of it (0–1), per joint.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LimitUse {
    /// Position: largest distance from the centre over the distance to the limit on that side.
    pub position: Vec<f64>,
    /// Speed over the speed limit.
    pub speed: Vec<f64>,
    /// Acceleration over the acceleration limit.
    pub acceleration: Vec<f64>,
    /// Lowest height of the elbow, wrist and flange, m.
    pub lowest_z_m: f64,
}

/// The designed experiment.
#[derive(Clone, Debug, Serialize)]
pub struct Excitation {
    /// The joint motion at [`ExciteOptions::rate_hz`].
    #[serde(skip)]
    pub trajectory: JointTrajectory,
    /// The targeted parameters (effect and name).
    pub targets: Vec<String>,
    /// The nuisance parameters.
    pub nuisance: Vec<String>,
    /// Log-determinant of the targets' information given the nuisance parameters (relative
    /// parameters, unit noise).
    pub log_det: f64,
    /// Its condition number.
    pub condition: f64,
    /// The same for the naive sine sweep.
    pub naive_log_det: f64,
    /// Condition number of the naive sine sweep.
    pub naive_condition: f64,
    /// Designs evaluated.
    pub designs: usize,
    /// How close the designed motion comes to every limit.
    pub limits: LimitUse,
    /// The options.
    pub options: ExciteOptions,
}

/// Per joint: centre, and coefficients `a_l`, `b_l`.
#[derive(Clone, Debug)]
struct Design {
    centre: Vec<f64>,
    a: Vec<Vec<f64>>,
    b: Vec<Vec<f64>>,
}

/// Quintic smooth step on [0, 1] and its two derivatives (per unit of its argument).
fn smooth(x: f64) -> (f64, f64, f64) {
    if x <= 0.0 {
        return (0.0, 0.0, 0.0);
    }
    if x >= 1.0 {
        return (1.0, 0.0, 0.0);
    }
    let (x2, x3) = (x * x, x * x * x);
    (
        x3 * (10.0 - 15.0 * x + 6.0 * x2),
        30.0 * x2 * (1.0 - 2.0 * x + x2),
        60.0 * x * (1.0 - 3.0 * x + 2.0 * x2),
    )
}

fn duration(o: &ExciteOptions) -> f64 {
    o.period_s * o.periods as f64
}

/// The window: fade in over `fade`, out over the last `fade` (value, first, second
/// derivative).
fn window(t: f64, dur: f64, fade: f64) -> (f64, f64, f64) {
    if fade <= 0.0 {
        return (1.0, 0.0, 0.0);
    }
    let (a, da, dda) = smooth(t / fade);
    let (b, db, ddb) = smooth((dur - t) / fade);
    let (da, dda) = (da / fade, dda / (fade * fade));
    let (db, ddb) = (-db / fade, ddb / (fade * fade));
    (a * b, da * b + a * db, dda * b + 2.0 * da * db + a * ddb)
}

/// Joint `j`'s offset from its centre at `t` (without the centre): value, speed, acceleration.
fn joint_at(d: &Design, j: usize, t: f64, o: &ExciteOptions) -> (f64, f64, f64) {
    let w0 = TAU / o.period_s;
    let (mut f, mut fd, mut fdd) = (0.0, 0.0, 0.0);
    for (l, (a, b)) in d.a[j].iter().zip(&d.b[j]).enumerate() {
        let w = w0 * (l + 1) as f64;
        let (s, c) = (w * t).sin_cos();
        f += a * s + b * c;
        fd += w * (a * c - b * s);
        fdd -= w * w * (a * s + b * c);
    }
    let (g, gd, gdd) = window(t, duration(o), o.fade_s);
    (g * f, gd * f + g * fd, gdd * f + 2.0 * gd * fd + g * fdd)
}

fn sample(d: &Design, o: &ExciteOptions, rate: f64) -> JointTrajectory {
    let n = d.centre.len();
    let dur = duration(o);
    let len = (dur * rate).round() as usize + 1;
    let mut tr = JointTrajectory::new(n);
    let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for k in 0..len {
        let t = (k as f64 / rate).min(dur);
        for j in 0..n {
            let (f, fd, fdd) = joint_at(d, j, t, o);
            q[j] = d.centre[j] + f;
            qd[j] = fd;
            qdd[j] = fdd;
        }
        tr.push(t, &q, &qd, &qdd);
    }
    tr
}

/// Limits of a joint as the excitation uses them.
#[derive(Clone, Copy, Debug)]
struct JointRoom {
    /// Centre of the motion (the home pose 0 when inside the range, else the middle), rad.
    centre: f64,
    /// Room from the centre down to the lower limit, rad.
    below: f64,
    /// Room from the centre up to the upper limit, rad.
    above: f64,
    /// Speed limit, rad/s.
    speed: f64,
    /// Acceleration limit, rad/s².
    acceleration: f64,
}

impl JointRoom {
    /// The share of the room on its side that an offset `f` from the centre uses.
    fn position_share(&self, f: f64) -> f64 {
        if f >= 0.0 {
            f / self.above.max(1e-12)
        } else {
            -f / self.below.max(1e-12)
        }
    }
}

/// Centre, room to each position limit, speed and acceleration limits of joint `j`.
fn joint_limits(robot: &RobotModel, j: usize) -> JointRoom {
    let jt = &robot.joints[j];
    let (lo, hi) = if jt.upper > jt.lower {
        (jt.lower, jt.upper)
    } else {
        (-3.0, 3.0)
    };
    // The home pose (0) when inside the range, else the middle.
    let c = if lo < 0.0 && hi > 0.0 {
        0.0
    } else {
        0.5 * (lo + hi)
    };
    let v = if jt.velocity_limit > 0.0 {
        jt.velocity_limit
    } else {
        2.0
    };
    let a = if jt.acceleration_limit > 0.0 {
        jt.acceleration_limit
    } else {
        5.0
    };
    JointRoom {
        centre: c,
        below: c - lo,
        above: hi - c,
        speed: v,
        acceleration: a,
    }
}

/// Scale each joint's coefficients so that it uses at most `share` of its limits (checked on
/// a fine grid), times `pos_scale[j]` of its position room on either side of the centre.
fn scale_to_limits(robot: &RobotModel, d: &mut Design, o: &ExciteOptions, pos_scale: &[f64]) {
    let n = d.centre.len();
    let dur = duration(o);
    let m = (dur * 50.0).round() as usize + 1;
    for (j, &ps) in pos_scale.iter().enumerate().take(n) {
        let r = joint_limits(robot, j);
        let (mut up, mut down, mut mfd, mut mfdd) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for k in 0..m {
            let t = dur * k as f64 / (m - 1) as f64;
            let (f, fd, fdd) = joint_at(d, j, t, o);
            up = up.max(f);
            down = down.max(-f);
            mfd = mfd.max(fd.abs());
            mfdd = mfdd.max(fdd.abs());
        }
        // 2 % below the share: the grid may miss a peak between its points.
        let s = 0.98 * o.limit_share;
        let k = (s * r.above * ps / up.max(1e-12))
            .min(s * r.below * ps / down.max(1e-12))
            .min(s * r.speed / mfd.max(1e-12))
            .min(s * r.acceleration / mfdd.max(1e-12));
        for x in d.a[j].iter_mut().chain(d.b[j].iter_mut()) {
            *x *= k;
        }
    }
}

/// How close `tr` comes to every limit.
pub(crate) fn limit_use(robot: &RobotModel, tr: &JointTrajectory) -> LimitUse {
    let n = tr.n;
    let (mut p, mut s, mut a) = (vec![0.0f64; n], vec![0.0f64; n], vec![0.0f64; n]);
    let mut lowest = f64::INFINITY;
    for k in 0..tr.len() {
        for j in 0..n {
            let r = joint_limits(robot, j);
            p[j] = p[j].max(r.position_share(tr.q(k)[j] - r.centre));
            s[j] = s[j].max(tr.qd(k)[j].abs() / r.speed);
            a[j] = a[j].max(tr.qdd(k)[j].abs() / r.acceleration);
        }
        lowest = lowest.min(lowest_point(robot, tr.q(k)));
    }
    LimitUse {
        position: p,
        speed: s,
        acceleration: a,
        lowest_z_m: lowest,
    }
}

/// The points kept clear: joint origins from joint 3 on and the flange, base frame.
fn watched(robot: &RobotModel, q: &[f64]) -> Vec<[f64; 3]> {
    let f = crate::kinematics::fk::fk(robot, q);
    let mut v: Vec<[f64; 3]> = f
        .joint_frames()
        .iter()
        .skip(2)
        .map(|fr| [fr.pos.x, fr.pos.y, fr.pos.z])
        .collect();
    v.push([f.flange.pos.x, f.flange.pos.y, f.flange.pos.z]);
    v
}

fn lowest_point(robot: &RobotModel, q: &[f64]) -> f64 {
    watched(robot, q)
        .iter()
        .map(|p| p[2])
        .fold(f64::INFINITY, f64::min)
}

/// Whether every sample keeps the watched points above the floor and out of the box.
fn clear(robot: &RobotModel, tr: &JointTrajectory, o: &ExciteOptions) -> bool {
    let step = (tr.len() / 400).max(1);
    (0..tr.len()).step_by(step).all(|k| {
        watched(robot, tr.q(k)).iter().all(|p| {
            p[2] >= o.floor_z_m
                && o.keep_out
                    .is_none_or(|(lo, hi)| !(0..3).all(|i| p[i] >= lo[i] && p[i] <= hi[i]))
        })
    })
}

/// The regressor's parameters: (effect, index, name, scale).
fn parameters(model: &Model, effects: &[String]) -> Result<Vec<(String, usize, String, f64)>> {
    let mut v = Vec::new();
    for e in effects {
        let specs = model.params(e)?;
        let vals = model.values(e)?;
        for (i, sp) in specs.iter().enumerate() {
            let x = vals.get(i).copied().unwrap_or(0.0);
            let scale = if x.abs() > 0.0 {
                x.abs()
            } else if sp.upper.is_finite() && sp.upper > 0.0 {
                0.1 * sp.upper
            } else {
                1.0
            };
            v.push((e.clone(), i, format!("{e} {}", sp.name), scale));
        }
    }
    Ok(v)
}

/// The regressor's columns of `params` along `tr` (relative to each parameter's scale; rows
/// sample by sample, joint by joint): the derivative of the effects' torques, by forward
/// differences of the effect alone (the effects are linear in most parameters, where this is
/// exact).
fn columns(
    model: &Model,
    params: &[(String, usize, String, f64)],
    tr: &JointTrajectory,
    stride: usize,
) -> Result<Vec<Vec<f64>>> {
    let n = model.n;
    let p = params.len();
    let mut es = model.effects.clone();
    for name in crate::effects::catalogue() {
        es.set_enabled(name, false);
    }
    let mut cols: Vec<Vec<f64>> = Vec::with_capacity(p);
    let rows: Vec<usize> = (0..tr.len()).step_by(stride.max(1)).collect();
    for (e, i, _, scale) in params {
        es.set_enabled(e, true);
        let v0 = es.get_mut(e)?.values();
        let spec = &es.get_mut(e)?.params()[*i];
        let h = 1e-4 * scale;
        let hh = if v0[*i] + h <= spec.upper { h } else { -h };
        let mut v1 = v0.clone();
        v1[*i] += hh;
        let mut col = Vec::with_capacity(rows.len() * n);
        let (mut t0, mut t1) = (vec![0.0; n], vec![0.0; n]);
        let mut base = Vec::with_capacity(rows.len() * n);
        for &k in &rows {
            t0.iter_mut().for_each(|x| *x = 0.0);
            es.add_torque(tr.q(k), tr.qd(k), tr.qdd(k), &mut t0);
            base.extend_from_slice(&t0);
        }
        es.get_mut(e)?.set_values(&v1)?;
        for (r, &k) in rows.iter().enumerate() {
            t1.iter_mut().for_each(|x| *x = 0.0);
            es.add_torque(tr.q(k), tr.qd(k), tr.qdd(k), &mut t1);
            for j in 0..n {
                col.push((t1[j] - base[r * n + j]) / hh * scale);
            }
        }
        es.get_mut(e)?.set_values(&v0)?;
        es.set_enabled(e, false);
        cols.push(col);
    }
    Ok(cols)
}

/// Information matrix `Σ Yᵀ Y` of `params` along `tr` ([`columns`]).
fn information(
    model: &Model,
    params: &[(String, usize, String, f64)],
    tr: &JointTrajectory,
    stride: usize,
) -> Result<DMatrix<f64>> {
    let cols = columns(model, params, tr, stride)?;
    let p = cols.len();
    let mut m = DMatrix::zeros(p, p);
    for a in 0..p {
        for b in a..p {
            let s: f64 = cols[a].iter().zip(&cols[b]).map(|(x, y)| x * y).sum();
            m[(a, b)] = s;
            m[(b, a)] = s;
        }
    }
    Ok(m)
}

/// The targets' information given the nuisance parameters (Schur complement), its
/// log-determinant and condition number. `t`: the number of targets (the first rows).
fn targeted(info: &DMatrix<f64>, t: usize) -> (f64, f64) {
    let p = info.nrows();
    let itt = info.view((0, 0), (t, t)).into_owned();
    let s = if p > t {
        let itn = info.view((0, t), (t, p - t)).into_owned();
        let inn = info.view((t, t), (p - t, p - t)).into_owned();
        // A tiny ridge: nuisance columns that the motion does not excite are left out.
        let ridge = 1e-9 * inn.diagonal().max().max(1e-300);
        let inn = inn + DMatrix::identity(p - t, p - t) * ridge;
        match inn.cholesky() {
            Some(c) => &itt - &itn * c.solve(&itn.transpose()),
            None => itt,
        }
    } else {
        itt
    };
    let s = (&s + s.transpose()) * 0.5;
    let ev = s.symmetric_eigenvalues();
    let (lo, hi) = ev
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
    if lo <= 0.0 {
        return (f64::NEG_INFINITY, f64::INFINITY);
    }
    (ev.iter().map(|x| x.ln()).sum(), hi / lo)
}

/// The naive sine sweep: every joint one sine of the period at the same limits.
fn naive(robot: &RobotModel, o: &ExciteOptions) -> Design {
    let n = robot.dof();
    let mut d = Design {
        centre: (0..n).map(|j| joint_limits(robot, j).centre).collect(),
        a: vec![vec![0.0; o.harmonics]; n],
        b: vec![vec![0.0; o.harmonics]; n],
    };
    for j in 0..n {
        d.a[j][0] = 1.0;
    }
    d
}

/// A design scaled to the limits and shrunk in position until it keeps clear (at most 8
/// halvings toward 0.1 of the range); `None` when it never does.
fn fit_design(
    robot: &RobotModel,
    d: &Design,
    o: &ExciteOptions,
) -> Option<(Design, JointTrajectory)> {
    let n = robot.dof();
    let mut ps = vec![1.0; n];
    for _ in 0..8 {
        let mut x = d.clone();
        scale_to_limits(robot, &mut x, o, &ps);
        let tr = sample(&x, o, 20.0);
        if clear(robot, &tr, o) {
            return Some((x, tr));
        }
        // Shrink the arm joints (2, 3, 5) most: they move the wrist toward the floor.
        for (j, s) in ps.iter_mut().enumerate() {
            *s *= if matches!(j, 1 | 2 | 4) { 0.7 } else { 0.85 };
        }
    }
    None
}

/// The joints whose torque some of `params` acts on along `tr`.
fn acted_on(
    model: &Model,
    params: &[(String, usize, String, f64)],
    tr: &JointTrajectory,
) -> Result<Vec<bool>> {
    let n = model.n;
    let mut on = vec![false; n];
    for col in columns(model, params, tr, 1)? {
        for (i, v) in col.iter().enumerate() {
            if *v != 0.0 {
                on[i % n] = true;
            }
        }
    }
    Ok(on)
}

/// Design the experiment for `robot`. Errors: an unknown effect, no target parameter, no
/// design that keeps clear, a model error.
pub fn design(robot: &RobotModel, o: &ExciteOptions) -> Result<Excitation> {
    check_options(o)?;
    let mut model = Model::new(robot)?;
    for e in o.targets.iter().chain(&o.nuisance) {
        model.set_enabled(e, true)?;
    }
    let tp = parameters(&model, &o.targets)?;
    if tp.is_empty() {
        return Err(Error::Invalid(format!(
            "excite: the targets {:?} have no parameter on this robot",
            o.targets
        )));
    }
    let np = parameters(&model, &o.nuisance)?;
    let all: Vec<_> = tp.iter().chain(&np).cloned().collect();
    let n = robot.dof();
    let mut rng = ChaCha8Rng::seed_from_u64(o.seed);
    let sweep = naive(robot, o);
    let fitted_sweep = fit_design(robot, &sweep, o);
    // The search varies the motion of the joints whose torque the targets act on (on the sine
    // sweep); the other joints keep the sine sweep, which keeps clear. Their nuisance
    // parameters do not couple with the targets, so their motion cannot make the targets
    // better identifiable.
    let active = match &fitted_sweep {
        Some((_, tr)) => acted_on(&model, &tp, tr)?,
        None => vec![true; n],
    };
    let mut search = DesignSearch {
        robot,
        o,
        model: &model,
        all: &all,
        t: tp.len(),
        active,
        sweep,
        floor_ld: f64::NEG_INFINITY,
        designs: 0,
    };
    // The naive sine sweep is the first design: the search never returns a worse one, nor
    // one less informative (a lower log-determinant) than it.
    let mut best: Option<(Design, f64)> = match &fitted_sweep {
        Some((x, tr)) => {
            let sc = search.score(tr)?;
            search.floor_ld = sc.0;
            Some((x.clone(), search.merit(sc)))
        }
        None => None,
    };
    search.random_designs(&mut rng, &mut best)?;
    // Local refinement: perturb the best design's coefficients, shrinking the step.
    if let Some(b) = best.clone() {
        best = Some(search.refine(&mut rng, b)?);
    }
    let Some((d, _)) = best else {
        return Err(Error::Invalid(format!(
            "excite: no design keeps the elbow, wrist and flange above {:.2} m and out of the keep-out box within the limits",
            o.floor_z_m
        )));
    };
    let tr = sample(&d, o, o.rate_hz);
    let (log_det, condition) = search.score(&tr)?;
    let (naive_log_det, naive_condition) = match &fitted_sweep {
        Some((x, _)) => search.score(&sample(x, o, o.rate_hz))?,
        None => (f64::NEG_INFINITY, f64::INFINITY),
    };
    let limits = limit_use(robot, &tr);
    Ok(Excitation {
        trajectory: tr,
        targets: tp.iter().map(|p| p.2.clone()).collect(),
        nuisance: np.iter().map(|p| p.2.clone()).collect(),
        log_det,
        condition,
        naive_log_det,
        naive_condition,
        designs: search.designs,
        limits,
        options: o.clone(),
    })
}

/// Errors for options no design can follow: a period, rate, harmonic or period count that is
/// not positive, a limit share outside (0, 1].
fn check_options(o: &ExciteOptions) -> Result<()> {
    if !(o.period_s > 0.0 && o.rate_hz > 0.0 && o.harmonics >= 1 && o.periods >= 1) {
        return Err(Error::Invalid(
            "excite: period, rate, harmonics and periods must be > 0".into(),
        ));
    }
    if !(o.limit_share > 0.0 && o.limit_share <= 1.0) {
        return Err(Error::Invalid(
            "excite: limit share must be in (0, 1]".into(),
        ));
    }
    Ok(())
}

/// The search for an experiment: what it scores, the joints it varies, the sine sweep it
/// starts from and the designs it tried.
struct DesignSearch<'a> {
    robot: &'a RobotModel,
    o: &'a ExciteOptions,
    model: &'a Model,
    /// Target parameters first, then the nuisance ones.
    all: &'a [(String, usize, String, f64)],
    /// Number of target parameters.
    t: usize,
    /// Joints whose motion the search varies.
    active: Vec<bool>,
    sweep: Design,
    /// Log-determinant of the sine sweep: no design less informative is taken.
    floor_ld: f64,
    /// Designs tried.
    designs: usize,
}

impl DesignSearch<'_> {
    /// Log-determinant and condition number of the targets' information along `tr`.
    fn score(&self, tr: &JointTrajectory) -> Result<(f64, f64)> {
        Ok(targeted(&information(self.model, self.all, tr, 1)?, self.t))
    }

    /// What the search maximises: a small condition number first, then a large
    /// log-determinant (per target).
    fn merit(&self, (ld, cond): (f64, f64)) -> f64 {
        -cond.ln() + 0.1 * ld / self.t as f64
    }

    /// [`DesignSearch::merit`], minus infinity for a design less informative than the sweep.
    fn floored_merit(&self, sc: (f64, f64)) -> f64 {
        if sc.0 >= self.floor_ld {
            self.merit(sc)
        } else {
            f64::NEG_INFINITY
        }
    }

    /// A random design: the sweep with random coefficients (falling with the harmonic) on the
    /// varied joints.
    fn random(&self, rng: &mut ChaCha8Rng) -> Design {
        let mut d = self.sweep.clone();
        for j in (0..self.robot.dof()).filter(|&j| self.active[j]) {
            for x in d.a[j].iter_mut().chain(d.b[j].iter_mut()) {
                *x = rng.gen_range(-1.0..1.0);
            }
            for l in 0..self.o.harmonics {
                d.a[j][l] /= (l + 1) as f64;
                d.b[j][l] /= (l + 1) as f64;
            }
        }
        d
    }

    /// Random designs that keep clear, the best kept in `best`.
    fn random_designs(
        &mut self,
        rng: &mut ChaCha8Rng,
        best: &mut Option<(Design, f64)>,
    ) -> Result<()> {
        for _ in 0..self.o.tries {
            let d = self.random(rng);
            self.designs += 1;
            let Some((x, tr)) = fit_design(self.robot, &d, self.o) else {
                continue;
            };
            let m = self.floored_merit(self.score(&tr)?);
            if best.as_ref().is_none_or(|b| m > b.1) {
                *best = Some((x, m));
            }
        }
        Ok(())
    }

    /// Local refinement of `(design, merit)`: perturb the coefficients, shrinking the step.
    fn refine(
        &mut self,
        rng: &mut ChaCha8Rng,
        (b0, mut ld0): (Design, f64),
    ) -> Result<(Design, f64)> {
        let mut cur = b0;
        let mut step = 0.3;
        for _ in 0..self.o.tries {
            let mut d = cur.clone();
            for j in (0..self.robot.dof()).filter(|&j| self.active[j]) {
                let mag = d.a[j]
                    .iter()
                    .chain(&d.b[j])
                    .fold(0.0f64, |m, x| m.max(x.abs()))
                    .max(1e-6);
                for x in d.a[j].iter_mut().chain(d.b[j].iter_mut()) {
                    *x += step * mag * rng.gen_range(-1.0..1.0);
                }
            }
            self.designs += 1;
            let Some((x, tr)) = fit_design(self.robot, &d, self.o) else {
                step *= 0.9;
                continue;
            };
            let m = self.floored_merit(self.score(&tr)?);
            if m > ld0 {
                cur = x;
                ld0 = m;
            } else {
                step *= 0.95;
            }
        }
        Ok((cur, ld0))
    }
}

/// A keep-out box as `xmin,ymin,zmin,xmax,ymax,zmax` (base frame, m): its min and max
/// corners ([`ExciteOptions::keep_out`]). Errors: not six finite numbers, a min above its max.
pub fn parse_keep_out(s: &str) -> Result<([f64; 3], [f64; 3])> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect::<Option<_>>()
        .ok_or_else(|| Error::Invalid(format!("keep-out box `{s}`: expected six numbers in m")))?;
    match v.as_slice() {
        [x0, y0, z0, x1, y1, z1] if x0 <= x1 && y0 <= y1 && z0 <= z1 => {
            Ok(([*x0, *y0, *z0], [*x1, *y1, *z1]))
        }
        _ => Err(Error::Invalid(format!(
            "keep-out box `{s}`: expected xmin,ymin,zmin,xmax,ymax,zmax with min <= max"
        ))),
    }
}

/// The experiment's files for `robot_name`, name and text: `excite.csv` (the trajectory
/// `simulate --trajectory` reads), `excite.mod` (ABB RAPID) and `excite.script` (URScript),
/// their joint targets every `1 / target_hz` s, and `excite.json` (the design's figures).
pub fn files(
    e: &Excitation,
    robot_name: &str,
    target_hz: f64,
) -> Result<Vec<(&'static str, String)>> {
    if !(target_hz.is_finite() && target_hz > 0.0) {
        return Err(Error::Invalid(format!(
            "excite: joint target rate {target_hz} Hz: expected a number > 0"
        )));
    }
    let log_hz = e.options.rate_hz;
    Ok(vec![
        ("excite.csv", csv(&e.trajectory)),
        (
            "excite.mod",
            rapid(&e.trajectory, robot_name, target_hz, log_hz),
        ),
        (
            "excite.script",
            urscript(&e.trajectory, robot_name, target_hz, log_hz),
        ),
        (
            "excite.json",
            serde_json::to_string_pretty(e)
                .map_err(|x| Error::Invalid(format!("excite: the design as JSON: {x}")))?,
        ),
    ])
}

/// The trajectory as the CSV `simulate --trajectory` reads: `t[s]`, `q1[rad]…`, `qd1[rad/s]…`,
/// `qdd1[rad/s^2]…`.
pub fn csv(tr: &JointTrajectory) -> String {
    let n = tr.n;
    let mut head = vec!["t[s]".to_string()];
    head.extend((1..=n).map(|j| format!("q{j}[rad]")));
    head.extend((1..=n).map(|j| format!("qd{j}[rad/s]")));
    head.extend((1..=n).map(|j| format!("qdd{j}[rad/s^2]")));
    let mut s = head.join(",");
    s.push('\n');
    for k in 0..tr.len() {
        let mut row = vec![format!("{:.6}", tr.t[k])];
        row.extend(tr.q(k).iter().map(|v| format!("{v:.9}")));
        row.extend(tr.qd(k).iter().map(|v| format!("{v:.9}")));
        row.extend(tr.qdd(k).iter().map(|v| format!("{v:.9}")));
        s.push_str(&row.join(","));
        s.push('\n');
    }
    s
}

/// Every `k`-th sample such that the targets are `1/hz` apart.
fn every(tr: &JointTrajectory, hz: f64) -> Vec<usize> {
    if tr.len() < 2 {
        return (0..tr.len()).collect();
    }
    let dt = tr.t[1] - tr.t[0];
    let k = ((1.0 / hz) / dt).round().max(1.0) as usize;
    let mut v: Vec<usize> = (0..tr.len()).step_by(k).collect();
    if v.last() != Some(&(tr.len() - 1)) {
        v.push(tr.len() - 1);
    }
    v
}

/// An ABB RAPID module that plays the trajectory: joint targets (degrees) every `1/hz` s,
/// each reached in that time (`MoveAbsJ … \T`), with a small zone so that the motion flows.
/// The controller's log should be sampled at `log_hz` (stated in the module's header).
pub fn rapid(tr: &JointTrajectory, robot_name: &str, hz: f64, log_hz: f64) -> String {
    let idx = every(tr, hz);
    let mut s = format!(
        "MODULE printwatt_excite\n  ! Excitation trajectory for {robot_name}, written by printwatt excite.\n  ! {} joint targets every {:.3} s; log the axis torques at {log_hz:.0} Hz while it runs.\n",
        idx.len(),
        1.0 / hz
    );
    s.push_str(&format!(
        "  CONST num dt := {:.4};\n  PROC excite()\n",
        1.0 / hz
    ));
    let deg = |v: f64| v.to_degrees();
    for (i, &k) in idx.iter().enumerate() {
        let q = tr.q(k);
        let mut j: Vec<String> = q
            .iter()
            .take(6)
            .map(|v| format!("{:.4}", deg(*v)))
            .collect();
        while j.len() < 6 {
            j.push("0".into());
        }
        let target = format!("[[{}],[9E9,9E9,9E9,9E9,9E9,9E9]]", j.join(","));
        if i == 0 {
            s.push_str(&format!("    MoveAbsJ {target}, v100, fine, tool0;\n"));
        } else {
            let zone = if i + 1 == idx.len() { "fine" } else { "z1" };
            s.push_str(&format!(
                "    MoveAbsJ {target}, v1000\\T:=dt, {zone}, tool0;\n"
            ));
        }
    }
    s.push_str("  ENDPROC\nENDMODULE\n");
    s
}

/// A URScript program that plays the trajectory with `servoj` every `1/hz` s (positions in
/// rad); log at `log_hz`.
pub fn urscript(tr: &JointTrajectory, robot_name: &str, hz: f64, log_hz: f64) -> String {
    let idx = every(tr, hz);
    let mut s = format!(
        "# Excitation trajectory for {robot_name}, written by printwatt excite.\n# {} joint targets every {:.4} s (servoj); log joint torques/currents at {log_hz:.0} Hz.\ndef printwatt_excite():\n",
        idx.len(),
        1.0 / hz
    );
    let q0 = tr.q(0);
    s.push_str(&format!(
        "  movej([{}], a=0.5, v=0.5)\n",
        q0.iter()
            .map(|v| format!("{v:.6}"))
            .collect::<Vec<_>>()
            .join(", ")
    ));
    for &k in &idx {
        s.push_str(&format!(
            "  servoj([{}], 0, 0, {:.4}, 0.1, 300)\n",
            tr.q(k)
                .iter()
                .map(|v| format!("{v:.6}"))
                .collect::<Vec<_>>()
                .join(", "),
            1.0 / hz
        ));
    }
    s.push_str("  stopj(2.0)\nend\nprintwatt_excite()\n");
    s
}
