//! Error-controlled path reduction for long prints: a placement of a path whose layers repeat
//! up to a shift in z ([`crate::toolpath::repeat`]) is evaluated on a few representative
//! layers, and the energy of the others is interpolated over z.
//!
//! # What is evaluated, and how
//! The job's Cartesian plan (placement-independent, [`super::PathJob::plan`]) is cut into
//! *units*, one per layer with the travel that leads to it, as sample ranges of the one plan:
//! a unit's samples are those of its moves, the corner blend into the next unit included. At
//! a placement:
//!
//! 1. **Every sample** is checked for reach (the wrist centre within the arm's reach, no
//!    trigonometry), as the full evaluation's prune does.
//! 2. **Every layer at the geometric level**: the arm configuration is tracked by inverse
//!    kinematics on every `stride`-th sample of the whole path (a multiple of
//!    `check_every`, so these samples are ones the full evaluation checks too), trying the
//!    configurations at the first sample in the full evaluation's order; each tracked
//!    sample is checked against the joint position limits with their margins and the elbow
//!    and shoulder singularity margins. An infeasible layer anywhere makes the placement
//!    infeasible, whatever the representative layers say.
//! 3. **Representative layers in full**: the units outside the repeating run (the first
//!    layer and whatever precedes the run, the last layer's lift), the first and last unit of
//!    each repeating class, and interior units at Chebyshev–Lobatto positions in the class
//!    are tracked sample by sample (from the tracked configuration of step 2), differentiated,
//!    checked (joint margins, wrist rule, singularities, collisions against the bed and the
//!    beads laid so far by the whole path), and integrated with the full evaluation's
//!    per-sample energy and its trapezoid weights. These samples give the full evaluation's
//!    numbers for those units (same samples, same arithmetic).
//! 4. **Interpolation**: per class, the energy per sample of each unit (every additive
//!    quantity: supply, drives, losses, per-joint mechanical and electrical energy) is
//!    interpolated over the layer height z by the polynomial through the evaluated units
//!    (barycentric Lagrange), multiplied by each unit's sample count (known exactly) and
//!    summed.
//! 5. **Error estimate**: the same sum from the nested lower-order interpolant (every second
//!    node) differs from it by `d`; the estimate's error is stated as `d` plus one sample's
//!    energy per interpolated unit (the dt phase of unit boundaries). When it exceeds
//!    [`ReduceOptions::rel_tol`] of the estimate, the node count doubles (5, 9, 17 nodes per
//!    class); a class with no more members than nodes is evaluated exactly.
//!
//! # When the full evaluation is used instead
//! The placement is evaluated in full (and the estimate records why) when a joint's velocity,
//! acceleration or jerk demand may bind somewhere (the controller would slow down there, and
//! the slow-down changes the whole plan): when it exceeds the limit on an evaluated unit, or
//! when its peak over a class's evaluated units plus the largest change of that peak between
//! neighbouring evaluated units exceeds [`ReduceOptions::headroom`] of the limit (the peak of
//! a layer between two evaluated ones is taken to lie within that bound).
//! The wrist rule (near the wrist singularity, joints 4 and 6 within a share of their limits)
//! needs joint rates: units where a tracked sample comes within twice `wrist_min` of the
//! wrist singularity are evaluated sample by sample unless the evaluated units come near it
//! too and use at most `headroom` of the allowed share there.
//!
//! # Limitations
//! Between the representative layers, collisions are not checked (the extreme layers, where
//! the part is lowest and highest, are), and the configuration is tracked at the stride, not
//! every sample. The answer of an optimisation is therefore always re-evaluated in full
//! ([`confirm`]).

use super::feasibility::{self, Infeasible, Margins, Reason, World};
use super::sweep::{Evaluated, Evaluator, Feasible, Losses, Objective, Scratch};
use crate::energy;
use crate::kinematics::{nozzle_target, opw, IkFailure, JointVec};
use crate::math::{Frame, V3};
use crate::placement::Placement;
use crate::timing::profile::CartesianMotion;
use crate::toolpath::repeat::{self, Repetition};
use crate::toolpath::Toolpath;
use serde::{Deserialize, Serialize};
use std::ops::Range;

/// Options of the reduction.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ReduceOptions {
    /// Reduce only paths with at least this many samples in the job's plan (a short path is
    /// cheap to evaluate in full). 0: whenever the path repeats.
    pub min_samples: usize,
    /// Geometric tracking stride, samples (rounded up to a multiple of the feasibility
    /// options' `check_every`).
    pub stride: usize,
    /// Target relative error of the objective estimate (dimensionless): more layers are
    /// evaluated while the stated error exceeds it.
    pub rel_tol: f64,
    /// Largest number of evaluated units per class (5, 9 or 17).
    pub max_nodes: usize,
    /// Share of a joint's velocity, acceleration or jerk limit that the demand predicted for
    /// the interpolated layers may reach before the placement is evaluated in full
    /// (dimensionless; see the module docs).
    pub headroom: f64,
    /// Position tolerance for telling repeated layers apart, m.
    pub tolerance_m: f64,
}

