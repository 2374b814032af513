//! The fast placement objective and parallel sweeps.
//!
//! [`Evaluator`] times the path at a placement with [`crate::timing::time_at_planned`]: the
//! Cartesian plan of the first round, which does not depend on the placement, is computed once
//! per job ([`PathJob::plan`]) and shared; the motion is re-planned only for a candidate whose
//! joint limits bind. Energy comes
//! from [`energy::eval_sample`] per sample with no per-sample allocation and no series stored;
//! call [`crate::energy::evaluate`] (via [`PathJob::evaluate`]) only for placements reported in
//! detail. Feasibility (singularity margins, collisions) is checked on every
//! `check_every`-th sample, see [`crate::evaluate::feasibility`].
//!
//! Sweeps run the placements in parallel with rayon (outermost loop only); results are
//! collected in input order, so they are bit-identical for any thread count.

use crate::dynamics::DynData;
use crate::energy::{self, SamplePower};
use crate::error::{Error, Result};
use crate::evaluate::feasibility::{self, FeasibilityOptions, Infeasible, Margins, Reason, World};
use crate::evaluate::job::PathJob;
use crate::frame::Placement;
use crate::kinematics::IkSolver;
use crate::math::V3;
use crate::simd::LANES;
use crate::timing::profile::Nodes;
use crate::timing::{self, Buffers, TimedPath, TimingFailure};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Samples from which a full evaluation keeps no per-sample sines and cosines of the joint
/// positions (96 bytes a sample for a six-axis arm, a third of what a timed sample holds):
/// its feasibility checks and energy compute them again where they need them, with the same
/// function (the same values), at some cost in time that only a long print's one-off full
/// evaluations pay.
pub const LEAN_SAMPLES: usize = 200_000;

/// Which energy the search minimises (all in J over the whole print).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Objective {
    /// Energy drawn from the supply: standby (cabinet power × print time) plus the drives'
    /// draw under the robot's regeneration policy. Equals the mechanical energy for robots
    /// without drive data (no standby).
    #[default]
    Supply,
    /// Energy drawn by the drives alone (supply minus standby): what the placement can change.
    /// Equals the mechanical energy for robots without drive data.
    Drives,
    /// Signed mechanical work ∑ⱼ ∫ τⱼ q̇ⱼ dt (seed 000's power τ·q̇; braking work counts as
    /// recovered).
    Mechanical,
    /// Positive mechanical work ∑ⱼ ∫ max(τⱼ q̇ⱼ, 0) dt: what the joints deliver when nothing is
    /// regenerated (braking work is lost, not returned).
    MechanicalPositive,
    /// Absolute mechanical work ∑ⱼ ∫ |τⱼ q̇ⱼ| dt: driving plus braking work, as if braking cost
    /// as much as driving (an upper bound, not what a drive draws).
    MechanicalAbs,
}

impl Objective {
    /// Every objective with its command-line name.
    pub const ALL: [(&'static str, Objective); 5] = [
        ("supply", Objective::Supply),
        ("drives", Objective::Drives),
        ("mechanical", Objective::Mechanical),
        ("mechanical_positive", Objective::MechanicalPositive),
        ("mechanical_abs", Objective::MechanicalAbs),
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        Objective::ALL
            .iter()
            .find(|(_, o)| *o == self)
            .map_or("supply", |(n, _)| n)
    }

    /// One line saying what the objective is (for reports).
    pub fn describe(self) -> &'static str {
        match self {
            Objective::Supply => "supply energy = standby + drives (J)",
            Objective::Drives => "drives' energy, standby excluded (J)",
            Objective::Mechanical => "signed mechanical work Σ∫τq̇ dt (J)",
            Objective::MechanicalPositive => {
                "positive mechanical work Σ∫max(τq̇, 0) dt, no regeneration (J)"
            }
            Objective::MechanicalAbs => "absolute mechanical work Σ∫|τq̇| dt (J)",
        }
    }
}

impl std::str::FromStr for Objective {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        let t = s.trim().to_ascii_lowercase().replace('-', "_");
        if let Some((_, o)) = Objective::ALL.iter().find(|(n, _)| *n == t) {
            return Ok(*o);
        }
        match t.as_str() {
            // Older or natural spellings.
            "drive" | "electrical" => Ok(Objective::Drives),
            "mechanical_pos" | "positive" => Ok(Objective::MechanicalPositive),
            _ => Err(Error::Invalid(format!(
                "unknown objective `{s}` (expected supply, drives, mechanical, mechanical_positive or mechanical_abs)"
            ))),
        }
    }
}

/// A feasible placement's numbers (energies in J, times in s). The supply energy is
/// `supply_j = standby_j + drives_j`; the drives' losses by kind are in [`Losses`] (the full
/// breakdown of one placement is [`crate::energy::TotalEnergy`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Feasible {
    /// The objective's energy, J.
    pub energy_j: f64,
    /// Supply energy (standby + drives), J.
    pub supply_j: f64,
    /// Energy drawn by the drives under the regeneration policy, J (= mechanical without
    /// drive data).
    pub drives_j: f64,
    /// Standby energy: cabinet power × print time, J.
    pub standby_j: f64,
    /// Signed mechanical work ∑ ∫ τ·q̇ dt, J.
    pub mechanical_j: f64,
    /// Positive mechanical work ∑ ∫ max(τ·q̇, 0) dt, J.
    pub mechanical_positive_j: f64,
    /// Absolute mechanical work ∑ ∫ |τ·q̇| dt, J.
    pub mechanical_abs_j: f64,
    /// Electrical energy of the drives ∑ ∫ p_el dt, J (= mechanical without drive data).
    pub electrical_j: f64,
    /// Losses by kind, J: friction ∫τ_f q̇, gearbox, copper ∫R i², and returned energy the
    /// regeneration policy burns.
    pub losses: Losses,
    /// Print duration, s.
    pub duration_s: f64,
    /// Samples at the interpolation period.
    pub samples: usize,
    /// Planning rounds (1 = no joint limit bound).
    pub rounds: usize,
    /// Per joint signed mechanical work, J.
    pub joint_mechanical_j: Vec<f64>,
    /// Per joint absolute mechanical work, J.
    pub joint_mechanical_abs_j: Vec<f64>,
    /// Per joint electrical energy, J.
    pub joint_electrical_j: Vec<f64>,
    /// Smallest margins met on the checked samples.
    pub margins: Margins,
    /// With the path reduction on ([`Evaluator::with_reduction`]): how these numbers were
    /// obtained (an estimate and its error, or why the placement was evaluated in full).
    /// `None`: a full evaluation. JSON: `path_reduction` beside the numbers of an evaluated
    /// placement's outcome, omitted when `None` (see `ser_outcome`; the positional shard
    /// files carry it in their own field).
    #[serde(skip)]
    pub path_reduction: Option<crate::evaluate::reduce::Estimate>,
}

