//! Long measurement logs for the memory test and bench: the first rows of a log.

use std::io::{BufRead, Write};
use std::path::Path;

/// Write to `to` the first `rows` data rows of `log`, with its comments and header.
pub fn cut(log: &Path, rows: usize, to: &Path) {
    let r = std::io::BufReader::new(std::fs::File::open(log).expect("log"));
    let mut w = std::io::BufWriter::new(std::fs::File::create(to).expect("cut log"));
    let (mut n, mut header) = (0, false);
    for line in r.lines() {
        let line = line.expect("line");
        let data = !line.starts_with('#');
        if data && header {
            n += 1;
            if n > rows {
                break;
            }
        }
        header |= data;
        writeln!(w, "{line}").expect("write");
    }
}
