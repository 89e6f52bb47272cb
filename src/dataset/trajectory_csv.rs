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
pub fn read_trajectory(path: &Path) -> Result<Vec<TimedPoint>> {
    let mut table = CsvTable::open(path)?;
    let (t, x, y) = (table.column("t")?, table.column("x")?, table.column("y")?);
    let mut points: Vec<TimedPoint> = Vec::new();
    table.for_each_row(|row| {
        let p = TimedPoint {
            t: row.number(t, "t")?,
            x: row.number(x, "x")?,
            y: row.number(y, "y")?,
        };
        row.ensure_after(points.last().map(|q| q.t), p.t)?;
        points.push(p);
        Ok(())
    })?;
    if points.is_empty() {
        return Err(Error::parse(
            path,
            0,
            "no rows: the file has a header but no data",
        ));
    }
    Ok(points)
}

/// Writes `t,x,y` rows (millimetre precision).
pub fn write_trajectory(path: &Path, points: &[TimedPoint]) -> Result<()> {
    let mut text = String::from("t,x,y\n");
    for p in points {
        text.push_str(&format!("{:.3},{:.3},{:.3}\n", p.t, p.x, p.y));
    }
    crate::export::write_atomically(path, text.as_bytes())
}
