//! `printwatt diagnose`

use anyhow::Result;
use printwatt::identify::{self, diagnose};

/// Say that fewer folds were used than asked for (a warning, in `--json` too).
fn note_folds(a: &super::DiagnoseArgs, used: usize) {
    super::note_warnings(
        &a.log.log.display().to_string(),
        &[format!(
            "--folds {}: {used} folds used, blocks shorter than the residual's correlation time would not be independent",
            a.folds
        )],
    );
}

/// `printwatt diagnose`: rank the effects by the share of the residual they explain.
pub fn run(a: super::DiagnoseArgs) -> Result<()> {
    let (robot, mut model, log) = super::compare::load(&a.log)?;
    let bar = super::compare::Bar::new();
    let prep = identify::Prepared::with_progress(&model, &log, &bar)?;
    let mut d = diagnose::diagnose_with_progress(&prep, &mut model, a.folds, &bar)?;
    drop(bar);
    if d.folds != a.folds {
        note_folds(&a, d.folds);
    }
    d.calibration = robot.effects.calibration_summary();
    // The last check before anything leaves (the JSON or the printed ranking).
    printwatt::output::check_finite_json(
        &format!("diagnose of the log {}", a.log.log.display()),
        &d,
    )?;
    write_diagnosis(&a, &robot, &d)?;
    if a.out.json {
        super::print_json(&d)?;
        return Ok(());
    }
    outln!(
        "robot: {}",
        d.calibration
            .clone()
            .unwrap_or_else(|| format!("{} (nominal, not calibrated)", robot.name()))
    );
    outln!(
        "model: {}; RMSE {:.4} {}; {}-fold time blocks",
        d.model_effects.join(", "),
        d.base_rmse,
        log.kind.unit(),
        d.folds
    );
    outln!(
        "noise floor (estimated from the data) {:.4} {}; residual correlation time {:.3} s; blocks of {:.2} s",
        d.noise_floor,
        log.kind.unit(),
        d.correlation_time_s,
        d.block_length_s
    );
    outln!(
        "{:<4} {:<16} {:>8} {:>12} {:>8} {:>8} {:>10} {:>5}  joints",
        "rank",
        "effect",
        "status",
        "val_rmse",
        "cut_%",
        "t",
        "dBIC",
        "sig"
    );
    for (i, c) in d.candidates.iter().enumerate() {
        print_candidate(i, c)?;
    }
    if !d.not_observable.is_empty() {
        outln!(
            "not observable in a `{}` log: {}",
            log.kind.prefix(),
            d.not_observable.join(", ")
        );
    }
    for u in &d.unexplained {
        outln!("unexplained: {u}");
    }
    outln!("{}", d.verdict);
    Ok(())
}

/// With `--out DIR`: write `diagnose.json` there (checked against the inputs first).
fn write_diagnosis(
    a: &super::DiagnoseArgs,
    robot: &printwatt::robot::RobotModel,
    d: &diagnose::Diagnosis,
) -> Result<()> {
    if let Some(dir) = &a.out.out {
        let inputs = super::inputs(
            &a.log.robot.robot,
            Some(robot),
            &[Some(a.log.log.as_path())],
        );
        printwatt::output::check_dir(dir, &inputs)?;
        std::fs::create_dir_all(dir).map_err(|e| printwatt::Error::io(dir, e))?;
        printwatt::output::write_file(
            &dir.join("diagnose.json"),
            printwatt::output::json_text(d)?.as_bytes(),
            &inputs,
            printwatt::output::Existing::Force(a.out.force),
        )?;
    }
    Ok(())
}

/// Print the effect ranked `i` (from 0): its line of the ranking, why it is not plausible,
/// and for one of the three first that is significant, its parameters and note.
fn print_candidate(i: usize, c: &diagnose::Candidate) -> Result<()> {
    outln!(
        "{:<4} {:<16} {:>8} {:>12.4} {:>8.1} {:>8.1} {:>10.1} {:>5}  {:?}",
        i + 1,
        c.effect,
        if c.in_model { "refit" } else { "missing" },
        c.validation_rmse,
        c.rmse_cut_pct,
        c.t_statistic,
        c.delta_bic,
        if c.significant {
            "yes"
        } else if !c.plausible {
            "n/a"
        } else {
            "no"
        },
        c.joints
    );
    if let Some(w) = &c.implausible {
        outln!("       not plausible for this robot: {w}");
    }
    if i < 3 && c.significant {
        for p in &c.params {
            if p.value != p.nominal {
                match p.std_error {
                    Some(se) => outln!(
                        "       {} = {:.4} ± {:.4} {} (was {:.4})",
                        p.name,
                        p.value,
                        se,
                        p.unit,
                        p.nominal
                    ),
                    None => outln!("       {} = not identifiable", p.name),
                }
            }
        }
        if let Some(n) = &c.note {
            outln!("       {n}");
        }
    }
    Ok(())
}
