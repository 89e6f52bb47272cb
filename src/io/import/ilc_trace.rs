//! Traces of the Microsoft Indoor Location Competition 2.0 (ILC; sample data and format at
//! github.com/location-competition/indoor-location-competition-20, MIT licence, © XYZ10
//! Inc.): one smartphone walk per text file, tab-separated, `#` lines are headers (site,
//! floor, phone, sensor specs), data rows `unix_ms TYPE values...`.
//!
//! Converted:
//! * `TYPE_ACCELEROMETER ax ay az [accuracy]` (m/s², gravity included): the IMU's clock,
//!   `t = unix_ms / 1000` seconds (f64); `TYPE_GYROSCOPE` (rad/s), `TYPE_MAGNETIC_FIELD`
//!   (µT) and `TYPE_ROTATION_VECTOR` (device → east-north-up) are interpolated onto it (see
//!   [`super::sensor_streams`]). A calibrated `TYPE_X` is preferred; when a trace has only
//!   `TYPE_X_UNCALIBRATED x y z [bx by bz [accuracy]]`, its values minus the estimated bias
//!   are used (Android's definition). The rotation vector's fourth value is its `w` when
//!   `x² + y² + z² + v²` is 1 within 0.02, else its accuracy (the sample data logs
//!   `x y z accuracy`); a missing `w` is `sqrt(max(0, 1 − x² − y² − z²))`.
//! * `TYPE_WIFI ssid bssid rssi frequency last_seen_ms`: rows sharing `unix_ms` are one scan
//!   at `t = unix_ms / 1000`. Android hands out cached results, so a reading whose
//!   `last_seen` is more than [`IlcImportConfig::max_wifi_age_s`] before the scan is stale
//!   and dropped (counted); so is a scan left empty. In the sample data fresh readings are
//!   0.2–2.3 s old (a scan's sweep) and the next mode starts at one scan period, ~2.3 s,
//!   hence the default 2.5 s. A BSSID twice in one scan keeps its freshest reading; an SSID
//!   holding a comma or quote is blanked (wifi.csv cannot hold it).
//! * `TYPE_WAYPOINT x y`: ground truth in the floor's metre frame ([`Waypoint`], no level).
//!
//! Skipped and counted: iBeacon and Bluetooth rows, the `DIST` rows, accuracy changes, the
//! uncalibrated rows of a sensor whose calibrated rows exist, and any unknown `TYPE_*`.
//!
//! Strictness: a malformed row (too few or too many values, a non-number, NaN, a value out
//! of the sensor's range) is an error naming the file and line. An unterminated last line,
//! which a logger cut short (perhaps mid-number), is never used: it is skipped and reported
//! ([`IlcTraceSummary::truncated_last_line`]). Rows of different sensors interleave freely;
//! one sensor's rows may be out of order by up to
//! [`super::sensor_streams::REORDER_TOLERANCE_S`] (sorted, counted), further is an error. A
//! trace without accelerometer or gyroscope rows is an error naming the missing sensor.

use super::log_lines::{LogLines, axes, number, read_log_lines};
use super::sensor_streams::{ImuStreams, SensorStream, assemble_imu, rotation_vector_quaternion};
use super::wifi_sightings::{DroppedSightings, fresh_readings};
use crate::error::{Error, Result};
use crate::io::waypoints_csv::Waypoint;
use crate::sensor::imu::{ImuRecording, MAX_ACCEL, MAX_GYRO, MAX_MAG, SamplingReport};
use crate::sensor::wifi::{WifiReading, WifiScan, check_reading, normalise_bssid};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// The importer's settings; every default in one place.
///
/// | field            | default | meaning                                                  |
/// |------------------|---------|----------------------------------------------------------|
/// | `max_wifi_age_s` | 2.5 s   | readings last seen longer before their scan are dropped  |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct IlcImportConfig {
    /// A WiFi reading whose `last_seen` is more than this before its scan is stale, seconds.
    pub max_wifi_age_s: f64,
}

impl Default for IlcImportConfig {
    fn default() -> Self {
        Self {
            max_wifi_age_s: 2.5,
        }
    }
}

