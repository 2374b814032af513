//! Evaluating one placement of a path: the job (path, robot, options), the evaluator that
//! times the path at a placement, solves IK, computes torques, losses and energy, and the
//! feasibility checks (reach, joint limits and margins, singularity margins, collisions);
//! the error-controlled path reduction that evaluates a long print from its representative
//! layers.

pub mod evaluator;
pub mod feasibility;
pub(crate) mod job;
pub mod reduce;

pub use evaluator::{Evaluated, Evaluator, Feasible, Objective};
pub use feasibility::{FeasibilityOptions, Infeasible, Reason};
pub use job::{PathJob, PlacementEval};
