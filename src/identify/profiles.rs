//! Where the model fails, in the ways a person reads a residual: per joint,
//! the residual (model − measured) binned against the joint's velocity (friction shows as a
//! step at q̇ = 0), position (gravity and balancer errors) and time (drift), and a ranking of
//! the structures that explain the residual beyond the noise floor.
//!
//! - A **profile** is [`BINS`] equal-width bins of a variable with the residual's mean and RMS
//!   in each. What it explains beyond noise: the between-bin sum of squares
//!   `Σ n_b (r̄_b − r̄)²` less what white noise of the channel's noise floor `σ` puts there
//!   (`(B − 1) σ²`, `B` non-empty bins), as an RMS over the samples:
//!   `explained_rms = √(max(SS_between − (B − 1) σ², 0) / N)`.
//! - The **direction step** (friction): mean residual over `0 < q̇ ≤ v_b` minus over
//!   `−v_b ≤ q̇ < 0`, `v_b` = [`STEP_BAND`] × the joint's largest |q̇| (at least
//!   [`STEP_BAND_MIN_RAD_S`]), with its standard error; a smooth (gravity, viscous) error
//!   changes little across so narrow a band, Coulomb friction jumps by `f_c+ + f_c−`.
//! - The **ranking** ([`Failure`]) of the structures `direction` (`r ≈ a + b sign(q̇)`, 1
//!   degree of freedom, over moving samples), `velocity`, `position`, `acceleration` and
//!   `time` (binned) by their explained RMS; unlike a share of squared residual per regime, a
//!   friction step shows even when friction is small beside the residual elsewhere. The noise
//!   floor is [`crate::identify::structure::noise_floor`] (second differences of the residual).

use serde::Serialize;

/// Bins of a profile.
pub(crate) const BINS: usize = 20;
/// Half-width of the band around q̇ = 0 of the direction step, as a fraction of the joint's
/// largest |q̇|.
pub(crate) const STEP_BAND: f64 = 0.1;
/// Smallest half-width of that band, rad/s.
pub(crate) const STEP_BAND_MIN_RAD_S: f64 = 0.005;

/// One bin of a profile.
#[derive(Clone, Debug, Serialize)]
pub struct ProfileBin {
    /// Bin centre (unit of the profile's variable).
    pub x: f64,
    /// Samples in the bin.
    pub samples: usize,
    /// Mean residual, signal unit (0 for an empty bin).
    pub mean: f64,
    /// RMS residual, signal unit (0 for an empty bin).
    pub rms: f64,
}

/// The residual of one channel against one variable, binned.
#[derive(Clone, Debug, Serialize)]
pub struct Profile {
    /// `velocity`, `position`, `acceleration` or `time`.
    pub against: String,
    /// Unit of the variable (`rad/s`, `rad`, `rad/s²`, `s`; prismatic joints: `m/s`, `m`,
    /// `m/s²`).
    pub unit: String,
    /// The bins, in increasing `x`.
    pub bins: Vec<ProfileBin>,
    /// Residual the bin means explain beyond noise, RMS over the samples, signal unit.
    pub explained_rms: f64,
}

/// The residual profiles of one joint.
#[derive(Clone, Debug, Serialize)]
pub struct JointProfiles {
    /// Channel compared (`joint_3`, or `total` for a supply-power log).
    pub channel: String,
    /// Joint whose motion the residual is binned against (1-based).
    pub joint: usize,
    /// Noise floor of the channel's residual, signal unit.
    pub noise_floor: f64,
    /// Against the joint's velocity.
    pub velocity: Profile,
    /// Against the joint's position.
    pub position: Profile,
    /// Against time.
    pub time: Profile,
    /// Mean residual just above q̇ = 0 minus just below (signal unit; friction: −(f_c+ + f_c−)
    /// for a model missing it, residual = model − measured).
    pub direction_step: f64,
    /// Its standard error (signal unit; 0 when a side of the band is empty).
    pub direction_step_se: f64,
    /// Half-width of the band, rad/s (m/s for a prismatic joint).
    pub step_band: f64,
}

