//! One placement, evaluated end to end: the toolpath is blended and timed as a controller
//! would run it at that placement (one arm configuration, joint limits respected), and the
//! resulting joint trajectory goes through inverse dynamics and the energy model.

use crate::energy::{self, EnergyModel, EnergyOptions, EnergyReport};
use crate::error::Result;
use crate::frame::Placement;
use crate::kinematics::IkSolver;
use crate::robot::RobotModel;
use crate::timing::{
    self, Buffers, JointStageOptions, Piece, Plan, ProfileOptions, TimedPath, TimingFailure,
};
use crate::toolpath::Toolpath;

/// Everything about a job that does not depend on the placement: the robot, its energy
/// model, the blended path and the timing options. Build once, evaluate many placements.
pub struct PathJob<'a> {
    /// The robot.
    pub robot: &'a RobotModel,
    /// Its energy model (dynamics, drives, regeneration, standby).
    pub energy: EnergyModel,
    /// The programmed moves (part frame).
    pub moves: Vec<timing::Move>,
    /// The blended path (part frame).
    pub pieces: Vec<Piece>,
    /// The placement-independent first Cartesian plan of the path, shared by all placements.
    pub plan: Plan,
    /// Cartesian profile limits and period.
    pub profile: ProfileOptions,
    /// Joint-stage options.
    pub joint: JointStageOptions,
    /// Source file of the path (named in timing failures).
    pub source: String,
}

/// The result of one placement.
#[derive(Clone, Debug)]
pub struct PlacementEval {
    /// The placement.
    pub placement: Placement,
    /// The timed path (joint trajectory, Cartesian motion, slow-downs).
    pub timed: TimedPath,
    /// Energy per joint and in total, with per-sample series.
    pub energy: EnergyReport,
}

impl<'a> PathJob<'a> {
    /// Prepare a job. Errors: the robot lacks what dynamics need (names the link), or the path
    /// has no moves.
    pub fn new(
        robot: &'a RobotModel,
        path: &Toolpath,
        energy_options: EnergyOptions,
        profile: ProfileOptions,
        joint: JointStageOptions,
    ) -> Result<Self> {
        let energy = EnergyModel::with_options(robot, energy_options)?;
        Self::with_energy(robot, energy, path, profile, joint)
    }

    /// Prepare a job with an energy model built already (of `robot`; many jobs of one robot,
    /// e.g. the segments of a stations plan, share one: building it costs more than a short
    /// path's set-up). Errors: the path has no moves.
    pub(crate) fn with_energy(
        robot: &'a RobotModel,
        energy: EnergyModel,
        path: &Toolpath,
        profile: ProfileOptions,
        joint: JointStageOptions,
    ) -> Result<Self> {
        let moves = timing::moves_from_toolpath(path);
        if moves.is_empty() {
            return Err(crate::error::Error::Invalid(format!(
                "{}: the path has no moves of non-zero length",
                path.source
            )));
        }
        let dwells = timing::dwells_from_toolpath(path);
        let dwell_s: f64 = dwells.iter().map(|d| d.1).sum();
        timing::budget::check(&moves, dwell_s, &profile, robot.dof(), &path.source)?;
        let pieces = timing::blend_path_with_dwells(&moves, &dwells);
        let plan = Plan::new(&pieces, &profile);
        Ok(PathJob {
            robot,
            energy,
            moves,
            pieces,
            plan,
            profile,
            joint,
            source: path.source.clone(),
        })
    }

    /// Source line of timing move `i`.
    pub fn line_of(&self, i: usize) -> usize {
        self.moves.get(i).map_or(0, |m| m.line)
    }

    /// The placement-independent side of timing this job's path, with `lines` giving the
    /// source line of each timing move.
    pub fn timing<'b>(&'b self, lines: &'b dyn Fn(usize) -> usize) -> timing::PathTiming<'b> {
        timing::PathTiming {
            pieces: &self.pieces,
            plan: &self.plan,
            moves_line: lines,
            profile: &self.profile,
            joint: &self.joint,
            source: &self.source,
        }
    }

    /// Time the path at a placement (the nozzle turned by [`Placement::nozzle_yaw`]).
    pub fn time(
        &self,
        solver: &IkSolver,
        at: &Placement,
    ) -> std::result::Result<TimedPath, TimingFailure> {
        self.time_keeping(solver, at, false)
    }

    /// [`PathJob::time`] keeping no joint velocities and accelerations
    /// ([`Buffers::lean_rates`]: the timed path's `qd` and `qdd` are empty, derived where
    /// used); for a consumer that takes them a block at a time.
    pub(crate) fn time_lean(
        &self,
        solver: &IkSolver,
        at: &Placement,
    ) -> std::result::Result<TimedPath, TimingFailure> {
        self.time_keeping(solver, at, true)
    }

    /// The path timed at `at`, its rates kept unless `lean`.
    fn time_keeping(
        &self,
        solver: &IkSolver,
        at: &Placement,
        lean: bool,
    ) -> std::result::Result<TimedPath, TimingFailure> {
        let lines = |i: usize| self.line_of(i);
        // Nobody reads the sines and cosines of the buffers dropped here: none are kept.
        let mut buf = Buffers::default();
        (buf.transient_sincos, buf.lean_rates) = (true, lean);
        timing::time_at_planned(solver, &self.timing(&lines), at, &mut buf)
    }

    /// Time the path and compute its energy at a placement. The outer error is a model error;
    /// the inner one says why the placement is infeasible.
    pub fn evaluate(
        &self,
        at: &Placement,
    ) -> Result<std::result::Result<PlacementEval, TimingFailure>> {
        let solver = IkSolver::new(self.robot)?;
        let timed = match self.time(&solver, at) {
            Ok(t) => t,
            Err(e) => return Ok(Err(e)),
        };
        let energy = energy::evaluate(&self.energy, &timed.traj)?;
        Ok(Ok(PlacementEval {
            placement: *at,
            timed,
            energy,
        }))
    }

    /// [`PathJob::evaluate`] with the feasibility checks a placement sweep applies (`feas`:
    /// reach, joint-limit, wrist, elbow and shoulder margins, and collisions of the robot
    /// with the bed, the printed part and itself), evaluated on every sample as
    /// [`crate::evaluate::Evaluator::evaluate_full`] does. The checks' answer is the reason a
    /// sweep gives for the same placement, word for word.
    ///
    /// Outer error: a model error. Middle error: no motion to evaluate (the path cannot be
    /// timed at the placement: unreachable, a configuration change), with the sweep's
    /// reason. Otherwise the evaluation and the failed check, if any (the motion exists, so
    /// its energy is computed regardless; the caller states the failure).
    pub fn evaluate_checked(
        &self,
        at: &Placement,
        feas: crate::evaluate::FeasibilityOptions,
    ) -> Result<
        std::result::Result<
            (PlacementEval, Option<crate::evaluate::Infeasible>),
            crate::evaluate::Infeasible,
        >,
    > {
        feas.check()?;
        let ev = crate::evaluate::Evaluator::new(self, feas, crate::evaluate::Objective::Supply);
        let mut sc = ev.scratch()?;
        let checked = ev.evaluate_full(&mut sc, at).outcome.err();
        Ok(match self.evaluate(at)? {
            Ok(e) => Ok((e, checked)),
            Err(t) => Err(checked.unwrap_or_else(|| crate::evaluate::Infeasible::from_timing(&t))),
        })
    }
}
