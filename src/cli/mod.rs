//! The command-line front end: a thin layer of clap over library calls. Every command that
//! prints results also answers in JSON with `--json`.

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use printwatt::robot;
use std::path::{Path, PathBuf};

/// `println!` for results: the write's error is returned with `?` (a closed pipe or a full
/// disk ends the command through its error path, see [`StdoutFailed`]), never a panic.
macro_rules! outln {
    () => {
        $crate::cli::out_line(format_args!(""))?
    };
    ($($t:tt)*) => {
        $crate::cli::out_line(format_args!($($t)*))?
    };
}

/// `print!` for results, as [`outln!`].
macro_rules! out {
    ($($t:tt)*) => {
        $crate::cli::out_text(format_args!($($t)*))?
    };
}

pub mod args;
mod compare;
mod diagnose;
mod energy;
mod excite;
mod identify;
mod inspect;
mod merge;
mod optimise;
mod robot_init;
mod robots;
mod simulate;
mod stations;
mod study;
mod sweep;
mod view;

/// `printwatt --version`: the package version and the git commit it was built from (build.rs).
pub const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (commit ",
    env!("PRINTWATT_COMMIT"),
    ")"
);

/// printwatt: where to put a 3D concrete print so the robot arm spends the least energy.
#[derive(Parser, Debug)]
#[command(name = "printwatt", version = VERSION, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

/// An error and its causes on one line, `outer: inner: …`, without repeating a cause whose
/// text already ends the line (a library error that quotes its source, e.g. an I/O error
/// naming its file and what the system said, is not followed by the system's words again).
pub fn error_text(e: &anyhow::Error) -> String {
    let mut s = String::new();
    for c in e.chain() {
        let t = c.to_string();
        if s.is_empty() {
            s = t;
        } else if !s.ends_with(&t) {
            s.push_str(": ");
            s.push_str(&t);
        }
    }
    s
}

/// The commands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// List the shipped robots with reach, payload, joint count and provenance.
    Robots(RobotsArgs),
    /// Start a robot of your own: `robot init URDF` writes a drive-file template for its joints.
    Robot(robot_init::RobotCmd),
    /// Evaluate placements of a path (grid, named set or list) in parallel: energy or why not.
    Sweep(sweep::SweepArgs),
    /// Put the shards of a split run (`sweep --shard`, `optimise --uncertainty N --shard`, `study --shard`) together: the files of a single run.
    Merge(merge::MergeArgs),
    /// Find the minimum-energy placement (grid, then a seeded Nelder–Mead refinement or pattern search) and write a report.
    Optimise(optimise::OptimiseArgs),
    /// Design study: optimise every path of a study file on each of its robots and cells, and
    /// say which robot and cell prints each path, and all of them, for the least energy.
    Study(study::StudyArgs),
    /// Plan stations for a path larger than one placement's reach: where the arm stands, where
    /// the path is split, least energy plus a stated cost per relocation.
    Stations(stations::StationsArgs),
    /// Energy of a joint trajectory, or of a toolpath at one placement.
    Energy(energy::EnergyCmd),
    /// Compare the model with a measured log: RMSE, energy error, where the residual sits.
    Compare(CompareArgs),
    /// Rank the catalogue effects by how much of the residual each explains (held out).
    Diagnose(DiagnoseArgs),
    /// Fit effects' parameters, report the error ladder, write a calibrated robot file.
    Identify(IdentifyArgs),
    /// Write a simulated log from a "true" robot with hidden effects.
    Simulate(SimulateArgs),
    /// Design an excitation experiment for the parameters the placement decision depends on:
    /// a trajectory CSV, an ABB RAPID module and a URScript program.
    Excite(excite::ExciteArgs),
    /// A live 3-D view in the browser (local web server): move the part and watch the
    /// energy, the margins and the feasibility follow; play the arm; optimise and export.
    View(view::ViewArgs),
    /// How a toolpath was read: format, units, moves, print and travel length, bounding box,
    /// layers, commanded speeds, the reader's warnings.
    Inspect(inspect::InspectArgs),
}

