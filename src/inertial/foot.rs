//! Foot-mounted IMU → strides: a zero-velocity-aided strapdown INS (Harle 2013 §IV; Foxlin
//! 2005; Skog et al. 2010 for the stance detector).
//!
//! The pipeline, one stage per file:
//! 1. [`super::stance`]: the SHOE detector marks the samples where the foot is flat (with a
//!    gait-adaptive threshold), the stillest of them for zero-velocity updates, and which
//!    stances are clear (as still as their neighbours);
//! 2. [`super::strapdown`]: from the first stance (roll and pitch from its mean specific
//!    force, yaw 0; the gyro bias from it when the walker stands still long enough) the INS
//!    integrates every sample with its own `dt`;
//! 3. [`super::zupt`]: during stance the error-state filter applies zero-velocity updates —
//!    unless the stance is not clear and the INS is faster than `zupt_gate_speed` at each of
//!    its update samples (a mid-swing dip of the statistic, not a stance);
//! 4. here: the stances cut the path into strides. Each stance's last sample closes a stride
//!    from the previous stance (its `t`, horizontal `length`, height change `dz`, and
//!    `dheading`, the change of walking direction: the direction of this stride's
//!    displacement less the previous stride's; 0 for the first stride, whose direction is
//!    the walk's initial heading). Dead reckoning the strides therefore reproduces the INS
//!    path, which is given turned to that frame (the first stride along +x); the foot's yaw
//!    would not (at a stance it points about half-way between the strides before and after,
//!    a look-ahead of half the turn: docs/error-models.md). A stride that is too short in
//!    distance or time (a shuffle, a spurious stance) is merged into the next one; standing
//!    still produces no stance end and so no stride. A gap in the samples longer than
//!    `max_gap_s` cannot be integrated: the open stride is dropped, and the INS restarts at
//!    the next stance (re-levelled, same yaw, same position).

use super::foot_config::{FootConfig, FootFigures};
use super::stance::{ShoeDetector, samples_in};
use super::strapdown::{NavState, heading_axis, heading_of, level};
use super::zupt::ZuptFilter;
use super::{HeadingSource, StepEvents};
use crate::error::{Error, Result};
use crate::geometry::RigidTransform;
use crate::sensor::step::{MAX_STEP_DZ, MAX_STEP_LENGTH};
use crate::sensor::{ImuRecording, Step, StepTrace};
use nalgebra::Vector3;

/// The gate on zero-velocity updates applies while the last update is this recent, seconds:
/// after a longer unaided stretch the velocity error itself may exceed the gate.
pub const GATE_HORIZON_S: f64 = 2.0;

/// Whether the current stance's zero-velocity updates are applied.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Run {
    /// No zero-velocity sample seen yet.
    Undecided,
    /// Applied: the foot is at rest.
    Accepted,
    /// Every zero-velocity sample so far failed the gate: a dip of the statistic while the
    /// foot moves fast.
    Gated,
}

/// The INS state at a stance that opened a stride.
#[derive(Debug, Clone, Copy)]
struct Anchor {
    t: f64,
    position: Vector3<f64>,
}

