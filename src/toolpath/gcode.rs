//! G-code reader (RS-274 as slicers and 3DCP tools write it).
//!
//! Supported: `G0`/`G1` with `X Y Z E F`; `G2`/`G3` arcs in the `G17` (XY) plane with `I J`
//! (centre offset from the start; `G90.1` makes them absolute) or `R` (radius; `R < 0` = the
//! arc longer than half a circle), full circles (I/J form with end = start), helices (Z change
//! during an arc); `G90`/`G91` absolute/relative (also switch E, as Marlin does), `M82`/`M83`
//! absolute/relative E; `G20`/`G21` inches/mm; `G92` set position (X Y Z E; no axes = all 0);
//! `G61` exact stop (zone fine), `G64` blend (`P` = blend radius in file units, no `P` = the
//! caller's default), `G9` exact stop on its line; `G4` dwell (`P` in ms or `S` in s: the
//! path stops and holds still there for that time, see [`Toolpath::dwells`]; without either,
//! a warning naming the line); comments `;` and `( … )`; `N…` line
//! numbers; `*…` checksums; `%`; `; MARK name` comments become [`Mark`]s.
//!
//! Extrusion: a move prints when E increases on it, or when extrusion has been switched on by
//! one of [`ReadOptions::print_on_mcodes`] (default `M3`, `M101`; off: `M5`, `M103`) and the
//! move is not `G0`. A file with neither E words nor those M-codes prints on every
//! `G1`/`G2`/`G3` and travels on `G0`.
//!
//! Speeds: F is in mm/min (in/min under G20) and modal. `G0` uses an F given on its own line
//! (which also becomes the modal feed, as in Marlin), else
//! [`ReadOptions::default_travel_speed`]; other moves before any F use the default print or
//! travel speed.
//!
//! The first `G0`/`G1` sets the start point and makes no move.
//!
//! The letters on an M-code line without a G word are the M-code's parameters (`M201 X1000
//! Y1000`, `M203 …`, `M205 …` in every slicer's start code), never coordinates or extrusion;
//! text parameters and bare flags (`M1002 judge_flag …`, `M17 S`) end the line.
//!
//! Slicer comments: layer markers (`;LAYER:n` from Cura, `;LAYER_CHANGE` from PrusaSlicer,
//! `; CHANGE_LAYER` from Bambu Studio; the first kind met counts) become
//! [`Toolpath::layer_starts`], feature comments (`;TYPE:…`, `; FEATURE: …`)
//! [`Toolpath::features`].
//!
//! Unknown G/M codes and extended commands (`SET_FAN …`) are ignored and listed in one
//! warning. `G18`/`G19` (other arc planes) are an error. `M117`/`M118` messages are skipped.

use std::collections::BTreeSet;

use super::{ccw_angle, perr, Dwell, Feature, Mark, Move, MoveKind, ReadOptions, Toolpath, Zone};
use crate::error::Result;
use crate::math::V3;

/// Metres per millimetre.
const M_PER_MM: f64 = 1e-3;
/// Metres per inch.
const M_PER_INCH: f64 = 0.0254;

struct Word {
    letter: char,
    value: f64,
    col: usize,
}

struct PendingMove {
    mv: Move,
    rapid: bool,
    extruding: bool,
    feed: Option<f64>,
}

