//! Measured logs as `docs/measurement-logs.md` specifies them: `t`, `q1..qN`, optional
//! `qd`/`qdd`, and one compared signal (`tau1..N`, `i1..N`, `p1..N` or `p_total`); units in
//! headers; `#` comments and `# key: value` metadata; unknown columns kept with one warning;
//! column maps for header-less controller exports.
//!
//! Velocities and accelerations missing from the log are derived from `q` by a local cubic
//! least-squares fit (a Savitzky–Golay filter generalised to non-uniform time stamps) over a
//! window of `2m + 1` samples, `m = clamp(round(0.025 s × rate), 2, 30)`: about 50 ms of data,
//! 13 samples at 250 Hz, 7 at 100 Hz. The fit smooths encoder noise before differencing
//! (zero phase: the window is centred; it is shifted inwards at the ends).

use crate::error::{Error, Result};
use crate::identify::motion::LogMotion;
use crate::table::{Dim, Table};
use std::path::Path;

/// Minimum number of samples of a log used for fitting.
pub(crate) const MIN_SAMPLES: usize = 50;

/// Which signal a log carries.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SignalKind {
    /// Joint torques `tau1..N`, N·m.
    Torque,
    /// Motor currents `i1..N`, A.
    Current,
    /// Electrical power per axis `p1..N`, W.
    AxisPower,
    /// Supply power `p_total`, W.
    TotalPower,
}

impl SignalKind {
    /// Column prefix (`tau`, `i`, `p`, `p_total`).
    pub fn prefix(&self) -> &'static str {
        match self {
            SignalKind::Torque => "tau",
            SignalKind::Current => "i",
            SignalKind::AxisPower => "p",
            SignalKind::TotalPower => "p_total",
        }
    }
    /// SI unit of the signal.
    pub fn unit(&self) -> &'static str {
        match self {
            SignalKind::Torque => "N·m",
            SignalKind::Current => "A",
            SignalKind::AxisPower | SignalKind::TotalPower => "W",
        }
    }
    /// Parse `tau`, `i`, `p`, `p_total`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "tau" => Some(SignalKind::Torque),
            "i" => Some(SignalKind::Current),
            "p" => Some(SignalKind::AxisPower),
            "p_total" => Some(SignalKind::TotalPower),
            _ => None,
        }
    }
    /// Number of channels for a robot of `n` joints.
    pub fn channels(&self, n: usize) -> usize {
        if *self == SignalKind::TotalPower {
            1
        } else {
            n
        }
    }
}

/// A measured log, SI units, with derivatives filled.
#[derive(Debug)]
pub struct Log {
    /// File name for messages.
    pub file: String,
    /// Motion: `t` s, `q` rad; velocities rad/s and accelerations rad/s² by
    /// [`LogMotion::rates`].
    pub traj: LogMotion,
    /// The compared signal.
    pub kind: SignalKind,
    /// Measured signal, row-major `len × channels` (units of [`SignalKind::unit`]).
    pub y: Vec<f64>,
    /// Channels per sample (N, or 1 for `p_total`).
    pub channels: usize,
    /// `# key: value` metadata.
    pub metadata: Vec<(String, String)>,
    /// Warnings (unknown columns, ignored signals, derived derivatives).
    pub warnings: Vec<String>,
    /// Column names and the units written in the header (empty when none).
    pub units: Vec<(String, String)>,
    /// 1-based line of the header row (0 for a column map).
    pub header_line: usize,
    /// Source line of each sample (4 bytes a sample: a log of more lines is refused).
    pub lines: Vec<u32>,
    /// Half-width `m` of the derivative window when velocities/accelerations were derived.
    pub derivative_half_window: Option<usize>,
}

impl Log {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.traj.len()
    }
    /// Whether the log has no samples.
    pub fn is_empty(&self) -> bool {
        self.traj.is_empty()
    }
    /// Mean sample rate, Hz.
    pub fn rate_hz(&self) -> f64 {
        let d = self.traj.duration();
        if d > 0.0 {
            (self.len() - 1) as f64 / d
        } else {
            0.0
        }
    }
}

fn digits_after<'a>(name: &'a str, p: &str) -> Option<&'a str> {
    name.strip_prefix(p)
        .filter(|r| !r.is_empty() && r.chars().all(|c| c.is_ascii_digit()))
}