/// Drive losses by kind over the print, J.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Losses {
    /// Friction ∑ ∫ τ_f q̇ dt, J.
    pub friction_j: f64,
    /// Gearbox ∑ ∫ p_gear dt, J.
    pub gear_j: f64,
    /// Copper ∑ ∫ R i² dt, J.
    pub copper_j: f64,
    /// Returned energy the regeneration policy burns, J.
    pub regeneration_lost_j: f64,
}

impl Feasible {
    /// The energy of objective `o`, J.
    pub fn of(&self, o: Objective) -> f64 {
        match o {
            Objective::Supply => self.supply_j,
            Objective::Drives => self.drives_j,
            Objective::Mechanical => self.mechanical_j,
            Objective::MechanicalPositive => self.mechanical_positive_j,
            Objective::MechanicalAbs => self.mechanical_abs_j,
        }
    }
}

/// A placement and what became of it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Evaluated {
    /// The placement (m, rad).
    #[serde(serialize_with = "ser_placement")]
    pub placement: Placement,
    /// Its numbers, or why it is infeasible. JSON: `{"status": "feasible", …numbers}` or
    /// `{"status": "infeasible", "reason": …, …}` (docs/json.md).
    #[serde(serialize_with = "ser_outcome")]
    pub outcome: std::result::Result<Feasible, Infeasible>,
}

/// The outcome in JSON without Rust's `Ok`/`Err` wrapper: a `status` tag beside the fields.
fn ser_outcome<S: serde::Serializer>(
    o: &std::result::Result<Feasible, Infeasible>,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    #[derive(Serialize)]
    struct WithEstimate<'a> {
        #[serde(flatten)]
        f: &'a Feasible,
        #[serde(skip_serializing_if = "Option::is_none")]
        path_reduction: Option<&'a crate::evaluate::reduce::Estimate>,
    }
    #[derive(Serialize)]
    #[serde(tag = "status", rename_all = "snake_case")]
    enum Outcome<'a> {
        Feasible(WithEstimate<'a>),
        Infeasible(&'a Infeasible),
    }
    match o {
        Ok(f) => Outcome::Feasible(WithEstimate {
            f,
            path_reduction: f.path_reduction.as_ref(),
        })
        .serialize(s),
        Err(i) => Outcome::Infeasible(i).serialize(s),
    }
}

fn ser_placement<S: serde::Serializer>(
    p: &Placement,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    PlacementRow::from(p).serialize(s)
}

/// A placement in JSON/CSV units: m and degrees.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub(crate) struct PlacementRow {
    /// m.
    pub x_m: f64,
    /// m.
    pub y_m: f64,
    /// m.
    pub z_m: f64,
    /// Part yaw, deg.
    pub yaw_deg: f64,
    /// Nozzle spin, deg.
    pub spin_deg: f64,
}

impl From<&Placement> for PlacementRow {
    fn from(p: &Placement) -> Self {
        PlacementRow {
            x_m: p.x,
            y_m: p.y,
            z_m: p.z,
            yaw_deg: p.yaw.to_degrees(),
            spin_deg: p.nozzle_spin.to_degrees(),
        }
    }
}

impl Evaluated {
    /// The objective energy, J; +∞ when infeasible (never NaN).
    pub fn cost(&self) -> f64 {
        match &self.outcome {
            Ok(f) if f.energy_j.is_finite() => f.energy_j,
            _ => f64::INFINITY,
        }
    }
    /// The feasible numbers, if any.
    pub fn feasible(&self) -> Option<&Feasible> {
        self.outcome.as_ref().ok()
    }
}

/// Per-thread scratch space of an [`Evaluator`].
pub struct Scratch<'a> {
    pub(super) solver: IkSolver<'a>,
    pub(super) data: DynData,
    buf: Buffers,
    pub(super) poses: Vec<parry3d_f64::math::Isometry<f64>>,
    pub(super) sp: SamplePower,
    pub(super) red: crate::evaluate::reduce::Buffers,
}

/// The fast objective over one job: immutable, shared by all threads.
pub struct Evaluator<'j, 'a> {
    /// The job (robot, energy model, blended path, options).
    pub job: &'j PathJob<'a>,
    /// Feasibility thresholds.
    pub feasibility: FeasibilityOptions,
    /// What is minimised.
    pub objective: Objective,
    pub(super) shapes: crate::evaluate::feasibility::collision::RobotShapes,
    /// Beads of the unslowed plan (shared by every placement whose timing did not re-plan).
    pub(super) beads: crate::evaluate::feasibility::collision::Beads,
    pub(super) bbox_all: (V3, V3),
    /// The print head above its clearance, checked against the printed part.
    head: Option<crate::evaluate::feasibility::collision::HeadOverPart>,
    /// Where the head meets the part along the unslowed plan, per nozzle spin (bits of the
    /// spin, rad): placement-independent otherwise, so found once.
    head_hits: std::sync::Mutex<
        Vec<(
            u64,
            Option<crate::evaluate::feasibility::collision::HeadHit>,
        )>,
    >,
    lines: Vec<usize>,
    /// Walls printed before this path (nozzle-tip segments, part frame, m), in every
    /// placement's collision scene ([`Evaluator::with_prior_walls`]).
    prior: Vec<(V3, V3)>,
    /// The path reduction for long repetitive prints, when on.
    reduction: Option<crate::evaluate::reduce::Reduction>,
    /// Scratch spaces of earlier [`Evaluator::sweep`] calls, reused by the next ones: a fresh
    /// scratch's first evaluation costs ~20 % more (its buffers are allocated and faulted in
    /// anew), and a search sweeps a few placements at a time hundreds of times. At most one
    /// per thread that ever ran a sweep at the same time. Results do not depend on which
    /// scratch an evaluation gets (the buffers are overwritten, never read first).
    pool: std::sync::Mutex<Vec<Scratch<'a>>>,
    /// Samples from which a full evaluation is lean ([`LEAN_SAMPLES`]; other values in
    /// tests, to compare both ways on one path).
    pub(crate) lean_from: usize,
}

