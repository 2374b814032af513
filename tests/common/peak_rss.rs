//! Peak resident memory of child processes, for the memory tests: of every child waited for
//! so far (`getrusage(RUSAGE_CHILDREN)`), or of one child on its own (`wait4`).
#![allow(dead_code)] // each test binary uses a subset

use std::process::{Command, ExitStatus, Stdio};

/// Peak resident memory of the children waited for so far, bytes (the maximum over them).
pub fn children_max_rss() -> u64 {
    let mut ru: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: `ru` is a valid, writable rusage for the call to fill.
    let rc = unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut ru) };
    assert_eq!(rc, 0, "getrusage");
    ru.ru_maxrss as u64 * 1024
}

/// What one child did: its exit status, its standard output and error, and its own peak
/// resident memory in bytes.
pub struct Run {
    pub status: ExitStatus,
    pub stdout: String,
    pub stderr: String,
    pub peak_rss: u64,
}

/// Run `cmd` to its end and measure its own peak resident memory (`wait4` on it alone, so
/// that runs measured one after the other do not see each other's peaks). Its output goes
/// through files in `scratch`, so that a full pipe cannot stall it while it is waited for.
#[allow(clippy::zombie_processes)] // the child is reaped by `wait4`, which gives its rusage
pub fn run_measured(cmd: &mut Command, scratch: &std::path::Path) -> Run {
    use std::os::unix::process::ExitStatusExt;
    let out = scratch.join(format!("peak-rss-{}.stdout", std::process::id()));
    let err = scratch.join(format!("peak-rss-{}.stderr", std::process::id()));
    let child = cmd
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out).expect("stdout file"))
        .stderr(std::fs::File::create(&err).expect("stderr file"))
        .spawn()
        .expect("spawn");
    let mut status = 0;
    let mut ru: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: the child's pid is ours to wait for; `status` and `ru` are valid and writable.
    let pid = unsafe { libc::wait4(child.id() as libc::pid_t, &mut status, 0, &mut ru) };
    assert_eq!(pid, child.id() as libc::pid_t, "wait4");
    drop(child);
    let read = |p: &std::path::Path| std::fs::read_to_string(p).unwrap_or_default();
    Run {
        status: ExitStatus::from_raw(status),
        stdout: read(&out),
        stderr: read(&err),
        peak_rss: ru.ru_maxrss as u64 * 1024,
    }
}
