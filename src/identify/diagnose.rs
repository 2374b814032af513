//! Which effect is missing: each catalogue effect observable in the log is fitted alone on top
//! of the current model (switched on if it was off, its parameters re-fitted if it was on),
//! k-fold by contiguous time blocks; candidates are ranked by the held-out RMSE.
//!
//! Claims a statistician would sign. The noise floor is estimated from the data (second
//! differences of the residual, [`crate::identify::structure`]) and printed, and so is the
//! residual's correlation time; the blocks are made at least that long (fewer folds, at least
//! 2; no claim at all when the log is shorter than two correlation times). A candidate is
//! significant when
//! - it is physically plausible for the robot (no `balancer` on a robot whose drive file
//!   declares none, such as the UR10e; on a robot without drive data it is a candidate with
//!   an assumed geometry, said in its note),
//! - it cuts the held-out RMSE by at least [`MIN_GAIN`],
//! - its held-out gain is beyond noise and autocorrelation: the held-out rows are cut into
//!   chunks one correlation time long, and the t statistic of the chunk means of
//!   `|r_before|² − |r_after|²` exceeds the one-sided 95 % quantile of Student's t with
//!   (chunks − 1) degrees of freedom (chunks that long are close to independent), and
//! - its BIC `m ln(SSR/m) + P ln m` beats the current model's by more than [`MIN_DELTA_BIC`],
//! - it is material: on some channel, the held-out RMS it explains reaches the channel's noise
//!   floor and [`MIN_MATERIAL`] of the channel's measured RMS (a log with only 1 % parameter errors has nothing missing), and
//! - its fitted values are physically plausible ([`crate::identify::plausible`]: e.g. a payload
//!   of 16 g whose centre of mass lies metres from the flange;
//!   e.g. a `rigid_body` fit no physical robot has is named, with the reason, but not claimed).
//!
//! The best plausible candidate is also fitted jointly with each of the next ones
//! ([`PAIR_LEADERS`]): one effect
//! fitted alone can soak up another (a friction fit that takes a payload's gravity torque ends
//! with a parameter at a bound, and the next round finds nothing). A pair that cuts the best
//! single candidate's held-out RMSE by another [`MIN_GAIN`] is a candidate of its own, named
//! `a,b` (what `identify --effects a,b` fits).
//!
//! When none is, the diagnosis says nothing significant is missing; when structure beyond the
//! noise floor remains that no candidate explains, it says so per joint, with what it
//! correlates against and its dominant period ([`Diagnosis::unexplained`]).

use crate::effects::catalogue;
use crate::error::Result;
use crate::identify::columns::Columns;
use crate::identify::fit::{fit_parameters, residuals, FittedParam};
use crate::identify::model::{Model, Prepared};
use crate::identify::motion::Rate;
use crate::identify::structure::{self, Unexplained};
use serde::Serialize;

/// Minimum relative cut of the held-out RMSE for a significant candidate.
pub(crate) const MIN_GAIN: f64 = 0.05;
/// BIC improvement (decrease) required for a significant candidate.
pub(crate) const MIN_DELTA_BIC: f64 = 10.0;
/// Materiality: on some channel, the held-out RMS a significant candidate explains must reach
/// both that channel's noise floor and this fraction of its measured RMS. An effect smaller than 1 % of the signal moves the energy by about 1 % or less,
/// the accuracy the loop is asked to reach (target: ≥ 99 %); a log whose only errors
/// are that small (e.g. 1 % link-mass and inertia errors) has nothing missing.
pub(crate) const MIN_MATERIAL: f64 = 0.01;