/// A scratch taken from [`Evaluator`]'s pool (or made) for one rayon job of a sweep, given
/// back when the job ends.
struct Pooled<'p, 'a> {
    pool: &'p std::sync::Mutex<Vec<Scratch<'a>>>,
    sc: Option<Scratch<'a>>,
}

impl Drop for Pooled<'_, '_> {
    fn drop(&mut self) {
        if let (Some(sc), Ok(mut p)) = (self.sc.take(), self.pool.lock()) {
            p.push(sc);
        }
    }
}

/// The outcome of an evaluation that was abandoned part-way (a failed check stopped the
/// energy integration, or the caller no longer needed the placement): never reported.
fn abandoned() -> Infeasible {
    Infeasible {
        reason: Reason::ModelError,
        sample: None,
        t_s: None,
        line: None,
        point_m: None,
        detail: "evaluation abandoned part-way".into(),
    }
}

/// Done with the buffers of an evaluation that timed `timed` (if it did): kept for the next
/// placement, or freed when the evaluation was `lean`.
fn done_with(buf: &mut Buffers, timed: Option<TimedPath>, lean: bool) {
    match timed {
        Some(t) if !lean => buf.recycle(t),
        _ if lean => buf.release(),
        _ => {}
    }
}

/// The feasibility checks of a path timed at one placement, every sample (see
/// [`Evaluator::evaluate_full_unless`]).
struct FullChecks<'c, 'j, 'a> {
    ev: &'c Evaluator<'j, 'a>,
    timed: &'c TimedPath,
    world: &'c World,
    beads: &'c crate::evaluate::feasibility::collision::Beads,
    /// The part frame in the base frame.
    frame: &'c crate::math::Frame,
    /// The joints' sines and cosines of every sample (`2 n` a sample), when `shared`.
    sincos_all: &'c [f64],
    shared: bool,
    /// Singularities and collisions are checked on every `every`-th sample.
    every: usize,
    /// Set when a check fails (the integration then stops).
    failed: &'c AtomicBool,
    joint_checks: crate::evaluate::feasibility::margins::JointChecks,
}

impl FullChecks<'_, '_, '_> {
    /// Sample `k`'s sines and cosines, when shared.
    #[inline]
    fn sincos_of(&self, k: usize) -> Option<&[f64]> {
        let n = self.ev.job.robot.dof();
        self.shared
            .then(|| &self.sincos_all[k * 2 * n..(k + 1) * 2 * n])
    }

    /// Every check in sample order: the margins, or the first failure. The joint checks of
    /// LANES samples at once where they all pass (JointChecks::screen: the same margins),
    /// else sample by sample as the scalar path runs them; the first failure is reported at
    /// its own sample either way. Abandoned once `cancel` is set (looked at every 64 samples).
    fn run(
        &self,
        poses: &mut Vec<parry3d_f64::math::Isometry<f64>>,
        cancel: Option<&AtomicBool>,
    ) -> std::result::Result<Margins, Infeasible> {
        let ev = self.ev;
        let model = ev.job.robot;
        let o = &ev.feasibility;
        let (n, m, every) = (model.dof(), self.timed.traj.len(), self.every);
        let tr = &self.timed.traj;
        let mut margins = Margins::default();
        // The checked samples' singularity and collision checks LANES at a time where they
        // apply (feasibility::CheckedLanes: check_sample_with's answers).
        let mut lanes = self
            .shared
            .then(|| feasibility::CheckedLanes::new(model, o, &ev.shapes))
            .flatten();
        let blocks = crate::simd::level() != crate::simd::Level::Scalar;
        // The velocities and accelerations, kept or (a long path) derived a block at a time.
        let mut rates = crate::trajectory::RateBlocks::new(tr, self.timed.motion.dt);
        let mut k0 = 0;
        while k0 < m {
            if k0 % 64 == 0 && cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                // Abandoned: the result is not read.
                return Err(abandoned());
            }
            let count = if blocks {
                crate::simd::LANES.min(m - k0).min(64 - k0 % 64)
            } else {
                1
            };
            let (qd, qdd) = rates.block(k0, count);
            let screened = blocks
                && self.joint_checks.screen(
                    o,
                    n,
                    count,
                    &tr.q[k0 * n..(k0 + count) * n],
                    qd,
                    qdd,
                    self.shared
                        .then(|| &self.sincos_all[k0 * 2 * n..(k0 + count) * 2 * n]),
                    &mut margins,
                );
            if screened {
                // Every joint check passed: the checked samples of the block.
                let first = k0.div_ceil(every) * every;
                for k in (first..k0 + count).step_by(every) {
                    self.sample(k, None, &mut lanes, poses, &mut margins)?;
                }
                if k0 + count == m && (m - 1) % every != 0 {
                    self.sample(m - 1, None, &mut lanes, poses, &mut margins)?;
                }
            } else {
                for k in k0..k0 + count {
                    let row = (k - k0) * n..(k - k0 + 1) * n;
                    let joint_check = self.joint_checks.check(
                        model,
                        o,
                        tr.q(k),
                        self.sincos_of(k),
                        &qd[row.clone()],
                        &qdd[row],
                        &mut margins,
                    );
                    if k % every == 0 || k + 1 == m || joint_check.is_some() {
                        self.sample(k, joint_check, &mut lanes, poses, &mut margins)?;
                    }
                }
            }
            k0 += count;
        }
        Ok(margins)
    }

    /// Sample `k`'s singularity and collision checks after its joint checks gave
    /// `joint_check`, and where it fails.
    fn sample(
        &self,
        k: usize,
        joint_check: Option<(Reason, String)>,
        lanes: &mut Option<feasibility::CheckedLanes>,
        poses: &mut Vec<parry3d_f64::math::Isometry<f64>>,
        margins: &mut Margins,
    ) -> std::result::Result<(), Infeasible> {
        let ev = self.ev;
        let model = ev.job.robot;
        let o = &ev.feasibility;
        let (n, m) = (model.dof(), self.timed.traj.len());
        let tr = &self.timed.traj;
        let found = joint_check.or_else(|| {
            let scene = feasibility::Scene {
                world: self.world,
                shapes: &ev.shapes,
                beads: self.beads,
            };
            match lanes.as_mut() {
                Some(lanes) => lanes.check(
                    model,
                    o,
                    scene,
                    k,
                    self.every,
                    &tr.q[..m * n],
                    self.sincos_all,
                    poses,
                    margins,
                ),
                None => feasibility::check_sample_with(
                    model,
                    o,
                    scene,
                    tr.q(k),
                    self.sincos_of(k),
                    self.beads.laid_at(k),
                    poses,
                    margins,
                ),
            }
        });
        let Some((reason, detail)) = found else {
            return Ok(());
        };
        self.failed.store(true, Ordering::Relaxed);
        let motion = &*self.timed.motion;
        let mi = ev.job.pieces[motion.piece[k]].move_index;
        let tip = self.frame.apply(&motion.p[k]);
        Err(Infeasible {
            reason,
            sample: Some(k),
            t_s: Some(k as f64 * motion.dt),
            line: Some(ev.job.line_of(mi)),
            point_m: Some([tip.x, tip.y, tip.z]),
            detail,
        })
    }
}

