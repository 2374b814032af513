//! `printwatt simulate`

use anyhow::{bail, Context, Result};
use printwatt::identify::{self, log::SignalKind, simulate};

/// `printwatt simulate`: a log from a "true" robot with hidden effects.
pub fn run(a: super::SimulateArgs) -> Result<()> {
    let robot = a.robot.load()?;
    // The output is checked against the inputs before any work.
    let inputs = super::inputs(
        &a.robot.robot,
        Some(&robot),
        &[
            a.path.path.as_deref(),
            a.trajectory.as_deref(),
            a.robot.tool.as_deref(),
        ],
    );
    let out_dir = a.out.dir(Some(std::path::Path::new(".")));
    let out_file = out_dir.as_ref().map(|d| d.join("log.csv"));
    if let (Some(d), Some(f)) = (&out_dir, &out_file) {
        super::args::check_out_dir(d)?;
        printwatt::output::check_file(f, &inputs, printwatt::output::Existing::Force(a.out.force))?;
    }
    check_numbers(&a)?;
    let mut truth = identify::Model::new(&robot)?;
    let hidden = simulate::parse_hidden(a.hidden.as_deref().unwrap_or("")).context("--hidden")?;
    simulate::apply_hidden(&mut truth, &hidden)?;
    let kind = SignalKind::parse(&a.signal)
        .with_context(|| format!("--signal `{}`: expected tau, i, p or p_total", a.signal))?;
    if !(a.rate > 0.0 && a.rate.is_finite()) {
        bail!("--rate must be > 0 Hz");
    }
    let placement = a.at.one()?;
    let dense = dense_trajectory(&a, &robot, placement)?;
    let traj = simulate::resample(&dense, a.rate);
    let noise = a.noise.unwrap_or(match kind {
        SignalKind::Torque => 2.0,
        SignalKind::Current => 0.02,
        SignalKind::AxisPower => 5.0,
        SignalKind::TotalPower => 20.0,
    });
    let opt = simulate::SensorOptions {
        kind,
        noise,
        noise_q: a.noise_q,
        current_quantum: a.quantum,
        seed: a.seed,
    };
    let meta = log_meta(&a, &robot, kind, noise);
    let text = simulate::simulate_log(&truth, &traj, &opt, &meta)?;
    if let (Some(d), Some(f)) = (&out_dir, &out_file) {
        std::fs::create_dir_all(d).map_err(|e| printwatt::Error::io(d, e))?;
        printwatt::output::write_file(
            f,
            text.as_bytes(),
            &inputs,
            printwatt::output::Existing::Force(a.out.force),
        )?;
        if !a.out.json {
            eprintln!(
                "wrote {} ({} samples at {} Hz)",
                f.display(),
                traj.len(),
                a.rate
            );
        }
    }
    if a.out.json {
        let log = Log {
            robot: &robot,
            kind,
            noise,
            samples: traj.len(),
            file: out_file.as_deref(),
        };
        print_json_summary(&a, &log, &text)?;
    }
    Ok(())
}

/// The metadata lines of the simulated log: robot, sample rate, and how it was simulated.
fn log_meta(
    a: &super::SimulateArgs,
    robot: &printwatt::robot::RobotModel,
    kind: SignalKind,
    noise: f64,
) -> Vec<(String, String)> {
    vec![
        ("robot".to_string(), robot.name().to_string()),
        ("sample_rate_hz".into(), format!("{}", a.rate)),
        (
            "description".into(),
            format!(
                "simulated by printwatt simulate; hidden: {}; noise {} {} (signal), {} rad (q); seed {}",
                a.hidden.as_deref().unwrap_or("none"),
                noise,
                kind.unit(),
                a.noise_q,
                a.seed
            ),
        ),
    ]
}

