//! `printwatt optimise`: coarse grid sweep, seeded pattern-search refinement, baseline
//! comparison, sensitivity within ±50 mm, and the run report under `results/<run>/`.

use super::sweep::{detail, meta, parse_placement, run_sweep, PlacementArgs};
use anyhow::{Context, Result};
use printwatt::evaluate::reduce;
use printwatt::report::placement::RunReport;
use printwatt::search::optimise::{self, feasible_centre, worst_of, OptimiseOptions};
use printwatt::search::refine::{self, Bounds, SearchOptions};
use printwatt::search::tolerance::Tolerance;
use printwatt::toolpath::Placement;
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
    #[arg(long, default_value_t = 1000.0)]
    pub prints_per_year: f64,
    /// Grid carbon intensity for the yearly CO₂ figure, kg CO₂ per kWh.
    #[arg(long, default_value_t = 0.4)]
    pub grid_kg_co2_per_kwh: f64,
    /// Write the chosen placement for the robot into this directory: `wobj_print.mod` (ABB RAPID
    /// wobjdata), `frame.json` (COMPAS frame), and the path re-expressed in the robot base
    /// frame as `path_base.gcode` and `path_base.mod` (RAPID MoveL in wobj0). Existing files
    /// are replaced only with --force.
    #[arg(long)]
    pub export: Option<std::path::PathBuf>,
}

/// What the tolerance check says, in one line.
pub fn tolerance_line(c: &printwatt::search::tolerance::ToleranceCheck) -> String {
    use printwatt::report::placement::tolerance_text;
    if c.corners == 0 {
        "not checked (--tolerance 0,0)".into()
    } else if c.holds {
        tolerance_text(c, true)
    } else {
        format!(
            "{}; no grid cell near the optimum holds it",
            tolerance_text(c, true)
        )
    }
}

/// Parse `--tolerance`: `XY_MM,YAW_DEG` or `XY_MM,Z_MM,YAW_DEG`.
pub fn parse_tolerance(s: &str) -> Result<Tolerance> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| {
            t.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v >= 0.0)
                .with_context(|| format!("--tolerance `{s}`: `{}` is not a number >= 0", t.trim()))
        })
        .collect::<Result<_>>()?;
    let (xy, z, yaw) = match v.as_slice() {
        [xy, yaw] => (*xy, *xy, *yaw),
        [xy, z, yaw] => (*xy, *z, *yaw),
        _ => anyhow::bail!("--tolerance `{s}`: expected XY_MM,YAW_DEG or XY_MM,Z_MM,YAW_DEG"),
    };
    if xy > 500.0 || z > 500.0 || yaw > 45.0 {
        anyhow::bail!("--tolerance `{s}`: at most 500 mm and 45°");
    }
    Ok(Tolerance {
        xy_m: xy / 1000.0,
        z_m: z / 1000.0,
        yaw_rad: yaw.to_radians(),
    })
}

