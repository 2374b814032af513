//! CSV readers: paths as lists of points, and named placements.
//!
//! Format: `#` starts a comment (whole line or trailing); blank lines are skipped; the first
//! other line is the header, comma-separated column names with an optional unit in brackets,
//! e.g. `x[mm],y[mm],z[mm],speed[mm/s],print`. Names are case-insensitive.
//!
//! Units: lengths `mm` (default), `cm`, `m`, `in`; speeds `mm/s` (default), `m/s`,
//! `mm/min`, `m/min`, `in/min`, `in/s`; angles `deg` (default), `rad`.
//!
//! Path columns: `x`, `y`, `z` (required), `speed` (optional, TCP speed of the move that ends
//! at this point), `print` (optional, `0`/`1`, default 1). Other columns are ignored with a
//! warning. The first point is the start; each later point ends a straight move (zone
//! [`ReadOptions::default_zone`]); repeated points are skipped. `# MARK name` comment lines
//! mark the last point read.

use super::{perr, Mark, Move, MoveKind, NamedPlacement, Placement, ReadOptions, Toolpath};
use crate::error::Result;
use crate::math::V3;

#[derive(Clone, Copy, PartialEq)]
enum Quantity {
    Length,
    Speed,
    Angle,
    Flag,
    Text,
}

struct Column {
    name: String,
    factor: f64,
}

/// Fields of one line with their 1-based starting columns (leading spaces skipped).
fn split_fields(line: &str) -> Vec<(usize, String)> {
    split_fields_sep(line, ',')
}

/// Split on `sep`; with `;` (a European spreadsheet's export) a decimal comma becomes a point.
fn split_fields_sep(line: &str, sep: char) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut col = 1;
    for part in line.split(sep) {
        let lead = part.chars().take_while(|c| c.is_whitespace()).count();
        let t = part.trim();
        let t = if sep == ';' {
            t.replace(',', ".")
        } else {
            t.to_string()
        };
        out.push((col + lead, t));
        col += part.chars().count() + 1;
    }
    out
}

/// The field separator of a CSV from its header: `;` when the header has semicolons and no
/// commas (European spreadsheet exports, decimal comma in the numbers), else `,`.
pub(crate) fn separator(header: &str) -> char {
    if header.contains(';') && !header.contains(',') {
        ';'
    } else {
        ','
    }
}

/// Levenshtein distance of two short names.
fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().take(64).collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            cur[j + 1] = (prev[j] + usize::from(ca != cb))
                .min(prev[j + 1] + 1)
                .min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

fn strip_comment(line: &str) -> (&str, Option<&str>) {
    match line.find('#') {
        Some(p) => (&line[..p], Some(&line[p + 1..])),
        None => (line, None),
    }
}

fn unit_factor(q: Quantity, unit: &str) -> Option<f64> {
    let u = unit.trim().to_ascii_lowercase();
    match q {
        Quantity::Length => match u.as_str() {
            "mm" => Some(1e-3),
            "cm" => Some(1e-2),
            "m" => Some(1.0),
            "in" | "inch" => Some(0.0254),
            _ => None,
        },
        Quantity::Speed => match u.as_str() {
            "mm/s" => Some(1e-3),
            "m/s" => Some(1.0),
            "mm/min" => Some(1e-3 / 60.0),
            "m/min" => Some(1.0 / 60.0),
            "in/min" => Some(0.0254 / 60.0),
            "in/s" => Some(0.0254),
            _ => None,
        },
        Quantity::Angle => match u.as_str() {
            "deg" | "°" => Some(std::f64::consts::PI / 180.0),
            "rad" => Some(1.0),
            _ => None,
        },
        Quantity::Flag | Quantity::Text => None,
    }
}

fn expected_units(q: Quantity) -> &'static str {
    match q {
        Quantity::Length => "mm, cm, m or in",
        Quantity::Speed => "mm/s, m/s, mm/min, m/min, in/min or in/s",
        Quantity::Angle => "deg or rad",
        Quantity::Flag | Quantity::Text => "no unit",
    }
}