impl Default for ReduceOptions {
    fn default() -> Self {
        ReduceOptions {
            min_samples: 200_000,
            stride: 40,
            rel_tol: 1e-3,
            max_nodes: 17,
            headroom: 0.98,
            tolerance_m: repeat::REPEAT_TOLERANCE_M,
        }
    }
}

/// How a placement was evaluated when the reduction is on (JSON: the `path_reduction` object of a
/// feasible placement, docs/json.md).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Estimate {
    /// Stated error of the objective energy, J (0 when evaluated in full).
    pub error_j: f64,
    /// Layers (units) of the path.
    pub layers: usize,
    /// Layers evaluated sample by sample.
    pub layers_evaluated: usize,
    /// Samples evaluated sample by sample (of [`Feasible::samples`]).
    pub samples_evaluated: usize,
    /// Why this placement was evaluated in full instead, if it was.
    pub fallback: Option<String>,
}

/// The placement-independent side of the reduction: the units as sample ranges of the job's
/// plan. Build with [`Reduction::plan`].
#[derive(Clone, Debug)]
pub struct Reduction {
    /// Sample ranges of every unit of the repeating run, in order.
    units: Vec<Range<usize>>,
    /// Layer height of each run unit, m.
    z: Vec<f64>,
    /// Run units per class (indices into `units`).
    classes: Vec<Vec<usize>>,
    /// Options.
    pub options: ReduceOptions,
    /// What was found (for reports).
    pub summary: Summary,
}

/// What the reduction found in the path (JSON: `summary` of `optimise.path_reduction`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    /// Layers (units) of the path.
    pub layers: usize,
    /// Units per repeat (1: every layer the same, 2: alternating seams, …).
    pub period: usize,
    /// Layers in the repeating run.
    pub repeating_layers: usize,
    /// Samples of the path's plan.
    pub samples: usize,
}

/// Why a path is evaluated in full.
#[derive(Clone, Debug, PartialEq)]
pub enum NotReduced {
    /// Fewer samples than [`ReduceOptions::min_samples`].
    Short(usize),
    /// No layers repeat.
    NoRepetition,
    /// The repeating layers could not be mapped onto the plan (a layer without samples).
    Unmapped,
}

impl std::fmt::Display for NotReduced {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NotReduced::Short(n) => write!(f, "the path has {n} samples: evaluated in full"),
            NotReduced::NoRepetition => write!(f, "no layers repeat: evaluated in full"),
            NotReduced::Unmapped => {
                write!(f, "repeating layers without samples: evaluated in full")
            }
        }
    }
}

/// Sample where toolpath move `i` begins in the plan `motion` of `pieces` (timing moves drop
/// zero-length toolpath moves; a corner blend belongs to the move it starts on).
fn sample_of_move(
    path: &Toolpath,
    pieces: &[crate::timing::Piece],
    motion: &CartesianMotion,
    i: usize,
) -> usize {
    let timing_index = (0..i.min(path.moves.len()))
        .filter(|&k| path.moves[k].length(&path.move_start(k)) >= crate::timing::MIN_MOVE_LENGTH_M)
        .count();
    let piece = pieces
        .iter()
        .position(|p| p.move_index >= timing_index)
        .unwrap_or(pieces.len());
    motion
        .piece
        .iter()
        .position(|&p| p >= piece)
        .unwrap_or(motion.p.len())
}

impl Reduction {
    /// Plan the reduction of `job`'s path (`path` is the toolpath the job was built from).
    /// Errors say why the path is evaluated in full.
    pub fn plan(
        job: &super::PathJob<'_>,
        path: &Toolpath,
        options: ReduceOptions,
    ) -> std::result::Result<Reduction, NotReduced> {
        let motion = &job.plan.motion;
        let m = motion.p.len();
        if m < options.min_samples {
            return Err(NotReduced::Short(m));
        }
        let rep: Repetition =
            repeat::repetition(path, options.tolerance_m).ok_or(NotReduced::NoRepetition)?;
        let mut units = Vec::new();
        let mut z = Vec::new();
        for k in rep.run.clone() {
            let u = &rep.units[k];
            let a = sample_of_move(path, &job.pieces, motion, u.moves.start);
            let b = sample_of_move(path, &job.pieces, motion, u.moves.end);
            if b <= a {
                return Err(NotReduced::Unmapped);
            }
            units.push(a..b);
            z.push(u.z_m);
        }
        let classes = (0..rep.period)
            .map(|c| rep.class(c).iter().map(|k| k - rep.run.start).collect())
            .collect();
        Ok(Reduction {
            units,
            z,
            classes,
            options,
            summary: Summary {
                layers: rep.units.len(),
                period: rep.period,
                repeating_layers: rep.run.len(),
                samples: m,
            },
        })
    }
}