/// Dimension of a log column from its name; `None` for unknown columns.
pub(crate) fn log_dim(name: &str) -> Option<Dim> {
    if let Some(d) = crate::trajectory::trajectory_dim(name) {
        return Some(d);
    }
    if name == "p_total" || digits_after(name, "p").is_some() {
        Some(Dim::Power)
    } else if digits_after(name, "tau").is_some() {
        Some(Dim::Torque)
    } else if digits_after(name, "i").is_some() {
        Some(Dim::Current)
    } else {
        None
    }
}

/// Expand a column map such as `t, q1..q6[deg], qd1..qd6, i1..i6, skip*12` into header cells.
pub(crate) fn expand_column_map(map: &str) -> Result<Vec<String>> {
    let mut out = Vec::new();
    let mut skip = 0usize;
    for raw in map.split(',') {
        let item = raw.trim();
        if item.is_empty() {
            return Err(Error::Invalid(format!("column map `{map}`: empty entry")));
        }
        let (body, unit) = match (item.find('['), item.ends_with(']')) {
            (Some(i), true) => (&item[..i], &item[i..]),
            _ => (item, ""),
        };
        let body = body.trim();
        if let Some(count) = body.strip_prefix("skip") {
            let k = if count.is_empty() {
                1
            } else {
                count
                    .trim_start_matches('*')
                    .trim()
                    .parse::<usize>()
                    .map_err(|_| {
                        Error::Invalid(format!("column map: bad skip count in `{item}`"))
                    })?
            };
            for _ in 0..k {
                skip += 1;
                out.push(format!("skip~{skip}"));
            }
        } else if let Some((a, b)) = body.split_once("..") {
            let split = |s: &str| -> Option<(String, usize)> {
                let s = s.trim();
                let i = s.find(|c: char| c.is_ascii_digit())?;
                Some((s[..i].to_string(), s[i..].parse().ok()?))
            };
            match (split(a), split(b)) {
                (Some((pa, ka)), Some((pb, kb))) if pa == pb && ka <= kb => {
                    for k in ka..=kb {
                        out.push(format!("{pa}{k}{unit}"));
                    }
                }
                _ => {
                    return Err(Error::Invalid(format!(
                        "column map: cannot expand range `{item}` (use e.g. q1..q6)"
                    )))
                }
            }
        } else {
            out.push(item.to_string());
        }
    }
    Ok(out)
}

/// Read a log for a robot of `n` joints. `columns`: an optional column map for a file without
/// a header row. Errors name the file, line and column (see the module docs for the checks).
///
/// The file is read line by line and only the columns compared are kept (time, positions,
/// the signal, and velocities and accelerations when the log gives them), so that reading costs
/// no more memory than those values.
pub fn read_log(path: &Path, n: usize, columns: Option<&str>) -> Result<Log> {
    let file = path.display().to_string();
    let mut b = Builder::new(&file, n, columns);
    let lines = crate::table::for_each_line(path, &mut |ln, line| b.feed(ln, line))?;
    b.finish(lines)
}

/// Parse log text; see [`read_log`].
pub fn parse_log(text: &str, file: &str, n: usize, columns: Option<&str>) -> Result<Log> {
    let mut b = Builder::new(file, n, columns);
    let mut count = 0;
    for (i, l) in text.lines().enumerate() {
        count = i + 1;
        b.feed(i + 1, l)?;
    }
    b.finish(count)
}

/// Where the compared columns of a header are.
struct Columns {
    t: usize,
    q: Vec<usize>,
    qd: Option<Vec<usize>>,
    qdd: Option<Vec<usize>>,
    /// The signal's columns, when the header has a signal.
    y: Option<Vec<usize>>,
}

/// A log read one line at a time (see [`read_log`]): the table reader's header, the columns
/// it keeps, and the first time that does not increase. Errors of the header's columns and of
/// the times are reported after every row is read, as a reader of the whole table reports
/// them.
struct Builder<'a> {
    file: String,
    n: usize,
    map: Option<&'a str>,
    /// The column map's header, once expanded.
    map_header: Option<String>,
    /// Whether the column map's header has been read.
    map_fed: bool,
    reader: crate::table::TableReader<'static>,
    /// The compared columns, or the header's error (known once the header is read).
    cols: Option<Result<Columns>>,
    rows: usize,
    first_line: usize,
    last_line: usize,
    t: Vec<f64>,
    q: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
    y: Vec<f64>,
    lines: Vec<u32>,
    not_after: Option<Error>,
}

