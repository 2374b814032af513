//! Deterministic sharding of placement sweeps and of uncertainty studies' draws, for cluster
//! engines (a Slurm job array, a Kubernetes Indexed Job) and for splitting any long run by hand.
//!
//! The same holds for the draws of an uncertainty study ([`KIND_UNCERTAINTY`]): draw `d` owns
//! its own random stream, so shard `index` computes the draws `d mod count = index` and
//! [`merge`] returns them in draw order ([`MergedRows::Draws`]); and for the cases of a design
//! study ([`KIND_STUDY`]): each case is optimised from its own inputs alone, and [`merge`]
//! returns the cases' results in study order ([`MergedRows::Study`]).
//!
//! A sweep of `total` placements is split into `count` shards; shard `index` (0-based) owns the
//! placements `i` with `i mod count = index`. Interleaving keeps the shards' costs alike: a
//! grid's infeasible region (cheap, pruned early) is spread over every shard instead of falling
//! to one. Every placement's evaluation depends on the placement alone (no warm start across
//! placements), so a shard's rows are bit for bit the rows a single run computes for the same
//! placements; [`merge`] puts them back in sweep order.
//!
//! A shard is a directory holding [`HEADER`] (JSON: which shard, of what job, computed from
//! which inputs by which printwatt) and [`ROWS`] (the rows in postcard, a compact binary serde
//! format: `f64`s keep every bit, which JSON's shortest decimal form does only for finite
//! numbers and a reader with exact parsing). [`merge`] refuses shards of different jobs,
//! inputs or printwatt builds, a shard given twice, a missing shard and a damaged rows file,
//! and names which.

use crate::campaign::study::CaseResult;
use crate::error::{Error, Result};
use crate::evaluate::evaluator::{Evaluated, Feasible};
use crate::evaluate::feasibility::Infeasible;
use crate::frame::Placement;
use crate::search::uncertainty::Draw;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The shard header's file name inside a shard directory.
pub const HEADER: &str = "shard.json";
/// The shard rows' file name inside a shard directory.
pub const ROWS: &str = "rows.postcard";
/// Version of the shard files' layout.
pub const SCHEMA_VERSION: u32 = 1;
/// `kind` of a sweep shard.
pub const KIND_SWEEP: &str = "printwatt-sweep-shard";
/// `kind` of a shard of an `optimise --uncertainty` study (its rows are draws).
pub const KIND_UNCERTAINTY: &str = "printwatt-optimise-uncertainty-shard";
/// `kind` of a shard of a design study (its rows are cases, [`crate::campaign::study`]).
pub const KIND_STUDY: &str = "printwatt-study-shard";

/// One shard of a split run: `index` (0-based) of `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// 0-based index of this shard, `< count`.
    pub index: usize,
    /// Number of shards, ≥ 1.
    pub count: usize,
}

/// Where a shard's index and count were read from (for messages).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ShardSource {
    /// Given as `K/N`.
    Given,
    /// Slurm job array variables (`SLURM_ARRAY_TASK_ID`, `_MIN`, `_MAX`, `_COUNT`).
    Slurm,
    /// Kubernetes Indexed Job (`JOB_COMPLETION_INDEX`).
    Kubernetes,
}

impl Shard {
    /// Shard `index` of `count` (0-based index).
    pub fn new(index: usize, count: usize) -> Result<Shard> {
        if count == 0 {
            return Err(Error::Invalid("a run cannot be split into 0 shards".into()));
        }
        if index >= count {
            return Err(Error::Invalid(format!(
                "shard {index} of {count}: the index is 0-based and must be below {count}"
            )));
        }
        Ok(Shard { index, count })
    }

