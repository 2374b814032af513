//! The README cannot drift from the binary: every ```sh block of README.md is run, command by
//! command, against the built `printwatt` (on the PATH of the shell) in a scratch directory
//! holding `paths/`, `presets/` and `tests/data/` of this tree. A block preceded by an HTML
//! comment `<!-- readme-test: skip: <reason> -->` is not run (the set-up commands, the slow
//! optimisations); the test asserts that every skip gives a reason.

mod common;
use common::root;

use std::path::Path;
use std::process::Command;

/// The README's sh blocks: (line of the fence, skip reason, logical command lines).
fn blocks(text: &str) -> Vec<(usize, Option<String>, Vec<String>)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        if lines[i].trim() == "```sh" {
            let fence = i + 1;
            let skip = lines[..i]
                .iter()
                .rev()
                .find(|l| !l.trim().is_empty())
                .and_then(|l| l.trim().strip_prefix("<!-- readme-test: skip"))
                .map(|r| {
                    r.trim_end_matches("-->")
                        .trim()
                        .trim_start_matches(':')
                        .trim()
                        .to_string()
                });
            let mut cmds: Vec<String> = Vec::new();
            let mut cont = false;
            i += 1;
            while i < lines.len() && lines[i].trim() != "```" {
                let l = lines[i];
                let t = l.trim();
                if cont {
                    cmds.last_mut()
                        .unwrap()
                        .push_str(&format!(" {}", t.trim_end_matches('\\')));
                } else if t.starts_with('#') || t.is_empty() {
                    // a comment line (or the continuation of a comment after a command)
                } else {
                    cmds.push(t.trim_end_matches('\\').to_string());
                }
                cont = t.ends_with('\\');
                i += 1;
            }
            out.push((fence, skip, cmds));
        }
        i += 1;
    }
    out
}

fn link(from: &Path, to: &Path) {
    std::os::unix::fs::symlink(from, to).unwrap();
}

#[test]
fn every_readme_command_block_runs_against_the_built_binary() {
    let text = std::fs::read_to_string(root().join("README.md")).unwrap();
    let bs = blocks(&text);
    assert!(bs.len() >= 5, "{} sh blocks found", bs.len());
    let d = std::env::temp_dir().join(format!("printwatt-readme-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(d.join("tests")).unwrap();
    link(&root().join("paths"), &d.join("paths"));
    link(&root().join("presets"), &d.join("presets"));
    link(&root().join("tests/data"), &d.join("tests/data"));
    let bin_dir = Path::new(env!("CARGO_BIN_EXE_printwatt")).parent().unwrap();
    let path = format!(
        "{}:{}",
        bin_dir.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut ran = 0;
    for (fence, skip, cmds) in &bs {
        if let Some(reason) = skip {
            assert!(
                !reason.is_empty(),
                "README.md:{fence}: a skip without a reason"
            );
            continue;
        }
        for c in cmds {
            assert!(
                c.starts_with("printwatt "),
                "README.md:{fence}: `{c}` is not a printwatt command (mark the block skip)"
            );
            let o = Command::new("sh")
                .arg("-c")
                .arg(c)
                .current_dir(&d)
                .env("PATH", &path)
                .env_remove("PRINTWATT_ROBOTS")
                .output()
                .unwrap();
            let err = String::from_utf8_lossy(&o.stderr);
            assert!(
                o.status.success(),
                "README.md:{fence}: `{c}` failed ({:?}):\n{err}",
                o.status.code()
            );
            assert!(!err.contains("panicked"), "README.md:{fence}: `{c}`: {err}");
            assert!(
                !o.stdout.is_empty() || err.contains("wrote "),
                "README.md:{fence}: `{c}` printed nothing; stderr: {err}"
            );
            ran += 1;
        }
    }
    assert!(ran >= 10, "only {ran} README commands ran");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn readme_says_how_to_put_printwatt_on_the_path() {
    let text = std::fs::read_to_string(root().join("README.md")).unwrap();
    assert!(text.contains("cargo install --path ."));
    // Every sh block outside the set-up uses `printwatt …`, never `target/release/printwatt`
    // or `cargo run` (the set-up block is the one place for cargo).
    for (fence, skip, cmds) in blocks(&text) {
        for c in cmds {
            if skip.as_deref().is_some_and(|r| r.starts_with("the set-up")) {
                continue;
            }
            assert!(c.starts_with("printwatt "), "README.md:{fence}: `{c}`");
        }
    }
}

/// The ```text blocks of the README's main-job section, in order.
fn main_job_text_blocks(readme: &str) -> Vec<Vec<String>> {
    let sec = readme
        .split("## The main job")
        .nth(1)
        .and_then(|s| s.split("\n## ").next())
        .expect("README has a main-job section");
    sec.split("```text\n")
        .skip(1)
        .map(|b| {
            b.split("```")
                .next()
                .unwrap_or("")
                .lines()
                .map(str::to_string)
                .collect()
        })
        .collect()
}

#[test]
fn the_readme_main_job_output_is_what_optimise_prints() {
    // Every line the README shows of the main job (the answer, then the robust choice with
    // `--uncertainty 20`) must be a line the built binary prints now: a changed default
    // cannot leave a stale answer on the front page.
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let blocks = main_job_text_blocks(&readme);
    assert_eq!(blocks.len(), 2, "the answer and the robust choice");
    let dir = std::env::temp_dir().join(format!("printwatt-readme-main-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    for (k, (block, extra)) in blocks
        .iter()
        .zip([&[][..], &["--uncertainty", "20"][..]])
        .enumerate()
    {
        let out = common::ok(
            common::bin()
                .arg("optimise")
                .args(extra)
                .arg("--out")
                .arg(dir.join(format!("run{k}"))),
        );
        let printed = String::from_utf8_lossy(&out.stdout);
        for line in block {
            assert!(
                printed.lines().any(|l| l == line),
                "README main-job line not printed by `printwatt optimise {}`:\n{line}\nprinted:\n{printed}",
                extra.join(" ")
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
