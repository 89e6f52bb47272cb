//! The outputs of one learned walk: its track (CSV and GeoJSON), map (GeoJSON and one picture
//! per floor), walkable plan and configuration, and its figures for `summary.json`.

use super::field_outputs::write_field_map_png;
use super::learn_inputs::WalkFiles;
use anyhow::Result;
use footslam::filter::departure::Departure;
use footslam::geometry::path_length;
use footslam::geometry::{HexGrid, LocalFrame};
use footslam::io::RunFolder;
use footslam::io::field_map_geojson::write_field_map_geojson;
use footslam::io::floor_plan_geojson::write_floor_plan;
use footslam::io::map_geojson::write_map_geojson;
use footslam::io::track_geojson::write_track_geojson;
use footslam::io::{TimedPoint, TrackPoint, write_trajectory, write_trajectory_with};
use footslam::map::{HexMapSnapshot, PlanConfig, walkable_plan};
use footslam::model::PairLikelihood;
use footslam::pipeline::{
    AxesReport, FieldReport, LearnWalk, Quality, QualityConfig, SmoothingReport, WalkRun,
};
use footslam::render::map_png::{MapPicture, PictureConfig, write_map_png};
use serde::Serialize;

/// One walk's figures in `summary.json`.
#[derive(Debug, Serialize)]
pub(super) struct Summary {
    /// The walk's verdict and its reasons (docs/robustness.md).
    pub(super) quality: Quality,
    steps_file: String,
    gps_file: Option<String>,
    /// Steps of the trace that carry an absolute heading.
    steps_with_heading: usize,
    /// Steps whose absolute heading weighted the particles.
    headings_used: usize,
    pub(super) particles: usize,
    pub(super) steps: usize,
    seed: u64,
    pub(super) filter_runtime_s: f64,
    pub(super) particle_steps_per_s: f64,
    pub(super) final_effective_sample_size: f64,
    min_effective_sample_size: f64,
    resamplings: usize,
    best_particle: usize,
    best_particle_weight: f64,
    best_path_log_likelihood: f64,
    pub(super) hexagons: usize,
    /// Floors found from the steps' height changes (1 for a walk on one floor).
    levels: usize,
    map_area_m2: f64,
    path_length_m: f64,
    pub(super) gps_fixes: usize,
    pub(super) gps_fixes_used: usize,
    /// How far path and map were moved towards the prior map's frame, metres.
    prior_offset_m: (f64, f64),
    /// Where the walk's orientation came from and how well it is known.
    heading: HeadingSummary,
    /// Walkable area of `plan.geojson`, m² (`None`: the map had too little to make a plan
    /// of, and no file was written).
    walkable_plan_m2: Option<f64>,
    /// With WiFi: how the scans weighed inside the filter (`None` without scans).
    wifi_in_filter: Option<WifiSummary>,
    /// Whether the walk's turns showed the building's dominant directions, and how many
    /// straight steps they weighed.
    building_axes: AxesReport,
    /// With the steps' magnetic field (`field` column): how it weighed inside the filter.
    pub(super) magnetic_field: Option<FieldReport>,
    /// The whole-walk answer in `track.csv`: how many final paths it averages and how far
    /// they spread.
    pub(super) smoothing: SmoothingReport,
    /// How far the learned path departs from the dead-reckoned steps (`dead_reckoning.csv`),
    /// what supports it, and which path `track.csv` holds (`answer`).
    departure_from_dead_reckoning: Departure,
}

/// How a walk's WiFi scans weighed inside the filter ([`footslam::model::scan_pairs`]).
#[derive(Debug, Serialize)]
struct WifiSummary {
    /// Scans in the walk's WiFi log.
    scans: usize,
    /// Rows of the log that repeated an access point within a scan (the later kept).
    duplicate_readings: usize,
    /// Scans that weighted the particles.
    scans_used: usize,
    /// Scan pairs close enough in time to calibrate the model on dead reckoning.
    calibration_pairs: usize,
    /// Pairs of a scan and an earlier one that weighed in.
    informative_pairs: usize,
    /// How long before its time stamp a scan was heard, as calibrated, seconds.
    latency_s: Option<f64>,
    /// The calibrated model: per distance bin the median dissimilarity and its spread, dB.
    model: Option<PairLikelihood>,
    /// In a FeetSLAM pass: the other walks' scans (where the pass before placed them) the
    /// scans were weighed against, and the pairs that calibrated that model (`None`: not
    /// in this run).
    cross_walk_references: Option<usize>,
    cross_walk_calibration_pairs: Option<usize>,
    /// The part of `best_path_log_likelihood` the scans gave.
    best_path_wifi_log_likelihood: f64,
    /// Why the scans did not weigh (`None` when they did).
    unused: Option<String>,
}

