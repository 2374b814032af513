//! Golden transcripts of the command line: for every command and the error cases that matter,
//! the command, its stdout, its stderr and its exit code, in `tests/transcripts/<name>.txt`.
//! A change of any of them fails here with a diff-like message; when the change is meant,
//! `PRINTWATT_BLESS=1 cargo test --release --test cli_transcripts` rewrites the files (review
//! them with `git diff tests/transcripts`).
//!
//! Volatile parts are normalised explicitly, and only these: the repository path (`<ROOT>`),
//! the scratch directory (`<TMP>`), the version and commit (`<VERSION>`), wall-clock times
//! (`<SECONDS> s`, `<RATE> placements/s`) and UTC stamps (`<UTC>`). Every number of a result
//! stays as printed.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// One transcript: a name (its file), the arguments (`{ROOT}` and `{TMP}` expanded), and the
/// files a case needs written into its scratch directory first.
struct Case {
    name: &'static str,
    args: &'static str,
    files: &'static [(&'static str, &'static str)],
}

const CASES: &[Case] = &[
    Case {
        name: "robots",
        args: "robots",
        files: &[],
    },
    Case {
        name: "energy_at_a_placement",
        args: "energy --path {ROOT}/paths/default.gcode --at 1.7,0,0,90,30 --no-csv",
        files: &[],
    },
    Case {
        name: "energy_of_a_trajectory",
        args: "energy --robot abb_irb6700_200_260 --trajectory {ROOT}/tests/data/traj/irb6700_default_25hz.csv --out {TMP}/e",
        files: &[],
    },
    Case {
        name: "sweep_small_grid",
        args: "sweep --path {ROOT}/paths/default.gcode --x 1.4:1.8:0.4 --y 0 --z 0.2 --yaw 0,90",
        files: &[],
    },
    Case {
        name: "optimise_small",
        args: "optimise --path {ROOT}/paths/default.gcode --x 1.4:1.8:0.2 --y -0.2:0.2:0.2 --z 0.2 --yaw 0,90 --max-evals 10 --tolerance 0,0 --no-report",
        files: &[],
    },
    Case {
        name: "stations_track",
        args: "stations --path {ROOT}/paths/floor_four_rooms.gcode --relocation-cost 20000 --track -1,1.5:13,1.5 --wrist-margin 0 --out {TMP}/stations",
        files: &[],
    },
    Case {
        name: "excite",
        args: "excite --robot abb_irb6700_200_260 --tries 20 --rate 50 --out {TMP}/excite",
        files: &[],
    },
    Case {
        name: "simulate",
        args: "simulate --robot abb_irb4600_40_255 --excite 8 --hidden coulomb=30 --signal tau --noise 2 --rate 100 --seed 7 --out {TMP}",
        files: &[],
    },
    Case {
        name: "compare",
        args: "compare --robot abb_irb4600_40_255 --log {TMP}/log.csv",
        files: &[],
    },
    Case {
        name: "diagnose",
        args: "diagnose --robot abb_irb4600_40_255 --log {TMP}/log.csv",
        files: &[],
    },
    Case {
        name: "identify",
        args: "identify --robot abb_irb4600_40_255 --log {TMP}/log.csv --effects coulomb --out {TMP}/id",
        files: &[],
    },
    Case {
        name: "sweep_shard_0_of_2",
        args: "sweep --path {ROOT}/paths/default.gcode --x 1.4:1.8:0.4 --y 0 --z 0.2 --yaw 0,90 --shard 0/2 --out {TMP}/shards",
        files: &[],
    },
    Case {
        name: "sweep_shard_1_of_2",
        args: "sweep --path {ROOT}/paths/default.gcode --x 1.4:1.8:0.4 --y 0 --z 0.2 --yaw 0,90 --shard 1/2 --out {TMP}/shards",
        files: &[],
    },
    Case {
        name: "merge",
        args: "merge {TMP}/shards --out {TMP}/merged",
        files: &[],
    },
    Case {
        name: "study_two_arms",
        args: "study {TMP}/study.toml --out {TMP}/study",
        files: &[
            ("study_wall.gcode", include_str!("../paths/default.gcode")),
            (
                "study.toml",
                "[study]\nname = \"two-arms\"\noptions = [\"--max-evals\", \"12\"]\n\n[[robot]]\nname = \"big\"\nrobot = \"abb_irb6700_200_260\"\n\n[[robot]]\nname = \"small\"\nrobot = \"abb_irb4600_40_255\"\n\n[[cell]]\nname = \"near\"\nx = \"1.3:1.7:0.2\"\ny = \"-0.25:0.25:0.25\"\nyaw = 90\n\n[[cell]]\nname = \"far\"\nx = 4.5\ny = 0\nyaw = \"0,90\"\n\n[[path]]\nname = \"wall\"\nfile = \"study_wall.gcode\"\n",
            ),
        ],
    },
    Case {
        name: "error_robot_name_typo",
        args: "energy --robot abb_irb670 --path {ROOT}/paths/default.gcode --at 1.7,0,0,90 --no-csv",
        files: &[],
    },
    Case {
        name: "error_placement_in_millimetres",
        args: "energy --path {ROOT}/paths/default.gcode --at 1700,0,0,90 --no-csv",
        files: &[],
    },
    Case {
        name: "error_malformed_gcode",
        args: "energy --path {TMP}/bad.gcode --at 1.7,0,0,90 --no-csv",
        files: &[(
            "bad.gcode",
            "G21\nG90\nG1 X0 Y0 Z0 F6000\nG1 X100 Y0 E1\nG1 X100 Yabc E2\n",
        )],
    },
    Case {
        name: "error_unknown_option",
        args: "sweep --yaws 0,90",
        files: &[],
    },
    Case {
        name: "inspect_gcode",
        args: "inspect {ROOT}/paths/default.gcode",
        files: &[],
    },
    Case {
        name: "inspect_rapid",
        args: "inspect {ROOT}/paths/wall_rapid.mod",
        files: &[],
    },
    Case {
        name: "inspect_csv_in_assumed_mm_json",
        args: "inspect {TMP}/wall.csv --json",
        files: &[(
            "wall.csv",
            "x,y,z,print\n0,0,20,1\n2000,0,20,1\n2000,1000,20,1\n2000,1000,40,0\n0,0,40,1\n",
        )],
    },
    Case {
        name: "inspect_refuses_a_robot",
        args: "inspect {ROOT}/robots/abb_irb6700_200_260",
        files: &[],
    },
    // A drive-file template for a URDF of one's own, then the same again: refused, the file kept.
    Case {
        name: "robot_init",
        args: "robot init {TMP}/arm.urdf --out {TMP}/arm_drive.toml",
        files: &[("arm.urdf", "<?xml version=\"1.0\"?>\n<robot name=\"three_joint_arm\">\n  <link name=\"base_link\"/>\n  <link name=\"link_1\">\n    <inertial><mass value=\"20\"/><origin xyz=\"0 0 0.2\"/><inertia ixx=\"0.5\" iyy=\"0.5\" izz=\"0.1\"/></inertial>\n  </link>\n  <link name=\"link_2\">\n    <inertial><mass value=\"10\"/><origin xyz=\"0.3 0 0\"/><inertia ixx=\"0.05\" iyy=\"0.3\" izz=\"0.3\"/></inertial>\n  </link>\n  <link name=\"link_3\"/>\n  <link name=\"tool0\"/>\n  <joint name=\"joint_1\" type=\"revolute\">\n    <parent link=\"base_link\"/><child link=\"link_1\"/><origin xyz=\"0 0 0.4\"/><axis xyz=\"0 0 1\"/>\n    <limit lower=\"-3\" upper=\"3\" velocity=\"2\" effort=\"0\"/>\n  </joint>\n  <joint name=\"joint_2\" type=\"revolute\">\n    <parent link=\"link_1\"/><child link=\"link_2\"/><origin xyz=\"0 0 0.4\"/><axis xyz=\"0 1 0\"/>\n    <limit lower=\"-2\" upper=\"2\" velocity=\"2\" effort=\"0\"/>\n  </joint>\n  <joint name=\"joint_3\" type=\"revolute\">\n    <parent link=\"link_2\"/><child link=\"link_3\"/><origin xyz=\"0.6 0 0\"/><axis xyz=\"0 1 0\"/>\n    <limit lower=\"-2\" upper=\"2\" velocity=\"3\" effort=\"0\"/>\n  </joint>\n  <joint name=\"flange\" type=\"fixed\">\n    <parent link=\"link_3\"/><child link=\"tool0\"/><origin xyz=\"0.1 0 0\"/>\n  </joint>\n</robot>\n")],
    },
    Case {
        name: "robot_init_refuses_to_overwrite",
        args: "robot init {TMP}/arm.urdf --out {TMP}/arm_drive.toml",
        files: &[],
    },
    // The view serves until stopped (tests/view_browser.rs drives it in a browser); here,
    // what it refuses before it binds.
    Case {
        name: "view_refuses_an_uncertainty_study",
        args: "view --uncertainty 3 --port 0",
        files: &[],
    },
];

