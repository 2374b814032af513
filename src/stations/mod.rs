//! Multi-station plans: a path larger than one placement's reach (a building floor) printed by
//! an arm that is moved between stations (on a track or a crawler).
//!
//! # The problem ([`StationsProblem`])
//! The path (part frame, m), the robot, the energy, timing and feasibility options of every
//! other placement command, the candidate stations ([`Candidates`]: a grid over the path's
//! footprint, or points along a track line) and the user's stated cost of one relocation, J
//! (and optionally per metre moved, J/m).
//!
//! # Where the path may be split ([`split_units`])
//! The path is cut into **units**: maximal runs of consecutive extruding moves at one z level
//! (the end height of the move). A unit therefore ends where the nozzle stops extruding (a
//! travel move follows) or where a layer changes (the next extruding move ends at another
//! height; a rising move belongs to the layer it rises to). A plan's **segments** are
//! contiguous runs of units, in path order: the path is never reordered, so a path that
//! prints the whole floor layer by layer can only be split layer by layer.
//!
//! # The model (stated, not hidden)
//! - A segment of units `i..=j` is the sub-path from the first move of unit `i` to the last
//!   move of unit `j`, the travel moves between its units included (the arm makes them). The
//!   first segment also holds the path's lead-in (moves before the first unit), the last its
//!   lead-out, so that a one-station plan evaluates exactly the whole path.
//! - The travel moves between two segments printed from different stations are **not**
//!   evaluated: the relocation replaces them, and its cost is the user's number
//!   ([`StationsProblem::relocation_j`] + [`StationsProblem::relocation_j_per_m`] × the
//!   distance between the stations). printwatt does not model the move of the arm itself.
//! - Each segment is timed and its energy computed **from rest to rest at its station**, with
//!   [`crate::evaluate::Evaluator`] on the sub-path: the same timing, dynamics, losses and
//!   feasibility (reach with one arm configuration, joint limits and margins, singularity
//!   margins, collisions with the bed under the segment, with the beads the segment lays
//!   itself and with the walls the segments before it printed,
//!   [`crate::evaluate::Evaluator::with_prior_walls`]) as `sweep` and `optimise`.
//! - Where a station stands and the way between stations are checked against the walls in
//!   plan view ([`floor`]): a station's floor disc ([`StationsProblem::footprint_m`], the
//!   robot's foot with its carriage or crawler) may not stand on a wall printed before or by
//!   its segment, the disc swept along the straight line to the next station may not cross a
//!   wall printed before the move, and a track's rail may not lie under any wall.
//! - Two consecutive segments never share a station position: an arm that stays would print
//!   them as one segment.
//!
//! # The solver ([`solve`])
//! Every contiguous run of units is evaluated from every candidate station that passes a
//! geometric pre-filter (the run's points within the arm's horizontal reach annulus at the
//! run's heights, with a slack of [`PREFILTER_SLACK_REACH`] of the reach plus
//! [`PREFILTER_SAMPLE_M`]); a run that no candidate passes ends the runs starting at its first
//! unit (a longer run contains its points). Then dynamic programming over the split points
//! chooses the plan of least `Σ segment energies + relocation costs`: exact over the candidate
//! set. Deterministic: candidates are evaluated in parallel (rayon) and collected in input
//! order, the DP runs sequentially with ties to the first candidate, so the plan is identical
//! for any thread count.

pub mod floor;
mod run;
mod solve;

pub use run::{run, Sites, StationsJob, StationsOutcome, DEFAULT_Z_M};
pub use solve::{solve, Plan, PlanStats, Segment};

use crate::energy::EnergyOptions;
use crate::error::{Error, Result};
use crate::evaluate::{FeasibilityOptions, Objective};
use crate::frame::Placement;
use crate::math::V3;
use crate::robot::RobotModel;
use crate::timing::{JointStageOptions, ProfileOptions};
use crate::toolpath::{Dwell, Toolpath};
use serde::Serialize;

/// Share of the reach added to the reach annulus by the pre-filter (dimensionless): the
/// annulus is sampled every 1 % of the reach, so 2 % keeps every station the sampling might
/// misjudge.
pub(crate) const PREFILTER_SLACK_REACH: f64 = 0.02;

/// Spacing of the path points the pre-filter tests, m; half of it is added to the slack.
pub(crate) const PREFILTER_SAMPLE_M: f64 = 0.05;

/// Two z levels closer than this are one layer, m.
pub(crate) const LEVEL_TOLERANCE_M: f64 = 1e-6;

