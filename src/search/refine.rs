//! The refinement on [argmin]'s Nelder–Mead simplex, derivative-free and tolerant of a
//! feasibility-bounded objective (an infeasible placement costs +∞, which only ever loses a
//! comparison). The search runs over x, y, bed height z (continuous, within
//! [`Bounds`]), part yaw and nozzle spin, in units of their initial steps so that the simplex
//! is well scaled. It starts from a simplex around the best grid cell that holds the
//! placement [`Tolerance`] (the grid is the seed), and a candidate only becomes the answer once
//! all its tolerance corners are feasible (checked lazily, only for candidates that would
//! improve on the answer so far). An argmin observer reports each iteration (the progress bar).
//!
//! Evaluations are sequential on one thread (the tolerance corners in parallel), and
//! Nelder–Mead is deterministic, so the answer does not depend on the thread count.

use crate::error::{Error, Result};
use crate::evaluate::evaluator::{Evaluated, Evaluator, Scratch};
use crate::frame::Placement;
use crate::search::neldermead::{BatchCost, SpeculativeNelderMead};
use crate::search::optimise::{sensitivity_with_probes, OptimiseOptions, OptimiseResult};
use crate::search::tolerance::{Checker, Tolerance, ToleranceCheck};
use argmin::core::observers::{Observe, ObserverMode};
use argmin::core::{Executor, IterState, State, KV};
use serde::Serialize;
use std::cell::RefCell;
use std::sync::{Arc, Mutex};

/// Box bounds of the search (m); yaw and spin are unbounded angles.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Bounds {
    /// x range, m.
    pub x: [f64; 2],
    /// y range, m.
    pub y: [f64; 2],
    /// Bed height (z) range, m.
    pub z: [f64; 2],
}

impl Bounds {
    /// The box over `ps` in x and y, and in z over `z` (m, `[min, max]`) or else `ps`. Error:
    /// `z` not finite or min > max.
    pub fn over(ps: &[Placement], z: Option<[f64; 2]>) -> Result<Bounds> {
        let span = |f: &dyn Fn(&Placement) -> f64| {
            ps.iter()
                .map(f)
                .fold([f64::INFINITY, f64::NEG_INFINITY], |r, v| {
                    [r[0].min(v), r[1].max(v)]
                })
        };
        let z = match z {
            Some([a, b]) if a.is_finite() && b.is_finite() && a <= b => [a, b],
            Some([a, b]) => {
                return Err(Error::Invalid(format!(
                    "z bounds {a}…{b} m: expected finite min <= max"
                )))
            }
            None => span(&|p| p.z),
        };
        Ok(Bounds {
            x: span(&|p| p.x),
            y: span(&|p| p.y),
            z,
        })
    }

    /// Is `p` inside (closed box)?
    pub fn contains(&self, p: &Placement) -> bool {
        let inside = |v: f64, r: [f64; 2]| v >= r[0] - 1e-12 && v <= r[1] + 1e-12;
        inside(p.x, self.x) && inside(p.y, self.y) && inside(p.z, self.z)
    }

    /// The bounds `p` lies on (within `eps` m), named, e.g. "z max = 1.300 m". A bound of zero
    /// width (a fixed coordinate) is not reported.
    pub fn on_bounds(&self, p: &Placement, eps: f64) -> Vec<String> {
        let mut v = Vec::new();
        for (name, val, r) in [("x", p.x, self.x), ("y", p.y, self.y), ("z", p.z, self.z)] {
            if r[1] - r[0] <= eps {
                continue;
            }
            if (val - r[0]).abs() <= eps {
                v.push(format!("{name} min = {:.3} m", r[0]));
            }
            if (val - r[1]).abs() <= eps {
                v.push(format!("{name} max = {:.3} m", r[1]));
            }
        }
        v
    }
}

/// Progress of the search, as seen by the observer: (iteration, evaluations, best cost J).
pub type Progress = Arc<dyn Fn(u64, usize, f64) + Send + Sync>;

struct Obs {
    evals: Arc<Mutex<usize>>,
    report: Progress,
    /// Iterations completed (kept here: a run stopped by the evaluation budget returns an
    /// error, not its state).
    iterations: Arc<Mutex<usize>>,
}

