//! printwatt: where to put a 3D concrete print so the robot arm spends the least energy, and
//! how well the energy model agrees with what the robot measured.
//!
//! The pipeline, one stage a module: `robot` → `kinematics` → `dynamics` → `energy`.
//! Units are SI everywhere inside (m, rad, s, kg, N·m, W, J); conversions happen only where
//! data enter or leave.

pub mod error;
pub mod kinematics;
pub mod math;
pub mod robot;
pub mod trajectory;

pub use error::{Error, Result};
