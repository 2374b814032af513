//! `printwatt study`: a design study, every path of a building on several robots and cells
//! (a study file, docs/study.md), each case optimised as `printwatt optimise` does, the answers
//! side by side in one directory. Splits into shards by case for a cluster (`--shard`), put
//! back together by `printwatt merge` bit for bit.

use super::optimise::OptimiseArgs;
use anyhow::{bail, Context, Result};
use clap::Parser;
use printwatt::campaign::study::{CaseResult, Study};
use printwatt::search::OptimiseConfig;
use std::io::IsTerminal;
use std::path::PathBuf;

/// `printwatt study` arguments.
#[derive(clap::Args, Debug, Clone)]
pub struct StudyArgs {
    /// Study file (TOML, docs/study.md): the robots, the cells (where the part may be placed),
    /// the paths, and the cases (default: every robot × cell × path).
    #[arg(value_name = "FILE")]
    pub study: PathBuf,
    /// Worker threads for each case's evaluations (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Run one shard of the cases, for a cluster run: `K/N` (shard K, 0-based, of N owns cases
    /// K, K+N, …), `auto` (index and count from a Slurm job array) or `auto/N` (Slurm, or a
    /// Kubernetes Indexed Job's JOB_COMPLETION_INDEX). Writes `<--out>/shard-K-of-N/`;
    /// `printwatt merge` puts the shards together into the study directory of a single run,
    /// bit for bit (docs/cluster.md).
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Parent directory of the default study directory `<DIR>/runs/study-<name>-<UTC time>`.
    #[arg(long, value_name = "DIR", default_value = "results")]
    pub results_dir: PathBuf,
    /// --out: the study directory (summary.json, study.csv, report.html, one report page per
    /// case, run.json).
    #[command(flatten)]
    pub out: super::args::OutputArgs,
}

/// Options a study's `options` lists may not hold: the study file says which robot, tool and
/// path each case runs, and the study command says where the output goes and how it runs.
const NOT_IN_A_STUDY: [&str; 12] = [
    "--robot",
    "--tool",
    "--path",
    "--out",
    "--run",
    "--results-dir",
    "--json",
    "--force",
    "--threads",
    "--shard",
    "--export",
    "--no-report",
];

/// The objective is set once for the whole study: energies of different objectives cannot be
/// compared.
const STUDY_LEVEL_ONLY: [&str; 1] = ["--objective"];

/// The job of a study in a normalised form (shards of one study agree on it): the study file
/// as named; its content and every file it names are hashed as inputs.
pub fn job_key(a: &StudyArgs) -> String {
    format!("study {}", a.study.display())
}

/// Refuse an option that a study's `options` list (`where_`: which entry) may not hold.
fn check_options(options: &[String], where_: &str, study_level: bool) -> Result<()> {
    for o in options {
        let flag = o.split('=').next().unwrap_or(o);
        if NOT_IN_A_STUDY.contains(&flag) {
            bail!("{where_}: `{o}` is not an option of a study case (the study file names each case's robot, tool and path; `printwatt study` says where the output goes)");
        }
        if !study_level && STUDY_LEVEL_ONLY.contains(&flag) {
            bail!("{where_}: `{o}` belongs in [study] options: every case minimises the same objective, or their energies could not be compared");
        }
    }
    Ok(())
}

/// Every case's `optimise` arguments, in case order: the robot, tool and path of the case,
/// the cell's placement options, then the options of the study, the robot, the cell and the
/// path, in that order (a later one wins where an option takes one value).
pub fn case_args(study: &Study, threads: Option<usize>) -> Result<Vec<OptimiseArgs>> {
    let f = study.file.display();
    check_options(&study.options, &format!("{f}: [study] options"), true)?;
    for r in &study.robots {
        check_options(
            &r.options,
            &format!("{f}: robot `{}` options", r.name),
            false,
        )?;
    }
    for c in &study.cells {
        check_options(
            &c.options,
            &format!("{f}: cell `{}` options", c.name),
            false,
        )?;
    }
    for p in &study.paths {
        check_options(
            &p.options,
            &format!("{f}: path `{}` options", p.name),
            false,
        )?;
    }
    study
        .cases
        .iter()
        .map(|c| {
            let (r, ce, p) = (
                &study.robots[c.robot],
                &study.cells[c.cell],
                &study.paths[c.path],
            );
            let mut v: Vec<String> = vec!["printwatt".into(), "optimise".into()];
            v.push(format!("--robot={}", r.robot.display()));
            if let Some(t) = &r.tool {
                v.push(format!("--tool={}", t.display()));
            }
            v.push(format!("--path={}", p.file.display()));
            for (k, val) in &ce.placement {
                v.push(format!("--{k}={val}"));
            }
            v.extend(study.options.iter().cloned());
            v.extend(r.options.iter().cloned());
            v.extend(ce.options.iter().cloned());
            v.extend(p.options.iter().cloned());
            v.push("--no-report".into());
            let cli = super::Cli::try_parse_from(&v).map_err(|e| {
                let text = e.render().to_string();
                anyhow::anyhow!(
                    "{f}: case {} ({}): its options do not parse: {}",
                    c.index,
                    study.case_name(c),
                    text.lines()
                        .next()
                        .unwrap_or("")
                        .trim_start_matches("error: ")
                )
            })?;
            let super::Command::Optimise(mut oa) = cli.command else {
                bail!("case {}: not an optimise command line", c.index);
            };
            oa.p.threads = threads;
            Ok(oa)
        })
        .collect()
}

