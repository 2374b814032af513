//! Toolpaths: the path the nozzle follows, in its own part frame, read from the formats 3DCP
//! teams have (G-code, CSV of points, ABB RAPID).
//!
//! Units: SI inside (m, rad, m/s). Millimetres, inches, degrees and feed rates (mm/min, mm/s,
//! in/min) are converted in the readers of this module and nowhere else.
//!
//! The part frame is right-handed with +z up (against gravity); the nozzle points down along
//! −z. A [`Placement`] maps the part frame into the robot base frame.
//!
//! Limitations (all readers): orientations are not kept (the nozzle is assumed vertical; RAPID
//! quaternions are read and dropped); only the TCP position, speed, blend zone and extrusion
//! state of each move are kept.

mod csv;
mod gcode;
pub mod inspect;
mod rapid;
pub mod repeat;

use std::path::Path;

use crate::error::{read_text, Error, Result};
use crate::math::{rot_axis, V3};

pub use self::csv::{parse_csv, parse_placements};
/// The placement value lives in [`crate::frame`]; re-exported here for code that
/// names it beside the readers.
pub use crate::frame::{NamedPlacement, Placement, PlacementParseError};

pub use self::gcode::parse_gcode;
pub use self::rapid::{
    parse_rapid, read_program, read_program_entry, RapidProgram, RapidTarget, MAX_CALL_DEPTH,
};

/// Corner blending at the end of a move.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Zone {
    /// Stop exactly at the end point (RAPID `fine`, G-code `G61`/`G9`).
    Fine,
    /// Blend the corner within this radius around the end point, m (RAPID `z10` = 0.010 m).
    Blend(f64),
}

impl Zone {
    /// Blend radius in m; 0 for [`Zone::Fine`].
    pub fn radius(&self) -> f64 {
        match *self {
            Zone::Fine => 0.0,
            Zone::Blend(r) => r,
        }
    }
}

/// Geometry of one move.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MoveKind {
    /// Straight line from the previous end point to [`Move::end`].
    Line,
    /// Circular (or helical) arc from the previous end point to [`Move::end`].
    ///
    /// Point at fraction `u ∈ [0, 1]` of the move, with `p0` the start point:
    /// `centre + R(normal, u·sweep)(p0 − centre) + normal·(u·axial)`, `R` a right-handed
    /// rotation. The motion is counter-clockwise about `normal` (G17: G3 has `normal = +z`,
    /// G2 has `normal = −z`); `sweep > 0`.
    Arc {
        /// Centre of the circle, in the plane of the start point, m.
        centre: V3,
        /// Unit axis of the circle; the motion turns positively about it.
        normal: V3,
        /// Radius, m.
        radius: f64,
        /// Swept angle, rad, in (0, 2π] (2π = full circle).
        sweep: f64,
        /// Helical rise along `normal` over the whole move, m (0 for a planar arc).
        axial: f64,
    },
}

/// One move of a toolpath: from the end of the previous move (or [`Toolpath::start`]) to `end`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Move {
    /// Line or arc.
    pub kind: MoveKind,
    /// End point in the part frame, m.
    pub end: V3,
    /// Commanded TCP speed, m/s (> 0).
    pub speed: f64,
    /// Corner blend at the end of the move.
    pub zone: Zone,
    /// `true` when extruding, `false` for travel.
    pub print: bool,
    /// 1-based line of the source file that commanded this move.
    pub line: usize,
}

impl Move {
    /// Length of the move starting at `start` (m).
    pub fn length(&self, start: &V3) -> f64 {
        match self.kind {
            MoveKind::Line => (self.end - start).norm(),
            MoveKind::Arc {
                radius,
                sweep,
                axial,
                ..
            } => (radius * sweep).hypot(axial),
        }
    }

