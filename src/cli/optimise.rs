//! `printwatt optimise`: coarse grid sweep, seeded pattern-search refinement, baseline
//! comparison, sensitivity within ±50 mm, and the run report under `results/<run>/`.

use super::sweep::{detail, meta, parse_placement, run_sweep, PlacementArgs};
use crate::placement::optimise::{self, feasible_centre, worst_of, OptimiseOptions};
use crate::placement::sweep::Evaluator;
use crate::report::placement::RunReport;
use anyhow::{Context, Result};

/// `printwatt optimise` arguments. With none, runs the shipped default robot and path on a
/// default workspace grid and writes `results/optimise-default/`.
#[derive(clap::Args, Debug)]
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
}

/// `printwatt optimise`.
pub fn run(a: OptimiseArgs) -> Result<()> {
    let p = &a.p;
    let l = p.load()?;
    // Decide where the run goes before the work: an occupied --run fails now, not after.
    let dir = if a.no_report {
        None
    } else {
        p.run_dir(&l, Some("optimise"))?
    };
    let job = l.job()?;
    let ev = Evaluator::new(&job, l.feas, l.objective);
    let (ps, names, grid) = p.placements(Some(l.default_grid()))?;
    let baseline_given = match &a.baseline {
        Some(s) => Some(parse_placement(s).context("--baseline")?),
        None => None,
    };
    let pool = p.pool()?;
    let t0 = std::time::Instant::now();
    let rows = run_sweep(&ev, &ps, &pool)?;
    if !rows.iter().any(|r| r.cost().is_finite()) {
        anyhow::bail!(
            "{}",
            crate::placement::advice::nothing_feasible(&rows, &l.robot).trim_end()
        );
    }
    let step = grid
        .as_ref()
        .and_then(|g| {
            let d = |v: &[f64]| (v.len() > 1).then(|| (v[1] - v[0]).abs());
            match (d(&g.xs), d(&g.ys)) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            }
        })
        .unwrap_or(0.1);
    let opts = OptimiseOptions {
        seed: a.seed,
        max_evals: a.max_evals,
        step_xy_m: step / 2.0,
        yaw: !a.fixed_yaw,
        spin: !a.fixed_spin,
        ..Default::default()
    };
    let res = pool.install(|| optimise::optimise(&ev, &rows, &opts))?;
    let baseline = match baseline_given {
        Some(b) => {
            let r = pool.install(|| ev.sweep(&[b], &|_, _| {}))?;
            r.into_iter().next().map(|e| ("given".to_string(), e))
        }
        None => feasible_centre(&rows)
            .map(|e| ("centre of the feasible grid region".to_string(), e.clone())),
    };
    let secs = t0.elapsed().as_secs_f64();
    let mut details = Vec::new();
    details.extend(detail(&job, "best", &res.best)?);
    if let Some(w) = worst_of(&rows) {
        details.extend(detail(&job, "worst", w)?);
    }
    if let Some((_, b)) = &baseline {
        details.extend(detail(&job, "baseline", b)?);
    }
    let n_eval = ps.len() + res.evals + 4;
    let mut m = meta(
        &l,
        pool.current_num_threads(),
        secs,
        n_eval,
        ev.nominal_samples(),
    );
    m.push(("seed".into(), a.seed.to_string()));
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
        details,
        electrical: l.robot.drive.is_some(),
    };
    if let Some(dir) = &dir {
        rep.write(dir)?;
    }
    if p.json {
        println!("{}", rep.summary_json(false)?);
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
        f.energy_j, p.objective, f.duration_s
    );
    if let (Some((how, b)), Some((j, pct))) = (&rep.baseline, rep.saving()) {
        println!(
            "saving vs baseline ({how}: x = {:.3}, y = {:.3}, yaw = {:.1}°, {:.1} J): {j:.1} J ({pct:.2} %)",
            b.placement.x,
            b.placement.y,
            b.placement.yaw.to_degrees(),
            b.cost()
        );
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
        println!(
            "grid {} placements ({} feasible), refinement {} evaluations; {:.2} s",
            rep.rows.len(),
            rep.rows.iter().filter(|r| r.cost().is_finite()).count(),
            o.evals,
            secs
        );
    }
    if let Some(dir) = &dir {
        println!("report: {}", dir.join("report.html").display());
    }
    Ok(())
}
