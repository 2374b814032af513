//! The solver of [`crate::stations::StationsProblem`]: candidate runs and stations, their evaluation in
//! parallel, and the dynamic programme over the split points (see the module documentation
//! of [`super`]).

use crate::error::{Error, Result};
use crate::evaluate::evaluator::{Evaluated, Evaluator, Feasible};
use crate::evaluate::PathJob;
use crate::math::V3;
use crate::stations::floor::{self, Floor, Router, Way};
use crate::stations::{
    reach_annulus, segment_moves, split_units, sub_path, Headings, Station, StationsProblem, Unit,
    PREFILTER_SAMPLE_M, PREFILTER_SLACK_REACH,
};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicUsize, Ordering};

/// One segment of a plan: a contiguous run of units printed from one station.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Segment {
    /// First and last unit (0-based, inclusive).
    pub units: [usize; 2],
    /// First and last move of the sub-path (0-based indices into the path's moves, inclusive).
    pub moves: [usize; 2],
    /// Source lines of the first and last move (1-based).
    pub lines: [usize; 2],
    /// Where the robot stands.
    pub station: Station,
    /// Extruded length of the segment, m.
    pub print_length_m: f64,
    /// The segment's numbers, timed and evaluated from rest to rest at its station (energies
    /// J, times s).
    pub eval: Feasible,
}

/// How much work the plan took.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct PlanStats {
    /// Units of the path (where it may be split).
    pub units: usize,
    /// Candidate station positions.
    pub positions: usize,
    /// Runs of units evaluated (those some candidate passed the pre-filter for).
    pub runs: usize,
    /// (run, station) evaluations (full timing, feasibility and energy).
    pub evaluations: usize,
    /// Feasible ones among them.
    pub feasible: usize,
    /// (run, position) pairs dropped because the station's floor disc stands on a wall printed
    /// before or by the run.
    pub footprint_on_wall: usize,
    /// Moves between stations refused because no way of the floor disc is clear of the printed
    /// walls (the straight line on a track; around the walls otherwise).
    pub way_blocked: usize,
    /// Moves between stations whose straight line crosses a printed wall but which have a clear
    /// way around the walls (a crawler's detour, e.g. through a door).
    pub detoured: usize,
    /// The reach annulus the pre-filter used (before its slack), m.
    pub annulus_m: (f64, f64),
    /// The pre-filter's slack, m.
    pub slack_m: f64,
}

/// A multi-station plan: the segments in path order, each with its station, and the totals.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Plan {
    /// The path's units.
    pub units: Vec<Unit>,
    /// The segments, in path order.
    pub segments: Vec<Segment>,
    /// Moves of the arm between stations (segments − 1).
    pub relocations: usize,
    /// Distance moved between stations, m (along the ways).
    pub relocation_distance_m: f64,
    /// The way of each relocation (the straight line, or the detour around printed walls).
    pub ways: Vec<Way>,
    /// Relocation cost: relocations × cost + distance × cost per metre, J.
    pub relocation_j: f64,
    /// Σ segment energies (the objective), J.
    pub energy_j: f64,
    /// `energy_j + relocation_j`, J: what the plan minimises.
    pub total_j: f64,
    /// Work done.
    pub stats: PlanStats,
}

/// A feasible candidate: run, index of the station in the run, its energy (J).
struct Cand {
    run: usize,
    k: usize,
    cost: f64,
}

/// A run of units `i..=j` and its candidate stations (position index, station).
struct Run {
    i: usize,
    j: usize,
    stations: Vec<(usize, Station)>,
    /// Positions within reach dropped because their floor disc stands on a wall, with the
    /// first such (position, move of the wall).
    on_wall: (usize, Option<(usize, usize)>),
}