    /// Parse a shard specification, reading the environment through `env`:
    /// - `K/N`: shard `K` (0-based) of `N`;
    /// - `auto`: index and count from a Slurm job array (`SLURM_ARRAY_TASK_ID` minus
    ///   `SLURM_ARRAY_TASK_MIN`; count `SLURM_ARRAY_TASK_MAX − MIN + 1`, which must equal
    ///   `SLURM_ARRAY_TASK_COUNT`: the array must be contiguous, step 1);
    /// - `auto/N`: `N` shards, the index from Slurm as above or from a Kubernetes Indexed Job's
    ///   `JOB_COMPLETION_INDEX` (Kubernetes does not tell a pod the number of completions).
    pub fn parse(spec: &str, env: &dyn Fn(&str) -> Option<String>) -> Result<(Shard, ShardSource)> {
        let spec = spec.trim();
        let bad = |why: &str| {
            Error::Invalid(format!(
                "shard `{spec}`: {why} (expected K/N with a 0-based K, `auto` in a Slurm job array, or `auto/N`)"
            ))
        };
        let num = |s: &str, what: &str| -> Result<usize> {
            s.trim()
                .parse::<usize>()
                .map_err(|_| bad(&format!("{what} `{}` is not a whole number", s.trim())))
        };
        let (k, n) = match spec.split_once('/') {
            Some((k, n)) => (k.trim(), Some(num(n, "the count")?)),
            None => (spec, None),
        };
        if k != "auto" {
            let Some(n) = n else {
                return Err(bad("no count"));
            };
            return Ok((Shard::new(num(k, "the index")?, n)?, ShardSource::Given));
        }
        let var = |name: &str| -> Result<Option<usize>> {
            match env(name) {
                None => Ok(None),
                Some(v) => v.trim().parse::<usize>().map(Some).map_err(|_| {
                    Error::Invalid(format!(
                        "shard `{spec}`: the environment variable {name}=`{v}` is not a whole number"
                    ))
                }),
            }
        };
        if let Some(id) = var("SLURM_ARRAY_TASK_ID")? {
            let min = var("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
            let max = var("SLURM_ARRAY_TASK_MAX")?;
            let count = var("SLURM_ARRAY_TASK_COUNT")?;
            if id < min {
                return Err(Error::Invalid(format!(
                    "shard `{spec}`: SLURM_ARRAY_TASK_ID {id} is below SLURM_ARRAY_TASK_MIN {min}"
                )));
            }
            let span = max.map(|m| m + 1 - min.min(m + 1));
            let slurm_n = match (span, count) {
                (Some(s), Some(c)) if s != c => {
                    return Err(Error::Invalid(format!(
                        "shard `{spec}`: the Slurm array is not contiguous (tasks {min}..={} but {c} of them); use --array={min}-{} without a step or a list",
                        max.unwrap_or(min),
                        max.unwrap_or(min)
                    )))
                }
                (Some(s), _) => Some(s),
                (None, c) => c,
            };
            let n = match (n, slurm_n) {
                (Some(n), Some(s)) if n != s => {
                    return Err(Error::Invalid(format!(
                        "shard `{spec}`: {n} shards asked for, but the Slurm array has {s} tasks"
                    )))
                }
                (Some(n), _) => n,
                (None, Some(s)) => s,
                (None, None) => return Err(bad("Slurm does not say how many tasks the array has")),
            };
            return Ok((Shard::new(id - min, n)?, ShardSource::Slurm));
        }
        if let Some(id) = var("JOB_COMPLETION_INDEX")? {
            let Some(n) = n else {
                return Err(bad(
                    "in a Kubernetes Indexed Job give the number of completions, e.g. auto/8",
                ));
            };
            return Ok((Shard::new(id, n)?, ShardSource::Kubernetes));
        }
        Err(bad(
            "neither SLURM_ARRAY_TASK_ID (Slurm job array) nor JOB_COMPLETION_INDEX (Kubernetes Indexed Job) is set",
        ))
    }

    /// Whether this shard owns placement `i` (0-based, in sweep order).
    pub fn owns(&self, i: usize) -> bool {
        i % self.count == self.index
    }

    /// The placements this shard owns out of `total`, in sweep order.
    pub fn indices(&self, total: usize) -> Vec<usize> {
        (self.index..total).step_by(self.count).collect()
    }

    /// The directory name of this shard inside a parent: `shard-<K>-of-<N>` (K 0-based,
    /// zero-padded so that names sort in shard order).
    pub fn dir_name(&self) -> String {
        let w = (self.count - 1).to_string().len();
        format!("shard-{:0w$}-of-{}", self.index, self.count)
    }
}

/// What a shard was computed from: which job, which inputs, which printwatt.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShardHeader {
    /// [`SCHEMA_VERSION`].
    pub schema_version: u32,
    /// What kind of run was split ([`KIND_SWEEP`], [`KIND_UNCERTAINTY`], [`KIND_STUDY`]).
    pub kind: String,
    /// This shard.
    pub shard: Shard,
    /// Items in the whole run: placements (a sweep), draws (an uncertainty study) or cases (a
    /// design study).
    pub total: usize,
    /// Items (rows) in this shard.
    pub rows: usize,
    /// The job in a normalised form: every option that changes a result (not where the output
    /// goes, not the thread count, not the shard). Shards of one run have the same job.
    pub job: String,
    /// The command line of the shard run, to rebuild the job when merging.
    pub args: Vec<String>,
    /// The working directory the shard ran in; relative paths in `args` are relative to it.
    pub cwd: PathBuf,
    /// SHA-256 of every input file (as named in the run), hex.
    pub inputs: BTreeMap<String, String>,
    /// The printwatt build (`printwatt --version`); shards of different builds do not merge.
    pub version: String,
    /// SHA-256 of the rows file, hex.
    pub rows_sha256: String,
    /// Wall time of the shard's evaluations, s (informative; not part of any result).
    pub wall_time_s: f64,
}

