//! A FootSLAM walk's WiFi scans inside the filter: which scans fall in a step, and their
//! weight for one particle ([`crate::model::scan_pairs`] eq. 3) at the point of the step
//! walked by then.

use super::scan_trail::ScanTrail;
use crate::geometry::Pose2;
use crate::model::{ReferenceScans, ScanEvidence};
use crate::sensor::step::share_of_step;
use std::sync::Arc;

/// A walk's WiFi scans waiting to be applied, and where each applied one was taken.
#[derive(Debug)]
pub(super) struct ScanQueue {
    evidence: Arc<ScanEvidence>,
    /// The other walks' placed scans, in a FeetSLAM batch's later passes.
    references: Option<Arc<ReferenceScans>>,
    /// Index of the next scan to apply.
    pub(super) next: usize,
    /// The level of each scan applied.
    levels: Vec<i32>,
    /// Scans applied at the current step and the fraction of the step walked at each.
    step_scans: Vec<(usize, f32)>,
}

impl ScanQueue {
    /// The queue of `evidence`'s scans, none applied, weighed also against `references`.
    pub(super) fn new(
        evidence: Arc<ScanEvidence>,
        references: Option<Arc<ReferenceScans>>,
    ) -> Self {
        Self {
            evidence,
            references,
            next: 0,
            levels: Vec::new(),
            step_scans: Vec::new(),
        }
    }

    /// Moves the scans taken after `previous` and up to `t` (those before the first step
    /// apply at the start pose) into the step's scans, on `level`.
    pub(super) fn take_step(&mut self, previous: Option<f64>, t: f64, level: i32) {
        self.step_scans.clear();
        let times = self.evidence.times();
        while let Some(&ts) = times.get(self.next).filter(|&&ts| ts <= t) {
            let along = share_of_step(previous, t, ts);
            self.step_scans.push((self.next, along as f32));
            self.levels.push(level);
            self.next += 1;
        }
    }

    /// Whether the other walks' scans weigh in too.
    pub(super) fn has_references(&self) -> bool {
        self.references.is_some()
    }

    /// The step's scans for a particle that moved from `from` to `to` with `trail`: for
    /// each, eq. (3) at the point walked by then, which then joins the trail. Returns the
    /// log of the product.
    pub(super) fn log_factor(&self, from: Pose2, to: Pose2, trail: &mut ScanTrail) -> f64 {
        let mut log_factor = 0.0;
        for &(k, along) in &self.step_scans {
            let along = f64::from(along);
            let at = (
                (from.x + along * (to.x - from.x)) as f32,
                (from.y + along * (to.y - from.y)) as f32,
            );
            let level = self.levels[k];
            let earlier = &*trail;
            log_factor +=
                self.evidence
                    .log_factor(k, at, |j| earlier.get(j), |j| self.levels[j] == level);
            if let Some(references) = &self.references {
                log_factor += references.log_factor(k, at, level);
            }
            trail.push(at);
        }
        log_factor
    }
}