/// One ranked candidate.
#[derive(Clone, Debug, Serialize)]
pub struct Candidate {
    /// Catalogue name, or two names joined by `,` for a pair fitted jointly.
    pub effect: String,
    /// Whether it was already switched on (then the candidate is a re-fit of its parameters).
    pub in_model: bool,
    /// Joints (1-based) it acts on.
    pub joints: Vec<usize>,
    /// Fitted parameters on the whole log, with standard errors.
    pub params: Vec<FittedParam>,
    /// Held-out RMSE after adding it (signal unit): the expected error.
    pub validation_rmse: f64,
    /// Cut of the held-out RMSE, %.
    pub rmse_cut_pct: f64,
    /// BIC change (negative is better).
    pub delta_bic: f64,
    /// Physically plausible for this robot.
    pub plausible: bool,
    /// Why not plausible, if not.
    pub implausible: Option<String>,
    /// t statistic of the held-out gain over chunks one correlation time long.
    pub t_statistic: f64,
    /// RMS it explains on held-out blocks, `√(base_rmse² − validation_rmse²)` (0 when it
    /// explains nothing), signal unit.
    pub explained_rms: f64,
    /// Materiality, %: the largest, over the channels where the held-out RMS it explains
    /// (`√((SSR_before − SSR_after)/rows)`) reaches the channel's noise floor, of that RMS as a
    /// share of the channel's measured RMS (0 when no channel qualifies; at least
    /// [`MIN_MATERIAL`] for a claim).
    pub explained_pct_of_signal: f64,
    /// Significant by every criterion (module docs).
    pub significant: bool,
    /// Parameters it cannot tell apart, if any.
    pub note: Option<String>,
}

/// The diagnosis.
#[derive(Clone, Debug, Serialize)]
pub struct Diagnosis {
    /// Version of this JSON shape (docs/json.md).
    pub schema_version: u32,
    /// The calibration the model came from (`None`: a nominal robot); set by the caller.
    pub calibration: Option<String>,
    /// RMSE of the current model over the log (signal unit).
    pub base_rmse: f64,
    /// Folds used (time blocks at least one correlation time long).
    pub folds: usize,
    /// Noise floor estimated from the data (RMS over channels, signal unit).
    pub noise_floor: f64,
    /// Noise floor per channel (signal unit).
    pub noise_floor_per_channel: Vec<f64>,
    /// Correlation time of the residual (longest over channels), s.
    pub correlation_time_s: f64,
    /// Length of one held-out block, s.
    pub block_length_s: f64,
    /// Structure beyond the noise floor left after the best significant candidate (or in the
    /// current model's residual when there is none), per channel.
    pub unexplained: Vec<Unexplained>,
    /// Effects in the model.
    pub model_effects: Vec<String>,
    /// Candidates, best first.
    pub candidates: Vec<Candidate>,
    /// The best significant candidate, if any.
    pub best: Option<String>,
    /// One sentence.
    pub verdict: String,
    /// Effects not observable in this kind of log.
    pub not_observable: Vec<String>,
}

/// Contiguous time blocks: the rows of each.
pub fn blocks(len: usize, folds: usize) -> Vec<std::ops::Range<usize>> {
    let folds = folds.max(2);
    (0..folds)
        .map(|f| f * len / folds..(f + 1) * len / folds)
        .collect()
}

/// Diagnose the residual of `model` on the log; the model is left unchanged.
pub fn diagnose(prep: &Prepared, model: &mut Model, folds: usize) -> Result<Diagnosis> {
    diagnose_with_progress(prep, model, folds, &crate::identify::NoProgress)
}

