//! Separately clocked sensor streams of a phone log, put onto the accelerometer's clock as
//! one [`ImuRecording`] (shared by the public-dataset importers: [`super::ilc_trace`],
//! [`super::ipin_log`]).
//!
//! Phone loggers write each sensor's rows as they arrive, interleaved and sometimes a few
//! milliseconds out of order. A [`SensorStream`] collects one sensor's rows with their file
//! lines: a row may come up to [`REORDER_TOLERANCE_S`] before its stream's previous row (it
//! is sorted into place and counted); a row further back is an error naming its line.
//! Interleaving between streams is free.
//!
//! [`assemble_imu`] takes the accelerometer's times as the recording's clock (rows repeating
//! a time are dropped and counted) and gives each sample the gyroscope, magnetometer and
//! pressure linearly interpolated at that time, and the orientation normalised-linearly
//! interpolated (nlerp, sign-aligned); before a stream's first row or after its last, its
//! end value is held.

use crate::sensor::imu::{ImuRecording, ImuSample};

/// A row may come this long before its stream's previous row and is sorted into place,
/// seconds; a row further back is an error.
pub const REORDER_TOLERANCE_S: f64 = 0.05;

/// One sensor's rows: times (seconds), values and the 1-based file line of each.
#[derive(Debug, Clone, Default)]
pub struct SensorStream<const N: usize> {
    rows: Vec<(f64, [f64; N], usize)>,
    reordered: usize,
    /// The latest time so far and its line.
    latest: Option<(f64, usize)>,
}

impl<const N: usize> SensorStream<N> {
    /// Adds a row; the error says why it is out of order (the caller names the line).
    ///
    /// # Errors
    ///
    /// A message when `t` or a value is NaN or infinite, or `t` is more than
    /// [`REORDER_TOLERANCE_S`] before the latest time so far (naming that row's line).
    pub fn push(&mut self, t: f64, value: [f64; N], line: usize) -> Result<(), String> {
        if !t.is_finite() || value.iter().any(|v| !v.is_finite()) {
            return Err("values must be finite numbers (found NaN or infinity)".into());
        }
        if let Some((last, last_line)) = self.latest
            && t < last
        {
            if last - t > REORDER_TOLERANCE_S {
                return Err(format!(
                    "time {t} s is {:.3} s before the same sensor's row at line {last_line} \
                     ({last} s); rows of one sensor may be out of order by at most \
                     {REORDER_TOLERANCE_S} s",
                    last - t
                ));
            }
            self.reordered += 1;
        } else {
            self.latest = Some((t, line));
        }
        self.rows.push((t, value, line));
        Ok(())
    }

    /// Number of rows.
    #[must_use]
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// True when the stream has no rows.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// Rows that came before their predecessor (within the tolerance) and were sorted.
    #[must_use]
    pub fn reordered(&self) -> usize {
        self.reordered
    }

    /// The rows `(t, value, line)` sorted by time (stable: rows sharing a time keep their
    /// file order).
    #[must_use]
    pub fn rows_sorted(&self) -> Vec<(f64, [f64; N], usize)> {
        let mut rows = self.rows.clone();
        if self.reordered > 0 {
            rows.sort_by(|a, b| a.0.total_cmp(&b.0));
        }
        rows
    }
}

/// An optional stream evaluated at increasing times (a cursor walks it once).
struct Resampler<const N: usize> {
    rows: Vec<(f64, [f64; N], usize)>,
    next: usize,
}

impl<const N: usize> Resampler<N> {
    fn new(stream: &SensorStream<N>) -> Self {
        Self {
            rows: stream.rows_sorted(),
            next: 0,
        }
    }

    /// The two rows around `t` and the weight of the second (0 before the first row, 1
    /// after the last). `t` must not decrease between calls.
    fn bracket(&mut self, t: f64) -> Option<([f64; N], [f64; N], f64)> {
        let rows = &self.rows;
        let (first, last) = (rows.first()?, rows.last()?);
        if t <= first.0 {
            return Some((first.1, first.1, 0.0));
        }
        if t >= last.0 {
            return Some((last.1, last.1, 1.0));
        }
        while self.next < rows.len() && rows[self.next].0 < t {
            self.next += 1;
        }
        // rows[next - 1].0 < t <= rows[next].0, both exist by the checks above.
        let (a, b) = (&rows[self.next - 1], &rows[self.next]);
        let w = if b.0 > a.0 {
            (t - a.0) / (b.0 - a.0)
        } else {
            1.0
        };
        Some((a.1, b.1, w))
    }

