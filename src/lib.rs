#![warn(missing_docs)]
//! printwatt: where to put a 3D concrete print so the robot arm spends the least energy, and
//! how well the energy model agrees with what the robot measured.
//!
//! The pipeline, one stage a module: `robot` → `kinematics` → `toolpath` → `timing` →
//! `dynamics` → `energy` → `placement`; `identify` compares with measured logs; `report`
//! writes what people read. The command-line front end (`printwatt`) is a binary over this
//! library; it is not part of the library's API.
//! Units are SI everywhere inside (m, rad, s, kg, N·m, W, J); conversions happen only where
//! data enter or leave.
//!
//! ```
//! use printwatt::{dynamics, kinematics, robot};
//! use std::path::Path;
//!
//! // A shipped robot: URDF + drive file (payload, motors, friction, OPW parameters).
//! let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/abb_irb6700_200_260");
//! let model = robot::load(&dir)?;
//!
//! // Nozzle tip 1.6 m in front of the robot, on the floor, pointing straight down.
//! let target = kinematics::nozzle_target(&nalgebra::Vector3::new(1.6, 0.0, 0.0), 0.0);
//! let solutions = kinematics::solve_all(&model, &target)?;
//! assert!(!solutions.is_empty());
//!
//! // Torque (N·m) to hold the first solution still, with the payload.
//! let dm = dynamics::DynModel::new(&model, dynamics::DynOptions { payload: true, armature: true })?;
//! let mut data = dm.data();
//! let mut tau = [0.0; 6];
//! dynamics::gravity_torque(&dm, &mut data, &solutions[0].q, &mut tau)?;
//! assert!(tau[1].abs() > 1000.0); // the shoulder carries the arm
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod campaign;
pub mod dynamics;
pub mod effects;
pub mod energy;
pub mod error;
pub mod evaluate;
pub mod export;
pub mod fastmath;
pub mod frame;
pub mod identify;
pub mod kinematics;
pub mod math;
pub mod numerics;
pub mod output;
pub mod report;
pub mod robot;
pub mod search;
pub mod simd;
pub mod stations;
pub mod table;
pub mod timing;
pub mod toolpath;
pub mod trajectory;
#[cfg(feature = "view")]
pub mod view;

pub use error::{Error, Result};

/// The linear-algebra crate of every public vector, matrix and transform (nalgebra 0.34), so
/// that a user of printwatt names the same types without pinning its version.
pub use nalgebra;

// The main job in one line each (see `examples/`).
pub use energy::{EnergyModel, EnergyOptions, EnergyReport};
pub use evaluate::PathJob;
pub use frame::Placement;
pub use robot::{load as load_robot, RobotModel};
pub use toolpath::{load as load_path, ReadOptions, Toolpath};
