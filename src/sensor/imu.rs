//! Raw inertial recordings: accelerometer, gyroscope and, when logged, magnetometer,
//! orientation (Android's rotation vector) and barometer, sample by sample.
//!
//! Real logs are uneven: samples come late, twice or not at all. [`ImuRecording::new`] keeps
//! the samples in strictly increasing time (the readers drop exact duplicates before) and
//! measures the sampling in a [`SamplingReport`], so the step detectors integrate with each
//! sample's true `dt` and can break a stride at a gap.

use serde::{Deserialize, Serialize};

/// One IMU sample, in the sensor's own frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuSample {
    /// Time, seconds (any epoch; Unix seconds are fine: kept in f64).
    pub t: f64,
    /// Specific force (gravity included), m/s², sensor frame.
    pub accel: [f64; 3],
    /// Angular rate, rad/s, sensor frame.
    pub gyro: [f64; 3],
    /// Magnetic field, µT, sensor frame, when logged.
    pub mag: Option<[f64; 3]>,
    /// Orientation, sensor → east-north-up, as a unit quaternion `[x, y, z, w]` (Android's
    /// rotation vector), when logged.
    pub orientation: Option<[f64; 4]>,
    /// Air pressure, hPa, when logged.
    pub pressure: Option<f64>,
}

/// Largest accepted specific force per axis, m/s² (±16 g: the range of common IMUs).
pub const MAX_ACCEL: f64 = 16.0 * 9.81;
/// Largest accepted angular rate per axis, rad/s (about 2,300 °/s).
pub const MAX_GYRO: f64 = 40.0;
/// Largest accepted magnetic field per axis, µT (Earth's is 25–65 µT; steel adds some).
pub const MAX_MAG: f64 = 2_000.0;
/// Accepted air pressure, hPa (from the Dead Sea shore to above Everest's summit).
pub const PRESSURE_RANGE: std::ops::RangeInclusive<f64> = 250.0..=1_100.0;

/// Why a sample is unusable, if it is.
///
/// # Errors
///
/// A message naming the value and the rule when the time or a value is not finite, an axis exceeds
/// [`MAX_ACCEL`], [`MAX_GYRO`] (with a hint at degrees per second) or [`MAX_MAG`], the orientation
/// quaternion's norm is outside [0.9, 1.1], or the pressure is outside [`PRESSURE_RANGE`].
pub fn check_sample(s: &ImuSample) -> Result<(), String> {
    if !s.t.is_finite() {
        return Err("time must be a finite number".into());
    }
    let axes = |v: &[f64; 3], max: f64, what: &str, unit: &str| -> Result<(), String> {
        for (a, name) in v.iter().zip(["x", "y", "z"]) {
            if !a.is_finite() {
                return Err(format!("{what} {name} is not a finite number"));
            }
            if a.abs() > max {
                return Err(format!(
                    "{what} {name} = {} {unit} is beyond ±{max} {unit}",
                    crate::error::short_number(*a)
                ));
            }
        }
        Ok(())
    };
    axes(&s.accel, MAX_ACCEL, "acceleration", "m/s²")?;
    axes(&s.gyro, MAX_GYRO, "angular rate", "rad/s").map_err(|m| {
        format!("{m} (degrees per second? the columns take rad/s: pass --gyro-unit deg/s)")
    })?;
    if let Some(m) = &s.mag {
        axes(m, MAX_MAG, "magnetic field", "µT")?;
    }
    if let Some(q) = &s.orientation {
        if q.iter().any(|v| !v.is_finite()) {
            return Err("orientation quaternion is not finite".into());
        }
        let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
        if !(0.9..=1.1).contains(&norm) {
            return Err(format!(
                "orientation quaternion has norm {norm:.3}, not 1 (expected qx,qy,qz,qw of a unit quaternion)"
            ));
        }
    }
    if let Some(p) = s.pressure
        && !(p.is_finite() && PRESSURE_RANGE.contains(&p))
    {
        return Err(format!(
            "pressure {} hPa is outside [{}, {}] hPa",
            crate::error::short_number(p),
            PRESSURE_RANGE.start(),
            PRESSURE_RANGE.end()
        ));
    }
    Ok(())
}

/// How a recording was sampled, for the user and for the detectors.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SamplingReport {
    /// Samples kept.
    pub samples: usize,
    /// Time from the first to the last sample, seconds.
    pub duration_s: f64,
    /// Median interval between samples, seconds.
    pub median_dt_s: f64,
    /// Rate implied by the median interval, Hz.
    pub rate_hz: f64,
    /// Rows dropped because they repeated the previous row's time.
    pub duplicate_times: usize,
    /// Intervals longer than [`GAP_FACTOR`] × the median interval (samples missing).
    pub gaps: usize,
    /// The longest interval between samples, seconds.
    pub longest_gap_s: f64,
    /// Intervals that differ from the median by more than 25 % (uneven sampling).
    pub uneven_intervals: usize,
}

