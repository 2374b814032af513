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
pub(crate) const FIT_ROWS_MAX: usize = 20_000;

/// The rows used for fitting: all of `rows`, or an even stride of at most [`FIT_ROWS_MAX`].
pub(crate) fn fit_rows(rows: &[usize]) -> Vec<usize> {
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
    let (tau, sig) = base_signal(prep, model, rows);
    let lin = Linearisation {
        prep,
        lay,
        theta,
        rows,
        tau,
        sig,
    };
    let mut o = 0;
    for (name, &pe) in lay.effects.iter().zip(&lay.sizes) {
        let pos = model
            .position(name)
            .ok_or_else(|| Error::Invalid(format!("effect `{name}` is not in the model")))?;
        let vals = model.values(name)?;
        let stage = model.effect(name)?.stage();
        let block = Block { name, pos, o, pe };
        if stage != Stage::Torque {
            lin.motor_columns(model, &block, &vals, jac)?;
        } else {
            lin.torque_columns(model, &block, &vals, jac)?;
        }
        o += pe;
    }
    Ok(())
}

/// Torque (row-major `rows.len() × n`) and signal (`rows.len() × channels`) at `rows`.
fn base_signal(prep: &Prepared, model: &Model, rows: &[usize]) -> (Vec<f64>, Vec<f64>) {
    let n = model.n;
    let ch = prep.log.channels;
    let mut tau = vec![0.0; rows.len() * n];
    let mut sig = vec![0.0; rows.len() * ch];
    for (r, &k) in rows.iter().enumerate() {
        prep.torque_row_kept(model, k, &[], &mut tau[r * n..(r + 1) * n]);
        model.signal_from_torque(
            prep.log.kind,
            &tau[r * n..(r + 1) * n],
            prep.rates(k, true).qd(),
            &mut sig[r * ch..(r + 1) * ch],
        );
    }
    (tau, sig)
}

/// One effect's parameters in the Jacobian: its name, position in the model, first column
/// and parameter count.
struct Block<'a> {
    name: &'a str,
    pos: usize,
    o: usize,
    pe: usize,
}

/// The point a Jacobian is taken at: the torque and signal at the fitted rows.
struct Linearisation<'a> {
    prep: &'a Prepared<'a>,
    lay: &'a Layout,
    theta: &'a [f64],
    rows: &'a [usize],
    tau: Vec<f64>,
    sig: Vec<f64>,
}

