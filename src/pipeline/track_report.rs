//! What the `track` job gives: the whole-walk answer read into rows ([`TrackAnswer`]) and
//! its report ([`TrackReport`]), which is `summary.json` on the command line and the
//! `summary` dict in Python.

use super::track::TrackRun;
use super::track_job::PreparedTrack;
use super::track_records::{PlanFit, RecoveryEvent};
use super::{Quality, QualityConfig};
use crate::filter::rf_assist::EvidenceReport;
use crate::filter::{EpsilonSource, RfMode};
use crate::geometry::LocalFrame;
use crate::io::{SmoothedPoint, TrackPoint};
use crate::model::wifi_distance::Normalisation;
use serde::Serialize;
use std::time::Instant;

/// Stage 4: the whole-walk answer, one row per step with an estimate (`track.csv`), and
/// what the smoother gave.
#[derive(Debug, Default)]
pub struct TrackAnswer {
    /// The smoothed rows (empty online).
    pub rows: Vec<SmoothedPoint>,
    /// What the smoother gave (`None` online).
    pub smoothing: Option<TrackSmoothingReport>,
}

impl TrackAnswer {
    /// Reads the run's smoothed walk (taking it) at the steps' `times`.
    pub fn read(run: &mut TrackRun, times: &[f64]) -> Self {
        let started = Instant::now();
        let Some(walk) = run.smoothed.take() else {
            return Self::default();
        };
        let mut stats = TrackSmoothingReport::default();
        let mut rows = Vec::new();
        for (i, (&t, k)) in times.iter().zip(walk.iter()).enumerate() {
            let Some(k) = k else { continue };
            stats.steps_certain += usize::from(k.certain);
            if k.certain && stats.first_certain_step.is_none() {
                stats.first_certain_step = Some(i + 1);
            }
            let Some(c) = k.estimate else { continue };
            stats.steps_estimated += 1;
            rows.push(SmoothedPoint {
                point: TrackPoint {
                    t,
                    x: c.x,
                    y: c.y,
                    z: c.z,
                    level: c.level,
                },
                certain: k.certain,
                hypotheses: k.hypotheses,
                spread: c.spread,
                share: c.weight,
            });
        }
        stats.path_nodes_peak = run.path_nodes_peak;
        stats.runtime_s = started.elapsed().as_secs_f64();
        Self {
            rows,
            smoothing: Some(stats),
        }
    }

    /// The steps the whole walk settles (one hypothesis): the answer's track.
    #[must_use]
    pub fn certain(&self) -> Vec<TrackPoint> {
        self.rows
            .iter()
            .filter(|r| r.certain)
            .map(|r| r.point)
            .collect()
    }

    /// The other steps' estimates, `(x, y, level)`.
    #[must_use]
    pub fn uncertain(&self) -> Vec<(f32, f32, i32)> {
        self.rows
            .iter()
            .filter(|r| !r.certain)
            .map(|r| (r.point.x as f32, r.point.y as f32, r.point.level))
            .collect()
    }
}

/// What the smoother answered.
#[derive(Debug, Clone, Default, Serialize)]
pub struct TrackSmoothingReport {
    /// Steps with a smoothed estimate (`track.csv` rows).
    pub steps_estimated: usize,
    /// Steps whose place the whole walk settles (one hypothesis).
    pub steps_certain: usize,
    /// The first certain step (1-based).
    pub first_certain_step: Option<usize>,
    /// Largest number of path nodes held (16 bytes each).
    pub path_nodes_peak: usize,
    /// Seconds spent smoothing after the last step.
    pub runtime_s: f64,
}

/// What the radio map did.
#[derive(Debug, Clone, Serialize)]
pub struct RfReport {
    /// The radio map's name.
    pub radiomap_file: String,
    /// The WiFi log's name.
    pub wifi_file: String,
    /// Scans in the log.
    pub scans: usize,
    /// Scans that hear at least one access point of the radio map (a warning below half).
    pub scans_matched: usize,
    /// Rows of the WiFi log that repeated an access point within a scan (the later kept).
    pub duplicate_readings: usize,
    /// The mode used.
    pub mode: RfMode,
    /// The distance's divisor used: `paper` (k) or `sqrt` (√k).
    pub distance: Normalisation,
    /// The region threshold used, dBm.
    pub epsilon_dbm: f64,
    /// Where it came from: `given`, `calibrated` (the map's) or `derived`.
    pub epsilon_source: EpsilonSource,
    /// The step at which the filter started (the first after the first scan).
    pub started_at_step: Option<usize>,
    /// Scans no particle was consistent with (ignored).
    pub measurements_ignored: usize,
    /// The radio evidence's calibration (evidence mode).
    pub evidence: Option<EvidenceReport>,
    /// Why the radio evidence fell back to containment regions, if it did.
    pub evidence_fallback: Option<String>,
}

/// The floor plan's size.
#[derive(Debug, Clone, Serialize)]
pub struct PlanStats {
    /// Walkable surfaces.
    pub surfaces: usize,
    /// Their area, m².
    pub walkable_area_m2: f64,
    /// The lowest and highest level.
    pub levels: (i32, i32),
}

