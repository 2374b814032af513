//! CSV readers: paths as lists of points, and named placements, on the one CSV reader and unit
//! table of [`crate::table`].
//!
//! Format: `#` starts a comment (whole line or trailing); blank lines are skipped; the first
//! other line is the header, comma-separated column names with an optional unit in brackets,
//! e.g. `x[mm],y[mm],z[mm],speed[mm/s],print`. Names are case-insensitive.
//!
//! Units: lengths `mm`, `cm`, `m`, `in`; speeds `mm/s`, `m/s`, `mm/min`, `m/min`, `in/min`,
//! `in/s`; angles `deg` (default), `rad`. A path's `x`, `y`, `z` written without a unit are
//! read in [`ReadOptions::path_units`] (speeds without a unit in that unit per second); when
//! that is not given either, in mm, and the reader says so in a warning naming the file and
//! the header line. A unit in the header always wins over [`ReadOptions::path_units`] (a
//! warning says so when the two differ). A path whose bounding box is implausible for a
//! printed part (diagonal below 50 mm or above 50 m) gets a warning naming the unit used.
//!
//! Path columns: `x`, `y`, `z` (required), `speed` (optional, TCP speed of the move that ends
//! at this point), `print` (optional, `0`/`1`, default 1). Other columns are ignored with a
//! warning. The first point is the start; each later point ends a straight move (zone
//! [`ReadOptions::default_zone`]); repeated points are skipped. `# MARK name` comment lines
//! mark the last point read.

use super::{
    extent_warning, perr, Mark, Move, MoveKind, NamedPlacement, PathUnits, Placement, ReadOptions,
    Toolpath,
};
use crate::error::Result;
use crate::math::V3;
use crate::table::{check_count, lines, number, parse_header, Column, ColumnSpec, Dim, Line};

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