/// Choose the plan of least energy plus relocation cost (see [`super`]). `progress(done,
/// total)` is called after each run of units is evaluated (from any thread). Errors: bad
/// numbers in the problem, a path no candidate set covers (naming the first unit that cannot
/// be printed, its moves, lines and why), model errors.
pub fn solve(p: &StationsProblem, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Plan> {
    p.check()?;
    let path = p.path;
    let units = split_units(path)?;
    let (annulus, slack) = prefilter_annulus(p)?;
    let (rmin, rmax) = ((annulus.0 - slack).max(0.0), annulus.1 + slack);

    // The walls each move lays (collision scene of later segments) and in plan view: a
    // track's rail may not lie under any.
    let walls = floor::wall_chords(path);
    let floor = Floor::from_chords(&walls);
    if let Some([a, b]) = p.candidates.track {
        if let Some(mv) = floor.first_blocking(a, b, 0.0, path.moves.len()) {
            return Err(Error::Invalid(format!(
                "{}: the track ({:.3}, {:.3}) → ({:.3}, {:.3}) m lies under the wall printed by line {} (move {mv}): move the track off the walls",
                path.source, a[0], a[1], b[0], b[1], path.moves[mv].line
            )));
        }
    }
    let runs = Prefilter::new(p, &units, &floor, (rmin, rmax)).runs();
    let evaluated = evaluate_runs(p, &units, &runs, &walls, progress)?;
    let search = Search {
        p,
        units,
        runs,
        evaluated,
    };
    let mut ways = Ways {
        p,
        floor: &floor,
        router: Router::new(&floor, p.footprint_m),
    };
    let mut chains = Chains::new(&search);
    chains.link(&search, &mut ways);
    let stats = PlanStats {
        units: search.units.len(),
        positions: p.candidates.positions.len(),
        runs: search.runs.len(),
        evaluations: chains.n_eval,
        feasible: chains.cands.len(),
        footprint_on_wall: search.runs.iter().map(|r| r.on_wall.0).sum(),
        way_blocked: chains.way_blocked,
        detoured: chains.detoured,
        annulus_m: annulus,
        slack_m: slack,
    };
    let Some(end) = chains.end(search.units.len()) else {
        return Err(uncovered(
            p,
            &search.units,
            &search.runs,
            &search.evaluated,
            &cands_ends(&chains.cands, &search.runs, &chains.best),
        ));
    };
    search.plan(&chains, end, &mut ways, stats)
}

/// The reach annulus of the pre-filter at the path's heights, and its slack, m.
fn prefilter_annulus(p: &StationsProblem) -> Result<((f64, f64), f64)> {
    let path = p.path;
    let reach = crate::evaluate::feasibility::reach_m(p.robot);
    // Heights of the path in the base frame.
    let (lo, hi) = path
        .bounding_box()
        .ok_or_else(|| Error::Invalid(format!("{}: the path has no moves", path.source)))?;
    let zs: Vec<f64> = (0..5)
        .map(|k| p.z_m + lo.z + (hi.z - lo.z) * k as f64 / 4.0)
        .collect();
    let annulus = reach_annulus(p.robot, &zs).ok_or_else(|| {
        Error::Invalid(format!(
            "{}: the robot reaches no point with a vertical nozzle at heights {:.3}…{:.3} m above its base: change the station height (the part origin's height above the base)",
            path.source, zs[0], zs[4]
        ))
    })?;
    let slack = PREFILTER_SLACK_REACH * reach + PREFILTER_SAMPLE_M / 2.0;
    Ok((annulus, slack))
}

/// The pre-filter: which candidate positions can reach every point of a run of units and
/// do not stand on its walls.
struct Prefilter<'a> {
    p: &'a StationsProblem<'a>,
    units: &'a [Unit],
    /// Horizontal distance range [min, max] of every move's points from every position.
    dist: Vec<[f64; 2]>,
    /// Centroid sums of the extruded points per move (for headings facing the work).
    centre: Vec<(f64, f64, usize)>,
    /// The first move whose wall a station's floor disc at each position would stand on.
    wall_under: Vec<Option<usize>>,
    /// Distances from a position a run's points must lie within, m.
    range: (f64, f64),
}

