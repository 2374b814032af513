//! Prune before tracking, and the argmin search (it runs
//! its evaluations in parallel and stays deterministic).

use argmin::core::{CostFunction, Executor, IterState, Problem, State};
use printwatt::energy::EnergyOptions;
use printwatt::evaluate::{Evaluated, Evaluator, FeasibilityOptions, Objective, PathJob};
use printwatt::robot::{self, RobotModel};
use printwatt::search::neldermead::{BatchCost, SpeculativeNelderMead};
use printwatt::search::optimise::{default_grid, OptimiseOptions};
use printwatt::search::refine::{self, Bounds, SearchOptions};
use printwatt::search::tolerance::Tolerance;
use printwatt::search::Grid;
use printwatt::timing::{JointStageOptions, ProfileOptions};
use printwatt::toolpath::{self, Placement, ReadOptions, Toolpath};
use std::cell::RefCell;
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn load(robot_id: &str, path: &str) -> (RobotModel, Toolpath) {
    let model = robot::load(&root().join("robots").join(robot_id)).unwrap();
    let tp = toolpath::load(&root().join("paths").join(path), &ReadOptions::default()).unwrap();
    (model, tp)
}

fn job<'a>(model: &'a RobotModel, tp: &Toolpath, prune_stride: usize) -> PathJob<'a> {
    PathJob::new(
        model,
        tp,
        EnergyOptions::default(),
        ProfileOptions::default(),
        JointStageOptions {
            prune_stride,
            ..Default::default()
        },
    )
    .unwrap()
}

fn pool(n: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .unwrap()
}

/// Sweep `ps` with and without pruning; every feasible result must be identical (energies,
/// times, margins) and every infeasible one must stay infeasible. Returns (feasible,
/// infeasible) counts.
fn same_with_and_without_pruning(robot_id: &str, path: &str, ps: &[Placement]) -> (usize, usize) {
    let (model, tp) = load(robot_id, path);
    let (jp, ju) = (job(&model, &tp, 8), job(&model, &tp, 0));
    let feas = FeasibilityOptions::default();
    let pruned = Evaluator::new(&jp, feas, Objective::Supply)
        .sweep(ps, &|_, _| {})
        .unwrap();
    let unpruned = Evaluator::new(&ju, feas, Objective::Supply)
        .sweep(ps, &|_, _| {})
        .unwrap();
    let mut n = (0, 0);
    for (a, b) in pruned.iter().zip(&unpruned) {
        assert_eq!(a.placement, b.placement);
        match (&a.outcome, &b.outcome) {
            (Ok(x), Ok(y)) => {
                assert_eq!(x, y, "{robot_id} {path} at {:?}", a.placement);
                assert_eq!(x.energy_j.to_bits(), y.energy_j.to_bits());
                n.0 += 1;
            }
            (Err(_), Err(_)) => n.1 += 1,
            _ => panic!(
                "{robot_id} {path} at {:?}: pruned {:?} but unpruned {:?}",
                a.placement,
                a.outcome.as_ref().map(|f| f.energy_j),
                b.outcome.as_ref().map(|f| f.energy_j)
            ),
        }
    }
    n
}

#[test]
fn pruned_and_unpruned_evaluation_agree_on_shipped_examples() {
    // The main job's default grid (every other of its 1536 placements; 38 are feasible).
    let (model, _) = load("abb_irb6700_200_260", "default.gcode");
    let ps: Vec<Placement> = default_grid(printwatt::evaluate::feasibility::reach_m(&model))
        .placements()
        .into_iter()
        .step_by(2)
        .collect();
    let (f, i) = same_with_and_without_pruning("abb_irb6700_200_260", "default.gcode", &ps);
    assert!(f >= 10 && i >= 700, "{f} feasible, {i} infeasible");
    // The README's IRB 4600 wall example and seed 000's path on a coarser grid.
    let g = Grid {
        xs: vec![0.9, 1.3, 1.7, 2.1],
        ys: vec![-0.5, 0.0, 0.5],
        zs: vec![0.3],
        yaws: vec![0.0, std::f64::consts::FRAC_PI_2],
        spins: vec![0.0],
    };
    let (f, i) = same_with_and_without_pruning(
        "abb_irb4600_40_255",
        "wall_multilayer.gcode",
        &g.placements(),
    );
    assert!(f >= 5 && i >= 2, "{f} feasible, {i} infeasible");
    let (f, i) = same_with_and_without_pruning(
        "abb_irb6700_200_260",
        "seed000_test_path.gcode",
        &g.placements(),
    );
    assert!(f >= 1 && i >= 1, "{f} feasible, {i} infeasible");
    // Seed 001 on the TX200 (a different OPW geometry).
    let g = Grid {
        xs: (0..6).map(|i| 0.4 + 0.3 * i as f64).collect(),
        ys: vec![-0.8, 0.0, 0.8],
        zs: vec![-0.4, 0.0],
        yaws: vec![0.0],
        spins: vec![0.0],
    };
    let (f, i) =
        same_with_and_without_pruning("staubli_tx200", "seed001_y2x2y_r8.gcode", &g.placements());
    assert!(f >= 1 && i >= 1, "{f} feasible, {i} infeasible");
}

