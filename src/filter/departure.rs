//! FootSLAM's answer against dead reckoning: how far the learned path departs from the
//! dead-reckoned steps, what supports the departure, and which of the two to trust.
//!
//! FootSLAM bends a walk where its map term (eq. 6) finds revisits. Where the walk really
//! came back, the bend corrects drift; where it walked a parallel corridor or lane a few
//! metres from its way out, eq. (6) rewards folding the one onto the other as much
//! (docs/footslam.md, the hallway walks), and nothing in the steps tells the two apart. What
//! does tell them apart is how far dead reckoning would have had to be wrong:
//!
//! * a step of the learned path **revisits** when it comes within `revisit_radius_m` of an
//!   earlier step at least `revisit_min_walked_m` of walking before;
//! * the revisit is **plausible** when the dead-reckoned positions of the same two steps lie
//!   within `revisit_radius_m + drift · w` of each other, `w` the distance walked between
//!   them and `drift` dead reckoning's error per metre walked — the walker may have come back
//!   there and dead reckoning drifted that much. Measured after a rigid fit: foot-mounted
//!   strides 0.4–1.8 % of the distance (the hallway walks), phone steps 1–2 % (the museum
//!   routes); the default `drift` of 4 % leaves twice that.
//!
//! A walk whose learned revisits are mostly implausible, with no evidence beside the steps
//! (WiFi scans, compass headings, GPS fixes, a prior map or outline), has been folded by the
//! map term alone: the dead-reckoned path is then the one to trust.

use crate::geometry::{Pose2, RigidTransform, nearest_rank};
use crate::sensor::Step;
use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

/// Settings of the check; every default in one place.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DepartureConfig {
    /// Answer with the dead-reckoned path (and its map) when the check says to trust it.
    /// Default true.
    pub fall_back: bool,
    /// How near an earlier step a step must come to revisit it, metres. Default 1.
    pub revisit_radius_m: f64,
    /// Walking since the earlier step before a return counts as a revisit, metres.
    /// Default 10.
    pub revisit_min_walked_m: f64,
    /// Dead reckoning's error per metre walked that a plausible revisit may need. Default
    /// 0.04.
    pub drift: f64,
    /// The largest share of implausible revisits the learned path may hold, with no other
    /// evidence, before dead reckoning is trusted instead. Default 0.5.
    pub max_implausible_share: f64,
    /// Departures (p95, after a rigid fit) smaller than this are not questioned, metres.
    /// Default 1.
    pub min_departure_m: f64,
}

impl Default for DepartureConfig {
    fn default() -> Self {
        Self {
            fall_back: true,
            revisit_radius_m: 1.0,
            revisit_min_walked_m: 10.0,
            drift: 0.04,
            max_implausible_share: 0.5,
            min_departure_m: 1.0,
        }
    }
}

impl DepartureConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`](crate::Error::Config) when `revisit_radius_m` is outside [0.05, 100] m,
    /// `revisit_min_walked_m` or `min_departure_m` outside [0, 10 000] m, or `drift` or
    /// `max_implausible_share` outside [0, 1].
    pub fn validate(&self) -> crate::error::Result<()> {
        use crate::error::check_range;
        check_range(
            "departure.revisit_radius_m",
            self.revisit_radius_m,
            0.05..=100.0,
            "m",
        )?;
        check_range(
            "departure.revisit_min_walked_m",
            self.revisit_min_walked_m,
            0.0..=10_000.0,
            "m",
        )?;
        check_range("departure.drift", self.drift, 0.0..=1.0, "")?;
        check_range(
            "departure.max_implausible_share",
            self.max_implausible_share,
            0.0..=1.0,
            "",
        )?;
        check_range(
            "departure.min_departure_m",
            self.min_departure_m,
            0.0..=10_000.0,
            "m",
        )
    }
}

/// Which path a run's answer is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Trust {
    /// FootSLAM's learned path.
    Learned,
    /// The dead-reckoned steps.
    DeadReckoning,
}

/// How the learned path departs from dead reckoning and what supports it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Departure {
    /// 95th percentile of the distance between learned and dead-reckoned positions after
    /// the best rigid fit, metres.
    pub p95_m: f64,
    /// The same, as a share of the walk's length.
    pub share_of_length: f64,
    /// Steps of the learned path that revisit an earlier one.
    pub revisits: usize,
    /// Of them, those dead reckoning could have missed.
    pub plausible_revisits: usize,
    /// Evidence beside the steps that weighed in: `wifi`, `compass`, `gps`, `prior map or
    /// outline`.
    pub other_evidence: Vec<&'static str>,
    /// The share of revisits dead reckoning could not have missed (0 without revisits).
    pub implausible_share: f64,
    /// The path to trust.
    pub trust: Trust,
    /// The path the run answers with: `trust`, or the learned path when `fall_back` is off.
    pub answer: Trust,
}

