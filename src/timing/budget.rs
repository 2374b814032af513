//! Budgets instead of crashes: before a path is planned, the samples and memory it needs are
//! estimated from its length, speeds, the acceleration and jerk limits and the interpolation
//! period, and a path beyond the budget is refused with an error that names the likely cause
//! (`F1.5` meant as `F1500`, a speed in m/s written as mm/s, a 100 km move, a period in µs).
//!
//! The estimate is a lower bound of what planning allocates: the time is at least the sum of
//! `length / speed` over the moves and at least `2 √(L / a)` (accelerating over the whole path
//! and back), plus the dwells (`G4` holds), the samples are that time over the period plus the
//! jerk filter's length
//! `a / (j · dt)`, the speed nodes are the path length over the node spacing.

use super::geometry::Move;
use super::profile::ProfileOptions;
use crate::error::{Error, Result};

/// Environment variable that sets the sample budget (default [`DEFAULT_MAX_SAMPLES`]).
pub const MAX_SAMPLES_ENV: &str = "PRINTWATT_MAX_SAMPLES";

/// Default budget of samples of one timed path: 5 million, i.e. 5.5 h of motion at the default
/// 4 ms period, about 6.6 GB for a 6-axis arm when the whole per-sample series is kept (see
/// [`bytes_per_sample`]).
pub(crate) const DEFAULT_MAX_SAMPLES: usize = 5_000_000;

/// The sample budget: `$PRINTWATT_MAX_SAMPLES` when set to a positive integer, else
/// [`DEFAULT_MAX_SAMPLES`].
pub fn max_samples() -> usize {
    std::env::var(MAX_SAMPLES_ENV)
        .ok()
        .and_then(|s| s.trim().parse::<usize>().ok())
        .filter(|&n| n > 0)
        .unwrap_or(DEFAULT_MAX_SAMPLES)
}

/// Peak bytes per sample of a timed path of an `n`-joint arm when its whole per-sample series
/// is kept (`printwatt energy`: the Cartesian motion, joint positions, velocities,
/// accelerations, their sines and cosines, TCP points, the planner's working vectors and the
/// energy series), measured as the peak resident memory of the whole command over the samples
/// on long prints: about 1.3 KB a sample for a 6-axis arm, 300 + 170·n. The measurement is a
/// test (`the_sample_budget_states_the_memory_it_measures`).
pub fn bytes_per_sample(n: usize) -> usize {
    300 + 170 * n
}

/// What planning a path will need.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// Lower bound of the motion's duration, s.
    pub duration_s: f64,
    /// Samples at the period (plus the jerk filter's length).
    pub samples: f64,
    /// Speed-profile nodes.
    pub nodes: f64,
    /// Memory, bytes.
    pub bytes: f64,
    /// Index of the move that takes the most time.
    pub slowest: usize,
}

/// Estimate what planning `moves` with `popts` needs for an `n`-joint arm.
pub fn estimate(moves: &[Move], popts: &ProfileOptions, n: usize) -> Estimate {
    estimate_with_dwell(moves, 0.0, popts, n)
}

/// [`estimate`] with `dwell_s` seconds of dwells (holds at rest) on the path.
pub(crate) fn estimate_with_dwell(
    moves: &[Move],
    dwell_s: f64,
    popts: &ProfileOptions,
    n: usize,
) -> Estimate {
    let mut t = 0.0;
    let mut length = 0.0;
    let mut slowest = (0, 0.0);
    for (i, m) in moves.iter().enumerate() {
        let len = m.prim.length();
        let ti = len / m.speed;
        if ti > slowest.1 || ti.is_nan() {
            slowest = (i, if ti.is_nan() { f64::INFINITY } else { ti });
        }
        t += ti;
        length += len;
    }
    let t = t.max(2.0 * (length / popts.accel).sqrt()) + dwell_s;
    let taps = popts.accel / popts.jerk / popts.dt;
    let samples = t / popts.dt + taps;
    let nodes = length / popts.ds + moves.len() as f64;
    let bytes = samples * bytes_per_sample(n) as f64 + nodes * 48.0;
    Estimate {
        duration_s: t,
        samples: if samples.is_nan() {
            f64::INFINITY
        } else {
            samples
        },
        nodes: if nodes.is_nan() { f64::INFINITY } else { nodes },
        bytes,
        slowest: slowest.0,
    }
}

/// Refuse a path whose planning would exceed the sample budget ([`max_samples`]); the error
/// names `source`, the estimate and the likely cause.
/// `dwell_s`: the total of the path's dwells (holds at rest), s.
pub fn check(
    moves: &[Move],
    dwell_s: f64,
    popts: &ProfileOptions,
    n: usize,
    source: &str,
) -> Result<()> {
    check_inputs(moves, popts, source)?;
    let max = max_samples() as f64;
    let e = estimate_with_dwell(moves, dwell_s, popts, n);
    if dwell_s / popts.dt > max || dwell_s.is_nan() {
        return Err(Error::Invalid(format!(
            "{source}: the dwells (G4) add up to {dwell_s} s: {} samples at the {} s period, \
             more than the {} samples the planner allows; shorten the dwells",
            dwell_s / popts.dt,
            popts.dt,
            max_samples()
        )));
    }
    if e.samples <= max && e.nodes <= 2.0 * max {
        return Ok(());
    }
    let cause = likely_cause(moves, popts, &e, max, source);
    Err(Error::Invalid(format!(
        "{source}: timing this path would take at least {:.3e} s of motion, {:.3e} samples at {} ms (~{:.1} GB), more than the budget of {} samples ({MAX_SAMPLES_ENV}): {cause}",
        e.duration_s,
        e.samples,
        popts.dt * 1e3,
        e.bytes / 1e9,
        max as usize
    )))
}

