//! `printwatt merge`: put the shards of a split sweep, uncertainty study or design study
//! together into the files a single run writes (`summary.json`, `placements.csv`,
//! `report.html`; a study's directory), bit for bit; `run.json` says how the merged run was
//! made.

use anyhow::{bail, Context, Result};
use clap::Parser;
use printwatt::campaign::shard;
use std::path::PathBuf;

/// `printwatt merge` arguments.
#[derive(clap::Args, Debug)]
pub struct MergeArgs {
    /// Shard directories (`shard-K-of-N/`), or directories holding them (the --out every shard
    /// of the run wrote into).
    #[arg(required = true, value_name = "SHARDS")]
    pub shards: Vec<PathBuf>,
    /// --out: the merged run directory (summary.json, placements.csv, report.html, run.json).
    #[command(flatten)]
    pub out: super::args::OutputArgs,
}

/// `printwatt merge`.
pub fn run(m: MergeArgs) -> Result<()> {
    let t0 = std::time::Instant::now();
    let Shards {
        dirs,
        shard_dirs,
        merged,
    } = read_and_merge(&m)?;
    let h = &merged.header;
    // The job's relative paths are relative to where the shards ran.
    let out = match &m.out.out {
        Some(o) => Some(std::path::absolute(o).with_context(|| o.display().to_string())?),
        None => None,
    };
    let here = std::env::current_dir().context("the working directory")?;
    if h.cwd != here {
        std::env::set_current_dir(&h.cwd).with_context(|| {
            format!(
                "the shards ran in {}, which the job's relative paths refer to",
                h.cwd.display()
            )
        })?;
    }
    let cli = super::Cli::try_parse_from(
        std::iter::once("printwatt".to_string()).chain(h.args.iter().cloned()),
    )
    .context("the shards' command line")?;
    if h.kind == shard::KIND_STUDY {
        let super::Command::Study(sa) = cli.command else {
            bail!("the shards hold study cases but were not written by `printwatt study`");
        };
        let (facts, extra) = merged_facts(&merged, &dirs, "cases", t0);
        let shard::MergedRows::Study(results) = merged.rows else {
            bail!("the shards hold placements or draws, not study cases");
        };
        return super::study::merge(
            sa,
            h,
            results,
            &shard_dirs,
            out,
            &m.out,
            (facts, extra),
            &here,
        );
    }
    if h.kind == shard::KIND_UNCERTAINTY {
        let super::Command::Optimise(oa) = cli.command else {
            bail!("the shards hold uncertainty draws but were not written by `printwatt optimise`");
        };
        return merge_study(oa, &merged, &dirs, out, &m.out, t0);
    }
    let super::Command::Sweep(sa) = cli.command else {
        bail!("the shards were not written by `printwatt sweep`");
    };
    let mut a = sa.p;
    a.out = super::args::OutputArgs {
        out,
        json: m.out.json,
        force: m.out.force,
    };
    a.run = None;
    merge_sweep(a, merged, &dirs, t0, &here)
}

/// The shards of a run, read and merged.
struct Shards {
    /// The shard directories.
    dirs: Vec<PathBuf>,
    /// Each shard's index and its absolute directory.
    shard_dirs: Vec<(usize, PathBuf)>,
    /// The merge.
    merged: shard::Merged,
}

/// Find and read the shards (an output overlapping any of them refused first) and merge
/// them, the merge checked to come from this build.
fn read_and_merge(m: &MergeArgs) -> Result<Shards> {
    let dirs = shard::find_shards(&m.shards)?;
    // The merged run must not replace or change a shard: an output equal to, inside or
    // holding any input is refused, with or without --force.
    if let Some(o) = &m.out.out {
        let inputs: Vec<PathBuf> = m.shards.iter().chain(&dirs).cloned().collect();
        printwatt::output::refuse_overlap(o, &inputs)?;
    }
    let mut data = Vec::with_capacity(dirs.len());
    for d in &dirs {
        data.push(shard::read_shard(d)?);
    }
    // Absolute: the merge runs the job in the directory the shards ran in.
    let shard_dirs: Vec<(usize, PathBuf)> = data
        .iter()
        .map(|s| {
            (
                s.header.shard.index,
                std::path::absolute(&s.dir).unwrap_or_else(|_| s.dir.clone()),
            )
        })
        .collect();
    let merged = shard::merge(data)?;
    let h = &merged.header;
    if h.version != super::VERSION {
        bail!(
            "the shards were computed by printwatt {}, this is printwatt {}: merge with the build that computed them",
            h.version,
            super::VERSION
        );
    }
    Ok(Shards {
        dirs,
        shard_dirs,
        merged,
    })
}

