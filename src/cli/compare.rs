//! `printwatt compare`, `diagnose`, `identify`: shared loading, and `compare` itself.

use super::LogArgs;
use anyhow::{Context, Result};
use printwatt::identify::motion::Rate;
use printwatt::identify::{self, metrics, model::Model, Log};
use printwatt::report::html::Page;
use printwatt::report::svg::{self, Series};
use std::path::Path;

/// A progress bar on stderr for the loop's long stages (hidden when stderr is not a terminal,
/// as indicatif does).
pub(crate) struct Bar(indicatif::ProgressBar);

impl Bar {
    pub(crate) fn new() -> Self {
        use std::io::IsTerminal;
        let b = if std::io::stderr().is_terminal() {
            indicatif::ProgressBar::new(0)
        } else {
            indicatif::ProgressBar::hidden()
        };
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{msg:18} [{bar:40}] {percent:>3} % ({elapsed} elapsed, ~{eta} left)",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        Bar(b)
    }
}

impl printwatt::identify::Progress for Bar {
    fn update(&self, stage: &str, done: u64, total: u64) {
        if self.0.length() != Some(total) {
            self.0.set_length(total);
        }
        if self.0.message() != stage {
            self.0.set_message(stage.to_string());
        }
        self.0.set_position(done);
    }
}

impl Drop for Bar {
    fn drop(&mut self) {
        self.0.finish_and_clear();
    }
}

/// The robot, the model (effects switched per drive file and command line) and the log.
pub(crate) fn load(a: &LogArgs) -> Result<(printwatt::robot::RobotModel, Model, Log)> {
    let robot = a.robot.load()?;
    let mut model = Model::new(&robot)
        .with_context(|| format!("building the model of {}", a.robot.robot.display()))?;
    // `viscous[2]`: the effect on joint 2 only (its parameters of the other joints zero), as
    // `identify --effects` and `simulate --hidden` take it.
    identify::switch_effects(&mut model, robot.dof(), a.effects.as_deref(), None)
        .with_context(|| format!("--effects `{}`", a.effects.as_deref().unwrap_or("")))?;
    identify::switch_effects(&mut model, robot.dof(), None, a.without.as_deref())
        .with_context(|| format!("--without `{}`", a.without.as_deref().unwrap_or("")))?;
    let log = identify::read_log_for(&robot, &a.log, a.columns.as_deref()).map_err(|e| {
        // A controller's export often has no header: say how to name its columns.
        let hint = if a.columns.is_none() && e.to_string().contains("found numbers") {
            "; a log without a header row needs --columns, e.g. --columns 't, q1..q6, tau1..tau6' \
             (docs/measurement-logs.md)"
        } else {
            ""
        };
        anyhow::anyhow!("reading log {}: {e}{hint}", a.log.display())
    })?;
    super::note_warnings(&log.file, &log.warnings);
    check_log_robot(&log, &robot);
    Ok((robot, model, log))
}

/// Warn when the log's metadata names another robot than the one it is compared with.
pub(crate) fn check_log_robot(log: &Log, robot: &printwatt::robot::RobotModel) {
    let named = log
        .metadata
        .iter()
        .find(|(k, _)| k.eq_ignore_ascii_case("robot"))
        .map(|(_, v)| v.trim().to_string());
    if let Some(n) = named {
        let norm = |s: &str| {
            s.chars()
                .filter(|c| c.is_ascii_alphanumeric())
                .collect::<String>()
                .to_ascii_lowercase()
        };
        let dir_name = robot
            .source
            .parent()
            .and_then(|p| p.file_name())
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default();
        let same = [robot.name(), dir_name.as_str()]
            .iter()
            .any(|r| !r.is_empty() && norm(r) == norm(&n));
        if !same && !n.is_empty() {
            super::note_warnings(
                &log.file,
                &[format!(
                    "{}: the log's metadata names robot `{n}`, but it is compared with `{}`",
                    log.file,
                    robot.name()
                )],
            );
        }
    }
}

/// `printwatt compare`.
pub fn run(a: super::CompareArgs) -> Result<()> {
    let (robot, model, log) = load(&a.log)?;
    let inputs = super::inputs(
        &a.log.robot.robot,
        Some(&robot),
        &[Some(a.log.log.as_path())],
    );
    check_outputs(&a, &inputs)?;
    let bar = Bar::new();
    let prep = identify::Prepared::with_progress(&model, &log, &bar)?;
    drop(bar);
    // The prediction is kept only for the report.
    let (mut cmp, pred) = if a.out.out.is_some() {
        metrics::compare(&prep, &model)
    } else {
        (metrics::compare_metrics(&prep, &model), Vec::new())
    };
    cmp.calibration = robot.effects.calibration_summary();
    // The last check before anything leaves: the JSON, the report and the printed table.
    printwatt::output::check_finite_json(
        &format!("compare of the log {}", a.log.log.display()),
        &cmp,
    )?;
    if let Some(dir) = &a.out.out {
        write_outputs(dir, &a, &inputs, (&log, &pred), &cmp)?;
    }
    if a.out.json {
        super::print_json(&cmp)?;
        return Ok(());
    }
    print_comparison(&cmp, &robot, &log)?;
    print_failures(&cmp)?;
    Ok(())
}

