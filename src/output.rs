//! The output policy, in one place, for every command: nothing the user gave is lost or
//! overwritten, and what printwatt writes appears complete or not at all.
//!
//! - [`Inputs`] knows every file a command reads (a robot directory's files, the URDF and drive
//!   file, paths, sets, logs, validation logs, trajectories); [`Inputs::check`] refuses an
//!   output that is one of them (same canonical path, or the same file by device and inode, as a
//!   hard link is) or a directory that holds one.
//! - [`write_file`] writes one file atomically (a sibling temporary file, then a rename), after
//!   [`Inputs::check`], and refuses to replace an existing file unless told it may.
//! - [`RunDir`] writes a run directory as a whole: it is locked while a run writes it (a lock
//!   file holding the PID; a second run into the same directory fails and names the first),
//!   written into a sibling staging directory, then put in place by one rename. A manifest
//!   (`.printwatt-manifest.json`, SHA-256 of every file written) tells printwatt's own files from
//!   anything else; a directory holding a file printwatt did not write (or that was changed
//!   since) is never replaced. Temporary files and directories and locks of processes that are
//!   no longer running are removed.
//! - [`run_name`] keeps `--run` inside `--results-dir` (no `..`, no absolute path).
//! - [`check_finite`] is the last check before numbers leave: a NaN or an infinity becomes an
//!   error naming the first sample and quantity where it appeared; [`check_finite_json`] does
//!   the same for any serialisable result (every `--json` print and JSON file), naming the JSON
//!   path of the first one.

use crate::error::{Error, Result};
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Component, Path, PathBuf};

/// Name of the manifest file inside a run directory.
pub(crate) const MANIFEST: &str = ".printwatt-manifest.json";

/// Every input file of a command. Outputs are checked against them before anything is written.
#[derive(Clone, Debug, Default)]
pub struct Inputs {
    files: Vec<PathBuf>,
}

/// Identity of a file: canonical path, and (on Unix) device and inode.
#[derive(Clone, Debug, PartialEq)]
struct FileId {
    canon: PathBuf,
    dev_ino: Option<(u64, u64)>,
}

fn file_id(p: &Path) -> Option<FileId> {
    let canon = std::fs::canonicalize(p).ok()?;
    #[cfg(unix)]
    let dev_ino = {
        use std::os::unix::fs::MetadataExt;
        std::fs::metadata(p).ok().map(|m| (m.dev(), m.ino()))
    };
    #[cfg(not(unix))]
    let dev_ino = None;
    Some(FileId { canon, dev_ino })
}

impl Inputs {
    /// No inputs yet.
    pub fn new() -> Self {
        Inputs::default()
    }

    /// Add an input file (or directory).
    pub fn add(&mut self, p: impl AsRef<Path>) -> &mut Self {
        self.files.push(p.as_ref().to_path_buf());
        self
    }

    /// Add a robot as given on the command line (`arg`, after resolving a shipped name) and the
    /// files its model was read from: a robot directory's `robot.urdf` (or other `.urdf`) and
    /// `drive.toml`, the URDF, the drive file (and, for a drive file given alone, the URDF it
    /// names).
    pub fn add_robot(&mut self, arg: &Path, model: Option<&crate::robot::RobotModel>) -> &mut Self {
        self.add(arg);
        let dir = if arg.is_dir() {
            Some(arg.to_path_buf())
        } else {
            None
        };
        if let Some(d) = dir {
            // What `robot::load` reads from a directory: robot.urdf (or its one .urdf) and
            // drive.toml. Other files (an identified drive file written earlier, a README) are
            // not inputs of this command.
            self.files.push(d.join("robot.urdf"));
            self.files.push(d.join("drive.toml"));
            if let Ok(rd) = std::fs::read_dir(&d) {
                for e in rd.flatten() {
                    if e.path().extension().is_some_and(|x| x == "urdf") {
                        self.files.push(e.path());
                    }
                }
            }
        } else if arg.extension().is_some_and(|x| x == "toml") {
            // A drive file given alone: the URDF it names is an input too (model.source).
            self.files.push(arg.to_path_buf());
        }
        if let Some(m) = model {
            self.add(&m.source);
            // The drive file beside the URDF, when the robot was given by its URDF's directory.
            if let Some(p) = m.source.parent() {
                let d = p.join("drive.toml");
                if d.exists() {
                    self.add(d);
                }
            }
        }
        self
    }

    /// The inputs as given.
    pub fn paths(&self) -> &[PathBuf] {
        &self.files
    }

    /// Refuse `out` if it is an input (same canonical path, or the same file by device and
    /// inode), or a directory that holds an input.
    pub fn check(&self, out: &Path) -> Result<()> {
        let Some(o) = file_id(out) else {
            // Not there yet: it cannot be an input (its parent may still be; see below).
            return self.check_not_inside(out);
        };
        for i in &self.files {
            if let Some(id) = file_id(i) {
                let same = id.canon == o.canon || (id.dev_ino.is_some() && id.dev_ino == o.dev_ino);
                if same {
                    return Err(Error::Invalid(format!(
                        "refusing to write {}: it is an input of this command ({}); choose another output path",
                        out.display(),
                        i.display()
                    )));
                }
            }
        }
        self.check_not_inside(out)
    }

    /// Refuse `dir` if an input lies inside it (replacing the directory would remove it).
    fn check_not_inside(&self, dir: &Path) -> Result<()> {
        let Ok(d) = std::fs::canonicalize(dir) else {
            return Ok(());
        };
        if !d.is_dir() {
            return Ok(());
        }
        for i in &self.files {
            if let Ok(c) = std::fs::canonicalize(i) {
                if c != d && c.starts_with(&d) {
                    return Err(Error::Invalid(format!(
                        "refusing to write into {}: it holds {}, an input of this command; choose another output directory",
                        dir.display(),
                        i.display()
                    )));
                }
            }
        }
        Ok(())
    }
}

/// What to do when the output file exists already (and is not an input).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Existing {
    /// Replace it: the user named this output explicitly (`--out FILE`).
    Replace,
    /// Replace it only if `--force` was given (`true`); else refuse naming the path.
    Force(bool),
}

/// Write one output file: refused if it is an input (see [`Inputs::check`]) or, per
/// `existing`, if it exists; then written atomically (see [`write_atomic`]).
pub fn write_file(path: &Path, contents: &[u8], inputs: &Inputs, existing: Existing) -> Result<()> {
    write_file_with(path, inputs, existing, &mut |w| w.write_all(contents))
}

/// What streams an output's bytes into its (buffered, temporary) file.
pub(crate) type Fill<'a> = dyn FnMut(&mut dyn Write) -> std::io::Result<()> + 'a;

/// [`write_file`] with the contents streamed by `fill` as they are formatted (a long series
/// is never held in memory as text); the file still appears whole or not at all.
pub fn write_file_with(
    path: &Path,
    inputs: &Inputs,
    existing: Existing,
    fill: &mut Fill<'_>,
) -> Result<()> {
    check_file(path, inputs, existing)?;
    if existing == Existing::Force(false) {
        write_new_atomic_with(path, fill)
    } else {
        write_atomic_with(path, fill)
    }
}