/// Merge the shards of a sweep: the job is loaded again here and checked to be the one the
/// shards ran (same job, same inputs, the same placements in the same order), then the run
/// is finished as a single run finishes it.
fn merge_sweep(
    a: super::sweep::PlacementArgs,
    merged: shard::Merged,
    dirs: &[PathBuf],
    t0: std::time::Instant,
    here: &std::path::Path,
) -> Result<()> {
    let h = &merged.header;
    if super::sweep::job_key(&a) != h.job {
        bail!("this printwatt reads the shards' command line as a different job than the one they ran");
    }
    let l = a.load()?;
    unchanged_inputs(h, &super::sweep::hash_inputs(&a.inputs(&l))?)?;
    let run_dir = a.run_dir(&l, None)?;
    let job = l.job()?;
    let ev = l.evaluator(&job, &a.evaluation)?;
    let (ps, names, grid) = a.placements(Some(l.default_grid()))?;
    let shard::MergedRows::Sweep(swept) = &merged.rows else {
        bail!("the shards hold draws, not placements");
    };
    if ps.len() != swept.len() {
        bail!(
            "the job asks for {} placements, the shards hold {}",
            ps.len(),
            swept.len()
        );
    }
    if let Some(i) = ps.iter().zip(swept).position(|(p, r)| {
        let q = &r.placement;
        [p.x, p.y, p.z, p.yaw, p.nozzle_spin]
            .iter()
            .zip([q.x, q.y, q.z, q.yaw, q.nozzle_spin])
            .any(|(a, b)| a.to_bits() != b.to_bits())
    }) {
        bail!("placement {i} of the shards is not placement {i} of the job");
    }
    let (facts, extra) = merged_facts(&merged, dirs, "placements", t0);
    let shard::MergedRows::Sweep(rows) = merged.rows else {
        bail!("the shards hold draws, not placements");
    };
    std::env::set_current_dir(here).ok();
    super::sweep::finish(
        &a,
        &l,
        &job,
        &ev,
        super::sweep::Swept { rows, names, grid },
        run_dir,
        (facts, extra),
    )
}

/// Merge the shards of an `optimise --uncertainty N --shard …` run: the optimisation is run
/// again here (deterministic: the answer and the candidates the shards drew for), the draws
/// come from the shards, and the run directory is the one a single run writes.
fn merge_study(
    mut a: super::optimise::OptimiseArgs,
    merged: &shard::Merged,
    dirs: &[PathBuf],
    out: Option<PathBuf>,
    o: &super::args::OutputArgs,
    t0: std::time::Instant,
) -> Result<()> {
    let h = &merged.header;
    let shard::MergedRows::Draws(draws) = &merged.rows else {
        bail!("the shards hold placements, not uncertainty draws");
    };
    let Some(out) = out else {
        bail!("merging an uncertainty study writes its run directory: give --out DIR");
    };
    a.shard = None;
    a.no_report = false;
    a.export = None;
    a.p.run = None;
    a.p.out = super::args::OutputArgs {
        out: Some(out),
        json: o.json,
        force: o.force,
    };
    if super::optimise::job_key(&a) != h.job {
        bail!("this printwatt reads the shards' command line as a different job than the one they ran");
    }
    if a.uncertainty != Some(h.total) {
        bail!(
            "the shards hold {} draws, their command line asks for {:?}",
            h.total,
            a.uncertainty
        );
    }
    let l = a.p.load()?;
    unchanged_inputs(h, &super::sweep::hash_inputs(&a.p.inputs(&l))?)?;
    drop(l);
    let (facts, extra) = merged_facts(merged, dirs, "draws", t0);
    super::optimise::run_with(
        a,
        Some(super::optimise::MergedDraws {
            draws: draws.clone(),
            facts: (facts, extra),
        }),
    )
}

/// Every input the shards hashed is unchanged now (`now`: the same inputs hashed again).
pub(super) fn unchanged_inputs(
    h: &shard::ShardHeader,
    now: &std::collections::BTreeMap<String, String>,
) -> Result<()> {
    for (f, sha) in &h.inputs {
        if now.get(f) != Some(sha) {
            bail!("{f} changed since the shards ran (SHA-256 differs): the shards are results of the old file; re-run them");
        }
    }
    Ok(())
}

/// `run.json` of a merged run: the merge's own facts, the shards it read, their count, the
/// number of items (`items`: "placements" or "draws") and the shards' summed wall time.
fn merged_facts(
    merged: &shard::Merged,
    dirs: &[PathBuf],
    items: &'static str,
    t0: std::time::Instant,
) -> (serde_json::Value, Vec<(&'static str, serde_json::Value)>) {
    let h = &merged.header;
    let facts = super::sweep::run_facts(1, t0.elapsed().as_secs_f64(), 0);
    let extra = vec![
        (
            "merged_from",
            serde_json::json!(dirs
                .iter()
                .map(|d| d.display().to_string())
                .collect::<Vec<_>>()),
        ),
        ("shards", serde_json::json!(h.shard.count)),
        (items, serde_json::json!(h.total)),
        (
            "shard_wall_time_s",
            serde_json::json!(merged.shard_wall_time_s),
        ),
    ];
    (facts, extra)
}
