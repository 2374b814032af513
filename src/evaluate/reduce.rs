//! Error-controlled path reduction for long prints: a placement of a path whose layers repeat
//! up to a shift in z ([`crate::toolpath::repeat`]) is evaluated on a few representative
//! layers, and the energy of the others is interpolated over z.
//!
//! # What is evaluated, and how
//! The job's Cartesian plan (placement-independent, [`crate::evaluate::PathJob::plan`]) is cut into
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
//! # Where a joint's rate limit binds: the layer is re-planned on its own
//! The feasibility checks of every evaluated unit come first (an infeasible placement costs
//! no re-planning). Then a unit (or the stretch before or after the repeating run) where a
//! joint's velocity, acceleration or jerk demand exceeds its limit is re-planned on its own
//! ([`Replanner`]): the stretch of path from the unit's start to its end, with enough path
//! before and after ([`Reduction`]'s `pad_m`), entered and left at the unslowed plan's node
//! speeds, slowed down by the full evaluation's rule until the limits hold. Its energy and
//! sample count replace the unslowed ones; for the units between evaluated ones, the
//! slow-down (energy and samples added) is interpolated linearly in z between the evaluated
//! neighbours, with a stated error per unit of the larger of their difference and half the
//! larger slow-down, plus one sample's energy per re-planned unit (its samples' phase). A unit
//! still over a limit after `max_iterations` plans makes the placement infeasible. The rule
//! is local ([`crate::timing::joint::Slowing`]): the speed is capped around a sample over a
//! limit, and where the demand comes from a ramp (a limit that binds again where the speed is
//! already capped, typically) the acceleration is lowered over that ramp only, so the full
//! evaluation's slow-down of a layer is that of the layer re-planned on its own, up to the
//! samples' phase.
//!
//! Where the rate demand may bind between evaluated units unlike at them (per class and
//! channel, the larger of the two neighbours' peaks plus the largest change of the peak
//! between neighbouring evaluated units exceeds [`ReduceOptions::headroom`] of the limit),
//! more units are evaluated: the next node count, then every unit in that interval.
//!
//! # When the full evaluation is used instead
//! The placement is evaluated in full (and the estimate records why) when the stated error is
//! still above [`ReduceOptions::max_rel_error`] with the most nodes.
//! (A ramp where a limit binds again lowers the acceleration over that ramp only, which
//! re-planning a layer on its own reproduces.)
//! The wrist rule (near the wrist singularity, joints 4 and 6 within a share of their limits)
//! needs joint rates: units where a tracked sample comes within twice `wrist_min` of the
//! wrist singularity are evaluated sample by sample unless the evaluated units come near it
//! too and use at most `headroom` of the allowed share there.
//!
//! # Limitations
//! Between the representative layers, collisions are not checked (the extreme layers, where
//! the part is lowest and highest, are), the configuration is tracked at the stride, not
//! every sample, and a rate limit that binds only there is found only through the peak bound
//! above. The answer of an optimisation is therefore always re-evaluated in full
//! ([`confirm`]).

