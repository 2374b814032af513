//! `printwatt energy`: the energy of one joint trajectory, or of a toolpath at one placement.

use super::args;
use anyhow::{bail, Context, Result};
use printwatt::dynamics::complete_derivatives;
use printwatt::energy::{self, EnergyModel, EnergyReport};
use printwatt::evaluate::PathJob;
use printwatt::output::Existing;
use printwatt::timing::{JointStageOptions, Slowdown};
use printwatt::trajectory;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// `printwatt energy`
#[derive(clap::Args, Debug)]
pub struct EnergyCmd {
    #[command(flatten)]
    pub robot: args::RobotArg,
    /// Joint trajectory CSV: `t, q1..qN` (+ optional `qd1..qdN`, `qdd1..qddN`); units in
    /// brackets (`t[ms]`, `q1[deg]`), SI by default. Missing derivatives: central differences.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["path", "at"])]
    pub trajectory: Option<PathBuf>,
    #[command(flatten)]
    pub path: args::PathArg,
    #[command(flatten)]
    pub at: args::AtArg,
    #[command(flatten)]
    pub timing: args::TimingArgs,
    #[command(flatten)]
    pub energy: args::EnergyArgs,
    /// The checks an --at placement is put through, as in `sweep`: a failed one is stated (in
    /// the summary, on stderr and in the JSON `feasibility`) with the reason `sweep` gives, and
    /// the motion is evaluated regardless; a path that cannot be timed there is an error.
    #[command(flatten)]
    pub feasibility: args::FeasibilityArgs,
    /// --out: the per-sample CSV `<input stem>.energy.csv` (t, q, q̇, q̈, torque, mechanical and
    /// electrical power per joint, supply power).
    #[command(flatten)]
    pub out: args::OutputArgs,
    /// Write no per-sample CSV (print the summary only).
    #[arg(long)]
    pub no_csv: bool,
}

#[derive(Serialize)]
struct Summary<'a> {
    robot: &'a str,
    input: String,
    placement: Option<PlacementOut>,
    /// The placement checks `sweep` applies (none for a trajectory).
    #[serde(skip_serializing_if = "Option::is_none")]
    feasibility: Option<&'a FeasibilityOut>,
    print_time_s: f64,
    slowdowns: &'a [Slowdown],
    output_csv: Option<String>,
    energy: &'a EnergyReport,
}

/// The placement's checks: `{"status": "feasible"}` or `{"status": "infeasible", "reason": …}`
/// with the fields of a sweep row's infeasible outcome.
#[derive(Serialize)]
#[serde(tag = "status", rename_all = "snake_case")]
enum FeasibilityOut {
    Feasible,
    Infeasible(printwatt::evaluate::Infeasible),
}

#[derive(Serialize)]
struct PlacementOut {
    x_m: f64,
    y_m: f64,
    z_m: f64,
    yaw_deg: f64,
    nozzle_spin_deg: f64,
}

/// Run `printwatt energy`.
pub fn run(a: EnergyCmd) -> Result<()> {
    let model = a.robot.load()?;
    let opts = a.energy.options()?;
    let placement = a.at.one()?;
    if a.trajectory.is_none() && placement.is_none() {
        bail!("give either --trajectory T, or --at x,y,z,yaw (with --path P; default paths/default.gcode)");
    }
    let input = match &a.trajectory {
        Some(t) => t.clone(),
        None => a.path.file(),
    };
    // Every output is checked against every input before anything is computed or written.
    let inputs = super::inputs(
        &a.robot.robot,
        Some(&model),
        &[Some(input.as_path()), a.robot.tool.as_deref()],
    );
    let out_dir = if a.no_csv {
        None
    } else {
        a.out.dir(Some(Path::new(".")))
    };
    let out = out_dir.as_ref().map(|d| d.join(default_out(&input)));
    if let Some(d) = &out_dir {
        args::check_out_dir(d)?;
    }
    if let Some(o) = &out {
        printwatt::output::check_file(o, &inputs, Existing::Force(a.out.force))?;
    }
    let Evaluation {
        traj,
        slowdowns,
        report,
        feasibility,
    } = match &a.trajectory {
        Some(tp) => evaluate_trajectory(tp, &model, opts)?,
        None => evaluate_at(&a, &model, opts, placement, &input)?,
    };
    check_report_finite(&report, &traj, &input)?;
    if let Some(o) = &out {
        if let Some(d) = &out_dir {
            std::fs::create_dir_all(d).map_err(|e| printwatt::Error::io(d, e))?;
        }
        // Streamed as it is formatted: a long print's series is never held as text.
        printwatt::output::write_file_with(o, &inputs, Existing::Force(a.out.force), &mut |w| {
            report.series.write_csv(Some(&traj), w)
        })?;
    }
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
        feasibility: feasibility.as_ref(),
        print_time_s: report.duration_s,
        slowdowns: &slowdowns,
        output_csv: out.as_ref().map(|o| o.display().to_string()),
        energy: &report,
    };
    if a.out.json {
        let mut v = serde_json::to_value(&summary)?;
        if let Some(e) = v.get_mut("energy").and_then(|e| e.as_object_mut()) {
            e.remove("series"); // per-sample data go to the CSV
        }
        super::print_json(&v)?;
    } else {
        print_summary(&summary, &model)?;
    }
    Ok(())
}