/// Parse a header: `(name, factor)` per column. `kind` maps a lower-case name to its quantity
/// (`None` = unknown column, ignored).
fn parse_header(
    file: &str,
    lineno: usize,
    line: &str,
    kind: &dyn Fn(&str) -> Option<Quantity>,
    warnings: &mut Vec<String>,
) -> Result<Vec<Column>> {
    let mut cols = Vec::new();
    for (col, field) in split_fields(line) {
        let (name, unit) = match field.find('[') {
            Some(p) => {
                let Some(q) = field[p..].find(']') else {
                    return Err(perr(
                        file,
                        lineno,
                        col + field.chars().count(),
                        format!("expected ']' to close the unit of column '{}'", &field[..p]),
                    ));
                };
                (
                    field[..p].trim().to_ascii_lowercase(),
                    Some(field[p + 1..p + q].to_string()),
                )
            }
            None => (field.to_ascii_lowercase(), None),
        };
        if name.is_empty() {
            return Err(perr(
                file,
                lineno,
                col,
                "expected a column name, found nothing",
            ));
        }
        let factor = match kind(&name) {
            None => {
                let known = [
                    "x",
                    "y",
                    "z",
                    "speed",
                    "print",
                    "name",
                    "yaw",
                    "nozzle_spin",
                ];
                let close = known
                    .iter()
                    .filter(|k| kind(k).is_some())
                    .find(|k| edit_distance(k, &name) <= 2 && name.len() > 1);
                warnings.push(match close {
                    Some(k) => format!(
                        "{file}:{lineno}: unknown column '{name}' ignored (did you mean '{k}'? without it its default is used)"
                    ),
                    None => format!("{file}:{lineno}: unknown column '{name}' ignored"),
                });
                f64::NAN
            }
            Some(q @ (Quantity::Flag | Quantity::Text)) => {
                if let Some(u) = unit {
                    return Err(perr(
                        file,
                        lineno,
                        col,
                        format!("column '{name}' takes no unit, found '[{u}]'"),
                    ));
                }
                let _ = q;
                1.0
            }
            Some(q) => {
                let u = unit.unwrap_or_else(|| {
                    match q {
                        Quantity::Speed => "mm/s",
                        Quantity::Angle => "deg",
                        _ => "mm",
                    }
                    .to_string()
                });
                unit_factor(q, &u).ok_or_else(|| {
                    perr(
                        file,
                        lineno,
                        col,
                        format!(
                            "unknown unit '{u}' for column '{name}': expected {}",
                            expected_units(q)
                        ),
                    )
                })?
            }
        };
        if cols.iter().any(|c: &Column| c.name == name) {
            return Err(perr(
                file,
                lineno,
                col,
                format!("column '{name}' appears twice: expected each column once"),
            ));
        }
        cols.push(Column { name, factor });
    }
    Ok(cols)
}

fn require(file: &str, lineno: usize, cols: &[Column], names: &[&str]) -> Result<Vec<usize>> {
    names
        .iter()
        .map(|n| {
            cols.iter().position(|c| c.name == *n).ok_or_else(|| {
                perr(
                    file,
                    lineno,
                    1,
                    format!(
                        "expected a column '{n}' in the header (required: {})",
                        names.join(", ")
                    ),
                )
            })
        })
        .collect()
}

fn number(file: &str, lineno: usize, col: usize, name: &str, text: &str) -> Result<f64> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(perr(
            file,
            lineno,
            col,
            format!(
                "expected a finite number for '{name}', found {}",
                if text.is_empty() {
                    "nothing".to_string()
                } else {
                    format!("'{text}'")
                }
            ),
        )),
    }
}

/// Data rows: `(line number, fields)`, plus comment lines `(line number, text)` interleaved
/// as `Err`.
enum Row {
    Header(usize, String),
    Data(usize, Vec<(usize, String)>, usize),
    Comment(String),
}

fn rows(text: &str) -> Vec<Row> {
    let mut out = Vec::new();
    let mut header_seen = false;
    let mut sep = ',';
    for (i, raw) in text.lines().enumerate() {
        let (body, comment) = strip_comment(raw);
        if body.trim().is_empty() {
            if let Some(c) = comment {
                out.push(Row::Comment(c.trim().to_string()));
            }
            continue;
        }
        if header_seen {
            out.push(Row::Data(
                i + 1,
                split_fields_sep(body, sep),
                body.trim_end().chars().count() + 1,
            ));
        } else {
            header_seen = true;
            sep = separator(body);
            // The header's fields are split on commas below: give it commas.
            out.push(Row::Header(
                i + 1,
                if sep == ';' {
                    body.replace(';', ",")
                } else {
                    body.to_string()
                },
            ));
        }
    }
    out
}

fn check_count(
    file: &str,
    lineno: usize,
    fields: &[(usize, String)],
    n: usize,
    eol: usize,
) -> Result<()> {
    if fields.len() != n {
        let col = if fields.len() > n { fields[n].0 } else { eol };
        return Err(perr(
            file,
            lineno,
            col,
            format!(
                "expected {n} fields as in the header, found {}",
                fields.len()
            ),
        ));
    }
    Ok(())
}

