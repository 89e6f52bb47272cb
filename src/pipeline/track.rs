//! Tracking one walk on a known floor plan (Woodman & Harle 2008), as stages:
//!
//! 1. **prior** — a [`Tracker`] (or, with a radio map and the walk's scans, an
//!    [`RfTracker`] whose prior is the first scan's containment region, Woodman & Harle 2009);
//! 2. **steps** — each step propagates, weighs and resamples the particles; its report is
//!    kept as an 8-byte [`StepRecord`](super::StepRecord), its estimate (from localisation
//!    on) as the filtered track, and the particle cloud at the steps asked for;
//! 3. **smoothing** — the whole-walk answer, read step by step from the particles' ancestry
//!    ([`SmoothedWalk`]) unless the configuration asks for causal answers only.

use super::Progress;
use super::quality::{Quality, QualityConfig, TrackEvidence, track_quality};
use super::track_records::StepRecords;
use crate::Result;
use crate::filter::{RfLocaliser, RfTracker, SmoothedWalk, TrackStep, Tracker, TrackerConfig};
use crate::io::TrackPoint;
use crate::map::FloorTopology;
use crate::model::TransitionPrior;
use crate::sensor::{Step, StepTrace, WifiScan};
use rayon::prelude::*;
use std::time::Instant;

/// The steps after which [`track`] keeps the particle cloud.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub enum SnapshotSteps {
    /// None.
    #[default]
    Never,
    /// The prior (step 0), steps 5 and 25, the step of localisation and the last step.
    Auto,
    /// These steps (0 = the prior).
    At(Vec<usize>),
}

/// Steps of [`SnapshotSteps::Auto`] besides the prior, localisation and the last.
const AUTO_SNAPSHOTS: [usize; 2] = [5, 25];

impl SnapshotSteps {
    fn wanted(&self, step: usize, last: bool, first_fix: bool) -> bool {
        match self {
            Self::Never => false,
            Self::Auto => step == 0 || AUTO_SNAPSHOTS.contains(&step) || last || first_fix,
            Self::At(list) => list.contains(&step),
        }
    }
}

/// A walk's WiFi and the radio map that places it.
#[derive(Debug, Clone, Copy)]
pub struct RadioInput<'a> {
    /// The radio map on the plan's topology.
    pub localiser: &'a RfLocaliser,
    /// The walk's scans, in time order, on the steps' clock.
    pub scans: &'a [WifiScan],
}

/// What [`track`] tracks a walk on.
#[derive(Debug, Clone, Copy)]
pub struct TrackInput<'a> {
    /// The floor plan's walkable surfaces and their connections.
    pub topology: &'a FloorTopology,
    /// A learned map's transitions as a motion prior (FeetSLAM's reuse of a FootSLAM map).
    pub transitions: Option<&'a TransitionPrior>,
    /// RF-assisted localisation.
    pub radio: Option<RadioInput<'a>>,
}

/// The particle cloud after a step, as `(x, y, level)` per particle.
#[derive(Debug, Clone)]
pub struct CloudSnapshot {
    /// The step after which it was taken (0 = the prior).
    pub step: usize,
    /// `prior`, `step`, or `localised` (the step of the first fix).
    pub what: &'static str,
    /// The particles.
    pub points: Vec<(f32, f32, i32)>,
    /// Rows of the filtered track at that step.
    pub track_len: usize,
}

/// What [`track`] gives.
#[derive(Debug)]
pub struct TrackRun<'a> {
    /// Every step's record and the deaths.
    pub records: StepRecords,
    /// The estimate of each step from localisation on, as the filter saw it.
    pub filtered: Vec<TrackPoint>,
    /// The particle clouds asked for.
    pub snapshots: Vec<CloudSnapshot>,
    /// The whole-walk answer, per step, computed as it is read (`None` with
    /// `smoothing = false`).
    pub smoothed: Option<SmoothedWalk<'a>>,
    /// Largest number of path nodes the ancestry held (16 bytes each).
    pub path_nodes_peak: usize,
    /// The prior's particles (0 for an RF tracker that never started).
    pub initial_particles: usize,
    /// Memory per particle of the filter.
    pub bytes_per_particle: f64,
    /// Scans no particle was consistent with (ignored).
    pub measurements_ignored: usize,
    /// Steps whose absolute heading weighted the particles.
    pub headings_used: usize,
    /// The filter's seed.
    pub seed: u64,
    /// Seconds spent in the filter.
    pub filter_runtime_s: f64,
    /// Prior draws cut at `kld.max_particles` before the KLD bound was met.
    pub capped_draws: usize,
    /// The step at which the ancestry outgrew `smoothing_max_nodes` (the run then has no
    /// whole-walk answer).
    pub smoothing_dropped_at: Option<usize>,
}

impl TrackRun<'_> {
    /// The run's verdict ([`track_quality`]); `steps_certain` is the number of steps the
    /// whole-walk answer made certain (0 without smoothing).
    #[must_use]
    pub fn quality(&self, steps_certain: usize, config: &QualityConfig) -> Quality {
        track_quality(
            &TrackEvidence {
                fit: &self.records.fit,
                recoveries: &self.records.recoveries,
                steps: self.records.steps.len(),
                settled: steps_certain > 0 || self.records.first_localised().is_some(),
                capped_draws: self.capped_draws,
                smoothing_dropped_at: self.smoothing_dropped_at,
            },
            config,
        )
    }
}

