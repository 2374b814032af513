//! The report of a multi-station plan ([`crate::stations`]): `summary.json`,
//! `stations.csv` (one row per segment) and a self-contained `report.html` with the plan on
//! the top view (the path coloured by station, station markers with their heading, reach
//! circles) and the energy per segment. No physics here: every number arrives computed.

use super::svg::{self, colour, esc, fmt_num, ticks, Frame};
use crate::error::Result;
use crate::evaluate::evaluator::PlacementRow;
use crate::output::RunDir;
use crate::stations::Plan;
use crate::toolpath::{PathSample, Toolpath};
use serde::Serialize;
use std::fmt::Write as _;

/// Everything the plan's report shows.
pub struct StationsReport<'a> {
    /// Page title.
    pub title: String,
    /// Facts about the job (robot, path, objective, options), in order.
    pub meta: Vec<(String, String)>,
    /// The plan.
    pub plan: &'a Plan,
    /// The whole path (part frame, m), drawn on the top view.
    pub path: &'a Toolpath,
    /// The user's cost of one relocation, J.
    pub relocation_cost_j: f64,
    /// The user's cost per metre between stations, J/m.
    pub relocation_cost_per_m_j: f64,
}

/// A station in JSON/CSV units (part frame: m and degrees).
#[derive(Serialize)]
struct StationRow {
    x_m: f64,
    y_m: f64,
    heading_deg: f64,
}

/// One segment in `summary.json`.
#[derive(Serialize)]
struct SegmentRow {
    index: usize,
    units: [usize; 2],
    moves: [usize; 2],
    lines: [usize; 2],
    station: StationRow,
    at: PlacementRow,
    print_length_m: f64,
    energy_j: f64,
    supply_j: f64,
    drives_j: f64,
    standby_j: f64,
    duration_s: f64,
    samples: usize,
}

#[derive(Serialize)]
struct Summary<'a> {
    title: &'a str,
    meta: std::collections::BTreeMap<String, String>,
    relocation_cost_j: f64,
    relocation_cost_per_m_j: f64,
    stations: usize,
    relocations: usize,
    relocation_distance_m: f64,
    relocation_j: f64,
    energy_j: f64,
    total_j: f64,
    segments: Vec<SegmentRow>,
    units: &'a [crate::stations::Unit],
    ways: &'a [crate::stations::floor::Way],
    stats: &'a crate::stations::PlanStats,
}

