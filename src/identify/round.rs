//! One round of the measurement loop as a user runs it, shared by the binary and the Python
//! bindings: read a log against a robot (units checked), switch effects on and off by name
//! (`viscous[2]`: joint 2 only), plan which effects a round fits (the ones asked for, plus the
//! effects of earlier calibration rounds, re-fitted jointly), and fit them with the
//! train/validation split.

use crate::error::{Error, Result};
use crate::identify::ladder::{self, HeldParam, Identification};
use crate::identify::log::{Log, SignalKind};
use crate::identify::metrics;
use crate::identify::model::{parse_effect_subsets, Model, Prepared};
use crate::robot::RobotModel;
use std::path::Path;

/// Read a measured log for `robot` (docs/measurement-logs.md; `columns`: a column map for a
/// log without header) and check that its joint columns' units suit the robot's joint kinds
/// (angles for revolute joints, lengths for prismatic ones). Errors name the file and row.
pub fn read_log_for(robot: &RobotModel, path: &Path, columns: Option<&str>) -> Result<Log> {
    let log = crate::identify::read_log(path, robot.dof(), columns)?;
    let (names, units): (Vec<String>, Vec<String>) = log.units.iter().cloned().unzip();
    let kinds: Vec<_> = robot.joints.iter().map(|j| j.kind).collect();
    crate::trajectory::check_joint_units(&log.file, log.header_line, &names, &units, &kinds)?;
    Ok(log)
}

/// Switch effects of `model` (a robot of `n` joints) on and off by name: `on` (comma list;
/// when given, every other effect is switched off) and then `off`. `viscous[2]` means the
/// effect on (off) joint 2 only: its parameters of the other joints (of joint 2) are set to
/// zero ([`Model::keep_joints`]). Errors: an unknown effect, a joint beyond `n`, a parameter
/// whose bounds exclude zero.
pub fn switch_effects(
    model: &mut Model,
    n: usize,
    on: Option<&str>,
    off: Option<&str>,
) -> Result<()> {
    if let Some(list) = on {
        let subsets = parse_effect_subsets(list, n)?;
        model.disable_all();
        for (e, joints) in subsets {
            model.set_enabled(e, true)?;
            if let Some(js) = joints {
                model.keep_joints(e, &js)?;
            }
        }
    }
    if let Some(list) = off {
        for (e, joints) in parse_effect_subsets(list, n)? {
            match joints {
                None => model.set_enabled(e, false)?,
                Some(js) => {
                    let rest: Vec<usize> = (1..=n).filter(|k| !js.contains(k)).collect();
                    model.keep_joints(e, &rest)?;
                }
            }
        }
    }
    Ok(())
}

/// What one identification round fits.
#[derive(Clone, Debug, PartialEq)]
pub struct RoundPlan {
    /// The effects fitted, in ladder order: the carried ones first, then the asked ones.
    pub effects: Vec<&'static str>,
    /// Effects of earlier calibration rounds (a calibrated robot) re-fitted jointly with the
    /// asked ones, not frozen.
    pub carried: Vec<&'static str>,
    /// Parameters held at their prior values (outside an `effect[j]` subset), with the reason.
    pub hold: Vec<HeldParam>,
    /// Whether Coulomb friction is fitted per direction (`coulomb_directional` asked for);
    /// symmetric otherwise.
    pub directional_coulomb: bool,
    /// Whether the payload's inertia is fitted (`payload_inertia` asked for).
    pub payload_inertia: bool,
}