/// The checks of [`write_file`] without writing: call it for every output of a command before
/// writing the first, so that a refusal leaves nothing half done.
pub fn check_file(path: &Path, inputs: &Inputs, existing: Existing) -> Result<()> {
    inputs.check(path)?;
    if path.is_dir() {
        return Err(Error::Invalid(format!(
            "{} is a directory: give a file name for this output",
            path.display()
        )));
    }
    if path.exists() && existing == Existing::Force(false) {
        return Err(Error::OutputExists {
            path: path.to_path_buf(),
        });
    }
    if let Some(parent) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        if parent.exists() && !parent.is_dir() {
            return Err(Error::Invalid(format!(
                "cannot write {}: {} exists and is not a directory",
                path.display(),
                parent.display()
            )));
        }
    }
    Ok(())
}

/// Check an output directory before anything is written into it: not an input, holds no
/// input, and not an existing file.
pub fn check_dir(dir: &Path, inputs: &Inputs) -> Result<()> {
    inputs.check(dir)?;
    if dir.exists() && !dir.is_dir() {
        return Err(Error::Invalid(format!(
            "{} exists and is not a directory: choose another output directory",
            dir.display()
        )));
    }
    Ok(())
}

/// `p` made absolute with every existing part resolved (symbolic links, `..`): the deepest
/// existing ancestor canonicalised, the rest appended, `.` dropped and `..` taken lexically.
pub(crate) fn resolve_lenient(p: &Path) -> PathBuf {
    let abs = std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let mut norm = PathBuf::new();
    for c in abs.components() {
        match c {
            Component::ParentDir => {
                norm.pop();
            }
            Component::CurDir => {}
            other => norm.push(other.as_os_str()),
        }
    }
    let mut base = norm.clone();
    let mut rest = Vec::new();
    loop {
        if let Ok(mut c) = std::fs::canonicalize(&base) {
            for part in rest.iter().rev() {
                c.push(part);
            }
            return c;
        }
        match (base.file_name().map(|n| n.to_os_string()), base.parent()) {
            (Some(n), Some(parent)) => {
                rest.push(n);
                base = parent.to_path_buf();
            }
            _ => return norm,
        }
    }
}

/// Refuse an output directory `out` that is one of `inputs`, lies inside one, or holds one:
/// writing it (with or without `--force`) would replace or change that input.
pub fn refuse_overlap(out: &Path, inputs: &[PathBuf]) -> Result<()> {
    let o = resolve_lenient(out);
    for i in inputs {
        let c = resolve_lenient(i);
        let why = if o == c {
            "it is"
        } else if o.starts_with(&c) {
            "it lies inside"
        } else if c.starts_with(&o) {
            "it holds"
        } else {
            continue;
        };
        return Err(Error::Invalid(format!(
            "refusing to write {}: {why} {}, an input of this command (whether or not replacing is allowed); choose an output outside every input",
            out.display(),
            i.display()
        )));
    }
    Ok(())
}

/// Refuse `path` if it is one of `inputs` (compared after canonicalisation and by device and
/// inode). Kept for callers with a list of paths; see [`Inputs::check`].
pub fn guard_inputs(out: &Path, inputs: &[&Path]) -> Result<()> {
    let mut i = Inputs::new();
    for p in inputs {
        i.add(p);
    }
    i.check(out)
}

/// Whether a process with this PID is running (Linux: `/proc/PID`; elsewhere assumed running).
pub(crate) fn process_alive(pid: u32) -> bool {
    if pid == std::process::id() {
        return true;
    }
    if cfg!(target_os = "linux") {
        Path::new("/proc").join(pid.to_string()).exists()
    } else {
        true
    }
}

/// PID in a temporary name `….tmp-PID` or `….printwatt-tmp-PID`.
fn tmp_pid(name: &str) -> Option<u32> {
    let (_, pid) = name
        .rsplit_once("tmp-")
        .or_else(|| name.rsplit_once("old-"))?;
    pid.parse().ok()
}

/// Remove `<name>.tmp-PID` siblings of `path` left by processes that are no longer running
/// (an interrupted write). Returns how many were removed.
pub(crate) fn clean_stale_temps(path: &Path) -> usize {
    let (Some(dir), Some(name)) = (path.parent(), path.file_name()) else {
        return 0;
    };
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    let prefix = format!("{}.tmp-", name.to_string_lossy());
    let mut n = 0;
    if let Ok(rd) = std::fs::read_dir(dir) {
        for e in rd.flatten() {
            let f = e.file_name().to_string_lossy().into_owned();
            if let Some(pid) = f.strip_prefix(&prefix).and_then(|p| p.parse::<u32>().ok()) {
                if !process_alive(pid) && std::fs::remove_file(e.path()).is_ok() {
                    n += 1;
                }
            }
        }
    }
    n
}

/// Write `contents` to `path` atomically: a sibling temporary file `<path>.tmp-PID`, synced,
/// then renamed over `path`. Stale temporary files of dead processes are removed first. Checks
/// nothing about inputs: use [`write_file`] for outputs of commands.
pub fn write_atomic(path: &Path, contents: &[u8]) -> Result<()> {
    write_atomic_with(path, &mut |w| w.write_all(contents))
}

/// The temporary file of `path`, filled by `fill` through a buffer and synced.
fn fill_temp(tmp: &Path, fill: &mut Fill<'_>) -> std::io::Result<()> {
    let mut w = std::io::BufWriter::with_capacity(1 << 16, std::fs::File::create(tmp)?);
    fill(&mut w)?;
    let f = w.into_inner().map_err(|e| e.into_error())?;
    f.sync_all()
}

/// [`write_atomic`] with the contents streamed by `fill`.
pub(crate) fn write_atomic_with(path: &Path, fill: &mut Fill<'_>) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }
    clean_stale_temps(path);
    let tmp: PathBuf = {
        let mut s = path.as_os_str().to_owned();
        s.push(format!(".tmp-{}", std::process::id()));
        s.into()
    };
    let res = fill_temp(&tmp, fill).and_then(|()| std::fs::rename(&tmp, path));
    if let Err(e) = res {
        let _ = std::fs::remove_file(&tmp);
        return Err(Error::io(path, e));
    }
    Ok(())
}

/// [`write_atomic`] for a file that must not exist, its contents streamed by `fill`: the
/// temporary file is put in place by a hard link, which fails if `path` exists, so of two runs
/// writing the same new file at once the second fails ([`Error::OutputExists`]) instead of
/// replacing the first's. On a file system without hard links, an existence check and a
/// rename.
pub(crate) fn write_new_atomic_with(path: &Path, fill: &mut Fill<'_>) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }
    clean_stale_temps(path);
    let tmp: PathBuf = {
        let mut s = path.as_os_str().to_owned();
        s.push(format!(".tmp-{}", std::process::id()));
        s.into()
    };
    let res = (|| {
        fill_temp(&tmp, fill)?;
        test_delay("PRINTWATT_TEST_WRITE_DELAY_MS");
        match std::fs::hard_link(&tmp, path) {
            Ok(()) => std::fs::remove_file(&tmp),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Err(e),
            Err(_) if !path.exists() => std::fs::rename(&tmp, path),
            Err(_) => Err(std::io::ErrorKind::AlreadyExists.into()),
        }
    })();
    match res {
        Ok(()) => Ok(()),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            if e.kind() == std::io::ErrorKind::AlreadyExists {
                Err(Error::OutputExists {
                    path: path.to_path_buf(),
                })
            } else {
                Err(Error::io(path, e))
            }
        }
    }
}

