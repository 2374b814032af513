//! Comparison metrics (docs/measurement-logs.md "What is compared"): RMSE of the compared
//! signal per channel and in total (seed 000, eq. 8), energy over the log and its relative
//! error, accuracy `100 % − |relative energy error|`; where the residual sits: worst time
//! windows and operating regimes per joint.
//!
//! Energies: `tau` logs `∫ max(τ q̇, 0) dt` per joint (mechanical energy drawn); `i` logs the
//! same with `τ = K_t G i`; `p` and `p_total` logs `∫ P dt` (what a meter integrates). Trapezoidal.
#![allow(clippy::needless_range_loop)] // parallel per-sample arrays indexed by sample

use crate::identify::log::SignalKind;
use crate::identify::model::{Model, Prepared};
use crate::identify::motion::Rate;
use serde::Serialize;

/// Metrics of one channel or of the total.
#[derive(Clone, Debug, Serialize)]
pub struct ChannelMetrics {
    /// `joint_1`…, or `total`.
    pub name: String,
    /// RMSE of the compared signal (signal unit).
    pub rmse: f64,
    /// RMS of the measured signal (signal unit).
    pub measured_rms: f64,
    /// Measured energy, J.
    pub energy_measured_j: f64,
    /// Modelled energy, J.
    pub energy_model_j: f64,
    /// Relative energy error `(E_model − E_measured)/|E_measured|`, %.
    pub energy_error_pct: f64,
    /// `100 − |energy_error_pct|`, %.
    pub accuracy_pct: f64,
}

/// A time window with a large residual.
#[derive(Clone, Debug, Serialize)]
pub struct Window {
    /// Start time, s.
    pub t_start: f64,
    /// End time, s.
    pub t_end: f64,
    /// Residual RMSE in the window (signal unit).
    pub rmse: f64,
    /// Channel with the largest residual there.
    pub worst_channel: String,
}

/// Share of the squared residual in one operating regime of one joint.
#[derive(Clone, Debug, Serialize)]
pub struct Regime {
    /// Joint name.
    pub joint: String,
    /// `positive_speed`, `negative_speed`, `near_zero_speed`, `high_acceleration`,
    /// `pose_bin_k_of_4`.
    pub regime: String,
    /// Share of samples, %.
    pub samples_pct: f64,
    /// Share of the squared residual, %.
    pub residual_pct: f64,
}

/// The full comparison.
#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    /// Version of this JSON shape (docs/json.md).
    pub schema_version: u32,
    /// The calibration the model came from (`None`: a nominal robot).
    pub calibration: Option<String>,
    /// Log file.
    pub log: String,
    /// Signal compared.
    pub signal: SignalKind,
    /// Its unit.
    pub unit: String,
    /// Samples.
    pub samples: usize,
    /// Duration, s.
    pub duration_s: f64,
    /// Effects switched on in the model.
    pub effects: Vec<String>,
    /// Per channel.
    pub channels: Vec<ChannelMetrics>,
    /// Total.
    pub total: ChannelMetrics,
    /// Worst windows, largest first.
    pub worst_windows: Vec<Window>,
    /// Regimes whose residual share exceeds their sample share by 1.5× or more, largest
    /// ratio first (all regimes in `regimes_all`).
    pub regimes: Vec<Regime>,
    /// All regimes (share of the squared residual per regime; kept for older readers: a
    /// share cannot see friction, read `failures`).
    pub regimes_all: Vec<Regime>,
    /// Where the model fails: per joint and structure (`direction`, `velocity`, `position`,
    /// `acceleration`, `time`), the residual RMS each explains beyond the noise floor, largest
    /// first ([`crate::identify::profiles`]).
    pub failures: Vec<crate::identify::profiles::Failure>,
    /// Per joint, the residual binned against velocity, position and time, and the direction
    /// step at q̇ = 0.
    pub profiles: Vec<crate::identify::profiles::JointProfiles>,
    /// Warnings from reading the log.
    pub warnings: Vec<String>,
}

use crate::numerics::trapezoid as integrate;

/// Channel names for a log.
pub(crate) fn channel_names(prep: &Prepared) -> Vec<String> {
    if prep.log.kind == SignalKind::TotalPower {
        vec!["total".into()]
    } else {
        (1..=prep.log.traj.n)
            .map(|j| format!("joint_{j}"))
            .collect()
    }
}

/// Power series (W) of channel `c` at every row of the log, with signal value `v(k)` and
/// velocity `qd[k]` of the channel's joint ([`channel_joint`]).
fn power_by(
    prep: &Prepared,
    model: &Model,
    qd: &[f64],
    v: impl Fn(usize) -> f64,
    c: usize,
) -> Vec<f64> {
    (0..qd.len())
        .map(|k| power_at(prep, model, qd[k], v(k), c))
        .collect()
}