impl Observe<IterState<Vec<f64>, (), (), (), (), f64>> for Obs {
    fn observe_iter(
        &mut self,
        state: &IterState<Vec<f64>, (), (), (), (), f64>,
        _kv: &KV,
    ) -> std::result::Result<(), argmin::core::Error> {
        let n = self.evals.lock().map(|g| *g).unwrap_or(0);
        if let Ok(mut it) = self.iterations.lock() {
            *it = (*it).max(state.get_iter() as usize);
        }
        (self.report)(state.get_iter(), n, state.get_best_cost());
        Ok(())
    }
}

struct Problem<'e, 'j, 'a> {
    ev: &'e Evaluator<'j, 'a>,
    sc: RefCell<Scratch<'a>>,
    origin: Placement,
    scale: [f64; 5],
    active: [bool; 5],
    bounds: Bounds,
    budget: usize,
    evals: Arc<Mutex<usize>>,
    visited: RefCell<Vec<Evaluated>>,
    history: RefCell<Vec<f64>>,
    /// Speculative evaluations that were not needed.
    speculative: RefCell<usize>,
}

const BUDGET: &str = "evaluation budget spent";

/// Candidates (best first) whose tolerance is checked after the simplex search.
const CANDIDATES: usize = 2;
/// Bisection steps between the grid seed and the best candidate when no candidate holds.
const BISECTIONS: usize = 4;

impl Problem<'_, '_, '_> {
    fn placement(&self, u: &[f64]) -> Placement {
        let mut d = [0.0; 5];
        let mut k = 0;
        for ((di, on), sc) in d.iter_mut().zip(self.active).zip(self.scale) {
            if on {
                *di = u[k] * sc;
                k += 1;
            }
        }
        Placement {
            x: self.origin.x + d[0],
            y: self.origin.y + d[1],
            z: self.origin.z + d[2],
            yaw: self.origin.yaw + d[3],
            nozzle_spin: self.origin.nozzle_spin + d[4],
        }
    }
}

/// The problem as argmin holds it (by reference, so that its state can be read afterwards).
struct ByRef<'p, 'e, 'j, 'a>(&'p Problem<'e, 'j, 'a>);

/// A point evaluated for the simplex, not yet counted.
enum Pending {
    /// Outside the search box: +∞, never evaluated, not counted.
    Outside,
    /// Evaluated.
    Done(Box<Evaluated>),
}

impl BatchCost for ByRef<'_, '_, '_, '_> {
    type Pending = Pending;

    fn evaluate(
        &self,
        points: &[Vec<f64>],
    ) -> std::result::Result<Vec<Pending>, argmin::core::Error> {
        let pr = self.0;
        let ps: Vec<Placement> = points.iter().map(|u| pr.placement(u)).collect();
        let inside: Vec<Placement> = ps
            .iter()
            .copied()
            .filter(|p| pr.bounds.contains(p))
            .collect();
        let mut done = if inside.len() == 1 {
            // One point: this thread, with the problem's own scratch.
            vec![pr.ev.evaluate(&mut pr.sc.borrow_mut(), &inside[0])]
        } else {
            pr.ev
                .sweep(&inside, &|_, _| {})
                .map_err(|e| argmin::core::Error::msg(e.to_string()))?
        }
        .into_iter();
        Ok(ps
            .iter()
            .map(|p| {
                if pr.bounds.contains(p) {
                    done.next()
                        .map_or(Pending::Outside, |e| Pending::Done(Box::new(e)))
                } else {
                    Pending::Outside
                }
            })
            .collect())
    }

    fn commit(&self, p: Pending) -> std::result::Result<f64, argmin::core::Error> {
        let pr = self.0;
        let e = match p {
            Pending::Outside => return Ok(f64::INFINITY),
            Pending::Done(e) => e,
        };
        {
            let mut n = pr
                .evals
                .lock()
                .map_err(|_| argmin::core::Error::msg("lock"))?;
            if *n >= pr.budget {
                return Err(argmin::core::Error::msg(BUDGET));
            }
            *n += 1;
        }
        let c = e.cost();
        let best = pr.history.borrow().last().copied().unwrap_or(f64::INFINITY);
        pr.history.borrow_mut().push(best.min(c));
        if c.is_finite() {
            pr.visited.borrow_mut().push(*e);
        }
        Ok(c)
    }

