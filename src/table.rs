//! The one reader of CSV files printwatt takes (toolpaths as points, placement sets, joint
//! trajectories, measurement logs) and the one unit table ([`si_factor`]).
//!
//! The format: `#` starts a comment (a whole line, or the rest of a line); `# key: value`
//! lines before the header are metadata; blank lines are skipped; the first other line is the
//! header, column names with an optional unit in brackets (`t[ms]`, `q3[deg]`, `x[mm]`),
//! case-insensitive; then rows of values. A header with semicolons and no commas marks a
//! European spreadsheet export: `;` separates the fields and a decimal comma becomes a point.
//! Units are converted to SI here, on reading, and only here. Every error names the file, the
//! 1-based line and column, and the column's name where there is one (a NaN or an infinity is
//! refused as "expected a finite number for 'q1', found 'NaN'").
//!
//! Two levels: [`Table`] reads a whole numeric table (trajectories); [`TableReader`] reads one
//! line at a time and keeps no rows, for readers that keep only some columns of a long file
//! (measurement logs, with [`for_each_line`]); [`lines`], [`parse_header`], [`number`] and
//! [`check_count`] are the pieces they are made of, for readers with text and flag columns or
//! comments among the rows (toolpath points, placement sets).

use crate::error::{read_text, Error, Result};
use std::path::Path;

/// A parsed numeric table with SI values.
#[derive(Clone, Debug, Default)]
pub struct Table {
    /// File name used in messages.
    pub file: String,
    /// Column names without their unit suffix, lower-cased.
    pub names: Vec<String>,
    /// Unit written in the header for each column (empty when none).
    pub units: Vec<String>,
    /// `# key: value` lines before the header.
    pub metadata: Vec<(String, String)>,
    /// Rows of SI values.
    pub rows: Vec<Vec<f64>>,
    /// 1-based source line of each row, for messages.
    pub lines: Vec<usize>,
    /// 1-based line of the header row.
    pub header_line: usize,
}

/// The physical dimension a column holds; decides which units are accepted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dim {
    /// Time: s, ms, us.
    Time,
    /// Joint angle: rad, deg (for prismatic joints the same column is in m; mm accepted).
    Angle,
    /// Angular velocity: rad/s, deg/s.
    AngularVelocity,
    /// Angular acceleration: rad/s^2, deg/s^2.
    AngularAcceleration,
    /// Torque: Nm, N.m, kNm, mNm.
    Torque,
    /// Current: A, mA.
    Current,
    /// Power: W, kW, mW.
    Power,
    /// Length: m, mm, cm, in.
    Length,
    /// Speed: m/s, mm/s, mm/min, m/min, in/min, in/s.
    Speed,
    /// A rotation about an axis (a part's yaw, a nozzle's spin): rad, deg.
    Rotation,
    /// A plain number.
    Number,
    /// A 0/1 (or false/true) flag: no unit.
    Flag,
    /// Text (a name): no unit.
    Text,
}