/// The search box: x and y over the placements asked for, z over `--z-bounds` or them.
pub fn search_bounds(ps: &[Placement], z_bounds: Option<&str>) -> Result<Bounds> {
    let z = match z_bounds {
        Some(s) => {
            let v: Vec<f64> = s
                .split(':')
                .map(|t| t.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
                .collect::<Option<_>>()
                .with_context(|| format!("--z-bounds `{s}`: expected min:max in m"))?;
            match v.as_slice() {
                [a, b] if a <= b => Some([*a, *b]),
                _ => anyhow::bail!("--z-bounds `{s}`: expected min:max with min <= max (m)"),
            }
        }
        None => None,
    };
    Ok(Bounds::over(ps, z)?)
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
    let mut k = String::new();
    if n.robust != "expected" {
        k += &format!(" robust={}", n.robust);
    }
    if n.prints_per_year != 1000.0 || n.grid_kg_co2_per_kwh != 0.4 {
        k += &format!(
            " prints_per_year={} grid_kg_co2_per_kwh={}",
            n.prints_per_year, n.grid_kg_co2_per_kwh
        );
    }
    k
}

/// `printwatt optimise`.
pub fn run(a: OptimiseArgs) -> Result<()> {
    run_with(a, None)
}

/// `printwatt optimise`, with the uncertainty study's draws given (`merged`: a merge of
/// shards) instead of computed.
pub fn run_with(a: OptimiseArgs, merged: Option<MergedDraws>) -> Result<()> {
    let p = &a.p;
    let l = p.load()?;
    // A shard of the uncertainty study writes its shard directory and nothing else; it is
    // taken before the work, as a run directory is.
    let mut shard_out = None;
    if let Some(spec) = &a.shard {
        use printwatt::campaign::shard::Shard;
        let (sh, source) = Shard::parse(spec, &|k| std::env::var(k).ok())?;
        let Some(parent) = p.out.out.clone() else {
            anyhow::bail!("--shard writes a shard directory: give --out DIR (every shard of the run writes DIR/shard-K-of-N/, and `printwatt merge DIR` puts them together)");
        };
        if p.run.is_some() {
            anyhow::bail!(
                "--shard writes into --out DIR/shard-K-of-N/, not into a --run directory"
            );
        }
        let rd = printwatt::output::RunDir::begin_at(
            &parent.join(sh.dir_name()),
            &p.inputs(&l),
            printwatt::output::Existing::Force(p.out.force),
        )?;
        shard_out = Some((sh, source, rd));
    }
    // Take the run directory before the work: an occupied or locked --run fails now.
    // A JSON run writes nothing but the JSON unless --out (or --run) is given.
    let json_only = p.out.json && p.out.out.is_none() && p.run.is_none();
    let mut run_dir = if a.no_report || json_only || shard_out.is_some() {
        None
    } else {
        p.run_dir(&l, Some("optimise"))?
    };
    let job = l.job()?;
    let pool = p.pool()?;
    let Some(Computed { rep, secs, n_eval }) = compute(
        &a,
        &l,
        &job,
        &pool,
        merged.as_ref().map(|m| m.draws.as_slice()),
        &mut shard_out,
        std::io::stderr().is_terminal(),
    )?
    else {
        // A shard of the uncertainty study: written.
        return Ok(());
    };
    let mut written = None;
    if let Some(mut rd) = run_dir.take() {
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
        match &merged {
            Some(m) => {
                // The merge's own wall time includes the optimisation run again here.
                let mut f = m.facts.0.clone();
                f["wall_time_s"] = serde_json::json!(secs);
                let mut extra = m.facts.1.clone();
                extra.push(spec);
                super::sweep::write_run_facts(&mut rd, f, &extra)?
            }
            None => super::sweep::write_run_facts(
                &mut rd,
                super::sweep::run_facts(pool.current_num_threads(), secs, n_eval),
                &[spec],
            )?,
        }
        written = Some(rd.commit()?);
    } else {
        rep.check_finite()?;
    }
    if let (Some(ex), Some(b)) = (&a.export, rep.best()) {
        let files = [
            (
                ex.join("wobj_print.mod"),
                format!(
                    "MODULE printwatt_placement\n{}ENDMODULE\n",
                    printwatt::export::wobjdata("wobjPrint", &b.placement)
                ),
            ),
            (
                ex.join("frame.json"),
                serde_json::to_string_pretty(&printwatt::export::compas_frame(&b.placement))?,
            ),
            (
                ex.join("path_base.gcode"),
                printwatt::export::gcode_base(
                    &printwatt::export::base_frame_path(&job.moves, &b.placement),
                    &b.placement,
                    l.robot.name(),
                ),
            ),
            (
                ex.join("path_base.mod"),
                printwatt::export::rapid_base(
                    &printwatt::export::base_frame_path(&job.moves, &b.placement),
                    &b.placement,
                    &l.robot,
                ),
            ),
        ];
        for (f, text) in &files {
            if f.exists() && !p.out.force {
                anyhow::bail!("{} exists: replacing it needs --force", f.display());
            }
            printwatt::output::guard_inputs(f, &[l.path_file.as_path()])?;
            printwatt::output::write_atomic(f, text.as_bytes())?;
        }
    }
    if p.out.json {
        super::print_json_text(&rep.summary_json(false)?)?;
        return Ok(());
    }
    let best = rep.best().context("no feasible placement")?;
    let bp = &best.placement;
    let f = best.feasible().context("best is infeasible")?;
    println!(
        "best placement: x = {:.3} m, y = {:.3} m, z = {:.3} m, yaw = {:.1}°, spin = {:.1}°",
        bp.x,
        bp.y,
        bp.z,
        bp.yaw.to_degrees(),
        bp.nozzle_spin.to_degrees()
    );
    println!(
        "energy {:.1} J ({}), print time {:.2} s",
        f.energy_j,
        l.objective.describe(),
        f.duration_s
    );
    println!(
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
        println!("{}", printwatt::report::placement::full_check_line(c));
    }
    if let Some((how, b)) = &rep.baseline {
        println!(
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
        println!(
            "baseline tolerance: {}",
            printwatt::report::placement::baseline_tolerance_text(c)
        );
    }
    if let Some(sv) = rep.optimise.as_ref().and_then(|o| o.savings.as_ref()) {
        let t = |(j, pct): (f64, f64)| printwatt::report::placement::saving_text(j, pct);
        println!(
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
    if let Some(si) = rep.optimise.as_ref().and_then(|o| o.search.as_ref()) {
        println!("tolerance: {}", tolerance_line(&si.tolerance));
        if let Some(jm) = &si.joint_margin {
            println!("joint-limit margin: {jm}");
        }
        if let Some(om) = &si.on_margin {
            println!(
                "optimum on a joint-limit margin: {om} (the margin, not the energy, stops the search here; --joint-margin)"
            );
        }
        if let Some(sk) = &si.spin_kept {
            println!("nozzle spin: {sk}");
        }
        if let Some(b) = &si.budget_spent {
            println!("search stopped: {b} (--max-evals)");
        }
        if let Some(pm) = &si.polished {
            println!("polish: {pm}");
        }
        if !si.on_bounds.is_empty() {
            println!(
                "optimum on a search bound: {} (widen --x/--y/--z-bounds there)",
                si.on_bounds.join(", ")
            );
        }
    }
    if let Some(u) = rep.optimise.as_ref().and_then(|o| o.uncertainty.as_ref()) {
        for l in printwatt::report::placement::uncertainty_lines(u) {
            println!("{l}");
        }
    }
    if let Some(d) = rep.optimise.as_ref().and_then(|o| o.decision.as_ref()) {
        for b in &d.bound_steps {
            println!("{}", printwatt::search::robust::bound_line(b));
        }
        for l in d.robust.iter().flat_map(printwatt::search::robust::lines) {
            println!("{l}");
        }
    }
    if let Some(o) = &rep.optimise {
        let s = &o.sensitivity;
        // A value with its unit, or why there is none.
        let fmt = |v: Option<f64>, unit: &str| {
            v.map_or("infeasible".to_string(), |v| format!("{v:.1} {unit}"))
        };
        let fmt_d =
            |v: Option<f64>, unit: &str| v.map_or("n/a".to_string(), |v| format!("{v:.1} {unit}"));
        println!(
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
            println!(
                "one-sided slopes (optimum on the feasibility boundary): dE/dx {}, dE/dy {}",
                fmt_d(s.one_sided_j_per_m[0], "J/m"),
                fmt_d(s.one_sided_j_per_m[1], "J/m")
            );
        }
        for l in o.search.iter().flat_map(|si| &si.lower_neighbours) {
            println!("cheaper neighbour not taken: {l}");
        }
        println!(
            "grid {} placements ({} feasible), refinement {} evaluations; {:.2} s",
            rep.rows.len(),
            rep.rows.iter().filter(|r| r.cost().is_finite()).count(),
            o.evals,
            secs
        );
    }
    if let Some(dir) = &written {
        println!("report: {}", dir.join("report.html").display());
    }
    Ok(())
}

/// An optimisation's answer: the report (every figure of the run's files) and the facts of
/// the run (wall time of the work, s; evaluations).
pub struct Computed {
    /// The report of the run.
    pub rep: RunReport,
    /// Wall time of the grid, the refinement and the study, s.
    pub secs: f64,
    /// Every evaluation the answer needed.
    pub n_eval: usize,
}

/// The work of `printwatt optimise` on a loaded job: grid, refinement, full re-evaluation of
/// a reduced answer, baseline, uncertainty study (its draws from `merged_draws` when given),
/// detailed placements; the report. With `shard_out` (an uncertainty study's shard) the shard
/// is written and `None` returned. `progress`: show the refinement's progress bar.
pub fn compute(
    a: &OptimiseArgs,
    l: &super::sweep::Loaded,
    job: &printwatt::evaluate::PathJob,
    pool: &rayon::ThreadPool,
    merged_draws: Option<&[printwatt::search::uncertainty::Draw]>,
    shard_out: &mut Option<(
        printwatt::campaign::shard::Shard,
        printwatt::campaign::shard::ShardSource,
        printwatt::output::RunDir,
    )>,
    progress: bool,
) -> Result<Option<Computed>> {
    let p = &a.p;
    let ev = l.evaluator(job, &p.evaluation)?;
    let (ps, names, grid) = p.placements(Some(l.default_grid()))?;
    let baseline_given = match &a.baseline {
        Some(s) => Some(parse_placement(s).context("--baseline")?),
        None => None,
    };
    let t0 = std::time::Instant::now();
    let rows = run_sweep(&ev, &ps, pool)?;
    if !rows.iter().any(|r| r.cost().is_finite()) {
        anyhow::bail!(
            "{}",
            printwatt::search::advice::nothing_feasible_named(
                &rows,
                &l.robot,
                &super::sweep::knob_flag
            )
            .trim_end()
        );
    }
    let step = grid.as_ref().and_then(|g| g.step_xy_m()).unwrap_or(0.1);
    let opts = OptimiseOptions {
        seed: a.seed,
        max_evals: a.max_evals,
        step_xy_m: step / 2.0,
        yaw: !a.fixed_yaw,
        spin: !a.fixed_spin,
        ..Default::default()
    };
    let tol = parse_tolerance(&a.tolerance)?;
    let bounds = search_bounds(&ps, a.z_bounds.as_deref())?;
    let mut res = match a.search.as_str() {
        "nelder-mead" | "nelder_mead" | "nm" => {
            let so = SearchOptions::new(bounds, tol);
            let bar = progress.then(|| {
                let b = indicatif::ProgressBar::new(opts.max_evals as u64);
                b.set_style(
                    indicatif::ProgressStyle::with_template(
                        "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} refinement evaluations {msg}",
                    )
                    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
                );
                b
            });
            let b2 = bar.clone();
            let progress: refine::Progress = std::sync::Arc::new(move |_it, n, best| {
                if let Some(b) = &b2 {
                    b.set_position(n as u64);
                    b.set_message(format!("best {best:.1} J"));
                }
            });
            let (mut r, info) =
                pool.install(|| refine::refine(&ev, &rows, &opts, &so, progress))?;
            if let Some(b) = bar {
                b.finish_and_clear();
            }
            r.search = Some(info);
            r
        }
        "pattern" => pool.install(|| optimise::optimise(&ev, &rows, &opts))?,
        s => anyhow::bail!("--search `{s}`: expected nelder-mead or pattern"),
    };
    // The answer of a reduced evaluation is always re-evaluated in full; the report shows
    // both figures.
    if let Some((full, chk)) = pool.install(|| reduce::confirm(&ev, &res.best))? {
        if let Err(why) = &full.outcome {
            anyhow::bail!(
                "the placement chosen on representative layers (x = {:.3} m, y = {:.3} m, z = {:.3} m, yaw = {:.1}°) is infeasible when every sample is evaluated: {why}; run again with --evaluation full",
                full.placement.x,
                full.placement.y,
                full.placement.z,
                full.placement.yaw.to_degrees()
            );
        }
        res.best = full;
        res.path_reduction = Some(chk);
    }
    let baseline = match baseline_given {
        Some(b) => {
            let r = pool.install(|| ev.sweep(&[b], &|_, _| {}))?;
            r.into_iter().next().map(|e| ("given".to_string(), e))
        }
        None => feasible_centre(&rows)
            .map(|e| ("centre of the feasible grid region".to_string(), e.clone())),
    };
    if let Some((_, b)) = &baseline {
        res.savings = optimise::Savings::of(&res.best, b);
        // The baseline is checked against the tolerance the answer holds (every corner, so
        // the report can say how many fail), in the run's pool.
        if res.search.is_some() && !tol.is_zero() && b.cost().is_finite() {
            res.baseline_tolerance =
                Some(pool.install(|| {
                    printwatt::search::tolerance::check_all(&ev, &b.placement, &tol)
                })?);
        }
    }
    if let Some(n) = a.uncertainty {
        if n == 0 || n > 100_000 {
            anyhow::bail!("--uncertainty {n}: expected 1 to 100000 draws");
        }
        // Candidates: the answer first, then every feasible grid cell that is not nominally
        // better than it (a cheaper cell is one the search rejected because it does not hold
        // the placement tolerance: not a candidate a site could use).
        let mut cands = vec![res.best.clone()];
        cands.extend(
            rows.iter()
                .filter(|r| {
                    r.cost().is_finite()
                        && r.cost() >= res.best.cost()
                        && r.placement != res.best.placement
                })
                .cloned(),
        );
        let setup = printwatt::search::uncertainty::StudySetup::new(
            &ev,
            &cands,
            baseline.as_ref().map(|b| &b.1),
            n,
            a.seed,
            None,
        )?;
        if let Some((sh, source, rd)) = shard_out.take() {
            write_study_shard(a, l, &setup, (sh, source, rd), t0)?;
            return Ok(None);
        }
        let study = match merged_draws {
            Some(d) => setup.reduce(d)?,
            None => {
                let all: Vec<usize> = (0..n).collect();
                let per = pool.install(|| setup.draws(&all))?;
                setup.reduce(&per)?
            }
        };
        res.uncertainty = Some(study);
        if res.search.is_some() {
            let ro = printwatt::search::robust::RobustOptions {
                draws: n,
                seed: a.seed,
                criterion: printwatt::search::robust::Criterion::parse(&a.robust)?,
                prints_per_year: a.prints_per_year,
                grid_kg_co2_per_kwh: a.grid_kg_co2_per_kwh,
                ..Default::default()
            };
            let so = SearchOptions::new(bounds, tol);
            let r = pool
                .install(|| printwatt::search::robust::robust(&ev, &res.best, &opts, &so, &ro))?;
            res.decision.get_or_insert_with(Default::default).robust = Some(r);
        }
    }
    if let Some(si) = &res.search {
        if !si.on_bounds.is_empty() {
            let steps = pool.install(|| {
                printwatt::search::robust::bound_steps(
                    &ev,
                    &res.best,
                    &si.bounds,
                    &printwatt::search::robust::BOUND_STEPS_M,
                )
            })?;
            res.decision
                .get_or_insert_with(Default::default)
                .bound_steps = steps;
        }
    }
    let secs = t0.elapsed().as_secs_f64();
    // The placements shown in detail (series for the report), evaluated in parallel.
    let mut wanted = vec![("best", &res.best)];
    wanted.extend(worst_of(&rows).map(|w| ("worst", w)));
    wanted.extend(baseline.as_ref().map(|(_, b)| ("baseline", b)));
    let details: Vec<_> = {
        use rayon::prelude::*;
        pool.install(|| {
            wanted
                .par_iter()
                .map(|(label, e)| detail(job, label, e))
                .collect::<Result<Vec<_>>>()
        })?
        .into_iter()
        .flatten()
        .collect()
    };
    // Every evaluation the answer needed: grid, refinement, tolerance checks (with the
    // bisection and spin points; the baseline's corners) and the 4 sensitivity points.
    let base_corners = res.baseline_tolerance.as_ref().map_or(0, |c| c.corners);
    let n_eval = ps.len()
        + res.evals
        + res.search.as_ref().map_or(0, |si| si.tolerance_evals)
        + base_corners
        + 4;
    let mut m = meta(l, ev.nominal_samples());
    m.extend(super::sweep::evaluation_line(&ev));
    m.push(("seed".into(), a.seed.to_string()));
    if let Some(si) = &res.search {
        m.push(("search".into(), si.method.clone()));
        m.push(("tolerance".into(), tolerance_line(&si.tolerance)));
        m.push((
            "search bounds".into(),
            format!(
                "x {:.3}…{:.3} m, y {:.3}…{:.3} m, z {:.3}…{:.3} m",
                si.bounds.x[0],
                si.bounds.x[1],
                si.bounds.y[0],
                si.bounds.y[1],
                si.bounds.z[0],
                si.bounds.z[1]
            ),
        ));
        if !si.on_bounds.is_empty() {
            m.push((
                "optimum on a search bound".into(),
                format!("{}: widen the range there", si.on_bounds.join(", ")),
            ));
        }
        if let Some(jm) = &si.joint_margin {
            m.push(("joint-limit margin kept".into(), jm.clone()));
        }
        m.push((
            "evaluations".into(),
            if base_corners > 0 {
                format!(
                    "grid {}, refinement {}, tolerance corners {} (the answer's search {}, the baseline {})",
                    ps.len(),
                    res.evals,
                    si.tolerance_evals + base_corners,
                    si.tolerance_evals,
                    base_corners
                )
            } else {
                format!(
                    "grid {}, refinement {}, tolerance corners {}",
                    ps.len(),
                    res.evals,
                    si.tolerance_evals
                )
            },
        ));
        if let Some(om) = &si.on_margin {
            m.push((
                "optimum on a joint-limit margin".into(),
                format!("{om}: the margin, not the energy, stops the search here (--joint-margin)"),
            ));
        }
        if let Some(sk) = &si.spin_kept {
            m.push(("nozzle spin".into(), sk.clone()));
        }
        if let Some(b) = &si.budget_spent {
            m.push(("search stopped".into(), b.clone()));
        }
        if let Some(pm) = &si.polished {
            m.push(("polish".into(), pm.clone()));
        }
        for l in &si.lower_neighbours {
            m.push(("cheaper neighbour not taken".into(), l.clone()));
        }
    }
    let site = printwatt::report::site::SiteGeometry::new(
        &l.robot,
        job,
        res.best.placement.z,
        &l.path_file,
        names.as_deref(),
    );
    let rep = RunReport {
        title: format!(
            "printwatt optimise: {} on {}",
            l.path_file.display(),
            l.robot.name()
        ),
        meta: m,
        rows,
        names,
        grid,
        optimise: Some(res),
        baseline,
        site: Some(site),
        details,
        electrical: l.robot.drive.is_some(),
    };
    Ok(Some(Computed { rep, secs, n_eval }))
}

/// `optimise --uncertainty N --shard SPEC`: this shard's draws of the study, written as the
/// shard directory `<--out>/shard-K-of-N/` (docs/cluster.md).
fn write_study_shard(
    a: &OptimiseArgs,
    l: &super::sweep::Loaded,
    setup: &printwatt::search::uncertainty::StudySetup,
    (sh, source, rd): (
        printwatt::campaign::shard::Shard,
        printwatt::campaign::shard::ShardSource,
        printwatt::output::RunDir,
    ),
    t0: std::time::Instant,
) -> Result<()> {
    use printwatt::campaign::shard;
    let p = &a.p;
    let idx = sh.indices(setup.len());
    let pool = p.pool()?;
    let t1 = std::time::Instant::now();
    let draws = pool.install(|| setup.draws(&idx))?;
    let draw_s = t1.elapsed().as_secs_f64();
    let rows: Vec<(usize, printwatt::search::uncertainty::Draw)> =
        idx.into_iter().zip(draws).collect();
    let bytes = shard::encode_draws(&rows)?;
    let wall_time_s = t0.elapsed().as_secs_f64();
    let done = format!(
        "{} of {} uncertainty draws in {draw_s:.2} s (grid and refinement {:.2} s)",
        rows.len(),
        setup.len(),
        wall_time_s - draw_s
    );
    super::sweep::write_shard(
        rd,
        super::sweep::ShardOut {
            kind: shard::KIND_UNCERTAINTY,
            shard: sh,
            source,
            total: setup.len(),
            rows: rows.len(),
            job: job_key(a),
            inputs: super::sweep::hash_inputs(&p.inputs(l))?,
            bytes,
            wall_time_s,
        },
        p.out.json,
        &done,
    )
}
