//! FootSLAM's whole-walk answer: the final particles' ancestral paths, averaged.
//!
//! After the last step every particle carries, through its resampling ancestors
//! ([`super::Lineage`]), one whole path; the weighted final particles' paths are a sample
//! of the joint smoothing distribution `p(P_0:k | Z_1:k)` (Kitagawa 1996, sec. 4.1; the
//! "genealogical tree" of Doucet & Johansen 2009). One sampled path carries the motion
//! noise of eq. (5) that its particle happened to draw; their mean does not.
//!
//! `draws` paths are drawn from the final weights (systematic, so a particle of weight `w`
//! is drawn `⌊draws·w⌋` or `⌈draws·w⌉` times) and replayed from their random streams. The
//! posterior of a walk that may or may not have closed a loop has several modes, and the
//! mean of two modes is a path nobody walked: only the paths within `mode_radius_m` (RMS
//! over the walk) of the most probable path are averaged, per step, and their RMS distance
//! from that mean is the step's spread — how firmly the particles agree on where it was.
//! The configuration is [`super::SmoothingConfig`].

use super::{FootSlam, Pose2, resample};
use crate::random::filter_stream;
use rand::RngExt;
use rayon::prelude::*;

/// The mean of the drawn paths near the most probable one, per step.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct SmoothedPath {
    /// One pose per step: the mean position, the most probable path's heading.
    pub(super) path: Vec<Pose2>,
    /// Per step, the RMS distance of the averaged paths from their mean, metres.
    pub(super) spread_m: Vec<f64>,
    /// Distinct paths drawn, and how many of them were averaged.
    pub(super) distinct: usize,
    pub(super) averaged: usize,
}

impl FootSlam {
    /// The whole-walk answer about `best`, the most probable particle's replayed path.
    pub(super) fn smoothed_path(&self, best: &[Pose2]) -> SmoothedPath {
        let config = self.config.smoothing;
        let n = self.particles.len();
        let draws = config.draws.min(n);
        let alone = || SmoothedPath {
            path: best.to_vec(),
            spread_m: vec![0.0; best.len()],
            distinct: 1,
            averaged: 1,
        };
        if draws == 0 || best.is_empty() {
            return alone();
        }
        // The stream after the last step's: the draw does not disturb the filter's.
        let k = self.steps.len() as u64 + 1;
        let u0 = filter_stream(self.config.seed, k).random::<f64>();
        let mut drawn = Vec::with_capacity(draws);
        resample::systematic(&self.weights, draws, u0, &mut drawn);
        // Distinct particles, with how often each was drawn (systematic draws come sorted).
        let mut counted: Vec<(usize, usize)> = Vec::new();
        for &i in &drawn {
            match counted.last_mut() {
                Some((j, c)) if *j == i => *c += 1,
                _ => counted.push((i, 1)),
            }
        }
        let radius2 = config.mode_radius_m * config.mode_radius_m;
        let near: Vec<(Vec<(f32, f32)>, usize)> = counted
            .par_iter()
            .filter_map(|&(i, count)| {
                let path = self.replay_path(i);
                let ms = path
                    .iter()
                    .zip(best)
                    .map(|(p, b)| (p.x - b.x).powi(2) + (p.y - b.y).powi(2))
                    .sum::<f64>()
                    / best.len() as f64;
                (ms <= radius2).then(|| {
                    let points = path.iter().map(|p| (p.x as f32, p.y as f32)).collect();
                    (points, count)
                })
            })
            .collect();
        let total: usize = near.iter().map(|(_, c)| c).sum();
        if total == 0 {
            return alone();
        }
        let w = 1.0 / total as f64;
        let mean: Vec<(f64, f64)> = (0..best.len())
            .map(|s| {
                near.iter().fold((0.0, 0.0), |(x, y), (p, c)| {
                    let cw = *c as f64 * w;
                    (x + cw * f64::from(p[s].0), y + cw * f64::from(p[s].1))
                })
            })
            .collect();
        let spread_m = mean
            .iter()
            .enumerate()
            .map(|(s, &(mx, my))| {
                let v = near.iter().fold(0.0, |v, (p, c)| {
                    let (dx, dy) = (f64::from(p[s].0) - mx, f64::from(p[s].1) - my);
                    v + *c as f64 * w * (dx * dx + dy * dy)
                });
                v.sqrt()
            })
            .collect();
        SmoothedPath {
            path: mean
                .iter()
                .zip(best)
                .map(|(&(x, y), b)| Pose2::new(x, y, b.heading))
                .collect(),
            spread_m,
            distinct: counted.len(),
            averaged: near.len(),
        }
    }
}