/// Factor converting a value in `unit` to SI for dimension `dim`, or `None` if unknown.
pub(crate) fn si_factor(dim: Dim, unit: &str) -> Option<f64> {
    let u = unit
        .trim()
        .to_ascii_lowercase()
        .replace(['·', ' ', '*'], "")
        .replace("n.m", "nm");
    if u.is_empty() {
        return Some(1.0);
    }
    let deg = std::f64::consts::PI / 180.0;
    let f = match dim {
        Dim::Time | Dim::Angle | Dim::AngularVelocity | Dim::AngularAcceleration => {
            return joint_unit_factor(dim, &u)
        }
        Dim::Torque => match u.as_str() {
            "nm" | "n" => 1.0,
            "knm" | "kn" => 1e3,
            "mnm" => 1e-3,
            _ => return None,
        },
        Dim::Current => match u.as_str() {
            "a" => 1.0,
            "ma" => 1e-3,
            _ => return None,
        },
        Dim::Power => match u.as_str() {
            "w" => 1.0,
            "kw" => 1e3,
            "mw" => 1e-3,
            _ => return None,
        },
        Dim::Length => match u.as_str() {
            "m" => 1.0,
            "mm" => 1e-3,
            "cm" => 1e-2,
            "in" | "inch" => 0.0254,
            _ => return None,
        },
        Dim::Speed => match u.as_str() {
            "m/s" => 1.0,
            "mm/s" => 1e-3,
            "mm/min" => 1e-3 / 60.0,
            "m/min" => 1.0 / 60.0,
            "in/min" => 0.0254 / 60.0,
            "in/s" => 0.0254,
            _ => return None,
        },
        Dim::Rotation => match u.as_str() {
            "rad" => 1.0,
            "deg" | "°" => deg,
            _ => return None,
        },
        Dim::Number => match u.as_str() {
            "" | "1" | "-" => 1.0,
            _ => return None,
        },
        Dim::Flag | Dim::Text => return None,
    };
    Some(f)
}

/// [`si_factor`] of a time or a joint's position, velocity or acceleration (`u`: the unit,
/// lower case, spaces removed).
fn joint_unit_factor(dim: Dim, u: &str) -> Option<f64> {
    let deg = std::f64::consts::PI / 180.0;
    let f = match dim {
        Dim::Time => match u {
            "s" => 1.0,
            "ms" => 1e-3,
            "us" | "µs" => 1e-6,
            "min" => 60.0,
            _ => return None,
        },
        Dim::Angle => match u {
            "rad" | "m" => 1.0,
            "deg" | "°" => deg,
            "mm" => 1e-3,
            _ => return None,
        },
        Dim::AngularVelocity => match u {
            "rad/s" | "m/s" => 1.0,
            "deg/s" => deg,
            "mm/s" => 1e-3,
            "rpm" => 2.0 * std::f64::consts::PI / 60.0,
            _ => return None,
        },
        Dim::AngularAcceleration => match u {
            "rad/s^2" | "rad/s2" | "m/s^2" | "m/s2" => 1.0,
            "deg/s^2" | "deg/s2" => deg,
            "mm/s^2" | "mm/s2" => 1e-3,
            _ => return None,
        },
        _ => return None,
    };
    Some(f)
}

/// The kind of a joint column's unit ([`Dim::Angle`], [`Dim::AngularVelocity`],
/// [`Dim::AngularAcceleration`] hold a revolute joint's in rad or deg, a prismatic joint's in
/// m or mm): `Some(true)` for a length-based unit (`mm`, `m/s`, `in/s^2`, …), `Some(false)` for
/// an angular one (`rad`, `deg/s`, `°`, `rpm`, …), `None` for no unit or one of neither kind.
pub fn joint_unit_is_linear(unit: &str) -> Option<bool> {
    let u = unit.trim().to_ascii_lowercase();
    if u == "rpm" {
        return Some(false);
    }
    let base = u.split('/').next().unwrap_or("");
    if base.is_empty() {
        None
    } else if si_factor(Dim::Length, base).is_some() {
        Some(true)
    } else if si_factor(Dim::Rotation, base).is_some() {
        Some(false)
    } else {
        None
    }
}

/// The units [`si_factor`] accepts for `dim`, for messages.
pub(crate) fn expected_units(dim: Dim) -> &'static str {
    match dim {
        Dim::Time => "s, ms, us or min",
        Dim::Angle => "rad or deg (m or mm for a prismatic joint)",
        Dim::AngularVelocity => "rad/s, deg/s or rpm (m/s or mm/s for a prismatic joint)",
        Dim::AngularAcceleration => "rad/s^2 or deg/s^2 (m/s^2 or mm/s^2 for a prismatic joint)",
        Dim::Torque => "Nm, kNm or mNm",
        Dim::Current => "A or mA",
        Dim::Power => "W, kW or mW",
        Dim::Length => "mm, cm, m or in",
        Dim::Speed => "mm/s, m/s, mm/min, m/min, in/min or in/s",
        Dim::Rotation => "deg or rad",
        Dim::Number => "no unit (or 1)",
        Dim::Flag | Dim::Text => "no unit",
    }
}

