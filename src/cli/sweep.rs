//! `printwatt sweep`: evaluate a grid, a named set or a list of placements in parallel.

use anyhow::{bail, Context, Result};
use printwatt::energy::EnergyOptions;
use printwatt::evaluate::evaluator::{Evaluated, Evaluator, Objective};
use printwatt::evaluate::feasibility::FeasibilityOptions;
use printwatt::evaluate::PathJob;
use printwatt::report::placement::RunReport;
use printwatt::search::optimise::{best_of, worst_of};
use printwatt::search::{parse_range, Grid};
use printwatt::timing::{JointStageOptions, ProfileOptions};
use printwatt::toolpath::{self, Placement};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

/// Options shared by `sweep` and `optimise`: robot, path, where to place it, feasibility.
#[derive(clap::Args, Debug, Clone)]
pub struct PlacementArgs {
    #[command(flatten)]
    pub robot: super::args::RobotArg,
    #[command(flatten)]
    pub path: super::args::PathArg,
    /// Grid x of the part origin, m: `min:max:step`, a value, or a comma list (default: a
    /// 16-cell grid over the robot's reach).
    #[arg(long, allow_hyphen_values = true)]
    pub x: Option<String>,
    /// Grid y of the part origin, m: `min:max:step`, a value, or a comma list (default: as
    /// --x).
    #[arg(long, allow_hyphen_values = true)]
    pub y: Option<String>,
    /// z of the part origin (nozzle tip height on the bed), m: value, list or range
    /// (default 0 for a given grid; with --set, one value replacing the set's heights).
    #[arg(long, allow_hyphen_values = true)]
    pub z: Option<String>,
    /// Part yaws about the vertical, deg: a value, a comma list or `min:max:step` [default: 0].
    #[arg(long, allow_hyphen_values = true)]
    pub yaw: Option<String>,
    /// Named placements CSV (e.g. `paths/placements/p1-p5.csv`).
    #[arg(long, value_name = "FILE")]
    pub set: Option<PathBuf>,
    #[command(flatten)]
    pub at: super::args::AtArg,
    #[command(flatten)]
    pub timing: super::args::TimingArgs,
    #[command(flatten)]
    pub energy: super::args::EnergyArgs,
    #[command(flatten)]
    pub evaluation: super::args::EvaluationArgs,
    /// Energy to minimise: `supply` (standby + drives), `drives` (standby excluded),
    /// `mechanical` (signed Σ∫τq̇), `mechanical_positive` (Σ∫max(τq̇, 0): no regeneration),
    /// `mechanical_abs` (Σ∫|τq̇|: braking costed like driving).
    #[arg(long, default_value = "supply")]
    pub objective: String,
    #[command(flatten)]
    pub feasibility: super::args::FeasibilityArgs,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Shorthand for `--out <results-dir>/<RUN>`: the run directory (summary.json,
    /// placements.csv, report.html). An existing run is never replaced without --force.
    #[arg(long, value_name = "RUN", conflicts_with = "out")]
    pub run: Option<String>,
    /// Parent directory of --run and of optimise's default run directories.
    #[arg(long, value_name = "DIR", default_value = "results")]
    pub results_dir: PathBuf,
    /// --out: the run directory (summary.json, placements.csv, report.html).
    #[command(flatten)]
    pub out: super::args::OutputArgs,
}

/// `printwatt sweep` arguments.
#[derive(clap::Args, Debug)]
pub struct SweepArgs {
    /// Robot, path, placements and feasibility options.
    #[command(flatten)]
    pub p: PlacementArgs,
    /// Evaluate one shard of the placements for a cluster run: `K/N` (shard K, 0-based, of N;
    /// shard K owns placements K, K+N, K+2N, …), `auto` (index and count from a Slurm job
    /// array), `auto/N` (index from Slurm or a Kubernetes Indexed Job's JOB_COMPLETION_INDEX).
    /// Writes `<--out>/shard-K-of-N/`; `printwatt merge` puts the shards together into the
    /// files a single run writes, bit for bit (docs/cluster.md).
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
}

/// A file shipped in the source tree: relative to the working directory if it exists there,
/// else to the crate's source directory.
pub fn shipped(rel: &str) -> PathBuf {
    let local = Path::new(rel);
    if local.exists() {
        local.to_path_buf()
    } else {
        Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
    }
}

/// Everything loaded for a placement command.
pub struct Loaded {
    /// The robot.
    pub robot: printwatt::robot::RobotModel,
    /// The toolpath (part frame, m).
    pub path: toolpath::Toolpath,
    /// Where the toolpath came from.
    pub path_file: PathBuf,
    /// What is minimised (J).
    pub objective: Objective,
    /// Feasibility thresholds.
    pub feas: FeasibilityOptions,
    /// Energy model options (--regeneration, --no-payload, --no-friction).
    pub energy: EnergyOptions,
    /// Controller timing (--period, --accel, --jerk).
    pub profile: ProfileOptions,
}

impl Loaded {
    /// The job (energy model, blended and planned path) with the command line's energy and
    /// timing options.
    pub fn job(&self) -> Result<PathJob<'_>> {
        Ok(PathJob::new(
            &self.robot,
            &self.path,
            self.energy,
            self.profile,
            JointStageOptions::default(),
        )?)
    }

