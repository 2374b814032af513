//! Placement tolerance: a recommended placement must stay feasible when the part (or the
//! robot base) sits a little off, as it will on a site. The placement is re-evaluated at the
//! corners of the tolerance box: x ± δxy, y ± δxy, z ± δz and yaw ± δyaw (16 corners); the
//! nozzle spin is programmed, not placed, and is not varied.

use super::sweep::{Evaluated, Evaluator};
use crate::error::Result;
use crate::placement::Placement;
use serde::Serialize;

/// The placement tolerance (half-widths of the box).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Tolerance {
    /// ± in x and y, m.
    pub xy_m: f64,
    /// ± in z, m.
    pub z_m: f64,
    /// ± in part yaw, rad.
    pub yaw_rad: f64,
}

impl Default for Tolerance {
    /// ±20 mm in x, y and z; ±1° in yaw.
    fn default() -> Self {
        Tolerance {
            xy_m: 0.02,
            z_m: 0.02,
            yaw_rad: 1f64.to_radians(),
        }
    }
}

impl Tolerance {
    /// No tolerance: nothing to check.
    pub fn is_zero(&self) -> bool {
        self.xy_m == 0.0 && self.z_m == 0.0 && self.yaw_rad == 0.0
    }

    /// The 16 corners of the tolerance box around `p` (x fastest, then y, z, yaw).
    pub fn corners(&self, p: &Placement) -> Vec<Placement> {
        let mut v = Vec::with_capacity(16);
        for sa in [-1.0, 1.0] {
            for sz in [-1.0, 1.0] {
                for sy in [-1.0, 1.0] {
                    for sx in [-1.0, 1.0] {
                        v.push(Placement {
                            x: p.x + sx * self.xy_m,
                            y: p.y + sy * self.xy_m,
                            z: p.z + sz * self.z_m,
                            yaw: p.yaw + sa * self.yaw_rad,
                            nozzle_spin: p.nozzle_spin,
                        });
                    }
                }
            }
        }
        v
    }

    /// One line for reports: "±20 mm (x, y, z), ±1.0° (yaw)".
    pub fn describe(&self) -> String {
        format!(
            "±{:.0} mm in x and y, ±{:.0} mm in z, ±{:.1}° in yaw",
            self.xy_m * 1000.0,
            self.z_m * 1000.0,
            self.yaw_rad.to_degrees()
        )
    }
}

/// The outcome of re-evaluating a placement at its tolerance corners.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ToleranceCheck {
    /// The tolerance checked.
    pub tolerance: Tolerance,
    /// Corners evaluated (16 when the tolerance holds; fewer when an infeasible corner
    /// stopped the check, see [`CORNER_BATCH`]; 0 for a zero tolerance).
    pub corners: usize,
    /// Corners that are infeasible, with the reason (as printed).
    pub failures: Vec<String>,
    /// True when every corner is feasible.
    pub holds: bool,
    /// Highest objective energy over the corners, J (`None` if none is feasible or no corner).
    pub worst_j: Option<f64>,
    /// Lowest objective energy over the corners, J.
    pub best_j: Option<f64>,
}

/// Corners are evaluated in batches of this many (in parallel within a batch); the check stops
/// after the first batch with an infeasible corner. The batches are fixed, so what is
/// evaluated does not depend on the thread count.
pub const CORNER_BATCH: usize = 4;

/// Re-evaluate `at` at the corners of `tol` (in parallel batches, in order; deterministic),
/// stopping after the first batch that has an infeasible corner.
pub fn check(ev: &Evaluator, at: &Placement, tol: &Tolerance) -> Result<ToleranceCheck> {
    if tol.is_zero() {
        return Ok(ToleranceCheck {
            tolerance: *tol,
            corners: 0,
            failures: Vec::new(),
            holds: true,
            worst_j: None,
            best_j: None,
        });
    }
    let cs = tol.corners(at);
    let mut r = Vec::with_capacity(cs.len());
    for batch in cs.chunks(CORNER_BATCH) {
        let b = ev.sweep(batch, &|_, _| {})?;
        let failed = b.iter().any(|e| !e.cost().is_finite());
        r.extend(b);
        if failed {
            break;
        }
    }
    Ok(summarise(tol, &r))
}

/// Summarise evaluated corners (a check holds when all 16 were evaluated and are feasible).
pub fn summarise(tol: &Tolerance, r: &[Evaluated]) -> ToleranceCheck {
    let failures: Vec<String> = r
        .iter()
        .filter_map(|e| e.outcome.as_ref().err().map(|x| x.to_string()))
        .collect();
    let costs: Vec<f64> = r
        .iter()
        .map(Evaluated::cost)
        .filter(|c| c.is_finite())
        .collect();
    ToleranceCheck {
        tolerance: *tol,
        corners: r.len(),
        holds: failures.is_empty() && r.len() == 16,
        failures,
        worst_j: costs.iter().copied().reduce(f64::max),
        best_j: costs.iter().copied().reduce(f64::min),
    }
}
