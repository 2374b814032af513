//! One error type for the library. Variants carry the offending values so that the CLI can
//! print a message that names the file, the line or field, and what was expected.

use std::path::PathBuf;

/// Every failure the library reports. No variant is a panic in disguise: each one is a
/// user-facing message.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// Text that does not parse: names the file, 1-based line and column, and what was expected.
    #[error("{file}:{line}:{column}: {msg}")]
    Parse {
        file: String,
        line: usize,
        column: usize,
        msg: String,
    },
    /// A value that parses but is wrong: names the file and the field.
    #[error("{file}: {field}: {msg}")]
    Field {
        file: String,
        field: String,
        msg: String,
    },
    /// Two sizes that must agree do not.
    #[error("{what}: got {got}, expected {expected}")]
    SizeMismatch {
        what: String,
        got: usize,
        expected: usize,
    },
    /// Dynamics were asked of a robot whose link has no `<inertial>`.
    #[error(
        "{file}: link `{link}` has no <inertial>: dynamics need the mass, centre of mass and \
         inertia of every moving link (kinematics alone work without them)"
    )]
    MissingInertial { file: String, link: String },
    /// A pose or path the robot cannot reach, with the reason.
    #[error("unreachable: {0}")]
    Unreachable(String),
    /// Anything else that the user's input makes impossible, with the reason.
    #[error("{0}")]
    Invalid(String),
}

/// Result with the library's error.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// Wrap an I/O error with the path it concerns.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }
}

/// Read a whole text file, naming it on failure.
pub fn read_text(path: &std::path::Path) -> Result<String> {
    std::fs::read_to_string(path).map_err(|e| Error::io(path, e))
}
