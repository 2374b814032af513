//! Measured logs against the model: reading logs, comparison metrics, residual diagnosis,
//! parameter identification with the error ladder, and simulated logs from a "true" robot.

pub mod log;
pub mod model;

pub use log::{read_log, Log, SignalKind};
pub use model::{Model, Prepared, DEFAULT_EFFECTS};