/// The number of a word whose letter is at `from - 1`: its value and the index after it.
fn lex_number(
    file: &str,
    lineno: usize,
    chars: &[char],
    from: usize,
    letter: char,
) -> Result<(f64, usize)> {
    let mut j = from;
    while j < chars.len() && (chars[j] == ' ' || chars[j] == '\t') {
        j += 1;
    }
    let num_start = j;
    if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
        j += 1;
    }
    let mut digits = 0;
    while j < chars.len() && chars[j].is_ascii_digit() {
        j += 1;
        digits += 1;
    }
    if j < chars.len() && chars[j] == '.' {
        j += 1;
        while j < chars.len() && chars[j].is_ascii_digit() {
            j += 1;
            digits += 1;
        }
    }
    if digits == 0 {
        let found: String = chars[num_start..]
            .iter()
            .take_while(|x| !x.is_whitespace() && **x != ';' && **x != '(')
            .take(12)
            .collect();
        let found = if found.is_empty() {
            "end of line".to_string()
        } else {
            format!("'{found}'")
        };
        return Err(perr(
            file,
            lineno,
            num_start + 1,
            format!("expected a number after '{letter}', found {found}"),
        ));
    }
    let text: String = chars[num_start..j].iter().collect();
    let value: f64 = text.parse().unwrap_or(f64::NAN);
    if !value.is_finite() {
        return Err(perr(
            file,
            lineno,
            num_start + 1,
            format!("expected a finite number after '{letter}', found '{text}'"),
        ));
    }
    Ok((value, j))
}

/// An extended command (`SET_FAN_SPEED …`, `EXCLUDE_OBJECT_DEFINE …`) starting at `i`: its
/// first word; `Gnan`/`Xinf` are refused as words whose number is not a number.
fn extended_command(file: &str, lineno: usize, chars: &[char], i: usize) -> Result<String> {
    let c = chars[i];
    let cmd: String = chars[i..]
        .iter()
        .take_while(|x| !x.is_whitespace())
        .collect();
    // `Gnan`, `Xinf`: a word whose number is not a number, not an extended command.
    let tail = cmd[c.len_utf8()..].to_ascii_lowercase();
    if tail.starts_with("nan") || tail.starts_with("inf") {
        return Err(perr(
            file,
            lineno,
            i + 2,
            format!(
                "expected a number after '{}', found '{}'",
                c.to_ascii_uppercase(),
                crate::error::clip(&cmd[c.len_utf8()..])
            ),
        ));
    }
    Ok(cmd)
}

/// The `( … )` comment opening at `i`: its text and the index after it.
fn paren_comment(file: &str, lineno: usize, chars: &[char], i: usize) -> Result<(String, usize)> {
    match chars[i + 1..].iter().position(|&x| x == ')') {
        Some(p) => Ok((chars[i + 1..i + 1 + p].iter().collect(), i + p + 2)),
        None => Err(perr(
            file,
            lineno,
            chars.len() + 1,
            format!(
                "expected ')' to close the comment opened at column {}",
                i + 1
            ),
        )),
    }
}

/// Split one line into words, comments and an optional extended command.
#[allow(clippy::type_complexity)]
fn lex_line(
    file: &str,
    lineno: usize,
    line: &str,
) -> Result<(Vec<Word>, Vec<String>, Option<String>)> {
    let chars: Vec<char> = line.chars().collect();
    let mut words = Vec::new();
    let mut comments = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() || c == '%' {
            i += 1;
        } else if c == ';' {
            comments.push(chars[i + 1..].iter().collect());
            break;
        } else if c == '*' {
            break;
        } else if c == '(' {
            let (comment, next) = paren_comment(file, lineno, &chars, i)?;
            comments.push(comment);
            i = next;
        } else if c.is_ascii_alphabetic() {
            let next = chars.get(i + 1).copied().unwrap_or(' ');
            if words.is_empty() && (next.is_ascii_alphabetic() || next == '_') {
                let cmd = extended_command(file, lineno, &chars, i)?;
                return Ok((words, comments, Some(cmd)));
            }
            let letter = c.to_ascii_uppercase();
            // `G28 X Y`, `G28 W` (Prusa: home without mesh levelling): bare letters are flags of
            // the homing command, not words.
            let homing = words
                .first()
                .is_some_and(|w: &Word| w.letter == 'G' && w.value == 28.0);
            if homing
                && chars
                    .get(i + 1)
                    .is_none_or(|x| x.is_whitespace() || *x == ';')
            {
                i += 1;
                continue;
            }
            // An M-code's parameters may be free text or bare flags (Bambu Studio's `M1002
            // judge_flag …`, `M1002 gcode_claim_action : 2`, `M17 S`, `M620 S0A`): they are
            // never coordinates, so the rest of such a line is skipped.
            let m_line = words.first().is_some_and(|w: &Word| w.letter == 'M');
            let (value, j) = match lex_number(file, lineno, &chars, i + 1, letter) {
                Ok(v) => v,
                Err(_) if m_line => break,
                Err(e) => return Err(e),
            };
            if m_line && chars.get(j).is_some_and(|x| x.is_ascii_alphabetic()) {
                break;
            }
            words.push(Word {
                letter,
                value,
                col: i + 1,
            });
            i = j;
            // Messages: the rest of the line is free text.
            if letter == 'M' && (value == 117.0 || value == 118.0) {
                break;
            }
        } else {
            return Err(perr(
                file,
                lineno,
                i + 1,
                format!("expected a G-code word (a letter and a number) or a comment, found '{c}'"),
            ));
        }
    }
    Ok((words, comments, None))
}

