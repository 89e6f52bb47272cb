//! Position error at sparse ground-truth points (waypoints), as real datasets give it: the
//! track is linearly interpolated at each waypoint's time and compared with the waypoint.
//! A step-based track has no point while the walker stands after the last step: a waypoint
//! up to [`HOLD_S`] after the track's end is compared with its last point (and counted as
//! `held`); so is a waypoint up to [`HOLD_BEFORE_S`] before its first point with that point
//! (the walk's start, where the walker stood until the first step ended). Other waypoints
//! outside the track's time span are skipped and counted (a track that starts at
//! localisation has no estimate before it).

use super::position_error::{Alignment, ErrorReport, interpolate_at, position_errors};
use crate::error::{Error, Result};
use crate::io::{TimedPoint, Waypoint};
use serde::Serialize;

/// How long after its last point a track still stands there, seconds.
pub const HOLD_S: f64 = 5.0;

/// How long before its first point a track already stands there, seconds: about one step,
/// since a step-based track's first point is the end of the first step.
pub const HOLD_BEFORE_S: f64 = 1.0;

/// One waypoint's error.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WaypointError {
    /// The waypoint's time, seconds.
    pub t: f64,
    /// The waypoint, local metres.
    pub x: f64,
    /// North, metres.
    pub y: f64,
    /// The track at `t` (after the alignment), local metres.
    pub estimate_x: f64,
    /// North, metres.
    pub estimate_y: f64,
    /// Distance between the two, metres.
    pub error: f64,
}

/// The errors at every waypoint within the track's time span, and their summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WaypointErrors {
    /// Summary (`skipped` counts waypoints outside the track's time span).
    pub report: ErrorReport,
    /// Per waypoint, in time order.
    pub points: Vec<WaypointError>,
    /// Waypoints after the track's end (within [`HOLD_S`]) compared with its last point, or
    /// just before its start (within [`HOLD_BEFORE_S`]) with its first.
    pub held: usize,
}

/// Errors of `track` (time order, local metres) at `waypoints` (time order; of waypoints that
/// share a time the first counts).
///
/// # Errors
///
/// - [`Error::NotEnough`] when `waypoints` or `track` is empty, or a rigid alignment would rest on
///   too few or too close waypoints (as [`position_errors`]).
/// - [`Error::Mismatch`] when no waypoint lies within the track's time span (with [`HOLD_BEFORE_S`]
///   and [`HOLD_S`]): another clock?
/// - [`Error::InvalidData`] for a waypoint or track point that is not finite.
pub fn waypoint_errors(
    waypoints: &[Waypoint],
    track: &[TimedPoint],
    alignment: Alignment,
) -> Result<WaypointErrors> {
    if waypoints.is_empty() {
        return Err(Error::not_enough("there are no waypoints", ""));
    }
    let mut truth: Vec<TimedPoint> = Vec::with_capacity(waypoints.len());
    for w in waypoints {
        if truth.last().is_none_or(|p| w.t > p.t) {
            truth.push(TimedPoint {
                t: w.t,
                x: w.x,
                y: w.y,
            });
        }
    }
    let mut held = 0;
    let (matched, estimates): (Vec<TimedPoint>, Vec<TimedPoint>) = truth
        .iter()
        .filter_map(|w| {
            let at = interpolate_at(track, w.t).or_else(|| {
                let (first, last) = (track.first()?, track.last()?);
                let after = w.t > last.t && w.t - last.t <= HOLD_S;
                let before = w.t < first.t && first.t - w.t <= HOLD_BEFORE_S;
                let p = if after { last } else { first };
                (after || before).then(|| {
                    held += 1;
                    (p.x, p.y)
                })
            });
            at.map(|(x, y)| (*w, TimedPoint { t: w.t, x, y }))
        })
        .unzip();
    if estimates.is_empty() {
        let span = |v: &[TimedPoint]| (v[0].t, v[v.len() - 1].t);
        let (w0, w1) = span(&truth);
        return Err(match track.is_empty() {
            true => Error::not_enough("the track has no points", ""),
            false => {
                let (t0, t1) = span(track);
                Error::mismatch(
                    format!(
                        "none of the {} waypoints ([{w0}, {w1}] s) lies within the track's time span [{t0}, {t1}] s",
                        truth.len()
                    ),
                    "are they on the same clock?",
                )
            }
        });
    }
    let mut report = position_errors(&matched, &estimates, alignment)?;
    report.skipped = truth.len() - estimates.len();
    let points = matched
        .iter()
        .zip(&estimates)
        .map(|(w, e)| {
            let (x, y) = report.transform.map_or((e.x, e.y), |t| t.apply((e.x, e.y)));
            WaypointError {
                t: w.t,
                x: w.x,
                y: w.y,
                estimate_x: x,
                estimate_y: y,
                error: (x - w.x).hypot(y - w.y),
            }
        })
        .collect();
    Ok(WaypointErrors {
        report,
        points,
        held,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tp(t: f64, x: f64, y: f64) -> TimedPoint {
        TimedPoint { t, x, y }
    }

    fn wp(t: f64, x: f64, y: f64) -> Waypoint {
        Waypoint {
            t,
            x,
            y,
            level: None,
        }
    }

    #[test]
    fn interpolates_the_track_at_each_waypoint() {
        let track = [tp(10.0, 0.0, 0.0), tp(20.0, 10.0, 0.0)];
        // t = 15: track (5, 0), waypoint (5, 3) → 3 m; t = 20: 0 m; t = 24: held at the
        // end (10, 0) → 2 m; t = 5 and 26 outside.
        let w = [
            wp(5.0, 0.0, 0.0),
            wp(15.0, 5.0, 3.0),
            wp(15.0, 9.0, 9.0),
            wp(20.0, 10.0, 0.0),
            wp(24.0, 10.0, 2.0),
            wp(26.0, 0.0, 0.0),
        ];
        let r = waypoint_errors(&w, &track, Alignment::None).expect("errors");
        assert_eq!((r.report.n, r.report.skipped, r.held), (3, 2, 1));
        assert_eq!(r.report.max, 3.0);
        assert_eq!(r.points[2].error, 2.0);
        assert_eq!(r.points[0].error, 3.0);
        assert_eq!((r.points[0].estimate_x, r.points[0].estimate_y), (5.0, 0.0));
        let e = waypoint_errors(&[wp(100.0, 0.0, 0.0)], &track, Alignment::None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("same clock"), "{e}");
    }

    #[test]
    fn a_waypoint_just_before_the_first_step_is_held_at_the_start() {
        let track = [tp(10.0, 1.0, 0.0), tp(20.0, 10.0, 0.0)];
        // t = 9.2: 0.8 s before the first point, held there (1, 0) → 1 m; t = 8.5 is more
        // than a step before, skipped.
        let w = [wp(8.5, 0.0, 0.0), wp(9.2, 0.0, 0.0), wp(20.0, 10.0, 0.0)];
        let r = waypoint_errors(&w, &track, Alignment::None).expect("errors");
        assert_eq!((r.report.n, r.report.skipped, r.held), (2, 1, 1));
        assert_eq!(r.points[0].error, 1.0);
    }
}
