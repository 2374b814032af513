//! Which effect is missing: each catalogue effect observable in the log is fitted alone on top
//! of the current model (switched on if it was off, its parameters re-fitted if it was on),
//! k-fold by contiguous time blocks; candidates are ranked by the held-out RMSE. A candidate
//! is significant when it cuts the held-out RMSE by at least [`MIN_GAIN`] and its BIC
//! `m ln(SSR/m) + P ln m` beats the current model's by more than [`MIN_DELTA_BIC`] (the penalty
//! for the parameters it adds). When none is, the diagnosis says that nothing significant is
//! missing.

use crate::effects::CATALOGUE;
use crate::error::Result;
use crate::identify::fit::{fit, residuals, FittedParam};
use crate::identify::model::{Model, Prepared};
use serde::Serialize;

/// Minimum relative cut of the held-out RMSE for a significant candidate.
pub const MIN_GAIN: f64 = 0.05;
/// BIC improvement (decrease) required for a significant candidate.
pub const MIN_DELTA_BIC: f64 = 10.0;

/// One ranked candidate.
#[derive(Clone, Debug, Serialize)]
pub struct Candidate {
    /// Catalogue name.
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
    /// Significant by both criteria.
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
    /// Folds used.
    pub folds: usize,
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

/// Contiguous time blocks.
pub fn blocks(len: usize, folds: usize) -> Vec<Vec<usize>> {
    let folds = folds.max(2);
    (0..folds)
        .map(|f| (f * len / folds..(f + 1) * len / folds).collect())
        .collect()
}

/// Diagnose the residual of `model` on the log; the model is left unchanged.
pub fn diagnose(prep: &Prepared, model: &mut Model, folds: usize) -> Result<Diagnosis> {
    let len = prep.len();
    let all: Vec<usize> = (0..len).collect();
    let base_state = model.state();
    let mut r = Vec::new();
    residuals(prep, model, &all, &mut r);
    let m = r.len() as f64;
    let ssr0: f64 = r.iter().map(|x| x * x).sum();
    let base_rmse = (ssr0 / m).sqrt();
    let bic0 = m * (ssr0 / m).max(1e-300).ln();
    let bl = blocks(len, folds);
    let mut cands = Vec::new();
    let mut not_obs = Vec::new();
    for name in CATALOGUE {
        if !Model::observable(name, prep.log.kind) {
            not_obs.push(name.to_string());
            continue;
        }
        let in_model = model.is_enabled(name);
        let mut sse = 0.0;
        let mut cnt = 0usize;
        for b in &bl {
            // Blocks are contiguous: the training rows are everything outside [lo, hi]
            // (linear in the log length; `b.contains` per row was quadratic).
            let (lo, hi) = (
                b.first().copied().unwrap_or(0),
                b.last().copied().unwrap_or(0),
            );
            let train: Vec<usize> = (0..lo).chain(hi + 1..len).collect();
            model.restore(&base_state);
            fit(prep, model, &[name], &train)?;
            residuals(prep, model, b, &mut r);
            sse += r.iter().map(|x| x * x).sum::<f64>();
            cnt += r.len();
        }
        model.restore(&base_state);
        let full = fit(prep, model, &[name], &all)?;
        // Joints it acts on: channels whose prediction moved by more than 10 % of the largest
        // move, or per-joint parameters that moved by more than two standard errors.
        let mut pred1 = Vec::new();
        prep.predict(model, &all, &mut pred1);
        model.restore(&base_state);
        let mut pred0 = Vec::new();
        prep.predict(model, &all, &mut pred0);
        let ch = prep.log.channels;
        let mut joints = Vec::new();
        if ch > 1 {
            let d: Vec<f64> = (0..ch)
                .map(|c| {
                    (0..len)
                        .map(|k| (pred1[k * ch + c] - pred0[k * ch + c]).powi(2))
                        .sum::<f64>()
                })
                .collect();
            let dmax = d.iter().cloned().fold(0.0, f64::max);
            joints = (0..ch)
                .filter(|&c| dmax > 0.0 && d[c] > 0.01 * dmax)
                .map(|c| c + 1)
                .collect();
        } else {
            for p in &full.params {
                if let Some(j) = p
                    .name
                    .split_once('[')
                    .and_then(|(_, r)| r.trim_end_matches(']').parse::<usize>().ok())
                {
                    let moved = (p.value - p.nominal).abs();
                    if moved > 0.0 && p.std_error.is_none_or(|s| moved > 2.0 * s) {
                        joints.push(j);
                    }
                }
            }
        }
        let cv = (sse / cnt.max(1) as f64).sqrt();
        let cut = if base_rmse > 0.0 {
            100.0 * (1.0 - cv / base_rmse)
        } else {
            0.0
        };
        let bic = m * (full.ssr / m).max(1e-300).ln() + full.params.len() as f64 * m.ln();
        let dbic = bic - bic0;
        cands.push(Candidate {
            effect: name.to_string(),
            in_model,
            joints,
            params: full.params,
            validation_rmse: cv,
            rmse_cut_pct: cut,
            delta_bic: dbic,
            significant: cut >= 100.0 * MIN_GAIN && dbic < -MIN_DELTA_BIC,
            note: full.ill_conditioned.map(|i| i.to_string()),
        });
    }
    model.restore(&base_state);
    cands.sort_by(|a, b| a.validation_rmse.total_cmp(&b.validation_rmse));
    let best = cands
        .first()
        .filter(|c| c.significant)
        .map(|c| c.effect.clone());
    let verdict = match (&best, cands.first()) {
        (Some(b), Some(c)) => format!(
            "`{b}` {} explains the largest part of the residual: held-out RMSE {:.4} → {:.4} ({:.1} % less) on joints {:?}",
            if c.in_model { "(re-fitted)" } else { "(missing)" },
            base_rmse,
            c.validation_rmse,
            c.rmse_cut_pct,
            c.joints
        ),
        (None, Some(c)) => format!(
            "nothing significant is missing: the best candidate `{}` cuts the held-out RMSE by only {:.1} % (threshold {:.0} %, ΔBIC {:.1}); the residual looks like noise",
            c.effect,
            c.rmse_cut_pct,
            100.0 * MIN_GAIN,
            c.delta_bic
        ),
        _ => "no candidate effect is observable in this log".into(),
    };
    Ok(Diagnosis {
        schema_version: crate::identify::JSON_SCHEMA_VERSION,
        calibration: None,
        base_rmse,
        folds: bl.len(),
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