/// The words of one line, sorted by letter.
#[derive(Default)]
struct LineWords {
    axis: [Option<f64>; 3],
    first_axis_col: usize,
    i: Option<f64>,
    j: Option<f64>,
    r: Option<(f64, usize)>,
    e: Option<f64>,
    f: Option<(f64, usize)>,
    p: Option<f64>,
    s: Option<f64>,
    /// G codes ×10 (G90.1 = 901) with their columns.
    gs: Vec<(i64, usize)>,
    /// M codes ×10 with their columns.
    ms: Vec<(i64, usize)>,
}

impl LineWords {
    fn new(words: &[Word]) -> Self {
        let mut lw = LineWords::default();
        let code = |v: f64| (v * 10.0).round().clamp(-1e9, 1e9) as i64;
        for w in words {
            match w.letter {
                'G' => lw.gs.push((code(w.value), w.col)),
                'M' => lw.ms.push((code(w.value), w.col)),
                'X' | 'Y' | 'Z' => {
                    lw.axis[(w.letter as u8 - b'X') as usize] = Some(w.value);
                    if lw.first_axis_col == 0 {
                        lw.first_axis_col = w.col;
                    }
                }
                'I' => lw.i = Some(w.value),
                'J' => lw.j = Some(w.value),
                'R' => lw.r = Some((w.value, w.col)),
                'E' => lw.e = Some(w.value),
                'F' => lw.f = Some((w.value, w.col)),
                'P' => lw.p = Some(w.value),
                'S' => lw.s = Some(w.value),
                _ => {} // N, K, T, H, D, Q, A, B, C …: not needed for the path.
            }
        }
        // An M-code line without a G word (`M201 X1000 Y1000 Z500 E5000`, `M203 …`,
        // `M92 …`, `M906 …`): its letters are the M-code's parameters (accelerations, speed
        // limits, steps per mm, currents), not coordinates, an extrusion or a feed.
        if !lw.ms.is_empty() && lw.gs.is_empty() {
            lw.axis = [None; 3];
            lw.first_axis_col = 0;
            (lw.i, lw.j, lw.r, lw.e, lw.f) = (None, None, None, None, None);
        }
        lw
    }

    fn has_xyz(&self) -> bool {
        self.axis.iter().any(|a| a.is_some())
    }

    fn has_arc_words(&self) -> bool {
        self.i.is_some() || self.j.is_some() || self.r.is_some()
    }
}

/// What a line's G codes say about the line itself (the modal state is in [`Reader`]).
#[derive(Default)]
struct LineModes {
    /// The motion code given on the line (0–3) and its column.
    motion: Option<(u8, usize)>,
    /// `G9`: exact stop on this line.
    exact_here: bool,
    /// `G92`, `G28`, `G10`, `G53`: axis words that are not a move.
    non_motion_axes: Option<i64>,
}