    /// The placement objective over `job` (built by [`Loaded::job`]) with the path reduction
    /// that `--evaluation` asks for (none for a path that is short or does not repeat).
    pub fn evaluator<'j, 'a>(
        &'a self,
        job: &'j PathJob<'a>,
        evaluation: &super::args::EvaluationArgs,
    ) -> Result<Evaluator<'j, 'a>> {
        Ok(printwatt::search::run::evaluator(
            job,
            &self.path,
            self.feas,
            self.objective,
            evaluation.evaluation.parse()?,
        ))
    }

    /// The workspace grid used when the command line names no placements.
    pub fn default_grid(&self) -> Grid {
        printwatt::search::optimise::default_grid(printwatt::evaluate::feasibility::reach_m(
            &self.robot,
        ))
    }
}

impl PlacementArgs {
    /// Load the robot and path and turn the options into library options.
    pub fn load(&self) -> Result<Loaded> {
        let robot = self.robot.load()?;
        let path_file = self.path.file();
        let path = super::load_path(&path_file, &self.path.read_options(&self.timing)?)?;
        let objective: Objective = self.objective.parse()?;
        let feas = self.feasibility.options(robot.dof())?;
        Ok(Loaded {
            robot,
            path,
            path_file,
            objective,
            feas,
            energy: self.energy.options()?,
            profile: self.timing.profile()?,
        })
    }

    /// The placements asked for: `(placements, names, grid)`. `default_grid` is used when no
    /// grid, set or list is given (None: error).
    pub fn placements(&self, default_grid: Option<Grid>) -> Result<Asked> {
        let asked = self.placements_unchecked(default_grid)?;
        if let Some(p) = asked
            .0
            .iter()
            .find(|p| super::args::check_metres(p).is_err())
        {
            super::args::check_metres(p).context("placement")?;
        }
        Ok(asked)
    }

