//! `rigid_body`: errors of the links' own inertial parameters, identified as base parameters
//! (the classical linear regressor of the rigid-body dynamics reduced by QR with column
//! pivoting; Gautier & Khalil 1990, Khalil & Dombre 2002 ch. 12; cf. pinocchio
//! `computeJointTorqueRegressor`; [`crate::dynamics::rnea_regressor`]).
//!
//! RNEA is linear in the ten standard parameters of every moving link
//! (`m, h = m c, I` about the joint origin, in the joint frame; [`DynModel::link_params`]):
//! `τ = W(q, q̇, q̈) π`. Some columns of `W` are zero (parameters the chain cannot move, e.g.
//! most of link 1's) and some are combinations of others; the *base parameters* are the
//! independent set. They are found once per robot, on first use (an energy model, whose
//! rigid-body errors are zero, never needs them): `W` at 100 seeded random states, columns
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

use super::uncertain::at;
use super::{check_values, BuildContext, DrawPhase, Drawing, Effect, ParamSpec, Uncertainty};
use crate::dynamics::{rnea, rnea_regressor, DynData, DynModel, DynOptions, MAX_DOF};
use crate::error::Result;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;

/// Bound on each base-parameter error, SI (kg, kg·m, kg·m²).
pub(crate) const RIGID_BODY_MAX: f64 = 1e4;
/// Largest plausible change of a link's mass by a calibration, as a fraction of its nominal
/// mass (a stated bound, not a law of physics: CAD link masses are rarely off by more than a
/// few tens of per cent; a larger change is a different robot or an effect the catalogue
/// lacks, folded into the link by the fit).
pub(crate) const RIGID_BODY_MAX_MASS_CHANGE: f64 = 0.5;
/// Standard errors by which each fitted base-parameter error is pulled toward the nominal
/// before the plausibility checks (only violations the data insist on are reported).
pub(crate) const RIGID_BODY_PLAUSIBILITY_SIGMAS: f64 = 2.0;
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

/// The base-parameter set of one robot (found by [`Base::find`]).
#[derive(Debug, PartialEq)]
struct Base {
    /// (link, standard parameter) of each base parameter.
    independent: Vec<(usize, usize)>,
    /// Each base parameter in words: its independent standard parameter plus the dependent
    /// ones it absorbs.
    combination: Vec<String>,
    /// Orthonormal basis (columns) of the standard-parameter changes the torques cannot see
    /// (the null space of `W`), in the pseudo-inertia coordinates of [`j_coords`]: the
    /// realisations of one set of base parameters differ by these.
    null_j: nalgebra::DMatrix<f64>,
    /// The nominal robot's base-parameter values `π₁ + K π₂` (SI, parameter order).
    nominal_values: Vec<f64>,
}

/// The structure shared by copies: the nominal rigid body, and its base-parameter set found
/// on first use. Finding the base (the regressor at [`BASE_SAMPLES`] states, a QR and two
/// SVDs) costs milliseconds that an energy model never needs: the effect is null (zero
/// errors) unless identification or a drive file's `[effects.values]` sets it, and a null
/// effect adds no torque. Identification, the parameter list and every value access build it.
#[derive(Debug)]
struct Shared {
    /// The nominal rigid body (payload merged, no armature).
    nominal: DynModel,
    /// Joint ranges the random states of [`Base::find`] are drawn from, rad or m.
    ranges: Vec<(f64, f64)>,
    /// The base parameters, found on first use.
    base: std::sync::OnceLock<Base>,
}

/// A link's ten standard parameters as its pseudo-inertia `J` (4 × 4, symmetric).
fn pseudo_inertia(p: &[f64]) -> nalgebra::Matrix4<f64> {
    let i = nalgebra::Matrix3::new(p[4], p[7], p[8], p[7], p[5], p[9], p[8], p[9], p[6]);
    let s = nalgebra::Matrix3::identity() * (0.5 * i.trace()) - i;
    let mut j = nalgebra::Matrix4::<f64>::zeros();
    j.fixed_view_mut::<3, 3>(0, 0).copy_from(&s);
    for a in 0..3 {
        j[(a, 3)] = p[1 + a];
        j[(3, a)] = p[1 + a];
    }
    j[(3, 3)] = p[0];
    j
}

