//! A placement a site can act on under what the drive data do not know: the robust choice
//! over plausible robots, the regret of the nominal answer, and what measuring each uncertain
//! parameter is worth.
//!
//! The draws are the uncertainty study's ([`crate::search::uncertainty`]: the drive file's
//! `[uncertainty]` ranges, or a calibrated robot's standard errors). The candidates are the
//! nominal answer, the corners of its tolerance box, a local stencil around it (± a step in
//! x, y and z, ± 5° in yaw) and the optimum of each draw: the refinement
//! ([`crate::search::refine::refine`]) run again from the nominal answer with that draw's
//! robot (the same evaluator machinery, in this process). Every candidate is timed once
//! (timing does not depend on the drawn numbers) and its energy integrated under every draw.
//!
//! Regret of a candidate in a draw: its energy (the objective) minus the lowest energy of any
//! candidate in that draw, J. The recommendation minimises the expected energy over the draws
//! ([`RobustObjective::Expected`]) or the largest regret ([`RobustObjective::Regret`]). Only
//! candidates whose tolerance box holds under the nominal robot take part (a placement a site
//! cannot hold is no choice, and would make every regret look larger). "Within 1 %" is
//! against the energy a placement can change, the drives' energy of the draw's best candidate
//! (standby, which no placement changes but through the print time, is reported
//! separately).
//!
//! Value of measuring a parameter (the expected value of partial perfect information): with
//! the parameter known, the choice may change. Per candidate, the energy difference to the
//! recommendation is regressed (least squares, linear) on the drawn value of the parameter;
//! the value is the mean over the draws of the largest predicted saving of any candidate over
//! the recommendation (0 when none is predicted cheaper). A parameter that does not move the
//! decision is worth ~0; the sum over parameters is bounded by neither, the value of knowing
//! everything (the recommendation's expected regret) bounds each.
//!
//! Every reduction runs in draw order and the draws use their own ChaCha8 streams, so the
//! study is identical for any thread count.

use crate::energy::EnergyModel;
use crate::error::{Error, Result};
use crate::evaluate::evaluator::{Evaluated, Evaluator};
use crate::evaluate::PathJob;
use crate::frame::Placement;
use crate::robot::RobotModel;
use crate::search::optimise::OptimiseOptions;
use crate::search::refine::{self, Bounds, SearchOptions};
use crate::search::tolerance::Checker;
use crate::search::uncertainty::{self, Ranges, Source};
use rayon::prelude::*;
use serde::Serialize;

use crate::search::job::RobustObjective;

/// Options of [`robust`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RobustOptions {
    /// Draws (plausible robots), >= 1.
    pub draws: usize,
    /// Seed of the draws (draw `d`: ChaCha8 stream `d`).
    pub seed: u64,
    /// What the recommendation minimises.
    pub criterion: RobustObjective,
    /// Ranges to draw from (`None`: the drive file's, else the defaults).
    #[serde(skip)]
    pub ranges: Option<Ranges>,
    /// Step of the local stencil in x, y and z, m.
    pub stencil_m: f64,
    /// Step of the local stencil in yaw, rad.
    pub stencil_yaw_rad: f64,
    /// Re-run the refinement per draw for that draw's optimum.
    pub draw_optima: bool,
    /// Refinement evaluations per draw (the tolerance checks not counted).
    pub draw_evals: usize,
    /// Prints a year, for the yearly figures.
    pub prints_per_year: f64,
    /// Grid carbon intensity, kg CO₂ per kWh, for the yearly figures.
    pub grid_kg_co2_per_kwh: f64,
}

impl Default for RobustOptions {
    /// 20 draws, seed 42, expected energy, ±50 mm and ±5° stencil, each draw's optimum with
    /// 40 refinement evaluations, 1000 prints a year, 0.4 kg CO₂/kWh.
    fn default() -> Self {
        RobustOptions {
            draws: 20,
            seed: crate::search::job::DEFAULT_SEED,
            criterion: RobustObjective::Expected,
            ranges: None,
            stencil_m: 0.05,
            stencil_yaw_rad: 5f64.to_radians(),
            draw_optima: true,
            draw_evals: 40,
            prints_per_year: crate::search::job::DEFAULT_PRINTS_PER_YEAR,
            grid_kg_co2_per_kwh: crate::search::job::DEFAULT_GRID_KG_CO2_PER_KWH,
        }
    }
}