/// The header through [`parse_header`], with one warning per column the reader does not know
/// (a near-miss of a known name gets "did you mean").
fn header(
    file: &str,
    lineno: usize,
    fields: &[crate::table::Cell],
    spec: &dyn Fn(&str) -> Option<ColumnSpec>,
    warnings: &mut Vec<String>,
) -> Result<Vec<Column>> {
    let cols = parse_header(file, lineno, fields, spec)?;
    for c in cols.iter().filter(|c| c.factor.is_none()) {
        let name = &c.name;
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
            .filter(|k| spec(k).is_some())
            .find(|k| edit_distance(k, name) <= 2 && name.len() > 1);
        warnings.push(match close {
            Some(k) => format!(
                "{file}:{lineno}: unknown column '{name}' ignored (did you mean '{k}'? without it its default is used)"
            ),
            None => format!("{file}:{lineno}: unknown column '{name}' ignored"),
        });
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

/// A known column's value in SI: the field's number times the column's factor.
fn value(
    file: &str,
    lineno: usize,
    cols: &[Column],
    fields: &[crate::table::Cell],
    i: usize,
) -> Result<f64> {
    let f = &fields[i];
    Ok(number(file, lineno, f.col, &cols[i].name, &f.text)? * cols[i].factor.unwrap_or(1.0))
}

/// The columns of a path CSV as its header names them.
#[derive(Default)]
struct PathColumns {
    cols: Vec<Column>,
    /// Indices of the x, y, z columns.
    idx: Vec<usize>,
    speed_i: Option<usize>,
    print_i: Option<usize>,
}

impl PathColumns {
    /// One data row: its point, whether it prints, and its speed (the default for its kind
    /// without a speed column).
    fn row(
        &self,
        file: &str,
        lineno: usize,
        fields: &[crate::table::Cell],
        opts: &ReadOptions,
    ) -> Result<(V3, bool, f64)> {
        let mut p = V3::zeros();
        for (k, &i) in self.idx.iter().enumerate() {
            p[k] = value(file, lineno, &self.cols, fields, i)?;
        }
        let print = match self.print_i {
            Some(i) => match fields[i].text.to_ascii_lowercase().as_str() {
                "1" | "true" => true,
                "0" | "false" => false,
                other => {
                    return Err(perr(
                        file,
                        lineno,
                        fields[i].col,
                        format!("expected 0 or 1 for 'print', found '{other}'"),
                    ))
                }
            },
            None => true,
        };
        let speed = match self.speed_i {
            Some(i) => {
                let v = value(file, lineno, &self.cols, fields, i)?;
                if v <= 0.0 {
                    return Err(perr(
                        file,
                        lineno,
                        fields[i].col,
                        format!("expected a positive speed, found '{}'", fields[i].text),
                    ));
                }
                v
            }
            None if print => opts.default_print_speed,
            None => opts.default_travel_speed,
        };
        Ok((p, print, speed))
    }
}

/// A `# MARK name` comment: a mark at the path's end so far (`length` along it, m).
fn push_mark(tp: &mut Toolpath, comment: &str, length: f64) {
    if let Some(rest) = comment.strip_prefix("MARK ") {
        if let Some(name) = rest.split_whitespace().next() {
            tp.marks.push(Mark {
                name: name.to_string(),
                point: tp.end(),
                s: length,
            });
        }
    }
}

/// Parse a CSV path; `file` names the source in messages. See the module docs.
pub fn parse_csv(text: &str, file: &str, opts: &ReadOptions) -> Result<Toolpath> {
    let mut tp = Toolpath {
        source: file.to_string(),
        ..Default::default()
    };
    let mut layout = PathColumns::default();
    let mut have_start = false;
    let mut length = 0.0;
    let units = opts.path_units.unwrap_or(PathUnits::Mm);
    let kind = |n: &str| match n {
        "x" | "y" | "z" => Some(ColumnSpec::default_unit(Dim::Length, units.symbol())),
        "speed" => Some(ColumnSpec::default_unit(Dim::Speed, units.speed_symbol())),
        "print" => Some(ColumnSpec::si(Dim::Flag)),
        _ => None,
    };
    // How the coordinates were read, for the extent warning.
    let mut read_as = String::new();
    for row in lines(text) {
        match row {
            Line::Header(lineno, fields) => {
                let cols = header(file, lineno, &fields, &kind, &mut tp.warnings)?;
                let idx = require(file, lineno, &cols, &["x", "y", "z"])?;
                layout = PathColumns {
                    speed_i: cols.iter().position(|c| c.name == "speed"),
                    print_i: cols.iter().position(|c| c.name == "print"),
                    cols,
                    idx,
                };
                read_as = coordinate_units(
                    file,
                    lineno,
                    &layout.cols,
                    &layout.idx,
                    opts,
                    &mut tp.warnings,
                );
            }
            Line::Comment(_, c) => push_mark(&mut tp, &c, length),
            Line::Data(lineno, fields, eol) => {
                check_count(file, lineno, &fields, layout.cols.len(), eol)?;
                let (p, print, speed) = layout.row(file, lineno, &fields, opts)?;
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
    if layout.cols.is_empty() {
        return Err(perr(
            file,
            1,
            1,
            "expected a header line such as 'x[mm],y[mm],z[mm]', found an empty file",
        ));
    }
    extent_warning(&mut tp, file, &read_as, opts.scale);
    Ok(tp)
}

/// Which units the coordinate columns `idx` were read in, as a phrase for the extent warning
/// ("read as mm (stated in the header)"); pushes the warning that mm was assumed when neither
/// the header nor [`ReadOptions::path_units`] states a unit, and the one that the header
/// overrides a different [`ReadOptions::path_units`].
fn coordinate_units(
    file: &str,
    lineno: usize,
    cols: &[Column],
    idx: &[usize],
    opts: &ReadOptions,
    warnings: &mut Vec<String>,
) -> String {
    let stated: Vec<&str> = idx
        .iter()
        .map(|&i| cols[i].unit.as_str())
        .filter(|u| !u.is_empty())
        .collect();
    let unstated = stated.len() < idx.len();
    if let Some(u) = opts.path_units {
        if let Some(s) = stated.iter().find(|s| !s.eq_ignore_ascii_case(u.symbol())) {
            warnings.push(format!(
                "{file}:{lineno}: the header states [{s}]; it wins over the path units {} given",
                u.symbol()
            ));
        }
    }
    match (unstated, opts.path_units) {
        (false, _) => {
            let mut units = stated.clone();
            units.dedup();
            format!("read as {} (stated in the header)", units.join("/"))
        }
        (true, Some(u)) => format!("read as {} (the path units given)", u.symbol()),
        (true, None) => {
            warnings.push(format!(
                "{file}:{lineno}: x, y, z have no unit; mm assumed (state it in the header, \
                 x[mm],y[mm],z[mm] or x[m],y[m],z[m], or set the path units to mm or m)"
            ));
            "read as mm (assumed: the header states no unit)".to_string()
        }
    }
}

/// The x, y, z and yaw of a placements row (index 0 left for the name), SI; a coordinate no
/// arm reaches is refused at its row and column.
fn placement_coords(
    file: &str,
    lineno: usize,
    cols: &[Column],
    idx: &[usize],
    fields: &[crate::table::Cell],
) -> Result<[f64; 5]> {
    let mut v = [0.0; 5];
    for (k, &i) in idx.iter().enumerate().skip(1) {
        v[k] = value(file, lineno, cols, fields, i)?;
        // A coordinate no arm reaches is named at its row and column, with the
        // column's unit (the set's own, not the command line's metres).
        if (1..=3).contains(&k) && v[k].abs() >= crate::frame::MAX_PLAUSIBLE_M {
            let f = &fields[i];
            return Err(perr(
                file,
                lineno,
                f.col,
                format!(
                    "{} = {} reads as {} m (column unit {}): no robot reaches that \
                     far; check the value or the column's unit",
                    cols[i].name,
                    f.text,
                    crate::table::show(v[k]),
                    if cols[i].unit.is_empty() {
                        "mm, the default"
                    } else {
                        cols[i].unit.as_str()
                    }
                ),
            ));
        }
    }
    Ok(v)
}

/// Parse named placements: header `name,x[mm],y[mm],z[mm],yaw[deg]`, optional
/// `nozzle_spin[deg]`; lengths default to mm and angles to degrees. Returns m and rad.
pub fn parse_placements(text: &str, file: &str) -> Result<Vec<NamedPlacement>> {
    let kind = |n: &str| match n {
        "x" | "y" | "z" => Some(ColumnSpec::default_unit(Dim::Length, "mm")),
        "yaw" | "nozzle_spin" => Some(ColumnSpec::default_unit(Dim::Rotation, "deg")),
        "name" => Some(ColumnSpec::si(Dim::Text)),
        _ => None,
    };
    let mut warnings = Vec::new();
    let mut cols: Vec<Column> = Vec::new();
    let mut idx = Vec::new();
    let mut spin_i = None;
    let mut out = Vec::new();
    for row in lines(text) {
        match row {
            Line::Header(lineno, fields) => {
                cols = header(file, lineno, &fields, &kind, &mut warnings)?;
                idx = require(file, lineno, &cols, &["name", "x", "y", "z", "yaw"])?;
                spin_i = cols.iter().position(|c| c.name == "nozzle_spin");
            }
            Line::Comment(..) => {}
            Line::Data(lineno, fields, eol) => {
                check_count(file, lineno, &fields, cols.len(), eol)?;
                let v = placement_coords(file, lineno, &cols, &idx, &fields)?;
                let spin = match spin_i {
                    Some(i) => value(file, lineno, &cols, &fields, i)?,
                    None => 0.0,
                };
                let name = &fields[idx[0]];
                if name.text.is_empty() {
                    return Err(perr(
                        file,
                        lineno,
                        name.col,
                        "expected a name, found nothing",
                    ));
                }
                out.push(NamedPlacement {
                    name: name.text.clone(),
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
