//! Placement tolerance: a recommended placement must stay feasible when the part (or the
//! robot base) sits a little off, as it will on a site. The placement is re-evaluated at the
//! corners of the tolerance box: x ± δxy, y ± δxy, z ± δz and yaw ± δyaw (16 corners); the
//! nozzle spin is programmed, not placed, and is not varied.
//!
//! [`check`] checks one placement on its own. A search that checks many placements uses a
//! [`Checker`]: it stops at the first infeasible corner, tries first the corner that failed
//! last, evaluates as many corners at once as the pool has threads, and never evaluates a
//! placement twice. What it reports does not depend on the thread count.

use crate::error::Result;
use crate::evaluate::evaluator::{Evaluated, Evaluator};
use crate::frame::Placement;
use serde::Serialize;
use std::cell::{Cell, RefCell};
use std::collections::{HashMap, HashSet};

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

impl Tolerance {
    /// Refuse a tolerance that is not a number >= 0 or is wider than 0.5 m or 45°.
    pub fn check(&self) -> crate::error::Result<()> {
        let ok = |v: f64, max: f64| v.is_finite() && (0.0..=max).contains(&v);
        if ok(self.xy_m, 0.5) && ok(self.z_m, 0.5) && ok(self.yaw_rad, 45f64.to_radians()) {
            Ok(())
        } else {
            Err(crate::error::Error::Invalid(format!(
                "tolerance ±{} m in x and y, ±{} m in z, ±{}° in yaw: expected numbers >= 0, at most 0.5 m and 45°",
                self.xy_m,
                self.z_m,
                self.yaw_rad.to_degrees()
            )))
        }
    }
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
    pub(crate) fn is_zero(&self) -> bool {
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
    /// stopped the check: see [`CORNER_BATCH`] for [`check`], [`Checker::check`] stops at the
    /// first infeasible corner; 0 for a zero tolerance).
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
pub(crate) const CORNER_BATCH: usize = 4;

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

/// Re-evaluate `at` at every one of the 16 corners of `tol` (in one parallel sweep, results in
/// corner order; deterministic, independent of the thread count), without stopping at the first
/// infeasible one: for a placement reported beside the answer (the baseline), whose check
/// says how many corners fail. A zero tolerance evaluates nothing and holds.
pub(crate) fn check_all(ev: &Evaluator, at: &Placement, tol: &Tolerance) -> Result<ToleranceCheck> {
    if tol.is_zero() {
        return Ok(summarise(tol, &[]));
    }
    let r = ev.sweep(&tol.corners(at), &|_, _| {})?;
    Ok(summarise(tol, &r))
}

/// Summarise evaluated corners (a check holds when all 16 were evaluated and are feasible, or
/// the tolerance is zero).
pub(crate) fn summarise(tol: &Tolerance, r: &[Evaluated]) -> ToleranceCheck {
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
        holds: failures.is_empty() && (r.len() == 16 || tol.is_zero()),
        failures,
        worst_j: costs.iter().copied().reduce(f64::max),
        best_j: costs.iter().copied().reduce(f64::min),
    }
}

/// A placement as a hash key: the bits of its five coordinates (two placements are the same
/// only when every coordinate is bit for bit the same).
fn key(p: &Placement) -> [u64; 5] {
    [
        p.x.to_bits(),
        p.y.to_bits(),
        p.z.to_bits(),
        p.yaw.to_bits(),
        p.nozzle_spin.to_bits(),
    ]
}

/// The tolerance checks (and the other single evaluations) of one search, made cheaply and
/// deterministically:
///
/// - a check stops at the **first infeasible corner** in its order (the answer, holds or not,
///   does not need the others); the order is [`Tolerance::corners`]' with the corner that
///   failed the last failing check moved to the front (a tolerance box that fails usually fails
///   on the same side again: toward a joint limit, into the bed);
/// - corners are evaluated as many at once as the current rayon pool has threads, each thread
///   taking the next corner in the order as soon as it is free ([`Evaluator::sweep_until`]);
///   the first infeasible corner abandons those after it where they stand, and one that
///   finished first was evaluated for nothing (on one thread there are none): it is counted as
///   speculative, never reported;
/// - every evaluation is kept by placement (bit for bit), so a placement is never evaluated
///   twice (two candidates that are the same point, a corner evaluated ahead of need).
///
/// The corners a check reports, its failures and the evaluation count are those of the
/// sequential check in this order, whatever the thread count.
///
/// [`Checker::plain`] checks as [`check`] does and evaluates every placement it is asked for
/// (the search as it was before this checker: the reference its tests compare with).
pub struct Checker<'e, 'j, 'a> {
    ev: &'e Evaluator<'j, 'a>,
    tol: Tolerance,
    /// [`Checker::plain`]: every check is [`check`], every evaluation made anew.
    plain: bool,
    /// Evaluations counted in plain mode.
    plain_count: Cell<usize>,
    /// Corner indices (of [`Tolerance::corners`]) in the order they are tried.
    order: RefCell<Vec<usize>>,
    /// Every evaluation made, by placement.
    cache: RefCell<HashMap<[u64; 5], Evaluated>>,
    /// Placements the checks and [`Checker::evaluate`] have used (each counted once).
    used: RefCell<HashSet<[u64; 5]>>,
    /// Evaluations made (used or not).
    made: Cell<usize>,
}

