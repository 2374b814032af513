//! `printwatt stations`: a multi-station plan for a path larger than one placement's reach
//! (library: [`printwatt::stations`]; report: [`printwatt::report::stations`]).

use super::sweep::{meta, Loaded, PlacementArgs};
use anyhow::{bail, Context, Result};
use printwatt::report::stations::StationsReport;
use printwatt::stations::{self, Headings, Sites, StationsJob};
use printwatt::timing::JointStageOptions;
use std::io::IsTerminal;

/// `printwatt stations` arguments: the robot, path, timing, energy, feasibility and output
/// options of `sweep` and `optimise` (the placement grid options excepted: this command
/// chooses its own stations), plus the relocation cost and the candidate stations.
#[derive(clap::Args, Debug)]
#[command(
    after_help = "Station height: --z is the height of the part origin above each station's base frame, m (default -0.5: the base 0.5 m above the floor the path is printed on, a robot on a track carriage or crawler; at 0 the base stands in the bed the feasibility check models). --spin: one nozzle spin, deg (default 0). Costs in J, lengths in m, angles in deg."
)]
pub struct StationsArgs {
    /// Robot, path, timing, energy, feasibility and output options (`--x`, `--y`, `--yaw`,
    /// `--set` and `--at` do not apply: give `--station-step`, `--track`, `--heading`).
    #[command(flatten)]
    pub p: PlacementArgs,
    /// Cost of one relocation of the arm between stations, J: your number (the energy of
    /// moving the arm on its track or crawler, the cabinet's standby meanwhile, …); printwatt
    /// does not model the move. Required.
    #[arg(long, value_name = "J")]
    pub relocation_cost: f64,
    /// Extra relocation cost per metre between consecutive stations, J/m.
    #[arg(long, value_name = "J/M", default_value_t = 0.0)]
    pub relocation_cost_per_m: f64,
    /// Spacing of the candidate station positions, m: a grid over the path's footprint
    /// widened by the robot's reach, or points along --track.
    #[arg(long, value_name = "M", default_value_t = 0.5)]
    pub station_step: f64,
    /// Candidate stations along a straight track from X0,Y0 to X1,Y1 (m, part frame) every
    /// --station-step, instead of the grid.
    #[arg(long, value_name = "X0,Y0:X1,Y1", allow_hyphen_values = true)]
    pub track: Option<String>,
    /// Heading of the robot at a station (its base x axis in the part frame): `auto` (facing
    /// the centroid of the segment it prints) or angles in deg (a list: each a candidate).
    #[arg(
        long,
        value_name = "auto|DEG",
        default_value = "auto",
        allow_hyphen_values = true
    )]
    pub heading: String,
    /// Radius of the floor disc a station occupies (the robot's foot with its track carriage
    /// or crawler), m: a station may not stand on a wall printed before or by its segment, nor
    /// cross one on the way to the next station. Default: 0.2 × the arm's reach (an estimate
    /// from the IRB 6640 family's foot; give your carriage's or crawler's).
    #[arg(long, value_name = "M")]
    pub footprint: Option<f64>,
    /// Write the hand-off of every station into DIR: per station the work object, the path
    /// in the base frame (G-code, RAPID) and a RAPID module printing in `wobjPrint`, each with
    /// the planned arm configuration (`station_<k>_…`).
    #[arg(long, value_name = "DIR")]
    pub export: Option<std::path::PathBuf>,
}

fn parse_xy(s: &str, what: &str) -> Result<[f64; 2]> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect::<Option<_>>()
        .with_context(|| format!("--track: `{s}` in {what}: expected X,Y in m"))?;
    match v.as_slice() {
        [x, y] => Ok([*x, *y]),
        _ => bail!("--track: `{s}` in {what}: expected X,Y in m"),
    }
}

