//! Time parameterisation of a toolpath the way a robot controller runs it.

pub mod geometry;
pub mod profile;

pub use geometry::{blend_path, Move, Piece, Prim};
pub use profile::{CartesianMotion, ProfileOptions};