    /// Point at fraction `u ∈ [0, 1]` of the arc length of the move starting at `start` (m).
    /// Exact for lines and arcs (arcs and helices have constant speed in the angle).
    pub fn point_at(&self, start: &V3, u: f64) -> V3 {
        let u = if u.is_nan() { 0.0 } else { u.clamp(0.0, 1.0) };
        if u >= 1.0 {
            return self.end;
        }
        match self.kind {
            MoveKind::Line => start + (self.end - start) * u,
            MoveKind::Arc {
                centre,
                normal,
                sweep,
                axial,
                ..
            } => centre + rot_axis(&normal, sweep * u) * (start - centre) + normal * (axial * u),
        }
    }
}

/// A named point on the path (from `; MARK name` comments), e.g. seed 000's `Ps`, `Pm`, `Pe`.
#[derive(Clone, Debug, PartialEq)]
pub struct Mark {
    /// Name as written after `MARK`.
    pub name: String,
    /// Position in the part frame, m.
    pub point: V3,
    /// Arc length from the start of the path, m.
    pub s: f64,
}

/// One sample of [`Toolpath::sample`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathSample {
    /// Position in the part frame, m.
    pub p: V3,
    /// Arc length from the start of the path, m.
    pub s: f64,
    /// Index of the move this sample lies on (0 for the start point).
    pub move_index: usize,
    /// Whether that move extrudes.
    pub print: bool,
}

/// A toolpath in its part frame (m, m/s).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Toolpath {
    /// Where the source came from (file name), for messages.
    pub source: String,
    /// Start point, m.
    pub start: V3,
    /// The moves, in order.
    pub moves: Vec<Move>,
    /// Named points (`MARK` comments), in order of appearance.
    pub marks: Vec<Mark>,
    /// Non-fatal notes from the reader (ignored codes, assumptions). The library never prints.
    pub warnings: Vec<String>,
    /// Timed holds at rest (G-code `G4`), in order.
    pub dwells: Vec<Dwell>,
    /// The procedures of a RAPID module, in file order (empty for other formats).
    pub procedures: Vec<Procedure>,
    /// The RAPID procedure the path was read from (`main`, the chosen entry, or the one
    /// procedure with moves); `None` for other formats.
    pub entry: Option<String>,
    /// Layers as a slicer marked them (G-code `;LAYER:n` from Cura, `;LAYER_CHANGE` from
    /// PrusaSlicer, `; CHANGE_LAYER` from Bambu Studio): the index of the first move after
    /// each marker, in order (a layer without moves repeats the next index). Empty when the
    /// file has no markers. See [`Toolpath::layer_of`].
    pub layer_starts: Vec<usize>,
    /// Feature boundaries a slicer wrote (`;TYPE:WALL-OUTER`, `; FEATURE: Outer wall`), in
    /// order: where the kind of extrusion changes.
    pub features: Vec<Feature>,
}

/// Where a slicer's feature (`;TYPE:` / `; FEATURE:` comment) starts.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Feature {
    /// Index of the first move after the comment.
    pub first_move: usize,
    /// The feature as written (`WALL-OUTER`, `Perimeter`, `Outer wall`, …).
    pub name: String,
}

/// A procedure of a RAPID module (`PROC`, `FUNC` or `TRAP`).
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Procedure {
    /// Name as written.
    pub name: String,
    /// Line of its `PROC`.
    pub line: usize,
    /// Move instructions in its body (all branches; calls not followed).
    pub moves: usize,
}

/// A hold at rest on the path (G-code `G4 P<ms>` / `G4 S<s>`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dwell {
    /// Index of the move the dwell follows; `None`: before any move, at the start point.
    pub after_move: Option<usize>,
    /// Duration, s (finite, ≥ 0).
    pub seconds: f64,
    /// Source line.
    pub line: usize,
}

/// Relative tolerance used to tell z levels apart in [`Toolpath::layer_count`], m.
pub(crate) const LAYER_Z_TOLERANCE_M: f64 = 1e-6;

impl Toolpath {
    /// Diagonal of the axis-aligned bounding box of the start and every move's end point, m
    /// (an arc's bulge beyond its end points is left out: the end points bound a printed part
    /// closely enough for a plausibility check).
    pub(crate) fn extent_diagonal(&self) -> f64 {
        let (mut lo, mut hi) = (self.start, self.start);
        for m in &self.moves {
            lo = lo.inf(&m.end);
            hi = hi.sup(&m.end);
        }
        (hi - lo).norm()
    }