/// Per-thread buffers of the reduced evaluation.
#[derive(Default)]
pub struct Buffers {
    thin: Vec<f64>,
    qs: Vec<f64>,
}

/// Index of each additive quantity in a unit's energy vector.
const SUPPLY: usize = 0;
const DRIVES: usize = 1;
const REGEN: usize = 2;
const FRICTION: usize = 3;
const GEAR: usize = 4;
const COPPER: usize = 5;
const MPOS: usize = 6;
const FIXED: usize = 7;

fn objective_of(v: &[f64], n: usize, o: Objective) -> f64 {
    match o {
        Objective::Supply => v[SUPPLY],
        Objective::Drives => v[DRIVES],
        Objective::Mechanical => v[FIXED..FIXED + n].iter().sum(),
        Objective::MechanicalPositive => v[MPOS],
        Objective::MechanicalAbs => v[FIXED + n..FIXED + 2 * n].iter().sum(),
    }
}

/// Chebyshev–Lobatto positions among `len` members for `nodes` nodes (nested: the positions
/// for `2·nodes − 1` contain these), deduplicated, in order.
fn lobatto(len: usize, nodes: usize) -> Vec<usize> {
    if len <= nodes {
        return (0..len).collect();
    }
    let mut v: Vec<usize> = (0..nodes)
        .map(|i| {
            let x = 0.5 * (1.0 - (std::f64::consts::PI * i as f64 / (nodes - 1) as f64).cos());
            (x * (len - 1) as f64).round() as usize
        })
        .collect();
    v.dedup();
    v
}

/// Σ over `at` of the interpolant through `(xs, ys)` (barycentric Lagrange; at a node its own
/// value) times `weights`.
fn interpolated_sum(
    xs: &[f64],
    ys: &[Vec<f64>],
    at: &[f64],
    weights: &[f64],
    dim: usize,
) -> Vec<f64> {
    let w: Vec<f64> = (0..xs.len())
        .map(|i| {
            1.0 / (0..xs.len())
                .filter(|&j| j != i)
                .map(|j| xs[i] - xs[j])
                .product::<f64>()
        })
        .collect();
    let mut out = vec![0.0; dim];
    for (x, wt) in at.iter().zip(weights) {
        if let Some(i) = xs.iter().position(|xi| xi == x) {
            for d in 0..dim {
                out[d] += wt * ys[i][d];
            }
            continue;
        }
        let c: Vec<f64> = (0..xs.len()).map(|i| w[i] / (x - xs[i])).collect();
        let den: f64 = c.iter().sum();
        for d in 0..dim {
            let num: f64 = (0..xs.len()).map(|i| c[i] * ys[i][d]).sum();
            out[d] += wt * num / den;
        }
    }
    out
}

/// A reduced evaluation's outcome: numbers, infeasible, or "evaluate in full, because".
enum Outcome {
    Done(Box<Feasible>),
    Infeasible(Infeasible),
    Full(String),
}

/// Evaluate `at` with the reduction `red` (see the module docs). Falls back to the full
/// evaluation (recorded in [`Feasible::path_reduction`]) where the module docs say.
pub(super) fn evaluate<'a>(
    ev: &Evaluator<'_, 'a>,
    red: &Reduction,
    sc: &mut Scratch<'a>,
    at: &Placement,
) -> std::result::Result<Feasible, Infeasible> {
    match reduced(ev, red, sc, at) {
        Outcome::Done(f) => Ok(*f),
        Outcome::Infeasible(i) => Err(i),
        Outcome::Full(why) => {
            let mut r = ev.evaluate_full_inner(sc, at);
            if let Ok(f) = &mut r {
                f.path_reduction = Some(Estimate {
                    error_j: 0.0,
                    layers: red.summary.layers,
                    layers_evaluated: red.summary.layers,
                    samples_evaluated: f.samples,
                    fallback: Some(why),
                });
            }
            r
        }
    }
}