/// Strides of a foot-mounted recording: one event per stride, the INS path at each stance
/// (the first point is the first stance) and the figures. A recording without any stance
/// gives no strides.
///
/// # Errors
///
/// - [`Error::Config`] when `config` fails [`FootConfig::validate`].
/// - [`Error::InvalidData`] when, without `config.gravity`, the first stance's mean specific force
///   is outside 5–15 m/s² (accelerations in g?); or, as a safeguard, when a stride fails
///   [`check_step`](crate::sensor::step::check_step) (long strides are split).
pub fn detect_strides(
    recording: &ImuRecording,
    config: &FootConfig,
) -> Result<StepEvents<FootFigures>> {
    config.validate()?;
    let samples = recording.samples();
    let n = samples.len();
    let dt_median = recording.report().median_dt_s;
    let t: Vec<f64> = samples.iter().map(|s| s.t).collect();
    let accel: Vec<[f64; 3]> = samples.iter().map(|s| s.accel).collect();
    let gyro: Vec<[f64; 3]> = samples.iter().map(|s| s.gyro).collect();

    let mask = ShoeDetector::new(config, config.gravity.unwrap_or(9.81))
        .detect(&t, &accel, &gyro, dt_median);
    let stance = &mask.stance;
    let mut figures = FootFigures {
        detector_threshold: mask.median_threshold,
        ..FootFigures::default()
    };
    let level_samples = samples_in(config.max_level_s, dt_median, 1);
    let mean_force = |k: usize| -> Vector3<f64> {
        // The mean specific force of the stance run containing sample k, from its start.
        let mut start = k;
        while start > 0 && stance[start - 1] {
            start -= 1;
        }
        let mut sum = Vector3::zeros();
        let mut count = 0.0_f64;
        for a in accel[start..]
            .iter()
            .zip(&stance[start..])
            .take(level_samples)
        {
            if !*a.1 {
                break;
            }
            sum += Vector3::from(*a.0);
            count += 1.0;
        }
        sum / count.max(1.0)
    };

    let mut steps: Vec<Step> = Vec::new();
    let mut path: Vec<[f64; 3]> = Vec::new();
    let Some(first) = stance.iter().position(|&s| s) else {
        return finish(steps, path, figures);
    };
    let f0 = mean_force(first);
    let gravity = config.gravity.unwrap_or(f0.norm());
    if !(5.0..=15.0).contains(&gravity) {
        return Err(Error::invalid(
            "the first stance",
            format!(
                "mean specific force is {gravity:.2} m/s², not gravity: are the accelerations \
                 in m/s² (not g)?"
            ),
        ));
    }
    figures.gravity = gravity;
    let bias = gyro_bias(&t, &gyro, &mask.statistic, first, config);
    figures.gyro_bias = bias.into();
    let axis = heading_axis(&f0);
    let mut state = NavState::at_rest(Vector3::zeros(), level(&f0, &axis, 0.0), gravity);
    let mut filter = ZuptFilter::new(
        config.accel_noise_density,
        config.gyro_noise_density,
        config.zero_velocity_sigma,
        config.initial_tilt_sigma,
    );

    let mut anchor: Option<Anchor> = None;
    // The direction of the last stride walked (none before the first).
    let mut walked: Option<f64> = None;
    let mut lost = false; // after a gap, until the next stance
    let mut reanchor = false; // after a restart, until the stance ends
    let mut run = Run::Undecided; // the current stance's fate
    let mut last_zupt_t = t[first];
    let (mut residual_sum, mut residual_count) = (0.0, 0usize);
    let mut stride_time = 0.0;
    for k in first..n {
        if k > first {
            let dt = t[k] - t[k - 1];
            if dt > config.max_gap_s {
                figures.gaps_skipped += 1;
                if !(stance[k - 1] && stance[k]) {
                    // The foot moved across the gap: the open stride cannot be measured.
                    if anchor.is_some() && !lost {
                        figures.strides_lost_to_gaps += 1;
                    }
                    lost = true;
                }
            } else if !lost {
                let f = 0.5 * (Vector3::from(accel[k - 1]) + Vector3::from(accel[k]));
                let w = 0.5 * (Vector3::from(gyro[k - 1]) + Vector3::from(gyro[k])) - bias;
                let f_n = state.propagate(&f, &w, dt);
                filter.predict(&f_n, dt);
            }
        }
        if !stance[k] {
            continue;
        }
        if k == first || !stance[k - 1] {
            run = Run::Undecided;
        }
        if lost {
            // Restart cleanly: re-levelled, at rest, same position and yaw.
            let yaw = heading_of(&state.attitude, &axis);
            state = NavState::at_rest(state.position, level(&mean_force(k), &axis, yaw), gravity);
            filter.restart(config.initial_tilt_sigma);
            lost = false;
            reanchor = true;
            run = Run::Accepted;
            if let Some(a) = anchor {
                // The walker is assumed not to have moved across the gap.
                state.position = a.position;
            }
        }
        if mask.zupt[k] && run != Run::Accepted {
            // Gate (after Foxlin's plausibility tests): a foot at rest after a recent update
            // cannot have drifted to `zupt_gate_speed`; a mid-swing dip of the statistic can.
            // Each zero-velocity sample is tested until one passes: the landing may fail,
            // the foot flat a moment later passes; a mid-swing dip fails throughout.
            // A clear stance (as still as its neighbours) needs no gate: gating it after a
            // wrong update would only carry the error on.
            let recent = t[k] - last_zupt_t < GATE_HORIZON_S;
            run = if !mask.clear[k] && recent && state.velocity.norm() > config.zupt_gate_speed {
                Run::Gated
            } else {
                Run::Accepted
            };
        }
        if run == Run::Accepted {
            if mask.zupt[k] {
                last_zupt_t = t[k];
                let r = filter.update_zero_velocity(&mut state);
                residual_sum += r;
                residual_count += 1;
                figures.max_zupt_residual = figures.max_zupt_residual.max(r);
            }
            if k > first {
                figures.stationary_s += (t[k] - t[k - 1]).min(config.max_gap_s);
            }
        }
        let stance_ends = k + 1 == n || !stance[k + 1];
        if stance_ends && run == Run::Gated {
            figures.gated_stances += 1;
        }
        if !stance_ends || run != Run::Accepted {
            continue;
        }
        figures.stances += 1;
        let here = Anchor {
            t: t[k],
            position: state.position,
        };
        let Some(from) = anchor.filter(|_| !reanchor) else {
            if anchor.is_none() {
                path.push(here.position.into());
            }
            anchor = Some(here);
            reanchor = false;
            continue;
        };
        let d = here.position - from.position;
        let length = d.xy().norm();
        if length < config.min_stride_length || here.t - from.t < config.min_stride_s {
            figures.merged_strides += 1;
            continue;
        }
        stride_time += here.t - from.t;
        emit(
            &from,
            &here,
            &mut walked,
            &mut steps,
            &mut path,
            &mut figures,
        );
        anchor = Some(here);
    }
    figures.mean_zupt_residual = residual_sum / (residual_count.max(1) as f64);
    if stride_time > 0.0 {
        figures.cadence_per_min = 60.0 * steps.len() as f64 / stride_time;
    }
    finish(steps, path, figures)
}

