//! Build script: records the git commit this binary is built from, for `printwatt --version`.
//! Outside a git checkout (a crate tarball, `cargo install` from a copy), or without git on the
//! PATH, the version says so instead of failing the build.

use std::path::PathBuf;
use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).output().ok()?;
    if !out.status.success() {
        return None;
    }
    let s = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (!s.is_empty()).then_some(s)
}

fn main() {
    println!("cargo:rerun-if-env-changed=PRINTWATT_COMMIT");
    let commit = match std::env::var("PRINTWATT_COMMIT") {
        Ok(c) if !c.trim().is_empty() => c.trim().to_string(),
        _ => match git(&["rev-parse", "--short", "HEAD"]) {
            Some(c) => {
                // Rebuild when HEAD moves: HEAD itself, the branch it names and packed refs.
                // Only files that exist are declared: cargo takes a missing file for a changed
                // one, and every build would then recompile the crate.
                let watch = |p: PathBuf| {
                    if p.is_file() {
                        println!("cargo:rerun-if-changed={}", p.display());
                    }
                };
                if let Some(dir) = git(&["rev-parse", "--git-dir"]) {
                    watch(PathBuf::from(dir).join("HEAD"));
                    if let (Some(common), Some(r)) = (
                        git(&["rev-parse", "--git-common-dir"]),
                        git(&["symbolic-ref", "-q", "HEAD"]),
                    ) {
                        let common = PathBuf::from(common);
                        watch(common.join(r));
                        watch(common.join("packed-refs"));
                    }
                }
                c
            }
            None => "unknown commit: not built from a git checkout".to_string(),
        },
    };
    println!("cargo:rustc-env=PRINTWATT_COMMIT={commit}");
}
