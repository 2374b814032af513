//! Run an optimisation job ([`OptimiseConfig`]) from start to report: the grid, the refinement,
//! the full re-evaluation of a reduced answer, the baseline and the savings against it, the
//! baseline's tolerance check, the uncertainty study, the decision (the robust choice over the
//! drawn robots, the value of measuring each parameter, the search bounds moved outward) and
//! the detailed placements. Front ends
//! (the command line, the Python module, a design study) build the config and show the
//! outcome; progress goes through an [`Observer`] (argmin's problem/solver/observer split: the
//! library reports, the front end shows).
//!
//! Every rayon step runs in the caller's current pool (`pool.install(|| run(..))` to choose
//! the thread count); the answer does not depend on it.

use crate::error::{Error, Result};
use crate::evaluate::evaluator::{Evaluated, Evaluator, Objective, LEAN_SAMPLES};
use crate::evaluate::feasibility::FeasibilityOptions;
use crate::evaluate::{reduce, PathJob};
use crate::report::placement::{Detail, RunReport};
use crate::robot::RobotModel;
use crate::search::advice::Knob;
use crate::search::job::{job_with, OptimiseConfig, SearchMethod};
use crate::search::optimise::{self, feasible_centre, worst_of, OptimiseOptions};
use crate::search::refine::{self, Bounds, SearchOptions};
use crate::search::robust::{self, RobustOptions};
use crate::search::tolerance::ToleranceCheck;
use crate::search::uncertainty::{Draw, StudySetup};
use crate::timing::JointStageOptions;
use std::path::Path;

/// A stage of an optimisation that reports progress.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// The grid of candidate placements.
    Grid,
    /// The refinement from the best grid cell.
    Refinement,
}

/// Progress of a stage.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress {
    /// The stage.
    pub stage: Stage,
    /// Evaluations done.
    pub done: usize,
    /// Evaluations planned (the refinement's budget for [`Stage::Refinement`]).
    pub total: usize,
    /// Best objective so far, J (the refinement only).
    pub best_j: Option<f64>,
}

/// What a front end does while a job runs: show its progress, name its settings. Every method
/// has a default that does nothing (or names a setting in words), so `&Silent` runs a job
/// quietly.
pub trait Observer: Sync {
    /// A stage begins (`total` evaluations planned).
    fn begin(&self, _stage: Stage, _total: usize) {}
    /// A stage made progress.
    fn progress(&self, _p: Progress) {}
    /// A stage ended.
    fn end(&self, _stage: Stage) {}
    /// The front end's name for a setting (in the advice when nothing is feasible).
    fn setting_name(&self, k: Knob) -> String {
        k.words().to_string()
    }
}

/// An observer that shows nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Observer for Silent {}

/// An optimisation's answer: the report (every figure of the run's files) and the facts of the
/// run.
pub struct OptimiseOutcome {
    /// The report of the run.
    pub report: RunReport,
    /// Wall time of the grid, the refinement and the study, s.
    pub secs: f64,
    /// Every evaluation the answer needed.
    pub evaluations: usize,
}

/// The draws of one shard of an uncertainty study ([`run_shard`]).
pub struct ShardDraws {
    /// `(draw index, draw)`, in the order asked for.
    pub rows: Vec<(usize, Draw)>,
    /// Draws of the whole study.
    pub total: usize,
    /// Wall time of the draws, s.
    pub draw_s: f64,
    /// Wall time of the grid, the refinement and the draws, s.
    pub secs: f64,
}