/// [`diagnose`], telling `progress` how many candidate fits are done (stage `"diagnosing"`;
/// per observable candidate one fit per fold and one on the whole log).
pub fn diagnose_with_progress(
    prep: &Prepared,
    model: &mut Model,
    folds: usize,
    progress: &dyn crate::identify::Progress,
) -> Result<Diagnosis> {
    let len = prep.len();
    let all: Vec<usize> = (0..len).collect();
    let base_state = model.state();
    let ch = prep.log.channels;
    let (r0, ssr0, base_ss) = base_residual(prep, model)?;
    let m = (len * ch) as f64;
    let base_rmse = (ssr0 / m).sqrt();
    let bic0 = m * (ssr0 / m).max(1e-300).ln();
    let meas_ms = measured_mean_square(prep);
    let t = &prep.log.traj.t;
    let dur = t.last().copied().unwrap_or(0.0) - t.first().copied().unwrap_or(0.0);
    let dt = dur / (len.max(2) - 1) as f64;
    let (nf, tau_c) = noise_of(&r0, ch, dt)?;
    let noise = (nf.iter().map(|v| v * v).sum::<f64>() / ch.max(1) as f64).sqrt();
    let (too_short, bl, chunk) = fold_plan(len, folds, dur, dt, tau_c);
    let base = Baseline {
        all: &all,
        blocks: &bl,
        r0: &r0,
        chunk,
        base_ss: &base_ss,
        meas_ms: &meas_ms,
        noise_floor: &nf,
        bic0,
        base_rmse,
        too_short,
    };
    let (mut cands, not_obs, observable) = score_each(prep, model, &base_state, &base, progress)?;
    score_pairs(prep, model, &base_state, &base, &observable, &mut cands)?;
    model.restore(&base_state);
    cands.sort_by(|a, b| a.validation_rmse.total_cmp(&b.validation_rmse));
    // The best significant candidate (an implausible one ranked above it is named, not
    // claimed).
    let best = cands
        .iter()
        .find(|c| c.significant || c.plausible)
        .filter(|c| c.significant)
        .map(|c| c.effect.clone());
    drop(r0);
    let unexplained = unexplained_after(prep, model, &base_state, &best, &all)?;
    let left = left_text(&unexplained);
    let noise_txt = format!(
        "noise floor {noise:.4} (from the data), residual correlation time {tau_c:.3} s, {} blocks of {:.2} s",
        bl.len(),
        dur / bl.len() as f64
    );
    let verdict = verdict(&best, &cands, base_rmse, too_short, dur, &noise_txt, &left);
    Ok(Diagnosis {
        schema_version: crate::identify::JSON_SCHEMA_VERSION,
        calibration: None,
        base_rmse,
        folds: bl.len(),
        noise_floor: noise,
        noise_floor_per_channel: nf,
        correlation_time_s: tau_c,
        block_length_s: dur / bl.len() as f64,
        unexplained,
        model_effects: model
            .enabled_names()
            .iter()
            .map(|s| s.to_string())
            .collect(),
        candidates: cands,
        best,
        verdict,
        not_observable: not_obs,
    })
}

/// The held-out blocks, at least one correlation time `tau_c` long each (at most `folds` of
/// them, at least 2), and the rows per chunk of one correlation time; with whether the log is
/// shorter than two correlation times.
fn fold_plan(
    len: usize,
    folds: usize,
    dur: f64,
    dt: f64,
    tau_c: f64,
) -> (bool, Vec<std::ops::Range<usize>>, usize) {
    // Blocks at least one correlation time long.
    let max_folds = if tau_c > 0.0 {
        (dur / tau_c).floor() as usize
    } else {
        folds
    };
    let too_short = max_folds < 2;
    let bl = blocks(len, folds.min(max_folds).max(2));
    let chunk = ((tau_c / dt.max(1e-300)).ceil() as usize).clamp(1, len.max(1));
    (too_short, bl, chunk)
}

/// What is left after the best claim, as the verdict's tail (empty when nothing is).
fn left_text(unexplained: &[Unexplained]) -> String {
    if unexplained.is_empty() {
        String::new()
    } else {
        format!(
            "; structure no catalogue effect explains remains: {}",
            unexplained
                .iter()
                .map(|u| u.to_string())
                .collect::<Vec<_>>()
                .join("; ")
        )
    }
}

/// The current model's residual over the whole log, kept channel by channel outside memory:
/// with its sum of squares, in total and per channel.
fn base_residual(prep: &Prepared, model: &Model) -> Result<(Columns, f64, Vec<f64>)> {
    let ch = prep.log.channels;
    let mut ssr0: f64 = std::iter::empty::<f64>().sum();
    let mut base_ss = vec![0.0; ch.max(1)];
    let r0 = residual_columns(prep, model, &mut |r| {
        for x in r {
            ssr0 += x * x;
        }
        for (i, v) in r.iter().enumerate() {
            base_ss[i % ch.max(1)] += v * v;
        }
    })?;
    Ok((r0, ssr0, base_ss))
}