    fn placements_unchecked(&self, default_grid: Option<Grid>) -> Result<Asked> {
        let deg = |what: &str, s: &str| -> Result<Vec<f64>> {
            Ok(parse_range(what, s)?
                .into_iter()
                .map(f64::to_radians)
                .collect())
        };
        if let Some(set) = &self.set {
            let named = toolpath::load_placements(set)
                .with_context(|| format!("loading placements {}", set.display()))?;
            let names = named.iter().map(|n| n.name.clone()).collect();
            let mut ps: Vec<Placement> = named.iter().map(|n| n.placement).collect();
            // A single --z replaces the set's heights (the bed height is often unknown).
            if let Some(z) = &self.z {
                let zs = parse_range("z", z)?;
                if zs.len() != 1 {
                    bail!("with --set, --z takes a single height (m)");
                }
                for p in &mut ps {
                    p.z = zs[0];
                }
            }
            let (ps, names) = self.with_spins(ps, names)?;
            return Ok((ps, Some(names), None));
        }
        if let Some(at) = &self.at.at {
            let mut v = Vec::new();
            for (i, item) in at.split(';').filter(|s| !s.trim().is_empty()).enumerate() {
                v.push(parse_placement(item).with_context(|| format!("--at item {}", i + 1))?);
            }
            if v.is_empty() {
                bail!("--at `{at}`: no placements");
            }
            if self.at.spin.is_some() {
                let names = (1..=v.len()).map(|i| i.to_string()).collect();
                let (v, names) = self.with_spins(v, names)?;
                return Ok((v, Some(names), None));
            }
            return Ok((v, None, None));
        }
        let mut g = match (&self.x, &self.y) {
            (Some(x), Some(y)) => Grid {
                xs: parse_range("x", x)?,
                ys: parse_range("y", y)?,
                zs: parse_range("z", self.z.as_deref().unwrap_or("0"))?,
                yaws: deg("yaw", self.yaw.as_deref().unwrap_or("0"))?,
                spins: deg("spin", self.at.spin.as_deref().unwrap_or("0"))?,
            },
            (None, None) => match default_grid {
                Some(g) => g,
                None => bail!("give a grid (--x and --y), a named set (--set) or a list (--at)"),
            },
            _ => bail!("--x and --y go together"),
        };
        if self.x.is_none() {
            // Default grid: the user's z, yaw and spin lists still apply when given.
            if let Some(z) = &self.z {
                g.zs = parse_range("z", z)?;
            }
            if let Some(y) = &self.yaw {
                g.yaws = deg("yaw", y)?;
            }
            if let Some(s) = &self.at.spin {
                g.spins = deg("spin", s)?;
            }
        }
        if g.len() > 1_000_000 {
            bail!("{} placements: more than 1,000,000", g.len());
        }
        Ok((g.placements(), None, Some(g)))
    }

    /// The inputs of the command (robot files, path, set) for the output policy.
    pub fn inputs(&self, l: &Loaded) -> printwatt::output::Inputs {
        super::inputs(
            &self.robot.robot,
            Some(&l.robot),
            &[
                Some(l.path_file.as_path()),
                self.set.as_deref(),
                self.robot.tool.as_deref(),
            ],
        )
    }

    /// Take the run directory `--results-dir/<run>` before any work (locked for this run,
    /// checked against the inputs and for files printwatt did not write).
    pub fn begin_run(
        &self,
        l: &Loaded,
        run: Option<&str>,
    ) -> Result<Option<printwatt::output::RunDir>> {
        match run {
            None => Ok(None),
            Some(r) => Ok(Some(printwatt::output::RunDir::begin(
                &self.results_dir,
                r,
                &self.inputs(l),
                printwatt::output::Existing::Force(self.out.force),
            )?)),
        }
    }

    /// Every placement of a set or list at every `--spin` (deg), added to the placement's own
    /// spin; names get `@<spin>°` when more than one spin is asked for. Without `--spin` the
    /// placements are returned as given.
    fn with_spins(
        &self,
        ps: Vec<Placement>,
        names: Vec<String>,
    ) -> Result<(Vec<Placement>, Vec<String>)> {
        let Some(sp) = &self.at.spin else {
            return Ok((ps, names));
        };
        let spins = parse_range("spin", sp)?;
        let mut out = Vec::with_capacity(ps.len() * spins.len());
        let mut out_names = Vec::with_capacity(ps.len() * spins.len());
        for (p, n) in ps.iter().zip(&names) {
            for s in &spins {
                out.push(Placement {
                    nozzle_spin: p.nozzle_spin + s.to_radians(),
                    ..*p
                });
                out_names.push(if spins.len() > 1 {
                    format!("{n}@{s}°")
                } else {
                    n.clone()
                });
            }
        }
        Ok((out, out_names))
    }

    /// A rayon pool with `--threads` (or the global default).
    pub fn pool(&self) -> Result<rayon::ThreadPool> {
        let mut b = rayon::ThreadPoolBuilder::new();
        if let Some(n) = self.threads {
            if n == 0 {
                bail!("--threads must be at least 1");
            }
            b = b.num_threads(n);
        }
        Ok(b.build()?)
    }
}

/// A file-name-safe token: ASCII letters, digits, `-`, `_` and `.`; anything else becomes `_`.
fn safe_token(s: &str) -> String {
    let t: String = s
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' || c == '.' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let t = t.trim_matches('_').to_string();
    if t.is_empty() {
        "x".into()
    } else {
        t
    }
}

