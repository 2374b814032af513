//! The minimum-energy placement: a coarse grid sweep, then a seeded pattern search (compass
//! search with one extra random direction per iteration, drawn from a ChaCha8 stream seeded by
//! [`OptimiseOptions::seed`]) over x, y, part yaw and nozzle spin. Infeasible placements cost
//! +∞ and keep their reason. Each poll set is evaluated in parallel and reduced in a fixed
//! order (lowest cost, ties to the first), so results do not depend on the thread count.
//!
//! The search starts from the best grid cell and only accepts strict improvements, so its
//! answer is never worse than the best grid cell.

use crate::error::{Error, Result};
use crate::evaluate::evaluator::{Evaluated, Evaluator};
use crate::frame::Placement;
use crate::search::Grid;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

/// Options of the refinement.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct OptimiseOptions {
    /// Seed of the random poll directions.
    pub seed: u64,
    /// Largest number of refinement evaluations (the grid not counted).
    pub max_evals: usize,
    /// Initial step in x and y, m (default: half the grid step).
    pub step_xy_m: f64,
    /// Initial step in yaw and spin, rad.
    pub step_angle_rad: f64,
    /// Stop when the x/y step is below this, m.
    pub tol_xy_m: f64,
    /// Angle steps stop shrinking below this, rad.
    pub tol_angle_rad: f64,
    /// Search the part yaw.
    pub yaw: bool,
    /// Search the nozzle spin.
    pub spin: bool,
    /// Offset for the sensitivity numbers, m (±50 mm).
    pub sensitivity_m: f64,
}

impl Default for OptimiseOptions {
    fn default() -> Self {
        OptimiseOptions {
            seed: 42,
            max_evals: 120,
            step_xy_m: 0.05,
            step_angle_rad: 10f64.to_radians(),
            tol_xy_m: 0.002,
            tol_angle_rad: 0.5f64.to_radians(),
            yaw: true,
            spin: true,
            sensitivity_m: 0.05,
        }
    }
}

/// How sharply energy rises near the optimum: energies at ±h in x and y (J; `None` where
/// infeasible, with the reason), central-difference gradient (J/m) and curvature (J/m²).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Sensitivity {
    /// Offset h, m.
    pub h_m: f64,
    /// Energy at the optimum, J.
    pub e0_j: f64,
    /// Energies at x−h, x+h, y−h, y+h, J.
    pub e_j: [Option<f64>; 4],
    /// Reasons for infeasible neighbours (same order), else `None`.
    pub reasons: [Option<String>; 4],
    /// ∂E/∂x, ∂E/∂y, J/m (central differences; `None` if a neighbour is infeasible).
    pub gradient_j_per_m: [Option<f64>; 2],
    /// ∂²E/∂x², ∂²E/∂y², J/m².
    pub curvature_j_per_m2: [Option<f64>; 2],
    /// One-sided slopes (E(±h) − E0)/h toward the feasible side when only one neighbour in
    /// x (resp. y) is feasible (the optimum often lies on the feasibility boundary), J/m,
    /// signed as a slope along +x/+y.
    pub one_sided_j_per_m: [Option<f64>; 2],
    /// Largest rise over the optimum among the four neighbours, % (feasible ones).
    pub max_rise_pct: Option<f64>,
}