/// The reader's modal state while it walks the file.
struct Reader<'a> {
    file: &'a str,
    opts: &'a ReadOptions,
    /// Metres per file unit (G20/G21).
    unit: f64,
    abs: bool,
    e_rel: bool,
    ij_abs: bool,
    motion: Option<u8>,
    pos: V3,
    offset: V3,
    e: f64,
    feed: Option<f64>,
    zone_mode: Zone,
    pump_on: bool,
    saw_e: bool,
    saw_pump: bool,
    started: bool,
    unknown: BTreeSet<String>,
    /// `G4` dwells with a usable duration (`P` in ms or `S` in s).
    dwells: Vec<Dwell>,
    /// The lines of `G4` dwells without one.
    untimed_dwells: Vec<usize>,
    start: V3,
    pending: Vec<PendingMove>,
    marks: Vec<Mark>,
    length: f64,
    /// The layer marker family the file uses (the first one met): Cura, PrusaSlicer or Bambu.
    layer_family: Option<LayerMarker>,
    layer_starts: Vec<usize>,
    features: Vec<Feature>,
}

/// A slicer's layer marker comment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum LayerMarker {
    /// `;LAYER:n` (Cura).
    Cura,
    /// `;LAYER_CHANGE` (PrusaSlicer, Bambu Studio, OrcaSlicer).
    Prusa,
    /// `; CHANGE_LAYER` (Bambu Studio).
    Bambu,
}

impl LayerMarker {
    fn of(comment: &str) -> Option<LayerMarker> {
        let c = comment.trim();
        if let Some(n) = c.strip_prefix("LAYER:") {
            return n.trim().parse::<i64>().ok().map(|_| LayerMarker::Cura);
        }
        match c {
            "LAYER_CHANGE" => Some(LayerMarker::Prusa),
            "CHANGE_LAYER" => Some(LayerMarker::Bambu),
            _ => None,
        }
    }
}

/// The feature named by a `;TYPE:…` or `; FEATURE: …` comment.
fn feature_of(comment: &str) -> Option<&str> {
    let c = comment.trim();
    c.strip_prefix("TYPE:")
        .or_else(|| c.strip_prefix("FEATURE:"))
        .map(str::trim)
        .filter(|n| !n.is_empty())
}

/// Parse G-code text; `file` names the source in messages. See the module docs for the dialect.
pub fn parse_gcode(text: &str, file: &str, opts: &ReadOptions) -> Result<Toolpath> {
    let mut r = Reader::new(file, opts);
    for (idx, raw) in text.lines().enumerate() {
        if r.line(idx + 1, raw)? {
            break;
        }
    }
    Ok(r.finish())
}

impl<'a> Reader<'a> {
    fn new(file: &'a str, opts: &'a ReadOptions) -> Self {
        Reader {
            file,
            opts,
            unit: M_PER_MM,
            abs: true,
            e_rel: false,
            ij_abs: false,
            motion: None,
            pos: V3::zeros(),
            offset: V3::zeros(),
            e: 0.0,
            feed: None,
            zone_mode: opts.default_zone,
            pump_on: false,
            saw_e: false,
            saw_pump: false,
            started: false,
            unknown: BTreeSet::new(),
            dwells: Vec::new(),
            untimed_dwells: Vec::new(),
            start: V3::zeros(),
            pending: Vec::new(),
            marks: Vec::new(),
            length: 0.0,
            layer_family: None,
            layer_starts: Vec::new(),
            features: Vec::new(),
        }
    }

