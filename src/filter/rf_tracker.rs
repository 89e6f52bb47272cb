//! The known-map tracker driven by step events and WiFi scans together (Woodman & Harle
//! 2009, sec. 5): the filter starts at the first scan with its prior drawn in that scan's
//! region `R_prior` (eq. 2) — or about a known start — and then each scan weighs the
//! particles (eq. 12; [`super::rf_assist`]) where they were when it was taken: at the first
//! step after the scan, at the point of each particle's move at the scan's time (interpolated
//! between the step events before and after it).
//!
//! This is eq. 12's "latest scan at every step", judged at the scan's time: a containment
//! region applied again at the following steps to where each particle was at the scan
//! changes nothing (every particle descends from one already inside). With `every_step`
//! the latest scan is instead applied at every step where the particles are then, as the
//! paper's words read: with tight regions (a threshold calibrated on the survey) that cuts
//! off the walker's lead over a scan up to 5 s old and drags the belief behind.
//!
//! Steps before the first scan come before any WiFi information; without a known start they
//! are reported without particles (and count towards the steps to localise).

use super::path_tree::{SmoothedStep, SmoothedWalk};
use super::rf_assist::{RfLocaliser, RfMode};
use super::tracker::{StepMeasurement, TrackStep, Tracker};
use super::tracker_config::TrackerConfig;
use crate::error::{Error, Result};
use crate::map::{CellField, FloorTopology};
use crate::model::TransitionPrior;
use crate::sensor::{Step, WifiScan};

/// A [`Tracker`] fed with WiFi scans through a radio map.
#[derive(Debug)]
pub struct RfTracker<'a> {
    topology: &'a FloorTopology,
    config: TrackerConfig,
    rf: &'a RfLocaliser,
    scans: &'a [WifiScan],
    tracker: Option<Tracker<'a>>,
    /// `scans[..next_scan]` are at or before the last step.
    next_scan: usize,
    /// The latest usable scan's index and its measurement.
    current: Option<(usize, Option<CellField>)>,
    /// The last scan applied.
    applied: Option<usize>,
    /// Time of the last step processed.
    last_step: Option<f64>,
    /// Steps processed.
    steps: usize,
    /// Steps processed before the tracker started (its prior stands after the last of them).
    started_after: Option<usize>,
    /// A learned map's transitions as a motion prior, handed to the tracker.
    transitions: Option<&'a TransitionPrior>,
}

impl<'a> RfTracker<'a> {
    /// A tracker on `topology` using `rf`'s radio map with `scans` (in time order, on the
    /// step trace's clock).
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `config` fails [`TrackerConfig::validate`]; [`Error::InvalidData`]
    /// when `scans` are not in time order; and, when the tracker starts at once (a known start, or
    /// evidence mode), the errors of [`Tracker::new`].
    pub fn new(
        topology: &'a FloorTopology,
        config: &TrackerConfig,
        rf: &'a RfLocaliser,
        scans: &'a [WifiScan],
    ) -> Result<Self> {
        config.validate()?;
        if let Some(w) = scans.windows(2).find(|w| w[1].t < w[0].t) {
            return Err(Error::invalid(
                format!("WiFi scan at t = {}", w[1].t),
                format!("follows one at t = {}: scans must be in time order", w[0].t),
            ));
        }
        // With radio evidence the map rules no place out: the walk starts anywhere on the
        // plan at its first step, so every step has an answer.
        let tracker = match (config.start, rf.config().mode) {
            (Some(_), _) | (None, RfMode::Evidence) => Some(Tracker::new(topology, config)?),
            (None, _) => None,
        };
        let started_after = tracker.as_ref().map(|_| 0);
        Ok(Self {
            topology,
            config: config.clone(),
            rf,
            scans,
            tracker,
            next_scan: 0,
            current: None,
            applied: None,
            last_step: None,
            steps: 0,
            started_after,
            transitions: None,
        })
    }

    /// The whole-walk answer for each step processed (the belief after it), from the
    /// tracker's ancestry ([`Tracker::smoothed`]); `None` for the steps before the tracker
    /// started (no scan yet) except the last of them, where its prior stands. `None` when
    /// smoothing is off.
    pub fn smoothed(&self) -> Option<Vec<Option<SmoothedStep>>> {
        let smoothed = self.tracker.as_ref().map(Tracker::smoothed);
        self.place_smoothed(smoothed)
    }

