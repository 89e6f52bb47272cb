//! GPS fixes as CSV: header `t,lat,lon[,accuracy]` (seconds on the steps' clock, WGS84
//! degrees, 1σ horizontal metres — default 5 m); extra columns are ignored.

use super::csv_table::CsvTable;
use crate::error::Result;
use crate::sensor::gps::{DEFAULT_ACCURACY, GpsFix, check_fix};
use std::path::Path;

/// Reads and validates GPS fixes; errors name the file and line.
///
/// # Errors
///
/// [`Error::Io`](crate::Error::Io) when `path` cannot be opened, else
/// [`Error::Parse`](crate::Error::Parse) naming the line: a missing `t`, `lat` or `lon` column, a
/// value that is not a finite number, a time beyond 1e11 s, a fix that fails [`check_fix`]
/// (latitude beyond ±89°, longitude beyond ±180°, the receivers' `0,0` for no fix, accuracy
/// outside (0, 1000] m, a time not after the previous fix's), or no data rows.
pub fn read_gps_csv(path: &Path) -> Result<Vec<GpsFix>> {
    gps_from_table(CsvTable::open(path)?)
}

/// Reads and validates GPS fixes from CSV `text` (the file format's header and rows), as
/// [`read_gps_csv`] reads a file; errors name the table `name` and the 0-based data row.
///
/// # Errors
///
/// As [`read_gps_csv`], as [`Error::InvalidData`](crate::Error::InvalidData) naming `name` and
/// the row.
pub fn gps_from_str(text: &str, name: &str) -> Result<Vec<GpsFix>> {
    gps_from_table(CsvTable::from_text(text, name)?)
}

fn gps_from_table(mut table: CsvTable) -> Result<Vec<GpsFix>> {
    let t = table.column("t")?;
    let lat = table.column("lat")?;
    let lon = table.column("lon")?;
    let accuracy = table.optional_column("accuracy");
    let mut fixes: Vec<GpsFix> = Vec::new();
    table.for_each_row(|row| {
        let fix = GpsFix {
            t: row.time(t, "t")?,
            lat: row.number(lat, "lat")?,
            lon: row.number(lon, "lon")?,
            accuracy: row
                .optional_number(accuracy, "accuracy")?
                .unwrap_or(DEFAULT_ACCURACY),
        };
        check_fix(&fix, fixes.last().map(|f| f.t)).map_err(|m| row.error(m))?;
        fixes.push(fix);
        Ok(())
    })?;
    if fixes.is_empty() {
        return Err(table.error(0, "no fixes: the file has a header but no data rows"));
    }
    Ok(fixes)
}

/// Writes fixes as CSV `t,lat,lon,accuracy` (degrees to 1e-8°, about a millimetre).
///
/// # Errors
///
/// [`Error::Io`](crate::Error::Io) when `path` cannot be written, as
/// [`write_atomically`](crate::io::write_atomically); an existing file is then left as it was.
pub fn write_gps_csv(path: &Path, fixes: &[GpsFix]) -> Result<()> {
    let mut text = String::from("t,lat,lon,accuracy\n");
    for f in fixes {
        text.push_str(&format!(
            "{:.3},{:.8},{:.8},{:.2}\n",
            f.t, f.lat, f.lon, f.accuracy
        ));
    }
    crate::io::write_atomically(path, text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Vec<GpsFix>> {
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("gps.csv");
        std::fs::write(&p, text).expect("write");
        read_gps_csv(&p)
    }

    #[test]
    fn reads_with_and_without_accuracy_and_round_trips() {
        let f = read("t,lat,lon\n0,48.1,11.5\n1,48.10001,11.5\n").expect("ok");
        assert_eq!(f.len(), 2);
        assert_eq!(f[0].accuracy, DEFAULT_ACCURACY);
        let f = read("t,lon,lat,accuracy,extra\n0.5,11.5,48.1,3.5,x\n").expect("ok");
        assert_eq!((f[0].lat, f[0].lon, f[0].accuracy), (48.1, 11.5, 3.5));
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("out.csv");
        write_gps_csv(&p, &f).expect("write");
        assert_eq!(read_gps_csv(&p).expect("read"), f);
    }

    #[test]
    fn errors_name_the_line_and_problem() {
        let e = read("t,lat,lon\n0,48,11\n1,95,11\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("gps.csv:3") && e.contains("latitude"), "{e}");
        let e = read("t,lat,lon\n1,48,11\n0,48,11\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains(":3") && e.contains("increasing"), "{e}");
        let e = read("t,lat,lon,accuracy\n0,48,11,-2\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains(":2") && e.contains("accuracy"), "{e}");
        let e = read("t,lat\n0,48\n").unwrap_err().to_string();
        assert!(e.contains("lon"), "{e}");
        let e = read("t,lat,lon\n").unwrap_err().to_string();
        assert!(e.contains("no fixes"), "{e}");
        let e = read("t,lat,lon\n0,NaN,11\n").unwrap_err().to_string();
        assert!(e.contains(":2"), "{e}");
    }
}
