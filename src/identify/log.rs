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
use crate::table::{Dim, Table};
use crate::trajectory::JointTrajectory;
use std::path::Path;

/// Minimum number of samples of a log used for fitting.
pub const MIN_SAMPLES: usize = 50;

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
#[derive(Clone, Debug)]
pub struct Log {
    /// File name for messages.
    pub file: String,
    /// Motion: `t` s, `q` rad, `qd` rad/s, `qdd` rad/s².
    pub traj: JointTrajectory,
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
    /// Source line of each sample.
    pub lines: Vec<usize>,
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
pub fn log_dim(name: &str) -> Option<Dim> {
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
pub fn expand_column_map(map: &str) -> Result<Vec<String>> {
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
                out.push(format!("skip#{skip}"));
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
pub fn read_log(path: &Path, n: usize, columns: Option<&str>) -> Result<Log> {
    let text = crate::error::read_text(path)?;
    parse_log(&text, &path.display().to_string(), n, columns)
}

/// Parse log text; see [`read_log`].
pub fn parse_log(text: &str, file: &str, n: usize, columns: Option<&str>) -> Result<Log> {
    let table = match columns {
        None => Table::parse(text, file, &log_dim)?,
        Some(map) => {
            let header = expand_column_map(map)?.join(",");
            // Metadata comments stay before the header; the header goes before the first data
            // row. Line numbers are those of the file.
            let mut lines: Vec<&str> = text.lines().collect();
            let first_data = lines
                .iter()
                .position(|l| {
                    let t = l.trim();
                    !t.is_empty() && !t.starts_with('#')
                })
                .unwrap_or(lines.len());
            lines.insert(first_data, &header);
            let joined = lines.join("\n");
            let mut t = Table::parse(&joined, file, &log_dim).map_err(|e| match e {
                Error::Parse {
                    file,
                    line,
                    column,
                    msg,
                } if line > first_data + 1 => Error::Parse {
                    file,
                    line: line - 1,
                    column,
                    msg,
                },
                Error::Parse {
                    file, column, msg, ..
                } => Error::Invalid(format!(
                    "{file}: column map `{map}` (entry at character {column}): {msg}"
                )),
                e => e,
            })?;
            for l in t.lines.iter_mut() {
                *l -= 1;
            }
            t
        }
    };
    from_table(table, n)
}

fn from_table(table: Table, n: usize) -> Result<Log> {
    let file = table.file.clone();
    let mut warnings = Vec::new();
    let (mut traj, supplied) = crate::trajectory::from_table(&table, n)?;
    // The signal.
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
            file,
            field: "header".into(),
            msg: format!(
                "no compared signal: expected one of tau1..tau{n}, i1..i{n}, p1..p{n} or p_total"
            ),
        });
    };
    if found.len() > 1 {
        warnings.push(format!(
            "{file}: several signals ({}); comparing `{}`",
            found
                .iter()
                .map(|(s, _)| s.prefix())
                .collect::<Vec<_>>()
                .join(", "),
            kind.prefix()
        ));
    }
    let channels = kind.channels(n);
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
    let mut y = Vec::with_capacity(table.rows.len() * channels);
    for r in &table.rows {
        y.extend(cols.iter().map(|&c| r[c]));
    }
    // Unknown columns: one warning.
    let known = |name: &str| {
        name.starts_with("skip#")
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
    if !unknown.is_empty() {
        warnings.push(format!(
            "{file}: ignoring unknown columns {}",
            unknown.join(", ")
        ));
    }
    if traj.len() < MIN_SAMPLES {
        return Err(Error::Invalid(format!(
            "{file}: {} samples (lines {}–{}); at least {MIN_SAMPLES} are needed to compare and fit",
            traj.len(),
            table.lines.first().copied().unwrap_or(0),
            table.lines.last().copied().unwrap_or(0)
        )));
    }
    let mut half = None;
    if !supplied.velocities || !supplied.accelerations {
        let rate = (traj.len() - 1) as f64 / traj.duration().max(1e-12);
        let m = half_window(rate);
        half = Some(m);
        let (qd, qdd) = smooth_derivatives(&traj.t, &traj.q, n, m);
        if !supplied.velocities {
            traj.qd = qd;
        }
        if !supplied.accelerations {
            traj.qdd = qdd;
        }
    }
    // A hole in the time axis: name it (energy and RMSE integrate across it).
    if traj.t.len() > 2 {
        let mut d: Vec<f64> = traj.t.windows(2).map(|w| w[1] - w[0]).collect();
        let dt_of = d.clone();
        d.sort_by(f64::total_cmp);
        let median = d[d.len() / 2];
        if let Some(k) = dt_of
            .iter()
            .position(|&x| x > 10.0 * median && x > median + 0.05)
        {
            warnings.push(format!(
                "{file}:{}: time jumps by {:.3} s from the previous sample (the log's usual step is {:.4} s): a hole in the log; energies and errors are integrated across it",
                table.lines.get(k + 1).copied().unwrap_or(0),
                dt_of[k],
                median
            ));
        }
    }
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
        y,
        channels,
        metadata: table.metadata,
        warnings,
        lines: table.lines,
        derivative_half_window: half,
    })
}

/// Half-width `m` of the derivative window for a sample rate in Hz: about 25 ms each side,
/// `clamp(round(0.025 × rate), 2, 30)`.
pub fn half_window(rate_hz: f64) -> usize {
    ((0.025 * rate_hz).round() as usize).clamp(2, 30)
}

/// Velocities (rad/s) and accelerations (rad/s²) of `q` (row-major `len × n`, rad) at times
/// `t` (s) by a local cubic least-squares fit over `2m + 1` samples (Savitzky–Golay on
/// non-uniform time stamps; window shifted inwards at the ends).
pub fn smooth_derivatives(t: &[f64], q: &[f64], n: usize, m: usize) -> (Vec<f64>, Vec<f64>) {
    crate::numerics::smooth_differentiate(t, q, n, m)
}