impl Linearisation<'_> {
    /// Forward-difference step of parameter `i` (backwards where forwards would leave its
    /// range).
    fn step(&self, i: usize) -> f64 {
        let mut h = 1e-5 * self.theta[i].abs().max(1e-2);
        if self.theta[i] + h > self.lay.upper[i] {
            h = -h;
        }
        h
    }

    /// Columns of a motor or supply effect: forward differences of the motor model at the
    /// same torque.
    fn motor_columns(
        &self,
        model: &mut Model,
        b: &Block,
        vals: &[f64],
        jac: &mut [f64],
    ) -> Result<()> {
        let n = model.n;
        let ch = self.prep.log.channels;
        let p = self.theta.len();
        let mut s2 = [0.0; MAX_DOF];
        for li in 0..b.pe {
            let i = b.o + li;
            let h = self.step(i);
            let mut v = vals.to_vec();
            v[li] += h;
            model.set_values(b.name, &v)?;
            for (r, &k) in self.rows.iter().enumerate() {
                model.signal_from_torque(
                    self.prep.log.kind,
                    &self.tau[r * n..(r + 1) * n],
                    self.prep.rates(k, true).qd(),
                    &mut s2[..ch],
                );
                for c in 0..ch {
                    jac[(r * ch + c) * p + i] = (s2[c] - self.sig[r * ch + c]) / h;
                }
            }
            model.set_values(b.name, vals)?;
        }
        Ok(())
    }

    /// Columns of a torque effect: its torque derivatives, carried to current and power logs
    /// through a forward difference of the motor model.
    fn torque_columns(
        &self,
        model: &Model,
        b: &Block,
        vals: &[f64],
        jac: &mut [f64],
    ) -> Result<()> {
        let n = model.n;
        let ch = self.prep.log.channels;
        let kind = self.prep.log.kind;
        let p = self.theta.len();
        let pe = b.pe;
        let td = self.torque_derivative(model.effect(b.name)?, b, vals, n)?;
        let mut s2 = [0.0; MAX_DOF];
        let mut t2 = [0.0; MAX_DOF];
        let mut d = vec![0.0; n * pe]; // dτ_j/dθ_li at j * pe + li
        for (r, &k) in self.rows.iter().enumerate() {
            td.at(self.prep, model, b.pos, k, &mut d);
            let tr = &self.tau[r * n..(r + 1) * n];
            for li in 0..pe {
                let i = b.o + li;
                if kind == crate::identify::SignalKind::Torque {
                    for j in 0..n {
                        jac[(r * ch + j) * p + i] = d[j * pe + li];
                    }
                } else {
                    let h = td.hs[li];
                    for j in 0..n {
                        t2[j] = tr[j] + h * d[j * pe + li];
                    }
                    let rates = self.prep.rates(k, true);
                    model.signal_from_torque(kind, &t2[..n], rates.qd(), &mut s2[..ch]);
                    for c in 0..ch {
                        jac[(r * ch + c) * p + i] = (s2[c] - self.sig[r * ch + c]) / h;
                    }
                }
            }
        }
        Ok(())
    }

    /// How a torque effect's torque moves with its parameters: by its regressor when it is
    /// linear, else through copies with one parameter stepped each.
    fn torque_derivative<'e>(
        &self,
        eff: &'e dyn Effect,
        b: &Block,
        vals: &[f64],
        n: usize,
    ) -> Result<TorqueDerivative<'e>> {
        let pe = b.pe;
        let prep = self.prep;
        let hs: Vec<f64> = (0..pe).map(|li| self.step(b.o + li)).collect();
        // Perturbed copies for effects without a regressor.
        let mut y = vec![0.0; n * pe];
        let linear = self.rows.first().is_none_or(|&k| {
            let r = prep.rates(k, true);
            eff.regressor(prep.log.traj.q(k), r.qd(), r.qdd(), &mut y)
        });
        let mut copies: Vec<Box<dyn Effect>> = Vec::new();
        if !linear {
            for li in 0..pe {
                let mut c = eff.clone_box();
                let mut v = vals.to_vec();
                v[li] += hs[li];
                c.set_values(&v)?;
                copies.push(c);
            }
        }
        Ok(TorqueDerivative {
            eff,
            hs,
            linear,
            copies,
        })
    }
}

/// A torque effect's torque derivatives: its regressor when linear, else forward differences
/// through copies with one parameter stepped each.
struct TorqueDerivative<'e> {
    eff: &'e dyn Effect,
    /// Forward-difference step of each parameter.
    hs: Vec<f64>,
    linear: bool,
    copies: Vec<Box<dyn Effect>>,
}

impl TorqueDerivative<'_> {
    /// `dτ_j/dθ_li` at sample `k` into `d` (at `j * pe + li`): the prepared regressor row
    /// where there is one, else the effect's regressor, else forward differences.
    fn at(&self, prep: &Prepared, model: &Model, pos: usize, k: usize, d: &mut [f64]) {
        let n = model.n;
        let pe = self.hs.len();
        let r = prep.rates(k, true);
        let (q, qd, qdd) = (prep.log.traj.q(k), r.qd(), r.qdd());
        if prep.regressor_row(model, pos, k, d) {
        } else if self.linear {
            self.eff.regressor(q, qd, qdd, d);
        } else {
            let mut base = [0.0; MAX_DOF];
            let mut t2 = [0.0; MAX_DOF];
            base[..n].iter_mut().for_each(|v| *v = 0.0);
            self.eff.add_torque(q, qd, qdd, &mut base[..n]);
            for (li, c) in self.copies.iter().enumerate() {
                t2[..n].iter_mut().for_each(|v| *v = 0.0);
                c.add_torque(q, qd, qdd, &mut t2[..n]);
                for j in 0..n {
                    d[j * pe + li] = (t2[j] - base[j]) / self.hs[li];
                }
            }
        }
    }
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
pub(crate) const HAC_BLOCK_CORRELATION_TIMES: f64 = 16.0;

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