/// Where the uncertainty study's draws come from.
enum Draws<'d> {
    /// Computed here, every one.
    All,
    /// Computed elsewhere (the shards put together).
    Given(&'d [Draw]),
    /// Only these, for a shard.
    Shard(&'d [usize]),
}

enum Answer {
    Report(Box<OptimiseOutcome>),
    Shard(ShardDraws),
}

/// Run an optimisation job: grid, refinement, full re-evaluation of a reduced answer, baseline
/// and savings, the baseline's tolerance check, uncertainty study, detailed placements; the
/// report. Errors: bad settings, no feasible grid placement (with advice, settings named by the
/// observer), a reduced answer infeasible in full, a model error.
pub fn run(config: &OptimiseConfig, observer: &dyn Observer) -> Result<OptimiseOutcome> {
    reported(work(config, Draws::All, observer)?)
}

/// [`run`] with the uncertainty study's draws given (every draw, in draw order: the shards of
/// a split run put together) instead of computed.
pub fn run_merged(
    config: &OptimiseConfig,
    draws: &[Draw],
    observer: &dyn Observer,
) -> Result<OptimiseOutcome> {
    reported(work(config, Draws::Given(draws), observer)?)
}

/// The report of a whole run ([`work`] answers with one unless a shard was asked for).
fn reported(a: Answer) -> Result<OptimiseOutcome> {
    match a {
        Answer::Report(o) => Ok(*o),
        Answer::Shard(_) => unreachable!("no shard asked for"),
    }
}

/// One shard of the uncertainty study of a job: the grid and the refinement as [`run`] (the
/// same answer on every machine), then only the draws `indices`.
pub fn run_shard(
    config: &OptimiseConfig,
    indices: &[usize],
    observer: &dyn Observer,
) -> Result<ShardDraws> {
    if config.settings.uncertainty.is_none() {
        return Err(Error::Invalid(
            "a shard of an uncertainty study needs its number of draws".into(),
        ));
    }
    match work(config, Draws::Shard(indices), observer)? {
        Answer::Shard(s) => Ok(s),
        Answer::Report(_) => unreachable!("a shard was asked for"),
    }
}

/// The placement objective over `job` with the path reduction `mode` asks for (none for a
/// path that is short or does not repeat).
pub fn evaluator<'j, 'a>(
    job: &'j PathJob<'a>,
    path: &crate::toolpath::Toolpath,
    feasibility: FeasibilityOptions,
    objective: Objective,
    mode: crate::search::job::EvaluationMode,
) -> Evaluator<'j, 'a> {
    let ev = Evaluator::new(job, feasibility, objective);
    match mode.reduce_options() {
        Some(o) => match reduce::Reduction::plan(job, path, o) {
            Ok(r) => ev.with_reduction(r),
            Err(_) => ev,
        },
        None => ev,
    }
}

/// The regret of the decision before the measurement behind a calibrated robot (the robust
/// study on the robot it was calibrated from, over its estimate ranges, from the calibrated
/// answer's placement) and after it (`after`). The base robot is resolved as `--robot` is (a
/// path, or a shipped robot's name); when it cannot be loaded that is said and `before` is
/// left out.
fn measurement_worth(
    config: &OptimiseConfig,
    base_robot: &str,
    answer: &Evaluated,
    opts: &OptimiseOptions,
    so: &SearchOptions,
    ro: &RobustOptions,
    after: &robust::Robust,
) -> Result<robust::MeasurementWorth> {
    let mut worth = robust::MeasurementWorth {
        base_robot: base_robot.to_string(),
        before: None,
        after: robust::RegretFigures::of(after),
        note: None,
    };
    let base = crate::robot::shipped::resolve(std::path::Path::new(base_robot))
        .ok_or_else(|| "not found (neither a path nor a shipped robot)".to_string())
        .and_then(|p| crate::robot::load(&p).map_err(|e| e.to_string()));
    let base = match base {
        Ok(b) => b,
        Err(why) => {
            worth.note = Some(format!("base robot {base_robot}: {why}"));
            return Ok(worth);
        }
    };
    let s = &config.settings;
    let job = job_with(config, &base, s.profile)?;
    let ev = evaluator(&job, &config.path, s.feasibility, s.objective, s.evaluation);
    let start = ev.sweep(&[answer.placement], &|_, _| {})?;
    match start.first().filter(|e| e.feasible().is_some()) {
        Some(a) => {
            let r = robust::robust(&ev, a, opts, so, ro)?;
            worth.before = Some(robust::RegretFigures::of(&r));
        }
        None => {
            worth.note = Some(format!(
                "base robot {base_robot}: the calibrated answer is infeasible with it"
            ));
        }
    }
    Ok(worth)
}

/// Run `f` with a refinement progress callback that reports to `observer` (the callback must
/// own what it holds: it goes to another thread).
fn with_refine_progress<T>(
    observer: &dyn Observer,
    total: usize,
    f: impl FnOnce(refine::Progress) -> T,
) -> T {
    let (tx, rx) = std::sync::mpsc::channel::<(usize, f64)>();
    std::thread::scope(|s| {
        s.spawn(move || {
            for (n, best) in rx {
                observer.progress(Progress {
                    stage: Stage::Refinement,
                    done: n,
                    total,
                    best_j: Some(best),
                });
            }
        });
        let tx = std::sync::Mutex::new(tx);
        let progress: refine::Progress = std::sync::Arc::new(move |_it, n, best| {
            if let Ok(t) = tx.lock() {
                let _ = t.send((n, best));
            }
        });
        f(progress)
    })
}

/// The search from the grid's `rows`: the refinement (Nelder–Mead with the placement
/// tolerance, or the pattern search). A reduced answer is evaluated in full after
/// ([`confirm_in_full`]).
fn find(
    ev: &Evaluator,
    rows: &[Evaluated],
    opts: &OptimiseOptions,
    so: &SearchOptions,
    method: SearchMethod,
    observer: &dyn Observer,
) -> Result<optimise::OptimiseResult> {
    Ok(match method {
        SearchMethod::NelderMead => {
            observer.begin(Stage::Refinement, opts.max_evals);
            let r = with_refine_progress(observer, opts.max_evals, |progress| {
                refine::refine(ev, rows, opts, so, progress)
            });
            observer.end(Stage::Refinement);
            let (mut r, info) = r?;
            r.search = Some(info);
            r
        }
        SearchMethod::Pattern => optimise::optimise(ev, rows, opts)?,
    })
}

/// A reduced answer evaluated in full (the report shows both figures); an answer infeasible
/// in full is refused, naming the placement. The answer's detail figures are worked out
/// beside, from the same timed path: returned when there was a full evaluation to take them
/// from.
fn confirm_in_full(
    ev: &Evaluator,
    job: &PathJob,
    res: &mut optimise::OptimiseResult,
) -> Result<Option<DetailFigures>> {
    let figures = std::sync::Mutex::new(None);
    let also = |t: &crate::timing::TimedPath| {
        let f = detail_figures(job, t);
        if let Ok(mut g) = figures.lock() {
            *g = Some(f);
        }
    };
    if let Some((full, chk)) = reduce::confirm_beside(ev, &res.best, &also)? {
        res.best = full;
        res.path_reduction = Some(chk);
    }
    refuse_infeasible_in_full(&res.best)?;
    figures.into_inner().ok().flatten().transpose()
}

/// What needs only the grid, worked out beside the refinement: the baseline, its tolerance
/// check and the worst and baseline placements in detail.
struct Beside {
    baseline: Option<(String, Evaluated)>,
    baseline_tolerance: Option<ToleranceCheck>,
    details: Vec<Detail>,
}

/// A job as it runs: the config, its path job and objective, the grid, the search settings and
/// the observer.
struct Run<'r, 'j, 'a> {
    config: &'r OptimiseConfig,
    job: &'j PathJob<'a>,
    ev: &'r Evaluator<'j, 'a>,
    ps: &'r [crate::toolpath::Placement],
    opts: &'r OptimiseOptions,
    so: &'r SearchOptions,
    observer: &'r dyn Observer,
}

