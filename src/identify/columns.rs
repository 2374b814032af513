//! Whole-log columns of numbers kept outside memory: a long log's prediction or residual
//! (`len` rows × `width` channels) is written once, channel by channel, to a temporary file
//! (the exact bytes of each `f64`) and read back one channel, or one part of a channel, at a
//! time by the analyses that pass over the whole log. Their memory then holds one channel of
//! the log at a time instead of all of them.
//!
//! The file is created in the system's temporary directory under a new name (never an
//! existing file) and removed when the columns are dropped (on Unix at once: it has no name
//! while it is open). When no temporary file can be written, the columns stay in memory; the
//! numbers read back are the same either way.

use crate::error::{Error, Result};
use std::io::{Seek, SeekFrom, Write};
use std::path::PathBuf;

/// `len × width` numbers, stored channel by channel (see the module docs).
#[derive(Debug)]
pub(crate) struct Columns {
    len: usize,
    width: usize,
    store: Store,
}

#[derive(Debug)]
enum Store {
    /// The temporary file and its path while it still has a name.
    File(std::fs::File, Option<PathBuf>),
    /// Channel-major, in memory.
    Memory(Vec<f64>),
}

impl Columns {
    /// Room for `len` rows of `width` channels, in a temporary file when one can be made.
    pub fn new(len: usize, width: usize) -> Self {
        let store = temp_file()
            .map(|(f, p)| Store::File(f, p))
            .unwrap_or_else(|_| Store::Memory(vec![0.0; len * width]));
        Columns { len, width, store }
    }

    /// Room for `len` rows of `width` channels in memory.
    pub(crate) fn in_memory(len: usize, width: usize) -> Self {
        Columns {
            len,
            width,
            store: Store::Memory(vec![0.0; len * width]),
        }
    }

    /// Rows.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Channels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Write rows `k0..k0 + block.len() / width` from `block` (row-major, `width` a row).
    pub(crate) fn write_rows(&mut self, k0: usize, block: &[f64]) -> Result<()> {
        let w = self.width.max(1);
        let rows = block.len() / w;
        let len = self.len;
        match &mut self.store {
            Store::Memory(v) => {
                for c in 0..w {
                    for r in 0..rows {
                        v[c * len + k0 + r] = block[r * w + c];
                    }
                }
                Ok(())
            }
            Store::File(f, _) => {
                let mut bytes = Vec::with_capacity(rows * 8);
                for c in 0..w {
                    bytes.clear();
                    for r in 0..rows {
                        bytes.extend_from_slice(&block[r * w + c].to_le_bytes());
                    }
                    f.seek(SeekFrom::Start(((c * len + k0) * 8) as u64))
                        .and_then(|_| f.write_all(&bytes))
                        .map_err(io_error)?;
                }
                Ok(())
            }
        }
    }

    /// Rows `k0..k0 + out.len()` of channel `c` into `out` (positioned reads: any number of
    /// threads read at once).
    pub fn read(&self, c: usize, k0: usize, out: &mut [f64]) -> Result<()> {
        let at = c * self.len + k0;
        match &self.store {
            Store::Memory(v) => {
                out.copy_from_slice(&v[at..at + out.len()]);
                Ok(())
            }
            Store::File(f, _) => {
                let mut bytes = vec![0u8; out.len().min(BLOCK_ROWS) * 8];
                let mut done = 0;
                while done < out.len() {
                    let m = (out.len() - done).min(BLOCK_ROWS);
                    read_at(f, &mut bytes[..m * 8], ((at + done) * 8) as u64).map_err(io_error)?;
                    for (o, b) in out[done..done + m].iter_mut().zip(bytes.chunks_exact(8)) {
                        *o = f64::from_le_bytes(b.try_into().unwrap_or([0; 8]));
                    }
                    done += m;
                }
                Ok(())
            }
        }
    }

    /// Whether the numbers are in a temporary file (not in memory).
    pub(crate) fn in_file(&self) -> bool {
        matches!(self.store, Store::File(..))
    }

    /// Row `k` of channel `c` when the numbers are in memory.
    pub(crate) fn in_memory_at(&self, c: usize, k: usize) -> Option<f64> {
        match &self.store {
            Store::Memory(v) => v.get(c * self.len + k).copied(),
            Store::File(..) => None,
        }
    }

    /// Channel `c`, every row.
    pub fn column(&self, c: usize) -> Result<Vec<f64>> {
        let mut out = vec![0.0; self.len];
        self.read(c, 0, &mut out)?;
        Ok(out)
    }

    /// Every channel, row-major `len × width`.
    pub fn rows(&self) -> Result<Vec<f64>> {
        let w = self.width.max(1);
        let mut out = vec![0.0; self.len * w];
        let mut col = vec![0.0; self.len.min(BLOCK_ROWS)];
        for c in 0..w {
            let mut k0 = 0;
            while k0 < self.len {
                let m = (self.len - k0).min(BLOCK_ROWS);
                self.read(c, k0, &mut col[..m])?;
                for (r, v) in col[..m].iter().enumerate() {
                    out[(k0 + r) * w + c] = *v;
                }
                k0 += m;
            }
        }
        Ok(out)
    }
}

impl Drop for Columns {
    fn drop(&mut self) {
        if let Store::File(_, Some(p)) = &self.store {
            let _ = std::fs::remove_file(p);
        }
    }
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

/// Rows a whole-log pass takes at a time.
pub(crate) const BLOCK_ROWS: usize = 32_768;

fn io_error(e: std::io::Error) -> Error {
    Error::io(std::env::temp_dir(), e)
}

/// A new temporary file, opened for reading and writing, and its path unless it could be
/// removed already (Unix: an open file needs no name).
pub(crate) fn temp_file() -> std::io::Result<(std::fs::File, Option<PathBuf>)> {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let dir = std::env::temp_dir();
    let stamp = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    let mut last = None;
    for _ in 0..16 {
        let i = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let path = dir.join(format!(
            "printwatt-columns-{}-{stamp}-{i}.bin",
            std::process::id()
        ));
        match std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create_new(true)
            .open(&path)
        {
            Ok(f) => {
                let named = if cfg!(unix) && std::fs::remove_file(&path).is_ok() {
                    None
                } else {
                    Some(path)
                };
                return Ok((f, named));
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last = Some(e),
            Err(e) => return Err(e),
        }
    }
    Err(last.unwrap_or_else(|| std::io::Error::other("no temporary file")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_read_back_the_exact_numbers_written_in_a_file_and_in_memory() {
        let (len, w) = (70_001, 3);
        let block: Vec<f64> = (0..len * w)
            .map(|i| (i as f64 * 0.37).sin() * 1e3 + f64::EPSILON * i as f64)
            .collect();
        for mut c in [Columns::new(len, w), Columns::in_memory(len, w)] {
            let mut k0 = 0;
            while k0 < len {
                let m = (len - k0).min(BLOCK_ROWS);
                c.write_rows(k0, &block[k0 * w..(k0 + m) * w]).unwrap();
                k0 += m;
            }
            assert_eq!(c.rows().unwrap(), block);
            let col = c.column(2).unwrap();
            assert!(col
                .iter()
                .enumerate()
                .all(|(k, v)| v.to_bits() == block[k * w + 2].to_bits()));
            let mut part = vec![0.0; 5];
            c.read(1, 40_000, &mut part).unwrap();
            assert_eq!(
                part,
                (0..5)
                    .map(|r| block[(40_000 + r) * w + 1])
                    .collect::<Vec<_>>()
            );
        }
    }
}
