//! The report page of a design study ([`crate::placement::study`]): which robot and cell
//! prints each path for the least energy, the robot-and-cell combinations over every path,
//! and every case with a link to its own optimise report. Energies in J, times in s,
//! positions in m, angles in deg (as labelled).

use super::html::Page;
use super::svg::{self, esc, Frame};
use crate::error::Result;
use crate::placement::study::{CaseResult, Study};
use std::fmt::Write as _;

/// The study's report page (self-contained XHTML), from its results (one per case, in case
/// order). Deterministic: the same results give the same bytes.
pub fn html(study: &Study, results: &[CaseResult]) -> Result<String> {
    let t = study.tables(results)?;
    let objective = results
        .first()
        .map_or_else(String::new, |r| r.objective.clone());
    let mut pg = Page::new(&format!("printwatt study: {}", study.name));
    let answered = results.iter().filter(|r| r.outcome.is_ok()).count();
    let mut facts = vec![
        ("study file".to_string(), study.file.display().to_string()),
        ("objective minimised".into(), objective.clone()),
        (
            "cases".into(),
            format!(
                "{} ({} robots × {} cells × {} paths{}), {answered} with a feasible placement",
                results.len(),
                study.robots.len(),
                study.cells.len(),
                study.paths.len(),
                if results.len() == study.robots.len() * study.cells.len() * study.paths.len() {
                    ""
                } else {
                    ", listed"
                }
            ),
        ),
    ];
    if let Some(d) = &study.description {
        facts.insert(0, ("description".into(), d.clone()));
    }
    pg.kv(&facts);

    pg.h2("Which robot and cell for each path");
    pg.p(&format!(
        "The cheapest case of each path ({objective} energy at its optimised placement) and how much more the next cheapest needs."
    ));
    let rows: Vec<Vec<String>> = t
        .paths
        .iter()
        .map(|p| {
            vec![
                p.path.clone(),
                p.best
                    .as_ref()
                    .map_or("none feasible".into(), |b| b.0.clone()),
                p.best.as_ref().map_or(String::new(), |b| b.1.clone()),
                p.energy_j.map_or("-".into(), |e| format!("{e:.1}")),
                p.runner_up.map_or("-".into(), |(i, dj, pct)| {
                    let c = &study.cases[i];
                    format!(
                        "{} / {}: +{dj:.1} J (+{pct:.1} %)",
                        study.robots[c.robot].name, study.cells[c.cell].name
                    )
                }),
                format!("{} of {}", p.feasible, p.cases),
            ]
        })
        .collect();
    pg.table(
        &[
            "path".into(),
            "robot".into(),
            "cell".into(),
            "energy [J]".into(),
            "next cheapest".into(),
            "feasible cases".into(),
        ],
        &rows,
    );

    pg.h2("Robot and cell over every path");
    pg.p("Totals over the paths each robot-and-cell combination was given; combinations that print every path come first, by energy. A total over fewer paths is not comparable with a complete one.");
    let rows: Vec<Vec<String>> = t
        .combinations
        .iter()
        .map(|c| {
            vec![
                c.robot.clone(),
                c.cell.clone(),
                format!("{} of {}", c.feasible, c.paths),
                format!("{:.1}", c.energy_j),
                format!("{:.1}", c.supply_j),
                format!("{:.1}", c.duration_s),
                if c.infeasible.is_empty() {
                    "-".into()
                } else {
                    c.infeasible.join(", ")
                },
            ]
        })
        .collect();
    pg.table(
        &[
            "robot".into(),
            "cell".into(),
            "paths feasible".into(),
            format!("{objective} energy [J]"),
            "supply [J]".into(),
            "print time [s]".into(),
            "paths without a feasible placement".into(),
        ],
        &rows,
    );
    let complete: Vec<_> = t
        .combinations
        .iter()
        .filter(|c| c.feasible == c.paths)
        .collect();
    if complete.is_empty() {
        pg.p("No robot-and-cell combination prints every path it was given.");
    } else {
        let cats: Vec<String> = complete
            .iter()
            .map(|c| format!("{} / {}", c.robot, c.cell))
            .collect();
        let vals: Vec<f64> = complete.iter().map(|c| c.energy_j).collect();
        pg.figure(
            "combinations",
            &svg::bar_chart(
                &Frame::new(
                    "Total energy of the combinations that print every path",
                    "robot / cell",
                    &format!("{objective} energy [J]"),
                )
                .size(760.0, 360.0),
                &cats,
                &[(objective.clone(), vals)],
            ),
            "Sum over the paths of each case's energy at its optimised placement.",
        );
    }

    // Energy per path, one bar per robot and cell (missing: no feasible placement).
    let mut combos: Vec<(usize, usize)> = Vec::new();
    for c in &study.cases {
        if !combos.contains(&(c.robot, c.cell)) {
            combos.push((c.robot, c.cell));
        }
    }
    let paths: Vec<usize> = (0..study.paths.len())
        .filter(|p| study.cases.iter().any(|c| c.path == *p))
        .collect();
    let groups: Vec<(String, Vec<f64>)> = combos
        .iter()
        .map(|&(r, ce)| {
            (
                format!("{} / {}", study.robots[r].name, study.cells[ce].name),
                paths
                    .iter()
                    .map(|&p| {
                        study
                            .cases
                            .iter()
                            .zip(results)
                            .find(|(c, _)| c.robot == r && c.cell == ce && c.path == p)
                            .and_then(|(_, res)| res.energy_j())
                            .unwrap_or(f64::NAN)
                    })
                    .collect(),
            )
        })
        .collect();
    let cats: Vec<String> = paths.iter().map(|&p| study.paths[p].name.clone()).collect();
    pg.figure(
        "per-path",
        &svg::bar_chart(
            &Frame::new(
                "Energy per path at each case's optimised placement",
                "path",
                &format!("{objective} energy [J]"),
            )
            .size(900.0, 400.0)
            .missing("none"),
            &cats,
            &groups,
        ),
        "\"none\": no feasible placement of that path for that robot in that cell (the case table says why).",
    );

    pg.h2("Every case");
    let mut tb = String::from("<table><thead><tr>");
    for h in [
        "case",
        "robot",
        "cell",
        "path",
        "x [m]",
        "y [m]",
        "z [m]",
        "yaw [°]",
        "spin [°]",
        "energy [J]",
        "print time [s]",
        "vs baseline",
        "report / why not",
    ] {
        let _ = write!(tb, "<th>{}</th>", esc(h));
    }
    tb.push_str("</tr></thead><tbody>");
    for (c, r) in study.cases.iter().zip(results) {
        let _ = write!(
            tb,
            "<tr><td>{}</td><td class=\"t\">{}</td><td class=\"t\">{}</td><td class=\"t\">{}</td>",
            c.index,
            esc(&study.robots[c.robot].name),
            esc(&study.cells[c.cell].name),
            esc(&study.paths[c.path].name)
        );
        match &r.outcome {
            Ok(b) => {
                let [x, y, z, yaw, spin] = b.placement;
                let f = &b.feasible;
                let saving = b.baseline_j.map_or("-".to_string(), |bj| {
                    format!("{:.1} %", 100.0 * (bj - f.energy_j) / bj.abs().max(1e-12))
                });
                let _ = write!(
                    tb,
                    "<td>{x:.3}</td><td>{y:.3}</td><td>{z:.3}</td><td>{:.1}</td><td>{:.1}</td><td>{:.1}</td><td>{:.2}</td><td>{}</td>",
                    yaw.to_degrees(),
                    spin.to_degrees(),
                    f.energy_j,
                    f.duration_s,
                    esc(&saving)
                );
                let file = study.case_file(c);
                let notes = if b.notes.is_empty() {
                    String::new()
                } else {
                    format!(" ({})", esc(&b.notes.join("; ")))
                };
                let _ = write!(
                    tb,
                    "<td class=\"t\"><a href=\"{}\">{}</a>{notes}</td></tr>",
                    esc(&file),
                    esc(&file)
                );
            }
            Err(why) => {
                let _ = write!(
                    tb,
                    "<td colspan=\"8\" class=\"t\">no feasible placement</td><td class=\"t\">{}</td></tr>",
                    esc(why)
                );
            }
        }
    }
    tb.push_str("</tbody></table>");
    pg.raw(&tb);
    Ok(pg.finish())
}
