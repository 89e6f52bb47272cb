//! The library's one error type.
//!
//! Every variant says what went wrong and where; the CLI adds context with `anyhow` and prints it.

use std::ops::{Bound, RangeBounds};
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
        /// The allowed range or rule: the way out.
        reason: String,
    },
    /// Values in the data that break a rule: not finite, out of time order, physically
    /// implausible. Fix: correct the named item.
    #[error("{item}: {problem}")]
    InvalidData {
        /// What holds the value, e.g. `track point 3` or `floor polygon 2 (hall)`.
        item: String,
        /// The value and the rule it breaks.
        problem: String,
    },
    /// Inputs that are each valid but do not belong together: another building, another
    /// clock, another grid.
    #[error("{problem}{}", fix_suffix(.fix))]
    Mismatch {
        /// Which inputs disagree, and how.
        problem: String,
        /// The way out.
        fix: String,
    },
    /// Too little data for the result asked for: an empty track, no waypoints, no map.
    #[error("{problem}{}", fix_suffix(.fix))]
    NotEnough {
        /// What is missing.
        problem: String,
        /// The way out (empty when there is none beyond supplying the data).
        fix: String,
    },
    /// An input or a result beyond a documented size limit.
    #[error("{what} is too large: {size}, at most {limit}{}", fix_suffix(.fix))]
    TooLarge {
        /// What would be too large, e.g. `an occupancy grid`.
        what: String,
        /// Its size.
        size: String,
        /// The limit.
        limit: String,
        /// The way out.
        fix: String,
    },
    /// The output folder cannot be used as asked: a file, an input's folder, another run's.
    #[error("{}: {problem}", .path.display())]
    Output {
        /// The `--out` folder (or output file) concerned.
        path: PathBuf,
        /// What is wrong and the way out.
        problem: String,
    },
    /// An output could not be encoded (PNG, PGM, JSON) or its picture allocated.
    #[error("cannot {what}: {message}")]
    Encode {
        /// What was being done, e.g. `encode the map picture as PNG`.
        what: String,
        /// The encoder's message.
        message: String,
    },
    /// A simulator preset produced an inconsistent layout: a bug in the preset, not in the
    /// user's data.
    #[error("simulator: {0}")]
    Simulation(String),
    /// An option of a job given a value it cannot take: each face spells the option its own
    /// way (`--plan-margin`, `plan_margin`).
    #[error("{option}: {problem}")]
    BadOption {
        /// The option's name in snake case, as the job's request and Python name it.
        option: &'static str,
        /// The value and why it cannot be taken.
        problem: String,
    },
    /// Inputs that do not belong together as given, with the one option that makes them do:
    /// each face spells the option its own way (`--one-floor`, `one_floor=True`).
    #[error("{problem}, or set {remedy}")]
    Remedied {
        /// What is wrong, with the input's name first.
        problem: String,
        /// The option that fixes it.
        remedy: Remedy,
    },
}

/// An option of a job that makes a failed check pass, for each face to spell: the command
/// line as `--one-floor` or `--hex-radius 0.5`, Python as `one_floor=True` or
/// `hex_radius=0.5`.
///
/// ```
/// use footslam::error::{Remedy, RemedyValue};
/// let r = Remedy { option: "hex_radius", value: RemedyValue::Number(0.5) };
/// assert_eq!(r.to_string(), "hex_radius = 0.5");
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Remedy {
    /// The option's name in snake case, as the job's request and Python name it.
    pub option: &'static str,
    /// What to set it to.
    pub value: RemedyValue,
}

/// The value a [`Remedy`] sets.
#[derive(Debug, Clone, PartialEq)]
pub enum RemedyValue {
    /// A switch turned on (`--one-floor`, `one_floor=True`).
    Flag,
    /// A number (`--hex-radius 0.5`, `hex_radius=0.5`).
    Number(f64),
    /// A latitude and longitude, degrees (`--origin LAT,LON`, `origin=(lat, lon)`).
    LatLon(f64, f64),
    /// A value only the user knows, described (`--gps-t0 <the UTC time …>`).
    Described(&'static str),
}

impl std::fmt::Display for Remedy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.value {
            RemedyValue::Flag => write!(f, "{}", self.option),
            RemedyValue::Number(v) => write!(f, "{} = {v}", self.option),
            RemedyValue::LatLon(lat, lon) => write!(f, "{} = {lat},{lon}", self.option),
            RemedyValue::Described(what) => write!(f, "{} = <{what}>", self.option),
        }
    }
}