impl<'a> Builder<'a> {
    fn new(file: &str, n: usize, map: Option<&'a str>) -> Self {
        Builder {
            file: file.to_string(),
            n,
            map,
            map_header: None,
            map_fed: false,
            reader: crate::table::TableReader::new(file, &log_dim),
            cols: None,
            rows: 0,
            first_line: 0,
            last_line: 0,
            t: Vec::new(),
            q: Vec::new(),
            qd: Vec::new(),
            qdd: Vec::new(),
            y: Vec::new(),
            lines: Vec::new(),
            not_after: None,
        }
    }

    /// Expand the column map (once).
    fn map_header(&mut self) -> Result<Option<String>> {
        if let (Some(map), None) = (self.map, &self.map_header) {
            self.map_header = Some(expand_column_map(map)?.join(","));
        }
        Ok(self.map_header.clone())
    }

    /// Read the column map's header as line `ln`; its errors name the map.
    fn feed_map(&mut self, ln: usize) -> Result<()> {
        let Some(header) = self.map_header()? else {
            return Ok(());
        };
        self.map_fed = true;
        let map = self.map.unwrap_or_default();
        self.reader.feed(ln, &header).map_err(|e| match e {
            Error::Parse {
                file, column, msg, ..
            } => Error::Invalid(format!(
                "{file}: column map `{map}` (entry at character {column}): {msg}"
            )),
            e => e,
        })?;
        self.header_read();
        Ok(())
    }

    fn feed(&mut self, ln: usize, line: &str) -> Result<()> {
        if self.map.is_some() && !self.map_fed {
            self.map_header()?;
            let l = line.trim();
            if !l.is_empty() && !l.starts_with('#') {
                self.feed_map(ln)?;
            }
        }
        let had_header = !self.reader.header().names.is_empty();
        if !self.reader.feed(ln, line)? {
            if !had_header && !self.reader.header().names.is_empty() {
                self.header_read();
            }
            return Ok(());
        }
        self.rows += 1;
        if self.first_line == 0 {
            self.first_line = ln;
        }
        self.last_line = ln;
        let Some(Ok(c)) = &self.cols else {
            return Ok(());
        };
        if self.not_after.is_some() {
            return Ok(());
        }
        let row = self.reader.row();
        let t = row[c.t];
        if let Some(prev) = self.t.last() {
            if t <= *prev {
                self.not_after = Some(Error::Parse {
                    file: self.file.clone(),
                    line: ln,
                    column: 1,
                    msg: format!(
                        "time `t` = {} s is not after the previous sample's {} s",
                        crate::table::show(t),
                        crate::table::show(*prev)
                    ),
                });
                return Ok(());
            }
        }
        self.t.push(t);
        self.q.extend(c.q.iter().map(|&k| row[k]));
        if let Some(v) = &c.qd {
            self.qd.extend(v.iter().map(|&k| row[k]));
        }
        if let Some(v) = &c.qdd {
            self.qdd.extend(v.iter().map(|&k| row[k]));
        }
        if let Some(v) = &c.y {
            self.y.extend(v.iter().map(|&k| row[k]));
        }
        self.lines.push(u32::try_from(ln).map_err(|_| Error::Parse {
            file: self.file.clone(),
            line: ln,
            column: 1,
            msg: format!("a log of more than {} lines cannot be read", u32::MAX),
        })?);
        Ok(())
    }

    /// The header is read: find the compared columns.
    fn header_read(&mut self) {
        let table = self.reader.header();
        let n = self.n;
        self.cols = Some(
            crate::trajectory::columns(table, n).map(|(t, q, qd, qdd)| Columns {
                t,
                q,
                qd,
                qdd,
                y: signal(table, n).ok().map(|(_, cols, _)| cols),
            }),
        );
    }