impl WifiSummary {
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
struct HeadingSummary {
    /// `gps fixes` (the first fixes' track), `compass` (the steps' `heading` column),
    /// `config` (`start.heading` with `start_heading_sigma`), `assumed` (`start.heading`,
    /// exact: a map in the walk's own frame) or `unknown` (uniform over the circle).
    start_source: &'static str,
    /// The start heading, degrees counter-clockwise from east.
    start_deg: f64,
    /// Its spread before the walk, degrees (1σ; 0 when assumed exact).
    start_sigma_deg: f64,
    /// The spread of the particles' headings after the last step, degrees (1σ,
    /// [`FootSlam::heading_spread`]): the map's orientation as the whole walk pins it.
    final_sigma_deg: f64,
}

/// The frame of a run's maps, what placed it on the globe, and the part of it the pictures
/// show.
#[derive(Debug, Clone, Copy)]
pub(super) struct MapFrame<'a> {
    /// The local frame.
    pub(super) frame: &'a LocalFrame,
    /// The building outline, local metres, when given.
    pub(super) outline: Option<&'a geo::Polygon<f64>>,
    /// An outline or a prior map holds the frame to the globe (north up).
    pub(super) anchored: bool,
    /// `--picture-extent`: the part of the frame the map pictures show.
    pub(super) picture_extent: Option<[f64; 4]>,
}

impl<'a> MapFrame<'a> {
    /// The frame of a run's `input`: anchored by its outline or prior map; the pictures
    /// show `picture_extent`, else what they draw.
    pub(super) fn of(
        input: &'a footslam::pipeline::LearnInput<'a>,
        picture_extent: Option<[f64; 4]>,
    ) -> Self {
        Self {
            frame: &input.frame,
            outline: input.outline,
            anchored: input.outline.is_some() || input.prior_map.is_some(),
            picture_extent,
        }
    }
}

/// The pictures of a learned map: one per floor, `NAME.png` the first (level 0) and
/// `NAME-level+N.png` the others, each with the path's part on that floor.
pub(super) struct MapPictures<'a> {
    /// The path `(x, y, level)`, empty for a map of several walks.
    pub(super) path: &'a [(f64, f64, i32)],
    /// What the path is, for the key.
    pub(super) path_label: &'a str,
    /// The frame's y axis points north.
    pub(super) north_up: bool,
    /// The building outline, drawn over the map.
    pub(super) outline: Option<&'a geo::Polygon<f64>>,
    /// The part of the frame shown (`--picture-extent`); `None`: what is drawn.
    pub(super) extent: Option<[f64; 4]>,
}

impl MapPictures<'_> {
    /// Writes the pictures of `map` to `at(NAME…)`.
    pub(super) fn write(
        &self,
        at: &dyn Fn(&str) -> std::path::PathBuf,
        name: &str,
        map: &HexMapSnapshot,
    ) -> Result<()> {
        let mut levels = map.cell_levels();
        if !levels.contains(&0) {
            levels.insert(0, 0);
        }
        for level in levels {
            let on_level = HexMapSnapshot {
                cells: map
                    .cells
                    .iter()
                    .filter(|c| c.level == level)
                    .cloned()
                    .collect(),
                levels: Vec::new(),
                ..*map
            };
            // The path on this floor, broken where the walk left it.
            let (mut walked, mut breaks) = (Vec::new(), Vec::new());
            let mut previous = None;
            for (i, &(x, y, l)) in self.path.iter().enumerate() {
                if l == level {
                    if previous.is_some_and(|j| j + 1 != i) {
                        breaks.push(walked.len());
                    }
                    walked.push((x, y));
                    previous = Some(i);
                }
            }
            let picture = MapPicture {
                path_breaks: &breaks,
                outline: self.outline,
                path_label: self.path_label,
                north_up: self.north_up,
                ..MapPicture::new(&on_level, &walked)
            };
            let file = match level {
                0 => format!("{name}.png"),
                l => format!("{name}-level{l:+}.png"),
            };
            let config = PictureConfig {
                extent: self.extent,
                ..PictureConfig::default()
            };
            write_map_png(&at(&file), &picture, &config)?;
        }
        Ok(())
    }
}