impl Layout {
    /// The layout of `effects` (switched on here) and their current values.
    fn of(model: &mut Model, effects: &[&'static str]) -> Result<(Layout, Vec<f64>)> {
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
        Ok((lay, theta))
    }

    /// `effect.param` of parameter `i`.
    fn qualified(&self, i: usize) -> String {
        format!("{}.{}", self.names[i].0, self.names[i].1)
    }
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
pub(crate) fn fit_holding(
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
    let (lay, mut theta) = Layout::of(model, effects)?;
    let nominal = theta.clone();
    let p = theta.len();
    let cons = Constraints::new(model, &lay, hold, &mut theta);
    if !cons.ties.is_empty() || cons.payload_held.is_some() {
        set_all(model, &lay, &theta)?;
    }
    let mut r = Vec::new();
    residuals(prep, model, rows, &mut r);
    let m = r.len();
    let ssr = sum_of_squares(&r);
    let pb = Problem {
        prep,
        lay: &lay,
        cons: &cons,
        rows,
    };
    let mut sol = Solution {
        theta,
        r,
        ssr,
        lambda: 1e-9,
        jac: vec![0.0; m * p],
        rp: Vec::new(),
    };
    pb.minimise(model, &mut sol)?;
    let spread = if p > 0 {
        pb.spread(model, &mut sol)?
    } else {
        Spread::none(p)
    };
    let at_bound = pb.at_bound(hold, &sol.theta, &nominal, &spread.se);
    let params = (0..p)
        .map(|i| FittedParam {
            effect: lay.names[i].0.clone(),
            name: lay.names[i].1.clone(),
            unit: lay.names[i].2.clone(),
            nominal: nominal[i],
            value: sol.theta[i],
            std_error: spread.se[i],
        })
        .collect();
    // RMSE and SSR over every row given (the fit may have used a stride of them).
    let (ssr, m) = if rows.len() == all_rows.len() || !full_ssr {
        (sol.ssr, m)
    } else {
        ssr_over(prep, model, all_rows, &mut sol.r)
    };
    Ok(FitResult {
        params,
        rmse: (ssr / m.max(1) as f64).sqrt(),
        ssr,
        residuals: m,
        condition_number: spread.cond,
        ill_conditioned: spread.ill,
        at_bound,
        hac_block_rows: spread.hac_rows,
        correlation: spread.correlation,
    })
}

/// The sum of squares of `r`.
fn sum_of_squares(r: &[f64]) -> f64 {
    r.iter().map(|x| x * x).sum::<f64>()
}

/// Sum of squared residuals and their count over every row of `all_rows`, a block of rows at
/// a time (the sum adds the same terms in the same order as over all rows at once).
fn ssr_over(prep: &Prepared, model: &Model, all_rows: &[usize], r: &mut Vec<f64>) -> (f64, usize) {
    let mut ssr: f64 = std::iter::empty::<f64>().sum();
    let mut m = 0;
    for block in all_rows.chunks(crate::identify::columns::BLOCK_ROWS) {
        residuals(prep, model, block, r);
        for x in r.iter() {
            ssr += x * x;
        }
        m += r.len();
    }
    (ssr, m)
}

/// How the fitted parameters move together: tied pairs, held parameters and the payload's
/// held inertia.
struct Constraints {
    /// Tied pairs `(leader, follower)`: with symmetric Coulomb `f_c−[j]` follows `f_c+[j]`.
    ties: Vec<(usize, usize)>,
    /// Parameters that are not fitted.
    held: Vec<bool>,
    /// The payload with the positions of `dm` and `dI_xx`, when its inertia is held.
    payload_held: Option<(crate::effects::Payload, usize, usize)>,
}

impl Constraints {
    /// The constraints of `lay` with `hold` held; tied pairs of `theta` start from their mean
    /// (unless the leader is held, which then leads) and a held payload inertia follows.
    fn new(model: &Model, lay: &Layout, hold: &[String], theta: &mut [f64]) -> Constraints {
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
        for &(a, b) in &ties {
            let ha = hold.iter().any(|h| *h == lay.qualified(a));
            if ha {
                theta[b] = theta[a];
            } else {
                let v = 0.5 * (theta[a] + theta[b]);
                theta[a] = v;
                theta[b] = v;
            }
        }
        let cons = Constraints {
            ties,
            held,
            payload_held: Self::payload_held(model, lay),
        };
        if cons.payload_held.is_some() {
            cons.follow(theta);
        }
        cons
    }

    /// The payload's inertia held (only its mass and centre of mass fitted): its inertia about
    /// its own centre of mass stays the prior's, so `dI_*` follow `dm` and `dh_*`.
    fn payload_held(
        model: &Model,
        lay: &Layout,
    ) -> Option<(crate::effects::Payload, usize, usize)> {
        if model.payload_inertia {
            return None;
        }
        let find = |n: &str| lay.names.iter().position(|x| x.0 == "payload" && x.1 == n);
        match (
            model.effects.typed::<crate::effects::Payload>("payload"),
            find("dm"),
            find("dI_xx"),
        ) {
            (Some(pl), Some(dm), Some(di)) => Some((pl.clone(), dm, di)),
            _ => None,
        }
    }

    /// Followers take their leader's value and a held payload inertia follows its mass and
    /// first moment.
    fn follow(&self, th: &mut [f64]) {
        for &(a, b) in &self.ties {
            th[b] = th[a];
        }
        if let Some((pl, dm, di)) = &self.payload_held {
            let d = pl.held_inertia_error(th[*dm], [th[dm + 1], th[dm + 2], th[dm + 3]]);
            th[*di..di + 6].copy_from_slice(&d);
        }
    }

    /// A follower's Jacobian column is added to its leader's and zeroed.
    fn tie_cols(&self, jac: &mut [f64], rows_m: usize, p: usize) {
        for r in 0..rows_m {
            for &(a, b) in &self.ties {
                jac[r * p + a] += jac[r * p + b];
                jac[r * p + b] = 0.0;
            }
        }
    }

    /// The chain rule through `dI = P(Δh)/m` (`P(d) = |d|² 1 − d dᵀ`, `m = m₀ + Δm`): the
    /// columns of `dm` and `dh_*` gain the held inertia's columns times its derivatives (near a
    /// light load the inertia follows the first moment strongly).
    fn payload_chain(&self, jac: &mut [f64], rows_m: usize, th: &[f64]) {
        let Some((pl, dm, di)) = &self.payload_held else {
            return;
        };
        let p = th.len();
        let (dm, di) = (*dm, *di);
        let der = pl.held_inertia_derivatives(th[dm], [th[dm + 1], th[dm + 2], th[dm + 3]]);
        for r in 0..rows_m {
            let row = &mut jac[r * p..(r + 1) * p];
            for (c, dc) in der.iter().enumerate() {
                let add: f64 = (0..6).map(|k| row[di + k] * dc[k]).sum();
                row[dm + c] += add;
            }
        }
    }
}

/// What a fit works on: the log, the parameter layout, its constraints and the fitted rows.
struct Problem<'a> {
    prep: &'a Prepared<'a>,
    lay: &'a Layout,
    cons: &'a Constraints,
    rows: &'a [usize],
}

/// The state of a fit: parameters, residuals, their sum of squares, the damping and the
/// Jacobian's and trial residuals' buffers.
struct Solution {
    theta: Vec<f64>,
    r: Vec<f64>,
    ssr: f64,
    lambda: f64,
    jac: Vec<f64>,
    rp: Vec<f64>,
}

/// The spread of a fit: standard errors, conditioning and correlation.
struct Spread {
    se: Vec<Option<f64>>,
    hac_rows: usize,
    cond: f64,
    ill: Option<IllConditioning>,
    correlation: Correlation,
}

impl Spread {
    /// No spread: no standard errors, condition number 1.
    fn none(p: usize) -> Spread {
        Spread {
            se: vec![None; p],
            hac_rows: 1,
            cond: 1.0,
            ill: None,
            correlation: Correlation::default(),
        }
    }
}

impl Problem<'_> {
    /// The constrained Jacobian at `sol.theta` as its transpose (`p × m`, column-major); the
    /// caller hands its data back to `sol.jac`.
    fn jacobian_t(&self, model: &mut Model, sol: &mut Solution) -> Result<nalgebra::DMatrix<f64>> {
        let p = sol.theta.len();
        let m = sol.r.len();
        jacobian(
            self.prep,
            model,
            self.lay,
            &sol.theta,
            self.rows,
            &mut sol.jac,
        )?;
        self.cons.tie_cols(&mut sol.jac, m, p);
        self.cons.payload_chain(&mut sol.jac, m, &sol.theta);
        // The row-major Jacobian is its transpose, column-major: no copy.
        Ok(nalgebra::DMatrix::from_vec(
            p,
            m,
            std::mem::take(&mut sol.jac),
        ))
    }

