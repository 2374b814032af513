//! Repetition in a toolpath: layers that repeat up to a shift in z.
//!
//! A building-scale print is hundreds of layers of the same outline, each one layer height
//! above the last. [`layers`] cuts a path into *units*, one per print layer: a unit is the
//! travel that leads to a layer (retract, z hop, travel, whatever the slicer emits) plus the
//! layer's print moves. [`repetition`] finds the longest run of consecutive units in which
//! every unit equals the unit `period` before it shifted in z (same XY geometry, same kinds
//! of move, speeds, zones, print flags and dwells; float noise up to a tolerance in m). A
//! period of 2 is a wall whose seam alternates between two corners; the units of one *class*
//! (same index modulo the period) are then the same up to z.
//!
//! Units: lengths and tolerances in m, speeds in m/s, dwells in s (as in [`Toolpath`]).
//!
//! Limitations: only print moves at constant z define layers (a helical "vase" path has no
//! layers and never repeats); a layer whose outline changes (a taper, a window opening) ends
//! the run; straight runs within a layer are not reduced here.

use super::{MoveKind, Toolpath};
use std::ops::Range;

/// Default tolerance when comparing positions of repeated layers, m (1 µm: G-code written
/// with 4 decimals in mm is exact to 0.1 µm).
pub const REPEAT_TOLERANCE_M: f64 = 1e-6;

/// Largest repeat period tried (layers).
pub(crate) const MAX_PERIOD: usize = 4;

/// One unit of a path: the moves leading to a print layer and the layer's print moves.
#[derive(Clone, Debug, PartialEq)]
pub struct Unit {
    /// Toolpath move indices of the unit (the travel before the layer, then its print moves).
    pub moves: Range<usize>,
    /// Height of the layer's print moves in the part frame, m.
    pub z_m: f64,
}

/// Layers that repeat: the result of [`repetition`].
#[derive(Clone, Debug, PartialEq)]
pub struct Repetition {
    /// Every unit of the path, in order. Moves after the last unit (the final retract and
    /// lift) belong to no unit.
    pub units: Vec<Unit>,
    /// Units per repeat (1: every layer the same; 2: two alternating layers, …).
    pub period: usize,
    /// The repeating run, unit indices: for every `k` in `run.start + period .. run.end`, unit
    /// `k` equals unit `k - period` shifted in z.
    pub run: Range<usize>,
}

impl Repetition {
    /// The units of class `c` (`0..period`) in the run, in order.
    pub fn class(&self, c: usize) -> Vec<usize> {
        self.run
            .clone()
            .filter(|k| (k - self.run.start) % self.period == c)
            .collect()
    }
}

/// The print height of move `i` if it extrudes at constant z (a line with equal end
/// heights, or a planar arc), m.
fn print_level(path: &Toolpath, i: usize, tol: f64) -> Option<f64> {
    let m = &path.moves[i];
    if !m.print {
        return None;
    }
    let s = path.move_start(i);
    let flat = match m.kind {
        MoveKind::Line => (m.end.z - s.z).abs() <= tol,
        MoveKind::Arc { normal, axial, .. } => {
            axial.abs() <= tol && (normal.z.abs() - 1.0).abs() <= 1e-9
        }
    };
    // An extruder-only line (no distance) does not define a layer.
    (flat && m.length(&s) > 0.0).then_some(m.end.z)
}

/// Cut `path` into units, one per print layer (see the module docs). `tol` (m) tells z levels
/// apart. A path without constant-z print moves has no units.
pub fn layers(path: &Toolpath, tol: f64) -> Vec<Unit> {
    let mut units: Vec<Unit> = Vec::new();
    let mut start = 0;
    let mut level: Option<f64> = None;
    let mut last_print: Option<usize> = None;
    for i in 0..path.moves.len() {
        let Some(z) = print_level(path, i, tol) else {
            if path.moves[i].print {
                last_print = Some(i);
            }
            continue;
        };
        match level {
            Some(l) if (z - l).abs() > tol => {
                // A new layer: the previous unit ends at its last print move.
                let end = last_print.map_or(i, |p| p + 1);
                units.push(Unit {
                    moves: start..end,
                    z_m: l,
                });
                start = end;
                level = Some(z);
            }
            None => level = Some(z),
            _ => {}
        }
        last_print = Some(i);
    }
    if let (Some(l), Some(p)) = (level, last_print) {
        units.push(Unit {
            moves: start..p + 1,
            z_m: l,
        });
    }
    units
}