/// The normalised transcript text of one run.
fn transcript(args: &[String], out: &std::process::Output, tmp: &Path) -> String {
    let root = root();
    let norm = |s: &str| normalise(s, &root, tmp);
    format!(
        "$ printwatt {}\n--- exit code: {}\n--- stdout\n{}--- stderr\n{}",
        norm(&args.join(" ")),
        out.status
            .code()
            .map_or("signal".to_string(), |c| c.to_string()),
        ensure_newline(&norm(&String::from_utf8_lossy(&out.stdout))),
        ensure_newline(&norm(&String::from_utf8_lossy(&out.stderr))),
    )
    .replace("\r\n", "\n")
}

fn ensure_newline(s: &str) -> String {
    if s.is_empty() || s.ends_with('\n') {
        s.to_string()
    } else {
        format!("{s}\n")
    }
}

/// Replace the number just before `unit` (a run of digits, `.`, `-`) by `placeholder`, at
/// every place `unit` follows a number.
fn mask_number_before(s: &str, unit: &str, placeholder: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut rest = s;
    while let Some(i) = rest.find(unit) {
        let head = &rest[..i];
        let num_start = head
            .char_indices()
            .rev()
            .take_while(|(_, c)| c.is_ascii_digit() || *c == '.')
            .last()
            .map(|(k, _)| k);
        match num_start {
            Some(k) if head[k..].chars().any(|c| c.is_ascii_digit()) => {
                out.push_str(&head[..k]);
                out.push_str(placeholder);
            }
            _ => out.push_str(head),
        }
        out.push_str(unit);
        rest = &rest[i + unit.len()..];
    }
    out.push_str(rest);
    out
}

