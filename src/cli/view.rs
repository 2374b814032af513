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
}

/// Run `printwatt view`: bind, evaluate the grid for the energy map, print the URL, serve
/// until interrupted.
pub fn run(a: ViewArgs) -> Result<()> {
    if a.o.shard.is_some() {
        bail!("--shard: the view runs no shard (use `printwatt optimise --shard`)");
    }
    if a.o.uncertainty.is_some() {
        bail!("--uncertainty: the view's optimise button runs no uncertainty study (use `printwatt optimise --uncertainty N`)");
    }
    if a.o.p.out.out.is_some() || a.o.p.out.json {
        bail!("--out/--json: the view writes no report and prints only its address (the page's export goes to --export DIR)");
    }
    let mut o = a.o.clone();
    // --at is where the page starts, else the answer of the run named by --run; the
    // optimisation's grid is the one given, or the default.
    let mut start = o.p.at.one()?;
    if let Some(run) = o.p.run.take() {
        let dir = if std::path::Path::new(&run).is_dir() {
            std::path::PathBuf::from(&run)
        } else {
            o.p.results_dir.join(&run)
        };
        let at = printwatt::view::placement_of_run(&dir).with_context(|| format!("--run {run}"))?;
        if start.is_none() {
            start = Some(at);
        }
    }
    o.p.at = super::args::AtArg {
        at: None,
        spin: None,
    };
    let l = o.p.load()?;
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
