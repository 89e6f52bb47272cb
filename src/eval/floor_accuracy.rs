//! How often a 2.5D track is on the right floor: the share of track points whose level equals
//! the truth's level at the same time.

use crate::io::TrackPoint;

/// A time and a floor level.
pub type TimedLevel = (f64, i32);

/// Times closer than this are the same step, seconds.
const SAME_TIME: f64 = 1e-3;

/// Share of `track` points (time, level) whose level equals the level of the `truth` point
/// with the same time (within a millisecond); points with no truth at their time are skipped.
/// `None` when no point can be compared. Both series must be sorted by time.
#[must_use]
pub fn floor_accuracy(truth: &[TimedLevel], track: &[TimedLevel]) -> Option<f64> {
    let mut compared = 0usize;
    let mut right = 0usize;
    for &(t, level) in track {
        let i = truth.partition_point(|q| q.0 < t - SAME_TIME);
        if let Some(&(tt, true_level)) = truth.get(i)
            && (tt - t).abs() <= SAME_TIME
        {
            compared += 1;
            right += usize::from(level == true_level);
        }
    }
    (compared > 0).then(|| right as f64 / compared as f64)
}

/// [`floor_accuracy`] of two 2.5D tracks (e.g. the simulator's truth.csv and track's
/// track.csv), compared by their points' levels.
#[must_use]
pub fn track_floor_accuracy(truth: &[TrackPoint], track: &[TrackPoint]) -> Option<f64> {
    let levels =
        |v: &[TrackPoint]| -> Vec<TimedLevel> { v.iter().map(|p| (p.t, p.level)).collect() };
    floor_accuracy(&levels(truth), &levels(track))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_by_time() {
        let truth = [(0.0, 0), (1.0, 0), (2.0, 1), (3.0, 1)];
        assert_eq!(floor_accuracy(&truth, &[(1.0, 0), (2.0, 0)]), Some(0.5));
        assert_eq!(floor_accuracy(&truth, &[(2.0004, 1), (3.0, 1)]), Some(1.0));
        assert_eq!(floor_accuracy(&truth, &[(5.0, 1)]), None);
        assert_eq!(floor_accuracy(&[], &[]), None);
    }
}
