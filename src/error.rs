//! One error type for the library. Variants carry the offending values so that the CLI can
//! print a message that names the file, the line or field, and what was expected.

use std::path::PathBuf;

/// Every failure the library reports. No variant is a panic in disguise: each one is a
/// user-facing message.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        #[source]
        source: std::io::Error,
    },
    /// Text that does not parse: names the file, 1-based line and column, and what was expected.
    #[error("{file}:{line}:{column}: {}", clip(msg))]
    Parse {
        /// The file.
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong and what was expected.
        msg: String,
    },
    /// A value that parses but is wrong: names the file and the field.
    #[error("{file}: {field}: {}", clip(msg))]
    Field {
        /// The file.
        file: String,
        /// The field (a key path, a column name, an element).
        field: String,
        /// What is wrong and what was expected.
        msg: String,
    },
    /// Two sizes that must agree do not.
    #[error("{what}: got {got}, expected {expected}")]
    SizeMismatch {
        /// What was counted.
        what: String,
        /// The size given.
        got: usize,
        /// The size needed.
        expected: usize,
    },
    /// Dynamics were asked of a robot whose link has no `<inertial>`.
    #[error(
        "{file}: link `{link}` has no <inertial>: dynamics need the mass, centre of mass and \
         inertia of every moving link (kinematics alone work without them)"
    )]
    MissingInertial {
        /// The URDF.
        file: String,
        /// The link without `<inertial>`.
        link: String,
    },
    /// A pose or path the robot cannot reach, with the reason.
    #[error("unreachable: {}", clip(.0))]
    Unreachable(String),
    /// Anything else that the user's input makes impossible, with the reason.
    #[error("{}", clip(.0))]
    Invalid(String),
    /// An output (a file, or a run directory holding an earlier run) exists already and the
    /// caller did not ask to replace it ([`crate::output::Existing::Force`]`(false)`).
    #[error("{} exists already", path.display())]
    OutputExists {
        /// The file or directory.
        path: PathBuf,
    },
    /// An output the library will not write there: it would replace an input or land in a
    /// folder that is not the user's (the reason says which). The caller picks another place.
    #[error("{}: refusing to write there: {reason}; write it to another directory", path.display())]
    OutputRefused {
        /// The file that would have been written.
        path: PathBuf,
        /// Why not there.
        reason: String,
    },
    /// A run name that would leave the results directory (`..`, `.`, an absolute path, empty).
    #[error(
        "run name `{name}`: a run name must stay inside the results directory (plain names \
         such as `grid` or `a/b`; no `..`, `.` or absolute path)"
    )]
    BadRunName {
        /// The name given.
        name: String,
    },
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

/// Read a whole text file, naming it on failure. The text is decoded as files come from
/// people's tools (see [`decode_text`]): a UTF-8 byte-order mark is dropped, CR-only and CRLF
/// line endings become LF, and invalid UTF-8 is an error naming the line and byte.
pub(crate) fn read_text(path: &std::path::Path) -> Result<String> {
    let bytes = read_capped(path)?;
    decode_text(&bytes, &path.display().to_string())
}

/// Most bytes read from one input file: 1 GiB (a 1,000,000-row log is about 150 MB), or
/// `PRINTWATT_MAX_INPUT_BYTES`. A larger input, or one without end (`/dev/urandom`, a FIFO),
/// stops there with an error naming the file.
pub(crate) fn max_input_bytes() -> u64 {
    std::env::var("PRINTWATT_MAX_INPUT_BYTES")
        .ok()
        .and_then(|v| v.trim().parse::<u64>().ok())
        .filter(|&n| n > 0)
        .unwrap_or(1 << 30)
}

/// Read a whole file, at most [`max_input_bytes`]: a longer one is an error naming it and the
/// limit (nothing beyond the limit is read).
pub(crate) fn read_capped(path: &std::path::Path) -> Result<Vec<u8>> {
    use std::io::Read;
    let max = max_input_bytes();
    let f = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut bytes = Vec::new();
    f.take(max + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| Error::io(path, e))?;
    if bytes.len() as u64 > max {
        return Err(too_long(path, max));
    }
    Ok(bytes)
}

