//! The calibrated robot: a drive file that names its URDF and carries the identified
//! parameters with their standard errors, the logs and dates they came from and every earlier
//! round's parameters ([`crate::effects::Calibration`]). Written with the one drive-file schema
//! ([`crate::robot::drive`], serde both ways), for robots with per-joint drive tables (the
//! identified values go to the drive keys), without them and for URDF-only robots (they go
//! to `[effects.values]`). Every command takes the written file as `--robot`.

use crate::effects::Effect;
use crate::error::{Error, Result};
use crate::identify::ladder::Identification;
use crate::identify::model::Model;
use crate::identify::Log;
use crate::robot::drive::{parse_drive_file, DriveFile, DriveKept, DriveKeysMut, PayloadTable};
use crate::robot::RobotModel;
use crate::robot::{CalibratedParam, Calibration, CalibrationRound};
use std::path::{Component, Path, PathBuf};

/// What [`write_calibrated`] needs.
#[derive(Debug)]
pub struct CalibrationInput<'a> {
    /// The robot as loaded (its URDF path in `source`, its drive file in `effects.file`).
    pub robot: &'a RobotModel,
    /// The drive file the robot was loaded from, if any.
    pub drive_file: Option<&'a Path>,
    /// The `--robot` argument as the user gave it.
    pub robot_arg: &'a str,
    /// The model after identification.
    pub model: &'a Model,
    /// The identification (ladder, parameters, held parameters).
    pub id: &'a Identification,
    /// The log fitted.
    pub log: &'a Log,
    /// UTC date `YYYY-MM-DD`.
    pub date: String,
}

/// Default file name of the calibrated robot: `<name>.calibrated.toml`, where `<name>` is the
/// robot's directory or file name without `.calibrated` (so rounds never grow the name).
pub fn default_file_name(robot_arg: &Path) -> String {
    let base = robot_arg
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "robot".into());
    let mut stem = base
        .trim_end_matches(".toml")
        .trim_end_matches(".urdf")
        .to_string();
    for suffix in [".calibrated", ".identified"] {
        while let Some(s) = stem.strip_suffix(suffix) {
            stem = s.to_string();
        }
    }
    if stem == "drive" || stem.is_empty() {
        stem = robot_arg
            .parent()
            .and_then(|p| p.file_name())
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "robot".into());
    }
    format!("{stem}.calibrated.toml")
}

/// The relative path from directory `from` to `to` (both made absolute), or `to` absolute.
pub(crate) fn relative_path(from: &Path, to: &Path) -> PathBuf {
    let abs = |p: &Path| {
        p.canonicalize().unwrap_or_else(|_| {
            std::env::current_dir()
                .map(|c| c.join(p))
                .unwrap_or(p.to_path_buf())
        })
    };
    let (f, t) = (abs(from), abs(to));
    let fc: Vec<Component> = f.components().collect();
    let tc: Vec<Component> = t.components().collect();
    let common = fc.iter().zip(&tc).take_while(|(a, b)| a == b).count();
    if common == 0 {
        return t;
    }
    let mut r = PathBuf::new();
    for _ in common..fc.len() {
        r.push("..");
    }
    for c in &tc[common..] {
        r.push(c.as_os_str());
    }
    r
}

/// Today's UTC date `YYYY-MM-DD` (civil-from-days, Howard Hinnant's algorithm).
pub(crate) fn utc_date_today() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs() as i64)
        .unwrap_or(0);
    let z = secs.div_euclid(86_400) + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!("{y:04}-{m:02}-{d:02}")
}

/// Whether `path` lies inside directory `dir` (both canonicalised where they exist).
pub(crate) fn is_inside(path: &Path, dir: &Path) -> bool {
    let Ok(d) = dir.canonicalize() else {
        return false;
    };
    let parent = path.parent().unwrap_or(Path::new("."));
    let parent = if parent.as_os_str().is_empty() {
        Path::new(".")
    } else {
        parent
    };
    parent.canonicalize().is_ok_and(|p| p.starts_with(&d))
}

