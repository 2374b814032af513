//! `stations` as one job ([`StationsJob`] → [`run`] → [`StationsOutcome`]): the candidate
//! stations from where they may stand ([`Sites`]) and how the robot faces ([`Headings`]), the
//! stated defaults (the height of the part origin above a station's base, the floor disc a
//! station occupies), the solve with its progress, and the facts a report states about the
//! job. The command line and Python build the job from their arguments and print or return
//! the outcome; neither chooses anything.

use super::{default_footprint_m, solve, Candidates, Headings, Plan, StationsProblem};
use crate::energy::EnergyOptions;
use crate::error::Result;
use crate::evaluate::{FeasibilityOptions, Objective};
use crate::robot::RobotModel;
use crate::timing::{JointStageOptions, ProfileOptions};
use crate::toolpath::Toolpath;

/// Height of the part origin above a station's base frame when none is given, m: the base
/// 0.5 m above the floor printed on (a robot on a track carriage or crawler). At 0 the base
/// stands in the bed the feasibility check models.
pub const DEFAULT_Z_M: f64 = -0.5;

/// Where candidate stations may stand.
#[derive(Debug, Clone, PartialEq)]
pub enum Sites {
    /// A grid every `step_m` m over the path's footprint widened by the arm's reach.
    Grid {
        /// Spacing, m.
        step_m: f64,
    },
    /// Points every `step_m` m along the straight track from `from` to `to` (part frame, m).
    Track {
        /// One end, m.
        from: [f64; 2],
        /// The other end, m.
        to: [f64; 2],
        /// Spacing, m.
        step_m: f64,
    },
}

/// One `stations` job: the robot, the path, the options every placement command shares, the
/// candidate stations and the user's relocation cost.
#[derive(Debug, Clone)]
pub struct StationsJob<'a> {
    /// The robot.
    pub robot: &'a RobotModel,
    /// The path, part frame.
    pub path: &'a Toolpath,
    /// Energy model options.
    pub energy: EnergyOptions,
    /// Cartesian timing.
    pub profile: ProfileOptions,
    /// Joint-space timing.
    pub joint: JointStageOptions,
    /// Feasibility checks.
    pub feasibility: FeasibilityOptions,
    /// The energy minimised.
    pub objective: Objective,
    /// Where stations may stand.
    pub sites: Sites,
    /// How the robot faces at a station.
    pub headings: Headings,
    /// Height of the part origin above each station's base frame, m ([`DEFAULT_Z_M`]).
    pub z_m: f64,
    /// The nozzle spin, rad.
    pub spin_rad: f64,
    /// Cost of one relocation, J (the user's number).
    pub relocation_j: f64,
    /// Extra cost per metre between consecutive stations, J/m.
    pub relocation_j_per_m: f64,
    /// Radius of the floor disc a station occupies, m; `None`: [`default_footprint_m`], an
    /// estimate.
    pub footprint_m: Option<f64>,
}

impl<'a> StationsJob<'a> {
    /// A job with the stated defaults: a grid every 0.5 m, headings toward each segment's
    /// centroid, [`DEFAULT_Z_M`], spin 0, no cost per metre, the estimated footprint, and the
    /// default timing, energy, feasibility and objective of every placement command.
    pub fn new(robot: &'a RobotModel, path: &'a Toolpath, relocation_j: f64) -> Self {
        StationsJob {
            robot,
            path,
            energy: EnergyOptions::default(),
            profile: ProfileOptions::default(),
            joint: JointStageOptions::default(),
            feasibility: FeasibilityOptions::default(),
            objective: Objective::default(),
            sites: Sites::Grid { step_m: 0.5 },
            headings: Headings::Auto,
            z_m: DEFAULT_Z_M,
            spin_rad: 0.0,
            relocation_j,
            relocation_j_per_m: 0.0,
            footprint_m: None,
        }
    }