/// Accepted median magnitude of the specific force over a recording, m/s²: about gravity's
/// 9.81 for a phone, up to twice that for a foot IMU on a brisk walk (16.9 and 21.2 m/s²
/// measured on two fast Vicon-room walks). A recording in g (median 1–2.5) falls below.
pub const GRAVITY_RANGE: std::ops::RangeInclusive<f64> = 4.0..=60.0;

/// Sampling rates an IMU recording may have, Hz (the median interval's): phones log at
/// 50–500 Hz, foot IMUs at 100–1000; a rate far outside says the times are in other units
/// than seconds.
pub const RATE_RANGE_HZ: std::ops::RangeInclusive<f64> = 5.0..=10_000.0;

/// Why a recording's sampling rate is implausible, if it is (with the likely unit mistake).
fn check_rate(report: &SamplingReport) -> Result<(), String> {
    let (lo, hi) = (*RATE_RANGE_HZ.start(), *RATE_RANGE_HZ.end());
    let rate = report.rate_hz;
    if rate < lo {
        return Err(format!(
            "samples come every {} s (median), {} Hz: an IMU samples at {lo}–{hi} Hz; are the \
             times in milliseconds (divide them by 1000)?",
            crate::error::short_number(report.median_dt_s),
            crate::error::short_number(rate)
        ));
    }
    if rate > hi {
        return Err(format!(
            "samples come every {} s (median), {} Hz: an IMU samples at {lo}–{hi} Hz; are the \
             times in other units than seconds (minutes, or clock ticks)?",
            crate::error::short_number(report.median_dt_s),
            crate::error::short_number(rate)
        ));
    }
    Ok(())
}

