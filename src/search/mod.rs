//! The minimum-energy search over placements: the candidate grid, the refinement (Nelder–Mead
//! or pattern search, through argmin's problem/solver/observer split), the placement
//! tolerance a site can hold, the uncertainty study over what the drive data do not know, and
//! the advice printed when nothing is feasible.

pub mod advice;
pub(crate) mod grid;
pub mod job;
pub mod margins;
pub mod neldermead;
pub mod optimise;
pub mod pareto;
pub mod refine;
pub mod robust;
pub mod run;
pub mod tolerance;
pub mod uncertainty;
pub mod value_of_information;

pub use grid::{parse_range, Grid};
pub use job::{EvaluationMode, OptimiseConfig, OptimiseSettings, PlacementSet, SearchMethod};
pub use run::{run, Observer, OptimiseOutcome, Silent};
