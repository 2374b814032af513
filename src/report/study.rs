//! The report page of a design study ([`crate::campaign::study`]): which robot and cell
//! prints each path for the least energy, the robot-and-cell combinations over every path,
//! and every case with a link to its own optimise report. Energies in J, times in s,
//! positions in m, angles in deg (as labelled).

use super::html::Page;
use super::svg::{self, esc, Frame};
use crate::campaign::study::{CaseResult, Study, StudyTables};
use crate::error::Result;
use std::fmt::Write as _;

/// The study's report page (self-contained XHTML), from its results (one per case, in case
/// order). Deterministic: the same results give the same bytes.
pub fn html(study: &Study, results: &[CaseResult]) -> Result<String> {
    let t = study.tables(results)?;
    let objective = results
        .first()
        .map_or_else(String::new, |r| r.objective.clone());
    let mut pg = facts(study, results, &objective);
    per_path_section(&mut pg, study, &t, &objective);
    combinations_section(&mut pg, &t, &objective);
    per_path_chart(&mut pg, study, results, &t, &objective);
    pg.h2("Every case");
    pg.raw(&case_table(study, results));
    Ok(pg.finish())
}

/// The page with its title and the study's facts (file, objective, cases).
fn facts(study: &Study, results: &[CaseResult], objective: &str) -> Page {
    let mut pg = Page::new(&format!("printwatt study: {}", study.name));
    let answered = results.iter().filter(|r| r.outcome.is_ok()).count();
    let mut facts = vec![
        ("study file".to_string(), study.file.display().to_string()),
        ("objective minimised".into(), objective.to_string()),
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
    // The drive data of every robot: estimated or given (each case's report says it too).
    for r in &study.robots {
        let file = crate::robot::shipped::resolve(&r.robot).unwrap_or_else(|| r.robot.clone());
        let status = match crate::robot::load(&file) {
            Ok(m) => crate::robot::drive_data_status(&m),
            Err(e) => format!("not read here ({e})"),
        };
        facts.push((format!("drive data of {}", r.name), status));
    }
    pg.kv(&facts);

    pg
}

/// The cheapest robot and cell of each path, and the next cheapest.
fn per_path_section(pg: &mut Page, study: &Study, t: &StudyTables, objective: &str) {
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
}

/// Totals of each robot-and-cell combination over the paths, and the chart of the extra
/// energy over the cheapest complete one.
fn combinations_section(pg: &mut Page, t: &StudyTables, objective: &str) {
    pg.h2("Robot and cell over every path");
    pg.p("Totals over the paths each robot-and-cell combination was given; combinations that print every path come first, by energy. A total over fewer paths is not comparable with a complete one.");
    // The supply column only where the objective is not the supply energy itself.
    let supply_col = objective != "supply";
    let rows: Vec<Vec<String>> = t
        .combinations
        .iter()
        .map(|c| {
            let sum = |v: f64, d: usize| {
                if c.feasible == 0 {
                    "-".to_string()
                } else {
                    format!("{v:.d$}")
                }
            };
            let mut r = vec![
                c.robot.clone(),
                c.cell.clone(),
                format!("{} of {}", c.feasible, c.paths),
                sum(c.energy_j, 1),
            ];
            if supply_col {
                r.push(sum(c.supply_j, 1));
            }
            r.push(sum(c.duration_s, 1));
            r.push(if c.infeasible.is_empty() {
                "-".into()
            } else {
                c.infeasible.join(", ")
            });
            r
        })
        .collect();
    let mut header = vec![
        "robot".to_string(),
        "cell".into(),
        "paths feasible".into(),
        format!("{objective} energy [J]"),
    ];
    if supply_col {
        header.push("supply [J]".into());
    }
    header.push("print time [s]".into());
    header.push("paths without a feasible placement".into());
    pg.table(&header, &rows);
    combinations_chart(pg, t, objective);
}

/// The extra energy of each combination that prints every path over the cheapest one.
fn combinations_chart(pg: &mut Page, t: &StudyTables, objective: &str) {
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
        // The differences decide, not the totals (often within a few %): bars from the
        // cheapest.
        let least = complete[0].energy_j;
        let vals: Vec<f64> = complete.iter().map(|c| c.energy_j - least).collect();
        pg.figure(
            "combinations",
            &svg::bar_chart(
                &Frame::new(
                    &format!(
                        "Extra energy over the cheapest combination that prints every path ({} / {}, {least:.1} J)",
                        complete[0].robot, complete[0].cell
                    ),
                    "robot / cell",
                    &format!("extra {objective} energy [J]"),
                )
                .size(760.0, 360.0),
                &cats,
                &[(objective.to_string(), vals)],
            ),
            "Sum over the paths of each case's energy at its optimised placement, minus the cheapest combination's.",
        );
    }
}

/// Energy per path above the path's cheapest case, one bar per robot and cell (missing: no
/// feasible placement).
fn per_path_chart(
    pg: &mut Page,
    study: &Study,
    results: &[CaseResult],
    t: &StudyTables,
    objective: &str,
) {
    let mut combos: Vec<(usize, usize)> = Vec::new();
    for c in &study.cases {
        if !combos.contains(&(c.robot, c.cell)) {
            combos.push((c.robot, c.cell));
        }
    }
    let cats: Vec<String> = t.paths.iter().map(|p| p.path.clone()).collect();
    let groups: Vec<(String, Vec<f64>)> = combos
        .iter()
        .map(|&(r, ce)| {
            (
                format!("{} / {}", study.robots[r].name, study.cells[ce].name),
                t.paths
                    .iter()
                    .map(|pb| {
                        study
                            .cases
                            .iter()
                            .zip(results)
                            .find(|(c, _)| {
                                c.robot == r && c.cell == ce && study.paths[c.path].name == pb.path
                            })
                            .and_then(|(_, res)| res.energy_j())
                            .zip(pb.energy_j)
                            .map_or(f64::NAN, |(e, least)| e - least)
                    })
                    .collect(),
            )
        })
        .collect();
    pg.figure(
        "per-path",
        &svg::bar_chart(
            &Frame::new(
                "Extra energy per path over its cheapest robot and cell",
                "path",
                &format!("extra {objective} energy [J]"),
            )
            .size(900.0, 400.0)
            .missing("none"),
            &cats,
            &groups,
        ),
        "Each case's energy at its optimised placement minus the cheapest case of the same path (0: the cheapest); \"none\": no feasible placement of that path for that robot in that cell (the case table says why).",
    );
}

/// The table of every case: placement, energy, saving, its report or why it has none.
fn case_table(study: &Study, results: &[CaseResult]) -> String {
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
        "notes",
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
                    let pct = 100.0 * (bj - f.energy_j) / bj.abs().max(1e-12);
                    match b.baseline_holds_tolerance {
                        Some(false) => {
                            format!("{pct:.1} % (the baseline does not hold the tolerance)")
                        }
                        _ => format!("{pct:.1} %"),
                    }
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
                let _ = write!(
                    tb,
                    "<td class=\"t\"><a href=\"{}\">{}</a></td><td class=\"t\" style=\"font-size:0.85em\">{}</td></tr>",
                    esc(&file),
                    esc(&file),
                    esc(&b.notes.join("; "))
                );
            }
            Err(why) => {
                let _ = write!(
                    tb,
                    "<td colspan=\"8\" class=\"t\">no feasible placement</td><td colspan=\"2\" class=\"t\">{}</td></tr>",
                    esc(why)
                );
            }
        }
    }
    tb.push_str("</tbody></table>");
    tb
}