use crate::energy;
use crate::evaluate::evaluator::{Evaluated, Evaluator, Feasible, Losses, Objective, Scratch};
use crate::evaluate::feasibility::{self, Infeasible, Margins, Reason, World};
use crate::frame::Placement;
use crate::kinematics::{nozzle_target, opw, IkFailure, JointVec};
use crate::math::{Frame, V3};
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
    /// Largest relative stated error accepted (dimensionless): an estimate whose stated error
    /// is still above it with the most nodes is replaced by the full evaluation, which says
    /// why.
    pub max_rel_error: f64,
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
            max_rel_error: 5e-3,
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
    /// Stated error of the objective energy, J (0 when evaluated in full; at least the
    /// summation order's rounding otherwise, even when every layer was evaluated).
    pub error_j: f64,
    /// Layers (units) of the path.
    pub layers: usize,
    /// Layers evaluated sample by sample.
    pub layers_evaluated: usize,
    /// Samples evaluated sample by sample (of [`Feasible::samples`]).
    pub samples_evaluated: usize,
    /// Layers (or the stretches before and after the repeating run) re-planned on their own
    /// because a joint's rate limit bound there (0 when evaluated in full).
    #[serde(default)]
    pub layers_replanned: usize,
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
    /// Speed at each node of the job's plan with no slow-down, m/s (the boundary speeds of a
    /// layer re-planned on its own, see [`replan`]).
    v0: Vec<f64>,
    /// Path length added on each side of a layer re-planned on its own, m: beyond the reach
    /// of a slow-down inside the layer (deceleration distance, jerk filter, the nodes capped
    /// around a violation), with a factor 3.
    pad_m: f64,
    /// Bounding box (part frame, m: lower and upper corner) of each [`REACH_CHUNK`] samples
    /// of the job's plan, for the reach check of every sample (see [`chunk_reaches`]).
    reach_boxes: Vec<[V3; 2]>,
    /// What the evaluations did (counts, for benchmarks and tests).
    stats: Stats,
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
        job: &crate::evaluate::PathJob<'_>,
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
        let nodes = &job.plan.nodes;
        let popts = &job.profile;
        let v0 = job.plan.v.clone();
        let v_max = nodes.cap.iter().copied().fold(0.0, f64::max);
        let taps = ((popts.accel / popts.jerk / popts.dt).round()).max(1.0);
        // Deceleration distance, the filter's length and the capped nodes (± taps + 2
        // samples) at the highest speed, three times over (a ramp whose acceleration a re-plan
        // lowers to a third reaches as far).
        let pad_m = 3.0
            * (v_max * v_max / (2.0 * popts.accel.max(1e-9))
                + (2.0 * taps + 4.0) * popts.dt * v_max)
            + 0.01;
        let reach_boxes = motion
            .p
            .chunks(REACH_CHUNK)
            .map(|c| {
                c.iter()
                    .fold([c[0], c[0]], |[lo, hi], q| [lo.inf(q), hi.sup(q)])
            })
            .collect();
        Ok(Reduction {
            units,
            z,
            classes,
            v0,
            pad_m,
            reach_boxes,
            stats: Stats::default(),
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

/// Samples per bounding box of the reach check ([`Reduction`]'s `reach_boxes`).
const REACH_CHUNK: usize = 256;

/// Whether the wrist centre of every sample in the part-frame box `[lo, hi]` (m) is certainly
/// within the reach of an OPW arm's front shoulder branch, when a sample `q` has its wrist
/// centre at `R (q + o)` (base frame; `R` a rotation about z, `o` in m): the distance from
/// joint 1's axis (less the lateral offset `b`) and from joint 2's axis over the box,
/// bounded from below and above, clear the conditions of [`opw::arm_reaches`] by a micrometre
/// (far beyond rounding). `false` says nothing: the samples are then checked one by one.
fn chunk_reaches(p: &crate::robot::opw::OpwParams, lo: &V3, hi: &V3, o: &V3) -> bool {
    const MARGIN_M: f64 = 1e-6;
    // Squared distance from 0 to the interval [a, b], and the larger square of its ends.
    let near2 = |a: f64, b: f64| {
        if a > 0.0 {
            a * a
        } else if b < 0.0 {
            b * b
        } else {
            0.0
        }
    };
    let far2 = |a: f64, b: f64| (a * a).max(b * b);
    let (xl, xh) = (lo.x + o.x, hi.x + o.x);
    let (yl, yh) = (lo.y + o.y, hi.y + o.y);
    let b2 = p.b * p.b;
    let rmin2 = near2(xl, xh) + near2(yl, yh) - b2;
    let rmax2 = far2(xl, xh) + far2(yl, yh) - b2;
    // (NaN-safe: a NaN bound is not clear.)
    if rmin2.is_nan() || rmin2 <= MARGIN_M || !rmax2.is_finite() {
        return false;
    }
    let (xl, xh) = (rmin2.sqrt() - p.a1, rmax2.sqrt() - p.a1);
    let (zl, zh) = (lo.z + o.z - p.c1, hi.z + o.z - p.c1);
    let s_min = (near2(xl, xh) + near2(zl, zh)).sqrt();
    let s_max = (far2(xl, xh) + far2(zl, zh)).sqrt();
    let kappa = (p.a2 * p.a2 + p.c3 * p.c3).sqrt();
    s_min > (p.c2 - kappa).abs() + MARGIN_M && s_max < p.c2 + kappa - MARGIN_M
}

/// Counts of what the reduced evaluations of one [`Reduction`] did (for benchmarks and
/// tests; the results never depend on them).
#[derive(Debug, Default)]
pub(crate) struct Stats {
    estimates: std::sync::atomic::AtomicUsize,
    rejected: std::sync::atomic::AtomicUsize,
    full: std::sync::atomic::AtomicUsize,
    replanned: std::sync::atomic::AtomicUsize,
}

impl Clone for Stats {
    /// A fresh count (a cloned reduction counts its own evaluations).
    fn clone(&self) -> Self {
        Stats::default()
    }
}

/// A snapshot of [`Stats`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// Placements evaluated on representative layers (estimates).
    pub estimates: usize,
    /// Placements found infeasible by the reduced evaluation (no full evaluation).
    pub rejected: usize,
    /// Placements evaluated in full instead (whatever the outcome).
    pub full: usize,
    /// Layers (or the stretches before and after the repeating run) re-planned on their own
    /// because a joint's rate limit bound there.
    pub replanned_layers: usize,
}

impl Reduction {
    /// What the evaluations with this reduction did so far.
    pub fn counts(&self) -> Counts {
        use std::sync::atomic::Ordering::Relaxed;
        Counts {
            estimates: self.stats.estimates.load(Relaxed),
            rejected: self.stats.rejected.load(Relaxed),
            full: self.stats.full.load(Relaxed),
            replanned_layers: self.stats.replanned.load(Relaxed),
        }
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
    use std::sync::atomic::Ordering::Relaxed;
    match reduced(ev, red, sc, at) {
        Outcome::Done(f) => {
            red.stats.estimates.fetch_add(1, Relaxed);
            Ok(*f)
        }
        Outcome::Infeasible(i) => {
            red.stats.rejected.fetch_add(1, Relaxed);
            Err(i)
        }
        Outcome::Full(why) => {
            red.stats.full.fetch_add(1, Relaxed);
            let mut r = ev.evaluate_full_inner(sc, at);
            if let Ok(f) = &mut r {
                f.path_reduction = Some(Estimate {
                    error_j: 0.0,
                    layers: red.summary.layers,
                    layers_evaluated: red.summary.layers,
                    samples_evaluated: f.samples,
                    layers_replanned: 0,
                    fallback: Some(why),
                });
            }
            r
        }
    }
}

/// The reduced evaluation of `at` (see the module docs): every sample's reach, the
/// configuration tracked and checked on every stride-th sample, then the representative units
/// evaluated and the others interpolated.
fn reduced<'a>(
    ev: &Evaluator<'_, 'a>,
    red: &Reduction,
    sc: &mut Scratch<'a>,
    at: &Placement,
) -> Outcome {
    let job = ev.job;
    let motion = &*job.plan.motion;
    let m = motion.p.len();
    let o = &ev.feasibility;
    let every = o.check_every.max(1);
    let stride = red.options.stride.max(1).div_ceil(every) * every;
    let frame = at.frame();
    let rot = nozzle_target(&V3::zeros(), at.nozzle_yaw()).rot;
    let solver = sc.solver.clone();
    if m == 0 {
        return Outcome::Full("the plan has no samples".into());
    }
    // 1. Reach of every sample.
    if let Err(e) = reach_every_sample(ev, red, &solver, &frame, &rot) {
        return Outcome::Infeasible(e);
    }
    // The print head against the part printed so far, every sample of the plan (found once
    // per nozzle spin: it does not depend on where the robot stands).
    if let Some(e) = ev.head_infeasible(&job.plan.motion, &ev.beads, at) {
        return Outcome::Infeasible(e);
    }
    // 2. Configuration tracked on every stride-th sample, candidates as the full evaluation
    // orders them, and the geometric checks on the tracked samples.
    let thin_idx = thin_indices(m, stride);
    let tracker = Tracker {
        ev,
        solver: &solver,
        frame: &frame,
        rot,
        thin_idx: &thin_idx,
    };
    if let Err(e) = tracker.choose(&mut sc.red.thin) {
        return Outcome::Infeasible(e);
    }
    let segs = Segments::new(red, m);
    let mut refine = Refine::new(red);
    if let Err(e) = tracker.check(&segs, &sc.red.thin, &mut refine.near_wrist) {
        return Outcome::Infeasible(e);
    }
    // 3.–5. The evaluated units sample by sample, the rest interpolated.
    let world = World::new(&frame, ev.bbox_all, o).with_floor(&ev.shapes);
    let ctx = Ctx {
        ev,
        red,
        frame: &frame,
        rot,
        world: &world,
        stride,
        thin_idx: &thin_idx,
    };
    refine.run(&ctx, sc, &segs)
}

/// Step 1 of the module docs: the reach of every sample, coarse to fine (the fine pass skips
/// the chunks of samples whose bounding box is certainly within reach, which gives the same
/// verdict and sample).
fn reach_every_sample(
    ev: &Evaluator<'_, '_>,
    red: &Reduction,
    solver: &crate::kinematics::IkSolver<'_>,
    frame: &Frame,
    rot: &crate::math::M3,
) -> std::result::Result<(), Infeasible> {
    let job = ev.job;
    let model = job.robot;
    let motion = &*job.plan.motion;
    let m = motion.p.len();
    let coarse = (0..m).step_by(64);
    let Some(d) = solver.wrist_offset(rot) else {
        for k in coarse.chain(0..m) {
            let tip = frame.apply(&motion.p[k]);
            solver
                .reachable(&Frame {
                    rot: *rot,
                    pos: tip,
                })
                .map_err(|r| unreachable_at(job, k, tip, r))?;
        }
        return Ok(());
    };
    let check = |k: usize| {
        let tip = frame.apply(&motion.p[k]);
        solver
            .wrist_centre_reachable(&(tip + d), 1e-9)
            .map_err(|r| unreachable_at(job, k, tip, r))
    };
    for k in coarse {
        check(k)?;
    }
    // The wrist centre of part-frame point q is R (q + o) in the base frame.
    let o = frame.rot.transpose() * (frame.pos + d);
    let boxes = if red.summary.samples == m {
        &red.reach_boxes[..]
    } else {
        &[]
    };
    for c in 0..m.div_ceil(REACH_CHUNK) {
        let clear = model
            .opw
            .as_ref()
            .zip(boxes.get(c))
            .is_some_and(|(p, bx)| chunk_reaches(p, &bx[0], &bx[1], &o));
        if clear {
            continue;
        }
        for k in c * REACH_CHUNK..((c + 1) * REACH_CHUNK).min(m) {
            check(k)?;
        }
    }
    Ok(())
}

/// The tracked samples of a plan of `m` samples: every `stride`-th and the last.
fn thin_indices(m: usize, stride: usize) -> Vec<usize> {
    (0..m)
        .step_by(stride)
        .chain((!(m - 1).is_multiple_of(stride)).then_some(m - 1))
        .collect()
}

/// Step 2 of the module docs at one placement: the arm's configuration tracked on the tracked
/// samples and checked there.
struct Tracker<'c, 'j, 'a> {
    ev: &'c Evaluator<'j, 'a>,
    solver: &'c crate::kinematics::IkSolver<'a>,
    frame: &'c Frame,
    /// The nozzle's orientation in the base frame (the same at every sample).
    rot: crate::math::M3,
    thin_idx: &'c [usize],
}