/// One candidate placement over the draws.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Candidate {
    /// The placement (x, y, z m; yaw, spin in degrees).
    #[serde(serialize_with = "ser_placement")]
    pub placement: Placement,
    /// Where it came from: `nominal answer`, `tolerance corner`, `stencil`, `optimum of draw d`.
    pub origin: String,
    /// Energy (objective) under the nominal robot, J.
    pub nominal_j: f64,
    /// Expected energy (objective) over the draws, J.
    pub expected_j: f64,
    /// Expected drives' energy over the draws, J.
    pub expected_drives_j: f64,
    /// Expected standby energy over the draws, J.
    pub expected_standby_j: f64,
    /// Expected regret over the draws, J.
    pub expected_regret_j: f64,
    /// 95th percentile of the regret, J.
    pub p95_regret_j: f64,
    /// Largest regret, J.
    pub max_regret_j: f64,
    /// Share of draws in which it is the best candidate (0–1).
    pub p_best: f64,
    /// Share of draws in which its regret is within 1 % of the best candidate's drives'
    /// energy (standby excluded) (0–1).
    pub p_within_1pct: f64,
}

/// A placement as JSON: x, y, z (m), yaw and spin (degrees).
pub(crate) fn ser_placement<S: serde::Serializer>(
    p: &Placement,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    use serde::ser::SerializeStruct;
    let mut st = s.serialize_struct("Placement", 5)?;
    st.serialize_field("x", &p.x)?;
    st.serialize_field("y", &p.y)?;
    st.serialize_field("z", &p.z)?;
    st.serialize_field("yaw_deg", &p.yaw.to_degrees())?;
    st.serialize_field("spin_deg", &p.nozzle_spin.to_degrees())?;
    st.end()
}

/// What knowing one uncertain parameter is worth.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ParameterValue {
    /// The parameter, as the study names it (`balancer force`: preload relative to the
    /// nominal, 0 when absent).
    pub name: String,
    /// Share of the variance of the nominal answer's regret its value explains (R² of a
    /// linear fit, 0–1).
    pub regret_explained: f64,
    /// Expected regret removed by knowing it before choosing, J per print.
    pub value_j: f64,
    /// The same, kWh a year at [`RobustOptions::prints_per_year`].
    pub value_kwh_per_year: f64,
}

/// A search bound moved outward (e.g. a plinth under the robot): the answer's placement with
/// that coordinate moved by the step.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BoundStep {
    /// The bound, as the search names it (`z min = 0.000 m`).
    pub bound: String,
    /// How far it moved outward, m.
    pub step_m: f64,
    /// The coordinate's value there, m.
    pub at_m: f64,
    /// Energy (objective) there, J (`None`: infeasible).
    pub energy_j: Option<f64>,
    /// Saving against the answer, J (positive: moving the bound pays).
    pub saving_j: Option<f64>,
    /// Why it is infeasible, else `None`.
    pub reason: Option<String>,
}

/// The outcome of [`robust`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Robust {
    /// What was minimised.
    pub criterion: RobustObjective,
    /// Draws.
    pub draws: usize,
    /// Seed of the draws.
    pub seed: u64,
    /// Where the ranges came from.
    pub source: Source,
    /// Identified parameters drawn from their standard errors (calibrated robots).
    pub calibrated: Vec<String>,
    /// Every candidate compared (the nominal answer first).
    pub candidates: Vec<Candidate>,
    /// Index of the recommendation in `candidates`.
    pub recommended: usize,
    /// Candidates whose tolerance box was checked under the nominal robot (every one but the
    /// nominal answer; those where it does not hold are left out of `candidates`).
    pub tolerance_checked: usize,
    /// Expected drives' energy of each draw's best candidate, J (what a placement can change).
    pub drives_j: f64,
    /// Expected standby energy of the recommendation, J (shown apart: no placement changes it
    /// but through the print time).
    pub standby_j: f64,
    /// The uncertain parameters, most valuable to measure first.
    pub value_of_information: Vec<ParameterValue>,
    /// Value of knowing every parameter (the recommendation's expected regret), J per print.
    pub value_of_everything_j: f64,
    /// Prints a year the yearly figures assume.
    pub prints_per_year: f64,
    /// Grid carbon intensity assumed, kg CO₂/kWh.
    pub grid_kg_co2_per_kwh: f64,
    /// Expected energy of the recommendation over a year, kWh, and its CO₂, kg.
    pub yearly_kwh: f64,
    /// CO₂ of `yearly_kwh` at the stated intensity, kg.
    pub yearly_kg_co2: f64,
    /// Per draw, per candidate: energy (objective), J.
    pub energy_j: Vec<Vec<f64>>,
    /// Per draw: the drives' energy of the best candidate, J (the "within 1 %" reference).
    pub best_drives_j: Vec<f64>,
    /// Per draw: the parameters drawn (name, value), the first draw's names.
    pub parameters: Vec<String>,
    /// Per draw, the drawn values in the order of `parameters`.
    pub drawn: Vec<Vec<f64>>,
    /// Evaluations made (per-draw refinements, candidates, tolerance checks).
    pub evaluations: usize,
}