/// How a reader wants a column read: its dimension and the unit assumed when the header gives
/// none (empty: SI).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct ColumnSpec {
    /// The dimension (decides the units accepted).
    pub dim: Dim,
    /// Unit assumed when the header gives none (`"mm"`, `"deg"`; `""` = SI).
    pub default_unit: &'static str,
}

impl ColumnSpec {
    /// A column in SI unless its header says otherwise.
    pub fn si(dim: Dim) -> Self {
        ColumnSpec {
            dim,
            default_unit: "",
        }
    }
    /// A column in `unit` unless its header says otherwise.
    pub(crate) fn default_unit(dim: Dim, unit: &'static str) -> Self {
        ColumnSpec {
            dim,
            default_unit: unit,
        }
    }
}

/// One field of a line: its 1-based starting column (leading spaces skipped) and its trimmed
/// text (a decimal comma already made a point in a `;`-separated file).
#[derive(Clone, Debug, PartialEq)]
pub struct Cell {
    /// 1-based character column where the value starts.
    pub col: usize,
    /// The trimmed text.
    pub text: String,
}

/// One line of a CSV file as the readers see it (blank lines are dropped).
#[derive(Clone, Debug, PartialEq)]
pub enum Line {
    /// A line holding only a comment: its 1-based number and the text after `#`, trimmed.
    Comment(usize, String),
    /// The header: 1-based line number and its fields.
    Header(usize, Vec<Cell>),
    /// A data row: 1-based line number, its fields, and the column just past its last
    /// character (where a missing field would start).
    Data(usize, Vec<Cell>, usize),
}

/// The field separator of a CSV from its header line: `;` for a European spreadsheet export
/// (header with semicolons and no commas; numbers then have a decimal comma), else `,`.
pub(crate) fn separator(header: &str) -> char {
    if header.contains(';') && !header.contains(',') {
        ';'
    } else {
        ','
    }
}

fn cells(line: &str, sep: char, decimal_comma: bool) -> Vec<Cell> {
    let mut out = Vec::new();
    let mut col = 1;
    for part in line.split(sep) {
        let lead = part.chars().take_while(|c| c.is_whitespace()).count();
        let t = part.trim();
        let text = if decimal_comma {
            t.replace(',', ".")
        } else {
            t.to_string()
        };
        out.push(Cell {
            col: col + lead,
            text,
        });
        col += part.chars().count() + 1;
    }
    out
}

/// A line without its line end split at its first `#`: the body before it and the comment
/// after it, if any.
fn split_comment(raw: &str) -> (&str, Option<&str>) {
    let raw = raw.trim_end_matches('\r');
    match raw.find('#') {
        Some(p) => (&raw[..p], Some(&raw[p + 1..])),
        None => (raw, None),
    }
}

/// Split CSV text into comment, header and data lines (see the module docs).
pub fn lines(text: &str) -> Vec<Line> {
    let mut out = Vec::new();
    let mut sep = None;
    for (i, raw) in text.lines().enumerate() {
        let (body, comment) = split_comment(raw);
        if body.trim().is_empty() {
            if let Some(c) = comment {
                out.push(Line::Comment(i + 1, c.trim().to_string()));
            }
            continue;
        }
        match sep {
            None => {
                let s = separator(body);
                sep = Some(s);
                out.push(Line::Header(i + 1, cells(body, s, false)));
            }
            Some(s) => out.push(Line::Data(
                i + 1,
                cells(body, s, s == ';'),
                body.trim_end().chars().count() + 1,
            )),
        }
    }
    out
}

