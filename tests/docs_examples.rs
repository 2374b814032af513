//! The documentation cannot drift from the code: the drive-file examples of
//! `docs/drive-file.md` load through the robot loader, the measurement-log examples of
//! `docs/measurement-logs.md` read through the log reader, the drive-file reference names every
//! key the shipped drive files use, every document the repository points to exists inside it,
//! and the manual reads as a manual, not as a log of work.
//!
//! Example blocks name what they need on their fence line: ```` ```toml robot=<shipped
//! robot> ```` (the block is written as `drive.toml` beside a copy of that robot's URDF) and
//! ```` ```csv robot=<shipped robot> columns="<column map>" ```` (the column map only for a
//! log without a header).

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(rel: &str) -> String {
    std::fs::read_to_string(root().join(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "printwatt-docs-{tag}-{}-{}",
        std::process::id(),
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |t| t.subsec_nanos())
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A fenced block: the line of its fence (1-based), the fence's info string after the
/// language, and its text.
struct Block {
    line: usize,
    info: String,
    text: String,
}

/// The fenced blocks of `text` in language `lang` (```` ```lang ```` or ```` ```lang info ````).
fn blocks(text: &str, lang: &str) -> Vec<Block> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let t = lines[i].trim();
        let info = t
            .strip_prefix("```")
            .and_then(|r| r.strip_prefix(lang))
            .filter(|r| r.is_empty() || r.starts_with(' '));
        if let Some(info) = info {
            let line = i + 1;
            let mut body = Vec::new();
            i += 1;
            while i < lines.len() && lines[i].trim() != "```" {
                body.push(lines[i]);
                i += 1;
            }
            out.push(Block {
                line,
                info: info.trim().to_string(),
                text: body.join("\n") + "\n",
            });
        }
        i += 1;
    }
    out
}

/// The value of `key=value` or `key="value with spaces"` on a fence line.
fn info_value(info: &str, key: &str) -> Option<String> {
    let start = info.find(&format!("{key}="))? + key.len() + 1;
    let rest = &info[start..];
    Some(match rest.strip_prefix('"') {
        Some(q) => q[..q.find('"').expect("closing quote on the fence line")].to_string(),
        None => rest.split_whitespace().next().unwrap_or("").to_string(),
    })
}

#[test]
fn drive_file_doc_example_loads() {
    let doc = read("docs/drive-file.md");
    let bs = blocks(&doc, "toml");
    assert!(
        bs.len() >= 3,
        "docs/drive-file.md: {} toml blocks",
        bs.len()
    );
    let (mut with_drive, mut with_opw, mut with_ranges) = (false, false, false);
    for b in &bs {
        let at = format!("docs/drive-file.md:{}", b.line);
        let robot = info_value(&b.info, "robot")
            .unwrap_or_else(|| panic!("{at}: the fence line names no `robot=`"));
        let d = scratch("drive");
        std::fs::copy(
            root().join("robots").join(&robot).join("robot.urdf"),
            d.join("robot.urdf"),
        )
        .unwrap_or_else(|e| panic!("{at}: shipped robot `{robot}`: {e}"));
        std::fs::write(d.join("drive.toml"), &b.text).unwrap();
        // A drive file naming its URDF is given on its own, as a calibrated robot is;
        // otherwise the directory is the robot.
        let given = if b.text.contains("\nurdf =") || b.text.starts_with("urdf =") {
            d.join("drive.toml")
        } else {
            d.clone()
        };
        let model = printwatt::load_robot(&given).unwrap_or_else(|e| panic!("{at}: {e}"));
        printwatt::effects::EffectSet::of_robot(&model)
            .unwrap_or_else(|e| panic!("{at}: the [effects] table: {e}"));
        let ranges = printwatt::search::uncertainty::Ranges::of_robot(&model)
            .unwrap_or_else(|e| panic!("{at}: the [uncertainty] table: {e}"));
        assert_eq!(
            ranges.is_some(),
            b.text.contains("[uncertainty]"),
            "{at}: the [uncertainty] table was not read"
        );
        with_drive |= model.drive.is_some();
        with_opw |= model.opw.is_some();
        with_ranges |= ranges.is_some();
        let _ = std::fs::remove_dir_all(&d);
    }
    assert!(
        with_drive && with_opw && with_ranges,
        "docs/drive-file.md: no complete example (drive data {with_drive}, OPW {with_opw}, \
         uncertainty ranges {with_ranges})"
    );
}

