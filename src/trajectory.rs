//! Joint trajectories: samples of time, position, velocity and acceleration per joint.

use crate::error::{Error, Result};

/// A sampled joint trajectory. Positions in rad (m for prismatic joints), velocities in
/// rad/s, accelerations in rad/s², times in s. Joint values are stored row-major: sample `k`,
/// joint `j` at index `k * n + j`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct JointTrajectory {
    /// Number of joints.
    pub n: usize,
    /// Sample times, s, strictly increasing.
    pub t: Vec<f64>,
    /// Positions, rad (row-major, `t.len() * n`).
    pub q: Vec<f64>,
    /// Velocities, rad/s (row-major).
    pub qd: Vec<f64>,
    /// Accelerations, rad/s² (row-major).
    pub qdd: Vec<f64>,
}

impl JointTrajectory {
    /// An empty trajectory for `n` joints.
    pub fn new(n: usize) -> Self {
        JointTrajectory {
            n,
            ..Default::default()
        }
    }

    /// Append one sample; slices must have length `n`.
    pub fn push(&mut self, t: f64, q: &[f64], qd: &[f64], qdd: &[f64]) {
        debug_assert!(q.len() == self.n && qd.len() == self.n && qdd.len() == self.n);
        self.t.push(t);
        self.q.extend_from_slice(q);
        self.qd.extend_from_slice(qd);
        self.qdd.extend_from_slice(qdd);
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Positions of sample `k`, rad.
    pub fn q(&self, k: usize) -> &[f64] {
        &self.q[k * self.n..(k + 1) * self.n]
    }

    /// Velocities of sample `k`, rad/s.
    pub fn qd(&self, k: usize) -> &[f64] {
        &self.qd[k * self.n..(k + 1) * self.n]
    }

    /// Accelerations of sample `k`, rad/s².
    pub fn qdd(&self, k: usize) -> &[f64] {
        &self.qdd[k * self.n..(k + 1) * self.n]
    }

    /// Duration, s.
    pub fn duration(&self) -> f64 {
        match (self.t.first(), self.t.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        }
    }

    /// Check that times are finite and strictly increasing and all values finite.
    pub fn validate(&self, what: &str) -> Result<()> {
        for (k, w) in self.t.windows(2).enumerate() {
            if w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater) {
                return Err(Error::Invalid(format!(
                    "{what}: time is not strictly increasing at sample {} (t = {} then {})",
                    k + 1,
                    w[0],
                    w[1]
                )));
            }
        }
        for (name, v) in [("q", &self.q), ("qd", &self.qd), ("qdd", &self.qdd)] {
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                return Err(Error::Invalid(format!(
                    "{what}: {name}{} is not finite at sample {}",
                    i % self.n + 1,
                    i / self.n
                )));
            }
        }
        Ok(())
    }
}

/// Which columns a trajectory file supplied.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Supplied {
    /// `qd1..qdN` were in the file.
    pub velocities: bool,
    /// `qdd1..qddN` were in the file.
    pub accelerations: bool,
}

/// Dimension of a trajectory column from its name (`t`, `qK`, `qdK`, `qddK`).
pub(crate) fn trajectory_dim(name: &str) -> Option<crate::table::Dim> {
    use crate::table::Dim;
    let digits = |p: &str| {
        name.strip_prefix(p)
            .is_some_and(|r| !r.is_empty() && r.chars().all(|c| c.is_ascii_digit()))
    };
    if name == "t" {
        Some(Dim::Time)
    } else if digits("qdd") {
        Some(Dim::AngularAcceleration)
    } else if digits("qd") {
        Some(Dim::AngularVelocity)
    } else if digits("q") {
        Some(Dim::Angle)
    } else {
        None
    }
}