/// Does unit `b` equal unit `a` shifted by a constant z (within `tol` m)?
fn same_shifted(path: &Toolpath, a: &Unit, b: &Unit, tol: f64) -> bool {
    if a.moves.len() != b.moves.len() || a.moves.is_empty() {
        return false;
    }
    let dz = b.z_m - a.z_m;
    let near = |pa: &crate::math::V3, pb: &crate::math::V3| {
        (pb.x - pa.x).abs() <= tol && (pb.y - pa.y).abs() <= tol && (pb.z - pa.z - dz).abs() <= tol
    };
    let eq = |x: f64, y: f64| (x - y).abs() <= 1e-9 * x.abs().max(y.abs()).max(1.0);
    if !near(
        &path.move_start(a.moves.start),
        &path.move_start(b.moves.start),
    ) {
        return false;
    }
    for (i, j) in a.moves.clone().zip(b.moves.clone()) {
        let (ma, mb) = (&path.moves[i], &path.moves[j]);
        if ma.print != mb.print
            || !eq(ma.speed, mb.speed)
            || !eq(ma.zone.radius(), mb.zone.radius())
            || std::mem::discriminant(&ma.zone) != std::mem::discriminant(&mb.zone)
            || !near(&ma.end, &mb.end)
        {
            return false;
        }
        match (ma.kind, mb.kind) {
            (MoveKind::Line, MoveKind::Line) => {}
            (
                MoveKind::Arc {
                    centre: ca,
                    normal: na,
                    radius: ra,
                    sweep: sa,
                    axial: xa,
                },
                MoveKind::Arc {
                    centre: cb,
                    normal: nb,
                    radius: rb,
                    sweep: sb,
                    axial: xb,
                },
            ) => {
                if !near(&ca, &cb)
                    || (na - nb).norm() > 1e-9
                    || (ra - rb).abs() > tol
                    || (sa - sb).abs() > 1e-9
                    || (xa - xb).abs() > tol
                {
                    return false;
                }
            }
            _ => return false,
        }
    }
    // Dwells inside the units must correspond one to one.
    let dwells = |u: &Unit| -> Vec<(usize, f64)> {
        path.dwells
            .iter()
            .filter_map(|d| {
                let i = d.after_move?;
                u.moves.contains(&i).then(|| (i - u.moves.start, d.seconds))
            })
            .collect()
    };
    let (da, db) = (dwells(a), dwells(b));
    da.len() == db.len()
        && da
            .iter()
            .zip(&db)
            .all(|(x, y)| x.0 == y.0 && (x.1 - y.1).abs() <= 1e-9)
}

/// The longest run of units that repeat up to a shift in z, trying periods 1 to
/// [`MAX_PERIOD`] (the shortest period wins a tie). `None` when no unit repeats, or when the
/// layer heights within a class do not increase strictly (z is the interpolation abscissa of
/// [`crate::evaluate::reduce`]). `tol` in m (see [`REPEAT_TOLERANCE_M`]).
pub fn repetition(path: &Toolpath, tol: f64) -> Option<Repetition> {
    let units = layers(path, tol);
    let mut best: Option<(usize, Range<usize>)> = None;
    for period in 1..=MAX_PERIOD.min(units.len() / 2) {
        let mut k = period;
        while k < units.len() {
            if !same_shifted(path, &units[k - period], &units[k], tol)
                || units[k].z_m <= units[k - period].z_m + tol
            {
                k += 1;
                continue;
            }
            let start = k - period;
            while k < units.len()
                && same_shifted(path, &units[k - period], &units[k], tol)
                && units[k].z_m > units[k - period].z_m + tol
            {
                k += 1;
            }
            let run = start..k;
            if best.as_ref().is_none_or(|(_, r)| run.len() > r.len()) {
                best = Some((period, run));
            }
        }
    }
    let (period, run) = best?;
    // Every class needs at least two members to be a repeat.
    if run.len() < 2 * period {
        return None;
    }
    Some(Repetition { units, period, run })
}