/// Every key of every shipped drive file, as `table.key` (arrays of tables without an index).
fn keys(v: &toml::Value, pre: &str, out: &mut Vec<String>) {
    match v {
        toml::Value::Table(t) => {
            for (k, v) in t {
                let name = if pre.is_empty() {
                    k.clone()
                } else {
                    format!("{pre}.{k}")
                };
                out.push(name.clone());
                keys(v, &name, out);
            }
        }
        toml::Value::Array(a) => {
            for v in a.iter().filter(|v| v.is_table()) {
                keys(v, pre, out);
            }
        }
        _ => {}
    }
}

#[test]
fn drive_file_doc_names_every_key_of_the_shipped_drive_files() {
    let doc = read("docs/drive-file.md");
    let mut found = Vec::new();
    for e in std::fs::read_dir(root().join("robots")).unwrap() {
        let p = e.unwrap().path().join("drive.toml");
        if p.is_file() {
            let v: toml::Value = std::fs::read_to_string(&p).unwrap().parse().unwrap();
            keys(&v, "", &mut found);
        }
    }
    assert!(
        found.len() > 20,
        "{} keys in the shipped drive files",
        found.len()
    );
    let mut missing: Vec<String> = found
        .into_iter()
        .filter(|k| {
            let last = k.rsplit('.').next().unwrap();
            !(doc.contains(&format!("`{last}`"))
                || doc.contains(&format!("`[{k}]`"))
                || doc.contains(&format!("`[[{k}]]`")))
        })
        .collect();
    missing.sort();
    missing.dedup();
    assert!(
        missing.is_empty(),
        "docs/drive-file.md does not document these keys of the shipped drive files: {missing:?}"
    );
}

#[test]
fn measurement_log_doc_example_reads() {
    let doc = read("docs/measurement-logs.md");
    let bs = blocks(&doc, "csv");
    assert!(
        bs.len() >= 2,
        "docs/measurement-logs.md: {} csv blocks",
        bs.len()
    );
    let mut with_map = false;
    for b in &bs {
        let at = format!("docs/measurement-logs.md:{}", b.line);
        let robot = info_value(&b.info, "robot")
            .unwrap_or_else(|| panic!("{at}: the fence line names no `robot=`"));
        let columns = info_value(&b.info, "columns");
        with_map |= columns.is_some();
        let model = printwatt::load_robot(&root().join("robots").join(&robot))
            .unwrap_or_else(|e| panic!("{at}: shipped robot `{robot}`: {e}"));
        let d = scratch("log");
        let file = d.join("log.csv");
        std::fs::write(&file, &b.text).unwrap();
        let log = printwatt::identify::read_log_for(&model, &file, columns.as_deref())
            .unwrap_or_else(|e| panic!("{at}: {e}"));
        assert!(
            log.warnings.is_empty(),
            "{at}: the example reads with warnings: {:?}",
            log.warnings
        );
        assert!(log.len() >= 50, "{at}: {} samples", log.len());
        // The units of the examples (ms, deg) are converted: the motion is well within a
        // turn and a second.
        assert!(
            log.traj.duration() > 0.0 && log.traj.duration() < 1.0,
            "{at}: duration {} s",
            log.traj.duration()
        );
        assert!(
            log.traj.q.iter().all(|q| q.abs() < std::f64::consts::PI),
            "{at}: joint angles not converted to rad"
        );
        let _ = std::fs::remove_dir_all(&d);
    }
    assert!(
        with_map,
        "docs/measurement-logs.md: no example of a log read through a column map"
    );
}

/// Text files under `dir` (recursively), skipping build output.
fn text_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        let name = e.file_name().to_string_lossy().into_owned();
        if p.is_dir() {
            if !matches!(
                name.as_str(),
                "target" | "__pycache__" | ".venv" | "node_modules"
            ) && !name.starts_with('.')
            {
                text_files(&p, out);
            }
        } else if std::fs::read_to_string(&p).is_ok() {
            out.push(p);
        }
    }
}

/// The documents of the manual: README.md, docs/*.md, results/README.md.
fn manual() -> Vec<PathBuf> {
    let mut files = vec![
        root().join("README.md"),
        root().join("results/README.md"),
        root().join("robots/README.md"),
        root().join("paths/README.md"),
    ];
    for e in std::fs::read_dir(root().join("docs")).unwrap().flatten() {
        if e.path().extension().is_some_and(|x| x == "md") {
            files.push(e.path());
        }
    }
    files.sort();
    files
}