/// The outcome of [`optimise`].
#[derive(Clone, Debug, Serialize)]
pub struct OptimiseResult {
    /// The best placement found and its numbers.
    pub best: Evaluated,
    /// The best grid cell (the start of the refinement).
    pub best_grid: Evaluated,
    /// Refinement evaluations used.
    pub evals: usize,
    /// Refinement iterations.
    pub iterations: usize,
    /// Objective after each iteration, J.
    pub history_j: Vec<f64>,
    /// Sensitivity at the optimum.
    pub sensitivity: Sensitivity,
    /// The argmin search's method, the tolerance the answer holds and the bounds it lies on
    /// (`None` for the pattern search).
    pub search: Option<crate::search::refine::SearchInfo>,
    /// Savings against the baseline in supply, drives and the objective (set by the caller).
    pub savings: Option<Savings>,
    /// The baseline's placement tolerance: the same tolerance the answer must hold, checked at
    /// all 16 corners of the baseline's box ([`crate::search::tolerance::check_all`]; set by the
    /// caller). `None` when there is no baseline, it is infeasible, the tolerance is zero or
    /// the answer's tolerance is not checked (the pattern search).
    pub baseline_tolerance: Option<crate::search::tolerance::ToleranceCheck>,
    /// The uncertainty study of the answer (with an uncertainty study's draws).
    pub uncertainty: Option<crate::search::uncertainty::Study>,
    /// The decision a site can act on ([`crate::search::run`]): the robust choice, what
    /// measuring each parameter is worth, what moving a search bound the answer lies on is
    /// worth. JSON: omitted when `None`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub decision: Option<crate::search::robust::Decision>,
    /// With the path reduction on: the answer's full evaluation beside its estimate (set by
    /// the caller with [`crate::evaluate::reduce::confirm`]; `best` then holds the full evaluation).
    /// JSON: omitted when `None`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub path_reduction: Option<crate::evaluate::reduce::FullCheck>,
}

/// Savings of the best placement against a baseline, each as (J, % of the baseline).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Savings {
    /// Objective energy saved.
    pub objective: (f64, f64),
    /// Supply energy (standby + drives) saved.
    pub supply: (f64, f64),
    /// Drives' energy (standby excluded) saved.
    pub drives: (f64, f64),
    /// Standby energy saved (shorter or longer print).
    pub standby: (f64, f64),
}

impl Savings {
    /// Savings of `best` against `base` (both feasible), else `None`.
    pub fn of(best: &Evaluated, base: &Evaluated) -> Option<Savings> {
        let (b, o) = (base.feasible()?, best.feasible()?);
        // Rounded to the operands' digits: equal placements save exactly 0, not float noise.
        let sv = |x: f64, y: f64| {
            (
                crate::numerics::difference(x, y),
                crate::numerics::relative_difference_pct(x, y),
            )
        };
        Some(Savings {
            objective: sv(b.energy_j, o.energy_j),
            supply: sv(b.supply_j, o.supply_j),
            drives: sv(b.drives_j, o.drives_j),
            standby: sv(b.standby_j, o.standby_j),
        })
    }
}

/// Refine from the best feasible entry of `grid_results` (in order; ties to the first).
/// Error: no feasible grid placement.
pub fn optimise(
    ev: &Evaluator,
    grid_results: &[Evaluated],
    opts: &OptimiseOptions,
) -> Result<OptimiseResult> {
    let start = best_of(grid_results)
        .ok_or_else(|| {
            Error::Invalid("no feasible placement in the grid: nothing to refine".into())
        })?
        .clone();
    refine(ev, start, opts)
}

/// Index of the lowest finite cost (ties to the first).
pub(crate) fn best_index(v: &[Evaluated]) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for (i, e) in v.iter().enumerate() {
        let c = e.cost();
        if c.is_finite() && best.is_none_or(|(_, b)| c < b) {
            best = Some((i, c));
        }
    }
    best.map(|b| b.0)
}

/// The lowest-cost entry.
pub fn best_of(v: &[Evaluated]) -> Option<&Evaluated> {
    best_index(v).map(|i| &v[i])
}

/// Highest finite-cost entry (the worst feasible placement).
pub fn worst_of(v: &[Evaluated]) -> Option<&Evaluated> {
    let mut w: Option<(usize, f64)> = None;
    for (i, e) in v.iter().enumerate() {
        let c = e.cost();
        if c.is_finite() && w.is_none_or(|(_, b)| c > b) {
            w = Some((i, c));
        }
    }
    w.map(|w| &v[w.0])
}

fn eval_all(ev: &Evaluator, ps: &[Placement]) -> Result<Vec<Evaluated>> {
    ev.sweep(ps, &|_, _| {})
}

