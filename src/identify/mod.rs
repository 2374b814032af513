//! Measured logs against the model (architecture.md, `identify`): reading logs
//! ([`log`]; a long log's velocities and accelerations are kept outside memory, [`motion`]),
//! comparison metrics ([`metrics`]), residual diagnosis ([`diagnose`]), parameter
//! identification with the error ladder ([`ladder`], [`fit`]), where the model fails
//! ([`profiles`]), one round as a user runs it ([`round`]), simulated logs from a "true"
//! robot ([`simulate`]). Charts are drawn by [`crate::report::svg`].

pub mod calibrate;
pub(crate) mod columns;
pub mod diagnose;
pub mod excite;
pub mod fit;
pub mod ladder;
pub mod log;
pub mod metrics;
pub mod model;
pub mod motion;
pub mod plausible;
pub(crate) mod profiles;
pub(crate) mod round;
pub mod simulate;
pub(crate) mod structure;

pub use log::{read_log, Log, SignalKind};
pub use model::{Model, Prepared, DEFAULT_EFFECTS};
pub use round::{read_log_for, run_round, switch_effects, RoundJob, RoundPlan, RoundResult};

/// An observer of a long run's progress (preparing a log, diagnosing): called with the stage
/// (`"preparing the log"`, `"diagnosing"`), the units of work done and their total (rows, or
/// fits). The library draws nothing; the binary shows a bar. Called at most a few hundred
/// times per stage, from the working thread.
pub trait Progress: Sync {
    /// `done` of `total` units of `stage` are finished.
    fn update(&self, stage: &str, done: u64, total: u64);
}

/// Progress that goes nowhere.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoProgress;

impl Progress for NoProgress {
    fn update(&self, _stage: &str, _done: u64, _total: u64) {}
}

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
