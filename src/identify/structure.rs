//! What the residual says beyond the catalogue: the noise floor estimated from the data, the
//! residual's correlation time, and per joint the structure no effect explains, with what it
//! correlates against (position, velocity, time) and its dominant period.
//!
//! - Noise floor per channel: `σ̂² = mean((r[k+1] − 2 r[k] + r[k−1])²) / 6`, the variance of
//!   white noise seen through the second difference (smooth model errors cancel there).
//! - Correlation time: the first lag (tried at 1, 2, 4, … samples) at which the residual's
//!   autocorrelation falls below 1/e, in seconds.
//! - Structure on a channel: its RMS above [`STRUCTURE_RATIO`] × its noise floor. Against a
//!   variable `x` (the joint's position, velocity, or time) the share of the residual's
//!   variance explained by the mean of `x`'s bin ([`BINS`] equal-width bins: the correlation
//!   ratio η²); the dominant period from a periodogram on a log-spaced frequency grid, reported
//!   when its peak exceeds [`PEAK_RATIO`] × the median power.

use serde::Serialize;

/// A channel's residual RMS above this multiple of its noise floor is structure.
pub(crate) const STRUCTURE_RATIO: f64 = 1.5;
/// Bins of the correlation ratio.
pub(crate) const BINS: usize = 20;
/// A periodogram peak above this multiple of the median power gives a dominant period.
pub(crate) const PEAK_RATIO: f64 = 20.0;

/// Noise floor of one channel of a row-major residual (`ch` channels), signal unit.
pub fn noise_floor(r: &[f64], ch: usize, c: usize) -> f64 {
    let len = r.len() / ch.max(1);
    if len < 3 {
        return 0.0;
    }
    let mut s = 0.0;
    for k in 1..len - 1 {
        let d = r[(k + 1) * ch + c] - 2.0 * r[k * ch + c] + r[(k - 1) * ch + c];
        s += d * d;
    }
    (s / (len - 2) as f64 / 6.0).sqrt()
}

/// Correlation time of one channel, s (`dt` the mean sample period).
pub(crate) fn correlation_time(r: &[f64], ch: usize, c: usize, dt: f64) -> f64 {
    let len = r.len() / ch.max(1);
    if len < 4 {
        return 0.0;
    }
    let mean = (0..len).map(|k| r[k * ch + c]).sum::<f64>() / len as f64;
    let x = |k: usize| r[k * ch + c] - mean;
    let var = (0..len).map(|k| x(k) * x(k)).sum::<f64>() / len as f64;
    if var <= 0.0 {
        return 0.0;
    }
    let mut lag = 1;
    while lag < len / 2 {
        let acf = (0..len - lag).map(|k| x(k) * x(k + lag)).sum::<f64>() / len as f64 / var;
        if acf < (-1.0f64).exp() {
            return lag as f64 * dt;
        }
        lag *= 2;
    }
    (len / 2) as f64 * dt
}

/// Correlation ratio η² of `y` against `x` ([`BINS`] equal-width bins), in [0, 1].
pub(crate) fn correlation_ratio(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len().min(y.len());
    if n < 2 {
        return 0.0;
    }
    let (lo, hi) = x[..n]
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(*v), b.max(*v))
        });
    if hi - lo <= 1e-12 * (1.0 + hi.abs()) {
        return 0.0;
    }
    let mean = y[..n].iter().sum::<f64>() / n as f64;
    let mut sum = [0.0; BINS];
    let mut cnt = [0usize; BINS];
    for k in 0..n {
        let b = (((x[k] - lo) / (hi - lo)) * BINS as f64)
            .floor()
            .min(BINS as f64 - 1.0) as usize;
        sum[b] += y[k];
        cnt[b] += 1;
    }
    let total: f64 = y[..n].iter().map(|v| (v - mean).powi(2)).sum();
    if total <= 0.0 {
        return 0.0;
    }
    let between: f64 = (0..BINS)
        .filter(|&b| cnt[b] > 0)
        .map(|b| cnt[b] as f64 * (sum[b] / cnt[b] as f64 - mean).powi(2))
        .sum();
    (between / total).clamp(0.0, 1.0)
}

