//! `rigid_body`: errors of the links' own inertial parameters, identified as base parameters
//! (the classical linear regressor of the rigid-body dynamics reduced by QR with column
//! pivoting; Gautier & Khalil 1990, Khalil & Dombre 2002 ch. 12; cf. pinocchio
//! `computeJointTorqueRegressor`; [`crate::dynamics::rnea_regressor`]).
//!
//! RNEA is linear in the ten standard parameters of every moving link
//! (`m, h = m c, I` about the joint origin, in the joint frame; [`DynModel::link_params`]):
//! `τ = W(q, q̇, q̈) π`. Some columns of `W` are zero (parameters the chain cannot move, e.g.
//! most of link 1's) and some are combinations of others; the *base parameters* are the
//! independent set. They are found once per robot: `W` at 100 seeded random states, columns
//! normalised, QR with column pivoting (nalgebra `col_piv_qr`); the rank `r` counts
//! `|R_kk| > 10⁻⁸ |R_00|`, the first `r` pivoted columns are the independent standard
//! parameters, and each base parameter is its independent standard parameter plus the
//! combination `K = W₁⁺ W₂` of the dependent ones ([`RigidBody::combination`]).
//!
//! The effect's parameters are the *errors* `δθ_b` of the base parameters (named after their
//! independent standard parameter, e.g. `L3.m` kg, `L2.hx` kg·m, `L1.Izz` kg·m²), zero in the
//! nominal robot. Torque `τ = W₁ δθ_b`, evaluated as one RNEA of a model whose only
//! parameters are `δθ_b` on the independent entries (exact by linearity). Regressor: the
//! independent columns `W₁` of [`crate::dynamics::rnea_regressor`].
//! So a wrong link mass or centre of mass is named as such and not absorbed by `balancer` or
//! `payload`.

use super::{check_values, BuildContext, Effect, ParamSpec};
use crate::dynamics::{rnea, rnea_regressor, DynData, DynModel, DynOptions, MAX_DOF};
use crate::error::Result;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;

/// Bound on each base-parameter error, SI (kg, kg·m, kg·m²).
pub const RIGID_BODY_MAX: f64 = 1e4;
/// Random states used to find the base parameters.
const BASE_SAMPLES: usize = 100;
/// Relative threshold on `|R_kk|` for the rank.
const RANK_TOL: f64 = 1e-8;

const PARAM_NAMES: [(&str, &str); 10] = [
    ("m", "kg"),
    ("hx", "kg·m"),
    ("hy", "kg·m"),
    ("hz", "kg·m"),
    ("Ixx", "kg·m²"),
    ("Iyy", "kg·m²"),
    ("Izz", "kg·m²"),
    ("Ixy", "kg·m²"),
    ("Ixz", "kg·m²"),
    ("Iyz", "kg·m²"),
];

/// The structure shared by copies: the base-parameter set of one robot.
#[derive(Debug)]
struct Base {
    /// The nominal rigid body (payload merged, no armature).
    nominal: DynModel,
    /// (link, standard parameter) of each base parameter.
    independent: Vec<(usize, usize)>,
    /// Each base parameter in words: its independent standard parameter plus the dependent
    /// ones it absorbs.
    combination: Vec<String>,
}

/// Errors of the base inertial parameters.
#[derive(Debug, Clone)]
pub struct RigidBody {
    /// `δθ_b`, SI (units in [`Effect::params`]).
    pub delta: Vec<f64>,
    base: Arc<Base>,
    /// The model whose only parameters are `δθ_b` (torque = its RNEA).
    delta_model: DynModel,
}

/// Registry entry: the base parameters of the robot's rigid body (payload merged), no error.
pub(crate) fn build(ctx: &BuildContext) -> Result<Box<dyn Effect>> {
    Ok(Box::new(RigidBody::new(ctx.robot)?))
}

fn std_name(link: usize, p: usize) -> String {
    format!("L{}.{}", link + 1, PARAM_NAMES[p].0)
}

