//! `printwatt optimise`: coarse grid sweep, seeded pattern-search refinement, baseline
//! comparison, sensitivity within ±50 mm, and the run report under `results/<run>/`.

use super::sweep::{parse_placement, Loaded, PlacementArgs};
use anyhow::{Context, Result};
use printwatt::search::job::parse_z_bounds;
use printwatt::search::run::{Progress, Stage};
use printwatt::search::{Observer, OptimiseConfig, OptimiseSettings, PlacementSet};
use std::io::IsTerminal;

/// `printwatt optimise` arguments. With none, runs the shipped default robot and path on a
/// default workspace grid and writes `results/optimise-default/`.
#[derive(clap::Args, Debug, Clone)]
pub struct OptimiseArgs {
    /// Robot, path, grid and feasibility options.
    #[command(flatten)]
    pub p: PlacementArgs,
    /// Baseline placement `x,y,z,yaw` (m, m, m, deg); default: the feasible grid cell
    /// nearest the centre of the feasible region.
    #[arg(long, allow_hyphen_values = true)]
    pub baseline: Option<String>,
    /// Seed of the refinement's random directions.
    #[arg(long, default_value_t = 42)]
    pub seed: u64,
    /// Largest number of refinement evaluations.
    #[arg(long, default_value_t = 120)]
    pub max_evals: usize,
    /// Keep the part yaw fixed during the refinement.
    #[arg(long)]
    pub fixed_yaw: bool,
    /// Keep the nozzle spin fixed during the refinement.
    #[arg(long)]
    pub fixed_spin: bool,
    /// Do not write a run directory.
    #[arg(long)]
    pub no_report: bool,
    /// Refinement: `nelder-mead` (argmin, over x, y, z, yaw, spin; default) or `pattern` (the
    /// earlier compass search over x, y, yaw, spin at the grid cell's z).
    #[arg(long, default_value = "nelder-mead")]
    pub search: String,
    /// Placement tolerance the answer must hold, `XY_MM,YAW_DEG` or `XY_MM,Z_MM,YAW_DEG`
    /// (every corner of the box is re-evaluated); `0,0` switches the check off.
    #[arg(long, default_value = "20,1")]
    pub tolerance: String,
    /// Range of the bed height searched, `min:max` in m (default: the grid's z range; the
    /// default grid spans 0 to half the reach).
    #[arg(long, allow_hyphen_values = true)]
    pub z_bounds: Option<String>,
    /// Uncertainty study: draw N plausible robots (masses, inertias, drive constants,
    /// friction, balancer present or not, payload; ranges from the drive file's
    /// `[uncertainty]` table, standard errors for a calibrated robot) seeded by --seed, and
    /// re-evaluate the recommended placement, the feasible grid cells and the baseline under
    /// each.
    #[arg(long, value_name = "N")]
    pub uncertainty: Option<usize>,
    /// With --uncertainty: compute one shard of the draws, for a cluster run: `K/N` (0-based
    /// shard K of N owns draws K, K+N, …), `auto` (index and count from a Slurm job array) or
    /// `auto/N` (Slurm, or a Kubernetes Indexed Job's JOB_COMPLETION_INDEX). Every shard runs
    /// the grid and the refinement (deterministic, the same answer on every machine) and
    /// writes `<--out>/shard-K-of-N/`; `printwatt merge` puts the shards together into the
    /// files of a single run, bit for bit.
    #[arg(long, value_name = "SPEC", requires = "uncertainty")]
    pub shard: Option<String>,
    /// With --uncertainty: the robust choice minimises the expected energy over the draws
    /// (`expected`, default) or the worst-case regret (`regret`), over the answer, its
    /// tolerance corners, a local stencil and each drawn robot's own optimum.
    #[arg(long, default_value = "expected", value_name = "CRITERION")]
    pub robust: String,
    /// Prints a year, for the yearly figures of the robust choice and the value of measuring.
    #[arg(long, default_value_t = printwatt::search::job::DEFAULT_PRINTS_PER_YEAR)]
    pub prints_per_year: f64,
    /// Grid carbon intensity for the yearly CO₂ figure, kg CO₂ per kWh.
    #[arg(long, default_value_t = printwatt::search::job::DEFAULT_GRID_KG_CO2_PER_KWH)]
    pub grid_kg_co2_per_kwh: f64,
    /// Print time against energy: time the answer again with the TCP acceleration and jerk
    /// limits scaled by 0.5, 0.75, 1, 1.5 and 2 (the controller's AccSet; the print speed stays)
    /// and mark the settings no other beats in both (the Pareto front), with each one's CO₂.
    #[arg(long)]
    pub pareto: bool,
    /// Skip the margin trade: by default the answer is found again with joint-limit margins
    /// of 3°, 5° and 8° and wrist margins of 0°, 5° and 8° (the others as configured), and
    /// the report states each one's energy, so a site can choose its margins knowingly.
    #[arg(long)]
    pub no_margin_trade: bool,
    /// Write the chosen placement for the robot into this directory: `frame.json` (COMPAS
    /// frame) and the path re-expressed in the robot base frame as `path_base.gcode`; then
    /// `wobj_print.mod` (ABB RAPID wobjdata), `path_base.mod` (RAPID MoveL in wobj0) and
    /// `path_part.mod` (printing in wobjPrint), or for a Universal Robots arm the URScript
    /// program `path_base.script`. Existing files are replaced only with --force.
    #[arg(long)]
    pub export: Option<std::path::PathBuf>,
}

