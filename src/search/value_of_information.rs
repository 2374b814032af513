//! What knowing an uncertain parameter before choosing the placement is worth (the expected
//! value of partial perfect information), from the draws of a robust study alone (no nested
//! sampling).
//!
//! For a parameter with drawn values `x_d` and each candidate `c`, the energy difference to
//! the recommendation `Δ_c(d) = E(c, d) − E(rec, d)` is fitted by least squares as
//! `a_c + b_c·x`; the slope is kept only where the draws support it (|t| ≥ 2; else the fit is
//! the mean difference, which is >= 0 for a recommendation chosen by expected energy). Knowing
//! `x`, one would choose the candidate of lowest fitted difference, so the value of knowing
//! it is the mean over the draws of `max(0, −min_c (a_c + b_c·x_d))`, J per print, at most the
//! value of knowing everything (the recommendation's expected regret). A parameter that does
//! not move the decision has no supported slope and is worth 0.
//!
//! How much of the regret a parameter explains: R² of the same linear fit of the nominal
//! answer's regret on its values.

use crate::search::robust::ParameterValue;

/// Least squares `y ≈ a + b·x`: (a, b, t-statistic of b, R²). `None` without spread in x.
fn fit(x: &[f64], y: &[f64]) -> Option<(f64, f64, f64, f64)> {
    let n = x.len() as f64;
    if x.len() < 3 {
        return None;
    }
    let mx = x.iter().sum::<f64>() / n;
    let my = y.iter().sum::<f64>() / n;
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxx += (a - mx) * (a - mx);
        sxy += (a - mx) * (b - my);
        syy += (b - my) * (b - my);
    }
    if sxx.is_nan() || sxx <= 0.0 {
        return None;
    }
    let b = sxy / sxx;
    let a = my - b * mx;
    let sse = (syy - b * sxy).max(0.0);
    let se = (sse / (n - 2.0) / sxx).sqrt();
    let t = if se > 0.0 {
        b / se
    } else if b != 0.0 {
        f64::INFINITY
    } else {
        0.0
    };
    let r2 = if syy > 0.0 {
        (b * sxy / syy).clamp(0.0, 1.0)
    } else {
        0.0
    };
    Some((a, b, t, r2))
}

/// The expected saving of knowing a parameter whose drawn values are `x`: each other
/// candidate's energy difference to the recommendation (`diffs`) as a line in the parameter
/// (its mean where the slope is not significant, |t| < 2), the best line's saving averaged over
/// the `n` draws; never negative, never more than knowing everything (`everything`).
fn value_of_knowing(x: &[f64], diffs: &[Vec<f64>], n: usize, everything: f64) -> f64 {
    let lines: Vec<(f64, f64)> = diffs
        .iter()
        .filter_map(|y| {
            let (a, b, t, _) = fit(x, y)?;
            Some(if t.abs() >= 2.0 {
                (a, b)
            } else {
                (y.iter().sum::<f64>() / n as f64, 0.0)
            })
        })
        .collect();
    let value_j = x
        .iter()
        .map(|&xd| {
            let m = lines.iter().map(|(a, b)| a + b * xd).fold(0.0f64, f64::min);
            -m
        })
        .sum::<f64>()
        / n as f64;
    if value_j > 0.0 {
        value_j.min(everything)
    } else {
        0.0
    }
}

/// The value of knowing each parameter, most valuable first (ties by name). `drawn[d][i]`:
/// parameter `i`'s value in draw `d`; `energy_j[d][c]`: candidate `c`'s energy in draw `d`;
/// `rec`: the recommendation, `nominal`: the nominal answer (for the regret explained).
/// Parameters without spread, or with a value missing in some draw, are left out.
pub fn rank(
    parameters: &[String],
    drawn: &[Vec<f64>],
    energy_j: &[Vec<f64>],
    rec: usize,
    nominal: usize,
    prints_per_year: f64,
) -> Vec<ParameterValue> {
    let n = energy_j.len();
    if n < 3 {
        return Vec::new();
    }
    let k = energy_j[0].len();
    let ok: Vec<usize> = (0..k)
        .filter(|&c| {
            energy_j
                .iter()
                .all(|e| e.get(c).is_some_and(|v| v.is_finite()))
        })
        .collect();
    if !ok.contains(&rec) {
        return Vec::new();
    }
    let best: Vec<f64> = energy_j
        .iter()
        .map(|e| ok.iter().map(|&c| e[c]).fold(f64::INFINITY, f64::min))
        .collect();
    let nominal_regret: Vec<f64> = (0..n).map(|d| energy_j[d][nominal] - best[d]).collect();
    // Knowing every parameter is worth the recommendation's expected regret; knowing one is
    // worth no more (the linear fits may extrapolate beyond it).
    let everything = (0..n).map(|d| energy_j[d][rec] - best[d]).sum::<f64>() / n as f64;
    let diffs: Vec<Vec<f64>> = ok
        .iter()
        .filter(|&&c| c != rec)
        .map(|&c| (0..n).map(|d| energy_j[d][c] - energy_j[d][rec]).collect())
        .collect();
    let mut out = Vec::new();
    for (i, name) in parameters.iter().enumerate() {
        let x: Vec<f64> = drawn
            .iter()
            .map(|v| v.get(i).copied().unwrap_or(f64::NAN))
            .collect();
        if x.iter().any(|v| !v.is_finite()) {
            continue;
        }
        if x.iter().all(|v| *v == x[0]) {
            continue;
        }
        let r2 = fit(&x, &nominal_regret).map_or(0.0, |f| f.3);
        let value_j = value_of_knowing(&x, &diffs, n, everything);
        out.push(ParameterValue {
            name: name.clone(),
            regret_explained: r2,
            value_j,
            value_kwh_per_year: value_j * prints_per_year / 3.6e6,
        });
    }
    out.sort_by(|a, b| {
        b.value_j
            .total_cmp(&a.value_j)
            .then(b.regret_explained.total_cmp(&a.regret_explained))
            .then(a.name.cmp(&b.name))
    });
    out
}
