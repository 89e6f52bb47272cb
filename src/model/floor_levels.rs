//! Floors from height changes: which level of a building each step is on, for FootSLAM's
//! stacked hexagon maps (Robertson et al. 2009, sec. 5: "the approach extends to 2.5D by
//! stacking hexagon maps per floor").
//!
//! FootSLAM's map is a plane of hexagons. A walk over several floors would overlay them;
//! instead each step is given a **level** from its height (the running sum of the steps'
//! `dz`), the same for every particle, and each level has its own hexagon map.
//!
//! * A **level** is a height where the walker kept walking on the flat: a stretch of at
//!   least `settle_distance` metres whose heights stay within `flat_band` of its first. Its
//!   height is the stretch's mean. The walk's first floor is its start level (0 unless
//!   given) at height 0 (walks start on a floor).
//! * A flat stretch within `tolerance` of a known level is that level, and the level's
//!   height follows it: a slow height drift (the foot INS's, a barometer's weather, a metre
//!   over a long walk) moves the floor's reference along instead of opening a floor beside
//!   it. A flat stretch
//!   further from every level is a new one, numbered `max + 1` above the highest and
//!   `min − 1` below the lowest. A flat stretch between two known levels (a half landing
//!   walked for a while) joins the nearer: floors are further apart than `2 × tolerance`.
//! * **Each step is on the level nearest its height.** A staircase is thus split at half
//!   height between the two floors it joins, as surveyors draw the treads of a plan (the
//!   tower simulator's "nearest floor").
//!
//! [`find_levels`] runs this over a whole walk; a [`LevelTracker`] seeded with its answer
//! places every step on the levels of the whole walk (a stair climbed for the first time
//! already splits at half height). Unseeded, the tracker finds levels as the steps come,
//! which gives the same levels but puts the first climb onto the floor it left until the
//! new floor has been walked for `settle_distance`.
//!
//! Steps with no height change (`dz = 0` throughout) are all on level 0: one plane, as
//! before.

use crate::error::{Error, Result};
pub use crate::map::FloorLevel;
use crate::sensor::Step;
use serde::{Deserialize, Serialize};

/// The most levels a walk can have; flat stretches beyond are put on the nearest level.
pub const MAX_LEVELS: usize = 64;

/// Settings of the level finder; every default in one place.
///
/// | field             | default | meaning                                                  |
/// |-------------------|---------|----------------------------------------------------------|
/// | `enabled`         | true    | false: every step on level 0 (one plane)                 |
/// | `tolerance`       | 1.2 m   | a flat stretch this close to a level's height is that level |
/// | `settle_distance` | 4 m     | walked on the flat before a height counts as a floor     |
/// | `flat_band`       | 0.5 m   | how much a flat stretch's height may vary                |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LevelConfig {
    /// Find levels from the steps' height changes. Default true.
    pub enabled: bool,
    /// A flat stretch within this distance of a level's height is on that level, metres:
    /// half the least floor spacing expected. Default 1.2 m (floors ≥ 2.4 m apart).
    pub tolerance: f64,
    /// Distance walked within `flat_band` before a height counts as a floor, metres: longer
    /// than a half landing is crossed. Default 4 m.
    pub settle_distance: f64,
    /// Spread of heights allowed along a flat stretch, metres. Default 0.5 m.
    pub flat_band: f64,
}

impl Default for LevelConfig {
    fn default() -> Self {
        Self {
            enabled: true,
            tolerance: 1.2,
            settle_distance: 4.0,
            flat_band: 0.5,
        }
    }
}

impl LevelConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `tolerance` is outside [0.1, 50] m, `settle_distance` outside
    /// [0, 1000] m or `flat_band` outside [0.01, 10] m.
    pub fn validate(&self) -> Result<()> {
        crate::error::check_range("levels.tolerance", self.tolerance, 0.1..=50.0, "m")?;
        crate::error::check_range(
            "levels.settle_distance",
            self.settle_distance,
            0.0..=1000.0,
            "m",
        )?;
        crate::error::check_range("levels.flat_band", self.flat_band, 0.01..=10.0, "m")?;
        Ok(())
    }
}

/// Assigns steps to levels as they come (see the module documentation).
#[derive(Debug, Clone)]
pub struct LevelTracker {
    config: LevelConfig,
    /// Known levels, in the order found.
    levels: Vec<FloorLevel>,
    /// Height of the last step, metres.
    z: f64,
    /// The flat stretch being walked: its first height, distance, and height sum and count.
    flat_z0: f64,
    flat_distance: f64,
    flat_sum: f64,
    flat_count: usize,
}