impl IlcImportConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] naming `ilc.max_wifi_age_s` when it is not a positive, finite number of
    /// seconds.
    pub fn validate(&self) -> Result<()> {
        if self.max_wifi_age_s.is_finite() && self.max_wifi_age_s > 0.0 {
            Ok(())
        } else {
            Err(crate::error::Error::config(
                "ilc.max_wifi_age_s",
                self.max_wifi_age_s.to_string(),
                "must be a positive number of seconds",
            ))
        }
    }
}

/// What an import read, kept and dropped.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IlcTraceSummary {
    /// Lines in the file.
    pub lines: usize,
    /// `#` header lines.
    pub header_lines: usize,
    /// Empty lines.
    pub blank_lines: usize,
    /// The header's `SiteID`, when given.
    pub site_id: Option<String>,
    /// The header's `FloorName`, when given.
    pub floor_name: Option<String>,
    /// The header's `Brand Model`, when given.
    pub device: Option<String>,
    /// Data rows per `TYPE_*`.
    pub rows: BTreeMap<String, usize>,
    /// The row types behind the IMU channels (`accelerometer`, `gyroscope`, `magnetometer`,
    /// `orientation`).
    pub imu_sources: BTreeMap<String, String>,
    /// The IMU recording's sampling (samples kept, rate, duplicate times dropped, gaps).
    pub imu: SamplingReport,
    /// Sensor rows out of order (within the tolerance) and sorted into place.
    pub reordered_rows: usize,
    /// WiFi scans kept.
    pub wifi_scans: usize,
    /// WiFi readings kept.
    pub wifi_readings: usize,
    /// WiFi readings dropped as stale (last seen more than `max_wifi_age_s` before the scan).
    pub stale_readings_dropped: usize,
    /// The staleness limit used, seconds.
    pub max_wifi_age_s: f64,
    /// Scans dropped because every reading was stale.
    pub empty_scans_dropped: usize,
    /// Readings dropped for repeating a BSSID within a scan (the freshest is kept).
    pub duplicate_bssids_dropped: usize,
    /// SSIDs blanked for holding a comma or quote.
    pub ssids_blanked: usize,
    /// Waypoints kept.
    pub waypoints: usize,
    /// Rows of known types that footslam does not convert, per type.
    pub not_converted: BTreeMap<String, usize>,
    /// Rows of unknown `TYPE_*`, skipped, per type.
    pub unknown_types: BTreeMap<String, usize>,
    /// The 1-based number of an unterminated last line, skipped (it may be cut short).
    pub truncated_last_line: Option<usize>,
}

/// One converted trace.
#[derive(Debug, Clone)]
pub struct IlcTrace {
    /// The inertial recording on the accelerometer's clock.
    pub imu: ImuRecording,
    /// WiFi scans, in time order (possibly none).
    pub wifi: Vec<WifiScan>,
    /// Ground-truth waypoints, in time order (possibly none).
    pub waypoints: Vec<Waypoint>,
    /// Counts.
    pub summary: IlcTraceSummary,
}

/// Known row types that are not converted.
const NOT_CONVERTED: [&str; 7] = [
    "TYPE_BEACON",
    "TYPE_BLUE",
    "TYPE_BLU4",
    "TYPE_DIST1",
    "TYPE_DIST2",
    "TYPE_SENSOR_MAGNETIC_FIELD_ACCURACY_CHANGED",
    "TYPE_GAME_ROTATION_VECTOR",
];

/// The row types of one 3-axis sensor: calibrated and uncalibrated.
#[derive(Default)]
struct Axes {
    calibrated: SensorStream<3>,
    uncalibrated: SensorStream<3>,
}

impl Axes {
    /// The calibrated rows when there are any, else the uncalibrated ones; with the name of
    /// the type used and the count of rows not used.
    fn choose(self, name: &str) -> (SensorStream<3>, Option<String>, usize) {
        if !self.calibrated.is_empty() {
            let unused = self.uncalibrated.len();
            (self.calibrated, Some(name.to_string()), unused)
        } else if !self.uncalibrated.is_empty() {
            (self.uncalibrated, Some(format!("{name}_UNCALIBRATED")), 0)
        } else {
            (SensorStream::default(), None, 0)
        }
    }
}

/// One scan's readings while reading: reading, last seen (ms), line.
type PendingScan = Vec<(WifiReading, Option<i64>)>;