fn bbox<'p>(pts: impl Iterator<Item = &'p V3>) -> Option<(V3, V3)> {
    let mut lo = V3::repeat(f64::INFINITY);
    let mut hi = V3::repeat(f64::NEG_INFINITY);
    let mut any = false;
    for p in pts {
        lo = lo.inf(p);
        hi = hi.sup(p);
        any = true;
    }
    any.then_some((lo, hi))
}

impl<'j, 'a> Evaluator<'j, 'a> {
    /// Plan the placement-independent Cartesian motion once.
    pub fn new(
        job: &'j PathJob<'a>,
        feasibility: FeasibilityOptions,
        objective: Objective,
    ) -> Self {
        let motion0 = &job.plan.motion;
        let all = bbox(motion0.p.iter()).unwrap_or((V3::zeros(), V3::zeros()));
        Evaluator {
            job,
            feasibility,
            objective,
            shapes: crate::evaluate::feasibility::collision::RobotShapes::new(
                job.robot,
                feasibility::reach_m(job.robot),
                &feasibility.radii,
            ),
            beads: crate::evaluate::feasibility::collision::Beads::new(
                &motion0.p,
                &motion0.print,
                feasibility.check_every,
                crate::evaluate::feasibility::collision::BEAD_RADIUS_M,
            ),
            bbox_all: all,
            head: feasibility
                .collisions
                .then(|| {
                    crate::evaluate::feasibility::collision::HeadOverPart::new(
                        job.robot,
                        feasibility::reach_m(job.robot),
                        &feasibility.radii,
                        feasibility.head_clearance_m,
                    )
                })
                .flatten(),
            head_hits: std::sync::Mutex::new(Vec::new()),
            lines: job.moves.iter().map(|m| m.line).collect(),
            prior: Vec::new(),
            reduction: None,
            pool: std::sync::Mutex::new(Vec::new()),
            lean_from: LEAN_SAMPLES,
        }
    }

    /// A scratch from the pool, or a new one (`None`: the robot has no IK).
    fn pooled(&self) -> Pooled<'_, 'a> {
        let sc = self
            .pool
            .lock()
            .ok()
            .and_then(|mut p| p.pop())
            .or_else(|| self.scratch().ok());
        Pooled {
            pool: &self.pool,
            sc,
        }
    }

    /// Evaluate placements with the path reduction `r` ([`crate::evaluate::reduce`]): estimates with a
    /// stated error instead of full evaluations. Built from this evaluator's job.
    pub fn with_reduction(mut self, r: crate::evaluate::reduce::Reduction) -> Self {
        self.reduction = Some(r);
        self
    }

    /// The path reduction in use, if any.
    pub fn reduction(&self) -> Option<&crate::evaluate::reduce::Reduction> {
        self.reduction.as_ref()
    }

    /// Evaluate one placement in full, whether or not the reduction is on.
    pub fn evaluate_full(&self, sc: &mut Scratch<'a>, at: &Placement) -> Evaluated {
        Evaluated {
            placement: *at,
            outcome: self.evaluate_full_inner(sc, at),
        }
    }

    /// This evaluator with walls printed before its path starts (nozzle-tip segments, part
    /// frame, m) in the collision scene of every placement, as beads laid from the first
    /// sample on (a multi-station plan's earlier segments).
    pub fn with_prior_walls(mut self, prior: Vec<(V3, V3)>) -> Self {
        let motion0 = &self.job.plan.motion;
        self.beads = crate::evaluate::feasibility::collision::Beads::with_prior(
            &prior,
            &motion0.p,
            &motion0.print,
            self.feasibility.check_every,
            crate::evaluate::feasibility::collision::BEAD_RADIUS_M,
        );
        self.prior = prior;
        if let Ok(mut h) = self.head_hits.lock() {
            h.clear();
        }
        self
    }

    /// Where the print head meets the part printed so far along `motion` (whose beads are
    /// `beads`) at `at`, as an infeasible outcome: every sample checked
    /// ([`crate::evaluate::feasibility::collision::HeadOverPart`]). For the unslowed plan the
    /// answer is found once per nozzle spin.
    pub(super) fn head_infeasible(
        &self,
        motion: &std::sync::Arc<crate::timing::profile::CartesianMotion>,
        beads: &crate::evaluate::feasibility::collision::Beads,
        at: &Placement,
    ) -> Option<Infeasible> {
        let head = self.head.as_ref()?;
        let spin = head.spin_checked(at.nozzle_spin);
        let hit = if std::sync::Arc::ptr_eq(motion, &self.job.plan.motion) {
            let key = spin.to_bits();
            let known = self
                .head_hits
                .lock()
                .ok()
                .and_then(|h| h.iter().find(|e| e.0 == key).map(|e| e.1.clone()));
            match known {
                Some(h) => h,
                None => {
                    let h = head.first_hit(beads, &motion.p, spin);
                    if let Ok(mut all) = self.head_hits.lock() {
                        all.push((key, h.clone()));
                    }
                    h
                }
            }
        } else {
            head.first_hit(beads, &motion.p, spin)
        }?;
        let k = hit.sample;
        let tip = at.frame().apply(&motion.p[k]);
        Some(Infeasible {
            reason: Reason::CollisionPart,
            sample: Some(k),
            t_s: Some(k as f64 * motion.dt),
            line: Some(
                self.job
                    .line_of(self.job.pieces[motion.piece[k]].move_index),
            ),
            point_m: Some([tip.x, tip.y, tip.z]),
            detail: hit.detail,
        })
    }

