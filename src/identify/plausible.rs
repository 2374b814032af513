//! Physical plausibility of every effect's fitted values (docs/effects.md, "Plausibility"):
//! a fit no physical robot has is reported with the reason, is not written as the calibrated
//! robot by `identify` and is not claimed by `diagnose`. Each effect states its own rule in
//! its file ([`crate::effects::Effect::implausible_fit`]), with the limits and helpers the
//! rules share beside the effects (`crate::effects::plausible`); this module holds the driver
//! ([`implausible_fit`]).

use crate::identify::model::Model;

pub(crate) use crate::effects::plausible::payload_written;

/// Why the current (fitted) values of effect `name` are not physically plausible for the
/// robot of `model`, given each value's standard error (`None`: held or not identifiable), or
/// `None` when they are: each effect's own rule ([`crate::effects::Effect::implausible_fit`]).
pub fn implausible_fit(model: &Model, name: &str, std_errors: &[Option<f64>]) -> Option<String> {
    model.implausible_fit(name, std_errors)
}