impl StationsReport<'_> {
    fn rows(&self) -> Vec<SegmentRow> {
        self.plan
            .segments
            .iter()
            .enumerate()
            .map(|(k, s)| SegmentRow {
                index: k + 1,
                units: s.units,
                moves: s.moves,
                lines: s.lines,
                station: StationRow {
                    x_m: s.station.x_m,
                    y_m: s.station.y_m,
                    heading_deg: s.station.heading_rad.to_degrees(),
                },
                at: PlacementRow::from(&s.station.placement),
                print_length_m: s.print_length_m,
                energy_j: s.eval.energy_j,
                supply_j: s.eval.supply_j,
                drives_j: s.eval.drives_j,
                standby_j: s.eval.standby_j,
                duration_s: s.eval.duration_s,
                samples: s.eval.samples,
            })
            .collect()
    }

    /// `summary.json` (docs/json.md, `stations --json`).
    pub fn summary_json(&self) -> Result<String> {
        let p = self.plan;
        let summary = Summary {
            title: &self.title,
            meta: self.meta.iter().cloned().collect(),
            relocation_cost_j: self.relocation_cost_j,
            relocation_cost_per_m_j: self.relocation_cost_per_m_j,
            stations: p.segments.len(),
            relocations: p.relocations,
            relocation_distance_m: p.relocation_distance_m,
            relocation_j: p.relocation_j,
            energy_j: p.energy_j,
            total_j: p.total_j,
            segments: self.rows(),
            units: &p.units,
            ways: &p.ways,
            stats: &p.stats,
        };
        crate::output::check_finite_json("the stations plan", &summary)?;
        crate::output::json_text(&summary)
    }

    /// `stations.csv`: one row per segment (m, deg, J, s).
    pub fn csv(&self) -> String {
        let mut s = String::from(
            "segment,station_x[m],station_y[m],heading[deg],at_x[m],at_y[m],at_z[m],at_yaw[deg],at_spin[deg],first_unit,last_unit,first_move,last_move,first_line,last_line,print_length[m],energy[J],supply[J],drives[J],duration[s],samples\n",
        );
        for r in self.rows() {
            let _ = writeln!(
                s,
                "{},{:.4},{:.4},{:.3},{:.4},{:.4},{:.4},{:.3},{:.3},{},{},{},{},{},{},{:.4},{:.3},{:.3},{:.3},{:.3},{}",
                r.index,
                r.station.x_m,
                r.station.y_m,
                r.station.heading_deg,
                r.at.x_m,
                r.at.y_m,
                r.at.z_m,
                r.at.yaw_deg,
                r.at.spin_deg,
                r.units[0],
                r.units[1],
                r.moves[0],
                r.moves[1],
                r.lines[0],
                r.lines[1],
                r.print_length_m,
                r.energy_j,
                r.supply_j,
                r.drives_j,
                r.duration_s,
                r.samples
            );
        }
        s
    }

    /// The plan on the top view (part frame, equal scales): the path's extruded moves coloured
    /// by the station printing them, travel moves grey (dashed between stations: replaced by
    /// the relocation), each station a numbered disc with a tick along its heading, and its
    /// reach annulus (outer circle solid, inner dashed, from the pre-filter's annulus).
    pub fn top_view_svg(&self) -> String {
        let plan = self.plan;
        let pts = self.path.sample(0.05);
        let fr = PlanFrame::new(plan, &pts);
        let mut s = format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" class="stations-top-view" data-n="{}"><text x="{:.1}" y="20" font-size="14" font-weight="bold" text-anchor="middle">{}</text>"#,
            plan.segments.len() + pts.len(),
            fr.w / 2.0,
            esc("Plan on the top view (part frame)"),
            w = fr.w,
            h = fr.h,
        );
        fr.axes(&mut s);
        fr.reach_circles(&mut s, plan);
        fr.path_moves(&mut s, plan, &pts);
        fr.relocation_ways(&mut s, plan);
        fr.stations(&mut s, plan);
        fr.legend(&mut s, plan);
        s.push_str("</svg>");
        s
    }

    /// The self-contained `report.html`.
    pub fn html(&self) -> String {
        let p = self.plan;
        let mut pg = super::html::Page::new(&self.title);
        pg.kv(&self.meta);
        pg.h2("Plan");
        pg.p(&format!(
            "{} station(s), {} relocation(s) ({:.2} m moved): segment energies {:.1} J + relocations {:.1} J = {:.1} J.",
            p.segments.len(),
            p.relocations,
            p.relocation_distance_m,
            p.energy_j,
            p.relocation_j,
            p.total_j
        ));
        pg.figure(
            "top-view",
            &self.top_view_svg(),
            "The path in its part frame coloured by the station that prints it; discs: stations (the tick points along the robot's heading); circles: the arm's horizontal reach (solid outer, dashed inner) at the station.",
        );
        self.segment_table(&mut pg);
        let cats: Vec<String> = (1..=p.segments.len()).map(|k| k.to_string()).collect();
        let e: Vec<f64> = p.segments.iter().map(|s| s.eval.energy_j).collect();
        pg.figure(
            "energy-per-segment",
            &svg::bar_chart(
                &Frame::new("Energy per segment", "segment (station)", "energy (J)"),
                &cats,
                &[("energy".into(), e)],
            ),
            "Each segment timed and evaluated from rest to rest at its station.",
        );
        model_section(&mut pg, p);
        pg.finish()
    }

    /// The table of segments: station, placement, units, lines, print length, energy, time.
    fn segment_table(&self, pg: &mut super::html::Page) {
        let header: Vec<String> = [
            "segment",
            "station x [m]",
            "station y [m]",
            "heading [°]",
            "placement x,y,z,yaw,spin (m, m, m, °, °)",
            "units",
            "lines",
            "print [m]",
            "energy [J]",
            "time [s]",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        let rows: Vec<Vec<String>> = self
            .rows()
            .iter()
            .map(|r| {
                vec![
                    r.index.to_string(),
                    format!("{:.3}", r.station.x_m),
                    format!("{:.3}", r.station.y_m),
                    format!("{:.1}", r.station.heading_deg),
                    format!(
                        "{:.3},{:.3},{:.3},{:.2},{:.2}",
                        r.at.x_m, r.at.y_m, r.at.z_m, r.at.yaw_deg, r.at.spin_deg
                    ),
                    format!("{}–{}", r.units[0], r.units[1]),
                    format!("{}–{}", r.lines[0], r.lines[1]),
                    format!("{:.2}", r.print_length_m),
                    format!("{:.1}", r.energy_j),
                    format!("{:.2}", r.duration_s),
                ]
            })
            .collect();
        pg.table(&header, &rows);
    }
    /// Write `summary.json`, `stations.csv` and `report.html` into a run directory being
    /// written (commit it afterwards).
    pub fn write_into(&self, rd: &mut RunDir) -> Result<()> {
        rd.write("summary.json", self.summary_json()?.as_bytes())?;
        rd.write("stations.csv", self.csv().as_bytes())?;
        rd.write("report.html", self.html().as_bytes())?;
        Ok(())
    }
}

