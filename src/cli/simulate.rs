//! `printwatt simulate`

use super::load_robot;
use anyhow::{bail, Context, Result};
use printwatt::identify::{self, log::SignalKind, simulate};

/// `printwatt simulate`: a log from a "true" robot with hidden effects.
pub fn run(a: super::SimulateArgs) -> Result<()> {
    let robot = load_robot(&a.robot)?;
    // The output is checked against the inputs before any work.
    printwatt::output::check_file(
        &a.out,
        &super::inputs(
            &a.robot,
            Some(&robot),
            &[a.path.as_deref(), a.trajectory.as_deref()],
        ),
        printwatt::output::Existing::Replace,
    )?;
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
    let hidden = simulate::parse_hidden(a.hidden.as_deref().unwrap_or(""))?;
    simulate::apply_hidden(&mut truth, &hidden)?;
    let kind = SignalKind::parse(&a.signal)
        .with_context(|| format!("--signal `{}`: expected tau, i, p or p_total", a.signal))?;
    if !(a.rate > 0.0 && a.rate.is_finite()) {
        bail!("--rate must be > 0 Hz");
    }
    let dense = match (&a.path, &a.trajectory, a.excite) {
        (Some(p), None, None) => {
            let at = a.at.as_deref().context("--path needs --at x,y,z,yaw_deg")?;
            let pl = printwatt::toolpath::Placement::parse(at).with_context(|| {
                format!(
                    "--at `{at}`: expected x,y,z,yaw in m, m, m, deg (and an optional spin, deg)"
                )
            })?;
            let tp = super::load_path(p, &printwatt::toolpath::ReadOptions::default())?;
            let job = printwatt::placement::PathJob::new(
                &robot,
                &tp,
                printwatt::energy::EnergyOptions::default(),
                printwatt::timing::ProfileOptions::default(),
                printwatt::timing::JointStageOptions::default(),
            )?;
            match job.evaluate(&pl)? {
                Ok(e) => e.timed.traj,
                Err(f) => bail!("the path is not feasible at {at}: {f}"),
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
    let inputs = super::inputs(
        &a.robot,
        Some(&robot),
        &[a.path.as_deref(), a.trajectory.as_deref()],
    );
    printwatt::output::write_file(
        &a.out,
        text.as_bytes(),
        &inputs,
        printwatt::output::Existing::Replace,
    )?;
    eprintln!(
        "wrote {} ({} samples at {} Hz)",
        a.out.display(),
        traj.len(),
        a.rate
    );
    Ok(())
}