/// What else a user reads: the shipped robots' drive files, the presets and the committed
/// results' READMEs.
fn user_files() -> Vec<PathBuf> {
    let mut files = manual();
    for dir in ["robots", "results"] {
        for e in std::fs::read_dir(root().join(dir)).unwrap().flatten() {
            for name in ["drive.toml", "README.md"] {
                let f = e.path().join(name);
                if f.is_file() {
                    files.push(f);
                }
            }
        }
    }
    for e in std::fs::read_dir(root().join("presets")).unwrap().flatten() {
        if e.path().extension().is_some_and(|x| x == "toml") {
            files.push(e.path());
        }
    }
    files.sort();
    files
}

/// `docs/<name>.md` mentions in `text`: the names.
fn doc_mentions(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find("docs/") {
        let after = &rest[i + 5..];
        let name: String = after
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '-' || *c == '_')
            .collect();
        let preceded_by_path = rest[..i]
            .chars()
            .last()
            .is_some_and(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
        if !name.is_empty() && after[name.len()..].starts_with(".md") && !preceded_by_path {
            out.push(name);
        }
        rest = &rest[i + 5..];
    }
    out
}

#[test]
fn docs_point_only_inside_the_repository() {
    let mut files = user_files();
    text_files(&root().join("src"), &mut files);
    text_files(&root().join("python"), &mut files);
    assert!(files.len() > 50, "{} files", files.len());
    let mut bad = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        let rel = f.strip_prefix(root()).unwrap_or(f).display().to_string();
        for (k, line) in text.lines().enumerate() {
            if line.contains("../shared") {
                bad.push(format!(
                    "{rel}:{}: points outside the repository: {}",
                    k + 1,
                    line.trim()
                ));
            }
            for name in doc_mentions(line) {
                if !root().join("docs").join(format!("{name}.md")).is_file() {
                    bad.push(format!("{rel}:{}: docs/{name}.md does not exist", k + 1));
                }
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// Whether `line` names `word` (case-insensitive, a whole word) followed by a number
/// (`session 12`, `Issue #9`, `issue-12`).
fn word_then_number(line: &str, word: &str) -> bool {
    let lower = line.to_lowercase();
    let b = lower.as_bytes();
    let mut from = 0;
    while let Some(i) = lower[from..].find(word) {
        let s = from + i;
        let e = s + word.len();
        from = e;
        if s > 0 && b[s - 1].is_ascii_alphanumeric() {
            continue;
        }
        let mut k = e;
        while k < b.len() && matches!(b[k], b' ' | b'#' | b'-' | b'_') {
            k += 1;
        }
        if k > e && k < b.len() && b[k].is_ascii_digit() {
            return true;
        }
        if k == e && k < b.len() && b[k].is_ascii_digit() {
            return true;
        }
    }
    false
}

/// Whether `line` holds an ISO date `YYYY-MM-DD`.
fn iso_date(line: &str) -> bool {
    let b = line.as_bytes();
    let d = |i: usize| b.get(i).is_some_and(|c| c.is_ascii_digit());
    (0..b.len()).any(|i| {
        (i == 0 || !d(i - 1))
            && (0..4).all(|k| d(i + k))
            && b.get(i + 4) == Some(&b'-')
            && d(i + 5)
            && d(i + 6)
            && b.get(i + 7) == Some(&b'-')
            && d(i + 8)
            && d(i + 9)
            && !d(i + 10)
    })
}

#[test]
fn diary_words_are_recognised() {
    assert!(word_then_number("### Session 12 (x)", "session"));
    assert!(word_then_number("at session 11's end", "session"));
    assert!(word_then_number("issue 12, item 3", "issue"));
    assert!(word_then_number("(issue #9)", "issue"));
    assert!(word_then_number("the issue-9 regeneration", "issue"));
    assert!(!word_then_number("a known issue with 3 joints", "issue"));
    assert!(!word_then_number("sessions of work", "session"));
    assert!(iso_date("measured on 2026-11-26 at idle"));
    assert!(!iso_date("a range 12-34-56"));
    assert!(!iso_date("date = \"YYYY-MM-DD\""));
}

#[test]
fn docs_are_not_a_diary() {
    let mut bad = Vec::new();
    for f in manual() {
        let text = std::fs::read_to_string(&f).unwrap();
        let rel = f.strip_prefix(root()).unwrap_or(&f).display().to_string();
        for (k, line) in text.lines().enumerate() {
            let what = if word_then_number(line, "session") {
                "names a session"
            } else if word_then_number(line, "issue") {
                "names an issue number"
            } else if iso_date(line) {
                "carries a date"
            } else {
                continue;
            };
            bad.push(format!("{rel}:{}: {what}: {}", k + 1, line.trim()));
        }
    }
    assert!(
        bad.is_empty(),
        "the manual describes the product, not the work on it:\n{}",
        bad.join("\n")
    );
}