fn reduced<'a>(
    ev: &Evaluator<'_, 'a>,
    red: &Reduction,
    sc: &mut Scratch<'a>,
    at: &Placement,
) -> Outcome {
    let job = ev.job;
    let model = job.robot;
    let n = model.dof();
    let motion = &*job.plan.motion;
    let m = motion.p.len();
    let dt = motion.dt;
    let o = &ev.feasibility;
    let every = o.check_every.max(1);
    let stride = red.options.stride.max(1).div_ceil(every) * every;
    let frame = at.frame();
    let rot = nozzle_target(&V3::zeros(), at.nozzle_yaw()).rot;
    let solver = sc.solver.clone();
    let line_at = |k: usize| job.line_of(job.pieces[motion.piece[k]].move_index);
    let unreachable = |k: usize, tip: V3, reason: IkFailure| {
        let mi = job.pieces[motion.piece[k]].move_index;
        Infeasible::from_timing(&crate::timing::TimingFailure::Unreachable {
            sample: k,
            t: k as f64 * dt,
            point: tip,
            move_index: mi,
            line: job.line_of(mi),
            reason,
        })
    };
    if m == 0 {
        return Outcome::Full("the plan has no samples".into());
    }
    // 1. Reach of every sample (coarse to fine).
    {
        let coarse = (0..m).step_by(64);
        match solver.wrist_offset(&rot) {
            Some(d) => {
                for k in coarse.chain(0..m) {
                    let tip = frame.apply(&motion.p[k]);
                    if let Err(r) = solver.wrist_centre_reachable(&(tip + d), 1e-9) {
                        return Outcome::Infeasible(unreachable(k, tip, r));
                    }
                }
            }
            None => {
                for k in coarse.chain(0..m) {
                    let tip = frame.apply(&motion.p[k]);
                    if let Err(r) = solver.reachable(&Frame { rot, pos: tip }) {
                        return Outcome::Infeasible(unreachable(k, tip, r));
                    }
                }
            }
        }
    }
    let target = |k: usize| {
        let tip = frame.apply(&motion.p[k]);
        (Frame { rot, pos: tip }, tip)
    };
    // 2. Configuration tracked on every stride-th sample, candidates as the full evaluation
    // orders them.
    let (t0, tip0) = target(0);
    let mut cands = match solver.solve_all(&t0) {
        Ok(c) => c,
        Err(r) => return Outcome::Infeasible(unreachable(0, tip0, r)),
    };
    cands.sort_by(|a, b| {
        crate::kinematics::limit_margin(model, &b.q)
            .total_cmp(&crate::kinematics::limit_margin(model, &a.q))
    });
    let max_step: Vec<f64> = model
        .joints
        .iter()
        .map(|j| {
            if j.velocity_limit.is_finite() {
                (j.velocity_limit * dt * 4.0).max(0.05)
            } else {
                0.5
            }
        })
        .collect();
    let thin_idx: Vec<usize> = (0..m)
        .step_by(stride)
        .chain((!(m - 1).is_multiple_of(stride)).then_some(m - 1))
        .collect();
    let mut best_fail: Option<(usize, Infeasible)> = None;
    let mut chosen = false;
    let thin = &mut sc.red.thin;
    for c in &cands {
        thin.clear();
        let mut prev = c.q;
        let mut fail = None;
        for (i, &k) in thin_idx.iter().enumerate() {
            let (tg, tip) = target(k);
            let q = match solver.solve_near(&tg, &prev) {
                Ok(q) => q,
                Err(r) => {
                    fail = Some((k, unreachable(k, tip, r)));
                    break;
                }
            };
            if i > 0 {
                let steps = (k - thin_idx[i - 1]) as f64;
                if let Some(j) =
                    (0..n).find(|&j| (q[j] - prev[j]).abs() > (max_step[j] * steps).min(1.0))
                {
                    let tf = crate::timing::TimingFailure::ConfigurationChange {
                        sample: k,
                        t: k as f64 * dt,
                        point: tip,
                        line: line_at(k),
                        joint: j,
                        jump: (q[j] - prev[j]).abs(),
                    };
                    fail = Some((k, Infeasible::from_timing(&tf)));
                    break;
                }
            }
            thin.extend_from_slice(&q[..n]);
            prev = q;
        }
        match fail {
            None => {
                chosen = true;
                break;
            }
            Some((k, e)) => {
                if best_fail.as_ref().is_none_or(|b| k > b.0) {
                    best_fail = Some((k, e));
                }
            }
        }
    }
    if !chosen {
        return Outcome::Infeasible(best_fail.map(|b| b.1).unwrap_or_else(|| {
            unreachable(
                0,
                tip0,
                IkFailure::Unsupported("no IK solution at the first sample".into()),
            )
        }));
    }
    // The units evaluated at the first level, and which samples they cover.
    let nu = red.units.len();
    let run = red.units.first().map_or(0, |u| u.start)..red.units.last().map_or(0, |u| u.end);
    // Interpolation nodes (Chebyshev–Lobatto in each class) and every unit evaluated sample by
    // sample (the nodes and units near the wrist singularity).
    let mut evaluated = vec![false; nu];
    let mut node = vec![false; nu];
    let mut near_wrist = vec![false; nu];
    let mut level = 5.min(red.options.max_nodes.max(3));
    for cl in &red.classes {
        for i in lobatto(cl.len(), level) {
            evaluated[cl[i]] = true;
            node[cl[i]] = true;
        }
    }
    // Geometric checks on the tracked samples; units where the wrist comes near its
    // singularity are noted (the wrist rule needs joint rates, see below).
    let mut margins = Margins::default();
    let unit_of = |k: usize| -> Option<usize> {
        if !run.contains(&k) {
            return None;
        }
        let i = red.units.partition_point(|u| u.end <= k);
        (i < nu).then_some(i)
    };
    let zeros = [0.0; crate::kinematics::MAX_DOF];
    for (i, &k) in thin_idx.iter().enumerate() {
        let q = &sc.red.thin[i * n..(i + 1) * n];
        let opw_p = model.opw.as_ref().filter(|_| n >= 6);
        if let (Some(p), Some(u)) = (opw_p, unit_of(k)) {
            if opw::wrist_singularity(p, q) < 2.0 * o.wrist_min {
                near_wrist[u] = true;
            }
        }
        let fail = super::margins::check_joint_sample(
            model,
            o,
            q,
            &zeros[..n],
            &zeros[..n],
            &mut Margins::default(),
        )
        .or_else(|| {
            let p = opw_p?;
            let e = opw::elbow_singularity(p, q);
            let s = opw::shoulder_singularity(p, q);
            if e < o.elbow_min {
                return Some((
                    Reason::ElbowSingularity,
                    format!("elbow measure {e:.4} < {:.4}", o.elbow_min),
                ));
            }
            (s < o.shoulder_min_m).then(|| {
                (
                    Reason::ShoulderSingularity,
                    format!(
                        "wrist centre {s:.3} m from axis 1 < {:.3} m",
                        o.shoulder_min_m
                    ),
                )
            })
        });
        if let Some((reason, detail)) = fail {
            let tip = frame.apply(&motion.p[k]);
            return Outcome::Infeasible(Infeasible {
                reason,
                sample: Some(k),
                t_s: Some(k as f64 * dt),
                line: Some(line_at(k)),
                point_m: Some([tip.x, tip.y, tip.z]),
                detail,
            });
        }
    }
    // 3. The evaluated units, sample by sample.
    let dim = FIXED + 3 * n;
    let mut unit_e: Vec<Option<Vec<f64>>> = vec![None; nu];
    let mut peaks: Vec<Option<Vec<f64>>> = vec![None; nu];
    let mut exact_peak = vec![0.0; 3 * n];
    let mut exact = vec![0.0; dim];
    let world = World::new(&frame, ev.bbox_all, o);
    let mut done = vec![false; nu];
    let mut samples_evaluated = 0;
    let mut first_pass = true;
    loop {
        // Contiguous sample ranges to evaluate now: the exact rest (first pass) and every unit
        // marked and not done.
        let mut ranges: Vec<Range<usize>> = Vec::new();
        if first_pass {
            if run.start > 0 {
                ranges.push(0..run.start);
            }
            if run.end < m {
                ranges.push(run.end..m);
            }
        }
        for (u, r) in red.units.iter().enumerate() {
            if evaluated[u] && !done[u] {
                ranges.push(r.clone());
                done[u] = true;
            }
        }
        ranges.sort_by_key(|r| r.start);
        let mut merged: Vec<Range<usize>> = Vec::new();
        for r in ranges {
            match merged.last_mut() {
                Some(l) if l.end == r.start => l.end = r.end,
                _ => merged.push(r),
            }
        }
        for r in merged {
            samples_evaluated += r.len();
            match window(
                ev,
                red,
                sc,
                at,
                &frame,
                &world,
                r,
                stride,
                &thin_idx,
                &mut margins,
                &unit_of,
                &mut unit_e,
                &mut exact,
                &mut peaks,
                &mut exact_peak,
            ) {
                Ok(()) => {}
                Err(o) => return o,
            }
        }
        first_pass = false;
        // Joint rate demands of the interpolated units, bounded from the evaluated ones.
        if let Some(why) = rate_bound(red, &peaks, &evaluated, red.options.headroom) {
            return Outcome::Full(why);
        }
        // The wrist rule on units not evaluated: accepted when the evaluated units come near
        // the wrist singularity too and use at most `headroom` of the allowed share there;
        // otherwise those units are evaluated sample by sample.
        let wrist_ok = margins
            .wrist_rate
            .is_some_and(|r| r <= red.options.headroom * o.wrist_rate_max);
        let pending: Vec<usize> = (0..nu)
            .filter(|&u| near_wrist[u] && !evaluated[u])
            .collect();
        if !wrist_ok && !pending.is_empty() {
            for u in pending {
                evaluated[u] = true;
            }
            continue;
        }
        // 4./5. Interpolate per class; refine while the stated error is too large.
        let (total, err) = estimate(red, &unit_e, &evaluated, &node, n, ev.objective, &exact);
        let too_big = err > red.options.rel_tol * objective_of(&total, n, ev.objective).abs();
        let next = 2 * level - 1;
        if too_big && next <= red.options.max_nodes && red.classes.iter().any(|c| c.len() > level) {
            level = next;
            for cl in &red.classes {
                for i in lobatto(cl.len(), level) {
                    evaluated[cl[i]] = true;
                    node[cl[i]] = true;
                }
            }
            continue;
        }
        let layers_evaluated =
            evaluated.iter().filter(|e| **e).count() + (red.summary.layers - red.units.len());
        let v = &total;
        let jm = v[FIXED..FIXED + n].to_vec();
        let jabs = v[FIXED + n..FIXED + 2 * n].to_vec();
        let jel = v[FIXED + 2 * n..FIXED + 3 * n].to_vec();
        let energy_j = objective_of(v, n, ev.objective);
        if !energy_j.is_finite() {
            return Outcome::Full("non-finite estimate".into());
        }
        return Outcome::Done(Box::new(Feasible {
            energy_j,
            supply_j: v[SUPPLY],
            drives_j: v[DRIVES],
            standby_j: v[SUPPLY] - v[DRIVES],
            mechanical_j: jm.iter().sum(),
            mechanical_positive_j: v[MPOS],
            mechanical_abs_j: jabs.iter().sum(),
            electrical_j: jel.iter().sum(),
            losses: Losses {
                friction_j: v[FRICTION],
                gear_j: v[GEAR],
                copper_j: v[COPPER],
                regeneration_lost_j: v[REGEN],
            },
            duration_s: dt * m.saturating_sub(1) as f64,
            samples: m,
            rounds: 1,
            joint_mechanical_j: jm,
            joint_mechanical_abs_j: jabs,
            joint_electrical_j: jel,
            margins,
            path_reduction: Some(Estimate {
                error_j: err,
                layers: red.summary.layers,
                layers_evaluated,
                samples_evaluated,
                fallback: None,
            }),
        }));
    }
}