/// The standard parameters of a pseudo-inertia (inverse of [`pseudo_inertia`]):
/// `I = tr(Σ) 1 − Σ`.
fn standard_of(j: &nalgebra::Matrix4<f64>) -> [f64; 10] {
    let s = j.fixed_view::<3, 3>(0, 0).into_owned();
    let i = nalgebra::Matrix3::identity() * s.trace() - s;
    [
        j[(3, 3)],
        j[(0, 3)],
        j[(1, 3)],
        j[(2, 3)],
        i[(0, 0)],
        i[(1, 1)],
        i[(2, 2)],
        i[(0, 1)],
        i[(0, 2)],
        i[(1, 2)],
    ]
}

const SQRT2: f64 = std::f64::consts::SQRT_2;

/// Coordinates of a pseudo-inertia in which the Euclidean norm is the Frobenius norm of `J`.
fn j_coords(j: &nalgebra::Matrix4<f64>) -> [f64; 10] {
    [
        j[(0, 0)],
        j[(1, 1)],
        j[(2, 2)],
        SQRT2 * j[(0, 1)],
        SQRT2 * j[(0, 2)],
        SQRT2 * j[(1, 2)],
        SQRT2 * j[(0, 3)],
        SQRT2 * j[(1, 3)],
        SQRT2 * j[(2, 3)],
        j[(3, 3)],
    ]
}

fn j_of_coords(v: &[f64]) -> nalgebra::Matrix4<f64> {
    let (a, b, c) = (v[3] / SQRT2, v[4] / SQRT2, v[5] / SQRT2);
    let (d, e, f) = (v[6] / SQRT2, v[7] / SQRT2, v[8] / SQRT2);
    nalgebra::Matrix4::new(v[0], a, b, d, a, v[1], c, e, b, c, v[2], f, d, e, f, v[9])
}

/// Iterations of the alternating projections of [`RigidBody::nearest_physical`].
const PROJECTION_ITERATIONS: usize = 3000;

/// Errors of the base inertial parameters.
#[derive(Debug, Clone)]
pub struct RigidBody {
    /// `δθ_b`, SI (units in [`Effect::params`]); empty while every error is zero and the
    /// base parameters have not been set ([`Effect::values`] gives them in full).
    delta: Vec<f64>,
    shared: Arc<Shared>,
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

impl Base {
    /// The base parameters of `nominal`: the regressor at [`BASE_SAMPLES`] seeded random
    /// states within `ranges` (one per joint), reduced by QR with column pivoting.
    fn find(nominal: &DynModel, ranges: &[(f64, f64)]) -> Base {
        let n = nominal.dof();
        let w = Base::sampled_regressor(nominal, ranges);
        let rows = w.nrows();
        let norms: Vec<f64> = (0..w.ncols()).map(|c| w.column(c).norm()).collect();
        let (indep, dep) = Base::pivot_columns(&w, &norms);
        let (indep, dep) = (indep.as_slice(), dep.as_slice());
        // K = W₁⁺ W₂ in raw units: base_k = π_k + Σ K_kj π_j.
        let w1 = nalgebra::DMatrix::from_fn(rows, indep.len(), |i, k| w[(i, indep[k])]);
        let w2 = nalgebra::DMatrix::from_fn(rows, dep.len(), |i, k| w[(i, dep[k])]);
        let k = w1
            .clone()
            .svd(true, true)
            .solve(&w2, 1e-12)
            .unwrap_or_else(|_| nalgebra::DMatrix::zeros(indep.len(), dep.len()));
        let combination = Base::combination_names(indep, dep, &k);
        let null_j = Base::null_space_j(&w, &norms, n);
        let std_value = |c: usize| nominal.link_params(c / 10)[c % 10];
        let nominal_values: Vec<f64> = indep
            .iter()
            .enumerate()
            .map(|(row, &c)| {
                std_value(c)
                    + dep
                        .iter()
                        .enumerate()
                        .map(|(col, &dc)| k[(row, col)] * std_value(dc))
                        .sum::<f64>()
            })
            .collect();
        Base {
            independent: indep.iter().map(|&c| (c / 10, c % 10)).collect(),
            combination,
            null_j,
            nominal_values,
        }
    }

