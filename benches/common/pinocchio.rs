//! Pinocchio 4.1's C++ RNEA as the same-run reference of the benches ("the
//! pinocchio ratio in the same run"), timed by the harness `../shared/bench/pinocchio-rnea/
//! run.sh` beside the checkout (its README says how; the first run builds it, ~45 s).
//! `PRINTWATT_PINOCCHIO_RUN` names another copy of the harness. Shared by
//! `benches/dynamics.rs`, `benches/placement.rs`, `benches/layers.rs` and
//! `benches/optimise.rs`.

#![allow(dead_code)] // each bench uses what it needs

use std::path::{Path, PathBuf};
use std::process::Command;

/// The harness: `PRINTWATT_PINOCCHIO_RUN`, else `../shared/bench/pinocchio-rnea/run.sh`
/// beside the checkout.
pub fn harness() -> PathBuf {
    std::env::var_os("PRINTWATT_PINOCCHIO_RUN")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/bench/pinocchio-rnea/run.sh")
        })
}

/// Pinocchio's RNEA on `urdf`: ns per call (median over the harness's batches) and the
/// model's `nv`, or why it is unavailable.
pub fn rnea_ns(urdf: &Path) -> Result<(f64, usize), String> {
    let run = harness();
    if !run.is_file() {
        return Err(format!("{} not found", run.display()));
    }
    let out = Command::new(&run)
        .arg(urdf)
        .output()
        .map_err(|e| format!("cannot run {}: {e}", run.display()))?;
    if !out.status.success() {
        return Err(format!(
            "{} failed: {}",
            run.display(),
            String::from_utf8_lossy(&out.stderr)
                .lines()
                .last()
                .unwrap_or("")
        ));
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let field = |k: &str| {
        text.lines()
            .rev()
            .take(4)
            .find_map(|l| l.strip_prefix(k).and_then(|v| v.trim().parse::<f64>().ok()))
    };
    match (field("pinocchio_rnea_ns_per_call"), field("pinocchio_nv")) {
        (Some(ns), Some(nv)) => Ok((ns, nv as usize)),
        _ => Err("could not parse pinocchio_rnea_ns_per_call".into()),
    }
}

/// One line for a bench's output: `what` (ns per path sample) as a multiple of one Pinocchio
/// RNEA call on `urdf`, timed now (the same run), or why the reference is unavailable.
pub fn ratio_line(what: &str, ns_per_sample: f64, urdf: &Path) -> String {
    match rnea_ns(urdf) {
        Ok((pin, nv)) => format!(
            "  {what}: {ns_per_sample:.1} ns per path sample = {:.2} x Pinocchio 4.1's C++ RNEA call in this run ({pin:.1} ns, nv = {nv})",
            ns_per_sample / pin
        ),
        Err(e) => format!(
            "  {what}: {ns_per_sample:.1} ns per path sample; the Pinocchio reference is unavailable ({e})"
        ),
    }
}

/// One line for a bench's output: a whole run of `seconds` on a path of `samples` samples as
/// a multiple of one Pinocchio RNEA pass over those samples (one call each) timed now, or why
/// the reference is unavailable: a figure that carries from one machine to another.
pub fn pass_line(what: &str, seconds: f64, samples: usize, urdf: &Path) -> String {
    match rnea_ns(urdf) {
        Ok((pin, nv)) => {
            let pass = pin * 1e-9 * samples as f64;
            format!(
                "  {what}: {seconds:.3} s = {:.1} x one Pinocchio 4.1 C++ RNEA pass over the path's {samples} samples in this run ({pass:.4} s: {pin:.1} ns per call, nv = {nv})",
                seconds / pass
            )
        }
        Err(e) => format!("  {what}: {seconds:.3} s; the Pinocchio reference is unavailable ({e})"),
    }
}