/// Refuse a unit on the wrong kind of joint: a length unit (`q1[mm]`, `qd1[m/s]`) on a revolute
/// joint, an angle unit (`q1[deg]`) on a prismatic one. `names` and `units` are the header's
/// lower-case column names and units; `kinds` the robot's joints in chain order. The error names
/// the file, the header line and the column.
pub(crate) fn check_joint_units(
    file: &str,
    header_line: usize,
    names: &[String],
    units: &[String],
    kinds: &[crate::robot::JointKind],
) -> Result<()> {
    use crate::robot::JointKind;
    for (c, (name, unit)) in names.iter().zip(units).enumerate() {
        let u = unit.trim().to_ascii_lowercase();
        if u.is_empty() {
            continue;
        }
        let idx = ["qdd", "qd", "q"].iter().find_map(|p| {
            name.strip_prefix(p)
                .filter(|r| !r.is_empty() && r.chars().all(|c| c.is_ascii_digit()))
                .and_then(|r| r.parse::<usize>().ok())
        });
        let Some(k) = idx else { continue };
        let Some(kind) = kinds.get(k.wrapping_sub(1)) else {
            continue;
        };
        let Some(linear) = crate::table::joint_unit_is_linear(&u) else {
            continue;
        };
        let wrong = match kind {
            JointKind::Revolute => linear,
            JointKind::Prismatic => !linear,
        };
        if wrong {
            return Err(Error::Parse {
                file: file.to_string(),
                line: header_line,
                column: c + 1,
                msg: format!(
                    "column `{name}[{unit}]`: joint {k} is {}, so `{unit}` is the wrong kind of unit (expected {})",
                    match kind {
                        JointKind::Revolute => "revolute",
                        JointKind::Prismatic => "prismatic",
                    },
                    match kind {
                        JointKind::Revolute => "rad or deg",
                        JointKind::Prismatic => "m or mm",
                    }
                ),
            });
        }
    }
    Ok(())
}

/// Read a joint trajectory CSV for `model` (see [`read_csv`]), refusing units on the wrong
/// kind of joint (see [`check_joint_units`]).
pub fn read_csv_for(
    path: &std::path::Path,
    model: &crate::robot::RobotModel,
) -> Result<(JointTrajectory, Supplied)> {
    let table = crate::table::Table::read(path, &trajectory_dim)?;
    let kinds: Vec<_> = model.joints.iter().map(|j| j.kind).collect();
    check_joint_units(
        &table.file,
        table.header_line,
        &table.names,
        &table.units,
        &kinds,
    )?;
    from_table(&table, model.dof())
}

/// Read a joint trajectory CSV with columns `t, q1..qN` and optionally `qd1..qdN`,
/// `qdd1..qddN` (units in brackets, SI by default). Missing derivatives are left at zero and
/// reported in [`Supplied`]; fill them with central differences before use. Errors name the
/// file, line and column; a joint count that does not match `n` names both numbers.
pub fn read_csv(path: &std::path::Path, n: usize) -> Result<(JointTrajectory, Supplied)> {
    let table = crate::table::Table::read(path, &trajectory_dim)?;
    from_table(&table, n)
}

/// The columns of a trajectory's header: time, positions, and velocities and accelerations
/// when given. Errors (naming the file and header line): no `t`, a count of `q`, `qd` or `qdd`
/// columns other than `n`.
#[allow(clippy::type_complexity)]
pub fn columns(
    table: &crate::table::Table,
    n: usize,
) -> Result<(usize, Vec<usize>, Option<Vec<usize>>, Option<Vec<usize>>)> {
    let file = &table.file;
    let tcol = table.col("t").ok_or_else(|| Error::Field {
        file: file.clone(),
        field: "t".into(),
        msg: "missing the time column `t`".into(),
    })?;
    let count = |p: &str| {
        (1..=64)
            .take_while(|k| table.col(&format!("{p}{k}")).is_some())
            .count()
    };
    let nq = count("q");
    if nq != n {
        return Err(Error::SizeMismatch {
            what: format!(
                "{file}: line {} (header): joint position columns q1..qN (the robot has {n} joints)",
                table.header_line
            ),
            got: nq,
            expected: n,
        });
    }
    let cols = |p: &str| -> Result<Option<Vec<usize>>> {
        let k = count(p);
        if k == 0 {
            return Ok(None);
        }
        if k != n {
            return Err(Error::SizeMismatch {
                what: format!(
                    "{file}: line {} (header): columns {p}1..{p}N",
                    table.header_line
                ),
                got: k,
                expected: n,
            });
        }
        Ok(Some(
            (1..=n)
                .map(|j| table.col(&format!("{p}{j}")).unwrap_or(0))
                .collect(),
        ))
    };
    let qc = cols("q")?.unwrap_or_default();
    let qdc = cols("qd")?;
    let qddc = cols("qdd")?;
    Ok((tcol, qc, qdc, qddc))
}