    /// Multiply the geometry by `k` (points, arc centres, radii and rises, marks and their
    /// arc lengths); speeds are kept.
    pub fn scale(&mut self, k: f64) {
        self.start *= k;
        for m in &mut self.moves {
            m.end *= k;
            if let MoveKind::Arc {
                centre,
                radius,
                axial,
                ..
            } = &mut m.kind
            {
                *centre *= k;
                *radius *= k;
                *axial *= k;
            }
        }
        for mk in &mut self.marks {
            mk.point *= k;
            mk.s *= k;
        }
    }

    /// Start point of move `i` (m): the previous move's end, or [`Toolpath::start`].
    pub fn move_start(&self, i: usize) -> V3 {
        if i == 0 {
            self.start
        } else {
            self.moves.get(i - 1).map_or(self.start, |m| m.end)
        }
    }

    /// Iterate `(start, move)` pairs.
    pub fn segments(&self) -> impl Iterator<Item = (V3, &Move)> + '_ {
        self.moves
            .iter()
            .enumerate()
            .map(move |(i, m)| (self.move_start(i), m))
    }

    /// End point of the path (m).
    pub fn end(&self) -> V3 {
        self.moves.last().map_or(self.start, |m| m.end)
    }

    /// Total length of all moves, m.
    pub fn length(&self) -> f64 {
        self.segments().map(|(s, m)| m.length(&s)).sum()
    }

    /// Length of the extruding moves, m.
    pub fn print_length(&self) -> f64 {
        self.segments()
            .filter(|(_, m)| m.print)
            .map(|(s, m)| m.length(&s))
            .sum()
    }

    /// Points every `ds` m or closer (each move is cut into equal parts no longer than `ds`),
    /// with every move's end point included, so corners are kept. `ds` is raised to
    /// `length / 10⁶` at least (at most about 10⁶ samples plus move ends), and a non-positive or NaN `ds` gives the move end points only.
    pub fn sample(&self, ds: f64) -> Vec<PathSample> {
        let total = self.length();
        let ds = if ds.is_finite() && ds > 0.0 {
            ds.max(total / 1e6)
        } else {
            f64::INFINITY
        };
        let mut out = vec![PathSample {
            p: self.start,
            s: 0.0,
            move_index: 0,
            print: self.moves.first().is_some_and(|m| m.print),
        }];
        let mut s0 = 0.0;
        for (i, (start, m)) in self.segments().enumerate() {
            let len = m.length(&start);
            let n = if ds.is_finite() {
                ((len / ds).ceil() as usize).max(1)
            } else {
                1
            };
            for k in 1..=n {
                let u = k as f64 / n as f64;
                out.push(PathSample {
                    p: m.point_at(&start, u),
                    s: s0 + len * u,
                    move_index: i,
                    print: m.print,
                });
            }
            s0 += len;
        }
        out
    }

    /// Axis-aligned bounding box `(min, max)` in m over all moves, or `None` for a path without
    /// moves. Arcs are bounded by samples every 1° of sweep (error ≤ 4·10⁻⁵ radius).
    pub fn bounding_box(&self) -> Option<(V3, V3)> {
        if self.moves.is_empty() {
            return None;
        }
        let mut lo = self.start;
        let mut hi = self.start;
        let mut add = |p: V3| {
            lo = lo.inf(&p);
            hi = hi.sup(&p);
        };
        for (start, m) in self.segments() {
            match m.kind {
                MoveKind::Line => add(m.end),
                MoveKind::Arc { sweep, .. } => {
                    let n = ((sweep.to_degrees()).ceil() as usize).clamp(1, 360);
                    for k in 1..=n {
                        add(m.point_at(&start, k as f64 / n as f64));
                    }
                }
            }
        }
        Some((lo, hi))
    }

    /// Number of distinct z levels (tolerance [`LAYER_Z_TOLERANCE_M`]) among the end points of
    /// extruding moves that stay at constant z. A helical (spiral) path counts as one layer per
    /// distinct end height.
    pub fn layer_count(&self) -> usize {
        let mut zs: Vec<f64> = self
            .segments()
            .filter(|(_, m)| m.print)
            .map(|(_, m)| m.end.z)
            .collect();
        zs.sort_by(|a, b| a.total_cmp(b));
        let mut n = 0;
        let mut last = f64::NEG_INFINITY;
        for z in zs {
            if z - last > LAYER_Z_TOLERANCE_M {
                n += 1;
                last = z;
            }
        }
        n
    }

    /// The slicer layer (0-based, in marker order) of move `i`: the number of layer markers
    /// before it, less one; `None` before the first marker or when the file has none.
    pub fn layer_of(&self, i: usize) -> Option<usize> {
        self.layer_starts
            .partition_point(|&s| s <= i)
            .checked_sub(1)
    }

    /// Layers: the slicer's markers when the file has them ([`Toolpath::layer_starts`]), else
    /// the distinct z levels of the print moves ([`Toolpath::layer_count`]).
    pub fn layers(&self) -> usize {
        if self.layer_starts.is_empty() {
            self.layer_count()
        } else {
            self.layer_starts.len()
        }
    }

    /// The mark named `name`, if any.
    pub fn mark(&self, name: &str) -> Option<&Mark> {
        self.marks.iter().find(|m| m.name == name)
    }

    /// A printing path through `points` (part frame, m) at the print speed `speed` (m/s), each
    /// corner blended within `zone`: what a designer's list of points is (COMPAS, Grasshopper,
    /// the Python bindings). `source` names it in messages; move `k` has line `k + 1` (the
    /// point's 1-based row). Consecutive duplicate points are dropped. Errors: fewer than two
    /// distinct points, a non-finite coordinate (naming the row), a speed that is not > 0, a
    /// blend radius that is not finite and >= 0.
    pub fn from_points(points: &[V3], speed: f64, zone: Zone, source: &str) -> Result<Toolpath> {
        if !(speed.is_finite() && speed > 0.0) {
            return Err(Error::Invalid(format!(
                "{source}: speed {speed} m/s: expected a finite speed > 0"
            )));
        }
        if !(zone.radius().is_finite() && zone.radius() >= 0.0) {
            return Err(Error::Invalid(format!(
                "{source}: zone {} m: expected a finite blend radius >= 0",
                zone.radius()
            )));
        }
        if let Some(k) = points.iter().position(|p| p.iter().any(|v| !v.is_finite())) {
            return Err(Error::Invalid(format!(
                "{source}: point {} (row {k}) has a coordinate that is not a finite number: {:?}",
                k + 1,
                points[k].as_slice()
            )));
        }
        let Some(start) = points.first() else {
            return Err(Error::Invalid(format!(
                "{source}: no points: expected at least two distinct points (m)"
            )));
        };
        let mut tp = Toolpath {
            source: source.to_string(),
            start: *start,
            ..Default::default()
        };
        for (k, p) in points.iter().enumerate().skip(1) {
            if (p - tp.end()).norm() <= 1e-12 {
                continue;
            }
            tp.moves.push(Move {
                kind: MoveKind::Line,
                end: *p,
                speed,
                zone,
                print: true,
                line: k + 1,
            });
        }
        if tp.moves.is_empty() {
            return Err(Error::Invalid(format!(
                "{source}: {} point(s), all at the same place: expected at least two distinct points (m)",
                points.len()
            )));
        }
        Ok(tp)
    }
}