    fn parallel(&self) -> bool {
        rayon::current_num_threads() > 1
    }

    fn evaluate_guessed(
        &self,
        point: &[f64],
        guess: &[f64],
        needed_from: f64,
    ) -> std::result::Result<(Pending, Option<Pending>), argmin::core::Error> {
        let pr = self.0;
        let (p, g) = (pr.placement(point), pr.placement(guess));
        let one =
            |at: &Placement| Pending::Done(Box::new(pr.ev.evaluate(&mut pr.sc.borrow_mut(), at)));
        Ok(match (pr.bounds.contains(&p), pr.bounds.contains(&g)) {
            (true, true) => {
                // The guess is needed when the point costs at least `needed_from` (an
                // infeasible point costs +∞, as `commit` counts it).
                let (a, b) = pr
                    .ev
                    .evaluate_with_guess(&p, &g, &|e| e.cost() >= needed_from);
                (
                    Pending::Done(Box::new(a)),
                    b.map(|e| Pending::Done(Box::new(e))),
                )
            }
            // The point is outside (+∞): the guess is needed; one point, on this thread.
            (false, true) => (Pending::Outside, Some(one(&g))),
            (true, false) => (one(&p), Some(Pending::Outside)),
            (false, false) => (Pending::Outside, Some(Pending::Outside)),
        })
    }

    fn discarded(&self, p: Pending) {
        if let Pending::Done(_) = p {
            *self.0.speculative.borrow_mut() += 1;
        }
    }
}

/// What [`refine`] adds to the classic result: the tolerance the answer holds, the bounds it
/// lies on, the evaluations the tolerance checks took.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SearchInfo {
    /// "nelder-mead (argmin)" or "pattern".
    pub method: String,
    /// The tolerance check of the answer.
    pub tolerance: ToleranceCheck,
    /// Evaluations spent on tolerance corners (not counted in `evals`).
    pub tolerance_evals: usize,
    /// The search box.
    pub bounds: Bounds,
    /// Search bounds the answer lies on (named), e.g. "z max = 1.300 m": widen them.
    pub on_bounds: Vec<String>,
    /// Grid cells tried before one held the tolerance (1 = the best cell held it).
    pub grid_cells_tried: usize,
    /// Speculative evaluations the search made in parallel and did not need (extra work on a
    /// second core; 0 on one thread; not counted in `evals`; a guess abandoned part-way is not
    /// counted). A fact of the run, not of the
    /// answer (it depends on the thread count): not serialised into a run's summary, which is
    /// the same for 1 and 2 threads; the binary writes it to `run.json`.
    #[serde(skip)]
    pub speculative_evals: usize,
    /// The joint-limit margin the answer keeps, in words (closest joint, its distance from a
    /// limit and the margin).
    pub joint_margin: Option<String>,
    /// The wrist margin the answer keeps, in words (its closest approach of q5 to the wrist
    /// singularity over every sample and the margin; or that passing through is allowed).
    #[serde(default)]
    pub wrist_margin: Option<String>,
    /// The answer lies on a joint-limit margin (within 0.01°): named like a search bound.
    pub on_margin: Option<String>,
    /// Set when the energy does not depend on the nozzle spin at the answer (no difference at
    /// the printed digits) and the search's spin was replaced by the start's: says so.
    pub spin_kept: Option<String>,
    /// Set when Nelder–Mead stopped because it had used its evaluation budget, not because its
    /// simplex converged: its best point is where the budget ran out (the polish may still move
    /// the answer from there), and more evaluations may move it. Says so, with the budget and
    /// the energy the simplex gained from the start cell.
    pub budget_spent: Option<String>,
    /// Set when a sensitivity probe (±h in x or y) of the search's answer cost less and held
    /// the tolerance, so the answer moved there: how many steps, which way, how many J.
    pub polished: Option<String>,
    /// The answer's sensitivity probes that cost less than the answer but are not it, each
    /// with the reason (its tolerance box does not hold, it lies outside the search box).
    pub lower_neighbours: Vec<String>,
}

/// Options of the argmin refinement beyond [`OptimiseOptions`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SearchOptions {
    /// Search box.
    pub bounds: Bounds,
    /// Tolerance the answer must hold.
    pub tolerance: Tolerance,
    /// Initial simplex step in z, m.
    pub step_z_m: f64,
    /// Search z (bed height).
    pub z: bool,
    /// Grid cells tried (best first) for one that holds the tolerance.
    pub max_start_cells: usize,
}

