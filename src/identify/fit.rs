//! Bounded nonlinear least squares (Levenberg–Marquardt with column scaling, bounds by
//! projection, forward-difference Jacobian; one step when the model is linear in the
//! parameters) of the enabled effects' parameters to a log, with the LS covariance, the
//! condition number and the near-null space of the (column-normalised) Jacobian.
//! The objective is the sum of squared signal residuals over samples and channels, i.e. the
//! RMSE of seed 000, eq. 8.

use crate::error::Result;
use crate::identify::model::{Model, Prepared};
use serde::Serialize;

/// Column-normalised condition number above which a fit is reported as ill-conditioned.
pub const CONDITION_LIMIT: f64 = 1e4;

/// One fitted parameter.
#[derive(Clone, Debug, Serialize)]
pub struct FittedParam {
    /// Catalogue name of the effect.
    pub effect: String,
    /// Parameter name, e.g. `f_c[2]`.
    pub name: String,
    /// SI unit.
    pub unit: String,
    /// Value before the fit.
    pub nominal: f64,
    /// Fitted value.
    pub value: f64,
    /// Standard error from the LS covariance `σ² (JᵀJ)⁻¹` (same unit); `None` when not
    /// identifiable.
    pub std_error: Option<f64>,
}

/// Parameters the data cannot tell apart.
#[derive(Clone, Debug, Serialize)]
pub struct IllConditioning {
    /// Condition number of the column-normalised Jacobian (∞ when a column is zero).
    pub condition_number: f64,
    /// Groups of parameters spanning the near-null space (one group per direction); a group
    /// of one is a parameter the motion does not excite at all.
    pub groups: Vec<Vec<String>>,
}

impl std::fmt::Display for IllConditioning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "ill-conditioned fit (condition number {:.3e}): the motion cannot tell apart ",
            self.condition_number
        )?;
        let g: Vec<String> = self
            .groups
            .iter()
            .map(|g| {
                if g.len() == 1 {
                    format!("{} (not excited)", g[0])
                } else {
                    format!("{{{}}}", g.join(", "))
                }
            })
            .collect();
        write!(f, "{}", g.join("; "))
    }
}

/// The result of a fit.
#[derive(Clone, Debug, Serialize)]
pub struct FitResult {
    /// Parameters in effect order.
    pub params: Vec<FittedParam>,
    /// RMSE on the fitted rows (signal unit).
    pub rmse: f64,
    /// Sum of squared residuals on the fitted rows.
    pub ssr: f64,
    /// Number of residuals (rows × channels).
    pub residuals: usize,
    /// Condition number of the column-normalised Jacobian.
    pub condition_number: f64,
    /// Set when some parameters cannot be told apart.
    pub ill_conditioned: Option<IllConditioning>,
}

/// Residuals `prediction − measurement` at `rows`.
pub fn residuals(prep: &Prepared, model: &Model, rows: &[usize], out: &mut Vec<f64>) {
    prep.predict(model, rows, out);
    let ch = prep.log.channels;
    for (r, &k) in rows.iter().enumerate() {
        for c in 0..ch {
            out[r * ch + c] -= prep.log.y[k * ch + c];
        }
    }
}

struct Layout {
    effects: Vec<&'static str>,
    sizes: Vec<usize>,
    lower: Vec<f64>,
    upper: Vec<f64>,
    names: Vec<(String, String, String)>,
}

fn set_all(model: &mut Model, lay: &Layout, theta: &[f64]) -> Result<()> {
    let mut o = 0;
    for (e, &p) in lay.effects.iter().zip(&lay.sizes) {
        model.set_values(e, &theta[o..o + p])?;
        o += p;
    }
    Ok(())
}

