//! Logfiles of the IPIN indoor localisation competition's smartphone track, as written by
//! the `GetSensorData` Android app (LOPSI group, CAR-CSIC; field layouts from the header the
//! app writes into every logfile, `github.com/lopsi/GetSensorData_Android`,
//! `MainActivity.java`): one line per reading, fields separated by `;`, `%` lines are
//! comments. Times are `AppTimestamp`, seconds since the recording started, common to all
//! sensors (kept in f64); `SensorTimestamp` is the sensor's own clock and is not used,
//! except to age WiFi readings (below).
//!
//! Converted (field 0 is the tag):
//! * `ACCE;AppTs;SensorTs;Acc_X;Acc_Y;Acc_Z[;Accuracy]` (m/s²): the IMU's clock;
//!   `GYRO;…;Gyr_X;Gyr_Y;Gyr_Z[;Accuracy]` (rad/s), `MAGN;…;Mag_X;Mag_Y;Mag_Z[;Accuracy]`
//!   (µT), `PRES;AppTs;SensorTs;Pres[;Accuracy]` (mbar = hPa) and
//!   `AHRS;AppTs;SensorTs;PitchX;RollY;YawZ;RotVecX;RotVecY;RotVecZ[;Accuracy]` (degrees;
//!   Android rotation vector, device → ENU, `w = sqrt(1 − x² − y² − z²)`) are interpolated
//!   onto it ([`super::sensor_streams`]).
//! * `WIFI;AppTs;SensorTs;SSID;BSSID;Frequency;RSS` (or, in older logs, without
//!   `Frequency`): rows sharing `AppTs` are one scan. `SensorTs` is when the access point
//!   was last seen (Android's `ScanResult.timestamp`, on the boot clock): a reading last
//!   seen more than [`IpinImportConfig::max_wifi_age_s`] before the newest reading of its
//!   scan is a cached, stale result and is dropped (counted). A BSSID twice in a scan keeps
//!   its freshest reading; an SSID holding a comma or quote is blanked.
//! * `GNSS;AppTs;SensorTs;Lat;Long;Altitude;Bearing;Accuracy;Speed[;UTCTime];SatInView;SatInUse`
//!   → [`GpsFix`] `(t, lat, lon, accuracy)`; an accuracy of 0 (unknown) becomes
//!   [`crate::sensor::gps::DEFAULT_ACCURACY`], a fix repeating a time is dropped (counted).
//! * `POSI;Timestamp;Counter;Latitude;Longitude;FloorID;BuildingID`: the competition's
//!   ground-truth landmarks, as [`IpinPosition`] (see [`positions_to_waypoints`]).
//!
//! Skipped and counted: other tags (`LIGH`, `PROX`, `SOUN`, `BLUE`, `BLE4`, `HUMI`, `TEMP`,
//! `RFID`, `IMUX`, `IMUL`, `IMUI`, and any unknown one). Strict about the lines it
//! converts: too few or too many fields, a non-number, NaN, a value out of range or a time
//! more than [`super::sensor_streams::REORDER_TOLERANCE_S`] before the same sensor's
//! previous line is an error naming the file and line (an unterminated last line, perhaps
//! cut mid-number, is skipped and reported, see [`super::log_lines`]).

use super::log_lines::{LogLines, axes, number, read_log_lines};
use super::sensor_streams::{ImuStreams, SensorStream, assemble_imu, rotation_vector_quaternion};
use super::wifi_sightings::{DroppedSightings, fresh_readings};
use crate::error::{Error, Result};
use crate::geometry::LocalFrame;
use crate::io::waypoints_csv::Waypoint;
use crate::sensor::gps::{DEFAULT_ACCURACY, GpsFix, check_fix};
use crate::sensor::imu::{
    ImuRecording, MAX_ACCEL, MAX_GYRO, MAX_MAG, PRESSURE_RANGE, SamplingReport,
};
use crate::sensor::wifi::{WifiReading, WifiScan, check_reading, normalise_bssid};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// The importer's settings; every default in one place.
///
/// | field            | default | meaning                                                     |
/// |------------------|---------|-------------------------------------------------------------|
/// | `max_wifi_age_s` | 2.5 s   | readings last seen this long before their scan's newest are dropped |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct IpinImportConfig {
    /// A WiFi reading last seen more than this before the newest of its scan is stale,
    /// seconds.
    pub max_wifi_age_s: f64,
}