/// Load every case (robot, tool, path, options) before any work, so that a typo in the last
/// case fails the study at once; returns every input file (the study file, then each case's
/// robot files, path, set and tool).
fn check_cases(study: &Study, args: &[OptimiseArgs]) -> Result<printwatt::output::Inputs> {
    let mut inputs = printwatt::output::Inputs::new();
    inputs.add(&study.file);
    let mut seen = std::collections::BTreeSet::new();
    for (c, a) in study.cases.iter().zip(args) {
        let case = || format!("case {} ({})", c.index, study.case_name(c));
        if let Some(b) = &a.baseline {
            super::sweep::parse_placement(b)
                .context("--baseline")
                .with_context(case)?;
        }
        let l = a.p.load().with_context(case)?;
        for p in a.p.inputs(&l).paths() {
            if seen.insert(p.clone()) {
                inputs.add(p);
            }
        }
        // Every option parsed before any work, as the inputs are loaded.
        a.config(l)
            .with_context(|| format!("case {} ({})", c.index, study.case_name(c)))?;
    }
    Ok(inputs)
}

/// The job of a case: its arguments with the robot and path loaded.
fn case_config(a: &OptimiseArgs) -> Result<OptimiseConfig> {
    a.config(a.p.load()?)
}

/// A case's answer in a few lines: the placement and energy, or why there is none (the
/// reason's lines joined), then its notes, one per line.
fn case_line(study: &Study, k: usize, r: &CaseResult, secs: f64) -> String {
    let c = &study.cases[k];
    let head = format!(
        "case {} of {} ({}):",
        k + 1,
        study.cases.len(),
        study.case_name(c)
    );
    match &r.outcome {
        Ok(b) => {
            let mut s = format!(
                "{head} {:.1} J ({}) at x = {:.3} m, y = {:.3} m, z = {:.3} m, yaw = {:.1}°; {:.2} s",
                b.feasible.energy_j,
                r.objective,
                b.placement[0],
                b.placement[1],
                b.placement[2],
                b.placement[3].to_degrees(),
                secs
            );
            for n in &b.notes {
                s.push_str(&format!("\n  note: {n}"));
            }
            s
        }
        Err(why) => format!(
            "{head} no feasible placement: {}",
            why.split_whitespace().collect::<Vec<_>>().join(" ")
        ),
    }
}

/// Run the cases `indices` (in order), each on `pool` ([`printwatt::campaign::study::run`]),
/// writing each answered case's report page into `rd` (when given) as soon as it is made; a
/// line per case on stderr unless `quiet`.
fn run_cases(
    study: &Study,
    args: &[OptimiseArgs],
    indices: &[usize],
    pool: &rayon::ThreadPool,
    mut rd: Option<&mut printwatt::output::RunDir>,
    quiet: bool,
) -> Result<Vec<CaseResult>> {
    let bars = super::optimise::Bars::new(std::io::stderr().is_terminal(), false);
    let config_of = |c: &printwatt::campaign::study::Case| {
        case_config(&args[c.index]).map_err(|e| printwatt::Error::Invalid(super::error_text(&e)))
    };
    let mut done = |c: &printwatt::campaign::study::Case,
                    r: &CaseResult,
                    page: Option<String>,
                    secs: f64|
     -> printwatt::Result<()> {
        if let (Some(page), Some(rd)) = (page, rd.as_deref_mut()) {
            rd.write(&study.case_file(c), page.as_bytes())?;
        }
        if !quiet {
            eprintln!("{}", case_line(study, c.index, r, secs));
        }
        Ok(())
    };
    Ok(pool.install(|| {
        printwatt::campaign::study::run(study, indices, &config_of, &bars, &mut done)
    })?)
}

/// The study file: as given, or, for a relative path that is not there, the one shipped in the
/// source tree (`studies/example.toml` from any directory), as `--path paths/…` resolves.
pub fn study_file(a: &StudyArgs) -> PathBuf {
    if a.study.is_relative() && !a.study.exists() {
        let shipped = super::sweep::shipped(&a.study.to_string_lossy());
        if shipped.exists() {
            return shipped;
        }
    }
    a.study.clone()
}

