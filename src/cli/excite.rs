//! `printwatt excite`: an excitation experiment designed for the parameters the placement
//! decision depends on, written as the trajectory CSV `simulate --trajectory` reads, an ABB
//! RAPID module and a URScript program.

use anyhow::{Context, Result};
use printwatt::identify::excite::{self, ExciteOptions};

/// `printwatt excite` arguments.
#[derive(clap::Args, Debug)]
pub struct ExciteArgs {
    #[command(flatten)]
    pub robot: super::args::RobotArg,
    /// Effects the decision depends on, to be made identifiable (identify's names; the
    /// `worth measuring` line of `optimise --uncertainty N` says which).
    #[arg(long, default_value = "balancer")]
    pub target: String,
    /// Effects fitted alongside (identify's names; empty: none).
    #[arg(long, default_value = "viscous,coulomb")]
    pub nuisance: String,
    /// Period of the Fourier motion, s.
    #[arg(long, default_value_t = 10.0)]
    pub period: f64,
    /// Harmonics per joint.
    #[arg(long, default_value_t = 5)]
    pub harmonics: usize,
    /// Periods in the experiment.
    #[arg(long, default_value_t = 2)]
    pub periods: usize,
    /// Sample rate of the trajectory CSV, the rate the controller should log at, Hz.
    #[arg(long, default_value_t = 250.0)]
    pub rate: f64,
    /// Rate of the joint targets of the RAPID and URScript programs, Hz.
    #[arg(long, default_value_t = 25.0)]
    pub target_rate: f64,
    /// Share of every position range, speed and acceleration limit used (0–1).
    #[arg(long, default_value_t = 0.8)]
    pub limit_share: f64,
    /// Lowest height of the elbow, wrist and flange above the base frame's origin, m.
    #[arg(long, default_value_t = 0.3, allow_hyphen_values = true)]
    pub floor: f64,
    /// A box the elbow, wrist and flange stay out of (the bed and the part), base frame:
    /// `xmin,ymin,zmin,xmax,ymax,zmax` in m.
    #[arg(long, allow_hyphen_values = true)]
    pub keep_out: Option<String>,
    /// Random designs tried (then as many local refinements).
    #[arg(long, default_value_t = 150)]
    pub tries: usize,
    /// Seed of the search.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Directory for excite.csv, excite.mod, excite.script and excite.json.
    #[command(flatten)]
    pub out: super::args::OutputArgs,
}

fn list(s: &str) -> Vec<String> {
    s.split(',')
        .map(str::trim)
        .filter(|x| !x.is_empty())
        .map(String::from)
        .collect()
}

/// `printwatt excite`.
pub fn run(a: ExciteArgs) -> Result<()> {
    let robot = a.robot.load()?;
    let keep_out = match &a.keep_out {
        Some(s) => Some(excite::parse_keep_out(s).context("--keep-out")?),
        None => None,
    };
    let o = ExciteOptions {
        period_s: a.period,
        harmonics: a.harmonics,
        periods: a.periods,
        rate_hz: a.rate,
        limit_share: a.limit_share,
        targets: list(&a.target),
        nuisance: list(&a.nuisance),
        tries: a.tries,
        seed: a.seed,
        floor_z_m: a.floor,
        keep_out,
        ..Default::default()
    };
    let e = excite::design(&robot, &o)?;
    let name = robot.name().to_string();
    let dir = a.out.dir(Some(std::path::Path::new(".")));
    let mut written = Vec::new();
    if let Some(d) = &dir {
        super::args::check_out_dir(d)?;
        std::fs::create_dir_all(d)?;
        let files = excite::files(&e, &name, a.target_rate)?;
        for (f, text) in &files {
            let p = d.join(f);
            if p.exists() && !a.out.force {
                anyhow::bail!("{} exists: replacing it needs --force", p.display());
            }
            printwatt::output::write_atomic(&p, text.as_bytes())?;
            written.push(p);
        }
    }
    if a.out.json {
        let mut v = serde_json::to_value(&e)?;
        v["schema_version"] = serde_json::json!(printwatt::output::JSON_SCHEMA_VERSION);
        v["warnings"] = serde_json::json!([]);
        v["files"] = serde_json::json!(written
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>());
        super::print_json_text(&serde_json::to_string_pretty(&v)?)?;
        return Ok(());
    }
    outln!(
        "excitation for {name}: {:.1} s at {:.0} Hz, {} harmonics of a {:.1} s period; targets {} (nuisance {})",
        e.trajectory.duration(),
        a.rate,
        a.harmonics,
        a.period,
        e.targets.join(", "),
        if e.nuisance.is_empty() { "none".into() } else { e.nuisance.join(", ") }
    );
    outln!(
        "targets' information given the nuisance: log-det {:.2}, condition number {:.3e} (naive sine sweep: log-det {:.2}, condition number {:.3e}; {:.1}× better)",
        e.log_det,
        e.condition,
        e.naive_log_det,
        e.naive_condition,
        e.naive_condition / e.condition
    );
    let mx = |v: &[f64]| v.iter().copied().fold(0.0f64, f64::max) * 100.0;
    outln!(
        "limits used: position {:.0} %, speed {:.0} %, acceleration {:.0} % (largest over the joints); lowest elbow/wrist/flange point {:.3} m",
        mx(&e.limits.position),
        mx(&e.limits.speed),
        mx(&e.limits.acceleration),
        e.limits.lowest_z_m
    );
    for p in &written {
        outln!("wrote {}", p.display());
    }
    Ok(())
}