impl<'a> Prefilter<'a> {
    /// Sample every move and measure its distances from every candidate position.
    fn new(
        p: &'a StationsProblem<'a>,
        units: &'a [Unit],
        floor: &Floor,
        range: (f64, f64),
    ) -> Self {
        let path = p.path;
        let positions = &p.candidates.positions;
        let n_pos = positions.len();
        let mut dist = vec![[f64::INFINITY, f64::NEG_INFINITY]; path.moves.len() * n_pos];
        let mut centre = vec![(0.0, 0.0, 0usize); path.moves.len()];
        for (mi, (start, m)) in path.segments().enumerate() {
            let len = m.length(&start);
            let n = ((len / PREFILTER_SAMPLE_M).ceil() as usize).max(1);
            let pts: Vec<(f64, f64)> = (0..=n)
                .map(|k| {
                    let q = m.point_at(&start, k as f64 / n as f64);
                    (q.x, q.y)
                })
                .collect();
            if m.print {
                centre[mi] = (
                    pts.iter().map(|q| q.0).sum(),
                    pts.iter().map(|q| q.1).sum(),
                    pts.len(),
                );
            }
            for (s, pos) in positions.iter().enumerate() {
                let d = &mut dist[mi * n_pos + s];
                for q in &pts {
                    let r = (q.0 - pos[0]).hypot(q.1 - pos[1]);
                    d[0] = d[0].min(r);
                    d[1] = d[1].max(r);
                }
            }
        }
        let wall_under: Vec<Option<usize>> = positions
            .iter()
            .map(|&q| floor.first_blocking(q, q, p.footprint_m, path.moves.len()))
            .collect();
        Prefilter {
            p,
            units,
            dist,
            centre,
            wall_under,
            range,
        }
    }

    /// Runs of units with the positions passing the pre-filter.
    fn runs(&self) -> Vec<Run> {
        let (path, units) = (self.p.path, self.units);
        let n_units = units.len();
        let n_pos = self.p.candidates.positions.len();
        let (rmin, rmax) = self.range;
        let mut runs: Vec<Run> = Vec::new();
        for i in 0..n_units {
            let mut acc = vec![[f64::INFINITY, f64::NEG_INFINITY]; n_pos];
            let mut sums = (0.0, 0.0, 0usize);
            let first = segment_moves(path, units, i, i).0;
            let mut upto = first; // moves first..upto are folded in
            for j in i..n_units {
                let last = segment_moves(path, units, i, j).1;
                for mi in upto..=last {
                    for (s, a) in acc.iter_mut().enumerate() {
                        let d = self.dist[mi * n_pos + s];
                        a[0] = a[0].min(d[0]);
                        a[1] = a[1].max(d[1]);
                    }
                    sums.0 += self.centre[mi].0;
                    sums.1 += self.centre[mi].1;
                    sums.2 += self.centre[mi].2;
                }
                upto = last + 1;
                let pass: Vec<usize> = (0..n_pos)
                    .filter(|&s| acc[s][0] >= rmin && acc[s][1] <= rmax)
                    .collect();
                if pass.is_empty() {
                    break; // a longer run holds these points too
                }
                runs.push(self.run(i, j, last, pass, sums));
            }
        }
        runs
    }

    /// The run of units `i..=j` (its last move `last`) from the positions in reach (`pass`),
    /// leaving out those standing on its walls; `sums` are its centroid sums.
    fn run(
        &self,
        i: usize,
        j: usize,
        last: usize,
        pass: Vec<usize>,
        sums: (f64, f64, usize),
    ) -> Run {
        let p = self.p;
        // A station may not stand on a wall printed before or by this run.
        let mut on_wall = (0, None);
        let pass: Vec<usize> = pass
            .into_iter()
            .filter(|&s| match self.wall_under[s] {
                Some(mv) if mv <= last => {
                    on_wall.0 += 1;
                    on_wall.1.get_or_insert((s, mv));
                    false
                }
                _ => true,
            })
            .collect();
        let c = (sums.0 / sums.2.max(1) as f64, sums.1 / sums.2.max(1) as f64);
        let mut stations = Vec::new();
        for s in pass {
            let [x, y] = p.candidates.positions[s];
            match &p.candidates.headings {
                Headings::Auto => {
                    let h = (c.1 - y).atan2(c.0 - x);
                    stations.push((s, Station::new(x, y, h, p.z_m, p.spin_rad)));
                }
                Headings::Fixed(hs) => {
                    for &h in hs {
                        stations.push((s, Station::new(x, y, h, p.z_m, p.spin_rad)));
                    }
                }
            }
        }
        Run {
            i,
            j,
            stations,
            on_wall,
        }
    }
}