    /// [`Self::smoothed`], ending the smoothing ([`Tracker::take_smoothed`]): each step's
    /// answer is computed as it is read.
    pub fn take_smoothed(&mut self) -> Option<SmoothedWalk<'a>> {
        if !self.config.smoothing {
            return None;
        }
        let cluster = self.config.cluster;
        let walk = match (self.tracker.as_mut(), self.started_after) {
            (Some(t), Some(before)) => t.take_smoothed()?.on_walk(before, self.steps),
            _ => SmoothedWalk::empty(self.topology, cluster, self.steps),
        };
        Some(walk)
    }

    /// The tracker's smoothed steps (`None`: no tracker yet) placed on this walk's steps.
    fn place_smoothed(
        &self,
        smoothed: Option<Option<Vec<SmoothedStep>>>,
    ) -> Option<Vec<Option<SmoothedStep>>> {
        let mut out = vec![None; self.steps];
        let (Some(smoothed), Some(before)) = (smoothed, self.started_after) else {
            return self.config.smoothing.then_some(out);
        };
        // Tracker step g stands after this walk's step `before + g` (1-based).
        for (g, s) in smoothed?.into_iter().enumerate() {
            if let Some(slot) = (before + g).checked_sub(1).and_then(|i| out.get_mut(i)) {
                *slot = Some(s);
            }
        }
        Some(out)
    }

    /// Uses a learned map's transitions as the tracker's motion prior
    /// ([`Tracker::set_transition_prior`]).
    pub fn set_transition_prior(&mut self, prior: Option<&'a TransitionPrior>) {
        self.transitions = prior;
        if let Some(t) = self.tracker.as_mut() {
            t.set_transition_prior(prior);
        }
    }

    /// The tracker, once started.
    #[must_use]
    pub fn tracker(&self) -> Option<&Tracker<'a>> {
        self.tracker.as_ref()
    }

    /// Particles of the prior, once started.
    pub fn initial_particles(&self) -> Option<usize> {
        self.tracker.as_ref().map(Tracker::initial_particles)
    }

    /// Processes one step with the latest scan at or before it.
    ///
    /// # Errors
    ///
    /// As [`Tracker::update`]: [`Error::InvalidData`] for a step whose length, heading change or
    /// height change is not finite; and, at the scan that starts the tracker, the errors of
    /// [`Tracker::new_in_region`] (no particle can be placed on the plan).
    pub fn update(&mut self, step: &Step) -> Result<TrackStep> {
        while self.next_scan < self.scans.len() && self.scans[self.next_scan].t <= step.t {
            self.next_scan += 1;
        }
        let max_age = self.rf.config().max_scan_age;
        let latest = self
            .next_scan
            .checked_sub(1)
            .filter(|&i| step.t - self.scans[i].t <= max_age);
        // The prior was drawn at this step for this scan: it stands where the walker was
        // when the scan was taken.
        let mut started = false;
        if let Some(i) = latest
            && self.current.as_ref().is_none_or(|c| c.0 != i)
        {
            let (prior, measurement) = self.rf.scan_fields(&self.scans[i]);
            match self.tracker.as_mut() {
                Some(t) => t.set_region(Some(prior)),
                None => {
                    let mut tracker =
                        Tracker::new_in_region(self.topology, &self.config, Some(prior))?;
                    tracker.set_transition_prior(self.transitions);
                    self.tracker = Some(tracker);
                    started = true;
                }
            }
            self.current = Some((i, measurement));
        }
        let previous = self.last_step.replace(step.t);
        if started {
            self.started_after = Some(self.steps);
        }
        self.steps += 1;
        let Some(tracker) = self.tracker.as_mut() else {
            return Ok(TrackStep {
                t: step.t,
                particles: 0,
                clusters: None,
                estimate: None,
                localised: false,
                recovery: None,
                fit: None,
            });
        };
        let every_step = self.rf.config().every_step;
        let measurement = match (latest, &self.current) {
            (Some(i), Some((j, Some(m)))) if i == *j && (every_step || self.applied != Some(i)) => {
                self.applied = Some(i);
                Some(if every_step {
                    StepMeasurement::at_end(m)
                } else {
                    StepMeasurement {
                        field: m,
                        at: if started {
                            0.0
                        } else {
                            share_of_step(previous, step.t, self.scans[i].t)
                        },
                    }
                })
            }
            _ => None,
        };
        tracker.update_with(step, measurement)
    }
}

