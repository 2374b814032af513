//! The geometric path a controller follows: lines and arcs as programmed, with each corner
//! that has a zone replaced by a blend curve that stays inside the zone. Positions in m.

use crate::math::V3;

/// Tangent-angle change (rad) below which a junction counts as smooth (no blend, no stop).
pub(crate) const SMOOTH_JUNCTION_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// One primitive of the geometric path.
#[derive(Clone, Copy, Debug, PartialEq)]
// Pieces live in one Vec per path; boxing the blend table would cost an indirection per
// evaluation in the hot sampling loop for no real saving.
#[allow(clippy::large_enum_variant)]
pub enum Prim {
    /// Straight line from `a` to `b`, m.
    Line {
        /// Start, m.
        a: V3,
        /// End, m.
        b: V3,
    },
    /// Circular arc (optionally helical): `p(θ) = centre + r (cos θ u + sin θ w) + rise · θ/sweep`
    /// for θ in [0, sweep]; `u`, `w` orthonormal, `w` the direction of motion at the start.
    Arc {
        /// Centre, m.
        centre: V3,
        /// Unit vector from the centre to the start point.
        u: V3,
        /// Unit vector of the direction of motion at the start.
        w: V3,
        /// Radius, m.
        radius: f64,
        /// Swept angle, rad.
        sweep: f64,
        /// Axial displacement over the whole arc (helix), m.
        rise: V3,
    },
    /// Cubic Bézier blend with control points `p` (m), parameterised by arc length through a
    /// table of `BLEND_TABLE` entries.
    Blend {
        /// Control points, m.
        p: [V3; 4],
        /// Arc length at evenly spaced curve parameters, m.
        table: [f64; BLEND_TABLE],
    },
}

/// Number of arc-length table entries of a blend.
pub(crate) const BLEND_TABLE: usize = 33;

fn bezier(p: &[V3; 4], u: f64) -> V3 {
    let v = 1.0 - u;
    p[0] * (v * v * v) + p[1] * (3.0 * v * v * u) + p[2] * (3.0 * v * u * u) + p[3] * (u * u * u)
}

fn bezier_d(p: &[V3; 4], u: f64) -> V3 {
    let v = 1.0 - u;
    (p[1] - p[0]) * (3.0 * v * v) + (p[2] - p[1]) * (6.0 * v * u) + (p[3] - p[2]) * (3.0 * u * u)
}

impl Prim {
    /// A blend from `p0` (tangent `ta`) to `p3` (tangent `tb`) whose control polygon reaches
    /// `2d/3` along each tangent: for two lines meeting at a corner this is the parabola through
    /// the zone entry and exit points with the corner as its control point.
    pub fn blend(p0: V3, ta: V3, p3: V3, tb: V3, d: f64) -> Prim {
        let p = [p0, p0 + ta * (2.0 * d / 3.0), p3 - tb * (2.0 * d / 3.0), p3];
        // Cumulative arc length at u = k/(BLEND_TABLE-1), by 5-point Gauss–Legendre per interval.
        let mut table = [0.0; BLEND_TABLE];
        let gx = [
            0.0,
            -0.538_469_310_105_683,
            0.538_469_310_105_683,
            -0.906_179_845_938_664,
            0.906_179_845_938_664,
        ];
        let gw = [
            0.568_888_888_888_889,
            0.478_628_670_499_366,
            0.478_628_670_499_366,
            0.236_926_885_056_189,
            0.236_926_885_056_189,
        ];
        let h = 1.0 / (BLEND_TABLE - 1) as f64;
        for k in 1..BLEND_TABLE {
            let (a, b) = ((k - 1) as f64 * h, k as f64 * h);
            let mut acc = 0.0;
            for (x, w) in gx.iter().zip(gw.iter()) {
                let u = 0.5 * (a + b) + 0.5 * (b - a) * x;
                acc += w * bezier_d(&p, u).norm();
            }
            table[k] = table[k - 1] + 0.5 * (b - a) * acc;
        }
        Prim::Blend { p, table }
    }

    /// Length, m.
    pub fn length(&self) -> f64 {
        match self {
            Prim::Line { a, b } => (b - a).norm(),
            Prim::Arc {
                radius,
                sweep,
                rise,
                ..
            } => ((radius * sweep).powi(2) + rise.norm_squared()).sqrt(),
            Prim::Blend { table, .. } => table[BLEND_TABLE - 1],
        }
    }