/// The state of a read.
#[derive(Default)]
struct Reader {
    accel: Axes,
    gyro: Axes,
    mag: Axes,
    orientation: SensorStream<4>,
    waypoints: SensorStream<2>,
    scans: BTreeMap<i64, PendingScan>,
    latest_scan: Option<(i64, usize)>,
    rows: BTreeMap<String, usize>,
    not_converted: BTreeMap<String, usize>,
    unknown: BTreeMap<String, usize>,
    ssids_blanked: usize,
    header: BTreeMap<String, String>,
}

/// Reads an ILC trace file. Errors name the file and line.
///
/// # Errors
///
/// * [`Error::Config`] when `config` fails [`IlcImportConfig::validate`].
/// * [`Error::Io`] when `path` cannot be read.
/// * [`Error::Parse`] naming the line: a row that is not `unix_ms<TAB>TYPE_...`, a time that is
///   not Unix milliseconds, a converted type with the wrong number of values, a value that is
///   not a finite number or is beyond the sensor's range, a rotation vector not of unit length,
///   an empty BSSID, or a row more than
///   [`REORDER_TOLERANCE_S`](super::sensor_streams::REORDER_TOLERANCE_S) before the same
///   sensor's previous row.
/// * [`Error::Parse`] on the file: no data rows, no accelerometer or gyroscope rows; or samples
///   that do not make an [`ImuRecording`] (named by the accelerometer row's line).
pub fn read_ilc_trace(path: &Path, config: &IlcImportConfig) -> Result<IlcTrace> {
    config.validate()?;
    let mut reader = Reader::default();
    let mut header = BTreeMap::new();
    let seen = read_log_lines(
        path,
        '#',
        |rest| read_header(rest, &mut header),
        |raw, line| reader.read_row(raw, line),
    )?;
    reader.header = header;
    if reader.rows.is_empty() {
        return Err(Error::parse(
            path,
            0,
            "no data rows (`unix_ms TYPE values...`): is this an Indoor Location Competition trace?",
        ));
    }
    reader.finish(path, config, seen)
}

/// Collects a header line's `key:value` pairs.
fn read_header(rest: &str, header: &mut BTreeMap<String, String>) {
    for pair in rest.split('\t') {
        if let Some((k, v)) = pair.split_once(':') {
            header.insert(k.trim().to_string(), v.trim().to_string());
        }
    }
}