/// Per channel: the measured signal's mean square.
fn measured_mean_square(prep: &Prepared) -> Vec<f64> {
    let (len, ch) = (prep.len(), prep.log.channels);
    let mut meas_ms = vec![0.0; ch.max(1)];
    for (i, v) in prep.log.y.iter().enumerate() {
        meas_ms[i % ch.max(1)] += v * v / len.max(1) as f64;
    }
    meas_ms
}

/// The residual's noise floor per channel and its correlation time (longest over channels),
/// s, at sample interval `dt`.
fn noise_of(r0: &Columns, ch: usize, dt: f64) -> Result<(Vec<f64>, f64)> {
    let mut nf = Vec::with_capacity(ch);
    let mut tau_c = 0.0;
    for c in 0..ch {
        let col = r0.column(c)?;
        nf.push(structure::noise_floor(&col, 1, 0));
        tau_c = f64::max(tau_c, structure::correlation_time(&col, 1, 0, dt));
    }
    Ok((nf, tau_c))
}

/// Every observable catalogue effect scored alone, with progress; with the effects not
/// observable in this kind of log and the observable ones.
fn score_each(
    prep: &Prepared,
    model: &mut Model,
    base_state: &crate::identify::model::ModelState,
    base: &Baseline,
    progress: &dyn crate::identify::Progress,
) -> Result<(Vec<Candidate>, Vec<String>, Vec<&'static str>)> {
    let mut cands = Vec::new();
    let mut not_obs = Vec::new();
    let observable: Vec<&'static str> = catalogue()
        .into_iter()
        .filter(|c| model.observable(c, prep.log.kind))
        .collect();
    let total = (observable.len() * (base.blocks.len() + 1)) as u64;
    let mut done = 0u64;
    progress.update("diagnosing", 0, total);
    for name in catalogue() {
        if !model.observable(name, prep.log.kind) {
            not_obs.push(name.to_string());
            continue;
        }
        let tick = |k: u64| progress.update("diagnosing", done + k, total);
        cands.push(score(prep, model, base_state, base, &[name], &tick)?);
        done += base.blocks.len() as u64 + 1;
    }
    Ok((cands, not_obs, observable))
}