/// A row in the shard file: the placement's raw numbers (m, rad) and the outcome as it is in
/// memory (postcard keeps every bit of every `f64`).
#[derive(Serialize, Deserialize)]
struct Row {
    index: u64,
    /// x, y, z (m), yaw, nozzle spin (rad).
    placement: [f64; 5],
    outcome: std::result::Result<Feasible, Infeasible>,
    /// The outcome's path-reduction estimate (not part of `Feasible`'s own serialisation).
    path_reduction: Option<crate::evaluate::reduce::Estimate>,
}

/// Encode a shard's rows (index in sweep order, evaluation).
pub fn encode_rows(rows: &[(usize, Evaluated)]) -> Result<Vec<u8>> {
    let rows: Vec<Row> = rows
        .iter()
        .map(|(i, e)| Row {
            index: *i as u64,
            placement: [
                e.placement.x,
                e.placement.y,
                e.placement.z,
                e.placement.yaw,
                e.placement.nozzle_spin,
            ],
            outcome: e.outcome.clone(),
            path_reduction: e.feasible().and_then(|f| f.path_reduction.clone()),
        })
        .collect();
    postcard::to_stdvec(&rows).map_err(|e| Error::Invalid(format!("encoding shard rows: {e}")))
}

/// Decode a shard's rows (what [`encode_rows`] wrote); `what` names the file in errors.
pub(crate) fn decode_rows(bytes: &[u8], what: &str) -> Result<Vec<(usize, Evaluated)>> {
    let rows: Vec<Row> = postcard::from_bytes(bytes)
        .map_err(|e| Error::Invalid(format!("{what}: not a printwatt shard rows file ({e})")))?;
    Ok(rows
        .into_iter()
        .map(|r| {
            let [x, y, z, yaw, nozzle_spin] = r.placement;
            let mut outcome = r.outcome;
            if let Ok(f) = &mut outcome {
                f.path_reduction = r.path_reduction;
            }
            (
                r.index as usize,
                Evaluated {
                    placement: Placement {
                        x,
                        y,
                        z,
                        yaw,
                        nozzle_spin,
                    },
                    outcome,
                },
            )
        })
        .collect())
}