/// A station's floor disc radius when none is given, as a share of the arm's reach
/// ([`crate::evaluate::feasibility::reach_m`]), dimensionless. ESTIMATE: the IRB 6640 family's
/// foot is 1107 × 720 mm at a working radius of 3.2 m (ABB product specification IRB 6640;
/// [3rd] Joseph, *Mastering ROS for Robotics Programming*): a circumscribed radius of 0.66 m,
/// 0.21 of the reach. A track carriage or crawler is often larger: give its radius.
pub(crate) const FOOTPRINT_PER_REACH: f64 = 0.2;

/// The default floor disc radius of a station for `model`, m ([`FOOTPRINT_PER_REACH`] × reach).
pub fn default_footprint_m(model: &RobotModel) -> f64 {
    FOOTPRINT_PER_REACH * crate::evaluate::feasibility::reach_m(model)
}

/// The largest number of candidate station positions accepted (a finer grid is refused with
/// the count, not run for hours).
pub(crate) const MAX_CANDIDATES: usize = 20_000;

/// A unit of the path: a maximal run of extruding moves at one z level, the smallest piece a
/// plan assigns to a station.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Unit {
    /// Index of the first move (0-based, into [`Toolpath::moves`]).
    pub first_move: usize,
    /// Index of the last move (inclusive).
    pub last_move: usize,
    /// Source line of the first move (1-based).
    pub first_line: usize,
    /// Source line of the last move.
    pub last_line: usize,
    /// z level of the unit (end height of its moves, part frame), m.
    pub z_m: f64,
    /// Extruded length, m.
    pub print_length_m: f64,
}

/// Cut `path` into units (see the module documentation). Error: the path extrudes nowhere.
pub fn split_units(path: &Toolpath) -> Result<Vec<Unit>> {
    let mut units: Vec<Unit> = Vec::new();
    let mut prev_print = false;
    for (i, (start, m)) in path.segments().enumerate() {
        if !m.print {
            prev_print = false;
            continue;
        }
        let len = m.length(&start);
        let same_level = units
            .last()
            .is_some_and(|u| (u.z_m - m.end.z).abs() <= LEVEL_TOLERANCE_M);
        if prev_print && same_level {
            if let Some(u) = units.last_mut() {
                u.last_move = i;
                u.last_line = m.line;
                u.print_length_m += len;
            }
        } else {
            units.push(Unit {
                first_move: i,
                last_move: i,
                first_line: m.line,
                last_line: m.line,
                z_m: m.end.z,
                print_length_m: len,
            });
        }
        prev_print = true;
    }
    if units.is_empty() {
        return Err(Error::Invalid(format!(
            "{}: the path has no extruding moves: nothing to split between stations",
            path.source
        )));
    }
    Ok(units)
}

/// The moves of the segment of units `i..=j` as a range of move indices (inclusive): from the
/// first move of unit `i` (move 0 for the first unit: the lead-in) to the last move of unit
/// `j` (the last move of the path for the last unit: the lead-out).
pub(crate) fn segment_moves(path: &Toolpath, units: &[Unit], i: usize, j: usize) -> (usize, usize) {
    let first = if i == 0 { 0 } else { units[i].first_move };
    let last = if j + 1 == units.len() {
        path.moves.len() - 1
    } else {
        units[j].last_move
    };
    (first, last)
}

/// The sub-path of moves `first..=last` (as [`segment_moves`] gives them): it starts at rest at
/// the start of move `first`; source lines are kept. Dwells after a kept move are kept; a
/// dwell right before the first move is held at the start.
pub fn sub_path(path: &Toolpath, first: usize, last: usize) -> Toolpath {
    let dwells = path
        .dwells
        .iter()
        .filter_map(|d| {
            let after_move = match d.after_move {
                None if first == 0 => None,
                None => return None,
                Some(k) if k + 1 == first => None,
                Some(k) if k >= first && k <= last => Some(k - first),
                Some(_) => return None,
            };
            Some(Dwell { after_move, ..*d })
        })
        .collect();
    Toolpath {
        source: path.source.clone(),
        start: path.move_start(first),
        moves: path.moves[first..=last].to_vec(),
        marks: Vec::new(),
        warnings: Vec::new(),
        dwells,
        ..Default::default()
    }
}

/// Which way a station's robot faces.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Headings {
    /// Toward the centroid of the segment's extruded points (joint 1 near the middle of its
    /// range over the segment), chosen per segment.
    Auto,
    /// Each of these headings (rad, part frame: the direction of the robot base's x axis),
    /// every one a candidate (a track fixes the heading).
    Fixed(Vec<f64>),
}

