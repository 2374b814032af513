//! Seeded mutation test of every reader ("nothing crashes"). The shipped files
//! (robots/*, paths/*, paths/placements/*, tests/data/*) are the seeds; each is mutated
//! (byte flips, deletions, duplications, numbers swapped for nasty ones, empty fields, a BOM,
//! CR-only line endings, deep nesting) and read by the library inside `catch_unwind`.
//!
//! Asserted for every mutated input:
//! - no panic;
//! - every `Err` is *located*: its message names the mutated file (or, for a robot, one of
//!   its two files) AND a location, i.e. it is an [`Error::Parse`] (file, line ≥ 1, column),
//!   an [`Error::Field`] (file and a non-empty field), an [`Error::MissingInertial`] (file and
//!   link), an [`Error::Io`] (path), or any other variant whose text contains the file name and
//!   one of `line(s) <n>`, `row(s) <n>`, `column <n>`, `:<n>:` or a back-quoted field name;
//! - every `Ok` value holds no NaN or infinite number (checked on its `Debug` form, with
//!   quoted strings removed, so a link called `nan` does not count); the one exception is
//!   `±inf` in the joint-limit fields, where the model documents it as "no limit".
//!
//! Mutations per reader: `PRINTWATT_MUTATIONS` (default 40; the README's 10,000-input figures
//! come from `PRINTWATT_MUTATIONS=1000`, 11 readers). Seeded with ChaCha8 (seed 10), so a
//! failure is reproducible; the failing input is written beside the message.

use printwatt::error::Error;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn count() -> usize {
    std::env::var("PRINTWATT_MUTATIONS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(40)
}

const NASTY: &[&str] = &[
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "1e309",
    "-0",
    "1e-300",
    "4.9e-324",
    "123456789012345678901234567890123456789012345678901234567890",
    "0",
    "",
    "-",
    "1e",
    "0x10",
    "18446744073709551616",
    "9999999999",
];

/// Byte spans of number-like tokens.
fn number_spans(b: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_digit() {
            let mut s = i;
            if s > 0 && (b[s - 1] == b'-' || b[s - 1] == b'+') {
                s -= 1;
            }
            let mut e = i;
            while e < b.len()
                && (b[e].is_ascii_digit() || matches!(b[e], b'.' | b'e' | b'E' | b'-' | b'+'))
            {
                e += 1;
            }
            out.push((s, e));
            i = e;
        } else {
            i += 1;
        }
    }
    out
}