impl Tracker<'_, '_, '_> {
    /// The tool target at sample `k` of the job's plan, and its tip (base frame).
    fn target(&self, k: usize) -> (Frame, V3) {
        let tip = self.frame.apply(&self.ev.job.plan.motion.p[k]);
        (
            Frame {
                rot: self.rot,
                pos: tip,
            },
            tip,
        )
    }

    /// Track the configurations at the first sample in the full evaluation's order until one
    /// follows every tracked sample (its joint positions left in `thin`, row-major); otherwise
    /// the failure furthest along the path.
    fn choose(&self, thin: &mut Vec<f64>) -> std::result::Result<(), Infeasible> {
        let job = self.ev.job;
        let model = job.robot;
        let dt = job.plan.motion.dt;
        let (t0, tip0) = self.target(0);
        let mut cands = self
            .solver
            .solve_all(&t0)
            .map_err(|r| unreachable_at(job, 0, tip0, r))?;
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
        let mut best_fail: Option<(usize, Infeasible)> = None;
        for c in &cands {
            let Some((k, e)) = self.track(c.q, &max_step, thin) else {
                return Ok(());
            };
            if best_fail.as_ref().is_none_or(|b| k > b.0) {
                best_fail = Some((k, e));
            }
        }
        Err(best_fail.map(|b| b.1).unwrap_or_else(|| {
            unreachable_at(
                job,
                0,
                tip0,
                IkFailure::Unsupported("no IK solution at the first sample".into()),
            )
        }))
    }

    /// Track the tracked samples from configuration `q0` at the first, each near the previous
    /// one's answer, into `thin`: the sample and failure where a sample is out of reach or a
    /// joint moves more than `max_step` per sample, if any.
    fn track(
        &self,
        q0: JointVec,
        max_step: &[f64],
        thin: &mut Vec<f64>,
    ) -> Option<(usize, Infeasible)> {
        let job = self.ev.job;
        let n = job.robot.dof();
        let dt = job.plan.motion.dt;
        let motion = &*job.plan.motion;
        thin.clear();
        let mut prev = q0;
        for (i, &k) in self.thin_idx.iter().enumerate() {
            let (tg, tip) = self.target(k);
            let q = match self.solver.solve_near(&tg, &prev) {
                Ok(q) => q,
                Err(r) => return Some((k, unreachable_at(job, k, tip, r))),
            };
            if i > 0 {
                let steps = (k - self.thin_idx[i - 1]) as f64;
                if let Some(j) =
                    (0..n).find(|&j| (q[j] - prev[j]).abs() > (max_step[j] * steps).min(1.0))
                {
                    let tf = crate::timing::TimingFailure::ConfigurationChange {
                        sample: k,
                        t: k as f64 * dt,
                        point: tip,
                        line: job.line_of(job.pieces[motion.piece[k]].move_index),
                        file: std::sync::Arc::new(job.source.clone()),
                        joint: j,
                        jump: (q[j] - prev[j]).abs(),
                    };
                    return Some((k, Infeasible::from_timing(&tf)));
                }
            }
            thin.extend_from_slice(&q[..n]);
            prev = q;
        }
        None
    }

    /// The geometric checks on the tracked samples (`thin`, row-major): joint positions with
    /// their margins, elbow and shoulder singularities. Units where the wrist comes near its
    /// singularity are marked in `near_wrist` (the wrist rule needs joint rates).
    fn check(
        &self,
        segs: &Segments<'_>,
        thin: &[f64],
        near_wrist: &mut [bool],
    ) -> std::result::Result<(), Infeasible> {
        let job = self.ev.job;
        let model = job.robot;
        let n = model.dof();
        let motion = &*job.plan.motion;
        let o = &self.ev.feasibility;
        let zeros = [0.0; crate::kinematics::MAX_DOF];
        for (i, &k) in self.thin_idx.iter().enumerate() {
            let q = &thin[i * n..(i + 1) * n];
            let opw_p = model.opw.as_ref().filter(|_| n >= 6);
            if let (Some(p), Some(u)) = (opw_p, segs.unit_of(k)) {
                let near = o
                    .wrist_min
                    .max(crate::evaluate::feasibility::margins::wrist_floor(o));
                if opw::wrist_singularity(p, q) < 2.0 * near {
                    near_wrist[u] = true;
                }
            }
            let fail = crate::evaluate::feasibility::margins::check_joint_sample(
                model,
                o,
                q,
                &zeros[..n],
                &zeros[..n],
                &mut Margins::default(),
            )
            .or_else(|| elbow_or_shoulder(o, opw_p?, q));
            if let Some((reason, detail)) = fail {
                let tip = self.frame.apply(&motion.p[k]);
                return Err(Infeasible {
                    reason,
                    sample: Some(k),
                    t_s: Some(k as f64 * motion.dt),
                    line: Some(job.line_of(job.pieces[motion.piece[k]].move_index)),
                    point_m: Some([tip.x, tip.y, tip.z]),
                    detail,
                });
            }
        }
        Ok(())
    }
}

/// The elbow or shoulder singularity margin that joint positions `q` of an OPW arm `p` break,
/// if any, with its detail.
fn elbow_or_shoulder(
    o: &crate::evaluate::feasibility::FeasibilityOptions,
    p: &crate::robot::opw::OpwParams,
    q: &[f64],
) -> Option<(Reason, String)> {
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
}

/// Where the samples of the job's plan belong. Segment ids: the units of the repeating run,
/// then the exact stretches before (`nu`) and after (`nu + 1`) the run.
struct Segments<'r> {
    units: &'r [Range<usize>],
    /// The samples of the repeating run.
    run: Range<usize>,
    /// Samples of the job's plan.
    m: usize,
}

impl<'r> Segments<'r> {
    /// The segments of `red` over a plan of `m` samples.
    fn new(red: &'r Reduction, m: usize) -> Self {
        let run = red.units.first().map_or(0, |u| u.start)..red.units.last().map_or(0, |u| u.end);
        Segments {
            units: &red.units,
            run,
            m,
        }
    }

    /// The unit of the repeating run that sample `k` belongs to, if any.
    #[inline]
    fn unit_of(&self, k: usize) -> Option<usize> {
        if !self.run.contains(&k) {
            return None;
        }
        let nu = self.units.len();
        let i = self.units.partition_point(|u| u.end <= k);
        (i < nu).then_some(i)
    }

    /// The segment that sample `k` belongs to.
    #[inline]
    fn seg_of(&self, k: usize) -> usize {
        let nu = self.units.len();
        self.unit_of(k)
            .unwrap_or(if k < self.run.start { nu } else { nu + 1 })
    }

    /// The samples of segment `g`.
    fn range(&self, g: usize) -> Range<usize> {
        let nu = self.units.len();
        if g < nu {
            self.units[g].clone()
        } else if g == nu {
            0..self.run.start
        } else {
            self.run.end..self.m
        }
    }
}

/// Steps 3–5 of the module docs at one placement: which units are evaluated sample by sample,
/// what they gave, and the segments re-planned where a joint rate limit binds.
struct Refine {
    /// Units evaluated sample by sample (or due to be).
    evaluated: Vec<bool>,
    /// Units that are interpolation nodes (Chebyshev–Lobatto in each class).
    node: Vec<bool>,
    /// Units where a tracked sample comes near the wrist singularity.
    near_wrist: Vec<bool>,
    /// Units evaluated so far.
    done: Vec<bool>,
    /// Interpolation nodes per class.
    level: usize,
    margins: Margins,
    /// Per segment: the additive quantities without slow-down.
    unit_e: Vec<Option<Vec<f64>>>,
    /// Per segment: the peak rate demand per joint and channel, as a share of the limit.
    peaks: Vec<Option<Vec<f64>>>,
    /// Per segment: where a joint rate limit binds (the first such sample).
    binds: Vec<Option<String>>,
    /// Per segment: the re-planned outcome, as a change.
    delta: Vec<Option<Replanned>>,
    samples_evaluated: usize,
    first_pass: bool,
}

impl Refine {
    /// Nothing evaluated yet; the first level's nodes marked.
    fn new(red: &Reduction) -> Self {
        let nu = red.units.len();
        let nseg = nu + 2;
        let mut r = Refine {
            evaluated: vec![false; nu],
            node: vec![false; nu],
            near_wrist: vec![false; nu],
            done: vec![false; nu],
            level: 5.min(red.options.max_nodes.max(3)),
            margins: Margins::default(),
            unit_e: vec![None; nseg],
            peaks: vec![None; nseg],
            binds: vec![None; nseg],
            delta: vec![None; nseg],
            samples_evaluated: 0,
            first_pass: true,
        };
        r.mark_nodes(red);
        r
    }

    /// Mark the current level's nodes of every class as nodes, to be evaluated.
    fn mark_nodes(&mut self, red: &Reduction) {
        for cl in &red.classes {
            for i in lobatto(cl.len(), self.level) {
                self.evaluated[cl[i]] = true;
                self.node[cl[i]] = true;
            }
        }
    }

    /// Go to the next node count where there is one and a class has more members than
    /// nodes; whether it did.
    fn raise_level(&mut self, red: &Reduction) -> bool {
        let next = 2 * self.level - 1;
        if next <= red.options.max_nodes && red.classes.iter().any(|c| c.len() > self.level) {
            self.level = next;
            self.mark_nodes(red);
            return true;
        }
        false
    }

    /// Evaluate units until the estimate's stated error is small enough: the outcome.
    fn run(mut self, ctx: &Ctx<'_, '_, '_>, sc: &mut Scratch<'_>, segs: &Segments<'_>) -> Outcome {
        let red = ctx.red;
        let ev = ctx.ev;
        let n = ev.job.robot.dof();
        let mut replanner = Replanner::new(ctx);
        loop {
            // Every window's feasibility first (cheap next to a re-plan), then the re-plans.
            if let Err(o) = self.evaluate_due(ctx, sc, segs) {
                return o;
            }
            if let Err(o) = self.replan_binding(ctx, sc, segs, &mut replanner) {
                return o;
            }
            // Joint rate demands of the interpolated units, bounded from the evaluated ones:
            // where a layer in between may bind unlike its evaluated neighbours, more layers
            // are evaluated (the next node count, then every layer of that stretch).
            let flagged = rate_bound(
                red,
                &self.peaks,
                &self.evaluated,
                &self.delta,
                red.options.headroom,
            );
            if !flagged.is_empty() {
                if !self.raise_level(red) {
                    for u in flagged {
                        self.evaluated[u] = true;
                    }
                }
                continue;
            }
            if self.wrist_rule_pending(ctx) {
                continue;
            }
            // 4./5. Interpolate per class; refine while the stated error is too large.
            let est = self.estimate(red, n, ev.objective);
            let err = est.error_j;
            let objective = objective_of(&est.total, n, ev.objective).abs();
            let too_big = err > red.options.rel_tol * objective;
            if too_big && self.raise_level(red) {
                continue;
            }
            if err > red.options.max_rel_error * objective {
                return Outcome::Full(format!(
                    "the estimate's stated error {:.3} % is above the accepted {:.3} %",
                    err / objective * 100.0,
                    red.options.max_rel_error * 100.0
                ));
            }
            return self.feasible(ctx, est);
        }
    }

