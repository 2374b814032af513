//! The report of a placement run under `results/<run>/`: `summary.json` and `placements.csv`
//! for scripts, `report.html` (self-contained, inline SVG) for people. Numbers arrive
//! computed; this module only formats them.
//!
//! Figures: a top view drawn to scale (equal axis scales) with the robot base, the reachable
//! annulus at the bed height, the part outline at the optimum and the energy over (x, y) at the
//! best grid cell's bed height and yaw (infeasible cells crossed by reason; the colour bar
//! covers the optimum; the ring marks the best grid cell, which is feasible, the dot the refined
//! optimum); for named sets (P1–P5) the named positions on the same map, with seed 000's values
//! beside ours for that reproduction; slices of energy against bed height and yaw through the
//! best cell; energy per placement (bars); the supply breakdown stacked (standby, motion work,
//! losses by kind); energy per joint; power–time curves per joint (decimated to the pixel
//! columns) and the cumulative energy at the best and worst placements; infeasible placements
//! counted by reason, their details collapsed.

use super::html::Page;
use super::site::SiteGeometry;
use super::svg::{self, CellMark, Heatmap, MapPoint, Series, TopView};
use crate::energy::EnergyReport;
use crate::error::{Error, Result};
use crate::evaluate::evaluator::{Evaluated, PlacementRow};
use crate::output::{Existing, Inputs, RunDir};
use crate::search::grid::Grid;
use crate::search::optimise::OptimiseResult;
use serde::Serialize;
use std::path::Path;

/// Where the energy bars start when they start at the standby: (floor, lowest standby,
/// highest standby), J.
type BarsFloor = (f64, f64, f64);

/// A placement reported in detail: its energy report and what the charts draw of its series.
#[derive(Clone, Debug)]
pub struct Detail {
    /// Label (e.g. "best", "worst", "baseline", "P1").
    pub label: String,
    /// The placement's sweep entry.
    pub eval: Evaluated,
    /// Its energy report (the per-sample series may be left empty when `charts` is given).
    pub energy: EnergyReport,
    /// The power and cumulative-energy charts' series taken in sample by sample
    /// ([`DetailCharts`]); `None`: the charts are drawn from `energy.series`.
    pub charts: Option<DetailCharts>,
}

/// The series the report's power and cumulative-energy charts of a detailed placement draw,
/// taken in sample by sample as the energy is evaluated
/// ([`crate::energy::evaluate_streaming`]): the charts' decimated points only, so a placement
/// reported in detail holds no per-sample series. The charts are those drawn from the whole
/// series, byte for byte.
#[derive(Clone, Debug)]
pub struct DetailCharts {
    /// Drawn with electrical (true) or mechanical (false) power.
    pub electrical: bool,
    n: usize,
    power: Vec<svg::StreamedSeries>,
    cumulative: Vec<svg::StreamedSeries>,
    /// Running integrals (supply first when electrical, then the joints) and the previous
    /// sample's time and values.
    acc: Vec<f64>,
    prev: Option<(f64, Vec<f64>)>,
    now: Vec<f64>,
}

impl DetailCharts {
    /// Charts of `samples` samples of a robot with joints `names`, with electrical or
    /// mechanical power (the report's choice, [`RunReport::electrical`]).
    pub fn new(names: &[String], samples: usize, electrical: bool) -> Self {
        let joint_names: Vec<&str> = names.iter().map(|s| s.as_str()).collect();
        let pf = svg::Frame::new("", "", "").size(760.0, 360.0);
        let pb = svg::line_buckets(&pf, &joint_names);
        let mut cum_names = Vec::new();
        if electrical {
            cum_names.push("supply");
        }
        cum_names.extend(joint_names.iter().copied());
        let cf = svg::Frame::new("", "", "").size(760.0, 320.0);
        let cb = svg::line_buckets(&cf, &cum_names);
        DetailCharts {
            electrical,
            n: names.len(),
            power: joint_names
                .iter()
                .map(|n| svg::StreamedSeries::new(n, samples, pb))
                .collect(),
            cumulative: cum_names
                .iter()
                .map(|n| svg::StreamedSeries::new(n, samples, cb))
                .collect(),
            acc: vec![0.0; cum_names.len()],
            prev: None,
            now: vec![0.0; cum_names.len()],
        }
    }

    /// The next sample at time `t`, s.
    pub fn push(&mut self, t: f64, s: &crate::energy::SamplePower) {
        let n = self.n;
        let p = if self.electrical { &s.p_el } else { &s.p_mech };
        for (series, &v) in self.power.iter_mut().zip(&p[..n]) {
            series.push(t, v);
        }
        let off = usize::from(self.electrical);
        if self.electrical {
            self.now[0] = s.p_supply;
        }
        self.now[off..off + n].copy_from_slice(&p[..n]);
        // crate::numerics::cumulative_trapezoid, one sample at a time.
        if let Some((t0, y0)) = &self.prev {
            for (i, a) in self.acc.iter_mut().enumerate() {
                *a += 0.5 * (self.now[i] + y0[i]) * (t - t0);
            }
        }
        for (c, a) in self.cumulative.iter_mut().zip(&self.acc) {
            c.push(t, *a);
        }
        match &mut self.prev {
            Some((t0, y0)) => {
                *t0 = t;
                y0.copy_from_slice(&self.now);
            }
            None => self.prev = Some((t, self.now.clone())),
        }
    }

    /// Every sample is in.
    pub fn finish(&mut self) {
        for s in self.power.iter_mut().chain(self.cumulative.iter_mut()) {
            s.finish();
        }
    }
}

/// Everything a run report shows.
#[derive(Clone, Debug)]
pub struct RunReport {
    /// Title of the page.
    pub title: String,
    /// Free-form facts shown at the top and stored in `summary.json` (`meta`).
    pub meta: Vec<(String, String)>,
    /// Every evaluated placement, in sweep order.
    pub rows: Vec<Evaluated>,
    /// Names of the rows (named sets), same length as `rows` when given.
    pub names: Option<Vec<String>>,
    /// The grid the rows come from, when they do (for the heatmap).
    pub grid: Option<Grid>,
    /// Search result, for `optimise`.
    pub optimise: Option<OptimiseResult>,
    /// Baseline placement and how it was chosen, for `optimise`.
    pub baseline: Option<(String, Evaluated)>,
    /// Placements reported in detail.
    pub details: Vec<Detail>,
    /// Use electrical (true) or mechanical (false) power in the per-joint figures.
    pub electrical: bool,
    /// The cell drawn to scale (annulus, part outline, published values), when known.
    pub site: Option<SiteGeometry>,
}

#[derive(Serialize)]
struct JointSummary {
    name: String,
    mechanical_j: f64,
    electrical_j: f64,
    electrical_positive_j: f64,
    share_pct: f64,
}

#[derive(Serialize)]
struct DetailSummary {
    label: String,
    placement: PlacementRow,
    supply_j: f64,
    mechanical_j: f64,
    electrical_j: f64,
    duration_s: f64,
    joints: Vec<JointSummary>,
}

#[derive(Serialize)]
struct Summary<'a> {
    title: &'a str,
    meta: std::collections::BTreeMap<String, String>,
    placements: usize,
    feasible: usize,
    infeasible_by_reason: std::collections::BTreeMap<&'static str, usize>,
    best: Option<&'a Evaluated>,
    worst: Option<&'a Evaluated>,
    spread_pct: Option<f64>,
    reduction_pct: Option<f64>,
    baseline: Option<(&'a str, &'a Evaluated)>,
    saving_j: Option<f64>,
    saving_pct: Option<f64>,
    optimise: Option<&'a OptimiseResult>,
    details: Vec<DetailSummary>,
    named: Option<Vec<(String, &'a Evaluated)>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    rows: Option<&'a [Evaluated]>,
}

impl RunReport {
    /// Best feasible row or the optimiser's answer.
    pub fn best(&self) -> Option<&Evaluated> {
        self.optimise
            .as_ref()
            .map(|o| &o.best)
            .or_else(|| crate::search::optimise::best_of(&self.rows))
    }

