//! `learn --wifi`: a radio map from the walks alone. Each walk's scans are placed on its
//! learned path (FootSLAM's most probable path) and added to the cells of the plan learned
//! from the run's map — the survey of Woodman & Harle (2009) with no floor plan drawn by
//! anyone: the learned map stands in for the plan, the learned path for the tracker.

use super::learn_inputs::Walk;
use super::radio_outputs::{held_out_quantiles, write_radio_map_files};
use anyhow::{Context, Result};
use footslam::filter::{EPSILON_MISS, FootSlamEstimate, RfConfig, path_points, survey_paths};
use footslam::geometry::LocalFrame;
use footslam::io::RunFolder;
use footslam::map::{CellConfig, HexMapSnapshot, PlanConfig, walkable_plan};
use serde::Serialize;
use std::collections::BTreeMap;

/// What `learn --wifi` made: `summary.json`'s `radio` block.
#[derive(Debug, Serialize)]
pub(super) struct RadioSummary {
    /// Cell granularity, metres.
    granularity_m: f64,
    /// Cells of the learned plan, and the rooms (walkable pieces) they divide.
    cells: usize,
    rooms: usize,
    /// Scans read, added to a cell, and left out (placed outside every cell), per walk in
    /// the order of the walks (walks without a WiFi log: zeros).
    scans: Vec<usize>,
    scans_added: Vec<usize>,
    scans_skipped: Vec<usize>,
    /// Share of the learned plan's area in cells with a scan, and scans per such cell.
    coverage: f64,
    mean_scans_per_covered_cell: f64,
    access_points: usize,
    /// The region thresholds calibrated on the walks' own scans (as `survey` does).
    epsilon: Option<f64>,
    epsilon_sqrt: Option<f64>,
    ndist_leave_one_out_p50_p90_p99_max: BTreeMap<&'static str, [Option<f64>; 4]>,
}

/// Builds the radio map of `walks` on the plan learned from `map` (every walk's learned map,
/// merged, in the frame of the walks' paths: `estimates`, one per walk) and writes
/// `radiomap.geojson`, `radiomap.csv` and the heatmaps into `folder`.
pub(super) fn learn_radio_map(
    folder: &RunFolder,
    walks: &[Walk],
    estimates: &[&FootSlamEstimate],
    map: &HexMapSnapshot,
    cell_config: &CellConfig,
    frame: &LocalFrame,
) -> Result<RadioSummary> {
    let plan_config = PlanConfig::default();
    let learned = walkable_plan(map, &plan_config)
        .context("the learned map is too small to cut radio-map cells from")?;
    let paths: Vec<_> = walks
        .iter()
        .zip(estimates)
        .map(|(walk, estimate)| {
            let path = path_points(walk.trace.steps(), &estimate.path, plan_config.level);
            (path, walk.scans.as_slice())
        })
        .collect();
    let survey = survey_paths(
        &learned.plan,
        &paths,
        cell_config,
        RfConfig::default().missing_rssi,
        EPSILON_MISS,
    )
    .context("WiFi on the learned plan")?;
    let radio = &survey.map;
    write_radio_map_files(folder, "", &learned.plan, radio, frame)?;
    let (coverage, per_cell) = radio.coverage();
    Ok(RadioSummary {
        granularity_m: cell_config.granularity,
        cells: survey.cells.cells().len(),
        rooms: survey.cells.rooms().len(),
        scans: walks.iter().map(|w| w.scans.len()).collect(),
        scans_added: survey.counts.iter().map(|c| c.added).collect(),
        scans_skipped: survey.counts.iter().map(|c| c.skipped).collect(),
        coverage,
        mean_scans_per_covered_cell: per_cell,
        access_points: radio.access_points().len(),
        epsilon: radio.epsilon,
        epsilon_sqrt: radio.epsilon_sqrt,
        ndist_leave_one_out_p50_p90_p99_max: held_out_quantiles(&survey.held),
    })
}