/// A pause of `$var` milliseconds where a test needs a window to interrupt a write (to kill
/// it, or to start a second run); none when the variable is not set.
fn test_delay(var: &str) {
    if let Some(ms) = std::env::var(var).ok().and_then(|v| v.parse::<u64>().ok()) {
        std::thread::sleep(std::time::Duration::from_millis(ms));
    }
}

/// Check a `--run` name: one or more plain relative path components (no `..`, `.`, root or
/// drive prefix), so that the run directory stays inside `--results-dir`.
pub(crate) fn run_name(run: &str) -> Result<PathBuf> {
    let p = Path::new(run);
    if run.trim().is_empty() {
        return Err(Error::BadRunName { name: run.into() });
    }
    for c in p.components() {
        match c {
            Component::Normal(_) => {}
            _ => return Err(Error::BadRunName { name: run.into() }),
        }
    }
    Ok(p.to_path_buf())
}

/// SHA-256 of `bytes`, lower-case hex.
pub fn sha256_hex(bytes: &[u8]) -> String {
    let d = Sha256::digest(bytes);
    d.iter().map(|b| format!("{b:02x}")).collect()
}

#[derive(serde::Serialize, serde::Deserialize, Default)]
struct Manifest {
    /// Always "printwatt".
    writer: String,
    /// File name → SHA-256 (hex) of its content as written.
    files: BTreeMap<String, String>,
}

/// A run directory being written. Created by [`RunDir::begin`] (which takes the lock), filled
/// with [`RunDir::write`], put in place by [`RunDir::commit`]. Dropped without commit (an
/// error), it removes its staging directory and lock and leaves any earlier run untouched.
///
/// Each file is synced to disk on a thread of its own while the next one is made; the commit
/// waits for every sync before it puts the run in place, so a committed run's files are on
/// disk as before, without the program waiting for each sync in turn (an `fsync` costs
/// 10–20 ms here; `printwatt optimise` writes four files).
#[derive(Debug)]
pub struct RunDir {
    target: PathBuf,
    staging: PathBuf,
    lock: PathBuf,
    /// The lock file, open and locked (`flock`) for as long as this run writes: the lock
    /// ends with the process, whatever ends it, so a lock is never stale.
    lock_file: Option<std::fs::File>,
    files: BTreeMap<String, String>,
    /// An earlier run put back at the target when this run began (see [`RunDir::restored`]).
    restored: Option<PathBuf>,
    /// The syncs under way: the file's path and the thread syncing it.
    syncing: Vec<(PathBuf, std::thread::JoinHandle<std::io::Result<()>>)>,
    done: bool,
}

/// Files a legacy run directory (written before manifests) may hold.
const LEGACY_RUN_FILES: [&str; 3] = ["summary.json", "placements.csv", "report.html"];

impl RunDir {
    /// Begin writing `results_dir/run` (`run` checked by [`run_name`]). See [`RunDir::begin_at`].
    pub fn begin(
        results_dir: &Path,
        run: &str,
        inputs: &Inputs,
        existing: Existing,
    ) -> Result<RunDir> {
        let rel = run_name(run)?;
        RunDir::begin_at(&results_dir.join(rel), inputs, existing)
    }

    /// Begin writing the directory `target`: refuse it if it is or holds an input, if it holds
    /// anything printwatt did not write (or changed since), or (per `existing`) if it exists;
    /// take the lock (fails naming the PID of a running printwatt that holds it); remove stale
    /// staging directories and locks of dead processes; create the staging directory.
    pub fn begin_at(target: &Path, inputs: &Inputs, existing: Existing) -> Result<RunDir> {
        let name = target
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .ok_or_else(|| Error::Invalid(format!("{}: not a directory name", target.display())))?;
        let parent = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        inputs.check(target)?;
        std::fs::create_dir_all(&parent).map_err(|e| Error::io(&parent, e))?;
        let lock = parent.join(format!(".{name}.printwatt-lock"));
        let lock_file = take_lock(&lock, target)?;
        let mut rd = RunDir {
            target: target.to_path_buf(),
            staging: parent.join(format!(".{name}.printwatt-tmp-{}", std::process::id())),
            lock,
            lock_file: Some(lock_file),
            restored: None,
            files: BTreeMap::new(),
            syncing: Vec::new(),
            done: false,
        };
        // Staging and old directories of other runs: with the lock held, their writers are
        // gone (a PID reused since does not matter). A staging directory is removed; an old
        // run moved aside by a replacement that was interrupted before the new run was in
        // place is put back (the earlier result is never lost); one whose replacement
        // completed is removed.
        if let Ok(entries) = std::fs::read_dir(&parent) {
            let mut olds = Vec::new();
            for e in entries.flatten() {
                let f = e.file_name().to_string_lossy().into_owned();
                if f.starts_with(&format!(".{name}.printwatt-tmp-")) && tmp_pid(&f).is_some() {
                    let _ = std::fs::remove_dir_all(e.path());
                } else if f.starts_with(&format!(".{name}.printwatt-old-")) && tmp_pid(&f).is_some()
                {
                    olds.push(e.path());
                }
            }
            olds.sort_by_key(|p| std::fs::metadata(p).and_then(|m| m.modified()).ok());
            for old in olds.into_iter().rev() {
                if !target.exists() && std::fs::rename(&old, target).is_ok() {
                    rd.restored = Some(old);
                    continue;
                }
                let _ = std::fs::remove_dir_all(&old);
            }
        }
        if target.exists() {
            if !target.is_dir() {
                return Err(Error::Invalid(format!(
                    "{} exists and is not a directory: choose another run name",
                    target.display()
                )));
            }
            check_ours(target)?;
            let empty = std::fs::read_dir(target).is_ok_and(|mut d| d.next().is_none());
            if existing == Existing::Force(false) && !empty {
                return Err(Error::OutputExists {
                    path: target.to_path_buf(),
                });
            }
        }
        std::fs::create_dir_all(&rd.staging).map_err(|e| Error::io(&rd.staging, e))?;
        rd.done = false;
        Ok(rd)
    }

    /// The directory the run will be in once committed.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Write one file of the run (a plain file name) into the staging directory. Its sync to
    /// disk runs on its own thread; [`RunDir::commit`] waits for it (and reports its error).
    pub fn write(&mut self, name: &str, contents: &[u8]) -> Result<()> {
        if name.contains(['/', '\\']) || name == MANIFEST || name.starts_with('.') {
            return Err(Error::Invalid(format!(
                "run file name `{name}` not allowed"
            )));
        }
        let p = self.staging.join(name);
        let mut f = std::fs::File::create(&p).map_err(|e| Error::io(&p, e))?;
        f.write_all(contents).map_err(|e| Error::io(&p, e))?;
        let sync = std::thread::Builder::new()
            .name("printwatt-sync".into())
            .spawn(move || f.sync_all());
        match sync {
            Ok(h) => self.syncing.push((p, h)),
            // No thread to be had: sync here.
            Err(_) => std::fs::File::open(&p)
                .and_then(|f| f.sync_all())
                .map_err(|e| Error::io(&p, e))?,
        }
        self.files.insert(name.to_string(), sha256_hex(contents));
        Ok(())
    }