/// Evaluate every run from its stations (rayon; collected in run order), the walls of the
/// units before it in its collision scene.
fn evaluate_runs(
    p: &StationsProblem,
    units: &[Unit],
    runs: &[Run],
    walls: &[Vec<(V3, V3)>],
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<Vec<Evaluated>>> {
    let path = p.path;
    let done = AtomicUsize::new(0);
    let total = runs.len();
    // One energy model for every segment (it depends on the robot only).
    let model = crate::energy::EnergyModel::with_options(p.robot, p.energy)?;
    runs.par_iter()
        .map(|run| {
            let (first, last) = segment_moves(path, units, run.i, run.j);
            let sub = sub_path(path, first, last);
            let job = PathJob::with_energy(p.robot, model.clone(), &sub, p.profile, p.joint)?;
            let prior: Vec<_> = walls[..first].iter().flatten().copied().collect();
            let ev = Evaluator::new(&job, p.feasibility, p.objective).with_prior_walls(prior);
            let ps: Vec<_> = run.stations.iter().map(|(_, s)| s.placement).collect();
            let rows = ev.sweep(&ps, &|_, _| {})?;
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
            Ok(rows)
        })
        .collect::<Result<_>>()
}

/// The ways between candidate positions after the walls up to a move.
struct Ways<'a> {
    p: &'a StationsProblem<'a>,
    floor: &'a Floor,
    router: Router<'a>,
}

impl Ways<'_> {
    /// The way from position `a` to `b` after the walls up to move `last`, or None when none
    /// is clear. On a track the carriage keeps to the rail: only the straight way counts.
    fn way(&mut self, a: usize, b: usize, last: usize) -> Option<Way> {
        let positions = &self.p.candidates.positions;
        if self.p.candidates.track.is_some() {
            self.floor
                .first_blocking(positions[a], positions[b], self.p.footprint_m, last)
                .is_none()
                .then(|| Way {
                    points: vec![positions[a], positions[b]],
                    length_m: (positions[a][0] - positions[b][0])
                        .hypot(positions[a][1] - positions[b][1]),
                })
        } else {
            self.router.way(positions[a], positions[b], last)
        }
    }
}

/// The evaluated runs of a stations problem.
struct Search<'a> {
    p: &'a StationsProblem<'a>,
    units: Vec<Unit>,
    runs: Vec<Run>,
    evaluated: Vec<Vec<Evaluated>>,
}

/// The dynamic programme over the feasible candidates: the best chain of segments ending at
/// each.
struct Chains {
    cands: Vec<Cand>,
    /// Candidates by their last unit, in run order within it.
    by_end: Vec<Vec<usize>>,
    best: Vec<f64>,
    back: Vec<Option<usize>>,
    /// Distance moved so far along the ways, m: of two chains of the same cost (a mirror
    /// station with the same energy, no cost per metre) the one that moves less is kept.
    moved: Vec<f64>,
    /// Way lengths between positions after the walls up to a move (None: no clear way);
    /// they depend on the positions and the split only.
    ways: std::collections::HashMap<(usize, usize, usize), Option<f64>>,
    n_eval: usize,
    way_blocked: usize,
    detoured: usize,
}

impl Chains {
    /// Flatten the feasible candidates: (run, index in run), grouped by their last unit.
    fn new(s: &Search) -> Chains {
        let mut cands: Vec<Cand> = Vec::new();
        let mut n_eval = 0;
        for (r, rows) in s.evaluated.iter().enumerate() {
            n_eval += rows.len();
            for (k, e) in rows.iter().enumerate() {
                let c = e.cost();
                if c.is_finite() {
                    cands.push(Cand { run: r, k, cost: c });
                }
            }
        }
        let mut by_end: Vec<Vec<usize>> = vec![Vec::new(); s.units.len()];
        for (ci, c) in cands.iter().enumerate() {
            by_end[s.runs[c.run].j].push(ci);
        }
        Chains {
            best: vec![f64::INFINITY; cands.len()],
            back: vec![None; cands.len()],
            moved: vec![0.0; cands.len()],
            cands,
            by_end,
            ways: Default::default(),
            n_eval,
            way_blocked: 0,
            detoured: 0,
        }
    }

    /// Link every candidate to the best chain before it, unit by unit.
    fn link(&mut self, s: &Search, ways: &mut Ways) {
        for j in 0..s.units.len() {
            for x in 0..self.by_end[j].len() {
                let ci = self.by_end[j][x];
                let c = &self.cands[ci];
                if s.runs[c.run].i == 0 {
                    self.best[ci] = c.cost;
                    continue;
                }
                if let Some((pi, v, m)) = self.best_before(ci, s, ways) {
                    self.best[ci] = v + self.cands[ci].cost;
                    self.moved[ci] = m;
                    self.back[ci] = Some(pi);
                }
            }
        }
    }