/// One structure of the residual of one joint, ranked by what it explains.
#[derive(Clone, Debug, Serialize)]
pub struct Failure {
    /// Channel (`joint_2`, `total`).
    pub channel: String,
    /// Joint whose motion it is read against (1-based).
    pub joint: usize,
    /// `direction` (a step with the sign of the velocity: friction), `velocity`, `position`
    /// (gravity, balancer), `acceleration` (inertia), `time` (drift).
    pub structure: String,
    /// Residual RMS it explains beyond noise, signal unit.
    pub explained_rms: f64,
    /// `explained_rms` over the channel's noise floor.
    pub ratio_to_noise: f64,
    /// Share of the channel's residual variance it explains, %.
    pub explained_pct: f64,
}

/// Binned profile of `r` against `x` (`BINS` equal-width bins), with the noise floor `sigma`.
pub fn profile(against: &str, unit: &str, x: &[f64], r: &[f64], sigma: f64) -> Profile {
    let n = x.len().min(r.len());
    let (lo, hi) = x[..n]
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(*v), b.max(*v))
        });
    let mut sum = [0.0; BINS];
    let mut sq = [0.0; BINS];
    let mut cnt = [0usize; BINS];
    let span = hi - lo;
    let flat = span.is_nan() || span <= 1e-12 * (1.0 + hi.abs());
    for k in 0..n {
        let b = if flat {
            0
        } else {
            (((x[k] - lo) / (hi - lo) * BINS as f64).floor() as usize).min(BINS - 1)
        };
        sum[b] += r[k];
        sq[b] += r[k] * r[k];
        cnt[b] += 1;
    }
    let mean = r[..n].iter().sum::<f64>() / n.max(1) as f64;
    let mut between = 0.0;
    let mut used = 0usize;
    let width = if flat { 0.0 } else { (hi - lo) / BINS as f64 };
    let bins = (0..BINS)
        .map(|b| {
            let c = cnt[b];
            let m = if c > 0 { sum[b] / c as f64 } else { 0.0 };
            if c > 0 {
                between += c as f64 * (m - mean).powi(2);
                used += 1;
            }
            ProfileBin {
                x: if flat {
                    lo
                } else {
                    lo + (b as f64 + 0.5) * width
                },
                samples: c,
                mean: m,
                rms: if c > 0 {
                    (sq[b] / c as f64).sqrt()
                } else {
                    0.0
                },
            }
        })
        .filter(|b| !flat || b.samples > 0)
        .collect();
    let excess = (between - used.saturating_sub(1) as f64 * sigma * sigma).max(0.0);
    Profile {
        against: against.into(),
        unit: unit.into(),
        bins,
        explained_rms: (excess / n.max(1) as f64).sqrt(),
    }
}

/// Step of the mean residual across q̇ = 0 within `±band`: (step, standard error).
pub fn direction_step(qd: &[f64], r: &[f64], band: f64) -> (f64, f64) {
    let side = |pos: bool| {
        let v: Vec<f64> = qd
            .iter()
            .zip(r)
            .filter(|(q, _)| {
                if pos {
                    **q > 0.0 && **q <= band
                } else {
                    **q < 0.0 && **q >= -band
                }
            })
            .map(|(_, r)| *r)
            .collect();
        let n = v.len() as f64;
        if v.len() < 2 {
            return None;
        }
        let m = v.iter().sum::<f64>() / n;
        let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0);
        Some((m, var / n))
    };
    match (side(true), side(false)) {
        (Some((mp, vp)), Some((mn, vn))) => (mp - mn, (vp + vn).sqrt()),
        _ => (0.0, 0.0),
    }
}

/// What `r ≈ a + b sign(q̇)` over the moving samples (|q̇| > `still`) explains beyond noise,
/// as an RMS over all `r.len()` samples.
fn direction_explained(qd: &[f64], r: &[f64], still: f64, sigma: f64) -> f64 {
    let (mut sp, mut np, mut sn, mut nn) = (0.0, 0usize, 0.0, 0usize);
    for (q, v) in qd.iter().zip(r) {
        if *q > still {
            sp += v;
            np += 1;
        } else if *q < -still {
            sn += v;
            nn += 1;
        }
    }
    if np == 0 || nn == 0 {
        return 0.0;
    }
    let (mp, mn) = (sp / np as f64, sn / nn as f64);
    let m = (sp + sn) / (np + nn) as f64;
    let between = np as f64 * (mp - m).powi(2) + nn as f64 * (mn - m).powi(2);
    ((between - sigma * sigma).max(0.0) / r.len().max(1) as f64).sqrt()
}

