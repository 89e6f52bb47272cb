//! `footslam track`'s summary: `summary.json`, the step records it is written from, and the
//! lines printed at the end of a run.

use footslam::filter::RfMode;
use footslam::geometry::LocalFrame;
use footslam::model::wifi_distance::Normalisation;
use footslam::pipeline::{Quality, RecoveryEvent, StepRecord};
use serde::Serialize;
use std::path::Path;

/// `summary.json`.
#[derive(Debug, Serialize)]
pub(super) struct Summary<'r> {
    /// The run's verdict and its reasons (docs/robustness.md).
    pub(super) quality: Quality,
    pub(super) rf: Option<RfSummary>,
    /// Whether the steps' absolute headings weighted the particles.
    pub(super) headings_used: bool,
    /// Steps of the trace that carry an absolute heading.
    pub(super) steps_with_heading: usize,
    pub(super) plan_file: String,
    /// The learned map whose transitions were the motion prior, and its hexagons.
    pub(super) hexmap_file: Option<String>,
    pub(super) hexmap_hexagons: Option<usize>,
    pub(super) steps_file: String,
    pub(super) steps: usize,
    pub(super) steps_to_localise: Option<usize>,
    pub(super) localised_at_t: Option<f64>,
    /// Rows of the filtered track (from localisation on).
    pub(super) track_rows: usize,
    /// The whole-walk answer (absent with `--online`).
    pub(super) smoothing: Option<SmoothingSummary>,
    pub(super) particles_initial: usize,
    pub(super) particles_max: usize,
    pub(super) particles_final: usize,
    /// Written from the step records as they are read (a long walk's lists are long).
    #[serde(serialize_with = "particles_per_step")]
    pub(super) particles_per_step: &'r [StepRecord],
    #[serde(serialize_with = "clusters_per_step")]
    pub(super) clusters_per_step: &'r [StepRecord],
    pub(super) deaths: usize,
    pub(super) recoveries: &'r [RecoveryEvent],
    /// How well the steps fitted the plan.
    pub(super) plan_fit: footslam::pipeline::PlanFit,
    pub(super) seed: u64,
    pub(super) threads: usize,
    pub(super) runtime_s: f64,
    pub(super) filter_runtime_s: f64,
    pub(super) particle_steps_per_s: f64,
    pub(super) bytes_per_particle: f64,
    pub(super) peak_memory_bytes: Option<u64>,
    pub(super) plan: PlanStats,
    pub(super) origin: LocalFrame,
    pub(super) version: &'static str,
}

/// What the radio map did.
#[derive(Debug, Serialize)]
pub(super) struct RfSummary {
    pub(super) radiomap_file: String,
    pub(super) wifi_file: String,
    pub(super) scans: usize,
    /// Scans that hear at least one access point of the radio map (a warning below half).
    pub(super) scans_matched: usize,
    /// Rows of the WiFi log that repeated an access point within a scan (the later kept).
    pub(super) duplicate_readings: usize,
    pub(super) mode: RfMode,
    /// The distance's divisor used: `paper` (k) or `sqrt` (√k).
    pub(super) distance: Normalisation,
    /// The region threshold used.
    pub(super) epsilon_dbm: f64,
    /// Where it came from: `given`, `calibrated` (the map's) or `derived` (from the map's
    /// histograms, for a map without a calibration).
    pub(super) epsilon_source: footslam::filter::EpsilonSource,
    /// The step at which the filter started (the first after the first scan).
    pub(super) started_at_step: Option<usize>,
    /// Scans no particle was consistent with (ignored).
    pub(super) measurements_ignored: usize,
    /// The radio evidence's calibration (`--rf-mode evidence`).
    pub(super) evidence: Option<footslam::model::EvidenceCalibration>,
    /// Why the radio evidence fell back to containment regions, if it did.
    pub(super) evidence_fallback: Option<String>,
}

/// What the smoother answered.
#[derive(Debug, Serialize)]
pub(super) struct SmoothingSummary {
    /// Steps with a smoothed estimate (`track.csv` rows).
    pub(super) steps_estimated: usize,
    /// Steps whose place the whole walk settles (one hypothesis).
    pub(super) steps_certain: usize,
    /// The first certain step (1-based).
    pub(super) first_certain_step: Option<usize>,
    /// Largest number of path nodes held (16 bytes each).
    pub(super) path_nodes_peak: usize,
    /// Seconds spent smoothing after the last step.
    pub(super) runtime_s: f64,
}

/// What the smoothed walk gave, counted as it was written.
#[derive(Debug, Default)]
pub(super) struct SmoothedStats {
    pub(super) estimated: usize,
    pub(super) certain: usize,
    pub(super) first_certain: Option<usize>,
    pub(super) path_nodes_peak: usize,
    pub(super) runtime_s: f64,
}

/// The floor plan's size.
#[derive(Debug, Serialize)]
pub(super) struct PlanStats {
    pub(super) surfaces: usize,
    pub(super) walkable_area_m2: f64,
    pub(super) levels: (i32, i32),
}

fn particles_per_step<S: serde::Serializer>(r: &&[StepRecord], s: S) -> Result<S::Ok, S::Error> {
    s.collect_seq(r.iter().map(|r| r.particles()))
}

fn clusters_per_step<S: serde::Serializer>(r: &&[StepRecord], s: S) -> Result<S::Ok, S::Error> {
    s.collect_seq(r.iter().map(|r| r.clusters()))
}

impl Summary<'_> {
    /// Prints the run's outcome on stdout, `out` being the run's folder.
    pub(super) fn print(&self, out: &Path) {
        match self.steps_to_localise {
            Some(k) => info!(
                "localised after {k} of {} steps ({} particles at the start, {} at the end, {} deaths)",
                self.steps, self.particles_initial, self.particles_final, self.deaths
            ),
            None => info!(
                "not localised in {} steps ({} particles at the start, {} at the end, {} deaths)",
                self.steps, self.particles_initial, self.particles_final, self.deaths
            ),
        }
        if let Some(rf) = &self.rf {
            info!(
                "radio map: {} measurements, {} distance, epsilon {:.2} dBm ({}), started at step {}, {} scan(s) ignored",
                rf.mode.name(),
                rf.distance.name(),
                rf.epsilon_dbm,
                rf.epsilon_source.name(),
                rf.started_at_step.map_or("-".into(), |s| s.to_string()),
                rf.measurements_ignored
            );
        }
        if let Some(smoothing) = &self.smoothing
            && smoothing.steps_estimated < self.steps
        {
            let started = self.rf.as_ref().and_then(|rf| rf.started_at_step);
            info!(
                "track.csv: {} of {} steps have an estimate{}",
                smoothing.steps_estimated,
                self.steps,
                started.map_or(String::new(), |s| format!(
                    " (the filter started at step {s}, after the first WiFi scan; the steps \
                     before it have no row)"
                ))
            );
        }
        info!(
            "filter: {:.2} s, {:.2e} particle-steps/s",
            self.filter_runtime_s, self.particle_steps_per_s
        );
        super::verbosity::done(out, Some(&self.quality.line()));
    }
}