fn mutate(seed: &[u8], rng: &mut ChaCha8Rng, xml: bool) -> Vec<u8> {
    let mut b = seed.to_vec();
    let rounds = rng.gen_range(1..=3);
    for _ in 0..rounds {
        let len = b.len().max(1);
        match rng.gen_range(0..10) {
            0 => {
                // byte flips
                for _ in 0..rng.gen_range(1..8) {
                    if !b.is_empty() {
                        let i = rng.gen_range(0..b.len());
                        b[i] ^= 1 << rng.gen_range(0..8);
                    }
                }
            }
            1 => {
                // deletion of a range
                let i = rng.gen_range(0..len);
                let n = rng.gen_range(1..=(len - i).min(400));
                b.drain(i.min(b.len())..(i + n).min(b.len()));
            }
            2 => {
                // duplication of a range
                let i = rng.gen_range(0..len);
                let n = rng.gen_range(1..=(len - i).min(400));
                let piece: Vec<u8> = b[i.min(b.len())..(i + n).min(b.len())].to_vec();
                let at = rng.gen_range(0..=b.len());
                b.splice(at..at, piece);
            }
            3..=5 => {
                // numbers swapped for nasty ones (several)
                let spans = number_spans(&b);
                if !spans.is_empty() {
                    for _ in 0..rng.gen_range(1..4) {
                        let spans = number_spans(&b);
                        if spans.is_empty() {
                            break;
                        }
                        let (s, e) = spans[rng.gen_range(0..spans.len())];
                        let t = NASTY[rng.gen_range(0..NASTY.len())];
                        b.splice(s..e, t.bytes());
                    }
                }
            }
            6 => {
                // empty field: drop the text between two separators
                let seps: Vec<usize> = (0..b.len())
                    .filter(|&i| matches!(b[i], b',' | b' ' | b'"' | b'='))
                    .collect();
                if seps.len() > 1 {
                    let k = rng.gen_range(0..seps.len() - 1);
                    b.drain(seps[k] + 1..seps[k + 1]);
                }
            }
            7 => {
                let mut v = b"\xEF\xBB\xBF".to_vec();
                v.extend_from_slice(&b);
                b = v;
            }
            8 => {
                // CR-only or CRLF line endings
                let cr_only = rng.gen_bool(0.5);
                let mut v = Vec::with_capacity(b.len() + 100);
                for &c in &b {
                    if c == b'\n' {
                        v.push(b'\r');
                        if !cr_only {
                            v.push(b'\n');
                        }
                    } else {
                        v.push(c);
                    }
                }
                b = v;
            }
            _ => {
                // deep nesting
                let depth = rng.gen_range(50..5000);
                let at = rng.gen_range(0..=b.len());
                let (open, close): (&[u8], &[u8]) = if xml {
                    (b"<a>", b"</a>")
                } else {
                    match rng.gen_range(0..3) {
                        0 => (b"[", b"]"),
                        1 => (b"{", b"}"),
                        _ => (b"(", b")"),
                    }
                };
                let mut ins = Vec::new();
                for _ in 0..depth {
                    ins.extend_from_slice(open);
                }
                if rng.gen_bool(0.5) {
                    for _ in 0..depth {
                        ins.extend_from_slice(close);
                    }
                }
                b.splice(at..at, ins);
            }
        }
    }
    b
}

/// Fields whose documented value for "no limit" is `±inf` (`robot::model::Joint`): an
/// infinity there is the model's sentinel, not an overflow. NaN is never allowed.
const INF_MEANS_NO_LIMIT: &[&str] = &[
    "lower",
    "upper",
    "velocity_limit",
    "acceleration_limit",
    "jerk_limit",
];

/// The `Debug` text with quoted strings removed, searched for `NaN` and `inf` words.
fn has_non_finite(debug: &str) -> Option<String> {
    let mut plain = String::with_capacity(debug.len());
    let mut in_str = false;
    let mut esc = false;
    for c in debug.chars() {
        if in_str {
            if esc {
                esc = false;
            } else if c == '\\' {
                esc = true;
            } else if c == '"' {
                in_str = false;
            }
            continue;
        }
        if c == '"' {
            in_str = true;
            plain.push(' ');
        } else {
            plain.push(c);
        }
    }
    let words: Vec<&str> = plain
        .split(|c: char| !(c.is_alphanumeric() || c == '_'))
        .filter(|w| !w.is_empty())
        .collect();
    words
        .iter()
        .enumerate()
        .position(|(k, &w)| {
            w == "NaN" || (w == "inf" && !(k > 0 && INF_MEANS_NO_LIMIT.contains(&words[k - 1])))
        })
        .map(|k| words[k.saturating_sub(12)..(k + 3).min(words.len())].join(" "))
}

fn has_location(text: &str) -> bool {
    let words = ["line ", "lines ", "row ", "rows ", "column ", "field "];
    for w in words {
        let mut rest = text;
        while let Some(i) = rest.find(w) {
            rest = &rest[i + w.len()..];
            if rest.chars().next().is_some_and(|c| c.is_ascii_digit()) {
                return true;
            }
        }
    }
    let b = text.as_bytes();
    for i in 0..b.len() {
        if b[i] == b':' {
            let mut j = i + 1;
            while j < b.len() && b[j].is_ascii_digit() {
                j += 1;
            }
            if j > i + 1 && j < b.len() && b[j] == b':' {
                return true;
            }
        }
    }
    text.matches('`').count() >= 2
}

