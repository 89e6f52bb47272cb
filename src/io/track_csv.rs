//! A tracked walker's 2.5D positions as CSV: `t,x,y,z,level` (local metres), as `footslam
//! track` writes them in `track.csv`.

use super::csv_table::CsvTable;
use crate::error::{Error, Result};
use std::io::Write;
use std::path::Path;

/// A 2.5D position at a time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackPoint {
    /// Seconds.
    pub t: f64,
    /// East, metres.
    pub x: f64,
    /// North, metres.
    pub y: f64,
    /// Height, metres.
    pub z: f64,
    /// Floor level.
    pub level: i32,
}

/// Reads `t,x,y,z,level` rows (extra columns ignored); times must be strictly increasing and
/// `level` an integer. An empty track (header only) is valid: a walker never localised.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be opened, else [`Error::Parse`] naming the line: a missing
/// `t`, `x`, `y`, `z` or `level` column, a value that is not a finite number, a coordinate more
/// than 1,000 km from the origin, a `level` that is not an integer, or a time beyond 1e11 s or
/// not after the previous row's.
pub fn read_track(path: &Path) -> Result<Vec<TrackPoint>> {
    let mut table = CsvTable::open(path)?;
    let columns = ["t", "x", "y", "z", "level"].map(|c| table.column(c));
    let [t, x, y, z, level] = columns;
    let (t, x, y, z, level) = (t?, x?, y?, z?, level?);
    let mut points: Vec<TrackPoint> = Vec::new();
    table.for_each_row(|row| {
        let l = row.number(level, "level")?;
        if l.fract() != 0.0 || l.abs() > 1e6 {
            return Err(row.error(format!("level `{l}` is not an integer")));
        }
        let p = TrackPoint {
            t: row.number(t, "t")?,
            x: row.coordinate(x, "x")?,
            y: row.coordinate(y, "y")?,
            z: row.coordinate(z, "z")?,
            level: l as i32,
        };
        row.ensure_after(points.last().map(|q| q.t), p.t)?;
        points.push(p);
        Ok(())
    })?;
    Ok(points)
}

/// A smoothed position with how sure the whole walk makes it (`footslam track`'s
/// `track.csv`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SmoothedPoint {
    /// The heaviest hypothesis' position.
    pub point: TrackPoint,
    /// True when one hypothesis, no wider than the localisation spread, remains.
    pub certain: bool,
    /// Hypotheses (clusters) at this step.
    pub hypotheses: usize,
    /// The RMS distance of the answer's hypothesis' particles from its position, metres.
    pub spread: f64,
    /// The answer's hypothesis' share of the belief, in [0, 1].
    pub share: f64,
}

/// Writes `t,x,y,z,level` rows (millimetre precision).
///
/// # Errors
///
/// [`Error::InvalidData`] when a point's `t`, `x`, `y` or `z` is not finite (nothing is
/// written); [`Error::Io`] when `path` cannot be written, as
/// [`write_atomically_with`](crate::io::write_atomically_with).
pub fn write_track(path: &Path, points: &[TrackPoint]) -> Result<()> {
    check_finite(points.iter(), path)?;
    crate::io::write_atomically_with(path, |w| {
        w.write_all(b"t,x,y,z,level\n")?;
        for p in points {
            write_point(w, p)?;
            w.write_all(b"\n")?;
        }
        Ok(())
    })
}

/// Writes `t,x,y,z,level,certain,hypotheses,spread,share` rows (`certain` 1 or 0; `spread`
/// in metres to the centimetre, `share` to three decimals): a reader of
/// `t,x,y,z,level` reads it as a track. The points are streamed (a long walk's smoothed
/// track is computed as it is written); a non-finite one stops the writing and nothing is
/// written.
///
/// # Errors
///
/// [`Error::InvalidData`] when a point's `t`, `x`, `y` or `z` is not finite (nothing is
/// written); [`Error::Io`] when `path` cannot be written, as
/// [`write_atomically_with`](crate::io::write_atomically_with).
pub fn write_smoothed_track(
    path: &Path,
    points: impl IntoIterator<Item = SmoothedPoint>,
) -> Result<()> {
    let mut bad = None;
    let written = crate::io::write_atomically_with(path, |w| {
        w.write_all(b"t,x,y,z,level,certain,hypotheses,spread,share\n")?;
        for p in points {
            if !is_finite(&p.point) {
                bad = Some(p.point);
                return Err(std::io::Error::other("a track point is not finite"));
            }
            write_point(w, &p.point)?;
            writeln!(
                w,
                ",{},{},{:.2},{:.3}",
                u8::from(p.certain),
                p.hypotheses,
                p.spread,
                p.share
            )?;
        }
        Ok(())
    });
    match bad {
        Some(p) => Err(not_finite(&p, path)),
        None => written,
    }
}

/// Refuses a track with a non-finite value (nothing is written).
fn check_finite<'a>(mut points: impl Iterator<Item = &'a TrackPoint>, path: &Path) -> Result<()> {
    match points.find(|p| !is_finite(p)) {
        Some(p) => Err(not_finite(p, path)),
        None => Ok(()),
    }
}

fn is_finite(p: &TrackPoint) -> bool {
    p.t.is_finite() && p.x.is_finite() && p.y.is_finite() && p.z.is_finite()
}

fn not_finite(p: &TrackPoint, path: &Path) -> Error {
    Error::invalid(
        format!("track point at t = {}", p.t),
        format!("is not finite; nothing written to {}", path.display()),
    )
}

fn write_point(w: &mut dyn Write, p: &TrackPoint) -> std::io::Result<()> {
    write!(w, "{:.3},{:.3},{:.3},{:.3},{}", p.t, p.x, p.y, p.z, p.level)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_errors() {
        let dir = tempfile::tempdir().expect("tmp");
        let path = dir.path().join("track.csv");
        let points = vec![
            TrackPoint {
                t: 0.5,
                x: 1.0,
                y: -2.0,
                z: 3.0,
                level: 1,
            },
            TrackPoint {
                t: 1.0,
                x: 1.5,
                y: -2.25,
                z: 3.0,
                level: 1,
            },
        ];
        write_track(&path, &points).expect("write");
        assert_eq!(read_track(&path).expect("read"), points);
        write_track(&path, &[]).expect("empty");
        assert!(read_track(&path).expect("empty read").is_empty());
        std::fs::write(&path, "t,x,y,z,level\n0,0,0,0,1.5\n").expect("write");
        let e = read_track(&path).expect_err("fractional level").to_string();
        assert!(e.contains("track.csv:2:"), "{e}");
        std::fs::write(&path, "t,x,y,z,level\n1,0,0,0,1\n0,0,0,0,1\n").expect("write");
        assert!(read_track(&path).is_err());
    }
}