impl RoundPlan {
    /// Plan a round on `robot` (whose calibration, if any, names earlier rounds' effects) for
    /// a log of `kind`: `fit` is the comma list of effects to fit (`coulomb,viscous[2]`; a
    /// joint in brackets fits that joint's parameters, the others are held at their prior).
    /// Errors: nothing named, an unknown effect or joint, an effect this log's signal cannot
    /// see.
    pub fn new(robot: &RobotModel, model: &Model, fit: &str, kind: SignalKind) -> Result<Self> {
        let subsets = parse_effect_subsets(fit, robot.dof())?;
        if subsets.is_empty() {
            return Err(Error::Invalid(
                "no effect to fit named: give a comma list, e.g. coulomb,balancer".into(),
            ));
        }
        let asked: Vec<&'static str> = subsets.iter().map(|(e, _)| *e).collect();
        let mut hold = Vec::new();
        for (e, joints) in &subsets {
            if let Some(js) = joints {
                let list: Vec<String> = js.iter().map(|j| j.to_string()).collect();
                for name in model.params_outside(e, js)? {
                    hold.push(HeldParam {
                        name,
                        reason: format!("only joint(s) {} of `{e}` asked for", list.join(", ")),
                    });
                }
            }
        }
        let mut carried: Vec<&'static str> = Vec::new();
        if let Some(c) = &robot.effects.calibration {
            for e in c.rounds.iter().flat_map(|r| r.effects.iter()) {
                if let Some(name) = crate::effects::catalogue().into_iter().find(|n| n == e) {
                    if !asked.contains(&name)
                        && !carried.contains(&name)
                        && model.observable(name, kind)
                    {
                        carried.push(name);
                    }
                }
            }
        }
        let effects: Vec<&'static str> = carried.iter().chain(&asked).copied().collect();
        if let Some(e) = effects.iter().find(|e| !model.observable(e, kind)) {
            return Err(Error::Invalid(format!(
                "effect `{e}` cannot be seen in a `{}` log",
                kind.prefix()
            )));
        }
        Ok(RoundPlan {
            effects,
            carried,
            hold,
            directional_coulomb: crate::identify::model::asks_directional_coulomb(fit),
            payload_inertia: crate::identify::model::asks_payload_inertia(fit),
        })
    }

    /// Fit the round: on the whole of `log` validated on the whole of `validation` when one
    /// is given, else on the first 75 % of `log` validated on the last 25 %
    /// ([`crate::identify::train_validation_split`]). `prep` is `log` prepared for `model`,
    /// `vprep` the validation log prepared likewise. The model ends with the fitted values.
    pub fn fit(
        &self,
        model: &mut Model,
        log: (&Log, &Prepared),
        validation: Option<(&Log, &Prepared)>,
    ) -> Result<Identification> {
        let (l, prep) = log;
        model.coulomb_directional = self.directional_coulomb;
        model.payload_inertia = self.payload_inertia;
        match validation {
            Some((v, vprep)) => {
                let tr: Vec<usize> = (0..l.len()).collect();
                let va: Vec<usize> = (0..v.len()).collect();
                let what = format!("fitted on {}, validated on {}", l.file, v.file);
                ladder::identify_holding(
                    model,
                    (prep, &tr),
                    (vprep, &va),
                    &self.effects,
                    what,
                    &self.hold,
                )
            }
            None => {
                let (train, val) = crate::identify::train_validation_split(l.len());
                if val.is_empty() || train.is_empty() {
                    return Err(Error::Invalid(format!(
                        "{}: {} samples are too few to split into fit and validation",
                        l.file,
                        l.len()
                    )));
                }
                let what = format!(
                    "fitted on the first 75 % of {} (t < {:.2} s), validated on the last 25 %",
                    l.file, l.traj.t[val.start]
                );
                let tr: Vec<usize> = train.collect();
                let va: Vec<usize> = val.collect();
                ladder::identify_holding(
                    model,
                    (prep, &tr),
                    (prep, &va),
                    &self.effects,
                    what,
                    &self.hold,
                )
            }
        }
    }
}

/// One identification round as a job: the robot and logs, the plan, where the calibrated robot
/// and the report go. [`run_round`] runs it for the binary and the Python bindings alike.
pub struct RoundJob<'a> {
    /// The robot as loaded (a calibrated one: its earlier rounds are in its effects).
    pub robot: &'a RobotModel,
    /// The robot as the user named it (a shipped name or a path), recorded in the calibrated
    /// file.
    pub robot_arg: &'a str,
    /// Where the robot was read from (a shipped name resolved to its directory).
    pub resolved: &'a Path,
    /// The log fitted.
    pub log: &'a Log,
    /// A validation log; without one the last 25 % of `log` validates.
    pub validation: Option<&'a Log>,
    /// What the round fits ([`RoundPlan::new`]).
    pub plan: &'a RoundPlan,
    /// The calibrated robot's file (drive file format), written unless the fit is implausible.
    pub calibrated_to: &'a Path,
    /// The installed robots' directory: the calibrated robot is never written into it.
    pub installed: Option<&'a Path>,
    /// Replace an existing calibrated robot or report.
    pub force: bool,
    /// A directory for the round's report (`report.html`, `ladder.svg`, `ladder.md`,
    /// `identify.json`), or none.
    pub report_dir: Option<&'a Path>,
    /// Every input file, checked against every output before any work.
    pub inputs: &'a crate::output::Inputs,
}

/// What one round found and wrote.
pub struct RoundResult {
    /// The identification: ladder, parameters with standard errors, held and implausible ones.
    pub id: Identification,
    /// The calibrated robot written; none when the fit is not physically plausible (then
    /// nothing is written: [`RoundResult::refusal`]).
    pub written: Option<std::path::PathBuf>,
}

