//! A measured log's motion: its times and positions in memory, its velocities and
//! accelerations (read from the log or derived from the positions) in memory for a log of at
//! most [`IN_MEMORY_ROWS`] rows, and for a longer log in a temporary file, read back a block
//! of [`BLOCK_ROWS`] rows at a time. A long log's memory then holds its times, positions and
//! signal (what its text carries), not the twice as large velocities and accelerations.
//!
//! The file holds each row's velocities then accelerations (`2n` numbers, the exact bytes
//! of each `f64`). It is created in the system's temporary directory under a new name and
//! has no name while open on Unix (elsewhere it is removed when the motion is dropped).
//! Reading is positioned (`pread`), so any number of threads read at once; each thread keeps
//! the last block it read. When no temporary file can be written the rates stay in memory;
//! the numbers read back are the same either way.

use crate::kinematics::MAX_DOF;
use std::ops::Range;

/// Rows up to which a log's velocities and accelerations stay in memory (9.6 MB for six
/// joints): as many as the fits keep of any log.
pub(crate) const IN_MEMORY_ROWS: usize = 100_000;

/// Rows a thread reads from the file at a time (48 KB for six joints).
pub(crate) const BLOCK_ROWS: usize = 512;

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

/// What writes a block of rows' rates: `fill(t, q, rows, slots)`.
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
    store: Store,
}

#[derive(Debug)]
enum Store {
    /// Row-major, `2n` a row.
    Memory(Vec<f64>),
    /// The temporary file, its path while it still has a name, and a number no other store
    /// of this process has (the threads' kept blocks are keyed by it).
    File {
        file: std::fs::File,
        path: Option<std::path::PathBuf>,
        id: u64,
    },
}

impl LogMotion {
    /// The motion of `t` and `q` (`n` joints), with the rates of rows `rows` written into
    /// their slots (`rows.len() × 2n`, row-major, velocities then accelerations) by
    /// `fill(t, q, rows, slots)`, a block of rows at a time, in order.
    pub(crate) fn new(n: usize, t: Vec<f64>, q: Vec<f64>, fill: &mut Fill) -> Self {
        let len = t.len();
        let w = 2 * n;
        let store = if len > IN_MEMORY_ROWS {
            to_file(len, w, &mut |rows, out| fill(&t, &q, rows, out))
        } else {
            None
        };
        let store = store.unwrap_or_else(|| {
            let mut v = vec![0.0; len * w];
            fill(&t, &q, 0..len, &mut v);
            Store::Memory(v)
        });
        LogMotion { n, t, q, store }
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
    pub fn rates_in_file(&self) -> bool {
        matches!(self.store, Store::File { .. })
    }

    /// Velocities and accelerations of sample `k` (`k < len`). A read of the temporary file
    /// that fails (the disk failing under a running process) gives NaN, which every output's
    /// finiteness check then reports.
    pub fn rates(&self, k: usize) -> Rates {
        let n = self.n;
        let w = 2 * n;
        match &self.store {
            Store::Memory(v) => Rates::from_both(n, &v[k * w..(k + 1) * w]),
            Store::File { file, id, .. } => {
                let len = self.len();
                KEPT.with(|b| {
                    let mut b = b.borrow_mut();
                    let fresh =
                        b.id == *id && b.rows.contains(&k) && b.bytes.len() >= b.rows.len() * w * 8;
                    if !fresh {
                        let start = k - k % BLOCK_ROWS;
                        let rows = start..(start + BLOCK_ROWS).min(len);
                        b.bytes.resize(rows.len() * w * 8, 0);
                        let ok = read_at(file, &mut b.bytes, (start * w * 8) as u64).is_ok();
                        b.id = if ok { *id } else { u64::MAX };
                        b.rows = if ok { rows } else { 0..0 };
                        if !ok {
                            return Rates {
                                n,
                                v: [f64::NAN; 2 * MAX_DOF],
                            };
                        }
                    }
                    let at = (k - b.rows.start) * w * 8;
                    let mut v = [0.0; 2 * MAX_DOF];
                    for (o, c) in v[..w]
                        .iter_mut()
                        .zip(b.bytes[at..at + w * 8].chunks_exact(8))
                    {
                        *o = f64::from_le_bytes(c.try_into().unwrap_or([0; 8]));
                    }
                    Rates { n, v }
                })
            }
        }
    }
}

impl Drop for LogMotion {
    fn drop(&mut self) {
        if let Store::File { path: Some(p), .. } = &self.store {
            let _ = std::fs::remove_file(p);
        }
    }
}

/// The block of rates a thread read last: the store it came from, its rows, its bytes.
struct Kept {
    id: u64,
    rows: Range<usize>,
    bytes: Vec<u8>,
}

thread_local! {
    static KEPT: std::cell::RefCell<Kept> = const {
        std::cell::RefCell::new(Kept { id: u64::MAX, rows: 0..0, bytes: Vec::new() })
    };
}

/// The rates of `len` rows of width `w` written by `fill` into a new temporary file; `None`
/// when no file can be made or written (the caller keeps them in memory).
fn to_file(len: usize, w: usize, fill: &mut dyn FnMut(Range<usize>, &mut [f64])) -> Option<Store> {
    use std::io::Write;
    static NEXT_ID: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let (file, path) = crate::identify::columns::temp_file().ok()?;
    let drop_path = |p: &Option<std::path::PathBuf>| {
        if let Some(p) = p {
            let _ = std::fs::remove_file(p);
        }
    };
    const WRITE_ROWS: usize = 8 * BLOCK_ROWS;
    let mut vals = vec![0.0; WRITE_ROWS.min(len) * w];
    let mut bytes = Vec::with_capacity(vals.len() * 8);
    let mut out = std::io::BufWriter::new(&file);
    let mut k0 = 0;
    while k0 < len {
        let rows = k0..(k0 + WRITE_ROWS).min(len);
        let v = &mut vals[..rows.len() * w];
        fill(rows.clone(), v);
        bytes.clear();
        for x in v.iter() {
            bytes.extend_from_slice(&x.to_le_bytes());
        }
        if out.write_all(&bytes).is_err() {
            drop(out);
            drop_path(&path);
            return None;
        }
        k0 = rows.end;
    }
    if out.flush().is_err() {
        drop(out);
        drop_path(&path);
        return None;
    }
    drop(out);
    Some(Store::File {
        file,
        path,
        id: NEXT_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
    })
}

/// Fill `buf` from `file` at byte `offset`, without moving a shared file position.
#[cfg(unix)]
fn read_at(file: &std::fs::File, buf: &mut [u8], offset: u64) -> std::io::Result<()> {
    std::os::unix::fs::FileExt::read_exact_at(file, buf, offset)
}

/// Fill `buf` from `file` at byte `offset`, without moving a shared file position.
#[cfg(windows)]
fn read_at(file: &std::fs::File, mut buf: &mut [u8], mut offset: u64) -> std::io::Result<()> {
    while !buf.is_empty() {
        match std::os::windows::fs::FileExt::seek_read(file, buf, offset) {
            Ok(0) => return Err(std::io::ErrorKind::UnexpectedEof.into()),
            Ok(m) => {
                buf = &mut buf[m..];
                offset += m as u64;
            }
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(())
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
