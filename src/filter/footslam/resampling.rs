//! FootSLAM's steps (d) and (f): the weights normalised, and the particles resampled —
//! survivors share their maps' nodes ([`crate::map::HexMapForest::inherit`]) and extend
//! their ancestry ([`super::Lineage`]) only when their index changes.

use super::{FootSlam, Particle};
use crate::filter::resample::{self, ResampleMethod};
use crate::map::ParticleHexMap;
use crate::random::filter_stream;
use rand::RngExt;
use rayon::prelude::*;

impl FootSlam {
    /// Normalises the log weights and fills the linear weights; sums in index order so the
    /// result does not depend on the thread count.
    pub(super) fn normalise(&mut self) {
        let max = self
            .log_weights
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        // The exponentials in parallel, their sum in index order.
        let (weights, log_weights) = (&mut self.weights, &mut self.log_weights);
        let shifted = |(w, &l): (&mut f64, &f64)| *w = (l - max).exp();
        weights.par_iter_mut().zip(&*log_weights).for_each(shifted);
        let log_sum = max + weights.iter().sum::<f64>().ln();
        let normalised = |(w, l): (&mut f64, &mut f64)| {
            *l -= log_sum;
            *w = l.exp();
        };
        weights.par_iter_mut().zip(log_weights).for_each(normalised);
        debug_assert!((self.weights.iter().sum::<f64>() - 1.0).abs() < 1e-6);
    }

    /// Resamples after step `k`; survivors share maps ([`crate::map::HexMapForest::inherit`])
    /// and extend their ancestry only when their index changes.
    pub(super) fn resample(&mut self, k: u64) {
        let n = self.particles.len();
        let u0 = filter_stream(self.config.seed, k).random::<f64>();
        match self.config.resample.method {
            ResampleMethod::Systematic => {
                resample::systematic(&self.weights, n, u0, &mut self.parents)
            }
            ResampleMethod::Residual => {
                resample::residual(&self.weights, n, u0, &mut self.parents, &mut self.residuals);
            }
        }
        // The next generation, maps and ancestry apart.
        let particles = &self.particles;
        self.parents
            .par_iter()
            .map(|&j| {
                let p = &particles[j];
                Particle {
                    pose: p.pose,
                    error: p.error,
                    map: ParticleHexMap::default(),
                    ancestry: p.ancestry,
                    path_log_likelihood: p.path_log_likelihood,
                    wifi_log_likelihood: p.wifi_log_likelihood,
                    trail: p.trail.clone(),
                    axes: p.axes,
                    field: p.field.clone(),
                }
            })
            .collect_into_vec(&mut self.next);
        self.maps.inherit(
            &mut self.particles,
            |p| &mut p.map,
            &self.parents,
            &mut self.children,
            (&mut self.next, |p| &mut p.map),
        );
        // A particle whose index changed starts a segment of ancestry (room made first: what
        // no particle of the next generation descends from goes).
        (self.lineage).collect_garbage(&mut self.next, |p| &mut p.ancestry, n);
        let from_step = (k + 1) as u32;
        for (i, p) in self.next.iter_mut().enumerate() {
            if self.parents[i] != i {
                p.ancestry = self.lineage.child(p.ancestry, from_step, i as u32);
            }
        }
        std::mem::swap(&mut self.particles, &mut self.next);
        // The old generation goes in parallel: its maps' own nodes, trails and field maps.
        self.next.par_drain(..).for_each(drop);
        let uniform = -(n as f64).ln();
        self.log_weights.fill(uniform);
        self.weights.fill(1.0 / n as f64);
        self.resamplings += 1;
    }
}