/// Robot, log and model switches shared by compare/diagnose/identify.
#[derive(clap::Args, Debug, Clone)]
pub struct LogArgs {
    #[command(flatten)]
    pub robot: args::RobotArg,
    /// Measured log (CSV, docs/measurement-logs.md).
    #[arg(long, value_name = "FILE")]
    pub log: PathBuf,
    /// Column map for a log without header, e.g. "t, q1..q6[deg], i1..i6, skip*12".
    #[arg(long)]
    pub columns: Option<String>,
    /// Effects switched on (comma list of catalogue names); for `identify`: the effects to
    /// fit, in ladder order. `viscous[2]`: on joint 2 only, as in `simulate --hidden` (for
    /// `compare` and `diagnose` the effect's parameters of the other joints are zero; for
    /// `identify` they are held at their prior).
    #[arg(long)]
    pub effects: Option<String>,
    /// Effects switched off (comma list; `viscous[2]`: on joint 2 only).
    #[arg(long)]
    pub without: Option<String>,
}

/// `printwatt compare`
#[derive(clap::Args, Debug)]
pub struct CompareArgs {
    #[command(flatten)]
    pub log: LogArgs,
    /// --out: compare.json and report.html.
    #[command(flatten)]
    pub out: args::OutputArgs,
}

/// `printwatt diagnose`
#[derive(clap::Args, Debug)]
pub struct DiagnoseArgs {
    #[command(flatten)]
    pub log: LogArgs,
    /// Number of time-block folds, 2 to 100 (fewer are used, with a warning, when the
    /// residual's correlation time makes blocks that short dependent).
    #[arg(long, default_value_t = 5, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(2..=100))]
    pub folds: usize,
    /// --out: diagnose.json.
    #[command(flatten)]
    pub out: args::OutputArgs,
}

/// `printwatt identify`
#[derive(clap::Args, Debug)]
pub struct IdentifyArgs {
    #[command(flatten)]
    pub log: LogArgs,
    /// Validate on this log instead of the last quarter of --log.
    #[arg(long, value_name = "FILE")]
    pub validate_log: Option<PathBuf>,
    /// Where to write the calibrated robot (default: `<name>.calibrated.toml` in --out, or in
    /// the current directory; never in the installed robots folder).
    #[arg(long, value_name = "FILE")]
    pub drive_out: Option<PathBuf>,
    /// --out: the calibrated robot, ladder.md, ladder.svg and identify.json.
    #[command(flatten)]
    pub out: args::OutputArgs,
}

/// `printwatt simulate`
#[derive(clap::Args, Debug)]
pub struct SimulateArgs {
    /// The nominal robot (the "true" robot is it plus --hidden).
    #[command(flatten)]
    pub robot: args::RobotArg,
    #[command(flatten)]
    pub path: args::PathArg,
    #[command(flatten)]
    pub at: args::AtArg,
    #[command(flatten)]
    pub timing: args::TimingArgs,
    /// Joint trajectory CSV instead of a path.
    #[arg(long, value_name = "FILE")]
    pub trajectory: Option<PathBuf>,
    /// Synthetic exciting motion (sums of sines within limits) of this many seconds.
    #[arg(long, value_name = "SECONDS")]
    pub excite: Option<f64>,
    /// Hidden effects of the true robot, e.g. "coulomb=40,balancer=8000:20000,payload=+15".
    #[arg(long, allow_hyphen_values = true)]
    pub hidden: Option<String>,
    /// Signal to log: tau, i, p or p_total.
    #[arg(long, default_value = "tau")]
    pub signal: String,
    /// Signal noise standard deviation (signal unit; default 2 N·m, 0.02 A, 5 W, 20 W).
    #[arg(long)]
    pub noise: Option<f64>,
    /// Position noise standard deviation, rad.
    #[arg(long, default_value_t = 1e-6)]
    pub noise_q: f64,
    /// Current quantisation step, A (current logs).
    #[arg(long, default_value_t = 0.01)]
    pub quantum: f64,
    /// Sample rate, Hz.
    #[arg(long, default_value_t = 250.0)]
    pub rate: f64,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// --out: the log, `log.csv`.
    #[command(flatten)]
    pub out: args::OutputArgs,
}