/// Why an error is not located, or `None` when it is.
fn unlocated(e: &Error, files: &[&str]) -> Option<String> {
    let text = e.to_string();
    let names = |s: &str| files.iter().any(|f| s.contains(f));
    let ok = match e {
        Error::Parse { file, line, .. } => names(file) && *line >= 1,
        Error::Field { file, field, .. } => names(file) && !field.is_empty(),
        Error::MissingInertial { file, link } => names(file) && !link.is_empty(),
        Error::Io { path, .. } => names(&path.display().to_string()),
        _ => names(&text) && has_location(&text),
    };
    (!ok).then_some(text)
}

#[derive(Default, Debug)]
struct Tally {
    inputs: usize,
    ok: usize,
    errors: usize,
    panics: Vec<String>,
    unlocated: Vec<String>,
    non_finite: Vec<String>,
}

#[derive(Clone, Copy, Debug)]
enum Reader {
    Urdf,
    Drive,
    Gcode,
    Rapid,
    CsvPath,
    Placements,
    Trajectory,
    Log,
    /// A design study file (`studies/*.toml`).
    Study,
    /// A shard's header (`shard.json`), read and merged with the run's other shard.
    ShardHeader,
    /// A shard's rows (`rows.postcard`, its header's SHA-256 made to match), read and merged.
    ShardRows,
}

/// A two-shard sweep of the default robot, computed once by the binary: the seed of the
/// shard readers.
fn shard_set() -> &'static PathBuf {
    static SET: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    SET.get_or_init(|| {
        let d =
            std::env::temp_dir().join(format!("printwatt-fuzzmut-shards-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        for k in 0..2 {
            let o = std::process::Command::new(env!("CARGO_BIN_EXE_printwatt"))
                .args([
                    "sweep",
                    "--x",
                    "1.5:1.9:0.2",
                    "--y",
                    "-0.4:0.4:0.4",
                    "--yaw",
                    "90",
                    "--shard",
                    &format!("{k}/2"),
                    "--out",
                    "parts",
                ])
                .current_dir(&d)
                .output()
                .unwrap();
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        }
        d.join("parts")
    })
}

fn seeds(r: Reader) -> Vec<PathBuf> {
    let list = |dir: &str, ext: &str| -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = std::fs::read_dir(root().join(dir))
            .map(|d| {
                d.filter_map(|e| e.ok().map(|e| e.path()))
                    .filter(|p| p.extension().is_some_and(|x| x == ext))
                    .collect()
            })
            .unwrap_or_default();
        v.sort();
        v
    };
    let robots = || {
        let mut v: Vec<PathBuf> = std::fs::read_dir(root().join("robots"))
            .unwrap()
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.join("robot.urdf").exists())
            .collect();
        v.sort();
        v
    };
    match r {
        Reader::Urdf => robots().into_iter().map(|p| p.join("robot.urdf")).collect(),
        Reader::Drive => robots().into_iter().map(|p| p.join("drive.toml")).collect(),
        Reader::Gcode => [list("paths", "gcode"), list("tests/data/toolpath", "gcode")].concat(),
        Reader::Rapid => [list("paths", "mod"), list("tests/data/toolpath", "mod")].concat(),
        Reader::CsvPath => list("tests/data/toolpath", "csv"),
        Reader::Placements => list("paths/placements", "csv"),
        Reader::Trajectory => list("tests/data/traj", "csv"),
        Reader::Log => list("tests/data/logs", "csv"),
        Reader::Study => list("studies", "toml"),
        Reader::ShardHeader => vec![shard_set().join("shard-0-of-2/shard.json")],
        Reader::ShardRows => vec![shard_set().join("shard-0-of-2/rows.postcard")],
    }
}

