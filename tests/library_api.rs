//! The pieces that used to live in the CLI and are now library functions:
//! one placement parser, derivative completion, the train/validation split. None of their
//! errors names a command-line flag.

use printwatt::dynamics::complete_derivatives;
use printwatt::toolpath::{Placement, PlacementParseError};
use printwatt::trajectory::{JointTrajectory, Supplied};

#[test]
fn one_placement_parser_takes_an_optional_spin_and_refuses_nan() {
    let p = Placement::parse("1.7, 0,0.2,90").unwrap();
    assert_eq!((p.x, p.y, p.z), (1.7, 0.0, 0.2));
    assert!((p.yaw - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    assert_eq!(p.nozzle_spin, 0.0);
    let p: Placement = "1.7,0,0.2,90,45".parse().unwrap();
    assert!((p.nozzle_spin - std::f64::consts::FRAC_PI_4).abs() < 1e-15);
    assert_eq!(
        Placement::parse("1.7,0,nan,90"),
        Err(PlacementParseError::NotFinite {
            item: 3,
            text: "nan".into()
        })
    );
    assert_eq!(
        Placement::parse("1.7,0,0,inf"),
        Err(PlacementParseError::NotFinite {
            item: 4,
            text: "inf".into()
        })
    );
    assert_eq!(
        Placement::parse("1.7,,0,90"),
        Err(PlacementParseError::Empty { item: 2 })
    );
    assert_eq!(
        Placement::parse("1.7,x,0,90"),
        Err(PlacementParseError::NotANumber {
            item: 2,
            text: "x".into()
        })
    );
    assert_eq!(
        Placement::parse("1.7,0,0"),
        Err(PlacementParseError::Count { got: 3 })
    );
    assert_eq!(
        Placement::parse("1,2,3,4,5,6"),
        Err(PlacementParseError::Count { got: 6 })
    );
    for bad in ["1.7,0,nan,90", "", "1,2", "a,b,c,d"] {
        let msg = Placement::parse(bad).unwrap_err().to_string();
        assert!(!msg.contains("--"), "a library error names a flag: {msg}");
    }
}

fn traj(t: &[f64], q: &[f64]) -> JointTrajectory {
    JointTrajectory {
        n: 1,
        t: t.to_vec(),
        q: q.to_vec(),
        qd: vec![0.0; q.len()],
        qdd: vec![0.0; q.len()],
    }
}

#[test]
fn derivative_completion_keeps_what_the_file_gave() {
    // q = t², q̇ = 2t, q̈ = 2 on a non-uniform grid: the three-point quadratic is exact.
    let t = [0.0, 0.1, 0.25, 0.4, 0.6];
    let q: Vec<f64> = t.iter().map(|x| x * x).collect();
    // Positions only: both derivatives from q.
    let mut a = traj(&t, &q);
    let none = Supplied {
        velocities: false,
        accelerations: false,
    };
    complete_derivatives(&mut a, none).unwrap();
    for (k, &x) in t.iter().enumerate() {
        assert!((a.qd[k] - 2.0 * x).abs() < 1e-12, "{k}");
        assert!((a.qdd[k] - 2.0).abs() < 1e-12, "{k}");
    }
    // Velocities given (deliberately not 2t, to see they are kept): q̈ from them.
    let mut b = traj(&t, &q);
    b.qd = t.iter().map(|x| 3.0 * x).collect();
    let vel = Supplied {
        velocities: true,
        accelerations: false,
    };
    complete_derivatives(&mut b, vel).unwrap();
    for (k, &x) in t.iter().enumerate() {
        assert!((b.qd[k] - 3.0 * x).abs() < 1e-15);
        assert!((b.qdd[k] - 3.0).abs() < 1e-12, "{k}");
    }
    // Accelerations given, velocities not: q̇ from q, q̈ kept.
    let mut c = traj(&t, &q);
    c.qdd = vec![7.0; t.len()];
    let acc = Supplied {
        velocities: false,
        accelerations: true,
    };
    complete_derivatives(&mut c, acc).unwrap();
    assert!(c.qdd.iter().all(|&v| v == 7.0));
    assert!((c.qd[2] - 0.5).abs() < 1e-12);
    // Time not increasing: an error, not a panic, naming no flag.
    let mut d = traj(&[0.0, 0.1, 0.1], &[0.0, 1.0, 2.0]);
    let e = complete_derivatives(&mut d, none).unwrap_err().to_string();
    assert!(
        e.contains("not strictly increasing") && !e.contains("--"),
        "{e}"
    );
}

#[test]
fn train_validation_split_is_the_first_three_quarters_then_the_rest() {
    let (tr, va) = printwatt::identify::train_validation_split(1000);
    assert_eq!((tr, va), (0..750, 750..1000));
    let (tr, va) = printwatt::identify::train_validation_split(7);
    assert_eq!((tr.end, va.start, va.end), (5, 5, 7));
    let (tr, va) = printwatt::identify::train_validation_split(0);
    assert!(tr.is_empty() && va.is_empty());
}

#[test]
fn utc_stamp_names_run_directories() {
    assert_eq!(printwatt::output::utc_stamp(0), "19700101T000000Z");
    assert_eq!(
        printwatt::output::utc_stamp(1_795_000_000),
        "20261118T110640Z"
    );
}

/// The string literals of a Rust source text (normal and raw strings), comments skipped.
fn string_literals(src: &str) -> Vec<(usize, String)> {
    let b = src.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    let line_at = |i: usize| src[..i].matches('\n').count() + 1;
    while i < b.len() {
        match b[i] {
            b'/' if b.get(i + 1) == Some(&b'/') => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                i += 2;
                while i + 1 < b.len() && !(b[i] == b'*' && b[i + 1] == b'/') {
                    i += 1;
                }
                i += 2;
            }
            b'\'' => {
                // A char literal ('"', '\'', 'x') or a lifetime ('a).
                if b.get(i + 1) == Some(&b'\\') {
                    i += 2;
                    while i < b.len() && b[i] != b'\'' {
                        i += 1;
                    }
                    i += 1;
                } else if b.get(i + 2) == Some(&b'\'') {
                    i += 3;
                } else {
                    i += 1;
                }
            }
            b'r' if matches!(b.get(i + 1), Some(b'"') | Some(b'#'))
                && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_')) =>
            {
                let mut j = i + 1;
                let mut hashes = 0;
                while b.get(j) == Some(&b'#') {
                    hashes += 1;
                    j += 1;
                }
                if b.get(j) != Some(&b'"') {
                    i += 1;
                    continue;
                }
                let close = format!("\"{}", "#".repeat(hashes));
                let start = j + 1;
                let end = src[start..].find(&close).map_or(b.len(), |e| start + e);
                out.push((line_at(i), src[start..end].to_string()));
                i = end + close.len();
            }
            b'"' => {
                let start = i + 1;
                let mut j = start;
                while j < b.len() && b[j] != b'"' {
                    j += if b[j] == b'\\' { 2 } else { 1 };
                }
                out.push((line_at(i), src[start..j.min(b.len())].to_string()));
                i = j + 1;
            }
            _ => i += 1,
        }
    }
    out
}

/// `--name` (a command-line option) in a text.
fn names_a_flag(s: &str) -> Option<&str> {
    let b = s.as_bytes();
    (0..b.len().saturating_sub(2)).find_map(|k| {
        let before_ok = k == 0 || !(b[k - 1] == b'-' || b[k - 1].is_ascii_alphanumeric());
        (before_ok && b[k] == b'-' && b[k + 1] == b'-' && b[k + 2].is_ascii_lowercase())
            .then(|| &s[k..(k + 20).min(s.len())])
    })
}

/// Library messages never name command-line options: the library is used from Rust and
/// Python, where no `--flag` exists; the binary (src/cli, src/main.rs) maps typed errors and
/// advice to its options. Scans every string literal of the library's sources, and the
/// rendered advice and errors that once named flags.
#[test]
fn library_errors_never_name_command_line_flags() {
    // The scanner finds what it must (so that a clean scan means something).
    let probe = "let a = \"ok\"; // \"--not-this\"\nlet b = format!(\"give --out DIR\");\nlet c = r#\"raw --force\"#;";
    let found: Vec<String> = string_literals(probe)
        .into_iter()
        .filter_map(|(_, s)| names_a_flag(&s).map(str::to_string))
        .collect();
    assert_eq!(found.len(), 2, "{found:?}");

    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    let mut stack = vec![src.clone()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                if p != src.join("cli") {
                    stack.push(p);
                }
            } else if p.extension().is_some_and(|x| x == "rs") && p != src.join("main.rs") {
                files.push(p);
            }
        }
    }
    assert!(files.len() > 50, "{} library files", files.len());
    let mut bad = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        // Unit tests inside a library file may run the binary; only the library proper.
        let text = text.split("#[cfg(test)]").next().unwrap_or("");
        for (line, s) in string_literals(text) {
            // Other programs' options a message may quote (Slurm's `sbatch --array`).
            let s = s.replace("--array=", "");
            if let Some(flag) = names_a_flag(&s) {
                bad.push(format!("{}:{line}: {flag}…", f.display()));
            }
        }
    }
    assert!(
        bad.is_empty(),
        "library messages naming flags:\n{}",
        bad.join("\n")
    );

    // The rendered advice and the errors that once named flags.
    use printwatt::evaluate::Reason;
    use printwatt::search::advice::what_to_try;
    for r in [
        Reason::Unreachable,
        Reason::ConfigurationChange,
        Reason::JointLimitMargin,
        Reason::WristSingularity,
        Reason::ElbowSingularity,
        Reason::ShoulderSingularity,
        Reason::CollisionBed,
        Reason::SelfCollision,
    ] {
        let a = what_to_try(r);
        let words = a.to_string();
        assert!(
            names_a_flag(&words).is_none() && !words.contains("{}"),
            "{words}"
        );
        // A front end names the settings its own way.
        let cli = a.render(&|k| format!("--{}", k.words().replace(' ', "-")));
        assert_eq!(cli.contains("--"), !a.knobs.is_empty(), "{cli}");
    }
    let e = printwatt::identify::simulate::parse_hidden("viscous").unwrap_err();
    assert!(names_a_flag(&e.to_string()).is_none(), "{e}");
}