/// The gyroscope's bias: its mean over the still samples (`T < γ_floor`) of the first stance
/// when they span at least `min_bias_s` (the walker stands before setting off), else zero.
fn gyro_bias(
    t: &[f64],
    gyro: &[[f64; 3]],
    statistic: &[f64],
    first: usize,
    config: &FootConfig,
) -> Vector3<f64> {
    let mut sum = Vector3::zeros();
    let (mut count, mut span) = (0.0_f64, 0.0);
    for k in first + 1..t.len() {
        if statistic[k] >= config.threshold_floor {
            break;
        }
        sum += Vector3::from(gyro[k]);
        count += 1.0;
        span = t[k] - t[first];
    }
    if config.min_bias_s > 0.0 && span >= config.min_bias_s {
        sum / count
    } else {
        Vector3::zeros()
    }
}

/// Appends the stride `from → to` (split into equal parts if implausibly long); `direction`
/// is the direction of the stride before it (radians in the INS frame; `None` before the
/// first stride, which sets the walk's initial direction and so turns by 0), updated to
/// this one's.
fn emit(
    from: &Anchor,
    to: &Anchor,
    direction: &mut Option<f64>,
    steps: &mut Vec<Step>,
    path: &mut Vec<[f64; 3]>,
    figures: &mut FootFigures,
) {
    let d = to.position - from.position;
    let length = d.xy().norm();
    let parts = ((length / MAX_STEP_LENGTH).ceil())
        .max((d.z.abs() / MAX_STEP_DZ).ceil())
        .max(1.0);
    if parts > 1.0 {
        figures.split_strides += 1;
    }
    let m = parts as usize;
    // A stride without horizontal length (possible only with `min_stride_length` 0) keeps
    // the direction walked before it.
    let turn = if length > 0.0 {
        let along = d.y.atan2(d.x);
        let before = direction.replace(along).unwrap_or(along);
        crate::geometry::wrap_turn(along - before)
    } else {
        0.0
    };
    for i in 1..=m {
        let s = i as f64 / parts;
        let p = from.position + d * s;
        steps.push(Step {
            t: from.t + (to.t - from.t) * s,
            length: length / parts,
            dheading: if i == 1 { turn } else { 0.0 },
            dz: d.z / parts,
            heading: None,
        });
        path.push(p.into());
    }
}