impl SearchOptions {
    /// The options `printwatt optimise` uses in `bounds` with `tolerance`: a first simplex step
    /// in z of a quarter of the z range (at least 10 mm), z searched when its range is not
    /// empty, and up to 20 grid cells tried for a start that holds the tolerance.
    pub fn new(bounds: Bounds, tolerance: Tolerance) -> SearchOptions {
        SearchOptions {
            bounds,
            tolerance,
            step_z_m: ((bounds.z[1] - bounds.z[0]) / 4.0).max(0.01),
            z: bounds.z[1] > bounds.z[0],
            max_start_cells: 20,
        }
    }
}

/// The grid's feasible cells in cost order (ties to the first).
fn ranked(grid: &[Evaluated]) -> Vec<&Evaluated> {
    let mut v: Vec<(usize, &Evaluated)> = grid
        .iter()
        .enumerate()
        .filter(|(_, e)| e.cost().is_finite())
        .collect();
    v.sort_by(|a, b| a.1.cost().total_cmp(&b.1.cost()).then(a.0.cmp(&b.0)));
    v.into_iter().map(|(_, e)| e).collect()
}

/// Refine with Nelder–Mead from the best grid cell that holds the tolerance. `progress` is
/// called by the argmin observer after each iteration. Errors: no feasible grid cell; a model
/// error.
pub fn refine(
    ev: &Evaluator,
    grid: &[Evaluated],
    opts: &OptimiseOptions,
    so: &SearchOptions,
    progress: Progress,
) -> Result<(OptimiseResult, SearchInfo)> {
    refine_with(ev, grid, opts, so, progress, Checker::new(ev, so.tolerance))
}

/// [`refine`] with every tolerance check made in full and every placement evaluated each time
/// it is asked for ([`Checker::plain`]): the refinement as it was before the fast checks, the
/// reference that `tests/placement_search.rs` and `benches/optimise.rs` compare with. The
/// answer is the same; only the evaluation count differs.
pub fn refine_plain(
    ev: &Evaluator,
    grid: &[Evaluated],
    opts: &OptimiseOptions,
    so: &SearchOptions,
    progress: Progress,
) -> Result<(OptimiseResult, SearchInfo)> {
    refine_with(
        ev,
        grid,
        opts,
        so,
        progress,
        Checker::plain(ev, so.tolerance),
    )
}

fn refine_with(
    ev: &Evaluator,
    grid: &[Evaluated],
    opts: &OptimiseOptions,
    so: &SearchOptions,
    progress: Progress,
    checker: Checker,
) -> Result<(OptimiseResult, SearchInfo)> {
    let cells = ranked(grid);
    if cells.is_empty() {
        return Err(Error::Invalid(
            "no feasible placement in the grid: nothing to refine".into(),
        ));
    }
    let (start, start_chk, robust_start, tried) = seed_cell(&cells, so, &checker)?;
    let problem = Problem::around(ev, &start, opts, so)?;
    let (iterations, converged) = if robust_start && opts.max_evals > problem.dim() {
        problem.nelder_mead(opts, progress)?
    } else {
        (0, true)
    };
    let used = *problem
        .evals
        .lock()
        .map_err(|_| Error::Invalid("lock".into()))?;
    let mut best = held_answer(&problem, &checker, &start, start_chk, robust_start)?;
    let spin_kept = keep_start_spin(&checker, opts, &start, &mut best)?;
    let budget_spent = (!converged).then(|| {
        format!(
            "Nelder–Mead used its {} evaluations before its simplex converged: its best point is where the budget ran out ({:.1} J below the start cell's {:.1} J); a larger evaluation budget may still move it",
            opts.max_evals,
            start.cost() - best.0.cost(),
            start.cost()
        )
    });
    let (best, chk, sens, polish) = polish(ev, &checker, so, opts, best)?;
    let speculative = *problem.speculative.borrow() + checker.speculative();
    let tol_evals = checker.evaluations();
    let on_bounds = so.bounds.on_bounds(&best.placement, 0.005);
    let (joint_margin, wrist_margin, on_margin) = margin_lines(ev, &best);
    let history = problem.history.borrow().clone();
    Ok((
        OptimiseResult {
            best,
            best_grid: cells[0].clone(),
            evals: used,
            iterations,
            history_j: history,
            sensitivity: sens,
            search: None,
            savings: None,
            baseline_tolerance: None,
            uncertainty: None,
            decision: None,
            path_reduction: None,
        },
        SearchInfo {
            method: "nelder-mead (argmin)".into(),
            tolerance: chk,
            tolerance_evals: tol_evals,
            bounds: so.bounds,
            on_bounds,
            grid_cells_tried: tried,
            speculative_evals: speculative,
            joint_margin,
            wrist_margin,
            on_margin,
            spin_kept,
            budget_spent,
            polished: polish.moved,
            lower_neighbours: polish.lower,
        },
    ))
}

