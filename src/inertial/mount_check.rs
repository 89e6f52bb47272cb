//! Does the recording look like the mount the user named? A foot in swing turns at 5–10
//! rad/s every stride and strikes the ground at 2–5 g; a phone held in front of the body
//! rarely passes 3–4 rad/s, and one swung in the hand, which can turn as fast (6.9–9.7
//! rad/s at the 99th percentile on the shared museum walks), is not struck: its
//! acceleration's 90th percentile stayed at 11.5–12.7 m/s² where every shared foot walk's
//! was 14.3–46. Running one front end on the other's data gives steps that look plausible
//! one by one and are wrong together (a foot IMU through the phone detector counts two
//! steps a stride; a phone through the foot INS finds almost no strides), so the mismatch
//! is said, not swallowed.

use super::Mount;
use crate::sensor::{ImuRecording, ImuSample};

/// 99th percentile of the angular rate's magnitude above which a recording may be
/// foot-mounted, rad/s (foot walks measured 5.1–11.5; hand-held phones 1.8–4.7, swung
/// ones up to 9.7).
pub const FOOT_SWING_RATE: f64 = 5.5;
/// The same below which a recording cannot be foot-mounted while walking, rad/s.
pub const HAND_HELD_RATE: f64 = 3.0;
/// 90th percentile of the specific force's magnitude above which a recording may be
/// foot-mounted, m/s² (heel strikes: 14.3–46 on the shared foot walks; phones, swung or
/// not, 11.5–12.7).
pub const FOOT_STRIKE_FORCE: f64 = 13.5;

/// The `q`-quantile (0–1) over the recording of the magnitude of the vector `pick` takes
/// from each sample.
fn magnitude_quantile(recording: &ImuRecording, pick: fn(&ImuSample) -> [f64; 3], q: f64) -> f64 {
    let mut values: Vec<f64> = recording
        .samples()
        .iter()
        .map(|s| pick(s).iter().map(|v| v * v).sum::<f64>().sqrt())
        .collect();
    let k = ((values.len() as f64 * q) as usize).min(values.len() - 1);
    *values.select_nth_unstable_by(k, f64::total_cmp).1
}

/// The 99th percentile of `|ω|` over the recording, rad/s.
#[must_use]
pub fn angular_rate_p99(recording: &ImuRecording) -> f64 {
    magnitude_quantile(recording, |s| s.gyro, 0.99)
}

/// The 90th percentile of the specific force's magnitude `|a|` over the recording, m/s².
#[must_use]
pub fn specific_force_p90(recording: &ImuRecording) -> f64 {
    magnitude_quantile(recording, |s| s.accel, 0.9)
}

/// A warning when the recording does not look like `mount`, `None` when it does.
#[must_use]
pub fn check_mount(recording: &ImuRecording, mount: Mount, strides: usize) -> Option<String> {
    let p99 = angular_rate_p99(recording);
    match mount {
        Mount::Phone if p99 > FOOT_SWING_RATE => {
            let p90 = specific_force_p90(recording);
            (p90 > FOOT_STRIKE_FORCE).then(|| {
                format!(
                    "angular rates reach {p99:.1} rad/s (99th percentile) and accelerations \
                     {p90:.1} m/s² (90th), as a foot's swings and heel strikes do; a phone, \
                     even swung in the hand, stays under {FOOT_STRIKE_FORCE} m/s²: is this a \
                     foot-mounted IMU (--mount foot)?"
                )
            })
        }
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

    fn recording(rate: impl Fn(usize) -> f64, force: impl Fn(usize) -> f64) -> ImuRecording {
        let samples = (0..1000)
            .map(|i| ImuSample {
                t: i as f64 * 0.01,
                accel: [0.0, 0.0, force(i)],
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
        // 3 % of the samples at 8 rad/s: the 99th percentile is 8; heel strikes at 30 m/s²
        // on 15 % of the samples.
        let strike = |i: usize| if i % 100 < 15 { 30.0 } else { 9.81 };
        let foot = recording(|i| if i % 100 < 3 { -8.0 } else { 0.5 }, strike);
        assert_eq!(angular_rate_p99(&foot), 8.0);
        assert_eq!(specific_force_p90(&foot), 30.0);
        assert!(check_mount(&foot, Mount::Phone, 10).is_some());
        assert!(check_mount(&foot, Mount::Foot, 10).is_none());
        let hand = recording(|i| (i as f64 * 0.1).sin(), |_| 9.81);
        assert!(check_mount(&hand, Mount::Foot, 10).is_some());
        assert!(check_mount(&hand, Mount::Phone, 10).is_none());
        // A phone swung in the hand turns as fast as a foot, but is not struck.
        let swung = recording(
            |i| if i % 100 < 3 { -8.0 } else { 0.5 },
            |i| 9.81 + (i % 7) as f64 * 0.3,
        );
        assert!(check_mount(&swung, Mount::Phone, 10).is_none());
    }
}