/// Why the joint rate demand may bind on a unit that is not evaluated, if it may: per class
/// and channel (joint × velocity/acceleration/jerk, as a share of the limit), the peak over
/// the evaluated units plus the largest change between neighbouring evaluated units, against
/// `headroom`.
fn rate_bound(
    red: &Reduction,
    peaks: &[Option<Vec<f64>>],
    evaluated: &[bool],
    headroom: f64,
) -> Option<String> {
    const KIND: [&str; 3] = ["velocity", "acceleration", "jerk"];
    for cl in &red.classes {
        if cl.iter().all(|&u| evaluated[u]) {
            continue;
        }
        let ev: Vec<&Vec<f64>> = cl.iter().filter_map(|&u| peaks[u].as_ref()).collect();
        let Some(first) = ev.first() else { continue };
        for c in 0..first.len() {
            let max = ev.iter().map(|p| p[c]).fold(0.0, f64::max);
            let step = ev
                .windows(2)
                .map(|w| (w[1][c] - w[0][c]).abs())
                .fold(0.0, f64::max);
            if max + step > headroom {
                return Some(format!(
                    "joint {} uses up to {:.0} % of its {} limit on the evaluated layers (changing by up to {:.0} % between them): it may bind on a layer in between",
                    c / 3 + 1,
                    max * 100.0,
                    KIND[c % 3],
                    step * 100.0
                ));
            }
        }
    }
    None
}