    /// Levenberg–Marquardt iterations (at most 40) until a step no longer improves the fit;
    /// the model keeps the solution.
    fn minimise(&self, model: &mut Model, sol: &mut Solution) -> Result<()> {
        let p = sol.theta.len();
        for _iter in 0..40 {
            if p == 0 {
                break;
            }
            let jt = self.jacobian_t(model, sol)?;
            let jtj = gram(&jt);
            let mut g = &jt * nalgebra::DVector::from_column_slice(&sol.r);
            sol.jac = jt.data.into();
            let jtj = self.freeze(jtj, &mut g);
            let improved = self.damped_step(model, sol, &jtj, &g)?;
            set_all(model, self.lay, &sol.theta)?;
            if !improved {
                break;
            }
        }
        Ok(())
    }

    /// The normal equations with held and unexcited columns frozen (identity row and column,
    /// no gradient): those parameters stay where they are.
    fn freeze(
        &self,
        jtj: nalgebra::DMatrix<f64>,
        g: &mut nalgebra::DVector<f64>,
    ) -> nalgebra::DMatrix<f64> {
        let p = g.len();
        let maxdiag = (0..p).map(|i| jtj[(i, i)]).fold(0.0, f64::max);
        // Columns with no excitation stay where they are.
        let frozen: Vec<bool> = (0..p)
            .map(|i| self.cons.held[i] || jtj[(i, i)] <= 1e-12 * maxdiag)
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
        jtj
    }