    fn linear(&mut self, t: f64) -> Option<[f64; N]> {
        let (a, b, w) = self.bracket(t)?;
        Some(std::array::from_fn(|i| a[i] + w * (b[i] - a[i])))
    }
}

/// Normalised linear interpolation of unit quaternions `[x, y, z, w]`, the shorter way.
fn nlerp(a: [f64; 4], b: [f64; 4], w: f64) -> [f64; 4] {
    let dot: f64 = a.iter().zip(&b).map(|(p, q)| p * q).sum();
    let sign = if dot < 0.0 { -1.0 } else { 1.0 };
    let q: [f64; 4] = std::array::from_fn(|i| a[i] + w * (sign * b[i] - a[i]));
    let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    if norm > 0.0 { q.map(|v| v / norm) } else { a }
}

/// The unit quaternion `[x, y, z, w]` of an Android rotation vector's `x, y, z`, with
/// `w = sqrt(max(0, 1 − x² − y² − z²))`; `None` when `|(x, y, z)|` exceeds 1 by more than
/// 5 % (not a rotation vector).
#[must_use]
pub fn rotation_vector_quaternion(x: f64, y: f64, z: f64) -> Option<[f64; 4]> {
    let n2 = x * x + y * y + z * z;
    if !(n2.is_finite() && n2 <= 1.05 * 1.05) {
        return None;
    }
    let w = (1.0 - n2).max(0.0).sqrt();
    let norm = (n2 + w * w).sqrt();
    Some([x / norm, y / norm, z / norm, w / norm])
}

/// The streams of one phone log, ready to become an [`ImuRecording`].
#[derive(Debug, Default)]
pub struct ImuStreams {
    /// Specific force, m/s²: the recording's clock.
    pub accel: SensorStream<3>,
    /// Angular rate, rad/s.
    pub gyro: SensorStream<3>,
    /// Magnetic field, µT (optional: empty when not logged).
    pub mag: SensorStream<3>,
    /// Orientation sensor → ENU, `[x, y, z, w]` (optional).
    pub orientation: SensorStream<4>,
    /// Air pressure, hPa (optional).
    pub pressure: SensorStream<1>,
}

impl ImuStreams {
    /// Rows sorted into place across all streams.
    #[must_use]
    pub fn reordered(&self) -> usize {
        self.accel.reordered()
            + self.gyro.reordered()
            + self.mag.reordered()
            + self.orientation.reordered()
            + self.pressure.reordered()
    }
}