/// The error of an input longer than `max` bytes (see [`max_input_bytes`]).
pub(crate) fn too_long(path: &std::path::Path, max: u64) -> Error {
    Error::Invalid(format!(
        "{}: longer than {max} bytes, the most printwatt reads from one input (PRINTWATT_MAX_INPUT_BYTES); is it the file meant?",
        path.display()
    ))
}

/// Decode the bytes of a text file: UTF-8, with an optional byte-order mark (Excel's "CSV
/// UTF-8" writes one) dropped; CRLF and CR-only line endings (old Mac exports) turned into LF,
/// so that every reader counts lines the same way. Invalid UTF-8 is a [`Error::Parse`] naming
/// the 1-based line and the 1-based byte within it (column) of the first bad byte, and the
/// byte's offset in the file. UTF-16 files (a UTF-16 byte-order mark) are named as such.
pub(crate) fn decode_text(bytes: &[u8], file: &str) -> Result<String> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    if bytes.starts_with(b"\xFF\xFE") || bytes.starts_with(b"\xFE\xFF") {
        return Err(Error::Parse {
            file: file.into(),
            line: 1,
            column: 1,
            msg: "the file is UTF-16 encoded: save it as UTF-8 (e.g. Excel's \"CSV UTF-8\")".into(),
        });
    }
    let text = match std::str::from_utf8(bytes) {
        Ok(t) => t,
        Err(e) => {
            let at = e.valid_up_to();
            let before = &bytes[..at];
            let line = 1 + before.iter().filter(|&&b| b == b'\n' || b == b'\r').count()
                - before.windows(2).filter(|w| w == b"\r\n").count();
            let line_start = before
                .iter()
                .rposition(|&b| b == b'\n' || b == b'\r')
                .map_or(0, |i| i + 1);
            return Err(Error::Parse {
                file: file.into(),
                line,
                column: at - line_start + 1,
                msg: format!(
                    "invalid UTF-8 (byte 0x{:02X} at byte offset {at} of the file): save the file as UTF-8",
                    bytes[at]
                ),
            });
        }
    };
    if !text.contains('\r') {
        return Ok(text.to_string());
    }
    Ok(text.replace("\r\n", "\n").replace('\r', "\n"))
}

/// Shorten a message for people: any run of more than [`CLIP_TOKEN`] characters without
/// whitespace is cut to its first characters and its length, so that a 5 MB token in a file is
/// not echoed whole; the whole message is kept under [`CLIP_MESSAGE`] characters.
pub fn clip(msg: &str) -> String {
    if msg.len() <= CLIP_TOKEN {
        return msg.to_string();
    }
    let mut out = String::with_capacity(msg.len().min(CLIP_MESSAGE + 64));
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        let n = word.chars().count();
        if n > CLIP_TOKEN {
            let head: String = word.chars().take(CLIP_TOKEN / 2).collect();
            out.push_str(&format!("{head}…({n} characters)"));
        } else {
            out.push_str(word);
        }
        word.clear();
    };
    for c in msg.chars() {
        if c.is_whitespace() {
            flush(&mut word, &mut out);
            out.push(c);
        } else {
            word.push(c);
        }
        if out.len() > CLIP_MESSAGE {
            break;
        }
    }
    flush(&mut word, &mut out);
    if out.len() > CLIP_MESSAGE {
        let mut cut = CLIP_MESSAGE;
        while !out.is_char_boundary(cut) {
            cut -= 1;
        }
        out.truncate(cut);
        out.push('…');
    }
    out
}

/// Longest token [`clip`] keeps whole, characters.
pub(crate) const CLIP_TOKEN: usize = 120;
/// Longest message [`clip`] keeps, bytes.
pub(crate) const CLIP_MESSAGE: usize = 2000;
