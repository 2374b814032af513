//! The speed profile along the path, as an industrial controller runs it: the commanded speed
//! on each move, slower where the path bends (lateral acceleration limit), stops at fine points
//! and at both ends, acceleration-limited ramps (forward–backward pass over the path), then a
//! moving-average (FIR) filter of length `a_max / j_max` on the interpolated positions, the way
//! controllers limit jerk: it turns the trapezoidal speed profile into a jerk-limited S-curve
//! and makes the acceleration continuous through corners and arc entries, at the price of a
//! small, measured deviation from the programmed path in curves.

use super::geometry::Piece;
use crate::math::V3;

/// Limits and resolution of the Cartesian profile. SI units.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ProfileOptions {
    /// Tangential acceleration limit of the TCP, m/s².
    pub accel: f64,
    /// Lateral (centripetal) acceleration limit of the TCP in curves, m/s².
    pub lateral_accel: f64,
    /// Jerk limit of the TCP, m/s³ (sets the FIR filter length `accel / jerk`).
    pub jerk: f64,
    /// Interpolation and output period, s (controllers: 2–12 ms).
    pub dt: f64,
    /// Path discretisation for the speed profile, m.
    pub ds: f64,
}

impl Default for ProfileOptions {
    fn default() -> Self {
        ProfileOptions {
            accel: 1.0,
            lateral_accel: 1.0,
            jerk: 10.0,
            dt: 0.004,
            ds: 0.001,
        }
    }
}

/// Nodes of the path where the speed limit is evaluated.
#[derive(Clone, Debug, Default)]
pub struct Nodes {
    /// Arc length, m.
    pub s: Vec<f64>,
    /// Index of the piece the node starts (the last piece for the final node).
    pub piece: Vec<usize>,
    /// Speed cap from the commanded speed, curvature and stops, m/s.
    pub cap: Vec<f64>,
    /// Time held at rest at each node before leaving it (dwells), s; empty when the path has
    /// no dwells (then 0 everywhere).
    pub dwell: Vec<f64>,
}

impl Nodes {
    /// Total time held at rest at the nodes (dwells), s.
    pub(crate) fn dwell_total(&self) -> f64 {
        self.dwell.iter().sum()
    }
}

/// Start arc length of each piece, m (one more entry: the total length).
pub(crate) fn piece_starts(pieces: &[Piece]) -> Vec<f64> {
    let mut out = Vec::with_capacity(pieces.len() + 1);
    let mut acc = 0.0;
    out.push(0.0);
    for p in pieces {
        acc += p.prim.length();
        out.push(acc);
    }
    out
}

/// Evaluate the speed caps at nodes no more than `opts.ds` apart.
pub fn nodes(pieces: &[Piece], opts: &ProfileOptions) -> Nodes {
    let mut n = Nodes::default();
    // (node, seconds) of the dwells.
    let mut dwells: Vec<(usize, f64)> = Vec::new();
    let mut s0 = 0.0;
    for (k, p) in pieces.iter().enumerate() {
        let len = p.prim.length();
        let m = ((len / opts.ds).ceil() as usize).max(1);
        for i in 0..m {
            let ls = len * i as f64 / m as f64;
            let kappa = p.prim.curvature(ls);
            let mut cap = p.speed;
            if kappa > 1e-12 {
                cap = cap.min((opts.lateral_accel / kappa).sqrt());
            }
            if i == 0 {
                if k == 0 {
                    cap = 0.0;
                    if p.dwell_before > 0.0 {
                        dwells.push((n.s.len(), p.dwell_before));
                    }
                } else {
                    let prev = &pieces[k - 1];
                    cap = cap.min(prev.speed);
                    if prev.stop_after || prev.dwell_after > 0.0 {
                        cap = 0.0;
                    }
                    if prev.dwell_after > 0.0 {
                        dwells.push((n.s.len(), prev.dwell_after));
                    }
                }
            }
            n.s.push(s0 + ls);
            n.piece.push(k);
            n.cap.push(cap);
        }
        s0 += len;
    }
    if let Some(last) = pieces.last() {
        if last.dwell_after > 0.0 {
            dwells.push((n.s.len(), last.dwell_after));
        }
    }
    n.s.push(s0);
    n.piece.push(pieces.len().saturating_sub(1));
    n.cap.push(0.0);
    if !dwells.is_empty() {
        n.dwell = vec![0.0; n.s.len()];
        for (i, t) in dwells {
            n.dwell[i] += t;
        }
    }
    n
}