/// The calibrated drive file's text.
pub fn calibrated_text(inp: &CalibrationInput, dst: &Path) -> Result<String> {
    let mut f = base_drive_file(inp, dst)?;
    write_effects(&mut f, inp.model, inp.robot.drive.is_some())?;
    f.calibration = Some(calibration_record(inp));
    let body = f.to_toml()?;
    Ok(format!(
        "# calibrated robot written by `printwatt identify` on {} from {}; every printwatt command takes it as its robot.\n\
# All values SI, unit in the key; [calibration] lists every identified parameter with its\n\
# standard error, the round, log and date it came from.\n{body}",
        inp.date, inp.log.file
    ))
}

/// The drive file the calibrated one starts from (the input's, or an empty one), pointing at
/// the robot's URDF from `dst`'s folder and naming the robot.
fn base_drive_file(inp: &CalibrationInput, dst: &Path) -> Result<DriveFile> {
    let robot = inp.robot;
    let mut f: DriveFile = match inp.drive_file {
        Some(p) => {
            let text = crate::error::read_text(p)?;
            parse_drive_file(&text, &p.display().to_string())?
        }
        None => DriveFile::default(),
    };
    let dst_dir = match dst.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    f.robot.urdf = Some(
        relative_path(&dst_dir, &robot.source)
            .to_string_lossy()
            .into_owned(),
    );
    if f.robot.name.is_none() {
        f.robot.name = Some(robot.name().to_string());
    }
    Ok(f)
}

/// The model's effects into `f`: each effect writes its values to the drive keys it owns
/// (per-joint drive tables only); every other enabled effect (and, without drive tables,
/// every enabled one) keeps its values in `[effects.values]`, which wins over the `[effects]`
/// keys they replace. The effect that is the robot's own body ([`DriveKept::Body`]: the
/// payload) is written as the robot's payload.
fn write_effects(f: &mut DriveFile, model: &Model, has_drive: bool) -> Result<()> {
    let mut effects = f.effects.take().unwrap_or_default();
    let mut values = effects.values.take().unwrap_or_default();
    let mut enabled = model.enabled_names();
    let mut body = None;
    for name in crate::effects::catalogue() {
        let e = model.effect(name)?;
        let mut keys = DriveKeysMut::new(f, &model.gear, has_drive);
        let kept = e.write_drive_keys(&mut keys)?;
        let kept = keys.kept(kept);
        if kept == DriveKept::Body {
            values.remove(name);
            enabled.retain(|x| *x != name);
            for key in e.effects_keys() {
                effects.clear_key(key)?;
            }
            body = Some(e);
            continue;
        }
        if kept == DriveKept::Keys {
            values.remove(name);
            continue;
        }
        if model.is_enabled(name) {
            values.insert(name.to_string(), e.values());
            for key in e.effects_keys() {
                effects.clear_key(key)?;
            }
        } else {
            values.remove(name);
        }
    }
    if let Some(p) = body.map(|e| payload_table(model, e)).transpose()?.flatten() {
        f.payload = Some(p);
    }
    effects.enabled = Some(enabled.iter().map(|s| s.to_string()).collect());
    effects.values = (!values.is_empty()).then_some(values);
    f.effects = Some(effects);
    Ok(())
}

/// The identified payload `payload` as the robot's payload: mass, centre of mass and inertia
/// about the centre of mass, in the flange frame (named in the description), exactly the body
/// the fit scored. `None` when the payload is off or null.
fn payload_table(model: &Model, payload: &dyn Effect) -> Result<Option<PayloadTable>> {
    if !model.is_enabled(payload.name()) || payload.is_null() {
        return Ok(None);
    }
    let Some(p) = payload.as_any().downcast_ref::<crate::effects::Payload>() else {
        return Ok(None);
    };
    let pv = payload.values();
    let (b, lift) = crate::identify::plausible::payload_written(p);
    let i = b.inertia;
    Ok(Some(PayloadTable {
        mass_kg: b.mass,
        com_m: [b.com.x, b.com.y, b.com.z],
        inertia_kg_m2: [
            i[(0, 0)],
            i[(1, 1)],
            i[(2, 2)],
            i[(0, 1)],
            i[(0, 2)],
            i[(1, 2)],
        ],
        description: Some(format!(
            "payload identified by printwatt identify; centre of mass and inertia (about the centre of mass) in the frame of flange link `{}` (mass error {:+.4} kg, first moment error [{:+.4}, {:+.4}, {:+.4}] kg·m{})",
            model.flange_link,
            pv[0],
            pv[1],
            pv[2],
            pv[3],
            if lift > 0.0 {
                format!("; inertia raised by {lift:.2e} kg·m² to a rigid body's")
            } else {
                String::new()
            }
        )),
    }))
}