/// What `energy` computed: the joint trajectory, where the timing slowed down, the energy
/// report, and the placement's checks (none for a trajectory).
struct Evaluation {
    traj: trajectory::JointTrajectory,
    slowdowns: Vec<Slowdown>,
    report: EnergyReport,
    feasibility: Option<FeasibilityOut>,
}

/// The joint trajectory file `tp` read for the robot (missing derivatives completed) and
/// its energy.
fn evaluate_trajectory(
    tp: &Path,
    model: &printwatt::robot::RobotModel,
    opts: energy::EnergyOptions,
) -> Result<Evaluation> {
    let (mut traj, sup) = trajectory::read_csv_for(tp, model)?;
    complete_derivatives(&mut traj, sup)?;
    let em = EnergyModel::with_options(model, opts)?;
    let report = energy::evaluate(&em, &traj)?;
    Ok(Evaluation {
        traj,
        slowdowns: Vec::new(),
        report,
        feasibility: None,
    })
}

/// The path `input` timed and evaluated at the `--at` placement, put through the checks of
/// `sweep` (a failed one is stated, and the motion evaluated regardless).
fn evaluate_at(
    a: &EnergyCmd,
    model: &printwatt::robot::RobotModel,
    opts: energy::EnergyOptions,
    placement: Option<printwatt::frame::Placement>,
    input: &Path,
) -> Result<Evaluation> {
    let placement = placement.context("--at")?;
    let path = super::load_path(input, &a.path.read_options(&a.timing)?)?;
    let profile = a.timing.profile()?;
    let job = PathJob::new(model, &path, opts, profile, JointStageOptions::default())?;
    let feas = a.feasibility.options(model.dof())?;
    let (ev, failed) = job.evaluate_checked(&placement, feas)?.map_err(|e| {
        anyhow::anyhow!(
            "placement {} is infeasible: {e}",
            a.at.at.as_deref().unwrap_or_default()
        )
    })?;
    let feasibility = match failed {
        None => FeasibilityOut::Feasible,
        Some(why) => {
            super::note_warnings(
                &input.display().to_string(),
                &[format!(
                    "placement {} is INFEASIBLE as `sweep` checks it: {why}; its energy is \
                     evaluated regardless",
                    a.at.at.as_deref().unwrap_or_default()
                )],
            );
            FeasibilityOut::Infeasible(why)
        }
    };
    Ok(Evaluation {
        traj: ev.timed.traj,
        slowdowns: ev.timed.slowdowns,
        report: ev.energy,
        feasibility: Some(feasibility),
    })
}