    /// The sample ranges due now, contiguous ones merged: the exact stretches (first pass)
    /// and every unit marked and not done.
    fn due(&mut self, red: &Reduction, segs: &Segments<'_>) -> Vec<Range<usize>> {
        let mut ranges: Vec<Range<usize>> = Vec::new();
        if self.first_pass {
            if segs.run.start > 0 {
                ranges.push(0..segs.run.start);
            }
            if segs.run.end < segs.m {
                ranges.push(segs.run.end..segs.m);
            }
        }
        for (u, r) in red.units.iter().enumerate() {
            if self.evaluated[u] && !self.done[u] {
                ranges.push(r.clone());
                self.done[u] = true;
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
        merged
    }

    /// Step 3: track, check and integrate the samples due, window by window.
    fn evaluate_due(
        &mut self,
        ctx: &Ctx<'_, '_, '_>,
        sc: &mut Scratch<'_>,
        segs: &Segments<'_>,
    ) -> std::result::Result<(), Outcome> {
        for r in self.due(ctx.red, segs) {
            self.samples_evaluated += r.len();
            self.window(ctx, sc, r, segs)?;
        }
        self.first_pass = false;
        Ok(())
    }

    /// Step 3b: the segments where a joint rate limit binds re-planned on their own, as the
    /// controller slows down there (see [`Replanner`]), and each one's change noted.
    fn replan_binding(
        &mut self,
        ctx: &Ctx<'_, '_, '_>,
        sc: &mut Scratch<'_>,
        segs: &Segments<'_>,
        replanner: &mut Replanner,
    ) -> std::result::Result<(), Outcome> {
        let nseg = self.binds.len();
        let binding: Vec<usize> = (0..nseg).filter(|&g| self.binds[g].is_some()).collect();
        if binding.is_empty() {
            return Ok(());
        }
        replanner.run(ctx, sc, &binding, &|g| segs.range(g), &mut self.margins)?;
        for st in &replanner.stretches {
            let (Some(r), Some(e0)) = (&st.result, &self.unit_e[st.g]) else {
                continue;
            };
            let mut d = r.clone();
            for (x, b) in d.e.iter_mut().zip(e0) {
                *x -= b;
            }
            d.samples -= segs.range(st.g).len() as f64;
            self.delta[st.g] = Some(d);
        }
        Ok(())
    }

    /// The wrist rule on units not evaluated: accepted when the evaluated units come near the
    /// wrist singularity too and use at most `headroom` of the allowed share there; otherwise
    /// those units are marked to be evaluated sample by sample (and this says so).
    fn wrist_rule_pending(&mut self, ctx: &Ctx<'_, '_, '_>) -> bool {
        let red = ctx.red;
        let nu = red.units.len();
        let wrist_ok = self
            .margins
            .wrist_rate
            .is_some_and(|r| r <= red.options.headroom * ctx.ev.feasibility.wrist_rate_max);
        let pending: Vec<usize> = (0..nu)
            .filter(|&u| self.near_wrist[u] && !self.evaluated[u])
            .collect();
        if !wrist_ok && !pending.is_empty() {
            for u in pending {
                self.evaluated[u] = true;
            }
            return true;
        }
        false
    }

    /// The feasible outcome of the estimate `est`.
    fn feasible(self, ctx: &Ctx<'_, '_, '_>, est: Sum) -> Outcome {
        let (ev, red) = (ctx.ev, ctx.red);
        let n = ev.job.robot.dof();
        let motion = &*ev.job.plan.motion;
        let (m, dt) = (motion.p.len(), motion.dt);
        let (total, err) = (&est.total, est.error_j);
        let layers_evaluated =
            self.evaluated.iter().filter(|e| **e).count() + (red.summary.layers - red.units.len());
        let v = total;
        let jm = v[FIXED..FIXED + n].to_vec();
        let jabs = v[FIXED + n..FIXED + 2 * n].to_vec();
        let jel = v[FIXED + 2 * n..FIXED + 3 * n].to_vec();
        let energy_j = objective_of(v, n, ev.objective);
        if !energy_j.is_finite() {
            return Outcome::Full("non-finite estimate".into());
        }
        let samples = (m as f64 + est.extra_samples).round().max(1.0) as usize;
        let replanned = self.delta.iter().filter(|d| d.is_some()).count();
        red.stats
            .replanned
            .fetch_add(replanned, std::sync::atomic::Ordering::Relaxed);
        Outcome::Done(Box::new(Feasible {
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
            duration_s: dt * samples.saturating_sub(1) as f64,
            samples,
            rounds: 1 + usize::from(replanned > 0),
            joint_mechanical_j: jm,
            joint_mechanical_abs_j: jabs,
            joint_electrical_j: jel,
            margins: self.margins,
            path_reduction: Some(Estimate {
                error_j: err,
                layers: red.summary.layers,
                layers_evaluated,
                samples_evaluated: self.samples_evaluated,
                layers_replanned: replanned,
                fallback: None,
            }),
        }))
    }
}

/// Units between evaluated ones (per class) where a joint's rate demand may bind unlike at
/// their evaluated neighbours: per channel (joint × velocity/acceleration/jerk, as a share of
/// the limit), the larger of the two neighbours' peaks plus the largest change between
/// neighbouring evaluated units of the class, against `headroom`. Between two neighbours
/// that both bound (and were re-planned), the layers are taken to bind too: their slow-down
/// is interpolated (see [`Refine::estimate`]).
fn rate_bound(
    red: &Reduction,
    peaks: &[Option<Vec<f64>>],
    evaluated: &[bool],
    delta: &[Option<Replanned>],
    headroom: f64,
) -> Vec<usize> {
    let mut out = Vec::new();
    for cl in &red.classes {
        let ev: Vec<usize> = cl
            .iter()
            .copied()
            .filter(|&u| evaluated[u] && peaks[u].is_some())
            .collect();
        let Some(&first) = ev.first() else { continue };
        let channels = peaks[first].as_ref().map_or(0, |p| p.len());
        let step: Vec<f64> = (0..channels)
            .map(|c| {
                ev.windows(2)
                    .filter(|w| delta[w[0]].is_none() && delta[w[1]].is_none())
                    .map(|w| {
                        (peaks[w[1]].as_ref().unwrap()[c] - peaks[w[0]].as_ref().unwrap()[c]).abs()
                    })
                    .fold(0.0, f64::max)
            })
            .collect();
        for w in ev.windows(2) {
            let (a, b) = (w[0], w[1]);
            let between = cl
                .iter()
                .copied()
                .filter(|&u| !evaluated[u] && red.z[u] > red.z[a] && red.z[u] < red.z[b]);
            if delta[a].is_some() && delta[b].is_some() {
                continue;
            }
            let (pa, pb) = (peaks[a].as_ref().unwrap(), peaks[b].as_ref().unwrap());
            if (0..channels)
                .any(|c| pa[c].max(pb[c]) + step[c].max((pa[c] - pb[c]).abs()) > headroom)
            {
                out.extend(between);
            }
        }
    }
    out
}

/// A reduced estimate: the additive quantities, the stated error of the objective (J) and
/// the samples the slow-downs add (estimated where interpolated).
struct Sum {
    total: Vec<f64>,
    error_j: f64,
    extra_samples: f64,
}

/// Add `w` times `v` to `total`, element by element.
fn add_scaled(total: &mut [f64], v: &[f64], w: f64) {
    for (t, x) in total.iter_mut().zip(v) {
        *t += w * x;
    }
}

impl Refine {
    /// The estimate (see the module docs): per class, the energy per sample of the node units
    /// without slow-down interpolated over z, plus each unit's slow-down (re-planned minus
    /// unslowed energy and samples) interpolated linearly between its evaluated neighbours.
    fn estimate(&self, red: &Reduction, n: usize, obj: Objective) -> Sum {
        let nu = red.units.len();
        let dim = self
            .unit_e
            .iter()
            .flatten()
            .next()
            .map_or(FIXED + 3 * n, |v| v.len());
        let mut sum = Sum {
            total: vec![0.0; dim],
            error_j: 0.0,
            extra_samples: 0.0,
        };
        // The exact stretches and every evaluated unit: their own numbers.
        for g in (0..nu).filter(|&u| self.evaluated[u]).chain([nu, nu + 1]) {
            if let Some(e) = &self.unit_e[g] {
                add_scaled(&mut sum.total, e, 1.0);
            }
            if let Some(d) = &self.delta[g] {
                add_scaled(&mut sum.total, &d.e, 1.0);
                sum.extra_samples += d.samples;
            }
        }
        for cl in &red.classes {
            let rest: Vec<usize> = cl.iter().copied().filter(|&u| !self.evaluated[u]).collect();
            if rest.is_empty() {
                continue;
            }
            self.interpolate_class(red, cl, &rest, n, obj, &mut sum);
            self.interpolate_slowdowns(red, cl, &rest, n, obj, &mut sum);
        }
        self.add_phase_errors(red, n, obj, &mut sum);
        sum.error_j += summation_rounding(red.summary.samples, &self.unit_e, &sum.total, n, obj);
        sum
    }

    /// Class `cl`'s units not evaluated (`rest`): the energy per sample of the node units
    /// (no slow-down) interpolated over z, times each unit's samples, added to `sum`; its
    /// error, the nested lower order's difference plus one sample's energy per unit.
    fn interpolate_class(
        &self,
        red: &Reduction,
        cl: &[usize],
        rest: &[usize],
        n: usize,
        obj: Objective,
        sum: &mut Sum,
    ) {
        let dim = sum.total.len();
        let len = |u: usize| red.units[u].len() as f64;
        let nodes: Vec<usize> = cl.iter().copied().filter(|&u| self.node[u]).collect();
        let xs: Vec<f64> = nodes.iter().map(|&u| red.z[u]).collect();
        let ys: Vec<Vec<f64>> = nodes
            .iter()
            .map(|&u| {
                self.unit_e[u]
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
        add_scaled(&mut sum.total, &hi, 1.0);
        // One sample's energy per interpolated unit: the phase of unit boundaries.
        let per_sample = ys
            .iter()
            .map(|y| objective_of(y, n, obj).abs())
            .fold(0.0, f64::max);
        sum.error_j += (objective_of(&hi, n, obj) - objective_of(&lo, n, obj)).abs()
            + rest.len() as f64 * per_sample;
    }

    /// Class `cl`'s units not evaluated (`rest`): the slow-down linear in z between the
    /// evaluated neighbours, added to `sum`; the error stated per unit is the larger of their
    /// difference and half the larger slow-down.
    fn interpolate_slowdowns(
        &self,
        red: &Reduction,
        cl: &[usize],
        rest: &[usize],
        n: usize,
        obj: Objective,
        sum: &mut Sum,
    ) {
        let dim = sum.total.len();
        let evs: Vec<usize> = cl.iter().copied().filter(|&u| self.evaluated[u]).collect();
        for &u in rest {
            let b = evs.partition_point(|&e| red.z[e] < red.z[u]);
            let (Some(&ua), Some(&ub)) = (evs.get(b.wrapping_sub(1)), evs.get(b)) else {
                continue;
            };
            let (da, db) = (&self.delta[ua], &self.delta[ub]);
            if da.is_none() && db.is_none() {
                continue;
            }
            let t = (red.z[u] - red.z[ua]) / (red.z[ub] - red.z[ua]);
            let zero = Replanned {
                e: vec![0.0; dim],
                samples: 0.0,
            };
            let (da, db) = (da.as_ref().unwrap_or(&zero), db.as_ref().unwrap_or(&zero));
            for ((x, a), b) in sum.total.iter_mut().zip(&da.e).zip(&db.e) {
                *x += (1.0 - t) * a + t * b;
            }
            sum.extra_samples += (1.0 - t) * da.samples + t * db.samples;
            let (oa, ob) = (objective_of(&da.e, n, obj), objective_of(&db.e, n, obj));
            sum.error_j += (oa - ob).abs().max(0.5 * oa.abs().max(ob.abs()));
        }
    }

    /// Every re-planned segment: its phase against the full evaluation, one sample's energy
    /// (the re-planned stretch starts its samples at its own first node; the full
    /// evaluation's samples there are shifted by every slow-down before them), added to
    /// `sum`'s error.
    fn add_phase_errors(&self, red: &Reduction, n: usize, obj: Objective, sum: &mut Sum) {
        let nu = red.units.len();
        for g in 0..self.unit_e.len() {
            if let (Some(_), Some(e)) = (&self.delta[g], &self.unit_e[g]) {
                let samples = if g < nu {
                    red.units[g].len()
                } else {
                    red.summary
                        .samples
                        .saturating_sub(red.units.iter().map(|u| u.len()).sum())
                };
                sum.error_j += objective_of(e, n, obj).abs() / samples.max(1) as f64;
            }
        }
    }
}

/// The rounding floor of an estimate's stated error, J: the estimate adds each unit's own sum
/// of sample energies, the full evaluation sums every sample in one run, and the two orders
/// differ by rounding even when every unit is evaluated sample by sample. Recursive summation
/// of `samples` terms errs by at most `samples` × ε × Σ|terms| (Higham, *Accuracy and
/// Stability of Numerical Algorithms*, §4.2) for each order; the magnitude taken is the larger
/// of the units' summed |objective| and the total's |objective| (Σ|terms| itself when a unit's
/// samples share a sign, as the supply's do: standby keeps it positive), doubled for the two
/// orders. Without it an estimate from every layer states an error of 0 J and a difference of
/// 10⁻¹⁰ J reads as outside it.
fn summation_rounding(
    samples: usize,
    unit_e: &[Option<Vec<f64>>],
    total: &[f64],
    n: usize,
    obj: Objective,
) -> f64 {
    let units: f64 = unit_e
        .iter()
        .flatten()
        .map(|e| objective_of(e, n, obj).abs())
        .sum();
    let magnitude = units.max(objective_of(total, n, obj).abs());
    2.0 * samples as f64 * f64::EPSILON * magnitude
}

/// What a re-planned segment changes: the additive quantities and the sample count, each
/// as re-planned minus unslowed (as returned by [`replan`]: the re-planned values).
#[derive(Clone, Debug)]
struct Replanned {
    e: Vec<f64>,
    samples: f64,
}

/// The placement-wide inputs of [`window`] and [`replan`].
struct Ctx<'c, 'j, 'a> {
    ev: &'c Evaluator<'j, 'a>,
    red: &'c Reduction,
    frame: &'c Frame,
    /// The nozzle's orientation in the base frame (the same at every sample).
    rot: crate::math::M3,
    world: &'c World,
    stride: usize,
    thin_idx: &'c [usize],
}

/// The largest demand over limit of sample `i` of derivatives `qd`, `qdd`, `qddd`
/// (row-major), with the joint and the limit's name, updating `peak` (3 per joint).
fn rates(
    model: &crate::robot::RobotModel,
    check_jerk: bool,
    qd: &[f64],
    qdd: &[f64],
    qddd: &[f64],
    i: usize,
    peak: &mut [f64],
) -> Option<(usize, crate::timing::LimitKind, f64)> {
    use crate::timing::LimitKind as K;
    let n = model.dof();
    let mut worst: Option<(usize, K, f64)> = None;
    for (j, jt) in model.joints.iter().enumerate() {
        for (c, (v, lim, kind)) in [
            (qd[i * n + j], jt.velocity_limit, K::Velocity),
            (qdd[i * n + j], jt.acceleration_limit, K::Acceleration),
            (
                if check_jerk { qddd[i * n + j] } else { 0.0 },
                jt.jerk_limit,
                K::Jerk,
            ),
        ]
        .into_iter()
        .enumerate()
        {
            if !(lim.is_finite() && lim > 0.0) {
                continue;
            }
            let ratio = v.abs() / lim;
            peak[3 * j + c] = peak[3 * j + c].max(ratio);
            if ratio > 1.0 && worst.is_none_or(|w| ratio > w.2) {
                worst = Some((j, kind, ratio));
            }
        }
    }
    worst
}

/// Feasibility of the tracked samples `idx` (indices into `qs`, `qd`, `qdd`, row-major) as the
/// full evaluation checks it: joint margins and the wrist rule on every sample, singularities
/// and collisions on every `check_every`-th. `at(i)`: the sample of the job's plan that sample
/// `i` stands for (its index there, for the beads laid, and the place reported), its
/// position (part frame) and whether it is checked in full.
fn check(
    ctx: &Ctx<'_, '_, '_>,
    poses: &mut Vec<parry3d_f64::math::Isometry<f64>>,
    js: &Joints<'_>,
    idx: impl Iterator<Item = usize>,
    at: &dyn Fn(usize) -> (usize, V3, bool),
    margins: &mut Margins,
) -> std::result::Result<(), Outcome> {
    let ev = ctx.ev;
    let job = ev.job;
    let model = job.robot;
    let n = model.dof();
    let o = &ev.feasibility;
    let motion = &*job.plan.motion;
    let beads = &ev.beads;
    let (qs, qd, qdd) = (js.qs, js.qd, js.qdd);
    for i in idx {
        let q = &qs[i * n..(i + 1) * n];
        let jc = crate::evaluate::feasibility::margins::check_joint_sample(
            model,
            o,
            q,
            &qd[i * n..(i + 1) * n],
            &qdd[i * n..(i + 1) * n],
            margins,
        );
        let (k, p, full) = at(i);
        if full || jc.is_some() {
            if let Some((reason, detail)) = jc.or_else(|| {
                feasibility::check_sample(
                    model,
                    o,
                    feasibility::Scene {
                        world: ctx.world,
                        shapes: &ev.shapes,
                        beads,
                    },
                    q,
                    beads.laid_at(k),
                    poses,
                    margins,
                )
            }) {
                let mi = job.pieces[motion.piece[k]].move_index;
                let tip = ctx.frame.apply(&p);
                return Err(Outcome::Infeasible(Infeasible {
                    reason,
                    sample: Some(k),
                    t_s: Some(k as f64 * motion.dt),
                    line: Some(job.line_of(mi)),
                    point_m: Some([tip.x, tip.y, tip.z]),
                    detail,
                }));
            }
        }
    }
    Ok(())
}

/// Joint positions and their first two derivatives of tracked samples (row-major).
struct Joints<'t> {
    qs: &'t [f64],
    qd: &'t [f64],
    qdd: &'t [f64],
}

impl Joints<'_> {
    /// The energy model at sample `i` into `sp`; a model error is the infeasibility at its
    /// sample of the job's plan, `at_sample(i)`.
    #[inline]
    fn eval(
        &self,
        job: &crate::evaluate::PathJob<'_>,
        data: &mut crate::dynamics::DynData,
        sp: &mut crate::energy::SamplePower,
        i: usize,
        at_sample: &dyn Fn(usize) -> usize,
    ) -> std::result::Result<(), Outcome> {
        let n = job.robot.dof();
        let dt = job.plan.motion.dt;
        energy::eval_sample(
            &job.energy,
            data,
            &self.qs[i * n..(i + 1) * n],
            &self.qd[i * n..(i + 1) * n],
            &self.qdd[i * n..(i + 1) * n],
            sp,
        )
        .map(|_| ())
        .map_err(|e| Outcome::Infeasible(Infeasible::model_error(at_sample(i), dt, &e)))
    }
}

/// Where the energy of tracked samples goes (see [`integrate`]).
struct Sink<'w> {
    /// Trapezoid weight of sample `i`, s.
    w: &'w dyn Fn(usize) -> f64,
    /// The sums that sample `i` is added to (an index into `acc`).
    dest: &'w dyn Fn(usize) -> usize,
    /// The sample of the job's plan that sample `i` stands for (errors name it).
    at_sample: &'w dyn Fn(usize) -> usize,
    /// The sums (every additive quantity).
    acc: &'w mut [Option<Vec<f64>>],
}