/// Options for the readers. Speeds in m/s, lengths in m.
#[derive(Clone, Debug, PartialEq)]
pub struct ReadOptions {
    /// TCP speed of extruding moves when the file gives none (G-code before any `F`, CSV
    /// without a `speed` column), m/s.
    pub default_print_speed: f64,
    /// TCP speed of travel moves when the file gives none (G-code `G0` without `F` on the
    /// same line), m/s.
    pub default_travel_speed: f64,
    /// Corner blend for G-code (`G64` without `P`, and the initial mode) and CSV moves.
    pub default_zone: Zone,
    /// G-code M-codes that switch extrusion on (default `M3`, `M101`).
    pub print_on_mcodes: Vec<u32>,
    /// G-code M-codes that switch extrusion off (default `M5`, `M103`).
    pub print_off_mcodes: Vec<u32>,
    /// Length unit of CSV path columns written without one (`x`, not `x[mm]`); speeds
    /// without a unit follow it per second. `None`: mm, with a warning that mm was assumed. A
    /// unit in the header always wins. Formats that define their own units (G-code `G20`/`G21`,
    /// RAPID mm) refuse it.
    pub path_units: Option<PathUnits>,
    /// Factor applied to the path's geometry after its units are read (points, arc centres
    /// and radii, marks; not speeds). 1 leaves the path as read.
    pub scale: f64,
    /// RAPID: the procedure to read as the entry instead of `main` (case-insensitive), for
    /// modules whose `main` chooses its path at run time (an `IF` on an input). Other formats
    /// refuse it.
    pub proc: Option<String>,
}