/// Acceleration-limited speed at each node under the caps (times `scale`, per node), m/s.
pub(crate) fn speed_at_nodes(nodes: &Nodes, scale: &[f64], accel: f64) -> Vec<f64> {
    speed_at_nodes_local(nodes, scale, accel, &[])
}

/// [`speed_at_nodes`] with the acceleration lowered locally: the ramp between nodes `i − 1`
/// and `i` is limited to `accel · min(accel_scale[i − 1], accel_scale[i])` (m/s²; an empty
/// `accel_scale` is 1 everywhere). This is how the controller lowers the acceleration over
/// a stretch of path only: the speed stays continuous, ramps elsewhere keep `accel`, and the
/// jerk filter (its length set by the global `accel / jerk`) blends the change of
/// acceleration at the stretch's ends.
pub(crate) fn speed_at_nodes_local(
    nodes: &Nodes,
    scale: &[f64],
    accel: f64,
    accel_scale: &[f64],
) -> Vec<f64> {
    let n = nodes.s.len();
    let mut v: Vec<f64> = (0..n).map(|i| nodes.cap[i] * scale[i]).collect();
    let local = accel_scale.len() == n;
    let a = |i: usize| {
        if local {
            accel * accel_scale[i - 1].min(accel_scale[i])
        } else {
            accel
        }
    };
    for i in 1..n {
        let ds = nodes.s[i] - nodes.s[i - 1];
        v[i] = v[i].min((v[i - 1] * v[i - 1] + 2.0 * a(i) * ds).sqrt());
    }
    for i in (0..n - 1).rev() {
        let ds = nodes.s[i + 1] - nodes.s[i];
        v[i] = v[i].min((v[i + 1] * v[i + 1] + 2.0 * a(i + 1) * ds).sqrt());
    }
    v
}

/// Uniform-time samples of arc length `s(t)` (m) for node speeds `v`, constant acceleration
/// between nodes, period `dt`. The path is held at rest at node `i` for `nodes.dwell[i]`.
pub(crate) fn sample_arc_length(nodes: &Nodes, v: &[f64], dt: f64) -> Vec<f64> {
    let n = nodes.s.len();
    // Arrival time `ta` and leaving time `tl` at each node (equal without dwells).
    let mut ta = vec![0.0; n];
    let has_dwell = nodes.dwell.len() == n;
    let mut tl = if has_dwell {
        let mut t = vec![0.0; n];
        t[0] = nodes.dwell[0];
        t
    } else {
        Vec::new()
    };
    for i in 1..n {
        let ds = nodes.s[i] - nodes.s[i - 1];
        let vs = v[i] + v[i - 1];
        let t_prev = if has_dwell { tl[i - 1] } else { ta[i - 1] };
        ta[i] = t_prev + if vs > 0.0 { 2.0 * ds / vs } else { 0.0 };
        if has_dwell {
            tl[i] = ta[i] + nodes.dwell[i];
        }
    }
    let tl: &[f64] = if has_dwell { &tl } else { &ta };
    let total = tl[n - 1];
    let steps = (total / dt).ceil() as usize;
    let mut out = Vec::with_capacity(steps + 1);
    let mut i = 1;
    for k in 0..=steps {
        let t = (k as f64 * dt).min(total);
        while i < n - 1 && tl[i] < t {
            i += 1;
        }
        let (t0, t1) = (tl[i - 1], ta[i]);
        let ds = nodes.s[i] - nodes.s[i - 1];
        let s = if has_dwell && t >= t1 {
            nodes.s[i] // arrived (and held there during a dwell)
        } else if has_dwell && t <= t0 {
            nodes.s[i - 1] // still held at the previous node
        } else if t1 > t0 {
            let tau = t - t0;
            let a = (v[i] * v[i] - v[i - 1] * v[i - 1]) / (2.0 * ds);
            (nodes.s[i - 1] + v[i - 1] * tau + 0.5 * a * tau * tau)
                .max(nodes.s[i - 1])
                .min(nodes.s[i]) // NaN-safe, unlike clamp
        } else {
            nodes.s[i]
        };
        out.push(s);
    }
    out
}