    /// Wait for every file's sync; the first error, naming its file.
    fn wait_for_syncs(&mut self) -> Result<()> {
        let mut first = None;
        for (p, h) in self.syncing.drain(..) {
            let r = h.join().unwrap_or_else(|_| {
                Err(std::io::Error::other(
                    "the thread syncing the file panicked",
                ))
            });
            if let (Err(e), None) = (r, &first) {
                first = Some(Error::io(&p, e));
            }
        }
        first.map_or(Ok(()), Err)
    }

    /// Put the run in place: the manifest is written, an earlier run (checked again to be
    /// printwatt's own) is moved aside, the staging directory renamed to the target, the earlier
    /// run removed, the lock released. Returns the target.
    pub fn commit(mut self) -> Result<PathBuf> {
        test_delay("PRINTWATT_TEST_COMMIT_DELAY_MS");
        self.wait_for_syncs()?;
        let m = Manifest {
            writer: "printwatt".into(),
            files: self.files.clone(),
        };
        let text = serde_json::to_string_pretty(&m)
            .map_err(|e| Error::Invalid(format!("writing the manifest: {e}")))?;
        let mp = self.staging.join(MANIFEST);
        std::fs::write(&mp, text).map_err(|e| Error::io(&mp, e))?;
        let old = self.target.with_file_name(format!(
            ".{}.printwatt-old-{}",
            self.target
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default(),
            std::process::id()
        ));
        let had_old = self.target.exists();
        if had_old {
            check_ours(&self.target)?;
            std::fs::rename(&self.target, &old).map_err(|e| Error::io(&self.target, e))?;
            test_delay("PRINTWATT_TEST_REPLACE_DELAY_MS");
        }
        if let Err(e) = std::fs::rename(&self.staging, &self.target) {
            if had_old {
                let _ = std::fs::rename(&old, &self.target);
            }
            return Err(Error::io(&self.target, e));
        }
        if had_old {
            let _ = std::fs::remove_dir_all(&old);
        }
        self.release_lock();
        self.done = true;
        Ok(self.target.clone())
    }
}

impl Drop for RunDir {
    fn drop(&mut self) {
        let _ = self.wait_for_syncs();
        if !self.done {
            let _ = std::fs::remove_dir_all(&self.staging);
            self.release_lock();
        }
    }
}

impl RunDir {
    /// Remove the lock file, then unlock it (a run that opened it meanwhile finds it gone
    /// and opens the new one: see [`take_lock`]).
    fn release_lock(&mut self) {
        if let Some(f) = self.lock_file.take() {
            let _ = std::fs::remove_file(&self.lock);
            drop(f);
        }
    }
}

/// Take the lock of `target`: the file `lock`, locked with `flock` (held until the returned
/// file is closed, which the system does when the process ends, however it ends) and holding
/// our PID to name us. A lock held by a running printwatt is an error naming its PID; a lock
/// file left by a killed run is not locked, so it is simply taken (a PID reused since by
/// another process plays no part).
fn take_lock(lock: &Path, target: &Path) -> Result<std::fs::File> {
    for _ in 0..20 {
        let mut f = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(lock)
            .map_err(|e| Error::io(lock, e))?;
        match f.try_lock() {
            Ok(()) => {
                // The file may have been removed by its previous owner between our open and
                // our lock: only the file at the path is the lock.
                if !same_file(&f, lock) {
                    continue;
                }
                let _ = f.set_len(0);
                let _ = writeln!(f, "{}", std::process::id());
                return Ok(f);
            }
            Err(std::fs::TryLockError::WouldBlock) => {
                let pid = std::fs::read_to_string(lock)
                    .ok()
                    .and_then(|s| s.trim().parse::<u32>().ok());
                let who = pid.map_or_else(|| "PID unknown".to_string(), |p| format!("PID {p}"));
                return Err(Error::Invalid(format!(
                    "{} is being written by another printwatt run ({who}, lock {}): wait for it to finish, or choose another run name",
                    target.display(),
                    lock.display()
                )));
            }
            Err(std::fs::TryLockError::Error(e)) => return Err(Error::io(lock, e)),
        }
    }
    Err(Error::Invalid(format!(
        "{}: could not take the lock {}; remove it if no printwatt is running",
        target.display(),
        lock.display()
    )))
}

/// Whether the open file `f` is the file at `p` (same device and inode).
fn same_file(f: &std::fs::File, p: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (f.metadata(), std::fs::metadata(p)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = f;
        p.exists()
    }
}

/// Error unless every entry of the existing directory `dir` was written by printwatt and is
/// unchanged: listed in its manifest with the same SHA-256. Stale temporary files of dead
/// processes are removed first. A directory without a manifest is accepted only as a run
/// written before manifests existed: nothing but `summary.json`, `placements.csv` and
/// `report.html`, with a summary whose title printwatt writes.
fn check_ours(dir: &Path) -> Result<()> {
    let rd = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
    let mut names = Vec::new();
    for e in rd.flatten() {
        let f = e.file_name().to_string_lossy().into_owned();
        if let Some((_, pid)) = f.rsplit_once(".tmp-") {
            if pid.parse::<u32>().is_ok_and(|p| !process_alive(p))
                && std::fs::remove_file(e.path()).is_ok()
            {
                continue;
            }
        }
        names.push(f);
    }
    let foreign = |f: &str, why: &str| {
        Error::Invalid(format!(
            "refusing to replace {}: it holds `{f}`, {why}; choose another run name, or move that file away",
            dir.display()
        ))
    };
    let mp = dir.join(MANIFEST);
    if mp.exists() {
        let m: Manifest = std::fs::read_to_string(&mp)
            .ok()
            .and_then(|t| serde_json::from_str(&t).ok())
            .ok_or_else(|| foreign(MANIFEST, "a manifest printwatt cannot read"))?;
        for f in names.iter().filter(|f| *f != MANIFEST) {
            let Some(h) = m.files.get(f) else {
                return Err(foreign(f, "which printwatt did not write"));
            };
            let bytes = std::fs::read(dir.join(f)).map_err(|e| Error::io(dir.join(f), e))?;
            if &sha256_hex(&bytes) != h {
                return Err(foreign(f, "which was changed after printwatt wrote it"));
            }
        }
        return Ok(());
    }
    for f in &names {
        if !LEGACY_RUN_FILES.contains(&f.as_str()) {
            return Err(foreign(f, "which printwatt did not write"));
        }
    }
    if names.iter().any(|f| f == "summary.json") {
        let ok = std::fs::read_to_string(dir.join("summary.json"))
            .ok()
            .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
            .and_then(|v| v.get("title").and_then(|t| t.as_str()).map(str::to_string))
            .is_some_and(|t| t.starts_with("printwatt "));
        if !ok {
            return Err(foreign(
                "summary.json",
                "which is not a printwatt summary (no manifest says printwatt wrote it)",
            ));
        }
    } else if !names.is_empty() {
        return Err(foreign(
            &names[0],
            "and no manifest says printwatt wrote it",
        ));
    }
    Ok(())
}

/// The last check before numbers leave printwatt: `columns` names the quantities, `rows` gives
/// samples. A NaN or an infinity is an error naming `what`, the first sample (0-based) and the
/// quantity where it appeared.
pub fn check_finite<'a>(
    what: &str,
    columns: &[String],
    rows: impl Iterator<Item = &'a [f64]>,
) -> Result<()> {
    for (k, r) in rows.enumerate() {
        check_finite_row(what, columns, k, r)?;
    }
    Ok(())
}