    /// The problem the solver takes: the candidate positions made, the footprint chosen.
    /// Errors: a step that is not finite and > 0, too many candidates.
    pub fn problem(&self) -> Result<StationsProblem<'a>> {
        let candidates = match &self.sites {
            Sites::Grid { step_m } => Candidates::grid(
                self.path,
                *step_m,
                crate::evaluate::feasibility::reach_m(self.robot),
                self.headings.clone(),
            )?,
            Sites::Track { from, to, step_m } => {
                Candidates::track(*from, *to, *step_m, self.headings.clone())?
            }
        };
        Ok(StationsProblem {
            robot: self.robot,
            path: self.path,
            energy: self.energy,
            profile: self.profile,
            joint: self.joint,
            feasibility: self.feasibility,
            objective: self.objective,
            candidates,
            z_m: self.z_m,
            spin_rad: self.spin_rad,
            relocation_j: self.relocation_j,
            relocation_j_per_m: self.relocation_j_per_m,
            footprint_m: self
                .footprint_m
                .unwrap_or_else(|| default_footprint_m(self.robot)),
        })
    }
}

/// What a `stations` job found.
#[derive(Debug, Clone)]
pub struct StationsOutcome {
    /// The plan.
    pub plan: Plan,
    /// The candidate stations, in words.
    pub sites: String,
    /// The floor disc radius used, m.
    pub footprint_m: f64,
    /// Wall time of the solve, s.
    pub secs: f64,
}

/// Run `job`: make the candidates, solve, time it. `progress(done, total)` is called as runs
/// of units are evaluated (from rayon's threads; install a pool around the call to choose
/// their number). Errors: the job's (steps, costs, candidates) and no plan printing the path,
/// naming the first unit that cannot be printed and why.
pub fn run(job: &StationsJob, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<StationsOutcome> {
    let problem = job.problem()?;
    let t0 = std::time::Instant::now();
    let plan = solve(&problem, progress)?;
    Ok(StationsOutcome {
        plan,
        sites: problem.candidates.description.clone(),
        footprint_m: problem.footprint_m,
        secs: t0.elapsed().as_secs_f64(),
    })
}

impl StationsOutcome {
    /// The facts a report states about `job` and this outcome, as (name, text): the
    /// stations, their height, spin and heading, the footprint and the relocation cost.
    pub fn facts(&self, job: &StationsJob) -> Vec<(String, String)> {
        let heading = match &job.headings {
            Headings::Auto => "auto".to_string(),
            Headings::Fixed(h) => h
                .iter()
                .map(|a| trimmed(a.to_degrees()))
                .collect::<Vec<_>>()
                .join(","),
        };
        let stats = &self.plan.stats;
        vec![
            ("stations".into(), self.sites.clone()),
            (
                "station height and spin".into(),
                format!(
                    "part origin {:.3} m above the base frame; nozzle spin {:.1}° (part frame); heading {heading}",
                    job.z_m,
                    job.spin_rad.to_degrees(),
                ),
            ),
            (
                "station footprint".into(),
                format!(
                    "floor disc of radius {:.3} m ({}): stations stand on no wall printed before or by their segment and the way between stations crosses none ({}; {} positions on walls dropped, {} moves with no clear way refused, {} moves around walls)",
                    self.footprint_m,
                    if job.footprint_m.is_some() { "given" } else { "estimate: 0.2 × reach" },
                    match job.sites {
                        Sites::Track { .. } => "on the track: the straight way along the rail",
                        Sites::Grid { .. } => "a crawler: the shortest way around the walls printed so far",
                    },
                    stats.footprint_on_wall,
                    stats.way_blocked,
                    stats.detoured
                ),
            ),
            (
                "relocation cost".into(),
                format!(
                    "{} J per relocation + {} J/m (given)",
                    job.relocation_j, job.relocation_j_per_m
                ),
            ),
        ]
    }
}

/// `v` with at most 6 decimals and no trailing zeros (a heading typed as 90 reads 90).
fn trimmed(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}
