//! Step detection on the acceleration magnitude: low-pass, then peak/valley detection with
//! hysteresis, an adaptive swing threshold and a minimum step period.
//!
//! The magnitude `|a| = √(a_x² + a_y² + a_z²)` does not depend on how the phone is held
//! (Ab Rahman et al., §2.1 eq. 1; Harle 2013, §III "peak detection"). It is smoothed by two
//! cascaded first-order low-pass sections with a cut-off in hertz, integrated with each
//! sample's own `dt`, so the detector behaves the same at 50 Hz and at 200 Hz. A peak is
//! confirmed once the signal has fallen a hysteresis below it, a valley once it has risen a
//! hysteresis above it; a peak–valley pair is a step when (Pratama et al.'s dynamic
//! thresholds, Ab Rahman et al. eq. 2, in the form of one swing threshold)
//!
//! ```text
//! a_max(k) − a_min(k) ≥ c(k),   c(k) = max(c_min, ρ · s̄(k−1))
//! ```
//!
//! where `s̄` is a running mean of the accepted swings (reset after a pause), and the peak
//! comes at least `min_step_period_s` after the previous step's. The physical floor `c_min`
//! keeps a phone at rest (swing ≈ 0.1 m/s²) silent; the adaptive part rejects the small
//! secondary bumps of a vigorous gait.

use crate::error::Result;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Parameters of the step detector; every default in one place.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StepDetectorConfig {
    /// Cut-off of the low-pass filter on `|a|`, Hz. Default 3 Hz: above the step frequency
    /// of walking and running (1.4–3 Hz), below the heel-strike jerk and hand tremor.
    pub low_pass_hz: f64,
    /// Smallest peak-to-valley swing of a step `c_min`, m/s². Default 1.0 m/s²: a phone held
    /// in the hand swings 2–8 m/s² per step (filtered), at rest under 0.2 m/s².
    pub min_swing: f64,
    /// Fraction `ρ` of the running mean swing that a step must reach. Default 0.35.
    pub adaptive_fraction: f64,
    /// Shortest time between two steps' peaks, seconds. Default 0.28 s (about 214 steps/min,
    /// beyond a brisk walk's 120–140 and a jog's 160–180).
    pub min_step_period_s: f64,
    /// Longest time between two steps of one walking bout, seconds; a longer pause counts as
    /// standing and resets the adaptive threshold. Default 2.0 s.
    pub max_step_period_s: f64,
}

impl Default for StepDetectorConfig {
    fn default() -> Self {
        Self {
            low_pass_hz: 3.0,
            min_swing: 1.0,
            adaptive_fraction: 0.35,
            min_step_period_s: 0.28,
            max_step_period_s: 2.0,
        }
    }
}

impl StepDetectorConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `low_pass_hz` is outside [0.5, 20] Hz,
    /// `min_swing` outside [0.05, 50] m/s², `adaptive_fraction` outside [0, 1], `min_step_period_s`
    /// outside [0.05, 2] s, or `max_step_period_s` below `min_step_period_s` or above 30 s.
    pub fn validate(&self) -> Result<()> {
        crate::error::check_range(
            "phone.steps.low_pass_hz",
            self.low_pass_hz,
            0.5..=20.0,
            "Hz",
        )?;
        crate::error::check_range("phone.steps.min_swing", self.min_swing, 0.05..=50.0, "m/s²")?;
        crate::error::check_range(
            "phone.steps.adaptive_fraction",
            self.adaptive_fraction,
            0.0..=1.0,
            "",
        )?;
        crate::error::check_range(
            "phone.steps.min_step_period_s",
            self.min_step_period_s,
            0.05..=2.0,
            "s",
        )?;
        crate::error::check_range(
            "phone.steps.max_step_period_s",
            self.max_step_period_s,
            self.min_step_period_s..=30.0,
            "s",
        )
    }
}

/// A step found by [`StepDetector::update`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DetectedStep {
    /// Time of the step's peak, seconds.
    pub t: f64,
    /// Filtered magnitude at the peak, m/s².
    pub a_max: f64,
    /// Filtered magnitude at the valley after it, m/s².
    pub a_min: f64,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Phase {
    /// Tracking the running maximum `(t, value)`.
    SeekPeak { t: f64, value: f64 },
    /// A peak is confirmed; tracking the running minimum after it.
    SeekValley { peak_t: f64, peak: f64, value: f64 },
}