/// `printwatt study`.
pub fn run(a: StudyArgs) -> Result<()> {
    let study = Study::read(&study_file(&a))?;
    let args = case_args(&study, a.threads)?;
    let inputs = check_cases(&study, &args)?;
    let pool = match args.first() {
        Some(c) => c.p.pool()?,
        None => bail!("the study has no case"),
    };
    if let Some(spec) = &a.shard {
        return run_shard(&a, &study, &args, &inputs, &pool, spec);
    }
    // A JSON run writes nothing but the JSON unless --out is given.
    let dir = match &a.out.out {
        Some(d) => Some(d.clone()),
        None if a.out.json => None,
        None => Some(super::sweep::fresh_run_dir(&a.results_dir, |now| {
            format!("study-{}-{}", study.name, printwatt::output::utc_stamp(now))
        })),
    };
    // Taken before the work: an occupied directory or one that is an input fails now.
    let mut rd = match &dir {
        Some(dir) => Some(printwatt::output::RunDir::begin_at(
            dir,
            &inputs,
            printwatt::output::Existing::Force(a.out.force),
        )?),
        None => None,
    };
    let t0 = std::time::Instant::now();
    let all: Vec<usize> = (0..study.cases.len()).collect();
    let results = run_cases(&study, &args, &all, &pool, rd.as_mut(), a.out.json)?;
    let secs = t0.elapsed().as_secs_f64();
    let evals: usize = results.iter().map(|r| r.evaluations).sum();
    let facts = super::sweep::run_facts(pool.current_num_threads(), secs, evals);
    finish(&study, results, rd, (facts, Vec::new()), a.out.json)
}

/// `printwatt study --shard`: this shard's cases, written as `<--out>/shard-K-of-N/`.
fn run_shard(
    a: &StudyArgs,
    study: &Study,
    args: &[OptimiseArgs],
    inputs: &printwatt::output::Inputs,
    pool: &rayon::ThreadPool,
    spec: &str,
) -> Result<()> {
    use printwatt::campaign::shard::{self, Shard};
    let (sh, source) = Shard::parse(spec, &|k| std::env::var(k).ok())?;
    let Some(parent) = a.out.out.clone() else {
        bail!("--shard writes a shard directory: give --out DIR (every shard of the study writes DIR/shard-K-of-N/, and `printwatt merge DIR` puts them together)");
    };
    let mut rd = printwatt::output::RunDir::begin_at(
        &parent.join(sh.dir_name()),
        inputs,
        printwatt::output::Existing::Force(a.out.force),
    )?;
    let idx = sh.indices(study.cases.len());
    let t0 = std::time::Instant::now();
    // The shard directory holds its cases' report pages beside its rows.
    let results = run_cases(study, args, &idx, pool, Some(&mut rd), a.out.json)?;
    let secs = t0.elapsed().as_secs_f64();
    let answered = results.iter().filter(|r| r.outcome.is_ok()).count();
    let rows: Vec<(usize, CaseResult)> = idx.into_iter().zip(results).collect();
    let bytes = shard::encode_cases(&rows)?;
    let done = format!(
        "{} of {} cases optimised ({answered} with a feasible placement) in {secs:.2} s",
        rows.len(),
        study.cases.len()
    );
    super::sweep::write_shard(
        rd,
        super::sweep::ShardOut {
            kind: shard::KIND_STUDY,
            shard: sh,
            source,
            total: study.cases.len(),
            rows: rows.len(),
            job: job_key(a),
            inputs: super::sweep::hash_inputs(inputs)?,
            bytes,
            wall_time_s: secs,
        },
        a.out.json,
        &done,
    )
}

