//! `printwatt energy`: the energy of one joint trajectory, or of a toolpath at one placement.

use super::load_robot;
use anyhow::{bail, Context, Result};
use printwatt::dynamics::complete_derivatives;
use printwatt::energy::{self, EnergyModel, EnergyOptions, EnergyReport};
use printwatt::output::{write_file, Existing};
use printwatt::placement::PathJob;
use printwatt::robot::Regeneration;
use printwatt::timing::{JointStageOptions, ProfileOptions, Slowdown};
use printwatt::toolpath::{self, Placement, ReadOptions};
use printwatt::trajectory;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// `printwatt energy`
#[derive(clap::Args, Debug)]
pub struct EnergyArgs {
    /// Robot: a directory with robot.urdf (+ drive.toml), a .urdf, a drive .toml, or the name
    /// of a shipped robot.
    #[arg(long)]
    pub robot: PathBuf,
    /// Joint trajectory CSV: `t, q1..qN` (+ optional `qd1..qdN`, `qdd1..qddN`); units in
    /// brackets (`t[ms]`, `q1[deg]`), SI by default. Missing derivatives: central differences.
    #[arg(long, conflicts_with_all = ["path", "at"])]
    pub trajectory: Option<PathBuf>,
    /// Toolpath (G-code, CSV of points, ABB RAPID module), timed at the placement `--at`.
    #[arg(long, requires = "at")]
    pub path: Option<PathBuf>,
    /// Placement of the path's part frame in the robot base frame: `x,y,z,yaw` in m, m, m, deg.
    #[arg(long, allow_hyphen_values = true)]
    pub at: Option<String>,
    /// Nozzle rotation about its own (vertical) axis relative to the part, deg.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub spin: f64,
    /// Corner blend radius for G-code moves that give none, mm.
    #[arg(long, default_value_t = 5.0)]
    pub zone: f64,
    /// Interpolation period of the controller, ms (the output sample period).
    #[arg(long, default_value_t = 4.0)]
    pub period: f64,
    /// TCP acceleration limit, m/s².
    #[arg(long, default_value_t = 1.0)]
    pub accel: f64,
    /// TCP jerk limit, m/s³.
    #[arg(long, default_value_t = 10.0)]
    pub jerk: f64,
    /// Override the drive file's regeneration policy: none, per_axis, dc_bus, grid.
    #[arg(long)]
    pub regeneration: Option<String>,
    /// Leave the payload out.
    #[arg(long)]
    pub no_payload: bool,
    /// Leave friction out.
    #[arg(long)]
    pub no_friction: bool,
    /// Per-sample output CSV (t, q, q̇, q̈, torque, mechanical and electrical power per joint,
    /// supply power). Default: `<input stem>.energy.csv` beside the current directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct Summary<'a> {
    robot: &'a str,
    input: String,
    placement: Option<PlacementOut>,
    print_time_s: f64,
    slowdowns: &'a [Slowdown],
    output_csv: String,
    energy: &'a EnergyReport,
}

#[derive(Serialize)]
struct PlacementOut {
    x_m: f64,
    y_m: f64,
    z_m: f64,
    yaw_deg: f64,
    nozzle_spin_deg: f64,
}

/// Parse `--at x,y,z,yaw[,spin]` ([`Placement::parse`]); a `--spin` other than 0 sets the
/// nozzle spin (giving both is an error).
pub fn parse_placement(s: &str, spin_deg: f64) -> Result<Placement> {
    let mut p = Placement::parse(s).with_context(|| format!("--at `{s}`"))?;
    if spin_deg != 0.0 {
        if s.split(',').count() == 5 {
            bail!("--at `{s}` gives a nozzle spin and so does --spin {spin_deg}: give one");
        }
        p.nozzle_spin = spin_deg.to_radians();
    }
    Ok(p)
}