/// The estimate: (total vector, stated error of the objective, J).
fn estimate(
    red: &Reduction,
    unit_e: &[Option<Vec<f64>>],
    evaluated: &[bool],
    node: &[bool],
    n: usize,
    obj: Objective,
    exact: &[f64],
) -> (Vec<f64>, f64) {
    let dim = exact.len();
    let mut total = exact.to_vec();
    let mut err = 0.0;
    let len = |u: usize| red.units[u].len() as f64;
    for cl in &red.classes {
        let nodes: Vec<usize> = cl.iter().copied().filter(|&u| node[u]).collect();
        let rest: Vec<usize> = cl.iter().copied().filter(|&u| !evaluated[u]).collect();
        for &u in cl.iter().filter(|&&u| evaluated[u]) {
            if let Some(e) = &unit_e[u] {
                for d in 0..dim {
                    total[d] += e[d];
                }
            }
        }
        if rest.is_empty() {
            continue;
        }
        // Energy per sample of each evaluated unit, over z.
        let xs: Vec<f64> = nodes.iter().map(|&u| red.z[u]).collect();
        let ys: Vec<Vec<f64>> = nodes
            .iter()
            .map(|&u| {
                unit_e[u]
                    .as_ref()
                    .map(|e| e.iter().map(|v| v / len(u)).collect())
                    .unwrap_or_else(|| vec![0.0; dim])
            })
            .collect();
        let at: Vec<f64> = rest.iter().map(|&u| red.z[u]).collect();
        let wts: Vec<f64> = rest.iter().map(|&u| len(u)).collect();
        let hi = interpolated_sum(&xs, &ys, &at, &wts, dim);
        // The nested lower order: every second node.
        let lo = {
            let keep: Vec<usize> = (0..xs.len()).step_by(2).collect();
            let xl: Vec<f64> = keep.iter().map(|&i| xs[i]).collect();
            let yl: Vec<Vec<f64>> = keep.iter().map(|&i| ys[i].clone()).collect();
            interpolated_sum(&xl, &yl, &at, &wts, dim)
        };
        for d in 0..dim {
            total[d] += hi[d];
        }
        // One sample's energy per interpolated unit: the phase of unit boundaries.
        let per_sample = ys
            .iter()
            .map(|y| objective_of(y, n, obj).abs())
            .fold(0.0, f64::max);
        err += (objective_of(&hi, n, obj) - objective_of(&lo, n, obj)).abs()
            + rest.len() as f64 * per_sample;
    }
    (total, err)
}

