//! Vertices of STL (binary or ASCII) and Wavefront OBJ meshes, for collision hulls.
//!
//! Only the vertex positions are read: a link's mesh is used as its convex hull (see
//! [`crate::evaluate::feasibility::collision`]), so faces, normals and materials do not matter. Units are
//! the file's (URDF meshes are in metres unless a `scale` says otherwise).

use crate::error::{Error, Result};
use crate::math::V3;
use std::path::{Path, PathBuf};

/// Read the vertices of an `.stl` or `.obj` file (by extension, case-insensitive).
pub fn read_vertices(path: &Path) -> Result<Vec<V3>> {
    let bytes = std::fs::read(path).map_err(|e| Error::Io {
        path: path.to_path_buf(),
        source: e,
    })?;
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let name = path.display().to_string();
    let pts = match ext.as_str() {
        "stl" => stl_vertices(&bytes, &name)?,
        "obj" => obj_vertices(&bytes, &name)?,
        _ => {
            return Err(Error::Invalid(format!(
                "{name}: mesh format `.{ext}` is not supported (STL and OBJ are)"
            )))
        }
    };
    if pts.len() < 4 {
        return Err(Error::Invalid(format!(
            "{name}: {} vertices, a hull needs at least 4",
            pts.len()
        )));
    }
    if pts.iter().any(|p| !p.iter().all(|c| c.is_finite())) {
        return Err(Error::Invalid(format!("{name}: a vertex is not finite")));
    }
    Ok(pts)
}

fn stl_vertices(b: &[u8], name: &str) -> Result<Vec<V3>> {
    // Binary STL: 80-byte header, u32 triangle count, 50 bytes per triangle. An ASCII file
    // starts with "solid" but so do some binary ones: trust the size when it matches.
    if b.len() >= 84 {
        let n = u32::from_le_bytes([b[80], b[81], b[82], b[83]]) as usize;
        if n.checked_mul(50).and_then(|x| x.checked_add(84)) == Some(b.len()) {
            let f = |o: usize| f32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]) as f64;
            let mut out = Vec::with_capacity(3 * n);
            for t in 0..n {
                let base = 84 + 50 * t + 12; // skip the normal
                for v in 0..3 {
                    let o = base + 12 * v;
                    out.push(V3::new(f(o), f(o + 4), f(o + 8)));
                }
            }
            return Ok(out);
        }
    }
    let text = std::str::from_utf8(b)
        .map_err(|_| Error::Invalid(format!("{name}: neither binary nor ASCII STL")))?;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let mut it = line.split_whitespace();
        if it.next() == Some("vertex") {
            out.push(parse3(&mut it, name, i + 1)?);
        }
    }
    Ok(out)
}

fn obj_vertices(b: &[u8], name: &str) -> Result<Vec<V3>> {
    let text = String::from_utf8_lossy(b);
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let mut it = line.split_whitespace();
        if it.next() == Some("v") {
            out.push(parse3(&mut it, name, i + 1)?);
        }
    }
    Ok(out)
}

fn parse3<'a>(it: &mut impl Iterator<Item = &'a str>, name: &str, line: usize) -> Result<V3> {
    let mut v = [0.0; 3];
    for c in &mut v {
        *c = it
            .next()
            .and_then(|s| s.parse().ok())
            .ok_or_else(|| Error::Parse {
                file: name.into(),
                line,
                column: 1,
                msg: "expected three numbers after the vertex keyword".into(),
            })?;
    }
    Ok(V3::from(v))
}

/// Where a URDF mesh `filename` points: relative paths and `file://` against the URDF's
/// directory; `package://pkg/rest` against a directory named `pkg` found in `ROS_PACKAGE_PATH`
/// or among the URDF's ancestors (or their children), else `None`.
pub(crate) fn resolve_mesh_path(filename: &str, urdf_dir: &Path) -> Option<PathBuf> {
    resolve_mesh_path_in(filename, urdf_dir).map(|(p, _)| p)
}

/// [`resolve_mesh_path`] with the directory the name is relative to: the package's directory
/// for `package://`, else the URDF's directory (also for an absolute path).
pub(crate) fn resolve_mesh_path_in(filename: &str, urdf_dir: &Path) -> Option<(PathBuf, PathBuf)> {
    if let Some(rest) = filename.strip_prefix("package://") {
        let (pkg, rel) = rest.split_once('/')?;
        let mut roots: Vec<PathBuf> = std::env::var_os("ROS_PACKAGE_PATH")
            .map(|v| std::env::split_paths(&v).collect())
            .unwrap_or_default();
        roots.extend(urdf_dir.ancestors().map(Path::to_path_buf));
        for r in roots {
            for cand in [r.join(pkg), r.clone()] {
                if cand.file_name().is_some_and(|n| n == pkg) {
                    let p = cand.join(rel);
                    if p.is_file() {
                        return Some((p, cand));
                    }
                }
            }
        }
        return None;
    }
    let f = filename.strip_prefix("file://").unwrap_or(filename);
    let p = Path::new(f);
    Some((
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            urdf_dir.join(p)
        },
        urdf_dir.to_path_buf(),
    ))
}

/// Formats of visual meshes the view draws (lower-case extensions).
pub(crate) const VISUAL_FORMATS: [&str; 3] = ["stl", "dae", "obj"];

/// A visual mesh `filename` of the URDF in `urdf_dir`: the file (canonical) and its format,
/// only when it is a file of [`VISUAL_FORMATS`] that lies inside the directory its name is
/// relative to (see [`resolve_mesh_path_in`]); otherwise why not.
pub(crate) fn visual_mesh_file(
    filename: &str,
    urdf_dir: &Path,
) -> std::result::Result<(PathBuf, String), String> {
    let (p, root) = resolve_mesh_path_in(filename, urdf_dir)
        .ok_or_else(|| {
            "not found (a package:// file is looked for in ROS_PACKAGE_PATH and among the URDF's ancestors)"
                .to_string()
        })?;
    let ext = p
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    if !VISUAL_FORMATS.contains(&ext.as_str()) {
        return Err(format!(
            "format `.{ext}` is not drawn (STL, COLLADA .dae and OBJ are)"
        ));
    }
    let file = std::fs::canonicalize(&p).map_err(|e| format!("{}: {e}", p.display()))?;
    let root = std::fs::canonicalize(&root).map_err(|e| format!("{}: {e}", root.display()))?;
    if !file.starts_with(&root) || !file.is_file() {
        return Err(format!(
            "{} is not a file inside {}",
            file.display(),
            root.display()
        ));
    }
    Ok((file, ext))
}
