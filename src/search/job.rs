//! The job of an optimisation, validated: every option the command line, the Python module and
//! a design study give, as typed values with their defaults written once
//! ([`OptimiseSettings::default`]). Raw text becomes a typed value in one place each: the
//! search method ([`SearchMethod`]), the evaluation mode ([`EvaluationMode`]), the robust
//! choice's objective ([`RobustObjective`]) and the placement tolerance ([`Tolerance`],
//! `XY_MM,YAW_DEG` or `XY_MM,Z_MM,YAW_DEG`) parse with [`FromStr`] and print back with
//! [`Display`](std::fmt::Display). [`crate::search::run`] runs the job.

use crate::energy::EnergyOptions;
use crate::error::{Error, Result};
use crate::evaluate::evaluator::Objective;
use crate::evaluate::feasibility::FeasibilityOptions;
use crate::evaluate::reduce::ReduceOptions;
use crate::robot::RobotModel;
use crate::search::grid::Grid;
use crate::search::tolerance::Tolerance;
use crate::timing::ProfileOptions;
use crate::toolpath::{Placement, Toolpath};
use std::fmt;
use std::path::PathBuf;
use std::str::FromStr;

/// Seed of the refinement's random directions and of the uncertainty study's draws.
pub const DEFAULT_SEED: u64 = 42;
/// Largest number of refinement evaluations.
pub const DEFAULT_MAX_EVALS: usize = 120;
/// Most draws an uncertainty study may take.
pub(crate) const MAX_UNCERTAINTY_DRAWS: usize = 100_000;
/// Prints a year the yearly figures of the robust choice assume.
pub const DEFAULT_PRINTS_PER_YEAR: f64 = 1000.0;
/// Grid carbon intensity the yearly CO₂ figure assumes, kg CO₂ per kWh.
pub const DEFAULT_GRID_KG_CO2_PER_KWH: f64 = 0.4;

/// What the robust choice of an uncertainty study minimises over the drawn robots.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RobustObjective {
    /// The expected energy over the draws.
    #[default]
    Expected,
    /// The worst regret over the draws (minimax regret).
    Regret,
}

impl FromStr for RobustObjective {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim() {
            "expected" | "expected-energy" | "mean" => Ok(RobustObjective::Expected),
            "regret" | "worst-regret" | "minimax" => Ok(RobustObjective::Regret),
            o => Err(Error::Invalid(format!(
                "robust objective `{o}`: expected `expected` (expected energy) or `regret` (worst-case regret)"
            ))),
        }
    }
}

impl fmt::Display for RobustObjective {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            RobustObjective::Expected => "expected",
            RobustObjective::Regret => "regret",
        })
    }
}

/// The refinement after the grid.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SearchMethod {
    /// Nelder–Mead (argmin) over x, y, z, yaw and spin, within the search box, holding the
    /// placement tolerance.
    #[default]
    NelderMead,
    /// The compass search over x, y, yaw and spin at the grid cell's z.
    Pattern,
}

impl FromStr for SearchMethod {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "nelder-mead" | "nelder_mead" | "nm" => Ok(SearchMethod::NelderMead),
            "pattern" => Ok(SearchMethod::Pattern),
            s => Err(Error::Invalid(format!(
                "search method `{s}`: expected nelder-mead or pattern"
            ))),
        }
    }
}

impl fmt::Display for SearchMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            SearchMethod::NelderMead => "nelder-mead",
            SearchMethod::Pattern => "pattern",
        })
    }
}

/// How each placement is evaluated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EvaluationMode {
    /// A long path (at least 200,000 samples) whose layers repeat up to a shift in z is
    /// evaluated on a few representative layers, the others interpolated over z with a stated
    /// error, and the answer re-evaluated in full.
    #[default]
    Auto,
    /// Every sample of every placement.
    Full,
    /// The reduction whenever layers repeat, whatever the length.
    Reduced,
}

