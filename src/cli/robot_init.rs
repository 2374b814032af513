//! `printwatt robot init URDF`: a drive-file template for a URDF (the library writes it).

use anyhow::Result;
use clap::{Args, Subcommand};
use std::path::PathBuf;

/// `printwatt robot …`
#[derive(Args, Debug)]
pub struct RobotCmd {
    #[command(subcommand)]
    pub action: RobotAction,
}

/// What `printwatt robot` does.
#[derive(Subcommand, Debug)]
pub enum RobotAction {
    /// Write a drive-file template (drive.toml) for a URDF's joints: every key explained,
    /// placeholders marked ESTIMATE, `[robot] urdf` relative to the file written. Never
    /// overwrites a file.
    Init(InitArgs),
}

/// `printwatt robot init`
#[derive(Args, Debug)]
pub struct InitArgs {
    /// The robot's URDF.
    #[arg(value_name = "URDF")]
    pub urdf: PathBuf,
    /// The drive file to write (refused if it exists).
    #[arg(long, value_name = "FILE", default_value = "drive.toml")]
    pub out: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Run `printwatt robot …`.
pub fn run(c: RobotCmd) -> Result<()> {
    match c.action {
        RobotAction::Init(a) => init(a),
    }
}

fn init(a: InitArgs) -> Result<()> {
    let t = match printwatt::robot::template::write_drive_template(&a.urdf, &a.out) {
        // No --force here: a drive file being filled in is never replaced.
        Err(printwatt::Error::OutputExists { path }) => anyhow::bail!(
            "{} exists already: `robot init` never replaces a file; choose another --out (or move the file away)",
            path.display()
        ),
        r => r?,
    };
    super::note_warnings(&a.urdf.display().to_string(), &t.warnings);
    let robot_arg = t.path.display().to_string();
    if a.json {
        super::print_json(&serde_json::json!({
            "drive_file": robot_arg,
            "urdf": t.urdf_relative,
            "robot": t.robot,
            "joints": t.joints,
            "estimated_links": t.estimated_links,
        }))?;
        return Ok(());
    }
    outln!(
        "wrote {robot_arg}: a drive-file template for {} ({} joints: {})",
        t.robot,
        t.joints.len(),
        t.joints.join(", ")
    );
    outln!("  [robot] urdf = \"{}\"", t.urdf_relative);
    if !t.estimated_links.is_empty() {
        outln!(
            "  links without an <inertial> in the URDF (estimated; commented [links.<name>] tables to fill in): {}",
            t.estimated_links.join(", ")
        );
    }
    outln!("  replace every ESTIMATE and fill in the commented keys (docs/drive-file.md); it loads as written:");
    outln!("  printwatt energy --robot {robot_arg} --at X,Y,Z,YAW");
    Ok(())
}