/// The median of the magnitudes of `vectors`.
fn median_magnitude(vectors: impl Iterator<Item = [f64; 3]>) -> f64 {
    let mut m: Vec<f64> = vectors
        .map(|v| v.iter().map(|a| a * a).sum::<f64>().sqrt())
        .collect();
    if m.is_empty() {
        return f64::NAN;
    }
    let mid = m.len() / 2;
    *m.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// Why a recording's columns look mixed up, if they do, judged on the whole recording
/// before any one row is (a row's value out of range would otherwise be blamed on its unit):
/// accelerometer and gyroscope columns swapped (the rates hold gravity), or acceleration
/// converted from g (`accel_factor`, the factor the reader applied) that was already in m/s².
#[must_use]
pub fn diagnose_columns(samples: &[ImuSample], accel_factor: f64) -> Option<String> {
    let accel = median_magnitude(samples.iter().map(|s| s.accel));
    let gyro = median_magnitude(samples.iter().map(|s| s.gyro));
    let as_written = accel / accel_factor;
    // Gravity in g (a median near 1) is a unit, not a swap.
    let in_g = (0.8..=1.25).contains(&as_written);
    if GRAVITY_RANGE.contains(&gyro) && as_written < *GRAVITY_RANGE.start() && !in_g {
        return Some(format!(
            "the angular-rate columns hold gravity (median magnitude {gyro:.2}, as an \
             accelerometer's in m/s²) and the acceleration columns do not (median {:.2}): are \
             the accelerometer's and the gyroscope's columns swapped?",
            as_written
        ));
    }
    if accel_factor != 1.0 && !GRAVITY_RANGE.contains(&accel) && GRAVITY_RANGE.contains(&as_written)
    {
        return Some(format!(
            "the acceleration columns' median magnitude is {as_written:.2} as written, \
             gravity's in m/s², so they are in m/s² already: leave out --accel-unit g"
        ));
    }
    None
}

/// An interval longer than this many median intervals counts as a gap.
pub const GAP_FACTOR: f64 = 5.0;

/// A validated IMU recording: at least two samples, times strictly increasing, values finite
/// and within the documented ranges; optional channels present in every sample or in none.
///
/// A recording checked and its sampling measured:
///
/// ```
/// use footslam::sensor::{ImuRecording, ImuSample};
///
/// // Ten seconds of a phone lying still at 50 Hz, two of them lost.
/// let still = |i: u32| ImuSample {
///     t: f64::from(i) / 50.0,
///     accel: [0.0, 0.0, 9.81],
///     gyro: [0.0; 3],
///     mag: None,
///     orientation: None,
///     pressure: None,
/// };
/// let mut samples: Vec<ImuSample> = (0..500).map(still).collect();
/// samples.drain(200..300);
/// let recording = ImuRecording::new(samples, 0).expect("a valid recording");
/// let report = recording.report();
/// assert_eq!(report.samples, 400);
/// assert!((report.rate_hz - 50.0).abs() < 1e-6);
/// assert_eq!(report.gaps, 1);
/// assert!((report.longest_gap_s - 2.02).abs() < 1e-9);
///
/// // Acceleration in g instead of m/s² is refused, the likely mistake named.
/// let in_g = (0..100).map(|i| ImuSample { accel: [0.0, 0.0, 1.0], ..still(i) }).collect();
/// let (_, problem) = ImuRecording::new(in_g, 0).unwrap_err();
/// assert!(problem.contains("in g?"), "{problem}");
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ImuRecording {
    samples: Vec<ImuSample>,
    report: SamplingReport,
}

impl ImuRecording {
    /// A recording from samples; `duplicate_times` is how many rows the reader dropped for
    /// repeating a time (reported). The error names the 0-based sample index.
    ///
    /// # Errors
    ///
    /// A 0-based sample index and a message when there are fewer than two samples, a sample fails
    /// [`check_sample`], times do not strictly increase, the magnetometer, orientation or pressure
    /// is given in some samples only, the median acceleration magnitude is outside
    /// [`GRAVITY_RANGE`] (in g?), or the sampling rate is outside [`RATE_RANGE_HZ`]
    /// (times not in seconds?).
    pub fn new(samples: Vec<ImuSample>, duplicate_times: usize) -> Result<Self, (usize, String)> {
        if samples.len() < 2 {
            return Err((
                samples.len().saturating_sub(1),
                format!(
                    "a recording needs at least two samples, found {}",
                    samples.len()
                ),
            ));
        }
        let first = &samples[0];
        for (i, s) in samples.iter().enumerate() {
            check_sample(s).map_err(|m| (i, m))?;
            if i > 0 && s.t <= samples[i - 1].t {
                return Err((
                    i,
                    format!(
                        "time {} s is not after the previous sample's {} s (samples must be sorted by time)",
                        s.t,
                        samples[i - 1].t
                    ),
                ));
            }
            let same = |a: bool, b: bool, what: &str| {
                if a == b {
                    Ok(())
                } else {
                    Err((
                        i,
                        format!("{what} is given in some samples and missing in others"),
                    ))
                }
            };
            same(s.mag.is_some(), first.mag.is_some(), "the magnetometer")?;
            same(
                s.orientation.is_some(),
                first.orientation.is_some(),
                "the orientation",
            )?;
            same(s.pressure.is_some(), first.pressure.is_some(), "pressure")?;
        }
        let median = median_magnitude(samples.iter().map(|s| s.accel));
        if !GRAVITY_RANGE.contains(&median) {
            return Err((
                0,
                format!(
                    "the acceleration's median magnitude over the whole recording is {median:.2}, \
                     outside [{}, {}] m/s² around gravity's 9.81 (in g? pass --accel-unit g, or \
                     multiply by 9.80665; the columns take m/s² with gravity included)",
                    GRAVITY_RANGE.start(),
                    GRAVITY_RANGE.end()
                ),
            ));
        }
        let report = sampling_report(&samples, duplicate_times);
        check_rate(&report).map_err(|m| (0, m))?;
        Ok(Self { samples, report })
    }

    /// The samples, in time order.
    #[must_use]
    pub fn samples(&self) -> &[ImuSample] {
        &self.samples
    }

    /// How the recording was sampled.
    #[must_use]
    pub fn report(&self) -> &SamplingReport {
        &self.report
    }

    /// The recording with the angular-rate axes named in `flip` negated (`flip[i]`: axis
    /// `x`, `y`, `z`), for gyroscopes whose axes are mirrored against the accelerometer's.
    #[must_use]
    pub fn with_gyro_flipped(&self, flip: [bool; 3]) -> Self {
        let mut samples = self.samples.clone();
        for s in &mut samples {
            for (w, &f) in s.gyro.iter_mut().zip(&flip) {
                if f {
                    *w = -*w;
                }
            }
        }
        Self {
            samples,
            report: self.report.clone(),
        }
    }

    /// True when every sample carries a magnetometer reading.
    #[must_use]
    pub fn has_magnetometer(&self) -> bool {
        self.samples[0].mag.is_some()
    }

    /// True when every sample carries an orientation quaternion.
    #[must_use]
    pub fn has_orientation(&self) -> bool {
        self.samples[0].orientation.is_some()
    }

    /// True when every sample carries air pressure.
    #[must_use]
    pub fn has_pressure(&self) -> bool {
        self.samples[0].pressure.is_some()
    }
}

fn sampling_report(samples: &[ImuSample], duplicate_times: usize) -> SamplingReport {
    let mut dts: Vec<f64> = samples.windows(2).map(|w| w[1].t - w[0].t).collect();
    let longest_gap_s = dts.iter().copied().fold(0.0, f64::max);
    let (gaps, uneven) = {
        let mut sorted = dts.clone();
        sorted.sort_by(f64::total_cmp);
        let median = sorted[sorted.len() / 2];
        let gaps = dts.iter().filter(|&&d| d > GAP_FACTOR * median).count();
        let uneven = dts
            .iter()
            .filter(|&&d| (d - median).abs() > 0.25 * median)
            .count();
        dts = sorted;
        (gaps, uneven)
    };
    let median_dt_s = dts[dts.len() / 2];
    SamplingReport {
        samples: samples.len(),
        duration_s: samples[samples.len() - 1].t - samples[0].t,
        median_dt_s,
        rate_hz: 1.0 / median_dt_s,
        duplicate_times,
        gaps,
        longest_gap_s,
        uneven_intervals: uneven,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(t: f64) -> ImuSample {
        ImuSample {
            t,
            accel: [0.0, 0.0, 9.81],
            gyro: [0.0; 3],
            mag: None,
            orientation: None,
            pressure: None,
        }
    }

    #[test]
    fn reports_rate_gaps_and_duplicates() {
        let mut s: Vec<_> = (0..100)
            .map(|i| sample(1.7e9 + f64::from(i) * 0.01))
            .collect();
        s.extend((0..10).map(|i| sample(1.7e9 + 2.0 + f64::from(i) * 0.01)));
        let r = ImuRecording::new(s, 3).expect("valid");
        let rep = r.report();
        assert_eq!(rep.samples, 110);
        assert!((rep.rate_hz - 100.0).abs() < 1e-3, "{}", rep.rate_hz);
        assert_eq!(rep.gaps, 1);
        assert_eq!(rep.duplicate_times, 3);
        assert!((rep.longest_gap_s - 1.01).abs() < 1e-6);
    }

    #[test]
    fn rejects_unsorted_absurd_and_mixed_channels() {
        assert_eq!(
            ImuRecording::new(vec![sample(1.0), sample(0.5)], 0)
                .unwrap_err()
                .0,
            1
        );
        let mut bad = sample(1.0);
        bad.accel[2] = 1e6;
        assert!(ImuRecording::new(vec![sample(0.0), bad], 0).is_err());
        let in_g: Vec<_> = (0..10)
            .map(|i| ImuSample {
                accel: [0.0, 0.0, 1.0],
                ..sample(f64::from(i))
            })
            .collect();
        let e = ImuRecording::new(in_g, 0).unwrap_err();
        assert!(e.1.contains("in g?"), "{}", e.1);
        let mut with_mag = sample(1.0);
        with_mag.mag = Some([20.0, 0.0, -40.0]);
        let e = ImuRecording::new(vec![sample(0.0), with_mag], 0).unwrap_err();
        assert!(e.1.contains("magnetometer"), "{}", e.1);
        assert!(ImuRecording::new(vec![sample(0.0)], 0).is_err());
    }

    #[test]
    fn times_in_milliseconds_and_mixed_up_columns_are_named() {
        // 100 Hz stamped in milliseconds: a sample every 10 "seconds".
        let ms: Vec<_> = (0..50).map(|i| sample(f64::from(i) * 10.0)).collect();
        let (_, m) = ImuRecording::new(ms, 0).unwrap_err();
        assert!(m.contains("milliseconds"), "{m}");
        let walking = |i: i32| ImuSample {
            accel: [0.3 * f64::from(i % 5), 0.2, 9.81],
            gyro: [0.1 + 0.05 * f64::from(i % 7), 0.0, 0.0],
            ..sample(f64::from(i) * 0.01)
        };
        let fine: Vec<_> = (0..50).map(walking).collect();
        assert_eq!(diagnose_columns(&fine, 1.0), None);
        let swapped: Vec<_> = fine
            .iter()
            .map(|s| ImuSample {
                accel: s.gyro,
                gyro: s.accel,
                ..*s
            })
            .collect();
        let m = diagnose_columns(&swapped, 1.0).expect("swapped");
        assert!(m.contains("swapped"), "{m}");
        // Already m/s², read as g: said, with the value as written.
        let as_g: Vec<_> = fine
            .iter()
            .map(|s| ImuSample {
                accel: s.accel.map(|a| a * 9.806_65),
                ..*s
            })
            .collect();
        let m = diagnose_columns(&as_g, 9.806_65).expect("double g");
        assert!(
            m.contains("leave out --accel-unit g") && m.contains("9.8"),
            "{m}"
        );
        // A file in g and deg/s without the flags is not a swap.
        let g_deg: Vec<_> = fine
            .iter()
            .map(|s| ImuSample {
                accel: s.accel.map(|a| a / 9.806_65),
                gyro: s.gyro.map(f64::to_degrees),
                ..*s
            })
            .collect();
        assert_eq!(diagnose_columns(&g_deg, 1.0), None);
    }
}