/// Encode a shard's draws of an uncertainty study (draw index, draw).
pub fn encode_draws(rows: &[(usize, Draw)]) -> Result<Vec<u8>> {
    postcard::to_stdvec(rows).map_err(|e| Error::Invalid(format!("encoding shard draws: {e}")))
}

/// Encode a shard's cases of a design study (case index, result).
pub fn encode_cases(rows: &[(usize, CaseResult)]) -> Result<Vec<u8>> {
    postcard::to_stdvec(rows).map_err(|e| Error::Invalid(format!("encoding shard cases: {e}")))
}

/// Decode a shard's cases (what [`encode_cases`] wrote); `what` names the file in errors.
pub(crate) fn decode_cases(bytes: &[u8], what: &str) -> Result<Vec<(usize, CaseResult)>> {
    postcard::from_bytes(bytes)
        .map_err(|e| Error::Invalid(format!("{what}: not a printwatt shard cases file ({e})")))
}

/// Decode a shard's draws (what [`encode_draws`] wrote); `what` names the file in errors.
pub(crate) fn decode_draws(bytes: &[u8], what: &str) -> Result<Vec<(usize, Draw)>> {
    postcard::from_bytes(bytes)
        .map_err(|e| Error::Invalid(format!("{what}: not a printwatt shard draws file ({e})")))
}

/// The rows of a shard, by the kind of run it split.
#[derive(Clone, Debug)]
pub enum ShardRows {
    /// A sweep's rows: (index in sweep order, evaluation).
    Sweep(Vec<(usize, Evaluated)>),
    /// An uncertainty study's draws: (draw index, draw).
    Draws(Vec<(usize, Draw)>),
    /// A design study's cases: (case index, result).
    Study(Vec<(usize, CaseResult)>),
}

impl ShardRows {
    /// The indices the rows hold, in the order stored.
    pub fn indices(&self) -> Vec<usize> {
        match self {
            ShardRows::Sweep(r) => r.iter().map(|(i, _)| *i).collect(),
            ShardRows::Draws(r) => r.iter().map(|(i, _)| *i).collect(),
            ShardRows::Study(r) => r.iter().map(|(i, _)| *i).collect(),
        }
    }
}

/// A whole run's rows in order.
#[derive(Clone, Debug)]
pub enum MergedRows {
    /// Every placement's evaluation, in sweep order.
    Sweep(Vec<Evaluated>),
    /// Every draw, in draw order.
    Draws(Vec<Draw>),
    /// Every case's result, in study order.
    Study(Vec<CaseResult>),
}

/// A shard read from its directory.
#[derive(Clone, Debug)]
pub struct ShardData {
    /// The directory it was read from.
    pub dir: PathBuf,
    /// Its header.
    pub header: ShardHeader,
    /// Its rows.
    pub rows: ShardRows,
}

/// Read one shard directory (its header and rows; the rows' SHA-256 checked).
pub fn read_shard(dir: &Path) -> Result<ShardData> {
    let hp = dir.join(HEADER);
    let text = std::fs::read_to_string(&hp)
        .map_err(|e| Error::Invalid(format!("{}: {e}", hp.display())))?;
    let header: ShardHeader = serde_json::from_str(&text).map_err(|e| {
        Error::Invalid(format!(
            "{}: not a printwatt shard header ({e})",
            hp.display()
        ))
    })?;
    if header.schema_version != SCHEMA_VERSION {
        return Err(Error::Invalid(format!(
            "{}: shard layout version {} (this printwatt reads version {SCHEMA_VERSION})",
            hp.display(),
            header.schema_version
        )));
    }
    // A header edited by hand (or damaged) must not hold a shard no run writes.
    Shard::new(header.shard.index, header.shard.count)
        .map_err(|e| Error::Invalid(format!("{}: `shard`: {e}", hp.display())))?;
    let rp = dir.join(ROWS);
    let bytes = std::fs::read(&rp).map_err(|e| Error::Invalid(format!("{}: {e}", rp.display())))?;
    let sha = crate::output::sha256_hex(&bytes);
    if sha != header.rows_sha256 {
        return Err(Error::Invalid(format!(
            "{}: damaged or replaced (SHA-256 {sha}, the header says {})",
            rp.display(),
            header.rows_sha256
        )));
    }
    let what = rp.display().to_string();
    let rows = match header.kind.as_str() {
        KIND_SWEEP => ShardRows::Sweep(decode_rows(&bytes, &what)?),
        KIND_UNCERTAINTY => ShardRows::Draws(decode_draws(&bytes, &what)?),
        KIND_STUDY => ShardRows::Study(decode_cases(&bytes, &what)?),
        k => {
            return Err(Error::Invalid(format!(
                "{}: a shard of kind `{k}`, which this printwatt does not know",
                hp.display()
            )))
        }
    };
    Ok(ShardData {
        dir: dir.to_path_buf(),
        header,
        rows,
    })
}