impl RoundResult {
    /// For a fit that is not physically plausible, the error that says why no calibrated robot
    /// was written.
    pub fn refusal(&self) -> Option<Error> {
        (!self.id.implausible.is_empty()).then(|| {
            Error::Invalid(format!(
                "the fit is not physically plausible, so no calibrated robot was written: {}",
                self.id.implausible.join("; ")
            ))
        })
    }
}

/// The round's report in `dir`: the error per joint before (`before`) and after the fit on the
/// log `on` was prepared from, the ladder (SVG and Markdown), the page and the JSON.
fn write_report(
    job: &RoundJob,
    model: &Model,
    on: &Prepared,
    id: &Identification,
    before: &metrics::Comparison,
    written: &Path,
    dir: &Path,
) -> Result<()> {
    use crate::output;
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let after = metrics::compare_metrics(on, model);
    let on = match job.validation {
        Some(v) => format!("the validation log {}", v.file),
        None => format!("the log fitted, {}", job.log.file),
    };
    let robot = job.robot;
    let earlier = robot
        .effects
        .calibration
        .as_ref()
        .map_or(&[][..], |c| c.rounds.as_slice());
    let unit = job.log.kind.unit();
    let report = crate::report::identify::IdentifyReport {
        title: format!("printwatt identify: {} on {}", job.log.file, robot.name()),
        facts: vec![
            ("robot".into(), robot.name().to_string()),
            ("robot file".into(), crate::robot::robot_file_display(robot)),
            ("drive data".into(), crate::robot::drive_data_status(robot)),
            ("log".into(), job.log.file.clone()),
            ("signal unit".into(), unit.to_string()),
            ("validated on".into(), id.validation.clone()),
            ("calibrated robot".into(), written.display().to_string()),
        ],
        earlier_rounds: earlier,
        id,
        unit: unit.to_string(),
        before_after: Some((before, &after, on)),
    };
    output::write_atomic(&dir.join("ladder.svg"), report.ladder_svg().as_bytes())?;
    output::write_atomic(&dir.join("report.html"), report.html().as_bytes())?;
    output::write_atomic(&dir.join("ladder.md"), ladder::table(id, unit).as_bytes())?;
    output::write_atomic(
        &dir.join("identify.json"),
        output::json_text(id)?.as_bytes(),
    )?;
    Ok(())
}

/// Run one identification round: check every output against every input, prepare the logs
/// for `model` (`progress` told how far), fit the plan, and, when the fit is physically
/// plausible, write the calibrated robot and the report. `model` ends with the fitted values.
pub fn run_round(
    job: &RoundJob,
    model: &mut Model,
    progress: &dyn crate::identify::Progress,
) -> Result<RoundResult> {
    use crate::identify::calibrate;
    use crate::output::{self, Existing};
    if let Some(dir) = job.report_dir {
        output::check_dir(dir, job.inputs)?;
    }
    output::check_file(job.calibrated_to, job.inputs, Existing::Force(job.force))?;
    let prep = Prepared::with_progress(model, job.log, progress)?;
    let vprep = match job.validation {
        Some(v) => Some(Prepared::new(model, v)?),
        None => None,
    };
    // The error per joint before the fit (on the validation log when there is one).
    let on = vprep.as_ref().unwrap_or(&prep);
    let before = job.report_dir.map(|_| metrics::compare_metrics(on, model));
    let id = job
        .plan
        .fit(model, (job.log, &prep), job.validation.zip(vprep.as_ref()))?;
    // The last check before anything leaves: the calibrated robot, the files, the JSON.
    output::check_finite_json(&format!("identify of the log {}", job.log.file), &id)?;
    if !id.implausible.is_empty() {
        return Ok(RoundResult { id, written: None });
    }
    let drive_src = crate::identify::model::drive_file_of(job.resolved);
    calibrate::write_calibrated(
        &calibrate::CalibrationInput {
            robot: job.robot,
            drive_file: drive_src.as_deref(),
            robot_arg: job.robot_arg,
            model,
            id: &id,
            log: job.log,
            date: calibrate::utc_date_today(),
        },
        job.calibrated_to,
        job.installed,
        job.force,
    )?;
    let written = job.calibrated_to.to_path_buf();
    if let (Some(dir), Some(before)) = (job.report_dir, before) {
        write_report(job, model, on, &id, &before, &written, dir)?;
    }
    Ok(RoundResult {
        id,
        written: Some(written),
    })
}
