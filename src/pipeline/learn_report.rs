//! `learn`'s `summary.json` as typed structs ([`LearnReport`], one [`WalkReport`] per
//! walk): what the command line writes and the Python package returns, from one
//! definition, so the keys cannot drift.

use super::learn::{LearnWalk, Learned, LearnedRadio};
use super::learn_job::{PreparedLearn, WalkLabels};
use super::learn_reports::{AxesReport, FieldReport, SmoothingReport};
use super::learn_walks::WalkRun;
use super::quality::{Quality, QualityConfig};
use crate::filter::departure::Departure;
use crate::geometry::{HexGrid, LocalFrame, path_length};
use crate::map::{CellConfig, LearnedPlan};
use crate::model::PairLikelihood;
use crate::model::wifi_distance::held_out_quantiles;
use serde::Serialize;
use std::collections::BTreeMap;

/// One walk's figures in `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct WalkReport {
    /// The walk's verdict and its reasons (docs/robustness.md).
    pub quality: Quality,
    /// The steps' name (a path, or `<DataFrame>`).
    pub steps_file: String,
    /// The GPS fixes' name.
    pub gps_file: Option<String>,
    /// Steps of the trace that carry an absolute heading.
    pub steps_with_heading: usize,
    /// Steps whose absolute heading weighted the particles.
    pub headings_used: usize,
    /// Particles.
    pub particles: usize,
    /// Steps.
    pub steps: usize,
    /// The walk's seed (the run's plus its number in the batch).
    pub seed: u64,
    /// Seconds in the filter.
    pub filter_runtime_s: f64,
    /// Particles × steps per second of filter.
    pub particle_steps_per_s: f64,
    /// Effective sample size after the last step.
    pub final_effective_sample_size: f64,
    /// Its least over the walk.
    pub min_effective_sample_size: f64,
    /// Resamplings over the walk.
    pub resamplings: usize,
    /// The most probable particle's index and weight, and its path's log likelihood.
    pub best_particle: usize,
    /// Its weight.
    pub best_particle_weight: f64,
    /// Its path's log likelihood.
    pub best_path_log_likelihood: f64,
    /// Hexagons of the learned map.
    pub hexagons: usize,
    /// Floors found from the steps' height changes (1 for a walk on one floor).
    pub levels: usize,
    /// The map's area, m².
    pub map_area_m2: f64,
    /// The answer's length, metres.
    pub path_length_m: f64,
    /// GPS fixes given, and used.
    pub gps_fixes: usize,
    /// GPS fixes that weighted the particles.
    pub gps_fixes_used: usize,
    /// How far path and map were moved towards the prior map's frame, metres.
    pub prior_offset_m: (f64, f64),
    /// Where the walk's orientation came from and how well it is known.
    pub heading: HeadingReport,
    /// Walkable area of `plan.geojson`, m² (`None`: the map had too little to make a plan
    /// of, and no file was written).
    pub walkable_plan_m2: Option<f64>,
    /// With WiFi: how the scans weighed inside the filter (`None` without scans).
    pub wifi_in_filter: Option<WalkWifiReport>,
    /// Whether the walk's turns showed the building's dominant directions, and how many
    /// straight steps they weighed.
    pub building_axes: AxesReport,
    /// With the steps' magnetic field (`field` column): how it weighed inside the filter.
    pub magnetic_field: Option<FieldReport>,
    /// The whole-walk answer in `track.csv`: how many final paths it averages and how far
    /// they spread.
    pub smoothing: SmoothingReport,
    /// How far the learned path departs from the dead-reckoned steps (`dead_reckoning.csv`),
    /// what supports it, and which path `track.csv` holds (`answer`).
    pub departure_from_dead_reckoning: Departure,
}