// --- The speculative Nelder–Mead against argmin's own -----------------------------------

/// A test function: Rosenbrock in 3-D, +∞ on a half-space (an "infeasible" region), so that
/// every kind of step (expansion, both contractions, shrink) occurs.
fn f(u: &[f64]) -> f64 {
    if u[0] + u[1] > 2.5 {
        return f64::INFINITY;
    }
    (0..u.len() - 1)
        .map(|i| 100.0 * (u[i + 1] - u[i] * u[i]).powi(2) + (1.0 - u[i]).powi(2))
        .sum()
}

struct Plain(RefCell<Vec<Vec<f64>>>);
impl CostFunction for Plain {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, u: &Vec<f64>) -> Result<f64, argmin::core::Error> {
        self.0.borrow_mut().push(u.clone());
        Ok(f(u))
    }
}

struct Batched(RefCell<Vec<Vec<f64>>>, RefCell<usize>);
impl BatchCost for Batched {
    type Pending = (Vec<f64>, f64);
    fn evaluate(&self, ps: &[Vec<f64>]) -> Result<Vec<(Vec<f64>, f64)>, argmin::core::Error> {
        use rayon::prelude::*;
        Ok(ps.par_iter().map(|u| (u.clone(), f(u))).collect())
    }
    fn commit(&self, p: (Vec<f64>, f64)) -> Result<f64, argmin::core::Error> {
        self.0.borrow_mut().push(p.0);
        Ok(p.1)
    }
    fn parallel(&self) -> bool {
        rayon::current_num_threads() > 1
    }
    fn discarded(&self, _p: (Vec<f64>, f64)) {
        *self.1.borrow_mut() += 1;
    }
}

fn simplex() -> Vec<Vec<f64>> {
    vec![
        vec![-1.2, 1.0, 0.5],
        vec![-0.7, 1.0, 0.5],
        vec![-1.2, 1.5, 0.5],
        vec![-1.2, 1.0, 1.0],
    ]
}

#[test]
fn speculative_nelder_mead_takes_the_steps_of_argmins_nelder_mead() {
    let iters = 400;
    let reference = Plain(RefCell::new(Vec::new()));
    let solver = argmin::solver::neldermead::NelderMead::new(simplex())
        .with_sd_tolerance(1e-10)
        .unwrap();
    let r = Executor::new(reference, solver)
        .configure(|s| s.max_iters(iters))
        .run()
        .unwrap();
    let ref_best = r.state().get_best_param().unwrap().clone();
    let ref_iters = r.state().get_iter();
    let ref_calls = r.problem.problem.as_ref().unwrap().0.borrow().clone();
    assert!(ref_calls.len() > 100, "a long enough run");
    for threads in [1, 2] {
        let (best, it, calls, spec) = pool(threads).install(|| {
            let solver = SpeculativeNelderMead::new(simplex())
                .with_sd_tolerance(1e-10)
                .unwrap();
            let r = Executor::new(Batched(RefCell::new(Vec::new()), RefCell::new(0)), solver)
                .configure(|s| s.max_iters(iters))
                .run()
                .unwrap();
            let st: &IterState<Vec<f64>, (), (), (), (), f64> = r.state();
            let p: &Problem<Batched> = &r.problem;
            let b = p.problem.as_ref().unwrap();
            let out = (
                st.get_best_param().unwrap().clone(),
                st.get_iter(),
                b.0.borrow().clone(),
                *b.1.borrow(),
            );
            out
        });
        assert_eq!(it, ref_iters, "{threads} threads");
        assert_eq!(
            calls, ref_calls,
            "{threads} threads: the same points in the same order"
        );
        assert_eq!(best, ref_best);
        if threads == 1 {
            assert_eq!(spec, 0, "no speculation on one thread");
        } else {
            assert!(spec > 0 && spec < calls.len(), "{spec} guesses discarded");
        }
    }
}