/// The default run name: `<command>-<robot dir or file stem>-<path stem>-<UTC time>`.
pub fn default_run_name(command: &str, robot: &Path, path: &Path, unix_s: u64) -> String {
    let stem = |p: &Path| {
        p.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let r = if robot
        .file_name()
        .is_some_and(|f| f == "drive.toml" || f == "robot.urdf")
    {
        robot.parent().map(stem).unwrap_or_default()
    } else {
        stem(robot)
    };
    format!(
        "{command}-{}-{}-{}",
        safe_token(&r),
        safe_token(&stem(path)),
        printwatt::output::utc_stamp(unix_s)
    )
}

impl PlacementArgs {
    /// Where this run writes: `--run` under `--results-dir` (an existing, non-empty directory
    /// needs `--force`), else, when `default_for` names the command, a fresh
    /// `runs/<command>-<robot>-<path>-<UTC time>` (suffixed `-2`, `-3`, … if taken). `None`:
    /// no run directory.
    /// The directory is taken through the output policy ([`printwatt::output::RunDir`]): locked
    /// for this run, checked against the inputs, refused if it holds files printwatt did not
    /// write (even with --force), written whole at the end.
    pub fn run_dir(
        &self,
        l: &Loaded,
        default_for: Option<&str>,
    ) -> Result<Option<printwatt::output::RunDir>> {
        if self.run.is_some() {
            return self.begin_run(l, self.run.as_deref());
        }
        if let Some(dir) = &self.out.out {
            return Ok(Some(printwatt::output::RunDir::begin_at(
                dir,
                &self.inputs(l),
                printwatt::output::Existing::Force(self.out.force),
            )?));
        }
        let Some(cmd) = default_for else {
            return Ok(None);
        };
        let dir = fresh_run_dir(&self.results_dir, |now| {
            default_run_name(cmd, &self.robot.robot, &l.path_file, now)
        });
        Ok(Some(printwatt::output::RunDir::begin_at(
            &dir,
            &self.inputs(l),
            printwatt::output::Existing::Force(false),
        )?))
    }
}

/// Placements asked for on the command line: the placements, their names (named sets) and the
/// grid they form (grids).
pub type Asked = (Vec<Placement>, Option<Vec<String>>, Option<Grid>);

/// Parse `x,y,z,yaw[,spin]` (m, m, m, deg, deg) into a placement ([`Placement::parse`]).
pub fn parse_placement(s: &str) -> Result<Placement> {
    Placement::parse(s).with_context(|| format!("`{s}`"))
}

/// Run a sweep with a progress bar on a terminal.
pub fn run_sweep(
    ev: &Evaluator,
    ps: &[Placement],
    pool: &rayon::ThreadPool,
) -> Result<Vec<Evaluated>> {
    let bar = if std::io::stderr().is_terminal() && ps.len() > 1 {
        let b = indicatif::ProgressBar::new(ps.len() as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} placements ({per_sec}, eta {eta})",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        Some(b)
    } else {
        None
    };
    let cb = |done: usize, _total: usize| {
        if let Some(b) = &bar {
            b.set_position(done as u64);
        }
    };
    let r = pool.install(|| ev.sweep(ps, &cb))?;
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    Ok(r)
}

pub use printwatt::search::run::{detail, evaluation_line};

/// Facts about the job shown in reports and `summary.json` ([`printwatt::search::run::meta`]).
pub fn meta(l: &Loaded, samples: usize) -> Vec<(String, String)> {
    printwatt::search::run::meta(&l.robot, &l.path_file, l.objective, &l.feas, samples)
}

/// How a run was executed, for `run.json` (changes from run to run; no result depends on it):
/// A run directory not taken yet: `<results_dir>/runs/<name(now)>` (`now`: Unix time, s),
/// suffixed `-2`, `-3`, … when taken.
pub fn fresh_run_dir(results_dir: &Path, name: impl FnOnce(u64) -> String) -> PathBuf {
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0);
    let base = name(now);
    let parent = results_dir.join("runs");
    let mut dir = parent.join(&base);
    let mut k = 2;
    while dir.exists() {
        dir = parent.join(format!("{base}-{k}"));
        k += 1;
    }
    dir
}

