//! The command-line front end: a thin layer of clap over library calls. Every command that
//! prints results also answers in JSON with `--json`.

use crate::robot;
use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use serde::Serialize;
use std::path::{Path, PathBuf};

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
        Command::Robots(a) => cmd_robots(a),
    }
}

#[derive(Serialize)]
struct RobotRow {
    id: String,
    name: String,
    joints: usize,
    reach_m: Option<f64>,
    rated_payload_kg: Option<f64>,
    moving_mass_kg: f64,
    closed_form_ik: bool,
    drive_data: bool,
    provenance: String,
}

fn cmd_robots(a: RobotsArgs) -> Result<()> {
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(&a.dir)
        .with_context(|| format!("reading robots directory {}", a.dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    let mut rows = Vec::new();
    for d in dirs {
        let m = robot::load(&d).with_context(|| format!("loading robot {}", d.display()))?;
        rows.push(RobotRow {
            id: d
                .file_name()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default(),
            name: m.info.name.clone(),
            joints: m.dof(),
            reach_m: m.info.reach_m,
            rated_payload_kg: m.info.rated_payload_kg,
            moving_mass_kg: m.moving_mass(),
            closed_form_ik: m.opw.is_some(),
            drive_data: m.drive.is_some(),
            provenance: m.info.provenance.clone(),
        });
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&rows)?);
        return Ok(());
    }
    println!(
        "{:<22} {:<28} {:>6} {:>8} {:>11} {:>10} {:>4} {:>5}",
        "id", "name", "joints", "reach_m", "payload_kg", "mass_kg", "opw", "drive"
    );
    for r in &rows {
        let o = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.2}"));
        println!(
            "{:<22} {:<28} {:>6} {:>8} {:>11} {:>10.1} {:>4} {:>5}",
            r.id,
            r.name,
            r.joints,
            o(r.reach_m),
            o(r.rated_payload_kg),
            r.moving_mass_kg,
            if r.closed_form_ik { "yes" } else { "no" },
            if r.drive_data { "yes" } else { "no" }
        );
    }
    println!();
    for r in &rows {
        println!("{}: {}", r.id, r.provenance);
    }
    Ok(())
}