impl<'e, 'j, 'a> Checker<'e, 'j, 'a> {
    /// A checker of `tol` over `ev`'s placements.
    pub fn new(ev: &'e Evaluator<'j, 'a>, tol: Tolerance) -> Self {
        Checker {
            ev,
            tol,
            plain: false,
            plain_count: Cell::new(0),
            order: RefCell::new((0..16).collect()),
            cache: RefCell::new(HashMap::new()),
            used: RefCell::new(HashSet::new()),
            made: Cell::new(0),
        }
    }

    /// A checker that checks as [`check`] does (batches of [`CORNER_BATCH`] corners, stopping
    /// after the first batch with an infeasible corner, in the fixed order) and evaluates every
    /// placement anew each time it is asked for one, without evaluating ahead: the search
    /// before [`Checker::new`], kept as the reference the fast checks are tested against.
    pub fn plain(ev: &'e Evaluator<'j, 'a>, tol: Tolerance) -> Self {
        Checker {
            plain: true,
            ..Checker::new(ev, tol)
        }
    }

    /// The tolerance checked.
    pub fn tolerance(&self) -> &Tolerance {
        &self.tol
    }

    /// Evaluations used by the checks and [`Checker::evaluate`] (each placement once; in
    /// plain mode, every evaluation): the same for any thread count.
    pub fn evaluations(&self) -> usize {
        if self.plain {
            return self.plain_count.get();
        }
        self.used.borrow().len()
    }

    /// Evaluations made ahead of need and never used (0 on one thread and in plain mode).
    pub fn speculative(&self) -> usize {
        if self.plain {
            return 0;
        }
        self.made.get() - self.evaluations().min(self.made.get())
    }

    /// Evaluate the placements not evaluated yet (in parallel), and keep them.
    fn ensure(&self, ps: &[Placement]) -> Result<()> {
        let todo: Vec<Placement> = {
            let cache = self.cache.borrow();
            let mut seen = HashSet::new();
            ps.iter()
                .filter(|p| !cache.contains_key(&key(p)) && seen.insert(key(p)))
                .copied()
                .collect()
        };
        if todo.is_empty() {
            return Ok(());
        }
        let r = self.ev.sweep(&todo, &|_, _| {})?;
        self.made.set(self.made.get() + r.len());
        let mut cache = self.cache.borrow_mut();
        for e in r {
            cache.insert(key(&e.placement), e);
        }
        Ok(())
    }

    /// Take `p`'s evaluation as used (counted once) and return it.
    fn take(&self, p: &Placement) -> Evaluated {
        self.used.borrow_mut().insert(key(p));
        self.cache.borrow()[&key(p)].clone()
    }

