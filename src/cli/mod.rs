//! The command-line front end: a thin layer of clap over library calls. Every command that
//! prints results also answers in JSON with `--json`.

use crate::robot;
use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};

mod optimise;
mod robots;
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
        Command::Sweep(a) => sweep::run(a),
        Command::Optimise(a) => optimise::run(a),
    }
}