impl Departure {
    /// Checks `learned` (one pose per step) against `dead_reckoned` (the same steps from the
    /// same start) with the walk's `steps` (their lengths give the distance walked);
    /// `other_evidence` names what beside the steps weighed the particles.
    #[must_use]
    pub fn check(
        steps: &[Step],
        learned: &[Pose2],
        dead_reckoned: &[Pose2],
        other_evidence: Vec<&'static str>,
        config: &DepartureConfig,
    ) -> Self {
        let a: Vec<(f64, f64)> = learned.iter().map(|p| (p.x, p.y)).collect();
        let b: Vec<(f64, f64)> = dead_reckoned.iter().map(|p| (p.x, p.y)).collect();
        let mut walked = Vec::with_capacity(steps.len());
        let mut total = 0.0;
        for s in steps {
            total += s.length;
            walked.push(total);
        }
        let p95_m = RigidTransform::fit(&a, &b).map_or(0.0, |fit| {
            let mut d: Vec<f64> = a
                .iter()
                .zip(&b)
                .map(|(&p, q)| {
                    let p = fit.apply(p);
                    (p.0 - q.0).hypot(p.1 - q.1)
                })
                .collect();
            d.sort_unstable_by(f64::total_cmp);
            if d.is_empty() {
                0.0
            } else {
                nearest_rank(&d, 95)
            }
        });
        let (revisits, plausible_revisits) = revisits(&a, &b, &walked, config);
        let implausible_share = if revisits == 0 {
            0.0
        } else {
            1.0 - plausible_revisits as f64 / revisits as f64
        };
        let folded = other_evidence.is_empty()
            && p95_m > config.min_departure_m
            && implausible_share > config.max_implausible_share;
        let trust = if folded {
            Trust::DeadReckoning
        } else {
            Trust::Learned
        };
        Self {
            p95_m,
            share_of_length: if total > 0.0 { p95_m / total } else { 0.0 },
            revisits,
            plausible_revisits,
            other_evidence,
            implausible_share,
            trust,
            answer: if config.fall_back {
                trust
            } else {
                Trust::Learned
            },
        }
    }
}

/// Steps of `learned` that revisit an earlier one, and how many of those are plausible
/// under `dead_reckoned` (see the [module](self)). A grid of `revisit_radius_m` cells finds
/// the candidates.
fn revisits(
    learned: &[(f64, f64)],
    dead_reckoned: &[(f64, f64)],
    walked: &[f64],
    config: &DepartureConfig,
) -> (usize, usize) {
    let r = config.revisit_radius_m;
    let cell = |(x, y): (f64, f64)| ((x / r).floor() as i64, (y / r).floor() as i64);
    let mut grid: FxHashMap<(i64, i64), Vec<u32>> = FxHashMap::default();
    let (mut revisits, mut plausible) = (0, 0);
    for (i, &p) in learned.iter().enumerate() {
        let (cx, cy) = cell(p);
        let (mut revisit, mut allowed) = (false, false);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for &j in grid.get(&(cx + dx, cy + dy)).into_iter().flatten() {
                    let j = j as usize;
                    let between = walked[i] - walked[j];
                    let q = learned[j];
                    if between < config.revisit_min_walked_m || (p.0 - q.0).hypot(p.1 - q.1) > r {
                        continue;
                    }
                    revisit = true;
                    let (u, v) = (dead_reckoned[i], dead_reckoned[j]);
                    if (u.0 - v.0).hypot(u.1 - v.1) <= r + config.drift * between {
                        allowed = true;
                    }
                }
            }
        }
        revisits += usize::from(revisit);
        plausible += usize::from(revisit && allowed);
        grid.entry((cx, cy)).or_default().push(i as u32);
    }
    (revisits, plausible)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A walk 20 m east, a U-turn, and 20 m back along a lane `lane` metres north, 1 m
    /// steps.
    fn out_and_back(lane: f64) -> (Vec<Step>, Vec<Pose2>) {
        let mut steps = Vec::new();
        for i in 0..42 {
            let dheading = match i {
                20 | 21 => std::f64::consts::FRAC_PI_2,
                _ => 0.0,
            };
            let length = if i == 20 || i == 21 { lane / 2.0 } else { 1.0 };
            steps.push(Step {
                t: f64::from(i),
                length: length.max(0.01),
                dheading,
                dz: 0.0,
                heading: None,
            });
        }
        let mut pose = Pose2::default();
        let dr = steps
            .iter()
            .map(|s| {
                pose = pose.step(s.length, s.dheading);
                pose
            })
            .collect();
        (steps, dr)
    }

    /// `path` with the return leg folded onto y = 0.
    fn folded(path: &[Pose2]) -> Vec<Pose2> {
        path.iter()
            .enumerate()
            .map(|(i, p)| {
                if i > 21 {
                    Pose2::new(p.x, 0.0, p.heading)
                } else {
                    *p
                }
            })
            .collect()
    }

    #[test]
    fn a_return_folded_onto_a_lane_far_from_it_is_not_trusted() {
        // The return ran 6 m north of the way out, 20 m apart in walking at most: dead
        // reckoning is not 6 m off over so little, so the fold was the map's doing.
        let (steps, dr) = out_and_back(6.0);
        let config = DepartureConfig::default();
        let d = Departure::check(&steps, &folded(&dr), &dr, Vec::new(), &config);
        assert!(d.revisits > 10 && d.plausible_revisits == 0, "{d:?}");
        assert!(d.p95_m > 2.0, "{d:?}");
        assert_eq!(d.trust, Trust::DeadReckoning);
        // With WiFi that weighed in, the learned path stands.
        let d = Departure::check(&steps, &folded(&dr), &dr, vec!["wifi"], &config);
        assert_eq!(d.trust, Trust::Learned);
    }

    #[test]
    fn a_fold_dead_reckoning_could_have_missed_is_trusted() {
        // Lanes 1.2 m apart: within the drift allowed after 10–40 m of walking.
        let (steps, dr) = out_and_back(1.2);
        let config = DepartureConfig {
            min_departure_m: 0.5,
            ..Default::default()
        };
        let d = Departure::check(&steps, &folded(&dr), &dr, Vec::new(), &config);
        assert!(d.revisits > 10, "{d:?}");
        assert!(d.implausible_share < 0.5, "{d:?}");
        assert_eq!(d.trust, Trust::Learned);
        // The dead-reckoned path itself departs by nothing.
        let same = Departure::check(&steps, &dr, &dr, Vec::new(), &config);
        assert!(same.p95_m < 1e-9 && same.trust == Trust::Learned);
    }
}
