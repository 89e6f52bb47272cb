//! Do the step events look like a person walking? People keep the ratio of step length to
//! cadence (the *walk ratio*, metres per step a minute) nearly constant across walking
//! speeds, about 0.006 for adults (Sekiya & Nagasaki 1998, "Reproducibility of the walking
//! patterns of normal young adults", Gait & Posture 7(3)). On the shared recordings it was
//! 0.0027–0.0076 (14 Vicon-room and 6 hallway foot walks, 4 museum phone walks).
//!
//! Timestamps in the wrong scale move it far: a foot INS integrates acceleration twice, so
//! times scaled by `k` scale stride lengths by about `k²` and cadence by `1/k`, the ratio by
//! `k³` (halved times: 8× lower, measured 0.0007); a phone's Weinberg step lengths do not
//! depend on time, so its ratio scales by `k`. Such traces look plausible step by step and
//! are wrong together, so they are said.

use super::Mount;

/// Walk ratios (metres per step a minute) a walk may have: about half and twice the
/// extremes measured on real walks.
pub const WALK_RATIO_RANGE: std::ops::RangeInclusive<f64> = 0.0015..=0.015;

/// Fewer steps than this say nothing about a gait.
pub const MIN_GAIT_STEPS: usize = 10;

/// A warning when `steps` steps of mean length `step_m` (a foot's stride is two steps) at
/// `per_min` steps a minute, detected as `mount`, do not fit human walking.
#[must_use]
pub fn check_gait(mount: Mount, steps: usize, step_m: f64, per_min: f64) -> Option<String> {
    if steps < MIN_GAIT_STEPS || !(step_m.is_finite() && per_min.is_finite() && per_min > 0.0) {
        return None;
    }
    let ratio = step_m / per_min;
    if WALK_RATIO_RANGE.contains(&ratio) {
        return None;
    }
    let why = match mount {
        Mount::Foot => "a foot INS's stride lengths grow with the square of a time scale",
        Mount::Phone => "a phone's cadence scales with the timestamps",
    };
    Some(format!(
        "steps of {step_m:.2} m at {per_min:.0} steps a minute (a walk ratio of {ratio:.4} m \
         per step a minute) do not fit human walking ({}–{} m; people keep it near 0.006 at \
         any speed): are the timestamps in seconds, at the rate the samples came? ({why})",
        WALK_RATIO_RANGE.start(),
        WALK_RATIO_RANGE.end()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_walk_passes_and_scaled_timestamps_do_not() {
        // own-31 (hallway, foot): 0.71 m steps at 97.5 a minute.
        assert!(check_gait(Mount::Foot, 33, 0.706, 97.5).is_none());
        // The same with its times halved: 0.13 m at 195.
        let m = check_gait(Mount::Foot, 33, 0.131, 195.0).expect("halved");
        assert!(
            m.contains("walk ratio of 0.0007") && m.contains("timestamps"),
            "{m}"
        );
        // A phone's times doubled: the cadence halves, the lengths stay.
        assert!(check_gait(Mount::Phone, 80, 0.65, 42.0).is_some());
        // Too few steps to judge; no cadence.
        assert!(check_gait(Mount::Foot, 5, 0.131, 195.0).is_none());
        assert!(check_gait(Mount::Phone, 50, 0.6, 0.0).is_none());
    }
}