    /// Saving of the best against the baseline, (J, %).
    pub fn saving(&self) -> Option<(f64, f64)> {
        let b = self.baseline.as_ref()?.1.cost();
        let o = self.best()?.cost();
        (b.is_finite() && o.is_finite() && b != 0.0).then(|| {
            (
                crate::numerics::difference(b, o),
                crate::numerics::relative_difference_pct(b, o),
            )
        })
    }

    /// Spread (max − min) / min over feasible rows, %.
    pub fn spread_pct(&self) -> Option<f64> {
        let lo = crate::search::optimise::best_of(&self.rows)?.cost();
        let hi = crate::search::optimise::worst_of(&self.rows)?.cost();
        (lo > 0.0).then(|| crate::numerics::difference(hi, lo) / lo * 100.0)
    }

    /// Reduction (max − min) / max over feasible rows, % (seed 000's 53.72 % definition).
    pub fn reduction_pct(&self) -> Option<f64> {
        let lo = crate::search::optimise::best_of(&self.rows)?.cost();
        let hi = crate::search::optimise::worst_of(&self.rows)?.cost();
        (hi > 0.0).then(|| crate::numerics::relative_difference_pct(hi, lo))
    }

    /// `summary.json`: counts, best/worst, spread, baseline and saving, search result and
    /// sensitivity, per-joint energies of the detailed placements; every row with `with_rows`.
    pub fn summary_json(&self, with_rows: bool) -> Result<String> {
        self.summary_json_with(with_rows, &[])
    }

    /// [`RunReport::summary_json`] with `extra` top-level fields (a command's `warnings`),
    /// written straight from the report ([`crate::output::json_text_with`]): no JSON value
    /// tree of the rows is built.
    pub fn summary_json_with(
        &self,
        with_rows: bool,
        extra: &[(&str, serde_json::Value)],
    ) -> Result<String> {
        let mut reasons = std::collections::BTreeMap::new();
        for r in &self.rows {
            if let Err(e) = &r.outcome {
                *reasons.entry(e.reason.name()).or_insert(0) += 1;
            }
        }
        let details = self
            .details
            .iter()
            .map(|d| {
                let tot_el: f64 = d.energy.joints.iter().map(|j| self.joint_value(j)).sum();
                DetailSummary {
                    label: d.label.clone(),
                    placement: PlacementRow::from(&d.eval.placement),
                    supply_j: d.energy.total.supply_j,
                    mechanical_j: d.energy.total.mechanical_j,
                    electrical_j: d.energy.total.electrical_j,
                    duration_s: d.energy.duration_s,
                    joints: d
                        .energy
                        .joints
                        .iter()
                        .map(|j| JointSummary {
                            name: j.name.clone(),
                            mechanical_j: j.mechanical_j,
                            electrical_j: j.electrical_j,
                            electrical_positive_j: j.electrical_positive_j,
                            share_pct: if tot_el != 0.0 {
                                self.joint_value(j) / tot_el * 100.0
                            } else {
                                0.0
                            },
                        })
                        .collect(),
                }
            })
            .collect();
        let s = Summary {
            title: &self.title,
            meta: self.meta.iter().cloned().collect(),
            placements: self.rows.len(),
            feasible: self.rows.iter().filter(|r| r.cost().is_finite()).count(),
            infeasible_by_reason: reasons,
            best: self.best(),
            worst: crate::search::optimise::worst_of(&self.rows),
            spread_pct: self.spread_pct(),
            reduction_pct: self.reduction_pct(),
            baseline: self.baseline.as_ref().map(|(s, e)| (s.as_str(), e)),
            saving_j: self.saving().map(|s| s.0),
            saving_pct: self.saving().map(|s| s.1),
            optimise: self.optimise.as_ref(),
            details,
            named: self
                .names
                .as_ref()
                .map(|n| n.iter().cloned().zip(self.rows.iter()).collect()),
            rows: with_rows.then_some(self.rows.as_slice()),
        };
        crate::output::json_text_with(&s, extra)
    }

    fn joint_value(&self, j: &crate::energy::JointEnergy) -> f64 {
        if self.electrical {
            j.electrical_j
        } else {
            j.mechanical_j
        }
    }

    /// `placements.csv`: one row per placement (m, deg, J, s), reason and where for
    /// infeasible ones.
    pub fn placements_csv(&self) -> String {
        let mut s = String::from(
            "name,x_m,y_m,z_m,yaw_deg,spin_deg,feasible,energy_j,supply_j,mechanical_j,mechanical_abs_j,electrical_j,duration_s,rounds,reason,sample,t_s,line,detail\n",
        );
        for (i, r) in self.rows.iter().enumerate() {
            let p = PlacementRow::from(&r.placement);
            let name = self
                .names
                .as_ref()
                .and_then(|n| n.get(i).cloned())
                .unwrap_or_else(|| i.to_string());
            s.push_str(&format!(
                "{},{},{},{},{},{},",
                csv_cell(&name),
                p.x_m,
                p.y_m,
                p.z_m,
                p.yaw_deg,
                p.spin_deg
            ));
            match &r.outcome {
                Ok(f) => s.push_str(&format!(
                    "true,{},{},{},{},{},{},{},,,,,\n",
                    f.energy_j,
                    f.supply_j,
                    f.mechanical_j,
                    f.mechanical_abs_j,
                    f.electrical_j,
                    f.duration_s,
                    f.rounds
                )),
                Err(e) => s.push_str(&format!(
                    "false,,,,,,,,{},{},{},{},{}\n",
                    e.reason.name(),
                    e.sample.map(|v| v.to_string()).unwrap_or_default(),
                    e.t_s.map(|v| v.to_string()).unwrap_or_default(),
                    e.line.map(|v| v.to_string()).unwrap_or_default(),
                    csv_cell(&e.detail)
                )),
            }
        }
        s
    }

    /// Indices `(iz, iyaw)` of the best feasible grid row's bed height and yaw, and its (ix, iy).
    fn best_cell(&self, g: &Grid) -> Option<[usize; 4]> {
        if self.rows.len() != g.len() {
            return None;
        }
        let b = crate::search::optimise::best_of(&self.rows)?;
        let near = |v: &[f64], x: f64| {
            v.iter()
                .enumerate()
                .min_by(|a, b| (a.1 - x).abs().total_cmp(&(b.1 - x).abs()))
                .map(|(i, _)| i)
                .unwrap_or(0)
        };
        let p = &b.placement;
        Some([
            near(&g.xs, p.x),
            near(&g.ys, p.y),
            near(&g.zs, p.z),
            near(&g.yaws, p.yaw),
        ])
    }