    fn finish(mut self, lines: usize) -> Result<Log> {
        if self.map.is_some() && !self.map_fed {
            self.feed_map(lines + 1)?;
        }
        let file = self.file.clone();
        let n = self.n;
        let table = self.reader.finish()?;
        let cols = match self.cols.take() {
            Some(c) => c?,
            None => crate::trajectory::columns(&table, n).map(|(t, q, qd, qdd)| Columns {
                t,
                q,
                qd,
                qdd,
                y: None,
            })?,
        };
        if self.rows < 3 {
            return Err(Error::Invalid(format!(
                "{file}: {} samples; at least 3 are needed",
                self.rows
            )));
        }
        if let Some(e) = self.not_after.take() {
            return Err(e);
        }
        let mut warnings = Vec::new();
        let (kind, _, several) = signal(&table, n)?;
        warnings.extend(several);
        let channels = kind.channels(n);
        let len = self.t.len();
        warnings.extend(unknown_columns(&table, n, &file));
        if len < MIN_SAMPLES {
            return Err(Error::Invalid(format!(
                "{file}: {len} samples (lines {}–{}); at least {MIN_SAMPLES} are needed to compare and fit",
                self.first_line, self.last_line
            )));
        }
        warnings.extend(time_hole(&self.t, &self.lines, &file));
        let (traj, half) = motion(
            &cols,
            n,
            std::mem::take(&mut self.t),
            std::mem::take(&mut self.q),
            std::mem::take(&mut self.qd),
            std::mem::take(&mut self.qdd),
        );
        Ok(Log {
            units: table
                .names
                .iter()
                .cloned()
                .zip(table.units.iter().cloned())
                .collect(),
            header_line: table.header_line,
            file,
            traj,
            kind,
            y: std::mem::take(&mut self.y),
            channels,
            metadata: table.metadata,
            warnings,
            lines: std::mem::take(&mut self.lines),
            derivative_half_window: half,
        })
    }
}

/// One warning naming the header's unknown columns, if any.
fn unknown_columns(table: &Table, n: usize, file: &str) -> Option<String> {
    let known = |name: &str| {
        name.starts_with("skip~")
            || log_dim(name).is_some_and(|_| {
                let idx = |p: &str| digits_after(name, p).and_then(|d| d.parse::<usize>().ok());
                name == "t"
                    || name == "p_total"
                    || ["q", "qd", "qdd", "tau", "i", "p"]
                        .iter()
                        .any(|p| idx(p).is_some_and(|k| k >= 1 && k <= n))
            })
    };
    let unknown: Vec<&str> = table
        .names
        .iter()
        .map(String::as_str)
        .filter(|c| !known(c))
        .collect();
    (!unknown.is_empty())
        .then(|| format!("{file}: ignoring unknown columns {}", unknown.join(", ")))
}

/// The log's motion: velocities and accelerations read from the log, those it lacks filled by
/// smoothed differences of the positions; with the half window used, if any.
fn motion(
    cols: &Columns,
    n: usize,
    t: Vec<f64>,
    q: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
) -> (LogMotion, Option<usize>) {
    let (have_qd, have_qdd) = (cols.qd.is_some(), cols.qdd.is_some());
    let half = (!(have_qd && have_qdd)).then(|| {
        let len = t.len();
        let duration = t.last().copied().unwrap_or(0.0) - t.first().copied().unwrap_or(0.0);
        half_window((len - 1) as f64 / duration.max(1e-12))
    });
    let m = LogMotion::new(n, t, q, &mut |t, q, rows, out| {
        for (r, k) in rows.enumerate() {
            let (a, b) = out[r * 2 * n..(r + 1) * 2 * n].split_at_mut(n);
            a.fill(0.0);
            b.fill(0.0);
            if let Some(m) = half {
                crate::numerics::smooth_differentiate_row(t, q, n, m, k, a, b);
            }
            if have_qd {
                a.copy_from_slice(&qd[k * n..(k + 1) * n]);
            }
            if have_qdd {
                b.copy_from_slice(&qdd[k * n..(k + 1) * n]);
            }
        }
    });
    (m, half)
}

/// A hole in the time axis, named (energy and RMSE integrate across it): the first step over
/// ten times the median and 50 ms longer, with its line in `lines`.
fn time_hole(t: &[f64], lines: &[u32], file: &str) -> Option<String> {
    if t.len() <= 2 {
        return None;
    }
    let mut d: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    let mid = d.len() / 2;
    let median = *d.select_nth_unstable_by(mid, f64::total_cmp).1;
    drop(d);
    let k = t
        .windows(2)
        .map(|w| w[1] - w[0])
        .position(|x| x > 10.0 * median && x > median + 0.05)?;
    Some(format!(
        "{file}:{}: time jumps by {:.3} s from the previous sample (the log's usual step is {:.4} s): a hole in the log; energies and errors are integrated across it",
        lines.get(k + 1).copied().unwrap_or(0),
        t[k + 1] - t[k],
        median
    ))
}

