//! Bounded nonlinear least squares (Levenberg–Marquardt with column scaling, bounds by
//! projection, forward-difference Jacobian; one step when the model is linear in the
//! parameters) of the enabled effects' parameters to a log, with the LS covariance, the
//! condition number and the near-null space of the (column-normalised) Jacobian.
//! The objective is the sum of squared signal residuals over samples and channels, i.e. the
//! RMSE of seed 000, eq. 8.

use crate::dynamics::MAX_DOF;
use crate::effects::{Effect, Stage};
use crate::error::{Error, Result};
use crate::identify::model::{Model, Prepared};
use serde::Serialize;

/// At most this many rows take part in the parameter fit (an even stride through the rows
/// given; every row is still used for the returned RMSE and by the callers' validation).
/// Neighbouring rows of a controller log are correlated over the residual's correlation time,
/// so a longer log adds little information to the fit and only time: with the cap, fitting is
/// of fixed cost and everything else is linear in the log length.
pub const FIT_ROWS_MAX: usize = 20_000;

/// The rows used for fitting: all of `rows`, or an even stride of at most [`FIT_ROWS_MAX`].
pub fn fit_rows(rows: &[usize]) -> Vec<usize> {
    if rows.len() <= FIT_ROWS_MAX {
        return rows.to_vec();
    }
    let stride = rows.len().div_ceil(FIT_ROWS_MAX);
    rows.iter().step_by(stride).copied().collect()
}

/// Jacobian `∂ signal / ∂ θ` at `rows` (row-major `rows.len()·channels × θ.len()`), by
/// derivatives of each fitted effect alone: a linear torque effect's regressor column; a
/// nonlinear one's forward difference of its own torque; a motor or supply effect's forward
/// difference of the motor model at the same torque. Torque changes reach current and power
/// logs through a forward difference of the motor model. No full re-prediction per column.
fn jacobian(
    prep: &Prepared,
    model: &mut Model,
    lay: &Layout,
    theta: &[f64],
    rows: &[usize],
    jac: &mut [f64],
) -> Result<()> {
    let n = model.n;
    let ch = prep.log.channels;
    let kind = prep.log.kind;
    let p = theta.len();
    let m = rows.len() * ch;
    let mut tau = vec![0.0; rows.len() * n];
    let mut sig = vec![0.0; m];
    for (r, &k) in rows.iter().enumerate() {
        prep.torque_row_kept(model, k, &[], &mut tau[r * n..(r + 1) * n]);
        model.signal_from_torque(
            kind,
            &tau[r * n..(r + 1) * n],
            prep.log.traj.qd(k),
            &mut sig[r * ch..(r + 1) * ch],
        );
    }
    let step = |i: usize| {
        let mut h = 1e-5 * theta[i].abs().max(1e-2);
        if theta[i] + h > lay.upper[i] {
            h = -h;
        }
        h
    };
    let mut s2 = [0.0; MAX_DOF];
    let mut t2 = [0.0; MAX_DOF];
    let mut o = 0;
    for (name, &pe) in lay.effects.iter().zip(&lay.sizes) {
        let pos = model
            .position(name)
            .ok_or_else(|| Error::Invalid(format!("effect `{name}` is not in the model")))?;
        let vals = model.values(name)?;
        let stage = model.effect(name)?.stage();
        if stage != Stage::Torque {
            for li in 0..pe {
                let i = o + li;
                let h = step(i);
                let mut v = vals.clone();
                v[li] += h;
                model.set_values(name, &v)?;
                for (r, &k) in rows.iter().enumerate() {
                    model.signal_from_torque(
                        kind,
                        &tau[r * n..(r + 1) * n],
                        prep.log.traj.qd(k),
                        &mut s2[..ch],
                    );
                    for c in 0..ch {
                        jac[(r * ch + c) * p + i] = (s2[c] - sig[r * ch + c]) / h;
                    }
                }
                model.set_values(name, &vals)?;
            }
            o += pe;
            continue;
        }
        let eff = model.effect(name)?;
        let hs: Vec<f64> = (0..pe).map(|li| step(o + li)).collect();
        // Perturbed copies for effects without a regressor.
        let mut y = vec![0.0; n * pe];
        let linear = rows.first().is_none_or(|&k| {
            eff.regressor(
                prep.log.traj.q(k),
                prep.log.traj.qd(k),
                prep.log.traj.qdd(k),
                &mut y,
            )
        });
        let mut copies: Vec<Box<dyn Effect>> = Vec::new();
        if !linear {
            for li in 0..pe {
                let mut c = eff.clone_box();
                let mut v = vals.clone();
                v[li] += hs[li];
                c.set_values(&v)?;
                copies.push(c);
            }
        }
        let mut d = vec![0.0; n * pe]; // dτ_j/dθ_li at j * pe + li
        let mut base = [0.0; MAX_DOF];
        for (r, &k) in rows.iter().enumerate() {
            let (q, qd, qdd) = (
                prep.log.traj.q(k),
                prep.log.traj.qd(k),
                prep.log.traj.qdd(k),
            );
            if prep.regressor_row(model, pos, k, &mut d) {
            } else if linear {
                eff.regressor(q, qd, qdd, &mut d);
            } else {
                base[..n].iter_mut().for_each(|v| *v = 0.0);
                eff.add_torque(q, qd, qdd, &mut base[..n]);
                for (li, c) in copies.iter().enumerate() {
                    t2[..n].iter_mut().for_each(|v| *v = 0.0);
                    c.add_torque(q, qd, qdd, &mut t2[..n]);
                    for j in 0..n {
                        d[j * pe + li] = (t2[j] - base[j]) / hs[li];
                    }
                }
            }
            let tr = &tau[r * n..(r + 1) * n];
            for li in 0..pe {
                let i = o + li;
                if kind == crate::identify::SignalKind::Torque {
                    for j in 0..n {
                        jac[(r * ch + j) * p + i] = d[j * pe + li];
                    }
                } else {
                    let h = hs[li];
                    for j in 0..n {
                        t2[j] = tr[j] + h * d[j * pe + li];
                    }
                    model.signal_from_torque(kind, &t2[..n], qd, &mut s2[..ch]);
                    for c in 0..ch {
                        jac[(r * ch + c) * p + i] = (s2[c] - sig[r * ch + c]) / h;
                    }
                }
            }
        }
        o += pe;
    }
    Ok(())
}

