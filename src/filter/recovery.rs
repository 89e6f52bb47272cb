//! Recovery when every particle dies (a drifting heading, a step through a wall the map does
//! not know, a wrong map), after the map-based and history-based particle filters of the
//! smartphone-PDR paper (Alg. 1 and sec. 3.1):
//!
//! 1. **heading search** — re-propagate the last belief with the step's heading corrected:
//!    first the previous heading kept (the step's heading change undone), then `±c, ±2c, …`
//!    up to a limit, alternating sides (Alg. 1);
//! 2. **history fitting** — re-seed particles within a radius of the last belief that had a
//!    single cluster (eq. 5) and replay the steps since through the filter, doubling the
//!    radius on each failure (sec. 3.1 fits the recent path to earlier positions);
//! 3. **global re-initialisation** — a fresh uniform prior over the whole plan.
//!
//! This module holds the schedule and the report; [`super::Tracker`] runs them.

use serde::{Deserialize, Serialize};

/// Recovery when every particle dies; every default in one place.
///
/// | field                | default | meaning                                                   |
/// |----------------------|---------|-----------------------------------------------------------|
/// | `heading_increment`  | 5°      | heading search step `c` (smartphone paper, Alg. 1)         |
/// | `heading_max`        | 45°     | largest heading correction tried                          |
/// | `history_steps`      | 40      | steps of history kept for history fitting                 |
/// | `history_radius`     | 1 m     | first spread about the last good particles (eq. 5)        |
/// | `history_attempts`   | 3       | tries, doubling the spread each time                      |
/// | `history_particles`  | 20,000  | particles re-seeded about the last good belief            |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RecoveryConfig {
    /// Heading search increment, radians.
    pub heading_increment: f64,
    /// Largest heading correction of the search, radians.
    pub heading_max: f64,
    /// Steps of history kept since the last good belief.
    pub history_steps: usize,
    /// Radius of the first re-seeding spread, metres.
    pub history_radius: f64,
    /// Re-seeding attempts (the radius doubles each time) before a global re-initialisation.
    pub history_attempts: usize,
    /// Particles re-seeded about the last good belief.
    pub history_particles: usize,
}

impl Default for RecoveryConfig {
    fn default() -> Self {
        Self {
            heading_increment: 5f64.to_radians(),
            heading_max: 45f64.to_radians(),
            history_steps: 40,
            history_radius: 1.0,
            history_attempts: 3,
            history_particles: 20_000,
        }
    }
}

/// How the filter recovered after every particle died.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "method", rename_all = "snake_case")]
pub enum Recovery {
    /// The step re-propagated with its heading change corrected by `correction_deg` degrees.
    HeadingSearch {
        /// The correction that let particles survive, degrees.
        correction_deg: f64,
    },
    /// Particles re-seeded within `radius_m` of the last single-cluster belief and the last
    /// `steps` steps replayed.
    History {
        /// Radius of the re-seeding, metres.
        radius_m: f64,
        /// Steps replayed, the current one included.
        steps: usize,
    },
    /// A fresh uniform prior over the whole plan.
    Global,
}

/// Heading corrections to try, in order, for a step whose heading change was `dheading`:
/// `−dheading` (keep the previous heading), then `+c, −c, +2c, −2c, …` while `|k·c| ≤ max`.
pub fn heading_corrections(dheading: f32, c: f32, max: f32) -> impl Iterator<Item = f32> {
    let steps = if c > 0.0 { (max / c).floor() as i32 } else { 0 };
    std::iter::once(-dheading)
        .filter(move |d| d.abs() > 1e-6 && d.abs() <= max.max(c))
        .chain((1..=steps).flat_map(move |k| [k as f32 * c, -(k as f32) * c]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corrections_alternate_and_stop_at_the_limit() {
        let c: Vec<f32> = heading_corrections(0.2, 0.1, 0.25).collect();
        assert_eq!(c.len(), 5);
        assert!((c[0] + 0.2).abs() < 1e-6);
        assert!((c[1] - 0.1).abs() < 1e-6 && (c[2] + 0.1).abs() < 1e-6);
        assert!((c[3] - 0.2).abs() < 1e-6 && (c[4] + 0.2).abs() < 1e-6);
        // A straight step has nothing to undo.
        assert_eq!(heading_corrections(0.0, 0.1, 0.25).count(), 4);
        assert_eq!(heading_corrections(0.0, 0.1, 0.0).count(), 0);
    }

    #[test]
    fn recovery_serialises_with_its_method() {
        let s = serde_json::to_string(&Recovery::History {
            radius_m: 2.0,
            steps: 5,
        })
        .expect("json");
        assert_eq!(s, r#"{"method":"history","radius_m":2.0,"steps":5}"#);
        assert_eq!(
            serde_json::to_string(&Recovery::Global).expect("json"),
            r#"{"method":"global"}"#
        );
    }
}