    /// Read one line; true at a program end (`M2`, `M30`).
    fn line(&mut self, lineno: usize, raw: &str) -> Result<bool> {
        let (words, comments, ext) = lex_line(self.file, lineno, raw)?;
        for c in &comments {
            let next = self.pending.len();
            if let Some(m) = LayerMarker::of(c) {
                if *self.layer_family.get_or_insert(m) == m {
                    self.layer_starts.push(next);
                }
            } else if let Some(name) = feature_of(c) {
                if self.features.last().is_none_or(|f| f.name != name) {
                    self.features.push(Feature {
                        first_move: next,
                        name: name.to_string(),
                    });
                }
            }
        }
        if let Some(cmd) = ext {
            self.unknown.insert(cmd);
        }
        let lw = LineWords::new(&words);
        let modes = self.g_codes(lineno, &lw)?;
        let program_end = self.m_codes(&lw);
        if let Some((f, col)) = lw.f {
            if f <= 0.0 {
                return Err(perr(
                    self.file,
                    lineno,
                    col + 1,
                    format!("expected a positive feed rate after 'F', found {f}"),
                ));
            }
        }
        let f_here = lw.f.map(|(f, _)| f * self.unit / 60.0);
        if let Some(g) = modes.non_motion_axes {
            if g == 920 {
                self.set_position(&lw);
            }
            if let Some(f) = f_here {
                self.feed = Some(f);
            }
        } else {
            self.motion_words(lineno, &lw, &modes, f_here)?;
        }
        for name in mark_names(&comments) {
            self.marks.push(Mark {
                name,
                point: self.pos,
                s: self.length,
            });
        }
        Ok(program_end)
    }

    /// Apply a line's G codes to the modal state.
    fn g_codes(&mut self, lineno: usize, lw: &LineWords) -> Result<LineModes> {
        let mut modes = LineModes::default();
        for &(g, col) in &lw.gs {
            match g {
                0 | 10 | 20 | 30 => modes.motion = Some(((g / 10) as u8, col)),
                // Dwell: `P` in ms (Marlin/RepRap), `S` in s: a hold at rest after the last
                // move so far. Without a usable duration: warned at the end.
                40 => match lw
                    .p
                    .map(|p| p / 1000.0)
                    .or(lw.s)
                    .filter(|t| t.is_finite() && *t >= 0.0)
                {
                    Some(seconds) => self.dwells.push(Dwell {
                        after_move: self.pending.len().checked_sub(1),
                        seconds,
                        line: lineno,
                    }),
                    None => self.untimed_dwells.push(lineno),
                },
                90 => modes.exact_here = true,
                170 => {}
                180 | 190 => {
                    return Err(perr(
                        self.file,
                        lineno,
                        col,
                        format!(
                            "G{} selects the {} plane: only G17 (XY plane) is supported, \
                             expected G17",
                            g / 10,
                            if g == 180 { "XZ" } else { "YZ" }
                        ),
                    ))
                }
                200 => self.unit = M_PER_INCH,
                210 => self.unit = M_PER_MM,
                610 => self.zone_mode = Zone::Fine,
                640 => {
                    self.zone_mode = match lw.p {
                        Some(p) if p >= 0.0 => Zone::Blend(p * self.unit),
                        _ => self.opts.default_zone,
                    }
                }
                900 => {
                    self.abs = true;
                    self.e_rel = false;
                }
                910 => {
                    self.abs = false;
                    self.e_rel = true;
                }
                901 => self.ij_abs = true,
                911 => self.ij_abs = false,
                920 => modes.non_motion_axes = Some(920),
                // Homing, offsets, bed levelling (G29, G29.1, G29.2) and probing moves (G38.2 …
                // G38.5, Bambu Studio's G380): their axes are not path points.
                280 | 100 | 530 | 290 | 291 | 292 | 382..=385 | 3800 => {
                    modes.non_motion_axes = Some(g);
                    self.unknown.insert(gname(g));
                }
                400 | 490 | 800 | 940 => {}
                _ => {
                    self.unknown.insert(gname(g));
                }
            }
        }
        Ok(modes)
    }