/// Refuse non-finite noise, quantum and rate, an excitation over the sample budget and a
/// rate no controller logs at.
fn check_numbers(a: &super::SimulateArgs) -> Result<()> {
    for (opt, v) in [
        ("--noise-q", a.noise_q),
        ("--quantum", a.quantum),
        ("--rate", a.rate),
    ] {
        super::finite(opt, v)?;
    }
    if let Some(n) = a.noise {
        super::finite("--noise", n)?;
    }
    if let Some(d) = a.excite {
        if !(d.is_finite() && d > 0.0) {
            bail!("--excite {d}: expected a duration > 0 s");
        }
        // Budget: the dense excitation is sampled at 1 kHz (6 joints × 3 quantities).
        let samples = d * 1000.0;
        if samples > printwatt::timing::budget::max_samples() as f64 {
            bail!(
                "--excite {d} s needs {samples:.3e} samples at 1 kHz, more than the budget of {} ({}): did you mean {} s?",
                printwatt::timing::budget::max_samples(),
                printwatt::timing::budget::MAX_SAMPLES_ENV,
                d / 1000.0
            );
        }
    }
    if a.rate > 1e5 {
        bail!(
            "--rate {} Hz: above 100 kHz no controller logs; did you mean {} Hz?",
            a.rate,
            a.rate / 1000.0
        );
    }
    Ok(())
}

/// The dense joint trajectory to sample: the path timed at the placement, a trajectory file,
/// or an excitation of the given duration (exactly one of them).
fn dense_trajectory(
    a: &super::SimulateArgs,
    robot: &printwatt::robot::RobotModel,
    placement: Option<printwatt::frame::Placement>,
) -> Result<printwatt::trajectory::JointTrajectory> {
    Ok(match (&a.path.path, &a.trajectory, a.excite) {
        (Some(p), None, None) => {
            let pl = placement.context("--path needs --at x,y,z,yaw")?;
            let tp = super::load_path(p, &a.path.read_options(&a.timing)?)?;
            let job = printwatt::evaluate::PathJob::new(
                robot,
                &tp,
                printwatt::energy::EnergyOptions::default(),
                a.timing.profile()?,
                printwatt::timing::JointStageOptions::default(),
            )?;
            match job.evaluate(&pl)? {
                Ok(e) => e.timed.traj,
                Err(f) => bail!(
                    "the path is not feasible at {}: {f}",
                    a.at.at.as_deref().unwrap_or_default()
                ),
            }
        }
        (None, Some(t), None) => {
            let (mut tr, sup) = printwatt::trajectory::read_csv_for(t, robot)?;
            printwatt::dynamics::complete_derivatives(&mut tr, sup)?;
            tr
        }
        (None, None, Some(d)) => simulate::excitation(robot, d, 1000.0, a.seed),
        _ => bail!("give exactly one of --path P --at …, --trajectory T, --excite SECONDS"),
    })
}

/// The simulated log as the JSON summary describes it.
struct Log<'a> {
    robot: &'a printwatt::robot::RobotModel,
    kind: SignalKind,
    noise: f64,
    samples: usize,
    file: Option<&'a std::path::Path>,
}

/// Print the JSON summary of the simulated log `text` (its samples too when no file is
/// written).
fn print_json_summary(a: &super::SimulateArgs, log: &Log, text: &str) -> Result<()> {
    let (columns, rows) = csv_columns_rows(text)?;
    let mut v = serde_json::json!({
        "schema_version": identify::JSON_SCHEMA_VERSION,
        "robot": log.robot.name(),
        "log": log.file.map(|f| f.display().to_string()),
        "signal": log.kind.prefix(),
        "unit": log.kind.unit(),
        "samples": log.samples,
        "rate_hz": a.rate,
        "hidden": a.hidden.as_deref().unwrap_or(""),
        "noise": log.noise,
        "noise_q_rad": a.noise_q,
        "seed": a.seed,
        "columns": columns,
    });
    // A JSON run without --out writes no file: the samples come in the JSON.
    if log.file.is_none() {
        v["rows"] = serde_json::json!(rows);
    }
    super::print_json(&v)?;
    Ok(())
}

/// The header (column names with units) and the rows of a simulated log's CSV text (`#`
/// metadata lines skipped).
fn csv_columns_rows(text: &str) -> Result<(Vec<String>, Vec<Vec<f64>>)> {
    let mut lines = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty());
    let columns: Vec<String> = lines
        .next()
        .unwrap_or_default()
        .split(',')
        .map(|c| c.trim().to_string())
        .collect();
    let rows = lines
        .map(|l| {
            l.split(',')
                .map(|x| x.trim().parse::<f64>())
                .collect::<std::result::Result<Vec<f64>, _>>()
        })
        .collect::<std::result::Result<Vec<_>, _>>()
        .context("simulated log: a value that is not a number")?;
    Ok((columns, rows))
}