/// `summary.json` of `track`, and the `summary` Python returns: one struct, so that the
/// two cannot differ.
#[derive(Debug, Clone, Serialize)]
pub struct TrackReport {
    /// The run's verdict and its reasons (docs/robustness.md).
    pub quality: Quality,
    /// What the radio map did (with one).
    pub rf: Option<RfReport>,
    /// Whether the steps' absolute headings weighted the particles.
    pub headings_used: bool,
    /// Steps of the trace that carry an absolute heading.
    pub steps_with_heading: usize,
    /// The plan's name.
    pub plan_file: String,
    /// The learned map whose transitions were the motion prior.
    pub hexmap_file: Option<String>,
    /// Its hexagons.
    pub hexmap_hexagons: Option<usize>,
    /// The steps' name.
    pub steps_file: String,
    /// How many steps there were.
    pub steps: usize,
    /// The first step after which the filter was localised (1-based).
    pub steps_to_localise: Option<usize>,
    /// Its time, s.
    pub localised_at_t: Option<f64>,
    /// Rows of the filtered track (from localisation on).
    pub track_rows: usize,
    /// The whole-walk answer (absent online).
    pub smoothing: Option<TrackSmoothingReport>,
    /// Particles at the prior.
    pub particles_initial: usize,
    /// Particles at most.
    pub particles_max: usize,
    /// Particles after the last step.
    pub particles_final: usize,
    /// Particles after each step.
    pub particles_per_step: Vec<usize>,
    /// Clusters after each step (none: not clustered).
    pub clusters_per_step: Vec<Option<usize>>,
    /// Times every particle died.
    pub deaths: usize,
    /// Each death's recovery.
    pub recoveries: Vec<RecoveryEvent>,
    /// How well the steps fitted the plan.
    pub plan_fit: PlanFit,
    /// The filter's seed.
    pub seed: u64,
    /// The worker threads.
    pub threads: usize,
    /// Seconds from the job's start to the report.
    pub runtime_s: f64,
    /// Seconds in the filter.
    pub filter_runtime_s: f64,
    /// The filter's throughput.
    pub particle_steps_per_s: f64,
    /// Memory per particle of the filter, bytes.
    pub bytes_per_particle: f64,
    /// The process' peak memory, bytes.
    pub peak_memory_bytes: Option<u64>,
    /// The plan's size.
    pub plan: PlanStats,
    /// The local frame.
    pub origin: LocalFrame,
    /// footslam's version.
    pub version: &'static str,
}

impl TrackReport {
    /// Stage 5: the report of `run` on `prepared` with its `answer`, the job having started
    /// at `started` (runtimes), on the current rayon pool (threads).
    #[must_use]
    pub fn new(
        prepared: &PreparedTrack,
        run: &TrackRun,
        answer: &TrackAnswer,
        started: Instant,
    ) -> Self {
        let records = &run.records;
        let steps = prepared.trace.steps();
        let first = records.first_localised();
        let initial = run.initial_particles;
        let certain = answer.smoothing.as_ref().map_or(0, |s| s.steps_certain);
        let particles: Vec<usize> = records.steps.iter().map(|r| r.particles()).collect();
        Self {
            quality: run.quality(certain, &QualityConfig::default()),
            rf: prepared.radio.as_ref().map(|r| RfReport {
                radiomap_file: r.map_label.clone(),
                wifi_file: r.wifi_label.clone(),
                scans: r.scans.len(),
                scans_matched: r.matched,
                duplicate_readings: r.duplicate_readings,
                mode: r.localiser.config().mode,
                distance: r.localiser.distance(),
                epsilon_dbm: r.localiser.epsilon(),
                epsilon_source: r.localiser.epsilon_source(),
                started_at_step: particles.iter().position(|&n| n > 0).map(|i| i + 1),
                measurements_ignored: run.measurements_ignored,
                evidence: r.localiser.evidence(),
                evidence_fallback: r.localiser.fallback().map(str::to_owned),
            }),
            headings_used: run.headings_used > 0,
            steps_with_heading: prepared.trace.with_heading(),
            plan_file: prepared.plan_label.clone(),
            hexmap_file: prepared.transitions.as_ref().map(|(_, l)| l.clone()),
            hexmap_hexagons: prepared.transitions.as_ref().map(|(t, _)| t.len()),
            steps_file: prepared.steps_label.clone(),
            steps: steps.len(),
            steps_to_localise: first.map(|i| i + 1),
            localised_at_t: first.map(|i| steps[i].t),
            track_rows: run.filtered.len(),
            smoothing: answer.smoothing.clone(),
            particles_initial: initial,
            particles_max: particles
                .iter()
                .copied()
                .max()
                .unwrap_or(initial)
                .max(initial),
            particles_final: particles.last().copied().unwrap_or(initial),
            clusters_per_step: records.steps.iter().map(|r| r.clusters()).collect(),
            particles_per_step: particles,
            deaths: records.recoveries.len(),
            recoveries: records.recoveries.clone(),
            plan_fit: records.fit,
            seed: run.seed,
            threads: rayon::current_num_threads(),
            runtime_s: started.elapsed().as_secs_f64(),
            filter_runtime_s: run.filter_runtime_s,
            particle_steps_per_s: records.particle_steps() as f64 / run.filter_runtime_s.max(1e-9),
            bytes_per_particle: run.bytes_per_particle,
            peak_memory_bytes: crate::memory::peak_bytes(),
            plan: PlanStats {
                surfaces: prepared.topology.len(),
                walkable_area_m2: prepared.topology.total_area(),
                levels: prepared.topology.levels(),
            },
            origin: prepared.frame,
            version: env!("CARGO_PKG_VERSION"),
        }
    }
}