impl Sink<'_> {
    /// Sample `i`'s powers (`n` joints) added into its sums, in a fixed order (the same sums,
    /// bit for bit, however the powers were computed).
    #[inline]
    fn add(&mut self, n: usize, i: usize, sp: &crate::energy::SamplePower) {
        let dim = FIXED + 3 * n;
        let w = (self.w)(i);
        let acc = self.acc[(self.dest)(i)].get_or_insert_with(|| vec![0.0; dim]);
        acc[SUPPLY] += w * sp.p_supply;
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
}

/// Energy of the tracked samples `idx` of `js`, added to `sink` sample by sample in sample
/// order.
fn integrate(
    ctx: &Ctx<'_, '_, '_>,
    data: &mut crate::dynamics::DynData,
    sp: &mut crate::energy::SamplePower,
    js: &Joints<'_>,
    idx: impl Iterator<Item = usize>,
    sink: &mut Sink<'_>,
) -> std::result::Result<(), Outcome> {
    let job = ctx.ev.job;
    let n = job.robot.dof();
    let level = crate::simd::level();
    if level == crate::simd::Level::Scalar || !job.energy.batchable() {
        for i in idx {
            js.eval(job, data, sp, i, sink.at_sample)?;
            sink.add(n, i, sp);
        }
        return Ok(());
    }
    integrate_lanes(job, data, sp, js, idx, sink, level)
}

