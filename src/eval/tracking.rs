//! Scoring a known-map tracking run against the truth: how many steps it took to localise,
//! whether that was the right place, and how well the walker was tracked afterwards.

use super::position_error::{Alignment, ErrorReport, position_errors};
use crate::filter::{Cluster, SmoothedStep, TrackStep};
use crate::io::TimedPoint;
use crate::sensor::TruePose;
use serde::Serialize;

/// A first fix farther than this from the truth, or on another floor, is the wrong cluster,
/// metres.
pub const RIGHT_CLUSTER_RADIUS: f64 = 3.0;

/// The score of one tracking run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrackingScore {
    /// Steps until the belief first formed a single cluster (1-based), `None` if never.
    pub steps_to_localise: Option<usize>,
    /// The first single cluster was within [`RIGHT_CLUSTER_RADIUS`] of the truth and on its
    /// floor.
    pub right_cluster: bool,
    /// Horizontal errors of the estimates from localisation on; `None` if never localised.
    pub errors: Option<ErrorReport>,
    /// Share of those estimates on the true floor level.
    pub floor_accuracy: Option<f64>,
    /// Steps at which every particle died.
    pub deaths: usize,
}

/// Scores `reports` (one per step) against `truth` (one pose per step).
#[must_use]
pub fn score_tracking(truth: &[TruePose], reports: &[TrackStep]) -> TrackingScore {
    let first = reports.iter().position(|r| r.localised);
    let right_cluster = first.is_some_and(|i| {
        let (Some(c), Some(p)) = (reports[i].estimate, truth.get(i)) else {
            return false;
        };
        (c.x - p.x).hypot(c.y - p.y) <= RIGHT_CLUSTER_RADIUS && c.level == p.level
    });
    let tracked: Vec<(TimedPoint, TimedPoint, bool)> = first
        .map(|i| {
            reports
                .iter()
                .zip(truth)
                .skip(i)
                .filter_map(|(r, p)| {
                    let c = r.estimate?;
                    let t = r.t;
                    Some((
                        TimedPoint { t, x: c.x, y: c.y },
                        TimedPoint { t, x: p.x, y: p.y },
                        c.level == p.level,
                    ))
                })
                .collect()
        })
        .unwrap_or_default();
    let estimates: Vec<TimedPoint> = tracked.iter().map(|e| e.0).collect();
    let truths: Vec<TimedPoint> = tracked.iter().map(|e| e.1).collect();
    let errors = (!tracked.is_empty())
        .then(|| position_errors(&truths, &estimates, Alignment::None).ok())
        .flatten();
    let floor_accuracy = (!tracked.is_empty())
        .then(|| tracked.iter().filter(|e| e.2).count() as f64 / tracked.len() as f64);
    TrackingScore {
        steps_to_localise: first.map(|i| i + 1),
        right_cluster,
        errors,
        floor_accuracy,
        deaths: reports.iter().filter(|r| r.recovery.is_some()).count(),
    }
}

/// The score of a run's whole-walk (smoothed) answer.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SmoothedScore {
    /// Errors of the certain smoothed steps from the filter's first fix on (the steps
    /// [`TrackingScore::errors`] covers).
    pub errors_after_fix: Option<ErrorReport>,
    /// Errors of every certain smoothed step, those before the first fix included.
    pub errors_certain: Option<ErrorReport>,
    /// Steps the whole walk makes certain.
    pub certain_steps: usize,
    /// Of those, steps before the filter's first fix.
    pub certain_before_fix: usize,
    /// Certain steps farther than [`RIGHT_CLUSTER_RADIUS`] from the truth.
    pub certain_wrong: usize,
    /// Share of the certain steps on the true floor level.
    pub certain_floor_accuracy: Option<f64>,
}