impl Default for IpinImportConfig {
    fn default() -> Self {
        Self {
            max_wifi_age_s: 2.5,
        }
    }
}

/// One ground-truth landmark of a logfile (`POSI`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct IpinPosition {
    /// Time, seconds (`AppTimestamp` clock).
    pub t: f64,
    /// WGS84 latitude, degrees.
    pub lat: f64,
    /// WGS84 longitude, degrees.
    pub lon: f64,
    /// Floor number.
    pub floor: i32,
    /// Building number.
    pub building: i32,
}

/// What an import read, kept and dropped.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IpinLogSummary {
    /// Lines seen.
    pub lines: LogLines,
    /// Data lines per tag.
    pub rows: BTreeMap<String, usize>,
    /// The IMU recording's sampling.
    pub imu: SamplingReport,
    /// Whether the IMU carries magnetometer, orientation (AHRS) and pressure channels.
    pub imu_channels: Vec<String>,
    /// Sensor lines out of order (within the tolerance) and sorted into place.
    pub reordered_rows: usize,
    /// WiFi scans kept.
    pub wifi_scans: usize,
    /// WiFi readings kept.
    pub wifi_readings: usize,
    /// WiFi readings dropped as stale.
    pub stale_readings_dropped: usize,
    /// The staleness limit used, seconds.
    pub max_wifi_age_s: f64,
    /// Readings dropped for repeating a BSSID within a scan.
    pub duplicate_bssids_dropped: usize,
    /// SSIDs blanked for holding a comma or quote.
    pub ssids_blanked: usize,
    /// GNSS fixes kept.
    pub gnss_fixes: usize,
    /// GNSS fixes dropped for repeating a time.
    pub gnss_duplicates_dropped: usize,
    /// GNSS fixes without an accuracy, given the default.
    pub gnss_default_accuracy: usize,
    /// Ground-truth positions (`POSI`).
    pub positions: usize,
    /// Lines of tags footslam does not convert, per tag (known and unknown).
    pub skipped_tags: BTreeMap<String, usize>,
}

/// One converted logfile.
#[derive(Debug, Clone)]
pub struct IpinLog {
    /// The inertial recording on the accelerometer's clock.
    pub imu: ImuRecording,
    /// WiFi scans in time order (possibly none).
    pub wifi: Vec<WifiScan>,
    /// GNSS fixes in time order (possibly none).
    pub gnss: Vec<GpsFix>,
    /// Ground-truth positions in time order (possibly none).
    pub positions: Vec<IpinPosition>,
    /// Counts.
    pub summary: IpinLogSummary,
}

/// Ground-truth positions as waypoints in `frame`'s metres, the floor number as level.
#[must_use]
pub fn positions_to_waypoints(positions: &[IpinPosition], frame: &LocalFrame) -> Vec<Waypoint> {
    positions
        .iter()
        .map(|p| {
            let (x, y) = frame.to_local(p.lon, p.lat);
            Waypoint {
                t: p.t,
                x,
                y,
                level: Some(p.floor),
            }
        })
        .collect()
}

impl IpinLog {
    /// The frame of the log's waypoints: `origin` when given, else the first ground-truth
    /// position's; `None` when neither is there.
    #[must_use]
    pub fn waypoint_frame(&self, origin: Option<LocalFrame>) -> Option<LocalFrame> {
        origin.or_else(|| {
            self.positions
                .first()
                .and_then(|p| LocalFrame::new(p.lat, p.lon))
        })
    }

    /// The ground-truth positions as waypoints in `frame`'s metres; `None` without a frame
    /// or without positions.
    #[must_use]
    pub fn waypoints(&self, frame: Option<&LocalFrame>) -> Option<Vec<Waypoint>> {
        let frame = frame.filter(|_| !self.positions.is_empty())?;
        Some(positions_to_waypoints(&self.positions, frame))
    }
}