    /// The best chain candidate `ci` can follow: (candidate, cost with the relocation, moved).
    fn best_before(&mut self, ci: usize, s: &Search, ways: &mut Ways) -> Option<(usize, f64, f64)> {
        let (p, path) = (s.p, s.p.path);
        let c = &self.cands[ci];
        let run = &s.runs[c.run];
        let (pos, _) = &run.stations[c.k];
        let mut b: Option<(usize, f64, f64)> = None;
        for &pi in &self.by_end[run.i - 1] {
            if !self.best[pi].is_finite() {
                continue;
            }
            let pc = &self.cands[pi];
            let (ppos, _) = &s.runs[pc.run].stations[pc.k];
            if ppos == pos {
                continue; // the arm would print both as one segment
            }
            let last = segment_moves(path, &s.units, run.i - 1, run.i - 1).1;
            let detoured = &mut self.detoured;
            let way = *self.ways.entry((*ppos, *pos, last)).or_insert_with(|| {
                ways.way(*ppos, *pos, last).map(|w| {
                    if w.points.len() > 2 {
                        *detoured += 1;
                    }
                    w.length_m
                })
            });
            let Some(way_m) = way else {
                self.way_blocked += 1;
                continue; // no way to this station is clear of the printed walls
            };
            let v = self.best[pi] + p.relocation_j + p.relocation_j_per_m * way_m;
            let m = self.moved[pi] + way_m;
            if b.is_none_or(|(_, bv, bm)| better(v, m, bv, bm)) {
                b = Some((pi, v, m));
            }
        }
        b
    }

    /// The best complete chain's last candidate, if any chain prints the last unit.
    fn end(&self, n_units: usize) -> Option<usize> {
        let (best, moved) = (&self.best, &self.moved);
        let mut end: Option<usize> = None;
        for &ci in &self.by_end[n_units - 1] {
            if best[ci].is_finite()
                && end.is_none_or(|e| better(best[ci], moved[ci], best[e], moved[e]))
            {
                end = Some(ci);
            }
        }
        end
    }
}

impl Search<'_> {
    /// The plan of the chain ending at candidate `end`: its segments, ways and totals.
    fn plan(self, chains: &Chains, end: usize, ways: &mut Ways, stats: PlanStats) -> Result<Plan> {
        let (p, path) = (self.p, self.p.path);
        let (cands, runs, units) = (&chains.cands, &self.runs, &self.units);
        let mut chain = vec![end];
        while let Some(b) = chains.back[*chain.last().unwrap_or(&end)] {
            chain.push(b);
        }
        chain.reverse();
        let mut segments = Vec::with_capacity(chain.len());
        for &ci in &chain {
            let c = &cands[ci];
            let run = &runs[c.run];
            let (first, last) = segment_moves(path, units, run.i, run.j);
            let Some(eval) = self.evaluated[c.run][c.k].feasible().cloned() else {
                return Err(Error::Invalid(
                    "internal: an infeasible segment in the plan".into(),
                ));
            };
            segments.push(Segment {
                units: [run.i, run.j],
                moves: [first, last],
                lines: [path.moves[first].line, path.moves[last].line],
                station: run.stations[c.k].1,
                print_length_m: units[run.i..=run.j].iter().map(|u| u.print_length_m).sum(),
                eval,
            });
        }
        let mut ways_taken = Vec::with_capacity(chain.len().saturating_sub(1));
        for w in chain.windows(2) {
            let pos = |ci: usize| runs[cands[ci].run].stations[cands[ci].k].0;
            let last = segment_moves(
                path,
                units,
                runs[cands[w[0]].run].j,
                runs[cands[w[0]].run].j,
            )
            .1;
            ways_taken.push(ways.way(pos(w[0]), pos(w[1]), last).ok_or_else(|| {
                Error::Invalid("internal: a relocation of the plan has no clear way".into())
            })?);
        }
        let relocation_distance_m: f64 = ways_taken.iter().map(|w| w.length_m).sum();
        let relocations = segments.len() - 1;
        let relocation_j =
            relocations as f64 * p.relocation_j + p.relocation_j_per_m * relocation_distance_m;
        let energy_j: f64 = segments.iter().map(|s| s.eval.energy_j).sum();
        Ok(Plan {
            units: self.units,
            segments,
            relocations,
            relocation_distance_m,
            ways: ways_taken,
            relocation_j,
            energy_j,
            total_j: energy_j + relocation_j,
            stats,
        })
    }
}