/// `printwatt stations`.
pub fn run(a: StationsArgs) -> Result<()> {
    let p = &a.p;
    refuse_placement_options(p)?;
    let l = p.load()?;
    let job = job(&a, &l)?;
    let json_only = p.out.json && p.out.out.is_none() && p.run.is_none();
    let mut run_dir = if json_only {
        None
    } else {
        p.run_dir(&l, Some("stations"))?
    };
    let pool = p.pool()?;
    let outcome = plan_with_progress(&pool, &job)?;
    let (plan, secs) = (&outcome.plan, outcome.secs);
    let mut m = meta(&l, 0);
    m.retain(|(k, _)| k != "nominal path samples");
    m.extend(outcome.facts(&job));
    let rep = StationsReport {
        title: format!(
            "printwatt stations: {} on {}",
            l.path_file.display(),
            l.robot.name()
        ),
        meta: m,
        plan,
        path: &l.path,
        relocation_cost_j: a.relocation_cost,
        relocation_cost_per_m_j: a.relocation_cost_per_m,
    };
    let mut written = None;
    if let Some(mut rd) = run_dir.take() {
        rep.write_into(&mut rd)?;
        super::sweep::write_run_facts(
            &mut rd,
            super::sweep::run_facts(pool.current_num_threads(), secs, plan.stats.evaluations),
            &[],
        )?;
        written = Some(rd.commit()?);
    }
    if let Some(ex) = &a.export {
        export_hand_off(ex, p.out.force, &l, plan)?;
    }
    if p.out.json {
        super::print_json_text(&rep.summary_json()?)?;
        return Ok(());
    }
    print_plan(&a, &l, plan, secs)?;
    if let Some(dir) = &written {
        outln!("report: {}", dir.join("report.html").display());
    }
    Ok(())
}

/// Refuse the placement options `stations` does not take: it chooses its own stations.
fn refuse_placement_options(p: &PlacementArgs) -> Result<()> {
    for (given, opt) in [
        (p.x.is_some(), "--x"),
        (p.y.is_some(), "--y"),
        (p.yaw.is_some(), "--yaw"),
        (p.set.is_some(), "--set"),
        (p.at.at.is_some(), "--at"),
    ] {
        if given {
            bail!("{opt}: `stations` chooses its own stations; give --station-step, --track or --heading instead");
        }
    }
    Ok(())
}

/// The stations job of the command line: the loaded robot and path, the station height and
/// nozzle spin, the headings, the candidate sites and the relocation costs.
fn job<'l>(a: &StationsArgs, l: &'l Loaded) -> Result<StationsJob<'l>> {
    let p = &a.p;
    let z = match &p.z {
        Some(s) => {
            let v = printwatt::search::parse_range("z", s)?;
            if v.len() != 1 {
                bail!("--z `{s}`: `stations` takes one height (m)");
            }
            v[0]
        }
        None => stations::DEFAULT_Z_M,
    };
    let spin = match &p.at.spin {
        Some(s) => s
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .with_context(|| format!("--spin `{s}`: `stations` takes one angle in deg"))?
            .to_radians(),
        None => 0.0,
    };
    let headings = if a.heading.trim() == "auto" {
        Headings::Auto
    } else {
        Headings::Fixed(
            printwatt::search::parse_range("heading", &a.heading)?
                .into_iter()
                .map(f64::to_radians)
                .collect(),
        )
    };
    let sites = match &a.track {
        Some(t) => {
            let (s0, s1) = t
                .split_once(':')
                .with_context(|| format!("--track `{t}`: expected X0,Y0:X1,Y1 (m)"))?;
            Sites::Track {
                from: parse_xy(s0, t)?,
                to: parse_xy(s1, t)?,
                step_m: a.station_step,
            }
        }
        None => Sites::Grid {
            step_m: a.station_step,
        },
    };
    Ok(StationsJob {
        energy: l.energy,
        profile: l.profile,
        joint: JointStageOptions::default(),
        feasibility: l.feas,
        objective: l.objective,
        sites,
        headings,
        z_m: z,
        spin_rad: spin,
        relocation_j_per_m: a.relocation_cost_per_m,
        footprint_m: a.footprint,
        ..StationsJob::new(&l.robot, &l.path, a.relocation_cost)
    })
}