/// The state of a read.
#[derive(Default)]
struct Reader {
    imu: ImuStreams,
    /// Per scan time (ms): reading, sensor timestamp (s).
    scans: BTreeMap<i64, Vec<(WifiReading, f64)>>,
    latest_scan: Option<(f64, usize)>,
    gnss: SensorStream<3>,
    gnss_default_accuracy: usize,
    posi: SensorStream<4>,
    rows: BTreeMap<String, usize>,
    skipped: BTreeMap<String, usize>,
    ssids_blanked: usize,
}

/// Reads an IPIN logfile. Errors name the file and line.
///
/// # Errors
///
/// * [`Error::Config`] naming `ipin.max_wifi_age_s` when it is not a positive, finite number
///   of seconds.
/// * [`Error::Io`] when `path` cannot be read.
/// * [`Error::Parse`] naming the line: a line that is not `TAG;AppTimestamp;...`, a converted
///   tag with the wrong number of fields, a value that is not a finite number, a negative
///   time, a value out of range (sensor axes, pressure, rotation vector, GNSS fix, POSI
///   position, floor or building), a WIFI line without a MAC address, or a line more than
///   [`REORDER_TOLERANCE_S`](super::sensor_streams::REORDER_TOLERANCE_S) before the same
///   sensor's previous line.
/// * [`Error::Parse`] on the file: no data lines, no ACCE or GYRO lines; or samples that do not
///   make an [`ImuRecording`] (named by the ACCE line).
pub fn read_ipin_log(path: &Path, config: &IpinImportConfig) -> Result<IpinLog> {
    if !(config.max_wifi_age_s.is_finite() && config.max_wifi_age_s > 0.0) {
        return Err(crate::error::Error::config(
            "ipin.max_wifi_age_s",
            config.max_wifi_age_s.to_string(),
            "must be a positive number of seconds",
        ));
    }
    let mut reader = Reader::default();
    let seen = read_log_lines(path, '%', |_| {}, |raw, line| reader.read_line(raw, line))?;
    if reader.rows.is_empty() {
        return Err(Error::parse(
            path,
            0,
            "no data lines (`TAG;AppTimestamp;...`): is this an IPIN competition logfile?",
        ));
    }
    reader.finish(path, config, seen)
}

/// An integer-valued field.
fn integer(field: &str, what: &str) -> Result<i32, String> {
    let v = number(field, what)?;
    if v.fract() != 0.0 || v.abs() > 1e6 {
        return Err(format!("{what} `{field}` is not an integer"));
    }
    Ok(v as i32)
}