/// The candidate stations: positions of the robot base in the part frame (m) and headings.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Candidates {
    /// Base positions (x, y) in the part frame, m.
    pub positions: Vec<[f64; 2]>,
    /// Headings.
    pub headings: Headings,
    /// How they were made (for reports), e.g. "grid every 0.50 m over the footprint ± 2.60 m".
    pub description: String,
    /// The track's ends (part frame, m) when the positions lie on a track: its rail may not
    /// lie under a wall.
    pub track: Option<[[f64; 2]; 2]>,
}

impl Candidates {
    /// Positions on a grid every `step_m` (m) over the path's footprint widened by the arm's
    /// reach ([`grid_positions`]), with `headings`. Errors as [`grid_positions`].
    pub fn grid(path: &Toolpath, step_m: f64, reach_m: f64, headings: Headings) -> Result<Self> {
        Ok(Candidates {
            positions: grid_positions(path, step_m, reach_m)?,
            headings,
            description: format!("grid every {step_m} m over the footprint ± {reach_m:.2} m"),
            track: None,
        })
    }

    /// Positions every `step_m` (m) along the track from `a` to `b` (part frame, m;
    /// [`track_positions`]), with `headings`. Errors as [`track_positions`].
    pub fn track(a: [f64; 2], b: [f64; 2], step_m: f64, headings: Headings) -> Result<Self> {
        Ok(Candidates {
            positions: track_positions(a, b, step_m)?,
            headings,
            description: format!(
                "track ({}, {}) → ({}, {}) m every {step_m} m",
                a[0], a[1], b[0], b[1]
            ),
            track: Some([a, b]),
        })
    }
}

/// A grid every `step_m` (m) over the path's footprint (its xy bounding box) widened by
/// `margin_m` on every side, aligned to multiples of `step_m` (so a shifted job gives the same
/// lattice). Error: a step that is not > 0, or more than [`MAX_CANDIDATES`] positions.
pub fn grid_positions(path: &Toolpath, step_m: f64, margin_m: f64) -> Result<Vec<[f64; 2]>> {
    if !(step_m.is_finite() && step_m > 0.0) {
        return Err(Error::Invalid(format!(
            "station step {step_m} m: expected a finite step > 0"
        )));
    }
    let (lo, hi) = path
        .bounding_box()
        .ok_or_else(|| Error::Invalid(format!("{}: the path has no moves", path.source)))?;
    let k0 = |v: f64| ((v - margin_m) / step_m).floor() as i64;
    let k1 = |v: f64| ((v + margin_m) / step_m).ceil() as i64;
    let (nx, ny) = (k1(hi.x) - k0(lo.x) + 1, k1(hi.y) - k0(lo.y) + 1);
    let n = (nx.max(0) as u128) * (ny.max(0) as u128);
    if n > MAX_CANDIDATES as u128 {
        return Err(Error::Invalid(format!(
            "station grid every {step_m} m over the footprint: {n} positions, more than {MAX_CANDIDATES}: use a larger step"
        )));
    }
    let mut v = Vec::with_capacity(n as usize);
    for iy in k0(lo.y)..=k1(hi.y) {
        for ix in k0(lo.x)..=k1(hi.x) {
            v.push([ix as f64 * step_m, iy as f64 * step_m]);
        }
    }
    Ok(v)
}

/// Positions every `step_m` (m) along the track from `a` to `b` (part frame, m), both ends
/// included (the last spacing may be shorter). Error: a step that is not > 0, or more than
/// [`MAX_CANDIDATES`] positions.
pub fn track_positions(a: [f64; 2], b: [f64; 2], step_m: f64) -> Result<Vec<[f64; 2]>> {
    if !(step_m.is_finite() && step_m > 0.0) {
        return Err(Error::Invalid(format!(
            "station step {step_m} m: expected a finite step > 0"
        )));
    }
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    let n = (len / step_m - 1e-9).ceil().max(0.0) as usize;
    if n + 1 > MAX_CANDIDATES {
        return Err(Error::Invalid(format!(
            "track of {len:.3} m every {step_m} m: more than {MAX_CANDIDATES} positions: use a larger step"
        )));
    }
    let mut v: Vec<[f64; 2]> = (0..n)
        .map(|k| {
            let t = k as f64 * step_m / len.max(1e-12);
            [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
        })
        .collect();
    v.push(b);
    Ok(v)
}

/// A station: where the robot base stands in the part frame and which way it faces, and the
/// placement of the part frame in that robot's base frame it amounts to.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Station {
    /// Base position in the part frame, m.
    pub x_m: f64,
    /// Base position in the part frame, m.
    pub y_m: f64,
    /// Heading of the base's x axis in the part frame, rad.
    pub heading_rad: f64,
    /// The part frame in this robot's base frame (what `--at` takes): yaw = −heading,
    /// (x, y) = −Rz(−heading)·(x_m, y_m), z and nozzle spin as given.
    #[serde(skip)]
    pub placement: Placement,
}

