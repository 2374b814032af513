//! Placements of a toolpath in the robot's workspace: evaluating one placement (timing, IK,
//! dynamics, energy), and, built on it, feasibility, sweeps and the minimum-energy search.

pub mod eval;

pub use eval::{PathJob, PlacementEval};
