//! Is the gyroscope in the accelerometer's frame, and are the timestamps in seconds? A
//! recording logged in a left-handed frame, or with one gyroscope axis inverted, or stamped
//! in other units than it says, gives step events that look plausible one by one and are
//! wrong together, so it is detected from the data and said, with the way out.
//!
//! * **Foot.** At every stance the zero-velocity update measures how far the strapdown
//!   velocity has drifted since the last one (`FootFigures::mean_zupt_residual`). With the
//!   gyroscope in the accelerometer's frame it stayed at 0.002–0.019 m/s on every shared
//!   foot walk (6 hallway, 8 Vicon); with any one axis or all three negated, gravity leaks
//!   into the velocity during each swing and it rose to 0.09–0.27 m/s (3 walks × 3 axes).
//!   Above [`FOOT_ZUPT_RESIDUAL_MAX`] the INS is run again with each axis, and all three,
//!   negated: a flip that brings the residual under the bound names the axis.
//! * **Phone with an orientation quaternion.** Between two samples the quaternion turns by
//!   the body rates the gyroscope integrates (`q̇ = ½ q ⊗ ω`). Regressed per axis over
//!   0.1 s windows, the quaternion turns 0.88–0.97 times as far as the gyroscope, with
//!   correlation 0.85–0.94, on a real phone walk; a negated axis gives the opposite sign,
//!   and timestamps stretched by a factor `k` make the gyroscope turn `k` times as far.
//!   A quaternion written the wrong way (its inverse, ENU → sensor; or `w, x, y, z` in the
//!   `qx, qy, qz, qw` columns) correlates poorly on some axes and well once undone: each
//!   mistake is tried before any gyroscope axis is blamed.
//!
//!   Some phones' quaternions are noisy about one axis (a yaw pulled by the magnetometer
//!   indoors): on a third of the ILC site-1 F1 walks (one phone's), the worst axis correlates
//!   at only 0.10–0.5, still positive. There the least-squares gain (the quaternion's turn
//!   regressed on the gyroscope's) shrinks with the correlation (1.5–2.0 seen, near a ×2
//!   time base's 2.1), while the ratio of the two turns' root mean squares (1.06–1.21) grows
//!   with the quaternion's noise instead. A time base is wrong only when both say so, and
//!   axes that agree however weakly (every correlation positive) are not called disagreeing.

use super::foot::detect_strides;
use super::foot_config::FootConfig;
use crate::sensor::ImuRecording;

/// Mean stance velocity residual above which a foot recording's gyroscope looks out of the
/// accelerometer's frame, m/s (measured: at most 0.019 right, at least 0.089 mirrored).
pub const FOOT_ZUPT_RESIDUAL_MAX: f64 = 0.045;

/// Correlation between the quaternion's and the gyroscope's rotation on one axis below
/// which that axis counts as negated (right: 0.85 and more).
pub const MIRRORED_CORRELATION: f64 = -0.5;

/// Correlation on every axis above which the gyroscope and the quaternion agree (right:
/// 0.85 and more).
pub const CONSISTENT_CORRELATION: f64 = 0.5;

/// Gains of the gyroscope against the quaternion outside this range, by both estimates
/// ([`AxisAgreement::gains`]), mean the timestamps do not count seconds at the rate the
/// samples came (right, over the 106 ILC site-1 F1 walks: root-mean-square ratio 0.55–1.24,
/// least squares 1.00–1.97, never both outside; timestamps ×2 or ×½ give 2.1 and 0.56).
pub const GAIN_RANGE: std::ops::RangeInclusive<f64> = 0.7..=1.4;

/// A way an orientation quaternion's columns are commonly written wrong.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum QuaternionMistake {
    /// The inverse rotation, ENU → sensor (`qx, qy, qz` negated).
    Conjugated,
    /// `w, x, y, z` written into the `qx, qy, qz, qw` columns.
    ScalarFirst,
}

impl QuaternionMistake {
    /// The quaternion `[x, y, z, w]` as read, with the mistake undone.
    #[must_use]
    pub fn undo(self, q: [f64; 4]) -> [f64; 4] {
        match self {
            Self::Conjugated => [-q[0], -q[1], -q[2], q[3]],
            Self::ScalarFirst => [q[1], q[2], q[3], q[0]],
        }
    }
}