/// The compared signal of a header: its kind, its columns, and a warning when the header has
/// several. Errors: no signal, or a per-joint signal of another count than `n` (naming the
/// header line).
fn signal(table: &Table, n: usize) -> Result<(SignalKind, Vec<usize>, Option<String>)> {
    let file = &table.file;
    let count = |p: &str| {
        (1..=64)
            .take_while(|k| table.col(&format!("{p}{k}")).is_some())
            .count()
    };
    let mut found = Vec::new();
    for (kind, k) in [
        (SignalKind::Torque, count("tau")),
        (SignalKind::Current, count("i")),
        (SignalKind::AxisPower, count("p")),
        (
            SignalKind::TotalPower,
            usize::from(table.col("p_total").is_some()),
        ),
    ] {
        if k > 0 {
            found.push((kind, k));
        }
    }
    let Some(&(kind, k)) = found.first() else {
        return Err(Error::Field {
            file: file.clone(),
            field: "header".into(),
            msg: format!(
                "no compared signal: expected one of tau1..tau{n}, i1..i{n}, p1..p{n} or p_total"
            ),
        });
    };
    let several = (found.len() > 1).then(|| {
        format!(
            "{file}: several signals ({}); comparing `{}`",
            found
                .iter()
                .map(|(s, _)| s.prefix())
                .collect::<Vec<_>>()
                .join(", "),
            kind.prefix()
        )
    });
    if kind != SignalKind::TotalPower && k != n {
        return Err(Error::SizeMismatch {
            what: format!(
                "{file}: line {} (header): columns {p}1..{p}N (the robot has {n} joints)",
                table.header_line,
                p = kind.prefix()
            ),
            got: k,
            expected: n,
        });
    }
    let cols: Vec<usize> = if kind == SignalKind::TotalPower {
        vec![table.col("p_total").unwrap_or(0)]
    } else {
        (1..=n)
            .map(|j| table.col(&format!("{}{j}", kind.prefix())).unwrap_or(0))
            .collect()
    };
    Ok((kind, cols, several))
}

/// Half-width `m` of the derivative window for a sample rate in Hz: about 25 ms each side,
/// `clamp(round(0.025 × rate), 2, 30)`.
pub(crate) fn half_window(rate_hz: f64) -> usize {
    ((0.025 * rate_hz).round() as usize).clamp(2, 30)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A log text of `rows` rows at 250 Hz with slightly uneven time stamps, two joints,
    /// torques; with velocity columns when `qd`.
    fn log_text(rows: usize, qd: bool) -> String {
        let mut s = String::from(if qd {
            "t,q1,q2,qd1,qd2,tau1,tau2\n"
        } else {
            "t,q1,q2,tau1,tau2\n"
        });
        for k in 0..rows {
            let t = k as f64 * 0.004 + 1e-5 * ((k * 7) % 3) as f64;
            let (a, b) = ((0.7 * t).sin(), (1.3 * t).cos() * 0.5);
            if qd {
                s += &format!(
                    "{t:.6},{a:.9},{b:.9},{:.9},{:.9},1.5,-2.5\n",
                    0.7 * t.cos(),
                    -0.65 * (1.3 * t).sin()
                );
            } else {
                s += &format!("{t:.6},{a:.9},{b:.9},1.5,-2.5\n");
            }
        }
        s
    }

    #[test]
    fn a_long_logs_derived_and_read_rates_equal_the_whole_log_derivatives_bit_for_bit() {
        let rows = crate::identify::motion::IN_MEMORY_ROWS + 1234;
        for with_qd in [false, true] {
            let log = parse_log(&log_text(rows, with_qd), "long.csv", 2, None).unwrap();
            assert!(
                log.traj.rates_in_file(),
                "a log of {rows} rows keeps its rates in a file"
            );
            let m = log.derivative_half_window.unwrap();
            let (qd, qdd) = crate::numerics::smooth_differentiate(&log.traj.t, &log.traj.q, 2, m);
            let text = log_text(rows, with_qd);
            let read_qd: Vec<f64> = text
                .lines()
                .skip(1)
                .flat_map(|l| {
                    let c: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
                    if with_qd {
                        vec![c[3], c[4]]
                    } else {
                        vec![]
                    }
                })
                .collect();
            for k in (0..rows).step_by(97).chain([0, rows - 1, rows / 2]) {
                let r = log.traj.rates(k);
                for j in 0..2 {
                    let want_qd = if with_qd {
                        read_qd[k * 2 + j]
                    } else {
                        qd[k * 2 + j]
                    };
                    assert_eq!(r.qd()[j].to_bits(), want_qd.to_bits(), "qd row {k}");
                    assert_eq!(
                        r.qdd()[j].to_bits(),
                        qdd[k * 2 + j].to_bits(),
                        "qdd row {k}"
                    );
                }
            }
        }
    }
}