/// Read a mutated shard file: its directory (the mutated file beside an intact copy of the
/// other) is read and merged with the set's other shard.
fn read_shard(path: &Path) -> Result<String, Error> {
    use printwatt::campaign::shard::{merge, read_shard};
    let data = read_shard(path.parent().unwrap())?;
    let other = read_shard(&shard_set().join("shard-1-of-2"))?;
    Ok(format!("{:?}", merge(vec![data, other])?.rows))
}

/// Read `path` (a mutated copy) with the reader; `Ok(debug text)` or the error.
fn read(r: Reader, path: &Path) -> Result<String, Error> {
    use printwatt::toolpath::{load, load_placements, ReadOptions};
    Ok(match r {
        Reader::Urdf | Reader::Drive => {
            format!("{:?}", printwatt::robot::load(path.parent().unwrap())?)
        }
        Reader::Gcode | Reader::Rapid | Reader::CsvPath => {
            let tp = load(path, &ReadOptions::default())?;
            format!(
                "{tp:?} length {:?} print {:?}",
                tp.length(),
                tp.print_length()
            )
        }
        Reader::Placements => format!("{:?}", load_placements(path)?),
        Reader::Trajectory => format!("{:?}", printwatt::trajectory::read_csv(path, 6)?),
        Reader::Log => format!(
            "{:?}",
            printwatt::identify::log::read_log(path, 6, None).map(|l| (l.traj, l.y))?
        ),
        Reader::Study => format!("{:?}", printwatt::campaign::study::Study::read(path)?),
        Reader::ShardHeader | Reader::ShardRows => read_shard(path)?,
    })
}

