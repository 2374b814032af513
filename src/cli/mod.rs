//! The command-line front end: a thin layer of clap over library calls. Every command that
//! prints results also answers in JSON with `--json`.

use crate::robot;
use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};

mod compare;
mod diagnose;
mod energy;
mod identify;
mod optimise;
mod robots;
mod simulate;
pub mod sweep;

/// printwatt: where to put a 3D concrete print so the robot arm spends the least energy.
#[derive(Parser, Debug)]
#[command(name = "printwatt", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

/// The commands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// List the shipped robots with reach, payload, joint count and provenance.
    Robots(RobotsArgs),
    /// Evaluate placements of a path (grid, named set or list) in parallel: energy or why not.
    Sweep(sweep::SweepArgs),
    /// Find the minimum-energy placement (grid, then seeded pattern search) and write a report.
    Optimise(optimise::OptimiseArgs),
    /// Energy of a joint trajectory, or of a toolpath at one placement.
    Energy(energy::EnergyArgs),
    /// Compare the model with a measured log: RMSE, energy error, where the residual sits.
    Compare(CompareArgs),
    /// Rank the catalogue effects by how much of the residual each explains (held out).
    Diagnose(DiagnoseArgs),
    /// Fit effects' parameters, report the error ladder, write a calibrated robot file.
    Identify(IdentifyArgs),
    /// Write a simulated log from a "true" robot with hidden effects.
    Simulate(SimulateArgs),
}

/// Robot, log and model switches shared by compare/diagnose/identify.
#[derive(clap::Args, Debug, Clone)]
pub struct LogArgs {
    /// Robot: a shipped robot's name, a directory, a .urdf or a drive .toml file.
    #[arg(long)]
    pub robot: PathBuf,
    /// Measured log (CSV, docs/measurement-logs.md).
    #[arg(long)]
    pub log: PathBuf,
    /// Column map for a log without header, e.g. "t, q1..q6[deg], i1..i6, skip*12".
    #[arg(long)]
    pub columns: Option<String>,
    /// Effects switched on (comma list of catalogue names); for `identify`: the effects to
    /// fit, in ladder order.
    #[arg(long)]
    pub effects: Option<String>,
    /// Effects switched off (comma list).
    #[arg(long)]
    pub without: Option<String>,
}

/// `printwatt compare`
#[derive(clap::Args, Debug)]
pub struct CompareArgs {
    #[command(flatten)]
    pub log: LogArgs,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
    /// Directory for compare.json and report.html.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// `printwatt diagnose`
#[derive(clap::Args, Debug)]
pub struct DiagnoseArgs {
    #[command(flatten)]
    pub log: LogArgs,
    /// Number of time-block folds.
    #[arg(long, default_value_t = 5)]
    pub folds: usize,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// `printwatt identify`
#[derive(clap::Args, Debug)]
pub struct IdentifyArgs {
    #[command(flatten)]
    pub log: LogArgs,
    /// Validate on this log instead of the last quarter of --log.
    #[arg(long)]
    pub validate_log: Option<PathBuf>,
    /// Where to write the calibrated robot (default: `<name>.calibrated.toml` in --out, or in
    /// the current directory; never in the installed robots folder).
    #[arg(long)]
    pub drive_out: Option<PathBuf>,
    /// Overwrite an existing calibrated robot file (never the input).
    #[arg(long)]
    pub force: bool,
    /// Directory for the calibrated robot, ladder.md, ladder.svg and identify.json.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// `printwatt simulate`
#[derive(clap::Args, Debug)]
pub struct SimulateArgs {
    /// Robot (nominal model).
    #[arg(long)]
    pub robot: PathBuf,
    /// Toolpath to time at --at.
    #[arg(long)]
    pub path: Option<PathBuf>,
    /// Placement x,y,z (m), yaw (deg).
    #[arg(long, allow_hyphen_values = true)]
    pub at: Option<String>,
    /// Joint trajectory CSV instead of a path.
    #[arg(long)]
    pub trajectory: Option<PathBuf>,
    /// Synthetic exciting motion (sums of sines within limits) of this many seconds.
    #[arg(long)]
    pub excite: Option<f64>,
    /// Hidden effects of the true robot, e.g. "coulomb=40,balancer=8000:20000,payload=+15".
    #[arg(long, allow_hyphen_values = true)]
    pub hidden: Option<String>,
    /// Signal to log: tau, i, p or p_total.
    #[arg(long, default_value = "tau")]
    pub signal: String,
    /// Signal noise standard deviation (signal unit; default 2 N·m, 0.02 A, 5 W, 20 W).
    #[arg(long)]
    pub noise: Option<f64>,
    /// Position noise standard deviation, rad.
    #[arg(long, default_value_t = 1e-6)]
    pub noise_q: f64,
    /// Current quantisation step, A (current logs).
    #[arg(long, default_value_t = 0.01)]
    pub quantum: f64,
    /// Sample rate, Hz.
    #[arg(long, default_value_t = 250.0)]
    pub rate: f64,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Output log.
    #[arg(long)]
    pub out: PathBuf,
}

/// `printwatt robots`
#[derive(clap::Args, Debug)]
pub struct RobotsArgs {
    /// Directory holding one sub-directory per robot.
    #[arg(long, default_value_os_t = default_robots_dir())]
    pub dir: PathBuf,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// The shipped robots directory: `$PRINTWATT_ROBOTS`, else `robots/` in the working
/// directory, else the one in the source tree this binary was built from.
pub fn default_robots_dir() -> PathBuf {
    if let Some(p) = std::env::var_os("PRINTWATT_ROBOTS") {
        return p.into();
    }
    let local = Path::new("robots");
    if local.is_dir() {
        return local.to_path_buf();
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join("robots")
}

/// Resolve a `--robot` argument: a path, or the name of a shipped robot.
pub fn resolve_robot(arg: &Path) -> PathBuf {
    if arg.exists() {
        return arg.to_path_buf();
    }
    let shipped = default_robots_dir().join(arg);
    if shipped.exists() {
        shipped
    } else {
        arg.to_path_buf()
    }
}

/// Load a robot named on the command line, with context for the error message.
pub fn load_robot(arg: &Path) -> Result<robot::RobotModel> {
    let p = resolve_robot(arg);
    robot::load(&p).with_context(|| format!("loading robot {}", arg.display()))
}

/// Run the parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Robots(a) => robots::run(a),
        Command::Energy(a) => energy::run(a),
        Command::Sweep(a) => sweep::run(a),
        Command::Optimise(a) => optimise::run(a),
        Command::Compare(a) => compare::run(a),
        Command::Diagnose(a) => diagnose::run(a),
        Command::Identify(a) => identify::run(a),
        Command::Simulate(a) => simulate::run(a),
    }
}

/// Parse a comma-separated list of exactly `n` finite numbers.
pub fn parse_list(s: &str, n: usize) -> Result<Vec<f64>> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| {
            let t = x.trim();
            t.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .with_context(|| format!("`{t}` is not a finite number"))
        })
        .collect::<Result<_>>()?;
    if v.len() != n {
        anyhow::bail!("expected {n} comma-separated numbers, got {}", v.len());
    }
    Ok(v)
}