#[test]
fn argmin_search_is_bit_identical_with_one_and_two_threads() {
    let (model, tp) = load("abb_irb6700_200_260", "default.gcode");
    let j = job(&model, &tp, 8);
    let ev = Evaluator::new(&j, FeasibilityOptions::default(), Objective::Supply);
    let g = Grid {
        xs: vec![1.4, 1.5, 1.6],
        ys: vec![-0.1, 0.1],
        zs: vec![0.4, 0.6],
        yaws: vec![std::f64::consts::FRAC_PI_2],
        spins: vec![0.0],
    };
    let grid = ev.sweep(&g.placements(), &|_, _| {}).unwrap();
    let so = SearchOptions {
        bounds: Bounds {
            x: [1.4, 1.6],
            y: [-0.1, 0.1],
            z: [0.4, 0.6],
        },
        tolerance: Tolerance::default(),
        step_z_m: 0.05,
        z: true,
        max_start_cells: 5,
    };
    let opts = OptimiseOptions {
        max_evals: 30,
        ..Default::default()
    };
    let run = |n: usize| {
        pool(n).install(|| {
            refine::refine(&ev, &grid, &opts, &so, std::sync::Arc::new(|_, _, _| {})).unwrap()
        })
    };
    let (a, ia) = run(1);
    let (b, ib) = run(2);
    let best_grid = grid
        .iter()
        .map(Evaluated::cost)
        .fold(f64::INFINITY, f64::min);
    assert!(a.best.cost() <= best_grid);
    assert_eq!(a.best.placement, b.best.placement);
    assert_eq!(a.best.cost().to_bits(), b.best.cost().to_bits());
    assert_eq!(a.evals, b.evals);
    assert_eq!(a.history_j, b.history_j);
    // Everything but the count of unused speculative guesses (none on one thread) is equal.
    assert_eq!(ia.speculative_evals, 0);
    let (mut ia, mut ib) = (ia, ib);
    ia.speculative_evals = 0;
    ib.speculative_evals = 0;
    assert_eq!(ia, ib);
    assert_eq!(
        format!("{:?}", a.sensitivity),
        format!("{:?}", b.sensitivity)
    );
}

/// [`Batched`] that drops a guess the step does not need (as the placement search does: its
/// evaluation abandoned part-way), counting the drops.
struct Abandoning(RefCell<Vec<Vec<f64>>>, RefCell<usize>);
impl BatchCost for Abandoning {
    type Pending = (Vec<f64>, f64);
    fn evaluate(&self, ps: &[Vec<f64>]) -> Result<Vec<(Vec<f64>, f64)>, argmin::core::Error> {
        Ok(ps.iter().map(|u| (u.clone(), f(u))).collect())
    }
    fn commit(&self, p: (Vec<f64>, f64)) -> Result<f64, argmin::core::Error> {
        self.0.borrow_mut().push(p.0);
        Ok(p.1)
    }
    fn parallel(&self) -> bool {
        true
    }
    fn evaluate_guessed(
        &self,
        point: &[f64],
        guess: &[f64],
        needed_from: f64,
    ) -> Result<((Vec<f64>, f64), Option<(Vec<f64>, f64)>), argmin::core::Error> {
        let c = f(point);
        let g = if c >= needed_from {
            Some((guess.to_vec(), f(guess)))
        } else {
            *self.1.borrow_mut() += 1;
            None
        };
        Ok(((point.to_vec(), c), g))
    }
}

#[test]
fn speculative_nelder_mead_that_abandons_unneeded_guesses_takes_argmins_steps() {
    // The guess (the inside contraction) is dropped whenever the reflected point is below the
    // worst vertex: exactly when the step does not take it. The points asked for, in order,
    // and the answer are still those of argmin's solver.
    let iters = 400;
    let solver = argmin::solver::neldermead::NelderMead::new(simplex())
        .with_sd_tolerance(1e-10)
        .unwrap();
    let r = Executor::new(Plain(RefCell::new(Vec::new())), solver)
        .configure(|s| s.max_iters(iters))
        .run()
        .unwrap();
    let ref_best = r.state().get_best_param().unwrap().clone();
    let ref_calls = r.problem.problem.as_ref().unwrap().0.borrow().clone();
    let solver = SpeculativeNelderMead::new(simplex())
        .with_sd_tolerance(1e-10)
        .unwrap();
    let r = Executor::new(
        Abandoning(RefCell::new(Vec::new()), RefCell::new(0)),
        solver,
    )
    .configure(|s| s.max_iters(iters))
    .run()
    .unwrap();
    let b = r.problem.problem.as_ref().unwrap();
    assert_eq!(
        *b.0.borrow(),
        ref_calls,
        "the same points in the same order"
    );
    assert_eq!(r.state().get_best_param().unwrap(), &ref_best);
    assert!(*b.1.borrow() > 10, "{} guesses dropped", b.1.borrow());
}