/// The streaming step detector (no allocation per sample).
#[derive(Debug, Clone)]
pub struct StepDetector {
    config: StepDetectorConfig,
    /// Low-pass time constant `τ = 1 / (2π f_c)`, seconds.
    tau: f64,
    /// The two low-pass stages.
    stage: [f64; 2],
    phase: Phase,
    /// Running mean swing `s̄`, m/s² (0 before the first step of a bout).
    mean_swing: f64,
    /// The last accepted step's peak time.
    last_step_t: Option<f64>,
    /// Pairs rejected because they came sooner than `min_step_period_s`.
    too_soon: usize,
}

impl StepDetector {
    /// A detector; `config` must be valid.
    #[must_use]
    pub fn new(config: &StepDetectorConfig) -> Self {
        Self {
            config: config.clone(),
            tau: 1.0 / (2.0 * PI * config.low_pass_hz),
            stage: [0.0; 2],
            phase: Phase::SeekPeak {
                t: f64::NEG_INFINITY,
                value: f64::NEG_INFINITY,
            },
            mean_swing: 0.0,
            last_step_t: None,
            too_soon: 0,
        }
    }

    /// Restarts the filter at a sample (the first, or the first after a gap): no step spans
    /// the restart. The step history (minimum period) is kept.
    pub fn restart(&mut self, t: f64, magnitude: f64) {
        self.stage = [magnitude; 2];
        self.phase = Phase::SeekPeak {
            t,
            value: magnitude,
        };
    }

    /// Pairs rejected for coming sooner than the minimum step period.
    #[must_use]
    pub fn rejected_too_soon(&self) -> usize {
        self.too_soon
    }

    /// The filtered magnitude after the last sample, m/s².
    #[must_use]
    pub fn filtered(&self) -> f64 {
        self.stage[1]
    }

    /// Feeds one sample taken `dt` seconds after the previous one; returns a step when this
    /// sample confirms one.
    pub fn update(&mut self, t: f64, dt: f64, magnitude: f64) -> Option<DetectedStep> {
        // Two first-order sections, each y += α (x − y), α = dt / (τ + dt).
        let alpha = dt / (self.tau + dt);
        self.stage[0] += alpha * (magnitude - self.stage[0]);
        self.stage[1] += alpha * (self.stage[0] - self.stage[1]);
        let y = self.stage[1];
        // A pause ends the bout: its swing must not hold the threshold up for the next one
        // (a phone handled vigorously, then carried gently, would otherwise stay silent).
        if self
            .last_step_t
            .is_some_and(|last| t - last > self.config.max_step_period_s)
        {
            self.mean_swing = 0.0;
        }
        let threshold = self.threshold();
        let hysteresis = 0.5 * threshold;
        match self.phase {
            Phase::SeekPeak { value, .. } if y > value => {
                self.phase = Phase::SeekPeak { t, value: y };
                None
            }
            Phase::SeekPeak { t: peak_t, value } => {
                if y < value - hysteresis {
                    self.phase = Phase::SeekValley {
                        peak_t,
                        peak: value,
                        value: y,
                    };
                }
                None
            }
            Phase::SeekValley {
                peak_t,
                peak,
                value,
            } => {
                if y < value {
                    self.phase = Phase::SeekValley {
                        peak_t,
                        peak,
                        value: y,
                    };
                    return None;
                }
                if y <= value + hysteresis {
                    return None;
                }
                self.phase = Phase::SeekPeak { t, value: y };
                self.accept(peak_t, peak, value, threshold)
            }
        }
    }

    /// Ends the signal (at a gap or at the end of the recording): a peak followed by a fall
    /// of at least the threshold is a step even though the rise that would confirm its
    /// valley never came. The detector must be restarted before the next sample.
    pub fn flush(&mut self) -> Option<DetectedStep> {
        let Phase::SeekValley {
            peak_t,
            peak,
            value,
        } = self.phase
        else {
            return None;
        };
        self.phase = Phase::SeekPeak {
            t: peak_t,
            value: f64::NEG_INFINITY,
        };
        self.accept(peak_t, peak, value, self.threshold())
    }

    fn threshold(&self) -> f64 {
        self.config
            .min_swing
            .max(self.config.adaptive_fraction * self.mean_swing)
    }