/// [`check_finite`] for one row, sample `k` (0-based), for writers that produce rows one at a
/// time.
pub(crate) fn check_finite_row(
    what: &str,
    columns: &[String],
    k: usize,
    row: &[f64],
) -> Result<()> {
    if let Some(j) = row.iter().position(|v| !v.is_finite()) {
        let q = columns.get(j).map_or("?", String::as_str);
        return Err(Error::Invalid(format!(
            "{what}: `{q}` is {} at sample {k}: the model produced a number that is not a number; check the robot's drive and inertia data",
            row[j]
        )));
    }
    Ok(())
}

/// The last check before a serialisable result leaves printwatt (a `--json` print, a
/// `compare.json`, an `identify.json`, ...): a NaN or an infinity anywhere inside `value` is an
/// error naming `what` and the JSON path of the first one, e.g. `channels[2].rmse` (a time
/// series' index is its sample).
///
/// The check walks `value`'s own [`serde::Serialize`] output with a serialiser that keeps the
/// path and writes nothing. It must run on the typed value, before `serde_json` sees it:
/// `serde_json` silently turns NaN and infinities into `null`.
pub fn check_finite_json<T: serde::Serialize + ?Sized>(what: &str, value: &T) -> Result<()> {
    let mut f = finite::Finder::default();
    match value.serialize(&mut f) {
        Err(finite::Found::NonFinite { path, value }) => {
            let path = if path.is_empty() {
                "(the value itself)".to_string()
            } else {
                path.trim_start_matches('.').to_string()
            };
            Err(Error::Invalid(format!(
                "{what}: `{path}` is {value}: the model produced a number that is not a number; nothing was written; check the robot's drive and inertia data and the log"
            )))
        }
        // Anything else (a map key JSON cannot hold, ...) is the serialiser's to report.
        Err(finite::Found::Other(_)) | Ok(()) => Ok(()),
    }
}

/// The serialiser behind [`check_finite_json`]: it follows the value, records the path of
/// struct fields (`.name`), map keys (`.key`), sequence elements (`[i]`) and enum variants,
/// and stops at the first non-finite float.
mod finite {
    use serde::ser::{self, Serialize};
    use std::fmt;

    #[derive(Default)]
    pub(crate) struct Finder {
        path: Vec<String>,
    }

    #[derive(Debug)]
    pub(crate) enum Found {
        NonFinite { path: String, value: f64 },
        Other(String),
    }

    impl fmt::Display for Found {
        fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            match self {
                Found::NonFinite { path, value } => write!(f, "{path} = {value}"),
                Found::Other(m) => f.write_str(m),
            }
        }
    }

    impl std::error::Error for Found {}

    impl ser::Error for Found {
        fn custom<T: fmt::Display>(msg: T) -> Self {
            Found::Other(msg.to_string())
        }
    }

    impl Finder {
        fn float(&self, v: f64) -> Result<(), Found> {
            if v.is_finite() {
                Ok(())
            } else {
                Err(Found::NonFinite {
                    path: self.path.concat(),
                    value: v,
                })
            }
        }

        fn under<T: Serialize + ?Sized>(&mut self, seg: String, v: &T) -> Result<(), Found> {
            self.path.push(seg);
            let r = v.serialize(&mut *self);
            self.path.pop();
            r
        }
    }

    /// A map key as the path shows it: a string as is, anything else as JSON would print it.
    fn key_name<T: Serialize + ?Sized>(key: &T) -> String {
        match serde_json::to_value(key) {
            Ok(serde_json::Value::String(s)) => s,
            Ok(v) => v.to_string(),
            Err(_) => "?".into(),
        }
    }

    pub(crate) struct Compound<'a> {
        f: &'a mut Finder,
        i: usize,
        key: String,
    }

    impl<'a> Compound<'a> {
        fn new(f: &'a mut Finder) -> Self {
            Compound {
                f,
                i: 0,
                key: String::new(),
            }
        }
        fn element<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Found> {
            let seg = format!("[{}]", self.i);
            self.i += 1;
            self.f.under(seg, v)
        }
    }

    /// The sequence-like compounds: each element is a path segment `[i]`; a variant's compound
    /// pops the variant's name at its end.
    macro_rules! sequence_compound {
        ($trait:ident, $method:ident, $pop:expr) => {
            impl ser::$trait for Compound<'_> {
                type Ok = ();
                type Error = Found;
                fn $method<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Found> {
                    self.element(v)
                }
                fn end(self) -> Result<(), Found> {
                    if $pop {
                        self.f.path.pop();
                    }
                    Ok(())
                }
            }
        };
    }
    sequence_compound!(SerializeSeq, serialize_element, false);
    sequence_compound!(SerializeTuple, serialize_element, false);
    sequence_compound!(SerializeTupleStruct, serialize_field, false);
    sequence_compound!(SerializeTupleVariant, serialize_field, true);

    impl ser::SerializeMap for Compound<'_> {
        type Ok = ();
        type Error = Found;
        fn serialize_key<T: Serialize + ?Sized>(&mut self, key: &T) -> Result<(), Found> {
            self.key = key_name(key);
            Ok(())
        }
        fn serialize_value<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Found> {
            let seg = format!(".{}", self.key);
            self.f.under(seg, v)
        }
        fn end(self) -> Result<(), Found> {
            Ok(())
        }
    }

    /// The struct-like compounds: each field is a path segment `.name`; a variant's compound
    /// pops the variant's name at its end.
    macro_rules! struct_compound {
        ($trait:ident, $pop:expr) => {
            impl ser::$trait for Compound<'_> {
                type Ok = ();
                type Error = Found;
                fn serialize_field<T: Serialize + ?Sized>(
                    &mut self,
                    name: &'static str,
                    v: &T,
                ) -> Result<(), Found> {
                    self.f.under(format!(".{name}"), v)
                }
                fn end(self) -> Result<(), Found> {
                    if $pop {
                        self.f.path.pop();
                    }
                    Ok(())
                }
            }
        };
    }
    struct_compound!(SerializeStruct, false);
    struct_compound!(SerializeStructVariant, true);

    /// Values that are never numbers: nothing to check.
    macro_rules! ignored_values {
        ($($method:ident: $t:ty),*) => {
            $(fn $method(self, _: $t) -> Result<(), Found> {
                Ok(())
            })*
        };
    }
    impl<'a> ser::Serializer for &'a mut Finder {
        type Ok = ();
        type Error = Found;
        type SerializeSeq = Compound<'a>;
        type SerializeTuple = Compound<'a>;
        type SerializeTupleStruct = Compound<'a>;
        type SerializeTupleVariant = Compound<'a>;
        type SerializeMap = Compound<'a>;
        type SerializeStruct = Compound<'a>;
        type SerializeStructVariant = Compound<'a>;

        ignored_values!(serialize_bool: bool, serialize_i8: i8, serialize_i16: i16, serialize_i32: i32,
            serialize_i64: i64, serialize_u8: u8, serialize_u16: u16, serialize_u32: u32,
            serialize_u64: u64, serialize_char: char, serialize_str: &str,
            serialize_bytes: &[u8]);
        fn serialize_f32(self, v: f32) -> Result<(), Found> {
            self.float(f64::from(v))
        }
        fn serialize_f64(self, v: f64) -> Result<(), Found> {
            self.float(v)
        }
        fn serialize_none(self) -> Result<(), Found> {
            Ok(())
        }
        fn serialize_some<T: Serialize + ?Sized>(self, v: &T) -> Result<(), Found> {
            v.serialize(self)
        }
        fn serialize_unit(self) -> Result<(), Found> {
            Ok(())
        }
        fn serialize_unit_struct(self, _: &'static str) -> Result<(), Found> {
            Ok(())
        }
        fn serialize_unit_variant(
            self,
            _: &'static str,
            _: u32,
            _: &'static str,
        ) -> Result<(), Found> {
            Ok(())
        }
        fn serialize_newtype_struct<T: Serialize + ?Sized>(
            self,
            _: &'static str,
            v: &T,
        ) -> Result<(), Found> {
            v.serialize(self)
        }
        fn serialize_newtype_variant<T: Serialize + ?Sized>(
            self,
            _: &'static str,
            _: u32,
            variant: &'static str,
            v: &T,
        ) -> Result<(), Found> {
            self.under(format!(".{variant}"), v)
        }
        fn serialize_seq(self, _: Option<usize>) -> Result<Compound<'a>, Found> {
            Ok(Compound::new(self))
        }
        fn serialize_tuple(self, _: usize) -> Result<Compound<'a>, Found> {
            Ok(Compound::new(self))
        }
        fn serialize_tuple_struct(self, _: &'static str, _: usize) -> Result<Compound<'a>, Found> {
            Ok(Compound::new(self))
        }
        fn serialize_tuple_variant(
            self,
            _: &'static str,
            _: u32,
            variant: &'static str,
            _: usize,
        ) -> Result<Compound<'a>, Found> {
            self.path.push(format!(".{variant}"));
            Ok(Compound::new(self))
        }
        fn serialize_map(self, _: Option<usize>) -> Result<Compound<'a>, Found> {
            Ok(Compound::new(self))
        }
        fn serialize_struct(self, _: &'static str, _: usize) -> Result<Compound<'a>, Found> {
            Ok(Compound::new(self))
        }
        fn serialize_struct_variant(
            self,
            _: &'static str,
            _: u32,
            variant: &'static str,
            _: usize,
        ) -> Result<Compound<'a>, Found> {
            self.path.push(format!(".{variant}"));
            Ok(Compound::new(self))
        }
    }
}

