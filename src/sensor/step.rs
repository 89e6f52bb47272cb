//! Pedestrian step events from a step detector or a foot-mounted INS (the "step vector
//! measurement" `Z^U_k` of Robertson et al. 2009, Fig. 5).

use serde::{Deserialize, Serialize};

/// One step event.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Step {
    /// Time of the step, seconds (any epoch, strictly increasing along a trace).
    pub t: f64,
    /// Stride length, metres.
    pub length: f64,
    /// Heading change since the previous step, radians counter-clockwise.
    pub dheading: f64,
    /// Height change, metres (0 when not measured).
    pub dz: f64,
    /// Absolute heading, radians counter-clockwise from east, when a compass gives one.
    pub heading: Option<f64>,
}

/// A validated sequence of steps: times strictly increasing, all values finite, lengths in
/// `[0, MAX_STEP_LENGTH]`.
///
/// Steps checked as a trace is made, and dead-reckoned:
///
/// ```
/// use footslam::geometry::Pose2;
/// use footslam::sensor::{Step, StepTrace};
/// use std::f64::consts::FRAC_PI_2;
///
/// let step = |t: f64, dheading: f64| Step { t, length: 1.0, dheading, dz: 0.0, heading: None };
/// let trace = StepTrace::new(vec![step(0.0, 0.0), step(0.5, 0.0), step(1.0, FRAC_PI_2)])
///     .expect("valid steps");
/// // Two metres east, then a left turn and one metre north.
/// let poses = trace.dead_reckon(Pose2::default());
/// assert!((poses[2].x - 2.0).abs() < 1e-12 && (poses[2].y - 1.0).abs() < 1e-12);
///
/// // The error names the step (0-based) and the rule.
/// let (index, problem) = StepTrace::new(vec![step(1.0, 0.0), step(1.0, 0.0)]).unwrap_err();
/// assert_eq!(index, 1);
/// assert!(problem.contains("strictly increasing"));
/// let (_, problem) = StepTrace::new(vec![step(0.0, 90.0)]).unwrap_err();
/// assert!(problem.contains("degrees?"));
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StepTrace {
    steps: Vec<Step>,
}

/// Longest plausible single stride, metres (running strides reach about 2.5 m).
pub const MAX_STEP_LENGTH: f64 = 3.0;
/// Largest plausible height change in one step, metres.
pub const MAX_STEP_DZ: f64 = 1.0;

/// Largest plausible time stamp, seconds (about the year 5100 in Unix seconds): a larger one
/// is another unit (Unix milliseconds are about 1.7e12) or a corrupt value.
pub const MAX_TIME_S: f64 = 1e11;

/// Why a time stamp `t` (seconds) is implausible, if it is.
///
/// # Errors
///
/// A message with the likely unit mistake when `|t|` exceeds [`MAX_TIME_S`].
pub fn check_time(t: f64) -> Result<(), String> {
    if t.abs() > MAX_TIME_S {
        return Err(format!(
            "time {t:e} s is beyond {MAX_TIME_S:e} s: times must be in seconds (Unix seconds are about 1.7e9; milliseconds would be about 1.7e12)"
        ));
    }
    Ok(())
}

/// Why a step is implausible, if it is.
///
/// # Errors
///
/// A message naming the value and the rule when a value is not finite, the time fails
/// [`check_time`], the length is outside [0, [`MAX_STEP_LENGTH`]] m, the heading change or the
/// absolute heading exceeds a full turn (degrees?), `dz` exceeds [`MAX_STEP_DZ`], or the time is
/// not after `previous_t`.
pub fn check_step(step: &Step, previous_t: Option<f64>) -> Result<(), String> {
    let finite = [step.t, step.length, step.dheading, step.dz];
    if finite.iter().any(|v| !v.is_finite()) || step.heading.is_some_and(|h| !h.is_finite()) {
        return Err("values must be finite numbers (found NaN or infinity)".into());
    }
    check_time(step.t)?;
    if !(0.0..=MAX_STEP_LENGTH).contains(&step.length) {
        return Err(format!(
            "step length {} m is outside [0, {MAX_STEP_LENGTH}] m",
            crate::error::short_number(step.length)
        ));
    }
    if step.dheading.abs() > 2.0 * std::f64::consts::PI {
        return Err(format!(
            "heading change {} rad exceeds one full turn (radians are expected: degrees? \
             multiply by π/180)",
            crate::error::short_number(step.dheading)
        ));
    }
    if let Some(h) = step.heading
        && h.abs() > 2.0 * std::f64::consts::PI
    {
        return Err(format!(
            "absolute heading {} rad is beyond one full turn: headings are radians \
             counter-clockwise from east (degrees? multiply by π/180)",
            crate::error::short_number(h)
        ));
    }
    if step.dz.abs() > MAX_STEP_DZ {
        return Err(format!(
            "height change {} m exceeds {MAX_STEP_DZ} m per step",
            crate::error::short_number(step.dz)
        ));
    }
    if let Some(p) = previous_t
        && step.t <= p
    {
        return Err(format!(
            "time {} s is not after the previous step's {} s (times must be strictly increasing)",
            step.t, p
        ));
    }
    Ok(())
}