    /// Apply a line's M codes (extrusion on/off, E mode); true at a program end.
    fn m_codes(&mut self, lw: &LineWords) -> bool {
        let mut program_end = false;
        for &(m, _) in &lw.ms {
            let code = (m / 10) as u32;
            if m % 10 == 0 && self.opts.print_on_mcodes.contains(&code) {
                self.pump_on = true;
                self.saw_pump = true;
            } else if m % 10 == 0 && self.opts.print_off_mcodes.contains(&code) {
                self.pump_on = false;
                self.saw_pump = true;
            } else {
                match m {
                    820 => self.e_rel = false,
                    830 => self.e_rel = true,
                    0 | 10 => {}
                    20 | 300 => program_end = true,
                    _ => {
                        self.unknown.insert(format!("M{}", fmt_code(m)));
                    }
                }
            }
        }
        program_end
    }

    /// `G92`: the given axes (and E) take the given values; without axes, all are zero.
    fn set_position(&mut self, lw: &LineWords) {
        let mut any = false;
        for (k, a) in lw.axis.iter().enumerate() {
            if let Some(v) = a {
                self.offset[k] = self.pos[k] - v * self.unit;
                any = true;
            }
        }
        if let Some(v) = lw.e {
            self.e = v;
            any = true;
        }
        if !any {
            self.offset = self.pos;
            self.e = 0.0;
        }
    }

    /// The extrusion of a line's E word (m of filament are irrelevant: only its sign is used).
    fn extrusion(&mut self, lw: &LineWords) -> f64 {
        let Some(v) = lw.e else { return 0.0 };
        self.saw_e = true;
        if self.e_rel {
            self.e += v;
            v
        } else {
            let de = v - self.e;
            self.e = v;
            de
        }
    }

    /// A line that may move: coordinates (or arc words) under the modal motion code.
    fn motion_words(
        &mut self,
        lineno: usize,
        lw: &LineWords,
        modes: &LineModes,
        f_here: Option<f64>,
    ) -> Result<()> {
        if let Some((m, _)) = modes.motion {
            self.motion = Some(m);
        }
        // E first: a line with only E (retract, prime) extrudes without moving.
        let de = self.extrusion(lw);
        let is_arc_motion = matches!(self.motion, Some(2) | Some(3));
        if !(lw.has_xyz() || (is_arc_motion && lw.has_arc_words())) {
            if let Some(f) = f_here {
                self.feed = Some(f);
            }
            return Ok(());
        }
        let Some(m) = self.motion else {
            return Err(perr(
                self.file,
                lineno,
                lw.first_axis_col.max(1),
                "coordinates without a motion mode: expected G0, G1, G2 or G3 first",
            ));
        };
        let target = self.target(lw);
        if let Some(f) = f_here {
            self.feed = Some(f);
        }
        if !self.started && m <= 1 {
            self.started = true;
            self.start = target;
            self.pos = target;
            return Ok(());
        }
        self.started = true;
        let kind = if m <= 1 {
            MoveKind::Line
        } else {
            let col = modes.motion.map_or(lw.first_axis_col.max(1), |(_, c)| c);
            arc_kind(
                self.file,
                lineno,
                col,
                m == 2,
                &self.pos,
                &target,
                (lw.i, lw.j, lw.r.map(|(r, c)| (r * self.unit, c))),
                self.unit,
                self.ij_abs,
                &self.offset,
            )?
        };
        let mv = Move {
            kind,
            end: target,
            speed: 0.0,
            zone: if modes.exact_here {
                Zone::Fine
            } else {
                self.zone_mode
            },
            print: false,
            line: lineno,
        };
        let len = mv.length(&self.pos);
        if len > 1e-12 {
            self.length += len;
            self.pending.push(PendingMove {
                mv,
                rapid: m == 0,
                extruding: de > 1e-12 || (self.pump_on && m != 0),
                feed: if m == 0 { f_here } else { self.feed },
            });
            self.pos = target;
        }
        Ok(())
    }

    /// Where a line's axis words move to (m; absolute or relative, with the G92 offset).
    fn target(&self, lw: &LineWords) -> V3 {
        let mut target = self.pos;
        for (k, a) in lw.axis.iter().enumerate() {
            if let Some(v) = a {
                target[k] = if self.abs {
                    v * self.unit + self.offset[k]
                } else {
                    self.pos[k] + v * self.unit
                };
            }
        }
        target
    }