/// The interpolation settings and every move's speed must be finite and positive; the error
/// names `source` (and the move's line).
fn check_inputs(moves: &[Move], popts: &ProfileOptions, source: &str) -> Result<()> {
    for (what, v, unit) in [
        ("interpolation period", popts.dt, "s"),
        ("TCP acceleration limit", popts.accel, "m/s²"),
        (
            "TCP lateral acceleration limit",
            popts.lateral_accel,
            "m/s²",
        ),
        ("TCP jerk limit", popts.jerk, "m/s³"),
        ("path node spacing", popts.ds, "m"),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::Invalid(format!(
                "{source}: the {what} must be finite and > 0, got {v} {unit}"
            )));
        }
    }
    for m in moves {
        if !(m.speed.is_finite() && m.speed > 0.0) {
            return Err(Error::Invalid(format!(
                "{source}:{}: the move's speed must be finite and > 0, got {} m/s",
                m.line, m.speed
            )));
        }
    }
    Ok(())
}

/// The likely cause of a path over the sample budget, for the error: a controller period far
/// too short, a speed slower than any print (a unit slip), a move far too long, a tiny jerk or
/// acceleration limit, or a path that simply is long. `e` is the path's estimate.
fn likely_cause(
    moves: &[Move],
    popts: &ProfileOptions,
    e: &Estimate,
    max: f64,
    source: &str,
) -> String {
    let m = &moves[e.slowest.min(moves.len().saturating_sub(1))];
    let len = m.prim.length();
    let v_mm_s = m.speed * 1e3;
    let ext = std::path::Path::new(source)
        .extension()
        .map(|x| x.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let gcode = matches!(ext.as_str(), "gcode" | "nc" | "ngc" | "g");
    if popts.dt < 1e-4 {
        format!(
            "the interpolation period {} ms is far shorter than a controller's (0.5–12 ms)",
            popts.dt * 1e3
        )
    } else if m.speed < 1e-3 {
        let speed = if gcode {
            let f = m.speed * 60e3;
            format!(
                "F{} mm/min is {} mm/s; did you mean F{}?",
                fmt_num(f),
                fmt_num(v_mm_s),
                fmt_num(f * 1e3)
            )
        } else {
            format!(
                "{} mm/s is slower than any print; did you mean {} mm/s?",
                fmt_num(v_mm_s),
                fmt_num(v_mm_s * 1e3)
            )
        };
        format!(
            "the move on line {} ({:.3} m) is commanded at {speed}",
            m.line, len
        )
    } else if len > 1e3 || !len.is_finite() {
        format!(
            "the move on line {} is {:.3e} m long: check the coordinates and their unit (mm, m, inch)",
            m.line, len
        )
    } else if popts.accel / popts.jerk / popts.dt > 0.5 * max {
        format!(
            "the jerk limit {} m/s³ is tiny against the acceleration limit {} m/s² (the jerk filter alone is {:.3e} samples)",
            popts.jerk,
            popts.accel,
            popts.accel / popts.jerk / popts.dt
        )
    } else if e.duration_s > 2.0 * moves.iter().map(|m| m.prim.length() / m.speed).sum::<f64>() {
        format!(
            "the acceleration limit {} m/s² is tiny: ramps alone take {:.3e} s",
            popts.accel, e.duration_s
        )
    } else {
        format!(
            "the path simply is long: the slowest move is line {} ({:.3} m at {} mm/s); time it in parts or raise the budget",
            m.line,
            len,
            fmt_num(v_mm_s)
        )
    }
}

/// A number as a person writes it: up to 6 significant digits, no trailing zeros.
fn fmt_num(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    if x != 0.0 && (x.abs() >= 1e9 || x.abs() < 1e-4) {
        return format!("{x:.3e}");
    }
    let s = format!("{x:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::V3;
    use crate::timing::geometry::Prim;

    fn line(len: f64, speed: f64) -> Move {
        Move {
            prim: Prim::Line {
                a: V3::zeros(),
                b: V3::new(len, 0.0, 0.0),
            },
            speed,
            zone: 0.0,
            print: true,
            line: 3,
        }
    }

    #[test]
    fn a_slow_feed_is_named_with_a_did_you_mean() {
        let e = check(
            &[line(1.0, 0.025e-3)],
            0.0,
            &ProfileOptions::default(),
            6,
            "a.gcode",
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("F1.5 mm/min is 0.025 mm/s; did you mean F1500?"),
            "{e}"
        );
        assert!(e.starts_with("a.gcode:"), "{e}");
    }

    #[test]
    fn an_ordinary_path_passes() {
        check(
            &[line(5.8, 0.15)],
            0.0,
            &ProfileOptions::default(),
            6,
            "a.gcode",
        )
        .unwrap();
        let est = estimate(&[line(5.8, 0.15)], &ProfileOptions::default(), 6);
        assert!((est.duration_s - 5.8 / 0.15).abs() < 1e-9);
    }
}
