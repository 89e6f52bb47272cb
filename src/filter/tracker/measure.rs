//! Weighing the proposal by what else the step measured: an extra field (e.g. a WiFi region),
//! the step's absolute heading, and a learned map's transitions.

use super::{StepMeasurement, TrackParticle, Tracker};
use crate::sensor::Step;
use rayon::prelude::*;

impl Tracker<'_> {
    /// Adds `m`'s value at every proposed particle to its log-weight, unless that would leave
    /// no particle alive (eq. 1 of the 2009 paper: `w_t = w_{t−1} · p(z_t | s_t)`). Each
    /// particle is judged at the share `m.at` of its move from its parent (`particles[i]`,
    /// which `proposal[i]` was propagated from: every path here ends in [`Self::propagate`]),
    /// on the floor of the nearer end.
    pub(super) fn measure(&mut self, m: StepMeasurement<'_>) {
        let (topology, at) = (self.topology, m.at.clamp(0.0, 1.0));
        debug_assert_eq!(self.particles.len(), self.proposal.len());
        let value = |from: &TrackParticle, to: &TrackParticle| {
            if at >= 1.0 {
                return m.field.at(topology.level(to.surface), to.x, to.y);
            }
            let level = topology.level(if at < 0.5 { from.surface } else { to.surface });
            let x = from.x + at * (to.x - from.x);
            let y = from.y + at * (to.y - from.y);
            m.field.at(level, x, y)
        };
        let parents = &self.particles;
        let any_alive = self
            .proposal
            .par_iter()
            .zip(parents.par_iter())
            .zip(self.log_weights.par_iter())
            .any(|((to, from), lw)| *lw > f32::NEG_INFINITY && value(from, to) > f32::NEG_INFINITY);
        if !any_alive {
            self.ignored += 1;
            return;
        }
        self.proposal
            .par_iter()
            .zip(parents.par_iter())
            .zip(self.log_weights.par_iter_mut())
            .for_each(|((to, from), lw)| *lw += value(from, to));
    }

    /// Heading measurement (not in Woodman & Harle; a compass as in harle-2013 §V): adds
    /// `ln p(h_t | θ_t)` of the step's absolute heading to every proposed particle's
    /// log-weight (tempered by its eq. 3), where the step has one and the model is enabled.
    /// The model's floor keeps every particle alive, so a disturbed reading cannot kill the
    /// belief. Returns whether the step had a heading to apply.
    pub(super) fn measure_heading(&mut self, step: &Step) -> bool {
        let Some(h) = step.heading.filter(|_| self.heading.enabled()) else {
            return false;
        };
        let (model, c) = (&self.heading, self.heading.offset_measurement(h));
        // Tempered by the disturbance's correlation length (heading_likelihood eq. 3).
        let tau = model.temper(step.length) as f32;
        self.proposal
            .par_iter()
            .zip(self.log_weights.par_iter_mut())
            .for_each(|(p, lw)| *lw += tau * model.log_likelihood_f32(&c, p.heading));
        true
    }

    /// The learned map's transitions (FeetSLAM's reuse of a FootSLAM map): adds each
    /// proposed particle's [`TransitionPrior::log_factor`] for its move from its parent, on
    /// the floor it reached. A factor is finite, so no particle dies of it.
    pub(super) fn measure_transitions(&mut self) {
        let Some(prior) = self.transitions else {
            return;
        };
        let topology = self.topology;
        self.proposal
            .par_iter()
            .zip(self.particles.par_iter())
            .zip(self.log_weights.par_iter_mut())
            .for_each(|((to, from), lw)| {
                if *lw > f32::NEG_INFINITY {
                    let level = topology.level(to.surface);
                    *lw += prior.log_factor(
                        (f64::from(from.x), f64::from(from.y)),
                        (f64::from(to.x), f64::from(to.y)),
                        level,
                    );
                }
            });
    }
}