    /// The moves with their print flags and speeds, and the reader's warnings.
    fn finish(self) -> Toolpath {
        let file = self.file;
        let opts = self.opts;
        let infer_from_g = !self.saw_e && !self.saw_pump;
        let moves: Vec<Move> = self
            .pending
            .into_iter()
            .map(|p| {
                let print = if infer_from_g { !p.rapid } else { p.extruding };
                let default = if print {
                    opts.default_print_speed
                } else {
                    opts.default_travel_speed
                };
                Move {
                    print,
                    speed: p.feed.unwrap_or(default),
                    ..p.mv
                }
            })
            .collect();
        let mut warnings = Vec::new();
        if !self.unknown.is_empty() {
            warnings.push(format!(
                "{file}: ignored codes: {}",
                self.unknown.into_iter().collect::<Vec<_>>().join(", ")
            ));
        }
        if !self.untimed_dwells.is_empty() {
            warnings.push(untimed_dwell_warning(file, &self.untimed_dwells));
        }
        if infer_from_g {
            warnings.push(format!(
                "{file}: no E words and no extrusion M-codes: G1/G2/G3 taken as printing, G0 as travel"
            ));
        }
        if !moves.is_empty() && !moves.iter().any(|m: &Move| m.print) {
            warnings.push(format!(
                "{file}: no print moves: every move is travel (G0, or no extrusion), so nothing is printed; the energy is that of the travel alone"
            ));
        }
        Toolpath {
            source: file.to_string(),
            start: self.start,
            moves,
            marks: self.marks,
            warnings,
            dwells: self.dwells,
            layer_starts: self.layer_starts,
            features: self.features,
            ..Default::default()
        }
    }
}

/// The names of `; MARK name` comments on a line.
fn mark_names(comments: &[String]) -> Vec<String> {
    let mut names = Vec::new();
    for c in comments {
        if let Some(rest) = c.trim().strip_prefix("MARK") {
            if let Some(name) = rest.split_whitespace().next() {
                if rest.starts_with(char::is_whitespace) {
                    names.push(name.to_string());
                }
            }
        }
    }
    names
}

fn untimed_dwell_warning(file: &str, lines: &[usize]) -> String {
    let shown: Vec<String> = lines.iter().take(10).map(|l| l.to_string()).collect();
    format!(
        "{file}: line {}{}: G4 dwell without a usable P<ms> or S<s> ({} in all): \
         not timed, the hold is missing from the cycle time and the standby energy",
        shown.join(", "),
        if lines.len() > 10 { ", …" } else { "" },
        lines.len()
    )
}

fn fmt_code(c10: i64) -> String {
    if c10 % 10 == 0 {
        format!("{}", c10 / 10)
    } else {
        format!("{}.{}", c10 / 10, (c10 % 10).abs())
    }
}

fn gname(g: i64) -> String {
    format!("G{}", fmt_code(g))
}