/// Pattern search from `start`.
pub fn refine(ev: &Evaluator, start: Evaluated, opts: &OptimiseOptions) -> Result<OptimiseResult> {
    let mut rng = ChaCha8Rng::seed_from_u64(opts.seed);
    let mut cur = start.clone();
    let mut step = [
        opts.step_xy_m,
        opts.step_xy_m,
        opts.step_angle_rad,
        opts.step_angle_rad,
    ];
    let active = [true, true, opts.yaw, opts.spin];
    let tol = [
        opts.tol_xy_m,
        opts.tol_xy_m,
        opts.tol_angle_rad,
        opts.tol_angle_rad,
    ];
    let mut evals = 0;
    let mut iterations = 0;
    let mut history = vec![cur.cost()];
    let shift = |p: &Placement, d: &[f64; 4]| Placement {
        x: p.x + d[0],
        y: p.y + d[1],
        z: p.z,
        yaw: p.yaw + d[2],
        nozzle_spin: p.nozzle_spin + d[3],
    };
    while evals < opts.max_evals && (step[0] >= tol[0] || step[1] >= tol[1]) {
        iterations += 1;
        let mut dirs: Vec<[f64; 4]> = Vec::new();
        for k in 0..4 {
            if !active[k] || step[k] < tol[k] {
                continue;
            }
            for s in [-1.0, 1.0] {
                let mut d = [0.0; 4];
                d[k] = s * step[k];
                dirs.push(d);
            }
        }
        // One seeded random direction scaled by the steps.
        let mut d = [0.0; 4];
        for k in 0..4 {
            if active[k] {
                d[k] = rng.gen_range(-1.0..=1.0) * step[k];
            }
        }
        dirs.push(d);
        let ps: Vec<Placement> = dirs.iter().map(|d| shift(&cur.placement, d)).collect();
        evals += ps.len();
        let res = eval_all(ev, &ps)?;
        match best_index(&res) {
            Some(i) if res[i].cost() < cur.cost() => cur = res[i].clone(),
            _ => {
                for s in &mut step {
                    *s *= 0.5;
                }
            }
        }
        history.push(cur.cost());
    }
    let sensitivity = sensitivity(ev, &cur, opts.sensitivity_m)?;
    Ok(OptimiseResult {
        best: cur,
        best_grid: start,
        evals,
        iterations,
        history_j: history,
        sensitivity,
        search: None,
        savings: None,
        baseline_tolerance: None,
        uncertainty: None,
        decision: None,
        path_reduction: None,
    })
}

/// Names of the four sensitivity probes, in the order of [`probes`] and [`Sensitivity::e_j`].
pub const PROBE_NAMES: [&str; 4] = ["x−", "x+", "y−", "y+"];

/// The four sensitivity probes around `p`: x−h, x+h, y−h, y+h (h in m; z, yaw and spin kept).
pub fn probes(p: &Placement, h: f64) -> [Placement; 4] {
    [(-h, 0.0), (h, 0.0), (0.0, -h), (0.0, h)].map(|(dx, dy)| Placement {
        x: p.x + dx,
        y: p.y + dy,
        ..*p
    })
}

/// Energies at ±h in x and y around `at`, gradient and curvature.
pub fn sensitivity(ev: &Evaluator, at: &Evaluated, h: f64) -> Result<Sensitivity> {
    Ok(sensitivity_with_probes(ev, at, h)?.0)
}

/// [`sensitivity`] and the four probes' evaluations it was computed from (in the order of
/// [`probes`]), for a caller that may move to a probe without evaluating it again.
pub(crate) fn sensitivity_with_probes(
    ev: &Evaluator,
    at: &Evaluated,
    h: f64,
) -> Result<(Sensitivity, Vec<Evaluated>)> {
    let r = eval_all(ev, &probes(&at.placement, h))?;
    Ok((sensitivity_of(at, h, &r), r))
}

