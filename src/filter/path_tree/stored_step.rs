//! A smoothed step as the tree keeps it until the end of the walk (64 bytes, lossless).

use super::SmoothedStep;
use crate::filter::cluster::Cluster;

/// `certain`, kept in the top bit of [`StoredStep::ancestors`].
const CERTAIN_BIT: u32 = 1 << 31;

/// A smoothed step as the tree keeps it until the end of the walk: 64 bytes, where a
/// [`SmoothedStep`] takes 96. Lossless: every count here is below 2³¹ (particles are capped
/// at `kld.max_particles` ≤ 2·10⁸, clusters at `cluster.max_particles` ≤ 10⁷); a larger
/// one would be kept as 2³¹ − 1.
#[derive(Debug, Clone, Copy)]
pub(super) struct StoredStep {
    x: f64,
    y: f64,
    z: f64,
    heading: f64,
    spread: f64,
    weight: f64,
    level: i32,
    /// `u32::MAX`: no estimate.
    particles: u32,
    hypotheses: u32,
    /// Distinct ancestors; the top bit is `certain`.
    ancestors: u32,
}

impl StoredStep {
    pub(super) const NONE: Self = Self {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        heading: 0.0,
        spread: 0.0,
        weight: 0.0,
        level: 0,
        particles: u32::MAX,
        hypotheses: 0,
        ancestors: 0,
    };

    pub(super) fn store(step: &SmoothedStep) -> Self {
        let count = |n: usize| n.min((CERTAIN_BIT - 1) as usize) as u32;
        let certain = if step.certain { CERTAIN_BIT } else { 0 };
        let (hypotheses, ancestors) = (count(step.hypotheses), count(step.ancestors) | certain);
        match step.estimate {
            Some(c) => Self {
                x: c.x,
                y: c.y,
                z: c.z,
                heading: c.heading,
                spread: c.spread,
                weight: c.weight,
                level: c.level,
                particles: count(c.particles),
                hypotheses,
                ancestors,
            },
            None => Self {
                hypotheses,
                ancestors,
                ..Self::NONE
            },
        }
    }

    pub(super) fn get(&self) -> SmoothedStep {
        SmoothedStep {
            estimate: (self.particles != u32::MAX).then_some(Cluster {
                x: self.x,
                y: self.y,
                z: self.z,
                level: self.level,
                heading: self.heading,
                spread: self.spread,
                weight: self.weight,
                particles: self.particles as usize,
            }),
            hypotheses: self.hypotheses as usize,
            certain: self.ancestors & CERTAIN_BIT != 0,
            ancestors: (self.ancestors & !CERTAIN_BIT) as usize,
        }
    }
}