/// The seed: the best grid cell whose tolerance corners are all feasible (else the best cell,
/// with its failed check). Every tolerance check and single evaluation of the refinement goes
/// through `checker` (first failure stops a check; nothing is evaluated twice). With whether
/// the seed holds its tolerance and how many cells were tried.
fn seed_cell(
    cells: &[&Evaluated],
    so: &SearchOptions,
    checker: &Checker,
) -> Result<(Evaluated, ToleranceCheck, bool, usize)> {
    let mut start: Option<(Evaluated, ToleranceCheck)> = None;
    let mut tried = 0;
    let mut first_check = None;
    for c in cells.iter().take(so.max_start_cells.max(1)) {
        tried += 1;
        let chk = checker.check(&c.placement)?;
        if chk.holds {
            start = Some(((*c).clone(), chk));
            break;
        }
        first_check.get_or_insert(chk);
    }
    let robust_start = start.is_some();
    let (start, start_chk) = match start {
        Some(s) => s,
        // None holds: refine from the best cell and say that the tolerance is not held.
        None => (
            cells[0].clone(),
            first_check.expect("at least one cell was checked"),
        ),
    };
    Ok((start, start_chk, robust_start, tried))
}

impl<'e, 'j, 'a> Problem<'e, 'j, 'a> {
    /// The search around `start`: the coordinates searched and their first steps, the budget.
    fn around(
        ev: &'e Evaluator<'j, 'a>,
        start: &Evaluated,
        opts: &OptimiseOptions,
        so: &SearchOptions,
    ) -> Result<Self> {
        let active = [true, true, so.z, opts.yaw, opts.spin];
        let scale = [
            opts.step_xy_m,
            opts.step_xy_m,
            so.step_z_m,
            opts.step_angle_rad,
            opts.step_angle_rad,
        ];
        Ok(Problem {
            ev,
            sc: RefCell::new(ev.scratch()?),
            origin: start.placement,
            scale,
            active,
            bounds: so.bounds,
            budget: opts.max_evals,
            evals: Arc::new(Mutex::new(0usize)),
            visited: RefCell::new(Vec::new()),
            history: RefCell::new(vec![start.cost()]),
            speculative: RefCell::new(0),
        })
    }

    /// How many coordinates are searched.
    fn dim(&self) -> usize {
        self.active.iter().filter(|a| **a).count()
    }

    /// Nelder–Mead from the grid cell (argmin, with the evaluation budget): its iterations and
    /// whether its simplex converged.
    fn nelder_mead(&self, opts: &OptimiseOptions, progress: Progress) -> Result<(usize, bool)> {
        let dim = self.dim();
        // Initial simplex: the grid cell and one step along each searched coordinate.
        let mut simplex = vec![vec![0.0; dim]];
        for k in 0..dim {
            let mut v = vec![0.0; dim];
            v[k] = 1.0;
            simplex.push(v);
        }
        let solver = SpeculativeNelderMead::new(simplex)
            .with_sd_tolerance(1e-6)
            .map_err(|e| Error::Invalid(format!("Nelder–Mead: {e}")))?;
        let done_iters = Arc::new(Mutex::new(0usize));
        let obs = Obs {
            evals: self.evals.clone(),
            report: progress,
            iterations: done_iters.clone(),
        };
        let r = Executor::new(ByRef(self), solver)
            .configure(|s| s.max_iters(opts.max_evals as u64))
            .add_observer(obs, ObserverMode::Always)
            .run();
        match r {
            Ok(res) => Ok((
                res.state().get_iter() as usize,
                matches!(
                    res.state().get_termination_reason(),
                    Some(argmin::core::TerminationReason::SolverConverged)
                ),
            )),
            Err(e) if e.to_string().contains(BUDGET) => {
                Ok((done_iters.lock().map(|g| *g).unwrap_or(0), false))
            }
            Err(e) => Err(Error::Invalid(format!("Nelder–Mead: {e}"))),
        }
    }
}

