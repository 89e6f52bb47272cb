//! The simulator's radio truth as CSV, for scoring radio maps: the access points
//! (`wifi_aps.csv`: `bssid,x,y,level`, local metres) and the expected RSSI field
//! (`wifi_field.csv`: `level,x,y` and one column per access point's BSSID, dBm, on a grid over
//! the walkable area; not clipped at the detection floor).

use crate::error::{Error, Result};
use crate::sensor::AccessPoint;
use std::path::Path;

/// Writes the access points.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be written, as
/// [`write_atomically`](crate::io::write_atomically); an existing file is then left as it was.
pub fn write_access_points(path: &Path, aps: &[AccessPoint]) -> Result<()> {
    let mut text = String::from("bssid,x,y,level\n");
    for a in aps {
        text.push_str(&format!("{},{:.3},{:.3},{}\n", a.bssid, a.x, a.y, a.level));
    }
    crate::io::write_atomically(path, text.as_bytes())
}

/// Writes the expected field: one row per grid point, one column per access point (in the
/// order of `aps`).
///
/// # Errors
///
/// [`Error::InvalidData`] when a row does not hold one finite value per access point (nothing
/// is written); [`Error::Io`] when `path` cannot be written, as
/// [`write_atomically`](crate::io::write_atomically).
pub fn write_radio_field(
    path: &Path,
    aps: &[AccessPoint],
    rows: &[(i32, f64, f64, Vec<f64>)],
) -> Result<()> {
    let mut text = String::from("level,x,y");
    for a in aps {
        text.push(',');
        text.push_str(&a.bssid);
    }
    text.push('\n');
    for (level, x, y, rssi) in rows {
        if rssi.len() != aps.len() || rssi.iter().any(|v| !v.is_finite()) {
            return Err(Error::invalid(
                format!("field row at ({x}, {y}) on level {level}"),
                format!(
                    "does not hold one finite value per access point; nothing written to {}",
                    path.display()
                ),
            ));
        }
        text.push_str(&format!("{level},{x:.2},{y:.2}"));
        for v in rssi {
            text.push_str(&format!(",{v:.1}"));
        }
        text.push('\n');
    }
    crate::io::write_atomically(path, text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_aps_and_a_wide_field() {
        let dir = tempfile::tempdir().expect("tmp");
        let aps = vec![
            AccessPoint {
                bssid: "02:00:00:00:00:00".into(),
                x: 1.0,
                y: 2.0,
                level: 0,
            },
            AccessPoint {
                bssid: "02:00:00:00:00:01".into(),
                x: 3.0,
                y: 4.0,
                level: 1,
            },
        ];
        let p = dir.path().join("aps.csv");
        write_access_points(&p, &aps).expect("aps");
        let text = std::fs::read_to_string(&p).expect("read");
        assert_eq!(text.lines().count(), 3);
        let f = dir.path().join("field.csv");
        write_radio_field(&f, &aps, &[(0, 0.5, 0.5, vec![-50.0, -80.25])]).expect("field");
        let text = std::fs::read_to_string(&f).expect("read");
        assert_eq!(
            text,
            "level,x,y,02:00:00:00:00:00,02:00:00:00:00:01\n0,0.50,0.50,-50.0,-80.2\n"
        );
        assert!(write_radio_field(&f, &aps, &[(0, 0.5, 0.5, vec![-50.0])]).is_err());
    }
}