/// printwatt build, command line, worker threads, wall time (s) and evaluations.
pub fn run_facts(threads: usize, secs: f64, evaluations: usize) -> serde_json::Value {
    serde_json::json!({
        "schema_version": 1,
        "printwatt": super::VERSION,
        "command": std::env::args().collect::<Vec<_>>().join(" "),
        "threads": threads,
        "wall_time_s": secs,
        "evaluations": evaluations,
        "evaluations_per_s": evaluations as f64 / secs.max(1e-9),
    })
}

/// Write `run.json` ([`run_facts`] and `extra` fields) into a run directory being written.
pub fn write_run_facts(
    rd: &mut printwatt::output::RunDir,
    mut facts: serde_json::Value,
    extra: &[(&str, serde_json::Value)],
) -> Result<()> {
    if let Some(o) = facts.as_object_mut() {
        for (k, v) in extra {
            o.insert((*k).to_string(), v.clone());
        }
    }
    rd.write("run.json", printwatt::output::json_text(&facts)?.as_bytes())?;
    Ok(())
}

/// Print a one-line-per-placement table.
pub fn print_rows(rows: &[Evaluated], names: Option<&[String]>) -> Result<()> {
    outln!(
        "{:>8} {:>8} {:>8} {:>8} {:>7} {:>7}  {:>12} {:>9}  note",
        "name",
        "x[m]",
        "y[m]",
        "z[m]",
        "yaw[°]",
        "spin[°]",
        "energy[J]",
        "time[s]"
    );
    for (i, r) in rows.iter().enumerate() {
        let p = &r.placement;
        let name = names
            .and_then(|n| n.get(i).cloned())
            .unwrap_or_else(|| i.to_string());
        let (e, t, note) = match &r.outcome {
            Ok(f) => (
                format!("{:.1}", f.energy_j),
                format!("{:.2}", f.duration_s),
                String::new(),
            ),
            Err(x) => ("-".into(), "-".into(), x.to_string()),
        };
        outln!(
            "{name:>8} {:>8.3} {:>8.3} {:>8.3} {:>7.1} {:>7.1}  {e:>12} {t:>9}  {note}",
            p.x,
            p.y,
            p.z,
            p.yaw.to_degrees(),
            p.nozzle_spin.to_degrees()
        );
    }
    Ok(())
}

/// `printwatt sweep`.
pub fn run(a: SweepArgs) -> Result<()> {
    if let Some(spec) = &a.shard {
        return run_shard(&a.p, spec);
    }
    let a = a.p;
    let l = a.load()?;
    let run_dir = a.run_dir(&l, None)?;
    let job = l.job()?;
    let ev = l.evaluator(&job, &a.evaluation)?;
    let (ps, names, grid) = a.placements(Some(l.default_grid()))?;
    let pool = a.pool()?;
    let t0 = std::time::Instant::now();
    let rows = run_sweep(&ev, &ps, &pool)?;
    let secs = t0.elapsed().as_secs_f64();
    let facts = run_facts(pool.current_num_threads(), secs, ps.len());
    finish(
        &a,
        &l,
        &job,
        &ev,
        Swept { rows, names, grid },
        run_dir,
        (facts, Vec::new()),
    )
}

/// A sweep's rows with their names and grid (as [`PlacementArgs::placements`] gave them).
pub struct Swept {
    /// Every placement's evaluation, in sweep order.
    pub rows: Vec<Evaluated>,
    /// Names of the placements (sets, lists with spins).
    pub names: Option<Vec<String>>,
    /// The grid they form, when they do.
    pub grid: Option<Grid>,
}