/// [`integrate`] in runs of up to LANES consecutive samples in lockstep (energy::eval_rows:
/// each sample's powers bit for bit the per-sample path's), added sample by sample.
fn integrate_lanes(
    job: &crate::evaluate::PathJob<'_>,
    data: &mut crate::dynamics::DynData,
    sp: &mut crate::energy::SamplePower,
    js: &Joints<'_>,
    idx: impl Iterator<Item = usize>,
    sink: &mut Sink<'_>,
    level: crate::simd::Level,
) -> std::result::Result<(), Outcome> {
    let n = job.robot.dof();
    let mut lanes = energy::PowerLanes::default();
    let mut inputs = energy::LaneInputs::default();
    let mut idx = idx.peekable();
    while let Some(i0) = idx.next() {
        let mut count = 1;
        while count < crate::simd::LANES && idx.peek() == Some(&(i0 + count)) {
            idx.next();
            count += 1;
        }
        let rows = energy::Rows {
            q: &js.qs[i0 * n..],
            sincos: None,
            qd: &js.qd[i0 * n..],
            qdd: &js.qdd[i0 * n..],
        };
        if energy::eval_rows(
            &job.energy,
            data,
            count,
            &rows,
            &mut inputs,
            &mut lanes,
            level,
        )
        .is_ok()
        {
            for l in 0..count {
                sink.add(n, i0 + l, &lanes.sample(l));
            }
        } else {
            // The error at its own sample, as the per-sample path reports it.
            for i in i0..i0 + count {
                js.eval(job, data, sp, i, sink.at_sample)?;
                sink.add(n, i, sp);
            }
        }
    }
    Ok(())
}

/// The tool tip `tip` (base frame, m) at sample `k` of the job's plan is out of the arm's
/// reach: the failure as the timing reports it, naming the path's file and the move's line.
fn unreachable_at(
    job: &crate::evaluate::PathJob<'_>,
    k: usize,
    tip: V3,
    reason: IkFailure,
) -> Infeasible {
    let motion = &*job.plan.motion;
    let mi = job.pieces[motion.piece[k]].move_index;
    Infeasible::from_timing(&crate::timing::TimingFailure::Unreachable {
        sample: k,
        t: k as f64 * motion.dt,
        point: tip,
        line: job.line_of(mi),
        reason,
        file: std::sync::Arc::new(job.source.clone()),
    })
}

/// Track the samples `r` of the job's plan (and a few on each side, for the derivatives)
/// into `qs`, from the tracked sample at or before them: that sample.
fn track_window(
    ctx: &Ctx<'_, '_, '_>,
    sc: &Scratch<'_>,
    r: &Range<usize>,
    qs: &mut Vec<f64>,
) -> std::result::Result<usize, Outcome> {
    const PAD: usize = 4;
    let job = ctx.ev.job;
    let n = job.robot.dof();
    let motion = &*job.plan.motion;
    let m = motion.p.len();
    let lo = r.start.saturating_sub(PAD);
    let hi = (r.end + PAD).min(m);
    // Start at the tracked sample at or before `lo`.
    let ti = (lo / ctx.stride).min(ctx.thin_idx.len() - 1);
    let t0 = ctx.thin_idx[ti];
    // IK near the previous sample's answer, sample by sample from the tracked one (the
    // lockstep batches of track_near: the same answers and first failure).
    crate::timing::joint::track_near(
        &sc.solver,
        &ctx.rot,
        hi - t0,
        |i| ctx.frame.apply(&motion.p[t0 + i]),
        &sc.red.thin[ti * n..(ti + 1) * n],
        qs,
    )
    .map_err(|(i, tip, reason)| Outcome::Infeasible(unreachable_at(job, t0 + i, tip, reason)))?;
    Ok(t0)
}

impl Refine {
    /// Track, check and integrate the samples `r` of the job's plan (a union of whole
    /// segments: units and the exact stretches). A joint rate limit exceeded on a segment is
    /// noted in `binds` (that segment is then re-planned, see [`Replanner`]); the feasibility
    /// checks go on.
    fn window(
        &mut self,
        ctx: &Ctx<'_, '_, '_>,
        sc: &mut Scratch<'_>,
        r: Range<usize>,
        segs: &Segments<'_>,
    ) -> std::result::Result<(), Outcome> {
        let job = ctx.ev.job;
        let n = job.robot.dof();
        let motion = &*job.plan.motion;
        let m = motion.p.len();
        let dt = motion.dt;
        let every = ctx.ev.feasibility.check_every.max(1);
        let mut qs = std::mem::take(&mut sc.red.qs);
        let t0 = match track_window(ctx, sc, &r, &mut qs) {
            Ok(t0) => t0,
            Err(e) => {
                sc.red.qs = qs;
                return Err(e);
            }
        };
        let (qd, qdd, qddd) = crate::timing::joint::differentiate(&qs, n, dt);
        self.note_rates(ctx, &r, t0, segs, [&qd, &qdd, &qddd]);
        let js = Joints {
            qs: &qs,
            qd: &qd,
            qdd: &qdd,
        };
        let res = check(
            ctx,
            &mut sc.poses,
            &js,
            (r.start - t0)..(r.end - t0),
            &|i| {
                let k = i + t0;
                (k, motion.p[k], k.is_multiple_of(every) || k + 1 == m)
            },
            &mut self.margins,
        )
        .and_then(|()| {
            integrate(
                ctx,
                &mut sc.data,
                &mut sc.sp,
                &js,
                (r.start - t0)..(r.end - t0),
                &mut Sink {
                    w: &|i| crate::numerics::trapezoid_weight(i + t0, m, dt),
                    dest: &|i| segs.seg_of(i + t0),
                    at_sample: &|i| i + t0,
                    acc: &mut self.unit_e,
                },
            )
        });
        sc.red.qs = qs;
        res
    }