/// Shorthand for results carrying [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// The one range check of every configuration's `validate`: `Ok` when `value` is finite
/// and within `range` (`lo..=hi`, `lo..hi`, `lo..`, or a pair of [`Bound`]s for an open
/// start), else an [`Error::Config`] naming `field`, the value and the range, in `unit`
/// (e.g. `"m"`, or `""`).
///
/// # Errors
///
/// [`Error::Config`] when `value` is NaN, infinite or outside `range`; its reason states the
/// range and unit (`must be in (0, 1)`, `must be at least 0.05 m`).
///
/// # Examples
///
/// ```
/// use footslam::error::check_range;
/// use std::ops::Bound::Excluded;
/// assert!(check_range("kld.bin_size", 0.5, 0.05..=100.0, "m").is_ok());
/// let err = check_range("kld.epsilon", 1.0, (Excluded(0.0), Excluded(1.0)), "").unwrap_err();
/// assert_eq!(err.to_string(), "invalid configuration: kld.epsilon = 1: must be in (0, 1)");
/// ```
pub fn check_range(
    field: &'static str,
    value: f64,
    range: impl RangeBounds<f64>,
    unit: &str,
) -> Result<()> {
    if value.is_finite() && range.contains(&value) {
        return Ok(());
    }
    let unit = if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    };
    let reason = match (range.start_bound(), range.end_bound()) {
        (Bound::Unbounded, Bound::Unbounded) => "must be finite".to_string(),
        (lo, Bound::Unbounded) => match lo {
            Bound::Included(v) => format!("must be at least {v}{unit}"),
            _ => format!("must be above {}{unit}", bound_value(lo)),
        },
        (Bound::Unbounded, hi) => match hi {
            Bound::Included(v) => format!("must be at most {v}{unit}"),
            _ => format!("must be below {}{unit}", bound_value(hi)),
        },
        (lo, hi) => format!(
            "must be in {}{}, {}{}{unit}",
            if matches!(lo, Bound::Included(_)) {
                "["
            } else {
                "("
            },
            bound_value(lo),
            bound_value(hi),
            if matches!(hi, Bound::Included(_)) {
                "]"
            } else {
                ")"
            },
        ),
    };
    Err(Error::config(field, value, reason))
}

fn bound_value(b: Bound<&f64>) -> String {
    match b {
        Bound::Included(v) | Bound::Excluded(v) => v.to_string(),
        Bound::Unbounded => String::new(),
    }
}

impl Error {
    /// A configuration field whose value breaks `reason` (a rule other than a range; ranges
    /// go through [`check_range`]).
    pub fn config(field: &'static str, value: impl ToString, reason: impl Into<String>) -> Self {
        Error::Config {
            field,
            value: value.to_string(),
            reason: reason.into(),
        }
    }

    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            error: source,
        }
    }

    /// Data whose `item` breaks a rule (`problem` gives the value and the rule).
    pub fn invalid(item: impl Into<String>, problem: impl Into<String>) -> Self {
        Error::InvalidData {
            item: item.into(),
            problem: problem.into(),
        }
    }

    /// Inputs that do not belong together, with the way out.
    pub fn mismatch(problem: impl Into<String>, fix: impl Into<String>) -> Self {
        Error::Mismatch {
            problem: problem.into(),
            fix: fix.into(),
        }
    }

    /// Too little data, with the way out (`""` when there is none).
    pub fn not_enough(problem: impl Into<String>, fix: impl Into<String>) -> Self {
        Error::NotEnough {
            problem: problem.into(),
            fix: fix.into(),
        }
    }

    /// `what` of `size` beyond `limit`, with the way out (`""` when there is none).
    pub fn too_large(
        what: impl Into<String>,
        size: impl ToString,
        limit: impl ToString,
        fix: impl Into<String>,
    ) -> Self {
        Error::TooLarge {
            what: what.into(),
            size: size.to_string(),
            limit: limit.to_string(),
            fix: fix.into(),
        }
    }

    /// An output folder or file that cannot be used as asked.
    pub fn output(path: impl Into<PathBuf>, problem: impl Into<String>) -> Self {
        Error::Output {
            path: path.into(),
            problem: problem.into(),
        }
    }

    /// An output that could not be encoded.
    pub fn encode(what: impl Into<String>, message: impl ToString) -> Self {
        Error::Encode {
            what: what.into(),
            message: message.to_string(),
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

/// `: FIX` after a message, or nothing when there is no way out to add.
fn fix_suffix(fix: &str) -> String {
    if fix.is_empty() {
        String::new()
    } else {
        format!(": {fix}")
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

/// A number as a user can read it: plainly when that is short, else in scientific notation
/// (1e308 printed plainly has 309 digits).
///
/// ```
/// use footslam::error::short_number;
/// assert_eq!(short_number(2.5), "2.5");
/// assert_eq!(short_number(1e308), "1e308");
/// ```
#[must_use]
pub fn short_number(v: f64) -> String {
    let plain = v.to_string();
    if plain.len() > 24 {
        format!("{v:e}")
    } else {
        plain
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
