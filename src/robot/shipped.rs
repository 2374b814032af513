//! The robots shipped with printwatt (`robots/<name>/robot.urdf` + `drive.toml`) and how a
//! robot argument (a path, or a shipped robot's name) is resolved. Shared by the binary and the
//! Python bindings.

use std::path::{Path, PathBuf};

/// The shipped robots directory: `$PRINTWATT_ROBOTS`, else `robots/` in the working directory,
/// else the one in the source tree this library was built from.
pub fn robots_dir() -> PathBuf {
    if let Some(p) = std::env::var_os("PRINTWATT_ROBOTS") {
        return p.into();
    }
    let local = Path::new("robots");
    if local.is_dir() {
        return local.to_path_buf();
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join("robots")
}

/// Names of the shipped robots (directories of [`robots_dir`] holding a `robot.urdf`), sorted.
pub fn names() -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(robots_dir())
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .filter(|e| e.path().join("robot.urdf").is_file())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// Resolve a robot argument: the path itself when it exists, else the shipped robot of that
/// name, else `None`.
pub fn resolve(arg: &Path) -> Option<PathBuf> {
    if arg.exists() {
        return Some(arg.to_path_buf());
    }
    let shipped = robots_dir().join(arg);
    shipped.exists().then_some(shipped)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shipped_names_resolve_and_unknown_names_do_not() {
        let names = names();
        assert!(names.contains(&"ur10e".to_string()), "{names:?}");
        for n in &names {
            let p = resolve(Path::new(n)).expect("a shipped robot resolves");
            assert!(p.join("robot.urdf").is_file(), "{}", p.display());
        }
        assert_eq!(resolve(Path::new("no_such_robot_xyz")), None);
    }
}