impl EvaluationMode {
    /// The reduction options, or `None` for [`EvaluationMode::Full`].
    pub(crate) fn reduce_options(self) -> Option<ReduceOptions> {
        let d = ReduceOptions::default();
        match self {
            EvaluationMode::Auto => Some(d),
            EvaluationMode::Full => None,
            EvaluationMode::Reduced => Some(ReduceOptions {
                min_samples: 0,
                ..d
            }),
        }
    }
}

impl FromStr for EvaluationMode {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim() {
            "auto" => Ok(EvaluationMode::Auto),
            "full" => Ok(EvaluationMode::Full),
            "reduced" => Ok(EvaluationMode::Reduced),
            m => Err(Error::Invalid(format!(
                "evaluation `{m}`: expected auto, full or reduced"
            ))),
        }
    }
}

impl fmt::Display for EvaluationMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            EvaluationMode::Auto => "auto",
            EvaluationMode::Full => "full",
            EvaluationMode::Reduced => "reduced",
        })
    }
}

impl FromStr for Tolerance {
    type Err = Error;
    /// `XY_MM,YAW_DEG` or `XY_MM,Z_MM,YAW_DEG` (mm, mm, deg); `0,0` switches the check off.
    fn from_str(s: &str) -> Result<Self> {
        let v: Vec<f64> = s
            .split(',')
            .map(|t| {
                t.trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite() && *v >= 0.0)
                    .ok_or_else(|| {
                        Error::Invalid(format!(
                            "tolerance `{s}`: `{}` is not a number >= 0",
                            t.trim()
                        ))
                    })
            })
            .collect::<Result<_>>()?;
        let (xy, z, yaw) = match v.as_slice() {
            [xy, yaw] => (*xy, *xy, *yaw),
            [xy, z, yaw] => (*xy, *z, *yaw),
            _ => {
                return Err(Error::Invalid(format!(
                    "tolerance `{s}`: expected XY_MM,YAW_DEG or XY_MM,Z_MM,YAW_DEG"
                )))
            }
        };
        if xy > 500.0 || z > 500.0 || yaw > 45.0 {
            return Err(Error::Invalid(format!(
                "tolerance `{s}`: at most 500 mm and 45°"
            )));
        }
        Ok(Tolerance {
            xy_m: xy / 1000.0,
            z_m: z / 1000.0,
            yaw_rad: yaw.to_radians(),
        })
    }
}

impl fmt::Display for Tolerance {
    /// `XY_MM,Z_MM,YAW_DEG`, the form [`FromStr`] reads.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{},{},{}",
            self.xy_m * 1000.0,
            self.z_m * 1000.0,
            self.yaw_rad.to_degrees()
        )
    }
}