/// Profiles and ranked structures of a residual.
///
/// `res(c)` is channel `c`'s residual (model − measured) at every one of the `len` samples
/// (it may fail, e.g. reading it from a file); `names` the channel names; `q`, `qd`, `qdd`
/// give joint `j`'s value at sample `k`; `t` the times (s); `prismatic[j]` whether joint `j`
/// is prismatic (units). A supply-power log (one channel, several joints) is read against
/// every joint's motion. One channel and one joint's motion are held at a time.
#[allow(clippy::too_many_arguments)]
pub(crate) fn analyse_columns(
    res: &dyn Fn(usize) -> crate::error::Result<Vec<f64>>,
    len: usize,
    names: &[String],
    n: usize,
    t: &[f64],
    q: &dyn Fn(usize, usize) -> f64,
    rate: &dyn Fn(usize, crate::identify::motion::Rate) -> crate::error::Result<Vec<f64>>,
    prismatic: &[bool],
) -> crate::error::Result<(Vec<JointProfiles>, Vec<Failure>)> {
    let ch = names.len().max(1);
    let mut profiles = Vec::new();
    let mut failures = Vec::new();
    for j in 0..n {
        let c = if ch == 1 { 0 } else { j };
        if c >= ch {
            break;
        }
        let r: Vec<f64> = res(c)?;
        let sigma = crate::identify::structure::noise_floor(&r, 1, 0);
        let var = {
            let m = r.iter().sum::<f64>() / len.max(1) as f64;
            r.iter().map(|v| (v - m).powi(2)).sum::<f64>() / len.max(1) as f64
        };
        let p = prismatic.get(j).copied().unwrap_or(false);
        let (u_q, u_qd, u_qdd) = if p {
            ("m", "m/s", "m/s²")
        } else {
            ("rad", "rad/s", "rad/s²")
        };
        // One joint column at a time.
        let xqd: Vec<f64> = rate(j, crate::identify::motion::Rate::Velocity)?;
        let vmax = xqd.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        let band = (STEP_BAND * vmax).max(STEP_BAND_MIN_RAD_S);
        let (step, se) = direction_step(&xqd, &r, band);
        let vel = profile("velocity", u_qd, &xqd, &r, sigma);
        let dir = direction_explained(&xqd, &r, 0.01 * vmax, sigma);
        drop(xqd);
        let xq: Vec<f64> = (0..len).map(|k| q(k, j)).collect();
        let pos = profile("position", u_q, &xq, &r, sigma);
        drop(xq);
        let time = profile("time", "s", &t[..len.min(t.len())], &r, sigma);
        let xqdd: Vec<f64> = rate(j, crate::identify::motion::Rate::Acceleration)?;
        let acc = profile("acceleration", u_qdd, &xqdd, &r, sigma);
        drop(xqdd);
        let channel = names[c].clone();
        for (structure, e) in [
            ("direction", dir),
            ("velocity", vel.explained_rms),
            ("position", pos.explained_rms),
            ("acceleration", acc.explained_rms),
            ("time", time.explained_rms),
        ] {
            failures.push(Failure {
                channel: channel.clone(),
                joint: j + 1,
                structure: structure.into(),
                explained_rms: e,
                ratio_to_noise: if sigma > 0.0 { e / sigma } else { 0.0 },
                explained_pct: if var > 0.0 {
                    (100.0 * e * e / var).min(100.0)
                } else {
                    0.0
                },
            });
        }
        profiles.push(JointProfiles {
            channel,
            joint: j + 1,
            noise_floor: sigma,
            velocity: vel,
            position: pos,
            time,
            direction_step: step,
            direction_step_se: se,
            step_band: band,
        });
    }
    // Largest explained first.
    failures.sort_by(|a, b| b.explained_rms.total_cmp(&a.explained_rms));
    Ok((profiles, failures))
}