/// Run `printwatt energy`.
pub fn run(a: EnergyArgs) -> Result<()> {
    let model = load_robot(&a.robot)?;
    let spin = super::finite("--spin", a.spin)?;
    // Every output is checked against every input before anything is computed or written.
    let inputs = super::inputs(
        &a.robot,
        Some(&model),
        &[a.trajectory.as_deref(), a.path.as_deref()],
    );
    let planned_out = a.out.clone().or_else(|| {
        a.trajectory
            .as_deref()
            .or(a.path.as_deref())
            .map(default_out)
    });
    if let Some(o) = &planned_out {
        printwatt::output::check_file(o, &inputs, Existing::Replace)?;
    }
    let mut opts = EnergyOptions {
        payload: !a.no_payload,
        friction: !a.no_friction,
        ..Default::default()
    };
    if let Some(r) = &a.regeneration {
        opts.regeneration = Some(Regeneration::parse(r).with_context(|| {
            format!("--regeneration `{r}`: expected none, per_axis, dc_bus or grid")
        })?);
    }
    let (input, traj, placement, slowdowns, report) = if let Some(tp) = &a.trajectory {
        let (mut traj, sup) = trajectory::read_csv_for(tp, &model)?;
        complete_derivatives(&mut traj, sup)?;
        let em = EnergyModel::with_options(&model, opts)?;
        let report = energy::evaluate(&em, &traj)?;
        (tp.clone(), traj, None, Vec::new(), report)
    } else if let (Some(pp), Some(at)) = (&a.path, &a.at) {
        let placement = parse_placement(at, spin)?;
        let ro = ReadOptions {
            default_zone: toolpath::Zone::Blend(a.zone * 1e-3),
            ..Default::default()
        };
        for (opt, v) in [
            ("--zone", a.zone),
            ("--period", a.period),
            ("--accel", a.accel),
            ("--jerk", a.jerk),
        ] {
            super::finite(opt, v)?;
        }
        if a.zone < 0.0 {
            bail!("--zone {}: expected a blend radius >= 0 mm", a.zone);
        }
        let path = super::load_path(pp, &ro)?;
        let profile = ProfileOptions {
            accel: a.accel,
            lateral_accel: a.accel,
            jerk: a.jerk,
            dt: a.period * 1e-3,
            ..Default::default()
        };
        if !(profile.dt > 0.0 && profile.accel > 0.0 && profile.jerk > 0.0) {
            bail!("--period, --accel and --jerk must be > 0");
        }
        let job = PathJob::new(&model, &path, opts, profile, JointStageOptions::default())?;
        let ev = job
            .evaluate(&placement)?
            .map_err(|e| anyhow::anyhow!("placement {at} is infeasible: {e}"))?;
        (
            pp.clone(),
            ev.timed.traj,
            Some(placement),
            ev.timed.slowdowns,
            ev.energy,
        )
    } else {
        bail!("give either --trajectory T, or --path P with --at x,y,z,yaw");
    };
    let out = a.out.clone().unwrap_or_else(|| default_out(&input));
    let mut csv = Vec::new();
    report.series.write_csv(Some(&traj), &mut csv)?;
    check_report_finite(&report, &csv, &input)?;
    write_file(&out, &csv, &inputs, Existing::Replace)?;
    let summary = Summary {
        robot: model.name(),
        input: input.display().to_string(),
        placement: placement.map(|p| PlacementOut {
            x_m: p.x,
            y_m: p.y,
            z_m: p.z,
            yaw_deg: p.yaw.to_degrees(),
            nozzle_spin_deg: p.nozzle_spin.to_degrees(),
        }),
        print_time_s: report.duration_s,
        slowdowns: &slowdowns,
        output_csv: out.display().to_string(),
        energy: &report,
    };
    if a.json {
        let mut v = serde_json::to_value(&summary)?;
        if let Some(e) = v.get_mut("energy").and_then(|e| e.as_object_mut()) {
            e.remove("series"); // per-sample data go to the CSV
        }
        super::print_json(&v)?;
    } else {
        print_summary(&summary, &model);
    }
    Ok(())
}

