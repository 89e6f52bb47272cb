//! Timed positions from CSV, placed on the globe for the page: tracks (`t,x,y` with
//! optional `level`, `spread` or `spread_m`, `certain`), the truth and waypoints, all in
//! local metres of a run's frame, and GPS fixes. Extra columns are ignored; errors name file and line.

use super::layer::PathPoint;
use crate::error::Result;
use crate::geometry::LocalFrame;
use crate::io::csv_table::CsvTable;
use std::collections::HashMap;
use std::path::Path;

/// Floor levels of a walk's steps by time (milliseconds), for a path whose CSV has no
/// `level` column (learn's `track.csv`; its `track.geojson` has them).
pub type LevelsByTime = HashMap<i64, i32>;

/// The key of time `t` (seconds) in [`LevelsByTime`].
#[must_use]
pub fn time_key(t: f64) -> i64 {
    (t * 1000.0).round() as i64
}

/// Reads `path` (`t,x,y` and optional `level`, `spread`/`spread_m`, `certain` columns) in
/// `frame`; a row without a `level` takes its level from `levels` when its time is there.
/// Times must not decrease.
///
/// # Errors
///
/// [`Error::Io`](crate::Error::Io) when `path` cannot be read;
/// [`Error::Parse`](crate::Error::Parse) naming the line when a `t`, `x` or `y` column is missing,
/// a value is not a finite number, a time is implausible or comes before the previous row's, a
/// coordinate is too far from the origin for a local frame, a `level` is not a whole number within
/// ±1000, or a `spread` is negative.
pub fn read_path_csv(
    path: &Path,
    frame: &LocalFrame,
    levels: Option<&LevelsByTime>,
) -> Result<Vec<PathPoint>> {
    let mut table = CsvTable::open(path)?;
    let (t, x, y) = (table.column("t")?, table.column("x")?, table.column("y")?);
    let level = table.optional_column("level");
    let spread = table
        .optional_column("spread")
        .or_else(|| table.optional_column("spread_m"));
    let certain = table.optional_column("certain");
    let mut points: Vec<PathPoint> = Vec::new();
    table.for_each_row(|row| {
        let time = row.time(t, "t")?;
        if let Some(previous) = points.last().map(|p| p.t)
            && time < previous
        {
            return Err(row.error(format!(
                "time {time} s is before the previous row's {previous} s (rows must be sorted by time)"
            )));
        }
        let mut p = PathPoint::from_local(
            frame,
            time,
            row.coordinate(x, "x")?,
            row.coordinate(y, "y")?,
        );
        p.level = match row.optional_number(level, "level")? {
            Some(l) if l.fract() != 0.0 || l.abs() > 1000.0 => {
                return Err(row.error(format!("level `{l}` is not a floor number")));
            }
            Some(l) => Some(l as i32),
            None => levels.and_then(|m| m.get(&time_key(time)).copied()),
        };
        p.spread = match row.optional_number(spread, "spread")? {
            Some(s) if s < 0.0 => {
                return Err(row.error(format!("spread {s} m is negative")));
            }
            s => s,
        };
        p.certain = row.optional_number(certain, "certain")?.map(|c| c != 0.0);
        points.push(p);
        Ok(())
    })?;
    Ok(points)
}

/// Reads waypoints (`t,x,y[,level]`, [`crate::io::read_waypoints`]) in `frame`.
///
/// # Errors
///
/// As [`crate::io::read_waypoints`]: the file cannot be read, or a line is malformed or out of time
/// order (file and line named).
pub fn read_waypoints_path(path: &Path, frame: &LocalFrame) -> Result<Vec<PathPoint>> {
    Ok(crate::io::read_waypoints(path)?
        .into_iter()
        .map(|w| PathPoint {
            level: w.level,
            ..PathPoint::from_local(frame, w.t, w.x, w.y)
        })
        .collect())
}

/// Reads GPS fixes (`t,lat,lon[,accuracy]`, [`crate::io::read_gps_csv`]), each fix's
/// accuracy as its spread.
///
/// # Errors
///
/// As [`crate::io::read_gps_csv`]: the file cannot be read, or a line is malformed or its fix fails
/// [`check_fix`](crate::sensor::gps::check_fix) (file and line named).
pub fn read_gps_path(path: &Path) -> Result<Vec<PathPoint>> {
    Ok(crate::io::read_gps_csv(path)?
        .into_iter()
        .map(|fix| PathPoint {
            t: fix.t,
            lon: fix.lon,
            lat: fix.lat,
            level: None,
            spread: Some(fix.accuracy),
            certain: None,
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Vec<PathPoint>> {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("track.csv");
        std::fs::write(&path, text).expect("write");
        let mut levels = LevelsByTime::new();
        levels.insert(time_key(2.0), 3);
        read_path_csv(&path, &LocalFrame::default(), Some(&levels))
    }

    #[test]
    fn optional_columns_are_read_and_missing_levels_looked_up() {
        let points = read("t,x,y,spread_m\n1,0,0,0.5\n2,1,0,0.25\n").expect("read");
        assert_eq!(points.len(), 2);
        assert_eq!(points[0].level, None);
        assert_eq!(points[1].level, Some(3), "from the levels by time");
        assert_eq!(points[1].spread, Some(0.25));
        assert!(points[1].lon > 0.0 && points[1].lat == 0.0);
        let points = read("t,x,y,z,level,certain,spread\n1,0,0,0,2,0,1.5\n").expect("read");
        assert_eq!(
            (points[0].level, points[0].certain, points[0].spread),
            (Some(2), Some(false), Some(1.5))
        );
    }

    #[test]
    fn errors_name_the_file_and_line() {
        let err = read("t,x,y\n1,0,0\n2,zero,0\n").expect_err("not a number");
        let message = err.to_string();
        assert!(
            message.contains("track.csv") && message.contains(":3"),
            "{message}"
        );
        let err = read("t,x,y\n2,0,0\n1,0,0\n").expect_err("out of order");
        assert!(err.to_string().contains("sorted by time"), "{err}");
        assert!(read("t,y\n1,0\n").is_err(), "no x column");
    }
}