    /// The corners of `at` in the order they are tried.
    fn ordered_corners(&self, at: &Placement) -> Vec<Placement> {
        let cs = self.tol.corners(at);
        self.order.borrow().iter().map(|&i| cs[i]).collect()
    }

    /// Evaluate `p` (counted); with `ahead`, the first corners of its tolerance box are
    /// evaluated in the same parallel batch, where a thread would otherwise wait (they are
    /// used only if `p` is then checked).
    pub fn evaluate(&self, p: &Placement, ahead: bool) -> Result<Evaluated> {
        if self.plain {
            self.plain_count.set(self.plain_count.get() + 1);
            return Ok(self.ev.sweep(&[*p], &|_, _| {})?.remove(0));
        }
        let width = rayon::current_num_threads().max(1);
        let mut batch = vec![*p];
        if ahead && !self.tol.is_zero() {
            batch.extend(self.ordered_corners(p).into_iter().take(width - 1));
        }
        self.ensure(&batch)?;
        Ok(self.take(p))
    }

    /// `e`, an evaluation made elsewhere (by [`Evaluator::sweep`] or [`Evaluator::evaluate`],
    /// bit for bit what this checker would make), taken as if [`Checker::evaluate`] had made
    /// it: counted once, kept, and returned (the kept one when this placement was evaluated
    /// before). In plain mode the placement is evaluated anew, as every plain evaluation is.
    pub fn adopt(&self, e: &Evaluated) -> Result<Evaluated> {
        if self.plain {
            return self.evaluate(&e.placement, false);
        }
        {
            let mut cache = self.cache.borrow_mut();
            if let std::collections::hash_map::Entry::Vacant(v) = cache.entry(key(&e.placement)) {
                v.insert(e.clone());
                self.made.set(self.made.get() + 1);
            }
        }
        Ok(self.take(&e.placement))
    }

    /// Check `at`'s tolerance box: the corners in this checker's order, as many at once as
    /// the pool has threads (no batch waits for its slowest corner), up to the first
    /// infeasible one, which abandons the corners under way after it.
    pub fn check(&self, at: &Placement) -> Result<ToleranceCheck> {
        if self.plain {
            let c = check(self.ev, at, &self.tol)?;
            self.plain_count.set(self.plain_count.get() + c.corners);
            return Ok(c);
        }
        if self.tol.is_zero() {
            return Ok(summarise(&self.tol, &[]));
        }
        let order = self.order.borrow().clone();
        let cs = self.tol.corners(at);
        // The corners not kept yet, in the check's order, up to the first kept infeasible one
        // (the check ends there): evaluated as many at once as the pool has threads, each
        // thread taking the next corner as it is free, until the first infeasible one in this
        // order, which abandons those after it.
        let todo: Vec<Placement> = {
            let cache = self.cache.borrow();
            let mut seen = HashSet::new();
            let mut v = Vec::new();
            for &i in &order {
                match cache.get(&key(&cs[i])) {
                    Some(e) if !e.cost().is_finite() => break,
                    Some(_) => {}
                    None => {
                        if seen.insert(key(&cs[i])) {
                            v.push(cs[i]);
                        }
                    }
                }
            }
            v
        };
        if !todo.is_empty() {
            let done = self.ev.sweep_until(&todo, &|e| !e.cost().is_finite())?;
            let mut cache = self.cache.borrow_mut();
            for e in done.into_iter().flatten() {
                self.made.set(self.made.get() + 1);
                cache.insert(key(&e.placement), e);
            }
        }
        // The check itself, in order, from the kept evaluations.
        let mut r = Vec::with_capacity(16);
        for &i in &order {
            let e = self.take(&cs[i]);
            let failed = !e.cost().is_finite();
            r.push(e);
            if failed {
                // Try this corner first next time.
                let mut o = self.order.borrow_mut();
                o.retain(|&j| j != i);
                o.insert(0, i);
                return Ok(summarise(&self.tol, &r));
            }
        }
        Ok(summarise(&self.tol, &r))
    }
}
