//! How a toolpath was read: its format and units, the moves, the print and travel length,
//! the bounding box, the layers, the commanded speeds, the time at those speeds and the
//! reader's warnings (skipped instructions, ignored codes, assumptions). What
//! `printwatt inspect FILE` prints.
//!
//! Print and travel are the reader's own flags ([`Move::print`]): extrusion (E words or the
//! extrusion M-codes) in G-code, the `print` column in CSV, every move in RAPID. Layers are
//! the slicer's layer markers where the G-code has them, else the distinct z levels of the
//! print moves' end points ([`Toolpath::layers`]).

use std::path::Path;

use serde::Serialize;

use super::{Move, MoveKind, Procedure, ReadOptions, Toolpath};

/// The file format, from the extension as [`super::load`] chooses its reader.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Format {
    /// G-code (`.gcode`, `.nc`, `.ngc`, `.g`).
    Gcode,
    /// CSV of points (`.csv`).
    Csv,
    /// ABB RAPID module (`.mod`, `.prg`, `.modx`).
    Rapid,
    /// Another extension (the reader refuses it; kept for paths built in code).
    Other,
}

impl Format {
    /// The format of `file` by its extension.
    pub fn of(file: &Path) -> Format {
        let ext = file
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .unwrap_or_default();
        match ext.as_str() {
            "gcode" | "nc" | "ngc" | "g" => Format::Gcode,
            "csv" => Format::Csv,
            "mod" | "prg" | "modx" => Format::Rapid,
            _ => Format::Other,
        }
    }

    /// A human name of the format.
    pub fn name(self) -> &'static str {
        match self {
            Format::Gcode => "G-code",
            Format::Csv => "CSV of points",
            Format::Rapid => "ABB RAPID module",
            Format::Other => "points built in code",
        }
    }
}

/// Smallest and largest of a set of commanded speeds, m/s.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SpeedRange {
    /// Slowest, m/s.
    pub min_m_s: f64,
    /// Fastest, m/s.
    pub max_m_s: f64,
}

/// Axis-aligned bounding box of the path, m.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BoundingBox {
    /// Lower corner `[x, y, z]`, m.
    pub min_m: [f64; 3],
    /// Upper corner `[x, y, z]`, m.
    pub max_m: [f64; 3],
    /// Edge lengths `[x, y, z]`, m.
    pub size_m: [f64; 3],
    /// Diagonal, m.
    pub diagonal_m: f64,
}

/// How a toolpath was read. Lengths in m, speeds in m/s, times in s.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Inspection {
    /// The file as named.
    pub file: String,
    /// The reader used.
    pub format: Format,
    /// How the coordinates were read (unit and where it came from).
    pub units: String,
    /// Whether millimetres were assumed because a CSV header states no unit.
    pub mm_assumed: bool,
    /// Factor applied to the geometry after reading (1: as read).
    pub scale: f64,
    /// Start point `[x, y, z]`, m.
    pub start_m: [f64; 3],
    /// Number of moves.
    pub moves: usize,
    /// Moves that extrude.
    pub print_moves: usize,
    /// Moves that do not.
    pub travel_moves: usize,
    /// Arcs (and helices) among the moves.
    pub arc_moves: usize,
    /// Length of the extruding moves, m.
    pub print_length_m: f64,
    /// Length of the other moves, m.
    pub travel_length_m: f64,
    /// Bounding box over every move (arcs included); `None` without moves.
    pub bounding_box: Option<BoundingBox>,
    /// Layers: the slicer's layer markers when the G-code has them, else the distinct z levels
    /// of the print moves' end points (see `layers_from`).
    pub layers: usize,
    /// Where `layers` comes from: `markers` (a slicer's `;LAYER:n`, `;LAYER_CHANGE` or
    /// `; CHANGE_LAYER` comments) or `z_levels`.
    pub layers_from: &'static str,
    /// The slicer's feature names (`;TYPE:` / `; FEATURE:` comments), each once, in order of
    /// first appearance; empty without such comments.
    pub features: Vec<String>,
    /// Commanded speeds of the print moves; `None` without print moves.
    pub print_speed: Option<SpeedRange>,
    /// Commanded speeds of the travel moves; `None` without travel moves.
    pub travel_speed: Option<SpeedRange>,
    /// Holds at rest (G-code `G4`), count.
    pub dwells: usize,
    /// Their total duration, s.
    pub dwell_s: f64,
    /// Every move at its commanded speed, plus the dwells, s: a lower bound of the print
    /// time (no acceleration, no corner slow-down, no joint limits).
    pub duration_at_commanded_speed_s: f64,
    /// Named points (`MARK` comments), in order.
    pub marks: Vec<String>,
    /// Source lines of the first and the last move.
    pub first_line: Option<usize>,
    /// Source line of the last move.
    pub last_line: Option<usize>,
    /// The reader's warnings (skipped instructions, ignored codes, assumptions), as written.
    pub reader_warnings: Vec<String>,
    /// RAPID: the module's procedures (name, line, move instructions in the body), in file
    /// order; empty for other formats.
    pub procedures: Vec<Procedure>,
    /// RAPID: the procedure the path was read from (`main` and its calls, the chosen entry,
    /// or the one procedure with moves); `None` for other formats.
    pub entry_procedure: Option<String>,
}