    /// Decides on a confirmed peak–valley pair (eq. 2's thresholds and the minimum period).
    fn accept(&mut self, t: f64, a_max: f64, a_min: f64, threshold: f64) -> Option<DetectedStep> {
        let swing = a_max - a_min;
        if swing < threshold {
            return None;
        }
        if let Some(last) = self.last_step_t
            && t - last < self.config.min_step_period_s
        {
            self.too_soon += 1;
            return None;
        }
        // Running mean over about the last four steps.
        self.mean_swing = if self.mean_swing == 0.0 {
            swing
        } else {
            0.75 * self.mean_swing + 0.25 * swing
        };
        self.last_step_t = Some(t);
        Some(DetectedStep { t, a_max, a_min })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_gentle_bout_after_a_vigorous_one_and_a_pause_is_detected() {
        // 20 s of a phone swung hard (±8 m/s², 2 Hz), 10 s still, 20 s of gentle walking
        // (±1.5 m/s²): the hard swing's threshold must not outlive the pause.
        let mut d = StepDetector::new(&StepDetectorConfig::default());
        let rate = 50.0;
        let mut gentle = 0;
        for i in 0..(50 * 50) {
            let t = f64::from(i) / rate;
            let amp = match t {
                t if t < 20.0 => 8.0,
                t if t < 30.0 => 0.0,
                _ => 1.5,
            };
            let m = 9.81 + amp * (2.0 * PI * 2.0 * t).sin();
            if i == 0 {
                d.restart(t, m);
                continue;
            }
            if d.update(t, 1.0 / rate, m).is_some_and(|s| s.t > 30.0) {
                gentle += 1;
            }
        }
        assert!(
            (36..=41).contains(&gentle),
            "{gentle} steps in 20 s at 2 Hz"
        );
    }

    /// Walking (a 2 Hz, ±`amp` vertical oscillation) for `walk_s`, then still for `still_s`.
    fn count(rate_hz: f64, amp: f64, walk_s: f64, still_s: f64) -> (usize, usize) {
        let mut d = StepDetector::new(&StepDetectorConfig::default());
        let n = ((walk_s + still_s) * rate_hz) as usize;
        let (mut walking, mut still) = (0, 0);
        for i in 0..n {
            let t = i as f64 / rate_hz;
            let a_up = if t < walk_s {
                amp * (2.0 * PI * 2.0 * t).sin()
            } else {
                0.0
            };
            // Phone tilted: gravity split over y and z, the motion along gravity.
            let g = 9.81 + a_up;
            let m = (0.0f64.powi(2) + (0.6 * g).powi(2) + (0.8 * g).powi(2)).sqrt();
            if i == 0 {
                d.restart(t, m);
                continue;
            }
            if let Some(s) = d.update(t, 1.0 / rate_hz, m) {
                if s.t < walk_s + 0.3 {
                    walking += 1;
                } else {
                    still += 1;
                }
            }
        }
        (walking, still)
    }

    #[test]
    fn a_2_hz_walk_of_10_s_gives_20_steps_and_none_while_still() {
        for rate in [50.0, 100.0, 200.0] {
            let (walking, still) = count(rate, 3.0, 10.0, 5.0);
            assert!((19..=21).contains(&walking), "{rate} Hz: {walking} steps");
            assert_eq!(still, 0, "{rate} Hz");
        }
    }

    #[test]
    fn noise_below_the_physical_threshold_is_no_step() {
        // ±0.3 m/s² at 2 Hz: a phone in a still hand.
        assert_eq!(count(100.0, 0.3, 10.0, 0.0), (0, 0));
    }

    #[test]
    fn peaks_closer_than_the_minimum_period_are_one_step() {
        // A 5 Hz oscillation (0.2 s period) is faster than min_step_period_s = 0.28 s: at
        // most every second peak is taken.
        let mut d = StepDetector::new(&StepDetectorConfig::default());
        d.restart(0.0, 9.81);
        let mut steps = 0;
        for i in 1..1000 {
            let t = f64::from(i) * 0.01;
            let m = 9.81 + 4.0 * (2.0 * PI * 5.0 * t).sin();
            steps += usize::from(d.update(t, 0.01, m).is_some());
        }
        assert!(steps <= 26, "{steps}");
        assert!(d.rejected_too_soon() >= 20, "{}", d.rejected_too_soon());
    }

    #[test]
    fn flush_takes_a_peak_whose_valley_was_cut_off() {
        let mut d = StepDetector::new(&StepDetectorConfig::default());
        d.restart(0.0, 9.81);
        // Up to a peak of 12.81 at 0.125 s, then down to 6.96 at 0.35 s, then the end.
        let mut found = None;
        for i in 1..=35 {
            let t = f64::from(i) * 0.01;
            found = found.or(d.update(t, 0.01, 9.81 + 3.0 * (2.0 * PI * 2.0 * t).sin()));
        }
        assert!(found.is_none());
        let s = d.flush().expect("a peak and a fall beyond the threshold");
        assert!(s.a_max - s.a_min > 1.0 && s.t > 0.1 && s.t < 0.35, "{s:?}");
        assert!(d.flush().is_none());
    }

    #[test]
    fn rejects_out_of_range_settings() {
        let c = StepDetectorConfig {
            low_pass_hz: 0.0,
            ..Default::default()
        };
        assert!(c.validate().is_err());
        assert!(StepDetectorConfig::default().validate().is_ok());
    }
}