impl WalkReport {
    /// The report of `walk` learned as `run`, its inputs named by `labels`, its walkable plan
    /// `plan` (`None`: too small to make one).
    pub fn new(
        walk: &LearnWalk,
        run: &WalkRun,
        labels: &WalkLabels,
        plan: Option<&LearnedPlan>,
    ) -> Self {
        let (config, estimate, filter) = (&run.config, &run.estimate, &run.filter);
        let steps = walk.trace.len();
        let ess = filter.ess_history();
        Self {
            quality: run.quality(&QualityConfig::default()),
            steps_file: labels.steps.clone(),
            gps_file: labels.gps.clone(),
            steps_with_heading: walk.trace.with_heading(),
            headings_used: filter.headings_used(),
            particles: config.particles,
            steps,
            seed: config.seed,
            filter_runtime_s: run.runtime_s,
            particle_steps_per_s: (config.particles * steps) as f64 / run.runtime_s.max(1e-9),
            final_effective_sample_size: filter.effective_sample_size(),
            min_effective_sample_size: ess.iter().copied().fold(f64::INFINITY, f64::min),
            resamplings: filter.resamplings(),
            best_particle: estimate.index,
            best_particle_weight: estimate.weight,
            best_path_log_likelihood: estimate.path_log_likelihood,
            hexagons: estimate.map.cells.len(),
            levels: estimate.map.levels.len().max(1),
            map_area_m2: estimate.map.cells.len() as f64
                * HexGrid::new(config.hex_radius).cell_area(),
            path_length_m: path_length(estimate.path.iter().map(|p| (p.x, p.y))),
            gps_fixes: walk.fixes.len(),
            gps_fixes_used: filter.gps_fixes_used(),
            prior_offset_m: estimate.prior_offset,
            heading: HeadingReport {
                start_source: run.start_source,
                start_deg: config.start.heading.to_degrees(),
                start_sigma_deg: config
                    .start_heading_sigma
                    .min(std::f64::consts::PI)
                    .to_degrees(),
                final_sigma_deg: filter.heading_spread().to_degrees(),
            },
            walkable_plan_m2: plan.map(|p| p.area_m2),
            wifi_in_filter: WalkWifiReport::of(walk, run, labels.wifi_duplicate_readings),
            building_axes: run.axes_report(),
            magnetic_field: run.field_report(),
            smoothing: run.smoothing_report(),
            departure_from_dead_reckoning: run.departure.clone(),
        }
    }
}

/// How a walk's WiFi scans weighed inside the filter ([`crate::model::scan_pairs`]).
#[derive(Debug, Clone, Serialize)]
pub struct WalkWifiReport {
    /// Scans in the walk's WiFi log.
    pub scans: usize,
    /// Rows of the log that repeated an access point within a scan (the later kept).
    pub duplicate_readings: usize,
    /// Scans that weighted the particles.
    pub scans_used: usize,
    /// Scan pairs close enough in time to calibrate the model on dead reckoning.
    pub calibration_pairs: usize,
    /// Pairs of a scan and an earlier one that weighed in.
    pub informative_pairs: usize,
    /// How long before its time stamp a scan was heard, as calibrated, seconds.
    pub latency_s: Option<f64>,
    /// The calibrated model: per distance bin the median dissimilarity and its spread, dB.
    pub model: Option<PairLikelihood>,
    /// In a FeetSLAM pass: the other walks' scans (where the pass before placed them) the
    /// scans were weighed against (`None`: not in this run).
    pub cross_walk_references: Option<usize>,
    /// The pairs that calibrated that model.
    pub cross_walk_calibration_pairs: Option<usize>,
    /// The part of `best_path_log_likelihood` the scans gave.
    pub best_path_wifi_log_likelihood: f64,
    /// Why the scans did not weigh (`None` when they did).
    pub unused: Option<String>,
}

impl WalkWifiReport {
    /// The report of `walk`'s scans in `run`; `None` for a walk without scans.
    fn of(walk: &LearnWalk, run: &WalkRun, duplicate_readings: usize) -> Option<Self> {
        let outcome = run.wifi.as_ref()?;
        let evidence = outcome.as_ref().ok();
        Some(Self {
            scans: walk.scans.len(),
            duplicate_readings,
            scans_used: run.filter.scans_used(),
            calibration_pairs: evidence.map_or(0, |e| e.calibration_pairs),
            informative_pairs: evidence.map_or(0, |e| e.pairs()),
            latency_s: evidence.map(|e| e.latency_s),
            model: evidence.map(|e| e.likelihood.clone()),
            cross_walk_references: run.wifi_references.as_ref().map(|r| r.references()),
            cross_walk_calibration_pairs: run.wifi_references.as_ref().map(|r| r.calibration_pairs),
            best_path_wifi_log_likelihood: run.estimate.wifi_log_likelihood,
            unused: outcome.as_ref().err().map(ToString::to_string),
        })
    }
}

/// Where a walk's start heading came from and how uncertain the map's orientation is.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct HeadingReport {
    /// `gps fixes` (the first fixes' track), `compass` (the steps' `heading` column),
    /// `config` (`start.heading` with `start_heading_sigma`), `assumed` (`start.heading`,
    /// exact: a map in the walk's own frame) or `unknown` (uniform over the circle).
    pub start_source: &'static str,
    /// The start heading, degrees counter-clockwise from east.
    pub start_deg: f64,
    /// Its spread before the walk, degrees (1σ; 0 when assumed exact).
    pub start_sigma_deg: f64,
    /// The spread of the particles' headings after the last step, degrees (1σ,
    /// [`crate::filter::FootSlam::heading_spread`]): the map's orientation as the whole
    /// walk pins it.
    pub final_sigma_deg: f64,
}