/// With `--out DIR`: check `compare.json` and `report.html` there against the inputs before
/// any work.
fn check_outputs(a: &super::CompareArgs, inputs: &printwatt::output::Inputs) -> Result<()> {
    if let Some(dir) = &a.out.out {
        printwatt::output::check_dir(dir, inputs)?;
        for f in ["compare.json", "report.html"] {
            printwatt::output::check_file(
                &dir.join(f),
                inputs,
                printwatt::output::Existing::Force(a.out.force),
            )?;
        }
    }
    Ok(())
}

/// Write `compare.json` and `report.html` (the model's prediction `pred` against the log,
/// checked finite first) into `dir`.
fn write_outputs(
    dir: &Path,
    a: &super::CompareArgs,
    inputs: &printwatt::output::Inputs,
    (log, pred): (&Log, &[f64]),
    cmp: &metrics::Comparison,
) -> Result<()> {
    // The report plots the model's prediction, sample by sample.
    let ch = log.channels.max(1);
    let names: Vec<String> = (0..ch)
        .map(|c| {
            cmp.channels.get(c).map_or_else(
                || format!("channel {}", c + 1),
                |x| format!("model {}", x.name),
            )
        })
        .collect();
    printwatt::output::check_finite("compare: model prediction", &names, pred.chunks(ch))?;
    printwatt::output::write_file(
        &dir.join("compare.json"),
        printwatt::output::json_text(cmp)?.as_bytes(),
        inputs,
        printwatt::output::Existing::Force(a.out.force),
    )?;
    write_report(&dir.join("report.html"), log, pred, cmp)?;
    Ok(())
}

/// Print the comparison: the robot, the log and the model, a table of the channels and the
/// worst windows.
fn print_comparison(
    cmp: &metrics::Comparison,
    robot: &printwatt::robot::RobotModel,
    log: &Log,
) -> Result<()> {
    outln!(
        "robot: {}",
        cmp.calibration
            .clone()
            .unwrap_or_else(|| format!("{} (nominal, not calibrated)", robot.name()))
    );
    outln!(
        "log {} ({} samples, {:.2} s, signal `{}` [{}]); model: {}",
        cmp.log,
        cmp.samples,
        cmp.duration_s,
        log.kind.prefix(),
        cmp.unit,
        cmp.effects.join(", ")
    );
    outln!(
        "{:<10} {:>12} {:>12} {:>12} {:>12} {:>9} {:>9}",
        "channel",
        "rmse",
        "meas_rms",
        "E_meas_J",
        "E_model_J",
        "dE_%",
        "acc_%"
    );
    for c in cmp.channels.iter().chain(std::iter::once(&cmp.total)) {
        outln!(
            "{:<10} {:>12.4} {:>12.4} {:>12.1} {:>12.1} {:>9.2} {:>9.2}",
            c.name,
            c.rmse,
            c.measured_rms,
            c.energy_measured_j,
            c.energy_model_j,
            c.energy_error_pct,
            c.accuracy_pct
        );
    }
    outln!("worst windows:");
    for w in &cmp.worst_windows {
        outln!(
            "  {:>8.2}–{:<8.2} s  rmse {:.4} (mostly {})",
            w.t_start,
            w.t_end,
            w.rmse,
            w.worst_channel
        );
    }
    Ok(())
}

/// Where the model fails: the ranked structures above the noise floor, and the direction step
/// at q̇ = 0 per joint (friction).
fn print_failures(cmp: &metrics::Comparison) -> Result<()> {
    let unit = &cmp.unit;
    outln!("where the model fails (residual RMS a structure explains beyond the noise floor):");
    let shown: Vec<_> = cmp
        .failures
        .iter()
        .filter(|f| f.ratio_to_noise >= 1.0)
        .take(10)
        .collect();
    if shown.is_empty() {
        outln!("  nothing beyond the noise floor");
    }
    for f in shown {
        outln!(
            "  {:<8} against joint {} {:<12} {:>10.4} {unit} ({:6.1} × noise floor, {:5.1} % of its residual variance)",
            f.channel, f.joint, f.structure, f.explained_rms, f.ratio_to_noise, f.explained_pct
        );
    }
    outln!("direction step of the residual at q̇ = 0 (friction; mean just above minus just below):");
    for p in &cmp.profiles {
        outln!(
            "  {:<8} joint {}: {:+.4} ± {:.4} {unit} (band ±{:.3}), noise floor {:.4} {unit}",
            p.channel,
            p.joint,
            p.direction_step,
            p.direction_step_se,
            p.step_band,
            p.noise_floor
        );
    }
    Ok(())
}

