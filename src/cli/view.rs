//! `printwatt view`: the live 3-D view ([`printwatt::view`]) of an optimisation job, with the
//! robot, path and options of `printwatt optimise`.

use super::optimise::OptimiseArgs;
use anyhow::{bail, Context, Result};
use std::net::SocketAddr;

/// `printwatt view` arguments: those of `optimise` (the page's optimise button runs that job;
/// `--at` is the placement shown first, `--run RUN` shows the answer of a run directory of
/// `optimise` or `sweep` (a directory, or a name under --results-dir) and writes nothing,
/// `--export DIR` is where the export button writes) and where the server listens.
#[derive(clap::Args, Debug)]
pub struct ViewArgs {
    /// Robot, path, grid, feasibility and search options, as `printwatt optimise`.
    #[command(flatten)]
    pub o: OptimiseArgs,
    /// Port on 127.0.0.1 (0: a free port; the URL is printed).
    #[arg(long, default_value_t = 8765)]
    pub port: u16,
    /// Listen on this address (`IP:PORT`) instead of 127.0.0.1; every request must then carry
    /// the random token printed in the URL.
    #[arg(long, value_name = "ADDR", conflicts_with = "port")]
    pub listen: Option<SocketAddr>,
    /// With --run of a `stations` run: show station K (1-based): the part at that station's
    /// placement and only the moves it prints (give the run's --robot and --path).
    #[arg(long, value_name = "K", requires = "run", conflicts_with = "case")]
    pub station: Option<usize>,
    /// With --run of a `study` run: show case CASE (its index, or robot/cell/path) with the
    /// case's robot, tool, path, cell and options, starting at its answer.
    #[arg(long, value_name = "CASE", requires = "run")]
    pub case: Option<String>,
}

/// [`ViewArgs`] as a parser of their own (a study case's arguments are parsed again).
#[derive(clap::Parser, Debug)]
#[command(name = "printwatt view")]
struct Reparse {
    #[command(flatten)]
    v: ViewArgs,
}

/// The view of case `case` of the study run `dir`: the case's robot, tool, path, cell and
/// options, with the front end's own server and export arguments, starting at its answer.
fn case_view(a: &ViewArgs, dir: &std::path::Path, case: &str) -> Result<ViewArgs> {
    let c = printwatt::view::case_of_run(dir, case)?;
    let mut argv: Vec<String> = vec!["view".into(), format!("--robot={}", c.robot)];
    if let Some(t) = &c.tool {
        argv.push(format!("--tool={t}"));
    }
    argv.push(format!("--path={}", c.path));
    for (k, v) in &c.cell {
        argv.push(format!("--{k}={v}"));
    }
    argv.extend(c.options.iter().cloned());
    match a.listen {
        Some(l) => argv.push(format!("--listen={l}")),
        None => argv.push(format!("--port={}", a.port)),
    }
    if let Some(e) = &a.o.export {
        argv.push(format!("--export={}", e.display()));
    }
    if a.o.p.out.force {
        argv.push("--force".into());
    }
    if let Some(p) = c.placement {
        argv.push(format!(
            "--at={},{},{},{}",
            p.x,
            p.y,
            p.z,
            p.yaw.to_degrees()
        ));
        argv.push(format!("--spin={}", p.nozzle_spin.to_degrees()));
    }
    let parsed = <Reparse as clap::Parser>::try_parse_from(&argv)
        .with_context(|| format!("case {} ({}): its options", c.index, c.name))?;
    eprintln!(
        "case {} ({}){}",
        c.index,
        c.name,
        if c.placement.is_none() {
            ": the case has no answer; the view starts at the grid's centre"
        } else {
            ""
        }
    );
    Ok(parsed.v)
}

