//! Where a station stands and the way between stations, against the walls on the floor.
//!
//! A station occupies a disc of the floor ([`crate::stations::StationsProblem::footprint_m`]: the robot's
//! foot plus its track carriage or crawler). Walls are the beads the path lays, seen from above
//! (nozzle-tip chords widened by the bead's half-width,
//! [`crate::evaluate::feasibility::collision::BEAD_RADIUS_M`]): a wall stands on the floor from the moment
//! it is printed, whatever its height, so every check is in the floor plane.
//!
//! - A station may not stand on a wall printed before or by its own segment (the disc must be
//!   clear of the walls of every move up to the segment's last).
//! - The way to the next station (the disc swept along it) may not cross a wall printed before
//!   the move: on a track the straight line along the rail; for a crawler the shortest way
//!   around the walls ([`Router`]).
//! - A track's rail, the whole line between its ends, may not lie under any wall.

use crate::evaluate::feasibility::collision::BEAD_RADIUS_M;
use crate::math::V3;
use crate::toolpath::{MoveKind, Toolpath};
use serde::Serialize;

/// Arcs are cut into chords of at most this sweep, deg, for the plan view.
const ARC_CHORD_DEG: f64 = 5.0;

/// One wall chord seen from above: its ends (part frame, m) and the move that lays it.
#[derive(Clone, Copy, Debug)]
struct Chord {
    a: [f64; 2],
    b: [f64; 2],
    /// Index of the move (into [`Toolpath::moves`]).
    mv: usize,
}

/// The walls of a path in plan view, in path order.
pub struct Floor {
    chords: Vec<Chord>,
}

/// Distance between the segments `p0–p1` and `q0–q1` in the plane, m.
fn segment_distance(p0: [f64; 2], p1: [f64; 2], q0: [f64; 2], q1: [f64; 2]) -> f64 {
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    // Proper crossing: distance 0.
    let (d1, d2) = (cross(q0, q1, p0), cross(q0, q1, p1));
    let (d3, d4) = (cross(p0, p1, q0), cross(p0, p1, q1));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return 0.0;
    }
    point_segment_distance(p0, q0, q1)
        .min(point_segment_distance(p1, q0, q1))
        .min(point_segment_distance(q0, p0, p1))
        .min(point_segment_distance(q1, p0, p1))
}

/// Distance from `p` to the segment `a–b` in the plane, m.
fn point_segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy)
}

/// The walls each move of `path` lays, in path order (one entry per move, empty for a travel
/// move): nozzle-tip chords in the part frame, m, lines whole and arcs in chords of at most
/// 5°. The stations' collision scene ([`crate::evaluate::Evaluator::with_prior_walls`]) and
/// the plan view ([`Floor`]) are both made of them.
pub fn wall_chords(path: &Toolpath) -> Vec<Vec<(V3, V3)>> {
    path.segments()
        .map(|(start, m)| {
            if !m.print {
                return Vec::new();
            }
            let n = match m.kind {
                MoveKind::Line => 1,
                MoveKind::Arc { sweep, .. } => {
                    ((sweep.abs().to_degrees() / ARC_CHORD_DEG).ceil() as usize).max(1)
                }
            };
            (0..n)
                .map(|k| {
                    (
                        m.point_at(&start, k as f64 / n as f64),
                        m.point_at(&start, (k + 1) as f64 / n as f64),
                    )
                })
                .collect()
        })
        .collect()
}

impl Floor {
    /// The plan view of the walls [`wall_chords`] gives (indexed by move).
    pub fn from_chords(walls: &[Vec<(V3, V3)>]) -> Floor {
        let chords = walls
            .iter()
            .enumerate()
            .flat_map(|(mv, w)| {
                w.iter().map(move |(a, b)| Chord {
                    a: [a.x, a.y],
                    b: [b.x, b.y],
                    mv,
                })
            })
            .collect();
        Floor { chords }
    }

    /// The first move up to `last_move` (inclusive) whose wall comes closer than `r` (m) plus
    /// the bead's half-width to the segment `p0–p1` (a point when equal), or `None`: clear.
    pub fn first_blocking(
        &self,
        p0: [f64; 2],
        p1: [f64; 2],
        r: f64,
        last_move: usize,
    ) -> Option<usize> {
        let clear = r + BEAD_RADIUS_M;
        let (xlo, xhi) = (p0[0].min(p1[0]) - clear, p0[0].max(p1[0]) + clear);
        let (ylo, yhi) = (p0[1].min(p1[1]) - clear, p0[1].max(p1[1]) + clear);
        self.chords
            .iter()
            .take_while(|c| c.mv <= last_move)
            .find(|c| {
                // Bounding boxes first.
                c.a[0].max(c.b[0]) >= xlo
                    && c.a[0].min(c.b[0]) <= xhi
                    && c.a[1].max(c.b[1]) >= ylo
                    && c.a[1].min(c.b[1]) <= yhi
                    && segment_distance(p0, p1, c.a, c.b) < clear
            })
            .map(|c| c.mv)
    }
}