/// Merge the shards of `printwatt study --shard …`: the study file is read again (from the
/// directory the shards ran in; unchanged, as every input), the cases' results come from the
/// shards and their report pages from the shard directories (`shard_dirs`: shard index →
/// directory; each page checked against the SHA-256 its case recorded), and the study
/// directory is the one a single run writes.
#[allow(clippy::too_many_arguments)]
pub fn merge(
    a: StudyArgs,
    h: &printwatt::campaign::shard::ShardHeader,
    results: Vec<CaseResult>,
    shard_dirs: &[(usize, PathBuf)],
    out: Option<PathBuf>,
    o: &super::args::OutputArgs,
    facts: (serde_json::Value, Vec<(&'static str, serde_json::Value)>),
    here: &std::path::Path,
) -> Result<()> {
    let Some(out) = out else {
        bail!("merging a study writes its study directory: give --out DIR");
    };
    if job_key(&a) != h.job {
        bail!("this printwatt reads the shards' command line as a different job than the one they ran");
    }
    let study = Study::read(&study_file(&a))?;
    if study.cases.len() != results.len() {
        bail!(
            "the study file has {} cases, the shards hold {}",
            study.cases.len(),
            results.len()
        );
    }
    let args = case_args(&study, a.threads)?;
    let inputs = check_cases(&study, &args)?;
    super::merge::unchanged_inputs(h, &super::sweep::hash_inputs(&inputs)?)?;
    let mut rd = printwatt::output::RunDir::begin_at(
        &out,
        &inputs,
        printwatt::output::Existing::Force(o.force),
    )?;
    for (c, r) in study.cases.iter().zip(&results) {
        let Some(sha) = &r.report_sha256 else {
            continue;
        };
        let owner = c.index % h.shard.count;
        let Some((_, dir)) = shard_dirs.iter().find(|(i, _)| *i == owner) else {
            bail!(
                "no directory for shard {owner}, which holds case {}",
                c.index
            );
        };
        let f = dir.join(study.case_file(c));
        let page = std::fs::read(&f).with_context(|| {
            format!(
                "case {} ({}): its report page {}",
                c.index,
                study.case_name(c),
                f.display()
            )
        })?;
        if &printwatt::output::sha256_hex(&page) != sha {
            bail!(
                "{}: damaged or replaced (its SHA-256 is not the one case {} recorded)",
                f.display(),
                c.index
            );
        }
        rd.write(&study.case_file(c), &page)?;
    }
    std::env::set_current_dir(here).ok();
    finish(&study, results, Some(rd), facts, o.json)
}

/// Finish the study directory (shared by a single run and `merge`; each answered case's report
/// page is in it already): `summary.json`, `study.csv`, `report.html` and `run.json`; then the
/// answer on the terminal, or the summary as JSON. Without `rd` (a JSON run without --out)
/// nothing is written.
pub fn finish(
    study: &Study,
    results: Vec<CaseResult>,
    rd: Option<printwatt::output::RunDir>,
    facts: (serde_json::Value, Vec<(&str, serde_json::Value)>),
    json: bool,
) -> Result<()> {
    let summary = study.summary(&results)?;
    let summary_text = printwatt::output::json_text(&summary)?;
    let mut dir = None;
    if let Some(mut rd) = rd {
        rd.write("summary.json", summary_text.as_bytes())?;
        rd.write("study.csv", study.csv(&results)?.as_bytes())?;
        rd.write(
            "report.html",
            printwatt::report::study::html(study, &results)?.as_bytes(),
        )?;
        super::sweep::write_run_facts(&mut rd, facts.0, &facts.1)?;
        dir = Some(rd.commit()?);
    }
    if json {
        return super::print_json_text(&summary_text);
    }
    print_tables(study, &results)?;
    if let Some(dir) = dir {
        outln!("report: {}", dir.join("report.html").display());
    }
    Ok(())
}

/// Print the study's answer: per path the cheapest robot and cell and the next cheapest, then
/// per robot and cell the paths it prints and their energy.
fn print_tables(study: &Study, results: &[CaseResult]) -> Result<()> {
    let t = study.tables(results)?;
    let objective = results.first().map_or("", |r| r.objective.as_str());
    outln!(
        "{:<16} {:<16} {:<16} {:>12}  next cheapest",
        "path",
        "robot",
        "cell",
        "energy[J]"
    );
    for p in &t.paths {
        match (&p.best, p.energy_j) {
            (Some((r, c)), Some(e)) => outln!(
                "{:<16} {:<16} {:<16} {:>12.1}  {}",
                p.path,
                r,
                c,
                e,
                p.runner_up.map_or("-".into(), |(i, dj, pct)| {
                    let k = &study.cases[i];
                    format!(
                        "{} / {}: +{dj:.1} J (+{pct:.1} %)",
                        study.robots[k.robot].name, study.cells[k.cell].name
                    )
                })
            ),
            _ => outln!(
                "{:<16} {:<16} {:<16} {:>12}  no robot and cell of the study prints it",
                p.path,
                "-",
                "-",
                "-"
            ),
        }
    }
    for c in &t.combinations {
        if c.feasible == c.paths {
            outln!(
                "{} / {}: every path ({}), {:.1} J ({objective}), print time {:.1} s",
                c.robot,
                c.cell,
                c.paths,
                c.energy_j,
                c.duration_s
            );
        } else {
            outln!(
                "{} / {}: {} of {} paths ({:.1} J); no feasible placement for {}",
                c.robot,
                c.cell,
                c.feasible,
                c.paths,
                c.energy_j,
                c.infeasible.join(", ")
            );
        }
    }
    Ok(())
}
