//! WiFi logs as CSV: header `t,bssid,rssi[,ssid,freq]` (seconds on the step trace's clock,
//! access point id, dBm, network name, MHz), one row per sighting; rows sharing `t` are one
//! scan. Times must not decrease; extra columns are ignored. Errors name the file and line.
//!
//! Real logs sometimes list one access point twice in a scan (a phone that reports a
//! network twice, or a converter that merged two sweeps under one time stamp): the later row
//! is kept, as the importers keep the freshest reading, and [`WifiLog::duplicate_readings`]
//! counts the rows dropped.

use super::csv_table::CsvTable;
use crate::error::{Error, Result};
use crate::sensor::wifi::{WifiReading, WifiScan, check_reading, normalise_bssid};
use std::path::Path;

/// A WiFi log as read: its scans in time order, and the repeated readings left out.
#[derive(Debug, Clone, PartialEq)]
pub struct WifiLog {
    /// The scans, in time order, one reading per access point each.
    pub scans: Vec<WifiScan>,
    /// Rows that repeated an access point already in their scan (the earlier of each pair
    /// was replaced by the later).
    pub duplicate_readings: usize,
}

/// Reads a WiFi log into scans, in time order (see [`read_wifi_log`] for the count of
/// repeated readings).
///
/// # Errors
///
/// As [`read_wifi_log`].
pub fn read_wifi(path: &Path) -> Result<Vec<WifiScan>> {
    Ok(read_wifi_log(path)?.scans)
}

/// Reads a WiFi log: its scans and how many repeated readings were left out.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be opened, else [`Error::Parse`] naming the line: a missing
/// `t`, `bssid` or `rssi` column, a value that is not a finite number, a time beyond 1e11 s or
/// before the previous row's, a `bssid` that is empty or holds a comma or quote, an `rssi`
/// outside [-120, 0] dBm or a `freq` outside [100, 100000] MHz, or no data rows.
pub fn read_wifi_log(path: &Path) -> Result<WifiLog> {
    wifi_from_table(CsvTable::open(path)?)
}

/// Reads a WiFi log from CSV `text` (the file format's header and rows), as [`read_wifi`]
/// reads a file; errors name the table `name` and the 0-based data row.
///
/// # Errors
///
/// As [`read_wifi`], as [`Error::InvalidData`] naming `name` and the row.
pub fn wifi_from_str(text: &str, name: &str) -> Result<Vec<WifiScan>> {
    Ok(wifi_from_table(CsvTable::from_text(text, name)?)?.scans)
}

/// Reads a WiFi log from CSV `text`, as [`read_wifi_log`] reads a file.
///
/// # Errors
///
/// As [`read_wifi_log`], as [`Error::InvalidData`] naming `name` and the row.
pub fn wifi_log_from_str(text: &str, name: &str) -> Result<WifiLog> {
    wifi_from_table(CsvTable::from_text(text, name)?)
}

fn wifi_from_table(mut table: CsvTable) -> Result<WifiLog> {
    let (t, bssid, rssi) = (
        table.column("t")?,
        table.column("bssid")?,
        table.column("rssi")?,
    );
    let (ssid, freq) = (table.optional_column("ssid"), table.optional_column("freq"));
    let mut scans: Vec<WifiScan> = Vec::new();
    let mut duplicate_readings = 0;
    table.for_each_row(|row| {
        let time = row.time(t, "t")?;
        let id = normalise_bssid(row.text(bssid)).ok_or_else(|| {
            row.error(format!(
                "bssid `{}` is empty or holds a comma or quote",
                row.text(bssid)
            ))
        })?;
        let reading = WifiReading {
            bssid: id,
            rssi: row.number(rssi, "rssi")?,
            ssid: ssid
                .map(|c| row.text(c).trim().to_string())
                .filter(|s| !s.is_empty()),
            freq: row.optional_number(freq, "freq")?,
        };
        check_reading(&reading).map_err(|m| row.error(m))?;
        match scans.last_mut() {
            Some(scan) if scan.t == time => {
                match scan.readings.iter_mut().find(|r| r.bssid == reading.bssid) {
                    Some(earlier) => {
                        *earlier = reading;
                        duplicate_readings += 1;
                    }
                    None => scan.readings.push(reading),
                }
            }
            last => {
                if let Some(scan) = last
                    && time < scan.t
                {
                    return Err(row.error(format!(
                        "time {time} s is before the previous row's {} s (rows must be sorted by time)",
                        scan.t
                    )));
                }
                scans.push(WifiScan {
                    t: time,
                    readings: vec![reading],
                });
            }
        }
        Ok(())
    })?;
    if scans.is_empty() {
        return Err(table.error(0, "no sightings: the file has a header but no data rows"));
    }
    Ok(WifiLog {
        scans,
        duplicate_readings,
    })
}