/// The share of the move from the step event at `previous` to the one at `t` done at
/// `scan_t` (clamped to [0, 1]); 1 without an earlier step, when the move's start is unknown.
fn share_of_step(previous: Option<f64>, t: f64, scan_t: f64) -> f32 {
    match previous {
        Some(p) if t > p => ((scan_t - p) / (t - p)).clamp(0.0, 1.0) as f32,
        _ => 1.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::{CellMap, CellRaster, RadioMap, TopologyConfig};
    use crate::sim::Tower;
    use std::sync::Arc;

    #[test]
    fn a_prior_region_holds_every_particle_and_an_impossible_measurement_is_ignored() {
        let tower = Tower::new(&Default::default()).expect("tower");
        let topology = FloorTopology::build(&tower.plan, &TopologyConfig::default()).expect("topo");
        let cells = CellMap::build(&tower.plan, &topology, &Default::default()).expect("cells");
        let map = RadioMap::empty(&cells);
        let raster = Arc::new(CellRaster::on_plan(&map, &topology, 0.25).expect("raster"));
        // The region: the cells of level 1 west of x = 10 m.
        let values: Vec<f32> = cells
            .cells()
            .iter()
            .map(|c| {
                let west =
                    geo::BoundingRect::bounding_rect(&c.area).is_some_and(|b| b.max().x <= 10.0);
                if c.level == 1 && west {
                    0.0
                } else {
                    f32::NEG_INFINITY
                }
            })
            .collect();
        let region = CellField::new(raster.clone(), values, f32::NEG_INFINITY);
        let config = TrackerConfig::default();
        let mut tracker =
            Tracker::new_in_region(&topology, &config, Some(region.clone())).expect("tracker");
        let uniform = Tracker::new(&topology, &config).expect("uniform");
        // The uniform prior's density on the region: its share of the floor area.
        let area = |inside: &dyn Fn(&crate::map::RadioCell) -> bool| {
            cells
                .cells()
                .iter()
                .filter(|c| inside(c))
                .map(|c| geo::Area::unsigned_area(&c.area))
                .sum::<f64>()
        };
        let share = area(&|c| {
            c.level == 1
                && geo::BoundingRect::bounding_rect(&c.area).is_some_and(|b| b.max().x <= 10.0)
        }) / area(&|_| true);
        let ratio = tracker.initial_particles() as f64 / uniform.initial_particles() as f64;
        assert!((ratio / share - 1.0).abs() < 0.05, "{ratio} vs {share}");
        assert!(
            tracker
                .particles()
                .iter()
                .all(|p| { region.at(topology.level(p.surface), p.x, p.y) == 0.0 })
        );
        let step = Step {
            t: 0.5,
            length: 0.0,
            dheading: 0.0,
            dz: 0.0,
            heading: None,
        };
        let nowhere = CellField::new(raster, Vec::new(), f32::NEG_INFINITY);
        let r = tracker
            .update_with(&step, Some(StepMeasurement::at_end(&nowhere)))
            .expect("step");
        assert_eq!(tracker.measurements_ignored(), 1);
        assert!(r.particles > 0 && r.recovery.is_none());
        let r = tracker
            .update_with(&step, Some(StepMeasurement::at_end(&region)))
            .expect("step");
        assert_eq!(tracker.measurements_ignored(), 1);
        assert!(r.particles > 0);
    }

    #[test]
    fn a_scan_falls_at_its_share_of_the_step() {
        assert_eq!(share_of_step(Some(1.0), 2.0, 1.25), 0.25);
        assert_eq!(share_of_step(Some(1.0), 2.0, 0.5), 0.0);
        assert_eq!(share_of_step(Some(1.0), 2.0, 2.0), 1.0);
        assert_eq!(share_of_step(Some(2.0), 2.0, 2.0), 1.0);
        assert_eq!(share_of_step(None, 2.0, 1.5), 1.0);
    }
}