/// The report's "where the model fails" section: the ranked structures as a table and, per
/// joint, the binned residual against velocity, position and time.
fn failure_section(pg: &mut Page, cmp: &metrics::Comparison) {
    let unit = cmp.unit.as_str();
    pg.h2("Where the model fails");
    pg.p(&format!(
        "Per joint, the residual (model − measured) binned against the joint's velocity (friction \
shows as a step at q̇ = 0), position (gravity and balancer errors) and time (drift). The table \
ranks the structures by the residual RMS they explain beyond the noise floor [{unit}]."
    ));
    let header: Vec<String> = [
        "channel".to_string(),
        "joint".into(),
        "structure".into(),
        format!("explained RMS [{unit}]"),
        "× noise floor".into(),
        "% of residual variance".into(),
    ]
    .into();
    let rows: Vec<Vec<String>> = cmp
        .failures
        .iter()
        .take(15)
        .map(|f| {
            vec![
                f.channel.clone(),
                f.joint.to_string(),
                f.structure.clone(),
                format!("{:.4}", f.explained_rms),
                format!("{:.1}", f.ratio_to_noise),
                format!("{:.1}", f.explained_pct),
            ]
        })
        .collect();
    pg.table(&header, &rows);
    for k in 0..cmp.profiles.len() {
        pg.figure_row(&profile_row(cmp, k));
    }
}

/// The binned residual of the `k`-th joint profile against velocity, position and time, as
/// a row of figures.
fn profile_row(cmp: &metrics::Comparison, k: usize) -> Vec<(String, String, String)> {
    let (p, unit) = (&cmp.profiles[k], cmp.unit.as_str());
    let mut row = Vec::new();
    for pr in [&p.velocity, &p.position, &p.time] {
        let (x, y): (Vec<f64>, Vec<f64>) = pr
            .bins
            .iter()
            .filter(|b| b.samples > 0)
            .map(|b| (b.x, b.mean))
            .unzip();
        let fr = svg::Frame::new(
            &format!(
                "{} mean residual vs joint {} {}",
                p.channel, p.joint, pr.against
            ),
            &format!(
                "{} [{}]",
                if pr.against == "time" {
                    "time".to_string()
                } else {
                    format!("joint {} {}", p.joint, pr.against)
                },
                pr.unit
            ),
            &format!("mean residual [{unit}]"),
        )
        .size(345.0, 300.0);
        row.push((
            format!("{}-profile-{}-q{}", p.channel, pr.against, p.joint),
            svg::line_chart(&fr, &[Series::new("bin mean", &x, &y)]),
            format!(
                "{}: residual binned against {} (explains {:.4} {unit} beyond noise){}.",
                p.channel,
                pr.against,
                pr.explained_rms,
                if pr.against == "velocity" {
                    format!(
                        "; step at q̇ = 0: {:+.4} ± {:.4} {unit}",
                        p.direction_step, p.direction_step_se
                    )
                } else {
                    String::new()
                }
            ),
        ));
    }
    row
}

/// `report.html`: measured vs modelled, residual over time, residual vs q̇, q̈, q per joint.
fn write_report(path: &Path, log: &Log, pred: &[f64], cmp: &metrics::Comparison) -> Result<()> {
    let ch = log.channels;
    let unit = cmp.unit.as_str();
    let mut pg = Page::new(&format!("Model vs measurement: {}", cmp.log));
    pg.p(&format!(
        "Signal {} [{unit}], {} samples over {:.2} s; model effects: {}. Total RMSE {:.4} {unit}, \
energy error {:.2} %, accuracy {:.2} %. Residual = model − measured.",
        log.kind.prefix(),
        cmp.samples,
        cmp.duration_s,
        cmp.effects.join(", "),
        cmp.total.rmse,
        cmp.total.energy_error_pct,
        cmp.total.accuracy_pct
    ));
    let header: Vec<String> = [
        "channel".to_string(),
        format!("RMSE [{unit}]"),
        format!("measured RMS [{unit}]"),
        "E measured [J]".into(),
        "E model [J]".into(),
        "energy error [%]".into(),
        "accuracy [%]".into(),
    ]
    .into();
    let rows: Vec<Vec<String>> = cmp
        .channels
        .iter()
        .chain(std::iter::once(&cmp.total))
        .map(|c| {
            vec![
                c.name.clone(),
                format!("{:.4}", c.rmse),
                format!("{:.4}", c.measured_rms),
                format!("{:.1}", c.energy_measured_j),
                format!("{:.1}", c.energy_model_j),
                format!("{:.2}", c.energy_error_pct),
                format!("{:.2}", c.accuracy_pct),
            ]
        })
        .collect();
    pg.table(&header, &rows);
    failure_section(&mut pg, cmp);
    for c in 0..ch {
        channel_section(&mut pg, (log, pred), cmp, c);
    }
    printwatt::output::write_atomic(path, pg.finish().as_bytes())?;
    Ok(())
}