    /// Up to twelve damped steps, the damping growing tenfold after each that fails; the first
    /// that lowers the sum of squares is taken. Whether the fit improved by more than 1e-10
    /// relative.
    fn damped_step(
        &self,
        model: &mut Model,
        sol: &mut Solution,
        jtj: &nalgebra::DMatrix<f64>,
        g: &nalgebra::DVector<f64>,
    ) -> Result<bool> {
        let p = sol.theta.len();
        for _try in 0..12 {
            let mut a = jtj.clone();
            for i in 0..p {
                let d = jtj[(i, i)].max(1e-30);
                a[(i, i)] += sol.lambda * d + 1e-14 * d;
            }
            let step = match a.clone().cholesky() {
                Some(c) => c.solve(&(-g)),
                None => {
                    sol.lambda *= 10.0;
                    continue;
                }
            };
            let mut th: Vec<f64> = sol
                .theta
                .iter()
                .zip(step.iter())
                .map(|(a, b)| a + b)
                .collect();
            for (i, t) in th.iter_mut().enumerate() {
                *t = t.clamp(self.lay.lower[i], self.lay.upper[i]);
            }
            self.cons.follow(&mut th);
            set_all(model, self.lay, &th)?;
            residuals(self.prep, model, self.rows, &mut sol.rp);
            let s = sum_of_squares(&sol.rp);
            if s < sol.ssr {
                let rel = (sol.ssr - s) / sol.ssr.max(1e-300);
                sol.theta = th;
                std::mem::swap(&mut sol.r, &mut sol.rp);
                sol.ssr = s;
                sol.lambda = (sol.lambda / 10.0).max(1e-12);
                return Ok(rel > 1e-10);
            }
            sol.lambda *= 10.0;
        }
        Ok(false)
    }

