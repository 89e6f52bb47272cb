//! Sparse ground-truth positions as CSV (`waypoints.csv`): header `t,x,y[,level]` (seconds on
//! the recording's clock, metres east and north in the floor plan's local frame, integer
//! floor level); extra columns are ignored. Real datasets mark a handful of such points per
//! walk (the Indoor Location Competition's `TYPE_WAYPOINT`, IPIN's `POSI`).

use super::csv_table::CsvTable;
use crate::error::{Error, Result};
use std::path::Path;

/// One ground-truth point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Waypoint {
    /// Time, seconds.
    pub t: f64,
    /// Metres east in the local frame.
    pub x: f64,
    /// Metres north in the local frame.
    pub y: f64,
    /// Floor level, when known.
    pub level: Option<i32>,
}

/// Reads waypoints; times must not decrease. Errors name the file and line.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be opened, else [`Error::Parse`] naming the line: a missing
/// `t`, `x` or `y` column, a value that is not a finite number, a time beyond 1e11 s or before
/// the previous row's, a coordinate more than 1,000 km from the origin, a `level` that is not
/// an integer within ±1000, or no data rows.
pub fn read_waypoints(path: &Path) -> Result<Vec<Waypoint>> {
    let mut table = CsvTable::open(path)?;
    let (t, x, y) = (table.column("t")?, table.column("x")?, table.column("y")?);
    let level = table.optional_column("level");
    let mut out: Vec<Waypoint> = Vec::new();
    table.for_each_row(|row| {
        let w = Waypoint {
            t: row.time(t, "t")?,
            x: row.coordinate(x, "x")?,
            y: row.coordinate(y, "y")?,
            level: match row.optional_number(level, "level")? {
                Some(l) if l.fract() != 0.0 || l.abs() > 1000.0 => {
                    return Err(row.error(format!("level {l} is not a floor number")));
                }
                l => l.map(|l| l as i32),
            },
        };
        if w.x.abs() > 1e6 || w.y.abs() > 1e6 {
            return Err(row.error(format!(
                "position ({}, {}) is more than 1000 km from the origin",
                w.x, w.y
            )));
        }
        if let Some(p) = out.last()
            && w.t < p.t
        {
            return Err(row.error(format!(
                "time {} s is before the previous row's {} s (rows must be sorted by time)",
                w.t, p.t
            )));
        }
        out.push(w);
        Ok(())
    })?;
    if out.is_empty() {
        return Err(Error::parse(
            path,
            0,
            "no waypoints: the file has a header but no data rows",
        ));
    }
    Ok(out)
}

/// Writes waypoints as CSV (`t,x,y` and `level` when any waypoint has one).
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be written, as
/// [`write_atomically`](crate::io::write_atomically); an existing file is then left as it was.
pub fn write_waypoints(path: &Path, waypoints: &[Waypoint]) -> Result<()> {
    let with_level = waypoints.iter().any(|w| w.level.is_some());
    let mut text = String::from(if with_level {
        "t,x,y,level\n"
    } else {
        "t,x,y\n"
    });
    for w in waypoints {
        text.push_str(&format!("{:.3},{:.4},{:.4}", w.t, w.x, w.y));
        if with_level {
            text.push(',');
            if let Some(l) = w.level {
                text.push_str(&l.to_string());
            }
        }
        text.push('\n');
    }
    crate::io::write_atomically(path, text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_and_rejects_unsorted() {
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("waypoints.csv");
        let w = vec![
            Waypoint {
                t: 1_574_000_000.5,
                x: 1.0,
                y: 2.0,
                level: Some(0),
            },
            Waypoint {
                t: 1_574_000_010.0,
                x: 3.0,
                y: -2.0,
                level: None,
            },
        ];
        write_waypoints(&p, &w).expect("write");
        assert_eq!(read_waypoints(&p).expect("read"), w);
        std::fs::write(&p, "t,x,y\n2,0,0\n1,0,0\n").expect("write");
        let e = read_waypoints(&p).unwrap_err().to_string();
        assert!(e.contains("waypoints.csv:3") && e.contains("sorted"), "{e}");
        std::fs::write(&p, "t,x,y,level\n2,0,0,1.5\n").expect("write");
        assert!(read_waypoints(&p).is_err());
    }
}