/// Everything after the evaluations (shared by `sweep` and `merge`): detailed best and worst
/// placements, the report files and `run.json` into `run_dir`, and the terminal or JSON
/// answer.
pub fn finish(
    a: &PlacementArgs,
    l: &Loaded,
    job: &PathJob,
    ev: &Evaluator,
    swept: Swept,
    mut run_dir: Option<printwatt::output::RunDir>,
    facts: (serde_json::Value, Vec<(&str, serde_json::Value)>),
) -> Result<()> {
    let Swept { rows, names, grid } = swept;
    let mut details = Vec::new();
    if run_dir.is_some() {
        if let Some(b) = best_of(&rows) {
            details.extend(detail(job, "best", b)?);
        }
        if let Some(w) = worst_of(&rows) {
            details.extend(detail(job, "worst", w)?);
        }
    }
    let site = printwatt::report::site::SiteGeometry::new(
        &l.robot,
        job,
        best_of(&rows).map_or(0.0, |b| b.placement.z),
        &l.path_file,
        names.as_deref(),
    );
    let rep = RunReport {
        title: format!(
            "printwatt sweep: {} on {}",
            l.path_file.display(),
            l.robot.name()
        ),
        meta: meta(l, ev.nominal_samples())
            .into_iter()
            .chain(evaluation_line(ev))
            .collect(),
        rows,
        names,
        grid,
        optimise: None,
        baseline: None,
        site: Some(site),
        details,
        electrical: l.robot.drive.is_some(),
    };
    if let Some(mut rd) = run_dir.take() {
        rep.write_into(&mut rd)?;
        write_run_facts(&mut rd, facts.0, &facts.1)?;
        let dir = rd.commit()?;
        if !a.out.json {
            eprintln!("wrote {}", dir.display());
        }
    } else {
        rep.check_finite()?;
    }
    if a.out.json {
        super::print_report_json(&rep, true)?;
    } else {
        print_answer(&rep, l)?;
    }
    Ok(())
}

/// Print a sweep's answer: the rows, the best placement (or why none is feasible), the spread
/// and the reduction.
fn print_answer(rep: &RunReport, l: &Loaded) -> Result<()> {
    print_rows(&rep.rows, rep.names.as_deref())?;
    if let Some(b) = rep.best() {
        let p = &b.placement;
        outln!(
            "best: x = {:.3} m, y = {:.3} m, z = {:.3} m, yaw = {:.1}°, spin = {:.1}°: {:.1} J",
            p.x,
            p.y,
            p.z,
            p.yaw.to_degrees(),
            p.nozzle_spin.to_degrees(),
            b.cost()
        );
    }
    if rep.best().is_none() {
        out!(
            "{}",
            printwatt::search::advice::nothing_feasible_named(&rep.rows, &l.robot, &knob_flag)
        );
    }
    if let Some(s) = rep.spread_pct() {
        outln!("spread (max-min)/min: {s:.2} %");
    }
    if let Some(s) = rep.reduction_pct() {
        outln!("reduction (max-min)/max: {s:.2} %");
    }
    Ok(())
}

/// The command-line option for a setting the library's advice names.
pub fn knob_flag(k: printwatt::search::advice::Knob) -> String {
    use printwatt::search::advice::Knob;
    match k {
        Knob::X => "--x",
        Knob::Y => "--y",
        Knob::Z => "--z",
        Knob::Yaw => "--yaw",
        Knob::Spin => "--spin",
        Knob::JointMargin => "--joint-margin",
        Knob::WristRateMax => "--wrist-rate-max",
        Knob::WristMargin => "--wrist-margin",
        Knob::ElbowMin => "--elbow-min",
        Knob::ShoulderMin => "--shoulder-min",
        _ => k.words(),
    }
    .to_string()
}

/// The job of a sweep in a normalised form: every option that changes a result, none of those
/// that only say where the output goes or how many threads run (shards of one run agree on it).
pub fn job_key(a: &PlacementArgs) -> String {
    let mut n = a.clone();
    n.out = super::args::OutputArgs {
        out: None,
        json: false,
        force: false,
    };
    n.run = None;
    n.results_dir = PathBuf::new();
    n.threads = None;
    format!("{n:?}")
}

/// SHA-256 (hex) of every input file of the job, keyed by the path as the run names it.
pub fn hash_inputs(
    inputs: &printwatt::output::Inputs,
) -> Result<std::collections::BTreeMap<String, String>> {
    let mut m = std::collections::BTreeMap::new();
    for p in inputs.paths() {
        if p.is_file() {
            let bytes = std::fs::read(p).with_context(|| format!("reading {}", p.display()))?;
            m.insert(
                p.display().to_string(),
                printwatt::output::sha256_hex(&bytes),
            );
        }
    }
    Ok(m)
}