/// The joint whose velocity channel `c`'s power takes.
fn channel_joint(prep: &Prepared, c: usize) -> usize {
    c.min(prep.log.traj.n - 1)
}

/// Power (W) of channel `c` with signal value `v` at its joint's velocity `qd`.
fn power_at(prep: &Prepared, model: &Model, qd: f64, v: f64, c: usize) -> f64 {
    match prep.log.kind {
        SignalKind::Torque => (v * qd).max(0.0),
        SignalKind::Current => (v * model.kt[c] * model.gear[c] * qd).max(0.0),
        _ => v,
    }
}

/// RMSE and energies on a subset of rows: (rmse, measured J, model J). The rows are predicted
/// a block at a time; each sum adds the same terms in the same order as over whole columns.
pub fn evaluate_rows(prep: &Prepared, model: &Model, rows: &[usize]) -> (f64, f64, f64) {
    let ch = prep.log.channels;
    let y = &prep.log.y;
    let t = &prep.log.traj.t;
    // What a sum of no terms is: each sum below continues from it, as `Iterator::sum` does.
    let empty: f64 = std::iter::empty::<f64>().sum();
    let mut ssr = empty;
    // Per channel: the trapezoid sums of the measured and the modelled power, and the
    // previous sample's (time, measured power, modelled power).
    let mut em_c = vec![empty; ch];
    let mut ep_c = vec![empty; ch];
    let mut prev: Vec<Option<(f64, f64, f64)>> = vec![None; ch];
    let mut pred = Vec::new();
    for block in rows.chunks(crate::identify::columns::BLOCK_ROWS) {
        prep.predict(model, block, &mut pred);
        for (r, &k) in block.iter().enumerate() {
            let rates = prep.rates(k, false);
            for c in 0..ch {
                let (a, b) = (pred[r * ch + c], y[k * ch + c]);
                ssr += (a - b).powi(2);
                let qd = rates.qd()[channel_joint(prep, c)];
                let (pm, pp) = (
                    power_at(prep, model, qd, b, c),
                    power_at(prep, model, qd, a, c),
                );
                if let Some((t0, m0, p0)) = prev[c] {
                    em_c[c] += 0.5 * (t[k] - t0) * (m0 + pm);
                    ep_c[c] += 0.5 * (t[k] - t0) * (p0 + pp);
                }
                prev[c] = Some((t[k], pm, pp));
            }
        }
    }
    let (mut em, mut ep) = (0.0, 0.0);
    for c in 0..ch {
        em += em_c[c];
        ep += ep_c[c];
    }
    ((ssr / (rows.len() * ch).max(1) as f64).sqrt(), em, ep)
}

/// Relative error in %, guarded against a zero reference.
pub(crate) fn rel_pct(model: f64, measured: f64) -> f64 {
    if measured.abs() > 1e-12 {
        100.0 * (model - measured) / measured.abs()
    } else if model.abs() > 1e-12 {
        100.0
    } else {
        0.0
    }
}

/// Compare the model with the whole log. Returns the metrics and the prediction
/// (row-major `len × channels`).
pub fn compare(prep: &Prepared, model: &Model) -> (Comparison, Vec<f64>) {
    let (cmp, pred) = compare_with(prep, model, true);
    (cmp, pred.unwrap_or_default())
}

/// [`compare`] without the prediction: the metrics only. The prediction of a long log is
/// kept outside memory while the metrics pass over it ([`crate::identify::columns`]), so that
/// the memory holds the log and one channel at a time.
pub fn compare_metrics(prep: &Prepared, model: &Model) -> Comparison {
    compare_with(prep, model, false).0
}

/// The comparison, and the prediction when `want_pred`: with the prediction in a temporary
/// file, or in memory when the file fails (the same numbers either way).
fn compare_with(prep: &Prepared, model: &Model, want_pred: bool) -> (Comparison, Option<Vec<f64>>) {
    let ch = prep.log.channels;
    let len = prep.log.len();
    let filed = predicted(prep, model, crate::identify::columns::Columns::new(len, ch))
        .and_then(|pred| compare_columns(prep, model, &pred, want_pred));
    match filed {
        Ok(r) => r,
        Err(_) => {
            let pred = crate::identify::columns::Columns::in_memory(len, ch);
            let pred = predicted(prep, model, pred).expect("in-memory columns do not fail");
            compare_columns(prep, model, &pred, want_pred).expect("in-memory columns do not fail")
        }
    }
}