/// Turns `path` about its first point so that its first stride runs along +x: the frame
/// in which the strides' `dheading` starts (the first stride sets the walk's direction).
fn turn_to_first_stride(path: &mut [[f64; 3]]) {
    let Some(&[x0, y0, _]) = path.first() else {
        return;
    };
    let Some(a) = path
        .iter()
        .map(|p| (p[0] - x0, p[1] - y0))
        .find(|&(dx, dy)| dx.hypot(dy) > 0.0)
        .map(|(dx, dy)| dy.atan2(dx))
    else {
        return;
    };
    let turn = RigidTransform {
        angle: -a,
        ..RigidTransform::default()
    };
    for p in path.iter_mut() {
        let (x, y) = turn.apply((p[0] - x0, p[1] - y0));
        (p[0], p[1]) = (x0 + x, y0 + y);
    }
}

fn finish(
    steps: Vec<Step>,
    mut path: Vec<[f64; 3]>,
    mut figures: FootFigures,
) -> Result<StepEvents<FootFigures>> {
    turn_to_first_stride(&mut path);
    figures.strides = steps.len();
    figures.distance_m = steps.iter().map(|s| s.length).sum();
    if !steps.is_empty() {
        figures.mean_stride_length_m = figures.distance_m / steps.len() as f64;
    }
    figures.final_dz_m = match (path.first(), path.last()) {
        (Some(a), Some(b)) => b[2] - a[2],
        _ => 0.0,
    };
    let trace = StepTrace::new(steps)
        .map_err(|(i, m)| Error::invalid(format!("stride {i} of the foot INS"), m))?;
    Ok(StepEvents {
        trace,
        path,
        heading_source: HeadingSource::Gyroscope,
        figures,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::ImuSample;
    use nalgebra::{Rotation3, Vector3};
    use std::f64::consts::TAU;

    /// A foot on a known trajectory: stands 2 s, then for each `(length, turn)` a 0.7 s swing
    /// along a straight line (position and yaw follow `s(τ) = τ − sin(2πτ)/2π`, whose speed
    /// and acceleration vanish at both ends; the foot pitches by up to [`PITCH`] and back, as
    /// a real foot does — a pure translation would look still to any IMU at mid-swing) and a
    /// 0.8 s stance; the turn happens in the swing and the stride runs along the new heading. The sensor is mounted upside down and tilted
    /// (z down, 0.1 rad about y). Samples in `drop` (a time interval) are left out.
    fn synthetic(rate: f64, strides: &[(f64, f64)], drop: Option<(f64, f64)>) -> ImuRecording {
        let (stand, swing, stance) = (2.0, 0.7, 0.8);
        let mount = Rotation3::from_euler_angles(std::f64::consts::PI, 0.1, 0.0);
        let g = 9.81;
        let duration = stand + strides.len() as f64 * (swing + stance);
        let mut samples = Vec::new();
        let mut k = 0;
        loop {
            let t = f64::from(k) / rate;
            k += 1;
            if t > duration {
                break;
            }
            if drop.is_some_and(|(a, b)| t > a && t < b) {
                continue;
            }
            // Where in the walk: heading before this stride, and the swing's phase τ.
            let mut yaw = 0.0;
            let (mut accel, mut yaw_rate) = (Vector3::zeros(), 0.0);
            let (mut pitch, mut pitch_rate) = (0.0, 0.0);
            let mut start = stand;
            for &(length, turn) in strides {
                if t >= start && t < start + swing {
                    let tau = (t - start) / swing;
                    let s = tau - (TAU * tau).sin() / TAU;
                    let ds = (1.0 - (TAU * tau).cos()) / swing;
                    let dds = TAU * (TAU * tau).sin() / (swing * swing);
                    let heading = yaw + turn;
                    accel = length * dds * Vector3::new(heading.cos(), heading.sin(), 0.0);
                    yaw_rate = turn * ds;
                    yaw += turn * s;
                    // The foot pitches up to PITCH and back: β = P sin²(πτ).
                    pitch = PITCH * (std::f64::consts::PI * tau).sin().powi(2);
                    pitch_rate = PITCH * std::f64::consts::PI * (TAU * tau).sin() / swing;
                    break;
                }
                if t >= start + swing {
                    yaw += turn;
                }
                start += swing + stance;
            }
            // C = R_z(ψ) R_y(β) M; ω^n = ψ̇ ẑ + R_z(ψ) β̇ ŷ; ω^b = Cᵀ ω^n.
            let rz = Rotation3::from_axis_angle(&Vector3::z_axis(), yaw);
            let c = rz * Rotation3::from_axis_angle(&Vector3::y_axis(), pitch) * mount;
            let f = c.inverse() * (accel + Vector3::new(0.0, 0.0, g));
            let w_n = Vector3::new(0.0, 0.0, yaw_rate) + rz * Vector3::new(0.0, pitch_rate, 0.0);
            let w = c.inverse() * w_n;
            samples.push(ImuSample {
                t,
                accel: f.into(),
                gyro: w.into(),
                mag: None,
                orientation: None,
                pressure: None,
            });
        }
        ImuRecording::new(samples, 0).expect("valid synthetic recording")
    }

    /// The foot's largest pitch in a swing, radians.
    const PITCH: f64 = 0.5;

    const WALK: [(f64, f64); 4] = [(1.2, 0.0), (1.4, 0.5), (1.0, -1.2), (1.3, 0.0)];

    #[test]
    fn synthetic_strides_are_measured_at_any_rate() {
        for rate in [100.0, 200.0, 250.0] {
            let e = detect_strides(&synthetic(rate, &WALK, None), &FootConfig::default())
                .expect("strides");
            let steps = e.trace.steps();
            assert_eq!(steps.len(), WALK.len(), "{rate} Hz: {steps:?}");
            assert_eq!(e.path.len(), WALK.len() + 1);
            for (s, &(length, turn)) in steps.iter().zip(&WALK) {
                assert!(
                    (s.length - length).abs() < 0.03,
                    "{rate} Hz: {s:?} vs {length}"
                );
                assert!(
                    (s.dheading - turn).abs() < 0.01,
                    "{rate} Hz: {s:?} vs {turn}"
                );
                assert!(s.dz.abs() < 0.01 && s.heading.is_none());
            }
            // Each stride ends with its stance: 2 + i (0.7 + 0.8) s.
            assert!((steps[3].t - 8.0).abs() < 0.02, "{}", steps[3].t);
            let f = &e.figures;
            assert_eq!((f.strides, f.gaps_skipped, f.merged_strides), (4, 0, 0));
            assert!((f.gravity - 9.81).abs() < 1e-6);
            assert!((f.distance_m - 4.9).abs() < 0.1, "{f:?}");
            // 4 strides in 4 × 1.5 s of walking: 40 per minute.
            assert!((f.cadence_per_min - 40.0).abs() < 1.0, "{f:?}");
        }
    }

    #[test]
    fn dead_reckoned_strides_are_the_ins_path() {
        // A gap in the middle too: the restart must not break the chain of directions.
        for drop in [None, Some((3.7, 4.2))] {
            let e = detect_strides(&synthetic(200.0, &WALK, drop), &FootConfig::default())
                .expect("strides");
            let steps = e.trace.steps();
            assert_eq!(
                steps[0].dheading, 0.0,
                "the first stride sets the direction"
            );
            // The path is given in the strides' frame: its first stride runs along +x.
            let (x0, y0) = (e.path[0][0], e.path[0][1]);
            assert!(
                (e.path[1][1] - y0).abs() < 1e-9 && e.path[1][0] > x0,
                "{:?}",
                e.path
            );
            let walked = e
                .trace
                .dead_reckon(crate::geometry::Pose2::new(x0, y0, 0.0));
            for (p, q) in walked.iter().zip(&e.path[1..]) {
                assert!((p.x - q[0]).hypot(p.y - q[1]) < 1e-9, "{p:?} vs {q:?}");
            }
        }
    }

    #[test]
    fn a_gap_drops_the_open_stride_and_the_walk_resumes() {
        // Half a second missing in the middle of the second swing (3.5 s + 0.35 s).
        let rec = synthetic(200.0, &WALK, Some((3.7, 4.2)));
        let e = detect_strides(&rec, &FootConfig::default()).expect("strides");
        let f = &e.figures;
        assert_eq!((f.gaps_skipped, f.strides_lost_to_gaps), (1, 1), "{f:?}");
        let steps = e.trace.steps();
        assert_eq!(steps.len(), 3, "{steps:?}");
        // The strides before and after the gap keep their lengths. The stride after it turns
        // from the last one walked by its own turn plus the part of the lost stride's turn
        // (0.5 rad) the gyroscope saw before the gap: s(τ) of the swing at 3.7 s.
        assert!((steps[0].length - 1.2).abs() < 0.03);
        let tau: f64 = (3.7 - 3.5) / 0.7;
        let seen = 0.5 * (tau - (TAU * tau).sin() / TAU);
        assert!((steps[1].length - 1.0).abs() < 0.03, "{steps:?}");
        assert!((steps[1].dheading - (seen - 1.2)).abs() < 0.02, "{steps:?}");
        assert!((steps[2].length - 1.3).abs() < 0.03);
        // The path holds one point per stride plus the start, each stride its length apart.
        assert_eq!(e.path.len(), 4);
        for (s, w) in steps.iter().zip(e.path.windows(2)) {
            let d = (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
            assert!((d - s.length).abs() < 1e-9);
        }
    }

    #[test]
    fn standing_still_makes_no_strides() {
        // A minute at 100 Hz of a still sensor with a little deterministic noise.
        let samples = (0..6000)
            .map(|k| {
                let n = |i: f64| (f64::from(k) * 0.37 + i).sin();
                ImuSample {
                    t: f64::from(k) * 0.01,
                    accel: [0.02 * n(1.0), 0.02 * n(2.0), -9.81 + 0.02 * n(3.0)],
                    gyro: [0.003 * n(4.0), 0.003 * n(5.0), 0.003 * n(6.0)],
                    mag: None,
                    orientation: None,
                    pressure: None,
                }
            })
            .collect();
        let rec = ImuRecording::new(samples, 0).expect("valid");
        let e = detect_strides(&rec, &FootConfig::default()).expect("strides");
        assert!(e.trace.is_empty());
        assert_eq!(e.path.len(), 1);
        assert_eq!(e.figures.stances, 1);
        assert!(e.figures.stationary_s > 59.0, "{:?}", e.figures);
    }

    #[test]
    fn short_shuffles_are_merged() {
        // A 5 cm shuffle then a real stride: one stride of 1.25 m.
        let e = detect_strides(
            &synthetic(200.0, &[(0.05, 0.0), (1.2, 0.0)], None),
            &FootConfig::default(),
        )
        .expect("strides");
        assert_eq!(e.trace.len(), 1, "{:?} {:?}", e.trace, e.figures);
        assert_eq!(e.figures.merged_strides, 1, "{:?}", e.figures);
        assert!((e.trace.steps()[0].length - 1.25).abs() < 0.03);
    }

    #[test]
    fn config_defaults_validate_and_unknown_fields_are_refused() {
        assert!(FootConfig::default().validate().is_ok());
        let c: FootConfig = serde_json::from_str(r#"{"max_gap_s": 0.2}"#).expect("parse");
        assert_eq!(c.max_gap_s, 0.2);
        assert_eq!(c.window_s, FootConfig::default().window_s);
        assert!(serde_json::from_str::<FootConfig>(r#"{"window": 1}"#).is_err());
        let bad = FootConfig {
            threshold_ceiling: 1.0,
            ..FootConfig::default()
        };
        assert!(bad.validate().is_err());
    }
}