/// What `learn` made of the walks' WiFi: `summary.json`'s `radio` block.
#[derive(Debug, Clone, Serialize)]
pub struct LearnRadioReport {
    /// Cell granularity, metres.
    pub granularity_m: f64,
    /// Cells of the learned plan.
    pub cells: usize,
    /// The rooms (walkable pieces) they divide.
    pub rooms: usize,
    /// Scans read per walk, in the order of the walks (walks without a WiFi log: zeros).
    pub scans: Vec<usize>,
    /// Scans added to a cell, per walk.
    pub scans_added: Vec<usize>,
    /// Scans left out (placed outside every cell), per walk.
    pub scans_skipped: Vec<usize>,
    /// Share of the learned plan's area in cells with a scan.
    pub coverage: f64,
    /// Scans per such cell.
    pub mean_scans_per_covered_cell: f64,
    /// Access points of the map.
    pub access_points: usize,
    /// The region threshold calibrated on the walks' own scans (as `survey` does).
    pub epsilon: Option<f64>,
    /// The same for the square-root distance.
    pub epsilon_sqrt: Option<f64>,
    /// Leave-one-out normalised distances of held-out scans: p50, p90, p99 and max.
    pub ndist_leave_one_out_p50_p90_p99_max: BTreeMap<&'static str, [Option<f64>; 4]>,
}

impl LearnRadioReport {
    /// The report of `radio`, made on `cells` of walks that held `scans` scans each.
    #[must_use]
    pub fn new(scans: Vec<usize>, radio: &LearnedRadio, cells: &CellConfig) -> Self {
        let survey = &radio.survey;
        let map = &survey.map;
        let (coverage, per_cell) = map.coverage();
        Self {
            granularity_m: cells.granularity,
            cells: survey.cells.cells().len(),
            rooms: survey.cells.rooms().len(),
            scans,
            scans_added: survey.counts.iter().map(|c| c.added).collect(),
            scans_skipped: survey.counts.iter().map(|c| c.skipped).collect(),
            coverage,
            mean_scans_per_covered_cell: per_cell,
            access_points: map.access_points().len(),
            epsilon: map.epsilon,
            epsilon_sqrt: map.epsilon_sqrt,
            ndist_leave_one_out_p50_p90_p99_max: held_out_quantiles(&survey.held),
        }
    }
}

/// `summary.json` of `learn`: one walk's figures at the top level, or a batch's under
/// `walks`, and the run's.
#[derive(Debug, Clone, Serialize)]
pub struct LearnReport {
    /// A batch's verdict: its walks' reasons, each named (one walk's is in its report).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub quality: Option<Quality>,
    /// One walk's report.
    #[serde(flatten)]
    pub single: Option<WalkReport>,
    /// A batch's reports, walk by walk.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub walks: Vec<WalkReport>,
    /// Seconds from the start of the job to the report.
    pub runtime_s: f64,
    /// Worker threads.
    pub threads: usize,
    /// Hexagon edges the outline crosses.
    pub outline_edges: usize,
    /// Hexagons of the prior map.
    pub prior_map_hexagons: usize,
    /// Walks whose counts the prior map holds.
    pub prior_map_walks: u32,
    /// FeetSLAM iterations run over the batch (`iterations` in the configuration; 0 for
    /// one walk, or for walks in frames of their own).
    pub iterations: u32,
    /// The process's peak resident memory, where the system tells.
    pub peak_memory_bytes: Option<u64>,
    /// The frame of maps and paths.
    pub origin: LocalFrame,
    /// The radio map made from the walks' WiFi logs.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radio: Option<LearnRadioReport>,
    /// The toolkit's version.
    pub version: &'static str,
}

impl LearnReport {
    /// The report of `learned`, learned from `prepared`; `walks` holds each walk's report
    /// (made with its walkable plan, [`WalkReport::new`]). `started` is when the job began
    /// and `threads` the worker threads it ran on.
    #[must_use]
    pub fn new(
        prepared: &PreparedLearn,
        learned: &Learned,
        mut walks: Vec<WalkReport>,
        started: std::time::Instant,
        threads: usize,
    ) -> Self {
        let batch = walks.len() > 1;
        let quality = batch.then(|| {
            Quality::combined(
                walks
                    .iter()
                    .enumerate()
                    .map(|(i, s)| (format!("walk {}", i + 1), &s.quality)),
            )
        });
        let single = if batch { None } else { walks.pop() };
        Self {
            quality,
            single,
            walks,
            runtime_s: started.elapsed().as_secs_f64(),
            threads,
            outline_edges: learned.outline_edges,
            prior_map_hexagons: learned.prior_map_hexagons,
            prior_map_walks: learned.prior_map_walks,
            iterations: learned.iterations,
            peak_memory_bytes: crate::memory::peak_bytes(),
            origin: prepared.frame,
            radio: learned.combined.radio.as_ref().map(|r| {
                let scans = prepared.walks.iter().map(|w| w.scans.len()).collect();
                LearnRadioReport::new(scans, r, &prepared.config.cells)
            }),
            version: env!("CARGO_PKG_VERSION"),
        }
    }

    /// Each walk's report, in order.
    pub fn walk_reports(&self) -> impl Iterator<Item = &WalkReport> {
        self.single.iter().chain(&self.walks)
    }
}