/// The length unit of a path file's unlabelled coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathUnits {
    /// Millimetres.
    Mm,
    /// Metres.
    M,
}

impl PathUnits {
    /// `mm` or `m` (case-insensitive); an error naming the accepted values otherwise.
    pub fn parse(s: &str) -> Result<PathUnits> {
        match s.trim().to_ascii_lowercase().as_str() {
            "mm" => Ok(PathUnits::Mm),
            "m" => Ok(PathUnits::M),
            other => Err(Error::Invalid(format!(
                "path units '{other}': expected mm or m"
            ))),
        }
    }

    /// The unit's symbol.
    pub(crate) fn symbol(self) -> &'static str {
        match self {
            PathUnits::Mm => "mm",
            PathUnits::M => "m",
        }
    }

    /// The matching speed unit.
    pub(crate) fn speed_symbol(self) -> &'static str {
        match self {
            PathUnits::Mm => "mm/s",
            PathUnits::M => "m/s",
        }
    }
}

impl Default for ReadOptions {
    /// 0.1 m/s print, 0.25 m/s travel, 5 mm blend radius, M3/M101 on, M5/M103 off, CSV
    /// coordinates without a unit in mm (with a warning), scale 1.
    fn default() -> Self {
        ReadOptions {
            default_print_speed: 0.1,
            default_travel_speed: 0.25,
            default_zone: Zone::Blend(0.005),
            print_on_mcodes: vec![3, 101],
            print_off_mcodes: vec![5, 103],
            path_units: None,
            scale: 1.0,
            proc: None,
        }
    }
}

/// Read a toolpath, choosing the reader by extension: `.gcode`/`.nc`/`.ngc`/`.g` → G-code,
/// `.csv` → CSV of points, `.mod`/`.prg`/`.modx` → ABB RAPID.
pub fn load(path: &Path, opts: &ReadOptions) -> Result<Toolpath> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    let name = path.display().to_string();
    let parse: fn(&str, &str, &ReadOptions) -> Result<Toolpath> = match ext.as_str() {
        "gcode" | "nc" | "ngc" | "g" => parse_gcode,
        "csv" => parse_csv,
        "mod" | "prg" | "modx" => parse_rapid,
        _ => {
            return Err(Error::Invalid(format!(
                "{name}: unknown toolpath extension '.{ext}': expected .gcode, .nc, .ngc, .g, \
                 .csv, .mod, .prg or .modx"
            )))
        }
    };
    if !(opts.scale.is_finite() && opts.scale > 0.0) {
        return Err(Error::Invalid(format!(
            "{name}: scale {}: expected a finite factor > 0",
            opts.scale
        )));
    }
    if let (Some(u), false) = (opts.path_units, ext == "csv") {
        return Err(Error::Invalid(format!(
            "{name}: path units '{}' apply to CSV paths only: G-code states its units (G21 mm, \
             G20 inch) and RAPID is in mm; use a scale factor to resize",
            u.symbol()
        )));
    }
    if let (Some(p), false) = (&opts.proc, matches!(ext.as_str(), "mod" | "prg" | "modx")) {
        return Err(Error::Invalid(format!(
            "{name}: an entry procedure ('{p}') applies to RAPID modules only (.mod, .prg, \
             .modx)"
        )));
    }
    let text = read_text(path)?;
    let mut tp = parse(&text, &name, opts)?;
    if opts.scale != 1.0 {
        tp.scale(opts.scale);
    }
    check_extent(&tp, &name)?;
    let unit = match ext.as_str() {
        "csv" => None,
        "mod" | "prg" | "modx" => Some("read as mm, RAPID's unit"),
        _ => Some("read in the file's units, mm (G21) unless it says G20 (inch)"),
    };
    if let Some(unit) = unit {
        extent_warning(&mut tp, &name, unit, opts.scale);
    }
    warn_slow_moves(
        &mut tp,
        &name,
        matches!(ext.as_str(), "gcode" | "nc" | "ngc" | "g"),
    );
    Ok(tp)
}

