//! True paths as CSV (the simulator's `truth.csv`): header `t,x,y,z,level,heading` (seconds,
//! metres east, north and up, integer floor level, radians counter-clockwise from east), one
//! row per step; extra columns are ignored.
//!
//! On reading, `z` and `level` default to 0 and `heading` to the direction of motion from the
//! previous row (from the origin for the first row, the [`TruePath`] convention).

use super::csv_table::CsvTable;
use crate::error::{Error, Result};
use crate::geometry::angle::wrap_angle;
use crate::sensor::{TruePath, TruePose};
use std::path::Path;

/// Writes `truth` as CSV (millisecond times, 0.1 mm positions, microradian headings).
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be written, as
/// [`write_atomically`](crate::io::write_atomically); an existing file is then left as it was.
pub fn write_truth(path: &Path, truth: &TruePath) -> Result<()> {
    let mut text = String::from("t,x,y,z,level,heading\n");
    for p in &truth.poses {
        text.push_str(&format!(
            "{:.3},{:.4},{:.4},{:.4},{},{:.6}\n",
            p.t, p.x, p.y, p.z, p.level, p.heading
        ));
    }
    crate::io::write_atomically(path, text.as_bytes())
}

/// Reads a true path; times must be strictly increasing and levels integers. Errors name the
/// file and line.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be opened, else [`Error::Parse`] naming the line: a missing
/// `t`, `x` or `y` column, a value that is not a finite number, an `x`, `y` or `z` more than
/// 1,000 km from the origin, a `level` that is not a 32-bit integer, a time beyond 1e11 s or
/// not after the previous row's, or no data rows.
pub fn read_truth(path: &Path) -> Result<TruePath> {
    let mut table = CsvTable::open(path)?;
    let (t, x, y) = (table.column("t")?, table.column("x")?, table.column("y")?);
    let (z, level, heading) = (
        table.optional_column("z"),
        table.optional_column("level"),
        table.optional_column("heading"),
    );
    let mut poses: Vec<TruePose> = Vec::new();
    table.for_each_row(|row| {
        let (px, py) = (row.coordinate(x, "x")?, row.coordinate(y, "y")?);
        let previous = poses.last().map_or((0.0, 0.0), |p| (p.x, p.y));
        let level = match row.optional_number(level, "level")? {
            None => 0,
            Some(l)
                if l.fract() == 0.0 && (f64::from(i32::MIN)..=f64::from(i32::MAX)).contains(&l) =>
            {
                l as i32
            }
            Some(l) => {
                return Err(row.error(format!(
                    "column `level`: `{l}` is not an integer floor level"
                )));
            }
        };
        let pose = TruePose {
            t: row.number(t, "t")?,
            x: px,
            y: py,
            z: match z {
                Some(z) if !row.text(z).is_empty() => row.coordinate(z, "z")?,
                _ => 0.0,
            },
            level,
            heading: match row.optional_number(heading, "heading")? {
                Some(h) => h,
                None => wrap_angle((py - previous.1).atan2(px - previous.0)),
            },
        };
        row.ensure_after(poses.last().map(|p| p.t), pose.t)?;
        poses.push(pose);
        Ok(())
    })?;
    if poses.is_empty() {
        return Err(Error::parse(
            path,
            0,
            "no rows: the file has a header but no data",
        ));
    }
    Ok(TruePath { poses })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<TruePath> {
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("truth.csv");
        std::fs::write(&p, text).expect("write");
        read_truth(&p)
    }

    #[test]
    fn round_trips_a_simulated_walk() {
        let sim = crate::sim::simulate(&crate::sim::SimConfig::default()).expect("simulation");
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("truth.csv");
        write_truth(&p, &sim.truth).expect("write");
        let back = read_truth(&p).expect("read");
        assert_eq!(back.len(), sim.truth.len());
        for (a, b) in back.poses.iter().zip(&sim.truth.poses) {
            assert!(
                (a.t - b.t).abs() <= 5e-4 && (a.x - b.x).abs() <= 5e-5 && (a.y - b.y).abs() <= 5e-5
            );
            assert!(
                a.level == b.level
                    && (a.z - b.z).abs() <= 5e-5
                    && (a.heading - b.heading).abs() <= 5e-7
            );
        }
        let text = std::fs::read_to_string(&p).expect("text");
        assert!(text.starts_with("t,x,y,z,level,heading\n"));
    }

    #[test]
    fn optional_columns_have_defaults() {
        let path = read("t,y,x,extra\n0.5,1,0,a\n1.0,1,1,b\n").expect("ok");
        let (a, b) = (path.poses[0], path.poses[1]);
        assert!((a.heading - std::f64::consts::FRAC_PI_2).abs() < 1e-12 && b.heading.abs() < 1e-12);
        assert!(a.z == 0.0 && a.level == 0 && (b.x - 1.0).abs() < 1e-12);
        assert_eq!(
            read("t,x,y,level\n0,0,0,-2\n").expect("ok").poses[0].level,
            -2
        );
    }

    #[test]
    fn errors_name_the_file_line_and_problem() {
        let e = read("t,x,y\n0,0,0\n1,abc,0\n")
            .expect_err("must fail")
            .to_string();
        assert!(e.contains("truth.csv:3") && e.contains("`x`"), "{e}");
        let e = read("t,x,y\n1,0,0\n1,0,0\n")
            .expect_err("must fail")
            .to_string();
        assert!(e.contains(":3") && e.contains("increasing"), "{e}");
        let e = read("t,x,y,level\n0,0,0,1.5\n")
            .expect_err("must fail")
            .to_string();
        assert!(e.contains(":2") && e.contains("level"), "{e}");
        let e = read("t,x\n0,0\n").expect_err("must fail").to_string();
        assert!(e.contains("missing column `y`"), "{e}");
        let e = read("t,x,y\n").expect_err("must fail").to_string();
        assert!(e.contains("no rows"), "{e}");
        let e = read("t,x,y\n0,inf,0\n").expect_err("must fail").to_string();
        assert!(e.contains(":2") && e.contains("finite"), "{e}");
    }
}