/// Tracks the walk `trace` on `input` with `config`, keeping the particle clouds of
/// `snapshots`. The stages are those of the [module](self). Warns through `progress` when
/// the prior stopped at `kld.max_particles` before its bound was met. The result borrows
/// `input`, not the trace.
///
/// # Errors
///
/// As [`Tracker::new`] or [`RfTracker::new`](crate::filter::RfTracker::new): `config` out of range,
/// a start off the plan, or a plan with no walkable surface; as their `update`: a step that is not
/// finite, or (with a radio map) no particle placeable at the first scan.
pub fn track<'a>(
    input: &TrackInput<'a>,
    trace: &StepTrace,
    config: &TrackerConfig,
    snapshots: &SnapshotSteps,
    progress: &dyn Progress,
) -> Result<TrackRun<'a>> {
    let started = Instant::now();
    let mut walker = prior(input, config, progress)?;
    let mut run = TrackRun {
        records: StepRecords::default(),
        filtered: Vec::new(),
        snapshots: Vec::new(),
        smoothed: None,
        path_nodes_peak: 0,
        initial_particles: 0,
        bytes_per_particle: 0.0,
        measurements_ignored: 0,
        headings_used: 0,
        seed: config.seed,
        filter_runtime_s: 0.0,
        capped_draws: 0,
        smoothing_dropped_at: None,
    };
    if let Some(tracker) = walker.tracker()
        && snapshots.wanted(0, trace.is_empty(), false)
    {
        run.snapshots.push(snapshot(tracker, 0, "prior", 0));
    }
    progress.start("tracking", trace.len() as u64);
    let mut localised_before = false;
    for (i, step) in trace.steps().iter().enumerate() {
        let report = walker.update(step)?;
        let first_fix = report.localised && !localised_before;
        localised_before |= report.localised;
        if localised_before && let Some(c) = report.estimate {
            run.filtered.push(TrackPoint {
                t: step.t,
                x: c.x,
                y: c.y,
                z: c.z,
                level: c.level,
            });
        }
        let k = i + 1;
        if snapshots.wanted(k, k == trace.len(), first_fix)
            && let Some(tracker) = walker.tracker()
        {
            let what = if first_fix { "localised" } else { "step" };
            run.snapshots
                .push(snapshot(tracker, k, what, run.filtered.len()));
        }
        run.records.push(i, step.t, &report);
        progress.advance(1);
    }
    progress.finish();
    run.smoothed = walker.take_smoothed(trace.len());
    if let Some(tracker) = walker.tracker() {
        run.path_nodes_peak = tracker.path_nodes_peak();
        // The prior's particles: an RF tracker starts at the first scan.
        run.initial_particles = tracker.initial_particles();
        run.bytes_per_particle = tracker.bytes_per_particle();
        run.measurements_ignored = tracker.measurements_ignored();
        run.headings_used = tracker.headings_used();
        run.capped_draws = tracker.capped_draws();
        run.smoothing_dropped_at = tracker.smoothing_dropped_at();
    }
    run.filter_runtime_s = started.elapsed().as_secs_f64();
    Ok(run)
}

/// Stage 1: the filter and its prior.
fn prior<'a>(
    input: &TrackInput<'a>,
    config: &TrackerConfig,
    progress: &dyn Progress,
) -> Result<Walker<'a>> {
    let walker = match input.radio {
        Some(radio) => {
            let mut t = RfTracker::new(input.topology, config, radio.localiser, radio.scans)?;
            t.set_transition_prior(input.transitions);
            Walker::Rf(Box::new(t))
        }
        None => {
            let mut t = Tracker::new(input.topology, config)?;
            t.set_transition_prior(input.transitions);
            Walker::Plain(Box::new(t))
        }
    };
    if let Some(tracker) = walker.tracker()
        && tracker.capped_draws() > 0
    {
        progress.warn(&format!(
            "the prior over the plan stopped at kld.max_particles = {} before the KLD bound \
             was met: the plan is large for an unknown start (each step will be slow and the \
             prior thin); give a start, a radio map, or raise the cap",
            config.kld.max_particles
        ));
    }
    Ok(walker)
}

/// The tracker's particle cloud now.
fn snapshot(tracker: &Tracker, step: usize, what: &'static str, track_len: usize) -> CloudSnapshot {
    let topology = tracker.topology();
    CloudSnapshot {
        step,
        what,
        // In parallel: the prior's snapshot is a million points.
        points: tracker
            .particles()
            .par_iter()
            .map(|p| (p.x, p.y, topology.level(p.surface)))
            .collect(),
        track_len,
    }
}

/// The tracker with or without a radio map.
enum Walker<'a> {
    Plain(Box<Tracker<'a>>),
    Rf(Box<RfTracker<'a>>),
}

impl<'a> Walker<'a> {
    fn tracker(&self) -> Option<&Tracker<'a>> {
        match self {
            Walker::Plain(t) => Some(t),
            Walker::Rf(t) => t.tracker(),
        }
    }

    /// The smoothed belief after each of the walk's `steps` steps (`None` without
    /// smoothing), computed as it is read.
    fn take_smoothed(&mut self, steps: usize) -> Option<SmoothedWalk<'a>> {
        match self {
            // Tracker step k + 1 stands after the walk's step k; step 0 is the prior.
            Walker::Plain(t) => Some(t.take_smoothed()?.on_walk(0, steps)),
            Walker::Rf(t) => t.take_smoothed(),
        }
    }

    fn update(&mut self, step: &Step) -> Result<TrackStep> {
        match self {
            Walker::Plain(t) => t.update(step),
            Walker::Rf(t) => t.update(step),
        }
    }
}