impl StepTrace {
    /// A trace from steps, checked with [`check_step`]; the error names the 0-based index.
    ///
    /// # Errors
    ///
    /// The first step that fails [`check_step`] (against the step before it), as its 0-based index
    /// and the message.
    pub fn new(steps: Vec<Step>) -> Result<Self, (usize, String)> {
        let mut previous = None;
        for (i, s) in steps.iter().enumerate() {
            check_step(s, previous).map_err(|m| (i, m))?;
            previous = Some(s.t);
        }
        Ok(Self { steps })
    }

    /// The steps, in time order.
    #[must_use]
    pub fn steps(&self) -> &[Step] {
        &self.steps
    }

    /// Number of steps.
    #[must_use]
    pub fn len(&self) -> usize {
        self.steps.len()
    }

    /// Steps that carry an absolute heading.
    #[must_use]
    pub fn with_heading(&self) -> usize {
        self.steps.iter().filter(|s| s.heading.is_some()).count()
    }

    /// True when there are no steps.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.steps.is_empty()
    }

    /// Dead-reckoned poses from `start`, one per step (after the step), by
    /// Woodman & Harle eq. 9–11 ([`dead_reckon`]).
    #[must_use]
    pub fn dead_reckon(&self, start: crate::geometry::Pose2) -> Vec<crate::geometry::Pose2> {
        dead_reckon(&self.steps, start)
    }
}

/// `steps` dead-reckoned from `start`, one pose per step (after the step), by Woodman &
/// Harle eq. 9–11.
#[must_use]
pub fn dead_reckon(steps: &[Step], start: crate::geometry::Pose2) -> Vec<crate::geometry::Pose2> {
    let mut pose = start;
    steps
        .iter()
        .map(|s| {
            pose = pose.step(s.length, s.dheading);
            pose
        })
        .collect()
}

/// The share of the step from the step event at `previous` to the one at `t` walked at
/// `at` (clamped to [0, 1]); 0 for the first step, whose measurements apply at the start
/// pose.
#[must_use]
pub fn share_of_step(previous: Option<f64>, t: f64, at: f64) -> f64 {
    match previous {
        Some(t0) if t > t0 => ((at - t0) / (t - t0)).clamp(0.0, 1.0),
        _ => 0.0,
    }
}

/// Where time `at` falls along `steps` (in time order): the index of the first step at or
/// after it (`steps.len()` past the last) and the share of that step walked by then
/// ([`share_of_step`]; 0 before the first step).
#[must_use]
pub fn step_at_time(steps: &[Step], at: f64) -> (usize, f64) {
    let k = steps.partition_point(|s| s.t < at);
    let along = match steps.get(k) {
        Some(step) => share_of_step(k.checked_sub(1).map(|j| steps[j].t), step.t, at),
        None => 0.0,
    };
    (k, along)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn step(t: f64, length: f64) -> Step {
        Step {
            t,
            length,
            dheading: 0.0,
            dz: 0.0,
            heading: None,
        }
    }

    #[test]
    fn rejects_unsorted_times_nan_and_absurd_lengths() {
        assert!(StepTrace::new(vec![step(0.0, 0.7), step(1.0, 0.7)]).is_ok());
        assert_eq!(
            StepTrace::new(vec![step(1.0, 0.7), step(1.0, 0.7)])
                .unwrap_err()
                .0,
            1
        );
        assert!(StepTrace::new(vec![step(0.0, f64::NAN)]).is_err());
        assert!(StepTrace::new(vec![step(0.0, 12.0)]).is_err());
        assert!(StepTrace::new(vec![step(0.0, -0.1)]).is_err());
        // Angles in degrees are caught when they leave one turn, and said so.
        let mut degrees = step(0.0, 0.7);
        degrees.heading = Some(135.0);
        let (_, m) = StepTrace::new(vec![degrees]).unwrap_err();
        assert!(
            m.contains("absolute heading 135 rad") && m.contains("degrees?"),
            "{m}"
        );
        let mut turn = step(0.0, 0.7);
        turn.dheading = 90.0;
        let (_, m) = StepTrace::new(vec![turn]).unwrap_err();
        assert!(m.contains("degrees?"), "{m}");
        let mut huge = step(0.0, 0.7);
        huge.dz = 1e308;
        let (_, m) = StepTrace::new(vec![huge]).unwrap_err();
        assert!(m.contains("1e308 m"), "{m}");
    }

    #[test]
    fn dead_reckoning_follows_eq_9_to_11() {
        let mut s = vec![step(0.0, 1.0), step(1.0, 1.0)];
        s[1].dheading = std::f64::consts::FRAC_PI_2;
        let poses = StepTrace::new(s)
            .expect("valid")
            .dead_reckon(Default::default());
        assert!((poses[1].x - 1.0).abs() < 1e-12 && (poses[1].y - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_time_falls_in_the_step_that_ends_at_or_after_it() {
        let step = |t: f64| Step {
            t,
            length: 0.7,
            dheading: 0.0,
            dz: 0.0,
            heading: None,
        };
        let steps = [step(1.0), step(2.0), step(3.0)];
        assert_eq!(step_at_time(&steps, 0.5), (0, 0.0));
        assert_eq!(step_at_time(&steps, 1.0), (0, 0.0));
        assert_eq!(step_at_time(&steps, 1.25), (1, 0.25));
        assert_eq!(step_at_time(&steps, 3.0), (2, 1.0));
        assert_eq!(step_at_time(&steps, 9.0), (3, 0.0));
    }
}
