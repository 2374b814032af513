//! A small reader for numeric CSV tables as printwatt's inputs use them: `#` comment lines,
//! `# key: value` metadata before the header, one header row whose names may carry a unit in
//! brackets (`t[ms]`, `q3[deg]`, `tau2[kNm]`), then rows of numbers. Units are converted to SI
//! here, on reading, and only here. Every error names the file, the 1-based line and column.

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
    /// Speed: m/s, mm/s, mm/min, m/min.
    Speed,
    /// A plain number.
    Number,
}

/// Factor converting a value in `unit` to SI for dimension `dim`, or `None` if unknown.
pub fn si_factor(dim: Dim, unit: &str) -> Option<f64> {
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
        Dim::Time => match u.as_str() {
            "s" => 1.0,
            "ms" => 1e-3,
            "us" | "µs" => 1e-6,
            "min" => 60.0,
            _ => return None,
        },
        Dim::Angle => match u.as_str() {
            "rad" | "m" => 1.0,
            "deg" | "°" => deg,
            "mm" => 1e-3,
            _ => return None,
        },
        Dim::AngularVelocity => match u.as_str() {
            "rad/s" | "m/s" => 1.0,
            "deg/s" => deg,
            "mm/s" => 1e-3,
            "rpm" => 2.0 * std::f64::consts::PI / 60.0,
            _ => return None,
        },
        Dim::AngularAcceleration => match u.as_str() {
            "rad/s^2" | "rad/s2" | "m/s^2" | "m/s2" => 1.0,
            "deg/s^2" | "deg/s2" => deg,
            "mm/s^2" | "mm/s2" => 1e-3,
            _ => return None,
        },
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
            "in" => 0.0254,
            _ => return None,
        },
        Dim::Speed => match u.as_str() {
            "m/s" => 1.0,
            "mm/s" => 1e-3,
            "mm/min" => 1e-3 / 60.0,
            "m/min" => 1.0 / 60.0,
            _ => return None,
        },
        Dim::Number => match u.as_str() {
            "" | "1" | "-" => 1.0,
            _ => return None,
        },
    };
    Some(f)
}

/// Split `name[unit]` into (lower-cased name, unit).
fn split_unit(h: &str) -> (String, String) {
    let h = h.trim();
    match (h.find('['), h.ends_with(']')) {
        (Some(i), true) => (
            h[..i].trim().to_ascii_lowercase(),
            h[i + 1..h.len() - 1].trim().to_string(),
        ),
        _ => (h.to_ascii_lowercase(), String::new()),
    }
}

impl Table {
    /// Read a CSV file. `dim_of` gives the dimension of a column from its name (unit checks),
    /// or `None` for a column the caller does not know (kept, converted with factor 1 if it
    /// has no unit).
    pub fn read(path: &Path, dim_of: &dyn Fn(&str) -> Option<Dim>) -> Result<Table> {
        let text = read_text(path)?;
        Table::parse(&text, &path.display().to_string(), dim_of)
    }

    /// Parse CSV text; see [`Table::read`].
    pub fn parse(text: &str, file: &str, dim_of: &dyn Fn(&str) -> Option<Dim>) -> Result<Table> {
        let mut t = Table {
            file: file.to_string(),
            ..Default::default()
        };
        let mut factors: Vec<f64> = Vec::new();
        let mut sep = ',';
        let perr = |line: usize, column: usize, msg: String| Error::Parse {
            file: file.to_string(),
            line,
            column,
            msg,
        };
        for (ln0, raw) in text.lines().enumerate() {
            let ln = ln0 + 1;
            let line = raw.trim_end_matches('\r');
            let trimmed = line.trim();
            if trimmed.is_empty() {
                continue;
            }
            if let Some(c) = trimmed.strip_prefix('#') {
                if t.names.is_empty() {
                    if let Some((k, v)) = c.split_once(':') {
                        t.metadata
                            .push((k.trim().to_string(), v.trim().to_string()));
                    }
                }
                continue;
            }
            if t.names.is_empty() {
                sep = crate::toolpath::csv_separator(line);
                t.header_line = ln;
                let mut col = 1;
                for cell in line.split(sep) {
                    let (name, unit) = split_unit(cell);
                    if name.is_empty() {
                        return Err(perr(ln, col, "empty column name in the header".into()));
                    }
                    if t.names.contains(&name) {
                        return Err(perr(
                            ln,
                            col,
                            format!("column `{name}` appears twice in the header"),
                        ));
                    }
                    let f = match dim_of(&name) {
                        Some(d) => si_factor(d, &unit).ok_or_else(|| {
                            perr(
                                ln,
                                col,
                                format!("unknown unit `{unit}` for column `{name}` ({d:?})"),
                            )
                        })?,
                        None if unit.is_empty() => 1.0,
                        None => 1.0,
                    };
                    factors.push(f);
                    t.names.push(name);
                    t.units.push(unit);
                    col += cell.chars().count() + 1;
                }
                if t.names.iter().all(|n| n.parse::<f64>().is_ok()) {
                    return Err(perr(
                        ln,
                        1,
                        "expected a header row of column names, found numbers".into(),
                    ));
                }
                continue;
            }
            let owned;
            let line = if sep == ';' {
                owned = line.replace(',', ".");
                owned.as_str()
            } else {
                line
            };
            let cells: Vec<&str> = line.split(sep).collect();
            if cells.len() != t.names.len() {
                return Err(perr(
                    ln,
                    1,
                    format!(
                        "expected {} values (one per header column), found {}",
                        t.names.len(),
                        cells.len()
                    ),
                ));
            }
            let mut row = Vec::with_capacity(cells.len());
            let mut col = 1;
            for (k, cell) in cells.iter().enumerate() {
                let s = cell.trim();
                let v: f64 = s.parse().map_err(|_| {
                    perr(
                        ln,
                        col,
                        format!("column `{}`: expected a number, found `{s}`", t.names[k]),
                    )
                })?;
                if !v.is_finite() {
                    return Err(perr(
                        ln,
                        col,
                        format!("column `{}`: value `{s}` is not finite", t.names[k]),
                    ));
                }
                row.push(v * factors[k]);
                col += cell.chars().count() + 1;
            }
            t.rows.push(row);
            t.lines.push(ln);
        }
        if t.names.is_empty() {
            return Err(perr(1, 1, "no header row found".into()));
        }
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
            e.contains("d.csv:2:1") && e.contains("expected 2 values"),
            "{e}"
        );
    }
}
