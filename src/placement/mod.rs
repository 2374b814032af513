//! Placements of a toolpath in the robot's workspace: evaluating one placement (timing, IK,
//! dynamics, energy), feasibility (reach, limits, singularity margin, collision), parallel
//! sweeps and the minimum-energy search.

pub mod advice;
pub mod collision;
pub mod eval;
pub mod export;
pub mod feasibility;
pub mod margins;
pub mod neldermead;
pub mod optimise;
pub mod reduce;
pub mod search;
pub mod shard;
pub mod stations;
pub mod study;
pub mod sweep;
pub mod tolerance;
pub mod uncertainty;
pub mod value;

pub use eval::{PathJob, PlacementEval};
pub use feasibility::{FeasibilityOptions, Infeasible, Reason};
pub use sweep::{parse_range, Evaluated, Evaluator, Feasible, Grid, Objective};
pub use value::{NamedPlacement, Placement, PlacementParseError, PlacementUnitsError};