/// Plan the stations in `pool`, with a progress bar on a terminal.
fn plan_with_progress(
    pool: &rayon::ThreadPool,
    job: &StationsJob,
) -> Result<stations::StationsOutcome> {
    let bar = std::io::stderr().is_terminal().then(|| {
        let b = indicatif::ProgressBar::new(0);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} runs of units",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    });
    let cb = |done: usize, total: usize| {
        if let Some(b) = &bar {
            b.set_length(total as u64);
            b.set_position(done as u64);
        }
    };
    let outcome = pool.install(|| stations::run(job, &cb));
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    Ok(outcome?)
}

/// With `--export DIR`: write the robot program files of every station there (`force`:
/// replace existing ones).
fn export_hand_off(
    ex: &std::path::Path,
    force: bool,
    l: &Loaded,
    plan: &stations::Plan,
) -> Result<()> {
    let stations: Vec<_> = plan
        .segments
        .iter()
        .map(|s| (s.moves, s.station.placement))
        .collect();
    let files = printwatt::export::stations_hand_off(
        &l.robot,
        &l.path,
        &stations,
        l.energy,
        l.profile,
        l.feas,
        l.objective,
    )?;
    std::fs::create_dir_all(ex)?;
    for (name, text) in &files {
        let f = ex.join(name);
        if f.exists() && !force {
            bail!("{} exists: replacing it needs --force", f.display());
        }
        printwatt::output::guard_inputs(&f, &[l.path_file.as_path()])?;
        printwatt::output::write_atomic(&f, text.as_bytes())?;
    }
    Ok(())
}

/// Print the plan: the relocations, one line per segment, the energies and the search's
/// effort (`secs` its wall time).
fn print_plan(a: &StationsArgs, l: &Loaded, plan: &stations::Plan, secs: f64) -> Result<()> {
    outln!(
        "plan: {} station(s), {} relocation(s) at {} J each + {} J/m ({:.2} m moved)",
        plan.segments.len(),
        plan.relocations,
        a.relocation_cost,
        a.relocation_cost_per_m,
        plan.relocation_distance_m
    );
    outln!(
        "{:>3} {:>8} {:>8} {:>8}  {:<36} {:>7} {:>9} {:>8} {:>10} {:>8}",
        "seg",
        "x[m]",
        "y[m]",
        "head[°]",
        "--at x,y,z,yaw,spin (m, °)",
        "units",
        "lines",
        "print[m]",
        "energy[J]",
        "time[s]"
    );
    for (k, s) in plan.segments.iter().enumerate() {
        let at = &s.station.placement;
        outln!(
            "{:>3} {:>8.3} {:>8.3} {:>8.1}  {:<36} {:>7} {:>9} {:>8.2} {:>10.1} {:>8.2}",
            k + 1,
            s.station.x_m,
            s.station.y_m,
            s.station.heading_rad.to_degrees(),
            format!(
                "{:.3},{:.3},{:.3},{:.2},{:.2}",
                at.x,
                at.y,
                at.z,
                at.yaw.to_degrees(),
                at.nozzle_spin.to_degrees()
            ),
            format!("{}–{}", s.units[0], s.units[1]),
            format!("{}–{}", s.lines[0], s.lines[1]),
            s.print_length_m,
            s.eval.energy_j,
            s.eval.duration_s
        );
    }
    outln!(
        "energy {:.1} J ({}) + relocations {:.1} J = total {:.1} J",
        plan.energy_j,
        l.objective.describe(),
        plan.relocation_j,
        plan.total_j
    );
    outln!(
        "{} units; {} candidate positions; {} runs of units; {} evaluations of a run from a station ({} feasible); wall time {secs:.2} s",
        plan.stats.units,
        plan.stats.positions,
        plan.stats.runs,
        plan.stats.evaluations,
        plan.stats.feasible
    );
    Ok(())
}
