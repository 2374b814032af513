//! What the benches set up alike: the shipped default robot (ABB IRB 6700-200/2.60), the
//! default path (`paths/default.gcode`) and a path job with the default energy, profile and
//! joint-stage options (the CLI's defaults).

#![allow(dead_code)] // each bench uses what it needs

use printwatt::energy::EnergyOptions;
use printwatt::placement::PathJob;
use printwatt::robot::{self, RobotModel};
use printwatt::timing::{JointStageOptions, ProfileOptions};
use printwatt::toolpath::{self, ReadOptions, Toolpath};
use std::path::{Path, PathBuf};

/// The checkout's root directory.
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The shipped default robot's directory.
pub fn robot_dir() -> PathBuf {
    root().join("robots/abb_irb6700_200_260")
}

/// The shipped default robot.
pub fn robot() -> RobotModel {
    robot::load(&robot_dir()).unwrap()
}

/// The default path (`paths/default.gcode`).
pub fn default_path() -> Toolpath {
    toolpath::load(&root().join("paths/default.gcode"), &ReadOptions::default()).unwrap()
}

/// `tp` on `model` with the default energy, profile and joint-stage options.
pub fn job<'a>(model: &'a RobotModel, tp: &Toolpath) -> PathJob<'a> {
    PathJob::new(
        model,
        tp,
        EnergyOptions::default(),
        ProfileOptions::default(),
        JointStageOptions::default(),
    )
    .unwrap()
}