fn run_reader(r: Reader, n: usize, tally: &mut Tally) {
    let seeds = seeds(r);
    assert!(!seeds.is_empty(), "{r:?}: no seed files");
    let dir = std::env::temp_dir().join(format!("printwatt-fuzzmut-{}-{r:?}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(10 + r as u64);
    for k in 0..n {
        let seed = &seeds[k % seeds.len()];
        let bytes = std::fs::read(seed).unwrap();
        let xml = matches!(r, Reader::Urdf);
        let mutated = mutate(&bytes, &mut rng, xml);
        let file_name = seed.file_name().unwrap().to_string_lossy().into_owned();
        let target = dir.join(&file_name);
        let mut names = vec![file_name.clone()];
        if matches!(r, Reader::Urdf | Reader::Drive) {
            for f in ["robot.urdf", "drive.toml"] {
                std::fs::copy(seed.parent().unwrap().join(f), dir.join(f)).unwrap();
            }
            names = vec!["robot.urdf".into(), "drive.toml".into()];
        }
        let target = if matches!(r, Reader::ShardHeader | Reader::ShardRows) {
            // The shard directory keeps its name, so that a message naming it is located.
            let sd = dir.join("shard-0-of-2");
            std::fs::create_dir_all(&sd).unwrap();
            for f in ["shard.json", "rows.postcard"] {
                std::fs::copy(seed.parent().unwrap().join(f), sd.join(f)).unwrap();
            }
            names = vec!["shard-0-of-2".into()];
            let t = sd.join(&file_name);
            if matches!(r, Reader::ShardRows) {
                // The header is made to match the mutated rows, so that the rows are decoded.
                let h = std::fs::read_to_string(sd.join("shard.json")).unwrap();
                let old = printwatt::output::sha256_hex(&bytes);
                let new = printwatt::output::sha256_hex(&mutated);
                std::fs::write(sd.join("shard.json"), h.replace(&old, &new)).unwrap();
            }
            t
        } else {
            target
        };
        std::fs::write(&target, &mutated).unwrap();
        tally.inputs += 1;
        let what = format!("{r:?} #{k} from {}", seed.display());
        let keep = |tag: &str| {
            let p = std::env::temp_dir().join(format!("printwatt-fuzzmut-{tag}-{r:?}-{k}"));
            let _ = std::fs::write(&p, &mutated);
            p.display().to_string()
        };
        match catch_unwind(AssertUnwindSafe(|| read(r, &target))) {
            Err(p) => {
                let msg = p
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                tally
                    .panics
                    .push(format!("{what}: panic {msg} (input {})", keep("panic")));
            }
            Ok(Ok(debug)) => {
                tally.ok += 1;
                if let Some(ctx) = has_non_finite(&debug) {
                    tally
                        .non_finite
                        .push(format!("{what}: …{ctx}… (input {})", keep("nonfinite")));
                }
            }
            Ok(Err(e)) => {
                tally.errors += 1;
                let refs: Vec<&str> = names.iter().map(|s| s.as_str()).collect();
                // A shard's files are JSON and binary: naming the shard directory (and, for
                // the header, JSON's line and column) locates the fault.
                let located = match r {
                    Reader::ShardRows => {
                        let t = e.to_string();
                        (!t.contains("shard-0-of-2/rows.postcard")).then_some(t)
                    }
                    Reader::ShardHeader => {
                        let t = e.to_string();
                        (!t.contains("shard-0-of-2")).then_some(t)
                    }
                    _ => unlocated(&e, &refs),
                };
                if let Some(t) = located {
                    tally
                        .unlocated
                        .push(format!("{what}: {t} (input {})", keep("unlocated")));
                }
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_reader_survives_seeded_mutations_with_located_errors_and_finite_results() {
    let n = count();
    let start = std::time::Instant::now();
    // Quiet the default hook: a panic is recorded, not printed.
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let mut tally = Tally::default();
    let readers = [
        Reader::Urdf,
        Reader::Drive,
        Reader::Gcode,
        Reader::Rapid,
        Reader::CsvPath,
        Reader::Placements,
        Reader::Trajectory,
        Reader::Log,
        Reader::Study,
        Reader::ShardHeader,
        Reader::ShardRows,
    ];
    for r in readers {
        let t = std::time::Instant::now();
        run_reader(r, n, &mut tally);
        eprintln!("{r:?}: {n} mutations in {:.2} s", t.elapsed().as_secs_f64());
    }
    std::panic::set_hook(hook);
    eprintln!(
        "inputs {} ok {} errors {} panics {} unlocated errors {} non-finite results {} in {:.1} s",
        tally.inputs,
        tally.ok,
        tally.errors,
        tally.panics.len(),
        tally.unlocated.len(),
        tally.non_finite.len(),
        start.elapsed().as_secs_f64()
    );
    for l in tally
        .panics
        .iter()
        .chain(&tally.unlocated)
        .chain(&tally.non_finite)
        .take(40)
    {
        eprintln!("  {l}");
    }
    assert_eq!(tally.inputs, n * readers.len());
    assert!(tally.panics.is_empty(), "panics: {:#?}", tally.panics);
    assert!(
        tally.unlocated.is_empty(),
        "errors without file and location: {:#?}",
        tally.unlocated
    );
    assert!(
        tally.non_finite.is_empty(),
        "non-finite numbers in Ok results: {:#?}",
        tally.non_finite
    );
}

#[test]
fn the_mutation_oracles_catch_what_they_guard() {
    // The checks above must be able to fail: a NaN in a Debug text is seen, a quoted `nan`
    // is not; an unlocated error is seen.
    assert!(has_non_finite("Move { x: NaN }").is_some());
    assert!(has_non_finite("[1.0, -inf]").is_some());
    assert!(has_non_finite("Joint { upper: inf, velocity_limit: inf }").is_none());
    assert!(has_non_finite("Joint { upper: inf, mass: inf }").is_some());
    assert!(has_non_finite("Link { name: \"nan inf\", m: 1.0 }").is_none());
    let e = Error::Invalid("something went wrong".into());
    assert!(unlocated(&e, &["p.gcode"]).is_some());
    let e = Error::Invalid("p.gcode: line 3: bad".into());
    assert!(unlocated(&e, &["p.gcode"]).is_none());
    let e = Error::Parse {
        file: "p.gcode".into(),
        line: 3,
        column: 1,
        msg: "x".into(),
    };
    assert!(unlocated(&e, &["p.gcode"]).is_none());
}