/// Moving average of length `taps` over a padded sequence (the first and last values are
/// held), output length `len + taps − 1`. Applied to positions, it limits jerk.
pub(crate) fn box_filter<T>(x: &[T], taps: usize) -> Vec<T>
where
    T: Copy
        + std::ops::Add<Output = T>
        + std::ops::Sub<Output = T>
        + std::ops::Mul<f64, Output = T>,
{
    if taps <= 1 || x.is_empty() {
        return x.to_vec();
    }
    let n = x.len();
    let first = x[0];
    let last = x[n - 1];
    let get = |i: isize| -> T {
        if i < 0 {
            first
        } else if i as usize >= n {
            last
        } else {
            x[i as usize]
        }
    };
    let out_len = n + taps - 1;
    let mut out = Vec::with_capacity(out_len);
    // Running sum over the window [k - taps + 1, k]; restarted every 1024 samples to bound
    // rounding drift.
    let inv = 1.0 / taps as f64;
    let mut sum = first * 0.0;
    for j in 0..taps as isize {
        sum = sum + get(j - taps as isize + 1);
    }
    for k in 0..out_len as isize {
        if k > 0 {
            sum = sum + get(k) - get(k - taps as isize);
            if k % 1024 == 0 {
                let mut fresh = first * 0.0;
                for j in (k - taps as isize + 1)..=k {
                    fresh = fresh + get(j);
                }
                sum = fresh;
            }
        }
        out.push(sum * inv);
    }
    out
}

/// The Cartesian motion of the TCP in the part frame at a uniform period.
#[derive(Clone, Debug, Default)]
pub struct CartesianMotion {
    /// Period, s.
    pub dt: f64,
    /// TCP position per sample, part frame, m (after the jerk filter).
    pub p: Vec<V3>,
    /// Arc length per sample after the filter, m (a smoothed progress measure).
    pub s: Vec<f64>,
    /// Whether the sample lies on a print (extruding) piece.
    pub print: Vec<bool>,
    /// Piece index per sample.
    pub piece: Vec<usize>,
    /// Filter length, samples.
    pub taps: usize,
}

impl CartesianMotion {
    /// Duration, s.
    pub fn duration(&self) -> f64 {
        self.dt * self.p.len().saturating_sub(1) as f64
    }
}

/// Plan the Cartesian motion along `pieces` with per-node speed `scale` (1 = no slow-down).
pub fn plan(
    pieces: &[Piece],
    nodes: &Nodes,
    scale: &[f64],
    opts: &ProfileOptions,
) -> CartesianMotion {
    let v = speed_at_nodes(nodes, scale, opts.accel);
    plan_at_speeds(pieces, nodes, &v, opts)
}