/// A way of the floor disc between two stations in plan view: the polyline its centre follows
/// (part frame, m; the straight line when that is clear) and its length, m.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Way {
    /// Points of the polyline, from the station left to the station reached, m.
    pub points: Vec<[f64; 2]>,
    /// Length of the polyline, m.
    pub length_m: f64,
}

/// Corners of the polygon put around each wall end for detours.
const DETOUR_CORNERS: usize = 8;

/// The walls' plan view after one move: the detour graph's nodes (corners of an octagon put
/// around every wall end, outside the disc's clearance, where the disc stands clear) and the
/// straight ways between them that are clear.
struct Graph {
    nodes: Vec<[f64; 2]>,
    /// `n × n` lengths of the clear straight ways between nodes, m (∞ where blocked).
    edge: Vec<f64>,
}

/// Shortest ways of a floor disc of radius `r` (m) around the walls printed so far, for a
/// crawler that goes around walls (not for a track: its carriage stays on the rail).
///
/// A way is the straight line when that is clear ([`Floor::first_blocking`]); otherwise the
/// shortest polyline through the corners of octagons around the wall ends (each just outside
/// the disc's clearance `r` + the bead's half-width from the end: the octagon circumscribes
/// the clearance circle, so its edges stay clear of the end they surround), every leg of
/// which passes the same check. A way found is therefore clear by the same test as a straight
/// one; its length is at most a few per cent above the true shortest (the octagon against
/// the circle); a way is missed only where a gap is narrower than the octagon needs (a door
/// less than ≈ 2.2 × the clearance wide), which is conservative.
pub struct Router<'f> {
    floor: &'f Floor,
    r: f64,
    graphs: std::collections::HashMap<usize, Graph>,
}

impl<'f> Router<'f> {
    /// Ways of a disc of radius `r_m` (m) around the walls of `floor`.
    pub fn new(floor: &'f Floor, r_m: f64) -> Self {
        Router {
            floor,
            r: r_m,
            graphs: Default::default(),
        }
    }

    fn graph(&mut self, last_move: usize) -> &Graph {
        let (floor, r) = (self.floor, self.r);
        self.graphs.entry(last_move).or_insert_with(|| {
            let clear = r + BEAD_RADIUS_M;
            // Circumradius of the octagon whose edges touch the clearance circle, a hair out.
            let rad =
                clear / (std::f64::consts::PI / DETOUR_CORNERS as f64).cos() * (1.0 + 1e-9) + 1e-9;
            let mut ends: Vec<[f64; 2]> = floor
                .chords
                .iter()
                .take_while(|c| c.mv <= last_move)
                .flat_map(|c| [c.a, c.b])
                .collect();
            ends.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
            ends.dedup();
            let nodes: Vec<[f64; 2]> = ends
                .iter()
                .flat_map(|e| {
                    (0..DETOUR_CORNERS).map(move |k| {
                        let a = std::f64::consts::TAU * k as f64 / DETOUR_CORNERS as f64;
                        [e[0] + rad * a.cos(), e[1] + rad * a.sin()]
                    })
                })
                .filter(|q| floor.first_blocking(*q, *q, r, last_move).is_none())
                .collect();
            let n = nodes.len();
            let mut edge = vec![f64::INFINITY; n * n];
            for i in 0..n {
                for j in i + 1..n {
                    if floor
                        .first_blocking(nodes[i], nodes[j], r, last_move)
                        .is_none()
                    {
                        let d = dist(nodes[i], nodes[j]);
                        edge[i * n + j] = d;
                        edge[j * n + i] = d;
                    }
                }
            }
            Graph { nodes, edge }
        })
    }