/// Smallest plausible bounding-box diagonal of a 3DCP path, m.
pub(crate) const MIN_PLAUSIBLE_EXTENT_M: f64 = 0.05;
/// Largest plausible bounding-box diagonal of a 3DCP path, m.
pub(crate) const MAX_PLAUSIBLE_EXTENT_M: f64 = 50.0;

/// Warn when the path's bounding-box diagonal lies outside
/// [[`MIN_PLAUSIBLE_EXTENT_M`], [`MAX_PLAUSIBLE_EXTENT_M`]]: a unit slip is likely. `unit`
/// says how the coordinates were read (and how to change that), `scale` the factor applied.
pub(crate) fn extent_warning(tp: &mut Toolpath, file: &str, unit: &str, scale: f64) {
    let d = tp.extent_diagonal();
    if (MIN_PLAUSIBLE_EXTENT_M..=MAX_PLAUSIBLE_EXTENT_M).contains(&d) {
        return;
    }
    let what = if d < MIN_PLAUSIBLE_EXTENT_M {
        "smaller than 50 mm"
    } else {
        "larger than 50 m"
    };
    let scaled = if scale != 1.0 {
        format!(", scaled by {scale}")
    } else {
        String::new()
    };
    tp.warnings.push(format!(
        "{file}: the path's bounding box spans {} m (diagonal), {what}: implausible for a \
         concrete-printed part; its coordinates were {unit}{scaled}. If that is wrong, state \
         the unit (CSV: x[m],y[m],z[m] in the header, or the path units) or resize with the \
         scale setting",
        fmt_g(d)
    ));
}