impl Station {
    /// The station at base position (x, y) (part frame, m) facing `heading` (rad), with the
    /// part origin at height `z` (m) above the base frame and nozzle spin `spin` (rad,
    /// relative to the part frame, as everywhere in printwatt).
    pub fn new(x: f64, y: f64, heading: f64, z: f64, spin: f64) -> Station {
        let (s, c) = (-heading).sin_cos();
        Station {
            x_m: x,
            y_m: y,
            heading_rad: heading,
            placement: Placement {
                x: -(c * x - s * y),
                y: -(s * x + c * y),
                z,
                yaw: -heading,
                nozzle_spin: spin,
            },
        }
    }
}

/// The multi-station problem: what is to be printed, by what, from where, and what a
/// relocation costs. Separate from the solver ([`solve`]).
pub struct StationsProblem<'a> {
    /// The robot.
    pub robot: &'a RobotModel,
    /// The whole path (part frame, m).
    pub path: &'a Toolpath,
    /// Energy model options.
    pub energy: EnergyOptions,
    /// Controller timing.
    pub profile: ProfileOptions,
    /// Joint-stage timing options.
    pub joint: JointStageOptions,
    /// Feasibility thresholds (as `sweep` and `optimise`).
    pub feasibility: FeasibilityOptions,
    /// The energy minimised, J.
    pub objective: Objective,
    /// Candidate stations.
    pub candidates: Candidates,
    /// Height of the part origin above each station's base frame, m.
    pub z_m: f64,
    /// Nozzle spin relative to the part frame, rad (as `--spin`).
    pub spin_rad: f64,
    /// The user's cost of one relocation, J (≥ 0).
    pub relocation_j: f64,
    /// The user's cost per metre between consecutive stations, J/m (≥ 0).
    pub relocation_j_per_m: f64,
    /// Radius of the floor disc a station occupies (the robot's foot with its track carriage
    /// or crawler), m (≥ 0; [`default_footprint_m`] when the user gives none).
    pub footprint_m: f64,
}

impl StationsProblem<'_> {
    /// Check the numbers the user gave: finite, costs ≥ 0, at least one candidate position.
    pub fn check(&self) -> Result<()> {
        for (what, v) in [
            ("relocation cost (J)", self.relocation_j),
            ("relocation cost per metre (J/m)", self.relocation_j_per_m),
            ("station footprint radius (m)", self.footprint_m),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::Invalid(format!(
                    "{what} {v}: expected a finite number >= 0"
                )));
            }
        }
        if !(self.z_m.is_finite() && self.spin_rad.is_finite()) {
            return Err(Error::Invalid(
                "station height and spin must be finite".into(),
            ));
        }
        if self.candidates.positions.is_empty() {
            return Err(Error::Invalid("no candidate station positions".into()));
        }
        if let Headings::Fixed(h) = &self.candidates.headings {
            if h.is_empty() || h.iter().any(|v| !v.is_finite()) {
                return Err(Error::Invalid(
                    "headings: expected at least one finite angle".into(),
                ));
            }
        }
        Ok(())
    }
}

/// Horizontal reach of a downward nozzle over heights `zs` (base frame, m): the smallest and
/// largest distance from axis 1 at which some nozzle yaw (every 30°) has an IK solution,
/// sampled every 1 % of the reach up to 120 %, over all `zs`. `None`: nothing reachable.
pub(crate) fn reach_annulus(model: &RobotModel, zs: &[f64]) -> Option<(f64, f64)> {
    let solver = crate::kinematics::IkSolver::new(model).ok()?;
    let reach = crate::evaluate::feasibility::reach_m(model);
    let mut lo: Option<f64> = None;
    let mut hi: Option<f64> = None;
    for &z in zs {
        for i in 0..=120 {
            let r = reach * i as f64 / 100.0;
            let hit = (0..12).any(|k| {
                let yaw = (k as f64 * 30.0).to_radians();
                let target = crate::kinematics::nozzle_target(&V3::new(r, 0.0, z), yaw);
                solver.solve_all(&target).is_ok_and(|s| !s.is_empty())
            });
            if hit {
                lo = Some(lo.map_or(r, |l: f64| l.min(r)));
                hi = Some(hi.map_or(r, |h: f64| h.max(r)));
            }
        }
    }
    lo.zip(hi)
}