    /// The shortest way of the disc from `p0` to `p1` (m) across the floor as it is after
    /// move `last_move` (walls laid up to it), or `None` when none is clear.
    pub fn way(&mut self, p0: [f64; 2], p1: [f64; 2], last_move: usize) -> Option<Way> {
        let (floor, r) = (self.floor, self.r);
        if floor.first_blocking(p0, p1, r, last_move).is_none() {
            return Some(Way {
                points: vec![p0, p1],
                length_m: dist(p0, p1),
            });
        }
        let g = self.graph(last_move);
        let n = g.nodes.len();
        // Dense Dijkstra from p0 (index n) to p1 (index n + 1) over the nodes.
        let seen = |q: [f64; 2], i: usize| {
            floor
                .first_blocking(q, g.nodes[i], r, last_move)
                .is_none()
                .then(|| dist(q, g.nodes[i]))
        };
        let to_end: Vec<Option<f64>> = (0..n).map(|i| seen(p1, i)).collect();
        let mut d: Vec<f64> = (0..n)
            .map(|i| seen(p0, i).unwrap_or(f64::INFINITY))
            .collect();
        let mut prev: Vec<Option<usize>> = vec![None; n];
        let mut done = vec![false; n];
        let mut best_end: Option<(f64, usize)> = None;
        while let Some(u) = (0..n)
            .filter(|&i| !done[i] && d[i].is_finite())
            .min_by(|&a, &b| d[a].total_cmp(&d[b]))
        {
            if best_end.is_some_and(|(e, _)| d[u] >= e) {
                break;
            }
            done[u] = true;
            if let Some(t) = to_end[u] {
                if best_end.is_none_or(|(e, _)| d[u] + t < e) {
                    best_end = Some((d[u] + t, u));
                }
            }
            for v in 0..n {
                let w = g.edge[u * n + v];
                if !done[v] && d[u] + w < d[v] {
                    d[v] = d[u] + w;
                    prev[v] = Some(u);
                }
            }
        }
        let (length_m, mut u) = best_end?;
        let mut points = vec![p1, g.nodes[u]];
        while let Some(q) = prev[u] {
            points.push(g.nodes[q]);
            u = q;
        }
        points.push(p0);
        points.reverse();
        Some(Way { points, length_m })
    }
}

/// Distance between two points of the plane, m.
fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_distances_agree_with_parry3d_in_the_plane() {
        use parry3d_f64::math::{Isometry, Point};
        use parry3d_f64::shape::Segment;
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let mut p = || [rng.gen_range(-2.0..2.0), rng.gen_range(-2.0..2.0)];
        for _ in 0..2000 {
            let (a, b, c, d) = (p(), p(), p(), p());
            let seg = |u: [f64; 2], v: [f64; 2]| {
                Segment::new(Point::new(u[0], u[1], 0.0), Point::new(v[0], v[1], 0.0))
            };
            let id = Isometry::identity();
            let reference = parry3d_f64::query::distance(&id, &seg(a, b), &id, &seg(c, d)).unwrap();
            let mine = segment_distance(a, b, c, d);
            assert!(
                (mine - reference).abs() < 1e-12,
                "{a:?}-{b:?} to {c:?}-{d:?}: {mine} vs {reference}"
            );
        }
    }

    #[test]
    fn clockwise_arcs_are_cut_into_chords_like_counter_clockwise_ones() {
        // A clockwise arc's sweep is negative: it was laid as one chord across the whole
        // arc in the stations' collision scene.
        let arc = |g: &str| {
            let text = format!("G21\nG90\nG0 X0 Y0 Z20\nM3\n{g} X20 Y0 I10 J0 F9000\nM5\n");
            let tp = crate::toolpath::parse_gcode(&text, "arc.gcode", &Default::default()).unwrap();
            wall_chords(&tp).iter().map(Vec::len).max().unwrap()
        };
        assert_eq!(arc("G2"), 36);
        assert_eq!(arc("G3"), 36);
    }

    #[test]
    fn segment_distances_are_those_of_the_plane() {
        // Crossing, parallel, end to end, and a point.
        assert_eq!(
            segment_distance([0.0, -1.0], [0.0, 1.0], [-1.0, 0.0], [1.0, 0.0]),
            0.0
        );
        assert!(
            (segment_distance([0.0, 0.0], [1.0, 0.0], [0.0, 0.5], [1.0, 0.5]) - 0.5).abs() < 1e-15
        );
        assert!(
            (segment_distance([0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]) - 1.0).abs() < 1e-15
        );
        assert!((point_segment_distance([0.5, 2.0], [0.0, 0.0], [1.0, 0.0]) - 2.0).abs() < 1e-15);
        assert!(
            (segment_distance([3.0, 4.0], [3.0, 4.0], [0.0, 0.0], [0.0, 0.0]) - 5.0).abs() < 1e-15
        );
    }
}