/// The recording on the accelerometer's clock. Accelerometer and gyroscope must have rows
/// (the caller says which is missing: this returns `Err((0, message))` then); other errors
/// carry the 1-based line of the accelerometer row whose sample is invalid.
///
/// # Errors
///
/// `(0, message)` when the accelerometer or the gyroscope has no rows; else `(line, message)`
/// when the samples do not make an [`ImuRecording`] ([`ImuRecording::new`]: a value out of
/// range, fewer than two samples, a median acceleration not gravity's, a sampling rate no IMU
/// has), `line` being the accelerometer row of the sample at fault (the first row for a fault
/// of the whole recording).
pub fn assemble_imu(streams: &ImuStreams) -> Result<ImuRecording, (usize, String)> {
    for (stream, name) in [
        (&streams.accel, "accelerometer"),
        (&streams.gyro, "gyroscope"),
    ] {
        if stream.is_empty() {
            return Err((
                0,
                format!("no {name} rows: an IMU recording needs both accelerometer and gyroscope"),
            ));
        }
    }
    let accel = streams.accel.rows_sorted();
    let mut gyro = Resampler::new(&streams.gyro);
    let mut mag = Resampler::new(&streams.mag);
    let mut orientation = Resampler::new(&streams.orientation);
    let mut pressure = Resampler::new(&streams.pressure);
    let mut samples: Vec<ImuSample> = Vec::with_capacity(accel.len());
    let mut lines: Vec<usize> = Vec::with_capacity(accel.len());
    let mut duplicates = 0;
    for &(t, a, line) in &accel {
        if samples.last().is_some_and(|s| s.t == t) {
            duplicates += 1;
            continue;
        }
        let gyro = gyro
            .linear(t)
            .ok_or((line, "no gyroscope rows".to_string()))?;
        samples.push(ImuSample {
            t,
            accel: a,
            gyro,
            mag: mag.linear(t),
            orientation: orientation.bracket(t).map(|(p, q, w)| nlerp(p, q, w)),
            pressure: pressure.linear(t).map(|[p]| p),
        });
        lines.push(line);
    }
    ImuRecording::new(samples, duplicates).map_err(|(i, m)| (lines.get(i).copied().unwrap_or(0), m))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_interpolated_onto_the_accelerometer_clock() {
        let mut s = ImuStreams::default();
        for (i, t) in [0.0, 0.02, 0.02, 0.04].iter().enumerate() {
            s.accel.push(*t, [0.0, 0.0, 9.8], i + 1).expect("push");
        }
        s.gyro.push(0.01, [0.1, 0.0, 0.0], 10).expect("push");
        s.gyro.push(0.03, [0.3, 0.0, 0.0], 11).expect("push");
        s.pressure.push(0.0, [1000.0], 12).expect("push");
        s.pressure.push(0.04, [1001.0], 13).expect("push");
        let q = rotation_vector_quaternion(0.0, 0.0, (0.5f64).sin()).expect("q");
        s.orientation
            .push(0.0, [0.0, 0.0, 0.0, 1.0], 14)
            .expect("push");
        s.orientation.push(0.04, q, 15).expect("push");
        let r = assemble_imu(&s).expect("valid");
        let g: Vec<f64> = r.samples().iter().map(|x| x.gyro[0]).collect();
        // Held before the first row (0.1), interpolated (0.2), held after the last (0.3).
        assert!(
            (g[0] - 0.1).abs() < 1e-12 && (g[1] - 0.2).abs() < 1e-12 && (g[2] - 0.3).abs() < 1e-12
        );
        assert_eq!(r.report().duplicate_times, 1);
        assert!((r.samples()[1].pressure.expect("p") - 1000.5).abs() < 1e-9);
        assert!(!r.has_magnetometer());
        // Halfway between identity and a 1 rad yaw: a 0.5 rad yaw.
        let mid = r.samples()[1].orientation.expect("q");
        assert!((mid[2] - (0.25f64).sin()).abs() < 1e-9 && (mid[3] - (0.25f64).cos()).abs() < 1e-9);
    }

    #[test]
    fn small_reorders_are_sorted_and_large_ones_refused() {
        let mut s = SensorStream::<1>::default();
        s.push(1.0, [1.0], 1).expect("push");
        s.push(0.98, [2.0], 2).expect("within tolerance");
        assert_eq!(s.reordered(), 1);
        assert_eq!(s.rows_sorted()[0].0, 0.98);
        let e = s.push(0.5, [3.0], 3).unwrap_err();
        assert!(e.contains("line 1"), "{e}");
        assert!(s.push(2.0, [f64::NAN], 4).is_err());
    }

    #[test]
    fn missing_gyroscope_is_named() {
        let mut s = ImuStreams::default();
        s.accel.push(0.0, [0.0, 0.0, 9.8], 1).expect("push");
        let (line, m) = assemble_imu(&s).unwrap_err();
        assert_eq!(line, 0);
        assert!(m.contains("gyroscope"), "{m}");
    }

    #[test]
    fn rotation_vectors_become_unit_quaternions() {
        let q = rotation_vector_quaternion(0.0, 0.0, 0.6).expect("q");
        assert!((q[3] - 0.8).abs() < 1e-12);
        assert!(rotation_vector_quaternion(1.0, 1.0, 0.0).is_none());
        let q = rotation_vector_quaternion(0.0, 0.0, 1.01).expect("within 5 %");
        assert!((q[2] - 1.0).abs() < 1e-12 && q[3] == 0.0);
    }
}
