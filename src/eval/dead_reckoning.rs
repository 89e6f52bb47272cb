//! Dead reckoning as a baseline track: the step trace integrated from a start pose, one
//! timed point per step, to be scored beside an estimated track. Against a dense truth it
//! starts at the origin facing east (the step-trace convention); against sparse waypoints
//! it is placed at the first waypoint at its time.

use super::position_error::{Alignment, interpolate_at};
use super::waypoint_error::{WaypointErrors, waypoint_errors};
use crate::error::Result;
use crate::geometry::Pose2;
use crate::io::{TimedPoint, Waypoint};
use crate::sensor::StepTrace;

/// Dead reckoning's errors at waypoints, and how its heading was set.
#[derive(Debug, Clone, PartialEq)]
pub struct WaypointDeadReckoning {
    /// The errors at the waypoints.
    pub errors: WaypointErrors,
    /// Whether the steps carry an absolute heading (the path follows it); otherwise the
    /// path was rigidly aligned to the waypoints.
    pub absolute_heading: bool,
}

/// The trace dead-reckoned from the origin facing east: one point per step, at its time.
#[must_use]
pub fn dead_reckoning_track(trace: &StepTrace) -> Vec<TimedPoint> {
    trace
        .steps()
        .iter()
        .zip(trace.dead_reckon(Pose2::default()))
        .map(|(s, p)| TimedPoint {
            t: s.t,
            x: p.x,
            y: p.y,
        })
        .collect()
}

/// Dead reckoning's errors at `waypoints` (not empty), its path started at the first one:
/// with the steps' absolute heading when their first step carries one (measured with
/// `alignment`), else rigidly aligned.
///
/// # Errors
///
/// As [`waypoint_errors`]: [`Error::NotEnough`](crate::Error::NotEnough) when `waypoints` is empty
/// or a rigid alignment (steps without an absolute heading) rests on too few or too close
/// waypoints; [`Error::Mismatch`](crate::Error::Mismatch) when no waypoint falls within the walk's
/// time span (another clock?); [`Error::InvalidData`](crate::Error::InvalidData) for a waypoint
/// that is not finite.
pub fn waypoint_dead_reckoning(
    waypoints: &[Waypoint],
    trace: &StepTrace,
    alignment: Alignment,
) -> Result<WaypointDeadReckoning> {
    let absolute = trace.steps().first().and_then(|s| s.heading).is_some();
    let points = match waypoints.first() {
        Some(first) => dead_reckoning_from(trace, first, absolute),
        None => Vec::new(),
    };
    let align = if absolute {
        alignment
    } else {
        Alignment::Rigid
    };
    Ok(WaypointDeadReckoning {
        errors: waypoint_errors(waypoints, &points, align)?,
        absolute_heading: absolute,
    })
}

/// Dead reckoning placed at the first waypoint at its time: the walker stands at the start
/// until the first step; with `absolute`, the heading before the first step is the first
/// step's measured heading less its turn, so the path follows the measured headings.
#[must_use]
pub fn dead_reckoning_from(trace: &StepTrace, first: &Waypoint, absolute: bool) -> Vec<TimedPoint> {
    let steps = trace.steps();
    let heading = match steps.first() {
        Some(s) if absolute => s.heading.unwrap_or(0.0) - s.dheading,
        _ => 0.0,
    };
    let start = Pose2 {
        x: 0.0,
        y: 0.0,
        heading,
    };
    let t0 = steps.first().map_or(first.t, |s| first.t.min(s.t - 1e-3));
    let mut points = vec![TimedPoint {
        t: t0,
        x: 0.0,
        y: 0.0,
    }];
    points.extend(
        steps
            .iter()
            .zip(trace.dead_reckon(start))
            .map(|(s, p)| TimedPoint {
                t: s.t,
                x: p.x,
                y: p.y,
            }),
    );
    // Shift so that the path passes the first waypoint at its time.
    if let Some((x, y)) = interpolate_at(&points, first.t) {
        for p in &mut points {
            p.x += first.x - x;
            p.y += first.y - y;
        }
    }
    points
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::Step;

    fn trace(heading: Option<f64>) -> StepTrace {
        let steps = (1..=3)
            .map(|k| Step {
                t: f64::from(k),
                length: 1.0,
                dheading: 0.0,
                dz: 0.0,
                heading,
            })
            .collect();
        StepTrace::new(steps).expect("trace")
    }

    #[test]
    fn from_the_origin_one_point_per_step() {
        let points = dead_reckoning_track(&trace(None));
        let xy: Vec<(f64, f64, f64)> = points.iter().map(|p| (p.t, p.x, p.y)).collect();
        assert_eq!(xy, vec![(1.0, 1.0, 0.0), (2.0, 2.0, 0.0), (3.0, 3.0, 0.0)]);
    }

    #[test]
    fn from_the_first_waypoint_with_the_absolute_heading() {
        let north = std::f64::consts::FRAC_PI_2;
        let first = Waypoint {
            t: 0.0,
            x: 10.0,
            y: 5.0,
            level: None,
        };
        let points = dead_reckoning_from(&trace(Some(north)), &first, true);
        // Standing at (10, 5) at t = 0, then 1 m north a second.
        assert_eq!((points[0].t, points[0].x, points[0].y), (0.0, 10.0, 5.0));
        let end = points[3];
        assert!(
            (end.x - 10.0).abs() < 1e-12 && (end.y - 8.0).abs() < 1e-12,
            "{end:?}"
        );
        let at = |t: f64, y: f64| Waypoint {
            t,
            x: 10.0,
            y,
            level: None,
        };
        let waypoints = [first, at(2.0, 7.0), at(3.0, 8.0)];
        let dr = waypoint_dead_reckoning(&waypoints, &trace(Some(north)), Alignment::None)
            .expect("errors");
        assert!(dr.absolute_heading);
        assert!(dr.errors.report.max < 1e-9, "{:?}", dr.errors.report);
        let dr = waypoint_dead_reckoning(&waypoints, &trace(None), Alignment::None).expect("rigid");
        assert!(!dr.absolute_heading);
    }
}