/// What the tolerance check says, in one line ([`printwatt::search::run::tolerance_line`]).
pub use printwatt::search::run::tolerance_line;

/// The progress bars of an optimisation on a terminal: the grid's (more than one placement)
/// and the refinement's, each shown only when asked for.
pub struct Bars {
    /// Show the grid's bar.
    pub grid: bool,
    /// Show the refinement's bar.
    pub refine: bool,
    bar: std::sync::Mutex<Option<indicatif::ProgressBar>>,
}

impl Bars {
    /// Bars for the stages asked for.
    pub fn new(grid: bool, refine: bool) -> Bars {
        Bars {
            grid,
            refine,
            bar: std::sync::Mutex::new(None),
        }
    }
}

impl Observer for Bars {
    fn begin(&self, stage: Stage, total: usize) {
        let template = match stage {
            Stage::Grid if self.grid && total > 1 => {
                "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} placements ({per_sec}, eta {eta})"
            }
            Stage::Refinement if self.refine => {
                "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} refinement evaluations {msg}"
            }
            _ => return,
        };
        let b = indicatif::ProgressBar::new(total as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template(template)
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        if let Ok(mut g) = self.bar.lock() {
            *g = Some(b);
        }
    }
    fn progress(&self, p: Progress) {
        if let Ok(g) = self.bar.lock() {
            if let Some(b) = g.as_ref() {
                b.set_position(p.done as u64);
                if let Some(best) = p.best_j {
                    b.set_message(format!("best {best:.1} J"));
                }
            }
        }
    }
    fn end(&self, _stage: Stage) {
        if let Ok(mut g) = self.bar.lock() {
            if let Some(b) = g.take() {
                b.finish_and_clear();
            }
        }
    }
    fn setting_name(&self, k: printwatt::search::advice::Knob) -> String {
        super::sweep::knob_flag(k)
    }
}

impl OptimiseArgs {
    /// The job these arguments ask for, with the robot and path loaded (`l`): every option
    /// parsed into its typed value here, and only here.
    pub fn config(&self, l: Loaded) -> Result<OptimiseConfig> {
        let (placements, names, grid) = self.p.placements(Some(l.default_grid()))?;
        let baseline = match &self.baseline {
            Some(s) => Some(parse_placement(s).context("--baseline")?),
            None => None,
        };
        let settings = OptimiseSettings {
            objective: l.objective,
            feasibility: l.feas,
            energy: l.energy,
            profile: l.profile,
            evaluation: self.p.evaluation.evaluation.parse()?,
            baseline,
            seed: self.seed,
            max_evals: self.max_evals,
            fixed_yaw: self.fixed_yaw,
            fixed_spin: self.fixed_spin,
            search: self.search.parse()?,
            tolerance: self.tolerance.parse()?,
            z_bounds: self.z_bounds.as_deref().map(parse_z_bounds).transpose()?,
            uncertainty: self.uncertainty,
            robust: self.robust.parse()?,
            prints_per_year: self.prints_per_year,
            grid_kg_co2_per_kwh: self.grid_kg_co2_per_kwh,
            pareto: self.pareto,
            margin_trade: !self.no_margin_trade,
        };
        settings.check()?;
        Ok(OptimiseConfig {
            robot: l.robot,
            path: l.path,
            path_file: l.path_file,
            placements: Some(PlacementSet {
                placements,
                names,
                grid,
            }),
            settings,
        })
    }
}

/// An uncertainty study's draws computed elsewhere (the shards put together by `printwatt
/// merge`), with the facts of the merged run for `run.json`.
pub struct MergedDraws {
    /// Every draw, in draw order.
    pub draws: Vec<printwatt::search::uncertainty::Draw>,
    /// `run.json` of the merged run ([`super::sweep::run_facts`]) and its extra fields.
    pub facts: (serde_json::Value, Vec<(&'static str, serde_json::Value)>),
}

/// The job of an `optimise` run in a normalised form: every option that changes a result, none
/// of those that say where the output goes, how many threads run or which shard this is.
pub fn job_key(a: &OptimiseArgs) -> String {
    let mut n = a.clone();
    let pk = super::sweep::job_key(&n.p);
    n.shard = None;
    n.export = None;
    n.no_report = false;
    format!(
        "{pk} baseline={:?} seed={} max_evals={} fixed_yaw={} fixed_spin={} search={} tolerance={} z_bounds={:?} uncertainty={:?}",
        n.baseline,
        n.seed,
        n.max_evals,
        n.fixed_yaw,
        n.fixed_spin,
        n.search,
        n.tolerance,
        n.z_bounds,
        n.uncertainty
    ) + &robust_key(&n)
}

/// The robust choice's options in the job key (only when they differ from the defaults, so
/// that the key of a run without them is unchanged).
fn robust_key(n: &OptimiseArgs) -> String {
    use printwatt::search::job::{
        RobustObjective, DEFAULT_GRID_KG_CO2_PER_KWH, DEFAULT_PRINTS_PER_YEAR,
    };
    let mut k = String::new();
    match n.robust.parse::<RobustObjective>() {
        Ok(o) if o == RobustObjective::default() => {}
        Ok(o) => k += &format!(" robust={o}"),
        Err(_) => k += &format!(" robust={}", n.robust),
    }
    if n.prints_per_year != DEFAULT_PRINTS_PER_YEAR
        || n.grid_kg_co2_per_kwh != DEFAULT_GRID_KG_CO2_PER_KWH
    {
        k += &format!(
            " prints_per_year={} grid_kg_co2_per_kwh={}",
            n.prints_per_year, n.grid_kg_co2_per_kwh
        );
    }
    if n.pareto {
        k += " pareto";
    }
    if n.no_margin_trade {
        k += " no_margin_trade";
    }
    k
}

/// `printwatt optimise`.
pub fn run(a: OptimiseArgs) -> Result<()> {
    run_with(a, None)
}

/// A shard of the uncertainty study: which shard, where its number came from, and the shard
/// directory it writes.
type StudyShard = (
    printwatt::campaign::shard::Shard,
    printwatt::campaign::shard::ShardSource,
    printwatt::output::RunDir,
);

/// `printwatt optimise`, with the uncertainty study's draws given (`merged`: a merge of
/// shards) instead of computed.
pub fn run_with(a: OptimiseArgs, merged: Option<MergedDraws>) -> Result<()> {
    let p = &a.p;
    let l = p.load()?;
    let inputs = p.inputs(&l);
    // A shard of the uncertainty study writes its shard directory and nothing else; it is
    // taken before the work, as a run directory is.
    let mut shard_out = take_shard_dir(&a, &inputs)?;
    // Take the run directory before the work: an occupied or locked --run fails now.
    // A JSON run writes nothing but the JSON unless --out (or --run) is given.
    let json_only = p.out.json && p.out.out.is_none() && p.run.is_none();
    let mut run_dir = if a.no_report || json_only || shard_out.is_some() {
        None
    } else {
        p.run_dir(&l, Some("optimise"))?
    };
    let pool = p.pool()?;
    let cfg = a.config(l)?;
    let term = std::io::stderr().is_terminal();
    let bars = Bars::new(term, term);
    if let Some(sh) = shard_out.take() {
        let n = cfg.settings.uncertainty.unwrap_or(0);
        let idx = sh.0.indices(n);
        let d = pool.install(|| printwatt::search::run::run_shard(&cfg, &idx, &bars))?;
        return write_study_shard(&a, &inputs, d, sh);
    }
    let outcome = match &merged {
        Some(m) => pool.install(|| printwatt::search::run::run_merged(&cfg, &m.draws, &bars))?,
        None => pool.install(|| printwatt::search::run(&cfg, &bars))?,
    };
    let rep = &outcome.report;
    let mut written = None;
    if let Some(rd) = run_dir.take() {
        written = Some(write_run(rd, &outcome, merged.as_ref(), &pool)?);
    } else {
        rep.check_finite()?;
    }
    export_hand_off(&a, &cfg, rep)?;
    if p.out.json {
        super::print_report_json(rep, false)?;
        return Ok(());
    }
    print_answer(rep, &cfg)?;
    if let Some(si) = rep.optimise.as_ref().and_then(|o| o.search.as_ref()) {
        print_search_notes(si)?;
    }
    if let Some(u) = rep.optimise.as_ref().and_then(|o| o.uncertainty.as_ref()) {
        for l in printwatt::report::placement::uncertainty_lines(u) {
            outln!("{l}");
        }
    }
    if let Some(d) = rep.optimise.as_ref().and_then(|o| o.decision.as_ref()) {
        print_decision(d)?;
    }
    if let Some(o) = &rep.optimise {
        print_sensitivity(rep, o, outcome.secs)?;
    }
    if let Some(dir) = &written {
        outln!("report: {}", dir.join("report.html").display());
    }
    Ok(())
}

/// With `--shard`: take this shard's directory `<--out>/shard-K-of-N/` before the work.
fn take_shard_dir(
    a: &OptimiseArgs,
    inputs: &printwatt::output::Inputs,
) -> Result<Option<StudyShard>> {
    let p = &a.p;
    let Some(spec) = &a.shard else {
        return Ok(None);
    };
    use printwatt::campaign::shard::Shard;
    let (sh, source) = Shard::parse(spec, &|k| std::env::var(k).ok())?;
    let Some(parent) = p.out.out.clone() else {
        anyhow::bail!("--shard writes a shard directory: give --out DIR (every shard of the run writes DIR/shard-K-of-N/, and `printwatt merge DIR` puts them together)");
    };
    if p.run.is_some() {
        anyhow::bail!("--shard writes into --out DIR/shard-K-of-N/, not into a --run directory");
    }
    let rd = printwatt::output::RunDir::begin_at(
        &parent.join(sh.dir_name()),
        inputs,
        printwatt::output::Existing::Force(p.out.force),
    )?;
    Ok(Some((sh, source, rd)))
}

/// Write the run's report and its facts into the run directory and commit it; returns the
/// directory written.
fn write_run(
    mut rd: printwatt::output::RunDir,
    outcome: &printwatt::search::OptimiseOutcome,
    merged: Option<&MergedDraws>,
    pool: &rayon::ThreadPool,
) -> Result<std::path::PathBuf> {
    let rep = &outcome.report;
    // In the run's pool: its threads make the report's files at once.
    pool.install(|| rep.write_into(&mut rd))?;
    // Facts of this run, not of its answer: the speculative evaluations of the parallel
    // refinement depend on the thread count.
    let spec = rep
        .optimise
        .as_ref()
        .and_then(|o| o.search.as_ref())
        .map(|si| si.speculative_evals);
    let spec = ("speculative_evaluations", serde_json::json!(spec));
    match merged {
        Some(m) => {
            // The merge's own wall time includes the optimisation run again here.
            let mut f = m.facts.0.clone();
            f["wall_time_s"] = serde_json::json!(outcome.secs);
            let mut extra = m.facts.1.clone();
            extra.push(spec);
            super::sweep::write_run_facts(&mut rd, f, &extra)?
        }
        None => super::sweep::write_run_facts(
            &mut rd,
            super::sweep::run_facts(
                pool.current_num_threads(),
                outcome.secs,
                outcome.evaluations,
            ),
            &[spec],
        )?,
    }
    Ok(rd.commit()?)
}

/// With `--export DIR`: write the robot program files of the best placement there.
fn export_hand_off(
    a: &OptimiseArgs,
    cfg: &OptimiseConfig,
    rep: &printwatt::report::placement::RunReport,
) -> Result<()> {
    let (Some(ex), Some(b)) = (&a.export, rep.best()) else {
        return Ok(());
    };
    let files: Vec<(std::path::PathBuf, String)> =
        printwatt::search::run::hand_off(cfg, &b.placement)?
            .into_iter()
            .map(|(name, text)| (ex.join(name), text))
            .collect();
    for (f, text) in &files {
        if f.exists() && !a.p.out.force {
            anyhow::bail!("{} exists: replacing it needs --force", f.display());
        }
        printwatt::output::guard_inputs(f, &[cfg.path_file.as_path()])?;
        printwatt::output::write_atomic(f, text.as_bytes())?;
    }
    Ok(())
}

/// Print the answer: the best placement, its energy split, the full-path check, the baseline,
/// its tolerance and the saving against it.
fn print_answer(rep: &printwatt::report::placement::RunReport, cfg: &OptimiseConfig) -> Result<()> {
    let best = rep.best().context("no feasible placement")?;
    let bp = &best.placement;
    let f = best.feasible().context("best is infeasible")?;
    outln!(
        "best placement: x = {:.3} m, y = {:.3} m, z = {:.3} m, yaw = {:.1}°, spin = {:.1}°",
        bp.x,
        bp.y,
        bp.z,
        bp.yaw.to_degrees(),
        bp.nozzle_spin.to_degrees()
    );
    outln!(
        "energy {:.1} J ({}), print time {:.2} s",
        f.energy_j,
        cfg.settings.objective.describe(),
        f.duration_s
    );
    outln!(
        "supply {:.1} J = standby {:.1} J + drives {:.1} J (friction {:.1} J, gear {:.1} J, copper {:.1} J, regeneration lost {:.1} J)",
        f.supply_j,
        f.standby_j,
        f.drives_j,
        f.losses.friction_j,
        f.losses.gear_j,
        f.losses.copper_j,
        f.losses.regeneration_lost_j
    );
    if let Some(c) = rep
        .optimise
        .as_ref()
        .and_then(|o| o.path_reduction.as_ref())
    {
        outln!("{}", printwatt::report::placement::full_check_line(c));
    }
    print_baseline(rep)
}

/// Print the baseline placement, its tolerance and the saving against it.
fn print_baseline(rep: &printwatt::report::placement::RunReport) -> Result<()> {
    if let Some((how, b)) = &rep.baseline {
        outln!(
            "baseline ({how}): x = {:.3} m, y = {:.3} m, z = {:.3} m, yaw = {:.1}°: {:.1} J",
            b.placement.x,
            b.placement.y,
            b.placement.z,
            b.placement.yaw.to_degrees(),
            b.cost()
        );
    }
    let base_tol = rep
        .optimise
        .as_ref()
        .and_then(|o| o.baseline_tolerance.as_ref());
    if let (Some(_), Some(c)) = (&rep.baseline, base_tol) {
        outln!(
            "baseline tolerance: {}",
            printwatt::report::placement::baseline_tolerance_text(c)
        );
    }
    if let Some(sv) = rep.optimise.as_ref().and_then(|o| o.savings.as_ref()) {
        let t = |(j, pct): (f64, f64)| printwatt::report::placement::saving_text(j, pct);
        outln!(
            "saving vs baseline: supply {}, drives {}, standby {}{}",
            t(sv.supply),
            t(sv.drives),
            t(sv.standby),
            base_tol.map_or(
                String::new(),
                printwatt::report::placement::baseline_saving_caveat
            )
        );
    }
    Ok(())
}

/// Print what the search says about its answer: the tolerance box, the margins it kept, the
/// nozzle spin, a spent budget, the polish and the bounds it ran into.
fn print_search_notes(si: &printwatt::search::refine::SearchInfo) -> Result<()> {
    outln!("tolerance: {}", tolerance_line(&si.tolerance));
    if let Some(jm) = &si.joint_margin {
        outln!("joint-limit margin: {jm}");
    }
    if let Some(wm) = &si.wrist_margin {
        outln!("wrist margin: {wm}");
    }
    if let Some(om) = &si.on_margin {
        outln!(
            "optimum on a joint-limit margin: {om} (the margin, not the energy, stops the search here; --joint-margin)"
        );
    }
    if let Some(sk) = &si.spin_kept {
        outln!("nozzle spin: {sk}");
    }
    if let Some(b) = &si.budget_spent {
        outln!("search stopped: {b} (--max-evals)");
    }
    if let Some(pm) = &si.polished {
        outln!("polish: {pm}");
    }
    if !si.on_bounds.is_empty() {
        outln!(
            "optimum on a search bound: {} (widen --x/--y/--z-bounds there)",
            si.on_bounds.join(", ")
        );
    }
    Ok(())
}

/// Print the decision: the bound steps, the robust choice, the measurement advice, the Pareto
/// front and the margins.
fn print_decision(d: &printwatt::search::robust::Decision) -> Result<()> {
    for b in &d.bound_steps {
        outln!("{}", printwatt::search::robust::bound_line(b));
    }
    for l in d.robust.iter().flat_map(printwatt::search::robust::lines) {
        outln!("{l}");
    }
    if let Some(m) = &d.measurement {
        outln!("{m}");
    }
    for l in printwatt::search::pareto::lines(&d.pareto) {
        outln!("{l}");
    }
    for l in d.margins.iter().flat_map(printwatt::search::margins::lines) {
        outln!("{l}");
    }
    Ok(())
}

/// Print the optimum's neighbourhood (energies, derivatives, one-sided slopes, cheaper
/// neighbours not taken) and the effort of the search, `secs` its wall time.
fn print_sensitivity(
    rep: &printwatt::report::placement::RunReport,
    o: &printwatt::search::optimise::OptimiseResult,
    secs: f64,
) -> Result<()> {
    let s = &o.sensitivity;
    // A value with its unit, or why there is none.
    let fmt = |v: Option<f64>, unit: &str| {
        v.map_or("infeasible".to_string(), |v| format!("{v:.1} {unit}"))
    };
    let fmt_d =
        |v: Option<f64>, unit: &str| v.map_or("n/a".to_string(), |v| format!("{v:.1} {unit}"));
    outln!(
        "±{:.0} mm: E(x−) {}, E(x+) {}, E(y−) {}, E(y+) {}; dE/dx {}, dE/dy {}; d²E/dx² {}, d²E/dy² {}",
        s.h_m * 1000.0,
        fmt(s.e_j[0], "J"),
        fmt(s.e_j[1], "J"),
        fmt(s.e_j[2], "J"),
        fmt(s.e_j[3], "J"),
        fmt_d(s.gradient_j_per_m[0], "J/m"),
        fmt_d(s.gradient_j_per_m[1], "J/m"),
        fmt_d(s.curvature_j_per_m2[0], "J/m²"),
        fmt_d(s.curvature_j_per_m2[1], "J/m²")
    );
    if s.one_sided_j_per_m.iter().any(|v| v.is_some()) {
        outln!(
            "one-sided slopes (optimum on the feasibility boundary): dE/dx {}, dE/dy {}",
            fmt_d(s.one_sided_j_per_m[0], "J/m"),
            fmt_d(s.one_sided_j_per_m[1], "J/m")
        );
    }
    for l in o.search.iter().flat_map(|si| &si.lower_neighbours) {
        outln!("cheaper neighbour not taken: {l}");
    }
    outln!(
        "grid {} placements ({} feasible), refinement {} evaluations; {:.2} s",
        rep.rows.len(),
        rep.rows.iter().filter(|r| r.cost().is_finite()).count(),
        o.evals,
        secs
    );
    Ok(())
}

/// `optimise --uncertainty N --shard SPEC`: this shard's draws of the study, written as the
/// shard directory `<--out>/shard-K-of-N/` (docs/cluster.md).
fn write_study_shard(
    a: &OptimiseArgs,
    inputs: &printwatt::output::Inputs,
    d: printwatt::search::run::ShardDraws,
    (sh, source, rd): (
        printwatt::campaign::shard::Shard,
        printwatt::campaign::shard::ShardSource,
        printwatt::output::RunDir,
    ),
) -> Result<()> {
    use printwatt::campaign::shard;
    let bytes = shard::encode_draws(&d.rows)?;
    let done = format!(
        "{} of {} uncertainty draws in {:.2} s (grid and refinement {:.2} s)",
        d.rows.len(),
        d.total,
        d.draw_s,
        d.secs - d.draw_s
    );
    super::sweep::write_shard(
        rd,
        super::sweep::ShardOut {
            kind: shard::KIND_UNCERTAINTY,
            shard: sh,
            source,
            total: d.total,
            rows: d.rows.len(),
            job: job_key(a),
            inputs: super::sweep::hash_inputs(inputs)?,
            bytes,
            wall_time_s: d.secs,
        },
        a.p.out.json,
        &done,
    )
}