/// Window of the phone's quaternion-against-gyroscope regression, seconds.
const WINDOW_S: f64 = 0.1;

/// Fewer windows than this (or too little rotation) say nothing.
const MIN_WINDOWS: usize = 50;

/// What the data say about the recording's frame or time base.
#[derive(Debug, Clone, PartialEq)]
pub enum FrameFinding {
    /// Negating the gyroscope axes `flip` (x, y, z) makes the recording consistent.
    MirroredGyro {
        /// The axes to negate.
        flip: [bool; 3],
        /// The inconsistency as recorded and after the flip (foot: m/s; phone: the
        /// axes' correlations, as recorded).
        before: f64,
        /// After the flip.
        after: f64,
    },
    /// The gyroscope turns `gain` times as far as the orientation quaternion between the
    /// same samples: the timestamps are not in seconds, or the rate is not what they say.
    TimeBase {
        /// Median gain over the three axes.
        gain: f64,
    },
    /// The orientation quaternion agrees with the gyroscope once `mistake` is undone.
    Quaternion {
        /// The mistake.
        mistake: QuaternionMistake,
        /// The worst axis's correlation as recorded.
        before: f64,
        /// The same with the mistake undone.
        after: f64,
    },
    /// The gyroscope and the orientation quaternion disagree, and neither an axis flip nor
    /// a quaternion mistake explains it.
    Disagreeing {
        /// The worst axis's correlation.
        correlation: f64,
    },
    /// The foot INS's stance residual is far above a foot IMU's and no axis flip explains
    /// it (units, timestamps or a recording that is not a foot's).
    Inconsistent {
        /// Mean stance velocity residual, m/s.
        residual: f64,
    },
}

impl FrameFinding {
    /// The finding in words, with the way out.
    #[must_use]
    pub fn message(&self) -> String {
        match self {
            Self::MirroredGyro {
                flip,
                before,
                after,
            } => format!(
                "the gyroscope's {} mirrored against the accelerometer's frame (a \
                 left-handed frame, or inverted axes): negated, the recording becomes \
                 consistent ({before:.3} → {after:.3}); pass --gyro-flip {}, or negate those \
                 columns",
                axes_words(*flip),
                axes_flag(*flip)
            ),
            Self::TimeBase { gain } => format!(
                "the gyroscope turns {gain:.2} times as far as the orientation quaternion \
                 between the same samples: the timestamps are not in seconds, or the samples \
                 came at another rate than the timestamps say"
            ),
            Self::Quaternion {
                mistake: QuaternionMistake::Conjugated,
                before,
                after,
            } => format!(
                "the orientation quaternion turns as the inverse of the gyroscope's rotation \
                 (worst axis correlation {before:.2} as recorded, {after:.2} conjugated): it \
                 looks like the rotation ENU → sensor, where the format takes sensor → ENU; \
                 negate the qx, qy, qz columns"
            ),
            Self::Quaternion {
                mistake: QuaternionMistake::ScalarFirst,
                before,
                after,
            } => format!(
                "the orientation quaternion's columns look to hold w, x, y, z (worst axis \
                 correlation with the gyroscope {before:.2} as recorded, {after:.2} read that \
                 way); the format's order is qx, qy, qz, qw: reorder the columns"
            ),
            Self::Disagreeing { correlation } => format!(
                "the gyroscope and the orientation quaternion disagree (worst axis \
                 correlation {correlation:.2}; a phone's agree at 0.85 and more), and no \
                 gyroscope axis flip or quaternion convention explains it: check the columns"
            ),
            Self::Inconsistent { residual } => format!(
                "the foot INS's mean stance velocity residual is {residual:.3} m/s, far above \
                 a foot IMU's (at most {FOOT_ZUPT_RESIDUAL_MAX} m/s); no gyroscope axis flip \
                 explains it: check the units, the timestamps and that the IMU was on a foot"
            ),
        }
    }
}

/// `x`, `y`, `z` letters of the axes set in `flip` (`--gyro-flip`'s value).
#[must_use]
pub fn axes_flag(flip: [bool; 3]) -> String {
    ["x", "y", "z"]
        .iter()
        .zip(flip)
        .filter(|(_, f)| *f)
        .map(|(a, _)| *a)
        .collect()
}

