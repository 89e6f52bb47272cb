//! The lines of a phone sensor log (ILC traces, IPIN logfiles): comment lines and blank lines
//! counted, every other line handed to a parser with its 1-based number.
//!
//! A parser's error becomes an error naming the file and line. An unterminated last data
//! line is what a logger that was cut off (app killed, disk full) leaves, and it may end in
//! a number cut short (`0.12|345` parses as `0.12`), so it is never used: it is skipped and
//! its number reported in [`LogLines::truncated_last_line`] (both formats end their lines
//! with a newline; the competition's traces close with an `endTime` comment). A leading
//! byte-order mark is dropped; bytes that are not UTF-8 (SSIDs in legacy encodings) are
//! replaced, not refused.

use crate::error::{Error, Result};
use serde::Serialize;
use std::path::Path;

/// What reading a log's lines saw.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct LogLines {
    /// Lines in the file.
    pub lines: usize,
    /// Comment (header) lines.
    pub comment_lines: usize,
    /// Empty lines.
    pub blank_lines: usize,
    /// The number of an unterminated last data line, skipped (it may be cut short).
    pub truncated_last_line: Option<usize>,
}

/// Reads `path` line by line: lines starting with `comment` go to `on_comment` (without the
/// marker), other non-blank lines to `on_line` (without a trailing `\r`).
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be read; [`Error::Parse`] naming the line, with the
/// message, at the first line `on_line` refuses (reading stops there). Bytes that are not
/// UTF-8 are replaced, not refused.
pub fn read_log_lines(
    path: &Path,
    comment: char,
    mut on_comment: impl FnMut(&str),
    mut on_line: impl FnMut(&str, usize) -> Result<(), String>,
) -> Result<LogLines> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let bytes = bytes.strip_prefix("\u{feff}".as_bytes()).unwrap_or(&bytes);
    let text = String::from_utf8_lossy(bytes);
    let terminated = text.is_empty() || text.ends_with('\n');
    let pieces: Vec<&str> = text.split('\n').collect();
    // `split` yields an empty piece after a final newline: not a line.
    let lines = if terminated {
        pieces.len() - 1
    } else {
        pieces.len()
    };
    let mut seen = LogLines {
        lines,
        comment_lines: 0,
        blank_lines: 0,
        truncated_last_line: None,
    };
    for (i, raw) in pieces.iter().take(lines).enumerate() {
        let line = i + 1;
        let raw = raw.strip_suffix('\r').unwrap_or(raw);
        if raw.trim().is_empty() {
            seen.blank_lines += 1;
        } else if let Some(rest) = raw.strip_prefix(comment) {
            seen.comment_lines += 1;
            on_comment(rest);
        } else if line == lines && !terminated {
            seen.truncated_last_line = Some(line);
        } else if let Err(message) = on_line(raw, line) {
            return Err(Error::parse(path, line, message));
        }
    }
    Ok(seen)
}

/// A finite number from a log's field; the error names `what`.
///
/// # Errors
///
/// A message naming `what` when `field` (trimmed) is not a number, or is NaN or infinite.
pub fn number(field: &str, what: &str) -> Result<f64, String> {
    match field.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(format!("{what} `{field}` is not a finite number")),
        Err(_) => Err(format!("{what} `{field}` is not a number")),
    }
}

/// A 3-axis sensor's three finite values within ±`max`.
///
/// # Errors
///
/// As [`number`] for each of the first three fields, and when a value is beyond ±`max`. Fewer
/// than three fields are not refused: the missing axes read 0.
pub fn axes(fields: &[&str], what: &str, max: f64) -> Result<[f64; 3], String> {
    let mut v = [0.0; 3];
    for (slot, (field, axis)) in v.iter_mut().zip(fields.iter().zip(["x", "y", "z"])) {
        *slot = number(field, &format!("{what} {axis}"))?;
        if slot.abs() > max {
            return Err(format!(
                "{what} {axis} = {} is beyond ±{max}",
                crate::error::short_number(*slot)
            ));
        }
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(text: &str) -> Result<(LogLines, Vec<usize>)> {
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("log.txt");
        std::fs::write(&p, text).expect("write");
        let mut ok = Vec::new();
        let seen = read_log_lines(
            &p,
            '#',
            |_| {},
            |l, n| {
                l.parse::<i32>().map_err(|e| e.to_string())?;
                ok.push(n);
                Ok(())
            },
        )?;
        Ok((seen, ok))
    }

    #[test]
    fn counts_lines_and_never_uses_an_unterminated_last_line() {
        let (seen, ok) = run("\u{feff}# head\n1\n\n2\r\n3\n").expect("valid");
        assert_eq!(
            (seen.lines, seen.comment_lines, seen.blank_lines),
            (5, 1, 1)
        );
        assert_eq!(ok, vec![2, 4, 5]);
        // A number cut short still parses: the unterminated line is skipped all the same.
        let (seen, ok) = run("1\n2\n34").expect("cut");
        assert_eq!((seen.truncated_last_line, ok), (Some(3), vec![1, 2]));
        let (seen, ok) = run("1\n2\n3.").expect("truncated");
        assert_eq!((seen.truncated_last_line, ok), (Some(3), vec![1, 2]));
        let e = run("1\n2\n3.\n").unwrap_err().to_string();
        assert!(e.contains("log.txt:3"), "{e}");
        let e = run("1\nx\n3").unwrap_err().to_string();
        assert!(e.contains("log.txt:2"), "{e}");
        assert_eq!(run("").expect("empty").0.lines, 0);
    }
}