impl Reader {
    fn read_row(&mut self, raw: &str, line: usize) -> Result<(), String> {
        let fields: Vec<&str> = raw.split('\t').collect();
        let (Some(time), Some(kind)) = (fields.first(), fields.get(1)) else {
            return Err(format!(
                "expected `unix_ms<TAB>TYPE<TAB>values...`, found `{}`",
                raw.chars().take(60).collect::<String>()
            ));
        };
        let ms: i64 = time.trim().parse().map_err(|_| {
            format!("time `{time}` is not an integer number of milliseconds since 1970")
        })?;
        if !(0..=10_000_000_000_000).contains(&ms) {
            return Err(format!("time {ms} ms is not a Unix time in milliseconds"));
        }
        let kind = kind.trim();
        if !kind.starts_with("TYPE_") {
            return Err(format!("`{kind}` is not a row type (TYPE_...)"));
        }
        let t = ms as f64 / 1000.0;
        let mut values = &fields[2..];
        if kind != "TYPE_WIFI" {
            while values.last().is_some_and(|v| v.trim().is_empty()) {
                values = &values[..values.len() - 1];
            }
        }
        let counts = |allowed: &[usize]| -> Result<(), String> {
            if allowed.contains(&values.len()) {
                Ok(())
            } else {
                Err(format!(
                    "{kind} has {} values, expected {} (line cut short?)",
                    values.len(),
                    allowed
                        .iter()
                        .map(usize::to_string)
                        .collect::<Vec<_>>()
                        .join(" or ")
                ))
            }
        };
        let order = |e: String| format!("{kind}: {e}");
        match kind {
            "TYPE_ACCELEROMETER" | "TYPE_GYROSCOPE" | "TYPE_MAGNETIC_FIELD" => {
                counts(&[3, 4])?;
                let (what, max, target) = self.sensor(kind);
                let v = axes(values, what, max)?;
                target.calibrated.push(t, v, line).map_err(order)?;
            }
            "TYPE_ACCELEROMETER_UNCALIBRATED"
            | "TYPE_GYROSCOPE_UNCALIBRATED"
            | "TYPE_MAGNETIC_FIELD_UNCALIBRATED" => {
                counts(&[3, 6, 7])?;
                let base = kind.trim_end_matches("_UNCALIBRATED");
                let (what, max, target) = self.sensor(base);
                let raw = axes(values, what, max)?;
                let bias = if values.len() >= 6 {
                    axes(&values[3..6], &format!("{what} bias"), max)?
                } else {
                    [0.0; 3]
                };
                let v = std::array::from_fn(|i| raw[i] - bias[i]);
                target.uncalibrated.push(t, v, line).map_err(order)?;
            }
            "TYPE_ROTATION_VECTOR" => {
                counts(&[3, 4, 5])?;
                let [x, y, z] = axes(&values[..3], "rotation vector", 1.05)?;
                let given_w = match values.len() {
                    4 => {
                        let v = number(values[3], "rotation vector w or accuracy")?;
                        ((x * x + y * y + z * z + v * v) - 1.0)
                            .abs()
                            .le(&0.02)
                            .then_some(v)
                    }
                    5 => Some(number(values[3], "rotation vector w")?),
                    _ => None,
                };
                let q = match given_w {
                    Some(w) => {
                        let n = (x * x + y * y + z * z + w * w).sqrt();
                        if !(0.9..=1.1).contains(&n) {
                            return Err(format!(
                                "rotation vector (x, y, z, w) has norm {n:.3}, not 1"
                            ));
                        }
                        [x / n, y / n, z / n, w / n]
                    }
                    None => rotation_vector_quaternion(x, y, z)
                        .ok_or_else(|| "rotation vector (x, y, z) is longer than 1".to_string())?,
                };
                self.orientation.push(t, q, line).map_err(order)?;
            }
            "TYPE_WIFI" => {
                counts(&[4, 5])?;
                self.read_wifi(ms, values, line)?;
            }
            "TYPE_WAYPOINT" => {
                counts(&[2])?;
                let (x, y) = (number(values[0], "x")?, number(values[1], "y")?);
                if x.abs() > 1e6 || y.abs() > 1e6 {
                    return Err(format!("waypoint ({x}, {y}) is more than 1000 km away"));
                }
                self.waypoints.push(t, [x, y], line).map_err(order)?;
            }
            k if NOT_CONVERTED.contains(&k) => {
                *self.not_converted.entry(k.to_string()).or_default() += 1;
            }
            k => {
                *self.unknown.entry(k.to_string()).or_default() += 1;
            }
        }
        *self.rows.entry(kind.to_string()).or_default() += 1;
        Ok(())
    }

    /// The name, range and streams of the 3-axis sensor behind a calibrated type name.
    fn sensor(&mut self, kind: &str) -> (&'static str, f64, &mut Axes) {
        match kind {
            "TYPE_ACCELEROMETER" => ("acceleration", MAX_ACCEL, &mut self.accel),
            "TYPE_GYROSCOPE" => ("angular rate", MAX_GYRO, &mut self.gyro),
            _ => ("magnetic field", MAX_MAG, &mut self.mag),
        }
    }

    fn read_wifi(&mut self, ms: i64, values: &[&str], line: usize) -> Result<(), String> {
        if let Some((latest, latest_line)) = self.latest_scan
            && ms < latest
        {
            if (latest - ms) as f64 / 1000.0 > super::sensor_streams::REORDER_TOLERANCE_S {
                return Err(format!(
                    "TYPE_WIFI: time {ms} ms is before the scan at line {latest_line} ({latest} ms)"
                ));
            }
        } else {
            self.latest_scan = Some((ms, line));
        }
        let bssid = normalise_bssid(values[1])
            .ok_or_else(|| format!("bssid `{}` is empty or holds a comma or quote", values[1]))?;
        let mut ssid = Some(values[0].trim().to_string()).filter(|s| !s.is_empty());
        if ssid.as_deref().is_some_and(|s| s.contains([',', '"'])) {
            ssid = None;
            self.ssids_blanked += 1;
        }
        let reading = WifiReading {
            bssid,
            rssi: number(values[2], "rssi")?,
            ssid,
            freq: Some(number(values[3], "frequency")?),
        };
        check_reading(&reading)?;
        let last_seen = match values.get(4) {
            Some(v) => Some(v.trim().parse::<i64>().map_err(|_| {
                format!("last_seen `{v}` is not an integer number of milliseconds")
            })?),
            None => None,
        };
        self.scans.entry(ms).or_default().push((reading, last_seen));
        Ok(())
    }