/// Dominant period of `y` sampled at times `t` (s), if the periodogram has a clear peak.
/// At most 20 000 points are used (evenly strided), frequencies from 2/T to a quarter of the
/// (strided) sample rate.
pub(crate) fn dominant_period(t: &[f64], y: &[f64]) -> Option<f64> {
    let n = t.len().min(y.len());
    if n < 16 {
        return None;
    }
    let stride = n.div_ceil(20_000);
    let idx: Vec<usize> = (0..n).step_by(stride).collect();
    let dur = t[n - 1] - t[0];
    if dur <= 0.0 {
        return None;
    }
    let fs = (idx.len() - 1) as f64 / dur;
    let mean = idx.iter().map(|&k| y[k]).sum::<f64>() / idx.len() as f64;
    let (f_lo, f_hi) = (2.0 / dur, fs / 4.0);
    if f_hi <= f_lo {
        return None;
    }
    let nf = 160;
    let mut power = Vec::with_capacity(nf);
    for i in 0..nf {
        let f = f_lo * (f_hi / f_lo).powf(i as f64 / (nf - 1) as f64);
        let w = std::f64::consts::TAU * f;
        let (mut c, mut s) = (0.0, 0.0);
        for &k in &idx {
            let v = y[k] - mean;
            let (sn, cs) = (w * t[k]).sin_cos();
            c += v * cs;
            s += v * sn;
        }
        power.push((f, c * c + s * s));
    }
    let mut sorted: Vec<f64> = power.iter().map(|p| p.1).collect();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    let (f, p) = power
        .iter()
        .copied()
        .fold((0.0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
    (median > 0.0 && p > PEAK_RATIO * median).then(|| 1.0 / f)
}

/// Structure left on one channel that no catalogue effect explains.
#[derive(Clone, Debug, Serialize)]
pub struct Unexplained {
    /// Channel name (`tau3`, `p_total`, …).
    pub channel: String,
    /// Joint (1-based) the structure is attributed to: the channel's joint, or for a
    /// single-channel log the joint whose position or velocity explains most of it.
    pub joint: usize,
    /// Residual RMS (signal unit).
    pub rms: f64,
    /// Noise floor (signal unit).
    pub noise_floor: f64,
    /// η² of the residual against the joint's position.
    pub vs_position: f64,
    /// η² against the joint's velocity.
    pub vs_velocity: f64,
    /// η² against time.
    pub vs_time: f64,
    /// What it correlates with most: `position`, `velocity` or `time`.
    pub strongest: String,
    /// Dominant period, s, if any.
    pub dominant_period_s: Option<f64>,
}

impl std::fmt::Display for Unexplained {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} (joint {}): residual RMS {:.4} is {:.1} × its noise floor {:.4}; correlates with {} (η² position {:.2}, velocity {:.2}, time {:.2})",
            self.channel,
            self.joint,
            self.rms,
            self.rms / self.noise_floor.max(1e-300),
            self.noise_floor,
            self.strongest,
            self.vs_position,
            self.vs_velocity,
            self.vs_time
        )?;
        if let Some(p) = self.dominant_period_s {
            write!(f, ", dominant period {p:.3} s")?;
        }
        Ok(())
    }
}

/// Channels of the residual with structure beyond the noise floor, the residual given a
/// channel at a time: `res(c)` is channel `c`'s residual at every sample (it may fail, e.g.
/// reading it from a file), `names` the channels. `q(k, j)`: the log's joint positions;
/// `qd(j)`: joint `j`'s velocity at every sample; `t`: times.
pub(crate) fn unexplained_columns(
    res: &dyn Fn(usize) -> crate::error::Result<Vec<f64>>,
    names: &[String],
    n_joints: usize,
    t: &[f64],
    q: &dyn Fn(usize, usize) -> f64,
    qd: &dyn Fn(usize) -> crate::error::Result<Vec<f64>>,
) -> crate::error::Result<Vec<Unexplained>> {
    let ch = names.len();
    let len = t.len();
    let mut out = Vec::new();
    for (c, name) in names.iter().enumerate() {
        let y: Vec<f64> = res(c)?;
        let rms = (y.iter().map(|v| v * v).sum::<f64>() / len.max(1) as f64).sqrt();
        let nf = noise_floor(&y, 1, 0);
        if rms.is_nan() || rms <= STRUCTURE_RATIO * nf {
            continue;
        }
        let joints: Vec<usize> = if ch == n_joints {
            vec![c]
        } else {
            (0..n_joints).collect()
        };
        let mut best: Option<(f64, f64, usize)> = None;
        for j in joints {
            let xq: Vec<f64> = (0..len).map(|k| q(k, j)).collect();
            let xv: Vec<f64> = qd(j)?;
            let (ep, ev) = (correlation_ratio(&xq, &y), correlation_ratio(&xv, &y));
            if best.is_none_or(|b| ep.max(ev) > b.0.max(b.1)) {
                best = Some((ep, ev, j));
            }
        }
        let (ep, ev, j) = best.unwrap_or((0.0, 0.0, 0));
        let et = correlation_ratio(t, &y);
        let strongest = if ep >= ev && ep >= et {
            "position"
        } else if ev >= et {
            "velocity"
        } else {
            "time"
        };
        out.push(Unexplained {
            channel: name.clone(),
            joint: j + 1,
            rms,
            noise_floor: nf,
            vs_position: ep,
            vs_velocity: ev,
            vs_time: et,
            strongest: strongest.into(),
            dominant_period_s: dominant_period(t, &y),
        });
    }
    Ok(out)
}
