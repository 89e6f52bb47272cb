//! Does the recording look like the mount the user named? A foot in swing turns at 5–10
//! rad/s every stride; a phone held in front of the body rarely passes 3–4 rad/s. Running
//! one front end on the other's data gives steps that look plausible one by one and are
//! wrong together (a foot IMU through the phone detector counts two steps a stride; a phone
//! through the foot INS finds almost no strides), so the mismatch is said, not swallowed.

use super::Mount;
use crate::sensor::ImuRecording;

/// 99th percentile of the angular rate's magnitude above which a recording looks
/// foot-mounted, rad/s (foot walks measured 6.2–9.4; hand-held phones 1.8–4.7).
pub const FOOT_SWING_RATE: f64 = 5.5;
/// The same below which a recording cannot be foot-mounted while walking, rad/s.
pub const HAND_HELD_RATE: f64 = 3.0;

/// The 99th percentile of `|ω|` over the recording, rad/s.
pub fn angular_rate_p99(recording: &ImuRecording) -> f64 {
    let mut rates: Vec<f64> = recording
        .samples()
        .iter()
        .map(|s| s.gyro.iter().map(|w| w * w).sum::<f64>().sqrt())
        .collect();
    let k = ((rates.len() as f64 * 0.99) as usize).min(rates.len() - 1);
    *rates.select_nth_unstable_by(k, f64::total_cmp).1
}

/// A warning when the recording does not look like `mount`, `None` when it does.
pub fn check_mount(recording: &ImuRecording, mount: Mount, strides: usize) -> Option<String> {
    let p99 = angular_rate_p99(recording);
    match mount {
        Mount::Phone if p99 > FOOT_SWING_RATE => Some(format!(
            "angular rates reach {p99:.1} rad/s (99th percentile), as a foot in swing does; a \
             hand-held phone rarely passes {HAND_HELD_RATE} rad/s: is this a foot-mounted IMU \
             (--mount foot)?"
        )),
        Mount::Foot if p99 < HAND_HELD_RATE && strides > 0 => Some(format!(
            "angular rates stay below {p99:.1} rad/s (99th percentile); a foot in swing turns \
             at 5–10 rad/s every stride: is this a hand-held phone (--mount phone)?"
        )),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::ImuSample;

    fn recording(rate: impl Fn(usize) -> f64) -> ImuRecording {
        let samples = (0..1000)
            .map(|i| ImuSample {
                t: i as f64 * 0.01,
                accel: [0.0, 0.0, 9.81],
                gyro: [0.0, rate(i), 0.0],
                mag: None,
                orientation: None,
                pressure: None,
            })
            .collect();
        ImuRecording::new(samples, 0).expect("valid")
    }

    #[test]
    fn a_swinging_foot_is_not_a_phone_and_a_calm_hand_is_not_a_foot() {
        // 3 % of the samples at 8 rad/s: the 99th percentile is 8.
        let foot = recording(|i| if i % 100 < 3 { -8.0 } else { 0.5 });
        assert_eq!(angular_rate_p99(&foot), 8.0);
        assert!(check_mount(&foot, Mount::Phone, 10).is_some());
        assert!(check_mount(&foot, Mount::Foot, 10).is_none());
        let hand = recording(|i| (i as f64 * 0.1).sin());
        assert!(check_mount(&hand, Mount::Foot, 10).is_some());
        assert!(check_mount(&hand, Mount::Phone, 10).is_none());
    }
}
