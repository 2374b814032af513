//! `printwatt identify`

use anyhow::{Context, Result};
use printwatt::identify::{self, ladder};

/// `printwatt identify`: fit the listed effects in turn, report the ladder, write the
/// calibrated robot (`<name>.calibrated.toml` in --out or the current directory).
pub fn run(a: super::IdentifyArgs) -> Result<()> {
    let mut la = a.log.clone();
    let fit_list = la.effects.take().unwrap_or_default();
    let (robot, mut model, log) = super::compare::load(&la)?;
    // `coulomb,viscous[2]`: effects, each for every joint or for the joints in brackets (the
    // others' parameters held at their prior values). A calibrated robot: the effects of
    // earlier rounds are re-fitted jointly with the new ones (first, so the ladder shows
    // them), not frozen; parameters this log cannot determine are held at their calibrated
    // values by the ladder.
    let plan = identify::RoundPlan::new(&robot, &model, &fit_list, log.kind)
        .with_context(|| format!("--effects `{fit_list}`"))?;
    // The calibrated robot: always written, into --out (or the current directory), never
    // into the installed robots folder; the round checks every output against every input
    // before any work.
    let inputs = super::inputs(
        &la.robot.robot,
        Some(&robot),
        &[Some(la.log.as_path()), a.validate_log.as_deref()],
    );
    let resolved = super::resolve_robot(&la.robot.robot);
    let dst = calibrated_path(&a, &resolved);
    let vlog = validation_log(&a, &robot)?;
    let installed = super::default_robots_dir();
    let job = identify::RoundJob {
        robot: &robot,
        robot_arg: &la.robot.robot.display().to_string(),
        resolved: &resolved,
        log: &log,
        validation: vlog.as_ref(),
        plan: &plan,
        calibrated_to: &dst,
        installed: Some(&installed),
        force: a.out.force,
        report_dir: a.out.out.as_deref(),
        inputs: &inputs,
    };
    let bar = super::compare::Bar::new();
    let round = identify::run_round(&job, &mut model, &bar);
    drop(bar);
    let round = round?;
    let (id, written) = (&round.id, round.written.clone());
    if let Some(refused) = round.refusal() {
        // Reported, never written as the calibrated robot.
        if a.out.json {
            let v = serde_json::json!({
                "schema_version": 1,
                "identification": id,
                "drive_file": null,
                "calibrated_robot": null,
            });
            super::print_json(&v)?;
        } else {
            out!("{}", ladder::table(id, log.kind.unit()));
        }
        return Err(refused.into());
    }
    if a.out.json {
        let v = serde_json::json!({
            "schema_version": 1,
            "identification": id,
            "drive_file": written,
            "calibrated_robot": written,
            "started_from": robot.effects.calibration_summary(),
            "refitted_from_earlier_rounds": plan.carried,
        });
        super::print_json(&v)?;
        return Ok(());
    }
    print_round(id, &robot, &plan, log.kind.unit())?;
    if let Some(w) = written {
        outln!("wrote {}", w.display());
    }
    Ok(())
}

/// Where the calibrated robot goes: `--drive-out`, else its default name in `--out` (or the
/// current directory).
fn calibrated_path(a: &super::IdentifyArgs, resolved: &std::path::Path) -> std::path::PathBuf {
    match &a.drive_out {
        Some(p) => p.clone(),
        None => a
            .out
            .out
            .clone()
            .unwrap_or_else(|| std::path::PathBuf::from("."))
            .join(identify::calibrate::default_file_name(resolved)),
    }
}

/// The validation log (`--validate-log`), read for the robot with its warnings noted.
fn validation_log(
    a: &super::IdentifyArgs,
    robot: &printwatt::robot::RobotModel,
) -> Result<Option<identify::Log>> {
    Ok(match &a.validate_log {
        Some(p) => {
            let v = identify::read_log_for(robot, p, a.log.columns.as_deref())
                .with_context(|| format!("reading validation log {}", p.display()))?;
            super::note_warnings(&v.file, &v.warnings);
            Some(v)
        }
        None => None,
    })
}

/// Print the round: the validation, the ladder, where it started, what was re-fitted, held
/// or at a bound, and the parameters it changed (`unit`: of the compared signal).
fn print_round(
    id: &ladder::Identification,
    robot: &printwatt::robot::RobotModel,
    plan: &identify::RoundPlan,
    unit: &str,
) -> Result<()> {
    outln!("{}", id.validation);
    out!("{}", ladder::table(id, unit));
    if let Some(c) = robot.effects.calibration_summary() {
        outln!("started from {c}");
    }
    if !plan.carried.is_empty() {
        outln!(
            "re-fitted jointly with this round: {} (from earlier rounds)",
            plan.carried.join(", ")
        );
    }
    if let Some(ill) = &id.ill_conditioned {
        outln!("{ill}");
    }
    for h in &id.held_at_prior {
        outln!("held at its prior value: {} ({})", h.name, h.reason);
    }
    for b in &id.at_bound {
        outln!(
            "at a bound of its range: {b} (the fit wanted to go further: another effect may be missing; try it jointly, e.g. --effects {},<next candidate>)",
            id.ladder.last().map(|s| s.fitted.join(",")).unwrap_or_default()
        );
    }
    outln!("identified parameters (changed ones):");
    for p in &id.params {
        if (p.value - p.nominal).abs() > 1e-12 {
            if id
                .held_at_prior
                .iter()
                .any(|h| h.name == format!("{}.{}", p.effect, p.name))
            {
                continue;
            }
            outln!(
                "  {:<16} {:<10} {:>12.4} ± {:<10.4} {} (was {:.4})",
                p.effect,
                p.name,
                p.value,
                p.std_error.unwrap_or(f64::NAN),
                p.unit,
                p.nominal
            );
        }
    }
    Ok(())
}