    /// Covariance and conditioning at the solution: standard errors, condition number,
    /// near-null groups and correlation.
    fn spread(&self, model: &mut Model, sol: &mut Solution) -> Result<Spread> {
        let p = sol.theta.len();
        let jt = self.jacobian_t(model, sol)?;
        let jtj = gram(&jt);
        sol.jac = jt.data.into();
        let m = sol.r.len();
        let norms = self.column_norms(&jtj, &sol.theta, m);
        let con = Conditioning::new(self.lay, &self.cons.held, &jtj, &norms);
        let pa = con.act.len();
        let sigma2 = sol.ssr / (m.saturating_sub(pa).max(1) as f64);
        let weak: Vec<bool> = (0..p)
            .map(|i| {
                self.cons.held[i]
                    || norms[i] == 0.0
                    || con
                        .groups
                        .iter()
                        .any(|g| g.contains(&self.lay.qualified(i)))
            })
            .collect();
        let cov = con.pseudo_inverse();
        let hac_rows = hac_block_rows(&sol.r, self.prep.log.channels);
        let (hac, estimated) = self.sandwich(sol, &con.act, &norms, &cov, hac_rows);
        let mut se = vec![None; p];
        for (ii, &i) in con.act.iter().enumerate() {
            if !weak[i] && norms[i] > 0.0 {
                let v = (sigma2 * cov[(ii, ii)]).max(hac[(ii, ii)]).max(0.0);
                se[i] = Some(v.sqrt() / norms[i]);
            }
        }
        for &(a, bb) in &self.cons.ties {
            se[bb] = se[a];
        }
        // The correlation of the parameters with a standard error, from the covariance whose
        // diagonal the standard errors came from (the sandwich one when it was estimated; a
        // tied parameter moves with its twin).
        let cov_of = |ii: usize, kk: usize| {
            if estimated {
                hac[(ii, kk)]
            } else {
                sigma2 * cov[(ii, kk)]
            }
        };
        let correlation = self.correlation(&se, &con.act, &cov_of);
        let ill = if con.groups.is_empty() {
            None
        } else {
            Some(IllConditioning {
                condition_number: con.number,
                groups: con.groups,
            })
        };
        Ok(Spread {
            se,
            hac_rows,
            cond: con.number,
            ill,
            correlation,
        })
    }

