//! Timed positions as CSV (`t,x,y` plus any other columns), as in `track.csv` and the
//! simulator's `truth.csv`.

use super::csv_table::CsvTable;
use crate::error::{Error, Result};
use std::path::Path;

/// A position at a time, local metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimedPoint {
    /// Seconds.
    pub t: f64,
    /// East, metres.
    pub x: f64,
    /// North, metres.
    pub y: f64,
}

/// Reads `t,x,y` rows (extra columns ignored); times must be strictly increasing.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be opened, else [`Error::Parse`] naming the line: a missing
/// `t`, `x` or `y` column, a value that is not a finite number, a coordinate more than
/// 1,000 km from the origin, a time beyond 1e11 s or not after the previous row's, or no data
/// rows.
pub fn read_trajectory(path: &Path) -> Result<Vec<TimedPoint>> {
    read_rows(path, false).map(|(points, _)| points)
}

/// Reads a track's `t,x,y` rows, keeping only those its optional `certain` column marks 1
/// (`footslam track`'s smoothed answer marks 0 the steps whose place the whole walk leaves
/// ambiguous: their position is the likeliest hypothesis, not a fix); returns the rows kept
/// and how many were left out. A file without the column is read whole.
///
/// # Errors
///
/// As [`read_trajectory`], and [`Error::Parse`] when a `certain` cell holds a number other than
/// 0 or 1, or every row has `certain` 0.
pub fn read_certain_trajectory(path: &Path) -> Result<(Vec<TimedPoint>, usize)> {
    read_rows(path, true)
}

fn read_rows(path: &Path, certain_only: bool) -> Result<(Vec<TimedPoint>, usize)> {
    let mut table = CsvTable::open(path)?;
    let (t, x, y) = (table.column("t")?, table.column("x")?, table.column("y")?);
    let certain = table.optional_column("certain").filter(|_| certain_only);
    let mut points: Vec<TimedPoint> = Vec::new();
    let (mut rows, mut previous) = (0usize, None);
    table.for_each_row(|row| {
        rows += 1;
        let p = TimedPoint {
            t: row.number(t, "t")?,
            x: row.coordinate(x, "x")?,
            y: row.coordinate(y, "y")?,
        };
        row.ensure_after(previous, p.t)?;
        previous = Some(p.t);
        let keep = match row.optional_number(certain, "certain")? {
            None => true,
            Some(1.0) => true,
            Some(0.0) => false,
            Some(c) => return Err(row.error(format!("`certain` is {c}, not 0 or 1"))),
        };
        if keep {
            points.push(p);
        }
        Ok(())
    })?;
    if rows == 0 {
        return Err(Error::parse(
            path,
            0,
            "no rows: the file has a header but no data",
        ));
    }
    if points.is_empty() {
        return Err(Error::parse(
            path,
            0,
            "no certain rows: the walk never settled the walker's place (every row has certain = 0)",
        ));
    }
    let dropped = rows - points.len();
    Ok((points, dropped))
}

/// Writes `t,x,y,<extra>` rows (millimetre precision): a trajectory with one more value per
/// row, e.g. learn's `spread_m`.
///
/// # Errors
///
/// [`Error::InvalidData`] naming the file when a point's `t`, `x` or `y` is not finite
/// (nothing is written: [`read_trajectory`] would refuse it); [`Error::Io`] when `path`
/// cannot be written, as [`write_atomically_with`](crate::io::write_atomically_with).
pub fn write_trajectory_with(
    path: &Path,
    extra: &str,
    rows: impl IntoIterator<Item = (TimedPoint, f64)>,
) -> Result<()> {
    let mut bad = None;
    let written = crate::io::write_atomically_with(path, |w| {
        writeln!(w, "t,x,y,{extra}")?;
        for (p, v) in rows {
            if !(p.t.is_finite() && p.x.is_finite() && p.y.is_finite()) {
                bad = Some(p);
                return Err(std::io::Error::other("a trajectory point is not finite"));
            }
            writeln!(w, "{:.3},{:.3},{:.3},{:.3}", p.t, p.x, p.y, v)?;
        }
        Ok(())
    });
    match bad {
        Some(p) => Err(not_finite(&p, path)),
        None => written,
    }
}

/// The error for a point that is not finite.
fn not_finite(p: &TimedPoint, path: &Path) -> Error {
    Error::invalid(
        path.display().to_string(),
        format!(
            "the point at t = {} s, ({}, {}), is not finite: nothing was written",
            p.t, p.x, p.y
        ),
    )
}

/// Writes `t,x,y` rows (millimetre precision).
///
/// # Errors
///
/// As [`write_trajectory_with`].
pub fn write_trajectory(path: &Path, points: impl IntoIterator<Item = TimedPoint>) -> Result<()> {
    let mut bad = None;
    let written = crate::io::write_atomically_with(path, |w| {
        w.write_all(b"t,x,y\n")?;
        for p in points {
            if !(p.t.is_finite() && p.x.is_finite() && p.y.is_finite()) {
                bad = Some(p);
                return Err(std::io::Error::other("a trajectory point is not finite"));
            }
            writeln!(w, "{:.3},{:.3},{:.3}", p.t, p.x, p.y)?;
        }
        Ok(())
    });
    match bad {
        Some(p) => Err(not_finite(&p, path)),
        None => written,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_that_is_not_finite_is_refused_and_nothing_is_written() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("path.csv");
        let point = |t: f64, x: f64| TimedPoint { t, x, y: 1.0 };
        write_trajectory(&path, [point(0.0, 0.0), point(1.0, 2.0)]).expect("written");
        assert_eq!(read_trajectory(&path).expect("read back").len(), 2);
        let err =
            write_trajectory(&path, [point(0.0, 0.0), point(1.0, f64::NAN)]).expect_err("NaN");
        assert!(err.to_string().contains("not finite"), "{err}");
        let err = write_trajectory_with(&path, "spread_m", [(point(f64::INFINITY, 0.0), 0.5)])
            .expect_err("inf");
        assert!(err.to_string().contains("nothing was written"), "{err}");
        // The earlier file stands.
        assert_eq!(read_trajectory(&path).expect("read back").len(), 2);
    }
}