/// A length in m to four significant figures, without trailing noise.
fn fmt_g(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let digits = (3 - x.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{x:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Commanded speeds below this are implausible for printing (m/s): 1 mm/s, a sixtieth of the
/// slowest 3DCP print speeds. Such a speed is usually a unit slip (`F1.5` meant `F1500`).
pub(crate) const SLOW_MOVE_M_S: f64 = 1e-3;

/// Warn (naming the lines) about moves commanded below [`SLOW_MOVE_M_S`]. Paths too long to
/// time at such a speed are refused later by the timing budget; shorter ones still run, so
/// the user must be told.
fn warn_slow_moves(tp: &mut Toolpath, file: &str, gcode: bool) {
    let slow: Vec<&Move> = tp
        .moves
        .iter()
        .filter(|m| m.speed < SLOW_MOVE_M_S)
        .collect();
    let Some(first) = slow.first() else {
        return;
    };
    let lines: Vec<String> = slow.iter().take(10).map(|m| m.line.to_string()).collect();
    // Six decimals, so that 1.5 mm/min prints as 1.5 and not 1.4999999999999998.
    let r = |x: f64| (x * 1e6).round() / 1e6;
    let v_mm_s = first.speed * 1e3;
    let hint = if gcode {
        let f = first.speed * 60e3;
        format!(
            "F{} mm/min is {} mm/s; did you mean F{}?",
            r(f),
            r(v_mm_s),
            r(f * 1e3)
        )
    } else {
        format!("{} mm/s; did you mean {} mm/s?", r(v_mm_s), r(v_mm_s * 1e3))
    };
    tp.warnings.push(format!(
        "{file}: line {}{}: {} move(s) commanded below 1 mm/s ({hint}); timed as given",
        lines.join(", "),
        if slow.len() > 10 { ", …" } else { "" },
        slow.len()
    ));
}

/// Largest coordinate a toolpath may hold, m (100 km: far beyond any printer, small enough
/// that lengths and times stay finite).
pub(crate) const MAX_EXTENT_M: f64 = 1e5;

/// Refuse a toolpath whose points lie beyond [`MAX_EXTENT_M`] or whose move lengths are not
/// finite (numbers like `1e308` parse but overflow every later sum), naming the move's line.
pub(crate) fn check_extent(tp: &Toolpath, file: &str) -> Result<()> {
    let bad = |p: &V3| p.iter().any(|c| !c.is_finite() || c.abs() > MAX_EXTENT_M);
    if bad(&tp.start) {
        return Err(Error::Field {
            file: file.into(),
            field: "start point".into(),
            msg: format!(
                "coordinates {:?} m lie beyond {MAX_EXTENT_M} m: check the units",
                tp.start
            ),
        });
    }
    let mut total = 0.0;
    for (i, m) in tp.moves.iter().enumerate() {
        let len = m.length(&tp.move_start(i));
        total += len;
        if bad(&m.end) || !len.is_finite() || !total.is_finite() {
            return Err(Error::Parse {
                file: file.into(),
                line: m.line,
                column: 1,
                msg: format!(
                    "the move ends at {:?} m (length {len} m), beyond {MAX_EXTENT_M} m from \
                     the part origin: check the units",
                    m.end
                ),
            });
        }
    }
    Ok(())
}

/// Read named placements from a CSV file with header `name,x[mm],y[mm],z[mm],yaw[deg]`
/// (optional `nozzle_spin[deg]`); units as in CSV paths (lengths default mm, angles default
/// deg). See [`parse_placements`].
pub fn load_placements(path: &Path) -> Result<Vec<NamedPlacement>> {
    let text = read_text(path)?;
    parse_placements(&text, &path.display().to_string())
}

/// Build a parse error (1-based line and column).
pub(crate) fn perr(file: &str, line: usize, column: usize, msg: impl Into<String>) -> Error {
    Error::Parse {
        file: file.to_string(),
        line,
        column,
        msg: msg.into(),
    }
}

/// Circle through three points `a → b → c` (m): `(centre, unit normal, radius, sweep)`, the
/// motion turning positively about `normal` from `a` through `b` to `c`. `None` when the
/// points are (nearly) collinear or coincide.
pub(crate) fn circle_through(a: &V3, b: &V3, c: &V3) -> Option<(V3, V3, f64, f64)> {
    let ab = b - a;
    let ac = c - a;
    let n = ab.cross(&ac);
    let n2 = n.norm_squared();
    let scale = ab.norm_squared().max(ac.norm_squared());
    if n2.is_nan() || n2 <= 1e-18 * scale * scale || !n2.is_finite() {
        return None;
    }
    // Circumcentre: a + (|ac|²(n × ab)... standard formula.
    let centre =
        a + (ac.norm_squared() * n.cross(&ab) + ab.norm_squared() * ac.cross(&n)) / (2.0 * n2);
    let normal = n / n2.sqrt();
    let radius = (a - centre).norm();
    let sweep = ccw_angle(&(a - centre), &(c - centre), &normal);
    Some((centre, normal, radius, sweep))
}

/// Angle in `(0, 2π]` turning `from` to `to` positively about unit `normal` (2π when equal
/// directions).
pub(crate) fn ccw_angle(from: &V3, to: &V3, normal: &V3) -> f64 {
    let x = from.dot(to);
    let y = normal.dot(&from.cross(to));
    let mut a = y.atan2(x);
    if a <= 1e-12 {
        a += std::f64::consts::TAU;
    }
    a.min(std::f64::consts::TAU)
}