/// Parse a CSV path; `file` names the source in messages. See the module docs.
pub fn parse_csv(text: &str, file: &str, opts: &ReadOptions) -> Result<Toolpath> {
    let mut tp = Toolpath {
        source: file.to_string(),
        ..Default::default()
    };
    let mut cols: Vec<Column> = Vec::new();
    let mut idx = Vec::new();
    let (mut speed_i, mut print_i) = (None, None);
    let mut have_start = false;
    let mut length = 0.0;
    let kind = |n: &str| match n {
        "x" | "y" | "z" => Some(Quantity::Length),
        "speed" => Some(Quantity::Speed),
        "print" => Some(Quantity::Flag),
        _ => None,
    };
    for row in rows(text) {
        match row {
            Row::Header(lineno, line) => {
                cols = parse_header(file, lineno, &line, &kind, &mut tp.warnings)?;
                idx = require(file, lineno, &cols, &["x", "y", "z"])?;
                speed_i = cols.iter().position(|c| c.name == "speed");
                print_i = cols.iter().position(|c| c.name == "print");
            }
            Row::Comment(c) => {
                if let Some(rest) = c.strip_prefix("MARK ") {
                    if let Some(name) = rest.split_whitespace().next() {
                        tp.marks.push(Mark {
                            name: name.to_string(),
                            point: tp.end(),
                            s: length,
                        });
                    }
                }
            }
            Row::Data(lineno, fields, eol) => {
                check_count(file, lineno, &fields, cols.len(), eol)?;
                let mut p = V3::zeros();
                for (k, &i) in idx.iter().enumerate() {
                    let (col, t) = &fields[i];
                    p[k] = number(file, lineno, *col, &cols[i].name, t)? * cols[i].factor;
                }
                let print = match print_i {
                    Some(i) => match fields[i].1.to_ascii_lowercase().as_str() {
                        "1" | "true" => true,
                        "0" | "false" => false,
                        other => {
                            return Err(perr(
                                file,
                                lineno,
                                fields[i].0,
                                format!("expected 0 or 1 for 'print', found '{other}'"),
                            ))
                        }
                    },
                    None => true,
                };
                let speed = match speed_i {
                    Some(i) => {
                        let (col, t) = &fields[i];
                        let v = number(file, lineno, *col, "speed", t)? * cols[i].factor;
                        if v <= 0.0 {
                            return Err(perr(
                                file,
                                lineno,
                                *col,
                                format!("expected a positive speed, found '{t}'"),
                            ));
                        }
                        v
                    }
                    None if print => opts.default_print_speed,
                    None => opts.default_travel_speed,
                };
                if !have_start {
                    have_start = true;
                    tp.start = p;
                    continue;
                }
                let len = (p - tp.end()).norm();
                if len <= 1e-12 {
                    continue;
                }
                length += len;
                tp.moves.push(Move {
                    kind: MoveKind::Line,
                    end: p,
                    speed,
                    zone: opts.default_zone,
                    print,
                    line: lineno,
                });
            }
        }
    }
    if cols.is_empty() {
        return Err(perr(
            file,
            1,
            1,
            "expected a header line such as 'x[mm],y[mm],z[mm]', found an empty file",
        ));
    }
    Ok(tp)
}

/// Parse named placements: header `name,x[mm],y[mm],z[mm],yaw[deg]`, optional
/// `nozzle_spin[deg]`; lengths default to mm and angles to degrees. Returns m and rad.
pub fn parse_placements(text: &str, file: &str) -> Result<Vec<NamedPlacement>> {
    let kind = |n: &str| match n {
        "x" | "y" | "z" => Some(Quantity::Length),
        "yaw" | "nozzle_spin" => Some(Quantity::Angle),
        "name" => Some(Quantity::Text),
        _ => None,
    };
    let mut warnings = Vec::new();
    let mut cols: Vec<Column> = Vec::new();
    let mut idx = Vec::new();
    let mut spin_i = None;
    let mut out = Vec::new();
    for row in rows(text) {
        match row {
            Row::Header(lineno, line) => {
                cols = parse_header(file, lineno, &line, &kind, &mut warnings)?;
                idx = require(file, lineno, &cols, &["name", "x", "y", "z", "yaw"])?;
                spin_i = cols.iter().position(|c| c.name == "nozzle_spin");
            }
            Row::Comment(_) => {}
            Row::Data(lineno, fields, eol) => {
                check_count(file, lineno, &fields, cols.len(), eol)?;
                let mut v = [0.0; 5];
                for (k, &i) in idx.iter().enumerate().skip(1) {
                    let (col, t) = &fields[i];
                    v[k] = number(file, lineno, *col, &cols[i].name, t)? * cols[i].factor;
                }
                let spin = match spin_i {
                    Some(i) => {
                        let (col, t) = &fields[i];
                        number(file, lineno, *col, "nozzle_spin", t)? * cols[i].factor
                    }
                    None => 0.0,
                };
                let (col, name) = &fields[idx[0]];
                if name.is_empty() {
                    return Err(perr(file, lineno, *col, "expected a name, found nothing"));
                }
                out.push(NamedPlacement {
                    name: name.clone(),
                    placement: Placement {
                        x: v[1],
                        y: v[2],
                        z: v[3],
                        yaw: v[4],
                        nozzle_spin: spin,
                    },
                });
            }
        }
    }
    if cols.is_empty() {
        return Err(perr(
            file,
            1,
            1,
            "expected a header line 'name,x[mm],y[mm],z[mm],yaw[deg]', found an empty file",
        ));
    }
    Ok(out)
}