    /// The joint rate demands of the samples `r` (derivatives `d` of the samples tracked from
    /// `t0`: velocity, acceleration, jerk, row-major) into each segment's peaks, and the first
    /// sample where a limit binds into its `binds`.
    fn note_rates(
        &mut self,
        ctx: &Ctx<'_, '_, '_>,
        r: &Range<usize>,
        t0: usize,
        segs: &Segments<'_>,
        d: [&[f64]; 3],
    ) {
        let model = ctx.ev.job.robot;
        let n = model.dof();
        let check_jerk = ctx.ev.job.joint.check_jerk;
        for k in r.clone() {
            let g = segs.seg_of(k);
            let peak = self.peaks[g].get_or_insert_with(|| vec![0.0; 3 * n]);
            if let Some((j, kind, ratio)) = rates(model, check_jerk, d[0], d[1], d[2], k - t0, peak)
            {
                if self.binds[g].is_none() {
                    self.binds[g] = Some(format!(
                        "joint {} exceeds its {kind:?} limit ({:.0} %) at sample {k}",
                        j + 1,
                        ratio * 100.0
                    ));
                }
            }
        }
    }
}

/// One stretch of the path re-planned on its own (see [`Replanner`]): a segment's samples
/// of the job's plan with [`Reduction::pad_m`] of path before and after, entered and left at
/// the unslowed plan's node speeds.
struct Stretch {
    /// Segment id (a unit, or the exact stretch before or after the repeating run).
    g: usize,
    /// The segment's arc-length range in the job's plan (filtered), m.
    s_a: f64,
    s_b: f64,
    /// Node range of the job's plan.
    i0: usize,
    i1: usize,
    nodes: crate::timing::profile::Nodes,
    /// Its slow-downs so far (the full evaluation's rule, [`crate::timing::joint::Slowing`]).
    slowing: crate::timing::joint::Slowing,
    q_start: JointVec,
    /// Plans made so far.
    rounds: usize,
    /// Fewest samples over a limit any plan so far left (`usize::MAX` before the first).
    fewest: usize,
    /// Planned again since its scale or the acceleration changed.
    dirty: bool,
    /// The re-planned segment's additive quantities and samples.
    result: Option<Replanned>,
}

/// The segments where a joint's rate limit binds, re-planned with the full evaluation's rule
/// ([`crate::timing::joint::time_path_planned`]) on the stretch around each: each round, the
/// nodes around every sample over a limit are capped at `margin / ratio` (square root for
/// acceleration, cube root for jerk) of the current speed, or, where the demand comes from a
/// ramp, the ramp's acceleration is lowered ([`crate::timing::joint::Slowing`]), and the
/// stretch is planned again. A stretch still over a limit after `max_iterations` plans makes
/// the placement infeasible. Only the evaluated segments are re-planned: the slow-down of the
/// layers between is interpolated ([`Refine::estimate`]).
struct Replanner {
    popts: crate::timing::ProfileOptions,
    stretches: Vec<Stretch>,
}

/// A stretch planned and tracked: the motion, joint positions and derivatives (row-major),
/// the samples not distorted by the stretch's ends, and every (sample, joint, limit, ratio)
/// over a limit near the segment.
struct Planned {
    mo: CartesianMotion,
    /// Node speeds of the plan, m/s.
    v: Vec<f64>,
    qs: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
    clean: Range<usize>,
    viol: Vec<crate::timing::joint::Excess>,
}

impl Stretch {
    fn new(ctx: &Ctx<'_, '_, '_>, thin: &[f64], g: usize, seg: Range<usize>) -> Stretch {
        let red = ctx.red;
        let job = ctx.ev.job;
        let n = job.robot.dof();
        let nodes = &job.plan.nodes;
        let motion = &*job.plan.motion;
        let m = motion.p.len();
        let (a, b) = (seg.start, seg.end);
        let s_a = motion.s[a.min(m - 1)];
        let s_b = if b < m { motion.s[b] } else { f64::INFINITY };
        let last = nodes.s.len() - 1;
        let i0 = nodes
            .s
            .partition_point(|&x| x < s_a - red.pad_m)
            .saturating_sub(1);
        let i1 = if b < m {
            nodes.s.partition_point(|&x| x <= s_b + red.pad_m).min(last)
        } else {
            last
        };
        let slice = |v: &Vec<f64>| v[i0..=i1].to_vec();
        let mut sub = crate::timing::profile::Nodes {
            s: slice(&nodes.s),
            piece: nodes.piece[i0..=i1].to_vec(),
            cap: slice(&nodes.cap),
            dwell: if nodes.dwell.is_empty() {
                Vec::new()
            } else {
                slice(&nodes.dwell)
            },
        };
        let nl = sub.s.len();
        if i0 > 0 {
            sub.cap[0] = red.v0[i0];
        }
        if i1 < last {
            sub.cap[nl - 1] = red.v0[i1];
        }
        // The configuration: from the tracked sample at or before the stretch's start.
        let k_start = motion.s.partition_point(|&x| x < sub.s[0]).min(m - 1);
        let ti = (k_start / ctx.stride).min(ctx.thin_idx.len() - 1);
        Stretch {
            g,
            s_a,
            s_b,
            i0,
            i1,
            nodes: sub,
            slowing: crate::timing::joint::Slowing::new(nl),
            q_start: JointVec::from_slice(&thin[ti * n..(ti + 1) * n]),
            rounds: 0,
            fewest: usize::MAX,
            dirty: true,
            result: None,
        }
    }

    /// The sample of the job's plan at the place of sample `i` of `mo`.
    fn k_of(motion: &CartesianMotion, mo: &CartesianMotion, i: usize) -> usize {
        motion
            .s
            .partition_point(|&x| x <= mo.s[i])
            .saturating_sub(1)
    }

    /// Plan, track and differentiate the stretch; list the limits exceeded near the segment.
    fn plan(
        &mut self,
        ctx: &Ctx<'_, '_, '_>,
        sc: &mut Scratch<'_>,
        popts: &crate::timing::ProfileOptions,
    ) -> std::result::Result<Planned, Outcome> {
        self.rounds += 1;
        let job = ctx.ev.job;
        let model = job.robot;
        let n = model.dof();
        let motion = &*job.plan.motion;
        let dt = motion.dt;
        let last = job.plan.nodes.s.len() - 1;
        let v = self.slowing.speeds(&self.nodes, popts.accel);
        let mo = crate::timing::profile::plan_at_speeds(&job.pieces, &self.nodes, &v, popts);
        let len = mo.p.len();
        let taps = mo.taps;
        // Samples not distorted by the stretch's ends (the filter holds the first and last
        // positions; derivatives reach 2 samples): all of them at the path's own ends.
        let lo = if self.i0 == 0 { 0 } else { (taps + 3).min(len) };
        let hi = if self.i1 == last {
            len
        } else {
            (len + 1).saturating_sub(taps).saturating_sub(4).max(lo)
        };
        let mut qs = Vec::with_capacity(len * n);
        // IK near the previous sample's answer, sample by sample (the lockstep batches of
        // track_near: the same answers and first failure).
        if let Err((i, tip, reason)) = crate::timing::joint::track_near(
            &sc.solver,
            &ctx.rot,
            len,
            |i| ctx.frame.apply(&mo.p[i]),
            &self.q_start,
            &mut qs,
        ) {
            let k = Stretch::k_of(motion, &mo, i);
            return Err(Outcome::Infeasible(unreachable_at(job, k, tip, reason)));
        }
        let (qd, qdd, qddd) = crate::timing::joint::differentiate(&qs, n, dt);
        let viol = self.excesses(ctx, &mo, [&qd, &qdd, &qddd], lo..hi);
        Ok(Planned {
            mo,
            v,
            qs,
            qd,
            qdd,
            clean: lo..hi,
            viol,
        })
    }

    /// Every limit exceeded on the samples `clean` of plan `mo` near the segment, as the full
    /// evaluation lists them (derivatives `d`: velocity, acceleration, jerk, row-major).
    fn excesses(
        &self,
        ctx: &Ctx<'_, '_, '_>,
        mo: &CartesianMotion,
        d: [&[f64]; 3],
        clean: Range<usize>,
    ) -> Vec<crate::timing::joint::Excess> {
        use crate::timing::LimitKind as K;
        let red = ctx.red;
        let job = ctx.ev.job;
        let model = job.robot;
        let n = model.dof();
        let dt = job.plan.motion.dt;
        let jopts = &job.joint;
        let [qd, qdd, qddd] = d;
        let near = |x: f64| x >= self.s_a - 0.5 * red.pad_m && x < self.s_b + 0.5 * red.pad_m;
        let mut viol = Vec::new();
        for i in clean {
            if !near(mo.s[i]) {
                continue;
            }
            // Every limit over at this sample, as the full evaluation lists them.
            for (j, jt) in model.joints.iter().enumerate() {
                for (v, lim, kind) in [
                    (qd[i * n + j], jt.velocity_limit, K::Velocity),
                    (qdd[i * n + j], jt.acceleration_limit, K::Acceleration),
                    (
                        if jopts.check_jerk && jt.jerk_limit.is_finite() {
                            qddd[i * n + j]
                        } else {
                            0.0
                        },
                        jt.jerk_limit,
                        K::Jerk,
                    ),
                ] {
                    if lim.is_finite() && v.abs() > lim {
                        viol.push(crate::timing::joint::Excess {
                            sample: i,
                            joint: j,
                            kind,
                            ratio: v.abs() / lim,
                            ramp_share: crate::timing::joint::ramp_share(
                                kind,
                                qd[i * n + j],
                                qdd[i * n + j],
                                qddd[i * n + j],
                                crate::timing::joint::path_rates(&mo.s, dt, i),
                            ),
                        });
                    }
                }
            }
        }
        viol
    }