/// The report's section of channel `c`: measured and modelled signal, the residual over time
/// and, per joint it depends on, the residual against velocity, acceleration and position.
fn channel_section(
    pg: &mut Page,
    (log, pred): (&Log, &[f64]),
    cmp: &metrics::Comparison,
    c: usize,
) {
    let ch = log.channels;
    let n = log.traj.n;
    let t = &log.traj.t;
    let unit = cmp.unit.as_str();
    let y_label = |what: &str| format!("{what} [{unit}]");
    let signal = match log.kind.prefix() {
        "tau" => "torque τ",
        "i" => "motor current i",
        "p" => "axis power p",
        _ => "supply power p_total",
    };
    let name = &cmp.channels[c].name;
    let meas: Vec<f64> = (0..log.len()).map(|k| log.y[k * ch + c]).collect();
    let model: Vec<f64> = (0..log.len()).map(|k| pred[k * ch + c]).collect();
    let res: Vec<f64> = model.iter().zip(&meas).map(|(a, b)| a - b).collect();
    pg.h2(name);
    let f = svg::Frame::new(
        &format!("{name}: measured and modelled"),
        "time [s]",
        &y_label(signal),
    )
    .size(1000.0, 340.0);
    pg.figure(
        &format!("{name}-signal"),
        &svg::line_chart(
            &f,
            &[
                Series::new("measured", t, &meas),
                Series::new("model", t, &model),
            ],
        ),
        &format!("{name}: measured and modelled signal over time."),
    );
    let f = svg::Frame::new(
        &format!("{name}: residual (model − measured)"),
        "time [s]",
        &y_label("residual"),
    )
    .size(1000.0, 300.0);
    pg.figure(
        &format!("{name}-residual"),
        &svg::line_chart(&f, &[Series::new("residual", t, &res)]),
        &format!("{name}: residual over time."),
    );
    let joints: Vec<usize> = if ch == 1 { (0..n).collect() } else { vec![c] };
    for j in joints {
        pg.figure_row(&residual_scatter_row(log, name, j, &res, unit));
    }
}

/// Channel `name`'s residual `res` against joint `j`'s velocity, acceleration and position,
/// as a row of scatter plots.
fn residual_scatter_row(
    log: &Log,
    name: &str,
    j: usize,
    res: &[f64],
    unit: &str,
) -> Vec<(String, String, String)> {
    let y_label = |what: &str| format!("{what} [{unit}]");
    let mut row = Vec::new();
    for (lab, sym, unit_x, f) in [
        ("velocity", "q̇", "rad/s", JointTrajSel::Qd),
        ("acceleration", "q̈", "rad/s²", JointTrajSel::Qdd),
        ("position", "q", "rad", JointTrajSel::Q),
    ] {
        let rate = |r| {
            log.traj
                .column(j, r)
                .unwrap_or_else(|_| vec![f64::NAN; log.len()])
        };
        let x: Vec<f64> = match f {
            JointTrajSel::Q => (0..log.len()).map(|k| log.traj.q(k)[j]).collect(),
            JointTrajSel::Qd => rate(Rate::Velocity),
            JointTrajSel::Qdd => rate(Rate::Acceleration),
        };
        let fr = svg::Frame::new(
            &format!("{name} residual vs joint {} {lab}", j + 1),
            &format!("joint {} {lab} {sym} [{unit_x}]", j + 1),
            &y_label("residual"),
        )
        .size(345.0, 300.0);
        row.push((
            format!("{name}-residual-vs-q{}-{lab}", j + 1),
            svg::scatter(&fr, &[Series::new("", &x, res)]),
            format!("{name}: residual vs joint {} {lab}.", j + 1),
        ));
    }
    row
}

#[derive(Clone, Copy)]
enum JointTrajSel {
    Q,
    Qd,
    Qdd,
}