/// The model's prediction of every row into `out`, a block of rows at a time.
fn predicted(
    prep: &Prepared,
    model: &Model,
    mut out: crate::identify::columns::Columns,
) -> crate::error::Result<crate::identify::columns::Columns> {
    let len = prep.log.len();
    let block = crate::identify::columns::BLOCK_ROWS;
    let mut rows = Vec::with_capacity(block.min(len));
    let mut pred = Vec::new();
    let mut k0 = 0;
    while k0 < len {
        let k1 = (k0 + block).min(len);
        rows.clear();
        rows.extend(k0..k1);
        prep.predict(model, &rows, &mut pred);
        out.write_rows(k0, &pred)?;
        k0 = k1;
    }
    Ok(out)
}

/// [`compare`] of the prediction `pred` (channel by channel).
fn compare_columns(
    prep: &Prepared,
    model: &Model,
    pred: &crate::identify::columns::Columns,
    want_pred: bool,
) -> crate::error::Result<(Comparison, Option<Vec<f64>>)> {
    let log = prep.log;
    let len = log.len();
    let ch = log.channels;
    let n = log.traj.n;
    let names = channel_names(prep);
    let t = &log.traj.t;
    let channels = (0..ch)
        .map(|c| channel_metrics(prep, model, pred, names[c].clone(), &[c]))
        .collect::<crate::error::Result<Vec<ChannelMetrics>>>()?;
    let all: Vec<usize> = (0..ch).collect();
    let total = channel_metrics(prep, model, pred, "total".into(), &all)?;
    // The residual of channel `c`, every row.
    let residual = |c: usize| residual_of(log, pred, c);
    let dur = log.traj.duration();
    let windows = worst_windows(log, &names, &residual)?;
    // Regimes per joint (each sample's squared residual and motion read where they are).
    let mut regimes_all = Vec::new();
    for j in 0..n {
        let c = if ch == 1 { 0 } else { j };
        let res = residual(c)?;
        joint_regimes(log, &res, j, &mut regimes_all)?;
    }
    let mut regimes: Vec<Regime> = regimes_all
        .iter()
        .filter(|r| r.samples_pct > 1.0 && r.residual_pct > 1.5 * r.samples_pct)
        .cloned()
        .collect();
    regimes.sort_by(|a, b| {
        (b.residual_pct / b.samples_pct).total_cmp(&(a.residual_pct / a.samples_pct))
    });
    regimes.truncate(12);
    let prismatic: Vec<bool> = (0..n).map(|j| model.dynamics().is_prismatic(j)).collect();
    let (profiles, failures) = crate::identify::profiles::analyse_columns(
        &residual,
        len,
        &names,
        n,
        t,
        &|k, j| log.traj.q(k)[j],
        &|j, r| log.traj.column(j, r),
        &prismatic,
    )?;
    let pred = if want_pred { Some(pred.rows()?) } else { None };
    Ok((
        Comparison {
            schema_version: crate::identify::JSON_SCHEMA_VERSION,
            calibration: None,
            log: log.file.clone(),
            signal: log.kind,
            unit: log.kind.unit().into(),
            samples: len,
            duration_s: dur,
            effects: model
                .enabled_names()
                .iter()
                .map(|s| s.to_string())
                .collect(),
            channels,
            total,
            worst_windows: windows,
            regimes,
            regimes_all,
            failures,
            profiles,
            warnings: log.warnings.clone(),
        },
        pred,
    ))
}

/// The figures of the channels `cs` together, named `name`: RMSE, measured RMS and the
/// energy measured and modelled.
fn channel_metrics(
    prep: &Prepared,
    model: &Model,
    pred: &crate::identify::columns::Columns,
    name: String,
    cs: &[usize],
) -> crate::error::Result<ChannelMetrics> {
    let log = prep.log;
    let len = log.len();
    let ch = log.channels;
    let t = &log.traj.t;
    let y = |k: usize, c: usize| log.y[k * ch + c];
    let (mut ssr, mut sm, mut cnt) = (0.0, 0.0, 0usize);
    let (mut em, mut ep) = (0.0, 0.0);
    for &c in cs {
        let p = pred.column(c)?;
        for k in 0..len {
            ssr += (p[k] - y(k, c)).powi(2);
            sm += y(k, c).powi(2);
            cnt += 1;
        }
        let qd = log.traj.column(channel_joint(prep, c), Rate::Velocity)?;
        em += integrate(t, &power_by(prep, model, &qd, |k| y(k, c), c));
        ep += integrate(t, &power_by(prep, model, &qd, |k| p[k], c));
    }
    let e = rel_pct(ep, em);
    Ok(ChannelMetrics {
        name,
        rmse: (ssr / cnt.max(1) as f64).sqrt(),
        measured_rms: (sm / cnt.max(1) as f64).sqrt(),
        energy_measured_j: em,
        energy_model_j: ep,
        energy_error_pct: e,
        accuracy_pct: 100.0 - e.abs(),
    })
}