fn work(config: &OptimiseConfig, draws: Draws, observer: &dyn Observer) -> Result<Answer> {
    let s = &config.settings;
    s.check()?;
    let job = job_with(config, &config.robot, s.profile)?;
    let ev = evaluator(&job, &config.path, s.feasibility, s.objective, s.evaluation);
    let set = config.placement_set();
    let ps = &set.placements;
    let t0 = std::time::Instant::now();
    let rows = grid(config, &ev, ps, observer)?;
    let opts = optimise_options(s, &set);
    let bounds = Bounds::over(ps, s.z_bounds)?;
    let so = SearchOptions::new(bounds, s.tolerance);
    let run = Run {
        config,
        job: &job,
        ev: &ev,
        ps,
        opts: &opts,
        so: &so,
        observer,
    };
    // The refinement, and beside it (on another thread where there is one) what needs only
    // the grid: the baseline and the worst placement, each in detail. A shard of an
    // uncertainty study reports its draws only, so it details nothing.
    let shard = s.uncertainty.is_some() && matches!(draws, Draws::Shard(_));
    let (found, beside) = rayon::join(
        || find(&ev, &rows, &opts, &so, s.search, observer),
        || run.beside(&rows, !shard),
    );
    let mut res = found?;
    let beside = beside?;
    let confirmed = confirm_in_full(&ev, &job, &mut res)?.map(|f| (res.best.placement, f));
    let margin_trade = if s.margin_trade {
        Some(run.margin_trade(&rows, &mut res)?)
    } else {
        None
    };
    let baseline = beside.baseline;
    if let Some((_, b)) = &baseline {
        res.savings = optimise::Savings::of(&res.best, b);
    }
    res.baseline_tolerance = beside.baseline_tolerance;
    if let Some(n) = s.uncertainty {
        if let Some(shard) = run.uncertainty(n, &rows, &mut res, &baseline, draws, t0)? {
            return Ok(Answer::Shard(shard));
        }
    }
    run.decide(&mut res, margin_trade)?;
    let secs = t0.elapsed().as_secs_f64();
    // The answer's detail from its confirmation, unless the decision moved the answer.
    let best = match confirmed {
        Some((at, (energy, charts))) if at == res.best.placement => Some(Detail {
            label: "best".into(),
            eval: res.best.clone(),
            energy,
            charts: Some(charts),
        }),
        _ => detail(&job, "best", &res.best)?,
    };
    let mut details: Vec<Detail> = best.into_iter().collect();
    details.extend(beside.details);
    let base_corners = res.baseline_tolerance.as_ref().map_or(0, |c| c.corners);
    let n_eval = evaluations(ps.len(), &res);
    let m = run.meta(&res, base_corners);
    let site = crate::report::site::SiteGeometry::new(
        &config.robot,
        &job,
        res.best.placement.z,
        &config.path_file,
        set.names.as_deref(),
    );
    let report = RunReport {
        title: format!(
            "printwatt optimise: {} on {}",
            config.path_file.display(),
            config.robot.name()
        ),
        meta: m,
        rows,
        names: set.names,
        grid: set.grid,
        optimise: Some(res),
        baseline,
        site: Some(site),
        details,
        electrical: config.robot.drive.is_some(),
    };
    Ok(Answer::Report(Box::new(OptimiseOutcome {
        report,
        secs,
        evaluations: n_eval,
    })))
}