#[test]
fn an_evaluation_beside_a_guess_is_the_plain_evaluation_and_an_unwanted_guess_is_dropped() {
    // Evaluator::evaluate_with_guess (the search's reflected point with its guess beside it,
    // each placement's checks and energy integration at once where a thread is free): the
    // first placement and a wanted guess are evaluated bit for bit as a sweep evaluates them,
    // an unwanted guess is dropped, on 1 and 2 threads; feasible, infeasible after the
    // timing (a joint-limit margin) and unreachable placements.
    let (model, tp) = load("abb_irb6700_200_260", "default.gcode");
    let j = job(&model, &tp, 8);
    let ev = Evaluator::new(&j, FeasibilityOptions::default(), Objective::Supply);
    let y90 = std::f64::consts::FRAC_PI_2;
    // A tolerance corner of the grid cell beside the answer fails on the joint-3 margin.
    let corners = Tolerance::default().corners(&Placement::new(1.43, 0.121, 0.0, y90));
    let margin = pool(2)
        .install(|| ev.sweep(&corners, &|_, _| {}).unwrap())
        .into_iter()
        .find(|e| {
            e.outcome.as_ref().err().map(|x| x.reason)
                == Some(printwatt::evaluate::feasibility::Reason::JointLimitMargin)
        })
        .expect("a corner on the joint-limit margin")
        .placement;
    let ps = [
        Placement::new(1.534, 0.121, 0.0, y90),
        margin,
        Placement::new(0.5, -2.0, 0.0, 0.0),
    ];
    let plain = pool(1).install(|| ev.sweep(&ps, &|_, _| {}).unwrap());
    assert!(plain[0].cost().is_finite());
    assert!(
        plain[1..].iter().all(|e| !e.cost().is_finite()),
        "{:?}",
        plain
            .iter()
            .map(|e| e.outcome.as_ref().err())
            .collect::<Vec<_>>()
    );
    for threads in [1, 2] {
        pool(threads).install(|| {
            for (i, a) in ps.iter().enumerate() {
                for (k, b) in ps.iter().enumerate() {
                    for want in [true, false] {
                        let (ea, eb) = ev.evaluate_with_guess(a, b, &|_| want);
                        assert_eq!(ea, plain[i], "{threads} threads");
                        assert_eq!(ea.cost().to_bits(), plain[i].cost().to_bits());
                        assert_eq!(eb.as_ref(), want.then_some(&plain[k]));
                    }
                }
            }
        });
    }
}

#[test]
fn a_sweep_until_the_first_infeasible_placement_gives_every_evaluation_up_to_it_bit_for_bit() {
    // Evaluator::sweep_until (a tolerance check's corners: each thread takes the next corner
    // as it is free; the first infeasible one abandons those after it): every entry up to the
    // first accepted placement is the plain evaluation bit for bit, on 1 and 2 threads; on one
    // thread nothing after it is evaluated; an entry after it, when present, is the plain
    // evaluation too; with none accepted, every entry is there.
    let (model, tp) = load("abb_irb6700_200_260", "default.gcode");
    let j = job(&model, &tp, 8);
    let ev = Evaluator::new(&j, FeasibilityOptions::default(), Objective::Supply);
    let y90 = std::f64::consts::FRAC_PI_2;
    let feasible = [
        Placement::new(1.534, 0.121, 0.0, y90),
        Placement::new(1.534, -0.121, 0.0, y90),
        Placement::new(1.44, 0.121, 0.0, y90),
    ];
    let unreachable = Placement::new(0.5, -2.0, 0.0, 0.0);
    let mut ps = feasible.to_vec();
    ps.push(unreachable);
    ps.extend(feasible);
    let plain = pool(1).install(|| ev.sweep(&ps, &|_, _| {}).unwrap());
    assert!(plain[..3].iter().all(|e| e.cost().is_finite()));
    assert!(!plain[3].cost().is_finite());
    let infeasible = |e: &Evaluated| !e.cost().is_finite();
    for threads in [1, 2] {
        pool(threads).install(|| {
            let r = ev.sweep_until(&ps, &infeasible).unwrap();
            assert_eq!(r.len(), ps.len());
            for k in 0..=3 {
                assert_eq!(
                    r[k].as_ref(),
                    Some(&plain[k]),
                    "{threads} threads, entry {k}"
                );
            }
            for (k, e) in r.iter().enumerate().skip(4) {
                if threads == 1 {
                    assert!(
                        e.is_none(),
                        "one thread: entry {k} evaluated after the first"
                    );
                }
                if let Some(e) = e {
                    assert_eq!(e, &plain[k]);
                }
            }
            let all = ev.sweep_until(&feasible, &infeasible).unwrap();
            assert_eq!(
                all.into_iter().map(Option::unwrap).collect::<Vec<_>>(),
                plain[..3].to_vec()
            );
            assert!(ev.sweep_until(&[], &infeasible).unwrap().is_empty());
        });
    }
}