/// Track, check and integrate the samples `r` (a union of whole units and the exact rest).
#[allow(clippy::too_many_arguments)]
fn window<'a>(
    ev: &Evaluator<'_, 'a>,
    _red: &Reduction,
    sc: &mut Scratch<'a>,
    _at: &Placement,
    frame: &Frame,
    world: &World,
    r: Range<usize>,
    stride: usize,
    thin_idx: &[usize],
    margins: &mut Margins,
    unit_of: &dyn Fn(usize) -> Option<usize>,
    unit_e: &mut [Option<Vec<f64>>],
    exact: &mut [f64],
    peaks: &mut [Option<Vec<f64>>],
    exact_peak: &mut [f64],
) -> std::result::Result<(), Outcome> {
    const PAD: usize = 4;
    let job = ev.job;
    let model = job.robot;
    let n = model.dof();
    let motion = &*job.plan.motion;
    let m = motion.p.len();
    let dt = motion.dt;
    let o = &ev.feasibility;
    let every = o.check_every.max(1);
    let lo = r.start.saturating_sub(PAD);
    let hi = (r.end + PAD).min(m);
    // Start at the tracked sample at or before `lo`.
    let ti = (lo / stride).min(thin_idx.len() - 1);
    let t0 = thin_idx[ti];
    let rot = nozzle_target(&V3::zeros(), _at.nozzle_yaw()).rot;
    let mut prev = JointVec::from_slice(&sc.red.thin[ti * n..(ti + 1) * n]);
    let qs = &mut sc.red.qs;
    qs.clear();
    for k in t0..hi {
        let tip = frame.apply(&motion.p[k]);
        let q = match sc.solver.solve_near(&Frame { rot, pos: tip }, &prev) {
            Ok(q) => q,
            Err(reason) => {
                let mi = job.pieces[motion.piece[k]].move_index;
                return Err(Outcome::Infeasible(Infeasible::from_timing(
                    &crate::timing::TimingFailure::Unreachable {
                        sample: k,
                        t: k as f64 * dt,
                        point: tip,
                        move_index: mi,
                        line: job.line_of(mi),
                        reason,
                    },
                )));
            }
        };
        qs.extend_from_slice(&q[..n]);
        prev = q;
    }
    let (qd, qdd, qddd) = crate::timing::joint::differentiate(qs, n, dt);
    let check_jerk = job.joint.check_jerk;
    for k in r.clone() {
        let i = k - t0;
        let peak: &mut [f64] = match unit_of(k) {
            Some(u) => peaks[u].get_or_insert_with(|| vec![0.0; 3 * n]),
            None => exact_peak,
        };
        for (j, jt) in model.joints.iter().enumerate() {
            for (c, (v, lim, what)) in [
                (qd[i * n + j], jt.velocity_limit, "velocity"),
                (qdd[i * n + j], jt.acceleration_limit, "acceleration"),
                (
                    if check_jerk { qddd[i * n + j] } else { 0.0 },
                    jt.jerk_limit,
                    "jerk",
                ),
            ]
            .into_iter()
            .enumerate()
            {
                if !(lim.is_finite() && lim > 0.0) {
                    continue;
                }
                let ratio = v.abs() / lim;
                if ratio > 1.0 {
                    return Err(Outcome::Full(format!(
                        "joint {} exceeds its {what} limit ({:.0} %) at sample {k}: the controller slows down",
                        j + 1,
                        ratio * 100.0
                    )));
                }
                peak[3 * j + c] = peak[3 * j + c].max(ratio);
            }
        }
    }
    // Feasibility, as the full evaluation checks it, on these samples.
    let beads = &ev.beads;
    for k in r.clone() {
        let i = k - t0;
        let q = &qs[i * n..(i + 1) * n];
        let jc = super::margins::check_joint_sample(
            model,
            o,
            q,
            &qd[i * n..(i + 1) * n],
            &qdd[i * n..(i + 1) * n],
            margins,
        );
        if k % every == 0 || k + 1 == m || jc.is_some() {
            if let Some((reason, detail)) = jc.or_else(|| {
                feasibility::check_sample(
                    model,
                    o,
                    feasibility::Scene {
                        world,
                        shapes: &ev.shapes,
                        beads,
                    },
                    q,
                    beads.laid_at(k),
                    &mut sc.poses,
                    margins,
                )
            }) {
                let mi = job.pieces[motion.piece[k]].move_index;
                let tip = frame.apply(&motion.p[k]);
                return Err(Outcome::Infeasible(Infeasible {
                    reason,
                    sample: Some(k),
                    t_s: Some(k as f64 * dt),
                    line: Some(job.line_of(mi)),
                    point_m: Some([tip.x, tip.y, tip.z]),
                    detail,
                }));
            }
        }
    }
    // Energy, with the full evaluation's weights, into each unit's vector (or the rest).
    let dim = FIXED + 3 * n;
    for k in r {
        let i = k - t0;
        let w = crate::numerics::trapezoid_weight(k, m, dt);
        let p = match energy::eval_sample(
            &job.energy,
            &mut sc.data,
            &qs[i * n..(i + 1) * n],
            &qd[i * n..(i + 1) * n],
            &qdd[i * n..(i + 1) * n],
            &mut sc.sp,
        ) {
            Ok(p) => p,
            Err(e) => {
                return Err(Outcome::Infeasible(Infeasible {
                    reason: Reason::ModelError,
                    sample: Some(k),
                    t_s: Some(k as f64 * dt),
                    line: None,
                    point_m: None,
                    detail: e.to_string(),
                }))
            }
        };
        let acc: &mut [f64] = match unit_of(k) {
            Some(u) => unit_e[u].get_or_insert_with(|| vec![0.0; dim]),
            None => exact,
        };
        let sp = &sc.sp;
        acc[SUPPLY] += w * p;
        acc[DRIVES] += w * sp.p_drives;
        acc[REGEN] += w * sp.p_regeneration_lost;
        for j in 0..n {
            let pm = sp.p_mech[j];
            acc[FIXED + j] += w * pm;
            acc[FIXED + n + j] += w * pm.abs();
            acc[MPOS] += w * pm.max(0.0);
            acc[FIXED + 2 * n + j] += w * sp.p_el[j];
            acc[FRICTION] += w * sp.p_friction[j];
            acc[GEAR] += w * sp.p_gear[j];
            acc[COPPER] += w * sp.p_copper[j];
        }
    }
    Ok(())
}