    /// Norm of each Jacobian column (`NaN` for a held one); a column whose effect on the
    /// signal is below 1e-6 of the signal's RMS (for the parameter at max(|θ|, 1)) is not
    /// excited: treated as zero.
    fn column_norms(&self, jtj: &nalgebra::DMatrix<f64>, theta: &[f64], m: usize) -> Vec<f64> {
        let ch = self.prep.log.channels;
        let yrms = (self
            .rows
            .iter()
            .flat_map(|&k| self.prep.log.y[k * ch..(k + 1) * ch].iter())
            .map(|v| v * v)
            .sum::<f64>()
            / m.max(1) as f64)
            .sqrt();
        (0..theta.len())
            .map(|i| {
                if self.cons.held[i] {
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
            .collect()
    }

    /// Autocorrelation-consistent (sandwich) covariance of the active columns: the scores
    /// `g_t = J_tᵀ r_t` of each row (normalised active columns) summed over overlapping blocks
    /// of `hac_rows` rows, `Ω = (T / B) · mean_s(G_s G_sᵀ)`, `Cov = S⁺ Ω S⁺`, widened for the
    /// estimate's degrees of freedom; with whether there was a block to estimate it from.
    fn sandwich(
        &self,
        sol: &Solution,
        act: &[usize],
        norms: &[f64],
        cov: &nalgebra::DMatrix<f64>,
        hac_rows: usize,
    ) -> (nalgebra::DMatrix<f64>, bool) {
        let pa = act.len();
        let ch = self.prep.log.channels;
        let t_rows = sol.r.len() / ch.max(1);
        let prefix = score_prefix(sol, ch, act, norms);
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
        let hac = (cov * omega * cov) * (t975 / z).powi(2);
        (hac, windows > 0 && t_rows > 0)
    }

    /// Correlation of the parameters that have a standard error, from the covariance `cov_of`
    /// of the active columns (a tied parameter takes its leader's column).
    fn correlation(
        &self,
        se: &[Option<f64>],
        act: &[usize],
        cov_of: &dyn Fn(usize, usize) -> f64,
    ) -> Correlation {
        let col = |i: usize| {
            let i = self.cons.ties.iter().find(|t| t.1 == i).map_or(i, |t| t.0);
            act.iter().position(|&a| a == i)
        };
        let with_se: Vec<(usize, usize)> = (0..se.len())
            .filter(|&i| se[i].is_some())
            .filter_map(|i| col(i).map(|ii| (i, ii)))
            .collect();
        Correlation {
            params: with_se
                .iter()
                .map(|&(i, _)| self.lay.qualified(i))
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
        }
    }

    /// Fitted (not held) parameters that ended at a bound of their range, leaving out those
    /// whose prior already sat there (a joint without this effect is not news).
    fn at_bound(
        &self,
        hold: &[String],
        theta: &[f64],
        nominal: &[f64],
        se: &[Option<f64>],
    ) -> Vec<String> {
        let lay = self.lay;
        (0..theta.len())
            .filter(|&i| !self.cons.held[i] && !hold.iter().any(|h| *h == lay.qualified(i)))
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
            .map(|i| lay.qualified(i))
            .collect()
    }
}

/// Running sums over the rows of the scores `J_tᵀ r_t` on the normalised active columns (the
/// first is zero), for block sums by difference.
fn score_prefix(
    sol: &Solution,
    ch: usize,
    act: &[usize],
    norms: &[f64],
) -> Vec<nalgebra::DVector<f64>> {
    let p = sol.theta.len();
    let t_rows = sol.r.len() / ch.max(1);
    let mut prefix = vec![nalgebra::DVector::<f64>::zeros(act.len()); t_rows + 1];
    for t in 0..t_rows {
        let mut g = prefix[t].clone();
        for c in 0..ch {
            let row = t * ch + c;
            let res = sol.r[row];
            for (ii, &i) in act.iter().enumerate() {
                if norms[i] > 0.0 {
                    g[ii] += sol.jac[row * p + i] / norms[i] * res;
                }
            }
        }
        prefix[t + 1] = g;
    }
    prefix
}

/// The conditioning of the active (not held) columns of a fit.
struct Conditioning {
    /// The active columns.
    act: Vec<usize>,
    /// Eigen-decomposition of the column-normalised `JᵀJ` on the active columns.
    eig: nalgebra::SymmetricEigen<f64, nalgebra::Dyn>,
    /// Eigenvalues at or below this span the near-null space.
    cut: f64,
    /// Condition number of the column-normalised Jacobian (∞ when a column is zero).
    number: f64,
    /// Parameters the data cannot tell apart: unexcited ones alone, then one group per
    /// near-null direction.
    groups: Vec<Vec<String>>,
}

impl Conditioning {
    /// The conditioning of `jtj` on the columns not `held`, normalised by `norms`.
    fn new(
        lay: &Layout,
        held: &[bool],
        jtj: &nalgebra::DMatrix<f64>,
        norms: &[f64],
    ) -> Conditioning {
        // The analysis runs on the active (not held) columns `act`.
        let act: Vec<usize> = (0..held.len()).filter(|&i| !held[i]).collect();
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
        let number = if zero_col || emin <= 0.0 {
            f64::INFINITY
        } else {
            (emax / emin).sqrt()
        };
        let cut = emax / (CONDITION_LIMIT * CONDITION_LIMIT);
        let mut groups: Vec<Vec<String>> = act
            .iter()
            .filter(|&&i| norms[i] == 0.0)
            .map(|&i| vec![lay.qualified(i)])
            .collect();
        for (c, &ev) in eig.eigenvalues.iter().enumerate() {
            if ev <= cut {
                let v = eig.eigenvectors.column(c);
                let g: Vec<String> = act
                    .iter()
                    .enumerate()
                    .filter(|&(ii, &i)| norms[i] > 0.0 && v[ii].abs() > 0.2)
                    .map(|(_, &i)| lay.qualified(i))
                    .collect();
                if !g.is_empty() && !groups.contains(&g) {
                    groups.push(g);
                }
            }
        }
        Conditioning {
            act,
            eig,
            cut,
            number,
            groups,
        }
    }

    /// Covariance (up to `σ²`) by the pseudo-inverse on the well-determined subspace.
    fn pseudo_inverse(&self) -> nalgebra::DMatrix<f64> {
        let pa = self.act.len();
        let mut cov = nalgebra::DMatrix::<f64>::zeros(pa, pa);
        for (c, &ev) in self.eig.eigenvalues.iter().enumerate() {
            if ev > self.cut {
                let v = self.eig.eigenvectors.column(c);
                cov += (v * v.transpose()) / ev;
            }
        }
        cov
    }
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
