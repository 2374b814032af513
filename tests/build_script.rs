//! The build script records the commit for `printwatt --version` without making every build
//! stale: cargo takes a declared `rerun-if-changed` file that does not exist for a changed one
//! and recompiles the crate on every build. The script's own output (beside `OUT_DIR`) must
//! therefore declare only files that exist.

use std::path::Path;

#[test]
fn build_script_declares_only_existing_files() {
    let out_dir = Path::new(env!("OUT_DIR"));
    let output = out_dir.parent().unwrap().join("output");
    let text =
        std::fs::read_to_string(&output).unwrap_or_else(|e| panic!("{}: {e}", output.display()));
    assert!(
        text.contains("cargo:rustc-env=PRINTWATT_COMMIT="),
        "the build script records the commit:\n{text}"
    );
    for line in text.lines() {
        if let Some(p) = line.strip_prefix("cargo:rerun-if-changed=") {
            assert!(
                Path::new(p).exists(),
                "build.rs declares rerun-if-changed on {p}, which does not exist: every \
                 build would recompile the crate"
            );
        }
    }
}