    fn finish(self, path: &Path, config: &IlcImportConfig, seen: LogLines) -> Result<IlcTrace> {
        let mut not_converted = self.not_converted;
        let mut sources = BTreeMap::new();
        let mut streams = ImuStreams::default();
        let mut reordered = 0;
        for (axes, name, channel, slot) in [
            (
                self.accel,
                "TYPE_ACCELEROMETER",
                "accelerometer",
                &mut streams.accel,
            ),
            (self.gyro, "TYPE_GYROSCOPE", "gyroscope", &mut streams.gyro),
            (
                self.mag,
                "TYPE_MAGNETIC_FIELD",
                "magnetometer",
                &mut streams.mag,
            ),
        ] {
            reordered += axes.calibrated.reordered() + axes.uncalibrated.reordered();
            let (stream, source, unused) = axes.choose(name);
            if unused > 0 {
                not_converted.insert(format!("{name}_UNCALIBRATED"), unused);
            }
            if let Some(source) = source {
                sources.insert(channel.to_string(), source);
            }
            *slot = stream;
        }
        for (channel, name) in [
            ("accelerometer", "TYPE_ACCELEROMETER"),
            ("gyroscope", "TYPE_GYROSCOPE"),
        ] {
            if !sources.contains_key(channel) {
                return Err(Error::parse(
                    path,
                    0,
                    format!(
                        "no {channel} rows ({name} or {name}_UNCALIBRATED): footslam needs the \
                         accelerometer and the gyroscope"
                    ),
                ));
            }
        }
        if !self.orientation.is_empty() {
            sources.insert("orientation".into(), "TYPE_ROTATION_VECTOR".into());
        }
        reordered += self.orientation.reordered() + self.waypoints.reordered();
        streams.orientation = self.orientation;
        let imu = assemble_imu(&streams).map_err(|(line, m)| Error::parse(path, line, m))?;

        let max_age_ms = config.max_wifi_age_s * 1000.0;
        let (mut dropped, mut empty, mut readings) = (DroppedSightings::default(), 0, 0);
        let mut wifi = Vec::with_capacity(self.scans.len());
        for (ms, pending) in self.scans {
            let sightings = pending
                .into_iter()
                .map(|(r, seen)| (r, seen.map(|s| s as f64)))
                .collect();
            let kept = fresh_readings(sightings, ms as f64, max_age_ms, &mut dropped);
            if kept.is_empty() {
                empty += 1;
                continue;
            }
            readings += kept.len();
            wifi.push(WifiScan {
                t: ms as f64 / 1000.0,
                readings: kept,
            });
        }
        let waypoints: Vec<Waypoint> = self
            .waypoints
            .rows_sorted()
            .into_iter()
            .map(|(t, [x, y], _)| Waypoint {
                t,
                x,
                y,
                level: None,
            })
            .collect();
        let header = self.header;
        let device = match (header.get("Brand"), header.get("Model")) {
            (Some(b), Some(m)) => Some(format!("{b} {m}")),
            (b, m) => b.or(m).cloned(),
        };
        let summary = IlcTraceSummary {
            lines: seen.lines,
            header_lines: seen.comment_lines,
            blank_lines: seen.blank_lines,
            site_id: header.get("SiteID").cloned(),
            floor_name: header.get("FloorName").cloned(),
            device,
            rows: self.rows,
            imu_sources: sources,
            imu: imu.report().clone(),
            reordered_rows: reordered,
            wifi_scans: wifi.len(),
            wifi_readings: readings,
            stale_readings_dropped: dropped.stale,
            max_wifi_age_s: config.max_wifi_age_s,
            empty_scans_dropped: empty,
            duplicate_bssids_dropped: dropped.duplicates,
            ssids_blanked: self.ssids_blanked,
            waypoints: waypoints.len(),
            not_converted,
            unknown_types: self.unknown,
            truncated_last_line: seen.truncated_last_line,
        };
        Ok(IlcTrace {
            imu,
            wifi,
            waypoints,
            summary,
        })
    }
}

#[cfg(test)]
mod tests;