    /// The regressor W at [`BASE_SAMPLES`] seeded random states within `ranges` (one per
    /// joint): one row per sample and joint, ten columns per link.
    fn sampled_regressor(nominal: &DynModel, ranges: &[(f64, f64)]) -> nalgebra::DMatrix<f64> {
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
            for (j, &(lo, hi)) in ranges.iter().enumerate().take(n) {
                q[j] = rng.gen_range(lo..=hi);
                qd[j] = rng.gen_range(-1.5..=1.5);
                qdd[j] = rng.gen_range(-3.0..=3.0);
            }
            rnea_regressor(nominal, &mut d, &q[..n], &qd[..n], &qdd[..n], &mut ys)
                .expect("slices of the model's joint count");
            for j in 0..n {
                for c in 0..ncol {
                    w[(s * n + j, c)] = ys[j * ncol + c];
                }
            }
        }
        w
    }

    /// The independent and dependent columns of W (`norms`: its column norms), by QR with
    /// column pivoting of its normalised non-zero columns.
    fn pivot_columns(w: &nalgebra::DMatrix<f64>, norms: &[f64]) -> (Vec<usize>, Vec<usize>) {
        let (rows, ncol) = (w.nrows(), w.ncols());
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
        (indep.to_vec(), dep.to_vec())
    }

    /// Each base parameter as a name: its independent standard parameter plus the largest
    /// terms of the dependent ones (`k`: the combination matrix).
    fn combination_names(
        indep: &[usize],
        dep: &[usize],
        k: &nalgebra::DMatrix<f64>,
    ) -> Vec<String> {
        indep
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
            .collect()
    }