impl Reader {
    fn read_line(&mut self, raw: &str, line: usize) -> Result<(), String> {
        let mut fields: Vec<&str> = raw.split(';').collect();
        while fields.len() > 1 && fields.last().is_some_and(|f| f.trim().is_empty()) {
            fields.pop();
        }
        let tag = fields[0].trim();
        if !(2..=8).contains(&tag.len())
            || !tag
                .chars()
                .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit())
        {
            return Err(format!(
                "expected `TAG;AppTimestamp;...` (e.g. ACCE, WIFI, POSI), found `{}`",
                raw.chars().take(40).collect::<String>()
            ));
        }
        let n = fields.len();
        let counts = |allowed: &[usize]| -> Result<(), String> {
            if allowed.contains(&n) {
                Ok(())
            } else {
                let list: Vec<String> = allowed.iter().map(usize::to_string).collect();
                Err(format!(
                    "{tag} line has {n} fields, expected {} (line cut short?)",
                    list.join(" or ")
                ))
            }
        };
        let time = |i: usize| -> Result<f64, String> {
            let t = number(fields[i], "timestamp")?;
            if t < 0.0 {
                return Err(format!("timestamp {t} s is negative"));
            }
            Ok(t)
        };
        let order = |e: String| format!("{tag}: {e}");
        match tag {
            "ACCE" | "GYRO" | "MAGN" => {
                counts(&[6, 7])?;
                let t = time(1)?;
                let (what, max, stream) = match tag {
                    "ACCE" => ("acceleration", MAX_ACCEL, &mut self.imu.accel),
                    "GYRO" => ("angular rate", MAX_GYRO, &mut self.imu.gyro),
                    _ => ("magnetic field", MAX_MAG, &mut self.imu.mag),
                };
                let v = axes(&fields[3..6], what, max)?;
                stream.push(t, v, line).map_err(order)?;
            }
            "PRES" => {
                counts(&[4, 5])?;
                let t = time(1)?;
                let p = number(fields[3], "pressure")?;
                if !PRESSURE_RANGE.contains(&p) {
                    return Err(format!(
                        "pressure {} mbar is outside [{}, {}] mbar",
                        crate::error::short_number(p),
                        PRESSURE_RANGE.start(),
                        PRESSURE_RANGE.end()
                    ));
                }
                self.imu.pressure.push(t, [p], line).map_err(order)?;
            }
            "AHRS" => {
                counts(&[9, 10])?;
                let t = time(1)?;
                axes(&fields[3..6], "pitch/roll/yaw", 360.0)?;
                let [x, y, z] = axes(&fields[6..9], "rotation vector", 1.05)?;
                let q = rotation_vector_quaternion(x, y, z)
                    .ok_or_else(|| "rotation vector (x, y, z) is longer than 1".to_string())?;
                self.imu.orientation.push(t, q, line).map_err(order)?;
            }
            "WIFI" => self.read_wifi(&fields, line)?,
            "GNSS" => {
                counts(&[9, 10, 11, 12])?;
                let t = time(1)?;
                let (lat, lon) = (
                    number(fields[3], "latitude")?,
                    number(fields[4], "longitude")?,
                );
                let mut accuracy = number(fields[7], "accuracy")?;
                if accuracy <= 0.0 {
                    accuracy = DEFAULT_ACCURACY;
                    self.gnss_default_accuracy += 1;
                }
                check_fix(
                    &GpsFix {
                        t,
                        lat,
                        lon,
                        accuracy,
                    },
                    None,
                )?;
                self.gnss
                    .push(t, [lat, lon, accuracy], line)
                    .map_err(order)?;
            }
            "POSI" => {
                counts(&[7])?;
                let t = time(1)?;
                let (lat, lon) = (
                    number(fields[3], "latitude")?,
                    number(fields[4], "longitude")?,
                );
                if lat.abs() > 90.0 || lon.abs() > 180.0 {
                    return Err(format!(
                        "position ({lat}, {lon}) is not a latitude and longitude"
                    ));
                }
                let floor = integer(fields[5], "floor ID")?;
                let building = integer(fields[6], "building ID")?;
                self.posi
                    .push(t, [lat, lon, f64::from(floor), f64::from(building)], line)
                    .map_err(order)?;
            }
            other => {
                *self.skipped.entry(other.to_string()).or_default() += 1;
            }
        }
        *self.rows.entry(tag.to_string()).or_default() += 1;
        Ok(())
    }

    /// `WIFI;AppTs;SensorTs;SSID;BSSID;[Frequency;]RSS`; an SSID may itself hold `;`, so the
    /// fields are taken from the end: the BSSID is the MAC address before the numbers.
    fn read_wifi(&mut self, fields: &[&str], line: usize) -> Result<(), String> {
        let n = fields.len();
        let malformed = || {
            format!(
                "WIFI line has {n} fields, expected `WIFI;AppTimestamp;SensorTimestamp;SSID;BSSID;[Frequency;]RSS`"
            )
        };
        // Counted before any field is taken from the end (a bare `WIFI;` has one field).
        if n < 6 {
            return Err(malformed());
        }
        let is_mac = |s: &str| normalise_bssid(s).is_some_and(|b| b.len() == 17 && b.contains(':'));
        let with_freq = n >= 7 && is_mac(fields[n - 3]);
        let bssid_at = if with_freq { n - 3 } else { n - 2 };
        if bssid_at < 4 || (!with_freq && !is_mac(fields[bssid_at])) {
            return Err(malformed());
        }
        let t = number(fields[1], "timestamp")?;
        let seen = number(fields[2], "sensor timestamp")?;
        if let Some((latest, latest_line)) = self.latest_scan
            && t < latest
        {
            if latest - t > super::sensor_streams::REORDER_TOLERANCE_S {
                return Err(format!(
                    "WIFI: time {t} s is before the scan at line {latest_line} ({latest} s)"
                ));
            }
        } else {
            self.latest_scan = Some((t, line));
        }
        let raw_ssid = fields[3..bssid_at].join(";");
        let mut ssid = Some(raw_ssid.trim().to_string()).filter(|s| !s.is_empty());
        if ssid.as_deref().is_some_and(|s| s.contains([',', '"'])) {
            ssid = None;
            self.ssids_blanked += 1;
        }
        let reading = WifiReading {
            bssid: normalise_bssid(fields[bssid_at]).ok_or("empty BSSID")?,
            rssi: number(fields[n - 1], "RSS")?,
            ssid,
            freq: if with_freq {
                Some(number(fields[n - 2], "frequency")?)
            } else {
                None
            },
        };
        check_reading(&reading)?;
        // Scans are keyed by the millisecond the app logged them (the app writes %.3f).
        let key = (t * 1000.0).round() as i64;
        self.scans.entry(key).or_default().push((reading, seen));
        Ok(())
    }

    fn finish(self, path: &Path, config: &IpinImportConfig, seen: LogLines) -> Result<IpinLog> {
        for (stream, tag, name) in [
            (&self.imu.accel, "ACCE", "accelerometer"),
            (&self.imu.gyro, "GYRO", "gyroscope"),
        ] {
            if stream.is_empty() {
                return Err(Error::parse(
                    path,
                    0,
                    format!(
                        "no {name} lines ({tag}): footslam needs the accelerometer and the gyroscope"
                    ),
                ));
            }
        }
        let mut channels = Vec::new();
        for (present, name) in [
            (!self.imu.mag.is_empty(), "magnetometer"),
            (!self.imu.orientation.is_empty(), "orientation"),
            (!self.imu.pressure.is_empty(), "pressure"),
        ] {
            if present {
                channels.push(name.to_string());
            }
        }
        let imu = assemble_imu(&self.imu).map_err(|(line, m)| Error::parse(path, line, m))?;
        let (mut dropped, mut readings) = (DroppedSightings::default(), 0);
        let mut wifi = Vec::with_capacity(self.scans.len());
        for (key, pending) in self.scans {
            let newest = pending.iter().map(|(_, s)| *s).fold(f64::MIN, f64::max);
            let sightings = pending.into_iter().map(|(r, s)| (r, Some(s))).collect();
            // The newest reading is never stale, so a scan keeps at least one.
            let kept = fresh_readings(sightings, newest, config.max_wifi_age_s, &mut dropped);
            readings += kept.len();
            wifi.push(WifiScan {
                t: key as f64 / 1000.0,
                readings: kept,
            });
        }
        let mut gnss: Vec<GpsFix> = Vec::new();
        let mut gnss_duplicates = 0;
        for (t, [lat, lon, accuracy], _) in self.gnss.rows_sorted() {
            if gnss.last().is_some_and(|f| f.t == t) {
                gnss_duplicates += 1;
                continue;
            }
            gnss.push(GpsFix {
                t,
                lat,
                lon,
                accuracy,
            });
        }
        let positions: Vec<IpinPosition> = self
            .posi
            .rows_sorted()
            .into_iter()
            .map(|(t, [lat, lon, floor, building], _)| IpinPosition {
                t,
                lat,
                lon,
                floor: floor as i32,
                building: building as i32,
            })
            .collect();
        let reordered = self.imu.reordered() + self.gnss.reordered() + self.posi.reordered();
        let summary = IpinLogSummary {
            lines: seen,
            rows: self.rows,
            imu: imu.report().clone(),
            imu_channels: channels,
            reordered_rows: reordered,
            wifi_scans: wifi.len(),
            wifi_readings: readings,
            stale_readings_dropped: dropped.stale,
            max_wifi_age_s: config.max_wifi_age_s,
            duplicate_bssids_dropped: dropped.duplicates,
            ssids_blanked: self.ssids_blanked,
            gnss_fixes: gnss.len(),
            gnss_duplicates_dropped: gnss_duplicates,
            gnss_default_accuracy: self.gnss_default_accuracy,
            positions: positions.len(),
            skipped_tags: self.skipped,
        };
        Ok(IpinLog {
            imu,
            wifi,
            gnss,
            positions,
            summary,
        })
    }
}