impl LevelTracker {
    /// A tracker on level `start` at height 0, knowing `seeded` levels beforehand (those of
    /// [`find_levels`] on the same walk; level `start` at height 0 is added if missing).
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `config` fails [`LevelConfig::validate`] or `start` is beyond ±1000;
    /// [`Error::InvalidData`] when a seeded level is given twice or at a height that is not finite.
    pub fn new(config: LevelConfig, start: i32, seeded: &[FloorLevel]) -> Result<Self> {
        config.validate()?;
        crate::error::check_range("start_level", f64::from(start), -1000.0..=1000.0, "")?;
        // The walk starts on its start level: at height 0 whatever height the level had at
        // the end of the walk (seeded from `find_levels`, drift included).
        let mut levels = vec![FloorLevel {
            level: start,
            z: 0.0,
        }];
        for l in seeded.iter().filter(|l| l.level != start) {
            if !l.z.is_finite() || levels.iter().any(|k| k.level == l.level) {
                return Err(Error::invalid(
                    format!("floor level {}", l.level),
                    format!(
                        "given twice or with a height that is not finite ({} m)",
                        l.z
                    ),
                ));
            }
            levels.push(*l);
        }
        Ok(Self {
            config,
            levels,
            z: 0.0,
            flat_z0: 0.0,
            flat_distance: 0.0,
            flat_sum: 0.0,
            flat_count: 0,
        })
    }

    /// The levels known so far, sorted by number.
    #[must_use]
    pub fn levels(&self) -> Vec<FloorLevel> {
        let mut levels = self.levels.clone();
        levels.sort_by_key(|l| l.level);
        levels
    }

    /// The height reached, metres.
    #[must_use]
    pub fn height(&self) -> f64 {
        self.z
    }

    /// Moves by one step and returns its level.
    pub fn step(&mut self, step: &Step) -> i32 {
        if !self.config.enabled {
            return self.levels[0].level;
        }
        self.z += step.dz;
        if (self.z - self.flat_z0).abs() > self.config.flat_band {
            self.flat_z0 = self.z;
            self.flat_distance = 0.0;
            self.flat_sum = 0.0;
            self.flat_count = 0;
        }
        self.flat_distance += step.length;
        self.flat_sum += self.z;
        self.flat_count += 1;
        if self.flat_distance >= self.config.settle_distance {
            self.settle(self.flat_sum / self.flat_count as f64);
        }
        self.nearest(self.z)
    }

    /// A flat stretch at height `z`: the known level within `tolerance` follows it (its
    /// height becomes `z`, so that a slow height drift — the foot INS's, a barometer's
    /// weather — moves the floor's reference with it); otherwise a new level when it is
    /// beyond the highest or the lowest.
    fn settle(&mut self, z: f64) {
        let tolerance = self.config.tolerance;
        if let Some(known) = self
            .levels
            .iter_mut()
            .filter(|l| (l.z - z).abs() <= tolerance)
            .min_by(|a, b| (a.z - z).abs().total_cmp(&(b.z - z).abs()))
        {
            known.z = z;
            return;
        }
        if self.levels.len() >= MAX_LEVELS {
            return;
        }
        let above = self.levels.iter().all(|l| l.z < z);
        let below = self.levels.iter().all(|l| l.z > z);
        let numbers = self.levels.iter().map(|l| l.level);
        let level = match (above, below) {
            (true, _) => numbers.max().unwrap_or(0) + 1,
            (_, true) => numbers.min().unwrap_or(0) - 1,
            _ => return,
        };
        self.levels.push(FloorLevel { level, z });
    }

    /// The level whose height is nearest `z` (the lower on a tie).
    fn nearest(&self, z: f64) -> i32 {
        self.levels
            .iter()
            .min_by(|a, b| {
                (a.z - z)
                    .abs()
                    .total_cmp(&(b.z - z).abs())
                    .then(a.level.cmp(&b.level))
            })
            .map_or(0, |l| l.level)
    }
}