    fn blend_u(table: &[f64; BLEND_TABLE], s: f64) -> f64 {
        let s = s.max(0.0).min(table[BLEND_TABLE - 1]); // NaN-safe, unlike clamp
        let k = table.partition_point(|&x| x < s).clamp(1, BLEND_TABLE - 1);
        let (a, b) = (table[k - 1], table[k]);
        let f = if b > a { (s - a) / (b - a) } else { 0.0 };
        ((k - 1) as f64 + f) / (BLEND_TABLE - 1) as f64
    }

    /// Point at arc length `s` (m) from the start, clamped to the primitive.
    pub fn point(&self, s: f64) -> V3 {
        let len = self.length();
        let s = s.max(0.0).min(len); // NaN-safe, unlike clamp
        match self {
            Prim::Line { a, b } => {
                if len > 0.0 {
                    a + (b - a) * (s / len)
                } else {
                    *a
                }
            }
            Prim::Arc {
                centre,
                u,
                w,
                radius,
                sweep,
                rise,
            } => {
                let f = if len > 0.0 { s / len } else { 0.0 };
                let th = f * sweep;
                centre + (u * th.cos() + w * th.sin()) * *radius + rise * f
            }
            Prim::Blend { p, table } => bezier(p, Self::blend_u(table, s)),
        }
    }

    /// Unit tangent at arc length `s`.
    pub(crate) fn tangent(&self, s: f64) -> V3 {
        let len = self.length();
        let t = match self {
            Prim::Line { a, b } => b - a,
            Prim::Arc {
                u,
                w,
                radius,
                sweep,
                rise,
                ..
            } => {
                let f = if len > 0.0 {
                    (s / len).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let th = f * sweep;
                (w * th.cos() - u * th.sin()) * (radius * sweep) + rise
            }
            Prim::Blend { p, table } => bezier_d(p, Self::blend_u(table, s)),
        };
        let n = t.norm();
        if n > 0.0 {
            t / n
        } else {
            V3::x()
        }
    }

    /// Curvature at arc length `s`, 1/m.
    pub(crate) fn curvature(&self, s: f64) -> f64 {
        match self {
            Prim::Line { .. } => 0.0,
            Prim::Arc {
                radius,
                sweep,
                rise,
                ..
            } => {
                // Helix: κ = r / (r² + c²) with c = rise / sweep.
                let c2 = if *sweep > 0.0 {
                    rise.norm_squared() / (sweep * sweep)
                } else {
                    0.0
                };
                radius / (radius * radius + c2)
            }
            Prim::Blend { .. } => {
                let h = (self.length() * 1e-3).max(1e-7);
                let a = self.tangent((s - h).max(0.0));
                let b = self.tangent((s + h).min(self.length()));
                let ds = (s + h).min(self.length()) - (s - h).max(0.0);
                if ds > 0.0 {
                    (b - a).norm() / ds
                } else {
                    0.0
                }
            }
        }
    }

    /// The part of this primitive between arc lengths `s0 < s1` (lines and arcs only; a blend
    /// is returned unchanged).
    pub(crate) fn trimmed(&self, s0: f64, s1: f64) -> Prim {
        let len = self.length();
        match *self {
            Prim::Line { .. } => Prim::Line {
                a: self.point(s0),
                b: self.point(s1),
            },
            Prim::Arc {
                centre,
                u,
                w,
                radius,
                sweep,
                rise,
            } => {
                if len <= 0.0 {
                    return *self;
                }
                let (f0, f1) = (s0 / len, s1 / len);
                let (th0, th1) = (f0 * sweep, f1 * sweep);
                let (s, c) = th0.sin_cos();
                Prim::Arc {
                    centre: centre + rise * f0,
                    u: u * c + w * s,
                    w: w * c - u * s,
                    radius,
                    sweep: th1 - th0,
                    rise: rise * (f1 - f0),
                }
            }
            Prim::Blend { .. } => *self,
        }
    }
}

/// A programmed move as the timing layer needs it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Move {
    /// The geometry, part frame, m.
    pub prim: Prim,
    /// Commanded TCP speed, m/s.
    pub speed: f64,
    /// Zone (corner blend) radius at the end of the move, m; 0 = fine point (stop).
    pub zone: f64,
    /// Extruding (print) or travel.
    pub print: bool,
    /// Source line of the move (for reports).
    pub line: usize,
}