impl Robust {
    /// The recommendation.
    pub fn recommendation(&self) -> &Candidate {
        &self.candidates[self.recommended]
    }

    /// The nominal answer.
    pub fn nominal(&self) -> &Candidate {
        &self.candidates[0]
    }
}

/// Preload of the balancer of `m`, N (`None`: no balancer).
fn balancer_preload(m: &RobotModel) -> Option<f64> {
    let t = &m.effects.table;
    match t.values.as_ref().and_then(|v| v.get("balancer")) {
        Some(b) if b.len() >= 2 => Some(b[0]),
        _ => t.balancer_preload_n,
    }
}

/// The local neighbourhood of `p`: the tolerance corners and ± `h` in x, y (and z when the
/// search box allows it), ± `yaw` in yaw, inside `bounds`.
fn neighbourhood(
    p: &Placement,
    so: &SearchOptions,
    h: f64,
    yaw: f64,
) -> Vec<(Placement, &'static str)> {
    let mut v: Vec<(Placement, &'static str)> = Vec::new();
    if !so.tolerance.is_zero() {
        v.extend(
            so.tolerance
                .corners(p)
                .into_iter()
                .map(|c| (c, "tolerance corner")),
        );
    }
    let mut st = vec![
        Placement { x: p.x - h, ..*p },
        Placement { x: p.x + h, ..*p },
        Placement { y: p.y - h, ..*p },
        Placement { y: p.y + h, ..*p },
        Placement {
            yaw: p.yaw - yaw,
            ..*p
        },
        Placement {
            yaw: p.yaw + yaw,
            ..*p
        },
    ];
    if so.z {
        st.push(Placement { z: p.z - h, ..*p });
        st.push(Placement { z: p.z + h, ..*p });
    }
    v.extend(st.into_iter().map(|c| (c, "stencil")));
    v.retain(|(c, _)| so.bounds.contains(c));
    v
}

fn same(a: &Placement, b: &Placement) -> bool {
    (a.x - b.x).abs() < 5e-4
        && (a.y - b.y).abs() < 5e-4
        && (a.z - b.z).abs() < 5e-4
        && (a.yaw - b.yaw).abs() < 1e-3
        && (a.nozzle_spin - b.nozzle_spin).abs() < 1e-3
}

/// The robust choice around `answer` (the nominal answer, feasible and holding its
/// tolerance) over `o.draws` plausible robots. `opts` and `so` are the refinement's (each
/// draw's optimum is searched with them, `o.draw_evals` evaluations each). Errors: no draw, an
/// infeasible answer, a model error.
pub fn robust(
    ev: &Evaluator,
    answer: &Evaluated,
    opts: &OptimiseOptions,
    so: &SearchOptions,
    o: &RobustOptions,
) -> Result<Robust> {
    if o.draws == 0 {
        return Err(Error::Invalid("robust choice: at least 1 draw".into()));
    }
    if answer.feasible().is_none() {
        return Err(Error::Invalid(
            "robust choice: the nominal answer is infeasible".into(),
        ));
    }
    let nominal = ev.job.robot;
    let (ranges, source) = uncertainty::resolve_ranges(nominal, o.ranges)?;
    let calibrated = uncertainty::calibrated_names(nominal, &ranges);
    let robots = drawn_robots(nominal, &ranges, o)?;
    let jobs = drawn_jobs(ev.job, &robots)?;
    let evs: Vec<Evaluator> = jobs
        .iter()
        .map(|j| Evaluator::new(j, ev.feasibility, ev.objective))
        .collect();
    let mut evaluations = 0usize;
    // Candidates: the answer, its neighbourhood, each draw's optimum.
    let a = answer.placement;
    let mut cands = around(&a, so, o);
    if o.draw_optima {
        evaluations += draw_optima(&evs, &a, opts, so, o, &mut cands)?;
    }
    let (mut keep, tolerance_checked, n_eval) = usable(ev, so, distinct(cands))?;
    evaluations += n_eval;
    let mut per = draw_energies(ev, &evs, &keep)?;
    keep_whole(&mut keep, &mut per)?;
    let n = o.draws;
    let nf = n as f64;
    let best = best_per_draw(&per, keep.len());
    let candidates = compare(&keep, &per, &best);
    let recommended = recommendation(&candidates, o.criterion);
    let (parameters, drawn) = drawn_table(&robots);
    let (energy_j, value_of_information) =
        value_of_information(&parameters, &drawn, &per, recommended, o);
    let rec = &candidates[recommended];
    let drives_j = best.iter().map(|b| b.1).sum::<f64>() / nf;
    let yearly_kwh = rec.expected_j * o.prints_per_year / 3.6e6;
    Ok(Robust {
        criterion: o.criterion,
        draws: n,
        seed: o.seed,
        source,
        calibrated,
        value_of_everything_j: rec.expected_regret_j,
        standby_j: rec.expected_standby_j,
        drives_j,
        recommended,
        tolerance_checked,
        candidates,
        value_of_information,
        prints_per_year: o.prints_per_year,
        grid_kg_co2_per_kwh: o.grid_kg_co2_per_kwh,
        yearly_kwh,
        yearly_kg_co2: yearly_kwh * o.grid_kg_co2_per_kwh,
        energy_j,
        best_drives_j: best.iter().map(|b| b.1).collect(),
        parameters,
        drawn,
        evaluations,
    })
}

/// The recommendation: the best candidate by the criterion (the first of equals).
fn recommendation(candidates: &[Candidate], criterion: RobustObjective) -> usize {
    let score = |c: &Candidate| match criterion {
        RobustObjective::Expected => c.expected_j,
        RobustObjective::Regret => c.max_regret_j,
    };
    (1..candidates.len()).fold(0, |b, c| {
        if score(&candidates[c]) < score(&candidates[b]) {
            c
        } else {
            b
        }
    })
}

/// The objective energy per draw and candidate, and from it the value of measuring each drawn
/// parameter for the recommendation, most valuable first.
fn value_of_information(
    parameters: &[String],
    drawn: &[Vec<f64>],
    per: &[Vec<[f64; 3]>],
    recommended: usize,
    o: &RobustOptions,
) -> (Vec<Vec<f64>>, Vec<ParameterValue>) {
    let energy_j: Vec<Vec<f64>> = per
        .iter()
        .map(|e| e.iter().map(|x| x[0]).collect())
        .collect();
    let value = crate::search::value_of_information::rank(
        parameters,
        drawn,
        &energy_j,
        recommended,
        0,
        o.prints_per_year,
    );
    (energy_j, value)
}

/// A drawn robot with the parameters drawn for it (name, value).
type DrawnRobot = (RobotModel, Vec<(String, f64)>);

/// A candidate kept for the comparison: placement, origin and nominal energy, J.
type Kept = (Placement, String, f64);

/// The drawn robots, in draw order (the balancer force drawn as a factor on its preload).
fn drawn_robots(
    nominal: &RobotModel,
    ranges: &uncertainty::Ranges,
    o: &RobustOptions,
) -> Result<Vec<DrawnRobot>> {
    let effects = crate::effects::EffectSet::of_robot(nominal)?;
    let p0 = balancer_preload(nominal).filter(|f| *f != 0.0);
    Ok((0..o.draws)
        .map(|d| {
            let (m, mut drawn) = uncertainty::drawn_robot_of(nominal, &effects, ranges, o.seed, d);
            if let Some(p0) = p0 {
                drawn.push((
                    "balancer force".into(),
                    balancer_preload(&m).unwrap_or(0.0) / p0,
                ));
            }
            (m, drawn)
        })
        .collect())
}

/// The path job of each drawn robot: `job` with that robot's energy model.
fn drawn_jobs<'r>(job: &PathJob<'r>, robots: &'r [DrawnRobot]) -> Result<Vec<PathJob<'r>>> {
    robots
        .iter()
        .map(|(m, _)| {
            Ok(PathJob {
                robot: m,
                energy: EnergyModel::with_options(m, job.energy.options())?,
                moves: job.moves.clone(),
                pieces: job.pieces.clone(),
                plan: job.plan.clone(),
                profile: job.profile,
                joint: job.joint,
                source: job.source.clone(),
            })
        })
        .collect()
}

/// The nominal answer `a` and its neighbourhood, with their origins.
fn around(a: &Placement, so: &SearchOptions, o: &RobustOptions) -> Vec<(Placement, String)> {
    let mut cands: Vec<(Placement, String)> = vec![(*a, "nominal answer".into())];
    for (p, why) in neighbourhood(a, so, o.stencil_m, o.stencil_yaw_rad) {
        cands.push((p, why.into()));
    }
    cands
}

/// Each drawn robot's own optimum from the answer `a` (the refinement with `o.draw_evals`
/// evaluations), added to `cands` where its tolerance holds; the evaluations made.
fn draw_optima(
    evs: &[Evaluator],
    a: &Placement,
    opts: &OptimiseOptions,
    so: &SearchOptions,
    o: &RobustOptions,
    cands: &mut Vec<(Placement, String)>,
) -> Result<usize> {
    let dopts = OptimiseOptions {
        max_evals: o.draw_evals,
        ..*opts
    };
    let found: Vec<Result<(Option<Placement>, usize)>> = evs
        .iter()
        .map(|evd| {
            let start = evd.evaluate(&mut evd.scratch()?, a);
            if start.feasible().is_none() {
                return Ok((None, 1));
            }
            let quiet: refine::Progress = std::sync::Arc::new(|_, _, _| {});
            let (r, si) = refine::refine(evd, &[start], &dopts, so, quiet)?;
            let n = 1 + r.evals + si.tolerance_evals + 4;
            Ok((si.tolerance.holds.then_some(r.best.placement), n))
        })
        .collect();
    let mut evaluations = 0;
    for (d, f) in found.into_iter().enumerate() {
        let (p, n) = f?;
        evaluations += n;
        if let Some(p) = p {
            cands.push((p, format!("optimum of draw {d}")));
        }
    }
    Ok(evaluations)
}

/// Distinct placements only (the first origin kept).
fn distinct(cands: Vec<(Placement, String)>) -> Vec<(Placement, String)> {
    let mut uniq: Vec<(Placement, String)> = Vec::new();
    for (p, w) in cands {
        if !uniq.iter().any(|(q, _)| same(q, &p)) {
            uniq.push((p, w));
        }
    }
    uniq
}

/// The candidates a site can use: feasible under the nominal robot (timed once) and holding
/// their tolerance box there (the nominal answer holds its own; a candidate where it does not
/// is left out before any draw). With the tolerance boxes checked and the evaluations made.
fn usable(
    ev: &Evaluator,
    so: &SearchOptions,
    uniq: Vec<(Placement, String)>,
) -> Result<(Vec<Kept>, usize, usize)> {
    // Feasible under the nominal robot, timed once.
    let ps: Vec<Placement> = uniq.iter().map(|c| c.0).collect();
    let nom = ev.sweep(&ps, &|_, _| {})?;
    let mut evaluations = ps.len();
    let mut keep: Vec<Kept> = Vec::new();
    for ((p, w), e) in uniq.into_iter().zip(&nom) {
        if e.cost().is_finite() {
            keep.push((p, w, e.cost()));
        } else if w == "nominal answer" {
            return Err(Error::Invalid(
                "robust choice: the nominal answer is infeasible when evaluated again".into(),
            ));
        }
    }
    // The choice is among placements a site can use: those whose tolerance box holds under
    // the nominal robot (the nominal answer holds its own; a candidate where it does not is
    // left out before any draw).
    let checker = Checker::new(ev, so.tolerance);
    let mut tolerance_checked = 0;
    if !so.tolerance.is_zero() {
        let mut held = Vec::with_capacity(keep.len());
        for (i, c) in keep.into_iter().enumerate() {
            if i > 0 {
                tolerance_checked += 1;
                if !checker.check(&c.0)?.holds {
                    continue;
                }
            }
            held.push(c);
        }
        keep = held;
    }
    evaluations += checker.evaluations();
    Ok((keep, tolerance_checked, evaluations))
}

/// Energies (objective, drives, standby) of each candidate under each drawn robot, in draw
/// order; infinite where a drawn robot cannot give them. Each candidate is timed once, under
/// the nominal robot.
fn draw_energies(ev: &Evaluator, evs: &[Evaluator], keep: &[Kept]) -> Result<Vec<Vec<[f64; 3]>>> {
    let timed: Vec<crate::timing::TimedPath> = {
        let r: Vec<Result<crate::timing::TimedPath>> = keep
            .par_iter()
            .map(|(p, _, _)| {
                let mut sc = ev.scratch()?;
                ev.timed(&mut sc, p).map_err(|e| {
                    Error::Invalid(format!("robust choice: re-timing a candidate: {e}"))
                })
            })
            .collect();
        r.into_iter().collect::<Result<_>>()?
    };
    // Energies per draw (objective, drives, standby), in draw order.
    let per: Vec<Result<Vec<[f64; 3]>>> = evs
        .par_iter()
        .map(|evd| {
            let mut sc = evd.scratch()?;
            Ok(timed
                .iter()
                .map(|t| {
                    evd.energy_of(&mut sc, t, Default::default())
                        .map_or([f64::INFINITY; 3], |f| {
                            [f.energy_j, f.drives_j, f.standby_j]
                        })
                })
                .collect())
        })
        .collect();
    per.into_iter().collect::<Result<_>>()
}

/// A candidate whose energy some drawn robot cannot give (a model error) is left out; the
/// nominal answer must have them all.
fn keep_whole(keep: &mut Vec<Kept>, per: &mut [Vec<[f64; 3]>]) -> Result<()> {
    let whole: Vec<bool> = (0..keep.len())
        .map(|c| per.iter().all(|e| e[c].iter().all(|v| v.is_finite())))
        .collect();
    if !whole[0] {
        return Err(Error::Invalid(
            "robust choice: a drawn robot cannot give the nominal answer's energy".into(),
        ));
    }
    let mut i = 0;
    keep.retain(|_| {
        i += 1;
        whole[i - 1]
    });
    for e in per.iter_mut() {
        let mut i = 0;
        e.retain(|_| {
            i += 1;
            whole[i - 1]
        });
    }
    Ok(())
}

/// Per draw: the best of the `k` candidates and its drives' energy.
fn best_per_draw(per: &[Vec<[f64; 3]>], k: usize) -> Vec<(usize, f64)> {
    per.iter()
        .map(|e| {
            let mut b = 0;
            for c in 1..k {
                if e[c][0] < e[b][0] {
                    b = c;
                }
            }
            (b, e[b][1])
        })
        .collect()
}

/// Each candidate over the draws: expected energies, regret against each draw's best, how
/// often it is the best or within 1 % of it.
fn compare(keep: &[Kept], per: &[Vec<[f64; 3]>], best: &[(usize, f64)]) -> Vec<Candidate> {
    let n = per.len();
    let nf = n as f64;
    let regret = |c: usize, d: usize| per[d][c][0] - per[d][best[d].0][0];
    keep.iter()
        .enumerate()
        .map(|(c, (p, w, e0))| {
            let mut r: Vec<f64> = (0..n).map(|d| regret(c, d)).collect();
            let within = (0..n).filter(|&d| r[d] <= 0.01 * best[d].1.abs()).count();
            let bests = (0..n).filter(|&d| best[d].0 == c).count();
            let mean = |i: usize| per.iter().map(|e| e[c][i]).sum::<f64>() / nf;
            let er = r.iter().sum::<f64>() / nf;
            r.sort_by(f64::total_cmp);
            Candidate {
                placement: *p,
                origin: w.clone(),
                nominal_j: *e0,
                expected_j: mean(0),
                expected_drives_j: mean(1),
                expected_standby_j: mean(2),
                expected_regret_j: er,
                p95_regret_j: uncertainty::percentile(&r, 0.95),
                max_regret_j: r[n - 1],
                p_best: bests as f64 / nf,
                p_within_1pct: within as f64 / nf,
            }
        })
        .collect()
}

/// The parameters drawn (the first draw's names) and each draw's values in their order (NaN
/// where a draw lacks one).
fn drawn_table(robots: &[DrawnRobot]) -> (Vec<String>, Vec<Vec<f64>>) {
    let parameters: Vec<String> = robots[0].1.iter().map(|(nm, _)| nm.clone()).collect();
    let drawn: Vec<Vec<f64>> = robots
        .iter()
        .map(|(_, v)| {
            parameters
                .iter()
                .enumerate()
                .map(|(i, nm)| v.get(i).filter(|x| &x.0 == nm).map_or(f64::NAN, |x| x.1))
                .collect()
        })
        .collect();
    (parameters, drawn)
}

/// What moving each search bound the answer lies on is worth: the answer's placement with
/// that coordinate moved outward by each of `steps` (m), evaluated under the nominal robot
/// (x, y, yaw and spin kept: a lower bound on what a new search there would find).
pub fn bound_steps(
    ev: &Evaluator,
    answer: &Evaluated,
    bounds: &Bounds,
    steps: &[f64],
) -> Result<Vec<BoundStep>> {
    let p = answer.placement;
    let e0 = answer.cost();
    let mut asked: Vec<(String, Placement, f64, f64)> = Vec::new();
    let eps = 0.005;
    for (name, val, r) in [
        ("x", p.x, bounds.x),
        ("y", p.y, bounds.y),
        ("z", p.z, bounds.z),
    ] {
        if r[1] - r[0] <= eps {
            continue;
        }
        for (lo, edge) in [(true, r[0]), (false, r[1])] {
            if (val - edge).abs() > eps {
                continue;
            }
            for &s in steps {
                let at = if lo { edge - s } else { edge + s };
                let mut q = p;
                match name {
                    "x" => q.x = at,
                    "y" => q.y = at,
                    _ => q.z = at,
                }
                let label = format!("{name} {} = {edge:.3} m", if lo { "min" } else { "max" });
                asked.push((label, q, s, at));
            }
        }
    }
    let ps: Vec<Placement> = asked.iter().map(|a| a.1).collect();
    let r = ev.sweep(&ps, &|_, _| {})?;
    Ok(asked
        .into_iter()
        .zip(r)
        .map(|((bound, _, step_m, at_m), e)| {
            let energy_j = e.feasible().map(|f| f.energy_j);
            BoundStep {
                bound,
                step_m,
                at_m,
                energy_j,
                saving_j: energy_j.map(|x| e0 - x),
                reason: e.outcome.as_ref().err().map(|x| x.to_string()),
            }
        })
        .collect())
}

/// The robust choice in words, a line each (J, %).
pub fn lines(r: &Robust) -> Vec<String> {
    let rec = r.recommendation();
    let nom = r.nominal();
    let p = &rec.placement;
    let crit = match r.criterion {
        RobustObjective::Expected => "lowest expected energy",
        RobustObjective::Regret => "lowest worst-case regret",
    };
    let mut v = vec![
        format!(
            "robust choice ({crit} over {} plausible robots, {} candidates: the answer, its neighbourhood{}): x = {:.3} m, y = {:.3} m, z = {:.3} m, yaw = {:.1}°, spin = {:.1}° ({})",
            r.draws,
            r.candidates.len(),
            if r.candidates.iter().any(|c| c.origin.starts_with("optimum")) { ", each robot's own optimum" } else { "" },
            p.x,
            p.y,
            p.z,
            p.yaw.to_degrees(),
            p.nozzle_spin.to_degrees(),
            rec.origin
        ),
        format!(
            "robust choice: expected energy {:.1} J (drives {:.1} J, standby {:.1} J shown apart); best in {:.0} % of the draws, within 1 % of the drives' energy ({:.1} J) of each robot's best in {:.0} %",
            rec.expected_j,
            rec.expected_drives_j,
            rec.expected_standby_j,
            rec.p_best * 100.0,
            0.01 * r.drives_j,
            rec.p_within_1pct * 100.0
        ),
        format!(
            "robust choice: regret {:.1} J expected, {:.1} J at the 95th percentile (the nominal answer: {:.1} J expected, {:.1} J at the 95th percentile, within 1 % in {:.0} % of the draws)",
            rec.expected_regret_j,
            rec.p95_regret_j,
            nom.expected_regret_j,
            nom.p95_regret_j,
            nom.p_within_1pct * 100.0
        ),
    ];
    if r.value_of_information
        .first()
        .is_some_and(|t| t.value_j <= 0.0)
    {
        v.push(format!(
            "worth measuring: nothing (knowing any one parameter would not change the choice over the draws); knowing everything: {:.1} J per print",
            r.value_of_everything_j
        ));
    } else if let Some(top) = r.value_of_information.first() {
        let more: Vec<String> = r
            .value_of_information
            .iter()
            .skip(1)
            .take(2)
            .map(|x| format!("{} {:.1} J", x.name, x.value_j))
            .collect();
        v.push(format!(
            "worth measuring: {} ({:.1} J per print, {:.2} kWh a year at {:.0} prints; explains {:.0} % of the regret's variance); next: {}; knowing everything: {:.1} J per print",
            top.name,
            top.value_j,
            top.value_kwh_per_year,
            r.prints_per_year,
            top.regret_explained * 100.0,
            if more.is_empty() { "none".into() } else { more.join(", ") },
            r.value_of_everything_j
        ));
    }
    v.push(format!(
        "robust choice over a year: {:.1} kWh at {:.0} prints, {:.1} kg CO₂ at {:.2} kg/kWh",
        r.yearly_kwh, r.prints_per_year, r.yearly_kg_co2, r.grid_kg_co2_per_kwh
    ));
    v
}

/// A bound step in words.
pub fn bound_line(b: &BoundStep) -> String {
    match (b.energy_j, b.saving_j) {
        (Some(e), Some(s)) => format!(
            "bound {} moved {:.1} m (to {:.3} m): {e:.1} J, {} {:.1} J",
            b.bound,
            b.step_m,
            b.at_m,
            if s >= 0.0 { "saves" } else { "costs" },
            s.abs()
        ),
        _ => format!(
            "bound {} moved {:.1} m (to {:.3} m): infeasible ({})",
            b.bound,
            b.step_m,
            b.at_m,
            b.reason.as_deref().unwrap_or("?")
        ),
    }
}

/// What `optimise` reports beside its answer for a site to decide on.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Decision {
    /// The robust choice over the draws (with an uncertainty study and the Nelder–Mead
    /// refinement; `None` without them).
    pub robust: Option<Robust>,
    /// Each search bound the answer lies on, moved outward by 0.2 m and 0.4 m.
    pub bound_steps: Vec<BoundStep>,
    /// With a calibrated robot: the regret before the measurement (the robot it was
    /// calibrated from, drawn from its ranges) and after it (drawn from the identified
    /// covariance).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub measurement: Option<MeasurementWorth>,
    /// With the Pareto option: the answer timed with the acceleration and jerk limits scaled.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub pareto: Vec<crate::search::pareto::TimingPoint>,
    /// The answer found again with other joint-limit and wrist-singularity margins
    /// ([`crate::search::margins`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub margins: Option<crate::search::margins::MarginTrade>,
}