/// The model section: how the path is split and checked, and the search's candidates.
fn model_section(pg: &mut super::html::Page, p: &Plan) {
    pg.h2("Model");
    pg.p("The path is split only between units: maximal runs of extruding moves at one z level (a unit ends at a travel move or a layer change). Each segment is timed and its energy computed from rest to rest at its station, with the feasibility checks of sweep and optimise (reach with one arm configuration, joint limits and margins, singularity margins, collisions with the bed, the beads the segment lays and the walls the earlier segments printed). A station stands on no wall printed before or by its segment (its floor disc, the robot's foot with its carriage or crawler), and the straight way to the next station (that disc swept) crosses no wall printed before the move: a plan whose way needs a detour is refused. The travel between two stations' segments is replaced by the relocation, whose cost is the number given, not modelled.");
    pg.kv(&[
        (
            "units".into(),
            format!("{} (where the path may be split)", p.stats.units),
        ),
        (
            "candidates".into(),
            format!(
                "{} positions; {} runs of units evaluated from {} stations ({} feasible)",
                p.stats.positions, p.stats.runs, p.stats.evaluations, p.stats.feasible
            ),
        ),
        (
            "reach pre-filter".into(),
            format!(
                "annulus {:.3}–{:.3} m, slack {:.3} m",
                p.stats.annulus_m.0, p.stats.annulus_m.1, p.stats.slack_m
            ),
        ),
    ]);
}

/// The drawing frame of the plan's top view: its size and margins (px), the equal-scaled
/// extent it shows (part frame, m) and the scale (px per metre).
struct PlanFrame {
    w: f64,
    h: f64,
    ml: f64,
    mr: f64,
    mt: f64,
    mb: f64,
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
    k: f64,
}