/// The refinement's options from the job's settings: its first step in x and y half the
/// grid's (or 5 cm).
fn optimise_options(
    s: &crate::search::job::OptimiseSettings,
    set: &crate::search::job::PlacementSet,
) -> OptimiseOptions {
    let step = set.grid.as_ref().and_then(|g| g.step_xy_m()).unwrap_or(0.1);
    OptimiseOptions {
        seed: s.seed,
        max_evals: s.max_evals,
        step_xy_m: step / 2.0,
        yaw: !s.fixed_yaw,
        spin: !s.fixed_spin,
        ..Default::default()
    }
}

/// Every evaluation the answer needed: grid, refinement, tolerance checks (with the bisection
/// and spin points; the baseline's corners) and the 4 sensitivity points.
fn evaluations(grid_n: usize, res: &optimise::OptimiseResult) -> usize {
    let base_corners = res.baseline_tolerance.as_ref().map_or(0, |c| c.corners);
    grid_n + res.evals + res.search.as_ref().map_or(0, |si| si.tolerance_evals) + base_corners + 4
}

/// The grid of candidate placements evaluated, with progress; an error with advice (settings
/// named by the observer) when no placement is feasible.
fn grid(
    config: &OptimiseConfig,
    ev: &Evaluator,
    ps: &[crate::toolpath::Placement],
    observer: &dyn Observer,
) -> Result<Vec<Evaluated>> {
    observer.begin(Stage::Grid, ps.len());
    let rows = ev.sweep(ps, &|done, total| {
        observer.progress(Progress {
            stage: Stage::Grid,
            done,
            total,
            best_j: None,
        })
    });
    observer.end(Stage::Grid);
    let rows = rows?;
    if !rows.iter().any(|r| r.cost().is_finite()) {
        return Err(Error::Invalid(
            crate::search::advice::nothing_feasible_named(&rows, &config.robot, &|k| {
                observer.setting_name(k)
            })
            .trim_end()
            .to_string(),
        ));
    }
    Ok(rows)
}

/// An error when the placement chosen on representative layers is infeasible with every
/// sample evaluated.
fn refuse_infeasible_in_full(full: &Evaluated) -> Result<()> {
    if let Err(why) = &full.outcome {
        return Err(Error::Invalid(format!(
            "the placement chosen on representative layers (x = {:.3} m, y = {:.3} m, z = {:.3} m, yaw = {:.1}°) is infeasible when every sample is evaluated: {why}; evaluate every sample instead (full evaluation)",
            full.placement.x,
            full.placement.y,
            full.placement.z,
            full.placement.yaw.to_degrees()
        )));
    }
    Ok(())
}

