//! The prior, drawn by Fox's sequential KLD rule: uniform over every surface and heading (or
//! inside a region), or about a known start.

use super::particle::{SCALE_RANGE, wrap};
use super::{CHUNK, TrackParticle, Tracker};
use crate::error::{Error, Result};
use crate::filter::tracker_config::StartPose;
use crate::map::{CellField, FloorTopology};
use rand::RngExt;
use rand_distr::StandardNormal;
use rand_pcg::Pcg64Mcg;
use rayon::prelude::*;
use std::f32::consts::PI;

/// Chunks drawn at once when sampling a prior (a fixed number, so results do not depend on
/// the number of threads).
const PRIOR_BATCH: usize = 8;
/// Tries to place one prior particle on a surface before giving up on it.
pub(super) const PLACEMENT_TRIES: usize = 64;

impl<'a> Tracker<'a> {
    /// Draws the uniform prior over every surface and heading — inside the region when one
    /// is set and particles can be placed there, else over the whole plan.
    pub(super) fn draw_uniform_prior(&mut self, salt: u64) -> Result<()> {
        if let Some(region) = self.region.take() {
            let drawn = self.draw_prior_in(salt, Some(&region));
            self.region = Some(region);
            if drawn.is_ok() {
                return drawn;
            }
        }
        self.draw_prior_in(salt, None)
    }

    /// The uniform prior over every surface and heading, restricted to where `region` is
    /// finite when given: candidates are drawn uniformly over the whole plan and counted by
    /// the KLD rule exactly as the unrestricted prior, and those outside the region are
    /// dropped. The prior thus has the unrestricted prior's density, its particle count
    /// proportional to the region's floor area (Woodman & Harle 2009, sec. 2 and 5.1) — KLD
    /// counted over the region's own bins would ask for more particles per square metre the
    /// more fragmented the region (every cell's edge bins count whole).
    fn draw_prior_in(&mut self, salt: u64, region: Option<&CellField>) -> Result<()> {
        let topology = self.topology;
        let (lo, hi) = SCALE_RANGE;
        let scale_sigma = self.config.scale_sigma as f32;
        let drift_sigma = self.config.drift_sigma as f32;
        let at_least = self.config.kld.min_particles;
        self.draw_candidates(salt, at_least, move |rng| {
            let (surface, [x, y]) = topology.sample_uniform(rng);
            let keep = region.is_none_or(|r| {
                r.at(topology.level(surface), x as f32, y as f32) > f32::NEG_INFINITY
            });
            let particle = TrackParticle {
                x: x as f32,
                y: y as f32,
                heading: rng.random_range(-PI..PI),
                scale: (1.0 + scale_sigma * rng.sample::<f32, _>(StandardNormal)).clamp(lo, hi),
                drift: if drift_sigma > 0.0 {
                    drift_sigma * rng.sample::<f32, _>(StandardNormal)
                } else {
                    0.0
                },
                surface,
            };
            Some((particle, keep))
        })
    }

    /// Draws prior particles by Fox's sequential KLD rule: chunks are generated in parallel
    /// from per-chunk streams, then counted in order until `n ≥ n_χ(k)`.
    pub(super) fn draw_prior(
        &mut self,
        salt: u64,
        draw: impl Fn(&mut Pcg64Mcg) -> Option<TrackParticle> + Sync,
    ) -> Result<()> {
        self.draw_candidates(salt, 0, move |rng| draw(rng).map(|p| (p, true)))
    }