impl RigidBody {
    /// The base parameters of `robot` (payload merged into the last link). Error: the robot
    /// lacks inertials.
    pub fn new(robot: &crate::robot::RobotModel) -> Result<Self> {
        let nominal = DynModel::new(
            robot,
            DynOptions {
                payload: true,
                armature: false,
            },
        )?;
        let n = nominal.dof();
        let ncol = 10 * n;
        // W at seeded random states within the joint limits.
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let rows = BASE_SAMPLES * n;
        let mut w = nalgebra::DMatrix::<f64>::zeros(rows, ncol);
        let mut d = DynData::default();
        let mut ys = vec![0.0; n * ncol];
        for s in 0..BASE_SAMPLES {
            let mut q = [0.0; MAX_DOF];
            let mut qd = [0.0; MAX_DOF];
            let mut qdd = [0.0; MAX_DOF];
            for (j, jt) in robot.joints.iter().enumerate().take(n) {
                let (lo, hi) = if jt.upper > jt.lower {
                    (jt.lower, jt.upper)
                } else {
                    (-3.0, 3.0)
                };
                q[j] = rng.gen_range(lo..=hi);
                qd[j] = rng.gen_range(-1.5..=1.5);
                qdd[j] = rng.gen_range(-3.0..=3.0);
            }
            rnea_regressor(&nominal, &mut d, &q[..n], &qd[..n], &qdd[..n], &mut ys)?;
            for j in 0..n {
                for c in 0..ncol {
                    w[(s * n + j, c)] = ys[j * ncol + c];
                }
            }
        }
        let norms: Vec<f64> = (0..ncol).map(|c| w.column(c).norm()).collect();
        let nmax = norms.iter().cloned().fold(0.0, f64::max);
        let nonzero: Vec<usize> = (0..ncol).filter(|&c| norms[c] > 1e-9 * nmax).collect();
        let mut wn = nalgebra::DMatrix::<f64>::zeros(rows, nonzero.len());
        for (k, &c) in nonzero.iter().enumerate() {
            wn.set_column(k, &(w.column(c) / norms[c]));
        }
        let qr = wn.clone().col_piv_qr();
        let r = qr.r();
        let mut order = nalgebra::DMatrix::<f64>::from_fn(1, nonzero.len(), |_, k| k as f64);
        qr.p().permute_columns(&mut order);
        let r00 = r[(0, 0)].abs();
        let rank = (0..r.nrows().min(r.ncols()))
            .take_while(|&k| r[(k, k)].abs() > RANK_TOL * r00)
            .count();
        let pick: Vec<usize> = (0..nonzero.len())
            .map(|k| nonzero[order[(0, k)] as usize])
            .collect();
        let (indep, dep) = pick.split_at(rank);
        // K = W₁⁺ W₂ in raw units: base_k = π_k + Σ K_kj π_j.
        let w1 = nalgebra::DMatrix::from_fn(rows, indep.len(), |i, k| w[(i, indep[k])]);
        let w2 = nalgebra::DMatrix::from_fn(rows, dep.len(), |i, k| w[(i, dep[k])]);
        let k = w1
            .clone()
            .svd(true, true)
            .solve(&w2, 1e-12)
            .unwrap_or_else(|_| nalgebra::DMatrix::zeros(indep.len(), dep.len()));
        let combination = indep
            .iter()
            .enumerate()
            .map(|(row, &c)| {
                let mut s = std_name(c / 10, c % 10);
                let mut terms: Vec<(f64, usize)> = dep
                    .iter()
                    .enumerate()
                    .filter(|(col, _)| k[(row, *col)].abs() > 1e-6)
                    .map(|(col, &dc)| (k[(row, col)], dc))
                    .collect();
                terms.sort_by(|a, b| b.0.abs().total_cmp(&a.0.abs()));
                for (v, dc) in terms.iter().take(4) {
                    s += &format!(" {:+.4}·{}", v, std_name(dc / 10, dc % 10));
                }
                if terms.len() > 4 {
                    s += &format!(" … ({} terms)", terms.len());
                }
                s
            })
            .collect();
        let independent: Vec<(usize, usize)> = indep.iter().map(|&c| (c / 10, c % 10)).collect();
        let delta = vec![0.0; independent.len()];
        let base = Arc::new(Base {
            nominal,
            independent,
            combination,
        });
        let delta_model = base.nominal.with_link_params(&[]);
        Ok(RigidBody {
            delta,
            base,
            delta_model,
        })
    }

    /// Each base parameter in words (its standard parameter and the dependent ones it
    /// absorbs, with coefficients), in parameter order.
    pub fn combination(&self) -> &[String] {
        &self.base.combination
    }

    fn rebuild(&mut self) {
        let n = self.base.nominal.dof();
        let mut p = vec![[0.0; 10]; n];
        for (v, &(l, k)) in self.delta.iter().zip(&self.base.independent) {
            p[l][k] = *v;
        }
        self.delta_model = self.base.nominal.with_link_params(&p);
    }
}

impl Effect for RigidBody {
    fn name(&self) -> &'static str {
        "rigid_body"
    }
    fn params(&self) -> Vec<ParamSpec> {
        self.base
            .independent
            .iter()
            .map(|&(l, k)| ParamSpec {
                name: std_name(l, k),
                unit: PARAM_NAMES[k].1,
                lower: -RIGID_BODY_MAX,
                upper: RIGID_BODY_MAX,
            })
            .collect()
    }
    fn values(&self) -> Vec<f64> {
        self.delta.clone()
    }
    fn set_values(&mut self, values: &[f64]) -> Result<()> {
        check_values(self.name(), &self.params(), values)?;
        self.delta.copy_from_slice(values);
        self.rebuild();
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn is_null(&self) -> bool {
        self.delta.iter().all(|v| *v == 0.0)
    }
    fn add_torque(&self, q: &[f64], qd: &[f64], qdd: &[f64], tau: &mut [f64]) {
        if self.is_null() {
            return;
        }
        let n = tau.len().min(MAX_DOF);
        let mut t = [0.0; MAX_DOF];
        let mut d = DynData::default();
        if rnea(&self.delta_model, &mut d, q, qd, qdd, &mut t[..n]).is_ok() {
            for (a, b) in tau.iter_mut().zip(&t[..n]) {
                *a += b;
            }
        }
    }
    fn regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64], y: &mut [f64]) -> bool {
        let p = self.base.independent.len();
        let n = self.base.nominal.dof();
        let ncol = 10 * n;
        let mut ys = [0.0; 10 * MAX_DOF * MAX_DOF];
        let mut d = DynData::default();
        if y.len() < n * p
            || rnea_regressor(&self.base.nominal, &mut d, q, qd, qdd, &mut ys[..n * ncol]).is_err()
        {
            return false;
        }
        for j in 0..n {
            for (c, &(l, k)) in self.base.independent.iter().enumerate() {
                y[j * p + c] = ys[j * ncol + 10 * l + k];
            }
        }
        true
    }
}