/// Writes scans as CSV (`t,bssid,rssi,ssid,freq`; empty ssid/freq when unknown), one row per
/// reading, scans in order.
///
/// # Errors
///
/// [`Error::InvalidData`] when an SSID holds a comma, quote or newline (nothing is written);
/// [`Error::Io`] when `path` cannot be written, as
/// [`write_atomically`](crate::io::write_atomically).
pub fn write_wifi(path: &Path, scans: &[WifiScan]) -> Result<()> {
    let mut text = String::from("t,bssid,rssi,ssid,freq\n");
    for scan in scans {
        for r in &scan.readings {
            if r.ssid
                .as_deref()
                .is_some_and(|s| s.contains([',', '"', '\n']))
            {
                return Err(Error::invalid(
                    format!("ssid {:?}", r.ssid),
                    format!(
                        "holds a comma, quote or newline; nothing written to {}",
                        path.display()
                    ),
                ));
            }
            text.push_str(&format!(
                "{:.3},{},{:.1},{},{}\n",
                scan.t,
                r.bssid,
                r.rssi,
                r.ssid.as_deref().unwrap_or(""),
                r.freq.map_or(String::new(), |f| format!("{f}"))
            ));
        }
    }
    crate::io::write_atomically(path, text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(text: &str) -> (tempfile::TempDir, std::path::PathBuf) {
        let dir = tempfile::tempdir().expect("tmp");
        let p = dir.path().join("wifi.csv");
        std::fs::write(&p, text).expect("write");
        (dir, p)
    }

    #[test]
    fn rows_sharing_a_time_are_one_scan_and_round_trip() {
        let (_d, p) = file(
            "t,bssid,rssi,ssid,freq\n1.0,AA:BB:CC:DD:EE:01,-60,lab,2412\n1.0,aa:bb:cc:dd:ee:02,-71.5,,\n3.0,aa:bb:cc:dd:ee:01,-64,lab,2412\n",
        );
        let scans = read_wifi(&p).expect("read");
        assert_eq!(scans.len(), 2);
        assert_eq!(scans[0].readings.len(), 2);
        assert_eq!(scans[0].rssi("aa:bb:cc:dd:ee:01"), Some(-60.0));
        assert_eq!(scans[0].readings[0].ssid.as_deref(), Some("lab"));
        assert_eq!(scans[0].readings[1].freq, None);
        write_wifi(&p, &scans).expect("write");
        assert_eq!(read_wifi(&p).expect("again"), scans);
    }

    #[test]
    fn a_repeated_access_point_keeps_the_later_reading_and_is_counted() {
        let (_d, p) = file("t,bssid,rssi\n1,a,-60\n1,b,-70\n1,a,-61\n2,a,-65\n2,a,-66\n");
        let log = read_wifi_log(&p).expect("read");
        assert_eq!(log.duplicate_readings, 2);
        assert_eq!(log.scans.len(), 2);
        assert_eq!(log.scans[0].readings.len(), 2);
        assert_eq!(log.scans[0].rssi("a"), Some(-61.0));
        assert_eq!(log.scans[1].rssi("a"), Some(-66.0));
        assert_eq!(read_wifi(&p).expect("read"), log.scans);
    }

    #[test]
    fn bad_rows_are_named() {
        for (text, expected) in [
            (
                "t,bssid,rssi\n2,a,-60\n1,b,-60\n",
                "wifi.csv:3: time 1 s is before",
            ),
            ("t,bssid,rssi\n1,a,12\n", "wifi.csv:2: rssi 12 dBm"),
            ("t,bssid,rssi\n1,a,NaN\n", "wifi.csv:2:"),
            ("t,bssid,rssi\n1, ,-50\n", "wifi.csv:2: bssid"),
            ("t,bssid,rssi\n", "no sightings"),
            ("t,bssid\n1,a\n", "rssi"),
        ] {
            let (_d, p) = file(text);
            let e = read_wifi(&p).expect_err(text).to_string();
            assert!(e.contains(expected), "{e}\nexpected: {expected}");
        }
    }
}