/// Mask `YYYY-MM-DDTHH:MM:SSZ` and `YYYYMMDDTHHMMSSZ` stamps.
fn mask_utc(s: &str) -> String {
    let b: Vec<char> = s.chars().collect();
    let mut out = String::with_capacity(s.len());
    let mut i = 0;
    let is_stamp = |w: &[char]| {
        let pat_long = "dddd-dd-ddTdd:dd:ddZ";
        let pat_short = "ddddddddTddddddZ";
        let m = |p: &str| {
            w.len() >= p.len()
                && p.chars().zip(w).all(|(pc, c)| match pc {
                    'd' => c.is_ascii_digit(),
                    x => x == *c,
                })
        };
        if m(pat_long) {
            Some(pat_long.len())
        } else if m(pat_short) {
            Some(pat_short.len())
        } else {
            None
        }
    };
    while i < b.len() {
        if let Some(n) = is_stamp(&b[i..]) {
            out.push_str("<UTC>");
            i += n;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    out
}

/// The explicit normalisations (module docs).
fn normalise(s: &str, root: &Path, tmp: &Path) -> String {
    let mut s = s.replace(&tmp.display().to_string(), "<TMP>");
    s = s.replace(&root.display().to_string(), "<ROOT>");
    let version = env!("CARGO_PKG_VERSION");
    let lines: Vec<String> = s
        .lines()
        .map(|l| {
            let mut l = l.to_string();
            if l.contains(&format!("printwatt {version}")) {
                // `printwatt 0.1.0 (abc1234)`: the commit changes with every commit.
                if let Some(i) = l.find(&format!("printwatt {version}")) {
                    let end = l[i..].find(')').map_or(l.len(), |e| i + e + 1);
                    l.replace_range(i..end, "printwatt <VERSION>");
                }
            }
            l = mask_number_before(&l, " placements/s", "<RATE>");
            // Wall times: the tail of `optimise` and `sweep` summaries, `merge`'s report,
            // `study`'s line per case.
            if ["refinement", "wall", "merged", "shard"]
                .iter()
                .any(|k| l.contains(k))
                || l.starts_with("case ")
            {
                l = mask_number_before(&l, " s", "<SECONDS>");
            }
            mask_utc(&l)
        })
        .collect();
    let mut t = lines.join("\n");
    if s.ends_with('\n') {
        t.push('\n');
    }
    t
}

fn expand(args: &str, tmp: &Path) -> Vec<String> {
    args.split_whitespace()
        .map(|a| {
            a.replace("{ROOT}", &root().display().to_string())
                .replace("{TMP}", &tmp.display().to_string())
        })
        .collect()
}

/// Every command and the error cases that matter, against their golden transcripts (see the
/// module docs); the cases run in order in one scratch directory (compare, diagnose and
/// identify read the log simulate wrote; merge reads the two shards).
#[test]
fn every_command_matches_its_golden_transcript() {
    let tmp = std::env::temp_dir().join(format!("printwatt-transcripts-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    std::fs::create_dir_all(&tmp).unwrap();
    let bless = std::env::var_os("PRINTWATT_BLESS").is_some_and(|v| v == "1");
    let dir = root().join("tests/transcripts");
    let mut failures = Vec::new();
    let t0 = std::time::Instant::now();
    for case in CASES {
        for (name, text) in case.files {
            std::fs::write(tmp.join(name), text).unwrap();
        }
        let args = expand(case.args, &tmp);
        let out = Command::new(env!("CARGO_BIN_EXE_printwatt"))
            .args(&args)
            .current_dir(&tmp)
            .env_remove("PRINTWATT_ROBOTS")
            .env("NO_COLOR", "1")
            .output()
            .expect("run printwatt");
        let got = transcript(&args, &out, &tmp);
        let file = dir.join(format!("{}.txt", case.name));
        if bless {
            std::fs::create_dir_all(&dir).unwrap();
            std::fs::write(&file, &got).unwrap();
            continue;
        }
        let want = std::fs::read_to_string(&file).unwrap_or_else(|_| {
            panic!(
                "{} missing: run PRINTWATT_BLESS=1 cargo test --release --test cli_transcripts",
                file.display()
            )
        });
        if got != want {
            let first = got
                .lines()
                .zip(want.lines())
                .position(|(a, b)| a != b)
                .unwrap_or(got.lines().count().min(want.lines().count()));
            failures.push(format!(
                "{}: differs at line {} of the transcript\n  got:  {}\n  want: {}",
                case.name,
                first + 1,
                got.lines().nth(first).unwrap_or("<end>"),
                want.lines().nth(first).unwrap_or("<end>")
            ));
        }
    }
    let _ = std::fs::remove_dir_all(&tmp);
    assert!(
        failures.is_empty(),
        "{} of {} transcripts differ (PRINTWATT_BLESS=1 rewrites them when the change is meant):\n{}",
        failures.len(),
        CASES.len(),
        failures.join("\n")
    );
    // Every command of the binary has a transcript.
    let help = Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .arg("--help")
        .output()
        .unwrap();
    let help = String::from_utf8_lossy(&help.stdout).into_owned();
    let commands: Vec<&str> = help
        .split("Commands:")
        .nth(1)
        .unwrap_or("")
        .lines()
        .skip_while(|l| l.trim().is_empty())
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .collect();
    assert!(commands.len() >= 8, "{help}");
    for c in commands {
        assert!(
            CASES
                .iter()
                .any(|k| k.args.split_whitespace().next() == Some(c)),
            "no transcript runs `printwatt {c}`"
        );
    }
    assert!(
        t0.elapsed().as_secs_f64() < 20.0,
        "transcripts took {:.1} s",
        t0.elapsed().as_secs_f64()
    );
}

/// The normalisations do what the module docs say, and no more.
#[test]
fn transcript_normalisation_masks_only_volatile_parts() {
    let root = root();
    let tmp = Path::new("/tmp/x-1");
    let s = format!(
        "wrote /tmp/x-1/log.csv\nwarning: {}/robots/a: b\ngrid 18 placements, refinement 10 evaluations; 0.92 s\nwall time 0.03 s for 1 placements (35.7 placements/s)\nrun 2026-11-23T18:47:10Z, energy 12850.7 J in 39.10 s\n",
        root.display()
    );
    let n = normalise(&s, &root, tmp);
    assert_eq!(
        n,
        "wrote <TMP>/log.csv\nwarning: <ROOT>/robots/a: b\ngrid 18 placements, refinement 10 evaluations; <SECONDS> s\nwall time <SECONDS> s for 1 placements (<RATE> placements/s)\nrun <UTC>, energy 12850.7 J in 39.10 s\n"
    );
}