/// Run `printwatt view`: bind, evaluate the grid for the energy map, print the URL, serve
/// until interrupted.
pub fn run(a: ViewArgs) -> Result<()> {
    refuse_options(&a)?;
    let mut o = a.o.clone();
    // --at is where the page starts, else the answer of the run named by --run; the
    // optimisation's grid is the one given, or the default.
    let mut start = o.p.at.one()?;
    let mut station = None;
    if let Some(run) = o.p.run.take() {
        let dir = if std::path::Path::new(&run).is_dir() {
            std::path::PathBuf::from(&run)
        } else {
            o.p.results_dir.join(&run)
        };
        if let Some(case) = &a.case {
            let v =
                case_view(&a, &dir, case).with_context(|| format!("--run {run} --case {case}"))?;
            return self::run(v);
        }
        station = start_from_run(&a, &dir, &run, &mut start)?;
    }
    o.p.at = super::args::AtArg {
        at: None,
        spin: None,
    };
    let mut l = o.p.load()?;
    if let Some((k, s)) = &station {
        station_path(*k, s, &mut l)?;
    }
    let job = o.config(l)?;
    if let Some(d) = &o.export {
        super::args::check_out_dir(d).context("--export")?;
    }
    let cfg = printwatt::view::ViewConfig {
        job,
        start,
        export_dir: o.export.clone(),
        force: o.p.out.force,
        hints: printwatt::view::ViewHints {
            export_dir: "start the view with --export DIR".into(),
            force: "--force".into(),
        },
    };
    let addr = a
        .listen
        .unwrap_or_else(|| SocketAddr::from(([127, 0, 0, 1], a.port)));
    let bound = printwatt::view::server::bind(addr, a.listen.is_some())?;
    let state = printwatt::view::ViewState::new(&cfg)?;
    outln!("printwatt view: {}", bound.url());
    super::flush_stdout()?;
    eprintln!(
        "serving {} on {}; Ctrl-C stops",
        cfg.job.robot.name(),
        bound.addr
    );
    printwatt::view::server::serve(bound, &state)?;
    Ok(())
}

/// Refuse the `optimise` options the view does not take: shards, the uncertainty study, a
/// report or JSON.
fn refuse_options(a: &ViewArgs) -> Result<()> {
    if a.o.shard.is_some() {
        bail!("--shard: the view runs no shard (use `printwatt optimise --shard`)");
    }
    if a.o.uncertainty.is_some() {
        bail!("--uncertainty: the view's optimise button runs no uncertainty study (use `printwatt optimise --uncertainty N`)");
    }
    if a.o.p.out.out.is_some() || a.o.p.out.json {
        bail!("--out/--json: the view writes no report and prints only its address (the page's export goes to --export DIR)");
    }
    Ok(())
}

/// Where the page starts with `--run DIR` (unless `--at` set `start`): the placement of
/// station `--station K` of a stations run, returned with the station, or the run's answer.
fn start_from_run(
    a: &ViewArgs,
    dir: &std::path::Path,
    run: &str,
    start: &mut Option<printwatt::frame::Placement>,
) -> Result<Option<(usize, printwatt::view::StationOfRun)>> {
    if let Some(k) = a.station {
        let s = printwatt::view::station_of_run(dir, k)
            .with_context(|| format!("--run {run} --station {k}"))?;
        if start.is_none() {
            *start = Some(s.placement);
        }
        return Ok(Some((k, s)));
    } else {
        let at = printwatt::view::placement_of_run(dir).with_context(|| format!("--run {run}"))?;
        if start.is_none() {
            *start = Some(at);
        }
    }
    Ok(None)
}

/// Cut the loaded path down to the moves station `k` prints (`s`: the station of the
/// stations run), refusing a path the run was not made for.
fn station_path(
    k: usize,
    s: &printwatt::view::StationOfRun,
    l: &mut super::sweep::Loaded,
) -> Result<()> {
    let [first, last] = s.moves;
    let file = l.path_file.display().to_string();
    let name = l
        .path_file
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    if let Some(p) = s
        .path
        .as_deref()
        .filter(|p| !name.is_empty() && !p.contains(&name))
    {
        bail!("--station {k}: the stations run was made for the path {p}, not {file}; give its --path");
    }
    if last >= l.path.moves.len() {
        bail!(
            "--station {k}: the station prints moves {first}..={last}, but {file} has {} moves; give the run's --path",
            l.path.moves.len()
        );
    }
    l.path = printwatt::stations::sub_path(&l.path, first, last);
    eprintln!(
        "station {k} of {}: moves {first}..={last} of {file}",
        s.stations
    );
    Ok(())
}