/// Out of the greedy trap: the best plausible candidate fitted jointly with each of the next
/// ones. A pair is claimed when it cuts the held-out RMSE of the best single candidate by at
/// least [`MIN_GAIN`] (one effect fitted alone can soak up another, or leave a parameter at a
/// bound of its range, and the next round then finds nothing).
fn score_pairs(
    prep: &Prepared,
    model: &mut Model,
    base_state: &crate::identify::model::ModelState,
    base: &Baseline,
    observable: &[&'static str],
    cands: &mut Vec<Candidate>,
) -> Result<()> {
    cands.sort_by(|a, b| a.validation_rmse.total_cmp(&b.validation_rmse));
    let lead: Vec<&'static str> = cands
        .iter()
        .filter(|c| c.plausible && c.significant)
        .take(PAIR_LEADERS)
        .filter_map(|c| observable.iter().copied().find(|o| *o == c.effect))
        .collect();
    let best_single = cands
        .iter()
        .find(|c| c.plausible && c.significant)
        .map(|c| c.validation_rmse);
    if let (Some(single), Some((a, rest))) = (best_single, lead.split_first()) {
        for b in rest {
            let c = score(prep, model, base_state, base, &[a, b], &|_| {})?;
            if c.validation_rmse <= single * (1.0 - MIN_GAIN) {
                cands.push(c);
            }
        }
    }
    Ok(())
}

/// Structure beyond the noise floor left after the best claim (or in the current model's
/// residual when there is none), kept channel by channel as the current model's residual
/// was; the model is restored to `base_state`.
fn unexplained_after(
    prep: &Prepared,
    model: &mut Model,
    base_state: &crate::identify::model::ModelState,
    best: &Option<String>,
    all: &[usize],
) -> Result<Vec<Unexplained>> {
    if let Some(b) = best {
        let names: Vec<&'static str> = b
            .split(',')
            .filter_map(|w| catalogue().into_iter().find(|c| *c == w))
            .collect();
        fit_parameters(prep, model, &names, all)?;
    }
    // What is left, kept channel by channel as the current model's residual was.
    let left_r = residual_columns(prep, model, &mut |_| {})?;
    model.restore(base_state);
    let names = crate::identify::metrics::channel_names(prep);
    structure::unexplained_columns(
        &|c| left_r.column(c),
        &names,
        model.n,
        &prep.log.traj.t,
        &|k, j| prep.log.traj.q(k)[j],
        &|j| prep.log.traj.column(j, Rate::Velocity),
    )
}

/// The diagnosis in one sentence: the best claim, or why there is none.
fn verdict(
    best: &Option<String>,
    cands: &[Candidate],
    base_rmse: f64,
    too_short: bool,
    dur: f64,
    noise_txt: &str,
    left: &str,
) -> String {
    match (best, cands.first()) {
        (Some(b), _) => {
            let c = cands.iter().find(|c| c.effect == *b).expect("best is a candidate");
            format!(
                "`{b}` {} explains the largest part of the residual: held-out RMSE {:.4} → {:.4} ({:.1} % less, t = {:.1}) on joints {:?}; {noise_txt}{left}",
                if c.in_model { "(re-fitted)" } else { "(missing)" },
                base_rmse,
                c.validation_rmse,
                c.rmse_cut_pct,
                c.t_statistic,
                c.joints
            )
        }
        (None, _) if too_short => format!(
            "no claim: the log ({dur:.2} s) is shorter than two correlation times of the residual; {noise_txt}{left}"
        ),
        (None, Some(c)) => format!(
            "nothing significant is missing from the catalogue: the best candidate `{}` cuts the held-out RMSE by {:.1} % (threshold {:.0} %, t = {:.1}, ΔBIC {:.1}) and explains {:.2} % of the signal's RMS (threshold {:.0} %{}); {noise_txt}{}",
            c.effect,
            c.rmse_cut_pct,
            100.0 * MIN_GAIN,
            c.t_statistic,
            c.delta_bic,
            c.explained_pct_of_signal,
            100.0 * MIN_MATERIAL,
            c.implausible.as_deref().map(|w| format!(", not plausible: {w}")).unwrap_or_default(),
            if left.is_empty() {
                "; the residual is at the noise floor".to_string()
            } else {
                left.to_string()
            }
        ),
        _ => "no candidate effect is observable in this log".into(),
    }
}

/// The best plausible, significant candidate is also fitted jointly with each of the next
/// `PAIR_LEADERS − 1`.
pub(crate) const PAIR_LEADERS: usize = 5;

/// The current model's figures every candidate is scored against.
struct Baseline<'a> {
    all: &'a [usize],
    blocks: &'a [std::ops::Range<usize>],
    /// The current model's residual over the whole log, channel by channel.
    r0: &'a Columns,
    /// Rows per chunk of one correlation time.
    chunk: usize,
    /// Per channel: the current model's squared residual.
    base_ss: &'a [f64],
    /// Per channel: the measured signal's mean square.
    meas_ms: &'a [f64],
    noise_floor: &'a [f64],
    bic0: f64,
    base_rmse: f64,
    too_short: bool,
}