// --- Fast tolerance checks (`optimise` faster, same answer) ----------------------

/// The main job's search options: the default grid's box, z from 0 to R/2, ±20 mm / ±1°.
fn default_search(model: &RobotModel) -> (Grid, SearchOptions, OptimiseOptions) {
    let g = default_grid(printwatt::evaluate::feasibility::reach_m(model));
    let span = |v: &[f64]| [v[0], v[v.len() - 1]];
    let so = SearchOptions {
        bounds: Bounds {
            x: span(&g.xs),
            y: span(&g.ys),
            z: span(&g.zs),
        },
        tolerance: Tolerance::default(),
        step_z_m: (g.zs[g.zs.len() - 1] - g.zs[0]) / 4.0,
        z: true,
        max_start_cells: 20,
    };
    let opts = OptimiseOptions {
        max_evals: 60,
        step_xy_m: (g.xs[1] - g.xs[0]).min(g.ys[1] - g.ys[0]) / 2.0,
        ..Default::default()
    };
    (g, so, opts)
}

#[test]
fn the_faster_optimise_finds_the_same_placement_as_the_exhaustive_refinement() {
    // The main job (default robot, path and grid; 60 refinement evaluations for test speed):
    // the seed search rejects cells on a failing corner, the candidates fail their tolerance
    // and the answer comes from the bisection toward the seed, then the spin check; every path
    // through the checks is taken. The fast checks (first failure stops a check, the corner
    // that failed last first, nothing evaluated twice, corners ahead of need) must give the
    // answer of the plain checks bit for bit, with fewer evaluations, on 1 and 2 threads.
    let (model, tp) = load("abb_irb6700_200_260", "default.gcode");
    let j = job(&model, &tp, 8);
    let ev = Evaluator::new(&j, FeasibilityOptions::default(), Objective::Supply);
    let (g, so, opts) = default_search(&model);
    let grid = pool(2).install(|| ev.sweep(&g.placements(), &|_, _| {}).unwrap());
    let quiet = || std::sync::Arc::new(|_, _, _| {}) as refine::Progress;
    let (plain, plain_info) = pool(2)
        .install(|| refine::refine_plain(&ev, &grid, &opts, &so, quiet()))
        .unwrap();
    assert!(
        plain_info.grid_cells_tried > 1,
        "a seed cell failed its tolerance"
    );
    assert!(plain_info.spin_kept.is_some(), "the spin check was made");
    assert!(
        plain.best.cost()
            > plain
                .history_j
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min),
        "the best candidate failed its tolerance: the answer comes from the bisection"
    );
    for threads in [1, 2] {
        let (fast, info) = pool(threads)
            .install(|| refine::refine(&ev, &grid, &opts, &so, quiet()))
            .unwrap();
        assert_eq!(
            fast.best.placement, plain.best.placement,
            "{threads} threads"
        );
        assert_eq!(fast.best.cost().to_bits(), plain.best.cost().to_bits());
        assert_eq!(fast.best, plain.best);
        assert_eq!(fast.evals, plain.evals);
        assert_eq!(fast.history_j, plain.history_j);
        assert_eq!(fast.sensitivity, plain.sensitivity);
        assert_eq!(info.tolerance, plain_info.tolerance, "the answer's check");
        assert!(info.tolerance.holds && info.tolerance.corners == 16);
        assert_eq!(info.grid_cells_tried, plain_info.grid_cells_tried);
        assert_eq!(info.spin_kept, plain_info.spin_kept);
        assert_eq!(info.on_bounds, plain_info.on_bounds);
        assert_eq!(info.joint_margin, plain_info.joint_margin);
        assert!(
            info.tolerance_evals < plain_info.tolerance_evals,
            "{} tolerance evaluations against {}",
            info.tolerance_evals,
            plain_info.tolerance_evals
        );
        if threads == 1 {
            assert_eq!(info.speculative_evals, 0);
        }
    }
}