impl Run<'_, '_, '_> {
    /// The answer found again with other joint-limit and wrist margins: what each costs. A
    /// stricter setting's answer also keeps the configured margins; when it is cheaper, the
    /// search stopped short of it, and the refinement runs again from it (`res` becomes its
    /// answer).
    fn margin_trade(
        &self,
        rows: &[Evaluated],
        res: &mut optimise::OptimiseResult,
    ) -> Result<crate::search::margins::MarginTrade> {
        let (config, ev, opts, so) = (self.config, self.ev, self.opts, self.so);
        let s = &config.settings;
        let trade_evals = std::cell::Cell::new(0usize);
        let find_with =
            |feas: &FeasibilityOptions| -> Result<std::result::Result<Evaluated, String>> {
                let ev = evaluator(self.job, &config.path, *feas, s.objective, s.evaluation);
                let rows = ev.sweep(self.ps, &|_, _| {})?;
                if !rows.iter().any(|r| r.cost().is_finite()) {
                    return Ok(Err("no feasible grid placement".into()));
                }
                let r = find(&ev, &rows, opts, so, s.search, &Silent)?;
                trade_evals.set(
                    trade_evals.get()
                        + rows.len()
                        + r.evals
                        + r.search.as_ref().map_or(0, |si| si.tolerance_evals),
                );
                Ok(Ok(r.best))
            };
        let mut trade = crate::search::margins::trade(&s.feasibility, &res.best, &find_with)?;
        if let Some(from) = trade.cheaper_stricter().cloned() {
            let at = from.placement.expect("a feasible setting has a placement");
            let mut seeded = rows.to_vec();
            seeded.extend(ev.sweep(&[at], &|_, _| {})?);
            let again = find(ev, &seeded, opts, so, s.search, self.observer)?;
            if again.best.feasible().is_some() && again.best.cost() < res.best.cost() {
                // The first refinement's evaluations belong to the trade now.
                trade_evals.set(
                    trade_evals.get()
                        + 1
                        + res.evals
                        + res.search.as_ref().map_or(0, |si| si.tolerance_evals),
                );
                trade.restart = Some(crate::search::margins::Restart {
                    joint_margin_deg: from.joint_margin_deg,
                    wrist_margin_deg: from.wrist_margin_deg,
                    before_j: res.best.cost(),
                    after_j: again.best.cost(),
                });
                *res = again;
                trade.answer_is(&res.best);
            }
        }
        trade.evaluations = trade_evals.get();
        Ok(trade)
    }

    /// The baseline (the given placement, or the centre of the feasible grid region), checked
    /// against the placement tolerance after a search that holds it (every corner, so the
    /// report can say how many fail); with `detailed`, the worst grid cell and the baseline in
    /// detail. A long print's details one at a time: each holds its whole timed path (about
    /// 80 bytes a sample), and two at once would raise the run's peak memory for little time.
    fn beside(&self, rows: &[Evaluated], detailed: bool) -> Result<Beside> {
        use rayon::prelude::*;
        let s = &self.config.settings;
        let baseline = match s.baseline {
            Some(b) => {
                let r = self.ev.sweep(&[b], &|_, _| {})?;
                r.into_iter().next().map(|e| ("given".to_string(), e))
            }
            None => feasible_centre(rows)
                .map(|e| ("centre of the feasible grid region".to_string(), e.clone())),
        };
        let tol = s.tolerance;
        let baseline_tolerance = match &baseline {
            Some((_, b))
                if s.search == SearchMethod::NelderMead
                    && !tol.is_zero()
                    && b.cost().is_finite() =>
            {
                Some(crate::search::tolerance::check_all(
                    self.ev,
                    &b.placement,
                    &tol,
                )?)
            }
            _ => None,
        };
        let mut wanted: Vec<(&str, &Evaluated)> = Vec::new();
        if detailed {
            wanted.extend(worst_of(rows).map(|w| ("worst", w)));
            wanted.extend(baseline.as_ref().map(|(_, b)| ("baseline", b)));
        }
        let each = |(label, e): &(&str, &Evaluated)| detail(self.job, label, e);
        let details: Vec<Option<Detail>> = if self.job.plan.motion.p.len() >= LEAN_SAMPLES {
            wanted.iter().map(each).collect::<Result<_>>()?
        } else {
            wanted.par_iter().map(each).collect::<Result<_>>()?
        };
        Ok(Beside {
            baseline,
            baseline_tolerance,
            details: details.into_iter().flatten().collect(),
        })
    }

    /// The uncertainty study over `n` drawn robots and the robust decision; for a shard, only
    /// its draws (returned).
    fn uncertainty(
        &self,
        n: usize,
        rows: &[Evaluated],
        res: &mut optimise::OptimiseResult,
        baseline: &Option<(String, Evaluated)>,
        draws: Draws,
        t0: std::time::Instant,
    ) -> Result<Option<ShardDraws>> {
        // Candidates: the answer first, then every feasible grid cell that is not nominally
        // better than it (a cheaper cell is one the search rejected because it does not hold
        // the placement tolerance: not a candidate a site could use).
        let mut cands = vec![res.best.clone()];
        cands.extend(
            rows.iter()
                .filter(|r| {
                    r.cost().is_finite()
                        && r.cost() >= res.best.cost()
                        && r.placement != res.best.placement
                })
                .cloned(),
        );
        let seed = self.config.settings.seed;
        let setup = StudySetup::new(
            self.ev,
            &cands,
            baseline.as_ref().map(|b| &b.1),
            n,
            seed,
            None,
        )?;
        let study = match draws {
            Draws::Shard(idx) => {
                let t1 = std::time::Instant::now();
                let d = setup.draws(idx)?;
                let draw_s = t1.elapsed().as_secs_f64();
                return Ok(Some(ShardDraws {
                    rows: idx.iter().copied().zip(d).collect(),
                    total: setup.len(),
                    draw_s,
                    secs: t0.elapsed().as_secs_f64(),
                }));
            }
            Draws::Given(d) => setup.reduce(d)?,
            Draws::All => {
                let all: Vec<usize> = (0..n).collect();
                let per = setup.draws(&all)?;
                setup.reduce(&per)?
            }
        };
        res.uncertainty = Some(study);
        if res.search.is_some() {
            self.robust_decision(n, res)?;
        }
        Ok(None)
    }

    /// The decision a site can act on: the robust choice over the drawn robots around the
    /// answer and each drawn robot's own optimum (the refinement run again), with what
    /// measuring each parameter is worth.
    fn robust_decision(&self, n: usize, res: &mut optimise::OptimiseResult) -> Result<()> {
        let s = &self.config.settings;
        let ro = RobustOptions {
            draws: n,
            seed: s.seed,
            criterion: s.robust,
            prints_per_year: s.prints_per_year,
            grid_kg_co2_per_kwh: s.grid_kg_co2_per_kwh,
            ..Default::default()
        };
        let r = robust::robust(self.ev, &res.best, self.opts, self.so, &ro)?;
        let measurement = match &self.config.robot.effects.calibration {
            Some(c) => Some(measurement_worth(
                self.config,
                &c.base_robot,
                &res.best,
                self.opts,
                self.so,
                &ro,
                &r,
            )?),
            None => None,
        };
        let d = res.decision.get_or_insert_with(Default::default);
        d.robust = Some(r);
        d.measurement = measurement;
        Ok(())
    }

    /// The rest of the decision: what moving a search bound is worth, print time against
    /// energy, the margin trade.
    fn decide(
        &self,
        res: &mut optimise::OptimiseResult,
        margin_trade: Option<crate::search::margins::MarginTrade>,
    ) -> Result<()> {
        // What moving a search bound the answer lies on is worth (a plinth under the robot).
        if let Some(si) = &res.search {
            if !si.on_bounds.is_empty() {
                let steps =
                    robust::bound_steps(self.ev, &res.best, &si.bounds, &robust::BOUND_STEPS_M)?;
                res.decision
                    .get_or_insert_with(Default::default)
                    .bound_steps = steps;
            }
        }
        // Print time against energy at the answer (the controller's acceleration and jerk).
        if self.config.settings.pareto {
            let pts = crate::search::pareto::time_energy(self.config, &res.best.placement)?;
            res.decision.get_or_insert_with(Default::default).pareto = pts;
        }
        if let Some(t) = margin_trade {
            res.decision.get_or_insert_with(Default::default).margins = Some(t);
        }
        Ok(())
    }

    /// The report's header lines: the run's settings, then the search's.
    fn meta(&self, res: &optimise::OptimiseResult, base_corners: usize) -> Vec<(String, String)> {
        let (config, s) = (self.config, &self.config.settings);
        let mut m = meta(
            &config.robot,
            &config.path_file,
            s.objective,
            &s.feasibility,
            self.ev.nominal_samples(),
        );
        m.push(("print speed".into(), print_speed_text(&config.path)));
        m.extend(evaluation_line(self.ev));
        m.push(("seed".into(), s.seed.to_string()));
        if let Some(si) = &res.search {
            search_meta(&mut m, si, res, self.ps.len(), base_corners);
        }
        m
    }
}