/// Scores the smoothed answer `smoothed` (one per step, as `reports`) against `truth`.
#[must_use]
pub fn score_smoothed(
    truth: &[TruePose],
    reports: &[TrackStep],
    smoothed: &[SmoothedStep],
) -> SmoothedScore {
    let first = reports
        .iter()
        .position(|r| r.localised)
        .unwrap_or(reports.len());
    let certain: Vec<(usize, Cluster, &TruePose)> = smoothed
        .iter()
        .zip(truth)
        .enumerate()
        .filter(|(_, (s, _))| s.certain)
        .filter_map(|(i, (s, p))| Some((i, s.estimate?, p)))
        .collect();
    let errors = |from: usize| {
        let pairs: Vec<(TimedPoint, TimedPoint)> = certain
            .iter()
            .filter(|(i, ..)| *i >= from)
            .map(|(_, c, p)| {
                (
                    TimedPoint {
                        t: p.t,
                        x: c.x,
                        y: c.y,
                    },
                    TimedPoint {
                        t: p.t,
                        x: p.x,
                        y: p.y,
                    },
                )
            })
            .collect();
        let (estimates, truths): (Vec<_>, Vec<_>) = pairs.into_iter().unzip();
        (!estimates.is_empty())
            .then(|| position_errors(&truths, &estimates, Alignment::None).ok())
            .flatten()
    };
    SmoothedScore {
        errors_after_fix: errors(first),
        errors_certain: errors(0),
        certain_steps: certain.len(),
        certain_before_fix: certain.iter().filter(|(i, ..)| *i < first).count(),
        certain_wrong: certain
            .iter()
            .filter(|(_, c, p)| (c.x - p.x).hypot(c.y - p.y) > RIGHT_CLUSTER_RADIUS)
            .count(),
        certain_floor_accuracy: (!certain.is_empty()).then(|| {
            certain
                .iter()
                .filter(|(_, c, p)| c.level == p.level)
                .count() as f64
                / certain.len() as f64
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn report(t: f64, estimate: Option<(f64, f64, i32)>, localised: bool) -> TrackStep {
        TrackStep {
            t,
            particles: 100,
            clusters: estimate.map(|_| if localised { 1 } else { 2 }),
            estimate: estimate.map(|(x, y, level)| Cluster {
                x,
                y,
                z: 3.0 * f64::from(level),
                level,
                heading: 0.0,
                spread: 0.5,
                weight: 1.0,
                particles: 100,
            }),
            localised,
            recovery: None,
            fit: None,
        }
    }

    fn pose(t: f64, x: f64, level: i32) -> TruePose {
        TruePose {
            t,
            x,
            y: 0.0,
            z: 3.0 * f64::from(level),
            level,
            heading: 0.0,
        }
    }

    #[test]
    fn scores_from_the_first_single_cluster_on() {
        let truth = [
            pose(1.0, 0.0, 0),
            pose(2.0, 1.0, 0),
            pose(3.0, 2.0, 1),
            pose(4.0, 3.0, 1),
        ];
        let reports = [
            report(1.0, None, false),
            report(2.0, Some((1.5, 0.0, 0)), true),
            report(3.0, Some((2.0, 0.0, 0)), false),
            report(4.0, Some((3.0, 0.0, 1)), true),
        ];
        let s = score_tracking(&truth, &reports);
        assert_eq!(s.steps_to_localise, Some(2));
        assert!(s.right_cluster);
        let e = s.errors.expect("errors");
        assert_eq!(e.n, 3);
        assert!((e.max - 0.5).abs() < 1e-12);
        assert!((s.floor_accuracy.expect("floors") - 2.0 / 3.0).abs() < 1e-12);
        // A first fix far away is the wrong cluster.
        let wrong = [report(1.0, Some((20.0, 0.0, 0)), true)];
        assert!(!score_tracking(&truth[..1], &wrong).right_cluster);
        let never = score_tracking(&truth, &[report(1.0, None, false)]);
        assert_eq!((never.steps_to_localise, never.errors), (None, None));
    }

    #[test]
    fn smoothed_scores_count_certain_steps_before_and_after_the_fix() {
        let truth = [pose(1.0, 0.0, 0), pose(2.0, 1.0, 0), pose(3.0, 2.0, 1)];
        let reports = [
            report(1.0, None, false),
            report(2.0, Some((1.5, 0.0, 0)), true),
            report(3.0, Some((2.0, 0.0, 1)), true),
        ];
        let step = |x: f64, level: i32, certain: bool| SmoothedStep {
            estimate: report(0.0, Some((x, 0.0, level)), true).estimate,
            hypotheses: 1,
            certain,
            ancestors: 1,
        };
        let smoothed = [step(0.25, 0, true), step(1.0, 0, false), step(6.0, 0, true)];
        let s = score_smoothed(&truth, &reports, &smoothed);
        assert_eq!(
            (s.certain_steps, s.certain_before_fix, s.certain_wrong),
            (2, 1, 1)
        );
        assert_eq!(s.certain_floor_accuracy, Some(0.5));
        assert_eq!(s.errors_after_fix.expect("after").n, 1);
        let all = s.errors_certain.expect("all");
        assert_eq!(all.n, 2);
        assert!((all.max - 4.0).abs() < 1e-12);
    }
}