/// The last check before the numbers leave: every per-sample value of the trajectory and of the
/// energy series, and every total, finite; else an error naming the first sample and quantity.
fn check_report_finite(report: &EnergyReport, csv: &[u8], input: &Path) -> Result<()> {
    let what = format!("energy of {}", input.display());
    let text = String::from_utf8_lossy(csv);
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap_or_default()
        .split(',')
        .map(str::to_string)
        .collect();
    for (k, l) in lines.enumerate() {
        for (j, c) in l.split(',').enumerate() {
            if matches!(c.trim(), "NaN" | "inf" | "-inf") {
                bail!(
                    "{what}: `{}` is {c} at sample {k}: the model produced a number that is not a number; check the robot's drive and inertia data",
                    header.get(j).map_or("?", String::as_str)
                );
            }
        }
    }
    let v = serde_json::to_value(report)?;
    // Totals: serde_json writes a non-finite number as null; a null where the report has a
    // number is the same failure.
    fn nulls(v: &serde_json::Value, path: &mut String, out: &mut Option<String>) {
        if out.is_some() {
            return;
        }
        match v {
            serde_json::Value::Null => *out = Some(path.clone()),
            serde_json::Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    let l = path.len();
                    path.push_str(&format!("[{i}]"));
                    nulls(x, path, out);
                    path.truncate(l);
                }
            }
            serde_json::Value::Object(o) => {
                for (k, x) in o {
                    if k == "series" {
                        continue;
                    }
                    let l = path.len();
                    path.push('.');
                    path.push_str(k);
                    nulls(x, path, out);
                    path.truncate(l);
                }
            }
            _ => {}
        }
    }
    let mut bad = None;
    nulls(&v, &mut String::new(), &mut bad);
    if let Some(p) = bad {
        bail!(
            "{what}: `energy{p}` is not a finite number: check the robot's drive and inertia data"
        );
    }
    Ok(())
}

fn default_out(input: &Path) -> PathBuf {
    let stem = input
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "trajectory".into());
    PathBuf::from(format!("{stem}.energy.csv"))
}

fn print_summary(s: &Summary, model: &printwatt::robot::RobotModel) {
    let r = s.energy;
    println!("robot      {}", s.robot);
    println!("input      {}", s.input);
    if let Some(p) = &s.placement {
        println!(
            "placement  x {:.3} m, y {:.3} m, z {:.3} m, yaw {:.1} deg, nozzle spin {:.1} deg",
            p.x_m, p.y_m, p.z_m, p.yaw_deg, p.nozzle_spin_deg
        );
    }
    println!("model      {}", r.model);
    println!("time       {:.2} s ({} samples)", r.duration_s, r.samples);
    for sd in s.slowdowns {
        println!(
            "slow-down  joint {} {:?} limit at t = {:.2} s (path {:.3} m, move {}): demand {:.2}x the limit, speed x{:.2}",
            sd.joint + 1, sd.kind, sd.t, sd.s, sd.move_index + 1, sd.ratio, sd.speed_factor
        );
    }
    println!();
    println!(
        "{:<10} {:>12} {:>12} {:>12} {:>12} {:>12} {:>10}",
        "joint", "mech [J]", "friction [J]", "copper [J]", "elec [J]", "peak P [W]", "rms τ [Nm]"
    );
    for (j, je) in r.joints.iter().enumerate() {
        let name = model
            .joints
            .get(j)
            .map_or(je.name.as_str(), |x| x.name.as_str());
        println!(
            "{:<10} {:>12.1} {:>12.1} {:>12.1} {:>12.1} {:>12.1} {:>10.1}",
            name,
            je.mechanical_j,
            je.friction_j,
            je.copper_j,
            je.electrical_j,
            je.peak_electrical_power_w.max(je.peak_mechanical_power_w),
            je.rms_torque_nm
        );
    }
    let t = &r.total;
    println!(
        "{:<10} {:>12.1} {:>12.1} {:>12.1} {:>12.1}",
        "total", t.mechanical_j, t.friction_j, t.copper_j, t.electrical_j
    );
    println!();
    println!(
        "supply energy {:.1} J = rigid body {:.1}{} + friction {:.1} + gear {:.1} + copper {:.1} + regeneration lost {:.1} + standby {:.1}",
        t.supply_j,
        t.rigid_body_j,
        if t.balancer_j != 0.0 {
            format!(" + balancer {:.1}", t.balancer_j)
        } else {
            String::new()
        },
        t.friction_j,
        t.gear_j,
        t.copper_j,
        t.regeneration_lost_j,
        t.standby_j
    );
    println!("per-sample torque and power written to {}", s.output_csv);
}