impl PlanFrame {
    /// The frame showing the path samples `pts` and the plan's stations with their outer reach.
    fn new(plan: &Plan, pts: &[PathSample]) -> Self {
        let (_, r_out) = plan.stats.annulus_m;
        let (w, h) = (900.0, 520.0);
        let (ml, mr, mt, mb) = (60.0, 150.0, 36.0, 46.0);
        let mut ext = [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        let mut grow = |x: f64, y: f64| {
            ext[0] = ext[0].min(x);
            ext[1] = ext[1].max(x);
            ext[2] = ext[2].min(y);
            ext[3] = ext[3].max(y);
        };
        for q in pts {
            grow(q.p.x, q.p.y);
        }
        for s in &plan.segments {
            grow(s.station.x_m - r_out, s.station.y_m - r_out);
            grow(s.station.x_m + r_out, s.station.y_m + r_out);
        }
        let pad = 0.03 * (ext[1] - ext[0]).max(ext[3] - ext[2]).max(0.1);
        let ((x0, x1, y0, y1), k) = svg::equal_scales(
            (ext[0] - pad, ext[1] + pad, ext[2] - pad, ext[3] + pad),
            (w - ml - mr, h - mt - mb),
        );
        PlanFrame {
            w,
            h,
            ml,
            mr,
            mt,
            mb,
            x0,
            x1,
            y0,
            y1,
            k,
        }
    }

    /// Horizontal position of `x` (m), px.
    fn px(&self, x: f64) -> f64 {
        self.ml + (x - self.x0) * self.k
    }

    /// Vertical position of `y` (m), px.
    fn py(&self, y: f64) -> f64 {
        self.mt + (self.y1 - y) * self.k
    }

    /// Draw the grid lines with their ticks, the plot's border and the axis labels.
    fn axes(&self, s: &mut String) {
        let (w, h, ml, mr, mt, mb) = (self.w, self.h, self.ml, self.mr, self.mt, self.mb);
        let (pw, ph) = (w - ml - mr, h - mt - mb);
        for t in ticks(self.x0, self.x1, 8) {
            let _ = write!(
                s,
                r##"<line x1="{0:.1}" y1="{1:.1}" x2="{0:.1}" y2="{2:.1}" stroke="#eee"/><text x="{0:.1}" y="{3:.1}" font-size="10" text-anchor="middle">{4}</text>"##,
                self.px(t),
                mt,
                h - mb,
                h - mb + 14.0,
                fmt_num(t)
            );
        }
        for t in ticks(self.y0, self.y1, 5) {
            let _ = write!(
                s,
                r##"<line x1="{0:.1}" y1="{1:.1}" x2="{2:.1}" y2="{1:.1}" stroke="#eee"/><text x="{3:.1}" y="{4:.1}" font-size="10" text-anchor="end">{5}</text>"##,
                ml,
                self.py(t),
                w - mr,
                ml - 4.0,
                self.py(t) + 3.0,
                fmt_num(t)
            );
        }
        let _ = write!(
            s,
            r##"<rect x="{ml}" y="{mt}" width="{pw:.1}" height="{ph:.1}" fill="none" stroke="#999"/><text x="{:.1}" y="{:.1}" font-size="12" text-anchor="middle">x (m)</text><text x="14" y="{:.1}" font-size="12" text-anchor="middle" transform="rotate(-90 14 {:.1})">y (m)</text>"##,
            ml + pw / 2.0,
            h - 8.0,
            mt + ph / 2.0,
            mt + ph / 2.0
        );
    }

    /// Draw each station's reach annulus: the outer circle solid, the inner one dashed.
    fn reach_circles(&self, s: &mut String, plan: &Plan) {
        let (r_in, r_out) = plan.stats.annulus_m;
        for (n, sg) in plan.segments.iter().enumerate() {
            let c = colour(n);
            let (sx, sy) = (self.px(sg.station.x_m), self.py(sg.station.y_m));
            let _ = write!(
                s,
                r#"<g class="reach"><circle cx="{sx:.1}" cy="{sy:.1}" r="{:.1}" fill="{c}" fill-opacity="0.05" stroke="{c}" stroke-width="1"/><circle cx="{sx:.1}" cy="{sy:.1}" r="{:.1}" fill="none" stroke="{c}" stroke-width="1" stroke-dasharray="4 3"/></g>"#,
                r_out * self.k,
                r_in * self.k
            );
        }
    }

    /// Draw the path move by move: one polyline per run of samples with the same owning segment
    /// and the same kind (print or travel); travel between stations dashed.
    fn path_moves(&self, s: &mut String, plan: &Plan, pts: &[PathSample]) {
        let owner = |mi: usize| {
            plan.segments
                .iter()
                .position(|sg| mi >= sg.moves[0] && mi <= sg.moves[1])
        };
        let mut cur: Option<(Option<usize>, bool, String)> = None;
        let mut paths: Vec<(Option<usize>, bool, String)> = Vec::new();
        let mut last_pt: Option<(f64, f64)> = None;
        for q in pts.iter().skip(1) {
            let o = owner(q.move_index);
            let key = (o, q.print);
            let start = !matches!(&cur, Some((co, cp, _)) if (*co, *cp) == key);
            if start {
                if let Some(c) = cur.take() {
                    paths.push(c);
                }
                let (lx, ly) = last_pt.unwrap_or((q.p.x, q.p.y));
                cur = Some((
                    o,
                    q.print,
                    format!("M{:.1},{:.1}", self.px(lx), self.py(ly)),
                ));
            }
            if let Some((_, _, d)) = cur.as_mut() {
                let _ = write!(d, " L{:.1},{:.1}", self.px(q.p.x), self.py(q.p.y));
            }
            last_pt = Some((q.p.x, q.p.y));
        }
        if let Some(c) = cur.take() {
            paths.push(c);
        }
        for (o, print, d) in &paths {
            let (stroke, width, dash, class) = match (o, print) {
                (Some(n), true) => (colour(*n), 2.5, "", format!("print segment-{}", n + 1)),
                (Some(_), false) => ("#888", 1.0, "", "travel".to_string()),
                (None, _) => (
                    "#bbb",
                    1.0,
                    r#" stroke-dasharray="3 3""#,
                    "relocation-travel".into(),
                ),
            };
            let _ = write!(
                s,
                r#"<path class="{class}" d="{d}" fill="none" stroke="{stroke}" stroke-width="{width}"{dash}/>"#
            );
        }
    }

    /// Draw the ways of the relocations (the floor disc's centre; a detour around printed walls
    /// where the straight line crosses one).
    fn relocation_ways(&self, s: &mut String, plan: &Plan) {
        for (n, way) in plan.ways.iter().enumerate() {
            let d: Vec<String> = way
                .points
                .iter()
                .map(|q| format!("{:.1},{:.1}", self.px(q[0]), self.py(q[1])))
                .collect();
            let _ = write!(
                s,
                r##"<polyline class="relocation-way" points="{}" fill="none" stroke="#333" stroke-width="1.5" stroke-dasharray="6 4"><title>relocation {} → {}: {:.2} m{}</title></polyline>"##,
                d.join(" "),
                n + 1,
                n + 2,
                way.length_m,
                if way.points.len() > 2 {
                    ", around printed walls"
                } else {
                    ""
                }
            );
        }
    }

    /// Draw the stations: a numbered disc with a tick along its heading.
    fn stations(&self, s: &mut String, plan: &Plan) {
        for (n, sg) in plan.segments.iter().enumerate() {
            let c = colour(n);
            let (sx, sy) = (self.px(sg.station.x_m), self.py(sg.station.y_m));
            let hd = sg.station.heading_rad;
            let _ = write!(
                s,
                r#"<g class="station"><line x1="{sx:.1}" y1="{sy:.1}" x2="{:.1}" y2="{:.1}" stroke="{c}" stroke-width="2"/><circle cx="{sx:.1}" cy="{sy:.1}" r="8" fill="{c}" stroke="black" stroke-width="1"><title>station {}: ({:.3}, {:.3}) m, heading {:.1}°; lines {}–{}; {:.1} J</title></circle><text x="{sx:.1}" y="{:.1}" font-size="10" font-weight="bold" fill="white" text-anchor="middle">{}</text></g>"#,
                sx + 18.0 * hd.cos(),
                sy - 18.0 * hd.sin(),
                n + 1,
                sg.station.x_m,
                sg.station.y_m,
                hd.to_degrees(),
                sg.lines[0],
                sg.lines[1],
                sg.eval.energy_j,
                sy + 3.5,
                n + 1
            );
        }
    }

    /// Draw the legend right of the plot: each station's energy, the kinds of line, the reach.
    fn legend(&self, s: &mut String, plan: &Plan) {
        let (r_in, r_out) = plan.stats.annulus_m;
        let lx = self.w - self.mr + 12.0;
        let mut ly = self.mt + 10.0;
        for (n, sg) in plan.segments.iter().enumerate() {
            let _ = write!(
                s,
                r#"<line x1="{lx}" y1="{ly:.1}" x2="{:.1}" y2="{ly:.1}" stroke="{}" stroke-width="3"/><text x="{:.1}" y="{:.1}" font-size="11">station {}: {} J</text>"#,
                lx + 14.0,
                colour(n),
                lx + 18.0,
                ly + 4.0,
                n + 1,
                fmt_num(sg.eval.energy_j)
            );
            ly += 16.0;
        }
        for (style, text) in [
            (r##"stroke="#888""##, "travel"),
            (
                r##"stroke="#bbb" stroke-dasharray="3 3""##,
                "replaced by relocation",
            ),
            (
                r##"stroke="#333" stroke-width="1.5" stroke-dasharray="6 4""##,
                "relocation way",
            ),
        ] {
            let _ = write!(
                s,
                r#"<line x1="{lx}" y1="{ly:.1}" x2="{:.1}" y2="{ly:.1}" {style}/><text x="{:.1}" y="{:.1}" font-size="11">{text}</text>"#,
                lx + 14.0,
                lx + 18.0,
                ly + 4.0
            );
            ly += 16.0;
        }
        let _ = write!(
            s,
            r##"<text x="{lx}" y="{:.1}" font-size="10">reach {}–{} m</text>"##,
            ly + 4.0,
            fmt_num(r_in),
            fmt_num(r_out)
        );
    }
}