/// The search's header lines: method, tolerance, bounds, margins, evaluations and what
/// stopped it.
fn search_meta(
    m: &mut Vec<(String, String)>,
    si: &refine::SearchInfo,
    res: &optimise::OptimiseResult,
    grid_n: usize,
    base_corners: usize,
) {
    m.push(("search".into(), si.method.clone()));
    m.push(("tolerance".into(), tolerance_line(&si.tolerance)));
    m.push((
        "search bounds".into(),
        format!(
            "x {:.3}…{:.3} m, y {:.3}…{:.3} m, z {:.3}…{:.3} m",
            si.bounds.x[0],
            si.bounds.x[1],
            si.bounds.y[0],
            si.bounds.y[1],
            si.bounds.z[0],
            si.bounds.z[1]
        ),
    ));
    if !si.on_bounds.is_empty() {
        m.push((
            "optimum on a search bound".into(),
            format!("{}: widen the range there", si.on_bounds.join(", ")),
        ));
    }
    if let Some(jm) = &si.joint_margin {
        m.push(("joint-limit margin kept".into(), jm.clone()));
    }
    if let Some(wm) = &si.wrist_margin {
        m.push(("wrist margin kept".into(), wm.clone()));
    }
    m.push((
        "evaluations".into(),
        evaluations_text(si, res, grid_n, base_corners),
    ));
    if let Some(om) = &si.on_margin {
        m.push((
            "optimum on a joint-limit margin".into(),
            format!("{om}: the margin, not the energy, stops the search here (the joint margin)"),
        ));
    }
    if let Some(sk) = &si.spin_kept {
        m.push(("nozzle spin".into(), sk.clone()));
    }
    if let Some(b) = &si.budget_spent {
        m.push(("search stopped".into(), b.clone()));
    }
    if let Some(pm) = &si.polished {
        m.push(("polish".into(), pm.clone()));
    }
    for l in &si.lower_neighbours {
        m.push(("cheaper neighbour not taken".into(), l.clone()));
    }
}