/// Column-normalised condition number above which a fit is reported as ill-conditioned.
pub(crate) const CONDITION_LIMIT: f64 = 1e4;

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
    /// Standard error (same unit): the larger of the least-squares one `σ² (JᵀJ)⁻¹` and the
    /// autocorrelation-consistent one (overlapping-block sandwich
    /// `(JᵀJ)⁻¹ Ω (JᵀJ)⁻¹`, blocks several residual correlation times long; docs/identify.md);
    /// `None` when not identifiable or held.
    pub std_error: Option<f64>,
}

/// Parameters the data cannot tell apart.
#[derive(Clone, Debug, Serialize)]
pub struct IllConditioning {
    /// Condition number of the column-normalised Jacobian (∞ when a column is zero; `null`
    /// in JSON).
    #[serde(serialize_with = "finite_or_null")]
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
    /// Condition number of the column-normalised Jacobian (`null` in JSON when infinite).
    #[serde(serialize_with = "finite_or_null")]
    pub condition_number: f64,
    /// Set when some parameters cannot be told apart.
    pub ill_conditioned: Option<IllConditioning>,
    /// Fitted (not held) parameters that ended at a bound of their range (`effect.param`,
    /// e.g. `coulomb.f_c+[2]`): the fit wanted to go further, so another effect may be
    /// missing or soaked up.
    pub at_bound: Vec<String>,
    /// Rows per block of the autocorrelation-consistent standard errors (at least a few
    /// residual correlation times).
    pub hac_block_rows: usize,
    /// Correlation of the parameters that have a standard error: the standard errors and
    /// this matrix together are the fit's covariance, which the uncertainty study draws
    /// from for a calibrated robot.
    pub correlation: Correlation,
}

/// Correlation matrix of some fitted parameters (`effect.param` names, row-major, symmetric,
/// unit diagonal).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Correlation {
    /// `effect.param` of each row and column.
    pub params: Vec<String>,
    /// The matrix, one row per parameter.
    pub matrix: Vec<Vec<f64>>,
}

/// A number, or `null` when it is not finite (an infinite condition number).
pub(crate) fn finite_or_null<S: serde::Serializer>(
    v: &f64,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    if v.is_finite() {
        s.serialize_f64(*v)
    } else {
        s.serialize_none()
    }
}

/// Blocks of the autocorrelation-consistent standard errors are this many residual
/// correlation times long (at least).
pub const HAC_BLOCK_CORRELATION_TIMES: f64 = 16.0;