#[test]
fn a_tolerance_check_stopped_at_the_first_infeasible_corner_agrees_with_all_sixteen() {
    // Placements whose boxes hold and placements whose boxes fail on different sides, checked
    // one after the other through one checker (its corner order changes as checks fail): each
    // verdict is that of evaluating all 16 corners, the failure it names is an infeasible
    // corner of the box, a box that holds reports the energies of all 16, and the reports
    // and counts are the same on 1 and 2 threads.
    let (model, tp) = load("abb_irb6700_200_260", "default.gcode");
    let j = job(&model, &tp, 8);
    let ev = Evaluator::new(&j, FeasibilityOptions::default(), Objective::Supply);
    let tol = Tolerance::default();
    let y90 = std::f64::consts::FRAC_PI_2;
    let ps = [
        Placement::new(1.43, 0.121, 0.0, y90), // fails (joint 3 margin side)
        Placement::new(1.534, 0.121, 0.0, y90), // holds
        Placement::new(1.43, -0.121, 0.0, y90), // fails
        Placement::new(1.43, 0.364, 0.0, y90), // fails
        Placement::new(1.534, 0.121, 0.0, y90), // holds, again: nothing evaluated twice
    ];
    let all: Vec<Vec<Evaluated>> = ps
        .iter()
        .map(|p| ev.sweep(&tol.corners(p), &|_, _| {}).unwrap())
        .collect();
    let run = |threads: usize| {
        pool(threads).install(|| {
            let c = printwatt::search::tolerance::Checker::new(&ev, tol);
            let r: Vec<_> = ps.iter().map(|p| c.check(p).unwrap()).collect();
            (r, c.evaluations())
        })
    };
    let (one, n1) = run(1);
    let (two, n2) = run(2);
    assert_eq!(one, two, "the same reports on 1 and 2 threads");
    assert_eq!(n1, n2, "the same evaluation count on 1 and 2 threads");
    let mut held = 0;
    for ((chk, corners), p) in one.iter().zip(&all).zip(&ps) {
        let feasible = corners.iter().all(|e| e.cost().is_finite());
        assert_eq!(chk.holds, feasible, "{p:?}");
        if feasible {
            held += 1;
            assert_eq!(chk.corners, 16);
            let costs: Vec<f64> = corners.iter().map(Evaluated::cost).collect();
            assert_eq!(chk.best_j, costs.iter().copied().reduce(f64::min));
            assert_eq!(chk.worst_j, costs.iter().copied().reduce(f64::max));
        } else {
            assert_eq!(chk.failures.len(), 1, "{chk:?}");
            let named: Vec<String> = corners
                .iter()
                .filter_map(|e| e.outcome.as_ref().err().map(|x| x.to_string()))
                .collect();
            assert!(named.contains(&chk.failures[0]), "{chk:?}");
            assert!(chk.corners < 16);
        }
    }
    assert_eq!(held, 2);
    // Each placement at most once: the first three failing checks and one box held (16).
    let full_failures: usize = one.iter().filter(|c| !c.holds).map(|c| c.corners).sum();
    assert_eq!(n1, 16 + full_failures);
}