/// The centre of a G17 arc (m), from I/J (offset or absolute) or R (the short arc unless R < 0).
#[allow(clippy::too_many_arguments)]
fn arc_centre(
    at: (&str, usize, usize, &str),
    clockwise: bool,
    p0: &V3,
    p1: &V3,
    ijr: (Option<f64>, Option<f64>, Option<(f64, usize)>),
    unit: f64,
    ij_abs: bool,
    offset: &V3,
) -> Result<V3> {
    let (file, line, col, gword) = at;
    let (wi, wj, wr) = ijr;
    let same_xy = (p1.x - p0.x).hypot(p1.y - p0.y) < 1e-9;
    Ok(match (wi.is_some() || wj.is_some(), wr) {
        (true, Some((_, rcol))) => {
            return Err(perr(
                file,
                line,
                rcol,
                format!("{gword}: expected either I/J (centre offset) or R (radius), not both"),
            ))
        }
        (false, None) => {
            return Err(perr(
                file,
                line,
                col,
                format!("{gword} needs a centre: expected I and J (centre offset) or R (radius)"),
            ))
        }
        (true, None) => {
            let (i, j) = (wi.unwrap_or(0.0) * unit, wj.unwrap_or(0.0) * unit);
            if ij_abs {
                V3::new(i + offset.x, j + offset.y, p0.z)
            } else {
                V3::new(p0.x + i, p0.y + j, p0.z)
            }
        }
        (false, Some((r, rcol))) => {
            if same_xy {
                return Err(perr(
                    file,
                    line,
                    rcol,
                    format!("{gword}: an R-form arc cannot be a full circle; expected I and J"),
                ));
            }
            let d = V3::new(p1.x - p0.x, p1.y - p0.y, 0.0);
            let dn = d.norm();
            let half = dn / 2.0;
            let ra = r.abs();
            if ra < half - 1e-6_f64.max(1e-6 * half) {
                return Err(perr(
                    file,
                    line,
                    rcol,
                    format!(
                        "{gword}: radius {:.6} mm is less than half the chord {:.6} mm: expected \
                         |R| ≥ chord / 2",
                        ra * 1e3,
                        half * 1e3
                    ),
                ));
            }
            let h = (ra * ra - half * half).max(0.0).sqrt();
            let u = d / dn;
            let left = V3::new(-u.y, u.x, 0.0);
            // Short arc: centre left of the chord for G3 (ccw), right for G2; R < 0 swaps.
            let side = if clockwise { -1.0 } else { 1.0 } * if r < 0.0 { -1.0 } else { 1.0 };
            let mid = V3::new((p0.x + p1.x) / 2.0, (p0.y + p1.y) / 2.0, p0.z);
            mid + left * (side * h)
        }
    })
}

/// Geometry of a G17 arc from `p0` to `p1` (m). `ijr` holds I, J in file units and R in m.
#[allow(clippy::too_many_arguments)]
fn arc_kind(
    file: &str,
    line: usize,
    col: usize,
    clockwise: bool,
    p0: &V3,
    p1: &V3,
    ijr: (Option<f64>, Option<f64>, Option<(f64, usize)>),
    unit: f64,
    ij_abs: bool,
    offset: &V3,
) -> Result<MoveKind> {
    let gword = if clockwise { "G2" } else { "G3" };
    let normal = if clockwise { -V3::z() } else { V3::z() };
    let (wi, wj, wr) = ijr;
    let same_xy = (p1.x - p0.x).hypot(p1.y - p0.y) < 1e-9;
    let centre = arc_centre(
        (file, line, col, gword),
        clockwise,
        p0,
        p1,
        (wi, wj, wr),
        unit,
        ij_abs,
        offset,
    )?;
    let v0 = V3::new(p0.x - centre.x, p0.y - centre.y, 0.0);
    let v1 = V3::new(p1.x - centre.x, p1.y - centre.y, 0.0);
    let r0 = v0.norm();
    let r1 = v1.norm();
    if r0 < 1e-9 {
        return Err(perr(
            file,
            line,
            col,
            format!("{gword}: the centre is on the start point: expected a radius > 0"),
        ));
    }
    if (r0 - r1).abs() > 2e-6_f64.max(1e-3 * r0) {
        return Err(perr(
            file,
            line,
            col,
            format!(
                "{gword}: the end point is {:.4} mm from the centre but the start is {:.4} mm: \
                 expected both on one circle",
                r1 * 1e3,
                r0 * 1e3
            ),
        ));
    }
    let sweep = if same_xy {
        std::f64::consts::TAU
    } else {
        ccw_angle(&v0, &v1, &normal)
    };
    Ok(MoveKind::Arc {
        centre,
        normal,
        radius: r0,
        sweep,
        axial: (p1.z - p0.z) * normal.z,
    })
}