/// UTC time `YYYYmmddTHHMMSSZ` of a Unix time, s (proleptic Gregorian; Howard Hinnant's
/// days-to-civil algorithm). Used to name run directories.
pub fn utc_stamp(unix_s: u64) -> String {
    let days = (unix_s / 86_400) as i64;
    let sod = unix_s % 86_400;
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}{m:02}{d:02}T{:02}{:02}{:02}Z",
        sod / 3600,
        (sod / 60) % 60,
        sod % 60
    )
}

/// Version of every `--json` answer and JSON file printwatt writes (docs/json.md); raised when a
/// field changes meaning or is removed (fields may be added without a raise).
pub const JSON_SCHEMA_VERSION: u32 = 1;

/// Significant digits kept in JSON numbers: far finer than any model or measurement behind
/// them, coarse enough that float noise (`0.050000000000000044`) does not reach a reader.
pub(crate) const JSON_SIGNIFICANT_DIGITS: usize = 9;

/// `x` rounded to `digits` significant digits (non-finite values unchanged).
pub(crate) fn round_significant(x: f64, digits: usize) -> f64 {
    if !x.is_finite() || x == 0.0 {
        return x;
    }
    format!("{:.*e}", digits.saturating_sub(1), x)
        .parse()
        .unwrap_or(x)
}

/// Round every non-integer number of a JSON value to [`JSON_SIGNIFICANT_DIGITS`].
pub(crate) fn round_json(v: &mut serde_json::Value) {
    match v {
        serde_json::Value::Number(n) if n.is_f64() => {
            if let Some(x) = n.as_f64() {
                let r = round_significant(x, JSON_SIGNIFICANT_DIGITS);
                if let Some(m) = serde_json::Number::from_f64(r) {
                    *n = m;
                }
            }
        }
        serde_json::Value::Array(a) => a.iter_mut().for_each(round_json),
        serde_json::Value::Object(o) => o.values_mut().for_each(round_json),
        _ => {}
    }
}

/// The last step before a JSON document leaves: numbers rounded ([`round_json`]) and, for an
/// object, `schema_version` ([`JSON_SCHEMA_VERSION`]) added when it has none.
pub fn finish_json(v: &mut serde_json::Value) {
    round_json(v);
    stamp_json(v);
}

/// For an object, `schema_version` ([`JSON_SCHEMA_VERSION`]) added when it has none; numbers
/// left at full precision (the Python dictionaries that mirror a JSON document).
pub fn stamp_json(v: &mut serde_json::Value) {
    if let serde_json::Value::Object(o) = v {
        if !o.contains_key("schema_version") {
            o.insert("schema_version".into(), JSON_SCHEMA_VERSION.into());
        }
    }
}

/// A serialisable value as finished, pretty JSON text ([`finish_json`]).
pub fn json_text<T: serde::Serialize + ?Sized>(value: &T) -> Result<String> {
    json_text_with(value, &[])
}

/// [`json_text`] with `extra` top-level fields (an object's keys, replacing any of the same
/// name): the finished pretty JSON text written straight from `value`'s own
/// [`serde::Serialize`] output, numbers rounded ([`round_significant`]) as they are written,
/// with no `serde_json::Value` tree of the document in between. The text is byte for byte
/// what [`finish_json`] and `serde_json::to_string_pretty` give for the same value (keys in
/// sorted order, `schema_version` added to an object that has none, non-finite numbers as
/// `null`).
pub fn json_text_with<T: serde::Serialize + ?Sized>(
    value: &T,
    extra: &[(&str, serde_json::Value)],
) -> Result<String> {
    let r = value
        .serialize(pretty::Render {
            depth: 0,
            top: Some(extra),
        })
        .map_err(|e| Error::Invalid(e.to_string()))?;
    Ok(r.text)
}

/// The writer behind [`json_text_with`]: a [`serde::Serializer`] that renders each value as
/// its pretty-printed text at its depth. An object's members are rendered one by one and kept
/// (as text) until the object ends, because `serde_json`'s map orders keys: the memory held is
/// that of the text, never a tree of values.
mod pretty {
    use serde::ser::{self, Serialize};
    use std::collections::BTreeMap;
    use std::fmt::Write as _;

    #[derive(Debug)]
    pub struct Error(String);