/// The evaluations of a search in words: grid, refinement, tolerance corners (the answer's and
/// the baseline's), the margin trade's.
fn evaluations_text(
    si: &refine::SearchInfo,
    res: &optimise::OptimiseResult,
    grid_n: usize,
    base_corners: usize,
) -> String {
    let trade_evals = res
        .decision
        .as_ref()
        .and_then(|d| d.margins.as_ref())
        .map_or(String::new(), |t| {
            format!(", margin trade {}", t.evaluations)
        });
    if base_corners > 0 {
        format!(
            "grid {}, refinement {}, tolerance corners {} (the answer's search {}, the baseline {}){trade_evals}",
            grid_n,
            res.evals,
            si.tolerance_evals + base_corners,
            si.tolerance_evals,
            base_corners
        )
    } else {
        format!(
            "grid {}, refinement {}, tolerance corners {}{trade_evals}",
            grid_n, res.evals, si.tolerance_evals
        )
    }
}

/// The hand-off of an optimisation's answer `at` for the controller
/// ([`crate::export::hand_off`]: work object, COMPAS frame, base-frame G-code and RAPID, a
/// part-frame RAPID module in `wobjPrint`, each with the planned arm configuration), as
/// `(file name, text)`; the job's feasibility settings (the wrist margin among them) decide
/// the export's `SingArea`.
pub fn hand_off(
    config: &OptimiseConfig,
    at: &crate::toolpath::Placement,
) -> Result<Vec<(String, String)>> {
    let s = &config.settings;
    let job = PathJob::new(
        &config.robot,
        &config.path,
        s.energy,
        s.profile,
        JointStageOptions::default(),
    )?;
    let ev = Evaluator::new(&job, s.feasibility, s.objective);
    crate::export::hand_off(&ev, at, "")
}

/// What the tolerance check says, in one line.
pub fn tolerance_line(c: &ToleranceCheck) -> String {
    use crate::report::placement::tolerance_text;
    if c.corners == 0 {
        "not checked (tolerance 0,0)".into()
    } else if c.holds {
        tolerance_text(c, true)
    } else {
        format!(
            "{}; no grid cell near the optimum holds it",
            tolerance_text(c, true)
        )
    }
}

/// Full energy report of one placement (for the detailed figures); `None` for an infeasible
/// one.
pub fn detail(job: &PathJob, label: &str, e: &Evaluated) -> Result<Option<Detail>> {
    if !e.cost().is_finite() {
        return Ok(None);
    }
    let solver = crate::kinematics::IkSolver::new(job.robot)?;
    // Positions only: the rates are derived a block at a time as the energy takes them.
    let Ok(timed) = job.time_lean(&solver, &e.placement) else {
        return Ok(None);
    };
    let (energy, charts) = detail_figures(job, &timed)?;
    Ok(Some(Detail {
        label: label.into(),
        eval: e.clone(),
        energy,
        charts: Some(charts),
    }))
}

/// A placement's detail figures: its energy report and charts.
type DetailFigures = (
    crate::energy::EnergyReport,
    crate::report::placement::DetailCharts,
);