    /// The null space of W (`norms`: its column norms) in standard parameters (zero columns
    /// included), then in pseudo-inertia coordinates, orthonormalised; `n` links.
    fn null_space_j(w: &nalgebra::DMatrix<f64>, norms: &[f64], n: usize) -> nalgebra::DMatrix<f64> {
        let (rows, ncol) = (w.nrows(), w.ncols());
        let nmax = norms.iter().cloned().fold(0.0, f64::max);
        // Null space of W in standard parameters (zero columns included), then in
        // pseudo-inertia coordinates, orthonormalised.
        let scale: Vec<f64> = norms
            .iter()
            .map(|&v| if v > 1e-9 * nmax { v } else { 1.0 })
            .collect();
        let wn_all = nalgebra::DMatrix::from_fn(rows, ncol, |i, c| w[(i, c)] / scale[c]);
        let svd = wn_all.transpose().svd(true, false);
        let smax = svd.singular_values.max();
        let u = svd.u.as_ref().expect("svd with u");
        let mut null_cols = Vec::new();
        for (k, &sv) in svd.singular_values.iter().enumerate() {
            if sv <= RANK_TOL * smax {
                null_cols.push(k);
            }
        }
        // Columns of U beyond the rows' count are not computed by a thin SVD: ncol ≤ rows
        // here (BASE_SAMPLES · n rows ≫ 10 n columns), so U (ncol × ncol) is complete.
        let mut nj = nalgebra::DMatrix::<f64>::zeros(ncol, null_cols.len());
        for (o, &k) in null_cols.iter().enumerate() {
            for l in 0..n {
                let mut p = [0.0; 10];
                for (a, pa) in p.iter_mut().enumerate() {
                    *pa = u[(10 * l + a, k)] / scale[10 * l + a];
                }
                let v = j_coords(&pseudo_inertia(&p));
                for a in 0..10 {
                    nj[(10 * l + a, o)] = v[a];
                }
            }
        }
        if nj.ncols() > 0 {
            let svd = nj.svd(true, false);
            let smax = svd.singular_values.max();
            let keep: Vec<usize> = (0..svd.singular_values.len())
                .filter(|&k| svd.singular_values[k] > 1e-9 * smax)
                .collect();
            let u = svd.u.expect("svd with u");
            nalgebra::DMatrix::from_fn(ncol, keep.len(), |i, k| u[(i, keep[k])])
        } else {
            nj
        }
    }
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
        let ranges = robot
            .joints
            .iter()
            .take(nominal.dof())
            .map(|jt| {
                if jt.upper > jt.lower {
                    (jt.lower, jt.upper)
                } else {
                    (-3.0, 3.0)
                }
            })
            .collect();
        let delta_model = nominal.with_link_params(&[]);
        Ok(RigidBody {
            delta: Vec::new(),
            shared: Arc::new(Shared {
                nominal,
                ranges,
                base: std::sync::OnceLock::new(),
            }),
            delta_model,
        })
    }

    /// The base parameters (found now if no copy of this effect has needed them yet).
    fn base(&self) -> &Base {
        self.shared
            .base
            .get_or_init(|| Base::find(&self.shared.nominal, &self.shared.ranges))
    }

    /// Whether the base parameters have been found (by this effect or a copy of it): they
    /// are found on first use, not when the effect is built (an energy model never uses them).
    pub fn base_found(&self) -> bool {
        self.shared.base.get().is_some()
    }

    /// The nominal robot's values of the base parameters (each independent standard parameter
    /// plus the dependent ones it absorbs; SI, in parameter order). Errors `δ = −2 ×` these
    /// mirror the rigid body (every torque negated).
    pub fn nominal_base_values(&self) -> &[f64] {
        &self.base().nominal_values
    }

    /// Each base parameter in words (its standard parameter and the dependent ones it
    /// absorbs, with coefficients), in parameter order.
    pub fn combination(&self) -> &[String] {
        &self.base().combination
    }

    /// Smallest eigenvalue of the pseudo-inertia `J = [[½ tr(I) 1 − I, h], [hᵀ, m]]` of one
    /// link's standard parameters (`I` about the joint origin), kg·m²; a physically consistent
    /// link (positive mass, inertia of a real mass distribution: the triangle inequalities
    /// included) has `J ⪰ 0` (Wensing, Kim & Slotine 2017).
    pub(crate) fn pseudo_inertia_min_eigenvalue(p: &[f64; 10]) -> f64 {
        pseudo_inertia(p).symmetric_eigenvalues().min()
    }

    /// The physically consistent robot nearest to `links` (standard parameters per link) among
    /// those with the same base parameters (same torques), found by cyclic projections
    /// (von Neumann / Bregman; converge to a point of the intersection when there is one) in
    /// pseudo-inertia coordinates onto: the realisations of these base parameters (affine:
    /// `links` plus the null space of `W`), the links whose pseudo-inertia is positive
    /// semidefinite (or no less so than the nominal link's), and the links whose mass is within
    /// [`RIGID_BODY_MAX_MASS_CHANGE`] of the nominal. Returns the last realisation (on the
    /// affine set).
    fn nearest_physical(&self, links: &[[f64; 10]]) -> Vec<[f64; 10]> {
        let n = links.len();
        let nom: Vec<[f64; 10]> = (0..n).map(|l| self.shared.nominal.link_params(l)).collect();
        let floor: Vec<f64> = nom
            .iter()
            .map(|p| Self::pseudo_inertia_min_eigenvalue(p).min(0.0))
            .collect();
        let a = nalgebra::DVector::from_iterator(
            10 * n,
            links.iter().flat_map(|p| j_coords(&pseudo_inertia(p))),
        );
        let nb = &self.base().null_j;
        let onto_a = |x: &nalgebra::DVector<f64>| -> nalgebra::DVector<f64> {
            if nb.ncols() == 0 {
                return a.clone();
            }
            &a + nb * (nb.transpose() * (x - &a))
        };
        let mut x = a.clone();
        for _ in 0..PROJECTION_ITERATIONS {
            for l in 0..n {
                let j = j_of_coords(&x.as_slice()[10 * l..10 * l + 10]);
                let e = j.symmetric_eigen();
                let vals = e.eigenvalues.map(|v| v.max(floor[l]));
                let mut j = e.eigenvectors
                    * nalgebra::Matrix4::from_diagonal(&vals)
                    * e.eigenvectors.transpose();
                let m0 = nom[l][0];
                j[(3, 3)] = j[(3, 3)].clamp(
                    (1.0 - RIGID_BODY_MAX_MASS_CHANGE) * m0,
                    (1.0 + RIGID_BODY_MAX_MASS_CHANGE) * m0,
                );
                x.as_mut_slice()[10 * l..10 * l + 10].copy_from_slice(&j_coords(&j));
            }
            x = onto_a(&x);
        }
        (0..n)
            .map(|l| standard_of(&j_of_coords(&x.as_slice()[10 * l..10 * l + 10])))
            .collect()
    }

    /// The links' standard parameters of the robot this fit describes: nominal plus each
    /// base-parameter error on its independent standard parameter (the realisation the model
    /// evaluates), each error first pulled `sigmas` standard errors toward zero.
    fn corrected_links(&self, std_errors: &[Option<f64>], sigmas: f64) -> Vec<[f64; 10]> {
        let n = self.shared.nominal.dof();
        let mut p: Vec<[f64; 10]> = (0..n).map(|l| self.shared.nominal.link_params(l)).collect();
        for (i, (&v, &(l, k))) in self.delta.iter().zip(&self.base().independent).enumerate() {
            let s = std_errors.get(i).copied().flatten().unwrap_or(0.0);
            p[l][k] += v.signum() * (v.abs() - sigmas * s).max(0.0);
        }
        p
    }

    fn rebuild(&mut self) {
        let n = self.shared.nominal.dof();
        let mut p = vec![[0.0; 10]; n];
        for (v, &(l, k)) in self.delta.iter().zip(&self.base().independent) {
            p[l][k] = *v;
        }
        self.delta_model = self.shared.nominal.with_link_params(&p);
    }
}