#[test]
fn the_search_box_step_and_tolerance_limits_are_set_once_for_the_cli_and_python() {
    use printwatt::frame::Placement;
    use printwatt::search::refine::{Bounds, SearchOptions};
    use printwatt::search::tolerance::Tolerance;
    use printwatt::search::Grid;
    let g = Grid {
        xs: vec![1.0, 1.4, 1.8],
        ys: vec![-0.3, 0.0],
        zs: vec![0.0, 0.5],
        yaws: vec![0.0],
        spins: vec![0.0],
    };
    assert_eq!(g.step_xy_m(), Some(0.3_f64.min(0.4)));
    let one = Grid {
        xs: vec![1.0],
        ys: vec![0.0],
        ..g.clone()
    };
    assert_eq!(one.step_xy_m(), None);
    let ps: Vec<Placement> = g.placements();
    let b = Bounds::over(&ps, None).unwrap();
    assert_eq!((b.x, b.y, b.z), ([1.0, 1.8], [-0.3, 0.0], [0.0, 0.5]));
    assert_eq!(Bounds::over(&ps, Some([0.1, 0.2])).unwrap().z, [0.1, 0.2]);
    assert!(Bounds::over(&ps, Some([0.2, 0.1])).is_err());
    assert!(Bounds::over(&ps, Some([f64::NAN, 0.1])).is_err());
    let so = SearchOptions::new(b, Tolerance::default());
    assert!(so.z && (so.step_z_m - 0.125).abs() < 1e-15 && so.max_start_cells == 20);
    let flat = SearchOptions::new(
        Bounds::over(&ps, Some([0.0, 0.0])).unwrap(),
        Tolerance::default(),
    );
    assert!(!flat.z && flat.step_z_m == 0.01);
    assert!(Tolerance::default().check().is_ok());
    for bad in [
        Tolerance {
            xy_m: 0.6,
            ..Tolerance::default()
        },
        Tolerance {
            z_m: -0.01,
            ..Tolerance::default()
        },
        Tolerance {
            yaw_rad: 46f64.to_radians(),
            ..Tolerance::default()
        },
        Tolerance {
            xy_m: f64::NAN,
            ..Tolerance::default()
        },
    ] {
        assert!(bad.check().is_err(), "{bad:?}");
    }
}

#[test]
fn optimise_says_when_its_evaluation_budget_not_convergence_ended_the_search() {
    // The answer of a search stopped by its budget is where the budget ran out; more
    // evaluations may move it. The report must say so, and must not when the simplex
    // converged.
    with_small_search(|ev, grid, so| {
        let run = |max_evals: usize| {
            let opts = OptimiseOptions {
                max_evals,
                yaw: false,
                spin: false,
                ..Default::default()
            };
            refine::refine(ev, grid, &opts, so, std::sync::Arc::new(|_, _, _| {})).unwrap()
        };
        let (short, info) = run(8);
        assert_eq!(short.evals, 8);
        let said = info
            .budget_spent
            .expect("a search stopped by its budget says so");
        assert!(said.contains("8 evaluations"), "{said}");
        let (long, info) = run(2000);
        assert!(
            long.evals < 2000,
            "converged before the budget: {} evaluations",
            long.evals
        );
        assert_eq!(
            info.budget_spent, None,
            "a converged search claims a spent budget"
        );
    });
}

/// The default path on the IRB 6700 over a 3 × 2 grid at z = 0.5 m, yaw 90° (a small search
/// that stops early on a budget of 8 and converges on one of 2000), with the default tolerance.
fn with_small_search(f: impl FnOnce(&Evaluator, &[Evaluated], &SearchOptions)) {
    let (model, tp) = load("abb_irb6700_200_260", "default.gcode");
    let j = job(&model, &tp, 8);
    let ev = Evaluator::new(&j, FeasibilityOptions::default(), Objective::Supply);
    let g = Grid {
        xs: vec![1.4, 1.5, 1.6],
        ys: vec![-0.1, 0.1],
        zs: vec![0.5],
        yaws: vec![std::f64::consts::FRAC_PI_2],
        spins: vec![0.0],
    };
    let grid = ev.sweep(&g.placements(), &|_, _| {}).unwrap();
    let so = SearchOptions::new(
        Bounds::over(&g.placements(), None).unwrap(),
        Tolerance::default(),
    );
    f(&ev, &grid, &so);
}