/// The shard directories named by `paths`: each is a shard directory (holding [`HEADER`]) or
/// a directory whose subdirectories are shards (e.g. the `--out` every array task wrote into).
/// Sorted by path, duplicates (the same directory named twice) removed.
pub fn find_shards(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for p in paths {
        if p.join(HEADER).is_file() {
            out.push(p.clone());
            continue;
        }
        let rd =
            std::fs::read_dir(p).map_err(|e| Error::Invalid(format!("{}: {e}", p.display())))?;
        let mut found = false;
        for e in rd {
            let e = e.map_err(|e| Error::Invalid(format!("{}: {e}", p.display())))?;
            if e.path().join(HEADER).is_file() {
                out.push(e.path());
                found = true;
            }
        }
        if !found {
            return Err(Error::Invalid(format!(
                "{}: neither a shard directory (no {HEADER}) nor a directory holding shards",
                p.display()
            )));
        }
    }
    out.sort();
    let mut canon: Vec<PathBuf> = Vec::new();
    out.retain(|p| {
        let c = std::fs::canonicalize(p).unwrap_or_else(|_| p.clone());
        if canon.contains(&c) {
            false
        } else {
            canon.push(c);
            true
        }
    });
    Ok(out)
}

/// A whole run put back together from its shards.
#[derive(Clone, Debug)]
pub struct Merged {
    /// The header of shard 0 (job, args, cwd, inputs, version are the same in every shard).
    pub header: ShardHeader,
    /// Every row, in order (placements in sweep order, or draws in draw order).
    pub rows: MergedRows,
    /// Sum of the shards' wall times, s.
    pub shard_wall_time_s: f64,
}

/// Put shards back together: they must be of one job (same kind, job, inputs and printwatt
/// build, same count and total), each shard present once, each holding exactly the rows it
/// owns. Errors name the shard directories at fault.
pub fn merge(shards: Vec<ShardData>) -> Result<Merged> {
    let Some(first) = shards.first() else {
        return Err(Error::Invalid("no shards to merge".into()));
    };
    let h0 = first.header.clone();
    let d0 = first.dir.display().to_string();
    let n = h0.shard.count;
    let mut slot: Vec<Option<&ShardData>> = vec![None; n];
    for s in &shards {
        let h = &s.header;
        let d = s.dir.display();
        check_same_run(s, &h0, &d0)?;
        check_shard_rows(s, n)?;
        if let Some(prev) = slot[h.shard.index] {
            return Err(Error::Invalid(format!(
                "shard {} of {n} is given twice: {} and {d}",
                h.shard.index,
                prev.dir.display()
            )));
        }
        slot[h.shard.index] = Some(s);
    }
    let missing: Vec<String> = slot
        .iter()
        .enumerate()
        .filter(|(_, s)| s.is_none())
        .map(|(i, _)| i.to_string())
        .collect();
    if !missing.is_empty() {
        return Err(Error::Invalid(format!(
            "{} of {n} shards missing (0-based: {}); merge needs every shard of the run",
            missing.len(),
            missing.join(", ")
        )));
    }
    let wall: f64 = shards.iter().map(|s| s.header.wall_time_s).sum();
    // Every shard is of kind h0.kind (checked above), so each holds rows of that kind.
    let rows = match h0.kind.as_str() {
        KIND_SWEEP => MergedRows::Sweep(place(h0.total, &shards, |r| match r {
            ShardRows::Sweep(r) => Some(r.as_slice()),
            _ => None,
        })),
        KIND_STUDY => MergedRows::Study(place(h0.total, &shards, |r| match r {
            ShardRows::Study(r) => Some(r.as_slice()),
            _ => None,
        })),
        _ => MergedRows::Draws(place(h0.total, &shards, |r| match r {
            ShardRows::Draws(r) => Some(r.as_slice()),
            _ => None,
        })),
    };
    let header = slot[0].map(|s| s.header.clone()).unwrap_or(h0);
    Ok(Merged {
        header,
        rows,
        shard_wall_time_s: wall,
    })
}