/// `printwatt robots`
#[derive(clap::Args, Debug)]
pub struct RobotsArgs {
    /// Directory holding one sub-directory per robot.
    #[arg(long, default_value_os_t = default_robots_dir())]
    pub dir: PathBuf,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// The shipped robots directory: `$PRINTWATT_ROBOTS`, else `robots/` in the working
/// directory, else the one in the source tree this binary was built from.
pub fn default_robots_dir() -> PathBuf {
    robot::shipped::robots_dir()
}

/// Resolve a `--robot` argument: a path, or the name of a shipped robot (the argument itself
/// when it is neither, so that the error names what was typed).
pub fn resolve_robot(arg: &Path) -> PathBuf {
    robot::shipped::resolve(arg).unwrap_or_else(|| arg.to_path_buf())
}

/// Load a robot named on the command line, with context for the error message. Its warnings
/// are shown (see [`note_warnings`]).
pub fn load_robot(arg: &Path) -> Result<robot::RobotModel> {
    let p = resolve_robot(arg);
    if !p.exists() {
        anyhow::bail!(
            "robot `{}`: no such file or directory, and no shipped robot of that name; {}",
            arg.display(),
            args::robot_suggestion(arg)
        );
    }
    let m = robot::load(&p).with_context(|| format!("loading robot {}", arg.display()))?;
    note_warnings(&m.source.display().to_string(), &m.warnings);
    Ok(m)
}

/// Load a toolpath named on the command line; its warnings are shown.
pub fn load_path(
    p: &Path,
    opts: &printwatt::toolpath::ReadOptions,
) -> Result<printwatt::toolpath::Toolpath> {
    let tp = printwatt::toolpath::load(p, opts)
        .map_err(proc_hint)
        .with_context(|| format!("loading path {}", p.display()))?;
    note_warnings(&tp.source, &tp.warnings);
    Ok(tp)
}

/// A reader error with the command line's hint added where the RAPID reader asks for the entry
/// procedure to be named.
pub fn proc_hint(e: printwatt::error::Error) -> anyhow::Error {
    let msg = e.to_string();
    if msg.contains("name the procedure to read as the entry") {
        anyhow::anyhow!("{msg}\nhint: choose it with --proc NAME")
    } else {
        anyhow::Error::new(e)
    }
}

/// The inputs of a command for the output policy: the robot (every file of its directory, its
/// URDF and drive file) and the other files named.
pub fn inputs(
    robot_arg: &Path,
    model: Option<&robot::RobotModel>,
    files: &[Option<&Path>],
) -> printwatt::output::Inputs {
    let mut i = printwatt::output::Inputs::new();
    i.add_robot(&resolve_robot(robot_arg), model);
    for f in files.iter().flatten() {
        i.add(f);
    }
    i
}

/// A warning shown to the user: on stderr when it is noted, and in every `--json` output under
/// `warnings`.
#[derive(Clone, Debug, serde::Serialize, PartialEq)]
pub struct Warning {
    /// The input file it concerns.
    pub file: String,
    /// 1-based line, where the reader knows it.
    pub line: Option<usize>,
    /// The message (without the file and line).
    pub message: String,
}

static WARNINGS: std::sync::Mutex<Vec<Warning>> = std::sync::Mutex::new(Vec::new());

/// Split a reader's warning `file:line: message` (or `file: message`, or a bare message) into a
/// [`Warning`] for `file`.
pub fn parse_warning(file: &str, w: &str) -> Warning {
    let rest = w
        .strip_prefix(file)
        .and_then(|r| r.strip_prefix(':'))
        .map(str::trim_start);
    let (line, message) = match rest {
        Some(r) => {
            let digits: String = r.chars().take_while(|c| c.is_ascii_digit()).collect();
            match (digits.parse::<usize>(), r[digits.len()..].strip_prefix(':')) {
                (Ok(l), Some(m)) => {
                    // `file:line:column: msg` too.
                    let m = m.trim_start();
                    let d2: String = m.chars().take_while(|c| c.is_ascii_digit()).collect();
                    let m = match m[d2.len()..].strip_prefix(':') {
                        Some(mm) if !d2.is_empty() => mm.trim_start(),
                        _ => m,
                    };
                    (Some(l), m.to_string())
                }
                _ => (None, r.to_string()),
            }
        }
        None => (None, w.to_string()),
    };
    Warning {
        file: file.to_string(),
        line,
        message,
    }
}

/// Show a reader's warnings: each goes to stderr now (`warning: file:line: message`) and is
/// kept for the `warnings` of a `--json` output. A warning already noted in this run (the same
/// file read again, e.g. by each case of a study) is not repeated.
pub fn note_warnings(file: &str, ws: &[String]) {
    for w in ws {
        let w = parse_warning(file, w);
        if let Ok(mut g) = WARNINGS.lock() {
            if g.contains(&w) {
                continue;
            }
            g.push(w.clone());
        }
        match w.line {
            Some(l) => eprintln!(
                "warning: {}:{l}: {}",
                w.file,
                printwatt::error::clip(&w.message)
            ),
            None => eprintln!(
                "warning: {}: {}",
                w.file,
                printwatt::error::clip(&w.message)
            ),
        }
    }
}

/// The warnings noted so far.
pub fn warnings() -> Vec<Warning> {
    WARNINGS.lock().map(|g| g.clone()).unwrap_or_default()
}

/// Writing a result to standard output failed: the reader closed the pipe (`| head`), or the
/// disk it goes to is full (`> /dev/full`). The command stops through its error path (run
/// directories not committed are removed); `main` ends quietly with the conventional status of
/// a closed pipe (141), or with one line naming what the system said.
#[derive(Debug)]
pub struct StdoutFailed(pub std::io::Error);

impl std::fmt::Display for StdoutFailed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "writing to standard output: {}", self.0)
    }
}

