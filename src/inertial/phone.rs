//! Hand-held phone → steps: a step-and-heading system (Harle 2013, §V; Ab Rahman et al.,
//! §2: step detection, stride length, heading).
//!
//! One pass over the samples, each with its own `dt` and no allocation per sample:
//!
//! 1. **steps** — [`super::step_detector`]: peaks and valleys of the low-passed acceleration
//!    magnitude (orientation-free), an adaptive swing threshold over a physical floor, a
//!    minimum step period;
//! 2. **length** — [`super::stride_model`]: Weinberg's `K·(a_max − a_min)^{1/4}`;
//! 3. **heading** — [`super::heading_fusion`]: the mean forward direction over the step, from
//!    the rotation vector when logged ([`HeadingSource::RotationVector`]), else gyroscope +
//!    magnetometer ([`HeadingSource::GyroMagnetometer`]), else the gyroscope alone
//!    ([`HeadingSource::Gyroscope`], relative: `Step::heading` is `None`);
//! 4. **height** — [`super::barometer`]: the change of the low-passed pressure height since the
//!    previous step, when pressure is logged (else 0).
//!
//! The first step's `dheading` is measured from the heading at the first sample, so that
//! [`crate::sensor::StepTrace::dead_reckon`] from a start pose with that heading retraces
//! `path`. **Gaps**: an interval longer than [`PhoneConfig::max_gap_s`] restarts the step
//! detector and the gyro/magnetometer filter (no step spans a gap); the figures count the
//! gaps, their time and the steps they probably hid (the gap over the last step period when
//! the walker was walking just before).

use super::barometer::{Barometer, BarometerConfig};
use super::heading_fusion::{
    HeadingFilter, HeadingFusionConfig, forward_from_quaternion, heading_of,
};
use super::step_detector::{DetectedStep, StepDetector, StepDetectorConfig};
use super::stride_model::StrideModelConfig;
use super::{HeadingSource, StepEvents};
use crate::error::{Error, Result};
use crate::geometry::wrap_turn;
use crate::sensor::step::MAX_STEP_DZ;
use crate::sensor::{ImuRecording, ImuSample, Step, StepTrace};
use serde::{Deserialize, Serialize};

/// Parameters of the phone step-and-heading system; every default in one place (each
/// section documents its own).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PhoneConfig {
    /// Step detection on the acceleration magnitude.
    pub steps: StepDetectorConfig,
    /// The stride-length model and its one calibratable constant.
    pub stride: StrideModelConfig,
    /// Heading: declination, magnetometer fusion.
    pub heading: HeadingFusionConfig,
    /// Barometric height.
    pub barometer: BarometerConfig,
    /// Longest interval between two samples that is still integrated, seconds; a longer one
    /// is a gap. Default 0.2 s: shorter than the minimum step period (0.28 s), so a gap
    /// under the limit cannot hide a whole step, and ten samples at 50 Hz.
    pub max_gap_s: f64,
    /// Use the rotation vector for the heading when the recording has one. Default true.
    pub use_rotation_vector: bool,
    /// Use the magnetometer (when logged and no rotation vector is used). Default true.
    pub use_magnetometer: bool,
}

impl Default for PhoneConfig {
    fn default() -> Self {
        Self {
            steps: StepDetectorConfig::default(),
            stride: StrideModelConfig::default(),
            heading: HeadingFusionConfig::default(),
            barometer: BarometerConfig::default(),
            max_gap_s: 0.2,
            use_rotation_vector: true,
            use_magnetometer: true,
        }
    }
}

impl PhoneConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] from the first section that fails its `validate` ([`StepDetectorConfig`],
    /// [`StrideModelConfig`], [`HeadingFusionConfig`], [`BarometerConfig`]), or when `max_gap_s` is
    /// outside [0.001, 60] s.
    pub fn validate(&self) -> Result<()> {
        self.steps.validate()?;
        self.stride.validate()?;
        self.heading.validate()?;
        self.barometer.validate()?;
        if !(self.max_gap_s.is_finite() && (0.001..=60.0).contains(&self.max_gap_s)) {
            return Err(crate::error::Error::config(
                "phone.max_gap_s",
                self.max_gap_s.to_string(),
                "must be in [0.001, 60] s",
            ));
        }
        Ok(())
    }
}

/// How the heading was obtained, in figures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HeadingFigures {
    /// The source used.
    pub source: HeadingSource,
    /// Declination applied to absolute headings, radians.
    pub declination: f64,
    /// Magnetometer readings used in the complementary filter.
    pub magnetometer_used: usize,
    /// Magnetometer readings skipped for a field strength outside the configured range.
    pub magnetometer_skipped: usize,
}