/// Plan the Cartesian motion along `pieces` through the node speeds `v` (m/s, from
/// [`speed_at_nodes`] or [`speed_at_nodes_local`]).
pub(crate) fn plan_at_speeds(
    pieces: &[Piece],
    nodes: &Nodes,
    v: &[f64],
    opts: &ProfileOptions,
) -> CartesianMotion {
    let s_raw = sample_arc_length(nodes, v, opts.dt);
    let starts = piece_starts(pieces);
    let taps = ((opts.accel / opts.jerk / opts.dt).round() as usize).max(1);
    let piece_of = |s: f64| {
        starts
            .partition_point(|&x| x <= s)
            .saturating_sub(1)
            .min(pieces.len() - 1)
    };
    let point_at = |s: f64| {
        let k = piece_of(s);
        pieces[k].prim.point(s - starts[k])
    };
    // Each unfiltered series let go once filtered (a long path's are tens of megabytes).
    let p_raw: Vec<V3> = s_raw.iter().map(|&s| point_at(s)).collect();
    let p = box_filter(&p_raw, taps);
    drop(p_raw);
    let s = box_filter(&s_raw, taps);
    drop(s_raw);
    let piece: Vec<usize> = s.iter().map(|&x| piece_of(x)).collect();
    let print = piece.iter().map(|&k| pieces[k].print).collect();
    CartesianMotion {
        dt: opts.dt,
        p,
        s,
        print,
        piece,
        taps,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::timing::geometry::{blend_path, Move, Prim};

    fn square(zone: f64, speed: f64) -> Vec<Move> {
        let c = [
            V3::new(0.0, 0.0, 0.0),
            V3::new(0.5, 0.0, 0.0),
            V3::new(0.5, 0.3, 0.0),
            V3::new(0.0, 0.3, 0.0),
            V3::new(0.0, 0.0, 0.0),
        ];
        c.windows(2)
            .enumerate()
            .map(|(i, w)| Move {
                prim: Prim::Line { a: w[0], b: w[1] },
                speed,
                zone,
                print: true,
                line: i + 1,
            })
            .collect()
    }

    #[test]
    fn straight_segments_hold_speed_and_blends_stay_in_zone() {
        let moves = square(0.01, 0.2);
        let pieces = blend_path(&moves);
        assert_eq!(pieces.len(), 7, "4 lines + 3 blends");
        let opts = ProfileOptions::default();
        let nodes = nodes(&pieces, &opts);
        let scale = vec![1.0; nodes.s.len()];
        let m = plan(&pieces, &nodes, &scale, &opts);
        // Speed on the middle of the first straight (x from 0.15 to 0.35 m).
        let mut checked = 0;
        for k in 1..m.p.len() - 1 {
            let x = m.p[k].x;
            if m.p[k].y.abs() < 1e-12 && x > 0.15 && x < 0.35 {
                let v = (m.p[k + 1] - m.p[k - 1]).norm() / (2.0 * m.dt);
                assert!((v - 0.2).abs() < 0.002, "speed {v} at x = {x}");
                checked += 1;
            }
        }
        assert!(checked > 100, "{checked}");
        // Every sample near a corner stays within the zone sphere of that corner.
        let corners = [
            V3::new(0.5, 0.0, 0.0),
            V3::new(0.5, 0.3, 0.0),
            V3::new(0.0, 0.3, 0.0),
        ];
        for p in &m.p {
            for c in &corners {
                let d = (p - c).norm();
                if d < 0.01 {
                    // Inside the zone: must be inside the square's corner region (not overshooting).
                    assert!(
                        p.x <= 0.5 + 1e-9 && p.y <= 0.3 + 1e-9 && p.x >= -1e-9,
                        "{p:?}"
                    );
                }
            }
        }
        // Continuity of acceleration: second differences change by a bounded amount per step.
        let acc: Vec<V3> = (1..m.p.len() - 1)
            .map(|k| (m.p[k + 1] - m.p[k] * 2.0 + m.p[k - 1]) / (m.dt * m.dt))
            .collect();
        let max_jump = acc
            .windows(2)
            .map(|w| (w[1] - w[0]).norm())
            .fold(0.0, f64::max);
        let max_acc = acc.iter().map(|a| a.norm()).fold(0.0, f64::max);
        assert!(
            max_acc <= opts.accel.max(opts.lateral_accel) * 1.5,
            "max acc {max_acc}"
        );
        // Jerk limit: |Δa|/dt bounded by a few times the jerk limit (lateral + tangential combine).
        assert!(
            max_jump / m.dt < 3.0 * opts.jerk,
            "jerk {}",
            max_jump / m.dt
        );
        // Starts and ends at rest.
        assert!(
            (m.p[1] - m.p[0]).norm() < 1e-6
                && (m.p[m.p.len() - 1] - m.p[m.p.len() - 2]).norm() < 1e-6
        );
    }

    #[test]
    fn box_filter_preserves_constant_velocity() {
        let x: Vec<f64> = (0..100).map(|k| k as f64 * 0.1).collect();
        let y = box_filter(&x, 5);
        for k in 10..90 {
            assert!(((y[k + 1] - y[k]) - 0.1).abs() < 1e-12);
        }
    }
}