/// The calibration record: earlier rounds carried over, this round appended, every
/// identified parameter with the round it came from.
fn calibration_record(inp: &CalibrationInput) -> Calibration {
    let mut cal = inp
        .robot
        .effects
        .calibration
        .clone()
        .unwrap_or(Calibration {
            base_robot: inp.robot_arg.to_string(),
            ..Default::default()
        });
    let round = cal.rounds.len() + 1;
    cal.rounds.push(this_round(inp, round));
    for p in &inp.id.params {
        let key = format!("{}.{}", p.effect, p.name);
        let held_reason = inp
            .id
            .held_at_prior
            .iter()
            .find(|h| h.name == key)
            .map(|h| h.reason.clone());
        let held = held_reason.is_some();
        let entry = CalibratedParam {
            effect: p.effect.clone(),
            name: p.name.clone(),
            unit: p.unit.clone(),
            value: p.value,
            std_error: if held { None } else { p.std_error },
            prior: p.nominal,
            round,
            status: match held_reason {
                Some(r) => format!("held at prior: {r}"),
                None => "fitted".into(),
            },
        };
        match cal
            .params
            .iter_mut()
            .find(|q| q.effect == entry.effect && q.name == entry.name)
        {
            // A parameter held this round keeps an earlier round's fitted value.
            Some(q) if held && q.status == "fitted" => {}
            Some(q) => *q = entry,
            None => cal.params.push(entry),
        }
    }
    cal
}

/// This round of the calibration: its log, effects, validation and the correlation of what it
/// fitted (held parameters keep no standard error).
fn this_round(inp: &CalibrationInput, round: usize) -> CalibrationRound {
    let (before, after) = (
        inp.id
            .ladder
            .first()
            .map_or(f64::NAN, |s| s.validation_rmse),
        inp.id.ladder.last().map_or(f64::NAN, |s| s.validation_rmse),
    );
    // The correlation of what this round fitted (held parameters keep no standard error).
    let corr = &inp.id.correlation;
    let kept: Vec<usize> = (0..corr.params.len())
        .filter(|&i| {
            !inp.id
                .held_at_prior
                .iter()
                .any(|h| h.name == corr.params[i])
        })
        .filter(|&i| {
            corr.matrix
                .get(i)
                .is_some_and(|r| r.len() == corr.params.len())
        })
        .collect();
    CalibrationRound {
        round,
        date: inp.date.clone(),
        log: inp.log.file.clone(),
        signal: inp.log.kind.prefix().to_string(),
        effects: inp
            .id
            .ladder
            .last()
            .map(|s| s.fitted.clone())
            .unwrap_or_default(),
        validation: inp.id.validation.clone(),
        validation_rmse_before: before,
        validation_rmse_after: after,
        correlated: kept.iter().map(|&i| corr.params[i].clone()).collect(),
        correlation: kept
            .iter()
            .map(|&i| kept.iter().map(|&k| corr.matrix[i][k]).collect())
            .collect(),
    }
}

/// Write the calibrated robot to `dst`. Refuses: the input drive file or URDF itself, a file
/// inside `installed` (the shipped robots folder), an existing file unless `force`.
pub fn write_calibrated(
    inp: &CalibrationInput,
    dst: &Path,
    installed: Option<&Path>,
    force: bool,
) -> Result<()> {
    let same = |a: &Path, b: &Path| {
        a == b
            || a.canonicalize()
                .ok()
                .is_some_and(|x| b.canonicalize().is_ok_and(|y| x == y))
    };
    if inp.drive_file.is_some_and(|s| same(dst, s)) || same(dst, &inp.robot.source) {
        return Err(Error::OutputRefused {
            path: dst.to_path_buf(),
            reason: "it is the input robot file".into(),
        });
    }
    if let Some(dir) = installed {
        if is_inside(dst, dir) {
            return Err(Error::OutputRefused {
                path: dst.to_path_buf(),
                reason: format!("it is inside the installed robots folder {}", dir.display()),
            });
        }
    }
    if dst.exists() && !force {
        return Err(Error::OutputExists {
            path: dst.to_path_buf(),
        });
    }
    let text = calibrated_text(inp, dst)?;
    crate::output::write_atomic(dst, text.as_bytes())
}