/// The sensitivity at `at` from its four evaluated probes `r` (in the order of [`probes`]).
fn sensitivity_of(at: &Evaluated, h: f64, r: &[Evaluated]) -> Sensitivity {
    let e0 = at.cost();
    let e: [Option<f64>; 4] = std::array::from_fn(|i| r[i].feasible().map(|f| f.energy_j));
    let reasons: [Option<String>; 4] =
        std::array::from_fn(|i| r[i].outcome.as_ref().err().map(|x| x.to_string()));
    let g = |a: Option<f64>, b: Option<f64>| Some((b? - a?) / (2.0 * h));
    let c = |a: Option<f64>, b: Option<f64>| Some((b? - 2.0 * e0 + a?) / (h * h));
    let max_rise = e
        .iter()
        .flatten()
        .map(|v| (v - e0) / e0 * 100.0)
        .fold(None, |m: Option<f64>, v| Some(m.map_or(v, |m| m.max(v))));
    let one = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (None, Some(b)) => Some((b - e0) / h),
        (Some(a), None) => Some((e0 - a) / h),
        _ => None,
    };
    Sensitivity {
        one_sided_j_per_m: [one(e[0], e[1]), one(e[2], e[3])],
        h_m: h,
        e0_j: e0,
        e_j: e,
        reasons,
        gradient_j_per_m: [g(e[0], e[1]), g(e[2], e[3])],
        curvature_j_per_m2: [c(e[0], e[1]), c(e[2], e[3])],
        max_rise_pct: max_rise,
    }
}

/// The baseline "centre of the feasible region": the feasible grid entry nearest (in x, y) to
/// the centroid of all feasible entries (ties to the first).
pub fn feasible_centre(v: &[Evaluated]) -> Option<&Evaluated> {
    let f: Vec<&Evaluated> = v.iter().filter(|e| e.cost().is_finite()).collect();
    if f.is_empty() {
        return None;
    }
    let cx = f.iter().map(|e| e.placement.x).sum::<f64>() / f.len() as f64;
    let cy = f.iter().map(|e| e.placement.y).sum::<f64>() / f.len() as f64;
    let mut best: Option<(&Evaluated, f64)> = None;
    for e in f {
        let d = (e.placement.x - cx).powi(2) + (e.placement.y - cy).powi(2);
        if best.is_none_or(|(_, b)| d < b) {
            best = Some((e, d));
        }
    }
    best.map(|b| b.0)
}

/// A default workspace grid for a robot of reach R (m): 16 × 16 cells with x from 0.35·R to
/// 0.95·R and y within ±0.7·R, bed heights z ∈ {0, R/4, R/2} (z = 0: nozzle tip at the
/// height of the base-frame origin, usually the floor; the refinement then searches z
/// continuously within [0, R/2], see [`DEFAULT_Z_MAX_PER_REACH`]), part yaws 0° and 90°,
/// spin 0°: 1536 placements.
pub fn default_grid(reach_m: f64) -> Grid {
    let n = 16;
    let lin = |a: f64, b: f64| -> Vec<f64> {
        (0..n)
            .map(|i| ((a + (b - a) * i as f64 / (n - 1) as f64) * 1000.0).round() / 1000.0)
            .collect()
    };
    Grid {
        xs: lin(0.35 * reach_m, 0.95 * reach_m),
        ys: lin(-0.7 * reach_m, 0.7 * reach_m),
        zs: vec![
            0.0,
            (0.5 * DEFAULT_Z_MAX_PER_REACH * reach_m * 1000.0).round() / 1000.0,
            (DEFAULT_Z_MAX_PER_REACH * reach_m * 1000.0).round() / 1000.0,
        ],
        yaws: vec![0.0, std::f64::consts::FRAC_PI_2],
        spins: vec![0.0],
    }
}

/// Upper bound of the default bed-height range, as a fraction of the reach (dimensionless):
/// the bed top may sit from the base-frame origin (z = 0) up to R/2 (1.3 m on the IRB 6700,
/// above the shoulder), a cell bound for a bed a person can still work at.
pub(crate) const DEFAULT_Z_MAX_PER_REACH: f64 = 0.5;