/// Build a trajectory from a parsed table; see [`read_csv`].
pub(crate) fn from_table(
    table: &crate::table::Table,
    n: usize,
) -> Result<(JointTrajectory, Supplied)> {
    let file = &table.file;
    let (tcol, qc, qdc, qddc) = columns(table, n)?;
    if table.rows.len() < 3 {
        return Err(Error::Invalid(format!(
            "{file}: {} samples; at least 3 are needed",
            table.rows.len()
        )));
    }
    let mut tr = JointTrajectory::new(n);
    let zeros = vec![0.0; n];
    for (r, row) in table.rows.iter().enumerate() {
        if let Some(prev) = tr.t.last() {
            if row[tcol] <= *prev {
                return Err(Error::Parse {
                    file: file.clone(),
                    line: table.lines[r],
                    column: 1,
                    msg: format!(
                        "time `t` = {} s is not after the previous sample's {} s",
                        crate::table::show(row[tcol]),
                        crate::table::show(*prev)
                    ),
                });
            }
        }
        let pick = |c: &Option<Vec<usize>>| {
            c.as_ref()
                .map_or(zeros.clone(), |c| c.iter().map(|&k| row[k]).collect())
        };
        let q: Vec<f64> = qc.iter().map(|&k| row[k]).collect();
        tr.push(row[tcol], &q, &pick(&qdc), &pick(&qddc));
    }
    Ok((
        tr,
        Supplied {
            velocities: qdc.is_some(),
            accelerations: qddc.is_some(),
        },
    ))
}

/// The velocities and accelerations of a trajectory sampled every `dt` s, a block of samples
/// at a time: the trajectory's own when it keeps them, else derived from its positions by
/// the stencil that timing differentiates with
/// ([`crate::numerics::uniform_rates_rows`]: the same values, bit for bit, as the kept
/// ones). A long print's full evaluation keeps only the positions
/// ([`crate::timing::Buffers::lean_rates`]): 96 bytes a sample fewer for a six-axis arm.
pub(crate) struct RateBlocks<'t> {
    traj: &'t JointTrajectory,
    /// The stencil's weights for the period (found once).
    w: [([f64; 3], [f64; 3]); 3],
    level: crate::simd::Level,
    qd: Vec<f64>,
    qdd: Vec<f64>,
}

impl<'t> RateBlocks<'t> {
    /// The rates of `traj`, sampled every `dt` s (at least 3 samples and a finite `dt` > 0
    /// when it keeps only its positions).
    pub(crate) fn new(traj: &'t JointTrajectory, dt: f64) -> Self {
        RateBlocks {
            traj,
            w: crate::numerics::uniform_weights(dt),
            level: crate::simd::level(),
            qd: Vec::new(),
            qdd: Vec::new(),
        }
    }

    /// The velocities and accelerations of samples `k0 .. k0 + count` (row-major, `count × n`
    /// each).
    pub(crate) fn block(&mut self, k0: usize, count: usize) -> (&[f64], &[f64]) {
        let tr = self.traj;
        let n = tr.n;
        let (a, b) = (k0 * n, (k0 + count) * n);
        if tr.qd.len() == tr.q.len() && tr.qdd.len() == tr.q.len() {
            return (&tr.qd[a..b], &tr.qdd[a..b]);
        }
        if self.qd.len() < b - a {
            self.qd.resize(b - a, 0.0);
            self.qdd.resize(b - a, 0.0);
        }
        crate::numerics::uniform_rates_rows(
            &tr.q,
            n,
            &self.w,
            k0,
            count,
            &mut self.qd,
            &mut self.qdd,
            self.level,
        );
        (&self.qd[..b - a], &self.qdd[..b - a])
    }
}