#[test]
fn no_printed_neighbour_is_cheaper_than_the_answer_and_holds_the_tolerance_unexplained() {
    // The answer's ±50 mm probes are printed beside it. A probe that costs less and holds the
    // tolerance is a better answer: the search moves there. A cheaper probe that is not taken
    // is named with the reason. Checked independently: the probes are evaluated again and
    // each cheaper one's tolerance box re-checked with the plain corner check.
    with_small_search(|ev, grid, so| {
        for max_evals in [0, 8, 2000] {
            let opts = OptimiseOptions {
                max_evals,
                yaw: false,
                spin: false,
                ..Default::default()
            };
            let (res, info) =
                refine::refine(ev, grid, &opts, so, std::sync::Arc::new(|_, _, _| {})).unwrap();
            assert!(info.tolerance.holds, "{max_evals}: {:?}", info.tolerance);
            let e0 = res.best.cost();
            let h = opts.sensitivity_m;
            let again = ev
                .sweep(
                    &printwatt::search::optimise::probes(&res.best.placement, h),
                    &|_, _| {},
                )
                .unwrap();
            for (k, e) in again.iter().enumerate() {
                let name = printwatt::search::optimise::PROBE_NAMES[k];
                assert_eq!(e.cost().to_bits(), {
                    res.sensitivity.e_j[k].unwrap_or(f64::INFINITY).to_bits()
                });
                if e.cost() >= e0 {
                    continue;
                }
                let said = info
                    .lower_neighbours
                    .iter()
                    .find(|l| l.starts_with(&format!("E({name})")))
                    .unwrap_or_else(|| {
                        panic!("{max_evals}: E({name}) {} < {e0} J not named", e.cost())
                    });
                let in_box = so.bounds.contains(&e.placement);
                let holds = printwatt::search::tolerance::check(ev, &e.placement, &so.tolerance)
                    .unwrap()
                    .holds;
                assert!(
                    !(in_box && holds) || said.contains("polish stopped"),
                    "{max_evals}: {said}, yet it holds the tolerance in the box"
                );
            }
            if max_evals == 0 {
                // The grid cell itself (0.1 m grid): a cheaper 50 mm neighbour holds the tolerance.
                let moved = info
                    .polished
                    .as_deref()
                    .expect("the polish moved the answer");
                assert!(
                    moved.contains("J below where the search stopped"),
                    "{moved}"
                );
                assert!(e0 < grid.iter().map(|e| e.cost()).fold(f64::INFINITY, f64::min));
            }
        }
    });
}

#[test]
fn the_polish_moving_to_a_probe_it_reuses_gives_the_answer_of_evaluating_it_again() {
    // The polish moves to a cheaper ±50 mm probe that holds the tolerance; it takes the probe's
    // evaluation from the sensitivity that has just made it instead of evaluating it again.
    // The plain refinement evaluates it again: the answer, its sensitivity, the polish's words
    // and the evaluation counts must be the same bit for bit, on 1 and 2 threads.
    with_small_search(|ev, grid, so| {
        let opts = OptimiseOptions {
            max_evals: 0,
            yaw: false,
            spin: false,
            ..Default::default()
        };
        let quiet = || std::sync::Arc::new(|_, _, _| {}) as refine::Progress;
        let (plain, plain_info) = pool(1)
            .install(|| refine::refine_plain(ev, grid, &opts, so, quiet()))
            .unwrap();
        assert!(plain_info.polished.is_some(), "the polish moved the answer");
        for threads in [1, 2] {
            let (fast, info) = pool(threads)
                .install(|| refine::refine(ev, grid, &opts, so, quiet()))
                .unwrap();
            assert_eq!(fast.best, plain.best, "{threads} threads");
            assert_eq!(fast.best.cost().to_bits(), plain.best.cost().to_bits());
            assert_eq!(fast.sensitivity, plain.sensitivity);
            assert_eq!(info.polished, plain_info.polished);
            assert_eq!(info.lower_neighbours, plain_info.lower_neighbours);
            assert_eq!(info.tolerance, plain_info.tolerance);
            if threads == 1 {
                assert_eq!(info.speculative_evals, 0, "nothing made ahead of need");
            }
        }
    });
}

#[test]
fn a_checker_counts_an_adopted_evaluation_once_and_never_makes_it_again() {
    // An evaluation made elsewhere and adopted is kept and counted as one evaluation used:
    // asking the checker for the same placement afterwards returns it without another.
    with_small_search(|ev, grid, _so| {
        let e = grid.iter().find(|e| e.cost().is_finite()).unwrap();
        pool(1).install(|| {
            let c = printwatt::search::tolerance::Checker::new(ev, Tolerance::default());
            let a = c.adopt(e).unwrap();
            assert_eq!(&a, e);
            assert_eq!((c.evaluations(), c.speculative()), (1, 0));
            let b = c.evaluate(&e.placement, false).unwrap();
            assert_eq!(&b, e);
            assert_eq!((c.evaluations(), c.speculative()), (1, 0));
            // Adopting a placement already kept returns the kept evaluation.
            let again = c.adopt(e).unwrap();
            assert_eq!(&again, e);
            assert_eq!(c.evaluations(), 1);
        });
    });
}