/// The energy report and charts of a placement's detail, from its timed path: the energy
/// integrated sample by sample into the report's figures and charts (no per-sample series is
/// kept: a long print's would be hundreds of bytes a sample).
fn detail_figures(job: &PathJob, timed: &crate::timing::TimedPath) -> Result<DetailFigures> {
    let mut charts = crate::report::placement::DetailCharts::new(
        job.energy.joint_names(),
        timed.traj.len(),
        job.robot.drive.is_some(),
    );
    let t = &timed.traj.t;
    let dt = timed.motion.dt;
    let energy =
        crate::energy::evaluate_streaming_timed(&job.energy, &timed.traj, dt, &mut |k, s| {
            charts.push(t[k], s)
        })?;
    charts.finish();
    Ok((energy, charts))
}

/// The report line saying how placements were evaluated, when the path reduction is on.
pub fn evaluation_line(ev: &Evaluator) -> Option<(String, String)> {
    let s = &ev.reduction()?.summary;
    Some((
        "evaluation".into(),
        format!(
            "reduced: {} layers, {} repeating with period {}, {} samples; each placement evaluated on representative layers, the others interpolated over z (each feasible placement states its error); a full evaluation evaluates every sample",
            s.layers, s.repeating_layers, s.period, s.samples
        ),
    ))
}

/// Facts about the job shown in reports and `summary.json` (`meta`). Only what determines the
/// results: how a run was executed (threads, wall time, command line) belongs elsewhere, so
/// that the same job gives the same `summary.json`, `placements.csv` and `report.html` bit for
/// bit, on one machine or merged from shards.
pub fn meta(
    robot: &RobotModel,
    path_file: &Path,
    objective: Objective,
    feas: &FeasibilityOptions,
    samples: usize,
) -> Vec<(String, String)> {
    vec![
        ("robot".into(), robot.name().to_string()),
        (
            "robot file".into(),
            crate::robot::robot_file_display(robot),
        ),
        (
            "drive data".into(),
            crate::robot::drive_data_status(robot),
        ),
        (
            "calibration".into(),
            robot
                .effects
                .calibration_summary()
                .unwrap_or_else(|| "none (nominal robot)".into()),
        ),
        ("path".into(), path_file.display().to_string()),
        (
            "objective".into(),
            // The name the command line takes (`mechanical_abs`), not the Rust variant.
            format!("{}: {}", objective.name(), objective.describe()),
        ),
        ("nominal path samples".into(), samples.to_string()),
        (
            "feasibility".into(),
            format!(
                "joint-limit margin {} deg, wrist margin {} deg, near the wrist singularity (|sin q5| < {}) joints 4/6 at most {:.0} % of their limits, elbow ≥ {}, shoulder ≥ {} m, collisions {} (every {} samples)",
                (0..robot.dof())
                    .map(|j| format!(
                        "{:.1}",
                        crate::evaluate::feasibility::margins::joint_margin(robot, feas, j).to_degrees()
                    ))
                    .collect::<Vec<_>>()
                    .join("/"),
                feas.wrist_margin_rad.to_degrees(),
                feas.wrist_min,
                feas.wrist_rate_max * 100.0,
                feas.elbow_min,
                feas.shoulder_min_m,
                if feas.collisions { "on" } else { "off" },
                feas.check_every
            ),
        ),
    ]
}

/// The commanded TCP speed of a path's printing moves in words: one speed, or the range and
/// the length-weighted mean, with the printed length ("150 mm/s over 5.71 m of printing").
pub(crate) fn print_speed_text(tp: &crate::toolpath::Toolpath) -> String {
    let (mut lo, mut hi, mut len, mut wsum) = (f64::INFINITY, 0.0f64, 0.0, 0.0);
    for (start, mv) in tp.segments().filter(|(_, m)| m.print) {
        let l = mv.length(&start);
        lo = lo.min(mv.speed);
        hi = hi.max(mv.speed);
        len += l;
        wsum += l * mv.speed;
    }
    if len <= 0.0 {
        return "no printing moves".into();
    }
    if hi - lo <= 1e-9 * hi {
        format!("{:.0} mm/s over {len:.2} m of printing", hi * 1000.0)
    } else {
        format!(
            "{:.0}–{:.0} mm/s ({:.0} mm/s length-weighted) over {len:.2} m of printing",
            lo * 1000.0,
            hi * 1000.0,
            wsum / len * 1000.0
        )
    }
}

/// An error in words as a front end shows it: the error, then each cause it does not end with
/// already, joined by `: `.
pub fn error_text(e: &(dyn std::error::Error + 'static)) -> String {
    let mut s = e.to_string();
    let mut cur = e.source();
    while let Some(c) = cur {
        let t = c.to_string();
        if !s.ends_with(&t) {
            s.push_str(": ");
            s.push_str(&t);
        }
        cur = c.source();
    }
    s
}