/// The answer must hold the tolerance: the best candidates the search visited first, else the
/// best placement on the segment from the (tolerance-holding) seed toward the best candidate,
/// else the seed.
fn held_answer(
    problem: &Problem,
    checker: &Checker,
    start: &Evaluated,
    start_chk: ToleranceCheck,
    robust_start: bool,
) -> Result<(Evaluated, ToleranceCheck)> {
    let mut best = (start.clone(), start_chk);
    let mut cands: Vec<Evaluated> = problem
        .visited
        .borrow()
        .iter()
        .filter(|e| e.cost() < start.cost())
        .cloned()
        .collect();
    cands.sort_by(|a, b| a.cost().total_cmp(&b.cost()));
    for c in cands.iter().take(CANDIDATES) {
        let chk = checker.check(&c.placement)?;
        if chk.holds {
            return Ok((c.clone(), chk));
        }
    }
    if robust_start {
        if let Some(target) = cands.first() {
            bisect_toward(checker, start.placement, target.placement, &mut best)?;
        }
    }
    Ok(best)
}

/// Bisection on the segment from `s0` toward `s1`: a point cheaper than `best` that holds its
/// tolerance becomes `best`; the search moves on toward `s1` from each feasible point.
fn bisect_toward(
    checker: &Checker,
    s0: Placement,
    s1: Placement,
    best: &mut (Evaluated, ToleranceCheck),
) -> Result<()> {
    let at = |t: f64| Placement {
        x: s0.x + t * (s1.x - s0.x),
        y: s0.y + t * (s1.y - s0.y),
        z: s0.z + t * (s1.z - s0.z),
        yaw: s0.yaw + t * (s1.yaw - s0.yaw),
        nozzle_spin: s0.nozzle_spin + t * (s1.nozzle_spin - s0.nozzle_spin),
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..BISECTIONS {
        let t = 0.5 * (lo + hi);
        let p = at(t);
        let e = checker.evaluate(&p, true)?;
        let ok = if e.cost() < best.0.cost() {
            let chk = checker.check(&p)?;
            if chk.holds {
                *best = (e, chk);
                true
            } else {
                false
            }
        } else {
            e.cost().is_finite()
        };
        if ok {
            lo = t;
        } else {
            hi = t;
        }
    }
    Ok(())
}

/// A nozzle spin the energy does not depend on (a round nozzle whose spin only shifts
/// joint 6 by a constant) is not an answer: Nelder–Mead would pick it from rounding noise.
/// Where the start's spin gives the same energy (no difference at the printed digits,
/// [`crate::numerics::difference`]) and holds the tolerance, the start's spin is kept in
/// `best`; says so.
fn keep_start_spin(
    checker: &Checker,
    opts: &OptimiseOptions,
    start: &Evaluated,
    best: &mut (Evaluated, ToleranceCheck),
) -> Result<Option<String>> {
    if !(opts.spin && best.0.placement.nozzle_spin != start.placement.nozzle_spin) {
        return Ok(None);
    }
    let p = Placement {
        nozzle_spin: start.placement.nozzle_spin,
        ..best.0.placement
    };
    let e = checker.evaluate(&p, true)?;
    if e.cost().is_finite() && crate::numerics::difference(e.cost(), best.0.cost()) == 0.0 {
        let chk = checker.check(&p)?;
        if chk.holds || !best.1.holds {
            let kept = format!(
                "the energy does not depend on the nozzle spin here ({:.1}° and {:.1}° give the same energy): the spin is kept at {:.1}°",
                best.0.placement.nozzle_spin.to_degrees(),
                p.nozzle_spin.to_degrees(),
                p.nozzle_spin.to_degrees()
            );
            *best = (e, chk);
            return Ok(Some(kept));
        }
    }
    Ok(None)
}

/// The joint-limit margin the answer keeps, its wrist margin, and the joint-limit margin it
/// lies on, in words.
fn margin_lines(
    ev: &Evaluator,
    best: &Evaluated,
) -> (Option<String>, Option<String>, Option<String>) {
    let stmt = best.feasible().and_then(|f| {
        crate::evaluate::feasibility::margins::margin_statement(
            ev.job.robot,
            &ev.feasibility,
            &f.margins,
        )
    });
    let joint_margin = stmt.as_ref().map(|s| s.0.clone());
    let wrist_margin = best.feasible().and_then(|f| {
        crate::evaluate::feasibility::margins::wrist_statement(&ev.feasibility, &f.margins)
    });
    let on_margin = stmt.filter(|s| s.1).map(|s| s.0);
    (joint_margin, wrist_margin, on_margin)
}

/// At most this many compass steps of [`polish`].
const POLISH_STEPS: usize = 8;

/// What [`polish`] did and saw.
struct Polish {
    moved: Option<String>,
    lower: Vec<String>,
}

/// The answer's own sensitivity probes ([`crate::search::optimise::probes`], ±h in x and y) as a last
/// compass step: a probe that costs less than the answer, lies in the search box and holds
/// the tolerance is a better answer, so the answer moves there and is probed again (at most
/// [`POLISH_STEPS`] times). A cheaper probe that does not hold the tolerance, or lies outside
/// the box, is named with the reason, so that no printed neighbour contradicts the answer
/// unexplained. Skipped (probes only) when the answer itself does not hold the tolerance.
#[allow(clippy::type_complexity)]
fn polish(
    ev: &Evaluator,
    checker: &Checker,
    so: &SearchOptions,
    opts: &OptimiseOptions,
    start: (Evaluated, ToleranceCheck),
) -> Result<(
    Evaluated,
    ToleranceCheck,
    crate::search::optimise::Sensitivity,
    Polish,
)> {
    use crate::search::optimise::{probes, PROBE_NAMES};
    let h = opts.sensitivity_m;
    let (mut best, mut chk) = start;
    let e_stop = best.cost();
    let mut steps: Vec<&str> = Vec::new();
    loop {
        let (sens, evaluated) = sensitivity_with_probes(ev, &best, h)?;
        let e0 = best.cost();
        let mut lower: Vec<(usize, f64)> = (0..4)
            .filter_map(|i| sens.e_j[i].filter(|&e| e < e0).map(|e| (i, e)))
            .collect();
        lower.sort_by(|a, b| a.1.total_cmp(&b.1));
        let ps = probes(&best.placement, h);
        let mut refused = Vec::new();
        let mut next = None;
        for &(i, e) in &lower {
            let why = if !chk.holds {
                "the answer itself does not hold the tolerance".to_string()
            } else if !so.bounds.contains(&ps[i]) {
                "it lies outside the search box".to_string()
            } else if steps.len() >= POLISH_STEPS {
                format!("the polish stopped after {POLISH_STEPS} steps")
            } else {
                let c = checker.check(&ps[i])?;
                if c.holds {
                    next = Some((i, c));
                    break;
                }
                format!(
                    "its tolerance box does not hold ({})",
                    c.failures.first().map_or("a corner is infeasible", |f| f)
                )
            };
            refused.push(format!(
                "E({}) {e:.1} J is below the answer's {e0:.1} J, but {why}",
                PROBE_NAMES[i]
            ));
        }
        match next {
            Some((i, c)) => {
                // The probe the sensitivity has just evaluated, not evaluated again.
                best = checker.adopt(&evaluated[i])?;
                chk = c;
                steps.push(PROBE_NAMES[i]);
            }
            None => {
                let moved = (!steps.is_empty()).then(|| {
                    format!(
                        "the answer moved {} of {:.0} mm ({}) to a cheaper neighbour that holds the tolerance: {:.1} J below where the search stopped",
                        if steps.len() == 1 { "1 step".to_string() } else { format!("{} steps", steps.len()) },
                        h * 1000.0,
                        steps.join(", "),
                        e_stop - best.cost()
                    )
                });
                return Ok((
                    best,
                    chk,
                    sens,
                    Polish {
                        moved,
                        lower: refused,
                    },
                ));
            }
        }
    }
}