    impl std::fmt::Display for Error {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str(&self.0)
        }
    }
    impl std::error::Error for Error {}
    impl ser::Error for Error {
        fn custom<T: std::fmt::Display>(msg: T) -> Self {
            Error(msg.to_string())
        }
    }

    /// A rendered value.
    pub struct Out {
        pub text: String,
    }

    fn out(text: String) -> Result<Out, Error> {
        Ok(Out { text })
    }

    /// Renders one value at `depth` (indentation of its closing bracket). `top`: the document
    /// itself (an object gets `schema_version` and the extra fields).
    #[derive(Clone, Copy)]
    pub struct Render<'e> {
        pub depth: usize,
        pub top: Option<&'e [(&'e str, serde_json::Value)]>,
    }

    fn child(depth: usize) -> Render<'static> {
        Render {
            depth: depth + 1,
            top: None,
        }
    }

    fn string(s: &str) -> String {
        serde_json::to_string(s).unwrap_or_default()
    }

    fn float(x: f64) -> String {
        let r = super::round_significant(x, super::JSON_SIGNIFICANT_DIGITS);
        match serde_json::Number::from_f64(r) {
            Some(n) => n.to_string(),
            None => "null".into(),
        }
    }

    fn indent(s: &mut String, depth: usize) {
        for _ in 0..depth {
            s.push_str("  ");
        }
    }

    /// `[` items `]` as serde_json's pretty printer writes them.
    fn array(items: &[String], depth: usize) -> String {
        if items.is_empty() {
            return "[]".into();
        }
        let size: usize = items.iter().map(|it| it.len() + 2 * depth + 4).sum();
        let mut s = String::with_capacity(size + 2 * depth + 4);
        s.push('[');
        for (i, it) in items.iter().enumerate() {
            s.push_str(if i == 0 { "\n" } else { ",\n" });
            indent(&mut s, depth + 1);
            s.push_str(it);
        }
        s.push('\n');
        indent(&mut s, depth);
        s.push(']');
        s
    }

    /// `{` members `}` in key order.
    fn object(members: &BTreeMap<String, String>, depth: usize) -> String {
        if members.is_empty() {
            return "{}".into();
        }
        let size: usize = members
            .iter()
            .map(|(k, v)| k.len() + v.len() + 2 * depth + 10)
            .sum();
        let mut s = String::with_capacity(size + 2 * depth + 4);
        s.push('{');
        for (i, (k, v)) in members.iter().enumerate() {
            s.push_str(if i == 0 { "\n" } else { ",\n" });
            indent(&mut s, depth + 1);
            s.push_str(&string(k));
            s.push_str(": ");
            s.push_str(v);
        }
        s.push('\n');
        indent(&mut s, depth);
        s.push('}');
        s
    }

    /// `{"variant": value}`.
    fn tagged(variant: &str, value: String, depth: usize) -> String {
        let mut m = BTreeMap::new();
        m.insert(variant.to_string(), value);
        object(&m, depth)
    }

    pub struct Seq<'e> {
        r: Render<'e>,
        items: Vec<String>,
        variant: Option<&'static str>,
    }

    pub struct Map<'e> {
        r: Render<'e>,
        members: BTreeMap<String, String>,
        key: Option<String>,
        variant: Option<&'static str>,
    }

    impl<'e> Seq<'e> {
        fn new(r: Render<'e>, variant: Option<&'static str>, len: Option<usize>) -> Self {
            Seq {
                r,
                items: Vec::with_capacity(len.unwrap_or(0).min(4096)),
                variant,
            }
        }
        fn push<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Error> {
            // Inside a tagged variant the array sits one level deeper.
            let d = self.r.depth + usize::from(self.variant.is_some());
            self.items.push(v.serialize(child(d))?.text);
            Ok(())
        }
        fn done(self) -> Result<Out, Error> {
            match self.variant {
                None => out(array(&self.items, self.r.depth)),
                Some(v) => out(tagged(
                    v,
                    array(&self.items, self.r.depth + 1),
                    self.r.depth,
                )),
            }
        }
    }

    impl<'e> Map<'e> {
        fn new(r: Render<'e>, variant: Option<&'static str>) -> Self {
            Map {
                r,
                members: BTreeMap::new(),
                key: None,
                variant,
            }
        }
        fn depth(&self) -> usize {
            self.r.depth + usize::from(self.variant.is_some())
        }
        fn field<T: Serialize + ?Sized>(&mut self, key: &str, v: &T) -> Result<(), Error> {
            let text = v.serialize(child(self.depth()))?.text;
            self.members.insert(key.to_string(), text);
            Ok(())
        }
        fn done(mut self) -> Result<Out, Error> {
            if let Some(extra) = self.r.top {
                if !self.members.contains_key("schema_version") {
                    self.members.insert(
                        "schema_version".into(),
                        super::JSON_SCHEMA_VERSION.to_string(),
                    );
                }
                for (k, v) in extra {
                    let text = v.serialize(child(self.r.depth))?.text;
                    self.members.insert(k.to_string(), text);
                }
            }
            match self.variant {
                None => out(object(&self.members, self.r.depth)),
                Some(v) => out(tagged(
                    v,
                    object(&self.members, self.r.depth + 1),
                    self.r.depth,
                )),
            }
        }
    }

    macro_rules! int {
        ($($f:ident: $t:ty),*) => {$(
            fn $f(self, v: $t) -> Result<Out, Error> {
                out(v.to_string())
            }
        )*};
    }

    impl<'e> ser::Serializer for Render<'e> {
        type Ok = Out;
        type Error = Error;
        type SerializeSeq = Seq<'e>;
        type SerializeTuple = Seq<'e>;
        type SerializeTupleStruct = Seq<'e>;
        type SerializeTupleVariant = Seq<'e>;
        type SerializeMap = Map<'e>;
        type SerializeStruct = Map<'e>;
        type SerializeStructVariant = Map<'e>;

        int!(serialize_i8: i8, serialize_i16: i16, serialize_i32: i32, serialize_i64: i64,
             serialize_u8: u8, serialize_u16: u16, serialize_u32: u32, serialize_u64: u64);

        fn serialize_i128(self, v: i128) -> Result<Out, Error> {
            match (i64::try_from(v), u64::try_from(v)) {
                (Ok(_), _) | (_, Ok(_)) => out(v.to_string()),
                _ => Err(Error("number out of range".into())),
            }
        }
        fn serialize_u128(self, v: u128) -> Result<Out, Error> {
            match u64::try_from(v) {
                Ok(_) => out(v.to_string()),
                Err(_) => Err(Error("number out of range".into())),
            }
        }
        fn serialize_bool(self, v: bool) -> Result<Out, Error> {
            out(v.to_string())
        }
        fn serialize_f32(self, v: f32) -> Result<Out, Error> {
            out(float(f64::from(v)))
        }
        fn serialize_f64(self, v: f64) -> Result<Out, Error> {
            out(float(v))
        }
        fn serialize_char(self, v: char) -> Result<Out, Error> {
            out(string(v.encode_utf8(&mut [0; 4])))
        }
        fn serialize_str(self, v: &str) -> Result<Out, Error> {
            out(string(v))
        }
        fn serialize_bytes(self, v: &[u8]) -> Result<Out, Error> {
            let items: Vec<String> = v.iter().map(|b| b.to_string()).collect();
            out(array(&items, self.depth))
        }
        fn serialize_none(self) -> Result<Out, Error> {
            out("null".into())
        }
        fn serialize_some<T: Serialize + ?Sized>(self, v: &T) -> Result<Out, Error> {
            v.serialize(self)
        }
        fn serialize_unit(self) -> Result<Out, Error> {
            out("null".into())
        }
        fn serialize_unit_struct(self, _: &'static str) -> Result<Out, Error> {
            out("null".into())
        }
        fn serialize_unit_variant(
            self,
            _: &'static str,
            _: u32,
            variant: &'static str,
        ) -> Result<Out, Error> {
            out(string(variant))
        }
        fn serialize_newtype_struct<T: Serialize + ?Sized>(
            self,
            _: &'static str,
            v: &T,
        ) -> Result<Out, Error> {
            v.serialize(self)
        }
        fn serialize_newtype_variant<T: Serialize + ?Sized>(
            self,
            _: &'static str,
            _: u32,
            variant: &'static str,
            v: &T,
        ) -> Result<Out, Error> {
            let inner = v.serialize(child(self.depth))?.text;
            out(tagged(variant, inner, self.depth))
        }
        fn serialize_seq(self, len: Option<usize>) -> Result<Seq<'e>, Error> {
            Ok(Seq::new(self, None, len))
        }
        fn serialize_tuple(self, len: usize) -> Result<Seq<'e>, Error> {
            Ok(Seq::new(self, None, Some(len)))
        }
        fn serialize_tuple_struct(self, _: &'static str, len: usize) -> Result<Seq<'e>, Error> {
            Ok(Seq::new(self, None, Some(len)))
        }
        fn serialize_tuple_variant(
            self,
            _: &'static str,
            _: u32,
            variant: &'static str,
            len: usize,
        ) -> Result<Seq<'e>, Error> {
            Ok(Seq::new(self, Some(variant), Some(len)))
        }
        fn serialize_map(self, _: Option<usize>) -> Result<Map<'e>, Error> {
            Ok(Map::new(self, None))
        }
        fn serialize_struct(self, _: &'static str, _: usize) -> Result<Map<'e>, Error> {
            Ok(Map::new(self, None))
        }
        fn serialize_struct_variant(
            self,
            _: &'static str,
            _: u32,
            variant: &'static str,
            _: usize,
        ) -> Result<Map<'e>, Error> {
            Ok(Map::new(self, Some(variant)))
        }
        fn collect_str<T: std::fmt::Display + ?Sized>(self, v: &T) -> Result<Out, Error> {
            let mut s = String::new();
            let _ = write!(s, "{v}");
            out(string(&s))
        }
    }

    macro_rules! seq_impl {
        ($($tr:ident :: $m:ident),*) => {$(
            impl ser::$tr for Seq<'_> {
                type Ok = Out;
                type Error = Error;
                fn $m<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Error> {
                    self.push(v)
                }
                fn end(self) -> Result<Out, Error> {
                    self.done()
                }
            }
        )*};
    }
    seq_impl!(
        SerializeSeq::serialize_element,
        SerializeTuple::serialize_element,
        SerializeTupleStruct::serialize_field,
        SerializeTupleVariant::serialize_field
    );

    impl ser::SerializeMap for Map<'_> {
        type Ok = Out;
        type Error = Error;
        fn serialize_key<T: Serialize + ?Sized>(&mut self, k: &T) -> Result<(), Error> {
            self.key = Some(k.serialize(Key)?);
            Ok(())
        }
        fn serialize_value<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Error> {
            let k = self
                .key
                .take()
                .ok_or_else(|| Error("a map value without its key".into()))?;
            self.field(&k, v)
        }
        fn end(self) -> Result<Out, Error> {
            self.done()
        }
    }

    macro_rules! struct_impl {
        ($($tr:ident),*) => {$(
            impl ser::$tr for Map<'_> {
                type Ok = Out;
                type Error = Error;
                fn serialize_field<T: Serialize + ?Sized>(
                    &mut self,
                    key: &'static str,
                    v: &T,
                ) -> Result<(), Error> {
                    self.field(key, v)
                }
                fn end(self) -> Result<Out, Error> {
                    self.done()
                }
            }
        )*};
    }
    struct_impl!(SerializeStruct, SerializeStructVariant);

    /// A map key as serde_json's value serialiser takes it: a string, or a number, a boolean
    /// or a character written as one.
    struct Key;

    fn key_error() -> Error {
        Error("key must be a string".into())
    }

    macro_rules! key_display {
        ($($f:ident: $t:ty),*) => {$(
            fn $f(self, v: $t) -> Result<String, Error> {
                Ok(v.to_string())
            }
        )*};
    }

    impl ser::Serializer for Key {
        type Ok = String;
        type Error = Error;
        type SerializeSeq = ser::Impossible<String, Error>;
        type SerializeTuple = ser::Impossible<String, Error>;
        type SerializeTupleStruct = ser::Impossible<String, Error>;
        type SerializeTupleVariant = ser::Impossible<String, Error>;
        type SerializeMap = ser::Impossible<String, Error>;
        type SerializeStruct = ser::Impossible<String, Error>;
        type SerializeStructVariant = ser::Impossible<String, Error>;

        key_display!(serialize_i8: i8, serialize_i16: i16, serialize_i32: i32,
            serialize_i64: i64, serialize_i128: i128, serialize_u8: u8, serialize_u16: u16,
            serialize_u32: u32, serialize_u64: u64, serialize_u128: u128,
            serialize_bool: bool, serialize_char: char, serialize_str: &str);

        fn serialize_f32(self, v: f32) -> Result<String, Error> {
            self.serialize_f64(f64::from(v))
        }
        fn serialize_f64(self, v: f64) -> Result<String, Error> {
            if v.is_finite() {
                Ok(serde_json::Number::from_f64(v)
                    .map(|n| n.to_string())
                    .unwrap_or_default())
            } else {
                Err(Error("float key must be finite".into()))
            }
        }
        fn serialize_bytes(self, _: &[u8]) -> Result<String, Error> {
            Err(key_error())
        }
        fn serialize_none(self) -> Result<String, Error> {
            Err(key_error())
        }
        fn serialize_some<T: Serialize + ?Sized>(self, _: &T) -> Result<String, Error> {
            Err(key_error())
        }
        fn serialize_unit(self) -> Result<String, Error> {
            Err(key_error())
        }
        fn serialize_unit_struct(self, _: &'static str) -> Result<String, Error> {
            Err(key_error())
        }
        fn serialize_unit_variant(
            self,
            _: &'static str,
            _: u32,
            variant: &'static str,
        ) -> Result<String, Error> {
            Ok(variant.to_string())
        }
        fn serialize_newtype_struct<T: Serialize + ?Sized>(
            self,
            _: &'static str,
            v: &T,
        ) -> Result<String, Error> {
            v.serialize(self)
        }
        fn serialize_newtype_variant<T: Serialize + ?Sized>(
            self,
            _: &'static str,
            _: u32,
            _: &'static str,
            _: &T,
        ) -> Result<String, Error> {
            Err(key_error())
        }
        fn serialize_seq(self, _: Option<usize>) -> Result<Self::SerializeSeq, Error> {
            Err(key_error())
        }
        fn serialize_tuple(self, _: usize) -> Result<Self::SerializeTuple, Error> {
            Err(key_error())
        }
        fn serialize_tuple_struct(
            self,
            _: &'static str,
            _: usize,
        ) -> Result<Self::SerializeTupleStruct, Error> {
            Err(key_error())
        }
        fn serialize_tuple_variant(
            self,
            _: &'static str,
            _: u32,
            _: &'static str,
            _: usize,
        ) -> Result<Self::SerializeTupleVariant, Error> {
            Err(key_error())
        }
        fn serialize_map(self, _: Option<usize>) -> Result<Self::SerializeMap, Error> {
            Err(key_error())
        }
        fn serialize_struct(
            self,
            _: &'static str,
            _: usize,
        ) -> Result<Self::SerializeStruct, Error> {
            Err(key_error())
        }
        fn serialize_struct_variant(
            self,
            _: &'static str,
            _: u32,
            _: &'static str,
            _: usize,
        ) -> Result<Self::SerializeStructVariant, Error> {
            Err(key_error())
        }
    }
}