/// The library's public items (`pub fn`, `pub struct`, … outside the command-line front end),
/// counted in the source; items only the crate uses are `pub(crate)`.
fn public_items() -> usize {
    fn walk(dir: &std::path::Path, n: &mut usize) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                if !p.ends_with("cli") && !p.ends_with("assets") {
                    walk(&p, n);
                }
            } else if p.extension().is_some_and(|x| x == "rs") && !p.ends_with("main.rs") {
                let text = std::fs::read_to_string(&p).unwrap();
                *n += text
                    .lines()
                    .filter(|l| {
                        let l = l.trim_start();
                        l.strip_prefix("pub ").is_some_and(|rest| {
                            let rest = rest.trim_start_matches("unsafe ");
                            // `pub const fn` is a function; `pub const X` a constant.
                            let rest = rest.strip_prefix("const fn ").map_or(rest, |_| "fn ");
                            [
                                "fn ", "struct ", "enum ", "trait ", "type ", "const ", "static ",
                                "mod ", "use ",
                            ]
                            .iter()
                            .any(|k| rest.starts_with(k))
                        })
                    })
                    .count();
            }
        }
    }
    let mut n = 0;
    walk(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &mut n,
    );
    n
}

/// What the library offers outside the crate does not grow unnoticed: an item only the crate
/// itself uses is `pub(crate)` (the `private_interfaces` lint in Cargo.toml keeps such an
/// item out of public signatures). An item is public when the command line, the Python
/// bindings, a test, a bench or an example names it, or when a public item's signature or a
/// re-export shows it. Raise the bound only for a new public item a user needs.
#[test]
fn the_public_surface_does_not_grow_past_its_recorded_size() {
    const RECORDED: usize = 1217;
    let n = public_items();
    eprintln!("{n} public items (bound {RECORDED})");
    assert!(
        n > 500,
        "the count found only {n} public items: is src/ where it was?"
    );
    assert!(
        n <= RECORDED,
        "{n} public items, {RECORDED} recorded: make crate-internal items `pub(crate)`"
    );
}
