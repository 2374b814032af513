//! printwatt: where to put a 3D concrete print so the robot arm spends the least energy, and
//! how well the energy model agrees with what the robot measured.
//!
//! The pipeline, one stage a module: `robot` → `kinematics` → `toolpath` → `timing` →
//! `dynamics` → `energy` → `placement`; `identify` compares with measured logs; `report`
//! writes what people read; `cli` is the thin front end.
//! Units are SI everywhere inside (m, rad, s, kg, N·m, W, J); conversions happen only where
//! data enter or leave.

pub mod cli;
pub mod dynamics;
pub mod effects;
pub mod energy;
pub mod error;
pub mod identify;
pub mod kinematics;
pub mod math;
pub mod output;
pub mod placement;
pub mod report;
pub mod robot;
pub mod table;
pub mod timing;
pub mod toolpath;
pub mod trajectory;

pub use error::{Error, Result};
