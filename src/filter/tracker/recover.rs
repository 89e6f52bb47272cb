//! Recovery when every particle died at a step: heading search, then history fitting from
//! the last single-cluster belief, then a fresh uniform prior.

use super::particle::wrap;
use super::prior::PLACEMENT_TRIES;
use super::propagate::StepInput;
use super::{CHUNK, SALT_HEADING, SALT_HISTORY, SALT_PRIOR, TrackParticle, Tracker};
use crate::filter::recovery::{Recovery, heading_corrections};
use crate::map::FloorTopology;
use crate::sensor::Step;
use rand::RngExt;
use rand_distr::StandardNormal;
use rand_pcg::Pcg64Mcg;
use rayon::prelude::*;

impl Tracker<'_> {
    /// Keeps the last single-cluster belief and the steps since, for history fitting.
    pub(super) fn remember(&mut self, step: &Step, localised: bool) {
        if localised {
            self.last_good = Some(self.particles.clone());
            self.history.clear();
        } else if self.last_good.is_some() {
            self.history.push_back(*step);
            if self.history.len() > self.config.recovery.history_steps {
                self.last_good = None;
                self.history.clear();
            }
        }
    }

    /// Every particle died at this step: heading search, then history fitting from the last
    /// good belief, then a fresh uniform prior. On return the proposal holds live particles
    /// (or, for [`Recovery::Global`], the belief is a fresh prior).
    pub(super) fn recover(&mut self, u: &StepInput) -> Recovery {
        let r = self.config.recovery;
        for (attempt, correction) in
            heading_corrections(u.dheading, r.heading_increment as f32, r.heading_max as f32)
                .enumerate()
        {
            let salt = SALT_HEADING ^ crate::random::mix(attempt as u64);
            if self.propagate(u, correction, salt) {
                return Recovery::HeadingSearch {
                    correction_deg: f64::from(correction).to_degrees(),
                };
            }
        }
        if let Some(good) = self.last_good.take() {
            let history: Vec<Step> = self.history.iter().copied().collect();
            for attempt in 0..r.history_attempts {
                let radius = r.history_radius * f64::from(1u32 << attempt.min(16));
                if self.fit_history(&good, &history, u, radius, attempt as u64) {
                    self.last_good = Some(good);
                    return Recovery::History {
                        radius_m: radius,
                        steps: history.len() + 1,
                    };
                }
            }
        }
        self.last_good = None;
        self.history.clear();
        self.localised_once = false;
        if self
            .draw_uniform_prior(SALT_PRIOR ^ crate::random::mix(self.steps))
            .is_err()
        {
            // Unreachable for a non-empty plan; keep the previous belief rather than none.
            self.proposal.clone_from(&self.particles);
        }
        Recovery::Global
    }

    /// History fitting: re-seeds particles within `radius` of the last good belief (eq. 5 of
    /// the smartphone paper) and replays the steps since then through the filter; true when
    /// some survive the current step too (the proposal then holds them).
    fn fit_history(
        &mut self,
        good: &[TrackParticle],
        history: &[Step],
        u: &StepInput,
        radius: f64,
        attempt: u64,
    ) -> bool {
        let salt = SALT_HISTORY ^ crate::random::mix(self.steps ^ (attempt << 48));
        let topology = self.topology;
        let heading_sigma = (self.config.recovery.heading_max / 2.0) as f32;
        let n = self.config.recovery.history_particles;
        let seeded: Vec<TrackParticle> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .flat_map_iter(|c| {
                let mut rng = crate::random::stream(self.config.seed ^ salt, 0, c as u64);
                let count = CHUNK.min(n - c * CHUNK);
                (0..count)
                    .filter_map(|_| {
                        let p = good[rng.random_range(0..good.len())];
                        jitter(topology, &p, radius, heading_sigma, &mut rng)
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
        if seeded.is_empty() {
            return false;
        }
        self.particles = seeded;
        // The re-seeded belief stands at the last good step; the replay replaces the steps
        // since in the ancestry (kept aside until the fit succeeds).
        let keep_paths = self.tree.is_some();
        let roots = if keep_paths {
            self.path_nodes()
        } else {
            Vec::new()
        };
        let mut replayed = Vec::new();
        for (k, s) in history.iter().enumerate() {
            let Ok(h) = StepInput::of(s) else {
                return false;
            };
            if !self.propagate(&h, 0.0, salt ^ crate::random::mix(k as u64 + 1)) {
                return false;
            }
            // A replayed step's heading weighs again but is not counted again.
            self.measure_heading(s);
            self.measure_transitions();
            let m = self.weigh();
            self.resample(m, salt ^ crate::random::mix(k as u64 + 1));
            if keep_paths {
                replayed.push((self.path_nodes(), self.ancestors.clone()));
            }
        }
        if !self.propagate(u, 0.0, salt) {
            return false;
        }
        if let Some(tree) = self.tree.as_mut() {
            let good_step = (self.steps as usize).saturating_sub(1 + history.len());
            tree.root(good_step, roots, self.topology, &self.config.cluster);
            for (nodes, ancestors) in replayed {
                tree.push(nodes, &ancestors, self.topology, &self.config.cluster);
            }
        }
        true
    }
}

/// A copy of `p` moved uniformly within `radius` (eq. 5 of the smartphone paper) and turned by
/// a normal heading error, on a surface of its level; `None` when that point is off the plan.
fn jitter(
    topology: &FloorTopology,
    p: &TrackParticle,
    radius: f64,
    heading_sigma: f32,
    rng: &mut Pcg64Mcg,
) -> Option<TrackParticle> {
    let level = topology.level(p.surface);
    let z = f64::from(topology.z(p.surface));
    for _ in 0..PLACEMENT_TRIES {
        let r = radius * rng.random::<f64>().sqrt();
        let phi = rng.random_range(0.0..std::f64::consts::TAU);
        let (x, y) = (
            f64::from(p.x) + r * phi.cos(),
            f64::from(p.y) + r * phi.sin(),
        );
        if let Some(surface) = topology.locate(x, y, Some(level), Some(z)) {
            let turn: f32 = rng.sample(StandardNormal);
            return Some(TrackParticle {
                x: x as f32,
                y: y as f32,
                heading: wrap(p.heading + heading_sigma * turn),
                scale: p.scale,
                drift: p.drift,
                surface,
            });
        }
    }
    None
}