    /// Energy of grid cell (ix, iy, iz, iyaw), minimum over the nozzle spins (a flat direction);
    /// `Err(reason)` when every spin is infeasible.
    fn cell(
        &self,
        g: &Grid,
        ix: usize,
        iy: usize,
        iz: usize,
        iyaw: usize,
    ) -> std::result::Result<f64, &'static str> {
        let mut best = f64::INFINITY;
        let mut why = "infeasible";
        for isp in 0..g.spins.len() {
            match &self.rows[g.index(ix, iy, iz, iyaw, isp)].outcome {
                Ok(_) => best = best.min(self.rows[g.index(ix, iy, iz, iyaw, isp)].cost()),
                Err(e) => why = e.reason.name(),
            }
        }
        if best.is_finite() {
            Ok(best)
        } else {
            Err(why)
        }
    }

    /// The top view drawn to scale: the energy over (x, y) at the best grid cell's bed height
    /// and yaw (a slice, not a minimum over them), or the named placements of a set; the robot
    /// base, the reachable annulus and the part outline at the optimum.
    pub fn heatmap_svg(&self) -> Option<String> {
        let mut v = TopView {
            value_label: "energy [J]".into(),
            ..Default::default()
        };
        let title;
        if let Some(g) = self
            .grid
            .as_ref()
            .filter(|g| g.xs.len() >= 2 && g.ys.len() >= 2)
        {
            title = self.energy_cells(g, &mut v)?;
        } else if let Some(names) = &self.names {
            for (n, r) in names.iter().zip(&self.rows) {
                v.points.push(MapPoint {
                    x: r.placement.x,
                    y: r.placement.y,
                    label: n.clone(),
                    value: r.cost(),
                    class: "named".into(),
                });
            }
            title = "Top view (to scale): the named placements".into();
        } else {
            return None;
        }
        let best = self.best().filter(|b| b.cost().is_finite());
        if let Some(b) = best {
            // The refined optimum: only an optimisation has one off the grid.
            if self.grid.is_some() && self.optimise.is_some() {
                v.points.push(MapPoint {
                    x: b.placement.x,
                    y: b.placement.y,
                    label: "optimum".into(),
                    value: b.cost(),
                    class: "optimum".into(),
                });
            }
        }
        self.base_shapes(&mut v);
        if let Some(site) = &self.site {
            self.site_shapes(site, best, &mut v);
        }
        let f =
            svg::Frame::new(&title, "x in the robot base frame [m]", "y [m]").size(900.0, 640.0);
        Some(svg::top_view(&f, &v))
    }

    /// Put the energy over (x, y) at the best grid cell's bed height and yaw on the top view,
    /// infeasible cells marked by reason and the best cell ringed; returns the view's title.
    fn energy_cells(&self, g: &Grid, v: &mut TopView) -> Option<String> {
        let [bx, by, iz, iyaw] = self.best_cell(g)?;
        let (nx, ny) = (g.xs.len(), g.ys.len());
        let mut values = vec![f64::NAN; nx * ny];
        let mut marks = Vec::new();
        for iy in 0..ny {
            for ix in 0..nx {
                match self.cell(g, ix, iy, iz, iyaw) {
                    Ok(e) => values[iy * nx + ix] = e,
                    Err(why) => marks.push(CellMark {
                        col: ix,
                        row: iy,
                        class: why.to_string(),
                        at: None,
                    }),
                }
            }
        }
        let title = format!(
            "Top view (to scale): energy at bed z = {} m, yaw = {}°",
            svg::fmt_num(g.zs[iz]),
            svg::fmt_num(g.yaws[iyaw].to_degrees())
        );
        v.points.push(MapPoint {
            x: g.xs[bx],
            y: g.ys[by],
            label: String::new(),
            value: values[by * nx + bx],
            class: "best-cell".into(),
        });
        v.cells = Some(Heatmap {
            xs: g.xs.clone(),
            ys: g.ys.clone(),
            values,
            marks,
            value_label: "energy [J]".into(),
        });
        Some(title)
    }

    /// Put the robot base on the top view to scale: the pedestal under it, the base's own
    /// footprint (its collision geometry from above), or a marker at axis 1 when the robot
    /// file has none.
    fn base_shapes(&self, v: &mut TopView) {
        let footprint = self
            .site
            .as_ref()
            .map(|s| s.base_footprint_m.clone())
            .unwrap_or_default();
        if let Some((h, r)) = self.site.as_ref().and_then(|s| s.pedestal_m) {
            v.circles.push((
                0.0,
                0.0,
                r,
                "pedestal".into(),
                format!(
                    "pedestal ({} m high, radius {} m)",
                    svg::fmt_num(h),
                    svg::fmt_num(r)
                ),
            ));
        }
        if footprint.len() >= 3 {
            v.footprints.push((
                "base".into(),
                "robot base (collision geometry from above)".into(),
                footprint,
            ));
        } else {
            v.circles
                .push((0.0, 0.0, 0.12, "base".into(), "robot base (axis 1)".into()));
        }
    }

    /// Put the site on the top view: the reach annulus and the part's outline at the best
    /// placement.
    fn site_shapes(&self, site: &SiteGeometry, best: Option<&Evaluated>, v: &mut TopView) {
        if let Some((lo, hi)) = site.annulus_m {
            v.circles.push((
                0.0,
                0.0,
                hi,
                "reach".into(),
                format!("reach {}–{} m", svg::fmt_num(lo), svg::fmt_num(hi)),
            ));
            if lo > 0.0 {
                v.circles
                    .push((0.0, 0.0, lo, "reach-inner".into(), "inner reach".into()));
            }
        }
        if let (Some(b), false) = (best, site.part_xy_m.is_empty()) {
            let f = b.placement.frame();
            let pts = site
                .part_xy_m
                .iter()
                .map(|&(x, y)| {
                    let p = f.apply(&crate::math::V3::new(x, y, 0.0));
                    (p.x, p.y)
                })
                .collect();
            let what = if self.optimise.is_some() {
                "part at the optimum"
            } else {
                "part at the best placement"
            };
            v.lines.push((what.into(), pts));
        }
    }

    /// Energy against bed height and against yaw through the best grid cell (other variables
    /// at the best cell's values; minimum over spin). `None` where the grid has one value.
    fn slices_svg(&self) -> (Vec<(String, String, String)>, Vec<String>) {
        let mut out = Vec::new();
        let mut notes = Vec::new();
        let Some(g) = self.grid.as_ref() else {
            return (out, notes);
        };
        let Some([ix, iy, iz, iyaw]) = self.best_cell(g) else {
            return (out, notes);
        };
        let val = |iz, iyaw| self.cell(g, ix, iy, iz, iyaw).unwrap_or(f64::NAN);
        // A slice with one feasible point is no curve: said in words instead of drawn.
        let lone = |what: &str, at: &[f64], y: &[f64], unit: &str| -> Option<String> {
            let feasible: Vec<usize> = (0..y.len()).filter(|&k| y[k].is_finite()).collect();
            (feasible.len() < 2).then(|| {
                format!(
                    "Energy against {what} through the best grid cell: only {} of the {} {what}s is feasible{} (no curve to draw).",
                    feasible.len(),
                    y.len(),
                    feasible.first().map_or(String::new(), |&k| format!(
                        ", {}{unit}: {:.1} J",
                        svg::fmt_num(at[k]),
                        y[k]
                    ))
                )
            })
        };
        if g.zs.len() > 1 {
            let y: Vec<f64> = (0..g.zs.len()).map(|k| val(k, iyaw)).collect();
            if let Some(n) = lone("bed height", &g.zs, &y, " m") {
                notes.push(n);
            } else {
                let f = svg::Frame::new(
                    &format!(
                        "Energy against bed height at x = {} m, y = {} m, yaw = {}°",
                        svg::fmt_num(g.xs[ix]),
                        svg::fmt_num(g.ys[iy]),
                        svg::fmt_num(g.yaws[iyaw].to_degrees())
                    ),
                    "bed height z [m]",
                    "energy [J]",
                )
                .size(440.0, 300.0);
                out.push((
                    "slice-z".into(),
                    svg::scatter(&f, &[Series::new("energy", &g.zs, &y)]),
                    "Energy against bed height through the best grid cell (gaps: infeasible)."
                        .into(),
                ));
            }
        }
        if g.yaws.len() > 1 {
            let yaws: Vec<f64> = g.yaws.iter().map(|a| a.to_degrees()).collect();
            let y: Vec<f64> = (0..g.yaws.len()).map(|k| val(iz, k)).collect();
            if let Some(n) = lone("yaw", &yaws, &y, "°") {
                notes.push(n);
                return (out, notes);
            }
            let f = svg::Frame::new(
                &format!(
                    "Energy against yaw at x = {} m, y = {} m, z = {} m",
                    svg::fmt_num(g.xs[ix]),
                    svg::fmt_num(g.ys[iy]),
                    svg::fmt_num(g.zs[iz])
                ),
                "part yaw [°]",
                "energy [J]",
            )
            .size(440.0, 300.0);
            out.push((
                "slice-yaw".into(),
                svg::scatter(&f, &[Series::new("energy", &yaws, &y)]),
                "Energy against part yaw through the best grid cell (gaps: infeasible).".into(),
            ));
        }
        (out, notes)
    }

    /// The top view's caption, naming only what is drawn in it.
    fn heatmap_caption(&self, svg_text: &str) -> String {
        let mut parts = vec![
            "Top view drawn to scale (1 m is as long on both axes): the robot base".to_string(),
        ];
        let site = self.site.as_ref();
        if site.and_then(|s| s.annulus_m).is_some() {
            parts.push("the reach of a downward nozzle at the bed height (dashed)".into());
        }
        if svg_text.contains("class=\"part at the") {
            parts.push(if self.optimise.is_some() {
                "the part outline at the optimum (red)".into()
            } else {
                "the part outline at the best placement (red)".into()
            });
        }
        let mut s = parts.join(", ");
        if svg_text.contains("<rect") && self.grid.is_some() && svg_text.contains("<title>(") {
            s.push_str("; cells: energy at the best cell's bed height and yaw (a slice, not a minimum over them)");
            if svg_text.contains("<g class=\"mark-") && svg_text.contains("stroke-width=\"1.3\"") {
                s.push_str(", crosses mark infeasible cells by reason");
            }
        }
        if self.names.is_some() && self.grid.is_none() {
            s.push_str("; the named placements coloured by their energy (labels of placements at the same spot stacked)");
            if svg_text.contains("data-infeasible") {
                s.push_str(", a red cross marks an infeasible one");
            }
        }
        if svg_text.contains("mark-best-cell") {
            s.push_str(if self.optimise.is_some() {
                "; the ring marks the best grid cell"
            } else {
                "; the ring marks the best placement of the sweep"
            });
        }
        if svg_text.contains("mark-optimum") {
            s.push_str(", the dot the refined optimum");
        }
        s.push('.');
        s
    }

    /// Supply energy of the detailed placements, stacked: standby, motion work (rigid body and
    /// balancer), and the losses by kind. The stack sums to the supply energy.
    fn supply_svg(&self) -> Option<String> {
        if self.details.is_empty() || !self.details.iter().all(|d| d.energy.has_drive) {
            return None;
        }
        let cats: Vec<String> = self.details.iter().map(|d| d.label.clone()).collect();
        let part = |f: &dyn Fn(&crate::energy::TotalEnergy) -> f64| -> Vec<f64> {
            self.details.iter().map(|d| f(&d.energy.total)).collect()
        };
        let parts = vec![
            ("standby".to_string(), part(&|t| t.standby_j)),
            ("rigid-body work".to_string(), part(&|t| t.rigid_body_j)),
            ("balancer".to_string(), part(&|t| t.balancer_j)),
            ("friction".to_string(), part(&|t| t.friction_j)),
            ("gearbox".to_string(), part(&|t| t.gear_j)),
            ("copper".to_string(), part(&|t| t.copper_j)),
            (
                "regeneration lost".to_string(),
                part(&|t| t.regeneration_lost_j),
            ),
        ];
        let f = svg::Frame::new("Supply energy, stacked by kind", "placement", "energy [J]")
            .size(760.0, 360.0);
        Some(svg::stacked_bars(&f, &cats, &parts))
    }

    /// Cumulative energy over time at a detailed placement: supply (with drives) and per joint.
    fn cumulative_svg(&self, d: &Detail) -> String {
        if let Some(c) = d
            .charts
            .as_ref()
            .filter(|c| c.electrical == self.electrical)
        {
            let f = svg::Frame::new(
                &format!("Cumulative energy at the {} placement", d.label),
                "time [s]",
                "energy [J]",
            )
            .size(760.0, 320.0);
            return svg::line_chart_streamed(&f, &c.cumulative);
        }
        let s = &d.energy.series;
        let n = d.energy.joints.len();
        let p = if self.electrical { &s.p_el } else { &s.p_mech };
        let cum = |y: &dyn Fn(usize) -> f64| {
            let v: Vec<f64> = (0..s.t.len()).map(y).collect();
            crate::numerics::cumulative_trapezoid(&s.t, &v)
        };
        let mut series = Vec::new();
        if self.electrical && s.p_supply.len() == s.t.len() {
            series.push(Series::new("supply", &s.t, &cum(&|k| s.p_supply[k])));
        }
        for j in 0..n {
            series.push(Series::new(
                &d.energy.joints[j].name,
                &s.t,
                &cum(&|k| p[k * n + j]),
            ));
        }
        let f = svg::Frame::new(
            &format!("Cumulative energy at the {} placement", d.label),
            "time [s]",
            "energy [J]",
        )
        .size(760.0, 320.0);
        svg::line_chart(&f, &series)
    }

    /// The energy per placement, with where its bars start when they start at the standby
    /// ([`Self::standby_floor`]).
    fn bars_svg(&self) -> Option<(String, Option<BarsFloor>)> {
        let (cats, vals): (Vec<String>, Vec<f64>) = if let Some(n) = &self.names {
            n.iter()
                .cloned()
                .zip(self.rows.iter().map(|r| r.cost()))
                .map(|(a, b)| (a, if b.is_finite() { b } else { f64::NAN }))
                .unzip()
        } else if self.rows.len() <= 12 {
            self.rows
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    let c = r.cost();
                    (format!("#{i}"), if c.is_finite() { c } else { f64::NAN })
                })
                .unzip()
        } else {
            let mut c = Vec::new();
            let mut v = Vec::new();
            if let Some((_, b)) = &self.baseline {
                c.push("baseline".to_string());
                v.push(b.cost());
            }
            if let Some(o) = &self.optimise {
                c.push("best grid".into());
                v.push(o.best_grid.cost());
                c.push("optimum".into());
                v.push(o.best.cost());
                for (k, lab) in ["x−50mm", "x+50mm", "y−50mm", "y+50mm"].iter().enumerate() {
                    c.push(lab.to_string());
                    v.push(o.sensitivity.e_j[k].unwrap_or(f64::NAN));
                }
            }
            if let Some(w) = crate::search::optimise::worst_of(&self.rows) {
                c.push("worst grid".into());
                v.push(w.cost());
            }
            (c, v)
        };
        if cats.is_empty() {
            return None;
        }
        let floor = self.standby_floor(&vals);
        let mut f = svg::Frame::new(
            if floor.is_some() {
                "Energy per placement above the standby every placement draws"
            } else {
                "Energy per placement"
            },
            "placement",
            "energy [J]",
        )
        .size(760.0, 360.0)
        .missing("infeasible");
        if let Some((base, _, _)) = floor {
            f = f.baseline(base);
        }
        Some((svg::bar_chart(&f, &cats, &[("energy".into(), vals)]), floor))
    }

    /// Where the bars of the energy per placement start when the objective includes the
    /// standby (the cabinet at rest for the print time, the same at every placement up to the
    /// print time's change): a round value at or below the smallest standby of the feasible
    /// rows, below every bar; with the standby's range `(floor, min, max)`, J. `None` when the
    /// objective does not include the standby or it is 0.
    fn standby_floor(&self, vals: &[f64]) -> Option<BarsFloor> {
        let feas: Vec<&crate::evaluate::evaluator::Feasible> = self
            .rows
            .iter()
            .chain(self.optimise.as_ref().map(|o| &o.best))
            .chain(self.baseline.as_ref().map(|b| &b.1))
            .filter_map(|r| r.feasible())
            .collect();
        if feas.is_empty()
            || !feas
                .iter()
                .all(|f| (f.energy_j - f.supply_j).abs() <= 1e-9 * f.supply_j.abs().max(1.0))
        {
            return None;
        }
        let lo = feas
            .iter()
            .map(|f| f.standby_j)
            .fold(f64::INFINITY, f64::min);
        let hi = feas.iter().map(|f| f.standby_j).fold(0.0, f64::max);
        let vmin = vals
            .iter()
            .copied()
            .filter(|v| v.is_finite())
            .fold(f64::INFINITY, f64::min);
        if !(lo > 0.0 && lo.is_finite() && vmin.is_finite()) {
            return None;
        }
        // Two significant digits, rounded down: a round number below every bar.
        let top = lo.min(0.98 * vmin);
        let mag = 10f64.powf(top.log10().floor() - 1.0);
        let base = (top / mag).floor() * mag;
        (base > 0.0).then_some((base, lo, hi))
    }

    /// The regret of the recommended placement across the drawn robots: how many draws fall in
    /// each band of regret (its energy minus the best candidate's in that draw).
    fn uncertainty_svg(&self) -> Option<String> {
        let u = self.optimise.as_ref()?.uncertainty.as_ref()?;
        let regret: Vec<f64> = u
            .per_draw_j
            .iter()
            .map(|d| (d[0] - d[1]).max(0.0))
            .filter(|r| r.is_finite())
            .collect();
        if regret.is_empty() {
            return None;
        }
        let hi = regret.iter().copied().fold(0.0, f64::max);
        let bins = 10usize;
        let (cats, counts): (Vec<String>, Vec<f64>) = if hi <= 0.0 {
            (vec!["0 J".into()], vec![regret.len() as f64])
        } else {
            let w = hi / bins as f64;
            let mut c = vec![0.0; bins];
            for r in &regret {
                c[((r / w) as usize).min(bins - 1)] += 1.0;
            }
            (
                (0..bins)
                    .map(|k| {
                        format!(
                            "{}–{}",
                            svg::fmt_num(w * k as f64),
                            svg::fmt_num(w * (k + 1) as f64)
                        )
                    })
                    .collect(),
                c,
            )
        };
        let f = svg::Frame::new(
            &format!(
                "Regret of the recommended placement over {} drawn robots",
                regret.len()
            ),
            "regret: its energy minus the best candidate's in the same draw [J]",
            "draws",
        )
        .size(760.0, 340.0);
        Some(svg::bar_chart(&f, &cats, &[("draws".into(), counts)]))
    }

    /// The robust choice's regret per candidate (expected and 95th percentile), the
    /// recommendation, the nominal answer and the candidates of lowest expected regret.
    fn regret_svg(&self) -> Option<String> {
        let r = self
            .optimise
            .as_ref()
            .and_then(|o| o.decision.as_ref())
            .and_then(|d| d.robust.as_ref())?;
        let mut idx: Vec<usize> = (0..r.candidates.len()).collect();
        idx.sort_by(|&a, &b| {
            r.candidates[a]
                .expected_regret_j
                .total_cmp(&r.candidates[b].expected_regret_j)
                .then(a.cmp(&b))
        });
        let mut shown: Vec<usize> = vec![r.recommended];
        if !shown.contains(&0) {
            shown.push(0);
        }
        for i in idx {
            if shown.len() >= REGRET_BARS {
                break;
            }
            if !shown.contains(&i) {
                shown.push(i);
            }
        }
        shown.sort_by(|&a, &b| {
            r.candidates[a]
                .expected_regret_j
                .total_cmp(&r.candidates[b].expected_regret_j)
                .then(a.cmp(&b))
        });
        let cats: Vec<String> = shown
            .iter()
            .map(|&i| {
                let tag = if i == r.recommended {
                    "recommended"
                } else if i == 0 {
                    "nominal answer"
                } else {
                    "candidate"
                };
                format!("#{i} {tag}")
            })
            .collect();
        let groups = vec![
            (
                "expected regret".to_string(),
                shown
                    .iter()
                    .map(|&i| r.candidates[i].expected_regret_j)
                    .collect(),
            ),
            (
                "95th-percentile regret".to_string(),
                shown
                    .iter()
                    .map(|&i| r.candidates[i].p95_regret_j)
                    .collect(),
            ),
        ];
        let f = svg::Frame::new("Regret per candidate placement", "candidate", "regret [J]")
            .size(760.0, 360.0);
        Some(svg::bar_chart(&f, &cats, &groups))
    }

    fn joints_svg(&self) -> Option<String> {
        let d0 = self.details.first()?;
        let cats: Vec<String> = d0.energy.joints.iter().map(|j| j.name.clone()).collect();
        let groups: Vec<(String, Vec<f64>)> = self
            .details
            .iter()
            .map(|d| {
                (
                    d.label.clone(),
                    d.energy
                        .joints
                        .iter()
                        .map(|j| self.joint_value(j))
                        .collect(),
                )
            })
            .collect();
        let what = if self.electrical {
            "electrical"
        } else {
            "mechanical"
        };
        let f = svg::Frame::new(&format!("Energy per joint ({what})"), "joint", "energy [J]")
            .size(760.0, 360.0);
        Some(svg::bar_chart(&f, &cats, &groups))
    }

    fn power_svg(&self, d: &Detail) -> String {
        let what = if self.electrical {
            "electrical"
        } else {
            "mechanical τ·q̇"
        };
        let f = svg::Frame::new(
            &format!("Power per joint ({what}) at the {} placement", d.label),
            "time [s]",
            "power [W]",
        )
        .size(760.0, 360.0);
        if let Some(c) = d
            .charts
            .as_ref()
            .filter(|c| c.electrical == self.electrical)
        {
            return svg::line_chart_streamed(&f, &c.power);
        }
        let s = &d.energy.series;
        let n = d.energy.joints.len();
        let p = if self.electrical { &s.p_el } else { &s.p_mech };
        let series: Vec<Series> = (0..n)
            .map(|j| {
                let y: Vec<f64> = (0..s.t.len()).map(|k| p[k * n + j]).collect();
                Series::new(&d.energy.joints[j].name, &s.t, &y)
            })
            .collect();
        svg::line_chart(&f, &series)
    }

    /// Rows `placement, ours, paper, ratio` when the run has published values beside it.
    pub(crate) fn reference_rows(&self) -> Option<Vec<Vec<String>>> {
        let (_, refs) = self.site.as_ref()?.reference.as_ref()?;
        let names = self.names.as_ref()?;
        Some(
            refs.iter()
                .map(|(n, paper)| {
                    let ours = names
                        .iter()
                        .position(|x| x == n)
                        .map(|i| self.rows[i].cost())
                        .filter(|c| c.is_finite());
                    vec![
                        n.clone(),
                        ours.map_or("infeasible".into(), |v| format!("{v:.1}")),
                        paper.map_or("n/a".into(), |v| format!("{v:.1}")),
                        match (ours, paper) {
                            (Some(o), Some(p)) if *p > 0.0 => format!("{:.2}", o / p),
                            _ => "n/a".into(),
                        },
                    ]
                })
                .collect(),
        )
    }

    /// The answer card of an optimisation, the first thing on its page: where to put the part,
    /// how much it draws (drives and standby apart) and saves against the baseline, how sure
    /// the answer is (the tolerance box, the uncertainty study when it ran) and what it
    /// assumes (robot file, drive data status, margins, path, print speed). Well-formed XHTML;
    /// `None` without an optimisation.
    pub(crate) fn answer_card(&self) -> Option<String> {
        let o = self.optimise.as_ref()?;
        let b = &o.best;
        let f = b.feasible()?;
        let p = PlacementRow::from(&b.placement);
        let mut items: Vec<(&str, String)> = vec![(
            "where",
            format!(
                "x = {:.3} m, y = {:.3} m, z = {:.3} m, yaw = {:.1}° (nozzle spin {:.1}°), in the robot base frame",
                p.x_m, p.y_m, p.z_m, p.yaw_deg, p.spin_deg
            ),
        )];
        let objective = self
            .meta_value("objective")
            .map(|o| o.split(':').next().unwrap_or("").to_string())
            .unwrap_or_default();
        items.push((
            "how much",
            format!(
                "energy {:.1} J{}, print time {:.2} s: drives {:.1} J, standby {:.1} J (the cabinet at rest for the print time)",
                f.energy_j,
                if objective.is_empty() {
                    String::new()
                } else {
                    format!(" ({objective})")
                },
                f.duration_s,
                f.drives_j,
                f.standby_j
            ),
        ));
        if let (Some(sv), Some((how, base))) = (&o.savings, &self.baseline) {
            let t = |x: (f64, f64)| saving_text(x.0, x.1);
            let mut line = format!(
                "supply {}, drives {}, standby {} against the baseline ({how}: {:.1} J)",
                t(sv.supply),
                t(sv.drives),
                t(sv.standby),
                base.cost()
            );
            if let Some(c) = o.baseline_tolerance.as_ref().filter(|c| !c.holds) {
                line.push_str(&baseline_saving_caveat(c));
            }
            items.push(("saving", line));
        }
        items.push(("how sure", answer_how_sure(o)));
        Some(self.answer_html(&items))
    }

    /// The value of the run description's entry `k`, if it has one.
    fn meta_value(&self, k: &str) -> Option<String> {
        self.meta
            .iter()
            .find(|(key, _)| key == k)
            .map(|(_, v)| v.clone())
    }

    /// The answer card's XHTML: its items, then what it assumes (robot, robot file, drive
    /// data, margins, path, print speed, as far as the run description names them).
    fn answer_html(&self, items: &[(&str, String)]) -> String {
        let mut assumes = Vec::new();
        for (k, label) in [
            ("robot", "robot"),
            ("robot file", "robot file"),
            ("drive data", "drive data"),
            ("feasibility", "margins"),
            ("path", "path"),
            ("print speed", "print speed"),
        ] {
            if let Some(v) = self.meta_value(k) {
                assumes.push(format!("{label}: {v}"));
            }
        }
        let mut h = String::from("<section id=\"answer\" class=\"answer\"><h2>The answer</h2><dl>");
        for (k, v) in items {
            h.push_str(&format!(
                "<dt>{}</dt><dd class=\"answer-{}\">{}</dd>",
                svg::esc(k),
                k.replace(' ', "-"),
                svg::esc(v)
            ));
        }
        h.push_str("<dt>what it assumes</dt><dd class=\"answer-assumes\"><ul>");
        for a in &assumes {
            h.push_str(&format!("<li>{}</li>", svg::esc(a)));
        }
        h.push_str("</ul></dd></dl></section>");
        h
    }

    /// The HTML page.
    pub fn html(&self) -> String {
        let mut pg = Page::new(&self.title);
        if let Some(card) = self.answer_card() {
            pg.raw(&card);
        }
        if !self.meta.iter().any(|(k, _)| k == "drive data") {
            // Every report states the status of its drive data (estimated or not).
            pg.p("drive data: not stated by the caller");
        }
        pg.kv(&self.meta);
        let mut facts = self.summary_facts();
        if let Some(o) = &self.optimise {
            facts.extend(sensitivity_facts(o));
        }
        pg.h2("Summary").kv(&facts);
        self.decision_section(&mut pg);
        if let Some(h) = self.heatmap_svg() {
            pg.figure("heatmap", &h, &self.heatmap_caption(&h));
        }
        let (slices, notes) = self.slices_svg();
        if !slices.is_empty() {
            pg.figure_row(&slices);
        }
        for n in notes {
            pg.p(&n);
        }
        self.reference_section(&mut pg);
        self.bars_figure(&mut pg);
        if let Some(u) = self.uncertainty_svg() {
            pg.figure(
                "uncertainty",
                &u,
                "The uncertainty study: for each robot drawn from the drive data's ranges, how much more energy the recommended placement needs than the best of the candidates in that robot (0: it is the best there); the number of draws in each band of regret.",
            );
        }
        self.joints_section(&mut pg);
        if let Some(sup) = self.supply_svg() {
            pg.figure(
                "supply",
                &sup,
                "Supply energy of the placements reported in detail, stacked: standby, motion work and the losses by kind (negative parts, e.g. work returned by gravity, below zero; the printed total is the supply energy).",
            );
        }
        self.detail_figures(&mut pg);
        self.infeasible_section(&mut pg);
        pg.finish()
    }

    /// The summary's facts up to the sensitivity: placements, the best, the full-path check,
    /// the baseline and its tolerance, the saving, the spread and the uncertainty study.
    fn summary_facts(&self) -> Vec<(String, String)> {
        let feasible = self.rows.iter().filter(|r| r.cost().is_finite()).count();
        let mut facts = vec![(
            "placements".to_string(),
            format!("{} ({} feasible)", self.rows.len(), feasible),
        )];
        if let Some(b) = self.best() {
            facts.push(("best".into(), describe(b)));
        }
        if let Some(c) = self
            .optimise
            .as_ref()
            .and_then(|o| o.path_reduction.as_ref())
        {
            if let Some((k, v)) = full_check_line(c).split_once(": ") {
                facts.push((k.to_string(), v.to_string()));
            }
        }
        let base_tol = self
            .optimise
            .as_ref()
            .and_then(|o| o.baseline_tolerance.as_ref());
        if let Some((how, b)) = &self.baseline {
            facts.push((format!("baseline ({how})"), describe(b)));
            if let Some(c) = base_tol {
                facts.push(("baseline tolerance".into(), baseline_tolerance_text(c)));
            }
        }
        if let Some((j, pct)) = self.saving() {
            let mut t = saving_text(j, pct);
            if let Some(c) = base_tol.filter(|c| !c.holds) {
                t.push_str(&baseline_saving_caveat(c));
            }
            facts.push(("saving vs baseline".into(), t));
        }
        if let Some(s) = self.spread_pct() {
            facts.push((
                "spread (max−min)/min over feasible rows".into(),
                format!("{s:.2} %"),
            ));
        }
        if let Some(u) = self.optimise.as_ref().and_then(|o| o.uncertainty.as_ref()) {
            for l in uncertainty_lines(u) {
                if let Some((k, v)) = l.split_once(": ") {
                    facts.push((k.to_string(), v.to_string()));
                }
            }
        }
        facts
    }

    /// The decision section: the bound steps, the robust choice, the measurement advice, the
    /// Pareto front and the margins as facts, then the Pareto and regret figures.
    fn decision_section(&self, pg: &mut Page) {
        let Some(d) = self.optimise.as_ref().and_then(|o| o.decision.as_ref()) else {
            return;
        };
        let mut lines: Vec<String> = d
            .bound_steps
            .iter()
            .map(crate::search::robust::bound_line)
            .collect();
        lines.extend(d.robust.iter().flat_map(crate::search::robust::lines));
        lines.extend(d.measurement.iter().map(|m| m.to_string()));
        lines.extend(crate::search::pareto::lines(&d.pareto));
        lines.extend(d.margins.iter().flat_map(crate::search::margins::lines));
        let kv: Vec<(String, String)> = lines
            .iter()
            .map(|l| match l.split_once(": ") {
                Some((k, v)) => (k.to_string(), v.to_string()),
                None => (String::new(), l.clone()),
            })
            .collect();
        if !kv.is_empty() {
            pg.h2("Decision").kv(&kv);
        }
        if let Some(p) = pareto_svg(&d.pareto) {
            pg.figure(
                "pareto",
                &p,
                "Print time against energy at the answer, with the controller's TCP acceleration and jerk limits scaled (the print speed stays): every feasible setting, and the Pareto front (no other setting is faster and cheaper).",
            );
        }
        if let Some(r) = self.regret_svg() {
            pg.figure(
                "regret",
                &r,
                "Regret of each candidate placement over the plausible robots: how much more energy than each robot's own best it uses, averaged over the draws and at their 95th percentile (the recommendation, the nominal answer and the candidates of lowest expected regret; #k is the candidate's index in the JSON's decision.robust.candidates).",
            );
        }
    }

    /// Our energies beside the paper's, when the site names a reference.
    fn reference_section(&self, pg: &mut Page) {
        let Some(rows) = self.reference_rows() else {
            return;
        };
        pg.h2("Ours beside the paper");
        let h: Vec<String> = ["placement", "ours [J]", "paper [J]", "ours / paper"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        pg.table(&h, &rows);
        if let Some((src, _)) = self.site.as_ref().and_then(|s| s.reference.as_ref()) {
            pg.p(&format!("Paper values: {src}."));
        }
    }

    /// The bar chart of energy per placement, its caption naming the standby floor the bars
    /// start from when they do.
    fn bars_figure(&self, pg: &mut Page) {
        let Some((b, floor)) = self.bars_svg() else {
            return;
        };
        let caption = match floor {
            Some((base, lo, hi)) if b.contains("axis-from") => format!(
                "Energy per placement, the bars starting at {} J: every placement draws the standby (the cabinet at rest for the print time, {:.1}…{:.1} J here) below it, so the bars show what the placement changes, the drives' energy and the standby's change with the print time (missing bars: infeasible).",
                svg::fmt_num(base),
                lo,
                hi
            ),
            _ => "Energy per placement (missing bars: infeasible).".into(),
        };
        pg.figure("bars", &b, &caption);
    }

    /// The energy per joint at the placements reported in detail: the chart and its table.
    fn joints_section(&self, pg: &mut Page) {
        let Some(j) = self.joints_svg() else {
            return;
        };
        pg.figure(
            "joints",
            &j,
            "Energy per joint at the placements reported in detail.",
        );
        let header: Vec<String> = std::iter::once("joint".to_string())
            .chain(self.details.iter().map(|d| format!("{} [J]", d.label)))
            .collect();
        let n = self.details[0].energy.joints.len();
        let rows: Vec<Vec<String>> = (0..n)
            .map(|j| {
                std::iter::once(self.details[0].energy.joints[j].name.clone())
                    .chain(self.details.iter().map(|d| {
                        d.energy
                            .joints
                            .get(j)
                            .map_or(String::new(), |x| format!("{:.1}", self.joint_value(x)))
                    }))
                    .collect()
            })
            .collect();
        pg.table(&header, &rows);
    }

    /// Power and cumulative energy over time at the best and worst placements (at every
    /// placement reported in detail when there are two at most).
    fn detail_figures(&self, pg: &mut Page) {
        for (k, d) in self.details.iter().enumerate() {
            if d.label == "best" || d.label == "worst" || self.details.len() <= 2 {
                pg.figure(
                    &format!("power-{k}"),
                    &self.power_svg(d),
                    &format!(
                        "Power per joint over time at the {} placement: {}",
                        d.label,
                        describe(&d.eval)
                    ),
                );
                pg.figure(
                    &format!("cumulative-{k}"),
                    &self.cumulative_svg(d),
                    &format!("Cumulative energy at the {} placement.", d.label),
                );
            }
        }
    }

    /// The infeasible placements: a table by reason with a first example of each, and the
    /// first 200 of them in a collapsed table.
    fn infeasible_section(&self, pg: &mut Page) {
        let mut by_reason: std::collections::BTreeMap<&'static str, (usize, String)> =
            Default::default();
        for r in &self.rows {
            if let Err(e) = &r.outcome {
                let ent = by_reason
                    .entry(e.reason.name())
                    .or_insert_with(|| (0, format!("{} — {}", describe(r), e)));
                ent.0 += 1;
            }
        }
        if by_reason.is_empty() {
            return;
        }
        pg.h2("Infeasible placements by reason");
        let h: Vec<String> = ["reason", "placements", "first example"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let rows: Vec<Vec<String>> = by_reason
            .iter()
            .map(|(k, (n, ex))| vec![k.to_string(), n.to_string(), ex.clone()])
            .collect();
        pg.table(&h, &rows);
        let infeasible: Vec<Vec<String>> = self
            .rows
            .iter()
            .filter_map(|r| {
                r.outcome.as_ref().err().map(|e| {
                    let p = PlacementRow::from(&r.placement);
                    vec![
                        format!("{:.3}", p.x_m),
                        format!("{:.3}", p.y_m),
                        format!("{:.3}", p.z_m),
                        format!("{:.1}", p.yaw_deg),
                        format!("{:.1}", p.spin_deg),
                        e.to_string(),
                    ]
                })
            })
            .take(200)
            .collect();
        let h: Vec<String> = [
            "x [m]",
            "y [m]",
            "z [m]",
            "yaw [°]",
            "spin [°]",
            "why and where",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        pg.collapsed(
            &format!(
                "Details of {} infeasible placements (all in placements.csv)",
                infeasible.len()
            ),
            &super::html::table(&h, &infeasible),
        );
    }

    /// Write `summary.json`, `placements.csv` and `report.html` into the directory `dir`
    /// through the output policy ([`RunDir`]: locked, staged, one rename, refused if it holds
    /// files printwatt did not write).
    pub fn write(&self, dir: &Path) -> Result<()> {
        let mut rd = RunDir::begin_at(dir, &Inputs::new(), Existing::Replace)?;
        self.write_into(&mut rd)?;
        rd.commit()?;
        Ok(())
    }

    /// Write `summary.json`, `placements.csv` and `report.html` into a run directory being
    /// written (commit it afterwards). The numbers are checked to be finite first.
    pub fn write_into(&self, rd: &mut RunDir) -> Result<()> {
        self.check_finite()?;
        // The three files are made at once where the current rayon pool has threads free
        // (each is made by the same code as alone), then written in the same order.
        let (summary, (csv, html)) = rayon::join(
            || self.summary_json(true),
            || rayon::join(|| self.placements_csv(), || self.html()),
        );
        rd.write("summary.json", summary?.as_bytes())?;
        rd.write("placements.csv", csv.as_bytes())?;
        rd.write("report.html", html.as_bytes())?;
        Ok(())
    }

    /// No NaN or infinity in the numbers of a feasible placement (energy, time): the first is
    /// an error naming the placement and quantity.
    pub fn check_finite(&self) -> Result<()> {
        for (i, r) in self.rows.iter().enumerate() {
            if let Ok(f) = &r.outcome {
                for (q, v) in [("energy_j", f.energy_j), ("duration_s", f.duration_s)] {
                    if !v.is_finite() {
                        return Err(Error::Invalid(format!(
                            "placement {i} (x = {} m, y = {} m): {q} is {v}: the model produced a number that is not a number; check the robot's drive and inertia data",
                            r.placement.x, r.placement.y
                        )));
                    }
                }
            }
        }
        Ok(())
    }
}

fn describe(e: &Evaluated) -> String {
    let p = PlacementRow::from(&e.placement);
    let at = format!(
        "x = {:.3} m, y = {:.3} m, z = {:.3} m, yaw = {:.1}°, spin = {:.1}°",
        p.x_m, p.y_m, p.z_m, p.yaw_deg, p.spin_deg
    );
    match &e.outcome {
        Ok(f) => format!("{at}: {:.1} J, {:.2} s", f.energy_j, f.duration_s),
        Err(r) => format!("{at}: infeasible, {r}"),
    }
}

fn csv_cell(s: &str) -> String {
    if s.contains(',') || s.contains('"') || s.contains('\n') {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// One line comparing the reduced estimate of an optimisation's answer with its full
/// evaluation: "energy at the answer: full evaluation … J; estimate from … of … layers … J ±
/// … J (… %)".
pub fn full_check_line(c: &crate::evaluate::reduce::FullCheck) -> String {
    format!(
        "energy at the answer: full evaluation {:.1} J; estimate from {} of {} layers {:.1} J ± {:.1} J ({:+.3} % from the full figure, {} the stated error)",
        c.full_j,
        c.layers_evaluated,
        c.summary.layers,
        c.estimate_j,
        c.error_j,
        c.difference_pct,
        if c.within_error { "within" } else { "OUTSIDE" }
    )
}

/// Print time against energy of the timing settings at the answer, the Pareto front apart.
fn pareto_svg(ps: &[crate::search::pareto::TimingPoint]) -> Option<String> {
    let pick = |front: bool| -> (Vec<f64>, Vec<f64>) {
        ps.iter()
            .filter(|p| p.pareto == front)
            .filter_map(|p| p.duration_s.zip(p.energy_j))
            .unzip()
    };
    let (ft, fe) = pick(true);
    if ft.is_empty() {
        return None;
    }
    let (ot, oe) = pick(false);
    let mut series = vec![svg::Series::new("Pareto front", &ft, &fe)];
    if !ot.is_empty() {
        series.push(svg::Series::new("dominated", &ot, &oe));
    }
    let f = svg::Frame::new(
        "Print time against energy (acceleration and jerk scaled)",
        "print time [s]",
        "energy [J]",
    )
    .size(760.0, 360.0);
    Some(svg::scatter(&f, &series))
}

/// Candidates drawn in the report's regret chart (the recommendation, the nominal answer and
/// those of lowest expected regret).
const REGRET_BARS: usize = 12;

/// The uncertainty study in a few lines "what: value" (terminal and report).
pub fn uncertainty_lines(u: &crate::search::uncertainty::Study) -> Vec<String> {
    use crate::search::uncertainty::Source;
    let src = match &u.source {
        Source::DriveFile(f) => format!("ranges of {f} [uncertainty]"),
        Source::Default => {
            "built-in default ranges (the drive file has no [uncertainty] table)".into()
        }
        Source::Given => "ranges given by the caller".into(),
    };
    let cal = if u.calibrated.is_empty() {
        String::new()
    } else {
        format!(
            "; standard errors of the identified {}",
            u.calibrated.join(", ")
        )
    };
    let mut v = vec![
        format!(
            "uncertainty: {} plausible robots (seed {}, {src}{cal}), {} candidate placements each",
            u.draws, u.seed, u.candidates
        ),
        format!(
            "uncertainty, recommended placement within 1 % of each robot's best: {:.0} % of the draws (the best in {:.0} %)",
            u.p_within_1pct * 100.0,
            u.p_best * 100.0
        ),
    ];
    if let Some(s) = u.saving_pct {
        v.push(format!(
            "uncertainty, saving against the baseline: {:.2} % expected, 90 % interval {:.2} … {:.2} %",
            s[0], s[1], s[2]
        ));
    }
    v.push(format!(
        "uncertainty, rank correlation of the placements with the nominal robot's: Spearman {:.3} mean, {:.3} lowest",
        u.rank_correlation[0], u.rank_correlation[1]
    ));
    if let Some((name, r)) = u.depends_on.first() {
        v.push(format!(
            "uncertainty, the answer depends most on: {name} (Spearman {r:+.2}; next: {})",
            u.depends_on
                .iter()
                .skip(1)
                .take(2)
                .map(|(n, r)| format!("{n} {r:+.2}"))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    v
}

/// The baseline's tolerance check in words: "holds ±20 mm in x and y, …: all 16 corners
/// feasible, energy a…b J" or "does NOT hold …: k of the 16 corners infeasible (first: why)"
/// (energies in J).
pub fn baseline_tolerance_text(c: &crate::search::tolerance::ToleranceCheck) -> String {
    tolerance_text(c, false)
}

/// A tolerance check in words: "holds ±20 mm in x and y, …: all 16 corners feasible, energy
/// a…b J" or "does NOT hold …: k of the n corners infeasible (first: why)"; `checked` says
/// "corners checked infeasible" (a check that stops after the first batch with an infeasible
/// corner has not evaluated them all). Energies in J.
pub(crate) fn tolerance_text(
    c: &crate::search::tolerance::ToleranceCheck,
    checked: bool,
) -> String {
    if c.holds {
        format!(
            "holds {}: all {} corners feasible, energy {:.1}…{:.1} J",
            c.tolerance.describe(),
            c.corners,
            c.best_j.unwrap_or(f64::NAN),
            c.worst_j.unwrap_or(f64::NAN)
        )
    } else {
        format!(
            "does NOT hold {}: {} of the {} corners {}infeasible (first: {})",
            c.tolerance.describe(),
            c.failures.len(),
            c.corners,
            if checked { "checked " } else { "" },
            c.failures.first().map_or("", String::as_str)
        )
    }
}

/// What a saving against a baseline that does not hold the placement tolerance (`c`) is
/// measured against, appended to the saving: empty when the baseline holds it.
pub fn baseline_saving_caveat(c: &crate::search::tolerance::ToleranceCheck) -> String {
    if c.holds {
        String::new()
    } else {
        format!(
            "; measured against a baseline that does NOT hold the placement tolerance ({} of its {} corners infeasible): a placement a site could not rely on",
            c.failures.len(),
            c.corners
        )
    }
}

/// The answer card's "how sure" item: the placement tolerance box and the uncertainty study's
/// verdict (or why there is none).
fn answer_how_sure(o: &OptimiseResult) -> String {
    let mut sure = Vec::new();
    if let Some(si) = &o.search {
        sure.push(format!(
            "placement tolerance: {}",
            tolerance_text(&si.tolerance, true)
        ));
    }
    match &o.uncertainty {
        Some(u) => {
            let mut t = format!(
                "over {} robots drawn from the drive data's ranges, the recommended placement is the best candidate in {:.0} % of them and within 1 % of each one's best in {:.0} %",
                u.draws,
                u.p_best * 100.0,
                u.p_within_1pct * 100.0
            );
            if let Some(r) = o
                .decision
                .as_ref()
                .and_then(|d| d.robust.as_ref())
                .and_then(|r| r.candidates.get(r.recommended))
            {
                t.push_str(&format!(
                    "; expected regret {:.1} J, 95th percentile {:.1} J",
                    r.expected_regret_j, r.p95_regret_j
                ));
            }
            if let Some(sp) = u.saving_pct {
                t.push_str(&format!(
                    "; saving against the baseline {:.2} % expected, 90 % interval {:.2} … {:.2} %",
                    sp[0], sp[1], sp[2]
                ));
            }
            sure.push(t);
        }
        None => sure.push(
            "uncertainty study not run: the figures are those of the nominal robot (the study draws plausible robots from the drive data's ranges and says how often this placement stays the best)".into(),
        ),
    }
    sure.join("; ")
}

/// The summary's facts on the optimum's neighbourhood (energies of the neighbours, gradient,
/// curvature, one-sided slopes) and the search's effort.
fn sensitivity_facts(o: &OptimiseResult) -> Vec<(String, String)> {
    let s = &o.sensitivity;
    let f = |v: Option<f64>| v.map_or("infeasible".to_string(), |v| format!("{v:.2}"));
    // Derivatives need both neighbours (one for the one-sided slope): "n/a" otherwise.
    let g = |v: Option<f64>| v.map_or("n/a".to_string(), |v| format!("{v:.2}"));
    let xy = |label: &str, v: [Option<f64>; 2]| {
        (label.to_string(), format!("{} / {}", g(v[0]), g(v[1])))
    };
    vec![
        (
            format!("energy at x∓{0:.0} mm, y∓{0:.0} mm [J]", s.h_m * 1000.0),
            format!(
                "{} / {} / {} / {}",
                f(s.e_j[0]),
                f(s.e_j[1]),
                f(s.e_j[2]),
                f(s.e_j[3])
            ),
        ),
        xy("gradient dE/dx, dE/dy [J/m]", s.gradient_j_per_m),
        xy("curvature d²E/dx², d²E/dy² [J/m²]", s.curvature_j_per_m2),
        xy(
            "one-sided slopes dE/dx, dE/dy [J/m] (one neighbour infeasible)",
            s.one_sided_j_per_m,
        ),
        (
            "search".into(),
            format!("{} evaluations, {} iterations", o.evals, o.iterations),
        ),
    ]
}

/// A saving as people read it: `"819.8 J (6.00 %)"`, or `"no difference"` when the saving is
/// 0 after rounding to the operands' digits ([`crate::numerics::difference`]). `j` in J,
/// `pct` in %.
pub fn saving_text(j: f64, pct: f64) -> String {
    if j == 0.0 {
        "no difference".into()
    } else {
        format!("{j:.1} J ({pct:.2} %)")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::search::tolerance::{Tolerance, ToleranceCheck};

    #[test]
    fn a_tolerance_check_in_words_names_the_corners_and_the_first_failure() {
        let tolerance = Tolerance {
            xy_m: 0.02,
            z_m: 0.02,
            yaw_rad: 1f64.to_radians(),
        };
        let failed = ToleranceCheck {
            tolerance,
            corners: 8,
            failures: vec!["joint 3 near its limit".into(), "reach".into()],
            holds: false,
            worst_j: Some(12.0),
            best_j: Some(10.0),
        };
        let t = tolerance_text(&failed, true);
        assert!(t.starts_with("does NOT hold ±20 mm"), "{t}");
        assert!(
            t.ends_with(": 2 of the 8 corners checked infeasible (first: joint 3 near its limit)"),
            "{t}"
        );
        assert!(baseline_tolerance_text(&failed)
            .ends_with(": 2 of the 8 corners infeasible (first: joint 3 near its limit)"));
        let held = ToleranceCheck {
            corners: 16,
            failures: vec![],
            holds: true,
            ..failed
        };
        assert!(
            tolerance_text(&held, true).ends_with(": all 16 corners feasible, energy 10.0…12.0 J")
        );
    }
}