/// Block length (rows) for the autocorrelation-consistent covariance of a row-major residual
/// `r` with `ch` channels: [`HAC_BLOCK_CORRELATION_TIMES`] times the longest channel's
/// correlation time in rows, at least 1 and at most a quarter of the rows.
pub(crate) fn hac_block_rows(r: &[f64], ch: usize) -> usize {
    let t = r.len() / ch.max(1);
    let tau = (0..ch)
        .map(|c| crate::identify::structure::correlation_time(r, ch, c, 1.0))
        .fold(1.0f64, f64::max);
    ((HAC_BLOCK_CORRELATION_TIMES * tau).ceil() as usize)
        .max(1)
        .min((t / 4).max(1))
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
    all_rows: &[usize],
    hold: &[String],
) -> Result<FitResult> {
    fit_core(prep, model, effects, all_rows, hold, true)
}

/// [`fit`] without the final pass over every row: the returned RMSE and SSR are those of the
/// rows the fit used ([`fit_rows`]). For callers that evaluate the fitted model themselves.
pub(crate) fn fit_parameters(
    prep: &Prepared,
    model: &mut Model,
    effects: &[&'static str],
    rows: &[usize],
) -> Result<FitResult> {
    fit_core(prep, model, effects, rows, &[], false)
}

/// `Jᵀ J` of the Jacobian `J` (`m × p`) held as its transpose `jt` (`p × m`, column-major:
/// `J`'s row-major data). The second factor is a strided view of the same data, not a
/// transposed copy (`m × p` values less at the peak of a fit); the product is the same
/// matrixmultiply `gemm` over the same values (it packs its operands whatever their strides), so
/// the same bits as multiplying by an owned transpose.
fn gram(jt: &nalgebra::DMatrix<f64>) -> nalgebra::DMatrix<f64> {
    let (p, m) = jt.shape();
    let j = nalgebra::DMatrixView::from_slice_with_strides(jt.as_slice(), m, p, p, 1);
    jt * j
}

fn fit_core(
    prep: &Prepared,
    model: &mut Model,
    effects: &[&'static str],
    all_rows: &[usize],
    hold: &[String],
    full_ssr: bool,
) -> Result<FitResult> {
    let fit_on = fit_rows(all_rows);
    let rows = &fit_on[..];
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
    // Symmetric Coulomb (the default): `f_c−[j]` follows `f_c+[j]` (one level per joint).
    let ties: Vec<(usize, usize)> = if model.coulomb_directional {
        Vec::new()
    } else {
        let find = |e: &str, n: &str| lay.names.iter().position(|x| x.0 == e && x.1 == n);
        (1..=model.n)
            .filter_map(|j| {
                Some((
                    find("coulomb", &format!("f_c+[{j}]"))?,
                    find("coulomb", &format!("f_c-[{j}]"))?,
                ))
            })
            .collect()
    };
    let held: Vec<bool> = lay
        .names
        .iter()
        .enumerate()
        .map(|(i, (e, n, _))| {
            hold.iter().any(|h| *h == format!("{e}.{n}"))
                || ties.iter().any(|t| t.1 == i)
                || (e == "payload" && n.starts_with("dI_") && !model.payload_inertia)
        })
        .collect();
    // Tied pairs start from their mean (unless one of them is held, which then leads).
    let mut tie_ok = Vec::new();
    for &(a, b) in &ties {
        let ha = hold
            .iter()
            .any(|h| *h == format!("{}.{}", lay.names[a].0, lay.names[a].1));
        if ha {
            theta[b] = theta[a];
        } else {
            let v = 0.5 * (theta[a] + theta[b]);
            theta[a] = v;
            theta[b] = v;
        }
        tie_ok.push((a, b));
    }
    let ties = tie_ok;
    let tie_cols = |jac: &mut [f64], rows_m: usize| {
        for r in 0..rows_m {
            for &(a, b) in &ties {
                jac[r * p + a] += jac[r * p + b];
                jac[r * p + b] = 0.0;
            }
        }
    };
    // The payload's inertia held (only its mass and centre of mass fitted): its inertia about
    // its own centre of mass stays the prior's, so `dI_*` follow `dm` and `dh_*`.
    let payload_held = if model.payload_inertia {
        None
    } else {
        let find = |n: &str| lay.names.iter().position(|x| x.0 == "payload" && x.1 == n);
        match (
            model.effects.typed::<crate::effects::Payload>("payload"),
            find("dm"),
            find("dI_xx"),
        ) {
            (Some(pl), Some(dm), Some(di)) => Some((pl.clone(), dm, di)),
            _ => None,
        }
    };
    let follow = |th: &mut [f64]| {
        for &(a, b) in &ties {
            th[b] = th[a];
        }
        if let Some((pl, dm, di)) = &payload_held {
            let d = pl.held_inertia_error(th[*dm], [th[dm + 1], th[dm + 2], th[dm + 3]]);
            th[*di..di + 6].copy_from_slice(&d);
        }
    };
    if payload_held.is_some() {
        follow(&mut theta);
    }
    // The chain rule through `dI = P(Δh)/m` (`P(d) = |d|² 1 − d dᵀ`, `m = m₀ + Δm`): the
    // columns of `dm` and `dh_*` gain the held inertia's columns times its derivatives (near a
    // light load the inertia follows the first moment strongly).
    let payload_chain = |jac: &mut [f64], rows_m: usize, th: &[f64]| {
        let Some((pl, dm, di)) = &payload_held else {
            return;
        };
        let (dm, di) = (*dm, *di);
        let der = pl.held_inertia_derivatives(th[dm], [th[dm + 1], th[dm + 2], th[dm + 3]]);
        for r in 0..rows_m {
            let row = &mut jac[r * p..(r + 1) * p];
            for (c, dc) in der.iter().enumerate() {
                let add: f64 = (0..6).map(|k| row[di + k] * dc[k]).sum();
                row[dm + c] += add;
            }
        }
    };
    if !ties.is_empty() || payload_held.is_some() {
        set_all(model, &lay, &theta)?;
    }
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
    for _iter in 0..40 {
        if p == 0 {
            break;
        }
        jacobian(prep, model, &lay, &theta, rows, &mut jac)?;
        tie_cols(&mut jac, m);
        payload_chain(&mut jac, m, &theta);
        // The row-major Jacobian is its transpose, column-major: no copy.
        let jt = nalgebra::DMatrix::from_vec(p, m, std::mem::take(&mut jac));
        let jtj = gram(&jt);
        let mut g = &jt * nalgebra::DVector::from_column_slice(&r);
        jac = jt.data.into();
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
            follow(&mut th);
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
    let mut hac_rows = 1;
    let mut cond = 1.0;
    let mut ill = None;
    let mut correlation = Correlation::default();
    if p > 0 {
        jacobian(prep, model, &lay, &theta, rows, &mut jac)?;
        tie_cols(&mut jac, m);
        payload_chain(&mut jac, m, &theta);
        let jt = nalgebra::DMatrix::from_vec(p, m, std::mem::take(&mut jac));
        let jtj = gram(&jt);
        jac = jt.data.into();
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
        // Autocorrelation-consistent (sandwich) covariance: the scores `g_t = J_tᵀ r_t` of
        // each row (normalised active columns) summed over overlapping blocks of
        // `hac_rows` rows, `Ω = (T / B) · mean_s(G_s G_sᵀ)`, `Cov = S⁺ Ω S⁺`.
        hac_rows = hac_block_rows(&r, ch);
        let t_rows = m / ch.max(1);
        let mut prefix = vec![nalgebra::DVector::<f64>::zeros(pa); t_rows + 1];
        for t in 0..t_rows {
            let mut g = prefix[t].clone();
            for c in 0..ch {
                let row = t * ch + c;
                let res = r[row];
                for (ii, &i) in act.iter().enumerate() {
                    if norms[i] > 0.0 {
                        g[ii] += jac[row * p + i] / norms[i] * res;
                    }
                }
            }
            prefix[t + 1] = g;
        }
        let b = hac_rows.min(t_rows.max(1));
        let windows = t_rows + 1 - b.min(t_rows);
        let mut omega = nalgebra::DMatrix::<f64>::zeros(pa, pa);
        if windows > 0 && t_rows > 0 {
            for s0 in 0..windows {
                let d = &prefix[s0 + b] - &prefix[s0];
                omega += &d * d.transpose();
            }
            // At the least-squares solution the scores sum to zero, so block sums are
            // negatively correlated: the batch-means estimate is low by the factor
            // `1 − B/T`, corrected here.
            let frac = (b as f64 / t_rows as f64).min(0.5);
            omega *= t_rows as f64 / b as f64 / windows as f64 / (1.0 - frac);
        }
        // The block estimate of Ω has about 1.5 T/B degrees of freedom (overlapping batch
        // means): the standard error is widened by t(ν)/z so that ±1.96 SE is a 95 % interval.
        let nu = (1.5 * t_rows as f64 / b.max(1) as f64).max(1.0);
        let z = 1.959_964f64;
        let t975 = z
            + (z.powi(3) + z) / (4.0 * nu)
            + (5.0 * z.powi(5) + 16.0 * z.powi(3) + 3.0 * z) / (96.0 * nu * nu);
        let hac = (&cov * omega * &cov) * (t975 / z).powi(2);
        for (ii, &i) in act.iter().enumerate() {
            if !weak[i] && norms[i] > 0.0 {
                let v = (sigma2 * cov[(ii, ii)]).max(hac[(ii, ii)]).max(0.0);
                se[i] = Some(v.sqrt() / norms[i]);
            }
        }
        for &(a, bb) in &ties {
            se[bb] = se[a];
        }
        // The correlation of the parameters with a standard error, from the covariance whose
        // diagonal the standard errors came from (the sandwich one when it was estimated; a
        // tied parameter moves with its twin).
        let cov_of = |ii: usize, kk: usize| {
            if windows > 0 && t_rows > 0 {
                hac[(ii, kk)]
            } else {
                sigma2 * cov[(ii, kk)]
            }
        };
        let col = |i: usize| {
            let i = ties.iter().find(|t| t.1 == i).map_or(i, |t| t.0);
            act.iter().position(|&a| a == i)
        };
        let with_se: Vec<(usize, usize)> = (0..p)
            .filter(|&i| se[i].is_some())
            .filter_map(|i| col(i).map(|ii| (i, ii)))
            .collect();
        correlation = Correlation {
            params: with_se
                .iter()
                .map(|&(i, _)| format!("{}.{}", lay.names[i].0, lay.names[i].1))
                .collect(),
            matrix: with_se
                .iter()
                .map(|&(_, ii)| {
                    with_se
                        .iter()
                        .map(|&(_, kk)| {
                            let d = (cov_of(ii, ii) * cov_of(kk, kk)).sqrt();
                            if ii == kk {
                                1.0
                            } else if d > 0.0 && d.is_finite() {
                                (0.5 * (cov_of(ii, kk) + cov_of(kk, ii)) / d).clamp(-1.0, 1.0)
                            } else {
                                0.0
                            }
                        })
                        .collect()
                })
                .collect(),
        };
        if !groups.is_empty() {
            ill = Some(IllConditioning {
                condition_number: cond,
                groups,
            });
        }
    }
    let at_bound: Vec<String> = (0..p)
        .filter(|&i| {
            !held[i]
                && !hold
                    .iter()
                    .any(|h| *h == format!("{}.{}", lay.names[i].0, lay.names[i].1))
        })
        .filter(|&i| {
            let span = (lay.upper[i] - lay.lower[i]).abs();
            let tol = 1e-9
                * theta[i].abs().max(1.0).min(if span.is_finite() {
                    span
                } else {
                    f64::INFINITY
                });
            (theta[i] - lay.lower[i]).abs() <= tol || (lay.upper[i] - theta[i]).abs() <= tol
        })
        // A parameter whose prior already sat at the bound (a joint without this effect)
        // is not news.
        .filter(|&i| (theta[i] - nominal[i]).abs() > 0.0 || se[i].is_some())
        .map(|i| format!("{}.{}", lay.names[i].0, lay.names[i].1))
        .collect();
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
    // RMSE and SSR over every row given (the fit may have used a stride of them).
    let (ssr, m) = if rows.len() == all_rows.len() || !full_ssr {
        (ssr, m)
    } else {
        // A block of rows at a time; the sum adds the same terms in the same order.
        let mut ssr: f64 = std::iter::empty::<f64>().sum();
        let mut m = 0;
        for block in all_rows.chunks(crate::identify::columns::BLOCK_ROWS) {
            residuals(prep, model, block, &mut r);
            for x in &r {
                ssr += x * x;
            }
            m += r.len();
        }
        (ssr, m)
    };
    Ok(FitResult {
        params,
        rmse: (ssr / m.max(1) as f64).sqrt(),
        ssr,
        residuals: m,
        condition_number: cond,
        ill_conditioned: ill,
        at_bound,
        hac_block_rows: hac_rows,
        correlation,
    })
}

#[cfg(test)]
mod tests {
    use super::gram;

    /// `JᵀJ` from the strided view equals `JᵀJ` from an owned transpose bit for bit, on small
    /// (nalgebra's own loops) and large (matrixmultiply's packed `gemm`) Jacobians.
    #[test]
    fn the_normal_equations_from_a_strided_view_equal_those_of_a_transposed_copy_bit_for_bit() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        for (m, p) in [(0, 3), (1, 1), (5, 3), (40, 7), (1200, 36), (4999, 13)] {
            let rows: Vec<f64> = (0..m * p)
                .map(|_| rng.gen_range(-1.0..1.0) * 10f64.powi(rng.gen_range(-6..6)))
                .collect();
            let jt = nalgebra::DMatrix::from_vec(p, m, rows);
            let want = &jt * jt.transpose();
            let got = gram(&jt);
            assert_eq!(got.shape(), (p, p));
            for (a, b) in got.iter().zip(want.iter()) {
                assert_eq!(a.to_bits(), b.to_bits(), "{m} × {p}");
            }
        }
    }
}