/// The rows of every shard (those `pick` finds) put at their indices 0..total. Every index is
/// held exactly once (checked by [`merge`]), so each slot is filled.
fn place<'s, T: Clone + 's>(
    total: usize,
    shards: &'s [ShardData],
    pick: impl Fn(&'s ShardRows) -> Option<&'s [(usize, T)]>,
) -> Vec<T> {
    let mut rows: Vec<Option<T>> = vec![None; total];
    for part in shards.iter().filter_map(|s| pick(&s.rows)) {
        for (i, e) in part {
            rows[*i] = Some(e.clone());
        }
    }
    rows.into_iter().flatten().collect()
}

/// Refuse a shard of another run than shard `h0` (directory `d0`): another kind, build,
/// shard count, number of items, options or input files.
fn check_same_run(s: &ShardData, h0: &ShardHeader, d0: &str) -> Result<()> {
    let h = &s.header;
    let d = s.dir.display();
    let n = h0.shard.count;
    let differs = |what: &str, a: &dyn std::fmt::Display, b: &dyn std::fmt::Display| {
        Error::Invalid(format!(
            "{d} is not a shard of the same run as {d0}: its {what} is {a}, not {b}"
        ))
    };
    if h.kind != h0.kind {
        return Err(differs("kind", &h.kind, &h0.kind));
    }
    if h.version != h0.version {
        return Err(differs("printwatt build", &h.version, &h0.version));
    }
    if h.shard.count != n {
        return Err(differs("shard count", &h.shard.count, &n));
    }
    if h.total != h0.total {
        return Err(differs("number of items", &h.total, &h0.total));
    }
    if h.job != h0.job {
        return Err(Error::Invalid(format!(
            "{d} is not a shard of the same run as {d0}: the options differ\n  {d}: {}\n  {d0}: {}",
            h.args.join(" "),
            h0.args.join(" ")
        )));
    }
    if h.inputs != h0.inputs {
        let which: Vec<&str> = h
            .inputs
            .iter()
            .filter(|(k, v)| h0.inputs.get(*k) != Some(v))
            .map(|(k, _)| k.as_str())
            .chain(
                h0.inputs
                    .keys()
                    .filter(|k| !h.inputs.contains_key(*k))
                    .map(String::as_str),
            )
            .collect();
        return Err(Error::Invalid(format!(
            "{d} and {d0} were computed from different input files: {} changed between the shards' runs",
            which.join(", ")
        )));
    }
    Ok(())
}

/// Refuse a shard that does not hold exactly the rows it owns (`n`: the shard count).
fn check_shard_rows(s: &ShardData, n: usize) -> Result<()> {
    let h = &s.header;
    let d = s.dir.display();
    let want = h.shard.indices(h.total);
    let have = s.rows.indices();
    if have != want || h.rows != want.len() {
        return Err(Error::Invalid(format!(
            "{d}: shard {} of {n} should hold items {}, {}, … ({} rows) and holds {} rows",
            h.shard.index,
            h.shard.index,
            h.shard.index + n,
            want.len(),
            have.len()
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env<'a>(vars: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |k| {
            vars.iter()
                .find(|(n, _)| *n == k)
                .map(|(_, v)| v.to_string())
        }
    }

    #[test]
    fn shards_partition_the_placements_in_interleaved_order() {
        for n in 1..6 {
            let mut seen = vec![0; 23];
            for k in 0..n {
                let s = Shard::new(k, n).unwrap();
                for i in s.indices(23) {
                    assert!(s.owns(i));
                    seen[i] += 1;
                }
            }
            assert!(seen.iter().all(|c| *c == 1), "{n} shards: {seen:?}");
        }
    }

    #[test]
    fn shard_spec_is_read_from_the_flag_slurm_or_kubernetes() {
        let none = env(&[]);
        assert_eq!(
            Shard::parse("2/4", &none).unwrap().0,
            Shard::new(2, 4).unwrap()
        );
        assert!(Shard::parse("4/4", &none).is_err());
        assert!(Shard::parse("1/0", &none).is_err());
        assert!(Shard::parse("x/4", &none).is_err());
        assert!(Shard::parse("auto", &none)
            .unwrap_err()
            .to_string()
            .contains("SLURM_ARRAY_TASK_ID"));
        let slurm = env(&[
            ("SLURM_ARRAY_TASK_ID", "3"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
            ("SLURM_ARRAY_TASK_MAX", "4"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ]);
        let (s, src) = Shard::parse("auto", &slurm).unwrap();
        assert_eq!((s, src), (Shard::new(2, 4).unwrap(), ShardSource::Slurm));
        assert!(Shard::parse("auto/5", &slurm).is_err());
        let stepped = env(&[
            ("SLURM_ARRAY_TASK_ID", "2"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_MAX", "6"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ]);
        assert!(Shard::parse("auto", &stepped)
            .unwrap_err()
            .to_string()
            .contains("not contiguous"));
        let k8s = env(&[("JOB_COMPLETION_INDEX", "7")]);
        assert_eq!(
            Shard::parse("auto/8", &k8s).unwrap(),
            (Shard::new(7, 8).unwrap(), ShardSource::Kubernetes)
        );
        assert!(Shard::parse("auto", &k8s).is_err());
        assert!(Shard::parse("auto/7", &k8s).is_err());
    }

    #[test]
    fn shard_rows_keep_every_bit_including_non_finite_numbers() {
        use crate::evaluate::feasibility::Reason;
        let inf = Evaluated {
            placement: Placement {
                x: 0.1 + 0.2,
                y: -1.0 / 3.0,
                z: f64::MIN_POSITIVE,
                yaw: std::f64::consts::PI,
                nozzle_spin: -0.0,
            },
            outcome: Err(Infeasible {
                reason: Reason::Unreachable,
                sample: Some(17),
                t_s: Some(f64::INFINITY),
                line: None,
                point_m: Some([1.0e-300, f64::NAN, 3.0]),
                detail: "ä detail".into(),
            }),
        };
        let bytes = encode_rows(&[(5, inf.clone())]).unwrap();
        let back = decode_rows(&bytes, "t").unwrap();
        assert_eq!(back.len(), 1);
        assert_eq!(back[0].0, 5);
        let b = &back[0].1;
        assert_eq!(b.placement.x.to_bits(), inf.placement.x.to_bits());
        assert_eq!(b.placement.y.to_bits(), inf.placement.y.to_bits());
        assert_eq!(
            b.placement.nozzle_spin.to_bits(),
            inf.placement.nozzle_spin.to_bits()
        );
        let (Err(a), Err(o)) = (&b.outcome, &inf.outcome) else {
            panic!("outcome changed kind");
        };
        assert_eq!(a.t_s.map(f64::to_bits), o.t_s.map(f64::to_bits));
        assert_eq!(
            a.point_m.map(|p| p.map(f64::to_bits)),
            o.point_m.map(|p| p.map(f64::to_bits))
        );
        assert_eq!(a.detail, o.detail);
        assert!(decode_rows(&bytes[..bytes.len() - 3], "cut").is_err());
    }
}