    /// Samples of the unslowed plan (a lower bound of every placement's sample count).
    pub fn nominal_samples(&self) -> usize {
        self.job.plan.motion.p.len()
    }

    /// Cartesian plan nodes (placement-independent).
    pub fn nodes(&self) -> &Nodes {
        &self.job.plan.nodes
    }

    /// Scratch space for one thread. Error: the robot has no IK (too many joints).
    pub fn scratch(&self) -> Result<Scratch<'a>> {
        let solver = IkSolver::new(self.job.robot)
            .map_err(|e| Error::Invalid(format!("inverse kinematics: {e}")))?;
        Ok(Scratch {
            solver,
            data: self.job.energy.data(),
            buf: Buffers::default(),
            poses: Vec::new(),
            sp: SamplePower::default(),
            red: Default::default(),
        })
    }

    /// Time the path at `at` (see [`timing::time_at_planned`]).
    fn time(
        &self,
        sc: &mut Scratch<'a>,
        at: &Placement,
    ) -> std::result::Result<TimedPath, TimingFailure> {
        let lines = |i: usize| self.lines.get(i).copied().unwrap_or(0);
        timing::time_at_planned(&sc.solver, &self.job.timing(&lines), at, &mut sc.buf)
    }

    /// Evaluate one placement: timing, feasibility, energy. Never fails: an infeasible
    /// placement is a value with a reason.
    pub fn evaluate(&self, sc: &mut Scratch<'a>, at: &Placement) -> Evaluated {
        let outcome = self.evaluate_inner(sc, at);
        Evaluated {
            placement: *at,
            outcome,
        }
    }

    fn evaluate_inner(
        &self,
        sc: &mut Scratch<'a>,
        at: &Placement,
    ) -> std::result::Result<Feasible, Infeasible> {
        match &self.reduction {
            Some(r) => crate::evaluate::reduce::evaluate(self, r, sc, at),
            None => self.evaluate_full_inner(sc, at),
        }
    }

    /// The full evaluation: every sample timed, checked and integrated.
    pub(super) fn evaluate_full_inner(
        &self,
        sc: &mut Scratch<'a>,
        at: &Placement,
    ) -> std::result::Result<Feasible, Infeasible> {
        // Never abandoned without a flag to say so.
        self.evaluate_full_unless(sc, at, None, None)
            .unwrap_or_else(|| Err(abandoned()))
    }

    /// [`Evaluator::evaluate_full_inner`], with `also` given the timed path beside the
    /// checks and the energy (on another thread where there is one): what else needs every
    /// sample of this placement (a report's detail) takes it from this timing instead of
    /// timing the path again. `also` is not called when the timing fails.
    pub(super) fn evaluate_full_beside(
        &self,
        sc: &mut Scratch<'a>,
        at: &Placement,
        also: &(dyn Fn(&TimedPath) + Sync),
    ) -> std::result::Result<Feasible, Infeasible> {
        self.evaluate_full_unless(sc, at, None, Some(also))
            .unwrap_or_else(|| Err(abandoned()))
    }

    /// [`Evaluator::evaluate_full_inner`], abandoned (`None`) once `cancel` is set: looked at
    /// before and after the timing, every 64 samples of the checks and every batch of the
    /// energy integration. An evaluation that is not abandoned is the full one, bit for bit.
    fn evaluate_full_unless(
        &self,
        sc: &mut Scratch<'a>,
        at: &Placement,
        cancel: Option<&AtomicBool>,
        also: Option<&(dyn Fn(&TimedPath) + Sync)>,
    ) -> Option<std::result::Result<Feasible, Infeasible>> {
        let cancelled = || cancel.is_some_and(|c| c.load(Ordering::Relaxed));
        if cancelled() {
            return None;
        }
        // A long path keeps no per-sample sines and cosines: the checks and the energy take
        // them again where they need them (the same values, bit for bit); and its buffers
        // are freed after, not kept for a next placement.
        let lean = self.job.plan.motion.p.len() >= self.lean_from;
        let keep = (sc.buf.transient_sincos, sc.buf.lean_rates);
        (sc.buf.transient_sincos, sc.buf.lean_rates) = (lean, lean);
        let timed = self.time(sc, at);
        (sc.buf.transient_sincos, sc.buf.lean_rates) = keep;
        let timed = match timed {
            Ok(t) => t,
            Err(e) => {
                done_with(&mut sc.buf, None, lean);
                return Some(Err(Infeasible::from_timing(&e)));
            }
        };
        if cancelled() {
            done_with(&mut sc.buf, Some(timed), lean);
            return None;
        }
        let r = match also {
            None => self.check_and_integrate(sc, at, &timed, cancel),
            Some(f) => {
                rayon::join(
                    || self.check_and_integrate(sc, at, &timed, cancel),
                    || f(&timed),
                )
                .0
            }
        };
        done_with(&mut sc.buf, Some(timed), lean); // the buffers kept for the next placement, or freed
        (!cancelled()).then_some(r)
    }

    /// The feasibility checks and the energy integration of the path timed at `at`, at once
    /// where a thread is free (rayon::join: the energy is taken up by an idle thread, else run
    /// here after the checks). The energy does not depend on the checks: the outcome is that
    /// of checking first and integrating after, bit for bit. A failed check tells the
    /// integration to stop.
    fn check_and_integrate(
        &self,
        sc: &mut Scratch<'a>,
        at: &Placement,
        timed: &TimedPath,
        cancel: Option<&AtomicBool>,
    ) -> std::result::Result<Feasible, Infeasible> {
        let cancelled = || cancel.is_some_and(|c| c.load(Ordering::Relaxed));
        let motion = &*timed.motion;
        let m = timed.traj.len();
        let frame = at.frame();
        // Feasibility on every k-th sample.
        let o = &self.feasibility;
        let world = World::new(&frame, self.bbox_all, o).with_floor(&self.shapes);
        let every = o.check_every.max(1);
        // The printed beads: the job's when this placement kept the planned motion, else anew.
        let replanned;
        let beads = if std::sync::Arc::ptr_eq(&timed.motion, &self.job.plan.motion) {
            &self.beads
        } else {
            replanned = crate::evaluate::feasibility::collision::Beads::with_prior(
                &self.prior,
                &motion.p,
                &motion.print,
                every,
                crate::evaluate::feasibility::collision::BEAD_RADIUS_M,
            );
            &replanned
        };
        // The joints' sines and cosines of every sample, from the IK's FK re-check.
        let n = self.job.robot.dof();
        let Scratch {
            data,
            buf,
            poses,
            sp,
            ..
        } = sc;
        let shared = buf.sincos.len() == m * 2 * n;
        let sincos_all = &buf.sincos[..];
        let failed = AtomicBool::new(false);
        let fc = FullChecks {
            ev: self,
            timed,
            world: &world,
            beads,
            frame: &frame,
            sincos_all,
            shared,
            every,
            failed: &failed,
            joint_checks: crate::evaluate::feasibility::margins::JointChecks::new(
                self.job.robot,
                o,
            ),
        };
        let checks = || fc.run(poses, cancel);
        let stop = || failed.load(Ordering::Relaxed) || cancelled();
        let energy = || {
            self.energy_parts(
                data,
                sp,
                shared.then_some(sincos_all),
                timed,
                Margins::default(),
                &stop,
            )
        };
        let (checked, integrated) = rayon::join(checks, energy);
        // The print head against the part, every sample: the first failure in sample order.
        let checked = match (checked, self.head_infeasible(&timed.motion, beads, at)) {
            (Err(e), Some(h)) if h.sample < e.sample => Err(h),
            (Ok(_), Some(h)) => Err(h),
            (c, _) => c,
        };
        checked.and_then(|margins| integrated.map(|f| Feasible { margins, ..f }))
    }

    /// Time the path at `at` with the job's timing (no feasibility checks beyond what timing
    /// checks): the trajectory that [`Evaluator::energy_of`] integrates.
    pub fn timed(
        &self,
        sc: &mut Scratch<'a>,
        at: &Placement,
    ) -> std::result::Result<TimedPath, TimingFailure> {
        self.time(sc, at)
    }

    /// The energies of an already timed path under this evaluator's energy model (the same
    /// integration as [`Evaluator::evaluate`]); `margins` are copied into the result. Used to
    /// re-evaluate one trajectory under many plausible robots (timing does not depend on the
    /// dynamics).
    pub fn energy_of(
        &self,
        sc: &mut Scratch<'a>,
        timed: &TimedPath,
        margins: Margins,
    ) -> std::result::Result<Feasible, Infeasible> {
        self.energy_inner(sc, timed, margins, false)
    }

    /// `shared`: `sc.buf.sincos` holds the sines and cosines of `timed`'s joint positions (the
    /// path was just timed with this scratch).
    fn energy_inner(
        &self,
        sc: &mut Scratch<'a>,
        timed: &TimedPath,
        margins: Margins,
        shared: bool,
    ) -> std::result::Result<Feasible, Infeasible> {
        let n = self.job.robot.dof();
        let m = timed.traj.len();
        let Scratch { data, buf, sp, .. } = sc;
        let sincos = (shared && buf.sincos.len() == m * 2 * n).then_some(&buf.sincos[..]);
        self.energy_parts(data, sp, sincos, timed, margins, &|| false)
    }

    /// The energies of `timed` with the given scratch parts; `sincos`: the sines and cosines
    /// of its joint positions when known (`2 n` a sample). The integration ends early (with an
    /// error nobody reads) once `stop` says so: the caller found the placement infeasible, or
    /// abandoned it, and discards the result.
    fn energy_parts(
        &self,
        data: &mut DynData,
        sp: &mut SamplePower,
        sincos: Option<&[f64]>,
        timed: &TimedPath,
        margins: Margins,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> std::result::Result<Feasible, Infeasible> {
        // Energy: trapezoid at uniform dt in LANES interleaved partial sums (sample k into
        // lane k mod LANES; energy::EnergySums), the same bits from the lockstep and the
        // per-sample paths; no allocation per sample.
        let mut sums = energy::EnergySums::default();
        let level = crate::simd::level();
        match sincos {
            // Lockstep batches of LANES samples (bit-identical to the per-sample path). The
            // sines are the shared ones, or (energy_of) computed 8 samples at a time, bit for
            // bit fastmath::sin_cos.
            _ if level != crate::simd::Level::Scalar && self.job.energy.batchable() => {
                self.sum_lanes(data, sincos, timed, &mut sums, stop, level)?;
            }
            _ => self.sum_samples(data, sp, sincos, timed, &mut sums, stop)?,
        }
        self.feasible_of(&sums, timed, margins)
    }

    /// Sum the energies of `timed` into `sums` in lockstep batches of LANES samples, at SIMD
    /// level `level`.
    fn sum_lanes(
        &self,
        data: &mut DynData,
        sincos: Option<&[f64]>,
        timed: &TimedPath,
        sums: &mut energy::EnergySums,
        stopped: &(dyn Fn() -> bool + Sync),
        level: crate::simd::Level,
    ) -> std::result::Result<(), Infeasible> {
        let n = self.job.robot.dof();
        let m = timed.traj.len();
        let dt = timed.motion.dt;
        let tr = &timed.traj;
        let mut pl = energy::PowerLanes::default();
        let mut inputs = energy::LaneInputs::default();
        let mut rates = crate::trajectory::RateBlocks::new(tr, dt);
        for k0 in (0..m).step_by(LANES) {
            if stopped() {
                return Err(abandoned());
            }
            let count = LANES.min(m - k0);
            let (qd, qdd) = rates.block(k0, count);
            let r = energy::Rows {
                q: tr.q.get(k0 * n..).unwrap_or(&[]),
                sincos: sincos.map(|s| s.get(k0 * 2 * n..).unwrap_or(&[])),
                qd,
                qdd,
            };
            // Inside the path every weight is dt (what trapezoid_weight gives there).
            let mut w = [dt; LANES];
            if k0 == 0 || k0 + LANES >= m {
                w = [0.0; LANES];
                for (l, w) in w.iter_mut().enumerate().take(count) {
                    *w = crate::numerics::trapezoid_weight(k0 + l, m, dt);
                }
            }
            // The batch's powers, then added into the sums, in one compiled pass.
            energy::eval_rows_summed(
                &self.job.energy,
                data,
                count,
                &r,
                &mut inputs,
                &mut pl,
                sums,
                &w,
                level,
            )
            .map_err(|e| Infeasible::model_error(k0, dt, &e))?;
        }
        Ok(())
    }

    /// Sum the energies of `timed` into `sums` sample by sample.
    fn sum_samples(
        &self,
        data: &mut DynData,
        sp: &mut SamplePower,
        sincos: Option<&[f64]>,
        timed: &TimedPath,
        sums: &mut energy::EnergySums,
        stopped: &(dyn Fn() -> bool + Sync),
    ) -> std::result::Result<(), Infeasible> {
        let n = self.job.robot.dof();
        let m = timed.traj.len();
        let dt = timed.motion.dt;
        let mut rates = crate::trajectory::RateBlocks::new(&timed.traj, dt);
        for k in 0..m {
            if k % LANES == 0 && stopped() {
                return Err(abandoned());
            }
            let (qd, qdd) = rates.block(k, 1);
            let r = match sincos {
                Some(s) => energy::eval_sample_with_sincos(
                    &self.job.energy,
                    data,
                    timed.traj.q(k),
                    &s[k * 2 * n..(k + 1) * 2 * n],
                    qd,
                    qdd,
                    sp,
                ),
                None => energy::eval_sample(&self.job.energy, data, timed.traj.q(k), qd, qdd, sp),
            };
            r.map_err(|e| Infeasible::model_error(k, dt, &e))?;
            sums.add_sample(k, sp, crate::numerics::trapezoid_weight(k, m, dt), n);
        }
        Ok(())
    }

    /// The energies of `timed` from its summed lanes `sums`, with `margins`.
    fn feasible_of(
        &self,
        sums: &energy::EnergySums,
        timed: &TimedPath,
        margins: Margins,
    ) -> std::result::Result<Feasible, Infeasible> {
        let n = self.job.robot.dof();
        let m = timed.traj.len();
        let dt = timed.motion.dt;
        let total = energy::EnergySums::lanes_total;
        let (mut supply, mut drives) = (total(&sums.supply), total(&sums.drives));
        if m < 2 {
            supply = 0.0;
            drives = 0.0;
        }
        let per_joint = |a: &[[f64; LANES]; crate::dynamics::MAX_DOF]| -> Vec<f64> {
            a[..n].iter().map(total).collect()
        };
        let all_joints = |a: &[[f64; LANES]; crate::dynamics::MAX_DOF]| -> f64 {
            let mut t = 0.0;
            for x in &a[..n] {
                t += total(x);
            }
            t
        };
        let (jm, jabs, jel) = (
            per_joint(&sums.mech),
            per_joint(&sums.mech_abs),
            per_joint(&sums.el),
        );
        let mpos = all_joints(&sums.mech_pos);
        let losses = Losses {
            friction_j: all_joints(&sums.friction),
            gear_j: all_joints(&sums.gear),
            copper_j: all_joints(&sums.copper),
            regeneration_lost_j: total(&sums.regeneration_lost),
        };
        let rounds = timed.rounds;
        let mechanical_j: f64 = jm.iter().sum();
        let mechanical_abs_j: f64 = jabs.iter().sum();
        let energy_j = match self.objective {
            Objective::Supply => supply,
            Objective::Drives => drives,
            Objective::Mechanical => mechanical_j,
            Objective::MechanicalPositive => mpos,
            Objective::MechanicalAbs => mechanical_abs_j,
        };
        if !energy_j.is_finite() {
            return Err(Infeasible {
                reason: Reason::ModelError,
                sample: None,
                t_s: None,
                line: None,
                point_m: None,
                detail: "non-finite energy".into(),
            });
        }
        Ok(Feasible {
            energy_j,
            supply_j: supply,
            drives_j: drives,
            standby_j: supply - drives,
            mechanical_j,
            mechanical_positive_j: mpos,
            losses,
            mechanical_abs_j,
            electrical_j: jel.iter().sum(),
            duration_s: dt * m.saturating_sub(1) as f64,
            samples: m,
            rounds,
            joint_mechanical_j: jm,
            joint_mechanical_abs_j: jabs,
            joint_electrical_j: jel,
            margins,
            path_reduction: None,
        })
    }

    /// One placement with a scratch from the pool (a "no IK solver" model error when none can
    /// be made), abandoned (`None`) once `cancel` is set (see
    /// [`Evaluator::evaluate_full_unless`]; an evaluation with the path reduction is not
    /// abandoned part-way).
    fn evaluate_pooled(&self, at: &Placement, cancel: Option<&AtomicBool>) -> Option<Evaluated> {
        let mut pooled = self.pooled();
        let Some(sc) = &mut pooled.sc else {
            return Some(Evaluated {
                placement: *at,
                outcome: Err(Infeasible {
                    detail: "no IK solver".into(),
                    ..abandoned()
                }),
            });
        };
        let outcome = match &self.reduction {
            Some(_) if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) => return None,
            Some(_) => self.evaluate_inner(sc, at),
            None => self.evaluate_full_unless(sc, at, cancel, None)?,
        };
        Some(Evaluated {
            placement: *at,
            outcome,
        })
    }

    /// Evaluate `first` and, on another thread where one is free, `guess` beside it (a point a
    /// search will need next only for some outcomes of `first`). Once `first` is evaluated, a
    /// guess that `wanted(&first)` rejects is abandoned where it stands and `None` is
    /// returned for it; a wanted guess is evaluated in full. Both evaluations are those of
    /// [`Evaluator::evaluate`] bit for bit, and whether the guess is returned depends only on
    /// `wanted`, never on timing or the thread count (on one thread, an unwanted guess is
    /// never started).
    pub fn evaluate_with_guess(
        &self,
        first: &Placement,
        guess: &Placement,
        wanted: &(dyn Fn(&Evaluated) -> bool + Sync),
    ) -> (Evaluated, Option<Evaluated>) {
        let cancel = AtomicBool::new(false);
        let (a, b) = rayon::join(
            || {
                let e = self.evaluate_pooled(first, None);
                if !e.as_ref().is_some_and(wanted) {
                    cancel.store(true, Ordering::Relaxed);
                }
                e
            },
            || self.evaluate_pooled(guess, Some(&cancel)),
        );
        // Never abandoned without the flag: the fall-backs do not run.
        let a = a.unwrap_or_else(|| Evaluated {
            placement: *first,
            outcome: Err(abandoned()),
        });
        if !wanted(&a) {
            return (a, None);
        }
        let b = b.or_else(|| self.evaluate_pooled(guess, None));
        (a, b)
    }

    /// Evaluate `placements` in their order until the first one that `stop` accepts: as many
    /// at once as the current pool has threads, each thread taking the next placement not yet
    /// started (no batch waits for its slowest member). Once placement `i` is evaluated and
    /// `stop` accepts it, the placements after `i` are not started, and those under way are
    /// abandoned where they stand ([`Evaluator::evaluate_with_guess`]'s mechanism).
    ///
    /// Entry `k` of the result is `Some` (the evaluation of [`Evaluator::evaluate`], bit for
    /// bit) for every `k` up to the first accepted placement (or for all, when none is
    /// accepted); after it, an entry is `Some` only when that evaluation finished before it
    /// could be abandoned (work ahead of need, which depends on timing; on one thread there is
    /// none). Which placements are accepted, and every entry up to the first, do not depend on
    /// the thread count.
    pub fn sweep_until(
        &self,
        placements: &[Placement],
        stop: &(dyn Fn(&Evaluated) -> bool + Sync),
    ) -> Result<Vec<Option<Evaluated>>> {
        // Fail early (once) if the model cannot be solved at all.
        if self.pooled().sc.is_none() {
            drop(self.scratch()?);
        }
        let n = placements.len();
        let next = AtomicUsize::new(0);
        // The first accepted index so far (`n`: none).
        let first = AtomicUsize::new(n);
        let cancel: Vec<AtomicBool> = (0..n).map(|_| AtomicBool::new(false)).collect();
        let out: Vec<std::sync::Mutex<Option<Evaluated>>> =
            (0..n).map(|_| std::sync::Mutex::new(None)).collect();
        let worker = || loop {
            let i = next.fetch_add(1, Ordering::SeqCst);
            if i >= n || i > first.load(Ordering::SeqCst) {
                break;
            }
            let Some(e) = self.evaluate_pooled(&placements[i], Some(&cancel[i])) else {
                continue;
            };
            if stop(&e) && first.fetch_min(i, Ordering::SeqCst) > i {
                for c in &cancel[i + 1..] {
                    c.store(true, Ordering::SeqCst);
                }
            }
            if let Ok(mut slot) = out[i].lock() {
                *slot = Some(e);
            }
        };
        let workers = rayon::current_num_threads().clamp(1, n.max(1));
        let worker = &worker;
        rayon::scope(|s| {
            for _ in 1..workers {
                s.spawn(move |_| worker());
            }
            worker();
        });
        let f = first.load(Ordering::SeqCst);
        let mut r: Vec<Option<Evaluated>> = out
            .into_iter()
            .map(|m| m.into_inner().unwrap_or_else(|p| p.into_inner()))
            .collect();
        // Never abandoned without the flag: an entry up to the first accepted one that is
        // missing (it cannot be) is evaluated here.
        for (k, e) in r.iter_mut().enumerate().take(f.saturating_add(1).min(n)) {
            if e.is_none() {
                *e = self.evaluate_pooled(&placements[k], None);
            }
        }
        Ok(r)
    }

    /// Evaluate many placements in parallel (rayon, current pool), in input order.
    /// `progress(done, total)` is called after each placement (from any thread).
    pub fn sweep(
        &self,
        placements: &[Placement],
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<Vec<Evaluated>> {
        // Fail early (once) if the model cannot be solved at all.
        if self.pooled().sc.is_none() {
            drop(self.scratch()?);
        }
        let done = AtomicUsize::new(0);
        let total = placements.len();
        let out = placements
            .par_iter()
            .map_init(
                || self.pooled(),
                |pooled, at| {
                    let r = match &mut pooled.sc {
                        Some(sc) => self.evaluate(sc, at),
                        None => Evaluated {
                            placement: *at,
                            outcome: Err(Infeasible {
                                reason: Reason::ModelError,
                                sample: None,
                                t_s: None,
                                line: None,
                                point_m: None,
                                detail: "no IK solver".into(),
                            }),
                        },
                    };
                    let d = done.fetch_add(1, Ordering::Relaxed) + 1;
                    progress(d, total);
                    r
                },
            )
            .collect();
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lean_full_evaluation_gives_the_same_outcome_bit_for_bit() {
        // The multi-layer wall with the IRB 6700 at placements around it, feasible and not
        // (reach, joint and wrist margins, collisions): evaluated in full keeping the
        // per-sample sines (the short path's way) and without them (a long print's way),
        // every outcome is the same, numbers and reasons.
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let model = crate::robot::load(&root.join("robots/abb_irb6700_200_260")).unwrap();
        let path = crate::toolpath::load(
            &root.join("paths/wall_multilayer.gcode"),
            &crate::toolpath::ReadOptions::default(),
        )
        .unwrap();
        let job = PathJob::new(
            &model,
            &path,
            crate::energy::EnergyOptions::default(),
            crate::timing::ProfileOptions::default(),
            crate::timing::JointStageOptions::default(),
        )
        .unwrap();
        let mut kept = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
        kept.lean_from = usize::MAX;
        let mut lean = Evaluator::new(&job, FeasibilityOptions::default(), Objective::Supply);
        lean.lean_from = 0;
        let (mut sk, mut sl) = (kept.scratch().unwrap(), lean.scratch().unwrap());
        let mut reasons = std::collections::BTreeSet::new();
        let mut feasible = 0;
        for x in [0.8, 1.1, 1.4, 1.7, 2.0, 2.4] {
            for y in [-0.6, 0.0, 0.5] {
                for z in [-0.4, 0.0, 0.6] {
                    for yaw in [0.0f64, 90.0, 200.0] {
                        let at = Placement::new(x, y, z, yaw.to_radians());
                        let a = kept.evaluate_full(&mut sk, &at);
                        let b = lean.evaluate_full(&mut sl, &at);
                        assert_eq!(a, b, "at {at:?}");
                        // The lean scratch keeps no sines and no buffers.
                        assert!(sl.buf.sincos.is_empty() && sl.buf.qs.capacity() == 0);
                        match &a.outcome {
                            Ok(_) => feasible += 1,
                            Err(i) => {
                                reasons.insert(i.reason);
                            }
                        }
                    }
                }
            }
        }
        assert!(feasible >= 5, "{feasible} feasible placements");
        assert!(reasons.len() >= 3, "too few kinds of failure: {reasons:?}");
    }
}