/// The detector's figures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PhoneFigures {
    /// Steps detected.
    pub steps: usize,
    /// Time from the first to the last sample, seconds.
    pub duration_s: f64,
    /// Time walking (sum of step intervals up to `steps.max_step_period_s`), seconds.
    pub walking_s: f64,
    /// Time neither walking nor in a gap, seconds.
    pub standing_s: f64,
    /// Steps per minute of walking.
    pub cadence_spm: f64,
    /// Mean stride length, metres.
    pub mean_stride_m: f64,
    /// Sum of the stride lengths, metres.
    pub total_length_m: f64,
    /// Weinberg's constant `K` used.
    pub stride_constant: f64,
    /// Heading source details.
    pub heading: HeadingFigures,
    /// Intervals longer than `max_gap_s`.
    pub gaps: usize,
    /// Time inside gaps, seconds.
    pub gap_s: f64,
    /// The longest interval between samples, seconds.
    pub longest_gap_s: f64,
    /// Steps probably hidden in gaps (gap ÷ step period, when walking before the gap).
    pub steps_possibly_missed: usize,
    /// Peak–valley pairs rejected for coming sooner than the minimum step period.
    pub rejected_too_soon: usize,
    /// Net height change from the barometer, metres (0 without pressure).
    pub height_change_m: f64,
    /// Steps whose height change was capped at ±`MAX_STEP_DZ` (pressure jumps).
    pub dz_capped: usize,
}