/// The last check before the numbers leave: every per-sample value of the trajectory and of the
/// energy series, and every total, finite; else an error naming the first sample and quantity.
/// The series are scanned where they are (no text is formatted), and only the totals are
/// turned into a JSON value.
fn check_report_finite(
    report: &EnergyReport,
    traj: &printwatt::trajectory::JointTrajectory,
    input: &Path,
) -> Result<()> {
    let what = format!("energy of {}", input.display());
    if let Some((col, k, v)) = report.series.first_non_finite(Some(traj)) {
        bail!(
            "{what}: `{col}` is {v} at sample {k}: the model produced a number that is not a number; check the robot's drive and inertia data"
        );
    }
    let v = serde_json::json!({
        "duration_s": report.duration_s,
        "standby_power_w": report.standby_power_w,
        "joints": report.joints,
        "total": report.total,
    });
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

fn print_summary(s: &Summary, model: &printwatt::robot::RobotModel) -> Result<()> {
    let r = s.energy;
    outln!("robot      {}", s.robot);
    outln!("input      {}", s.input);
    if let Some(p) = &s.placement {
        outln!(
            "placement  x {:.3} m, y {:.3} m, z {:.3} m, yaw {:.1} deg, nozzle spin {:.1} deg",
            p.x_m,
            p.y_m,
            p.z_m,
            p.yaw_deg,
            p.nozzle_spin_deg
        );
    }
    match s.feasibility {
        Some(FeasibilityOut::Feasible) => {
            outln!("checks     feasible (the checks of `sweep`)")
        }
        Some(FeasibilityOut::Infeasible(why)) => {
            outln!("checks     INFEASIBLE (the checks of `sweep`): {why}; evaluated regardless")
        }
        None => {}
    }
    outln!("model      {}", r.model);
    outln!("time       {:.2} s ({} samples)", r.duration_s, r.samples);
    for sd in s.slowdowns {
        let ramp = if sd.accel_factor < 1.0 {
            format!(", ramp acceleration x{:.2}", sd.accel_factor)
        } else {
            String::new()
        };
        outln!(
            "slow-down  joint {} {:?} limit at t = {:.2} s (path {:.3} m, move {}): demand {:.2}x the limit, speed x{:.2}{ramp}",
            sd.joint + 1, sd.kind, sd.t, sd.s, sd.move_index + 1, sd.ratio, sd.speed_factor
        );
    }
    outln!();
    print_joints(r, model)?;
    outln!();
    print_supply(&r.total)?;
    print_by_effect(&r.by_effect)?;
    if let Some(o) = &s.output_csv {
        outln!("per-sample torque and power written to {o}");
    }
    Ok(())
}

/// Print the table of the joints' energies, peak power and RMS torque, with the totals.
fn print_joints(r: &EnergyReport, model: &printwatt::robot::RobotModel) -> Result<()> {
    outln!(
        "{:<10} {:>12} {:>12} {:>12} {:>12} {:>12} {:>10}",
        "joint",
        "mech [J]",
        "friction [J]",
        "copper [J]",
        "elec [J]",
        "peak P [W]",
        "rms τ [Nm]"
    );
    for (j, je) in r.joints.iter().enumerate() {
        let name = model
            .joints
            .get(j)
            .map_or(je.name.as_str(), |x| x.name.as_str());
        outln!(
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
    outln!(
        "{:<10} {:>12.1} {:>12.1} {:>12.1} {:>12.1}",
        "total",
        t.mechanical_j,
        t.friction_j,
        t.copper_j,
        t.electrical_j
    );
    Ok(())
}

/// One decimal; a value that rounds to zero is printed 0.0, not -0.0 (the signed rigid-body
/// and balancer work of a closed print cycle is near zero).
fn j1(x: f64) -> String {
    let s = format!("{x:.1}");
    if s == "-0.0" {
        "0.0".to_string()
    } else {
        s
    }
}

/// Print each effect's energy and the part of the supply energy it is booked to.
fn print_by_effect(by: &[energy::EffectEnergy]) -> Result<()> {
    if by.is_empty() {
        return Ok(());
    }
    let each: Vec<String> = by
        .iter()
        .map(|e| match e.energy_j {
            Some(j) => format!("{} {} J ({})", e.effect, j1(j), e.part),
            None => format!("{} (inside the rigid body)", e.effect),
        })
        .collect();
    outln!("by effect  {}", each.join(", "));
    Ok(())
}

/// Print the supply energy and its parts.
fn print_supply(t: &energy::TotalEnergy) -> Result<()> {
    outln!(
        "supply energy {} J = rigid body {}{} + friction {} + gear {} + copper {} + regeneration lost {} + standby {}",
        j1(t.supply_j),
        j1(t.rigid_body_j),
        if t.balancer_j != 0.0 {
            format!(" + balancer {}", j1(t.balancer_j))
        } else {
            String::new()
        },
        j1(t.friction_j),
        j1(t.gear_j),
        j1(t.copper_j),
        j1(t.regeneration_lost_j),
        j1(t.standby_j)
    );
    Ok(())
}
