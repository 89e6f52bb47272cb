//! Propagation, Algorithm 1 for every particle: the step perturbed and scaled (eqs. 7–8),
//! moved (eqs. 9–11), walked through the floor polygons' walls and connections, and weighted
//! by its height change across stairs (eqs. 15–17).

use super::fit::Propagation;
use super::memo::Memo;
use super::particle::{SCALE_RANGE, wrap};
use super::resample::resize;
use super::{CHUNK, TrackParticle, Tracker};
use crate::error::{Error, Result};
use crate::map::FloorTopology;
use crate::sensor::Step;
use rand::RngExt;
use rand_distr::StandardNormal;
use rand_pcg::Pcg64Mcg;
use rayon::prelude::*;

/// Step inputs in the particles' precision.
#[derive(Debug, Clone, Copy)]
pub(super) struct StepInput {
    pub(super) length: f32,
    pub(super) dheading: f32,
    pub(super) dz: f32,
}

impl Tracker<'_> {
    /// Algorithm 1 for every particle of the belief, into the proposal: returns false when
    /// every particle hit a wall. `heading_offset` is added to the step's heading change
    /// (the heading search of recovery). Its sums are kept for the step's fit
    /// ([`super::StepFit`]).
    pub(super) fn propagate(&mut self, u: &StepInput, heading_offset: f32, salt: u64) -> bool {
        let n = self.particles.len();
        resize(&mut self.proposal, n);
        resize(&mut self.log_weights, n);
        resize(&mut self.bin_index, n);
        let model = Motion {
            topology: self.topology,
            length_sigma: self.config.length_sigma as f32,
            dheading_sigma: self.config.dheading_sigma as f32,
            dz_sigma: self.config.dz_sigma as f32,
            scale_walk_sigma: self.config.scale_walk_sigma as f32,
            drift_walk_sigma: self.config.drift_walk_sigma as f32,
            u: StepInput {
                dheading: u.dheading + heading_offset,
                ..*u
            },
        };
        let (seed, step, bins, dense) = (
            self.config.seed ^ salt,
            self.steps,
            &self.bins,
            self.dense_bins,
        );
        let chunks: Vec<Propagation> = self
            .particles
            .par_chunks(CHUNK)
            .zip(self.proposal.par_chunks_mut(CHUNK))
            .zip(self.log_weights.par_chunks_mut(CHUNK))
            .zip(self.bin_index.par_chunks_mut(CHUNK))
            .enumerate()
            .map(|(c, (((from, to), lw), bi))| {
                let mut rng = crate::random::stream(seed, step, c as u64);
                let mut sums = Propagation {
                    particles: from.len(),
                    ..Propagation::default()
                };
                // Most particles share a log-weight (no change of height): one exp each.
                let mut exp = Memo::default();
                for (i, (p, q)) in from.iter().zip(to.iter_mut()).enumerate() {
                    let (next, ll) = model.apply(p, &mut rng);
                    if ll > f32::NEG_INFINITY {
                        let w = exp.get(ll, |l| f64::from(l).exp());
                        let dz_poly = model.topology.z(next.surface) - model.topology.z(p.surface);
                        sums.alive += 1;
                        sums.weight += w;
                        sums.weighted_dz += w * f64::from(dz_poly);
                    }
                    *q = next;
                    lw[i] = ll;
                    if dense {
                        let level = model.topology.level(next.surface);
                        bi[i] = bins.bin(next.x, next.y, next.heading, level) as u32;
                    }
                }
                sums
            })
            .collect();
        self.propagation = chunks
            .into_iter()
            .fold(Propagation::default(), Propagation::add);
        self.propagation.alive > 0
    }
}

/// The step model and the map the particles move on (Algorithm 1).
struct Motion<'a> {
    topology: &'a FloorTopology,
    length_sigma: f32,
    dheading_sigma: f32,
    dz_sigma: f32,
    scale_walk_sigma: f32,
    drift_walk_sigma: f32,
    u: StepInput,
}

impl Motion<'_> {
    /// Algorithm 1 for one particle: the moved particle and its log-weight (−∞ when a wall
    /// was crossed).
    #[inline]
    fn apply(&self, p: &TrackParticle, rng: &mut Pcg64Mcg) -> (TrackParticle, f32) {
        let x: f32 = rng.sample(StandardNormal);
        let y: f32 = rng.sample(StandardNormal);
        let drift = if self.drift_walk_sigma > 0.0 {
            let d: f32 = rng.sample(StandardNormal);
            p.drift + self.drift_walk_sigma * d
        } else {
            p.drift
        };
        let dtheta = self.u.dheading + drift + self.dheading_sigma * x; // eq. (8)
        let length = (self.u.length * p.scale + self.length_sigma * y).max(0.0); // eq. (7)
        let heading = wrap(p.heading + dtheta); // eq. (9)
        let (sin, cos) = heading.sin_cos();
        let to = [p.x + length * cos, p.y + length * sin]; // eqs. (10), (11)
        let scale = if self.scale_walk_sigma > 0.0 {
            let s: f32 = rng.sample(StandardNormal);
            (p.scale + self.scale_walk_sigma * s).clamp(SCALE_RANGE.0, SCALE_RANGE.1)
        } else {
            p.scale
        };
        let moved = |surface| TrackParticle {
            x: to[0],
            y: to[1],
            heading,
            scale,
            drift,
            surface,
        };
        match self.topology.walk(p.surface, [p.x, p.y], to) {
            None => (moved(p.surface), f32::NEG_INFINITY), // eq. (14)
            Some(surface) => {
                let dz_poly = self.topology.z(surface) - self.topology.z(p.surface); // eq. (15)
                let e = (self.u.dz - dz_poly) / self.dz_sigma;
                (moved(surface), -0.5 * e * e) // eq. (17), up to a constant
            }
        }
    }
}

impl StepInput {
    pub(super) fn of(step: &Step) -> Result<Self> {
        if !(step.length.is_finite() && step.dheading.is_finite() && step.dz.is_finite()) {
            return Err(Error::invalid(
                format!("step at t = {} s", step.t),
                "has a non-finite length, heading change or height change",
            ));
        }
        Ok(Self {
            length: step.length as f32,
            dheading: step.dheading as f32,
            dz: step.dz as f32,
        })
    }
}
