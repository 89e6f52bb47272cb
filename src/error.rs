//! The library's one error type.
//!
//! Every variant says what went wrong and where; the CLI adds context with `anyhow` and prints it.

use std::path::PathBuf;

/// Errors raised by footslam's library.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be opened, read or written. Fix: check the path and permissions.
    #[error("{}: {error}", .path.display())]
    Io {
        /// The file concerned.
        path: PathBuf,
        /// The operating system's error (in the message, not repeated as a source).
        error: std::io::Error,
    },
    /// An input file is malformed at a given line. Fix: correct the named line.
    #[error("{}{}: {}", .path.display(), line_suffix(*.line), .message)]
    Parse {
        /// The file concerned.
        path: PathBuf,
        /// 1-based line number (0 when the problem concerns the whole file).
        line: usize,
        /// What is wrong there.
        message: String,
    },
    /// A configuration value is out of its documented range. Fix: change the named field.
    #[error("invalid configuration: {field} = {}: {reason}", short_value(.value))]
    Config {
        /// The offending field, e.g. `footslam.hex_radius`.
        field: &'static str,
        /// Its value as text.
        value: String,
        /// The allowed range or rule.
        reason: &'static str,
    },
    /// Input data cannot be processed as given (e.g. an empty trace). Fix: see the message.
    #[error("invalid input: {0}")]
    Input(String),
}

/// Shorthand for results carrying [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// `Ok` when `value` is finite and within `[lo, hi]`, else an [`Error::Config`] naming
/// `field` with `reason` (the configs' `validate` methods).
pub fn check_range(
    field: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    reason: &'static str,
) -> Result<()> {
    if value.is_finite() && (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(Error::Config {
            field,
            value: value.to_string(),
            reason,
        })
    }
}

impl Error {
    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            error: source,
        }
    }

    /// A parse error at `line` of `path`.
    pub fn parse(path: impl Into<PathBuf>, line: usize, message: impl Into<String>) -> Self {
        Error::Parse {
            path: path.into(),
            line,
            message: message.into(),
        }
    }
}

/// `:LINE` after a file name, or nothing when the problem concerns the whole file (line 0).
fn line_suffix(line: usize) -> String {
    if line == 0 {
        String::new()
    } else {
        format!(":{line}")
    }
}

/// A value as the user can read it: a number too long to print plainly (1e308 has 309
/// digits) in scientific notation.
fn short_value(value: &str) -> String {
    match value.parse::<f64>() {
        Ok(v) if value.len() > 24 => format!("{v:e}"),
        _ => value.to_owned(),
    }
}