    /// Feasibility and energy of the segment's samples of a plan without violations.
    fn finish(
        &self,
        ctx: &Ctx<'_, '_, '_>,
        sc: &mut Scratch<'_>,
        pl: &Planned,
        margins: &mut Margins,
    ) -> std::result::Result<Replanned, Outcome> {
        let job = ctx.ev.job;
        let n = job.robot.dof();
        let motion = &*job.plan.motion;
        let dt = motion.dt;
        let every = ctx.ev.feasibility.check_every.max(1);
        let last = job.plan.nodes.s.len() - 1;
        let mo = &pl.mo;
        let len = mo.p.len();
        let (i0, i1) = (self.i0, self.i1);
        let in_seg = |i: usize| pl.clean.contains(&i) && mo.s[i] >= self.s_a && mo.s[i] < self.s_b;
        let idx = || (0..len).filter(|&i| in_seg(i));
        let k_of = |i: usize| Stretch::k_of(motion, mo, i);
        let js = Joints {
            qs: &pl.qs,
            qd: &pl.qd,
            qdd: &pl.qdd,
        };
        check(
            ctx,
            &mut sc.poses,
            &js,
            idx(),
            &|i| {
                (
                    k_of(i),
                    mo.p[i],
                    i.is_multiple_of(every) || (i1 == last && i + 1 == len),
                )
            },
            margins,
        )?;
        let mut acc = [None];
        integrate(
            ctx,
            &mut sc.data,
            &mut sc.sp,
            &js,
            idx(),
            &mut Sink {
                w: &|i| {
                    if (i == 0 && i0 == 0) || (i + 1 == len && i1 == last) {
                        0.5 * dt
                    } else {
                        dt
                    }
                },
                dest: &|_| 0,
                at_sample: &k_of,
                acc: &mut acc,
            },
        )?;
        let [e] = acc;
        Ok(Replanned {
            e: e.unwrap_or_else(|| vec![0.0; FIXED + 3 * n]),
            samples: idx().count() as f64,
        })
    }
}

impl Replanner {
    fn new(ctx: &Ctx<'_, '_, '_>) -> Self {
        Replanner {
            popts: ctx.ev.job.profile,
            stretches: Vec::new(),
        }
    }

    fn add(&mut self, ctx: &Ctx<'_, '_, '_>, thin: &[f64], g: usize, seg: Range<usize>) {
        if !self.stretches.iter().any(|s| s.g == g) {
            self.stretches.push(Stretch::new(ctx, thin, g, seg));
        }
    }

    /// Re-plan the segments `binding` until no limit binds; `range(g)`: segment `g`'s samples.
    fn run(
        &mut self,
        ctx: &Ctx<'_, '_, '_>,
        sc: &mut Scratch<'_>,
        binding: &[usize],
        range: &dyn Fn(usize) -> Range<usize>,
        margins: &mut Margins,
    ) -> std::result::Result<(), Outcome> {
        let thin = std::mem::take(&mut sc.red.thin);
        for &g in binding {
            self.add(ctx, &thin, g, range(g));
        }
        sc.red.thin = thin;
        let job = ctx.ev.job;
        let jopts = &job.joint;
        let max_rounds = jopts.max_iterations.max(1);
        let motion = &*job.plan.motion;
        while self.stretches.iter().any(|s| s.dirty) {
            for st in self.stretches.iter_mut().filter(|s| s.dirty) {
                let pl = st.plan(ctx, sc, &self.popts)?;
                if pl.viol.is_empty() {
                    st.result = Some(st.finish(ctx, sc, &pl, margins)?);
                    st.dirty = false;
                    continue;
                }
                let again = crate::timing::joint::replan_again(
                    st.rounds,
                    max_rounds,
                    pl.viol.len(),
                    st.fewest,
                );
                st.fewest = st.fewest.min(pl.viol.len());
                if !again {
                    let w = pl
                        .viol
                        .iter()
                        .max_by(|x, y| x.ratio.total_cmp(&y.ratio))
                        .expect("non-empty");
                    let (i, j, kind, ratio) = (w.sample, w.joint, w.kind, w.ratio);
                    let k = Stretch::k_of(motion, &pl.mo, i);
                    let tip = ctx.frame.apply(&pl.mo.p[i]);
                    let line = job.line_of(job.pieces[motion.piece[k]].move_index);
                    return Err(Outcome::Infeasible(Infeasible {
                        reason: Reason::JointLimits,
                        sample: Some(k),
                        t_s: Some(k as f64 * motion.dt),
                        line: Some(line),
                        point_m: Some([tip.x, tip.y, tip.z]),
                        detail: format!(
                            "joint {} {kind:?} limit still exceeded ({ratio:.2}x) at path sample {k} (t = {:.3} s, move on line {line} of {}) after re-planning this layer {} times (the reduced evaluation re-plans each evaluated layer where a limit binds on its own)",
                            j + 1,
                            k as f64 * motion.dt,
                            job.source,
                            st.rounds - 1,
                        ),
                    }));
                }
                // The full evaluation's rule: the speed capped, or the acceleration of a
                // ramp lowered, around each sample over a limit (both local).
                let margin =
                    crate::timing::joint::round_margin(jopts.margin, st.rounds, max_rounds);
                st.slowing.apply(&st.nodes, &pl.v, &pl.mo, &pl.viol, margin);
            }
        }
        Ok(())
    }
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
    confirm_beside(ev, best, &|_| {})
}

/// [`confirm`], with `also` given the full evaluation's timed path beside its checks and
/// energy ([`Evaluator::evaluate_full_beside`]).
pub(crate) fn confirm_beside(
    ev: &Evaluator<'_, '_>,
    best: &Evaluated,
    also: &(dyn Fn(&crate::timing::TimedPath) + Sync),
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
        outcome: ev.evaluate_full_beside(&mut sc, &best.placement, also),
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

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn a_chunk_called_within_reach_has_every_sample_within_reach() {
        // Random part-frame boxes (up to 0.5 m a side) around the IRB 6700 at random yaws and
        // offsets: wherever the box test says "every sample reaches", 200 random points of the
        // box (and its corners) pass the per-sample check; and it says so for most boxes well
        // inside the reach.
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let model = crate::robot::load(&root.join("robots/abb_irb6700_200_260")).unwrap();
        let solver = crate::kinematics::IkSolver::new(&model).unwrap();
        let p = model.opw.as_ref().unwrap();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let (mut clear, mut tried) = (0, 0);
        for _ in 0..4000 {
            let yaw = rng.gen_range(-3.2..3.2);
            let rot = crate::math::rot_z(yaw);
            let o = V3::new(
                rng.gen_range(-3.0..3.0),
                rng.gen_range(-3.0..3.0),
                rng.gen_range(-1.0..2.5),
            );
            let lo = V3::new(
                rng.gen_range(-0.5..0.5),
                rng.gen_range(-0.5..0.5),
                rng.gen_range(-0.5..0.5),
            );
            let hi = lo
                + V3::new(
                    rng.gen_range(0.0..0.5),
                    rng.gen_range(0.0..0.5),
                    rng.gen_range(0.0..0.5),
                );
            tried += 1;
            if !chunk_reaches(p, &lo, &hi, &o) {
                continue;
            }
            clear += 1;
            let corners = (0..8).map(|i| {
                V3::new(
                    if i & 1 == 0 { lo.x } else { hi.x },
                    if i & 2 == 0 { lo.y } else { hi.y },
                    if i & 4 == 0 { lo.z } else { hi.z },
                )
            });
            let inside: Vec<V3> = (0..200)
                .map(|_| {
                    V3::new(
                        rng.gen_range(lo.x..=hi.x),
                        rng.gen_range(lo.y..=hi.y),
                        rng.gen_range(lo.z..=hi.z),
                    )
                })
                .collect();
            for q in corners.chain(inside) {
                let w = rot * (q + o);
                assert!(
                    solver.wrist_centre_reachable(&w, 0.0).is_ok(),
                    "{q:?} of box {lo:?}..{hi:?}, o = {o:?}, yaw {yaw}"
                );
            }
        }
        assert!(clear > tried / 10, "{clear} of {tried} boxes clear");
    }
}