/// The full re-evaluation of an optimisation's answer beside its estimate (JSON: the
/// `optimise.path_reduction` object of an optimise summary, docs/json.md).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FullCheck {
    /// What the reduction found in the path.
    pub summary: Summary,
    /// The reduced estimate of the objective at the answer, J.
    pub estimate_j: f64,
    /// Its stated error, J.
    pub error_j: f64,
    /// The full evaluation's objective at the answer, J.
    pub full_j: f64,
    /// (estimate − full) / full, %.
    pub difference_pct: f64,
    /// Whether |estimate − full| ≤ the stated error.
    pub within_error: bool,
    /// Layers evaluated sample by sample at the answer (of `summary.layers`).
    pub layers_evaluated: usize,
}

/// Re-evaluate `best` (evaluated with the reduction) in full: returns the full result and the
/// comparison, or `None` when `best` was not an estimate (evaluated in full already). The
/// full result may be infeasible (an interior layer the reduction did not check for
/// collisions): the caller must say so.
pub fn confirm(
    ev: &Evaluator<'_, '_>,
    best: &Evaluated,
) -> crate::error::Result<Option<(Evaluated, FullCheck)>> {
    let (Some(red), Some(f)) = (ev.reduction(), best.feasible()) else {
        return Ok(None);
    };
    let Some(est) = f.path_reduction.as_ref().filter(|e| e.fallback.is_none()) else {
        return Ok(None);
    };
    let mut sc = ev.scratch()?;
    let full = Evaluated {
        placement: best.placement,
        outcome: ev.evaluate_full_inner(&mut sc, &best.placement),
    };
    let full_j = full.cost();
    let chk = FullCheck {
        summary: red.summary.clone(),
        estimate_j: f.energy_j,
        error_j: est.error_j,
        full_j,
        difference_pct: (f.energy_j - full_j) / full_j * 100.0,
        within_error: (f.energy_j - full_j).abs() <= est.error_j,
        layers_evaluated: est.layers_evaluated,
    };
    Ok(Some((full, chk)))
}