impl Effect for RigidBody {
    fn name(&self) -> &'static str {
        "rigid_body"
    }
    fn uncertainty(&self) -> Option<Uncertainty> {
        at(DrawPhase::Robot, 0)
    }
    /// Every link's mass (± `link_mass_rel`), centre of mass (± `link_com_m` along each axis
    /// of the link frame) and inertia tensor (± `link_inertia_rel`, scaled as a whole).
    fn draw(&self, d: &mut Drawing<'_>, _joint: Option<usize>) {
        for i in 0..d.robot.links.len() {
            if d.robot.links[i].is_none() {
                continue;
            }
            let f = 1.0 + d.ranges.link_mass_rel * d.uniform();
            if let Some(l) = d.robot.links[i].as_mut() {
                l.mass *= f;
            }
            d.record(format!("link {} mass", i + 1), f);
            for k in 0..3 {
                let s = d.ranges.link_com_m * d.uniform();
                if let Some(l) = d.robot.links[i].as_mut() {
                    l.com[k] += s;
                }
            }
            let g = 1.0 + d.ranges.link_inertia_rel * d.uniform();
            if let Some(l) = d.robot.links[i].as_mut() {
                l.inertia *= g;
            }
            d.record(format!("link {} inertia", i + 1), g);
        }
    }
    fn params(&self) -> Vec<ParamSpec> {
        self.base()
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
        if self.delta.is_empty() {
            // Every error zero (not set yet): one per base parameter.
            return vec![0.0; self.base().independent.len()];
        }
        self.delta.clone()
    }
    fn set_values(&mut self, values: &[f64]) -> Result<()> {
        check_values(self.name(), &self.params(), values)?;
        self.delta = values.to_vec();
        self.rebuild();
        Ok(())
    }
    fn clone_box(&self) -> Box<dyn Effect> {
        Box::new(self.clone())
    }
    fn is_null(&self) -> bool {
        self.delta.iter().all(|v| *v == 0.0)
    }
    /// Implausible when no physically consistent robot has the fitted base parameters (each
    /// error first pulled [`RIGID_BODY_PLAUSIBILITY_SIGMAS`] standard errors toward the
    /// nominal): every realisation of them (the standard parameters may move along the null
    /// space of the regressor without changing a torque) gives some link a negative mass, a
    /// mass changed by more than [`RIGID_BODY_MAX_MASS_CHANGE`] of its nominal, or an inertia
    /// no mass distribution has (pseudo-inertia not positive semidefinite, where the nominal
    /// link's is). Searched by [`RigidBody::nearest_physical`]; a violation is reported when
    /// it exceeds 1 % of the link's nominal mass or pseudo-inertia trace.
    fn implausible_fit(&self, std_errors: &[Option<f64>]) -> Option<String> {
        let n = self.shared.nominal.dof();
        let pulled = self.corrected_links(std_errors, RIGID_BODY_PLAUSIBILITY_SIGMAS);
        let nom: Vec<[f64; 10]> = (0..n).map(|l| self.shared.nominal.link_params(l)).collect();
        if pulled == nom {
            return None;
        }
        let best = self.nearest_physical(&pulled);
        let full = self.corrected_links(&[], 0.0);
        let mut why = Vec::new();
        for l in 0..n {
            let (m0, m) = (nom[l][0], best[l][0]);
            let tol_m = 0.01 * m0.abs().max(1e-6);
            let scale = pseudo_inertia(&nom[l]).trace().abs().max(1e-9);
            if m < -tol_m {
                why.push(format!(
                    "link {} would weigh {m:.1} kg (nominal {m0:.1} kg; {:.1} kg as fitted)",
                    l + 1,
                    full[l][0]
                ));
            } else if (m - m0).abs() > RIGID_BODY_MAX_MASS_CHANGE * m0 + tol_m {
                why.push(format!(
                    "link {} mass changes by {:+.1} kg, more than {:.0} % of its nominal {m0:.1} kg",
                    l + 1,
                    m - m0,
                    100.0 * RIGID_BODY_MAX_MASS_CHANGE
                ));
            }
            let e0 = Self::pseudo_inertia_min_eigenvalue(&nom[l]).min(0.0);
            let e = Self::pseudo_inertia_min_eigenvalue(&best[l]);
            if e < e0 - 0.01 * scale {
                why.push(format!(
                    "link {} inertia is not physically consistent (pseudo-inertia eigenvalue {e:.3} kg·m² < 0)",
                    l + 1
                ));
            }
        }
        (!why.is_empty()).then(|| {
            format!(
                "no physical robot has the fitted base parameters, even in its nearest realisation: {} (each error pulled {} standard errors toward the nominal)",
                why.join("; "),
                RIGID_BODY_PLAUSIBILITY_SIGMAS
            )
        })
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
        let p = self.base().independent.len();
        let n = self.shared.nominal.dof();
        let ncol = 10 * n;
        let mut ys = [0.0; 10 * MAX_DOF * MAX_DOF];
        let mut d = DynData::default();
        if y.len() < n * p
            || rnea_regressor(
                &self.shared.nominal,
                &mut d,
                q,
                qd,
                qdd,
                &mut ys[..n * ncol],
            )
            .is_err()
        {
            return false;
        }
        for j in 0..n {
            for (c, &(l, k)) in self.base().independent.iter().enumerate() {
                y[j * p + c] = ys[j * ncol + 10 * l + k];
            }
        }
        true
    }
}
