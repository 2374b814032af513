//! `printwatt inspect FILE`: how a toolpath was read — format, units, moves, print and travel
//! length, bounding box, layers, commanded speeds, the time at those speeds, the reader's
//! warnings.

use super::args;
use anyhow::{bail, Context, Result};
use printwatt::toolpath::inspect::{inspect, Inspection, SpeedRange};
use std::path::PathBuf;

/// `printwatt inspect`
#[derive(clap::Args, Debug)]
pub struct InspectArgs {
    /// The toolpath to inspect: G-code, a CSV of points or an ABB RAPID module. (Robots are
    /// listed and described by `printwatt robots`.)
    #[arg(value_name = "FILE")]
    pub file: PathBuf,
    /// Length unit of a CSV path's x, y, z columns written without one (`x`, not `x[mm]`);
    /// unlabelled speeds follow it per second. Without it such a file is read in mm, with a
    /// warning that mm was assumed. A unit in the header wins. G-code and RAPID state their
    /// own units and refuse it.
    #[arg(long, value_name = "mm|m")]
    pub path_units: Option<String>,
    /// RAPID: the procedure to read as the entry instead of `main`, for a module whose main
    /// chooses its path at run time (an IF on an input). Other formats refuse it.
    #[arg(long = "proc", value_name = "NAME")]
    pub proc_name: Option<String>,
    /// Factor applied to the path's geometry after its units are read (points, arcs; not
    /// speeds).
    #[arg(long, value_name = "FACTOR", default_value_t = 1.0)]
    pub scale: f64,
    /// Corner blend radius for G-code and CSV moves that give none, mm (RAPID zones are read
    /// from the file).
    #[arg(long, value_name = "MM", default_value_t = 5.0)]
    pub zone: f64,
    /// Print the inspection as JSON (shape: docs/json.md).
    #[arg(long)]
    pub json: bool,
}

/// Run `printwatt inspect`.
pub fn run(a: InspectArgs) -> Result<()> {
    let f = &a.file;
    let ext = f
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    if f.is_dir() || matches!(ext.as_str(), "urdf" | "toml") {
        bail!(
            "{}: a robot, not a toolpath: `printwatt inspect` reads toolpaths (G-code, CSV of \
             points, RAPID); robots are described by `printwatt robots` (`--dir DIR` for a \
             directory of robots)",
            f.display()
        );
    }
    let path = args::PathArg {
        path: Some(f.clone()),
        path_units: a.path_units.clone(),
        proc_name: a.proc_name.clone(),
        scale: a.scale,
    };
    let timing = args::TimingArgs {
        zone: a.zone,
        period: 4.0,
        accel: 1.0,
        jerk: 10.0,
    };
    let opts = path.read_options(&timing)?;
    let tp = printwatt::toolpath::load(f, &opts)
        .map_err(super::proc_hint)
        .with_context(|| format!("loading path {}", f.display()))?;
    let ins = inspect(&tp, f, &opts);
    if a.json {
        super::note_warnings(&tp.source, &tp.warnings);
        return super::print_json(&ins);
    }
    text(&ins)
}

/// Speeds in m/s and mm/s.
fn speeds(r: &Option<SpeedRange>) -> String {
    match r {
        None => "none".into(),
        Some(r) if r.min_m_s == r.max_m_s => {
            format!("{:.4} m/s ({:.1} mm/s)", r.min_m_s, r.min_m_s * 1e3)
        }
        Some(r) => format!(
            "{:.4} to {:.4} m/s ({:.1} to {:.1} mm/s)",
            r.min_m_s,
            r.max_m_s,
            r.min_m_s * 1e3,
            r.max_m_s * 1e3
        ),
    }
}

fn xyz(v: &[f64; 3]) -> String {
    format!("({:.4}, {:.4}, {:.4}) m", v[0], v[1], v[2])
}

/// One fact per line; SI units stated.
fn text(i: &Inspection) -> Result<()> {
    outln!("file                {}", i.file);
    outln!("format              {}", i.format.name());
    outln!("units               {}", i.units);
    outln!(
        "mm assumed          {}",
        if i.mm_assumed { "yes" } else { "no" }
    );
    outln!("scale               {}", i.scale);
    outln!("start               {}", xyz(&i.start_m));
    outln!(
        "moves               {} ({} print, {} travel; {} arcs)",
        i.moves,
        i.print_moves,
        i.travel_moves,
        i.arc_moves
    );
    match (i.first_line, i.last_line) {
        (Some(a), Some(b)) => outln!("source lines        {a} to {b} (first and last move)"),
        _ => outln!("source lines        none (no moves)"),
    }
    outln!("print length        {:.4} m", i.print_length_m);
    outln!("travel length       {:.4} m", i.travel_length_m);
    match &i.bounding_box {
        Some(b) => {
            outln!("bounding box min    {}", xyz(&b.min_m));
            outln!("bounding box max    {}", xyz(&b.max_m));
            outln!(
                "bounding box size   {:.4} x {:.4} x {:.4} m (diagonal {:.4} m)",
                b.size_m[0],
                b.size_m[1],
                b.size_m[2],
                b.diagonal_m
            );
        }
        None => outln!("bounding box        none (no moves)"),
    }
    let from = if i.layers_from == "markers" {
        "the slicer's layer markers"
    } else {
        "distinct z of print moves"
    };
    outln!("layers              {} ({from})", i.layers);
    if !i.features.is_empty() {
        outln!("features            {}", i.features.join(", "));
    }
    outln!("print speed         {}", speeds(&i.print_speed));
    outln!("travel speed        {}", speeds(&i.travel_speed));
    outln!("dwells              {} ({:.3} s)", i.dwells, i.dwell_s);
    outln!(
        "time at speed       {:.3} s (every move at its commanded speed, plus dwells; no acceleration)",
        i.duration_at_commanded_speed_s
    );
    if i.marks.is_empty() {
        outln!("marks               none");
    } else {
        outln!("marks               {}", i.marks.join(", "));
    }
    if !i.procedures.is_empty() {
        outln!(
            "procedures          {} (read from: {})",
            i.procedures.len(),
            i.entry_procedure.as_deref().unwrap_or("none")
        );
        for p in &i.procedures {
            let read = if i.entry_procedure.as_deref() == Some(p.name.as_str()) {
                "  <- read"
            } else {
                ""
            };
            outln!("  {:<18}line {}, {} moves{read}", p.name, p.line, p.moves);
        }
    }
    outln!("reader warnings     {}", i.reader_warnings.len());
    for w in &i.reader_warnings {
        outln!("  {}", printwatt::error::clip(w));
    }
    Ok(())
}
