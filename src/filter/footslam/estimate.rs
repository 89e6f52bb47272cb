//! The filter's answer: the most probable particle's map and the whole-walk path.

use super::{FootSlam, FootSlamEstimate, sample_start};
use crate::filter::outline_fit::{fit_outline_shift, unseen_seconds};
use crate::geometry::Pose2;
use crate::map::{FieldMap, FieldMapSnapshot};
use crate::random::stream;

impl FootSlam {
    /// The most probable particle's map and whole path (replayed from its ancestry).
    ///
    /// "Most probable" is judged on the whole path: the particle whose path has the
    /// largest product of eq. (6)'s factors since the first step, rather than the largest
    /// current weight, which only reflects the steps since the last resampling.
    ///
    /// With GPS and a prior map, the path and map are moved `κ·δ` towards the prior's frame
    /// (see [`FootSlam::with_anchors`]).
    #[must_use]
    pub fn estimate(&self) -> FootSlamEstimate {
        let index = self
            .particles
            .iter()
            .enumerate()
            .fold((0, f64::NEG_INFINITY), |best, (i, p)| {
                if p.path_log_likelihood > best.1 {
                    (i, p.path_log_likelihood)
                } else {
                    best
                }
            })
            .0;
        let (dx, dy) = self.grid.center(self.offset);
        let (mut dx, mut dy) = (self.offset_pull * dx, self.offset_pull * dy);
        let best = self.replay_path(index);
        let smoothed = self.smoothed_path(&best);
        let replayed = smoothed.path;
        if let Some(check) = &self.outage_check
            && self.outline_fit_sigma > 0.0
        {
            let points: Vec<(f64, f64)> = replayed.iter().map(|p| (p.x + dx, p.y + dy)).collect();
            let unseen = unseen_seconds(&check.times, &check.fix_times);
            let (sx, sy) = fit_outline_shift(
                &points,
                &unseen,
                &check.zone,
                check.crossing_cost,
                self.outline_fit_sigma,
            );
            dx += sx;
            dy += sy;
        }
        let shift = self.grid.hex_at(dx, dy);
        let prior_shift = shift - self.offset;
        let mut map = self.maps.snapshot(
            &self.particles[index].map,
            self.config.hex_radius,
            self.config.alpha,
        );
        let levels = self.level_tracker.levels();
        if levels.len() > 1 || self.config.start_level != 0 {
            map.levels = levels;
        }
        for c in &mut map.cells {
            c.hex += shift;
        }
        let path = replayed
            .into_iter()
            .map(|p| Pose2::new(p.x + dx, p.y + dy, p.heading))
            .collect();
        FootSlamEstimate {
            index,
            weight: self.weights.get(index).copied().unwrap_or(0.0),
            path_log_likelihood: self.particles[index].path_log_likelihood,
            wifi_log_likelihood: f64::from(self.particles[index].wifi_log_likelihood),
            path,
            spread_m: smoothed.spread_m,
            smoothed_paths: (smoothed.distinct, smoothed.averaged),
            levels: self.step_levels.clone(),
            map,
            prior_offset: (dx, dy),
            prior_shift,
            field_map: self
                .field
                .as_ref()
                .and_then(|e| e.reading_model())
                .map(|model| FieldMapSnapshot {
                    radius: model.cell_radius(),
                    components: model.components(),
                    offset: (dx, dy),
                    cells: (self.particles[index].field.as_deref())
                        .map_or_else(|| FieldMap::new().snapshot(), FieldMap::snapshot),
                }),
        }
    }

    /// Re-draws particle `index`'s whole path from the random streams its ancestors used;
    /// the motion does not depend on the map (eq. 5), so this reproduces it exactly (in the
    /// particle's own frame, before any move towards a prior map).
    #[must_use]
    pub fn replay_path(&self, index: usize) -> Vec<Pose2> {
        let seed = self.config.seed;
        let ancestry = self.particles[index].ancestry;
        let indices = self.lineage.indices(ancestry, self.steps.len() + 1);
        let mut rng = stream(seed, 0, u64::from(indices[0]));
        let mut error = self.motion.sample_initial(&mut rng);
        let mut pose = sample_start(&self.config, &mut rng);
        self.steps
            .iter()
            .enumerate()
            .map(|(s, &(length, dheading))| {
                let k = s as u64 + 1;
                let mut rng = stream(seed, k, u64::from(indices[s + 1]));
                error = self.motion.sample_error(error, &mut rng);
                pose = self
                    .motion
                    .sample_step(pose, error, length, dheading, &mut rng);
                pose
            })
            .collect()
    }
}