/// Is a chain of cost `v` (J) that moves `m` (m) better than one of `bv`, `bm`? Lower cost;
/// costs within 1e-9 relative (the same energy up to rounding, a mirror station) go to the
/// chain that moves less.
fn better(v: f64, m: f64, bv: f64, bm: f64) -> bool {
    let tie = 1e-9 * v.abs().max(bv.abs());
    v < bv - tie || ((v - bv).abs() <= tie && m < bm)
}

/// For each unit, whether some chain of feasible segments from the start prints it (the
/// chain's last segment ends at or after it).
fn cands_ends(cands: &[Cand], runs: &[Run], best: &[f64]) -> Vec<bool> {
    let n = runs.iter().map(|r| r.j + 1).max().unwrap_or(0);
    let mut covered = vec![false; n];
    for (ci, c) in cands.iter().enumerate() {
        if best[ci].is_finite() {
            let r = &runs[c.run];
            for u in covered.iter_mut().take(r.j + 1).skip(r.i) {
                *u = true;
            }
        }
    }
    covered
}

/// The error of a path no plan covers: the first unit no chain of feasible segments reaches,
/// with its moves and lines and why the candidates failed there.
fn uncovered(
    p: &StationsProblem,
    units: &[Unit],
    runs: &[Run],
    evaluated: &[Vec<Evaluated>],
    covered: &[bool],
) -> Error {
    let u = (0..units.len())
        .find(|&k| !covered.get(k).copied().unwrap_or(false))
        .unwrap_or(0);
    let unit = &units[u];
    let (first, last) = (unit.first_move, unit.last_move);
    // Why: the candidates evaluated for runs holding this unit alone.
    let mut reasons: BTreeMap<&str, usize> = BTreeMap::new();
    let mut tried = 0;
    let mut feasible_alone = 0;
    let mut example: Option<String> = None;
    for (r, run) in runs.iter().enumerate() {
        if run.i == u && run.j == u {
            for (e, (_, st)) in evaluated[r].iter().zip(&run.stations) {
                tried += 1;
                match &e.outcome {
                    Ok(_) => feasible_alone += 1,
                    Err(x) => {
                        *reasons.entry(x.reason.name()).or_insert(0) += 1;
                        example.get_or_insert_with(|| {
                            format!(
                                "; e.g. from the station at ({:.3}, {:.3}) m facing {:.1}°: {x}",
                                st.x_m,
                                st.y_m,
                                st.heading_rad.to_degrees()
                            )
                        });
                    }
                }
            }
        }
    }
    let n_pos = p.candidates.positions.len();
    let on_wall = runs
        .iter()
        .find(|r| r.i == u && r.j == u)
        .map_or((0, None), |r| r.on_wall);
    let why = if tried == 0 && on_wall.0 > 0 {
        let (s, mv) = on_wall.1.unwrap_or((0, 0));
        let pos = p.candidates.positions[s];
        format!(
            "the {} candidate position(s) within reach stand on walls (a floor disc of radius {:.3} m), e.g. ({:.3}, {:.3}) m on the wall of line {}",
            on_wall.0, p.footprint_m, pos[0], pos[1], p.path.moves[mv].line
        )
    } else if tried == 0 {
        format!(
            "none of the {n_pos} candidate positions has all its points within the arm's reach ({})",
            p.candidates.description
        )
    } else if feasible_alone > 0 {
        format!(
            "{feasible_alone} station(s) print it alone, but none continues a plan of the units before it (consecutive segments need different stations, and the way between two stations, a floor disc of radius {:.3} m, may not cross a printed wall)",
            p.footprint_m
        )
    } else {
        let list: Vec<String> = reasons.iter().map(|(k, v)| format!("{k} {v}")).collect();
        format!(
            "of the {tried} candidate stations within reach, none is feasible: {}{}",
            list.join(", "),
            example.unwrap_or_default()
        )
    };
    Error::Invalid(format!(
        "{}: no plan of stations prints the path: unit {} (moves {}–{}, lines {}–{}, z = {:.3} m, {:.2} m extruded) cannot be printed from any candidate station: {why}",
        p.path.source,
        u,
        first,
        last,
        p.path.moves[first].line,
        p.path.moves[last].line,
        unit.z_m,
        unit.print_length_m
    ))
}