/// A synthetic logfile in the app's format: `seconds` of 50 Hz inertial lines, 10 Hz AHRS
/// and pressure, a WiFi scan per second (one reading stale), 1 Hz GNSS, a POSI every 2 s,
/// and light and sound lines; walking east at 1 m/s from (`lat`, `lon`). For tests and
/// examples.
#[must_use]
pub fn synthetic_ipin_log(seconds: u32, lat: f64, lon: f64) -> String {
    use std::fmt::Write as _;
    let mut s = String::from(
        "% LogFile created by the 'GetSensorData' App for Android.\n\
         % Phone used for this logfile:\n% Model: \tsynthetic\n%\n",
    );
    let metres_per_degree_lon = 111_320.0 * lat.to_radians().cos();
    let steps = seconds * 50;
    for k in 0..steps {
        let t = f64::from(k) * 0.02;
        let st = 1000.0 + t;
        let phase = t * 2.0 * std::f64::consts::PI * 1.8;
        let _ = writeln!(
            s,
            "ACCE;{t:.3};{st:.3};{:.5};{:.5};{:.5};3",
            0.3 * phase.sin(),
            0.2,
            9.81 + 1.5 * phase.sin()
        );
        let _ = writeln!(
            s,
            "GYRO;{:.3};{st:.3};{:.5};{:.5};0.01000;3",
            t + 0.004,
            0.05 * phase.cos(),
            -0.02
        );
        let _ = writeln!(s, "MAGN;{:.3};{st:.3};21.5;4.2;-38.9;3", t + 0.006);
        if k % 5 == 0 {
            let _ = writeln!(
                s,
                "AHRS;{:.3};{st:.3};1.2;-0.8;90.0;0.01;-0.005;0.70710678;3",
                t + 0.008
            );
            let _ = writeln!(s, "PRES;{:.3};{st:.3};1013.25;3", t + 0.009);
            let _ = writeln!(s, "LIGH;{:.3};{st:.3};120.0;0", t + 0.009);
        }
        if k % 50 == 25 {
            let scan_t = t + 0.011;
            let seen = 5000.0 + scan_t;
            let _ = writeln!(
                s,
                "WIFI;{scan_t:.3};{seen:.3};lab;00:11:22:33:44:55;2412;-55"
            );
            let _ = writeln!(
                s,
                "WIFI;{scan_t:.3};{:.3};lab-5g;00:11:22:33:44:56;5180;-67",
                seen - 0.4
            );
            let _ = writeln!(
                s,
                "WIFI;{scan_t:.3};{:.3};old;00:11:22:33:44:57;2437;-80",
                seen - 9.0
            );
            let _ = writeln!(s, "SOUN;{scan_t:.3};0.01;0.02;45.0");
            let x = scan_t;
            let _ = writeln!(
                s,
                "GNSS;{scan_t:.3};{:.3};{lat:.8};{:.8};410.0;90.0;12.0;1.0;{:.0};9;7",
                1_600_000_000.0 + scan_t,
                lon + x / metres_per_degree_lon,
                1_600_000_000_000.0 + scan_t * 1000.0
            );
        }
        if k % 100 == 0 {
            let x = t;
            let _ = writeln!(
                s,
                "POSI;{t:.3};{};{lat:.8};{:.8};0;1",
                k / 100 + 1,
                lon + x / metres_per_degree_lon
            );
        }
    }
    s
}

#[cfg(test)]
mod tests;
