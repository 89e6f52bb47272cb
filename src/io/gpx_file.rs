//! GPS fixes from GPX 1.1 track points (read with the `gpx` crate).
//!
//! Each track point (every track, every segment, in file order) becomes a fix; its UTC time
//! is put on the steps' clock by subtracting `t0`, the UTC time (Unix seconds) of the steps'
//! `t = 0`. A point's horizontal accuracy is `hdop × 5 m` when it has an `<hdop>` (a typical
//! user-equivalent range error, so that HDOP 1 gives the CSV default of 5 m), else 5 m.

use crate::error::{Error, Result};
use crate::sensor::gps::{DEFAULT_ACCURACY, GpsFix, check_fix};
use std::path::Path;
use time::OffsetDateTime;
use time::format_description::well_known::Rfc3339;

/// Metres of 1σ horizontal error per unit of HDOP.
pub const HDOP_METRES: f64 = DEFAULT_ACCURACY;

/// Reads the track points of a GPX file as fixes on the steps' clock (`t = UTC − t0`, with
/// `t0` in Unix seconds). Errors name the file and, for a bad point, its index.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be opened; [`Error::Parse`] on the file when it is not
/// valid GPX, holds no track point, or a track point (named by index) has no `<time>` or fails
/// [`check_fix`] (position out of range or `0,0`, an HDOP giving an accuracy outside
/// (0, 1000] m, a time not after the previous point's).
pub fn read_gpx(path: &Path, t0: f64) -> Result<Vec<GpsFix>> {
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let gpx = gpx::read(std::io::BufReader::new(file)).map_err(|e| {
        let mut message = format!("not a valid GPX file: {e}");
        let mut source = std::error::Error::source(&e);
        while let Some(s) = source {
            message.push_str(&format!(": {s}"));
            source = s.source();
        }
        Error::parse(path, 0, message)
    })?;
    let points = gpx
        .tracks
        .iter()
        .flat_map(|t| &t.segments)
        .flat_map(|s| &s.points);
    let mut fixes: Vec<GpsFix> = Vec::new();
    for (i, p) in points.enumerate() {
        let bad = |m: String| Error::parse(path, 0, format!("track point {i}: {m}"));
        let time = p
            .time
            .ok_or_else(|| bad("has no <time>; fixes need times".into()))?;
        let utc = OffsetDateTime::from(time);
        let unix = utc.unix_timestamp() as f64 + f64::from(utc.nanosecond()) * 1e-9;
        let point = p.point();
        let fix = GpsFix {
            t: unix - t0,
            lat: point.y(),
            lon: point.x(),
            accuracy: p.hdop.map_or(DEFAULT_ACCURACY, |h| h * HDOP_METRES),
        };
        check_fix(&fix, fixes.last().map(|f| f.t)).map_err(bad)?;
        fixes.push(fix);
    }
    if fixes.is_empty() {
        return Err(Error::parse(
            path,
            0,
            "no track points (<trkpt>) in the file",
        ));
    }
    Ok(fixes)
}

/// Unix seconds of an RFC 3339 UTC time such as `2024-05-01T10:00:00Z` (or a plain number
/// of Unix seconds).
///
/// # Errors
///
/// A message when `text` is a number that is not finite, or neither a number nor an RFC 3339
/// time with a zone (`Z` or `+02:00`).
pub fn parse_utc_time(text: &str) -> Result<f64, String> {
    if let Ok(v) = text.trim().parse::<f64>() {
        return if v.is_finite() {
            Ok(v)
        } else {
            Err(format!("`{text}` is not a finite number of seconds"))
        };
    }
    let t = OffsetDateTime::parse(text.trim(), &Rfc3339).map_err(|e| {
        format!("`{text}` is neither Unix seconds nor an RFC 3339 time (2024-05-01T10:00:00Z): {e}")
    })?;
    Ok(t.unix_timestamp() as f64 + f64::from(t.nanosecond()) * 1e-9)
}

#[cfg(test)]
mod tests {
    use super::*;

    const GPX: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<gpx version="1.1" creator="test" xmlns="http://www.topografix.com/GPX/1/1">
  <trk><trkseg>
    <trkpt lat="48.1" lon="11.5"><time>2024-05-01T10:00:01Z</time><hdop>0.8</hdop></trkpt>
    <trkpt lat="48.10001" lon="11.50002"><time>2024-05-01T10:00:02.5Z</time></trkpt>
  </trkseg></trk>
</gpx>"#;

    fn write(text: &str) -> (tempfile::TempDir, std::path::PathBuf) {
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("walk.gpx");
        std::fs::write(&p, text).expect("write");
        (dir, p)
    }

    #[test]
    fn reads_times_positions_and_hdop() {
        let (_dir, p) = write(GPX);
        let t0 = parse_utc_time("2024-05-01T10:00:00Z").expect("time");
        let f = read_gpx(&p, t0).expect("read");
        assert_eq!(f.len(), 2);
        assert!((f[0].t - 1.0).abs() < 1e-9 && (f[1].t - 2.5).abs() < 1e-6);
        assert_eq!((f[0].lat, f[0].lon), (48.1, 11.5));
        assert!((f[0].accuracy - 4.0).abs() < 1e-12);
        assert_eq!(f[1].accuracy, DEFAULT_ACCURACY);
        assert_eq!(
            parse_utc_time("1714557600").expect("number"),
            1_714_557_600.0
        );
        assert_eq!(t0, 1_714_557_600.0);
        assert!(parse_utc_time("yesterday").is_err());
    }

    #[test]
    fn bad_files_are_explained() {
        let (_dir, p) = write(&GPX.replace("<time>2024-05-01T10:00:01Z</time>", ""));
        let e = read_gpx(&p, 0.0).unwrap_err().to_string();
        assert!(e.contains("walk.gpx") && e.contains("track point 0"), "{e}");
        let (_dir, p) = write(&GPX.replace("10:00:02.5", "09:00:00"));
        let e = read_gpx(&p, 0.0).unwrap_err().to_string();
        assert!(
            e.contains("track point 1") && e.contains("increasing"),
            "{e}"
        );
        let (_dir, p) = write("<gpx><trk>");
        assert!(read_gpx(&p, 0.0).unwrap_err().to_string().contains("GPX"));
        let (_dir, p) = write(&GPX.replace(r#"lat="48.1""#, r#"lat="98.1""#));
        assert!(read_gpx(&p, 0.0).is_err());
    }
}