/// A piece of the geometric path after blending.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    /// The geometry, m.
    pub prim: Prim,
    /// Commanded speed, m/s.
    pub speed: f64,
    /// Extruding or travel.
    pub print: bool,
    /// Index of the programmed move this piece comes from (the first one, for a blend).
    pub move_index: usize,
    /// Whether this piece is a corner blend.
    pub blend: bool,
    /// Whether the path must stop (v = 0) at the end of this piece.
    pub stop_after: bool,
    /// Time held at rest at the end of this piece (a dwell), s; 0 = none. Implies `stop_after`.
    pub dwell_after: f64,
    /// Time held at rest at the start of this piece, s; only on the first piece (a dwell
    /// before any move), 0 = none.
    pub dwell_before: f64,
}

/// Replace every corner that has a zone by a blend inside the zone; stop at fine corners.
/// The blend starts `d = min(zone, ½ len_k, ½ len_k+1)` before the corner and ends `d` after it
/// (measured along each move), so it stays within the zone sphere around the corner.
pub fn blend_path(moves: &[Move]) -> Vec<Piece> {
    let mut out = Vec::with_capacity(moves.len() * 2);
    let n = moves.len();
    // Trim lengths at the start and end of each move.
    let mut cut_start = vec![0.0; n];
    let mut cut_end = vec![0.0; n];
    let mut stop = vec![false; n];
    for k in 0..n.saturating_sub(1) {
        let (a, b) = (&moves[k], &moves[k + 1]);
        let ta = a.prim.tangent(a.prim.length());
        let tb = b.prim.tangent(0.0);
        let angle = ta.dot(&tb).clamp(-1.0, 1.0).acos();
        if angle <= SMOOTH_JUNCTION_RAD {
            continue;
        }
        if a.zone <= 0.0 {
            stop[k] = true;
            continue;
        }
        let d = a
            .zone
            .min(0.5 * (a.prim.length() - cut_start[k]))
            .min(0.5 * b.prim.length());
        if d <= 1e-9 || angle > std::f64::consts::PI - 1e-3 {
            stop[k] = true; // reversal or degenerate: stop
            continue;
        }
        cut_end[k] = d;
        cut_start[k + 1] = d;
    }
    for k in 0..n {
        let m = &moves[k];
        let len = m.prim.length();
        let prim = if cut_start[k] > 0.0 || cut_end[k] > 0.0 {
            m.prim.trimmed(cut_start[k], len - cut_end[k])
        } else {
            m.prim
        };
        out.push(Piece {
            prim,
            speed: m.speed,
            print: m.print,
            move_index: k,
            blend: false,
            stop_after: stop[k] || k + 1 == n,
            dwell_after: 0.0,
            dwell_before: 0.0,
        });
        if cut_end[k] > 0.0 {
            let nx = &moves[k + 1];
            let p0 = prim.point(prim.length());
            let ta = prim.tangent(prim.length());
            let p3 = nx.prim.point(cut_start[k + 1]);
            let tb = nx.prim.tangent(cut_start[k + 1]);
            out.push(Piece {
                prim: Prim::blend(p0, ta, p3, tb, cut_end[k]),
                speed: m.speed.min(nx.speed),
                print: m.print && nx.print,
                move_index: k,
                blend: true,
                stop_after: false,
                dwell_after: 0.0,
                dwell_before: 0.0,
            });
        }
    }
    out
}

/// Put dwells on blended pieces: `(k, seconds)` holds the path at rest for `seconds` at the end
/// of programmed move `k` (`None`: at the start, before the first move). The move before a
/// dwell stops: its corner blend, if any, is undone (the pieces are rebuilt from `moves`).
/// A dwell at the start is held as `dwell_before` of the first piece.
pub fn blend_path_with_dwells(moves: &[Move], dwells: &[(Option<usize>, f64)]) -> Vec<Piece> {
    let mut at_start = 0.0;
    if dwells.is_empty() {
        return blend_path(moves);
    }
    let mut after = vec![0.0; moves.len()];
    for &(k, t) in dwells {
        match k {
            Some(k) if k < moves.len() => after[k] += t,
            Some(_) => {
                if let Some(last) = after.last_mut() {
                    *last += t;
                }
            }
            None => at_start += t,
        }
    }
    // Blend each run of moves between dwells on its own, so that the move before a dwell
    // ends exactly at its programmed end point, at rest.
    let mut out = Vec::with_capacity(moves.len() * 2);
    let mut first = 0;
    for k in 0..moves.len() {
        if after[k] > 0.0 || k + 1 == moves.len() {
            let offset = first;
            for mut p in blend_path(&moves[first..=k]) {
                p.move_index += offset;
                out.push(p);
            }
            if let Some(last) = out.last_mut() {
                last.stop_after = true;
                last.dwell_after = after[k];
            }
            first = k + 1;
        }
    }
    if let Some(p) = out.first_mut() {
        p.dwell_before = at_start;
    }
    out
}