fn range<'a>(moves: impl Iterator<Item = &'a Move>) -> Option<SpeedRange> {
    moves.fold(None, |acc, m| {
        Some(match acc {
            None => SpeedRange {
                min_m_s: m.speed,
                max_m_s: m.speed,
            },
            Some(r) => SpeedRange {
                min_m_s: r.min_m_s.min(m.speed),
                max_m_s: r.max_m_s.max(m.speed),
            },
        })
    })
}

/// The units the coordinates of a file of `format` were read in, in words.
fn units_read(format: Format, mm_assumed: bool, opts: &ReadOptions) -> String {
    match format {
        Format::Gcode => {
            "the file's own: mm (G21) unless it says G20 (inch); F in mm/min (in/min under G20)"
                .to_string()
        }
        Format::Rapid => "mm, RAPID's unit; speeds in mm/s".to_string(),
        Format::Csv if mm_assumed => "mm (assumed: the header states no unit)".to_string(),
        Format::Csv => match opts.path_units {
            Some(u) => format!(
                "as stated in the header, else {} (the path units given)",
                u.symbol()
            ),
            None => "as stated in the header".to_string(),
        },
        Format::Other => "m".to_string(),
    }
}

/// How `tp` was read from `file` with the options `opts` (the ones given to
/// [`super::load`]): see [`Inspection`].
pub fn inspect(tp: &Toolpath, file: &Path, opts: &ReadOptions) -> Inspection {
    let format = Format::of(file);
    let mm_assumed = format == Format::Csv && tp.warnings.iter().any(|w| w.contains("mm assumed"));
    let units = units_read(format, mm_assumed, opts);
    let (mut print_length_m, mut travel_length_m, mut duration) = (0.0, 0.0, 0.0);
    for (s, m) in tp.segments() {
        let len = m.length(&s);
        if m.print {
            print_length_m += len;
        } else {
            travel_length_m += len;
        }
        duration += len / m.speed;
    }
    let dwell_s = tp.dwells.iter().fold(0.0, |t, d| t + d.seconds);
    let bounding_box = tp.bounding_box().map(|(lo, hi)| {
        let size = hi - lo;
        BoundingBox {
            min_m: [lo.x, lo.y, lo.z],
            max_m: [hi.x, hi.y, hi.z],
            size_m: [size.x, size.y, size.z],
            diagonal_m: size.norm(),
        }
    });
    let print_moves = tp.moves.iter().filter(|m| m.print).count();
    Inspection {
        file: file.display().to_string(),
        format,
        units,
        mm_assumed,
        scale: opts.scale,
        start_m: [tp.start.x, tp.start.y, tp.start.z],
        moves: tp.moves.len(),
        print_moves,
        travel_moves: tp.moves.len() - print_moves,
        arc_moves: tp
            .moves
            .iter()
            .filter(|m| matches!(m.kind, MoveKind::Arc { .. }))
            .count(),
        print_length_m,
        travel_length_m,
        bounding_box,
        layers: tp.layers(),
        layers_from: if tp.layer_starts.is_empty() {
            "z_levels"
        } else {
            "markers"
        },
        features: tp.features.iter().fold(Vec::new(), |mut v, f| {
            if !v.contains(&f.name) {
                v.push(f.name.clone());
            }
            v
        }),
        print_speed: range(tp.moves.iter().filter(|m| m.print)),
        travel_speed: range(tp.moves.iter().filter(|m| !m.print)),
        dwells: tp.dwells.len(),
        dwell_s,
        duration_at_commanded_speed_s: duration + dwell_s,
        marks: tp.marks.iter().map(|m| m.name.clone()).collect(),
        first_line: tp.moves.first().map(|m| m.line),
        last_line: tp.moves.last().map(|m| m.line),
        reader_warnings: tp.warnings.clone(),
        procedures: tp.procedures.clone(),
        entry_procedure: tp.entry.clone(),
    }
}
