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

/// Gains of the gyroscope against the quaternion outside this range (with every axis
/// correlated) mean the timestamps do not count seconds at the rate the samples came
/// (right: 1.03–1.14 on real phone walks; timestamps ×2 or ×½ give 2.1 and 0.56).
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

/// Per-axis gain and correlation of the quaternion's rotation against the gyroscope's over
/// 0.1 s windows; `None` without a quaternion or with too little rotation.
#[must_use]
pub fn gyro_against_orientation(recording: &ImuRecording) -> Option<[(f64, f64); 3]> {
    gyro_against(recording, |q| q)
}

/// [`gyro_against_orientation`] with each quaternion first passed through `read`.
fn gyro_against(
    recording: &ImuRecording,
    read: impl Fn([f64; 4]) -> [f64; 4],
) -> Option<[(f64, f64); 3]> {
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
    let mut out = [(0.0, 0.0); 3];
    for i in 0..3 {
        if !(gg[i] > 1e-6 && qq[i] > 1e-6) {
            return None;
        }
        out[i] = (qg[i] / gg[i], qg[i] / (gg[i] * qq[i]).sqrt());
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
    let worst = |axes: &[(f64, f64); 3]| axes.iter().map(|a| a.1).fold(f64::INFINITY, f64::min);
    let consistent = |axes: &[(f64, f64); 3]| worst(axes) > CONSISTENT_CORRELATION;
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
        let flip = axes.map(|(_, r)| r < MIRRORED_CORRELATION);
        let after = axes.iter().map(|a| a.1.abs()).fold(f64::INFINITY, f64::min);
        if flip.contains(&true) && after > CONSISTENT_CORRELATION {
            return Some(FrameFinding::MirroredGyro {
                flip,
                before: worst(&axes),
                after,
            });
        }
        return Some(FrameFinding::Disagreeing {
            correlation: worst(&axes),
        });
    }
    let mut gains = axes.map(|(g, _)| g);
    gains.sort_by(f64::total_cmp);
    // The regression's gain is the quaternion's turn per the gyroscope's: its inverse is
    // how far the gyroscope turns per the quaternion's.
    let gain = 1.0 / gains[1];
    (!GAIN_RANGE.contains(&gain)).then_some(FrameFinding::TimeBase { gain })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::ImuSample;

    /// A phone turning about each axis in turn, its quaternion integrated from the same
    /// rates (`q̇ = ½ q ⊗ ω`), 100 Hz for 20 s.
    fn turning_phone(time_scale: f64) -> ImuRecording {
        let mut q = [0.0, 0.0, 0.0, 1.0f64];
        let dt = 0.01;
        let samples = (0..2000)
            .map(|k| {
                let t = f64::from(k) * dt;
                let w = [
                    0.8 * (1.3 * t).sin(),
                    0.6 * (0.7 * t + 1.0).sin(),
                    0.9 * (0.45 * t + 2.0).cos(),
                ];
                let s = ImuSample {
                    t: 1.7e9 + t * time_scale,
                    accel: [0.1, 0.2, 9.8],
                    gyro: w,
                    mag: None,
                    orientation: Some(q),
                    pressure: None,
                };
                // q ← q ⊗ exp(ω dt / 2)
                let [x, y, z] = w.map(|v| 0.5 * v * dt);
                let [qx, qy, qz, qw] = q;
                q = [
                    qw * x + qx + qy * z - qz * y,
                    qw * y - qx * z + qy + qz * x,
                    qw * z + qx * y - qy * x + qz,
                    qw - qx * x - qy * y - qz * z,
                ];
                let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
                q = q.map(|v| v / n);
                s
            })
            .collect();
        ImuRecording::new(samples, 0).expect("recording")
    }

    #[test]
    fn a_consistent_phone_passes_and_gains_are_one() {
        let r = turning_phone(1.0);
        let axes = gyro_against_orientation(&r).expect("enough rotation");
        for (gain, corr) in axes {
            assert!((gain - 1.0).abs() < 0.05 && corr > 0.99, "{axes:?}");
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