/// A column of a parsed header.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    /// Name without its unit, lower-cased.
    pub name: String,
    /// The unit written in brackets (empty when none).
    pub unit: String,
    /// 1-based character column of the name.
    pub col: usize,
    /// Factor to SI; `None` for a column the reader does not know (its `spec` gave `None`).
    pub factor: Option<f64>,
}

fn parse_err(file: &str, line: usize, column: usize, msg: impl Into<String>) -> Error {
    Error::Parse {
        file: file.to_string(),
        line,
        column,
        msg: msg.into(),
    }
}

/// A header field's lower-case column name and its unit (the text in `[...]`, or empty).
fn name_and_unit(file: &str, line: usize, col: usize, field: &str) -> Result<(String, String)> {
    Ok(match field.find('[') {
        Some(p) => {
            let Some(q) = field[p..].find(']') else {
                return Err(parse_err(
                    file,
                    line,
                    col + field.chars().count(),
                    format!("expected ']' to close the unit of column '{}'", &field[..p]),
                ));
            };
            (
                field[..p].trim().to_ascii_lowercase(),
                field[p + 1..p + q].trim().to_string(),
            )
        }
        None => (field.to_ascii_lowercase(), String::new()),
    })
}

/// The factor to SI of column `name` in `unit` as `spec` reads it (`None`: a column the reader
/// does not know); errors for a unit on a flag or text column, or an unknown unit.
fn column_factor(
    file: &str,
    line: usize,
    col: usize,
    (name, unit): (&str, &str),
    spec: &dyn Fn(&str) -> Option<ColumnSpec>,
) -> Result<Option<f64>> {
    Ok(match spec(name) {
        None => None,
        Some(ColumnSpec {
            dim: Dim::Flag | Dim::Text,
            ..
        }) => {
            if !unit.is_empty() {
                return Err(parse_err(
                    file,
                    line,
                    col,
                    format!("column '{name}' takes no unit, found '[{unit}]'"),
                ));
            }
            Some(1.0)
        }
        Some(ColumnSpec { dim, default_unit }) => {
            let u = if unit.is_empty() { default_unit } else { unit };
            Some(si_factor(dim, u).ok_or_else(|| {
                parse_err(
                    file,
                    line,
                    col,
                    format!(
                        "unknown unit '{u}' for column '{name}': expected {}",
                        expected_units(dim)
                    ),
                )
            })?)
        }
    })
}

/// Parse a header's fields: each column's name, unit and factor to SI. `spec` says how the
/// reader wants a (lower-case) column name read, `None` for a column it does not know (kept
/// with no factor: [`Table`] reads it as a plain number, the toolpath reader ignores it).
///
/// Errors (file, line, column): an unclosed `[`, an empty name, a unit on a flag or text
/// column, an unknown unit (naming the units accepted), a name given twice, a header made of
/// numbers only.
pub(crate) fn parse_header(
    file: &str,
    line: usize,
    fields: &[Cell],
    spec: &dyn Fn(&str) -> Option<ColumnSpec>,
) -> Result<Vec<Column>> {
    // A file without a header starts with data: say so before any check of its "names".
    if !fields.is_empty() && fields.iter().all(|c| c.text.parse::<f64>().is_ok()) {
        return Err(parse_err(
            file,
            line,
            1,
            "expected a header row of column names, found numbers",
        ));
    }
    let mut cols: Vec<Column> = Vec::with_capacity(fields.len());
    for Cell { col, text: field } in fields {
        let col = *col;
        let (name, unit) = name_and_unit(file, line, col, field)?;
        if name.is_empty() {
            return Err(parse_err(
                file,
                line,
                col,
                "expected a column name, found nothing",
            ));
        }
        let factor = column_factor(file, line, col, (&name, &unit), spec)?;
        if cols.iter().any(|c| c.name == name) {
            return Err(parse_err(
                file,
                line,
                col,
                format!("column '{name}' appears twice: expected each column once"),
            ));
        }
        cols.push(Column {
            name,
            unit,
            col,
            factor,
        });
    }
    if cols.iter().all(|c| c.name.parse::<f64>().is_ok()) {
        return Err(parse_err(
            file,
            line,
            1,
            "expected a header row of column names, found numbers",
        ));
    }
    Ok(cols)
}