    /// The KLD rule of [`Self::draw_prior`] over candidates `(particle, keep)`: every
    /// candidate counts towards `n` and its bin, only kept ones become particles; drawing
    /// goes on (up to `max_particles` candidates) until at least `at_least` are kept.
    ///
    /// Two passes over the same streams, so that a million-particle prior is written once,
    /// in place, rather than grown: the counting pass draws batches of chunks into reused
    /// buffers and runs the rule, noting how many candidates of each chunk it took and kept;
    /// the drawing pass draws those chunks again (each from its own stream: the same
    /// candidates) and writes their kept particles straight into the belief.
    fn draw_candidates(
        &mut self,
        salt: u64,
        at_least: usize,
        draw: impl Fn(&mut Pcg64Mcg) -> Option<(TrackParticle, bool)> + Sync,
    ) -> Result<()> {
        let seed = self.config.seed ^ salt;
        let max = self.config.kld.max_particles;
        let draw_chunk = |c: usize, out: &mut Vec<(TrackParticle, bool)>| {
            let mut rng = crate::random::stream(seed, 0, c as u64);
            out.clear();
            out.extend(
                (0..CHUNK).filter_map(|_| (0..PLACEMENT_TRIES).find_map(|_| draw(&mut rng))),
            );
        };
        // Counting pass: (candidates taken, kept) of each chunk.
        let mut taken: Vec<(usize, usize)> = Vec::new();
        let mut buffers: Vec<Vec<(TrackParticle, bool)>> = (0..PRIOR_BATCH)
            .map(|_| Vec::with_capacity(CHUNK))
            .collect();
        let (mut candidates, mut kept) = (0usize, 0usize);
        let mut settled = false;
        self.bins.clear();
        let mut required = self.bins.required(0);
        'outer: loop {
            let first = taken.len();
            buffers
                .par_iter_mut()
                .enumerate()
                .for_each(|(k, out)| draw_chunk(first + k, out));
            if buffers.iter().all(Vec::is_empty) {
                return Err(Error::not_enough(
                    "no prior particle could be placed on a walkable surface",
                    "",
                ));
            }
            for batch in &buffers {
                let mut t = (0, 0);
                for &(p, keep) in batch {
                    candidates += 1;
                    t.0 += 1;
                    if !settled {
                        let level = self.topology.level(p.surface);
                        if self.bins.mark(self.bins.bin(p.x, p.y, p.heading, level)) {
                            required = self.bins.required(self.bins.occupied());
                        }
                        settled = self.bins.enough_given(candidates, required);
                    }
                    if keep {
                        kept += 1;
                        t.1 += 1;
                    }
                    if (settled && kept >= at_least) || candidates >= max {
                        let met = self.bins.satisfied(candidates, self.bins.occupied());
                        self.capped_draws += usize::from(candidates >= max && !met);
                        taken.push(t);
                        break 'outer;
                    }
                }
                taken.push(t);
            }
        }
        if kept == 0 {
            return Err(Error::not_enough(
                "no prior particle could be placed inside the prior region",
                "",
            ));
        }
        // Drawing pass: each chunk's kept particles into their place.
        let mut particles = Vec::with_capacity(kept);
        particles.par_extend(rayon::iter::repeat_n(TrackParticle::default(), kept));
        let mut places = Vec::with_capacity(taken.len());
        let mut rest = particles.as_mut_slice();
        for (c, &(n, k)) in taken.iter().enumerate() {
            let (head, tail) = rest.split_at_mut(k);
            places.push((c, n, head));
            rest = tail;
        }
        places.into_par_iter().for_each_init(
            || Vec::with_capacity(CHUNK),
            |buffer, (c, n, out)| {
                draw_chunk(c, buffer);
                let own = buffer[..n].iter().filter(|(_, keep)| *keep);
                for (slot, &(p, _)) in out.iter_mut().zip(own) {
                    *slot = p;
                }
            },
        );
        self.particles = particles;
        // The uniform prior stands in for this step's proposal when it replaces a dead belief
        // (copied in parallel: a million particles' fresh pages).
        self.proposal.clear();
        self.proposal.par_extend(self.particles.par_iter().copied());
        Ok(())
    }

    /// The known start's surface, or a clear error when the point is off the plan.
    pub(super) fn locate_start(&self, start: &StartPose) -> Result<StartSampler<'a>> {
        let surface = self
            .topology
            .locate(start.x, start.y, start.level, None)
            .ok_or_else(|| {
                Error::mismatch(
                    format!(
                        "the start ({}, {}{}) is not on a walkable surface of the plan",
                        start.x,
                        start.y,
                        start
                            .level
                            .map_or(String::new(), |l| format!(", level {l}"))
                    ),
                    "give a start inside the plan, in its frame",
                )
            })?;
        Ok(StartSampler {
            topology: self.topology,
            start: *start,
            level: self.topology.level(surface),
            z: f64::from(self.topology.z(surface)),
            position_sigma: self.config.start_position_sigma,
            heading_sigma: self.config.start_heading_sigma,
            scale_sigma: self.config.scale_sigma,
            drift_sigma: self.config.drift_sigma,
        })
    }
}

/// Draws particles about a known start.
pub(super) struct StartSampler<'a> {
    topology: &'a FloorTopology,
    start: StartPose,
    level: i32,
    z: f64,
    position_sigma: f64,
    heading_sigma: f64,
    scale_sigma: f64,
    drift_sigma: f64,
}

impl StartSampler<'_> {
    pub(super) fn sample(&self, rng: &mut Pcg64Mcg) -> Option<TrackParticle> {
        let g = |rng: &mut Pcg64Mcg| rng.sample::<f64, _>(StandardNormal);
        let x = self.start.x + self.position_sigma * g(rng);
        let y = self.start.y + self.position_sigma * g(rng);
        let surface = self.topology.locate(x, y, Some(self.level), Some(self.z))?;
        Some(
            TrackParticle {
                x: x as f32,
                y: y as f32,
                heading: match self.start.heading {
                    Some(h) => wrap((h + self.heading_sigma * g(rng)) as f32),
                    // Unknown: uniform over the circle.
                    None => rng.random_range(-PI..PI),
                },
                scale: (1.0 + self.scale_sigma * g(rng)) as f32,
                drift: (self.drift_sigma * g(rng)) as f32,
                surface,
            }
            .clamp_scale(),
        )
    }
}
