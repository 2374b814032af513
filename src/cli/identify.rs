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
    // Every output checked against every input before anything is computed or written.
    let inputs = super::inputs(
        &la.robot.robot,
        Some(&robot),
        &[Some(la.log.as_path()), a.validate_log.as_deref()],
    );
    if let Some(dir) = &a.out.out {
        printwatt::output::check_dir(dir, &inputs)?;
    }
    // The calibrated robot: always written, into --out (or the current directory), never
    // into the installed robots folder.
    let resolved = super::resolve_robot(&la.robot.robot);
    let dst = match &a.drive_out {
        Some(p) => p.clone(),
        None => a
            .out
            .out
            .clone()
            .unwrap_or_else(|| std::path::PathBuf::from("."))
            .join(identify::calibrate::default_file_name(&resolved)),
    };
    printwatt::output::check_file(
        &dst,
        &inputs,
        printwatt::output::Existing::Force(a.out.force),
    )?;
    let bar = super::compare::Bar::new();
    let prep = identify::Prepared::with_progress(&model, &log, &bar)?;
    drop(bar);
    let vlog = match &a.validate_log {
        Some(p) => {
            let v = identify::read_log_for(&robot, p, la.columns.as_deref())
                .with_context(|| format!("reading validation log {}", p.display()))?;
            super::note_warnings(&v.file, &v.warnings);
            Some(v)
        }
        None => None,
    };
    let vprep = match &vlog {
        Some(v) => Some(identify::Prepared::new(&model, v)?),
        None => None,
    };
    // The error per joint before the fit (on the validation log when there is one), for the
    // report written with --out.
    let before = a.out.out.as_ref().map(|_| match &vprep {
        Some(v) => identify::metrics::compare(v, &model).0,
        None => identify::metrics::compare(&prep, &model).0,
    });
    let id = plan.fit(&mut model, (&log, &prep), vlog.as_ref().zip(vprep.as_ref()))?;
    // The last check before anything leaves: the calibrated robot, the files, the JSON.
    printwatt::output::check_finite_json(
        &format!("identify of the log {}", a.log.log.display()),
        &id,
    )?;
    if !id.implausible.is_empty() {
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
            out!("{}", ladder_table(&id, log.kind.unit()));
        }
        anyhow::bail!(
            "the fit is not physically plausible, so no calibrated robot was written: {}",
            id.implausible.join("; ")
        );
    }
    let drive_src = identify::model::drive_file_of(&resolved);
    let installed = super::default_robots_dir();
    identify::calibrate::write_calibrated(
        &identify::calibrate::CalibrationInput {
            robot: &robot,
            drive_file: drive_src.as_deref(),
            robot_arg: &la.robot.robot.display().to_string(),
            model: &model,
            id: &id,
            log: &log,
            date: identify::calibrate::utc_date_today(),
        },
        &dst,
        Some(&installed),
        a.out.force,
    )?;
    let written = Some(dst);
    if let Some(dir) = &a.out.out {
        std::fs::create_dir_all(dir).map_err(|e| printwatt::Error::io(dir, e))?;
        let after = match &vprep {
            Some(v) => identify::metrics::compare(v, &model).0,
            None => identify::metrics::compare(&prep, &model).0,
        };
        let on = match &vlog {
            Some(v) => format!("the validation log {}", v.file),
            None => format!("the log fitted, {}", log.file),
        };
        let earlier = robot
            .effects
            .calibration
            .as_ref()
            .map_or(&[][..], |c| c.rounds.as_slice());
        let report = printwatt::report::identify::IdentifyReport {
            title: format!("printwatt identify: {} on {}", log.file, robot.name()),
            facts: vec![
                ("robot".into(), robot.name().to_string()),
                (
                    "robot file".into(),
                    printwatt::robot::robot_file_display(&robot),
                ),
                (
                    "drive data".into(),
                    printwatt::robot::drive_data_status(&robot),
                ),
                ("log".into(), log.file.clone()),
                ("signal unit".into(), log.kind.unit().to_string()),
                ("validated on".into(), id.validation.clone()),
                (
                    "calibrated robot".into(),
                    written
                        .as_ref()
                        .map_or(String::new(), |w| w.display().to_string()),
                ),
            ],
            earlier_rounds: earlier,
            id: &id,
            unit: log.kind.unit().to_string(),
            before_after: before.as_ref().map(|b| (b, &after, on)),
        };
        printwatt::output::write_atomic(&dir.join("ladder.svg"), report.ladder_svg().as_bytes())?;
        printwatt::output::write_atomic(&dir.join("report.html"), report.html().as_bytes())?;
        printwatt::output::write_atomic(
            &dir.join("ladder.md"),
            ladder_table(&id, log.kind.unit()).as_bytes(),
        )?;
        printwatt::output::write_atomic(
            &dir.join("identify.json"),
            printwatt::output::json_text(&id)?.as_bytes(),
        )?;
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
    outln!("{}", id.validation);
    out!("{}", ladder_table(&id, log.kind.unit()));
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
    if let Some(w) = written {
        outln!("wrote {}", w.display());
    }
    Ok(())
}

fn ladder_table(id: &ladder::Identification, unit: &str) -> String {
    let mut s = format!(
        "| step | train RMSE [{unit}] | validation RMSE [{unit}] | validation energy error [%] | accuracy [%] |\n|---|---|---|---|---|\n"
    );
    for r in &id.ladder {
        s.push_str(&format!(
            "| {} | {:.4} | {:.4} | {:.2} | {:.2} |\n",
            r.step,
            r.train_rmse,
            r.validation_rmse,
            r.validation_energy_error_pct,
            r.validation_accuracy_pct
        ));
    }
    s
}