/// What the measurement behind a calibrated robot did to the decision: the same robust study
/// on the robot it was calibrated from (its estimate ranges) and on the calibrated robot (the
/// identified covariance), with the same draws, seed and candidates rule.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeasurementWorth {
    /// The robot the calibration started from, as `identify --robot` was given it.
    pub base_robot: String,
    /// `None` when the base robot could not be loaded (then the reason is in `note`).
    pub before: Option<RegretFigures>,
    /// The calibrated robot's figures.
    pub after: RegretFigures,
    /// Why `before` is missing, if it is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// The recommendation's regret over a study's draws.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RegretFigures {
    /// The recommended placement (x, y, z m; yaw, spin in degrees).
    #[serde(serialize_with = "ser_placement")]
    pub placement: Placement,
    /// Expected regret, J.
    pub expected_regret_j: f64,
    /// 95th-percentile regret, J.
    pub p95_regret_j: f64,
    /// Expected drives' energy of each draw's best candidate, J.
    pub drives_j: f64,
}

impl RegretFigures {
    /// The figures of `r`'s recommendation.
    pub fn of(r: &Robust) -> Self {
        let c = r.recommendation();
        RegretFigures {
            placement: c.placement,
            expected_regret_j: c.expected_regret_j,
            p95_regret_j: c.p95_regret_j,
            drives_j: r.drives_j,
        }
    }
}

impl std::fmt::Display for MeasurementWorth {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = &self.after;
        match &self.before {
            Some(b) => write!(
                f,
                "measurement: expected regret {:.1} J before (robot {}, estimate ranges; 95th percentile {:.1} J), {:.1} J after (identified covariance; 95th percentile {:.1} J)",
                b.expected_regret_j, self.base_robot, b.p95_regret_j, a.expected_regret_j, a.p95_regret_j
            ),
            None => write!(
                f,
                "measurement: expected regret {:.1} J after calibration (95th percentile {:.1} J); before: {}",
                a.expected_regret_j,
                a.p95_regret_j,
                self.note.as_deref().unwrap_or("not computed")
            ),
        }
    }
}

/// The steps a search bound is moved by in [`bound_steps`] for the report, m (a 0.2 m and a
/// 0.4 m plinth).
pub(crate) const BOUND_STEPS_M: [f64; 2] = [0.2, 0.4];