/// The residual (prediction − measurement) of channel `c`, every row.
fn residual_of(
    log: &crate::identify::log::Log,
    pred: &crate::identify::columns::Columns,
    c: usize,
) -> crate::error::Result<Vec<f64>> {
    let ch = log.channels;
    let mut r = pred.column(c)?;
    for (k, v) in r.iter_mut().enumerate() {
        *v -= log.y[k * ch + c];
    }
    Ok(r)
}

/// The five worst windows of the log by residual RMS: each window's squared residual per
/// channel, a channel at a time.
fn worst_windows(
    log: &crate::identify::log::Log,
    names: &[String],
    residual: &dyn Fn(usize) -> crate::error::Result<Vec<f64>>,
) -> crate::error::Result<Vec<Window>> {
    let len = log.len();
    let ch = log.channels;
    let t = &log.traj.t;
    let dur = log.traj.duration();
    let wlen = (dur / 20.0).clamp(0.2, 1.0);
    let mut spans = Vec::new();
    let mut start = 0;
    while start < len {
        let t0 = t[start];
        let mut end = start;
        while end < len && t[end] < t0 + wlen {
            end += 1;
        }
        spans.push((start, end));
        start = end.max(start + 1);
    }
    let mut per = vec![0.0; spans.len() * ch];
    for c in 0..ch {
        let r = residual(c)?;
        for (w, &(start, end)) in spans.iter().enumerate() {
            let p = &mut per[w * ch + c];
            for v in &r[start..end] {
                *p += v.powi(2);
            }
        }
    }
    let mut windows = Vec::new();
    for (w, &(start, end)) in spans.iter().enumerate() {
        let per = &per[w * ch..(w + 1) * ch];
        let cnt = ((end - start) * ch).max(1) as f64;
        let worst = (0..ch)
            .max_by(|a, b| per[*a].total_cmp(&per[*b]))
            .unwrap_or(0);
        windows.push(Window {
            t_start: t[start],
            t_end: t[end.min(len) - 1],
            rmse: (per.iter().sum::<f64>() / cnt).sqrt(),
            worst_channel: names[worst].clone(),
        });
    }
    drop(per);
    drop(spans);
    windows.sort_by(|a, b| b.rmse.total_cmp(&a.rmse));
    windows.truncate(5);
    Ok(windows)
}

/// Joint `j`'s regimes (speed sign, standstill, high acceleration, pose quarter) with their
/// share of the samples and of the squared residual `res`, appended to `out`.
fn joint_regimes(
    log: &crate::identify::log::Log,
    res: &[f64],
    j: usize,
    out: &mut Vec<Regime>,
) -> crate::error::Result<()> {
    let len = log.len();
    let r2 = |k: usize| res[k].powi(2);
    let mut tot = 0.0;
    for k in 0..len {
        tot += r2(k);
    }
    let tot = tot.max(1e-300);
    // The joint's speed and |acceleration|, one column each.
    let speed = log.traj.column(j, Rate::Velocity)?;
    let mut accel = log.traj.column(j, Rate::Acceleration)?;
    accel.iter_mut().for_each(|a| *a = a.abs());
    let qd = |k: usize| speed[k];
    let q = |k: usize| log.traj.q(k)[j];
    let vmax = (0..len).fold(0.0f64, |a, k| a.max(qd(k).abs()));
    let v0 = (0.05 * vmax).max(0.005);
    let a80 = {
        let mut qdd = accel.clone();
        let at = (0.8 * (len - 1) as f64) as usize;
        *qdd.select_nth_unstable_by(at, f64::total_cmp).1
    };
    let (qmin, qmax) = (0..len).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), k| {
        (a.min(q(k)), b.max(q(k)))
    });
    let bin = |x: f64| {
        if qmax > qmin {
            (((x - qmin) / (qmax - qmin) * 4.0) as usize).min(3)
        } else {
            0
        }
    };
    let mut push = |name: String, f: &dyn Fn(usize) -> bool| {
        let (mut s, mut cnt) = (0.0, 0usize);
        for k in 0..len {
            if f(k) {
                s += r2(k);
                cnt += 1;
            }
        }
        out.push(Regime {
            joint: format!("joint_{}", j + 1),
            regime: name,
            samples_pct: 100.0 * cnt as f64 / len as f64,
            residual_pct: 100.0 * s / tot,
        });
    };
    push("positive_speed".into(), &|k| qd(k) > v0);
    push("negative_speed".into(), &|k| qd(k) < -v0);
    push("near_zero_speed".into(), &|k| qd(k).abs() <= v0);
    push("high_acceleration".into(), &|k| {
        accel[k] >= a80 && a80 > 0.0
    });
    for b in 0..4 {
        push(format!("pose_bin_{}_of_4", b + 1), &|k| bin(q(k)) == b);
    }
    Ok(())
}