/// The levels of a whole walk that starts on level `start`, sorted by number (always
/// `start` at height 0; only it when levels are disabled or the walk stays on one floor).
///
/// # Errors
///
/// [`Error::Config`] when `config` fails [`LevelConfig::validate`] or `start` is beyond ±1000.
pub fn find_levels(steps: &[Step], config: LevelConfig, start: i32) -> Result<Vec<FloorLevel>> {
    let mut tracker = LevelTracker::new(config, start, &[])?;
    for s in steps {
        tracker.step(s);
    }
    Ok(tracker.levels())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn step(length: f64, dz: f64) -> Step {
        Step {
            t: 0.0,
            length,
            dheading: 0.0,
            dz,
            heading: None,
        }
    }

    /// Flat walking, `n` strides of 1.2 m with small height noise.
    fn flat(n: usize) -> Vec<Step> {
        (0..n)
            .map(|i| step(1.2, if i % 2 == 0 { 0.03 } else { -0.03 }))
            .collect()
    }

    /// A switchback flight of `treads` strides rising `rise` each, with a half landing of
    /// two strides between its halves.
    fn stairs(treads: usize, rise: f64) -> Vec<Step> {
        let mut s: Vec<Step> = (0..treads / 2).map(|_| step(0.6, rise)).collect();
        s.extend((0..2).map(|_| step(0.8, 0.0)));
        s.extend((0..treads - treads / 2).map(|_| step(0.6, rise)));
        s
    }

    fn walk(parts: &[Vec<Step>]) -> Vec<Step> {
        parts.iter().flatten().copied().collect()
    }

    #[test]
    fn one_floor_is_level_zero() {
        let steps = flat(200);
        let levels = find_levels(&steps, LevelConfig::default(), 0).unwrap();
        assert_eq!(levels.len(), 1);
        assert!(
            levels[0].level == 0 && levels[0].z.abs() < 0.05,
            "{levels:?}"
        );
    }

    #[test]
    fn floors_up_and_down_are_found_and_stairs_split_at_half_height() {
        // Up two floors of 3 m (10 strides of 0.3 m each), back down one.
        let down: Vec<Step> = stairs(10, 0.3)
            .into_iter()
            .map(|s| step(s.length, -s.dz))
            .collect();
        let steps = walk(&[
            flat(10),
            stairs(10, 0.3),
            flat(10),
            stairs(10, 0.3),
            flat(10),
            down,
            flat(10),
        ]);
        let levels = find_levels(&steps, LevelConfig::default(), 0).unwrap();
        assert_eq!(levels.len(), 3, "{levels:?}");
        for (l, want) in levels.iter().zip([(0, 0.0), (1, 3.0), (2, 6.0)]) {
            assert_eq!(l.level, want.0);
            assert!((l.z - want.1).abs() < 0.1, "{l:?}");
        }
        // Seeded with the whole walk's levels, the first climb splits at half height.
        let mut t = LevelTracker::new(LevelConfig::default(), 0, &levels).unwrap();
        let on: Vec<i32> = steps.iter().map(|s| t.step(s)).collect();
        assert!(on[..10].iter().all(|&l| l == 0));
        // The first flight: 5 treads up to 1.5 m and the half landing on level 0, the rest on 1.
        assert!(on[10..17].iter().all(|&l| l == 0), "{:?}", &on[10..22]);
        assert!(on[18..32].iter().all(|&l| l == 1), "{:?}", &on[10..32]);
        assert_eq!(on[45], 2);
        assert_eq!(*on.last().unwrap(), 1);
    }

    #[test]
    fn a_half_landing_and_drift_make_no_floor() {
        // The half landing at 1.5 m is crossed in 1.6 m, less than settle_distance; a
        // height drift of −0.8 m over the next 120 m stays on the floor reached.
        let mut steps = walk(&[flat(5), stairs(10, 0.3), flat(5)]);
        steps.extend((0..100).map(|_| step(1.2, -0.008)));
        let levels = find_levels(&steps, LevelConfig::default(), 0).unwrap();
        assert_eq!(levels.len(), 2, "{levels:?}");
        assert!((levels[1].z - 2.2).abs() < 0.3, "{levels:?}");
        let mut t = LevelTracker::new(LevelConfig::default(), 0, &levels).unwrap();
        let on: Vec<i32> = steps.iter().map(|s| t.step(s)).collect();
        assert!(on[20..].iter().all(|&l| l == 1));
    }

    #[test]
    fn a_slow_drift_moves_the_floor_instead_of_opening_one() {
        // 300 strides on one floor drifting down 2 m in all (the tolerance is 1.2 m), then
        // a climb of 3 m: two levels, 3 m apart at the end.
        let mut steps: Vec<Step> = (0..300).map(|_| step(1.2, -2.0 / 300.0)).collect();
        steps.extend(stairs(10, 0.3));
        steps.extend(flat(10));
        let levels = find_levels(&steps, LevelConfig::default(), 0).unwrap();
        assert_eq!(levels.len(), 2, "{levels:?}");
        // A flat stretch's height is its mean: the drifting floor's lags by up to half the band.
        assert!((levels[1].z - levels[0].z - 3.0).abs() < 0.35, "{levels:?}");
    }

    #[test]
    fn disabled_or_bad_settings() {
        let steps = walk(&[flat(10), stairs(10, 0.3), flat(10)]);
        let off = LevelConfig {
            enabled: false,
            ..LevelConfig::default()
        };
        assert_eq!(find_levels(&steps, off, 0).unwrap().len(), 1);
        // A walk starting on level 3 numbers the floor above 4.
        let up = find_levels(&steps, LevelConfig::default(), 3).unwrap();
        assert_eq!(up.iter().map(|l| l.level).collect::<Vec<_>>(), vec![3, 4]);
        let bad = LevelConfig {
            tolerance: f64::NAN,
            ..LevelConfig::default()
        };
        assert!(find_levels(&steps, bad, 0).is_err());
    }
}