/// Score the candidate that fits `names` jointly on top of the current model: k-fold held-out
/// RMSE, the t statistic of its gain over chunks, BIC, materiality, plausibility (module docs).
/// `tick(k)`: `k` of its fits are done. The model is restored to `base_state`.
fn score(
    prep: &Prepared,
    model: &mut Model,
    base_state: &crate::identify::model::ModelState,
    base: &Baseline,
    names: &[&'static str],
    tick: &dyn Fn(u64),
) -> Result<Candidate> {
    let len = prep.len();
    let ch = prep.log.channels;
    let m = (base.r0.len() * ch) as f64;
    let held = held_out(prep, model, base_state, base, names, tick)?;
    model.restore(base_state);
    let full = fit_parameters(prep, model, names, base.all)?;
    tick(base.blocks.len() as u64 + 1);
    let (full_ssr, moved) = whole_log(prep, model, base)?;
    let implausible = implausibility(model, names, &full.params);
    model.restore(base_state);
    let joints = acting_joints(&moved, ch, &full.params);
    let cv = (held.sse / held.cnt.max(1) as f64).sqrt();
    let cut = if base.base_rmse > 0.0 {
        100.0 * (1.0 - cv / base.base_rmse)
    } else {
        0.0
    };
    let bic = m * (full_ssr / m).max(1e-300).ln() + full.params.len() as f64 * m.ln();
    let dbic = bic - base.bic0;
    let tstat = paired_t(&held.gains);
    let explained_rms = (base.base_rmse * base.base_rmse - cv * cv).max(0.0).sqrt();
    // Materiality on the channel where it is largest (held-out blocks cover every row). Only
    // channels where it explains at least the noise floor count (a channel with little
    // signal must not make a small absolute error look large).
    let explained_pct_of_signal = (0..ch.max(1))
        .map(|c| {
            let e = ((base.base_ss[c] - held.sse_c[c]) / len.max(1) as f64)
                .max(0.0)
                .sqrt();
            if base.meas_ms[c] > 0.0 && e >= base.noise_floor[c] {
                100.0 * e / base.meas_ms[c].sqrt()
            } else {
                0.0
            }
        })
        .fold(0.0, f64::max);
    let material = explained_pct_of_signal >= 100.0 * MIN_MATERIAL;
    Ok(Candidate {
        effect: names.join(","),
        in_model: names.iter().any(|n| model.is_enabled(n)),
        joints,
        params: full.params,
        validation_rmse: cv,
        rmse_cut_pct: cut,
        delta_bic: dbic,
        plausible: implausible.is_none(),
        significant: implausible.is_none()
            && !base.too_short
            && cut >= 100.0 * MIN_GAIN
            && tstat > t_quantile_95(held.gains.len().saturating_sub(1))
            && dbic < -MIN_DELTA_BIC
            && material,
        implausible,
        t_statistic: tstat,
        explained_rms,
        explained_pct_of_signal,
        note: candidate_note(model, names, full.ill_conditioned.map(|i| i.to_string())),
    })
}

/// What a candidate's fits leave in the blocks they held out.
struct HeldOut {
    /// Sum of squared held-out residuals.
    sse: f64,
    /// The same per channel.
    sse_c: Vec<f64>,
    /// Number of held-out residuals.
    cnt: usize,
    /// Held-out gain per chunk of one correlation time.
    gains: Vec<f64>,
}

/// The k-fold fits of `names` (each on every row outside one block) and what they leave in
/// the block held out; `tick(k)` after the `k`-th fit.
fn held_out(
    prep: &Prepared,
    model: &mut Model,
    base_state: &crate::identify::model::ModelState,
    base: &Baseline,
    names: &[&'static str],
    tick: &dyn Fn(u64),
) -> Result<HeldOut> {
    let len = prep.len();
    let ch = prep.log.channels;
    let mut r = Vec::new();
    let mut rows = Vec::new();
    // The current model's residual at the rows of a part, channel by channel.
    let mut r0 = Vec::new();
    let mut sse = 0.0;
    let mut sse_c = vec![0.0; ch.max(1)];
    let mut cnt = 0usize;
    let mut gains = Vec::with_capacity(base.blocks.len());
    for (bi, b) in base.blocks.iter().enumerate() {
        // Blocks are contiguous: the training rows are everything outside the block.
        let train: Vec<usize> = (0..b.start).chain(b.end..len).collect();
        model.restore(base_state);
        fit_parameters(prep, model, names, &train)?;
        drop(train);
        // Held-out gain per chunk of one correlation time: chunk means of
        // `|r_before|² − |r_after|²` are close to independent, so their t statistic
        // measures the gain against noise and autocorrelation. The block's residual is
        // taken a part at a time.
        let mut acc = 0.0;
        let mut in_chunk = 0usize;
        let mut block_ss = 0.0;
        for part in parts(b.clone()) {
            rows.clear();
            rows.extend(part.clone());
            residuals(prep, model, &rows, &mut r);
            base_part(base.r0, &part, &mut r0)?;
            for x in &r {
                block_ss += x * x;
            }
            for (i, x) in r.iter().enumerate() {
                sse_c[i % ch.max(1)] += x * x;
            }
            for (i, &k) in rows.iter().enumerate() {
                acc += (0..ch)
                    .map(|c| r0[c * rows.len() + i].powi(2) - r[i * ch + c].powi(2))
                    .sum::<f64>();
                in_chunk += 1;
                if in_chunk == base.chunk || k + 1 == b.end {
                    gains.push(acc / in_chunk as f64);
                    acc = 0.0;
                    in_chunk = 0;
                }
            }
            cnt += r.len();
        }
        sse += block_ss;
        tick(bi as u64 + 1);
    }
    Ok(HeldOut {
        sse,
        sse_c,
        cnt,
        gains,
    })
}

/// The fitted model's residual over the whole log (the fit may have used a stride of the
/// rows), a part at a time: its sum of squares, and per channel how far the prediction moved.
fn whole_log(prep: &Prepared, model: &Model, base: &Baseline) -> Result<(f64, Vec<f64>)> {
    let ch = prep.log.channels;
    let (mut r, mut rows, mut r0) = (Vec::new(), Vec::new(), Vec::new());
    let mut full_ssr = 0.0;
    let mut moved = vec![0.0; ch.max(1)];
    for part in parts(0..prep.len()) {
        rows.clear();
        rows.extend(part.clone());
        residuals(prep, model, &rows, &mut r);
        base_part(base.r0, &part, &mut r0)?;
        for x in &r {
            full_ssr += x * x;
        }
        for i in 0..rows.len() {
            for c in 0..ch {
                moved[c] += (r[i * ch + c] - r0[c * rows.len() + i]).powi(2);
            }
        }
    }
    Ok((full_ssr, moved))
}

/// Plausibility of the robot (e.g. no balancer declared) and of the fitted values (e.g. no
/// negative link mass), judged on the whole-log fit, effect by effect: why not, if not.
fn implausibility(model: &Model, names: &[&'static str], params: &[FittedParam]) -> Option<String> {
    names
        .iter()
        .filter_map(|name| {
            let std_errors: Vec<Option<f64>> = params
                .iter()
                .filter(|p| p.effect == *name)
                .map(|p| p.std_error)
                .collect();
            crate::identify::plausible::implausible_fit(model, name, &std_errors)
        })
        .reduce(|a, b| format!("{a}; {b}"))
}

/// A candidate's note: parameters the motion cannot tell apart, and a balancer's assumed
/// geometry on a robot without drive data.
fn candidate_note(model: &Model, names: &[&str], ill: Option<String>) -> Option<String> {
    let geometry = names
        .contains(&"balancer")
        .then(|| model.effects.typed::<crate::effects::Balancer>("balancer"))
        .flatten()
        .filter(|b| b.assumed_geometry)
        .map(|b| {
            format!(
                "balancer geometry assumed (lever {} m, base {} m: the robot has no drive data; \
                 give balancer_lever_m and balancer_base_m in a drive file)",
                b.a, b.b
            )
        });
    match (ill, geometry) {
        (Some(i), Some(g)) => Some(format!("{i}; {g}")),
        (i, g) => i.or(g),
    }
}

/// Joints a candidate acts on: channels whose prediction moved by more than 1 % of the largest
/// move (`moved[c]`: the sum over rows of the squared change of channel `c`'s prediction), or,
/// with one channel, per-joint parameters that moved by more than two standard errors.
fn acting_joints(moved: &[f64], ch: usize, params: &[FittedParam]) -> Vec<usize> {
    if ch > 1 {
        let dmax = moved.iter().cloned().fold(0.0, f64::max);
        return (0..ch)
            .filter(|&c| dmax > 0.0 && moved[c] > 0.01 * dmax)
            .map(|c| c + 1)
            .collect();
    }
    let mut joints = Vec::new();
    for p in params {
        if let Some(j) = p
            .name
            .split_once('[')
            .and_then(|(_, r)| r.trim_end_matches(']').parse::<usize>().ok())
        {
            let moved = (p.value - p.nominal).abs();
            if moved > 0.0 && p.std_error.is_none_or(|s| moved > 2.0 * s) && !joints.contains(&j) {
                joints.push(j);
            }
        }
    }
    joints
}

/// The rows `part` of `cols` into `out`, channel by channel (`ch × part.len()`).
fn base_part(cols: &Columns, part: &std::ops::Range<usize>, out: &mut Vec<f64>) -> Result<()> {
    let m = part.len();
    let ch = cols.width();
    out.resize(ch * m, 0.0);
    for c in 0..ch {
        cols.read(c, part.start, &mut out[c * m..(c + 1) * m])?;
    }
    Ok(())
}

/// The residual of `model` over every row of the log, a part of [`PART_ROWS`] rows at a time,
/// kept channel by channel ([`Columns`]): in a temporary file, or in memory when the file
/// fails. `each` sees each part's residual (row-major) once, in order.
fn residual_columns(
    prep: &Prepared,
    model: &Model,
    each: &mut dyn FnMut(&[f64]),
) -> Result<Columns> {
    let (len, ch) = (prep.len(), prep.log.channels);
    let mut cols = Columns::new(len, ch);
    let (mut r, mut rows) = (Vec::new(), Vec::new());
    let mut memory = false;
    for part in parts(0..len) {
        rows.clear();
        rows.extend(part.clone());
        residuals(prep, model, &rows, &mut r);
        each(&r);
        if !memory && cols.write_rows(part.start, &r).is_err() {
            // The file failed: the parts so far again, in memory.
            memory = true;
            cols = Columns::in_memory(len, ch);
            for earlier in parts(0..part.end) {
                rows.clear();
                rows.extend(earlier.clone());
                residuals(prep, model, &rows, &mut r);
                cols.write_rows(earlier.start, &r)?;
            }
        }
    }
    Ok(cols)
}

/// Rows per part of a pass over many rows: a residual is held for this many rows at a time.
const PART_ROWS: usize = 1 << 15;

/// `rows` in parts of [`PART_ROWS`].
fn parts(rows: std::ops::Range<usize>) -> impl Iterator<Item = std::ops::Range<usize>> {
    let end = rows.end;
    rows.step_by(PART_ROWS)
        .map(move |a| a..(a + PART_ROWS).min(end))
}

/// t statistic of gains (mean / standard error); +∞ when all gains are equal and positive.
pub(crate) fn paired_t(g: &[f64]) -> f64 {
    let b = g.len() as f64;
    if g.len() < 2 {
        return 0.0;
    }
    let mean = g.iter().sum::<f64>() / b;
    let var = g.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (b - 1.0);
    if var <= 0.0 {
        return if mean > 0.0 { f64::INFINITY } else { 0.0 };
    }
    mean / (var / b).sqrt()
}

/// One-sided 95 % quantile of Student's t with `dof` degrees of freedom (table; linear in
/// between, normal quantile 1.645 beyond 120).
pub(crate) fn t_quantile_95(dof: usize) -> f64 {
    const T: [f64; 10] = [
        6.314, 2.920, 2.353, 2.132, 2.015, 1.943, 1.895, 1.860, 1.833, 1.812,
    ];
    match dof {
        0 => f64::INFINITY,
        d if d <= 10 => T[d - 1],
        d if d <= 30 => 1.812 - (1.812 - 1.697) * (d - 10) as f64 / 20.0,
        d if d <= 120 => 1.697 - (1.697 - 1.658) * (d - 30) as f64 / 90.0,
        _ => 1.645,
    }
}