fn magnitude(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// The per-sample walking direction, from the chosen source.
struct Direction {
    source: HeadingSource,
    filter: HeadingFilter,
    declination: f64,
    use_magnetometer: bool,
}

impl Direction {
    fn mag(&self, s: &ImuSample) -> Option<[f64; 3]> {
        if self.use_magnetometer { s.mag } else { None }
    }

    /// Restarts at `s`; returns its forward vector.
    fn restart(&mut self, s: &ImuSample) -> [f64; 2] {
        match (self.source, s.orientation) {
            (HeadingSource::RotationVector, Some(q)) => forward_from_quaternion(q),
            _ => {
                self.filter.restart(s.accel, self.mag(s));
                let psi = self.filter.heading();
                [psi.cos(), psi.sin()]
            }
        }
    }

    /// Feeds `s`, `dt` after the previous sample; returns its forward vector.
    fn update(&mut self, dt: f64, s: &ImuSample) -> [f64; 2] {
        match (self.source, s.orientation) {
            (HeadingSource::RotationVector, Some(q)) => forward_from_quaternion(q),
            _ => {
                let psi = self.filter.update(dt, s.accel, s.gyro, self.mag(s));
                [psi.cos(), psi.sin()]
            }
        }
    }

    /// The heading of a summed forward vector, or `None` when it has no direction.
    fn heading(&self, sum: [f64; 2]) -> Option<f64> {
        let norm = sum[0].hypot(sum[1]);
        if norm.is_nan() || norm <= 1e-9 {
            return None;
        }
        Some(match self.source {
            HeadingSource::RotationVector => heading_of(sum, self.declination),
            // The filter's ψ already carries the declination.
            _ => sum[1].atan2(sum[0]),
        })
    }
}

/// The steps so far and what the next step is measured from.
struct Walk {
    steps: Vec<Step>,
    path: Vec<[f64; 3]>,
    /// Sum of the forward vectors since the last step.
    sum: [f64; 2],
    last_heading: f64,
    /// Filtered barometric height now, and at the last step.
    height: f64,
    last_height: f64,
    /// The last step's time and the interval before it.
    last_step: Option<(f64, f64)>,
    walking_s: f64,
    intervals: usize,
    dz_capped: usize,
}

impl Walk {
    fn accumulate(&mut self, forward: [f64; 2]) {
        self.sum = [self.sum[0] + forward[0], self.sum[1] + forward[1]];
    }

    /// Adds a detected step: length, mean heading since the last step, height change.
    fn add(
        &mut self,
        found: DetectedStep,
        config: &PhoneConfig,
        direction: &Direction,
        absolute: bool,
    ) {
        let length = config.stride.length(found.a_max, found.a_min);
        let heading = direction.heading(self.sum).unwrap_or(self.last_heading);
        let dheading = wrap_turn(heading - self.last_heading);
        let mut dz = self.height - self.last_height;
        if dz.abs() > MAX_STEP_DZ {
            dz = dz.clamp(-MAX_STEP_DZ, MAX_STEP_DZ);
            self.dz_capped += 1;
        }
        self.steps.push(Step {
            t: found.t,
            length,
            dheading,
            dz,
            heading: absolute.then_some(heading),
        });
        let p = self.path.last().copied().unwrap_or([0.0; 3]);
        self.path.push([
            p[0] + length * heading.cos(),
            p[1] + length * heading.sin(),
            p[2] + dz,
        ]);
        let interval = self.last_step.map_or(0.0, |(t, _)| found.t - t);
        if self.last_step.is_some() && interval <= config.steps.max_step_period_s {
            self.walking_s += interval;
            self.intervals += 1;
        }
        self.last_step = Some((found.t, interval));
        self.sum = [0.0; 2];
        self.last_heading = heading;
        self.last_height += dz;
    }
}

/// Steps of a hand-held phone recording.
///
/// # Errors
///
/// [`Error::Config`] when `config` fails [`PhoneConfig::validate`]; [`Error::InvalidData`], as a
/// safeguard, when a detected step fails [`check_step`](crate::sensor::step::check_step) (lengths
/// and height changes are already capped).
pub fn detect_steps(
    recording: &ImuRecording,
    config: &PhoneConfig,
) -> Result<StepEvents<PhoneFigures>> {
    config.validate()?;
    let samples = recording.samples();
    let source = if config.use_rotation_vector && recording.has_orientation() {
        HeadingSource::RotationVector
    } else if config.use_magnetometer && recording.has_magnetometer() {
        HeadingSource::GyroMagnetometer
    } else {
        HeadingSource::Gyroscope
    };
    let absolute = source != HeadingSource::Gyroscope;
    let mut detector = StepDetector::new(&config.steps);
    let mut direction = Direction {
        source,
        filter: HeadingFilter::new(&config.heading),
        declination: config.heading.declination,
        use_magnetometer: config.use_magnetometer && source == HeadingSource::GyroMagnetometer,
    };
    let mut barometer = Barometer::new(&config.barometer);

    let duration_s = recording.report().duration_s;
    let capacity = ((duration_s / config.steps.min_step_period_s) as usize + 1).min(10_000_000);
    let first = &samples[0];
    detector.restart(first.t, magnitude(first.accel));
    let forward = direction.restart(first);
    let start_height = first.pressure.map(|p| barometer.update(0.0, p));
    let mut walk = Walk {
        steps: Vec::with_capacity(capacity),
        path: Vec::with_capacity(capacity + 1),
        sum: forward,
        last_heading: direction.heading(forward).unwrap_or(0.0),
        height: start_height.unwrap_or(0.0),
        last_height: start_height.unwrap_or(0.0),
        last_step: None,
        walking_s: 0.0,
        intervals: 0,
        dz_capped: 0,
    };
    walk.path.push([0.0; 3]);
    let (mut gaps, mut gap_s, mut longest_gap_s, mut missed) = (0usize, 0.0, 0.0f64, 0usize);

    for w in samples.windows(2) {
        let (prev, s) = (&w[0], &w[1]);
        let dt = s.t - prev.t;
        longest_gap_s = longest_gap_s.max(dt);
        if let Some(p) = s.pressure {
            walk.height = barometer.update(dt, p);
        }
        if dt > config.max_gap_s {
            if let Some(found) = detector.flush() {
                walk.add(found, config, &direction, absolute);
            }
            gaps += 1;
            gap_s += dt;
            if let Some((t, interval)) = walk.last_step
                && prev.t - t <= config.steps.max_step_period_s
                && interval > 0.0
            {
                missed += (dt / interval).floor() as usize;
            }
            detector.restart(s.t, magnitude(s.accel));
            walk.accumulate(direction.restart(s));
            continue;
        }
        walk.accumulate(direction.update(dt, s));
        if let Some(found) = detector.update(s.t, dt, magnitude(s.accel)) {
            walk.add(found, config, &direction, absolute);
        }
    }
    if let Some(found) = detector.flush() {
        walk.add(found, config, &direction, absolute);
    }
    let Walk {
        steps,
        path,
        walking_s,
        intervals,
        dz_capped,
        height,
        ..
    } = walk;

    let total_length_m: f64 = steps.iter().map(|s| s.length).sum();
    let (used, skipped) = direction.filter.magnetometer_use();
    let figures = PhoneFigures {
        steps: steps.len(),
        duration_s,
        walking_s,
        standing_s: (duration_s - walking_s - gap_s).max(0.0),
        cadence_spm: if walking_s > 0.0 {
            intervals as f64 / walking_s * 60.0
        } else {
            0.0
        },
        mean_stride_m: if steps.is_empty() {
            0.0
        } else {
            total_length_m / steps.len() as f64
        },
        total_length_m,
        stride_constant: config.stride.weinberg_k,
        heading: HeadingFigures {
            source,
            declination: if absolute {
                config.heading.declination
            } else {
                0.0
            },
            magnetometer_used: used,
            magnetometer_skipped: skipped,
        },
        gaps,
        gap_s,
        longest_gap_s,
        steps_possibly_missed: missed,
        rejected_too_soon: detector.rejected_too_soon(),
        height_change_m: start_height.map_or(0.0, |h0| height - h0),
        dz_capped,
    };
    let trace = StepTrace::new(steps).map_err(|(i, m)| {
        Error::invalid(format!("phone step {i}"), format!("is implausible: {m}"))
    })?;
    Ok(StepEvents {
        trace,
        path,
        heading_source: source,
        figures,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    /// A walk at 2 steps/s for `walk_s` seconds, then `still_s` still, sampled at `rate`,
    /// phone flat facing north (or a quarter turn left of it after `turn_at`).
    fn walk(rate: f64, walk_s: f64, still_s: f64, turn_at: f64) -> Vec<ImuSample> {
        let n = ((walk_s + still_s) * rate) as usize;
        (0..n)
            .map(|i| {
                let t = 100.0 + i as f64 / rate;
                let up = if t - 100.0 < walk_s {
                    3.0 * (2.0 * PI * 2.0 * (t - 100.0)).sin()
                } else {
                    0.0
                };
                let yaw = if t - 100.0 >= turn_at { FRAC_PI_2 } else { 0.0 };
                ImuSample {
                    t,
                    accel: [0.0, 0.0, 9.81 + up],
                    gyro: [0.0; 3],
                    mag: None,
                    orientation: Some([0.0, 0.0, (yaw / 2.0).sin(), (yaw / 2.0).cos()]),
                    pressure: Some(1000.0 - 0.36 * ((t - 100.0) / walk_s).min(1.0)),
                }
            })
            .collect()
    }

    #[test]
    fn synthetic_walk_gives_steps_heading_and_height() {
        let r = ImuRecording::new(walk(50.0, 10.0, 5.0, 5.0), 0).expect("valid");
        let e = detect_steps(&r, &PhoneConfig::default()).expect("runs");
        let f = &e.figures;
        assert!((19..=21).contains(&f.steps), "{}", f.steps);
        assert_eq!(e.heading_source, HeadingSource::RotationVector);
        assert_eq!(e.path.len(), f.steps + 1);
        // North first, then west: the path goes up, then left.
        let s = e.trace.steps();
        assert!((s[0].heading.expect("absolute") - FRAC_PI_2).abs() < 1e-9);
        assert!((s[s.len() - 1].heading.expect("absolute") - PI).abs() < 1e-9);
        let turns: f64 = s.iter().map(|s| s.dheading).sum();
        assert!((turns - FRAC_PI_2).abs() < 1e-9, "{turns}");
        let end = e.path[e.path.len() - 1];
        assert!(end[0] < -3.0 && end[1] > 3.0, "{end:?}");
        // Cadence 120 steps/min; pressure falls 0.36 hPa while walking: about +3 m in all.
        assert!((f.cadence_spm - 120.0).abs() < 3.0, "{}", f.cadence_spm);
        assert!(
            (f.height_change_m - 3.0).abs() < 0.1,
            "{}",
            f.height_change_m
        );
        assert!(f.walking_s > 8.5 && f.standing_s > 4.5, "{f:?}");
    }

    #[test]
    fn a_gap_is_counted_and_makes_no_step() {
        let mut s = walk(100.0, 10.0, 0.0, 99.0);
        s.drain(400..500); // 1 s missing at 4 s
        let r = ImuRecording::new(s, 0).expect("valid");
        let f = detect_steps(&r, &PhoneConfig::default())
            .expect("runs")
            .figures;
        assert_eq!(f.gaps, 1);
        assert!((f.gap_s - 1.01).abs() < 1e-6);
        assert_eq!(f.steps_possibly_missed, 2);
        // 20 peaks, 2 of them (4.125 s, 4.625 s) inside the gap.
        assert_eq!(f.steps, 18);
    }

    #[test]
    fn without_orientation_or_magnetometer_the_heading_is_relative() {
        let s: Vec<_> = walk(50.0, 4.0, 0.0, 99.0)
            .into_iter()
            .map(|mut s| {
                s.orientation = None;
                s.pressure = None;
                s
            })
            .collect();
        let r = ImuRecording::new(s, 0).expect("valid");
        let e = detect_steps(&r, &PhoneConfig::default()).expect("runs");
        assert_eq!(e.heading_source, HeadingSource::Gyroscope);
        assert!(
            e.trace
                .steps()
                .iter()
                .all(|s| s.heading.is_none() && s.dz == 0.0)
        );
        // No rotation: straight along x.
        let end = e.path[e.path.len() - 1];
        assert!(end[0] > 3.0 && end[1].abs() < 1e-9, "{end:?}");
    }
}
