//! Writing results: files appear complete or not at all (written to a temporary name, then
//! renamed), and no input the user gave is ever overwritten.

use crate::error::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Refuse to write `out` if it is one of `inputs` (compared after canonicalisation).
pub fn guard_inputs(out: &Path, inputs: &[&Path]) -> Result<()> {
    let canon = |p: &Path| std::fs::canonicalize(p).ok();
    if let Some(o) = canon(out) {
        for i in inputs {
            if canon(i).as_ref() == Some(&o) {
                return Err(Error::Invalid(format!(
                    "refusing to write {}: it is an input of this command",
                    out.display()
                )));
            }
        }
    }
    Ok(())
}

/// Write `contents` to `path` atomically: a sibling temporary file, then a rename.
pub fn write_atomic(path: &Path, contents: &[u8]) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }
    let tmp: PathBuf = {
        let mut s = path.as_os_str().to_owned();
        s.push(format!(".tmp-{}", std::process::id()));
        s.into()
    };
    let res = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(contents)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = res {
        let _ = std::fs::remove_file(&tmp);
        return Err(Error::io(path, e));
    }
    Ok(())
}

/// Format a CSV: header cells then rows of numbers with full round-trip precision.
pub fn csv_string(header: &[String], rows: impl Iterator<Item = Vec<f64>>) -> String {
    let mut s = header.join(",");
    s.push('\n');
    for r in rows {
        let cells: Vec<String> = r.iter().map(|v| format!("{v}")).collect();
        s.push_str(&cells.join(","));
        s.push('\n');
    }
    s
}