/// Parse a range of the bed height searched, `min:max` in m.
pub fn parse_z_bounds(s: &str) -> Result<[f64; 2]> {
    let v: Vec<f64> = s
        .split(':')
        .map(|t| t.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect::<Option<_>>()
        .ok_or_else(|| Error::Invalid(format!("z bounds `{s}`: expected min:max in m")))?;
    match v.as_slice() {
        [a, b] if a <= b => Ok([*a, *b]),
        _ => Err(Error::Invalid(format!(
            "z bounds `{s}`: expected min:max with min <= max (m)"
        ))),
    }
}

/// The placements the grid stage evaluates: the placements, their names (named sets) and the
/// grid they form (grids).
#[derive(Clone, Debug, PartialEq)]
pub struct PlacementSet {
    /// Every placement, in evaluation order.
    pub placements: Vec<Placement>,
    /// Their names, when they have them.
    pub names: Option<Vec<String>>,
    /// The grid they form, when they do.
    pub grid: Option<Grid>,
}

impl PlacementSet {
    /// Every placement of a grid.
    pub fn grid(g: Grid) -> PlacementSet {
        PlacementSet {
            placements: g.placements(),
            names: None,
            grid: Some(g),
        }
    }
}

/// Every option of an optimisation but its inputs (robot, path, placements), with the
/// command's defaults.
#[derive(Clone, Debug)]
pub struct OptimiseSettings {
    /// What is minimised (J).
    pub objective: Objective,
    /// Feasibility thresholds.
    pub feasibility: FeasibilityOptions,
    /// Energy model options.
    pub energy: EnergyOptions,
    /// Controller timing.
    pub profile: ProfileOptions,
    /// How each placement is evaluated.
    pub evaluation: EvaluationMode,
    /// Baseline placement; `None`: the feasible grid cell nearest the centre of the feasible
    /// region.
    pub baseline: Option<Placement>,
    /// Seed of the refinement's random directions and of the uncertainty draws.
    pub seed: u64,
    /// Largest number of refinement evaluations.
    pub max_evals: usize,
    /// Keep the part yaw fixed during the refinement.
    pub fixed_yaw: bool,
    /// Keep the nozzle spin fixed during the refinement.
    pub fixed_spin: bool,
    /// The refinement.
    pub search: SearchMethod,
    /// Placement tolerance the answer must hold (zero: not checked).
    pub tolerance: Tolerance,
    /// Range of the bed height searched, m (`None`: the placements' z range).
    pub z_bounds: Option<[f64; 2]>,
    /// Draws of the uncertainty study (`None`: no study).
    pub uncertainty: Option<usize>,
    /// What the robust choice minimises over the uncertainty study's draws (with
    /// `uncertainty` and the Nelder–Mead refinement).
    pub robust: RobustObjective,
    /// Prints a year, for the yearly figures of the robust choice and the value of measuring.
    pub prints_per_year: f64,
    /// Grid carbon intensity for the yearly CO₂ figure, kg CO₂ per kWh.
    pub grid_kg_co2_per_kwh: f64,
    /// Time the answer again with the acceleration and jerk limits scaled
    /// ([`crate::search::pareto`]): print time against energy.
    pub pareto: bool,
    /// Find the answer again with other joint-limit and wrist margins
    /// ([`crate::search::margins`]) and state what each costs.
    pub margin_trade: bool,
}

impl Default for OptimiseSettings {
    fn default() -> Self {
        OptimiseSettings {
            objective: Objective::Supply,
            feasibility: FeasibilityOptions::default(),
            energy: EnergyOptions::default(),
            profile: ProfileOptions::default(),
            evaluation: EvaluationMode::default(),
            baseline: None,
            seed: DEFAULT_SEED,
            max_evals: DEFAULT_MAX_EVALS,
            fixed_yaw: false,
            fixed_spin: false,
            search: SearchMethod::default(),
            tolerance: Tolerance::default(),
            z_bounds: None,
            uncertainty: None,
            robust: RobustObjective::default(),
            prints_per_year: DEFAULT_PRINTS_PER_YEAR,
            grid_kg_co2_per_kwh: DEFAULT_GRID_KG_CO2_PER_KWH,
            pareto: false,
            margin_trade: true,
        }
    }
}

impl OptimiseSettings {
    /// Refuse settings no run could use.
    pub fn check(&self) -> Result<()> {
        self.tolerance.check()?;
        if let Some(n) = self.uncertainty {
            if n == 0 || n > MAX_UNCERTAINTY_DRAWS {
                return Err(Error::Invalid(format!(
                    "uncertainty study of {n} draws: expected 1 to 100000 draws"
                )));
            }
        }
        if let Some([a, b]) = self.z_bounds {
            if !(a.is_finite() && b.is_finite() && a <= b) {
                return Err(Error::Invalid(format!(
                    "z bounds {a}:{b}: expected min:max with min <= max (m)"
                )));
            }
        }
        if !(self.prints_per_year.is_finite() && self.prints_per_year >= 0.0) {
            return Err(Error::Invalid(format!(
                "prints per year {}: expected a finite number >= 0",
                self.prints_per_year
            )));
        }
        if !(self.grid_kg_co2_per_kwh.is_finite() && self.grid_kg_co2_per_kwh >= 0.0) {
            return Err(Error::Invalid(format!(
                "grid carbon intensity {} kg CO₂/kWh: expected a finite number >= 0",
                self.grid_kg_co2_per_kwh
            )));
        }
        if self.feasibility.check_every == 0 {
            return Err(Error::Invalid(
                "the collision check interval must be at least 1 sample".into(),
            ));
        }
        self.feasibility.check()
    }
}

/// An optimisation job: the robot, the path and where it may go, and the settings.
#[derive(Clone, Debug)]
pub struct OptimiseConfig {
    /// The robot.
    pub robot: RobotModel,
    /// The toolpath (part frame, m).
    pub path: Toolpath,
    /// Where the toolpath came from (named in the report).
    pub path_file: PathBuf,
    /// The placements of the grid stage; `None`: the default workspace grid over the reach
    /// ([`crate::search::optimise::default_grid`]).
    pub placements: Option<PlacementSet>,
    /// Every other option.
    pub settings: OptimiseSettings,
}

impl OptimiseConfig {
    /// A job on the default grid with the default settings.
    pub fn new(robot: RobotModel, path: Toolpath, path_file: impl Into<PathBuf>) -> Self {
        OptimiseConfig {
            robot,
            path,
            path_file: path_file.into(),
            placements: None,
            settings: OptimiseSettings::default(),
        }
    }

    /// The placements of the grid stage (the default grid when none are given).
    pub(crate) fn placement_set(&self) -> PlacementSet {
        match &self.placements {
            Some(p) => p.clone(),
            None => PlacementSet::grid(crate::search::optimise::default_grid(
                crate::evaluate::feasibility::reach_m(&self.robot),
            )),
        }
    }
}

/// The path job of `config` for `robot` (the config's own or another) timed with `profile`
/// (the config's, or scaled), with the config's energy options.
pub(crate) fn job_with<'a>(
    config: &'a OptimiseConfig,
    robot: &'a crate::robot::RobotModel,
    profile: crate::timing::ProfileOptions,
) -> Result<crate::evaluate::PathJob<'a>> {
    crate::evaluate::PathJob::new(
        robot,
        &config.path,
        config.settings.energy,
        profile,
        crate::timing::JointStageOptions::default(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typed_options_read_and_print_back() {
        for s in ["nelder-mead", "pattern"] {
            assert_eq!(s.parse::<SearchMethod>().unwrap().to_string(), s);
        }
        assert_eq!(
            "nm".parse::<SearchMethod>().unwrap(),
            SearchMethod::NelderMead
        );
        assert!("simplex".parse::<SearchMethod>().is_err());
        for s in ["auto", "full", "reduced"] {
            assert_eq!(s.parse::<EvaluationMode>().unwrap().to_string(), s);
        }
        for s in ["expected", "regret"] {
            assert_eq!(s.parse::<RobustObjective>().unwrap().to_string(), s);
        }
        assert!("median".parse::<RobustObjective>().is_err());
        let t: Tolerance = "20,1".parse().unwrap();
        assert_eq!(t, Tolerance::default());
        assert_eq!(t.to_string().parse::<Tolerance>().unwrap(), t);
        assert!("20".parse::<Tolerance>().is_err());
        assert!("600,1".parse::<Tolerance>().is_err());
        assert_eq!(parse_z_bounds("0:0.5").unwrap(), [0.0, 0.5]);
        assert!(parse_z_bounds("1:0").is_err());
    }

    #[test]
    fn defaults_are_the_commands() {
        let s = OptimiseSettings::default();
        assert_eq!((s.seed, s.max_evals), (42, 120));
        assert_eq!(s.search, SearchMethod::NelderMead);
        assert_eq!(s.evaluation, EvaluationMode::Auto);
        assert_eq!(s.robust, RobustObjective::Expected);
        assert_eq!((s.prints_per_year, s.grid_kg_co2_per_kwh), (1000.0, 0.4));
        assert!(s.check().is_ok());
        let bad = OptimiseSettings {
            prints_per_year: f64::NAN,
            ..OptimiseSettings::default()
        };
        assert!(bad.check().is_err());
    }
}