/// `printwatt sweep --shard`: evaluate this shard's placements and write them as the shard
/// directory `<--out>/shard-K-of-N/` (header and rows, docs/cluster.md).
fn run_shard(a: &PlacementArgs, spec: &str) -> Result<()> {
    use printwatt::campaign::shard::{self, Shard};
    let (sh, source) = Shard::parse(spec, &|k| std::env::var(k).ok())?;
    let Some(parent) = a.out.out.clone() else {
        bail!("--shard writes a shard directory: give --out DIR (every shard of the run writes DIR/shard-K-of-N/, and `printwatt merge DIR` puts them together)");
    };
    if a.run.is_some() {
        bail!("--shard writes into --out DIR/shard-K-of-N/, not into a --run directory");
    }
    let l = a.load()?;
    let inputs = a.inputs(&l);
    let rd = printwatt::output::RunDir::begin_at(
        &parent.join(sh.dir_name()),
        &inputs,
        printwatt::output::Existing::Force(a.out.force),
    )?;
    let job = l.job()?;
    let ev = l.evaluator(&job, &a.evaluation)?;
    let (ps, _, _) = a.placements(Some(l.default_grid()))?;
    let idx = sh.indices(ps.len());
    let mine: Vec<Placement> = idx.iter().map(|&i| ps[i]).collect();
    let pool = a.pool()?;
    let t0 = std::time::Instant::now();
    let rows = run_sweep(&ev, &mine, &pool)?;
    let secs = t0.elapsed().as_secs_f64();
    let feasible = rows.iter().filter(|r| r.cost().is_finite()).count();
    let rows: Vec<(usize, Evaluated)> = idx.into_iter().zip(rows).collect();
    let bytes = shard::encode_rows(&rows)?;
    let done = format!(
        "{} of {} placements evaluated ({feasible} feasible) in {secs:.2} s",
        rows.len(),
        ps.len()
    );
    write_shard(
        rd,
        ShardOut {
            kind: shard::KIND_SWEEP,
            shard: sh,
            source,
            total: ps.len(),
            rows: rows.len(),
            job: job_key(a),
            inputs: hash_inputs(&inputs)?,
            bytes,
            wall_time_s: secs,
        },
        a.out.json,
        &done,
    )
}

/// A shard's rows and what its header says of them ([`write_shard`]).
pub struct ShardOut {
    /// [`printwatt::campaign::shard::KIND_SWEEP`] or `KIND_UNCERTAINTY`.
    pub kind: &'static str,
    /// This shard.
    pub shard: printwatt::campaign::shard::Shard,
    /// Where its index came from (for the message).
    pub source: printwatt::campaign::shard::ShardSource,
    /// Items of the whole run.
    pub total: usize,
    /// Items in this shard.
    pub rows: usize,
    /// The normalised job ([`job_key`], or optimise's).
    pub job: String,
    /// SHA-256 of every input ([`hash_inputs`]).
    pub inputs: std::collections::BTreeMap<String, String>,
    /// The encoded rows.
    pub bytes: Vec<u8>,
    /// Wall time of the shard's work, s.
    pub wall_time_s: f64,
}

/// Write a shard directory (rows and header) into the run directory taken for it, and say so:
/// the header as JSON with `json`, else `shard K of N (source): <done>` and where it went.
pub fn write_shard(
    mut rd: printwatt::output::RunDir,
    o: ShardOut,
    json: bool,
    done: &str,
) -> Result<()> {
    use printwatt::campaign::shard::{self, ShardHeader, ShardSource};
    let header = ShardHeader {
        schema_version: shard::SCHEMA_VERSION,
        kind: o.kind.into(),
        shard: o.shard,
        total: o.total,
        rows: o.rows,
        job: o.job,
        args: std::env::args().skip(1).collect(),
        cwd: std::env::current_dir().context("the working directory")?,
        inputs: o.inputs,
        version: super::VERSION.into(),
        rows_sha256: printwatt::output::sha256_hex(&o.bytes),
        wall_time_s: o.wall_time_s,
    };
    let text = serde_json::to_string_pretty(&header)?;
    rd.write(shard::ROWS, &o.bytes)?;
    rd.write(shard::HEADER, text.as_bytes())?;
    let dir = rd.commit()?;
    if json {
        outln!("{text}");
    } else {
        let from = match o.source {
            ShardSource::Given => "as given",
            ShardSource::Slurm => "from the Slurm job array",
            ShardSource::Kubernetes => "from the Kubernetes Indexed Job",
        };
        outln!(
            "shard {} of {} ({from}): {done}",
            o.shard.index,
            o.shard.count
        );
        outln!("wrote {}", dir.display());
    }
    Ok(())
}
