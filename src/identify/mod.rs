//! Measured logs against the model (architecture.md, `identify`): reading logs
//! ([`log`]), comparison metrics ([`metrics`]), residual diagnosis ([`diagnose`]), parameter
//! identification with the error ladder ([`ladder`], [`fit`]), where the model fails
//! ([`profiles`]), simulated logs from a "true"
//! robot ([`simulate`]). Charts are drawn by [`crate::report::svg`].

pub mod calibrate;
pub mod diagnose;
pub mod fit;
pub mod ladder;
pub mod log;
pub mod metrics;
pub mod model;
pub mod profiles;
pub mod simulate;
pub mod structure;

pub use log::{read_log, Log, SignalKind};
pub use model::{Model, Prepared, DEFAULT_EFFECTS};

/// Version of the `--json` shapes of `compare`, `diagnose`, `identify` and `simulate`
/// (docs/json.md); raised when a field changes meaning or is removed.
pub const JSON_SCHEMA_VERSION: u32 = crate::output::JSON_SCHEMA_VERSION;

/// The default train/validation split of a log of `n` samples: the first 75 % (rows
/// `0..cut`) to fit, the last 25 % (`cut..n`) to validate. Time
/// blocks, not random rows, so that validation is on motion the fit has not seen.
pub fn train_validation_split(n: usize) -> (std::ops::Range<usize>, std::ops::Range<usize>) {
    let cut = n * 3 / 4;
    (0..cut, cut..n)
}