/// Writes one walk's outputs under `prefix` and returns its summary.
pub(super) fn write_walk(
    folder: &RunFolder,
    prefix: &str,
    files: &WalkFiles,
    walk: &LearnWalk,
    run: &WalkRun,
    frame: &MapFrame,
) -> Result<Summary> {
    let (config, estimate, filter) = (&run.config, &run.estimate, &run.filter);
    let (anchors, frame) = (frame, frame.frame);
    let north_up = anchors.anchored || run.heading_is_absolute();
    let at = |name: &str| folder.path(&format!("{prefix}{name}"));
    // Built one at a time from the trace and the path (a long walk's per-step outputs are
    // the largest things a run holds).
    let steps_and_path = || walk.trace.steps().iter().zip(&estimate.path);
    write_trajectory_with(
        &at("track.csv"),
        "spread_m",
        steps_and_path()
            .zip(&estimate.spread_m)
            .map(|((s, p), &spread)| {
                let point = TimedPoint {
                    t: s.t,
                    x: p.x,
                    y: p.y,
                };
                (point, spread)
            }),
    )?;
    let points: Vec<TrackPoint> = steps_and_path()
        .zip(&estimate.levels)
        .map(|((s, p), &level)| TrackPoint {
            t: s.t,
            x: p.x,
            y: p.y,
            z: estimate.map.level_height(level),
            level,
        })
        .collect();
    write_track_geojson(&at("track.geojson"), &points, frame)?;
    drop(points);
    write_map_geojson(&at("map.geojson"), &estimate.map, frame)?;
    // The path `(x, y, level)`, for the pictures.
    let path: Vec<(f64, f64, i32)> = estimate
        .path
        .iter()
        .zip(&estimate.levels)
        .map(|(p, &l)| (p.x, p.y, l))
        .collect();
    if let Some(field) = estimate.field_map.as_ref().filter(|f| !f.cells.is_empty()) {
        write_field_map_geojson(&at("fieldmap.geojson"), field, frame)?;
        write_field_map_png(&at("fieldmap.png"), field, &path, north_up)?;
    }
    let walkable_plan_m2 = write_learned_plan(&at("plan.geojson"), &estimate.map, frame)?;
    let pictures = MapPictures {
        path: &path,
        path_label: "most probable path",
        north_up,
        outline: anchors.outline,
        extent: anchors.picture_extent,
    };
    pictures.write(&at, "map", &estimate.map)?;
    if !prefix.is_empty() {
        folder.write_json(&format!("{prefix}config.json"), config)?;
    }
    write_trajectory(
        &at("dead_reckoning.csv"),
        walk.trace
            .steps()
            .iter()
            .zip(&run.dead_reckoned)
            .map(|(s, p)| TimedPoint {
                t: s.t,
                x: p.x,
                y: p.y,
            }),
    )?;
    let ess = filter.ess_history();
    let steps = walk.trace.len();
    Ok(Summary {
        quality: run.quality(&QualityConfig::default()),
        steps_file: files.steps_path.display().to_string(),
        gps_file: files.gps_path.as_ref().map(|p| p.display().to_string()),
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
        map_area_m2: estimate.map.cells.len() as f64 * HexGrid::new(config.hex_radius).cell_area(),
        path_length_m: path_length(path.iter().map(|&(x, y, _)| (x, y))),
        gps_fixes: walk.fixes.len(),
        gps_fixes_used: filter.gps_fixes_used(),
        prior_offset_m: estimate.prior_offset,
        walkable_plan_m2,
        wifi_in_filter: WifiSummary::of(walk, run, files.wifi_duplicate_readings),
        building_axes: run.axes_report(),
        magnetic_field: run.field_report(),
        smoothing: run.smoothing_report(),
        departure_from_dead_reckoning: run.departure.clone(),
        heading: HeadingSummary {
            start_source: run.start_source,
            start_deg: config.start.heading.to_degrees(),
            start_sigma_deg: config
                .start_heading_sigma
                .min(std::f64::consts::PI)
                .to_degrees(),
            final_sigma_deg: filter.heading_spread().to_degrees(),
        },
    })
}

/// Writes the walkable plan of `map` ([`walkable_plan`], default settings) to `path` and
/// returns its area; writes nothing and returns `None` when the map is too small to make
/// one (`footslam plan` gives the reason and the settings to change).
pub(super) fn write_learned_plan(
    path: &std::path::Path,
    map: &HexMapSnapshot,
    frame: &LocalFrame,
) -> Result<Option<f64>> {
    match walkable_plan(map, &PlanConfig::default()) {
        Ok(learned) => {
            write_floor_plan(path, &learned.plan, frame)?;
            Ok(Some(learned.area_m2))
        }
        Err(_) => Ok(None),
    }
}