fn axes_words(flip: [bool; 3]) -> String {
    let axes = axes_flag(flip);
    match axes.len() {
        1 => format!("{axes} axis looks"),
        _ => format!(
            "{} axes look",
            axes.chars()
                .map(String::from)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// Parses `--gyro-flip`'s value: any of `x`, `y`, `z`, each at most once.
///
/// # Errors
///
/// A message when `text` names a character other than `x`, `y`, `z`, names an axis twice, or is
/// empty.
pub fn parse_axes(text: &str) -> Result<[bool; 3], String> {
    let mut flip = [false; 3];
    for c in text.chars() {
        let i = match c.to_ascii_lowercase() {
            'x' => 0,
            'y' => 1,
            'z' => 2,
            _ => {
                return Err(format!(
                    "`{text}`: expected axes among x, y, z (e.g. `y` or `xyz`)"
                ));
            }
        };
        if flip[i] {
            return Err(format!("`{text}`: axis {c} named twice"));
        }
        flip[i] = true;
    }
    if flip == [false; 3] {
        return Err("expected at least one axis among x, y, z".into());
    }
    Ok(flip)
}

/// Checks a foot recording whose INS gave `residual` (mean stance velocity residual, m/s):
/// `None` below [`FOOT_ZUPT_RESIDUAL_MAX`]; else the flip that explains it, or
/// [`FrameFinding::Inconsistent`].
#[must_use]
pub fn check_foot_frame(
    recording: &ImuRecording,
    config: &FootConfig,
    residual: f64,
) -> Option<FrameFinding> {
    if residual.is_nan() || residual <= FOOT_ZUPT_RESIDUAL_MAX {
        return None;
    }
    let flips = [
        [true, false, false],
        [false, true, false],
        [false, false, true],
        [true, true, true],
    ];
    let best = flips
        .iter()
        .filter_map(|&flip| {
            let events = detect_strides(&recording.with_gyro_flipped(flip), config).ok()?;
            let r = events.figures.mean_zupt_residual;
            (events.figures.strides > 0 && r.is_finite()).then_some((flip, r))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1));
    Some(match best {
        Some((flip, after)) if after <= FOOT_ZUPT_RESIDUAL_MAX => FrameFinding::MirroredGyro {
            flip,
            before: residual,
            after,
        },
        _ => FrameFinding::Inconsistent { residual },
    })
}

/// How the quaternion's rotation about one body axis follows the gyroscope's, over 0.1 s
/// windows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisAgreement {
    /// Least-squares gain of the quaternion's turn on the gyroscope's (shrinks as the
    /// quaternion lags or smooths).
    pub slope: f64,
    /// Their correlation.
    pub correlation: f64,
    /// The quaternion's root-mean-square turn over the gyroscope's (grows with the
    /// quaternion's noise).
    pub rms_ratio: f64,
}

impl AxisAgreement {
    /// How far the gyroscope turns per the quaternion's turn, by both estimates: least
    /// squares, then root mean squares.
    #[must_use]
    pub fn gains(&self) -> [f64; 2] {
        [1.0 / self.slope, 1.0 / self.rms_ratio]
    }
}

/// Per-axis agreement of the quaternion's rotation with the gyroscope's over 0.1 s windows;
/// `None` without a quaternion or with too little rotation.
#[must_use]
pub fn gyro_against_orientation(recording: &ImuRecording) -> Option<[AxisAgreement; 3]> {
    gyro_against(recording, |q| q)
}

/// [`gyro_against_orientation`] with each quaternion first passed through `read`.
fn gyro_against(
    recording: &ImuRecording,
    read: impl Fn([f64; 4]) -> [f64; 4],
) -> Option<[AxisAgreement; 3]> {
    let samples = recording.samples();
    let span = samples.last()?.t - samples.first()?.t;
    let rate = (samples.len() - 1) as f64 / span;
    let lag = ((WINDOW_S * rate).round() as usize).max(1);
    if samples.len() < lag * MIN_WINDOWS || !recording.has_orientation() {
        return None;
    }
    // Integrated gyroscope rotation (trapezoid) since the first sample.
    let mut integral = Vec::with_capacity(samples.len());
    let mut acc = [0.0f64; 3];
    integral.push(acc);
    for w in samples.windows(2) {
        let dt = w[1].t - w[0].t;
        for (a, (g0, g1)) in acc.iter_mut().zip(w[0].gyro.iter().zip(&w[1].gyro)) {
            *a += 0.5 * (g0 + g1) * dt;
        }
        integral.push(acc);
    }
    let (mut qg, mut gg, mut qq) = ([0.0f64; 3], [0.0f64; 3], [0.0f64; 3]);
    for k in lag..samples.len() {
        let (Some(a), Some(b)) = (samples[k - lag].orientation, samples[k].orientation) else {
            return None;
        };
        let d = relative_rotation(read(a), read(b));
        for i in 0..3 {
            let g = integral[k][i] - integral[k - lag][i];
            qg[i] += d[i] * g;
            gg[i] += g * g;
            qq[i] += d[i] * d[i];
        }
    }
    let mut out = [AxisAgreement {
        slope: 0.0,
        correlation: 0.0,
        rms_ratio: 0.0,
    }; 3];
    for i in 0..3 {
        if !(gg[i] > 1e-6 && qq[i] > 1e-6) {
            return None;
        }
        out[i] = AxisAgreement {
            slope: qg[i] / gg[i],
            correlation: qg[i] / (gg[i] * qq[i]).sqrt(),
            rms_ratio: (qq[i] / gg[i]).sqrt(),
        };
    }
    Some(out)
}

/// The rotation vector (body frame) from orientation `a` to `b`, quaternions `[x, y, z, w]`:
/// `2 · vec(a* ⊗ b)` (small angles), on the short way round.
fn relative_rotation(a: [f64; 4], b: [f64; 4]) -> [f64; 3] {
    let [ax, ay, az, aw] = a;
    let [bx, by, bz, bw] = b;
    // a* ⊗ b with a* = (-ax, -ay, -az, aw).
    let w = aw * bw + ax * bx + ay * by + az * bz;
    let x = aw * bx - ax * bw - ay * bz + az * by;
    let y = aw * by + ax * bz - ay * bw - az * bx;
    let z = aw * bz - ax * by + ay * bx - az * bw;
    let s = if w < 0.0 { -2.0 } else { 2.0 };
    [s * x, s * y, s * z]
}

/// Checks a phone recording with an orientation quaternion: a quaternion written the
/// wrong way, a negated gyroscope axis, or timestamps that do not count seconds. `None` when
/// consistent or when the data cannot tell (no quaternion, too little rotation).
pub fn check_phone_frame(recording: &ImuRecording) -> Option<FrameFinding> {
    let axes = gyro_against_orientation(recording)?;
    let worst = |axes: &[AxisAgreement; 3]| {
        axes.iter()
            .map(|a| a.correlation)
            .fold(f64::INFINITY, f64::min)
    };
    let consistent = |axes: &[AxisAgreement; 3]| worst(axes) > CONSISTENT_CORRELATION;
    if !consistent(&axes) {
        for mistake in [
            QuaternionMistake::Conjugated,
            QuaternionMistake::ScalarFirst,
        ] {
            if let Some(undone) = gyro_against(recording, |q| mistake.undo(q))
                && consistent(&undone)
            {
                return Some(FrameFinding::Quaternion {
                    mistake,
                    before: worst(&axes),
                    after: worst(&undone),
                });
            }
        }
        let flip = axes.map(|a| a.correlation < MIRRORED_CORRELATION);
        let after = axes
            .iter()
            .map(|a| a.correlation.abs())
            .fold(f64::INFINITY, f64::min);
        if flip.contains(&true) && after > CONSISTENT_CORRELATION {
            return Some(FrameFinding::MirroredGyro {
                flip,
                before: worst(&axes),
                after,
            });
        }
        if worst(&axes) <= 0.0 {
            return Some(FrameFinding::Disagreeing {
                correlation: worst(&axes),
            });
        }
        // Every axis agrees, some weakly: a noisy quaternion, judged by the gains below.
    }
    // Each estimate's gain on the middle axis; the time base is wrong when both are out of
    // range on the same side. The least-squares gain is reported: on a clean recording it is
    // the nearer (timestamps ×2 on a museum walk: 2.1, the root-mean-square ratio 1.87).
    let middle = |k: usize| {
        let mut g = axes.map(|a| a.gains()[k]);
        g.sort_by(f64::total_cmp);
        g[1]
    };
    let (least_squares, rms) = (middle(0), middle(1));
    let (lo, hi) = (*GAIN_RANGE.start(), *GAIN_RANGE.end());
    let wrong = (least_squares > hi && rms > hi) || (least_squares < lo && rms < lo);
    wrong.then_some(FrameFinding::TimeBase {
        gain: least_squares,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::ImuSample;
    use std::f64::consts::PI;

    /// A phone turning about each axis in turn, its quaternion integrated from the same
    /// rates (`q̇ = ½ q ⊗ ω`), 100 Hz for 20 s.
    fn turning_phone(time_scale: f64) -> ImuRecording {
        phone(time_scale, 0.0, 0.0)
    }

    /// [`turning_phone`] swaying at 2 Hz as a walker's does, its quaternion integrated from
    /// rates low-passed with time constant `lag_s` and jittered about the vertical axis by
    /// up to `yaw_noise` rad per sample: a fused orientation that lags and is pulled by the
    /// magnetometer.
    fn phone(time_scale: f64, lag_s: f64, yaw_noise: f64) -> ImuRecording {
        let mut q = [0.0, 0.0, 0.0, 1.0f64];
        let mut smoothed = [0.0f64; 3];
        let dt = 0.01;
        let alpha = if lag_s > 0.0 { dt / (lag_s + dt) } else { 1.0 };
        let samples = (0..2000)
            .map(|k| {
                let t = f64::from(k) * dt;
                let sway = if lag_s > 0.0 {
                    (4.0 * PI * t).sin()
                } else {
                    0.0
                };
                let w = [
                    0.8 * (1.3 * t).sin() + 1.5 * sway,
                    0.6 * (0.7 * t + 1.0).sin() + 1.0 * sway,
                    0.9 * (0.45 * t + 2.0).cos() + 0.5 * sway,
                ];
                // A deterministic jitter in [-1, 1) per axis, the vertical's the largest.
                let jitter = |axis: f64| {
                    ((f64::from(k) * 12.9898 + axis * 78.233).sin() * 43_758.545).fract()
                };
                let e = [0.25, 0.25, 0.5].map(|share| share * yaw_noise);
                let p = [
                    e[0] * jitter(0.0),
                    e[1] * jitter(1.0),
                    e[2] * jitter(2.0),
                    1.0,
                ];
                let n = p.iter().map(|v| v * v).sum::<f64>().sqrt();
                let [px, py, pz, pw] = p.map(|v| v / n);
                let [qx, qy, qz, qw] = q;
                let sample = ImuSample {
                    t: 1.7e9 + t * time_scale,
                    accel: [0.1, 0.2, 9.8],
                    gyro: w,
                    mag: None,
                    // q ⊗ (a small random turn).
                    orientation: Some([
                        qw * px + qx * pw + qy * pz - qz * py,
                        qw * py - qx * pz + qy * pw + qz * px,
                        qw * pz + qx * py - qy * px + qz * pw,
                        qw * pw - qx * px - qy * py - qz * pz,
                    ]),
                    pressure: None,
                };
                for (m, v) in smoothed.iter_mut().zip(w) {
                    *m += alpha * (v - *m);
                }
                // q ← q ⊗ exp(ω dt / 2)
                let [x, y, z] = smoothed.map(|v| 0.5 * v * dt);
                let [qx, qy, qz, qw] = q;
                q = [
                    qw * x + qx + qy * z - qz * y,
                    qw * y - qx * z + qy + qz * x,
                    qw * z + qx * y - qy * x + qz,
                    qw - qx * x - qy * y - qz * z,
                ];
                let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
                q = q.map(|v| v / n);
                sample
            })
            .collect();
        ImuRecording::new(samples, 0).expect("recording")
    }

    #[test]
    fn a_lagging_noisy_quaternion_is_not_a_wrong_time_base() {
        // As some real phones' (ILC site 1 F1: least squares 1.5–2.0, root mean squares
        // 1.06–1.21, worst correlation 0.55–0.7): the least-squares gain alone would call
        // the timestamps wrong, the root-mean-square ratio does not.
        let r = phone(1.0, 0.1, 0.1);
        let axes = gyro_against_orientation(&r).expect("enough rotation");
        let middle = |k: usize| {
            let mut g = axes.map(|a| a.gains()[k]);
            g.sort_by(f64::total_cmp);
            g[1]
        };
        assert!(middle(0) > *GAIN_RANGE.end(), "{axes:?}");
        assert!(GAIN_RANGE.contains(&middle(1)), "{axes:?}");
        assert_eq!(check_phone_frame(&r), None);
        // Weaker still (a correlation of 0.16 about the vertical), yet every axis agrees.
        let noisier = phone(1.0, 0.1, 0.4);
        let worst = gyro_against_orientation(&noisier)
            .expect("enough rotation")
            .iter()
            .map(|a| a.correlation)
            .fold(1.0, f64::min);
        assert!(worst > 0.0 && worst < CONSISTENT_CORRELATION, "{worst}");
        assert_eq!(check_phone_frame(&noisier), None);
        // Its timestamps doubled are still caught (halved, both estimates cannot tell a
        // phone this noisy from a right one: the least-squares gain falls to 0.9).
        assert!(matches!(
            check_phone_frame(&phone(2.0, 0.1, 0.1)),
            Some(FrameFinding::TimeBase { .. })
        ));
    }

    #[test]
    fn a_consistent_phone_passes_and_gains_are_one() {
        let r = turning_phone(1.0);
        let axes = gyro_against_orientation(&r).expect("enough rotation");
        for a in axes {
            assert!(
                a.gains().iter().all(|g| (g - 1.0).abs() < 0.05) && a.correlation > 0.99,
                "{axes:?}"
            );
        }
        assert_eq!(check_phone_frame(&r), None);
    }

    #[test]
    fn a_negated_axis_is_named_and_a_wrong_time_base_measured() {
        let r = turning_phone(1.0).with_gyro_flipped([false, true, false]);
        match check_phone_frame(&r) {
            Some(FrameFinding::MirroredGyro { flip, .. }) => {
                assert_eq!(flip, [false, true, false]);
            }
            other => panic!("{other:?}"),
        }
        let slow = turning_phone(3.0);
        match check_phone_frame(&slow) {
            Some(FrameFinding::TimeBase { gain }) => assert!((gain - 3.0).abs() < 0.2, "{gain}"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_quaternion_written_the_wrong_way_is_named_not_the_gyroscope() {
        let r = turning_phone(1.0);
        let rewritten = |mistake: QuaternionMistake| {
            // Writing the mistake: its inverse applied to the right quaternion.
            let write = |q: [f64; 4]| match mistake {
                QuaternionMistake::Conjugated => [-q[0], -q[1], -q[2], q[3]],
                QuaternionMistake::ScalarFirst => [q[3], q[0], q[1], q[2]],
            };
            let samples = r
                .samples()
                .iter()
                .map(|s| ImuSample {
                    orientation: s.orientation.map(write),
                    ..*s
                })
                .collect();
            ImuRecording::new(samples, 0).expect("recording")
        };
        for mistake in [
            QuaternionMistake::Conjugated,
            QuaternionMistake::ScalarFirst,
        ] {
            match check_phone_frame(&rewritten(mistake)) {
                Some(f @ FrameFinding::Quaternion { mistake: m, .. }) => {
                    assert_eq!(m, mistake);
                    assert!(f.message().contains("quaternion"), "{}", f.message());
                }
                other => panic!("{mistake:?}: {other:?}"),
            }
        }
        // Timestamps ×2 and ×½ (the gain check's old bounds) are caught.
        for k in [2.0, 0.5] {
            assert!(
                matches!(
                    check_phone_frame(&turning_phone(k)),
                    Some(FrameFinding::TimeBase { .. })
                ),
                "{k}"
            );
        }
    }

    #[test]
    fn axes_parse_and_print() {
        assert_eq!(parse_axes("y"), Ok([false, true, false]));
        assert_eq!(parse_axes("XZ"), Ok([true, false, true]));
        assert!(parse_axes("yy").is_err() && parse_axes("w").is_err() && parse_axes("").is_err());
        assert_eq!(axes_flag([true, false, true]), "xz");
        let m = FrameFinding::MirroredGyro {
            flip: [false, true, false],
            before: 0.15,
            after: 0.006,
        }
        .message();
        assert!(
            m.contains("--gyro-flip y") && m.contains("y axis looks mirrored"),
            "{m}"
        );
    }
}
