//! A measured log's motion: its times and positions in memory, its velocities and
//! accelerations (read from the log or derived from the positions) as `2n` columns
//! ([`Columns`]: velocities then accelerations, joint by joint) in memory for a log of at
//! most [`IN_MEMORY_ROWS`] rows, and for a longer log in a temporary file. A long log's memory
//! then holds its times, positions and signal (what its text carries), not the twice as large
//! velocities and accelerations.
//!
//! The analyses that pass over the whole log read one joint's column at a time
//! ([`LogMotion::column`]); the per-row work (predictions, fits) reads a row's rates
//! ([`LogMotion::rates`]), a block of [`BLOCK_ROWS`] rows of every column at a time, each
//! thread keeping the last [`KEPT_BLOCKS`] blocks it read. Reads are positioned, so any
//! number of threads read at once. When no temporary file can be written the columns stay in
//! memory; the numbers read back are the same either way.

use crate::identify::columns::Columns;
use crate::kinematics::MAX_DOF;
use std::ops::Range;

/// Rows up to which a log's velocities and accelerations stay in memory (9.6 MB for six
/// joints): as many as the fits keep of any log.
pub(crate) const IN_MEMORY_ROWS: usize = 100_000;

/// Rows of every column a thread reads from the file at a time (96 KB for six joints).
pub(crate) const BLOCK_ROWS: usize = 1024;

/// Blocks of rates each thread keeps (a block goes to slot `block % KEPT_BLOCKS`): passes
/// that read several stretches of the log in turn each keep theirs.
pub(crate) const KEPT_BLOCKS: usize = 4;

/// Which rate a column holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rate {
    /// Velocity, rad/s (m/s for a prismatic joint).
    Velocity,
    /// Acceleration, rad/s² (m/s²).
    Acceleration,
}

/// Velocities (rad/s) and accelerations (rad/s²) of one sample of a log.
#[derive(Clone, Copy, Debug)]
pub struct Rates {
    n: usize,
    v: [f64; 2 * MAX_DOF],
}

impl Rates {
    /// Velocities, rad/s.
    pub fn qd(&self) -> &[f64] {
        &self.v[..self.n]
    }
    /// Accelerations, rad/s².
    pub fn qdd(&self) -> &[f64] {
        &self.v[self.n..2 * self.n]
    }
    /// Velocities then accelerations (`2n` values).
    pub(crate) fn both(&self) -> &[f64] {
        &self.v[..2 * self.n]
    }
    /// Rates of `n` joints from `2n` values (velocities then accelerations).
    pub(crate) fn from_both(n: usize, both: &[f64]) -> Self {
        let mut v = [0.0; 2 * MAX_DOF];
        v[..2 * n].copy_from_slice(&both[..2 * n]);
        Rates { n, v }
    }
}

/// What writes a block of rows' rates: `fill(t, q, rows, slots)` (`rows.len() × 2n`,
/// row-major, velocities then accelerations).
pub(crate) type Fill<'a> = dyn FnMut(&[f64], &[f64], Range<usize>, &mut [f64]) + 'a;

/// The motion of a measured log, SI units.
#[derive(Debug)]
pub struct LogMotion {
    /// Number of joints.
    pub n: usize,
    /// Sample times, s, strictly increasing.
    pub t: Vec<f64>,
    /// Positions, rad (row-major, `t.len() * n`).
    pub q: Vec<f64>,
    /// Velocities (columns `0..n`) and accelerations (`n..2n`).
    rates: Columns,
    /// A number no other motion of this process has (the threads' kept blocks are keyed by
    /// it).
    id: u64,
}

