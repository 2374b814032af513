//! `printwatt robots`

use super::RobotsArgs;
use anyhow::{Context, Result};
use printwatt::robot;
use serde::Serialize;
use std::path::PathBuf;

#[derive(Serialize)]
struct RobotRow {
    id: String,
    name: String,
    joints: usize,
    reach_m: Option<f64>,
    rated_payload_kg: Option<f64>,
    moving_mass_kg: f64,
    closed_form_ik: bool,
    drive_data: bool,
    provenance: String,
    inertia_sources: Vec<robot::inertia::InertiaSource>,
    link_names: Vec<String>,
}

/// `printwatt robots`: the shipped robots as a table or JSON.
pub fn run(a: RobotsArgs) -> Result<()> {
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(&a.dir)
        .with_context(|| format!("reading robots directory {}", a.dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    let mut rows = Vec::new();
    for d in dirs {
        rows.push(robot_row(&d)?);
    }
    if a.json {
        super::print_json(&serde_json::json!({ "robots": rows }))?;
        return Ok(());
    }
    print_table(&rows)?;
    Ok(())
}

/// The table row of the robot in directory `d`.
fn robot_row(d: &std::path::Path) -> Result<RobotRow> {
    let m = robot::load(d).with_context(|| format!("loading robot {}", d.display()))?;
    Ok(RobotRow {
        id: d
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        name: m.info.name.clone(),
        joints: m.dof(),
        reach_m: m.info.reach_m,
        rated_payload_kg: m.info.rated_payload_kg,
        moving_mass_kg: m.moving_mass(),
        closed_form_ik: m.opw.is_some(),
        drive_data: m.drive.is_some(),
        provenance: m.info.provenance.clone(),
        inertia_sources: m.info.inertia_sources.clone(),
        link_names: m.link_names.clone(),
    })
}

/// Print the robots as a table, then each one's provenance and where its link inertias come
/// from when not all from the URDF.
fn print_table(rows: &[RobotRow]) -> Result<()> {
    // Column widths from the longest id and name, so a long name does not shift the row.
    let wi = rows
        .iter()
        .map(|r| r.id.chars().count())
        .max()
        .unwrap_or(0)
        .max(2);
    let wn = rows
        .iter()
        .map(|r| r.name.chars().count())
        .max()
        .unwrap_or(0)
        .max(4);
    outln!(
        "{:<wi$} {:<wn$} {:>6} {:>8} {:>11} {:>10} {:>4} {:>5}",
        "id",
        "name",
        "joints",
        "reach_m",
        "payload_kg",
        "mass_kg",
        "opw",
        "drive"
    );
    for r in rows {
        let o = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.2}"));
        outln!(
            "{:<wi$} {:<wn$} {:>6} {:>8} {:>11} {:>10.1} {:>4} {:>5}",
            r.id,
            r.name,
            r.joints,
            o(r.reach_m),
            o(r.rated_payload_kg),
            r.moving_mass_kg,
            if r.closed_form_ik { "yes" } else { "no" },
            if r.drive_data { "yes" } else { "no" }
        );
    }
    outln!();
    for r in rows {
        outln!("{}: {}", r.id, r.provenance);
        // Where the link inertias come from, when not all from the URDF.
        let other: Vec<String> = r
            .link_names
            .iter()
            .zip(&r.inertia_sources)
            .filter(|(_, s)| **s != robot::inertia::InertiaSource::Urdf)
            .map(|(l, s)| format!("{l} {}", s.words()))
            .collect();
        if !other.is_empty() {
            outln!("{}: link inertias: {}", r.id, other.join(", "));
        }
    }
    Ok(())
}