/// A finite number from a field, or an error at `file:line:col` naming the column:
/// "expected a finite number for 'q1', found 'NaN'" (or "found nothing").
pub fn number(file: &str, line: usize, col: usize, name: &str, text: &str) -> Result<f64> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(parse_err(
            file,
            line,
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

/// The largest magnitude (SI) a value of `dim` can have in any robot's data: far beyond every
/// real robot, low enough that squares and sums of many samples stay finite. `None` for
/// dimensions without one (plain numbers, flags, text).
///
/// Time 1e10 s (Unix timestamps fit), joint position 1e4 rad or m, joint velocity 1e4 rad/s,
/// joint acceleration 1e6 rad/s², torque 1e7 N·m, current 1e5 A, power 1e8 W, length 1e4 m,
/// speed 1e3 m/s, rotation 1e4 rad.
pub(crate) fn physical_bound(dim: Dim) -> Option<(f64, &'static str)> {
    Some(match dim {
        Dim::Time => (1e10, "s"),
        Dim::Angle => (1e4, "rad (or m)"),
        Dim::AngularVelocity => (1e4, "rad/s (or m/s)"),
        Dim::AngularAcceleration => (1e6, "rad/s^2 (or m/s^2)"),
        Dim::Torque => (1e7, "N·m"),
        Dim::Current => (1e5, "A"),
        Dim::Power => (1e8, "W"),
        Dim::Length => (1e4, "m"),
        Dim::Speed => (1e3, "m/s"),
        Dim::Rotation => (1e4, "rad"),
        Dim::Number | Dim::Flag | Dim::Text => return None,
    })
}

/// A number for a message: plain when it reads well, in scientific notation when it is very
/// large or very small (`1e308`, not 309 digits).
pub fn show(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-4..1e9).contains(&a) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// `v` (SI, of dimension `dim`, read at `file:line:col` in column `name`) within
/// [`physical_bound`], or an error naming the place, the value and the bound.
pub(crate) fn check_physical(
    file: &str,
    line: usize,
    col: usize,
    name: &str,
    dim: Dim,
    v: f64,
) -> Result<f64> {
    match physical_bound(dim) {
        Some((bound, unit)) if v.abs() > bound => Err(parse_err(
            file,
            line,
            col,
            format!(
                "'{name}' = {} {unit} is outside any physical range (|value| <= {} {unit}): \
                 check the value or the column's unit",
                show(v),
                show(bound)
            ),
        )),
        _ => Ok(v),
    }
}

/// A data row must have one field per header column: the error points at the first extra
/// field, or at the end of the line when fields are missing.
pub(crate) fn check_count(
    file: &str,
    line: usize,
    fields: &[Cell],
    n: usize,
    eol: usize,
) -> Result<()> {
    if fields.len() != n {
        let col = if fields.len() > n { fields[n].col } else { eol };
        return Err(parse_err(
            file,
            line,
            col,
            format!(
                "expected {n} values (one per header column), found {}",
                fields.len()
            ),
        ));
    }
    Ok(())
}

/// An incremental reader of a numeric table: fed one line at a time (1-based line number and
/// its text), it keeps the header's names, units and metadata and the values of the last data
/// row read, in SI, never the rows before it. [`Table::parse`] collects its rows; the
/// measurement-log reader stores only the columns it needs, so that a long file costs no more
/// than its values.
pub(crate) struct TableReader<'a> {
    table: Table,
    dim_of: &'a dyn Fn(&str) -> Option<Dim>,
    factors: Vec<f64>,
    dims: Vec<Option<Dim>>,
    sep: Option<char>,
    row: Vec<f64>,
}

impl<'a> TableReader<'a> {
    /// A reader for `file` (the name used in messages); `dim_of` as for [`Table::read`].
    pub fn new(file: &str, dim_of: &'a dyn Fn(&str) -> Option<Dim>) -> Self {
        TableReader {
            table: Table {
                file: file.to_string(),
                ..Default::default()
            },
            dim_of,
            factors: Vec::new(),
            dims: Vec::new(),
            sep: None,
            row: Vec::new(),
        }
    }

    /// The header read so far (names, units, metadata, header line; no rows).
    pub fn header(&self) -> &Table {
        &self.table
    }

    /// The values of the data row read by the last [`TableReader::feed`] that returned `true`.
    pub fn row(&self) -> &[f64] {
        &self.row
    }

    /// Read one line (`ln`: its 1-based number): a comment, the header or a data row.
    /// Returns whether it was a data row (its values are then in [`TableReader::row`]).
    /// Errors as [`Table::parse`] gives them.
    pub fn feed(&mut self, ln: usize, raw: &str) -> Result<bool> {
        let (body, comment) = split_comment(raw);
        if body.trim().is_empty() {
            if let Some(c) = comment {
                if self.table.names.is_empty() {
                    if let Some((k, v)) = c.trim().split_once(':') {
                        self.table
                            .metadata
                            .push((k.trim().to_string(), v.trim().to_string()));
                    }
                }
            }
            return Ok(false);
        }
        let Some(sep) = self.sep else {
            let s = separator(body);
            self.sep = Some(s);
            let file = self.table.file.clone();
            let fields = cells(body, s, false);
            self.table.header_line = ln;
            let dim_of = self.dim_of;
            for c in parse_header(&file, ln, &fields, &|n| dim_of(n).map(ColumnSpec::si))? {
                self.factors.push(c.factor.unwrap_or(1.0));
                self.dims.push(dim_of(&c.name));
                self.table.names.push(c.name);
                self.table.units.push(c.unit);
            }
            return Ok(false);
        };
        let file = &self.table.file;
        let ncol = self.table.names.len();
        let decimal_comma = sep == ';';
        if body.split(sep).count() != ncol {
            let fields = cells(body, sep, decimal_comma);
            check_count(file, ln, &fields, ncol, body.trim_end().chars().count() + 1)?;
        }
        self.row.clear();
        let names = &self.table.names;
        let mut col = 1;
        for (k, part) in body.split(sep).enumerate() {
            let t = part.trim();
            let owned;
            let text = if decimal_comma && t.contains(',') {
                owned = t.replace(',', ".");
                owned.as_str()
            } else {
                t
            };
            let at = || col + part.chars().take_while(|c| c.is_whitespace()).count();
            let v = match text.parse::<f64>() {
                Ok(v) if v.is_finite() => v,
                _ => number(file, ln, at(), &names[k], text)?,
            } * self.factors[k];
            let v = match self.dims[k] {
                Some(d) if physical_bound(d).is_some_and(|(b, _)| v.abs() > b) => {
                    check_physical(file, ln, at(), &names[k], d, v)?
                }
                _ => v,
            };
            self.row.push(v);
            col += part.chars().count() + 1;
        }
        Ok(true)
    }

    /// The header and metadata read; an error when the text had no header row.
    pub fn finish(self) -> Result<Table> {
        if self.table.names.is_empty() {
            return Err(parse_err(&self.table.file, 1, 1, "no header row found"));
        }
        Ok(self.table)
    }
}

/// Visit the lines of a text file one at a time, as [`crate::error::read_text`] would give
/// them (UTF-8, a byte-order mark dropped, CRLF and CR-only line endings counted as one line
/// break each, at most [`crate::error::max_input_bytes`]), without holding the whole file:
/// `f` gets each line's 1-based number and text. The file is checked whole (its length and
/// encoding) before the first line is visited, so that its errors are the same as
/// [`crate::error::read_text`]'s. Returns the number of lines. Something other than a regular
/// file (a pipe, a device) is read whole.
pub(crate) fn for_each_line(
    path: &Path,
    f: &mut dyn FnMut(usize, &str) -> Result<()>,
) -> Result<usize> {
    // Read whole: the exact errors of `read_text`, or a file that is not a regular one.
    let whole = |f: &mut dyn FnMut(usize, &str) -> Result<()>| -> Result<usize> {
        let text = read_text(path)?;
        let mut count = 0;
        for (i, l) in text.lines().enumerate() {
            count = i + 1;
            f(i + 1, l)?;
        }
        Ok(count)
    };
    if !std::fs::metadata(path).is_ok_and(|m| m.is_file()) {
        return whole(f);
    }
    let max = crate::error::max_input_bytes();
    let len = std::fs::metadata(path)
        .map_err(|e| Error::io(path, e))?
        .len();
    if len > max {
        return Err(crate::error::too_long(path, max));
    }
    // The whole file first: its length and encoding (an invalid byte is named by
    // `read_text`, which then reads it whole).
    if !is_utf8_within(path, max)? {
        return whole(f);
    }
    // Then line by line.
    stream_lines(path, max, f)
}

/// Whether the file holds valid UTF-8 (false: read it whole for `read_text`'s error); an
/// error when it is longer than `max` bytes.
fn is_utf8_within(path: &Path, max: u64) -> Result<bool> {
    use std::io::Read;
    let mut r = std::fs::File::open(path)
        .map_err(|e| Error::io(path, e))?
        .take(max + 1);
    let mut buf = vec![0u8; 1 << 20];
    let mut carry: Vec<u8> = Vec::new();
    let mut total = 0u64;
    loop {
        let got = r.read(&mut buf).map_err(|e| Error::io(path, e))?;
        if got == 0 {
            break;
        }
        total += got as u64;
        if total > max {
            return Err(crate::error::too_long(path, max));
        }
        carry.extend_from_slice(&buf[..got]);
        match std::str::from_utf8(&carry) {
            Ok(_) => carry.clear(),
            Err(e) if e.error_len().is_none() => {
                carry = carry.split_off(e.valid_up_to());
            }
            Err(_) => return Ok(false),
        }
    }
    Ok(carry.is_empty())
}

/// Visit the lines of a checked file (at most `max` bytes) one at a time: a byte-order mark
/// dropped, LF, CRLF and lone CR each ending a line. Returns the number of lines.
fn stream_lines(
    path: &Path,
    max: u64,
    f: &mut dyn FnMut(usize, &str) -> Result<()>,
) -> Result<usize> {
    use std::io::{BufRead, Read};
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut r = std::io::BufReader::with_capacity(1 << 16, file.take(max + 1));
    let mut buf: Vec<u8> = Vec::new();
    let mut ln = 0usize;
    let mut first = true;
    loop {
        buf.clear();
        let got = r
            .read_until(b'\n', &mut buf)
            .map_err(|e| Error::io(path, e))?;
        if got == 0 {
            break;
        }
        let mut bytes = &buf[..];
        if first {
            first = false;
            bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
        }
        // Lines end at LF, CRLF or a lone CR.
        while !bytes.is_empty() {
            let end = bytes
                .iter()
                .position(|&b| b == b'\n' || b == b'\r')
                .unwrap_or(bytes.len());
            let Ok(line) = std::str::from_utf8(&bytes[..end]) else {
                return Err(Error::Invalid(format!(
                    "{}: changed while it was read",
                    path.display()
                )));
            };
            ln += 1;
            f(ln, line)?;
            let mut next = end;
            if next < bytes.len() {
                next += if bytes[next] == b'\r' && bytes.get(next + 1) == Some(&b'\n') {
                    2
                } else {
                    1
                };
            }
            bytes = &bytes[next..];
        }
    }
    Ok(ln)
}

impl Table {
    /// Read a CSV file. `dim_of` gives the dimension of a column from its name (unit checks;
    /// SI when the header gives no unit), or `None` for a column the caller does not know
    /// (kept, read as a plain number).
    pub fn read(path: &Path, dim_of: &dyn Fn(&str) -> Option<Dim>) -> Result<Table> {
        let text = read_text(path)?;
        Table::parse(&text, &path.display().to_string(), dim_of)
    }

    /// Parse CSV text; see [`Table::read`].
    pub fn parse(text: &str, file: &str, dim_of: &dyn Fn(&str) -> Option<Dim>) -> Result<Table> {
        let mut r = TableReader::new(file, dim_of);
        let mut rows = Vec::new();
        let mut lines = Vec::new();
        for (i, raw) in text.lines().enumerate() {
            if r.feed(i + 1, raw)? {
                rows.push(r.row().to_vec());
                lines.push(i + 1);
            }
        }
        let mut t = r.finish()?;
        t.rows = rows;
        t.lines = lines;
        Ok(t)
    }
    /// Index of a column by its (lower-case) name.
    pub fn col(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }

    /// The values of a column.
    pub fn column(&self, k: usize) -> Vec<f64> {
        self.rows.iter().map(|r| r[k]).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dims(n: &str) -> Option<Dim> {
        match n.chars().next() {
            Some('t') => Some(Dim::Time),
            Some('q') => Some(Dim::Angle),
            _ => None,
        }
    }

    #[test]
    fn one_unit_table_for_every_reader() {
        let mm = si_factor(Dim::Length, "mm").unwrap();
        assert_eq!(mm, 1e-3);
        assert_eq!(si_factor(Dim::Length, "inch"), Some(0.0254));
        assert_eq!(si_factor(Dim::Speed, "in/min"), Some(0.0254 / 60.0));
        assert_eq!(
            si_factor(Dim::Rotation, "deg"),
            Some(std::f64::consts::PI / 180.0)
        );
        assert_eq!(si_factor(Dim::Rotation, "m"), None);
        assert_eq!(si_factor(Dim::Torque, "N·m"), Some(1.0));
        assert_eq!(si_factor(Dim::Flag, "mm"), None);
    }

    #[test]
    fn trailing_comments_and_decimal_commas() {
        let t = Table::parse("t;q1[deg]\n0;1,5 # note\n", "f.csv", &dims).unwrap();
        assert!((t.rows[0][1] - 1.5f64.to_radians()).abs() < 1e-15);
    }

    #[test]
    fn units_are_converted_and_metadata_kept() {
        let t = Table::parse("# robot: x\nt[ms],q1[deg]\n0,180\n10,90\n", "a.csv", &dims).unwrap();
        assert_eq!(t.metadata, vec![("robot".into(), "x".into())]);
        assert!((t.rows[1][0] - 0.01).abs() < 1e-15);
        assert!((t.rows[0][1] - std::f64::consts::PI).abs() < 1e-15);
        assert_eq!(t.lines, vec![3, 4]);
    }

    #[test]
    fn errors_name_line_and_column() {
        let e = Table::parse("t,q1\n0,1\n1,NaN\n", "b.csv", &dims)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("b.csv:3:3:"), "{e}");
        assert!(e.contains("q1"), "{e}");
        let e = Table::parse("t,q1[furlong]\n", "c.csv", &dims)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("c.csv:1:3:") && e.contains("furlong"), "{e}");
        let e = Table::parse("t,q1\n0,1,2\n", "d.csv", &dims)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("d.csv:2:5") && e.contains("expected 2 values"),
            "{e}"
        );
        // A unit of another dimension is refused with the units accepted.
        let e = Table::parse("t[mm],q1\n", "e.csv", &dims)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("e.csv:1:1") && e.contains("expected s, ms"),
            "{e}"
        );
    }
}