impl LogMotion {
    /// The motion of `t` and `q` (`n` joints), with the rates of rows `rows` written into
    /// their slots by `fill(t, q, rows, slots)`, a block of rows at a time, in order.
    pub(crate) fn new(n: usize, t: Vec<f64>, q: Vec<f64>, fill: &mut Fill) -> Self {
        static NEXT_ID: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
        let len = t.len();
        let w = 2 * n;
        let write = |cols: &mut Columns, fill: &mut Fill| -> bool {
            const WRITE_ROWS: usize = 8 * BLOCK_ROWS;
            let mut vals = vec![0.0; WRITE_ROWS.min(len) * w];
            let mut k0 = 0;
            while k0 < len {
                let rows = k0..(k0 + WRITE_ROWS).min(len);
                let v = &mut vals[..rows.len() * w];
                fill(&t, &q, rows.clone(), v);
                if cols.write_rows(k0, v).is_err() {
                    return false;
                }
                k0 = rows.end;
            }
            true
        };
        let mut rates = if len > IN_MEMORY_ROWS {
            Columns::new(len, w)
        } else {
            Columns::in_memory(len, w)
        };
        if !write(&mut rates, fill) {
            // The file failed: in memory.
            rates = Columns::in_memory(len, w);
            write(&mut rates, fill);
        }
        LogMotion {
            n,
            t,
            q,
            rates,
            id: NEXT_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
        }
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

    /// Time span, s.
    pub fn duration(&self) -> f64 {
        match (self.t.first(), self.t.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        }
    }

    /// Whether the rates are kept in a temporary file (a log of more than
    /// [`IN_MEMORY_ROWS`] rows, when the file could be written).
    pub(crate) fn rates_in_file(&self) -> bool {
        self.rates.in_file()
    }

    /// Joint `j`'s velocity or acceleration, every row (one column read). Errors: the
    /// temporary file cannot be read.
    pub fn column(&self, j: usize, rate: Rate) -> crate::error::Result<Vec<f64>> {
        let c = match rate {
            Rate::Velocity => j,
            Rate::Acceleration => self.n + j,
        };
        self.rates.column(c)
    }

    /// Velocities and accelerations of sample `k` (`k < len`). A read of the temporary file
    /// that fails (the disk failing under a running process) gives NaN, which every output's
    /// finiteness check then reports.
    pub fn rates(&self, k: usize) -> Rates {
        let n = self.n;
        let w = 2 * n;
        let mut v = [0.0; 2 * MAX_DOF];
        if !self.rates.in_file() {
            for (c, x) in v[..w].iter_mut().enumerate() {
                *x = self.rates.in_memory_at(c, k).unwrap_or(f64::NAN);
            }
            return Rates { n, v };
        }
        let block = k / BLOCK_ROWS;
        KEPT.with(|kept| {
            let mut kept = kept.borrow_mut();
            let slot = &mut kept[block % KEPT_BLOCKS];
            if slot.id != self.id || slot.block != block {
                slot.id = u64::MAX;
                let rows = block * BLOCK_ROWS..((block + 1) * BLOCK_ROWS).min(self.len());
                let m = rows.len();
                slot.vals.resize(w * m, 0.0);
                for c in 0..w {
                    if self
                        .rates
                        .read(c, rows.start, &mut slot.vals[c * m..(c + 1) * m])
                        .is_err()
                    {
                        return Rates {
                            n,
                            v: [f64::NAN; 2 * MAX_DOF],
                        };
                    }
                }
                (slot.id, slot.block, slot.rows) = (self.id, block, m);
            }
            let r = k - block * BLOCK_ROWS;
            for (c, x) in v[..w].iter_mut().enumerate() {
                *x = slot.vals[c * slot.rows + r];
            }
            Rates { n, v }
        })
    }
}

/// A block of rates a thread read: the motion it came from, its number and rows, its values
/// column by column.
struct Kept {
    id: u64,
    block: usize,
    rows: usize,
    vals: Vec<f64>,
}

thread_local! {
    static KEPT: std::cell::RefCell<[Kept; KEPT_BLOCKS]> = std::cell::RefCell::new(
        std::array::from_fn(|_| Kept { id: u64::MAX, block: 0, rows: 0, vals: Vec::new() }),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A motion of `len` rows whose rates are a known function of the row.
    fn motion(len: usize) -> LogMotion {
        let n = 6;
        let t: Vec<f64> = (0..len).map(|k| k as f64 * 0.004).collect();
        let q = vec![0.0; len * n];
        LogMotion::new(n, t, q, &mut |_, _, rows, out| {
            for (r, k) in rows.enumerate() {
                for c in 0..2 * n {
                    out[r * 2 * n + c] = (k * 12 + c) as f64 * 0.37 + f64::EPSILON * k as f64;
                }
            }
        })
    }

    #[test]
    fn a_long_logs_rates_read_back_from_their_file_the_exact_numbers_from_any_thread_in_any_order()
    {
        let len = IN_MEMORY_ROWS + 3 * BLOCK_ROWS + 7;
        let m = motion(len);
        assert!(m.rates_in_file());
        let want = |k: usize, c: usize| (k * 12 + c) as f64 * 0.37 + f64::EPSILON * k as f64;
        let rows: Vec<usize> = [
            0,
            1,
            len - 1,
            BLOCK_ROWS - 1,
            BLOCK_ROWS,
            77_777,
            5,
            len - 2,
        ]
        .into_iter()
        .chain((0..len).step_by(997))
        .collect();
        std::thread::scope(|s| {
            for rev in [false, true] {
                let (m, rows) = (&m, &rows);
                s.spawn(move || {
                    let order: Vec<usize> = if rev {
                        rows.iter().rev().copied().collect()
                    } else {
                        rows.clone()
                    };
                    for k in order {
                        let r = m.rates(k);
                        for c in 0..6 {
                            assert_eq!(r.qd()[c].to_bits(), want(k, c).to_bits(), "row {k}");
                            assert_eq!(r.qdd()[c].to_bits(), want(k, 6 + c).to_bits(), "row {k}");
                        }
                    }
                });
            }
        });
        for c in [0, 5] {
            let col = m.column(c, Rate::Acceleration).unwrap();
            assert!((0..len)
                .step_by(101)
                .all(|k| col[k].to_bits() == want(k, 6 + c).to_bits()));
        }
        // Two long motions at once: each thread's kept block belongs to one of them.
        let other = motion(len);
        for k in [3, 3 + BLOCK_ROWS] {
            assert_eq!(
                m.rates(k).qd()[0].to_bits(),
                other.rates(k).qd()[0].to_bits()
            );
        }
    }

    #[test]
    fn a_short_logs_rates_stay_in_memory() {
        let m = motion(1000);
        assert!(!m.rates_in_file());
        assert_eq!(
            m.rates(999).qdd()[5],
            (999 * 12 + 11) as f64 * 0.37 + f64::EPSILON * 999.0
        );
    }
}
