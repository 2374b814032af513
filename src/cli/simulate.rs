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
    let mut truth = identify::Model::new(&robot)?;
    let hidden = simulate::parse_hidden(a.hidden.as_deref().unwrap_or("")).context("--hidden")?;
    simulate::apply_hidden(&mut truth, &hidden)?;
    let kind = SignalKind::parse(&a.signal)
        .with_context(|| format!("--signal `{}`: expected tau, i, p or p_total", a.signal))?;
    if !(a.rate > 0.0 && a.rate.is_finite()) {
        bail!("--rate must be > 0 Hz");
    }
    let placement = a.at.one()?;
    let dense = match (&a.path.path, &a.trajectory, a.excite) {
        (Some(p), None, None) => {
            let pl = placement.context("--path needs --at x,y,z,yaw")?;
            let tp = super::load_path(p, &a.path.read_options(&a.timing)?)?;
            let job = printwatt::evaluate::PathJob::new(
                &robot,
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
            let (mut tr, sup) = printwatt::trajectory::read_csv_for(t, &robot)?;
            printwatt::dynamics::complete_derivatives(&mut tr, sup)?;
            tr
        }
        (None, None, Some(d)) => simulate::excitation(&robot, d, 1000.0, a.seed),
        _ => bail!("give exactly one of --path P --at …, --trajectory T, --excite SECONDS"),
    };
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
    let meta = vec![
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
    ];
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
        let (columns, rows) = csv_columns_rows(&text)?;
        let mut v = serde_json::json!({
            "schema_version": identify::JSON_SCHEMA_VERSION,
            "robot": robot.name(),
            "log": out_file.as_ref().map(|f| f.display().to_string()),
            "signal": kind.prefix(),
            "unit": kind.unit(),
            "samples": traj.len(),
            "rate_hz": a.rate,
            "hidden": a.hidden.as_deref().unwrap_or(""),
            "noise": noise,
            "noise_q_rad": a.noise_q,
            "seed": a.seed,
            "columns": columns,
        });
        // A JSON run without --out writes no file: the samples come in the JSON.
        if out_file.is_none() {
            v["rows"] = serde_json::json!(rows);
        }
        super::print_json(&v)?;
    }
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
