//! The report of a placement run under `results/<run>/`: `summary.json` and `placements.csv`
//! for scripts, `report.html` (self-contained, inline SVG) for people. Numbers arrive
//! computed; this module only formats them.
//!
//! Figures: energy heatmap over the workspace (minimum over z, yaw and spin per (x, y) cell;
//! infeasible cells marked by reason; the optimum marked), energy per placement (bars, like
//! seed 000's P1–P5), energy per joint (grouped bars, like seed 001's Table 1), power–time
//! curves per joint at the best and worst placements (like seed 000's Fig. 2a).

use super::html::Page;
use super::svg::{self, CellMark, Heatmap, Series};
use crate::energy::EnergyReport;
use crate::error::{Error, Result};
use crate::output::{Existing, Inputs, RunDir};
use crate::placement::optimise::OptimiseResult;
use crate::placement::sweep::{Evaluated, Grid, PlacementRow};
use serde::Serialize;
use std::path::Path;

/// Files this module writes in a run directory; any other file there is "foreign".
pub const OUR_FILES: [&str; 3] = ["summary.json", "placements.csv", "report.html"];

/// A placement reported in detail (full energy report with per-sample series).
#[derive(Clone, Debug)]
pub struct Detail {
    /// Label (e.g. "best", "worst", "baseline", "P1").
    pub label: String,
    /// The placement's sweep entry.
    pub eval: Evaluated,
    /// Its full energy report.
    pub energy: EnergyReport,
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
            .or_else(|| crate::placement::optimise::best_of(&self.rows))
    }

    /// Saving of the best against the baseline, (J, %).
    pub fn saving(&self) -> Option<(f64, f64)> {
        let b = self.baseline.as_ref()?.1.cost();
        let o = self.best()?.cost();
        (b.is_finite() && o.is_finite() && b != 0.0).then(|| (b - o, (b - o) / b * 100.0))
    }

    /// Spread (max − min) / min over feasible rows, %.
    pub fn spread_pct(&self) -> Option<f64> {
        let lo = crate::placement::optimise::best_of(&self.rows)?.cost();
        let hi = crate::placement::optimise::worst_of(&self.rows)?.cost();
        (lo > 0.0).then(|| (hi - lo) / lo * 100.0)
    }

    /// Reduction (max − min) / max over feasible rows, % (seed 000's 53.72 % definition).
    pub fn reduction_pct(&self) -> Option<f64> {
        let lo = crate::placement::optimise::best_of(&self.rows)?.cost();
        let hi = crate::placement::optimise::worst_of(&self.rows)?.cost();
        (hi > 0.0).then(|| (hi - lo) / hi * 100.0)
    }

    /// `summary.json`: counts, best/worst, spread, baseline and saving, search result and
    /// sensitivity, per-joint energies of the detailed placements; every row with `with_rows`.
    pub fn summary_json(&self, with_rows: bool) -> Result<String> {
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
            worst: crate::placement::optimise::worst_of(&self.rows),
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
        serde_json::to_string_pretty(&s).map_err(|e| Error::Invalid(e.to_string()))
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

    /// The energy heatmap (None without a grid).
    pub fn heatmap_svg(&self) -> Option<String> {
        let g = self.grid.as_ref()?;
        if self.rows.len() != g.len() || g.xs.len() < 2 || g.ys.len() < 2 {
            return None;
        }
        let (nx, ny) = (g.xs.len(), g.ys.len());
        let mut values = vec![f64::NAN; nx * ny];
        let mut reason: Vec<Option<&'static str>> = vec![None; nx * ny];
        for iz in 0..g.zs.len() {
            for iyaw in 0..g.yaws.len() {
                for isp in 0..g.spins.len() {
                    for iy in 0..ny {
                        for ix in 0..nx {
                            let r = &self.rows[g.index(ix, iy, iz, iyaw, isp)];
                            let c = iy * nx + ix;
                            match &r.outcome {
                                Ok(f) => {
                                    if values[c].is_nan() || f.energy_j < values[c] {
                                        values[c] = f.energy_j;
                                    }
                                }
                                Err(e) => {
                                    if reason[c].is_none() {
                                        reason[c] = Some(e.reason.name());
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
        let mut marks = Vec::new();
        for c in 0..nx * ny {
            if !values[c].is_finite() {
                marks.push(CellMark {
                    col: c % nx,
                    row: c / nx,
                    class: reason[c].unwrap_or("infeasible").to_string(),
                    at: None,
                });
            }
        }
        if let Some(b) = self.best().filter(|b| b.cost().is_finite()) {
            let near = |v: &[f64], x: f64| {
                v.iter()
                    .enumerate()
                    .min_by(|a, b| (a.1 - x).abs().total_cmp(&(b.1 - x).abs()))
                    .map(|(i, _)| i)
                    .unwrap_or(0)
            };
            marks.push(CellMark {
                col: near(&g.xs, b.placement.x),
                row: near(&g.ys, b.placement.y),
                class: "optimum".into(),
                at: Some((b.placement.x, b.placement.y)),
            });
        }
        let f = svg::Frame::new(
            "Energy over the workspace (min over yaw/spin/z per cell)",
            "x of the part origin [m]",
            "y of the part origin [m]",
        )
        .size(760.0, 520.0);
        Some(svg::heatmap(
            &f,
            &Heatmap {
                xs: g.xs.clone(),
                ys: g.ys.clone(),
                values,
                marks,
                value_label: "energy [J]".into(),
            },
        ))
    }

    fn bars_svg(&self) -> Option<String> {
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
            if let Some(w) = crate::placement::optimise::worst_of(&self.rows) {
                c.push("worst grid".into());
                v.push(w.cost());
            }
            (c, v)
        };
        if cats.is_empty() {
            return None;
        }
        let f = svg::Frame::new("Energy per placement", "placement", "energy [J]")
            .size(760.0, 360.0)
            .missing("infeasible");
        Some(svg::bar_chart(&f, &cats, &[("energy".into(), vals)]))
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
        let s = &d.energy.series;
        let n = d.energy.joints.len();
        let p = if self.electrical { &s.p_el } else { &s.p_mech };
        let series: Vec<Series> = (0..n)
            .map(|j| {
                let y: Vec<f64> = (0..s.t.len()).map(|k| p[k * n + j]).collect();
                Series::new(&d.energy.joints[j].name, &s.t, &y)
            })
            .collect();
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
        svg::line_chart(&f, &series)
    }

    /// The HTML page.
    pub fn html(&self) -> String {
        let mut pg = Page::new(&self.title);
        pg.kv(&self.meta);
        let feasible = self.rows.iter().filter(|r| r.cost().is_finite()).count();
        let mut facts = vec![(
            "placements".to_string(),
            format!("{} ({} feasible)", self.rows.len(), feasible),
        )];
        if let Some(b) = self.best() {
            facts.push(("best".into(), describe(b)));
        }
        if let Some((how, b)) = &self.baseline {
            facts.push((format!("baseline ({how})"), describe(b)));
        }
        if let Some((j, pct)) = self.saving() {
            facts.push((
                "saving vs baseline".into(),
                format!("{j:.1} J ({pct:.2} %)"),
            ));
        }
        if let Some(s) = self.spread_pct() {
            facts.push((
                "spread (max−min)/min over feasible rows".into(),
                format!("{s:.2} %"),
            ));
        }
        if let Some(o) = &self.optimise {
            let s = &o.sensitivity;
            let f = |v: Option<f64>| v.map_or("infeasible".to_string(), |v| format!("{v:.2}"));
            // Derivatives need both neighbours (one for the one-sided slope): "n/a" otherwise.
            let g = |v: Option<f64>| v.map_or("n/a".to_string(), |v| format!("{v:.2}"));
            facts.push((
                format!("energy at x∓{0:.0} mm, y∓{0:.0} mm [J]", s.h_m * 1000.0),
                format!(
                    "{} / {} / {} / {}",
                    f(s.e_j[0]),
                    f(s.e_j[1]),
                    f(s.e_j[2]),
                    f(s.e_j[3])
                ),
            ));
            facts.push((
                "gradient dE/dx, dE/dy [J/m]".into(),
                format!(
                    "{} / {}",
                    g(s.gradient_j_per_m[0]),
                    g(s.gradient_j_per_m[1])
                ),
            ));
            facts.push((
                "curvature d²E/dx², d²E/dy² [J/m²]".into(),
                format!(
                    "{} / {}",
                    g(s.curvature_j_per_m2[0]),
                    g(s.curvature_j_per_m2[1])
                ),
            ));
            facts.push((
                "one-sided slopes dE/dx, dE/dy [J/m] (one neighbour infeasible)".into(),
                format!(
                    "{} / {}",
                    g(s.one_sided_j_per_m[0]),
                    g(s.one_sided_j_per_m[1])
                ),
            ));
            facts.push((
                "search".into(),
                format!("{} evaluations, {} iterations", o.evals, o.iterations),
            ));
        }
        pg.h2("Summary").kv(&facts);
        if let Some(h) = self.heatmap_svg() {
            pg.figure(
                "heatmap",
                &h,
                "Energy over the workspace; crosses mark infeasible cells by reason, the ring marks the optimum.",
            );
        }
        if let Some(b) = self.bars_svg() {
            pg.figure(
                "bars",
                &b,
                "Energy per placement (missing bars: infeasible).",
            );
        }
        if let Some(j) = self.joints_svg() {
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
            }
        }
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
        if !infeasible.is_empty() {
            pg.h2("Infeasible placements (first 200)");
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
            pg.table(&h, &infeasible);
        }
        pg.finish()
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
        rd.write("summary.json", self.summary_json(true)?.as_bytes())?;
        rd.write("placements.csv", self.placements_csv().as_bytes())?;
        rd.write("report.html", self.html().as_bytes())?;
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