impl std::error::Error for StdoutFailed {}

impl StdoutFailed {
    /// The reader went away (a closed pipe): nothing to tell anyone.
    pub fn closed_pipe(&self) -> bool {
        self.0.kind() == std::io::ErrorKind::BrokenPipe
    }
}

/// Write `args` and a newline to standard output; its error as [`StdoutFailed`].
pub fn out_line(args: std::fmt::Arguments) -> Result<()> {
    use std::io::Write;
    let mut o = std::io::stdout().lock();
    o.write_fmt(args)
        .and_then(|()| o.write_all(b"\n"))
        .map_err(|e| StdoutFailed(e).into())
}

/// Write `args` to standard output (no newline); its error as [`StdoutFailed`].
pub fn out_text(args: std::fmt::Arguments) -> Result<()> {
    use std::io::Write;
    std::io::stdout()
        .lock()
        .write_fmt(args)
        .map_err(|e| StdoutFailed(e).into())
}

/// Flush standard output at the end of a command (text written without a final newline is
/// still buffered); its error as [`StdoutFailed`].
pub fn flush_stdout() -> Result<()> {
    use std::io::Write;
    std::io::stdout()
        .flush()
        .map_err(|e| StdoutFailed(e).into())
}

/// Print a `--json` answer: numbers rounded and `schema_version` added
/// ([`printwatt::output::finish_json`]), the warnings noted so far added as `warnings` (an
/// object's key; other values are wrapped as `{"schema_version": …, "result": …, "warnings":
/// […]}`).
pub fn print_json<T: serde::Serialize>(v: &T) -> Result<()> {
    // Before serde_json sees it: serde_json writes NaN and infinities as `null`.
    printwatt::output::check_finite_json("JSON output", v)?;
    let mut v = serde_json::to_value(v)?;
    printwatt::output::finish_json(&mut v);
    add_warnings(&mut v);
    outln!("{}", serde_json::to_string_pretty(&v)?);
    Ok(())
}

/// [`print_json`] for JSON text already formatted.
pub fn print_json_text(text: &str) -> Result<()> {
    let v: serde_json::Value = serde_json::from_str(text)?;
    print_json(&v)
}

/// Print a run report's `summary.json` as the `--json` answer (with the warnings noted so far):
/// the text [`print_json_text`] gives for it, written straight from the report without a JSON
/// value tree of its rows.
pub fn print_report_json(
    rep: &printwatt::report::placement::RunReport,
    with_rows: bool,
) -> Result<()> {
    let ws = serde_json::to_value(warnings()).unwrap_or_default();
    let text = rep.summary_json_with(with_rows, &[("warnings", ws)])?;
    outln!("{text}");
    Ok(())
}

fn add_warnings(v: &mut serde_json::Value) {
    let ws = serde_json::to_value(warnings()).unwrap_or_default();
    match v {
        serde_json::Value::Object(o) => {
            o.insert("warnings".into(), ws);
        }
        other => {
            let inner = std::mem::take(other);
            *other = serde_json::json!({
                "schema_version": printwatt::output::JSON_SCHEMA_VERSION,
                "result": inner,
                "warnings": ws
            });
        }
    }
}

/// A command-line number: finite, else an error naming the option.
pub fn finite(opt: &str, v: f64) -> Result<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        anyhow::bail!("{opt} {v}: expected a finite number")
    }
}

/// Run the parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Robots(a) => robots::run(a),
        Command::Robot(a) => robot_init::run(a),
        Command::Energy(a) => energy::run(a),
        Command::Sweep(a) => sweep::run(a),
        Command::Merge(a) => merge::run(a),
        Command::Study(a) => study::run(a),
        Command::Optimise(a) => optimise::run(a),
        Command::Stations(a) => stations::run(a),
        Command::Compare(a) => compare::run(a),
        Command::Diagnose(a) => diagnose::run(a),
        Command::Identify(a) => identify::run(a),
        Command::Simulate(a) => simulate::run(a),
        Command::Excite(a) => excite::run(a),
        Command::View(a) => view::run(a),
        Command::Inspect(a) => inspect::run(a),
    }
}
