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
//! Unknown G/M codes and extended commands (`SET_FAN …`) are ignored and listed in one
//! warning. `G18`/`G19` (other arc planes) are an error. `M117`/`M118` messages are skipped.

use std::collections::BTreeSet;

use super::{ccw_angle, perr, Dwell, Mark, Move, MoveKind, ReadOptions, Toolpath, Zone};
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
            match chars[i + 1..].iter().position(|&x| x == ')') {
                Some(p) => {
                    comments.push(chars[i + 1..i + 1 + p].iter().collect());
                    i += p + 2;
                }
                None => {
                    return Err(perr(
                        file,
                        lineno,
                        chars.len() + 1,
                        format!(
                            "expected ')' to close the comment opened at column {}",
                            i + 1
                        ),
                    ))
                }
            }
        } else if c.is_ascii_alphabetic() {
            let next = chars.get(i + 1).copied().unwrap_or(' ');
            if words.is_empty() && (next.is_ascii_alphabetic() || next == '_') {
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
                return Ok((words, comments, Some(cmd)));
            }
            let letter = c.to_ascii_uppercase();
            let mut j = i + 1;
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

/// Parse G-code text; `file` names the source in messages. See the module docs for the dialect.
pub fn parse_gcode(text: &str, file: &str, opts: &ReadOptions) -> Result<Toolpath> {
    let mut unit = M_PER_MM;
    let mut abs = true;
    let mut e_rel = false;
    let mut ij_abs = false;
    let mut motion: Option<u8> = None;
    let mut pos = V3::zeros();
    let mut offset = V3::zeros();
    let mut e = 0.0;
    let mut feed: Option<f64> = None;
    let mut zone_mode = opts.default_zone;
    let mut pump_on = false;
    let mut saw_e = false;
    let mut saw_pump = false;
    let mut started = false;
    let mut unknown: BTreeSet<String> = BTreeSet::new();
    // `G4` dwells with a usable duration (`P` in ms or `S` in s), and the lines of those
    // without one.
    let mut dwells: Vec<Dwell> = Vec::new();
    let mut untimed_dwells: Vec<usize> = Vec::new();
    let mut start = V3::zeros();
    let mut pending: Vec<PendingMove> = Vec::new();
    let mut marks: Vec<Mark> = Vec::new();
    let mut length = 0.0;

    for (idx, raw) in text.lines().enumerate() {
        let lineno = idx + 1;
        let (words, comments, ext) = lex_line(file, lineno, raw)?;
        if let Some(cmd) = ext {
            unknown.insert(cmd);
        }
        let mut line_marks = Vec::new();
        for c in &comments {
            let t = c.trim();
            if let Some(rest) = t.strip_prefix("MARK") {
                if let Some(name) = rest.split_whitespace().next() {
                    if rest.starts_with(char::is_whitespace) {
                        line_marks.push(name.to_string());
                    }
                }
            }
        }
        // Collect words.
        let mut axis: [Option<f64>; 3] = [None; 3];
        let mut first_axis_col = 0;
        let (mut wi, mut wj, mut wr, mut we, mut wf, mut wp) = (None, None, None, None, None, None);
        let mut ws: Option<f64> = None;
        let mut gs: Vec<(i64, usize)> = Vec::new();
        let mut ms: Vec<(i64, usize)> = Vec::new();
        for w in &words {
            match w.letter {
                'G' => gs.push(((w.value * 10.0).round().clamp(-1e9, 1e9) as i64, w.col)),
                'M' => ms.push(((w.value * 10.0).round().clamp(-1e9, 1e9) as i64, w.col)),
                'X' | 'Y' | 'Z' => {
                    let k = (w.letter as u8 - b'X') as usize;
                    axis[k] = Some(w.value);
                    if first_axis_col == 0 {
                        first_axis_col = w.col;
                    }
                }
                'I' => wi = Some(w.value),
                'J' => wj = Some(w.value),
                'R' => wr = Some((w.value, w.col)),
                'E' => we = Some(w.value),
                'F' => wf = Some((w.value, w.col)),
                'P' => wp = Some(w.value),
                'S' => ws = Some(w.value),
                _ => {} // N, K, S, T, H, D, Q, A, B, C …: not needed for the path.
            }
        }
        // Modal codes first.
        let mut line_motion: Option<(u8, usize)> = None;
        let mut exact_here = false;
        let mut non_motion_axes: Option<i64> = None;
        for &(g, col) in &gs {
            match g {
                0 | 10 | 20 | 30 => line_motion = Some(((g / 10) as u8, col)),
                // Dwell: `P` in ms (Marlin/RepRap), `S` in s: a hold at rest after the last
                // move so far. Without a usable duration: warned below.
                40 => match wp
                    .map(|p| p / 1000.0)
                    .or(ws)
                    .filter(|t| t.is_finite() && *t >= 0.0)
                {
                    Some(seconds) => dwells.push(Dwell {
                        after_move: pending.len().checked_sub(1),
                        seconds,
                        line: lineno,
                    }),
                    None => untimed_dwells.push(lineno),
                },
                90 => exact_here = true,
                170 => {}
                180 | 190 => {
                    return Err(perr(
                        file,
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
                200 => unit = M_PER_INCH,
                210 => unit = M_PER_MM,
                610 => zone_mode = Zone::Fine,
                640 => {
                    zone_mode = match wp {
                        Some(p) if p >= 0.0 => Zone::Blend(p * unit),
                        _ => opts.default_zone,
                    }
                }
                900 => {
                    abs = true;
                    e_rel = false;
                }
                910 => {
                    abs = false;
                    e_rel = true;
                }
                901 => ij_abs = true,
                911 => ij_abs = false,
                920 => non_motion_axes = Some(920),
                280 | 100 | 530 => {
                    non_motion_axes = Some(g);
                    unknown.insert(gname(g));
                }
                400 | 490 | 800 | 940 => {}
                _ => {
                    unknown.insert(gname(g));
                }
            }
        }
        let mut program_end = false;
        for &(m, _) in &ms {
            let code = (m / 10) as u32;
            if m % 10 == 0 && opts.print_on_mcodes.contains(&code) {
                pump_on = true;
                saw_pump = true;
            } else if m % 10 == 0 && opts.print_off_mcodes.contains(&code) {
                pump_on = false;
                saw_pump = true;
            } else {
                match m {
                    820 => e_rel = false,
                    830 => e_rel = true,
                    0 | 10 => {}
                    20 | 300 => program_end = true,
                    _ => {
                        unknown.insert(format!("M{}", fmt_code(m)));
                    }
                }
            }
        }
        if let Some((f, col)) = wf {
            if f <= 0.0 {
                return Err(perr(
                    file,
                    lineno,
                    col + 1,
                    format!("expected a positive feed rate after 'F', found {f}"),
                ));
            }
        }
        let f_here = wf.map(|(f, _)| f * unit / 60.0);

        if let Some(g) = non_motion_axes {
            if g == 920 {
                let mut any = false;
                for (k, a) in axis.iter().enumerate() {
                    if let Some(v) = a {
                        offset[k] = pos[k] - v * unit;
                        any = true;
                    }
                }
                if let Some(v) = we {
                    e = v;
                    any = true;
                }
                if !any {
                    offset = pos;
                    e = 0.0;
                }
            }
            if let Some(f) = f_here {
                feed = Some(f);
            }
        } else {
            if let Some((m, _)) = line_motion {
                motion = Some(m);
            }
            let has_xyz = axis.iter().any(|a| a.is_some());
            let has_arc_words = wi.is_some() || wj.is_some() || wr.is_some();
            // E first: a line with only E (retract, prime) extrudes without moving.
            let mut de = 0.0;
            if let Some(v) = we {
                saw_e = true;
                if e_rel {
                    de = v;
                    e += v;
                } else {
                    de = v - e;
                    e = v;
                }
            }
            let is_arc_motion = matches!(motion, Some(2) | Some(3));
            if has_xyz || (is_arc_motion && has_arc_words) {
                let Some(m) = motion else {
                    return Err(perr(
                        file,
                        lineno,
                        first_axis_col.max(1),
                        "coordinates without a motion mode: expected G0, G1, G2 or G3 first",
                    ));
                };
                let mut target = pos;
                for (k, a) in axis.iter().enumerate() {
                    if let Some(v) = a {
                        target[k] = if abs {
                            v * unit + offset[k]
                        } else {
                            pos[k] + v * unit
                        };
                    }
                }
                if let Some(f) = f_here {
                    feed = Some(f);
                }
                let zone = if exact_here { Zone::Fine } else { zone_mode };
                let extruding = de > 1e-12 || (pump_on && m != 0);
                let move_feed = if m == 0 { f_here } else { feed };
                if !started && m <= 1 {
                    started = true;
                    start = target;
                    pos = target;
                } else {
                    started = true;
                    let kind = if m <= 1 {
                        MoveKind::Line
                    } else {
                        let col = line_motion.map_or(first_axis_col.max(1), |(_, c)| c);
                        arc_kind(
                            file,
                            lineno,
                            col,
                            m == 2,
                            &pos,
                            &target,
                            (wi, wj, wr.map(|(r, c)| (r * unit, c))),
                            unit,
                            ij_abs,
                            &offset,
                        )?
                    };
                    let mv = Move {
                        kind,
                        end: target,
                        speed: 0.0,
                        zone,
                        print: false,
                        line: lineno,
                    };
                    let len = mv.length(&pos);
                    if len > 1e-12 {
                        length += len;
                        pending.push(PendingMove {
                            mv,
                            rapid: m == 0,
                            extruding,
                            feed: move_feed,
                        });
                        pos = target;
                    }
                }
            } else if let Some(f) = f_here {
                feed = Some(f);
            }
        }
        for name in line_marks {
            marks.push(Mark {
                name,
                point: pos,
                s: length,
            });
        }
        if program_end {
            break;
        }
    }

    let infer_from_g = !saw_e && !saw_pump;
    let moves: Vec<Move> = pending
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
    if !unknown.is_empty() {
        warnings.push(format!(
            "{file}: ignored codes: {}",
            unknown.into_iter().collect::<Vec<_>>().join(", ")
        ));
    }
    if !untimed_dwells.is_empty() {
        let lines: Vec<String> = untimed_dwells
            .iter()
            .take(10)
            .map(|l| l.to_string())
            .collect();
        warnings.push(format!(
            "{file}: line {}{}: G4 dwell without a usable P<ms> or S<s> ({} in all): \
             not timed, the hold is missing from the cycle time and the standby energy",
            lines.join(", "),
            if untimed_dwells.len() > 10 {
                ", …"
            } else {
                ""
            },
            untimed_dwells.len()
        ));
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
    Ok(Toolpath {
        source: file.to_string(),
        start,
        moves,
        marks,
        warnings,
        dwells,
    })
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
    let centre = match (wi.is_some() || wj.is_some(), wr) {
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
    };
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
