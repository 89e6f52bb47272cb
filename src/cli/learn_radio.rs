//! `learn --wifi`'s outputs: the radio map made from the walks alone
//! ([`footslam::pipeline::LearnedRadio`]) and its summary.

use super::learn_outputs::MapFrame;
use super::radio_outputs::write_radio_map_files;
use anyhow::Result;
use footslam::io::RunFolder;
use footslam::map::CellConfig;
use footslam::model::wifi_distance::held_out_quantiles;
use footslam::pipeline::{LearnWalk, LearnedRadio};
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

/// Writes the radio map `learn` made of the walks' WiFi (`radiomap.geojson`, `radiomap.csv`
/// and the heatmaps) into `folder` and returns its summary; `walks` gives each walk's scans.
pub(super) fn write_learned_radio_map(
    folder: &RunFolder,
    walks: &[LearnWalk],
    radio: &LearnedRadio,
    cell_config: &CellConfig,
    frame: &MapFrame,
) -> Result<RadioSummary> {
    let survey = &radio.survey;
    let map = &survey.map;
    let plan = &radio.plan.plan;
    let pictures = (frame.frame, frame.anchored, frame.picture_extent);
    write_radio_map_files(folder, "", plan, map, pictures)?;
    let (coverage, per_cell) = map.coverage();
    Ok(RadioSummary {
        granularity_m: cell_config.granularity,
        cells: survey.cells.cells().len(),
        rooms: survey.cells.rooms().len(),
        scans: walks.iter().map(|w| w.scans.len()).collect(),
        scans_added: survey.counts.iter().map(|c| c.added).collect(),
        scans_skipped: survey.counts.iter().map(|c| c.skipped).collect(),
        coverage,
        mean_scans_per_covered_cell: per_cell,
        access_points: map.access_points().len(),
        epsilon: map.epsilon,
        epsilon_sqrt: map.epsilon_sqrt,
        ndist_leave_one_out_p50_p90_p99_max: held_out_quantiles(&survey.held),
    })
}