/// Fit the parameters of `effects` (switched on by this call) to the samples `rows`, starting
/// from their current values; the model keeps the fitted values.
pub fn fit(
    prep: &Prepared,
    model: &mut Model,
    effects: &[&'static str],
    rows: &[usize],
) -> Result<FitResult> {
    fit_holding(prep, model, effects, rows, &[])
}

/// [`fit`], holding the parameters named in `hold` (`effect.param`, e.g. `coulomb.f_c[5]`)
/// at their current values: they are not fitted, get no standard error and take no part in
/// the conditioning analysis (per-joint identifiability: a joint the motion does not excite
/// keeps its prior while the others are fitted).
pub fn fit_holding(
    prep: &Prepared,
    model: &mut Model,
    effects: &[&'static str],
    rows: &[usize],
    hold: &[String],
) -> Result<FitResult> {
    let mut lay = Layout {
        effects: effects.to_vec(),
        sizes: vec![],
        lower: vec![],
        upper: vec![],
        names: vec![],
    };
    let mut theta = Vec::new();
    for e in effects {
        model.set_enabled(e, true)?;
        let specs = model.params(e)?;
        lay.sizes.push(specs.len());
        for s in &specs {
            lay.lower.push(s.lower);
            lay.upper.push(s.upper);
            lay.names
                .push((e.to_string(), s.name.clone(), s.unit.to_string()));
        }
        theta.extend(model.values(e)?);
    }
    let nominal = theta.clone();
    let p = theta.len();
    let held: Vec<bool> = lay
        .names
        .iter()
        .map(|(e, n, _)| hold.iter().any(|h| *h == format!("{e}.{n}")))
        .collect();
    let mut r = Vec::new();
    residuals(prep, model, rows, &mut r);
    let m = r.len();
    let ssr_of = |r: &[f64]| r.iter().map(|x| x * x).sum::<f64>();
    let mut ssr = ssr_of(&r);
    let mut lambda = 1e-9;
    let mut jac = vec![0.0; m * p];
    let mut rp = Vec::new();
    let clamp = |th: &mut [f64]| {
        for (i, t) in th.iter_mut().enumerate() {
            *t = t.clamp(lay.lower[i], lay.upper[i]);
        }
    };
    let jacobian = |model: &mut Model,
                    theta: &[f64],
                    r: &[f64],
                    jac: &mut [f64],
                    rp: &mut Vec<f64>|
     -> Result<()> {
        for i in 0..p {
            let mut th = theta.to_vec();
            let mut h = 1e-5 * theta[i].abs().max(1e-2);
            if th[i] + h > lay.upper[i] {
                h = -h;
            }
            th[i] += h;
            set_all(model, &lay, &th)?;
            residuals(prep, model, rows, rp);
            for k in 0..m {
                jac[k * p + i] = (rp[k] - r[k]) / h;
            }
        }
        set_all(model, &lay, theta)
    };
    for _iter in 0..40 {
        if p == 0 {
            break;
        }
        jacobian(model, &theta, &r, &mut jac, &mut rp)?;
        let jm = nalgebra::DMatrix::from_row_slice(m, p, &jac);
        let jtj = jm.transpose() * &jm;
        let mut g = jm.transpose() * nalgebra::DVector::from_column_slice(&r);
        let maxdiag = (0..p).map(|i| jtj[(i, i)]).fold(0.0, f64::max);
        // Columns with no excitation stay where they are.
        let frozen: Vec<bool> = (0..p)
            .map(|i| held[i] || jtj[(i, i)] <= 1e-12 * maxdiag)
            .collect();
        let mut jtj = jtj;
        for i in 0..p {
            if frozen[i] {
                for k in 0..p {
                    jtj[(i, k)] = 0.0;
                    jtj[(k, i)] = 0.0;
                }
                jtj[(i, i)] = 1.0;
                g[i] = 0.0;
            }
        }
        let mut improved = false;
        for _try in 0..12 {
            let mut a = jtj.clone();
            for i in 0..p {
                let d = jtj[(i, i)].max(1e-30);
                a[(i, i)] += lambda * d + 1e-14 * d;
            }
            let step = match a.clone().cholesky() {
                Some(c) => c.solve(&(-&g)),
                None => {
                    lambda *= 10.0;
                    continue;
                }
            };
            let mut th: Vec<f64> = theta.iter().zip(step.iter()).map(|(a, b)| a + b).collect();
            clamp(&mut th);
            set_all(model, &lay, &th)?;
            residuals(prep, model, rows, &mut rp);
            let s = ssr_of(&rp);
            if s < ssr {
                let rel = (ssr - s) / ssr.max(1e-300);
                theta = th;
                std::mem::swap(&mut r, &mut rp);
                ssr = s;
                lambda = (lambda / 10.0).max(1e-12);
                improved = rel > 1e-10;
                break;
            }
            lambda *= 10.0;
        }
        set_all(model, &lay, &theta)?;
        if !improved {
            break;
        }
    }
    // Covariance and conditioning at the solution.
    let mut se = vec![None; p];
    let mut cond = 1.0;
    let mut ill = None;
    if p > 0 {
        jacobian(model, &theta, &r, &mut jac, &mut rp)?;
        let jm = nalgebra::DMatrix::from_row_slice(m, p, &jac);
        let jtj = jm.transpose() * &jm;
        // A column whose effect on the signal is below 1e-6 of the signal's RMS (for the
        // parameter at max(|θ|, 1)) is not excited: treated as zero.
        let ch = prep.log.channels;
        let yrms = (rows
            .iter()
            .flat_map(|&k| prep.log.y[k * ch..(k + 1) * ch].iter())
            .map(|v| v * v)
            .sum::<f64>()
            / m.max(1) as f64)
            .sqrt();
        let norms: Vec<f64> = (0..p)
            .map(|i| {
                if held[i] {
                    return f64::NAN;
                }
                let nrm = jtj[(i, i)].max(0.0).sqrt();
                if nrm * theta[i].abs().max(1.0) / (m.max(1) as f64).sqrt() < 1e-6 * yrms.max(1e-12)
                {
                    0.0
                } else {
                    nrm
                }
            })
            .collect();
        // The analysis runs on the active (not held) columns `act`.
        let act: Vec<usize> = (0..p).filter(|&i| !held[i]).collect();
        let pa = act.len();
        let mut s = nalgebra::DMatrix::<f64>::zeros(pa, pa);
        for (ii, &i) in act.iter().enumerate() {
            for (kk, &k) in act.iter().enumerate() {
                let d = norms[i] * norms[k];
                s[(ii, kk)] = if d > 0.0 { jtj[(i, k)] / d } else { 0.0 };
            }
        }
        let eig = s.symmetric_eigen();
        let emax = eig.eigenvalues.iter().cloned().fold(0.0, f64::max);
        let emin = eig
            .eigenvalues
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min);
        let zero_col = act.iter().any(|&i| norms[i] == 0.0);
        cond = if zero_col || emin <= 0.0 {
            f64::INFINITY
        } else {
            (emax / emin).sqrt()
        };
        let sigma2 = ssr / (m.saturating_sub(pa).max(1) as f64);
        let cut = emax / (CONDITION_LIMIT * CONDITION_LIMIT);
        let mut groups: Vec<Vec<String>> = act
            .iter()
            .filter(|&&i| norms[i] == 0.0)
            .map(|&i| vec![format!("{}.{}", lay.names[i].0, lay.names[i].1)])
            .collect();
        for (c, &ev) in eig.eigenvalues.iter().enumerate() {
            if ev <= cut {
                let v = eig.eigenvectors.column(c);
                let g: Vec<String> = act
                    .iter()
                    .enumerate()
                    .filter(|&(ii, &i)| norms[i] > 0.0 && v[ii].abs() > 0.2)
                    .map(|(_, &i)| format!("{}.{}", lay.names[i].0, lay.names[i].1))
                    .collect();
                if !g.is_empty() && !groups.contains(&g) {
                    groups.push(g);
                }
            }
        }
        let weak: Vec<bool> = (0..p)
            .map(|i| {
                held[i]
                    || norms[i] == 0.0
                    || groups
                        .iter()
                        .any(|g| g.contains(&format!("{}.{}", lay.names[i].0, lay.names[i].1)))
            })
            .collect();
        // Covariance by the pseudo-inverse on the well-determined subspace.
        let mut cov = nalgebra::DMatrix::<f64>::zeros(pa, pa);
        for (c, &ev) in eig.eigenvalues.iter().enumerate() {
            if ev > cut {
                let v = eig.eigenvectors.column(c);
                cov += (v * v.transpose()) / ev;
            }
        }
        for (ii, &i) in act.iter().enumerate() {
            if !weak[i] && norms[i] > 0.0 {
                se[i] = Some((sigma2 * cov[(ii, ii)]).max(0.0).sqrt() / norms[i]);
            }
        }
        if !groups.is_empty() {
            ill = Some(IllConditioning {
                condition_number: cond,
                groups,
            });
        }
    }
    let params = (0..p)
        .map(|i| FittedParam {
            effect: lay.names[i].0.clone(),
            name: lay.names[i].1.clone(),
            unit: lay.names[i].2.clone(),
            nominal: nominal[i],
            value: theta[i],
            std_error: se[i],
        })
        .collect();
    Ok(FitResult {
        params,
        rmse: (ssr / m.max(1) as f64).sqrt(),
        ssr,
        residuals: m,
        condition_number: cond,
        ill_conditioned: ill,
    })
}
