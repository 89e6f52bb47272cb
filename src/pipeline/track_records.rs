//! What a tracking run keeps of each step's report: 8 bytes a step (particles, clusters,
//! localised), where a whole [`TrackStep`] is over a hundred, and the steps at which every
//! particle died.

use crate::filter::{Recovery, StepFit, TrackStep};
use serde::Serialize;

/// One step's particle count, cluster count and whether the walker was localised. Particles
/// are below 2³¹ (`kld.max_particles` ≤ 2·10⁸), so the top bit holds `localised`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StepRecord {
    particles_localised: u32,
    /// `u32::MAX`: not clustered.
    clusters: u32,
}

impl StepRecord {
    const LOCALISED: u32 = 1 << 31;

    /// The record of a step's report.
    #[must_use]
    pub fn new(report: &TrackStep) -> Self {
        let count = |n: usize, max: u32| n.min(max as usize) as u32;
        let localised = if report.localised { Self::LOCALISED } else { 0 };
        Self {
            particles_localised: count(report.particles, Self::LOCALISED - 1) | localised,
            clusters: report.clusters.map_or(u32::MAX, |c| count(c, u32::MAX - 1)),
        }
    }

    /// Particles after the step.
    #[must_use]
    pub fn particles(self) -> usize {
        (self.particles_localised & !Self::LOCALISED) as usize
    }

    /// Whether the walker was localised (one dominant cluster) after the step.
    #[must_use]
    pub fn localised(self) -> bool {
        self.particles_localised & Self::LOCALISED != 0
    }

    /// Clusters after the step (`None`: the step was not clustered).
    #[must_use]
    pub fn clusters(self) -> Option<usize> {
        (self.clusters != u32::MAX).then_some(self.clusters as usize)
    }
}

/// A step at which every particle died, and how the filter recovered.
#[derive(Debug, Clone, Serialize)]
pub struct RecoveryEvent {
    /// The step (1-based).
    pub step: usize,
    /// Its time, seconds.
    pub t: f64,
    /// What the filter did.
    #[serde(flatten)]
    pub recovery: Recovery,
}

/// How well the walk fitted the plan, summed over its steps ([`StepFit`]): the evidence of
/// the tracking verdict.
#[derive(Debug, Default, Clone, Copy, PartialEq, Serialize)]
pub struct PlanFit {
    /// Steps the filter propagated.
    pub steps: usize,
    /// Their mean share of particles left alive by the walls.
    pub survival_mean: f64,
    /// Steps that left fewer than half the particles alive (every death included).
    pub steps_half_lost: usize,
    /// The largest excursion of the height change the plan's surfaces did not explain,
    /// summed along the walk (max − min of the running sum), metres: a walk that climbs
    /// a storey on a one-level plan shows the storey.
    pub unexplained_climb_m: f64,
    #[serde(skip)]
    survival_sum: f64,
    #[serde(skip)]
    climb: f64,
    #[serde(skip)]
    climb_min: f64,
    #[serde(skip)]
    climb_max: f64,
}

impl PlanFit {
    /// Adds one step's fit.
    pub fn add(&mut self, fit: &StepFit) {
        self.steps += 1;
        self.survival_sum += f64::from(fit.survival);
        self.survival_mean = self.survival_sum / self.steps as f64;
        self.steps_half_lost += usize::from(fit.survival < 0.5);
        self.climb += f64::from(fit.unexplained_dz);
        self.climb_min = self.climb_min.min(self.climb);
        self.climb_max = self.climb_max.max(self.climb);
        self.unexplained_climb_m = self.climb_max - self.climb_min;
    }
}

/// Every step's [`StepRecord`], and the steps at which every particle died.
#[derive(Debug, Default, Clone)]
pub struct StepRecords {
    /// One record per step of the walk.
    pub steps: Vec<StepRecord>,
    /// The deaths, in step order.
    pub recoveries: Vec<RecoveryEvent>,
    /// How well the steps fitted the plan.
    pub fit: PlanFit,
}

impl StepRecords {
    /// Records the report of step `i` (0-based) at time `t`.
    pub fn push(&mut self, i: usize, t: f64, report: &TrackStep) {
        self.steps.push(StepRecord::new(report));
        if let Some(fit) = &report.fit {
            self.fit.add(fit);
        }
        if let Some(recovery) = report.recovery {
            self.recoveries.push(RecoveryEvent {
                step: i + 1,
                t,
                recovery,
            });
        }
    }

    /// The first localised step (0-based).
    #[must_use]
    pub fn first_localised(&self) -> Option<usize> {
        self.steps.iter().position(|r| r.localised())
    }

    /// Particles summed over the steps (the filter's work).
    #[must_use]
    pub fn particle_steps(&self) -> usize {
        self.steps.iter().map(|r| r.particles()).sum()
    }
}
